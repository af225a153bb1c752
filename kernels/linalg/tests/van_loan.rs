//! Van Loan (1978) integrals against closed forms and identities.

use faer::{Mat, mat};
use proptest::prelude::*;
use sporadic_linalg::InputError;
use sporadic_linalg::{
    LinalgError, expm_integral, expm_scaled, gramian_integral, min_eigenvalue, zoh,
};

fn rel(x: &Mat<f64>, y: &Mat<f64>) -> f64 {
    (x - y).norm_l2() / y.norm_l2()
}

/// Brown & Hwang / filterpy example: A = [[0, 1], [−1, 0]], G = [0; 2], Q = GGᵀ, dt = 0.1.
/// Kalman form ∫₀ᵗ e^{As} Q e^{Aᵀs} ds = gramian_integral(Aᵀ, Q, t); closed form
/// 4·[[t/2 − sin 2t/4, sin² t/2], [sin² t/2, t/2 + sin 2t/4]].
#[test]
fn harmonic_oscillator_noise_gramian() {
    let a = mat![[0.0, 1.0], [-1.0, 0.0]];
    let q = mat![[0.0, 0.0], [0.0, 4.0]];
    let t: f64 = 0.1;
    let (phi, _) = zoh(a.as_ref(), Mat::<f64>::zeros(2, 1).as_ref(), t).unwrap();
    let phi_want = mat![[t.cos(), t.sin()], [-t.sin(), t.cos()]];
    assert!(rel(&phi, &phi_want) < 1e-15);
    // Printed (8 digits) reference values.
    assert!((phi[(0, 0)] - 0.99500417).abs() < 5e-9 && (phi[(0, 1)] - 0.09983342).abs() < 5e-9);
    let qd = gramian_integral(a.transpose(), q.as_ref(), t).unwrap();
    let s2 = (2.0 * t).sin();
    let want = mat![
        [t / 2.0 - s2 / 4.0, t.sin().powi(2) / 2.0],
        [t.sin().powi(2) / 2.0, t / 2.0 + s2 / 4.0]
    ] * faer::Scale(4.0);
    assert!(rel(&qd, &want) < 1e-14, "{:e}", rel(&qd, &want));
    for (got, printed) in [
        (qd[(0, 0)], 0.00133067),
        (qd[(0, 1)], 0.01993342),
        (qd[(1, 1)], 0.39866933),
    ] {
        assert!((got - printed).abs() < 5e-9);
    }
    assert_eq!(qd[(0, 1)], qd[(1, 0)]);
}

/// Double integrator: e^{At} = [[1, t], [0, 1]], Γ(t) = [t²/2; t].
#[test]
fn double_integrator_zoh() {
    let a = mat![[0.0, 1.0], [0.0, 0.0]];
    let b = mat![[0.0], [1.0]];
    for t in [1e-3, 0.1, 1.0, 7.5, 100.0] {
        let (ad, bd) = zoh(a.as_ref(), b.as_ref(), t).unwrap();
        assert!(rel(&ad, &mat![[1.0, t], [0.0, 1.0]]) < 1e-15);
        assert!(rel(&bd, &mat![[t * t / 2.0], [t]]) < 1e-15, "t={t}");
    }
}

/// Diagonal and singular A: ∫₀ᵗ e^{as} ds = (e^{at} − 1)/a, and t for a = 0.
#[test]
fn expm_integral_diagonal_and_singular() {
    let a = mat![[-2.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.5]];
    let t: f64 = 1.3;
    let got = expm_integral(a.as_ref(), t).unwrap();
    let want = mat![
        [(-2.0 * t).exp_m1() / -2.0, 0.0, 0.0],
        [0.0, t, 0.0],
        [0.0, 0.0, (0.5 * t).exp_m1() / 0.5]
    ];
    assert!(rel(&got, &want) < 1e-15);
}

/// Scalar Gramian ∫₀ᵗ e^{2as} q ds = q·(e^{2at} − 1)/(2a).
#[test]
fn scalar_gramian() {
    for (a, q, t) in [(-1.0f64, 3.0, 2.0), (0.3, 1e-6, 5.0), (-40.0, 2.0, 0.01)] {
        let got = gramian_integral(mat![[a]].as_ref(), mat![[q]].as_ref(), t).unwrap()[(0, 0)];
        let want = q * (2.0 * a * t).exp_m1() / (2.0 * a);
        assert!((got - want).abs() <= 1e-14 * want.abs(), "{got} {want}");
    }
}

/// The coupling block is rescaled internally: the result is linear in B and Q over 24 orders of
/// magnitude.
#[test]
fn linear_in_the_coupling_block() {
    let a = mat![[-0.5, 2.0, 0.0], [-2.0, -0.5, 1.0], [0.0, 0.0, -3.0]];
    let b = mat![[1.0, 0.0], [0.5, -1.0], [0.0, 2.0]];
    let (_, g1) = zoh(a.as_ref(), b.as_ref(), 0.7).unwrap();
    for s in [1e-12, 1e12] {
        let (_, gs) = zoh(a.as_ref(), (&b * faer::Scale(s)).as_ref(), 0.7).unwrap();
        assert!(rel(&(&gs * faer::Scale(1.0 / s)), &g1) < 1e-14);
    }
    let q = mat![[2.0, 1.0, 0.0], [1.0, 2.0, 0.5], [0.0, 0.5, 1.0]];
    let w1 = gramian_integral(a.as_ref(), q.as_ref(), 0.7).unwrap();
    for s in [1e-12, 1e12] {
        let ws = gramian_integral(a.as_ref(), (&q * faer::Scale(s)).as_ref(), 0.7).unwrap();
        assert!(rel(&(&ws * faer::Scale(1.0 / s)), &w1) < 1e-14);
    }
}

#[test]
fn error_paths() {
    let a = mat![[1.0, 0.0], [0.0, 1.0]];
    assert!(matches!(
        zoh(a.as_ref(), Mat::<f64>::zeros(3, 1).as_ref(), 1.0),
        Err(LinalgError::Input(InputError::DimensionMismatch {
            expected: 2,
            found: 3,
            ..
        }))
    ));
    assert!(matches!(
        zoh(a.as_ref(), mat![[1.0], [f64::NAN]].as_ref(), 1.0),
        Err(LinalgError::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        zoh(a.as_ref(), mat![[1.0], [0.0]].as_ref(), f64::INFINITY),
        Err(LinalgError::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        gramian_integral(a.as_ref(), mat![[1.0, 2.0], [0.0, 1.0]].as_ref(), 1.0),
        Err(LinalgError::InvalidArgument(_))
    ));
    assert!(matches!(
        gramian_integral(a.as_ref(), mat![[1.0]].as_ref(), 1.0),
        Err(LinalgError::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        expm_integral(Mat::<f64>::zeros(2, 3).as_ref(), 1.0),
        Err(LinalgError::Input(InputError::NotSquare { .. }))
    ));
    // B with no columns is allowed: Γ is n×0.
    let (_, g) = zoh(a.as_ref(), Mat::<f64>::zeros(2, 0).as_ref(), 1.0).unwrap();
    assert_eq!(g.shape(), (2, 0));
}

fn matrix(n: usize) -> impl Strategy<Value = Mat<f64>> {
    proptest::collection::vec(-1.5f64..1.5, n * n)
        .prop_map(move |v| Mat::from_fn(n, n, |i, j| v[i + n * j]))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// A·Γ(t) = (e^{At} − I)·B and the ZOH block equals expm_scaled.
    #[test]
    fn zoh_identity(n in 1usize..7, seed in matrix(7), bcols in 1usize..3, t in 0.01f64..3.0) {
        let a = seed.submatrix(0, 0, n, n).to_owned();
        let b = Mat::from_fn(n, bcols, |i, j| seed[(6 - i, j)]);
        let (ad, gamma) = zoh(a.as_ref(), b.as_ref(), t).unwrap();
        let e = expm_scaled(a.as_ref(), t).unwrap();
        prop_assert!((&ad - &e).norm_max() <= 1e-13 * e.norm_max());
        let lhs = &a * &gamma;
        let rhs = (&e - Mat::<f64>::identity(n, n)) * &b;
        let scale = a.norm_max() * gamma.norm_max() + e.norm_max() * b.norm_max();
        prop_assert!((&lhs - &rhs).norm_max() <= 1e-13 * scale.max(1.0));
    }

    /// Gramian: symmetric, PSD for PSD Q, and d/dt W(t) = e^{Aᵀt} Q e^{At} (checked by
    /// W(t + h) − W(t) ≈ ∫_t^{t+h} via the semigroup identity W(t+h) = W(t) + e^{Aᵀt} W(h) e^{At}).
    #[test]
    fn gramian_semigroup_and_psd(n in 1usize..6, seed in matrix(6), g in matrix(6), t in 0.05f64..2.0, h in 0.05f64..1.0) {
        let a = seed.submatrix(0, 0, n, n).to_owned();
        let gg = g.submatrix(0, 0, n, n).to_owned();
        let q = &gg * gg.transpose();
        let q = Mat::from_fn(n, n, |i, j| 0.5 * (q[(i, j)] + q[(j, i)]));
        let wt = gramian_integral(a.as_ref(), q.as_ref(), t).unwrap();
        let wh = gramian_integral(a.as_ref(), q.as_ref(), h).unwrap();
        let wth = gramian_integral(a.as_ref(), q.as_ref(), t + h).unwrap();
        let e = expm_scaled(a.as_ref(), t).unwrap();
        let composed = &wt + e.transpose() * &wh * &e;
        prop_assert!((&wth - &composed).norm_max() <= 1e-12 * wth.norm_max().max(1e-300));
        for i in 0..n { for j in 0..n { prop_assert_eq!(wt[(i, j)], wt[(j, i)]); } }
        prop_assert!(min_eigenvalue(wt.as_ref()).unwrap() >= -1e-13 * wt.norm_max());
    }
}
