//! Typed errors of the SDP crate.

use thiserror::Error;

/// Errors raised while building, reading or solving a standard-form SDP.
///
/// A solver run that ends without an optimum (infeasible, stalled, iteration limit) is **not** an
/// error: it is reported through [`crate::Status`] with the best point found. Errors are reserved
/// for input that cannot be solved at all.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SdpError {
    /// A number in the problem data is NaN or infinite.
    #[error("non-finite value {value} in {location}")]
    NonFinite {
        /// Where the value was found (e.g. `"A_3, block 2, entry (1,4)"`).
        location: String,
        /// The offending value.
        value: f64,
    },
    /// An index or size does not fit the declared structure.
    #[error("invalid problem structure: {0}")]
    Structure(String),
    /// A malformed SDPA sparse file.
    #[error("SDPA format error at line {line}: {reason}")]
    SdpaFormat {
        /// 1-based line number in the file.
        line: usize,
        /// What was expected and what was found.
        reason: String,
    },
    /// An I/O error while reading or writing a file.
    #[error("I/O error: {0}")]
    Io(String),
    /// A primal–dual point `(X, y, S)` does not fit the problem: `y` must be `m×1`, `X` and `S`
    /// must have one matrix per block (the list is `blocks×1`), each in the dense block layout
    /// of [`crate::problem`] (PSD `n×n`, LP `n×1`).
    #[error("{what} has shape {}×{}, expected {}×{}", found.0, found.1, expected.0, expected.1)]
    DimensionMismatch {
        /// What does not fit (e.g. `"X, block 2"`).
        what: String,
        /// The shape the problem requires (rows, columns).
        expected: (usize, usize),
        /// The shape given.
        found: (usize, usize),
    },
    /// A solver setting is out of range (e.g. a non-positive tolerance).
    #[error("invalid solver settings: {0}")]
    InvalidSettings(String),
}
