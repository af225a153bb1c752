//! The plant with `N` round-robin sensors (§2.1 and the hybrid model (9)).
//!
//! # Indexing convention
//!
//! Sensors are indexed from 0 in the Rust API; the paper's `σ ∈ {1, …, N}` is `index + 1` (error
//! messages and reports print the 1-based form). The round-robin successor (2) is
//! `Γ(σ) = σ + 1 mod N` ([`RoundRobinPlant::next`]).
//!
//! Following the hybrid model (9) and every theorem of the paper (the wording of (4) and
//! Definition 1 says the opposite, a typo): in mode σ the timer `τ` measures the time since
//! the previous sample, which came from sensor `σ − 1` (cyclically), and **sensor σ is read when
//! `τ ∈ [T_mσ, T_Mσ]`**. The window of sensor σ therefore bounds the interval *before* its sample.

use faer::{Mat, MatRef};
use sporadic_embed::Interval;
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite;
use sporadic_linalg::null_space;
use sporadic_model::SamplingWindow;

use crate::error::Error;

/// The values `T_mσ, …, T_Mσ` of `points` equally spaced sampling intervals of `window` (both ends
/// included; the single point `T_mσ` for a periodic window or `points < 2`), by
/// [`sporadic_embed::Interval::grid`].
///
/// # Errors
/// None for a valid [`SamplingWindow`] (the interval helper's checks are run anyway).
pub fn window_grid(window: SamplingWindow, points: usize) -> Result<Vec<f64>, Error> {
    Ok(Interval::new(window.t1(), window.t2())?.grid(points))
}

/// Whether the interval `tau` lies in `window` (`T_mσ ≤ τ ≤ T_Mσ`).
pub fn window_contains(window: SamplingWindow, tau: f64) -> bool {
    window.t1() <= tau && tau <= window.t2()
}

/// One sensor: output matrix `C_σ` (full row rank, Assumption 1), its sampling window
/// `[T_mσ, T_Mσ]` (Assumption 2: the admissible values of the time elapsed since the previous sample
/// when this sensor's sample arrives) and a basis `C_σ^⊥` of `ker C_σ` (orthonormal unless supplied
/// by the user with [`RoundRobinPlant::with_complement`]; the gains (45) do not depend on the choice).
#[derive(Debug, Clone)]
pub struct Sensor {
    c: Mat<f64>,
    window: SamplingWindow,
    c_perp: Mat<f64>,
}

impl Sensor {
    /// Output matrix `C_σ` (`m_σ × n`).
    pub fn c(&self) -> MatRef<'_, f64> {
        self.c.as_ref()
    }
    /// Sampling window `[T_mσ, T_Mσ]`.
    pub fn window(&self) -> SamplingWindow {
        self.window
    }
    /// Basis `C_σ^⊥` of `ker C_σ` (`n × (n − m_σ)`), `C_σ C_σ^⊥ = 0`.
    pub fn c_perp(&self) -> MatRef<'_, f64> {
        self.c_perp.as_ref()
    }
    /// Number of outputs `m_σ`.
    pub fn outputs(&self) -> usize {
        self.c.nrows()
    }
}

/// Plant (1) `ẋ = Ax + Bu + d` with `N` sensors sampled in round-robin order (2).
///
/// The known input `u` cancels in the estimation error, so only `A` and the sensors are stored.
/// For the continuous-output extension of Remark 1, pass `A_0 − L_c C_c` as `A`.
#[derive(Debug, Clone)]
pub struct RoundRobinPlant {
    a: Mat<f64>,
    sensors: Vec<Sensor>,
}

impl RoundRobinPlant {
    /// Builds the plant from `A` (`n × n`) and the sensors `(C_σ, window_σ)` in round-robin order.
    /// Each `C_σ^⊥` is the orthonormal basis of `ker C_σ` returned by
    /// [`sporadic_linalg::null_space`].
    ///
    /// # Errors
    /// Empty sensor list, non-square or non-finite `A`, `C_σ` with the wrong number of columns or
    /// rank-deficient ([`Error::RankDeficientOutput`]).
    pub fn new(
        a: MatRef<'_, f64>,
        sensors: &[(MatRef<'_, f64>, SamplingWindow)],
    ) -> Result<Self, Error> {
        let n = a.nrows();
        if a.ncols() != n {
            return Err(InputError::mismatch("columns of A", n, a.ncols()).into());
        }
        if n == 0 {
            return Err(InputError::empty("A").into());
        }
        check_finite(a, "A")?;
        if sensors.is_empty() {
            return Err(InputError::empty("round-robin sensors").into());
        }
        let mut out = Vec::with_capacity(sensors.len());
        for (k, &(c, window)) in sensors.iter().enumerate() {
            let sigma = k + 1;
            if c.ncols() != n {
                return Err(
                    InputError::mismatch(format!("columns of C_{sigma}"), n, c.ncols()).into(),
                );
            }
            if c.nrows() == 0 {
                return Err(InputError::empty(format!("C_{sigma}")).into());
            }
            check_finite(c, &format!("C_{sigma}"))?;
            let c_perp = null_space(c)?;
            let rank = n - c_perp.ncols();
            if rank < c.nrows() {
                return Err(Error::RankDeficientOutput {
                    sigma,
                    rank,
                    rows: c.nrows(),
                });
            }
            out.push(Sensor {
                c: c.to_owned(),
                window,
                c_perp,
            });
        }
        Ok(Self {
            a: a.to_owned(),
            sensors: out,
        })
    }

    /// Replaces `C_σ^⊥` (0-based `sigma`) by a user basis of `ker C_σ`, e.g. the example's choice in §6.
    /// Feasibility of (23)/(44) and the gains (45) do not depend on the choice (Remark 2), but the
    /// μ-margins of (47) do.
    ///
    /// # Errors
    /// Wrong shape, non-finite entries, `C_σ C_σ^⊥ ≠ 0` or `[C_σ^⊥ C_σᵀ]` singular
    /// ([`Error::InvalidComplement`]).
    pub fn with_complement(mut self, sigma: usize, c_perp: MatRef<'_, f64>) -> Result<Self, Error> {
        let n = self.n();
        let s = self.sensor(sigma)?;
        let m = s.outputs();
        if c_perp.nrows() != n || c_perp.ncols() != n - m {
            return Err(Error::InvalidComplement {
                sigma: sigma + 1,
                reason: format!(
                    "shape {}×{}, expected {}×{}",
                    c_perp.nrows(),
                    c_perp.ncols(),
                    n,
                    n - m
                ),
            });
        }
        check_finite(c_perp, "C^⊥")?;
        let prod = &s.c * c_perp;
        let scale = s.c.norm_l2() * c_perp.norm_l2();
        if prod.norm_l2() > 1e-10 * scale.max(f64::MIN_POSITIVE) {
            return Err(Error::InvalidComplement {
                sigma: sigma + 1,
                reason: format!("‖C C^⊥‖_F = {:.3e}", prod.norm_l2()),
            });
        }
        let full = Mat::from_fn(n, n, |i, j| {
            if j < n - m {
                c_perp[(i, j)]
            } else {
                s.c[(j - (n - m), i)]
            }
        });
        let sv = full
            .singular_values()
            .map_err(|_| Error::numerical("SVD of [C^⊥ Cᵀ] did not converge"))?;
        let (smax, smin) = (sv[0], sv[n - 1]);
        if smin <= 1e-12 * smax {
            return Err(Error::InvalidComplement {
                sigma: sigma + 1,
                reason: format!("[C^⊥ Cᵀ] is singular (σ_min/σ_max = {:.3e})", smin / smax),
            });
        }
        self.sensors[sigma].c_perp = c_perp.to_owned();
        Ok(self)
    }

    /// State dimension `n`.
    pub fn n(&self) -> usize {
        self.a.nrows()
    }
    /// Number of sensors `N`.
    pub fn num_sensors(&self) -> usize {
        self.sensors.len()
    }
    /// The flow matrix `A`.
    pub fn a(&self) -> MatRef<'_, f64> {
        self.a.as_ref()
    }
    /// Sensor `sigma` (0-based).
    ///
    /// # Errors
    /// [`Error::NoSuchSensor`] when `sigma ≥ N`.
    pub fn sensor(&self, sigma: usize) -> Result<&Sensor, Error> {
        self.sensors.get(sigma).ok_or(Error::NoSuchSensor {
            index: sigma,
            sensors: self.sensors.len(),
        })
    }
    /// All sensors in round-robin order.
    pub fn sensors(&self) -> &[Sensor] {
        &self.sensors
    }
    /// Round-robin successor `Γ(σ)` of (2), 0-based.
    pub fn next(&self, sigma: usize) -> usize {
        (sigma + 1) % self.sensors.len()
    }
    /// `T_M = max_σ T_Mσ`.
    pub fn t_max(&self) -> f64 {
        self.sensors
            .iter()
            .map(|s| s.window.t2())
            .fold(f64::NEG_INFINITY, f64::max)
    }
    /// `T_m = min_σ T_mσ`.
    pub fn t_min(&self) -> f64 {
        self.sensors
            .iter()
            .map(|s| s.window.t1())
            .fold(f64::INFINITY, f64::min)
    }
    /// Jitter-free scenario of Definition 1 (every window is a single point).
    pub fn is_jitter_free(&self) -> bool {
        self.sensors.iter().all(|s| s.window.is_periodic())
    }
    /// The same windows with other matrices: `A` and one `C_σ` per sensor (the plant in other
    /// state coordinates), orthonormal complements computed afresh.
    ///
    /// # Errors
    /// Those of [`RoundRobinPlant::new`], or a number of `C_σ` other than `N`.
    pub fn with_matrices(&self, a: MatRef<'_, f64>, cs: &[Mat<f64>]) -> Result<Self, Error> {
        if cs.len() != self.num_sensors() {
            return Err(InputError::mismatch("number of C_σ", self.num_sensors(), cs.len()).into());
        }
        let sensors: Vec<_> = cs
            .iter()
            .zip(&self.sensors)
            .map(|(c, s)| (c.as_ref(), s.window))
            .collect();
        Self::new(a, &sensors)
    }

    /// The same sensors with other windows (e.g. a jitter-free instance `T_σ` inside each window).
    ///
    /// # Errors
    /// Wrong number of windows.
    pub fn with_windows(&self, windows: &[SamplingWindow]) -> Result<Self, Error> {
        if windows.len() != self.num_sensors() {
            return Err(InputError::mismatch(
                "number of windows",
                self.num_sensors(),
                windows.len(),
            )
            .into());
        }
        let mut out = self.clone();
        for (s, w) in out.sensors.iter_mut().zip(windows) {
            s.window = *w;
        }
        Ok(out)
    }
}

/// Shorthands of the unit tests.
#[cfg(test)]
pub(crate) mod test_util {
    use super::*;

    /// A valid window.
    pub(crate) fn win(t1: f64, t2: f64) -> SamplingWindow {
        SamplingWindow::new(t1, t2).unwrap()
    }

    /// [`RoundRobinPlant::new`] from owned matrices.
    pub(crate) fn rr(
        a: Mat<f64>,
        sensors: Vec<(Mat<f64>, SamplingWindow)>,
    ) -> Result<RoundRobinPlant, Error> {
        let s: Vec<_> = sensors.iter().map(|(c, w)| (c.as_ref(), *w)).collect();
        RoundRobinPlant::new(a.as_ref(), &s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    use crate::plant::test_util::{rr, win};

    fn plant() -> RoundRobinPlant {
        let a = mat![[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, -2.0, -3.0]];
        rr(
            a,
            vec![
                (mat![[1.0, 0.0, 0.0]], win(0.1, 0.2)),
                (mat![[0.0, 1.0, 1.0], [1.0, 0.0, 0.0]], win(0.3, 0.3)),
            ],
        )
        .unwrap()
    }

    /// Sensors are looked up by 0-based index; an index past the last sensor is a typed error
    /// naming the index and the number of sensors (it used to panic).
    #[test]
    fn sensor_lookup() {
        let p = plant();
        assert_eq!(p.sensor(1).unwrap().outputs(), 2);
        assert_eq!(p.sensor(0).unwrap().window(), win(0.1, 0.2));
        let err = p.sensor(2).unwrap_err();
        assert!(
            matches!(
                err,
                Error::NoSuchSensor {
                    index: 2,
                    sensors: 2
                }
            ),
            "{err:?}"
        );
        assert_eq!(
            err.to_string(),
            "no sensor with index 2 (0-based): the plant has 2 sensors"
        );
        assert!(matches!(
            p.with_complement(5, Mat::zeros(3, 2).as_ref()),
            Err(Error::NoSuchSensor {
                index: 5,
                sensors: 2
            })
        ));
    }

    #[test]
    fn complements_are_orthonormal_kernel_bases() {
        let p = plant();
        for s in p.sensors() {
            let cp = s.c_perp();
            assert_eq!(cp.ncols(), 3 - s.outputs());
            let ccp = s.c() * cp;
            assert!(ccp.norm_max() < 1e-14);
            let g = cp.transpose() * cp;
            for i in 0..g.nrows() {
                for j in 0..g.ncols() {
                    let e = if i == j { 1.0 } else { 0.0 };
                    assert!((g[(i, j)] - e).abs() < 1e-14);
                }
            }
        }
        assert_eq!(p.next(0), 1);
        assert_eq!(p.next(1), 0);
        assert_eq!(p.t_max(), 0.3);
        assert_eq!(p.t_min(), 0.1);
        assert!(!p.is_jitter_free());
    }

    #[test]
    fn bad_inputs_are_typed_errors() {
        let a = mat![[0.0, 1.0], [0.0, 0.0]];
        let e = rr(
            a.clone(),
            vec![(mat![[1.0, 0.0], [2.0, 0.0]], win(0.1, 0.1))],
        );
        assert!(matches!(
            e,
            Err(Error::RankDeficientOutput {
                sigma: 1,
                rank: 1,
                rows: 2
            })
        ));
        assert!(SamplingWindow::new(0.2, 0.1).is_err());
        assert!(SamplingWindow::new(0.0, 0.1).is_err());
        let e = rr(a.clone(), vec![(mat![[1.0, f64::NAN]], win(0.1, 0.1))]);
        assert!(matches!(e, Err(Error::Input(InputError::NonFinite { .. }))));
        let e = rr(a.clone(), vec![(mat![[1.0, 0.0, 0.0]], win(0.1, 0.1))]);
        assert!(matches!(
            e,
            Err(Error::Input(InputError::DimensionMismatch { .. }))
        ));
        let e = rr(a.clone(), vec![]);
        assert!(matches!(e, Err(Error::Input(InputError::Empty { .. }))));
        let p = rr(a, vec![(mat![[1.0, 0.0]], win(0.1, 0.1))]).unwrap();
        let e = p.clone().with_complement(0, mat![[1.0], [0.0]].as_ref());
        assert!(matches!(e, Err(Error::InvalidComplement { sigma: 1, .. })));
        let p2 = p.with_complement(0, mat![[0.0], [-2.0]].as_ref()).unwrap();
        assert_eq!(p2.sensor(0).unwrap().c_perp()[(1, 0)], -2.0);
    }
}
