//! Primal–dual interior-point solver for block-diagonal SDPs with LP blocks.
//!
//! # Problem
//!
//! ```text
//! (P)  min ⟨C, X⟩   s.t. ⟨A_i, X⟩ = b_i (i = 1..m),  X ⪰ 0
//! (D)  max bᵀy      s.t. Σ_i y_i A_i + S = C,          S ⪰ 0
//! ```
//!
//! over a product of PSD blocks and nonnegative orthants (see [`crate::problem`]).
//!
//! # Algorithm
//!
//! An **infeasible-start primal–dual path-following method with Mehrotra's
//! predictor–corrector** (Mehrotra, SIAM J. Optim. 2(4), 1992) in the **HKM direction**
//! (Helmberg, Rendl, Vanderbei, Wolkowicz, SIAM J. Optim. 6(2), 1996; Kojima, Shindoh, Hara,
//! SIAM J. Optim. 7(1), 1997; Monteiro, SIAM J. Optim. 7(3), 1997) — the algorithm of SDPT3
//! (Toh, Todd, Tütüncü, Optim. Methods Softw. 11, 1999; Math. Prog. 95, 2003) and CSDP
//! (Borchers, Optim. Methods Softw. 11, 1999). Per iteration:
//!
//! 1. residuals `r_p = b − 𝒜(X)`, `R_d = C − 𝒜ᵀ(y) − S`, `μ = ⟨X,S⟩/n` (module `residuals`);
//! 2. the Schur matrix `M_ij = Σ_k tr(A_i X A_j S⁻¹)` assembled block by block with SDPA's
//!    sparsity-dependent formulas or a dense `KᵀK` form (`structure`, `schur`) and
//!    factorised by dense Cholesky with regularised / LBLᵀ fallbacks and iterative refinement
//!    (module `linsys`) — or, once these normal equations are too ill-conditioned to deliver
//!    `𝒜(ΔX) = r_p` to the tolerance, the same Newton system as a least-squares problem in the
//!    HKM-scaled space solved by Householder QR (module `lsq`);
//! 3. a predictor (`σ = 0`), step lengths to the cone boundary (module `step`: exact, or bounded
//!    by Lanczos steps for blocks of order 200 or more, module `lanczos`), the centring
//!    parameter `σ = (μ_aff/μ)^e` with SDPT3's adaptive exponent `e = max(1, 3 min(α_p,α_d)²)`,
//!    and a corrector with the second-order term `ΔX_a ΔS_a` (module `direction`);
//! 4. steps `α = min(1, γ α_max)` with `γ = 0.9 + 0.09 min(α_p, α_d)` (SDPT3), backtracked if a
//!    Cholesky factorisation of the new `X` or `S` fails.
//!
//! The starting point is SDPT3's `infeaspt` (module `start`), or a given point
//! ([`Solver::solve_from`]). The solve stops as **optimal** when the relative gap
//! `|⟨C,X⟩ − bᵀy|/(1+|⟨C,X⟩|+|bᵀy|)`, the relative complementarity `⟨X,S⟩/(1+|⟨C,X⟩|+|bᵀy|)`
//! and the relative infeasibilities are all within tolerance; a solve that stops early (stall,
//! breakdown, iteration limit) is **almost optimal** when the six DIMACS errors of the best point
//! are all within the reduced tolerance (the rule is documented at [`Status`]).
//!
//! ## Why HKM with an infeasible start rather than NT or a self-dual embedding
//!
//! HKM needs only `X` and `S⁻¹` per block — no Nesterov–Todd scaling point (a Cholesky and an
//! SVD/eigendecomposition per block per iteration) — and its Schur matrix can exploit the
//! sparsity of each `A_i` through SDPA's F1/F2/F3 formulas, since `X` and `S⁻¹` enter separately.
//! A homogeneous self-dual embedding (SeDuMi, MOSEK, Clarabel) yields infeasibility
//! certificates by construction but adds a dense rank-one column to every Schur solve and
//! changes the scaling of every iterate. SDPT3 and CSDP show that on the target problems
//! (control LMIs, SDPLIB) divergence along a ray is detected reliably from the iterates, so we
//! do that (the documentation of [`InfeasibilityCertificate`] explains the tests) and **verify** every
//! certificate on the problem data before reporting infeasibility.
//!
//! ## Robustness
//!
//! Near the optimum `cond(M)` grows like `1/μ²`; on control and truss problems (and on LMIs whose
//! optimal face is unbounded, where `y` drifts along a ray and `‖S‖` grows like `1/μ`) it passes
//! `1/ε` before the tolerances are met. A Cholesky solve of such an `M` leaves a residual of order
//! `ε ‖M‖ ‖Δy‖`, and recovering `ΔX = −X − (XΔS + …)S⁻¹` from explicit products amplifies the
//! rounding of a large `ΔS` by `‖X‖ ‖S⁻¹‖`: the computed `ΔX` misses `𝒜(ΔX) = r_p` and the primal
//! infeasibility grows while `μ` falls (where CSDP reports "partial success" and SDPA `pFEAS`).
//! Every direction is therefore refined against `r_p − 𝒜(ΔX)` recomputed from the actual `ΔX`;
//! if the error stays above ten times the refinement threshold, preconditioned conjugate
//! gradients on `KᵀK` (applied as two scaled block products, never through `M`, with the Cholesky
//! factor of `M` as preconditioner) try to bring it down to the threshold, and if they do not, the
//! rest of the solve uses the least-squares form (module `lsq`), whose primal error is
//! `ε ‖K‖ ‖Z‖` independently of `cond(M)`. Dependent, duplicate or empty constraints make `M` singular; the regularised
//! Cholesky / LBLᵀ fallback with iterative refinement handles them, and the best iterate
//! (smallest largest stopping measure) is returned when progress stalls. Non-finite data and
//! inconsistent structure are rejected with an [`SdpError`] before any work is done.
//!
//! ## Determinism
//!
//! Parallel work (rayon, over blocks and Schur rows) writes disjoint outputs that are combined
//! in a fixed order, so a given input and [`Settings`] always produce bitwise the same
//! [`Solution`].

mod blockops;
mod certificate;
mod cost;
mod direction;
mod facial;
mod ipm;
mod lanczos;
mod linsys;
mod lsq;
mod par;
mod point;
mod residuals;
mod schur;
mod settings;
mod small;
mod solution;
mod start;
mod step;
mod structure;

use std::fmt;
use std::sync::Arc;
use std::time::Instant;

pub use certificate::InfeasibilityCertificate;
pub use point::{Point, dimacs_errors, point_measures};
pub use settings::{IterationLog, LogCallback, Settings};
pub use solution::{FacialPath, Measures, Solution, Status};

use crate::error::SdpError;
use crate::problem::Problem;
use ipm::{Start, Workspace};
use linsys::SchurSolver;
use par::Exec;
use structure::Analysis;

/// Solves `problem` (analysis and interior-point iterations in one call).
///
/// With [`Settings::facial_reduction`] (the default), constraints `⟨A_i, X⟩ = 0` with a
/// semidefinite `A_i` are first eliminated by facial reduction (module `facial`): the problem
/// is solved on the face of the cone they expose and the solution mapped back, its measures
/// taken against `problem`. If the lifted point is not [`Status::Optimal`], or the reduced
/// problem ends infeasible, `problem` itself is solved as well (its infeasibility certificates
/// are verified on its own data) and the better of the two (status class, then largest DIMACS
/// error, as for a restart: [`Solver::solve`]) is returned; [`Solution::facial`] tells which
/// point it is.
pub fn solve(problem: &Problem, settings: &Settings) -> Result<Solution, SdpError> {
    if settings.facial_reduction {
        let started = Instant::now();
        check_settings(settings)?;
        structure::validate(problem)?;
        if let Some(reduction) = facial::reduce(problem) {
            let reduced = reduction.problem();
            let sol = Solver::new(reduced, settings.clone())?.solve(reduced)?;
            let face = if sol.status.is_infeasible() {
                None
            } else {
                let lifted = reduction.solution(problem, &sol, settings)?;
                if lifted.status.is_optimal() {
                    return Ok(Solution {
                        solve_time: started.elapsed(),
                        ..lifted
                    });
                }
                Some(lifted)
            };
            let plain = Solver::new(problem, settings.clone())?.solve(problem)?;
            let plain = Solution {
                facial: FacialPath::Unreduced {
                    face: face.as_ref().map_or(sol.status, |f| f.status),
                },
                ..plain
            };
            let best = match face {
                Some(lifted) => solution::better(lifted, plain),
                None => plain,
            };
            return Ok(Solution {
                solve_time: started.elapsed(),
                ..best
            });
        }
    }
    Solver::new(problem, settings.clone())?.solve(problem)
}

/// Solves `problem` starting the interior-point method from `start` instead of the default
/// starting point (see [`Solver::solve_from`]). `start` is a point of `problem` itself, so no
/// facial reduction is done ([`Settings::facial_reduction`] applies to [`solve`] only).
pub fn solve_from(
    problem: &Problem,
    settings: &Settings,
    start: &Point,
) -> Result<Solution, SdpError> {
    Solver::new(problem, settings.clone())?.solve_from(problem, start)
}

/// An acceptance test of [`Solver::solve_until`]: shown the dual vector `y` of an iterate and
/// the iterate's measures (as the log callback sees them), `true` ends the solve there with
/// [`Status::Accepted`].
pub type Accept<'a> = dyn FnMut(&[f64], &IterationLog) -> bool + Send + 'a;

/// Largest per-iteration work estimate ([`Analysis::work_estimate`], in flops) for which
/// `Settings::threads == 0` runs the solve on the calling thread: below it, handing every
/// block loop to rayon's global pool costs more in wake-ups and contention than it saves
/// (hinf1, control1, truss1: 2.5–5× slower on the global pool of 2 cores, measured with
/// `threads = 0` against `threads = 1`).
const SEQUENTIAL_WORK_MAX: f64 = 5e5;

/// Factor on the default starting levels `ξ`, `η` of a restart (see [`Solver::solve`]): on the
/// synthesis SDP (47) of a fuzzed order-5 plant that stalls from the default point, every factor
/// from 10 to 10⁴ on `ξ`, `η` or both reached `optimal` in 21–28 iterations.
const RESTART_LEVEL: f64 = 100.0;

/// A solver with the structure of a problem analysed once.
///
/// [`Solver::new`] validates the problem, builds the per-block constraint lists, chooses the
/// Schur formula of every block and allocates the `m×m` workspaces; [`Solver::solve`] then
/// solves any problem with the same block layout whose sparsity pattern is contained in the
/// analysed one (entries missing from the new problem are zeros), reusing all of that.
pub struct Solver {
    settings: Settings,
    analysis: Analysis,
    pool: Option<Arc<rayon::ThreadPool>>,
    workspace: Workspace,
}

impl fmt::Debug for Solver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Solver")
            .field("settings", &self.settings)
            .field("m", &self.analysis.m)
            .field("blocks", &self.analysis.blocks.len())
            .finish()
    }
}

fn check_settings(s: &Settings) -> Result<(), SdpError> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    if !(positive(s.tol_gap)
        && positive(s.tol_feas)
        && positive(s.tol_infeas)
        && positive(s.tol_reduced))
    {
        return Err(SdpError::InvalidSettings(format!(
            "tolerances must be finite and positive (tol_gap {}, tol_feas {}, tol_infeas {}, \
             tol_reduced {})",
            s.tol_gap, s.tol_feas, s.tol_infeas, s.tol_reduced
        )));
    }
    if let Some(g) = s.step_fraction
        && !(g > 0.0 && g < 1.0)
    {
        return Err(SdpError::InvalidSettings(format!(
            "step_fraction {g} outside (0, 1)"
        )));
    }
    Ok(())
}

impl Solver {
    /// Validates and analyses `problem` and allocates the workspaces.
    pub fn new(problem: &Problem, settings: Settings) -> Result<Solver, SdpError> {
        check_settings(&settings)?;
        let mut analysis = structure::analyse(problem)?;
        let threads = match settings.threads {
            0 if analysis.work_estimate() <= SEQUENTIAL_WORK_MAX => 1,
            k => k,
        };
        analysis.exec = if threads == 1 {
            Exec::Sequential
        } else {
            Exec::Parallel
        };
        let pool = if threads >= 2 {
            Some(Arc::new(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .map_err(|e| SdpError::InvalidSettings(format!("thread pool: {e}")))?,
            ))
        } else {
            None
        };
        let m = analysis.m;
        let workspace = Workspace {
            schur_rows: Vec::new(),
            linsys: SchurSolver::new(m, linsys::keeps_copy(&analysis)),
            lsq: None,
        };
        Ok(Solver {
            settings,
            analysis,
            pool,
            workspace,
        })
    }

    /// The settings in use.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Replaces the settings (e.g. tighter tolerances to continue a solve with
    /// [`Solver::solve_from`]), keeping the analysis and workspaces. The thread count is fixed
    /// at [`Solver::new`]; `settings.threads` is ignored here. Errors as for [`Solver::new`] on
    /// invalid settings.
    pub fn set_settings(&mut self, settings: Settings) -> Result<(), SdpError> {
        check_settings(&settings)?;
        self.settings = settings;
        Ok(())
    }

    /// Solves `problem`, which must have the analysed block layout and a sparsity pattern
    /// contained in the analysed one (otherwise [`SdpError::Structure`]).
    ///
    /// **Restart.** An infeasible-start method converges from a starting point that dominates
    /// a solution (`X⁰ ⪰ X*`, `S⁰ ⪰ S*`; Kojima, Megiddo and Mizuno, Math. Prog. 61, 1993);
    /// SDPT3's default point guesses that scale from the data. When the solution is far
    /// larger (an LMI whose certificate needs `P` of norm `10⁶` to meet an absolute margin, as
    /// the synthesis SDP (47) of Sferlazza et al. on a short sampling window), the iterates
    /// hug the boundary with steps of `10⁻⁴` while the infeasibilities stall, and the run ends
    /// in [`Status::NumericalTrouble`] far from any optimum; SDPA's manual gives the same
    /// advice for its `lambdaStar`. A run from the default point that ends so — numerical
    /// trouble with a largest DIMACS error above `√tol_reduced` (`10⁻³` by default: a stall
    /// near the optimum, as on hinf12, is an end-game matter) — is therefore repeated once from
    /// the default point with its levels multiplied by `100` (unless the time budget is spent),
    /// and the better of the two points by status class, then largest DIMACS error, is
    /// returned, marked [`Solution::restarted`], with the iterations and time of both runs.
    pub fn solve(&mut self, problem: &Problem) -> Result<Solution, SdpError> {
        self.run(problem, None, None)
    }

    /// Like [`Solver::solve`] (from `start` when given, as [`Solver::solve_from`]), but once per
    /// iteration, at an iterate that is neither optimal nor a verified infeasibility certificate,
    /// `accept` is shown its `y` and measures; the first `y` it accepts ends the solve with
    /// [`Status::Accepted`] at that iterate. The caller decides what is good enough: e.g. the
    /// LMI layer's margin problem stops at the first `y` at which every strict LMI verifies
    /// (`lmi::FeasibilityOptions::stop_when_verified`), which is a certificate although not
    /// the largest margin. The test costs what `accept` costs, every iteration.
    pub fn solve_until(
        &mut self,
        problem: &Problem,
        start: Option<&Point>,
        accept: &mut Accept<'_>,
    ) -> Result<Solution, SdpError> {
        if let Some(p) = start {
            point::check_point(&self.analysis, &p.y, &p.x, &p.s)?;
        }
        self.run(problem, start, Some(accept))
    }

    /// Like [`Solver::solve`], but the interior-point method starts from `start` (a warm start,
    /// e.g. a solution read with [`crate::solution_file::read_solution`]) instead of SDPT3's
    /// default point. The point need not be feasible, but the method needs an interior one:
    /// PSD blocks are symmetrised, `(M + Mᵀ)/2`, and every block of `X` or `S` that is not
    /// positive definite (no Cholesky factorisation; LP: an entry `≤ 0`) is shifted to
    /// `M + (ℓ − min(λ_min(M), 0))·I`, whose smallest eigenvalue is at least the level `ℓ` of the
    /// default starting point for that block (`ξ` for `X`, `η` for `S`, SDPT3's `infeaspt`;
    /// every entry for an LP block). Positive definite blocks, however close to the boundary,
    /// and `y` are used as given, so a written optimal solution restarts where it ended.
    ///
    /// Errors as for [`Solver::solve`], and [`SdpError::DimensionMismatch`] /
    /// [`SdpError::NonFinite`] for a starting point that does not fit the problem.
    pub fn solve_from(&mut self, problem: &Problem, start: &Point) -> Result<Solution, SdpError> {
        point::check_point(&self.analysis, &start.y, &start.x, &start.s)?;
        self.run(problem, Some(start), None)
    }

    fn run(
        &mut self,
        problem: &Problem,
        start: Option<&Point>,
        mut accept: Option<&mut Accept<'_>>,
    ) -> Result<Solution, SdpError> {
        let vals = self.analysis.values(problem)?;
        let Self {
            settings,
            analysis,
            pool,
            workspace,
        } = self;
        // The iteration may run on a pool worker, which does not see this thread's budget
        // scope: it is carried over.
        let budget = crate::budget::current();
        let mut run = || {
            crate::budget::within(budget.clone(), || {
                let mut once = |from: Start<'_>| {
                    ipm::run(
                        analysis,
                        &vals,
                        problem,
                        settings,
                        workspace,
                        from,
                        accept.as_deref_mut(),
                    )
                };
                let Some(p) = start else {
                    let first = once(Start::Default(1.0));
                    // A stall near the optimum (the end game) is not what a restart mends.
                    let near = first.measures.dimacs_max() <= settings.tol_reduced.sqrt();
                    if first.status != Status::NumericalTrouble
                        || near
                        || crate::budget::exhausted()
                    {
                        return first;
                    }
                    let second = once(Start::Default(RESTART_LEVEL));
                    let (iterations, solve_time) = (
                        first.iterations + second.iterations,
                        first.solve_time + second.solve_time,
                    );
                    return Solution {
                        iterations,
                        solve_time,
                        restarted: true,
                        ..solution::better(second, first)
                    };
                };
                once(Start::From(p))
            })
        };
        Ok(match (pool, analysis.exec) {
            (_, Exec::Sequential) => run(),
            (Some(p), Exec::Parallel) => p.install(run),
            // On rayon's global pool the whole iteration runs on one of its workers: every
            // parallel section then starts inside the pool (work stealing) instead of injecting
            // a job from outside and blocking on a latch, which cost ~20% of the LMI bench's
            // time in thread switches.
            (None, Exec::Parallel) => rayon::scope(|_| run()),
        })
    }
}

/// Test data for the solver's unit tests: Marsaglia's xorshift64 generator (2003), one copy for
/// every module.
#[cfg(test)]
pub(crate) struct XorShift(pub(crate) u64);

#[cfg(test)]
impl XorShift {
    /// The next state.
    pub(crate) fn bits(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Uniform in `[−0.5, 0.5)`.
    pub(crate) fn centred(&mut self) -> f64 {
        (self.bits() >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}
