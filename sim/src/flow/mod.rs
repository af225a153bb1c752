//! Flow maps `ẋ = f(t, x)` of hybrid systems (the "flow" half of `H = (C, f, D, g)`, Goebel, Sanfelice &
//! Teel 2012). General flows are integrated with the adaptive Dormand–Prince 5(4) scheme of
//! [`crate::dopri5`] ([`integrate_flow`]); linear time-invariant flows with known inputs ([`LtiFlow`])
//! additionally expose an exact propagator through [`Flow::as_lti`], which the simulation driver uses as
//! a fast path.
//!
//! **Time dependence and breakpoints.** A flow may depend on `t` through known inputs that jump at
//! *breakpoints* ([`Flow::next_breakpoint`]), e.g. a piecewise-constant input `u`. Such signals are
//! right-continuous (`u(b) = u(b⁺)`), so [`Flow::rhs`] at a breakpoint `b` already returns the dynamics
//! of the interval that *starts* at `b`. A solution flows over `[s, b]` with the dynamics valid on that
//! interval, which at its end `b` is the left limit `f(b⁻, x)` ([`Flow::rhs_left`]). [`integrate_flow`]
//! implements exactly this: it stops and restarts the integrator at every breakpoint, evaluates the
//! stages at the interval's start with `rhs` (right limit) and those at its end with `rhs_left`.

pub mod lti;

pub use lti::{InputSignal, LtiFlow, LtiPropagator, TransitionTable};

use crate::dopri5::{DenseStep, Dopri5, Outcome};
use crate::error::SimError;
use crate::event::Event;
use sporadic_linalg::input::check_len;

/// The flow map of a hybrid system (or of one of its parts).
pub trait Flow {
    /// Dimension of the state that flows.
    fn dim(&self) -> usize;

    /// Evaluates `dx = f(t, x)`. Both slices have length [`Flow::dim`]. A flow that cannot be evaluated
    /// must write a non-finite value; the integrator then stops with [`crate::SimError::Input`] (`NonFinite`).
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]);

    /// The first time strictly after `t` at which `f` is discontinuous in `t` (e.g. the switching times of
    /// a piecewise-constant input). Integrators stop and restart there. Default: none.
    fn next_breakpoint(&self, _t: f64) -> Option<f64> {
        None
    }

    /// The left limit `f(t⁻, x) = lim_{s↑t} f(s, x)`: the flow map of the interval that *ends* at `t`. It
    /// differs from [`Flow::rhs`] only at a breakpoint `t`, where `rhs` (right-continuous in `t`) returns
    /// the next interval's dynamics. Default: `rhs` at the largest float below `t`, which is exact for
    /// right-continuous piecewise-constant time dependence and within one unit in the last place of `t`
    /// otherwise; override it when the time dependence is known exactly (as [`LtiFlow`] does).
    fn rhs_left(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        self.rhs(t.next_down(), x, dx)
    }

    /// The exact LTI structure of this flow, if it has one (enables exact propagation).
    fn as_lti(&self) -> Option<&LtiFlow> {
        None
    }
}

impl<F: Flow + ?Sized> Flow for &F {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        (**self).rhs(t, x, dx)
    }
    fn next_breakpoint(&self, t: f64) -> Option<f64> {
        (**self).next_breakpoint(t)
    }
    fn rhs_left(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        (**self).rhs_left(t, x, dx)
    }
    fn as_lti(&self) -> Option<&LtiFlow> {
        (**self).as_lti()
    }
}

impl<F: Flow + ?Sized> Flow for Box<F> {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        (**self).rhs(t, x, dx)
    }
    fn next_breakpoint(&self, t: f64) -> Option<f64> {
        (**self).next_breakpoint(t)
    }
    fn rhs_left(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        (**self).rhs_left(t, x, dx)
    }
    fn as_lti(&self) -> Option<&LtiFlow> {
        (**self).as_lti()
    }
}

/// Integrates `ẋ = f(t, x)` of `flow` with `dp` from `(t0, x)` towards `t_end >= t0`, stopping early at
/// the first of `events` (see [`Dopri5::integrate`]). The integration stops and restarts (with a fresh
/// step size) at every breakpoint `b <= t_end` of the flow; the stages that fall on `b` use the left
/// limit [`Flow::rhs_left`]`(b)` and the restart at `b` uses [`Flow::rhs`]`(b)`, so the dynamics used
/// on each interval between breakpoints is the one valid on it (module documentation). `on_step` sees
/// every accepted step. On return `x` holds the state at the returned time (`t_end`, or the event time).
pub fn integrate_flow<F, S>(
    flow: &F,
    dp: &mut Dopri5,
    t0: f64,
    x: &mut [f64],
    t_end: f64,
    events: &[Event<'_>],
    mut on_step: S,
) -> Result<(f64, Outcome), SimError>
where
    F: Flow + ?Sized,
    S: FnMut(&DenseStep<'_>),
{
    check_len(x, flow.dim(), "state integrated along the flow")?;
    let mut t = t0;
    loop {
        // The next breakpoint, if it ends the current piece at or before t_end.
        let bp = flow.next_breakpoint(t).filter(|&b| b > t && b <= t_end);
        let seg_end = bp.unwrap_or(t_end);
        let rhs = |s: f64, z: &[f64], dz: &mut [f64]| {
            if bp.is_some() && s >= seg_end {
                flow.rhs_left(seg_end, z, dz);
            } else {
                flow.rhs(s, z, dz);
            }
        };
        let (reached, outcome) = dp.integrate(&rhs, t, x, seg_end, events, &mut on_step)?;
        t = reached;
        if matches!(outcome, Outcome::Event { .. }) || t >= t_end {
            return Ok((t, outcome));
        }
        // Past a switch the previous step size says nothing about the new dynamics.
        dp.reset_step();
    }
}

/// A general flow given by a closure `f(t, x, dx)`.
pub struct FnFlow<F> {
    dim: usize,
    f: F,
}

impl<F: Fn(f64, &[f64], &mut [f64])> FnFlow<F> {
    /// Wraps `f` as the flow of a `dim`-dimensional state.
    pub fn new(dim: usize, f: F) -> Self {
        Self { dim, f }
    }
}

impl<F: Fn(f64, &[f64], &mut [f64])> Flow for FnFlow<F> {
    fn dim(&self) -> usize {
        self.dim
    }
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        (self.f)(t, x, dx)
    }
}

/// The flow of an empty (zero-dimensional) state, e.g. the plant of a simulation that only evolves an
/// error system.
#[derive(Debug, Clone, Copy, Default)]
pub struct EmptyFlow;

impl Flow for EmptyFlow {
    fn dim(&self) -> usize {
        0
    }
    fn rhs(&self, _t: f64, _x: &[f64], _dx: &mut [f64]) {}
}
