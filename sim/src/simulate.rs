//! The simulation driver: plant + observer + sampling rule → hybrid arc.
//!
//! The closed loop is the hybrid system with state `(x, x̂)`: both flow with their own flow maps between
//! samples; at a sample `t_k` the plant is measured, `y_k = h_σ(x(t_k))`, and the observer jumps,
//! `x̂(t_k⁺) = g(x̂(t_k), y_k)`. This is the structure shared by the observers of Ferrante et al. (2016)
//! (3), Sferlazza et al. (2021) (11), Andrieu et al. (2014) (5)–(7), Etienne et al. (2017) (3) and the
//! interval observer of Rabehi et al. (4), (8).
//!
//! Two flow engines are used:
//! * **exact** — when both flows are LTI ([`crate::Flow::as_lti`]) and the rule is interval-based, the
//!   flows are propagated exactly ([`crate::LtiPropagator`]), which is both the most accurate and the
//!   fastest path;
//! * **adaptive** — otherwise the joint state is integrated with Dormand–Prince 5(4)
//!   ([`crate::Dopri5`]), restarted at the samples and at input switching times, and state-triggered
//!   samples are located on its dense output.
//!
//! **Limits at switching and sampling times.** Each flow interval is integrated with the dynamics valid
//! on it: inputs that switch at `b` enter with their left limit `u(b⁻)` at the end of the interval that
//! ends at `b` and with `u(b) = u(b⁺)` from `b` on ([`crate::flow::integrate_flow`]). At a sample `t_k`
//! the output and the jump map see the pre-jump state `(x(t_k), x̂(t_k⁻))`, reached with those left
//! limits; the next flow starts from the post-jump state with the right limits. A sample and a switch
//! at the same instant are therefore ordered flow → jump → flow with the new input, whichever the
//! engine.
//!
//! Sample times are `t_k = t_{k−1} + interval_k`; a sample falling exactly on the horizon is taken. Sample
//! times accumulate rounding errors, so a scheduled time may fall one rounding error short of the horizon
//! or of an input switch: the flow over such a sliver is one integrator step that lands exactly on the
//! scheduled time (never a step-size underflow).

use crate::arc::HybridArc;
use crate::dopri5::{Dopri5, Dopri5Options, Dopri5Stats, Outcome};
use crate::error::SimError;
use crate::event::{Direction, Event};
use crate::flow::{Flow, LtiPropagator, integrate_flow};
use crate::sampling::{SampleContext, SamplingRule, Trigger};
use crate::system::{HybridObserver, Jump, NoPlant, Observer, Plant, SampleEvent};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite_slice;
use sporadic_linalg::input::check_len;

/// Which samples of the arc are stored.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Record {
    /// Initial state, the pre- and post-jump states at every sample, and the final state.
    JumpsOnly,
    /// As [`Record::JumpsOnly`], plus the flow on the grid `t0 + k·dt`.
    Every(f64),
    /// As [`Record::JumpsOnly`], plus every accepted integrator step (exact flows: same as `JumpsOnly`).
    Steps,
}

/// Settings of a simulation.
#[derive(Debug, Clone, PartialEq)]
pub struct SimOptions {
    /// Initial time.
    pub t0: f64,
    /// Final ordinary time (may be `f64::INFINITY` when `max_jumps` is set).
    pub horizon: f64,
    /// Stop after this many jumps.
    pub max_jumps: Option<usize>,
    /// What to record.
    pub record: Record,
    /// Settings of the adaptive integrator.
    pub integrator: Dopri5Options,
    /// Use the adaptive integrator even when exact LTI propagation is possible (for cross-checks).
    pub force_integrator: bool,
}

impl SimOptions {
    /// Simulate on `[0, horizon]`, recording jumps only, with the default integrator settings.
    pub fn new(horizon: f64) -> Self {
        Self {
            t0: 0.0,
            horizon,
            max_jumps: None,
            record: Record::JumpsOnly,
            integrator: Dopri5Options::default(),
            force_integrator: false,
        }
    }

    /// Simulate until `jumps` samples have been taken (no time limit).
    pub fn jumps(jumps: usize) -> Self {
        Self {
            max_jumps: Some(jumps),
            ..Self::new(f64::INFINITY)
        }
    }

    /// Sets the recording mode.
    pub fn record(mut self, record: Record) -> Self {
        self.record = record;
        self
    }

    fn validate(&self) -> Result<(), SimError> {
        if !self.t0.is_finite() {
            return Err(InputError::non_finite("initial time").into());
        }
        if self.horizon.is_nan() || self.horizon < self.t0 {
            return Err(SimError::invalid(format!(
                "horizon {} precedes t0 = {}",
                self.horizon, self.t0
            )));
        }
        if self.horizon.is_infinite() && self.max_jumps.is_none() {
            return Err(SimError::invalid("an infinite horizon needs max_jumps"));
        }
        if let Record::Every(dt) = self.record
            && !(dt > 0.0 && dt.is_finite())
        {
            return Err(SimError::invalid(format!(
                "recording step must be finite and > 0, got {dt}"
            )));
        }
        Ok(())
    }
}

/// The measurements taken during a simulation, stored as a struct of arrays.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SampleLog {
    t: Vec<f64>,
    sensor: Vec<usize>,
    elapsed: Vec<f64>,
    y_start: Vec<usize>,
    y: Vec<f64>,
}

/// One measurement of a [`SampleLog`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measurement<'a> {
    /// Sampling instant.
    pub t: f64,
    /// Sensor.
    pub sensor: usize,
    /// Interval since the previous sample.
    pub elapsed: f64,
    /// Measured output.
    pub y: &'a [f64],
}

impl SampleLog {
    fn push(&mut self, ev: &SampleEvent, y: &[f64]) {
        self.t.push(ev.t);
        self.sensor.push(ev.sensor);
        self.elapsed.push(ev.elapsed);
        self.y_start.push(self.y.len());
        self.y.extend_from_slice(y);
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// `true` when no sample was taken.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Sampling instants.
    pub fn times(&self) -> &[f64] {
        &self.t
    }

    /// Sensor of every sample.
    pub fn sensors(&self) -> &[usize] {
        &self.sensor
    }

    /// Inter-sample intervals (the first one measured from the initial time).
    pub fn intervals(&self) -> &[f64] {
        &self.elapsed
    }

    /// Measurement `k` (`None` if out of range).
    pub fn get(&self, k: usize) -> Option<Measurement<'_>> {
        let start = *self.y_start.get(k)?;
        let end = self.y_start.get(k + 1).copied().unwrap_or(self.y.len());
        Some(Measurement {
            t: self.t[k],
            sensor: self.sensor[k],
            elapsed: self.elapsed[k],
            y: &self.y[start..end],
        })
    }
}

/// The result of a simulation.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// The joint arc `(x, x̂)` (plant components first).
    pub arc: HybridArc,
    /// Plant dimension.
    pub plant_dim: usize,
    /// Observer dimension.
    pub observer_dim: usize,
    /// The measurements.
    pub samples: SampleLog,
    /// Whether the exact LTI engine was used.
    pub exact: bool,
    /// Work of the adaptive integrator (zero for exact runs).
    pub integrator_stats: Dopri5Stats,
}

impl Simulation {
    /// The plant part of the arc.
    pub fn plant_arc(&self) -> Result<HybridArc, SimError> {
        self.arc.select(0..self.plant_dim)
    }

    /// The observer part of the arc.
    pub fn observer_arc(&self) -> Result<HybridArc, SimError> {
        self.arc
            .select(self.plant_dim..self.plant_dim + self.observer_dim)
    }

    /// The estimation error `x − x̂` (plant and observer of equal dimension).
    pub fn error_arc(&self) -> Result<HybridArc, SimError> {
        if self.plant_dim != self.observer_dim {
            return Err(InputError::mismatch(
                "observer dimension for the error x − x̂",
                self.plant_dim,
                self.observer_dim,
            )
            .into());
        }
        let n = self.plant_dim;
        let mut out = HybridArc::with_capacity(n, self.arc.len());
        let mut e = vec![0.0; n];
        for (ht, z) in self.arc.iter() {
            for i in 0..n {
                e[i] = z[i] - z[n + i];
            }
            out.push_unchecked(ht.t, ht.j, &e);
        }
        Ok(out)
    }
}

/// Simulates a closed hybrid system `ẋ = f(t, x)`, `x⁺ = g(x)` under a sampling rule (the jump map gets an
/// empty measurement). The arc is the system's own state.
pub fn simulate_hybrid<F: Flow, J: Jump, R: SamplingRule + ?Sized>(
    flow: F,
    jump: J,
    rule: &mut R,
    x0: &[f64],
    opts: &SimOptions,
) -> Result<Simulation, SimError> {
    let mut sys = HybridObserver { flow, jump };
    simulate(&mut NoPlant, &mut sys, rule, &[], x0, opts)
}

/// Event function of a state-triggered rule, in the joint state.
type Guard<'a> = &'a dyn Fn(f64, &[f64]) -> f64;

/// The flow of the joint state `(x, x̂)`: plant and observer flow side by side; the breakpoints are
/// those of both.
struct JointFlow<'a> {
    plant: &'a dyn Flow,
    observer: &'a dyn Flow,
    np: usize,
}

impl Flow for JointFlow<'_> {
    fn dim(&self) -> usize {
        self.np + self.observer.dim()
    }
    fn rhs(&self, t: f64, z: &[f64], dz: &mut [f64]) {
        let (dp, dq) = dz.split_at_mut(self.np);
        self.plant.rhs(t, &z[..self.np], dp);
        self.observer.rhs(t, &z[self.np..], dq);
    }
    fn rhs_left(&self, t: f64, z: &[f64], dz: &mut [f64]) {
        let (dp, dq) = dz.split_at_mut(self.np);
        self.plant.rhs_left(t, &z[..self.np], dp);
        self.observer.rhs_left(t, &z[self.np..], dq);
    }
    fn next_breakpoint(&self, t: f64) -> Option<f64> {
        [
            self.plant.next_breakpoint(t),
            self.observer.next_breakpoint(t),
        ]
        .into_iter()
        .flatten()
        .reduce(f64::min)
    }
}

/// Exact propagators of the plant and observer flows (`None` for an empty part).
struct ExactEngine {
    plant: Option<LtiPropagator>,
    observer: Option<LtiPropagator>,
}

struct Driver<'a, P: ?Sized, O: ?Sized> {
    plant: &'a mut P,
    observer: &'a mut O,
    np: usize,
    z: Vec<f64>,
    t: f64,
    j: usize,
    t_last: f64,
    arc: HybridArc,
    log: SampleLog,
    y: Vec<f64>,
    opts: &'a SimOptions,
}

/// Simulates plant + observer under `rule` from `(x0, x̂0)` (see the module documentation).
pub fn simulate<P, O, R>(
    plant: &mut P,
    observer: &mut O,
    rule: &mut R,
    x0: &[f64],
    xhat0: &[f64],
    opts: &SimOptions,
) -> Result<Simulation, SimError>
where
    P: Plant + ?Sized,
    O: Observer + ?Sized,
    R: SamplingRule + ?Sized,
{
    opts.validate()?;
    let np = plant.flow().dim();
    let no = observer.flow().dim();
    check_len(x0, np, "initial plant state")?;
    check_len(xhat0, no, "initial observer state")?;
    check_finite_slice(x0, "initial plant state")?;
    check_finite_slice(xhat0, "initial observer state")?;
    let lti_ok = |f: &dyn Flow| f.dim() == 0 || f.as_lti().is_some();
    let exact_possible = !opts.force_integrator && lti_ok(plant.flow()) && lti_ok(observer.flow());
    let mut exact = if exact_possible {
        let mk = |f: &dyn Flow| f.as_lti().map(|l| l.propagator()).transpose();
        Some(ExactEngine {
            plant: mk(plant.flow())?,
            observer: mk(observer.flow())?,
        })
    } else {
        None
    };
    let mut dp = Dopri5::new(opts.integrator.clone())?;
    let mut z = Vec::with_capacity(np + no);
    z.extend_from_slice(x0);
    z.extend_from_slice(xhat0);
    let mut d = Driver {
        plant,
        observer,
        np,
        z,
        t: opts.t0,
        j: 0,
        t_last: opts.t0,
        arc: HybridArc::new(np + no),
        log: SampleLog::default(),
        y: Vec::new(),
        opts,
    };
    if let (Some(m), Record::JumpsOnly) = (opts.max_jumps, opts.record) {
        // Two samples per jump plus the ends; capped so that a huge budget cannot exhaust memory up front.
        d.arc.reserve(2 * m.min(1 << 24) + 2);
    }
    d.arc.push_unchecked(d.t, 0, &d.z);
    let mut used_integrator = exact.is_none();
    loop {
        if d.j > 0 && d.t >= opts.horizon {
            break;
        }
        let trigger = {
            let ctx = SampleContext {
                t: d.t,
                j: d.j,
                plant: &d.z[..np],
                observer: &d.z[np..],
            };
            rule.next_sample(&ctx)?
        };
        match trigger {
            Trigger::Never => {
                if opts.horizon.is_finite() && opts.horizon > d.t {
                    d.flow_plain(exact.as_mut(), &mut dp, opts.horizon)?;
                    d.record_current();
                }
                break;
            }
            Trigger::After { interval, sensor } => {
                if !(interval.is_finite() && interval >= 0.0) || (d.j > 0 && interval == 0.0) {
                    return Err(SimError::invalid(format!(
                        "sampling rule returned the interval {interval} after {} samples (need > 0)",
                        d.j
                    )));
                }
                let t_next = d.t_last + interval;
                if t_next > opts.horizon {
                    if opts.horizon > d.t {
                        d.flow_plain(exact.as_mut(), &mut dp, opts.horizon)?;
                        d.record_current();
                    }
                    break;
                }
                d.flow_plain(exact.as_mut(), &mut dp, t_next)?;
                d.sample(sensor, interval)?;
            }
            Trigger::Event {
                sensor,
                max_interval,
            } => {
                if max_interval.is_nan() || max_interval <= 0.0 {
                    return Err(SimError::invalid(format!(
                        "max_interval must be > 0, got {max_interval}"
                    )));
                }
                let t_cap = d.t_last + max_interval;
                let t_stop = t_cap.min(opts.horizon);
                if !t_stop.is_finite() {
                    return Err(SimError::invalid(
                        "state-triggered sampling needs a finite horizon or max_interval",
                    ));
                }
                used_integrator = true;
                let t_last = d.t_last;
                let np = d.np;
                let guard = |t: f64, z: &[f64]| rule.guard(t - t_last, &z[..np], &z[np..]);
                let hit = d.flow_adaptive(&mut dp, t_stop, Some(&guard))?;
                if hit || t_stop == t_cap {
                    let elapsed = d.t - d.t_last;
                    d.sample(sensor, elapsed)?;
                } else {
                    d.record_current();
                    break;
                }
            }
        }
        if opts.max_jumps.is_some_and(|m| d.j >= m) {
            break;
        }
    }
    let integrator_stats = dp.stats();
    let no = d.z.len() - np;
    Ok(Simulation {
        arc: d.arc,
        plant_dim: np,
        observer_dim: no,
        samples: d.log,
        exact: !used_integrator,
        integrator_stats,
    })
}

/// Recording grid times `t0 + k·dt` strictly inside `(from, to)` (none unless recording on a grid).
fn grid_points(opts: &SimOptions, from: f64, to: f64) -> Vec<f64> {
    let Record::Every(dt) = opts.record else {
        return Vec::new();
    };
    let mut k = ((from - opts.t0) / dt).floor() as i64 + 1;
    let mut out = Vec::new();
    loop {
        let g = opts.t0 + k as f64 * dt;
        if g >= to {
            return out;
        }
        if g > from {
            out.push(g);
        }
        k += 1;
    }
}

impl<P: Plant + ?Sized, O: Observer + ?Sized> Driver<'_, P, O> {
    /// Flows from the current time to `t_to` (no event), recording according to the options. Does not
    /// record the state at `t_to`.
    fn flow_plain(
        &mut self,
        exact: Option<&mut ExactEngine>,
        dp: &mut Dopri5,
        t_to: f64,
    ) -> Result<(), SimError> {
        match exact {
            Some(ExactEngine { plant, observer }) => {
                let np = self.np;
                let grid = grid_points(self.opts, self.t, t_to);
                for g in grid.into_iter().chain(std::iter::once(t_to)) {
                    let tau = g - self.t;
                    let (zp, zo) = self.z.split_at_mut(np);
                    if let Some(p) = plant.as_mut() {
                        p.advance(self.t, zp, tau)?;
                    }
                    if let Some(o) = observer.as_mut() {
                        o.advance(self.t, zo, tau)?;
                    }
                    self.t = g;
                    if g < t_to {
                        self.arc.push_unchecked(g, self.j, &self.z);
                    }
                }
                check_finite_slice(&self.z, "state after an exact flow")?;
                Ok(())
            }
            None => {
                self.flow_adaptive(dp, t_to, None)?;
                Ok(())
            }
        }
    }

    /// Integrates the joint flow to `t_to` (stopping at the flows' breakpoints, with the inputs valid on
    /// each flow interval: [`integrate_flow`]), optionally with the state-triggered guard. Returns whether
    /// the guard fired (then the current time is the event time).
    fn flow_adaptive(
        &mut self,
        dp: &mut Dopri5,
        t_to: f64,
        guard: Option<Guard<'_>>,
    ) -> Result<bool, SimError> {
        let joint = JointFlow {
            plant: self.plant.flow(),
            observer: self.observer.flow(),
            np: self.np,
        };
        let events: Vec<Event<'_>> = guard
            .map(|g| Event::new(g, Direction::Rising))
            .into_iter()
            .collect();
        let record = self.opts.record;
        let (t0_grid, dt) = match record {
            Record::Every(dt) => (self.opts.t0, dt),
            _ => (0.0, f64::INFINITY),
        };
        let j = self.j;
        let arc = &mut self.arc;
        let mut buf = vec![0.0; self.z.len()];
        let (t_reached, outcome) = integrate_flow(
            &joint,
            dp,
            self.t,
            &mut self.z,
            t_to,
            &events,
            |s| match record {
                Record::JumpsOnly => {}
                Record::Steps => {
                    if s.t_end < t_to {
                        s.eval(s.t_end, &mut buf);
                        arc.push_unchecked(s.t_end, j, &buf);
                    }
                }
                Record::Every(_) => {
                    let k0 = ((s.t_start - t0_grid) / dt).floor() as i64 + 1;
                    let mut k = k0;
                    loop {
                        let g = t0_grid + k as f64 * dt;
                        if g > s.t_end || g >= t_to {
                            break;
                        }
                        if g > s.t_start {
                            s.eval(g, &mut buf);
                            arc.push_unchecked(g, j, &buf);
                        }
                        k += 1;
                    }
                }
            },
        )?;
        self.t = t_reached;
        Ok(matches!(outcome, Outcome::Event { .. }))
    }

    /// Records the current state unless a sample with the same hybrid time was just stored (e.g. the
    /// end of an integrator step cut at the sampling event).
    fn record_current(&mut self) {
        if let Some((ht, _)) = self.arc.last()
            && ht.t == self.t
            && ht.j == self.j
        {
            return;
        }
        self.arc.push_unchecked(self.t, self.j, &self.z);
    }

    /// Takes a sample from `sensor` at the current time, `elapsed` after the previous one: records the
    /// pre-jump state, measures the plant, applies the plant and observer jumps, records the post-jump state.
    fn sample(&mut self, sensor: usize, elapsed: f64) -> Result<(), SimError> {
        self.record_current();
        let ev = SampleEvent {
            t: self.t,
            j: self.j,
            sensor,
            elapsed,
        };
        let np = self.np;
        self.y.clear();
        let (zp, zo) = self.z.split_at_mut(np);
        self.plant.measure(&ev, zp, &mut self.y)?;
        check_finite_slice(&self.y, "measurement")?;
        self.plant.jump(&ev, zp)?;
        self.observer.jump(&ev, &self.y, zo)?;
        check_finite_slice(&self.z, "state after a jump")?;
        self.log.push(&ev, &self.y);
        self.j += 1;
        self.t_last = self.t;
        self.arc.push_unchecked(self.t, self.j, &self.z);
        Ok(())
    }
}
