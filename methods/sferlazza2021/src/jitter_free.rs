//! The jitter-free case (§4): design LMI (23) with gains (24), analysis LMI (18) for given gains, and
//! the monodromy matrix (19) as an independent check.
//!
//! With constant intervals `T_σ` the error sampled after each jump of sensor N evolves by
//! `J_1 = (I − K̄_N C_N) e^{AT_N} ⋯ (I − K̄_1 C_1) e^{AT_1}` (19): the observer achieves Goal 1 iff
//! `ρ(J_1) < 1`, iff (18) is feasible (Proposition 3); and an observer exists iff (23) is feasible,
//! iff `(C, e^{AT})` is detectable (Propositions 1 and 4, [`crate::detectability`]). (23) is (44)
//! with the single point `T_σ`, so the design reuses [`crate::synthesis`].

use faer::Mat;
use sporadic_linalg::InputError;
use sporadic_linalg::{expm_scaled, spectral_radius};
use sporadic_sdp::lmi::{Expr, FeasibilityOptions, LmiSolution, Model, SolveOptions, Var};

use crate::error::Error;
use crate::gain::{gain, jump_matrix};
use crate::plant::RoundRobinPlant;
use crate::synthesis::{Synthesis, design_margin};
use crate::validation::XiFamily;

/// The constant intervals `T_σ` of a jitter-free plant.
///
/// # Errors
/// [`Error::InvalidArgument`] if some window has jitter (use [`RoundRobinPlant::with_windows`]).
pub fn intervals(plant: &RoundRobinPlant) -> Result<Vec<f64>, Error> {
    if !plant.is_jitter_free() {
        return Err(Error::invalid(
            "the plant has jitter: pick T_σ with RoundRobinPlant::with_windows first",
        ));
    }
    Ok(plant.sensors().iter().map(|s| s.window().t1()).collect())
}

/// The monodromy matrix `J_1` of (19) for gains `K̄_σ` and intervals `T_σ` (sensor order).
///
/// # Errors
/// Wrong number or shape of gains/intervals, or a failing exponential.
pub fn monodromy(
    plant: &RoundRobinPlant,
    gains: &[Mat<f64>],
    intervals: &[f64],
) -> Result<Mat<f64>, Error> {
    let (n, n_s) = (plant.n(), plant.num_sensors());
    if gains.len() != n_s || intervals.len() != n_s {
        return Err(InputError::mismatch(
            "number of gains/intervals",
            n_s,
            gains.len().min(intervals.len()),
        )
        .into());
    }
    let mut j = Mat::<f64>::identity(n, n);
    for (s, ((k, &t), sensor)) in gains.iter().zip(intervals).zip(plant.sensors()).enumerate() {
        let c = sensor.c();
        if k.nrows() != n || k.ncols() != c.nrows() {
            return Err(InputError::mismatch(
                format!("shape of K̄_{}", s + 1),
                n * c.nrows(),
                k.nrows() * k.ncols(),
            )
            .into());
        }
        j = jump_matrix(k.as_ref(), c) * expm_scaled(plant.a(), t)? * &j;
    }
    Ok(j)
}

/// Result of the jitter-free design (Theorem 2).
#[derive(Debug, Clone)]
pub struct JitterFreeDesign {
    /// `P_1, …, P_N` solving (23) (as the minimiser of (47) with `T_σ = {T_σ}`).
    pub p: Vec<Mat<f64>>,
    /// Optimal value of (47).
    pub p_star: f64,
    /// Gains `K̄_σ` of (24).
    pub gains: Vec<Mat<f64>>,
    /// `ρ(J_1)` with these gains (< 1 by Theorem 2; checked).
    pub spectral_radius: f64,
    /// `λ_min(Ξ_σ(T_σ))` of (23) at the returned `P_σ`, recomputed with fresh exponentials
    /// (checked `> μ`, half the margin `2μ` imposed in the SDP).
    pub min_xi_eigenvalue: Vec<f64>,
}

/// Jitter-free design: solve (23) in the form (47) with margin `mu` and select the gains (24).
///
/// The result is re-verified independently of the SDP: `λ_min(Ξ_σ(T_σ)) > μ` with freshly computed
/// exponentials (a safety factor 2 on the imposed margin `2μ`) and `ρ(J_1) < 1` for the gains (24)
/// (Theorem 2 / Proposition 3).
///
/// # Errors
/// A plant with jitter, `μ ≤ 0`, [`Error::Infeasible`] when (23) has no solution (then by
/// Proposition 4 no observer achieves Goal 1), a solver failure, or
/// [`Error::VerificationFailed`] when an a-posteriori check fails.
pub fn design(
    plant: &RoundRobinPlant,
    mu: f64,
    options: &SolveOptions,
) -> Result<JitterFreeDesign, Error> {
    let t = intervals(plant)?;
    let mut syn = Synthesis::new(plant, mu, options)?;
    let res = syn.solve()?;
    let gains = (0..plant.num_sensors())
        .map(|s| gain(plant, s, res.p[s].as_ref(), t[s]))
        .collect::<Result<Vec<_>, _>>()?;
    let min_xi_eigenvalue = (0..plant.num_sensors())
        .map(|s| XiFamily::new(plant, &res.p, s)?.min_eigenvalue(t[s]))
        .collect::<Result<Vec<_>, _>>()?;
    for (s, &l) in min_xi_eigenvalue.iter().enumerate() {
        if !(l > mu) {
            return Err(Error::VerificationFailed {
                what: format!(
                    "λ_min(Ξ_{}(T_{})) of (23) (must exceed μ = {})",
                    s + 1,
                    s + 1,
                    crate::error::sig4(mu)
                ),
                value: l,
            });
        }
    }
    let rho = spectral_radius(monodromy(plant, &gains, &t)?.as_ref())?;
    if !(rho < 1.0) {
        return Err(Error::VerificationFailed {
            what: "ρ(J_1) of the monodromy (19) with the gains (24) (must be < 1)".into(),
            value: rho,
        });
    }
    Ok(JitterFreeDesign {
        p: res.p,
        p_star: res.p_star,
        gains,
        spectral_radius: rho,
        min_xi_eigenvalue,
    })
}

/// Strict feasibility of (23) as a margin problem ([`design_margin`] on `{T_σ}`): the returned
/// solution's [`sporadic_sdp::lmi::Outcome`] decides, and the variables give `P_σ` for (24).
///
/// # Errors
/// A plant with jitter or a modelling error.
pub fn design_feasibility(
    plant: &RoundRobinPlant,
    options: &FeasibilityOptions,
) -> Result<(LmiSolution, Vec<Var>), Error> {
    let t = intervals(plant)?;
    design_margin(
        plant,
        &t.iter().map(|&x| vec![x]).collect::<Vec<_>>(),
        options,
    )
}

/// Analysis LMI (18) for given gains `K̄_σ`, as a margin problem: maximise `t` with
///
/// ```text
/// [ e^{−AᵀT_σ} P_σ e^{−AT_σ}    ⋆  ]
/// [ P_Γ (I − K̄_σ C_σ)          P_Γ ] ⪰ t I,   P_σ ⪰ t I,   ‖P_σ‖₂ ≤ 1.
/// ```
///
/// Homogeneous, so (18) is feasible iff `t* > 0`; by Proposition 3 iff `ρ(J_1) < 1`.
///
/// # Errors
/// A plant with jitter, wrong gains, or a modelling error.
pub fn analysis_feasibility(
    plant: &RoundRobinPlant,
    gains: &[Mat<f64>],
    options: &FeasibilityOptions,
) -> Result<LmiSolution, Error> {
    let t = intervals(plant)?;
    let (n, n_s) = (plant.n(), plant.num_sensors());
    if gains.len() != n_s {
        return Err(InputError::mismatch("number of gains", n_s, gains.len()).into());
    }
    let mut m = Model::new();
    let p: Vec<Var> = (0..n_s)
        .map(|s| m.symmetric(&format!("P_{}", s + 1), n))
        .collect();
    for (s, sensor) in plant.sensors().iter().enumerate() {
        let c = sensor.c();
        if gains[s].nrows() != n || gains[s].ncols() != c.nrows() {
            return Err(InputError::mismatch(
                format!("shape of K̄_{}", s + 1),
                n * c.nrows(),
                gains[s].nrows() * gains[s].ncols(),
            )
            .into());
        }
        let e = expm_scaled(plant.a(), -t[s])?;
        let nx = &p[plant.next(s)];
        let top = e.transpose() * &p[s] * &e;
        let off = nx * jump_matrix(gains[s].as_ref(), c);
        let blk = Expr::sym_blocks(&[[Some(top), None], [Some(off), Some(nx.expr())]]);
        m.constrain(blk.gt(0.0).named(format!("(18) σ = {}", s + 1)))?;
        m.constrain(p[s].gt(0.0).named(format!("P_{} ≻ 0", s + 1)))?;
    }
    Ok(m.feasibility(options)?)
}
