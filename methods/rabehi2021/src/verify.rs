//! Embedding-independent verification of the condition of Theorem 1 (Rabehi et al. 2021, (19)):
//!
//! ```text
//! Φ(μ) = Γᵀ e^{Āᵀμ} P e^{Āμ} Γ − P ≺ 0     for every μ ∈ [τmin, τmax],
//! ```
//!
//! on a dense uniform μ-grid (`e^{Āμ}` by `sporadic_linalg::expm_stepper`), closed by a rigorous
//! bound between grid points: with `E(μ) = e^{Āμ}`, `dΦ/dμ = Γᵀ(EᵀĀᵀPE + EᵀPĀE)Γ`, so
//! `‖dΦ/dμ‖₂ ≤ 2‖Γ‖₂²‖Ā‖₂‖P‖₂ max‖E‖₂²`, and every μ is within `h/2` of a grid point μ_k where
//! `‖E(μ)‖₂ ≤ ‖E(μ_k)‖₂ e^{‖Ā‖₂h/2}`. Hence
//!
//! ```text
//! max_μ λmax(Φ(μ)) ≤ max_k λmax(Φ(μ_k)) + (h/2)·2‖Γ‖²‖Ā‖‖P‖·max_k‖E(μ_k)‖²·e^{‖Ā‖h}.
//! ```
//!
//! The grid is refined (doubled) until this bound is negative, the grid maximum itself is
//! non-negative (a counterexample), or a point budget is exhausted. The spectral radius of
//! `e^{Āμ}Γ` (Remark 5: (19) forces it below 1) is reported alongside.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_square_finite;
use sporadic_linalg::{expm_stepper, max_eigenvalue, spectral_radius, sym_part};

use crate::error::Error;
use crate::polytope::norm2;
use sporadic_model::SamplingWindow;

/// Settings of the grid verification.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridOptions {
    /// Initial number of grid points (at least 2). Default 1001.
    pub points: usize,
    /// Largest number of points after refinement. Default 65 537.
    pub max_points: usize,
    /// Also compute the spectral radius of `e^{Āμ}Γ` at every grid point. Default `true`.
    pub spectral_radius: bool,
}

impl Default for GridOptions {
    fn default() -> Self {
        Self {
            points: 1001,
            max_points: 65_537,
            spectral_radius: true,
        }
    }
}

/// Result of the grid verification of (19).
#[derive(Debug, Clone, PartialEq)]
pub struct GridCheck {
    /// Number of grid points of the final (finest) grid.
    pub points: usize,
    /// `max_k λmax(Φ(μ_k))`.
    pub max_eigenvalue: f64,
    /// Where it is attained.
    pub at: f64,
    /// The bound on the variation of `λmax(Φ)` between grid points (module docs).
    pub slack: f64,
    /// `max_eigenvalue + slack`: an upper bound on `max_μ λmax(Φ(μ))` over the whole window.
    pub bound: f64,
    /// Whether `bound < 0`: (19) holds on the whole window (up to rounding of the eigenvalue
    /// computations, ≈ 1e-15 relative).
    pub certified: bool,
    /// `max_k ρ(e^{Āμ_k}Γ)` (`NaN` when not computed).
    pub max_spectral_radius: f64,
    /// Where it is attained.
    pub radius_at: f64,
    /// `max_k ‖e^{Āμ_k}‖₂`.
    pub max_exp_norm: f64,
}

fn check_operands(
    a_bar: MatRef<'_, f64>,
    gamma: MatRef<'_, f64>,
    p: MatRef<'_, f64>,
) -> Result<usize, Error> {
    let n = check_square_finite(a_bar, "A-bar")?;
    for (m, what) in [(gamma, "Gamma"), (p, "P")] {
        let k = check_square_finite(m, what)?;
        if k != n {
            return Err(
                InputError::mismatch(format!("order of {what} (= order of A-bar)"), n, k).into(),
            );
        }
    }
    Ok(n)
}

/// One pass over a grid of `points` points.
fn pass(
    a_bar: MatRef<'_, f64>,
    gamma: MatRef<'_, f64>,
    p: MatRef<'_, f64>,
    window: &SamplingWindow,
    points: usize,
    radius: bool,
) -> Result<GridCheck, Error> {
    let n = a_bar.nrows();
    let grid = crate::system::window_grid(window, points);
    let h = if grid.len() > 1 {
        (window.t2() - window.t1()) / (grid.len() - 1) as f64
    } else {
        0.0
    };
    let mut stepper = expm_stepper(a_bar, window.t1(), h, grid.len() - 1)?;
    let mut e = Mat::<f64>::zeros(n, n);
    let mut out = GridCheck {
        points: grid.len(),
        max_eigenvalue: f64::NEG_INFINITY,
        at: window.t1(),
        slack: 0.0,
        bound: f64::NAN,
        certified: false,
        max_spectral_radius: if radius { 0.0 } else { f64::NAN },
        radius_at: window.t1(),
        max_exp_norm: 0.0,
    };
    for &mu in &grid {
        if stepper.next_into(e.as_mut()).is_none() {
            return Err(match stepper.error() {
                Some(err) => err.clone().into(),
                None => InputError::non_finite(format!("e^(A-bar mu) at mu = {mu}")).into(),
            });
        }
        let eg = &e * gamma;
        let phi = eg.transpose() * p * &eg - p;
        let lam = max_eigenvalue(sym_part(phi.as_ref())?.as_ref())?;
        if lam > out.max_eigenvalue {
            out.max_eigenvalue = lam;
            out.at = mu;
        }
        out.max_exp_norm = out.max_exp_norm.max(norm2(e.as_ref())?);
        if radius {
            let r = spectral_radius(eg.as_ref())?;
            if r > out.max_spectral_radius {
                out.max_spectral_radius = r;
                out.radius_at = mu;
            }
        }
    }
    let a_norm = norm2(a_bar)?;
    let lipschitz = 2.0
        * norm2(gamma)?.powi(2)
        * a_norm
        * norm2(p)?
        * out.max_exp_norm.powi(2)
        * (a_norm * h).exp();
    // Rounded up generously (the norms themselves carry relative errors of a few ulp).
    out.slack = 0.5 * h * lipschitz * (1.0 + 1e-10);
    out.bound = out.max_eigenvalue + out.slack;
    out.certified = out.bound < 0.0;
    Ok(out)
}

/// Verifies (19) for `(Ā, Γ, P)` on `window` (see the module docs).
///
/// # Errors
/// Bad shapes or non-finite input, `options.points < 2`, or a failure of the matrix exponential
/// or of an eigenvalue computation.
pub fn verify_theorem1(
    a_bar: MatRef<'_, f64>,
    gamma: MatRef<'_, f64>,
    p: MatRef<'_, f64>,
    window: &SamplingWindow,
    options: &GridOptions,
) -> Result<GridCheck, Error> {
    check_operands(a_bar, gamma, p)?;
    if options.points < 2 {
        return Err(
            InputError::parameter("grid points", options.points as f64, "need at least 2").into(),
        );
    }
    let mut points = options.points;
    loop {
        let check = pass(a_bar, gamma, p, window, points, options.spectral_radius)?;
        let refined = 2 * points - 1;
        if check.certified || check.max_eigenvalue >= 0.0 || refined > options.max_points {
            return Ok(check);
        }
        points = refined;
    }
}
