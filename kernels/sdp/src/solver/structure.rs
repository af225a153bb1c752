//! Structure analysis: validation of a [`Problem`], the per-block constraint lists and the choice
//! of Schur-complement formula for every block, done once per sparsity pattern.
//!
//! The Schur matrix of the HKM direction is `M_ij = Σ_k tr(A_i^k X_k A_j^k S_k⁻¹)` (sum over the
//! blocks `k` that both constraints touch). How a block's share is best computed depends on its
//! order `n` and on the sparsity of its constraint matrices, as in SDPA (Fujisawa, Kojima,
//! Nakata, "Exploiting sparsity in primal-dual interior-point methods for semidefinite
//! programming", Math. Prog. 79, 1997):
//!
//! * [`SchurPlan::Syrk`] — every `A_i^k` is dense enough that all products are dense anyway:
//!   with `X = L Lᵀ` and `S⁻¹ = R Rᵀ` (`R = L_S⁻ᵀ`), `M_ij = ⟨K_i, K_j⟩` with `K_i = Lᵀ A_i R`, so
//!   the block adds `KᵀK` for `K = [vec K_1 … vec K_p]` — two small GEMMs per constraint and one
//!   symmetric rank-k update. This is the BLAS-3 form that suits many small dense LMI blocks (the
//!   role of SDPT3's `skron` path), and `KᵀK` is positive semidefinite by construction.
//! * [`SchurPlan::Mixed`] — constraints are sorted by decreasing number of nonzeros and each row
//!   of the block's Schur share is computed with the cheaper of SDPA's formulas
//!   * **F1**: `G = X A_i S⁻¹` densely (restricted to the support `J` of `A_i`:
//!     `G = X[:,J] A_i[J,J] S⁻¹[J,:]`), then `M_ij = ⟨A_j, G⟩` for the sparser `j`;
//!   * **F2**: `U = X A_i` on the support `J` of `A_i` (`n×|J|`), then only the entries of
//!     `G = U S⁻¹[J,:]` on the pattern of each later `A_j`, each an inner product of length
//!     `|J|`: cheaper than F3 whenever the entries of `A_i` share rows and columns;
//!   * **F3**: the fully sparse double sum `Σ_{(α,β)∈A_i} Σ_{(γ,δ)∈A_j} a_αβ a_γδ X_βγ S⁻¹_δα`.
//! * [`SchurPlan::Lp`] — a diagonal block adds `Σ_l a_il a_jl x_l / s_l`, accumulated per index `l`.
//!
//! A [`Values`] object holds the numbers of one problem aligned with the analysed pattern, so a
//! problem whose pattern is contained in the analysed one can be re-solved without re-analysis.

use super::par::Exec;
use crate::error::SdpError;
use crate::problem::{BlockKind, Problem, SparseSym};

/// Which SDPA formula computes one row of a [`SchurPlan::Mixed`] block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Formula {
    /// Dense `G = X A_i S⁻¹` on the support of `A_i`, then sparse inner products.
    F1,
    /// `X A_i` on the support of `A_i`, then the entries of `X A_i S⁻¹` on later patterns as
    /// inner products.
    F2,
    /// Sparse–sparse double sum.
    F3,
}

/// How the Schur contribution of one block is assembled (see the module documentation).
#[derive(Debug, Clone)]
pub(crate) enum SchurPlan {
    /// Diagonal block: `by_index[l]` lists `(local constraint, entry position)` of index `l`.
    Lp { by_index: Vec<Vec<(usize, usize)>> },
    /// Dense `KᵀK` form.
    Syrk,
    /// Per-row F1/F2/F3 choice; `order` sorts local constraints by decreasing nonzeros.
    Mixed {
        order: Vec<usize>,
        formula: Vec<Formula>,
        /// Support (sorted row/column indices) of every local constraint; used by F1 and F2.
        support: Vec<Vec<usize>>,
    },
}

/// Pattern of one constraint matrix restricted to one block (upper triangle, sorted by
/// `(col, row)`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ConPattern {
    /// Global constraint index.
    pub con: usize,
    /// Row indices (`rows[e] ≤ cols[e]`).
    pub rows: Vec<usize>,
    /// Column indices.
    pub cols: Vec<usize>,
}

/// Analysed structure of one block.
#[derive(Debug, Clone)]
pub(crate) struct BlockPlan {
    /// PSD or LP.
    pub kind: BlockKind,
    /// Order (PSD) or length (LP).
    pub n: usize,
    /// Constraints touching the block, sorted by global index.
    pub cons: Vec<ConPattern>,
    /// Schur assembly method.
    pub schur: SchurPlan,
    /// Whether the constraint matrices are dense enough to be kept as dense `n×n` copies
    /// ([`Values::dense`]), which makes `𝒜` and `𝒜ᵀ` plain dot products and axpys.
    pub dense: bool,
}

/// Analysed structure of a whole problem.
#[derive(Debug, Clone)]
pub(crate) struct Analysis {
    /// Number of constraints.
    pub m: usize,
    /// One plan per block, in cone order.
    pub blocks: Vec<BlockPlan>,
    /// Barrier parameter count `Σ_k n_k` (the `n` of `μ = ⟨X, S⟩ / n`).
    pub nu: usize,
    /// How the block loops run (chosen by [`super::Solver::new`] from [`Analysis::work_estimate`]).
    pub exec: Exec,
}

impl Analysis {
    /// `f(k, block k)` for every block, in block order ([`Analysis::exec`]).
    pub(crate) fn map_blocks<T, F>(&self, f: F) -> Vec<T>
    where
        T: Send,
        F: Fn(usize, &BlockPlan) -> T + Sync + Send,
    {
        self.exec.map(self.blocks.len(), |k| f(k, &self.blocks[k]))
    }

    /// Rough flop count of one interior-point iteration: the dense Cholesky of the Schur
    /// matrix (`m³/3`), the per-block factorisations and products (`n_k³`) and the Schur
    /// assembly (`m_k n_k²` for the `m_k` constraints touching block `k`; `m_k` nonzeros per
    /// LP entry). Used only to decide whether parallel loops are worth their overhead.
    pub(crate) fn work_estimate(&self) -> f64 {
        let m = self.m as f64;
        let blocks: f64 = self
            .blocks
            .iter()
            .map(|b| {
                let (n, mk) = (b.n as f64, b.cons.len() as f64);
                match b.kind {
                    BlockKind::Psd => n * n * n + mk * n * n,
                    BlockKind::Lp => n + mk * mk,
                }
            })
            .sum();
        m * m * m / 3.0 + blocks
    }
}

/// Numbers of one problem aligned with an [`Analysis`].
#[derive(Debug, Clone)]
pub(crate) struct Values {
    /// Right-hand side `b`.
    pub b: Vec<f64>,
    /// Per block: `C` restricted to the block (its own pattern).
    pub c: Vec<SparseSym>,
    /// Per block, per local constraint: values aligned with [`ConPattern`] (zeros where the
    /// problem has no entry).
    pub a: Vec<Vec<Vec<f64>>>,
    /// Per block with [`BlockPlan::dense`]: the constraint matrices as full symmetric `n×n`
    /// column-major arrays, one after the other (`n²` numbers per local constraint).
    pub dense: Vec<Option<Vec<f64>>>,
}

/// Minimum fraction of nonzeros (over all constraints of a PSD block) for dense storage.
const DENSE_FRACTION: f64 = 0.3;
/// Largest dense copy of one block's constraints, in `f64`s (128 MiB).
const DENSE_MAX: usize = 1 << 24;

/// Upper bound on the number of `f64`s the dense workspaces may need (about 64 GiB): larger
/// problems are rejected up front instead of aborting on allocation.
const MAX_DENSE_ELEMENTS: u128 = 1 << 33;

fn structure_err(msg: String) -> SdpError {
    SdpError::Structure(msg)
}

fn check_sparse(
    mat: &SparseSym,
    kind: BlockKind,
    n: usize,
    what: &dyn Fn() -> String,
) -> Result<(), SdpError> {
    if mat.rows.len() != mat.cols.len() || mat.rows.len() != mat.vals.len() {
        return Err(structure_err(format!(
            "{}: rows/cols/vals lengths differ ({}, {}, {})",
            what(),
            mat.rows.len(),
            mat.cols.len(),
            mat.vals.len()
        )));
    }
    let mut prev: Option<(usize, usize)> = None;
    for (i, j, v) in mat.iter() {
        if i > j || j >= n {
            return Err(structure_err(format!(
                "{}: entry ({i},{j}) is not in the upper triangle of a block of size {n}",
                what()
            )));
        }
        if kind == BlockKind::Lp && i != j {
            return Err(structure_err(format!(
                "{}: off-diagonal entry ({i},{j}) in an LP block",
                what()
            )));
        }
        if !v.is_finite() {
            return Err(SdpError::NonFinite {
                location: format!("{}, entry ({i},{j})", what()),
                value: v,
            });
        }
        if prev.is_some_and(|p| p >= (j, i)) {
            return Err(structure_err(format!(
                "{}: entries not strictly sorted by (col, row) at ({i},{j})",
                what()
            )));
        }
        prev = Some((j, i));
    }
    Ok(())
}

/// Checks every invariant the solver relies on (a [`Problem`] has public fields, so it may not
/// come from [`crate::ProblemBuilder`]).
pub(crate) fn validate(problem: &Problem) -> Result<(), SdpError> {
    let m = problem.b.len();
    for (i, &bi) in problem.b.iter().enumerate() {
        if !bi.is_finite() {
            return Err(SdpError::NonFinite {
                location: format!("b[{i}]"),
                value: bi,
            });
        }
    }
    let mut dense: u128 = (m as u128) * (m as u128) * 3;
    for (k, bd) in problem.blocks.iter().enumerate() {
        let n = bd.block.size;
        if n == 0 {
            return Err(structure_err(format!("block {k} has size 0")));
        }
        dense += match bd.block.kind {
            BlockKind::Psd => (n as u128) * (n as u128) * 24,
            BlockKind::Lp => (n as u128) * 24,
        };
        if dense > MAX_DENSE_ELEMENTS {
            return Err(structure_err(format!(
                "problem too large for dense workspaces (block {k} of size {n}, m = {m})"
            )));
        }
        check_sparse(&bd.c, bd.block.kind, n, &|| format!("C, block {k}"))?;
        let mut prev: Option<usize> = None;
        for (i, a) in &bd.a {
            if *i >= m {
                return Err(structure_err(format!(
                    "block {k}: constraint index {i} out of range (m = {m})"
                )));
            }
            if prev.is_some_and(|p| p >= *i) {
                return Err(structure_err(format!(
                    "block {k}: constraint list not strictly increasing at {i}"
                )));
            }
            prev = Some(*i);
            check_sparse(a, bd.block.kind, n, &|| format!("A_{i}, block {k}"))?;
        }
    }
    Ok(())
}

/// Relative cost of one scattered (sparse) floating-point operation compared with one inside a
/// dense matrix product; used only to choose between formulas.
const SPARSE_WEIGHT: f64 = 4.0;

fn support_of(p: &ConPattern) -> Vec<usize> {
    let mut s: Vec<usize> = p.rows.iter().chain(&p.cols).copied().collect();
    s.sort_unstable();
    s.dedup();
    s
}

fn full_count(p: &ConPattern) -> usize {
    p.rows
        .iter()
        .zip(&p.cols)
        .map(|(r, c)| if r == c { 1 } else { 2 })
        .sum()
}

fn plan_psd(n: usize, cons: &[ConPattern]) -> SchurPlan {
    let nc = cons.len();
    let nf = n as f64;
    let mut order: Vec<usize> = (0..nc).collect();
    order.sort_by(|&a, &b| cons[b].rows.len().cmp(&cons[a].rows.len()).then(a.cmp(&b)));
    let support: Vec<Vec<usize>> = cons.iter().map(support_of).collect();
    let full: Vec<f64> = cons.iter().map(|p| full_count(p) as f64).collect();
    let nnz: Vec<f64> = cons.iter().map(|p| p.rows.len() as f64).collect();
    // Suffix sums (in sorted order) of nonzeros, for the inner-product part of each row.
    let mut suffix_nnz = vec![0.0; nc + 1];
    let mut suffix_full = vec![0.0; nc + 1];
    for t in (0..nc).rev() {
        suffix_nnz[t] = suffix_nnz[t + 1] + nnz[order[t]];
        suffix_full[t] = suffix_full[t + 1] + full[order[t]];
    }
    let mut formula = Vec::with_capacity(nc);
    let mut mixed_cost = 0.0;
    for t in 0..nc {
        let p = order[t];
        let j = support[p].len() as f64;
        let f1 = 2.0 * nf * j * (j + nf) + SPARSE_WEIGHT * 2.0 * suffix_nnz[t] + nf * nf;
        // Each full entry of A_p meets each upper entry of A_q in at most two terms.
        let f3 = SPARSE_WEIGHT * 2.0 * full[p] * suffix_nnz[t];
        // U = X A_p (n per full entry), the copy of S⁻¹[:,J], then two length-|J| inner
        // products per entry of the later A_q.
        let f2 = 2.0 * nf * full[p] + nf * j + SPARSE_WEIGHT * 2.0 * j * suffix_nnz[t];
        let (choice, cost) = if f1 <= f2.min(f3) {
            (Formula::F1, f1)
        } else if f2 < f3 {
            (Formula::F2, f2)
        } else {
            (Formula::F3, f3)
        };
        formula.push(choice);
        mixed_cost += cost;
    }
    let ncf = nc as f64;
    // Two triangular n×n products per constraint, scattering A_i densely, then KᵀK (lower half).
    let syrk_cost = ncf * (2.0 * nf * nf * nf + nf * nf) + ncf * ncf * nf * nf;
    if syrk_cost < mixed_cost {
        SchurPlan::Syrk
    } else {
        SchurPlan::Mixed {
            order,
            formula,
            support,
        }
    }
}

fn plan_lp(n: usize, cons: &[ConPattern]) -> SchurPlan {
    let mut by_index: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
    for (p, pat) in cons.iter().enumerate() {
        for (e, &r) in pat.rows.iter().enumerate() {
            by_index[r].push((p, e));
        }
    }
    SchurPlan::Lp { by_index }
}

/// Analyses a validated problem.
pub(crate) fn analyse(problem: &Problem) -> Result<Analysis, SdpError> {
    validate(problem)?;
    let mut blocks = Vec::with_capacity(problem.blocks.len());
    let mut nu = 0;
    for bd in &problem.blocks {
        let n = bd.block.size;
        nu += n;
        let cons: Vec<ConPattern> =
            bd.a.iter()
                .map(|(i, a)| ConPattern {
                    con: *i,
                    rows: a.rows.clone(),
                    cols: a.cols.clone(),
                })
                .collect();
        let schur = match bd.block.kind {
            BlockKind::Lp => plan_lp(n, &cons),
            BlockKind::Psd => plan_psd(n, &cons),
        };
        let full: usize = cons.iter().map(full_count).sum();
        let cells = n.saturating_mul(n).saturating_mul(cons.len());
        let dense = bd.block.kind == BlockKind::Psd
            && cells <= DENSE_MAX
            && full as f64 >= DENSE_FRACTION * cells as f64;
        blocks.push(BlockPlan {
            kind: bd.block.kind,
            n,
            cons,
            schur,
            dense,
        });
    }
    Ok(Analysis {
        m: problem.b.len(),
        blocks,
        nu,
        exec: Exec::Parallel,
    })
}

impl Analysis {
    /// Extracts the numbers of `problem`, which must have the analysed block layout and a
    /// sparsity pattern contained in the analysed one.
    pub(crate) fn values(&self, problem: &Problem) -> Result<Values, SdpError> {
        validate(problem)?;
        if problem.b.len() != self.m {
            return Err(structure_err(format!(
                "structure differs from the analysed problem: m = {} instead of {}",
                problem.b.len(),
                self.m
            )));
        }
        if problem.blocks.len() != self.blocks.len() {
            return Err(structure_err(format!(
                "structure differs from the analysed problem: {} blocks instead of {}",
                problem.blocks.len(),
                self.blocks.len()
            )));
        }
        let mut a_all = Vec::with_capacity(self.blocks.len());
        let mut c_all = Vec::with_capacity(self.blocks.len());
        for (k, (plan, bd)) in self.blocks.iter().zip(&problem.blocks).enumerate() {
            if bd.block.kind != plan.kind || bd.block.size != plan.n {
                return Err(structure_err(format!(
                    "structure differs from the analysed problem: block {k} is {:?} of size {} \
                     instead of {:?} of size {}",
                    bd.block.kind, bd.block.size, plan.kind, plan.n
                )));
            }
            let mut vals: Vec<Vec<f64>> =
                plan.cons.iter().map(|p| vec![0.0; p.rows.len()]).collect();
            let mut p = 0;
            for (i, a) in &bd.a {
                while p < plan.cons.len() && plan.cons[p].con < *i {
                    p += 1;
                }
                if p == plan.cons.len() || plan.cons[p].con != *i {
                    return Err(structure_err(format!(
                        "structure differs from the analysed problem: A_{i} has entries in block \
                         {k}, which the analysed problem has not"
                    )));
                }
                let pat = &plan.cons[p];
                let mut e = 0;
                for (r, c, v) in a.iter() {
                    while e < pat.rows.len() && (pat.cols[e], pat.rows[e]) < (c, r) {
                        e += 1;
                    }
                    if e == pat.rows.len() || (pat.cols[e], pat.rows[e]) != (c, r) {
                        return Err(structure_err(format!(
                            "structure differs from the analysed problem: entry ({r},{c}) of \
                             A_{i} in block {k} is outside the analysed pattern"
                        )));
                    }
                    vals[p][e] = v;
                }
            }
            a_all.push(vals);
            c_all.push(bd.c.clone());
        }
        let dense = self
            .blocks
            .iter()
            .zip(&a_all)
            .map(|(plan, vals)| {
                plan.dense.then(|| {
                    let n = plan.n;
                    let mut d = vec![0.0; n * n * plan.cons.len()];
                    for (p, (pat, v)) in plan.cons.iter().zip(vals).enumerate() {
                        let a = &mut d[p * n * n..(p + 1) * n * n];
                        for e in 0..v.len() {
                            let (r, c) = (pat.rows[e], pat.cols[e]);
                            a[r + c * n] = v[e];
                            a[c + r * n] = v[e];
                        }
                    }
                    d
                })
            })
            .collect();
        Ok(Values {
            b: problem.b.clone(),
            c: c_all,
            a: a_all,
            dense,
        })
    }
}
