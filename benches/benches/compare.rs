//! `sporadic compare` in process (the facade's [`sporadic::methods::compare`]): for every method,
//! the design at the plant file's window and the search of the largest certified `T2` with the
//! file's `T1`, with the command's default 25 s budget. Plants from the corpus of issue 22
//! (`tests/corpus/`), chosen to span the methods: a badly scaled linear plant, a plant with
//! disturbance bounds (rabehi2021 applies), a Lipschitz plant (etienne2017 applies) and a
//! round-robin plant (sferlazza2021 on three sensors).
//!
//! The goal of issue 22 is at most 10 s per plant of order ≤ 6 and a median of at most 2 s over the
//! whole corpus; `benches/scripts/corpus.sh` times every corpus plant once and reports the
//! slowest, which is too slow for repeated criterion samples.
//!
//! Run: `cargo bench -p sporadic-benches --bench compare -- --warm-up-time 1 --measurement-time 10`

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use sporadic::methods;
use sporadic::model::MethodOptions;
use sporadic::plant_file::PlantFile;

const PLANTS: [&str; 4] = [
    "badly-scaled-units",
    "bounded-mass-spring",
    "lipschitz-pendulum",
    "round-robin-three-sensors",
];

fn compare(c: &mut Criterion) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/corpus");
    let options = MethodOptions {
        time_limit: Some(Duration::from_secs(25)),
        ..MethodOptions::default()
    };
    let mut group = c.benchmark_group("compare");
    group.sample_size(10);
    for name in PLANTS {
        let file = PlantFile::read(&dir.join(format!("{name}.toml"))).expect("corpus plant");
        let limit = methods::default_limit(&file);
        group.bench_function(name, |b| {
            b.iter(|| {
                methods::compare(black_box(&file), &options, limit, &mut |_, _| {})
                    .expect("compare")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, compare);
criterion_main!(benches);
