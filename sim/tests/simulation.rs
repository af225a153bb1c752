//! End-to-end simulations against closed forms, the papers' printed values and values from
//! independent reference implementations.

use faer::{Mat, mat};
use proptest::prelude::*;
use sporadic_sim::{
    Adversarial, BoundedUniform, Exosystem, FnFlow, FromData, Gain, HybridObserver, InputSignal,
    JumpMap, JumpSide, LinearCorrection, LinearJump, LinearOutputs, LtiFlow, Periodic,
    PiecewiseConstant, Record, RoundRobin, SampleEvent, SampledPlant, SimError, SimOptions,
    Sinusoidal, Trigger, UniformRandom, simulate, simulate_hybrid,
};

const E: f64 = std::f64::consts::E;

#[test]
fn ferrante_example1_bound_and_contraction() {
    // A = M = 1, T1 = T2 = 1, P = 1, L = 1.1 − e^{-1} (Ferrante et al. 2016, Example 1; κ and γ to
    // full precision from an independent reference implementation).
    let l = 1.1 - (-1f64).exp();
    let alpha2 = E * E;
    let beta = 1.0 - (1.0 - l).powi(2) * E * E;
    let theta = (1.0 - beta / alpha2).ln();
    let gamma = theta.abs() / 2.0; // |θ|/(1 + T2)
    let r = gamma; // T2|θ|/(1 + T2)
    let kappa = E * (r / 2.0).exp(); // sqrt(α2/α1) e^{R/2}, corrected (21)
    assert!((kappa - 2.7632892).abs() < 1e-6 && (gamma - 0.0328433971).abs() < 1e-9);

    let flow = LtiFlow::new(mat![[1.0]].as_ref()).unwrap();
    let jump = LinearJump::new(mat![[1.0 - l]]).unwrap();
    let opts = SimOptions::new(20.0).record(Record::Every(0.01));
    let sim = simulate_hybrid(flow, jump, &mut Periodic::new(1.0).unwrap(), &[1.0], &opts).unwrap();
    assert!(sim.exact);
    assert_eq!(sim.arc.num_jumps(), 20);
    // Per-period contraction (1 − L) e = 0.7281718 between consecutive post-jump values.
    let jumps = sim.arc.jumps();
    for w in jumps.windows(2) {
        let ratio = sim.arc.state(w[1].after)[0] / sim.arc.state(w[0].after)[0];
        assert!((ratio - 0.7281718).abs() < 1e-7, "ratio {ratio}");
    }
    // |ε(t, j)| <= κ e^{−(γ/2)(t+j)} |ε0| everywhere, with equality at (1, 0).
    let mut worst: f64 = 0.0;
    for (ht, x) in sim.arc.iter() {
        let bound = kappa * (-(gamma / 2.0) * (ht.t + ht.j as f64)).exp();
        worst = worst.max(x[0].abs() / bound);
    }
    assert!((worst - 1.0).abs() < 1e-12, "max |ε|/bound = {worst}");
    let pre = sim.arc.value_at(1.0, JumpSide::Before).unwrap()[0];
    let post = sim.arc.value_at(1.0, JumpSide::After).unwrap()[0];
    assert!((pre - E).abs() < 1e-13 && (post - (1.0 - l) * E).abs() < 1e-13);
}

fn ferrante_example2() -> (Mat<f64>, Mat<f64>, Mat<f64>) {
    let a = mat![
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, 0.0],
        [-2.0, 1.0, -1.0, 0.0, 0.0],
        [2.0, -2.0, 0.0, -2.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0],
    ];
    let m = mat![[1.0, 0.0, 0.0, 0.0, 1.0]];
    let l = mat![[0.77524], [0.18123], [-0.12123], [-0.17406], [0.22469]];
    (a, m, l)
}

#[test]
fn ferrante_example2_slowest_sequence() {
    // Independent reference implementation: all intervals 0.2, ε0 = ones ⇒ ‖ε‖²/‖ε0‖² = 3.86e-6
    // after 100 jumps.
    let (a, m, l) = ferrante_example2();
    let mut plant = SampledPlant {
        flow: LtiFlow::new(a.as_ref()).unwrap(),
        output: LinearOutputs::new(vec![m.clone()]).unwrap(),
    };
    let mut obs = HybridObserver {
        flow: LtiFlow::new(a.as_ref()).unwrap(),
        jump: LinearCorrection::constant(m, l).unwrap(),
    };
    let opts = SimOptions::jumps(100);
    let mut rule = Periodic::new(0.2).unwrap();
    let sim = simulate(&mut plant, &mut obs, &mut rule, &[1.0; 5], &[0.0; 5], &opts).unwrap();
    let err = sim.error_arc().unwrap();
    let (ht, e) = err.last().unwrap();
    assert_eq!(ht.j, 100);
    assert!((ht.t - 20.0).abs() < 1e-12);
    let ratio = e.iter().map(|v| v * v).sum::<f64>() / 5.0;
    assert!(
        (ratio / 3.86e-6 - 1.0).abs() < 5e-3,
        "‖ε‖²/‖ε0‖² = {ratio:e}"
    );

    // The same run through the adaptive integrator agrees to 1e-9.
    let opts_dp = SimOptions {
        force_integrator: true,
        ..opts
    };
    let sim_dp = simulate(
        &mut plant,
        &mut obs,
        &mut Periodic::new(0.2).unwrap(),
        &[1.0; 5],
        &[0.0; 5],
        &opts_dp,
    )
    .unwrap();
    assert!(!sim_dp.exact && sim_dp.integrator_stats.accepted > 100);
    let (_, z_exact) = sim.arc.last().unwrap();
    let (_, z_dp) = sim_dp.arc.last().unwrap();
    for (a, b) in z_exact.iter().zip(z_dp) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
}

#[test]
fn round_robin_resets_measured_components() {
    // Quarter-car model of Sferlazza et al. (2021), §6, two sensors in round robin with noise. With the
    // gain K_σ = C_σᵀ the measured component of the estimate is reset to the measurement, so after each
    // jump |C_σ(x − x̂)| equals the noise sample, bounded by w̄_σ.
    let a = mat![
        [0.0, 1.0, 0.0, -1.0],
        [-64.0, -4.0, 0.0, 4.0],
        [0.0, 0.0, 0.0, 1.0],
        [355.5556, 22.2222, -8.8889, -22.2222],
    ];
    let c1 = mat![[1.0, 0.0, 0.0, 0.0]];
    let c2 = mat![[0.0, 0.0, 1.0, 0.0]];
    let outputs = LinearOutputs::new(vec![c1.clone(), c2.clone()])
        .unwrap()
        .with_noise(
            0,
            Box::new(BoundedUniform::symmetric(vec![0.002], 5).unwrap()),
        )
        .unwrap()
        .with_noise(
            1,
            Box::new(BoundedUniform::symmetric(vec![0.02], 6).unwrap()),
        )
        .unwrap();
    let mut plant = SampledPlant {
        flow: LtiFlow::new(a.as_ref()).unwrap(),
        output: outputs,
    };
    let gains = vec![
        Gain::Constant(c1.transpose().to_owned()),
        Gain::Constant(c2.transpose().to_owned()),
    ];
    let mut obs = HybridObserver {
        flow: LtiFlow::new(a.as_ref()).unwrap(),
        jump: LinearCorrection::new(vec![c1, c2], gains).unwrap(),
    };
    let windows = [(0.02, 0.07), (0.04, 0.09)];
    let mut rule = RoundRobin::new(&windows, 77).unwrap();
    let opts = SimOptions::new(2.0).record(Record::Every(0.005));
    let sim = simulate(
        &mut plant,
        &mut obs,
        &mut rule,
        &[0.1, 1.0, 0.05, 1.0],
        &[0.0; 4],
        &opts,
    )
    .unwrap();
    let log = &sim.samples;
    assert!(log.len() > 20);
    for k in 0..log.len() {
        let s = log.get(k).unwrap();
        assert_eq!(s.sensor, k % 2);
        let (lo, hi) = windows[s.sensor];
        assert!(
            (lo..=hi).contains(&s.elapsed),
            "interval {} outside window of sensor {}",
            s.elapsed,
            s.sensor
        );
    }
    let err = sim.error_arc().unwrap();
    for (r, k) in err.jumps().iter().zip(0..) {
        let comp = if k % 2 == 0 { 0 } else { 2 };
        let bound = if k % 2 == 0 { 0.002 } else { 0.02 };
        let e = err.state(r.after)[comp];
        assert!(
            e.abs() <= bound * (1.0 + 1e-12),
            "jump {k}: measured error {e}"
        );
    }
}

#[test]
fn andrieu_state_triggered_sampling() {
    // Andrieu et al. (2014), theorem-conforming design (Theorem 2) on a pendulum in normal form:
    // n = 2, f2 = −sin(x1) (c ≡ 1), K = [−2, −1]ᵀ, α = 0.2, a1 = 0.0693280, a3 = 4,
    // a2 = 56.2298; x(0) = (1, 0), x̂(0) = (−1, 2), L(0) = 1, horizon 2. Sample when s·L = α.
    let (alpha, a1, a2, a3, k) = (0.2, 0.0693280, 56.2298, 4.0, [-2.0, -1.0]);
    let plant_flow = FnFlow::new(2, |_t, x: &[f64], dx: &mut [f64]| {
        dx[0] = x[1];
        dx[1] = -x[0].sin();
    });
    let mut plant = SampledPlant {
        flow: plant_flow,
        output: |_ev: &SampleEvent, x: &[f64], y: &mut Vec<f64>| -> Result<(), SimError> {
            y.push(x[0]);
            Ok(())
        },
    };
    // Observer state (x̂1, x̂2, L, M); c(x̂, u) = 1.
    let obs_flow = FnFlow::new(4, move |_t, z: &[f64], dz: &mut [f64]| {
        dz[0] = z[1];
        dz[1] = -z[0].sin();
        dz[2] = a2 * z[2] * z[3];
        dz[3] = a3 * z[3];
    });
    let obs_jump = move |_ev: &SampleEvent, y: &[f64], z: &mut [f64]| -> Result<(), SimError> {
        let l_minus = z[2];
        let innov = z[0] - y[0];
        z[0] += alpha * k[0] * innov;
        z[1] += alpha * l_minus * k[1] * innov;
        z[2] = (1.0 - a1 * alpha) * l_minus + a1 * alpha;
        z[3] = 1.0;
        Ok(())
    };
    let mut obs = HybridObserver {
        flow: obs_flow,
        jump: obs_jump,
    };
    struct Rule {
        alpha: f64,
    }
    impl sporadic_sim::SamplingRule for Rule {
        fn next_sample(
            &mut self,
            ctx: &sporadic_sim::SampleContext<'_>,
        ) -> Result<Trigger, SimError> {
            // δ_k <= α / L(t_k) <= α.
            Ok(Trigger::Event {
                sensor: 0,
                max_interval: 1.01 * self.alpha / ctx.observer[2],
            })
        }
        fn guard(&self, s: f64, _plant: &[f64], obs: &[f64]) -> f64 {
            s * obs[2] - self.alpha
        }
    }
    let mut opts = SimOptions::new(2.0);
    opts.integrator.rtol = 1e-10;
    opts.integrator.atol = 1e-13;
    // |d(δL)/dt| reaches ≈ 2e3 here, so locate events to machine precision to get δ·L⁻ = α to 1e-9.
    opts.integrator.event_tol = 1e-15;
    let sim = simulate(
        &mut plant,
        &mut obs,
        &mut Rule { alpha },
        &[1.0, 0.0],
        &[-1.0, 2.0, 1.0, 1.0],
        &opts,
    )
    .unwrap();
    assert!(!sim.exact);
    let n = sim.samples.len();
    assert!((7000..=8200).contains(&n), "{n} samples (reference ≈ 7600)");
    let (mut lmin, mut lmax, mut dmin, mut dmax) = (f64::MAX, 0.0f64, f64::MAX, 0.0f64);
    for r in sim.arc.jumps() {
        let pre = sim.arc.state(r.before);
        let delta = sim.samples.intervals()[r.j_before];
        let l_minus = pre[4];
        assert!(
            (delta * l_minus - alpha).abs() <= 1e-9 * alpha,
            "δ·L⁻ = {}",
            delta * l_minus
        );
        assert!(l_minus >= 1.0 && sim.arc.state(r.after)[5] == 1.0);
        lmin = lmin.min(l_minus);
        lmax = lmax.max(l_minus);
        dmin = dmin.min(delta);
        dmax = dmax.max(delta);
    }
    // Reference ranges: L⁻ ∈ [6.43, 807], δ ∈ [2.5e-4, 0.031] (independent reference
    // implementation).
    assert!(
        (6.0..7.0).contains(&lmin) && (750.0..860.0).contains(&lmax),
        "L⁻ ∈ [{lmin}, {lmax}]"
    );
    assert!(
        (2.3e-4..2.7e-4).contains(&dmin) && (0.029..0.033).contains(&dmax),
        "δ ∈ [{dmin}, {dmax}]"
    );
    let (_, z) = sim.arc.last().unwrap();
    let e = ((z[2] - z[0]).powi(2) + (z[3] - z[1]).powi(2)).sqrt();
    assert!(e < 1e-8, "final error {e}");
}

#[test]
fn interval_observer_encloses_the_state() {
    // Rabehi et al. §V: spring–mass–damper with u = 10[2 sin 10t + sin 16t + sin 24t],
    // disturbance |d_i| <= 1 resampled every 0.01 s, noise v(t_k) = 0.4 cos(2 t_k), random sampling in
    // [0.04, 0.3], reported gain L = [−0.5004, −0.0494]ᵀ, C = [2, 0]. Bounds must enclose the state.
    let a = mat![[0.0, 1.0], [-1.0, -1.0]];
    let b = mat![[0.0], [1.0]];
    let u = || {
        Exosystem::sinusoid_sum(&[(20.0, 10.0, 0.0), (10.0, 16.0, 0.0), (10.0, 24.0, 0.0)]).unwrap()
    };
    let mut dist = BoundedUniform::symmetric(vec![1.0, 1.0], 2024).unwrap();
    let d = PiecewiseConstant::sample_and_hold(&mut dist, 0.0, 0.01, 20.0).unwrap();
    let plant_flow = LtiFlow::new(a.as_ref())
        .unwrap()
        .with_input(b.as_ref(), InputSignal::Exosystem(u()))
        .unwrap()
        .with_input(
            Mat::<f64>::identity(2, 2).as_ref(),
            InputSignal::PiecewiseConstant(d),
        )
        .unwrap();
    let c = [2.0, 0.0];
    let mut noise =
        Sinusoidal::new(vec![0.4], vec![2.0], vec![std::f64::consts::FRAC_PI_2]).unwrap();
    let output = move |ev: &SampleEvent, x: &[f64], y: &mut Vec<f64>| -> Result<(), SimError> {
        let mut v = [0.0];
        sporadic_sim::NoiseSource::sample(&mut noise, ev.t, &mut v);
        y.push(c[0] * x[0] + c[1] * x[1] + v[0]);
        Ok(())
    };
    let mut plant = SampledPlant {
        flow: plant_flow,
        output,
    };
    // Observer (4) on (x̲, x̄): ẋ̲ = A^M x̲ − A^N x̄ + Bu + d̲, ẋ̄ = A^M x̄ − A^N x̲ + Bu + d̄, with
    // A^M = [[0,1],[0,−1]] and A^N = [[0,0],[1,0]].
    let abar = mat![
        [0.0, 1.0, 0.0, 0.0],
        [0.0, -1.0, -1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0, -1.0]
    ];
    let bbar = mat![[0.0], [1.0], [0.0], [1.0]];
    let obs_flow = LtiFlow::new(abar.as_ref())
        .unwrap()
        .with_input(bbar.as_ref(), InputSignal::Exosystem(u()))
        .unwrap()
        .with_affine(vec![-1.0, -1.0, 1.0, 1.0])
        .unwrap();
    let l = [-0.5004, -0.0494];
    let vbar = 0.4;
    let obs_jump = move |_ev: &SampleEvent, y: &[f64], z: &mut [f64]| -> Result<(), SimError> {
        // G = I + L C; x̲⁺ = G⁺x̲ − G⁻x̄ − |L|v̄ − L y; x̄⁺ = G⁺x̄ − G⁻x̲ + |L|v̄ − L y.
        let g = [
            [1.0 + l[0] * c[0], l[0] * c[1]],
            [l[1] * c[0], 1.0 + l[1] * c[1]],
        ];
        let (lo, hi) = ([z[0], z[1]], [z[2], z[3]]);
        for i in 0..2 {
            let (mut nl, mut nh) = (
                -l[i].abs() * vbar - l[i] * y[0],
                l[i].abs() * vbar - l[i] * y[0],
            );
            for k in 0..2 {
                let (gp, gm) = (g[i][k].max(0.0), (-g[i][k]).max(0.0));
                nl += gp * lo[k] - gm * hi[k];
                nh += gp * hi[k] - gm * lo[k];
            }
            z[i] = nl;
            z[2 + i] = nh;
        }
        Ok(())
    };
    let mut obs = HybridObserver {
        flow: obs_flow,
        jump: obs_jump,
    };
    let mut rule = UniformRandom::new(0.04, 0.3, 31).unwrap();
    let x0 = [1.0, -1.0];
    let xhat0 = [x0[0] - 3.0, x0[1] - 3.0, x0[0] + 3.0, x0[1] + 3.0];
    let opts = SimOptions::new(20.0).record(Record::Every(0.01));
    let sim = simulate(&mut plant, &mut obs, &mut rule, &x0, &xhat0, &opts).unwrap();
    assert!(sim.exact);
    assert!(sim.samples.len() > 100);
    for (ht, z) in sim.arc.iter() {
        for i in 0..2 {
            assert!(
                z[2 + i] <= z[i] + 1e-9 && z[i] <= z[4 + i] + 1e-9,
                "t = {}: {z:?}",
                ht.t
            );
        }
    }
    // After the transient, the post-jump width of x1 is small (≈ 0.401, independent reference
    // implementation).
    let last = sim.arc.jumps().last().copied().unwrap();
    let z = sim.arc.state(last.after);
    let w1 = z[4] - z[2];
    assert!((w1 - 0.401).abs() < 0.01, "post-jump width of x1: {w1}");
}

#[test]
fn adversary_drives_the_simulation() {
    // Used as a sampling rule on an error system, the adversary realises exactly its greedy sequence.
    let (a, m, l) = ferrante_example2();
    let jmat = Mat::<f64>::identity(5, 5) - &l * &m;
    let v = |e: &[f64]| e.iter().map(|x| x * x).sum::<f64>();
    let mk = || {
        Adversarial::new(
            a.as_ref(),
            JumpMap::Matrix(jmat.clone()),
            Box::new(v),
            0.2,
            3.0,
            29,
        )
        .unwrap()
    };
    let e0 = [1.0, -1.0, 0.5, 0.0, 1.0];
    let (taus, errs) = mk().sequence(&e0, 30).unwrap();
    let flow = LtiFlow::new(a.as_ref()).unwrap();
    let sim = simulate_hybrid(
        flow,
        LinearJump::new(jmat.clone()).unwrap(),
        &mut mk(),
        &e0,
        &SimOptions::jumps(30),
    )
    .unwrap();
    assert_eq!(
        sim.samples.intervals(),
        &taus[..],
        "the requested intervals are passed through exactly"
    );
    for (r, e) in sim.arc.jumps().iter().zip(&errs) {
        for (x, y) in sim.arc.state(r.after).iter().zip(e) {
            assert!((x - y).abs() <= 1e-12 * (1.0 + y.abs()));
        }
    }
    // Sanity check (not a theorem): the greedy adversary ends with a larger V than a random sequence.
    let mut rng_seq = UniformRandom::new(0.2, 3.0, 3).unwrap();
    let sim_rand = simulate_hybrid(
        LtiFlow::new(a.as_ref()).unwrap(),
        LinearJump::new(jmat).unwrap(),
        &mut rng_seq,
        &e0,
        &SimOptions::jumps(30),
    )
    .unwrap();
    let v_adv = v(sim.arc.last().unwrap().1);
    let v_rand = v(sim_rand.arc.last().unwrap().1);
    assert!(v_adv > v_rand, "adversarial {v_adv:e} vs random {v_rand:e}");
}

#[test]
fn csv_export_round_trip() {
    let flow = LtiFlow::new(mat![[0.0, 1.0], [-1.0, 0.0]].as_ref()).unwrap();
    let jump = LinearJump::new(mat![[0.5, 0.0], [0.0, 1.0]]).unwrap();
    let opts = SimOptions::new(3.0).record(Record::Every(0.25));
    let sim = simulate_hybrid(
        flow,
        jump,
        &mut Periodic::new(1.0).unwrap(),
        &[1.0, 0.0],
        &opts,
    )
    .unwrap();
    let mut buf = Vec::new();
    sim.arc.write_csv(&mut buf, Some(&["p", "v"])).unwrap();
    let text = String::from_utf8(buf).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|s| s.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), sim.arc.len());
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row[0], sim.arc.times()[i]);
        assert_eq!(row[1] as usize, sim.arc.jump_counters()[i]);
        assert_eq!(&row[2..], sim.arc.state(i));
    }
    // 3 jumps at t = 1, 2, 3; grid points every 0.25 in between.
    assert_eq!(sim.arc.jump_times(), vec![1.0, 2.0, 3.0]);
    assert_eq!(sim.arc.len(), 1 + 3 * 3 + 2 * 3);
}

#[test]
fn invalid_simulation_inputs() {
    let flow = || LtiFlow::new(mat![[1.0]].as_ref()).unwrap();
    let jump = || LinearJump::new(mat![[0.5]]).unwrap();
    let rule = || Periodic::new(1.0).unwrap();
    assert!(
        simulate_hybrid(
            flow(),
            jump(),
            &mut rule(),
            &[1.0, 2.0],
            &SimOptions::new(1.0)
        )
        .is_err()
    );
    assert!(
        simulate_hybrid(
            flow(),
            jump(),
            &mut rule(),
            &[f64::NAN],
            &SimOptions::new(1.0)
        )
        .is_err()
    );
    assert!(simulate_hybrid(flow(), jump(), &mut rule(), &[1.0], &SimOptions::new(-1.0)).is_err());
    assert!(
        simulate_hybrid(
            flow(),
            jump(),
            &mut rule(),
            &[1.0],
            &SimOptions::new(f64::INFINITY)
        )
        .is_err()
    );
    let bad = SimOptions::new(1.0).record(Record::Every(0.0));
    assert!(simulate_hybrid(flow(), jump(), &mut rule(), &[1.0], &bad).is_err());
    // Data-driven sequence: when it runs out the system flows to the horizon.
    let mut data = FromData::from_slice(&[0.5, 0.5]).unwrap();
    let sim = simulate_hybrid(flow(), jump(), &mut data, &[1.0], &SimOptions::new(2.0)).unwrap();
    assert_eq!(sim.arc.num_jumps(), 2);
    let (ht, x) = sim.arc.last().unwrap();
    assert_eq!(ht.t, 2.0);
    assert!((x[0] - 0.25 * 2f64.exp()).abs() < 1e-13);
}

/// `ẋ = u(t)` with a piecewise-constant `u` given to the simulator as a user flow (not an `LtiFlow`).
struct HeldInput(PiecewiseConstant);

impl sporadic_sim::Flow for HeldInput {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, t: f64, _x: &[f64], dx: &mut [f64]) {
        dx[0] = self.0.value(t)[0];
    }
    fn next_breakpoint(&self, t: f64) -> Option<f64> {
        self.0.next_breakpoint(t)
    }
}

#[test]
fn inputs_are_left_limited_at_switches() {
    // Regression: the adaptive driver evaluated the last stages of a step ending at a switch of u with
    // the NEXT segment's value (u is right-continuous), which made the error control reject steps down
    // to ~1e-9 and left an error of ~1e-8 in x. ẋ = u with u = 1 on [0, 1), 100 on [1, 2), −50 after:
    // x(t) = t, then 1 + 100(t − 1), then 101 − 50(t − 2) — piecewise linear, so DP5 must be exact.
    let u = || {
        PiecewiseConstant::new(
            vec![0.0, 1.0, 2.0],
            vec![vec![1.0], vec![100.0], vec![-50.0]],
        )
        .unwrap()
    };
    let exact = |t: f64| {
        if t <= 1.0 {
            t
        } else if t <= 2.0 {
            1.0 + 100.0 * (t - 1.0)
        } else {
            101.0 - 50.0 * (t - 2.0)
        }
    };
    let identity =
        |_ev: &SampleEvent, _y: &[f64], _x: &mut [f64]| -> Result<(), SimError> { Ok(()) };
    // Period 0.5: samples on the switches (flow → jump → flow with the new input); 0.75: switches inside
    // flow intervals. Record::Steps also stores the state at every switch (end of an integrator call).
    for period in [0.5, 0.75] {
        let opts = SimOptions::new(3.0).record(Record::Steps);
        let sim = simulate_hybrid(
            HeldInput(u()),
            identity,
            &mut Periodic::new(period).unwrap(),
            &[0.0],
            &opts,
        )
        .unwrap();
        assert!(!sim.exact);
        for (ht, x) in sim.arc.iter() {
            assert!(
                (x[0] - exact(ht.t)).abs() <= 1e-12 * exact(ht.t).abs().max(1.0),
                "period {period}: x({}) = {} vs {}",
                ht.t,
                x[0],
                exact(ht.t)
            );
        }
        for t in [1.0, 2.0] {
            let before = sim.arc.value_at(t, JumpSide::Before).unwrap()[0];
            assert!(
                (before - exact(t)).abs() <= 1e-12 * exact(t),
                "x({t}⁻) = {before}"
            );
        }
        assert_eq!(sim.integrator_stats.rejected, 0, "period {period}");
    }
    // The same through an LtiFlow: the adaptive path (exact left limits) against the exact engine.
    let lti = || {
        LtiFlow::new(mat![[-0.5]].as_ref())
            .unwrap()
            .with_input(mat![[1.0]].as_ref(), InputSignal::PiecewiseConstant(u()))
            .unwrap()
    };
    let mut opts = SimOptions::new(3.0);
    let exact_run = simulate_hybrid(
        lti(),
        identity,
        &mut Periodic::new(0.5).unwrap(),
        &[2.0],
        &opts,
    )
    .unwrap();
    opts.force_integrator = true;
    opts.integrator.rtol = 1e-12;
    opts.integrator.atol = 1e-14;
    let dp5 = simulate_hybrid(
        lti(),
        identity,
        &mut Periodic::new(0.5).unwrap(),
        &[2.0],
        &opts,
    )
    .unwrap();
    assert!(exact_run.exact && !dp5.exact);
    for ((ta, a), (tb, b)) in exact_run.arc.iter().zip(dp5.arc.iter()) {
        assert_eq!(ta, tb);
        assert!(
            (a[0] - b[0]).abs() <= 1e-11 * a[0].abs().max(1.0),
            "t = {}: {} vs {}",
            ta.t,
            a[0],
            b[0]
        );
    }
}

#[test]
fn schedule_one_rounding_error_short_of_the_horizon_or_a_switch() {
    // Regression (found by sporadic-etienne2017): 15 intervals of 0.3 end at 4.499999999999999, one ulp
    // before the horizon 4.5; the final flow over that ulp raised StepSizeUnderflow. It lands on 4.5 now.
    let pendulum = || {
        FnFlow::new(2, |_t, x: &[f64], dx: &mut [f64]| {
            dx[0] = x[1];
            dx[1] = -x[0].sin();
        })
    };
    let identity =
        |_ev: &SampleEvent, _y: &[f64], _x: &mut [f64]| -> Result<(), SimError> { Ok(()) };
    let t15 = (0..15).fold(0.0, |t, _| t + 0.3);
    assert!(t15 < 4.5 && 4.5 - t15 <= 4.5 * f64::EPSILON);
    for record in [Record::JumpsOnly, Record::Every(0.005), Record::Steps] {
        let mut data = FromData::from_slice(&[0.3; 16]).unwrap();
        let opts = SimOptions::new(4.5).record(record);
        let sim = simulate_hybrid(pendulum(), identity, &mut data, &[1.0, 0.0], &opts).unwrap();
        assert_eq!(sim.arc.num_jumps(), 15);
        assert_eq!(sim.samples.times()[14], t15);
        let (ht, x) = sim.arc.last().unwrap();
        assert_eq!((ht.t, ht.j), (4.5, 15));
        // The same pendulum without samples (the jumps are the identity) reaches the same state.
        let free = simulate_hybrid(
            pendulum(),
            identity,
            &mut Periodic::new(10.0).unwrap(),
            &[1.0, 0.0],
            &SimOptions::new(4.5),
        )
        .unwrap();
        let (_, y) = free.arc.last().unwrap();
        assert!((x[0] - y[0]).abs() < 1e-8 && (x[1] - y[1]).abs() < 1e-8);
    }
    // An input switch one ulp after a sampling instant: a flow interval of one ulp with the new input.
    let u = PiecewiseConstant::new(vec![0.0, 4.5], vec![vec![1.0], vec![-1.0]]).unwrap();
    let mut data = FromData::from_slice(&[0.3; 20]).unwrap();
    let sim = simulate_hybrid(
        HeldInput(u),
        identity,
        &mut data,
        &[0.0],
        &SimOptions::new(6.0),
    )
    .unwrap();
    let (ht, x) = sim.arc.last().unwrap();
    assert_eq!(ht.t, 6.0);
    assert!((x[0] - (4.5 - 1.5)).abs() < 1e-12, "x(6) = {}", x[0]);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// For ε̇ = A ε, ε⁺ = J ε, the post-jump error at jump k is J e^{Aτ_k} ⋯ J e^{Aτ_1} ε0 (products computed
    /// independently with `expm_scaled`), time is nondecreasing, and j increases by one at each jump.
    #[test]
    fn linear_error_system_is_a_matrix_product(
        n in 1usize..5,
        entries in proptest::collection::vec(-1.5f64..1.5, 32),
        jentries in proptest::collection::vec(-1.0f64..1.0, 32),
        taus in proptest::collection::vec(0.05f64..1.5, 1..25),
        e0 in proptest::collection::vec(-1.0f64..1.0, 4),
    ) {
        let a = Mat::<f64>::from_fn(n, n, |i, j| entries[n * i + j]);
        let jm = Mat::<f64>::from_fn(n, n, |i, j| jentries[n * i + j]);
        let x0: Vec<f64> = e0[..n].to_vec();
        let mut data = FromData::from_slice(&taus).unwrap();
        let opts = SimOptions::new(taus.iter().sum::<f64>() + 1.0).record(Record::Every(0.3));
        let sim = simulate_hybrid(LtiFlow::new(a.as_ref()).unwrap(), LinearJump::new(jm.clone()).unwrap(), &mut data, &x0, &opts).unwrap();
        prop_assert_eq!(sim.arc.num_jumps(), taus.len());
        let ts = sim.arc.times();
        let js = sim.arc.jump_counters();
        for i in 1..ts.len() {
            prop_assert!(ts[i] >= ts[i - 1]);
            prop_assert!(js[i] == js[i - 1] || (js[i] == js[i - 1] + 1 && ts[i] == ts[i - 1]));
        }
        let mut x = Mat::<f64>::from_fn(n, 1, |i, _| x0[i]);
        for (r, &tau) in sim.arc.jumps().iter().zip(&taus) {
            x = &jm * (sporadic_linalg::expm_scaled(a.as_ref(), tau).unwrap() * &x);
            let got = sim.arc.state(r.after);
            let scale = (0..n).map(|i| x[(i, 0)].abs()).fold(1.0, f64::max);
            for i in 0..n {
                prop_assert!((got[i] - x[(i, 0)]).abs() <= 1e-10 * scale, "jump {}: {} vs {}", r.j_before + 1, got[i], x[(i, 0)]);
            }
        }
    }
}
