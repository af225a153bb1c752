//! Theorem 1 of Rabehi et al. (2021): for a given gain `L`, find `P = Pᵀ ≻ 0` with
//!
//! ```text
//! (19)   Γ(L)ᵀ e^{Āᵀμ} P e^{Āμ} Γ(L) − P ≺ 0    for every μ ∈ [τmin, τmax].
//! ```
//!
//! **SDP over the Taylor polytope.** For a fixed μ, (19) with `P ≻ 0` is equivalent (Schur
//! complement) to
//!
//! ```text
//! Q(M) = [[P, ΓᵀMᵀP], [PMΓ, P]] ≻ 0,     M = e^{Āμ},
//! ```
//!
//! which is affine in `M`; so `Q(M_i) ≻ 0` at the vertices `M_i` of [`crate::polytope`] gives
//! `Q ≻ 0` on their hull. The remainder `e^{Āμ} = Σ w_i M_i + Δ`, `‖Δ‖_F ≤ δ`, perturbs `Q` by
//! `[[0, ΓᵀΔᵀP], [PΔΓ, 0]]` of norm `≤ ‖P‖₂‖Γ‖₂δ`: the polytope certificate is accepted only if
//! `min_i λmin(Q(M_i)) > ‖P‖₂‖Γ‖₂δ`, every `λmin` being recomputed in `f64` from the returned `P`.
//! The LMIs are homogeneous in `P`, so margin maximisation under `‖P‖₂ ≤ 1` loses no generality
//! (`sporadic_sdp::lmi::Model::feasibility`).
//!
//! **Independent re-verification.** The `P` found is then checked on a dense μ-grid with a
//! rigorous bound between grid points ([`crate::verify`]); an analysis is *certified* only if both
//! checks pass.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_square_finite;
use sporadic_sdp::lmi::{Expr, FeasibilityOptions, Model, Outcome};

use crate::error::Error;
use crate::ipr::{MetzlerDecomposition, gamma_of_gain};
use crate::polytope::{PolytopeOptions, norm2, taylor_polytope};
use crate::system::Plant;
use crate::verify::{GridCheck, GridOptions, verify_theorem1};
use sporadic_model::SamplingWindow;

/// Settings of the Theorem 1 analysis.
#[derive(Debug, Clone, Default)]
pub struct AnalysisOptions {
    /// Construction of the Taylor polytope.
    pub polytope: PolytopeOptions,
    /// Grid re-verification.
    pub grid: GridOptions,
    /// Margin-maximisation settings of the LMI layer (solver tolerances, verification safety
    /// factor); the defaults normalise `‖P‖₂ ≤ 1`.
    pub feasibility: FeasibilityOptions,
}

/// Outcome of the Theorem 1 analysis of one jump matrix on one window.
#[derive(Debug, Clone)]
pub struct Analysis {
    /// Both the polytope certificate and the grid re-verification hold.
    pub certified: bool,
    /// The Lyapunov matrix `P` returned by the SDP (normalised, `‖P‖₂ ≤ 1`).
    pub p: Mat<f64>,
    /// Optimal common margin `t*` of the SDP (`Q(M_i) ⪰ t*I`).
    pub margin: Option<f64>,
    /// `min_i λmin(Q(M_i))` recomputed in `f64`.
    pub vertex_margin: f64,
    /// `‖P‖₂‖Γ‖₂δ`: what the Taylor remainder may take away from `vertex_margin`.
    pub remainder_effect: f64,
    /// Whether `vertex_margin > remainder_effect` (with a rounding allowance).
    pub polytope_certified: bool,
    /// Number of polytope vertices.
    pub vertices: usize,
    /// Taylor remainder bound `δ`.
    pub remainder: f64,
    /// Grid re-verification of (19) with this `P`.
    pub grid: GridCheck,
    /// The LMI layer's explanation of its verdict.
    pub reason: String,
}

/// Analyses (19) for the jump matrix `gamma` of the error flow `a_bar` (any pair of equal order:
/// `(Ā, Γ(L))`, or the decoupled blocks `(S, |G|)` and `(A, G)`).
///
/// # Errors
/// Bad shapes or non-finite input, invalid options, or a failure of a numerical kernel or of the
/// LMI layer. An infeasible LMI is not an error: it gives `certified = false`.
pub fn analyse(
    a_bar: MatRef<'_, f64>,
    gamma: MatRef<'_, f64>,
    window: &SamplingWindow,
    options: &AnalysisOptions,
) -> Result<Analysis, Error> {
    let n = check_square_finite(a_bar, "A-bar")?;
    let k = check_square_finite(gamma, "Gamma")?;
    if k != n {
        return Err(InputError::mismatch("order of Gamma (= order of A-bar)", n, k).into());
    }
    let poly = taylor_polytope(a_bar, window, &options.polytope)?;
    let delta = poly.remainder_bound();
    let mut m = Model::new();
    let p = m.symmetric("P", n);
    let products: Vec<Mat<f64>> = poly.vertices().iter().map(|v| v * gamma).collect();
    for (i, mg) in products.iter().enumerate() {
        let q = Expr::sym_blocks(&[
            vec![Some(p.expr()), None],
            vec![Some(&p * mg), Some(p.expr())],
        ]);
        m.constrain(q.gt(0.0).named(format!("Q_{}", i + 1)))?;
    }
    let sol = m.feasibility(&options.feasibility)?;
    let pv = sol.value(&p)?;
    let pv = Mat::from_fn(n, n, |i, j| 0.5 * (pv[(i, j)] + pv[(j, i)]));
    let mut vertex_margin = f64::INFINITY;
    let mut scale: f64 = 0.0;
    for mg in &products {
        let pm = &pv * mg;
        let q = Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
            (true, true) => pv[(i, j)],
            (false, false) => pv[(i - n, j - n)],
            (false, true) => pm[(i - n, j)],
            (true, false) => pm[(j - n, i)],
        });
        scale = scale.max(q.norm_max());
        vertex_margin = vertex_margin.min(sporadic_linalg::min_eigenvalue(q.as_ref())?);
    }
    let remainder_effect = norm2(pv.as_ref())? * norm2(gamma)? * delta;
    let rounding = 1e-12 * (1.0 + scale);
    let feasible = sol.outcome == Outcome::Feasible && sol.margin.is_some_and(|t| t > 0.0);
    let polytope_certified = feasible && vertex_margin > remainder_effect + rounding;
    let grid = verify_theorem1(a_bar, gamma, pv.as_ref(), window, &options.grid)?;
    Ok(Analysis {
        certified: polytope_certified && grid.certified,
        p: pv,
        margin: sol.margin,
        vertex_margin,
        remainder_effect,
        polytope_certified,
        vertices: products.len(),
        remainder: delta,
        grid,
        reason: sol.reason,
    })
}

/// Theorem 1 for a gain `L` of `plant`: [`analyse`] with `(Ā, Γ(L))`.
///
/// # Errors
/// As [`analyse`], plus `L` not `n × p` or not finite.
pub fn analyse_gain(
    plant: &Plant,
    window: &SamplingWindow,
    l: MatRef<'_, f64>,
    options: &AnalysisOptions,
) -> Result<Analysis, Error> {
    let decomposition = MetzlerDecomposition::new(plant.a())?;
    let gamma = gamma_of_gain(plant, l)?;
    analyse(
        decomposition.a_bar.as_ref(),
        gamma.as_ref(),
        window,
        options,
    )
}
