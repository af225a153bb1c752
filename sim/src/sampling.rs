//! Sampling rules: when the next measurement arrives, and from which sensor.
//!
//! * Interval-based rules ([`IntervalSequence`]): periodic; i.i.d. uniform in `[T1, T2]` (the sporadic
//!   class (2) of Ferrante et al. 2016, `T1 <= t_{k+1} − t_k <= T2`); round-robin over `N` sensors with
//!   per-sensor windows (Sferlazza et al. 2021, (2) and (9): the window of sensor `σ` bounds the interval
//!   *before* its sample); sequences read from data; and a greedy adversary ([`Adversarial`]) that picks
//!   every interval to maximise a Lyapunov-like function of the error after the next jump.
//! * State-triggered rules return [`Trigger::Event`] and provide a guard `g(s, x, x̂)` whose upward zero
//!   crossing (`s` = time elapsed since the last sample) triggers the sample, e.g. the rule
//!   `δ_k = min{s : s·L(t_k + s) = α}` of Andrieu et al. 2014, (7).
//!
//! All random rules are seeded ([`SimRng`]) and reproducible. The first sample is taken one interval after
//! the start of the simulation (there is no measurement at `t_0`), unless a first interval is set.

use sporadic_linalg::InputError;
use sporadic_linalg::input::check_len;
use sporadic_linalg::input::{LowerEnd, check_finite, check_finite_slice, check_window};
use std::io::BufRead;

use faer::{Mat, MatRef};
use sporadic_linalg::expm_stepper;

use crate::error::SimError;
use crate::rng::SimRng;

/// What the simulation knows when it asks for the next sample (at the previous sample, or at the start).
#[derive(Debug, Clone, Copy)]
pub struct SampleContext<'a> {
    /// Current time (the time of the previous sample, or the initial time).
    pub t: f64,
    /// Number of samples taken so far.
    pub j: usize,
    /// Plant state (after the previous jump).
    pub plant: &'a [f64],
    /// Observer state (after the previous jump).
    pub observer: &'a [f64],
}

/// How the next sample is triggered.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Trigger {
    /// After `interval` time units (measured from the previous sample), from `sensor`.
    After {
        /// Inter-sample time.
        interval: f64,
        /// Sensor index.
        sensor: usize,
    },
    /// When the rule's [`SamplingRule::guard`] crosses zero upwards, or after `max_interval` at the latest.
    Event {
        /// Sensor index.
        sensor: usize,
        /// Longest admissible interval (`f64::INFINITY` for none).
        max_interval: f64,
    },
    /// No further samples: flow until the horizon (with an infinite horizon the simulation stops here).
    Never,
}

/// A rule that decides when measurements arrive.
pub trait SamplingRule {
    /// Decides how the next sample is triggered.
    fn next_sample(&mut self, ctx: &SampleContext<'_>) -> Result<Trigger, SimError>;

    /// Guard of state-triggered rules: the sample is taken when `g(s, plant, observer)` crosses zero from
    /// below, `s` being the time elapsed since the previous sample. Interval rules never call it; the
    /// default never triggers.
    fn guard(&self, _elapsed: f64, _plant: &[f64], _observer: &[f64]) -> f64 {
        -1.0
    }
}

/// One inter-sample interval and the sensor sampled at its end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleInterval {
    /// Time since the previous sample.
    pub interval: f64,
    /// Sensor sampled at the end of the interval.
    pub sensor: usize,
}

/// A state-independent sequence of inter-sample intervals.
pub trait IntervalSequence {
    /// The next interval ([`SimError::SequenceExhausted`] when a finite sequence ends).
    fn next_interval(&mut self) -> Result<SampleInterval, SimError>;

    /// The next `count` intervals.
    fn take_intervals(&mut self, count: usize) -> Result<Vec<SampleInterval>, SimError> {
        (0..count).map(|_| self.next_interval()).collect()
    }
}

impl<T: IntervalSequence> SamplingRule for T {
    fn next_sample(&mut self, _ctx: &SampleContext<'_>) -> Result<Trigger, SimError> {
        match self.next_interval() {
            Ok(s) => Ok(Trigger::After {
                interval: s.interval,
                sensor: s.sensor,
            }),
            Err(SimError::SequenceExhausted { .. }) => Ok(Trigger::Never),
            Err(e) => Err(e),
        }
    }
}

/// A sampling window `[T1, T2]` with `0 < T1 <= T2 < ∞`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Window {
    t1: f64,
    t2: f64,
}

impl Window {
    /// Validates and builds the window; `what` names it in the error message.
    pub fn new(t1: f64, t2: f64) -> Result<Self, SimError> {
        Self::named(t1, t2, "sampling window")
    }

    fn named(t1: f64, t2: f64, what: &str) -> Result<Self, SimError> {
        check_window(what, t1, t2, LowerEnd::Positive)?;
        Ok(Self { t1, t2 })
    }

    /// Lower bound `T1`.
    pub fn t1(&self) -> f64 {
        self.t1
    }

    /// Upper bound `T2`.
    pub fn t2(&self) -> f64 {
        self.t2
    }

    /// Whether `tau ∈ [T1, T2]`.
    pub fn contains(&self, tau: f64) -> bool {
        (self.t1..=self.t2).contains(&tau)
    }

    fn draw(&self, rng: &mut SimRng) -> f64 {
        rng.uniform(self.t1, self.t2)
    }
}

fn check_first(first: f64) -> Result<f64, SimError> {
    if first.is_finite() && first >= 0.0 {
        Ok(first)
    } else {
        Err(SimError::invalid(format!(
            "first sampling interval must be finite and >= 0, got {first}"
        )))
    }
}

/// Periodic sampling `t_k = t_1 + (k − 1) T` (single sensor 0).
#[derive(Debug, Clone, PartialEq)]
pub struct Periodic {
    period: f64,
    first: Option<f64>,
}

impl Periodic {
    /// Period `T > 0`; the first sample is at `T`.
    pub fn new(period: f64) -> Result<Self, SimError> {
        Window::named(period, period, "period")?;
        Ok(Self {
            period,
            first: None,
        })
    }

    /// Takes the first sample after `first` (>= 0) instead of one period.
    pub fn with_first(mut self, first: f64) -> Result<Self, SimError> {
        self.first = Some(check_first(first)?);
        Ok(self)
    }
}

impl IntervalSequence for Periodic {
    fn next_interval(&mut self) -> Result<SampleInterval, SimError> {
        Ok(SampleInterval {
            interval: self.first.take().unwrap_or(self.period),
            sensor: 0,
        })
    }
}

/// I.i.d. intervals uniform in `[T1, T2]` (single sensor 0), seeded.
#[derive(Debug)]
pub struct UniformRandom {
    window: Window,
    first: Option<(f64, f64)>,
    rng: SimRng,
}

impl UniformRandom {
    /// Intervals uniform in `[t1, t2]`, `0 < t1 <= t2 < ∞`.
    pub fn new(t1: f64, t2: f64, seed: u64) -> Result<Self, SimError> {
        Ok(Self {
            window: Window::new(t1, t2)?,
            first: None,
            rng: SimRng::new(seed),
        })
    }

    /// Draws the first interval uniformly in `[lo, hi]` instead (`0 <= lo <= hi`), e.g. `[0, T2]` for the
    /// first sample time `t_1` of Ferrante et al. (2).
    pub fn with_first_window(mut self, lo: f64, hi: f64) -> Result<Self, SimError> {
        check_first(lo)?;
        check_first(hi)?;
        check_window("first sampling interval", lo, hi, LowerEnd::NonNegative)?;
        self.first = Some((lo, hi));
        Ok(self)
    }

    /// The window `[T1, T2]`.
    pub fn window(&self) -> Window {
        self.window
    }
}

impl IntervalSequence for UniformRandom {
    fn next_interval(&mut self) -> Result<SampleInterval, SimError> {
        let interval = match self.first.take() {
            Some((lo, hi)) => self.rng.uniform(lo, hi),
            None => self.window.draw(&mut self.rng),
        };
        Ok(SampleInterval {
            interval,
            sensor: 0,
        })
    }
}

/// Round-robin sampling of `N` sensors `0, 1, …, N−1, 0, 1, …` (Sferlazza et al. 2021, (2)); the interval
/// ending with the sample of sensor `σ` is uniform in the window of `σ` (the convention of their (9)).
#[derive(Debug)]
pub struct RoundRobin {
    windows: Vec<Window>,
    next: usize,
    rng: SimRng,
}

impl RoundRobin {
    /// One window `(T_mσ, T_Mσ)` per sensor; the first sample comes from sensor 0.
    pub fn new(windows: &[(f64, f64)], seed: u64) -> Result<Self, SimError> {
        if windows.is_empty() {
            return Err(InputError::empty("round-robin windows").into());
        }
        let windows = windows
            .iter()
            .enumerate()
            .map(|(s, &(a, b))| Window::named(a, b, &format!("sensor {s}")))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            windows,
            next: 0,
            rng: SimRng::new(seed),
        })
    }

    /// Starts the cycle at sensor `sensor` instead of 0.
    pub fn starting_at(mut self, sensor: usize) -> Result<Self, SimError> {
        if sensor >= self.windows.len() {
            return Err(SimError::invalid(format!(
                "starting sensor {sensor} of a round robin over {} sensors",
                self.windows.len()
            )));
        }
        self.next = sensor;
        Ok(self)
    }

    /// The window of each sensor.
    pub fn windows(&self) -> &[Window] {
        &self.windows
    }
}

impl IntervalSequence for RoundRobin {
    fn next_interval(&mut self) -> Result<SampleInterval, SimError> {
        let sensor = self.next;
        let interval = self.windows[sensor].draw(&mut self.rng);
        self.next = (sensor + 1) % self.windows.len();
        Ok(SampleInterval { interval, sensor })
    }
}

/// A finite sequence of intervals given as data (e.g. recorded sampling instants).
#[derive(Debug, Clone, PartialEq)]
pub struct FromData {
    data: Vec<SampleInterval>,
    pos: usize,
}

impl FromData {
    /// Validated intervals: finite, `>= 0`, and `> 0` except possibly the first.
    pub fn from_intervals(intervals: &[SampleInterval]) -> Result<Self, SimError> {
        for (k, s) in intervals.iter().enumerate() {
            if !s.interval.is_finite() || s.interval < 0.0 || (k > 0 && s.interval == 0.0) {
                return Err(SimError::invalid(format!(
                    "sampling interval {k} must be finite and > 0 (>= 0 for the first), got {}",
                    s.interval
                )));
            }
        }
        Ok(Self {
            data: intervals.to_vec(),
            pos: 0,
        })
    }

    /// Intervals of a single sensor 0.
    pub fn from_slice(intervals: &[f64]) -> Result<Self, SimError> {
        let v: Vec<_> = intervals
            .iter()
            .map(|&interval| SampleInterval {
                interval,
                sensor: 0,
            })
            .collect();
        Self::from_intervals(&v)
    }

    /// Sampling instants `t_1 < t_2 < …` (with `t_1 >= t0`), converted to intervals from `t0`.
    pub fn from_instants(t0: f64, instants: &[f64]) -> Result<Self, SimError> {
        check_finite_slice(instants, "sampling instants")?;
        let mut prev = t0;
        let mut v = Vec::with_capacity(instants.len());
        for &t in instants {
            v.push(t - prev);
            prev = t;
        }
        Self::from_slice(&v)
    }

    /// Reads intervals from CSV text: one interval per line, optionally followed by a sensor index
    /// (`interval,sensor`). Empty lines, lines starting with `#`, and a non-numeric first line (header)
    /// are skipped.
    pub fn from_csv<R: BufRead>(reader: R) -> Result<Self, SimError> {
        let mut v = Vec::new();
        for (ln, line) in reader.lines().enumerate() {
            let line = line?;
            let s = line.trim();
            if s.is_empty() || s.starts_with('#') {
                continue;
            }
            let mut fields = s.split(',').map(str::trim);
            let first = fields.next().unwrap_or_default();
            let interval = match first.parse::<f64>() {
                Ok(x) => x,
                Err(_) if ln == 0 => continue,
                Err(e) => {
                    return Err(SimError::Csv {
                        line: ln + 1,
                        message: format!("{first:?}: {e}"),
                    });
                }
            };
            let sensor = match fields.next() {
                Some(f) => f.parse::<usize>().map_err(|e| SimError::Csv {
                    line: ln + 1,
                    message: format!("{f:?}: {e}"),
                })?,
                None => 0,
            };
            if fields.next().is_some() {
                return Err(SimError::Csv {
                    line: ln + 1,
                    message: "more than two fields".into(),
                });
            }
            v.push(SampleInterval { interval, sensor });
        }
        Self::from_intervals(&v)
    }

    /// Number of intervals not yet consumed.
    pub fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }
}

impl IntervalSequence for FromData {
    fn next_interval(&mut self) -> Result<SampleInterval, SimError> {
        let s = self
            .data
            .get(self.pos)
            .copied()
            .ok_or(SimError::SequenceExhausted { used: self.pos })?;
        self.pos += 1;
        Ok(s)
    }
}

/// A general reset map `e⁺ = g(e)` writing into its second argument.
pub type ResetFn = Box<dyn Fn(&[f64], &mut [f64])>;

/// A Lyapunov-like function `V(e)`.
pub type LyapunovFn = Box<dyn Fn(&[f64]) -> f64>;

/// The jump map of the error dynamics seen by the adversary.
pub enum JumpMap {
    /// Linear reset `e⁺ = J e` (e.g. `J = I − LM`, Ferrante et al. (5)).
    Matrix(Mat<f64>),
    /// General reset `e⁺ = g(e)`, written into the output slice.
    Closure(ResetFn),
}

type ErrorMap = Box<dyn Fn(&[f64], &[f64]) -> Vec<f64>>;

/// Greedy worst-case sampling: for the error dynamics `ė = A e` between samples and `e⁺ = g(e)` at
/// samples, each interval is chosen on a grid of `[T1, T2]` to maximise `V(g(e^{Aτ} e))`, the Lyapunov-like
/// function of the error just after the next jump. Transition matrices of the grid are computed once
/// ([`sporadic_linalg::expm_stepper`]). Ties go to the shortest interval.
pub struct Adversarial {
    n: usize,
    candidates: Vec<f64>,
    transitions: Vec<Vec<f64>>,
    jump: JumpMap,
    v: LyapunovFn,
    error_of: Option<ErrorMap>,
    scratch: (Vec<f64>, Vec<f64>),
}

impl Adversarial {
    /// The adversary for `ė = A e`, reset `jump`, function `v`, window `[t1, t2]` and `grid` candidate
    /// intervals (`grid >= 2`, or 1 when `t1 == t2`).
    pub fn new(
        a: MatRef<'_, f64>,
        jump: JumpMap,
        v: LyapunovFn,
        t1: f64,
        t2: f64,
        grid: usize,
    ) -> Result<Self, SimError> {
        let window = Window::new(t1, t2)?;
        if a.nrows() != a.ncols() {
            return Err(InputError::mismatch(
                "columns of the error flow matrix",
                a.nrows(),
                a.ncols(),
            )
            .into());
        }
        check_finite(a, "error flow matrix")?;
        let n = a.nrows();
        if let JumpMap::Matrix(j) = &jump {
            if j.nrows() != n || j.ncols() != n {
                return Err(InputError::mismatch(
                    "size of the error jump matrix",
                    n,
                    j.nrows().max(j.ncols()),
                )
                .into());
            }
            check_finite(j.as_ref(), "error jump matrix")?;
        }
        let steps = if window.t1 == window.t2 {
            0
        } else if grid >= 2 {
            grid - 1
        } else {
            return Err(SimError::invalid(format!(
                "the adversary needs a grid of >= 2 intervals, got {grid}"
            )));
        };
        let h = if steps == 0 {
            0.0
        } else {
            (window.t2 - window.t1) / steps as f64
        };
        let stepper = expm_stepper(a, window.t1, h, steps)?;
        let mut candidates = Vec::with_capacity(steps + 1);
        let mut transitions = Vec::with_capacity(steps + 1);
        for (k, e) in stepper.enumerate() {
            candidates.push(window.t1 + k as f64 * h);
            let mut rm = Vec::with_capacity(n * n);
            for i in 0..n {
                for c in 0..n {
                    rm.push(e[(i, c)]);
                }
            }
            transitions.push(rm);
        }
        if candidates.len() != steps + 1 {
            return Err(SimError::invalid(
                "transition stepper returned too few matrices",
            ));
        }
        Ok(Self {
            n,
            candidates,
            transitions,
            jump,
            v,
            error_of: None,
            scratch: (vec![0.0; n], vec![0.0; n]),
        })
    }

    /// How to extract the error from the simulation state when used as a [`SamplingRule`]. By default the
    /// error is the plant state when the observer is empty, and `plant − observer` when both have the
    /// adversary's dimension.
    pub fn with_error_map(mut self, f: ErrorMap) -> Self {
        self.error_of = Some(f);
        self
    }

    /// The candidate intervals.
    pub fn candidates(&self) -> &[f64] {
        &self.candidates
    }

    fn apply_jump(&self, x: &[f64], out: &mut [f64]) {
        match &self.jump {
            JumpMap::Matrix(j) => {
                for (i, o) in out.iter_mut().enumerate() {
                    *o = (0..self.n).map(|k| j[(i, k)] * x[k]).sum();
                }
            }
            JumpMap::Closure(g) => g(x, out),
        }
    }

    /// The greedy choice for the error `e` just after a jump: `(index, interval, V after the next jump)`.
    pub fn choose(&mut self, e: &[f64]) -> Result<(usize, f64, f64), SimError> {
        check_len(e, self.n, "error given to the adversary")?;
        let (mut flowed, mut jumped) = std::mem::take(&mut self.scratch);
        let mut best = (0, self.candidates[0], f64::NEG_INFINITY);
        for (k, m) in self.transitions.iter().enumerate() {
            for (i, f) in flowed.iter_mut().enumerate() {
                *f = m[i * self.n..(i + 1) * self.n]
                    .iter()
                    .zip(e)
                    .map(|(a, b)| a * b)
                    .sum();
            }
            self.apply_jump(&flowed, &mut jumped);
            let val = (self.v)(&jumped);
            if !val.is_finite() {
                self.scratch = (flowed, jumped);
                return Err(InputError::non_finite(format!(
                    "V after the interval {}",
                    self.candidates[k]
                ))
                .into());
            }
            if val > best.2 {
                best = (k, self.candidates[k], val);
            }
        }
        self.scratch = (flowed, jumped);
        Ok(best)
    }

    /// The greedy worst-case sequence of `count` intervals from the initial error `e0`, following the error
    /// it produces. Returns the intervals and the post-jump errors.
    pub fn sequence(
        &mut self,
        e0: &[f64],
        count: usize,
    ) -> Result<(Vec<f64>, Vec<Vec<f64>>), SimError> {
        check_len(e0, self.n, "initial error given to the adversary")?;
        check_finite_slice(e0, "initial error given to the adversary")?;
        let mut e = e0.to_vec();
        let mut taus = Vec::with_capacity(count);
        let mut errs = Vec::with_capacity(count);
        let mut flowed = vec![0.0; self.n];
        for _ in 0..count {
            let (k, tau, _) = self.choose(&e)?;
            let m = &self.transitions[k];
            for (i, f) in flowed.iter_mut().enumerate() {
                *f = m[i * self.n..(i + 1) * self.n]
                    .iter()
                    .zip(&e)
                    .map(|(a, b)| a * b)
                    .sum();
            }
            self.apply_jump(&flowed, &mut e);
            taus.push(tau);
            errs.push(e.clone());
        }
        Ok((taus, errs))
    }
}

impl SamplingRule for Adversarial {
    fn next_sample(&mut self, ctx: &SampleContext<'_>) -> Result<Trigger, SimError> {
        let e = match &self.error_of {
            Some(f) => f(ctx.plant, ctx.observer),
            None if ctx.observer.is_empty() => ctx.plant.to_vec(),
            None if ctx.plant.is_empty() => ctx.observer.to_vec(),
            None if ctx.plant.len() == ctx.observer.len() => ctx
                .plant
                .iter()
                .zip(ctx.observer)
                .map(|(a, b)| a - b)
                .collect(),
            None => {
                return Err(SimError::invalid(
                    "the adversary cannot infer the error from plant and observer states of different sizes; \
                     set an error map",
                ));
            }
        };
        let (_, interval, _) = self.choose(&e)?;
        Ok(Trigger::After {
            interval,
            sensor: 0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn windows_are_validated() {
        assert!(Window::new(0.0, 1.0).is_err());
        assert!(Window::new(2.0, 1.0).is_err());
        assert!(Window::new(1.0, f64::INFINITY).is_err());
        assert!(Window::new(f64::NAN, 1.0).is_err());
        assert!(UniformRandom::new(-1.0, 1.0, 0).is_err());
        assert!(matches!(
            RoundRobin::new(&[(0.02, 0.07), (0.09, 0.04)], 0),
            Err(SimError::Input(InputError::InvalidWindow { .. }))
        ));
        assert!(Periodic::new(0.0).is_err());
        assert!(Periodic::new(1.0).unwrap().with_first(-1.0).is_err());
    }

    #[test]
    fn periodic_with_first() {
        let mut p = Periodic::new(0.5).unwrap().with_first(0.1).unwrap();
        let v: Vec<f64> = p
            .take_intervals(4)
            .unwrap()
            .iter()
            .map(|s| s.interval)
            .collect();
        assert_eq!(v, vec![0.1, 0.5, 0.5, 0.5]);
    }

    #[test]
    fn csv_and_instants() {
        let text = "interval,sensor\n# comment\n0.5,1\n\n0.25,0\n";
        let mut d = FromData::from_csv(text.as_bytes()).unwrap();
        assert_eq!(
            d.next_interval().unwrap(),
            SampleInterval {
                interval: 0.5,
                sensor: 1
            }
        );
        assert_eq!(
            d.next_interval().unwrap(),
            SampleInterval {
                interval: 0.25,
                sensor: 0
            }
        );
        assert!(matches!(
            d.next_interval(),
            Err(SimError::SequenceExhausted { used: 2 })
        ));
        let ctx = SampleContext {
            t: 0.0,
            j: 0,
            plant: &[],
            observer: &[],
        };
        assert_eq!(d.next_sample(&ctx).unwrap(), Trigger::Never);
        assert!(matches!(
            FromData::from_csv("0.5\nabc\n".as_bytes()),
            Err(SimError::Csv { line: 2, .. })
        ));
        assert!(FromData::from_csv("0.5\n-1\n".as_bytes()).is_err());
        let mut d = FromData::from_instants(0.0, &[0.5, 1.25, 2.0]).unwrap();
        let v: Vec<f64> = d
            .take_intervals(3)
            .unwrap()
            .iter()
            .map(|s| s.interval)
            .collect();
        assert_eq!(v, vec![0.5, 0.75, 0.75]);
        assert!(FromData::from_instants(0.0, &[1.0, 1.0]).is_err());
    }

    #[test]
    fn adversary_scalar_closed_form() {
        // ė = a e, e⁺ = J e, V = e²: V(J e^{aτ} e) is increasing in τ for a > 0 ⇒ always T2; for a < 0 ⇒ T1.
        for (a, expect) in [(1.0, 3.0), (-1.0, 0.2)] {
            let mut adv = Adversarial::new(
                mat![[a]].as_ref(),
                JumpMap::Matrix(mat![[0.5]]),
                Box::new(|e: &[f64]| e[0] * e[0]),
                0.2,
                3.0,
                15,
            )
            .unwrap();
            let (taus, errs) = adv.sequence(&[1.0], 5).unwrap();
            assert!(taus.iter().all(|&t| (t - expect).abs() < 1e-12), "{taus:?}");
            let expect_e5 = (0.5 * (a * expect).exp()).powi(5);
            assert!((errs[4][0] - expect_e5).abs() < 1e-12 * expect_e5.abs().max(1.0));
        }
    }
}
