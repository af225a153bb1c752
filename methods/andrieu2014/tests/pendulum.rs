//! Theorem 2 checked on a run: the theorem-conforming design on the globally Lipschitz pendulum
//! (`f2 = −sin x1`, `c ≡ 1`), K = [−2, −1]', α = 0.2, a1 = 0.069328, a3 = 4, a2 = 56.2298,
//! x(0) = (1, 0), x̂(0) = (−1, 2), L(0) = 1, horizon 2, noise-free.

mod common;

use sporadic_andrieu2014::pendulum::Pendulum;
use sporadic_andrieu2014::{Design, NormalFormPlant, RunOptions, lyapunov_steps, run};
use sporadic_sim::{PiecewiseConstant, ZeroNoise};

#[test]
fn c1_c2_theorem_run_on_the_pendulum() {
    let design = Design::binomial(2, 1.0).unwrap();
    let tuning = design.theorem_tuning(0.2).unwrap();
    let input = PiecewiseConstant::constant(vec![]).unwrap();
    let r = run(
        &NormalFormPlant(Pendulum),
        &[1.0, 0.0],
        &Pendulum,
        &[-1.0, 2.0],
        &input,
        &tuning,
        &mut ZeroNoise::new(1),
        &RunOptions::new(2.0),
    )
    .unwrap();
    let sup_l = common::assert_invariants(&r, &tuning, 1e-7);
    assert_eq!(r.c_max, 1.0);

    // Independent reference implementation: ~7 600 samples, L^- in [6.43, 807],
    // δ in [2.5e-4, 0.031].
    let n = r.sampling_times().len();
    let lmin = r
        .samples
        .iter()
        .map(|s| s.l_minus)
        .fold(f64::INFINITY, f64::min);
    let dmin = r
        .samples
        .iter()
        .map(|s| s.delta)
        .fold(f64::INFINITY, f64::min);
    let dmax = r.samples.iter().map(|s| s.delta).fold(0.0, f64::max);
    println!(
        "C2: {n} sampling instants, L^- in [{lmin:.4}, {sup_l:.2}], delta in [{dmin:.3e}, {dmax:.4}]"
    );
    assert!((7_400..=7_800).contains(&n), "{n} samples");
    assert!(
        (lmin - 6.43).abs() < 0.01 && (sup_l - 807.0).abs() < 1.0,
        "L^- range [{lmin}, {sup_l}]"
    );
    assert!(
        (dmin - 2.5e-4).abs() < 0.05e-4 && (dmax - 0.031).abs() < 0.0005,
        "delta range [{dmin}, {dmax}]"
    );

    // The Lyapunov decrease of Step 3 at every sample with ‖e_k‖ > 1e-7.
    let steps = lyapunov_steps(&design, &tuning, &r).unwrap();
    let checked: Vec<_> = steps.iter().filter(|s| s.error_norm > 1e-7).collect();
    let violations = checked.iter().filter(|s| !s.holds(1e-9)).count();
    println!(
        "C1: {} samples checked, {violations} violations",
        checked.len()
    );
    assert!(
        checked.len() > 100,
        "only {} samples with ‖e‖ > 1e-7",
        checked.len()
    );
    assert_eq!(violations, 0);

    // High-gain peaking (independent reference implementation: ‖e‖ goes 2.8 → 7.7 over the first
    // samples), then decay to machine zero.
    let norm = |v: Vec<f64>| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let norms: Vec<f64> = r.samples.iter().map(|s| norm(s.error())).collect();
    let first = norm(r.samples[0].error_minus());
    let peak = norms.iter().copied().fold(0.0, f64::max);
    let last = *norms.last().unwrap();
    println!(
        "C2: ‖e(t_1^-)‖ = {first:.4}, ‖e(t_2)‖ = {:.4}, peak ‖e_k‖ = {peak:.3}, final ‖e‖ = {last:.3e}",
        norms[1]
    );
    assert!((first - 2.82).abs() < 0.01 && (norms[1] - 7.72).abs() < 0.01);
    assert!(peak >= norms[1] && peak < 20.0, "peak {peak}");
    assert!(last < 1e-12, "final error {last}");
}
