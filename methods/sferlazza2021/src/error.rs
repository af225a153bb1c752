//! Typed errors of the round-robin observer crate.

use sporadic_linalg::{InputError, LinalgError};
use sporadic_sdp::lmi::ModelError;
use sporadic_sim::SimError;

/// Everything that can go wrong in this crate. Bad input is reported, never a panic.
///
/// Sensor indices `sigma` in the messages are **1-based**, as in the paper (`σ ∈ {1, …, N}`); the
/// Rust API itself indexes sensors from 0.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A dense linear-algebra kernel failed.
    #[error("linear algebra: {0}")]
    Linalg(#[from] LinalgError),
    /// The LMI modelling layer or the SDP solver failed.
    #[error("LMI/SDP: {0}")]
    Lmi(#[from] ModelError),
    /// The hybrid simulator (or its figure output) failed.
    #[error("simulation: {0}")]
    Sim(#[from] SimError),
    /// An interval helper of `sporadic-embed` rejected a window.
    #[error("window: {0}")]
    Interval(#[from] sporadic_embed::EmbedError),
    /// A rigorous interval kernel of `sporadic-interval` failed (the proof of [`crate::prove`]).
    #[error("interval arithmetic: {0}")]
    Enclosure(#[from] sporadic_interval::IntervalError),
    /// Writing a figure or a report failed.
    #[error("I/O: {0}")]
    Io(#[from] std::io::Error),
    /// Bad input: what was wrong and where (a matrix not square or empty, mismatched
    /// dimensions, NaN/Inf, a parameter out of range, an invalid sampling window).
    #[error(transparent)]
    Input(#[from] InputError),
    /// A sensor index (0-based, as in the Rust API) beyond the plant's `N` sensors.
    #[error("no sensor with index {index} (0-based): the plant has {sensors} sensors")]
    NoSuchSensor {
        /// The index asked for (0-based).
        index: usize,
        /// The number of sensors `N`.
        sensors: usize,
    },
    /// Any other invalid argument.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// A numerical kernel failed on valid input (an eigenvalue or singular value iteration that did
    /// not converge).
    #[error("numerical failure: {0}")]
    Numerical(String),
    /// Assumption 1 fails: `C_σ` is not of full row rank.
    #[error(
        "sensor {sigma}: C_σ has rank {rank} but {rows} rows (Assumption 1 needs full row rank)"
    )]
    RankDeficientOutput {
        /// Sensor (1-based).
        sigma: usize,
        /// Numerical rank of `C_σ`.
        rank: usize,
        /// Number of rows of `C_σ`.
        rows: usize,
    },
    /// A supplied complement `C_σ^⊥` is not a basis of `ker C_σ`.
    #[error("sensor {sigma}: the given C_σ^⊥ is not a basis of ker C_σ ({reason})")]
    InvalidComplement {
        /// Sensor (1-based).
        sigma: usize,
        /// What was checked.
        reason: String,
    },
    /// The necessary condition of Proposition 1 fails: `(C, e^{AT})` is not detectable.
    #[error(
        "not detectable (Prop. 1): at intervals T = {} the eigenvalue {} of e^(AT) (modulus \
         {}) has PBH margin {sigma_min:.3e} (σ_min of the block-normalised [λI − e^(AT); C]), \
         at or below the rank tolerance {rank_tol:e}{}",
        sig4_list(intervals),
        sig4_complex(*eig_re, *eig_im),
        sig4(*modulus),
        slow_decay(*modulus)
    )]
    NotDetectable {
        /// The inter-sample intervals `(T_1, …, T_N)` of the failing tuple.
        intervals: Vec<f64>,
        /// Real part of the undetectable eigenvalue of `e^{AT}`.
        eig_re: f64,
        /// Imaginary part of the undetectable eigenvalue of `e^{AT}`.
        eig_im: f64,
        /// Its modulus (≥ 1 up to the tolerance).
        modulus: f64,
        /// PBH margin: smallest singular value of `[(λI − e^{AT})/|λ|; C/‖C‖_F]`
        /// ([`sporadic_linalg::pbh_detectability`]).
        sigma_min: f64,
        /// The rank tolerance the margin was decided with
        /// ([`sporadic_linalg::PbhOptions::rank_tol`]).
        rank_tol: f64,
    },
    /// An LMI problem has no (strictly) feasible point.
    #[error("LMI infeasible: {what}")]
    Infeasible {
        /// Which problem.
        what: String,
    },
    /// The SDP solver stopped without an optimal or infeasible verdict.
    #[error("SDP solver stopped with status {status} while solving {what}")]
    SolverFailed {
        /// Which problem.
        what: String,
        /// The solver's status and the LMI layer's reason.
        status: String,
    },
    /// A design returned by the SDP failed its independent a-posteriori check (e.g. `ρ(J_1) ≥ 1` or
    /// `λ_min(Ξ_σ(T_σ)) ≤ 0` with freshly computed exponentials).
    #[error("a-posteriori verification failed: {what} = {value:.3e}")]
    VerificationFailed {
        /// The quantity checked.
        what: String,
        /// Its value.
        value: f64,
    },
    /// The §5.3 loop hit `max_iterations` without passing validation.
    #[error("design loop did not pass validation within {iterations} iterations")]
    NotConverged {
        /// Iterations performed.
        iterations: usize,
    },
    /// The worst point found by validation is already in the synthesis set: the SDP accuracy is too
    /// coarse compared with the margin μ.
    #[error(
        "sensor {sigma}: worst τ = {} is already in the synthesis set (λ_min = {lambda:.3e} ≤ μ = {}); \
         the SDP tolerance is too loose for this μ",
        sig4(*tau),
        sig4(*mu)
    )]
    Stalled {
        /// Sensor (1-based).
        sigma: usize,
        /// The repeated point.
        tau: f64,
        /// The minimum eigenvalue found there.
        lambda: f64,
        /// The margin.
        mu: f64,
    },
    /// The time budget of the enclosing [`sporadic_sdp::budget`] scope ran out.
    #[error("the time budget ran out during {during}")]
    Interrupted {
        /// What was running.
        during: &'static str,
    },
    /// The validation grid would exceed the configured cap (and no proof of (48) over the
    /// window decided in its place).
    #[error(
        "sensor {sigma}: validation grid needs {}, above the cap {cap:.3e}{proof}",
        grid_points(*points)
    )]
    GridTooLarge {
        /// Sensor (1-based).
        sigma: usize,
        /// Points needed.
        points: f64,
        /// Configured cap.
        cap: f64,
        /// How the proof of (48) tried in place of the grid ended, as a clause of the message
        /// starting with "; " (empty when none was tried).
        proof: String,
        /// Whether that proof stopped where its interval evaluation no longer resolves (48)
        /// ([`sporadic_model::ProofStop::Resolution`]): neither more time nor more pieces would
        /// decide the window in double precision, so the verdict is a numerical failure rather
        /// than an exhausted budget.
        unresolved: bool,
    },
}

/// The points a validation grid needs, in words (`∞` when the spacing (49) underflows).
fn grid_points(points: f64) -> String {
    if points.is_finite() {
        format!("{points:.3e} points")
    } else {
        "infinitely many points (its spacing (49) underflows to 0)".into()
    }
}

/// `x` must be a positive finite number (the error names the field `name`).
pub(crate) fn check_positive(name: &str, x: f64) -> Result<(), InputError> {
    if x > 0.0 && x.is_finite() {
        Ok(())
    } else {
        Err(InputError::parameter(
            name,
            x,
            "must be a positive finite number",
        ))
    }
}

/// `k` must be at least `min` (the error names the field `name`).
pub(crate) fn check_at_least(name: &str, k: usize, min: usize) -> Result<(), InputError> {
    if k >= min {
        Ok(())
    } else {
        Err(InputError::parameter(
            name,
            k as f64,
            format!("must be at least {min}"),
        ))
    }
}

pub(crate) use sporadic_model::sig4;

/// `re ± |im|i` with [`sig4`] (`re` alone when `im` is 0).
pub(crate) fn sig4_complex(re: f64, im: f64) -> String {
    if im == 0.0 {
        sig4(re)
    } else {
        let sign = if im < 0.0 { '−' } else { '+' };
        format!("{}{sign}{}i", sig4(re), sig4(im.abs()))
    }
}

/// A list of numbers for messages, `[a, b, …]` with [`sig4`].
pub(crate) fn sig4_list(xs: &[f64]) -> String {
    let items: Vec<String> = xs.iter().map(|&x| sig4(x)).collect();
    format!("[{}]", items.join(", "))
}

impl Error {
    pub(crate) fn invalid(msg: impl Into<String>) -> Self {
        Self::InvalidArgument(msg.into())
    }

    pub(crate) fn numerical(msg: impl Into<String>) -> Self {
        Self::Numerical(msg.into())
    }
}

/// For an undetectable eigenvalue inside the unit circle (counted as non-decaying by the
/// tolerance): that its mode decays, too slowly to certify, rather than not at all.
fn slow_decay(modulus: f64) -> String {
    if modulus >= 1.0 {
        String::new()
    } else {
        format!(
            "; the mode decays, but by a factor 1 − |λ| = {:.3e} per round, within the tolerance \
             that counts it as non-decaying, too slowly to certify",
            1.0 - modulus
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Messages print floats with 4 significant digits, never a 17-digit float or a Debug form.
    #[test]
    fn messages_have_four_significant_digits() {
        assert_eq!(sig4(0.1 + 0.2), "0.3");
        assert_eq!(sig4(std::f64::consts::PI), "3.142");
        assert_eq!(sig4(1.0 / 3.0e7), "3.333e-8");
        assert_eq!(sig4(-2.5e12), "-2.5e12");
        assert_eq!(sig4(169_502.3), "1.695e5");
        assert_eq!(sig4(9999.4), "9999");
        assert_eq!(sig4(0.000_123_46), "1.235e-4");
        assert_eq!(sig4_list(&[0.1 + 0.2, 1.0 / 3.0]), "[0.3, 0.3333]");
        assert_eq!(sig4_complex(0.999_999_9, -0.123_456), "1−0.1235i");
        let e = Error::NotDetectable {
            intervals: vec![std::f64::consts::FRAC_PI_3, 0.1 + 0.2],
            eig_re: -0.999_999_7,
            eig_im: 1.0 / 3.0e-3,
            modulus: 1.000_000_1,
            sigma_min: 1.234_567e-12,
            rank_tol: 1e-8,
        };
        assert_eq!(
            e.to_string(),
            "not detectable (Prop. 1): at intervals T = [1.047, 0.3] the eigenvalue -1+333.3i of \
             e^(AT) (modulus 1) has PBH margin 1.235e-12 (σ_min of the block-normalised \
             [λI − e^(AT); C]), at or below the rank tolerance 1e-8"
        );
        // A mode inside the unit circle, counted as non-decaying by the tolerance.
        let slow = Error::NotDetectable {
            intervals: vec![0.001],
            eig_re: 1.0 - 1e-10,
            eig_im: 0.0,
            modulus: 1.0 - 1e-10,
            sigma_min: 0.0,
            rank_tol: 1e-8,
        };
        assert!(
            slow.to_string().ends_with(
                "1 − |λ| = 1.000e-10 per round, within the tolerance that counts it as \
                            non-decaying, too slowly to certify"
            ),
            "{slow}"
        );
        let e = Error::Stalled {
            sigma: 2,
            tau: 0.1 + 0.2,
            lambda: 0.009_876_54,
            mu: 0.01,
        };
        assert_eq!(
            e.to_string(),
            "sensor 2: worst τ = 0.3 is already in the synthesis set (λ_min = 9.877e-3 ≤ μ = \
             0.01); the SDP tolerance is too loose for this μ"
        );
    }
}
