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

/// Bounds that keep the scales finite (LAPACK's `sfmin`; `sfmax = 1/sfmin`).
const SFMIN: f64 = f64::MIN_POSITIVE / f64::EPSILON;

/// The diagonal `D` (powers of 2) of the `gebal` scaling of `a` (no permutation): `D⁻¹AD` has
/// off-diagonal row and column 2-norms within a factor 2 of each other where that lowers their sum
/// by at least 5 %. All ones when `a` is already balanced.
pub fn balancing_scales(a: MatRef<'_, f64>) -> Vec<f64> {
    let n = a.nrows();
    let mut b = a.to_owned();
    let mut d = vec![1.0f64; n];
    let (sfmin, sfmax) = (SFMIN, 1.0 / SFMIN);
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

/// The diagonal `D` (powers of 2) of [`balancing_scales`] with the scales it leaves free fixed
/// as well. A state whose off-diagonal column is zero (it drives no other state, e.g. the angle
/// at the head of a motor's integrator chain) or whose off-diagonal row is zero (no other state
/// drives it) has no balanced scale: `gebal` skips it and keeps the user's unit, and the scales
/// of the states it is coupled to then follow that unit too, so `D⁻¹AD` depends on it (issue 22:
/// a DC motor with its angle in mrad refused a window that it certifies in rad). Such states are
/// peeled off one at a time (each test is on the states not yet peeled) until one state is left
/// or none is free; the remaining core is balanced by `gebal`, and each peeled state, in the
/// reverse order of peeling, gets the scale that makes the norm of its coupling to the states
/// scaled before it (its row if it is driven by one of them, else its column) equal to
/// `magnitude`, a rate the caller chooses from the problem (it must scale like `A` when time is
/// scaled, so that the balanced matrix does not depend on the units of time or state either). A
/// state coupled to none of them keeps scale 1. Equal to [`balancing_scales`] when no state is
/// peeled, and the peeled states keep scale 1 when `magnitude` is not positive and finite.
///
/// Used where only positive diagonal changes of coordinates are allowed, so that the choice of
/// these scales cannot be left to a later normalisation (the interval observer of Rabehi et al.
/// 2021, with the plant's slowest rate `min |a_ii|` as `magnitude`). The methods that also
/// change coordinates by a similarity keep [`balancing_scales`]: for Sferlazza et al. (2021) on a
/// rotorcraft whose actuator no state drives, a completed scaling (actuator coupling 0.4 instead
/// of 0.05) moved the precision limit of its proof of (48) below a 2600 ms window that the
/// `gebal` scaling certifies.
pub fn complete_balancing_scales(a: MatRef<'_, f64>, magnitude: f64) -> Vec<f64> {
    let n = a.nrows();
    let mut core: Vec<usize> = (0..n).collect();
    let mut peeled: Vec<usize> = Vec::new();
    while core.len() > 1 {
        let free = core.iter().position(|&i| {
            let column = core.iter().all(|&k| k == i || a[(k, i)] == 0.0);
            let row = core.iter().all(|&k| k == i || a[(i, k)] == 0.0);
            column || row
        });
        match free {
            Some(pos) => peeled.push(core.remove(pos)),
            None => break,
        }
    }
    if peeled.is_empty() {
        return balancing_scales(a);
    }
    let mut d = vec![1.0f64; n];
    let sub = Mat::from_fn(core.len(), core.len(), |i, j| a[(core[i], core[j])]);
    let sub_scales = balancing_scales(sub.as_ref());
    for (&i, &s) in core.iter().zip(&sub_scales) {
        d[i] = s;
    }
    if !(magnitude > 0.0 && magnitude.is_finite()) {
        return d;
    }
    let mut scaled: Vec<usize> = core;
    for &i in peeled.iter().rev() {
        let row = scaled
            .iter()
            .fold(0.0f64, |acc, &k| acc.hypot(a[(i, k)] * d[k]));
        let column = scaled
            .iter()
            .fold(0.0f64, |acc, &k| acc.hypot(a[(k, i)] / d[k]));
        let target = if row > 0.0 {
            row / magnitude
        } else if column > 0.0 {
            magnitude / column
        } else {
            1.0
        };
        if target.is_finite() && target > 0.0 {
            d[i] = 2f64.powi(target.clamp(SFMIN, 1.0 / SFMIN).log2().round() as i32);
        }
        scaled.push(i);
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

    /// The head of an integrator chain drives nothing: its scale, and through it the scales of
    /// the states it reads, no longer follow the user's units. A DC motor in every combination
    /// of power-of-2 units gets the same balanced matrix, and a free state's coupling the given
    /// magnitude up to a power of 2.
    #[test]
    fn undriven_and_undriving_states_are_balanced_too() {
        let motor = mat![[0.0, 1.0, 0.0], [0.0, -0.8, 4.0], [0.0, -1.5, -12.0]];
        let reference = balance_a(
            motor.as_ref(),
            &complete_balancing_scales(motor.as_ref(), 0.8),
        );
        for k in 0..27i32 {
            let units = [(k % 3) * 7 - 7, (k / 3 % 3) * 5 - 5, (k / 9) * 9 - 9];
            let t = Mat::from_fn(3, 3, |i, j| motor[(i, j)] * 2f64.powi(units[j] - units[i]));
            let b = balance_a(t.as_ref(), &complete_balancing_scales(t.as_ref(), 0.8));
            assert_eq!(b, reference, "units 2^{units:?}");
        }
        // ẋ1 = 1e-3·x2, ẋ2 = −2x2 (x1 drives nothing): |B_01| is the given 2.
        let lag = mat![[0.0, 1e-3], [0.0, -2.0]];
        let b = balance_a(lag.as_ref(), &complete_balancing_scales(lag.as_ref(), 2.0));
        assert!((2f64.sqrt()..=8f64.sqrt()).contains(&b[(0, 1)]), "{b:?}");
        // A state nothing drives (x1, row zero) gets its column norm set to the given 1.
        let fed = mat![[-3.0, 0.0], [1e5, -1.0]];
        let b = balance_a(fed.as_ref(), &complete_balancing_scales(fed.as_ref(), 1.0));
        assert!((0.5f64.sqrt()..=2f64.sqrt()).contains(&b[(1, 0)]), "{b:?}");
        // Without a magnitude the user's units stand.
        let chain = mat![[0.0, 5.0, 0.0], [0.0, 0.0, 0.25], [0.0, 0.0, 0.0]];
        assert_eq!(
            complete_balancing_scales(chain.as_ref(), f64::INFINITY),
            vec![1.0; 3]
        );
    }
}
