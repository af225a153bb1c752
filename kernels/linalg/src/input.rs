//! Validation of user input shared by every crate of the workspace.
//!
//! Each paper crate, the embedding and the simulator check the same things at their entry
//! points: matrices are square and non-empty, operands agree in size, data is finite, scalar
//! options lie in their admissible range, and sampling windows `[T1, T2]` are intervals of
//! `(0, ∞)`. [`InputError`] names the offending quantity and says what is wrong; each crate's
//! error type wraps it (`Error::Input`), so a caller sees the same message wherever the bad value
//! entered.

use faer::MatRef;

/// Bad input: what was wrong and where. Never a panic.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InputError {
    /// A matrix that must be square is not.
    #[error("{what} must be square, got {rows}×{cols}")]
    NotSquare {
        /// Which matrix.
        what: String,
        /// Number of rows.
        rows: usize,
        /// Number of columns.
        cols: usize,
    },
    /// An input that must hold at least one entry is empty.
    #[error("empty input: {what}")]
    Empty {
        /// Which input.
        what: String,
    },
    /// Two operands that must agree in size do not.
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
        /// Which quantity, with the offending entry when known.
        what: String,
    },
    /// A scalar option lies outside its admissible range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// Name of the parameter.
        name: String,
        /// The value supplied.
        value: f64,
        /// The condition it violates.
        reason: String,
    },
    /// A sampling window `[T1, T2]` is not an admissible interval of inter-sample times.
    #[error("invalid {what} [{lower}, {upper}]: {reason}")]
    InvalidWindow {
        /// Which window (`sampling window`, `sampling window of sensor 2`, …).
        what: String,
        /// Lower end (`T1`, `τ_min`, `τ_low`) as given.
        lower: f64,
        /// Upper end (`T2`, `τ_max`, `τ̄`) as given.
        upper: f64,
        /// Which condition is violated.
        reason: String,
    },
}

impl InputError {
    /// [`InputError::DimensionMismatch`].
    pub fn mismatch(what: impl Into<String>, expected: usize, found: usize) -> Self {
        Self::DimensionMismatch {
            what: what.into(),
            expected,
            found,
        }
    }

    /// [`InputError::NonFinite`].
    pub fn non_finite(what: impl Into<String>) -> Self {
        Self::NonFinite { what: what.into() }
    }

    /// [`InputError::Empty`].
    pub fn empty(what: impl Into<String>) -> Self {
        Self::Empty { what: what.into() }
    }

    /// [`InputError::InvalidParameter`].
    pub fn parameter(name: impl Into<String>, value: f64, reason: impl Into<String>) -> Self {
        Self::InvalidParameter {
            name: name.into(),
            value,
            reason: reason.into(),
        }
    }

    /// [`InputError::InvalidWindow`].
    pub fn window(
        what: impl Into<String>,
        lower: f64,
        upper: f64,
        reason: impl Into<String>,
    ) -> Self {
        Self::InvalidWindow {
            what: what.into(),
            lower,
            upper,
            reason: reason.into(),
        }
    }
}

/// Checks that every entry of `a` is finite; the error names the first offending entry.
pub fn check_finite(a: MatRef<'_, f64>, what: &str) -> Result<(), InputError> {
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            if !a[(i, j)].is_finite() {
                return Err(InputError::non_finite(format!("{what} at entry ({i},{j})")));
            }
        }
    }
    Ok(())
}

/// Checks that every entry of a vector is finite; the error names the first offending component.
pub fn check_finite_slice(x: &[f64], what: &str) -> Result<(), InputError> {
    match x.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(InputError::non_finite(format!("{what} at component {i}"))),
    }
}

/// Checks that `a` is square and non-empty; returns its order.
pub fn check_square(a: MatRef<'_, f64>, what: &str) -> Result<usize, InputError> {
    let (rows, cols) = (a.nrows(), a.ncols());
    if rows != cols {
        return Err(InputError::NotSquare {
            what: what.to_owned(),
            rows,
            cols,
        });
    }
    if rows == 0 {
        return Err(InputError::empty(what));
    }
    Ok(rows)
}

/// Checks that `a` is square, non-empty and finite; returns its order.
pub fn check_square_finite(a: MatRef<'_, f64>, what: &str) -> Result<usize, InputError> {
    let n = check_square(a, what)?;
    check_finite(a, what)?;
    Ok(n)
}

/// Checks that `a` is `rows × cols`.
pub fn check_shape(
    a: MatRef<'_, f64>,
    rows: usize,
    cols: usize,
    what: &str,
) -> Result<(), InputError> {
    check_dimension(&format!("rows of {what}"), rows, a.nrows())?;
    check_dimension(&format!("columns of {what}"), cols, a.ncols())
}

/// Checks that a size equals the one another operand requires.
pub fn check_dimension(what: &str, expected: usize, found: usize) -> Result<(), InputError> {
    if expected == found {
        Ok(())
    } else {
        Err(InputError::mismatch(what, expected, found))
    }
}

/// Checks that a vector has the length another operand requires.
pub fn check_len(x: &[f64], expected: usize, what: &str) -> Result<(), InputError> {
    check_dimension(what, expected, x.len())
}

/// Which lower end a sampling window admits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LowerEnd {
    /// `T1 > 0`: a positive minimal inter-sample time, which excludes Zeno behaviour.
    Positive,
    /// `T1 ≥ 0`: for objects that stay meaningful without a dwell time (the embedding of
    /// `τ ↦ e^{Aτ}`, conditions whose infeasibility at `T1 = 0` is itself informative).
    NonNegative,
}

/// Checks that `[lower, upper]` is a sampling window: both ends finite, `lower ≤ upper`, and the
/// lower end admissible as `lower_end` says. `what` names the window in the error.
pub fn check_window(
    what: &str,
    lower: f64,
    upper: f64,
    lower_end: LowerEnd,
) -> Result<(), InputError> {
    let bad = |reason: &str| Err(InputError::window(what, lower, upper, reason));
    if !(lower.is_finite() && upper.is_finite()) {
        return bad("both ends must be finite numbers");
    }
    match lower_end {
        LowerEnd::Positive if lower <= 0.0 => {
            return bad("the lower end must be positive (excludes Zeno behaviour)");
        }
        LowerEnd::NonNegative if lower < 0.0 => return bad("the lower end must be ≥ 0"),
        _ => {}
    }
    if lower > upper {
        return bad("the lower end must not exceed the upper end");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::{Mat, mat};

    #[test]
    fn finite_check_names_the_entry() {
        let a = mat![[1.0, 2.0], [f64::NAN, 0.0]];
        assert_eq!(
            check_finite(a.as_ref(), "A"),
            Err(InputError::non_finite("A at entry (1,0)"))
        );
        assert_eq!(
            check_finite_slice(&[0.0, f64::INFINITY], "x0"),
            Err(InputError::non_finite("x0 at component 1"))
        );
        assert_eq!(check_finite(a.submatrix(0, 0, 1, 2), "A"), Ok(()));
    }

    #[test]
    fn square_check_rejects_rectangular_and_empty() {
        let a = Mat::<f64>::zeros(2, 3);
        assert!(matches!(
            check_square(a.as_ref(), "A"),
            Err(InputError::NotSquare {
                rows: 2,
                cols: 3,
                ..
            })
        ));
        let e = Mat::<f64>::zeros(0, 0);
        assert_eq!(check_square(e.as_ref(), "A"), Err(InputError::empty("A")));
        assert_eq!(
            check_square(Mat::<f64>::identity(3, 3).as_ref(), "A"),
            Ok(3)
        );
        assert_eq!(check_dimension("rows of C", 2, 2), Ok(()));
        assert_eq!(
            check_shape(a.as_ref(), 2, 2, "C"),
            Err(InputError::mismatch("columns of C", 2, 3))
        );
        assert_eq!(check_shape(a.as_ref(), 2, 3, "C"), Ok(()));
        assert!(check_dimension("rows of C", 2, 3).is_err());
        assert_eq!(
            check_len(&[1.0, 2.0], 3, "x0"),
            Err(InputError::mismatch("x0", 3, 2))
        );
    }

    #[test]
    fn window_ends() {
        use LowerEnd::{NonNegative, Positive};
        assert!(check_window("w", 0.1, 0.5, Positive).is_ok());
        assert!(check_window("w", 0.5, 0.5, Positive).is_ok());
        assert!(check_window("w", 0.0, 0.5, Positive).is_err());
        assert!(check_window("w", 0.0, 0.5, NonNegative).is_ok());
        assert!(check_window("w", 0.0, 0.0, NonNegative).is_ok());
        assert!(check_window("w", -0.1, 0.5, NonNegative).is_err());
        assert!(check_window("w", 0.6, 0.5, Positive).is_err());
        assert!(check_window("w", f64::NAN, 0.5, Positive).is_err());
        assert!(check_window("w", 0.1, f64::INFINITY, Positive).is_err());
    }
}
