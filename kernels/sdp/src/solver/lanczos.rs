//! An upper bound on the largest eigenvalue of a symmetric operator from a few Lanczos steps,
//! for the step lengths of large blocks ([`super::step`]).
//!
//! The operator is only applied to vectors, so no `n×n` array is formed: SDPT3 computes the
//! step to the boundary of a block of order 200 or more the same way (`steplength.m`,
//! `lanczosfun`), at `O(kn²)` for `k` steps instead of the `O(n³)` of a congruence and an
//! eigenvalue decomposition.
//!
//! **Bound.** With full reorthogonalisation, `k` steps give the tridiagonal `T_k` and the
//! residual norm `r_1 = β_k |e_kᵀ y_1|` of its largest Ritz pair `(θ_1, y_1)`: an eigenvalue of
//! the operator lies within `r_1` of `θ_1`, and `θ_1 + r_1` bounds the largest one once the
//! Krylov space has found it, which it does in exact arithmetic when the start vector has a
//! component along the top eigenvector, the faster the larger that component. (SDPT3 tightens
//! `r_1` to `r_1²/g` by the Kato–Temple inequality, with the gap `g` to the next Ritz value;
//! that assumes no unresolved eigenvalue in the gap, and on a spectrum whose top is repeated it
//! fell below the largest eigenvalue.) Convergence is not tested before [`MIN_STEPS`] steps,
//! and the caller confirms the bound (a Cholesky test in [`super::step`]).

use faer::Mat;
use faer::linalg::matmul::matmul;
use faer::{Accum, Par};

/// Tolerance on the bound's excess `r_1`, relative to `max(|θ_1|, 1)`, at which the iteration
/// stops (SDPT3's `tol`, absolute there): the step to the boundary, `1/λ`, is then accurate to
/// about this relative to `λ` when it is a step the interior-point method can take (`λ ≳ 1`).
const TOL: f64 = 1e-3;

/// The Ritz values are computed every this many steps (and at the last), from
/// [`MIN_STEPS`] on.
const CHECK_EVERY: usize = 5;

/// Steps before convergence is tested (or `n`, if smaller): a few steps can resolve the next
/// eigenvalue to the tolerance before the start vector's small component along the extreme
/// eigenvector has grown (a random matrix of order 33: a Ritz value 1.8723 with a residual below
/// 1e-3 after 5 steps, the largest eigenvalue 1.9965).
const MIN_STEPS: usize = 15;

/// Largest number of steps for an operator of order `n` (SDPT3: `max(min(n, 30), √n)`).
fn max_steps(n: usize) -> usize {
    n.min(30).max((n as f64).sqrt().round() as usize)
}

/// An upper bound (see the module docs) on the largest eigenvalue of the symmetric operator
/// `apply` of order `n`, which writes `A v` into its second argument. `NaN` if a product is not
/// finite. The start vector is fixed (every component nonzero), so the result depends only on
/// the operator.
pub(crate) fn largest_eigenvalue_bound(n: usize, mut apply: impl FnMut(&[f64], &mut [f64])) -> f64 {
    if n == 0 {
        return f64::NEG_INFINITY;
    }
    let steps = max_steps(n);
    // Columns v_0 … v_steps of the Krylov basis.
    let mut basis = Mat::<f64>::zeros(n, steps + 1);
    basis.col_as_slice_mut(0).copy_from_slice(&start_vector(n));
    let mut alpha = Vec::with_capacity(steps);
    let mut beta: Vec<f64> = Vec::with_capacity(steps);
    let mut w = vec![0.0; n];
    let mut coefficients = Mat::<f64>::zeros(steps + 1, 1);
    for k in 0..steps {
        apply(basis.col_as_slice(k), &mut w);
        if !w.iter().all(|x| x.is_finite()) {
            return f64::NAN;
        }
        // Full reorthogonalisation against v_0 … v_k, twice ("twice is enough").
        let mut a = 0.0;
        for _ in 0..2 {
            let v = basis.as_ref().subcols(0, k + 1);
            let wm = faer::MatRef::from_column_major_slice(&w, n, 1);
            let mut c = coefficients.as_mut().subrows_mut(0, k + 1);
            matmul(c.as_mut(), Accum::Replace, v.transpose(), wm, 1.0, Par::Seq);
            a += c[(k, 0)];
            let wm = faer::MatMut::from_column_major_slice_mut(&mut w, n, 1);
            matmul(wm, Accum::Add, v, c.as_ref(), -1.0, Par::Seq);
        }
        alpha.push(a);
        let b = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        let last = k + 1 == steps || b <= f64::EPSILON * a.abs().max(1.0);
        if last || (k + 1 >= MIN_STEPS && (k + 1) % CHECK_EVERY == 0) {
            let (theta, residual) = largest_ritz_pair(&alpha, &beta, b);
            if last || residual <= TOL * theta.abs().max(1.0) {
                return theta + residual;
            }
        }
        beta.push(b);
        let next = basis.col_as_slice_mut(k + 1);
        for (vi, wi) in next.iter_mut().zip(&w) {
            *vi = wi / b;
        }
    }
    unreachable!("the last step returns")
}

/// The unit start vector of order `n`: irregular positive components (SDPT3 draws a random
/// one), so that an eigenvector of a structured operator is unlikely to be nearly orthogonal to
/// it, as a constant vector is to every antisymmetric mode of a Laplacian; fixed, so that the
/// solver's results do not depend on a seed.
fn start_vector(n: usize) -> Vec<f64> {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut v: Vec<f64> = (0..n)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            0.5 + (state >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect();
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    v.iter_mut().for_each(|x| *x /= norm);
    v
}

/// The largest Ritz value `θ_1` and its residual `r_1` from the tridiagonal with diagonal
/// `alpha` and off-diagonal `beta` (one shorter) and the next off-diagonal entry `b`.
fn largest_ritz_pair(alpha: &[f64], beta: &[f64], b: f64) -> (f64, f64) {
    let k = alpha.len();
    let t = Mat::<f64>::from_fn(k, k, |i, j| {
        if i == j {
            alpha[i]
        } else if i == j + 1 {
            beta[j]
        } else if j == i + 1 {
            beta[i]
        } else {
            0.0
        }
    });
    let Ok(evd) = t.self_adjoint_eigen(faer::Side::Lower) else {
        return (f64::NAN, f64::INFINITY);
    };
    // Eigenvalues ascending: the largest is the last; its residual is `b` times the last
    // component of its eigenvector.
    let top = k - 1;
    (evd.S()[top], b * evd.U()[(k - 1, top)].abs())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::XorShift;
    use proptest::prelude::*;

    /// `Q diag(λ) Qᵀ` with `Q` orthogonal from the QR factorisation of a random matrix, and `Q`.
    fn with_spectrum(rng: &mut XorShift, lambda: &[f64]) -> (Mat<f64>, Mat<f64>) {
        let n = lambda.len();
        let g = Mat::from_fn(n, n, |_, _| rng.centred());
        let q = g.qr().compute_Q();
        let mut m = Mat::zeros(n, n);
        for (k, &l) in lambda.iter().enumerate() {
            for j in 0..n {
                for i in 0..n {
                    m[(i, j)] += l * q[(i, k)] * q[(j, k)];
                }
            }
        }
        (m, q)
    }

    fn bound_of(m: &Mat<f64>) -> f64 {
        let n = m.nrows();
        largest_eigenvalue_bound(n, |v, out| {
            let vm = faer::MatRef::from_column_major_slice(v, n, 1);
            let om = faer::MatMut::from_column_major_slice_mut(out, n, 1);
            matmul(om, Accum::Replace, m.as_ref(), vm, 1.0, Par::Seq);
        })
    }

    proptest! {
        /// Where the start vector has a component of at least 0.05 along the top eigenvector
        /// and the top eigenvalue is apart from the rest (by 0.05 against a spread of 4), the
        /// bound is at least the largest eigenvalue (up to rounding) and close to it: spectra
        /// at random, in clusters of equal eigenvalues, and with the top repeated.
        #[test]
        fn bounds_the_largest_eigenvalue(
            n in 1usize..=120,
            seed in any::<u64>(),
            kind in 0usize..3,
        ) {
            let mut rng = XorShift(seed | 1);
            let mut lambda: Vec<f64> = (0..n).map(|_| 4.0 * rng.centred()).collect();
            if kind == 1 {
                lambda.iter_mut().for_each(|l| *l = l.round() / 2.0);
            }
            let mut top = lambda.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            for l in lambda.iter_mut() {
                if *l == top {
                    *l += 0.05;
                }
            }
            top += 0.05;
            if kind == 2 {
                lambda.iter_mut().take(n / 3).for_each(|l| *l = top);
            }
            let (m, q) = with_spectrum(&mut rng, &lambda);
            let v0 = start_vector(n);
            let along_top: f64 = (0..n)
                .filter(|&k| lambda[k] == top)
                .map(|k| (0..n).map(|i| q[(i, k)] * v0[i]).sum::<f64>().powi(2))
                .sum::<f64>()
                .sqrt();
            prop_assume!(along_top >= 0.05);
            let b = bound_of(&m);
            prop_assert!(b >= top - 1e-10 * (1.0 + top.abs()), "bound {b} below {top}");
            // Not much above it either (the excess is at most TOL once converged, the residual
            // otherwise).
            prop_assert!(b <= top + 0.05 * (1.0 + top.abs()), "bound {b} far above {top}");
        }
    }

    #[test]
    fn a_non_finite_product_gives_nan() {
        assert!(largest_eigenvalue_bound(3, |_, out| out.fill(f64::NAN)).is_nan());
    }
}
