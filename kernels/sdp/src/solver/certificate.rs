//! Infeasibility certificates (Farkas rays) and their independent verification.
//!
//! The infeasible-start method does not embed the problem homogeneously; as in SDPT3
//! (`sqlpcheckconvg.m`, `homRd`/`homrp`) and CSDP (`pinftol`/`dinftol`), infeasibility shows as
//! iterates that diverge along a ray, and the normalised iterate is tested as a certificate:
//!
//! * **(P) infeasible** — if `bᵀy > 0` and `ỹ = y / bᵀy`, then
//!   `𝒜ᵀ(ỹ) = (C − R_d − S)/bᵀy ⪯ (C − R_d)/bᵀy`, so `λ_max(𝒜ᵀ(ỹ)) ≤ ‖𝒜ᵀ(y) + S‖₂ / bᵀy`.
//!   A `ỹ` with `bᵀỹ = 1` and `λ_max(Σ ỹ_i A_i) ≤ ε` proves that every `X ⪰ 0` with
//!   `𝒜(X) = b` has `tr X ≥ 1/ε` (`1 = bᵀỹ = ⟨𝒜ᵀ(ỹ), X⟩ ≤ ε tr X`); `ε = 0` is Farkas' lemma.
//! * **(D) infeasible** — if `⟨C,X⟩ < 0` and `X̃ = X / (−⟨C,X⟩)`, then `X̃ ⪰ 0`, `⟨C, X̃⟩ = −1`
//!   and `‖𝒜(X̃)‖₂ = δ` proves that every dual feasible `y` has `‖y‖₂ ≥ 1/δ`
//!   (`−1 = ⟨C, X̃⟩ = ⟨S, X̃⟩ + yᵀ𝒜(X̃) ≥ −‖y‖ δ`).
//!
//! The candidate is accepted only after [`InfeasibilityCertificate::verify`] has recomputed
//! `ε` or `δ` from the raw [`Problem`] data (dense matrices, eigenvalues) and found it
//! `≤ tol_infeas`.

use faer::Mat;

use super::blockops::min_eig;
use super::linsys::SchurSolver;
use crate::error::SdpError;
use crate::problem::{BlockKind, Problem, SparseSym};

/// A Farkas-type proof of infeasibility (see the module documentation of `solver::certificate`).
#[derive(Debug, Clone, PartialEq)]
pub enum InfeasibilityCertificate {
    /// (P) is infeasible: `y` normalised to `bᵀy = 1` with `λ_max(Σ y_i A_i) = max_eig ≈ ≤ 0`.
    PrimalInfeasibility {
        /// The ray of (D).
        y: Vec<f64>,
        /// `λ_max(Σ_i y_i A_i)` over all blocks, recomputed by [`InfeasibilityCertificate::verify`].
        max_eig: f64,
    },
    /// (D) is infeasible: `X ⪰ 0` normalised to `⟨C, X⟩ = −1` with `𝒜(X) ≈ 0`.
    DualInfeasibility {
        /// The ray of (P), one matrix per block (LP blocks as `n×1` columns).
        x: Vec<Mat<f64>>,
        /// `‖𝒜(X)‖₂`.
        residual: f64,
        /// `λ_min(X)` over all blocks.
        min_eig: f64,
    },
}

impl InfeasibilityCertificate {
    /// Recomputes the certificate's defect from the problem data, independently of the solver's
    /// internal operators: for a primal-infeasibility certificate
    /// `max(0, λ_max(Σ y_i A_i)) / bᵀy` (`+∞` if `bᵀy ≤ 0`), for a dual-infeasibility one
    /// `max(‖𝒜(X)‖₂, max(0, −λ_min(X))) / (−⟨C, X⟩)` (`+∞` if `⟨C, X⟩ ≥ 0`). A certificate is
    /// exact when the defect is 0.
    pub fn verify(&self, problem: &Problem) -> Result<f64, SdpError> {
        match self {
            Self::PrimalInfeasibility { y, .. } => {
                if y.len() != problem.b.len() {
                    return Err(SdpError::Structure(format!(
                        "certificate has {} multipliers for m = {}",
                        y.len(),
                        problem.b.len()
                    )));
                }
                let by: f64 = y.iter().zip(&problem.b).map(|(a, b)| a * b).sum();
                let lam = max_eig_aty(problem, y);
                Ok(if by > 0.0 && lam.is_finite() {
                    lam.max(0.0) / by
                } else {
                    f64::INFINITY
                })
            }
            Self::DualInfeasibility { x, .. } => {
                let (cx, ax, lam) = primal_ray_data(problem, x)?;
                let res = ax.iter().map(|v| v * v).sum::<f64>().sqrt();
                Ok(if cx < 0.0 && lam.is_finite() {
                    res.max((-lam).max(0.0)) / -cx
                } else {
                    f64::INFINITY
                })
            }
        }
    }

    /// Builds a normalised primal-infeasibility certificate from `y` (requires `bᵀy > 0`) and
    /// fills in its recomputed `max_eig`.
    pub(crate) fn primal(problem: &Problem, y: &[f64]) -> Option<Self> {
        let by: f64 = y.iter().zip(&problem.b).map(|(a, b)| a * b).sum();
        if !(by > 0.0 && by.is_finite()) {
            return None;
        }
        let y: Vec<f64> = y.iter().map(|v| v / by).collect();
        let max_eig = max_eig_aty(problem, &y);
        Some(Self::PrimalInfeasibility { y, max_eig })
    }

    /// Builds a normalised dual-infeasibility certificate from `X` (requires `⟨C,X⟩ < 0`),
    /// polished by the Euclidean projection `X ← X − 𝒜ᵀ((𝒜𝒜ᵀ)⁻¹ 𝒜(X))` onto the null space
    /// of `𝒜`: an iterate diverging along a ray of (P) is only *approximately* in that null
    /// space (`‖𝒜(X̃)‖ = ‖b − r_p‖/|⟨C,X⟩|`), while its positive definiteness margin is large, so
    /// the projection makes `𝒜(X̃) = 0` to working accuracy without losing `X̃ ⪰ 0`. The result
    /// is verified afterwards like any other certificate.
    ///
    /// `gram` caches the factorised Gram matrix between calls of one solve.
    pub(crate) fn dual(
        problem: &Problem,
        x: &[Mat<f64>],
        gram: &mut Option<SchurSolver>,
    ) -> Option<Self> {
        let (cx, _, _) = primal_ray_data(problem, x).ok()?;
        if !(cx < 0.0 && cx.is_finite()) {
            return None;
        }
        let mut x: Vec<Mat<f64>> = x.iter().map(|m| m * faer::Scale(1.0 / -cx)).collect();
        if !problem.b.is_empty() {
            let gram = gram.get_or_insert_with(|| gram_solver(problem));
            for _ in 0..2 {
                let (_, ax, _) = primal_ray_data(problem, &x).ok()?;
                let z = gram.solve(&ax, None);
                for (k, xk) in x.iter_mut().enumerate() {
                    *xk -= dense_block(problem, k, &z);
                }
            }
            let (cx, _, _) = primal_ray_data(problem, &x).ok()?;
            if !(cx < 0.0 && cx.is_finite()) {
                return None;
            }
            x.iter_mut().for_each(|m| *m *= faer::Scale(1.0 / -cx));
        }
        let (_, ax, min_eig) = primal_ray_data(problem, &x).ok()?;
        let residual = ax.iter().map(|v| v * v).sum::<f64>().sqrt();
        Some(Self::DualInfeasibility {
            x,
            residual,
            min_eig,
        })
    }
}

/// `⟨A, B⟩` of two symmetric matrices stored as sorted upper triangles.
fn sparse_inner(a: &SparseSym, b: &SparseSym) -> f64 {
    let (mut i, mut j) = (0, 0);
    let mut s = 0.0;
    while i < a.nnz() && j < b.nnz() {
        let ka = (a.cols[i], a.rows[i]);
        let kb = (b.cols[j], b.rows[j]);
        match ka.cmp(&kb) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                let w = if ka.0 == ka.1 { 1.0 } else { 2.0 };
                s += w * a.vals[i] * b.vals[j];
                i += 1;
                j += 1;
            }
        }
    }
    s
}

/// Factorised Gram matrix `𝒜𝒜ᵀ`, `G_ij = Σ_k ⟨A_i^k, A_j^k⟩` (regularised if singular).
fn gram_solver(problem: &Problem) -> SchurSolver {
    let m = problem.b.len();
    let mut g = Mat::<f64>::zeros(m, m);
    for bd in &problem.blocks {
        for (p, (i, ai)) in bd.a.iter().enumerate() {
            for (j, aj) in &bd.a[..=p] {
                g[(*i, *j)] += sparse_inner(ai, aj);
            }
        }
    }
    let mut solver = SchurSolver::with_matrix(g);
    // The solver keeps `g`: nothing is re-assembled.
    solver.factorize(|_| {});
    solver
}

/// Dense symmetric (PSD) or diagonal-as-column (LP) copy of `Σ_i w_i A_i^k`.
fn dense_block(problem: &Problem, k: usize, w: &[f64]) -> Mat<f64> {
    let bd = &problem.blocks[k];
    let n = bd.block.size;
    let mut out = match bd.block.kind {
        BlockKind::Psd => Mat::zeros(n, n),
        BlockKind::Lp => Mat::zeros(n, 1),
    };
    let mut add = |i: usize, j: usize, v: f64| match bd.block.kind {
        BlockKind::Lp => out[(i, 0)] += v,
        BlockKind::Psd => {
            out[(i, j)] += v;
            if i != j {
                out[(j, i)] += v;
            }
        }
    };
    for (con, a) in &bd.a {
        let wi = w.get(*con).copied().unwrap_or(0.0);
        for (i, j, v) in a.iter() {
            add(i, j, wi * v);
        }
    }
    out
}

/// `λ_max(Σ y_i A_i)` over all blocks (`−∞` for a problem without blocks).
fn max_eig_aty(problem: &Problem, y: &[f64]) -> f64 {
    let mut lam = f64::NEG_INFINITY;
    for k in 0..problem.blocks.len() {
        let neg: Vec<f64> = y.iter().map(|v| -v).collect();
        let d = dense_block(problem, k, &neg);
        lam = lam.max(-min_eig(problem.blocks[k].block.kind, &d));
    }
    lam
}

/// `(⟨C, X⟩, 𝒜(X), λ_min(X))` computed from the problem data.
fn primal_ray_data(problem: &Problem, x: &[Mat<f64>]) -> Result<(f64, Vec<f64>, f64), SdpError> {
    if x.len() != problem.blocks.len() {
        return Err(SdpError::Structure(format!(
            "certificate has {} blocks, problem {}",
            x.len(),
            problem.blocks.len()
        )));
    }
    let mut cx = 0.0;
    let mut ax = vec![0.0; problem.b.len()];
    let mut lam = f64::INFINITY;
    for (k, (bd, xk)) in problem.blocks.iter().zip(x).enumerate() {
        let n = bd.block.size;
        let cols = if bd.block.kind == BlockKind::Psd {
            n
        } else {
            1
        };
        if xk.nrows() != n || xk.ncols() != cols {
            return Err(SdpError::Structure(format!(
                "certificate block {k} is {}×{}, expected {n}×{cols}",
                xk.nrows(),
                xk.ncols()
            )));
        }
        let dot = |mat: &crate::problem::SparseSym| -> f64 {
            mat.iter()
                .map(|(i, j, v)| match bd.block.kind {
                    BlockKind::Lp => v * xk[(i, 0)],
                    BlockKind::Psd if i == j => v * xk[(i, i)],
                    BlockKind::Psd => v * (xk[(i, j)] + xk[(j, i)]),
                })
                .sum()
        };
        cx += dot(&bd.c);
        for (con, a) in &bd.a {
            if let Some(slot) = ax.get_mut(*con) {
                *slot += dot(a);
            }
        }
        let mut sym = xk.clone();
        if bd.block.kind == BlockKind::Psd {
            super::blockops::symmetrize(&mut sym);
        }
        lam = lam.min(min_eig(bd.block.kind, &sym));
    }
    Ok((cx, ax, lam))
}
