//! The constants of the proof of Theorem 3 (input-to-state stability of the error dynamics (28)).
//!
//! With `Φ_σ(τ) = e^{−Aᵀτ}P_σe^{−Aτ}`, the Lyapunov function (30) is `V = e^{−ρτ}x̃ᵀΦ_σ(τ)x̃` and
//! `M(τ, σ) = Φ_σ(τ) − (I − K_σ(τ)C_σ)ᵀ P_Γ(σ) (I − K_σ(τ)C_σ)` (37). On the flow set
//! `C = ∪_σ [0, T_Mσ] × {σ}` and the jump set `D = ∪_σ [T_mσ, T_Mσ] × {σ}`:
//!
//! ```text
//! c_2 = max_C λ_M(Φ_σ(τ))                       (32)      c_F = max_C ‖Φ_σ(τ)‖ (= c_2, Φ ≻ 0)
//! c_3 = min_D λ_m(M(τ, σ)) / c_2                (38)      ([flag] the paper writes C; K_σ lives on D)
//! ρ   = ln(1 + c_3/2) / T_M
//! c_1 = min_C e^{−ρτ} λ_m(Φ_σ(τ))               (31)
//! c_J = max_D max(‖K_σᵀP_Γ(I − K_σC_σ)‖, ‖K_σᵀP_ΓK_σ‖)
//! γ_F = 2c_F²/(ρc_1),   γ_J = c_J + 2c_J²/(c_1c_3),   R = 1/(1 − e^{−ρT_m/2})
//! γ   = R/c_1 · max(γ_F T_M, γ_J),   M = c_2/c_1,   λ = ρ/2                                   (43)
//! ```
//!
//! so that `|x̃(t)|² ≤ M e^{−λt}|x̃(0)|² + γ(‖d‖²_∞ + ‖w‖²_∞)` (16), and
//! `V(t) ≤ e^{−ρt/2}V(0) + c_1γ(‖d‖²_∞ + ‖w‖²_∞)` (43).
//!
//! The extrema over τ are taken on uniform grids (`points_per_window` points per interval): they are
//! sampled values of smooth functions, not rigorous bounds.

use faer::Mat;
use sporadic_linalg::{expm_stepper, max_eigenvalue, min_eigenvalue};

use crate::error::{Error, check_at_least};
use crate::gain::{GainSchedule, congruence, gain, jump_matrix};
use crate::plant::window_grid;
use crate::validation::spectral_norm;
use sporadic_linalg::InputError;

/// Grid resolution of the extrema. Default: 2001 points per window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IssOptions {
    /// Points per interval `[0, T_Mσ]` and `[T_mσ, T_Mσ]`.
    pub points_per_window: usize,
}

impl IssOptions {
    /// Checks every field; the error names the offending one.
    ///
    /// # Errors
    /// [`InputError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<(), InputError> {
        check_at_least("points_per_window", self.points_per_window, 2)
    }
}

impl Default for IssOptions {
    fn default() -> Self {
        Self {
            points_per_window: 2001,
        }
    }
}

/// The constants of Theorem 3's proof.
#[derive(Debug, Clone, PartialEq)]
pub struct IssConstants {
    /// `c_1` (31).
    pub c1: f64,
    /// `c_2` (32).
    pub c2: f64,
    /// `c_3` (38).
    pub c3: f64,
    /// `ρ = ln(1 + c_3/2)/T_M`.
    pub rho: f64,
    /// `c_F`.
    pub c_f: f64,
    /// `c_J`.
    pub c_j: f64,
    /// `γ_F = 2c_F²/(ρc_1)` (35).
    pub gamma_f: f64,
    /// `γ_J = c_J + 2c_J²/(c_1c_3)` (39).
    pub gamma_j: f64,
    /// `R = Σ_k e^{−ρT_m k/2}`.
    pub r: f64,
    /// ISS gain γ of (16)/(43).
    pub gamma: f64,
    /// Overshoot `M = c_2/c_1` of (5).
    pub m: f64,
    /// Decay rate `λ = ρ/2` of (5).
    pub lambda: f64,
    /// `min_{τ ∈ [T_mσ, T_Mσ]} λ_m(M(τ, σ))` for each σ (the Theorem 3 certificate: all > 0).
    pub min_m_eigenvalue: Vec<f64>,
}

impl IssConstants {
    /// Right-hand side of (16): `M e^{−λt}|x̃(0)|² + γ(‖d‖² + ‖w‖²)` (a bound on `|x̃(t)|²`).
    pub fn error_bound_sq(&self, t: f64, x0_sq: f64, d_sup: f64, w_sup: f64) -> f64 {
        self.m * (-self.lambda * t).exp() * x0_sq + self.gamma * (d_sup * d_sup + w_sup * w_sup)
    }
}

/// Computes the constants for the observer `gains` (see the module docs).
///
/// # Errors
/// Fewer than 2 points, a failing kernel, or `min λ_m(M) ≤ 0` (Theorem 3's hypothesis (29) fails on
/// the grid: [`Error::Infeasible`]).
pub fn iss_constants(gains: &GainSchedule, settings: &IssOptions) -> Result<IssConstants, Error> {
    settings.validate()?;
    let k = settings.points_per_window;
    let plant = gains.plant();
    let n = plant.n();
    let neg_a = Mat::from_fn(n, n, |i, j| -plant.a()[(i, j)]);
    let mut c2 = 0.0f64;
    // (τ, λ_m(Φ_σ(τ))) on the flow set, for c_1 once ρ is known.
    let mut lam_min: Vec<(f64, f64)> = Vec::new();
    for (sensor, p) in plant.sensors().iter().zip(gains.p()) {
        let tm = sensor.window().t2();
        for (i, e) in expm_stepper(neg_a.as_ref(), 0.0, tm / (k - 1) as f64, k - 1)?.enumerate() {
            let phi = congruence(e.as_ref(), p.as_ref())?;
            c2 = c2.max(max_eigenvalue(phi.as_ref())?);
            lam_min.push((
                tm * i as f64 / (k - 1) as f64,
                min_eigenvalue(phi.as_ref())?,
            ));
        }
    }
    let c_f = c2;
    let mut min_m = Vec::with_capacity(plant.num_sensors());
    let mut c_j = 0.0f64;
    for (s, sensor) in plant.sensors().iter().enumerate() {
        let w = sensor.window();
        let p = &gains.p()[s];
        let p_next = &gains.p()[plant.next(s)];
        let c = sensor.c();
        let mut worst = f64::INFINITY;
        for tau in window_grid(w, k)? {
            let kg = gain(plant, s, p.as_ref(), tau)?;
            let jm = jump_matrix(kg.as_ref(), c);
            let phi = crate::gain::phi(plant.a(), p.as_ref(), tau)?;
            let m = &phi - congruence(jm.as_ref(), p_next.as_ref())?;
            worst = worst.min(min_eigenvalue(m.as_ref())?);
            let kp = kg.transpose() * p_next;
            c_j = c_j
                .max(spectral_norm((&kp * &jm).as_ref())?)
                .max(spectral_norm((&kp * &kg).as_ref())?);
        }
        min_m.push(worst);
    }
    let m_min = min_m.iter().copied().fold(f64::INFINITY, f64::min);
    if m_min.is_nan() || m_min <= 0.0 {
        return Err(Error::Infeasible {
            what: format!(
                "Theorem 3: min λ_m(M(τ, σ)) = {m_min:.3e} ≤ 0 on the grid; (29) fails for these gains"
            ),
        });
    }
    let c3 = m_min / c2;
    let t_big = plant.t_max();
    let rho = (1.0 + 0.5 * c3).ln() / t_big;
    let c1 = lam_min
        .iter()
        .map(|&(tau, l)| (-rho * tau).exp() * l)
        .fold(f64::INFINITY, f64::min);
    let gamma_f = 2.0 * c_f * c_f / (rho * c1);
    let gamma_j = c_j + 2.0 * c_j * c_j / (c1 * c3);
    let r = 1.0 / (1.0 - (-0.5 * rho * plant.t_min()).exp());
    let gamma = r / c1 * (gamma_f * t_big).max(gamma_j);
    Ok(IssConstants {
        c1,
        c2,
        c3,
        rho,
        c_f,
        c_j,
        gamma_f,
        gamma_j,
        r,
        gamma,
        m: c2 / c1,
        lambda: 0.5 * rho,
        min_m_eigenvalue: min_m,
    })
}
