//! Gain synthesis (Theorem 3, Corollary 2, Remark 6 of Etienne et al. 2017) and the analysis of
//! a given gain, each solved by margin maximisation (formulation F, [`crate::lmi`]) and
//! re-verified independently ([`crate::verify`]).
//!
//! * [`solve_margin`]: the optimal margin `t*` and the returned point, whatever its sign (what the
//!   bisection and the tables need).
//! * [`design`]: a gain only when the LMI layer verified strict feasibility **and** every
//!   independent check passed; otherwise a typed error ([`Error::Infeasible`],
//!   [`Error::Inconclusive`], [`Error::VerificationFailed`]).
//! * [`analyse`]: (20) with `L0 = P1K0`, `L1 = P1K1` for a given schedule (an LMI in `P1, P2`).
//!
//! Gains are recovered as in the paper: `K0 = P1⁻¹L0`, `K1 = P1⁻¹L1` (Cholesky of `P1`), and
//! `K(τ)` interpolates them on `[τ_low, τ̄]` ([`GainSchedule`]).

use sporadic_model::{SamplingWindow, SolverStats};
use sporadic_sdp::lmi::{FeasibilityOptions, Outcome};

use crate::conditions::gain_from;
use crate::error::Error;
use crate::gain::GainSchedule;
use crate::lmi::{Bounds, Condition, GainTerm, Lmi20, LmiResult, fixed_term};
use crate::system::Plant;
use crate::verify::{CheckOptions, IndependentCheck, check_certificate};

/// Options of [`design`], [`analyse`] and [`solve_margin`].
#[derive(Debug, Clone, Default)]
pub struct DesignOptions {
    /// Margin-problem options (default [`FeasibilityOptions::default`]: the LMI layer's solver
    /// settings and verification safety factor). The normalisation of the margin problem
    /// (`‖P1‖₂, ‖P2‖₂ ≤ 1`, `L0`, `L1` free) is always applied on top.
    pub feasibility: FeasibilityOptions,
    /// Grids and safety factor of the independent checks (default [`CheckOptions::default`]:
    /// 201-point τ grids for (19b)/(19c), 2001 points for the discrete contraction, safety 100).
    pub check: CheckOptions,
}

impl DesignOptions {
    /// Checks the options of the independent checks ([`CheckOptions::validate`]; the solver
    /// settings are checked by the LMI layer when the model is compiled).
    pub fn validate(&self) -> Result<(), Error> {
        self.check.validate()
    }
}

/// The optimal margin of formulation F at one window (no verdict beyond the LMI layer's).
#[derive(Debug, Clone)]
pub struct MarginSolution {
    /// The condition solved.
    pub condition: Condition,
    /// The window.
    pub window: SamplingWindow,
    /// `t*` (strictly feasible in exact arithmetic iff `t* > 0`; the bisection of
    /// [`crate::bisection`] counts a window as feasible when `t* > 1e-7`).
    pub margin: f64,
    /// The point returned by the solver (a certificate when the layer verified it).
    pub certificate: crate::verify::Certificate,
    /// Solver statistics and the LMI layer's verdict.
    pub stats: SolverStats,
}

impl MarginSolution {
    /// Whether the LMI layer verified strict feasibility at the returned point.
    pub fn verified(&self) -> bool {
        self.stats.outcome == Outcome::Feasible && self.margin > 0.0
    }

    pub(crate) fn from_parts(condition: Condition, window: SamplingWindow, r: LmiResult) -> Self {
        Self {
            condition,
            window,
            margin: r.margin,
            certificate: crate::verify::Certificate {
                p1: r.p1,
                p2: r.p2,
                l0: r.l0,
                l1: r.l1,
            },
            stats: r.stats,
        }
    }
}

/// A verified observer design.
#[derive(Debug, Clone)]
pub struct Design {
    /// The LMI solution (margin, certificate, statistics).
    pub lmi: MarginSolution,
    /// The gain `K(τ)` (`K0 = P1⁻¹L0`, `K1 = P1⁻¹L1`).
    pub gain: GainSchedule,
    /// The independent checks (all passed).
    pub check: IndependentCheck,
}

/// Solves the margin problem of `condition` at `window` and returns `t*` and the point.
pub fn solve_margin(
    plant: &Plant,
    condition: Condition,
    window: &SamplingWindow,
    options: &DesignOptions,
) -> Result<MarginSolution, Error> {
    let mut lmi = Lmi20::new(
        plant,
        condition,
        &Bounds::of(window),
        GainTerm::Free,
        &options.feasibility,
    )?;
    Ok(MarginSolution::from_parts(condition, *window, lmi.solve()?))
}

/// The optimal margin of (20) with `τ_low = 0` ([`solve_margin_without_dwell`]).
#[derive(Debug, Clone)]
pub struct DwellFreeMargin {
    /// The condition solved (Theorem 3 or Corollary 2).
    pub condition: Condition,
    /// The upper bound `τ̄`.
    pub tau_bar: f64,
    /// `t*`.
    pub margin: f64,
    /// Solver statistics and the LMI layer's verdict.
    pub stats: SolverStats,
}

impl DwellFreeMargin {
    /// Whether the LMI layer verified strict feasibility at the returned point.
    pub fn verified(&self) -> bool {
        self.stats.outcome == Outcome::Feasible && self.margin > 0.0
    }
}

/// The margin problem of `condition` (Theorem 3 or Corollary 2) on `[0, τ̄]`: no minimal dwell
/// time, so no [`SamplingWindow`] (whose lower end is positive), but (20) is defined there. With
/// `rank C < n`, `He(L0C)` vanishes on `ker C`, so (20c) requires `(τ_low/τ̄)(P2 − P1) ≻ 0` on
/// `ker C` — impossible at `τ_low = 0`: this solve shows it (`t* ≤ 0`), which is why the paper
/// requires `τ_low > 0`.
pub fn solve_margin_without_dwell(
    plant: &Plant,
    condition: Condition,
    tau_bar: f64,
    options: &DesignOptions,
) -> Result<DwellFreeMargin, Error> {
    let bounds = Bounds::new(0.0, tau_bar)?;
    let mut lmi = Lmi20::new(
        plant,
        condition,
        &bounds,
        GainTerm::Free,
        &options.feasibility,
    )?;
    let r = lmi.solve()?;
    Ok(DwellFreeMargin {
        condition,
        tau_bar,
        margin: r.margin,
        stats: r.stats,
    })
}

/// Turns a margin solution into a verified design (or the reason why not).
pub(crate) fn finish(
    plant: &Plant,
    sol: MarginSolution,
    gain: Option<GainSchedule>,
    options: &CheckOptions,
) -> Result<Design, Error> {
    let name = sol.condition.name();
    match sol.stats.outcome {
        Outcome::Feasible if sol.margin > 0.0 => {}
        Outcome::Feasible | Outcome::Infeasible => {
            return Err(Error::Infeasible {
                condition: name,
                margin: Some(sol.margin),
                reason: sol.stats.reason.clone(),
            });
        }
        Outcome::Unbounded | Outcome::Inconclusive => {
            return Err(Error::Inconclusive {
                condition: name,
                reason: sol.stats.reason.clone(),
            });
        }
    }
    let cert = &sol.certificate;
    let gain = match gain {
        Some(g) => g,
        None => {
            let k0 = gain_from(cert.p1.as_ref(), cert.l0.as_ref())?;
            let k1 = gain_from(cert.p1.as_ref(), cert.l1.as_ref())?;
            if sol.condition == Condition::Theorem3 {
                GainSchedule::interpolated(k0.as_ref(), k1.as_ref(), sol.window)?
            } else {
                GainSchedule::constant(k1.as_ref(), sol.window)?
            }
        }
    };
    let check = check_certificate(plant, sol.condition, &sol.window, cert, &gain, options)?;
    if let Some(e) = check.failure() {
        return Err(e);
    }
    Ok(Design {
        lmi: sol,
        gain,
        check,
    })
}

/// Designs the observer gain of `condition` for `window`: margin maximisation, gain recovery,
/// independent verification.
///
/// ```
/// use sporadic_etienne2017::{Condition, DesignOptions, SamplingWindow, design, example};
///
/// let plant = example::flexible_joint()?;
/// let w = SamplingWindow::new(0.01, 0.2)?;
/// let d = design(&plant, Condition::Corollary2, &w, &DesignOptions::default())?;
/// assert!(d.lmi.margin > 4.7e-4); // t* = 4.799e-4 ((20a)/(20b) scaled by τ̄; 5.402e-4 unscaled)
/// assert!(d.check.discrete.spectral_radius.value < 1.0);
/// # Ok::<(), sporadic_etienne2017::Error>(())
/// ```
pub fn design(
    plant: &Plant,
    condition: Condition,
    window: &SamplingWindow,
    options: &DesignOptions,
) -> Result<Design, Error> {
    options.validate()?;
    let sol = solve_margin(plant, condition, window, options)?;
    finish(plant, sol, None, &options.check)
}

/// Solves (20) for a given gain schedule (`L0 = P1K0`, `L1 = P1K1`) on the schedule's window;
/// Remark 6 for a periodic window, otherwise the (20c)/(20d) pair of Theorem 3 / Corollary 2.
pub fn analyse_margin(
    plant: &Plant,
    gain: &GainSchedule,
    options: &DesignOptions,
) -> Result<MarginSolution, Error> {
    let window = *gain.window();
    let condition = analysis_condition(gain);
    let term = fixed_term(plant, gain)?;
    let mut lmi = Lmi20::new(
        plant,
        condition,
        &Bounds::of(&window),
        term,
        &options.feasibility,
    )?;
    Ok(MarginSolution::from_parts(condition, window, lmi.solve()?))
}

/// Certifies a given gain schedule ([`analyse_margin`] plus the independent checks).
pub fn analyse(
    plant: &Plant,
    gain: &GainSchedule,
    options: &DesignOptions,
) -> Result<Design, Error> {
    options.validate()?;
    let sol = analyse_margin(plant, gain, options)?;
    finish(plant, sol, Some(gain.clone()), &options.check)
}

/// The condition under which a given schedule is analysed.
pub(crate) fn analysis_condition(gain: &GainSchedule) -> Condition {
    if gain.window().is_periodic() {
        Condition::Remark6
    } else if gain.is_constant() {
        Condition::Corollary2
    } else {
        Condition::Theorem3
    }
}
