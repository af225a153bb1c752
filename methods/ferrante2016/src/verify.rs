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
//!
//! **The certificate as its factor** ([`verify_factor`]). At the end of a long window of an
//! unstable plant `κ(P)` reaches `1/u` (it grows like `‖e^{A T2}‖²`): rounded to doubles, `P`
//! no longer determines its smallest eigenvalue, and the Cholesky residual alone makes the
//! allowance exceed one. A design therefore hands over the factor `R` it has from the
//! normalised coordinates, where its `P` is well conditioned (`crate::normalise::Scaling::factor_back`),
//! and the certificate is `P = RᵀR` exactly: `κ(R) = √κ(P)` and no residual. The products
//! are then the limit: their error estimate `u·κ(R)·‖Ê‖` exceeds one when `‖Ê‖ ~ 10⁶`, although
//! the error itself stays near `10⁻¹²` (measured in 60-digit arithmetic on the two-wheeled
//! robot of issue 22, `κ(R) = 7·10⁸`). A point that neither the stepper's exponential nor a
//! fresh one decides is evaluated again in double-double arithmetic
//! ([`sporadic_interval::double_double`]: `e^{Av}`, `I − LM`, `R⁻¹` and both products), whose
//! estimate is `u‖N‖` plus `10⁻³¹`-level terms amplified by `κ(R)²‖Ê‖`. On that robot the
//! largest certified `T2` went from 1.088 s and 1046.8 ms (seconds and milliseconds, both
//! ending at this check) to 1.226 s and 1172.8 ms (both ending at LMI (41), whose margin is
//! `10⁻⁹` there).

use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, MatRef, Side};
use sporadic_interval::constants::UNIT_ROUNDOFF;
use sporadic_interval::double_double::{self, DdMatrix, DoubleDouble, UNIT_ROUNDOFF_DD};
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
    /// Whether `P` was given by its factor `R` ([`verify_factor`]: `P = RᵀR` exactly, no
    /// Cholesky residual) rather than as a matrix ([`verify`]).
    pub factor_given: bool,
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

/// Checks (12) and the Schur property of `e^{Av}(I − LM)` on a dense grid of `[T1, T2]`, for
/// the Lyapunov matrix `P` as given (its Cholesky factor is computed, and the effect of its
/// residual is part of the rounding allowance; see the module docs).
pub fn verify(
    plant: &Plant,
    window: &SamplingWindow,
    l: MatRef<'_, f64>,
    p: MatRef<'_, f64>,
    options: &VerifyOptions,
) -> Result<Verification, Error> {
    plant.check_lyapunov_matrix(p)?;
    let n = p.nrows();
    // `P̂ = ΔPΔ` with `Δ` the powers of two nearest `diag(P)^(−½)` (exact scalings): `γ` is that
    // of `Ê = Δ⁻¹EΔ` in the norm of `P̂`, and its rounding is estimated there, so that neither
    // depends on the units of the state coordinates (a diagonal similarity).
    let delta = power_of_two_scaling(p);
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
    let eigenvalues = psym.self_adjoint_eigenvalues(Side::Lower).ok();
    let factor = psym.llt(Side::Lower).ok();
    let factored = match (eigenvalues, factor) {
        (Some(lambda), Some(factor)) if lambda[0] > 0.0 => {
            // `R = Lᵀ` (`P̂ ≈ LLᵀ`); `γ(v) = λmax(NᵀN)` with `N = R Ê R⁻¹` is the contraction
            // in the norm of `P̃ = RᵀR`, which differs from `P̂` by the residual
            // `δP = RᵀR − P̂` of the factorisation (of size `u‖P̂‖`, which `κ(P̂)` amplifies).
            // It is measured: `RᵀR` is formed in double-double arithmetic, and
            // `(1 + γ)‖R⁻ᵀδPR⁻¹‖_F` bounds the change of the largest eigenvalue of (12)
            // relative to `P̂` against that relative to `P̃` (module docs).
            let r = factor.L().transpose().to_owned();
            let r_inv = r.as_ref().partial_piv_lu().inverse();
            let residual = Mat::from_fn(n, n, |i, j| {
                let (x, y) = halves(i, j);
                let (hi, lo) = (0..=i.min(j))
                    .map(|k| two_prod(r[(k, i)], r[(k, j)]))
                    .chain([(-x, 0.0), (-y, 0.0)])
                    .fold((0.0, 0.0), |(hi, lo), (t, e)| {
                        let (s, f) = two_sum(hi, t);
                        (s, lo + f + e)
                    });
                hi + lo
            });
            Some(Factored {
                factorisation: (r_inv.transpose() * &residual * &r_inv).norm_l2(),
                kappa_r: (lambda[n - 1] / lambda[0]).sqrt(),
                r,
                r_inv,
                delta,
            })
        }
        _ => None,
    };
    contraction_test(plant, window, l, p, (factored, false), options)
}

/// Checks (12) and the Schur property of `e^{Av}(I − LM)` on a dense grid of `[T1, T2]` for the
/// Lyapunov matrix `P = RᵀR` given by its factor: `R` upper triangular with a positive
/// diagonal, and `P` the exact product (not its rounding). No factorisation is computed, so the
/// rounding allowance has no residual term: it is that of the products, of size `u·κ(R)`
/// with `κ(R) = √κ(P)` (module docs). A certificate whose `κ(P)` is near or beyond `1/u` (the
/// end of a long window of an unstable plant) cannot be checked as a matrix of doubles, whose
/// rounding alone moves its smallest eigenvalue by `u‖P‖`, but can as a factor.
pub fn verify_factor(
    plant: &Plant,
    window: &SamplingWindow,
    l: MatRef<'_, f64>,
    r: MatRef<'_, f64>,
    options: &VerifyOptions,
) -> Result<Verification, Error> {
    plant.check_lyapunov_factor(r)?;
    let n = r.nrows();
    // `Δ` the powers of two nearest `diag(P)^(−½)`, the inverse column norms of `R`; `R̂ = RΔ`
    // (exact), so that `P̂ = ΔPΔ = R̂ᵀR̂` has a diagonal near one.
    let delta: Vec<f64> = (0..n)
        .map(|j| nearest_power_of_two(r.col(j).norm_l2(), -1.0))
        .collect();
    let r_hat = Mat::from_fn(n, n, |i, j| r[(i, j)] * delta[j]);
    let p = factor_product(r);
    let factored = match spectral_condition(r_hat.as_ref()) {
        Some(kappa_r) if (0..n).all(|i| r[(i, i)] > 0.0) => Some(Factored {
            factorisation: 0.0,
            kappa_r,
            r_inv: r_hat.as_ref().partial_piv_lu().inverse(),
            r: r_hat,
            delta,
        }),
        _ => None,
    };
    contraction_test(plant, window, l, p.as_ref(), (factored, true), options)
}

/// `RᵀR` for an upper-triangular `R`, each entry summed in the same order as its mirror (the
/// result is exactly symmetric): the certificate of a factor rounded to doubles.
pub fn factor_product(r: MatRef<'_, f64>) -> Mat<f64> {
    let n = r.nrows();
    Mat::from_fn(n, n, |i, j| {
        (0..=i.min(j)).map(|k| r[(k, i)] * r[(k, j)]).sum::<f64>()
    })
}

/// The power of two nearest `x^e` (`1` for `x` not positive and finite; exponent within ±500,
/// so that every scaled entry stays finite): exact scalings.
fn nearest_power_of_two(x: f64, e: f64) -> f64 {
    if x > 0.0 && x.is_finite() {
        2f64.powi((e * x.log2()).round().clamp(-500.0, 500.0) as i32)
    } else {
        1.0
    }
}

/// The exact power-of-two congruence `Δ` with `Δ_ii ≈ P_ii^{−½}` (1 where `P_ii` is not
/// positive): the units in which `P` has a diagonal near one, for this check and for the proof
/// (`crate::prove`).
pub(crate) fn power_of_two_scaling(p: MatRef<'_, f64>) -> Vec<f64> {
    (0..p.nrows())
        .map(|i| nearest_power_of_two(p[(i, i)], -0.5))
        .collect()
}

/// `σmax(M)/σmin(M)` (`None` when the SVD fails or `M` is singular).
pub(crate) fn spectral_condition(m: MatRef<'_, f64>) -> Option<f64> {
    let s = m.singular_values().ok()?;
    let (hi, lo) = (*s.first()?, *s.last()?);
    (lo > 0.0).then(|| hi / lo)
}

/// `P̂ = ΔPΔ = RᵀR` in the units in which `P` has a diagonal near one (`Δ` exact powers of
/// two), for [`contraction_test`].
struct Factored {
    /// `R`, upper triangular.
    r: Mat<f64>,
    /// `R⁻¹` as computed.
    r_inv: Mat<f64>,
    /// The diagonal of `Δ`.
    delta: Vec<f64>,
    /// `κ(R)`.
    kappa_r: f64,
    /// `‖R⁻ᵀδPR⁻¹‖_F` for the residual `δP = RᵀR − P̂` of a computed factor (0 for a given
    /// one).
    factorisation: f64,
}

/// The grid test of (12) and of the Schur property shared by [`verify`] and [`verify_factor`]:
/// `p` is `P` as reported (for the value of (12) in the user's scale), `factored` its factor
/// (`None` when `P` is not positive definite).
fn contraction_test(
    plant: &Plant,
    window: &SamplingWindow,
    l: MatRef<'_, f64>,
    p: MatRef<'_, f64>,
    (factored, factor_given): (Option<Factored>, bool),
    options: &VerifyOptions,
) -> Result<Verification, Error> {
    let reset = plant.reset_matrix(l)?;
    options.validate()?;
    let (a, t1, t2) = (plant.a(), window.t1(), window.t2());
    let pts = options.grid_points.max(1);
    let n = p.nrows();
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
    let Some(Factored {
        r,
        r_inv,
        delta,
        kappa_r,
        factorisation,
    }) = factored
    else {
        return not_positive_definite(a, window, pts, &lhs_at, radius, (schur_holds, factor_given));
    };
    let anorm = a.norm_l1();
    // The contraction at `e` and its rounding estimate: `exponential` is the relative error
    // level of `e` (the stepper's bound on the uniform grid, `n + ‖Av‖₁` units of roundoff for
    // a fresh exponential: its first-order condition number for a normal `A`).
    let contraction = |e: MatRef<'_, f64>, exponential: f64| -> Result<(f64, f64), Error> {
        let er = e * reset.as_ref();
        let er = Mat::from_fn(n, n, |i, j| er[(i, j)] * delta[j] / delta[i]);
        let nm = &r * &er * &r_inv;
        let eps = (2.0 * n as f64 * UNIT_ROUNDOFF + exponential) * kappa_r * er.norm_l2();
        allowance(nm.as_ref(), eps, factorisation)
    };
    // The same in double-double arithmetic ([`sporadic_interval::double_double`]): `e^{Av}`,
    // `I − LM`, `R⁻¹` and the products, with `N` rounded to doubles at the end. Its error is
    // that rounding, `u‖N‖_F`, plus the double-double errors amplified as above (`κ(R)‖Ê‖_F`
    // times those of the exponential and the products, `κ(R)²‖Ê‖_F` times that of `R⁻¹`):
    // at the end of a long window of an unstable plant (`κ(R) ~ 10⁹`, `‖Ê‖ ~ 10⁶`) the
    // double-precision estimate exceeds one while this one stays below `10⁻⁶`.
    let r_dd = DdMatrix::from_f64(r.as_ref());
    let r_inv_dd = double_double::upper_triangular_inverse(r.as_ref());
    let (c, q) = (plant.c(), plant.q());
    let reset_dd = DdMatrix::from_fn(n, n, |i, j| {
        let lc = (0..q).fold(DoubleDouble::ZERO, |s, k| {
            s + DoubleDouble::product(l[(i, k)], c[(k, j)])
        });
        DoubleDouble::from(f64::from(u8::from(i == j))) - lc
    });
    let precise = |v: f64| -> Result<Option<(f64, f64)>, Error> {
        let (Some(e), Some(x)) = (double_double::expm(a, v), r_inv_dd.as_ref()) else {
            return Ok(None);
        };
        let er = e.mul(&reset_dd);
        let er = DdMatrix::from_fn(n, n, |i, j| er.get(i, j).scaled(delta[j] / delta[i]));
        let nm = r_dd.mul(&er).mul(x).to_f64();
        let ehat = er.to_f64().norm_l2();
        let level = (4.0 * n as f64 + anorm * v) * UNIT_ROUNDOFF_DD;
        let eps = UNIT_ROUNDOFF * nm.norm_l2() + level * kappa_r * (1.0 + kappa_r) * ehat;
        allowance(nm.as_ref(), eps, factorisation).map(Some)
    };
    let stepper = STEPPER_REANCHOR * (n as f64 + 1.0) * UNIT_ROUNDOFF;
    let fresh = |v: f64| (n as f64 + anorm * v) * UNIT_ROUNDOFF;
    // `γ − 1` and its rounding allowance at `v`, from the first evaluation that decides the
    // test `γ − 1 + rounding < −tolerance`: the stepper's `e` on its grid (when given), a
    // fresh exponential, double-double arithmetic; when none decides, the smallest value of
    // the test among them.
    // `fresh` is `e^{Av}` computed afresh at `v` (`expm_far`), needed only when the stepper's
    // `e` does not decide.
    let evaluate = |v: f64,
                    on_grid: Option<MatRef<'_, f64>>,
                    fresh_e: &dyn Fn() -> Result<Mat<f64>, Error>|
     -> Result<(f64, f64), Error> {
        let mut best = (f64::INFINITY, 0.0);
        let mut keep = |(rel, rounding): (f64, f64)| {
            if rel + rounding < best.0 + best.1 {
                best = (rel, rounding);
            }
            best.0 + best.1 < -options.tolerance
        };
        if let Some(e) = on_grid
            && keep(contraction(e, stepper)?)
        {
            return Ok(best);
        }
        if keep(contraction(fresh_e()?.as_ref(), fresh(v))?) {
            return Ok(best);
        }
        if let Some(x) = precise(v)? {
            keep(x);
        }
        Ok(best)
    };
    let test = |v: f64, e: MatRef<'_, f64>| -> Result<f64, Error> {
        let (rel, rounding) = evaluate(v, Some(e), &|| crate::grid::expm_far(a, v))?;
        Ok(rel + rounding)
    };
    let worst = extremum(a, t1, t2, pts, Sense::Max, test)?;
    let e = crate::grid::expm_far(a, worst.at)?;
    let (relative, rounding) = evaluate(worst.at, None, &|| Ok(e.clone()))?;
    Ok(Verification {
        grid_points,
        max_eigenvalue: lhs_at(e.as_ref())?,
        max_eigenvalue_at: worst.at,
        relative_max_eigenvalue: relative,
        rounding,
        max_spectral_radius: radius.value,
        max_spectral_radius_at: radius.at,
        factor_given,
        condition12_holds: worst.value < -options.tolerance,
        schur_holds,
    })
}

/// `(γ − 1, rounding)` for `N = R Ê R⁻¹` as computed, with `eps` its first-order error bound
/// (relative to nothing: an absolute bound on `‖δN‖₂`) and `factorisation` the effect of the
/// Cholesky residual ([`Verification::rounding`]).
fn allowance(nm: MatRef<'_, f64>, eps: f64, factorisation: f64) -> Result<(f64, f64), Error> {
    let n = nm.nrows();
    let gram = nm.transpose() * nm;
    let g = max_eigenvalue(gram.as_ref())?;
    let estimate = 2.0 * g.max(0.0).sqrt() * eps + eps * eps + n as f64 * UNIT_ROUNDOFF * g.abs();
    Ok((
        g - 1.0,
        SAFETY * estimate + MEASURED * (1.0 + g.abs()) * factorisation,
    ))
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
    (schur_holds, factor_given): (bool, bool),
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
        factor_given,
        condition12_holds: false,
        schur_holds,
    })
}
