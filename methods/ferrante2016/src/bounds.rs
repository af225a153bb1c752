//! The constants of the exponential bound of Theorem 1 and of the ISS bound of Theorem 2
//! (Ferrante et al. 2016, §3), computed from a pair `(P, L)` satisfying condition (12).
//!
//! With `E(τ) = e^{Aτ}` and `Ψ(v) = (I − LM)' E(v)' P E(v) (I − LM)`:
//!
//! ```text
//! α1 = min_{τ∈[0,T2]} λmin(E(τ)'PE(τ))        (15)      α2 = max_{τ∈[0,T2]} λmax(E(τ)'PE(τ))   (16)
//! β  = min_{v∈[T1,T2]} λmin(P − Ψ(v))          largest β of (18)/(27)
//! θ  = ln(1 − β/α2)                           (19)
//! γ  = |θ|/(1+T2),  R = T2|θ|/(1+T2)          (20a), the natural (largest γ, smallest R) choice
//! ‖ε(t,j)‖ ≤ κ e^{−(γ/2)(t+j)} ‖ε(0,0)‖,  κ = √(α2/α1) e^{R/2}                     (21), corrected
//! ```
//!
//! The printed (21) has `e^{R/α1}` in place of `e^{R/2}`; the derivation
//! `α1‖ε‖² ≤ V ≤ e^{R−γ(t+j)} α2 ‖ε0‖²` gives `e^{R/2}`, which is what [`Theorem1Bound::kappa`] holds
//! (the printed variant is kept in [`Theorem1Bound::kappa_printed`] for comparison).
//!
//! Theorem 2 (noisy output `y = Mz + η`, jump `ε⁺ = (I − LM)ε − Lη`):
//!
//! ```text
//! θη = ln(1 − β/(2α2)),  γη = |θη|/(1+T2),  Rη = T2|θη|/(1+T2)
//! ρ  = ‖P‖ (2/β + ‖P‖) max_{v∈[T1,T2]} ‖e^{Av}‖²       as printed
//! ρd = ‖P‖ (1 + 2‖P‖/β) max_{v∈[T1,T2]} ‖e^{Av}‖²      what Young's inequality with ω = β/2 gives
//! (35): ‖ε(t,j)‖ ≤ max{ √(2α2/α1) e^{Rη/2} e^{−γη(t+j)/2} ‖ε0‖,  ‖L‖ √(4 ρ α2/(β α1)) ‖η‖_(t,j) }
//! ```
//!
//! (`2ρe^{−θη}/((e^{−θη}−1)α1) = 4ρα2/(βα1)` exactly.) The printed `ρ` is not homogeneous in `P`
//! (scaling `P` by `c` scales `ρ` by neither `c` nor `c²` consistently with `β`), so the ISS claims of
//! this crate use `ρd`; both values are reported. The two agree when `‖P‖ = 1`.
//!
//! The extrema over `τ`/`v` are analysis constants: dense grid plus a golden-section refinement of
//! the best grid cell, not rigorous global optimisation.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::symmetric::sym_part;
use sporadic_linalg::{max_eigenvalue, min_eigenvalue};

use crate::error::Error;
use crate::grid::{Sense, extremum};
use crate::system::Plant;
use sporadic_model::SamplingWindow;

/// Options of [`bound_constants`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundOptions {
    /// Number of grid points on `[0, T2]` (for `α1`, `α2`) and on `[T1, T2]` (for `β`,
    /// `max ‖e^{Av}‖²`) before the local refinement. Default 2001.
    pub grid_points: usize,
}

impl BoundOptions {
    /// Checks the options; the error names the offending field (`grid_points ≥ 2`).
    pub fn validate(&self) -> Result<(), Error> {
        if self.grid_points < 2 {
            return Err(InputError::parameter(
                "grid_points",
                self.grid_points as f64,
                "at least 2 grid points are needed",
            )
            .into());
        }
        Ok(())
    }
}

impl Default for BoundOptions {
    fn default() -> Self {
        Self { grid_points: 2001 }
    }
}

/// Constants of Theorem 1 (GES of `𝒜`) for a given `(P, L)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Theorem1Bound {
    /// `α1` of (15).
    pub alpha1: f64,
    /// Where `α1` is attained (`τ ∈ [0, T2]`).
    pub alpha1_at: f64,
    /// `α2` of (16).
    pub alpha2: f64,
    /// Where `α2` is attained (`τ ∈ [0, T2]`).
    pub alpha2_at: f64,
    /// The largest admissible `β` of (18): `min_v λmin(P − Ψ(v))` (capped to `α2/2` in the degenerate
    /// case `β ≥ α2`, see [`Theorem1Bound::beta_capped`]).
    pub beta: f64,
    /// Where the minimum defining `β` is attained (`v ∈ [T1, T2]`).
    pub beta_at: f64,
    /// Whether `β` had to be reduced to `α2/2` because the largest value reached `α2` (possible only
    /// when `P` is a multiple of `I` and `(I − LM)` annihilates a direction; the proof assumes
    /// `1 − β/α2 > 0`).
    pub beta_capped: bool,
    /// `θ = ln(1 − β/α2) < 0` of (19): `V` contracts by `e^θ` at every jump.
    pub theta: f64,
    /// `γ = |θ|/(1+T2)`, the largest value allowed by (20a).
    pub gamma: f64,
    /// `R = T2|θ|/(1+T2)`, the smallest value allowed by (20a).
    pub r: f64,
    /// `κ = √(α2/α1) e^{R/2}` of the corrected (21).
    pub kappa: f64,
    /// `√(α2/α1) e^{R/α1}`, the constant as printed in (21) (kept for comparison only).
    pub kappa_printed: f64,
}

impl Theorem1Bound {
    /// The guaranteed exponential rate `γ/2` of `‖ε‖` in `t + j`.
    pub fn rate(&self) -> f64 {
        0.5 * self.gamma
    }

    /// The bound (21) (corrected): `κ e^{−(γ/2)(t+j)} ‖ε(0,0)‖` at hybrid time `(t, j)`.
    pub fn bound(&self, t: f64, j: usize, eps0_norm: f64) -> f64 {
        self.kappa * (-self.rate() * (t + j as f64)).exp() * eps0_norm
    }

    /// The Lyapunov bound (20b): `V(φ(t,j)) ≤ e^{θj} V(φ(0,0))`.
    pub fn lyapunov_bound(&self, j: usize, v0: f64) -> f64 {
        (self.theta * j as f64).exp() * v0
    }
}

/// Constants of Theorem 2 (ISS with respect to measurement noise) for a given `(P, L)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Theorem2Bound {
    /// `θη = ln(1 − β/(2α2))` of (29).
    pub theta_eta: f64,
    /// `γη = |θη|/(1+T2)`.
    pub gamma_eta: f64,
    /// `Rη = T2|θη|/(1+T2)`.
    pub r_eta: f64,
    /// `‖P‖` (spectral norm).
    pub norm_p: f64,
    /// `‖L‖` (spectral norm).
    pub norm_l: f64,
    /// `max_{v∈[T1,T2]} ‖e^{Av}‖²`.
    pub max_expm_norm_sq: f64,
    /// `ρ = ‖P‖(2/β + ‖P‖) max‖e^{Av}‖²`, as printed after (28).
    pub rho_printed: f64,
    /// `ρd = ‖P‖(1 + 2‖P‖/β) max‖e^{Av}‖²`, what the proof's steps give (used for the bound).
    pub rho_derived: f64,
    /// Transient constant of (35): `√(2α2/α1) e^{Rη/2}`.
    pub transient: f64,
    /// Noise gain of (35) with `ρd`: `‖L‖ √(4 ρd α2/(β α1))`.
    pub noise_gain: f64,
    /// Noise gain of (35) with the printed `ρ` (for comparison only).
    pub noise_gain_printed: f64,
}

impl Theorem2Bound {
    /// The ISS bound (35) at `(t, j)` for an initial error norm `eps0_norm` and the sup of the noise
    /// over the jumps up to `(t, j)`, `eta_sup` (only `η` at jump instants enters, (30b)).
    pub fn bound(&self, t: f64, j: usize, eps0_norm: f64, eta_sup: f64) -> f64 {
        let transient = self.transient * (-0.5 * self.gamma_eta * (t + j as f64)).exp() * eps0_norm;
        transient.max(self.noise_gain * eta_sup)
    }
}

/// The constants of Theorems 1 and 2 for one `(P, L)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundConstants {
    /// Theorem 1 (noise-free GES bound).
    pub theorem1: Theorem1Bound,
    /// Theorem 2 (ISS bound).
    pub theorem2: Theorem2Bound,
}

/// `E'XE` (symmetric up to rounding; the eigenvalue helpers of `sporadic-linalg` symmetrise it).
pub(crate) fn congruence(e: MatRef<'_, f64>, x: MatRef<'_, f64>) -> Mat<f64> {
    e.transpose() * (x * e)
}

/// Computes the constants of Theorems 1–2 for `(P, L)` on the window `[T1, T2]`.
///
/// Errors: bad shapes/non-finite input; [`Error::ConditionViolated`] when `α1 ≤ 0` (`P` not positive
/// definite) or `β ≤ 0` (condition (12) fails somewhere on the grid).
pub fn bound_constants(
    plant: &Plant,
    window: &SamplingWindow,
    l: MatRef<'_, f64>,
    p: MatRef<'_, f64>,
    options: &BoundOptions,
) -> Result<BoundConstants, Error> {
    plant.check_lyapunov_matrix(p)?;
    let reset = plant.reset_matrix(l)?;
    options.validate()?;
    let a = plant.a();
    let (t1, t2) = (window.t1(), window.t2());
    let pts = options.grid_points;

    // The eigenvalues are those of the symmetric parts (as `min_eigenvalue` takes them, so the
    // values are the same bit for bit), passed as such: `E'PE` and `P − Ψ` are symmetric only
    // up to rounding relative to `‖P‖‖E‖²`, which can exceed the symmetry check's tolerance
    // relative to their own entries (a random plant of order 4: an asymmetry of 1.6e-11 in
    // `P − Ψ` with entries up to 0.15).
    let alpha1 = extremum(a, 0.0, t2, pts, Sense::Min, |_, e| {
        Ok(min_eigenvalue(
            sym_part(congruence(e, p).as_ref())?.as_ref(),
        )?)
    })?;
    let alpha2 = extremum(a, 0.0, t2, pts, Sense::Max, |_, e| {
        Ok(max_eigenvalue(
            sym_part(congruence(e, p).as_ref())?.as_ref(),
        )?)
    })?;
    if alpha1.value <= 0.0 {
        return Err(Error::ConditionViolated {
            what: "alpha1 (P is not positive definite)",
            value: alpha1.value,
        });
    }
    let beta = extremum(a, t1, t2, pts, Sense::Min, |_, e| {
        let er = e * reset.as_ref();
        let psi = congruence(er.as_ref(), p);
        Ok(min_eigenvalue(sym_part((p - &psi).as_ref())?.as_ref())?)
    })?;
    if beta.value <= 0.0 {
        return Err(Error::ConditionViolated {
            what: "beta = min_v lambda_min(P - Psi(v))",
            value: beta.value,
        });
    }
    let max_expm = extremum(a, t1, t2, pts, Sense::Max, |_, e| {
        Ok(max_eigenvalue(
            sym_part((e.transpose() * e).as_ref())?.as_ref(),
        )?)
    })?;

    let (alpha1_v, alpha2_v) = (alpha1.value, alpha2.value);
    let beta_capped = beta.value >= alpha2_v;
    let beta_v = if beta_capped {
        0.5 * alpha2_v
    } else {
        beta.value
    };
    let theta = (-beta_v / alpha2_v).ln_1p();
    let gamma = theta.abs() / (1.0 + t2);
    let r = t2 * theta.abs() / (1.0 + t2);
    let ratio = (alpha2_v / alpha1_v).sqrt();
    let theorem1 = Theorem1Bound {
        alpha1: alpha1_v,
        alpha1_at: alpha1.at,
        alpha2: alpha2_v,
        alpha2_at: alpha2.at,
        beta: beta_v,
        beta_at: beta.at,
        beta_capped,
        theta,
        gamma,
        r,
        kappa: ratio * (0.5 * r).exp(),
        kappa_printed: ratio * (r / alpha1_v).exp(),
    };

    let theta_eta = (-beta_v / (2.0 * alpha2_v)).ln_1p();
    let gamma_eta = theta_eta.abs() / (1.0 + t2);
    let r_eta = t2 * theta_eta.abs() / (1.0 + t2);
    let norm_p = max_eigenvalue(p)?;
    let norm_l = max_eigenvalue((l.transpose() * l).as_ref())?
        .max(0.0)
        .sqrt();
    let emax = max_expm.value;
    let rho_printed = norm_p * (2.0 / beta_v + norm_p) * emax;
    let rho_derived = norm_p * (1.0 + 2.0 * norm_p / beta_v) * emax;
    let gain = |rho: f64| norm_l * (4.0 * rho * alpha2_v / (beta_v * alpha1_v)).sqrt();
    let theorem2 = Theorem2Bound {
        theta_eta,
        gamma_eta,
        r_eta,
        norm_p,
        norm_l,
        max_expm_norm_sq: emax,
        rho_printed,
        rho_derived,
        transient: (2.0 * alpha2_v / alpha1_v).sqrt() * (0.5 * r_eta).exp(),
        noise_gain: gain(rho_derived),
        noise_gain_printed: gain(rho_printed),
    };
    Ok(BoundConstants { theorem1, theorem2 })
}
