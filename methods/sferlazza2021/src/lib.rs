//! Round-robin sampled-data observer with jitter (Sferlazza, Tarbouriech & Zaccarian, *Automatica*
//! 129:109573, 2021) and the sequential-refinement design loop of its §5.3.
//!
//! `N` sensors `y_σ = C_σx` are read one at a time in round-robin order; sensor σ is read when the
//! time since the previous sample lies in its window `[T_mσ, T_Mσ]` (the convention of the hybrid
//! model (9)). Between samples the observer runs open loop; at a sample
//! `x̂⁺ = x̂ + K_σ(τ)(y_σ − C_σx̂)` with the gain (45) computed from a Lyapunov matrix `P_σ`.
//!
//! The method behind the contract of `sporadic` is [`Sferlazza2021`], an
//! [`ObserverMethod`]: it takes a [`Plant`] (round-robin sensors, or one output matrix as a single
//! sensor) and its [`Sampling`] (one [`SamplingWindow`] per sensor) and reports the gain schedules,
//! the certificate, the margin and the checks in a [`DesignReport`]. The crate's own entry point
//! is [`design()`] on a [`RoundRobinPlant`].
//!
//! ```
//! use sporadic_sferlazza2021::faer::mat;
//! use sporadic_sferlazza2021::{
//!     MethodOptions, ObserverMethod, Plant, Sampling, SamplingWindow, Sferlazza2021,
//! };
//!
//! // A lightly damped oscillator (ω = 2 rad/s, ζ = 0.05) with a position and a velocity
//! // sensor read in turn, each 0.1 s to 0.3 s after the previous sample.
//! let a = mat![[0.0, 1.0], [-4.0, -0.2]];
//! let (c1, c2) = (mat![[1.0, 0.0]], mat![[0.0, 1.0]]);
//! let plant = Plant::round_robin(a.as_ref(), None, &[c1.as_ref(), c2.as_ref()])?.named("oscillator");
//! let w = SamplingWindow::new(0.1, 0.3)?;
//! let sampling = Sampling::RoundRobin(vec![w, w]);
//!
//! let method = Sferlazza2021::default();
//! let report = method.design(&plant, &sampling, &MethodOptions::default())?;
//! assert!(report.status.is_certified(), "{:?}", report.reason);
//! // One gain schedule K_σ(τ) per sensor: 2 × 1 matrices on 11 values of τ in [0.1, 0.3].
//! let k1 = report.gain("K_1").unwrap();
//! assert_eq!((k1.to_mat().nrows(), k1.to_mat().ncols()), (2, 1));
//! assert_eq!(k1.schedule.as_ref().unwrap().tau.len(), 11);
//! assert!(report.margin.unwrap().value > 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Modules, in the paper's vocabulary:
//! * [`plant`]: the plant, sensors, windows and the complements `C_σ^⊥` (Assumptions 1–2);
//! * [`detectability`]: the necessary condition of Proposition 1 (PBH on the lifted pair);
//! * [`gain`]: `K_σ(τ)` by (45) and by its closed form, `Φ_σ(τ)`;
//! * [`jitter_free`]: design LMI (23) with gains (24), analysis LMI (18), the monodromy (19);
//! * [`exponential_bound`], [`synthesis`], [`validation`], [`design`](mod@design): the §5.3
//!   algorithm — Step 1 (β, γ), the synthesis SDP (47), the grid validation (48)–(50) with three
//!   grid policies, and the loop with its iteration log;
//! * [`iss`]: the constants of the proof of Theorem 3;
//! * [`simulation`]: the error dynamics (53) and the Lyapunov function (30) along them;
//! * [`example`]: the quarter-car suspension of §6;
//! * [`prove`]: the rigorous proof of (44) over every τ of the windows (interval arithmetic);
//! * [`method`]: the [`ObserverMethod`] implementation.
//!
//! Corrections of the printed paper (each documented where it applies): the window convention of
//! (4)/Definition 1 is reversed with respect to (9); the noise enters the jump as `−K_σw` (printed
//! `+K_σw` in (28)/(53)); `Ψ_σ` in the proof of Theorem 4 uses `P_σ`, not `P_Γ(σ)`; (46) has
//! `−P_ΓK_σC_σC_σᵀ`; the matrices printed in (52) are not a solution (`P_2` is indefinite).

pub mod design;
pub mod detectability;
pub mod error;
pub mod example;
pub mod exponential_bound;
pub mod gain;
pub mod iss;
pub mod jitter_free;
pub mod method;
pub mod normalise;
pub mod plant;
pub mod prove;
pub mod simulation;
pub mod synthesis;
pub mod validation;

pub use design::{
    Design, DesignLoop, DesignOptions, GridMinimum, IterationRecord, design, design_screened,
};
pub use detectability::{DetectabilityOptions, DetectabilityReport, PbhCheck};
pub use error::Error;
pub use example::QuarterCar;
pub use exponential_bound::{BoundOptions, CertifiedBound};
pub use gain::GainSchedule;
pub use iss::{IssConstants, IssOptions};
pub use jitter_free::JitterFreeDesign;
pub use method::{Sferlazza2021, output_map};
pub use plant::{RoundRobinPlant, Sensor};
pub use simulation::{ErrorTrajectory, JumpSample, SimulationOptions};
pub use synthesis::{Synthesis, SynthesisResult};
pub use validation::{
    ExponentialBound, GridPolicy, SensorValidation, UniformGrid, ValidationOptions, WindowGrid,
    XiFamily,
};

pub use faer;
pub use sporadic_embed::EmbedError;
pub use sporadic_linalg::{InputError, LinalgError, PbhOptions, PbhTest};
pub use sporadic_model::{
    Bounds, Check, DesignReport, Gain, GainSchedule as ReportedSchedule, Lipschitz, Margin,
    MaxIntervalReport, MethodError, MethodOptions, NamedMatrix, NotApplicable, ObserverMethod,
    Outputs, Plant, Probe, Reason, Sampling, SamplingScenario, SamplingWindow, Scenario, SearchEnd,
    SimulationReport, SolverStats, Status, Trajectory,
};
pub use sporadic_sdp::lmi::{Expr, FeasibilityOptions, LmiSolution, ModelError, SolveOptions, Var};
pub use sporadic_sim::SimError;
