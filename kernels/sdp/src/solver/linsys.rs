//! Solving the Schur-complement system `M Δy = r`.
//!
//! `M` is symmetric positive definite in exact arithmetic when the `A_i` are linearly
//! independent, but near the optimum it becomes very ill-conditioned and rounding (or dependent,
//! duplicate or empty constraints) can destroy definiteness. The strategy follows SDPT3's
//! `linsysolve.m` and CSDP:
//!
//! 1. symmetric diagonal equilibration `M̃ = D M D`, `D = diag(M)^{-1/2}` (unit diagonal; rows of
//!    constraints that touch no block get `D_ii = 1`);
//! 2. dense Cholesky `M̃ = L Lᵀ` (faer, blocked, left-looking);
//! 3. on failure, Cholesky of `M̃ + ρ I` for `ρ = 10⁻¹², 10⁻¹⁰, …, 10⁻⁴` (SDPT3 adds
//!    `ρ·diag(M)`, which is the same after equilibration);
//! 4. if that still fails, a Bunch–Kaufman `L B Lᵀ` factorisation of `M̃`;
//! 5. iterative refinement against the unregularised `M` (a few steps, stopped as soon as the
//!    residual stops decreasing), which removes most of the error of steps 3–4; the residuals
//!    come from a copy of `M` (its lower triangle, packed) or, where that is cheaper than the
//!    memory it takes, from the operators that define `M` ([`keeps_copy`]), and the Cholesky
//!    factor overwrites `M`.

use faer::linalg::cholesky::llt::factor::{
    LltRegularization, cholesky_in_place, cholesky_in_place_scratch,
};
use faer::linalg::solvers::Solve;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, Par, Side};

use super::structure::Analysis;
use crate::problem::BlockKind;

enum Factor {
    Llt,
    Lblt(faer::linalg::solvers::Lblt<f64>),
}

/// The product `v ↦ M v` formed from the operators that define `M` (for the Schur matrix of the
/// HKM direction `𝒜(X 𝒜ᵀ(v) S⁻¹)`, [`super::direction`]): the refinement residuals of a solver
/// that keeps no copy of `M`.
pub(crate) type Product<'a> = &'a dyn Fn(&[f64]) -> Vec<f64>;

/// Factorised Schur matrix with reusable workspaces.
///
/// Memory contract: the matrix is assembled into the array that then holds its Cholesky factor
/// (in place), so a solver holds one `m×m` array, plus a copy of the lower triangle of `M`
/// (`m(m+1)/2` entries, [`Packed`]) only when it keeps one ([`keeps_copy`]): the copy then
/// serves the refinement residuals and the regularised retries. Without it the residuals come from the caller's [`Product`], and a retry after a
/// failed factorisation re-assembles `M` (rare: only near the end of ill-conditioned solves).
/// The Bunch–Kaufman fallback keeps faer's factor instead of the Cholesky array (transiently
/// both while it factorises).
pub(crate) struct SchurSolver {
    /// Lower triangle of `M` until [`SchurSolver::factorize`] (the strict upper triangle is
    /// never read), then the Cholesky factor of `M̃ (+ ρI)` when [`Factor::Llt`]; `0×0` after
    /// the LBLᵀ fallback until the next assembly.
    l: Mat<f64>,
    /// Whether [`SchurSolver::copy`] holds `M`.
    keep: bool,
    /// Lower triangle of `M`, saved by [`SchurSolver::factorize`] when [`SchurSolver::keep`].
    copy: Packed,
    /// Equilibration `D`.
    d: Vec<f64>,
    factor: Factor,
    /// Regularisation `ρ` used by the last factorisation (`0` if none; `NaN` for LBLᵀ).
    pub regularization: f64,
    /// Whether some diagonal entry of `M` was not positive (an empty constraint, or rounding).
    empty_row: bool,
}

/// Lower triangle of a symmetric matrix, packed by columns (column `j` holds rows `j..m`), as
/// LAPACK's `'L'` packed storage: half the memory of the square array.
struct Packed {
    m: usize,
    data: Vec<f64>,
}

impl Packed {
    /// Empty (no matrix kept).
    fn empty() -> Self {
        Self {
            m: 0,
            data: Vec::new(),
        }
    }

    /// Copies the lower triangle of `a` (the strict upper triangle is not read).
    fn lower_of(&mut self, a: &Mat<f64>) {
        let m = a.nrows();
        self.m = m;
        self.data.clear();
        self.data.reserve_exact(m * (m + 1) / 2);
        for j in 0..m {
            self.data.extend_from_slice(&a.col_as_slice(j)[j..]);
        }
    }

    /// Column `j` from row `i ≥ j` to row `end` (exclusive).
    fn col(&self, j: usize, i: usize, end: usize) -> &[f64] {
        let offset = self.offset(j);
        &self.data[offset + (i - j)..offset + (end - j)]
    }

    /// Index of entry `(j, j)`: the columns before `j` hold `m + (m − 1) + … + (m − j + 1)`
    /// entries.
    fn offset(&self, j: usize) -> usize {
        j * self.m - j * j.saturating_sub(1) / 2
    }

    /// `M_ij` for `i ≥ j`.
    fn get(&self, i: usize, j: usize) -> f64 {
        self.data[self.offset(j) + (i - j)]
    }
}

/// Rows of `M` whose entries above the diagonal [`SchurSolver::residual`] reads together, as a
/// contiguous piece of each column of the stored lower triangle.
const RESIDUAL_TILE: usize = 64;

/// [`keeps_copy`]: the operator product is used when its flops are at most this multiple of
/// the `2m²` of a residual from the stored matrix (the product runs as dense matrix products
/// at several times the speed of the memory-bound pass over `M`).
const PRODUCT_FLOP_RATIO: f64 = 8.0;

/// A copy of `M` with fewer entries than this (8 MiB) is always kept: it costs little beside
/// the process itself, and the residuals from the stored matrix keep the directions of the
/// small ill-conditioned problems bitwise as they were (with operator residuals hinf15 ended
/// in numerical trouble instead of almost optimal, and most hinf problems moved at the 8th
/// digit).
const SMALL_COPY: usize = 1 << 20;

/// [`keeps_copy`]: a copy of `M` larger than this many arrays of the blocks' size is not kept
/// (an iteration holds about ten: `X`, `S`, their inverse factors, `S⁻¹`, the dual residual,
/// a direction and the step-length temporaries).
const ITERATE_ARRAYS: f64 = 10.0;

/// Whether the Schur solver of `an` keeps a copy of `M` for its refinement residuals: when the
/// copy is small ([`SMALL_COPY`]), or when the operator product `𝒜(X 𝒜ᵀ(v) S⁻¹)` (two dense
/// products per PSD block, `4n³` flops, and two passes over the constraint entries) would
/// cost more than [`PRODUCT_FLOP_RATIO`] times a pass over `M` and the copy is no larger than
/// [`ITERATE_ARRAYS`] arrays of the blocks. Problems with one or a few large blocks and `m`
/// about their order (maxG, mcp, qpG, thetaG11) keep it; problems whose `m` is large and far
/// exceeds the block orders (theta3–6: `m = 1106…4375`, `n = 150…300`; thetaG51: `m = 6910`,
/// `n = 1001`, whose copy would take 191 MB, more than all its iterates) form the residuals
/// from the operators and hold `M` once.
pub(crate) fn keeps_copy(an: &Analysis) -> bool {
    let product: f64 = an
        .blocks
        .iter()
        .map(|b| {
            let n = b.n as f64;
            let entries: usize = b.cons.iter().map(|c| c.rows.len()).sum();
            let dense = match b.kind {
                BlockKind::Psd => 4.0 * n * n * n,
                BlockKind::Lp => 3.0 * n,
            };
            dense + 4.0 * entries as f64
        })
        .sum();
    let arrays: f64 = an
        .blocks
        .iter()
        .map(|b| match b.kind {
            BlockKind::Psd => (b.n * b.n) as f64,
            BlockKind::Lp => b.n as f64,
        })
        .sum();
    an.m.saturating_mul(an.m) < SMALL_COPY || {
        let m = an.m as f64;
        product > PRODUCT_FLOP_RATIO * 2.0 * m * m && m * (m + 1.0) / 2.0 <= ITERATE_ARRAYS * arrays
    }
}

impl SchurSolver {
    /// Workspaces for an `m×m` system; `keep` as decided by [`keeps_copy`].
    pub(crate) fn new(m: usize, keep: bool) -> Self {
        Self {
            l: Mat::zeros(m, m),
            keep,
            copy: Packed::empty(),
            d: vec![1.0; m],
            factor: Factor::Llt,
            regularization: 0.0,
            empty_row: false,
        }
    }

    /// A solver for the matrix whose lower triangle is in `lower` (not yet factorised), keeping
    /// it for the residuals.
    pub(crate) fn with_matrix(lower: Mat<f64>) -> Self {
        let m = lower.nrows();
        Self {
            l: lower,
            keep: true,
            d: vec![1.0; m],
            ..Self::new(0, false)
        }
    }

    /// The matrix to assemble `M` into (lower triangle) before [`SchurSolver::factorize`].
    pub(crate) fn matrix_mut(&mut self) -> &mut Mat<f64> {
        self.cholesky_array()
    }

    /// The `m×m` array of the Cholesky factor, allocated again after the LBLᵀ fallback freed it.
    fn cholesky_array(&mut self) -> &mut Mat<f64> {
        let m = self.d.len();
        if self.l.nrows() != m {
            self.l = Mat::zeros(m, m);
        }
        &mut self.l
    }

    /// Scales the lower triangle of `M` (from the copy, or in place) to `M̃ + ρI` and factorises
    /// it in place.
    fn try_llt(&mut self, rho: f64) -> bool {
        let m = self.d.len();
        self.cholesky_array();
        let Self {
            l, keep, copy, d, ..
        } = self;
        for j in 0..m {
            for i in j..m {
                let mij = if *keep { copy.get(i, j) } else { l[(i, j)] };
                l[(i, j)] = d[i] * mij * d[j];
            }
            l[(j, j)] += rho;
        }
        let mut mem = faer::dyn_stack::MemBuffer::new(cholesky_in_place_scratch::<f64>(
            m,
            Par::Seq,
            Default::default(),
        ));
        let stack = faer::dyn_stack::MemStack::new(&mut mem);
        let ok = cholesky_in_place(
            l.as_mut(),
            LltRegularization::default(),
            Par::Seq,
            stack,
            Default::default(),
        )
        .is_ok();
        ok && (0..m).all(|i| l[(i, i)].is_finite() && l[(i, i)] > 0.0)
    }

    /// Factorises the matrix whose lower triangle is in [`SchurSolver::matrix_mut`] (the strict
    /// upper part is ignored). Without a copy of `M`, every attempt after a failed one first
    /// calls `reassemble` to write the lower triangle of `M` into the given array again (bitwise
    /// the first assembly, so the result is what it would be with a copy). Returns `false` only
    /// if no factorisation produced finite numbers.
    pub(crate) fn factorize(&mut self, mut reassemble: impl FnMut(&mut Mat<f64>)) -> bool {
        let m = self.d.len();
        self.empty_row = false;
        if self.keep {
            self.copy.lower_of(&self.l);
        }
        for j in 0..m {
            let dj = self.l[(j, j)];
            self.d[j] = if dj > 0.0 && dj.is_finite() {
                1.0 / dj.sqrt()
            } else {
                self.empty_row = true;
                1.0
            };
        }
        self.factor = Factor::Llt;
        for (attempt, rho) in [0.0, 1e-12, 1e-10, 1e-8, 1e-6, 1e-4]
            .into_iter()
            .enumerate()
        {
            if attempt > 0 && !self.keep {
                reassemble(&mut self.l);
            }
            if self.try_llt(rho) {
                self.regularization = rho;
                return true;
            }
        }
        // `D M D` in both triangles, each entry formed as `d_i·m_ij·d_j` in the order of its
        // own row and column, in the Cholesky array (freed after faer has copied it).
        let mut scaled = std::mem::replace(self.cholesky_array(), Mat::new());
        if !self.keep {
            reassemble(&mut scaled);
        }
        for j in 0..m {
            for i in j..m {
                let mij = if self.keep {
                    self.copy.get(i, j)
                } else {
                    scaled[(i, j)]
                };
                scaled[(i, j)] = self.d[i] * mij * self.d[j];
                scaled[(j, i)] = self.d[j] * mij * self.d[i];
            }
        }
        if !scaled.col_iter().all(|c| c.iter().all(|v| v.is_finite())) {
            return false;
        }
        self.factor = Factor::Lblt(scaled.lblt(Side::Lower));
        self.regularization = f64::NAN;
        true
    }

    /// `(M̃ + ρI)⁻¹` in the unscaled variables, `D (L Lᵀ)⁻¹ D`: a fixed symmetric positive
    /// definite approximation of `M⁻¹` (the preconditioner of [`super::direction`]'s conjugate
    /// gradients), or `None` after the indefinite fallback factorisation or when a diagonal
    /// entry of `M` is not positive (an empty constraint makes `M` singular, and conjugate
    /// gradients would diverge along it).
    pub(crate) fn preconditioner(&self) -> Option<impl Fn(&[f64]) -> Vec<f64> + '_> {
        (matches!(self.factor, Factor::Llt) && !self.empty_row)
            .then_some(move |r: &[f64]| self.apply_inverse(r))
    }

    fn apply_inverse(&self, r: &[f64]) -> Vec<f64> {
        let m = r.len();
        let mut z = Mat::from_fn(m, 1, |i, _| self.d[i] * r[i]);
        match &self.factor {
            Factor::Llt => {
                solve_lower_triangular_in_place(self.l.as_ref(), z.as_mut(), Par::Seq);
                solve_upper_triangular_in_place(self.l.transpose(), z.as_mut(), Par::Seq);
            }
            Factor::Lblt(f) => z = f.solve(&z),
        }
        (0..m).map(|i| self.d[i] * z[(i, 0)]).collect()
    }

    /// `r − M x`: from the stored copy ([`SchurSolver::stored_residual`]), or `r − product(x)`.
    fn residual(&self, r: &[f64], x: &[f64], product: Option<Product<'_>>) -> Vec<f64> {
        if self.keep {
            return self.stored_residual(r, x);
        }
        let product = product.expect("a Schur solver without a copy of M needs its product");
        r.iter().zip(product(x)).map(|(ri, mi)| ri - mi).collect()
    }

    /// `r − M x`, every `res[i]` summed over `j = 0, 1, …` in order (the products of the
    /// nonzero `x_j` only), from the stored lower triangle. Tiles of [`RESIDUAL_TILE`] columns
    /// `J` are taken in order; within a tile the rows above it read `M[i, J] = M[J, i]`, a
    /// contiguous piece of column `i`, the rows of the tile read both triangles, and the rows below
    /// it read columns `j ∈ J`.
    fn stored_residual(&self, r: &[f64], x: &[f64]) -> Vec<f64> {
        let m = r.len();
        let mut res = r.to_vec();
        let mut j0 = 0;
        while j0 < m {
            let j1 = (j0 + RESIDUAL_TILE).min(m);
            for (i, ri) in res.iter_mut().enumerate().take(j0) {
                let col = self.copy.col(i, j0, j1);
                for (mij, &xj) in col.iter().zip(&x[j0..j1]) {
                    if xj != 0.0 {
                        *ri -= mij * xj;
                    }
                }
            }
            for i in j0..j1 {
                let mut ri = res[i];
                for (j, &xj) in x.iter().enumerate().take(j1).skip(j0) {
                    if xj != 0.0 {
                        let mij = if j <= i {
                            self.copy.get(i, j)
                        } else {
                            self.copy.get(j, i)
                        };
                        ri -= mij * xj;
                    }
                }
                res[i] = ri;
            }
            for (j, &xj) in x.iter().enumerate().take(j1).skip(j0) {
                if xj != 0.0 {
                    let col = self.copy.col(j, j1, m);
                    for (ri, mij) in res[j1..].iter_mut().zip(col) {
                        *ri -= mij * xj;
                    }
                }
            }
            j0 = j1;
        }
        res
    }

    /// Solves `M x = r` with the current factorisation and iterative refinement; `product`
    /// forms the residuals of a solver without a copy of `M` (ignored, and may be `None`, when
    /// it keeps one).
    pub(crate) fn solve(&self, r: &[f64], product: Option<Product<'_>>) -> Vec<f64> {
        let mut x = self.apply_inverse(r);
        let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
        let mut res = self.residual(r, &x, product);
        let mut res_norm = norm(&res);
        let steps = if self.regularization == 0.0 { 2 } else { 8 };
        for _ in 0..steps {
            if !(res_norm > 0.0) {
                break;
            }
            let dx = self.apply_inverse(&res);
            let trial: Vec<f64> = x.iter().zip(&dx).map(|(a, b)| a + b).collect();
            let trial_res = self.residual(r, &trial, product);
            let trial_norm = norm(&trial_res);
            if trial_norm < 0.5 * res_norm {
                x = trial;
                res = trial_res;
                res_norm = trial_norm;
            } else {
                if trial_norm < res_norm {
                    x = trial;
                }
                break;
            }
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::{RESIDUAL_TILE, SchurSolver, keeps_copy};
    use crate::problem::{BlockKind, ProblemBuilder};
    use crate::solver::structure::analyse;
    use faer::Mat;
    use proptest::prelude::*;

    /// The memory contract on the two shapes of large SDPLIB problems: a Lovász theta problem
    /// (`m` far above the block order) holds `M` once, factorised in place; a max-cut relaxation
    /// (`m = n`, diagonal constraints) keeps the copy, which is no larger than an iterate.
    #[test]
    fn theta_holds_the_schur_matrix_once_and_max_cut_keeps_its_copy() {
        let n = 64;
        // theta: `tr X = 1` and `X_ij = 0` on the edges of a circulant graph of degree 32
        // (`m = 1025`, the shape of theta6: `m = 4375`, `n = 300`).
        let edges: Vec<(usize, usize)> = (0..n)
            .flat_map(|i| (1..=16).map(move |d| (i, (i + d) % n)))
            .map(|(i, j)| (i.min(j), i.max(j)))
            .collect();
        let mut theta = ProblemBuilder::new(1 + edges.len());
        let block = theta.add_block(BlockKind::Psd, n);
        theta.set_b(0, 1.0);
        for i in 0..n {
            theta.add_a(0, block, i, i, 1.0);
            for j in i..n {
                theta.add_c(block, i, j, 1.0);
            }
        }
        for (e, &(i, j)) in edges.iter().enumerate() {
            theta.add_a(1 + e, block, i, j, 1.0);
        }
        let theta = analyse(&theta.build().expect("theta")).expect("analysis");
        assert!(!keeps_copy(&theta));
        let m = theta.m;
        let mut solver = SchurSolver::new(m, keeps_copy(&theta));
        for i in 0..m {
            solver.matrix_mut()[(i, i)] = 2.0;
        }
        assert!(solver.factorize(|_| unreachable!("a definite M factorises at once")));
        assert_eq!(
            (solver.l.nrows(), solver.copy.data.len()),
            (m, 0),
            "one m×m array"
        );
        // max-cut: `X_ii = 1`, `C` the Laplacian of the same graph.
        let mut max_cut = ProblemBuilder::new(n);
        let block = max_cut.add_block(BlockKind::Psd, n);
        for i in 0..n {
            max_cut.set_b(i, 1.0);
            max_cut.add_a(i, block, i, i, 1.0);
        }
        for &(i, j) in &edges {
            max_cut.add_c(block, i, j, -0.25);
        }
        let max_cut = analyse(&max_cut.build().expect("max-cut")).expect("analysis");
        assert!(keeps_copy(&max_cut));
        // theta on 300 vertices with 1999 edges (the shape of thetaG51: `m = 6910`, `n = 1001`):
        // the product costs more than a pass over `M` (1.1·10⁸ against 6.4·10⁷ flops), but the
        // copy (2.0·10⁶ entries) would be larger than ten iterates (9·10⁵), so it is not kept.
        let n = 300;
        let mut theta = ProblemBuilder::new(2000);
        let block = theta.add_block(BlockKind::Psd, n);
        theta.set_b(0, 1.0);
        for i in 0..n {
            theta.add_a(0, block, i, i, 1.0);
        }
        let edges = (0..n).flat_map(|i| (1..=7).map(move |d| (i, (i + d) % n)));
        for (e, (i, j)) in edges.take(1999).enumerate() {
            theta.add_a(1 + e, block, i.min(j), i.max(j), 1.0);
        }
        let theta = analyse(&theta.build().expect("theta")).expect("analysis");
        assert!(!keeps_copy(&theta));
    }

    /// `r − M x` from the full symmetric matrix, column by column (each `res[i]` summed over
    /// `j` in order, zero `x_j` skipped): the reference the tiled residual must equal bitwise.
    fn by_columns(full: &Mat<f64>, r: &[f64], x: &[f64]) -> Vec<f64> {
        let mut res = r.to_vec();
        for (j, &xj) in x.iter().enumerate() {
            if xj == 0.0 {
                continue;
            }
            for (ri, mij) in res.iter_mut().zip(full.col_as_slice(j)) {
                *ri -= mij * xj;
            }
        }
        res
    }

    proptest! {
        /// A solver that factorises `M` in place (re-assembling it for every retry) computes
        /// the factorisation of the one that keeps a copy, bitwise: on positive definite
        /// matrices, on rank-deficient ones (regularised retries) and on indefinite ones (the
        /// LBLᵀ fallback); and with the exact product its refined solution agrees to rounding.
        #[test]
        fn factorising_in_place_gives_the_factor_of_the_copy(
            m in 1usize..40,
            kind in 0usize..3,
            seed in any::<u64>(),
        ) {
            let mut rng = crate::solver::XorShift(seed | 1);
            let mut next = move || rng.centred();
            // `B Bᵀ` with `B` of rank `m` (definite), `m / 2` (singular) or `B J Bᵀ` with a
            // signature `J` of both signs (indefinite).
            let rank = if kind == 1 { m.div_ceil(2) } else { m };
            let b = Mat::from_fn(m, rank, |_, _| next());
            let full = Mat::from_fn(m, m, |i, j| {
                (0..rank)
                    .map(|k| {
                        let sign = if kind == 2 && k % 2 == 1 { -1.0 } else { 1.0 };
                        sign * b[(i, k)] * b[(j, k)]
                    })
                    .sum::<f64>()
            });
            let lower = Mat::from_fn(m, m, |i, j| if i >= j { full[(i, j)] } else { 0.0 });
            let mut kept = SchurSolver::with_matrix(lower.clone());
            let factorised = kept.factorize(|_| {});
            prop_assert!(factorised);
            let mut in_place = SchurSolver::new(m, false);
            in_place.matrix_mut().copy_from(&lower);
            let mut reassembled = 0;
            let factorised = in_place.factorize(|out| {
                reassembled += 1;
                out.copy_from(&lower);
            });
            prop_assert!(factorised);
            prop_assert_eq!(
                kept.regularization.to_bits(),
                in_place.regularization.to_bits()
            );
            prop_assert_eq!(reassembled > 0, kept.regularization != 0.0);
            let r: Vec<f64> = (0..m).map(|_| next()).collect();
            let (a, b) = (kept.apply_inverse(&r), in_place.apply_inverse(&r));
            prop_assert!(a.iter().zip(&b).all(|(u, v)| u.to_bits() == v.to_bits()));
            if kind == 0 {
                let product = |v: &[f64]| -> Vec<f64> {
                    (0..m).map(|i| (0..m).map(|j| full[(i, j)] * v[j]).sum()).collect()
                };
                let (a, b) = (kept.solve(&r, None), in_place.solve(&r, Some(&product)));
                let scale = a.iter().fold(0.0f64, |s, v| s.max(v.abs()));
                // Two backward-stable solutions differ by up to `m ε cond(M)` relative: a random
                // `BBᵀ` can have `cond(M) = cond(B)² ≈ 1.5e11` (m = 11: 1.9e-6 apart, each with
                // a residual of 2e-7).
                let sv = full.singular_values().expect("singular values");
                let cond = sv[0] / sv[m - 1];
                let tolerance = 1e-6f64.max(m as f64 * f64::EPSILON * cond);
                prop_assert!(a.iter().zip(&b).all(|(u, v)| (u - v).abs() <= tolerance * scale));
            }
        }

        #[test]
        fn residual_from_the_lower_triangle_is_bitwise_the_full_one(
            m in 1usize..3 * RESIDUAL_TILE + 7,
            seed in any::<u64>(),
        ) {
            // A cheap deterministic generator: entries of mixed signs and magnitudes, some
            // exact zeros in x.
            let mut rng = crate::solver::XorShift(seed | 1);
            let mut next = move || {
                let bits = rng.bits();
                let u = (bits >> 11) as f64 / (1u64 << 53) as f64;
                (u - 0.5) * 10f64.powi((bits % 7) as i32 - 3)
            };
            let mut full = Mat::<f64>::zeros(m, m);
            for j in 0..m {
                for i in j..m {
                    let v = next();
                    full[(i, j)] = v;
                    full[(j, i)] = v;
                }
            }
            let r: Vec<f64> = (0..m).map(|_| next()).collect();
            let x: Vec<f64> = (0..m).map(|i| if i % 5 == 3 { 0.0 } else { next() }).collect();
            // Only the lower triangle is given; the upper one holds garbage that must not be read.
            let lower = Mat::from_fn(m, m, |i, j| if i >= j { full[(i, j)] } else { f64::NAN });
            let mut solver = SchurSolver::with_matrix(lower);
            solver.copy.lower_of(&solver.l);
            let tiled = solver.stored_residual(&r, &x);
            let reference = by_columns(&full, &r, &x);
            prop_assert!(tiled.iter().zip(&reference).all(|(a, b)| a.to_bits() == b.to_bits()));
        }
    }
}
