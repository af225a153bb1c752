//! The matrices of the stability and synthesis conditions evaluated at given numbers (no
//! optimisation): Theorem 2 (16c), Corollary 1 (19b)–(19c), Theorem 3 (20a)–(20d), the
//! interpolations used in the proof of Theorem 3, and the gain recovery of Remark 6.
//!
//! The LMI model ([`crate::lmi`]) builds the same matrices symbolically; these plain-matrix
//! versions serve the independent verification ([`crate::verify`]) and the tests of the algebra
//! of the proof of Theorem 3 (`P(τ)` affine in `τ`, the flow block affine in `τ` between `M¹_p`
//! and `M²_p`, the jump block `B(τ)` affine between (20c) and (20d)).
//!
//! The OCR of (16c), (19c) and of the block `B(τ)` of the Theorem 3 proof is garbled; the forms
//! below are the only ones consistent with the stated Schur complement and with (20c)/(20d):
//!
//! ```text
//! (16c)/(19c)  J(P⁻, P⁺, L) = [ He(L C) + P⁻ − P⁺    C'L' ]  ≻ 0
//!                             [ L C                   P⁺   ]
//!              ⇔  P⁻ − (I − K C)' P⁺ (I − K C) ≻ 0,   K = (P⁺)⁻¹ L,
//! ```
//!
//! with `P⁻ = P(τ)` just before the jump and `P⁺ = P(0) = P1` just after it.

use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::he;
use sporadic_linalg::input::{check_finite, check_shape};

use crate::error::Error;
use sporadic_model::SamplingWindow;

/// Checks that `x` is `n×n` and finite.
fn check_square(x: MatRef<'_, f64>, n: usize, what: &str) -> Result<(), Error> {
    check_shape(x, n, n, what)?;
    Ok(check_finite(x, what)?)
}

/// Checks `τ̄ > 0` and `τ` finite.
fn check_times(tau_bar: f64, tau: f64) -> Result<(), Error> {
    if !(tau_bar.is_finite() && tau_bar > 0.0) {
        return Err(InputError::parameter("tau_bar", tau_bar, "τ̄ must be finite and > 0").into());
    }
    if !tau.is_finite() {
        return Err(InputError::non_finite("τ").into());
    }
    Ok(())
}

/// Checks that two Lyapunov matrices are `n×n` (`n` from the first, ≥ 1) and finite; returns
/// `n`.
fn check_pair(
    p: MatRef<'_, f64>,
    other: MatRef<'_, f64>,
    names: (&'static str, &'static str),
) -> Result<usize, Error> {
    let n = p.nrows();
    if n == 0 {
        return Err(InputError::empty(names.0).into());
    }
    check_square(p, n, names.0)?;
    check_square(other, n, names.1)?;
    Ok(n)
}

/// `(1 − s) X0 + s X1` (shapes already checked).
fn affine(x0: MatRef<'_, f64>, x1: MatRef<'_, f64>, s: f64) -> Mat<f64> {
    x0 * (1.0 - s) + x1 * s
}

/// The Lyapunov matrix of Theorem 3, `P(τ) = (1 − τ/τ̄) P1 + (τ/τ̄) P2` (so `P(0) = P1`,
/// `P(τ̄) = P2`, `dP/dτ = (P2 − P1)/τ̄`).
pub fn lyapunov_matrix(
    p1: MatRef<'_, f64>,
    p2: MatRef<'_, f64>,
    tau_bar: f64,
    tau: f64,
) -> Result<Mat<f64>, Error> {
    check_pair(p1, p2, ("P1", "P2"))?;
    check_times(tau_bar, tau)?;
    Ok(affine(p1, p2, tau / tau_bar))
}

/// `M¹_p = He(P1 R_p) + (P2 − P1)/τ̄` and `M²_p = He(P2 R_p) + (P2 − P1)/τ̄`, (20a)–(20b).
pub fn flow_vertex_blocks(
    p1: MatRef<'_, f64>,
    p2: MatRef<'_, f64>,
    r: MatRef<'_, f64>,
    tau_bar: f64,
) -> Result<(Mat<f64>, Mat<f64>), Error> {
    Ok((
        flow_block(p1, p2, r, tau_bar, 0.0)?,
        flow_block(p1, p2, r, tau_bar, tau_bar)?,
    ))
}

/// The flow condition (19b) / (16b) with `∂P/∂s = 0` for the Lyapunov matrix of Theorem 3:
/// `N_p(τ) = He(P(τ) R_p) + (P2 − P1)/τ̄` (`M¹_p` at `τ = 0`, `M²_p` at `τ = τ̄`).
pub fn flow_block(
    p1: MatRef<'_, f64>,
    p2: MatRef<'_, f64>,
    r: MatRef<'_, f64>,
    tau_bar: f64,
    tau: f64,
) -> Result<Mat<f64>, Error> {
    let p = lyapunov_matrix(p1, p2, tau_bar, tau)?;
    check_square(r, p.nrows(), "vertex R_p")?;
    Ok(he((&p * r).as_ref())? + (p2 - p1) * (1.0 / tau_bar))
}

/// The jump block `J(P⁻, P⁺, L) = [He(LC) + P⁻ − P⁺, C'L'; LC, P⁺]` of (16c)/(19c) (module
/// docs). Shapes: `P⁻, P⁺` n×n, `L` n×q, `C` q×n.
pub fn jump_block(
    p_before: MatRef<'_, f64>,
    p_after: MatRef<'_, f64>,
    l: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
) -> Result<Mat<f64>, Error> {
    let n = check_pair(
        p_after,
        p_before,
        ("P⁺ (after the jump)", "P⁻ (before the jump)"),
    )?;
    let lc = gain_times_output(l, c, n, "L")?;
    let top = he(lc.as_ref())? + p_before - p_after;
    Ok(Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => top[(i, j)],
        (true, false) => lc[(j - n, i)],
        (false, true) => lc[(i - n, j)],
        (false, false) => p_after[(i - n, j - n)],
    }))
}

/// `X C` for a gain-like `X` (n×q) and the output matrix `C` (q×n), both checked.
fn gain_times_output(
    x: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
    n: usize,
    what: &str,
) -> Result<Mat<f64>, Error> {
    if c.nrows() == 0 {
        return Err(InputError::empty("C (no measured output, q = 0)").into());
    }
    check_shape(c, c.nrows(), n, "C")?;
    check_shape(x, n, c.nrows(), what)?;
    check_finite(c, "C")?;
    check_finite(x, what)?;
    Ok(x * c)
}

/// The Schur form of the jump condition: `P⁻ − (I − KC)' P⁺ (I − KC)` (positive definite iff
/// [`jump_block`] is with `L = P⁺K`, given `P⁺ ≻ 0`).
pub fn jump_decrease(
    p_before: MatRef<'_, f64>,
    p_after: MatRef<'_, f64>,
    k: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
) -> Result<Mat<f64>, Error> {
    check_pair(
        p_after,
        p_before,
        ("P⁺ (after the jump)", "P⁻ (before the jump)"),
    )?;
    let reset = reset_matrix(k, c)?;
    Ok(p_before - reset.transpose() * p_after * &reset)
}

/// `I − K C`, the reset of the error at a sample (`K` n×q, `C` q×n).
pub fn reset_matrix(k: MatRef<'_, f64>, c: MatRef<'_, f64>) -> Result<Mat<f64>, Error> {
    let n = k.nrows();
    if n == 0 {
        return Err(InputError::empty("gain K (n = 0)").into());
    }
    Ok(Mat::<f64>::identity(n, n) - gain_times_output(k, c, n, "K")?)
}

/// `(20c)`: `J(P(τ_low), P1, L0)`, i.e. `[He(L0C) − (τ_low/τ̄)(P1 − P2), C'L0'; ⋆, P1]`.
pub fn jump_block_low(
    p1: MatRef<'_, f64>,
    p2: MatRef<'_, f64>,
    l0: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
    window: &SamplingWindow,
) -> Result<Mat<f64>, Error> {
    let p_low = lyapunov_matrix(p1, p2, window.t2(), window.t1())?;
    jump_block(p_low.as_ref(), p1, l0, c)
}

/// `(20d)`: `J(P2, P1, L1)`, i.e. `[He(L1C) − (P1 − P2), C'L1'; ⋆, P1]`.
pub fn jump_block_high(
    p1: MatRef<'_, f64>,
    p2: MatRef<'_, f64>,
    l1: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
) -> Result<Mat<f64>, Error> {
    jump_block(p2, p1, l1, c)
}

/// Linear interpolation on `[τ_low, τ̄]`:
/// `X(τ) = X0 + (τ − τ_low)/(τ̄ − τ_low) (X1 − X0)` (used for `L(τ)` in the proof of Theorem 3
/// and for `K(τ)` in Remark 6); `X0` when `τ_low = τ̄`.
pub fn interpolate(
    x0: MatRef<'_, f64>,
    x1: MatRef<'_, f64>,
    window: &SamplingWindow,
    tau: f64,
) -> Result<Mat<f64>, Error> {
    check_shape(x1, x0.nrows(), x0.ncols(), "X1 (vs X0)")?;
    check_finite(x0, "X0")?;
    check_finite(x1, "X1")?;
    if !tau.is_finite() {
        return Err(InputError::non_finite("τ").into());
    }
    Ok(interpolate_checked(x0, x1, window, tau))
}

/// [`interpolate`] for operands already known to agree in shape and be finite.
pub(crate) fn interpolate_checked(
    x0: MatRef<'_, f64>,
    x1: MatRef<'_, f64>,
    window: &SamplingWindow,
    tau: f64,
) -> Mat<f64> {
    let width = window.t2() - window.t1();
    if width <= 0.0 {
        return x0.to_owned();
    }
    affine(x0, x1, (tau - window.t1()) / width)
}

/// `K = P1⁻¹ L` by a Cholesky factorisation of `P1` (the gain recovery of Theorem 3,
/// Corollary 2 and Remark 6).
pub fn gain_from(p1: MatRef<'_, f64>, l: MatRef<'_, f64>) -> Result<Mat<f64>, Error> {
    let n = p1.nrows();
    if n == 0 {
        return Err(InputError::empty("P1 (n = 0)").into());
    }
    check_square(p1, n, "P1")?;
    check_shape(l, n, l.ncols(), "L")?;
    check_finite(l, "L")?;
    let llt = p1.llt(faer::Side::Lower).map_err(|_| Error::Singular {
        what: "P1 is not positive definite (K = P1⁻¹L)".into(),
    })?;
    let k = llt.solve(l);
    check_finite(k.as_ref(), "K = P1⁻¹L").map_err(|_| Error::Singular {
        what: "P1 (K = P1⁻¹L overflowed)".into(),
    })?;
    Ok(k)
}
