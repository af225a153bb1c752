//! Hybrid-systems simulation for observers with sporadic measurements.
//!
//! A plant flows continuously; measurements arrive at sampling instants chosen by a [`SamplingRule`];
//! the observer flows between samples and jumps when a measurement arrives. The closed loop is a hybrid
//! system in the sense of Goebel, Sanfelice & Teel (*Hybrid Dynamical Systems*, 2012), whose solutions are
//! hybrid arcs on hybrid time domains `(t, j)` ([`HybridArc`]).
//!
//! Building blocks, one module per concept:
//! * [`arc`] — hybrid time domains and arcs (struct-of-arrays storage, jumps, projection onto ordinary
//!   time, CSV export);
//! * [`flow`] — flow maps: general closures ([`FnFlow`]) and LTI flows with known inputs ([`LtiFlow`]),
//!   propagated exactly by block-triangular exponentials ([`LtiPropagator`]);
//! * [`dopri5`] — adaptive Dormand–Prince 5(4) with dense output, and [`event`] — event location
//!   (`g(t, x) = 0` with a direction) by Brent's method on the dense output;
//! * [`sampling`] — sampling rules: periodic, uniform in `[T1, T2]`, round-robin with per-sensor windows,
//!   data-driven, greedy adversarial, and state-triggered rules;
//! * [`noise`] and [`signal`] — seeded disturbances/noise and exactly representable input signals;
//! * [`system`] — plant/observer interfaces and linear building blocks; [`simulate`](mod@simulate) — the
//!   driver;
//!
//! ```
//! use faer::mat;
//! use sporadic_sim::{LinearJump, LtiFlow, Periodic, SimOptions, simulate_hybrid};
//!
//! // Error system of Ferrante et al. (2016), Example 1: ε̇ = ε, ε⁺ = (1 − L) ε, samples every second.
//! let l = 1.1 - (-1f64).exp();
//! let flow = LtiFlow::new(mat![[1.0]].as_ref())?;
//! let jump = LinearJump::new(mat![[1.0 - l]])?;
//! let sim = simulate_hybrid(flow, jump, &mut Periodic::new(1.0)?, &[1.0], &SimOptions::new(3.0))?;
//! let (_, e) = sim.arc.last().unwrap();
//! assert!((e[0] - ((1.0 - l) * 1f64.exp()).powi(3)).abs() < 1e-13);
//! # Ok::<(), sporadic_sim::SimError>(())
//! ```

pub mod arc;
pub mod dopri5;
mod error;
pub mod event;
pub mod flow;
pub mod noise;
pub mod rng;
pub mod sampling;
pub mod signal;
pub mod simulate;
pub mod system;

pub use arc::{HybridArc, HybridTime, JumpRecord, JumpSide};
pub use dopri5::{DenseStep, Dopri5, Dopri5Options, Dopri5Stats, Outcome};
pub use error::SimError;
pub use event::{Direction, Event, brent};
pub use flow::{
    EmptyFlow, Flow, FnFlow, InputSignal, LtiFlow, LtiPropagator, TransitionTable, integrate_flow,
};
pub use noise::{BoundedUniform, Gaussian, NoiseSource, Sinusoidal, ZeroNoise};
pub use rng::SimRng;
pub use sampling::{
    Adversarial, FromData, IntervalSequence, JumpMap, Periodic, RoundRobin, SampleContext,
    SampleInterval, SamplingRule, Trigger, UniformRandom, Window,
};
pub use signal::{Exosystem, PiecewiseConstant};
pub use simulate::{
    Measurement, Record, SampleLog, SimOptions, Simulation, simulate, simulate_hybrid,
};
pub use system::{
    Gain, HybridObserver, Jump, LinearCorrection, LinearJump, LinearOutputs, NoPlant, Observer,
    Output, Plant, SampleEvent, SampledPlant,
};
