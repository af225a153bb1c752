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

use faer::Mat;
use rayon::prelude::*;

use super::blockops::{BlockMats, apply_at, mul, symmetrize};
use super::structure::{Analysis, Values};
use crate::problem::BlockKind;

/// `T_k = (X_k R_d,k + H_k − σμ I) S_k⁻¹` for every block.
pub(crate) fn rhs_blocks(
    an: &Analysis,
    x: &[Mat<f64>],
    zinv: &[Mat<f64>],
    rd: &[Mat<f64>],
    sigma_mu: f64,
    h: Option<&[Mat<f64>]>,
) -> BlockMats {
    an.blocks
        .par_iter()
        .enumerate()
        .map(|(k, b)| match b.kind {
            BlockKind::Lp => {
                let (xs, rs, zs) = (
                    x[k].col_as_slice(0),
                    rd[k].col_as_slice(0),
                    zinv[k].col_as_slice(0),
                );
                Mat::from_fn(b.n, 1, |l, _| {
                    let hl = h.map_or(0.0, |h| h[k][(l, 0)]);
                    (xs[l] * rs[l] + hl - sigma_mu) * zs[l]
                })
            }
            BlockKind::Psd => {
                let mut w = mul(&x[k], &rd[k]);
                if let Some(h) = h {
                    w += &h[k];
                }
                for i in 0..b.n {
                    w[(i, i)] -= sigma_mu;
                }
                mul(&w, &zinv[k])
            }
        })
        .collect()
}

/// `(ΔX, ΔS)` from `Δy`: `ΔS = R_d − 𝒜ᵀ(Δy)`, `ΔX = sym(−X − (X ΔS + H − σμI) S⁻¹)`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn recover(
    an: &Analysis,
    vals: &Values,
    x: &[Mat<f64>],
    zinv: &[Mat<f64>],
    rd: &[Mat<f64>],
    dy: &[f64],
    sigma_mu: f64,
    h: Option<&[Mat<f64>]>,
) -> (BlockMats, BlockMats) {
    let mut ds = super::blockops::zeros(an);
    apply_at(an, vals, dy, &mut ds);
    for (d, r) in ds.iter_mut().zip(rd) {
        *d = r - &*d;
    }
    let dx: BlockMats = an
        .blocks
        .par_iter()
        .enumerate()
        .map(|(k, b)| match b.kind {
            BlockKind::Lp => {
                let (xs, dss, zs) = (
                    x[k].col_as_slice(0),
                    ds[k].col_as_slice(0),
                    zinv[k].col_as_slice(0),
                );
                Mat::from_fn(b.n, 1, |l, _| {
                    let hl = h.map_or(0.0, |h| h[k][(l, 0)]);
                    -xs[l] - (xs[l] * dss[l] + hl - sigma_mu) * zs[l]
                })
            }
            BlockKind::Psd => {
                let mut w = mul(&x[k], &ds[k]);
                if let Some(h) = h {
                    w += &h[k];
                }
                for i in 0..b.n {
                    w[(i, i)] -= sigma_mu;
                }
                let mut d = mul(&w, &zinv[k]);
                d += &x[k];
                d *= faer::Scale(-1.0);
                symmetrize(&mut d);
                d
            }
        })
        .collect();
    (dx, ds)
}

/// Second-order term `H = ΔX ΔS` of the corrector (per block; elementwise for LP blocks).
pub(crate) fn second_order(an: &Analysis, dx: &[Mat<f64>], ds: &[Mat<f64>]) -> BlockMats {
    an.blocks
        .par_iter()
        .enumerate()
        .map(|(k, b)| match b.kind {
            BlockKind::Lp => Mat::from_fn(b.n, 1, |l, _| dx[k][(l, 0)] * ds[k][(l, 0)]),
            BlockKind::Psd => mul(&dx[k], &ds[k]),
        })
        .collect()
}

/// Iterative refinement of a direction against the primal linearised equation
/// `𝒜(ΔX) = r_p`.
///
/// Near the optimum `M` is badly conditioned and `ΔX = −X − (XΔS + H − σμI)S⁻¹` cancels, so the
/// computed `ΔX` can miss `r_p` by far more than the tolerance; full steps then *increase* the
/// primal infeasibility. Since `ΔX` is affine in `Δy` with `∂ΔX/∂Δy · δ = sym(X 𝒜ᵀ(δ) S⁻¹)`,
/// the correction `M δ = r_p − 𝒜(ΔX)` (same factorisation), `Δy += δ`, `ΔS −= 𝒜ᵀ(δ)`,
/// `ΔX += sym(X 𝒜ᵀ(δ) S⁻¹)` restores the equation; it is repeated while the residual is above
/// `threshold` and halves.
#[allow(clippy::too_many_arguments)]
pub(crate) fn refine(
    an: &Analysis,
    vals: &Values,
    x: &[Mat<f64>],
    zinv: &[Mat<f64>],
    rp: &[f64],
    threshold: f64,
    solve: &dyn Fn(&[f64]) -> Vec<f64>,
    dx: &mut BlockMats,
    dy: &mut [f64],
    ds: &mut BlockMats,
) {
    let residual = |dx: &[Mat<f64>]| {
        let mut adx = vec![0.0; an.m];
        super::blockops::apply_a(an, vals, dx, &mut adx);
        let e: Vec<f64> = rp.iter().zip(&adx).map(|(r, a)| r - a).collect();
        let n = e.iter().map(|v| v * v).sum::<f64>().sqrt();
        (e, n)
    };
    let (mut e, mut norm) = residual(dx);
    for _ in 0..3 {
        if !(norm > threshold) {
            break;
        }
        let delta = solve(&e);
        let mut w = super::blockops::zeros(an);
        apply_at(an, vals, &delta, &mut w);
        let corr: BlockMats = an
            .blocks
            .par_iter()
            .enumerate()
            .map(|(k, b)| match b.kind {
                BlockKind::Lp => {
                    Mat::from_fn(b.n, 1, |l, _| x[k][(l, 0)] * w[k][(l, 0)] * zinv[k][(l, 0)])
                }
                BlockKind::Psd => {
                    let mut c = mul(&mul(&x[k], &w[k]), &zinv[k]);
                    symmetrize(&mut c);
                    c
                }
            })
            .collect();
        let mut trial = dx.clone();
        super::blockops::axpy(&mut trial, 1.0, &corr);
        let (e2, n2) = residual(&trial);
        if !(n2 < norm) {
            break;
        }
        *dx = trial;
        super::blockops::axpy(ds, -1.0, &w);
        for (a, d) in dy.iter_mut().zip(&delta) {
            *a += d;
        }
        let improved = n2 < 0.5 * norm;
        e = e2;
        norm = n2;
        if !improved {
            break;
        }
    }
}
