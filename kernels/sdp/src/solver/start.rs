//! Starting point: scaled identities as in SDPT3's `infeaspt.m` (option 1).
//!
//! For a PSD block of order `n` with `‖A_i‖` the Frobenius norm of constraint `i` restricted to
//! the block (zero if it does not touch it):
//!
//! ```text
//! X⁰ = ξ I,  ξ = max(10, √n, n · max_i (1 + |b_i|) / (1 + ‖A_i‖))
//! S⁰ = η I,  η = max(10, √n, max_i (1 + ‖A_i‖), 1 + ‖C‖_F)
//! y⁰ = 0
//! ```
//!
//! and for an LP block of length `n` the same with `n` replaced by `√n` in `ξ`. The point is
//! interior but in general infeasible; the infeasible-start method removes the residuals.

use faer::Mat;

use super::blockops::BlockMats;
use super::structure::{Analysis, Values};
use crate::problem::BlockKind;

/// `(ξ, η)` of every block: the default starting levels `X⁰ = ξ I`, `S⁰ = η I`.
pub(crate) fn levels(an: &Analysis, vals: &Values) -> Vec<(f64, f64)> {
    an.blocks
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let n = b.n as f64;
            // 1 + ‖A_i‖_F for every constraint (1 for those not touching the block).
            let mut norm_a = vec![1.0; an.m];
            for (p, pat) in b.cons.iter().enumerate() {
                let sq: f64 = pat
                    .rows
                    .iter()
                    .zip(&pat.cols)
                    .zip(&vals.a[k][p])
                    .map(|((r, c), v)| if r == c { v * v } else { 2.0 * v * v })
                    .sum();
                norm_a[pat.con] = 1.0 + sq.sqrt();
            }
            let c_sq: f64 = vals.c[k]
                .iter()
                .map(|(r, c, v)| if r == c { v * v } else { 2.0 * v * v })
                .sum();
            let norm_c = 1.0 + c_sq.sqrt();
            let ratio = vals
                .b
                .iter()
                .zip(&norm_a)
                .fold(0.0f64, |acc, (bi, na)| acc.max((1.0 + bi.abs()) / na));
            let max_a = norm_a.iter().fold(0.0f64, |acc, &v| acc.max(v));
            let scale_x = match b.kind {
                BlockKind::Psd => n,
                BlockKind::Lp => n.sqrt(),
            };
            let xi = 10f64.max(n.sqrt()).max(scale_x * ratio);
            let eta = 10f64.max(n.sqrt()).max(max_a).max(norm_c);
            (xi, eta)
        })
        .collect()
}

/// `(X⁰, y⁰, S⁰)`, with the levels `ξ`, `η` multiplied by `factor` (`1` for SDPT3's point; a
/// restart after a stall starts further inside the cone, see [`super::Solver::solve`]).
pub(crate) fn initial_point(
    an: &Analysis,
    vals: &Values,
    factor: f64,
) -> (BlockMats, Vec<f64>, BlockMats) {
    let mut x = Vec::with_capacity(an.blocks.len());
    let mut s = Vec::with_capacity(an.blocks.len());
    for (b, (xi, eta)) in an.blocks.iter().zip(levels(an, vals)) {
        let (xi, eta) = (factor * xi, factor * eta);
        match b.kind {
            BlockKind::Psd => {
                x.push(Mat::from_fn(b.n, b.n, |i, j| if i == j { xi } else { 0.0 }));
                s.push(Mat::from_fn(
                    b.n,
                    b.n,
                    |i, j| if i == j { eta } else { 0.0 },
                ));
            }
            BlockKind::Lp => {
                x.push(Mat::from_fn(b.n, 1, |_, _| xi));
                s.push(Mat::from_fn(b.n, 1, |_, _| eta));
            }
        }
    }
    (x, vec![0.0; an.m], s)
}
