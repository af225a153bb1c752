//! Ferrante, Gouaisbaut, Sanfelice & Tarbouriech (2016), "State estimation of linear systems in the
//! presence of sporadic measurements", Automatica 73: an observer `ẑ` that runs open loop between
//! samples and jumps `ẑ⁺ = ẑ + L(y − Cẑ)` when a measurement arrives (the paper writes the output
//! matrix `M`; this crate calls it `C`), for inter-sample times in a window `[T1, T2]`, designed
//! through a hybrid Lyapunov function and a polytopic embedding of `e^{Av}`.
//!
//! The method behind `sporadic`'s common contract is [`Ferrante2016`], an
//! [`ObserverMethod`]: design with a typed verdict, largest window, simulation.
//!
//! ```
//! use sporadic_ferrante2016::faer::mat;
//! use sporadic_ferrante2016::sporadic_model::Plant;
//! use sporadic_ferrante2016::{Ferrante2016, MethodOptions, ObserverMethod, Sampling, SamplingWindow};
//!
//! // A lightly damped oscillator measured in position, every inter-sample time in [0.1, 1].
//! let plant = Plant::linear(
//!     mat![[0.0, 1.0], [-1.0, -0.2]].as_ref(),
//!     None,
//!     mat![[1.0, 0.0]].as_ref(),
//! )?
//! .named("damped oscillator");
//! let sampling = Sampling::Synchronous(SamplingWindow::new(0.1, 1.0)?);
//! let report = Ferrante2016::default().design(&plant, &sampling, &MethodOptions::default())?;
//! assert!(report.status.is_certified());
//! let l = report.gain("L").unwrap().to_mat(); // n × q: one column per output
//! assert_eq!((l.nrows(), l.ncols()), (2, 1));
//! assert!(report.margin.as_ref().unwrap().value > 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Modules, in the paper's vocabulary:
//! * [`system`]: the data of Problem 1, [`Plant`] `(A, C)`; the window `[T1, T2]` is a
//!   [`SamplingWindow`];
//! * [`detectability`]: the necessary condition of Remark 3 (`(e^{Av}, M)` detectable on the window,
//!   including the aliasing instants a grid would miss), with [`Error::NotDetectable`];
//! * [`design`](mod@design): Corollary 1 — LMI (41) over the vertices of a residue (default), Taylor or
//!   split embedding, margin maximisation, `L = F⁻¹J` ([`design()`]); and the same LMI with `J = FL`
//!   to certify a given gain ([`analyse`]);
//! * [`verify`](mod@verify): the embedding-independent grid check of (12) and of the Schur property of
//!   `e^{Av}(I − LM)`;
//! * [`bounds`]: the constants of Theorems 1 and 2 (`α1, α2, β, θ, γ, R, κ`, ISS gain) and the GES
//!   bound as a function of `(t, j)`;
//! * [`window`]: the largest certifiable `T2` for a given `T1` (and smallest `T1` for a given `T2`),
//!   by the shared window search of `sporadic-model`;
//! * [`method`]: [`Ferrante2016`], the [`ObserverMethod`] implementation;
//! * [`simulation`]: the observer and its error system simulated with `sporadic-sim`, and the check
//!   of the Theorem 1 bound along a solution;
//! * [`examples`]: the data of Examples 1 and 2 (their reproduction is in
//!   `sporadic-reproductions`).
//!
//! Corrections of the printed paper (each documented where it applies): `κ = √(α2/α1)e^{R/2}` in
//! (21) (printed `e^{R/α1}`); `ρ = ‖P‖(1 + 2‖P‖/β)max‖e^{Av}‖²` in Theorem 2 (the printed
//! `‖P‖(2/β + ‖P‖)…` is also computed); `(α2/α1)e^{R}` in (34). Additions that are not in the paper:
//! the robust form of (41) for embeddings with a remainder, the equivalent reduced `2n × 2n` vertex
//! LMI ([`LmiForm::Reduced`]), interval splitting, and the window searches.
//!
//! ```
//! use sporadic_ferrante2016::examples::example1;
//! use sporadic_ferrante2016::{BoundOptions, DesignOptions, analyse, bound_constants};
//!
//! // Example 1: A = M = 1, T1 = T2 = 1, L = 1.1 − e^{−1}, P = 1.
//! let ex = example1()?;
//! let c = bound_constants(&ex.plant, &ex.window, ex.l.as_ref(), ex.p.as_ref(), &BoundOptions::default())?;
//! assert!((c.theorem1.beta - 0.4698).abs() < 5e-5);
//! assert!((c.theorem1.theta + 0.0657).abs() < 5e-5);
//! // LMI (41) with J = F·L certifies the gain.
//! assert!(analyse(&ex.plant, &ex.window, ex.l.as_ref(), &DesignOptions::default())?.certified);
//! # Ok::<(), sporadic_ferrante2016::Error>(())
//! ```

mod active;
pub mod bounds;
mod certificate;
pub mod design;
pub mod detectability;
mod error;
pub mod examples;
mod grid;
mod lmi;
pub mod method;
pub mod normalise;
pub mod prove;
pub mod refine;
pub mod simulation;
pub mod system;
pub mod verify;
pub mod window;

pub use bounds::{BoundConstants, BoundOptions, Theorem1Bound, Theorem2Bound, bound_constants};
pub use design::{
    Analysis, Certificate, Design, DesignOptions, TraceCertificate, analyse, design,
    min_trace_certificate,
};
pub use detectability::{DetectabilityOptions, DetectabilityReport, check_detectability};
pub use error::Error;
pub use lmi::{LmiForm, LmiSize};
pub use method::Ferrante2016;
pub use prove::prove_condition12;
pub use refine::Refinement;
pub use simulation::{BoundCheck, check_bound, simulate_error, simulate_observer};
pub use system::Plant;
pub use verify::{Verification, VerifyOptions, factor_product, verify, verify_factor};
pub use window::{largest_t2, smallest_t1};

// The crates whose types appear in this crate's API, and their items at the root, so that a user
// needs no other crate (and no version-pinned faer). `sporadic_model::Plant` (the plant of the
// common contract) is reached as `sporadic_model::Plant`: this crate's `Plant` is the pair (A, C).
pub use faer;
pub use sporadic_embed;
pub use sporadic_embed::{
    Containment, EmbedError, Embedding, EmbeddingMethod, ResidueOptions, TaylorOptions, TaylorOrder,
};
pub use sporadic_linalg::{InputError, LinalgError, PbhOptions};
pub use sporadic_model;
pub use sporadic_model::{
    Bracketing, DesignReport, MaxIntervalReport, MethodError, MethodOptions, NotApplicable,
    ObserverMethod, Probe, Reason, Sampling, SamplingScenario, SamplingWindow, Scenario, SearchEnd,
    SolverStats, Status, Tolerance, Trajectory, WindowSearch, WindowSearchOptions,
};
pub use sporadic_sdp;
pub use sporadic_sdp::lmi::{FeasibilityOptions, ModelError, Normalisation, Outcome, SolveOptions};
pub use sporadic_sim;
pub use sporadic_sim::{HybridArc, InputSignal, SamplingRule, SimError, SimOptions, Simulation};
