//! The example of Etienne et al. (2017), §5: the flexible-joint robot (Spong 1987; also
//! Raff & Allgöwer 2007), with the data exactly as printed, and the gains printed by the paper.
//!
//! ```text
//! A = [   0     1      0    0 ]    B = [0, 21.6, 0, 0]'    C = [1 0 0 0]
//!     [ −48.6 −1.25  48.6   0 ]                               [0 1 0 0]
//!     [   0     0      0    1 ]
//!     [  19.5   0   −19.5   0 ]
//! φ = (0, 0, 0, 3.3 sin x3)'  ⇒  G = e4, H = e3', φ(s) = 3.3 sin s, φ' ∈ [−3.3, 3.3],  u = sin t.
//! ```
//!
//! The paper prints `φ` with the opposite sign and 3.3 instead of the 3.33 of Raff & Allgöwer;
//! the sign is irrelevant (symmetric Jacobian bound) and 3.3 is used as printed.

use faer::{Mat, mat};

use crate::error::Error;
use crate::gain::GainSchedule;
use crate::system::Plant;
use sporadic_model::SamplingWindow;

/// Jacobian bound of `φ(s) = 3.3 sin s`: `|φ'(s)| ≤ 3.3`.
pub const GAMMA: f64 = 3.3;

/// The flexible-joint robot of §5 with `φ'(s) ∈ [−3.3, 3.3]` (two vertices `R_1, R_2`, entry
/// (4,3) equal to −22.8 / −16.2).
pub fn flexible_joint() -> Result<Plant, Error> {
    let a = mat![
        [0.0, 1.0, 0.0, 0.0],
        [-48.6, -1.25, 48.6, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [19.5, 0.0, -19.5, 0.0],
    ];
    let b = mat![[0.0], [21.6], [0.0], [0.0]];
    let c = mat![[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]];
    let g = mat![[0.0], [0.0], [0.0], [1.0]];
    let h = mat![[0.0, 0.0, 1.0, 0.0]];
    Plant::lipschitz(
        a.as_ref(),
        b.as_ref(),
        c.as_ref(),
        g.as_ref(),
        h.as_ref(),
        GAMMA,
    )
}

/// The flexible-joint robot of §5 as a plant of the common contract (`sporadic_model::Plant`
/// with its Lipschitz section: `G = e4`, `H = e3ᵀ`, `φ'(s) ∈ [−3.3, 3.3]`), named
/// "flexible joint": what `design`, `prove` and `verify` of [`crate::Etienne2017`] take.
///
/// # Errors
/// None for the constant data (the `Result` is that of the constructors).
pub fn model_plant() -> Result<sporadic_model::Plant, Error> {
    let p = flexible_joint()?;
    let lip = sporadic_model::Lipschitz::new(
        mat![[0.0], [0.0], [0.0], [1.0]].as_ref(),
        mat![[0.0, 0.0, 1.0, 0.0]].as_ref(),
        mat![[-GAMMA]].as_ref(),
        mat![[GAMMA]].as_ref(),
    )?;
    Ok(sporadic_model::Plant::linear(p.a(), Some(p.b()), p.c())?
        .with_lipschitz(lip)?
        .named("flexible joint"))
}

/// The nonlinearity of the example, `φ(s) = 3.3 sin s` (m = 1).
pub fn phi(s: &[f64], out: &mut [f64]) {
    out[0] = GAMMA * s[0].sin();
}

/// The input of the example, `u(t) = sin t`.
pub fn input(t: f64, out: &mut [f64]) {
    out[0] = t.sin();
}

/// The static gain printed for Corollary 2 on `[0.01, 0.2]` (printed transposed, two decimals).
pub fn paper_static_gain() -> Mat<f64> {
    mat![[0.87, 0.04], [0.03, 0.99], [0.66, 0.09], [0.65, -0.12]]
}

/// The gains `(K0, K1)` printed for Theorem 3 on `[0.01, 0.3]` (printed transposed; the entry
/// "0.4" of `K0`, printed with one decimal, is read 0.40 and "1" as 1.00).
pub fn paper_tv_gains() -> (Mat<f64>, Mat<f64>) {
    (
        mat![[0.92, 0.00], [0.00, 1.0], [0.77, 0.04], [0.40, -0.06]],
        mat![[0.98, 0.01], [0.01, 1.0], [0.91, 0.05], [0.94, 0.01]],
    )
}

/// The paper's static `K` as a schedule on `window`.
pub fn paper_static_schedule(window: SamplingWindow) -> Result<GainSchedule, Error> {
    GainSchedule::constant(paper_static_gain().as_ref(), window)
}

/// The paper's `K(τ)` on `[0.01, 0.3]`.
pub fn paper_tv_schedule() -> Result<GainSchedule, Error> {
    let (k0, k1) = paper_tv_gains();
    GainSchedule::interpolated(k0.as_ref(), k1.as_ref(), SamplingWindow::new(0.01, 0.3)?)
}
