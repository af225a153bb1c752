//! Interval matrices in midpoint–radius form.

use crate::round::{
    ETA, add_up, dist_up, div_up, gamma_up, mul_up, rounding_error_up, sqrt_up, sub_down,
};
use crate::{Interval, IntervalError};
use faer::linalg::matmul::matmul;
use faer::linalg::solvers::DenseSolveCore;
use faer::{Accum, Mat, MatRef, Par};
use std::ops::{Add, Mul, Neg, Sub};

/// A real interval matrix in midpoint–radius form ⟨mid, rad⟩: the set of all real matrices X
/// with |X − mid| ≤ rad entrywise (exact real inequality).
///
/// Invariants: `mid` is finite, `rad` ≥ 0 entrywise and may be `+∞` (an entry with radius
/// `+∞` is the whole real line; it has midpoint 0). Every operation returns a matrix that
/// contains the exact result of the operation applied to any members of the operands; see the
/// crate documentation for why midpoint–radius form and how rounding errors are bounded.
#[derive(Debug, Clone, PartialEq)]
pub struct IntervalMatrix {
    mid: Mat<f64>,
    rad: Mat<f64>,
}

fn shape(m: MatRef<'_, f64>) -> (usize, usize) {
    (m.nrows(), m.ncols())
}

fn check_finite(what: &'static str, m: MatRef<'_, f64>) -> Result<(), IntervalError> {
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            if !m[(i, j)].is_finite() {
                return Err(IntervalError::NonFinite {
                    what,
                    row: i,
                    col: j,
                });
            }
        }
    }
    Ok(())
}

/// ⟨m, r⟩ for a scalar interval [lo, hi] (outward rounded; unbounded → ⟨0, ∞⟩).
fn mid_rad_of(x: Interval) -> (f64, f64) {
    if !(x.lo().is_finite() && x.hi().is_finite()) {
        return (0.0, f64::INFINITY);
    }
    let m = x.mid();
    (m, x.rad_up())
}

impl IntervalMatrix {
    /// Builds ⟨mid, rad⟩ from raw parts and restores the invariants: an entry with non-finite
    /// midpoint or NaN radius becomes the whole real line ⟨0, ∞⟩ (a valid enclosure).
    pub(crate) fn from_parts_sanitized(mut mid: Mat<f64>, mut rad: Mat<f64>) -> Self {
        for j in 0..mid.ncols() {
            for i in 0..mid.nrows() {
                if !mid[(i, j)].is_finite() || rad[(i, j)].is_nan() {
                    mid[(i, j)] = 0.0;
                    rad[(i, j)] = f64::INFINITY;
                }
            }
        }
        Self { mid, rad }
    }

    /// The point matrix ⟨m, 0⟩.
    ///
    /// # Errors
    /// [`IntervalError::NonFinite`] if `m` has a NaN or infinite entry.
    pub fn from_point(m: MatRef<'_, f64>) -> Result<Self, IntervalError> {
        check_finite("point matrix", m)?;
        Ok(Self {
            mid: m.to_owned(),
            rad: Mat::zeros(m.nrows(), m.ncols()),
        })
    }

    /// ⟨mid, rad⟩ from a midpoint and a radius matrix.
    ///
    /// # Errors
    /// [`IntervalError::DimensionMismatch`] for different shapes, [`IntervalError::NonFinite`]
    /// for a non-finite midpoint, [`IntervalError::InvalidInterval`] for a negative or NaN
    /// radius (`+∞` is allowed).
    pub fn from_mid_rad(mid: Mat<f64>, rad: Mat<f64>) -> Result<Self, IntervalError> {
        if shape(mid.as_ref()) != shape(rad.as_ref()) {
            return Err(IntervalError::DimensionMismatch {
                what: "from_mid_rad",
                left: shape(mid.as_ref()),
                right: shape(rad.as_ref()),
            });
        }
        check_finite("midpoint", mid.as_ref())?;
        for j in 0..rad.ncols() {
            for i in 0..rad.nrows() {
                let r = rad[(i, j)];
                if !(r >= 0.0) {
                    return Err(IntervalError::InvalidInterval {
                        lo: sub_down(mid[(i, j)], r),
                        hi: add_up(mid[(i, j)], r),
                    });
                }
            }
        }
        Ok(Self { mid, rad })
    }

    /// The interval matrix with entries [lo_ij, hi_ij] (converted to midpoint–radius form
    /// with outward rounding, so it may be slightly wider).
    ///
    /// # Errors
    /// [`IntervalError::DimensionMismatch`] for different shapes, [`IntervalError::NonFinite`]
    /// for a non-finite bound, [`IntervalError::InvalidInterval`] if some lo_ij > hi_ij.
    pub fn from_bounds(lo: MatRef<'_, f64>, hi: MatRef<'_, f64>) -> Result<Self, IntervalError> {
        if shape(lo) != shape(hi) {
            return Err(IntervalError::DimensionMismatch {
                what: "from_bounds",
                left: shape(lo),
                right: shape(hi),
            });
        }
        check_finite("lower bound", lo)?;
        check_finite("upper bound", hi)?;
        let (r, c) = shape(lo);
        let mut out = Self::zeros(r, c);
        for j in 0..c {
            for i in 0..r {
                let x = Interval::new(lo[(i, j)], hi[(i, j)])?;
                let (m, rr) = mid_rad_of(x);
                out.mid[(i, j)] = m;
                out.rad[(i, j)] = rr;
            }
        }
        Ok(out)
    }

    /// The matrix whose (i, j) entry encloses `f(i, j)`.
    pub fn from_fn(nrows: usize, ncols: usize, f: impl Fn(usize, usize) -> Interval) -> Self {
        let mut out = Self::zeros(nrows, ncols);
        for j in 0..ncols {
            for i in 0..nrows {
                let (m, r) = mid_rad_of(f(i, j));
                out.mid[(i, j)] = m;
                out.rad[(i, j)] = r;
            }
        }
        out
    }

    /// The zero matrix (a point matrix).
    pub fn zeros(nrows: usize, ncols: usize) -> Self {
        Self {
            mid: Mat::zeros(nrows, ncols),
            rad: Mat::zeros(nrows, ncols),
        }
    }

    /// The identity matrix (a point matrix).
    pub fn identity(n: usize) -> Self {
        Self {
            mid: Mat::identity(n, n),
            rad: Mat::zeros(n, n),
        }
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.mid.nrows()
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.mid.ncols()
    }

    /// The midpoint matrix.
    pub fn mid(&self) -> MatRef<'_, f64> {
        self.mid.as_ref()
    }

    /// The radius matrix (entrywise ≥ 0, possibly `+∞`).
    pub fn rad(&self) -> MatRef<'_, f64> {
        self.rad.as_ref()
    }

    /// Entry (i, j) as a scalar interval (outward rounded).
    ///
    /// # Panics
    /// If (i, j) is out of bounds.
    pub fn get(&self, i: usize, j: usize) -> Interval {
        let (m, r) = (self.mid[(i, j)], self.rad[(i, j)]);
        if r == f64::INFINITY {
            Interval::ENTIRE
        } else {
            Interval::from_mid_rad(m, r)
        }
    }

    /// Entrywise lower bounds (mid − rad rounded down).
    pub fn lower(&self) -> Mat<f64> {
        Mat::from_fn(self.nrows(), self.ncols(), |i, j| {
            sub_down(self.mid[(i, j)], self.rad[(i, j)])
        })
    }

    /// Entrywise upper bounds (mid + rad rounded up).
    pub fn upper(&self) -> Mat<f64> {
        Mat::from_fn(self.nrows(), self.ncols(), |i, j| {
            add_up(self.mid[(i, j)], self.rad[(i, j)])
        })
    }

    /// Whether every radius is finite.
    pub fn is_bounded(&self) -> bool {
        (0..self.ncols()).all(|j| (0..self.nrows()).all(|i| self.rad[(i, j)].is_finite()))
    }

    /// Largest radius (exact); 0 for an empty matrix.
    pub fn max_rad(&self) -> f64 {
        let mut r = 0.0f64;
        for j in 0..self.ncols() {
            for i in 0..self.nrows() {
                r = r.max(self.rad[(i, j)]);
            }
        }
        r
    }

    /// Largest entry width 2·rad (an upper bound of the width of every entry).
    pub fn max_width(&self) -> f64 {
        2.0 * self.max_rad()
    }

    /// Largest |mid_ij| (exact).
    pub fn max_abs_mid(&self) -> f64 {
        let mut r = 0.0f64;
        for j in 0..self.ncols() {
            for i in 0..self.nrows() {
                r = r.max(self.mid[(i, j)].abs());
            }
        }
        r
    }

    /// Entrywise upper bound of |X| over all members X (|mid| + rad rounded up).
    pub fn mag(&self) -> Mat<f64> {
        Mat::from_fn(self.nrows(), self.ncols(), |i, j| {
            add_up(self.mid[(i, j)].abs(), self.rad[(i, j)])
        })
    }

    /// Upper bound of max ‖X‖_∞ (largest absolute row sum) over all members X.
    pub fn norm_inf_up(&self) -> f64 {
        let mag = self.mag();
        let mut best = 0.0f64;
        for i in 0..self.nrows() {
            let mut s = 0.0;
            for j in 0..self.ncols() {
                s = add_up(s, mag[(i, j)]);
            }
            best = best.max(s);
        }
        best
    }

    /// Upper bound of max ‖X‖_1 (largest absolute column sum) over all members X.
    pub fn norm_1_up(&self) -> f64 {
        let mag = self.mag();
        let mut best = 0.0f64;
        for j in 0..self.ncols() {
            let mut s = 0.0;
            for i in 0..self.nrows() {
                s = add_up(s, mag[(i, j)]);
            }
            best = best.max(s);
        }
        best
    }

    /// Upper bound of max ‖X‖_F (Frobenius norm) over all members X. The squares are summed
    /// after dividing by a power of two near the largest magnitude, so the bound is finite
    /// whenever the norm itself is representable (squaring entries above `1e154` would
    /// overflow).
    pub fn norm_fro_up(&self) -> f64 {
        let mag = self.mag();
        let largest = mag.norm_max();
        if largest == 0.0 || !largest.is_finite() {
            return largest;
        }
        // A power of two near `largest` (2^e ≤ largest < 2^(e+1) within the clamp), finite and
        // nonzero thanks to the clamp, which is all the bound needs: every step below rounds up.
        let e = largest.log2().floor().clamp(-1000.0, 1000.0) as i32;
        let unit = 2f64.powi(e);
        let mut s = 0.0;
        for j in 0..self.ncols() {
            for i in 0..self.nrows() {
                let x = div_up(mag[(i, j)], unit);
                s = add_up(s, mul_up(x, x));
            }
        }
        mul_up(sqrt_up(s), unit)
    }

    /// Upper bound of max ‖X‖₂ (spectral norm) over all members X: √‖·‖₁·√‖·‖_∞ (each root
    /// taken before the product, so it overflows only with the norms), capped by the
    /// Frobenius bound.
    pub fn norm_2_up(&self) -> f64 {
        mul_up(sqrt_up(self.norm_1_up()), sqrt_up(self.norm_inf_up())).min(self.norm_fro_up())
    }

    /// The transpose (exact).
    pub fn transpose(&self) -> Self {
        Self {
            mid: self.mid.transpose().to_owned(),
            rad: self.rad.transpose().to_owned(),
        }
    }

    /// A symmetric interval matrix containing every **symmetric** member of `self`: midpoint
    /// fl((M + Mᵀ)/2), radius (R + Rᵀ)/2 plus the rounding error of the midpoint, rounded up.
    /// (A symmetric member X equals (X + Xᵀ)/2, and |X − (M + Mᵀ)/2| ≤ (R + Rᵀ)/2.) Use it
    /// on a product such as GᵀPG, whose members are symmetric but whose midpoint–radius
    /// form is not exactly symmetric in floating point.
    ///
    /// # Errors
    /// [`IntervalError::NotSquare`] for a rectangular matrix.
    pub fn symmetrized(&self) -> Result<Self, IntervalError> {
        let n = self.nrows();
        if self.ncols() != n {
            return Err(IntervalError::NotSquare {
                what: "interval matrix",
                rows: n,
                cols: self.ncols(),
            });
        }
        let mut mid = Mat::zeros(n, n);
        let mut rad = Mat::zeros(n, n);
        for j in 0..n {
            for i in j..n {
                let (a, b) = (self.mid[(i, j)], self.mid[(j, i)]);
                let m = 0.5 * a + 0.5 * b;
                // The halvings are exact (barring underflow, covered by η); the sum errs by at
                // most one rounding.
                let err = add_up(rounding_error_up(m), crate::round::ETA);
                let r = add_up(mul_up(0.5, add_up(self.rad[(i, j)], self.rad[(j, i)])), err);
                mid[(i, j)] = m;
                mid[(j, i)] = m;
                rad[(i, j)] = r;
                rad[(j, i)] = r;
            }
        }
        Ok(Self::from_parts_sanitized(mid, rad))
    }

    /// A verified enclosure of the inverse of every member of the square interval matrix
    /// `self`: with `R ≈ mid⁻¹` (floating-point LU) and `E = I − R·self` in interval
    /// arithmetic, `‖E‖_∞ ≤ e < 1` proves every member nonsingular and gives
    /// `X⁻¹ = Σ_k E^k R ∈ R ± ‖R‖_∞·e/(1 − e)` entrywise (Neumann series; Rump's
    /// preconditioned inclusion). `None` when `‖E‖_∞ < 1` is not proven (e.g. `self` contains a
    /// singular matrix).
    ///
    /// # Errors
    /// [`IntervalError::NotSquare`] for a rectangular matrix.
    pub fn verified_inverse(&self) -> Result<Option<Self>, IntervalError> {
        let k = self.nrows();
        if self.ncols() != k {
            return Err(IntervalError::NotSquare {
                what: "interval matrix",
                rows: k,
                cols: self.ncols(),
            });
        }
        let r = self.mid.partial_piv_lu().inverse();
        if !r.norm_max().is_finite() {
            return Ok(None);
        }
        let ri = Self::from_point(r.as_ref())?;
        let e = Self::identity(k)
            .checked_sub(&ri.checked_mul(self)?)?
            .norm_inf_up();
        if !(e < 1.0) {
            return Ok(None);
        }
        let delta = div_up(mul_up(ri.norm_inf_up(), e), sub_down(1.0, e));
        if !delta.is_finite() {
            return Ok(None);
        }
        Ok(Some(Self::from_mid_rad(
            r,
            Mat::from_fn(k, k, |_, _| delta),
        )?))
    }

    /// Whether mid and rad are exactly symmetric (square and equal to their transposes).
    pub fn is_symmetric(&self) -> bool {
        self.first_asymmetry().is_none() && self.nrows() == self.ncols()
    }

    pub(crate) fn first_asymmetry(&self) -> Option<(usize, usize)> {
        let n = self.nrows().min(self.ncols());
        for j in 0..n {
            for i in (j + 1)..n {
                if self.mid[(i, j)] != self.mid[(j, i)] || self.rad[(i, j)] != self.rad[(j, i)] {
                    return Some((i, j));
                }
            }
        }
        None
    }

    /// Whether the real point matrix `x` is a member (exact test: |x − mid| ≤ rad is decided
    /// exactly with an error-free difference). Shape mismatch or NaN gives `false`.
    pub fn contains_point(&self, x: MatRef<'_, f64>) -> bool {
        if shape(x) != shape(self.mid.as_ref()) {
            return false;
        }
        for j in 0..self.ncols() {
            for i in 0..self.nrows() {
                if !point_in(x[(i, j)], self.mid[(i, j)], self.rad[(i, j)]) {
                    return false;
                }
            }
        }
        true
    }

    /// Whether the scalar interval `x` lies inside entry (i, j) (conservative: `true` only if
    /// proven).
    ///
    /// # Panics
    /// If (i, j) is out of bounds.
    pub fn entry_contains(&self, i: usize, j: usize, x: Interval) -> bool {
        let (m, r) = (self.mid[(i, j)], self.rad[(i, j)]);
        if r == f64::INFINITY {
            return true;
        }
        point_in(x.lo(), m, r) && point_in(x.hi(), m, r)
    }

    /// Whether `other ⊆ self` (conservative: `true` only if proven; shape mismatch → `false`).
    pub fn contains(&self, other: &IntervalMatrix) -> bool {
        if shape(other.mid()) != shape(self.mid()) {
            return false;
        }
        for j in 0..self.ncols() {
            for i in 0..self.nrows() {
                let (m, r) = (self.mid[(i, j)], self.rad[(i, j)]);
                let (om, or) = (other.mid[(i, j)], other.rad[(i, j)]);
                let ok = if r == f64::INFINITY {
                    true
                } else if or == 0.0 {
                    point_in(om, m, r)
                } else {
                    add_up(dist_up(om, m), or) <= r
                };
                if !ok {
                    return false;
                }
            }
        }
        true
    }

    /// Whether the two interval matrices have a common member (conservative in the other
    /// direction: `false` only if they are proven disjoint).
    pub fn intersects(&self, other: &IntervalMatrix) -> bool {
        if shape(other.mid()) != shape(self.mid()) {
            return false;
        }
        for j in 0..self.ncols() {
            for i in 0..self.nrows() {
                let a = self.get(i, j);
                let b = other.get(i, j);
                if a.intersect(b).is_none() {
                    return false;
                }
            }
        }
        true
    }

    /// The smallest (up to outward rounding) interval matrix containing both.
    ///
    /// # Errors
    /// [`IntervalError::DimensionMismatch`] for different shapes.
    pub fn hull(&self, other: &IntervalMatrix) -> Result<Self, IntervalError> {
        self.same_shape("hull", other)?;
        Ok(Self::from_fn(self.nrows(), self.ncols(), |i, j| {
            self.get(i, j).hull(other.get(i, j))
        }))
    }

    fn same_shape(&self, what: &'static str, other: &IntervalMatrix) -> Result<(), IntervalError> {
        if shape(self.mid()) != shape(other.mid()) {
            return Err(IntervalError::DimensionMismatch {
                what,
                left: shape(self.mid()),
                right: shape(other.mid()),
            });
        }
        Ok(())
    }

    fn add_sub(&self, other: &IntervalMatrix, sign: f64) -> Self {
        let (r, c) = (self.nrows(), self.ncols());
        let mut mid = Mat::zeros(r, c);
        let mut rad = Mat::zeros(r, c);
        for j in 0..c {
            for i in 0..r {
                let a = self.mid[(i, j)];
                let b = sign * other.mid[(i, j)];
                // TwoSum: s + e = a + b exactly.
                let s = a + b;
                let bb = s - a;
                let e = (a - (s - bb)) + (b - bb);
                let e = if e.is_finite() {
                    e.abs()
                } else {
                    rounding_error_up(s)
                };
                mid[(i, j)] = s;
                rad[(i, j)] = add_up(add_up(self.rad[(i, j)], other.rad[(i, j)]), e);
            }
        }
        Self::from_parts_sanitized(mid, rad)
    }

    /// Sum `self + other`.
    ///
    /// # Errors
    /// [`IntervalError::DimensionMismatch`] for different shapes.
    pub fn checked_add(&self, other: &IntervalMatrix) -> Result<Self, IntervalError> {
        self.same_shape("add", other)?;
        Ok(self.add_sub(other, 1.0))
    }

    /// Difference `self − other`.
    ///
    /// # Errors
    /// [`IntervalError::DimensionMismatch`] for different shapes.
    pub fn checked_sub(&self, other: &IntervalMatrix) -> Result<Self, IntervalError> {
        self.same_shape("sub", other)?;
        Ok(self.add_sub(other, -1.0))
    }

    /// Product `self · other` (midpoint–radius product with an a-priori bound of the
    /// floating-point error of the midpoint product; see the crate documentation).
    ///
    /// # Errors
    /// [`IntervalError::DimensionMismatch`] if `self.ncols() != other.nrows()`.
    pub fn checked_mul(&self, other: &IntervalMatrix) -> Result<Self, IntervalError> {
        if self.ncols() != other.nrows() {
            return Err(IntervalError::DimensionMismatch {
                what: "mul",
                left: shape(self.mid()),
                right: shape(other.mid()),
            });
        }
        Ok(self.mul_unchecked(other))
    }

    /// Product; shapes must fit.
    ///
    /// Exact inclusion used: for |X − Am| ≤ Ar and |Y − Bm| ≤ Br,
    /// |XY − Am·Bm| ≤ |Am|·Br + Ar·(|Bm| + Br). The midpoint Cm = fl(Am·Bm) (faer GEMM, any
    /// summation order, with or without FMA) satisfies |Cm − Am·Bm| ≤ γ_k·|Am|·|Bm| + k·η
    /// (Higham, Thm 3.5 / §3.1, plus ≤ η/2 underflow error per product), k = inner dimension.
    /// Hence Cr = |Am|·(Br + γ_k|Bm|) + Ar·(|Bm| + Br) + k·η suffices. With W1, W2 the two
    /// brackets (rounded up entrywise), S = |Am|·W1 + Ar·W2 is a sum of 2k non-negative products
    /// computed by two GEMMs; its floating-point value S̃ satisfies S ≤ (S̃ + 2kη)/(1 − γ_2k),
    /// so Cr := (S̃ + 3kη)·(1/(1 − γ_2k)) rounded up is a valid radius.
    fn mul_unchecked(&self, other: &IntervalMatrix) -> Self {
        let (m, k, n) = (self.nrows(), self.ncols(), other.ncols());
        let mut cm = Mat::<f64>::zeros(m, n);
        matmul(
            cm.as_mut(),
            Accum::Replace,
            self.mid.as_ref(),
            other.mid.as_ref(),
            1.0,
            Par::Seq,
        );
        let g = gamma_up(k.max(1));
        let abs_a = Mat::from_fn(m, k, |i, j| self.mid[(i, j)].abs());
        let w1 = Mat::from_fn(k, n, |i, j| {
            add_up(other.rad[(i, j)], mul_up(g, other.mid[(i, j)].abs()))
        });
        let w2 = Mat::from_fn(k, n, |i, j| {
            add_up(other.mid[(i, j)].abs(), other.rad[(i, j)])
        });
        let mut s = Mat::<f64>::zeros(m, n);
        matmul(
            s.as_mut(),
            Accum::Replace,
            abs_a.as_ref(),
            w1.as_ref(),
            1.0,
            Par::Seq,
        );
        matmul(
            s.as_mut(),
            Accum::Add,
            self.rad.as_ref(),
            w2.as_ref(),
            1.0,
            Par::Seq,
        );
        let g2 = gamma_up(2 * k.max(1));
        let factor = div_up(1.0, sub_down(1.0, g2));
        let eta_k = mul_up(3.0 * k as f64, ETA);
        let rad = Mat::from_fn(m, n, |i, j| {
            let v = s[(i, j)];
            if v.is_nan() {
                f64::NAN // sanitized to ⟨0, ∞⟩ below
            } else {
                mul_up(add_up(v, eta_k), factor)
            }
        });
        Self::from_parts_sanitized(cm, rad)
    }

    /// `s · self` for a scalar interval `s`.
    pub fn scale(&self, s: Interval) -> Self {
        let (sm, sr) = mid_rad_of(s);
        let (r, c) = (self.nrows(), self.ncols());
        let mut mid = Mat::zeros(r, c);
        let mut rad = Mat::zeros(r, c);
        for j in 0..c {
            for i in 0..r {
                let a = self.mid[(i, j)];
                let ar = self.rad[(i, j)];
                let p = a * sm;
                let err = if a == 0.0 || sm == 0.0 {
                    0.0
                } else {
                    rounding_error_up(p)
                };
                mid[(i, j)] = p;
                // |x·t − a·sm| ≤ |a|·sr + ar·(|sm| + sr) for |x − a| ≤ ar, |t − sm| ≤ sr.
                let v = add_up(
                    add_up(mul_up(a.abs(), sr), mul_up(ar, add_up(sm.abs(), sr))),
                    err,
                );
                rad[(i, j)] = v;
            }
        }
        Self::from_parts_sanitized(mid, rad)
    }

    /// Adds the interval [−ρ, ρ] to every entry (ρ ≥ 0; NaN or negative ρ is treated as `+∞`).
    pub fn inflate(&self, rho: f64) -> Self {
        let rho = if rho >= 0.0 { rho } else { f64::INFINITY };
        let rad = Mat::from_fn(self.nrows(), self.ncols(), |i, j| {
            add_up(self.rad[(i, j)], rho)
        });
        Self {
            mid: self.mid.clone(),
            rad,
        }
    }

    /// Relative width: `max_width() / max_abs_mid()` (∞ if the midpoint is zero and the
    /// radius is not).
    pub fn rel_width(&self) -> f64 {
        let w = self.max_width();
        if w == 0.0 {
            0.0
        } else {
            w / self.max_abs_mid()
        }
    }
}

/// Exact test |x − m| ≤ r for floats (r ≥ 0 or +∞).
fn point_in(x: f64, m: f64, r: f64) -> bool {
    if x.is_nan() {
        return false;
    }
    if r == f64::INFINITY {
        return true;
    }
    let s = x - m;
    if !s.is_finite() {
        return false; // |x − m| > f64::MAX ≥ r
    }
    let bb = s - x;
    let e = (x - (s - bb)) + (-m - bb);
    // s = fl(x − m), s + e = x − m exactly. If |s| < r then |x − m| < next_up(|s|) ≤ r; if
    // |s| > r then |x − m| > next_down(|s|) ≥ r; ties are decided by the sign of e.
    let a = s.abs();
    if a < r {
        true
    } else if a > r {
        false
    } else {
        e == 0.0 || (e > 0.0) != (s > 0.0)
    }
}

impl Add for &IntervalMatrix {
    type Output = IntervalMatrix;
    /// # Panics
    /// On a shape mismatch (use [`IntervalMatrix::checked_add`] for a `Result`).
    fn add(self, rhs: &IntervalMatrix) -> IntervalMatrix {
        self.checked_add(rhs)
            .expect("interval matrix sum: shape mismatch")
    }
}

impl Sub for &IntervalMatrix {
    type Output = IntervalMatrix;
    /// # Panics
    /// On a shape mismatch (use [`IntervalMatrix::checked_sub`] for a `Result`).
    fn sub(self, rhs: &IntervalMatrix) -> IntervalMatrix {
        self.checked_sub(rhs)
            .expect("interval matrix difference: shape mismatch")
    }
}

impl Mul for &IntervalMatrix {
    type Output = IntervalMatrix;
    /// # Panics
    /// On a shape mismatch (use [`IntervalMatrix::checked_mul`] for a `Result`).
    fn mul(self, rhs: &IntervalMatrix) -> IntervalMatrix {
        self.checked_mul(rhs)
            .expect("interval matrix product: shape mismatch")
    }
}

impl Neg for &IntervalMatrix {
    type Output = IntervalMatrix;
    fn neg(self) -> IntervalMatrix {
        IntervalMatrix {
            mid: Mat::from_fn(self.nrows(), self.ncols(), |i, j| -self.mid[(i, j)]),
            rad: self.rad.clone(),
        }
    }
}
