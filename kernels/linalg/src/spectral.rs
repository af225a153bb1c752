//! Spectral quantities of general (non-symmetric) matrices.

use faer::{Mat, MatRef, c64};

use crate::{LinalgError, check};

/// ρ(A) = max |λ_i(A)|, from faer's real-input eigenvalue solver (Hessenberg QR).
///
/// # Errors
/// Non-square, empty or non-finite `a`; [`LinalgError::NoConvergence`] if the eigenvalue
/// iteration fails.
pub fn spectral_radius(a: MatRef<'_, f64>) -> Result<f64, LinalgError> {
    check::square_finite(a, "spectral_radius: A")?;
    let ev = a
        .eigenvalues()
        .map_err(|_| LinalgError::no_convergence("eigenvalues in spectral_radius"))?;
    Ok(ev.iter().map(|z| z.norm()).fold(0.0, f64::max))
}

/// A real eigenbasis `S` of a real matrix `A` and its eigenvalues ([`real_eigenbasis`]).
#[derive(Debug, Clone)]
pub struct RealEigenbasis {
    /// `S`: for each eigenvalue `σ + iω` with `ω > 0`, the real and imaginary parts of its
    /// eigenvector `u` (`‖u‖₂ = 1`), side by side; for a real eigenvalue its unit eigenvector.
    /// `S⁻¹AS` is block diagonal with the blocks `[[σ, ω], [−ω, σ]]` and `σ`, in the order of
    /// the columns.
    pub basis: Mat<f64>,
    /// The eigenvalues of `A`, as faer returns them (conjugate pairs included).
    pub eigenvalues: Vec<c64>,
}

/// The real eigenbasis of `a` (see [`RealEigenbasis`]) from faer's real-input eigenvalue
/// decomposition; `Ok(None)` when the decomposition has no such basis (an eigenvector of norm
/// zero or not finite, or conjugate pairs that do not match, so that the columns are not `n`).
/// The basis is not checked for conditioning: a defective or nearly defective `A` gives nearly
/// parallel columns, which the caller measures.
///
/// # Errors
/// Non-square, empty or non-finite `a`; [`LinalgError::NoConvergence`] if the eigenvalue
/// iteration fails.
pub fn real_eigenbasis(a: MatRef<'_, f64>) -> Result<Option<RealEigenbasis>, LinalgError> {
    check::square_finite(a, "real_eigenbasis: A")?;
    let n = a.nrows();
    let eigen = a
        .eigen()
        .map_err(|_| LinalgError::no_convergence("eigenvectors in real_eigenbasis"))?;
    let (u, lambda) = (eigen.U(), eigen.S().column_vector());
    let mut columns: Vec<Vec<f64>> = Vec::with_capacity(n);
    for j in 0..n {
        if lambda[j].im < 0.0 {
            continue;
        }
        // The real and imaginary parts of a complex pair's eigenvector share one scale, so that
        // `S⁻¹AS` holds the block `[[σ, ω], [−ω, σ]]`.
        let norm = (0..n)
            .map(|i| u[(i, j)].re.powi(2) + u[(i, j)].im.powi(2))
            .sum::<f64>()
            .sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            return Ok(None);
        }
        columns.push((0..n).map(|i| u[(i, j)].re / norm).collect());
        if lambda[j].im > 0.0 {
            columns.push((0..n).map(|i| u[(i, j)].im / norm).collect());
        }
    }
    if columns.len() != n {
        return Ok(None);
    }
    Ok(Some(RealEigenbasis {
        basis: Mat::from_fn(n, n, |i, j| columns[j][i]),
        eigenvalues: (0..n).map(|j| lambda[j]).collect(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn rotation_and_jordan() {
        // 0.5·rotation: |λ| = 0.5.
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let r = mat![[0.5 * c, -0.5 * s], [0.5 * s, 0.5 * c]];
        assert!((spectral_radius(r.as_ref()).unwrap() - 0.5).abs() < 1e-15);
        let j = mat![[-0.9, 100.0], [0.0, -0.9]];
        assert!((spectral_radius(j.as_ref()).unwrap() - 0.9).abs() < 1e-12);
        assert!(spectral_radius(mat![[1.0, f64::INFINITY], [0.0, 1.0]].as_ref()).is_err());
    }

    #[test]
    fn a_real_eigenbasis_block_diagonalises() {
        use faer::linalg::solvers::DenseSolveCore;
        // Eigenvalues −0.1 ± 2i, 3 and −1, mixed by a fixed well-conditioned T.
        let blocks = mat![
            [-0.1, 2.0, 0.0, 0.0],
            [-2.0, -0.1, 0.0, 0.0],
            [0.0, 0.0, 3.0, 0.0],
            [0.0, 0.0, 0.0, -1.0]
        ];
        let t = Mat::from_fn(4, 4, |i, j| {
            if i == j {
                2.0
            } else {
                ((3 * i + j) % 5) as f64 / 5.0 - 0.4
            }
        });
        let a = &t * &blocks * t.partial_piv_lu().inverse();
        let e = real_eigenbasis(a.as_ref()).unwrap().expect("a basis");
        let b = e.basis.partial_piv_lu().inverse() * &a * &e.basis;
        // Block diagonal with normal blocks: every entry off the blocks vanishes, and each 2×2
        // block is [[σ, ω], [−ω, σ]].
        let mut k = 0;
        while k < 4 {
            let pair = k + 1 < 4 && b[(k, k + 1)].abs() > 1e-9;
            let size = if pair { 2 } else { 1 };
            for i in 0..4 {
                for j in 0..4 {
                    let inside = (k..k + size).contains(&i) && (k..k + size).contains(&j);
                    if (k..k + size).contains(&j) && !inside {
                        assert!(b[(i, j)].abs() < 1e-12, "{b:?}");
                    }
                }
            }
            if pair {
                assert!((b[(k, k)] - b[(k + 1, k + 1)]).abs() < 1e-12, "{b:?}");
                assert!((b[(k, k + 1)] + b[(k + 1, k)]).abs() < 1e-12, "{b:?}");
                assert!((b[(k, k + 1)].abs() - 2.0).abs() < 1e-12, "{b:?}");
            }
            k += size;
        }
        assert_eq!(e.eigenvalues.len(), 4);
        assert!(real_eigenbasis(mat![[1.0, f64::NAN], [0.0, 1.0]].as_ref()).is_err());
    }
}
