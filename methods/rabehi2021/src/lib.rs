//! Rabehi, Meslem, El Amraoui & Ramdani (2021), "Interval impulsive observer for linear systems
//! with aperiodic discrete measurements", IEEE TAC 66(11):5407–5413: a continuous-time LTI plant
//! with bounded disturbance, measured with bounded noise at instants whose spacing lies in
//! `[τmin, τmax]`; an interval predictor runs open loop between samples and both bounds are
//! corrected impulsively at every sample.
//!
//! Modules, in the paper's vocabulary:
//! * [`system`]: the plant (2)–(3), the window of Assumption 1 and the bounds of Assumptions 2–3;
//! * [`ipr`]: the internal positive representation — `A^M`, `A^N`, `Ā`, `Γ(L)`, `Γ(G1, G2)` and
//!   the width/centre block structure;
//! * [`observer`]: the interval observer (4), (8) (flows, jumps, a `sporadic-sim` observer);
//! * [`polytope`]: the Taylor polytope of `e^{Āμ}` (paper's single-piece construction or split);
//! * [`analysis`]: Theorem 1 for a given `L` — SDP over the polytope, re-verified on a dense
//!   μ-grid ([`verify`]);
//! * [`prove`](mod@prove): the rigorous proof, in interval arithmetic, of Theorem 1's (19) for a
//!   design's `Γ(L)` and `P_19` for every `μ` of the window ([`prove_design`], issue 24);
//! * [`lyapunov`]: the constants of Theorem 1's proof and Lemma 1;
//! * [`synthesis`]: Proposition 1 — convex restriction `F = I`, alternating LMI steps, sequential
//!   convex inner approximation, Remark 6 re-verification with `Γ(L)`;
//! * [`window`]: necessary limits on `τmax` and the largest certified window (thin code around
//!   the shared search [`sporadic_model::search_upper`]); [`table`]: Table I;
//! * [`width`]: the deterministic interval width, its periodic orbits and guaranteed bounds;
//! * [`simulation`]: plant + observer with random admissible `d`, `v` and sampling, inclusion
//!   check;
//! * [`example`]: the data of §V (the reproduction of §V, Table I and Figures 1–2 is in
//!   `sporadic-reproductions`);
//! * [`Rabehi2021`]: the method behind the common contract [`ObserverMethod`] (design report
//!   with gain, certificate, margin and checks; largest window; simulation).
//!
//! Designing through the contract, for a plant of one's own (a stable plant whose first state is
//! measured, disturbance `|d_i| ≤ 0.1`, noise `|v| ≤ 0.01`, intervals in `[0.1, 1]`):
//!
//! ```
//! use sporadic_rabehi2021::faer::mat;
//! use sporadic_rabehi2021::sporadic_model::{Bounds, Plant};
//! use sporadic_rabehi2021::{MethodOptions, ObserverMethod, Rabehi2021, Sampling, SamplingWindow};
//!
//! let plant = Plant::linear(
//!     mat![[-1.0, 1.0], [0.0, -3.0]].as_ref(),
//!     None,
//!     mat![[1.0, 0.0]].as_ref(),
//! )?
//! .named("two-tank")
//! .with_bounds(Bounds::new(vec![0.1, 0.1], vec![0.01])?)?;
//! let sampling = Sampling::Synchronous(SamplingWindow::new(0.1, 1.0)?);
//! let report = Rabehi2021::default().design(&plant, &sampling, &MethodOptions::default())?;
//! assert!(report.status.is_certified());
//! let l = report.gain("L").unwrap().to_mat();
//! assert_eq!((l.nrows(), l.ncols()), (2, 1)); // L is n × p
//! assert!(report.margin.unwrap().value > 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Theorem 1 for the gain printed in §V, with the crate's own API:
//!
//! ```
//! use sporadic_rabehi2021::analysis::{AnalysisOptions, analyse_gain};
//! use sporadic_rabehi2021::example::{example_window, paper_gain, spring_mass_damper};
//!
//! // Theorem 1 for the gain printed in §V on [0.04, 0.3].
//! let plant = spring_mass_damper(1.0)?;
//! let a = analyse_gain(&plant, &example_window(), paper_gain().as_ref(), &AnalysisOptions::default())?;
//! assert!(a.certified && a.grid.bound < 0.0);
//! # Ok::<(), sporadic_rabehi2021::Error>(())
//! ```

pub mod analysis;
mod error;
pub mod example;
pub mod ipr;
pub mod lyapunov;
mod method;
pub mod observer;
pub mod polytope;
pub mod prove;
pub mod simulation;
pub mod synthesis;
pub mod system;
pub mod table;
pub mod verify;
pub mod width;
pub mod window;

pub use analysis::{Analysis, AnalysisOptions, analyse, analyse_gain};
pub use error::Error;
pub use method::Rabehi2021;
pub use observer::IntervalObserver;
pub use polytope::PolytopeOptions;
pub use prove::prove_design;
pub use simulation::{IntervalRun, simulate_interval};
pub use synthesis::{Bmi44Check, Design, DesignStatus, NotCertified, SynthesisOptions, synthesise};
pub use system::{Bounds, Plant};
pub use window::{
    TauMaxOptions, TauMaxSearch, largest_tau_max, largest_tau_max_for_gain, necessary_tau_max,
};

// The shared contract and the kernels this crate's API uses, so that a user needs only this
// crate. The common plant of the contract is reached as `sporadic_model::Plant`: this crate's
// `Plant` is the linear plant (2)–(3).
pub use faer;
pub use sporadic_embed::TaylorOrder;
pub use sporadic_linalg::{InputError, LinalgError};
pub use sporadic_model;
pub use sporadic_model::{
    DesignReport, MaxIntervalReport, MethodError, MethodOptions, NotApplicable, ObserverMethod,
    Probe, Reason, Sampling, SamplingScenario, SamplingWindow, Scenario, SearchEnd, Status,
    Trajectory, Verdict, WindowSearch, WindowSearchOptions,
};
pub use sporadic_sdp::lmi::{FeasibilityOptions, ModelError, SolveOptions};
