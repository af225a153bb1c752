//! The largest admissible `τ̄` for a given `τ_low` (not in the paper; spec §7): bisection on `τ̄`
//! of the optimal margin `t*` of formulation F.
//!
//! **Monotonicity** (spec §3.3 note 6), which makes bisection exact: a solution of (20) for
//! `τ̄` gives one for every `τ̄' ∈ [τ_low, τ̄]` with `P2' = P(τ̄')`, `L1' = L(τ̄')` and the same
//! `P1, L0` — the new `M²` is a convex combination of `M¹, M²`, the new (20c) is the old one
//! (`(τ_low/τ̄')(P1 − P2') = (τ_low/τ̄)(P1 − P2)`), and the new (20d) is the old `B(τ̄') ≻ 0`.
//! With `L0 = L1` the same argument holds for Corollary 2. For the periodic case (Remark 6) no
//! such argument is available (`τ_low = τ̄` moves with `h`); [`max_period`] bisects as well and
//! says so ([`MaxTauBar::monotone_by_proof`]).
//!
//! A probe counts as feasible when `t* > threshold` (spec: `1e-7`). Independently, the largest
//! probe whose point the LMI layer verified (margin above its rounding-aware tolerance, a few
//! `1e-7` for the example) is re-checked with every independent check of [`crate::verify`] and
//! returned as [`MaxTauBar::certified`]: the bracket is the numerical boundary, the certified
//! value a guaranteed one.
//!
//! One model is compiled per search; the window enters through parameters, so the solver's
//! structure analysis is reused by every probe.

use crate::design::{Design, DesignOptions, MarginSolution, finish};
use crate::error::Error;
use crate::lmi::{Condition, GainTerm, Lmi20};
use crate::system::{Plant, Window};
use sporadic_linalg::InputError;

/// Options of [`max_tau_bar`] and [`max_period`].
#[derive(Debug, Clone)]
pub struct BisectionOptions {
    /// LMI and check options used at every probe.
    pub design: DesignOptions,
    /// A probe is feasible iff `t* >` this (default `1e-7`, spec §3.6).
    pub threshold: f64,
    /// Stop when the bracket `[feasible, infeasible]` is at most this wide (default `1e-5`).
    pub tolerance: f64,
    /// First trial `τ̄` (default `None`: `2τ_low`, or `4·tolerance` when `τ_low = 0`).
    pub start: Option<f64>,
    /// Largest `τ̄` tried while doubling (default 100).
    pub limit: f64,
}

impl Default for BisectionOptions {
    fn default() -> Self {
        Self {
            design: DesignOptions::default(),
            threshold: 1e-7,
            tolerance: 1e-5,
            start: None,
            limit: 100.0,
        }
    }
}

/// One probed `τ̄`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Probe {
    /// The probed `τ̄` (`h` for the periodic search).
    pub tau_bar: f64,
    /// Optimal margin `t*`.
    pub margin: f64,
    /// `t* > threshold`.
    pub feasible: bool,
    /// The LMI layer verified the returned point.
    pub verified: bool,
}

/// Result of a search.
#[derive(Debug, Clone)]
pub struct MaxTauBar {
    /// The condition.
    pub condition: Condition,
    /// The fixed `τ_low` (`None` for the periodic search).
    pub tau_low: Option<f64>,
    /// Largest probed feasible `τ̄` (`None`: no feasible probe).
    pub feasible: Option<f64>,
    /// Smallest probed infeasible `τ̄` above it (`None` when the limit itself is feasible).
    pub infeasible: Option<f64>,
    /// The design at the largest probe whose point the LMI layer verified, re-checked
    /// independently (`None` if no probe was verified).
    pub certified: Option<Design>,
    /// Whether monotonicity of feasibility in `τ̄` is proven (Theorem 3, Corollary 2), so the
    /// bracket is the boundary of a single interval.
    pub monotone_by_proof: bool,
    /// Every probe, in order.
    pub probes: Vec<Probe>,
}

impl MaxTauBar {
    /// Midpoint of the bracket (the estimate of the largest `τ̄`), when both ends exist.
    pub fn estimate(&self) -> Option<f64> {
        Some(0.5 * (self.feasible? + self.infeasible?))
    }
}

fn check_options(o: &BisectionOptions) -> Result<(), Error> {
    let bad = |name, value, reason| Err(InputError::parameter(name, value, reason).into());
    if !(o.threshold >= 0.0 && o.threshold.is_finite()) {
        return bad("threshold", o.threshold, "must be finite and ≥ 0");
    }
    if !(o.tolerance > 0.0 && o.tolerance.is_finite()) {
        return bad("tolerance", o.tolerance, "must be finite and > 0");
    }
    if !(o.limit > 0.0 && o.limit.is_finite()) {
        return bad("limit", o.limit, "must be finite and > 0");
    }
    if let Some(s) = o.start
        && !(s > 0.0 && s.is_finite())
    {
        return bad("start", s, "must be finite and > 0");
    }
    Ok(())
}

struct Search<'a> {
    plant: &'a Plant,
    condition: Condition,
    lmi: Lmi20,
    window_of: Box<dyn Fn(f64) -> Result<Window, Error>>,
    options: &'a BisectionOptions,
    probes: Vec<Probe>,
    best_verified: Option<MarginSolution>,
}

impl Search<'_> {
    fn probe(&mut self, tau_bar: f64) -> Result<bool, Error> {
        let w = (self.window_of)(tau_bar)?;
        self.lmi.set_window(&w)?;
        let sol = MarginSolution::from_parts(self.condition, w, self.lmi.solve()?);
        let feasible = sol.margin > self.options.threshold;
        let verified = sol.verified();
        self.probes.push(Probe {
            tau_bar,
            margin: sol.margin,
            feasible,
            verified,
        });
        if verified
            && self
                .best_verified
                .as_ref()
                .is_none_or(|b| b.window.tau_bar() < tau_bar)
        {
            self.best_verified = Some(sol);
        }
        Ok(feasible)
    }

    /// Bracketing then bisection on `(floor, ∞)`: `floor` is the smallest admissible `τ̄`.
    fn run(mut self, floor: f64, start: f64, tau_low: Option<f64>) -> Result<MaxTauBar, Error> {
        let tol = self.options.tolerance;
        let limit = self.options.limit.max(start);
        let (mut lo, mut hi): (Option<f64>, Option<f64>);
        if self.probe(start)? {
            lo = Some(start);
            hi = None;
            let mut t = start;
            while t < limit {
                t = (2.0 * t).min(limit);
                if self.probe(t)? {
                    lo = Some(t);
                } else {
                    hi = Some(t);
                    break;
                }
            }
        } else {
            lo = None;
            hi = Some(start);
        }
        if let Some(mut h) = hi {
            let mut l = lo.unwrap_or(floor);
            while h - l > tol {
                let mid = 0.5 * (l + h);
                if mid <= floor || mid >= h {
                    break;
                }
                if self.probe(mid)? {
                    l = mid;
                    lo = Some(mid);
                } else {
                    h = mid;
                }
            }
            hi = Some(h);
        }
        let certified = match self.best_verified.take() {
            Some(sol) => Some(finish(self.plant, sol, None, &self.options.design.check)?),
            None => None,
        };
        Ok(MaxTauBar {
            condition: self.condition,
            tau_low,
            feasible: lo,
            infeasible: hi,
            certified,
            monotone_by_proof: self.condition != Condition::Remark6,
            probes: self.probes,
        })
    }
}

/// Largest `τ̄` for which `condition` (Theorem 3 or Corollary 2) is feasible with the given
/// `τ_low ≥ 0` (module docs).
///
/// ```no_run
/// use sporadic_etienne2017::{BisectionOptions, Condition, example, max_tau_bar};
///
/// let plant = example::flexible_joint()?;
/// let r = max_tau_bar(&plant, Condition::Corollary2, 0.01, &BisectionOptions::default())?;
/// assert!((r.estimate().unwrap() - 0.2898).abs() < 2e-4); // spec §4.5
/// # Ok::<(), sporadic_etienne2017::Error>(())
/// ```
pub fn max_tau_bar(
    plant: &Plant,
    condition: Condition,
    tau_low: f64,
    options: &BisectionOptions,
) -> Result<MaxTauBar, Error> {
    check_options(options)?;
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
    let first = Window::new(tau_low, start)?;
    let lmi = Lmi20::new(
        plant,
        condition,
        &first,
        GainTerm::Free,
        &options.design.feasibility,
    )?;
    let search = Search {
        plant,
        condition,
        lmi,
        window_of: Box::new(move |t| Window::new(tau_low, t)),
        options,
        probes: Vec::new(),
        best_verified: None,
    };
    search.run(tau_low, start, Some(tau_low))
}

/// Largest period `h` for which the periodic condition of Remark 6 is feasible, by the same
/// bracketing and bisection from `start` (default `0.01`); feasibility in `h` is not proven
/// monotone (module docs).
pub fn max_period(plant: &Plant, options: &BisectionOptions) -> Result<MaxTauBar, Error> {
    check_options(options)?;
    let start = options.start.unwrap_or(0.01);
    let first = Window::periodic(start)?;
    let lmi = Lmi20::new(
        plant,
        Condition::Remark6,
        &first,
        GainTerm::Free,
        &options.design.feasibility,
    )?;
    let search = Search {
        plant,
        condition: Condition::Remark6,
        lmi,
        window_of: Box::new(Window::periodic),
        options,
        probes: Vec::new(),
        best_verified: None,
    };
    search.run(0.0, start, None)
}

/// One row of the table of largest `τ̄` over `τ_low` (spec §4.5).
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
