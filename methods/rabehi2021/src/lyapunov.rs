//! The constants of the proof of Theorem 1 (Rabehi et al. 2021, (20)–(26)) and Lemma 1 (from
//! Ferrante et al. 2016), for a certified `(Ā, Γ, P)` on a window.
//!
//! * `V(z0) = ξ0ᵀ e^{Āᵀτ} P e^{Āτ} ξ0` (20), constant along flows (`τ̇ = −1`, `ξ̇0 = Āξ0`);
//! * `l1 = min_{τ∈[0,τmax]} λmin(e^{Āᵀτ}Pe^{Āτ})`, `l2 = max_{τ∈[0,τmax]} λmax(e^{Āᵀτ}Pe^{Āτ})`
//!   (22), so `l1‖ξ0‖² ≤ V ≤ l2‖ξ0‖²` (21) (evaluated on a grid: analysis constants);
//! * `η` with `Φ(μ) ⪯ −ηI` on the window: `η = −bound` of the rigorous grid check
//!   ([`crate::verify`]), so `V⁺ − V ≤ −η‖ξ0‖²` (25) and `V⁺ ≤ e^{θ1}V`, `θ1 = ln(1 − η/l2)` (26);
//! * Lemma 1 with `ρ = θ1`: for `γ ∈ (0, |ρ|/(1 + τmax)]` and `ω ≥ τmax|ρ|/(1 + τmax)`,
//!   `ρj ≤ ω − γ(t + j)` on every hybrid time domain of (13) (`t ≤ (j+1)τmax`, (16)); the
//!   extreme choices are used;
//! * GES (17): `‖ξ0(t, j)‖ ≤ κ e^{−λ(t+j)} ‖ξ0(0, 0)‖` with `κ = √(l2 e^{ω}/l1)`, `λ = γ/2`
//!   (derived from the above; the paper leaves them implicit).

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_square_finite;
use sporadic_linalg::{expm_scaled, expm_stepper, max_eigenvalue, min_eigenvalue, sym_part};

use crate::error::Error;
use crate::verify::{GridOptions, verify_theorem1};
use sporadic_model::SamplingWindow;

/// The constants of Theorem 1's proof for one certificate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Theorem1Constants {
    /// `l1` of (22).
    pub l1: f64,
    /// `l2` of (22).
    pub l2: f64,
    /// `η` of (25) (rigorous: from the grid bound).
    pub eta: f64,
    /// `θ1 = ln(1 − η/l2) < 0` of (26).
    pub theta1: f64,
    /// `γ = |θ1|/(1 + τmax)` (Lemma 1).
    pub gamma: f64,
    /// `ω = τmax|θ1|/(1 + τmax)` (Lemma 1).
    pub omega: f64,
    /// `κ = √(l2 e^{ω}/l1)` of (17).
    pub kappa: f64,
    /// `λ = γ/2` of (17).
    pub lambda: f64,
}

impl Theorem1Constants {
    /// Lemma 1's inequality `θ1·j ≤ ω − γ(t + j)` at one hybrid time.
    pub fn lemma1_holds(&self, t: f64, j: usize) -> bool {
        let j = j as f64;
        self.theta1 * j <= self.omega - self.gamma * (t + j) + 1e-12 * (1.0 + t + j)
    }

    /// The GES bound `κ e^{−λ(t+j)}` of (17) (multiply by `‖ξ0(0, 0)‖`).
    pub fn ges_factor(&self, t: f64, j: usize) -> f64 {
        self.kappa * (-self.lambda * (t + j as f64)).exp()
    }
}

/// Computes [`Theorem1Constants`] for `(Ā, Γ, P)` on `window`; `points` grid points for `l1, l2`
/// and the grid options for `η`.
///
/// # Errors
/// Bad shapes or non-finite input, `P` not positive definite on the grid (`l1 ≤ 0`), or (19) not
/// certified on the grid (`η ≤ 0`): [`Error::Input`] (`InvalidParameter`) naming the quantity.
pub fn theorem1_constants(
    a_bar: MatRef<'_, f64>,
    gamma: MatRef<'_, f64>,
    p: MatRef<'_, f64>,
    window: &SamplingWindow,
    points: usize,
    grid: &GridOptions,
) -> Result<Theorem1Constants, Error> {
    let n = check_square_finite(a_bar, "A-bar")?;
    if points < 2 {
        return Err(InputError::parameter("points", points as f64, "need at least 2").into());
    }
    let check = verify_theorem1(a_bar, gamma, p, window, grid)?;
    let eta = -check.bound;
    if !(eta > 0.0) {
        return Err(Error::Input(InputError::InvalidParameter {
            name: "eta (grid bound of (19))".into(),
            value: eta,
            reason: "(19) is not certified for this P, so Theorem 1 gives no constants".into(),
        }));
    }
    let h = window.t2() / (points - 1) as f64;
    let mut stepper = expm_stepper(a_bar, 0.0, h, points - 1)?;
    let mut e = Mat::<f64>::zeros(n, n);
    let (mut l1, mut l2) = (f64::INFINITY, f64::NEG_INFINITY);
    while stepper.next_into(e.as_mut()).is_some() {
        let q = e.transpose() * p * &e;
        let q = sym_part(q.as_ref())?;
        l1 = l1.min(min_eigenvalue(q.as_ref())?);
        l2 = l2.max(max_eigenvalue(q.as_ref())?);
    }
    if let Some(err) = stepper.error() {
        return Err(err.clone().into());
    }
    if !(l1 > 0.0) {
        return Err(InputError::parameter("l1", l1, "P is not positive definite").into());
    }
    let theta1 = (1.0 - eta / l2).ln();
    let tau_max = window.t2();
    let gamma_c = -theta1 / (1.0 + tau_max);
    let omega = tau_max * gamma_c;
    Ok(Theorem1Constants {
        l1,
        l2,
        eta,
        theta1,
        gamma: gamma_c,
        omega,
        kappa: (l2 * omega.exp() / l1).sqrt(),
        lambda: gamma_c / 2.0,
    })
}

/// The Lyapunov function (20), `V = ξᵀ e^{Āᵀτ} P e^{Āτ} ξ`, for the error `ξ` and the time `τ`
/// left until the next jump.
///
/// # Errors
/// Wrong lengths/shapes or a failure of the matrix exponential.
pub fn lyapunov_value(
    a_bar: MatRef<'_, f64>,
    p: MatRef<'_, f64>,
    xi: &[f64],
    tau: f64,
) -> Result<f64, Error> {
    let n = check_square_finite(a_bar, "A-bar")?;
    if xi.len() != n {
        return Err(InputError::mismatch("length of xi (= 2n)", n, xi.len()).into());
    }
    let e = expm_scaled(a_bar, tau)?;
    let z: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|k| e[(i, k)] * xi[k]).sum())
        .collect();
    Ok((0..n)
        .map(|i| z[i] * (0..n).map(|k| p[(i, k)] * z[k]).sum::<f64>())
        .sum())
}
