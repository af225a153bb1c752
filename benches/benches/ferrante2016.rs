//! Design time of the observer of Ferrante et al. (Automatica 2016), Corollary 1: Remark 3 precheck,
//! residue embedding of `e^{Av}` on `[T1, T2]`, margin maximisation of LMI (41) over the `ν`
//! vertices, `L = F⁻¹J`, and the 2801-point grid verification of (12).
//!
//! * `ferrante2016/example2/{corollary1,reduced}`: Example 2 (`n = 5`, `q = 1`, `[0.2, 3]`,
//!   16 vertices). `corollary1` (the printed 15×15 LMI (41)) is the reference of this file;
//!   `reduced` imposes the equivalent 10×10 Schur complement (39) at each vertex.
//! * `ferrante2016/random_{corollary1,reduced}/n`: random stable plants with `n` distinct real
//!   eigenvalues `−(0.3 + 0.4i)`, a random output row, window `[0.1, 0.6]`: `ν = 2^n` vertices.
//!   `n = 2..=8` by default; set `FERRANTE_BENCH_MAX_N=10` for the (slow) larger sizes.
//!
//! Run: `cargo bench -p sporadic-benches --bench ferrante2016 -- --warm-up-time 1 --measurement-time 5`

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use faer::Mat;
use faer::linalg::solvers::Solve;
use sporadic_ferrante2016::examples::example2;
use sporadic_ferrante2016::{DesignOptions, LmiForm, Plant, SamplingWindow, design};
use sporadic_sim::SimRng;

/// `A = V diag(−(0.3 + 0.4 i)) V⁻¹` with `V = I + U(−0.3, 0.3)`, `M ~ U(−1, 1)^{1×n}`.
fn random_plant(n: usize) -> Plant {
    let mut rng = SimRng::new(n as u64);
    let v = Mat::from_fn(n, n, |i, j| {
        f64::from(u8::from(i == j)) + rng.uniform(-0.3, 0.3)
    });
    let d = Mat::from_fn(
        n,
        n,
        |i, j| if i == j { -(0.3 + 0.4 * i as f64) } else { 0.0 },
    );
    let vinv = v.partial_piv_lu().solve(Mat::<f64>::identity(n, n));
    let a = &v * &d * &vinv;
    let m = Mat::from_fn(1, n, |_, _| rng.uniform(-1.0, 1.0));
    Plant::new(a.as_ref(), m.as_ref()).expect("plant")
}

fn options(form: LmiForm) -> DesignOptions {
    DesignOptions {
        form,
        ..Default::default()
    }
}

fn bench(c: &mut Criterion) {
    let ex = example2().expect("example 2");
    let mut g = c.benchmark_group("ferrante2016/example2");
    g.sample_size(20);
    for (name, form) in [
        ("corollary1", LmiForm::Corollary1),
        ("reduced", LmiForm::Reduced),
    ] {
        let opts = options(form);
        g.bench_function(name, |b| {
            b.iter(|| black_box(design(&ex.plant, &ex.window, &opts).expect("design")))
        });
    }
    g.finish();

    let max_n: usize = std::env::var("FERRANTE_BENCH_MAX_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(8);
    let window = SamplingWindow::new(0.1, 0.6).expect("window");
    for (name, form) in [
        ("random_corollary1", LmiForm::Corollary1),
        ("random_reduced", LmiForm::Reduced),
    ] {
        let mut g = c.benchmark_group(format!("ferrante2016/{name}"));
        g.sample_size(10);
        g.warm_up_time(Duration::from_millis(100));
        let opts = options(form);
        for n in 2..=max_n {
            let plant = random_plant(n);
            let d = design(&plant, &window, &opts).expect("random design");
            assert_eq!(d.embedding.vertex_count(), 1 << n);
            g.bench_with_input(BenchmarkId::from_parameter(n), &plant, |b, plant| {
                b.iter(|| black_box(design(plant, &window, &opts).expect("design")))
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
