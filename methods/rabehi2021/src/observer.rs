//! The interval impulsive observer of Rabehi et al. (2021), §III: an open-loop interval predictor
//! between samples (4) and an impulsive correction at every measurement (8).
//!
//! ```text
//! flow (4):   ẋ̲ = A^M x̲ − A^N x̄ + Bu + d̲,        ẋ̄ = A^M x̄ − A^N x̲ + Bu + d̄,
//! jump (8):   x̲⁺ = G⁺x̲ − G⁻x̄ − |L|v̄ − Ly,        x̄⁺ = G⁺x̄ − G⁻x̲ + |L|v̄ − Ly,      G = I + LC.
//! ```
//!
//! The errors `e̲ = x − x̲`, `ē = x̄ − x` then obey `ξ̇ = Āξ + Ξ(t)` (6) with `Ξ ≥ 0`, and
//! `ξ⁺ = Γ(L)ξ + Υ` (9) with `Γ(L) ≥ 0`, `Υ = [|L|v̄ + Lv; |L|v̄ − Lv] ≥ 0`: since `Ā` is Metzler,
//! the order `x̲ ≤ x ≤ x̄` survives every flow and every jump, for **any** gain `L`. Stability of
//! the interval (its width staying bounded) is what Theorem 1 adds.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite_slice;
use sporadic_sim::{Flow, InputSignal, LtiFlow, Observer, SampleEvent, SimError};

use crate::error::Error;
use crate::ipr::{MetzlerDecomposition, abs, negative_part, positive_part, reset_matrix};
use crate::system::{Bounds, Plant};

/// The observer data: plant, bounds, gain and the derived matrices of (4) and (8).
#[derive(Debug, Clone)]
pub struct IntervalObserver {
    plant: Plant,
    bounds: Bounds,
    decomposition: MetzlerDecomposition,
    l: Mat<f64>,
    g_plus: Mat<f64>,
    g_minus: Mat<f64>,
    /// `|L|v̄`.
    noise_shift: Vec<f64>,
}

impl IntervalObserver {
    /// Builds the observer for `plant`, `bounds` and the gain `L` (`n × p`).
    ///
    /// # Errors
    /// Dimension mismatches between plant, bounds and gain, or non-finite `L`.
    pub fn new(plant: &Plant, bounds: &Bounds, l: MatRef<'_, f64>) -> Result<Self, Error> {
        bounds.check_against(plant)?;
        let g = reset_matrix(plant, l)?;
        let abs_l = abs(l);
        let noise_shift = (0..plant.n())
            .map(|i| {
                (0..plant.p())
                    .map(|k| abs_l[(i, k)] * bounds.v_bar()[k])
                    .sum()
            })
            .collect();
        Ok(Self {
            plant: plant.clone(),
            bounds: bounds.clone(),
            decomposition: MetzlerDecomposition::new(plant.a())?,
            l: l.to_owned(),
            g_plus: positive_part(g.as_ref()),
            g_minus: negative_part(g.as_ref()),
            noise_shift,
        })
    }

    /// The plant.
    pub fn plant(&self) -> &Plant {
        &self.plant
    }

    /// The bounds of Assumptions 2–3 the observer uses.
    pub fn bounds(&self) -> &Bounds {
        &self.bounds
    }

    /// The gain `L`.
    pub fn gain(&self) -> MatRef<'_, f64> {
        self.l.as_ref()
    }

    /// `A^M`, `A^N`, `Ā`.
    pub fn decomposition(&self) -> &MetzlerDecomposition {
        &self.decomposition
    }

    /// `G⁺` and `G⁻` of `G = I + LC`.
    pub fn reset_parts(&self) -> (MatRef<'_, f64>, MatRef<'_, f64>) {
        (self.g_plus.as_ref(), self.g_minus.as_ref())
    }

    /// The state matrix of (4) acting on `(x̲, x̄)`: `[[A^M, −A^N], [−A^N, A^M]]`.
    pub fn flow_matrix(&self) -> Mat<f64> {
        let n = self.plant.n();
        let (am, an) = (&self.decomposition.a_m, &self.decomposition.a_n);
        Mat::from_fn(2 * n, 2 * n, |i, j| {
            let (r, c) = (i % n, j % n);
            if (i < n) == (j < n) {
                am[(r, c)]
            } else {
                -an[(r, c)]
            }
        })
    }

    /// The flow (4) as an exactly propagated LTI flow of `(x̲, x̄)`, with the known input `u`
    /// (`None` for `m = 0` or `u ≡ 0`) entering both bounds through `B`, and the constant terms
    /// `(d̲, d̄)`.
    ///
    /// # Errors
    /// An input signal whose dimension is not `m`.
    pub fn flow(&self, input: Option<InputSignal>) -> Result<LtiFlow, Error> {
        let n = self.plant.n();
        let mut flow = LtiFlow::new(self.flow_matrix().as_ref())?;
        if let Some(u) = input {
            let b = self.plant.b();
            let bb = Mat::from_fn(2 * n, b.ncols(), |i, k| b[(i % n, k)]);
            flow = flow.with_input(bb.as_ref(), u)?;
        }
        let affine: Vec<f64> = self
            .bounds
            .d_lower()
            .iter()
            .chain(self.bounds.d_upper())
            .copied()
            .collect();
        Ok(flow.with_affine(affine)?)
    }

    /// The correction (8): overwrites `lower`, `upper` (pre-jump bounds) with the post-jump bounds
    /// for the measurement `y`.
    ///
    /// # Errors
    /// Wrong lengths (`n`, `n`, `p`) or non-finite `y`.
    pub fn correct(&self, lower: &mut [f64], upper: &mut [f64], y: &[f64]) -> Result<(), Error> {
        let (n, p) = (self.plant.n(), self.plant.p());
        if lower.len() != n || upper.len() != n {
            return Err(InputError::mismatch(
                "length of the bounds (= n)",
                n,
                if lower.len() != n {
                    lower.len()
                } else {
                    upper.len()
                },
            )
            .into());
        }
        if y.len() != p {
            return Err(
                InputError::mismatch("length of the measurement y (= p)", p, y.len()).into(),
            );
        }
        check_finite_slice(y, "measurement y")?;
        let (gp, gm) = (&self.g_plus, &self.g_minus);
        let mut new_lower = vec![0.0; n];
        let mut new_upper = vec![0.0; n];
        for i in 0..n {
            let ly: f64 = (0..p).map(|k| self.l[(i, k)] * y[k]).sum();
            let (mut lo, mut hi) = (0.0, 0.0);
            for j in 0..n {
                lo += gp[(i, j)] * lower[j] - gm[(i, j)] * upper[j];
                hi += gp[(i, j)] * upper[j] - gm[(i, j)] * lower[j];
            }
            new_lower[i] = lo - self.noise_shift[i] - ly;
            new_upper[i] = hi + self.noise_shift[i] - ly;
        }
        lower.copy_from_slice(&new_lower);
        upper.copy_from_slice(&new_upper);
        Ok(())
    }

    /// The observer with its flow, ready for `sporadic_sim::simulate` (state `(x̲, x̄)`).
    ///
    /// # Errors
    /// As [`IntervalObserver::flow`].
    pub fn hybrid(&self, input: Option<InputSignal>) -> Result<HybridIntervalObserver, Error> {
        Ok(HybridIntervalObserver {
            flow: self.flow(input)?,
            observer: self.clone(),
        })
    }
}

/// The interval observer as a `sporadic_sim::Observer` (state `(x̲, x̄) ∈ R^{2n}`).
#[derive(Debug, Clone)]
pub struct HybridIntervalObserver {
    flow: LtiFlow,
    observer: IntervalObserver,
}

impl Observer for HybridIntervalObserver {
    fn flow(&self) -> &dyn Flow {
        &self.flow
    }

    fn jump(&mut self, _ev: &SampleEvent, y: &[f64], xhat: &mut [f64]) -> Result<(), SimError> {
        let n = self.observer.plant.n();
        let (lower, upper) = xhat.split_at_mut(n);
        self.observer
            .correct(lower, upper, y)
            .map_err(|e| SimError::InvalidArgument(format!("interval correction (8): {e}")))
    }
}
