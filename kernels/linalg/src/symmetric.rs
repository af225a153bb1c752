//! Symmetric matrices: symmetric parts, extreme eigenvalues, definiteness tests and the
//! isometric vectorisation `svec`/`smat` used by semidefinite programming.

use crate::InputError;
use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, MatRef, Side};

use crate::{LinalgError, check};

/// Relative tolerance for "symmetric" input: max|s_ij − s_ji| ≤ `SYMMETRY_TOLERANCE`·max|s_ij|.
/// Matrices assembled by floating-point products such as GGᵀ or AᵀP + PA are symmetric to a
/// few ulp; anything further off is treated as a caller error rather than silently symmetrised.
pub const SYMMETRY_TOLERANCE: f64 = 1e-10;

/// He(A) = A + Aᵀ.
///
/// # Errors
/// Non-square, empty or non-finite `a`.
pub fn he(a: MatRef<'_, f64>) -> Result<Mat<f64>, LinalgError> {
    let n = check::square_finite(a, "he: A")?;
    Ok(Mat::from_fn(n, n, |i, j| a[(i, j)] + a[(j, i)]))
}

/// (A + Aᵀ)/2.
///
/// # Errors
/// Non-square, empty or non-finite `a`.
pub fn sym_part(a: MatRef<'_, f64>) -> Result<Mat<f64>, LinalgError> {
    let n = check::square_finite(a, "sym_part: A")?;
    Ok(Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)])))
}

/// `XᵀPX`, symmetrised (the product is symmetric only up to rounding): a quadratic form `P`
/// in the coordinates `x = Xx'`. The product is formed as `(XᵀP)X`.
pub fn symmetric_congruence(x: MatRef<'_, f64>, p: MatRef<'_, f64>) -> Mat<f64> {
    let y = x.transpose() * p * x;
    Mat::from_fn(y.nrows(), y.ncols(), |i, j| 0.5 * (y[(i, j)] + y[(j, i)]))
}

/// [`certificate_root`] `R` with its inverse (LU), the change of coordinates `x' = Rx` and its
/// way back; `None` as [`certificate_root`], or when the inverse has a non-finite entry.
pub fn certificate_coordinates(p: &[Mat<f64>]) -> Option<(Mat<f64>, Mat<f64>)> {
    let r = certificate_root(p)?;
    let r_inv = r.partial_piv_lu().inverse();
    r_inv.is_all_finite().then_some((r, r_inv))
}

/// `R` (upper triangular, positive diagonal) with `RᵀR = Σ_k P_k/‖P_k‖_max` (Cholesky; the `P_k`
/// symmetrised): the coordinates `x' = Rx` of a certificate made of the Lyapunov matrices
/// `P_k`, in which their sum is of the order of the identity. A certificate that is
/// ill-conditioned in the plant's coordinates (designed in other ones and mapped back, or whose
/// margin is below the verification threshold there) is checked or solved again in these.
/// `None` when the sum is not numerically positive definite, an entry is not finite, or `p`
/// is empty or its matrices are not square of one order.
pub fn certificate_root(p: &[Mat<f64>]) -> Option<Mat<f64>> {
    let n = p.first()?.nrows();
    let mut sum = Mat::<f64>::zeros(n, n);
    for pk in p {
        let m = pk.norm_max();
        if pk.nrows() != n || pk.ncols() != n || !(m > 0.0 && m.is_finite()) {
            return None;
        }
        sum += Mat::from_fn(n, n, |i, j| 0.5 * (pk[(i, j)] + pk[(j, i)]) / m);
    }
    let llt = sum.llt(Side::Lower).ok()?;
    let r = llt.L().transpose().to_owned();
    r.is_all_finite().then_some(r)
}

/// Checks that `s` is square, non-empty, finite and symmetric within [`SYMMETRY_TOLERANCE`];
/// returns its order.
pub(crate) fn check_symmetric(s: MatRef<'_, f64>, what: &str) -> Result<usize, LinalgError> {
    let n = check::square_finite(s, what)?;
    let scale = s.norm_max();
    let mut worst = 0.0f64;
    for j in 0..n {
        for i in 0..j {
            worst = worst.max((s[(i, j)] - s[(j, i)]).abs());
        }
    }
    if worst > SYMMETRY_TOLERANCE * scale {
        return Err(LinalgError::InvalidArgument(format!(
            "{what} must be symmetric: max|s_ij − s_ji| = {worst:.3e} exceeds {SYMMETRY_TOLERANCE:.3e}·max|s_ij| = {:.3e}",
            SYMMETRY_TOLERANCE * scale
        )));
    }
    Ok(n)
}

/// Ascending eigenvalues of the symmetric part of a (checked) symmetric matrix.
fn symmetric_eigenvalues(s: MatRef<'_, f64>, what: &str) -> Result<Vec<f64>, LinalgError> {
    let n = check_symmetric(s, what)?;
    let sym = Mat::from_fn(n, n, |i, j| 0.5 * (s[(i, j)] + s[(j, i)]));
    sym.self_adjoint_eigenvalues(Side::Lower).map_err(|_| {
        LinalgError::no_convergence(&format!("symmetric eigenvalue iteration for {what}"))
    })
}

/// Smallest eigenvalue of a symmetric matrix (faer's self-adjoint eigenvalue solver applied to
/// (S + Sᵀ)/2).
///
/// # Errors
/// Bad shape, non-finite entries, asymmetry beyond [`SYMMETRY_TOLERANCE`], or failure of the
/// eigenvalue iteration.
pub fn min_eigenvalue(s: MatRef<'_, f64>) -> Result<f64, LinalgError> {
    Ok(symmetric_eigenvalues(s, "min_eigenvalue: S")?[0])
}

/// Largest eigenvalue of a symmetric matrix; see [`min_eigenvalue`].
///
/// # Errors
/// As [`min_eigenvalue`].
pub fn max_eigenvalue(s: MatRef<'_, f64>) -> Result<f64, LinalgError> {
    let ev = symmetric_eigenvalues(s, "max_eigenvalue: S")?;
    Ok(ev[ev.len() - 1])
}

/// Whether S − margin·I is positive definite, decided by attempting its Cholesky factorisation
/// (S is symmetrised first). With `margin` > 0 this certifies λ_min(S) > margin up to the
/// backward error of Cholesky (≈ n·u·‖S‖).
///
/// # Errors
/// Bad shape, non-finite entries or `margin`, asymmetry beyond [`SYMMETRY_TOLERANCE`].
pub fn is_positive_definite(s: MatRef<'_, f64>, margin: f64) -> Result<bool, LinalgError> {
    let n = check_symmetric(s, "is_positive_definite: S")?;
    check::finite_scalar(margin, "is_positive_definite: margin")?;
    let shifted = Mat::from_fn(n, n, |i, j| {
        0.5 * (s[(i, j)] + s[(j, i)]) - if i == j { margin } else { 0.0 }
    });
    Ok(shifted.llt(Side::Lower).is_ok())
}

/// Symmetric vectorisation: the upper triangle of S, column by column
/// ((0,0), (0,1), (1,1), (0,2), …), with off-diagonal entries multiplied by √2, so that
/// svec(X)·svec(Y) = tr(XY) for symmetric X, Y. Length n(n+1)/2. Entries are taken from
/// (S + Sᵀ)/2.
///
/// # Errors
/// Bad shape, non-finite entries, asymmetry beyond [`SYMMETRY_TOLERANCE`].
pub fn svec(s: MatRef<'_, f64>) -> Result<Vec<f64>, LinalgError> {
    let n = check_symmetric(s, "svec: S")?;
    let mut v = Vec::with_capacity(n * (n + 1) / 2);
    for j in 0..n {
        for i in 0..=j {
            let x = 0.5 * (s[(i, j)] + s[(j, i)]);
            v.push(if i == j {
                x
            } else {
                x * std::f64::consts::SQRT_2
            });
        }
    }
    Ok(v)
}

/// Inverse of [`svec`]: the symmetric matrix whose svec is `v`.
///
/// # Errors
/// [`LinalgError::Input`] (`Empty`) for an empty slice; [`LinalgError::InvalidArgument`] if `v.len()` is
/// not a triangular number n(n+1)/2; [`LinalgError::Input`] (`NonFinite`) for NaN/Inf entries.
pub fn smat(v: &[f64]) -> Result<Mat<f64>, LinalgError> {
    if v.is_empty() {
        return Err(InputError::empty("svec vector").into());
    }
    if v.iter().any(|x| !x.is_finite()) {
        return Err(InputError::non_finite("smat: v").into());
    }
    // n = (√(8len + 1) − 1)/2, verified in integers.
    let len = v.len();
    let mut n = (((8 * len + 1) as f64).sqrt() as usize).saturating_sub(1) / 2;
    while n * (n + 1) / 2 < len {
        n += 1;
    }
    if n * (n + 1) / 2 != len {
        return Err(LinalgError::InvalidArgument(format!(
            "smat: length {len} is not n(n+1)/2 for any n"
        )));
    }
    let mut m = Mat::zeros(n, n);
    let mut k = 0;
    for j in 0..n {
        for i in 0..=j {
            let x = if i == j {
                v[k]
            } else {
                v[k] * std::f64::consts::FRAC_1_SQRT_2
            };
            m[(i, j)] = x;
            m[(j, i)] = x;
            k += 1;
        }
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn he_and_sym_part() {
        let a = mat![[1.0, 2.0], [4.0, 3.0]];
        assert_eq!(he(a.as_ref()).unwrap(), mat![[2.0, 6.0], [6.0, 6.0]]);
        assert_eq!(sym_part(a.as_ref()).unwrap(), mat![[1.0, 3.0], [3.0, 3.0]]);
        assert!(matches!(
            he(Mat::<f64>::zeros(2, 3).as_ref()),
            Err(LinalgError::Input(InputError::NotSquare {
                rows: 2,
                cols: 3,
                ..
            }))
        ));
    }

    #[test]
    fn extreme_eigenvalues_closed_form() {
        // [[2, 1], [1, 2]] has eigenvalues 1 and 3.
        let s = mat![[2.0, 1.0], [1.0, 2.0]];
        assert!((min_eigenvalue(s.as_ref()).unwrap() - 1.0).abs() < 1e-14);
        assert!((max_eigenvalue(s.as_ref()).unwrap() - 3.0).abs() < 1e-14);
        // Tridiagonal [-1, 2, -1] of order n: λ_k = 2 − 2cos(kπ/(n+1)).
        let n = 9;
        let t = Mat::from_fn(n, n, |i, j| {
            if i == j {
                2.0
            } else if i.abs_diff(j) == 1 {
                -1.0
            } else {
                0.0
            }
        });
        let pi = std::f64::consts::PI;
        let lo = 2.0 - 2.0 * (pi / (n as f64 + 1.0)).cos();
        let hi = 2.0 - 2.0 * (n as f64 * pi / (n as f64 + 1.0)).cos();
        assert!((min_eigenvalue(t.as_ref()).unwrap() - lo).abs() < 1e-14);
        assert!((max_eigenvalue(t.as_ref()).unwrap() - hi).abs() < 1e-14);
    }

    #[test]
    fn rejects_clearly_nonsymmetric() {
        let a = mat![[1.0, 2.0], [0.0, 1.0]];
        assert!(matches!(
            min_eigenvalue(a.as_ref()),
            Err(LinalgError::InvalidArgument(_))
        ));
        assert!(matches!(
            is_positive_definite(a.as_ref(), 0.0),
            Err(LinalgError::InvalidArgument(_))
        ));
        assert!(matches!(
            svec(a.as_ref()),
            Err(LinalgError::InvalidArgument(_))
        ));
        // Rounding-level asymmetry is accepted.
        let b = mat![[1.0, 0.3], [0.3 + 1e-16, 1.0]];
        assert!(min_eigenvalue(b.as_ref()).is_ok());
    }

    #[test]
    fn positive_definiteness_with_margin() {
        let s = mat![[2.0, 1.0], [1.0, 2.0]]; // λ = 1, 3
        assert!(is_positive_definite(s.as_ref(), 0.0).unwrap());
        assert!(is_positive_definite(s.as_ref(), 0.999).unwrap());
        assert!(!is_positive_definite(s.as_ref(), 1.001).unwrap());
        let indefinite = mat![[1.0, 2.0], [2.0, 1.0]]; // λ = −1, 3
        assert!(!is_positive_definite(indefinite.as_ref(), 0.0).unwrap());
        assert!(is_positive_definite(indefinite.as_ref(), -1.001).unwrap());
        assert!(matches!(
            is_positive_definite(s.as_ref(), f64::NAN),
            Err(LinalgError::Input(InputError::NonFinite { .. }))
        ));
    }

    #[test]
    fn svec_layout_and_inner_product() {
        let x = mat![[1.0, 2.0, 4.0], [2.0, 3.0, 5.0], [4.0, 5.0, 6.0]];
        let r2 = std::f64::consts::SQRT_2;
        assert_eq!(
            svec(x.as_ref()).unwrap(),
            vec![1.0, 2.0 * r2, 3.0, 4.0 * r2, 5.0 * r2, 6.0]
        );
        let y = mat![[0.5, -1.0, 0.0], [-1.0, 2.0, 1.5], [0.0, 1.5, -3.0]];
        let dot: f64 = svec(x.as_ref())
            .unwrap()
            .iter()
            .zip(svec(y.as_ref()).unwrap())
            .map(|(a, b)| a * b)
            .sum();
        // tr(XY) by hand: Σ_ij x_ij y_ij = 0.5 − 2 + 0 − 2 + 6 + 7.5 + 0 + 7.5 − 18 = −0.5.
        assert!((dot - (-0.5)).abs() < 1e-14);
    }

    #[test]
    fn smat_rejects_bad_lengths() {
        assert!(matches!(
            smat(&[1.0, 2.0]),
            Err(LinalgError::InvalidArgument(_))
        ));
        assert!(matches!(
            smat(&[]),
            Err(LinalgError::Input(InputError::Empty { .. }))
        ));
        assert!(matches!(
            smat(&[f64::NAN]),
            Err(LinalgError::Input(InputError::NonFinite { .. }))
        ));
        assert_eq!(smat(&[7.0]).unwrap(), mat![[7.0]]);
    }
}
