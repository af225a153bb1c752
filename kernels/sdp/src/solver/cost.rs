//! The cost matrix `C` in the form the residuals read it.
//!
//! The residuals need `C` entrywise (`R_d = C − 𝒜ᵀ(y) − S`) and through `⟨C, X⟩`. A block where
//! `C` is dense keeps the dense block; elsewhere only its nonzero entries are kept, in the
//! column-major order of the dense layout, so that every sum runs over the same terms in the
//! same order as over the dense block (the omitted terms are exact zeros) and the residuals are
//! bitwise those of the dense form. A max-cut or graph-partition `C` (a sparse Laplacian) then
//! costs its nonzeros instead of an `n×n` array beside the iterates.

use faer::Mat;

use super::blockops::{block_inner, scatter_sym, zero_block};
use super::structure::{Analysis, Values};

/// `C` of one block.
pub(crate) enum CostBlock {
    /// The dense block (PSD `n×n`, LP `n×1`).
    Dense(Mat<f64>),
    /// The nonzero entries `(i, j, C_ij)` of the dense layout (both triangles of a PSD block),
    /// column by column.
    Entries(Vec<(usize, usize, f64)>),
}

/// A block is kept dense when at least this fraction of its entries is nonzero (an entry of
/// [`CostBlock::Entries`] takes three words, a dense entry one).
const DENSE_FRACTION: f64 = 1.0 / 3.0;

/// `C`, block by block.
pub(crate) struct Cost(Vec<CostBlock>);

impl Cost {
    /// `C` of the problem analysed in `an`.
    pub(crate) fn new(an: &Analysis, vals: &Values) -> Self {
        Self(
            an.blocks
                .iter()
                .enumerate()
                .map(|(k, b)| {
                    let mut dense = zero_block(b);
                    scatter_sym(b.kind, &vals.c[k], 1.0, &mut dense);
                    let mut entries = Vec::new();
                    for j in 0..dense.ncols() {
                        for (i, &v) in dense.col_as_slice(j).iter().enumerate() {
                            if v != 0.0 {
                                entries.push((i, j, v));
                            }
                        }
                    }
                    let size = (dense.nrows() * dense.ncols()) as f64;
                    if entries.len() as f64 >= DENSE_FRACTION * size {
                        CostBlock::Dense(dense)
                    } else {
                        CostBlock::Entries(entries)
                    }
                })
                .collect(),
        )
    }

    /// Block `k`.
    pub(crate) fn block(&self, k: usize) -> &CostBlock {
        &self.0[k]
    }

    /// `‖C‖_F`.
    pub(crate) fn norm_fro(&self) -> f64 {
        let mut total = 0.0;
        for c in &self.0 {
            total += match c {
                CostBlock::Dense(c) => block_inner(c, c),
                CostBlock::Entries(e) => e.iter().fold(0.0, |s, &(_, _, v)| s + v * v),
            };
        }
        total.sqrt()
    }

    /// `max |C_ij|`.
    pub(crate) fn norm_max(&self) -> f64 {
        let mut max = 0.0f64;
        for c in &self.0 {
            match c {
                CostBlock::Dense(c) => {
                    for j in 0..c.ncols() {
                        max = c.col_as_slice(j).iter().fold(max, |m, v| m.max(v.abs()));
                    }
                }
                CostBlock::Entries(e) => max = e.iter().fold(max, |m, &(_, _, v)| m.max(v.abs())),
            }
        }
        max
    }
}

impl CostBlock {
    /// `f(i, j, C_ij)` for every entry of the dense layout of a block of shape `rows×cols`,
    /// column by column (`C_ij = 0` off the kept entries).
    pub(crate) fn for_each(&self, rows: usize, cols: usize, mut f: impl FnMut(usize, usize, f64)) {
        match self {
            CostBlock::Dense(c) => {
                for j in 0..cols {
                    for (i, &v) in c.col_as_slice(j).iter().enumerate() {
                        f(i, j, v);
                    }
                }
            }
            CostBlock::Entries(e) => {
                let mut next = e.iter().peekable();
                for j in 0..cols {
                    for i in 0..rows {
                        let v = match next.peek() {
                            Some(&&(ei, ej, v)) if (ei, ej) == (i, j) => {
                                next.next();
                                v
                            }
                            _ => 0.0,
                        };
                        f(i, j, v);
                    }
                }
            }
        }
    }

    /// `⟨C, X⟩` of the block, summed in the order of [`block_inner`].
    pub(crate) fn inner(&self, x: &Mat<f64>) -> f64 {
        match self {
            CostBlock::Dense(c) => block_inner(c, x),
            CostBlock::Entries(e) => e.iter().fold(0.0, |s, &(i, j, v)| s + v * x[(i, j)]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::{BlockKind, ProblemBuilder};
    use crate::solver::structure::analyse;
    use proptest::prelude::*;

    proptest! {
        /// Sparse and dense blocks give bitwise the entries, norms and inner products of the
        /// dense `C`.
        #[test]
        fn kept_entries_give_the_sums_of_the_dense_matrix(
            n in 1usize..=30,
            fill in 0usize..=60,
            seed in any::<u64>(),
        ) {
            let mut rng = crate::solver::XorShift(seed | 1);
            let mut builder = ProblemBuilder::new(1);
            let psd = builder.add_block(BlockKind::Psd, n);
            let lp = builder.add_block(BlockKind::Lp, n);
            builder.add_a(0, psd, 0, 0, 1.0);
            builder.set_b(0, 1.0);
            for _ in 0..fill * n / 10 {
                let (i, j) = ((rng.bits() as usize) % n, (rng.bits() as usize) % n);
                builder.add_c(psd, i.min(j), i.max(j), rng.centred());
                let l = (rng.bits() as usize) % n;
                builder.add_c(lp, l, l, rng.centred());
            }
            let problem = builder.build().expect("problem");
            let an = analyse(&problem).expect("analysis");
            let vals = an.values(&problem).expect("values");
            let dense: Vec<Mat<f64>> = an
                .blocks
                .iter()
                .enumerate()
                .map(|(k, b)| {
                    let mut c = zero_block(b);
                    scatter_sym(b.kind, &vals.c[k], 1.0, &mut c);
                    c
                })
                .collect();
            let cost = Cost::new(&an, &vals);
            let fro = dense.iter().fold(0.0, |t, c| t + block_inner(c, c)).sqrt();
            let max = dense
                .iter()
                .flat_map(|c| (0..c.ncols()).flat_map(move |j| c.col_as_slice(j).iter()))
                .fold(0.0f64, |m, v| m.max(v.abs()));
            prop_assert_eq!(cost.norm_fro().to_bits(), fro.to_bits());
            prop_assert_eq!(cost.norm_max().to_bits(), max.to_bits());
            for (k, c) in dense.iter().enumerate() {
                let x = Mat::from_fn(c.nrows(), c.ncols(), |_, _| rng.centred());
                prop_assert_eq!(cost.block(k).inner(&x).to_bits(), block_inner(c, &x).to_bits());
                let mut seen = Vec::new();
                cost.block(k).for_each(c.nrows(), c.ncols(), |i, j, v| seen.push((i, j, v)));
                let reference: Vec<_> = (0..c.ncols())
                    .flat_map(|j| (0..c.nrows()).map(move |i| (i, j)))
                    .map(|(i, j)| (i, j, c[(i, j)]))
                    .collect();
                prop_assert_eq!(seen, reference);
            }
        }
    }
}
