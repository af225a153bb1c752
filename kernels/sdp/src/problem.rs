//! Standard-form SDP data over a block-diagonal cone.
//!
//! The primal–dual pair solved by this crate is
//!
//! ```text
//! (P)  min ⟨C, X⟩        s.t.  ⟨A_i, X⟩ = b_i  (i = 1..m),   X ⪰ 0
//! (D)  max bᵀy           s.t.  Σ_i y_i A_i + S = C,           S ⪰ 0
//! ```
//!
//! where `X`, `S`, `C`, `A_i` are block diagonal. Each block is either a dense PSD block of order
//! `n_k` or a nonnegative-orthant ("LP") block of length `n_k`, stored as a diagonal matrix.
//! LMI constraints `F(y) = F_0 + Σ y_i F_i ⪰ 0` are the dual form with `C = F_0`, `A_i = −F_i`.
//!
//! Data are stored **by block** (as in CSDP): every block keeps `C` restricted to the block and the
//! list of constraints that have a nonzero in it. Interior-point iterations assemble the Schur
//! complement block by block, so only pairs of constraints that share a block cost anything.
//!
//! # Dense block layout
//!
//! Wherever a block is a dense matrix — the iterates and solutions (`X`, `S` of
//! [`crate::Solution`] and [`crate::Point`]), the input of [`crate::dimacs_errors`] and of a warm
//! start, the dense views [`Problem::dense_objective`] and [`Problem::dense_constraint`] — it has
//! one layout: a PSD block of order `n` is an `n×n` symmetric matrix, and an LP block of length
//! `n` is an `n×1` **column holding the diagonal** (entry `(i, 0)` is the diagonal entry
//! `(i, i)` of the sparse storage, which keeps only diagonal entries for LP blocks). Inner
//! products `⟨A, X⟩` are then the sums of entrywise products over this layout for LP blocks
//! and over the full matrices for PSD blocks.

use faer::Mat;

use crate::error::SdpError;

/// Kind of a cone block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BlockKind {
    /// Symmetric positive-semidefinite block of the given order.
    Psd,
    /// Nonnegative orthant of the given length: a diagonal block, stored sparsely by its
    /// diagonal entries and densely as an `n×1` column (see the [module documentation](self)).
    Lp,
}

/// A cone block: its kind and its order (PSD) or length (LP).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Block {
    /// PSD or LP.
    pub kind: BlockKind,
    /// Order of the PSD block, or number of LP variables.
    pub size: usize,
}

/// A sparse symmetric matrix stored by its upper triangle (`i ≤ j`, block-local, 0-based).
///
/// Entries are sorted by `(j, i)` (column-major upper triangle), duplicates are summed and exact
/// zeros removed by [`ProblemBuilder::build`]. For LP blocks only diagonal entries occur.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SparseSym {
    /// Row indices (`rows[k] ≤ cols[k]`).
    pub rows: Vec<usize>,
    /// Column indices.
    pub cols: Vec<usize>,
    /// Values; the entry `(i, j)` with `i < j` stands for both `(i, j)` and `(j, i)`.
    pub vals: Vec<f64>,
}

impl SparseSym {
    /// Number of stored (upper-triangle) entries.
    pub fn nnz(&self) -> usize {
        self.vals.len()
    }

    /// Whether no entry is stored.
    pub fn is_empty(&self) -> bool {
        self.vals.is_empty()
    }

    /// Iterator over `(i, j, value)` with `i ≤ j`.
    pub fn iter(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.rows
            .iter()
            .zip(&self.cols)
            .zip(&self.vals)
            .map(|((&i, &j), &v)| (i, j, v))
    }

    /// The matrix in the dense layout of `block` (see the [module documentation](self)): PSD
    /// `n×n` with both triangles filled, LP an `n×1` column of the diagonal. Entries outside
    /// the block (possible only for hand-built data that [`ProblemBuilder::build`] would reject)
    /// are skipped, and an off-diagonal entry of an LP block is ignored.
    pub fn to_dense(&self, block: Block) -> Mat<f64> {
        let n = block.size;
        match block.kind {
            BlockKind::Psd => {
                let mut m = Mat::zeros(n, n);
                for (i, j, v) in self.iter().filter(|&(i, j, _)| i < n && j < n) {
                    m[(i, j)] = v;
                    m[(j, i)] = v;
                }
                m
            }
            BlockKind::Lp => {
                let mut m = Mat::zeros(n, 1);
                for (i, _, v) in self.iter().filter(|&(i, j, _)| i == j && i < n) {
                    m[(i, 0)] = v;
                }
                m
            }
        }
    }
}

/// All data of one cone block.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockData {
    /// Kind and size.
    pub block: Block,
    /// The objective matrix `C` restricted to this block.
    pub c: SparseSym,
    /// `(i, A_i restricted to this block)` for every constraint `i` with a nonzero here, sorted by `i`.
    pub a: Vec<(usize, SparseSym)>,
}

/// A standard-form SDP (see the module documentation for the sign convention).
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Block data, in cone order.
    pub blocks: Vec<BlockData>,
    /// Right-hand side `b` (length `m`, the number of constraints / dual variables).
    pub b: Vec<f64>,
}

impl Problem {
    /// Number of equality constraints `m` (= number of dual variables `y`).
    pub fn num_constraints(&self) -> usize {
        self.b.len()
    }

    /// `C`, one dense matrix per block in the layout of the [module documentation](self).
    pub fn dense_objective(&self) -> Vec<Mat<f64>> {
        self.blocks
            .iter()
            .map(|bd| bd.c.to_dense(bd.block))
            .collect()
    }

    /// `A_i` (0-based `i`), one dense matrix per block in the layout of the
    /// [module documentation](self) (zero in blocks it does not touch);
    /// [`SdpError::Structure`] if `i ≥ m`.
    pub fn dense_constraint(&self, i: usize) -> Result<Vec<Mat<f64>>, SdpError> {
        if i >= self.b.len() {
            return Err(SdpError::Structure(format!(
                "constraint index {i} out of range (m = {})",
                self.b.len()
            )));
        }
        Ok(self
            .blocks
            .iter()
            .map(|bd| match bd.a.binary_search_by_key(&i, |(k, _)| *k) {
                Ok(p) => bd.a[p].1.to_dense(bd.block),
                Err(_) => SparseSym::default().to_dense(bd.block),
            })
            .collect())
    }
}

/// Incremental, validating constructor of a [`Problem`].
///
/// Entries may be given in either triangle and more than once (they are summed). Indices are
/// 0-based. [`ProblemBuilder::build`] rejects out-of-range indices, off-diagonal entries in LP
/// blocks and non-finite numbers with an [`SdpError`] naming the offending entry.
#[derive(Debug, Clone)]
pub struct ProblemBuilder {
    blocks: Vec<Block>,
    b: Vec<f64>,
    /// `(constraint or usize::MAX for C, block, i, j, value)`.
    entries: Vec<(usize, usize, usize, usize, f64)>,
}

const OBJECTIVE: usize = usize::MAX;

impl ProblemBuilder {
    /// A problem with `m` constraints (`b = 0` until set) and no blocks yet.
    pub fn new(m: usize) -> Self {
        Self {
            blocks: Vec::new(),
            b: vec![0.0; m],
            entries: Vec::new(),
        }
    }

    /// Appends a cone block and returns its index.
    pub fn add_block(&mut self, kind: BlockKind, size: usize) -> usize {
        self.blocks.push(Block { kind, size });
        self.blocks.len() - 1
    }

    /// Sets `b_i`.
    pub fn set_b(&mut self, i: usize, value: f64) -> &mut Self {
        if i < self.b.len() {
            self.b[i] = value;
        } else {
            // Recorded and reported by `build` rather than panicking here.
            self.entries.push((i, usize::MAX, 0, 0, value));
        }
        self
    }

    /// Adds `value` to entry `(i, j)` (and `(j, i)`) of `C` in `block`.
    pub fn add_c(&mut self, block: usize, i: usize, j: usize, value: f64) -> &mut Self {
        self.entries.push((OBJECTIVE, block, i, j, value));
        self
    }

    /// Adds `value` to entry `(i, j)` (and `(j, i)`) of `A_constraint` in `block`.
    pub fn add_a(
        &mut self,
        constraint: usize,
        block: usize,
        i: usize,
        j: usize,
        value: f64,
    ) -> &mut Self {
        self.entries.push((constraint, block, i, j, value));
        self
    }

    /// Validates the data and assembles the block-wise storage.
    pub fn build(self) -> Result<Problem, SdpError> {
        let m = self.b.len();
        for (i, &bi) in self.b.iter().enumerate() {
            if !bi.is_finite() {
                return Err(SdpError::NonFinite {
                    location: format!("b[{i}]"),
                    value: bi,
                });
            }
        }
        let name = |c: usize| {
            if c == OBJECTIVE {
                "C".to_string()
            } else {
                format!("A_{c}")
            }
        };
        // Bucket entries per block, normalised to the upper triangle.
        let mut per_block: Vec<Vec<(usize, usize, usize, f64)>> =
            vec![Vec::new(); self.blocks.len()];
        for &(c, blk, i, j, v) in &self.entries {
            if blk == usize::MAX {
                return Err(SdpError::Structure(format!(
                    "b index {c} out of range (m = {m})"
                )));
            }
            if c != OBJECTIVE && c >= m {
                return Err(SdpError::Structure(format!(
                    "constraint index {c} out of range (m = {m})"
                )));
            }
            let Some(block) = self.blocks.get(blk) else {
                return Err(SdpError::Structure(format!(
                    "{}: block index {blk} out of range ({} blocks)",
                    name(c),
                    self.blocks.len()
                )));
            };
            if i >= block.size || j >= block.size {
                return Err(SdpError::Structure(format!(
                    "{}, block {blk}: entry ({i},{j}) outside a block of size {}",
                    name(c),
                    block.size
                )));
            }
            if block.kind == BlockKind::Lp && i != j {
                return Err(SdpError::Structure(format!(
                    "{}, block {blk}: off-diagonal entry ({i},{j}) in an LP block",
                    name(c)
                )));
            }
            if !v.is_finite() {
                return Err(SdpError::NonFinite {
                    location: format!("{}, block {blk}, entry ({i},{j})", name(c)),
                    value: v,
                });
            }
            let (r, s) = if i <= j { (i, j) } else { (j, i) };
            per_block[blk].push((c, s, r, v));
        }
        let mut blocks = Vec::with_capacity(self.blocks.len());
        for (blk, mut list) in per_block.into_iter().enumerate() {
            // Sort by matrix (C first via wrapping order below), then column, then row.
            list.sort_by_key(|&(c, col, row, _)| (c.wrapping_add(1), col, row));
            let mut c_mat = SparseSym::default();
            let mut a: Vec<(usize, SparseSym)> = Vec::new();
            let mut k = 0;
            while k < list.len() {
                let (c, col, row, mut v) = list[k];
                k += 1;
                while k < list.len() && list[k].0 == c && list[k].1 == col && list[k].2 == row {
                    v += list[k].3;
                    k += 1;
                }
                if v == 0.0 {
                    continue;
                }
                let target = if c == OBJECTIVE {
                    &mut c_mat
                } else {
                    if a.last().is_none_or(|(ci, _)| *ci != c) {
                        a.push((c, SparseSym::default()));
                    }
                    &mut a.last_mut().expect("just pushed").1
                };
                target.rows.push(row);
                target.cols.push(col);
                target.vals.push(v);
            }
            blocks.push(BlockData {
                block: self.blocks[blk],
                c: c_mat,
                a,
            });
        }
        Ok(Problem { blocks, b: self.b })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builder_sums_duplicates_and_normalises_triangle() {
        let mut pb = ProblemBuilder::new(2);
        let b0 = pb.add_block(BlockKind::Psd, 2);
        let b1 = pb.add_block(BlockKind::Lp, 3);
        pb.set_b(0, 1.0).set_b(1, -2.0);
        pb.add_c(b0, 1, 0, 0.5).add_c(b0, 0, 1, 0.25);
        pb.add_a(1, b0, 0, 0, 1.0)
            .add_a(0, b1, 2, 2, 3.0)
            .add_a(1, b1, 0, 0, 0.0);
        let p = pb.build().unwrap();
        assert_eq!(p.num_constraints(), 2);
        assert_eq!(p.blocks[0].c.iter().collect::<Vec<_>>(), vec![(0, 1, 0.75)]);
        assert_eq!(p.blocks[0].a.len(), 1);
        assert_eq!(p.blocks[0].a[0].0, 1);
        // The explicit zero in block 1 for constraint 1 is dropped.
        assert_eq!(p.blocks[1].a.len(), 1);
        assert_eq!(p.blocks[1].a[0].0, 0);
    }

    #[test]
    fn dense_views_use_the_block_layout() {
        let mut pb = ProblemBuilder::new(2);
        let s = pb.add_block(BlockKind::Psd, 2);
        let l = pb.add_block(BlockKind::Lp, 3);
        pb.add_c(s, 1, 0, 0.5).add_c(l, 2, 2, -1.0);
        pb.add_a(1, s, 1, 1, 2.0).add_a(1, l, 0, 0, 3.0);
        let p = pb.build().unwrap();
        let c = p.dense_objective();
        assert_eq!(c[0], faer::mat![[0.0, 0.5], [0.5, 0.0]]);
        assert_eq!(c[1], faer::mat![[0.0], [0.0], [-1.0]]);
        let a0 = p.dense_constraint(0).unwrap();
        assert_eq!(a0[0], Mat::zeros(2, 2));
        assert_eq!(a0[1], Mat::zeros(3, 1));
        let a1 = p.dense_constraint(1).unwrap();
        assert_eq!(a1[0], faer::mat![[0.0, 0.0], [0.0, 2.0]]);
        assert_eq!(a1[1], faer::mat![[3.0], [0.0], [0.0]]);
        assert!(matches!(p.dense_constraint(2), Err(SdpError::Structure(_))));
    }

    #[test]
    fn builder_rejects_bad_entries() {
        let mut pb = ProblemBuilder::new(1);
        let lp = pb.add_block(BlockKind::Lp, 2);
        pb.add_a(0, lp, 0, 1, 1.0);
        assert!(matches!(pb.build(), Err(SdpError::Structure(_))));

        let mut pb = ProblemBuilder::new(1);
        let s = pb.add_block(BlockKind::Psd, 2);
        pb.add_a(0, s, 0, 2, 1.0);
        assert!(matches!(pb.build(), Err(SdpError::Structure(_))));

        let mut pb = ProblemBuilder::new(1);
        let s = pb.add_block(BlockKind::Psd, 2);
        pb.add_c(s, 0, 0, f64::NAN);
        assert!(matches!(pb.build(), Err(SdpError::NonFinite { .. })));

        let mut pb = ProblemBuilder::new(1);
        pb.set_b(3, 1.0);
        assert!(matches!(pb.build(), Err(SdpError::Structure(_))));
    }
}
