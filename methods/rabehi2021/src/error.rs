//! Typed errors of `sporadic-rabehi2021`. Bad input is reported with what was wrong and where;
//! nothing in this crate panics on user data.

use sporadic_linalg::{InputError, LinalgError};

/// Everything that can go wrong while building, analysing, designing or simulating the interval
/// observer.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input: what was wrong and where (a matrix not square or empty, mismatched
    /// dimensions, NaN/Inf, a parameter out of range, an invalid sampling window).
    #[error(transparent)]
    Input(#[from] InputError),
    /// The disturbance bounds of Assumption 3 are contradictory (`d̲_i > d̄_i`) or the noise bound of
    /// Assumption 2 is negative (`v̄_i < 0`).
    #[error("invalid bound in {what} at component {index}: {reason}")]
    InvalidBounds {
        /// Which bound (`d_lower/d_upper` or `v_bar`).
        what: &'static str,
        /// Component index.
        index: usize,
        /// The violated condition, with the numbers.
        reason: String,
    },
    /// Assumption 4 fails: `Ā` is (numerically) singular, so the equilibrium `ξ_ueq = −Ā⁻¹Ξ̄` of
    /// the comparison system (11) does not exist.
    #[error("assumption A4 fails: A-bar is singular (reciprocal condition estimate {rcond:.3e})")]
    SingularABar {
        /// Smallest/largest singular value of `Ā`.
        rcond: f64,
    },
    /// The initial enclosure (5) `x̲(t0) ≤ x(t0) ≤ x̄(t0)` does not hold.
    #[error(
        "initial enclosure (5) violated at component {index}: lower {lower} <= x {x} <= upper {upper} fails"
    )]
    InitialEnclosure {
        /// Component.
        index: usize,
        /// `x̲_i(t0)`.
        lower: f64,
        /// `x_i(t0)`.
        x: f64,
        /// `x̄_i(t0)`.
        upper: f64,
    },
    /// A realised disturbance or noise sample leaves the bounds of Assumption 2 or 3.
    #[error("{what} = {value} at component {index} leaves its bounds [{lower}, {upper}]")]
    InadmissibleSignal {
        /// Which signal.
        what: &'static str,
        /// Component.
        index: usize,
        /// The offending value.
        value: f64,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
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
    /// An error from the polytopic embedding of `e^{Āμ}`.
    #[error("embedding: {0}")]
    Embed(#[from] sporadic_embed::EmbedError),
    /// An error from the LMI modelling layer or the SDP solver.
    #[error("LMI model: {0}")]
    Lmi(#[from] sporadic_sdp::lmi::ModelError),
    /// No LMI step of the Proposition 1 pipeline returned a finite point: the solver established
    /// neither feasibility nor infeasibility (a verdict on the plant, not bad input).
    #[error(
        "solver inconclusive: every one of the {steps} LMI steps of the Proposition 1 pipeline returned a non-finite point"
    )]
    SolverInconclusive {
        /// Number of LMI steps attempted.
        steps: usize,
    },
    /// An error from the hybrid simulator or the figure writer.
    #[error("simulation: {0}")]
    Sim(#[from] sporadic_sim::SimError),
}
