//! The HKM Newton system as a least-squares problem in the scaled space, solved by an orthogonal
//! (Householder QR) factorisation instead of the normal equations.
//!
//! # Why
//!
//! With `X = L_X L_Xᵀ`, `S = L_S L_Sᵀ` and the scaled constraint matrices
//!
//! ```text
//! K_i = L_Xᵀ A_i L_S⁻ᵀ          (one n×n matrix per block; √(x_l/s_l)·a_il for an LP block)
//! ```
//!
//! the Schur matrix is the Gram matrix `M = KᵀK`, `M_ij = ⟨K_i, K_j⟩`, and `X 𝒜ᵀ(δ) S⁻¹ =
//! L_X 𝒦(δ) L_S⁻¹` with `𝒦(δ) = Σ δ_i K_i`. The HKM direction `ΔX = sym(−X − T + X 𝒜ᵀ(Δy) S⁻¹)`
//! (`T` as in [`super::direction`]) becomes
//!
//! ```text
//! ΔX = sym(L_X Z L_S⁻¹),   Z = G + 𝒦(Δy),   G = −L_Xᵀ (L_S + R_d L_S⁻ᵀ) − L_X⁻¹ (H − σμ I) L_S⁻ᵀ,
//! ```
//!
//! and the primal equation `𝒜(ΔX) = r_p` reads `Kᵀ(g + K Δy) = r_p` (`g = vec G`): the normal
//! equations of a least-squares problem. Near the optimum the condition number of `K` grows like
//! `1/μ` and that of `M = KᵀK` like `1/μ²`; once it passes `1/ε ≈ 10¹⁶` (control and truss
//! problems of SDPLIB at `μ ≈ 10⁻⁷`, ill-posed control LMIs earlier) the computed `M` is
//! indefinite or its Cholesky solve leaves a residual `‖M Δy − r‖ ≈ ε ‖M‖ ‖Δy‖` far above the
//! feasibility tolerance, so the primal infeasibility *grows* while `μ` falls. This is where
//! CSDP ("partial success") and SDPA (`pFEAS`) stop.
//!
//! Solving the same system with the thin QR factorisation `K = Q R` (Golub & Van Loan,
//! *Matrix Computations*, 4th ed., §5.3; the augmented-system argument for interior-point methods
//! is M. H. Wright, SIAM J. Optim. 9(1), 1998) avoids forming `M`:
//!
//! ```text
//! c = Qᵀ g,   w = R⁻ᵀ r_p,   Δy = R⁻¹ (w − c₁),   Z = Q [w; c₂]
//! ```
//!
//! so that `KᵀZ = Rᵀ w = r_p` holds up to `ε ‖K‖ ‖Z‖` (backward stability of Householder QR):
//! the error of the primal equation no longer depends on `cond(M)`, and the dual equation
//! `ΔS = R_d − 𝒜ᵀ(Δy)` is exact by construction. Errors in `G` (which carries the ill-conditioned
//! factors) only perturb the complementarity part of the direction, which the next iterations
//! correct anyway.
//!
//! # When
//!
//! A QR of the `N×m` matrix `K` (`N = Σ n_k²`) costs about twice a symmetric rank-`N` update and
//! needs `N·m` numbers, so the normal equations remain the default; [`super::ipm`] switches to
//! this form for the rest of a solve as soon as a normal-equations direction misses
//! `𝒜(ΔX) = r_p` by more than the accepted error after iterative refinement, provided `K` fits
//! the memory budget (`N ≥ m` and `(N + m)·m` numbers at most 128 MiB).
//!
//! # Dependent constraints
//!
//! Numerically dependent constraints (duplicates, degeneracy at the optimum as in the QAP
//! relaxations, or the diverging dual ray of the hinf problems, along which `K` loses rank like
//! `μ`) show up as pivots `R_ii` at rounding level. Householder QR then stops being a usable
//! factor: faer deflates such a column (see [`DEFLATION`]) and leaves `R` in echelon form, and
//! raising the tiny pivots to a floor (what this module did before) gives a triangular matrix
//! whose inverse grows like `floor⁻ᵏ` over `k` dependent columns, not the factor of any nearby
//! matrix: on hinf10, hinf11 and qap6 the least-squares direction reached `10¹²⁸` and the solve
//! stopped.
//!
//! Instead, when a pivot falls below the deflation level, the QR is recomputed for the stacked
//! matrix `[K; ρD]` with `D = diag(‖K_i‖)` on the flagged constraints only (zero elsewhere):
//! Tikhonov regularisation (Golub & Van Loan, 4th ed., §6.1; like Clarabel's regularisation of
//! its QDLDL factorisation, applied only to the pivots found too small). Its
//! `R̃` is the exact triangular factor of `M + ρ² D²` with `|R̃_ii| ≥ ρ ‖K_i‖` (row `N + i`
//! is untouched until column `i`), so `Δy` stays bounded. With `K̃ = [K; ρD]`, `g̃ = [g; 0]`
//! the same formulas give `Z̃ = g̃ + K̃ Δy` and `K̃ᵀZ̃ = r_p`, i.e. `Z = g + K Δy` (the
//! complementarity equation is exact) and `KᵀZ = r_p − ρ² D² Δy`: the regularisation only
//! perturbs the primal equation, which the iterative refinement of [`super::direction`]
//! (Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., ch. 12) corrects along
//! every direction not itself at rounding level. `ρ` ([`REGULARISATION`]) is twice the
//! deflation level, so faer cannot deflate a regularised column; constraints whose pivots are
//! above the deflation level are not regularised (regularising others only raises their
//! pivots), so problems without dependent constraints get the same direction as before.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::householder::{
    apply_block_householder_sequence_on_the_left_in_place_scratch,
    apply_block_householder_sequence_on_the_left_in_place_with_conj,
    apply_block_householder_sequence_transpose_on_the_left_in_place_scratch,
    apply_block_householder_sequence_transpose_on_the_left_in_place_with_conj,
};
use faer::linalg::qr::no_pivoting::factor::{
    qr_in_place, qr_in_place_scratch, recommended_block_size,
};
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Conj, Mat, MatMut, Par};
use rayon::prelude::*;

use super::blockops::{BlockMats, Factors, load, load_transposed, mul, store, symmetrize};
use super::direction::Predictor;
use super::par::Exec;
use super::small;
use super::structure::{Analysis, Values};
use crate::problem::BlockKind;

/// Largest `[K; ρD]` ((rows + constraints) × constraints, in `f64`s) that is allocated
/// (128 MiB).
const MAX_ELEMENTS: usize = 1 << 24;
/// Relative pivot level, in units of `(rows of [K; ρD]) · ε`, below which faer's Householder QR
/// may treat a column as dependent: `qr_in_place` (faer 0.24, `no_pivoting::factor`) skips the
/// reflection of a column whose remaining norm is below `16·(rows − row)·ε` times its norm and
/// does *not* advance the row, which leaves `R` in echelon form with exact zeros on the
/// diagonal of the later columns. A pivot `|R_ii|` below `DEFLATION · rows · ε · ‖K_i‖` flags
/// constraint `i` as numerically dependent.
const DEFLATION: f64 = 16.0;
/// Tikhonov weight `ρ` of a dependent constraint in the same units: twice [`DEFLATION`], so that
/// the regularised column keeps a pivot `|R_ii| ≥ ρ ‖K_i‖` above faer's deflation level and `R`
/// is a true triangular factor.
const REGULARISATION: f64 = 2.0 * DEFLATION;
/// A constraint whose support covers at least this fraction of a block is scaled densely.
const DENSE_SUPPORT: f64 = 0.7;

/// Scaled constraint matrix `K`, overwritten by its Householder QR factorisation.
pub(crate) struct LeastSquares {
    m: usize,
    /// First row of every block in the stacked scaled space (`n²` rows per PSD block, `n` per LP
    /// block).
    offsets: Vec<usize>,
    rows: usize,
    /// For every constraint: `(block, local index)` of each block it touches.
    touches: Vec<Vec<(usize, usize)>>,
    /// For every PSD block and local constraint: the sorted support (row/column indices) of `A_i`.
    supports: Vec<Vec<Vec<usize>>>,
    /// `R` in the upper triangle, the Householder vectors below it.
    qr: Mat<f64>,
    /// Block Householder factors.
    coeff: Mat<f64>,
}

fn support_of(rows: &[usize], cols: &[usize]) -> Vec<usize> {
    let mut s: Vec<usize> = rows.iter().chain(cols).copied().collect();
    s.sort_unstable();
    s.dedup();
    s
}

impl LeastSquares {
    /// Whether [`LeastSquares::new`] can allocate the form for `an` (the size test alone).
    pub(crate) fn fits(an: &Analysis) -> bool {
        let m = an.m;
        let rows = an.blocks.iter().try_fold(0usize, |rows, b| {
            rows.checked_add(match b.kind {
                BlockKind::Psd => b.n.checked_mul(b.n)?,
                BlockKind::Lp => b.n,
            })
        });
        rows.is_some_and(|rows| {
            m > 0
                && rows >= m
                && rows
                    .checked_add(m)
                    .and_then(|r| r.checked_mul(m))
                    .is_some_and(|e| e <= MAX_ELEMENTS)
        })
    }

    /// Workspaces for `an`, or `None` when `K` would exceed the memory budget or cannot have full
    /// column rank (fewer scaled rows than constraints).
    pub(crate) fn new(an: &Analysis) -> Option<Self> {
        if !Self::fits(an) {
            return None;
        }
        let m = an.m;
        let mut offsets = Vec::with_capacity(an.blocks.len());
        let mut rows = 0usize;
        for b in &an.blocks {
            offsets.push(rows);
            rows += match b.kind {
                BlockKind::Psd => b.n * b.n,
                BlockKind::Lp => b.n,
            };
        }
        let mut touches = vec![Vec::new(); m];
        let mut supports = Vec::with_capacity(an.blocks.len());
        for (k, b) in an.blocks.iter().enumerate() {
            for (p, pat) in b.cons.iter().enumerate() {
                touches[pat.con].push((k, p));
            }
            supports.push(match b.kind {
                BlockKind::Psd => b
                    .cons
                    .iter()
                    .map(|pat| support_of(&pat.rows, &pat.cols))
                    .collect(),
                BlockKind::Lp => Vec::new(),
            });
        }
        let block = recommended_block_size::<f64>(rows + m, m);
        Some(Self {
            m,
            offsets,
            rows,
            touches,
            supports,
            qr: Mat::zeros(rows + m, m),
            coeff: Mat::zeros(block, m),
        })
    }

    /// Builds `K` at the iterate with factors `f` and factorises it, regularising the
    /// numerically dependent constraints (module documentation). Returns `false` (and leaves the
    /// workspace unusable until the next call) if a constraint is empty or the factorisation is
    /// not finite.
    pub(crate) fn factorize(
        &mut self,
        an: &Analysis,
        vals: &Values,
        x: &[Mat<f64>],
        f: &Factors,
    ) -> bool {
        self.fill(an, vals, x, f);
        let (rows, m) = (self.rows, self.m);
        let norms: Vec<f64> = (0..m).map(|c| self.qr.get(..rows, c).norm_l2()).collect();
        // An empty constraint (`A_i = 0`, hence `K_i = 0`) has no Householder reflection and
        // flooring its pivot made `Δy` overflow (planted problem with an empty constraint,
        // `solver_props::empty_constraint_keeps_normal_equations`): leave such problems to the
        // regularised normal equations, which decouple the row.
        if norms.contains(&0.0) {
            return false;
        }
        self.factor_in_place();
        let unit = (rows + m) as f64 * f64::EPSILON;
        let finite = |qr: &Mat<f64>| (0..m).all(|i| qr[(i, i)].is_finite());
        if !finite(&self.qr) {
            return false;
        }
        let dependent: Vec<usize> = (0..m)
            .filter(|&i| !(self.qr[(i, i)].abs() >= DEFLATION * unit * norms[i]))
            .collect();
        if dependent.is_empty() {
            return true;
        }
        self.fill(an, vals, x, f);
        for &i in &dependent {
            self.qr[(rows + i, i)] = REGULARISATION * unit * norms[i];
        }
        self.factor_in_place();
        finite(&self.qr)
    }

    /// Householder QR of the stacked `[K; ρD]` in place (`R` in the upper triangle).
    fn factor_in_place(&mut self) {
        let (rows, m) = (self.rows + self.m, self.m);
        let block = self.coeff.nrows();
        let mut mem = MemBuffer::new(qr_in_place_scratch::<f64>(
            rows,
            m,
            block,
            Par::Seq,
            Default::default(),
        ));
        qr_in_place(
            self.qr.as_mut(),
            self.coeff.as_mut(),
            Par::Seq,
            MemStack::new(&mut mem),
            Default::default(),
        );
    }

    /// Writes the scaled constraint matrix `K` into the first rows of the workspace and zeroes
    /// the regularisation rows below it.
    fn fill(&mut self, an: &Analysis, vals: &Values, x: &[Mat<f64>], f: &Factors) {
        let Self {
            offsets,
            touches,
            supports,
            qr,
            ..
        } = self;
        let fill = |c: usize, col: faer::ColMut<'_, f64>| {
            let col = col
                .try_as_col_major_mut()
                .expect("the columns of a Mat are contiguous")
                .as_slice_mut();
            col.fill(0.0);
            for &(k, p) in &touches[c] {
                let b = &an.blocks[k];
                let o = offsets[k];
                let v = &vals.a[k][p];
                let pat = &b.cons[p];
                match b.kind {
                    BlockKind::Lp => {
                        let (xs, zs) = (x[k].col_as_slice(0), f.zinv[k].col_as_slice(0));
                        for (e, &l) in pat.rows.iter().enumerate() {
                            col[o + l] += (xs[l] * zs[l]).sqrt() * v[e];
                        }
                    }
                    BlockKind::Psd => {
                        let n = b.n;
                        add_scaled_constraint(
                            ConstraintPattern {
                                n,
                                rows: &pat.rows,
                                cols: &pat.cols,
                                v,
                                support: &supports[k][p],
                            },
                            &f.lx[k],
                            &f.linv_s[k],
                            &mut col[o..o + n * n],
                        );
                    }
                }
            }
        };
        match an.exec {
            Exec::Sequential => qr
                .col_iter_mut()
                .enumerate()
                .for_each(|(c, col)| fill(c, col)),
            Exec::Parallel => qr
                .par_col_iter_mut()
                .enumerate()
                .for_each(|(c, col)| fill(c, col)),
        }
    }

    fn apply_qt(&self, v: &mut [f64]) {
        let mut mem = MemBuffer::new(
            apply_block_householder_sequence_transpose_on_the_left_in_place_scratch::<f64>(
                self.rows + self.m,
                self.coeff.nrows(),
                1,
            ),
        );
        apply_block_householder_sequence_transpose_on_the_left_in_place_with_conj(
            self.qr.as_ref(),
            self.coeff.as_ref(),
            Conj::No,
            MatMut::from_column_major_slice_mut(v, self.rows + self.m, 1),
            Par::Seq,
            MemStack::new(&mut mem),
        );
    }

    fn apply_q(&self, v: &mut [f64]) {
        let mut mem = MemBuffer::new(
            apply_block_householder_sequence_on_the_left_in_place_scratch::<f64>(
                self.rows + self.m,
                self.coeff.nrows(),
                1,
            ),
        );
        apply_block_householder_sequence_on_the_left_in_place_with_conj(
            self.qr.as_ref(),
            self.coeff.as_ref(),
            Conj::No,
            MatMut::from_column_major_slice_mut(v, self.rows + self.m, 1),
            Par::Seq,
            MemStack::new(&mut mem),
        );
    }

    /// `R⁻ᵀ v` in place.
    fn solve_rt(&self, v: &mut [f64]) {
        let r = self.qr.get(..self.m, ..self.m);
        solve_lower_triangular_in_place(
            r.transpose(),
            MatMut::from_column_major_slice_mut(v, self.m, 1),
            Par::Seq,
        );
    }

    /// `R⁻¹ v` in place.
    fn solve_r(&self, v: &mut [f64]) {
        let r = self.qr.get(..self.m, ..self.m);
        solve_upper_triangular_in_place(
            r,
            MatMut::from_column_major_slice_mut(v, self.m, 1),
            Par::Seq,
        );
    }

    /// `ΔX = sym(L_X Z L_S⁻¹)` per block from the stacked scaled `Z`.
    fn unscale(&self, an: &Analysis, x: &[Mat<f64>], f: &Factors, z: &[f64]) -> BlockMats {
        an.map_blocks(|k, b| {
            let o = self.offsets[k];
            match b.kind {
                BlockKind::Lp => {
                    let (xs, zs) = (x[k].col_as_slice(0), f.zinv[k].col_as_slice(0));
                    Mat::from_fn(b.n, 1, |l, _| (xs[l] * zs[l]).sqrt() * z[o + l])
                }
                BlockKind::Psd => {
                    let n = b.n;
                    let zk = &z[o..o + n * n];
                    let mut d = if n <= small::SMALL_PRODUCT {
                        small::with_bufs(n, |[a, t, out]| {
                            load(&f.lx[k], a);
                            small::mul(a, zk, n, t);
                            load(&f.linv_s[k], a);
                            small::mul(t, a, n, out);
                            store(out, n)
                        })
                    } else {
                        let zk = faer::MatRef::from_column_major_slice(zk, n, n);
                        mul(&mul(&f.lx[k], &zk.to_owned()), &f.linv_s[k])
                    };
                    symmetrize(&mut d);
                    d
                }
            }
        })
    }

    /// The stacked `g = vec G` (see the module documentation); `second` is the predictor
    /// `(ΔX_a, ΔS_a)` whose product `H = ΔX_a ΔS_a` enters the corrector.
    fn scaled_rhs(
        &self,
        an: &Analysis,
        x: &[Mat<f64>],
        f: &Factors,
        rd: &[Mat<f64>],
        sigma_mu: f64,
        second: Option<Predictor<'_>>,
    ) -> Vec<f64> {
        let mut out = vec![0.0; self.rows];
        let mut parts = Vec::with_capacity(an.blocks.len());
        let mut rest = out.as_mut_slice();
        for b in &an.blocks {
            let len = match b.kind {
                BlockKind::Lp => b.n,
                BlockKind::Psd => b.n * b.n,
            };
            let (part, tail) = rest.split_at_mut(len);
            parts.push(part);
            rest = tail;
        }
        an.exec.for_each_mut(&mut parts, |k, part| {
            let b = &an.blocks[k];
            let second = second.map(|(dx, ds)| (&dx[k], &ds[k]));
            match b.kind {
                BlockKind::Lp => {
                    let (xs, zs, rs) = (
                        x[k].col_as_slice(0),
                        f.zinv[k].col_as_slice(0),
                        rd[k].col_as_slice(0),
                    );
                    for (l, g) in part.iter_mut().enumerate() {
                        let h = second.map_or(0.0, |(dx, ds)| dx[(l, 0)] * ds[(l, 0)]);
                        // x s = x / zinv; all products kept in scaled form.
                        let xs_prod = xs[l] / zs[l];
                        *g = -xs_prod.sqrt()
                            - (xs[l] * zs[l]).sqrt() * rs[l]
                            - (h - sigma_mu) / xs_prod.sqrt();
                    }
                }
                BlockKind::Psd => scaled_rhs_block(f, k, &rd[k], sigma_mu, second, part),
            }
        });
        out
    }

    /// The HKM direction `(ΔX, Δy)` of the least-squares form; `ΔS` is left to the caller
    /// (`R_d − 𝒜ᵀ(Δy)`).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn direction(
        &self,
        an: &Analysis,
        x: &[Mat<f64>],
        f: &Factors,
        rd: &[Mat<f64>],
        rp: &[f64],
        sigma_mu: f64,
        second: Option<Predictor<'_>>,
    ) -> (BlockMats, Vec<f64>) {
        let m = self.m;
        let mut c = self.scaled_rhs(an, x, f, rd, sigma_mu, second);
        c.resize(self.rows + m, 0.0);
        self.apply_qt(&mut c);
        let mut w = rp.to_vec();
        self.solve_rt(&mut w);
        let mut dy: Vec<f64> = w.iter().zip(&c[..m]).map(|(a, b)| a - b).collect();
        self.solve_r(&mut dy);
        c[..m].copy_from_slice(&w);
        self.apply_q(&mut c);
        (self.unscale(an, x, f, &c), dy)
    }

    /// Minimum-norm correction for a primal residual `e`: `δ = R⁻¹R⁻ᵀ e` and the matching
    /// `ΔX` correction `sym(L_X Q [R⁻ᵀ e; 0] L_S⁻¹)`, which satisfies `𝒜(·) = e`.
    pub(crate) fn correction(
        &self,
        an: &Analysis,
        x: &[Mat<f64>],
        f: &Factors,
        e: &[f64],
    ) -> (Vec<f64>, BlockMats) {
        let mut w = e.to_vec();
        self.solve_rt(&mut w);
        let mut z = vec![0.0; self.rows + self.m];
        z[..self.m].copy_from_slice(&w);
        self.apply_q(&mut z);
        self.solve_r(&mut w);
        (w, self.unscale(an, x, f, &z))
    }
}

/// `vec G` of PSD block `k` into `out` (`n²` entries, column-major), with
/// `G = −L_Xᵀ (L_S + R_d L_S⁻ᵀ) + σμ L_X⁻¹ L_S⁻ᵀ − (L_X⁻¹ ΔX_a)(ΔS_a L_S⁻ᵀ)` (the last term only
/// for the corrector, from the predictor's `(ΔX_a, ΔS_a)` in `second`).
fn scaled_rhs_block(
    f: &Factors,
    k: usize,
    rd: &Mat<f64>,
    sigma_mu: f64,
    second: Option<(&Mat<f64>, &Mat<f64>)>,
    out: &mut [f64],
) {
    let (lx, linv_x, ls, linv_s) = (&f.lx[k], &f.linv_x[k], &f.ls[k], &f.linv_s[k]);
    let n = lx.nrows();
    if n <= small::SMALL_PRODUCT {
        // The products of the general branch below, on stack buffers.
        small::with_bufs(n, |[lst, p, q, g, u, w]| {
            load_transposed(linv_s, lst);
            load(rd, p);
            small::mul(p, lst, n, q);
            for j in 0..n {
                for (qi, li) in q[j * n..(j + 1) * n].iter_mut().zip(ls.col_as_slice(j)) {
                    *qi += li;
                }
            }
            load_transposed(lx, p);
            small::mul(p, q, n, g);
            for gi in g.iter_mut() {
                *gi *= -1.0;
            }
            if sigma_mu != 0.0 {
                load(linv_x, p);
                small::mul(p, lst, n, q);
                for (gi, qi) in g.iter_mut().zip(q.iter()) {
                    *gi += qi * sigma_mu;
                }
            }
            if let Some((dx, ds)) = second {
                load(linv_x, p);
                load(dx, u);
                small::mul(p, u, n, q);
                load(ds, u);
                small::mul(u, lst, n, w);
                small::mul(q, w, n, u);
                for (gi, ui) in g.iter_mut().zip(u.iter()) {
                    *gi -= ui;
                }
            }
            out.copy_from_slice(g);
        });
        return;
    }
    // −L_Xᵀ (L_S + R_d L_S⁻ᵀ)
    let mut inner = mul(rd, &linv_s.transpose().to_owned());
    inner += ls;
    let mut g = mul(&lx.transpose().to_owned(), &inner);
    g *= faer::Scale(-1.0);
    // + σμ L_X⁻¹ L_S⁻ᵀ − (L_X⁻¹ ΔX_a)(ΔS_a L_S⁻ᵀ)
    if sigma_mu != 0.0 {
        let nmat = mul(linv_x, &linv_s.transpose().to_owned());
        g += &(nmat * faer::Scale(sigma_mu));
    }
    if let Some((dx, ds)) = second {
        let left = mul(linv_x, dx);
        let right = mul(ds, &linv_s.transpose().to_owned());
        g -= &mul(&left, &right);
    }
    for j in 0..n {
        out[j * n..(j + 1) * n].copy_from_slice(g.col_as_slice(j));
    }
}

/// One constraint's part in a PSD block of order `n`: its upper-triangle pattern `(rows, cols)`,
/// values `v` and sorted support (the indices its rows and columns touch).
struct ConstraintPattern<'a> {
    n: usize,
    rows: &'a [usize],
    cols: &'a [usize],
    v: &'a [f64],
    support: &'a [usize],
}

/// Adds `K_p = L_Xᵀ A_p L_S⁻ᵀ` to `dst` (`n×n`, column-major). Only the rows `J` of `L_X` and
/// the columns `J` of `L_S⁻¹` take part, `K_p = L_X[J,:]ᵀ A_p[J,J] (L_S⁻¹[:,J])ᵀ`, where `J` is
/// the support, or every index when the support covers most of the block.
fn add_scaled_constraint(
    pattern: ConstraintPattern<'_>,
    lx: &Mat<f64>,
    linv_s: &Mat<f64>,
    dst: &mut [f64],
) {
    let ConstraintPattern {
        n,
        rows,
        cols,
        v,
        support,
    } = pattern;
    // `J`: the support, or every index when the support covers most of the block.
    let dense = support.len() as f64 >= DENSE_SUPPORT * n as f64;
    let nj = if dense { n } else { support.len() };
    let index = |c: usize| if dense { c } else { support[c] };
    let pos = |i: usize| {
        if dense {
            i
        } else {
            support.binary_search(&i).unwrap_or(0)
        }
    };
    // Calls `add(r, c, value)` for every entry of `A_p[J,J]` (both triangles).
    let scatter = |add: &mut dyn FnMut(usize, usize, f64)| {
        for e in 0..v.len() {
            let (r, c) = (pos(rows[e]), pos(cols[e]));
            add(r, c, v[e]);
            if r != c {
                add(c, r, v[e]);
            }
        }
    };
    if n <= small::SMALL_PRODUCT {
        // Stack buffers: `a = A_p[J,J]`, `left = L_X[J,:]ᵀ`, `right = (L_S⁻¹[:,J])ᵀ`.
        small::with_bufs(n, |[a, left, right, t, out]| {
            scatter(&mut |r, c, x| a[r + c * nj] += x);
            for c in 0..nj {
                let jc = index(c);
                for i in 0..n {
                    left[i + c * n] = lx[(jc, i)];
                    right[c + i * nj] = linv_s[(i, jc)];
                }
            }
            if dense {
                small::mul(left, a, n, t);
                small::mul(t, right, n, out);
            } else {
                // faer's kernel, as for larger blocks (same rounding on every block size).
                fn view(b: &[f64], r: usize, c: usize) -> faer::MatRef<'_, f64> {
                    faer::MatRef::from_column_major_slice(&b[..r * c], r, c)
                }
                fn prod(out: &mut [f64], l: faer::MatRef<'_, f64>, r: faer::MatRef<'_, f64>) {
                    let (nr, nc) = (l.nrows(), r.ncols());
                    faer::linalg::matmul::matmul(
                        faer::MatMut::from_column_major_slice_mut(&mut out[..nr * nc], nr, nc),
                        faer::Accum::Replace,
                        l,
                        r,
                        1.0,
                        Par::Seq,
                    )
                }
                prod(t, view(left, n, nj), view(a, nj, nj));
                prod(out, view(t, n, nj), view(right, nj, n));
            }
            for (d, o) in dst.iter_mut().zip(out.iter()) {
                *d += o;
            }
        });
        return;
    }
    let mut a = Mat::<f64>::zeros(nj, nj);
    scatter(&mut |r, c, x| a[(r, c)] += x);
    let left = Mat::from_fn(n, nj, |i, c| lx[(index(c), i)]);
    let right = Mat::from_fn(nj, n, |r, j| linv_s[(j, index(r))]);
    let kp = mul(&mul(&left, &a), &right);
    for j in 0..n {
        for i in 0..n {
            dst[i + j * n] += kp[(i, j)];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A lower-triangular factor with diagonal in `[0.5, 1.5]` (the shape of `L_X`, `L_S⁻¹`).
    fn lower(n: usize, e: &[f64], shift: usize) -> Mat<f64> {
        Mat::from_fn(n, n, |i, j| match i.cmp(&j) {
            std::cmp::Ordering::Greater => e[(shift + i * 16 + j) % e.len()],
            std::cmp::Ordering::Equal => 1.0 + 0.5 * e[(shift + i * 17) % e.len()],
            std::cmp::Ordering::Less => 0.0,
        })
    }

    fn max_diff(a: &[f64], b: &Mat<f64>) -> f64 {
        let n = b.nrows();
        (0..n * n).fold(0.0f64, |m, e| m.max((a[e] - b[(e % n, e / n)]).abs()))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// `K_p = L_Xᵀ A_p L_S⁻ᵀ` against faer's dense products, on block orders on both sides
        /// of the stack-buffer limit and on sparse and dense supports.
        #[test]
        fn scaled_constraint_matches_dense_formula(
            n in 1usize..=12,
            e in proptest::collection::vec(-1.0f64..1.0, 256),
            entries in proptest::collection::vec((0usize..12, 0usize..12, -1.0f64..1.0), 1..20),
        ) {
            let (lx, linv_s) = (lower(n, &e, 0), lower(n, &e, 7));
            let mut rows = Vec::new();
            let mut cols = Vec::new();
            let mut v = Vec::new();
            for &(r, c, x) in &entries {
                let (r, c) = (r % n, c % n);
                rows.push(r.min(c));
                cols.push(r.max(c));
                v.push(x);
            }
            let support = support_of(&rows, &cols);
            let mut dst = vec![0.25; n * n];
            add_scaled_constraint(
                ConstraintPattern { n, rows: &rows, cols: &cols, v: &v, support: &support },
                &lx,
                &linv_s,
                &mut dst,
            );
            let mut a = Mat::<f64>::zeros(n, n);
            for e in 0..v.len() {
                a[(rows[e], cols[e])] += v[e];
                if rows[e] != cols[e] {
                    a[(cols[e], rows[e])] += v[e];
                }
            }
            let mut reference = lx.transpose() * &a * linv_s.transpose();
            for j in 0..n {
                for i in 0..n {
                    reference[(i, j)] += 0.25;
                }
            }
            prop_assert!(max_diff(&dst, &reference) <= 1e-13 * (n * n * v.len()) as f64);
        }

        /// `G = −L_Xᵀ (L_S + R_d L_S⁻ᵀ) + σμ L_X⁻¹ L_S⁻ᵀ − (L_X⁻¹ ΔX_a)(ΔS_a L_S⁻ᵀ)` against
        /// faer's dense products, with and without the corrector term.
        #[test]
        fn scaled_rhs_matches_dense_formula(
            n in 1usize..=12,
            e in proptest::collection::vec(-1.0f64..1.0, 256),
            sigma_mu in 0.0f64..2.0,
            corrector in any::<bool>(),
        ) {
            let m = |shift: usize| Mat::from_fn(n, n, |i, j| e[(shift + 13 * i + 5 * j) % 256]);
            let f = Factors {
                lx: vec![lower(n, &e, 0)],
                linv_x: vec![lower(n, &e, 3)],
                linv_s: vec![lower(n, &e, 7)],
                ls: vec![lower(n, &e, 11)],
                zinv: vec![Mat::zeros(n, n)],
            };
            let (rd, dx, ds) = (m(1), m(2), m(4));
            let second = corrector.then_some((&dx, &ds));
            let mut out = vec![f64::NAN; n * n];
            scaled_rhs_block(&f, 0, &rd, sigma_mu, second, &mut out);
            let (lx, linv_x, ls, linv_s) = (&f.lx[0], &f.linv_x[0], &f.ls[0], &f.linv_s[0]);
            let mut reference = -(lx.transpose() * (ls + &rd * linv_s.transpose()))
                + linv_x * linv_s.transpose() * faer::Scale(sigma_mu);
            if corrector {
                reference -= (linv_x * &dx) * (&ds * linv_s.transpose());
            }
            prop_assert!(max_diff(&out, &reference) <= 1e-13 * (n * n) as f64);
        }
    }
}
