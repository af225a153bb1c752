//! Primal–dual points given from outside the solver: validation against a problem, their
//! quality measures (the kernels of the solver's own report), and interior starting points.

use faer::Mat;

use super::blockops::{BlockMats, cholesky, min_eig, symmetrize};
use super::cost::Cost;
use super::par::Exec;
use super::residuals::{DataNorms, measures, residuals};
use super::solution::{Measures, Solution};
use super::start::levels;
use super::structure::{self, Analysis, Values};
use crate::error::SdpError;
use crate::problem::{BlockKind, Problem};

/// A primal–dual point `(X, y, S)` in the dense block layout of [`crate::problem`]: one matrix
/// per block for `X` and for the dual slack `S` (PSD: `n×n` symmetric; LP: `n×1` column
/// holding the diagonal), and `y` of length `m`.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Primal matrix per block.
    pub x: Vec<Mat<f64>>,
    /// Dual variables.
    pub y: Vec<f64>,
    /// Dual slack per block.
    pub s: Vec<Mat<f64>>,
}

impl Solution {
    /// A copy of the returned point `(X, y, S)`.
    pub fn point(&self) -> Point {
        Point {
            x: self.x.clone(),
            y: self.y.clone(),
            s: self.s.clone(),
        }
    }
}

/// Checks that `(X, y, S)` fits the analysed layout and is finite.
pub(crate) fn check_point(
    an: &Analysis,
    y: &[f64],
    x: &[Mat<f64>],
    s: &[Mat<f64>],
) -> Result<(), SdpError> {
    let mismatch = |what: String, expected, found| SdpError::DimensionMismatch {
        what,
        expected,
        found,
    };
    if y.len() != an.m {
        return Err(mismatch("y".into(), (an.m, 1), (y.len(), 1)));
    }
    if let Some((i, v)) = y.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(SdpError::NonFinite {
            location: format!("y[{i}]"),
            value: *v,
        });
    }
    let nb = an.blocks.len();
    for (name, mats) in [("X", x), ("S", s)] {
        if mats.len() != nb {
            return Err(mismatch(
                format!("the block list of {name}"),
                (nb, 1),
                (mats.len(), 1),
            ));
        }
        for (k, (b, m)) in an.blocks.iter().zip(mats).enumerate() {
            let expected = match b.kind {
                BlockKind::Psd => (b.n, b.n),
                BlockKind::Lp => (b.n, 1),
            };
            if (m.nrows(), m.ncols()) != expected {
                return Err(mismatch(
                    format!("{name}, block {k}"),
                    expected,
                    (m.nrows(), m.ncols()),
                ));
            }
            for j in 0..m.ncols() {
                for i in 0..m.nrows() {
                    if !m[(i, j)].is_finite() {
                        return Err(SdpError::NonFinite {
                            location: format!("{name}, block {k}, entry ({i},{j})"),
                            value: m[(i, j)],
                        });
                    }
                }
            }
        }
    }
    Ok(())
}

/// Symmetrised copies of the blocks (LP columns unchanged).
fn symmetrized(an: &Analysis, v: &[Mat<f64>]) -> BlockMats {
    an.blocks
        .iter()
        .zip(v)
        .map(|(b, m)| {
            let mut m = m.clone();
            if b.kind == BlockKind::Psd {
                symmetrize(&mut m);
            }
            m
        })
        .collect()
}

/// Every quality measure of the point `(X, y, S)` for `problem`, computed exactly as for a
/// [`Solution`] (the same residual, eigenvalue and DIMACS kernels): relative gap and
/// infeasibilities, the six DIMACS errors and the smallest eigenvalues. PSD blocks of `X` and `S`
/// are symmetrised first, `(M + Mᵀ)/2`.
///
/// Errors: an invalid problem ([`SdpError::Structure`], [`SdpError::NonFinite`]), a point of the
/// wrong shape ([`SdpError::DimensionMismatch`]) or with a NaN or infinite entry
/// ([`SdpError::NonFinite`]).
pub fn point_measures(
    problem: &Problem,
    y: &[f64],
    x: &[Mat<f64>],
    s: &[Mat<f64>],
) -> Result<Measures, SdpError> {
    let mut an = structure::analyse(problem)?;
    an.exec = Exec::Sequential;
    let vals = an.values(problem)?;
    check_point(&an, y, x, s)?;
    let (x, s) = (symmetrized(&an, x), symmetrized(&an, s));
    let cd = Cost::new(&an, &vals);
    let norms = DataNorms::new(&vals.b, &cd);
    let res = residuals(&an, &vals, &cd, &norms, &x, y, &s);
    Ok(measures(&an, &norms, &res, &x, &s))
}

/// The six DIMACS errors (see [`Measures::dimacs`]) of any point `(X, y, S)` for `problem`:
/// `[‖𝒜(X)−b‖₂/(1+‖b‖_∞), max(0,−λ_min(X))/(1+‖b‖_∞), ‖𝒜ᵀ(y)+S−C‖_F/(1+‖C‖_max),
/// max(0,−λ_min(S))/(1+‖C‖_max), (⟨C,X⟩−bᵀy)/(1+|⟨C,X⟩|+|bᵀy|), ⟨X,S⟩/(1+|⟨C,X⟩|+|bᵀy|)]`.
///
/// For a [`Solution`] of `problem` this reproduces `solution.measures.dimacs` bitwise. Errors as
/// for [`point_measures`].
pub fn dimacs_errors(
    problem: &Problem,
    y: &[f64],
    x: &[Mat<f64>],
    s: &[Mat<f64>],
) -> Result<[f64; 6], SdpError> {
    point_measures(problem, y, x, s).map(|m| m.dimacs)
}

/// The starting point of [`super::Solver::solve_from`]: `start` with its PSD blocks symmetrised
/// and every block of `X` and `S` made strictly interior. A block `M` that is positive definite
/// (its Cholesky factorisation succeeds; LP: every entry `> 0`) is used as given, however close
/// to the boundary (optimal points have eigenvalues of `10⁻¹⁴·‖M‖`). Any other block is shifted
/// by a multiple of the identity, `M + (ℓ − λ_min(M))·I` (LP: that shift added to every entry),
/// so that its smallest eigenvalue is the level `ℓ` of the default starting point for that block
/// (SDPT3's `ξ` for `X`, `η` for `S`; module `start`). `y` is used as given.
pub(crate) fn interior_start(
    an: &Analysis,
    vals: &Values,
    start: &Point,
) -> (BlockMats, Vec<f64>, BlockMats) {
    let levels = levels(an, vals);
    let lift = |v: &[Mat<f64>], level: fn(&(f64, f64)) -> f64| -> BlockMats {
        let mut v = symmetrized(an, v);
        for ((b, m), lv) in an.blocks.iter().zip(v.iter_mut()).zip(&levels) {
            let interior = match b.kind {
                BlockKind::Psd => cholesky(m).is_some(),
                BlockKind::Lp => m.col_as_slice(0).iter().all(|&e| e > 0.0),
            };
            if interior {
                continue;
            }
            let lam = min_eig(b.kind, m);
            let lam = if lam.is_nan() {
                // Failed eigenvalue iteration: Gershgorin's bound −n·max|M_ij| ≤ λ_min.
                let mut max = 0.0f64;
                for j in 0..m.ncols() {
                    for i in 0..m.nrows() {
                        max = max.max(m[(i, j)].abs());
                    }
                }
                -(b.n as f64) * max
            } else {
                lam
            };
            let shift = level(lv) - lam.min(0.0);
            match b.kind {
                BlockKind::Psd => (0..b.n).for_each(|i| m[(i, i)] += shift),
                BlockKind::Lp => (0..b.n).for_each(|i| m[(i, 0)] += shift),
            }
        }
        v
    };
    (
        lift(&start.x, |l| l.0),
        start.y.clone(),
        lift(&start.s, |l| l.1),
    )
}
