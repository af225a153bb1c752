//! Spec §5 acceptance check 9: simulations of the nonlinear plant and observer (setup of spec
//! §4.4: x(0) = 0, x̂(0) = (1,1,1,1)', |z(0)| = 2) with the printed gains, for constant,
//! alternating and i.i.d. uniform sampling; along every run the Lyapunov function z'P1z just
//! after the samples decreases (proof of Theorem 3).

use sporadic_etienne2017::{
    DesignOptions, GainSchedule, Plant, SimulationSetup, analyse_margin, error_norm_after, example,
    lyapunov_at_samples, simulate_observer, worst_case_sampling,
};
use sporadic_sim::{FromData, SamplingRule, Simulation, UniformRandom};

fn run(plant: &Plant, k: &GainSchedule, rule: &mut dyn SamplingRule, horizon: f64) -> Simulation {
    let setup = SimulationSetup::new(vec![0.0; 4], vec![1.0; 4], horizon);
    simulate_observer(plant, &example::phi, &example::input, k, rule, &setup).unwrap()
}

fn alternating(a: f64, b: f64, count: usize) -> FromData {
    let v: Vec<f64> = (0..count).map(|i| if i % 2 == 0 { a } else { b }).collect();
    FromData::from_slice(&v).unwrap()
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
fn static_gain_constant_sampling_matches_reference() {
    let plant = example::flexible_joint().unwrap();
    let k = example::paper_static_schedule(sporadic_etienne2017::Window::new(0.01, 0.2).unwrap())
        .unwrap();
    let sim = run(
        &plant,
        &k,
        &mut FromData::from_slice(&[0.2; 25]).unwrap(),
        4.5,
    );
    assert!(!sim.exact); // nonlinear: the adaptive integrator was used
    let e = sim.error_arc().unwrap();
    // Spec §4.5 (RK4, h = 1e-3): |z(1)| = 9.6e-3, |z(2)| = 2.8e-4, |z(4)| = 4.8e-7 (after the
    // samples at t = 1, 2, 4).
    for (t, want) in [(1.0, 9.6e-3), (2.0, 2.8e-4), (4.0, 4.8e-7)] {
        let got = error_norm_after(&e, t).unwrap();
        assert!(
            (got - want).abs() < 0.06 * want,
            "|z({t})| = {got:e}, spec {want:e}"
        );
    }
    assert!(error_norm_after(&e, 4.0).unwrap() < 1e-5 * 2.0);
    assert_lyapunov_decreases(&sim, &k, &plant, "static, τ ≡ 0.2");
}

#[test]
fn time_varying_gain_constant_and_alternating_sampling() {
    let plant = example::flexible_joint().unwrap();
    let k = example::paper_tv_schedule().unwrap();
    let sim = run(
        &plant,
        &k,
        &mut FromData::from_slice(&[0.3; 16]).unwrap(),
        4.5,
    );
    let z4 = error_norm_after(&sim.error_arc().unwrap(), 4.0).unwrap();
    assert!(z4 < 1e-3 * 2.0, "|z(4)| = {z4:e}");
    assert_lyapunov_decreases(&sim, &k, &plant, "TV, τ ≡ 0.3");
    let sim = run(&plant, &k, &mut alternating(0.3, 0.01, 40), 4.5);
    let z4 = error_norm_after(&sim.error_arc().unwrap(), 4.0).unwrap();
    assert!(z4 < 1e-2 * 2.0, "|z(4)| = {z4:e}");
    assert_lyapunov_decreases(&sim, &k, &plant, "TV, alternating 0.3/0.01");
}

#[test]
fn random_and_adversarial_sampling_converge() {
    let plant = example::flexible_joint().unwrap();
    let ks = example::paper_static_schedule(sporadic_etienne2017::Window::new(0.01, 0.2).unwrap())
        .unwrap();
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
