//! Simulations of the nonlinear plant and observer (x(0) = 0, x̂(0) = (1,1,1,1)', |z(0)| = 2)
//! with the printed gains, for constant, alternating, i.i.d. uniform and adversarial sampling.
//! The reference values of an independent simulation (fixed-step RK4) are the error just after the first sample at or after t; along every run the
//! Lyapunov function z'P1z just after the samples decreases (proof of Theorem 3).

use sporadic_etienne2017::{
    DesignOptions, GainSchedule, Plant, SamplingWindow, SimulationSetup, analyse_margin,
    error_norm_after, error_norm_after_sample, example, lyapunov_at_samples, simulate_observer,
    worst_case_sampling,
};
use sporadic_sim::{FromData, Periodic, SamplingRule, Simulation, UniformRandom};

/// Past the first samples at or after t = 4 of every sequence below (4.0, 4.19, 4.2, 4.02) and on
/// none of their sample instants.
const HORIZON: f64 = 4.25;

fn run(plant: &Plant, k: &GainSchedule, rule: &mut dyn SamplingRule, horizon: f64) -> Simulation {
    let setup = SimulationSetup::new(vec![0.0; 4], vec![1.0; 4], horizon);
    simulate_observer(plant, &example::phi, &example::input, k, rule, &setup).unwrap()
}

fn alternating(a: f64, b: f64, count: usize) -> FromData {
    let v: Vec<f64> = (0..count).map(|i| if i % 2 == 0 { a } else { b }).collect();
    FromData::from_slice(&v).unwrap()
}

/// `|z|` after the first sample at or after each `t` against the reference's 2-significant-figure
/// values (one unit of the last digit), and the sample instant found.
fn assert_reference(sim: &Simulation, refs: &[(f64, f64, f64)], what: &str) {
    let e = sim.error_arc().unwrap();
    for &(t, tk_want, want) in refs {
        let (tk, got) = error_norm_after_sample(&e, t).unwrap();
        assert!(
            (tk - tk_want).abs() < 1e-9,
            "{what}: sample {tk} vs {tk_want}"
        );
        let unit = 10f64.powf(want.log10().floor() - 1.0);
        assert!(
            (got - want).abs() <= unit,
            "{what}: |z| after t = {t} is {got:e}, reference {want:e}"
        );
    }
}

/// `V_k` strictly decreasing while it is well above the integrator's noise floor.
fn assert_lyapunov_decreases(sim: &Simulation, k: &GainSchedule, plant: &Plant, what: &str) {
    let p1 = analyse_margin(plant, k, &DesignOptions::default())
        .unwrap()
        .certificate
        .p1;
    let v = lyapunov_at_samples(&sim.error_arc().unwrap(), p1.as_ref()).unwrap();
    assert!(v.len() > 10, "{what}: {} samples", v.len());
    for w in v.windows(2) {
        if w[1].1 > 1e-16 {
            assert!(
                w[1].1 < w[0].1,
                "{what}: V rose from {:e} to {:e} at t = {}",
                w[0].1,
                w[1].1,
                w[1].0
            );
        }
    }
}

#[test]
fn static_gain_matches_reference() {
    let plant = example::flexible_joint().unwrap();
    let k = example::paper_static_schedule(SamplingWindow::new(0.01, 0.2).unwrap()).unwrap();
    let sim = run(&plant, &k, &mut Periodic::new(0.2).unwrap(), HORIZON);
    assert!(!sim.exact); // nonlinear: the adaptive integrator was used
    // Reference simulation: |z(1)| = 9.6e-3, |z(2)| = 2.8e-4, |z(4)| = 4.8e-7.
    assert_reference(
        &sim,
        &[(1.0, 1.0, 9.6e-3), (2.0, 2.0, 2.8e-4), (4.0, 4.0, 4.8e-7)],
        "static, τ ≡ 0.2",
    );
    // Acceptance: |z(4)| < 1e-5·|z(0)|.
    assert!(error_norm_after(&sim.error_arc().unwrap(), 4.0).unwrap() < 1e-5 * 2.0);
    assert_lyapunov_decreases(&sim, &k, &plant, "static, τ ≡ 0.2");
    // Alternating 0.2, 0.01: samples at 2.09 and 4.19 are the first after 2 and 4.
    let sim = run(&plant, &k, &mut alternating(0.2, 0.01, 44), HORIZON);
    assert_reference(
        &sim,
        &[(2.0, 2.09, 2.6e-5), (4.0, 4.19, 1.8e-9)],
        "static, alternating 0.2/0.01",
    );
    assert_lyapunov_decreases(&sim, &k, &plant, "static, alternating");
}

#[test]
fn time_varying_gain_matches_reference() {
    let plant = example::flexible_joint().unwrap();
    let k = example::paper_tv_schedule().unwrap();
    let sim = run(&plant, &k, &mut Periodic::new(0.3).unwrap(), HORIZON);
    // Reference simulation: |z(1)| = 5.7e-2, |z(2)| = 4.9e-3, |z(4)| = 9.9e-5 (after the samples at 1.2,
    // 2.1 and 4.2).
    assert_reference(
        &sim,
        &[(1.0, 1.2, 5.7e-2), (2.0, 2.1, 4.9e-3), (4.0, 4.2, 9.9e-5)],
        "TV, τ ≡ 0.3",
    );
    // Acceptance: |z(4)| < 1e-3·|z(0)|.
    assert!(error_norm_after(&sim.error_arc().unwrap(), 4.0).unwrap() < 1e-3 * 2.0);
    assert_lyapunov_decreases(&sim, &k, &plant, "TV, τ ≡ 0.3");
    // Alternating 0.3, 0.01: first samples after 2 and 4 at 2.16 and 4.02.
    let sim = run(&plant, &k, &mut alternating(0.3, 0.01, 30), HORIZON);
    assert_reference(
        &sim,
        &[(2.0, 2.16, 8.2e-3), (4.0, 4.02, 3.1e-4)],
        "TV, alternating 0.3/0.01",
    );
    assert_lyapunov_decreases(&sim, &k, &plant, "TV, alternating 0.3/0.01");
}

#[test]
fn random_and_adversarial_sampling_converge() {
    let plant = example::flexible_joint().unwrap();
    let ks = example::paper_static_schedule(SamplingWindow::new(0.01, 0.2).unwrap()).unwrap();
    let ktv = example::paper_tv_schedule().unwrap();
    for (k, hi) in [(&ks, 0.2), (&ktv, 0.3)] {
        for seed in 0..3 {
            let mut rule = UniformRandom::new(0.01, hi, seed).unwrap();
            let sim = run(&plant, k, &mut rule, 8.0);
            let zt = error_norm_after(&sim.error_arc().unwrap(), 8.0).unwrap();
            assert!(
                zt < 1e-4 * 2.0,
                "seed {seed}, window [0.01, {hi}]: |z(8)| = {zt:e}"
            );
            assert_lyapunov_decreases(&sim, k, &plant, "uniform random");
        }
        let p1 = analyse_margin(&plant, k, &DesignOptions::default())
            .unwrap()
            .certificate
            .p1;
        for vertex in 0..2 {
            let mut adv = worst_case_sampling(&plant, k, p1.as_ref(), vertex, 30).unwrap();
            let sim = run(&plant, k, &mut adv, 8.0);
            let taus = sim.samples.intervals();
            assert!(
                taus.iter()
                    .all(|&t| (0.01 - 1e-12..=hi + 1e-12).contains(&t))
            );
            let zt = error_norm_after(&sim.error_arc().unwrap(), 8.0).unwrap();
            assert!(
                zt < 1e-2 * 2.0,
                "adversary on R_{}: |z(8)| = {zt:e}",
                vertex + 1
            );
            assert_lyapunov_decreases(&sim, k, &plant, "adversarial");
        }
    }
}
