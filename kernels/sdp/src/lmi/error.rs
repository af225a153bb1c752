//! Typed errors of the LMI modelling layer.

use std::fmt;

use thiserror::Error;

use crate::error::SdpError;
use sporadic_linalg::{InputError, LinalgError};

/// The shape `rows × cols` of a matrix expression.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Shape {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
}

impl Shape {
    /// `rows × cols`.
    pub fn new(rows: usize, cols: usize) -> Self {
        Self { rows, cols }
    }
}

impl fmt::Display for Shape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}×{}", self.rows, self.cols)
    }
}

/// Everything that can go wrong while building, compiling, solving or verifying an LMI model.
///
/// Expression arithmetic never panics: an operation on incompatible operands yields an expression
/// that carries the error, and the error is reported by the first fallible call that uses it
/// ([`crate::lmi::Model::constrain`], [`crate::lmi::Model::minimize`], [`crate::lmi::Expr::check`], …).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    /// Two operands of an operation have incompatible shapes.
    #[error("dimension mismatch in {op}: {left} is {left_shape} but {right} is {right_shape}")]
    DimensionMismatch {
        /// The operation (`"+"`, `"matrix product"`, `"block row 2"`, …).
        op: String,
        /// Description of the left/first operand.
        left: String,
        /// Its shape.
        left_shape: Shape,
        /// Description of the right/second operand.
        right: String,
        /// Its shape.
        right_shape: Shape,
    },
    /// A square matrix was required.
    #[error("{what} must be square, got {shape}")]
    NotSquare {
        /// What was required to be square.
        what: String,
        /// Its shape.
        shape: Shape,
    },
    /// A matrix inequality was posed on an expression that is not symmetric.
    #[error(
        "constraint `{constraint}` is not symmetric: {part} differs from its transpose by \
         {asymmetry:.3e} at entry ({row},{col}) (largest entry magnitude {scale:.3e})"
    )]
    NonSymmetric {
        /// Name of the constraint.
        constraint: String,
        /// Which part of the expression (`"the constant term"` or the coefficient of a scalar).
        part: String,
        /// Row of the largest asymmetry.
        row: usize,
        /// Column of the largest asymmetry.
        col: usize,
        /// `|F_ij − F_ji|`.
        asymmetry: f64,
        /// Largest magnitude in that part (the asymmetry is judged relative to it).
        scale: f64,
    },
    /// Bad input data, checked by the workspace's shared validation (`sporadic_linalg::input`):
    /// e.g. NaN or ±∞ in the value of a parameter.
    #[error(transparent)]
    Input(#[from] InputError),
    /// NaN or ±∞ in an expression's data (or produced by overflow while combining data).
    #[error("non-finite value {value} in {what}")]
    NonFinite {
        /// Where the value was found.
        what: String,
        /// The value.
        value: f64,
    },
    /// A variable, parameter or expression of another [`crate::lmi::Model`] was used.
    #[error("{what} belongs to a different model")]
    ForeignModel {
        /// What was foreign.
        what: String,
    },
    /// A product of two expressions that both contain decision variables (not affine).
    #[error("{op}: both operands contain decision variables; the result would not be affine")]
    NotAffine {
        /// The operation.
        op: String,
    },
    /// A constraint with zero rows or columns, or an index range outside an expression.
    #[error("{what}")]
    Empty {
        /// What was empty / out of range.
        what: String,
    },
    /// The model has no constraints.
    #[error("the model has no constraints")]
    NoConstraints,
    /// The equality constraints have no common solution.
    #[error(
        "equality constraints are inconsistent: after elimination a row of `{constraint}` \
         reduces to 0 = {residual:.3e}"
    )]
    InconsistentEqualities {
        /// A constraint contributing the inconsistent row.
        constraint: String,
        /// The non-zero right-hand side left over.
        residual: f64,
    },
    /// The objective depends on a scalar that no constraint restricts.
    #[error("objective is unbounded: it depends on `{scalar}`, which no constraint restricts")]
    Unbounded {
        /// Name of the unrestricted scalar (e.g. `P[0,1]`).
        scalar: String,
    },
    /// The objective must be a 1×1 expression.
    #[error("the objective must be a scalar (1×1) expression, got {shape}")]
    ObjectiveNotScalar {
        /// Its shape.
        shape: Shape,
    },
    /// A scalar value was asked of a variable or expression that is not 1×1
    /// ([`crate::lmi::LmiSolution::scalar`]).
    #[error("{what} is not a scalar: it has shape {shape}, expected 1×1")]
    NotScalar {
        /// The variable or expression.
        what: String,
        /// Its shape.
        shape: Shape,
    },
    /// A variable created after [`crate::lmi::Model::compile`] was used in the compiled model.
    #[error("{what} was created after the model was compiled")]
    UnknownVariable {
        /// The offending variable.
        what: String,
    },
    /// A new parameter value has the wrong shape.
    #[error("parameter `{param}` has shape {expected}, got a value of shape {found}")]
    ParamShape {
        /// Parameter name.
        param: String,
        /// Declared shape.
        expected: Shape,
        /// Shape of the new value.
        found: Shape,
    },
    /// Any other invalid argument (non-positive bound, margin cap, …).
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// The SDP solver rejected the compiled problem.
    #[error("SDP solver: {0}")]
    Solver(#[from] SdpError),
    /// A dense linear-algebra kernel failed during verification.
    #[error("linear algebra: {0}")]
    Linalg(#[from] LinalgError),
}
