//! The HKM search direction (Helmberg–Rendl–Vanderbei–Wolkowicz 1996; Kojima–Shindoh–Hara
//! 1997; Monteiro 1997) with Mehrotra's predictor–corrector (Mehrotra 1992).
//!
//! Linearising `XS = σμI − H` (`H = 0` for the predictor, `H = ΔX_a ΔS_a` for the corrector)
//! together with `𝒜(ΔX) = r_p`, `𝒜ᵀ(Δy) + ΔS = R_d` and eliminating `ΔS = R_d − 𝒜ᵀ(Δy)` and
//! `ΔX = −X − (X ΔS + H − σμI) S⁻¹` gives the Schur system
//!
//! ```text
//! M Δy = b + 𝒜(T),   T = (X R_d + H − σμ I) S⁻¹,   M_ij = tr(A_i X A_j S⁻¹),
//! ```
//!
//! after which `ΔX` is symmetrised (the HKM choice). For an LP block every product is
//! elementwise.
//!
//! The system is solved in one of two forms ([`System`]): the normal equations above (Cholesky of
//! `M`, module `linsys`), or the equivalent least-squares problem in the scaled space (QR of the
//! scaled constraint matrix, module `lsq`), which keeps `𝒜(ΔX) = r_p` accurate when `M` is too
//! ill-conditioned for double precision. Either way the direction is then refined against the
//! primal equation recomputed from the actual `ΔX` ([`refine`]; for a normal-equations direction
//! that refinement leaves inaccurate, by conjugate gradients, [`krylov`]), and
//! `ΔS = R_d − 𝒜ᵀ(Δy)` makes the dual equation exact.

use faer::Mat;

use super::blockops::{
    BlockMats, Factors, apply_a, apply_at, axpy, block_apply_a, block_apply_at, load, mul, store,
    symmetrize, zero_block,
};
use super::linsys::SchurSolver;
use super::lsq::LeastSquares;
use super::small;
use super::structure::{Analysis, BlockPlan, Values};
use crate::problem::BlockKind;

/// `T_k = (X_k R_d,k + H_k − σμ I) S_k⁻¹` for block `k` (`h`: its second-order term).
fn rhs_block(
    b: &BlockPlan,
    x: &Mat<f64>,
    zinv: &Mat<f64>,
    rd: &Mat<f64>,
    sigma_mu: f64,
    h: Option<&Mat<f64>>,
) -> Mat<f64> {
    match b.kind {
        BlockKind::Lp => {
            let (xs, rs, zs) = (x.col_as_slice(0), rd.col_as_slice(0), zinv.col_as_slice(0));
            Mat::from_fn(b.n, 1, |l, _| {
                let hl = h.map_or(0.0, |h| h[(l, 0)]);
                (xs[l] * rs[l] + hl - sigma_mu) * zs[l]
            })
        }
        BlockKind::Psd => hkm_product(x, rd, zinv, sigma_mu, h),
    }
}

/// `(X M + H − σμ I) S⁻¹` for a PSD block: `T` of [`rhs_block`] (`M = R_d`) and the core of
/// [`recover_block`] (`M = ΔS`). Blocks of order ≤ [`small::SMALL_PRODUCT`] are formed on stack
/// buffers with the same products as [`mul`] uses for them.
fn hkm_product(
    x: &Mat<f64>,
    m: &Mat<f64>,
    zinv: &Mat<f64>,
    sigma_mu: f64,
    h: Option<&Mat<f64>>,
) -> Mat<f64> {
    let n = x.nrows();
    if n <= small::SMALL_PRODUCT {
        return small::with_bufs(n, |[a, b, w, out]| {
            load(x, a);
            load(m, b);
            small::mul(a, b, n, w);
            if let Some(h) = h {
                for j in 0..n {
                    for (wi, hi) in w[j * n..(j + 1) * n].iter_mut().zip(h.col_as_slice(j)) {
                        *wi += hi;
                    }
                }
            }
            for i in 0..n {
                w[i + i * n] -= sigma_mu;
            }
            load(zinv, a);
            small::mul(w, a, n, out);
            store(out, n)
        });
    }
    let mut w = mul(x, m);
    if let Some(h) = h {
        w += h;
    }
    for i in 0..n {
        w[(i, i)] -= sigma_mu;
    }
    mul(&w, zinv)
}

/// `ΔX_k = sym(−X_k − (X_k ΔS_k + H_k − σμI) S_k⁻¹)` for block `k`.
fn recover_block(
    b: &BlockPlan,
    x: &Mat<f64>,
    zinv: &Mat<f64>,
    ds: &Mat<f64>,
    sigma_mu: f64,
    h: Option<&Mat<f64>>,
) -> Mat<f64> {
    match b.kind {
        BlockKind::Lp => {
            let (xs, dss, zs) = (x.col_as_slice(0), ds.col_as_slice(0), zinv.col_as_slice(0));
            Mat::from_fn(b.n, 1, |l, _| {
                let hl = h.map_or(0.0, |h| h[(l, 0)]);
                -xs[l] - (xs[l] * dss[l] + hl - sigma_mu) * zs[l]
            })
        }
        BlockKind::Psd => {
            let mut d = hkm_product(x, ds, zinv, sigma_mu, h);
            d += x;
            d *= faer::Scale(-1.0);
            symmetrize(&mut d);
            d
        }
    }
}

/// `ΔS_k = R_d,k − 𝒜ᵀ(Δy)_k` for block `k`.
fn dual_block(an: &Analysis, vals: &Values, k: usize, dy: &[f64], rd: &Mat<f64>) -> Mat<f64> {
    let mut o = zero_block(&an.blocks[k]);
    block_apply_at(an, vals, k, dy, &mut o);
    for j in 0..o.ncols() {
        for (oi, ri) in o.col_as_slice_mut(j).iter_mut().zip(rd.col_as_slice(j)) {
            *oi = ri - *oi;
        }
    }
    o
}

/// Second-order term `H_k = ΔX_k ΔS_k` of the corrector (elementwise for LP blocks).
fn second_order(b: &BlockPlan, dx: &Mat<f64>, ds: &Mat<f64>) -> Mat<f64> {
    match b.kind {
        BlockKind::Lp => Mat::from_fn(b.n, 1, |l, _| dx[(l, 0)] * ds[(l, 0)]),
        BlockKind::Psd => mul(dx, ds),
    }
}

/// Adds the per-block parts of `𝒜(·)` into `out` in block order (the order of [`apply_a`]).
fn add_parts(an: &Analysis, parts: impl IntoIterator<Item = Vec<f64>>, out: &mut [f64]) {
    for (b, part) in an.blocks.iter().zip(parts) {
        for (pat, s) in b.cons.iter().zip(part) {
            out[pat.con] += s;
        }
    }
}

/// The predictor `(ΔX_a, ΔS_a)` whose product `H = ΔX_a ΔS_a` is the corrector's second-order
/// term.
pub(crate) type Predictor<'a> = (&'a [Mat<f64>], &'a [Mat<f64>]);

/// Maps a primal residual `e` to `(δ, change of ΔX)` with `𝒜(change) ≈ e` (see [`refine`]).
type Correction<'a> = dyn Fn(&[f64]) -> (Vec<f64>, BlockMats) + 'a;

/// A search direction and how well it satisfies the primal equation.
pub(crate) struct Direction {
    /// `ΔX`.
    pub dx: BlockMats,
    /// `Δy`.
    pub dy: Vec<f64>,
    /// `ΔS = R_d − 𝒜ᵀ(Δy)`.
    pub ds: BlockMats,
    /// Whether this normal-equations direction is inaccurate: its error `‖r_p − 𝒜(ΔX)‖₂` after
    /// refinement is above [`Iterate::accepted`] and [`krylov`] did not bring it down to
    /// [`Iterate::rescued`].
    pub inaccurate: bool,
}

/// The data a direction is computed from.
pub(crate) struct Iterate<'a> {
    pub an: &'a Analysis,
    pub vals: &'a Values,
    pub x: &'a [Mat<f64>],
    pub f: &'a Factors,
    /// Primal residual `r_p = b − 𝒜(X)`.
    pub rp: &'a [f64],
    /// Dual residual `R_d = C − 𝒜ᵀ(y) − S`.
    pub rd: &'a [Mat<f64>],
    /// Refinement stops once `‖r_p − 𝒜(ΔX)‖₂` is at most this.
    pub threshold: f64,
    /// A normal-equations direction whose error after refinement is above this is inaccurate;
    /// conjugate gradients ([`krylov`]) try to rescue it before the caller gives up on it.
    pub accepted: f64,
    /// Error (at most [`Iterate::accepted`]) that a direction improved by [`krylov`] must reach
    /// to count as rescued.
    pub rescued: f64,
}

/// A factorised Newton system.
pub(crate) enum System<'a> {
    /// Cholesky (or fallback) factorisation of the Schur matrix `M`.
    Normal(&'a SchurSolver),
    /// QR factorisation of the scaled constraint matrix `K` (`M = KᵀK`).
    LeastSquares(&'a LeastSquares),
}

impl System<'_> {
    /// Whether this is the normal-equations form.
    pub(crate) fn is_normal(&self) -> bool {
        matches!(self, System::Normal(_))
    }

    /// The direction for centring target `σμ`; `second` is the predictor `(ΔX_a, ΔS_a)` for the
    /// corrector's second-order term. The normal equations read only `H = ΔX_a ΔS_a`: they
    /// drop the predictor once `H` is formed, before the corrector's arrays exist.
    pub(crate) fn direction(
        &self,
        it: &Iterate<'_>,
        sigma_mu: f64,
        second: Option<(BlockMats, BlockMats)>,
    ) -> Direction {
        let (an, vals, x, f) = (it.an, it.vals, it.x, it.f);
        let product = |v: &[f64]| schur_product(an, vals, x, &f.zinv, v);
        // The normal-equations form runs in two passes over the blocks: the right-hand side
        // `b + 𝒜(T)` (with the corrector's `H`), then `ΔS`, `ΔX` and `𝒜(ΔX)` from `Δy`.
        let (mut dx, mut dy, normal) = match self {
            System::Normal(solver) => {
                let terms =
                    second.map(|(dx, ds)| an.map_blocks(|k, b| second_order(b, &dx[k], &ds[k])));
                let h = |k: usize| terms.as_ref().map(|h| &h[k]);
                let parts = an.map_blocks(|k, b| {
                    let t = rhs_block(b, &x[k], &f.zinv[k], &it.rd[k], sigma_mu, h(k));
                    block_apply_a(an, vals, k, &t)
                });
                let mut r = vals.b.clone();
                add_parts(an, parts, &mut r);
                let dy = solver.solve(&r, Some(&product));
                let second = an.map_blocks(|k, b| {
                    let ds = dual_block(an, vals, k, &dy, &it.rd[k]);
                    let dx = recover_block(b, &x[k], &f.zinv[k], &ds, sigma_mu, h(k));
                    let part = block_apply_a(an, vals, k, &dx);
                    (dx, (ds, part))
                });
                // The second-order terms are dead once `ΔX` is recovered.
                drop(terms);
                let (dx, rest): (BlockMats, Vec<_>) = second.into_iter().unzip();
                let (ds, parts): (BlockMats, Vec<_>) = rest.into_iter().unzip();
                let mut adx = vec![0.0; an.m];
                add_parts(an, parts, &mut adx);
                (dx, dy, Some((ds, adx)))
            }
            System::LeastSquares(ls) => {
                let second = second
                    .as_ref()
                    .map(|(dx, ds)| (dx.as_slice(), ds.as_slice()));
                let (dx, dy) = ls.direction(an, x, f, it.rd, it.rp, sigma_mu, second);
                (dx, dy, None)
            }
        };
        let correction = |e: &[f64]| -> (Vec<f64>, BlockMats) {
            match self {
                System::Normal(solver) => {
                    let delta = solver.solve(e, Some(&product));
                    let corr = hkm_image(an, vals, x, &f.zinv, &delta);
                    (delta, corr)
                }
                System::LeastSquares(ls) => ls.correction(an, x, f, e),
            }
        };
        let (ds, adx) = match normal {
            Some((ds, adx)) => (Some(ds), adx),
            None => {
                let mut adx = vec![0.0; an.m];
                apply_a(an, vals, &dx, &mut adx);
                (None, adx)
            }
        };
        let (error, refined) = refine(
            it.rp,
            adx,
            it.threshold,
            &correction,
            &mut dx,
            &mut dy,
            |dx| {
                let mut adx = vec![0.0; an.m];
                apply_a(an, vals, dx, &mut adx);
                adx
            },
        );
        let (refined, inaccurate) = match self {
            System::Normal(solver) if error > it.accepted => {
                match krylov(it, solver, dx.as_mut_slice(), &mut dy) {
                    Some(e) => (true, !(e <= it.rescued)),
                    None => (refined, true),
                }
            }
            _ => (refined, false),
        };
        let ds = match ds {
            Some(ds) if !refined => ds,
            stale => {
                // The `ΔS` of the unrefined `Δy` goes before the new one is formed.
                drop(stale);
                an.map_blocks(|k, _| dual_block(an, vals, k, &dy, &it.rd[k]))
            }
        };
        Direction {
            dx,
            dy,
            ds,
            inaccurate,
        }
    }
}

/// `sym(X 𝒜ᵀ(δ) S⁻¹)` per block (elementwise for LP blocks): the change of `ΔX` per unit change of
/// `Δy` in the normal-equations form.
fn hkm_image(
    an: &Analysis,
    vals: &Values,
    x: &[Mat<f64>],
    zinv: &[Mat<f64>],
    delta: &[f64],
) -> BlockMats {
    // Block by block, each temporary dropped as soon as it is used: a PSD block holds at most
    // two `n×n` temporaries besides its result.
    an.map_blocks(|k, b| {
        let mut w = zero_block(b);
        block_apply_at(an, vals, k, delta, &mut w);
        match b.kind {
            BlockKind::Lp => {
                Mat::from_fn(b.n, 1, |l, _| x[k][(l, 0)] * w[(l, 0)] * zinv[k][(l, 0)])
            }
            BlockKind::Psd => {
                let xw = mul(&x[k], &w);
                drop(w);
                let mut c = mul(&xw, &zinv[k]);
                symmetrize(&mut c);
                c
            }
        }
    })
}

/// `M v = 𝒜(X 𝒜ᵀ(v) S⁻¹)`, the Schur matrix applied through the operators that define it
/// ([`hkm_image`], symmetric, so `𝒜` reads the same inner products as from `X 𝒜ᵀ(v) S⁻¹`): the
/// refinement residuals of a [`SchurSolver`] that keeps no copy of `M`.
pub(crate) fn schur_product(
    an: &Analysis,
    vals: &Values,
    x: &[Mat<f64>],
    zinv: &[Mat<f64>],
    v: &[f64],
) -> Vec<f64> {
    let mut mv = vec![0.0; an.m];
    apply_a(an, vals, &hkm_image(an, vals, x, zinv, v), &mut mv);
    mv
}

/// Most conjugate-gradient steps of [`krylov`].
const KRYLOV_STEPS: usize = 100;
/// [`krylov`] is not tried when its budget allows fewer steps than this: the least-squares form
/// is then cheap enough (`m` not much above the block orders, as on the gpp problems).
const KRYLOV_MIN_STEPS: usize = 20;
/// [`krylov`] spends at most this fraction of the flops of the QR factorisation of `K` that it
/// saves (`2 N m²` for `K` of `N` rows).
const KRYLOV_BUDGET: f64 = 0.25;

/// Step limit of [`krylov`]: [`KRYLOV_STEPS`], or fewer when the steps (four dense products per
/// PSD block of order `n`, `8 n³` flops) would exceed [`KRYLOV_BUDGET`] of a QR of `K`.
fn krylov_steps(an: &Analysis) -> usize {
    let (mut rows, mut step) = (0.0, 0.0);
    for b in &an.blocks {
        let n = b.n as f64;
        match b.kind {
            BlockKind::Psd => {
                rows += n * n;
                step += 8.0 * n * n * n;
            }
            BlockKind::Lp => {
                rows += n;
                step += 4.0 * n;
            }
        }
    }
    let m = an.m as f64;
    let affordable = KRYLOV_BUDGET * 2.0 * rows * m * m / step.max(1.0);
    (affordable.min(KRYLOV_STEPS as f64)) as usize
}

/// `sym(L_X (L_Xᵀ 𝒜ᵀ(δ) L_S⁻ᵀ) L_S⁻¹)` per block (elementwise for LP blocks): the change of `ΔX` per
/// unit change of `Δy` ([`hkm_image`]), formed through the scaled constraint matrix `K δ =
/// L_Xᵀ 𝒜ᵀ(δ) L_S⁻ᵀ` of [`super::lsq`] so that `𝒜(·) = Kᵀ(K δ)` is applied as two factors and
/// never through the (possibly numerically singular) product `M`.
fn scaled_image(it: &Iterate<'_>, delta: &[f64]) -> BlockMats {
    let (an, vals, x, f) = (it.an, it.vals, it.x, it.f);
    let mut w = super::blockops::zeros(an);
    apply_at(an, vals, delta, &mut w);
    an.map_blocks(|k, b| match b.kind {
        BlockKind::Lp => Mat::from_fn(b.n, 1, |l, _| {
            x[k][(l, 0)] * w[k][(l, 0)] * f.zinv[k][(l, 0)]
        }),
        BlockKind::Psd => {
            let (lx, linv_s) = (&f.lx[k], &f.linv_s[k]);
            let kd = mul(
                &mul(&lx.transpose().to_owned(), &w[k]),
                &linv_s.transpose().to_owned(),
            );
            let mut c = mul(&mul(lx, &kd), linv_s);
            symmetrize(&mut c);
            c
        }
    })
}

/// Preconditioned conjugate gradients on `Kᵀ K δ = r_p − 𝒜(ΔX)` for a normal-equations direction
/// that iterative refinement left inaccurate.
///
/// Refinement with the Cholesky factor of `M` is a stationary iteration: along eigenvectors of
/// `M` at or below the rounding level of its computed entries (the QAP relaxations, which have no
/// strictly feasible primal point, put the primal residual exactly there) it does not converge.
/// Conjugate gradients with the same factor as preconditioner (`(M̃ + ρI)⁻¹`, exact on the
/// well-conditioned part) and the operator applied as `Kᵀ(K δ)` ([`scaled_image`]) resolve the
/// few such directions in as many steps, each costing a few block products instead of the QR
/// factorisation of `K` that [`super::lsq`] needs. The iterate with the smallest true residual
/// `‖r_p − 𝒜(ΔX)‖₂` is kept; stops at `threshold`. Returns that residual if the direction
/// changed.
fn krylov(
    it: &Iterate<'_>,
    solver: &SchurSolver,
    dx: &mut [Mat<f64>],
    dy: &mut [f64],
) -> Option<f64> {
    let limit = krylov_steps(it.an);
    if limit < KRYLOV_MIN_STEPS {
        return None;
    }
    let precond = solver.preconditioner()?;
    let (an, vals) = (it.an, it.vals);
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(u, v)| u * v).sum::<f64>();
    let error_of = |dx: &[Mat<f64>]| {
        let mut adx = vec![0.0; an.m];
        apply_a(an, vals, dx, &mut adx);
        let e: Vec<f64> = it.rp.iter().zip(&adx).map(|(r, a)| r - a).collect();
        let n = dot(&e, &e).sqrt();
        (e, n)
    };
    let (mut r, mut best) = error_of(dx);
    let (mut cur_dx, mut cur_dy) = (dx.to_vec(), dy.to_vec());
    let mut z = precond(&r);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut improved = false;
    for _ in 0..limit {
        if !(rz > 0.0) || best <= it.threshold {
            break;
        }
        let img = scaled_image(it, &p);
        let mut q = vec![0.0; an.m];
        apply_a(an, vals, &img, &mut q);
        let pq = dot(&p, &q);
        if !(pq > 0.0) {
            break;
        }
        let alpha = rz / pq;
        axpy(&mut cur_dx, alpha, &img);
        for (a, d) in cur_dy.iter_mut().zip(&p) {
            *a += alpha * d;
        }
        for (a, d) in r.iter_mut().zip(&q) {
            *a -= alpha * d;
        }
        let (_, n) = error_of(&cur_dx);
        if n < best {
            best = n;
            dx.clone_from_slice(&cur_dx);
            dy.copy_from_slice(&cur_dy);
            improved = true;
        }
        z = precond(&r);
        let rz_next = dot(&r, &z);
        let beta = rz_next / rz;
        rz = rz_next;
        for (a, b) in p.iter_mut().zip(&z) {
            *a = b + beta * *a;
        }
    }
    improved.then_some(best)
}

/// Iterative refinement of a direction against the primal linearised equation
/// `𝒜(ΔX) = r_p`, recomputed from the actual `ΔX`.
///
/// Rounding in the solve and in the recovery of `ΔX` (which cancels near the optimum) can make
/// the computed `ΔX` miss `r_p` by more than the tolerance; full steps would then *increase* the
/// primal infeasibility. `ΔX` is affine in `Δy`, so `correction(e)` returns `δ` and the matching
/// change of `ΔX` with `𝒜(·) ≈ e` (same factorisation); `Δy += δ`, `ΔX += ·` is repeated while
/// the residual is above `threshold` and halves. `adx` is `𝒜(ΔX)` of the given direction and
/// `apply` computes `𝒜(·)`. Returns the final residual norm and whether the direction changed
/// (`ΔS` must then be formed again from the refined `Δy`).
fn refine(
    rp: &[f64],
    adx: Vec<f64>,
    threshold: f64,
    correction: &Correction<'_>,
    dx: &mut BlockMats,
    dy: &mut [f64],
    apply: impl Fn(&[Mat<f64>]) -> Vec<f64>,
) -> (f64, bool) {
    let residual = |adx: Vec<f64>| {
        let e: Vec<f64> = rp.iter().zip(&adx).map(|(r, a)| r - a).collect();
        let n = e.iter().map(|v| v * v).sum::<f64>().sqrt();
        (e, n)
    };
    let (mut e, mut norm) = residual(adx);
    let mut changed = false;
    for _ in 0..3 {
        if !(norm > threshold) {
            break;
        }
        // `ΔX + change` is formed in the change's own storage (`c + d` is `d + 1·c` bitwise).
        let (delta, mut trial) = correction(&e);
        axpy(&mut trial, 1.0, dx);
        let (e2, n2) = residual(apply(&trial));
        if !(n2 < norm) {
            break;
        }
        *dx = trial;
        for (a, d) in dy.iter_mut().zip(&delta) {
            *a += d;
        }
        changed = true;
        let improved = n2 < 0.5 * norm;
        e = e2;
        norm = n2;
        if !improved {
            break;
        }
    }
    (norm, changed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::ProblemBuilder;
    use crate::solver::blockops::{Factors, factor_all};
    use crate::solver::par::Exec;
    use crate::solver::schur::assemble;
    use crate::solver::structure::analyse;
    use proptest::prelude::*;

    proptest! {
        /// The matrix-free `M v` of [`schur_product`] (the refinement residuals of a Schur
        /// solver without a copy of `M`) against `M v` from the assembled lower triangle, on
        /// random problems with two PSD blocks (one on each side of the small-product limit)
        /// and an LP block, sparse and dense constraints, both executors.
        #[test]
        fn schur_product_matches_the_assembled_matrix(
            (n1, n2, n3) in (1usize..=6, 7usize..=24, 1usize..=9),
            m in 1usize..=40,
            density in 1usize..=12,
            seed in any::<u64>(),
            parallel in any::<bool>(),
        ) {
            let mut rng = crate::solver::XorShift(seed | 1);
            let mut next = move || rng.centred();
            let mut builder = ProblemBuilder::new(m);
            let blocks = [
                (builder.add_block(BlockKind::Psd, n1), n1, BlockKind::Psd),
                (builder.add_block(BlockKind::Psd, n2), n2, BlockKind::Psd),
                (builder.add_block(BlockKind::Lp, n3), n3, BlockKind::Lp),
            ];
            for i in 0..m {
                builder.set_b(i, next());
                for &(k, n, kind) in &blocks {
                    // Constraint i touches a block with a few (up to `density`) entries, or
                    // none at all.
                    let entries = (i * 7 + k * 3 + density) % (density + 2);
                    for _ in 0..entries {
                        let r = ((next() + 0.5) * n as f64) as usize % n;
                        let c = match kind {
                            BlockKind::Psd => ((next() + 0.5) * n as f64) as usize % n,
                            BlockKind::Lp => r,
                        };
                        builder.add_a(i, k, r.min(c), r.max(c), next());
                    }
                }
            }
            let problem = builder.build().expect("problem");
            let mut an = analyse(&problem).expect("analysis");
            an.exec = if parallel { Exec::Parallel } else { Exec::Sequential };
            let vals = an.values(&problem).expect("values");
            let mut point = |kind: BlockKind, n: usize| match kind {
                BlockKind::Psd => {
                    let b = Mat::from_fn(n, n, |_, _| next());
                    Mat::from_fn(n, n, |i, j| {
                        f64::from(u8::from(i == j)) + 0.4 * (b[(i, j)] + b[(j, i)]) / n as f64
                    })
                }
                BlockKind::Lp => Mat::from_fn(n, 1, |_, _| 1.0 + next()),
            };
            let x: BlockMats = blocks.iter().map(|&(_, n, kind)| point(kind, n)).collect();
            let s: BlockMats = blocks.iter().map(|&(_, n, kind)| point(kind, n)).collect();
            let f = Factors::new(
                &an,
                factor_all(&an, &x).expect("X factor"),
                factor_all(&an, &s).expect("S factor"),
            );
            let mut lower = Mat::zeros(m, m);
            assemble(&an, &vals, &x, &f, &mut lower, &mut Vec::new());
            let v: Vec<f64> = (0..m).map(|_| next()).collect();
            let got = schur_product(&an, &vals, &x, &f.zinv, &v);
            for i in 0..m {
                let (mut reference, mut scale) = (0.0, 0.0);
                for (j, vj) in v.iter().enumerate() {
                    let mij = if j <= i { lower[(i, j)] } else { lower[(j, i)] };
                    reference += mij * vj;
                    scale += (mij * vj).abs();
                }
                let err = (got[i] - reference).abs();
                prop_assert!(
                    err <= 1e-12 * scale.max(f64::MIN_POSITIVE) * (1 + n2) as f64,
                    "row {i}: {} against {reference} (scale {scale})", got[i]
                );
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// `(X M + H − σμ I) S⁻¹` against faer's dense products, on block orders on both sides
        /// of the stack-buffer limit, with and without the second-order term.
        #[test]
        fn hkm_product_matches_dense_formula(
            n in 1usize..=12,
            e in proptest::collection::vec(-1.0f64..1.0, 256),
            sigma_mu in 0.0f64..2.0,
            corrector in any::<bool>(),
        ) {
            let m = |shift: usize| Mat::from_fn(n, n, |i, j| e[(shift + 13 * i + 5 * j) % 256]);
            let (x, rd, zinv, h) = (m(0), m(1), m(2), m(3));
            let h = corrector.then_some(&h);
            let got = hkm_product(&x, &rd, &zinv, sigma_mu, h);
            let mut w = &x * &rd - Mat::<f64>::identity(n, n) * faer::Scale(sigma_mu);
            if let Some(h) = h {
                w += h;
            }
            let reference = &w * &zinv;
            let err = (&got - &reference).norm_max();
            prop_assert!(err <= 1e-13 * (n * n) as f64, "error {err}");
        }
    }
}
