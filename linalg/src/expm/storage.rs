//! Square-matrix storage backends for the scaling-and-squaring algorithm.
//!
//! [`pade`](super::pade) is written once, generically over [`SquareStorage`]; this module
//! provides the two backends it is instantiated with:
//!
//! * [`SmallMat<N>`]: a stack-allocated, column-major `[[f64; N]; N]` with fully unrolled
//!   loops and an in-register LU with partial pivoting. faer's per-call overhead (≈ 0.7–1.6 µs
//!   for `partial_piv_lu` at n = 2…8, ≈ 70–140 ns per matmul, plus ≈ 0.2 µs per `Mat`
//!   allocation, measured on the project machine) dominates the arithmetic for such orders,
//!   so `expm` dispatches orders 2…8 here, and orders 9…16 padded to 16 (see `expm::load`).
//!   The kernels are plain loops over fixed-size arrays; the drivers run them under
//!   `pulp::Arch::dispatch`, so they are auto-vectorised for AVX2/FMA when available.
//! * [`faer::Mat<f64>`]: faer's GEMM (`Par::Seq` below [`PARALLEL_MIN_ORDER`]) and faer's
//!   in-place partial-pivoting LU with preallocated permutations and scratch memory, so a
//!   reused workspace does not allocate.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};

/// Order from which faer's parallel GEMM (global parallelism setting) is used; below it the
/// sequential kernel is faster on small machines (faer-expm.md §1.6).
pub(crate) const PARALLEL_MIN_ORDER: usize = 256;

/// `(V − U)` had a zero (or non-finite) pivot in the LU factorisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SingularPivot;

/// The operations Algorithm 6.1 of Al-Mohy & Higham (2009) needs from a square matrix.
pub(crate) trait SquareStorage: Sized {
    /// Length-n work vector (for the |A|ᵀ power iteration of ℓ(A, m)).
    type Vector: AsRef<[f64]> + AsMut<[f64]>;
    /// Reusable scratch for the LU solve.
    type LuScratch;

    /// A zero matrix of order `n` (the small backend ignores `n`).
    fn zeros(n: usize) -> Self;
    /// A zero work vector of length `n`.
    fn zero_vector(n: usize) -> Self::Vector;
    /// Scratch memory for [`SquareStorage::lu_solve`] at order `n`.
    fn lu_scratch(n: usize) -> Self::LuScratch;
    /// The order n.
    fn order(&self) -> usize;
    /// Entry (i, j).
    fn get(&self, i: usize, j: usize) -> f64;
    /// Sets entry (i, j).
    fn set(&mut self, i: usize, j: usize, value: f64);
    /// `self ← src`.
    fn assign(&mut self, src: &Self);
    /// `self ← c·self`.
    fn scale(&mut self, c: f64);
    /// `self ← a·b`.
    fn assign_product(&mut self, a: &Self, b: &Self);
    /// `self ← accumulate·self + c0·I + Σ cₖ·Mₖ` (`accumulate` is 0 or 1).
    fn combine(&mut self, accumulate: bool, c0: f64, terms: &[(f64, &Self)]);
    /// `self ← a − b` and `other ← a + b` in one sweep (forms V−U and V+U).
    fn difference_and_sum(diff: &mut Self, sum: &mut Self, a: &Self, b: &Self);
    /// Induced 1-norm max_j Σ_i |a_ij|.
    fn norm1(&self) -> f64;
    /// `self ← |src|ᵀ` (entrywise absolute value, transposed).
    fn assign_abs_transpose(&mut self, src: &Self);
    /// `y ← self·x` (column-oriented, so the inner loop vectorises); returns max_i y_i.
    fn matvec_max(&self, x: &Self::Vector, y: &mut Self::Vector) -> f64;
    /// Solves `q·X = p` by LU with partial pivoting, overwriting `p` with X and `q` with its
    /// factors.
    fn lu_solve(
        q: &mut Self,
        p: &mut Self,
        scratch: &mut Self::LuScratch,
    ) -> Result<(), SingularPivot>;
    /// Whether every entry is finite.
    fn all_finite(&self) -> bool;
}

/// Column-major stack matrix of order `N` (`self.0[j][i]` is entry (i, j)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SmallMat<const N: usize>(pub(crate) [[f64; N]; N]);

impl<const N: usize> SquareStorage for SmallMat<N> {
    type Vector = [f64; N];
    type LuScratch = ();

    #[inline(always)]
    fn zeros(_n: usize) -> Self {
        Self([[0.0; N]; N])
    }
    #[inline(always)]
    fn zero_vector(_n: usize) -> [f64; N] {
        [0.0; N]
    }
    #[inline(always)]
    fn lu_scratch(_n: usize) {}
    #[inline(always)]
    fn order(&self) -> usize {
        N
    }
    #[inline(always)]
    fn get(&self, i: usize, j: usize) -> f64 {
        self.0[j][i]
    }
    #[inline(always)]
    fn set(&mut self, i: usize, j: usize, value: f64) {
        self.0[j][i] = value;
    }
    #[inline(always)]
    fn assign(&mut self, src: &Self) {
        *self = *src;
    }
    #[inline(always)]
    fn scale(&mut self, c: f64) {
        for col in &mut self.0 {
            for x in col {
                *x *= c;
            }
        }
    }
    #[inline(always)]
    fn assign_product(&mut self, a: &Self, b: &Self) {
        // Two output columns per pass: each column of `a` is loaded once for both.
        let mut j = 0;
        while j + 1 < N {
            let (mut c0, mut c1) = ([0.0; N], [0.0; N]);
            for k in 0..N {
                let (b0, b1) = (b.0[j][k], b.0[j + 1][k]);
                let ak = &a.0[k];
                for i in 0..N {
                    c0[i] += ak[i] * b0;
                    c1[i] += ak[i] * b1;
                }
            }
            self.0[j] = c0;
            self.0[j + 1] = c1;
            j += 2;
        }
        if j < N {
            let mut c0 = [0.0; N];
            for k in 0..N {
                let b0 = b.0[j][k];
                for i in 0..N {
                    c0[i] += a.0[k][i] * b0;
                }
            }
            self.0[j] = c0;
        }
    }
    #[inline(always)]
    fn combine(&mut self, accumulate: bool, c0: f64, terms: &[(f64, &Self)]) {
        if !accumulate {
            self.0 = [[0.0; N]; N];
        }
        for &(c, m) in terms {
            for j in 0..N {
                for i in 0..N {
                    self.0[j][i] += c * m.0[j][i];
                }
            }
        }
        for k in 0..N {
            self.0[k][k] += c0;
        }
    }
    #[inline(always)]
    fn difference_and_sum(diff: &mut Self, sum: &mut Self, a: &Self, b: &Self) {
        for j in 0..N {
            for i in 0..N {
                diff.0[j][i] = a.0[j][i] - b.0[j][i];
                sum.0[j][i] = a.0[j][i] + b.0[j][i];
            }
        }
    }
    #[inline(always)]
    fn norm1(&self) -> f64 {
        let mut best = 0.0f64;
        for col in &self.0 {
            let s: f64 = col.iter().map(|x| x.abs()).sum();
            // `max` would drop a NaN column sum; keep it visible.
            if s > best || s.is_nan() {
                best = s;
            }
        }
        best
    }
    #[inline(always)]
    fn assign_abs_transpose(&mut self, src: &Self) {
        for j in 0..N {
            for i in 0..N {
                self.0[j][i] = src.0[i][j].abs();
            }
        }
    }
    #[inline(always)]
    fn matvec_max(&self, x: &[f64; N], y: &mut [f64; N]) -> f64 {
        let mut acc = [0.0; N];
        for k in 0..N {
            let xk = x[k];
            let col = &self.0[k];
            for i in 0..N {
                acc[i] += col[i] * xk;
            }
        }
        *y = acc;
        acc.iter().fold(0.0, |m, &v| if v > m { v } else { m })
    }
    #[inline(always)]
    fn lu_solve(q: &mut Self, p: &mut Self, _scratch: &mut ()) -> Result<(), SingularPivot> {
        // Gaussian elimination with partial pivoting applied to [q | p] (Golub & Van Loan,
        // Algorithm 3.4.1), then back substitution with the reciprocal pivots.
        let mut inv_diag = [0.0; N];
        for k in 0..N {
            let mut piv = k;
            let mut big = q.0[k][k].abs();
            for i in k + 1..N {
                let v = q.0[k][i].abs();
                if v > big {
                    big = v;
                    piv = i;
                }
            }
            if big == 0.0 || !big.is_finite() {
                return Err(SingularPivot);
            }
            if piv != k {
                for j in 0..N {
                    q.0[j].swap(k, piv);
                    p.0[j].swap(k, piv);
                }
            }
            let inv = 1.0 / q.0[k][k];
            inv_diag[k] = inv;
            // Multipliers (zero above row k so the updates below run over whole columns).
            let mut l = [0.0; N];
            for i in k + 1..N {
                l[i] = q.0[k][i] * inv;
            }
            for j in k + 1..N {
                let ukj = q.0[j][k];
                for i in 0..N {
                    q.0[j][i] -= l[i] * ukj;
                }
            }
            for j in 0..N {
                let pkj = p.0[j][k];
                for i in 0..N {
                    p.0[j][i] -= l[i] * pkj;
                }
            }
        }
        for j in 0..N {
            let col = &mut p.0[j];
            for k in (0..N).rev() {
                let x = col[k] * inv_diag[k];
                col[k] = x;
                for i in 0..k {
                    col[i] -= q.0[k][i] * x;
                }
            }
        }
        Ok(())
    }
    #[inline(always)]
    fn all_finite(&self) -> bool {
        self.0.iter().all(|c| c.iter().all(|x| x.is_finite()))
    }
}

/// Scratch for faer's in-place partial-pivoting LU: row permutation and stack memory.
pub(crate) struct DenseLuScratch {
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: MemBuffer,
}

fn par_for(n: usize) -> Par {
    if n >= PARALLEL_MIN_ORDER {
        faer::get_global_parallelism()
    } else {
        Par::Seq
    }
}

impl SquareStorage for Mat<f64> {
    type Vector = Vec<f64>;
    type LuScratch = DenseLuScratch;

    fn zeros(n: usize) -> Self {
        Mat::zeros(n, n)
    }
    fn zero_vector(n: usize) -> Vec<f64> {
        vec![0.0; n]
    }
    fn lu_scratch(n: usize) -> DenseLuScratch {
        let par = par_for(n);
        let req = factor::lu_in_place_scratch::<usize, f64>(n, n, par, Default::default())
            .or(solve::solve_in_place_scratch::<usize, f64>(n, n, par));
        DenseLuScratch {
            perm: vec![0; n],
            perm_inv: vec![0; n],
            mem: MemBuffer::new(req),
        }
    }
    #[inline(always)]
    fn order(&self) -> usize {
        self.nrows()
    }
    #[inline(always)]
    fn get(&self, i: usize, j: usize) -> f64 {
        self[(i, j)]
    }
    #[inline(always)]
    fn set(&mut self, i: usize, j: usize, value: f64) {
        self[(i, j)] = value;
    }
    #[inline(always)]
    fn assign(&mut self, src: &Self) {
        self.copy_from(src);
    }
    #[inline(always)]
    fn scale(&mut self, c: f64) {
        for j in 0..self.ncols() {
            for x in self.col_as_slice_mut(j) {
                *x *= c;
            }
        }
    }
    #[inline(always)]
    fn assign_product(&mut self, a: &Self, b: &Self) {
        let n = self.nrows();
        matmul(
            self.as_mut(),
            Accum::Replace,
            a.as_ref(),
            b.as_ref(),
            1.0,
            par_for(n),
        );
    }
    #[inline(always)]
    fn combine(&mut self, accumulate: bool, c0: f64, terms: &[(f64, &Self)]) {
        for j in 0..self.ncols() {
            let dst = self.col_as_slice_mut(j);
            if !accumulate {
                dst.fill(0.0);
            }
            for &(c, m) in terms {
                for (d, x) in dst.iter_mut().zip(m.col_as_slice(j)) {
                    *d += c * x;
                }
            }
            dst[j] += c0;
        }
    }
    #[inline(always)]
    fn difference_and_sum(diff: &mut Self, sum: &mut Self, a: &Self, b: &Self) {
        for j in 0..a.ncols() {
            let (aj, bj) = (a.col_as_slice(j), b.col_as_slice(j));
            for (d, (x, y)) in diff.col_as_slice_mut(j).iter_mut().zip(aj.iter().zip(bj)) {
                *d = x - y;
            }
            for (s, (x, y)) in sum.col_as_slice_mut(j).iter_mut().zip(aj.iter().zip(bj)) {
                *s = x + y;
            }
        }
    }
    #[inline(always)]
    fn norm1(&self) -> f64 {
        let mut best = 0.0f64;
        for j in 0..self.ncols() {
            let s: f64 = self.col_as_slice(j).iter().map(|x| x.abs()).sum();
            if s > best || s.is_nan() {
                best = s;
            }
        }
        best
    }
    #[inline(always)]
    fn assign_abs_transpose(&mut self, src: &Self) {
        for j in 0..self.ncols() {
            for (i, x) in self.col_as_slice_mut(j).iter_mut().enumerate() {
                *x = src[(j, i)].abs();
            }
        }
    }
    #[inline(always)]
    fn matvec_max(&self, x: &Vec<f64>, y: &mut Vec<f64>) -> f64 {
        y.fill(0.0);
        for (k, &xk) in x.iter().enumerate() {
            for (yi, a) in y.iter_mut().zip(self.col_as_slice(k)) {
                *yi += a * xk;
            }
        }
        y.iter().fold(0.0, |m, &v| if v > m { v } else { m })
    }
    #[inline(always)]
    fn lu_solve(
        q: &mut Self,
        p: &mut Self,
        scratch: &mut DenseLuScratch,
    ) -> Result<(), SingularPivot> {
        let n = q.nrows();
        let par = par_for(n);
        let stack = MemStack::new(&mut scratch.mem);
        let (_, perm) = factor::lu_in_place(
            q.as_mut(),
            &mut scratch.perm,
            &mut scratch.perm_inv,
            par,
            stack,
            Default::default(),
        );
        for k in 0..n {
            let d = q[(k, k)];
            if d == 0.0 || !d.is_finite() {
                return Err(SingularPivot);
            }
        }
        solve::solve_in_place(q.as_ref(), q.as_ref(), perm, p.as_mut(), par, stack);
        Ok(())
    }
    #[inline(always)]
    fn all_finite(&self) -> bool {
        (0..self.ncols()).all(|j| self.col_as_slice(j).iter().all(|x| x.is_finite()))
    }
}
