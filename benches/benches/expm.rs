//! Matrix exponential: sporadic-linalg (Al-Mohy & Higham 2009, Algorithm 6.1) against
//! nalgebra 0.35 `DMatrix::exp()` (a port of SciPy's `_expm`, same algorithm family) on the
//! same matrices in the same run, plus faer matmul at the same orders (to express expm cost in
//! matrix-product equivalents) and `ExpmStepper` throughput.
//!
//! Before the timings, an accuracy/cost table is printed to stderr: for every benchmarked
//! matrix the chosen Padé degree m and squarings s, the flop lower bound
//! (π_m + s + 4/3)·2n³, and ‖e^A·e^{−A} − I‖₁ for both libraries; then the relative Frobenius
//! error of both libraries on Burkardt's test matrices against 60-digit references
//! (mpmath 1.3 `expm`, dps = 60).
//!
//! Then an interleaved A/B table (also stderr): for every (‖A‖₁, n) of the criterion groups,
//! batches of ours and of nalgebra alternate, and the median of the per-round time ratios is
//! printed. Both sides see the same machine load in every round, so this ratio is steadier than
//! the ratio of two criterion estimates taken seconds apart on a busy machine.
//!
//! Run: `cargo bench -p sporadic-benches --bench expm -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use nalgebra::DMatrix;
use sporadic_linalg::{expm, expm_parameters, expm_stepper};

const ORDERS: [usize; 6] = [2, 4, 8, 16, 64, 128];
const NORMS: [f64; 2] = [1.0, 10.0];

/// Deterministic pseudo-random matrix with entries in [−1, 1), scaled to ‖A‖₁ = `norm`.
fn test_matrix(n: usize, norm: f64) -> Mat<f64> {
    let mut state = 0x2545_f491_4f6c_dd1du64 ^ (n as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    let a = Mat::from_fn(n, n, |_, _| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        2.0 * ((state >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    });
    let n1 = norm1(&a);
    Mat::from_fn(n, n, |i, j| a[(i, j)] * norm / n1)
}

fn norm1(a: &Mat<f64>) -> f64 {
    (0..a.ncols())
        .map(|j| a.col(j).iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

fn to_na(a: &Mat<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

fn from_na(a: &DMatrix<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

/// π_m: matrix products of the degree-m evaluation (Al-Mohy & Higham 2009).
fn products(m: usize) -> f64 {
    match m {
        3 => 2.0,
        5 => 3.0,
        7 => 4.0,
        9 => 5.0,
        13 => 6.0,
        _ => 0.0,
    }
}

fn accuracy_report() {
    eprintln!("== cost and inverse-identity accuracy on the benchmark matrices ==");
    eprintln!(
        "{:>4} {:>6} {:>3} {:>3} {:>14} {:>16} {:>16}",
        "n", "‖A‖₁", "m", "s", "flop bound", "ours ‖XY−I‖₁", "nalgebra ‖XY−I‖₁"
    );
    for &n in &ORDERS {
        for &nrm in &NORMS {
            let a = test_matrix(n, nrm);
            let p = expm_parameters(a.as_ref()).unwrap();
            let flops =
                (products(p.degree) + p.squarings as f64 + 4.0 / 3.0) * 2.0 * (n as f64).powi(3);
            let neg = Mat::from_fn(n, n, |i, j| -a[(i, j)]);
            let ours = norm1(
                &(expm(a.as_ref()).unwrap() * expm(neg.as_ref()).unwrap()
                    - Mat::<f64>::identity(n, n)),
            );
            let na = from_na(&(to_na(&a).exp() * to_na(&neg).exp()));
            let theirs = norm1(&(na - Mat::<f64>::identity(n, n)));
            eprintln!(
                "{n:>4} {nrm:>6} {:>3} {:>3} {flops:>14.3e} {ours:>16.2e} {theirs:>16.2e}",
                p.degree, p.squarings
            );
        }
    }
    eprintln!("== relative Frobenius error vs 60-digit references (mpmath 1.3, dps = 60) ==");
    eprintln!("{:>12} {:>12} {:>12}", "case", "ours", "nalgebra");
    for (name, a, want) in burkardt_cases() {
        let n = a.len();
        let am = Mat::from_fn(n, n, |i, j| a[i][j]);
        let wm = Mat::from_fn(n, n, |i, j| want[i][j]);
        let ours = (expm(am.as_ref()).unwrap() - &wm).norm_l2() / wm.norm_l2();
        let theirs = (from_na(&to_na(&am).exp()) - &wm).norm_l2() / wm.norm_l2();
        eprintln!("{name:>12} {ours:>12.2e} {theirs:>12.2e}");
    }
}

type Case = (&'static str, Vec<Vec<f64>>, Vec<Vec<f64>>);

/// Burkardt's expm test matrices (SciPy `TestExpM`) with references computed by mpmath 1.3
/// `expm` at 60 decimal digits from the double-precision inputs, rounded to double.
fn burkardt_cases() -> Vec<Case> {
    let v = |rows: &[&[f64]]| rows.iter().map(|r| r.to_vec()).collect::<Vec<_>>();
    vec![
        (
            "burkardt_2",
            v(&[&[1.0, 3.0], &[3.0, 2.0]]),
            v(&[
                &[39.322809708033965, 46.16630143888589],
                &[46.16630143888589, 54.71157685432926],
            ]),
        ),
        (
            "burkardt_3",
            v(&[&[0.0, 1.0], &[-39.0, -40.0]]),
            v(&[
                &[0.3775604790970066, 0.009681037925564271],
                &[-0.3775604790970066, -0.00968103792556426],
            ]),
        ),
        (
            "burkardt_4",
            v(&[&[-49.0, 24.0], &[-64.0, 31.0]]),
            v(&[
                &[-0.7357587581447531, 0.5518190996580977],
                &[-1.4715175990882605, 1.1036382407155725],
            ]),
        ),
        (
            "burkardt_8",
            v(&[&[21.0, 17.0, 6.0], &[-5.0, -1.0, -6.0], &[4.0, 4.0, 16.0]]),
            v(&[
                &[28879845.542113077, 28879790.943963043, 4443027.961178919],
                &[-19993735.021605205, -19993680.42345517, -4443027.961178919],
                &[35544442.08203149, 35544442.08203149, 8886110.520507872],
            ]),
        ),
        (
            "burkardt_9",
            v(&[
                &[1.0, 2.0, 2.0, 2.0],
                &[3.0, 1.0, 1.0, 2.0],
                &[3.0, 2.0, 1.0, 2.0],
                &[3.0, 3.0, 3.0, 1.0],
            ]),
            v(&[
                &[
                    740.7037761710753,
                    610.8500221577392,
                    542.2743186672172,
                    549.175349323763,
                ],
                &[
                    731.2510147346803,
                    603.5523691900313,
                    535.0884273108778,
                    542.2743186672172,
                ],
                &[
                    823.7630239856446,
                    679.4257256482612,
                    603.5523691900313,
                    610.8500221577392,
                ],
                &[
                    998.4354965027543,
                    823.7630239856446,
                    731.2510147346803,
                    740.7037761710753,
                ],
            ]),
        ),
        (
            "burkardt_10",
            v(&[&[4.0, 2.0, 0.0], &[1.0, 4.0, 1.0], &[1.0, 1.0, 4.0]]),
            v(&[
                &[147.86662244637014, 183.76513864636843, 71.79703239999654],
                &[127.78108552318248, 183.76513864636843, 91.88256932318421],
                &[127.78108552318248, 163.67960172318075, 111.96810624637187],
            ]),
        ),
        (
            "burkardt_11",
            v(&[
                &[29.87942128909879, 0.7815750847907159, -2.289519314033932],
                &[0.7815750847907159, 25.72656945571064, 8.680737820540137],
                &[-2.289519314033932, 8.680737820540137, 34.39400925519054],
            ]),
            v(&[
                &[
                    5496313853692405.0,
                    -1.8231880972009064e16,
                    -3.0475770808580148e16,
                ],
                &[
                    -1.8231880972009064e16,
                    6.060522870222131e16,
                    1.0129184293024866e17,
                ],
                &[
                    -3.0475770808580148e16,
                    1.0129184293024866e17,
                    1.6929441124085002e17,
                ],
            ]),
        ),
        (
            "burkardt_12",
            v(&[
                &[-131.0, 19.0, 18.0],
                &[-390.0, 56.0, 54.0],
                &[-387.0, 57.0, 52.0],
            ]),
            v(&[
                &[-1.5096441587960896, 0.3678794391102887, 0.13533528117545907],
                &[-5.632570799902596, 1.4715177585023085, 0.4060058435263772],
                &[-4.9349383260981075, 1.1036383173308661, 0.54134112676299],
            ]),
        ),
        (
            "burkardt_14",
            v(&[
                &[0.0, 1e-8, 0.0],
                &[-(2e10 + 4e8 / 6.0), -3.0, 2e10],
                &[200.0 / 3.0, 0.0, -200.0 / 3.0],
            ]),
            v(&[
                &[
                    0.4468494682831738,
                    1.5404415738395202e-09,
                    0.4628114535587736,
                ],
                &[-5743067.779479561, -0.01528300386868225, -4526542.712784101],
                &[
                    0.44772297784949333,
                    1.5427048451959122e-09,
                    0.46348064883765006,
                ],
            ]),
        ),
    ]
}

/// Seconds per batch of the interleaved comparison.
const AB_BATCH: Duration = Duration::from_millis(2);
/// Rounds (ours batch + nalgebra batch) per configuration.
const AB_ROUNDS: usize = 41;

/// Iterations of `f` that take about [`AB_BATCH`].
fn batch_len(f: &mut impl FnMut()) -> usize {
    let mut k = 1usize;
    loop {
        let t = Instant::now();
        for _ in 0..k {
            f();
        }
        let dt = t.elapsed();
        if dt >= AB_BATCH / 4 || k >= 1 << 24 {
            let scale = AB_BATCH.as_secs_f64() / dt.as_secs_f64().max(1e-9);
            return ((k as f64 * scale).ceil() as usize).max(1);
        }
        k *= 2;
    }
}

/// Seconds per call of `f` over a batch of `k` calls.
fn time_batch(f: &mut impl FnMut(), k: usize) -> f64 {
    let t = Instant::now();
    for _ in 0..k {
        f();
    }
    t.elapsed().as_secs_f64() / k as f64
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Interleaved A/B comparison (see the module docs): median over rounds of
/// t_nalgebra / t_ours, with the median per-call times.
fn interleaved_report() {
    eprintln!("== interleaved A/B: median over {AB_ROUNDS} rounds of t_nalgebra / t_ours ==");
    eprintln!(
        "{:>6} {:>4} {:>12} {:>12} {:>7} {:>7} {:>7}",
        "‖A‖₁", "n", "ours", "nalgebra", "ratio", "q25", "q75"
    );
    for &nrm in &NORMS {
        for &n in &ORDERS {
            let a = test_matrix(n, nrm);
            let na = to_na(&a);
            let mut ours = || {
                black_box(expm(black_box(a.as_ref())).unwrap());
            };
            let mut theirs = || {
                black_box(black_box(&na).exp());
            };
            let (ko, kt) = (batch_len(&mut ours), batch_len(&mut theirs));
            let (mut to, mut tt, mut r) = (Vec::new(), Vec::new(), Vec::new());
            for _ in 0..AB_ROUNDS {
                let x = time_batch(&mut ours, ko);
                let y = time_batch(&mut theirs, kt);
                to.push(x);
                tt.push(y);
                r.push(y / x);
            }
            r.sort_by(f64::total_cmp);
            let q = |f: f64| r[((r.len() - 1) as f64 * f).round() as usize];
            eprintln!(
                "{nrm:>6} {n:>4} {:>10.2}µs {:>10.2}µs {:>7.2} {:>7.2} {:>7.2}",
                median(to) * 1e6,
                median(tt) * 1e6,
                q(0.5),
                q(0.25),
                q(0.75)
            );
        }
    }
}

fn bench_expm(c: &mut Criterion) {
    for &nrm in &NORMS {
        let mut group = c.benchmark_group(format!("expm_norm{nrm}"));
        for &n in &ORDERS {
            let a = test_matrix(n, nrm);
            let na = to_na(&a);
            group.bench_with_input(BenchmarkId::new("sporadic", n), &a, |b, a| {
                b.iter(|| expm(black_box(a.as_ref())).unwrap())
            });
            group.bench_with_input(BenchmarkId::new("nalgebra", n), &na, |b, na| {
                b.iter(|| black_box(na).exp())
            });
        }
        group.finish();
    }
    let mut group = c.benchmark_group("faer_matmul");
    for &n in &ORDERS {
        let a = test_matrix(n, 1.0);
        let mut out = Mat::<f64>::zeros(n, n);
        group.bench_with_input(BenchmarkId::from_parameter(n), &a, |b, a| {
            b.iter(|| {
                matmul(
                    out.as_mut(),
                    Accum::Replace,
                    black_box(a.as_ref()),
                    a.as_ref(),
                    1.0,
                    Par::Seq,
                )
            })
        });
    }
    group.finish();
}

fn bench_stepper(c: &mut Criterion) {
    const STEPS: usize = 10_000;
    let mut group = c.benchmark_group("expm_stepper");
    group.throughput(Throughput::Elements(STEPS as u64 + 1));
    for n in [4usize, 8] {
        let a = test_matrix(n, 1.0);
        let mut out = Mat::<f64>::zeros(n, n);
        group.bench_with_input(BenchmarkId::new("next_into", n), &a, |b, a| {
            b.iter(|| {
                let mut st = expm_stepper(a.as_ref(), 0.0, 1e-3, STEPS).unwrap();
                while st.next_into(out.as_mut()).is_some() {}
                black_box(&out);
            })
        });
    }
    group.finish();
}

fn main() {
    accuracy_report();
    interleaved_report();
    let mut c = Criterion::default().configure_from_args();
    bench_expm(&mut c);
    bench_stepper(&mut c);
    c.final_summary();
}
