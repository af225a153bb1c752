//! The contract shared by every observer method of `sporadic`.
//!
//! A method crate (one per paper) depends on this crate and implements [`ObserverMethod`] for
//! its method; the facade keeps a registry of them. This crate holds what every method needs:
//!
//! * [`plant`]: the validated plant ([`Plant`]: `A`, `B`, outputs or round-robin sensors,
//!   optional Lipschitz nonlinearity and disturbance/noise bounds);
//! * [`window`]: the sampling window [`SamplingWindow`] `[T1, T2]` and the [`Sampling`] of the
//!   outputs (one window, or one per round-robin sensor);
//! * [`outcome`]: [`Status`] (`certified`, `not_certified`, `not_applicable`) with a typed
//!   [`Reason`];
//! * [`report`]: the serialisable reports ([`DesignReport`], [`MaxIntervalReport`],
//!   [`CompareReport`]) with their schema ids;
//! * [`search`]: the one window search (largest `T2` for a given `T1`, smallest `T1` for a
//!   given `T2`) with its probe record;
//! * [`stats`]: [`SolverStats`] of one LMI solve;
//! * [`method`]: the [`ObserverMethod`] trait, [`MethodError`] and [`MethodOptions`];
//! * [`proof`]: rigorous proofs of a design's condition for every `τ` of its window
//!   ([`Proof`], the adaptive subdivision [`prove_on_window`]).
//!
//! ```
//! use sporadic_model::{Sampling, SamplingWindow, Status};
//!
//! let s = Sampling::Synchronous(SamplingWindow::new(0.2, 3.0)?);
//! assert_eq!((s.t1(), s.t2()), (0.2, 3.0));
//! assert!(Status::Certified.is_certified());
//! # Ok::<(), sporadic_linalg::InputError>(())
//! ```

pub mod method;
pub mod outcome;
pub mod plant;
pub mod proof;
pub mod report;
pub mod search;
pub mod stats;
pub mod window;

pub use faer;
pub use method::{
    BoxedError, MethodError, MethodOptions, ObserverMethod, SamplingScenario, Scenario, TimeLimit,
    Trajectory, check_simulatable, default_largest_window, design_within, largest_window_with,
    prove_within,
};
pub use outcome::{NotApplicable, Reason, Status};
pub use plant::{Bounds, Lipschitz, Outputs, Plant};
pub use proof::{
    PieceCheck, Proof, ProofOptions, ProofPiece, ProofStatus, ProofStop, WindowProof, combine,
    prove_on_window,
};
pub use report::{
    COMPARE_SCHEMA, Check, CompareEntry, CompareReport, DESIGN_SCHEMA, DesignReport, Gain,
    GainSchedule, MAX_INTERVAL_SCHEMA, Margin, MaxIntervalReport, NamedMatrix, Probe, SearchEnd,
    SimulationReport,
};
pub use search::{
    Bracketing, SearchError, Tolerance, Verdict, WindowSearch, WindowSearchOptions, search_lower,
    search_upper,
};
pub use sporadic_linalg::InputError;
pub use sporadic_sdp::budget::{self, Budget};
pub use stats::SolverStats;
pub use window::{Sampling, SamplingWindow, power_of_two, sig4, significant};
