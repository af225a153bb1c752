//! Example 1 of Ferrante et al. (2016): scalar plant A = M = 1, T1 = T2 = 1, P = 1, L = 1.1 − e^{−1}.
//! Expected values are closed forms and the paper's printed digits.

use std::f64::consts::E;

use approx::assert_relative_eq;
use sporadic_ferrante2016::examples::{example1, example1_paper};
use sporadic_ferrante2016::{
    BoundOptions, DesignOptions, LmiForm, VerifyOptions, analyse, bound_constants, check_bound,
    design, simulate_error, verify,
};
use sporadic_sim::{LtiFlow, Periodic, Record, SampleEvent, SimOptions, SimRng, simulate_hybrid};

/// The paper's construction: LMI (41) as printed (the library's default is its reduced form).
fn paper() -> DesignOptions {
    DesignOptions {
        form: LmiForm::Corollary1,
        ..DesignOptions::default()
    }
}

/// Rounds to `digits` decimals (the paper prints 4).
fn round(x: f64, digits: i32) -> f64 {
    let s = 10f64.powi(digits);
    (x * s).round() / s
}

#[test]
fn theorem1_constants_match_closed_forms_and_paper() {
    let ex = example1().unwrap();
    let c = bound_constants(
        &ex.plant,
        &ex.window,
        ex.l.as_ref(),
        ex.p.as_ref(),
        &BoundOptions::default(),
    )
    .unwrap()
    .theorem1;
    let l = 1.1 - 1.0 / E;
    // Closed forms: α1 = 1 (τ = 0), α2 = e² (τ = T2 = 1), β = 1 − (1−L)²e².
    let beta = 1.0 - (1.0 - l).powi(2) * E * E;
    let theta = (1.0 - beta / (E * E)).ln();
    assert_relative_eq!(c.alpha1, 1.0, max_relative = 1e-12);
    assert_relative_eq!(c.alpha2, E * E, max_relative = 1e-12);
    assert_relative_eq!(c.beta, beta, max_relative = 1e-12);
    assert_relative_eq!(c.theta, theta, max_relative = 1e-12);
    assert_relative_eq!(c.gamma, theta.abs() / 2.0, max_relative = 1e-12);
    assert_relative_eq!(c.r, theta.abs() / 2.0, max_relative = 1e-12);
    // Independent [ours] values (1e-6 relative).
    assert_relative_eq!(c.beta, 0.4697658047, max_relative = 1e-8);
    assert_relative_eq!(c.theta, -0.0656867943, max_relative = 1e-8);
    assert_relative_eq!(c.gamma, 0.0328433971, max_relative = 1e-8);
    assert_relative_eq!(c.kappa, 2.7632892, max_relative = 1e-6);
    assert_relative_eq!(c.kappa_printed, 2.8090417, max_relative = 1e-6);
    // The paper's printed digits.
    assert_eq!(round(l, 4), example1_paper::L);
    assert_eq!(round(c.beta, 4), example1_paper::BETA);
    assert_eq!(round(c.theta, 4), example1_paper::THETA);
    assert_eq!(round(c.gamma, 4), example1_paper::GAMMA);
    assert_eq!(round(c.r, 4), example1_paper::R);
    assert!(!c.beta_capped);
}

#[test]
fn theorem2_constants_match_closed_forms() {
    let ex = example1().unwrap();
    let c = bound_constants(
        &ex.plant,
        &ex.window,
        ex.l.as_ref(),
        ex.p.as_ref(),
        &BoundOptions::default(),
    )
    .unwrap()
    .theorem2;
    let l = 1.1 - 1.0 / E;
    let beta = 1.0 - (1.0 - l).powi(2) * E * E;
    let theta_eta = (1.0 - beta / (2.0 * E * E)).ln();
    let rho = E * E * (2.0 / beta + 1.0);
    assert_relative_eq!(c.theta_eta, theta_eta, max_relative = 1e-12);
    assert_relative_eq!(c.rho_printed, rho, max_relative = 1e-12);
    // ‖P‖ = 1 ⇒ both ρ variants coincide.
    assert_relative_eq!(c.rho_derived, rho, max_relative = 1e-12);
    assert_relative_eq!(
        c.noise_gain,
        l * (4.0 * rho * E * E / beta).sqrt(),
        max_relative = 1e-12
    );
    // Independent [ours] values.
    assert_relative_eq!(c.theta_eta, -0.0323041497, max_relative = 1e-8);
    assert_relative_eq!(c.rho_derived, 38.847523, max_relative = 1e-7);
    assert_relative_eq!(c.noise_gain, 36.194956, max_relative = 1e-7);
    assert_relative_eq!(c.transient, 3.8754029, max_relative = 1e-7);
    assert_relative_eq!(c.gamma_eta, 0.0161520749, max_relative = 1e-7);
}

#[test]
fn condition12_window_of_gains() {
    // (12) ⇔ |1 − L| < e^{−1}: L = 0.7321 passes, 0.6 and 1.4 fail.
    let ex = example1().unwrap();
    let check = |l: f64| {
        verify(
            &ex.plant,
            &ex.window,
            faer::mat![[l]].as_ref(),
            ex.p.as_ref(),
            &VerifyOptions::default(),
        )
        .unwrap()
    };
    let ok = check(1.1 - 1.0 / E);
    assert!(ok.passed());
    assert_relative_eq!(ok.max_spectral_radius, 1.0 - 0.1 * E, max_relative = 1e-12);
    assert!(!check(0.6).passed());
    assert!(!check(1.4).passed());
}

#[test]
fn lmi41_certifies_exactly_the_admissible_gains() {
    // X_1 = e, feasible iff |1 − L| < e^{−1}.
    let ex = example1().unwrap();
    let opts = paper();
    let certify = |l: f64| analyse(&ex.plant, &ex.window, faer::mat![[l]].as_ref(), &opts).unwrap();
    let ok = certify(1.1 - 1.0 / E);
    assert!(ok.certified, "{:?}", ok.stats);
    assert_eq!(ok.embedding.vertex_count(), 1);
    assert!(!certify(0.6).certified);
    assert!(!certify(1.4).certified);
    let d = design(&ex.plant, &ex.window, &opts).unwrap();
    let l = d.l[(0, 0)];
    assert!(1.0 - 1.0 / E < l && l < 1.0 + 1.0 / E, "L = {l}");
    assert!(d.verification.passed());
}

#[test]
fn bound_holds_along_the_simulated_solution_with_equality_at_first_jump() {
    // ε(0,0) = 1, τ(0,0) = 1; per-period contraction (1 − L)e; bound touched at t = 1⁻.
    let ex = example1().unwrap();
    let c = bound_constants(
        &ex.plant,
        &ex.window,
        ex.l.as_ref(),
        ex.p.as_ref(),
        &BoundOptions::default(),
    )
    .unwrap()
    .theorem1;
    let arc = simulate_error(
        &ex.plant,
        ex.l.as_ref(),
        &mut Periodic::new(1.0).unwrap(),
        &[1.0],
        &SimOptions::new(30.0).record(Record::Every(0.01)),
    )
    .unwrap();
    let check = check_bound(&arc, &c).unwrap();
    assert_eq!(arc.num_jumps(), 30);
    assert!(check.max_ratio <= 1.0 + 1e-12, "ratio {}", check.max_ratio);
    assert!(check.max_ratio >= 1.0 - 1e-12, "ratio {}", check.max_ratio);
    assert_eq!(check.j, 0);
    assert_relative_eq!(check.t, 1.0, max_relative = 1e-12);
    // At every jump (both sides) the bound holds, and the post-jump values contract by (1 − L)e.
    let l = 1.1 - 1.0 / E;
    let jumps = arc.jumps();
    for w in jumps.windows(2) {
        let ratio = arc.state(w[1].after)[0] / arc.state(w[0].after)[0];
        assert_relative_eq!(ratio, 0.7281718171540955, max_relative = 1e-10);
        assert_relative_eq!(ratio, (1.0 - l) * E, max_relative = 1e-10);
    }
}

#[test]
fn iss_bound_holds_with_bounded_measurement_noise() {
    // Theorem 2: ε⁺ = (1 − L)ε − Lη with |η| ≤ η̄ at the jumps; (35) with ρd must hold.
    let ex = example1().unwrap();
    let k = bound_constants(
        &ex.plant,
        &ex.window,
        ex.l.as_ref(),
        ex.p.as_ref(),
        &BoundOptions::default(),
    )
    .unwrap()
    .theorem2;
    let l = ex.l[(0, 0)];
    for (seed, eta_bar) in [(1u64, 1e-3), (2, 0.1), (3, 1.0)] {
        let mut rng = SimRng::new(seed);
        let jump = move |_: &SampleEvent, _: &[f64], x: &mut [f64]| {
            let eta = rng.uniform(-eta_bar, eta_bar);
            x[0] = (1.0 - l) * x[0] - l * eta;
            Ok(())
        };
        let sim = simulate_hybrid(
            LtiFlow::new(ex.plant.a()).unwrap(),
            jump,
            &mut Periodic::new(1.0).unwrap(),
            &[1.0],
            &SimOptions::new(60.0).record(Record::Every(0.05)),
        )
        .unwrap();
        for (ht, x) in sim.arc.iter() {
            let b = k.bound(ht.t, ht.j, 1.0, eta_bar);
            assert!(
                x[0].abs() <= b,
                "seed {seed}: |ε| = {} > bound {b} at {ht:?}",
                x[0].abs()
            );
        }
    }
}
