//! The typed reports every method fills, serialised by the CLI's `--json` and `--toml`.
//!
//! Schemas (the `schema` field; a script can rely on these fields):
//! * `sporadic.design/1` ([`DesignReport`]): `plant`, `method`, `citation`, `status`
//!   (`certified` | `not_certified` | `not_applicable`), `reason` (`null`, or an object with
//!   `kind` and `message`, see [`Reason`]), `window` (`[T1, T2]`) or `windows` (one per
//!   round-robin sensor), `observer` (the observer's equations and sign convention),
//!   `gains` (array of `{name, rows, meaning, schedule?}`), `certificate` (array of
//!   `{name, rows, meaning}`), `margin` (`{value, definition}`), `checks` (what was
//!   re-verified and how), `notes`, `seconds`, `simulation` when one was run, and `proof`
//!   when one was asked for ([`crate::Proof`]: `status` `proved` | `not_proved` |
//!   `inconclusive`, `condition`, `how`, `subintervals`, `margin_lower_bound`,
//!   `margin_definition`, `failed_on`, `enclosure_width`, `message`, `seconds`).
//! * `sporadic.max-interval/1` ([`MaxIntervalReport`]): `plant`, `method`, `status`,
//!   `reason`, `t1`, `limit`, `largest_certified_t2`, `first_failing_t2` (`null` when
//!   certified up to `limit`), `search_end`, `probes`, `design` (the design report at the
//!   largest certified window), `seconds`.
//! * `sporadic.compare/2` ([`CompareReport`]): `plant`, `limit` (the largest `T2` searched),
//!   `results` (one [`CompareEntry`] per method: `method`, `chooses_its_sampling`, `design` —
//!   the design report at the
//!   plant file's own sampling — and `largest_window` — the max-interval report with the
//!   file's `T1`, `null` when no search was run), `seconds`.

use crate::outcome::{Reason, Status};
use crate::window::{Sampling, SamplingWindow};
use faer::{Mat, MatRef};
use serde::{Deserialize, Serialize};

/// `schema` of a [`DesignReport`].
pub const DESIGN_SCHEMA: &str = "sporadic.design/1";
/// `schema` of a [`MaxIntervalReport`].
pub const MAX_INTERVAL_SCHEMA: &str = "sporadic.max-interval/1";
/// `schema` of a [`CompareReport`].
pub const COMPARE_SCHEMA: &str = "sporadic.compare/2";

/// A matrix with its name in the paper and what it is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NamedMatrix {
    /// The paper's name, e.g. `L`, `P`, `K_1`.
    pub name: String,
    /// The entries, row by row.
    pub rows: Vec<Vec<f64>>,
    /// What the matrix is (e.g. "Lyapunov matrix of (12)").
    pub meaning: String,
}

impl NamedMatrix {
    /// A named matrix from a faer matrix.
    pub fn new(
        name: impl Into<String>,
        value: MatRef<'_, f64>,
        meaning: impl Into<String>,
    ) -> Self {
        Self {
            name: name.into(),
            rows: rows_of(value),
            meaning: meaning.into(),
        }
    }

    /// The matrix as a faer matrix (a ragged or empty `rows` gives a `0 × 0` matrix).
    pub fn to_mat(&self) -> Mat<f64> {
        mat_of(&self.rows)
    }
}

/// The rows of a matrix as nested vectors.
pub fn rows_of(m: MatRef<'_, f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

/// A matrix from nested rows (`0 × 0` when empty or ragged).
pub fn mat_of(rows: &[Vec<f64>]) -> Mat<f64> {
    let c = rows.first().map_or(0, |r| r.len());
    if rows.iter().any(|r| r.len() != c) {
        return Mat::zeros(0, 0);
    }
    Mat::from_fn(rows.len(), c, |i, j| rows[i][j])
}

/// `rows` as an `r × c` matrix with finite entries, for gains and certificates a user brings;
/// the error message names the matrix (`what`) and the first offending entry (1-based).
pub fn checked_mat(rows: &[Vec<f64>], r: usize, c: usize, what: &str) -> Result<Mat<f64>, String> {
    let m = mat_of(rows);
    if m.nrows() != r || m.ncols() != c {
        return Err(format!(
            "{what} must be {r}×{c} (a ragged matrix reads as 0×0), found {}×{}",
            m.nrows(),
            m.ncols()
        ));
    }
    for j in 0..c {
        for i in 0..r {
            if !m[(i, j)].is_finite() {
                return Err(format!(
                    "{what}: entry ({}, {}) is not finite",
                    i + 1,
                    j + 1
                ));
            }
        }
    }
    Ok(m)
}

/// A gain that depends on the sampling interval `τ` (the time since the previous sample):
/// its law in words and its values on a grid of `τ`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GainSchedule {
    /// The law, e.g. "K(τ) = K0 + (τ − T1)/(T2 − T1)(K1 − K0)" or "(45) from P_σ".
    pub law: String,
    /// Grid of `τ`.
    pub tau: Vec<f64>,
    /// `K(τ)` at each grid point, row by row.
    pub samples: Vec<Vec<Vec<f64>>>,
}

/// An observer gain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Gain {
    /// The paper's name, e.g. `L` or `K_1`.
    pub name: String,
    /// The value (for a schedule: its value at the window's upper end `T2`).
    pub rows: Vec<Vec<f64>>,
    /// The observer equation this gain belongs to and its sign convention, e.g.
    /// `x̂⁺ = x̂ + L(y − Cx̂) at each sample`.
    pub meaning: String,
    /// Present when the gain depends on the sampling interval.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub schedule: Option<GainSchedule>,
}

impl Gain {
    /// A constant gain.
    pub fn constant(
        name: impl Into<String>,
        value: MatRef<'_, f64>,
        meaning: impl Into<String>,
    ) -> Self {
        Self {
            name: name.into(),
            rows: rows_of(value),
            meaning: meaning.into(),
            schedule: None,
        }
    }

    /// A gain schedule `K(τ)` sampled at `tau` by `at` (the reported `rows` are `K` at the last
    /// grid point).
    pub fn scheduled(
        name: impl Into<String>,
        meaning: impl Into<String>,
        law: impl Into<String>,
        tau: Vec<f64>,
        mut at: impl FnMut(f64) -> Mat<f64>,
    ) -> Self {
        let samples: Vec<Vec<Vec<f64>>> = tau.iter().map(|&t| rows_of(at(t).as_ref())).collect();
        Self {
            name: name.into(),
            rows: samples.last().cloned().unwrap_or_default(),
            meaning: meaning.into(),
            schedule: Some(GainSchedule {
                law: law.into(),
                tau,
                samples,
            }),
        }
    }

    /// The value as a faer matrix.
    pub fn to_mat(&self) -> Mat<f64> {
        mat_of(&self.rows)
    }
}

/// A margin with its definition. Margins of different methods measure different things; the
/// definition says what, and how the LMI variables were normalised.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Margin {
    /// The value (positive: certified with room to spare).
    pub value: f64,
    /// What it is, e.g. "largest t with Φ_i ⪯ −t·I at every vertex, under P ⪯ I".
    pub definition: String,
}

/// One re-verification made before a design is reported as certified.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Check {
    /// What was checked, e.g. "condition (12) on a τ-grid".
    pub what: String,
    /// How: the grid, the tolerance, the arithmetic.
    pub how: String,
    /// The decisive value (e.g. the largest eigenvalue found), if one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
    /// Whether it passed.
    pub passed: bool,
}

/// A simulation of a design.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimulationReport {
    /// The initial condition, sampling scenario and horizon, in words.
    pub setup: String,
    /// Number of samples (jumps).
    pub samples: usize,
    /// `‖x − x̂‖` (or the interval width) at the start.
    pub initial_error: f64,
    /// `‖x − x̂‖` (or the interval width) at the end.
    pub final_error: f64,
    /// The main results in words.
    pub result: String,
    /// The 2% settling time: the first time after which the norm stays below 2% of its
    /// initial value to the end of the run (`None`: it did not settle within the horizon, or
    /// within the part of the run returned when it ends early ([`Self::ends_early_at`]), or was
    /// not computed). See [`crate::Trajectory::settling_time`].
    #[serde(default)]
    pub settling_time: Option<f64>,
    /// The time from which the run is not returned, before its horizon (`None`: it reaches the
    /// horizon; the last sample returned is before this time). [`result`](Self::result) says why, e.g. widths below the resolution of double
    /// precision; a run cut short is not evidence that the error fails to settle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ends_early_at: Option<f64>,
    /// The SVG figure, if one was written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub figure: Option<String>,
}

/// The design of one method for one plant: the `sporadic.design/1` report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignReport {
    /// Always [`DESIGN_SCHEMA`].
    pub schema: String,
    /// The plant's name.
    pub plant: String,
    /// The method id, e.g. `ferrante2016`.
    pub method: String,
    /// The paper the method implements.
    pub citation: String,
    /// The outcome.
    pub status: Status,
    /// Why not certified / not applicable (`None` when certified).
    pub reason: Option<Reason>,
    /// The sampling window of a single-rate design.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window: Option<SamplingWindow>,
    /// The windows of a round-robin design, one per sensor in polling order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub windows: Option<Vec<SamplingWindow>>,
    /// The observer's equations (flow and jump) with the sign convention of its gains.
    pub observer: String,
    /// The observer gains.
    pub gains: Vec<Gain>,
    /// The certificate (Lyapunov matrices, multipliers).
    pub certificate: Vec<NamedMatrix>,
    /// The certified margin and its definition.
    pub margin: Option<Margin>,
    /// What was re-verified, and how.
    pub checks: Vec<Check>,
    /// Anything else a user should know.
    pub notes: Vec<String>,
    /// Wall time of the design, seconds.
    pub seconds: f64,
    /// A simulation of the design, when one was run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simulation: Option<SimulationReport>,
    /// The rigorous proof of the design's condition, when one was asked for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub proof: Option<crate::proof::Proof>,
}

impl DesignReport {
    /// An empty report with the status `status`; the method fills the rest.
    fn base(
        method: &dyn crate::ObserverMethod,
        plant: &str,
        sampling: Option<&Sampling>,
        status: Status,
        reason: Option<Reason>,
    ) -> Self {
        let (window, windows) = match sampling {
            Some(Sampling::Synchronous(w)) => (Some(*w), None),
            Some(Sampling::RoundRobin(ws)) => (None, Some(ws.clone())),
            None => (None, None),
        };
        Self {
            schema: DESIGN_SCHEMA.into(),
            plant: plant.into(),
            method: method.id().into(),
            citation: method.citation().into(),
            status,
            reason,
            window,
            windows,
            observer: method.observer().into(),
            gains: Vec::new(),
            certificate: Vec::new(),
            margin: None,
            checks: Vec::new(),
            notes: Vec::new(),
            seconds: 0.0,
            simulation: None,
            proof: None,
        }
    }

    /// A certified report for `sampling`; the method adds gains, certificate, margin and checks.
    pub fn certified(method: &dyn crate::ObserverMethod, plant: &str, sampling: &Sampling) -> Self {
        Self::base(method, plant, Some(sampling), Status::Certified, None)
    }

    /// A report without a design: the status is the reason's ([`Reason::status`]).
    pub fn without_design(
        method: &dyn crate::ObserverMethod,
        plant: &str,
        sampling: Option<&Sampling>,
        reason: Reason,
    ) -> Self {
        Self::base(method, plant, sampling, reason.status(), Some(reason))
    }

    /// The windows of the report, one or one per sensor (empty when none).
    pub fn sampling_windows(&self) -> Vec<SamplingWindow> {
        match (&self.window, &self.windows) {
            (Some(w), _) => vec![*w],
            (None, Some(ws)) => ws.clone(),
            (None, None) => Vec::new(),
        }
    }

    /// The gain named `name`.
    pub fn gain(&self, name: &str) -> Option<&Gain> {
        self.gains.iter().find(|g| g.name == name)
    }
}

/// How a window search ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SearchEnd {
    /// The bracket `[largest certified, first failing]` is within the requested tolerance.
    Converged,
    /// The search limit itself is certified.
    ReachedLimit,
    /// Not even the shortest window (periodic sampling at the fixed end) is certified.
    NothingCertified,
    /// The probe budget or the wall-time budget ran out before the bracket was resolved (the
    /// reason says which), or the probe at its failing end was cut short by its own budget.
    BudgetExhausted,
    /// The bracket is within the tolerance, but the probe at its failing end did not decide its
    /// window: it ended at the limit of double precision or with an inconclusive solve
    /// (`numerical_failure`, `solver_inconclusive`; the search's reason says which, and can
    /// differ from the probe's own, e.g. a refusal at a rounding level the method shows cannot
    /// resolve the margins near the bracket). The largest
    /// certified `T2` is then a lower bound of what the method certifies, not the method's
    /// boundary.
    Undecided,
}

/// One probed window of a search.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Probe {
    /// The window probed (for round-robin: the upper end applied to every sensor).
    pub t1: f64,
    /// Upper end.
    pub t2: f64,
    /// Whether a certified design was obtained.
    pub certified: bool,
    /// The method's margin at this probe, if one.
    pub margin: Option<f64>,
    /// Why the probe was not certified (`None` when certified).
    pub reason: Option<Reason>,
}

/// The largest certified window of one method for one plant: `sporadic.max-interval/1`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaxIntervalReport {
    /// Always [`MAX_INTERVAL_SCHEMA`].
    pub schema: String,
    /// The plant's name.
    pub plant: String,
    /// The method id.
    pub method: String,
    /// `certified` when some window was certified.
    pub status: Status,
    /// Why nothing was certified, or why the method does not apply.
    pub reason: Option<Reason>,
    /// The lower end kept fixed (`None` when the plant has no sampling window).
    pub t1: Option<f64>,
    /// The largest upper end searched (`None` when there was nothing to search).
    pub limit: Option<f64>,
    /// Largest certified `T2` (`None`: not even `[T1, T1]`).
    pub largest_certified_t2: Option<f64>,
    /// The first failing `T2` above it (`None` when `limit` itself is certified, or when the
    /// budget ran out before a failure above it was found).
    pub first_failing_t2: Option<f64>,
    /// How the search ended (`None` when the method does not apply).
    pub search_end: Option<SearchEnd>,
    /// Whether every probe's verdict is consistent with feasibility decreasing in `T2`.
    pub monotone: bool,
    /// Every probe, in order.
    pub probes: Vec<Probe>,
    /// The design at the largest certified window.
    pub design: Option<DesignReport>,
    /// Wall time of the whole search, seconds.
    pub seconds: f64,
}

impl MaxIntervalReport {
    /// A report without a search (the method does not apply, or the plant cannot be probed):
    /// the status is the reason's ([`Reason::status`]).
    pub fn without_search(
        method: &str,
        plant: &str,
        sampling: Option<&Sampling>,
        limit: Option<f64>,
        reason: Reason,
    ) -> Self {
        Self {
            schema: MAX_INTERVAL_SCHEMA.into(),
            plant: plant.into(),
            method: method.into(),
            status: reason.status(),
            reason: Some(reason),
            t1: sampling.map(|s| s.t1()),
            limit: limit.filter(|l| l.is_finite()),
            largest_certified_t2: None,
            first_failing_t2: None,
            search_end: None,
            monotone: true,
            probes: Vec::new(),
            design: None,
            seconds: 0.0,
        }
    }

    /// Why [`MaxIntervalReport::first_failing_t2`] was refused: the reason of the probe at that
    /// `T2` (`None` without a failing `T2`). The boundary a user reads is either the method's
    /// (an infeasible LMI, a loss of detectability at an aliasing interval) or the
    /// verification's (a margin that double precision cannot verify, a budget), and the two
    /// call for different actions.
    pub fn first_failure_reason(&self) -> Option<&Reason> {
        let f = self.first_failing_t2?;
        self.probes
            .iter()
            .rev()
            .find(|p| !p.certified && p.t2 == f)
            .and_then(|p| p.reason.as_ref())
    }
}

/// One method in a [`CompareReport`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompareEntry {
    /// The method id.
    pub method: String,
    /// Whether the method picks its own sampling instants
    /// ([`crate::ObserverMethod::chooses_its_sampling`]): its design's window is the range of
    /// intervals its rule produces, and no window search is run.
    #[serde(default)]
    pub chooses_its_sampling: bool,
    /// The design at the plant file's own sampling.
    pub design: DesignReport,
    /// The largest certified `T2` with the file's `T1` (`None`: no search was run, because
    /// the method does not apply or the comparison was asked without search).
    pub largest_window: Option<MaxIntervalReport>,
}

impl CompareEntry {
    /// The largest certified `T2` of the search, if one was run and certified anything.
    pub fn largest_certified_t2(&self) -> Option<f64> {
        self.largest_window
            .as_ref()
            .and_then(|r| r.largest_certified_t2)
    }

    /// Whether the file's sampling or some searched window was certified for sampling that the
    /// method does not choose: a method that picks its own sampling instants
    /// ([`CompareEntry::chooses_its_sampling`]) certifies its own rule, not the file's sampling.
    pub fn certifies_the_files_sampling(&self) -> bool {
        !self.chooses_its_sampling
            && (self.design.status.is_certified() || self.largest_certified_t2().is_some())
    }
}

/// Every method on one plant: `sporadic.compare/2`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompareReport {
    /// Always [`COMPARE_SCHEMA`].
    pub schema: String,
    /// The plant's name.
    pub plant: String,
    /// The largest `T2` searched (`None` when no search was run).
    pub limit: Option<f64>,
    /// One entry per method, in registry order.
    pub results: Vec<CompareEntry>,
    /// Wall time of the whole comparison, seconds.
    pub seconds: f64,
}

impl CompareReport {
    /// The report of `results` for `plant`.
    pub fn new(
        plant: impl Into<String>,
        limit: Option<f64>,
        results: Vec<CompareEntry>,
        seconds: f64,
    ) -> Self {
        Self {
            schema: COMPARE_SCHEMA.into(),
            plant: plant.into(),
            limit: limit.filter(|l| l.is_finite()),
            results,
            seconds,
        }
    }

    /// The entry of `method`.
    pub fn entry(&self, method: &str) -> Option<&CompareEntry> {
        self.results.iter().find(|e| e.method == method)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn probe(t2: f64, reason: Option<Reason>) -> Probe {
        Probe {
            t1: 0.1,
            t2,
            certified: reason.is_none(),
            margin: None,
            reason,
        }
    }

    /// The reason reported is the one of the probe at the first failing `T2`, not of a later
    /// probe beyond it (a search probes its scan points above the first failure after the
    /// bisection), and there is none without a failing `T2`.
    #[test]
    fn the_first_failure_reason_is_that_of_the_probe_at_the_first_failing_t2() {
        let lmi = |m: &str| Reason::InfeasibleLmi { message: m.into() };
        let mut r = MaxIntervalReport::without_search("m", "p", None, Some(8.0), lmi("unused"));
        r.probes = vec![
            probe(1.0, None),
            probe(4.0, Some(lmi("at 4"))),
            probe(2.0, None),
            probe(3.0, Some(lmi("at 3"))),
            probe(8.0, Some(lmi("at 8"))),
        ];
        r.largest_certified_t2 = Some(2.0);
        assert!(r.first_failure_reason().is_none());
        r.first_failing_t2 = Some(3.0);
        assert_eq!(r.first_failure_reason().map(Reason::message), Some("at 3"));
        r.first_failing_t2 = Some(4.0);
        assert_eq!(r.first_failure_reason().map(Reason::message), Some("at 4"));
    }
}
