//! The residue embedding's vertex count does not depend on the coordinates (issue 22): its
//! clusters are those of the balanced matrix (see the `residue` module docs), so a power-of-two
//! diagonal change of coordinates (the diagonal normal form of `sporadic-ferrante2016`) gives the
//! same expansion; and a well-conditioned similarity `S A S⁻¹` keeps the clusters of integrator
//! chains and Jordan blocks (whose spectral projectors are far beyond the merge limit in any
//! such coordinates). On a short window, the power series of the whole spectrum keeps a number
//! of powers set by the eigenvalues and the window, so its pieces and powers do not change
//! under a similarity or a change of time unit either.

mod common;

use common::Rng;
use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, MatRef};
use proptest::prelude::*;
use sporadic_embed::{Containment, Embedding, Method, ResidueExpansion, ResidueOptions};

/// `eight-state-modal` of the corpus: four lightly damped modes at 1, 2, 3 and 5 rad/s with a
/// weak coupling 0.1.
fn eight_state_modal() -> Mat<f64> {
    let mut a = Mat::<f64>::zeros(8, 8);
    for (k, (w2, damping)) in [(1.0, 0.02), (4.0, 0.04), (9.0, 0.06), (25.0, 0.1)]
        .into_iter()
        .enumerate()
    {
        let (p, v) = (2 * k, 2 * k + 1);
        a[(p, v)] = 1.0;
        a[(v, p)] = -w2;
        a[(v, v)] = -damping;
    }
    for (r, c) in [(1, 2), (3, 0), (3, 4), (5, 2), (5, 6), (7, 4)] {
        a[(r, c)] = 0.1;
    }
    a
}

/// `D A D⁻¹` for `D = diag(d)`.
fn diagonal_similarity(a: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)] * d[i] / d[j])
}

/// `S A S⁻¹` for a random well-conditioned `S = I + E`, `|E_ij| ≤ 0.3/n` (so `‖E‖₂ ≤ 0.3` and
/// `κ(S) ≤ 1.3/0.7`).
fn random_similarity(a: MatRef<'_, f64>, rng: &mut Rng) -> Mat<f64> {
    let n = a.nrows();
    let bound = 0.3 / n as f64;
    let s = Mat::from_fn(n, n, |i, j| {
        f64::from(u8::from(i == j)) + rng.uniform(-bound, bound)
    });
    let inv = s.partial_piv_lu().inverse();
    &s * a * &inv
}

/// The vertex count of the residue embedding of `a` on `[t1, t2]`, and whether its containment
/// is guaranteed, the power series of the whole spectrum on short windows turned off (the
/// clusters' box alone).
fn vertices(a: MatRef<'_, f64>, t1: f64, t2: f64) -> (usize, usize, bool) {
    let (exp, e) = embed(a, t1, t2, false, 1e-13);
    (
        exp.clusters().len(),
        e.vertex_count(),
        e.containment() == &Containment::Guaranteed,
    )
}

/// The residue embedding of `a` on `[t1, t2]` with the tail tolerance `tail` and the
/// short-window series allowed when `series` (balanced clusters).
fn embed(
    a: MatRef<'_, f64>,
    t1: f64,
    t2: f64,
    series: bool,
    tail: f64,
) -> (ResidueExpansion, Embedding) {
    let options = ResidueOptions {
        short_window_series: series,
        balanced_clusters: true,
        tail_tolerance: tail,
        ..ResidueOptions::default()
    };
    let exp = ResidueExpansion::with_options(a, options).unwrap();
    let e = exp.embed(t1, t2).unwrap();
    (exp, e)
}

/// The choices of the residue embedding of `a` on `[t1, t2]` with the short-window series and
/// the tail tolerance of a `sporadic-ferrante2016` design (`1e-9`): its clusters, its pieces and
/// the most terms a piece keeps. (Not the vertex count: terms whose whole range is below the
/// remainder are folded into it, and the remainder is bounded in the coordinates of `a`; nor the
/// containment, whose self-check measures rounding in those coordinates.)
fn choices(a: MatRef<'_, f64>, t1: f64, t2: f64) -> (usize, usize, usize) {
    let (exp, e) = embed(a, t1, t2, true, 1e-9);
    let Method::Residue { terms, .. } = e.method() else {
        panic!("{:?}", e.method());
    };
    (exp.clusters().len(), e.pieces().len(), *terms)
}

/// A four-story shear building (masses 1, stiffnesses 400, 350, 300, 250, Rayleigh-like
/// damping; modes at 6.5–33.7 rad/s), states (positions, velocities).
fn four_story_building() -> Mat<f64> {
    let k = [
        [-750.0, 350.0, 0.0, 0.0],
        [350.0, -650.0, 300.0, 0.0],
        [0.0, 300.0, -550.0, 250.0],
        [0.0, 0.0, 250.0, -250.0],
    ];
    let c = [
        [-1.55, 0.7, 0.0, 0.0],
        [0.7, -1.35, 0.6, 0.0],
        [0.0, 0.6, -1.15, 0.5],
        [0.0, 0.0, 0.5, -0.55],
    ];
    Mat::from_fn(8, 8, |i, j| match (i < 4, j < 4) {
        (true, true) => 0.0,
        (true, false) => f64::from(u8::from(j - 4 == i)),
        (false, true) => k[i - 4][j],
        (false, false) => c[i - 4][j - 4],
    })
}

/// The building on `[0.005, 0.08]` with the tail tolerance of a `sporadic-ferrante2016` design
/// (`1e-9`): 16 pieces of the centred series with six powers each (`16·2⁶` vertices), as given,
/// in other coordinates and in milliseconds. Before the series' order was set by the
/// eigenvalues, the tail bounds in the coordinates of the matrix kept six powers in the
/// diagonal normal form of the design and seven in others, which exceeded the corner budget, so
/// that the clusters' box (`2⁸` vertices, on which LMI (41) of the design is infeasible) was
/// taken there.
#[test]
fn a_building_on_a_short_window_keeps_its_pieces_in_any_coordinates() {
    let a = four_story_building();
    let given = choices(a.as_ref(), 0.005, 0.08);
    assert_eq!(given, (4, 16, 6));
    assert_eq!(
        embed(a.as_ref(), 0.005, 0.08, true, 1e-9).1.vertex_count(),
        1024
    );
    let mut rng = Rng(22);
    for _ in 0..4 {
        let d: Vec<f64> = (0..8).map(|_| 10f64.powf(rng.uniform(-1.0, 1.0))).collect();
        let similar = diagonal_similarity(random_similarity(a.as_ref(), &mut rng).as_ref(), &d);
        assert_eq!(choices(similar.as_ref(), 0.005, 0.08), given);
    }
    let ms = Mat::from_fn(8, 8, |i, j| a[(i, j)] * 1e-3);
    assert_eq!(choices(ms.as_ref(), 5.0, 80.0), given);
}

/// The diagonal normal form of `eight-state-modal` on `[0.01, 0.0185]` (the scaling the design
/// computes there): the same four clusters and `2⁸` vertices as the data as given; before the
/// balancing its projectors of norm up to `3·10⁴` merged three modes into one cluster of eight
/// moments, and the box had `2¹⁰` vertices.
#[test]
fn eight_state_modal_under_its_diagonal_scaling() {
    let a = eight_state_modal();
    let d = [
        1.0,
        2f64.powi(-6),
        2f64.powi(-15),
        2f64.powi(-21),
        2f64.powi(-15),
        2f64.powi(-21),
        1.0,
        2f64.powi(-6),
    ];
    let scaled = diagonal_similarity(a.as_ref(), &d);
    let given = vertices(a.as_ref(), 0.01, 0.0185);
    assert_eq!(given, (4, 256, true));
    assert_eq!(vertices(scaled.as_ref(), 0.01, 0.0185), given);
    // The time unit of the normal form changes nothing either.
    let k = 0.0185;
    let normal = Mat::from_fn(8, 8, |i, j| scaled[(i, j)] * k);
    assert_eq!(vertices(normal.as_ref(), 0.01 / k, 1.0), given);
}

/// A Jordan block `J_m(λ)` (`λ = 0`: an integrator chain) of order `m`, plus a real eigenvalue
/// `μ` away from it when `extra`.
fn jordan(m: usize, lambda: f64, extra: Option<f64>) -> Mat<f64> {
    let n = m + usize::from(extra.is_some());
    Mat::from_fn(n, n, |i, j| {
        if i < m && i == j {
            lambda
        } else if i < m && j == i + 1 && j < m {
            1.0
        } else if i == m && j == m {
            extra.unwrap_or(0.0)
        } else {
            0.0
        }
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(60))]

    /// Integrator chains and Jordan blocks (with or without a simple eigenvalue beside them)
    /// keep their clusters and vertex count under a random well-conditioned similarity, and
    /// under a random power-of-two diagonal scaling of it (entries from `2⁻³` to `2³`; the
    /// nilpotency test `‖N^j‖_F ≤ tol·‖N‖_F^j` of a Jordan block is not invariant under a
    /// wider diagonal scaling that balancing does not undo).
    #[test]
    fn jordan_blocks_and_integrator_chains_keep_their_vertex_count(
        seed in any::<u64>(),
        m in 2usize..=5,
        lambda in prop_oneof![Just(0.0), -1.0f64..0.5],
        extra in prop_oneof![Just(None), (-3.0f64..-1.5).prop_map(Some)],
    ) {
        let mut rng = Rng(seed);
        let a = jordan(m, lambda, extra);
        let (t1, t2) = (0.05, 1.5);
        let given = vertices(a.as_ref(), t1, t2);
        prop_assert!(given.2, "{given:?}");
        let similar = random_similarity(a.as_ref(), &mut rng);
        prop_assert_eq!(vertices(similar.as_ref(), t1, t2), given);
        let d: Vec<f64> = (0..a.nrows())
            .map(|_| 2f64.powi(rng.below(7) as i32 - 3))
            .collect();
        let scaled = diagonal_similarity(similar.as_ref(), &d);
        prop_assert_eq!(vertices(scaled.as_ref(), t1, t2), given);
    }

    /// Lightly damped modes (distinct eigenvalues), and a Jordan block beside a simple
    /// eigenvalue, on windows from short (the series of the whole spectrum) to long (the
    /// clusters' box): the same clusters, pieces and kept terms under a random similarity (a
    /// well-conditioned one, then a diagonal scaling by factors from 0.1 to 10) and under a
    /// change of time unit.
    #[test]
    fn short_window_series_keeps_its_pieces_under_similarity_and_time_scaling(
        seed in any::<u64>(),
        modes in 1usize..=3,
        jordan_size in prop_oneof![Just(0usize), 2usize..=3],
        t1 in 0.001f64..0.2,
        length in 0.01f64..2.0,
        unit in prop_oneof![Just(1e-3), Just(0.1), Just(60.0)],
    ) {
        let mut rng = Rng(seed);
        let n = 2 * modes + jordan_size;
        let mut a = Mat::<f64>::zeros(n, n);
        for k in 0..modes {
            let (w, z) = (rng.uniform(0.5, 6.0), rng.uniform(0.0, 0.1));
            let (p, v) = (2 * k, 2 * k + 1);
            a[(p, v)] = 1.0;
            a[(v, p)] = -w * w;
            a[(v, v)] = -2.0 * z * w;
        }
        let lambda = rng.uniform(-1.0, 0.5);
        for i in 2 * modes..n {
            a[(i, i)] = lambda;
            if i + 1 < n {
                a[(i, i + 1)] = 1.0;
            }
        }
        let (t1, t2) = (t1, t1 + length);
        let given = choices(a.as_ref(), t1, t2);
        let d: Vec<f64> = (0..n).map(|_| 10f64.powf(rng.uniform(-1.0, 1.0))).collect();
        let similar = diagonal_similarity(random_similarity(a.as_ref(), &mut rng).as_ref(), &d);
        prop_assert_eq!(choices(similar.as_ref(), t1, t2), given);
        let scaled = Mat::from_fn(n, n, |i, j| a[(i, j)] / unit);
        prop_assert_eq!(choices(scaled.as_ref(), t1 * unit, t2 * unit), given);
    }
}
