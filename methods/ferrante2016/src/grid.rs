//! Extrema over an interval of scalar functions of `e^{Av}`: a dense uniform grid (evaluated with
//! `sporadic_linalg::expm_stepper`) followed by a golden-section refinement of the best grid cell
//! (`sporadic_linalg::golden_section`).
//!
//! Used for the analysis constants of §4 (`α1`, `α2`, `β`, `max ‖e^{Av}‖²`), for the a-posteriori
//! verification of (12) and for the detectability precheck. These are *analysis* quantities: the grid
//! plus refinement finds the extremum to high accuracy for the smooth/piecewise-smooth functions that
//! occur, but it is not a rigorous global optimiser (the LMI certificate is what is rigorous).

use faer::{Mat, MatRef};
use sporadic_embed::Interval;
use sporadic_linalg::InputError;
use sporadic_linalg::{expm_scaled, expm_stepper, golden_section};

use crate::error::Error;
use sporadic_model::SamplingWindow;

/// `points` equally spaced inter-sample times covering `[T1, T2]` (both ends included; the single
/// point `T1` when the window is periodic or `points ≤ 1`).
pub(crate) fn window_grid(window: &SamplingWindow, points: usize) -> Result<Vec<f64>, Error> {
    Ok(Interval::new(window.t1(), window.t2())?.grid(points))
}

/// Whether the smallest or the largest value is sought.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Sense {
    /// Smallest value.
    Min,
    /// Largest value.
    Max,
}

/// An extremum and where it is attained.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Extremum {
    /// The extremal value.
    pub value: f64,
    /// The argument `v` attaining it.
    pub at: f64,
}

/// Number of golden-section iterations of the refinement (shrinks a grid cell by `0.618^60 ≈ 3e-13`).
const GOLDEN_STEPS: usize = 60;

/// Extremum of `v ↦ f(v, e^{Av})` over `[lo, hi]` (`lo ≤ hi`) from `points` equally spaced samples and
/// a golden-section refinement on the two grid cells around the best sample.
pub(crate) fn extremum<F>(
    a: MatRef<'_, f64>,
    lo: f64,
    hi: f64,
    points: usize,
    sense: Sense,
    mut f: F,
) -> Result<Extremum, Error>
where
    F: FnMut(f64, MatRef<'_, f64>) -> Result<f64, Error>,
{
    let grid = Interval::new(lo, hi)?.grid(points);
    let better = |x: f64, y: f64| match sense {
        Sense::Min => x < y,
        Sense::Max => x > y,
    };
    let n = a.nrows();
    let mut e = Mat::<f64>::zeros(n, n);
    let mut best = Extremum {
        value: f64::NAN,
        at: lo,
    };
    let mut best_k = 0usize;
    if grid.len() == 1 {
        let e = expm_scaled(a, lo)?;
        best.value = f(lo, e.as_ref())?;
    } else {
        let h = (hi - lo) / (grid.len() - 1) as f64;
        let mut stepper = expm_stepper(a, lo, h, grid.len() - 1)?;
        for (k, &v) in grid.iter().enumerate() {
            if stepper.next_into(e.as_mut()).is_none() {
                return Err(
                    InputError::non_finite(format!("e^(Av) on the grid at v = {v}")).into(),
                );
            }
            let value = f(v, e.as_ref())?;
            if !value.is_finite() {
                return Err(InputError::non_finite(format!("grid function at v = {v}")).into());
            }
            if k == 0 || better(value, best.value) {
                best = Extremum { value, at: v };
                best_k = k;
            }
        }
    }
    if !best.value.is_finite() {
        return Err(InputError::non_finite(format!("grid function at v = {}", best.at)).into());
    }
    if grid.len() > 1 {
        let left = grid[best_k.saturating_sub(1)];
        let right = grid[(best_k + 1).min(grid.len() - 1)];
        let sign = match sense {
            Sense::Min => 1.0,
            Sense::Max => -1.0,
        };
        let refined = golden_section(left, right, GOLDEN_STEPS, |v| {
            let e = expm_scaled(a, v)?;
            let value = f(v, e.as_ref())?;
            if value.is_finite() {
                Ok(sign * value)
            } else {
                Err(Error::from(InputError::non_finite(format!(
                    "grid function at v = {v}"
                ))))
            }
        })?;
        let value = sign * refined.value;
        if better(value, best.value) {
            best = Extremum {
                value,
                at: refined.at,
            };
        }
    }
    Ok(best)
}
