//! Step lengths to the boundary of the cone.
//!
//! For a PSD block with `X = L Lᵀ`, `X + α ΔX ⪰ 0` iff `I + α L⁻¹ ΔX L⁻ᵀ ⪰ 0`, so the largest
//! feasible step is `−1/λ_min(L⁻¹ ΔX L⁻ᵀ)` when that eigenvalue is negative and unbounded
//! otherwise (SDPT3 `steplength.m` uses the same quantity). For an LP block it is the ratio test
//! `min_{Δx_l < 0} −x_l / Δx_l`. The step actually taken is `min(1, γ·α_max)` with SDPT3's
//! adaptive fraction `γ = 0.9 + 0.09·min(α_p, α_d)` of the previous step lengths.
//!
//! Blocks below order [`LANCZOS_FROM`] get the exact eigenvalue, and only where needed: a block
//! whose `α_max` exceeds `1/γ` does not limit the step, and that is decided without an
//! eigenvalue: `λ_min(W) > −γ` iff `γ I + W` (`W = L⁻¹ ΔX L⁻ᵀ`) has a Cholesky factorisation.
//! Only the blocks failing that test — the ones that can bind — need `λ_min(W)`. Larger blocks
//! get a bound on `−λ_min(W)` from Lanczos steps with `W` applied to vectors, as SDPT3 does
//! ([`super::lanczos`]): `O(kn²)` for about 30 steps instead of the `O(n³)` of forming `W` and
//! reducing it. Unlike SDPT3 the step that is taken (the corrector's) is then confirmed by the
//! Cholesky test (a start vector nearly orthogonal to the extreme eigenvector makes Lanczos
//! converge to the next eigenvalue first; where the test fails the exact eigenvalue decides);
//! the predictor's steps, which only set the centring parameter, are not confirmed.
//!
//! Measured against the exact steps on the SDPLIB problems with a block of order 200 or more
//! (theta4–6, mcp250-1, gpp250-1, mcp500-1–4, gpp500-1–4, maxG11, thetaG11, qpG11, maxG51,
//! maxG32; whole process, one run each, back to back): the same status and iteration count on
//! each, objectives equal to 9–11 digits; time 3–8 % lower on theta4–6, 16–35 % on the others
//! but mcp500-1 (5 %): maxG11 7.17 → 4.98 s, qpG11 41.5 → 28.4 s, maxG32 85.6 → 56.0 s.

use faer::linalg::matmul::triangular::{BlockStructure, matmul as tri_matmul};
use faer::{Accum, Mat, MatMut, MatRef, Par};

use super::blockops::{cholesky_in_place, congruence, min_eig, min_eig_in_place};
use super::lanczos::largest_eigenvalue_bound;
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
    let mut t = Mat::from_fn(n, n, |i, j| shift * v[(i, j)] + dv[(i, j)]);
    cholesky_in_place(&mut t)
}

/// `α_max = −1/λ_min` for the smallest eigenvalue `λ_min` of `W` (`∞` if `λ_min ≥ 0`, `NaN`
/// if the eigenvalue computation failed).
fn exact_step(lam: f64) -> f64 {
    if lam.is_nan() {
        f64::NAN
    } else if lam < 0.0 {
        -1.0 / lam
    } else {
        f64::INFINITY
    }
}

/// PSD blocks of at least this order get their step bound from Lanczos steps on `−W`
/// ([`lanczos_step`]), as in SDPT3 (`steplength.m`, the same order).
const LANCZOS_FROM: usize = 200;

/// `α_max = 1/λ̄` for an upper bound `λ̄` ([`largest_eigenvalue_bound`]) on the largest
/// eigenvalue of `−W = −L⁻¹ ΔV L⁻ᵀ`, applied to vectors (three triangular or symmetric
/// products per Lanczos step; no `n×n` array is formed): at most the exact step once the
/// Krylov space has found the extreme eigenvalue, and within the Lanczos tolerance of it (`∞`
/// when `W ⪰ 0`, `NaN` if a product is not finite). [`Side::bound`] confirms it by a Cholesky
/// test at the step it leads to.
fn lanczos_step(linv: &Mat<f64>, d: &Mat<f64>) -> f64 {
    let n = d.nrows();
    let mut t = vec![0.0; n];
    let mut u = vec![0.0; n];
    let bound = largest_eigenvalue_bound(n, |v, out| {
        // t = L⁻ᵀ v, u = ΔV t, out = −L⁻¹ u.
        tri_matmul(
            MatMut::from_column_major_slice_mut(&mut t, n, 1),
            BlockStructure::Rectangular,
            Accum::Replace,
            linv.transpose(),
            BlockStructure::TriangularUpper,
            MatRef::from_column_major_slice(v, n, 1),
            BlockStructure::Rectangular,
            1.0,
            Par::Seq,
        );
        faer::linalg::matmul::matmul(
            MatMut::from_column_major_slice_mut(&mut u, n, 1),
            Accum::Replace,
            d.as_ref(),
            MatRef::from_column_major_slice(&t, n, 1),
            1.0,
            Par::Seq,
        );
        tri_matmul(
            MatMut::from_column_major_slice_mut(out, n, 1),
            BlockStructure::Rectangular,
            Accum::Replace,
            linv.as_ref(),
            BlockStructure::TriangularLower,
            MatRef::from_column_major_slice(&u, n, 1),
            BlockStructure::Rectangular,
            -1.0,
            Par::Seq,
        );
    });
    if bound.is_nan() {
        f64::NAN
    } else if bound > 0.0 {
        1.0 / bound
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

/// One side (primal `X` or dual `S`) of a step-length computation: the current point, the
/// inverse Cholesky factors `L⁻¹` of its PSD blocks and the direction.
#[derive(Clone, Copy)]
pub(crate) struct Side<'a> {
    pub cur: &'a [Mat<f64>],
    pub linv: &'a [Mat<f64>],
    pub d: &'a [Mat<f64>],
}

impl Side<'_> {
    /// Block `k`'s bound after the Cholesky test at `1/γ`; a Lanczos bound is confirmed when
    /// `confirm` asks for it.
    fn bound(&self, k: usize, kind: BlockKind, gamma: f64, confirm: Confirm) -> Bound {
        let (cur, d) = (&self.cur[k], &self.d[k]);
        match kind {
            BlockKind::Lp => {
                let (x, dx) = (cur.col_as_slice(0), d.col_as_slice(0));
                let mut a = f64::INFINITY;
                for l in 0..x.len() {
                    if dx[l] < 0.0 {
                        a = a.min(-x[l] / dx[l]);
                    }
                }
                Bound::Known(a)
            }
            BlockKind::Psd if cur.nrows() >= LANCZOS_FROM => {
                // The Lanczos bound holds once the Krylov space has found the extreme
                // eigenvalue; a Cholesky test at the step it leads to confirms that, and where
                // it fails the exact eigenvalue decides.
                let a = lanczos_step(&self.linv[k], d);
                let taken = (gamma * a).min(1.0);
                if a.is_nan()
                    || confirm == Confirm::No
                    || (taken > 0.0 && allows(cur, d, 1.0 / taken))
                {
                    Bound::Known(a)
                } else {
                    let mut w = congruence(&self.linv[k], d);
                    Bound::Known(exact_step(min_eig_in_place(BlockKind::Psd, &mut w)))
                }
            }
            BlockKind::Psd => {
                if allows(cur, d, gamma) {
                    Bound::Known(f64::INFINITY)
                } else {
                    let w = congruence(&self.linv[k], d);
                    let dmin = (0..w.nrows()).fold(f64::INFINITY, |m, i| m.min(w[(i, i)]));
                    Bound::Pending(w, dmin)
                }
            }
        }
    }
}

/// Whether [`step_lengths`] confirms its Lanczos bounds by a Cholesky test ([`Side::bound`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Confirm {
    /// For the step that is taken: a bound that is too long would leave the cone.
    Yes,
    /// For the predictor, whose steps only set the centring parameter.
    No,
}

/// The steps `min(1, γ·α_max)` of both sides, where `α_max` is the largest `α ≥ 0` with
/// `V + α ΔV ⪰ 0`; a side's step is `0` if an eigenvalue computation failed. Both sides share
/// each pass over the blocks.
///
/// Eigenvalues are computed only where needed: blocks with `λ_min(W) > −γ` cannot limit the
/// step; of the others, the one with the smallest diagonal of `W` (most likely to bind) gets
/// its exact `α`, and any other block then needs its eigenvalue only if it fails the Cholesky
/// test at that `α`. The result is the same as with an eigenvalue for every block, except
/// where a Cholesky test and the eigenvalue disagree by rounding at the boundary.
pub(crate) fn step_lengths(
    an: &Analysis,
    sides: [Side<'_>; 2],
    gamma: f64,
    confirm: Confirm,
) -> [f64; 2] {
    let tested = an.map_blocks(|k, b| sides.map(|side| side.bound(k, b.kind, gamma, confirm)));
    let mut bounds: [Vec<Bound>; 2] = [Vec::new(), Vec::new()];
    for pair in tested {
        for (list, bound) in bounds.iter_mut().zip(pair) {
            list.push(bound);
        }
    }
    // Per side: the minimum over the known bounds and the pending block most likely to bind.
    let mut alpha = [f64::INFINITY; 2];
    let mut first: [Option<(usize, f64)>; 2] = [None, None];
    for i in 0..2 {
        for (k, bound) in bounds[i].iter().enumerate() {
            match bound {
                Bound::Known(a) => alpha[i] = nan_min(alpha[i], *a),
                Bound::Pending(_, dmin) => {
                    if first[i].is_none_or(|(_, m)| *dmin < m) {
                        first[i] = Some((k, *dmin));
                    }
                }
            }
        }
    }
    // The most binding blocks' `W` are taken out of the list: their eigenvalues overwrite them.
    let mut exact_first: [(Option<Mat<f64>>, f64); 2] =
        [(None, f64::INFINITY), (None, f64::INFINITY)];
    for (i, slot) in exact_first.iter_mut().enumerate() {
        if let Some((k, _)) = first[i]
            && let Bound::Pending(w, _) =
                std::mem::replace(&mut bounds[i][k], Bound::Known(f64::INFINITY))
        {
            slot.0 = Some(w);
        }
    }
    an.exec.for_each_mut(&mut exact_first, |_, (w, a)| {
        if let Some(mut w) = w.take() {
            *a = exact_step(min_eig_in_place(BlockKind::Psd, &mut w));
        }
    });
    let exact_first = exact_first.map(|(_, a)| a);
    for i in 0..2 {
        alpha[i] = nan_min(alpha[i], exact_first[i]);
    }
    // Every other pending block needs its eigenvalue only if it fails the test at that α.
    if first.iter().any(Option::is_some) {
        let threshold = alpha;
        let rest = an.map_blocks(|k, _| {
            [0, 1].map(|i| match &bounds[i][k] {
                Bound::Known(_) => f64::INFINITY,
                Bound::Pending(w, _) => {
                    let side = &sides[i];
                    if threshold[i].is_finite()
                        && threshold[i] > 0.0
                        && allows(&side.cur[k], &side.d[k], 1.0 / threshold[i])
                    {
                        f64::INFINITY
                    } else {
                        exact_step(min_eig(BlockKind::Psd, w))
                    }
                }
            })
        });
        for pair in rest {
            for i in 0..2 {
                alpha[i] = nan_min(alpha[i], pair[i]);
            }
        }
    }
    alpha.map(|a| {
        if a.is_nan() {
            0.0
        } else {
            (gamma * a).min(1.0)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::XorShift;
    use crate::solver::blockops::{cholesky, lower_inverse};
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(12))]

        /// On a block of order [`LANCZOS_FROM`] or more the bound of [`Side::bound`] (Lanczos,
        /// confirmed by a Cholesky test) leads to a step inside the cone, `min(1, γα) < α_max`
        /// for the exact `α_max = −1/λ_min(L⁻¹ΔVL⁻ᵀ)`, and to one at most 1 % shorter than the
        /// exact one (`V` a random positive definite matrix, `ΔV` random symmetric, over seven
        /// decades of scale).
        #[test]
        fn the_lanczos_step_is_the_exact_step(
            extra in 0usize..40,
            seed in any::<u64>(),
            scale in -3i32..=3,
        ) {
            let n = LANCZOS_FROM + extra;
            let mut rng = XorShift(seed | 1);
            let g = Mat::from_fn(n, n, |_, _| rng.centred());
            let v = &g * g.transpose() + Mat::<f64>::identity(n, n) * 0.01;
            let h = Mat::from_fn(n, n, |_, _| rng.centred());
            let d = (&h + h.transpose()) * 10f64.powi(scale);
            let linv = lower_inverse(&cholesky(&v).expect("positive definite"));
            let exact = exact_step(min_eig(BlockKind::Psd, &congruence(&linv, &d)));
            let gamma = 0.95;
            let side = Side {
                cur: std::slice::from_ref(&v),
                linv: std::slice::from_ref(&linv),
                d: std::slice::from_ref(&d),
            };
            let Bound::Known(a) = side.bound(0, BlockKind::Psd, gamma, Confirm::Yes) else {
                return Err(TestCaseError::fail("a large block's bound is always known"));
            };
            prop_assert!(exact.is_finite() && a.is_finite());
            let taken = (gamma * a).min(1.0);
            prop_assert!(taken < exact, "step {taken} not inside the cone (α_max {exact})");
            prop_assert!(taken >= 0.99 * (gamma * exact).min(1.0), "step {taken}, exact {exact}");
        }
    }
}
