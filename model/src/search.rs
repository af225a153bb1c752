//! One window search for every method: the largest certified `T2` for a given `T1`, or the
//! smallest certified `T1` for a given `T2`, by bracketing and bisection over a probe that
//! designs (and re-verifies) at one window.
//!
//! **Monotonicity.** For every method here a design certified on a window is certified on each
//! of its sub-windows in exact arithmetic (the conditions quantify over every interval of the
//! window), so the certified `T2` form an interval `[T1, T2*]`. Numerical verdicts near the
//! boundary, and embeddings that are re-split when the window grows, need not be monotone: the
//! search therefore reports whether the verdicts of *all* its probes are consistent with
//! monotone feasibility ([`WindowSearch::monotone`]). A scan stops at its first failure and
//! bisects the certified → failed transition; its points beyond are probed after the
//! bisection, with what is left of the probe and wall-time budgets ([`sporadic_sdp::budget`]).
//! A certified one among them is the better answer (its design is verified on a window that
//! contains the failed ones, whose verdicts were numerical): the answer moves there, and the
//! transition above it is bisected in turn. The answer is thus always the largest certified
//! value probed (the smallest, for a lower-end search).
//!
//! Every search ends: after at most [`WindowSearchOptions::max_probes`] probes it stops with
//! [`SearchEnd::BudgetExhausted`] and the bracket found so far.

use crate::outcome::Reason;
use crate::report::{Probe, SearchEnd};
use sporadic_linalg::InputError;
use sporadic_sdp::budget;

/// How the first bracket `[certified, failed]` is found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bracketing {
    /// Probe the fixed end (the periodic window) and then `points` geometrically spaced values
    /// from it to the limit (the limit included); bisect inside the first certified → failed
    /// transition.
    Scan {
        /// Number of scan points (at least 1).
        points: usize,
    },
    /// Probe `start` (default: twice the fixed end for an upper-end search, half of it for a
    /// lower-end search), then double (halve) while certified and below (above) the limit. The
    /// fixed end itself is not probed: the bisection's floor is the fixed end.
    Doubling {
        /// First probe, if not the default.
        start: Option<f64>,
    },
}

/// When the bisection stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tolerance {
    /// Bracket `[a, b]` with `max(a/b, b/a) − 1 ≤ tol`, bisected at geometric midpoints.
    Relative(f64),
    /// Bracket with `|b − a| ≤ tol` (same unit as the window), bisected at arithmetic midpoints.
    Absolute(f64),
}

/// Options of [`search_upper`] and [`search_lower`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowSearchOptions {
    /// Bracketing phase. Default: `Scan { points: 6 }`.
    pub bracketing: Bracketing,
    /// Bisection tolerance. Default: `Relative(4e-3)` (the largest certified `T2` within 0.4%
    /// of the numerical boundary).
    pub tolerance: Tolerance,
    /// Largest number of probes (designs) of the whole search. Default 60.
    pub max_probes: usize,
}

impl Default for WindowSearchOptions {
    fn default() -> Self {
        Self {
            bracketing: Bracketing::Scan { points: 6 },
            tolerance: Tolerance::Relative(4e-3),
            max_probes: 60,
        }
    }
}

impl WindowSearchOptions {
    /// Checks every field; the error names the offending one.
    pub fn validate(&self) -> Result<(), InputError> {
        let positive = |name: &str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(InputError::parameter(
                    name,
                    x,
                    "must be a positive finite number",
                ))
            }
        };
        match self.bracketing {
            Bracketing::Scan { points: 0 } => {
                return Err(InputError::parameter(
                    "bracketing.points",
                    0.0,
                    "at least one scan point is needed",
                ));
            }
            Bracketing::Doubling { start: Some(s) } => positive("bracketing.start", s)?,
            _ => {}
        }
        match self.tolerance {
            Tolerance::Relative(t) => positive("tolerance (relative)", t)?,
            Tolerance::Absolute(t) => positive("tolerance (absolute)", t)?,
        }
        if self.max_probes < 2 {
            return Err(InputError::parameter(
                "max_probes",
                self.max_probes as f64,
                "at least two probes are needed",
            ));
        }
        Ok(())
    }
}

/// The verdict of one probe.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    /// Whether the window is certified.
    pub certified: bool,
    /// The method's margin there, if one.
    pub margin: Option<f64>,
    /// Why not certified.
    pub reason: Option<Reason>,
}

impl Verdict {
    /// A certified probe with margin `margin`.
    pub fn certified(margin: Option<f64>) -> Self {
        Self {
            certified: true,
            margin,
            reason: None,
        }
    }

    /// A failed probe.
    pub fn failed(reason: Reason) -> Self {
        Self {
            certified: false,
            margin: None,
            reason: Some(reason),
        }
    }
}

/// The result of a search.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowSearch {
    /// The end kept fixed (`T1` for [`search_upper`], `T2` for [`search_lower`]).
    pub fixed: f64,
    /// The best certified value of the searched end (`None`: none certified).
    pub best: Option<f64>,
    /// The first failing value beyond `best` (`None` when the limit is certified, or when the
    /// budgets ran out above a certified value before a failure beyond it was found).
    pub first_failure: Option<f64>,
    /// How the search ended.
    pub end: SearchEnd,
    /// Whether every probe's verdict is consistent with monotone feasibility.
    pub monotone: bool,
    /// Every probe, in the order made.
    pub probes: Vec<Probe>,
}

/// Errors of a search: invalid options or limits, or the probe's own error.
#[derive(Debug, thiserror::Error)]
pub enum SearchError<E: std::error::Error + 'static> {
    /// Invalid options, fixed end or limit.
    #[error(transparent)]
    Input(#[from] InputError),
    /// The probe failed (not a verdict: an error, e.g. bad input).
    #[error(transparent)]
    Probe(E),
}

/// The largest `T2 ∈ [t1, limit]` whose window `[t1, T2]` `probe` certifies (`probe` receives
/// `T2`).
pub fn search_upper<E: std::error::Error + 'static>(
    t1: f64,
    limit: f64,
    options: &WindowSearchOptions,
    probe: impl FnMut(f64) -> Result<Verdict, E>,
) -> Result<WindowSearch, SearchError<E>> {
    sporadic_linalg::input::check_window(
        "window search [T1, limit]",
        t1,
        limit,
        sporadic_linalg::input::LowerEnd::Positive,
    )?;
    run(t1, limit, true, options, probe)
}

/// The smallest `T1 ∈ [limit, t2]` whose window `[T1, t2]` `probe` certifies (`probe`
/// receives `T1`).
pub fn search_lower<E: std::error::Error + 'static>(
    t2: f64,
    limit: f64,
    options: &WindowSearchOptions,
    probe: impl FnMut(f64) -> Result<Verdict, E>,
) -> Result<WindowSearch, SearchError<E>> {
    sporadic_linalg::input::check_window(
        "window search [limit, T2]",
        limit,
        t2,
        sporadic_linalg::input::LowerEnd::Positive,
    )?;
    run(t2, limit, false, options, probe)
}

/// Probes in the searched direction, keeping the record and the budget.
struct Prober<P> {
    fixed: f64,
    upper: bool,
    probe: P,
    probes: Vec<Probe>,
    budget: usize,
}

impl<P> Prober<P> {
    /// `None` when the budget is spent.
    fn at<E>(&mut self, s: f64) -> Result<Option<bool>, E>
    where
        P: FnMut(f64) -> Result<Verdict, E>,
    {
        if self.probes.len() >= self.budget {
            return Ok(None);
        }
        let v = (self.probe)(s)?;
        let (t1, t2) = if self.upper {
            (self.fixed, s)
        } else {
            (s, self.fixed)
        };
        self.probes.push(Probe {
            t1,
            t2,
            certified: v.certified,
            margin: v.margin,
            reason: v.reason,
        });
        Ok(Some(v.certified))
    }
}

fn run<E: std::error::Error + 'static>(
    fixed: f64,
    limit: f64,
    upper: bool,
    options: &WindowSearchOptions,
    probe: impl FnMut(f64) -> Result<Verdict, E>,
) -> Result<WindowSearch, SearchError<E>> {
    options.validate()?;
    let mut p = Prober {
        fixed,
        upper,
        probe,
        probes: Vec::new(),
        budget: options.max_probes,
    };
    // `beyond(a, b)`: a lies further from the fixed end than b.
    let beyond = |a: f64, b: f64| if upper { a > b } else { a < b };
    let mut out = WindowSearch {
        fixed,
        best: None,
        first_failure: None,
        end: SearchEnd::Converged,
        monotone: true,
        probes: Vec::new(),
    };
    let finish = |mut out: WindowSearch, p: Prober<_>, end| {
        out.end = end;
        out.probes = p.probes;
        out
    };
    macro_rules! probe {
        ($s:expr) => {
            match p.at($s).map_err(SearchError::Probe)? {
                Some(ok) => ok,
                None => return Ok(finish(out, p, SearchEnd::BudgetExhausted)),
            }
        };
    }
    // Bracketing: `good` certified (or the floor), `bad` failed.
    let (good, bad): (f64, f64);
    let mut unchecked = Vec::new();
    match options.bracketing {
        Bracketing::Scan { points } => {
            if !probe!(fixed) {
                out.first_failure = Some(fixed);
                return Ok(finish(out, p, SearchEnd::NothingCertified));
            }
            out.best = Some(fixed);
            if fixed == limit {
                return Ok(finish(out, p, SearchEnd::ReachedLimit));
            }
            let ratio = limit / fixed;
            let scan: Vec<f64> = (1..=points)
                .map(|i| {
                    if i == points {
                        limit
                    } else {
                        fixed * ratio.powf(i as f64 / points as f64)
                    }
                })
                .collect();
            // Up to the first failure; the scan points beyond it are probed after the
            // bisection, with what is left of the budgets, only to check monotonicity.
            let mut first_fail = None;
            for (i, &s) in scan.iter().enumerate() {
                if !probe!(s) {
                    first_fail = Some(i);
                    break;
                }
                out.best = Some(s);
            }
            let Some(i) = first_fail else {
                return Ok(finish(out, p, SearchEnd::ReachedLimit));
            };
            good = if i == 0 { fixed } else { scan[i - 1] };
            bad = scan[i];
            out.first_failure = Some(bad);
            unchecked = scan[i + 1..].to_vec();
        }
        Bracketing::Doubling { start } => {
            let factor = if upper { 2.0 } else { 0.5 };
            let start = start.unwrap_or(fixed * factor);
            let start = if beyond(start, limit) { limit } else { start };
            if !probe!(start) {
                good = fixed; // the floor: not probed, not reported as certified
                bad = start;
            } else {
                out.best = Some(start);
                let mut t = start;
                let mut failed = None;
                while beyond(limit, t) {
                    t = if beyond(t * factor, limit) {
                        limit
                    } else {
                        t * factor
                    };
                    if probe!(t) {
                        out.best = Some(t);
                    } else {
                        failed = Some(t);
                        break;
                    }
                }
                let Some(f) = failed else {
                    return Ok(finish(out, p, SearchEnd::ReachedLimit));
                };
                good = out.best.unwrap_or(fixed);
                bad = f;
            }
            out.first_failure = Some(bad);
        }
    }
    // Bisection inside [good, bad]; then the scan points beyond the first failure, while the
    // probe budget and the wall-time budget last (a probe the time budget cuts short is no
    // verdict, and the search has its answer already). A certified one makes the verdicts
    // non-monotone and moves the answer there: its design is verified on the larger window,
    // which contains the failed ones; the next failing scan point above it is bisected in turn.
    let (mut good, mut bad) = (good, bad);
    let done = |g: f64, b: f64| match options.tolerance {
        Tolerance::Relative(t) => (g / b).max(b / g) - 1.0 <= t,
        Tolerance::Absolute(t) => (b - g).abs() <= t,
    };
    let mut unchecked = unchecked.into_iter();
    loop {
        while !done(good, bad) {
            let mid = match options.tolerance {
                Tolerance::Relative(_) => (good * bad).sqrt(),
                Tolerance::Absolute(_) => 0.5 * (good + bad),
            };
            if !(beyond(mid, good) && beyond(bad, mid)) {
                break; // the bracket cannot be split further in floating point
            }
            out.first_failure = Some(bad);
            if probe!(mid) {
                good = mid;
                out.best = Some(good);
            } else {
                bad = mid;
            }
        }
        out.first_failure = Some(bad);
        let mut certified_beyond = None;
        let mut bracket = None;
        for s in unchecked.by_ref() {
            if p.probes.len() >= p.budget || budget::exhausted() {
                break;
            }
            match p.at(s) {
                Ok(Some(true)) => {
                    out.monotone = false;
                    out.best = Some(s);
                    certified_beyond = Some(s);
                }
                Ok(Some(false)) => {
                    if let Some(c) = certified_beyond {
                        bracket = Some((c, s));
                        break;
                    }
                }
                Ok(None) => break,
                Err(_) if budget::exhausted() => break,
                Err(e) => return Err(SearchError::Probe(e)),
            }
        }
        match (bracket, certified_beyond) {
            (Some((g, b)), _) => (good, bad) = (g, b),
            (None, Some(c)) if c == limit => {
                out.first_failure = None;
                return Ok(finish(out, p, SearchEnd::ReachedLimit));
            }
            (None, Some(_)) => {
                // The budgets ran out above a certified scan point: no failure is known
                // beyond it.
                out.first_failure = None;
                return Ok(finish(out, p, SearchEnd::BudgetExhausted));
            }
            (None, None) => break,
        }
    }
    let end = if out.best.is_none() {
        SearchEnd::NothingCertified
    } else {
        SearchEnd::Converged
    };
    Ok(finish(out, p, end))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, thiserror::Error)]
    #[error("never")]
    struct Never;

    fn threshold(t: f64) -> impl FnMut(f64) -> Result<Verdict, Never> {
        move |s| {
            Ok(if s <= t {
                Verdict::certified(Some(t - s))
            } else {
                Verdict::failed(Reason::InfeasibleLmi {
                    message: "beyond".into(),
                })
            })
        }
    }

    #[test]
    fn scan_then_bisection_brackets_the_threshold() {
        let o = WindowSearchOptions::default();
        let r = search_upper(0.1, 10.0, &o, threshold(1.234)).unwrap();
        let (b, f) = (r.best.unwrap(), r.first_failure.unwrap());
        assert!(b <= 1.234 && 1.234 < f && f / b - 1.0 <= 1e-2, "{b} {f}");
        assert_eq!(r.end, SearchEnd::Converged);
        assert!(r.monotone);
        assert_eq!(r.probes[0].t2, 0.1);
    }

    /// Certified exactly on the closed intervals `on`: not monotone when there are several.
    fn certified_on(on: &[(f64, f64)], s: f64) -> Result<Verdict, Never> {
        Ok(if on.iter().any(|&(lo, hi)| (lo..=hi).contains(&s)) {
            Verdict::certified(None)
        } else {
            Verdict::failed(Reason::InfeasibleLmi {
                message: "gap".into(),
            })
        })
    }

    /// Certified up to 1 and again from 5 on.
    fn two_intervals(s: f64) -> Result<Verdict, Never> {
        certified_on(&[(0.0, 1.0), (5.0, f64::INFINITY)], s)
    }

    #[test]
    fn scan_points_beyond_the_first_failure_are_probed_last() {
        // Scan 0.1·100^(i/6): 0.215, 0.464, 1, 2.15 (fails), then bisection in [1, 2.15],
        // then 4.64 (fails) and 10 (certified: not monotone). The certified limit is the
        // answer.
        let r = search_upper(0.1, 10.0, &WindowSearchOptions::default(), two_intervals).unwrap();
        assert_eq!(
            (r.best, r.first_failure, r.end),
            (Some(10.0), None, SearchEnd::ReachedLimit)
        );
        assert!(!r.monotone);
        let t2: Vec<f64> = r.probes.iter().map(|p| p.t2).collect();
        let n = t2.len();
        assert_eq!(t2[n - 1], 10.0);
        assert!((t2[n - 2] - 0.1 * 100f64.powf(5.0 / 6.0)).abs() < 1e-12);
        assert!(
            t2[5..n - 2].iter().all(|&s| (1.0..2.16).contains(&s)),
            "{t2:?}"
        );
    }

    /// Certified up to 1, failing in (1, 3), certified in [3, 6], failing above.
    fn gap_then_threshold(s: f64) -> Result<Verdict, Never> {
        certified_on(&[(0.0, 1.0), (3.0, 6.0)], s)
    }

    #[test]
    fn a_certified_scan_point_beyond_a_failure_moves_the_answer_and_is_bisected_above() {
        // Scan 0.1·100^(i/6): …, 1, 2.15 (fails), bisection in [1, 2.15]; then 4.64
        // (certified) and 10 (fails): the answer moves to 4.64 and [4.64, 10] is bisected.
        let r = search_upper(
            0.1,
            10.0,
            &WindowSearchOptions::default(),
            gap_then_threshold,
        )
        .unwrap();
        let (b, f) = (r.best.unwrap(), r.first_failure.unwrap());
        assert!(b <= 6.0 && 6.0 < f && f / b - 1.0 <= 1e-2, "{b} {f}");
        assert_eq!(r.end, SearchEnd::Converged);
        assert!(!r.monotone);
        let best_probed = r
            .probes
            .iter()
            .filter(|p| p.certified)
            .map(|p| p.t2)
            .fold(0.0, f64::max);
        assert_eq!(best_probed, b);
    }

    #[test]
    fn the_monotonicity_check_stops_with_the_time_budget() {
        // The wall-time budget runs out during the bisection's last probe: the answer stands,
        // and no scan point beyond the first failure is probed.
        let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let cancel = flag.clone();
        let mut made = 0;
        let r = budget::within(budget::Budget::unlimited().with_cancel(flag), || {
            search_upper(0.1, 10.0, &WindowSearchOptions::default(), |s: f64| {
                made += 1;
                let v = two_intervals(s);
                if made == 13 {
                    cancel.store(true, std::sync::atomic::Ordering::Relaxed);
                }
                v
            })
        })
        .unwrap();
        assert_eq!(r.end, SearchEnd::Converged);
        assert!(r.monotone);
        assert_eq!(r.probes.len(), 13);
        assert!(r.probes.iter().all(|p| p.t2 < 2.2), "{:?}", r.probes);
        let (b, f) = (r.best.unwrap(), r.first_failure.unwrap());
        assert!(b <= 1.0 && 1.0 < f && f / b - 1.0 <= 4e-3, "{b} {f}");
    }

    #[test]
    fn a_certified_limit_is_the_answer_with_no_failure() {
        let r = search_upper(0.5, 20.0, &WindowSearchOptions::default(), threshold(100.0)).unwrap();
        assert_eq!(
            (r.best, r.first_failure, r.end),
            (Some(20.0), None, SearchEnd::ReachedLimit)
        );
    }

    #[test]
    fn doubling_with_an_absolute_tolerance() {
        let o = WindowSearchOptions {
            bracketing: Bracketing::Doubling { start: None },
            tolerance: Tolerance::Absolute(1e-5),
            max_probes: 100,
        };
        let r = search_upper(0.01, 100.0, &o, threshold(0.2898)).unwrap();
        let (b, f) = (r.best.unwrap(), r.first_failure.unwrap());
        assert!(b <= 0.2898 && 0.2898 < f && f - b <= 1e-5, "{b} {f}");
        // Below the first probe: bisection down towards the floor T1.
        let r = search_upper(0.01, 100.0, &o, threshold(0.015)).unwrap();
        assert!(r.best.unwrap() <= 0.015 && r.first_failure.unwrap() - r.best.unwrap() <= 1e-5);
        let r = search_upper(0.01, 100.0, &o, threshold(0.001)).unwrap();
        assert_eq!((r.best, r.end), (None, SearchEnd::NothingCertified));
    }

    #[test]
    fn lower_end_search_and_budget() {
        let r = search_lower(1.0, 0.01, &WindowSearchOptions::default(), |s: f64| {
            Ok::<_, Never>(if s >= 0.3 {
                Verdict::certified(None)
            } else {
                Verdict::failed(Reason::InfeasibleLmi {
                    message: String::new(),
                })
            })
        })
        .unwrap();
        assert!(r.best.unwrap() >= 0.3 && r.first_failure.unwrap() < 0.3);
        let o = WindowSearchOptions {
            max_probes: 3,
            ..WindowSearchOptions::default()
        };
        let r = search_upper(0.1, 10.0, &o, threshold(1.0)).unwrap();
        assert_eq!((r.end, r.probes.len()), (SearchEnd::BudgetExhausted, 3));
    }

    #[test]
    fn options_are_validated() {
        let bad = WindowSearchOptions {
            tolerance: Tolerance::Relative(0.0),
            ..WindowSearchOptions::default()
        };
        assert!(search_upper(0.1, 1.0, &bad, threshold(1.0)).is_err());
        assert!(search_upper(1.0, 0.1, &WindowSearchOptions::default(), threshold(1.0)).is_err());
    }
}
