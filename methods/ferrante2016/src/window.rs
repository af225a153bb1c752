//! The largest certifiable sampling window: bisection on `T2` for a given `T1`
//! ([`largest_t2`]), and on `T1` for a given `T2` ([`smallest_t1`]), with a full
//! [`design`](crate::design()) (LMI (41) plus grid verification) at every probe.
//!
//! **Monotonicity caveat.** Condition (12) itself is monotone in the window (a larger window only adds
//! values of `v`), and for the single-piece residue box a larger window gives a larger box whose hull
//! contains the smaller one's vertices, so LMI (41) is monotone too in exact arithmetic. Split or Taylor
//! embeddings, and the solver's verdicts near the feasibility boundary, need not be. The search therefore
//! does not assume monotonicity blindly: it first scans geometrically spaced points between the periodic
//! window and the search limit, reports whether the verdicts on *all* probed points are consistent with
//! monotone feasibility, and bisects (geometric midpoints) only inside the first certified → failed
//! transition. The answer is the bracket `[last certified, first failed]` of that transition; when the
//! probes were not monotone, larger windows beyond the bracket may also be certifiable
//! ([`WindowSearch::monotone`] is then `false`).

use crate::design::{DesignOptions, design_cached};
use crate::error::Error;
use crate::lmi::Lmi41;
use crate::system::{Plant, Window};
use sporadic_linalg::InputError;

/// Options of the window searches.
#[derive(Debug, Clone)]
pub struct WindowSearchOptions {
    /// Design options used at every probe.
    pub design: DesignOptions,
    /// Number of geometrically spaced scan points between the periodic window and the limit
    /// (at least 1; the limit itself is always probed). Default 6.
    pub scan_points: usize,
    /// Bisection stops when the bracket `[certified, failed]` satisfies
    /// `max(a/b, b/a) − 1 ≤ rel_tolerance`. Default `1e-2`.
    pub rel_tolerance: f64,
}

impl Default for WindowSearchOptions {
    fn default() -> Self {
        Self {
            design: DesignOptions::default(),
            scan_points: 6,
            rel_tolerance: 1e-2,
        }
    }
}

/// One probed window.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// The window `[T1, T2]` probed.
    pub t1: f64,
    /// Upper end.
    pub t2: f64,
    /// Whether a verified design was obtained.
    pub certified: bool,
    /// LMI margin (certified probes).
    pub margin: Option<f64>,
    /// Why the probe failed (empty when certified).
    pub reason: String,
}

/// Result of [`largest_t2`] / [`smallest_t1`].
#[derive(Debug, Clone, PartialEq)]
pub struct WindowSearch {
    /// The end that was kept fixed (`T1` for [`largest_t2`], `T2` for [`smallest_t1`]).
    pub fixed: f64,
    /// The best certified value of the searched end (`None`: not even the periodic window
    /// `T1 = T2 = fixed` is certified).
    pub best: Option<f64>,
    /// The first failing value beyond `best` (`None` when the search limit itself is certified).
    pub first_failure: Option<f64>,
    /// Whether the search limit was certified (then no finite bound was found within it).
    pub reached_limit: bool,
    /// Whether the verdicts on all probed points are consistent with monotone feasibility.
    pub monotone: bool,
    /// Every probe, in the order made.
    pub probes: Vec<Probe>,
}

/// Which end of the window is searched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Searched {
    Upper,
    Lower,
}

/// Largest `T2 ∈ [T1, t2_limit]` for which a verified design exists (see the module docs).
pub fn largest_t2(
    plant: &Plant,
    t1: f64,
    t2_limit: f64,
    options: &WindowSearchOptions,
) -> Result<WindowSearch, Error> {
    Window::new(t1, t2_limit)?;
    search(plant, t1, t2_limit, Searched::Upper, options)
}

/// Smallest `T1 ∈ [t1_limit, T2]` for which a verified design exists (see the module docs).
pub fn smallest_t1(
    plant: &Plant,
    t2: f64,
    t1_limit: f64,
    options: &WindowSearchOptions,
) -> Result<WindowSearch, Error> {
    Window::new(t1_limit, t2)?;
    search(plant, t2, t1_limit, Searched::Lower, options)
}

fn search(
    plant: &Plant,
    fixed: f64,
    limit: f64,
    which: Searched,
    options: &WindowSearchOptions,
) -> Result<WindowSearch, Error> {
    if options.scan_points == 0 {
        return Err(
            InputError::parameter("scan_points", 0.0, "at least one scan point is needed").into(),
        );
    }
    if !(options.rel_tolerance.is_finite() && options.rel_tolerance > 0.0) {
        return Err(InputError::parameter(
            "rel_tolerance",
            options.rel_tolerance,
            "must be a positive number",
        )
        .into());
    }
    let mut cache: Option<Lmi41> = None;
    let mut probes: Vec<Probe> = Vec::new();
    let mut probe = |s: f64, probes: &mut Vec<Probe>| -> Result<bool, Error> {
        let (t1, t2) = match which {
            Searched::Upper => (fixed, s),
            Searched::Lower => (s, fixed),
        };
        let window = Window::new(t1, t2)?;
        let (certified, margin, reason) =
            match design_cached(plant, &window, &options.design, &mut cache) {
                Ok(d) => (true, Some(d.certificate.margin), String::new()),
                Err(
                    e @ (Error::Infeasible { .. }
                    | Error::Inconclusive { .. }
                    | Error::VerificationFailed { .. }
                    | Error::NotDetectable { .. }),
                ) => (false, None, e.to_string()),
                Err(e) => return Err(e),
            };
        probes.push(Probe {
            t1,
            t2,
            certified,
            margin,
            reason,
        });
        Ok(certified)
    };

    let mut result = WindowSearch {
        fixed,
        best: None,
        first_failure: None,
        reached_limit: false,
        monotone: true,
        probes: Vec::new(),
    };
    if !probe(fixed, &mut probes)? {
        result.first_failure = Some(fixed);
        result.probes = probes;
        return Ok(result);
    }
    // Geometric scan from the periodic window to the limit.
    let ratio = limit / fixed;
    let k = options.scan_points;
    let scan: Vec<f64> = (1..=k)
        .map(|i| {
            if i == k {
                limit
            } else {
                fixed * ratio.powf(i as f64 / k as f64)
            }
        })
        .collect();
    let mut verdicts = Vec::with_capacity(k);
    for &s in &scan {
        verdicts.push(probe(s, &mut probes)?);
    }
    let first_fail = verdicts.iter().position(|&ok| !ok);
    result.monotone = match first_fail {
        Some(i) => verdicts[i..].iter().all(|&ok| !ok),
        None => true,
    };
    let Some(i) = first_fail else {
        result.best = Some(limit);
        result.reached_limit = true;
        result.probes = probes;
        return Ok(result);
    };
    let (mut good, mut bad) = (if i == 0 { fixed } else { scan[i - 1] }, scan[i]);
    while (good / bad).max(bad / good) - 1.0 > options.rel_tolerance {
        let mid = (good * bad).sqrt();
        if probe(mid, &mut probes)? {
            good = mid;
        } else {
            bad = mid;
        }
    }
    result.best = Some(good);
    result.first_failure = Some(bad);
    result.probes = probes;
    Ok(result)
}
