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
//! * [`faer::Mat<f64>`]: faer's GEMM (`Par::Seq` below [`PARALLEL_MIN_ORDER`]); the Padé
//!   system is solved by [`super::lu`]. The O(n²) element-wise operations work on contiguous column slices with
//!   [`LANES`] independent partial sums, so that they vectorise under the same dispatch.

use faer::linalg::matmul::matmul;
use faer::reborrow::ReborrowMut;
use faer::{Accum, Mat, MatMut, MatRef, Par};

use super::lu::PadeSolver;

/// Order from which faer's parallel GEMM (global parallelism setting) is used; below it the
/// sequential kernel is faster on small machines (measured on 2 cores with the expm bench).
pub(crate) const PARALLEL_MIN_ORDER: usize = 256;

/// `(V − U)` had a zero (or non-finite) pivot in the LU factorisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SingularPivot;

/// Number of independent partial sums in the element-wise reductions ([`abs_sum`],
/// [`all_finite`], [`dot`]): two AVX2 registers, enough to hide the latency of the adds.
const LANES: usize = 8;

/// Combines the partial sums in a fixed order.
#[inline(always)]
fn reduce(acc: [f64; LANES]) -> f64 {
    ((acc[0] + acc[4]) + (acc[2] + acc[6])) + ((acc[1] + acc[5]) + (acc[3] + acc[7]))
}

/// Σ|xᵢ| with [`LANES`] partial sums. Entry i always goes to partial sum i mod [`LANES`], so
/// appending zeros (the padding of `expm::load`) never changes a bit of the result.
#[inline(always)]
pub(crate) fn abs_sum(x: &[f64]) -> f64 {
    let mut acc = [0.0f64; LANES];
    let mut chunks = x.chunks_exact(LANES);
    for c in &mut chunks {
        for k in 0..LANES {
            acc[k] += c[k].abs();
        }
    }
    for (a, v) in acc.iter_mut().zip(chunks.remainder()) {
        *a += v.abs();
    }
    reduce(acc)
}

/// Σ aᵢ·xᵢ with [`LANES`] partial sums.
#[inline(always)]
fn dot(a: &[f64], x: &[f64]) -> f64 {
    let mut acc = [0.0f64; LANES];
    let (ca, cx) = (a.chunks_exact(LANES), x.chunks_exact(LANES));
    let (ra, rx) = (ca.remainder(), cx.remainder());
    for (p, q) in ca.zip(cx) {
        for k in 0..LANES {
            acc[k] += p[k] * q[k];
        }
    }
    for ((s, p), q) in acc.iter_mut().zip(ra).zip(rx) {
        *s += p * q;
    }
    reduce(acc)
}

/// The dot products of four columns with x at once (each chunk of x is loaded once for all
/// four; eight accumulator registers), each with the summation order of [`dot`].
#[inline(always)]
fn dot4(a: [&[f64]; 4], x: &[f64]) -> [f64; 4] {
    let mut acc = [[0.0f64; LANES]; 4];
    let cx = x.chunks_exact(LANES);
    let rx = cx.remainder();
    let (a0, a1) = (a[0].chunks_exact(LANES), a[1].chunks_exact(LANES));
    let (a2, a3) = (a[2].chunks_exact(LANES), a[3].chunks_exact(LANES));
    let rem = [
        a0.remainder(),
        a1.remainder(),
        a2.remainder(),
        a3.remainder(),
    ];
    for ((((q, p0), p1), p2), p3) in cx.zip(a0).zip(a1).zip(a2).zip(a3) {
        for k in 0..LANES {
            acc[0][k] += p0[k] * q[k];
            acc[1][k] += p1[k] * q[k];
            acc[2][k] += p2[k] * q[k];
            acc[3][k] += p3[k] * q[k];
        }
    }
    for c in 0..4 {
        for ((s, p), q) in acc[c].iter_mut().zip(rem[c]).zip(rx) {
            *s += p * q;
        }
    }
    [
        reduce(acc[0]),
        reduce(acc[1]),
        reduce(acc[2]),
        reduce(acc[3]),
    ]
}

/// Whether every entry is finite, without an early exit so that the loop vectorises: x·0 is
/// ±0 for finite x and NaN for ±∞ and NaN.
#[inline(always)]
pub(crate) fn all_finite(x: &[f64]) -> bool {
    let mut acc = [0.0f64; LANES];
    let mut chunks = x.chunks_exact(LANES);
    for c in &mut chunks {
        for k in 0..LANES {
            acc[k] += c[k] * 0.0;
        }
    }
    for (a, v) in acc.iter_mut().zip(chunks.remainder()) {
        *a += v * 0.0;
    }
    reduce(acc) == 0.0
}

/// Records column sum `s` of column `j` in the running (1-norm, first argmax); a NaN column
/// sum is kept rather than dropped.
///
/// The kernels of this module use plain loops rather than iterator adaptors with closures:
/// a closure that is not inlined into the dispatched entry point would be compiled without
/// its instruction set.
#[inline(always)]
fn update_max(best: &mut (f64, usize), s: f64, j: usize) {
    if s > best.0 || s.is_nan() {
        *best = (s, j);
    }
}

/// dst ← t·(column j of a); the column may have any stride.
#[inline(always)]
fn load_column(dst: &mut [f64], a: MatRef<'_, f64>, j: usize, t: f64) {
    let col = a.col(j);
    match col.try_as_col_major() {
        Some(c) => {
            for (d, x) in dst.iter_mut().zip(c.as_slice()) {
                *d = x * t;
            }
        }
        None => {
            for (d, x) in dst.iter_mut().zip(col.iter()) {
                *d = x * t;
            }
        }
    }
}

/// The operations Algorithm 6.1 of Al-Mohy & Higham (2009) needs from a square matrix.
pub(crate) trait SquareStorage: Sized {
    /// Length-n work vector (for the |A|ᵀ power iteration of ℓ(A, m)).
    type Vector: AsRef<[f64]> + AsMut<[f64]>;
    /// Reusable scratch for [`SquareStorage::solve_pade`].
    type LuScratch;

    /// A zero matrix of order `n` (the small backend ignores `n`).
    fn zeros(n: usize) -> Self;
    /// A zero work vector of length `n`.
    fn zero_vector(n: usize) -> Self::Vector;
    /// Scratch memory for [`SquareStorage::solve_pade`] at order `n`.
    fn lu_scratch(n: usize) -> Self::LuScratch;
    /// The order n.
    fn order(&self) -> usize;
    /// Entry (i, j).
    fn get(&self, i: usize, j: usize) -> f64;
    /// Sets entry (i, j).
    fn set(&mut self, i: usize, j: usize, value: f64);
    /// `self ← t·a`, padded with zeros to the order of `self`; returns whether every entry of
    /// the result is finite.
    fn load(&mut self, a: MatRef<'_, f64>, t: f64) -> bool;
    /// The leading `out.nrows()` × `out.ncols()` block into `out`; returns whether it is finite.
    fn store(&self, out: MatMut<'_, f64>) -> bool;
    /// The leading n×n block as a new faer matrix.
    fn to_mat(&self, n: usize) -> Mat<f64>;
    /// `self ← src`.
    fn assign(&mut self, src: &Self);
    /// `self ← c·self`.
    fn scale(&mut self, c: f64);
    /// `self ← a·b`.
    fn assign_product(&mut self, a: &Self, b: &Self);
    /// `self ← accumulate·self + c0·I + Σ cₖ·Mₖ` (`accumulate` is 0 or 1).
    fn combine(&mut self, accumulate: bool, c0: f64, terms: &[(f64, &Self)]);
    /// Induced 1-norm max_j Σ_i |a_ij| and the first column j attaining it.
    fn norm1_argmax(&self) -> (f64, usize);
    /// Induced 1-norm max_j Σ_i |a_ij|.
    #[inline(always)]
    fn norm1(&self) -> f64 {
        self.norm1_argmax().0
    }
    /// ‖self·b e_j‖₁ (a lower bound for ‖self·b‖₁ at the cost of one matrix–vector product);
    /// `y` is scratch.
    fn column_product_norm1(&self, b: &Self, j: usize, y: &mut Self::Vector) -> f64;
    /// Prepares `self` from `src` for [`SquareStorage::abs_transpose_matvec_max`] (|src|ᵀ or
    /// |src|, whichever layout the backend's product reads contiguously).
    fn prepare_abs_transpose(&mut self, src: &Self);
    /// `y ← |A|ᵀ·x` for the A given to [`SquareStorage::prepare_abs_transpose`]; returns
    /// max_i y_i.
    fn abs_transpose_matvec_max(&self, x: &Self::Vector, y: &mut Self::Vector) -> f64;
    /// `x ← (v − u)⁻¹(v + u)` by Gaussian elimination with partial pivoting (`q` and the
    /// scratch are overwritten).
    fn solve_pade(
        x: &mut Self,
        q: &mut Self,
        v: &Self,
        u: &Self,
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
    fn load(&mut self, a: MatRef<'_, f64>, t: f64) -> bool {
        let n = a.nrows();
        self.0 = [[0.0; N]; N];
        for j in 0..n {
            load_column(&mut self.0[j][..n], a, j, t);
        }
        self.all_finite()
    }
    #[inline(always)]
    fn store(&self, mut out: MatMut<'_, f64>) -> bool {
        let mut finite = true;
        for j in 0..out.ncols() {
            for (i, x) in out.rb_mut().col_mut(j).iter_mut().enumerate() {
                let v = self.0[j][i];
                finite &= v.is_finite();
                *x = v;
            }
        }
        finite
    }
    fn to_mat(&self, n: usize) -> Mat<f64> {
        Mat::from_fn(n, n, |i, j| self.0[j][i])
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
    fn norm1_argmax(&self) -> (f64, usize) {
        let mut best = (0.0, 0);
        for j in 0..N {
            update_max(&mut best, abs_sum(&self.0[j]), j);
        }
        best
    }
    #[inline(always)]
    fn column_product_norm1(&self, b: &Self, j: usize, y: &mut [f64; N]) -> f64 {
        let mut acc = [0.0; N];
        for k in 0..N {
            let bk = b.0[j][k];
            for i in 0..N {
                acc[i] += self.0[k][i] * bk;
            }
        }
        *y = acc;
        abs_sum(&acc)
    }
    #[inline(always)]
    fn prepare_abs_transpose(&mut self, src: &Self) {
        for j in 0..N {
            for i in 0..N {
                self.0[j][i] = src.0[i][j].abs();
            }
        }
    }
    #[inline(always)]
    fn abs_transpose_matvec_max(&self, x: &[f64; N], y: &mut [f64; N]) -> f64 {
        let mut acc = [0.0; N];
        for k in 0..N {
            let xk = x[k];
            let col = &self.0[k];
            for i in 0..N {
                acc[i] += col[i] * xk;
            }
        }
        *y = acc;
        let mut top = 0.0f64;
        for v in acc {
            if v > top {
                top = v;
            }
        }
        top
    }
    #[inline(always)]
    fn solve_pade(
        x: &mut Self,
        q: &mut Self,
        v: &Self,
        u: &Self,
        _scratch: &mut (),
    ) -> Result<(), SingularPivot> {
        for j in 0..N {
            for i in 0..N {
                q.0[j][i] = v.0[j][i] - u.0[j][i];
                x.0[j][i] = v.0[j][i] + u.0[j][i];
            }
        }
        Self::lu_solve(q, x)
    }
    #[inline(always)]
    fn all_finite(&self) -> bool {
        all_finite(self.0.as_flattened())
    }
}

impl<const N: usize> SmallMat<N> {
    /// Solves `q·X = p` by LU with partial pivoting, overwriting `p` with X and `q` with its
    /// factors.
    #[inline(always)]
    fn lu_solve(q: &mut Self, p: &mut Self) -> Result<(), SingularPivot> {
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
    type LuScratch = PadeSolver;

    fn zeros(n: usize) -> Self {
        Mat::zeros(n, n)
    }
    fn zero_vector(n: usize) -> Vec<f64> {
        vec![0.0; n]
    }
    fn lu_scratch(n: usize) -> PadeSolver {
        PadeSolver::new(n)
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
    fn load(&mut self, a: MatRef<'_, f64>, t: f64) -> bool {
        for j in 0..self.ncols() {
            load_column(self.col_as_slice_mut(j), a, j, t);
        }
        self.all_finite()
    }
    #[inline(always)]
    fn store(&self, mut out: MatMut<'_, f64>) -> bool {
        let (r, c) = (out.nrows(), out.ncols());
        out.copy_from(self.as_ref().submatrix(0, 0, r, c));
        let mut finite = true;
        for j in 0..c {
            finite &= all_finite(&self.col_as_slice(j)[..r]);
        }
        finite
    }
    fn to_mat(&self, n: usize) -> Mat<f64> {
        self.as_ref().submatrix(0, 0, n, n).to_owned()
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
    fn norm1_argmax(&self) -> (f64, usize) {
        let mut best = (0.0, 0);
        for j in 0..self.ncols() {
            update_max(&mut best, abs_sum(self.col_as_slice(j)), j);
        }
        best
    }
    #[inline(always)]
    fn column_product_norm1(&self, b: &Self, j: usize, y: &mut Vec<f64>) -> f64 {
        y.fill(0.0);
        for (k, &bk) in b.col_as_slice(j).iter().enumerate() {
            for (yi, a) in y.iter_mut().zip(self.col_as_slice(k)) {
                *yi += a * bk;
            }
        }
        abs_sum(y)
    }
    /// Stores |src| (not transposed): (|A|ᵀx)_j = Σ_i |a_ij|·x_i is then a dot product with a
    /// contiguous column (see [`dot4`]).
    #[inline(always)]
    fn prepare_abs_transpose(&mut self, src: &Self) {
        for j in 0..self.ncols() {
            for (d, x) in self.col_as_slice_mut(j).iter_mut().zip(src.col_as_slice(j)) {
                *d = x.abs();
            }
        }
    }
    #[inline(always)]
    fn abs_transpose_matvec_max(&self, x: &Vec<f64>, y: &mut Vec<f64>) -> f64 {
        let n = self.ncols();
        let mut top = 0.0f64;
        let mut j = 0;
        while j + 4 <= n {
            let d = dot4(
                [
                    self.col_as_slice(j),
                    self.col_as_slice(j + 1),
                    self.col_as_slice(j + 2),
                    self.col_as_slice(j + 3),
                ],
                x,
            );
            y[j..j + 4].copy_from_slice(&d);
            j += 4;
        }
        while j < n {
            y[j] = dot(self.col_as_slice(j), x);
            j += 1;
        }
        for &v in y.iter() {
            if v > top {
                top = v;
            }
        }
        top
    }
    #[inline(always)]
    fn solve_pade(
        x: &mut Self,
        _q: &mut Self,
        v: &Self,
        u: &Self,
        scratch: &mut PadeSolver,
    ) -> Result<(), SingularPivot> {
        let par = par_for(x.nrows());
        scratch.solve(x, v, u, par)
    }
    #[inline(always)]
    fn all_finite(&self) -> bool {
        let mut finite = true;
        for j in 0..self.ncols() {
            finite &= all_finite(self.col_as_slice(j));
        }
        finite
    }
}
