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
//! Cholesky factorisation) for which `S + (τ + d)I ≻ 0` with `τ` a tenth of
//! `tol_feas·(1 + max|C_ij|)`, the scale of the DIMACS error of `λ_min(S)`, and `d` the
//! negative part of `λ_min` of `S₀` on the face, which no `t` changes ([`face_deficit`]). When the optimum of (D) is not attained the
//! needed `t` grows like `1/τ` and the rounding of `t E`, about `ε t max|E|`, may exceed the
//! margin: then the `t` with the largest `λ_min(S)` on the search grid is taken. The solution's
//! measures are those of this point against the original problem, and its status follows the
//! rule of [`super::Status`] from them, so a point that misses the tolerances says so. Since
//! `S` carries `t E`, its smallest eigenvalue is known only to about `ε‖S‖`, which can reach the
//! tolerance: for the status, each cone error is counted with that accuracy added,
//! `4ε‖·‖_F` (scaled as the error), so that no eigensolver finds a larger violation than the
//! status admits.
//!
//! # Correcting the dual before lifting
//!
//! The dual of the reduced problem is a relaxation of the original dual: in the basis `[V, W]`
//! (`W` spanning `range(E)`), `S = [[S_r, B], [Bᵀ, G + t E_W]]`, and the Schur complement makes
//! `S ⪰ 0` possible for a finite `t` only if the coupling `B = VᵀS₀W` lies in `range(S_r)`. The
//! reduced solve returns `y` near the analytic centre of the reduced dual optimal set; when that
//! set has more than one point, that `y` need not be the projection of an original dual
//! solution, `B` has a component along the near-null directions of `S_r` (the range of `Y`),
//! and `t` grows like `‖B‖²/λ_min(S_r)` — so large that the rounding of `t E` spoils the
//! complementarity `⟨X, S⟩` (a planted case: `t = 6.3·10⁹`, complementarity `1.6·10⁻⁸`) or
//! the accuracy `4ε‖S‖_F` of the cone error, and no choice of `t` helps: the cone error falls
//! only as the rounding grows (5× and 9× larger `τ` still gave `t ≈ 3·10⁸`).
//!
//! For a primal optimal `X`, the dual optimal set is `{(y, S) feasible : S X = 0}` (Alizadeh,
//! Haeberly and Overton, "Complementarity and nondegeneracy in semidefinite programming",
//! Math. Program. 77, 1997). With `Q` the orthogonal projector onto the range of the reduced
//! `Y` (decided by [`range_split`] from `Y` and its slack, no threshold) lifted to `V Q Vᵀ`,
//! the equations `S(y) V Q Vᵀ = 0` are linear in `y`, free of the exposing multipliers
//! (`A_e V = 0`), and contain both the reduced complementarity `S_r Q = 0` and the condition
//! `Q Bᵀ = 0` that keeps `t` finite. [`complementary_dual`] moves `y` onto them while keeping
//! `T = Zᵀ S_r Z ≻ 0` on the complement `Z` of the range of `Y`: infeasible-start Newton
//! steps for the barrier `−log det T` subject to the equations (Boyd and Vandenberghe,
//! "Convex Optimization", 2004, §10.3), each cut short of the boundary of `T ⪰ 0`. When the
//! dual optimum is attained the equations are consistent and one full step usually reaches
//! them. A `y` on them leaves in `S_r` only rounding-level negative eigenvalues along the range
//! of `Y`; no `t` can remove those (`λ_min(S₀ + t E)` tends to `λ_min` of `S₀` on the face as
//! `t` grows, [`face_deficit`]), so the margin of the multiplier search is `τ` plus that
//! deficit, and its cone error is left to the measures. In the 2000 planted problems of
//! `facial_reduction_survey` (tests/solver_props.rs) with an attained dual, the plain lift
//! missed `Optimal` in 17, and the corrected lift reached it in all 17.
//!
//! # Which point is returned
//!
//! 1. The point lifted with the reduced solve's `y` ([`super::FacialPath::Lifted`]) if it is
//!    [`Status::Optimal`] (on problems where it is, e.g. the gpp problems, no correction is
//!    computed).
//! 2. Otherwise, when the complementarity system fits [`CORRECTION_ENTRIES`], the point lifted
//!    with the corrected `y` ([`super::FacialPath::Corrected`]) if it is better by the rule of
//!    [`super::solution::better`]: the status class first (optimal, almost optimal,
//!    verified infeasibility, anything else), then the smaller largest DIMACS error; the
//!    plain lift on a tie.
//! 3. If the better of the two is not optimal — or the reduced solve ended infeasible — the
//!    original problem is solved without reduction ([`crate::solve`]), and the better of that
//!    solution and the lifted point by the same rule is returned, the lifted point on a tie;
//!    [`super::FacialPath::Unreduced`] records that the unreduced solve won and the status the
//!    lifted point had. So a solve with facial reduction never ends in a worse status class
//!    than the solve without it, nor, when the lifted point is not optimal, with a larger
//!    largest DIMACS error in the same class — at the price of both solves when the face did
//!    not give an optimal point. This matters when the optimum of (D) is not attained (no
//!    correction can then reach the equations): in the 2000 such planted problems of the
//!    survey the point from the face was not optimal in 620 (the correction rescued 1 more),
//!    and the unreduced solve was optimal in 571 of them.
//!
//! Every step is deterministic (sequential decompositions, fixed order), and no threshold is
//! absolute: `τ` follows the data's scale, the singular value cut-off the matrix's, and the
//! range of `Y` is decided against its slack.
//!
//! Constraints that become linearly dependent on the face are not removed here: the solver
//! handles dependent constraints itself (regularised Cholesky, LBLᵀ and least-squares fallbacks).

use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd::{ComputeEigenvectors, self_adjoint_evd, self_adjoint_evd_scratch};
use std::borrow::Cow;

use faer::{Mat, Par};

use super::blockops::{
    block_inner, cholesky, inverse_from_linv, lower_inverse, min_eig, mul, scatter_sym, symmetrize,
};
use super::point::point_measures;
use super::settings::Settings;
use super::solution::{FacialPath, Solution, Status, better};
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

/// One round: a problem and its [`Face`].
#[derive(Debug, Clone)]
struct Round<'a> {
    /// The problem before this round: the caller's own for the first round (borrowed, not
    /// copied: on gpp500 a copy held 3 MB through the whole solve), the previous round's
    /// reduced problem after it.
    problem: Cow<'a, Problem>,
    face: Face,
}

/// The face a problem's exposing constraints define, and how its constraints map onto the
/// reduced problem's.
#[derive(Debug, Clone)]
struct Face {
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
pub(crate) struct Reduction<'a> {
    rounds: Vec<Round<'a>>,
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

/// One round of reduction of `problem` (its face and the reduced problem), or `None` if nothing
/// is exposed.
/// `Err(())`: the reduction is abandoned (a constraint vanishes on the face with `b_j ≠ 0`, or
/// nothing would be left to solve).
fn round(problem: &Problem) -> Result<Option<(Face, Problem)>, ()> {
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
        Face {
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
pub(crate) fn reduce(problem: &Problem) -> Option<Reduction<'_>> {
    let mut rounds: Vec<Round<'_>> = Vec::new();
    let mut current: Cow<'_, Problem> = Cow::Borrowed(problem);
    while rounds.len() < ROUNDS {
        match round(&current) {
            Ok(Some((face, reduced))) => {
                let problem = std::mem::replace(&mut current, Cow::Owned(reduced));
                rounds.push(Round { problem, face });
            }
            Ok(None) => break,
            Err(()) => return None,
        }
    }
    if rounds.is_empty() {
        None
    } else {
        Some(Reduction {
            rounds,
            reduced: current.into_owned(),
        })
    }
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

/// `max(0, −λ)`, `λ` the smallest eigenvalue of `S₀` on the null space of `E` over the blocks
/// where `E ≠ 0` (LP blocks: the entries where `E` is zero): the part of the cone error of
/// `S₀ + t E` that no multiplier `t` removes, since `λ_min(S₀ + t E)` tends to `λ` as `t`
/// grows. The null space is spanned by the eigenvectors of `E` whose eigenvalues are within
/// the eigenvalue tolerance of zero; a failed eigensolver counts as no deficit.
fn face_deficit(blocks: &[Block], s0: &[Mat<f64>], e: &[Option<Mat<f64>>]) -> f64 {
    let lambda = blocks
        .iter()
        .zip(s0)
        .zip(e)
        .filter_map(|((b, s), e)| {
            let e = e.as_ref()?;
            if b.kind == BlockKind::Lp {
                let on_face = (0..b.size).filter(|&l| e[(l, 0)] == 0.0);
                return Some(on_face.map(|l| s[(l, 0)]).fold(f64::INFINITY, f64::min));
            }
            let (ev, u) = eigen(e, true)?;
            let tol = eig_tol(b.size) * ev.last().copied().unwrap_or(0.0).max(0.0);
            let null: Vec<usize> = (0..b.size).filter(|&i| ev[i].abs() <= tol).collect();
            let v = Mat::from_fn(b.size, null.len(), |r, c| u[(r, null[c])]);
            let mut face = mul(&mul(&v.transpose().to_owned(), s), &v);
            symmetrize(&mut face);
            Some(
                eigen(&face, false)?
                    .0
                    .first()
                    .copied()
                    .unwrap_or(f64::INFINITY),
            )
        })
        .fold(f64::INFINITY, f64::min);
    (-lambda).max(0.0)
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

/// Rows of the complementarity system of `problem`: `n²` per PSD block of order `n`, `n` per
/// LP block.
fn stacked_rows(problem: &Problem) -> usize {
    problem
        .blocks
        .iter()
        .map(|bd| match bd.block.kind {
            BlockKind::Psd => bd.block.size * bd.block.size,
            BlockKind::Lp => bd.block.size,
        })
        .sum()
}

/// The columns `A_j X` (`j` in `free`, in that order) of the complementarity equations
/// `(S₀ − Σ_j δ_j A_j) X = 0`, every block's entries stacked (PSD block of order `n`: the `n²`
/// entries of the product column by column; LP block: the `n` products of entries). It does
/// not depend on `y`; the right-hand side [`complementarity_rhs`] does.
fn complementarity_matrix(problem: &Problem, x: &[Mat<f64>], free: &[usize]) -> Mat<f64> {
    let mut column = vec![usize::MAX; problem.b.len()];
    free.iter().enumerate().for_each(|(q, &j)| column[j] = q);
    let mut g = Mat::<f64>::zeros(stacked_rows(problem), free.len());
    let mut offset = 0;
    for (bd, xk) in problem.blocks.iter().zip(x) {
        let n = bd.block.size;
        let psd = bd.block.kind == BlockKind::Psd;
        for (j, a) in &bd.a {
            let q = column[*j];
            if q == usize::MAX {
                continue;
            }
            let mut add = |r: usize, c: usize, v: f64| {
                // Row r of A X gains v·(row c of X) (X symmetric: column c).
                if psd {
                    for l in 0..n {
                        g[(offset + r + n * l, q)] += v * xk[(c, l)];
                    }
                } else {
                    g[(offset + r, q)] += v * xk[(r, 0)];
                }
            };
            for (r, c, v) in a.iter() {
                add(r, c, v);
                if psd && r != c {
                    add(c, r, v);
                }
            }
        }
        offset += if psd { n * n } else { n };
    }
    g
}

/// The right-hand side `S₀ X` of the complementarity equations, stacked as the rows of
/// [`complementarity_matrix`].
fn complementarity_rhs(problem: &Problem, x: &[Mat<f64>], s0: &[Mat<f64>]) -> Vec<f64> {
    let mut h = Vec::with_capacity(stacked_rows(problem));
    for ((bd, xk), sk) in problem.blocks.iter().zip(x).zip(s0) {
        let n = bd.block.size;
        if bd.block.kind == BlockKind::Psd {
            let product = mul(sk, xk);
            for j in 0..n {
                h.extend((0..n).map(|i| product[(i, j)]));
            }
        } else {
            h.extend((0..n).map(|i| sk[(i, 0)] * xk[(i, 0)]));
        }
    }
    h
}

/// A singular value decomposition `G = U Σ Vᵀ` (computed sequentially, for determinism) for
/// least-squares solutions of smallest norm of `G δ = h` and the numerical null space of `G`,
/// with the singular values below `max(rows, cols)·ε·σ_max` treated as zero (the rule of
/// LAPACK's `xGELSS` and NumPy's `lstsq`).
struct MinNorm {
    u: Mat<f64>,
    sv: Diag<f64>,
    v: Mat<f64>,
    rank: usize,
}

impl MinNorm {
    /// The decomposition of `g`; `None` if it fails.
    fn new(g: &Mat<f64>) -> Option<Self> {
        use faer::linalg::svd::{ComputeSvdVectors, svd, svd_scratch};
        let (rows, cols) = (g.nrows(), g.ncols());
        let k = rows.min(cols);
        let mut sv = Diag::<f64>::zeros(k);
        let mut u = Mat::<f64>::zeros(rows, k);
        let mut v = Mat::<f64>::zeros(cols, cols);
        let mut mem = MemBuffer::new(svd_scratch::<f64>(
            rows,
            cols,
            ComputeSvdVectors::Thin,
            ComputeSvdVectors::Full,
            Par::Seq,
            Default::default(),
        ));
        svd(
            g.as_ref(),
            sv.as_mut(),
            Some(u.as_mut()),
            Some(v.as_mut()),
            Par::Seq,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .ok()?;
        let sigma_max = (0..k).map(|i| sv[i]).fold(0.0f64, f64::max);
        let cutoff = rows.max(cols) as f64 * f64::EPSILON * sigma_max;
        let rank = (0..k).filter(|&i| sv[i] > cutoff).count();
        Some(Self { u, sv, v, rank })
    }

    /// The least-squares solution of smallest norm of `G δ = h`.
    fn solve(&self, h: &[f64]) -> Vec<f64> {
        let (rows, cols) = (self.u.nrows(), self.v.nrows());
        let mut delta = vec![0.0; cols];
        for i in 0..self.rank {
            let coef = (0..rows).map(|r| self.u[(r, i)] * h[r]).sum::<f64>() / self.sv[i];
            delta
                .iter_mut()
                .enumerate()
                .for_each(|(c, d)| *d += coef * self.v[(c, i)]);
        }
        delta
    }

    /// An orthonormal basis of the numerical null space of `G`.
    fn null(&self) -> Mat<f64> {
        let cols = self.v.nrows();
        Mat::from_fn(cols, cols - self.rank, |r, c| self.v[(r, self.rank + c)])
    }
}

/// Largest number of entries of the complementarity system for which [`complementary_dual`]
/// is tried (`2²²`, 32 MiB of `f64`; e.g. one block of order 200 with 100 constraints).
const CORRECTION_ENTRIES: usize = 1 << 22;

/// Largest number of Newton steps of [`complementary_dual`].
const NEWTON_STEPS: usize = 20;

/// Fraction of the step to the boundary of `T ⪰ 0` that a Newton step of
/// [`complementary_dual`] takes at most (the usual interior-point safeguard).
const STEP_FRACTION: f64 = 0.9;

/// `Zᵀ M Z` block by block.
fn compress(z: &[Mat<f64>], m: &[Mat<f64>]) -> Vec<Mat<f64>> {
    z.iter()
        .zip(square(m))
        .map(|(z, m)| mul(&mul(&z.transpose().to_owned(), &m), z))
        .collect()
}

/// The dual of the problem after a round (`y`, one entry per kept constraint of the problem
/// before it, `problem`), corrected towards the dual optimal set of `problem` (module
/// documentation): Newton steps for the barrier `−log det T(y)`, `T = Zᵀ S_face(y) Z` the
/// slack of `face` (the problem after the round) on the complement `Z` of the range of its
/// primal solution, subject to the complementarity equations `S(y) Q = 0` of `problem`
/// (`Q` the lifted range projector), which are linear in `y` — the infeasible-start Newton
/// method for equality-constrained minimisation (Boyd and Vandenberghe, "Convex
/// Optimization", 2004, §10.3): each step solves the equations in the least-squares sense
/// with the smallest norm plus a Newton step for the barrier in their null space, and is cut
/// to [`STEP_FRACTION`] of the way to the boundary of `T ⪰ 0`. It stops after a full step
/// whose Newton decrement `δᵀHδ` is at most `1/4` (the region of quadratic convergence), or
/// after [`NEWTON_STEPS`]; `y` is left as it is if `T(y)` is not positive definite at the
/// start or a decomposition fails.
fn complementary_dual(
    problem: &Problem,
    q: &[Mat<f64>],
    kept: &[usize],
    face: &Problem,
    z: &[Mat<f64>],
    y: &mut [f64],
) {
    let m = kept.len();
    let Ok(a) = (0..m)
        .map(|j| face.dense_constraint(j).map(|aj| compress(z, &aj)))
        .collect::<Result<Vec<_>, _>>()
    else {
        return;
    };
    // The equations' matrix does not depend on `y`: decomposed once for every step.
    let Some(equations) = MinNorm::new(&complementarity_matrix(problem, q, kept)) else {
        return;
    };
    for _ in 0..NEWTON_STEPS {
        let Some(step) = newton_step(problem, q, kept, face, z, &a, &equations, y) else {
            return;
        };
        let (delta, alpha, decrement) = step;
        y.iter_mut().zip(&delta).for_each(|(v, d)| *v += alpha * d);
        if alpha == 1.0 && decrement <= 0.25 {
            return;
        }
    }
}

/// One step of [`complementary_dual`]: `(δ, α, δᵀHδ)`, or `None` if `T(y)` is not positive
/// definite or a decomposition fails. `a[j]` is `Zᵀ A_j Z` for the `j`-th constraint of
/// `face`; `equations` the decomposition of [`complementarity_matrix`].
fn newton_step(
    problem: &Problem,
    q: &[Mat<f64>],
    kept: &[usize],
    face: &Problem,
    z: &[Mat<f64>],
    a: &[Vec<Mat<f64>>],
    equations: &MinNorm,
    y: &[f64],
) -> Option<(Vec<f64>, f64, f64)> {
    let m = kept.len();
    let mut full = vec![0.0; problem.b.len()];
    kept.iter().zip(y).for_each(|(&j, &v)| full[j] = v);
    let h = complementarity_rhs(problem, q, &slack(problem, &full));
    let t = compress(z, &slack(face, y));
    let linv: Vec<Mat<f64>> = t
        .iter()
        .map(|t| cholesky(t).map(|l| lower_inverse(&l)))
        .collect::<Option<_>>()?;
    let tinv: Vec<Mat<f64>> = linv.iter().map(inverse_from_linv).collect();
    // B_j = T⁻¹ Ã_j: gradient tr(B_j) and Hessian tr(B_i B_j) of −log det T.
    let b: Vec<Vec<Mat<f64>>> = a
        .iter()
        .map(|aj| tinv.iter().zip(aj).map(|(ti, ajk)| mul(ti, ajk)).collect())
        .collect();
    let trace_of_product = |u: &Mat<f64>, v: &Mat<f64>| -> f64 {
        (0..u.nrows())
            .flat_map(|r| (0..u.ncols()).map(move |c| (r, c)))
            .map(|(r, c)| u[(r, c)] * v[(c, r)])
            .sum()
    };
    let grad: Vec<f64> = b
        .iter()
        .map(|bj| {
            bj.iter()
                .map(|bk| (0..bk.nrows()).map(|i| bk[(i, i)]).sum::<f64>())
                .sum()
        })
        .collect();
    let hess = Mat::from_fn(m, m, |i, j| {
        b[i].iter()
            .zip(&b[j])
            .map(|(u, v)| trace_of_product(u, v))
            .sum()
    });
    let particular = equations.solve(&h);
    let null = equations.null();
    // Newton step in the null space: (NᵀHN) w = −Nᵀ(∇f + H δ_p).
    let hp: Vec<f64> = (0..m)
        .map(|i| grad[i] + (0..m).map(|j| hess[(i, j)] * particular[j]).sum::<f64>())
        .collect();
    let k = null.ncols();
    let hn = mul(&hess, &null);
    let reduced = mul(&null.transpose().to_owned(), &hn);
    let rhs: Vec<f64> = (0..k)
        .map(|c| -(0..m).map(|r| null[(r, c)] * hp[r]).sum::<f64>())
        .collect();
    let w = if k == 0 {
        Vec::new()
    } else {
        MinNorm::new(&reduced)?.solve(&rhs)
    };
    let delta: Vec<f64> = (0..m)
        .map(|r| particular[r] + (0..k).map(|c| null[(r, c)] * w[c]).sum::<f64>())
        .collect();
    let decrement: f64 = (0..m)
        .map(|i| delta[i] * (0..m).map(|j| hess[(i, j)] * delta[j]).sum::<f64>())
        .sum();
    // T(y + αδ) = T − α ΔT: the step to the boundary is 1/λ_max(L⁻¹ ΔT L⁻ᵀ).
    let mut rho = 0.0f64;
    for (kb, l) in linv.iter().enumerate() {
        if l.nrows() == 0 {
            continue;
        }
        let mut dt = Mat::<f64>::zeros(l.nrows(), l.nrows());
        for (j, aj) in a.iter().enumerate() {
            for c in 0..dt.ncols() {
                for r in 0..dt.nrows() {
                    dt[(r, c)] += delta[j] * aj[kb][(r, c)];
                }
            }
        }
        let mut scaled = mul(&mul(l, &dt), &l.transpose().to_owned());
        symmetrize(&mut scaled);
        let (ev, _) = eigen(&scaled, false)?;
        rho = rho.max(ev.last().copied().unwrap_or(0.0));
    }
    let alpha = if rho <= STEP_FRACTION {
        1.0
    } else {
        STEP_FRACTION / rho
    };
    Some((delta, alpha, decrement))
}

/// `V X Vᵀ` block by block: a matrix of the problem after `round` lifted to the problem
/// before it (LP blocks: the kept entries; dropped blocks: zero).
fn lift_primal(round: &Round<'_>, x: &[Mat<f64>]) -> Vec<Mat<f64>> {
    round
        .problem
        .blocks
        .iter()
        .zip(&round.face.bases)
        .zip(&round.face.block_map)
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
        .collect()
}

/// A dense copy of every block, LP columns as diagonal matrices.
fn square(m: &[Mat<f64>]) -> Vec<Mat<f64>> {
    m.iter()
        .map(|b| {
            if b.ncols() == 1 && b.nrows() > 1 {
                Mat::from_fn(
                    b.nrows(),
                    b.nrows(),
                    |i, j| if i == j { b[(i, 0)] } else { 0.0 },
                )
            } else {
                b.clone()
            }
        })
        .collect()
}

/// The numerical range of `X` and its complement, block by block (module documentation): an
/// eigenvector `u` of `X` with eigenvalue `ξ` is in the range when `ξ/ξ_max > σ/σ_max`,
/// `σ = uᵀSu` for the complementary slack `S`, the maxima taken over all blocks (LP blocks:
/// the unit vectors, `x_l` and `s_l`). Near a strictly complementary solution `ξ σ ≈ μ` along
/// the central path, so each direction has one large and one small partner: an indicator in
/// the sense of El-Bakry, Tapia and Zhang ("A study of indicators for identifying zero
/// variables in interior-point methods", SIAM Rev. 36, 1994), free of any threshold. Returns
/// the orthogonal projector onto the range (in the layout of `x`) and an orthonormal basis of
/// the complement (`n × (n − rank)`; LP blocks: unit vectors); `None` if an eigensolver fails.
fn range_split(x: &[Mat<f64>], s: &[Mat<f64>]) -> Option<(Vec<Mat<f64>>, Vec<Mat<f64>>)> {
    let (xs, ss) = (square(x), square(s));
    let pairs: Vec<(Vec<f64>, Vec<f64>, Mat<f64>)> = xs
        .iter()
        .zip(&ss)
        .map(|(xk, sk)| {
            let (xi, u) = eigen(xk, true)?;
            let su = mul(sk, &u);
            let sigma = (0..u.ncols())
                .map(|c| (0..u.nrows()).map(|r| u[(r, c)] * su[(r, c)]).sum())
                .collect();
            Some((xi, sigma, u))
        })
        .collect::<Option<_>>()?;
    let max = |v: &[f64]| v.iter().fold(0.0f64, |m, e| m.max(*e));
    let xi_max = pairs.iter().map(|p| max(&p.0)).fold(0.0, f64::max);
    let sigma_max = pairs.iter().map(|p| max(&p.1)).fold(0.0, f64::max);
    let mut projectors = Vec::with_capacity(x.len());
    let mut complements = Vec::with_capacity(x.len());
    for ((xi, sigma, u), xk) in pairs.iter().zip(x) {
        let n = u.nrows();
        let range: Vec<bool> = xi
            .iter()
            .zip(sigma)
            .map(|(&a, &b)| a * sigma_max > b * xi_max)
            .collect();
        let mut q = Mat::<f64>::zeros(n, xk.ncols());
        for i in (0..n).filter(|&i| range[i]) {
            for c in 0..q.ncols() {
                for r in 0..n {
                    // LP: the diagonal of the projector, in one column.
                    let col = if xk.ncols() == 1 { r } else { c };
                    q[(r, c)] += u[(r, i)] * u[(col, i)];
                }
            }
        }
        let outside: Vec<usize> = (0..n).filter(|&i| !range[i]).collect();
        let z = Mat::from_fn(n, outside.len(), |r, c| u[(r, outside[c])]);
        projectors.push(q);
        complements.push(z);
    }
    Some((projectors, complements))
}

impl Reduction<'_> {
    /// The problem to solve.
    pub(crate) fn problem(&self) -> &Problem {
        &self.reduced
    }

    /// Whether the complementarity system of every round ([`complementarity_matrix`]: a dense
    /// `Σ_k n_k² × m` matrix and its singular value decomposition, `Σ_k n_k²·m²` flops) stays
    /// within [`CORRECTION_ENTRIES`]; beyond it a face that is not optimal goes straight to the
    /// unreduced solve, whose time and memory are those of any solve.
    fn correction_fits(&self) -> bool {
        self.rounds.iter().all(|r| {
            stacked_rows(&r.problem).saturating_mul(r.face.kept.len()) <= CORRECTION_ENTRIES
        })
    }

    /// The point of the original problem that `sol` (a solution of [`Reduction::problem`])
    /// stands for: `(X, y, S)` (module documentation), with the dual of every round corrected
    /// by [`complementary_dual`] first if `correct`.
    fn lift(
        &self,
        sol: &Solution,
        tau: f64,
        correct: bool,
    ) -> (Vec<Mat<f64>>, Vec<f64>, Vec<Mat<f64>>) {
        let (mut x, mut y) = (sol.x.clone(), sol.y.clone());
        for (i, r) in self.rounds.iter().enumerate().rev() {
            let p = &r.problem;
            if correct {
                let face = self
                    .rounds
                    .get(i + 1)
                    .map_or(&self.reduced, |next| &next.problem);
                if let Some((q, z)) = range_split(&x, &slack(face, &y)) {
                    complementary_dual(p, &lift_primal(r, &q), &r.face.kept, face, &z, &mut y);
                }
            }
            x = lift_primal(r, &x);
            let mut full_y = vec![0.0; p.b.len()];
            r.face
                .kept
                .iter()
                .zip(&y)
                .for_each(|(&j, &v)| full_y[j] = v);
            let blocks: Vec<Block> = p.blocks.iter().map(|bd| bd.block).collect();
            let s0 = slack(p, &full_y);
            let e: Vec<Option<Mat<f64>>> = p
                .blocks
                .iter()
                .map(|bd| {
                    let e = exposing_sum(bd, &r.face.exposing);
                    (!e.is_empty()).then(|| e.to_dense(bd.block))
                })
                .collect();
            let t = multiplier(&blocks, &s0, &e, tau + face_deficit(&blocks, &s0, &e));
            r.face
                .exposing
                .iter()
                .for_each(|&(i, sign)| full_y[i] = -t * sign);
            y = full_y;
        }
        let s = slack(&self.rounds[0].problem, &y);
        (x, y, s)
    }

    /// The solution of the original `problem` from `sol`, the solution of
    /// [`Reduction::problem`] (module documentation, "Which point is returned"): the lifted
    /// point if it is [`Status::Optimal`], otherwise the better ([`super::solution::better`])
    /// of it and the point lifted with the corrected dual.
    pub(crate) fn solution(
        &self,
        problem: &Problem,
        sol: &Solution,
        settings: &Settings,
    ) -> Result<Solution, SdpError> {
        let lifted = self.lifted(problem, sol, settings, false)?;
        if lifted.status.is_optimal() || !self.correction_fits() {
            return Ok(lifted);
        }
        let corrected = self.lifted(problem, sol, settings, true)?;
        Ok(better(lifted, corrected))
    }

    /// The point lifted from `sol` (dual corrected if `correct`) with its measures against the
    /// original `problem` and the status of the rule of [`Status`] (the cone errors of the
    /// lifted point, which is not an interior iterate, are held to `tol_feas` for
    /// [`Status::Optimal`]).
    fn lifted(
        &self,
        problem: &Problem,
        sol: &Solution,
        settings: &Settings,
        correct: bool,
    ) -> Result<Solution, SdpError> {
        let c = problem.dense_objective();
        let c_max = c
            .iter()
            .flat_map(|m| (0..m.ncols()).flat_map(move |j| m.col_as_slice(j).iter()))
            .fold(0.0f64, |x, v| x.max(v.abs()));
        let tau = 0.1 * settings.tol_feas * (1.0 + c_max);
        let (x, y, s) = self.lift(sol, tau, correct);
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
            solve_time: sol.solve_time,
            facial: if correct {
                FacialPath::Corrected
            } else {
                FacialPath::Lifted
            },
            restarted: sol.restarted,
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

    /// The range of `X` is decided against `S`: `X = diag(1, 1e-9, 0.5)` with
    /// `S = diag(1e-9, 2, 1e-9)` has range `{e₀, e₂}`; in the LP block `x = (1e-9, 3)`,
    /// `s = (1, 1e-9)` the second entry.
    #[test]
    fn range_split_follows_the_complementary_pair() {
        let diag =
            |d: &[f64]| Mat::from_fn(d.len(), d.len(), |i, j| if i == j { d[i] } else { 0.0 });
        let col = |d: &[f64]| Mat::from_fn(d.len(), 1, |i, _| d[i]);
        let x = vec![diag(&[1.0, 1e-9, 0.5]), col(&[1e-9, 3.0])];
        let s = vec![diag(&[1e-9, 2.0, 1e-9]), col(&[1.0, 1e-9])];
        let (q, z) = range_split(&x, &s).expect("eigensolver");
        let close = |a: &Mat<f64>, b: &Mat<f64>| {
            (0..a.ncols()).all(|j| (0..a.nrows()).all(|i| (a[(i, j)] - b[(i, j)]).abs() < 1e-12))
        };
        assert!(close(&q[0], &diag(&[1.0, 0.0, 1.0])), "{:?}", q[0]);
        assert!(close(&q[1], &col(&[0.0, 1.0])), "{:?}", q[1]);
        assert_eq!((z[0].nrows(), z[0].ncols()), (3, 1));
        assert!((z[0][(1, 0)].abs() - 1.0).abs() < 1e-12);
        assert_eq!((z[1].ncols(), z[1][(0, 0)].abs()), (1, 1.0));
    }

    /// `min_norm_and_null` on a rank-one `2×3` system: the solution of smallest norm and the
    /// two-dimensional null space.
    #[test]
    fn min_norm_solution_and_null_space() {
        let g = Mat::from_fn(2, 3, |i, j| (i + 1) as f64 * [1.0, 2.0, 2.0][j]);
        let equations = MinNorm::new(&g).expect("svd");
        let (delta, null) = (equations.solve(&[3.0, 6.0]), equations.null());
        let expected = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
        assert!(
            delta
                .iter()
                .zip(expected)
                .all(|(d, e)| (d - e).abs() < 1e-14),
            "{delta:?}"
        );
        assert_eq!(null.ncols(), 2);
        for c in 0..2 {
            let r: f64 = (0..3).map(|j| [1.0, 2.0, 2.0][j] * null[(j, c)]).sum();
            assert!(r.abs() < 1e-14, "{r}");
        }
    }
}
