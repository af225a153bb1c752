//! e^{Aτ} on a uniform grid τ_k = τ0 + k·h by repeated multiplication with e^{Ah}.
//!
//! # Re-anchoring rule and error growth
//! Write E = e^{Ah}, Ê = E + ΔE its computed value (‖ΔE‖ ≤ ε‖E‖, ε the backward-error level
//! of [`crate::expm`], O(u) times the conditioning of e^{Ah}), and X̂_j the computed
//! e^{A(τ_a + jh)} j steps after an anchor τ_a. Since X̂_{j+1} = fl(X̂_j·Ê), the error
//! e_j = X̂_j − X_j obeys e_{j+1} = e_j·Ê + X_j·ΔE + F_j with ‖F_j‖ ≤ γ_n‖X̂_j‖‖Ê‖ (γ_n ≈ n·u,
//! Higham 2002, §3.5), hence, to first order,
//!
//! ‖e_j‖ ≤ ‖e_0‖·‖E^j‖ + j·(ε + γ_n)·max_{i ≤ j} ‖X_i‖·‖E^{j−i}‖ :
//!
//! the error grows linearly in the number of steps (times the transient-growth factor of
//! ‖E^k‖ for non-normal A). Every [`ExpmStepper::reanchor`] steps (default
//! [`DEFAULT_REANCHOR`]) the product is discarded and replaced by a fresh `expm(A·τ_k)`, so the
//! error never exceeds that of one direct evaluation plus `reanchor`·(ε + γ_n)·κ, where κ bounds
//! ‖X_i‖‖E^{j−i}‖/‖X_j‖ over one anchor interval (κ = 1 for normal A with ‖e^{At}‖
//! non-increasing). The tests check this against direct `expm` along 10⁵-step grids. One
//! re-anchor costs about (π_m + s + 4/3)/1 ≈ 8–20 products versus one product per step, i.e.
//! ≲ 8 % overhead at the default interval.
//!
//! `next_into` never allocates: all matrices live in buffers created by [`expm_stepper`]
//! (stack arrays for n ≤ 8).

use crate::InputError;
use faer::{Mat, MatMut, MatRef};

use crate::expm::storage::SquareStorage;
use crate::expm::{Driver, store, with_driver};
use crate::{LinalgError, check};

/// Default number of steps between re-anchorings: keeps the accumulated error below
/// ≈ 256·(ε + n·u) ≈ 2·10⁻¹³ for n ≤ 8 and well-conditioned A (see the module docs).
pub const DEFAULT_REANCHOR: usize = 256;

/// One storage backend: the step matrix, the running product and a ping-pong buffer.
trait StepKernel: Send {
    /// current ← e^{Aτ} by a fresh exponential.
    fn anchor(&mut self, a: MatRef<'_, f64>, tau: f64) -> Result<(), LinalgError>;
    /// step ← e^{Ah}.
    fn set_step(&mut self, a: MatRef<'_, f64>, h: f64) -> Result<(), LinalgError>;
    /// current ← current·step.
    fn advance(&mut self);
    /// out ← current; returns whether every entry is finite.
    fn write(&self, out: MatMut<'_, f64>) -> bool;
}

struct Kernel<D: Driver> {
    driver: D,
    step: D::M,
    current: D::M,
    next: D::M,
    arch: pulp::Arch,
}

/// current·step → next, run under pulp's runtime instruction-set dispatch (AVX2/FMA for the
/// stack kernels).
struct Advance<'a, M>(&'a mut M, &'a M, &'a M);

impl<M: SquareStorage> pulp::WithSimd for Advance<'_, M> {
    type Output = ();
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        self.0.assign_product(self.1, self.2);
    }
}

impl<D: Driver + Send> StepKernel for Kernel<D>
where
    D::M: Send,
{
    fn anchor(&mut self, a: MatRef<'_, f64>, tau: f64) -> Result<(), LinalgError> {
        self.driver.exp_of(a, tau)?;
        self.current.assign(self.driver.result());
        Ok(())
    }
    fn set_step(&mut self, a: MatRef<'_, f64>, h: f64) -> Result<(), LinalgError> {
        self.driver.exp_of(a, h)?;
        self.step.assign(self.driver.result());
        Ok(())
    }
    #[inline]
    fn advance(&mut self) {
        self.arch
            .dispatch(Advance(&mut self.next, &self.current, &self.step));
        std::mem::swap(&mut self.current, &mut self.next);
    }
    fn write(&self, out: MatMut<'_, f64>) -> bool {
        store(&self.current, out)
    }
}

fn new_kernel<D: Driver + Send + 'static>(n: usize) -> Box<dyn StepKernel>
where
    D::M: Send,
{
    Box::new(Kernel::<D> {
        driver: D::new(n),
        step: D::M::zeros(n),
        current: D::M::zeros(n),
        next: D::M::zeros(n),
        arch: pulp::Arch::new(),
    })
}

/// Iterator over e^{A(τ0 + kh)}, k = 0, …, `steps` (see the module docs for the error control).
///
/// Use [`ExpmStepper::next_into`] in hot loops (no allocation), or the [`Iterator`]
/// implementation (one `Mat` per item).
pub struct ExpmStepper {
    kernel: Box<dyn StepKernel>,
    a: Mat<f64>,
    tau0: f64,
    h: f64,
    steps: usize,
    k: usize,
    reanchor: usize,
    /// Steps left until the next re-anchoring.
    until_anchor: usize,
    error: Option<LinalgError>,
}

/// Creates an [`ExpmStepper`] for e^{A(τ0 + kh)}, k = 0..=`steps`, re-anchored every
/// [`DEFAULT_REANCHOR`] steps.
///
/// # Errors
/// Bad `a` (non-square, empty, non-finite), non-finite `tau0`/`h`, or a failure of the two
/// exponentials computed up front (e^{Aτ0}, e^{Ah}).
pub fn expm_stepper(
    a: MatRef<'_, f64>,
    tau0: f64,
    h: f64,
    steps: usize,
) -> Result<ExpmStepper, LinalgError> {
    let n = check::square_finite(a, "expm_stepper matrix A")?;
    check::finite_scalar(tau0, "expm_stepper start time tau0")?;
    check::finite_scalar(h, "expm_stepper step h")?;
    let end = tau0 + steps as f64 * h;
    check::finite_scalar(end, "expm_stepper end time tau0 + steps·h")?;
    let mut kernel = with_driver!(n, new_kernel(n));
    kernel.set_step(a, h)?;
    kernel.anchor(a, tau0)?;
    Ok(ExpmStepper {
        kernel,
        a: a.to_owned(),
        tau0,
        h,
        steps,
        k: 0,
        reanchor: DEFAULT_REANCHOR,
        until_anchor: DEFAULT_REANCHOR,
        error: None,
    })
}

impl ExpmStepper {
    /// Sets the re-anchoring interval (`usize::MAX` disables re-anchoring).
    ///
    /// # Errors
    /// [`LinalgError::InvalidArgument`] if `every` is 0.
    pub fn with_reanchor(mut self, every: usize) -> Result<Self, LinalgError> {
        if every == 0 {
            return Err(LinalgError::InvalidArgument(
                "expm_stepper: re-anchoring interval must be ≥ 1".into(),
            ));
        }
        self.reanchor = every;
        // Next re-anchoring at the first multiple of `every` among the grid indices still to
        // come (index k is produced by the next call; index 0 never needs one).
        self.until_anchor = if self.k == 0 {
            every
        } else {
            self.k.div_ceil(every) * every - self.k + 1
        };
        Ok(self)
    }

    /// The re-anchoring interval in steps.
    pub fn reanchor(&self) -> usize {
        self.reanchor
    }

    /// Order n of the matrices produced.
    pub fn order(&self) -> usize {
        self.a.nrows()
    }

    /// The error that stopped the iteration early (a re-anchoring exponential failed, the
    /// running product overflowed, or `out` had the wrong shape), if any.
    pub fn error(&self) -> Option<&LinalgError> {
        self.error.as_ref()
    }

    /// Writes the next e^{Aτ_k} into `out` (n×n) and returns τ_k = τ0 + k·h; `None` after the
    /// last grid point or on error (see [`ExpmStepper::error`]; `out` is then unspecified).
    /// Does not allocate.
    pub fn next_into(&mut self, out: MatMut<'_, f64>) -> Option<f64> {
        if self.k > self.steps || self.error.is_some() {
            return None;
        }
        let n = self.a.nrows();
        if out.nrows() != n || out.ncols() != n {
            let found = if out.nrows() != n {
                out.nrows()
            } else {
                out.ncols()
            };
            self.error =
                Some(InputError::mismatch("ExpmStepper::next_into output order", n, found).into());
            return None;
        }
        let tau = self.tau0 + self.k as f64 * self.h;
        if self.k > 0 {
            self.until_anchor -= 1;
            if self.until_anchor == 0 {
                self.until_anchor = self.reanchor;
                if let Err(e) = self.kernel.anchor(self.a.as_ref(), tau) {
                    self.error = Some(e);
                    return None;
                }
            } else {
                self.kernel.advance();
            }
        }
        if !self.kernel.write(out) {
            self.error = Some(LinalgError::overflow("ExpmStepper running product e^{Aτ}"));
            return None;
        }
        self.k += 1;
        Some(tau)
    }
}

impl Iterator for ExpmStepper {
    type Item = Mat<f64>;

    fn next(&mut self) -> Option<Mat<f64>> {
        let n = self.a.nrows();
        let mut m = Mat::zeros(n, n);
        self.next_into(m.as_mut())?;
        Some(m)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = if self.error.is_some() {
            0
        } else {
            (self.steps + 1).saturating_sub(self.k)
        };
        (0, Some(left))
    }
}
