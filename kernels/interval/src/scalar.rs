//! Scalar intervals `[lo, hi]` with outward rounding.

use crate::IntervalError;
use crate::round::{
    add_down, add_up, div_down, div_up, mul_down, mul_up, sqrt_down, sqrt_up, sub_down, sub_up,
};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A closed real interval `[lo, hi]` (infimum–supremum form), `lo ≤ hi`, never empty.
///
/// Endpoints may be infinite (`[-∞, x]`, `[x, +∞]`, [`Interval::ENTIRE`]) but are never NaN.
/// Every operation returns an interval that contains the exact real result of the operation
/// applied to any members of the operands ("outward rounding", see the crate documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    lo: f64,
    hi: f64,
}

impl Interval {
    /// The whole real line.
    pub const ENTIRE: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };
    /// The point interval `[0, 0]`.
    pub const ZERO: Interval = Interval { lo: 0.0, hi: 0.0 };
    /// The point interval `[1, 1]`.
    pub const ONE: Interval = Interval { lo: 1.0, hi: 1.0 };

    /// The interval `[lo, hi]`.
    ///
    /// # Errors
    /// [`IntervalError::InvalidInterval`] if an endpoint is NaN, `lo > hi`, `lo = +∞` or `hi = −∞`.
    pub fn new(lo: f64, hi: f64) -> Result<Self, IntervalError> {
        if !(lo <= hi) || lo == f64::INFINITY || hi == f64::NEG_INFINITY {
            return Err(IntervalError::InvalidInterval { lo, hi });
        }
        Ok(Self { lo, hi })
    }

    /// The point interval `[x, x]`.
    ///
    /// # Errors
    /// [`IntervalError::InvalidInterval`] if `x` is NaN or infinite.
    pub fn point(x: f64) -> Result<Self, IntervalError> {
        if !x.is_finite() {
            return Err(IntervalError::InvalidInterval { lo: x, hi: x });
        }
        Ok(Self { lo: x, hi: x })
    }

    /// `[lo, hi]` without checks; callers guarantee `lo ≤ hi`, no NaN.
    #[inline]
    pub(crate) fn raw(lo: f64, hi: f64) -> Self {
        debug_assert!(lo <= hi, "raw interval [{lo}, {hi}]");
        Self { lo, hi }
    }

    /// The interval `[m − r, m + r]` (rounded outward) for finite `m` and `r ≥ 0`.
    #[inline]
    pub(crate) fn from_mid_rad(m: f64, r: f64) -> Self {
        Self::raw(sub_down(m, r), add_up(m, r))
    }

    /// Lower endpoint.
    #[inline]
    pub fn lo(self) -> f64 {
        self.lo
    }

    /// Upper endpoint.
    #[inline]
    pub fn hi(self) -> f64 {
        self.hi
    }

    /// A floating-point number inside the interval, close to its midpoint (0 for
    /// [`Interval::ENTIRE`], the finite endpoint's neighbourhood for half-unbounded intervals).
    pub fn mid(self) -> f64 {
        match (self.lo.is_finite(), self.hi.is_finite()) {
            (true, true) => {
                let m = 0.5 * self.lo + 0.5 * self.hi;
                m.clamp(self.lo, self.hi)
            }
            (false, false) => 0.0,
            (true, false) => self.lo.max(0.0),
            (false, true) => self.hi.min(0.0),
        }
    }

    /// Upper bound of the width `hi − lo`.
    pub fn width_up(self) -> f64 {
        sub_up(self.hi, self.lo)
    }

    /// Upper bound of the radius: the smallest float `r` found with `[lo, hi] ⊆ [mid − r, mid + r]`.
    pub fn rad_up(self) -> f64 {
        let m = self.mid();
        sub_up(m, self.lo).max(sub_up(self.hi, m))
    }

    /// Magnitude `max(|lo|, |hi|)` = max |x| over the interval (exact).
    pub fn mag(self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }

    /// Mignitude: min |x| over the interval (exact).
    pub fn mig(self) -> f64 {
        if self.lo > 0.0 {
            self.lo
        } else if self.hi < 0.0 {
            -self.hi
        } else {
            0.0
        }
    }

    /// Whether the real number `x` lies in the interval (false for NaN).
    pub fn contains(self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }

    /// Whether `other ⊆ self`.
    pub fn contains_interval(self, other: Interval) -> bool {
        self.lo <= other.lo && other.hi <= self.hi
    }

    /// Whether every member is strictly positive.
    pub fn is_positive(self) -> bool {
        self.lo > 0.0
    }

    /// Whether every member is strictly negative.
    pub fn is_negative(self) -> bool {
        self.hi < 0.0
    }

    /// Convex hull of the union.
    pub fn hull(self, other: Interval) -> Interval {
        Self::raw(self.lo.min(other.lo), self.hi.max(other.hi))
    }

    /// Intersection, `None` if it is empty.
    pub fn intersect(self, other: Interval) -> Option<Interval> {
        let lo = self.lo.max(other.lo);
        let hi = self.hi.min(other.hi);
        (lo <= hi).then(|| Self::raw(lo, hi))
    }

    /// {|x| : x ∈ self}.
    pub fn abs(self) -> Interval {
        Self::raw(self.mig(), self.mag())
    }

    /// {x² : x ∈ self} (tighter than `self * self`).
    pub fn sqr(self) -> Interval {
        let m = self.mig();
        let big = self.mag();
        Self::raw(mul_down(m, m), mul_up(big, big))
    }

    /// {√x : x ∈ self, x ≥ 0}; negative parts are cut off (`[0, 0]` if `hi < 0`).
    pub fn sqrt(self) -> Interval {
        if self.hi < 0.0 {
            return Self::ZERO;
        }
        Self::raw(sqrt_down(self.lo.max(0.0)), sqrt_up(self.hi))
    }

    /// {xⁿ : x ∈ self} for an integer power n ≥ 0 (by repeated outward-rounded products;
    /// even powers are non-negative).
    pub fn powi(self, n: u32) -> Interval {
        if n == 0 {
            return Self::ONE;
        }
        if n.is_multiple_of(2) {
            return self.sqr().powi(n / 2);
        }
        let mut acc = self;
        for _ in 1..n {
            acc = acc * self;
        }
        acc
    }

    /// {eˣ : x ∈ self}, with rigorous bounds (Taylor series of e^{x/2ᵏ} with a remainder bound,
    /// squared k times with directed rounding; `f64::exp` is not used because libm does not
    /// promise correct rounding). Accuracy: relative width ≲ 2ᵏ·13u with k ≈ log₂(64|x|),
    /// i.e. ≈ 1e-15 for |x| ≤ 1, ≈ 2e-12 for |x| ≈ 20, ≤ 1e-10 up to |x| = 709 (enough for the
    /// remainder bounds it is used for).
    pub fn exp(self) -> Interval {
        Self::raw(exp_down(self.lo), exp_up(self.hi))
    }
}

/// Number of Taylor terms and scaling target used by [`exp_up`]/[`exp_down`].
const EXP_TERMS: u32 = 12;
/// 2⁻⁷⁷ ≥ 2·(2⁻⁶)¹³: bound of the Taylor remainder after [`EXP_TERMS`] terms for s ≤ 2⁻⁶.
const EXP_REMAINDER: f64 = 1.0 / 151_115_727_451_828_646_838_272.0;

/// Lower (`up = false`) or upper bound of eʸ for 0 ≤ y, by scaling and squaring.
fn exp_nonneg(y: f64, up: bool) -> f64 {
    if y == 0.0 {
        return 1.0;
    }
    if y == f64::INFINITY {
        return if up { f64::INFINITY } else { f64::MAX };
    }
    if y > 710.0 {
        // e^710 > f64::MAX.
        return if up { f64::INFINITY } else { f64::MAX };
    }
    // y / 2^k ≤ 2^-6.
    let mut k = 0u32;
    let mut s = y;
    while s > 1.0 / 64.0 {
        s *= 0.5; // exact: s stays far above the subnormal range
        k += 1;
    }
    // Horner for Σ_{j=0}^{J} s^j/j!: p = 1 + s/1·(1 + s/2·(1 + … (1 + s/J))). All terms ≥ 0, so
    // rounding every operation in one direction bounds the sum in that direction.
    let mut p = 1.0;
    for j in (1..=EXP_TERMS).rev() {
        let t = if up {
            div_up(mul_up(s, p), j as f64)
        } else {
            div_down(mul_down(s, p), j as f64)
        };
        p = if up { add_up(1.0, t) } else { add_down(1.0, t) };
    }
    if up {
        // Remainder Σ_{j>J} s^j/j! ≤ s^{J+1}/(J+1)! · 1/(1 − s/(J+2)) ≤ 2·s^{J+1}/(J+1)! ≤ 2·s^{J+1}
        // (s ≤ 2^-6, J + 1 = 13): at most 2^-77, far below an ulp of p ≥ 1, but added for rigour.
        p = add_up(p, EXP_REMAINDER);
    }
    for _ in 0..k {
        p = if up { mul_up(p, p) } else { mul_down(p, p) };
    }
    p
}

/// Upper bound of eˣ.
pub(crate) fn exp_up(x: f64) -> f64 {
    if x >= 0.0 {
        exp_nonneg(x, true)
    } else if x == f64::NEG_INFINITY {
        0.0
    } else {
        let d = exp_nonneg(-x, false);
        div_up(1.0, d)
    }
}

/// Lower bound of eˣ (≥ 0).
pub(crate) fn exp_down(x: f64) -> f64 {
    if x >= 0.0 {
        exp_nonneg(x, false)
    } else if x == f64::NEG_INFINITY {
        0.0
    } else {
        let d = exp_nonneg(-x, true);
        if d == f64::INFINITY {
            0.0
        } else {
            div_down(1.0, d).max(0.0)
        }
    }
}

impl Add for Interval {
    type Output = Interval;
    fn add(self, rhs: Interval) -> Interval {
        Interval::raw(add_down(self.lo, rhs.lo), add_up(self.hi, rhs.hi))
    }
}

impl Sub for Interval {
    type Output = Interval;
    fn sub(self, rhs: Interval) -> Interval {
        Interval::raw(sub_down(self.lo, rhs.hi), sub_up(self.hi, rhs.lo))
    }
}

impl Neg for Interval {
    type Output = Interval;
    fn neg(self) -> Interval {
        Interval::raw(-self.hi, -self.lo)
    }
}

impl Mul for Interval {
    type Output = Interval;
    fn mul(self, rhs: Interval) -> Interval {
        let (a, b, c, d) = (self.lo, self.hi, rhs.lo, rhs.hi);
        let lo = mul_down(a, c)
            .min(mul_down(a, d))
            .min(mul_down(b, c))
            .min(mul_down(b, d));
        let hi = mul_up(a, c)
            .max(mul_up(a, d))
            .max(mul_up(b, c))
            .max(mul_up(b, d));
        Interval::raw(lo, hi)
    }
}

impl Div for Interval {
    type Output = Interval;
    /// Quotient; [`Interval::ENTIRE`] if the divisor contains 0 (a superset of the exact
    /// result, which may be unbounded or a union of two half-lines).
    fn div(self, rhs: Interval) -> Interval {
        if rhs.lo <= 0.0 && rhs.hi >= 0.0 {
            return Interval::ENTIRE;
        }
        let (a, b, c, d) = (self.lo, self.hi, rhs.lo, rhs.hi);
        let q = |x: f64, y: f64, up: bool| {
            // ±∞/±∞ cannot occur with a finite-or-infinite numerator only when both are
            // infinite; treat it as unbounded in the requested direction.
            if x.is_infinite() && y.is_infinite() {
                if up { f64::INFINITY } else { f64::NEG_INFINITY }
            } else if up {
                div_up(x, y)
            } else {
                div_down(x, y)
            }
        };
        let lo = q(a, c, false)
            .min(q(a, d, false))
            .min(q(b, c, false))
            .min(q(b, d, false));
        let hi = q(a, c, true)
            .max(q(a, d, true))
            .max(q(b, c, true))
            .max(q(b, d, true));
        Interval::raw(lo, hi)
    }
}

impl std::fmt::Display for Interval {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "[{:e}, {:e}]", self.lo, self.hi)
    }
}
