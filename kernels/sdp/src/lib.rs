//! `sporadic-sdp`: a primal–dual interior-point solver for semidefinite programs over a
//! block-diagonal cone (PSD blocks plus one or more nonnegative "LP" blocks), an LMI modelling
//! layer on top of it, SDPA sparse-format I/O, and CSDP-format solution files.

pub mod budget;
pub mod error;
pub mod lmi;
pub mod problem;
pub mod sdpa;
pub mod solution_file;
pub mod solver;

pub use budget::Budget;
pub use error::SdpError;
pub use problem::{Block, BlockData, BlockKind, Problem, ProblemBuilder, SparseSym};
pub use sdpa::{read_sdpa, read_sdpa_file, sdpa_objectives, write_sdpa};
pub use solution_file::{
    SolutionFileError, read_solution, read_solution_file, write_solution, write_solution_file,
};
pub use solver::{
    Accept, FacialPath, InfeasibilityCertificate, IterationLog, Measures, Point, Settings,
    Solution, Solver, Status, dimacs_errors, point_measures, solve, solve_from,
};
