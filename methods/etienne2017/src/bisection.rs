//! The largest admissible `τ̄` for a given `τ_low` (not in the paper): the shared window search
//! [`sporadic_model::search_upper`] on `τ̄` of the optimal margin `t*` of the margin problem
//! ([`crate::lmi`]), doubling from `2τ_low` and then bisecting to an absolute tolerance.
//!
//! **Monotonicity**, which makes bisection exact: a solution of (20) for `τ̄` gives one for every
//! `τ̄' ∈ [τ_low, τ̄]` with `P2' = P(τ̄')`, `L1' = L(τ̄')` and the same `P1, L0` — the new `M²` is
//! a convex combination of `M¹, M²`, the new (20c) is the old one
//! (`(τ_low/τ̄')(P1 − P2') = (τ_low/τ̄)(P1 − P2)`), and the new (20d) is the old `B(τ̄') ≻ 0`
//! of the proof of Theorem 3. With `L0 = L1` the same argument holds for Corollary 2. For the
//! periodic case (Remark 6) no such argument is available (`τ_low = τ̄` moves with `h`);
//! [`max_period`] bisects as well and says so ([`MaxTauBar::monotone_by_proof`]).
//!
//! A probe counts as feasible when `t* > threshold` (default `1e-7`, the scale of the example's
//! margins `~1e-4`). Independently, the largest probe whose point the LMI layer verified (margin
//! above its rounding-aware tolerance, a few `1e-7` for the example) is re-checked with every
//! independent check of [`crate::verify`] and returned as [`MaxTauBar::certified`]: the bracket
//! is the numerical boundary, the certified value a guaranteed one.
//!
//! One model is compiled per search; the window enters through parameters, so the solver's
//! structure analysis is reused by every probe.

use crate::design::{Design, DesignOptions, MarginSolution, finish};
use crate::error::Error;
use crate::lmi::{Bounds, Condition, GainTerm, Lmi20, LmiResult};
use crate::system::Plant;
use sporadic_linalg::InputError;
use sporadic_model::{
    Bracketing, Probe, Reason, SamplingWindow, SearchError, Tolerance, Verdict, WindowSearch,
    WindowSearchOptions, search_upper,
};
use sporadic_sdp::lmi::{FeasibilityOptions, Outcome};

/// Options of [`max_tau_bar`] and [`max_period`].
#[derive(Debug, Clone)]
pub struct BisectionOptions {
    /// LMI and check options used at every probe (default [`DesignOptions::default`]).
    pub design: DesignOptions,
    /// A probe is feasible iff `t* >` this (default `1e-7`).
    pub threshold: f64,
    /// Stop when the bracket `[feasible, infeasible]` is at most this wide (default `1e-5`).
    pub tolerance: f64,
    /// First trial `τ̄` (default `None`: `2τ_low`, or `4·tolerance` when `τ_low = 0`; `0.01` for
    /// [`max_period`]).
    pub start: Option<f64>,
    /// Largest `τ̄` tried while doubling (default 100).
    pub limit: f64,
    /// Largest number of probes of one search (default 100; the example needs about 25).
    pub max_probes: usize,
}

impl Default for BisectionOptions {
    fn default() -> Self {
        Self {
            design: DesignOptions::default(),
            threshold: 1e-7,
            tolerance: 1e-5,
            start: None,
            limit: 100.0,
            max_probes: 100,
        }
    }
}

impl BisectionOptions {
    /// Checks every field; the error names the offending one.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |name, value, reason| Err(InputError::parameter(name, value, reason).into());
        if !(self.threshold >= 0.0 && self.threshold.is_finite()) {
            return bad("threshold", self.threshold, "must be finite and ≥ 0");
        }
        if !(self.tolerance > 0.0 && self.tolerance.is_finite()) {
            return bad("tolerance", self.tolerance, "must be finite and > 0");
        }
        if !(self.limit > 0.0 && self.limit.is_finite()) {
            return bad("limit", self.limit, "must be finite and > 0");
        }
        if let Some(s) = self.start
            && !(s > 0.0 && s.is_finite())
        {
            return bad("start", s, "must be finite and > 0");
        }
        if self.max_probes < 2 {
            return bad(
                "max_probes",
                self.max_probes as f64,
                "at least two probes are needed",
            );
        }
        self.design.validate()
    }
}

/// Result of a search: the shared search's record, and the certified design at the largest
/// verified probe.
#[derive(Debug, Clone)]
pub struct MaxTauBar {
    /// The condition.
    pub condition: Condition,
    /// The fixed `τ_low` (`None` for the periodic search).
    pub tau_low: Option<f64>,
    /// The search: `best` is the largest feasible `τ̄` (`t* > threshold`), `first_failure` the
    /// smallest infeasible one above it; in each probe, `certified` means `t* > threshold`,
    /// `margin` is `t*`, `t1` the fixed `τ_low` (`t1 = t2 = h` for the periodic search, whose
    /// `fixed` is 0).
    pub search: WindowSearch,
    /// The design at the largest probe whose point the LMI layer verified, re-checked
    /// independently (`None` if no probe was verified, or when `τ_low = 0`: `[0, τ̄]` is no
    /// sampling window).
    pub certified: Option<Design>,
    /// Whether monotonicity of feasibility in `τ̄` is proven (Theorem 3, Corollary 2), so the
    /// bracket is the boundary of a single interval.
    pub monotone_by_proof: bool,
}

impl MaxTauBar {
    /// Largest probed feasible `τ̄` (`None`: no feasible probe).
    pub fn feasible(&self) -> Option<f64> {
        self.search.best
    }

    /// Smallest probed infeasible `τ̄` above it (`None` when the limit itself is feasible).
    pub fn infeasible(&self) -> Option<f64> {
        self.search.first_failure
    }

    /// Every probe, in order.
    pub fn probes(&self) -> &[Probe] {
        &self.search.probes
    }

    /// Midpoint of the bracket (the estimate of the largest `τ̄`), when both ends exist.
    pub fn estimate(&self) -> Option<f64> {
        Some(0.5 * (self.feasible()? + self.infeasible()?))
    }
}

/// One compiled instance of (20) with a free gain, moved from window to window.
pub(crate) struct CompiledProbe {
    condition: Condition,
    lmi: Lmi20,
}

impl CompiledProbe {
    /// Compiles (20) for `condition` at `first`.
    pub fn new(
        plant: &Plant,
        condition: Condition,
        first: Bounds,
        options: &FeasibilityOptions,
    ) -> Result<Self, Error> {
        let lmi = Lmi20::new(plant, condition, &first, GainTerm::Free, options)?;
        Ok(Self { condition, lmi })
    }

    /// Solves the margin problem at `bounds`.
    pub fn solve(&mut self, bounds: Bounds) -> Result<LmiResult, Error> {
        self.lmi.set_window(&bounds)?;
        self.lmi.solve()
    }

    /// Solves the margin problem at `window` ([`crate::solve_margin`] without recompiling the
    /// model).
    pub fn solve_window(&mut self, window: SamplingWindow) -> Result<MarginSolution, Error> {
        let r = self.solve(Bounds::of(&window))?;
        Ok(MarginSolution::from_parts(self.condition, window, r))
    }
}

/// The verdict of one threshold probe, with the reason of a failure.
fn threshold_verdict(r: &LmiResult, threshold: f64, condition: Condition) -> Verdict {
    if r.margin > threshold {
        return Verdict::certified(Some(r.margin));
    }
    let message = format!(
        "{}: optimal margin t* = {:.3e} of LMIs (20) is not above the threshold {threshold:.3e}; {}",
        condition.name(),
        r.margin,
        r.stats.reason
    );
    let reason = match r.stats.outcome {
        Outcome::Unbounded | Outcome::Inconclusive => Reason::SolverInconclusive { message },
        Outcome::Feasible | Outcome::Infeasible => Reason::InfeasibleLmi { message },
    };
    Verdict {
        certified: false,
        margin: Some(r.margin),
        reason: Some(reason),
    }
}

/// Whether the LMI layer verified strict feasibility at the returned point.
fn verified(r: &LmiResult) -> bool {
    r.stats.outcome == Outcome::Feasible && r.margin > 0.0
}

/// The threshold search shared by [`max_tau_bar`] and [`max_period`]: `window_of(τ̄)` gives the
/// bounds of a probe, `fixed` is the search's fixed end (a positive floor for the bisection).
fn run(
    plant: &Plant,
    condition: Condition,
    fixed: f64,
    start: f64,
    window_of: &dyn Fn(f64) -> Result<Bounds, Error>,
    options: &BisectionOptions,
) -> Result<(WindowSearch, Option<Design>), Error> {
    let mut probe = CompiledProbe::new(
        plant,
        condition,
        window_of(start)?,
        &options.design.feasibility,
    )?;
    let mut best_verified: Option<(Bounds, LmiResult)> = None;
    let search_options = WindowSearchOptions {
        bracketing: Bracketing::Doubling { start: Some(start) },
        tolerance: Tolerance::Absolute(options.tolerance),
        max_probes: options.max_probes,
    };
    let limit = options.limit.max(start);
    let search = search_upper(fixed, limit, &search_options, |tau_bar| {
        let bounds = window_of(tau_bar)?;
        let r = probe.solve(bounds)?;
        let v = threshold_verdict(&r, options.threshold, condition);
        if verified(&r)
            && best_verified
                .as_ref()
                .is_none_or(|(b, _)| b.tau_bar < tau_bar)
        {
            best_verified = Some((bounds, r));
        }
        Ok::<_, Error>(v)
    })
    .map_err(|e| match e {
        SearchError::Input(e) => Error::Input(e),
        SearchError::Probe(e) => e,
    })?;
    let certified = match best_verified {
        Some((b, r)) => match SamplingWindow::new(b.tau_low, b.tau_bar) {
            Ok(w) => Some(finish(
                plant,
                MarginSolution::from_parts(condition, w, r),
                None,
                &options.design.check,
            )?),
            // τ_low = 0: no sampling window, no design.
            Err(_) => None,
        },
        None => None,
    };
    Ok((search, certified))
}

/// The smallest positive `f64`: the floor of a search whose fixed end is 0 (the shared search
/// needs a positive fixed end; the bisection's midpoints `(floor + h)/2` are those of the floor
/// 0 in floating point).
const ZERO_FLOOR: f64 = f64::MIN_POSITIVE;

/// Largest `τ̄` for which `condition` (Theorem 3 or Corollary 2) is feasible with the given
/// `τ_low ≥ 0` (module docs). `τ_low = 0` is accepted so that the infeasibility of (20) without
/// a minimal dwell time can be searched ([`crate::solve_margin_without_dwell`]); no design is
/// returned there.
///
/// ```no_run
/// use sporadic_etienne2017::{BisectionOptions, Condition, example, max_tau_bar};
///
/// let plant = example::flexible_joint()?;
/// let r = max_tau_bar(&plant, Condition::Corollary2, 0.01, &BisectionOptions::default())?;
/// assert!((r.estimate().unwrap() - 0.2898).abs() < 2e-4);
/// # Ok::<(), sporadic_etienne2017::Error>(())
/// ```
pub fn max_tau_bar(
    plant: &Plant,
    condition: Condition,
    tau_low: f64,
    options: &BisectionOptions,
) -> Result<MaxTauBar, Error> {
    options.validate()?;
    if condition == Condition::Remark6 {
        return Err(InputError::parameter(
            "condition",
            f64::NAN,
            "the periodic case (Remark 6) is searched by max_period",
        )
        .into());
    }
    if !(tau_low.is_finite() && tau_low >= 0.0) {
        return Err(InputError::window(
            "sampling window [τ_low, τ̄]",
            tau_low,
            f64::NAN,
            "τ_low must be finite and ≥ 0",
        )
        .into());
    }
    let start = options.start.unwrap_or(if tau_low > 0.0 {
        2.0 * tau_low
    } else {
        4.0 * options.tolerance
    });
    if start <= tau_low {
        return Err(InputError::window(
            "sampling window [τ_low, τ̄]",
            tau_low,
            start,
            "the first trial τ̄ must exceed τ_low",
        )
        .into());
    }
    let fixed = if tau_low > 0.0 { tau_low } else { ZERO_FLOOR };
    let (mut search, certified) = run(
        plant,
        condition,
        fixed,
        start,
        &|t| Bounds::new(tau_low, t),
        options,
    )?;
    if tau_low == 0.0 {
        search.fixed = 0.0;
        search.probes.iter_mut().for_each(|p| p.t1 = 0.0);
    }
    Ok(MaxTauBar {
        condition,
        tau_low: Some(tau_low),
        search,
        certified,
        monotone_by_proof: true,
    })
}

/// Largest period `h` for which the periodic condition of Remark 6 is feasible, by the same
/// bracketing and bisection from `start` (default `0.01`); feasibility in `h` is not proven
/// monotone (module docs).
pub fn max_period(plant: &Plant, options: &BisectionOptions) -> Result<MaxTauBar, Error> {
    options.validate()?;
    let start = options.start.unwrap_or(0.01);
    let (mut search, certified) = run(
        plant,
        Condition::Remark6,
        ZERO_FLOOR,
        start,
        &|h| Bounds::new(h, h),
        options,
    )?;
    search.fixed = 0.0;
    search.probes.iter_mut().for_each(|p| p.t1 = p.t2);
    Ok(MaxTauBar {
        condition: Condition::Remark6,
        tau_low: None,
        search,
        certified,
        monotone_by_proof: false,
    })
}

/// One row of the table of largest `τ̄` over `τ_low`.
#[derive(Debug, Clone)]
pub struct TableRow {
    /// The fixed `τ_low`.
    pub tau_low: f64,
    /// One search per requested condition, in the order requested.
    pub searches: Vec<MaxTauBar>,
}

/// [`max_tau_bar`] for every `τ_low` of `tau_lows` and every condition of `conditions`
/// (Theorem 3 and/or Corollary 2).
pub fn max_tau_bar_table(
    plant: &Plant,
    conditions: &[Condition],
    tau_lows: &[f64],
    options: &BisectionOptions,
) -> Result<Vec<TableRow>, Error> {
    tau_lows
        .iter()
        .map(|&tau_low| {
            let searches = conditions
                .iter()
                .map(|&c| max_tau_bar(plant, c, tau_low, options))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(TableRow { tau_low, searches })
        })
        .collect()
}
