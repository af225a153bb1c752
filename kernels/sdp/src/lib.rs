//! `sporadic-sdp`: a primal–dual interior-point solver for semidefinite programs over a
//! block-diagonal cone (PSD blocks plus one or more nonnegative "LP" blocks), an LMI modelling
//! layer on top of it, and SDPA sparse-format I/O.

pub mod error;
pub mod lmi;
pub mod problem;
pub mod sdpa;
pub mod solver;

pub use error::SdpError;
pub use problem::{Block, BlockData, BlockKind, Problem, ProblemBuilder, SparseSym};
pub use sdpa::{read_sdpa, read_sdpa_file, sdpa_objectives, write_sdpa};
pub use solver::{
    InfeasibilityCertificate, IterationLog, Measures, Settings, Solution, Solver, Status, solve,
};
