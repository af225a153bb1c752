//! Step 3 of the §5.3 algorithm: validation of `Ξ_σ(τ) ≻ μI` (48) on a fine τ-grid with spacing (49),
//! and the worst point (50).
//!
//! # What is computed
//!
//! For sensor σ and the Lyapunov matrices `P_σ`, `P_Γ = P_Γ(σ)`,
//!
//! ```text
//! Ξ_σ(τ) = [ C^⊥ᵀ E(τ)ᵀ P_σ E(τ) C^⊥   ⋆  ]      E(τ) = e^{−Aτ}                      (44)
//!          [ P_Γ C^⊥                   P_Γ ]
//! ```
//!
//! is checked against `μI` on every point of a uniform grid of `[T_mσ, T_Mσ]` (or on an explicit list
//! of τ), and when some point fails, the exact minimiser over the grid of `λ_min(Ξ_σ(τ))` is returned.
//!
//! # How (exact optimisations, same result as one eigen-solve per point)
//!
//! * `E(τ_k)` comes from [`sporadic_linalg::ExpmStepper`] (one `n × n` product per point, re-anchored by
//!   a fresh exponential at every chunk start and every [`sporadic_linalg::DEFAULT_REANCHOR`] steps).
//! * Only the `(n − m)²` top-left block depends on τ. When `P_Γ − λI ≻ 0`, the Schur complement gives
//!   `Ξ_σ(τ) − λI ≻ 0 ⇔ C^⊥ᵀΦ_σ(τ)C^⊥ − R_λ ≻ 0` with the constant
//!   `R_λ = λI + C^⊥ᵀ P_Γ (P_Γ − λI)⁻¹ P_Γ C^⊥`, so each point costs three small products and one
//!   `(n − m)`-dimensional in-place Cholesky (pass/fail). If `P_Γ − λI` is not positive definite, every
//!   τ fails at level λ (it is a principal block of `Ξ_σ − λI`).
//! * **One pass, parallel over chunks** of the grid. In each chunk every point gets the Cholesky test at
//!   level μ; the `C^⊥ᵀΦ_σC^⊥` blocks of the failing points are kept in a chunk buffer, and the exact
//!   `λ_min(Ξ_σ(τ))` is computed at every `sample_stride`-th failing point (always the first). At the end
//!   of the chunk, with `λ̂` the smaller of the chunk's sampled minimum and the best value found so far
//!   by any chunk (shared atomically), the buffered points are re-tested at level `λ̂` — a Cholesky of
//!   the stored block, no new exponential — and the eigenvalue is computed only where that test fails,
//!   i.e. where `λ_min ≤ λ̂`. Every point that can be the grid minimiser is therefore evaluated, so the
//!   argmin (50) is exact (ties go to the smallest τ), while eigen-solves are needed only near the bottom
//!   of each dip.
//!
//! When no point fails, the reported minimum is that of a coarse subsample (the first point of every
//! chunk) and flagged as not exact; the pass/fail verdict itself is exact on every grid point.

use sporadic_linalg::InputError;
use std::ops::Range;
use std::sync::atomic::{AtomicU64, Ordering};

use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef, Side};
use rayon::prelude::*;
use sporadic_linalg::{expm_scaled, expm_stepper, min_eigenvalue};

use crate::error::{Error, check_at_least, sig4};
use crate::gain::check_sym;
use crate::plant::RoundRobinPlant;
use crate::prove::{XiDecisive, prove_validation};
use sporadic_model::{ProofStatus, ProofStop, SamplingWindow};

/// How the validation grid spacing `τ_{k+1} − τ_k` is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GridPolicy {
    /// The paper's (49): spacing `2δ* = 2μ / (p* ‖A‖ γ e^{βT_M})` (spectral norm). Not provably safe
    /// in general (it bounds the variation of `e^{−Aτ}`, not of `Ξ_σ(τ)`) but faithful to the paper;
    /// the default.
    Paper,
    /// A spacing from the rigorous Lipschitz bound `‖dΞ_σ/dτ‖ ≤ 2‖A‖ p* γ² e^{2βT_M} ‖C_σ^⊥‖²`:
    /// `2δ = 2μ / (2 p* ‖A‖ γ² e^{2βT_M} ‖C_σ^⊥‖²)`, so that `λ_min > μ` on the grid implies
    /// `λ_min > 0` on the whole window (Weyl's inequality).
    Rigorous,
    /// A fixed user spacing (upper bound on `τ_{k+1} − τ_k`), for fast experiments.
    Spacing(f64),
}

/// The exponential bound `‖e^{−Aτ}‖₂ ≤ γ e^{βτ}` (τ ≥ 0) of Step 1 ([34, Lemma 3]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExponentialBound {
    /// Rate β (larger than the spectral abscissa of −A).
    pub beta: f64,
    /// Constant `γ = √(λ_M(Π)/λ_m(Π))`.
    pub gamma: f64,
}

impl ExponentialBound {
    /// `γ e^{βT}`, the bound on `max_{0 ≤ τ ≤ T} ‖e^{−Aτ}‖₂`.
    pub fn at(&self, t: f64) -> f64 {
        self.gamma * (self.beta * t).exp()
    }
}

/// Spectral norm `‖M‖₂` (largest singular value; 0 for an empty matrix).
///
/// # Errors
/// The singular value iteration did not converge.
pub(crate) fn spectral_norm(m: MatRef<'_, f64>) -> Result<f64, Error> {
    if m.nrows() == 0 || m.ncols() == 0 {
        return Ok(0.0);
    }
    let sv = m
        .singular_values()
        .map_err(|_| Error::numerical("SVD did not converge"))?;
    Ok(sv[0])
}

/// Grid spacing (largest allowed `τ_{k+1} − τ_k`) for sensor `sigma` under `policy`, given the margin μ,
/// `p_norm` (an upper bound of `‖P_σ‖₂` over all σ, i.e. p* of (47)) and the exponential bound.
///
/// # Errors
/// Non-positive or non-finite parameters, or a failing SVD.
pub fn grid_spacing(
    plant: &RoundRobinPlant,
    sigma: usize,
    policy: GridPolicy,
    mu: f64,
    p_norm: f64,
    bound: &ExponentialBound,
) -> Result<f64, Error> {
    if !(mu > 0.0 && mu.is_finite() && p_norm > 0.0 && p_norm.is_finite()) {
        return Err(Error::invalid(format!(
            "grid spacing needs μ > 0 and p* > 0 (got μ = {}, p* = {})",
            sig4(mu),
            sig4(p_norm)
        )));
    }
    if let GridPolicy::Spacing(h) = policy
        && !(h > 0.0 && h.is_finite())
    {
        return Err(Error::invalid(format!(
            "grid spacing must be positive and finite (got {})",
            sig4(h)
        )));
    }
    let sensor = plant.sensor(sigma)?;
    if sensor.c_perp().ncols() == 0 {
        // m_σ = n: Ξ_σ(τ) = P_Γ does not depend on τ; one point is exact.
        return Ok(f64::MAX);
    }
    let growth = bound.at(plant.t_max());
    let a_norm = spectral_norm(plant.a())?;
    let spacing = match policy {
        // A = 0: Ξ does not depend on τ (also when the growth bound overflows, where the
        // formulas would give `0·∞`).
        GridPolicy::Paper | GridPolicy::Rigorous if a_norm == 0.0 => f64::INFINITY,
        GridPolicy::Paper => 2.0 * mu / (p_norm * a_norm * growth),
        GridPolicy::Rigorous => {
            let cp = spectral_norm(sensor.c_perp())?;
            2.0 * mu / (2.0 * p_norm * a_norm * growth * growth * cp * cp)
        }
        GridPolicy::Spacing(s) => s,
    };
    if spacing == f64::INFINITY {
        // A = 0 or C^⊥ = 0: Ξ does not depend on τ; any spacing is exact.
        Ok(f64::MAX)
    } else if spacing >= 0.0 {
        // 0 when (49) underflows (`‖A‖·γe^{βT_M}` beyond the double range, a strongly
        // non-normal `A` on a long window): the grid would need infinitely many points, which
        // `UniformGrid::covering` reports as above any cap.
        Ok(spacing)
    } else {
        Err(Error::invalid(format!(
            "grid spacing must be nonnegative (got {})",
            sig4(spacing)
        )))
    }
}

/// A uniform grid `τ_k = t_min + k·spacing`, `k = 0, …, points − 1`, whose last point is the window's
/// upper end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniformGrid {
    /// First point.
    pub t_min: f64,
    /// Distance between consecutive points (0 for a single point).
    pub spacing: f64,
    /// Number of points (≥ 1).
    pub points: usize,
}

impl UniformGrid {
    /// The coarsest uniform grid of `window` with spacing at most `max_spacing`:
    /// `ν = ⌈(T_M − T_m)/max_spacing⌉ + 1` points. `cap` bounds ν.
    ///
    /// # Errors
    /// Negative or NaN spacing, or more than `cap` points ([`Error::GridTooLarge`], sensor
    /// reported as 0; a spacing of 0, as [`grid_spacing`] gives when (49) underflows, needs
    /// infinitely many).
    pub fn covering(window: SamplingWindow, max_spacing: f64, cap: f64) -> Result<Self, Error> {
        if max_spacing.is_nan() || max_spacing < 0.0 {
            return Err(Error::invalid(format!(
                "grid spacing must be nonnegative (got {})",
                sig4(max_spacing)
            )));
        }
        let width = window.t2() - window.t1();
        if width == 0.0 {
            return Ok(Self {
                t_min: window.t1(),
                spacing: 0.0,
                points: 1,
            });
        }
        let intervals = (width / max_spacing).ceil();
        if !(intervals + 1.0 <= cap) {
            return Err(Error::GridTooLarge {
                sigma: 0,
                points: intervals + 1.0,
                cap,
                proof: String::new(),
                unresolved: false,
            });
        }
        let intervals = intervals.max(1.0) as usize;
        Ok(Self {
            t_min: window.t1(),
            spacing: width / intervals as f64,
            points: intervals + 1,
        })
    }

    /// The k-th point.
    pub fn tau(&self, k: usize) -> f64 {
        self.t_min + k as f64 * self.spacing
    }
}

/// Tuning of the validation pass (none of it changes the result). Defaults: 4096 points per
/// chunk, an exact eigenvalue at every 64th failing point, at most 4·10⁹ points per sensor,
/// parallel chunks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValidationOptions {
    /// Grid points per parallel chunk (each chunk starts with a fresh exponential).
    pub chunk_points: usize,
    /// The exact `λ_min` is computed at every `sample_stride`-th failing point of a chunk (a first
    /// estimate of the chunk's minimum).
    pub sample_stride: usize,
    /// Cap on the number of grid points per sensor.
    pub max_points: f64,
    /// Run chunks in parallel (rayon); `false` for single-core measurements.
    pub parallel: bool,
}

impl ValidationOptions {
    /// Checks every field; the error names the offending one.
    ///
    /// # Errors
    /// [`InputError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<(), InputError> {
        check_at_least("validation.chunk_points", self.chunk_points, 1)?;
        check_at_least("validation.sample_stride", self.sample_stride, 1)?;
        if !(self.max_points >= 1.0) {
            return Err(InputError::parameter(
                "validation.max_points",
                self.max_points,
                "must be at least 1",
            ));
        }
        Ok(())
    }
}

impl Default for ValidationOptions {
    fn default() -> Self {
        Self {
            chunk_points: 4096,
            sample_stride: 64,
            max_points: 4e9,
            parallel: true,
        }
    }
}

/// Outcome of validating one sensor.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorValidation {
    /// Sensor (0-based).
    pub sigma: usize,
    /// The margin μ tested (`Ξ_σ(τ) ≻ μI`).
    pub mu: f64,
    /// Points tested (0 for a validation decided by a proof over the window, the screen's
    /// points for a window above the cap refuted by its screen, see [`validate_window`]).
    pub points: usize,
    /// Grid spacing (0 for an explicit list of points).
    pub spacing: f64,
    /// Points with `λ_min(Ξ_σ(τ)) ≤ μ`.
    pub failures: u64,
    /// Minimum of `λ_min(Ξ_σ(τ))`: exact over all points when `failures > 0`, otherwise over a coarse
    /// subsample (see `min_is_exact`).
    pub min_eigenvalue: f64,
    /// Where `min_eigenvalue` is attained: the τ̄ of (50) when `failures > 0`.
    pub argmin_tau: f64,
    /// Whether `min_eigenvalue` is the exact minimum over all points.
    pub min_is_exact: bool,
    /// Number of full eigenvalue computations performed.
    pub eigen_evaluations: u64,
    /// `Some(k)`: (48) was proven for every `τ` of the window in interval arithmetic, on `k`
    /// pieces ([`crate::design::DesignOptions::proof_pieces`]), and no grid was run: `points`
    /// is 0, `spacing` that of the (49) grid it replaced, `min_eigenvalue` is μ (the proof
    /// shows `λ_min(Ξ_σ(τ)) > μ` at every τ, not by how much) and `argmin_tau` NaN.
    pub proof_pieces: Option<usize>,
}

impl SensorValidation {
    /// Whether (48) holds on every point.
    pub fn passed(&self) -> bool {
        self.failures == 0
    }

    /// The validation of sensor `sigma` at level μ by a proof of (48) over its whole window on
    /// `pieces` pieces, in place of the grid of spacing `spacing` (see
    /// [`SensorValidation::proof_pieces`]).
    pub fn proven(sigma: usize, mu: f64, spacing: f64, pieces: usize) -> Self {
        Self {
            sigma,
            mu,
            points: 0,
            spacing,
            failures: 0,
            min_eigenvalue: mu,
            argmin_tau: f64::NAN,
            min_is_exact: false,
            eigen_evaluations: 0,
            proof_pieces: Some(pieces),
        }
    }
}

/// The family `τ ↦ Ξ_σ(τ)` of (44) for fixed `P_1, …, P_N` and one sensor σ, with the precomputed
/// constants of the fast validation pass.
#[derive(Debug, Clone)]
pub struct XiFamily {
    sigma: usize,
    neg_a: Mat<f64>,
    c_perp: Mat<f64>,
    p_next: Mat<f64>,
    /// `P_Γ C^⊥` (`n × r`).
    off: Mat<f64>,
    /// `C^⊥` and `P_σ` column-major, for the fused kernel [`quad_form`].
    cp_cols: Vec<f64>,
    p_cols: Vec<f64>,
}

/// A level λ of the test `Ξ_σ(τ) − λI ≻ 0`: `Some(R_λ)` when `P_Γ − λI ≻ 0`, `None` when every τ fails.
struct Level {
    /// `R_λ` column-major (`r × r`).
    r: Option<Vec<f64>>,
}

/// Per-thread buffers of the validation kernel.
struct Workspace {
    e: Mat<f64>,
    e_cols: Vec<f64>,
    z: Vec<f64>,
    /// `C^⊥ᵀ Φ_σ(τ) C^⊥`, column-major `r × r`, lower triangle.
    q: Vec<f64>,
    chol: Vec<f64>,
}

/// Where the points come from.
#[derive(Clone, Copy)]
enum Source<'a> {
    Grid(UniformGrid),
    Points(&'a [f64]),
}

impl Source<'_> {
    fn len(&self) -> usize {
        match self {
            Self::Grid(g) => g.points,
            Self::Points(p) => p.len(),
        }
    }
}

/// Summary of one chunk.
#[derive(Clone, Copy, Default)]
struct ChunkResult {
    failures: u64,
    /// Smallest exact `λ_min` found among the chunk's failing points (may be pruned by the global best).
    best: Option<(f64, f64)>,
    /// `λ_min` at the chunk's first point.
    coarse: Option<(f64, f64)>,
    eig: u64,
}

/// The smallest `λ_min` found so far by any chunk (`f64` bits in an atomic, updated by compare-exchange).
struct SharedMin(AtomicU64);

impl SharedMin {
    fn new() -> Self {
        Self(AtomicU64::new(f64::INFINITY.to_bits()))
    }
    fn get(&self) -> f64 {
        f64::from_bits(self.0.load(Ordering::Relaxed))
    }
    fn lower_to(&self, v: f64) {
        let mut cur = self.0.load(Ordering::Relaxed);
        while v < f64::from_bits(cur) {
            match self.0.compare_exchange_weak(
                cur,
                v.to_bits(),
                Ordering::Relaxed,
                Ordering::Relaxed,
            ) {
                Ok(_) => break,
                Err(c) => cur = c,
            }
        }
    }
}

/// Smaller λ wins; ties go to the smaller τ.
fn better(a: Option<(f64, f64)>, b: Option<(f64, f64)>) -> Option<(f64, f64)> {
    match (a, b) {
        (None, x) | (x, None) => x,
        (Some(x), Some(y)) => {
            if y.0 < x.0 || (y.0 == x.0 && y.1 < x.1) {
                Some(y)
            } else {
                Some(x)
            }
        }
    }
}

/// `q ← (E C)ᵀ P (E C)` (lower triangle of the `r × r` result, column-major), for `E` (`n × n`), `C`
/// (`n × r`) and `P` (`n × n`) given as column-major slices; `z` is `n × r` scratch.
///
/// The three products are fused by hand and, for `n ≤ 8`, specialised on the order: at the sizes of
/// the validation kernel a general GEMM call spends most of its time in dispatch and packing
/// (measured with `perf` on the §6 example: ≈ 70 % of the validation pass inside the small-matrix
/// GEMM path for 4×4 operands).
#[inline]
fn quad_form(e: &[f64], c: &[f64], p: &[f64], n: usize, r: usize, z: &mut [f64], q: &mut [f64]) {
    macro_rules! fixed {
        ($($k:literal)*) => {
            match n {
                $($k => quad_form_fixed::<$k>(e, c, p, r, z, q),)*
                _ => quad_form_dyn(e, c, p, n, r, z, q),
            }
        };
    }
    fixed!(1 2 3 4 5 6 7 8)
}

#[inline(always)]
fn quad_form_fixed<const N: usize>(
    e: &[f64],
    c: &[f64],
    p: &[f64],
    r: usize,
    z: &mut [f64],
    q: &mut [f64],
) {
    let e = &e[..N * N];
    let p = &p[..N * N];
    for j in 0..r {
        let cj = &c[j * N..(j + 1) * N];
        let mut zj = [0.0; N];
        for k in 0..N {
            let ckj = cj[k];
            let ek = &e[k * N..(k + 1) * N];
            for i in 0..N {
                zj[i] += ek[i] * ckj;
            }
        }
        // pz_j = P z_j, then q_ij = z_i · pz_j for i ≥ j (z_i of earlier columns is final).
        let mut pzj = [0.0; N];
        for k in 0..N {
            let pk = &p[k * N..(k + 1) * N];
            for i in 0..N {
                pzj[i] += pk[i] * zj[k];
            }
        }
        z[j * N..(j + 1) * N].copy_from_slice(&zj);
        for i in 0..=j {
            let zi = &z[i * N..(i + 1) * N];
            let mut acc = 0.0;
            for k in 0..N {
                acc += zi[k] * pzj[k];
            }
            q[j + i * r] = acc;
        }
    }
}

fn quad_form_dyn(
    e: &[f64],
    c: &[f64],
    p: &[f64],
    n: usize,
    r: usize,
    z: &mut [f64],
    q: &mut [f64],
) {
    let mut pzj = vec![0.0; n];
    for j in 0..r {
        let zj = &mut z[j * n..(j + 1) * n];
        zj.fill(0.0);
        for k in 0..n {
            let ckj = c[k + j * n];
            for i in 0..n {
                zj[i] += e[i + k * n] * ckj;
            }
        }
        pzj.fill(0.0);
        for k in 0..n {
            for i in 0..n {
                pzj[i] += p[i + k * n] * z[k + j * n];
            }
        }
        for i in 0..=j {
            q[j + i * r] = (0..n).map(|k| z[k + i * n] * pzj[k]).sum();
        }
    }
}

/// Whether the symmetric `k × k` matrix whose lower triangle is in `a` (column-major) is positive
/// definite: an unpivoted Cholesky factorisation in place that stops at the first non-positive pivot
/// (the pass/fail test of the validation, without the dispatch overhead of a general factorisation at
/// these tiny orders).
#[inline]
fn cholesky_passes(a: &mut [f64], k: usize) -> bool {
    for j in 0..k {
        let mut d = a[j + j * k];
        for t in 0..j {
            d -= a[j + t * k] * a[j + t * k];
        }
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        a[j + j * k] = d;
        for i in j + 1..k {
            let mut v = a[i + j * k];
            for t in 0..j {
                v -= a[i + t * k] * a[j + t * k];
            }
            a[i + j * k] = v / d;
        }
    }
    true
}

impl XiFamily {
    /// The family for sensor `sigma` (0-based) and `p = [P_1, …, P_N]` (symmetric, `n × n`).
    ///
    /// # Errors
    /// Wrong count/shape, non-finite or non-symmetric `P_σ`, index out of range.
    pub fn new(plant: &RoundRobinPlant, p: &[Mat<f64>], sigma: usize) -> Result<Self, Error> {
        let n_s = plant.num_sensors();
        if p.len() != n_s {
            return Err(InputError::mismatch("number of P_σ", n_s, p.len()).into());
        }
        let c_perp = plant.sensor(sigma)?.c_perp().to_owned();
        for (k, pk) in p.iter().enumerate() {
            check_sym(pk.as_ref(), plant.n(), &format!("P_{}", k + 1))?;
        }
        let nx = plant.next(sigma);
        let off = &p[nx] * &c_perp;
        let cols = |m: &Mat<f64>| {
            (0..m.ncols())
                .flat_map(|j| (0..m.nrows()).map(move |i| (i, j)))
                .map(|(i, j)| m[(i, j)])
                .collect()
        };
        let cp_cols = cols(&c_perp);
        let p_cols = cols(&p[sigma]);
        Ok(Self {
            cp_cols,
            p_cols,
            sigma,
            neg_a: Mat::from_fn(plant.n(), plant.n(), |i, j| -plant.a()[(i, j)]),
            c_perp,
            p_next: p[nx].clone(),
            off,
        })
    }

    fn n(&self) -> usize {
        self.neg_a.nrows()
    }
    fn r(&self) -> usize {
        self.c_perp.ncols()
    }

    /// `Ξ_σ(τ)` of (44) (order `2n − m_σ`), with a fresh exponential.
    ///
    /// # Errors
    /// Non-finite τ or a failing exponential.
    pub fn matrix(&self, tau: f64) -> Result<Mat<f64>, Error> {
        if !tau.is_finite() {
            return Err(InputError::non_finite("τ").into());
        }
        let mut ws = self.workspace();
        ws.e.copy_from(expm_scaled(self.neg_a.as_ref(), tau)?);
        self.load(&mut ws);
        Ok(self.assemble(&ws.q))
    }

    /// `λ_min(Ξ_σ(τ))`.
    ///
    /// # Errors
    /// Non-finite τ or a failing kernel.
    pub fn min_eigenvalue(&self, tau: f64) -> Result<f64, Error> {
        Ok(min_eigenvalue(self.matrix(tau)?.as_ref())?)
    }

    fn workspace(&self) -> Workspace {
        let (n, r) = (self.n(), self.r());
        Workspace {
            e: Mat::zeros(n, n),
            e_cols: vec![0.0; n * n],
            z: vec![0.0; n * r],
            q: vec![0.0; r * r],
            chol: vec![0.0; r * r],
        }
    }

    fn level(&self, lambda: f64) -> Result<Level, Error> {
        let n = self.n();
        let shifted = Mat::from_fn(n, n, |i, j| {
            self.p_next[(i, j)] - if i == j { lambda } else { 0.0 }
        });
        let Ok(llt) = shifted.llt(Side::Lower) else {
            return Ok(Level { r: None });
        };
        let x = llt.solve(&self.off); // (P_Γ − λI)⁻¹ P_Γ C^⊥
        let g = self.off.transpose() * &x;
        let r = Mat::from_fn(self.r(), self.r(), |i, j| {
            0.5 * (g[(i, j)] + g[(j, i)]) + if i == j { lambda } else { 0.0 }
        });
        if !r.norm_max().is_finite() {
            return Err(InputError::non_finite("R_λ").into());
        }
        let k = self.r();
        Ok(Level {
            r: Some((0..k * k).map(|t| r[(t % k, t / k)]).collect()),
        })
    }

    /// `ws.q ← C^⊥ᵀ E ᵀ P_σ E C^⊥` from `ws.e`.
    #[inline]
    fn load(&self, ws: &mut Workspace) {
        let n = self.n();
        for j in 0..n {
            ws.e_cols[j * n..(j + 1) * n].copy_from_slice(ws.e.col_as_slice(j));
        }
        quad_form(
            &ws.e_cols,
            &self.cp_cols,
            &self.p_cols,
            n,
            self.r(),
            &mut ws.z,
            &mut ws.q,
        );
    }

    /// Whether `Ξ_σ(τ) − λI ≻ 0` for the point whose `C^⊥ᵀΦ_σC^⊥` block (lower, column-major) is `q`.
    #[inline]
    fn passes(&self, q: &[f64], chol: &mut [f64], level: &Level) -> bool {
        let Some(r) = &level.r else { return false };
        let k = self.r();
        if k == 0 {
            return true;
        }
        for j in 0..k {
            for i in j..k {
                chol[i + j * k] = q[i + j * k] - r[i + j * k];
            }
        }
        cholesky_passes(chol, k)
    }

    /// The full `Ξ_σ` from its `C^⊥ᵀΦ_σC^⊥` block `q`.
    fn assemble(&self, q: &[f64]) -> Mat<f64> {
        let (n, r) = (self.n(), self.r());
        Mat::from_fn(r + n, r + n, |i, j| match (i < r, j < r) {
            (true, true) => q[i.max(j) + i.min(j) * r],
            (false, true) => self.off[(i - r, j)],
            (true, false) => self.off[(j - r, i)],
            (false, false) => self.p_next[(i - r, j - r)],
        })
    }

    fn eig(&self, q: &[f64]) -> Result<f64, Error> {
        Ok(min_eigenvalue(self.assemble(q).as_ref())?)
    }

    /// Runs `f(ws, τ)` on every point of `range` with `ws.e = e^{−Aτ}` and `ws.q` loaded.
    fn scan<F>(
        &self,
        src: Source<'_>,
        range: Range<usize>,
        ws: &mut Workspace,
        mut f: F,
    ) -> Result<(), Error>
    where
        F: FnMut(&Self, &mut Workspace, f64) -> Result<(), Error>,
    {
        if range.is_empty() {
            return Ok(());
        }
        match src {
            Source::Grid(g) => {
                let mut st = expm_stepper(
                    self.neg_a.as_ref(),
                    g.tau(range.start),
                    g.spacing,
                    range.len() - 1,
                )?;
                while let Some(tau) = st.next_into(ws.e.as_mut()) {
                    self.load(ws);
                    f(self, ws, tau)?;
                }
                if let Some(e) = st.error() {
                    return Err(e.clone().into());
                }
            }
            Source::Points(pts) => {
                for &tau in &pts[range] {
                    if !tau.is_finite() {
                        return Err(InputError::non_finite("τ sample").into());
                    }
                    ws.e.copy_from(expm_scaled(self.neg_a.as_ref(), tau)?);
                    self.load(ws);
                    f(self, ws, tau)?;
                }
            }
        }
        Ok(())
    }

    fn chunk(
        &self,
        src: Source<'_>,
        range: Range<usize>,
        mu: &Level,
        stride: u64,
        global: &SharedMin,
    ) -> Result<ChunkResult, Error> {
        let mut ws = self.workspace();
        let rr = self.r() * self.r();
        let mut out = ChunkResult::default();
        let mut buf_q: Vec<f64> = Vec::new();
        let mut buf_tau: Vec<f64> = Vec::new();
        let mut sampled: Option<(f64, f64)> = None;
        self.scan(src, range, &mut ws, |me, ws, tau| {
            let mut lam = None;
            if !me.passes(&ws.q, &mut ws.chol, mu) {
                if out.failures % stride == 0 {
                    let l = me.eig(&ws.q)?;
                    out.eig += 1;
                    lam = Some(l);
                    sampled = better(sampled, Some((l, tau)));
                }
                out.failures += 1;
                buf_q.extend_from_slice(&ws.q);
                buf_tau.push(tau);
            }
            if out.coarse.is_none() {
                let l = match lam {
                    Some(l) => l,
                    None => {
                        out.eig += 1;
                        me.eig(&ws.q)?
                    }
                };
                out.coarse = Some((l, tau));
            }
            Ok(())
        })?;
        if let Some((lam_hat, _)) = sampled {
            let level = self.level(lam_hat.min(global.get()))?;
            let mut best = sampled;
            for (k, &tau) in buf_tau.iter().enumerate() {
                let q = &buf_q[k * rr..(k + 1) * rr];
                if !self.passes(q, &mut ws.chol, &level) {
                    out.eig += 1;
                    best = better(best, Some((self.eig(q)?, tau)));
                }
            }
            if let Some((l, _)) = best {
                global.lower_to(l);
            }
            out.best = best;
        }
        Ok(out)
    }

    fn run(
        &self,
        src: Source<'_>,
        mu: f64,
        settings: &ValidationOptions,
    ) -> Result<SensorValidation, Error> {
        if !mu.is_finite() {
            return Err(InputError::non_finite("μ").into());
        }
        settings.validate()?;
        let len = src.len();
        if len == 0 {
            return Err(Error::invalid("no points to validate"));
        }
        let chunks: Vec<Range<usize>> = (0..len.div_ceil(settings.chunk_points))
            .map(|c| c * settings.chunk_points..((c + 1) * settings.chunk_points).min(len))
            .collect();
        let level_mu = self.level(mu)?;
        let stride = settings.sample_stride as u64;
        let global = SharedMin::new();
        // Worker threads do not see the caller's budget scope: each chunk checks a copy.
        let budget = sporadic_sdp::budget::current();
        let work = |r: &Range<usize>| {
            if budget.is_exhausted() {
                return Err(Error::Interrupted {
                    during: "the validation (48) of the grid",
                });
            }
            self.chunk(src, r.clone(), &level_mu, stride, &global)
        };
        let res: Vec<ChunkResult> = if settings.parallel {
            chunks.par_iter().map(work).collect::<Result<_, _>>()?
        } else {
            chunks.iter().map(work).collect::<Result<_, _>>()?
        };
        let failures: u64 = res.iter().map(|c| c.failures).sum();
        let best = if failures == 0 {
            res.iter().fold(None, |b, c| better(b, c.coarse))
        } else {
            res.iter().fold(None, |b, c| better(b, c.best))
        };
        let (lam, tau) = best.expect("at least one point was evaluated");
        Ok(SensorValidation {
            sigma: self.sigma,
            mu,
            points: len,
            spacing: match src {
                Source::Grid(g) => g.spacing,
                Source::Points(_) => 0.0,
            },
            failures,
            min_eigenvalue: lam,
            argmin_tau: tau,
            min_is_exact: failures > 0,
            eigen_evaluations: res.iter().map(|c| c.eig).sum(),
            proof_pieces: None,
        })
    }

    /// Validates (48) `Ξ_σ(τ) ≻ μI` on the uniform grid (exponentials by the stepper) and returns the
    /// worst point (50) when it fails.
    ///
    /// # Errors
    /// Non-finite μ, bad settings or a failing kernel.
    pub fn validate_grid(
        &self,
        grid: UniformGrid,
        mu: f64,
        settings: &ValidationOptions,
    ) -> Result<SensorValidation, Error> {
        if grid.points == 0
            || grid.spacing.is_nan()
            || grid.spacing < 0.0
            || !grid.t_min.is_finite()
        {
            return Err(Error::invalid(format!(
                "invalid grid: {} points from τ = {}, spacing {}",
                grid.points,
                sig4(grid.t_min),
                sig4(grid.spacing)
            )));
        }
        self.run(Source::Grid(grid), mu, settings)
    }

    /// Validates `Ξ_σ(τ) ≻ μI` on an explicit list of τ (one fresh exponential per point; independent of
    /// the stepper).
    ///
    /// # Errors
    /// Empty list, non-finite τ or μ, or a failing kernel.
    pub fn validate_points(
        &self,
        taus: &[f64],
        mu: f64,
        settings: &ValidationOptions,
    ) -> Result<SensorValidation, Error> {
        self.run(Source::Points(taus), mu, settings)
    }
}

/// Grid points of (49) per piece of the budget of a proof of (48)
/// ([`validate_window`]): a piece costs a few interval exponentials and verified
/// definiteness tests, about as much as this many grid points (measured on the corpus: ≈ 3·10³
/// pieces/s against ≈ 6·10⁶ grid points/s on two cores), so an attempt that fails costs at
/// most about the grid it would have replaced.
pub const PROOF_POINTS_PER_PIECE: usize = 2048;

/// Smallest piece budget with which a proof of (48) is attempted (the number of pieces the
/// subdivision starts with): below it the grid is cheaper.
pub const MIN_PROOF_PIECES: usize = 16;

/// Points of the floating-point screen of a window whose (49) grid is above the cap
/// ([`validate_window`]): half of them uniform on `[T_mσ, T_Mσ]`, half geometric from `T_mσ`
/// (finer near the lower end of a window spanning decades): a fraction of a second of
/// exponentials and eigenvalues, against seconds for a proof that runs out of pieces.
pub const SCREEN_POINTS: usize = 4096;

/// The τ of the screen of `window` ([`SCREEN_POINTS`]).
fn screen_points(window: SamplingWindow) -> Vec<f64> {
    let (t1, t2) = (window.t1(), window.t2());
    let half = SCREEN_POINTS / 2;
    let last = (half - 1) as f64;
    let uniform = (0..half).map(|k| t1 + (t2 - t1) * (k as f64 / last));
    let geometric = (0..half).map(|k| t1 * (t2 / t1).powf(k as f64 / last));
    uniform.chain(geometric).map(|t| t.clamp(t1, t2)).collect()
}

/// The screen of a window whose (49) grid is above the cap ([`validate_window`]): `Ξ_σ(τ)` and
/// `λ_min(Ξ_σ(τ))` in floating point ([`XiFamily::matrix`], a fresh exponential, and a full
/// symmetric eigen-solve, as [`validate_naive`]) at the [`SCREEN_POINTS`] τ of
/// [`screen_points`]. The candidate `τ̂` is the point of least `λ_min(Ξ_σ(τ))/‖Ξ_σ(τ)‖_F`, the
/// most negative relative to the scale of `Ξ_σ(τ)` and so to the rounding of its evaluation
/// (`‖Ξ_σ(τ)‖` grows like `‖e^{−Aτ}‖²`: far in a long window, a floating-point `λ_min` of the
/// order of `ε‖Ξ_σ(τ)‖` below zero is rounding, whatever its absolute size). When that ratio is
/// negative, `Ξ_σ(τ̂)` is tested in interval arithmetic ([`XiDecisive`], the test of a piece
/// end by the proof): if it is shown not positive definite, (48) fails at `τ̂` for every μ > 0,
/// and the validation fails there (`points` the screen's, one failure, `min_eigenvalue` the
/// floating-point `λ_min(Ξ_σ(τ̂))`). Otherwise — no negative ratio, a `λ_min` below zero by no
/// more than the rounding the enclosure accounts for, or an enclosure that cannot be computed
/// — the screen decides nothing (`None`) and the proof runs.
fn screen_window(
    family: &XiFamily,
    plant: &RoundRobinPlant,
    p: &[Mat<f64>],
    spacing: f64,
    mu: f64,
) -> Result<Option<SensorValidation>, Error> {
    let taus = screen_points(plant.sensor(family.sigma)?.window());
    // (λ_min/‖Ξ‖_F, τ, λ_min) at the candidate.
    let mut worst: Option<(f64, f64, f64)> = None;
    for &tau in &taus {
        let xi = family.matrix(tau)?;
        let lambda = min_eigenvalue(xi.as_ref())?;
        let ratio = lambda / xi.norm_l2();
        if ratio < 0.0 && worst.is_none_or(|(r, _, _)| ratio < r) {
            worst = Some((ratio, tau, lambda));
        }
    }
    let Some((_, tau, lambda)) = worst else {
        return Ok(None);
    };
    let refuted = XiDecisive::new(plant, p, family.sigma).and_then(|mut c| c.at(tau));
    if !refuted.is_ok_and(|d| d.lo() >= 0.0) {
        return Ok(None);
    }
    Ok(Some(SensorValidation {
        sigma: family.sigma,
        mu,
        points: taus.len(),
        spacing,
        failures: 1,
        min_eigenvalue: lambda,
        argmin_tau: tau,
        min_is_exact: false,
        eigen_evaluations: taus.len() as u64,
        proof_pieces: None,
    }))
}

/// The (49) grid of a sensor's window, or, when it would have more points than the cap
/// ([`ValidationOptions::max_points`]), its size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WindowGrid {
    /// The grid, within the cap.
    Grid(UniformGrid),
    /// A grid above the cap: it is not run; only a refutation by the screen of its window or a
    /// proof of (48) over the window ([`validate_window`]) can decide the validation.
    OverCap {
        /// The largest spacing allowed (that of the grid that is not run).
        spacing: f64,
        /// Points the grid would need.
        points: f64,
        /// The cap.
        cap: f64,
    },
}

impl WindowGrid {
    /// [`UniformGrid::covering`], with a grid above the cap as [`WindowGrid::OverCap`] instead
    /// of an error.
    ///
    /// # Errors
    /// Non-positive spacing.
    pub fn covering(window: SamplingWindow, max_spacing: f64, cap: f64) -> Result<Self, Error> {
        match UniformGrid::covering(window, max_spacing, cap) {
            Ok(g) => Ok(Self::Grid(g)),
            Err(Error::GridTooLarge { points, cap, .. }) => Ok(Self::OverCap {
                spacing: max_spacing,
                points,
                cap,
            }),
            Err(e) => Err(e),
        }
    }

    /// Number of points of the grid (run or not).
    pub fn points(&self) -> f64 {
        match self {
            Self::Grid(g) => g.points as f64,
            Self::OverCap { points, .. } => *points,
        }
    }

    /// Spacing of the grid (run or not).
    pub fn spacing(&self) -> f64 {
        match self {
            Self::Grid(g) => g.spacing,
            Self::OverCap { spacing, .. } => *spacing,
        }
    }
}

/// A grid with more points than this (`2²⁴`, a few tenths of a second) is not run once the
/// proof of [`validate_window`] has refuted (48) on it: the refuted point is added to `T_σ` in
/// place of the grid's exact minimiser (50). A fuzzed plant of order 5 (`fuzz.sh 16 17`, plant
/// 3) spent its whole 25 s budget on one grid of 3.6·10⁹ points (just below the cap) after the
/// proof had refuted (48) by a margin of 10⁵. Smaller grids still find (50), as the paper does.
pub const REFUTED_POINT_FROM: usize = 1 << 24;

/// Validates (48) for one sensor, as the design loop and the check of a given certificate do:
/// with `proof_pieces = Some(k)` and a grid of at least [`MIN_PROOF_PIECES`] ×
/// [`PROOF_POINTS_PER_PIECE`] points, first by a proof of (48) for every `τ` of the window in
/// interval arithmetic ([`crate::prove`], at most `k` pieces and one per
/// [`PROOF_POINTS_PER_PIECE`] grid points), which implies (48) at every point of the grid and
/// decides in its place ([`SensorValidation::proven`]); otherwise, or when that proof does not
/// succeed, on the grid ([`XiFamily::validate_grid`]), which then decides and finds the worst
/// point (50) — except that a grid of more than [`REFUTED_POINT_FROM`] points on which the
/// proof has refuted (48) fails at the refuted point as below, without being run. `family` is
/// that of `p` and the sensor of `grid`.
///
/// A grid above the cap ([`WindowGrid::OverCap`]) is never run. Its window is first screened
/// in floating point at [`SCREEN_POINTS`] τ (half uniform, half geometric; fresh exponentials,
/// as [`XiFamily::min_eigenvalue`]): at its point of least `λ_min(Ξ_σ(τ))/‖Ξ_σ(τ)‖_F`, when
/// negative, `Ξ_σ(τ)` is evaluated in interval arithmetic, and if it is shown not positive
/// definite there (a rigorous disproof: a floating-point `λ_min` below zero by no more than its
/// rounding is not) the validation fails at that `τ` at once, before any proof: one failing
/// point, `points` the screen's, `min_eigenvalue` the floating-point `λ_min(Ξ_σ(τ))`. Otherwise
/// the proof (same piece budget) decides alone. When it shows that (48) fails at an end `τ` of
/// a piece (a rigorous disproof), the validation fails there: one failing point, `points` 0, `min_eigenvalue` the
/// floating-point `λ_min(Ξ_σ(τ))` at that `τ` (not the minimum over the window) and `argmin_tau`
/// that `τ`. Otherwise (no proof attempted, or one that ran out of pieces or time, stopped where
/// its interval evaluation no longer resolves (48), or could not be set up) the validation is
/// undecided: [`Error::GridTooLarge`], whose message says how the proof ended (and whose
/// `unresolved` flag marks the resolution limit, a numerical failure rather than a budget).
///
/// # Errors
/// As [`XiFamily::validate_grid`], and [`Error::GridTooLarge`] (sensor 1-based) for a grid above
/// the cap that the proof does not decide.
pub fn validate_window(
    family: &XiFamily,
    plant: &RoundRobinPlant,
    p: &[Mat<f64>],
    grid: WindowGrid,
    mu: f64,
    proof_pieces: Option<usize>,
    settings: &ValidationOptions,
) -> Result<SensorValidation, Error> {
    // Saturating: a grid above the cap may have more points than a usize holds.
    let per_piece = (grid.points() / PROOF_POINTS_PER_PIECE as f64).floor();
    let budget = proof_pieces.map_or(0, |k| {
        if per_piece >= k as f64 {
            k
        } else {
            per_piece as usize
        }
    });
    if let WindowGrid::OverCap { spacing, .. } = grid
        && let Some(v) = screen_window(family, plant, p, spacing, mu)?
    {
        return Ok(v);
    }
    // A proof that cannot be attempted (a failing interval kernel) leaves the decision to the
    // grid, like one that does not succeed.
    let proof =
        (budget >= MIN_PROOF_PIECES).then(|| prove_validation(plant, p, family.sigma, mu, budget));
    if let Some(Ok(w)) = &proof
        && w.status == ProofStatus::Proved
    {
        return Ok(SensorValidation::proven(
            family.sigma,
            mu,
            grid.spacing(),
            w.pieces,
        ));
    }
    // A rigorous disproof: (48) fails at an end of the piece, the one with the smaller λ_min.
    let refuted = |piece: &sporadic_model::ProofPiece| -> Result<SensorValidation, Error> {
        let [a, b] = piece.tau;
        let (la, lb) = (family.min_eigenvalue(a)?, family.min_eigenvalue(b)?);
        let (lambda, tau) = if lb < la { (lb, b) } else { (la, a) };
        Ok(SensorValidation {
            sigma: family.sigma,
            mu,
            points: 0,
            spacing: grid.spacing(),
            failures: 1,
            min_eigenvalue: lambda,
            argmin_tau: tau,
            min_is_exact: false,
            eigen_evaluations: 2,
            proof_pieces: None,
        })
    };
    let refuted_piece = match &proof {
        Some(Ok(w)) if w.status == ProofStatus::NotProved => w.failed_on.as_ref(),
        _ => None,
    };
    match grid {
        WindowGrid::Grid(g) => match refuted_piece {
            Some(piece) if g.points > REFUTED_POINT_FROM => refuted(piece),
            _ => family.validate_grid(g, mu, settings),
        },
        WindowGrid::OverCap { points, cap, .. } => {
            if let Some(piece) = refuted_piece {
                return refuted(piece);
            }
            // A grid of infinitely many points ((49) underflowed) is beyond every cap: no budget
            // decides the window, as when the proof stops at its resolution.
            let unresolved = points.is_infinite()
                || matches!(
                    &proof,
                    Some(Ok(w)) if w.stop == Some(ProofStop::Resolution)
                );
            let proof = match proof {
                None => String::new(),
                Some(Err(e)) => format!(
                    "; the proof of (48) over the window in its place could not be set up ({e})"
                ),
                Some(Ok(w)) => format!(
                    "; the proof of (48) over the window in its place (at most {budget} \
                     pieces) ended {}: {}",
                    w.status.as_str(),
                    w.message
                ),
            };
            Err(Error::GridTooLarge {
                sigma: family.sigma + 1,
                points,
                cap,
                proof,
                unresolved,
            })
        }
    }
}

/// Reference implementation for benchmarks and tests: one fresh exponential and one full symmetric
/// eigenvalue decomposition of `Ξ_σ(τ)` per grid point. Returns `(failures, min λ, argmin τ)`.
///
/// # Errors
/// A failing kernel.
pub fn validate_naive(
    family: &XiFamily,
    grid: UniformGrid,
    mu: f64,
) -> Result<(u64, f64, f64), Error> {
    let mut failures = 0;
    let mut best: Option<(f64, f64)> = None;
    for k in 0..grid.points {
        let tau = grid.tau(k);
        let l = family.min_eigenvalue(tau)?;
        if l <= mu {
            failures += 1;
        }
        best = better(best, Some((l, tau)));
    }
    let (l, t) = best.ok_or_else(|| Error::invalid("empty grid"))?;
    Ok((failures, l, t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::test_util::{rr, win};
    use faer::mat;

    fn plant() -> RoundRobinPlant {
        let a = mat![[0.0, 1.0, 0.0], [-2.0, -0.3, 1.0], [0.5, 0.0, -1.0]];
        rr(
            a,
            vec![
                (mat![[1.0, 0.0, 0.0]], win(0.1, 0.9)),
                (mat![[0.0, 0.0, 1.0]], win(0.2, 0.6)),
            ],
        )
        .unwrap()
    }

    fn ps() -> Vec<Mat<f64>> {
        vec![
            mat![[3.0, 0.5, 0.1], [0.5, 2.0, -0.3], [0.1, -0.3, 1.5]],
            mat![[2.0, -0.2, 0.0], [-0.2, 1.0, 0.4], [0.0, 0.4, 2.5]],
        ]
    }

    /// The fast two-pass validation gives exactly the naive per-point answer (failure count, minimum and
    /// minimiser), for levels that make many, few or no points fail, in parallel and sequentially.
    #[test]
    fn matches_naive_scan() {
        let plant = plant();
        let p = ps();
        for sigma in 0..2 {
            let fam = XiFamily::new(&plant, &p, sigma).unwrap();
            let grid =
                UniformGrid::covering(plant.sensor(sigma).unwrap().window(), 1e-3, 1e9).unwrap();
            let (_, lmin, _) = validate_naive(&fam, grid, 0.0).unwrap();
            for &mu in &[lmin - 0.1, lmin + 1e-4, lmin + 0.05, lmin + 0.5, 10.0] {
                let (nf, l, t) = validate_naive(&fam, grid, mu).unwrap();
                for parallel in [true, false] {
                    let s = ValidationOptions {
                        chunk_points: 37,
                        sample_stride: 5,
                        parallel,
                        ..Default::default()
                    };
                    let v = fam.validate_grid(grid, mu, &s).unwrap();
                    assert_eq!(v.failures, nf, "σ = {sigma}, μ = {mu}");
                    assert_eq!(v.points, grid.points);
                    if nf > 0 {
                        assert!(v.min_is_exact);
                        assert!(
                            (v.min_eigenvalue - l).abs() < 1e-11,
                            "{} vs {l}",
                            v.min_eigenvalue
                        );
                        assert!((v.argmin_tau - t).abs() < 1e-12, "{} vs {t}", v.argmin_tau);
                        assert!(
                            v.eigen_evaluations < grid.points as u64 / 3 + 40,
                            "{}",
                            v.eigen_evaluations
                        );
                    } else {
                        assert!(v.passed() && !v.min_is_exact && v.min_eigenvalue > mu);
                    }
                }
            }
        }
    }

    /// Explicit points use fresh exponentials: same verdict as the grid on the same τ.
    #[test]
    fn explicit_points_match_grid() {
        let plant = plant();
        let fam = XiFamily::new(&plant, &ps(), 0).unwrap();
        let grid = UniformGrid::covering(plant.sensor(0).unwrap().window(), 1e-2, 1e9).unwrap();
        let taus: Vec<f64> = (0..grid.points).map(|k| grid.tau(k)).collect();
        let (_, lmin, _) = validate_naive(&fam, grid, 0.0).unwrap();
        let s = ValidationOptions::default();
        let a = fam.validate_grid(grid, lmin + 0.02, &s).unwrap();
        let b = fam.validate_points(&taus, lmin + 0.02, &s).unwrap();
        assert_eq!(a.failures, b.failures);
        assert!((a.min_eigenvalue - b.min_eigenvalue).abs() < 1e-12);
        assert!(a.failures > 0);
    }

    /// A P_Γ with λ_min(P_Γ) ≤ μ makes every point fail (principal block), and the minimum is still exact:
    /// with coupling (the re-test runs at a level below λ_min(P_Γ)) and without (Ξ_σ(τ) has the constant
    /// eigenvalue λ_min(P_Γ): every point ties up to rounding, only the value is compared).
    #[test]
    fn degenerate_level_every_point_fails() {
        let plant = plant();
        for (coupled, p_next) in [
            (
                true,
                mat![[0.08, 0.2, 0.0], [0.2, 1.0, 0.0], [0.0, 0.0, 1.0]],
            ),
            (
                false,
                mat![[0.05, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            ),
        ] {
            let mut p = ps();
            p[1] = p_next;
            let fam = XiFamily::new(&plant, &p, 0).unwrap();
            let grid = UniformGrid::covering(plant.sensor(0).unwrap().window(), 2e-2, 1e9).unwrap();
            let (nf, l, t) = validate_naive(&fam, grid, 0.1).unwrap();
            let s = ValidationOptions {
                chunk_points: 7,
                sample_stride: 3,
                ..Default::default()
            };
            let v = fam.validate_grid(grid, 0.1, &s).unwrap();
            assert_eq!(nf as usize, grid.points);
            assert_eq!(v.failures, nf);
            assert!((v.min_eigenvalue - l).abs() < 1e-12, "{v:?} vs {l} at {t}");
            if coupled {
                assert!((v.argmin_tau - t).abs() < 1e-12, "{v:?} vs {l} at {t}");
            }
        }
    }

    #[test]
    fn grids_and_spacings() {
        let g = UniformGrid::covering(win(0.02, 0.07), 0.01, 1e9).unwrap();
        assert_eq!(g.points, 6);
        assert!((g.tau(5) - 0.07).abs() < 1e-15);
        let g = UniformGrid::covering(win(0.02, 0.07), 0.011, 1e9).unwrap();
        assert_eq!(g.points, 6);
        assert!(g.spacing <= 0.011);
        let g = UniformGrid::covering(win(0.05, 0.05), 0.01, 1e9).unwrap();
        assert_eq!((g.points, g.spacing), (1, 0.0));
        assert!(matches!(
            UniformGrid::covering(win(1e-3, 1.0), 1e-9, 1e6),
            Err(Error::GridTooLarge { .. })
        ));
        assert!(UniformGrid::covering(win(1e-3, 1.0), 0.0, 1e6).is_err());
        // (49) by hand: 2μ / (p ‖A‖ γ e^{βT_M}) with ‖diag(2, −3)‖ = 3.
        let plant = rr(
            mat![[2.0, 0.0], [0.0, -3.0]],
            vec![(mat![[1.0, 0.0]], win(0.1, 0.5))],
        )
        .unwrap();
        let b = ExponentialBound {
            beta: 3.5,
            gamma: 2.0,
        };
        let s = grid_spacing(&plant, 0, GridPolicy::Paper, 0.01, 10.0, &b).unwrap();
        let expect = 0.02 / (10.0 * 3.0 * 2.0 * (3.5f64 * 0.5).exp());
        assert!((s / expect - 1.0).abs() < 1e-14);
        let s = grid_spacing(&plant, 0, GridPolicy::Rigorous, 0.01, 10.0, &b).unwrap();
        let g = 2.0 * (3.5f64 * 0.5).exp();
        assert!((s / (0.02 / (2.0 * 10.0 * 3.0 * g * g)) - 1.0).abs() < 1e-14);
        assert_eq!(
            grid_spacing(&plant, 0, GridPolicy::Spacing(1e-3), 0.01, 10.0, &b).unwrap(),
            1e-3
        );
        assert!(grid_spacing(&plant, 0, GridPolicy::Paper, -1.0, 10.0, &b).is_err());
    }

    /// A window whose grid is above the cap is decided without it: where `Ξ_σ(τ)` is not positive
    /// definite somewhere, by the screen (its points, a τ where `λ_min < 0`); where it is
    /// positive definite but `λ_min` dips below μ, the screen decides nothing and the proof of
    /// (48) disproves it at a piece end (no points, `λ_min ≤ μ` there).
    #[test]
    fn window_above_the_cap_is_decided_by_the_screen_or_the_proof() {
        let over = WindowGrid::OverCap {
            spacing: 1e-12,
            points: 1e12,
            cap: 1e9,
        };
        let s = ValidationOptions::default();
        let stable = rr(
            mat![[-1.0, 0.2, 0.0], [0.0, -2.0, 0.5], [0.0, 0.0, -0.5]],
            vec![(mat![[1.0, 0.0, 0.0]], win(0.1, 0.5))],
        )
        .unwrap();
        let (two, p_two, p_stable) = (plant(), ps(), vec![Mat::identity(3, 3)]);
        let (mut screened, mut disproved) = (0, 0);
        for (plant, p) in [(&two, &p_two), (&stable, &p_stable)] {
            for sigma in 0..plant.num_sensors() {
                let fam = XiFamily::new(plant, p, sigma).unwrap();
                let w = plant.sensor(sigma).unwrap().window();
                let grid = UniformGrid::covering(w, 1e-4, 1e9).unwrap();
                let (_, lmin, _) = validate_naive(&fam, grid, 0.0).unwrap();
                let mu = if lmin < 0.0 { 0.01 } else { lmin + 0.1 };
                println!("σ = {sigma}: min λ_min {lmin}, μ = {mu}");
                let v = validate_window(&fam, plant, p, over, mu, Some(4096), &s).unwrap();
                assert!(!v.passed() && v.failures == 1, "{v:?}");
                // The same floating-point evaluation at the reported τ.
                let at = fam.min_eigenvalue(v.argmin_tau).unwrap();
                assert_eq!(at, v.min_eigenvalue, "{v:?}");
                if lmin < 0.0 {
                    assert_eq!(v.points, SCREEN_POINTS, "{v:?}");
                    assert!(at < 0.0, "{v:?}");
                    screened += 1;
                } else {
                    assert_eq!(v.points, 0, "{v:?}");
                    assert!(at <= mu, "{v:?}");
                    disproved += 1;
                }
            }
        }
        assert!(screened > 0 && disproved > 0, "{screened}, {disproved}");
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(16))]
        /// The fast validation (stepper, Schur complement + Cholesky pass/fail, eigenvalues only at
        /// candidate minimisers, parallel chunks) gives the naive per-point answer on random plants,
        /// Lyapunov matrices and levels: same failure count, and the same minimum and minimiser
        /// whenever some point fails.
        #[test]
        fn fast_validation_equals_naive(
            n in 2usize..5,
            av in proptest::collection::vec(-2.0f64..2.0, 16),
            gv in proptest::collection::vec(-1.0f64..1.0, 32),
            t_min in 0.05f64..0.3,
            width in 0.05f64..0.5,
            level in 0.0f64..1.0,
            chunk in 5usize..60,
        ) {
            let a = Mat::from_fn(n, n, |i, j| av[i * n + j]);
            let c = Mat::from_fn(1, n, |_, j| if j == 0 { 1.0 } else { 0.3 * av[j] });
            let plant =
                rr(a, vec![(c, win(t_min, t_min + width))]).unwrap();
            let spd = |off: usize| {
                let g = Mat::from_fn(n, n, |i, j| gv[off + i * n + j]);
                &g * g.transpose() + Mat::<f64>::identity(n, n) * 0.2
            };
            let p = vec![spd(0)];
            let fam = XiFamily::new(&plant, &p, 0).unwrap();
            let grid = UniformGrid::covering(plant.sensor(0).unwrap().window(), width / 300.0, 1e9).unwrap();
            let (_, lmin, _) = validate_naive(&fam, grid, 0.0).unwrap();
            // Levels from "every point fails" to "no point fails".
            let mu = lmin + level * (max_on_grid(&fam, grid) - lmin) * 1.2 - 1e-3;
            let (nf, l, t) = validate_naive(&fam, grid, mu).unwrap();
            let s = ValidationOptions { chunk_points: chunk, sample_stride: 3, ..Default::default() };
            let v = fam.validate_grid(grid, mu, &s).unwrap();
            proptest::prop_assert_eq!(v.failures, nf);
            if nf > 0 {
                proptest::prop_assert!((v.min_eigenvalue - l).abs() <= 1e-10 * l.abs().max(1.0));
                // Ties (up to rounding) may pick another minimiser; it must be optimal to rounding.
                let at = fam.min_eigenvalue(v.argmin_tau).unwrap();
                proptest::prop_assert!(
                    (v.argmin_tau - t).abs() <= 1e-12 || (at - l).abs() <= 1e-10 * l.abs().max(1.0)
                );
            } else {
                proptest::prop_assert!(v.min_eigenvalue > mu);
            }
        }
    }

    fn max_on_grid(fam: &XiFamily, grid: UniformGrid) -> f64 {
        (0..grid.points)
            .map(|k| fam.min_eigenvalue(grid.tau(k)).unwrap())
            .fold(f64::NEG_INFINITY, f64::max)
    }
}
