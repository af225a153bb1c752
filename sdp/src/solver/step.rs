//! Exact step lengths to the boundary of the cone.
//!
//! For a PSD block with `X = L Lᵀ`, `X + α ΔX ⪰ 0` iff `I + α L⁻¹ ΔX L⁻ᵀ ⪰ 0`, so the largest
//! feasible step is `−1/λ_min(L⁻¹ ΔX L⁻ᵀ)` when that eigenvalue is negative and unbounded
//! otherwise (SDPT3 `steplength.m` uses the same quantity, computed by Lanczos for large
//! blocks; we use a dense symmetric eigenvalue solver). For an LP block it is the ratio test
//! `min_{Δx_l < 0} −x_l / Δx_l`. The step actually taken is `min(1, γ·α_max)` with SDPT3's
//! adaptive fraction `γ = 0.9 + 0.09·min(α_p, α_d)` of the previous step lengths.
//!
//! A block whose `α_max` exceeds `1/γ` does not limit the step, and that is decided without an
//! eigenvalue: `λ_min(W) > −γ` iff `γ I + W` (`W = L⁻¹ ΔX L⁻ᵀ`) has a Cholesky factorisation.
//! Only the blocks failing that test — the ones that can bind — need `λ_min(W)`.

use faer::Mat;

use super::blockops::{cholesky, congruence, min_eig};
use super::small;
use super::structure::Analysis;
use crate::problem::BlockKind;

/// A block's step bound after the Cholesky tests.
enum Bound {
    /// Known `α_max` (LP ratio test, eigenvalue, or `∞` for a block that cannot bind).
    Known(f64),
    /// PSD block that may bind: `W = L⁻¹ ΔV L⁻ᵀ` and its smallest diagonal entry (an upper
    /// bound on `λ_min(W)`).
    Pending(Mat<f64>, f64),
}

/// Whether `shift·V + ΔV` has a Cholesky factorisation. For `V = L Lᵀ` this is congruent to
/// `shift·I + W` with `W = L⁻¹ ΔV L⁻ᵀ`, so it holds iff `λ_min(W) > −shift` (up to rounding):
/// then the block allows every step up to `1/shift`, decided without forming `W`.
fn allows(v: &Mat<f64>, dv: &Mat<f64>, shift: f64) -> bool {
    let n = v.nrows();
    if n <= small::SMALL {
        return small::with_bufs(n, |[buf]| {
            for j in 0..n {
                let (vj, dj) = (v.col_as_slice(j), dv.col_as_slice(j));
                for i in j..n {
                    buf[i + j * n] = shift * vj[i] + dj[i];
                }
            }
            small::cholesky_in_place(buf, n)
        });
    }
    let t = Mat::from_fn(n, n, |i, j| shift * v[(i, j)] + dv[(i, j)]);
    cholesky(&t).is_some()
}

/// `α_max = −1/λ_min(W)` (`∞` if `λ_min ≥ 0`, `NaN` if the eigenvalue computation failed).
fn exact_step(w: &Mat<f64>) -> f64 {
    let lam = min_eig(BlockKind::Psd, w);
    if lam.is_nan() {
        f64::NAN
    } else if lam < 0.0 {
        -1.0 / lam
    } else {
        f64::INFINITY
    }
}

/// Minimum with `NaN` propagation.
fn nan_min(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.min(b)
    }
}

/// The step `min(1, γ·α_max)` along `d` from the current point `cur`, given the inverse
/// Cholesky factors `linv` of its PSD blocks, where `α_max` is the largest `α ≥ 0` with
/// `V + α ΔV ⪰ 0`. Returns `0` if an eigenvalue computation failed.
///
/// Eigenvalues are computed only where needed: blocks with `λ_min(W) > −γ` cannot limit the
/// step; of the others, the one with the smallest diagonal of `W` (most likely to bind) gets
/// its exact `α`, and any other block then needs its eigenvalue only if it fails the Cholesky
/// test at that `α`. The result is the same as with an eigenvalue for every block, except
/// where a Cholesky test and the eigenvalue disagree by rounding at the boundary.
pub(crate) fn step_length(
    an: &Analysis,
    cur: &[Mat<f64>],
    linv: &[Mat<f64>],
    d: &[Mat<f64>],
    gamma: f64,
) -> f64 {
    let mut bounds: Vec<Bound> = an.map_blocks(|k, b| match b.kind {
        BlockKind::Lp => {
            let (x, dx) = (cur[k].col_as_slice(0), d[k].col_as_slice(0));
            let mut a = f64::INFINITY;
            for l in 0..x.len() {
                if dx[l] < 0.0 {
                    a = a.min(-x[l] / dx[l]);
                }
            }
            Bound::Known(a)
        }
        BlockKind::Psd => {
            if allows(&cur[k], &d[k], gamma) {
                Bound::Known(f64::INFINITY)
            } else {
                let w = congruence(&linv[k], &d[k]);
                let dmin = (0..w.nrows()).fold(f64::INFINITY, |m, i| m.min(w[(i, i)]));
                Bound::Pending(w, dmin)
            }
        }
    });
    let mut alpha = f64::INFINITY;
    let mut first: Option<(usize, f64)> = None;
    for (k, bound) in bounds.iter().enumerate() {
        match bound {
            Bound::Known(a) => alpha = nan_min(alpha, *a),
            Bound::Pending(_, dmin) => {
                if first.is_none_or(|(_, m)| *dmin < m) {
                    first = Some((k, *dmin));
                }
            }
        }
    }
    if let Some((k, _)) = first {
        if let Bound::Pending(w, _) = &bounds[k] {
            alpha = nan_min(alpha, exact_step(w));
        }
        bounds[k] = Bound::Known(f64::INFINITY);
        let threshold = alpha;
        let rest: Vec<f64> = an.exec.map(bounds.len(), |b| match &bounds[b] {
            Bound::Known(_) => f64::INFINITY,
            Bound::Pending(w, _) => {
                if threshold.is_finite()
                    && threshold > 0.0
                    && allows(&cur[b], &d[b], 1.0 / threshold)
                {
                    f64::INFINITY
                } else {
                    exact_step(w)
                }
            }
        });
        alpha = rest.into_iter().fold(alpha, nan_min);
    }
    if alpha.is_nan() {
        0.0
    } else {
        (gamma * alpha).min(1.0)
    }
}
