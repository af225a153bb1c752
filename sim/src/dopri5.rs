//! Adaptive Dormand–Prince 5(4) integration with dense output and event location.
//!
//! The scheme is the explicit Runge–Kutta pair of J. R. Dormand & P. J. Prince, "A family of embedded
//! Runge–Kutta formulae", J. Comput. Appl. Math. 6 (1980) 19–26, used in local-extrapolation mode (the
//! 5th-order solution is propagated, the embedded 4th-order one estimates the error) with the FSAL
//! property, the step-size controller with PI stabilisation (β = 0.04), the initial-step heuristic and the
//! 4th-order continuous extension of Hairer, Nørsett & Wanner, *Solving ODEs I* (2nd ed., 1993),
//! §II.4–II.6 and their code DOPRI5 (dense-output coefficients `d1…d7` of Shampine 1986 as used there).
//!
//! Events `g(t, x) = 0` are detected by a sign change of `g` between the ends of an accepted step and
//! located on the dense output with Brent's method ([`crate::event::brent`]) to `event_tol` relative to
//! the bracket, i.e. to `event_tol · (t_{n+1} − t_n)` absolute (plus the rounding `2ε|t|` of the time
//! itself), so that the accuracy does not degrade when `|t|` is large; the integration then stops
//! exactly at the event. The time is as accurate as the dense output (≈ the integration tolerance)
//! allows. Two crossings inside one step cancel and go unseen: bound the step with `h_max` when `g` can
//! oscillate faster than the solution.
//!
//! The right-hand side is only evaluated at times inside `[t0, t_end]`, and the stages of the step that
//! ends at `t_end` that belong to `t_end` are evaluated at exactly `t_end`: a caller whose `f` jumps at
//! `t_end` can therefore hand the integrator the left limit `f(t_end⁻)` there
//! ([`crate::flow::integrate_flow`] does). A remaining interval `t_end − t` below the time resolution
//! is covered by one step of exactly that length (it lands on `t_end`), never reported as a step-size
//! underflow: that error is reserved for steps the error control itself has shrunk to the rounding
//! level of `t`.

use crate::error::SimError;
use crate::event::{Event, brent};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite_slice;

// Butcher tableau of DOPRI5.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
// Error coefficients (5th minus 4th order weights).
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output (4th-order continuous extension).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// A remembered step size is reused by the next call only if it exceeds this many units of the time
/// resolution `ε|t|` (smaller ones can only come from slivers and would risk a step-size underflow).
const MEMORY_RESOLUTION: f64 = 1e4;

/// Settings of the integrator.
#[derive(Debug, Clone, PartialEq)]
pub struct Dopri5Options {
    /// Relative tolerance of the local error test.
    pub rtol: f64,
    /// Absolute tolerance of the local error test.
    pub atol: f64,
    /// First trial step (default: Hairer's heuristic).
    pub h_init: Option<f64>,
    /// Largest step allowed.
    pub h_max: f64,
    /// Step budget of one call to [`Dopri5::integrate`].
    pub max_steps: usize,
    /// If set, integrate with this constant step and no error control (for order studies).
    pub fixed_step: Option<f64>,
    /// Tolerance of event times relative to the length of the step whose end points bracket the event
    /// (the absolute tolerance is `event_tol · h`, plus the rounding `2ε|t|` of the time itself).
    pub event_tol: f64,
}

impl Default for Dopri5Options {
    fn default() -> Self {
        Self {
            rtol: 1e-9,
            atol: 1e-12,
            h_init: None,
            h_max: f64::INFINITY,
            max_steps: 10_000_000,
            fixed_step: None,
            event_tol: 1e-12,
        }
    }
}

impl Dopri5Options {
    /// Options with the given tolerances and defaults otherwise.
    pub fn with_tolerances(rtol: f64, atol: f64) -> Self {
        Self {
            rtol,
            atol,
            ..Self::default()
        }
    }

    fn validate(&self) -> Result<(), SimError> {
        let ok_tol = self.rtol >= 0.0 && self.atol >= 0.0 && self.rtol + self.atol > 0.0;
        if !(ok_tol && self.rtol.is_finite() && self.atol.is_finite()) {
            return Err(SimError::invalid(format!(
                "tolerances must be finite, >= 0 and not both 0: rtol {}, atol {}",
                self.rtol, self.atol
            )));
        }
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return Err(SimError::invalid(format!(
                "h_max must be > 0, got {}",
                self.h_max
            )));
        }
        if let Some(h) = self.h_init.or(self.fixed_step)
            && !(h > 0.0 && h.is_finite())
        {
            return Err(SimError::invalid(format!(
                "step sizes must be finite and > 0, got {h}"
            )));
        }
        if !(self.event_tol > 0.0 && self.event_tol.is_finite()) {
            return Err(SimError::invalid(format!(
                "event_tol must be finite and > 0, got {}",
                self.event_tol
            )));
        }
        Ok(())
    }
}

/// Counters of the work done so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Dopri5Stats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Right-hand-side evaluations.
    pub rhs_evals: usize,
    /// Located events.
    pub events: usize,
}

/// How a call to [`Dopri5::integrate`] ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outcome {
    /// The final time was reached.
    Reached,
    /// Event `index` occurred at time `t` (the state returned is the state at `t`).
    Event {
        /// Index of the event in the slice passed to `integrate`.
        index: usize,
        /// Located event time.
        t: f64,
    },
}

/// One accepted step with its continuous extension, valid on `[t_start, t_end]`.
pub struct DenseStep<'a> {
    t_old: f64,
    h: f64,
    /// Start of the step.
    pub t_start: f64,
    /// End of the step (earlier than `t_start + h` when the step was cut at an event).
    pub t_end: f64,
    r: [&'a [f64]; 5],
}

impl DenseStep<'_> {
    /// Evaluates the 4th-order continuous extension at `t ∈ [t_start, t_end]` into `out`.
    pub fn eval(&self, t: f64, out: &mut [f64]) {
        dense_eval(&self.r, self.t_old, self.h, t, out);
    }
}

fn dense_eval(r: &[&[f64]; 5], t_old: f64, h: f64, t: f64, out: &mut [f64]) {
    let th = (t - t_old) / h;
    let th1 = 1.0 - th;
    for (i, o) in out.iter_mut().enumerate() {
        *o = r[0][i] + th * (r[1][i] + th1 * (r[2][i] + th * (r[3][i] + th1 * r[4][i])));
    }
}

/// The Dormand–Prince 5(4) integrator with its work arrays (reusable across calls).
#[derive(Debug, Clone)]
pub struct Dopri5 {
    opts: Dopri5Options,
    stats: Dopri5Stats,
    last_h: Option<f64>,
    n: usize,
    k: [Vec<f64>; 7],
    y1: Vec<f64>,
    ys: Vec<f64>,
    rc: [Vec<f64>; 5],
    tmp: Vec<f64>,
}

impl Dopri5 {
    /// A new integrator with the given settings.
    pub fn new(opts: Dopri5Options) -> Result<Self, SimError> {
        opts.validate()?;
        Ok(Self {
            opts,
            stats: Dopri5Stats::default(),
            last_h: None,
            n: 0,
            k: Default::default(),
            y1: Vec::new(),
            ys: Vec::new(),
            rc: Default::default(),
            tmp: Vec::new(),
        })
    }

    /// The settings.
    pub fn options(&self) -> &Dopri5Options {
        &self.opts
    }

    /// Work counters accumulated over all calls.
    pub fn stats(&self) -> Dopri5Stats {
        self.stats
    }

    /// The step size proposed at the end of the previous call (used as the first trial step of the next).
    pub fn last_step(&self) -> Option<f64> {
        self.last_h
    }

    /// Forgets the step size of the previous call (the next call starts with the initial-step heuristic).
    pub fn reset_step(&mut self) {
        self.last_h = None;
    }

    fn resize(&mut self, n: usize) {
        if self.n != n {
            self.n = n;
            for v in self.k.iter_mut().chain(self.rc.iter_mut()) {
                *v = vec![0.0; n];
            }
            self.y1 = vec![0.0; n];
            self.ys = vec![0.0; n];
            self.tmp = vec![0.0; n];
        }
    }

    /// Hairer's initial step heuristic (Solving ODEs I, §II.4); `k[0]` holds `f(t0, y0)`.
    /// The trial evaluation is at `min(t0 + h, t_end)`.
    fn initial_step<F: Fn(f64, &[f64], &mut [f64])>(
        &mut self,
        f: &F,
        t0: f64,
        y0: &[f64],
        hmax: f64,
        t_end: f64,
    ) -> f64 {
        let (rtol, atol) = (self.opts.rtol, self.opts.atol);
        let mut dnf = 0.0;
        let mut dny = 0.0;
        for i in 0..self.n {
            let sk = atol + rtol * y0[i].abs();
            dnf += (self.k[0][i] / sk).powi(2);
            dny += (y0[i] / sk).powi(2);
        }
        let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
            1e-6
        } else {
            (dny / dnf).sqrt() * 0.01
        };
        h = h.min(hmax);
        for i in 0..self.n {
            self.ys[i] = y0[i] + h * self.k[0][i];
        }
        f((t0 + h).min(t_end), &self.ys, &mut self.tmp);
        self.stats.rhs_evals += 1;
        let mut der2 = 0.0;
        for i in 0..self.n {
            let sk = atol + rtol * y0[i].abs();
            der2 += ((self.tmp[i] - self.k[0][i]) / sk).powi(2);
        }
        let der2 = der2.sqrt() / h;
        let der12 = der2.abs().max(dnf.sqrt());
        let h1 = if der12 <= 1e-15 {
            (h * 1e-3).max(1e-6)
        } else {
            (0.01 / der12).powf(0.2)
        };
        (100.0 * h).min(h1).min(hmax)
    }

    /// Integrates `ẋ = f(t, x)` from `(t0, x)` towards `t_end > t0`, stopping early at the first event.
    ///
    /// On return `x` holds the state at the returned time (`t_end`, or the event time). `on_step` is called
    /// for every accepted step with its dense output (cut at the event if one occurred).
    pub fn integrate<F, S>(
        &mut self,
        f: &F,
        t0: f64,
        x: &mut [f64],
        t_end: f64,
        events: &[Event<'_>],
        mut on_step: S,
    ) -> Result<(f64, Outcome), SimError>
    where
        F: Fn(f64, &[f64], &mut [f64]),
        S: FnMut(&DenseStep<'_>),
    {
        if !(t0.is_finite() && t_end.is_finite()) {
            return Err(InputError::non_finite("integration interval").into());
        }
        if t_end < t0 {
            return Err(SimError::invalid(format!(
                "integration must go forward: t0 = {t0} > t_end = {t_end}"
            )));
        }
        check_finite_slice(x, "initial state of the integration")?;
        if t_end == t0 {
            return Ok((t0, Outcome::Reached));
        }
        let n = x.len();
        self.resize(n);
        let hmax = self.opts.h_max.min(t_end - t0);
        let uround = f64::EPSILON;
        let (rtol, atol) = (self.opts.rtol, self.opts.atol);
        let fixed = self.opts.fixed_step;

        let mut t = t0;
        f(t, x, &mut self.k[0]);
        self.stats.rhs_evals += 1;
        check_finite_slice(&self.k[0], "flow map at the initial state")?;
        // The first trial step is the remembered one, capped by h_max only: the end of the interval is
        // handled by the `last` logic below, so that a step shortened to fit a short interval (e.g. a
        // sliver of one rounding error before a sampling instant) does not overwrite the memory. A
        // remembered step at the rounding level of t says nothing useful here: restart the heuristic.
        let remembered = self
            .last_h
            .filter(|&h| h > MEMORY_RESOLUTION * t.abs() * uround);
        let mut h = match fixed.or(remembered).or(self.opts.h_init) {
            Some(h) => h.min(self.opts.h_max),
            None => self.initial_step(f, t, x, hmax, t_end),
        };
        let mut g_prev: Vec<f64> = events.iter().map(|e| (e.g)(t, x)).collect();
        let mut facold: f64 = 1e-4;
        let mut reject = false;
        let mut steps = 0usize;
        loop {
            if steps >= self.opts.max_steps {
                return Err(SimError::TooManySteps {
                    t,
                    max_steps: self.opts.max_steps,
                });
            }
            // A step that would end within 1 % of its length before t_end is stretched to land on it.
            let last = t + 1.01 * h >= t_end;
            // Underflow is about the step-size control: a last step may be arbitrarily short because the
            // remaining interval is (e.g. a sampling instant one rounding error before the horizon).
            if !last && 0.1 * h.abs() <= t.abs() * uround {
                return Err(SimError::StepSizeUnderflow { t, h });
            }
            let h_proposed = h;
            if last {
                h = t_end - t;
            }
            let t_new = if last { t_end } else { t + h };
            steps += 1;
            self.stage_all(f, t, x, h, t_new);
            // Error estimate.
            let err = if fixed.is_some() {
                0.0
            } else {
                let mut e2 = 0.0;
                for i in 0..n {
                    let ei = h
                        * (E1 * self.k[0][i]
                            + E3 * self.k[2][i]
                            + E4 * self.k[3][i]
                            + E5 * self.k[4][i]
                            + E6 * self.k[5][i]
                            + E7 * self.k[6][i]);
                    let sk = atol + rtol * x[i].abs().max(self.y1[i].abs());
                    e2 += (ei / sk).powi(2);
                }
                (e2 / n.max(1) as f64).sqrt()
            };
            if !err.is_finite() || !self.y1.iter().all(|v| v.is_finite()) {
                if fixed.is_some() {
                    return Err(InputError::non_finite(format!(
                        "state after the step from t = {t}"
                    ))
                    .into());
                }
                // Treat as a failed step: shrink strongly.
                self.stats.rejected += 1;
                h *= 0.1;
                reject = true;
                continue;
            }
            let fac11 = err.powf(0.2 - 0.04 * 0.75);
            let mut fac = fac11 / facold.powf(0.04);
            fac = (fac / 0.9).clamp(1.0 / 10.0, 1.0 / 0.2);
            let mut hnew = h / fac;
            if err <= 1.0 {
                // Accepted step.
                facold = err.max(1e-4);
                self.stats.accepted += 1;
                self.build_dense(x, h);
                // Events.
                let mut hit: Option<(usize, f64)> = None;
                let mut g_new = Vec::with_capacity(events.len());
                for (idx, ev) in events.iter().enumerate() {
                    let g1 = (ev.g)(t_new, &self.y1);
                    g_new.push(g1);
                    if ev.direction.crosses(g_prev[idx], g1) {
                        let te = self.locate(ev, t, t_new, h, g_prev[idx], g1)?;
                        if hit.is_none_or(|(_, tb)| te < tb) {
                            hit = Some((idx, te));
                        }
                    }
                }
                let t_step_end = hit.map_or(t_new, |(_, te)| te);
                {
                    let r = [
                        &self.rc[0][..],
                        &self.rc[1][..],
                        &self.rc[2][..],
                        &self.rc[3][..],
                        &self.rc[4][..],
                    ];
                    on_step(&DenseStep {
                        t_old: t,
                        h,
                        t_start: t,
                        t_end: t_step_end,
                        r,
                    });
                }
                if let Some((index, te)) = hit {
                    let r = [
                        &self.rc[0][..],
                        &self.rc[1][..],
                        &self.rc[2][..],
                        &self.rc[3][..],
                        &self.rc[4][..],
                    ];
                    dense_eval(&r, t, h, te, x);
                    check_finite_slice(x, "state at the event")?;
                    self.stats.events += 1;
                    self.last_h = Some(if fixed.is_some() {
                        h
                    } else {
                        hnew.min(self.opts.h_max)
                    });
                    return Ok((te, Outcome::Event { index, t: te }));
                }
                // FSAL: k7 = f(t_new, y1) becomes k1 of the next step.
                self.k.swap(0, 6);
                x.copy_from_slice(&self.y1);
                t = t_new;
                g_prev = g_new;
                if last {
                    // A final step shortened to hit t_end says little about the natural step size.
                    let next = if fixed.is_some() || h < h_proposed {
                        h_proposed
                    } else {
                        hnew
                    };
                    self.last_h = Some(next.min(self.opts.h_max));
                    return Ok((t, Outcome::Reached));
                }
                if let Some(hf) = fixed {
                    hnew = hf;
                } else {
                    hnew = hnew.min(self.opts.h_max);
                    if reject {
                        hnew = hnew.min(h);
                    }
                }
                reject = false;
                h = hnew;
            } else {
                // Rejected step.
                hnew = h / (fac11 / 0.9).min(1.0 / 0.2);
                reject = true;
                self.stats.rejected += 1;
                h = hnew;
            }
        }
    }

    /// Evaluates the seven stages of one step of size `h` from `(t, y)` to `t_new` (`= t + h` up to
    /// rounding); `k[0]` must hold `f(t, y)`. Stage times are clamped to `t_new` and the two stages with
    /// `c = 1` are evaluated at exactly `t_new`. Leaves the 5th-order solution in `y1` and `f(t_new, y1)`
    /// in `k[6]`.
    fn stage_all<F: Fn(f64, &[f64], &mut [f64])>(
        &mut self,
        f: &F,
        t: f64,
        y: &[f64],
        h: f64,
        t_new: f64,
    ) {
        let n = self.n;
        let at = |c: f64| (t + c * h).min(t_new);
        let [k1, k2, k3, k4, k5, k6, k7] = &mut self.k;
        for i in 0..n {
            self.ys[i] = y[i] + h * A21 * k1[i];
        }
        f(at(C2), &self.ys, k2);
        for i in 0..n {
            self.ys[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
        }
        f(at(C3), &self.ys, k3);
        for i in 0..n {
            self.ys[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
        }
        f(at(C4), &self.ys, k4);
        for i in 0..n {
            self.ys[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
        }
        f(at(C5), &self.ys, k5);
        for i in 0..n {
            self.ys[i] =
                y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
        }
        f(t_new, &self.ys, k6);
        for i in 0..n {
            self.y1[i] =
                y[i] + h * (A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]);
        }
        f(t_new, &self.y1, k7);
        self.stats.rhs_evals += 6;
    }

    /// Coefficients of the continuous extension on the accepted step `[t, t + h]` from `y0`.
    fn build_dense(&mut self, y0: &[f64], h: f64) {
        let k = &self.k;
        for i in 0..self.n {
            let ydiff = self.y1[i] - y0[i];
            let bspl = h * k[0][i] - ydiff;
            self.rc[0][i] = y0[i];
            self.rc[1][i] = ydiff;
            self.rc[2][i] = bspl;
            self.rc[3][i] = ydiff - h * k[6][i] - bspl;
            self.rc[4][i] = h
                * (D1 * k[0][i]
                    + D3 * k[2][i]
                    + D4 * k[3][i]
                    + D5 * k[4][i]
                    + D6 * k[5][i]
                    + D7 * k[6][i]);
        }
    }

    /// Locates the crossing of `ev` inside the accepted step `[t, t_new]`.
    fn locate(
        &mut self,
        ev: &Event<'_>,
        t: f64,
        t_new: f64,
        h: f64,
        g0: f64,
        g1: f64,
    ) -> Result<f64, SimError> {
        // Relative to the bracket, not to |t|: at t = 1e6 a |t|-relative 1e-12 would be 1e-6 absolute.
        let xtol = self.opts.event_tol * (t_new - t);
        let r = [
            &self.rc[0][..],
            &self.rc[1][..],
            &self.rc[2][..],
            &self.rc[3][..],
            &self.rc[4][..],
        ];
        let tmp = &mut self.tmp;
        brent(
            |s| {
                dense_eval(&r, t, h, s, tmp);
                (ev.g)(s, tmp)
            },
            t,
            t_new,
            g0,
            g1,
            xtol,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::event::Direction;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(32))]

        /// Random 2×2 linear systems: DP5 at rtol 1e-11 matches e^{At} x0 (independent: `expm_scaled`).
        #[test]
        fn matches_matrix_exponential(entries in proptest::collection::vec(-2.0f64..2.0, 4), x0 in proptest::collection::vec(-1.0f64..1.0, 2), t in 0.1f64..3.0) {
            let f = |_t: f64, x: &[f64], dx: &mut [f64]| {
                dx[0] = entries[0] * x[0] + entries[1] * x[1];
                dx[1] = entries[2] * x[0] + entries[3] * x[1];
            };
            let mut d = Dopri5::new(Dopri5Options::with_tolerances(1e-11, 1e-13)).unwrap();
            let mut x = [x0[0], x0[1]];
            d.integrate(&f, 0.0, &mut x, t, &[], |_| {}).unwrap();
            let a = faer::Mat::<f64>::from_fn(2, 2, |i, j| entries[2 * i + j]);
            let e = sporadic_linalg::expm_scaled(a.as_ref(), t).unwrap();
            let scale = e.norm_max().max(1.0);
            for i in 0..2 {
                let exact = e[(i, 0)] * x0[0] + e[(i, 1)] * x0[1];
                prop_assert!((x[i] - exact).abs() <= 1e-8 * scale, "{} vs {}", x[i], exact);
            }
        }

        /// ẋ = v from x0 hits the level c at t = (c − x0)/v; located to 1e-12 relative.
        #[test]
        fn event_time_of_uniform_motion(v in 0.1f64..10.0, c in 0.01f64..5.0) {
            let f = |_t: f64, _x: &[f64], dx: &mut [f64]| dx[0] = v;
            let g = |_t: f64, x: &[f64]| x[0] - c;
            let mut d = Dopri5::new(Dopri5Options::default()).unwrap();
            let mut x = [0.0];
            let t_end = 2.0 * c / v + 1.0;
            let (t, out) = d.integrate(&f, 0.0, &mut x, t_end, &[Event::new(&g, Direction::Rising)], |_| {}).unwrap();
            let hit = matches!(out, Outcome::Event { index: 0, .. });
            prop_assert!(hit, "no event");
            let expect = c / v;
            prop_assert!((t - expect).abs() <= 1e-12 * expect.max(1.0), "{} vs {}", t, expect);
        }
    }

    fn exp_sin(t: f64, x: &[f64], dx: &mut [f64]) {
        // x' = x cos t, x(0) = 1 ⇒ x(t) = e^{sin t}.
        dx[0] = x[0] * t.cos();
    }

    #[test]
    fn fifth_order_convergence_with_fixed_steps() {
        // Global error of a p-th order method scales like h^p: halving h divides it by ≈ 2^5 = 32.
        let exact = 2f64.sin().exp();
        let err = |h: f64| {
            let mut d = Dopri5::new(Dopri5Options {
                fixed_step: Some(h),
                ..Default::default()
            })
            .unwrap();
            let mut x = [1.0];
            d.integrate(&exp_sin, 0.0, &mut x, 2.0, &[], |_| {})
                .unwrap();
            (x[0] - exact).abs()
        };
        let (e1, e2, e3) = (err(0.2), err(0.1), err(0.05));
        let (r1, r2) = (e1 / e2, e2 / e3);
        assert!(
            (24.0..44.0).contains(&r1) && (24.0..44.0).contains(&r2),
            "ratios {r1} {r2} ({e1} {e2} {e3})"
        );
    }

    #[test]
    fn adaptive_meets_tolerance() {
        let mut d = Dopri5::new(Dopri5Options::with_tolerances(1e-10, 1e-12)).unwrap();
        let mut x = [1.0];
        let (t, out) = d
            .integrate(&exp_sin, 0.0, &mut x, 10.0, &[], |_| {})
            .unwrap();
        assert_eq!((t, out), (10.0, Outcome::Reached));
        assert!(
            (x[0] - 10f64.sin().exp()).abs() < 1e-8,
            "{}",
            x[0] - 10f64.sin().exp()
        );
        assert!(d.stats().accepted > 10);
    }

    #[test]
    fn dense_output_is_fourth_order_accurate() {
        // Harmonic oscillator, check the continuous extension against cos/sin inside every step.
        let f = |_t: f64, x: &[f64], dx: &mut [f64]| {
            dx[0] = x[1];
            dx[1] = -x[0];
        };
        let mut d = Dopri5::new(Dopri5Options::with_tolerances(1e-10, 1e-12)).unwrap();
        let mut x = [1.0, 0.0];
        let mut worst: f64 = 0.0;
        let mut buf = [0.0; 2];
        d.integrate(&f, 0.0, &mut x, 6.0, &[], |s| {
            for q in 1..4 {
                let t = s.t_start + (s.t_end - s.t_start) * q as f64 / 4.0;
                s.eval(t, &mut buf);
                worst = worst
                    .max((buf[0] - t.cos()).abs())
                    .max((buf[1] + t.sin()).abs());
            }
        })
        .unwrap();
        assert!(worst < 1e-8, "dense output error {worst}");
    }

    #[test]
    fn event_linear_growth() {
        // ẋ = 1 from 0 reaches 0.7 at t = 0.7 exactly.
        let f = |_t: f64, _x: &[f64], dx: &mut [f64]| dx[0] = 1.0;
        let g = |_t: f64, x: &[f64]| x[0] - 0.7;
        let mut d = Dopri5::new(Dopri5Options::default()).unwrap();
        let mut x = [0.0];
        let (t, out) = d
            .integrate(
                &f,
                0.0,
                &mut x,
                5.0,
                &[Event::new(&g, Direction::Rising)],
                |_| {},
            )
            .unwrap();
        assert!(matches!(out, Outcome::Event { index: 0, .. }));
        assert!((t - 0.7).abs() <= 1e-12 * 0.7, "event at {t}");
        assert!((x[0] - 0.7).abs() <= 1e-12);
    }

    #[test]
    fn event_harmonic_oscillator() {
        // x = cos t crosses zero downwards at π/2 and upwards at 3π/2.
        let f = |_t: f64, x: &[f64], dx: &mut [f64]| {
            dx[0] = x[1];
            dx[1] = -x[0];
        };
        let g = |_t: f64, x: &[f64]| x[0];
        let mut d = Dopri5::new(Dopri5Options::with_tolerances(1e-13, 1e-15)).unwrap();
        let mut x = [1.0, 0.0];
        let ev = [Event::new(&g, Direction::Rising)];
        let (t, _) = d.integrate(&f, 0.0, &mut x, 10.0, &ev, |_| {}).unwrap();
        let expect = 1.5 * std::f64::consts::PI;
        assert!(
            (t - expect).abs() <= 1e-11 * expect,
            "rising crossing at {t}, error {}",
            t - expect
        );
        let mut x = [1.0, 0.0];
        let ev = [Event::new(&g, Direction::Falling)];
        let (t, _) = d.integrate(&f, 0.0, &mut x, 10.0, &ev, |_| {}).unwrap();
        let expect = std::f64::consts::FRAC_PI_2;
        assert!(
            (t - expect).abs() <= 1e-11 * expect,
            "falling crossing at {t}"
        );
    }

    #[test]
    fn event_location_far_from_the_origin() {
        // Regression: the event tolerance was event_tol·|t| = 1e-6 absolute at t = 1e6. It is relative to
        // the bracket now, so the crossing of x = cos(t − t0) at t0 + π/2 is found to the resolution of t
        // (ulp(1e6) = 1.2e-10), as it is at t0 = 0 (`event_harmonic_oscillator`).
        let f = |_t: f64, x: &[f64], dx: &mut [f64]| {
            dx[0] = x[1];
            dx[1] = -x[0];
        };
        let g = |_t: f64, x: &[f64]| x[0];
        let mut d = Dopri5::new(Dopri5Options::with_tolerances(1e-13, 1e-15)).unwrap();
        for t0 in [0.0, 1e3, 1e6] {
            let mut x = [1.0, 0.0];
            let ev = [Event::new(&g, Direction::Falling)];
            let (t, out) = d.integrate(&f, t0, &mut x, t0 + 10.0, &ev, |_| {}).unwrap();
            assert!(matches!(out, Outcome::Event { index: 0, .. }));
            let expect = t0 + std::f64::consts::FRAC_PI_2;
            // Dense-output error (~1e-12) plus two units of the resolution of t (the old tolerance left
            // 1.4e-9 at t0 = 1e6).
            assert!(
                (t - expect).abs() <= 1e-11 + 2.0 * f64::EPSILON * expect,
                "t0 = {t0}: crossing at {t}, error {:e}",
                t - expect
            );
            d.reset_step();
        }
    }

    #[test]
    fn interval_of_one_rounding_error_lands_on_its_end() {
        // Regression (found by sporadic-etienne2017): a sampling instant accumulated as 15 × 0.3 =
        // 4.499999999999999 leaves one ulp to the horizon 4.5; integrating over it raised
        // StepSizeUnderflow. It is one step of exactly that length now.
        let f = |_t: f64, x: &[f64], dx: &mut [f64]| dx[0] = -x[0].sin();
        let mut d = Dopri5::new(Dopri5Options::default()).unwrap();
        let t15 = (0..15).fold(0.0, |t, _| t + 0.3);
        assert!(t15 < 4.5 && 4.5 - t15 <= 4.5 * f64::EPSILON);
        for (t0, t1) in [(t15, 4.5), (1e6, 1e6f64.next_up()), (0.1, 0.1f64.next_up())] {
            let mut x = [1.0];
            let (t, out) = d.integrate(&f, t0, &mut x, t1, &[], |_| {}).unwrap();
            assert_eq!((t, out), (t1, Outcome::Reached));
            assert!((x[0] - (1.0 - 1f64.sin() * (t1 - t0))).abs() <= 4.0 * f64::EPSILON);
        }
        // Genuine underflow (the step-size control shrinks steps to the resolution of t) is still an error.
        let blow = |_t: f64, x: &[f64], dx: &mut [f64]| dx[0] = x[0] * x[0];
        assert!(matches!(
            d.integrate(&blow, 0.0, &mut [1.0], 2.0, &[], |_| {}),
            Err(SimError::StepSizeUnderflow { .. })
                | Err(SimError::Input(InputError::NonFinite { .. }))
        ));
    }

    #[test]
    fn rhs_is_only_evaluated_inside_the_interval() {
        // The stages of the last step are evaluated at exactly t_end (not t + h, which may round past it),
        // so that a caller can hand the integrator the left limit of a discontinuous f there.
        use std::cell::RefCell;
        for (t0, t1) in [(0.1, 0.3), (0.7, 1.1), (1e6 + 0.1, 1e6 + 0.3), (0.0, 1e-3)] {
            let seen = RefCell::new(Vec::new());
            let f = |t: f64, x: &[f64], dx: &mut [f64]| {
                seen.borrow_mut().push(t);
                dx[0] = x[0].cos();
            };
            let mut d = Dopri5::new(Dopri5Options::default()).unwrap();
            d.integrate(&f, t0, &mut [0.5], t1, &[], |_| {}).unwrap();
            let seen = seen.into_inner();
            assert!(seen.iter().all(|&t| (t0..=t1).contains(&t)), "{t0}..{t1}");
            assert!(seen.contains(&t1));
        }
    }

    #[test]
    fn bad_input_is_rejected() {
        assert!(
            Dopri5::new(Dopri5Options {
                rtol: -1.0,
                ..Default::default()
            })
            .is_err()
        );
        assert!(
            Dopri5::new(Dopri5Options {
                fixed_step: Some(0.0),
                ..Default::default()
            })
            .is_err()
        );
        let mut d = Dopri5::new(Dopri5Options::default()).unwrap();
        let f = |_t: f64, _x: &[f64], dx: &mut [f64]| dx[0] = 1.0;
        assert!(d.integrate(&f, 1.0, &mut [0.0], 0.0, &[], |_| {}).is_err());
        assert!(
            d.integrate(&f, 0.0, &mut [f64::NAN], 1.0, &[], |_| {})
                .is_err()
        );
        // Finite-time blow-up: ẋ = x², x(0) = 1 explodes at t = 1.
        let blow = |_t: f64, x: &[f64], dx: &mut [f64]| dx[0] = x[0] * x[0];
        assert!(
            d.integrate(&blow, 0.0, &mut [1.0], 2.0, &[], |_| {})
                .is_err()
        );
    }
}
