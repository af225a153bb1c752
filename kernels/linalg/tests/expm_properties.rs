//! Property tests of the matrix exponential (proptest): group identities, similarity,
//! commuting sums, exact results for nilpotent and diagonal matrices, and the
//! norm-estimation path for large orders.

use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, Scale};
use proptest::prelude::*;
use sporadic_linalg::{expm, expm_scaled};

fn matrix(n: usize, r: f64) -> impl Strategy<Value = Mat<f64>> {
    proptest::collection::vec(-r..r, n * n)
        .prop_map(move |v| Mat::from_fn(n, n, |i, j| v[i + n * j]))
}

fn sub(m: &Mat<f64>, n: usize) -> Mat<f64> {
    m.submatrix(0, 0, n, n).to_owned()
}

fn norm1(m: &Mat<f64>) -> f64 {
    (0..m.ncols())
        .map(|j| m.col(j).iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

const U: f64 = f64::EPSILON / 2.0;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// e^{A}·e^{−A} = I up to ≈ n·u·‖e^A‖·‖e^{−A}‖ times a modest constant (orders 1–16 cover
    /// both the stack and the faer kernels).
    #[test]
    fn inverse_pair(n in 1usize..17, m in matrix(16, 1.0), scale in 0.01f64..8.0) {
        let a = sub(&m, n) * Scale(scale);
        let e = expm(a.as_ref()).unwrap();
        let ei = expm((&a * Scale(-1.0)).as_ref()).unwrap();
        let err = norm1(&(&e * &ei - Mat::<f64>::identity(n, n)));
        let bound = 200.0 * n as f64 * U * norm1(&e) * norm1(&ei);
        prop_assert!(err <= bound, "n={} err={:e} bound={:e}", n, err, bound);
    }

    /// e^{2A} = (e^{A})².
    #[test]
    fn doubling(n in 1usize..13, m in matrix(12, 1.0), scale in 0.01f64..5.0) {
        let a = sub(&m, n) * Scale(scale);
        let e = expm(a.as_ref()).unwrap();
        let e2 = expm_scaled(a.as_ref(), 2.0).unwrap();
        let err = norm1(&(&e * &e - &e2));
        prop_assert!(err <= 200.0 * n as f64 * U * norm1(&e) * norm1(&e), "err={:e}", err);
    }

    /// B = αA + βA² commutes with A, so e^{A+B} = e^{A}·e^{B}.
    #[test]
    fn commuting_sum(n in 1usize..11, m in matrix(10, 0.8), alpha in -1.0f64..1.0, beta in -0.5f64..0.5) {
        let a = sub(&m, n);
        let b = &a * Scale(alpha) + &a * &a * Scale(beta);
        let lhs = expm((&a + &b).as_ref()).unwrap();
        let ea = expm(a.as_ref()).unwrap();
        let eb = expm(b.as_ref()).unwrap();
        let rhs = &ea * &eb;
        let err = norm1(&(&lhs - &rhs));
        let bound = 500.0 * n as f64 * U * (norm1(&ea) * norm1(&eb) + norm1(&lhs)) * (1.0 + norm1(&a) + norm1(&b));
        prop_assert!(err <= bound, "err={:e} bound={:e}", err, bound);
    }

    /// e^{SΛS⁻¹} = S·e^{Λ}·S⁻¹ with S = I + E, ‖E‖₁ ≤ 0.5 (κ₁(S) ≤ 3), Λ diagonal.
    #[test]
    fn similarity(n in 1usize..11, m in matrix(10, 1.0), lam in proptest::collection::vec(-4.0f64..2.0, 10)) {
        let e0 = sub(&m, n);
        let e = &e0 * Scale(0.5 / norm1(&e0).max(1e-12));
        let s = Mat::<f64>::identity(n, n) + &e;
        let si = s.partial_piv_lu().inverse();
        let d = Mat::from_fn(n, n, |i, j| if i == j { lam[i] } else { 0.0 });
        let ed = Mat::from_fn(n, n, |i, j| if i == j { lam[i].exp() } else { 0.0 });
        let a = &s * &d * &si;
        let got = expm(a.as_ref()).unwrap();
        let want = &s * &ed * &si;
        let err = norm1(&(&got - &want));
        let bound = 1000.0 * n as f64 * U * norm1(&s) * norm1(&si) * norm1(&ed) * (1.0 + norm1(&d));
        prop_assert!(err <= bound, "err={:e} bound={:e}", err, bound);
    }

    /// Strictly upper-triangular (nilpotent) N with small-integer entries: e^N = Σ_{k<n} N^k/k!
    /// (a finite sum, evaluated here in the test).
    #[test]
    fn nilpotent_exact(n in 2usize..10, v in proptest::collection::vec(-3i32..4, 100)) {
        let nmat = Mat::from_fn(n, n, |i, j| if j > i { v[i * 10 + j] as f64 } else { 0.0 });
        let mut want = Mat::<f64>::identity(n, n);
        let mut term = Mat::<f64>::identity(n, n);
        for k in 1..n {
            term = &term * &nmat * Scale(1.0 / k as f64);
            want += &term;
        }
        let got = expm(nmat.as_ref()).unwrap();
        let err = (&got - &want).norm_max();
        prop_assert!(err <= 1e-13 * want.norm_max(), "err={:e}", err);
        // Also when hidden in a general-looking orientation (lower triangular = transpose).
        let gotl = expm(nmat.transpose()).unwrap();
        prop_assert!((gotl.transpose() - &got).norm_max() <= 1e-15 * want.norm_max());
    }

    /// Diagonal input: entrywise exp, bit for bit.
    #[test]
    fn diagonal_exact(d in proptest::collection::vec(-700.0f64..700.0, 1..12)) {
        let n = d.len();
        let a = Mat::from_fn(n, n, |i, j| if i == j { d[i] } else { 0.0 });
        let e = expm(a.as_ref()).unwrap();
        for i in 0..n {
            for j in 0..n {
                prop_assert_eq!(e[(i, j)], if i == j { d[i].exp() } else { 0.0 });
            }
        }
    }

    /// Upper-triangular input (Code Fragment 2.1) agrees with the same matrix computed through
    /// a general similarity-free route: e^{T} = (e^{T/2})² on the general path would re-detect
    /// the structure, so compare with P·e^{PᵀTP}·Pᵀ for the reversal permutation P (which
    /// makes T lower triangular, handled by transposition) and with the inverse identity.
    #[test]
    fn triangular_consistency(n in 2usize..9, m in matrix(8, 2.0)) {
        let t = Mat::from_fn(n, n, |i, j| if j >= i { m[(i, j)] } else { 0.0 });
        let e = expm(t.as_ref()).unwrap();
        let p = Mat::from_fn(n, n, |i, j| if i + j == n - 1 { 1.0 } else { 0.0 });
        let el = expm((p.transpose() * &t * &p).as_ref()).unwrap();
        let back = &p * &el * p.transpose();
        prop_assert!((&back - &e).norm_max() <= 1e-14 * e.norm_max());
        let ei = expm((&t * Scale(-1.0)).as_ref()).unwrap();
        let err = norm1(&(&e * &ei - Mat::<f64>::identity(n, n)));
        prop_assert!(err <= 200.0 * n as f64 * U * norm1(&e) * norm1(&ei));
        // Diagonal of e^T is exp of the diagonal of T (recomputed exactly by Fragment 2.1).
        for i in 0..n {
            prop_assert!((e[(i, i)] - t[(i, i)].exp()).abs() <= 2.0 * U * t[(i, i)].exp());
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    /// Mid orders (faer GEMM and the blocked Padé LU of `expm::lu`, exact norms): the inverse
    /// identity e^{A}·e^{−A} = I and e^{2A} = (e^{A})², at norms that select every degree.
    #[test]
    fn inverse_pair_mid_orders(n in 17usize..80, m in matrix(80, 1.0), norm in 0.005f64..12.0) {
        let a0 = sub(&m, n);
        let a = &a0 * Scale(norm / norm1(&a0));
        let e = expm(a.as_ref()).unwrap();
        let ei = expm((&a * Scale(-1.0)).as_ref()).unwrap();
        let err = norm1(&(&e * &ei - Mat::<f64>::identity(n, n)));
        let bound = 200.0 * n as f64 * U * norm1(&e) * norm1(&ei);
        prop_assert!(err <= bound, "n={} err={:e} bound={:e}", n, err, bound);
        let e2 = expm_scaled(a.as_ref(), 2.0).unwrap();
        let err2 = norm1(&(&e * &e - &e2));
        prop_assert!(err2 <= 200.0 * n as f64 * U * norm1(&e) * norm1(&e), "err2={:e}", err2);
    }
}

/// Orders ≥ 200 use the Higham–Tisseur norm estimator: check the inverse identity and
/// e^{A} = (e^{A/2})² at n = 220.
#[test]
fn large_order_with_norm_estimation() {
    let n = 220;
    let mut state = 0x1234_5678_9abc_def0u64;
    let a0 = Mat::from_fn(n, n, |_, _| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    });
    let a = &a0 * Scale(3.0 / norm1(&a0));
    let e = expm(a.as_ref()).unwrap();
    let ei = expm((&a * Scale(-1.0)).as_ref()).unwrap();
    let err = norm1(&(&e * &ei - Mat::<f64>::identity(n, n)));
    assert!(
        err <= 50.0 * n as f64 * U * norm1(&e) * norm1(&ei),
        "{err:e}"
    );
    let h = expm_scaled(a.as_ref(), 0.5).unwrap();
    let err2 = norm1(&(&h * &h - &e)) / norm1(&e);
    assert!(err2 <= 1e-13, "{err2:e}");
}
