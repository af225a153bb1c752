//! The [`ObserverMethod`] contract of Rabehi et al. (2021): the trait gives the crate's own design,
//! typed not-applicable and not-certified reasons, invalid input as `Err`, the largest window
//! (including a certified search limit), and the interval simulation.

use faer::{Mat, mat};
use sporadic_model::{
    Bounds as ModelBounds, Lipschitz, MethodError, MethodOptions, ObserverMethod,
    Plant as ModelPlant, Reason, Sampling, SamplingScenario, SamplingWindow, Scenario, SearchEnd,
    Status,
};
use sporadic_rabehi2021::example::{example_window, spring_mass_damper};
use sporadic_rabehi2021::synthesis::{NotCertified, SynthesisOptions, synthesise};
use sporadic_rabehi2021::window::{TauMaxOptions, largest_tau_max};
use sporadic_rabehi2021::{Rabehi2021, system};

/// The §V example as a contract plant: spring–mass–damper `c_s = 1`, `|d_i| ≤ 1`, `|v| ≤ 0.4`.
fn example_plant() -> ModelPlant {
    let p = spring_mass_damper(1.0).unwrap();
    ModelPlant::linear(p.a(), Some(p.b()), p.c())
        .unwrap()
        .named("spring-mass-damper")
        .with_bounds(ModelBounds::new(vec![1.0, 1.0], vec![0.4]).unwrap())
        .unwrap()
}

/// A stable plant whose window [0.5, 20] is certified (the max-interval regression).
fn stable_plant() -> ModelPlant {
    ModelPlant::linear(
        mat![[-1.0, 0.5], [0.0, -2.0]].as_ref(),
        None,
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap()
    .named("stable")
    .with_bounds(ModelBounds::new(vec![0.1, 0.1], vec![0.01]).unwrap())
    .unwrap()
}

fn synchronous(t1: f64, t2: f64) -> Sampling {
    Sampling::Synchronous(SamplingWindow::new(t1, t2).unwrap())
}

fn bits(m: &Mat<f64>) -> Vec<u64> {
    (0..m.nrows())
        .flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)].to_bits()))
        .collect()
}

#[test]
fn the_trait_gives_the_crate_design_on_the_paper_example() {
    let method = Rabehi2021::default();
    let window = example_window();
    let r = method
        .design(
            &example_plant(),
            &Sampling::Synchronous(window),
            &MethodOptions::default(),
        )
        .unwrap();
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    let d = synthesise(
        &spring_mass_damper(1.0).unwrap(),
        &window,
        &SynthesisOptions::default(),
    )
    .unwrap();
    assert!(d.is_certified());
    assert_eq!(bits(&r.gain("L").unwrap().to_mat()), bits(&d.l));
    let cert = |name: &str| {
        r.certificate
            .iter()
            .find(|c| c.name == name)
            .unwrap()
            .to_mat()
    };
    assert_eq!(bits(&cert("P")), bits(&d.p));
    assert_eq!(bits(&cert("G1")), bits(&d.g1));
    assert_eq!(bits(&cert("G2")), bits(&d.g2));
    let margin = r.margin.as_ref().unwrap();
    assert_eq!(margin.value.to_bits(), d.bmi.margin().to_bits());
    assert!(margin.value > 0.0 && margin.definition.contains("P ⪯"));
    assert!(
        r.checks.len() >= 4 && r.checks.iter().all(|c| c.passed),
        "{:?}",
        r.checks
    );
    assert!(
        r.notes
            .iter()
            .any(|n| n.contains("guaranteed interval width"))
    );
    assert_eq!(r.window, Some(window));
    // The deadbeat feature of the example: 1 + 2 L1 ≈ 0.
    assert!((1.0 + 2.0 * r.gain("L").unwrap().rows[0][0]).abs() < 0.01);
}

#[test]
fn plants_outside_the_method_are_not_applicable() {
    let method = Rabehi2021::default();
    let o = MethodOptions::default();
    let s = synchronous(0.04, 0.3);
    // No bounds: missing data.
    let p = spring_mass_damper(1.0).unwrap();
    let bare = ModelPlant::linear(p.a(), Some(p.b()), p.c()).unwrap();
    let r = method.design(&bare, &s, &o).unwrap();
    assert_eq!(r.status, Status::NotApplicable);
    assert!(
        matches!(r.reason, Some(Reason::MissingData { .. })),
        "{r:?}"
    );
    // A Lipschitz nonlinearity: unsupported.
    let lip = Lipschitz::new(
        mat![[0.0], [1.0]].as_ref(),
        mat![[1.0, 0.0]].as_ref(),
        mat![[-1.0]].as_ref(),
        mat![[1.0]].as_ref(),
    )
    .unwrap();
    let nonlinear = example_plant().with_lipschitz(lip).unwrap();
    let r = method.design(&nonlinear, &s, &o).unwrap();
    assert_eq!(r.status, Status::NotApplicable);
    assert!(matches!(
        r.reason,
        Some(Reason::UnsupportedStructure { .. })
    ));
    // Round-robin sensors: unsupported.
    let rr = ModelPlant::round_robin(
        p.a(),
        Some(p.b()),
        &[mat![[1.0, 0.0]].as_ref(), mat![[0.0, 1.0]].as_ref()],
    )
    .unwrap()
    .with_bounds(ModelBounds::new(vec![], vec![]).unwrap())
    .unwrap();
    let rs = Sampling::RoundRobin(vec![SamplingWindow::new(0.04, 0.3).unwrap(); 2]);
    let r = method.design(&rr, &rs, &o).unwrap();
    assert!(matches!(
        r.reason,
        Some(Reason::UnsupportedStructure { .. })
    ));
    assert!(method.applies(&example_plant(), &s).is_ok());
}

#[test]
fn a_window_beyond_the_necessary_limit_is_not_certified_with_a_typed_reason() {
    // c_s = 1: no gain passes (19) once T2 ≥ 2.037 (x2 unmeasured). One alternation cycle and no
    // sequential step keep the test short: the step limit ends the run.
    let method = Rabehi2021 {
        synthesis: SynthesisOptions {
            max_alternations: 1,
            sequential: false,
            ..SynthesisOptions::default()
        },
    };
    let r = method
        .design(
            &example_plant(),
            &synchronous(0.04, 2.5),
            &MethodOptions::default(),
        )
        .unwrap();
    assert_eq!(r.status, Status::NotCertified);
    let reason = r.reason.unwrap();
    assert!(
        matches!(
            reason,
            Reason::BudgetExhausted { .. } | Reason::InfeasibleLmi { .. }
        ),
        "{reason:?}"
    );
    assert!(reason.message().contains("(44) not certified"), "{reason}");
    assert!(r.gains.is_empty() && r.margin.is_none());
}

#[test]
fn not_certified_variants_map_to_their_reasons() {
    let infeasible = NotCertified::Infeasible {
        best_t: 0.1,
        remainder_effect: 1e-9,
        rounding: 1e-12,
        steps: 3,
    };
    assert_eq!(infeasible.reason().kind(), "infeasible_lmi");
    // A negative best value is refused with the rounding bound that decided it.
    assert!(
        infeasible.to_string().contains("rounding bound 1.000e-12"),
        "{infeasible}"
    );
    let budget = NotCertified::BudgetExhausted {
        best_t: 0.1,
        steps: 25,
        limit: "max_sequential",
    };
    assert_eq!(budget.reason().kind(), "budget_exhausted");
    let failed = NotCertified::VerificationFailed {
        best_t: -0.1,
        tau: Some(0.7),
        detail: "grid bound 1e-3".into(),
    };
    assert!(matches!(
        failed.reason(),
        Reason::VerificationFailed { tau: Some(t), .. } if t == 0.7
    ));
}

#[test]
fn invalid_input_is_an_error() {
    let bad = Rabehi2021 {
        synthesis: SynthesisOptions {
            p_min: -1.0,
            ..SynthesisOptions::default()
        },
    };
    let e = bad
        .design(
            &example_plant(),
            &synchronous(0.04, 0.3),
            &MethodOptions::default(),
        )
        .unwrap_err();
    assert!(matches!(e, MethodError::InvalidInput { .. }), "{e:?}");
    assert!(e.chain().contains("p_min"), "{}", e.chain());
    // A search limit below T1.
    let e = Rabehi2021::default()
        .largest_window(
            &example_plant(),
            &synchronous(0.04, 0.3),
            0.01,
            &MethodOptions::default(),
            &mut |_| {},
        )
        .unwrap_err();
    assert!(matches!(e, MethodError::InvalidInput { .. }), "{e:?}");
}

/// Regression: a certified search limit is the answer, with no failing `T2` (the former facade
/// reported "largest certified 19.982 (fails at 20.000)" without testing 20).
#[test]
fn a_certified_limit_is_the_largest_window_with_no_failure() {
    let method = Rabehi2021::default();
    let o = MethodOptions::default();
    let plant = stable_plant();
    let d = method.design(&plant, &synchronous(0.5, 20.0), &o).unwrap();
    assert!(d.status.is_certified(), "{:?}", d.reason);
    let r = method
        .largest_window(&plant, &synchronous(0.5, 0.5), 20.0, &o, &mut |_| {})
        .unwrap();
    assert_eq!(r.status, Status::Certified);
    assert_eq!(r.largest_certified_t2, Some(20.0));
    assert_eq!(r.first_failing_t2, None);
    assert_eq!(r.search_end, Some(SearchEnd::ReachedLimit));
    assert_eq!(r.probes.last().unwrap().t2, 20.0);
    assert!(r.design.as_ref().unwrap().status.is_certified());
    // The crate's own search says the same.
    let p = system::Plant::new(
        mat![[-1.0, 0.5], [0.0, -2.0]].as_ref(),
        Mat::<f64>::zeros(2, 0).as_ref(),
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap();
    let s = largest_tau_max(
        &p,
        0.5,
        &TauMaxOptions {
            upper: 20.0,
            resolution: 0.2,
            ..TauMaxOptions::default()
        },
    )
    .unwrap();
    assert_eq!((s.certified(), s.refuted()), (Some(20.0), None));
    assert_eq!(s.search.end, SearchEnd::ReachedLimit);
    assert_eq!(s.search.probes.len(), 2);
}

/// The shared search on the example (c_s = 1, T1 = 0.04) brackets the crate's own search with
/// the split polytope (claim `table1.split_polytope.cs=1`: 2.02770, probed at 0.009 below the
/// necessary limit ≈ 2.0367), and stops at the necessary limit.
#[test]
fn largest_window_on_the_example_brackets_the_crate_search() {
    let (previous, resolution) = (2.0276974182128913, 0.01);
    let necessary =
        sporadic_rabehi2021::necessary_tau_max(&spring_mass_damper(1.0).unwrap(), 0.04, 5.0)
            .unwrap()
            .unwrap();
    let mut seen = Vec::new();
    let r = Rabehi2021::default()
        .largest_window(
            &example_plant(),
            &synchronous(0.04, 0.3),
            5.0,
            &MethodOptions::default(),
            &mut |p| seen.push(p.t2),
        )
        .unwrap();
    let (best, fail) = (r.largest_certified_t2.unwrap(), r.first_failing_t2.unwrap());
    assert!(best <= previous + resolution && fail > previous, "{r:?}");
    assert!(
        fail <= necessary + 1e-3 && fail / best - 1.0 <= 1e-2,
        "{best} {fail}"
    );
    assert_eq!(r.limit, Some(5.0));
    assert!(seen.iter().all(|&t| t <= necessary + 1e-3), "{seen:?}");
    let cap_probe = r.probes.iter().find(|p| p.t2 >= necessary - 1e-3).unwrap();
    assert!(matches!(
        &cap_probe.reason,
        Some(Reason::InfeasibleLmi { message }) if message.contains("necessary condition")
    ));
    assert!(
        r.design
            .as_ref()
            .unwrap()
            .notes
            .iter()
            .any(|n| n.contains("necessary"))
    );
}

#[test]
fn simulation_of_a_certified_design_shrinks_the_interval() {
    let method = Rabehi2021::default();
    let plant = stable_plant();
    let d = method
        .design(&plant, &synchronous(0.5, 2.0), &MethodOptions::default())
        .unwrap();
    assert!(d.status.is_certified(), "{:?}", d.reason);
    let t = method.simulate(&plant, &d, &Scenario::default()).unwrap();
    assert_eq!(t.signals.len(), 2);
    assert_eq!(t.t.len(), t.norm.len());
    assert!(
        t.report.final_error < t.report.initial_error,
        "{:?}",
        t.report
    );
    assert!((t.report.initial_error - 8f64.sqrt()).abs() < 1e-12);
    assert!(t.report.result.contains("held"), "{}", t.report.result);
    assert!(t.report.samples > 10 && *t.t.last().unwrap() >= 80.0 - 1e-9);
    // Periodic sampling at T2, a given initial half-width and horizon.
    let s = Scenario {
        horizon: Some(10.0),
        initial_error: Some(vec![0.5, -2.0]),
        sampling: SamplingScenario::PeriodicT2,
    };
    let t = method.simulate(&plant, &d, &s).unwrap();
    assert_eq!(t.report.samples, 5);
    assert!((t.report.initial_error - (1.0f64 + 16.0).sqrt()).abs() < 1e-12);
    // A wrong initial half-width is bad input; a report without a design has no simulation.
    let bad = Scenario {
        initial_error: Some(vec![1.0]),
        ..Scenario::default()
    };
    assert!(matches!(
        method.simulate(&plant, &d, &bad),
        Err(MethodError::InvalidInput { .. })
    ));
    let none = method
        .design(
            &plant.clone().named("x"),
            &synchronous(0.5, 2.0),
            &MethodOptions::default(),
        )
        .map(|mut r| {
            r.status = Status::NotCertified;
            r
        })
        .unwrap();
    assert!(matches!(
        method.simulate(&plant, &none, &Scenario::default()),
        Err(MethodError::SimulationUnavailable { .. })
    ));
}

/// An inverted pendulum with a bounded torque disturbance (written for this check).
fn inverted_pendulum() -> ModelPlant {
    ModelPlant::linear(
        mat![[0.0, 1.0], [9.81, -0.1]].as_ref(),
        None,
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap()
    .with_bounds(ModelBounds::new(vec![0.0, 0.5], vec![0.002]).unwrap())
    .unwrap()
}

/// The pendulum's width map contracts only by `≈ 4·10⁻⁵` per sample near the method's limit:
/// certified, with a note that no width bound was found in the iteration budget, in words (it
/// read "invalid parameter width bound iterations = 100000").
#[test]
fn a_slowly_contracting_width_map_says_so() {
    let plant = inverted_pendulum();
    let r = Rabehi2021::default()
        .design(&plant, &synchronous(0.002, 0.02), &MethodOptions::default())
        .unwrap();
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    let note = r
        .notes
        .iter()
        .find(|n| n.starts_with("no guaranteed width bound"))
        .expect("a note on the width bound");
    assert!(note.contains("contracts too slowly"), "{note}");
    assert!(!note.contains("invalid parameter"), "{note}");
}

/// The pendulum's open-loop state grows like `e^{3.08t}`: over 20 s it reaches `10²⁴` while the
/// widths stay of order one, so `x̄ − x̲` is lost to rounding (the run reported widths of 0, the
/// enclosure "VIOLATED" and the error settled). The run is returned up to where the widths are
/// resolved, and says so.
#[test]
fn an_unstable_plant_is_simulated_while_its_widths_are_resolved() {
    let method = Rabehi2021::default();
    let plant = inverted_pendulum();
    let d = method
        .design(&plant, &synchronous(0.002, 0.02), &MethodOptions::default())
        .unwrap();
    let s = Scenario {
        horizon: Some(20.0),
        initial_error: None,
        sampling: SamplingScenario::PeriodicT2,
    };
    let t = method.simulate(&plant, &d, &s).unwrap();
    let r = &t.report.result;
    assert!(r.contains("held at every recorded point"), "{r}");
    assert!(r.contains("double-precision resolution"), "{r}");
    let end = *t.t.last().unwrap();
    assert!(end > 1.0 && end < 20.0, "{end}");
    // The report says where the run ends, so that no one reads "not settled" as a failure to
    // settle within the horizon.
    let cut = t.report.ends_early_at.expect("the run is cut short");
    assert!(cut > end && cut < 20.0, "{cut} {end}");
    assert!(t.report.final_error > 0.1, "{:?}", t.report);
    assert_eq!(t.norm.len(), t.t.len());
}

/// A synthesis whose solves are interrupted by the time budget ends `BudgetExhausted`: its best
/// value is that of interrupted solves, no verdict. (It read "infeasible_lmi: best
/// max_i lambda_max(Psi_i) = 0.000e0 … (stalled)" on a DC servo with `--time-limit 5`, and
/// `design_within` keeps an infeasibility as decided.)
#[test]
fn a_synthesis_cut_by_the_time_budget_is_no_infeasibility() {
    use sporadic_sdp::budget::{Budget, within};
    let window = example_window();
    let plant = spring_mass_damper(1.0).unwrap();
    let r = within(Budget::until(std::time::Instant::now()), || {
        synthesise(&plant, &window, &SynthesisOptions::default())
    });
    match r {
        Ok(d) => assert!(
            matches!(
                d.status,
                sporadic_rabehi2021::synthesis::DesignStatus::NotCertified(
                    NotCertified::BudgetExhausted { .. }
                )
            ),
            "{:?}",
            d.status
        ),
        Err(e) => assert!(
            matches!(e, sporadic_rabehi2021::Error::SolverInconclusive { .. }),
            "{e}"
        ),
    }
}
