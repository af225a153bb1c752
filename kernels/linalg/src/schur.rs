//! Real Schur decomposition A = U·T·Uᵀ (T upper quasi-triangular, U orthogonal) through faer's
//! public QZ routines applied to the pencil (A, I) (faer 0.24 exposes no standard real Schur
//! form).
//!
//! QZ returns orthogonal Q, Z with QᵀAZ = S (quasi-triangular) and QᵀIZ = R (triangular). R is
//! then orthogonal and triangular, hence R = D = diag(±1) and Z = Q·D, so QᵀAQ = S·D: T = S·D,
//! U = Q. The factorisation is verified (‖UTUᵀ − A‖ and the block structure of T) before use.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::ComputeEigenvectors;
use faer::linalg::gevd::{gen_hessenberg, qz_real};
use faer::{Col, Mat, MatRef, Par};

use crate::LinalgError;

/// T, U and the diagonal blocks of T as (first index, size ∈ {1, 2}).
pub(crate) struct RealSchur {
    pub(crate) t: Mat<f64>,
    pub(crate) u: Mat<f64>,
    pub(crate) blocks: Vec<(usize, usize)>,
}

/// Real Schur form of a square, finite, non-empty `a`.
pub(crate) fn real_schur(a: MatRef<'_, f64>) -> Result<RealSchur, LinalgError> {
    let n = a.nrows();
    let par = Par::Seq;
    let mut s = a.to_owned();
    let mut r = Mat::<f64>::identity(n, n);
    let mut q = Mat::<f64>::identity(n, n);
    let mut z = Mat::<f64>::identity(n, n);
    let hess_params: gen_hessenberg::GeneralizedHessenbergParams = faer::auto!(f64);
    let qz_params: faer::linalg::gevd::GeneralizedSchurParams = faer::auto!(f64);
    let req = gen_hessenberg::generalized_hessenberg_scratch::<f64>(n, hess_params)
        .or(qz_real::hessenberg_to_qz_scratch::<f64>(n, par, qz_params));
    let mut mem = MemBuffer::new(req);
    gen_hessenberg::generalized_hessenberg(
        s.as_mut(),
        r.as_mut(),
        Some(q.as_mut()),
        Some(z.as_mut()),
        par,
        MemStack::new(&mut mem),
        hess_params,
    );
    let (mut alphar, mut alphai, mut beta) = (
        Col::<f64>::zeros(n),
        Col::<f64>::zeros(n),
        Col::<f64>::zeros(n),
    );
    qz_real::hessenberg_to_qz(
        s.as_mut(),
        r.as_mut(),
        Some(q.as_mut()),
        Some(z.as_mut()),
        alphar.as_mut(),
        alphai.as_mut(),
        beta.as_mut(),
        ComputeEigenvectors::Yes,
        par,
        qz_params,
        MemStack::new(&mut mem),
    );
    let fail = || LinalgError::no_convergence("real Schur form (QZ on (A, I))");
    // T = S·D with D = sign(diag R); entries below the first subdiagonal are rounding noise.
    let mut t = Mat::from_fn(n, n, |i, j| {
        if i > j + 1 {
            0.0
        } else {
            s[(i, j)] * r[(j, j)].signum()
        }
    });
    let scale = a.norm_max().max(f64::MIN_POSITIVE);
    for k in 0..n.saturating_sub(1) {
        let sub = t[(k + 1, k)].abs();
        if sub != 0.0 && sub <= f64::EPSILON * (t[(k, k)].abs() + t[(k + 1, k + 1)].abs()) {
            t[(k + 1, k)] = 0.0;
        }
    }
    let mut blocks = Vec::with_capacity(n);
    let mut k = 0;
    while k < n {
        if k + 1 < n && t[(k + 1, k)] != 0.0 {
            if k + 2 < n && t[(k + 2, k + 1)] != 0.0 {
                return Err(fail());
            }
            blocks.push((k, 2));
            k += 2;
        } else {
            blocks.push((k, 1));
            k += 1;
        }
    }
    let residual = (&q * &t * q.transpose() - a).norm_max();
    if !residual.is_finite() || residual > 1e3 * n as f64 * f64::EPSILON * scale {
        return Err(fail());
    }
    Ok(RealSchur { t, u: q, blocks })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schur_of_a_matrix_with_complex_pairs() {
        let n = 7;
        let a = Mat::from_fn(n, n, |i, j| {
            ((i * 5 + j * 3) % 7) as f64 - 3.0 + if i == j { 0.5 } else { 0.0 }
        });
        let sch = real_schur(a.as_ref()).unwrap();
        let rec = &sch.u * &sch.t * sch.u.transpose();
        assert!((&rec - &a).norm_max() < 1e-12);
        assert!((sch.u.transpose() * &sch.u - Mat::<f64>::identity(n, n)).norm_max() < 1e-13);
        for j in 0..n {
            for i in j + 2..n {
                assert_eq!(sch.t[(i, j)], 0.0);
            }
        }
        assert_eq!(sch.blocks.iter().map(|b| b.1).sum::<usize>(), n);
        // 2×2 blocks carry complex eigenvalues: (t11 − t22)² + 4 t12 t21 < 0.
        for &(k, sz) in &sch.blocks {
            if sz == 2 {
                let (p, q, r, s) = (
                    sch.t[(k, k)],
                    sch.t[(k, k + 1)],
                    sch.t[(k + 1, k)],
                    sch.t[(k + 1, k + 1)],
                );
                assert!((p - s).powi(2) + 4.0 * q * r < 0.0);
            }
        }
    }
}
