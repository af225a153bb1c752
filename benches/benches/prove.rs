//! Rigorous proofs of designs (issue 24) against the designs themselves, in process through the
//! facade: for every example plant file (`examples/*.toml`) and every method that certifies it,
//! `design/<file>/<method>` times the design and `prove/<file>/<method>` the proof of that
//! design ([`sporadic::methods::prove`]). The goal is a proof time of at most
//! max(10 × design time, 2 s) for each pair; the ratio is read from the two groups of the same
//! run.
//!
//! Run: `cargo bench -p sporadic-benches --bench prove -- --warm-up-time 1 --measurement-time 5`

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use sporadic::methods;
use sporadic::model::{MethodOptions, ProofOptions};
use sporadic::plant_file::PlantFile;

fn prove(c: &mut Criterion) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("examples folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    let options = MethodOptions::default();
    let mut design_group = c.benchmark_group("design");
    design_group.sample_size(10);
    let mut pairs = Vec::new();
    for path in &files {
        let file = PlantFile::read(path).expect("example plant file");
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        for method in methods::registry() {
            let Ok(d) = methods::design(&file, method.as_ref(), &options) else {
                continue;
            };
            if !d.status.is_certified() {
                continue;
            }
            let name = format!("{stem}/{}", method.id());
            design_group.bench_function(&name, |b| {
                b.iter(|| methods::design(black_box(&file), method.as_ref(), &options))
            });
            pairs.push((name, file.clone(), method, d));
        }
    }
    design_group.finish();
    let mut prove_group = c.benchmark_group("prove");
    prove_group.sample_size(10);
    for (name, file, method, d) in &pairs {
        prove_group.bench_function(name, |b| {
            b.iter(|| {
                methods::prove(
                    black_box(file),
                    method.as_ref(),
                    d,
                    &ProofOptions::default(),
                )
                .expect("prove")
            })
        });
    }
    prove_group.finish();
}

criterion_group!(benches, prove);
criterion_main!(benches);
