//! The Padé solve r_m = (V − U)⁻¹(V + U) of Al-Mohy & Higham (2009), Algorithm 6.1, for the
//! faer backend.
//!
//! q_m(A) = V − U and p_m(A) = V + U are polynomials in the same matrix, so they commute and
//! r_m = p_m·q_m⁻¹ as well: X is computed from X·Q = P with Q = V − U, P = V + U. With the
//! row-pivoted factorisation ΠQ = LU (Gaussian elimination with partial pivoting), X =
//! P·U⁻¹·L⁻¹·Π:
//!
//! 1. ΠQ = LU by faer's recursive partial-pivoting LU (`lu_in_place`);
//! 2. Y·U = P by column blocks from the left: P_J ← P_J − Y_{<J}·U_{<J,J} (GEMM), then
//!    y_j = (p_j − Σ_{i∈J, i<j} u_ij·y_i)/u_jj within the block;
//! 3. Z·L = Y by column blocks from the right, likewise with the unit lower factor;
//! 4. X = Z·Π, a reordering of the columns.
//!
//! Solving from the right keeps the substitutions column-oriented: for a column-major
//! right-hand side, every step combines whole contiguous columns (no transposition, no row
//! interchanges, full-width vector operations), and the O(n³) work is in GEMM calls with
//! inner dimension up to n. For the orders this backend serves (n > 16) this is faster than
//! faer's `solve_in_place` (row permutation and two triangular solves) on the project
//! machine. The backward error is that of an LU solve of the transposed system (Higham,
//! *Accuracy and Stability of Numerical Algorithms*, 2nd ed., Theorem 9.4).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor::{lu_in_place, lu_in_place_scratch};
use faer::linalg::matmul::matmul;
use faer::reborrow::IntoConst;
use faer::{Accum, Mat, MatMut, MatRef, Par};

use super::storage::SingularPivot;

/// Block width of the substitutions.
const PANEL: usize = 8;

/// Rows the column combinations accumulate at once (four AVX2 registers of f64).
const ROWS: usize = 16;

/// Buffers for one order n: Q, P, the row permutation and faer's LU scratch.
pub(crate) struct PadeSolver {
    n: usize,
    /// Q = V − U (overwritten by L and U), column-major with leading dimension n.
    q: Vec<f64>,
    /// P = V + U (overwritten by Y, then Z), column-major with leading dimension n.
    p: Vec<f64>,
    /// Row order of ΠQ: row i of ΠQ is row `perm[i]` of Q.
    perm: Vec<usize>,
    /// Inverse of `perm` (filled by faer, unused).
    perm_inv: Vec<usize>,
    /// Scratch of `lu_in_place`.
    stack: MemBuffer,
}

impl PadeSolver {
    /// Buffers for order `n`.
    pub(crate) fn new(n: usize) -> Self {
        Self {
            n,
            q: vec![0.0; n * n],
            p: vec![0.0; n * n],
            perm: vec![0; n],
            perm_inv: vec![0; n],
            stack: MemBuffer::new(lu_in_place_scratch::<usize, f64>(
                n,
                n,
                Par::Seq,
                Default::default(),
            )),
        }
    }

    /// x ← (v − u)⁻¹(v + u); `par` is the parallelism of the GEMM calls.
    ///
    /// # Errors
    /// [`SingularPivot`] if a pivot column is zero or non-finite.
    #[inline(always)]
    pub(crate) fn solve(
        &mut self,
        x: &mut Mat<f64>,
        v: &Mat<f64>,
        u: &Mat<f64>,
        par: Par,
    ) -> Result<(), SingularPivot> {
        let n = self.n;
        for (j, (qj, pj)) in self
            .q
            .chunks_exact_mut(n)
            .zip(self.p.chunks_exact_mut(n))
            .enumerate()
        {
            let (vj, uj) = (v.col_as_slice(j), u.col_as_slice(j));
            for i in 0..n {
                qj[i] = vj[i] - uj[i];
                pj[i] = vj[i] + uj[i];
            }
        }
        self.factor(par)?;
        let q = MatRef::from_column_major_slice(&self.q, n, n);
        // Y·U = P.
        let mut j0 = 0;
        while j0 < n {
            let j1 = (j0 + PANEL).min(n);
            if j0 > 0 {
                let pm = MatMut::from_column_major_slice_mut(&mut self.p, n, n);
                let (done, rest) = pm.split_at_col_mut(j0);
                matmul(
                    rest.get_mut(.., ..j1 - j0),
                    Accum::Add,
                    done.into_const(),
                    q.get(..j0, j0..j1),
                    -1.0,
                    par,
                );
            }
            for j in j0..j1 {
                let (head, rest) = self.p.split_at_mut(j * n);
                let ucol = &self.q[j * n..(j + 1) * n];
                subtract_combination(&mut rest[..n], &head[j0 * n..], &ucol[j0..j], 1.0 / ucol[j]);
            }
            j0 = j1;
        }
        // Z·L = Y.
        let mut j1 = n;
        while j1 > 0 {
            let j0 = (j1 - 1) / PANEL * PANEL;
            if j1 < n {
                let pm = MatMut::from_column_major_slice_mut(&mut self.p, n, n);
                let (head, later) = pm.split_at_col_mut(j1);
                matmul(
                    head.get_mut(.., j0..),
                    Accum::Add,
                    later.into_const(),
                    q.get(j1.., j0..j1),
                    -1.0,
                    par,
                );
            }
            for j in (j0..j1).rev() {
                let (head, later) = self.p.split_at_mut((j + 1) * n);
                let lcol = &self.q[j * n + j + 1..j * n + j1];
                subtract_combination(&mut head[j * n..], &later[..(j1 - j - 1) * n], lcol, 1.0);
            }
            j1 = j0;
        }
        // X = Z·Π: Π has its ones at (i, perm[i]), so column perm[i] of X is column i of Z.
        for (i, &dst) in self.perm.iter().enumerate() {
            x.col_as_slice_mut(dst)
                .copy_from_slice(&self.p[i * n..(i + 1) * n]);
        }
        Ok(())
    }

    /// ΠQ = LU in place by faer's recursive partial-pivoting LU (`lu_in_place`); records the
    /// row order of Π and rejects a zero or non-finite pivot u_jj.
    #[inline(always)]
    fn factor(&mut self, par: Par) -> Result<(), SingularPivot> {
        let n = self.n;
        let q = MatMut::from_column_major_slice_mut(&mut self.q, n, n);
        lu_in_place(
            q,
            &mut self.perm,
            &mut self.perm_inv,
            par,
            MemStack::new(&mut self.stack),
            Default::default(),
        );
        for j in 0..n {
            let d = self.q[j * n + j];
            if d == 0.0 || !d.is_finite() {
                return Err(SingularPivot);
            }
        }
        Ok(())
    }
}

/// dst ← (dst − Σ_k coef_k·src_k)·scale, src_k = `srcs[k·n..(k+1)·n]` (n = `dst.len()`):
/// [`ROWS`] rows at a time, accumulated in registers over all k.
#[inline(always)]
fn subtract_combination(dst: &mut [f64], srcs: &[f64], coef: &[f64], scale: f64) {
    let n = dst.len();
    let mut r = 0;
    while r + ROWS <= n {
        let mut acc = [0.0; ROWS];
        acc.copy_from_slice(&dst[r..r + ROWS]);
        for (src, &c) in srcs.chunks_exact(n).zip(coef) {
            let s = &src[r..r + ROWS];
            for i in 0..ROWS {
                acc[i] -= c * s[i];
            }
        }
        for i in 0..ROWS {
            dst[r + i] = acc[i] * scale;
        }
        r += ROWS;
    }
    if r < n {
        let mut acc = [0.0; ROWS];
        let w = n - r;
        acc[..w].copy_from_slice(&dst[r..]);
        for (src, &c) in srcs.chunks_exact(n).zip(coef) {
            let s = &src[r..];
            for i in 0..w {
                acc[i] -= c * s[i];
            }
        }
        for i in 0..w {
            dst[r + i] = acc[i] * scale;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::linalg::solvers::Solve;

    fn pseudo_random(n: usize, seed: u64) -> Mat<f64> {
        let mut state = seed;
        Mat::from_fn(n, n, |_, _| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            2.0 * ((state >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        })
    }

    /// For commuting V, U (polynomials in one matrix, as in the Padé approximant), against
    /// faer's partial-pivoting LU solve of (V − U)X = V + U (the same factorisation, but faer's
    /// own row permutation and left-side triangular solves).
    #[test]
    fn matches_faer_partial_piv_lu_for_commuting_factors() {
        for n in [1, 2, 5, 15, 16, 17, 31, 33, 64, 70] {
            let a = pseudo_random(n, 11 + n as u64) * faer::Scale(0.3);
            let a2 = &a * &a;
            let id = Mat::<f64>::identity(n, n);
            // Degree-3 Padé pair: U = A(b3·A² + b1·I), V = b2·A² + b0·I.
            let u = &a * (&a2 + &id * faer::Scale(60.0));
            let v = &a2 * faer::Scale(12.0) + &id * faer::Scale(120.0);
            let mut x = Mat::zeros(n, n);
            PadeSolver::new(n).solve(&mut x, &v, &u, Par::Seq).unwrap();
            let want = (&v - &u).partial_piv_lu().solve(&v + &u);
            let scale = want.norm_max();
            let err = (&x - &want).norm_max();
            assert!(err <= 1e-13 * scale, "n={n}: err {err:e}, scale {scale:e}");
        }
    }

    /// X·Q = P for general (non-commuting) Q, P: the residual is at rounding level.
    #[test]
    fn right_side_residual_is_small() {
        for n in [3, 16, 17, 40, 65] {
            let v = pseudo_random(n, 5 + n as u64);
            let u = pseudo_random(n, 77 + n as u64);
            let (q, p) = (&v - &u, &v + &u);
            let mut x = Mat::zeros(n, n);
            PadeSolver::new(n).solve(&mut x, &v, &u, Par::Seq).unwrap();
            let res = (&x * &q - &p).norm_max();
            let bound = 1e-13 * n as f64 * x.norm_max() * q.norm_max();
            assert!(res <= bound, "n={n}: residual {res:e} > {bound:e}");
        }
    }

    /// V − U a cyclic shift (every leading minor singular, so every step interchanges rows)
    /// and V + U = I: X = shift⁻¹ = shiftᵀ exactly. A zero column of V − U is singular.
    #[test]
    fn pivots_and_detects_singularity() {
        let n = 20;
        let shift = Mat::from_fn(n, n, |i, j| if (j + 1) % n == i { 1.0 } else { 0.0 });
        let id = Mat::<f64>::identity(n, n);
        let v = (&shift + &id) * faer::Scale(0.5);
        let u = (&id - &shift) * faer::Scale(0.5);
        let mut x = Mat::zeros(n, n);
        PadeSolver::new(n).solve(&mut x, &v, &u, Par::Seq).unwrap();
        assert_eq!(x, shift.transpose().to_owned());
        let mut v2 = pseudo_random(n, 5);
        let u2 = pseudo_random(n, 6);
        for i in 0..n {
            v2[(i, 7)] = u2[(i, 7)];
        }
        assert_eq!(
            PadeSolver::new(n).solve(&mut x, &v2, &u2, Par::Seq),
            Err(SingularPivot)
        );
    }
}
