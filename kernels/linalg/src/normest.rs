//! Block 1-norm estimation: Higham & Tisseur (2000), *A block algorithm for matrix 1-norm
//! estimation, with an application to 1-norm pseudospectra*, SIAM J. Matrix Anal. Appl.
//! 21(4):1185–1201, Algorithm 2.4.
//!
//! Used by [`crate::expm`] for orders n ≥ [`crate::expm::EXACT_NORM_MAX_ORDER`] to estimate
//! ‖A^k‖₁ (k = 4, 6, 8, 10) of Al-Mohy & Higham (2009), Algorithm 6.1, as the 1-norm of a
//! product of already-formed powers, at O(n²) cost per iteration instead of forming A^k.
//! The estimate is a lower bound, almost always within a factor 3 and usually exact.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};

/// Number of columns t of the iteration matrix (the value used by Algorithm 6.1).
pub(crate) const BLOCK_COLUMNS: usize = 2;
/// Maximum number of iterations (`itmax` of Algorithm 2.4; 5 as in the expm references).
pub(crate) const MAX_ITERATIONS: usize = 5;

/// Deterministic SplitMix64 generator for the random ±1 columns, so results are reproducible.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_sign(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        if z >> 63 == 0 { 1.0 } else { -1.0 }
    }
}

/// Reusable buffers of Algorithm 2.4 for a fixed order n (t = [`BLOCK_COLUMNS`]).
pub(crate) struct Normest {
    n: usize,
    x: Mat<f64>,
    y: Mat<f64>,
    s: Mat<f64>,
    s_old: Mat<f64>,
    tmp: [Mat<f64>; 2],
    h: Vec<f64>,
    order: Vec<usize>,
    visited: Vec<bool>,
    ind: [usize; BLOCK_COLUMNS],
}

impl Normest {
    /// Buffers for order `n` (requires n > [`BLOCK_COLUMNS`]).
    pub(crate) fn new(n: usize) -> Self {
        let t = BLOCK_COLUMNS;
        Self {
            n,
            x: Mat::zeros(n, t),
            y: Mat::zeros(n, t),
            s: Mat::zeros(n, t),
            s_old: Mat::zeros(n, t),
            tmp: [Mat::zeros(n, t), Mat::zeros(n, t)],
            h: vec![0.0; n],
            order: (0..n).collect(),
            visited: vec![false; n],
            ind: [0; BLOCK_COLUMNS],
        }
    }

    /// Y ← F₁F₂⋯F_k·X (or, with `transpose`, Y ← F_kᵀ⋯F₁ᵀ·X).
    fn apply(
        factors: &[&Mat<f64>],
        transpose: bool,
        x: MatRef<'_, f64>,
        y: MatMut<'_, f64>,
        tmp: &mut [Mat<f64>; 2],
    ) {
        let k = factors.len();
        let factor = |step: usize| {
            if transpose {
                factors[step].as_ref().transpose()
            } else {
                factors[k - 1 - step].as_ref()
            }
        };
        let mut y = y;
        if k == 1 {
            matmul(y.as_mut(), Accum::Replace, factor(0), x, 1.0, Par::Seq);
            return;
        }
        matmul(tmp[0].as_mut(), Accum::Replace, factor(0), x, 1.0, Par::Seq);
        for step in 1..k {
            let [t0, t1] = &mut *tmp;
            let (src, dst) = if step % 2 == 1 {
                (&*t0, t1)
            } else {
                (&*t1, t0)
            };
            if step + 1 == k {
                matmul(
                    y.as_mut(),
                    Accum::Replace,
                    factor(step),
                    src.as_ref(),
                    1.0,
                    Par::Seq,
                );
            } else {
                matmul(
                    dst.as_mut(),
                    Accum::Replace,
                    factor(step),
                    src.as_ref(),
                    1.0,
                    Par::Seq,
                );
            }
        }
    }

    /// Lower bound for ‖F₁F₂⋯F_k‖₁ (all factors n×n, k ≥ 1), Algorithm 2.4 with t = 2.
    pub(crate) fn estimate_product(&mut self, factors: &[&Mat<f64>]) -> f64 {
        let n = self.n;
        let t = BLOCK_COLUMNS;
        let mut rng = SplitMix64(0x5eed_1234_abcd_0001);
        // Starting matrix: first column 𝟙, the others random ±1 without parallel columns;
        // then columns of unit 1-norm.
        self.x.col_mut(0).fill(1.0);
        for j in 1..t {
            loop {
                for i in 0..n {
                    self.x[(i, j)] = rng.next_sign();
                }
                if !(0..j).any(|l| parallel(self.x.as_ref(), j, self.x.as_ref(), l)) {
                    break;
                }
            }
        }
        for j in 0..t {
            for i in 0..n {
                self.x[(i, j)] /= n as f64;
            }
        }
        self.visited.fill(false);
        self.s.fill(0.0);
        let mut est_old = 0.0f64;
        let mut ind_best = 0usize;
        let mut k = 1;
        loop {
            Self::apply(
                factors,
                false,
                self.x.as_ref(),
                self.y.as_mut(),
                &mut self.tmp,
            );
            let (mut est, mut best_j) = (0.0f64, 0usize);
            for j in 0..t {
                let c: f64 = self.y.col(j).iter().map(|v| v.abs()).sum();
                if c > est {
                    est = c;
                    best_j = j;
                }
            }
            if (est > est_old || k == 2) && k >= 2 {
                ind_best = self.ind[best_j];
            }
            // (1)
            if k >= 2 && est <= est_old {
                return est_old;
            }
            est_old = est;
            std::mem::swap(&mut self.s, &mut self.s_old);
            if k > MAX_ITERATIONS {
                return est;
            }
            for j in 0..t {
                for i in 0..n {
                    self.s[(i, j)] = if self.y[(i, j)] >= 0.0 { 1.0 } else { -1.0 };
                }
            }
            // (2) every column of S parallel to a column of S_old: converged.
            if (0..t).all(|j| (0..t).any(|l| parallel(self.s.as_ref(), j, self.s_old.as_ref(), l)))
            {
                return est;
            }
            // Resample columns parallel to an earlier column of S or to a column of S_old.
            for j in 0..t {
                while (0..j).any(|l| parallel(self.s.as_ref(), j, self.s.as_ref(), l))
                    || (0..t).any(|l| parallel(self.s.as_ref(), j, self.s_old.as_ref(), l))
                {
                    for i in 0..n {
                        self.s[(i, j)] = rng.next_sign();
                    }
                }
            }
            // (3) Z = Aᵀ S, h_i = ‖Z(i, :)‖∞ (Z is stored in y).
            Self::apply(
                factors,
                true,
                self.s.as_ref(),
                self.y.as_mut(),
                &mut self.tmp,
            );
            for i in 0..n {
                self.h[i] = (0..t).map(|j| self.y[(i, j)].abs()).fold(0.0, f64::max);
            }
            // (4)
            let h_max = self.h.iter().copied().fold(0.0, f64::max);
            if k >= 2 && h_max == self.h[ind_best] {
                return est;
            }
            for (i, o) in self.order.iter_mut().enumerate() {
                *o = i;
            }
            let h = &self.h;
            self.order.sort_by(|&p, &q| h[q].total_cmp(&h[p]));
            // (5) the t most promising unit vectors were all used before: stop.
            if self.order[..t].iter().all(|&i| self.visited[i]) {
                return est;
            }
            let visited = &self.visited;
            // Unvisited first, order by h preserved (stable sort).
            self.order.sort_by_key(|&i| visited[i]);
            for j in 0..t {
                let idx = self.order[j];
                self.ind[j] = idx;
                self.x.col_mut(j).fill(0.0);
                self.x[(idx, j)] = 1.0;
                self.visited[idx] = true;
            }
            k += 1;
        }
    }
}

/// Whether ±1 columns `a[:, j]` and `b[:, l]` are parallel (|aᵀb| = n).
fn parallel(a: MatRef<'_, f64>, j: usize, b: MatRef<'_, f64>, l: usize) -> bool {
    let dot: f64 = a
        .col(j)
        .iter()
        .zip(b.col(l).iter())
        .map(|(x, y)| x * y)
        .sum();
    dot.abs() == a.nrows() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact_norm1(m: &Mat<f64>) -> f64 {
        (0..m.ncols())
            .map(|j| m.col(j).iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max)
    }

    fn pseudo_random(n: usize, seed: u64) -> Mat<f64> {
        let mut g = SplitMix64(seed);
        let mut state = seed;
        Mat::from_fn(n, n, |_, _| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            g.next_sign() * ((state >> 11) as f64 / (1u64 << 53) as f64)
        })
    }

    #[test]
    fn lower_bound_within_factor_three_of_exact_norm() {
        let mut worst = 1.0f64;
        for (n, seed) in [(10, 1u64), (37, 2), (64, 3), (120, 4), (250, 5)] {
            let a = pseudo_random(n, seed);
            let b = pseudo_random(n, seed + 100);
            let mut est = Normest::new(n);
            for factors in [vec![&a], vec![&a, &b], vec![&a, &b, &a]] {
                let mut p = factors[0].clone();
                for f in &factors[1..] {
                    p = &p * *f;
                }
                let exact = exact_norm1(&p);
                let e = est.estimate_product(&factors);
                assert!(
                    e <= exact * (1.0 + 1e-12),
                    "n={n}: estimate {e} above exact {exact}"
                );
                assert!(
                    e >= exact / 3.0,
                    "n={n}: estimate {e} too far below exact {exact}"
                );
                worst = worst.min(e / exact);
            }
        }
        assert!(worst > 0.5, "worst ratio {worst}");
    }

    #[test]
    fn exact_for_nonnegative_matrices() {
        // Higham & Tisseur: with first column 𝟙 the estimate is exact for nonnegative A.
        let n = 40;
        let a = Mat::from_fn(n, n, |i, j| ((i * 31 + j * 17) % 11) as f64);
        let mut est = Normest::new(n);
        let e = est.estimate_product(&[&a, &a]);
        let exact = exact_norm1(&(&a * &a));
        assert!((e - exact).abs() <= 1e-12 * exact);
    }

    #[test]
    fn finds_a_single_large_column() {
        // The maximal column is a unit-vector direction: found by the e_j steps.
        let n = 60;
        let mut a = pseudo_random(n, 9);
        for i in 0..n {
            a[(i, 41)] = if i % 2 == 0 { 50.0 } else { -50.0 };
        }
        let mut est = Normest::new(n);
        let e = est.estimate_product(&[&a]);
        assert!((e - exact_norm1(&a)).abs() <= 1e-12 * e);
    }
}
