//! Residue (spectral) embedding of `v ↦ e^{Av}` — Ferrante et al. (2016), §4.1, eqs. (42)–(43).
//!
//! **Step 1 (residues).** The resolvent has the partial-fraction expansion (42)
//! `(sI − A)⁻¹ = Σ_i Σ_{j ≤ m_i} R_ij / (s − λ_i)^j`, `m_i` the multiplicity of `λ_i` in the
//! minimal polynomial, and `R_ij = (A − λ_i I)^{j−1} E_i` with `E_i` the spectral projector.
//! Every residue is computed as a **contour moment** around its eigenvalue cluster `c` (centre
//! `λ̄`, radius `r`, `N` trapezoid nodes `s_k = λ̄ + ρ_k`, `ρ_k = r e^{2πik/N}`):
//!
//! ```text
//! R_j = (1/2πi) ∮ (s − λ̄)^{j−1} (sI − A)⁻¹ ds  ≈  (1/N) Σ_k ρ_k^j (s_k I − A)⁻¹,
//! ```
//!
//! which converges geometrically and needs only complex LU solves (no eigenvectors, so
//! defective eigenvalues, computed only to ~`ε^{1/m}`, are fine). The node count is doubled until
//! two successive rules agree.
//!
//! **Clusters.** Eigenvalues closer than a few ulps of `‖A‖` start in one cluster; a cluster
//! whose projector norm `‖E_c‖_F` exceeds [`ResidueOptions::max_projector_norm`] (nearly
//! repeated eigenvalues: huge, cancelling residues `∝ 1/gap`) or that cannot be separated
//! from the rest of the spectrum by a circle is merged with its nearest neighbour (keeping
//! conjugate symmetry), until every cluster is well conditioned. For a truly repeated
//! eigenvalue the moments vanish beyond the nilpotency index (`m_i`, detected numerically:
//! diagonalizable repeated eigenvalues keep a single term). For a cluster of distinct
//! eigenvalues they only decay; terms are kept until a rigorous tail bound (see
//! [`ResidueExpansion::truncate`]) is negligible, and that bound is reported as a remainder.
//!
//! **Balanced coordinates** (issue 22; opt-in, [`ResidueOptions::balanced_clusters`]). The
//! clusters (and their moment counts) are those of the
//! balanced matrix `B = D⁻¹AD` (`sporadic_linalg::balance`, LAPACK `gebal` scaling, `D` a
//! diagonal of powers of 2), whose residues are mapped back exactly, `R_j(A) = D R_j(B) D⁻¹`;
//! when `A` as given has clusters of the same structure its own residues are kept (bitwise
//! those of an unbalanced computation, e.g. for the paper's Example 2). Balancing removes the diagonal scaling
//! of the coordinates, so the projector norms the merging looks at, and with them the clusters
//! and the vertex count, are (up to the factor 2 of the balancing) the same for `A` and every
//! `SAS⁻¹` with a diagonal `S` that balancing undoes (not always for a reducible `A`, e.g. a
//! triangular Jordan block, whose nilpotency test `‖N^j‖_F ≤ tol·‖N‖_F^j` then depends on the
//! scaling): e.g. the four modes of `eight-state-modal` (corpus) keep, in the clusters' box,
//! `2⁸` vertices in the diagonal normal form of `sporadic-ferrante2016` (`D` spanning `2²¹`),
//! where the projector norms up to `3·10⁴` of the unbalanced matrix merged three of them and
//! gave `2¹⁰`. A general similarity `S` changes the norms at most by the factor `κ(S)`; clusters
//! of a defective eigenvalue (projector norms `∝ gap^{1−m}`) stay merged under any
//! well-conditioned one. The spectral projectors themselves carry no similarity-invariant size
//! (every projector is similar to an orthogonal one), so the merge criterion cannot be
//! invariant under every similarity. Of the choice below between the clusters and the whole
//! spectrum, the window condition and the powers the series keeps depend on the eigenvalues,
//! the window and the clusters' indices alone; the clusters' kept moments are exact counts for
//! simple and defective eigenvalues (nilpotency), and come from truncation bounds in the
//! coordinates of `A` only for a merged cluster of distinct eigenvalues.
//!
//! **Short windows** (not in the paper). On a window with `ρ(T2 − T1)/2 ≤ 1`, `ρ` the spread
//! `max|λ_i − λ_j|` of the spectrum, the whole spectrum is taken as one cluster expanded about
//! the centre `c` of the window (the power series `e^{Ac}e^{λ̄s}Σ_k s^k(A − λ̄I)^k/k!`,
//! `s = v − c`, truncated with a rigorous remainder, see [`ResidueExpansion::truncate`])
//! whenever that keeps at most
//! [`SHORT_WINDOW_EXTRA_TERMS`] more box coordinates than the clusters: its box is the tighter
//! one there (see [`ResidueExpansion::truncate`]; [`ResidueOptions::short_window_series`] turns
//! this off). Such a window is then halved while the halves together have no more box
//! corners, and a longer window — or a short one whose own series keeps too many terms — is cut
//! into short pieces when that costs at most the same factor in corners; pieces are then halved
//! all together while their corners stay within that budget, which lowers the remainder at the
//! same powers ([`ResidueExpansion::embed`]). The window condition depends on the eigenvalues and
//! the window alone; it holds for a window of sampling jitter around any nominal period, not
//! only near `v = 0`.
//!
//! **Step 2–4.** Each kept moment contributes real matrices and scalar functions
//! ([`CoefficientFunction`]); their exact ranges over `[T1, T2]` (43b) give a box whose
//! `2^K` corners map to the vertices (43a). Coefficients with a single-valued range contribute
//! one value only, so e.g. the eigenvalue `0` never doubles the vertex count.
//!
//! **Self-check.** `Σ_c E_c = I` and `max_v (‖Σ_k c_k(v) N_k − e^{Av}‖_F − δ)⁺ / ‖e^{Av}‖_F` on a
//! grid (`δ` the truncation remainder) must both be below [`ResidueOptions::check_tolerance`]
//! (default `1e-10`); otherwise the
//! containment is not claimed (see [`crate::Containment`]). On a window of a Hurwitz `A` longer
//! than the decay of every mode the grid ends at `S = T1 + 72/|α|` ([`DECAY_EXPONENTS`]),
//! and beyond it the whole expansion, `Σ_k max_{[S, T2]}|c_k|·‖N_k‖_F` from the exact ranges
//! (43b), must be below the tolerance relative to the window's largest `‖e^{Av}‖_F`.

use sporadic_linalg::InputError;
use std::f64::consts::PI;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par, c64};
use sporadic_linalg::balance::{balance_a, balancing_scales};
use sporadic_linalg::{expm_scaled, expm_stepper};

use crate::EmbedError;
use crate::coefficient::{CoefficientFunction, CoefficientRange};
use crate::corners::box_vertices;
use crate::embedding::{Containment, Embedding, HULL_TOLERANCE, Method};
use crate::interval::Interval;
use sporadic_linalg::input::check_square_finite;

/// Decay exponents `c` of the decay horizon `c/|α|` of a Hurwitz `A` (spectral abscissa
/// `α < 0`): beyond it every mode has decayed by `e^{−72} ≈ 5·10⁻³²`, sixteen orders of
/// magnitude below the unit roundoff for polynomial (Jordan) and non-normal factors. On a
/// longer window the residue embedding's reconstruction is checked on a grid of
/// `[T1, T1 + c/|α|]` and bounded through the coefficient ranges beyond
/// ([`ResidueExpansion::embed`]); methods use the same horizon for their own grids.
pub const DECAY_EXPONENTS: f64 = 72.0;

/// Tuning of the residue embedding. The defaults suit matrices up to `n ≈ 15`.
#[derive(Debug, Clone, PartialEq)]
pub struct ResidueOptions {
    /// Clusters whose spectral projector has a Frobenius norm above this in the balanced
    /// coordinates (see the module docs) are merged with their nearest neighbour (nearly
    /// repeated eigenvalues). Default `1e4`.
    pub max_projector_norm: f64,
    /// Moments kept beyond the algebraic multiplicity of a cluster of *distinct* eigenvalues,
    /// whose moments never vanish exactly. Each kept moment doubles the vertex count of a real
    /// cluster (quadruples for a complex pair). Default `2`.
    pub extra_moments: usize,
    /// A moment `R_j` is treated as exactly zero (nilpotency reached) when
    /// `‖R_j‖_F ≤ tol · ‖R_1‖_F · ‖A − λ̄I‖_F^{j−1}`. Default `1e-11`.
    pub nilpotency_tolerance: f64,
    /// Moments are dropped while the rigorous bound on the dropped tail stays below
    /// `tail_tolerance · max_v ‖e^{Av}‖_F`. Default `1e-13`.
    pub tail_tolerance: f64,
    /// Tolerance of the self-check (`Σ E_c = I`, grid reconstruction). Default `1e-10`.
    pub check_tolerance: f64,
    /// Number of grid points of the reconstruction self-check. Default `201`.
    pub check_points: usize,
    /// Largest admissible number of vertices. Default `2^16`.
    pub max_vertices: usize,
    /// Whether a short window (`ρ(T2 − T1)/2 ≤ 1`, `ρ` the spread of the spectrum) is embedded
    /// with the power series of the whole spectrum about its centre when that keeps at most
    /// [`SHORT_WINDOW_EXTRA_TERMS`] more box coordinates than the clusters (see the module docs). Default
    /// `true`.
    pub short_window_series: bool,
    /// Whether the clusters are taken from the balanced matrix when its cluster structure
    /// differs from that of `A` as given (see the module docs). Default `false`: on a plant
    /// written for a check (a drone axis in milliseconds, order 5, one unstable mode) the
    /// balanced clusters made ferrante2016 certify `T2` only up to 182 ms where the clusters of
    /// its diagonal normal form certify 400 ms; the vertex count is then not independent of a
    /// diagonal change of coordinates (issue 22, open).
    pub balanced_clusters: bool,
}

impl Default for ResidueOptions {
    fn default() -> Self {
        Self {
            max_projector_norm: 1e4,
            extra_moments: 2,
            nilpotency_tolerance: 1e-11,
            tail_tolerance: 1e-13,
            check_tolerance: 1e-10,
            check_points: 201,
            max_vertices: 1 << 16,
            short_window_series: true,
            balanced_clusters: false,
        }
    }
}

impl ResidueOptions {
    fn validate(&self) -> Result<(), EmbedError> {
        let positive = |x: f64, name: &str| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(EmbedError::InvalidArgument(format!(
                    "ResidueOptions::{name} must be positive and finite, got {x}"
                )))
            }
        };
        positive(self.max_projector_norm, "max_projector_norm")?;
        positive(self.nilpotency_tolerance, "nilpotency_tolerance")?;
        positive(self.tail_tolerance, "tail_tolerance")?;
        positive(self.check_tolerance, "check_tolerance")?;
        if self.check_points < 2 {
            return Err(EmbedError::InvalidArgument(
                "ResidueOptions::check_points must be at least 2".into(),
            ));
        }
        if self.max_vertices == 0 {
            return Err(EmbedError::InvalidArgument(
                "ResidueOptions::max_vertices must be at least 1".into(),
            ));
        }
        Ok(())
    }
}

/// How the moments of a cluster were obtained.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contour {
    /// Radius `r` of the circle around the cluster centre.
    pub radius: f64,
    /// Number of trapezoid nodes of the final rule.
    pub nodes: usize,
    /// Largest relative change of a moment between the last two rules (`N/2` vs `N` nodes).
    pub error_estimate: f64,
}

/// A cluster of eigenvalues with its residue matrices (contour moments).
///
/// A cluster is either self-conjugate (real centre, real residues) or the `Im > 0` member of a
/// conjugate pair of clusters (the residues of the partner are the complex conjugates).
#[derive(Debug, Clone)]
pub struct EigenCluster {
    eigenvalues: Vec<c64>,
    centre: c64,
    pair: bool,
    moments: Vec<Mat<c64>>,
    nilpotent: bool,
    contour: Option<Contour>,
}

impl EigenCluster {
    /// The computed eigenvalues of this cluster (for a conjugate pair, the members of the
    /// `Im > 0` cluster).
    pub fn eigenvalues(&self) -> &[c64] {
        &self.eigenvalues
    }

    /// Cluster centre `λ̄` (the mean of its eigenvalues; real for self-conjugate clusters).
    pub fn centre(&self) -> c64 {
        self.centre
    }

    /// Algebraic multiplicity (number of eigenvalues in the cluster).
    pub fn algebraic_multiplicity(&self) -> usize {
        self.eigenvalues.len()
    }

    /// Whether this cluster stands for itself and its complex-conjugate partner.
    pub fn is_conjugate_pair(&self) -> bool {
        self.pair
    }

    /// Whether the moments vanish (numerically) beyond [`Self::moment_count`]: the cluster is a
    /// single repeated eigenvalue whose index in the minimal polynomial is `moment_count()`.
    pub fn is_nilpotent(&self) -> bool {
        self.nilpotent
    }

    /// Number of stored residues `R_1, …` (the index `m_i` when [`Self::is_nilpotent`]).
    pub fn moment_count(&self) -> usize {
        self.moments.len()
    }

    /// Residue `R_j = (A − λ̄I)^{j−1} E` (`j ≥ 1`; `R_1 = E` is the spectral projector).
    /// Returns `None` beyond the stored moments (they are zero when the cluster is nilpotent).
    pub fn residue(&self, j: usize) -> Option<MatRef<'_, c64>> {
        j.checked_sub(1)
            .and_then(|k| self.moments.get(k))
            .map(|m| m.as_ref())
    }

    /// Contour data (`None` when the cluster is the whole spectrum and `E = I`).
    pub fn contour(&self) -> Option<Contour> {
        self.contour
    }

    /// Weight of the cluster in real expansions: 2 for a conjugate pair, 1 otherwise.
    fn weight(&self) -> f64 {
        if self.pair { 2.0 } else { 1.0 }
    }
}

/// One term `c(v) N` of the real expansion `e^{Av} = Σ_k c_k(v) N_k`.
#[derive(Debug, Clone)]
pub struct ExpansionTerm {
    /// The scalar function `c_k`.
    pub function: CoefficientFunction,
    /// The constant real matrix `N_k` (`R_j`, `Re R_j` or `Im R_j`).
    pub matrix: Mat<f64>,
}

/// The terms of the expansion kept on an interval and the bound on what was dropped.
#[derive(Debug, Clone)]
pub struct TruncatedExpansion {
    /// The kept terms.
    pub terms: Vec<ExpansionTerm>,
    /// Rigorous bound on `max_{v ∈ [T1,T2]} ‖e^{Av} − Σ_k c_k(v) N_k‖_F` caused by dropping
    /// moments (exact arithmetic on the computed residues; zero when nothing non-negligible was
    /// dropped).
    pub remainder_bound: f64,
}

/// Residue decomposition of `A`, independent of the sampling window (Remark 9 of Ferrante et
/// al.): build once, then [`ResidueExpansion::embed`] any number of intervals.
#[derive(Debug, Clone)]
pub struct ResidueExpansion {
    a: Mat<f64>,
    clusters: Vec<EigenCluster>,
    /// The whole spectrum as one cluster (`E = I`), when there is more than one cluster.
    whole: Option<EigenCluster>,
    /// `max |λ_i − λ_j|` over the computed eigenvalues.
    spread: f64,
    projector_sum_error: f64,
    options: ResidueOptions,
}

/// Eigenvalues closer than this times `‖A‖_F` start in one cluster. A defective eigenvalue of
/// index `m` is computed as `m` points about `(u‖A‖)^{1/m}` apart (`u` = unit roundoff), `1.5e-8`
/// for `m = 2`; merging at `1e-7` catches those without a contour solve, and a cluster of
/// genuinely distinct eigenvalues this close truncates with an error of order `1e-14 (‖A‖v)²`,
/// well inside the self-check. Wider defective clusters are merged adaptively.
const INITIAL_CLUSTER_DISTANCE: f64 = 1e-7;

/// How many more box coordinates (terms with a range that is not a single value) than the
/// clusters' box the power series of the whole spectrum may have on a short window (each
/// doubles the vertex count; see [`ResidueExpansion::truncate`]).
pub const SHORT_WINDOW_EXTRA_TERMS: usize = 2;

/// Where the variable of a cluster's series ranges (for its tail bound).
#[derive(Debug, Clone, Copy)]
enum Span {
    /// `v ∈ [t1, t2]` (the expansion (42) about `v = 0`).
    Window(f64, f64),
    /// `s ∈ [−h, h]` (a series about the centre of the window).
    Centred(f64),
}

/// How many times [`ResidueExpansion::embed`] may halve a window embedded by the centred power
/// series (at most `2^4 = 16` pieces).
pub const SERIES_SPLIT_DEPTH: usize = 4;

/// The embedding of one piece of a window, as [`ResidueExpansion::embed`] chooses pieces.
struct Piece {
    embedding: Embedding,
    /// Whether it is the centred power series of a short window.
    centred: bool,
    /// Its number of box coordinates ([`free_terms`]): the choices between pieces compare
    /// `2^free`, which depends on the eigenvalues and the kept powers, not on the norms that
    /// decide which small terms are folded into the remainder (those change with the
    /// coordinates).
    free: usize,
    /// The box coordinates the clusters' expansion has on the piece: the corner budget of the
    /// centred series is `2^(clusters_free + SHORT_WINDOW_EXTRA_TERMS)`.
    clusters_free: usize,
}

impl Piece {
    fn guaranteed(&self) -> bool {
        matches!(self.embedding.containment(), Containment::Guaranteed)
    }
}

/// `2^free`, saturating.
fn corners(free: usize) -> usize {
    u32::try_from(free)
        .ok()
        .and_then(|f| 1usize.checked_shl(f))
        .unwrap_or(usize::MAX)
}

/// Minimal union–find over eigenvalue indices.
struct UnionFind(Vec<usize>);

impl UnionFind {
    fn find(&mut self, i: usize) -> usize {
        let mut r = i;
        while self.0[r] != r {
            r = self.0[r];
        }
        let mut k = i;
        while self.0[k] != r {
            let next = self.0[k];
            self.0[k] = r;
            k = next;
        }
        r
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
    fn components(&mut self) -> Vec<Vec<usize>> {
        let n = self.0.len();
        let mut by_root: Vec<Vec<usize>> = vec![Vec::new(); n];
        for i in 0..n {
            let r = self.find(i);
            by_root[r].push(i);
        }
        by_root.into_iter().filter(|c| !c.is_empty()).collect()
    }
}

/// The structure of a decomposition: per cluster (sorted) the number of eigenvalues and of
/// moments, and whether it is nilpotent and a conjugate pair.
fn structure(clusters: &[EigenCluster]) -> Vec<(usize, usize, bool, bool)> {
    let mut s: Vec<_> = clusters
        .iter()
        .map(|c| (c.eigenvalues.len(), c.moments.len(), c.nilpotent, c.pair))
        .collect();
    s.sort_unstable();
    s
}

/// Index of the conjugate of every eigenvalue (a real eigenvalue is its own conjugate).
fn conjugate_pairing(lambdas: &[c64]) -> Vec<usize> {
    let n = lambdas.len();
    let mut conj = vec![usize::MAX; n];
    for i in 0..n {
        if conj[i] != usize::MAX {
            continue;
        }
        if lambdas[i].im == 0.0 {
            conj[i] = i;
            continue;
        }
        let target = lambdas[i].conj();
        let best = (0..n)
            .filter(|&j| j != i && conj[j] == usize::MAX)
            .min_by(|&x, &y| {
                (lambdas[x] - target)
                    .norm()
                    .total_cmp(&(lambdas[y] - target).norm())
            });
        match best {
            Some(j) => {
                conj[i] = j;
                conj[j] = i;
            }
            None => conj[i] = i,
        }
    }
    conj
}

fn complexify(a: MatRef<'_, f64>) -> Mat<c64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| c64::new(a[(i, j)], 0.0))
}

/// Trapezoid sums `Σ_k ρ_k^j (s_k I − A)⁻¹`, `j = 1..count`, over `nodes` nodes at angles
/// `2π(k + shift)/nodes`.
///
/// The resolvents are small dense solves, done with faer's low-level LU (partial pivoting) and
/// `Par::Seq`: the high-level `partial_piv_lu()` dispatches on the global (rayon) parallelism,
/// whose overhead is far larger than an `n ≤ 20` solve (it made the decomposition of a 3×3
/// matrix about 10× slower on the project machine).
fn contour_sums(
    a: &Mat<c64>,
    centre: c64,
    radius: f64,
    nodes: usize,
    shift: f64,
    count: usize,
) -> Result<Vec<Mat<c64>>, EmbedError> {
    let n = a.nrows();
    let mut sums = vec![Mat::<c64>::zeros(n, n); count];
    let req = factor::lu_in_place_scratch::<usize, c64>(n, n, Par::Seq, Default::default())
        .or(solve::solve_in_place_scratch::<usize, c64>(n, n, Par::Seq));
    let mut mem = MemBuffer::new(req);
    let (mut perm, mut perm_inv) = (vec![0usize; n], vec![0usize; n]);
    let mut lu = Mat::<c64>::zeros(n, n);
    let mut resolvent = Mat::<c64>::zeros(n, n);
    for k in 0..nodes {
        let theta = 2.0 * PI * (k as f64 + shift) / nodes as f64;
        let rho = c64::from_polar(radius, theta);
        let s = centre + rho;
        for j in 0..n {
            for i in 0..n {
                lu[(i, j)] = if i == j { s - a[(i, j)] } else { -a[(i, j)] };
                resolvent[(i, j)] = c64::new(if i == j { 1.0 } else { 0.0 }, 0.0);
            }
        }
        let stack = MemStack::new(&mut mem);
        let (_, p) = factor::lu_in_place(
            lu.as_mut(),
            &mut perm,
            &mut perm_inv,
            Par::Seq,
            stack,
            Default::default(),
        );
        solve::solve_in_place(
            lu.as_ref(),
            lu.as_ref(),
            p,
            resolvent.as_mut(),
            Par::Seq,
            stack,
        );
        let mut weight = rho;
        for sum in sums.iter_mut() {
            for j in 0..n {
                for i in 0..n {
                    let r = resolvent[(i, j)];
                    if !(r.re.is_finite() && r.im.is_finite()) {
                        return Err(EmbedError::Numerical(format!(
                            "singular resolvent on the contour at s = {s}"
                        )));
                    }
                    sum[(i, j)] += weight * r;
                }
            }
            weight *= rho;
        }
    }
    Ok(sums)
}

/// Relative agreement of two successive trapezoid rules required of the contour moments.
const CONTOUR_TOLERANCE: f64 = 1e-13;

/// Contour moments whose last two rules differ by more than this are not trusted: the cluster
/// is merged with its nearest neighbour instead.
const CONTOUR_ACCEPTANCE: f64 = 1e-10;

/// Contour moments `R_1..R_count` with node doubling until two rules agree. Gives up early
/// (returning the last estimate, above [`CONTOUR_TOLERANCE`]) when doubling stops paying off,
/// which happens when the circle passes too close to an ill-conditioned eigenvalue.
fn contour_moments(
    a: &Mat<c64>,
    centre: c64,
    radius: f64,
    ratio: f64,
    count: usize,
) -> Result<(Vec<Mat<c64>>, Contour), EmbedError> {
    const MAX_NODES: usize = 2048;
    let mut nodes = ((-39.0 / ratio.ln()).ceil() as usize).clamp(16, MAX_NODES / 2);
    nodes = nodes.div_ceil(4) * 4;
    let mut sums = contour_sums(a, centre, radius, nodes, 0.0, count)?;
    let mut previous = f64::INFINITY;
    loop {
        let extra = contour_sums(a, centre, radius, nodes, 0.5, count)?;
        let coarse: Vec<Mat<c64>> = sums
            .iter()
            .map(|s| Mat::from_fn(s.nrows(), s.ncols(), |i, j| s[(i, j)] / nodes as f64))
            .collect();
        for (s, e) in sums.iter_mut().zip(&extra) {
            for j in 0..s.ncols() {
                for i in 0..s.nrows() {
                    s[(i, j)] += e[(i, j)];
                }
            }
        }
        nodes *= 2;
        let fine: Vec<Mat<c64>> = sums
            .iter()
            .map(|s| Mat::from_fn(s.nrows(), s.ncols(), |i, j| s[(i, j)] / nodes as f64))
            .collect();
        let base = fine[0].norm_l2();
        let mut err: f64 = 0.0;
        for (j, (c, f)) in coarse.iter().zip(&fine).enumerate() {
            let diff = f - c;
            let scale = f.norm_l2() + base * radius.powi(j as i32);
            if scale > 0.0 {
                err = err.max(diff.norm_l2() / scale);
            }
        }
        if !err.is_finite() {
            err = f64::INFINITY;
        }
        let stalled = err > 0.1 * previous;
        if err <= CONTOUR_TOLERANCE || nodes >= MAX_NODES || stalled {
            return Ok((
                fine,
                Contour {
                    radius,
                    nodes,
                    error_estimate: err,
                },
            ));
        }
        previous = err;
    }
}

/// Truncates a moment sequence at numerical nilpotency; returns whether it was reached.
fn trim_nilpotent(moments: &mut Vec<Mat<c64>>, a: MatRef<'_, f64>, centre: c64, tol: f64) -> bool {
    let n = a.nrows();
    let shifted = Mat::from_fn(n, n, |i, j| {
        let d = if i == j { centre } else { c64::new(0.0, 0.0) };
        c64::new(a[(i, j)], 0.0) - d
    });
    let sigma = shifted.norm_l2();
    let base = moments[0].norm_l2();
    for j in 1..moments.len() {
        let size = moments[j].norm_l2();
        if sigma == 0.0 || size <= tol * base * sigma.powi(j as i32) {
            moments.truncate(j);
            return true;
        }
    }
    false
}

impl ResidueExpansion {
    /// Residue decomposition of `a` with default options.
    pub fn new(a: MatRef<'_, f64>) -> Result<Self, EmbedError> {
        Self::with_options(a, ResidueOptions::default())
    }

    /// Residue decomposition of `a` (square, non-empty, finite).
    pub fn with_options(a: MatRef<'_, f64>, options: ResidueOptions) -> Result<Self, EmbedError> {
        let n = check_square_finite(a, "A")?;
        options.validate()?;
        // The clusters are those of the balanced matrix `B = D⁻¹AD`, whose residues are mapped
        // back exactly (see the module docs); when `A` as given has clusters of the same
        // structure, its own residues are kept (they are as accurate, and bitwise those of an
        // unbalanced computation).
        let (mut d, mut balanced) = (vec![1.0; n], None);
        let (mut clusters, mut lambdas) = Self::decompose(a, &options)?;
        let scales = if options.balanced_clusters {
            balancing_scales(a)
        } else {
            vec![1.0; n]
        };
        if scales.iter().any(|&x| x != 1.0) {
            let b = balance_a(a, &scales);
            let (bc, bl) = Self::decompose(b.as_ref(), &options)?;
            if structure(&bc) != structure(&clusters) {
                (clusters, lambdas, d, balanced) = (bc, bl, scales, Some(b));
            }
        }
        let b = balanced.as_ref().map_or(a, |b| b.as_ref());
        let mut whole =
            (clusters.len() > 1).then(|| Self::whole_spectrum(b, &lambdas, &options, false));
        for c in clusters.iter_mut().chain(whole.iter_mut()) {
            for m in c.moments.iter_mut() {
                *m = Mat::from_fn(n, n, |i, j| m[(i, j)] * (d[i] / d[j]));
            }
        }
        let spread = lambdas
            .iter()
            .flat_map(|x| lambdas.iter().map(move |y| (x - y).norm()))
            .fold(0.0, f64::max);
        let mut sum = Mat::<f64>::zeros(n, n);
        for c in &clusters {
            let w = c.weight();
            for j in 0..n {
                for i in 0..n {
                    sum[(i, j)] += w * c.moments[0][(i, j)].re;
                }
            }
        }
        let projector_sum_error = (&sum - Mat::<f64>::identity(n, n)).norm_l2() / (n as f64).sqrt();
        Ok(Self {
            a: a.to_owned(),
            clusters,
            whole,
            spread,
            projector_sum_error,
            options,
        })
    }

    /// The clusters and the eigenvalues of `a`.
    fn decompose(
        a: MatRef<'_, f64>,
        options: &ResidueOptions,
    ) -> Result<(Vec<EigenCluster>, Vec<c64>), EmbedError> {
        let n = a.nrows();
        let sigma = a.norm_l2();
        let lambdas: Vec<c64> = if sigma == 0.0 {
            vec![c64::new(0.0, 0.0); n]
        } else {
            a.eigenvalues()
                .map_err(|e| EmbedError::Numerical(format!("eigenvalues of A: {e:?}")))?
        };
        if lambdas
            .iter()
            .any(|l| !(l.re.is_finite() && l.im.is_finite()))
        {
            return Err(InputError::non_finite("eigenvalues of A").into());
        }
        let conj = conjugate_pairing(&lambdas);
        let mut uf = UnionFind((0..n).collect());
        let merge = |uf: &mut UnionFind, i: usize, j: usize| {
            uf.union(i, j);
            uf.union(conj[i], conj[j]);
        };
        let delta0 = INITIAL_CLUSTER_DISTANCE * sigma;
        for i in 0..n {
            for j in i + 1..n {
                if (lambdas[i] - lambdas[j]).norm() <= delta0 {
                    merge(&mut uf, i, j);
                }
            }
        }
        let a_c = complexify(a);
        // Cache of computed clusters keyed by their member list (clusters unaffected by a merge
        // are not recomputed).
        let mut cache: Vec<(Vec<usize>, EigenCluster)> = Vec::new();
        let clusters = 'outer: loop {
            let comps = uf.components();
            if comps.len() == 1 {
                break vec![Self::whole_spectrum(a, &lambdas, options, true)];
            }
            let mut clusters = Vec::new();
            for comp in &comps {
                let self_conj = comp.contains(&conj[comp[0]]);
                let mean = comp.iter().map(|&i| lambdas[i]).sum::<c64>() / comp.len() as f64;
                if !self_conj && mean.im < 0.0 {
                    continue;
                }
                let mut centre = if self_conj {
                    c64::new(mean.re, 0.0)
                } else {
                    mean
                };
                if centre.re.abs() <= 16.0 * f64::EPSILON * sigma {
                    centre.re = 0.0;
                }
                let spread = comp
                    .iter()
                    .map(|&i| (lambdas[i] - centre).norm())
                    .fold(0.0, f64::max);
                let (dist, nearest) = (0..n)
                    .filter(|i| !comp.contains(i))
                    .map(|i| ((lambdas[i] - centre).norm(), i))
                    .min_by(|x, y| x.0.total_cmp(&y.0))
                    .expect("more than one component");
                if spread >= 0.8 * dist {
                    merge(&mut uf, comp[0], nearest);
                    continue 'outer;
                }
                let cluster = if let Some((_, c)) = cache.iter().find(|(m, _)| m == comp) {
                    c.clone()
                } else {
                    let c = Self::contour_cluster(
                        a, &a_c, comp, &lambdas, centre, !self_conj, spread, dist, options,
                    )?;
                    cache.push((comp.clone(), c.clone()));
                    c
                };
                let converged = cluster
                    .contour
                    .is_none_or(|c| c.error_estimate <= CONTOUR_ACCEPTANCE);
                if !converged || cluster.moments[0].norm_l2() > options.max_projector_norm {
                    // Nearly repeated (or numerically defective) eigenvalues: merge with the
                    // closest other eigenvalue.
                    let (_, i, j) = comp
                        .iter()
                        .flat_map(|&i| (0..n).filter(|j| !comp.contains(j)).map(move |j| (i, j)))
                        .map(|(i, j)| ((lambdas[i] - lambdas[j]).norm(), i, j))
                        .min_by(|x, y| x.0.total_cmp(&y.0))
                        .expect("more than one component");
                    merge(&mut uf, i, j);
                    continue 'outer;
                }
                clusters.push(cluster);
            }
            break clusters;
        };
        Ok((clusters, lambdas))
    }

    /// The cluster containing the whole spectrum: `E = I`, `R_j = (A − λ̄I)^{j−1}`, truncated at
    /// numerical nilpotency when it is the `only` cluster. With more than one, `A − λ̄I` has a
    /// nonzero eigenvalue and is never nilpotent (the relative test of `trim_nilpotent`,
    /// `‖N^j‖_F ≤ tol·‖N‖_F^j`, passes spuriously in coordinates where `‖N‖_F` is far above the
    /// spectral radius, e.g. 9 states with three modes and a Jordan block under a diagonal
    /// scaling by 0.1–10, and would drop the series' tail without a remainder).
    fn whole_spectrum(
        a: MatRef<'_, f64>,
        lambdas: &[c64],
        options: &ResidueOptions,
        only: bool,
    ) -> EigenCluster {
        let (mut moments, centre) = Self::shifted_powers(a, a.nrows() + options.extra_moments + 1);
        let nilpotent =
            only && trim_nilpotent(&mut moments, a, centre, options.nilpotency_tolerance);
        EigenCluster {
            eigenvalues: lambdas.to_vec(),
            centre,
            pair: false,
            moments,
            nilpotent,
            contour: None,
        }
    }

    /// The powers `(A − λ̄I)^k`, `k < count`, and the centre `λ̄ = tr(A)/n` (`0` when it is
    /// within rounding of `0`).
    fn shifted_powers(a: MatRef<'_, f64>, count: usize) -> (Vec<Mat<c64>>, c64) {
        let n = a.nrows();
        let trace: f64 = (0..n).map(|i| a[(i, i)]).sum();
        let mut lambda = trace / n as f64;
        if lambda.abs() <= 16.0 * f64::EPSILON * a.norm_l2() {
            lambda = 0.0;
        }
        let shifted = Mat::from_fn(n, n, |i, j| a[(i, j)] - if i == j { lambda } else { 0.0 });
        let mut moments = Vec::with_capacity(count);
        let mut power = Mat::<f64>::identity(n, n);
        for _ in 0..count {
            moments.push(complexify(power.as_ref()));
            power = &shifted * &power;
        }
        (moments, c64::new(lambda, 0.0))
    }

    /// Contour moments of one cluster (`comp` = indices into `lambdas`).
    fn contour_cluster(
        a: MatRef<'_, f64>,
        a_c: &Mat<c64>,
        comp: &[usize],
        lambdas: &[c64],
        centre: c64,
        pair: bool,
        spread: f64,
        dist: f64,
        options: &ResidueOptions,
    ) -> Result<EigenCluster, EmbedError> {
        // Far from both the cluster and the rest of the spectrum: rounding in the resolvent of
        // a defective cluster grows like r^{1−m}, the trapezoid error like max(s/r, r/d)^N.
        let radius = (spread * dist).sqrt().max(0.5 * dist);
        let ratio = (spread / radius).max(radius / dist);
        let count = comp.len() + options.extra_moments + 1;
        let (mut moments, contour) = contour_moments(a_c, centre, radius, ratio, count)?;
        if !pair {
            // Self-conjugate cluster: the moments are real up to rounding.
            for m in moments.iter_mut() {
                for j in 0..m.ncols() {
                    for i in 0..m.nrows() {
                        m[(i, j)].im = 0.0;
                    }
                }
            }
        }
        let nilpotent = trim_nilpotent(&mut moments, a, centre, options.nilpotency_tolerance);
        Ok(EigenCluster {
            eigenvalues: comp.iter().map(|&i| lambdas[i]).collect(),
            centre,
            pair,
            moments,
            nilpotent,
            contour: Some(contour),
        })
    }

    /// The system matrix `A`.
    pub fn matrix(&self) -> MatRef<'_, f64> {
        self.a.as_ref()
    }

    /// The eigenvalue clusters with their residues.
    pub fn clusters(&self) -> &[EigenCluster] {
        &self.clusters
    }

    /// `‖Σ_c E_c − I‖_F / √n` (self-check of the projectors).
    pub fn projector_sum_error(&self) -> f64 {
        self.projector_sum_error
    }

    /// The options in use.
    pub fn options(&self) -> &ResidueOptions {
        &self.options
    }

    /// All terms of the expansion for every stored moment, before any truncation.
    pub fn all_terms(&self) -> Vec<ExpansionTerm> {
        let mut terms = Vec::new();
        for c in &self.clusters {
            self.push_terms(c, c.moments.len(), &mut terms);
        }
        terms
    }

    fn push_terms(&self, c: &EigenCluster, keep: usize, out: &mut Vec<ExpansionTerm>) {
        let n = self.a.nrows();
        for (k, m) in c.moments.iter().take(keep).enumerate() {
            let power = k as u32;
            let re = Mat::from_fn(n, n, |i, j| m[(i, j)].re);
            if c.pair {
                let im = Mat::from_fn(n, n, |i, j| m[(i, j)].im);
                out.push(ExpansionTerm {
                    function: CoefficientFunction::Cosine {
                        re: c.centre.re,
                        im: c.centre.im,
                        power,
                    },
                    matrix: re,
                });
                out.push(ExpansionTerm {
                    function: CoefficientFunction::Sine {
                        re: c.centre.re,
                        im: c.centre.im,
                        power,
                    },
                    matrix: im,
                });
            } else {
                out.push(ExpansionTerm {
                    function: CoefficientFunction::Real {
                        lambda: c.centre.re,
                        power,
                    },
                    matrix: re,
                });
            }
        }
    }

    /// Rigorous bound on `max_v ‖Σ_{j ≥ keep} N^j s^j/j!‖_F · |e^{λ̄s}| · weight` for a cluster,
    /// with `N = (A − λ̄I)E` (so `N^j = R_{j+1}`) and `s` ranging over `span`: the stored
    /// moments are used exactly, and beyond them `‖N^{j}‖ ≤ ‖R_L‖ ‖N‖^{j−L+1}` gives the factor
    /// `e^{‖N‖|s|}`.
    fn tail_bound(c: &EigenCluster, keep: usize, span: Span) -> Result<f64, EmbedError> {
        let l = c.moments.len();
        let a = c.centre.re;
        // max over the span of `e^{λs}·growth^{|s|}`-type envelopes `e^{(±a + g)|s|}|s|^k/k!`.
        let max_of = |g: f64, k: usize| -> Result<f64, EmbedError> {
            let power = k as u32;
            Ok(match span {
                Span::Window(t1, t2) => {
                    CoefficientFunction::Real {
                        lambda: a + g,
                        power,
                    }
                    .range(t1, t2)?
                    .upper
                }
                Span::Centred(h) => {
                    let side = |lambda: f64| {
                        CoefficientFunction::Real { lambda, power }
                            .range(0.0, h)
                            .map(|r| r.upper)
                    };
                    side(a + g)?.max(side(g - a)?)
                }
            })
        };
        let mut total = 0.0;
        // Moments known exactly: all stored ones for a nilpotent cluster, all but the last
        // (which seeds the geometric extrapolation) otherwise.
        let exact_end = if c.nilpotent { l } else { l - 1 };
        for k in keep..exact_end {
            total += c.moments[k].norm_l2() * max_of(0.0, k)?;
        }
        if !c.nilpotent {
            let norm_n = c.moments[1].norm_l2();
            let from = keep.max(l - 1);
            let last = c.moments[l - 1].norm_l2() * norm_n.powi((from - (l - 1)) as i32);
            total += last * max_of(norm_n, from)?;
        }
        Ok(c.weight() * total)
    }

    /// The terms kept on `[t1, t2]`: per cluster the fewest moments whose dropped tail is below
    /// `tail_tolerance · scale`, with the rigorous bound on everything dropped.
    fn truncate_clusters(
        &self,
        clusters: &[EigenCluster],
        t1: f64,
        t2: f64,
        scale: f64,
    ) -> Result<TruncatedExpansion, EmbedError> {
        let mut terms = Vec::new();
        let mut remainder = 0.0;
        for c in clusters {
            let (keep, tail) = self.keep(c, Span::Window(t1, t2), 1.0, scale)?;
            remainder += tail;
            self.push_terms(c, keep, &mut terms);
        }
        Ok(TruncatedExpansion {
            terms,
            remainder_bound: remainder,
        })
    }

    /// [`ResidueExpansion::tail_bound`], its overflow (`e^{(λ̄+‖N‖)v}` far from `v = 0` when the
    /// projector norms are large) reported as a numerical limit of the expansion, not bad input.
    fn bounded_tail(c: &EigenCluster, keep: usize, span: Span) -> Result<f64, EmbedError> {
        Self::tail_bound(c, keep, span).map_err(|e| match e {
            EmbedError::Input(InputError::NonFinite { what }) => EmbedError::Numerical(format!(
                "the tail bound of the residue expansion overflows: {what}"
            )),
            e => e,
        })
    }

    /// The powers `K` the centred series keeps on a piece of half-length `h` (see
    /// [`ResidueExpansion::truncate`]): the fewest with `x^K/K!·e^{2x} ≤ tail_tolerance`,
    /// `x = h·max_i|λ_i − λ̄|`, plus `d − 1` for the largest index `d` of a cluster (the
    /// nilpotency index of a defective eigenvalue, the size of a merged one), at most the
    /// stored moments.
    fn series_order(&self, whole: &EigenCluster, h: f64) -> usize {
        let x = h * whole
            .eigenvalues
            .iter()
            .map(|l| (*l - whole.centre).norm())
            .fold(0.0, f64::max);
        let index = self
            .clusters
            .iter()
            .map(|c| {
                if c.nilpotent {
                    c.moments.len()
                } else {
                    c.eigenvalues.len()
                }
            })
            .max()
            .unwrap_or(1);
        // `x^K/K!` by its recurrence.
        let (mut order, mut term) = (0usize, 1.0f64);
        let growth = (2.0 * x).exp();
        while term * growth > self.options.tail_tolerance && order < whole.moments.len() {
            order += 1;
            term *= x / order as f64;
        }
        (order + index - 1).clamp(1, whole.moments.len())
    }

    /// The fewest moments of `c` whose dropped tail over `span`, times `factor`, is below
    /// `tail_tolerance · scale` (all stored moments if none is), and that tail.
    fn keep(
        &self,
        c: &EigenCluster,
        span: Span,
        factor: f64,
        scale: f64,
    ) -> Result<(usize, f64), EmbedError> {
        let bound = |k: usize| Self::bounded_tail(c, k, span);
        let l = c.moments.len();
        for k in 1..=l {
            let t = factor * bound(k)?;
            if t <= self.options.tail_tolerance * scale {
                return Ok((k, t));
            }
        }
        Ok((l, factor * bound(l)?))
    }

    /// The power series of the whole spectrum about the centre `c` of `[t1, t2]`:
    /// `e^{Av} = e^{Ac} e^{λ̄s} Σ_k s^k (A − λ̄I)^k/k!`, `s = v − c ∈ [−h, h]`, terms
    /// `(e^{Ac}(A − λ̄I)^k, b_c)` ([`CoefficientFunction::Centred`]), the powers kept by
    /// [`ResidueExpansion::series_order`], the remainder a cluster's tail bound over `|s| ≤ h`
    /// times `‖e^{Ac}‖_F` (`‖e^{Ac}X‖_F ≤ ‖e^{Ac}‖_F‖X‖_F`;
    /// `e^{Ac}` is the computed exponential, whose error the self-check of
    /// [`ResidueExpansion::embed`] measures with that of the residues).
    fn centred_series(
        &self,
        whole: &EigenCluster,
        t1: f64,
        t2: f64,
    ) -> Result<TruncatedExpansion, EmbedError> {
        let centre = t1 + 0.5 * (t2 - t1);
        let h = (centre - t1).max(t2 - centre);
        let shift = expm_scaled(self.a.as_ref(), centre)?;
        let factor = shift.norm_l2();
        if !factor.is_finite() {
            return Err(InputError::non_finite("e^{Ac} at the centre of the window").into());
        }
        let keep = self.series_order(whole, h);
        let tail = factor * Self::bounded_tail(whole, keep, Span::Centred(h))?;
        let n = self.a.nrows();
        let terms = whole
            .moments
            .iter()
            .take(keep)
            .enumerate()
            .map(|(k, m)| ExpansionTerm {
                function: CoefficientFunction::Centred {
                    lambda: whole.centre.re,
                    power: k as u32,
                    centre,
                },
                matrix: &shift * Mat::from_fn(n, n, |i, j| m[(i, j)].re),
            })
            .collect();
        Ok(TruncatedExpansion {
            terms,
            remainder_bound: tail,
        })
    }

    /// The terms kept on `[t1, t2]` (see [`ResidueExpansion::truncate`]) and the projector-sum
    /// error of the clusters they come from: those of [`ResidueExpansion::clusters`], or the
    /// whole spectrum as one cluster about the centre of the window (`E = I`, no projector
    /// error) on a *short* window, where `ρ(T2 − T1)/2 ≤ 1` for the spread
    /// `ρ = max|λ_i − λ_j|` of the spectrum, when that keeps at most
    /// [`SHORT_WINDOW_EXTRA_TERMS`] more box coordinates.
    fn window_terms(
        &self,
        t1: f64,
        t2: f64,
        scale: f64,
        series: bool,
    ) -> Result<(TruncatedExpansion, f64, usize), EmbedError> {
        let fine = self.truncate_clusters(&self.clusters, t1, t2, scale)?;
        let clusters_free = free_terms(&fine);
        if let Some(whole) = &self.whole
            && series
            && self.options.short_window_series
            && self.spread * 0.5 * (t2 - t1) <= 1.0
        {
            // Its tail bound `‖e^{Ac}‖_F e^{(|λ̄|+‖N‖_F)h}` may overflow in badly scaled
            // coordinates: then the clusters are used.
            if let Ok(merged) = self.centred_series(whole, t1, t2)
                && free_terms(&merged) <= clusters_free + SHORT_WINDOW_EXTRA_TERMS
            {
                return Ok((merged, 0.0, clusters_free));
            }
        }
        Ok((fine, self.projector_sum_error, clusters_free))
    }

    /// The expansion terms kept on `[t1, t2]` and the rigorous bound on the dropped moments
    /// (scale of the tail tolerance: `max(‖e^{AT1}‖_F, ‖e^{AT2}‖_F)`): per cluster of
    /// [`ResidueExpansion::clusters`] the fewest moments whose dropped tail is below
    /// `tail_tolerance · scale`, or, on a short window, the powers of the whole spectrum as one
    /// cluster chosen as below (see the module docs).
    ///
    /// Why (not in the paper): the box (43) lets the coefficient functions of the clusters vary
    /// independently, so besides `e^{Av}` it contains matrices whose clusters are at different
    /// times of the window, `e^{λ_i v_i}` with `v_i ≠ v_j`; their distance from the curve grows
    /// like `ρ(T2 − T1)`. The power series `e^{Ac} e^{λ̄s} Σ_k s^k (A − λ̄I)^k/k!` of the whole
    /// spectrum about the centre `c` of the window (`s = v − c ∈ [−h, h]`, `h = (T2 − T1)/2`)
    /// keeps the first-order term, `s(A − λ̄I)`, at one time; its first independent term,
    /// `s²(A − λ̄I)²/2`, ranges over `ρ²h²/2` (in the scale of the spectrum), which is at most
    /// `ρ(T2 − T1)/4` when `ρh ≤ 1`. Both quantities are similarity-invariant and do not change
    /// under a change of time unit (`A → kA`, `T → T/k`), and so is the number of powers kept:
    /// with `N = A − λ̄I` and `x = h·max_i|λ_i − λ̄|`, the dropped tail relative to `e^{Av}` is
    /// at most `(x^K/K!)e^x·e^x` in coordinates in which `A` is normal
    /// (`Σ_{k≥K} x^k/k! ≤ x^K/K!·e^x` and `‖e^{−Ns}‖₂ ≤ e^x`), so the series keeps the fewest
    /// `K` for which that is below the tail tolerance, plus `d − 1` powers for the largest index
    /// `d` of a cluster (a Jordan block of order `d` makes `‖N^k‖` grow like `k^{d−1}` times
    /// `x^k`; the nilpotent `N` of a single eigenvalue keeps all its `d` powers). The remainder
    /// is then bounded rigorously in the coordinates of `A`, as for any truncation, and may be
    /// larger than the tolerance there. (The powers were first chosen by that bound itself: a
    /// four-story building of order 8 on `[0.005, 0.08]` kept six powers on each of 16 pieces
    /// as given, seven in other coordinates, where the pieces then exceeded the corner budget
    /// and the clusters' box was taken; LMI (41) of `sporadic-ferrante2016` certified the
    /// window as given only.) E.g. four lightly damped modes at
    /// 1–5 rad/s (`ρ = 10`) on `[0.01, 0.122]`: the clusters' box is infeasible for LMI (41);
    /// the series about `v = 0` certifies with 512 vertices, the series about the centre with
    /// 256 (4 pieces), and windows up to `T2 = 0.186`.
    pub fn truncate(&self, t1: f64, t2: f64) -> Result<TruncatedExpansion, EmbedError> {
        let iv = Interval::new(t1, t2)?;
        let scale = expm_scaled(self.a.as_ref(), iv.t1())?
            .norm_l2()
            .max(expm_scaled(self.a.as_ref(), iv.t2())?.norm_l2());
        Ok(self.window_terms(iv.t1(), iv.t2(), scale, true)?.0)
    }

    /// The end `S` of the self-check grid on `iv`: `T1 + DECAY_EXPONENTS/|α|` when `A` is
    /// Hurwitz (spectral abscissa `α < 0`) and this lies inside the window, `T2` otherwise.
    /// Beyond `S` every mode has decayed by `e^{−72}` (relative to `T1`), so an equally spaced
    /// grid of the whole window would only sample where `e^{Av}` is negligible, and on a
    /// window like `[0.1, 10³⁰⁰]` its step `e^{Ah}` overflows in the squarings of the
    /// exponential (an oscillating mode's rounding errors grow like `2^k u`); the decayed
    /// tail `[S, T2]` is checked through the exact coefficient ranges instead (see
    /// [`ResidueExpansion::embed`]). `S` is similarity-invariant and scales as `1/k` under
    /// `A → kA`, like the window.
    fn check_end(&self, iv: &Interval) -> f64 {
        let alpha = self
            .clusters
            .iter()
            .flat_map(|c| c.eigenvalues.iter())
            .map(|l| l.re)
            .fold(f64::NEG_INFINITY, f64::max);
        let s = iv.t1() + DECAY_EXPONENTS / -alpha;
        if alpha < 0.0 && s.is_finite() && s < iv.t2() {
            s
        } else {
            iv.t2()
        }
    }

    /// Polytopic embedding of `{e^{Av} : v ∈ [t1, t2]}` (Ferrante et al. 2016, §4.1,
    /// (43a)–(43b)). `t1 = t2` gives the single vertex `e^{A t1}` (computed by `expm`).
    ///
    /// A window embedded by the power series about its centre (a short window, see the module
    /// docs) is halved, recursively up to [`SERIES_SPLIT_DEPTH`] times, while the halves'
    /// boxes together have no more corners than its own (not in the paper): on a half,
    /// `|v − c|` is halved, so the series needs fewer terms and every coefficient's range
    /// shrinks; the union of the halves' vertices still contains the curve (as for
    /// [`crate::embed_split`]). A window that is not short, or a short one whose own series was
    /// not chosen, is cut into the fewest `2^d` short
    /// pieces (`d ≤` [`SERIES_SPLIT_DEPTH`]) when their boxes have at most
    /// `2^`[`SHORT_WINDOW_EXTRA_TERMS`] times the corners of the clusters' box, the budget of
    /// the choice on a short window. The pieces of the series are then halved all together
    /// while they stay within that budget (`ResidueExpansion::fill_budget`). Corners are counted
    /// as `2^free`, `free` the terms whose
    /// coefficient function is not constant, which depends on the eigenvalues and the kept
    /// powers and not on the norms of the terms (the vertex count after small terms are folded
    /// into the remainder does, and made the certified window depend on the coordinates).
    pub fn embed(&self, t1: f64, t2: f64) -> Result<Embedding, EmbedError> {
        let iv = Interval::new(t1, t2)?;
        let whole = self.embed_piece(iv)?;
        let clusters_free = whole.clusters_free;
        let mut parts = Vec::new();
        if let Some(short) = self.short_pieces(iv, &whole)? {
            parts = short;
        } else {
            self.split_series(iv, whole, SERIES_SPLIT_DEPTH, &mut parts)?;
        }
        let parts = self.fill_budget(iv, clusters_free, parts)?;
        let mut parts: Vec<Embedding> = parts.into_iter().map(|p| p.embedding).collect();
        Ok(if parts.len() == 1 {
            parts.pop().expect("one piece")
        } else {
            Embedding::union(iv, parts)
        })
    }

    /// A window embedded by the clusters' box `whole` (not short, or short with its own series
    /// not chosen), cut into the fewest `2^d ≤ 2^SERIES_SPLIT_DEPTH` equal pieces that are short
    /// and, each embedded as [`ResidueExpansion::embed`] embeds a short window, have boxes with
    /// at most `2^SHORT_WINDOW_EXTRA_TERMS` times the corners of `whole` and no weaker
    /// containment; `None` when no `d` does.
    ///
    /// Both the short window whose own series misses the budget and every `d` beyond the
    /// fewest short pieces are tried because a piece's series has fewer free terms the shorter
    /// the piece: on a fuzzed plant of order 6 (diagonal normal form), the series of
    /// `[T1, 0.048]` had 8 free terms, within the budget, and was halved into 8 pieces of 5 (256
    /// vertices), certified by LMI (41); that of `[T1, 0.0486]` had one more, so the window kept
    /// the clusters' box (64 vertices) and was not certified, although its halves were within
    /// the budget — a certified window with sub-windows that were not.
    fn short_pieces(&self, iv: Interval, whole: &Piece) -> Result<Option<Vec<Piece>>, EmbedError> {
        let ratio = self.spread * 0.5 * iv.length();
        // A short window whose own series was chosen is halved by `split_series` instead.
        if self.whole.is_none() || !self.options.short_window_series || whole.centred {
            return Ok(None);
        }
        let Some(fewest) = (1..=SERIES_SPLIT_DEPTH).find(|&d| ratio <= (1u32 << d) as f64) else {
            return Ok(None);
        };
        let budget = corners(whole.clusters_free.saturating_add(SHORT_WINDOW_EXTRA_TERMS));
        'depth: for depth in fewest..=SERIES_SPLIT_DEPTH {
            let mut parts = Vec::new();
            for piece in iv.split(1 << depth)? {
                let p = self.embed_piece(piece)?;
                if !p.centred {
                    continue 'depth;
                }
                self.split_series(piece, p, SERIES_SPLIT_DEPTH - depth, &mut parts)?;
                let total = parts
                    .iter()
                    .fold(0usize, |t, p| t.saturating_add(corners(p.free)));
                if total > budget || (whole.guaranteed() && !parts.iter().all(Piece::guaranteed)) {
                    continue 'depth;
                }
            }
            return Ok(Some(parts));
        }
        Ok(None)
    }

    /// The pieces `parts` of `iv` (embedded by the centred series) halved all together, up to
    /// [`SERIES_SPLIT_DEPTH`] halvings of `iv`, while their corners stay within the budget of
    /// the window, `2^`[`SHORT_WINDOW_EXTRA_TERMS`] times the corners of the clusters' box on
    /// `iv` (`2^clusters_free`), and no half has a weaker containment than its piece; `parts`
    /// unchanged when they are not all centred series.
    ///
    /// The pieces' powers are set by the eigenvalues ([`ResidueExpansion::truncate`]), and their
    /// rigorous remainder, bounded in the coordinates of `A`, can be far above the tail tolerance
    /// in coordinates where `A` is far from normal. Halving a piece divides `x^K/K!` by `2^K`
    /// with the same `K`, so the budget is spent on a smaller remainder: on `eight-state-modal`
    /// (corpus) in random coordinates `x = Tz` on `[0.01, 0.282]`, 8 pieces of 2⁶ corners had
    /// remainders up to `5.8·10⁻⁶` in the Gramian normal form of `sporadic-ferrante2016` and no
    /// form certified the window by its own solve (66 s); on 16 pieces LMI (41) in those
    /// coordinates certified it in 11 s. Every choice depends on the free terms, not on norms,
    /// so it is the same in every coordinate system.
    fn fill_budget(
        &self,
        iv: Interval,
        clusters_free: usize,
        mut parts: Vec<Piece>,
    ) -> Result<Vec<Piece>, EmbedError> {
        if self.whole.is_none() || !parts.iter().all(|p| p.centred) {
            return Ok(parts);
        }
        let budget = corners(clusters_free.saturating_add(SHORT_WINDOW_EXTRA_TERMS));
        let shortest = iv.length() / f64::from(1u32 << SERIES_SPLIT_DEPTH);
        loop {
            let mut halved = Vec::with_capacity(2 * parts.len());
            for p in &parts {
                let piece = p.embedding.interval();
                if piece.length() < 1.5 * shortest {
                    return Ok(parts);
                }
                for half in piece.split(2)? {
                    let q = self.embed_piece(half)?;
                    if !q.centred || (p.guaranteed() && !q.guaranteed()) {
                        return Ok(parts);
                    }
                    halved.push(q);
                }
            }
            let total = halved
                .iter()
                .fold(0usize, |t, p| t.saturating_add(corners(p.free)));
            if total > budget {
                return Ok(parts);
            }
            parts = halved;
        }
    }

    /// Pushes the embedding `p` of `iv`, or, when it is the centred series of a short window
    /// and halving pays (see [`ResidueExpansion::embed`]), those of its halves.
    fn split_series(
        &self,
        iv: Interval,
        p: Piece,
        depth: usize,
        out: &mut Vec<Piece>,
    ) -> Result<(), EmbedError> {
        if depth > 0 && p.centred && p.free > 0 {
            let halves = iv.split(2)?;
            let left = self.embed_piece(halves[0])?;
            let right = self.embed_piece(halves[1])?;
            if corners(left.free).saturating_add(corners(right.free)) <= corners(p.free)
                && (!p.guaranteed() || (left.guaranteed() && right.guaranteed()))
            {
                self.split_series(halves[0], left, depth - 1, out)?;
                return self.split_series(halves[1], right, depth - 1, out);
            }
        }
        out.push(p);
        Ok(())
    }

    /// The embedding of one piece (see [`ResidueExpansion::embed`]). When the centred series
    /// fails the self-check (its matrices carry the rounding of `e^{Ac}`, e.g. `5·10⁻⁸` for a
    /// defective `A` with `‖A‖c ≈ 32`), the piece is embedded by the clusters instead.
    fn embed_piece(&self, iv: Interval) -> Result<Piece, EmbedError> {
        let p = self.embed_piece_with(iv, true)?;
        match p.embedding.method() {
            Method::Residue {
                reconstruction_error,
                ..
            } if p.centred && *reconstruction_error > self.options.check_tolerance => {
                self.embed_piece_with(iv, false)
            }
            _ => Ok(p),
        }
    }

    /// [`ResidueExpansion::embed_piece`], the centred series allowed or not.
    fn embed_piece_with(&self, iv: Interval, series: bool) -> Result<Piece, EmbedError> {
        let a = self.a.as_ref();
        if iv.is_point() {
            let x = expm_scaled(a, iv.t1())?;
            let method = Method::Residue {
                terms: 0,
                free_terms: 0,
                reconstruction_error: 0.0,
                projector_sum_error: self.projector_sum_error,
            };
            return Ok(Piece {
                embedding: Embedding::new(
                    a.to_owned(),
                    iv,
                    vec![x],
                    method,
                    Containment::Guaranteed,
                    0.0,
                ),
                centred: false,
                free: 0,
                clusters_free: 0,
            });
        }
        let points = self.options.check_points;
        let head = Interval::new(iv.t1(), self.check_end(&iv))?;
        let grid = head.grid(points);
        let exact: Vec<Mat<f64>> = expm_stepper(
            a,
            head.t1(),
            head.length() / (points - 1) as f64,
            points - 1,
        )?
        .collect();
        let scale = exact.iter().map(|e| e.norm_l2()).fold(0.0, f64::max);
        if !scale.is_finite() {
            return Err(InputError::non_finite("e^{Av} on the sampling window").into());
        }
        let (truncated, projector_sum_error, clusters_free) =
            self.window_terms(iv.t1(), iv.t2(), scale, series)?;
        let centred = matches!(
            truncated.terms.first().map(|t| t.function),
            Some(CoefficientFunction::Centred { .. })
        );
        let ranges: Vec<CoefficientRange> = truncated
            .terms
            .iter()
            .map(|t| t.function.range(iv.t1(), iv.t2()))
            .collect::<Result<_, _>>()?;
        let n = a.nrows();
        let (box_ranges, collapsed) =
            collapse_small_terms(&truncated.terms, &ranges, truncated.remainder_bound);
        let (vertices, free) = box_vertices(
            None,
            &truncated
                .terms
                .iter()
                .map(|t| t.matrix.as_ref())
                .collect::<Vec<_>>(),
            &box_ranges,
            self.options.max_vertices,
            (n, n),
        )?;
        // Self-check: reconstruction on the grid. Column g of `approx` is
        // vec(Σ_k c_k(v_g) N_k), all grid points in one matrix product.
        let terms = &truncated.terms;
        let dirs = Mat::from_fn(n * n, terms.len(), |p, k| terms[k].matrix[(p % n, p / n)]);
        let coefs = Mat::from_fn(terms.len(), grid.len(), |k, g| {
            terms[k].function.eval(grid[g])
        });
        let mut approx = Mat::<f64>::zeros(n * n, grid.len());
        matmul(
            approx.as_mut(),
            Accum::Replace,
            dirs.as_ref(),
            coefs.as_ref(),
            1.0,
            Par::Seq,
        );
        let reconstruction: Vec<f64> = exact
            .iter()
            .enumerate()
            .map(|(g, e)| {
                let err = (0..n * n)
                    .map(|p| (approx[(p, g)] - e[(p % n, p / n)]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                if err.is_nan() { f64::INFINITY } else { err }
            })
            .collect();
        // Beyond the decay of every mode (a window longer than `check_end`), the expansion
        // itself is negligible: `Σ_k max|c_k|·‖N_k‖_F` over `[S, T2]` (exact coefficient ranges)
        // relative to the window's scale.
        let tail_error = if head.t2() < iv.t2() {
            let mut size = 0.0;
            for t in terms {
                let r = t.function.range(head.t2(), iv.t2())?;
                size += r.lower.abs().max(r.upper.abs()) * t.matrix.norm_l2();
            }
            size / scale
        } else {
            0.0
        };
        // The kept terms differ from the whole expansion by at most the truncation remainder
        // (a rigorous bound, reported with the embedding): the self-check measures what is
        // left beyond it, the error of the computed residues themselves.
        let reconstruction_error = reconstruction
            .iter()
            .zip(&exact)
            .map(|(r, e)| (r - truncated.remainder_bound).max(0.0) / e.norm_l2())
            .fold(tail_error, f64::max);
        let tol = self.options.check_tolerance;
        let method = Method::Residue {
            terms: truncated.terms.len(),
            free_terms: free,
            reconstruction_error,
            projector_sum_error,
        };
        let mut embedding = Embedding::new(
            a.to_owned(),
            iv,
            vertices,
            method,
            Containment::Guaranteed,
            truncated.remainder_bound + collapsed * (1.0 + 1e-12),
        );
        if reconstruction_error > tol || projector_sum_error > tol {
            // The paper's argument does not apply to the computed residues; check e^{Av} on the
            // grid instead. Y(v) = Σ c_k(v) N_k lies in the hull (its coefficients lie in the
            // box), so dist(e^{Av}, hull) ≤ ‖Y(v) − e^{Av}‖_F; only where that bound is not
            // enough is the hull problem solved.
            let mut worst = if tail_error > HULL_TOLERANCE {
                (tail_error, head.t2())
            } else {
                (0.0f64, iv.t1())
            };
            for ((&v, e), &r) in grid.iter().zip(&exact).zip(&reconstruction) {
                let scale = embedding.relative_scale(e.as_ref());
                // Y(v) lies within `collapsed` of the hull (the collapsed coefficients are at
                // their midpoints there), so only the truncation remainder is left for `r`.
                let mut violation = (r - truncated.remainder_bound).max(0.0) / scale;
                if violation > HULL_TOLERANCE {
                    violation = violation.min(embedding.violation(e.as_ref())?);
                }
                if violation > worst.0 {
                    worst = (violation, v);
                }
            }
            embedding.set_containment(if worst.0 <= HULL_TOLERANCE {
                Containment::VerifiedOnGrid {
                    points: grid.len(),
                    max_error: worst.0,
                }
            } else {
                Containment::NotGuaranteed {
                    reason: format!(
                        "residue self-check failed (reconstruction error {reconstruction_error:.2e}, \
                         projector-sum error {:.2e}, tolerance {tol:.0e}) and e^(Av) lies {:.2e} \
                         (relative Frobenius distance) outside the hull at v = {}",
                        projector_sum_error, worst.0, worst.1
                    ),
                }
            });
        }
        Ok(Piece {
            embedding,
            centred,
            free: free_terms(&truncated),
            clusters_free,
        })
    }
}

/// Number of box coordinates of `t`: its terms whose coefficient function is not constant.
/// This depends on the eigenvalues and the kept powers only, not on the norms of the terms'
/// matrices (which decide what [`collapse_small_terms`] folds, and change with the
/// coordinates).
fn free_terms(t: &TruncatedExpansion) -> usize {
    t.terms.iter().filter(|x| !x.function.is_constant()).count()
}

/// The box ranges of the terms, with the terms whose whole variation is small folded into the
/// remainder, and the bound on what was folded.
///
/// When the expansion is truncated with a remainder `δ > 0` (clusters of distinct eigenvalues,
/// whose moments never vanish), each term `c_k(v)N_k` whose half-range times `‖N_k‖_F` is small
/// is replaced by its midpoint value: `c_k(v)N_k = m_k N_k + (c_k(v) − m_k)N_k` with
/// `‖(c_k(v) − m_k)N_k‖_F ≤ r_k‖N_k‖_F` (`m_k`, `r_k` the midpoint and the half-width of the
/// outward-rounded range, the midpoint rounded to nearest: `r_k` is increased by one ulp of the
/// larger end). Terms are folded, the smallest first, while the total folded stays at most `δ`
/// (so the remainder at most doubles); each one halves the vertex count. An exact expansion
/// (`δ = 0`) is left as it is.
fn collapse_small_terms(
    terms: &[ExpansionTerm],
    ranges: &[CoefficientRange],
    remainder: f64,
) -> (Vec<(f64, f64)>, f64) {
    let mut out: Vec<(f64, f64)> = ranges.iter().map(|r| (r.lower, r.upper)).collect();
    if !(remainder > 0.0 && remainder.is_finite()) {
        return (out, 0.0);
    }
    let mut sizes: Vec<(f64, usize)> = terms
        .iter()
        .zip(ranges)
        .enumerate()
        .filter(|(_, (_, r))| !r.is_degenerate())
        .map(|(k, (t, r))| {
            let half = 0.5 * (r.upper - r.lower) + f64::EPSILON * r.upper.abs().max(r.lower.abs());
            (half * t.matrix.norm_l2(), k)
        })
        .filter(|(size, _)| size.is_finite())
        .collect();
    sizes.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut folded = 0.0;
    for (size, k) in sizes {
        if folded + size > remainder {
            break;
        }
        folded += size;
        let mid = 0.5 * (ranges[k].lower + ranges[k].upper);
        out[k] = (mid, mid);
    }
    (out, folded)
}

/// Residue embedding with default options: shorthand for
/// `ResidueExpansion::new(a)?.embed(t1, t2)`.
pub fn residue_embedding(a: MatRef<'_, f64>, t1: f64, t2: f64) -> Result<Embedding, EmbedError> {
    Interval::new(t1, t2)?;
    ResidueExpansion::new(a)?.embed(t1, t2)
}
