//! Normalisation of the plant's state coordinates before the design (issue 22: verdicts must not
//! depend on the user's units).
//!
//! The design loop of §5.3 is not invariant under a change of state coordinates `x = D x_b`: the
//! normalisation `I ⪯ P_σ ⪯ p*I` of (47), the margin `μI` of (48) and the grid spacing (49)
//! (through `‖A‖₂` and the Step 1 constant `γ`) all depend on them. A plant written in badly
//! scaled units (e.g. millimetres and km/s) then needs a validation grid of 10³⁸ points, whereas the
//! same plant in SI units certifies at once. The method therefore designs in *balanced*
//! coordinates: `A_b = D⁻¹AD` with the diagonal `D` of the LAPACK `gebal` iteration (scaling only,
//! no permutation; Parlett & Reinsch 1969), whose entries are powers of 2, so that `A_b` and
//! `C_σ D` are exact and a plant that is already balanced is left bit-for-bit unchanged. The
//! result is mapped back exactly as well: with `x_b = D⁻¹x`,
//!
//! * `V = x_bᵀ P_b x_b = xᵀ D⁻¹P_bD⁻¹ x`, so `P = D⁻¹ P_b D⁻¹`;
//! * `x̂_b⁺ = x̂_b + K_b(y − C_bx̂_b)` is `x̂⁺ = x̂ + D K_b (y − Cx̂)`, so `K = D K_b`.
//!
//! Time scaling needs no normalisation: `Ξ_σ(τ)` of (44) depends on `A` and `τ` only through `Aτ`,
//! the spacing (49) scales with `1/‖A‖`, and Step 1's offsets with the plant's rate. Output scaling
//! needs none either: `Ξ_σ` depends on `C_σ` only through its kernel (orthonormal `C_σ^⊥`).

use faer::{Mat, MatRef};

use crate::error::Error;
use crate::plant::RoundRobinPlant;

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

/// The round-robin plant in the balanced coordinates `x_b = D⁻¹x` (`D = diag(d)`): `D⁻¹AD` and
/// `C_σD`, same windows, orthonormal complements.
///
/// # Errors
/// Those of [`RoundRobinPlant::new`].
pub fn balanced_plant(plant: &RoundRobinPlant, d: &[f64]) -> Result<RoundRobinPlant, Error> {
    let a = scale_a(plant.a(), d);
    let cs: Vec<Mat<f64>> = plant.sensors().iter().map(|s| scale_c(s.c(), d)).collect();
    let sensors: Vec<_> = cs
        .iter()
        .zip(plant.sensors())
        .map(|(c, s)| (c.as_ref(), s.window()))
        .collect();
    RoundRobinPlant::new(a.as_ref(), &sensors)
}

/// `D⁻¹AD` for `D = diag(d)`.
pub fn scale_a(a: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)] * d[j] / d[i])
}

/// `CD` for `D = diag(d)`.
pub fn scale_c(c: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    Mat::from_fn(c.nrows(), c.ncols(), |i, j| c[(i, j)] * d[j])
}

/// `P = D⁻¹ P_b D⁻¹` (the Lyapunov matrix in the user's coordinates).
pub fn unscale_p(p: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
    Mat::from_fn(p.nrows(), p.ncols(), |i, j| p[(i, j)] / (d[i] * d[j]))
}

/// `K = D K_b` (the gain in the user's coordinates).
pub fn unscale_k(k: MatRef<'_, f64>, d: &[f64]) -> Mat<f64> {
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
        let b = scale_a(bad.as_ref(), &d);
        assert!(b[(0, 1)].abs() < 8.0 && b[(1, 0)].abs() < 8.0, "{b:?}");
    }
}
