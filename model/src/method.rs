//! The contract every observer method implements.

use crate::outcome::{NotApplicable, Reason, Status};
use crate::plant::Plant;
use crate::proof::{Proof, ProofOptions, ProofStatus};
use crate::report::{DesignReport, Gain, MaxIntervalReport, NamedMatrix, SimulationReport};
use crate::search::{SearchError, Verdict, WindowSearchOptions, search_upper};
use crate::window::Sampling;
use sporadic_sdp::budget::{self, Budget};
use std::time::{Duration, Instant};

/// A boxed error with its chain of causes (a paper crate's typed error).
pub type BoxedError = Box<dyn std::error::Error + Send + Sync + 'static>;

/// Why a method call returned no report: bad input, or a failure that is not a verdict.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MethodError {
    /// The plant, sampling or options are invalid for this method (dimensions, values).
    #[error("{method}: invalid input: {source}")]
    InvalidInput {
        /// The method id.
        method: &'static str,
        /// The paper crate's error.
        #[source]
        source: BoxedError,
    },
    /// A numerical kernel failed in a way that is not a verdict on the plant.
    #[error("{method}: numerical failure: {source}")]
    Numerical {
        /// The method id.
        method: &'static str,
        /// The paper crate's error.
        #[source]
        source: BoxedError,
    },
    /// The method cannot check gains brought by the user ([`ObserverMethod::verify`]).
    #[error("{method}: verification of given gains is not available: {why}")]
    VerificationUnavailable {
        /// The method id.
        method: &'static str,
        /// Why.
        why: String,
    },
    /// The method offers no simulation for this design.
    #[error("{method}: simulation is not available: {why}")]
    SimulationUnavailable {
        /// The method id.
        method: &'static str,
        /// Why.
        why: String,
    },
}

impl MethodError {
    /// [`MethodError::InvalidInput`] of `method` described by `message`.
    pub fn invalid(method: &'static str, message: impl Into<String>) -> Self {
        MethodError::InvalidInput {
            method,
            source: message.into().into(),
        }
    }

    /// [`MethodError::Numerical`] of `method` caused by `source`.
    pub fn numerical(
        method: &'static str,
        source: impl std::error::Error + Send + Sync + 'static,
    ) -> Self {
        MethodError::Numerical {
            method,
            source: Box::new(source),
        }
    }

    /// The message of the error and of each of its causes, joined by `: `.
    pub fn chain(&self) -> String {
        let mut s = self.to_string();
        let mut cur = std::error::Error::source(self);
        while let Some(e) = cur {
            let m = e.to_string();
            if !s.contains(&m) {
                s.push_str(": ");
                s.push_str(&m);
            }
            cur = e.source();
        }
        s
    }
}

/// Options common to every method (the method-specific ones live in the method's own struct).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MethodOptions {
    /// The window search of [`ObserverMethod::largest_window`].
    pub search: WindowSearchOptions,
    /// Wall-time budget of one call (`None`: unlimited). A search that runs out of it stops with
    /// the bracket found so far.
    pub time_limit: Option<Duration>,
}

/// How the sampling intervals of a simulation are chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SamplingScenario {
    /// Uniformly at random in the window (each sensor's, for round-robin), with this seed.
    Uniform {
        /// Seed of the random intervals.
        seed: u64,
    },
    /// Always the shortest interval `T1`.
    PeriodicT1,
    /// Always the longest interval `T2`.
    PeriodicT2,
    /// The worst case the method's certificate can see: each interval chosen in the window,
    /// greedily, to maximise the Lyapunov function of the certificate just after the next
    /// sample (a method without such an adversary reports the simulation unavailable).
    WorstCase,
}

/// A simulation request.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// Simulated time (`None`: the method's default, a few dozen longest intervals).
    pub horizon: Option<f64>,
    /// Initial estimation error `x(0) − x̂(0)` (`None`: all ones; for an interval observer,
    /// the half-width of the initial enclosure).
    pub initial_error: Option<Vec<f64>>,
    /// The sampling intervals.
    pub sampling: SamplingScenario,
}

impl Default for Scenario {
    fn default() -> Self {
        Self {
            horizon: None,
            initial_error: None,
            sampling: SamplingScenario::Uniform { seed: 1 },
        }
    }
}

/// A simulated design: time series on the hybrid time domain and the summary.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// What `signals` are (e.g. "estimation error x − x̂", "interval width x̄ − x̲").
    pub quantity: String,
    /// Times `t`.
    pub t: Vec<f64>,
    /// Jump counters `j` (a sample increments `j` at the same `t`).
    pub j: Vec<usize>,
    /// Named signals, each with one value per `(t, j)`.
    pub signals: Vec<(String, Vec<f64>)>,
    /// The norm of the signals at each `(t, j)`.
    pub norm: Vec<f64>,
    /// The summary.
    pub report: SimulationReport,
}

impl Trajectory {
    /// The first time after which [`norm`](Self::norm) stays at or below `band` × its initial
    /// value to the end of the run, if it does by the last sample point of the run (`None`
    /// for an empty run, a zero or non-finite initial norm, or a run that ends outside the
    /// band). Scale-free: the band is relative to the initial norm.
    pub fn settling_time(&self, band: f64) -> Option<f64> {
        let first = *self.norm.first()?;
        if !(first.is_finite() && first > 0.0) {
            return None;
        }
        let bound = band * first;
        let outside = self.norm.iter().rposition(|&v| !(v <= bound));
        match outside {
            None => self.t.first().copied(),
            Some(k) if k + 1 < self.norm.len() => Some(self.t[k + 1]),
            Some(_) => None,
        }
    }
}

/// An observer design method of one paper.
///
/// Every method answers, for a validated [`Plant`] and its [`Sampling`]: does it apply
/// ([`applies`](Self::applies)), which observer does it certify ([`design`](Self::design)), how
/// long may the sampling intervals be ([`largest_window`](Self::largest_window)), and how does
/// the designed observer behave ([`simulate`](Self::simulate)). A verdict on the plant (not
/// certified, not applicable) is a report; only bad input and non-verdict failures are `Err`.
pub trait ObserverMethod: Send + Sync {
    /// The id used on the command line, e.g. `ferrante2016`.
    fn id(&self) -> &'static str;
    /// The paper: authors, year, title, venue.
    fn citation(&self) -> &'static str;
    /// One line: what the method designs.
    fn summary(&self) -> &'static str;
    /// The observer's equations (flow and jump) and the sign convention of its gains.
    fn observer(&self) -> &'static str;
    /// Whether the observer picks its own sampling instants: its design certifies the
    /// intervals its rule produces (reported as the design's window), not a window of
    /// arbitrary sampling sequences, so a window search does not apply
    /// ([`largest_window_with`] answers `not_applicable`).
    fn chooses_its_sampling(&self) -> bool {
        false
    }
    /// Whether the method covers this plant and sampling.
    fn applies(&self, plant: &Plant, sampling: &Sampling) -> Result<(), NotApplicable>;
    /// Designs and re-verifies an observer for every sampling sequence of `sampling`.
    fn design(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        options: &MethodOptions,
    ) -> Result<DesignReport, MethodError>;

    /// The largest certified upper end `T2 ≤ limit` with `T1` of `sampling` fixed (for
    /// round-robin, every sensor's upper end is moved together, see [`Sampling::with_t2`]).
    ///
    /// The default runs the shared [`search_upper`] with [`design`](Self::design) as the probe;
    /// `progress` sees every probe as it is made.
    fn largest_window(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        limit: f64,
        options: &MethodOptions,
        progress: &mut dyn FnMut(&crate::report::Probe),
    ) -> Result<MaxIntervalReport, MethodError> {
        default_largest_window(self, plant, sampling, limit, options, progress)
    }

    /// Proves rigorously, in interval arithmetic, that a certified design of this method
    /// satisfies the method's central condition for **every** sampling interval of its
    /// window(s) (see [`crate::proof`]). Called through [`prove_within`], which handles
    /// designs that are not certified and the time budget. The default: no prover
    /// (`inconclusive`).
    fn prove(
        &self,
        plant: &Plant,
        design: &DesignReport,
        options: &ProofOptions,
    ) -> Result<Proof, MethodError> {
        let _ = (plant, design, options);
        Ok(Proof::not_attempted(
            ProofStatus::Inconclusive,
            format!("{} has no prover", self.id()),
        ))
    }

    /// Checks gains the user brings (the `gains` of a design report, edited or designed
    /// elsewhere) on `sampling`: the method's condition for those gains, with the
    /// `certificate` given when it has one that fits, else with one the method finds for the
    /// fixed gains. The report is `certified` when the condition re-verifies in floating point
    /// as a design's would, `not_certified` (with the reason) otherwise.
    ///
    /// # Errors
    /// [`MethodError::InvalidInput`] for gains of the wrong names or shapes;
    /// [`MethodError::VerificationUnavailable`] (the default) for a method that cannot check
    /// given gains.
    fn verify(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        gains: &[Gain],
        certificate: &[NamedMatrix],
        options: &MethodOptions,
    ) -> Result<DesignReport, MethodError> {
        let _ = (plant, sampling, gains, certificate, options);
        Err(MethodError::VerificationUnavailable {
            method: self.id(),
            why: "this method has no check of given gains".into(),
        })
    }

    /// Simulates a certified design of this method (from [`design`](Self::design)).
    fn simulate(
        &self,
        plant: &Plant,
        design: &DesignReport,
        scenario: &Scenario,
    ) -> Result<Trajectory, MethodError> {
        let _ = (plant, design, scenario);
        Err(MethodError::SimulationUnavailable {
            method: self.id(),
            why: "this method has no simulation".into(),
        })
    }
}

/// [`ObserverMethod::design`] within [`MethodOptions::time_limit`]: every solve the design
/// starts on this thread stops once the limit (or any enclosing [`sporadic_sdp::budget`]
/// scope) runs out, and a design that ends uncertified after that reports
/// [`Reason::BudgetExhausted`] instead of whatever the interrupted solve led it to say. A
/// verdict decided before the budget ran out (not detectable, LMI infeasible, missing data,
/// unsupported structure) is kept, and so is a design certified in time (its certificate was
/// re-verified as usual).
pub fn design_within(
    method: &dyn ObserverMethod,
    plant: &Plant,
    sampling: &Sampling,
    options: &MethodOptions,
) -> Result<DesignReport, MethodError> {
    let start = Instant::now();
    let budget = Budget::for_duration(options.time_limit);
    budget::within(budget, || {
        let r = method.design(plant, sampling, options);
        if !budget::exhausted() {
            return r;
        }
        let decided = |d: &DesignReport| {
            d.status.is_certified()
                || matches!(
                    d.reason,
                    Some(
                        Reason::Undetectable { .. }
                            | Reason::InfeasibleLmi { .. }
                            | Reason::MissingData { .. }
                            | Reason::UnsupportedStructure { .. }
                    )
                )
        };
        match r {
            Ok(d) if decided(&d) => Ok(d),
            Ok(_) | Err(MethodError::Numerical { .. }) => {
                let mut d = DesignReport::without_design(
                    method,
                    plant.name(),
                    Some(sampling),
                    Reason::BudgetExhausted {
                        message: budget_words(&budget::current(), options.time_limit),
                    },
                );
                d.seconds = start.elapsed().as_secs_f64();
                Ok(d)
            }
            Err(e) => Err(e),
        }
    })
}

/// [`ObserverMethod::prove`] within [`ProofOptions::time_limit`], timed: a design that is
/// not certified is `not_proved` without a proof attempt (its condition already failed, or it
/// has no gains to prove), one the method does not apply to is `inconclusive`, and a proof
/// that is stopped by the budget is `inconclusive`.
pub fn prove_within(
    method: &dyn ObserverMethod,
    plant: &Plant,
    design: &DesignReport,
    options: &ProofOptions,
) -> Result<Proof, MethodError> {
    let start = Instant::now();
    if !design.status.is_certified() {
        // A method that does not apply has shown nothing failing: nothing is decided.
        let status = if design.status.is_not_applicable() {
            ProofStatus::Inconclusive
        } else {
            ProofStatus::NotProved
        };
        return Ok(Proof::not_attempted(
            status,
            format!(
                "the design is {} ({}): there is no certified design to prove",
                design.status,
                design
                    .reason
                    .as_ref()
                    .map_or_else(|| "no reason given".into(), |r| r.to_string())
            ),
        ));
    }
    let budget = Budget::for_duration(options.time_limit);
    let mut proof = budget::within(budget, || method.prove(plant, design, options))?;
    proof.seconds = start.elapsed().as_secs_f64();
    Ok(proof)
}

/// Which budget stopped a design or search.
fn budget_words(budget: &Budget, limit: Option<Duration>) -> String {
    if budget.is_cancelled() {
        "cancelled before the design was decided".into()
    } else {
        match limit {
            Some(l) => format!(
                "the time limit of {:.2} s ran out before the design was decided",
                l.as_secs_f64()
            ),
            None => "the enclosing time limit ran out before the design was decided".into(),
        }
    }
}

/// The check every [`ObserverMethod::simulate`] starts with: `design` is a certified design
/// of the method `id` (else [`MethodError::SimulationUnavailable`] says why not).
pub fn check_simulatable(id: &'static str, design: &DesignReport) -> Result<(), MethodError> {
    let why = if design.method != id {
        format!("the report is a design of {}, not of {id}", design.method)
    } else if !design.status.is_certified() {
        format!(
            "the design is {} ({}): there is no certified observer to simulate",
            design.status,
            design
                .reason
                .as_ref()
                .map_or_else(|| "no reason given".into(), |r| r.to_string())
        )
    } else {
        return Ok(());
    };
    Err(MethodError::SimulationUnavailable { method: id, why })
}

/// The search behind [`ObserverMethod::largest_window`]'s default: [`largest_window_with`] with
/// [`MethodOptions::search`] and [`ObserverMethod::design`] as the probe.
pub fn default_largest_window<M: ObserverMethod + ?Sized>(
    method: &M,
    plant: &Plant,
    sampling: &Sampling,
    limit: f64,
    options: &MethodOptions,
    progress: &mut dyn FnMut(&crate::report::Probe),
) -> Result<MaxIntervalReport, MethodError> {
    largest_window_with(
        method,
        plant,
        sampling,
        limit,
        &options.search,
        options,
        progress,
        &mut |s| method.design(plant, s, options),
    )
}

/// The body of every [`ObserverMethod::largest_window`]: [`search_upper`] on `T2` with
/// `probe` designing at each window ([`Sampling::with_t2`] of `sampling`), stopped early by
/// [`MethodOptions::time_limit`] (the report then holds the best window found so far, reason
/// [`Reason::BudgetExhausted`]). A method that can reuse work across probes (e.g. a compiled LMI
/// model whose window enters through parameters) passes its own `probe` and `search`.
///
/// `progress` sees every probe as it is made; the report keeps the design at the largest
/// certified `T2`.
#[allow(clippy::too_many_arguments)]
pub fn largest_window_with<M: ObserverMethod + ?Sized>(
    method: &M,
    plant: &Plant,
    sampling: &Sampling,
    limit: f64,
    search: &WindowSearchOptions,
    options: &MethodOptions,
    progress: &mut dyn FnMut(&crate::report::Probe),
    probe: &mut dyn FnMut(&Sampling) -> Result<DesignReport, MethodError>,
) -> Result<MaxIntervalReport, MethodError> {
    let start = Instant::now();
    let t1 = sampling.t1();
    if let Err(na) = method.applies(plant, sampling) {
        return Ok(MaxIntervalReport::without_search(
            method.id(),
            plant.name(),
            Some(sampling),
            Some(limit),
            na.reason,
        ));
    }
    if method.chooses_its_sampling() {
        return Ok(MaxIntervalReport::without_search(
            method.id(),
            plant.name(),
            Some(sampling),
            Some(limit),
            Reason::UnsupportedStructure {
                message: "this observer picks its own sampling instants, so it certifies no \
                          window of arbitrary sampling sequences; `design` reports the range of \
                          intervals its rule produces"
                    .into(),
            },
        ));
    }
    let mut report = MaxIntervalReport::without_search(
        method.id(),
        plant.name(),
        Some(sampling),
        Some(limit),
        Reason::BudgetExhausted {
            message: String::new(),
        },
    );
    // Filled below; the search decides status and reason.
    (report.status, report.reason) = (Status::NotCertified, None);
    let invalid = |e: BoxedError| MethodError::InvalidInput {
        method: method.id(),
        source: e,
    };
    // The designs of the certified probes (the report keeps the one at the answer; a
    // non-monotone search can certify beyond it).
    let mut certified: Vec<(f64, DesignReport)> = Vec::new();
    // Every probe made, for a search the budget cuts short (the search's own list is lost).
    let mut made = Vec::new();
    let out_of_time = || MethodError::Numerical {
        method: method.id(),
        source: Box::new(TimeLimit(options.time_limit)),
    };
    let mut run = |t2: f64| -> Result<Verdict, MethodError> {
        if budget::exhausted() {
            return Err(out_of_time());
        }
        let s = sampling.with_t2(t2).map_err(|e| invalid(Box::new(e)))?;
        let d = probe(&s);
        // A probe cut short by the budget is no verdict on its window.
        if budget::exhausted() && !d.as_ref().is_ok_and(|d| d.status.is_certified()) {
            return Err(out_of_time());
        }
        let d = d?;
        let v = Verdict {
            certified: d.status.is_certified(),
            margin: d.margin.as_ref().map(|m| m.value),
            reason: d.reason.clone(),
        };
        let probe = crate::report::Probe {
            t1,
            t2,
            certified: v.certified,
            margin: v.margin,
            reason: v.reason.clone(),
        };
        progress(&probe);
        made.push(probe);
        if v.certified {
            certified.push((t2, d));
        }
        Ok(v)
    };
    // Whether the wall-time budget was spent when the search ended (the other budget is its
    // number of probes), for the reason a search cut short gives.
    let (searched, timed_out) = budget::within(Budget::for_duration(options.time_limit), || {
        let s = search_upper(t1, limit, search, &mut run);
        (s, budget::exhausted())
    });
    let search = match searched {
        Ok(s) => s,
        Err(SearchError::Input(e)) => return Err(invalid(Box::new(e))),
        Err(SearchError::Probe(MethodError::Numerical { source, .. }))
            if source.downcast_ref::<TimeLimit>().is_some() =>
        {
            report.reason = Some(Reason::BudgetExhausted {
                message: source.to_string(),
            });
            report.search_end = Some(crate::report::SearchEnd::BudgetExhausted);
            let best = certified.into_iter().max_by(|a, b| a.0.total_cmp(&b.0));
            report.largest_certified_t2 = best.as_ref().map(|(t2, _)| *t2);
            // The smallest failing T2 above the largest certified one, as a finished search
            // reports it (a failure below it makes the verdicts non-monotone).
            let certified_max = report.largest_certified_t2.unwrap_or(f64::NEG_INFINITY);
            report.first_failing_t2 = made
                .iter()
                .filter(|p| !p.certified && p.t2 > certified_max)
                .map(|p| p.t2)
                .reduce(f64::min);
            report.monotone = made.iter().all(|p| p.certified || p.t2 > certified_max);
            report.status = if best.is_some() {
                Status::Certified
            } else {
                Status::NotCertified
            };
            report.design = best.map(|(_, d)| d);
            report.probes = made;
            report.seconds = start.elapsed().as_secs_f64();
            return Ok(report);
        }
        Err(SearchError::Probe(e)) => return Err(e),
    };
    report.largest_certified_t2 = search.best;
    report.first_failing_t2 = search.first_failure;
    report.search_end = Some(search.end);
    report.monotone = search.monotone;
    report.status = if search.best.is_some() {
        Status::Certified
    } else {
        Status::NotCertified
    };
    if search.best.is_none() {
        report.reason = search.probes.iter().rev().find_map(|p| p.reason.clone());
    } else if search.end == crate::report::SearchEnd::BudgetExhausted {
        let probes = search.probes.len();
        report.reason = Some(Reason::BudgetExhausted {
            message: if timed_out {
                format!(
                    "window search stopped after {probes} probes: {}",
                    TimeLimit(options.time_limit)
                )
            } else {
                format!("window search stopped after {probes} probes, its probe budget")
            },
        });
    }
    report.probes = search.probes;
    // A bracket whose failing end is a probe cut short by its own budget (a proof's pieces, a
    // refinement's cap) is not resolved by a verdict: the largest certified T2 is a lower bound
    // only, and the search says so instead of having converged.
    // So does one whose failing end ended at the limit of double precision or with an
    // inconclusive solve (`SearchEnd::Undecided`).
    if report.search_end == Some(crate::report::SearchEnd::Converged)
        && let (Some(_), Some(f)) = (report.largest_certified_t2, report.first_failing_t2)
        && let Some(why) = report.first_failure_reason().cloned()
    {
        let lower = |what: &str, message: &str| {
            format!(
                "the probe at T2 = {f:.6} was not decided ({what}: {message}); the largest \
                 certified T2 is a lower bound"
            )
        };
        match why {
            Reason::BudgetExhausted { message } => {
                report.search_end = Some(crate::report::SearchEnd::BudgetExhausted);
                report.reason = Some(Reason::BudgetExhausted {
                    message: lower("its own budget ran out", &message),
                });
            }
            Reason::NumericalFailure { message } => {
                report.search_end = Some(crate::report::SearchEnd::Undecided);
                report.reason = Some(Reason::NumericalFailure {
                    message: lower("numerical failure", &message),
                });
            }
            Reason::SolverInconclusive { message } => {
                report.search_end = Some(crate::report::SearchEnd::Undecided);
                report.reason = Some(Reason::SolverInconclusive {
                    message: lower("the solve was inconclusive", &message),
                });
            }
            _ => {}
        }
    }
    report.design = certified
        .into_iter()
        .find(|(t2, _)| Some(*t2) == search.best)
        .map(|(_, d)| d);
    report.seconds = start.elapsed().as_secs_f64();
    Ok(report)
}

/// The wall-time budget ran out (`None`: an enclosing budget, or a cancellation).
#[derive(Debug, thiserror::Error)]
pub struct TimeLimit(pub Option<Duration>);

impl std::fmt::Display for TimeLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0 {
            Some(l) => write!(f, "time limit of {:.2} s reached", l.as_secs_f64()),
            None => f.write_str("the enclosing time budget ran out or the run was cancelled"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(t: &[f64], norm: &[f64]) -> Trajectory {
        Trajectory {
            quantity: "error".into(),
            t: t.to_vec(),
            j: vec![0; t.len()],
            signals: Vec::new(),
            norm: norm.to_vec(),
            report: SimulationReport {
                setup: String::new(),
                samples: 0,
                initial_error: norm[0],
                final_error: *norm.last().unwrap(),
                result: String::new(),
                settling_time: None,
                ends_early_at: None,
                figure: None,
            },
        }
    }

    #[test]
    fn settling_time_is_the_last_entry_into_the_band_and_scale_free() {
        let t = [0.0, 1.0, 2.0, 3.0, 4.0];
        // Enters the 2% band at t = 2, leaves it at t = 3, re-enters at t = 4.
        let norm = [1.0, 0.5, 0.01, 0.03, 0.015];
        assert_eq!(run(&t, &norm).settling_time(0.02), Some(4.0));
        let scaled: Vec<f64> = norm.iter().map(|v| 1e-7 * v).collect();
        assert_eq!(run(&t, &scaled).settling_time(0.02), Some(4.0));
        // Ends outside the band: not settled.
        assert_eq!(
            run(&t, &[1.0, 0.5, 0.01, 0.01, 0.3]).settling_time(0.02),
            None
        );
        // A zero or non-finite start has no relative band.
        assert_eq!(run(&t, &[0.0; 5]).settling_time(0.02), None);
        assert_eq!(
            run(&t, &[f64::NAN, 0.0, 0.0, 0.0, 0.0]).settling_time(0.02),
            None
        );
        // A NaN later is outside every band.
        assert_eq!(
            run(&t, &[1.0, 0.0, f64::NAN, 0.0, 0.0]).settling_time(0.02),
            Some(3.0)
        );
    }

    /// Certifies every `T2 ≤ 2`; above, its probe is cut short by its own budget (no verdict),
    /// or with `precision`, ends at the limit of double precision.
    struct Undecided {
        precision: bool,
    }

    impl ObserverMethod for Undecided {
        fn id(&self) -> &'static str {
            "undecided"
        }
        fn citation(&self) -> &'static str {
            "a test method"
        }
        fn summary(&self) -> &'static str {
            "certifies up to T2 = 2, undecided above"
        }
        fn observer(&self) -> &'static str {
            "none"
        }
        fn applies(&self, _: &Plant, _: &Sampling) -> Result<(), NotApplicable> {
            Ok(())
        }
        fn design(
            &self,
            plant: &Plant,
            sampling: &Sampling,
            _: &MethodOptions,
        ) -> Result<DesignReport, MethodError> {
            Ok(if sampling.t2() <= 2.0 {
                DesignReport::certified(self, plant.name(), sampling)
            } else {
                let reason = if self.precision {
                    Reason::NumericalFailure {
                        message: "double-precision limit".into(),
                    }
                } else {
                    Reason::BudgetExhausted {
                        message: "the proof's piece budget ran out".into(),
                    }
                };
                DesignReport::without_design(self, plant.name(), Some(sampling), reason)
            })
        }
    }

    /// A bracket whose failing end is a probe that its own budget cut short ends the search as
    /// `budget_exhausted` with the largest certified `T2` as a lower bound, not `converged`
    /// (a sferlazza2021 search on an unstable round-robin plant, whose proof of (48) ran out of
    /// pieces above T2 ≈ 32.5, reported `converged` with that probe as the first failure); one
    /// that ended at the limit of double precision ends `undecided`.
    #[test]
    fn an_undecided_probe_does_not_end_a_search_as_converged() {
        let plant = Plant::linear(
            faer::mat![[-1.0]].as_ref(),
            None,
            faer::mat![[1.0]].as_ref(),
        )
        .unwrap();
        let sampling = Sampling::Synchronous(crate::SamplingWindow::new(0.5, 1.0).unwrap());
        for precision in [false, true] {
            let r = Undecided { precision }
                .largest_window(
                    &plant,
                    &sampling,
                    8.0,
                    &MethodOptions::default(),
                    &mut |_| {},
                )
                .unwrap();
            let best = r.largest_certified_t2.unwrap();
            let failing = r.first_failing_t2.unwrap();
            assert!(
                best <= 2.0 && failing > 2.0 && failing < 2.1,
                "{best} {failing}"
            );
            assert_eq!(r.status, Status::Certified);
            match (&r.reason, r.search_end) {
                (
                    Some(Reason::BudgetExhausted { message }),
                    Some(crate::report::SearchEnd::BudgetExhausted),
                ) if !precision => {
                    assert!(message.contains("lower bound") && message.contains("piece budget"));
                }
                (
                    Some(Reason::NumericalFailure { message }),
                    Some(crate::report::SearchEnd::Undecided),
                ) if precision => {
                    assert!(
                        message.contains("lower bound") && message.contains("double-precision")
                    );
                }
                other => panic!("{other:?}"),
            }
        }
    }
}
