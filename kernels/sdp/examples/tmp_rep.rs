//! tmp
use std::time::Instant;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let p = sporadic_sdp::read_sdpa_file(&args[1]).unwrap();
    let n: usize = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(20);
    let mut s = sporadic_sdp::Settings::default();
    if let Ok(t) = std::env::var("SPT") {
        s.threads = t.parse().unwrap();
    }
    let mut ts = vec![];
    let mut it = 0;
    for _ in 0..n {
        let t = Instant::now();
        let sol = sporadic_sdp::solve(&p, &s).unwrap();
        ts.push(t.elapsed().as_secs_f64() * 1e3);
        it = sol.iterations;
    }
    let first = ts[0];
    ts.sort_by(f64::total_cmp);
    println!(
        "first {:.3} min {:.3} med {:.3} ms it {}",
        first,
        ts[0],
        ts[n / 2],
        it
    );
}
