//! Small dense helpers for the design constants that `sporadic-linalg` does not provide: extreme
//! generalised eigenvalues of a symmetric-definite pencil and the spectral norm.

use faer::{Mat, MatRef, Side};
use sporadic_linalg::{max_eigenvalue, min_eigenvalue, sym_part};

use crate::error::Error;

/// Extreme eigenvalues `(λmin, λmax)` of the symmetric-definite pencil `(S, P)`, i.e. of
/// `R^{-T} S R^{-1}` with `P = R'R` (Cholesky; `R' = ` faer's lower factor). `P` must be positive
/// definite and `S` symmetric (it is symmetrised to remove rounding).
pub(crate) fn pencil_extremes(s: MatRef<'_, f64>, p: MatRef<'_, f64>) -> Result<(f64, f64), Error> {
    let n = p.nrows();
    let llt = p.llt(Side::Lower).map_err(|_| Error::NoConvergence {
        what: "Cholesky factor of P (P is not positive definite)".into(),
    })?;
    let l = llt.L();
    // X = L⁻¹ S, then M = L⁻¹ Xᵀ = L⁻¹ S L⁻ᵀ (S symmetric).
    let mut x = sym_part(s)?;
    l.solve_lower_triangular_in_place(x.as_mut());
    let mut m = Mat::from_fn(n, n, |i, j| x[(j, i)]);
    l.solve_lower_triangular_in_place(m.as_mut());
    let m = sym_part(m.as_ref())?;
    Ok((min_eigenvalue(m.as_ref())?, max_eigenvalue(m.as_ref())?))
}

/// Spectral norm `‖M‖₂ = √λmax(M'M)`.
pub(crate) fn spectral_norm(m: MatRef<'_, f64>) -> Result<f64, Error> {
    let g = m.transpose() * m;
    let g = sym_part(g.as_ref())?;
    Ok(max_eigenvalue(g.as_ref())?.max(0.0).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pencil_with_identity_is_ordinary_spectrum() {
        let s = faer::mat![[2.0, 1.0], [1.0, 2.0]];
        let (lo, hi) = pencil_extremes(s.as_ref(), Mat::<f64>::identity(2, 2).as_ref()).unwrap();
        assert!((lo - 1.0).abs() < 1e-14 && (hi - 3.0).abs() < 1e-14);
    }

    #[test]
    fn pencil_diagonal_ratio() {
        let s = faer::mat![[6.0, 0.0], [0.0, 1.0]];
        let p = faer::mat![[2.0, 0.0], [0.0, 4.0]];
        let (lo, hi) = pencil_extremes(s.as_ref(), p.as_ref()).unwrap();
        assert!((lo - 0.25).abs() < 1e-14 && (hi - 3.0).abs() < 1e-14);
        assert!(pencil_extremes(s.as_ref(), (-&p).as_ref()).is_err());
    }

    #[test]
    fn spectral_norm_of_rank_one() {
        // u vᵀ has norm |u||v| = 5 · √2.
        let m = faer::mat![[3.0, 3.0], [4.0, 4.0]];
        assert!((spectral_norm(m.as_ref()).unwrap() - 5.0 * 2f64.sqrt()).abs() < 1e-13);
    }
}
