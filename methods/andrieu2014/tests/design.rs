//! Design constants of Theorem 2 (steps (D1)–(D4) of `sporadic_andrieu2014::design`) and typed
//! errors of the design stage. Expected values: an independent reference implementation (Python)
//! and closed forms.

use approx::assert_relative_eq;
use proptest::prelude::*;
use sporadic_andrieu2014::{Design, Error, binomial_gain, q_matrix};
use sporadic_linalg::InputError;
use sporadic_linalg::{max_eigenvalue, min_eigenvalue, spectral_radius};

fn n2_design() -> Design {
    Design::binomial(2, 1.0).unwrap()
}

#[test]
fn p_and_p1_to_p4_and_a1_match_the_spec() {
    let d = n2_design();
    let p = d.p();
    let expected = [[0.5, -0.5], [-0.5, 1.5]];
    for i in 0..2 {
        for j in 0..2 {
            assert_relative_eq!(p[(i, j)], expected[i][j], epsilon = 1e-12);
        }
    }
    let s = std::f64::consts::FRAC_1_SQRT_2;
    assert_relative_eq!(d.p1(), 1.0 - s, max_relative = 1e-10);
    assert_relative_eq!(d.p2(), 1.0 + s, max_relative = 1e-10);
    assert_relative_eq!(d.p3(), 3.0 - 1.5f64.sqrt(), max_relative = 1e-10);
    assert_relative_eq!(d.p4(), 3.0 + 1.5f64.sqrt(), max_relative = 1e-10);
    assert_relative_eq!(d.a1(), 0.0693280, max_relative = 1e-6);
    assert_relative_eq!(
        d.a1(),
        1.0 / (2.0 * (1.0 + s) * (3.0 + 1.5f64.sqrt())),
        max_relative = 1e-10
    );
    assert_eq!(d.a3(), 4.0);
}

#[test]
fn alpha_m_matches_the_spec() {
    let d = n2_design();
    let am = d.alpha_m();
    assert!((0.4179..=0.4180).contains(&am), "alpha_m = {am}");
    // Holds below, fails above (and keeps failing up to α = 3, as the independent reference
    // implementation found).
    assert!(d.lemma4_holds(0.99 * am).unwrap());
    let mut a = 1.001 * am;
    while a < 3.0 {
        assert!(
            !d.lemma4_holds(a).unwrap(),
            "(17) holds again at alpha = {a}"
        );
        a += 0.01;
    }
}

#[test]
fn lemma4_and_lemma5_table_matches_the_spec() {
    let d = n2_design();
    // (α, λmax, 1 − α/(4p2), N1, N2, a2,min) from the independent reference implementation.
    let table = [
        (0.1, 0.969503, 0.985355, 3.9114, 2.2008, 47.02),
        (0.2, 0.945374, 0.970711, 4.4533, 2.8561, 56.23),
        (0.4, 0.935321, 0.941421, 5.7261, 4.9560, 82.18),
    ];
    for (alpha, lam, rhs, n1, n2, a2) in table {
        assert_relative_eq!(d.lemma4_lambda(alpha).unwrap(), lam, max_relative = 1e-6);
        assert_relative_eq!(d.lemma4_rhs(alpha), rhs, max_relative = 1e-6);
        assert_relative_eq!(d.n1(alpha).unwrap(), n1, max_relative = 2e-5);
        assert_relative_eq!(d.n2(alpha).unwrap(), n2, max_relative = 2e-5);
        assert_relative_eq!(d.a2_min(alpha).unwrap(), a2, max_relative = 1e-4);
    }
    // a2 = 56.2298 at α = 0.2, the value used for the pendulum run (tests/pendulum.rs).
    assert_relative_eq!(d.a2_min(0.2).unwrap(), 56.2298, max_relative = 2e-6);
}

#[test]
fn spectral_radius_and_determinant_of_q() {
    let k = binomial_gain(2);
    for (alpha, rho) in [(0.2, 0.8717), (0.8, 0.9038), (0.828, 0.9985), (0.9, 1.2500)] {
        let q = q_matrix(&k, alpha).unwrap();
        assert_relative_eq!(
            spectral_radius(q.as_ref()).unwrap(),
            rho,
            max_relative = 1e-4
        );
    }
    for alpha in [0.05, 0.3, 0.5, 0.9, 1.7] {
        let q = q_matrix(&k, alpha).unwrap();
        assert_relative_eq!(q.determinant(), 1.0 - 2.0 * alpha, epsilon = 1e-14);
    }
    // Schur boundary of the pure chain: α = 2√2 − 2.
    let edge = 2.0 * 2f64.sqrt() - 2.0;
    assert!(spectral_radius(q_matrix(&k, edge - 1e-6).unwrap().as_ref()).unwrap() < 1.0);
    assert!(spectral_radius(q_matrix(&k, edge + 1e-6).unwrap().as_ref()).unwrap() > 1.0);
}

#[test]
fn higher_order_designs_need_weighted_lyapunov() {
    // Independent reference implementation: r = 1 works for n = 2, 3 and fails for n = 4
    // (p3 ≈ −0.16); r = 0.1 / 0.01 repair it.
    assert_relative_eq!(
        Design::binomial(3, 1.0).unwrap().p3(),
        0.872,
        max_relative = 1e-3
    );
    match Design::binomial(4, 1.0) {
        Err(Error::NotDiagonallyDominated { p3 }) => {
            assert!((-0.17..-0.15).contains(&p3), "p3 = {p3}")
        }
        other => panic!("expected NotDiagonallyDominated, got {other:?}"),
    }
    for (n, p3) in [(4, 1.307), (5, 0.827), (6, 0.297)] {
        assert_relative_eq!(
            Design::binomial(n, 0.1).unwrap().p3(),
            p3,
            max_relative = 2e-3
        );
    }
    for (n, p3) in [(4, 1.72), (5, 1.57), (6, 1.43)] {
        assert_relative_eq!(
            Design::binomial(n, 0.01).unwrap().p3(),
            p3,
            max_relative = 5e-3
        );
    }
}

#[test]
fn inadmissible_choices_give_typed_errors() {
    // The paper's printed K = [−2, 1]': A + KC has the eigenvalue +0.414.
    assert!(matches!(
        Design::new(&[-2.0, 1.0], &[1.0, 1.0]),
        Err(Error::NotHurwitz { .. })
    ));
    assert!(matches!(
        Design::new(&[0.0, -1.0], &[1.0, 1.0]),
        Err(Error::NotHurwitz { .. })
    ));
    assert!(matches!(
        Design::new(&[-2.0, -1.0], &[1.0]),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        Design::new(&[], &[]),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        Design::new(&[-2.0, f64::NAN], &[1.0, 1.0]),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        Design::new(&[-2.0, -1.0], &[1.0, 0.0]),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));
    assert!(matches!(
        Design::binomial(2, -1.0),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));
    let d = n2_design();
    assert!(matches!(
        d.tuning(0.9, 100.0),
        Err(Error::AlphaNotAdmissible { .. })
    ));
    assert!(matches!(
        d.tuning(d.alpha_m(), 100.0),
        Err(Error::AlphaNotAdmissible { .. })
    ));
    assert!(matches!(
        d.tuning(-0.1, 100.0),
        Err(Error::AlphaNotAdmissible { .. })
    ));
    assert!(matches!(
        d.tuning(f64::NAN, 100.0),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        d.tuning(0.2, 50.0),
        Err(Error::GainRateTooSmall { .. })
    ));
    let t = d.theorem_tuning(0.2).unwrap();
    assert_relative_eq!(t.a2(), 56.2298, max_relative = 2e-6);
    assert_eq!(t.a3(), 4.0);
    assert!(matches!(
        d.lyapunov(&[1.0]),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
}

/// Monic polynomial coefficients of `∏ (s + λ_i)`: `[c_1, …, c_n]` of `s^n + c_1 s^{n−1} + … + c_n`.
fn poly_from_poles(poles: &[f64]) -> Vec<f64> {
    let mut c = vec![1.0];
    for &l in poles {
        let mut next = vec![0.0; c.len() + 1];
        for (i, &ci) in c.iter().enumerate() {
            next[i] += ci;
            next[i + 1] += l * ci;
        }
        c = next;
    }
    c[1..].to_vec()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// For random Hurwitz `K` (real poles, char. polynomial `s^n − K_1 s^{n−1} − … − K_n`) the design
    /// satisfies (8), (9), (9b) as matrix inequalities, and the small-α slope of the Lemma 4 quantity is
    /// at most `−1/(2p2)` as (A.4) of the proof predicts.
    #[test]
    fn design_inequalities_hold(poles in prop::collection::vec(0.5f64..3.0, 2..=3)) {
        let n = poles.len();
        let k: Vec<f64> = poly_from_poles(&poles).iter().map(|c| -c).collect();
        let d = match Design::new(&k, &vec![1.0; n]) {
            Ok(d) => d,
            Err(Error::NotDiagonallyDominated { .. }) => return Ok(()),
            Err(e) => panic!("{e}"),
        };
        let p = d.p();
        let acl = faer::Mat::from_fn(n, n, |i, j| f64::from(j == i + 1) + if j == 0 { k[i] } else { 0.0 });
        let lhs = acl.transpose() * p + p * &acl;
        prop_assert!(max_eigenvalue(lhs.as_ref()).unwrap() <= -1.0 + 1e-9);
        prop_assert!(min_eigenvalue(p).unwrap() >= d.p1() - 1e-12);
        let shifted = faer::Mat::from_fn(n, n, |i, j| p[(i, j)] * (i + j + 2) as f64 - d.p3() * p[(i, j)]);
        prop_assert!(min_eigenvalue(shifted.as_ref()).unwrap() >= -1e-9);
        let h = 1e-5;
        let slope = (d.lemma4_lambda(h).unwrap() - 1.0) / h;
        prop_assert!(slope <= -1.0 / (2.0 * d.p2()) + 1e-3, "slope {slope}");
        prop_assert!(d.alpha_m() > 0.0 && d.a1() * d.alpha_m() < 1.0);
    }

    /// Jury test for `K = [−k1, −k2]'`: `ρ(Q(α)) < 1 ⇔ 0 < αk1 < 2, k2 > 0, 2αk1 + α²k2 < 4`.
    #[test]
    fn q_schur_stability_matches_jury(k1 in 0.1f64..4.0, k2 in -1.0f64..4.0, alpha in 0.05f64..2.0) {
        let q = q_matrix(&[-k1, -k2], alpha).unwrap();
        let rho = spectral_radius(q.as_ref()).unwrap();
        let margin = [2.0 - alpha * k1, k2, 4.0 - 2.0 * alpha * k1 - alpha * alpha * k2];
        prop_assume!(margin.iter().all(|m| m.abs() > 1e-3));
        let jury = margin.iter().all(|&m| m > 0.0);
        prop_assert_eq!(rho < 1.0, jury, "rho = {}", rho);
    }
}
