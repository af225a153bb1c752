//! Lyapunov solvers against the Kronecker-product formulation and residual checks.

use faer::linalg::solvers::Solve;
use faer::{Mat, mat};
use proptest::prelude::*;
use sporadic_linalg::InputError;
use sporadic_linalg::{LinalgError, is_positive_definite, kron, lyap_continuous, lyap_discrete};

/// Oracle: vec(AᵀX + XA) = (I ⊗ Aᵀ + Aᵀ ⊗ I) vec X, vec(AᵀXA) = (Aᵀ ⊗ Aᵀ) vec X.
fn kron_oracle(a: &Mat<f64>, q: &Mat<f64>, discrete: bool) -> Mat<f64> {
    let n = a.nrows();
    let id = Mat::<f64>::identity(n, n);
    let op = if discrete {
        kron(a.transpose(), a.transpose()) - Mat::<f64>::identity(n * n, n * n)
    } else {
        kron(id.as_ref(), a.transpose()) + kron(a.transpose(), id.as_ref())
    };
    let rhs = Mat::from_fn(n * n, 1, |k, _| -q[(k % n, k / n)]);
    let x = op.partial_piv_lu().solve(&rhs);
    Mat::from_fn(n, n, |i, j| x[(i + n * j, 0)])
}

fn residual(a: &Mat<f64>, x: &Mat<f64>, q: &Mat<f64>, discrete: bool) -> f64 {
    let r = if discrete {
        a.transpose() * x * a - x + q
    } else {
        a.transpose() * x + x * a + q
    };
    r.norm_max()
        / (a.norm_max().powi(if discrete { 2 } else { 1 }).max(1.0) * x.norm_max() + q.norm_max())
}

#[test]
fn continuous_closed_form_2x2() {
    // A = −I: X = Q/2.
    let a = mat![[-1.0, 0.0], [0.0, -1.0]];
    let q = mat![[2.0, 1.0], [1.0, 4.0]];
    let x = lyap_continuous(a.as_ref(), q.as_ref()).unwrap();
    assert!((&x - &q * faer::Scale(0.5)).norm_max() < 1e-15);
    // Discrete with A = I/2: X − X/4 = Q ⇒ X = 4Q/3.
    let x = lyap_discrete((&a * faer::Scale(-0.5)).as_ref(), q.as_ref()).unwrap();
    assert!((&x - &q * faer::Scale(4.0 / 3.0)).norm_max() < 1e-14);
}

#[test]
fn complex_eigenvalues_match_kronecker_oracle() {
    // Lightly damped oscillators coupled: 2×2 blocks in the Schur form.
    let a = mat![
        [-0.1, 2.0, 0.3, 0.0, 0.0],
        [-2.0, -0.1, 0.0, 0.5, 0.0],
        [0.0, 0.0, -0.5, 7.0, 1.0],
        [0.2, 0.0, -7.0, -0.5, 0.0],
        [0.0, 1.0, 0.0, 0.0, -3.0]
    ];
    let q = Mat::from_fn(5, 5, |i, j| {
        if i == j {
            2.0
        } else {
            0.1 * ((i + j) as f64).sin()
        }
    });
    let x = lyap_continuous(a.as_ref(), q.as_ref()).unwrap();
    let oracle = kron_oracle(&a, &q, false);
    assert!((&x - &oracle).norm_max() <= 1e-12 * oracle.norm_max());
    assert!(is_positive_definite(x.as_ref(), 0.0).unwrap());
    let ad = &a * faer::Scale(0.15);
    let xd = lyap_discrete(ad.as_ref(), q.as_ref()).unwrap();
    let oracle = kron_oracle(&ad, &q, true);
    assert!((&xd - &oracle).norm_max() <= 1e-12 * oracle.norm_max());
}

#[test]
fn nonsymmetric_q_is_solved_too() {
    let a = mat![[-1.0, 3.0, 0.0], [0.0, -2.0, 1.0], [1.0, 0.0, -4.0]];
    let q = mat![[1.0, 2.0, 0.0], [-1.0, 0.5, 3.0], [0.0, 0.0, 1.0]];
    for discrete in [false, true] {
        let a2 = if discrete {
            &a * faer::Scale(0.2)
        } else {
            a.clone()
        };
        let x = if discrete {
            lyap_discrete(a2.as_ref(), q.as_ref())
        } else {
            lyap_continuous(a2.as_ref(), q.as_ref())
        }
        .unwrap();
        assert!((&x - &kron_oracle(&a2, &q, discrete)).norm_max() < 1e-12 * x.norm_max());
    }
}

#[test]
fn singular_equations_are_reported() {
    // λ = ±1: λ1 + λ2 = 0.
    let a = mat![[1.0, 0.0], [0.0, -1.0]];
    let q = Mat::<f64>::identity(2, 2);
    assert!(matches!(
        lyap_continuous(a.as_ref(), q.as_ref()),
        Err(LinalgError::Singular { .. })
    ));
    // Purely imaginary pair ±i: λ + λ̄ = 0.
    let rot = mat![[0.0, 1.0], [-1.0, 0.0]];
    assert!(matches!(
        lyap_continuous(rot.as_ref(), q.as_ref()),
        Err(LinalgError::Singular { .. })
    ));
    // λ1·λ2 = 2·0.5 = 1.
    let d = mat![[2.0, 0.0], [1.0, 0.5]];
    assert!(matches!(
        lyap_discrete(d.as_ref(), q.as_ref()),
        Err(LinalgError::Singular { .. })
    ));
    // Unit-circle rotation: λ·λ̄ = 1.
    assert!(matches!(
        lyap_discrete(rot.as_ref(), q.as_ref()),
        Err(LinalgError::Singular { .. })
    ));
}

#[test]
fn error_paths() {
    let a = mat![[-1.0, 0.0], [0.0, -1.0]];
    assert!(matches!(
        lyap_continuous(a.as_ref(), Mat::<f64>::zeros(3, 3).as_ref()),
        Err(LinalgError::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        lyap_discrete(Mat::<f64>::zeros(2, 3).as_ref(), a.as_ref()),
        Err(LinalgError::Input(InputError::NotSquare { .. }))
    ));
    assert!(matches!(
        lyap_continuous(mat![[f64::NAN]].as_ref(), mat![[1.0]].as_ref()),
        Err(LinalgError::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        lyap_continuous(
            Mat::<f64>::zeros(0, 0).as_ref(),
            Mat::<f64>::zeros(0, 0).as_ref()
        ),
        Err(LinalgError::Input(InputError::Empty { .. }))
    ));
}

#[test]
fn order_40_residual() {
    let n = 40;
    let a = Mat::from_fn(n, n, |i, j| {
        let v = (((i * 37 + j * 101) % 17) as f64 - 8.0) / 16.0;
        if i == j { v - 6.0 } else { v }
    });
    let q = Mat::from_fn(n, n, |i, j| {
        if i == j {
            1.0 + i as f64 / n as f64
        } else {
            0.0
        }
    });
    let x = lyap_continuous(a.as_ref(), q.as_ref()).unwrap();
    assert!(
        residual(&a, &x, &q, false) < 1e-14,
        "{:e}",
        residual(&a, &x, &q, false)
    );
    let ad = &a * faer::Scale(1.0 / 9.0);
    let xd = lyap_discrete(ad.as_ref(), q.as_ref()).unwrap();
    assert!(
        residual(&ad, &xd, &q, true) < 1e-14,
        "{:e}",
        residual(&ad, &xd, &q, true)
    );
}

fn matrix(n: usize) -> impl Strategy<Value = Mat<f64>> {
    proptest::collection::vec(-1.0f64..1.0, n * n)
        .prop_map(move |v| Mat::from_fn(n, n, |i, j| v[i + n * j]))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Random stable A (shifted so that max Re λ ≤ −0.2) and Q = GGᵀ + I: X ≻ 0, tiny residual,
    /// agreement with the Kronecker oracle.
    #[test]
    fn continuous_random(n in 1usize..9, m in matrix(8), g in matrix(8)) {
        let a0 = m.submatrix(0, 0, n, n).to_owned();
        let shift = a0.norm_l2() + 0.2; // ≥ ‖A0‖₂ ≥ max Re λ(A0)
        let a = Mat::from_fn(n, n, |i, j| a0[(i, j)] - if i == j { shift } else { 0.0 });
        let gn = g.submatrix(0, 0, n, n).to_owned();
        let q = &gn * gn.transpose() + Mat::<f64>::identity(n, n);
        let x = lyap_continuous(a.as_ref(), q.as_ref()).unwrap();
        prop_assert!(residual(&a, &x, &q, false) < 1e-13);
        prop_assert!(is_positive_definite(x.as_ref(), 0.0).unwrap());
        let oracle = kron_oracle(&a, &q, false);
        prop_assert!((&x - &oracle).norm_max() <= 1e-11 * oracle.norm_max());
    }

    /// Random Schur-stable A (ρ(A) ≤ ‖A‖₂ ≤ 0.95).
    #[test]
    fn discrete_random(n in 1usize..9, m in matrix(8), g in matrix(8)) {
        let a0 = m.submatrix(0, 0, n, n).to_owned();
        let a = &a0 * faer::Scale(0.95 / a0.norm_l2().max(1e-3));
        let gn = g.submatrix(0, 0, n, n).to_owned();
        let q = &gn * gn.transpose() + Mat::<f64>::identity(n, n);
        let x = lyap_discrete(a.as_ref(), q.as_ref()).unwrap();
        prop_assert!(residual(&a, &x, &q, true) < 1e-13);
        prop_assert!(is_positive_definite(x.as_ref(), 0.0).unwrap());
        let oracle = kron_oracle(&a, &q, true);
        prop_assert!((&x - &oracle).norm_max() <= 1e-10 * oracle.norm_max());
    }
}
