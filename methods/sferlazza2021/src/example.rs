//! The quarter-car active suspension of §6 (model (51)), with the sensors, windows, complements and
//! noise bounds of the paper.
//!
//! State: `x1 = z_s − z_u` (suspension deflection), `x2 = ż_s`, `x3 = z_u − z_r` (tire deflection),
//! `x4 = ż_u`. Parameters `k_s = 1.6·10⁴`, `b_s = 10³`, `m_s = 250`, `m_u = 45`, `k_t = 400`, `b_t = 0`
//! (as printed; `k_t = 400` gives a slow, almost undamped 1.15 rad/s mode).

use faer::{Mat, mat};

use crate::error::Error;
use crate::plant::RoundRobinPlant;
use sporadic_model::SamplingWindow;

/// Physical parameters of the quarter-car model (51).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuarterCar {
    /// Suspension stiffness `k_s`.
    pub ks: f64,
    /// Suspension damping `b_s`.
    pub bs: f64,
    /// Sprung mass `m_s`.
    pub ms: f64,
    /// Unsprung mass `m_u`.
    pub mu: f64,
    /// Tire stiffness `k_t`.
    pub kt: f64,
    /// Tire damping `b_t`.
    pub bt: f64,
}

impl Default for QuarterCar {
    /// The values printed in §6.
    fn default() -> Self {
        Self {
            ks: 1.6e4,
            bs: 1e3,
            ms: 250.0,
            mu: 45.0,
            kt: 400.0,
            bt: 0.0,
        }
    }
}

impl QuarterCar {
    /// The matrix `A` of (51).
    pub fn a(&self) -> Mat<f64> {
        let Self {
            ks,
            bs,
            ms,
            mu,
            kt,
            bt,
        } = *self;
        mat![
            [0.0, 1.0, 0.0, -1.0],
            [-ks / ms, -bs / ms, 0.0, bs / ms],
            [0.0, 0.0, 0.0, 1.0],
            [ks / mu, bs / mu, -kt / mu, -(bs + bt) / mu],
        ]
    }
}

/// Bounds of the zero-mean uniform process disturbance `|d_i| ≤ d̄_i` of §6.
pub const DISTURBANCE_BOUNDS: [f64; 4] = [0.004, 0.1, 0.04, 0.1];

/// Bounds of the zero-mean uniform measurement noise of §6: `|w_1| ≤ 0.002` (on x1), `|w_2| ≤ 0.02`
/// (on x3).
pub const NOISE_BOUNDS: [f64; 2] = [0.002, 0.02];

/// Sampling windows of §6: `[0.02, 0.07]` for σ = 1 and `[0.04, 0.09]` for σ = 2.
pub const WINDOWS: [(f64, f64); 2] = [(0.02, 0.07), (0.04, 0.09)];

/// The §6 plant: `C_1 = [1 0 0 0]`, `C_2 = [0 0 1 0]`, the windows [`WINDOWS`] and the paper's
/// (orthonormal) complements `C_1^⊥`, `C_2^⊥`.
///
/// # Errors
/// None for the printed data (the constructor's checks are run anyway).
pub fn suspension() -> Result<RoundRobinPlant, Error> {
    let plant = RoundRobinPlant::new(
        QuarterCar::default().a().as_ref(),
        &[
            (
                mat![[1.0, 0.0, 0.0, 0.0]].as_ref(),
                SamplingWindow::new(WINDOWS[0].0, WINDOWS[0].1)?,
            ),
            (
                mat![[0.0, 0.0, 1.0, 0.0]].as_ref(),
                SamplingWindow::new(WINDOWS[1].0, WINDOWS[1].1)?,
            ),
        ],
    )?;
    let c1p = mat![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0]
    ];
    let c2p = mat![
        [0.0, -1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0]
    ];
    plant
        .with_complement(0, c1p.as_ref())?
        .with_complement(1, c2p.as_ref())
}

/// The §6 quarter car as a plant and sampling of the common contract (`sporadic_model`):
/// round-robin over `C_1 = [1 0 0 0]`, `C_2 = [0 0 1 0]` with the windows [`WINDOWS`], named
/// "suspension": what `design`, `prove` and `verify` of [`crate::Sferlazza2021`] take.
///
/// # Errors
/// None for the printed data (the constructors' checks are run anyway).
pub fn model_plant() -> Result<(sporadic_model::Plant, sporadic_model::Sampling), Error> {
    let a = QuarterCar::default().a();
    let (c1, c2) = (mat![[1.0, 0.0, 0.0, 0.0]], mat![[0.0, 0.0, 1.0, 0.0]]);
    let plant = sporadic_model::Plant::round_robin(a.as_ref(), None, &[c1.as_ref(), c2.as_ref()])?
        .named("suspension");
    let windows = WINDOWS
        .iter()
        .map(|&(t1, t2)| SamplingWindow::new(t1, t2))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((plant, sporadic_model::Sampling::RoundRobin(windows)))
}

/// The matrices printed in (52). They are **not** a valid certificate: `P_2` is indefinite
/// (eigenvalue ≈ −0.342) and the pair violates (44) on both windows; they are kept only
/// to report that fact.
pub fn printed_solution() -> [Mat<f64>; 2] {
    [
        mat![
            [11.5, -2.3, -1.6, -1.1],
            [-2.3, 5.5, -2.1, 4.5],
            [-1.6, -2.1, 11.5, -1.3],
            [-1.1, 4.5, -1.3, 4.2]
        ],
        mat![
            [12.5, -0.8, -0.9, -1.0],
            [-0.8, 0.8, 0.9, 0.9],
            [-0.9, 0.9, 0.9, 0.1],
            [-1.0, 0.9, 0.1, 1.1]
        ],
    ]
}
