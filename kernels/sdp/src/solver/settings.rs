//! Solver settings and the per-iteration log record.

use std::fmt;
use std::sync::Arc;

/// Callback receiving one [`IterationLog`] per interior-point iteration.
pub type LogCallback = Arc<dyn Fn(&IterationLog) + Send + Sync>;

/// Parameters of the interior-point method.
///
/// The defaults are the consensus values of SDPT3 (`gaptol = 1e-8`), CSDP
/// (`axtol = atytol = objtol = 1e-8`) and Clarabel: relative gap and relative primal/dual
/// infeasibility `≤ 1e-8`, infeasibility certificates accurate to `1e-8`, at most 100 iterations;
/// a point that only meets `1e-6` in every DIMACS error is reported almost optimal.
#[derive(Clone)]
pub struct Settings {
    /// Relative duality gap: stop when `|⟨C,X⟩ − bᵀy| / (1 + |⟨C,X⟩| + |bᵀy|)` and the
    /// complementarity `⟨X,S⟩ / (1 + |⟨C,X⟩| + |bᵀy|)` are both below it.
    pub tol_gap: f64,
    /// Relative infeasibilities `‖𝒜(X) − b‖₂ / (1 + ‖b‖₂)` and
    /// `‖C − 𝒜ᵀ(y) − S‖_F / (1 + ‖C‖_F)`.
    pub tol_feas: f64,
    /// Infeasibility certificates: with `bᵀy = 1`, `λ_max(Σ y_i A_i) ≤ tol_infeas`; with
    /// `⟨C,X⟩ = −1`, `‖𝒜(X)‖₂ ≤ tol_infeas` (see [`crate::InfeasibilityCertificate`]).
    pub tol_infeas: f64,
    /// Reduced tolerance of [`crate::Status::AlmostOptimal`]: a solve that stops early (stall,
    /// numerical trouble, iteration limit) at a point whose six DIMACS errors are all within it
    /// is reported almost optimal (default `1e-6`; see [`crate::Status`]).
    pub tol_reduced: f64,
    /// Iteration limit.
    pub max_iterations: usize,
    /// Called once per iteration (including iteration 0, the starting point) when set.
    pub log: Option<LogCallback>,
    /// Worker threads: `1` runs the whole solve on the calling thread, `k ≥ 2` on a dedicated
    /// pool of `k` threads; `0` (automatic) runs small problems (per-iteration work estimate
    /// below about `5·10⁵` flops: a few small blocks and `m` below about 100) on the calling
    /// thread and larger ones on rayon's global pool (all cores). Results are bitwise
    /// identical for every value.
    pub threads: usize,
    /// Fixed step fraction `γ ∈ (0, 1)`; `None` uses SDPT3's adaptive `0.9 + 0.09·min(α_p, α_d)`.
    pub step_fraction: Option<f64>,
    /// Facial reduction in [`crate::solve`] (default on): constraints `⟨A_i, X⟩ = 0` with a
    /// semidefinite `A_i`, which leave (P) without a strictly feasible point, are eliminated by
    /// solving on the face they expose and mapping the solution back (Borwein and Wolkowicz
    /// 1981). Problems without such a constraint are solved exactly as with it off. A
    /// [`crate::Solver`] and [`crate::solve_from`] solve the problem as given.
    pub facial_reduction: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            tol_gap: 1e-8,
            tol_feas: 1e-8,
            tol_infeas: 1e-8,
            tol_reduced: 1e-6,
            max_iterations: 100,
            log: None,
            threads: 0,
            step_fraction: None,
            facial_reduction: true,
        }
    }
}

impl fmt::Debug for Settings {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Settings")
            .field("tol_gap", &self.tol_gap)
            .field("tol_feas", &self.tol_feas)
            .field("tol_infeas", &self.tol_infeas)
            .field("tol_reduced", &self.tol_reduced)
            .field("max_iterations", &self.max_iterations)
            .field("log", &self.log.as_ref().map(|_| "callback"))
            .field("threads", &self.threads)
            .field("step_fraction", &self.step_fraction)
            .field("facial_reduction", &self.facial_reduction)
            .finish()
    }
}

/// State of the iterate after one interior-point iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationLog {
    /// Iteration number (`0` = starting point).
    pub iteration: usize,
    /// `⟨C, X⟩`.
    pub primal_objective: f64,
    /// `bᵀy`.
    pub dual_objective: f64,
    /// `|⟨C,X⟩ − bᵀy| / (1 + |⟨C,X⟩| + |bᵀy|)`.
    pub rel_gap: f64,
    /// `‖𝒜(X) − b‖₂ / (1 + ‖b‖₂)`.
    pub primal_infeas: f64,
    /// `‖C − 𝒜ᵀ(y) − S‖_F / (1 + ‖C‖_F)`.
    pub dual_infeas: f64,
    /// Barrier parameter `⟨X, S⟩ / n`.
    pub mu: f64,
    /// Primal step length of the step that produced this iterate (`0` at iteration 0).
    pub primal_step: f64,
    /// Dual step length of that step.
    pub dual_step: f64,
}
