//! The data of Section III of Rabehi et al. (2021): the plant (2)–(3) and the disturbance/noise
//! bounds of Assumptions 2–3. The sampling window of Assumption 1 (`t_{k+1} − t_k ∈ [τmin, τmax]`)
//! is [`sporadic_model::SamplingWindow`] (`T1 = τmin`, `T2 = τmax`).

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_square_finite;
use sporadic_linalg::input::{check_finite, check_finite_slice};

use crate::error::Error;
use sporadic_model::SamplingWindow;

/// The plant (2)–(3): `ẋ = Ax + Bu + d(t)`, `y(t_k) = Cx(t_k) + v(t_k)`, with `x ∈ Rⁿ`, `u ∈ Rᵐ`,
/// `y ∈ Rᵖ`. The disturbance enters every state directly.
#[derive(Debug, Clone, PartialEq)]
pub struct Plant {
    a: Mat<f64>,
    b: Mat<f64>,
    c: Mat<f64>,
}

impl Plant {
    /// Checks shapes (`A` n×n, `B` n×m, `C` p×n with n, p ≥ 1; `m = 0` is allowed) and finiteness.
    ///
    /// # Errors
    /// [`Error::Input`] (`NotSquare`), [`Error::Input`] (`Empty`), [`Error::Input`] (`DimensionMismatch`), [`Error::Input`] (`NonFinite`).
    pub fn new(a: MatRef<'_, f64>, b: MatRef<'_, f64>, c: MatRef<'_, f64>) -> Result<Self, Error> {
        let n = check_square_finite(a, "A")?;
        if b.nrows() != n {
            return Err(InputError::mismatch("rows of B (= order of A)", n, b.nrows()).into());
        }
        check_finite(b, "B")?;
        if c.nrows() == 0 {
            return Err(InputError::empty("C (no measured output)").into());
        }
        if c.ncols() != n {
            return Err(InputError::mismatch("columns of C (= order of A)", n, c.ncols()).into());
        }
        check_finite(c, "C")?;
        Ok(Self {
            a: a.to_owned(),
            b: b.to_owned(),
            c: c.to_owned(),
        })
    }

    /// State dimension `n`.
    pub fn n(&self) -> usize {
        self.a.nrows()
    }

    /// Input dimension `m`.
    pub fn m(&self) -> usize {
        self.b.ncols()
    }

    /// Output dimension `p`.
    pub fn p(&self) -> usize {
        self.c.nrows()
    }

    /// `A`.
    pub fn a(&self) -> MatRef<'_, f64> {
        self.a.as_ref()
    }

    /// `B`.
    pub fn b(&self) -> MatRef<'_, f64> {
        self.b.as_ref()
    }

    /// `C`.
    pub fn c(&self) -> MatRef<'_, f64> {
        self.c.as_ref()
    }

    /// Checks that `l` is an `n × p` finite gain.
    pub(crate) fn check_gain(&self, l: MatRef<'_, f64>) -> Result<(), Error> {
        if l.nrows() != self.n() {
            return Err(InputError::mismatch("rows of L (= n)", self.n(), l.nrows()).into());
        }
        if l.ncols() != self.p() {
            return Err(InputError::mismatch("columns of L (= p)", self.p(), l.ncols()).into());
        }
        Ok(check_finite(l, "L")?)
    }
}

/// `points ≥ 2` equally spaced values from `T1` to `T2` of the window of Assumption 1 (one
/// point for a periodic window).
pub(crate) fn window_grid(window: &SamplingWindow, points: usize) -> Vec<f64> {
    let (t1, t2) = (window.t1(), window.t2());
    if t1 == t2 || points < 2 {
        return vec![t1];
    }
    let h = (t2 - t1) / (points - 1) as f64;
    (0..points)
        .map(|k| {
            if k + 1 == points {
                t2
            } else {
                t1 + k as f64 * h
            }
        })
        .collect()
}

/// The bounds of Assumptions 2–3: `|v(t)| ≤ v̄` (elementwise, `v̄ ∈ Rᵖ`, `v̄ ≥ 0`) and
/// `d̲ ≤ d(t) ≤ d̄` (`d̲, d̄ ∈ Rⁿ`).
#[derive(Debug, Clone, PartialEq)]
pub struct Bounds {
    d_lower: Vec<f64>,
    d_upper: Vec<f64>,
    v_bar: Vec<f64>,
}

impl Bounds {
    /// # Errors
    /// [`Error::Input`] (`DimensionMismatch`) when `d_lower`/`d_upper` have different lengths,
    /// [`Error::Input`] (`NonFinite`), [`Error::InvalidBounds`] for `d̲_i > d̄_i` or `v̄_i < 0`.
    pub fn new(d_lower: Vec<f64>, d_upper: Vec<f64>, v_bar: Vec<f64>) -> Result<Self, Error> {
        if d_lower.len() != d_upper.len() {
            return Err(InputError::mismatch(
                "length of d_upper (= length of d_lower)",
                d_lower.len(),
                d_upper.len(),
            )
            .into());
        }
        check_finite_slice(&d_lower, "d_lower")?;
        check_finite_slice(&d_upper, "d_upper")?;
        check_finite_slice(&v_bar, "v_bar")?;
        if let Some(i) = (0..d_lower.len()).find(|&i| d_lower[i] > d_upper[i]) {
            return Err(Error::InvalidBounds {
                what: "d_lower/d_upper",
                index: i,
                reason: format!("d_lower = {} > d_upper = {}", d_lower[i], d_upper[i]),
            });
        }
        if let Some(i) = v_bar.iter().position(|&v| v < 0.0) {
            return Err(Error::InvalidBounds {
                what: "v_bar",
                index: i,
                reason: format!("v_bar = {} < 0", v_bar[i]),
            });
        }
        Ok(Self {
            d_lower,
            d_upper,
            v_bar,
        })
    }

    /// The noise- and disturbance-free case of Remark 4 (`d̲ = d̄ = 0`, `v̄ = 0`).
    pub fn zero(n: usize, p: usize) -> Self {
        Self {
            d_lower: vec![0.0; n],
            d_upper: vec![0.0; n],
            v_bar: vec![0.0; p],
        }
    }

    /// `d̲`.
    pub fn d_lower(&self) -> &[f64] {
        &self.d_lower
    }

    /// `d̄`.
    pub fn d_upper(&self) -> &[f64] {
        &self.d_upper
    }

    /// `v̄`.
    pub fn v_bar(&self) -> &[f64] {
        &self.v_bar
    }

    /// Checks the dimensions against a plant (`n` disturbance and `p` noise components).
    pub fn check_against(&self, plant: &Plant) -> Result<(), Error> {
        if self.d_lower.len() != plant.n() {
            return Err(InputError::mismatch(
                "length of the disturbance bounds (= n)",
                plant.n(),
                self.d_lower.len(),
            )
            .into());
        }
        if self.v_bar.len() != plant.p() {
            return Err(InputError::mismatch(
                "length of the noise bound v_bar (= p)",
                plant.p(),
                self.v_bar.len(),
            )
            .into());
        }
        Ok(())
    }

    /// `Ξ̄ = [d̄ − d̲; d̄ − d̲]`, the constant upper bound of the disturbance term of (6).
    pub fn xi_bar(&self) -> Vec<f64> {
        let w: Vec<f64> = self
            .d_upper
            .iter()
            .zip(&self.d_lower)
            .map(|(u, l)| u - l)
            .collect();
        w.iter().chain(&w).copied().collect()
    }
}
