//! Result of a solve: status, point, objective values and quality measures.

use std::time::Duration;

use faer::Mat;

use super::certificate::InfeasibilityCertificate;

/// How a solve ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Status {
    /// Relative gap, complementarity and both relative infeasibilities are within tolerance.
    Optimal,
    /// (P) has no feasible `X`: certificate `y` with `Σ y_i A_i ⪯ 0`, `bᵀy > 0` (a ray of (D)).
    PrimalInfeasible,
    /// (D) has no feasible `(y, S)` (an LMI `C − Σ y_i A_i ⪰ 0` is infeasible): certificate
    /// `X ⪰ 0` with `𝒜(X) = 0`, `⟨C, X⟩ < 0`.
    DualInfeasible,
    /// The iteration limit was reached; the best point found is returned.
    MaxIterations,
    /// Progress stopped (tiny steps, stalled gap or infeasibility, Schur system breakdown)
    /// before the tolerances were met; the best point found is returned and its
    /// [`Measures`] tell how accurate it is.
    NumericalTrouble,
}

/// Quality measures of the returned point, recomputed from the problem data.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Measures {
    /// `|⟨C,X⟩ − bᵀy| / (1 + |⟨C,X⟩| + |bᵀy|)`.
    pub rel_gap: f64,
    /// `‖𝒜(X) − b‖₂ / (1 + ‖b‖₂)`.
    pub primal_infeas: f64,
    /// `‖C − 𝒜ᵀ(y) − S‖_F / (1 + ‖C‖_F)`.
    pub dual_infeas: f64,
    /// The six DIMACS error measures (Mittelmann, "An independent benchmarking of SDP and SOCP
    /// solvers", Math. Prog. 95, 2003): `‖𝒜(X)−b‖₂/(1+‖b‖_∞)`, `max(0,−λ_min(X))/(1+‖b‖_∞)`,
    /// `‖𝒜ᵀ(y)+S−C‖_F/(1+‖C‖_max)`, `max(0,−λ_min(S))/(1+‖C‖_max)`,
    /// `(⟨C,X⟩−bᵀy)/(1+|⟨C,X⟩|+|bᵀy|)`, `⟨X,S⟩/(1+|⟨C,X⟩|+|bᵀy|)`.
    pub dimacs: [f64; 6],
    /// Smallest eigenvalue of `X` over all blocks.
    pub min_eig_x: f64,
    /// Smallest eigenvalue of `S` over all blocks.
    pub min_eig_s: f64,
}

/// Outcome of a solve.
#[derive(Debug, Clone)]
pub struct Solution {
    /// How the solve ended.
    pub status: Status,
    /// Primal matrix per block (PSD: `n×n` symmetric; LP: `n×1` column).
    pub x: Vec<Mat<f64>>,
    /// Dual variables.
    pub y: Vec<f64>,
    /// Dual slack per block, same layout as `x`.
    pub s: Vec<Mat<f64>>,
    /// `⟨C, X⟩`.
    pub primal_objective: f64,
    /// `bᵀy`.
    pub dual_objective: f64,
    /// Interior-point iterations performed.
    pub iterations: usize,
    /// Accuracy of the returned point.
    pub measures: Measures,
    /// Set for [`Status::PrimalInfeasible`] / [`Status::DualInfeasible`]; verified against the
    /// problem data before it is returned.
    pub certificate: Option<InfeasibilityCertificate>,
    /// Wall-clock time of the solve (analysis excluded when re-solving with a [`crate::Solver`]).
    pub solve_time: Duration,
}
