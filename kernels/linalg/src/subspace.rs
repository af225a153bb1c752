//! Subspaces from the singular value decomposition.

use faer::{Mat, MatRef};

use crate::{LinalgError, check};

/// Orthonormal basis of ker M as the columns of an n×(n − r) matrix (n = number of columns
/// of M), from the right singular vectors of M belonging to singular values
/// σ ≤ tol = max(rows, cols)·ε·σ_max (the rank rule of MATLAB's `rank`/`null` and
/// NumPy's `matrix_rank`). `null_space(C)ᵀ` is an annihilator C^⊥ with C^⊥·Cᵀ = 0.
///
/// A matrix with no rows has kernel ℝⁿ (the identity is returned); one with no columns has
/// the trivial kernel in ℝ⁰ (a 0×0 matrix).
///
/// # Errors
/// [`LinalgError::Input`] (`NonFinite`) for NaN/Inf entries; [`LinalgError::NoConvergence`] if the SVD
/// fails.
pub fn null_space(m: MatRef<'_, f64>) -> Result<Mat<f64>, LinalgError> {
    let (rows, cols) = (m.nrows(), m.ncols());
    check::finite(m, "null_space: M")?;
    if cols == 0 {
        return Ok(Mat::zeros(0, 0));
    }
    if rows == 0 {
        return Ok(Mat::identity(cols, cols));
    }
    let svd = m
        .svd()
        .map_err(|_| LinalgError::no_convergence("SVD in null_space"))?;
    let s = svd.S().column_vector();
    let sigma_max = s.iter().copied().fold(0.0, f64::max);
    let tol = rows.max(cols) as f64 * f64::EPSILON * sigma_max;
    let rank = s.iter().filter(|&&x| x > tol).count();
    Ok(svd.V().submatrix(0, rank, cols, cols - rank).to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn kernel_of_a_row() {
        let c = mat![[1.0, 1.0, 0.0]];
        let k = null_space(c.as_ref()).unwrap();
        assert_eq!(k.shape(), (3, 2));
        assert!((&c * &k).norm_max() < 1e-15);
        assert!((k.transpose() * &k - Mat::<f64>::identity(2, 2)).norm_max() < 1e-15);
    }

    #[test]
    fn full_rank_and_degenerate_shapes() {
        let a = mat![[2.0, 0.0], [0.0, 3.0]];
        assert_eq!(null_space(a.as_ref()).unwrap().shape(), (2, 0));
        assert_eq!(
            null_space(Mat::<f64>::zeros(0, 3).as_ref()).unwrap(),
            Mat::<f64>::identity(3, 3)
        );
        assert_eq!(
            null_space(Mat::<f64>::zeros(2, 3).as_ref())
                .unwrap()
                .shape(),
            (3, 3)
        );
        assert!(null_space(mat![[f64::NAN]].as_ref()).is_err());
        // Rank deficiency at rounding level counts as deficient: rows 1 and 2 are parallel.
        let r = mat![[1.0, 2.0, 3.0], [0.1 * 1.0, 0.1 * 2.0, 0.1 * 3.0]];
        assert_eq!(null_space(r.as_ref()).unwrap().ncols(), 2);
    }
}
