//! Simulation of the example (spec 004 §8 A9–A11): guaranteed inclusion with random admissible
//! disturbance, noise and sampling; the deterministic width; noise-free GES.

use faer::Mat;
use sporadic_rabehi2021::example::figure_scenario;
use sporadic_rabehi2021::example::{
    example_bounds, example_window, paper_gain, spring_mass_damper,
};
use sporadic_rabehi2021::ipr::{MetzlerDecomposition, gamma_of_gain};
use sporadic_rabehi2021::lyapunov::{lyapunov_value, theorem1_constants};
use sporadic_rabehi2021::observer::IntervalObserver;
use sporadic_rabehi2021::simulation::simulate_interval;
use sporadic_rabehi2021::system::Bounds;
use sporadic_rabehi2021::verify::GridOptions;
use sporadic_rabehi2021::width::WidthDynamics;

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// A9: zero inclusion violations (tolerance 1e-9) over 20 s for several seeds, both sides of
/// every jump; A10: widths never exceed the guaranteed bound.
#[test]
fn inclusion_with_disturbance_and_noise() {
    let plant = spring_mass_damper(1.0).unwrap();
    let obs = IntervalObserver::new(&plant, &example_bounds(), paper_gain().as_ref()).unwrap();
    let widths = WidthDynamics::new(&plant, &example_bounds(), paper_gain().as_ref()).unwrap();
    let bound = widths
        .guaranteed_bound(&example_window(), &[6.0, 6.0], 20_001)
        .unwrap();
    for seed in 0..4u64 {
        let mut sc = figure_scenario(true);
        sc.sampling_seed = 100 + seed;
        if let Some(d) = sc.disturbance.as_mut() {
            d.seed = 200 + seed;
        }
        let run = simulate_interval(&obs, &sc).unwrap();
        assert_eq!(run.inclusion.violations, 0, "{:?}", run.inclusion);
        assert!(run.inclusion.worst < 0.0, "{:?}", run.inclusion);
        assert!(run.sim.arc.num_jumps() > 60);
        for k in 0..2 {
            for w in run.width(k) {
                assert!(
                    w <= bound.any_time[k],
                    "x{}: {w} > {}",
                    k + 1,
                    bound.any_time[k]
                );
            }
        }
        // The width is deterministic: after a jump the width of x1 is 0.0008 w1 + 2·0.5004·0.4.
        for j in run.sim.arc.jumps() {
            let (pre, post) = (run.sim.arc.state(j.before), run.sim.arc.state(j.after));
            let w1 = pre[4] - pre[2];
            let want = 0.0008 * w1 + 2.0 * 0.5004 * 0.4;
            assert!(((post[4] - post[2]) - want).abs() < 1e-9 * (1.0 + w1));
        }
    }
}

/// A10: periodic pre-jump widths and the bound over all sampling sequences (spec values).
#[test]
fn width_reference_values() {
    let plant = spring_mass_damper(1.0).unwrap();
    let w = WidthDynamics::new(&plant, &example_bounds(), paper_gain().as_ref()).unwrap();
    for (period, x1, x2) in [
        (0.04, 0.690, 5.187),
        (0.1, 1.011, 4.038),
        (0.2, 1.600, 3.917),
        (0.3, 2.268, 4.142),
    ] {
        let pre = w.periodic_pre_jump(period).unwrap();
        assert!(
            (pre[0] - x1).abs() < 1e-3 && (pre[1] - x2).abs() < 1e-3,
            "{period}: {pre:?}"
        );
        // Consistency: flowing one period from the post-jump width returns to it.
        let back = w.flow(&w.jump(&pre), period).unwrap();
        assert!((back[0] - pre[0]).abs() < 1e-12 && (back[1] - pre[1]).abs() < 1e-12);
    }
    let b = w
        .guaranteed_bound(&example_window(), &[0.0, 0.0], 20_001)
        .unwrap();
    assert!(
        (b.pre_jump[0] - 6.31).abs() < 0.01 && (b.pre_jump[1] - 19.07).abs() < 0.01,
        "{b:?}"
    );
    assert!((b.any_time[0] - 6.31).abs() < 0.01 && (b.any_time[1] - 19.73).abs() < 0.01);
    // The periodic orbits are admissible sequences, so they lie below the bound.
    assert!(b.pre_jump[0] >= 2.268 && b.pre_jump[1] >= 5.187);
}

/// A11: noise-free run (Remark 4): inclusion, per-jump contraction by ≤ 0.96706 with P = I,
/// V(z0) constant on flows and decreasing at jumps, Lemma 1 and the GES bound at every hybrid
/// time, and an exponentially shrinking width.
#[test]
fn noise_free_exponential_convergence() {
    let plant = spring_mass_damper(1.0).unwrap();
    let obs = IntervalObserver::new(&plant, &Bounds::zero(2, 1), paper_gain().as_ref()).unwrap();
    let run = simulate_interval(&obs, &figure_scenario(false)).unwrap();
    assert_eq!(run.inclusion.violations, 0);
    let jumps = run.sim.arc.jumps();
    for pair in jumps.windows(2) {
        let (a, b) = (norm(&run.xi(pair[0].before)), norm(&run.xi(pair[1].before)));
        assert!(b <= 0.96706 * a * (1.0 + 1e-9), "{b} > 0.96706·{a}");
    }
    let a_bar = MetzlerDecomposition::new(plant.a()).unwrap().a_bar;
    let gamma = gamma_of_gain(&plant, paper_gain().as_ref()).unwrap();
    let eye = Mat::<f64>::identity(4, 4);
    let fine = GridOptions {
        points: 20_001,
        ..GridOptions::default()
    };
    let c = theorem1_constants(
        a_bar.as_ref(),
        gamma.as_ref(),
        eye.as_ref(),
        &example_window(),
        3001,
        &fine,
    )
    .unwrap();
    let xi0 = norm(&run.xi(0));
    let samples = run.sample_times();
    let mut v_prev_flow: Option<(usize, f64)> = None;
    for i in 0..run.sim.arc.len() {
        let ht = run.sim.arc.hybrid_time(i);
        assert!(c.lemma1_holds(ht.t, ht.j), "Lemma 1 at {ht:?}");
        assert!(norm(&run.xi(i)) <= c.ges_factor(ht.t, ht.j) * xi0 * (1.0 + 1e-9));
        // V(z0) with P = I is constant along each flow (τ counts down to the next sample).
        if let Some(&next) = samples.get(ht.j) {
            let v = lyapunov_value(a_bar.as_ref(), eye.as_ref(), &run.xi(i), next - ht.t).unwrap();
            if let Some((j, v0)) = v_prev_flow
                && j == ht.j
            {
                // Round-off: ξ = x − x̲ is a difference of states of size ~1 (absolute error
                // ≲ 1e-13), so V = ‖e^{Āτ}ξ‖² carries an absolute error ≲ 1e-12·√V.
                let tol = 1e-9 * v0 + 1e-12 * v0.sqrt();
                assert!((v - v0).abs() <= tol, "V varies on flow {j}: {v0} → {v}");
            }
            v_prev_flow = Some((ht.j, v));
        }
    }
    // V⁺ ≤ e^{θ1} V at every jump (26): V(after) = ‖e^{Āμ}Γξ‖², V(before) = ‖ξ‖² for P = I.
    for r in &jumps {
        let Some(&next) = samples.get(r.j_before + 1) else {
            continue;
        };
        let before = norm(&run.xi(r.before)).powi(2);
        let after =
            lyapunov_value(a_bar.as_ref(), eye.as_ref(), &run.xi(r.after), next - r.t).unwrap();
        assert!(after <= c.theta1.exp() * before * (1.0 + 1e-9));
    }
    // Order of magnitude of the decay of the x2 width (spec A11: 3e-3 at 10 s, 1e-6 at 20 s).
    let w2 = run.width(1);
    let at = |t: f64| w2[run.times().iter().rposition(|&s| s <= t).unwrap()];
    assert!(at(10.0) > 3e-4 && at(10.0) < 3e-2, "{}", at(10.0));
    assert!(at(20.0) > 1e-7 && at(20.0) < 1e-5, "{}", at(20.0));
}
