//! Spectral quantities of general (non-symmetric) matrices.

use faer::MatRef;

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
}
