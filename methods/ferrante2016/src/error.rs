//! Typed errors of `sporadic-ferrante2016`. Bad input is reported with what was wrong and where;
//! nothing in this crate panics on user data.

use sporadic_embed::EmbedError;
use sporadic_linalg::{InputError, LinalgError};
use sporadic_model::{Reason, significant};
use sporadic_sdp::SdpError;
use sporadic_sdp::lmi::ModelError;

/// Everything that can go wrong while designing, certifying, bounding or simulating the observer.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input: what was wrong and where (a matrix not square or empty, mismatched
    /// dimensions, NaN/Inf, a parameter out of range, an invalid sampling window).
    #[error(transparent)]
    Input(#[from] InputError),
    /// The necessary condition of Remark 3 fails: the sampled pair `(e^{Av}, M)` is not detectable at
    /// the inter-sample time `v`, so no `(P, L)` can satisfy (12). The eigenvalue `μ` of `e^{Av}` with
    /// `|μ| ≥ 1` (up to the tolerance) has an (almost) unobservable eigenvector: the smallest
    /// singular value of `[(μI − e^{Av})/|μ|; M/‖M‖_F]` is `margin` (see
    /// [`sporadic_linalg::pbh_detectability`]). A mode with `|μ|` below one but within the
    /// tolerance is said to decay too slowly to certify, not to make (12) impossible.
    #[error(
        "(e^(Av), M) is not detectable at v = {}: eigenvalue {mu_re:.3e} + {mu_im:.3e}i (|mu| = \
         {modulus:.3e}) is unobservable (relative PBH margin {margin:.3e}); {}",
        significant(*v),
        consequence(*modulus)
    )]
    NotDetectable {
        /// The inter-sample time where detectability is lost.
        v: f64,
        /// Real part of the unobservable eigenvalue `μ` of `e^{Av}`.
        mu_re: f64,
        /// Imaginary part of `μ`.
        mu_im: f64,
        /// `|μ|` (at least one up to the tolerance).
        modulus: f64,
        /// Relative smallest singular value of the PBH matrix.
        margin: f64,
    },
    /// A gain `L` (or the design's `F`) is unusable: `F` singular, or `L` of the wrong size.
    #[error("singular matrix: {what}")]
    Singular {
        /// Which matrix.
        what: String,
    },
    /// A derived constant is degenerate (e.g. `β ≤ 0`: the given `(P, L)` does not satisfy (12), so
    /// Theorems 1–2 give no bound).
    #[error("condition (12) does not hold for the given (P, L): {what} = {value:.3e}")]
    ConditionViolated {
        /// Which quantity certifies the violation.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// LMI (41) (or (36) with `L` fixed) has no verifiable strictly feasible point on the vertex
    /// set: the optimal margin is at or below the verification threshold (then a strictly
    /// feasible point with a smaller margin is not excluded: a weakly detectable sampled pair,
    /// e.g. a window short against the plant's time constants, can have one whose margin is far
    /// below rounding), or the solver certified infeasibility, or the margin of the form solved
    /// is above the threshold but does not carry over to a margin of (41) that rounding can
    /// resolve at its point (`unverified`: a numerical failure, not an infeasibility); `reason`
    /// says which. Corollary 1 is only sufficient, so this does not prove that no gain exists
    /// (try interval splitting).
    #[error(
        "LMI (41) has no verifiable strictly feasible point: {}; {reason}",
        margin.map_or_else(|| "no margin computed".to_string(), |m| format!("margin {m:.3e}"))
    )]
    Infeasible {
        /// Optimal common margin `t*` of the margin problem, when one was computed.
        margin: Option<f64>,
        /// The LMI layer's explanation.
        reason: String,
        /// The margin `t*` of the form solved is above the verification threshold, but the
        /// returned point does not pass the vertex test of (41): the limit of double precision,
        /// which is no evidence of infeasibility ([`Error::reason`] maps it to
        /// [`Reason::NumericalFailure`]).
        unverified: bool,
        /// The rounding level `τ` of LMI (41) at the solver's point against which the margin
        /// was tested, when one was computed: the refusal does not resolve margins below it.
        threshold: Option<f64>,
    },
    /// The solver could establish neither feasibility nor infeasibility of the LMI.
    #[error("LMI solve inconclusive: {reason}")]
    Inconclusive {
        /// The LMI layer's explanation.
        reason: String,
    },
    /// The LMI returned a certificate, but the independent grid check of (12) or of the Schur
    /// property of `e^{Av}(I − LM)` failed (the design is not returned as valid).
    #[error(
        "a-posteriori verification failed: max lambda_max of (12) relative to P \
         (||R e^(Av)(I-LM) R^-1||^2 - 1, P = R'R) = {relative_max_eigenvalue:.3e} at v = {}, \
         required below -{resolution:.1e}; max spectral radius of e^(Av)(I-LM) = \
         {max_spectral_radius:.3e} at v = {}",
        significant(*at),
        significant(*radius_at)
    )]
    VerificationFailed {
        /// [`crate::Verification::relative_max_eigenvalue`] of the grid check.
        relative_max_eigenvalue: f64,
        /// `tolerance + rounding`: the contraction (12) must show.
        resolution: f64,
        /// Largest eigenvalue of (12)'s left-hand side on the grid.
        max_eigenvalue: f64,
        /// Where.
        at: f64,
        /// Largest spectral radius of `e^{Av}(I − LM)` on the grid.
        max_spectral_radius: f64,
        /// Where.
        radius_at: f64,
        /// The inter-sample time where the failing test fails: `at` when (12) fails, else
        /// `radius_at`.
        tau: f64,
    },
    /// LMI (41) holds, verified at every vertex by more than rounding, for the plant in the
    /// coordinates of its own certificate (computed as `R A R⁻¹`; module `certificate`), but
    /// the certificate mapped back to the plant's coordinates is too ill-conditioned for the
    /// grid check of (12) there to decide it (its contraction in the norm of `P` is within
    /// the check's resolution, [`crate::Verification::rounding`]): the window is at the
    /// precision limit of the method, not shown infeasible.
    #[error(
        "double-precision limit: LMI (41) holds in the coordinates of its own certificate \
         (margin {margin:.3e} there), but that certificate P has condition number {} in the \
         plant's coordinates, where the grid check of (12) cannot decide it: the largest eigenvalue of (12) relative to P, ||R e^(Av)(I-LM) R^-1||^2 - 1 with \
         P = R'R, is {relative_max_eigenvalue:.3e}, within its rounding allowance \
         {rounding:.1e} of zero, where the check asks for less than -{resolution:.1e} (its \
         tolerance {tolerance:.0e} plus that allowance); max spectral radius of e^(Av)(I-LM) = \
         {max_spectral_radius:.4}, below one",
        condition_words(*.condition)
    )]
    PrecisionLimit {
        /// Margin of the reduced LMI (41) in certificate coordinates.
        margin: f64,
        /// `λmax(P)/λmin(P)` of the certificate in the plant's coordinates.
        condition: f64,
        /// [`crate::Verification::relative_max_eigenvalue`] of the grid check.
        relative_max_eigenvalue: f64,
        /// [`crate::Verification::rounding`] of the grid check.
        rounding: f64,
        /// The grid check's relative tolerance.
        tolerance: f64,
        /// `tolerance + rounding`: the contraction (12) must show.
        resolution: f64,
        /// Largest spectral radius of `e^{Av}(I − LM)` on the grid.
        max_spectral_radius: f64,
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
    /// An error from the polytopic embedding of `e^{Av}`.
    #[error("embedding: {0}")]
    Embed(#[from] sporadic_embed::EmbedError),
    /// An error from the LMI modelling layer or the SDP solver.
    #[error("LMI model: {0}")]
    Lmi(#[from] sporadic_sdp::lmi::ModelError),
    /// An error from the hybrid simulator or the figure writer.
    #[error("simulation: {0}")]
    Sim(#[from] sporadic_sim::SimError),
}

/// A condition number for a message: `1.2e17`, or words when it is not finite (`P` rounded to
/// doubles is not positive definite).
fn condition_words(condition: f64) -> String {
    if condition.is_finite() {
        format!("{condition:.1e}")
    } else {
        "beyond double precision (rounded to doubles it is not positive definite)".into()
    }
}

impl Error {
    /// The verdict on the plant (and window) this error is, as a typed [`Reason`] keeping the
    /// message: `None` for bad input and for failures that are not verdicts (I/O, simulation,
    /// an internal error of the LMI model).
    ///
    /// | error | reason |
    /// | --- | --- |
    /// | [`Error::NotDetectable`] at `v` | [`Reason::Undetectable`] with `tau = v` |
    /// | [`Error::Infeasible`] with `unverified` | [`Reason::NumericalFailure`] |
    /// | [`Error::Infeasible`] otherwise | [`Reason::InfeasibleLmi`] |
    /// | [`Error::Inconclusive`] | [`Reason::SolverInconclusive`] |
    /// | [`Error::VerificationFailed`] | [`Reason::VerificationFailed`] with its `tau` |
    /// | [`Error::ConditionViolated`] | [`Reason::VerificationFailed`] without `tau` |
    /// | [`Error::Singular`] (`F` of the certificate) | [`Reason::NumericalFailure`] |
    /// | [`Error::PrecisionLimit`] | [`Reason::NumericalFailure`] |
    /// | too many vertices, unreachable Taylor tolerance | [`Reason::BudgetExhausted`] |
    /// | a kernel's overflow, non-convergence, singularity, non-finite data | [`Reason::NumericalFailure`] |
    pub fn reason(&self) -> Option<Reason> {
        let message = self.to_string();
        Some(match self {
            Error::NotDetectable { v, .. } => Reason::Undetectable { tau: *v, message },
            Error::Infeasible {
                unverified: true, ..
            } => Reason::NumericalFailure { message },
            Error::Infeasible { .. } => Reason::InfeasibleLmi { message },
            Error::Inconclusive { .. } => Reason::SolverInconclusive { message },
            Error::VerificationFailed { tau, .. } => Reason::VerificationFailed {
                tau: Some(*tau),
                message,
            },
            Error::ConditionViolated { .. } => Reason::VerificationFailed { tau: None, message },
            Error::Singular { .. } | Error::PrecisionLimit { .. } => {
                Reason::NumericalFailure { message }
            }
            Error::Embed(EmbedError::TooManyVertices { .. })
            | Error::Embed(EmbedError::ToleranceUnreachable { .. }) => {
                Reason::BudgetExhausted { message }
            }
            Error::Embed(EmbedError::Numerical(_)) => Reason::NumericalFailure { message },
            Error::Linalg(e) | Error::Embed(EmbedError::Linalg(e))
                if !matches!(e, LinalgError::Input(_) | LinalgError::InvalidArgument(_)) =>
            {
                Reason::NumericalFailure { message }
            }
            Error::Lmi(
                ModelError::NonFinite { .. } | ModelError::Solver(SdpError::NonFinite { .. }),
            ) => Reason::NumericalFailure { message },
            Error::Lmi(ModelError::Linalg(e))
                if !matches!(e, LinalgError::Input(_) | LinalgError::InvalidArgument(_)) =>
            {
                Reason::NumericalFailure { message }
            }
            _ => return None,
        })
    }

    /// Whether the error is bad input (dimensions, NaN, a parameter out of range, bad options),
    /// as opposed to a verdict ([`Error::reason`]) or a failure that is neither.
    pub fn is_input(&self) -> bool {
        let linalg =
            |e: &LinalgError| matches!(e, LinalgError::Input(_) | LinalgError::InvalidArgument(_));
        match self {
            Error::Input(_) => true,
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
            _ => false,
        }
    }
}

/// What an unobservable mode of modulus `modulus` means for (12): impossible when it does not
/// decay, too slow to certify when it decays within the tolerance of the unit circle.
fn consequence(modulus: f64) -> String {
    if modulus >= 1.0 {
        "condition (12) cannot hold (Remark 3)".to_string()
    } else {
        format!(
            "the mode decays, but by a factor 1 − |mu| = {:.3e} per sample, within the tolerance \
             that counts it as non-decaying: a certificate of (12) would rest on a decrease that \
             small, which the design does not attempt to verify in double precision",
            1.0 - modulus
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An unobservable mode on the unit circle makes (12) impossible; one that decays within the
    /// tolerance (an unmeasured reservoir with a time constant of 10⁷ s sampled every ms) only
    /// too slowly to certify.
    #[test]
    fn an_undetectable_mode_is_impossible_only_when_it_does_not_decay() {
        let at = |modulus: f64| {
            Error::NotDetectable {
                v: 0.001,
                mu_re: modulus,
                mu_im: 0.0,
                modulus,
                margin: 0.0,
            }
            .to_string()
        };
        assert!(at(1.0).ends_with("condition (12) cannot hold (Remark 3)"));
        let slow = at(1.0 - 1e-10);
        assert!(!slow.contains("cannot hold"), "{slow}");
        assert!(slow.contains("1 − |mu| = 1.000e-10"), "{slow}");
    }
}
