//! The internal positive representation and the observer's order preservation (Rabehi et al.
//! 2021, §III; spec 004 §8 A1–A2): example values from the paper, structural properties as
//! proptests.

use faer::{Mat, mat};
use proptest::prelude::*;
use sporadic_rabehi2021::example::{
    example_bounds, paper_gain, paper_reset_matrix, spring_mass_damper,
};
use sporadic_rabehi2021::ipr::{
    MetzlerDecomposition, abs, gamma_of_gain, is_metzler, is_nonnegative, jump_matrix,
    negative_part, pair_blocks, pair_matrix, positive_part, reset_matrix,
};
use sporadic_rabehi2021::observer::IntervalObserver;
use sporadic_rabehi2021::system::{Bounds, Plant};

/// A1: A^M, A^N and Ā of §V, Metzler/nonnegative structure, det Ā = −1, ξ_ueq.
#[test]
fn example_decomposition() {
    let plant = spring_mass_damper(1.0).unwrap();
    let d = MetzlerDecomposition::new(plant.a()).unwrap();
    assert_eq!(d.a_m, mat![[0.0, 1.0], [0.0, -1.0]]);
    assert_eq!(d.a_n, mat![[0.0, 0.0], [1.0, 0.0]]);
    assert_eq!(
        d.a_bar,
        mat![
            [0.0, 1.0, 0.0, 0.0],
            [0.0, -1.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0, -1.0]
        ]
    );
    assert!(is_metzler(d.a_bar.as_ref()) && !is_metzler(plant.a()));
    assert!(is_nonnegative(d.a_n.as_ref()));
    assert_eq!(&d.a_m - &d.a_n, plant.a().to_owned());
    // det Ā = det(S)·det(A) = (−1)·(1) (block structure), here from the LU of faer.
    let det = d.a_bar.determinant();
    assert!((det + 1.0).abs() < 1e-14, "{det}");
    // Spectrum: eig(S) ∪ eig(A) = {(−1 ± √5)/2} ∪ {−1/2 ± i√3/2}.
    let eig = d.a_bar.eigenvalues().unwrap();
    let max_re = eig.iter().map(|z| z.re).fold(f64::NEG_INFINITY, f64::max);
    assert!((max_re - (5f64.sqrt() - 1.0) / 2.0).abs() < 1e-12);
    // ξ_ueq = −Ā⁻¹Ξ̄ with Ξ̄ = 2·1 (spec §7: [−4, −2, −4, −2]).
    let xi = d.xi_ueq(&example_bounds().xi_bar()).unwrap();
    for (a, b) in xi.iter().zip([-4.0, -2.0, -4.0, -2.0]) {
        assert!((a - b).abs() < 1e-12, "{xi:?}");
    }
}

/// A2: Γ(L) of the printed gain, its spectrum {1, 1, ±0.0008} and Υ ≥ 0 for |v| ≤ v̄.
#[test]
fn printed_gain_jump_matrix() {
    let plant = spring_mass_damper(1.0).unwrap();
    let l = paper_gain();
    let g = reset_matrix(&plant, l.as_ref()).unwrap();
    assert!((&g - &paper_reset_matrix()).norm_max() <= 1.0e-4 + 1e-15);
    let gamma = gamma_of_gain(&plant, l.as_ref()).unwrap();
    let gp = mat![[0.0, 0.0], [0.0, 1.0]];
    let gm = Mat::from_fn(2, 2, |i, j| match (i, j) {
        (0, 0) => 0.0008,
        (1, 0) => 0.0988,
        _ => 0.0,
    });
    assert!((&gamma - &pair_matrix(gp.as_ref(), gm.as_ref())).norm_max() < 1e-12);
    assert!(is_nonnegative(gamma.as_ref()));
    let mut eig: Vec<f64> = gamma
        .eigenvalues()
        .unwrap()
        .iter()
        .map(|z| {
            assert!(z.im.abs() < 1e-12);
            z.re
        })
        .collect();
    eig.sort_by(f64::total_cmp);
    for (a, b) in eig.iter().zip([-0.0008, 0.0008, 1.0, 1.0]) {
        assert!((a - b).abs() < 1e-10, "{eig:?}");
    }
    // Υ = [|L|v̄ + Lv; |L|v̄ − Lv] ≥ 0 for v ∈ [−0.4, 0.4].
    for k in 0..=8 {
        let v = -0.4 + 0.1 * k as f64;
        for i in 0..2 {
            let (a, lv) = (l[(i, 0)].abs() * 0.4, l[(i, 0)] * v);
            assert!(a + lv >= -1e-15 && a - lv >= -1e-15);
        }
    }
}

fn matrix(n: usize, m: usize, scale: f64) -> impl Strategy<Value = Mat<f64>> {
    prop::collection::vec(-scale..scale, n * m)
        .prop_map(move |v| Mat::from_fn(n, m, |i, j| v[i * m + j]))
}

fn plant_and_gain() -> impl Strategy<Value = (Plant, Mat<f64>)> {
    (1usize..4, 1usize..3).prop_flat_map(|(n, p)| {
        (matrix(n, n, 3.0), matrix(p, n, 2.0), matrix(n, p, 2.0)).prop_map(move |(a, c, l)| {
            let b = Mat::<f64>::zeros(n, 1);
            (Plant::new(a.as_ref(), b.as_ref(), c.as_ref()).unwrap(), l)
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// A^M Metzler, A^N ≥ 0 with zero diagonal, A = A^M − A^N exactly, Ā Metzler, and
    /// TĀT = diag(A^M + A^N, A).
    #[test]
    fn metzler_decomposition(a in (1usize..5).prop_flat_map(|n| matrix(n, n, 5.0))) {
        let d = MetzlerDecomposition::new(a.as_ref()).unwrap();
        prop_assert!(is_metzler(d.a_m.as_ref()));
        prop_assert!(is_nonnegative(d.a_n.as_ref()));
        for i in 0..a.nrows() {
            prop_assert_eq!(d.a_n[(i, i)], 0.0);
            prop_assert_eq!(d.a_m[(i, i)], a[(i, i)]);
        }
        prop_assert_eq!(&d.a_m - &d.a_n, a.clone());
        prop_assert!(is_metzler(d.a_bar.as_ref()));
        let (s, centre) = pair_blocks(d.a_bar.as_ref()).unwrap();
        prop_assert!((&s - d.width_matrix()).norm_max() == 0.0);
        prop_assert!((&centre - &a).norm_max() == 0.0);
        // |A| = A⁺ + A⁻, A = A⁺ − A⁻, and A⁺, A⁻ never both positive.
        let (pp, nn) = (positive_part(a.as_ref()), negative_part(a.as_ref()));
        prop_assert_eq!(&pp - &nn, a.clone());
        prop_assert_eq!(&pp + &nn, abs(a.as_ref()));
        for j in 0..a.ncols() {
            for i in 0..a.nrows() {
                prop_assert!(pp[(i, j)] * nn[(i, j)] == 0.0);
            }
        }
    }

    /// Γ(L) ≥ 0 with the pair structure [[G⁺, G⁻], [G⁻, G⁺]], its blocks (|G|, G), and the
    /// elementwise ordering Γ(L) ≤ Γ(G⁺ + Δ, G⁻ + Δ) = Γ(L) + 𝟙₂ₓ₂ ⊗ Δ of (36).
    #[test]
    fn jump_matrix_sign_structure(
        (plant, l) in plant_and_gain(),
        delta_seed in prop::collection::vec(0.0f64..1.0, 9),
    ) {
        let n = plant.n();
        let g = reset_matrix(&plant, l.as_ref()).unwrap();
        let gamma = gamma_of_gain(&plant, l.as_ref()).unwrap();
        prop_assert!(is_nonnegative(gamma.as_ref()));
        let (width, centre) = pair_blocks(gamma.as_ref()).unwrap();
        prop_assert!((&width - abs(g.as_ref())).norm_max() < 1e-14);
        prop_assert!((&centre - &g).norm_max() < 1e-14);
        let delta = Mat::from_fn(n, n, |i, j| delta_seed[i * 3 + j]);
        let g1 = positive_part(g.as_ref()) + &delta;
        let g2 = negative_part(g.as_ref()) + &delta;
        let general = jump_matrix(g1.as_ref(), g2.as_ref());
        prop_assert!((&g1 - &g2 - &g).norm_max() < 1e-13);
        for j in 0..2 * n {
            for i in 0..2 * n {
                let d = delta[(i % n, j % n)];
                prop_assert!((general[(i, j)] - gamma[(i, j)] - d).abs() < 1e-13);
            }
        }
    }

    /// The correction (8) keeps x̲ ≤ x ≤ x̄ for any gain, any noise |v| ≤ v̄ and any enclosure,
    /// with x⁺ = x (the fictitious reset (7)).
    #[test]
    fn correction_preserves_inclusion(
        (plant, l) in plant_and_gain(),
        seeds in prop::collection::vec(0.0f64..1.0, 12),
        v_bar in 0.0f64..1.0,
    ) {
        let (n, p) = (plant.n(), plant.p());
        let bounds = Bounds::new(vec![-1.0; n], vec![1.0; n], vec![v_bar; p]).unwrap();
        let obs = IntervalObserver::new(&plant, &bounds, l.as_ref()).unwrap();
        let x: Vec<f64> = (0..n).map(|i| 4.0 * seeds[i] - 2.0).collect();
        let mut lower: Vec<f64> = (0..n).map(|i| x[i] - 3.0 * seeds[3 + i]).collect();
        let mut upper: Vec<f64> = (0..n).map(|i| x[i] + 3.0 * seeds[6 + i]).collect();
        let y: Vec<f64> = (0..p)
            .map(|k| {
                let v = v_bar * (2.0 * seeds[9 + k] - 1.0);
                (0..n).map(|j| plant.c()[(k, j)] * x[j]).sum::<f64>() + v
            })
            .collect();
        obs.correct(&mut lower, &mut upper, &y).unwrap();
        for i in 0..n {
            prop_assert!(lower[i] <= x[i] + 1e-12 && x[i] <= upper[i] + 1e-12,
                "{} <= {} <= {}", lower[i], x[i], upper[i]);
        }
    }

    /// The flow (4) keeps the inclusion for a constant admissible disturbance: the bounds and
    /// the state propagated exactly for τ (Van Loan, via the observer's LTI flow).
    #[test]
    fn flow_preserves_inclusion(
        (plant, _l) in plant_and_gain(),
        seeds in prop::collection::vec(0.0f64..1.0, 11),
        tau in 0.01f64..1.0,
    ) {
        let n = plant.n();
        let bounds = Bounds::new(vec![-1.0; n], vec![0.5; n], vec![0.0; plant.p()]).unwrap();
        let obs = IntervalObserver::new(&plant, &bounds, Mat::<f64>::zeros(n, plant.p()).as_ref())
            .unwrap();
        let d: Vec<f64> = (0..n).map(|i| -1.0 + 1.5 * seeds[9 + i.min(1)]).collect();
        let x: Vec<f64> = (0..n).map(|i| 2.0 * seeds[i] - 1.0).collect();
        let z0: Vec<f64> = (0..n)
            .map(|i| x[i] - seeds[3 + i])
            .chain((0..n).map(|i| x[i] + seeds[6 + i]))
            .collect();
        let bounds_flow = obs.flow(None).unwrap();
        let z = bounds_flow.propagate(0.0, &z0, tau).unwrap();
        let plant_flow = sporadic_sim::LtiFlow::new(plant.a()).unwrap().with_affine(d).unwrap();
        let xt = plant_flow.propagate(0.0, &x, tau).unwrap();
        for i in 0..n {
            let tol = 1e-9 * (1.0 + xt[i].abs());
            prop_assert!(z[i] <= xt[i] + tol && xt[i] <= z[n + i] + tol);
        }
    }
}
