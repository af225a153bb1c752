//! Input validation at the public entry points of this crate, on the shared checks of
//! [`crate::input`].

use faer::MatRef;

use crate::input::{InputError, check_square};

pub(crate) use crate::input::{check_finite as finite, check_square_finite as square_finite};

/// Checks that `a` is square and non-empty; returns its order.
pub(crate) fn square(a: MatRef<'_, f64>) -> Result<usize, InputError> {
    check_square(a, "matrix")
}

/// Checks that a scalar is finite.
pub(crate) fn finite_scalar(x: f64, what: &str) -> Result<(), InputError> {
    if x.is_finite() {
        Ok(())
    } else {
        Err(InputError::non_finite(what))
    }
}
