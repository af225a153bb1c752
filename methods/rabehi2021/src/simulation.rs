//! Closed-loop simulation of the plant (2)–(3) and the interval observer (4), (8) with
//! `sporadic-sim`: random admissible disturbance (piecewise constant, resampled on a fixed
//! period), bounded measurement noise, random sampling times in `[τmin, τmax]`, and the check of
//! the guaranteed inclusion `x̲ ≤ x ≤ x̄` at every recorded flow point and on both sides of every
//! jump.
//!
//! Both the plant and the observer are LTI with known inputs (an exosystem for `u`, a
//! piecewise-constant `d`, the constants `d̲`, `d̄`), so the simulator propagates them exactly by
//! block-triangular exponentials (Van Loan 1978; `sporadic_sim::LtiPropagator`): the inclusion is
//! checked up to round-off, not up to an integration tolerance.

use faer::Mat;
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_dimension;
use sporadic_linalg::input::check_finite_slice;
use sporadic_sim::{
    BoundedUniform, Exosystem, InputSignal, LtiFlow, PiecewiseConstant, Record, SampledPlant,
    SimError, SimOptions, Simulation, UniformRandom, simulate,
};

use crate::error::Error;
use crate::observer::IntervalObserver;
use sporadic_model::SamplingWindow;

/// The realised measurement noise.
#[derive(Debug, Clone, PartialEq)]
pub enum Noise {
    /// `v ≡ 0`.
    Zero,
    /// `v_k(t) = a_k cos(ω t)` (the example: `0.4 cos(2t)`).
    Cosine {
        /// Amplitudes `a_k` (one per output).
        amplitude: Vec<f64>,
        /// Angular frequency `ω`.
        omega: f64,
    },
}

/// The realised disturbance `d(t)`: piecewise constant, each value drawn uniformly in
/// `[lower, upper]`, resampled every `period` seconds.
#[derive(Debug, Clone, PartialEq)]
pub struct Disturbance {
    /// Lower end of the draws (must be `≥ d̲` of the observer).
    pub lower: Vec<f64>,
    /// Upper end of the draws (must be `≤ d̄` of the observer).
    pub upper: Vec<f64>,
    /// Resampling period.
    pub period: f64,
    /// Seed.
    pub seed: u64,
}

/// Everything the paper leaves open about its simulation (initial state and enclosure,
/// horizon, realised `d(t)`, sampling distribution).
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// `x(0)`.
    pub x0: Vec<f64>,
    /// `x̲(0)` (enclosure (5)).
    pub lower0: Vec<f64>,
    /// `x̄(0)`.
    pub upper0: Vec<f64>,
    /// Final time.
    pub horizon: f64,
    /// Inter-sample times are i.i.d. uniform in this window.
    pub sampling: SamplingWindow,
    /// Seed of the sampling times.
    pub sampling_seed: u64,
    /// The realised disturbance (`None`: `d ≡ 0`).
    pub disturbance: Option<Disturbance>,
    /// The realised noise.
    pub noise: Noise,
    /// `u(t) = Σ a sin(ωt + φ)` as `(a, ω, φ)` terms (empty: `u ≡ 0`; otherwise the plant must
    /// have a single input).
    pub input: Vec<(f64, f64, f64)>,
    /// Also record the flow on a uniform grid of this step (figures); `None`: jumps only.
    pub record_step: Option<f64>,
}

/// Result of the inclusion check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inclusion {
    /// Number of (point, component) pairs checked.
    pub checked: usize,
    /// Pairs with `x̲_i − x_i > tol` or `x_i − x̄_i > tol`, `tol` = [`INCLUSION_TOLERANCE`] times
    /// `max(|x_i|, |x̲_i|, |x̄_i|)` (the round-off of the propagation is relative to the state).
    pub violations: usize,
    /// `max(x̲_i − x_i, x_i − x̄_i)` over everything checked (negative: strictly inside).
    pub worst: f64,
    /// The first recorded time at which a width `x̄_i − x̲_i` is below [`RESOLUTION`] times
    /// `max(|x_i|, |x̲_i|, |x̄_i|)`: from there the bounds differ by little more than the
    /// rounding of the state (an unstable plant's state grows without bound while the width
    /// stays bounded), and widths and inclusion are not resolved in double precision.
    pub unresolved_from: Option<f64>,
}

/// A simulated run: the joint arc `(x, x̲, x̄)` and the inclusion check.
#[derive(Debug, Clone)]
pub struct IntervalRun {
    /// The simulation (plant state, then the observer state `(x̲, x̄)`).
    pub sim: Simulation,
    /// State dimension `n`.
    pub n: usize,
    /// Inclusion check with tolerance [`INCLUSION_TOLERANCE`].
    pub inclusion: Inclusion,
}

/// Tolerance of the inclusion check `x̲ ≤ x ≤ x̄` relative to the magnitude of the state and
/// its bounds (round-off of the exact propagation).
pub const INCLUSION_TOLERANCE: f64 = 1e-9;

/// Relative width below which the bounds are not resolved (see [`Inclusion::unresolved_from`]):
/// `2¹⁰` units of round-off of the state.
pub const RESOLUTION: f64 = 1024.0 * f64::EPSILON;

impl IntervalRun {
    /// Ordinary times of the recorded points.
    pub fn times(&self) -> &[f64] {
        self.sim.arc.times()
    }

    /// Jump counters of the recorded points.
    pub fn jumps(&self) -> &[usize] {
        self.sim.arc.jump_counters()
    }

    fn series(&self, offset: usize) -> Vec<f64> {
        (0..self.sim.arc.len())
            .map(|i| self.sim.arc.state(i)[offset])
            .collect()
    }

    /// `x_k` at the recorded points.
    pub fn state(&self, k: usize) -> Vec<f64> {
        self.series(k)
    }

    /// `x̲_k` at the recorded points.
    pub fn lower(&self, k: usize) -> Vec<f64> {
        self.series(self.n + k)
    }

    /// `x̄_k` at the recorded points.
    pub fn upper(&self, k: usize) -> Vec<f64> {
        self.series(2 * self.n + k)
    }

    /// The width `x̄_k − x̲_k` at the recorded points.
    pub fn width(&self, k: usize) -> Vec<f64> {
        self.upper(k)
            .iter()
            .zip(self.lower(k))
            .map(|(u, l)| u - l)
            .collect()
    }

    /// The interval error `ξ = [x − x̲; x̄ − x]` at recorded point `i`.
    pub fn xi(&self, i: usize) -> Vec<f64> {
        let z = self.sim.arc.state(i);
        let n = self.n;
        (0..n)
            .map(|k| z[k] - z[n + k])
            .chain((0..n).map(|k| z[2 * n + k] - z[k]))
            .collect()
    }

    /// The sampling instants `t_1, t_2, …`.
    pub fn sample_times(&self) -> &[f64] {
        self.sim.samples.times()
    }

    /// The inter-sample intervals `t_{k+1} − t_k` (the first one from `t = 0`).
    pub fn intervals(&self) -> &[f64] {
        self.sim.samples.intervals()
    }
}

fn check_inclusion(sim: &Simulation, n: usize) -> Inclusion {
    let mut out = Inclusion {
        checked: 0,
        violations: 0,
        worst: f64::NEG_INFINITY,
        unresolved_from: None,
    };
    for (t, z) in sim.arc.iter() {
        for k in 0..n {
            let (x, lo, hi) = (z[k], z[n + k], z[2 * n + k]);
            let scale = x.abs().max(lo.abs()).max(hi.abs());
            let gap = (lo - x).max(x - hi);
            out.checked += 1;
            out.worst = out.worst.max(gap);
            if gap > INCLUSION_TOLERANCE * scale {
                out.violations += 1;
            }
            if out.unresolved_from.is_none() && hi - lo < RESOLUTION * scale {
                out.unresolved_from = Some(t.t);
            }
        }
    }
    out
}

fn check_len(v: &[f64], n: usize, what: &str) -> Result<(), Error> {
    check_dimension(&format!("length of {what}"), n, v.len())?;
    Ok(check_finite_slice(v, what)?)
}

/// Simulates the plant and the interval observer under `scenario` and checks the inclusion.
///
/// # Errors
/// Wrong dimensions or non-finite data, an initial enclosure (5) that does not hold
/// ([`Error::InitialEnclosure`]), a realised disturbance or noise outside the bounds the observer
/// assumes ([`Error::InadmissibleSignal`]), or a simulator failure.
pub fn simulate_interval(
    observer: &IntervalObserver,
    scenario: &Scenario,
) -> Result<IntervalRun, Error> {
    let plant = observer.plant();
    let bounds = observer.bounds();
    let (n, p) = (plant.n(), plant.p());
    check_len(&scenario.x0, n, "x0")?;
    check_len(&scenario.lower0, n, "lower0")?;
    check_len(&scenario.upper0, n, "upper0")?;
    for i in 0..n {
        let (lo, x, hi) = (scenario.lower0[i], scenario.x0[i], scenario.upper0[i]);
        if !(lo <= x && x <= hi) {
            return Err(Error::InitialEnclosure {
                index: i,
                lower: lo,
                x,
                upper: hi,
            });
        }
    }
    if !(scenario.horizon > 0.0 && scenario.horizon.is_finite()) {
        return Err(
            InputError::parameter("horizon", scenario.horizon, "must be finite and > 0").into(),
        );
    }
    let (amplitude, omega) = match &scenario.noise {
        Noise::Zero => (vec![0.0; p], 0.0),
        Noise::Cosine { amplitude, omega } => {
            check_len(amplitude, p, "noise amplitude")?;
            if !omega.is_finite() {
                return Err(InputError::non_finite("noise frequency").into());
            }
            (amplitude.clone(), *omega)
        }
    };
    for (k, (&a, &vb)) in amplitude.iter().zip(bounds.v_bar()).enumerate() {
        if a.abs() > vb {
            return Err(Error::InadmissibleSignal {
                what: "noise amplitude",
                index: k,
                value: a,
                lower: -vb,
                upper: vb,
            });
        }
    }
    let input = if scenario.input.is_empty() {
        None
    } else {
        Some(InputSignal::Exosystem(Exosystem::sinusoid_sum(
            &scenario.input,
        )?))
    };
    // A scalar input: the plant must have m = 1 (the simulator reports any other m).
    let mut plant_flow = LtiFlow::new(plant.a())?;
    if let Some(u) = &input {
        plant_flow = plant_flow.with_input(plant.b(), u.clone())?;
    }
    if let Some(d) = &scenario.disturbance {
        check_len(&d.lower, n, "disturbance lower end")?;
        check_len(&d.upper, n, "disturbance upper end")?;
        for i in 0..n {
            if d.lower[i] < bounds.d_lower()[i] || d.upper[i] > bounds.d_upper()[i] {
                return Err(Error::InadmissibleSignal {
                    what: "disturbance range",
                    index: i,
                    value: if d.lower[i] < bounds.d_lower()[i] {
                        d.lower[i]
                    } else {
                        d.upper[i]
                    },
                    lower: bounds.d_lower()[i],
                    upper: bounds.d_upper()[i],
                });
            }
        }
        let mut source = BoundedUniform::new(d.lower.clone(), d.upper.clone(), d.seed)?;
        let signal =
            PiecewiseConstant::sample_and_hold(&mut source, 0.0, d.period, scenario.horizon)?;
        plant_flow = plant_flow.with_input(
            Mat::<f64>::identity(n, n).as_ref(),
            InputSignal::PiecewiseConstant(signal),
        )?;
    }
    let c = plant.c().to_owned();
    let output = move |ev: &sporadic_sim::SampleEvent,
                       x: &[f64],
                       y: &mut Vec<f64>|
          -> Result<(), SimError> {
        for i in 0..c.nrows() {
            let cx: f64 = (0..c.ncols()).map(|k| c[(i, k)] * x[k]).sum();
            y.push(cx + amplitude[i] * (omega * ev.t).cos());
        }
        Ok(())
    };
    let mut sim_plant = SampledPlant {
        flow: plant_flow,
        output,
    };
    let mut sim_observer = observer.hybrid(input)?;
    let mut rule = UniformRandom::new(
        scenario.sampling.t1(),
        scenario.sampling.t2(),
        scenario.sampling_seed,
    )?;
    let mut options = SimOptions::new(scenario.horizon);
    if let Some(dt) = scenario.record_step {
        options = options.record(Record::Every(dt));
    }
    let xhat0: Vec<f64> = scenario
        .lower0
        .iter()
        .chain(&scenario.upper0)
        .copied()
        .collect();
    let sim = simulate(
        &mut sim_plant,
        &mut sim_observer,
        &mut rule,
        &scenario.x0,
        &xhat0,
        &options,
    )?;
    let inclusion = check_inclusion(&sim, n);
    Ok(IntervalRun { sim, n, inclusion })
}
