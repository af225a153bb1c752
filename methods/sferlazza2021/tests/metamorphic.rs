//! Metamorphic properties of the jitter-tolerant design of Sferlazza et al. (2021) on random
//! plants (issue 22). Condition (44) of Theorem 4 and its gain (45) do not change, in exact
//! arithmetic, under
//!
//! * a change of time unit `(A, [T1, T2]) → (kA, [T1/k, T2/k])` (`Ξ_σ(τ)` depends on `A` and
//!   `τ` only through `Aτ`),
//! * a change of state coordinates `(A, C) → (TAT⁻¹, CT⁻¹)` (`Ξ_σ(τ)` of the transformed plant
//!   with the certificate `T⁻ᵀP_σT⁻¹` is congruent to that of the plant with `P_σ`), with `T` a
//!   random well-conditioned matrix times a badly scaled diagonal; integrator chains and Jordan
//!   blocks included,
//! * a change of output units `C → diag(c_k)C` (`Ξ_σ` reads `C_σ` only through its kernel),
//!
//! and a window that is certified certifies each of its sub-windows (the condition quantifies
//! over every `τ` of the window).
//!
//! Random plants of order 2–5: oscillatory plants (a complex pair with real part `+0.4`, `+0.1`,
//! `0` or `−0.2`, whose aliasing interval `π/ω` ends the window of an unstable or marginal pair
//! read by one output), integrator chains and Jordan blocks (eigenvalue `+0.3` or `−0.4`); one or
//! two outputs sampled together, or two round-robin sensors. The largest `T2` from `T1 = 0.05`
//! up to `10` of the plant as given is searched once; the transformed problem must then be certified at 99 % of it and not
//! certified at 101 % of the first failing `T2` (so the largest `T2` of both agree within 1 %).
//!
//! Not covered: the end of a search that is undecided in double precision (a long window of an
//! unstable plant whose `e^{−Aτ}` on the stable modes outgrows the precision of (48); the
//! report says `undecided`), where the `T2` at which precision runs out depends on the
//! coordinates. A case whose search ends that way is rejected (at most 6 per property).

use std::time::Duration;

use faer::Mat;
use faer::linalg::solvers::DenseSolveCore;
use proptest::prelude::*;
use sporadic_model::{SearchEnd, Tolerance};
use sporadic_sferlazza2021::{
    MethodOptions, ObserverMethod, Plant, Sampling, SamplingWindow, Sferlazza2021, Status,
};
use sporadic_sim::SimRng;

/// Draws of the seeded generator of the simulations (a proptest seed fixes a plant).
struct Rng(SimRng);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(SimRng::new(seed))
    }
    fn uniform(&mut self) -> f64 {
        self.0.uniform01()
    }
    fn normal(&mut self) -> f64 {
        self.0.standard_normal()
    }
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0.uniform(lo.ln(), hi.ln()).exp()
    }
    fn below(&mut self, k: u64) -> usize {
        (self.0.next_u64() % k) as usize
    }
}

const T1: f64 = 0.05;
const LIMIT: f64 = 10.0;

/// A random plant `(A, C)`: kinds 0–5 an oscillatory plant, a complex pair `σ ± iω` (`σ` =
/// `+0.4 / +0.1 / 0 / +0.4 / +0.1 / −0.2`, `ω` log-uniform in `[0.4, 4]`, so that the aliasing
/// interval `π/ω` of an unstable or marginal pair read by one output ends the window) and real
/// modes in `[−1, 0.5]`, mixed by a random well-conditioned change of coordinates; kind 6 an
/// integrator chain, kind 7 a Jordan block (eigenvalue `+0.3` or `−0.4`); one output (three
/// cases in four) or two sampled together, or, for `round_robin`, two outputs read by two
/// round-robin sensors.
fn random_plant(seed: u64, round_robin: bool) -> (Mat<f64>, Mat<f64>) {
    let mut r = Rng::new(seed);
    let kind = r.below(8);
    let n = 2 + r.below(4);
    let q = if round_robin {
        2
    } else {
        1 + usize::from(r.below(4) == 0)
    };
    let a = match kind {
        0..=5 => {
            let sigma = [0.4, 0.1, 0.0, 0.4, 0.1, -0.2][kind];
            let omega = r.log_uniform(0.4, 4.0);
            let mut modal = Mat::<f64>::zeros(n, n);
            modal[(0, 0)] = sigma;
            modal[(1, 1)] = sigma;
            modal[(0, 1)] = omega;
            modal[(1, 0)] = -omega;
            for i in 2..n {
                modal[(i, i)] = -1.0 + 1.5 * r.uniform();
            }
            let t = Mat::from_fn(n, n, |i, j| {
                f64::from(u8::from(i == j)) + r.normal() / (2.0 * (n as f64).sqrt())
            });
            &t * &modal * t.partial_piv_lu().inverse()
        }
        _ => {
            let lambda = if kind == 6 {
                0.0
            } else if r.uniform() < 0.5 {
                -0.4
            } else {
                0.3
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
    let c = if kind >= 6 {
        Mat::from_fn(q, n, |i, j| f64::from(u8::from(i == j)))
    } else {
        Mat::from_fn(q, n, |_, _| r.normal())
    };
    (a, c)
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
    panic!("no well-conditioned R in 100 draws (n = {n})")
}

/// The plant `(A, C)`, its outputs sampled together or, for `round_robin`, each row of `C` a
/// round-robin sensor.
fn plant(a: &Mat<f64>, c: &Mat<f64>, round_robin: bool) -> Plant {
    if round_robin {
        let rows: Vec<_> = (0..c.nrows()).map(|i| c.subrows(i, 1)).collect();
        Plant::round_robin(a.as_ref(), None, &rows).unwrap()
    } else {
        Plant::linear(a.as_ref(), None, c.as_ref()).unwrap()
    }
}

/// The window `[t1, t2]` of every output sampled together or, for `round_robin`, of each
/// sensor.
fn window(p: &Plant, round_robin: bool, t1: f64, t2: f64) -> Sampling {
    let w = SamplingWindow::new(t1, t2).unwrap();
    if round_robin {
        Sampling::RoundRobin(vec![w; p.sensors().len()])
    } else {
        Sampling::Synchronous(w)
    }
}

fn certified(p: &Plant, rr: bool, t1: f64, t2: f64) -> bool {
    Sferlazza2021::default()
        .design(p, &window(p, rr, t1, t2), &MethodOptions::default())
        .unwrap()
        .status
        == Status::Certified
}

/// The plant as given: `(largest certified T2, first failing T2)` from `T1` up to [`LIMIT`]
/// within 25 s (no failing `T2` when the search's budget ran out), or `None` when the search ended
/// undecided in double precision (see the module docs).
fn largest(p: &Plant, rr: bool) -> Option<(Option<f64>, Option<f64>)> {
    let mut options = MethodOptions::default();
    options.search.tolerance = Tolerance::Relative(4e-3);
    // The command line's default budget (a round-robin search of order 5 bisected near its end
    // with probes of 20 s each, 343 s in all, without one).
    options.time_limit = Some(Duration::from_secs(25));
    let r = Sferlazza2021::default()
        .largest_window(p, &window(p, rr, T1, T1), LIMIT, &options, &mut |_| {})
        .unwrap();
    match r.search_end {
        Some(SearchEnd::Undecided) => None,
        // Its failing end may be a probe cut short by its budget, not a refutation.
        Some(SearchEnd::BudgetExhausted) => Some((r.largest_certified_t2, None)),
        _ => Some((r.largest_certified_t2, r.first_failing_t2)),
    }
}

/// The transformed plant (`k` its time unit: its windows are the plant's divided by `k`) has
/// the same largest `T2` within 1 %, given the plant's `(best, first failure)`.
fn same_largest_window(
    q: &Plant,
    rr: bool,
    k: f64,
    (best, fail): (Option<f64>, Option<f64>),
) -> Result<(), TestCaseError> {
    match best {
        None => prop_assert!(
            !certified(q, rr, T1 / k, T1 / k),
            "the plant is not certified at the periodic window T1, the transformed one is"
        ),
        Some(b) => {
            let lo = (0.99 * b).max(T1);
            prop_assert!(
                certified(q, rr, T1 / k, lo / k),
                "certified up to {b} as given, not at {lo} transformed"
            );
            if let Some(f) = fail {
                let hi = 1.01 * f;
                prop_assert!(
                    !certified(q, rr, T1 / k, hi / k),
                    "first failure at {f} as given, certified at {hi} transformed"
                );
            }
        }
    }
    Ok(())
}

/// The plant's search, or a rejected case when it ended undecided.
fn searched(p: &Plant, rr: bool) -> Result<(Option<f64>, Option<f64>), TestCaseError> {
    largest(p, rr)
        .ok_or_else(|| TestCaseError::reject("the search ended undecided in double precision"))
}

proptest! {
    // A fixed seed: the same plants on every run (8 cases per property; a case whose search
    // ends undecided is rejected, at most 6 times per property).
    #![proptest_config(ProptestConfig {
        cases: 8,
        max_shrink_iters: 0,
        max_global_rejects: 6,
        rng_seed: proptest::test_runner::RngSeed::Fixed(22),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// `(A, [T1, T2]) → (kA, [T1/k, T2/k])`, `k` log-uniform in `[1e-3, 1e3]`; the outputs
    /// sampled together (round-robin sensors in the other properties).
    #[test]
    fn time_scaling(seed in any::<u64>()) {
        let (a, c) = random_plant(seed, false);
        let found = searched(&plant(&a, &c, false), false)?;
        let k = Rng::new(seed ^ 0x71e).log_uniform(1e-3, 1e3);
        same_largest_window(&plant(&(&a * faer::Scale(k)), &c, false), false, k, found)?;
    }

    /// `(A, C) → (TAT⁻¹, CT⁻¹)`, `T` well conditioned times a diagonal in `[1e-3, 1e3]`;
    /// every output sampled together, or two round-robin sensors.
    #[test]
    fn similarity(seed in any::<u64>(), rr in any::<bool>()) {
        let (a, c) = random_plant(seed, rr);
        let found = searched(&plant(&a, &c, rr), rr)?;
        let t = random_similarity(a.nrows(), seed);
        let ti = t.partial_piv_lu().inverse();
        same_largest_window(&plant(&(&t * &a * &ti), &(&c * &ti), rr), rr, 1.0, found)?;
    }

    /// `C → diag(c_k)C`, each output's unit `c_k` log-uniform in `[1e-3, 1e3]`; every output
    /// sampled together, or two round-robin sensors.
    #[test]
    fn output_scaling(seed in any::<u64>(), rr in any::<bool>()) {
        let (a, c) = random_plant(seed, rr);
        let found = searched(&plant(&a, &c, rr), rr)?;
        let mut r = Rng::new(seed ^ 0xc);
        let s: Vec<f64> = (0..c.nrows()).map(|_| r.log_uniform(1e-3, 1e3)).collect();
        let scaled = Mat::from_fn(c.nrows(), c.ncols(), |i, j| s[i] * c[(i, j)]);
        same_largest_window(&plant(&a, &scaled, rr), rr, 1.0, found)?;
    }

    /// A design on `[T1, T2]` (98 % of the largest `T2`) passes `verify` with its own gains and
    /// certificate on the window and on a random sub-window `[T1', T2']` (its gain schedule,
    /// listed over `[T1, T2]`, was refused there as input outside the window), and the
    /// sub-window is certified by a design of its own.
    #[test]
    fn window_inclusion(seed in any::<u64>(), rr in any::<bool>()) {
        let (a, c) = random_plant(seed, rr);
        let p = plant(&a, &c, rr);
        let (best, _) = searched(&p, rr)?;
        let b = best.ok_or_else(|| TestCaseError::reject("nothing certified"))?;
        let t2 = (0.98 * b).max(T1);
        let method = Sferlazza2021::default();
        let options = MethodOptions::default();
        let d = method.design(&p, &window(&p, rr, T1, t2), &options).unwrap();
        prop_assert_eq!(d.status, Status::Certified, "not certified at {} below the largest T2 {}: {:?}", t2, b, d.reason);
        let mut r = Rng::new(seed ^ 0x5b);
        let (x, y) = (r.uniform(), r.uniform());
        let (t1s, t2s) = (T1 + (t2 - T1) * x.min(y), T1 + (t2 - T1) * x.max(y));
        for (u, v) in [(T1, t2), (t1s, t2s)] {
            let check = method.verify(&p, &window(&p, rr, u, v), &d.gains, &d.certificate, &options).unwrap();
            prop_assert_eq!(check.status, Status::Certified, "the design of [{}, {}] fails verify on [{}, {}]: {:?}", T1, t2, u, v, check.reason);
        }
        prop_assert!(certified(&p, rr, t1s, t2s), "sub-window [{t1s}, {t2s}] of [{T1}, {t2}] not certified");
    }
}
