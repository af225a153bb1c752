//! Simulation of the stochastic error dynamics (53) and of the Lyapunov function (30) along it.
//!
//! ```text
//! flow:  dx̃/dt = A x̃ + d(t),          τ̇ = 1
//! jump (sample of sensor σ after τ ∈ [T_mσ, T_Mσ]):
//!        x̃⁺ = (I − K_σ(τ)C_σ) x̃ − K_σ(τ) w,   τ⁺ = 0,   σ⁺ = Γ(σ)
//! ```
//!
//! The intervals are drawn uniformly in the window of the sensor being sampled (the convention of (9),
//! see [`crate::plant`]: (53) must use the window of the new mode), by
//! [`sporadic_sim::RoundRobin`]. The noise sign is `−K w` as derived from (3) and (11b) (the paper
//! prints `+K w`; irrelevant for symmetric noise). The disturbance is zero-mean uniform in the box
//! `|d_i| ≤ d̄_i`, held constant over `disturbance_period` (the paper does not report the sample rate
//! of its noise generators), so the flow is propagated exactly (block-triangular exponentials).

use faer::Mat;
use sporadic_linalg::InputError;
use sporadic_sim::{
    BoundedUniform, InputSignal, LtiFlow, NoiseSource, PiecewiseConstant, Record, RoundRobin,
    SampleEvent, SimError, SimOptions, simulate_hybrid,
};

use crate::error::{Error, check_positive};
use crate::gain::GainSchedule;
use sporadic_linalg::input::check_finite_slice;

/// Options of [`simulate_error`]. The default is [`SimulationOptions::noise_free`] with a horizon
/// of 10 s from `x̃(0) = (1, …, 1)`.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationOptions {
    /// Final time.
    pub horizon: f64,
    /// Initial error `x̃(0)` (empty: `(1, …, 1)`).
    pub x0: Vec<f64>,
    /// Bounds `d̄_i` of the uniform disturbance (`None`: d = 0). Default `None`.
    pub disturbance: Option<Vec<f64>>,
    /// Hold time of each disturbance sample. Default 10⁻³ s.
    pub disturbance_period: f64,
    /// Per-sensor bounds of the uniform measurement noise (`None`: w = 0). Default `None`.
    pub noise: Option<Vec<Vec<f64>>>,
    /// Recording step of the flow. Default 10⁻³ s.
    pub record_step: f64,
    /// Seed of all random draws (intervals, d, w). Default 1.
    pub seed: u64,
    /// ρ of the Lyapunov function (30) (e.g. [`crate::iss::IssConstants::rho`]; 0 gives `x̃ᵀΦ_σ(τ)x̃`).
    /// Default 0.
    pub rho: f64,
}

impl Default for SimulationOptions {
    fn default() -> Self {
        Self::noise_free(10.0, Vec::new())
    }
}

impl SimulationOptions {
    /// Checks every scalar field and the finiteness of the vectors (their lengths are checked
    /// against the plant by [`simulate_error`]); the error names the offending field.
    ///
    /// # Errors
    /// [`InputError::InvalidParameter`] naming the field, or non-finite entries.
    pub fn validate(&self) -> Result<(), InputError> {
        check_positive("horizon", self.horizon)?;
        check_positive("record_step", self.record_step)?;
        check_positive("disturbance_period", self.disturbance_period)?;
        if !self.rho.is_finite() {
            return Err(InputError::parameter("rho", self.rho, "must be finite"));
        }
        check_finite_slice(&self.x0, "x0")?;
        if let Some(d) = &self.disturbance {
            check_finite_slice(d, "disturbance")?;
        }
        for w in self.noise.iter().flatten() {
            check_finite_slice(w, "noise")?;
        }
        Ok(())
    }

    /// Noise-free run of `horizon` seconds from `x0`.
    pub fn noise_free(horizon: f64, x0: Vec<f64>) -> Self {
        Self {
            horizon,
            x0,
            disturbance: None,
            disturbance_period: 1e-3,
            noise: None,
            record_step: 1e-3,
            seed: 1,
            rho: 0.0,
        }
    }
}

/// One sample (jump) of the simulation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JumpSample {
    /// Sampling instant.
    pub t: f64,
    /// Sensor read (0-based).
    pub sensor: usize,
    /// Interval τ since the previous sample.
    pub tau: f64,
    /// `V` just before the jump.
    pub v_before: f64,
    /// `V` just after the jump.
    pub v_after: f64,
}

/// The simulated error, the mode, the timer and `V` on the recorded hybrid time domain.
#[derive(Debug, Clone)]
pub struct ErrorTrajectory {
    /// Ordinary times.
    pub t: Vec<f64>,
    /// Jump counters.
    pub j: Vec<usize>,
    /// States `x̃` (one row per sample, `n` entries each).
    pub x: Vec<Vec<f64>>,
    /// Mode σ (the sensor to be sampled next, 0-based).
    pub sigma: Vec<usize>,
    /// Timer τ.
    pub tau: Vec<f64>,
    /// Lyapunov function (30).
    pub v: Vec<f64>,
    /// The samples.
    pub jumps: Vec<JumpSample>,
    /// `sup_t |d(t)|` of the realised disturbance.
    pub d_sup: f64,
    /// `sup_j |w_j|` of the realised noise.
    pub w_sup: f64,
}

fn vnorm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Simulates (53) for the observer `gains` (see the module docs).
///
/// # Errors
/// Bad settings (dimensions, non-positive horizon/steps) or a failing kernel.
pub fn simulate_error(
    gains: &GainSchedule,
    settings: &SimulationOptions,
) -> Result<ErrorTrajectory, Error> {
    let plant = gains.plant();
    let n = plant.n();
    settings.validate()?;
    let ones;
    let x0: &[f64] = if settings.x0.is_empty() {
        ones = vec![1.0; n];
        &ones
    } else {
        &settings.x0
    };
    if x0.len() != n {
        return Err(InputError::mismatch("initial error x̃(0)", n, x0.len()).into());
    }
    let mut flow = LtiFlow::new(plant.a())?;
    let mut d_sup = 0.0f64;
    if let Some(bounds) = &settings.disturbance {
        if bounds.len() != n {
            return Err(InputError::mismatch("disturbance bounds", n, bounds.len()).into());
        }
        let mut src = BoundedUniform::symmetric(bounds.clone(), settings.seed.wrapping_add(1))?;
        let count = (settings.horizon / settings.disturbance_period).ceil() as usize + 1;
        let starts: Vec<f64> = (0..count)
            .map(|k| k as f64 * settings.disturbance_period)
            .collect();
        let values: Vec<Vec<f64>> = starts
            .iter()
            .map(|&t| {
                let mut v = vec![0.0; n];
                src.sample(t, &mut v);
                d_sup = d_sup.max(vnorm(&v));
                v
            })
            .collect();
        let signal = InputSignal::PiecewiseConstant(PiecewiseConstant::new(starts, values)?);
        flow = flow.with_input(Mat::<f64>::identity(n, n).as_ref(), signal)?;
    }
    let mut noise: Vec<Option<BoundedUniform>> = Vec::with_capacity(plant.num_sensors());
    match &settings.noise {
        Some(b) => {
            if b.len() != plant.num_sensors() {
                return Err(
                    InputError::mismatch("noise bound sets", plant.num_sensors(), b.len()).into(),
                );
            }
            for (s, (bs, sensor)) in b.iter().zip(plant.sensors()).enumerate() {
                if bs.len() != sensor.outputs() {
                    return Err(InputError::mismatch(
                        format!("noise bounds of sensor {}", s + 1),
                        sensor.outputs(),
                        bs.len(),
                    )
                    .into());
                }
                noise.push(Some(BoundedUniform::symmetric(
                    bs.clone(),
                    settings.seed.wrapping_add(2 + s as u64),
                )?));
            }
        }
        None => noise.extend((0..plant.num_sensors()).map(|_| None)),
    }
    let windows: Vec<(f64, f64)> = plant
        .sensors()
        .iter()
        .map(|s| (s.window().t1(), s.window().t2()))
        .collect();
    let mut rule = RoundRobin::new(&windows, settings.seed)?;
    let mut w_sup = 0.0f64;
    let mut inner: Option<Error> = None;
    let jump = |ev: &SampleEvent, _y: &[f64], x: &mut [f64]| -> Result<(), SimError> {
        let s = ev.sensor;
        let k = match gains.gain(s, ev.elapsed) {
            Ok(k) => k,
            Err(e) => {
                inner = Some(e);
                return Err(SimError::InvalidArgument("gain K_σ(τ) failed".into()));
            }
        };
        let c = plant.sensors()[s].c();
        let m = c.nrows();
        let mut w = vec![0.0; m];
        if let Some(src) = noise[s].as_mut() {
            src.sample(ev.t, &mut w);
            w_sup = w_sup.max(vnorm(&w));
        }
        // x̃⁺ = x̃ − K (C x̃ + w)
        let innov: Vec<f64> = (0..m)
            .map(|i| (0..n).map(|l| c[(i, l)] * x[l]).sum::<f64>() + w[i])
            .collect();
        for (r, xr) in x.iter_mut().enumerate() {
            *xr -= (0..m).map(|i| k[(r, i)] * innov[i]).sum::<f64>();
        }
        Ok(())
    };
    let opts = SimOptions::new(settings.horizon).record(Record::Every(settings.record_step));
    let sim = simulate_hybrid(flow, jump, &mut rule, x0, &opts);
    if let Some(e) = inner {
        return Err(e);
    }
    let sim = sim?;
    let arc = &sim.arc;
    let jump_times = sim.samples.times();
    let n_s = plant.num_sensors();
    let mut out = ErrorTrajectory {
        t: Vec::with_capacity(arc.len()),
        j: Vec::with_capacity(arc.len()),
        x: Vec::with_capacity(arc.len()),
        sigma: Vec::with_capacity(arc.len()),
        tau: Vec::with_capacity(arc.len()),
        v: Vec::with_capacity(arc.len()),
        jumps: Vec::new(),
        d_sup,
        w_sup,
    };
    for (ht, x) in arc.iter() {
        let sigma = ht.j % n_s;
        let t_last = if ht.j == 0 {
            opts.t0
        } else {
            jump_times[ht.j - 1]
        };
        let tau = (ht.t - t_last).max(0.0);
        let phi = gains.phi(sigma, tau)?;
        let q: f64 = (0..n)
            .map(|i| x[i] * (0..n).map(|l| phi[(i, l)] * x[l]).sum::<f64>())
            .sum();
        out.t.push(ht.t);
        out.j.push(ht.j);
        out.x.push(x.to_vec());
        out.sigma.push(sigma);
        out.tau.push(tau);
        out.v.push((-settings.rho * tau).exp() * q);
    }
    for jr in arc.jumps() {
        out.jumps.push(JumpSample {
            t: jr.t,
            sensor: out.sigma[jr.before],
            tau: out.tau[jr.before],
            v_before: out.v[jr.before],
            v_after: out.v[jr.after],
        });
    }
    Ok(out)
}
