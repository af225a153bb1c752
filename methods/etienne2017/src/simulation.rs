//! Simulation of the nonlinear plant (1) and the impulsive observer (3) of Etienne et al. (2017)
//! with `sporadic-sim`: both flow with the adaptive Dormand–Prince 5(4) integrator (the error
//! dynamics is nonlinear, so there is no exact propagator), samples come from any
//! [`SamplingRule`], and at a sample the observer is reset with the gain evaluated at the length
//! of the interval that just ended:
//!
//! ```text
//! dx/dt = A x + B u + G φ(H x),     dx̂/dt = A x̂ + B u + G φ(H x̂),
//! x̂(t_k) = x̂(t_k⁻) + K(t_k − t_{k−1}) (C x(t_k) − C x̂(t_k⁻)),    k ≥ 1 (no reset at t_0 = 0).
//! ```
//!
//! The error `z = x − x̂` follows (4). Along any solution, `V_k = z(t_k)'P1 z(t_k)` (just after
//! the resets) is strictly decreasing for a certified design: the proof of Theorem 3 bounds the
//! decrease of `z'P(τ)z` for every vector field in the hull of Lemma 1.
//!
//! [`worst_case_sampling`] builds the greedy adversary of `sporadic-sim` for a design (with the
//! `τ`-dependent reset `I − K(τ)C`).

use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite;
use sporadic_linalg::input::{check_dimension, check_finite_slice};
use std::cell::RefCell;

use faer::{Mat, MatRef};
use sporadic_sim::{
    Adversarial, Dopri5Options, FnFlow, Gain, HybridArc, HybridObserver, JumpMap, LinearCorrection,
    LinearOutputs, Record, SampledPlant, SamplingRule, SimError, SimOptions, Simulation, simulate,
};

use crate::conditions::reset_matrix;
use crate::error::Error;
use crate::gain::GainSchedule;
use crate::system::Plant;

/// `φ : R^m → R^m`, written into the second argument.
pub type Nonlinearity<'a> = &'a dyn Fn(&[f64], &mut [f64]);

/// `u : R → R^l`, written into the second argument.
pub type Input<'a> = &'a dyn Fn(f64, &mut [f64]);

/// Initial states, horizon and integrator settings of a simulation.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationSetup {
    /// Plant initial state `x(0)`.
    pub x0: Vec<f64>,
    /// Observer initial state `x̂(0)`.
    pub xhat0: Vec<f64>,
    /// Final time.
    pub horizon: f64,
    /// Recording step of the flow (default `Some(0.005)`; `None`: samples only).
    pub record_step: Option<f64>,
    /// Integrator tolerances (default `rtol = 1e-9`, `atol = 1e-12`).
    pub integrator: Dopri5Options,
}

impl SimulationSetup {
    /// `x(0) = x0`, `x̂(0) = xhat0` on `[0, horizon]` with the default recording and integrator.
    pub fn new(x0: Vec<f64>, xhat0: Vec<f64>, horizon: f64) -> Self {
        Self {
            x0,
            xhat0,
            horizon,
            record_step: Some(0.005),
            integrator: Dopri5Options::default(),
        }
    }
}

/// `v ← v + M w` for a matrix `M` and vectors `v, w`.
fn add_mat_vec(m: MatRef<'_, f64>, w: &[f64], v: &mut [f64]) {
    for (i, vi) in v.iter_mut().enumerate() {
        *vi += (0..m.ncols()).map(|k| m[(i, k)] * w[k]).sum::<f64>();
    }
}

/// The flow `f(t, x) = A x + B u(t) + G φ(H x)` of the plant (and of the observer's copy).
fn lipschitz_flow<'a>(
    plant: &'a Plant,
    phi: Nonlinearity<'a>,
    input: Input<'a>,
) -> FnFlow<impl Fn(f64, &[f64], &mut [f64]) + 'a> {
    let (m, l) = (plant.m(), plant.b().ncols());
    let scratch = RefCell::new((vec![0.0; m], vec![0.0; m], vec![0.0; l]));
    FnFlow::new(plant.n(), move |t, x, dx| {
        let mut s = scratch.borrow_mut();
        let (hx, fx, u) = &mut *s;
        dx.fill(0.0);
        add_mat_vec(plant.a(), x, dx);
        hx.fill(0.0);
        add_mat_vec(plant.h(), x, hx);
        phi(hx, fx);
        add_mat_vec(plant.g(), fx, dx);
        if l > 0 {
            input(t, u);
            add_mat_vec(plant.b(), u, dx);
        }
    })
}

/// Simulates plant (1) and observer (3) with gain schedule `gain` under the sampling `rule`.
/// The joint arc stores `(x, x̂)`; [`Simulation::error_arc`] gives `z = x − x̂`.
pub fn simulate_observer<R: SamplingRule + ?Sized>(
    plant: &Plant,
    phi: Nonlinearity<'_>,
    input: Input<'_>,
    gain: &GainSchedule,
    rule: &mut R,
    setup: &SimulationSetup,
) -> Result<Simulation, Error> {
    let n = plant.n();
    for (x, what) in [(&setup.x0, "x(0)"), (&setup.xhat0, "x̂(0)")] {
        check_dimension(what, n, x.len())?;
        check_finite_slice(x, what)?;
    }
    if gain.k0().nrows() != n || gain.k0().ncols() != plant.q() {
        return Err(InputError::mismatch(
            "rows·columns of the observer gain",
            n * plant.q(),
            gain.k0().nrows() * gain.k0().ncols(),
        )
        .into());
    }
    let c = plant.c().to_owned();
    let mut sys = SampledPlant {
        flow: lipschitz_flow(plant, phi, input),
        output: LinearOutputs::new(vec![c.clone()])?,
    };
    let schedule = gain.clone();
    let correction = LinearCorrection::new(
        vec![c],
        vec![Gain::Scheduled(Box::new(move |tau| {
            Ok::<Mat<f64>, SimError>(schedule.at(tau))
        }))],
    )?;
    let mut observer = HybridObserver {
        flow: lipschitz_flow(plant, phi, input),
        jump: correction,
    };
    let mut opts = SimOptions::new(setup.horizon);
    opts.integrator = setup.integrator.clone();
    if let Some(dt) = setup.record_step {
        opts = opts.record(Record::Every(dt));
    }
    Ok(simulate(
        &mut sys,
        &mut observer,
        rule,
        &setup.x0,
        &setup.xhat0,
        &opts,
    )?)
}

/// `z'Pz` (`P` n×n, `z` of length n; both checked by the callers).
fn quadratic(p: MatRef<'_, f64>, z: &[f64]) -> f64 {
    let n = z.len();
    (0..n)
        .map(|i| z[i] * (0..n).map(|k| p[(i, k)] * z[k]).sum::<f64>())
        .sum()
}

/// `V_k = z'P1z` at `t = 0` and just after every sample: `(t_k, V_k)`.
pub fn lyapunov_at_samples(
    error: &HybridArc,
    p1: MatRef<'_, f64>,
) -> Result<Vec<(f64, f64)>, Error> {
    let n = error.dim();
    if p1.nrows() != n || p1.ncols() != n {
        return Err(InputError::mismatch("order of P1 vs error dimension", n, p1.nrows()).into());
    }
    check_finite(p1, "P1")?;
    let first = (!error.is_empty()).then_some(0);
    Ok(first
        .into_iter()
        .chain(error.jumps().into_iter().map(|r| r.after))
        .map(|i| (error.times()[i], quadratic(p1, error.state(i))))
        .collect())
}

/// The greedy worst-case sampling of `sporadic-sim` ([`Adversarial`]) for a design: between
/// samples the error follows the frozen vertex `R_vertex`, at a sample it is reset by
/// `I − K(τ)C` with the length `τ` of the interval that just ended, and each interval is chosen
/// among `grid` points of the window to maximise `z'P1z` after the next reset.
///
/// The reset depends on `τ`, which the adversary's jump map does not see; it is therefore run on
/// the augmented linear state `ζ = (z, s, c)` with `ż = R z`, `ṡ = c`, `ċ = 0`, started at
/// `s = 0, c = 1`, so that `s = τ` at the end of the interval (exactly, by the nilpotent block of
/// `e^{A_aug τ}`), and the reset `(z, s, c) ↦ ((I − K(s)C) z, 0, 1)`. When used as a
/// [`SamplingRule`] the error `ζ = (x − x̂, 0, 1)` is read from the simulation.
pub fn worst_case_sampling(
    plant: &Plant,
    gain: &GainSchedule,
    p1: MatRef<'_, f64>,
    vertex: usize,
    grid: usize,
) -> Result<Adversarial, Error> {
    let n = plant.n();
    let r = plant.vertices().get(vertex).ok_or(InputError::mismatch(
        "vertex index (number of vertices)",
        plant.vertices().len(),
        vertex,
    ))?;
    if p1.nrows() != n || p1.ncols() != n {
        return Err(InputError::mismatch("order of P1", n, p1.nrows()).into());
    }
    check_finite(p1, "P1")?;
    if gain.k0().nrows() != n || gain.k0().ncols() != plant.q() {
        return Err(InputError::mismatch(
            "rows·columns of the observer gain",
            n * plant.q(),
            gain.k0().nrows() * gain.k0().ncols(),
        )
        .into());
    }
    let w = *gain.window();
    let augmented = Mat::from_fn(n + 2, n + 2, |i, j| match (i < n, j < n) {
        (true, true) => r[(i, j)],
        _ => f64::from(i == n && j == n + 1),
    });
    let (schedule, c) = (gain.clone(), plant.c().to_owned());
    let reset = move |zeta: &[f64], out: &mut [f64]| {
        let jump = reset_matrix(schedule.at(zeta[n]).as_ref(), c.as_ref());
        match jump {
            Ok(m) => {
                for (i, o) in out[..n].iter_mut().enumerate() {
                    *o = (0..n).map(|k| m[(i, k)] * zeta[k]).sum();
                }
            }
            // Unreachable for a validated schedule; a NaN makes the adversary report it.
            Err(_) => out[..n].fill(f64::NAN),
        }
        out[n] = 0.0;
        out[n + 1] = 1.0;
    };
    let p = p1.to_owned();
    let v = move |zeta: &[f64]| quadratic(p.as_ref(), &zeta[..n]);
    let error_map = move |x: &[f64], xhat: &[f64]| -> Vec<f64> {
        x.iter()
            .zip(xhat)
            .map(|(a, b)| a - b)
            .chain([0.0, 1.0])
            .collect()
    };
    Ok(Adversarial::new(
        augmented.as_ref(),
        JumpMap::Closure(Box::new(reset)),
        Box::new(v),
        w.t1(),
        w.t2(),
        grid,
    )?
    .with_error_map(Box::new(error_map)))
}

/// Tolerance for "a sample at time `t`": sample times are sums of intervals and may differ from
/// the nominal instant by a few ulp.
const SAMPLE_TIME_SLACK: f64 = 1e-9;

/// `|z(t)|` at time `t` (at a sampling instant: just after the reset; `t` is nudged by `1e-9`
/// so that a sample computed as `t ± ulp` counts as at `t`).
pub fn error_norm_after(error: &HybridArc, t: f64) -> Result<f64, Error> {
    let end = error.times().last().copied().unwrap_or(f64::NAN);
    let z = error.value_at(
        (t + SAMPLE_TIME_SLACK).min(end),
        sporadic_sim::JumpSide::After,
    )?;
    Ok(norm(&z))
}

fn norm(z: &[f64]) -> f64 {
    z.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// `(t_k, |z(t_k)|)` just after the first sample `t_k ≥ t` (within `1e-9`), or `None` if the arc
/// has no such sample. This is the convention of the independent reference simulations
/// (fixed-step RK4) the reproduction compares with, whose "`|z(t)|`" is the error after the
/// first reset at or after `t`.
pub fn error_norm_after_sample(error: &HybridArc, t: f64) -> Option<(f64, f64)> {
    error
        .jumps()
        .into_iter()
        .find(|r| r.t >= t - SAMPLE_TIME_SLACK)
        .map(|r| (r.t, norm(error.state(r.after))))
}
