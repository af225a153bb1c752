//! Issue 22, item 8: the observer of Andrieu et al. (2014) on plant files' plants (matrices as in
//! `tests/corpus/*.toml` and `examples/*.toml`, none tuned for this method): verdicts, the
//! guaranteed inter-sample range, and metamorphic tests (time scaling, similarity).

use faer::{Mat, mat};
use proptest::prelude::*;
use sporadic_andrieu2014::Andrieu2014;
use sporadic_model::{
    DesignReport, Lipschitz, MethodOptions, ObserverMethod, Plant, Reason, Sampling,
    SamplingWindow, Scenario, Status,
};

fn window(t1: f64, t2: f64) -> Sampling {
    Sampling::Synchronous(SamplingWindow::new(t1, t2).unwrap())
}

fn design_of(plant: &Plant, sampling: &Sampling) -> DesignReport {
    Andrieu2014
        .design(plant, sampling, &MethodOptions::default())
        .unwrap()
}

fn design(a: Mat<f64>, c: Mat<f64>, t1: f64, t2: f64) -> DesignReport {
    let plant = Plant::linear(a.as_ref(), None, c.as_ref()).unwrap();
    design_of(&plant, &window(t1, t2))
}

fn certified_range(r: &DesignReport) -> (f64, f64) {
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    assert!(r.checks.iter().all(|c| c.passed), "{:?}", r.checks);
    assert!(r.margin.as_ref().unwrap().value > 0.0);
    let w = r.window.expect("window");
    (w.t1(), w.t2())
}

fn oscillator(w: f64) -> Mat<f64> {
    mat![[0.0, 1.0], [-w * w, 0.0]]
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs())
}

/// A chain of integrators has no time scale: L stays 1, the rule samples periodically, and the
/// design takes the file's longest interval as the period.
#[test]
fn chains_of_integrators_sample_periodically_at_the_files_t2() {
    let r = design(mat![[0.0, 1.0], [0.0, 0.0]], mat![[1.0, 0.0]], 0.05, 0.5);
    assert_eq!(certified_range(&r), (0.5, 0.5));
    let triple = mat![[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]];
    let r = design(triple, mat![[1.0, 0.0, 0.0]], 0.01, 0.2);
    assert_eq!(certified_range(&r), (0.2, 0.2));
}

/// Double integrator, independent check of the reported gain in the plant's coordinates: at the
/// period h = T2 (L ≡ 1), the sampled error map (I + G(h)c)e^{Ah} must be Schur stable.
#[test]
fn double_integrator_gain_gives_a_schur_error_map() {
    let a = mat![[0.0, 2.0], [0.0, 0.0]];
    let c = mat![[1.0, 0.0]];
    let r = design(a.clone(), c.clone(), 0.05, 0.5);
    let g = r.gain("G").unwrap();
    let sched = g.schedule.as_ref().unwrap();
    let h = *sched.tau.last().unwrap();
    assert_eq!(h, 0.5);
    let gm = g.to_mat();
    let e = sporadic_linalg::expm_scaled(a.as_ref(), h).unwrap();
    let m = (Mat::<f64>::identity(2, 2) + &gm * &c) * &e;
    let rho = sporadic_linalg::spectral_radius(m.as_ref()).unwrap();
    assert!(rho < 0.999, "ρ = {rho}");
}

/// Oscillators at ω = 1 and ω = 100: certified, and the ω = 100 range is the ω = 1 range / 100.
#[test]
fn oscillators_scale_with_their_frequency() {
    let (l1, u1) = certified_range(&design(oscillator(1.0), mat![[1.0, 0.0]], 0.5, 3.5));
    let (l100, u100) = certified_range(&design(oscillator(100.0), mat![[1.0, 0.0]], 0.001, 0.02));
    assert!(0.0 < l1 && l1 < u1);
    assert!(rel(l1 / 100.0, l100) < 1e-6, "{l1} {l100}");
    assert!(rel(u1 / 100.0, u100) < 1e-6, "{u1} {u100}");
    println!("oscillator ω=1: [{l1:.4e}, {u1:.4e}], ω=100: [{l100:.4e}, {u100:.4e}]");
}

/// Unstable plants are observable, so certified (`unstable-first-order.toml`,
/// `inverted-pendulum`-like second order).
#[test]
fn unstable_plants_are_certified() {
    let (l, u) = certified_range(&design(mat![[1.0]], mat![[1.0]], 0.05, 0.5));
    assert!(0.0 < l && l < u);
    let (l, u) = certified_range(&design(
        mat![[0.0, 1.0], [9.81, 0.0]],
        mat![[1.0, 0.0]],
        0.01,
        0.1,
    ));
    assert!(0.0 < l && l < u);
}

/// `multi-output-three-state.toml`: both outputs observe the state; the best-conditioned is used
/// and the notes say which.
#[test]
fn multi_output_plant_uses_the_best_conditioned_output() {
    let a = mat![[0.0, 1.0, 0.0], [-2.0, -0.2, 2.0], [1.0, 0.0, -1.0]];
    let r = design(a, mat![[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]], 0.05, 0.8);
    certified_range(&r);
    assert!(
        r.notes.iter().any(|n| n.contains("outputs tried")),
        "{:?}",
        r.notes
    );
}

/// Unobservable from every output: not applicable, with the reason.
#[test]
fn unobservable_plant_is_refused() {
    let r = design(mat![[-1.0, 0.0], [0.0, -2.0]], mat![[1.0, 0.0]], 0.1, 0.5);
    assert_eq!(r.status, Status::NotApplicable);
    match &r.reason {
        Some(Reason::UnsupportedStructure { message }) => {
            assert!(message.contains("not observable"), "{message}")
        }
        other => panic!("{other:?}"),
    }
    // `undetectable-integrator.toml`-like: an integrator the output does not see.
    let r = design(mat![[0.0, 0.0], [0.0, -1.0]], mat![[0.0, 1.0]], 0.1, 0.5);
    assert_eq!(r.status, Status::NotApplicable, "{:?}", r.reason);
}

/// Two modes 1e-9 apart read through their sum: observable in exact arithmetic, but the
/// transformation has condition number ~1e9 > 1/√ε: not certified, numerical failure.
#[test]
fn nearly_unobservable_plant_is_refused_as_ill_conditioned() {
    let r = design(
        mat![[-1.0, 0.0], [0.0, -1.0 - 1e-9]],
        mat![[1.0, 1.0]],
        0.1,
        0.5,
    );
    assert_eq!(r.status, Status::NotCertified, "{:?}", r.reason);
    match &r.reason {
        Some(Reason::NumericalFailure { message }) => {
            assert!(message.contains("condition number"), "{message}")
        }
        other => panic!("{other:?}"),
    }
    // 1e-3 apart: condition ~1e3, certified.
    certified_range(&design(
        mat![[-1.0, 0.0], [0.0, -1.001]],
        mat![[1.0, 1.0]],
        0.1,
        0.5,
    ));
}

/// `badly-scaled-units.toml`: the mass-spring-damper in mm and km/s gives the same range as in
/// SI units (the conditioning is measured after equilibration, so units do not matter).
#[test]
fn units_do_not_change_the_verdict_or_the_range() {
    let good = certified_range(&design(
        mat![[0.0, 1.0], [-4.0, -0.4]],
        mat![[1.0, 0.0]],
        0.05,
        1.0,
    ));
    let bad = certified_range(&design(
        mat![[0.0, 1e6], [-4e-6, -0.4]],
        mat![[0.001, 0.0]],
        0.05,
        1.0,
    ));
    assert!(
        rel(good.0, bad.0) < 1e-6 && rel(good.1, bad.1) < 1e-6,
        "{good:?} {bad:?}"
    );
}

/// `lipschitz-pendulum.toml`: the sine enters the last row, triangular: certified.
#[test]
fn triangular_lipschitz_plant_is_certified() {
    let plant = Plant::linear(
        mat![[0.0, 1.0], [0.0, -0.5]].as_ref(),
        None,
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap()
    .with_lipschitz(
        Lipschitz::new(
            mat![[0.0], [-1.0]].as_ref(),
            mat![[1.0, 0.0]].as_ref(),
            mat![[-1.0]].as_ref(),
            mat![[1.0]].as_ref(),
        )
        .unwrap(),
    )
    .unwrap();
    let r = design_of(&plant, &window(0.01, 0.3));
    let (l, u) = certified_range(&r);
    assert!(0.0 < l && l < u);
    // The nonlinearity only adds to the linear part's bound: no longer a guaranteed shortest
    // interval than for the linear plant alone (whose c̃ has one term less).
    let linear = certified_range(&design(
        mat![[0.0, 1.0], [0.0, -0.5]],
        mat![[1.0, 0.0]],
        0.01,
        0.3,
    ));
    assert!(l <= linear.0 * (1.0 + 1e-12), "{l} vs {}", linear.0);
    let sim = Andrieu2014.simulate(&plant, &r, &Scenario::default());
    assert!(sim.is_err());
}

/// `lipschitz-saturated-motor.toml` (φ' ∈ [0, 2] on the speed, entering the speed's row):
/// triangular in normal form, certified; the whole vector field times k (A → kA, G → kG) gives
/// the range divided by k.
#[test]
fn triangular_lipschitz_plant_scales_with_time() {
    let plant = |k: f64| {
        let a = mat![[0.0, 1.0, 0.0], [0.0, -0.2, 1.0], [0.0, -1.0, -3.0]];
        let a = Mat::from_fn(3, 3, |i, j| k * a[(i, j)]);
        Plant::linear(a.as_ref(), None, mat![[1.0, 0.0, 0.0]].as_ref())
            .unwrap()
            .with_lipschitz(
                Lipschitz::new(
                    mat![[0.0], [-k], [0.0]].as_ref(),
                    mat![[0.0, 1.0, 0.0]].as_ref(),
                    mat![[0.0]].as_ref(),
                    mat![[2.0]].as_ref(),
                )
                .unwrap(),
            )
            .unwrap()
    };
    let (l, u) = certified_range(&design_of(&plant(1.0), &window(0.01, 0.2)));
    let (lk, uk) = certified_range(&design_of(&plant(10.0), &window(0.001, 0.02)));
    assert!(
        rel(l / 10.0, lk) < 1e-6 && rel(u / 10.0, uk) < 1e-6,
        "{l} {u} / {lk} {uk}"
    );
}

/// A nonlinearity in the first row depending on x2 (= ẏ): not triangular, not applicable with
/// the structure needed.
#[test]
fn non_triangular_lipschitz_plant_is_refused() {
    let plant = Plant::linear(
        mat![[0.0, 1.0], [-1.0, 0.0]].as_ref(),
        None,
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap()
    .with_lipschitz(
        Lipschitz::new(
            mat![[1.0], [0.0]].as_ref(),
            mat![[0.0, 1.0]].as_ref(),
            mat![[-0.5]].as_ref(),
            mat![[0.5]].as_ref(),
        )
        .unwrap(),
    )
    .unwrap();
    let r = design_of(&plant, &window(0.01, 0.3));
    assert_eq!(r.status, Status::NotApplicable);
    match &r.reason {
        Some(Reason::UnsupportedStructure { message }) => {
            assert!(message.contains("not triangular"), "{message}")
        }
        other => panic!("{other:?}"),
    }
}

/// Round-robin sensors: not applicable; `largest_window` does not apply either.
#[test]
fn round_robin_and_window_search_do_not_apply() {
    let a = oscillator(1.0);
    let plant = Plant::round_robin(
        a.as_ref(),
        None,
        &[mat![[1.0, 0.0]].as_ref(), mat![[0.0, 1.0]].as_ref()],
    )
    .unwrap();
    let s = Sampling::RoundRobin(vec![SamplingWindow::new(0.1, 0.2).unwrap(); 2]);
    assert_eq!(design_of(&plant, &s).status, Status::NotApplicable);
    let lin = Plant::linear(a.as_ref(), None, mat![[1.0, 0.0]].as_ref()).unwrap();
    let r = Andrieu2014
        .largest_window(
            &lin,
            &window(0.1, 0.5),
            1.0,
            &MethodOptions::default(),
            &mut |_| {},
        )
        .unwrap();
    assert_eq!(r.status, Status::NotApplicable);
}

/// `ferrante2016-example2.toml` (n = 5, a sensor bias state) and `eight-state-modal`-like plants:
/// certified or refused with a reason, in bounded time.
#[test]
fn example_plant_of_order_five() {
    let a = mat![
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, 0.0],
        [-2.0, 1.0, -1.0, 0.0, 0.0],
        [2.0, -2.0, 0.0, -2.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0],
    ];
    let b = mat![[0.0], [0.0], [1.0], [0.0], [0.0]];
    let plant = Plant::linear(
        a.as_ref(),
        Some(b.as_ref()),
        mat![[1.0, 0.0, 0.0, 0.0, 1.0]].as_ref(),
    )
    .unwrap();
    let t = std::time::Instant::now();
    let r = design_of(&plant, &window(0.2, 3.0));
    let secs = t.elapsed().as_secs_f64();
    println!(
        "ferrante2016-example2: {:?} {:?} {:?} in {secs} s",
        r.status, r.window, r.reason
    );
    for n in &r.notes {
        println!("  {n}");
    }
    assert!(secs < 10.0);
    let (l, u) = certified_range(&r);
    assert!(0.0 < l && l <= u);
}

/// The simulation of a certified design: every interval inside the guaranteed window and the
/// error decays.
#[test]
fn simulation_stays_in_the_guaranteed_window_and_converges() {
    let a = mat![[0.0, 1.0], [-4.0, -0.4]];
    let plant = Plant::linear(a.as_ref(), None, mat![[1.0, 0.0]].as_ref()).unwrap();
    let r = design_of(&plant, &window(0.05, 1.0));
    let (l, u) = certified_range(&r);
    let tr = Andrieu2014
        .simulate(&plant, &r, &Scenario::default())
        .unwrap();
    println!("{}", tr.report.result);
    assert!(tr.report.result.contains("inside"), "{}", tr.report.result);
    assert!(tr.report.samples > 10);
    assert!(
        tr.report.final_error < 1e-3 * tr.report.initial_error,
        "{:?}",
        tr.report
    );
    assert!(tr.t.windows(2).all(|w| w[1] >= w[0]));
    assert!(l > 0.0 && u > l);
}

/// Random stable-ish plants of order 2–3 read in their first state.
fn plant_strategy() -> impl Strategy<Value = (usize, Vec<f64>)> {
    (2usize..=3).prop_flat_map(|n| (Just(n), prop::collection::vec(-2.0f64..2.0, n * n)))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(6))]

    /// A → kA (the same plant in another time unit): the guaranteed range scales by 1/k.
    #[test]
    fn metamorphic_time_scaling((n, entries) in plant_strategy(), log_k in -2.0f64..2.0) {
        let k = 10f64.powf(log_k);
        let a = Mat::from_fn(n, n, |i, j| entries[i * n + j] + f64::from(j == i + 1));
        let c = Mat::from_fn(1, n, |_, j| f64::from(j == 0));
        let r = design(a.clone(), c.clone(), 0.1, 1.0);
        prop_assume!(r.status == Status::Certified);
        let (l, u) = certified_range(&r);
        let ak = Mat::from_fn(n, n, |i, j| a[(i, j)] * k);
        let rk = design(ak, c, 0.1 / k, 1.0 / k);
        let (lk, uk) = certified_range(&rk);
        prop_assert!(rel(l / k, lk) < 1e-6, "{} vs {}", l / k, lk);
        prop_assert!(rel(u / k, uk) < 1e-6, "{} vs {}", u / k, uk);
    }

    /// A → SAS⁻¹, C → CS⁻¹ (the same plant in other state coordinates): the same range within 1 %.
    #[test]
    fn metamorphic_similarity(
        (n, entries) in plant_strategy(),
        s_entries in prop::collection::vec(-0.4f64..0.4, 9),
        d_log in prop::collection::vec(-3.0f64..3.0, 3),
    ) {
        let a = Mat::from_fn(n, n, |i, j| entries[i * n + j] + f64::from(j == i + 1));
        let c = Mat::from_fn(1, n, |_, j| f64::from(j == 0));
        let r = design(a.clone(), c.clone(), 0.1, 1.0);
        prop_assume!(r.status == Status::Certified);
        let (l, u) = certified_range(&r);
        // S = D (I + E), ‖E‖ < 1 (well conditioned up to the diagonal units D).
        let s = Mat::from_fn(n, n, |i, j| {
            10f64.powf(d_log[i]) * (f64::from(i == j) + s_entries[i * 3 + j] / n as f64)
        });
        use faer::linalg::solvers::DenseSolveCore;
        let s_inv = s.partial_piv_lu().inverse();
        let rs = design(&s * &a * &s_inv, &c * &s_inv, 0.1, 1.0);
        let (ls, us) = certified_range(&rs);
        prop_assert!(rel(l, ls) < 0.01, "{l} vs {ls}");
        prop_assert!(rel(u, us) < 0.01, "{u} vs {us}");
    }
}
