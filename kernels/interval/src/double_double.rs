//! Double-double arithmetic (a value is the unevaluated sum `hi + lo` of two doubles, about
//! 106 bits of significand; Dekker 1971, Hida–Li–Bailey 2001) for small dense matrices: the
//! products, the inverse of a triangular matrix and the matrix exponential, where a result in
//! double precision would carry errors relative to the norms of its factors that a later
//! product amplifies (a contraction `‖R e^{Av} R⁻¹‖` with `κ(R) ~ 10⁹` and `‖e^{Av}‖ ~ 10⁶`).
//!
//! The operations are those of Hida, Li and Bailey's "sloppy" double-double (relative error a
//! few units of [`UNIT_ROUNDOFF_DD`] per operation, no underflow or overflow handling); they
//! give estimates, not bounds, and their callers say what safety factor they apply.

use std::ops::{Add, Div, Mul, Neg, Sub};

use faer::{Mat, MatRef};

use crate::round::{two_prod, two_sum};

/// The unit roundoff of double-double arithmetic, `2⁻¹⁰⁴` (twice `2⁻¹⁰⁶` for its sloppy
/// operations).
pub const UNIT_ROUNDOFF_DD: f64 = 4.930380657631324e-32;

/// A double-double number `hi + lo` with `|lo| ≤ ulp(hi)/2`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DoubleDouble {
    /// The leading double (the value rounded to double precision).
    pub hi: f64,
    /// The trailing double.
    pub lo: f64,
}

impl DoubleDouble {
    /// Zero.
    pub const ZERO: Self = Self { hi: 0.0, lo: 0.0 };
    /// One.
    pub const ONE: Self = Self { hi: 1.0, lo: 0.0 };

    /// The exact product of two doubles.
    pub fn product(a: f64, b: f64) -> Self {
        let (hi, lo) = two_prod(a, b);
        Self { hi, lo }
    }

    /// `hi + lo` renormalised.
    fn renormalised(hi: f64, lo: f64) -> Self {
        let (hi, lo) = two_sum(hi, lo);
        Self { hi, lo }
    }

    /// The value rounded to double precision.
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// Multiplication by a power of two (exact).
    pub fn scaled(self, power_of_two: f64) -> Self {
        Self {
            hi: self.hi * power_of_two,
            lo: self.lo * power_of_two,
        }
    }

    /// Whether both parts are finite.
    pub fn is_finite(self) -> bool {
        self.hi.is_finite() && self.lo.is_finite()
    }
}

impl From<f64> for DoubleDouble {
    fn from(hi: f64) -> Self {
        Self { hi, lo: 0.0 }
    }
}

impl Add for DoubleDouble {
    type Output = Self;
    fn add(self, b: Self) -> Self {
        let (s, e) = two_sum(self.hi, b.hi);
        Self::renormalised(s, e + self.lo + b.lo)
    }
}

impl Neg for DoubleDouble {
    type Output = Self;
    fn neg(self) -> Self {
        Self {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Sub for DoubleDouble {
    type Output = Self;
    fn sub(self, b: Self) -> Self {
        self + (-b)
    }
}

impl Mul for DoubleDouble {
    type Output = Self;
    fn mul(self, b: Self) -> Self {
        let (p, e) = two_prod(self.hi, b.hi);
        Self::renormalised(p, e + (self.hi * b.lo + self.lo * b.hi))
    }
}

impl Div for DoubleDouble {
    type Output = Self;
    fn div(self, b: Self) -> Self {
        let q1 = self.hi / b.hi;
        let r = self - b * Self::from(q1);
        let q2 = r.hi / b.hi;
        Self::renormalised(q1, q2)
    }
}

/// A dense matrix of double-double numbers, column-major.
#[derive(Debug, Clone, PartialEq)]
pub struct DdMatrix {
    rows: usize,
    cols: usize,
    data: Vec<DoubleDouble>,
}

impl DdMatrix {
    /// The matrix with entries `f(i, j)`.
    pub fn from_fn(rows: usize, cols: usize, f: impl Fn(usize, usize) -> DoubleDouble) -> Self {
        let mut data = Vec::with_capacity(rows * cols);
        for j in 0..cols {
            for i in 0..rows {
                data.push(f(i, j));
            }
        }
        Self { rows, cols, data }
    }

    /// The matrix of doubles `a`, exactly.
    pub fn from_f64(a: MatRef<'_, f64>) -> Self {
        Self::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)].into())
    }

    /// The identity of order `n`.
    pub fn identity(n: usize) -> Self {
        Self::from_fn(n, n, kronecker)
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.cols
    }

    /// Entry `(i, j)`.
    pub fn get(&self, i: usize, j: usize) -> DoubleDouble {
        self.data[i + j * self.rows]
    }

    /// The matrix rounded to doubles.
    pub fn to_f64(&self) -> Mat<f64> {
        Mat::from_fn(self.rows, self.cols, |i, j| self.get(i, j).to_f64())
    }

    /// The product `self · b` (panics on mismatched inner dimensions).
    pub fn mul(&self, b: &Self) -> Self {
        assert_eq!(
            self.cols, b.rows,
            "inner dimensions of a double-double product"
        );
        Self::from_fn(self.rows, b.cols, |i, j| {
            (0..self.cols).fold(DoubleDouble::ZERO, |s, k| s + self.get(i, k) * b.get(k, j))
        })
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.data.iter().all(|x| x.is_finite())
    }

    /// The largest absolute column sum (of the leading parts).
    pub fn norm_l1(&self) -> f64 {
        (0..self.cols)
            .map(|j| (0..self.rows).map(|i| self.get(i, j).hi.abs()).sum::<f64>())
            .fold(0.0, f64::max)
    }
}

/// The entry `(i, j)` of the identity: one on the diagonal, zero elsewhere.
fn kronecker(i: usize, j: usize) -> DoubleDouble {
    DoubleDouble::from(f64::from(u8::from(i == j)))
}

/// The inverse of an upper-triangular matrix of doubles by back substitution in double-double
/// arithmetic (`None` when a diagonal entry is zero or a result is not finite). Entries below
/// the diagonal are ignored.
pub fn upper_triangular_inverse(r: MatRef<'_, f64>) -> Option<DdMatrix> {
    let n = r.nrows();
    if (0..n).any(|i| r[(i, i)] == 0.0) {
        return None;
    }
    let mut x = DdMatrix::from_fn(n, n, |_, _| DoubleDouble::ZERO);
    for j in 0..n {
        for i in (0..=j).rev() {
            let rhs = kronecker(i, j);
            let sum = (i + 1..=j).fold(rhs, |s, k| s - x.get(k, j) * r[(i, k)].into());
            x.data[i + j * n] = sum / r[(i, i)].into();
        }
    }
    x.is_finite().then_some(x)
}

/// Norm bound of the scaled argument of the Taylor series in [`expm`].
pub const TAYLOR_RADIUS: f64 = 0.25;

/// Degree of the Taylor polynomial in [`expm`]: `0.25²¹/21! < 5·10⁻³³`, below
/// [`UNIT_ROUNDOFF_DD`] relative to `e^{−0.25} ≤ ‖e^X‖` for `‖X‖₁ ≤ 0.25`.
pub const TAYLOR_DEGREE: u32 = 20;

/// `e^{Av}` in double-double arithmetic: `Av` formed exactly, scaled by `2⁻ˢ` to a norm at most
/// [`TAYLOR_RADIUS`], its Taylor polynomial of degree [`TAYLOR_DEGREE`] by Horner's rule, then
/// squared `s` times. `None` when an entry is not finite (overflow). Its relative error is a
/// few units of [`UNIT_ROUNDOFF_DD`] times the condition number of the exponential, which for
/// a normal `A` is at most `‖Av‖`.
pub fn expm(a: MatRef<'_, f64>, v: f64) -> Option<DdMatrix> {
    let n = a.nrows();
    let norm = a.norm_l1() * v.abs();
    if !norm.is_finite() {
        return None;
    }
    let squarings = if norm > TAYLOR_RADIUS {
        (norm / TAYLOR_RADIUS).log2().ceil() as i32
    } else {
        0
    };
    let scale = 2f64.powi(-squarings);
    let x = DdMatrix::from_fn(n, n, |i, j| {
        DoubleDouble::product(a[(i, j)], v).scaled(scale)
    });
    // Horner: T = I + X/1·(I + X/2·(… (I + X/m))).
    let mut t = DdMatrix::identity(n);
    for k in (1..=TAYLOR_DEGREE).rev() {
        let xt = x.mul(&t);
        let inv_k = DoubleDouble::ONE / f64::from(k).into();
        t = DdMatrix::from_fn(n, n, |i, j| kronecker(i, j) + xt.get(i, j) * inv_k);
    }
    for _ in 0..squarings {
        t = t.mul(&t);
        if !t.is_finite() {
            return None;
        }
    }
    t.is_finite().then_some(t)
}
