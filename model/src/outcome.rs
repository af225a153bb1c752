//! Outcomes of a method: certified, not certified (with a typed reason), not applicable (with
//! a typed reason). Bad input is not an outcome: it is an `Err` ([`crate::MethodError`]).

use serde::{Deserialize, Serialize};

/// What a method established for a plant and a sampling window, in the style of Clarabel's
/// `SolverStatus`. Serialised as the strings `certified`, `not_certified`, `not_applicable`;
/// the reason of the last two is a separate [`Reason`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// A design whose certificate was re-verified in floating point.
    Certified,
    /// The method applies but produced no certified design.
    NotCertified,
    /// The method does not cover this plant or sampling.
    NotApplicable,
}

impl Status {
    /// `Certified`.
    pub fn is_certified(self) -> bool {
        self == Status::Certified
    }
    /// `NotCertified`.
    pub fn is_not_certified(self) -> bool {
        self == Status::NotCertified
    }
    /// `NotApplicable`.
    pub fn is_not_applicable(self) -> bool {
        self == Status::NotApplicable
    }
    /// The string used in reports: `certified`, `not_certified`, `not_applicable`.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Certified => "certified",
            Status::NotCertified => "not_certified",
            Status::NotApplicable => "not_applicable",
        }
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.as_str())
    }
}

/// Why a method produced no certified design, or does not apply. Serialised as an object with
/// a `kind` (snake case of the variant), the variant's fields, and a human `message`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum Reason {
    // ---- not certified ----
    /// The design LMIs/BMIs have no (strictly) feasible point that can be verified: a solver
    /// infeasibility certificate, a maximal margin at or below the verification threshold
    /// (then no point satisfies them by more than the threshold; a strictly feasible point with
    /// a smaller margin is not excluded), or a necessary condition of the design inequalities
    /// that fails without a solve; the message says which.
    InfeasibleLmi {
        /// The method's explanation (which constraint, which certificate).
        message: String,
    },
    /// A necessary condition fails at a sampling interval in the window: the sampled pair
    /// `(e^{Aτ}, C)` is not detectable at `τ` (e.g. an aliasing interval of an oscillator).
    Undetectable {
        /// A sampling interval where detectability fails.
        tau: f64,
        /// The method's explanation.
        message: String,
    },
    /// The solver returned a candidate, but the independent floating-point re-verification of
    /// the method's condition failed.
    VerificationFailed {
        /// Where it failed (a sampling interval), if the check is pointwise.
        tau: Option<f64>,
        /// The method's explanation (the failing value and its threshold).
        message: String,
    },
    /// The solver could establish neither feasibility nor infeasibility.
    SolverInconclusive {
        /// The method's explanation (solver status, accuracy reached).
        message: String,
    },
    /// An iterative loop (refinement, alternation, search) ran out of its budget.
    BudgetExhausted {
        /// Which budget (iterations, probes, time) and how much of it was used.
        message: String,
    },
    /// A numerical kernel failed on this plant (e.g. overflow of `e^{Aτ}`).
    NumericalFailure {
        /// The error, with its chain of causes.
        message: String,
    },
    // ---- not applicable ----
    /// The method needs data the plant description lacks (e.g. a `[lipschitz]` or
    /// `[bounds]` section).
    MissingData {
        /// What is missing and why the method needs it.
        message: String,
    },
    /// The plant or sampling has a structure the method does not cover (e.g. a nonlinearity
    /// for a linear-plant method, round-robin sensors for a single-rate method).
    UnsupportedStructure {
        /// What is not covered.
        message: String,
    },
}

impl Reason {
    /// The status this reason belongs to (`NotCertified` or `NotApplicable`).
    pub fn status(&self) -> Status {
        match self {
            Reason::MissingData { .. } | Reason::UnsupportedStructure { .. } => {
                Status::NotApplicable
            }
            _ => Status::NotCertified,
        }
    }

    /// The human explanation.
    pub fn message(&self) -> &str {
        match self {
            Reason::InfeasibleLmi { message }
            | Reason::Undetectable { message, .. }
            | Reason::VerificationFailed { message, .. }
            | Reason::SolverInconclusive { message }
            | Reason::BudgetExhausted { message }
            | Reason::NumericalFailure { message }
            | Reason::MissingData { message }
            | Reason::UnsupportedStructure { message } => message,
        }
    }

    /// The `kind` string of the serialised reason.
    pub fn kind(&self) -> &'static str {
        match self {
            Reason::InfeasibleLmi { .. } => "infeasible_lmi",
            Reason::Undetectable { .. } => "undetectable",
            Reason::VerificationFailed { .. } => "verification_failed",
            Reason::SolverInconclusive { .. } => "solver_inconclusive",
            Reason::BudgetExhausted { .. } => "budget_exhausted",
            Reason::NumericalFailure { .. } => "numerical_failure",
            Reason::MissingData { .. } => "missing_data",
            Reason::UnsupportedStructure { .. } => "unsupported_structure",
        }
    }
}

impl std::fmt::Display for Reason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({})", self.message(), self.kind())
    }
}

/// A method does not apply to a plant: returned by [`crate::ObserverMethod::applies`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{method} does not apply: {reason}")]
pub struct NotApplicable {
    /// The method id.
    pub method: &'static str,
    /// Why ([`Reason::MissingData`] or [`Reason::UnsupportedStructure`]).
    pub reason: Reason,
}

impl NotApplicable {
    /// Missing data.
    pub fn missing(method: &'static str, message: impl Into<String>) -> Self {
        Self {
            method,
            reason: Reason::MissingData {
                message: message.into(),
            },
        }
    }
    /// Unsupported structure.
    pub fn unsupported(method: &'static str, message: impl Into<String>) -> Self {
        Self {
            method,
            reason: Reason::UnsupportedStructure {
                message: message.into(),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reasons_serialise_with_their_kind() {
        let r = Reason::Undetectable {
            tau: 0.314,
            message: "not detectable".into(),
        };
        let v = serde_json::to_value(&r).unwrap();
        assert_eq!(v["kind"], "undetectable");
        assert_eq!(v["tau"], 0.314);
        assert_eq!(r.kind(), "undetectable");
        assert_eq!(serde_json::from_value::<Reason>(v).unwrap(), r);
        assert_eq!(r.status(), Status::NotCertified);
        let na = NotApplicable::missing("x", "needs bounds");
        assert_eq!(na.reason.status(), Status::NotApplicable);
        assert_eq!(
            serde_json::to_value(Status::NotApplicable).unwrap(),
            "not_applicable"
        );
    }
}
