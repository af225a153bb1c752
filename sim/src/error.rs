//! Typed errors of `sporadic-sim`: every bad input is reported with what was wrong and where.

use sporadic_linalg::{InputError, LinalgError};

/// Everything that can go wrong while building or running a hybrid simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// Bad input: mismatched dimensions, NaN/Inf (also a state that became non-finite during the
    /// simulation), an empty input, an invalid sampling window.
    #[error(transparent)]
    Input(#[from] InputError),
    /// Any other invalid argument (negative tolerance, horizon in the past, …).
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// The adaptive integrator needed a step smaller than the floating-point resolution of `t`.
    #[error("step size underflow at t = {t} (h = {h:e}): the flow is too stiff or singular")]
    StepSizeUnderflow {
        /// Time at which the step was attempted.
        t: f64,
        /// The rejected step size.
        h: f64,
    },
    /// The adaptive integrator exceeded its step budget.
    #[error("step budget of {max_steps} exhausted at t = {t}")]
    TooManySteps {
        /// Time reached.
        t: f64,
        /// The configured budget.
        max_steps: usize,
    },
    /// A data-driven sampling sequence ran out of entries before the horizon.
    #[error("sampling sequence exhausted after {used} intervals")]
    SequenceExhausted {
        /// Number of intervals consumed.
        used: usize,
    },
    /// A line of a CSV input could not be parsed.
    #[error("CSV parse error at line {line}: {message}")]
    Csv {
        /// 1-based line number.
        line: usize,
        /// What was wrong with it.
        message: String,
    },
    /// An error from the dense linear-algebra kernels (matrix exponential, …).
    #[error("linear algebra: {0}")]
    Linalg(#[from] LinalgError),
    /// An I/O error while writing a CSV file.
    #[error("I/O error: {0}")]
    Io(#[from] std::io::Error),
}

impl SimError {
    pub(crate) fn invalid(msg: impl Into<String>) -> Self {
        Self::InvalidArgument(msg.into())
    }
}
