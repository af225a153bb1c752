//! Statistics of one LMI solve, as every method reports them.

use sporadic_sdp::Status;
use sporadic_sdp::lmi::{LmiSolution, Outcome};
use std::time::Duration;

/// Interior-point statistics of one LMI solve and what the LMI layer established from it.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverStats {
    /// What the LMI layer established (its own re-verification of every constraint).
    pub outcome: Outcome,
    /// Its explanation (deciding constraint or certificate).
    pub reason: String,
    /// Interior-point status.
    pub status: Status,
    /// Interior-point iterations.
    pub iterations: usize,
    /// Wall time of the interior-point solve.
    pub solve_time: Duration,
    /// Relative duality gap at the returned point.
    pub rel_gap: f64,
    /// Largest verification tolerance of a strict constraint: a margin at or below it is not a
    /// verified certificate (margin-maximisation solves only).
    pub margin_threshold: Option<f64>,
    /// Number of scalar decision variables of the model (a margin variable not counted).
    pub decision_scalars: usize,
}

impl SolverStats {
    /// The statistics of `solution`, for a model with `decision_scalars` scalar unknowns.
    pub fn of(solution: &LmiSolution, decision_scalars: usize) -> Self {
        Self {
            outcome: solution.outcome,
            reason: solution.reason.clone(),
            status: solution.sdp.status,
            iterations: solution.sdp.iterations,
            solve_time: solution.sdp.solve_time,
            rel_gap: solution.sdp.measures.rel_gap,
            margin_threshold: solution.margin_threshold,
            decision_scalars,
        }
    }
}
