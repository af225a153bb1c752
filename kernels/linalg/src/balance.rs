//! Diagonal balancing of a square matrix (LAPACK `gebal` scaling, no permutation; Parlett &
//! Reinsch 1969) and the exact maps of a diagonal change of state coordinates `x = D x_b`.
//!
//! A plant written in badly scaled units (e.g. millimetres and km/s) has `A` with entries over
//! many decades; every design that is not invariant under such a change of coordinates (a
//! normalisation `I ⪯ P`, a margin `μI`, a Taylor remainder tolerance, a grid spacing in `‖A‖`)
//! then gives a units-dependent verdict. The observer methods therefore design in balanced
//! coordinates `A_b = D⁻¹AD` and map the result back. The entries of `D` are powers of 2, so that
//! every map below is exact and an already balanced matrix is left bit-for-bit unchanged.

use faer::{Mat, MatRef};

/// Sweeps of the balancing iteration (each sweep that changes a scale reduces the off-diagonal row +
/// column norms by at least 5 %; LAPACK needs a handful).
const MAX_SWEEPS: usize = 200;

/// The diagonal `D` (powers of 2) of the `gebal` scaling of `a` (no permutation): `D⁻¹AD` has
/// off-diagonal row and column 2-norms within a factor 2 of each other where that lowers their sum
/// by at least 5 %. All ones when `a` is already balanced.
pub fn balancing_scales(a: MatRef<'_, f64>) -> Vec<f64> {
    let n = a.nrows();
    let mut b = a.to_owned();
    let mut d = vec![1.0f64; n];
    // Powers of 2 and bounds that keep the scales finite (LAPACK's sfmin/sfmax).
    let sfmin = f64::MIN_POSITIVE / f64::EPSILON;
    let sfmax = 1.0 / sfmin;
    for _ in 0..MAX_SWEEPS {
        let mut changed = false;
        for i in 0..n {
            let mut c = 0.0f64;
            let mut r = 0.0f64;
            for k in 0..n {
                if k != i {
                    c = c.hypot(b[(k, i)]);
                    r = r.hypot(b[(i, k)]);
                }
            }
            if c == 0.0 || r == 0.0 || !c.is_finite() || !r.is_finite() {
                continue;
            }
            let s = c + r;
            let mut f = 1.0f64;
            let (mut c2, mut r2) = (c, r);
            while c2 < r2 / 2.0 && f < sfmax / 2.0 && d[i] * f < sfmax / 2.0 {
                f *= 2.0;
                c2 *= 2.0;
                r2 /= 2.0;
            }
            while c2 / 2.0 >= r2 && f > sfmin * 2.0 && d[i] * f > sfmin * 2.0 {
                f /= 2.0;
                c2 /= 2.0;
                r2 *= 2.0;
            }
            if c2 + r2 >= 0.95 * s {
                continue;
            }
            d[i] *= f;
            for k in 0..n {
                b[(i, k)] /= f;
                b[(k, i)] *= f;
            }
            changed = true;
        }
        if !changed {
            break;
        }
    }
    d
}

/// `D⁻¹AD` for `D = diag(d)`.
pub fn balance_a(a: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)] * d[j] / d[i])
}

/// `CD` for `D = diag(d)`.
pub fn balance_c(c: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    Mat::from_fn(c.nrows(), c.ncols(), |i, j| c[(i, j)] * d[j])
}

/// `D⁻¹B` for `D = diag(d)` (a matrix acting into the state, e.g. an input or a nonlinearity
/// gain, in the balanced coordinates; also a form's row factor `L = D⁻¹L_b` back).
pub fn balance_b(b: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    Mat::from_fn(b.nrows(), b.ncols(), |i, j| b[(i, j)] / d[i])
}

/// `A = D A_b D⁻¹` (a state map in the user's coordinates; inverse of [`balance_a`]).
pub fn unbalance_a(a: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)] * d[i] / d[j])
}

/// `P_b = D P D` (a quadratic form `xᵀPx` in the balanced coordinates `x_b = D⁻¹x`; inverse of
/// [`unbalance_form`]).
pub fn balance_form(p: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    Mat::from_fn(p.nrows(), p.ncols(), |i, j| p[(i, j)] * d[i] * d[j])
}

/// `P = D⁻¹ P_b D⁻¹` (a quadratic form `x_bᵀP_bx_b` in the user's coordinates `x = Dx_b`).
pub fn unbalance_form(p: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    Mat::from_fn(p.nrows(), p.ncols(), |i, j| p[(i, j)] / (d[i] * d[j]))
}

/// `K = D K_b` (a gain `x̂_b⁺ = x̂_b + K_b(…)` in the user's coordinates `x = Dx_b`).
pub fn unbalance_gain(k: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    Mat::from_fn(k.nrows(), k.ncols(), |i, j| k[(i, j)] * d[i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn balanced_matrix_is_untouched_and_scales_are_powers_of_two() {
        let a = mat![[0.0, 2.0], [-2.0, -0.4]];
        assert_eq!(balancing_scales(a.as_ref()), vec![1.0, 1.0]);
        let bad = mat![[0.0, 1e6], [-4e-6, -0.4]];
        let d = balancing_scales(bad.as_ref());
        for x in &d {
            assert_eq!(x.log2().fract(), 0.0);
        }
        let b = balance_a(bad.as_ref(), &d);
        assert_eq!(unbalance_a(b.as_ref(), &d), bad);
        let col = mat![[3.0], [5.0]];
        assert_eq!(
            unbalance_gain(balance_b(col.as_ref(), &d).as_ref(), &d),
            col
        );
        assert!(b[(0, 1)].abs() < 8.0 && b[(1, 0)].abs() < 8.0, "{b:?}");
        // Powers of 2: the form round-trips exactly.
        let p = mat![[2.5, -0.3], [-0.3, 7.0]];
        assert_eq!(unbalance_form(balance_form(p.as_ref(), &d).as_ref(), &d), p);
    }
}
