//! Sferlazza et al. (2021), §5.3 validation pass and design loop on the §6 quarter-car example
//! (n = 4, m_σ = 1, so Ξ_σ(τ) is 7×7 and its τ-dependent block 3×3).
//!
//! * `sferlazza2021/validation_n4`: throughput (τ-points per second) of the validation of
//!   `Ξ_σ(τ) ≻ μI` with the iteration-1 P* of (47) on a uniform grid of each window, μ = 0.01:
//!   - `fast_1thread`: [`XiFamily::validate_grid`] on one thread (ExpmStepper, Schur complement on
//!     the constant P_Γ block, fused 3×3 quadratic form and Cholesky pass/fail, eigenvalues only at
//!     failing points near the minimum);
//!   - `fast_rayon`: the same on all cores (chunks in parallel);
//!   - `naive_1thread`: the reference, one fresh `expm` and one full symmetric eigenvalue
//!     decomposition of Ξ_σ(τ) per point ([`validate_naive`]), on the same grid.
//!
//!   σ = 1 passes everywhere at iteration 1; σ = 2 fails on ≈ 70 % of its window (the buffered re-test and eigenvalues near the minimum run).
//! * `sferlazza2021/synthesis`: one solve of (47) at iteration 1.
//! * `sferlazza2021/design`: the whole §5.3 design (Step 1, Proposition 1 screen, 3 iterations on the
//!   paper's (49) grids of ≈ 4.4·10⁶ points per sensor).
//!
//! Run: `cargo bench -p sporadic-benches --bench sferlazza2021`

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use sporadic_sferlazza2021::design::{DesignOptions, design};
use sporadic_sferlazza2021::example::suspension;
use sporadic_sferlazza2021::synthesis::{Synthesis, default_solve_options};
use sporadic_sferlazza2021::validation::{
    UniformGrid, ValidationOptions, XiFamily, validate_naive,
};

const POINTS: usize = 100_000;
const MU: f64 = 0.01;

fn bench(c: &mut Criterion) {
    let plant = suspension().expect("example plant");
    let p = Synthesis::new(&plant, MU, &default_solve_options())
        .and_then(|mut s| s.solve())
        .expect("(47)")
        .p;

    let mut g = c.benchmark_group("sferlazza2021/validation_n4");
    g.sample_size(10);
    g.throughput(Throughput::Elements(POINTS as u64));
    for sigma in 0..2 {
        let fam = XiFamily::new(&plant, &p, sigma).expect("family");
        let w = plant.sensor(sigma).expect("sensor").window();
        let grid =
            UniformGrid::covering(w, (w.t2() - w.t1()) / (POINTS - 1) as f64, 1e9).expect("grid");
        let seq = ValidationOptions {
            parallel: false,
            ..ValidationOptions::default()
        };
        let par = ValidationOptions::default();
        let id = format!("sigma{}", sigma + 1);
        g.bench_function(BenchmarkId::new("fast_1thread", &id), |b| {
            b.iter(|| black_box(fam.validate_grid(grid, MU, &seq).expect("validation")))
        });
        g.bench_function(BenchmarkId::new("fast_rayon", &id), |b| {
            b.iter(|| black_box(fam.validate_grid(grid, MU, &par).expect("validation")))
        });
        g.bench_function(BenchmarkId::new("naive_1thread", &id), |b| {
            b.iter(|| black_box(validate_naive(&fam, grid, MU).expect("naive")))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("sferlazza2021/synthesis");
    g.bench_function("iteration1_sdp47", |b| {
        b.iter(|| {
            let mut s = Synthesis::new(&plant, MU, &default_solve_options()).expect("(47)");
            black_box(s.solve().expect("solve").p_star)
        })
    });
    g.finish();

    let mut g = c.benchmark_group("sferlazza2021/design");
    g.sample_size(10);
    g.bench_function("suspension_paper_grid", |b| {
        b.iter(|| {
            black_box(
                design(&plant, &DesignOptions::default())
                    .expect("design")
                    .p_star,
            )
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
