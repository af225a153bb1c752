//! The impulsive observer gain `K(τ)` of Theorem 3 / Remark 6 (Etienne et al. 2017): affine in
//! the length `τ = t_k − t_{k−1}` of the interval that just ended,
//!
//! ```text
//! K(τ) = K0 + (τ − τ_low)/(τ̄ − τ_low) · (K1 − K0),   τ ∈ [τ_low, τ̄],
//! ```
//!
//! so `K(τ_low) = K0` and `K(τ̄) = K1`; constant (`K0 = K1`) for Corollary 2 and Remark 6.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::{check_finite, check_shape};

use crate::conditions::interpolate_checked;
use crate::error::Error;
use sporadic_model::SamplingWindow;

/// The gain schedule `τ ↦ K(τ)` on a window `[τ_low, τ̄]`.
#[derive(Debug, Clone, PartialEq)]
pub struct GainSchedule {
    k0: Mat<f64>,
    k1: Mat<f64>,
    window: SamplingWindow,
}

impl GainSchedule {
    /// A constant gain `K` (Corollary 2, Remark 6).
    pub fn constant(k: MatRef<'_, f64>, window: SamplingWindow) -> Result<Self, Error> {
        Self::interpolated(k, k, window)
    }

    /// `K(τ)` interpolating `K0` at `τ_low` and `K1` at `τ̄` (Theorem 3). For a periodic window
    /// `K0` and `K1` must coincide (the interpolation is undefined, Remark 6).
    pub fn interpolated(
        k0: MatRef<'_, f64>,
        k1: MatRef<'_, f64>,
        window: SamplingWindow,
    ) -> Result<Self, Error> {
        if k0.nrows() == 0 || k0.ncols() == 0 {
            return Err(InputError::empty("gain K0").into());
        }
        check_shape(k1, k0.nrows(), k0.ncols(), "K1 (vs K0)")?;
        check_finite(k0, "K0")?;
        check_finite(k1, "K1")?;
        if window.is_periodic() && k0 != k1 {
            return Err(InputError::window("sampling window [τ_low, τ̄]", window.t1(), window.t2(), "a time-varying gain needs τ_low < τ̄ (Remark 6: periodic sampling uses a static gain)").into());
        }
        Ok(Self {
            k0: k0.to_owned(),
            k1: k1.to_owned(),
            window,
        })
    }

    /// `K0 = K(τ_low)`.
    pub fn k0(&self) -> MatRef<'_, f64> {
        self.k0.as_ref()
    }

    /// `K1 = K(τ̄)`.
    pub fn k1(&self) -> MatRef<'_, f64> {
        self.k1.as_ref()
    }

    /// The window on which the schedule is defined.
    pub fn window(&self) -> &SamplingWindow {
        &self.window
    }

    /// Whether the gain does not depend on `τ`.
    pub fn is_constant(&self) -> bool {
        self.k0 == self.k1
    }

    /// `K(τ)`; `τ` is clamped into `[τ_low, τ̄]` (the schedule is only defined there, and a
    /// measured interval may differ from the window ends by rounding).
    pub fn at(&self, tau: f64) -> Mat<f64> {
        let t = tau.clamp(self.window.t1(), self.window.t2());
        interpolate_checked(self.k0.as_ref(), self.k1.as_ref(), &self.window, t)
    }
}
