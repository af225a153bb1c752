//! Typed errors of `sporadic-embed`.

use sporadic_linalg::{InputError, LinalgError};

/// Everything that can go wrong while building or querying an embedding.
///
/// Bad input (wrong shape, NaN/Inf, an inverted interval, contradictory bounds) is reported with
/// a variant naming the offending quantity; it never panics.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EmbedError {
    /// Bad input: a matrix not square or empty, mismatched dimensions, NaN/Inf, an invalid
    /// sampling window `[T1, T2]`.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A Jacobian entry has a lower bound above its upper bound.
    #[error("Jacobian bound for entry ({row},{col}): lower {lower} > upper {upper}")]
    InvalidBounds {
        /// Row of the entry (component of φ).
        row: usize,
        /// Column of the entry (argument of φ).
        col: usize,
        /// The lower bound given.
        lower: f64,
        /// The upper bound given.
        upper: f64,
    },
    /// The box has `2^free` corners, more than the configured limit.
    #[error("the polytope would have 2^{free} vertices, more than the limit of {limit}")]
    TooManyVertices {
        /// Number of coefficients (or Jacobian entries) with a non-degenerate range.
        free: usize,
        /// The configured maximal number of vertices.
        limit: usize,
    },
    /// No admissible Taylor order reaches the requested remainder tolerance.
    #[error(
        "Taylor remainder tolerance {requested:e} is unreachable: best bound {achieved:e} at order {order}; split [T1, T2] into shorter pieces"
    )]
    ToleranceUnreachable {
        /// The requested bound on the remainder.
        requested: f64,
        /// The smallest bound attained up to the maximal order.
        achieved: f64,
        /// The order at which `achieved` was attained.
        order: usize,
    },
    /// Any other invalid argument (zero pieces, a negative tolerance, …).
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// A numerical step failed (eigenvalue iteration, a singular resolvent on the contour, …).
    #[error("numerical failure: {0}")]
    Numerical(String),
    /// Error raised by a `sporadic-linalg` kernel (matrix exponential, …).
    #[error(transparent)]
    Linalg(#[from] LinalgError),
}
