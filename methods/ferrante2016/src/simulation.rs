//! Simulation of the observer (3) and of its error system (5)/(6) with `sporadic-sim` (exact LTI
//! flows, any sampling rule: periodic, random in `[T1, T2]`, adversarial), and the check of the
//! Theorem 1 bound along a simulated solution.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_sim::{
    HybridArc, HybridObserver, InputSignal, LinearCorrection, LinearJump, LinearOutputs, LtiFlow,
    SampledPlant, SamplingRule, SimOptions, Simulation, simulate, simulate_hybrid,
};

use crate::bounds::Theorem1Bound;
use crate::error::Error;
use crate::system::Plant;

/// Simulates the error system (5): `ε̇ = Aε` between samples, `ε⁺ = (I − LM)ε` at the samples chosen
/// by `rule`, from `ε(0, 0) = eps0`. Returns the hybrid arc of `ε`.
pub fn simulate_error<R: SamplingRule + ?Sized>(
    plant: &Plant,
    l: MatRef<'_, f64>,
    rule: &mut R,
    eps0: &[f64],
    options: &SimOptions,
) -> Result<HybridArc, Error> {
    let reset = plant.reset_matrix(l)?;
    let flow = LtiFlow::new(plant.a())?;
    let jump = LinearJump::new(reset)?;
    Ok(simulate_hybrid(flow, jump, rule, eps0, options)?.arc)
}

/// Simulates plant (1) with the known input `u` and the observer (3) with gain `L`: both flow with
/// `ż = Az + Bu`, and at every sample `ẑ⁺ = ẑ + L(Mz − Mẑ)`. The joint arc holds `(z, ẑ)`
/// ([`Simulation::error_arc`] gives `ε = z − ẑ`).
pub fn simulate_observer<R: SamplingRule + ?Sized>(
    plant: &Plant,
    b: MatRef<'_, f64>,
    input: InputSignal,
    l: MatRef<'_, f64>,
    rule: &mut R,
    z0: &[f64],
    zhat0: &[f64],
    options: &SimOptions,
) -> Result<Simulation, Error> {
    plant.check_gain(l)?;
    if b.nrows() != plant.n() {
        return Err(InputError::mismatch("rows of B vs n", plant.n(), b.nrows()).into());
    }
    let flow = LtiFlow::new(plant.a())?.with_input(b, input)?;
    let m: Mat<f64> = plant.c().to_owned();
    let mut sampled = SampledPlant {
        flow: flow.clone(),
        output: LinearOutputs::new(vec![m.clone()])?,
    };
    let mut observer = HybridObserver {
        flow,
        jump: LinearCorrection::constant(m, l.to_owned())?,
    };
    Ok(simulate(
        &mut sampled,
        &mut observer,
        rule,
        z0,
        zhat0,
        options,
    )?)
}

/// The Theorem 1 bound checked along an error arc.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundCheck {
    /// `max ‖ε(t,j)‖ / (κ e^{−(γ/2)(t+j)} ‖ε(0,0)‖)` over the recorded samples (≤ 1 ⇔ the bound holds).
    pub max_ratio: f64,
    /// Ordinary time of the largest ratio.
    pub t: f64,
    /// Jump counter of the largest ratio.
    pub j: usize,
    /// Number of samples checked (flow grid points and both sides of every jump).
    pub samples: usize,
}

/// Evaluates the corrected bound (21) at every recorded sample of `arc` (which must start at
/// `(0, 0)`; `ε(0,0)` is its first state).
pub fn check_bound(arc: &HybridArc, bound: &Theorem1Bound) -> Result<BoundCheck, Error> {
    let Some((t0, _)) = arc.iter().next() else {
        return Err(InputError::empty("hybrid arc of the error").into());
    };
    if t0.t != 0.0 || t0.j != 0 {
        return Err(InputError::parameter(
            "arc start time",
            t0.t,
            "the bound (21) is stated for arcs starting at (t, j) = (0, 0)",
        )
        .into());
    }
    let norm = |x: &[f64]| x.iter().map(|v| v * v).sum::<f64>().sqrt();
    let eps0 = norm(arc.state(0));
    let mut out = BoundCheck {
        max_ratio: 0.0,
        t: 0.0,
        j: 0,
        samples: arc.len(),
    };
    for (ht, x) in arc.iter() {
        let b = bound.bound(ht.t, ht.j, eps0);
        let ratio = if b > 0.0 { norm(x) / b } else { 0.0 };
        if ratio > out.max_ratio {
            out = BoundCheck {
                max_ratio: ratio,
                t: ht.t,
                j: ht.j,
                samples: arc.len(),
            };
        }
    }
    Ok(out)
}
