//! Step 2 of the §5.3 algorithm: the synthesis SDP (47) on finite sets `T_σ ⊂ [T_mσ, T_Mσ]`, and the
//! strict-feasibility (margin) form of the design LMIs (23)/(44).
//!
//! ```text
//! minimise p_M  over P_σ ∈ Sⁿ (σ = 1..N), p_M
//! s.t. Ξ_σ(τ) ⪰ 2μ I   ∀σ, ∀τ ∈ T_σ,          I ⪯ P_σ ⪯ p_M I   ∀σ                           (47)
//! ```
//!
//! with `Ξ_σ(τ) = [C_σ^⊥ᵀ E(τ)ᵀ P_σ E(τ) C_σ^⊥, ⋆; P_Γ(σ) C_σ^⊥, P_Γ(σ)]`, `E(τ) = e^{−Aτ}` (44). For a
//! fixed τ the block is linear in `(P_σ, P_Γ)`: its top-left is the congruence `Gᵀ P_σ G` with the
//! constant `G = E(τ) C_σ^⊥`. The model is compiled once ([`sporadic_sdp::lmi::Compiled`]) and every
//! new τ̄ of (50) is appended as one more block; the optimal value p* is unique (the optimiser is not).
//! Infeasibility of (47) certifies infeasibility of (44): (47) relaxes "Ξ ⪰ 2μI on the whole window",
//! and by homogeneity any strict solution of (44) can be scaled into (47).

use sporadic_linalg::InputError;
use sporadic_model::SolverStats;

use faer::Mat;
use sporadic_linalg::expm_scaled;
use sporadic_sdp::lmi::{
    Compiled, Constraint, Expr, FeasibilityOptions, LmiSolution, Model, Outcome, SolveOptions, Var,
};
use sporadic_sdp::{Settings, Status};

use crate::error::Error;
use crate::plant::{RoundRobinPlant, window_contains};

/// Solver options used for the small SDPs of this crate: relative gap `1e-7` (p* to about seven
/// digits), relative infeasibility `1e-8` (the margin μ ≥ 1e-3 dwarfs the resulting constraint error)
/// and a single thread (the problems are tiny).
pub fn default_solve_options() -> SolveOptions {
    let settings = Settings {
        tol_gap: 1e-7,
        tol_feas: 1e-8,
        threads: 1,
        ..Settings::default()
    };
    SolveOptions {
        settings,
        ..SolveOptions::default()
    }
}

/// The block `Ξ_σ(τ)` of (44) as an affine expression in the model's `P_1, …, P_N`.
///
/// # Errors
/// A failing exponential or an index out of range.
pub fn xi_expr(plant: &RoundRobinPlant, p: &[Var], sigma: usize, tau: f64) -> Result<Expr, Error> {
    let g = top_factor(plant, p, sigma, tau)?;
    let cp = plant.sensor(sigma)?.c_perp().to_owned();
    Ok(xi_blocks(plant, p, sigma, &g, &cp))
}

/// `G = E(τ)C_σ^⊥`, the factor of the upper-left block `GᵀP_σG` of `Ξ_σ(τ)`.
fn top_factor(
    plant: &RoundRobinPlant,
    p: &[Var],
    sigma: usize,
    tau: f64,
) -> Result<Mat<f64>, Error> {
    let sensor = plant.sensor(sigma)?;
    if p.len() != plant.num_sensors() {
        return Err(InputError::mismatch("number of P_σ", plant.num_sensors(), p.len()).into());
    }
    if !tau.is_finite() {
        return Err(InputError::non_finite("τ").into());
    }
    Ok(expm_scaled(plant.a(), -tau)? * sensor.c_perp())
}

/// `[gᵀP_σg, ⋆; P_Γ c, P_Γ]`: `Ξ_σ(τ)` for `g = G`, `c = C_σ^⊥`, and its congruence
/// `diag(F, I)ᵀΞ_σ(τ)diag(F, I)` for `g = GF`, `c = C_σ^⊥F`.
fn xi_blocks(plant: &RoundRobinPlant, p: &[Var], sigma: usize, g: &Mat<f64>, c: &Mat<f64>) -> Expr {
    let nx = &p[plant.next(sigma)];
    let top = g.transpose() * &p[sigma] * g;
    let off = nx * c.clone();
    Expr::sym_blocks(&[[Some(top), None], [Some(off), Some(nx.expr())]])
}

/// Scale `‖E(τ)C_σ^⊥‖_F²` above which [`xi_constraint`] scales a block (`2²⁰`).
///
/// Below it the blocks are left as they are, since the solver copes with such spreads: on the
/// fuzzed plant of [`xi_constraint`] the SDP was optimal in 11–13 iterations up to block norms
/// of `10³`, in 20 at `4·10⁵`, in 28 at `4·10⁷`, almost optimal after 50 at `8·10⁸`, and in
/// numerical trouble beyond. Scaling blocks of moderate scale is not neutral, because `P*` of
/// (47) is not unique (`p*` is) and which optimiser the solver returns decides borderline
/// validations of the §5.3 loop: scaling every block above `2¹⁰` made the proof of (48) on
/// the cart-pole of the issue-22 tests (block scales up to `4.4·10³`) inconclusive, and
/// scaling every block above one made the suspension example of §6 (up to `5.3·10³`) validate
/// at `μ = 0.1` after 1 iteration instead of 2 (an independent implementation needs 2). (These
/// figures were measured with the earlier scalar scaling of a block; the congruence of
/// [`xi_constraint`] keeps the same threshold, so the blocks below it are unchanged.)
const SCALE_FROM: f64 = 1048576.0;

/// The constraint `Ξ_σ(τ) ⪰ 2μI` of (47); when `‖G‖_F²` (`G = E(τ)C_σ^⊥`) is above
/// [`SCALE_FROM`], in the congruent form `diag(F, I)ᵀ(Ξ_σ(τ) − 2μI)diag(F, I) ⪰ 0` with
/// `F = V diag(min(1, 1/s_i))` from the SVD `G = WSVᵀ` (the same constraint: a congruence by
/// a nonsingular matrix keeps the feasible set; the products `GF` and `C_σ^⊥F` are rounded, an
/// `ε`-level perturbation of the data that the validation (48) of the result covers), i.e.
/// `[(GF)ᵀP_σ(GF), ⋆; P_ΓC_σ^⊥F, P_Γ] ⪰ 2μ diag(FᵀF, I)`: every direction in which `G` has grown
/// beyond one is brought back to one, the others are left alone.
///
/// `‖E(τ)‖ = ‖e^{−Aτ}‖` grows like `e^{βτ}`, so on a long window the blocks at large τ carry
/// data up to `10¹⁰` times that of the others, and the interior-point iterations from the
/// solver's default point stalled at steps of `10⁻⁸`–`10⁻²` (a fuzzed stable plant of order 6,
/// three outputs, `T2 ≥ 1.05`: `numerical_trouble` in 4–20 iterations; CSDP 6.2 needs 23–25
/// and reaches only reduced accuracy on two of three). Multiplying such a block by `2^{−k}`
/// (`2^k ≈ ‖G‖_F²`, an earlier form) made the same SDPs optimal in 11 iterations, but it
/// scales `P_Γ` and the margin `2μ` down with the growing directions: the solver's relative
/// accuracy then bounds the error of `λ_min(Ξ_σ(τ))` only by `10⁻⁸·‖G‖²`, and on a fuzzed
/// plant of order 6 (fuzz seed 17, plant 7, `T_M = 3.2`, `‖G‖² ≈ 10⁷`) the optimiser of (47)
/// missed `Ξ_σ(T_M) ⪰ 2μI` by `0.036`, which the proof of (48) then refuted, and the loop ran
/// (49) grids of 3·10⁸ points. The congruence scales only the top-left block's directions, so
/// the margin keeps its meaning relative to `P_Γ`.
fn xi_constraint(
    plant: &RoundRobinPlant,
    p: &[Var],
    sigma: usize,
    tau: f64,
    mu: f64,
) -> Result<Constraint, Error> {
    let g = top_factor(plant, p, sigma, tau)?;
    let cp = plant.sensor(sigma)?.c_perp().to_owned();
    let scale = g.norm_l2().powi(2);
    if !(scale > SCALE_FROM && scale.is_finite()) {
        return Ok(xi_blocks(plant, p, sigma, &g, &cp)
            .ge(2.0 * mu)
            .named(constraint_name(sigma, tau)));
    }
    let svd = g
        .thin_svd()
        .map_err(|_| Error::numerical("the SVD of E(τ)C^⊥ did not converge"))?;
    let (s, v) = (svd.S().column_vector(), svd.V());
    let (r, n) = (g.ncols(), plant.n());
    let f = Mat::from_fn(r, r, |i, j| v[(i, j)] * (1.0 / s[j]).min(1.0));
    let ftf = f.transpose() * &f;
    let rhs = Mat::from_fn(r + n, r + n, |i, j| {
        2.0 * mu
            * match (i < r, j < r) {
                (true, true) => ftf[(i, j)],
                _ => f64::from(u8::from(i == j)),
            }
    });
    Ok(xi_blocks(plant, p, sigma, &(&g * &f), &(&cp * &f))
        .ge(Expr::constant(rhs.as_ref()))
        .named(constraint_name(sigma, tau)))
}

fn constraint_name(sigma: usize, tau: f64) -> String {
    format!("Ξ_{}({tau:.9})", sigma + 1)
}

/// Result of one solve of (47).
#[derive(Debug, Clone)]
pub struct SynthesisResult {
    /// `P_1*, …, P_N*`.
    pub p: Vec<Mat<f64>>,
    /// Optimal value p* (unique).
    pub p_star: f64,
    /// Statistics of the solve (decision scalars: the `N` symmetric `P_σ` and `p_M`).
    pub stats: SolverStats,
}

impl SynthesisResult {
    /// Whether the solver reached its tolerances ([`Status::Optimal`]); `false` when a verified
    /// feasible point was accepted after a stall (see [`ACCEPT_GAP`]).
    pub fn optimal(&self) -> bool {
        matches!(self.stats.status, Status::Optimal)
    }
}

/// When the interior-point method stalls (`NumericalTrouble`/`MaxIterations`) at a point that passes the
/// LMI layer's independent verification with relative gap below this value, the point is accepted
/// (its p_M is an upper bound of p* within this relative gap). The synthesis only needs a feasible P;
/// p* enters the grid spacing (49), where an upper bound errs on the safe side (finer grid).
pub const ACCEPT_GAP: f64 = 1e-5;

/// The synthesis SDP (47), compiled once and re-solved as points are added.
pub struct Synthesis {
    compiled: Compiled,
    p: Vec<Var>,
    p_max: Var,
    mu: f64,
    points: Vec<Vec<f64>>,
    decision_scalars: usize,
}

impl std::fmt::Debug for Synthesis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Synthesis")
            .field("mu", &self.mu)
            .field("points", &self.points)
            .finish()
    }
}

impl Synthesis {
    /// Builds (47) with the initial sets `T_σ = {T_mσ, T_Mσ}` (`{T_σ}` for a jitter-free sensor).
    ///
    /// # Errors
    /// `μ ≤ 0` or non-finite, or a modelling error.
    pub fn new(plant: &RoundRobinPlant, mu: f64, options: &SolveOptions) -> Result<Self, Error> {
        if !(mu > 0.0 && mu.is_finite()) {
            return Err(InputError::parameter("mu", mu, "must be positive and finite").into());
        }
        let n = plant.n();
        let mut m = Model::new();
        let p: Vec<Var> = (0..plant.num_sensors())
            .map(|s| m.symmetric(&format!("P_{}", s + 1), n))
            .collect();
        let p_max = m.scalar("p_M");
        let mut points = Vec::with_capacity(plant.num_sensors());
        for (s, sensor) in plant.sensors().iter().enumerate() {
            let w = sensor.window();
            let set = if w.is_periodic() {
                vec![w.t1()]
            } else {
                vec![w.t1(), w.t2()]
            };
            for &tau in &set {
                m.constrain(xi_constraint(plant, &p, s, tau, mu)?)?;
            }
            points.push(set);
        }
        for (s, ps) in p.iter().enumerate() {
            m.constrain(ps.ge(1.0).named(format!("P_{} ⪰ I", s + 1)))?;
            m.constrain(ps.le(&p_max).named(format!("P_{} ⪯ p_M I", s + 1)))?;
        }
        m.minimize(&p_max)?;
        let compiled = m.compile(options)?;
        Ok(Self {
            compiled,
            decision_scalars: plant.num_sensors() * n * (n + 1) / 2 + 1,
            p,
            p_max,
            mu,
            points,
        })
    }

    /// The current sets `T_σ`.
    pub fn points(&self) -> &[Vec<f64>] {
        &self.points
    }

    /// The margin μ.
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// Appends `Ξ_σ(τ) ⪰ 2μI` for a new point τ of sensor `sigma` (0-based).
    ///
    /// # Errors
    /// τ outside the window, index out of range, or a modelling error.
    pub fn add_point(
        &mut self,
        plant: &RoundRobinPlant,
        sigma: usize,
        tau: f64,
    ) -> Result<(), Error> {
        if !window_contains(plant.sensor(sigma)?.window(), tau) {
            return Err(Error::invalid(format!(
                "τ = {tau} is not in the window of sensor {}",
                sigma + 1
            )));
        }
        self.compiled
            .add(xi_constraint(plant, &self.p, sigma, tau, self.mu)?)?;
        self.points[sigma].push(tau);
        Ok(())
    }

    /// Solves (47).
    ///
    /// # Errors
    /// [`Error::Infeasible`] on a solver certificate (then (44) is infeasible), [`Error::SolverFailed`]
    /// when the solver neither converged nor certified infeasibility.
    pub fn solve(&mut self) -> Result<SynthesisResult, Error> {
        let sol = self.compiled.solve()?;
        let stalled = matches!(
            sol.sdp.status,
            Status::NumericalTrouble | Status::MaxIterations
        );
        let accept = sol.outcome == Outcome::Inconclusive
            && stalled
            && sol.verification.passed()
            && sol.sdp.measures.rel_gap <= ACCEPT_GAP;
        if !accept {
            check_outcome(&sol, "the synthesis SDP (47)")?;
        }
        let p = self
            .p
            .iter()
            .map(|v| sol.value(v))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(SynthesisResult {
            p,
            p_star: sol.scalar(&self.p_max)?,
            stats: SolverStats::of(&sol, self.decision_scalars),
        })
    }
}

/// Maps an [`LmiSolution`] outcome to `Ok` (feasible and optimal) or a typed error.
pub(crate) fn check_outcome(sol: &LmiSolution, what: &str) -> Result<(), Error> {
    match sol.outcome {
        Outcome::Feasible => Ok(()),
        Outcome::Infeasible => Err(Error::Infeasible {
            what: format!("{what}: {}", sol.reason),
        }),
        _ => Err(Error::SolverFailed {
            what: what.to_owned(),
            status: format!("{} ({})", sol.sdp.status.as_str(), sol.reason),
        }),
    }
}

/// Strict feasibility of the design LMI (44) on the finite sets `points[σ]` (for a jitter-free plant
/// with `points[σ] = {T_σ}` this is (23)): maximal common margin `t*` with `Ξ_σ(τ) ⪰ t I` and
/// `P_σ ⪰ t I` under `‖P_σ‖₂ ≤ 1`. The model is homogeneous, so it is strictly feasible iff `t* > 0`
/// (decided with the LMI layer's verification rule: [`Outcome`]).
///
/// # Errors
/// Bad `points` or a modelling error.
pub fn design_margin(
    plant: &RoundRobinPlant,
    points: &[Vec<f64>],
    options: &FeasibilityOptions,
) -> Result<(LmiSolution, Vec<Var>), Error> {
    if points.len() != plant.num_sensors() {
        return Err(InputError::mismatch(
            "number of point sets",
            plant.num_sensors(),
            points.len(),
        )
        .into());
    }
    let n = plant.n();
    let mut m = Model::new();
    let p: Vec<Var> = (0..plant.num_sensors())
        .map(|s| m.symmetric(&format!("P_{}", s + 1), n))
        .collect();
    let mut cons: Vec<Constraint> = Vec::new();
    for (s, set) in points.iter().enumerate() {
        for &tau in set {
            cons.push(
                xi_expr(plant, &p, s, tau)?
                    .gt(0.0)
                    .named(constraint_name(s, tau)),
            );
        }
    }
    for (s, ps) in p.iter().enumerate() {
        cons.push(ps.gt(0.0).named(format!("P_{} ≻ 0", s + 1)));
    }
    for c in cons {
        m.constrain(c)?;
    }
    Ok((m.feasibility(options)?, p))
}
