//! Typed errors of `sporadic-linalg`.

use crate::InputError;

/// Everything that can go wrong in this crate. Bad input is reported, never a panic.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinalgError {
    /// Bad input: what was wrong and where (a matrix not square or empty, mismatched
    /// dimensions, NaN/Inf, a parameter out of range, an invalid sampling window).
    #[error(transparent)]
    Input(#[from] InputError),
    /// A matrix that must be inverted (or an equation that must have a unique solution) is singular.
    #[error("singular: {what}")]
    Singular {
        /// Which matrix or equation was singular.
        what: String,
    },
    /// An iterative method (eigenvalue, SVD, …) did not converge.
    #[error("no convergence: {what}")]
    NoConvergence {
        /// Which iteration failed.
        what: String,
    },
    /// The result is not representable in double precision (it overflows).
    #[error("overflow: {what}")]
    Overflow {
        /// Which result overflowed.
        what: String,
    },
    /// Any other invalid argument (negative tolerance, non-symmetric input, …).
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
}

impl LinalgError {
    pub(crate) fn singular(what: &str) -> Self {
        Self::Singular {
            what: what.to_owned(),
        }
    }
    pub(crate) fn no_convergence(what: &str) -> Self {
        Self::NoConvergence {
            what: what.to_owned(),
        }
    }
    pub(crate) fn overflow(what: &str) -> Self {
        Self::Overflow {
            what: what.to_owned(),
        }
    }
}
