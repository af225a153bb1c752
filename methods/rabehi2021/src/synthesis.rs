//! Proposition 1 of Rabehi et al. (2021): find `P = Pᵀ`, `F ∈ R^{2n×2n}`, `G1, G2 ∈ R^{n×n}`,
//! `L ∈ R^{n×p}` with `I + LC = G1 − G2` (35b), `G1, G2 ≥ 0` (35c–d) and, at every vertex `M_i`
//! of the Taylor polytope of `e^{Āμ}`,
//!
//! ```text
//!        [ −F − Fᵀ    FΓ     M_iᵀP ]
//! Ψ_i =  [ ΓᵀFᵀ      −P      0     ]  ≺ 0,     Γ = Γ(G1, G2) = [[G1, G2], [G2, G1]].     (44)
//!        [ P M_i      0      −P    ]
//! ```
//!
//! (The paper lists `{P, G1, G2, L}` as unknowns and forgets the slack `F` of the projection
//! lemma; `F` is a decision variable here.) The only bilinear term is `FΓ`. Everything is solved
//! with our own interior-point method through LMI steps of the common form
//!
//! ```text
//! minimise t   s.t.  Ψ_i ⪯ tI (i = 1..v),  p_min·I ⪯ P ⪯ p_max·I,  0 ≤ G1, G2 ≤ g_max,  (35b),
//! ```
//!
//! so that the value `t` of every step is comparable:
//!
//! 1. **Convex restriction** `F = I` ([`StepKind::ConvexRestriction`]): (44) is jointly
//!    homogeneous of degree 1 in `(F, P)`, so `F = fI` with `f > 0` is `F = I` without loss of
//!    generality within that family; one LMI in `(P, G1, G2, L, t)`.
//! 2. **Alternation** ([`StepKind::FixedGamma`] then [`StepKind::FixedF`]): with `(G1, G2)`
//!    fixed, an LMI in `(P, F, t)`; with `F` fixed, an LMI in `(P, G1, G2, L, t)`. Each step's
//!    feasible set contains the previous iterate, so `t` is non-increasing.
//! 3. **Sequential convex inner approximation** ([`StepKind::Sequential`]): at `(F_k, Γ_k)`,
//!    `FΓ = F_kΓ + FΓ_k − F_kΓ_k + ΔFΔΓ` with `ΔF = F − F_k`, `ΔΓ = Γ − Γ_k`; since
//!    `[[0, ΔFΔΓ], [⋆, 0]] ⪯ diag(αΔFΔFᵀ, ΔΓᵀΔΓ/α)` for any `α > 0`, the LMI
//!
//!    ```text
//!    [ Ψ_i^lin − tI   E₁ΔF        E₂ΔΓᵀ ]
//!    [ ⋆              −I/α        0     ]  ⪯ 0      (blocks of order 10n)
//!    [ ⋆              ⋆           −αI   ]
//!    ```
//!
//!    implies `Ψ_i ⪯ tI`, moves all variables at once, and contains the current iterate.
//!
//! Every step's `t` is **recomputed in `f64`** from the returned matrices (`max_i λmax(Ψ_i)`);
//! the best iterate is kept, and the log records every step. The run stops when (44) holds at
//! the vertices and Theorem 1 is certified for `Γ(L)` (below), when the value stalls, or at the
//! step limits; a run that does not get there is reported as **not certified**, with a typed
//! reason ([`NotCertified`]): the value stalled where `t` plus the rounding bound of its f64
//! evaluation is `≥ 0` ([`NotCertified::Infeasible`]), the
//! step limits or the time budget ran out while it was still decreasing
//! ([`NotCertified::BudgetExhausted`]), or
//! (44) holds at the vertices but the Theorem 1 re-verification for `Γ(L)` fails
//! ([`NotCertified::VerificationFailed`]). When no step returns a finite point at all the run is
//! [`Error::SolverInconclusive`].
//!
//! **Certificates.** [`Bmi44Check`] is Proposition 1's own certificate: (44) holds on the whole
//! window if `max_i λmax(Ψ_i) + ‖P‖₂δ < 0` (with a rounding allowance), `δ` the Taylor remainder
//! bound — `Ψ` depends on `M` only through the block `PM`, so the remainder perturbs it by at
//! most `‖PΔ‖₂ ≤ ‖P‖₂δ`. **Remark 6 caveat.** The observer is implemented with
//! `Γ(L) = [[G⁺, G⁻], [G⁻, G⁺]] ≤ Γ(G1, G2)` elementwise, and a common quadratic `P` is not
//! inherited by an elementwise-smaller nonnegative matrix; so as soon as (44) holds at the
//! vertices, Theorem 1 is re-verified for `Γ(L)` itself with a fresh `P`
//! ([`crate::analysis`], with [`SynthesisOptions::analysis`], independent of the design polytope).
//! That re-verification is the statement the observer needs, and it is rigorous on its own
//! (polytope with remainder, plus the grid bound); a design is [`DesignStatus::Certified`] only
//! when it passes.

use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite;
use std::time::{Duration, Instant};

use faer::{Mat, MatRef};
use sporadic_sdp::lmi::{Compiled, Expr, Model, Param, SolveOptions, Var};

use crate::analysis::{Analysis, AnalysisOptions, analyse};
use crate::error::Error;
use crate::ipr::{MetzlerDecomposition, gamma_of_gain, jump_matrix, negative_part, positive_part};
use crate::polytope::{PolytopeOptions, norm2, taylor_polytope};
use crate::system::Plant;
use sporadic_model::SamplingWindow;

/// Options of the Proposition 1 pipeline (defaults: [`SynthesisOptions::default`]).
#[derive(Debug, Clone)]
pub struct SynthesisOptions {
    /// Construction of the Taylor polytope.
    pub polytope: PolytopeOptions,
    /// Lower bound `P ⪰ p_min·I` (keeps `P ≻ 0` while `t > 0`). Default `1e-3`.
    pub p_min: f64,
    /// Upper bound `P ⪯ p_max·I` (normalisation of the homogeneous pair `(F, P)`). Default `1e3`.
    pub p_max: f64,
    /// Entrywise bound `G1, G2 ≤ g_max` (keeps the LP part bounded). Default `1e3`.
    pub g_max: f64,
    /// Largest number of alternation cycles (one `FixedGamma` plus one `FixedF` step each).
    /// Default 12.
    pub max_alternations: usize,
    /// Use the sequential convex inner approximation when the alternation stalls. Default `true`.
    pub sequential: bool,
    /// Largest number of sequential steps. Default 12.
    pub max_sequential: usize,
    /// A cycle (or sequential step) that lowers the best `t` by less than
    /// `stall_tolerance·(1 + |t|)` counts as a stall. Default `1e-4`.
    pub stall_tolerance: f64,
    /// Interior-point settings and the LMI layer's verification safety factor.
    pub solve: SolveOptions,
    /// Settings of the Theorem 1 re-verification with `Γ(L)` (Remark 6); by default a split Taylor
    /// polytope with remainder ≤ 1e-9 and the grid check, whatever the design polytope.
    pub analysis: AnalysisOptions,
    /// Factor of the rounding allowance of the `f64` re-check of (44) (multiplies
    /// `6n·ε_mach·max|Ψ_ij|`). Default 100.
    pub safety: f64,
}

impl Default for SynthesisOptions {
    fn default() -> Self {
        Self {
            polytope: PolytopeOptions::default(),
            p_min: 1e-3,
            p_max: 1e3,
            g_max: 1e3,
            max_alternations: 12,
            sequential: true,
            max_sequential: 12,
            stall_tolerance: 1e-4,
            solve: SolveOptions::default(),
            analysis: AnalysisOptions::default(),
            safety: 100.0,
        }
    }
}

impl SynthesisOptions {
    /// Checks every field; the error names the offending one.
    ///
    /// # Errors
    /// [`Error::Input`] for a non-positive or non-finite `p_min`, `p_max`, `g_max`,
    /// `stall_tolerance`, `p_min ≥ p_max`, `safety < 1`, or invalid polytope options.
    pub fn validate(&self) -> Result<(), Error> {
        let positive = |name, value: f64| {
            if value > 0.0 && value.is_finite() {
                Ok(())
            } else {
                Err(InputError::parameter(name, value, "must be finite and > 0"))
            }
        };
        positive("p_min", self.p_min)?;
        positive("p_max", self.p_max)?;
        positive("g_max", self.g_max)?;
        positive("stall_tolerance", self.stall_tolerance)?;
        if self.p_min >= self.p_max {
            return Err(InputError::parameter("p_min", self.p_min, "must be below p_max").into());
        }
        if !(self.safety >= 1.0 && self.safety.is_finite()) {
            return Err(
                InputError::parameter("safety", self.safety, "must be finite and >= 1").into(),
            );
        }
        self.polytope.validate()
    }
}

/// Which LMI a step solved (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepKind {
    /// `F = I`, variables `(P, G1, G2, L, t)`.
    ConvexRestriction,
    /// `(G1, G2)` fixed, variables `(P, F, t)`.
    FixedGamma,
    /// `F` fixed, variables `(P, G1, G2, L, t)`.
    FixedF,
    /// Sequential convex inner approximation, all variables.
    Sequential,
}

/// One line of the iteration log.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRecord {
    /// Step number (0 = the convex restriction).
    pub step: usize,
    /// Which LMI was solved.
    pub kind: StepKind,
    /// The solver's optimal `t`.
    pub solver_t: f64,
    /// `max_i λmax(Ψ_i)` recomputed in `f64` at the returned point.
    pub t: f64,
    /// Whether the point improved on the best one so far (and was kept).
    pub accepted: bool,
    /// Interior-point iterations.
    pub iterations: usize,
    /// Wall time of the step (build, solve, re-check).
    pub time: Duration,
}

/// The `f64` re-check of (44) at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bmi44Check {
    /// `max_i λmax(Ψ_i)`.
    pub max_eigenvalue: f64,
    /// `‖P‖₂δ`: the largest change of any `Ψ` the Taylor remainder can cause.
    pub remainder_effect: f64,
    /// Rounding allowance.
    pub rounding: f64,
    /// Smallest entry of `G1` and `G2` ((35c–d)).
    pub min_g_entry: f64,
    /// `max|I + LC − (G1 − G2)|` ((35b)).
    pub equality_residual: f64,
    /// `max_eigenvalue + remainder_effect + rounding < 0`, `G1, G2 ≥ 0` and (35b) within `1e-9`.
    pub certified: bool,
}

impl Bmi44Check {
    /// The margin of (44): `−(max_i λmax(Ψ_i) + ‖P‖₂δ + rounding)`, positive when (44) is
    /// certified on the whole window (the remainder `δ` of the Taylor polytope and the rounding
    /// allowance accounted for). `Ψ_i` is jointly homogeneous of degree 1 in `(F, P)`, so the
    /// value is relative to the normalisation `p_min·I ⪯ P ⪯ p_max·I` of
    /// [`SynthesisOptions`].
    pub fn margin(&self) -> f64 {
        -(self.max_eigenvalue + self.remainder_effect + self.rounding)
    }
}

/// Final status of a synthesis.
#[derive(Debug, Clone, PartialEq)]
pub enum DesignStatus {
    /// (44) holds at the vertices (`f64` re-check) and Theorem 1 is certified for `Γ(L)`.
    Certified,
    /// No certified design, with the typed reason.
    NotCertified(NotCertified),
}

/// Why a Proposition 1 run produced no certified design.
#[derive(Debug, Clone, PartialEq)]
pub enum NotCertified {
    /// The best value `t = max_i λmax(Ψ_i)` of (44) stayed `≥ 0` (up to rounding) and stopped
    /// decreasing (or the only allowed step, the convex restriction, was taken): the local BMI
    /// method found no point satisfying (44) at the polytope vertices.
    Infeasible {
        /// Best `max_i λmax(Ψ_i)`.
        best_t: f64,
        /// `‖P‖₂δ` at the best iterate.
        remainder_effect: f64,
        /// The rounding bound of the f64 evaluation of the `Ψ_i` at the best iterate
        /// (`max_i λmax(Ψ_i)` plus it must be negative).
        rounding: f64,
        /// Number of LMI steps solved.
        steps: usize,
    },
    /// The alternation or the sequential convex iterations hit their step limit
    /// ([`SynthesisOptions::max_alternations`], [`SynthesisOptions::max_sequential`]) while `t`
    /// was still decreasing and still `≥ 0`, or the time budget (`sporadic_sdp::budget`) ran
    /// out and interrupted the solves.
    BudgetExhausted {
        /// Best `max_i λmax(Ψ_i)`.
        best_t: f64,
        /// Number of LMI steps solved.
        steps: usize,
        /// Which limit ran out.
        limit: &'static str,
    },
    /// (44) holds at the vertices, but Theorem 1 for the implemented `Γ(L)` (Remark 6) is not
    /// certified: the polytope SDP or the μ-grid re-verification fails.
    VerificationFailed {
        /// `max_i λmax(Ψ_i)` (negative).
        best_t: f64,
        /// The μ where the grid check found its largest `λmax` of (19), when the grid check
        /// failed.
        tau: Option<f64>,
        /// The failing values.
        detail: String,
    },
}

impl std::fmt::Display for NotCertified {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NotCertified::Infeasible {
                best_t,
                remainder_effect,
                rounding,
                steps,
            } => write!(
                f,
                "(44) not certified: best max_i lambda_max(Psi_i) = {best_t:.3e} (+ remainder \
                 {remainder_effect:.3e}, + rounding bound {rounding:.3e}; the sum must be \
                 negative) after {steps} LMI steps (stalled)"
            ),
            NotCertified::BudgetExhausted {
                best_t,
                steps,
                limit,
            } => write!(
                f,
                "(44) not certified: best max_i lambda_max(Psi_i) = {best_t:.3e} after {steps} LMI steps ({limit} ran out before the value stalled)"
            ),
            NotCertified::VerificationFailed { best_t, detail, .. } => write!(
                f,
                "(44) holds at the vertices (max lambda_max = {best_t:.3e}) but Theorem 1 fails for Gamma(L) (Remark 6): {detail}"
            ),
        }
    }
}

impl NotCertified {
    /// The shared typed reason ([`sporadic_model::Reason`]) with this explanation:
    /// `Infeasible` → `InfeasibleLmi`, `BudgetExhausted` → `BudgetExhausted`,
    /// `VerificationFailed` → `VerificationFailed`.
    pub fn reason(&self) -> sporadic_model::Reason {
        use sporadic_model::Reason;
        let message = self.to_string();
        match self {
            NotCertified::Infeasible { .. } => Reason::InfeasibleLmi { message },
            NotCertified::BudgetExhausted { .. } => Reason::BudgetExhausted { message },
            NotCertified::VerificationFailed { tau, .. } => {
                Reason::VerificationFailed { tau: *tau, message }
            }
        }
    }
}

/// Result of [`synthesise`]: the best iterate, its checks and the iteration log.
#[derive(Debug, Clone)]
pub struct Design {
    /// Final verdict.
    pub status: DesignStatus,
    /// Observer gain `L` (`n × p`).
    pub l: Mat<f64>,
    /// `G1 ≥ 0`.
    pub g1: Mat<f64>,
    /// `G2 ≥ 0`.
    pub g2: Mat<f64>,
    /// Projection-lemma slack `F` (`2n × 2n`).
    pub f: Mat<f64>,
    /// Lyapunov matrix `P` of (44).
    pub p: Mat<f64>,
    /// `f64` re-check of (44) at the best iterate.
    pub bmi: Bmi44Check,
    /// Theorem 1 re-verification with `Γ(L)` (the last one run; run whenever an improved
    /// iterate satisfies (44) at the vertices).
    pub reverification: Option<Analysis>,
    /// Number of polytope vertices.
    pub vertices: usize,
    /// Taylor remainder bound `δ`.
    pub remainder: f64,
    /// Every LMI step, in order.
    pub log: Vec<StepRecord>,
}

impl Design {
    /// Whether the status is [`DesignStatus::Certified`].
    pub fn is_certified(&self) -> bool {
        self.status == DesignStatus::Certified
    }

    /// The best `t` reached (`max_i λmax(Ψ_i)` at the returned point).
    pub fn best_t(&self) -> f64 {
        self.bmi.max_eigenvalue
    }
}

/// A point `(P, F, G1, G2, L)` of the pipeline.
#[derive(Debug, Clone)]
struct Iterate {
    p: Mat<f64>,
    f: Mat<f64>,
    g1: Mat<f64>,
    g2: Mat<f64>,
    l: Mat<f64>,
    t: f64,
}

/// The data of (44) on one window: vertices, sizes, remainder.
struct Bmi44 {
    n: usize,
    c: Mat<f64>,
    vertices: Vec<Mat<f64>>,
    delta: f64,
}

/// The common variables of a step model.
struct Common {
    p: Var,
    t: Var,
}

impl Bmi44 {
    /// Adds `P`, `t`, the `P` bounds and the objective `min t`.
    fn common(&self, m: &mut Model, o: &SynthesisOptions) -> Result<Common, Error> {
        let p = m.symmetric("P", 2 * self.n);
        let t = m.scalar("t");
        m.constrain(p.ge(o.p_min).named("P >= p_min I"))?;
        m.constrain(p.le(o.p_max).named("P <= p_max I"))?;
        m.minimize(&t)?;
        Ok(Common { p, t })
    }

    /// Adds `G1`, `G2`, `L` with (35b)–(35d) and the bound `g_max`; returns `(G1, G2, L, Γ)`.
    fn reset_variables(
        &self,
        m: &mut Model,
        o: &SynthesisOptions,
    ) -> Result<(Var, Var, Var, Expr), Error> {
        let n = self.n;
        let g1 = m.full("G1", n, n);
        let g2 = m.full("G2", n, n);
        let l = m.full("L", n, self.c.nrows());
        m.constrain(
            (Expr::identity(n) + &l * &self.c)
                .equals(&g1 - &g2)
                .named("(35b) I + LC = G1 - G2"),
        )?;
        for (g, name) in [(&g1, "G1"), (&g2, "G2")] {
            m.constrain(g.ge_entrywise(0.0).named(format!("(35c-d) {name} >= 0")))?;
            m.constrain(g.le_entrywise(o.g_max).named(format!("{name} <= g_max")))?;
        }
        let gamma = Expr::blocks(&[
            vec![Some(g1.expr()), Some(g2.expr())],
            vec![Some(g2.expr()), Some(g1.expr())],
        ]);
        Ok((g1, g2, l, gamma))
    }

    /// `Ψ_i` from its blocks `−He(F)`, `FΓ` (both possibly linearised) and `P`.
    fn psi(corner: &Expr, coupling: &Expr, p: &Var, vertex: &Mat<f64>) -> Expr {
        Expr::sym_blocks(&[
            vec![Some(corner.clone()), None, None],
            vec![Some(coupling.t()), Some(-p), None],
            vec![Some(p * vertex), None, Some(-p)],
        ])
    }

    /// `Ψ_i ⪯ t I` of (44) at every vertex `i` of the polytope.
    fn constrain_vertices(
        &self,
        m: &mut Model,
        corner: &Expr,
        coupling: &Expr,
        c: &Common,
    ) -> Result<(), Error> {
        for (i, v) in self.vertices.iter().enumerate() {
            let psi = Self::psi(corner, coupling, &c.p, v);
            m.constrain(psi.le(&c.t).named(format!("Psi_{}", i + 1)))?;
        }
        Ok(())
    }

    /// Model of the steps with `F` fixed (a parameter): convex restriction and `FixedF`.
    fn fixed_f_model(&self, o: &SynthesisOptions) -> Result<StepModel, Error> {
        let mut m = Model::new();
        let c = self.common(&mut m, o)?;
        let (g1, g2, l, gamma) = self.reset_variables(&mut m, o)?;
        let two_n = 2 * self.n;
        let fk = m.param("F_k", dense_placeholder(two_n).as_ref())?;
        let corner = -fk.expr().he();
        let coupling = &fk * &gamma;
        self.constrain_vertices(&mut m, &corner, &coupling, &c)?;
        Ok(StepModel {
            compiled: m.compile(&o.solve)?,
            c: self.c.clone(),
            p: c.p,
            t: c.t,
            f: None,
            resets: Some((g1, g2, l)),
            fk: Some(fk),
            gk: None,
            alpha: None,
        })
    }

    /// Model of the steps with `(G1, G2)` fixed (a parameter `Γ_k`).
    fn fixed_gamma_model(&self, o: &SynthesisOptions) -> Result<StepModel, Error> {
        let mut m = Model::new();
        let c = self.common(&mut m, o)?;
        let two_n = 2 * self.n;
        let f = m.full("F", two_n, two_n);
        let gk = m.param("Gamma_k", dense_placeholder(two_n).as_ref())?;
        let corner = -f.expr().he();
        let coupling = &f * &gk;
        self.constrain_vertices(&mut m, &corner, &coupling, &c)?;
        Ok(StepModel {
            compiled: m.compile(&o.solve)?,
            c: self.c.clone(),
            p: c.p,
            t: c.t,
            f: Some(f),
            resets: None,
            fk: None,
            gk: Some(gk),
            alpha: None,
        })
    }

    /// Model of the sequential convex inner approximation at `(F_k, Γ_k)` with weight `α`
    /// (parameters `F_k`, `Γ_k`, `α`, `1/α`).
    fn sequential_model(&self, o: &SynthesisOptions) -> Result<StepModel, Error> {
        let mut m = Model::new();
        let c = self.common(&mut m, o)?;
        let (g1, g2, l, gamma) = self.reset_variables(&mut m, o)?;
        let two_n = 2 * self.n;
        let fk = m.param("F_k", dense_placeholder(two_n).as_ref())?;
        let gk = m.param("Gamma_k", dense_placeholder(two_n).as_ref())?;
        let alpha = m.param("alpha", faer::mat![[1.0]].as_ref())?;
        let inv_alpha = m.param("1/alpha", faer::mat![[1.0]].as_ref())?;
        let f = m.full("F", two_n, two_n);
        let linear = &fk * &gamma + &f * &gk - &fk * &gk;
        let d_f = &f - &fk;
        let d_gamma = &gamma - &gk;
        let t_id = &c.t * Expr::identity(two_n);
        for (i, v) in self.vertices.iter().enumerate() {
            let big = Expr::sym_blocks(&[
                vec![Some(-f.expr().he() - &t_id), None, None, None, None],
                vec![Some(linear.t()), Some(-&c.p - &t_id), None, None, None],
                vec![Some(&c.p * v), None, Some(-&c.p - &t_id), None, None],
                vec![
                    Some(d_f.t()),
                    None,
                    None,
                    Some(-(Expr::identity(two_n) * &inv_alpha)),
                    None,
                ],
                vec![
                    None,
                    Some(d_gamma.clone()),
                    None,
                    None,
                    Some(-(Expr::identity(two_n) * &alpha)),
                ],
            ]);
            m.constrain(big.le(0.0).named(format!("Psi_{}^inner", i + 1)))?;
        }
        Ok(StepModel {
            compiled: m.compile(&o.solve)?,
            c: self.c.clone(),
            p: c.p,
            t: c.t,
            f: Some(f),
            resets: Some((g1, g2, l)),
            fk: Some(fk),
            gk: Some(gk),
            alpha: Some((alpha, inv_alpha)),
        })
    }

    /// `max_i λmax(Ψ_i)` and `max|Ψ_ij|` at a point (`f64`).
    fn evaluate(
        &self,
        p: MatRef<'_, f64>,
        f: MatRef<'_, f64>,
        g1: MatRef<'_, f64>,
        g2: MatRef<'_, f64>,
    ) -> Result<(f64, f64), Error> {
        let two_n = 2 * self.n;
        let gamma = jump_matrix(g1, g2);
        let fg = f * &gamma;
        let mut worst = f64::NEG_INFINITY;
        let mut scale: f64 = 0.0;
        for v in &self.vertices {
            let pm = p * v;
            let psi = Mat::from_fn(3 * two_n, 3 * two_n, |i, j| {
                let (bi, bj) = (i / two_n, j / two_n);
                let (r, s) = (i % two_n, j % two_n);
                match (bi, bj) {
                    (0, 0) => -(f[(r, s)] + f[(s, r)]),
                    (0, 1) => fg[(r, s)],
                    (1, 0) => fg[(s, r)],
                    (0, 2) => pm[(s, r)],
                    (2, 0) => pm[(r, s)],
                    (1, 1) | (2, 2) => -0.5 * (p[(r, s)] + p[(s, r)]),
                    _ => 0.0,
                }
            });
            scale = scale.max(psi.norm_max());
            worst = worst.max(sporadic_linalg::max_eigenvalue(psi.as_ref())?);
        }
        Ok((worst, scale))
    }

    fn check(&self, it: &Iterate, o: &SynthesisOptions) -> Result<Bmi44Check, Error> {
        let (max_eigenvalue, scale) =
            self.evaluate(it.p.as_ref(), it.f.as_ref(), it.g1.as_ref(), it.g2.as_ref())?;
        let remainder_effect = norm2(it.p.as_ref())? * self.delta;
        let rounding = o.safety * (6 * self.n) as f64 * f64::EPSILON * scale;
        let n = self.n;
        let g = Mat::<f64>::identity(n, n) + &it.l * &self.c;
        let mut residual: f64 = 0.0;
        let mut min_g = f64::INFINITY;
        for j in 0..n {
            for i in 0..n {
                residual = residual.max((g[(i, j)] - it.g1[(i, j)] + it.g2[(i, j)]).abs());
                min_g = min_g.min(it.g1[(i, j)]).min(it.g2[(i, j)]);
            }
        }
        Ok(Bmi44Check {
            max_eigenvalue,
            remainder_effect,
            rounding,
            min_g_entry: min_g,
            equality_residual: residual,
            certified: max_eigenvalue + remainder_effect + rounding < 0.0
                && min_g >= 0.0
                && residual <= 1e-9,
        })
    }
}

/// A compiled step model and its handles.
struct StepModel {
    compiled: Compiled,
    /// The output matrix `C` (for the repair of the split (31)).
    c: Mat<f64>,
    p: Var,
    t: Var,
    f: Option<Var>,
    resets: Option<(Var, Var, Var)>,
    fk: Option<Param>,
    gk: Option<Param>,
    alpha: Option<(Param, Param)>,
}

impl StepModel {
    /// Solves at the current parameters; returns the new iterate (unchanged parts from `prev`),
    /// the solver's `t` and the iteration count, or `None` when the solver returned no usable
    /// point.
    fn solve(&mut self, prev: &Iterate) -> Result<Option<(Iterate, f64, usize)>, Error> {
        let sol = self.compiled.solve()?;
        let y = sol.decision_scalars();
        if y.iter().any(|v| !v.is_finite()) {
            return Ok(None);
        }
        let p = sol.value(&self.p)?;
        let solver_t = sol.scalar(&self.t)?;
        let f = match &self.f {
            Some(f) => sol.value(f)?,
            None => prev.f.clone(),
        };
        let (g1, g2, l) = match &self.resets {
            Some((g1, g2, l)) => {
                let l = sol.value(l)?;
                let (g1, g2) = repair_split(self.c.as_ref(), &l, &sol.value(g1)?, &sol.value(g2)?);
                (g1, g2, l)
            }
            None => (prev.g1.clone(), prev.g2.clone(), prev.l.clone()),
        };
        Ok(Some((
            Iterate {
                p,
                f,
                g1,
                g2,
                l,
                t: f64::NAN,
            },
            solver_t,
            sol.sdp.iterations,
        )))
    }
}

/// A dense value for a matrix parameter at compile time, so that the solver's structure analysis
/// covers every later value (re-solves then reuse it).
fn dense_placeholder(k: usize) -> Mat<f64> {
    Mat::from_fn(k, k, |i, j| if i == j { 2.0 } else { 1.0 })
}

/// Interior-point solutions satisfy (35b)–(35d) only up to the solver tolerance. The split is
/// repaired onto the exact form (31): `G1 = G⁺ + Δ`, `G2 = G⁻ + Δ` with `G = I + LC` from the
/// returned `L` and `Δ = max(0, ((G1 − G⁺) + (G2 − G⁻))/2)` (the entrywise least-squares choice),
/// so that `G1, G2 ≥ 0` and `G1 − G2 = G` hold exactly; (44) is then re-checked on the repaired
/// matrices.
fn repair_split(
    c: MatRef<'_, f64>,
    l: &Mat<f64>,
    g1: &Mat<f64>,
    g2: &Mat<f64>,
) -> (Mat<f64>, Mat<f64>) {
    let n = g1.nrows();
    let g = Mat::<f64>::identity(n, n) + l * c;
    let (gp, gm) = (positive_part(g.as_ref()), negative_part(g.as_ref()));
    let delta = Mat::from_fn(n, n, |i, j| {
        (0.5 * ((g1[(i, j)] - gp[(i, j)]) + (g2[(i, j)] - gm[(i, j)]))).max(0.0)
    });
    (&gp + &delta, &gm + &delta)
}

/// Runs the Proposition 1 pipeline (module docs) for `plant` on `window`.
///
/// # Errors
/// Invalid options or a failure of a numerical kernel or of the LMI layer. A design that cannot
/// be certified is not an error: see [`Design::status`].
pub fn synthesise(
    plant: &Plant,
    window: &SamplingWindow,
    options: &SynthesisOptions,
) -> Result<Design, Error> {
    synthesise_from(plant, window, None, options)
}

/// As [`synthesise`], with the first `F`-fixed step started from `initial_f` (`2n × 2n`, e.g.
/// the slack of a design on a neighbouring window) instead of `F = I`.
///
/// # Errors
/// As [`synthesise`], plus a wrongly sized or non-finite `initial_f`.
pub fn synthesise_from(
    plant: &Plant,
    window: &SamplingWindow,
    initial_f: Option<MatRef<'_, f64>>,
    options: &SynthesisOptions,
) -> Result<Design, Error> {
    options.validate()?;
    let n = plant.n();
    let two_n = 2 * n;
    if let Some(f) = initial_f {
        if f.nrows() != two_n || f.ncols() != two_n {
            return Err(
                InputError::mismatch("order of the initial F (= 2n)", two_n, f.nrows()).into(),
            );
        }
        check_finite(f, "initial F")?;
    }
    let decomposition = MetzlerDecomposition::new(plant.a())?;
    let poly = taylor_polytope(decomposition.a_bar.as_ref(), window, &options.polytope)?;
    let bmi = Bmi44 {
        n,
        c: plant.c().to_owned(),
        vertices: poly.vertices().to_vec(),
        delta: poly.remainder_bound(),
    };
    let mut run = Run {
        bmi: &bmi,
        plant,
        window,
        a_bar: decomposition.a_bar.as_ref(),
        options,
        log: Vec::new(),
        best: None,
        best_check: None,
        reverification: None,
        done: false,
        stop: Stop::Stalled,
    };

    // 1. Convex restriction F = I (or the given F).
    let mut fixed_f = bmi.fixed_f_model(options)?;
    let f0 = initial_f.map_or_else(|| Mat::<f64>::identity(two_n, two_n), |f| f.to_owned());
    let seed = Iterate {
        p: Mat::identity(two_n, two_n),
        f: f0.clone(),
        g1: Mat::zeros(n, n),
        g2: Mat::zeros(n, n),
        l: Mat::zeros(n, plant.p()),
        t: f64::INFINITY,
    };
    fixed_f
        .compiled
        .set_param(fixed_f.fk.as_ref().expect("F_k"), f0.as_ref())?;
    run.step(&mut fixed_f, &seed, StepKind::ConvexRestriction)?;

    // 2. Alternation.
    let mut fixed_gamma = None;
    let mut cycles = 0;
    while !run.done && run.best.is_some() && cycles < options.max_alternations {
        cycles += 1;
        run.stop = Stop::Budget("max_alternations");
        let before = run.best_t();
        let current = run.best.clone().expect("best");
        let model = match &mut fixed_gamma {
            Some(m) => m,
            None => fixed_gamma.insert(bmi.fixed_gamma_model(options)?),
        };
        let gamma = jump_matrix(current.g1.as_ref(), current.g2.as_ref());
        model
            .compiled
            .set_param(model.gk.as_ref().expect("Gamma_k"), gamma.as_ref())?;
        run.step(model, &current, StepKind::FixedGamma)?;
        if run.done {
            break;
        }
        let current = run.best.clone().expect("best");
        fixed_f
            .compiled
            .set_param(fixed_f.fk.as_ref().expect("F_k"), current.f.as_ref())?;
        run.step(&mut fixed_f, &current, StepKind::FixedF)?;
        if run.stalled(before) {
            run.stop = Stop::Stalled;
            break;
        }
    }

    // 3. Sequential convex inner approximation.
    let mut sequential = None;
    let mut steps = 0;
    while !run.done && options.sequential && run.best.is_some() && steps < options.max_sequential {
        steps += 1;
        run.stop = Stop::Budget("max_sequential");
        let before = run.best_t();
        let current = run.best.clone().expect("best");
        let gamma = jump_matrix(current.g1.as_ref(), current.g2.as_ref());
        let alpha = {
            let (gn, fnorm) = (gamma.norm_l2(), current.f.norm_l2());
            if gn > 0.0 && fnorm > 0.0 {
                gn / fnorm
            } else {
                1.0
            }
        };
        let model = match &mut sequential {
            Some(m) => m,
            None => sequential.insert(bmi.sequential_model(options)?),
        };
        let (a, inv_a) = model.alpha.as_ref().expect("alpha");
        model.compiled.set_param(a, faer::mat![[alpha]].as_ref())?;
        model
            .compiled
            .set_param(inv_a, faer::mat![[1.0 / alpha]].as_ref())?;
        model
            .compiled
            .set_param(model.fk.as_ref().expect("F_k"), current.f.as_ref())?;
        model
            .compiled
            .set_param(model.gk.as_ref().expect("Gamma_k"), gamma.as_ref())?;
        run.step(model, &current, StepKind::Sequential)?;
        if run.stalled(before) {
            run.stop = Stop::Stalled;
            break;
        }
    }
    run.finish(poly.vertex_count(), poly.remainder_bound())
}

/// Why the last loop of a run ended (when the run is not certified).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Stop {
    /// The value stalled, or no iterative step was allowed.
    Stalled,
    /// The named step limit ran out.
    Budget(&'static str),
}

/// State of one pipeline run.
struct Run<'a> {
    bmi: &'a Bmi44,
    plant: &'a Plant,
    window: &'a SamplingWindow,
    a_bar: MatRef<'a, f64>,
    options: &'a SynthesisOptions,
    log: Vec<StepRecord>,
    best: Option<Iterate>,
    best_check: Option<Bmi44Check>,
    reverification: Option<Analysis>,
    done: bool,
    stop: Stop,
}

impl Run<'_> {
    fn best_t(&self) -> f64 {
        self.best.as_ref().map_or(f64::INFINITY, |b| b.t)
    }

    /// Whether the best `t` improved by less than the stall tolerance since `before`.
    fn stalled(&self, before: f64) -> bool {
        let now = self.best_t();
        !(before - now > self.options.stall_tolerance * (1.0 + now.abs()))
    }

    /// Solves one step, re-checks it, keeps it if it improves, and tests the stopping rule.
    fn step(&mut self, model: &mut StepModel, prev: &Iterate, kind: StepKind) -> Result<(), Error> {
        let start = Instant::now();
        let solved = model.solve(prev)?;
        let Some((mut it, solver_t, iterations)) = solved else {
            self.log.push(StepRecord {
                step: self.log.len(),
                kind,
                solver_t: f64::NAN,
                t: f64::NAN,
                accepted: false,
                iterations: 0,
                time: start.elapsed(),
            });
            return Ok(());
        };
        let check = self.bmi.check(&it, self.options)?;
        it.t = check.max_eigenvalue;
        let accepted = it.t < self.best_t();
        if accepted {
            self.best = Some(it);
            self.best_check = Some(check);
        }
        self.log.push(StepRecord {
            step: self.log.len(),
            kind,
            solver_t,
            t: check.max_eigenvalue,
            accepted,
            iterations,
            time: start.elapsed(),
        });
        // The Remark 6 re-verification is what certifies the observer; it is run whenever (44)
        // holds at the vertices (the remainder is accounted for in `check.certified` and, for the
        // observer, by the rigorous re-verification itself).
        if accepted && check.max_eigenvalue + check.rounding < 0.0 && check.min_g_entry >= 0.0 {
            let best = self.best.as_ref().expect("accepted");
            let gamma = gamma_of_gain(self.plant, best.l.as_ref())?;
            let a = analyse(
                self.a_bar,
                gamma.as_ref(),
                self.window,
                &self.options.analysis,
            )?;
            self.done = a.certified;
            self.reverification = Some(a);
        }
        Ok(())
    }

    fn finish(self, vertices: usize, remainder: f64) -> Result<Design, Error> {
        let (Some(best), Some(check)) = (self.best, self.best_check) else {
            return Err(Error::SolverInconclusive {
                steps: self.log.len(),
            });
        };
        let steps = self.log.len();
        // A run cut by the time budget stopped because its solves were interrupted, not because
        // the value stalled: its best value is no verdict.
        let stop = if !self.done && sporadic_sdp::budget::exhausted() {
            Stop::Budget("the time budget")
        } else {
            self.stop
        };
        let status = if self.done {
            DesignStatus::Certified
        } else if !(check.max_eigenvalue + check.rounding < 0.0) {
            DesignStatus::NotCertified(match stop {
                Stop::Stalled => NotCertified::Infeasible {
                    best_t: check.max_eigenvalue,
                    remainder_effect: check.remainder_effect,
                    rounding: check.rounding,
                    steps,
                },
                Stop::Budget(limit) => NotCertified::BudgetExhausted {
                    best_t: check.max_eigenvalue,
                    steps,
                    limit,
                },
            })
        } else {
            let a = self.reverification.as_ref();
            DesignStatus::NotCertified(NotCertified::VerificationFailed {
                best_t: check.max_eigenvalue,
                tau: a.filter(|a| !a.grid.certified).map(|a| a.grid.at),
                detail: a.map_or("not run".into(), |a| {
                    format!(
                        "polytope {} (vertex margin {:.3e}), grid bound {:.3e}",
                        a.polytope_certified, a.vertex_margin, a.grid.bound
                    )
                }),
            })
        };
        Ok(Design {
            status,
            l: best.l,
            g1: best.g1,
            g2: best.g2,
            f: best.f,
            p: best.p,
            bmi: check,
            reverification: self.reverification,
            vertices,
            remainder,
            log: self.log,
        })
    }
}
