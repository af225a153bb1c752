//! # sporadic
//!
//! Design and certification of state observers for plants whose outputs arrive sporadically
//! (aperiodic, jittery, round-robin sampled measurements). This facade re-exports the workspace
//! crates under short names:
//!
//! - [`linalg`]: matrix exponential, Van Loan integrals, Lyapunov solvers, dense helpers;
//! - [`sdp`]: the primal–dual interior-point SDP solver, the LMI modelling layer, SDPA I/O.
//!
//! The `sporadic` binary (`cargo run --release -- --help`) drives the paper reproductions and the
//! solver from the command line.

pub mod methods;
pub mod plant_file;

pub use sporadic_linalg as linalg;
pub use sporadic_sdp as sdp;
