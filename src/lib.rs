//! # sporadic
//!
//! Design and certification of state observers for plants whose outputs arrive sporadically
//! (aperiodic, jittery, round-robin sampled measurements). This facade re-exports every crate of
//! the workspace under a short name, so one dependency gives the whole tool:
//!
//! - [`model`]: the contract every method implements — [`Plant`], [`Sampling`],
//!   [`SamplingWindow`], [`ObserverMethod`], [`DesignReport`] and [`Status`];
//! - the methods, one per paper: [`ferrante2016`], [`sferlazza2021`], [`andrieu2014`],
//!   [`etienne2017`], [`rabehi2021`] (their method structs are also at the root:
//!   [`Ferrante2016`], [`Sferlazza2021`], [`Andrieu2014`], [`Etienne2017`], [`Rabehi2021`]);
//! - [`methods`]: the registry of all methods and the adapters from a [`plant_file`];
//! - kernels: [`linalg`] (matrix exponential, Van Loan integrals, Lyapunov solvers, dense
//!   helpers), [`sdp`] (the primal–dual interior-point SDP solver, the LMI modelling layer,
//!   SDPA I/O), [`embed`] (polytopic embeddings of `τ ↦ e^{Aτ}`);
//! - [`sim`]: hybrid (flow/jump) simulation; [`faer`]: the linear-algebra crate of every
//!   matrix in the API.
//!
//! Two methods side by side on one plant, through the facade only:
//!
//! ```
//! use sporadic::faer::mat;
//! use sporadic::{MethodOptions, ObserverMethod, Plant, Sampling, SamplingWindow};
//!
//! let plant = Plant::linear(mat![[0.0, 1.0], [-1.0, -0.2]].as_ref(), None, mat![[1.0, 0.0]].as_ref())?
//!     .named("damped oscillator");
//! let sampling = Sampling::Synchronous(SamplingWindow::new(0.1, 0.5)?);
//! let methods: [&dyn ObserverMethod; 2] = [&sporadic::Ferrante2016::default(), &sporadic::Sferlazza2021::default()];
//! for m in methods {
//!     let report = m.design(&plant, &sampling, &MethodOptions::default())?;
//!     assert!(report.status.is_certified(), "{}: {:?}", m.id(), report.reason);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The `sporadic` binary (`cargo run --release -- --help`) drives the designs, the paper
//! reproductions and the solver from the command line.

pub mod gains_file;
pub mod methods;
pub mod plant_file;

pub use sporadic_andrieu2014 as andrieu2014;
pub use sporadic_embed as embed;
pub use sporadic_etienne2017 as etienne2017;
pub use sporadic_ferrante2016 as ferrante2016;
pub use sporadic_linalg as linalg;
pub use sporadic_model as model;
pub use sporadic_rabehi2021 as rabehi2021;
pub use sporadic_sdp as sdp;
pub use sporadic_sferlazza2021 as sferlazza2021;
pub use sporadic_sim as sim;

pub use faer;
pub use sporadic_andrieu2014::Andrieu2014;
pub use sporadic_etienne2017::Etienne2017;
pub use sporadic_ferrante2016::Ferrante2016;
pub use sporadic_model::{
    Bounds, DesignReport, Lipschitz, MethodError, MethodOptions, ObserverMethod, Plant, Reason,
    Sampling, SamplingWindow, Status,
};
pub use sporadic_rabehi2021::Rabehi2021;
pub use sporadic_sferlazza2021::Sferlazza2021;
