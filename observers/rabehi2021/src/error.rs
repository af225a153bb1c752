//! Typed errors of `sporadic-rabehi2021`. Bad input is reported with what was wrong and where;
//! nothing in this crate panics on user data.

use faer::MatRef;
use sporadic_linalg::LinalgError;

/// Everything that can go wrong while building, analysing, designing or simulating the interval
/// observer.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The sampling window violates Assumption 1 with `0 < τmin ≤ τmax < ∞` (Rabehi et al. 2021,
    /// A1; `τmin > 0` excludes Zeno behaviour).
    #[error("invalid sampling window [tau_min, tau_max] = [{tau_min}, {tau_max}]: {reason}")]
    InvalidWindow {
        /// Lower bound `τmin` as given.
        tau_min: f64,
        /// Upper bound `τmax` as given.
        tau_max: f64,
        /// Which condition is violated.
        reason: &'static str,
    },
    /// A matrix that must be square is not.
    #[error("{what} must be square, got {rows}×{cols}")]
    NotSquare {
        /// Which matrix.
        what: &'static str,
        /// Number of rows.
        rows: usize,
        /// Number of columns.
        cols: usize,
    },
    /// An input has no entries (`n = 0` or `p = 0`).
    #[error("empty input: {what}")]
    Empty {
        /// Which input.
        what: &'static str,
    },
    /// Two objects that must agree in size do not.
    #[error("dimension mismatch in {what}: expected {expected}, found {found}")]
    DimensionMismatch {
        /// Which dimension was checked.
        what: String,
        /// The size required by the other operand(s).
        expected: usize,
        /// The size actually supplied.
        found: usize,
    },
    /// An input (or a quantity computed from it) contains NaN or ±∞.
    #[error("non-finite value (NaN or ±Inf) in {what}")]
    NonFinite {
        /// Which quantity, with the offending entry.
        what: String,
    },
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
    /// A scalar option is outside its admissible range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// Name of the parameter.
        name: &'static str,
        /// The value supplied.
        value: f64,
        /// The condition it violates.
        reason: &'static str,
    },
    /// Assumption 4 fails: `Ā` is (numerically) singular, so the equilibrium `ξ_ueq = −Ā⁻¹Ξ̄` of
    /// the comparison system (11) does not exist.
    #[error("assumption A4 fails: A-bar is singular (reciprocal condition estimate {rcond:e})")]
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
    /// An error from the hybrid simulator or the figure writer.
    #[error("simulation: {0}")]
    Sim(#[from] sporadic_sim::SimError),
}

impl Error {
    pub(crate) fn mismatch(what: impl Into<String>, expected: usize, found: usize) -> Self {
        Self::DimensionMismatch {
            what: what.into(),
            expected,
            found,
        }
    }
    pub(crate) fn non_finite(what: impl Into<String>) -> Self {
        Self::NonFinite { what: what.into() }
    }
}

/// Checks that every entry of `a` is finite.
pub(crate) fn check_finite(a: MatRef<'_, f64>, what: &str) -> Result<(), Error> {
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            if !a[(i, j)].is_finite() {
                return Err(Error::non_finite(format!("{what} at entry ({i},{j})")));
            }
        }
    }
    Ok(())
}

/// Checks that every entry of `v` is finite.
pub(crate) fn check_finite_vec(v: &[f64], what: &str) -> Result<(), Error> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(i) => Err(Error::non_finite(format!("{what} at component {i}"))),
        None => Ok(()),
    }
}

/// Checks a square, non-empty, finite matrix; returns its order.
pub(crate) fn check_square(a: MatRef<'_, f64>, what: &'static str) -> Result<usize, Error> {
    if a.nrows() != a.ncols() {
        return Err(Error::NotSquare {
            what,
            rows: a.nrows(),
            cols: a.ncols(),
        });
    }
    if a.nrows() == 0 {
        return Err(Error::Empty { what });
    }
    check_finite(a, what)?;
    Ok(a.nrows())
}
