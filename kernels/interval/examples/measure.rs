//! Quick (criterion-free) measurements: 10×10 interval product time, and width/time of the
//! enclosure of e^{Aτ} over [0.2, 0.21] for a few matrices.
//! Run: `cargo run --release -p sporadic-interval --example measure`.

use faer::{Mat, mat};
use sporadic_interval::{EnclosureOptions, IntervalMatrix, expm_enclosure};
use std::time::Instant;

fn main() {
    let n = 10;
    let a = Mat::from_fn(n, n, |i, j| ((i * n + j) * 7919 % 97) as f64 / 97.0 - 0.5);
    let b = Mat::from_fn(n, n, |i, j| {
        ((i * n + j) * 104_729 % 89) as f64 / 89.0 - 0.5
    });
    let r = Mat::from_fn(n, n, |_, _| 0.5e-10);
    let ia = IntervalMatrix::from_mid_rad(a, r.clone()).unwrap();
    let ib = IntervalMatrix::from_mid_rad(b, r).unwrap();
    let reps = 200_000;
    for _ in 0..3 {
        let t = Instant::now();
        let mut acc = 0.0;
        for _ in 0..reps {
            let c = std::hint::black_box(&ia) * std::hint::black_box(&ib);
            acc += c.rad()[(3, 3)];
        }
        println!(
            "10x10 midpoint-radius interval product: {:.2} µs  [{acc:.3e}]",
            t.elapsed().as_secs_f64() / reps as f64 * 1e6
        );
    }
    let cases: Vec<(&str, Mat<f64>)> = vec![
        (
            "stiff burkardt3 [[0,1],[-39,-40]]",
            mat![[0.0, 1.0], [-39.0, -40.0]],
        ),
        (
            "stiff Ward3 (3x3)",
            mat![
                [-131.0, 19.0, 18.0],
                [-390.0, 56.0, 54.0],
                [-387.0, 57.0, 52.0]
            ],
        ),
        (
            "stiff triangular diag(-1000,-1,-0.01)",
            mat![[-1000.0, 1.0, 0.0], [0.0, -1.0, 1.0], [0.0, 0.0, -0.01]],
        ),
        ("defective [[1,1],[0,1]]", mat![[1.0, 1.0], [0.0, 1.0]]),
        (
            "defective Jordan4(-2)",
            mat![
                [-2.0, 1.0, 0.0, 0.0],
                [0.0, -2.0, 1.0, 0.0],
                [0.0, 0.0, -2.0, 1.0],
                [0.0, 0.0, 0.0, -2.0]
            ],
        ),
        ("rotating w=10", mat![[0.0, 10.0], [-10.0, 0.0]]),
        ("rotating w=100", mat![[0.0, 100.0], [-100.0, 0.0]]),
        ("damped oscillator", mat![[-0.1, 5.0], [-5.0, -0.1]]),
        (
            "random 10x10",
            Mat::from_fn(10, 10, |i, j| {
                ((i * 10 + j) * 7919 % 97) as f64 / 48.5 - 1.0
            }),
        ),
    ];
    println!(
        "\n{:<40} {:>10} {:>8} {:>12} {:>12} {:>12} {:>10}",
        "A", "‖A‖∞", "pieces", "hull relw", "piece relw", "point relw", "time"
    );
    for (name, a) in &cases {
        let norm = (0..a.nrows())
            .map(|i| (0..a.ncols()).map(|j| a[(i, j)].abs()).sum::<f64>())
            .fold(0.0, f64::max);
        let t = Instant::now();
        let r = expm_enclosure(a.as_ref(), 0.2, 0.21, &EnclosureOptions::default());
        let el = t.elapsed();
        let p = expm_enclosure(a.as_ref(), 0.2, 0.2, &EnclosureOptions::default());
        match (r, p) {
            (Ok(r), Ok(p)) => println!(
                "{:<40} {:>10.3e} {:>8} {:>12.3e} {:>12.3e} {:>12.3e} {:>8.2?}",
                name,
                norm,
                r.pieces.len(),
                r.rel_width,
                r.max_piece_rel_width,
                p.rel_width,
                el
            ),
            (r, p) => println!("{name}: {:?} / {:?}", r.err(), p.err()),
        }
    }
    // One piece only (no subdivision), to show what subdivision buys.
    println!("\nsingle piece over [0.2, 0.21] (max_pieces = 1):");
    for (name, a) in &cases {
        let o = EnclosureOptions {
            max_pieces: 1,
            ..EnclosureOptions::default()
        };
        match expm_enclosure(a.as_ref(), 0.2, 0.21, &o) {
            Ok(r) => println!("{:<40} hull relw {:>10.3e}", name, r.rel_width),
            Err(e) => println!("{name}: {e}"),
        }
    }
}
