//! Helpers shared by the integration tests: deterministic random matrices with prescribed
//! spectral structure, and an independent hull-membership check by linear programming with
//! `sporadic-sdp`'s LP block.

#![allow(dead_code)]

use faer::Mat;
use faer::linalg::solvers::DenseSolveCore;
use sporadic_sdp::{BlockKind, ProblemBuilder, Settings, solve};

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
#[derive(Debug, Clone, Copy)]
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

/// Barycentric weights for `E` from the linear program `min Σ(s⁺ + s⁻)` subject to
/// `Σ μ_i X_i + s⁺ − s⁻ = E`, `Σ μ_i = 1`, `μ, s⁺, s⁻ ≥ 0`, solved with the LP block of
/// `sporadic-sdp`. Returns the ℓ1 residual `Σ|Σ μ_i X_i − E|` of the solver's weights after
/// clipping them to the simplex — a certificate that does not trust the solver's own accuracy
/// claims (any status is accepted; only an error aborts).
pub fn lp_l1_distance(vertices: &[Mat<f64>], e: &Mat<f64>) -> f64 {
    let (r, c) = (e.nrows(), e.ncols());
    let nu = vertices.len();
    let d = r * c;
    let m = d + 1;
    let mut pb = ProblemBuilder::new(m);
    let blk = pb.add_block(BlockKind::Lp, nu + 2 * d);
    for j in 0..c {
        for i in 0..r {
            let row = i + r * j;
            for (k, x) in vertices.iter().enumerate() {
                pb.add_a(row, blk, k, k, x[(i, j)]);
            }
            pb.add_a(row, blk, nu + row, nu + row, 1.0);
            pb.add_a(row, blk, nu + d + row, nu + d + row, -1.0);
            pb.set_b(row, e[(i, j)]);
        }
    }
    for k in 0..nu {
        pb.add_a(d, blk, k, k, 1.0);
    }
    pb.set_b(d, 1.0);
    for k in nu..nu + 2 * d {
        pb.add_c(blk, k, k, 1.0);
    }
    let problem = pb.build().expect("valid LP");
    let settings = Settings {
        tol_gap: 1e-10,
        tol_feas: 1e-10,
        ..Settings::default()
    };
    let sol = solve(&problem, &settings).expect("LP solve");
    let x = &sol.x[0];
    let mu: Vec<f64> = (0..nu).map(|k| x[(k, 0)]).collect();
    l1_residual(vertices, e, &mu)
}

/// `Σ|Σ μ̂_i X_i − E|` for the weights clipped to `μ ≥ 0` and normalised to `Σ μ = 1`.
fn l1_residual(vertices: &[Mat<f64>], e: &Mat<f64>, mu: &[f64]) -> f64 {
    let clipped: Vec<f64> = mu.iter().map(|w| w.max(0.0)).collect();
    let total: f64 = clipped.iter().sum();
    assert!(total > 0.0, "no nonnegative weights");
    let mut residual = 0.0;
    for j in 0..e.ncols() {
        for i in 0..e.nrows() {
            let v: f64 = clipped
                .iter()
                .zip(vertices)
                .map(|(w, x)| w / total * x[(i, j)])
                .sum();
            residual += (v - e[(i, j)]).abs();
        }
    }
    residual
}
