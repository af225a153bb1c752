//! Property tests for the small dense helpers.

use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, Scale};
use proptest::prelude::*;
use sporadic_linalg::{
    he, is_positive_definite, kron, max_eigenvalue, min_eigenvalue, null_space, smat,
    spectral_radius, svec, sym_part,
};

fn matrix(r: usize, c: usize) -> impl Strategy<Value = Mat<f64>> {
    proptest::collection::vec(-2.0f64..2.0, r * c)
        .prop_map(move |v| Mat::from_fn(r, c, |i, j| v[i + r * j]))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// smat(svec(S)) = S and svec(X)·svec(Y) = tr(XY).
    #[test]
    fn svec_round_trip_and_isometry(n in 1usize..9, x0 in matrix(8, 8), y0 in matrix(8, 8)) {
        let x = sym_part(x0.submatrix(0, 0, n, n)).unwrap();
        let y = sym_part(y0.submatrix(0, 0, n, n)).unwrap();
        let vx = svec(x.as_ref()).unwrap();
        prop_assert_eq!(vx.len(), n * (n + 1) / 2);
        let back = smat(&vx).unwrap();
        prop_assert!((&back - &x).norm_max() <= 4.0 * f64::EPSILON * x.norm_max());
        let dot: f64 = vx.iter().zip(svec(y.as_ref()).unwrap()).map(|(a, b)| a * b).sum();
        let tr: f64 = (0..n).map(|i| (&x * &y)[(i, i)]).sum();
        prop_assert!((dot - tr).abs() <= 1e-13 * (1.0 + tr.abs()));
    }

    /// M = L·R with inner dimension r: ker M has dimension cols − r, an orthonormal basis, and
    /// M·K ≈ 0.
    #[test]
    fn null_space_orthonormal(rows in 1usize..7, cols in 1usize..8, r in 0usize..7, l0 in matrix(6, 6), r0 in matrix(6, 7)) {
        let r = r.min(rows).min(cols);
        let l = l0.submatrix(0, 0, rows, r).to_owned();
        let rr = r0.submatrix(0, 0, r, cols).to_owned();
        let m = &l * &rr;
        let k = null_space(m.as_ref()).unwrap();
        // Generic random factors have full rank r (a rank drop would need measure-zero input).
        prop_assert_eq!(k.ncols(), cols - r);
        prop_assert!((k.transpose() * &k - Mat::<f64>::identity(k.ncols(), k.ncols())).norm_max() < 1e-13);
        prop_assert!((&m * &k).norm_max() <= 1e-13 * m.norm_max().max(1.0));
    }

    /// λ_min ≤ Rayleigh quotients ≤ λ_max, Σλ bounds via the trace, and the Cholesky test agrees
    /// with λ_min away from the boundary.
    #[test]
    fn eigen_bounds_and_definiteness(n in 1usize..9, a0 in matrix(8, 8), v in proptest::collection::vec(-1.0f64..1.0, 8), margin in -3.0f64..3.0) {
        let s = sym_part(a0.submatrix(0, 0, n, n)).unwrap();
        let lo = min_eigenvalue(s.as_ref()).unwrap();
        let hi = max_eigenvalue(s.as_ref()).unwrap();
        prop_assert!(lo <= hi);
        let x = Mat::from_fn(n, 1, |i, _| v[i] + 1e-3);
        let rq = (x.transpose() * &s * &x)[(0, 0)] / (x.transpose() * &x)[(0, 0)];
        prop_assert!(rq >= lo - 1e-12 && rq <= hi + 1e-12);
        let trace: f64 = (0..n).map(|i| s[(i, i)]).sum();
        prop_assert!(n as f64 * lo <= trace + 1e-12 && trace <= n as f64 * hi + 1e-12);
        if (lo - margin).abs() > 1e-9 {
            prop_assert_eq!(is_positive_definite(s.as_ref(), margin).unwrap(), lo > margin);
        }
        prop_assert_eq!(he(s.as_ref()).unwrap(), &s * Scale(2.0));
    }

    /// Mixed-product property (A⊗B)(C⊗D) = (AC)⊗(BD).
    #[test]
    fn kron_mixed_product(a in matrix(2, 3), b in matrix(3, 2), c in matrix(3, 2), d in matrix(2, 4)) {
        let lhs = kron(a.as_ref(), b.as_ref()) * kron(c.as_ref(), d.as_ref());
        let rhs = kron((&a * &c).as_ref(), (&b * &d).as_ref());
        prop_assert!((&lhs - &rhs).norm_max() <= 1e-13 * rhs.norm_max().max(1.0));
    }

    /// ρ(S·diag(λ)·S⁻¹) = max|λ| for well-conditioned S.
    #[test]
    fn spectral_radius_of_similar_diagonal(n in 1usize..8, e0 in matrix(7, 7), lam in proptest::collection::vec(-3.0f64..3.0, 7)) {
        let e = e0.submatrix(0, 0, n, n).to_owned();
        let e = &e * Scale(0.4 / e.norm_l2().max(1e-12));
        let s = Mat::<f64>::identity(n, n) + &e;
        let si = s.partial_piv_lu().inverse();
        let d = Mat::from_fn(n, n, |i, j| if i == j { lam[i] } else { 0.0 });
        let rho = spectral_radius((&s * &d * &si).as_ref()).unwrap();
        let want = lam[..n].iter().fold(0.0f64, |m, x| m.max(x.abs()));
        // Eigenvalues of a diagonalisable matrix with κ₂(S) ≤ 7/3 are well conditioned, except
        // where two λ nearly coincide (they may then split into a complex pair of equal modulus
        // up to O(√u·gap)); 1e-6 covers both.
        prop_assert!((rho - want).abs() <= 1e-6 * want.max(1.0), "{} vs {}", rho, want);
    }
}
