//! Result of a solve: status, point, objective values and quality measures.

use std::time::Duration;

use faer::Mat;

use super::certificate::InfeasibilityCertificate;

/// How a solve ended.
///
/// # The rule
///
/// With the tolerances of [`crate::Settings`] (defaults in brackets):
///
/// * [`Status::Optimal`]: the relative gap `|⟨C,X⟩ − bᵀy|/(1+|⟨C,X⟩|+|bᵀy|)` and the relative
///   complementarity `⟨X,S⟩/(1+|⟨C,X⟩|+|bᵀy|)` are `≤ tol_gap` [1e-8], and the relative
///   infeasibilities `‖𝒜(X)−b‖₂/(1+‖b‖₂)` and `‖C−𝒜ᵀ(y)−S‖_F/(1+‖C‖_F)` are `≤ tol_feas` [1e-8]
///   (the iterates stay strictly inside the cone, so `X, S ≻ 0`; a point mapped back after
///   facial reduction, see [`crate::solve`], lies on the boundary, and its two cone errors
///   `max(0,−λ_min(X))/(1+‖b‖_∞)` and `max(0,−λ_min(S))/(1+max|C_ij|)`, with the accuracy
///   `4ε‖·‖_F` of a computed eigenvalue added, are held to `tol_feas` as well, and to
///   `tol_reduced` for [`Status::AlmostOptimal`]).
/// * [`Status::PrimalInfeasible`] / [`Status::DualInfeasible`]: a certificate verified on the
///   problem data to `tol_infeas` [1e-8].
/// * Otherwise the solve stopped early — progress stalled, a Newton system or a step broke down
///   (numerical trouble), or the iteration limit was reached — and the best point found is
///   returned. It is [`Status::AlmostOptimal`] when **all six DIMACS errors** of that point
///   ([`Measures::dimacs`], which are scaled by `1 + ‖b‖_∞`, `1 + max|C_ij|` and
///   `1 + |⟨C,X⟩| + |bᵀy|`; the signed gap error is taken in absolute value) are
///   `≤ tol_reduced` [1e-6], in the style of Clarabel's `AlmostSolved` and SDPA's `pdFEAS`;
///   [`Measures::dimacs_max`] is the accuracy it met. Otherwise it is
///   [`Status::MaxIterations`] (limit reached), [`Status::Interrupted`] (the time budget of the
///   enclosing [`crate::budget`] scope ran out, or the solve was cancelled) or
///   [`Status::NumericalTrouble`] (anything else).
///
/// So `NumericalTrouble`, `MaxIterations` and `Interrupted` never label a point whose DIMACS errors are all
/// within `tol_reduced`. The DIMACS errors are reported with every status.
///
/// A solve run with an acceptance test ([`crate::Solver::solve_until`]) also ends with
/// [`Status::Accepted`] at the first iterate (not optimal, not infeasible) that the test accepts;
/// that point is returned as it is, whatever its DIMACS errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Status {
    /// Relative gap, complementarity and both relative infeasibilities are within tolerance.
    Optimal,
    /// The solve stopped before [`Status::Optimal`] (stall, numerical trouble or iteration
    /// limit) at a point whose six DIMACS errors are all within the reduced tolerance
    /// `Settings::tol_reduced` (see the rule above): solved to reduced accuracy.
    AlmostOptimal,
    /// (P) has no feasible `X`: certificate `y` with `Σ y_i A_i ⪯ 0`, `bᵀy > 0` (a ray of (D)).
    PrimalInfeasible,
    /// (D) has no feasible `(y, S)` (an LMI `C − Σ y_i A_i ⪰ 0` is infeasible): certificate
    /// `X ⪰ 0` with `𝒜(X) = 0`, `⟨C, X⟩ < 0`.
    DualInfeasible,
    /// The iteration limit was reached at a point that is not [`Status::AlmostOptimal`]; the
    /// best point found is returned.
    MaxIterations,
    /// The budget of the enclosing [`crate::budget`] scope ran out (deadline passed or
    /// cancellation flag raised) at a point that is not [`Status::AlmostOptimal`]; the best
    /// point found is returned.
    Interrupted,
    /// Progress stopped (tiny steps, stalled gap or infeasibility, Schur system breakdown)
    /// at a point that is not [`Status::AlmostOptimal`]; the best point found is returned and
    /// its [`Measures`] tell how accurate it is.
    NumericalTrouble,
    /// The caller's acceptance test ([`crate::Solver::solve_until`]) accepted the current
    /// iterate before the tolerances of [`Status::Optimal`] were met; that iterate is returned.
    /// It is what the caller asked for (e.g. a point that already verifies the strict LMIs of
    /// a margin problem), in general not an optimum.
    Accepted,
}

impl Status {
    /// [`Status::Optimal`]: solved to the full tolerances.
    pub fn is_optimal(self) -> bool {
        self == Status::Optimal
    }

    /// [`Status::AlmostOptimal`]: solved to the reduced tolerance only.
    pub fn is_almost_optimal(self) -> bool {
        self == Status::AlmostOptimal
    }

    /// Optimal or almost optimal: the returned point is a (possibly reduced-accuracy) optimum.
    pub fn is_solved(self) -> bool {
        matches!(self, Status::Optimal | Status::AlmostOptimal)
    }

    /// Either infeasibility status (a verified certificate is attached to the solution).
    pub fn is_infeasible(self) -> bool {
        matches!(self, Status::PrimalInfeasible | Status::DualInfeasible)
    }

    /// [`Status::PrimalInfeasible`].
    pub fn is_primal_infeasible(self) -> bool {
        self == Status::PrimalInfeasible
    }

    /// [`Status::DualInfeasible`].
    pub fn is_dual_infeasible(self) -> bool {
        self == Status::DualInfeasible
    }

    /// [`Status::Accepted`]: stopped at an iterate the caller's acceptance test accepted.
    pub fn is_accepted(self) -> bool {
        self == Status::Accepted
    }

    /// Neither solved nor infeasible nor accepted: [`Status::MaxIterations`], [`Status::Interrupted`] or
    /// [`Status::NumericalTrouble`].
    pub fn is_failure(self) -> bool {
        matches!(
            self,
            Status::MaxIterations | Status::Interrupted | Status::NumericalTrouble
        )
    }

    /// A stable snake-case identifier in this crate's (P)/(D) naming: `optimal`,
    /// `almost_optimal`, `primal_infeasible`, `dual_infeasible`, `max_iterations`,
    /// `interrupted`, `numerical_trouble`, `accepted` (for SDPA files see
    /// [`crate::sdpa::sdpa_status_id`]).
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Optimal => "optimal",
            Status::AlmostOptimal => "almost_optimal",
            Status::PrimalInfeasible => "primal_infeasible",
            Status::DualInfeasible => "dual_infeasible",
            Status::MaxIterations => "max_iterations",
            Status::Interrupted => "interrupted",
            Status::NumericalTrouble => "numerical_trouble",
            Status::Accepted => "accepted",
        }
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
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

impl Measures {
    /// The largest DIMACS error in absolute value (`NaN` if any is `NaN`): the accuracy a
    /// [`Status::AlmostOptimal`] point met.
    pub fn dimacs_max(&self) -> f64 {
        self.dimacs.iter().fold(0.0f64, |m, e| {
            if e.is_nan() || m.is_nan() {
                f64::NAN
            } else {
                m.max(e.abs())
            }
        })
    }
}

/// How [`crate::solve`] used facial reduction for the returned point (the rule is in the
/// documentation of module `facial`, section "Which point is returned").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FacialPath {
    /// The problem was solved as given: facial reduction is off, found nothing to reduce or was
    /// abandoned, or the solve was a [`crate::Solver`] / [`crate::solve_from`] one.
    NotReduced,
    /// Solved on the face; the point lifted with the dual of the solve on the face.
    Lifted,
    /// Solved on the face; the dual corrected to satisfy the complementarity `S X = 0` of the
    /// original problem before lifting, because the plain lift was not optimal.
    Corrected,
    /// Solved on the face, but neither lifted point was better than the solve of the original
    /// problem without reduction, which is returned; `face` is the status the better lifted
    /// point had (or the infeasibility status of the solve on the face).
    Unreduced {
        /// Status of the point from the face that lost.
        face: Status,
    },
}

impl FacialPath {
    /// A stable snake-case identifier: `not_reduced`, `lifted`, `corrected`, `unreduced`.
    pub fn as_str(self) -> &'static str {
        match self {
            FacialPath::NotReduced => "not_reduced",
            FacialPath::Lifted => "lifted",
            FacialPath::Corrected => "corrected",
            FacialPath::Unreduced { .. } => "unreduced",
        }
    }
}

impl std::fmt::Display for FacialPath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FacialPath::Unreduced { face } => write!(f, "unreduced (face: {face})"),
            other => f.write_str(other.as_str()),
        }
    }
}

/// Outcome of a solve.
#[derive(Debug, Clone)]
pub struct Solution {
    /// How the solve ended.
    pub status: Status,
    /// Primal matrix per block in the dense block layout of [`crate::problem`] (PSD: `n×n`
    /// symmetric; LP: `n×1` column holding the diagonal).
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
    /// Wall-clock time of the solve (analysis excluded when re-solving with a [`crate::Solver`]);
    /// after facial reduction, of everything [`crate::solve`] did, both solves included.
    pub solve_time: Duration,
    /// Whether the point comes from a solve on a face of the cone ([`FacialPath`]).
    pub facial: FacialPath,
    /// Whether the interior-point method was run a second time, from a starting point further
    /// inside the cone, after the first run from the default point ended in
    /// [`Status::NumericalTrouble`] (see [`crate::Solver::solve`]); [`Solution::iterations`]
    /// and [`Solution::solve_time`] then count both runs.
    pub restarted: bool,
}

/// Rank of a status in [`better`]: optimal, almost optimal, a verified infeasibility
/// certificate, anything else.
fn status_class(status: Status) -> u8 {
    if status.is_optimal() {
        0
    } else if status.is_almost_optimal() {
        1
    } else if status.is_infeasible() {
        2
    } else {
        3
    }
}

/// The better of two solutions of the same problem — the two points of a facial reduction
/// (module `facial`), or the two runs of a restart ([`crate::Solver::solve`]): the better status
/// class ([`status_class`]), then the smaller largest DIMACS error ([`Measures::dimacs_max`],
/// `NaN` worst); `first` on a tie.
///
pub(crate) fn better(first: Solution, second: Solution) -> Solution {
    let key = |s: &Solution| {
        let e = s.measures.dimacs_max();
        (
            status_class(s.status),
            if e.is_nan() { f64::INFINITY } else { e },
        )
    };
    let (a, b) = (key(&first), key(&second));
    if b.0 < a.0 || (b.0 == a.0 && b.1 < a.1) {
        second
    } else {
        first
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_helpers_partition_the_statuses() {
        use Status::*;
        for s in [
            Optimal,
            AlmostOptimal,
            PrimalInfeasible,
            DualInfeasible,
            MaxIterations,
            Interrupted,
            NumericalTrouble,
            Accepted,
        ] {
            let classes = [
                s.is_solved(),
                s.is_infeasible(),
                s.is_failure(),
                s.is_accepted(),
            ];
            assert_eq!(classes.iter().filter(|&&c| c).count(), 1, "{s:?}");
            assert_eq!(s.is_optimal(), s == Optimal);
            assert_eq!(s.is_almost_optimal(), s == AlmostOptimal);
            assert_eq!(s.to_string(), s.as_str());
        }
        assert!(PrimalInfeasible.is_primal_infeasible() && !PrimalInfeasible.is_dual_infeasible());
        assert!(DualInfeasible.is_dual_infeasible() && !DualInfeasible.is_primal_infeasible());
    }

    #[test]
    fn dimacs_max_takes_absolute_values_and_propagates_nan() {
        let mut m = Measures {
            dimacs: [1e-9, 0.0, 2e-9, 0.0, -3e-7, 1e-8],
            ..Measures::default()
        };
        assert_eq!(m.dimacs_max(), 3e-7);
        m.dimacs[3] = f64::NAN;
        assert!(m.dimacs_max().is_nan());
    }

    fn solution_with(status: Status, dimacs_max: f64) -> Solution {
        Solution {
            status,
            x: Vec::new(),
            y: Vec::new(),
            s: Vec::new(),
            primal_objective: 0.0,
            dual_objective: 0.0,
            iterations: 0,
            measures: Measures {
                dimacs: [dimacs_max, 0.0, 0.0, 0.0, 0.0, 0.0],
                ..Default::default()
            },
            certificate: None,
            solve_time: std::time::Duration::ZERO,
            facial: FacialPath::NotReduced,
            restarted: false,
        }
    }

    /// The rule of `better`: status class first, then the largest DIMACS error (`NaN` worst),
    /// the first on a tie.
    #[test]
    fn better_ranks_status_then_dimacs() {
        let pick = |a: (Status, f64), b: (Status, f64)| {
            let s = better(solution_with(a.0, a.1), solution_with(b.0, b.1));
            (s.status, s.measures.dimacs[0])
        };
        let (opt, almost, trouble) = (
            Status::Optimal,
            Status::AlmostOptimal,
            Status::NumericalTrouble,
        );
        assert_eq!(pick((almost, 1e-9), (opt, 1e-8)), (opt, 1e-8));
        assert_eq!(pick((trouble, 1e-7), (almost, 1e-6)), (almost, 1e-6));
        assert_eq!(
            pick((trouble, 1e-7), (Status::PrimalInfeasible, 1.0)),
            (Status::PrimalInfeasible, 1.0)
        );
        assert_eq!(pick((almost, 1e-7), (almost, 1e-8)), (almost, 1e-8));
        assert_eq!(pick((almost, 1e-8), (almost, 1e-7)), (almost, 1e-8));
        assert_eq!(pick((trouble, 2e-3), (trouble, 2e-3)).1, 2e-3);
        let nan = pick((trouble, f64::NAN), (trouble, 1.0));
        assert_eq!(nan, (trouble, 1.0));
    }
}
