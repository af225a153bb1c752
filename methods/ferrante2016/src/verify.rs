//! A-posteriori verification of condition (12) of Theorem 1 (Ferrante et al. 2016), independent of the
//! polytopic embedding: on a dense grid of `v ∈ [T1, T2]` (plus a golden-section refinement of the worst
//! cell) with `e^{Av}` from `sporadic_linalg`,
//!
//! * the contraction of `E(v) = e^{Av}(I − LM)` in the norm of `P` must be strict:
//!   `γ(v) = ‖R E(v) R⁻¹‖₂² < 1` with `P = RᵀR` (Cholesky), which is (12) exactly, since
//!   `E'PE − P ≺ 0` iff `R⁻ᵀE'RᵀR E R⁻¹ ≺ I`; `γ(v) − 1 = λmax(P^{−½}(E'PE − P)P^{−½})` is the
//!   largest eigenvalue of (12) relative to `P` itself, and
//! * the spectral radius of `e^{Av}(I − LM)` must be below one (the necessary condition of Remark 3,
//!   which does not involve `P`).
//!
//! Both are reported; a design is only declared valid when both pass.
//!
//! **Why the factored form** (issue 22). `γ` does not change under any change of state
//! coordinates (`E → TET⁻¹`, `P → T⁻ᵀPT⁻¹`) or of the scale of `P`, and its rounding error is
//! about `u·κ(R)·‖E‖₂` with `κ(R) = √κ(P)`, both taken in the units in which `P` has a unit
//! diagonal ([`Verification::rounding`]). The earlier test asked for
//! `λmax(Δ(E'PE − P)Δ) < −10⁻⁹‖ΔPΔ‖` with `Δ = diag(P)^{−½}`, whose left side is at least
//! `−λmin(ΔPΔ)`: no certificate with a diagonally scaled condition number above `10⁹` could pass,
//! however strictly it contracts. On the corpus cart-pole (in coordinates `x = Tz`, `κ(T) < 10`)
//! a certificate with `κ(P) = 2.8·10⁸` contracts by `1 − γ = 3.2·10⁻³` while that test read
//! `−3.6·10⁻⁹` relative, and a window 1.8% longer failed it (`−2.8·10⁻¹⁰`): the largest
//! certified `T2` was 0.670 in those coordinates against 0.768 as given.

use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, MatRef, Side};
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
    /// Relative safety margin: (12) passes when the contraction in the norm of `P` is at least
    /// this, `γ − 1 < −max(tolerance, SAFETY·rounding)` (see the module docs), the spectral test
    /// when `ρ < 1 − tolerance`. Default `1e-9`.
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
    /// `max_v γ(v) − 1`, the largest eigenvalue of (12) relative to `P` itself
    /// (`λmax(P^{−½}(E'PE − P)P^{−½})`, see the module docs); `+∞` when `P` is not positive
    /// definite.
    pub relative_max_eigenvalue: f64,
    /// Estimate of the rounding error of [`Verification::relative_max_eigenvalue`] at the worst
    /// grid point, `2√γ·ε + ε² + nuγ` with `ε = 2nu·κ(R)·‖Ê‖₂` the first-order error bound
    /// of the two products `R Ê` and `(R Ê) R⁻¹` (`u = ε_mach/2` the unit roundoff, `κ(R) =
    /// √κ(P̂)`), where `P̂ = ΔPΔ` and `Ê = Δ⁻¹EΔ` with `Δ` the powers of two nearest
    /// `diag(P)^(−½)`: the check is made in the units in which `P` has a unit diagonal.
    pub rounding: f64,
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
    let n = p.nrows();
    // `P̂ = ΔPΔ` with `Δ` the powers of two nearest `diag(P)^(−½)` (exact scalings): `γ` is that
    // of `Ê = Δ⁻¹EΔ` in the norm of `P̂`, and its rounding is estimated there, so that neither
    // depends on the units of the state coordinates (a diagonal similarity).
    let delta: Vec<f64> = (0..n)
        .map(|i| {
            let d = p[(i, i)];
            if d > 0.0 && d.is_finite() {
                (-0.5 * d.log2()).round().exp2()
            } else {
                1.0
            }
        })
        .collect();
    let psym = Mat::from_fn(n, n, |i, j| {
        delta[i] * 0.5 * (p[(i, j)] + p[(j, i)]) * delta[j]
    });
    // λmax of (12)'s left-hand side in the user's scale at `e`, for the value reported.
    let lhs_at = |e: MatRef<'_, f64>| -> Result<f64, Error> {
        let er = e * reset.as_ref();
        let psi = congruence(er.as_ref(), p);
        // The symmetric part of the difference: `E'PE` is symmetric only up to rounding
        // relative to `‖P‖`, which near the boundary of (12) is not small relative to `E'PE − P`.
        let m = Mat::from_fn(n, n, |i, j| 0.5 * (psi[(i, j)] + psi[(j, i)]) - p[(i, j)]);
        Ok(max_eigenvalue(m.as_ref())?)
    };
    let radius = extremum(a, t1, t2, pts, Sense::Max, |_, e| {
        Ok(spectral_radius((e * reset.as_ref()).as_ref())?)
    })?;
    let grid_points = if window.is_periodic() { 1 } else { pts };
    let schur_holds = radius.value < 1.0 - options.tolerance;
    let eigenvalues = psym.self_adjoint_eigenvalues(Side::Lower).ok();
    let factor = psym.llt(Side::Lower).ok();
    let (Some(lambda), Some(factor)) = (eigenvalues, factor) else {
        return not_positive_definite(a, window, pts, &lhs_at, radius, schur_holds);
    };
    if !(lambda[0] > 0.0) {
        return not_positive_definite(a, window, pts, &lhs_at, radius, schur_holds);
    }
    // `R = Lᵀ` (`P̂ = LLᵀ`) and `R⁻¹`; `γ(v) = λmax(NᵀN)` with `N = R Ê R⁻¹`.
    let r = factor.L().transpose().to_owned();
    let r_inv = r.as_ref().partial_piv_lu().inverse();
    let gamma_at = |e: MatRef<'_, f64>| -> Result<(f64, f64), Error> {
        let er = e * reset.as_ref();
        let er = Mat::from_fn(n, n, |i, j| er[(i, j)] * delta[j] / delta[i]);
        let nm = &r * &er * &r_inv;
        let gram = nm.transpose() * &nm;
        Ok((max_eigenvalue(gram.as_ref())?, norm2(er.as_ref())?))
    };
    let gamma = extremum(a, t1, t2, pts, Sense::Max, |_, e| Ok(gamma_at(e)?.0 - 1.0))?;
    let worst = sporadic_linalg::expm_scaled(a, gamma.at)?;
    let (g, e_norm) = gamma_at(worst.as_ref())?;
    let kappa_r = (lambda[n - 1] / lambda[0]).sqrt();
    let eps = n as f64 * f64::EPSILON * kappa_r * e_norm;
    let rounding =
        2.0 * g.max(0.0).sqrt() * eps + eps * eps + 0.5 * n as f64 * f64::EPSILON * g.abs();
    Ok(Verification {
        grid_points,
        max_eigenvalue: lhs_at(worst.as_ref())?,
        max_eigenvalue_at: gamma.at,
        relative_max_eigenvalue: gamma.value,
        rounding,
        max_spectral_radius: radius.value,
        max_spectral_radius_at: radius.at,
        condition12_holds: gamma.value < -options.tolerance.max(SAFETY * rounding),
        schur_holds,
    })
}

/// Safety factor of the test of (12) over the rounding estimate [`Verification::rounding`].
pub const SAFETY: f64 = 10.0;

/// `‖m‖₂`.
fn norm2(m: MatRef<'_, f64>) -> Result<f64, Error> {
    Ok(m.singular_values()
        .map_err(|_| sporadic_linalg::LinalgError::NoConvergence {
            what: "singular values of e^(Av)(I − LM)".into(),
        })?
        .first()
        .copied()
        .unwrap_or(0.0))
}

/// The verification of a `P` that is not positive definite: (12) fails whatever its left-hand
/// side (its relative value is `+∞`); the value reported is `λmax` of that left-hand side at its
/// worst grid point.
fn not_positive_definite(
    a: MatRef<'_, f64>,
    window: &SamplingWindow,
    pts: usize,
    lhs_at: &dyn Fn(MatRef<'_, f64>) -> Result<f64, Error>,
    radius: crate::grid::Extremum,
    schur_holds: bool,
) -> Result<Verification, Error> {
    let lhs = extremum(a, window.t1(), window.t2(), pts, Sense::Max, |_, e| {
        lhs_at(e)
    })?;
    Ok(Verification {
        grid_points: if window.is_periodic() { 1 } else { pts },
        max_eigenvalue: lhs.value,
        max_eigenvalue_at: lhs.at,
        relative_max_eigenvalue: f64::INFINITY,
        rounding: 0.0,
        max_spectral_radius: radius.value,
        max_spectral_radius_at: radius.at,
        condition12_holds: false,
        schur_holds,
    })
}
