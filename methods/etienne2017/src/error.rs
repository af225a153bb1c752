//! Typed errors of `sporadic-etienne2017`. Bad input is reported with what was wrong and where;
//! nothing in this crate panics on user data.

use sporadic_embed::EmbedError;
use sporadic_linalg::{InputError, LinalgError};
use sporadic_model::Reason;
use sporadic_sdp::SdpError;
use sporadic_sdp::lmi::ModelError;

/// Everything that can go wrong while building the plant, designing or certifying a gain,
/// searching the largest sampling interval or simulating the observer.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input: what was wrong and where (a matrix not square or empty, mismatched
    /// dimensions, NaN/Inf, a parameter out of range, an invalid sampling window).
    #[error(transparent)]
    Input(#[from] InputError),
    /// A Jacobian entry has a lower bound above its upper bound.
    #[error("Jacobian bound of entry ({row},{col}): lower {lower} > upper {upper}")]
    InvalidJacobianBounds {
        /// Row (component of `φ`).
        row: usize,
        /// Column (argument of `φ`).
        col: usize,
        /// Lower bound given.
        lower: f64,
        /// Upper bound given.
        upper: f64,
    },
    /// The LMIs (20) have no verifiable strictly feasible point: the optimal common margin `t*`
    /// of the margin problem ([`crate::lmi`]) is not above the threshold, or the solver certified
    /// infeasibility. Theorem 3 and Corollary 2 are only sufficient, so this does not prove that
    /// no observer exists.
    #[error(
        "LMIs (20) have no verifiable strictly feasible point for {condition}: {}; {reason}",
        margin.map_or_else(|| "no margin computed".to_string(), |m| format!("margin {m:.3e}"))
    )]
    Infeasible {
        /// Which condition was solved.
        condition: &'static str,
        /// Optimal common margin `t*`, when one was computed.
        margin: Option<f64>,
        /// The LMI layer's explanation.
        reason: String,
    },
    /// The solver established neither feasibility nor infeasibility.
    #[error("LMI solve inconclusive for {condition}: {reason}")]
    Inconclusive {
        /// Which condition was solved.
        condition: &'static str,
        /// The LMI layer's explanation.
        reason: String,
    },
    /// A certificate `P1` is not positive definite, so `K = P1⁻¹L` cannot be formed.
    #[error("singular matrix: {what}")]
    Singular {
        /// Which matrix.
        what: String,
    },
    /// The LMI layer returned a certificate but the independent check (eigenvalues of every
    /// block of (20), the τ-grid check of (19b)/(19c), and the contraction of `z'P1z` across
    /// `(I − K(τ)C)e^{R_p τ}`) failed; the design is not returned as valid.
    #[error(
        "independent verification failed: {what} = {value:.3e} (rounding tolerance {tolerance:.3e}) at τ = {tau} (vertex {vertex:?})"
    )]
    VerificationFailed {
        /// Which check failed.
        what: &'static str,
        /// The offending value.
        value: f64,
        /// The rounding-error bound (with safety factor) it had to clear.
        tolerance: f64,
        /// Where on the τ grid (NaN for τ-independent blocks).
        tau: f64,
        /// Which vertex `R_p`, if vertex-specific.
        vertex: Option<usize>,
    },
    /// Writing an output file failed.
    #[error("I/O error on {path}: {source}")]
    Io {
        /// The file or directory.
        path: std::path::PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// An error from the dense linear-algebra kernels.
    #[error("linear algebra: {0}")]
    Linalg(#[from] LinalgError),
    /// An error from the Jacobian polytope (Lemma 1).
    #[error("polytope: {0}")]
    Embed(#[from] sporadic_embed::EmbedError),
    /// An error from the LMI modelling layer or the SDP solver.
    #[error("LMI model: {0}")]
    Lmi(#[from] sporadic_sdp::lmi::ModelError),
    /// An error from the hybrid simulator or the figure writer.
    #[error("simulation: {0}")]
    Sim(#[from] sporadic_sim::SimError),
}

impl Error {
    /// The verdict on the plant this error stands for, as a typed [`Reason`] (with the error's
    /// message), or `None` when it is not a verdict (bad input, I/O, a modelling error).
    ///
    /// * [`Error::Infeasible`] → [`Reason::InfeasibleLmi`];
    /// * [`Error::Inconclusive`] → [`Reason::SolverInconclusive`];
    /// * [`Error::VerificationFailed`] → [`Reason::VerificationFailed`] (with its `τ` when the
    ///   failing check is pointwise);
    /// * [`Error::Singular`] (`P1` of a verified point not positive definite), an overflow or a
    ///   non-convergence of a linear-algebra kernel (e.g. `e^{R_p τ}`), non-finite solver data →
    ///   [`Reason::NumericalFailure`];
    /// * a Jacobian polytope with too many vertices → [`Reason::UnsupportedStructure`] (the
    ///   plant is outside what Lemma 1's enumeration can handle).
    pub fn reason(&self) -> Option<Reason> {
        let message = self.to_string();
        let numerical =
            |e: &LinalgError| !matches!(e, LinalgError::Input(_) | LinalgError::InvalidArgument(_));
        Some(match self {
            Error::Infeasible { .. } => Reason::InfeasibleLmi { message },
            Error::Inconclusive { .. } => Reason::SolverInconclusive { message },
            Error::VerificationFailed { tau, .. } => Reason::VerificationFailed {
                tau: tau.is_finite().then_some(*tau),
                message,
            },
            Error::Singular { .. } => Reason::NumericalFailure { message },
            Error::Embed(EmbedError::TooManyVertices { .. }) => {
                Reason::UnsupportedStructure { message }
            }
            Error::Embed(EmbedError::Numerical(_)) => Reason::NumericalFailure { message },
            Error::Linalg(e) | Error::Embed(EmbedError::Linalg(e)) if numerical(e) => {
                Reason::NumericalFailure { message }
            }
            Error::Lmi(
                ModelError::NonFinite { .. } | ModelError::Solver(SdpError::NonFinite { .. }),
            ) => Reason::NumericalFailure { message },
            Error::Lmi(ModelError::Linalg(e)) if numerical(e) => {
                Reason::NumericalFailure { message }
            }
            _ => return None,
        })
    }

    /// Whether the error is bad input (dimensions, NaN, a parameter or window out of range).
    pub fn is_input(&self) -> bool {
        let linalg =
            |e: &LinalgError| matches!(e, LinalgError::Input(_) | LinalgError::InvalidArgument(_));
        match self {
            Error::Input(_) | Error::InvalidJacobianBounds { .. } => true,
            Error::Linalg(e) => linalg(e),
            Error::Embed(e) => match e {
                EmbedError::Input(_)
                | EmbedError::InvalidArgument(_)
                | EmbedError::InvalidBounds { .. } => true,
                EmbedError::Linalg(e) => linalg(e),
                _ => false,
            },
            Error::Lmi(e) => match e {
                ModelError::Input(_)
                | ModelError::InvalidArgument(_)
                | ModelError::Solver(SdpError::InvalidSettings(_)) => true,
                ModelError::Linalg(e) => linalg(e),
                _ => false,
            },
            Error::Sim(sporadic_sim::SimError::Input(_)) => true,
            _ => false,
        }
    }
}
