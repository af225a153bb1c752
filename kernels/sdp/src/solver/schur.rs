//! Assembly of the Schur complement (normal-equations) matrix of the HKM direction,
//!
//! ```text
//! M_ij = Σ_k tr(A_i^k X_k A_j^k S_k⁻¹)          (PSD blocks)
//!      + Σ_k Σ_l a_il^k a_jl^k x_l^k / s_l^k      (LP blocks),
//! ```
//!
//! block by block with the formula chosen in [`super::structure`] (Helmberg–Rendl–Vanderbei–
//! Wolkowicz 1996, eq. for `O`; Fujisawa–Kojima–Nakata 1997 for the F1/F2/F3 choice). Only pairs of
//! constraints sharing a block cost anything.
//!
//! Parallelism and determinism: blocks are processed in batches whose local buffers fit a memory
//! budget; within a batch the blocks run in parallel (rayon), and inside a block the rows of a
//! [`SchurPlan::Mixed`] block or the columns `K_i` of a [`SchurPlan::Syrk`] block run in
//! parallel. Every entry of a local buffer is computed by exactly one task in a fixed order, and
//! the buffers are added into `M` sequentially in block order, so the result is bitwise
//! independent of scheduling and of the number of threads.

use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{BlockStructure, matmul as tri_matmul};
use faer::prelude::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par};

use super::blockops::Factors;
use super::par::Exec;
use super::structure::{Analysis, BlockPlan, ConPattern, Formula, SchurPlan, Values};
use crate::problem::BlockKind;

/// Number of `f64`s the local buffers of concurrently processed blocks may use (32 MiB).
const BATCH_BUDGET: usize = 1 << 22;

/// Largest `n²·nc²` for which [`syrk_share`] forms `KᵀK` by plain inner products.
const SMALL_GRAM: usize = 1 << 16;

/// A [`SchurPlan::Mixed`] block with more than this many entries in its `nc×nc` share is
/// assembled alone, a group of rows at a time ([`grouped_rows`]), so that its share never
/// exists whole: on a problem with one large block (theta6, m = 4375) the share would be a
/// third `m×m` array beside `M` and its factor.
const ROW_GROUP: usize = 1 << 18;

/// Batches of fewer than this many blocks per thread parallelise the rows inside each block.
const ROW_PARALLEL_BLOCKS: usize = 4;

/// A block's share of `M` before it is added into the global matrix.
enum Local {
    /// LP block (accumulated directly into `M`) or block without constraints.
    Direct,
    /// Lower triangle in local constraint order ([`SchurPlan::Syrk`]).
    Lower(Mat<f64>),
    /// The block's `nc×nc` row-major slice of the shared buffer, in sorted order; row `t`
    /// holds columns `t' ≥ t` ([`SchurPlan::Mixed`]).
    Sorted,
}

/// Whether block `b` is assembled alone by [`grouped_rows`].
fn grouped(b: &BlockPlan) -> bool {
    matches!(b.schur, SchurPlan::Mixed { .. }) && b.cons.len() * b.cons.len() > ROW_GROUP
}

/// Entries of the shared row buffer that block `b` uses in a batch ([`SchurPlan::Mixed`] only).
fn sorted_len(b: &BlockPlan) -> usize {
    match b.schur {
        SchurPlan::Mixed { .. } => b.cons.len() * b.cons.len(),
        _ => 0,
    }
}

/// Fills the lower triangle of `out` (`m×m`) with the Schur matrix at the current iterate; the
/// strict upper triangle is left at zero.
///
/// `rows` holds the row buffers of the [`SchurPlan::Mixed`] blocks of one batch; it grows to the
/// largest batch once and is reused by every later batch and iteration (on problems with many
/// blocks a fresh buffer per block and iteration costs page faults: the 1024 vertex LMIs of
/// order 16 of an observer design with 117 constraints each allocated 112 MB per iteration).
/// Every entry a row formula reads back has been written by it in the same call, so the buffer
/// is never cleared.
pub(crate) fn assemble(
    an: &Analysis,
    vals: &Values,
    x: &[Mat<f64>],
    f: &Factors,
    out: &mut Mat<f64>,
    rows: &mut Vec<f64>,
) {
    out.fill(0.0);
    let nb = an.blocks.len();
    let mut k0 = 0;
    while k0 < nb {
        if grouped(&an.blocks[k0]) {
            grouped_rows(an, vals, x, f, k0, out, rows);
            k0 += 1;
            continue;
        }
        let mut k1 = k0;
        let mut used = 0usize;
        while k1 < nb && !grouped(&an.blocks[k1]) {
            let b = &an.blocks[k1];
            let need = match b.kind {
                BlockKind::Psd => b.cons.len() * b.cons.len(),
                BlockKind::Lp => 0,
            };
            if k1 > k0 && used + need > BATCH_BUDGET {
                break;
            }
            used += need;
            k1 += 1;
        }
        // With enough blocks to keep every thread busy, the rows inside a block run
        // sequentially: a task per row of a small block costs more than the row itself.
        let rows_exec = match an.exec {
            Exec::Parallel if k1 - k0 < ROW_PARALLEL_BLOCKS * rayon::current_num_threads() => {
                Exec::Parallel
            }
            _ => Exec::Sequential,
        };
        let lens: Vec<usize> = an.blocks[k0..k1].iter().map(sorted_len).collect();
        let total: usize = lens.iter().sum();
        if rows.len() < total {
            rows.resize(total, 0.0);
        }
        let mut shares: Vec<(&mut [f64], Local)> = Vec::with_capacity(k1 - k0);
        let mut rest = rows.as_mut_slice();
        for &len in &lens {
            let (head, tail) = rest.split_at_mut(len);
            shares.push((head, Local::Direct));
            rest = tail;
        }
        an.exec.for_each_mut(&mut shares, |i, (buf, local)| {
            let k = k0 + i;
            *local = local_share(
                &an.blocks[k],
                &vals.a[k],
                vals.dense[k].as_ref(),
                &x[k],
                f,
                k,
                rows_exec,
                buf,
            );
        });
        for (k, (buf, local)) in (k0..k1).zip(shares) {
            add_share(
                &an.blocks[k],
                &vals.a[k],
                &x[k],
                &f.zinv[k],
                local,
                buf,
                out,
            );
        }
        k0 = k1;
    }
}

fn local_share(
    plan: &BlockPlan,
    vals: &[Vec<f64>],
    dense: Option<&Vec<f64>>,
    x: &Mat<f64>,
    f: &Factors,
    k: usize,
    rows: Exec,
    buf: &mut [f64],
) -> Local {
    if plan.cons.is_empty() {
        return Local::Direct;
    }
    match &plan.schur {
        SchurPlan::Lp { .. } => Local::Direct,
        SchurPlan::Syrk => Local::Lower(syrk_share(
            plan,
            vals,
            dense.map(Vec::as_slice),
            &f.lx[k],
            &f.linv_s[k],
            rows,
        )),
        SchurPlan::Mixed { .. } => {
            mixed_rows(plan, vals, x, &f.zinv[k], 0, buf, rows);
            Local::Sorted
        }
    }
}

/// Rows `t0, t0 + 1, …` (sorted order) of a [`SchurPlan::Mixed`] block's share into `buf`, one
/// `nc`-entry row each (row `t` holds columns `t' ≥ t`), with each row's formula; the rows run
/// as `exec` says.
fn mixed_rows(
    plan: &BlockPlan,
    vals: &[Vec<f64>],
    x: &Mat<f64>,
    zinv: &Mat<f64>,
    t0: usize,
    buf: &mut [f64],
    exec: Exec,
) {
    let SchurPlan::Mixed {
        order,
        formula,
        support,
    } = &plan.schur
    else {
        return;
    };
    let nc = plan.cons.len();
    let d = RowData {
        order,
        cons: &plan.cons,
        vals,
        x,
        zinv,
    };
    exec.chunks_mut(buf, nc, RowScratch::default, |ws, p, row| {
        let t = t0 + p;
        let support = &support[order[t]];
        match formula[t] {
            Formula::F1 => f1_row(d, t, support, row, &mut ws.f1),
            Formula::F2 => f2_row(d, t, support, row, &mut ws.f2),
            Formula::F3 => f3_row(d, t, row),
        }
    });
}

/// Adds rows `t0, t0 + 1, …` of a [`SchurPlan::Mixed`] block's share (as [`mixed_rows`] wrote
/// them into `buf`) into the lower triangle of `out`.
fn add_rows(plan: &BlockPlan, t0: usize, buf: &[f64], out: &mut Mat<f64>) {
    let SchurPlan::Mixed { order, .. } = &plan.schur else {
        return;
    };
    let (cons, nc) = (&plan.cons, plan.cons.len());
    for (p, row) in buf.chunks_exact(nc).enumerate() {
        let t = t0 + p;
        let g1 = cons[order[t]].con;
        for t2 in t..nc {
            let g2 = cons[order[t2]].con;
            let (i, j) = if g1 >= g2 { (g1, g2) } else { (g2, g1) };
            out[(i, j)] += row[t2];
        }
    }
}

/// Block `k` ([`grouped`]) computed and added into `out` a group of rows at a time (at most
/// [`ROW_GROUP`] entries of `rows`), the rows of a group in parallel when the solve is. Every
/// entry of `out` receives the same value in the same order as from a whole share.
fn grouped_rows(
    an: &Analysis,
    vals: &Values,
    x: &[Mat<f64>],
    f: &Factors,
    k: usize,
    out: &mut Mat<f64>,
    rows: &mut Vec<f64>,
) {
    let plan = &an.blocks[k];
    let nc = plan.cons.len();
    let group = (ROW_GROUP / nc).max(1);
    if rows.len() < group * nc {
        rows.resize(group * nc, 0.0);
    }
    let mut t0 = 0;
    while t0 < nc {
        let t1 = (t0 + group).min(nc);
        let buf = &mut rows[..(t1 - t0) * nc];
        mixed_rows(plan, &vals.a[k], &x[k], &f.zinv[k], t0, buf, an.exec);
        add_rows(plan, t0, buf, out);
        t0 = t1;
    }
}

/// `KᵀK` with `K_i = L_Xᵀ A_i L_S⁻ᵀ` (lower triangle, local order); `dense` is the block's dense
/// copy of the `A_i` when it has one; the columns `K_i` are formed as `columns` says.
fn syrk_share(
    plan: &BlockPlan,
    vals: &[Vec<f64>],
    dense: Option<&[f64]>,
    lx: &Mat<f64>,
    linv_s: &Mat<f64>,
    columns: Exec,
) -> Mat<f64> {
    let n = plan.n;
    let nc = plan.cons.len();
    let nn = n * n;
    let mut kbuf = vec![0.0; nn * nc];
    columns.chunks_mut(
        &mut kbuf,
        nn,
        // `A_p` and `L_Xᵀ A_p`, reused for every column of a task (faer matrices: their
        // aligned, padded columns keep faer's kernels on their fast path).
        || (Mat::<f64>::zeros(n, n), Mat::<f64>::zeros(n, n)),
        |(a, t), p, chunk| {
            match dense {
                Some(d) => {
                    for c in 0..n {
                        a.col_as_slice_mut(c)
                            .copy_from_slice(&d[p * nn + c * n..p * nn + (c + 1) * n]);
                    }
                }
                None => {
                    let (pat, v) = (&plan.cons[p], &vals[p]);
                    a.fill(0.0);
                    for e in 0..v.len() {
                        let (r, c) = (pat.rows[e], pat.cols[e]);
                        a[(r, c)] += v[e];
                        if r != c {
                            a[(c, r)] += v[e];
                        }
                    }
                }
            }
            tri_matmul(
                t.as_mut(),
                BlockStructure::Rectangular,
                Accum::Replace,
                lx.transpose(),
                BlockStructure::TriangularUpper,
                a.as_ref(),
                BlockStructure::Rectangular,
                1.0,
                Par::Seq,
            );
            let kp = MatMut::from_column_major_slice_mut(chunk, n, n);
            tri_matmul(
                kp,
                BlockStructure::Rectangular,
                Accum::Replace,
                t.as_ref(),
                BlockStructure::Rectangular,
                linv_s.transpose(),
                BlockStructure::TriangularUpper,
                1.0,
                Par::Seq,
            );
        },
    );
    let mut local = Mat::zeros(nc, nc);
    if nn * nc * nc <= SMALL_GRAM {
        // faer hands products above 16³ multiply-adds to its large GEMM, which on first use in
        // a process reads the CPU cache sizes from sysfs (88 files, ~3 ms on our 2-core
        // machine): more than a whole small solve. For a small Gram matrix plain inner
        // products cost less.
        for q in 0..nc {
            let kq = &kbuf[q * nn..(q + 1) * nn];
            for p in q..nc {
                let kp = &kbuf[p * nn..(p + 1) * nn];
                local[(p, q)] = kp.iter().zip(kq).map(|(a, b)| a * b).sum();
            }
        }
        return local;
    }
    let kmat = MatRef::from_column_major_slice(&kbuf, nn, nc);
    tri_matmul(
        local.as_mut(),
        BlockStructure::TriangularLower,
        Accum::Replace,
        kmat.transpose(),
        BlockStructure::Rectangular,
        kmat,
        BlockStructure::Rectangular,
        1.0,
        Par::Seq,
    );
    local
}

/// What every row formula of a [`SchurPlan::Mixed`] block reads: the sorted constraint order,
/// the block's constraint patterns and values, `X` and `S⁻¹`.
#[derive(Clone, Copy)]
struct RowData<'a> {
    order: &'a [usize],
    cons: &'a [ConPattern],
    vals: &'a [Vec<f64>],
    x: &'a Mat<f64>,
    zinv: &'a Mat<f64>,
}

/// Per-task buffers of the row formulas (allocated on first use, then reused for every row).
#[derive(Default)]
struct RowScratch {
    f1: F1Scratch,
    f2: F2Scratch,
}

/// Reusable buffers of [`f2_row`]: `U = X[:,J] A_p[J,J]` and `V = S⁻¹[:,J]`, both `n×|J|`
/// column-major, so that forming `U` is a contiguous axpy per entry of `A_p` and `V` a copy of
/// `|J|` columns.
#[derive(Default)]
struct F2Scratch {
    u: Vec<f64>,
    v: Vec<f64>,
}

/// Row `t` (sorted order) with formula F2: `U = X A_p` on the support `J` of `A_p`, then every
/// entry of `G = X A_p S⁻¹ = U S⁻¹[J,:]` that the pattern of a later `A_q` needs as an inner
/// product of length `|J|`, and `row[t'] = ⟨A_q, G⟩`. It costs `|J|` (not the `nnz(A_p)` of F3)
/// per entry of `A_q`.
fn f2_row(d: RowData<'_>, t: usize, support: &[usize], row: &mut [f64], ws: &mut F2Scratch) {
    let RowData {
        order,
        cons,
        vals,
        x,
        zinv,
    } = d;
    let p = order[t];
    let (pat, v) = (&cons[p], &vals[p]);
    let n = x.nrows();
    let j = support.len();
    if n == 0 {
        row[t..].fill(0.0);
        return;
    }
    let pos = |i: usize| support.binary_search(&i).unwrap_or(0);
    ws.u.clear();
    ws.u.resize(n * j, 0.0);
    ws.v.clear();
    ws.v.resize(n * j, 0.0);
    let (u, sv) = (&mut ws.u, &mut ws.v);
    // U[:, c] += a X[:, r] and, off the diagonal, U[:, r] += a X[:, c] for A_p's entry (r, c, a).
    for e in 0..v.len() {
        let (r, c, a) = (pat.rows[e], pat.cols[e], v[e]);
        let pc = pos(c);
        for (ug, xg) in u[pc * n..(pc + 1) * n].iter_mut().zip(x.col_as_slice(r)) {
            *ug += a * xg;
        }
        if r != c {
            let pr = pos(r);
            for (ug, xg) in u[pr * n..(pr + 1) * n].iter_mut().zip(x.col_as_slice(c)) {
                *ug += a * xg;
            }
        }
    }
    for (vc, &col) in sv.chunks_exact_mut(n).zip(support) {
        vc.copy_from_slice(zinv.col_as_slice(col));
    }
    // G[g, d] = Σ_τ U[g, τ] V[d, τ], summed in the order of τ.
    let entry = |g: usize, d: usize| -> f64 {
        let mut s = -0.0;
        for (uc, vc) in u.chunks_exact(n).zip(sv.chunks_exact(n)) {
            s += uc[g] * vc[d];
        }
        s
    };
    for t2 in t..order.len() {
        let q = order[t2];
        let (pq, vq) = (&cons[q], &vals[q]);
        let mut s = 0.0;
        for e in 0..vq.len() {
            let (g, d) = (pq.rows[e], pq.cols[e]);
            s += vq[e]
                * if g == d {
                    entry(g, g)
                } else {
                    entry(g, d) + entry(d, g)
                };
        }
        row[t2] = s;
    }
}

/// Reusable buffers of [`f1_row`] (one set per task, so the rows of a block allocate nothing
/// once the buffers have grown to the shapes they need): each grows to the largest shape a row
/// asks of it, so a task that forms only dense rows holds three `n×n` arrays (`A_p`, `X A_p`,
/// `G`) and one that forms only rows on a support `J` arrays of `|J|` columns or rows.
struct F1Scratch {
    a: Mat<f64>,
    xa: Mat<f64>,
    g: Mat<f64>,
    xj: Mat<f64>,
    zj: Mat<f64>,
}

impl Default for F1Scratch {
    fn default() -> Self {
        let empty = || Mat::zeros(0, 0);
        Self {
            a: empty(),
            xa: empty(),
            g: empty(),
            xj: empty(),
            zj: empty(),
        }
    }
}

/// The leading `rows×cols` part of `buf`, which is first enlarged (zero-filled) if it is smaller.
fn grown(buf: &mut Mat<f64>, rows: usize, cols: usize) -> MatMut<'_, f64> {
    if buf.nrows() < rows || buf.ncols() < cols {
        *buf = Mat::zeros(rows.max(buf.nrows()), cols.max(buf.ncols()));
    }
    buf.as_mut().submatrix_mut(0, 0, rows, cols)
}

/// Row `t` (sorted order) with formula F1: `G = X A_p S⁻¹` on the support of `A_p`, then
/// `row[t'] = ⟨A_q, G⟩` for `t' ≥ t`.
fn f1_row(d: RowData<'_>, t: usize, support: &[usize], row: &mut [f64], ws: &mut F1Scratch) {
    let RowData {
        order,
        cons,
        vals,
        x,
        zinv,
    } = d;
    let p = order[t];
    let pat = &cons[p];
    let v = &vals[p];
    let n = x.nrows();
    let nj = support.len();
    let mut g = grown(&mut ws.g, n, n);
    if 10 * nj >= 7 * n {
        let mut a = grown(&mut ws.a, n, n);
        a.fill(0.0);
        for e in 0..v.len() {
            let (r, c) = (pat.rows[e], pat.cols[e]);
            a[(r, c)] += v[e];
            if r != c {
                a[(c, r)] += v[e];
            }
        }
        let mut xa = grown(&mut ws.xa, n, n);
        matmul(
            xa.rb_mut(),
            Accum::Replace,
            x.as_ref(),
            a.rb(),
            1.0,
            Par::Seq,
        );
        matmul(
            g.rb_mut(),
            Accum::Replace,
            xa.rb(),
            zinv.as_ref(),
            1.0,
            Par::Seq,
        );
    } else {
        let pos = |i: usize| support.binary_search(&i).unwrap_or(0);
        let mut a = grown(&mut ws.a, nj, nj);
        a.fill(0.0);
        for e in 0..v.len() {
            let (r, c) = (pos(pat.rows[e]), pos(pat.cols[e]));
            a[(r, c)] += v[e];
            if r != c {
                a[(c, r)] += v[e];
            }
        }
        let mut xj = grown(&mut ws.xj, n, nj);
        for (c, &sc) in support.iter().enumerate() {
            xj.rb_mut().col_mut(c).copy_from(x.col(sc));
        }
        let mut zj = grown(&mut ws.zj, nj, n);
        for (r, &sr) in support.iter().enumerate() {
            zj.rb_mut().row_mut(r).copy_from(zinv.row(sr));
        }
        let mut xa = grown(&mut ws.xa, n, nj);
        matmul(xa.rb_mut(), Accum::Replace, xj.rb(), a.rb(), 1.0, Par::Seq);
        matmul(g.rb_mut(), Accum::Replace, xa.rb(), zj.rb(), 1.0, Par::Seq);
    }
    // Upper triangle of G + Gᵀ (diagonal kept as G_rr).
    for c in 0..n {
        for r in 0..c {
            g[(r, c)] += g[(c, r)];
        }
    }
    for t2 in t..order.len() {
        let q = order[t2];
        let (pq, vq) = (&cons[q], &vals[q]);
        let mut s = 0.0;
        for e in 0..vq.len() {
            s += vq[e] * g[(pq.rows[e], pq.cols[e])];
        }
        row[t2] = s;
    }
}

/// `Σ_{(γ,δ)∈A_q} a_γδ X_βγ S⁻¹_δα` over the full symmetric pattern of `A_q` (stored as its upper
/// triangle), using the symmetry of `X` and `S⁻¹` to read columns only.
fn f3_inner(xb: &[f64], za: &[f64], pq: &ConPattern, vq: &[f64]) -> f64 {
    let mut s = 0.0;
    for f in 0..vq.len() {
        let (g, d) = (pq.rows[f], pq.cols[f]);
        s += vq[f]
            * if g == d {
                xb[g] * za[g]
            } else {
                xb[g] * za[d] + xb[d] * za[g]
            };
    }
    s
}

/// Row `t` (sorted order) with formula F3: the sparse double sum
/// `M_pq = Σ_{(α,β)∈A_p} Σ_{(γ,δ)∈A_q} a_αβ a_γδ X_βγ S⁻¹_δα`.
fn f3_row(d: RowData<'_>, t: usize, row: &mut [f64]) {
    let RowData {
        order,
        cons,
        vals,
        x,
        zinv,
    } = d;
    let p = order[t];
    let (pp, vp) = (&cons[p], &vals[p]);
    for t2 in t..order.len() {
        let q = order[t2];
        let (pq, vq) = (&cons[q], &vals[q]);
        let mut acc = 0.0;
        for e in 0..vp.len() {
            let (a, b) = (pp.rows[e], pp.cols[e]);
            acc += vp[e] * f3_inner(x.col_as_slice(b), zinv.col_as_slice(a), pq, vq);
            if a != b {
                acc += vp[e] * f3_inner(x.col_as_slice(a), zinv.col_as_slice(b), pq, vq);
            }
        }
        row[t2] = acc;
    }
}

/// Adds a block's share into the lower triangle of `out`.
fn add_share(
    plan: &BlockPlan,
    vals: &[Vec<f64>],
    x: &Mat<f64>,
    zinv: &Mat<f64>,
    local: Local,
    buf: &[f64],
    out: &mut Mat<f64>,
) {
    let cons = &plan.cons;
    let put = |out: &mut Mat<f64>, g1: usize, g2: usize, v: f64| {
        let (i, j) = if g1 >= g2 { (g1, g2) } else { (g2, g1) };
        out[(i, j)] += v;
    };
    match (local, &plan.schur) {
        (Local::Lower(l), _) => {
            for q in 0..cons.len() {
                for p in q..cons.len() {
                    put(out, cons[p].con, cons[q].con, l[(p, q)]);
                }
            }
        }
        (Local::Sorted, SchurPlan::Mixed { .. }) => add_rows(plan, 0, buf, out),
        (Local::Direct, SchurPlan::Lp { by_index }) => {
            let (xs, zs) = (x.col_as_slice(0), zinv.col_as_slice(0));
            for (l, list) in by_index.iter().enumerate() {
                let d = xs[l] * zs[l];
                for a in 0..list.len() {
                    let (p, e) = list[a];
                    let va = vals[p][e] * d;
                    for &(q, e2) in &list[..=a] {
                        put(out, cons[p].con, cons[q].con, va * vals[q][e2]);
                    }
                }
            }
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::ProblemBuilder;
    use crate::solver::blockops::factor_all;
    use crate::solver::structure::analyse;

    /// A symmetric positive definite `n×n` matrix `I + 0.1·(B + Bᵀ)/n` from a sequence.
    fn spd(n: usize, next: &mut impl FnMut() -> f64) -> Mat<f64> {
        let b = Mat::from_fn(n, n, |_, _| next());
        Mat::from_fn(n, n, |i, j| {
            (if i == j { 1.0 } else { 0.0 }) + 0.1 * (b[(i, j)] + b[(j, i)]) / n as f64
        })
    }

    /// A block whose share is assembled a group of rows at a time adds exactly the bits that
    /// its whole `nc×nc` share adds (same values, same order per entry), on both executors.
    #[test]
    fn grouped_rows_add_the_bits_of_the_whole_share() {
        let mut rng = crate::solver::XorShift(0x9e37_79b9_7f4a_7c15);
        let mut next = move || rng.centred();
        let (n, m) = (30, 600);
        let mut builder = ProblemBuilder::new(m);
        let block = builder.add_block(BlockKind::Psd, n);
        for i in 0..m {
            builder.set_b(i, next());
            // Two to six entries per constraint, mixing sparse and denser rows.
            for e in 0..2 + i % 5 {
                let (r, c) = ((i * 7 + e * 3) % n, (i * 11 + e * 5) % n);
                builder.add_a(i, block, r.min(c), r.max(c), next());
            }
        }
        let problem = builder.build().expect("problem");
        for exec in [Exec::Sequential, Exec::Parallel] {
            let mut an = analyse(&problem).expect("analysis");
            an.exec = exec;
            assert!(
                grouped(&an.blocks[0]),
                "the test block must take the grouped path"
            );
            let vals = an.values(&problem).expect("values");
            let x = vec![spd(n, &mut next)];
            let s = vec![spd(n, &mut next)];
            let fx = factor_all(&an, &x).expect("X factor");
            let fs = factor_all(&an, &s).expect("S factor");
            let f = Factors::new(&an, fx, fs);
            let mut grouped_out = Mat::zeros(m, m);
            let mut rows = Vec::new();
            assemble(&an, &vals, &x, &f, &mut grouped_out, &mut rows);
            assert!(
                rows.len() <= ROW_GROUP + m,
                "the row buffer stays within a group"
            );
            let mut whole = vec![0.0; m * m];
            let local = local_share(
                &an.blocks[0],
                &vals.a[0],
                None,
                &x[0],
                &f,
                0,
                exec,
                &mut whole,
            );
            let mut whole_out = Mat::zeros(m, m);
            add_share(
                &an.blocks[0],
                &vals.a[0],
                &x[0],
                &f.zinv[0],
                local,
                &whole,
                &mut whole_out,
            );
            assert!(
                (0..m).all(|i| whole_out[(i, i)] > 0.0),
                "M has a positive diagonal"
            );
            for j in 0..m {
                for i in j..m {
                    assert_eq!(
                        grouped_out[(i, j)].to_bits(),
                        whole_out[(i, j)].to_bits(),
                        "entry ({i}, {j})"
                    );
                }
            }
        }
    }
}
