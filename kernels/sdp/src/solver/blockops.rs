//! Block-diagonal matrices and the constraint operators.
//!
//! An iterate (`X`, `S`, a direction, a residual) is a `Vec<Mat<f64>>` with one entry per cone
//! block: an `n×n` symmetric matrix for a PSD block and an `n×1` column (the diagonal) for an LP
//! block — the layout of [`crate::Solution`]. With that layout the trace inner product
//! `⟨U, V⟩ = Σ_k tr(U_k V_k)` is the plain sum of entrywise products for both kinds.
//!
//! `𝒜(G) = (⟨A_i, G⟩)_i` and `𝒜ᵀ(y) = Σ_i y_i A_i` act on the sparse upper-triangle storage; `𝒜`
//! accepts non-symmetric `G` and then returns `⟨A_i, (G + Gᵀ)/2⟩ = ⟨A_i, G⟩` (`A_i` symmetric).
//! All sums run in a fixed order, so results are bitwise reproducible.

use faer::linalg::cholesky::llt::factor::{
    LltRegularization, cholesky_in_place as faer_cholesky_in_place,
};
use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{BlockStructure, matmul as tri_matmul};
use faer::linalg::triangular_inverse::invert_lower_triangular;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, Par};

use super::lsq::LeastSquares;
use super::small;
use super::structure::{Analysis, BlockPlan, SchurPlan, Values};
use crate::problem::{BlockKind, SparseSym};

/// One matrix per block (PSD `n×n`, LP `n×1`).
pub(crate) type BlockMats = Vec<Mat<f64>>;

/// Zero block matrices with the layout of `an`.
pub(crate) fn zeros(an: &Analysis) -> BlockMats {
    an.blocks.iter().map(zero_block).collect()
}

/// A zero matrix with the layout of block `b`.
pub(crate) fn zero_block(b: &BlockPlan) -> Mat<f64> {
    match b.kind {
        BlockKind::Psd => Mat::zeros(b.n, b.n),
        BlockKind::Lp => Mat::zeros(b.n, 1),
    }
}

/// `Σ_k ⟨a_k, b_k⟩` (trace inner product, summed block by block in order).
pub(crate) fn inner(a: &[Mat<f64>], b: &[Mat<f64>]) -> f64 {
    let mut total = 0.0;
    for (u, v) in a.iter().zip(b) {
        total += block_inner(u, v);
    }
    total
}

/// `⟨u, v⟩` of one block (entrywise products summed column by column).
pub(crate) fn block_inner(u: &Mat<f64>, v: &Mat<f64>) -> f64 {
    let mut s = 0.0;
    for j in 0..u.ncols() {
        let (cu, cv) = (u.col_as_slice(j), v.col_as_slice(j));
        for i in 0..cu.len() {
            s += cu[i] * cv[i];
        }
    }
    s
}

/// `a ← a + alpha·b`.
pub(crate) fn axpy(a: &mut [Mat<f64>], alpha: f64, b: &[Mat<f64>]) {
    for (u, v) in a.iter_mut().zip(b) {
        for j in 0..u.ncols() {
            let cv = v.col_as_slice(j);
            for (x, y) in u.col_as_slice_mut(j).iter_mut().zip(cv) {
                *x += alpha * y;
            }
        }
    }
}

/// Dense copy of a sparse symmetric block matrix into `out` (PSD: both triangles; LP: column).
pub(crate) fn scatter_sym(kind: BlockKind, mat: &SparseSym, scale: f64, out: &mut Mat<f64>) {
    for (i, j, v) in mat.iter() {
        add_entry(kind, out, i, j, scale * v);
    }
}

fn add_entry(kind: BlockKind, out: &mut Mat<f64>, i: usize, j: usize, v: f64) {
    match kind {
        BlockKind::Lp => out[(i, 0)] += v,
        BlockKind::Psd => {
            out[(i, j)] += v;
            if i != j {
                out[(j, i)] += v;
            }
        }
    }
}

/// `⟨A_p, G⟩` for every local constraint `p` of block `k`.
pub(crate) fn block_apply_a(an: &Analysis, vals: &Values, k: usize, g: &Mat<f64>) -> Vec<f64> {
    let b = &an.blocks[k];
    let v = &vals.a[k];
    if let Some(d) = &vals.dense[k] {
        let n = b.n;
        return (0..b.cons.len())
            .map(|p| {
                let a = &d[p * n * n..(p + 1) * n * n];
                let mut s = 0.0;
                for j in 0..n {
                    let (aj, gj) = (&a[j * n..(j + 1) * n], g.col_as_slice(j));
                    for i in 0..n {
                        s += aj[i] * gj[i];
                    }
                }
                s
            })
            .collect();
    }
    b.cons
        .iter()
        .zip(v)
        .map(|(pat, v)| {
            let mut s = 0.0;
            match b.kind {
                BlockKind::Lp => {
                    let g0 = g.col_as_slice(0);
                    for (e, &r) in pat.rows.iter().enumerate() {
                        s += v[e] * g0[r];
                    }
                }
                BlockKind::Psd => {
                    for e in 0..v.len() {
                        let (r, c) = (pat.rows[e], pat.cols[e]);
                        s += if r == c {
                            v[e] * g.col_as_slice(r)[r]
                        } else {
                            v[e] * (g.col_as_slice(c)[r] + g.col_as_slice(r)[c])
                        };
                    }
                }
            }
            s
        })
        .collect()
}

/// `out += 𝒜(G)`, i.e. `out_i += Σ_k ⟨A_i^k, G_k⟩`; blocks are evaluated independently
/// ([`Analysis::exec`]) and added in block order.
pub(crate) fn apply_a(an: &Analysis, vals: &Values, g: &[Mat<f64>], out: &mut [f64]) {
    let parts = an.map_blocks(|k, _| block_apply_a(an, vals, k, &g[k]));
    for (b, part) in an.blocks.iter().zip(parts) {
        for (pat, s) in b.cons.iter().zip(part) {
            out[pat.con] += s;
        }
    }
}

/// `out_k = Σ_i y_i A_i^k` for every block (overwrites `out`; blocks independently).
pub(crate) fn apply_at(an: &Analysis, vals: &Values, y: &[f64], out: &mut [Mat<f64>]) {
    an.exec
        .for_each_mut(out, |k, o| block_apply_at(an, vals, k, y, o));
}

/// `o = Σ_i y_i A_i^k` for block `k` (overwrites `o`).
pub(crate) fn block_apply_at(an: &Analysis, vals: &Values, k: usize, y: &[f64], o: &mut Mat<f64>) {
    let b = &an.blocks[k];
    o.fill(0.0);
    if let Some(d) = &vals.dense[k] {
        let n = b.n;
        for (p, pat) in b.cons.iter().enumerate() {
            let yi = y[pat.con];
            if yi == 0.0 {
                continue;
            }
            let a = &d[p * n * n..(p + 1) * n * n];
            for j in 0..n {
                let (aj, oj) = (&a[j * n..(j + 1) * n], o.col_as_slice_mut(j));
                for i in 0..n {
                    oj[i] += yi * aj[i];
                }
            }
        }
        return;
    }
    for (p, pat) in b.cons.iter().enumerate() {
        let yi = y[pat.con];
        if yi == 0.0 {
            continue;
        }
        let v = &vals.a[k][p];
        match b.kind {
            BlockKind::Lp => {
                let o0 = o.col_as_slice_mut(0);
                for e in 0..v.len() {
                    o0[pat.rows[e]] += yi * v[e];
                }
            }
            BlockKind::Psd => {
                for e in 0..v.len() {
                    let (r, c) = (pat.rows[e], pat.cols[e]);
                    o.col_as_slice_mut(c)[r] += yi * v[e];
                    if r != c {
                        o.col_as_slice_mut(r)[c] += yi * v[e];
                    }
                }
            }
        }
    }
}

/// Copies a square `Mat` into a column-major buffer of `n²` entries (leading dimension `n`).
pub(crate) fn load(m: &Mat<f64>, buf: &mut [f64]) {
    let n = m.nrows();
    for j in 0..n {
        buf[j * n..(j + 1) * n].copy_from_slice(m.col_as_slice(j));
    }
}

/// Copies the transpose of a square `Mat` into a column-major buffer of `n²` entries.
pub(crate) fn load_transposed(m: &Mat<f64>, buf: &mut [f64]) {
    let n = m.nrows();
    for j in 0..n {
        for (i, &v) in m.col_as_slice(j).iter().enumerate() {
            buf[j + i * n] = v;
        }
    }
}

/// A square `Mat` from a column-major buffer of order `n`.
pub(crate) fn store(buf: &[f64], n: usize) -> Mat<f64> {
    let mut m = Mat::zeros(n, n);
    for j in 0..n {
        m.col_as_slice_mut(j)
            .copy_from_slice(&buf[j * n..(j + 1) * n]);
    }
    m
}

/// Lower Cholesky factor of a symmetric matrix (only its lower triangle is read), or `None` if
/// the matrix is not numerically positive definite. The strict upper triangle of the result is 0.
pub(crate) fn cholesky(a: &Mat<f64>) -> Option<Mat<f64>> {
    let n = a.nrows();
    if n <= small::SMALL {
        return small::with_bufs(n, |[buf]| {
            load(a, buf);
            small::cholesky_in_place(buf, n).then(|| store(buf, n))
        });
    }
    let mut l = a.clone();
    if !cholesky_in_place(&mut l) {
        return None;
    }
    for j in 1..n {
        for i in 0..j {
            l[(i, j)] = 0.0;
        }
    }
    Some(l)
}

/// Overwrites the lower triangle of a symmetric matrix `a` (of order above [`small::SMALL`])
/// with its Cholesky factor, without the copy that [`cholesky`] returns; whether the matrix is
/// numerically positive definite. faer uses the strict upper triangle as workspace: it is not
/// read, and holds no meaningful values afterwards.
pub(crate) fn cholesky_in_place(a: &mut Mat<f64>) -> bool {
    let n = a.nrows();
    let mut mem = faer::dyn_stack::MemBuffer::new(
        faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch::<f64>(
            n,
            Par::Seq,
            Default::default(),
        ),
    );
    let stack = faer::dyn_stack::MemStack::new(&mut mem);
    faer_cholesky_in_place(
        a.as_mut(),
        LltRegularization::default(),
        Par::Seq,
        stack,
        Default::default(),
    )
    .is_ok()
        && (0..n).all(|i| a[(i, i)].is_finite() && a[(i, i)] > 0.0)
}

/// Inverse of a lower-triangular matrix (lower triangular, strict upper part 0).
pub(crate) fn lower_inverse(l: &Mat<f64>) -> Mat<f64> {
    let n = l.nrows();
    if n <= small::SMALL {
        return small::with_bufs(n, |[lb, out]| {
            load(l, lb);
            small::lower_inverse(lb, n, out);
            store(out, n)
        });
    }
    let mut inv = Mat::zeros(n, n);
    invert_lower_triangular(inv.as_mut(), l.as_ref(), Par::Seq);
    for j in 1..n {
        for i in 0..j {
            inv[(i, j)] = 0.0;
        }
    }
    inv
}

/// `Linvᵀ Linv`, the inverse of `L Lᵀ`, as a full symmetric matrix.
pub(crate) fn inverse_from_linv(linv: &Mat<f64>) -> Mat<f64> {
    let n = linv.nrows();
    if n <= small::SMALL {
        return small::with_bufs(n, |[lb, out]| {
            load(linv, lb);
            small::gram_of_lower(lb, n, out);
            store(out, n)
        });
    }
    let mut out = Mat::zeros(n, n);
    tri_matmul(
        out.as_mut(),
        BlockStructure::TriangularLower,
        Accum::Replace,
        linv.transpose(),
        BlockStructure::TriangularUpper,
        linv.as_ref(),
        BlockStructure::TriangularLower,
        1.0,
        Par::Seq,
    );
    for j in 1..n {
        for i in 0..j {
            out[(i, j)] = out[(j, i)];
        }
    }
    out
}

/// Dense `a·b` (sequential).
pub(crate) fn mul(a: &Mat<f64>, b: &Mat<f64>) -> Mat<f64> {
    let n = a.nrows();
    if n <= small::SMALL_PRODUCT && a.ncols() == n && b.nrows() == n && b.ncols() == n {
        return small::with_bufs(n, |[ab, bb, out]| {
            load(a, ab);
            load(b, bb);
            small::mul(ab, bb, n, out);
            store(out, n)
        });
    }
    let mut out = Mat::zeros(a.nrows(), b.ncols());
    matmul(
        out.as_mut(),
        Accum::Replace,
        a.as_ref(),
        b.as_ref(),
        1.0,
        Par::Seq,
    );
    out
}

/// Column panel of the in-place product `T ← T·L⁻ᵀ` in [`congruence`].
const CONGRUENCE_PANEL: usize = 128;

/// `linv · d · linvᵀ` for lower-triangular `linv` (the congruence used for step lengths).
///
/// Beyond the small blocks it takes one `n×n` array and an `n×`[`CONGRUENCE_PANEL`] panel:
/// `T = L⁻¹ D`, then `T ← T L⁻ᵀ` in place, panel by panel from the right, since column panel
/// `J` of the product reads only the columns of `T` up to the end of `J`. A block of order up
/// to the panel width is a single panel (the same product as with a separate output).
pub(crate) fn congruence(linv: &Mat<f64>, d: &Mat<f64>) -> Mat<f64> {
    let n = d.nrows();
    if n <= small::SMALL_PRODUCT {
        return small::with_bufs(n, |[lb, db, tmp, out]| {
            load(linv, lb);
            load(d, db);
            small::congruence(lb, db, n, tmp, out);
            store(out, n)
        });
    }
    let mut t = Mat::zeros(n, n);
    tri_matmul(
        t.as_mut(),
        BlockStructure::Rectangular,
        Accum::Replace,
        linv.as_ref(),
        BlockStructure::TriangularLower,
        d.as_ref(),
        BlockStructure::Rectangular,
        1.0,
        Par::Seq,
    );
    let mut panel = Mat::zeros(n, CONGRUENCE_PANEL.min(n));
    let mut end = n;
    while end > 0 {
        let start = end.saturating_sub(CONGRUENCE_PANEL);
        let w = end - start;
        let mut p = panel.as_mut().subcols_mut(0, w);
        // T[:, J] L⁻¹[J, J]ᵀ + T[:, ..start] L⁻¹[J, ..start]ᵀ
        tri_matmul(
            p.rb_mut(),
            BlockStructure::Rectangular,
            Accum::Replace,
            t.as_ref().subcols(start, w),
            BlockStructure::Rectangular,
            linv.as_ref().submatrix(start, start, w, w).transpose(),
            BlockStructure::TriangularUpper,
            1.0,
            Par::Seq,
        );
        if start > 0 {
            matmul(
                p.rb_mut(),
                Accum::Add,
                t.as_ref().subcols(0, start),
                linv.as_ref().submatrix(start, 0, w, start).transpose(),
                1.0,
                Par::Seq,
            );
        }
        t.as_mut().subcols_mut(start, w).copy_from(p.rb());
        end = start;
    }
    t
}

/// Replaces a square matrix by its symmetric part `(G + Gᵀ)/2`.
pub(crate) fn symmetrize(g: &mut Mat<f64>) {
    let n = g.nrows();
    for j in 0..n {
        for i in (j + 1)..n {
            let v = 0.5 * (g[(i, j)] + g[(j, i)]);
            g[(i, j)] = v;
            g[(j, i)] = v;
        }
    }
}

/// Smallest eigenvalue of a symmetric matrix (PSD block) or smallest entry (LP block); `NaN` if
/// the eigenvalue iteration fails.
pub(crate) fn min_eig(kind: BlockKind, a: &Mat<f64>) -> f64 {
    match kind {
        BlockKind::Psd if a.nrows() > small::JACOBI_MAX => min_eig_overwriting(&mut a.clone()),
        _ => min_eig_of(kind, a),
    }
}

/// [`min_eig`] of a matrix the caller no longer needs: a large PSD block is reduced to
/// tridiagonal form in its own storage (only its lower triangle is read), so the eigenvalue
/// costs no `n×n` copy.
pub(crate) fn min_eig_in_place(kind: BlockKind, a: &mut Mat<f64>) -> f64 {
    match kind {
        BlockKind::Psd if a.nrows() > small::JACOBI_MAX => min_eig_overwriting(a),
        _ => min_eig_of(kind, a),
    }
}

/// [`min_eig`] of an LP block or of a PSD block of order at most [`small::JACOBI_MAX`].
fn min_eig_of(kind: BlockKind, a: &Mat<f64>) -> f64 {
    match kind {
        BlockKind::Lp => a
            .col_as_slice(0)
            .iter()
            .fold(f64::INFINITY, |m, &v| m.min(v)),
        BlockKind::Psd => match a.nrows() {
            0 => f64::INFINITY,
            1 => a[(0, 0)],
            n => small::with_bufs(n, |[ab]| {
                load(a, ab);
                small::min_eig(ab, n)
            }),
        },
    }
}

/// Smallest eigenvalue of the symmetric matrix whose lower triangle is `a`, overwriting `a`:
/// Householder reduction to tridiagonal form in place, then the eigenvalues of the tridiagonal
/// matrix by the implicit QR algorithm (faer's `self_adjoint_eigenvalues` runs the same two
/// steps on a copy). `NaN` if the data are not finite or the iteration fails.
fn min_eig_overwriting(a: &mut Mat<f64>) -> f64 {
    use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
    use faer::linalg::evd::{self, tridiag};

    let n = a.nrows();
    if !(0..n).all(|j| a.col_as_slice(j)[j..].iter().all(|v| v.is_finite())) {
        return f64::NAN;
    }
    let par = faer::get_global_parallelism();
    let bs = faer::linalg::qr::no_pivoting::factor::recommended_block_size::<f64>(n, n);
    let mut householder = Mat::<f64>::zeros(bs, n - 1);
    let mut mem = MemBuffer::new(StackReq::any_of(&[
        tridiag::tridiag_in_place_scratch::<f64>(n, par, Default::default()),
        faer::linalg::temp_mat_scratch::<f64>(n, 1).array(2),
    ]));
    tridiag::tridiag_in_place(
        a.as_mut(),
        householder.as_mut(),
        par,
        MemStack::new(&mut mem),
        Default::default(),
    );
    let diag = faer::Col::<f64>::from_fn(n, |i| a[(i, i)]);
    let sub = faer::Col::<f64>::from_fn(n, |i| if i + 1 < n { a[(i + 1, i)] } else { 0.0 });
    let mut eig = faer::diag::Diag::<f64>::zeros(n);
    match evd::tridiagonal_self_adjoint_evd(
        diag.as_diagonal(),
        sub.as_diagonal(),
        eig.as_mut(),
        None,
        par,
        MemStack::new(&mut mem),
        Default::default(),
    ) {
        Ok(()) => eig
            .column_vector()
            .iter()
            .fold(f64::INFINITY, |m, &v| m.min(v)),
        Err(_) => f64::NAN,
    }
}

/// Factorisations of the current iterate needed by one interior-point iteration.
///
/// PSD block: `X = L_X L_Xᵀ`, `S = L_S L_Sᵀ`, the inverses `L_X⁻¹`, `L_S⁻¹`, and
/// `S⁻¹ = L_S⁻ᵀ L_S⁻¹`. LP block: only `zinv = 1/s` (the other fields are `0×0`, `linv_x = 1/x`).
///
/// Memory contract: the factors themselves are kept only where they are read, so a PSD block
/// holds three `n×n` arrays (`L_X⁻¹`, `L_S⁻¹`, `S⁻¹`), plus `L_X` under a
/// [`SchurPlan::Syrk`](super::structure::SchurPlan::Syrk) assembly, plus `L_X` and `L_S` when the
/// least-squares form ([`LeastSquares::fits`]) and its conjugate-gradient stand-in can run; the
/// others are `0×0`.
#[derive(Debug, Clone)]
pub(crate) struct Factors {
    /// `L_X`.
    pub lx: BlockMats,
    /// `L_X⁻¹`.
    pub linv_x: BlockMats,
    /// `L_S⁻¹`.
    pub linv_s: BlockMats,
    /// `L_S`.
    pub ls: BlockMats,
    /// `S⁻¹` (PSD, full symmetric) or `1/s` (LP).
    pub zinv: BlockMats,
}

/// `(L, L⁻¹)` of one PSD block, or for an LP block `(0×0, 1/v)` after checking `v > 0`;
/// `None` if the block is not numerically positive definite.
fn factor_block(kind: BlockKind, v: &Mat<f64>) -> Option<(Mat<f64>, Mat<f64>)> {
    match kind {
        BlockKind::Lp => {
            let vs = v.col_as_slice(0);
            if vs.iter().any(|&e| !(e > 0.0 && e.is_finite())) {
                return None;
            }
            Some((
                Mat::zeros(0, 0),
                Mat::from_fn(vs.len(), 1, |i, _| 1.0 / vs[i]),
            ))
        }
        BlockKind::Psd => {
            let l = cholesky(v)?;
            let linv = lower_inverse(&l);
            Some((l, linv))
        }
    }
}

/// Per block `(L, L⁻¹)` (PSD) or `(0×0, 1/v)` (LP), blocks independently; `None` if some
/// block is not positive definite.
pub(crate) fn factor_all(an: &Analysis, v: &[Mat<f64>]) -> Option<(BlockMats, BlockMats)> {
    unzip_factors(an.map_blocks(|k, b| factor_block(b.kind, &v[k])))
}

/// A new point and its [`factor_all`] factors.
pub(crate) type Factored = (BlockMats, (BlockMats, BlockMats));

/// For each `(cur, alpha, d)`, the point `cur + alpha·d` and its [`factor_all`] factors, all
/// formed in one pass over the blocks; `None` for a point with a block that is not positive
/// definite.
pub(crate) fn step_and_factor<const N: usize>(
    an: &Analysis,
    steps: [(&[Mat<f64>], f64, &[Mat<f64>]); N],
) -> [Option<Factored>; N] {
    let parts = an.map_blocks(|k, b| {
        steps.map(|(cur, alpha, d)| {
            let mut next = cur[k].clone();
            axpy(
                std::slice::from_mut(&mut next),
                alpha,
                std::slice::from_ref(&d[k]),
            );
            let f = factor_block(b.kind, &next);
            (next, f)
        })
    });
    let mut sides: [(BlockMats, Vec<_>); N] = std::array::from_fn(|_| (Vec::new(), Vec::new()));
    for block in parts {
        for ((next, factors), (n, f)) in sides.iter_mut().zip(block) {
            next.push(n);
            factors.push(f);
        }
    }
    sides.map(|(next, factors)| Some((next, unzip_factors(factors)?)))
}

fn unzip_factors(parts: Vec<Option<(Mat<f64>, Mat<f64>)>>) -> Option<(BlockMats, BlockMats)> {
    let mut ls = Vec::with_capacity(parts.len());
    let mut linvs = Vec::with_capacity(parts.len());
    for p in parts {
        let (l, linv) = p?;
        ls.push(l);
        linvs.push(linv);
    }
    Some((ls, linvs))
}

impl Factors {
    /// Assembles the factors from `factor_all(X)` and `factor_all(S)`.
    pub(crate) fn new(
        an: &Analysis,
        fx: (BlockMats, BlockMats),
        fs: (BlockMats, BlockMats),
    ) -> Self {
        let (mut lx, linv_x) = fx;
        let (mut ls, linv_s) = fs;
        if !LeastSquares::fits(an) {
            for (k, b) in an.blocks.iter().enumerate() {
                if !matches!(b.schur, SchurPlan::Syrk) {
                    lx[k] = Mat::new();
                }
                ls[k] = Mat::new();
            }
        }
        let zinv = an.map_blocks(|k, b| match b.kind {
            BlockKind::Lp => linv_s[k].clone(),
            BlockKind::Psd => inverse_from_linv(&linv_s[k]),
        });
        Self {
            lx,
            linv_x,
            linv_s,
            ls,
            zinv,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::XorShift;

    /// `Q diag(λ) Qᵀ` for a random orthogonal `Q` (Householder reflections of random vectors).
    fn with_spectrum(lambda: &[f64], rng: &mut XorShift) -> Mat<f64> {
        let n = lambda.len();
        let mut a = Mat::from_fn(n, n, |i, j| if i == j { lambda[i] } else { 0.0 });
        for _ in 0..3 {
            let v: Vec<f64> = (0..n).map(|_| rng.centred()).collect();
            let vv: f64 = v.iter().map(|x| x * x).sum();
            let h = Mat::from_fn(n, n, |i, j| {
                f64::from(u8::from(i == j)) - 2.0 * v[i] * v[j] / vv
            });
            a = mul(&mul(&h, &a), &h);
        }
        symmetrize(&mut a);
        a
    }

    #[test]
    fn eigenvalue_in_place_matches_the_spectrum_and_the_copying_form() {
        let mut rng = XorShift(0x5eed_0e16);
        for n in [small::JACOBI_MAX + 1, 37, 130] {
            let lambda: Vec<f64> = (0..n).map(|i| 3.0 - 0.05 * i as f64).collect();
            let exact = lambda.iter().copied().fold(f64::INFINITY, f64::min);
            let a = with_spectrum(&lambda, &mut rng);
            let copied = min_eig(BlockKind::Psd, &a);
            let mut b = a.clone();
            let in_place = min_eig_in_place(BlockKind::Psd, &mut b);
            assert!(
                (copied - exact).abs() < 1e-13 * n as f64,
                "n = {n}: {copied} vs {exact}"
            );
            assert_eq!(copied.to_bits(), in_place.to_bits(), "n = {n}");
            // Only the lower triangle is read.
            let mut lower = a.clone();
            for j in 1..n {
                for i in 0..j {
                    lower[(i, j)] = f64::NAN;
                }
            }
            assert_eq!(
                min_eig_in_place(BlockKind::Psd, &mut lower).to_bits(),
                in_place.to_bits()
            );
        }
    }

    #[test]
    fn congruence_in_panels_matches_the_dense_product() {
        let mut rng = XorShift(0xc0de);
        for n in [
            CONGRUENCE_PANEL - 1,
            CONGRUENCE_PANEL,
            2 * CONGRUENCE_PANEL + 37,
        ] {
            let linv = Mat::from_fn(n, n, |i, j| if i >= j { rng.centred() } else { 0.0 });
            let mut d = Mat::from_fn(n, n, |_, _| rng.centred());
            symmetrize(&mut d);
            let reference = &linv * &d * linv.transpose();
            let w = congruence(&linv, &d);
            let scale = (n as f64) * (n as f64);
            for j in 0..n {
                for i in 0..n {
                    assert!(
                        (w[(i, j)] - reference[(i, j)]).abs() <= 1e-15 * scale,
                        "n = {n}"
                    );
                }
            }
        }
    }

    #[test]
    fn eigenvalue_of_non_finite_data_is_nan() {
        let mut rng = XorShift(7);
        let mut a = with_spectrum(&[1.0; 20], &mut rng);
        a[(7, 3)] = f64::INFINITY;
        assert!(min_eig(BlockKind::Psd, &a).is_nan());
        a[(7, 3)] = f64::NAN;
        assert!(min_eig_in_place(BlockKind::Psd, &mut a).is_nan());
    }
}
