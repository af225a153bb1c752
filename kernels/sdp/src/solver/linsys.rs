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
//!    residual stops decreasing), which removes most of the error of steps 3–4.

use faer::linalg::cholesky::llt::factor::{
    LltRegularization, cholesky_in_place, cholesky_in_place_scratch,
};
use faer::linalg::solvers::Solve;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, Par, Side};

enum Factor {
    Llt,
    Lblt(faer::linalg::solvers::Lblt<f64>),
}

/// Factorised Schur matrix with reusable workspaces: the matrix itself (its lower triangle,
/// kept for the refinement residuals and the regularised retries) and its factor, two `m×m`
/// arrays in all.
pub(crate) struct SchurSolver {
    /// Lower triangle of `M` (the strict upper triangle is never read).
    m: Mat<f64>,
    /// Equilibration `D`.
    d: Vec<f64>,
    /// Cholesky factor of `M̃ (+ ρI)` when [`Factor::Llt`].
    l: Mat<f64>,
    factor: Factor,
    /// Regularisation `ρ` used by the last factorisation (`0` if none; `NaN` for LBLᵀ).
    pub regularization: f64,
    /// Whether some diagonal entry of `M` was not positive (an empty constraint, or rounding).
    empty_row: bool,
}

/// Rows of `M` whose entries above the diagonal [`SchurSolver::residual`] reads together, as a
/// contiguous piece of each column of the stored lower triangle.
const RESIDUAL_TILE: usize = 64;

impl SchurSolver {
    /// Workspaces for an `m×m` system.
    pub(crate) fn new(m: usize) -> Self {
        Self::with_matrix(Mat::zeros(m, m))
    }

    /// A solver for the matrix whose lower triangle is in `lower` (not yet factorised).
    pub(crate) fn with_matrix(lower: Mat<f64>) -> Self {
        let m = lower.nrows();
        Self {
            m: lower,
            d: vec![1.0; m],
            l: Mat::zeros(m, m),
            factor: Factor::Llt,
            regularization: 0.0,
            empty_row: false,
        }
    }

    /// The matrix to assemble `M` into (lower triangle) before [`SchurSolver::factorize`].
    pub(crate) fn matrix_mut(&mut self) -> &mut Mat<f64> {
        &mut self.m
    }

    fn try_llt(&mut self, rho: f64) -> bool {
        let m = self.m.nrows();
        for j in 0..m {
            for i in j..m {
                self.l[(i, j)] = self.d[i] * self.m[(i, j)] * self.d[j];
            }
            self.l[(j, j)] += rho;
        }
        let mut mem = faer::dyn_stack::MemBuffer::new(cholesky_in_place_scratch::<f64>(
            m,
            Par::Seq,
            Default::default(),
        ));
        let stack = faer::dyn_stack::MemStack::new(&mut mem);
        let ok = cholesky_in_place(
            self.l.as_mut(),
            LltRegularization::default(),
            Par::Seq,
            stack,
            Default::default(),
        )
        .is_ok();
        ok && (0..m).all(|i| self.l[(i, i)].is_finite() && self.l[(i, i)] > 0.0)
    }

    /// Factorises the matrix whose lower triangle is in [`SchurSolver::matrix_mut`] (the strict
    /// upper part is ignored). Returns `false` only if no factorisation produced finite numbers.
    pub(crate) fn factorize(&mut self) -> bool {
        let m = self.m.nrows();
        self.empty_row = false;
        for j in 0..m {
            let dj = self.m[(j, j)];
            self.d[j] = if dj > 0.0 && dj.is_finite() {
                1.0 / dj.sqrt()
            } else {
                self.empty_row = true;
                1.0
            };
        }
        self.factor = Factor::Llt;
        for rho in [0.0, 1e-12, 1e-10, 1e-8, 1e-6, 1e-4] {
            if self.try_llt(rho) {
                self.regularization = rho;
                return true;
            }
        }
        let scaled = Mat::from_fn(m, m, |i, j| {
            let (r, c) = if i >= j { (i, j) } else { (j, i) };
            self.d[i] * self.m[(r, c)] * self.d[j]
        });
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

    /// `r − M x`, every `res[i]` summed over `j = 0, 1, …` in order (the products of the
    /// nonzero `x_j` only), from the stored lower triangle. Tiles of [`RESIDUAL_TILE`] columns
    /// `J` are taken in order; within a tile the rows above it read `M[i, J] = M[J, i]`, a
    /// contiguous piece of column `i`, the rows of the tile read both triangles, and the rows below
    /// it read columns `j ∈ J`.
    fn residual(&self, r: &[f64], x: &[f64]) -> Vec<f64> {
        let m = r.len();
        let mut res = r.to_vec();
        let mut j0 = 0;
        while j0 < m {
            let j1 = (j0 + RESIDUAL_TILE).min(m);
            for (i, ri) in res.iter_mut().enumerate().take(j0) {
                let col = &self.m.col_as_slice(i)[j0..j1];
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
                            self.m[(i, j)]
                        } else {
                            self.m[(j, i)]
                        };
                        ri -= mij * xj;
                    }
                }
                res[i] = ri;
            }
            for (j, &xj) in x.iter().enumerate().take(j1).skip(j0) {
                if xj != 0.0 {
                    let col = &self.m.col_as_slice(j)[j1..];
                    for (ri, mij) in res[j1..].iter_mut().zip(col) {
                        *ri -= mij * xj;
                    }
                }
            }
            j0 = j1;
        }
        res
    }

    /// Solves `M x = r` with the current factorisation and iterative refinement.
    pub(crate) fn solve(&self, r: &[f64]) -> Vec<f64> {
        let mut x = self.apply_inverse(r);
        let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
        let mut res = self.residual(r, &x);
        let mut res_norm = norm(&res);
        let steps = if self.regularization == 0.0 { 2 } else { 8 };
        for _ in 0..steps {
            if !(res_norm > 0.0) {
                break;
            }
            let dx = self.apply_inverse(&res);
            let trial: Vec<f64> = x.iter().zip(&dx).map(|(a, b)| a + b).collect();
            let trial_res = self.residual(r, &trial);
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
    use super::{RESIDUAL_TILE, SchurSolver};
    use faer::Mat;
    use proptest::prelude::*;

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
        #[test]
        fn residual_from_the_lower_triangle_is_bitwise_the_full_one(
            m in 1usize..3 * RESIDUAL_TILE + 7,
            seed in any::<u64>(),
        ) {
            // A cheap deterministic generator: entries of mixed signs and magnitudes, some
            // exact zeros in x.
            let mut state = seed | 1;
            let mut next = move || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let u = (state >> 11) as f64 / (1u64 << 53) as f64;
                (u - 0.5) * 10f64.powi((state % 7) as i32 - 3)
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
            let solver = SchurSolver::with_matrix(lower);
            let tiled = solver.residual(&r, &x);
            let reference = by_columns(&full, &r, &x);
            prop_assert!(tiled.iter().zip(&reference).all(|(a, b)| a.to_bits() == b.to_bits()));
        }
    }
}
