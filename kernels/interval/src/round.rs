//! Directed rounding without access to the FPU rounding mode.
//!
//! Every function here returns a floating-point number that is a guaranteed lower (`*_down`)
//! or upper (`*_up`) bound of the exact real result of the operation on its (finite or
//! infinite) arguments, assuming IEEE 754 binary64 arithmetic with round-to-nearest, which is
//! what Rust guarantees for `+ - * / sqrt` on `f64`.
//!
//! * Sums and differences use Knuth's TwoSum, which gives the exact rounding error `e` of
//!   `s = fl(a + b)` (no underflow error is possible for additions). The bound is `s` itself
//!   when the error already points the right way, else `s.next_up()` / `s.next_down()`.
//! * Products, quotients and square roots step one unit in the last place outward from the
//!   round-to-nearest result: with round-to-nearest, `|fl(x) − x|` is at most half the spacing
//!   of the floating-point numbers around `fl(x)` (also in the subnormal range), so
//!   `fl(x).next_down() ≤ x ≤ fl(x).next_up()`. Exact zeros (a zero factor) are kept exact.
//! * Overflow: a finite exact result that rounds to `±∞` gets the finite bound `±f64::MAX` on
//!   the other side (`next_down(+∞) = f64::MAX`).
//!
//! Convention for unbounded intervals: `0 · ∞ = 0` in endpoint products (as in IEEE 1788).

/// Unit roundoff u = 2⁻⁵³ of binary64 with round-to-nearest.
pub const UNIT_ROUNDOFF: f64 = 1.0 / 9_007_199_254_740_992.0;
/// Smallest positive subnormal binary64 number η = 2⁻¹⁰⁷⁴ (absolute underflow error unit).
pub const ETA: f64 = f64::from_bits(1);

/// Knuth's TwoSum: `(s, e)` with `s = fl(a + b)` and `s + e = a + b` exactly (finite
/// arguments, no overflow).
#[inline]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// TwoProduct by a fused multiply-add: `(p, e)` with `p = fl(a·b)` and `p + e = a·b` exactly
/// (no underflow or overflow).
#[inline]
pub fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// Upper bound of a + b.
#[inline]
pub fn add_up(a: f64, b: f64) -> f64 {
    let (s, e) = two_sum(a, b);
    if s.is_finite() {
        // A non-finite `e` means an intermediate of TwoSum overflowed: step outward anyway.
        if e > 0.0 || !e.is_finite() {
            s.next_up()
        } else {
            s
        }
    } else if s == f64::NEG_INFINITY && a.is_finite() && b.is_finite() {
        -f64::MAX
    } else {
        s
    }
}

/// Lower bound of a + b.
#[inline]
pub fn add_down(a: f64, b: f64) -> f64 {
    -add_up(-a, -b)
}

/// Upper bound of a − b.
#[inline]
pub fn sub_up(a: f64, b: f64) -> f64 {
    add_up(a, -b)
}

/// Lower bound of a − b.
#[inline]
pub fn sub_down(a: f64, b: f64) -> f64 {
    add_down(a, -b)
}

/// Upper bound of a · b (with 0 · ∞ = 0).
#[inline]
pub fn mul_up(a: f64, b: f64) -> f64 {
    if a == 0.0 || b == 0.0 {
        0.0
    } else {
        (a * b).next_up()
    }
}

/// Lower bound of a · b (with 0 · ∞ = 0).
#[inline]
pub fn mul_down(a: f64, b: f64) -> f64 {
    if a == 0.0 || b == 0.0 {
        0.0
    } else {
        (a * b).next_down()
    }
}

/// Upper bound of a / b for b ≠ 0.
#[inline]
pub fn div_up(a: f64, b: f64) -> f64 {
    if a == 0.0 { 0.0 } else { (a / b).next_up() }
}

/// Lower bound of a / b for b ≠ 0.
#[inline]
pub fn div_down(a: f64, b: f64) -> f64 {
    if a == 0.0 { 0.0 } else { (a / b).next_down() }
}

/// Upper bound of √a for a ≥ 0.
#[inline]
pub fn sqrt_up(a: f64) -> f64 {
    if a == 0.0 { 0.0 } else { a.sqrt().next_up() }
}

/// Lower bound of √a for a ≥ 0 (clamped at 0).
#[inline]
pub fn sqrt_down(a: f64) -> f64 {
    if a <= 0.0 {
        0.0
    } else {
        a.sqrt().next_down().max(0.0)
    }
}

/// Upper bound of γ_k = k·u / (1 − k·u) (Higham's constant); `+∞` if k·u ≥ 1.
#[inline]
pub fn gamma_up(k: usize) -> f64 {
    let ku = mul_up(k as f64, UNIT_ROUNDOFF);
    let den = sub_down(1.0, ku);
    if den <= 0.0 {
        f64::INFINITY
    } else {
        div_up(ku, den)
    }
}

/// Upper bound of the absolute rounding error |fl(x) − x| of any single rounded operation whose
/// round-to-nearest result is `y = fl(x)`: u·|y| + η (half the spacing around `y` is at most
/// u·|y| for normal `y` and at most η/2 for subnormal `y`).
#[inline]
pub fn rounding_error_up(y: f64) -> f64 {
    add_up(mul_up(UNIT_ROUNDOFF, y.abs()), ETA)
}

/// Upper bound of |x − m|.
#[inline]
pub fn dist_up(x: f64, m: f64) -> f64 {
    let d = sub_up(x, m);
    let e = sub_up(m, x);
    d.max(e)
}
