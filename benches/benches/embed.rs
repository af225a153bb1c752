//! Vertex construction of `sporadic-embed` for n = 2..12 (issue 4, "Performance").
//!
//! For every order n a deterministic random matrix with distinct eigenvalues (real and complex)
//! is embedded on the window [T1, T2] = [0.2, 3] (Ferrante et al. 2016, Example 2) by
//!
//! * the residue box (Ferrante et al. 2016, §4.1): `residue_decomposition` (contour moments,
//!   independent of the window), `residue_vertices` (coefficient extrema, 2^K box corners and
//!   the 201-point reconstruction self-check) and `residue_total` (both);
//! * the Taylor polytope (Rabehi et al. 2021, §IV) with the order chosen for a
//!   remainder bound of 1e-10;
//!
//! and, as the reference measured in the same run, one matrix exponential `e^{A T2}`
//! (sporadic-linalg, Al-Mohy & Higham 2009) of the same matrix. Before the timings a table of
//! vertex counts, number of expansion terms K, containment statements and Taylor orders is
//! printed to stderr.
//!
//! Run: `cargo bench -p sporadic-benches --bench embed -- --warm-up-time 1 --measurement-time 2`

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion};
use faer::Mat;
use sporadic_embed::{
    Method, ResidueExpansion, TaylorOptions, residue_embedding, taylor_embedding,
};
use sporadic_linalg::expm_scaled;

const ORDERS: std::ops::RangeInclusive<usize> = 2..=12;
const T1: f64 = 0.2;
const T2: f64 = 3.0;

/// Deterministic pseudo-random matrix: entries uniform in [−1, 1), scaled to spectral norm 1,
/// shifted by −0.3 I (eigenvalue real parts in about [−1.3, 0.7]; generically distinct).
fn test_matrix(n: usize) -> Mat<f64> {
    let mut state = 0x9e37_79b9_7f4a_7c15u64 ^ (n as u64).wrapping_mul(0x2545_f491_4f6c_dd1d);
    let r = Mat::from_fn(n, n, |_, _| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        2.0 * ((state >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    });
    let norm = r
        .singular_values()
        .expect("singular values")
        .into_iter()
        .fold(0.0, f64::max);
    Mat::from_fn(n, n, |i, j| {
        r[(i, j)] / norm - if i == j { 0.3 } else { 0.0 }
    })
}

fn report() {
    eprintln!("== embeddings of e^(Aτ), τ ∈ [{T1}, {T2}] ==");
    eprintln!(
        "{:>3} {:>3} {:>5} {:>9} {:>12} {:>14} {:>6} {:>9} {:>10}",
        "n", "K", "free", "vertices", "recon err", "containment", "N", "vertices", "remainder"
    );
    for n in ORDERS {
        let a = test_matrix(n);
        let r = residue_embedding(a.as_ref(), T1, T2).expect("residue embedding");
        let Method::Residue {
            terms,
            free_terms,
            reconstruction_error,
            ..
        } = *r.method()
        else {
            unreachable!("residue method")
        };
        let containment = match r.containment() {
            sporadic_embed::Containment::Guaranteed => "guaranteed".to_string(),
            sporadic_embed::Containment::VerifiedOnGrid { points, .. } => {
                format!("grid({points})")
            }
            sporadic_embed::Containment::NotGuaranteed { .. } => "NOT".to_string(),
        };
        let t = taylor_embedding(a.as_ref(), T1, T2, &TaylorOptions::default())
            .expect("Taylor embedding");
        let Method::Taylor { order } = *t.method() else {
            unreachable!("Taylor method")
        };
        eprintln!(
            "{n:>3} {terms:>3} {free_terms:>5} {:>9} {reconstruction_error:>12.1e} {containment:>14} {order:>6} {:>9} {:>10.1e}",
            r.vertex_count(),
            t.vertex_count(),
            t.remainder_bound()
        );
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("embed");
    group.sample_size(20);
    for n in ORDERS {
        let a = test_matrix(n);
        group.bench_with_input(BenchmarkId::new("expm_reference", n), &a, |b, a| {
            b.iter(|| expm_scaled(black_box(a.as_ref()), T2).expect("expm"))
        });
        group.bench_with_input(BenchmarkId::new("residue_decomposition", n), &a, |b, a| {
            b.iter(|| ResidueExpansion::new(black_box(a.as_ref())).expect("residues"))
        });
        let expansion = ResidueExpansion::new(a.as_ref()).expect("residues");
        group.bench_with_input(
            BenchmarkId::new("residue_vertices", n),
            &expansion,
            |b, e| b.iter(|| black_box(e).embed(T1, T2).expect("vertices")),
        );
        group.bench_with_input(BenchmarkId::new("residue_total", n), &a, |b, a| {
            b.iter(|| residue_embedding(black_box(a.as_ref()), T1, T2).expect("embedding"))
        });
        group.bench_with_input(BenchmarkId::new("taylor_1e-10", n), &a, |b, a| {
            b.iter(|| {
                taylor_embedding(black_box(a.as_ref()), T1, T2, &TaylorOptions::default())
                    .expect("Taylor")
            })
        });
    }
    group.finish();
}

fn main() {
    report();
    let mut c = Criterion::default().configure_from_args();
    bench(&mut c);
    c.final_summary();
}
