//! The matrices of the stability and synthesis conditions evaluated at given numbers (no
//! optimisation): Theorem 2 (16c), Corollary 1 (19b)–(19c), Theorem 3 (20a)–(20d), the
//! interpolations used in the proof of Theorem 3, and the gain recovery of Remark 6.
//!
//! The LMI model ([`crate::lmi`]) builds the same matrices symbolically; these plain-matrix
//! versions serve the independent verification ([`crate::verify`]) and the tests of the algebra
//! of the proof (spec §3.3 "why it works").
//!
//! The OCR of (16c), (19c) and of the block `B(τ)` of the Theorem 3 proof is garbled; the forms
//! below are the only ones consistent with the stated Schur complement and with (20c)/(20d)
//! (spec §6):
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

use crate::error::{Error, check_shape};
use crate::system::Window;

/// `He(X) = X + X'`.
fn he(x: MatRef<'_, f64>) -> Mat<f64> {
    x + x.transpose()
}

/// The Lyapunov matrix of Theorem 3, `P(τ) = (1 − τ/τ̄) P1 + (τ/τ̄) P2` (so `P(0) = P1`,
/// `P(τ̄) = P2`, `dP/dτ = (P2 − P1)/τ̄`).
pub fn lyapunov_matrix(
    p1: MatRef<'_, f64>,
    p2: MatRef<'_, f64>,
    tau_bar: f64,
    tau: f64,
) -> Mat<f64> {
    let s = tau / tau_bar;
    p1 * (1.0 - s) + p2 * s
}

/// `M¹_p = He(P1 R_p) + (P2 − P1)/τ̄` and `M²_p = He(P2 R_p) + (P2 − P1)/τ̄`, (20a)–(20b).
pub fn flow_vertex_blocks(
    p1: MatRef<'_, f64>,
    p2: MatRef<'_, f64>,
    r: MatRef<'_, f64>,
    tau_bar: f64,
) -> (Mat<f64>, Mat<f64>) {
    let d = (p2 - p1) * (1.0 / tau_bar);
    (he((p1 * r).as_ref()) + &d, he((p2 * r).as_ref()) + &d)
}

/// The flow condition (19b) / (16b) with `∂P/∂s = 0` for the Lyapunov matrix of Theorem 3:
/// `N_p(τ) = He(P(τ) R_p) + (P2 − P1)/τ̄`.
pub fn flow_block(
    p1: MatRef<'_, f64>,
    p2: MatRef<'_, f64>,
    r: MatRef<'_, f64>,
    tau_bar: f64,
    tau: f64,
) -> Mat<f64> {
    let p = lyapunov_matrix(p1, p2, tau_bar, tau);
    he((&p * r).as_ref()) + (p2 - p1) * (1.0 / tau_bar)
}

/// The jump block `J(P⁻, P⁺, L) = [He(LC) + P⁻ − P⁺, C'L'; LC, P⁺]` of (16c)/(19c) (module
/// docs). Shapes: `P⁻, P⁺` n×n, `L` n×q, `C` q×n.
pub fn jump_block(
    p_before: MatRef<'_, f64>,
    p_after: MatRef<'_, f64>,
    l: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
) -> Mat<f64> {
    let n = p_after.nrows();
    let lc = l * c;
    let top = he(lc.as_ref()) + p_before - p_after;
    Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => top[(i, j)],
        (true, false) => lc[(j - n, i)],
        (false, true) => lc[(i - n, j)],
        (false, false) => p_after[(i - n, j - n)],
    })
}

/// The Schur form of the jump condition: `P⁻ − (I − KC)' P⁺ (I − KC)` (positive definite iff
/// [`jump_block`] is, given `P⁺ ≻ 0`).
pub fn jump_decrease(
    p_before: MatRef<'_, f64>,
    p_after: MatRef<'_, f64>,
    k: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
) -> Mat<f64> {
    let reset = reset_matrix(k, c);
    p_before - reset.transpose() * p_after * &reset
}

/// `I − K C`, the reset of the error at a sample.
pub fn reset_matrix(k: MatRef<'_, f64>, c: MatRef<'_, f64>) -> Mat<f64> {
    let n = k.nrows();
    Mat::<f64>::identity(n, n) - k * c
}

/// `(20c)`: `J(P(τ_low), P1, L0)`, i.e. `[He(L0C) − (τ_low/τ̄)(P1 − P2), C'L0'; ⋆, P1]`.
pub fn jump_block_low(
    p1: MatRef<'_, f64>,
    p2: MatRef<'_, f64>,
    l0: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
    window: &Window,
) -> Mat<f64> {
    let p_low = lyapunov_matrix(p1, p2, window.tau_bar(), window.tau_low());
    jump_block(p_low.as_ref(), p1, l0, c)
}

/// `(20d)`: `J(P2, P1, L1)`, i.e. `[He(L1C) − (P1 − P2), C'L1'; ⋆, P1]`.
pub fn jump_block_high(
    p1: MatRef<'_, f64>,
    p2: MatRef<'_, f64>,
    l1: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
) -> Mat<f64> {
    jump_block(p2, p1, l1, c)
}

/// Linear interpolation on `[τ_low, τ̄]`:
/// `X(τ) = X0 + (τ − τ_low)/(τ̄ − τ_low) (X1 − X0)` (used for `L(τ)` in the proof of Theorem 3
/// and for `K(τ)` in Remark 6); `X0` when `τ_low = τ̄`.
pub fn interpolate(
    x0: MatRef<'_, f64>,
    x1: MatRef<'_, f64>,
    window: &Window,
    tau: f64,
) -> Mat<f64> {
    let width = window.tau_bar() - window.tau_low();
    if width <= 0.0 {
        return x0.to_owned();
    }
    let s = (tau - window.tau_low()) / width;
    x0 + (x1 - x0) * s
}

/// `K = P1⁻¹ L` by a Cholesky factorisation of `P1` (the gain recovery of Theorem 3,
/// Corollary 2 and Remark 6).
pub fn gain_from(p1: MatRef<'_, f64>, l: MatRef<'_, f64>) -> Result<Mat<f64>, Error> {
    let n = p1.nrows();
    check_shape(p1, n, n, "P1")?;
    check_shape(l, n, l.ncols(), "L")?;
    let llt = p1.llt(faer::Side::Lower).map_err(|_| Error::Singular {
        what: "P1 is not positive definite (K = P1⁻¹L)".into(),
    })?;
    let k = llt.solve(l);
    if (0..k.ncols()).all(|j| (0..k.nrows()).all(|i| k[(i, j)].is_finite())) {
        Ok(k)
    } else {
        Err(Error::Singular {
            what: "P1 (K = P1⁻¹L overflowed)".into(),
        })
    }
}
