//! Metamorphic properties of the design and of the largest window (issue 22): LMI (41) of
//! Ferrante et al. (2016) and condition (12) do not change, in exact arithmetic, under
//!
//! * a change of time unit `(A, [T1, T2]) → (kA, [T1/k, T2/k])`,
//! * a change of state coordinates `(A, C) → (TAT⁻¹, CT⁻¹)` (random well-conditioned `T`
//!   times a badly scaled diagonal; integrator chains and Jordan blocks included),
//! * a change of output units `C → diag(c_k)C` (each output its own unit),
//!
//! and a window that is certified certifies each of its sub-windows (condition (12) quantifies
//! over every `v` of the window). Random plants of order 2–6, stable, unstable and marginal
//! (spectral abscissa −0.3, +0.2, 0), with one or two outputs, plus integrator chains and Jordan
//! blocks. The largest `T2` of the plant as given is searched once; the transformed problem must
//! then be certified at 99 % of it and not certified at 101 % of the first failing `T2` (so the
//! largest `T2` of both agree within 1 %).

use faer::Mat;
use faer::linalg::solvers::DenseSolveCore;
use proptest::prelude::*;
use sporadic_ferrante2016::{
    DesignOptions, Plant, SamplingWindow, Tolerance, VerifyOptions, WindowSearchOptions, design,
    largest_t2, verify,
};

/// A small deterministic generator (xorshift64*), so that a proptest seed fixes a plant.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(seed | 1)
    }
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform().max(1e-300), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.uniform()).exp()
    }
    fn below(&mut self, k: u64) -> usize {
        (self.uniform() * k as f64) as usize % k as usize
    }
}

const T1: f64 = 0.05;
const LIMIT: f64 = 3.0;

/// A random plant: kind 0–2 random `A` shifted to spectral abscissa −0.3 / +0.2 / 0, kind 3 an
/// integrator chain, kind 4 a Jordan block (eigenvalue −0.4 or +0.2); one or two outputs.
fn random_plant(seed: u64) -> Plant {
    let mut r = Rng::new(seed);
    let kind = r.below(5);
    let n = 2 + r.below(5);
    let q = 1 + r.below(2);
    let a = match kind {
        0..=2 => {
            let m = Mat::from_fn(n, n, |_, _| r.normal() / (n as f64).sqrt());
            let abscissa = m
                .eigenvalues()
                .unwrap()
                .iter()
                .map(|l| l.re)
                .fold(f64::NEG_INFINITY, f64::max);
            let target = [-0.3, 0.2, 0.0][kind];
            Mat::from_fn(n, n, |i, j| {
                m[(i, j)] + if i == j { target - abscissa } else { 0.0 }
            })
        }
        _ => {
            let lambda = if kind == 3 {
                0.0
            } else if r.uniform() < 0.5 {
                -0.4
            } else {
                0.2
            };
            Mat::from_fn(n, n, |i, j| {
                if i == j {
                    lambda
                } else if j == i + 1 {
                    1.0
                } else {
                    0.0
                }
            })
        }
    };
    let c = if kind >= 3 {
        Mat::from_fn(q, n, |i, j| if i == j { 1.0 } else { 0.0 })
    } else {
        Mat::from_fn(q, n, |_, _| r.normal())
    };
    Plant::new(a.as_ref(), c.as_ref()).unwrap()
}

/// `D·R` with `R = I + N/(2√n)` (`N` standard normal, redrawn until `κ(R) ≤ 10`) and `D`
/// diagonal with entries log-uniform in `[1e-3, 1e3]`: well conditioned up to units.
fn random_similarity(n: usize, seed: u64) -> Mat<f64> {
    let mut r = Rng::new(seed ^ 0x5eed);
    for _ in 0..100 {
        let m = Mat::from_fn(n, n, |i, j| {
            f64::from(u8::from(i == j)) + r.normal() / (2.0 * (n as f64).sqrt())
        });
        let s = m.singular_values().unwrap();
        if s[0] <= 10.0 * s[n - 1] {
            let d: Vec<f64> = (0..n).map(|_| r.log_uniform(1e-3, 1e3)).collect();
            return Mat::from_fn(n, n, |i, j| d[i] * m[(i, j)]);
        }
    }
    Mat::identity(n, n)
}

fn similar(p: &Plant, t: &Mat<f64>) -> Plant {
    let ti = t.partial_piv_lu().inverse();
    Plant::new((t * p.a() * &ti).as_ref(), (p.c() * &ti).as_ref()).unwrap()
}

fn certified(p: &Plant, t1: f64, t2: f64) -> bool {
    design(
        p,
        &SamplingWindow::new(t1, t2).unwrap(),
        &DesignOptions::default(),
    )
    .is_ok()
}

/// `(largest certified T2, first failing T2)` of the plant as given, from `T1`.
fn largest(p: &Plant) -> (Option<f64>, Option<f64>) {
    let search = WindowSearchOptions {
        tolerance: Tolerance::Relative(4e-3),
        ..WindowSearchOptions::default()
    };
    let s = largest_t2(p, T1, LIMIT, &DesignOptions::default(), &search).unwrap();
    (s.best, s.first_failure)
}

/// The transformed problem (`k` its time unit: its windows are the plant's divided by `k`) has
/// the same largest `T2` within 1 %, given the plant's `(best, first failure)`.
fn same_largest_window(
    q: &Plant,
    k: f64,
    (best, fail): (Option<f64>, Option<f64>),
) -> Result<(), TestCaseError> {
    match best {
        None => prop_assert!(
            !certified(q, T1 / k, T1 / k),
            "the plant is not certified at the periodic window T1, the transformed one is"
        ),
        Some(b) => {
            let lo = (0.99 * b).max(T1);
            prop_assert!(
                certified(q, T1 / k, lo / k),
                "certified up to {b} as given, not at {lo} transformed"
            );
            if let Some(f) = fail {
                let hi = 1.01 * f;
                prop_assert!(
                    !certified(q, T1 / k, hi / k),
                    "first failure at {f} as given, certified at {hi} transformed"
                );
            }
        }
    }
    Ok(())
}

proptest! {
    // A fixed seed: the same plants on every run (6 cases per property).
    #![proptest_config(ProptestConfig {
        cases: 6,
        max_shrink_iters: 0,
        rng_seed: proptest::test_runner::RngSeed::Fixed(22),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// `(A, [T1, T2]) → (kA, [T1/k, T2/k])`, `k` log-uniform in `[1e-3, 1e3]`.
    #[test]
    fn time_scaling(seed in any::<u64>()) {
        let p = random_plant(seed);
        let k = Rng::new(seed ^ 0x71e).log_uniform(1e-3, 1e3);
        let scaled = Plant::new((p.a() * faer::Scale(k)).as_ref(), p.c()).unwrap();
        same_largest_window(&scaled, k, largest(&p))?;
    }

    /// `(A, C) → (TAT⁻¹, CT⁻¹)`, `T` well conditioned times a diagonal in `[1e-3, 1e3]`.
    #[test]
    fn similarity(seed in any::<u64>()) {
        let p = random_plant(seed);
        let t = random_similarity(p.n(), seed);
        same_largest_window(&similar(&p, &t), 1.0, largest(&p))?;
    }

    /// `C → diag(c_k)C`, each output's unit `c_k` log-uniform in `[1e-3, 1e3]`.
    #[test]
    fn output_scaling(seed in any::<u64>()) {
        let p = random_plant(seed);
        let mut r = Rng::new(seed ^ 0xc);
        let c: Vec<f64> = (0..p.q()).map(|_| r.log_uniform(1e-3, 1e3)).collect();
        let scaled = Mat::from_fn(p.q(), p.n(), |i, j| c[i] * p.c()[(i, j)]);
        let scaled = Plant::new(p.a(), scaled.as_ref()).unwrap();
        same_largest_window(&scaled, 1.0, largest(&p))?;
    }

    /// A design on `[T1, T2]` (98 % of the largest `T2`) passes the grid check of (12) on the
    /// window and on a random sub-window `[T1', T2']`, and the sub-window is certified by a
    /// design of its own.
    #[test]
    fn window_inclusion(seed in any::<u64>()) {
        let p = random_plant(seed);
        if let (Some(b), _) = largest(&p) {
            let t2 = (0.98 * b).max(T1);
            let w = SamplingWindow::new(T1, t2).unwrap();
            let d = design(&p, &w, &DesignOptions::default());
            prop_assert!(d.is_ok(), "not certified at {t2} below the largest T2 {b}: {:?}", d.err());
            let d = d.unwrap();
            let mut r = Rng::new(seed ^ 0x5b);
            let (x, y) = (r.uniform(), r.uniform());
            let (t1s, t2s) = (T1 + (t2 - T1) * x.min(y), T1 + (t2 - T1) * x.max(y));
            let sub = SamplingWindow::new(t1s, t2s).unwrap();
            for win in [w, sub] {
                let v = verify(&p, &win, d.l.as_ref(), d.certificate.p.as_ref(), &VerifyOptions::default()).unwrap();
                prop_assert!(v.passed(), "the gain of [{T1}, {t2}] fails (12) on {win:?}: {v:?}");
            }
            prop_assert!(certified(&p, t1s, t2s), "sub-window [{t1s}, {t2s}] of [{T1}, {t2}] not certified");
        }
    }
}

/// The harmonic oscillator: `ω = 10` on the window divided by 10 has the largest `T2` of `ω = 1`
/// divided by 10 (it was 9 % short: 0.278 against 0.3056).
#[test]
fn oscillator_largest_window_scales_with_time() {
    let osc = |w: f64| {
        Plant::new(
            faer::mat![[0.0, 1.0], [-w * w, 0.0]].as_ref(),
            faer::mat![[1.0, 0.0]].as_ref(),
        )
        .unwrap()
    };
    let search = WindowSearchOptions {
        tolerance: Tolerance::Relative(1e-3),
        ..WindowSearchOptions::default()
    };
    let opts = DesignOptions::default();
    let t1 = largest_t2(&osc(1.0), 0.01, 5.0, &opts, &search)
        .unwrap()
        .best
        .unwrap();
    let t10 = largest_t2(&osc(10.0), 0.001, 0.5, &opts, &search)
        .unwrap()
        .best
        .unwrap();
    assert!(t1 > 3.0 && t1 < std::f64::consts::PI, "{t1}");
    assert!(
        (10.0 * t10 / t1 - 1.0).abs() < 0.01,
        "ω = 1: {t1}, ω = 10: {t10}"
    );
}

/// Similarity on the structured plants whatever the random draw: integrator chains (orders 3
/// and 5, one and two outputs) and Jordan blocks (eigenvalue −0.4 of order 3, +0.2 of order 4),
/// each under a random well-conditioned `T` times a diagonal in `[1e-3, 1e3]`.
#[test]
fn similarity_of_integrator_chains_and_jordan_blocks() {
    let block = |n: usize, q: usize, lambda: f64| {
        let a = Mat::from_fn(n, n, |i, j| {
            if i == j {
                lambda
            } else if j == i + 1 {
                1.0
            } else {
                0.0
            }
        });
        let c = Mat::from_fn(q, n, |i, j| if i == j { 1.0 } else { 0.0 });
        Plant::new(a.as_ref(), c.as_ref()).unwrap()
    };
    let cases = [
        block(3, 1, 0.0),
        block(5, 2, 0.0),
        block(3, 1, -0.4),
        block(4, 1, 0.2),
    ];
    for (k, p) in cases.iter().enumerate() {
        let t = random_similarity(p.n(), 1000 + k as u64);
        if let Err(e) = same_largest_window(&similar(p, &t), 1.0, largest(p)) {
            panic!("case {k}: {e}");
        }
    }
}

/// Similarity on random plants that failed before the normal forms (found by unseeded runs of
/// [`similarity`]): a 5-state plant (`T2` 0.621 as given, not certified at 0.615 transformed)
/// and an integrator chain of order 5 with two outputs.
#[test]
fn similarity_regressions() {
    for seed in [3127952270580911728, 14599065684562394882] {
        let p = random_plant(seed);
        let t = random_similarity(p.n(), seed);
        if let Err(e) = same_largest_window(&similar(&p, &t), 1.0, largest(&p)) {
            panic!("seed {seed}: {e}");
        }
    }
}
