//! Facial reduction: a primal without a strictly feasible point, solved on its minimal face.
//!
//! A constraint `⟨A_i, X⟩ = 0` whose matrix is positive semidefinite (or negative semidefinite:
//! its sign is flipped) forces every feasible `X ⪰ 0` onto the face `{X ⪰ 0 : A_i X = 0}`: then
//! (P) has no strictly feasible point, the optimal set of (D) is unbounded (`y_i → −∞` leaves
//! `S = C − Σ y_j A_j` dual feasible), and interior-point iterates follow a diverging ray and stop
//! short of the tolerances. Restricting (P) to that face — `X = V Y Vᵀ` block by block with the
//! columns of `V` a basis of the null space of `A_i` (LP blocks: the entries where `A_i` is zero)
//! — is the facial reduction of Borwein and Wolkowicz ("Facial reduction for a cone-convex
//! programming problem", J. Austral. Math. Soc. 30, 1981; "Regularizing the abstract convex
//! program", J. Math. Anal. Appl. 83, 1981). On the SDPLIB graph-partitioning problems `gpp*`
//! the constraint `⟨eeᵀ, X⟩ = 0` is of this kind, and restricting `X` to `e^⊥` is the projection
//! onto the minimal face used by Zhao, Karisch, Rendl and Wolkowicz for the quadratic assignment
//! problem ("Semidefinite programming relaxations for the quadratic assignment problem",
//! J. Comb. Optim. 2, 1998) and by Wolkowicz and Zhao for graph partitioning ("Semidefinite
//! programming relaxations for the graph partitioning problem", Discrete Appl. Math. 96–97,
//! 1999).
//!
//! # The reduced problem
//!
//! [`reduce`] finds every constraint with `b_i = 0` whose matrix is semidefinite on every block it
//! touches (entries of one sign in LP blocks), exposes the face of their signed sum `E`, and
//! writes `C → VᵀCV`, `A_j → VᵀA_jV`. The exposing constraints become `0 = 0` and are dropped, as
//! is any other constraint whose matrix vanishes on the face (a vanishing constraint with
//! `b_j ≠ 0` means (P) is infeasible or nearly so: the reduction is abandoned and the original
//! problem is solved, whose solve reports that with its own verified certificates). Constraints
//! that become semidefinite on the face start another round, at most [`ROUNDS`] in all.
//!
//! The basis `V` keeps the data sparse: with the range of `E` on its support spanned by the rows
//! of `Qᵀ` (eigenvectors, eigenvalues above a tolerance relative to `‖E‖`), Gauss–Jordan
//! elimination with complete pivoting brings `Qᵀ` to `[I G]` on pivot indices `P` and the rest
//! `N`, and the null space is `x_P = −G x_N`. Row `α ∉ P` of `V` is a unit vector, so a
//! constraint touching no pivot index keeps its entries (gpp: `X_jj = 1` stays `Y_jj = 1`, only
//! the pivot's `X_pp = 1` becomes the dense rank-one `eᵀYe = 1`, as `⟨eeᵀ, X⟩ = 0` was before),
//! and the Schur assembly keeps its sparse formulas. Complete pivoting keeps the entries of `G`
//! moderate (for a rank-one `E`, `|G_ij| ≤ 1`), so `V` is well conditioned.
//!
//! # Back to the original problem
//!
//! `X = V Y Vᵀ`, `y` of the kept constraints from the reduced solve, `S = C − Σ_j y_j A_j`. The
//! dropped exposing constraints get `y_i = −t·sign_i`, so that `S = S₀ + t E` with `E ⪰ 0`: since
//! `V ⊥ range(E)` and `b_i = 0`, neither `VᵀSV` (the reduced slack), `⟨X, S⟩` nor `bᵀy` depends
//! on `t`, while `λ_min(S)` grows with `t` (a Schur complement in the basis `[V, range(E)]`: the
//! coupling `VᵀS₀ range(E)` is paid for by `t`). The dual need not be attained, so no finite `t`
//! may give `S ⪰ 0` exactly: `t` is the smallest (found by growing and bisecting, each test a
//! Cholesky factorisation) for which `S + τI ≻ 0` with `τ` a tenth of `tol_feas·(1 + max|C_ij|)`,
//! the scale of the DIMACS error of `λ_min(S)`. When the optimum of (D) is not attained the
//! needed `t` grows like `1/τ` and the rounding of `t E`, about `ε t max|E|`, may exceed the
//! margin: then the `t` with the largest `λ_min(S)` on the search grid is taken. The solution's
//! measures are those of this point against the original problem, and its status follows the
//! rule of [`super::Status`] from them, so a point that misses the tolerances says so. Since
//! `S` carries `t E`, its smallest eigenvalue is known only to about `ε‖S‖`, which can reach the
//! tolerance: for the status, each cone error is counted with that accuracy added,
//! `4ε‖·‖_F` (scaled as the error), so that no eigensolver finds a larger violation than the
//! status admits.
//!
//! Constraints that become linearly dependent on the face are not removed here: the solver
//! handles dependent constraints itself (regularised Cholesky, LBLᵀ and least-squares fallbacks).

use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{ComputeEigenvectors, self_adjoint_evd, self_adjoint_evd_scratch};
use faer::{Mat, Par};

use super::blockops::{block_inner, cholesky, min_eig, mul, scatter_sym, symmetrize};
use super::point::point_measures;
use super::settings::Settings;
use super::solution::{Solution, Status};
use crate::error::SdpError;
use crate::problem::{Block, BlockData, BlockKind, Problem, ProblemBuilder, SparseSym};

/// Error bound of a computed smallest eigenvalue in units of `ε‖M‖_F` (a backward-stable
/// symmetric eigensolver is accurate to a modest multiple of `ε‖M‖₂ ≤ ε‖M‖_F`).
const EIG_ERROR: f64 = 4.0;

/// Largest number of reduction rounds (each drops at least one constraint).
const ROUNDS: usize = 8;

/// Tolerance of the eigenvalue tests, relative to the largest eigenvalue of a matrix of order
/// `n`: the backward error of a symmetric eigensolver is a modest multiple of `n·ε·‖A‖`.
fn eig_tol(n: usize) -> f64 {
    100.0 * n as f64 * f64::EPSILON
}

/// Eigenvalues (nondecreasing) and, if `vectors`, eigenvectors of the symmetric `a` (lower
/// triangle read), computed sequentially so that the reduction does not depend on the thread
/// count; `None` if the eigensolver fails.
fn eigen(a: &Mat<f64>, vectors: bool) -> Option<(Vec<f64>, Mat<f64>)> {
    let n = a.nrows();
    let mut s = Diag::<f64>::zeros(n);
    let mut u = Mat::<f64>::zeros(n, if vectors { n } else { 0 });
    let compute = if vectors {
        ComputeEigenvectors::Yes
    } else {
        ComputeEigenvectors::No
    };
    let mut mem = MemBuffer::new(self_adjoint_evd_scratch::<f64>(
        n,
        compute,
        Par::Seq,
        Default::default(),
    ));
    self_adjoint_evd(
        a.as_ref(),
        s.as_mut(),
        vectors.then(|| u.as_mut()),
        Par::Seq,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .ok()?;
    Some(((0..n).map(|i| s[i]).collect(), u))
}

/// Basis of the face in one block.
#[derive(Debug, Clone)]
enum Basis {
    /// The block is not reduced.
    Keep,
    /// PSD block, `X = V Y Vᵀ`: `rows[α]` lists the nonzeros `(column, value)` of row `α` of
    /// `V`, which has `cols` columns (`0`: the block is fixed at zero and dropped).
    Psd {
        rows: Vec<Vec<(usize, f64)>>,
        cols: usize,
    },
    /// LP block: the entries left free, in order (the others are fixed at zero).
    Lp { kept: Vec<usize> },
}

impl Basis {
    /// Order or length of the block after reduction.
    fn size(&self, n: usize) -> usize {
        match self {
            Basis::Keep => n,
            Basis::Psd { cols, .. } => *cols,
            Basis::Lp { kept } => kept.len(),
        }
    }
}

/// One round: a problem, the face its exposing constraints define, and how its constraints map
/// onto the next problem's.
#[derive(Debug, Clone)]
struct Round {
    /// The problem before this round.
    problem: Problem,
    /// Per block of `problem`.
    bases: Vec<Basis>,
    /// Index of every block of `problem` in the reduced problem (`None`: dropped).
    block_map: Vec<Option<usize>>,
    /// Exposing constraints with the sign that makes their matrix positive semidefinite.
    exposing: Vec<(usize, f64)>,
    /// Constraints of `problem` kept, in the order of the reduced problem.
    kept: Vec<usize>,
}

/// A problem reduced to a face of its cone (see the module documentation).
#[derive(Debug, Clone)]
pub(crate) struct Reduction {
    rounds: Vec<Round>,
    reduced: Problem,
}

/// The blocks of constraint `i`: `(block, A_i restricted to it)`.
fn parts_of(problem: &Problem) -> Vec<Vec<(usize, &SparseSym)>> {
    let mut parts = vec![Vec::new(); problem.b.len()];
    for (k, bd) in problem.blocks.iter().enumerate() {
        for (i, a) in &bd.a {
            if problem.b[*i] == 0.0 {
                parts[*i].push((k, a));
            }
        }
    }
    parts
}

/// Dense copy of `sign·A` on the rows and columns `support` (sorted).
fn dense_on(a: &SparseSym, support: &[usize], sign: f64) -> Mat<f64> {
    let pos = |r: usize| support.binary_search(&r).expect("in the support");
    let mut d = Mat::zeros(support.len(), support.len());
    for (r, c, v) in a.iter() {
        let (p, q) = (pos(r), pos(c));
        d[(p, q)] = sign * v;
        d[(q, p)] = sign * v;
    }
    d
}

fn support_of(a: &SparseSym) -> Vec<usize> {
    let mut s: Vec<usize> = a.rows.iter().chain(&a.cols).copied().collect();
    s.sort_unstable();
    s.dedup();
    s
}

/// The sign `σ ∈ {1, −1}` for which `σ A_i` is positive semidefinite on every block, if any.
///
/// Cheap tests first: the sign of the first nonzero diagonal entry (a nonzero semidefinite
/// matrix has one), diagonal entries of that sign, `a_rs² ≤ a_rr a_ss` (2×2 principal minors);
/// only a matrix passing them is decomposed, on its support.
fn semidefinite_sign(blocks: &[BlockData], parts: &[(usize, &SparseSym)]) -> Option<f64> {
    let sign = parts
        .iter()
        .flat_map(|(_, a)| a.iter())
        .find(|&(r, c, v)| r == c && v != 0.0)
        .map(|(_, _, v)| v.signum())?;
    for &(k, a) in parts {
        if blocks[k].block.kind == BlockKind::Lp {
            if a.vals.iter().any(|v| v * sign < 0.0) {
                return None;
            }
            continue;
        }
        let diag: Vec<(usize, f64)> = a
            .iter()
            .filter(|&(r, c, _)| r == c)
            .map(|(r, _, v)| (r, sign * v))
            .collect();
        if diag.iter().any(|&(_, v)| v < 0.0) {
            return None;
        }
        let d = |r: usize| {
            diag.binary_search_by_key(&r, |&(i, _)| i)
                .map_or(0.0, |p| diag[p].1)
        };
        let minors = a
            .iter()
            .filter(|&(r, c, _)| r != c)
            .all(|(r, c, v)| v * v <= d(r) * d(c) * (1.0 + eig_tol(2)));
        if !minors {
            return None;
        }
        let support = support_of(a);
        if support.len() > 1 {
            let (ev, _) = eigen(&dense_on(a, &support, sign), false)?;
            let (min, max) = (ev[0], ev[ev.len() - 1]);
            if min < -eig_tol(support.len()) * max {
                return None;
            }
        }
    }
    Some(sign)
}

/// `Σ σ_i A_i` over the exposing constraints in one block (upper triangle, sorted).
fn exposing_sum(bd: &BlockData, exposing: &[(usize, f64)]) -> SparseSym {
    let mut entries: Vec<(usize, usize, f64)> = Vec::new();
    for &(i, sign) in exposing {
        if let Ok(p) = bd.a.binary_search_by_key(&i, |(k, _)| *k) {
            entries.extend(bd.a[p].1.iter().map(|(r, c, v)| (c, r, sign * v)));
        }
    }
    entries.sort_by_key(|&(c, r, _)| (c, r));
    let mut e = SparseSym::default();
    for (c, r, v) in entries {
        if e.cols.last() == Some(&c) && e.rows.last() == Some(&r) {
            *e.vals.last_mut().expect("nonempty") += v;
        } else {
            e.rows.push(r);
            e.cols.push(c);
            e.vals.push(v);
        }
    }
    e
}

/// The basis of the null space of `E ⪰ 0` (nonzero) in a PSD block of order `n` (module
/// documentation); `None` if the eigensolver fails.
fn psd_basis(n: usize, e: &SparseSym) -> Option<Basis> {
    let support = support_of(e);
    let nj = support.len();
    let (lam, u) = eigen(&dense_on(e, &support, 1.0), true)?;
    let tol = eig_tol(nj) * lam[nj - 1];
    let range: Vec<usize> = (0..nj).filter(|&c| lam[c] > tol).collect();
    let r = range.len();
    if r == 0 {
        return None;
    }
    // Rows of Qᵀ, reduced in place to [I G] on the pivots.
    let mut m: Vec<Vec<f64>> = range
        .iter()
        .map(|&c| (0..nj).map(|q| u[(q, c)]).collect())
        .collect();
    let mut pivot = vec![usize::MAX; nj];
    for s in 0..r {
        let (mut bi, mut bq, mut best) = (s, usize::MAX, -1.0);
        for (i, row) in m.iter().enumerate().skip(s) {
            for (q, v) in row.iter().enumerate() {
                if pivot[q] == usize::MAX && v.abs() > best {
                    (bi, bq, best) = (i, q, v.abs());
                }
            }
        }
        m.swap(s, bi);
        pivot[bq] = s;
        let p = m[s][bq];
        m[s].iter_mut().for_each(|v| *v /= p);
        let row_s = m[s].clone();
        for (i, row) in m.iter_mut().enumerate() {
            let f = row[bq];
            if i != s && f != 0.0 {
                row.iter_mut().zip(&row_s).for_each(|(v, w)| *v -= f * w);
            }
        }
    }
    let is_pivot = |alpha: usize| {
        support
            .binary_search(&alpha)
            .is_ok_and(|q| pivot[q] != usize::MAX)
    };
    let mut col = vec![usize::MAX; n];
    let mut cols = 0;
    for (alpha, c) in col.iter_mut().enumerate() {
        if !is_pivot(alpha) {
            *c = cols;
            cols += 1;
        }
    }
    let rows = (0..n)
        .map(|alpha| match support.binary_search(&alpha) {
            Ok(q) if pivot[q] != usize::MAX => {
                let row = &m[pivot[q]];
                (0..nj)
                    .filter(|&w| pivot[w] == usize::MAX && row[w] != 0.0)
                    .map(|w| (col[support[w]], -row[w]))
                    .collect()
            }
            _ => vec![(col[alpha], 1.0)],
        })
        .collect();
    Some(Basis::Psd { rows, cols })
}

/// `Vᵀ A V` of one block, added to `out` through `add(row, col, value)` (both triangles meant).
fn transform(basis: &Basis, a: &SparseSym, add: &mut dyn FnMut(usize, usize, f64)) {
    match basis {
        Basis::Keep => a.iter().for_each(|(r, c, v)| add(r, c, v)),
        Basis::Lp { kept } => {
            for (r, _, v) in a.iter() {
                if let Ok(p) = kept.binary_search(&r) {
                    add(p, p, v);
                }
            }
        }
        Basis::Psd { rows, .. } => {
            for (r, c, v) in a.iter() {
                if r == c {
                    let row = &rows[r];
                    for (s, &(p, x)) in row.iter().enumerate() {
                        add(p, p, v * x * x);
                        for &(q, w) in &row[s + 1..] {
                            add(p, q, v * x * w);
                        }
                    }
                } else {
                    for &(p, x) in &rows[r] {
                        for &(q, w) in &rows[c] {
                            add(p, q, if p == q { 2.0 * v * x * w } else { v * x * w });
                        }
                    }
                }
            }
        }
    }
}

/// One round of reduction of `problem`, or `None` if nothing is exposed.
/// `Err(())`: the reduction is abandoned (a constraint vanishes on the face with `b_j ≠ 0`, or
/// nothing would be left to solve).
fn round(problem: &Problem) -> Result<Option<(Round, Problem)>, ()> {
    let parts = parts_of(problem);
    let exposing: Vec<(usize, f64)> = parts
        .iter()
        .enumerate()
        .filter(|(_, p)| !p.is_empty())
        .filter_map(|(i, p)| semidefinite_sign(&problem.blocks, p).map(|s| (i, s)))
        .collect();
    if exposing.is_empty() {
        return Ok(None);
    }
    let bases: Vec<Basis> = problem
        .blocks
        .iter()
        .map(|bd| {
            let e = exposing_sum(bd, &exposing);
            if e.is_empty() {
                return Some(Basis::Keep);
            }
            match bd.block.kind {
                BlockKind::Psd => psd_basis(bd.block.size, &e),
                BlockKind::Lp => Some(Basis::Lp {
                    kept: (0..bd.block.size)
                        .filter(|l| e.rows.binary_search(l).is_err())
                        .collect(),
                }),
            }
        })
        .collect::<Option<_>>()
        .ok_or(())?;
    let m = problem.b.len();
    let mut dropped = vec![false; m];
    exposing.iter().for_each(|&(i, _)| dropped[i] = true);
    let mut builder = ProblemBuilder::new(m);
    let mut block_map = Vec::with_capacity(bases.len());
    // Largest entry of every A_j before and after, times the growth bound of the basis.
    let mut before = vec![0.0f64; m];
    for (bd, basis) in problem.blocks.iter().zip(&bases) {
        let size = basis.size(bd.block.size);
        if size == 0 {
            block_map.push(None);
            continue;
        }
        let k = builder.add_block(bd.block.kind, size);
        block_map.push(Some(k));
        let growth = match basis {
            Basis::Psd { rows, .. } => rows
                .iter()
                .map(|r| r.iter().map(|(_, v)| v.abs()).sum::<f64>())
                .fold(0.0, f64::max),
            _ => 1.0,
        };
        transform(basis, &bd.c, &mut |r, c, v| {
            builder.add_c(k, r, c, v);
        });
        for (j, a) in &bd.a {
            if dropped[*j] {
                continue;
            }
            let big = a.vals.iter().fold(0.0f64, |x, v| x.max(v.abs()));
            before[*j] = before[*j].max(big * growth * growth);
            transform(basis, a, &mut |r, c, v| {
                builder.add_a(*j, k, r, c, v);
            });
        }
    }
    for j in 0..m {
        builder.set_b(j, problem.b[j]);
    }
    let mut reduced = builder.build().map_err(|_| ())?;
    let mut after = vec![0.0f64; m];
    for bd in &reduced.blocks {
        for (j, a) in &bd.a {
            after[*j] = a.vals.iter().fold(after[*j], |x, v| x.max(v.abs()));
        }
    }
    let n_max = problem
        .blocks
        .iter()
        .map(|bd| bd.block.size)
        .max()
        .unwrap_or(1);
    for j in 0..m {
        if !dropped[j] && after[j] <= eig_tol(n_max) * before[j] {
            if problem.b[j] != 0.0 {
                return Err(());
            }
            dropped[j] = true;
        }
    }
    let kept: Vec<usize> = (0..m).filter(|&j| !dropped[j]).collect();
    if kept.is_empty() || reduced.blocks.is_empty() {
        return Err(());
    }
    let mut new_index = vec![usize::MAX; m];
    kept.iter().enumerate().for_each(|(p, &j)| new_index[j] = p);
    for bd in &mut reduced.blocks {
        bd.a.retain(|(j, _)| !dropped[*j]);
        bd.a.iter_mut().for_each(|(j, _)| *j = new_index[*j]);
    }
    reduced.b = kept.iter().map(|&j| problem.b[j]).collect();
    Ok(Some((
        Round {
            problem: problem.clone(),
            bases,
            block_map,
            exposing,
            kept,
        },
        reduced,
    )))
}

/// The reduction of `problem` (validated), or `None` when it has no semidefinite constraint
/// with `b_i = 0` or the reduction is abandoned (module documentation).
pub(crate) fn reduce(problem: &Problem) -> Option<Reduction> {
    let mut rounds: Vec<Round> = Vec::new();
    let mut current: Option<Problem> = None;
    while rounds.len() < ROUNDS {
        let p = current.as_ref().unwrap_or(problem);
        match round(p) {
            Ok(Some((r, reduced))) => {
                rounds.push(r);
                current = Some(reduced);
            }
            Ok(None) => break,
            Err(()) => return None,
        }
    }
    current.map(|reduced| Reduction { rounds, reduced })
}

/// `C − Σ_j y_j A_j`, one dense matrix per block.
fn slack(problem: &Problem, y: &[f64]) -> Vec<Mat<f64>> {
    problem
        .blocks
        .iter()
        .map(|bd| {
            let mut s = bd.c.to_dense(bd.block);
            for (j, a) in &bd.a {
                scatter_sym(bd.block.kind, a, -y[*j], &mut s);
            }
            s
        })
        .collect()
}

/// `S₀ + t E` on the blocks where `E ≠ 0`, with `shift` added to its diagonal.
fn shifted(
    blocks: &[Block],
    s0: &[Mat<f64>],
    e: &[Option<Mat<f64>>],
    t: f64,
    shift: f64,
) -> Vec<(BlockKind, Mat<f64>)> {
    blocks
        .iter()
        .zip(s0)
        .zip(e)
        .filter_map(|((b, s), e)| {
            let e = e.as_ref()?;
            let mut m = s.clone();
            for j in 0..m.ncols() {
                let (mj, ej) = (m.col_as_slice_mut(j), e.col_as_slice(j));
                mj.iter_mut().zip(ej).for_each(|(v, w)| *v += t * w);
            }
            match b.kind {
                BlockKind::Lp => m.col_as_slice_mut(0).iter_mut().for_each(|v| *v += shift),
                BlockKind::Psd => (0..b.size).for_each(|i| m[(i, i)] += shift),
            }
            Some((b.kind, m))
        })
        .collect()
}

/// The multiplier `t ≥ 0` of the exposing constraints (module documentation): the smallest
/// (to a relative `2⁻¹²`) for which `S₀ + t E + τ I` is positive definite on every block where
/// `E ≠ 0` (a Cholesky factorisation per test), found by growing `t` tenfold from `τ/max|E|`
/// and bisecting. Past `(1 + max|S₀|)/(ε max|E|)` the rounding of `t E` is as large as `S₀`
/// itself; if no `t` below that passes (the dual optimum is not attained, or only at a scale
/// where rounding hides the margin `τ`), the one of the tenfold grid with the largest
/// `λ_min(S₀ + t E)` is returned and the measures of the point report its accuracy.
fn multiplier(blocks: &[Block], s0: &[Mat<f64>], e: &[Option<Mat<f64>>], tau: f64) -> f64 {
    let ok = |t: f64| {
        shifted(blocks, s0, e, t, tau)
            .iter()
            .all(|(kind, m)| match kind {
                BlockKind::Lp => m.col_as_slice(0).iter().all(|&v| v > 0.0),
                BlockKind::Psd => cholesky(m).is_some(),
            })
    };
    if ok(0.0) {
        return 0.0;
    }
    let max_abs = |m: &Mat<f64>| {
        (0..m.ncols())
            .flat_map(|j| m.col_as_slice(j).iter())
            .fold(0.0f64, |x, v| x.max(v.abs()))
    };
    let e_max = e.iter().flatten().map(max_abs).fold(0.0, f64::max);
    let s_max = s0.iter().map(max_abs).fold(0.0, f64::max);
    let t_cap = (1.0 + s_max) / (f64::EPSILON * e_max);
    let mut grid = vec![tau / e_max];
    let mut hi = grid[0];
    while !ok(hi) {
        if hi > t_cap {
            let lambda = |t: f64| {
                shifted(blocks, s0, e, t, 0.0)
                    .iter()
                    .map(|(kind, m)| min_eig(*kind, m))
                    .fold(f64::INFINITY, f64::min)
            };
            let best =
                grid.iter()
                    .map(|&t| (lambda(t), t))
                    .fold(
                        (f64::NEG_INFINITY, 0.0),
                        |b, c| if c.0 > b.0 { c } else { b },
                    );
            return best.1;
        }
        hi *= 10.0;
        grid.push(hi);
    }
    let mut lo = if grid.len() > 1 { hi / 10.0 } else { 0.0 };
    for _ in 0..12 {
        let mid = 0.5 * (lo + hi);
        if ok(mid) { hi = mid } else { lo = mid }
    }
    hi
}

impl Reduction {
    /// The problem to solve.
    pub(crate) fn problem(&self) -> &Problem {
        &self.reduced
    }

    /// The point of the original problem that `sol` (a solution of [`Reduction::problem`])
    /// stands for: `(X, y, S)` (module documentation).
    fn lift(&self, sol: &Solution, tau: f64) -> (Vec<Mat<f64>>, Vec<f64>, Vec<Mat<f64>>) {
        let (mut x, mut y) = (sol.x.clone(), sol.y.clone());
        for r in self.rounds.iter().rev() {
            let p = &r.problem;
            x = p
                .blocks
                .iter()
                .zip(&r.bases)
                .zip(&r.block_map)
                .map(|((bd, basis), k)| {
                    let n = bd.block.size;
                    match (basis, k) {
                        (Basis::Keep, Some(k)) => x[*k].clone(),
                        (Basis::Lp { kept }, Some(k)) => {
                            let mut full = Mat::zeros(n, 1);
                            kept.iter()
                                .enumerate()
                                .for_each(|(p, &l)| full[(l, 0)] = x[*k][(p, 0)]);
                            full
                        }
                        (Basis::Psd { rows, cols }, Some(k)) => {
                            let mut v = Mat::<f64>::zeros(n, *cols);
                            for (alpha, row) in rows.iter().enumerate() {
                                row.iter().for_each(|&(c, w)| v[(alpha, c)] = w);
                            }
                            let mut full = mul(&mul(&v, &x[*k]), &v.transpose().to_owned());
                            symmetrize(&mut full);
                            full
                        }
                        (_, None) => SparseSym::default().to_dense(bd.block),
                    }
                })
                .collect();
            let mut full_y = vec![0.0; p.b.len()];
            r.kept.iter().zip(&y).for_each(|(&j, &v)| full_y[j] = v);
            let blocks: Vec<Block> = p.blocks.iter().map(|bd| bd.block).collect();
            let s0 = slack(p, &full_y);
            let e: Vec<Option<Mat<f64>>> = p
                .blocks
                .iter()
                .map(|bd| {
                    let e = exposing_sum(bd, &r.exposing);
                    (!e.is_empty()).then(|| e.to_dense(bd.block))
                })
                .collect();
            let t = multiplier(&blocks, &s0, &e, tau);
            r.exposing
                .iter()
                .for_each(|&(i, sign)| full_y[i] = -t * sign);
            y = full_y;
        }
        let s = slack(&self.rounds[0].problem, &y);
        (x, y, s)
    }

    /// The solution of the original `problem` from `sol`, the solution of
    /// [`Reduction::problem`]: the lifted point with its measures against `problem` and the
    /// status of the rule of [`Status`] (the cone errors of the lifted point, which is not an
    /// interior iterate, are held to `tol_feas` for [`Status::Optimal`]).
    pub(crate) fn solution(
        &self,
        problem: &Problem,
        sol: Solution,
        settings: &Settings,
        started: std::time::Instant,
    ) -> Result<Solution, SdpError> {
        let c = problem.dense_objective();
        let c_max = c
            .iter()
            .flat_map(|m| (0..m.ncols()).flat_map(move |j| m.col_as_slice(j).iter()))
            .fold(0.0f64, |x, v| x.max(v.abs()));
        let tau = 0.1 * settings.tol_feas * (1.0 + c_max);
        let (x, y, s) = self.lift(&sol, tau);
        let measures = point_measures(problem, &y, &x, &s)?;
        // The cone errors with the accuracy of their eigenvalues added (module documentation).
        let fro = |v: &[Mat<f64>]| v.iter().map(|m| block_inner(m, m)).sum::<f64>().sqrt();
        let b_inf = problem.b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut d = measures.dimacs;
        d[1] += EIG_ERROR * f64::EPSILON * fro(&x) / (1.0 + b_inf);
        d[3] += EIG_ERROR * f64::EPSILON * fro(&s) / (1.0 + c_max);
        let optimal = measures.rel_gap <= settings.tol_gap
            && d[5] <= settings.tol_gap
            && measures.primal_infeas <= settings.tol_feas
            && measures.dual_infeas <= settings.tol_feas
            && d[1] <= settings.tol_feas
            && d[3] <= settings.tol_feas;
        let status = if optimal {
            Status::Optimal
        } else if d.iter().all(|e| e.abs() <= settings.tol_reduced) {
            Status::AlmostOptimal
        } else if sol.status.is_failure() {
            sol.status
        } else {
            Status::NumericalTrouble
        };
        let primal_objective = c.iter().zip(&x).map(|(c, x)| block_inner(c, x)).sum();
        let dual_objective = problem.b.iter().zip(&y).map(|(b, y)| b * y).sum();
        Ok(Solution {
            status,
            x,
            y,
            s,
            primal_objective,
            dual_objective,
            iterations: sol.iterations,
            measures,
            certificate: None,
            solve_time: started.elapsed(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one_block(n: usize, m: usize, entries: &[(usize, usize, usize, f64)], b: &[f64]) -> Problem {
        let mut pb = ProblemBuilder::new(m);
        pb.add_block(BlockKind::Psd, n);
        b.iter().enumerate().for_each(|(i, &v)| {
            pb.set_b(i, v);
        });
        for &(i, r, c, v) in entries {
            pb.add_a(i, 0, r, c, v);
        }
        pb.build().unwrap()
    }

    /// `⟨eeᵀ, X⟩ = 0` (gpp): one pivot row of `V` holds the elimination, every other row is a
    /// unit vector, and `eᵀV = 0` to rounding.
    #[test]
    fn basis_of_all_ones_is_sparse() {
        let n = 7;
        let mut e = SparseSym::default();
        for c in 0..n {
            for r in 0..=c {
                e.rows.push(r);
                e.cols.push(c);
                e.vals.push(1.0);
            }
        }
        let Some(Basis::Psd { rows, cols }) = psd_basis(n, &e) else {
            panic!("a PSD basis");
        };
        assert_eq!(cols, n - 1);
        let dense: Vec<_> = rows.iter().filter(|r| r.len() > 1).collect();
        assert_eq!(dense.len(), 1);
        assert!(rows.iter().filter(|r| r.len() == 1).all(|r| r[0].1 == 1.0));
        for c in 0..cols {
            let sum: f64 = rows
                .iter()
                .flatten()
                .filter(|(k, _)| *k == c)
                .map(|(_, v)| v)
                .sum();
            assert!(sum.abs() <= 8.0 * f64::EPSILON, "column {c}: eᵀv = {sum}");
        }
    }

    #[test]
    fn semidefinite_sign_of_constraints() {
        let ones: Vec<_> = (0..3)
            .flat_map(|c| (0..=c).map(move |r| (0, r, c, 1.0)))
            .collect();
        let minus: Vec<_> = ones.iter().map(|&(i, r, c, v)| (i, r, c, -v)).collect();
        // QAP's arrow constraint 2X_0j − 2X_jj = 0 is indefinite, a gangster constraint
        // X_ij = 0 has no diagonal, and diag(1, −1) has diagonal entries of both signs.
        let arrow = [(0, 0, 1, 1.0), (0, 1, 1, -2.0)];
        let gangster = [(0, 0, 1, 1.0)];
        let mixed = [(0, 0, 0, 1.0), (0, 1, 1, -1.0)];
        let cases: [(&[_], Option<f64>); 5] = [
            (&ones, Some(1.0)),
            (&minus, Some(-1.0)),
            (&arrow, None),
            (&gangster, None),
            (&mixed, None),
        ];
        for (entries, expected) in cases {
            let p = one_block(3, 1, entries, &[0.0]);
            let parts = parts_of(&p);
            assert_eq!(
                semidefinite_sign(&p.blocks, &parts[0]),
                expected,
                "{entries:?}"
            );
        }
    }

    /// `X_00 = 0` forces the first row and column of `X` to zero; `X_00 = 1` then vanishes on
    /// the face with `b ≠ 0` (the primal is infeasible) and the reduction is abandoned, while
    /// `X_00 + X_11 = 2` becomes `Y_00 = 2` and is kept.
    #[test]
    fn vanishing_constraints() {
        let infeasible = one_block(3, 2, &[(0, 0, 0, 1.0), (1, 0, 0, 1.0)], &[0.0, 1.0]);
        assert!(reduce(&infeasible).is_none());
        let p = one_block(
            3,
            2,
            &[(0, 0, 0, 1.0), (1, 0, 0, 1.0), (1, 1, 1, 1.0)],
            &[0.0, 2.0],
        );
        let r = reduce(&p).expect("reduced");
        let q = r.problem();
        assert_eq!(q.b, vec![2.0]);
        assert_eq!(q.blocks[0].block.size, 2);
        assert_eq!(
            q.blocks[0].a,
            vec![(
                0,
                SparseSym {
                    rows: vec![0],
                    cols: vec![0],
                    vals: vec![1.0]
                }
            )]
        );
    }
}
