//! Benchmarks of `sporadic-sim`.
//!
//! * `sim/linear_observer`: the 5-state observer of Ferrante et al. (2016), Example 2 (plant + observer,
//!   10 states in total), intervals uniform in [0.2, 3], 10⁶ jumps with exact flows — goal < 1 s.
//!   Reference in the same run: a naive loop with one direct `expm_scaled` per jump (10⁴ jumps).
//! * `sim/dopri5`: Dormand–Prince 5(4) throughput on the Lorenz system (rtol 1e-9), with the cost of the
//!   same number of bare right-hand-side evaluations as the reference.
//! * `sim/state_triggered`: the event-heavy run of Andrieu et al. (2014) (theorem-conforming
//!   design on a pendulum, α = 0.2: ≈ 7600 located events over 2 time units).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use faer::{Mat, mat};
use sporadic_sim::{
    Dopri5, Dopri5Options, FnFlow, HybridObserver, IntervalSequence, LinearCorrection,
    LinearOutputs, LtiFlow, SampleContext, SampleEvent, SampledPlant, SamplingRule, SimError,
    SimOptions, Trigger, UniformRandom, simulate,
};

fn ferrante_ex2() -> (Mat<f64>, Mat<f64>, Mat<f64>) {
    let a = mat![
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, 0.0],
        [-2.0, 1.0, -1.0, 0.0, 0.0],
        [2.0, -2.0, 0.0, -2.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0],
    ];
    let m = mat![[1.0, 0.0, 0.0, 0.0, 1.0]];
    let l = mat![[0.77524], [0.18123], [-0.12123], [-0.17406], [0.22469]];
    (a, m, l)
}

fn run_linear_observer(jumps: usize) -> f64 {
    let (a, m, l) = ferrante_ex2();
    let mut plant = SampledPlant {
        flow: LtiFlow::new(a.as_ref()).unwrap(),
        output: LinearOutputs::new(vec![m.clone()]).unwrap(),
    };
    let mut obs = HybridObserver {
        flow: LtiFlow::new(a.as_ref()).unwrap(),
        jump: LinearCorrection::constant(m, l).unwrap(),
    };
    let mut rule = UniformRandom::new(0.2, 3.0, 7).unwrap();
    let sim = simulate(
        &mut plant,
        &mut obs,
        &mut rule,
        &[1.0, -1.0, 0.5, 0.0, 1.0],
        &[0.0; 5],
        &SimOptions::jumps(jumps),
    )
    .unwrap();
    assert_eq!(sim.arc.num_jumps(), jumps);
    sim.arc.last().unwrap().1[0]
}

/// Naive reference: per jump, one direct `expm_scaled(A, τ)` shared by plant and observer, two
/// matrix–vector products and the correction.
fn run_reference(jumps: usize) -> f64 {
    let (a, m, l) = ferrante_ex2();
    let mut rule = UniformRandom::new(0.2, 3.0, 7).unwrap();
    let mut x = Mat::<f64>::from_fn(5, 1, |i, _| [1.0, -1.0, 0.5, 0.0, 1.0][i]);
    let mut xh = Mat::<f64>::zeros(5, 1);
    for _ in 0..jumps {
        let tau = rule.next_interval().unwrap().interval;
        let e = sporadic_linalg::expm_scaled(a.as_ref(), tau).unwrap();
        x = &e * &x;
        xh = &e * &xh;
        let innov = &m * &x - &m * &xh;
        xh = &xh + &l * &innov;
    }
    x[(0, 0)] - xh[(0, 0)]
}

fn bench_linear_observer(c: &mut Criterion) {
    let mut g = c.benchmark_group("sim/linear_observer");
    g.sample_size(10);
    g.throughput(Throughput::Elements(1_000_000));
    g.bench_function("exact_1e6_jumps", |b| {
        b.iter(|| black_box(run_linear_observer(1_000_000)))
    });
    g.throughput(Throughput::Elements(10_000));
    g.bench_function("exact_1e4_jumps", |b| {
        b.iter(|| black_box(run_linear_observer(10_000)))
    });
    g.bench_function("reference_direct_expm_1e4_jumps", |b| {
        b.iter(|| black_box(run_reference(10_000)))
    });
    g.finish();
}

fn lorenz(_t: f64, x: &[f64], dx: &mut [f64]) {
    dx[0] = 10.0 * (x[1] - x[0]);
    dx[1] = x[0] * (28.0 - x[2]) - x[1];
    dx[2] = x[0] * x[1] - 8.0 / 3.0 * x[2];
}

fn bench_dopri5(c: &mut Criterion) {
    let opts = Dopri5Options::with_tolerances(1e-9, 1e-12);
    let run = || {
        let mut dp = Dopri5::new(opts.clone()).unwrap();
        let mut x = [1.0, 1.0, 1.0];
        dp.integrate(&lorenz, 0.0, &mut x, 20.0, &[], |_| {})
            .unwrap();
        (x[0], dp.stats())
    };
    let stats = run().1;
    let mut g = c.benchmark_group("sim/dopri5");
    g.throughput(Throughput::Elements(stats.accepted as u64));
    g.bench_function("lorenz_t20_rtol1e-9", |b| b.iter(|| black_box(run().0)));
    let evals = stats.rhs_evals;
    g.bench_function("reference_bare_rhs_evals", |b| {
        b.iter(|| {
            let mut x = [1.0, 1.0, 1.0];
            let mut dx = [0.0; 3];
            for _ in 0..evals {
                lorenz(0.0, black_box(&x), &mut dx);
                x[0] += 1e-9 * dx[0];
            }
            black_box(x[0])
        })
    });
    g.finish();
}

struct AndrieuRule;

impl SamplingRule for AndrieuRule {
    fn next_sample(&mut self, ctx: &SampleContext<'_>) -> Result<Trigger, SimError> {
        Ok(Trigger::Event {
            sensor: 0,
            max_interval: 1.01 * 0.2 / ctx.observer[2],
        })
    }
    fn guard(&self, s: f64, _plant: &[f64], obs: &[f64]) -> f64 {
        s * obs[2] - 0.2
    }
}

fn run_andrieu() -> usize {
    let (alpha, a1, a2, a3, k) = (0.2, 0.0693280, 56.2298, 4.0, [-2.0, -1.0]);
    let mut plant = SampledPlant {
        flow: FnFlow::new(2, |_t, x: &[f64], dx: &mut [f64]| {
            dx[0] = x[1];
            dx[1] = -x[0].sin();
        }),
        output: |_ev: &SampleEvent, x: &[f64], y: &mut Vec<f64>| -> Result<(), SimError> {
            y.push(x[0]);
            Ok(())
        },
    };
    let mut obs = HybridObserver {
        flow: FnFlow::new(4, move |_t, z: &[f64], dz: &mut [f64]| {
            dz[0] = z[1];
            dz[1] = -z[0].sin();
            dz[2] = a2 * z[2] * z[3];
            dz[3] = a3 * z[3];
        }),
        jump: move |_ev: &SampleEvent, y: &[f64], z: &mut [f64]| -> Result<(), SimError> {
            let (l_minus, innov) = (z[2], z[0] - y[0]);
            z[0] += alpha * k[0] * innov;
            z[1] += alpha * l_minus * k[1] * innov;
            z[2] = (1.0 - a1 * alpha) * l_minus + a1 * alpha;
            z[3] = 1.0;
            Ok(())
        },
    };
    let mut opts = SimOptions::new(2.0);
    opts.integrator.rtol = 1e-10;
    opts.integrator.atol = 1e-13;
    let sim = simulate(
        &mut plant,
        &mut obs,
        &mut AndrieuRule,
        &[1.0, 0.0],
        &[-1.0, 2.0, 1.0, 1.0],
        &opts,
    )
    .unwrap();
    sim.samples.len()
}

fn bench_state_triggered(c: &mut Criterion) {
    let events = run_andrieu();
    let mut g = c.benchmark_group("sim/state_triggered");
    g.sample_size(10);
    g.throughput(Throughput::Elements(events as u64));
    g.bench_function("andrieu_c1_events", |b| b.iter(|| black_box(run_andrieu())));
    g.finish();
}

criterion_group!(
    benches,
    bench_linear_observer,
    bench_dopri5,
    bench_state_triggered
);
criterion_main!(benches);
