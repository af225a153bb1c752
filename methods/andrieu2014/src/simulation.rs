//! Closed-loop simulation of the observer designed for a linear plant file's plant
//! ([`crate::plant_design`]), on the hybrid simulator of [`crate::closed_loop`].
//!
//! The run is made in the scaled normal form (time `τ = ωt`, `z̃ = T x`), where the plant is
//! `dz̃/dτ = S z̃ + e_n ã'z̃`, `ã_i = a_i ω^{i−1}/ωⁿ` (zero input), and the observer is (5)–(7) with the
//! design's tuning; the error is reported in the plant's coordinates and time,
//! `x − x̂ = T⁻¹(z̃ − ẑ)`, `t = τ/ω`.

use faer::linalg::solvers::DenseSolveCore;
use sporadic_model::{Plant, Scenario, SimulationReport, Trajectory, sig4};
use sporadic_sim::{PiecewiseConstant, ZeroNoise};

use crate::closed_loop::{RunOptions, run};
use crate::error::Error;
use crate::plant_design::PlantDesign;
use crate::system::{NormalFormPlant, TriangularSystem};
use sporadic_linalg::InputError;
use sporadic_linalg::input::{check_finite_slice, check_len};

/// Budget of a simulation: at most this many samples.
pub const MAX_SAMPLES: usize = 100_000;

/// Default horizon, in guaranteed longest intervals `α/ω`.
const DEFAULT_HORIZON_INTERVALS: f64 = 40.0;

/// The linear plant in the scaled normal form: `f(z̃) = e_n ã'z̃`, `c = max|ã_i|`.
#[derive(Debug, Clone)]
struct ScaledCompanion {
    a: Vec<f64>,
    c: f64,
}

impl TriangularSystem for ScaledCompanion {
    fn order(&self) -> usize {
        self.a.len()
    }
    fn input_dim(&self) -> usize {
        0
    }
    fn nonlinearity(&self, x: &[f64], _u: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        let n = self.a.len();
        out[n - 1] = self.a.iter().zip(x).map(|(a, x)| a * x).sum();
    }
    fn lipschitz(&self, _xhat: &[f64], _u: &[f64]) -> f64 {
        self.c
    }
}

/// Simulates the design `d` of the linear plant `plant` from `x(0) = e0`, `x̂(0) = 0` (so
/// `x(0) − x̂(0) = e0`, default all ones), `L(0) = 1`, zero input, no noise, over
/// `scenario.horizon` seconds (default 40 longest intervals `α/ω`), at most [`MAX_SAMPLES`] samples.
/// The sampling scenario of `scenario` is ignored: rule (7) picks the instants.
///
/// Errors: [`Error::Input`] for a Lipschitz plant (its `φ` is not known), a wrong initial error
/// or horizon; the errors of [`run`].
pub fn simulate_linear(
    plant: &Plant,
    d: &PlantDesign,
    scenario: &Scenario,
) -> Result<Trajectory, Error> {
    if plant.lipschitz().is_some() {
        return Err(InputError::parameter(
            "lipschitz",
            1.0,
            "only a linear plant can be simulated (phi is known only through its Jacobian bounds)",
        )
        .into());
    }
    let nf = &d.normal_form;
    let n = nf.order();
    let omega = d.omega;
    let e0 = scenario
        .initial_error
        .clone()
        .unwrap_or_else(|| vec![1.0; n]);
    check_len(&e0, n, "initial error")?;
    check_finite_slice(&e0, "initial error")?;
    let horizon = scenario
        .horizon
        .unwrap_or(DEFAULT_HORIZON_INTERVALS * d.longest);
    if !(horizon.is_finite() && horizon > 0.0) {
        return Err(InputError::parameter("horizon", horizon, "need a finite horizon > 0").into());
    }
    let a: Vec<f64> = nf
        .coefficients()
        .iter()
        .enumerate()
        .map(|(i, a)| a * omega.powi(i as i32) / omega.powi(n as i32))
        .collect();
    let system = ScaledCompanion { a, c: d.c_scaled };
    let t = nf.scaled_transformation(omega);
    let t_inv = t.partial_piv_lu().inverse();
    let z0: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| t[(i, j)] * e0[j]).sum())
        .collect();
    let no_input = PiecewiseConstant::constant(vec![])?;
    let mut opts = RunOptions::new(omega * horizon);
    opts.max_samples = Some(MAX_SAMPLES);
    let r = run(
        &NormalFormPlant(system.clone()),
        &z0,
        &system,
        &vec![0.0; n],
        &no_input,
        &d.tuning,
        &mut ZeroNoise::new(1),
        &opts,
    )?;
    let to_x = |z: &[f64]| -> Vec<f64> {
        (0..n)
            .map(|i| (0..n).map(|j| t_inv[(i, j)] * (z[j] - z[n + j])).sum())
            .collect()
    };
    let mut times = Vec::new();
    let mut jumps = Vec::new();
    let mut errors: Vec<Vec<f64>> = Vec::new();
    for (ht, z) in r.arc.iter() {
        times.push(ht.t / omega);
        jumps.push(ht.j);
        errors.push(to_x(z));
    }
    let norm = |x: &[f64]| x.iter().map(|v| v * v).sum::<f64>().sqrt();
    let norms: Vec<f64> = errors.iter().map(|e| norm(e)).collect();
    let (dmin, dmax) = r
        .samples
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), s| {
            (lo.min(s.delta / omega), hi.max(s.delta / omega))
        });
    let slack = 1e-9;
    let inside = r.samples.iter().all(|s| {
        let dt = s.delta / omega;
        dt >= d.shortest * (1.0 - slack) && dt <= d.longest * (1.0 + slack)
    });
    let end = times.last().copied().unwrap_or(0.0);
    let initial = norm(&e0);
    let last = norms.last().copied().unwrap_or(f64::NAN);
    let signals = (0..n)
        .map(|i| {
            (
                format!("x_{} − x̂_{}", i + 1, i + 1),
                errors.iter().map(|e| e[i]).collect(),
            )
        })
        .collect();
    let budget = if r.samples.len() >= MAX_SAMPLES {
        format!(
            " (stopped by the budget of {MAX_SAMPLES} samples at t = {} s)",
            sig4(end)
        )
    } else {
        String::new()
    };
    Ok(Trajectory {
        quantity: "estimation error x − x̂".into(),
        t: times,
        j: jumps,
        signals,
        norm: norms,
        report: SimulationReport {
            setup: format!(
                "plant in scaled normal form (zero input, no noise), x(0) − x̂(0) = ({}) \
                 (|e(0)| = {}), x̂(0) = 0, L(0) = 1, instants picked by rule (7), \
                 horizon {} s; integration by Dormand–Prince 5(4), rtol 1e-9, atol 1e-12",
                e0.iter().map(|&v| sig4(v)).collect::<Vec<_>>().join(", "),
                sig4(initial),
                sig4(horizon)
            ),
            samples: r.samples.len(),
            initial_error: initial,
            final_error: last,
            result: format!(
                "{} samples{budget}, intervals in [{}, {}] (the plant's time unit; {} the guaranteed window [{}, {}]), \
                 |x − x̂| at the end = {}",
                r.samples.len(),
                sig4(dmin),
                sig4(dmax),
                if inside { "inside" } else { "OUTSIDE" },
                sig4(d.shortest),
                sig4(d.longest),
                sig4(last)
            ),
            settling_time: None,
            ends_early_at: None,
            figure: None,
        },
    })
}
