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
//! coordinates (`E → TET⁻¹`, `P → T⁻ᵀPT⁻¹`) or of the scale of `P`. Its rounding error is
//! about `u·κ(R)·‖E‖` with `κ(R) = √κ(P)` for the products, plus the residual of the Cholesky
//! factor `R`, `(1 + γ)‖R⁻ᵀ(RᵀR − P)R⁻¹‖` (up to `u·κ(P)`), which is measured rather than bounded
//! (both in the units in which `P` has a unit diagonal; [`Verification::rounding`]). The test
//! asks for `γ − 1` below `−tolerance` by ten times the estimate and twice the measured residual
//! at every grid point. The
//! earlier test asked for
//! `λmax(Δ(E'PE − P)Δ) < −10⁻⁹‖ΔPΔ‖` with `Δ = diag(P)^{−½}`, whose left side is at least
//! `−λmin(ΔPΔ)`: no certificate with a diagonally scaled condition number above `10⁹` could pass,
//! however strictly it contracts. On the corpus cart-pole (in coordinates `x = Tz`, `κ(T) < 10`)
//! a certificate with `κ(P) = 2.8·10⁸` contracts by `1 − γ = 3.2·10⁻³` while that test read
//! `−3.6·10⁻⁹` relative, and a window 1.8% longer failed it (`−2.8·10⁻¹⁰`): the largest
//! certified `T2` was 0.670 in those coordinates against 0.768 as given.

use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, MatRef, Side};
use sporadic_interval::constants::UNIT_ROUNDOFF;
use sporadic_interval::exact::{two_prod, two_sum};
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
    /// Relative safety margin: (12) passes when `γ − 1 + rounding < −tolerance` at every
    /// point of the grid and refinement (see the module docs and [`Verification::rounding`]),
    /// the spectral test when `ρ < 1 − tolerance`. Default `1e-9`.
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
    /// Largest eigenvalue of (12)'s left-hand side, in the user's scale, at the point where the
    /// test of (12) is worst ([`Verification::max_eigenvalue_at`]; it is not itself tested:
    /// rounding can make it positive where the contraction is resolved).
    pub max_eigenvalue: f64,
    /// Where it is attained.
    pub max_eigenvalue_at: f64,
    /// `max_v γ(v) − 1`, the largest eigenvalue of (12) relative to `P` itself
    /// (`λmax(P^{−½}(E'PE − P)P^{−½})`, see the module docs); `+∞` when `P` is not positive
    /// definite.
    pub relative_max_eigenvalue: f64,
    /// The allowance for rounding in the test of (12) at the worst point,
    /// `SAFETY·(2√γ·ε + ε² + nuγ) + MEASURED·(1 + γ)‖R⁻ᵀδPR⁻¹‖_F`: `ε = (2nu + e)·κ(R)·‖Ê‖_F`
    /// is the first-order error bound of `N = R Ê R⁻¹` (the two products, and the relative error
    /// `e` of the exponential: `n + ‖Av‖₁` units of roundoff for a fresh one, the stepper's
    /// bound `256(n + 1)u` on its grid), and `δP = RᵀR − P̂` the residual of the Cholesky
    /// factor, formed in double-double arithmetic (measured, not bounded). `u = ε_mach/2`,
    /// `κ(R) = √κ(P̂)`, `P̂ = ΔPΔ` and `Ê = Δ⁻¹EΔ` with `Δ` the powers of two nearest
    /// `diag(P)^(−½)`: the check is made in the units in which `P` has a unit diagonal.
    pub rounding: f64,
    /// Largest spectral radius of `e^{Av}(I − LM)`.
    pub max_spectral_radius: f64,
    /// Where it is attained.
    pub max_spectral_radius_at: f64,
    /// Whether (12) holds on the grid: `γ(v) − 1 + rounding(v) < −tolerance` at every grid and
    /// refinement point, each with its own rounding allowance.
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
    // `P̂ = Δ·sym(P)·Δ`: each entry the exact sum of two doubles (the scalings are powers of
    // two), kept as such for the residual of its factorisation below.
    let halves = |i: usize, j: usize| {
        let w = 0.5 * delta[i] * delta[j];
        (w * p[(i, j)], w * p[(j, i)])
    };
    let psym = Mat::from_fn(n, n, |i, j| {
        let (x, y) = halves(i, j);
        x + y
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
    // `R = Lᵀ` (`P̂ ≈ LLᵀ`) and `R⁻¹`; `γ(v) = λmax(NᵀN)` with `N = R Ê R⁻¹` is the contraction
    // in the norm of `P̃ = RᵀR`, which differs from `P̂` by the residual `δP = RᵀR − P̂` of
    // the factorisation (of size `u‖P̂‖`, which `κ(P̂)` amplifies). It is measured: `RᵀR` is
    // formed in double-double arithmetic, and `(1 + γ)‖R⁻ᵀδPR⁻¹‖_F` bounds the change of the
    // largest eigenvalue of (12) relative to `P̂` against that relative to `P̃` (module docs).
    let r = factor.L().transpose().to_owned();
    let r_inv = r.as_ref().partial_piv_lu().inverse();
    let residual = Mat::from_fn(n, n, |i, j| {
        let (x, y) = halves(i, j);
        let (mut hi, mut lo) = (0.0, 0.0);
        let mut add = |(t, e): (f64, f64)| {
            let (s, f) = two_sum(hi, t);
            hi = s;
            lo += f;
            lo += e;
        };
        for k in 0..=i.min(j) {
            add(two_prod(r[(k, i)], r[(k, j)]));
        }
        add((-x, 0.0));
        add((-y, 0.0));
        hi + lo
    });
    let factorisation = (r_inv.transpose() * &residual * &r_inv).norm_l2();
    let kappa_r = (lambda[n - 1] / lambda[0]).sqrt();
    let anorm = a.norm_l1();
    // The contraction at `e` and its rounding estimate: `exponential` is the relative error
    // level of `e` (the stepper's bound on the uniform grid, `n + ‖Av‖₁` units of roundoff for
    // a fresh exponential: its first-order condition number for a normal `A`).
    let contraction = |e: MatRef<'_, f64>, exponential: f64| -> Result<(f64, f64), Error> {
        let er = e * reset.as_ref();
        let er = Mat::from_fn(n, n, |i, j| er[(i, j)] * delta[j] / delta[i]);
        let nm = &r * &er * &r_inv;
        let gram = nm.transpose() * &nm;
        let g = max_eigenvalue(gram.as_ref())?;
        let eps = (2.0 * n as f64 * UNIT_ROUNDOFF + exponential) * kappa_r * er.norm_l2();
        let estimate =
            2.0 * g.max(0.0).sqrt() * eps + eps * eps + n as f64 * UNIT_ROUNDOFF * g.abs();
        Ok((
            g - 1.0,
            SAFETY * estimate + MEASURED * (1.0 + g.abs()) * factorisation,
        ))
    };
    let stepper = STEPPER_REANCHOR * (n as f64 + 1.0) * UNIT_ROUNDOFF;
    let fresh = |v: f64| (n as f64 + anorm * v) * UNIT_ROUNDOFF;
    // The test function `γ − 1 + rounding` at every grid point (with its own rounding
    // allowance); a point of the stepper's grid that it does not decide is evaluated again with
    // a fresh exponential.
    let test = |v: f64, e: MatRef<'_, f64>| -> Result<f64, Error> {
        let (rel, rounding) = contraction(e, stepper)?;
        if rel + rounding < -options.tolerance {
            return Ok(rel + rounding);
        }
        let e = crate::grid::expm_far(a, v)?;
        let (rel, rounding) = contraction(e.as_ref(), fresh(v))?;
        Ok(rel + rounding)
    };
    let worst = extremum(a, t1, t2, pts, Sense::Max, test)?;
    let e = crate::grid::expm_far(a, worst.at)?;
    let (relative, rounding) = contraction(e.as_ref(), fresh(worst.at))?;
    Ok(Verification {
        grid_points,
        max_eigenvalue: lhs_at(e.as_ref())?,
        max_eigenvalue_at: worst.at,
        relative_max_eigenvalue: relative,
        rounding,
        max_spectral_radius: radius.value,
        max_spectral_radius_at: radius.at,
        condition12_holds: worst.value < -options.tolerance,
        schur_holds,
    })
}

/// The stepper's error bound in units of `(n + 1)u` ([`sporadic_linalg::DEFAULT_REANCHOR`]
/// steps between fresh exponentials).
const STEPPER_REANCHOR: f64 = sporadic_linalg::DEFAULT_REANCHOR as f64;

/// Safety factor of the test of (12) over the first-order rounding estimate of the products and
/// the exponential ([`Verification::rounding`]).
pub const SAFETY: f64 = 10.0;

/// Factor over the measured effect of the Cholesky residual ([`Verification::rounding`]): it
/// is computed, not bounded, and the factor covers the rounding of that computation.
pub const MEASURED: f64 = 2.0;

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
