//! Residuals, objective values and the stopping measures.
//!
//! `r_p = b − 𝒜(X)`, `R_d = C − 𝒜ᵀ(y) − S`; relative measures as in SDPT3 (`sqlpmain.m`):
//! `‖r_p‖₂/(1+‖b‖₂)`, `‖R_d‖_F/(1+‖C‖_F)`, `|⟨C,X⟩−bᵀy|/(1+|⟨C,X⟩|+|bᵀy|)`, and the DIMACS
//! measures (Mittelmann 2003) for the final report.

use faer::Mat;

use super::blockops::{BlockMats, block_apply_a, block_apply_at, block_inner, min_eig, zero_block};
use super::cost::Cost;
use super::solution::Measures;
use super::structure::{Analysis, Values};

/// Norms of the data used to make measures relative.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DataNorms {
    /// `‖b‖₂`.
    pub b2: f64,
    /// `‖b‖_∞`.
    pub b_inf: f64,
    /// `‖C‖_F`.
    pub c_fro: f64,
    /// `max |C_ij|`.
    pub c_max: f64,
}

impl DataNorms {
    pub(crate) fn new(b: &[f64], cost: &Cost) -> Self {
        Self {
            b2: b.iter().map(|v| v * v).sum::<f64>().sqrt(),
            b_inf: b.iter().fold(0.0f64, |m, v| m.max(v.abs())),
            c_fro: cost.norm_fro(),
            c_max: cost.norm_max(),
        }
    }
}

/// Residuals and measures at one iterate.
#[derive(Debug, Clone)]
pub(crate) struct Residuals {
    /// `b − 𝒜(X)`.
    pub rp: Vec<f64>,
    /// `C − 𝒜ᵀ(y) − S`.
    pub rd: BlockMats,
    /// `⟨C, X⟩`.
    pub pobj: f64,
    /// `bᵀy`.
    pub dobj: f64,
    /// `⟨X, S⟩`.
    pub xs: f64,
    /// `‖r_p‖₂`.
    pub rp_norm: f64,
    /// `‖R_d‖_F`.
    pub rd_norm: f64,
    /// `|pobj − dobj| / (1 + |pobj| + |dobj|)`.
    pub rel_gap: f64,
    /// `⟨X, S⟩ / (1 + |pobj| + |dobj|)`.
    pub rel_compl: f64,
    /// `‖r_p‖₂ / (1 + ‖b‖₂)`.
    pub pinf: f64,
    /// `‖R_d‖_F / (1 + ‖C‖_F)`.
    pub dinf: f64,
}

impl Residuals {
    /// Largest of the four stopping measures.
    pub(crate) fn merit(&self) -> f64 {
        self.rel_gap
            .max(self.rel_compl)
            .max(self.pinf)
            .max(self.dinf)
    }

    /// Largest DIMACS error of an interior point (`X, S ≻ 0`, so the two eigenvalue errors of
    /// [`measures`] vanish): the same four formulas as there, without eigenvalues.
    pub(crate) fn dimacs_interior(&self, norms: &DataNorms) -> f64 {
        (self.rp_norm / (1.0 + norms.b_inf))
            .max(self.rd_norm / (1.0 + norms.c_max))
            .max(self.rel_gap)
            .max(self.rel_compl)
    }
}

/// Residuals at `(X, y, S)`.
pub(crate) fn residuals(
    an: &Analysis,
    vals: &Values,
    cost: &Cost,
    norms: &DataNorms,
    x: &[Mat<f64>],
    y: &[f64],
    s: &[Mat<f64>],
) -> Residuals {
    // One pass over the blocks: the block's part of 𝒜(X), R_d, and its shares of ⟨C, X⟩,
    // ⟨X, S⟩ and ‖R_d‖²_F (summed below in block order, as `inner` does).
    let parts = an.map_blocks(|k, b| {
        let ax = block_apply_a(an, vals, k, &x[k]);
        let mut r = zero_block(b);
        block_apply_at(an, vals, k, y, &mut r);
        let (c, sk) = (cost.block(k), &s[k]);
        let (rows, cols) = (r.nrows(), r.ncols());
        c.for_each(rows, cols, |i, j, cij| {
            r[(i, j)] = cij - r[(i, j)] - sk[(i, j)]
        });
        let shares = [c.inner(&x[k]), block_inner(&x[k], sk), block_inner(&r, &r)];
        (ax, r, shares)
    });
    let mut ax = vec![0.0; an.m];
    let mut rd: BlockMats = Vec::with_capacity(parts.len());
    let (mut pobj, mut xs, mut rd_sq) = (0.0, 0.0, 0.0);
    for (b, (part, r, [cx, xsk, rr])) in an.blocks.iter().zip(parts) {
        for (pat, v) in b.cons.iter().zip(part) {
            ax[pat.con] += v;
        }
        rd.push(r);
        pobj += cx;
        xs += xsk;
        rd_sq += rr;
    }
    let rp: Vec<f64> = vals.b.iter().zip(&ax).map(|(b, a)| b - a).collect();
    let dobj: f64 = vals.b.iter().zip(y).map(|(b, v)| b * v).sum();
    let rp_norm = rp.iter().map(|v| v * v).sum::<f64>().sqrt();
    let rd_norm = rd_sq.sqrt();
    let denom = 1.0 + pobj.abs() + dobj.abs();
    Residuals {
        rel_gap: (pobj - dobj).abs() / denom,
        rel_compl: xs / denom,
        pinf: rp_norm / (1.0 + norms.b2),
        dinf: rd_norm / (1.0 + norms.c_fro),
        rp,
        rd,
        pobj,
        dobj,
        xs,
        rp_norm,
        rd_norm,
    }
}

/// Final quality measures of a point (with eigenvalues of `X` and `S`).
pub(crate) fn measures(
    an: &Analysis,
    norms: &DataNorms,
    res: &Residuals,
    x: &[Mat<f64>],
    s: &[Mat<f64>],
) -> Measures {
    let min_over = |v: &[Mat<f64>]| {
        an.blocks
            .iter()
            .zip(v)
            .map(|(b, m)| min_eig(b.kind, m))
            .fold(
                f64::INFINITY,
                |a, e| if e.is_nan() { f64::NAN } else { a.min(e) },
            )
    };
    let min_eig_x = min_over(x);
    let min_eig_s = min_over(s);
    let denom = 1.0 + res.pobj.abs() + res.dobj.abs();
    let (bi, cm) = (1.0 + norms.b_inf, 1.0 + norms.c_max);
    Measures {
        rel_gap: res.rel_gap,
        primal_infeas: res.pinf,
        dual_infeas: res.dinf,
        dimacs: [
            res.rp_norm / bi,
            (-min_eig_x).max(0.0) / bi,
            res.rd_norm / cm,
            (-min_eig_s).max(0.0) / cm,
            (res.pobj - res.dobj) / denom,
            res.xs / denom,
        ],
        min_eig_x,
        min_eig_s,
    }
}
