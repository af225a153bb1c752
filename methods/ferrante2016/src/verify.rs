//! A-posteriori verification of condition (12) of Theorem 1 (Ferrante et al. 2016), independent of the
//! polytopic embedding: on a dense grid of `v ∈ [T1, T2]` (plus a golden-section refinement of the worst
//! cell) with `e^{Av}` from `sporadic_linalg`,
//!
//! * `λmax((I − LM)' e^{A'v} P e^{Av} (I − LM) − P)` must be negative, and
//! * the spectral radius of `e^{Av}(I − LM)` must be below one (the necessary condition of Remark 3,
//!   which does not involve `P`).
//!
//! Both are reported; a design is only declared valid when both pass.

use faer::MatRef;
use sporadic_linalg::InputError;
use sporadic_linalg::{max_eigenvalue, spectral_radius};

use crate::bounds::congruence;
use crate::error::Error;
use crate::grid::{Sense, extremum};
use crate::system::Plant;
use sporadic_model::SamplingWindow;

/// Options of [`verify`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerifyOptions {
    /// Number of equally spaced grid points on `[T1, T2]` (a single point when `T1 = T2`).
    /// Default 2801 (spacing 0.001 on Example 2's `[0.2, 3]`).
    pub grid_points: usize,
    /// Relative safety margin: (12) passes when `λmax < −tolerance·‖P‖`, the spectral test when
    /// `ρ < 1 − tolerance`. Default `1e-9`.
    pub tolerance: f64,
}

impl VerifyOptions {
    /// Checks the options; the error names the offending field (`tolerance`: finite, `≥ 0`).
    /// (`grid_points = 0` is taken as 1.)
    pub fn validate(&self) -> Result<(), Error> {
        if !(self.tolerance.is_finite() && self.tolerance >= 0.0) {
            return Err(InputError::parameter(
                "tolerance",
                self.tolerance,
                "must be a nonnegative number",
            )
            .into());
        }
        Ok(())
    }
}

impl Default for VerifyOptions {
    fn default() -> Self {
        Self {
            grid_points: 2801,
            tolerance: 1e-9,
        }
    }
}

/// Result of [`verify`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Verification {
    /// Number of grid points evaluated (before refinement).
    pub grid_points: usize,
    /// Largest eigenvalue of (12)'s left-hand side over the grid and refinement.
    pub max_eigenvalue: f64,
    /// Where it is attained.
    pub max_eigenvalue_at: f64,
    /// `max_eigenvalue / ‖P‖`.
    pub relative_max_eigenvalue: f64,
    /// Largest spectral radius of `e^{Av}(I − LM)`.
    pub max_spectral_radius: f64,
    /// Where it is attained.
    pub max_spectral_radius_at: f64,
    /// Whether (12) holds on the grid (with the safety margin).
    pub condition12_holds: bool,
    /// Whether `e^{Av}(I − LM)` is Schur on the grid (with the safety margin).
    pub schur_holds: bool,
}

impl Verification {
    /// Both tests passed.
    pub fn passed(&self) -> bool {
        self.condition12_holds && self.schur_holds
    }
}

/// Checks (12) and the Schur property of `e^{Av}(I − LM)` on a dense grid of `[T1, T2]`.
pub fn verify(
    plant: &Plant,
    window: &SamplingWindow,
    l: MatRef<'_, f64>,
    p: MatRef<'_, f64>,
    options: &VerifyOptions,
) -> Result<Verification, Error> {
    plant.check_lyapunov_matrix(p)?;
    let reset = plant.reset_matrix(l)?;
    options.validate()?;
    let (a, t1, t2) = (plant.a(), window.t1(), window.t2());
    let pts = options.grid_points.max(1);
    // Scale-invariant form of (12): with Δ = diag(P)^(-1/2), the test is made on
    // Δ(lhs)Δ against Δ P Δ (unit diagonal), which does not change under a diagonal change of
    // state coordinates (so a certificate of a badly scaled plant is judged as in balanced
    // coordinates); the value reported is λmax of the unscaled left-hand side at the worst v.
    let n = p.nrows();
    let delta: Vec<f64> = (0..n)
        .map(|i| {
            let d = p[(i, i)];
            if d > 0.0 && d.is_finite() {
                1.0 / d.sqrt()
            } else {
                1.0
            }
        })
        .collect();
    let ps = faer::Mat::from_fn(n, n, |i, j| delta[i] * p[(i, j)] * delta[j]);
    let lhs_at = |e: faer::MatRef<'_, f64>, scaled: bool| -> Result<f64, Error> {
        let er = e * reset.as_ref();
        let psi = congruence(er.as_ref(), p);
        // The symmetric part of the difference: `E'PE` is symmetric only up to rounding
        // relative to `‖P‖`, which near the boundary of (12) is not small relative to `E'PE − P`.
        let w = |i: usize| if scaled { delta[i] } else { 1.0 };
        let m = faer::Mat::from_fn(n, n, |i, j| {
            w(i) * (0.5 * (psi[(i, j)] + psi[(j, i)]) - p[(i, j)]) * w(j)
        });
        Ok(max_eigenvalue(m.as_ref())?)
    };
    let lhs = extremum(a, t1, t2, pts, Sense::Max, |_, e| lhs_at(e, true))?;
    let worst = sporadic_linalg::expm_scaled(a, lhs.at)?;
    let lhs_user = lhs_at(worst.as_ref(), false)?;
    let radius = extremum(a, t1, t2, pts, Sense::Max, |_, e| {
        Ok(spectral_radius((e * reset.as_ref()).as_ref())?)
    })?;
    let norm_ps = max_eigenvalue(ps.as_ref())?.abs().max(f64::MIN_POSITIVE);
    Ok(Verification {
        grid_points: if window.is_periodic() { 1 } else { pts },
        max_eigenvalue: lhs_user,
        max_eigenvalue_at: lhs.at,
        relative_max_eigenvalue: lhs.value / norm_ps,
        max_spectral_radius: radius.value,
        max_spectral_radius_at: radius.at,
        condition12_holds: lhs.value < -options.tolerance * norm_ps,
        schur_holds: radius.value < 1.0 - options.tolerance,
    })
}
