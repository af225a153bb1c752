//! Integrals of the matrix exponential through exponentials of block-triangular matrices:
//! Van Loan (1978), *Computing integrals involving the matrix exponential*, IEEE Trans.
//! Automat. Control 23(3):395–404, Theorem 1.
//!
//! * [`zoh`]: exp(t·[[A, B], [0, 0]]) = [[e^{At}, Γ(t)], [0, I]] with Γ(t) = ∫₀ᵗ e^{As} ds·B
//!   (zero-order-hold discretisation; SciPy `cont2discrete(method="zoh")`).
//! * [`expm_integral`]: the same with B = I.
//! * [`gramian_integral`]: exp(t·[[−Aᵀ, Q], [0, A]]) = [[·, F₁₂], [0, F₂₂ = e^{At}]] and
//!   ∫₀ᵗ e^{Aᵀs} Q e^{As} ds = F₂₂ᵀ F₁₂ (Van Loan 1978, Theorem 1 with the (1,2) block).
//!
//! The (1,2) block is linear in the coupling block, so the coupling block is first scaled by a
//! power of two 2^{−k} (exact) to match ‖A‖₁ and the result multiplied by 2^k: a coupling much
//! larger than A would otherwise inflate d_k = ‖M^k‖₁^{1/k} of Al-Mohy & Higham's
//! Algorithm 6.1 and force needless squarings (loss of accuracy in e^{At}).

use crate::InputError;
use faer::{Mat, MatRef};

use crate::symmetric::check_symmetric;
use crate::{LinalgError, check, expm_scaled};

/// Exponent k such that the coupling block of t·M, ‖C‖₁·|t|·2^{−k}, matches ‖A‖₁·|t| (or 1 when
/// A = 0) to within a factor √2; 0 for a zero coupling.
fn coupling_exponent(a_norm: f64, c_norm: f64, t: f64) -> i32 {
    if c_norm == 0.0 || t == 0.0 {
        return 0;
    }
    let ta = a_norm * t.abs();
    let target = if ta > 0.0 { ta.max(1e-100) } else { 1.0 };
    (c_norm * t.abs() / target)
        .log2()
        .round()
        .clamp(-1000.0, 1000.0) as i32
}

fn norm1(m: MatRef<'_, f64>) -> f64 {
    (0..m.ncols())
        .map(|j| m.col(j).iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

fn unscale(block: MatRef<'_, f64>, k: i32, what: &str) -> Result<Mat<f64>, LinalgError> {
    let f = (k as f64).exp2();
    let out = Mat::from_fn(block.nrows(), block.ncols(), |i, j| block[(i, j)] * f);
    check::finite(out.as_ref(), what).map_err(|_| LinalgError::overflow(what))?;
    Ok(out)
}

/// Zero-order-hold discretisation: (e^{At}, Γ(t) = ∫₀ᵗ e^{As} ds·B) from one exponential of
/// the (n+m)×(n+m) matrix t·[[A, B], [0, 0]] (Van Loan 1978, Theorem 1). Works for singular A
/// (no A⁻¹(e^{At} − I)).
///
/// # Errors
/// Bad A, B with a row count ≠ n, non-finite entries or t, or a failure of [`crate::expm()`].
pub fn zoh(
    a: MatRef<'_, f64>,
    b: MatRef<'_, f64>,
    t: f64,
) -> Result<(Mat<f64>, Mat<f64>), LinalgError> {
    let n = check::square_finite(a, "zoh: A")?;
    if b.nrows() != n {
        return Err(InputError::mismatch("zoh: rows of B (= order of A)", n, b.nrows()).into());
    }
    check::finite(b, "zoh: B")?;
    check::finite_scalar(t, "zoh: t")?;
    let m = b.ncols();
    let k = coupling_exponent(norm1(a), norm1(b), t);
    let f = (-k as f64).exp2();
    let big = Mat::from_fn(n + m, n + m, |i, j| match (i < n, j < n) {
        (true, true) => a[(i, j)],
        (true, false) => b[(i, j - n)] * f,
        _ => 0.0,
    });
    let e = expm_scaled(big.as_ref(), t)?;
    let gamma = unscale(e.submatrix(0, n, n, m), k, "zoh: input integral Γ(t)")?;
    Ok((e.submatrix(0, 0, n, n).to_owned(), gamma))
}

/// ∫₀ᵗ e^{As} ds (the input integral of [`zoh`] with B = I).
///
/// # Errors
/// As [`zoh`].
pub fn expm_integral(a: MatRef<'_, f64>, t: f64) -> Result<Mat<f64>, LinalgError> {
    let n = check::square(a)?;
    Ok(zoh(a, Mat::<f64>::identity(n, n).as_ref(), t)?.1)
}

/// Observability-type Gramian integral ∫₀ᵗ e^{Aᵀs} Q e^{As} ds for symmetric Q, as F₂₂ᵀF₁₂ from
/// exp(t·[[−Aᵀ, Q], [0, A]]) (Van Loan 1978); the result is symmetrised. For the
/// controllability form ∫₀ᵗ e^{As} Q e^{Aᵀs} ds pass Aᵀ.
///
/// # Errors
/// Bad A, Q of a different order or not symmetric (within
/// [`crate::symmetric::SYMMETRY_TOLERANCE`]), non-finite input, or a failure of [`crate::expm()`].
pub fn gramian_integral(
    a: MatRef<'_, f64>,
    q: MatRef<'_, f64>,
    t: f64,
) -> Result<Mat<f64>, LinalgError> {
    let n = check::square_finite(a, "gramian_integral: A")?;
    if q.nrows() != n || q.ncols() != n {
        let found = if q.nrows() != n { q.nrows() } else { q.ncols() };
        return Err(
            InputError::mismatch("gramian_integral: order of Q (= order of A)", n, found).into(),
        );
    }
    check_symmetric(q, "gramian_integral: Q")?;
    check::finite_scalar(t, "gramian_integral: t")?;
    let k = coupling_exponent(norm1(a), norm1(q), t);
    let f = (-k as f64).exp2();
    let big = Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => -a[(j, i)],
        (true, false) => 0.5 * (q[(i, j - n)] + q[(j - n, i)]) * f,
        (false, false) => a[(i - n, j - n)],
        (false, true) => 0.0,
    });
    let e = expm_scaled(big.as_ref(), t)?;
    let g = e.submatrix(n, n, n, n).transpose() * e.submatrix(0, n, n, n);
    let sym = Mat::from_fn(n, n, |i, j| 0.5 * (g[(i, j)] + g[(j, i)]));
    unscale(sym.as_ref(), k, "gramian_integral: result")
}
