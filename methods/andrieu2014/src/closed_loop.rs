//! Closed-loop simulation of a plant and the observer (5)–(7) of Andrieu et al. (2014) on the hybrid
//! simulator `sporadic-sim`: adaptive Dormand–Prince 5(4) flows, the sampling rule (7) located as a
//! state-triggered event on the dense output, and the jump of [`crate::observer::jump`].
//!
//! The observer part of the hybrid state is `(x̂, I, L_k, L, M)`:
//! * `x̂' = A x̂ + f(x̂, u)`;
//! * `I' = c(x̂, u)` with `I(t_k) = 0`, giving the gain in closed form `L = L_k exp((a2/a3)(e^{a3 I} − 1))`
//!   ([`crate::high_gain`]), which the sampling rule and the jump use (robust: `L ≥ L_k ≥ 1` holds by
//!   construction);
//! * `L_k' = 0` (the post-jump gain of the current interval, held);
//! * `L' = a2 L M c`, `M' = a3 M c`: the printed ODEs (6a)–(6b), integrated alongside purely as a
//!   cross-check of the closed form ([`SampleRecord::l_minus_integrated`]).
//!
//! The sampling event is `g(s) = s · L(t_k + s) − α` (rising), located by Brent's method on the dense
//! output to `1e-15` of the integrator step that brackets it, i.e. to the resolution of `t`: the step
//! can be many times longer than `δ_k` and `g' = L(1 + s a2 M c)` is large for theorem-conforming
//! tunings, so with `sporadic-sim`'s default `1e-12` the residual `|δ_k L(t_{k+1}^-) − α|` exceeded the
//! tolerance `1e-9 α` asserted for it in the property test; with `1e-15` it is ~4e-12 relative on
//! the theorem-conforming pendulum run ([`crate::pendulum`], `α = 0.2`). The input `u` is piecewise
//! constant; every flow interval between its switches is integrated with the value valid on it
//! (left limit at the switch, `sporadic_sim::Flow::rhs_left`).
//!
//! **Sampling instants.** The sampling sequence of (2), (7) starts at `t_0 = 0`. The reading `y_0` there
//! is not used: (5) at `k = 0` would need `δ_{−1}` and `L(t_0^-)`, and the proof of Theorem 2 starts
//! from `E_0` with no correction (the paper does not say whether `y_0` is used). The first
//! correction is at `t_1`, so a run over `[0, T]` has `samples.len()` corrections and
//! `samples.len() + 1` sampling instants ([`Run::sampling_times`]).

use sporadic_linalg::InputError;
use sporadic_linalg::input::check_len;
use sporadic_linalg::input::{check_dimension, check_finite_slice};
use std::cell::{Cell, RefCell};

use sporadic_sim::{
    Dopri5Options, Dopri5Stats, Flow, HybridArc, HybridObserver, NoiseSource, PiecewiseConstant,
    Record, SampleContext, SampleEvent, SampledPlant, SamplingRule, SimError, SimOptions, Trigger,
    simulate,
};

use crate::error::Error;
use crate::observer::{Tuning, high_gain, jump, sampling_function};
use crate::system::{Plant, TriangularSystem, vector_field};

/// Number of extra observer states after `x̂`: `I, L_k, L, M`.
const EXTRA: usize = 4;

/// Tolerance of the sampling event relative to the bracketing step (module documentation).
const EVENT_TOL: f64 = 1e-15;

/// Settings of a closed-loop run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOptions {
    /// Final time.
    pub horizon: f64,
    /// Initial gain `L(0) ≥ 1`.
    pub l0: f64,
    /// Relative tolerance of the integrator.
    pub rtol: f64,
    /// Absolute tolerance of the integrator.
    pub atol: f64,
    /// Record every accepted integrator step (for figures and the monotonicity check of `L`); otherwise
    /// only the pre/post-jump states.
    pub record_steps: bool,
    /// Stop after this many samples.
    pub max_samples: Option<usize>,
}

impl RunOptions {
    /// `[0, horizon]`, `L(0) = 1`, `rtol = 1e-9`, `atol = 1e-12` (reproduction settings, not given
    /// in the paper), steps recorded.
    pub fn new(horizon: f64) -> Self {
        Self {
            horizon,
            l0: 1.0,
            rtol: 1e-9,
            atol: 1e-12,
            record_steps: true,
            max_samples: None,
        }
    }
}

/// Everything about one measurement `k ≥ 1` of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct SampleRecord {
    /// Sample time `t_k`.
    pub t: f64,
    /// The period that ends here, `δ_{k−1} = t_k − t_{k−1}`.
    pub delta: f64,
    /// Gain at the start of the period, `L(t_{k−1})`.
    pub l_start: f64,
    /// Pre-jump gain `L(t_k^-)` from the closed form.
    pub l_minus: f64,
    /// Pre-jump `M(t_k^-)` from the closed form `e^{a3 I}`.
    pub m_minus: f64,
    /// Pre-jump gain from integrating (6a) directly.
    pub l_minus_integrated: f64,
    /// Pre-jump `M` from integrating (6b) directly.
    pub m_minus_integrated: f64,
    /// `I = ∫_{t_{k−1}}^{t_k} c(x̂, u)`.
    pub integral: f64,
    /// Post-jump gain `L(t_k)` (6c).
    pub l_plus: f64,
    /// The measurement `y_k` (with noise).
    pub y: f64,
    /// The noise-free output `h(z(t_k))`.
    pub output: f64,
    /// Plant state in normal-form coordinates, `x(t_k) = Φ(z(t_k))`.
    pub x: Vec<f64>,
    /// Estimate before the correction, `x̂(t_k^-)`.
    pub xhat_minus: Vec<f64>,
    /// Estimate after the correction, `x̂(t_k)`.
    pub xhat_plus: Vec<f64>,
}

impl SampleRecord {
    /// Post-jump estimation error `e_k = x̂(t_k) − x(t_k)`.
    pub fn error(&self) -> Vec<f64> {
        self.xhat_plus
            .iter()
            .zip(&self.x)
            .map(|(a, b)| a - b)
            .collect()
    }
    /// Pre-jump estimation error `x̂(t_k^-) − x(t_k)`.
    pub fn error_minus(&self) -> Vec<f64> {
        self.xhat_minus
            .iter()
            .zip(&self.x)
            .map(|(a, b)| a - b)
            .collect()
    }
}

/// The result of [`run`].
#[derive(Debug, Clone)]
pub struct Run {
    /// One record per measurement, in time order.
    pub samples: Vec<SampleRecord>,
    /// The joint hybrid arc `(z, x̂, I, L_k, L, M)` (plant state first, `plant_dim` components).
    pub arc: HybridArc,
    /// Plant dimension `m`.
    pub plant_dim: usize,
    /// Observer order `n`.
    pub order: usize,
    /// Initial plant state in normal-form coordinates, `x(0)`.
    pub x0: Vec<f64>,
    /// Initial estimate `x̂(0)`.
    pub xhat0: Vec<f64>,
    /// Initial gain `L(0)`.
    pub l0: f64,
    /// Largest `c(x̂, u)` over the recorded points (the run's `c_m` for Lemma 1).
    pub c_max: f64,
    /// Integrator work.
    pub stats: Dopri5Stats,
}

impl Run {
    /// Time series of the closed-form gain `L(t)` at the recorded points, as `(t, j, L)` for hybrid plots.
    pub fn gain_series(&self, tuning: &Tuning) -> (Vec<f64>, Vec<usize>, Vec<f64>) {
        let (m, n) = (self.plant_dim, self.order);
        let l = self
            .arc
            .map(|z| high_gain(tuning, z[m + n + 1], z[m + n]).0);
        (
            self.arc.times().to_vec(),
            self.arc.jump_counters().to_vec(),
            l,
        )
    }

    /// The sampling instants `t_0 = 0, t_1, …, t_N` of (7) in the run: `t_0` (no correction, see the
    /// module documentation) followed by the times of the `N = samples.len()` corrections.
    pub fn sampling_times(&self) -> Vec<f64> {
        std::iter::once(0.0)
            .chain(self.samples.iter().map(|s| s.t))
            .collect()
    }

    /// Component `i` of the estimate `x̂` at the recorded points.
    pub fn estimate_component(&self, i: usize) -> Vec<f64> {
        let m = self.plant_dim;
        self.arc.map(|z| z[m + i])
    }

    /// Component `i` of the plant state `z` at the recorded points.
    pub fn plant_component(&self, i: usize) -> Vec<f64> {
        self.arc.map(|z| z[i])
    }

    /// The final estimate `x̂(T)`.
    pub fn final_estimate(&self) -> Vec<f64> {
        let (_, z) = self
            .arc
            .last()
            .expect("a run records at least its initial state");
        z[self.plant_dim..self.plant_dim + self.order].to_vec()
    }

    /// The final plant state `z(T)` (plant coordinates).
    pub fn final_plant_state(&self) -> Vec<f64> {
        let (_, z) = self
            .arc
            .last()
            .expect("a run records at least its initial state");
        z[..self.plant_dim].to_vec()
    }
}

/// The plant's flow `ż = F(z, u(t))`. The simulator integrates each interval between switches of `u`
/// with the input valid on it (`rhs_left` at the interval's end, `sporadic_sim::integrate_flow`).
struct PlantFlow<'a, P: ?Sized> {
    plant: &'a P,
    input: &'a PiecewiseConstant,
}

impl<P: Plant + ?Sized> Flow for PlantFlow<'_, P> {
    fn dim(&self) -> usize {
        self.plant.dim()
    }
    fn rhs(&self, t: f64, z: &[f64], dz: &mut [f64]) {
        self.plant.rhs(z, self.input.value(t), dz);
    }
    fn rhs_left(&self, t: f64, z: &[f64], dz: &mut [f64]) {
        self.plant.rhs(z, self.input.left_limit(t), dz);
    }
    fn next_breakpoint(&self, t: f64) -> Option<f64> {
        self.input.next_breakpoint(t)
    }
}

/// The observer's flow on `[t_k, t_{k+1})`: (5) for `x̂`, `I' = c`, and (6a)–(6b) for the cross-check.
struct ObserverFlow<'a, S: ?Sized> {
    system: &'a S,
    tuning: &'a Tuning,
    input: &'a PiecewiseConstant,
    /// First invalid `c` seen: `(c, t)`.
    bad_c: Cell<Option<(f64, f64)>>,
}

impl<S: TriangularSystem + ?Sized> ObserverFlow<'_, S> {
    fn eval(&self, t: f64, u: &[f64], o: &[f64], d: &mut [f64]) {
        let n = self.system.order();
        vector_field(self.system, &o[..n], u, &mut d[..n]);
        let c = self.system.lipschitz(&o[..n], u);
        if !(c.is_finite() && c >= 0.0) {
            if self.bad_c.get().is_none() {
                self.bad_c.set(Some((c, t)));
            }
            d.fill(f64::NAN);
            return;
        }
        let (l, m) = (o[n + 2], o[n + 3]);
        d[n] = c;
        d[n + 1] = 0.0;
        d[n + 2] = self.tuning.a2() * l * m * c;
        d[n + 3] = self.tuning.a3() * m * c;
    }
}

impl<S: TriangularSystem + ?Sized> Flow for ObserverFlow<'_, S> {
    fn dim(&self) -> usize {
        self.system.order() + EXTRA
    }
    fn rhs(&self, t: f64, o: &[f64], d: &mut [f64]) {
        self.eval(t, self.input.value(t), o, d);
    }
    fn rhs_left(&self, t: f64, o: &[f64], d: &mut [f64]) {
        self.eval(t, self.input.left_limit(t), o, d);
    }
    fn next_breakpoint(&self, t: f64) -> Option<f64> {
        self.input.next_breakpoint(t)
    }
}

/// The sampling rule (7) as a state-triggered rule of the simulator.
struct UpdatedSampling<'a> {
    tuning: &'a Tuning,
    n: usize,
}

impl SamplingRule for UpdatedSampling<'_> {
    fn next_sample(&mut self, _ctx: &SampleContext<'_>) -> Result<Trigger, SimError> {
        Ok(Trigger::Event {
            sensor: 0,
            max_interval: f64::INFINITY,
        })
    }
    fn guard(&self, elapsed: f64, _plant: &[f64], o: &[f64]) -> f64 {
        let (l, _) = high_gain(self.tuning, o[self.n + 1], o[self.n]);
        sampling_function(self.tuning, elapsed, l)
    }
}

/// Simulates `plant` from `z0` with the observer for `system` from `x̂(0) = xhat0`, `L(0) = opts.l0`,
/// `M(0) = 1`, under the input `input` and additive output noise `noise` (dimension 1; use
/// `sporadic_sim::ZeroNoise::new(1)` for noise-free runs), on `[0, opts.horizon]`.
///
/// Errors: dimension mismatches and non-finite inputs ([`Error::Input`] (`DimensionMismatch`),
/// [`Error::Input`] (`NonFinite`)), `L(0) < 1`, a negative or non-finite `c(x̂, u)` at any evaluation
/// ([`Error::NegativeLipschitz`] / [`Error::Input`] (`NonFinite`)), and simulator failures ([`Error::Sim`]).
pub fn run<P, S>(
    plant: &P,
    z0: &[f64],
    system: &S,
    xhat0: &[f64],
    input: &PiecewiseConstant,
    tuning: &Tuning,
    noise: &mut dyn NoiseSource,
    opts: &RunOptions,
) -> Result<Run, Error>
where
    P: Plant + ?Sized,
    S: TriangularSystem + ?Sized,
{
    let n = system.order();
    let m = plant.dim();
    if n == 0 {
        return Err(InputError::mismatch("system order n (at least)", 1, 0).into());
    }
    check_len(tuning.gain(), n, "gain K")?;
    check_dimension("initial plant state", m, z0.len())?;
    check_dimension("initial estimate", n, xhat0.len())?;
    check_finite_slice(z0, "initial plant state")?;
    check_finite_slice(xhat0, "initial estimate")?;
    if input.dim() != system.input_dim() {
        return Err(
            InputError::mismatch("input dimension", system.input_dim(), input.dim()).into(),
        );
    }
    if noise.dim() != 1 {
        return Err(InputError::mismatch("output noise dimension", 1, noise.dim()).into());
    }
    if !(opts.l0.is_finite() && opts.l0 >= 1.0) {
        return Err(InputError::parameter("L(0)", opts.l0, "need a finite L(0) >= 1").into());
    }
    if !(opts.horizon.is_finite() && opts.horizon > 0.0) {
        return Err(
            InputError::parameter("horizon", opts.horizon, "need a finite horizon > 0").into(),
        );
    }
    let mut x0 = vec![0.0; n];
    plant.to_normal_form(z0, &mut x0);

    let observer_flow = ObserverFlow {
        system,
        tuning,
        input,
        bad_c: Cell::new(None),
    };
    let jump_error: RefCell<Option<Error>> = RefCell::new(None);
    let sim = {
        let mut sampled_plant = SampledPlant {
            flow: PlantFlow { plant, input },
            output: |ev: &SampleEvent, z: &[f64], y: &mut Vec<f64>| {
                let mut v = [0.0];
                noise.sample(ev.t, &mut v);
                y.push(plant.output(z) + v[0]);
                Ok(())
            },
        };
        let mut observer = HybridObserver {
            flow: &observer_flow,
            jump: |ev: &SampleEvent, y: &[f64], o: &mut [f64]| {
                let (l_minus, _) = high_gain(tuning, o[n + 1], o[n]);
                match jump(tuning, &o[..n], l_minus, ev.elapsed, y[0]) {
                    Ok(j) => {
                        o[..n].copy_from_slice(&j.xhat);
                        o[n] = 0.0;
                        o[n + 1] = j.l;
                        o[n + 2] = j.l;
                        o[n + 3] = 1.0;
                        Ok(())
                    }
                    Err(e) => {
                        let msg = format!("observer jump at t = {}: {e}", ev.t);
                        *jump_error.borrow_mut() = Some(e);
                        Err(SimError::InvalidArgument(msg))
                    }
                }
            },
        };
        let mut rule = UpdatedSampling { tuning, n };
        let mut obs0 = xhat0.to_vec();
        obs0.extend_from_slice(&[0.0, opts.l0, opts.l0, 1.0]);
        let mut sim_opts = SimOptions::new(opts.horizon).record(if opts.record_steps {
            Record::Steps
        } else {
            Record::JumpsOnly
        });
        sim_opts.max_jumps = opts.max_samples;
        sim_opts.integrator = Dopri5Options {
            event_tol: EVENT_TOL,
            ..Dopri5Options::with_tolerances(opts.rtol, opts.atol)
        };
        simulate(
            &mut sampled_plant,
            &mut observer,
            &mut rule,
            z0,
            &obs0,
            &sim_opts,
        )
    };
    if let Some((c, t)) = observer_flow.bad_c.get() {
        return Err(if c.is_nan() || c.is_infinite() {
            InputError::non_finite(format!("Lipschitz estimate c(x̂, u) at t = {t}")).into()
        } else {
            Error::NegativeLipschitz { c, t }
        });
    }
    if let Some(e) = jump_error.into_inner() {
        return Err(e);
    }
    let sim = sim?;

    let arc = sim.arc;
    let jumps = arc.jumps();
    let mut samples = Vec::with_capacity(jumps.len());
    // The simulator logs one measurement per jump, in the same order.
    let measurements = (0..sim.samples.len()).filter_map(|k| sim.samples.get(k));
    for (jr, meas) in jumps.iter().zip(measurements) {
        let pre = arc.state(jr.before);
        let post = arc.state(jr.after);
        let (oz, op) = (&pre[m..], &post[m..]);
        let (l_minus, m_minus) = high_gain(tuning, oz[n + 1], oz[n]);
        let mut x = vec![0.0; n];
        plant.to_normal_form(&pre[..m], &mut x);
        samples.push(SampleRecord {
            t: jr.t,
            delta: meas.elapsed,
            l_start: oz[n + 1],
            l_minus,
            m_minus,
            l_minus_integrated: oz[n + 2],
            m_minus_integrated: oz[n + 3],
            integral: oz[n],
            l_plus: op[n + 1],
            y: meas.y[0],
            output: plant.output(&pre[..m]),
            x,
            xhat_minus: oz[..n].to_vec(),
            xhat_plus: op[..n].to_vec(),
        });
    }
    // c_m: the largest c over the recorded points, on both sides of every input switch.
    let mut c_max = 0.0f64;
    for (ht, z) in arc.iter() {
        let xhat = &z[m..m + n];
        c_max = c_max
            .max(system.lipschitz(xhat, input.value(ht.t)))
            .max(system.lipschitz(xhat, input.left_limit(ht.t)));
    }
    Ok(Run {
        samples,
        arc,
        plant_dim: m,
        order: n,
        x0,
        xhat0: xhat0.to_vec(),
        l0: opts.l0,
        c_max,
        stats: sim.integrator_stats,
    })
}
