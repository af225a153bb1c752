//! Extrema over an interval of scalar functions of `e^{Av}`: a dense uniform grid (evaluated with
//! `sporadic_linalg::expm_stepper`) followed by a golden-section refinement of the best grid cell
//! (`sporadic_linalg::golden_section`).
//!
//! Used for the analysis constants of §4 (`α1`, `α2`, `β`, `max ‖e^{Av}‖²`), for the a-posteriori
//! verification of (12) and for the detectability precheck. These are *analysis* quantities: the grid
//! plus refinement finds the extremum to high accuracy for the smooth/piecewise-smooth functions that
//! occur, but it is not a rigorous global optimiser (the LMI certificate is what is rigorous).
//!
//! **Long windows** (issue 22). For a Hurwitz `A` with spectral abscissa `α < 0`, every mode
//! has decayed by `e^{−DECAY_EXPONENTS}` (far below rounding) at `v − T1 =`
//! [`decay_horizon`]` = DECAY_EXPONENTS/|α|` — a similarity-invariant, time-covariant length
//! (it scales as `1/k` under `A → kA`). Beyond `S = T1 + decay_horizon`, `e^{Av}` is
//! negligible and varies only on a logarithmic scale, so a window `[T1, T2]` with `T2 > S` is
//! sampled uniformly on `[T1, S]` (where `e^{Av}` varies) and geometrically on `[S, T2]`
//! ([`split_point`], [`tail_grid`]): an equally spaced grid on `[1, 10¹⁵]` would have its first
//! point after `T1` at `3.6·10¹¹` and miss everything. Windows with `T2 ≤ S` (and every plant
//! that is not Hurwitz) keep the uniform grid.
use faer::{Mat, MatRef};
use sporadic_embed::Interval;
use sporadic_linalg::{InputError, LinalgError};
use sporadic_linalg::{expm_scaled, expm_stepper, golden_section};

use crate::error::Error;
use sporadic_model::SamplingWindow;

// The decay exponents of `decay_horizon` are the embedding's own: its self-check grid ends at
// the same horizon.
pub use sporadic_embed::DECAY_EXPONENTS;

/// `DECAY_EXPONENTS/|α|` for a Hurwitz `A` with spectral abscissa `α = max Re λ(A) < 0`; `None`
/// when `A` is not Hurwitz (or its eigenvalues cannot be computed).
pub(crate) fn decay_horizon(a: MatRef<'_, f64>) -> Option<f64> {
    let lambdas = a.eigenvalues().ok()?;
    let alpha = lambdas
        .iter()
        .map(|l| l.re)
        .fold(f64::NEG_INFINITY, f64::max);
    let h = DECAY_EXPONENTS / -alpha;
    (alpha < 0.0 && h.is_finite()).then_some(h)
}

/// `T1 + decay_horizon` when it lies inside `(lo, hi)` (the window is longer than the decay
/// of every mode; see the module docs), `None` otherwise.
pub(crate) fn split_point(a: MatRef<'_, f64>, lo: f64, hi: f64) -> Option<f64> {
    let s = lo + decay_horizon(a)?;
    (s > lo && s < hi).then_some(s)
}

/// Geometrically spaced points from `s` to `hi` (`0 < s < hi`, both included): four per
/// factor of two, at most `points` (at least two).
pub(crate) fn tail_grid(s: f64, hi: f64, points: usize) -> Vec<f64> {
    let octaves = (hi / s).log2();
    let steps = ((4.0 * octaves).ceil() as usize).clamp(1, points.max(2) - 1);
    let ratio = (hi / s).ln() / steps as f64;
    (0..=steps)
        .map(|i| {
            if i == steps {
                hi
            } else {
                s * (ratio * i as f64).exp()
            }
        })
        .collect()
}

/// Largest `‖A‖_max·v` for which [`expm_far`] calls the exponential directly (`2³⁰`: the
/// scaling and squaring inside the exponential then stays well within its accuracy).
const DIRECT_EXPONENT: f64 = 1_073_741_824.0;

/// Largest number of squarings of [`expm_far`] (enough for `‖A‖_max·v` up to the largest
/// double).
const MAX_SQUARINGS: usize = 1100;

/// `e^{Av}` also where `v·A` overflows or the exponential's own scaling and squaring would lose
/// its accuracy (a point of the geometric tail of a long window, e.g. `v = 10³⁰⁰`):
/// `(e^{Av/2^j})^{2^j}` with the fewest halvings `j` that bring `‖A‖_max v/2^j` below
/// [`DIRECT_EXPONENT`] (none on an ordinary window, where this is the exponential itself).
pub(crate) fn expm_far(a: MatRef<'_, f64>, v: f64) -> Result<Mat<f64>, Error> {
    let norm = a.norm_max();
    let mut w = v;
    let mut squarings = 0;
    while norm * w > DIRECT_EXPONENT && squarings < MAX_SQUARINGS {
        w *= 0.5;
        squarings += 1;
    }
    let mut e = expm_scaled(a, w)?;
    for _ in 0..squarings {
        e = &e * &e;
        if !e.is_all_finite() {
            return Err(LinalgError::Overflow {
                what: format!("e^(Av) at v = {v} exceeds the double-precision range"),
            }
            .into());
        }
    }
    Ok(e)
}

/// The inter-sample times tested by the detectability precheck on `[T1, T2]`: `points` equally
/// spaced ones (both ends included; the single point `T1` when the window is periodic or
/// `points ≤ 1`), on `[T1, S]` followed by a geometric tail on `[S, T2]` when the window is
/// longer than the decay of every mode of `a` (see the module docs).
pub(crate) fn window_grid(
    a: MatRef<'_, f64>,
    window: &SamplingWindow,
    points: usize,
) -> Result<Vec<f64>, Error> {
    let (t1, t2) = (window.t1(), window.t2());
    Ok(match split_point(a, t1, t2) {
        Some(s) => {
            let mut grid = Interval::new(t1, s)?.grid(points);
            grid.extend(tail_grid(s, t2, points).into_iter().skip(1));
            grid
        }
        None => Interval::new(t1, t2)?.grid(points),
    })
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
/// a golden-section refinement on the two grid cells around the best sample; on a window
/// longer than the decay of every mode, the uniform samples cover `[lo, S]` and a geometric
/// grid covers `[S, hi]` (see the module docs).
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
    let Some(s) = split_point(a, lo, hi) else {
        return uniform_extremum(a, lo, hi, points, sense, &mut f);
    };
    let head = uniform_extremum(a, lo, s, points, sense, &mut f)?;
    let grid = tail_grid(s, hi, points);
    let mut tail = Extremum {
        value: f64::NAN,
        at: s,
    };
    let mut best_k = 0usize;
    for (k, &v) in grid.iter().enumerate() {
        let e = expm_far(a, v)?;
        let value = f(v, e.as_ref())?;
        if !value.is_finite() {
            return Err(InputError::non_finite(format!("grid function at v = {v}")).into());
        }
        if k == 0 || sense.better(value, tail.value) {
            tail = Extremum { value, at: v };
            best_k = k;
        }
    }
    let tail = refine(a, &grid, best_k, tail, sense, &mut f)?;
    Ok(if sense.better(tail.value, head.value) {
        tail
    } else {
        head
    })
}

impl Sense {
    /// Whether `x` is better than `y`.
    fn better(self, x: f64, y: f64) -> bool {
        match self {
            Sense::Min => x < y,
            Sense::Max => x > y,
        }
    }
}

/// Golden-section refinement on the two cells of `grid` around its best point `best_k`.
fn refine<F>(
    a: MatRef<'_, f64>,
    grid: &[f64],
    best_k: usize,
    best: Extremum,
    sense: Sense,
    f: &mut F,
) -> Result<Extremum, Error>
where
    F: FnMut(f64, MatRef<'_, f64>) -> Result<f64, Error>,
{
    if grid.len() < 2 {
        return Ok(best);
    }
    let left = grid[best_k.saturating_sub(1)];
    let right = grid[(best_k + 1).min(grid.len() - 1)];
    let sign = match sense {
        Sense::Min => 1.0,
        Sense::Max => -1.0,
    };
    let refined = golden_section(left, right, GOLDEN_STEPS, |v| {
        let e = expm_far(a, v)?;
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
    Ok(if sense.better(value, best.value) {
        Extremum {
            value,
            at: refined.at,
        }
    } else {
        best
    })
}

/// [`extremum`] on a uniform grid of `[lo, hi]`.
fn uniform_extremum<F>(
    a: MatRef<'_, f64>,
    lo: f64,
    hi: f64,
    points: usize,
    sense: Sense,
    f: &mut F,
) -> Result<Extremum, Error>
where
    F: FnMut(f64, MatRef<'_, f64>) -> Result<f64, Error>,
{
    let grid = Interval::new(lo, hi)?.grid(points);
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
            if k == 0 || sense.better(value, best.value) {
                best = Extremum { value, at: v };
                best_k = k;
            }
        }
    }
    if !best.value.is_finite() {
        return Err(InputError::non_finite(format!("grid function at v = {}", best.at)).into());
    }
    refine(a, &grid, best_k, best, sense, f)
}
