//! The illustrative example of Rabehi et al. (2021), §V: a spring–mass–damper with
//! `m_s = k_s = 1`, damping `c_s`, position measured as `y = 2x₁ + v`.

use faer::{Mat, mat};

use crate::error::Error;
use crate::simulation::{Disturbance, Noise, Scenario};
use crate::system::{Bounds, Plant};
use sporadic_model::SamplingWindow;

/// The damping values of Table I.
pub const TABLE1_DAMPING: [f64; 8] = [1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3];

/// The largest `τmax` of Table I for [`TABLE1_DAMPING`] (`None`: "–", no gain found by the
/// paper).
pub const TABLE1_TAU_MAX: [Option<f64>; 8] = [
    Some(1.1),
    Some(1.0),
    Some(0.9),
    Some(0.8),
    Some(0.5),
    Some(0.3),
    Some(0.05),
    None,
];

/// `τmin` of the example (the paper does not restate it for Table I; the design window's value is
/// assumed).
pub const TAU_MIN: f64 = 0.04;

/// `τmax` of the design example.
pub const TAU_MAX: f64 = 0.3;

/// The spring–mass–damper `A = [[0, 1], [−1, −c_s]]`, `B = [0; 1]`, `C = [2, 0]`.
///
/// # Errors
/// Non-finite `c_s`.
pub fn spring_mass_damper(c_s: f64) -> Result<Plant, Error> {
    Plant::new(
        mat![[0.0, 1.0], [-1.0, -c_s]].as_ref(),
        mat![[0.0], [1.0]].as_ref(),
        mat![[2.0, 0.0]].as_ref(),
    )
}

/// The bounds of the example: `−d̄ ≤ d ≤ d̄`, `d̄ = [1, 1]ᵀ`, and `v̄ = 0.4` (implied by
/// `v(t_k) = 0.4 cos(2t_k)`).
pub fn example_bounds() -> Bounds {
    Bounds::new(vec![-1.0, -1.0], vec![1.0, 1.0], vec![0.4]).expect("valid constant bounds")
}

/// The §V example as a plant of the common contract (`sporadic_model::Plant`): the
/// spring–mass–damper with `c_s = 1`, `|d_i| ≤ 1`, `|v| ≤ 0.4`, named "spring-mass-damper":
/// what `design`, `prove` and `verify` of [`crate::Rabehi2021`] take.
///
/// # Errors
/// None for the constant data (the `Result` is that of the constructors).
pub fn model_plant() -> Result<sporadic_model::Plant, Error> {
    let p = spring_mass_damper(1.0)?;
    Ok(sporadic_model::Plant::linear(p.a(), Some(p.b()), p.c())?
        .named("spring-mass-damper")
        .with_bounds(sporadic_model::Bounds::new(vec![1.0, 1.0], vec![0.4])?)?)
}

/// The design window `[0.04, 0.3]`.
pub fn example_window() -> SamplingWindow {
    SamplingWindow::new(TAU_MIN, TAU_MAX).expect("valid constant window")
}

/// The gain printed in §V: `Lᵀ = [−0.5004, −0.0494]`.
pub fn paper_gain() -> Mat<f64> {
    mat![[-0.5004], [-0.0494]]
}

/// The printed `I₂ + LC = G1 − G2 = [[−0.0008, 0], [−0.0987, 1]]`.
pub fn paper_reset_matrix() -> Mat<f64> {
    mat![[-0.0008, 0.0], [-0.0987, 1.0]]
}

/// The input `u(t) = 10[2 sin(10t) + sin(16t) + sin(24t)]` as `(amplitude, ω, phase)` terms.
pub const INPUT_TERMS: [(f64, f64, f64); 3] =
    [(20.0, 10.0, 0.0), (10.0, 16.0, 0.0), (10.0, 24.0, 0.0)];

/// The measurement noise `v(t_k) = 0.4 cos(2t_k)`.
pub fn noise(t: f64) -> f64 {
    0.4 * (2.0 * t).cos()
}

/// The simulation setup of Figure 1 (with disturbance and noise) or Figure 2 (`noisy = false`:
/// `d ≡ 0`, `v ≡ 0`, and the observer uses `d̲ = d̄ = 0`, `v̄ = 0`, Remark 4).
pub fn figure_scenario(noisy: bool) -> Scenario {
    let x0 = vec![1.0, -1.0];
    Scenario {
        lower0: x0.iter().map(|x| x - 3.0).collect(),
        upper0: x0.iter().map(|x| x + 3.0).collect(),
        x0,
        horizon: 20.0,
        sampling: example_window(),
        sampling_seed: 2021,
        disturbance: noisy.then(|| Disturbance {
            lower: vec![-1.0, -1.0],
            upper: vec![1.0, 1.0],
            period: 0.1,
            seed: 7,
        }),
        noise: if noisy {
            Noise::Cosine {
                amplitude: vec![0.4],
                omega: 2.0,
            }
        } else {
            Noise::Zero
        },
        input: INPUT_TERMS.to_vec(),
        record_step: Some(0.01),
    }
}
