//! Helpers shared by the integration tests: deterministic random matrices with prescribed
//! spectral structure, and an independent hull-membership check by linear programming with
//! `sporadic-sdp`'s LP block.

#![allow(dead_code)]

use faer::Mat;
use faer::linalg::solvers::DenseSolveCore;
use sporadic_sdp::{BlockKind, Problem, ProblemBuilder, Settings, Status, solve};

/// SplitMix64: a tiny deterministic generator (the tests take their seeds from proptest).
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// Spectral structure of a random test matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Dense random entries (generically distinct real and complex eigenvalues).
    Generic,
    /// Complex pairs (rotation blocks) under a similarity.
    Complex,
    /// Repeated but diagonalizable eigenvalues under a similarity.
    RepeatedDiagonalizable,
    /// Real Jordan blocks (defective eigenvalues) under a similarity.
    Defective,
    /// A defective complex pair (real Jordan form [[C, I], [0, C]]) plus real Jordan blocks.
    DefectiveComplex,
    /// Nearly repeated real eigenvalues (gaps 1e-7 … 1e-2) in an upper-triangular coupling.
    Clustered,
}

pub const KINDS: [Kind; 6] = [
    Kind::Generic,
    Kind::Complex,
    Kind::RepeatedDiagonalizable,
    Kind::Defective,
    Kind::DefectiveComplex,
    Kind::Clustered,
];

fn similarity(rng: &mut Rng, d: &Mat<f64>) -> Mat<f64> {
    let n = d.nrows();
    let s = Mat::from_fn(n, n, |i, j| {
        (if i == j { 1.0 } else { 0.0 }) + rng.uniform(-0.35, 0.35)
    });
    let inv = s.partial_piv_lu().inverse();
    &s * d * &inv
}

/// A random n×n matrix of the given kind (eigenvalue real parts in about [−2, 0.3]).
pub fn random_matrix(kind: Kind, n: usize, seed: u64) -> Mat<f64> {
    let mut rng = Rng(seed);
    let mut d = Mat::<f64>::zeros(n, n);
    match kind {
        Kind::Generic => {
            return Mat::from_fn(n, n, |_, _| rng.uniform(-1.5, 1.5));
        }
        Kind::Complex => {
            let mut i = 0;
            while i < n {
                let a = rng.uniform(-2.0, 0.3);
                if i + 1 < n {
                    let b = rng.uniform(0.2, 4.0);
                    d[(i, i)] = a;
                    d[(i + 1, i + 1)] = a;
                    d[(i, i + 1)] = b;
                    d[(i + 1, i)] = -b;
                    i += 2;
                } else {
                    d[(i, i)] = a;
                    i += 1;
                }
            }
        }
        Kind::RepeatedDiagonalizable => {
            let values = [rng.uniform(-2.0, 0.3), rng.uniform(-2.0, 0.3)];
            for i in 0..n {
                d[(i, i)] = values[usize::from(i % 3 == 2)];
            }
        }
        Kind::Clustered => {
            let base = rng.uniform(-2.0, 0.3);
            let gap = 10f64.powf(rng.uniform(-7.0, -2.0));
            for i in 0..n {
                d[(i, i)] = base + gap * i as f64;
                for j in i + 1..n {
                    d[(i, j)] = rng.uniform(-1.0, 1.0);
                }
            }
        }
        Kind::Defective | Kind::DefectiveComplex => {
            let mut i = 0;
            if matches!(kind, Kind::DefectiveComplex) && n >= 4 {
                let (a, b) = (rng.uniform(-1.5, 0.2), rng.uniform(0.5, 3.0));
                for k in [0, 2] {
                    d[(k, k)] = a;
                    d[(k + 1, k + 1)] = a;
                    d[(k, k + 1)] = b;
                    d[(k + 1, k)] = -b;
                }
                d[(0, 2)] = 1.0;
                d[(1, 3)] = 1.0;
                i = 4;
            }
            while i < n {
                let size = (1 + rng.below(3)).min(n - i);
                let lambda = rng.uniform(-2.0, 0.3);
                for k in i..i + size {
                    d[(k, k)] = lambda;
                    if k + 1 < i + size {
                        d[(k, k + 1)] = rng.uniform(0.5, 1.5);
                    }
                }
                i += size;
            }
        }
    }
    similarity(&mut rng, &d)
}

/// Outcome of [`lp_hull_membership`]: barycentric weights for `E` found by linear programming,
/// and how well they reproduce `E`.
#[derive(Debug, Clone)]
pub struct LpMembership {
    /// Status of the interior-point solve.
    pub status: Status,
    /// Interior-point iterations.
    pub iterations: usize,
    /// The solver's relative primal infeasibility `‖𝒜(x) − b‖₂ / (1 + ‖b‖₂)`.
    pub primal_infeas: f64,
    /// `‖Σ μ_i X_i − E‖_F` for the solver's weights (clipped to `μ ≥ 0`, normalised to `Σμ = 1`).
    pub solver_residual: f64,
    /// `‖Σ μ_i X_i − E‖_F` for the final weights [`Self::weights`] (the better of the solver's and the purified ones).
    pub residual: f64,
    /// `max(‖E‖_F, max_i ‖X_i‖_F)`, the scale of relative distances.
    pub scale: f64,
    /// Final weights: `μ ≥ 0`, `Σ μ = 1` (exactly up to rounding).
    pub weights: Vec<f64>,
}

impl LpMembership {
    /// `max(0, residual − allowance) / scale`: the relative violation certified by the weights.
    pub fn violation(&self, allowance: f64) -> f64 {
        (self.residual - allowance).max(0.0) / self.scale
    }
}

/// The linear program `min Σ(s⁺ + s⁻)` subject to `Qᵀ(Σ μ_i (X_i − X̄) − (E − X̄)) + s⁺ − s⁻ = 0`,
/// `Σ μ_i = 1`, `μ, s⁺, s⁻ ≥ 0`, as one LP block of `sporadic-sdp` (data divided by `scale`).
///
/// `X̄` is the mean vertex and `Q` the left singular vectors of the centred vertices
/// `X_i − X̄` (directions with singular value `≤ 1e-14 σ_max` dropped). In these coordinates
/// the constraint rows are mutually orthogonal and orthogonal to the row `Σμ = 1`; with the
/// raw `n²` entries as rows, the solver ended in `NumericalTrouble` (relative residual up to
/// `1e-6`) on a few per cent of the property-test instances, whose vertex sets are flat.
/// With `whiten`, each row is also divided by its singular value `σ_k`, which changes the
/// LP's objective but not its zero set. Neither form suffices alone: on a cloud of 286 Taylor
/// vertices of affine rank 6 (singular values over 3.3 orders of magnitude) the plain rows
/// stopped at a gap of `6.6e-7` (`AlmostOptimal`, relative violation `8.6e-9`; CSDP needs 39
/// iterations there) while the whitened ones give `Optimal` with residual `1e-15`; where the
/// target lies off the span by rounding along directions of tiny `σ_k`, whitening magnifies
/// that and the plain rows are the ones that succeed.
/// The part of `E − X̄` outside the span cannot be reached by any weights and simply stays in
/// the residual that [`lp_hull_membership`] recomputes.
pub fn hull_lp(vertices: &[Mat<f64>], e: &Mat<f64>, scale: f64, whiten: bool) -> Problem {
    let nu = vertices.len();
    let points: Vec<Vec<f64>> = vertices.iter().map(|x| vectorise(x, scale)).collect();
    let target = vectorise(e, scale);
    let d = target.len();
    let mean: Vec<f64> = (0..d)
        .map(|i| points.iter().map(|p| p[i]).sum::<f64>() / nu as f64)
        .collect();
    let centred = Mat::<f64>::from_fn(d, nu, |i, k| points[k][i] - mean[i]);
    let svd = centred.thin_svd().expect("SVD of the vertex cloud");
    let (u, sigma) = (svd.U(), svd.S());
    let smax = (0..sigma.dim()).map(|k| sigma[k]).fold(0.0, f64::max);
    let basis: Vec<usize> = (0..sigma.dim())
        .filter(|&k| sigma[k] > 1e-14 * smax)
        .collect();
    let r = basis.len();
    let row_scale = |k: usize| if whiten { sigma[k] } else { 1.0 };
    let coord = |v: &[f64], k: usize| {
        (0..d).map(|i| u[(i, k)] * (v[i] - mean[i])).sum::<f64>() / row_scale(k)
    };
    let mut pb = ProblemBuilder::new(r + 1);
    let blk = pb.add_block(BlockKind::Lp, nu + 2 * r);
    for (row, &k) in basis.iter().enumerate() {
        for (j, p) in points.iter().enumerate() {
            pb.add_a(row, blk, j, j, coord(p, k));
        }
        pb.add_a(row, blk, nu + row, nu + row, 1.0);
        pb.add_a(row, blk, nu + r + row, nu + r + row, -1.0);
        pb.set_b(row, coord(&target, k));
    }
    for j in 0..nu {
        pb.add_a(r, blk, j, j, 1.0);
    }
    pb.set_b(r, 1.0);
    for j in nu..nu + 2 * r {
        pb.add_c(blk, j, j, 1.0);
    }
    pb.build().expect("valid LP")
}

/// Independent hull-membership test for `E` against `co{X_i}`: barycentric weights from the
/// LP [`hull_lp`] solved by `sporadic-sdp`'s interior-point method, then purified; the LP is
/// solved in both its plain and its whitened form.
///
/// The solver's weights are clipped to `μ ≥ 0` and normalised to `Σμ = 1`. An interior-point
/// method stops at a relative primal infeasibility of about the requested `1e-10`, but a
/// `1e-9` certificate must hold after un-scaling on flat vertex sets; so, as LP codes do after
/// an interior-point solve, the weights are then purified ([`purify`]). All four candidates
/// are judged only by `‖Σ μ_i X_i − E‖_F`, recomputed from the data, and the better one is
/// returned: the result does not trust the solver's accuracy claims. Any solver status is
/// accepted (it is reported); a solver error panics.
pub fn lp_hull_membership(vertices: &[Mat<f64>], e: &Mat<f64>) -> LpMembership {
    let scale = vertices
        .iter()
        .map(|x| x.norm_l2())
        .fold(e.norm_l2(), f64::max);
    assert!(scale > 0.0, "all-zero hull problem");
    let points: Vec<Vec<f64>> = vertices.iter().map(|x| vectorise(x, scale)).collect();
    let target = vectorise(e, scale);
    let settings = Settings {
        tol_gap: 1e-10,
        tol_feas: 1e-10,
        ..Settings::default()
    };
    let certificate = |whiten: bool| {
        let sol = solve(&hull_lp(vertices, e, scale, whiten), &settings).expect("LP solve");
        let mut mu: Vec<f64> = (0..vertices.len()).map(|k| sol.x[0][(k, 0)]).collect();
        normalise(&mut mu);
        let solver_residual = residual(&points, &target, &mu) * scale;
        let mut purified = mu.clone();
        purify(&points, &target, &mut purified);
        let purified_residual = residual(&points, &target, &purified) * scale;
        let (residual, weights) = if purified_residual < solver_residual {
            (purified_residual, purified)
        } else {
            (solver_residual, mu)
        };
        LpMembership {
            status: sol.status,
            iterations: sol.iterations,
            primal_infeas: sol.measures.primal_infeas,
            solver_residual,
            residual,
            scale,
            weights,
        }
    };
    let plain = certificate(false);
    let whitened = certificate(true);
    if whitened.residual < plain.residual {
        whitened
    } else {
        plain
    }
}

/// Column-major entries of `x / scale`.
fn vectorise(x: &Mat<f64>, scale: f64) -> Vec<f64> {
    let mut v = Vec::with_capacity(x.nrows() * x.ncols());
    for j in 0..x.ncols() {
        for i in 0..x.nrows() {
            v.push(x[(i, j)] / scale);
        }
    }
    v
}

/// Clips to `μ ≥ 0` and rescales to `Σ μ = 1`.
fn normalise(mu: &mut [f64]) {
    mu.iter_mut().for_each(|w| *w = w.max(0.0));
    let total: f64 = mu.iter().sum();
    assert!(total > 0.0, "no positive weight");
    mu.iter_mut().for_each(|w| *w /= total);
}

/// `E − Σ μ_i X_i` (vectorised).
fn residual_vector(points: &[Vec<f64>], target: &[f64], mu: &[f64]) -> Vec<f64> {
    let mut r = target.to_vec();
    for (w, p) in mu.iter().zip(points) {
        if *w != 0.0 {
            r.iter_mut().zip(p).for_each(|(ri, pi)| *ri -= w * pi);
        }
    }
    r
}

/// `‖E − Σ μ_i X_i‖` (vectorised data).
fn residual(points: &[Vec<f64>], target: &[f64], mu: &[f64]) -> f64 {
    residual_vector(points, target, mu)
        .iter()
        .map(|x| x * x)
        .sum::<f64>()
        .sqrt()
}

/// Purification of interior-point weights: weights at the barrier level (`≤ 1e-8 max μ`) are
/// set to zero; then, on the support, Newton steps for `[X; 1ᵀ] μ = [E; 1]` — the
/// minimum-norm correction of the residual by an SVD pseudo-inverse — each with the largest
/// step `≤ 1` that keeps `μ ≥ 0`. A weight that reaches zero leaves the support; a full step
/// ends the purification.
fn purify(points: &[Vec<f64>], target: &[f64], mu: &mut [f64]) {
    let top = mu.iter().copied().fold(0.0, f64::max);
    for w in mu.iter_mut() {
        if *w <= 1e-8 * top {
            *w = 0.0;
        }
    }
    normalise(mu);
    let d = target.len();
    for _ in 0..mu.len() {
        let support: Vec<usize> = (0..mu.len()).filter(|&i| mu[i] > 0.0).collect();
        let r = residual_vector(points, target, mu);
        let m = Mat::<f64>::from_fn(d + 1, support.len(), |row, k| {
            if row < d {
                points[support[k]][row]
            } else {
                1.0
            }
        });
        let Ok(svd) = m.thin_svd() else { return };
        let (u, s, v) = (svd.U(), svd.S(), svd.V());
        let smax = (0..s.dim()).map(|k| s[k]).fold(0.0, f64::max);
        let mut delta = vec![0.0; support.len()];
        for k in 0..s.dim() {
            if s[k] <= 1e-13 * smax {
                continue;
            }
            let coef = (0..d).map(|row| u[(row, k)] * r[row]).sum::<f64>() / s[k];
            for (i, di) in delta.iter_mut().enumerate() {
                *di += coef * v[(i, k)];
            }
        }
        let mut step = 1.0f64;
        let mut blocking = None;
        for (&i, &di) in support.iter().zip(&delta) {
            if di < 0.0 && -mu[i] / di < step {
                step = -mu[i] / di;
                blocking = Some(i);
            }
        }
        for (&i, &di) in support.iter().zip(&delta) {
            mu[i] += step * di;
        }
        match blocking {
            Some(i) if support.len() > 1 => mu[i] = 0.0,
            _ => {
                normalise(mu);
                return;
            }
        }
        normalise(mu);
    }
}
