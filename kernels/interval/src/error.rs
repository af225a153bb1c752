//! Typed errors of `sporadic-interval`.

/// Everything that can go wrong in this crate. Bad input is reported, never a panic and never
/// a silently wrong enclosure.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntervalError {
    /// A scalar interval with `lo > hi` or a NaN endpoint.
    #[error("invalid interval [{lo}, {hi}]")]
    InvalidInterval {
        /// Requested lower endpoint.
        lo: f64,
        /// Requested upper endpoint.
        hi: f64,
    },
    /// A matrix that must be square is not.
    #[error("{what}: matrix is {rows}×{cols}, expected square")]
    NotSquare {
        /// Which argument.
        what: &'static str,
        /// Number of rows.
        rows: usize,
        /// Number of columns.
        cols: usize,
    },
    /// A matrix with no entries where a non-empty one is needed.
    #[error("{what}: empty matrix")]
    Empty {
        /// Which argument.
        what: &'static str,
    },
    /// Operands whose shapes do not fit together.
    #[error("dimension mismatch in {what}: {left:?} vs {right:?}")]
    DimensionMismatch {
        /// Which operation.
        what: &'static str,
        /// Shape (rows, cols) of the left operand.
        left: (usize, usize),
        /// Shape (rows, cols) of the right operand.
        right: (usize, usize),
    },
    /// NaN or ±∞ in an input that must be finite.
    #[error("{what}: non-finite entry at ({row}, {col})")]
    NonFinite {
        /// Which argument.
        what: &'static str,
        /// Row of the first offending entry.
        row: usize,
        /// Column of the first offending entry.
        col: usize,
    },
    /// Invalid sampling window: τ0 > τ1, a negative or non-finite τ.
    #[error("invalid τ-window [{tau0}, {tau1}]: {why}")]
    InvalidWindow {
        /// Requested lower end.
        tau0: f64,
        /// Requested upper end.
        tau1: f64,
        /// What is wrong with it.
        why: &'static str,
    },
    /// Invalid option value (non-positive tolerance, zero pieces, …).
    #[error("invalid option: {0}")]
    InvalidOption(&'static str),
    /// A bound needed by the algorithm is not representable in double precision
    /// (e.g. ‖A‖·τ1 overflows).
    #[error("overflow: {0}")]
    Overflow(&'static str),
    /// A matrix that must be symmetric (midpoint and radius) is not.
    #[error("{what}: not symmetric at ({row}, {col})")]
    NotSymmetric {
        /// Which argument.
        what: &'static str,
        /// Row of the first asymmetric entry.
        row: usize,
        /// Column of the first asymmetric entry.
        col: usize,
    },
    /// The rigorous enclosure became unbounded (radius overflow), e.g. for an extremely
    /// stiff or non-normal matrix over a long window. No enclosure is returned.
    #[error("enclosure failed: {0}")]
    EnclosureFailed(&'static str),
}

impl IntervalError {
    /// Whether the error says that a bound left the range of double precision (a radius or an
    /// endpoint overflowed) rather than that the input was malformed: on such an error a
    /// subdivided proof can decline the piece and split it, as for a wide enclosure.
    pub fn is_overflow(&self) -> bool {
        matches!(self, Self::Overflow(_) | Self::EnclosureFailed(_))
    }
}
