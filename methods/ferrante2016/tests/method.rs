//! The `ObserverMethod` contract of `Ferrante2016`: same numbers as the crate's own entry points,
//! typed verdicts, typed input errors, the window search and the simulation.

use std::f64::consts::PI;
use std::time::Duration;

use faer::{Mat, mat};
use sporadic_ferrante2016::examples::example2;
use sporadic_ferrante2016::sporadic_model::{Lipschitz, Plant as ModelPlant};
use sporadic_ferrante2016::{
    DesignOptions, Ferrante2016, MethodError, MethodOptions, ObserverMethod, Plant, Reason,
    Sampling, SamplingScenario, SamplingWindow, Scenario, SearchEnd, Status, WindowSearchOptions,
    design, largest_t2,
};

fn rows(m: &Mat<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

fn sync(t1: f64, t2: f64) -> Sampling {
    Sampling::Synchronous(SamplingWindow::new(t1, t2).unwrap())
}

/// Example 2 as a plant of the common contract.
fn example2_plant() -> ModelPlant {
    let ex = example2().unwrap();
    ModelPlant::linear(ex.plant.a(), Some(ex.b.as_ref()), ex.plant.c())
        .unwrap()
        .named("Example 2")
}

/// Undamped oscillator measured in position: `(e^{Av}, C)` is not detectable at `v = π`.
fn oscillator() -> ModelPlant {
    ModelPlant::linear(
        mat![[0.0, 1.0], [-1.0, 0.0]].as_ref(),
        None,
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap()
}

#[test]
fn the_trait_gives_the_crates_design_bitwise() {
    let ex = example2().unwrap();
    let method = Ferrante2016::default();
    let r = method
        .design(
            &example2_plant(),
            &sync(0.2, 3.0),
            &MethodOptions::default(),
        )
        .unwrap();
    let d = design(&ex.plant, &ex.window, &DesignOptions::default()).unwrap();
    assert_eq!(r.status, Status::Certified);
    assert_eq!(r.reason, None);
    assert_eq!(r.method, "ferrante2016");
    assert_eq!(r.window, Some(ex.window));
    let l = r.gain("L").unwrap();
    assert_eq!(l.rows, rows(&d.l));
    assert!(l.schedule.is_none());
    assert!(l.meaning.contains("ẑ⁺ = ẑ + L(y − Cẑ)"));
    let margin = r.margin.as_ref().unwrap();
    assert_eq!(margin.value.to_bits(), d.certificate.margin.to_bits());
    assert!(margin.definition.contains("‖P‖₂ ≤ 1") && margin.definition.contains("t ≤ 1"));
    let cert = |name: &str| r.certificate.iter().find(|m| m.name == name).unwrap();
    assert_eq!(cert("P").rows, rows(&d.certificate.p));
    assert_eq!(cert("F").rows, rows(&d.certificate.f));
    assert_eq!(cert("J").rows, rows(&d.certificate.j));
    assert!(r.checks.len() >= 4 && r.checks.iter().all(|c| c.passed));
    let grid = r.checks.iter().find(|c| c.what.contains("(12)")).unwrap();
    assert_eq!(grid.value, Some(d.verification.max_eigenvalue));
    assert!(grid.how.contains("2801"));
    assert!(r.seconds > 0.0);
    assert!(method.observer().contains("ẑ⁺ = ẑ + L(y − Cẑ)"));
    assert!(method.citation().contains("Automatica 73"));
}

#[test]
fn outside_the_method_is_not_applicable_with_a_typed_reason() {
    let method = Ferrante2016::default();
    let opts = MethodOptions::default();
    let lipschitz = oscillator()
        .with_lipschitz(
            Lipschitz::new(
                mat![[0.0], [1.0]].as_ref(),
                mat![[1.0, 0.0]].as_ref(),
                mat![[-1.0]].as_ref(),
                mat![[1.0]].as_ref(),
            )
            .unwrap(),
        )
        .unwrap();
    let c1 = mat![[1.0, 0.0]];
    let c2 = mat![[0.0, 1.0]];
    let round_robin = ModelPlant::round_robin(
        mat![[0.0, 1.0], [-1.0, 0.0]].as_ref(),
        None,
        &[c1.as_ref(), c2.as_ref()],
    )
    .unwrap();
    let rr_sampling = Sampling::RoundRobin(vec![
        SamplingWindow::new(0.1, 0.2).unwrap(),
        SamplingWindow::new(0.1, 0.2).unwrap(),
    ]);
    for (plant, sampling) in [
        (&lipschitz, sync(0.1, 0.5)),
        (&round_robin, sync(0.1, 0.5)),
        (&oscillator(), rr_sampling),
    ] {
        assert!(method.applies(plant, &sampling).is_err());
        let r = method.design(plant, &sampling, &opts).unwrap();
        assert_eq!(r.status, Status::NotApplicable);
        assert!(
            matches!(r.reason, Some(Reason::UnsupportedStructure { .. })),
            "{:?}",
            r.reason
        );
        assert!(r.gains.is_empty() && r.margin.is_none());
        let w = method
            .largest_window(plant, &sampling, 1.0, &opts, &mut |_| {})
            .unwrap();
        assert_eq!(w.status, Status::NotApplicable);
        assert!(w.probes.is_empty());
    }
}

#[test]
fn an_aliasing_interval_in_the_window_is_undetectable_at_that_interval() {
    let r = Ferrante2016::default()
        .design(&oscillator(), &sync(2.0, 4.0), &MethodOptions::default())
        .unwrap();
    assert_eq!(r.status, Status::NotCertified);
    match &r.reason {
        Some(Reason::Undetectable { tau, message }) => {
            assert!((tau - PI).abs() < 1e-12, "tau = {tau}");
            assert!(message.contains("not detectable"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    assert!(r.gains.is_empty() && r.margin.is_none());
}

#[test]
fn a_window_far_too_long_for_an_unstable_plant_is_not_certified() {
    // Eigenvalues 1 and 2, position measured: on [0.1, 8] no gain makes e^(Av)(I − LC) Schur
    // (its determinant e^(3v)(1 − CL) needs CL ≈ 1, its trace e^v + e^(2v) − C e^(Av) L then
    // needs C R_1 L ≈ 1 and C R_2 L ≈ 1 for the residues R_1 + R_2 = I, so CL ≈ 2). (The plant
    // with eigenvalues 1 and −2 that this test used is certifiable: L = (1, 1/2) cancels the
    // unstable mode, e^(Av)(I − LC) has eigenvalues 0 and e^(−2v).)
    let plant = ModelPlant::linear(
        mat![[0.0, 1.0], [-2.0, 3.0]].as_ref(),
        None,
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap();
    let r = Ferrante2016::default()
        .design(&plant, &sync(0.1, 8.0), &MethodOptions::default())
        .unwrap();
    assert_eq!(r.status, Status::NotCertified);
    assert!(
        matches!(r.reason, Some(Reason::InfeasibleLmi { .. })),
        "{:?}",
        r.reason
    );
}

#[test]
fn invalid_input_is_an_error_not_a_verdict() {
    let method = Ferrante2016 {
        design: DesignOptions {
            pieces: 0,
            ..Default::default()
        },
        ..Default::default()
    };
    let e = method
        .design(&oscillator(), &sync(0.5, 1.0), &MethodOptions::default())
        .unwrap_err();
    assert!(matches!(e, MethodError::InvalidInput { .. }), "{e}");
    assert!(e.chain().contains("pieces"), "{}", e.chain());
    let e = method
        .largest_window(
            &oscillator(),
            &sync(0.5, 1.0),
            2.0,
            &MethodOptions::default(),
            &mut |_| {},
        )
        .unwrap_err();
    assert!(matches!(e, MethodError::InvalidInput { .. }), "{e}");
    // A search limit below T1.
    let e = Ferrante2016::default()
        .largest_window(
            &oscillator(),
            &sync(0.5, 1.0),
            0.1,
            &MethodOptions::default(),
            &mut |_| {},
        )
        .unwrap_err();
    assert!(matches!(e, MethodError::InvalidInput { .. }), "{e}");
}

#[test]
fn largest_window_is_the_crates_search() {
    let method = Ferrante2016::default();
    let opts = MethodOptions::default();
    let mut seen = Vec::new();
    let r = method
        .largest_window(&oscillator(), &sync(0.5, 1.0), 5.0, &opts, &mut |p| {
            seen.push(p.clone())
        })
        .unwrap();
    let crate_plant = Plant::new(
        mat![[0.0, 1.0], [-1.0, 0.0]].as_ref(),
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap();
    let w = largest_t2(
        &crate_plant,
        0.5,
        5.0,
        &DesignOptions::default(),
        &WindowSearchOptions::default(),
    )
    .unwrap();
    assert_eq!(r.status, Status::Certified);
    assert_eq!(r.largest_certified_t2, w.best);
    assert_eq!(r.first_failing_t2, w.first_failure);
    assert_eq!(r.search_end, Some(SearchEnd::Converged));
    assert_eq!(r.probes, w.probes);
    assert_eq!(seen, r.probes);
    let (best, fail) = (r.largest_certified_t2.unwrap(), r.first_failing_t2.unwrap());
    // Detectability is lost at v = π: nothing beyond it is certified; the bracket is within 1 %.
    assert!(
        best < PI && best < fail && fail / best - 1.0 <= 1e-2 + 1e-12,
        "{best} {fail}"
    );
    assert!(r.probes.iter().all(|p| p.certified == (p.t2 <= best)));
    let d = r.design.as_ref().unwrap();
    assert_eq!(d.window, Some(SamplingWindow::new(0.5, best).unwrap()));
    assert!(d.status.is_certified());
    // Example 2: certified up to the limit 30, as before (no finite maximal T2).
    let r = method
        .largest_window(&example2_plant(), &sync(0.2, 3.0), 30.0, &opts, &mut |_| {})
        .unwrap();
    assert_eq!(r.largest_certified_t2, Some(30.0));
    assert_eq!(r.first_failing_t2, None);
    assert_eq!(r.search_end, Some(SearchEnd::ReachedLimit));
    // Out of time: the bracket found so far, with a typed reason.
    let hurry = MethodOptions {
        time_limit: Some(Duration::ZERO),
        ..Default::default()
    };
    let r = method
        .largest_window(&oscillator(), &sync(0.5, 1.0), 5.0, &hurry, &mut |_| {})
        .unwrap();
    assert_eq!(r.search_end, Some(SearchEnd::BudgetExhausted));
    assert!(matches!(r.reason, Some(Reason::BudgetExhausted { .. })));
}

#[test]
fn simulation_of_a_certified_design_converges() {
    let method = Ferrante2016::default();
    let plant = example2_plant();
    let r = method
        .design(&plant, &sync(0.2, 3.0), &MethodOptions::default())
        .unwrap();
    for sampling in [
        SamplingScenario::Uniform { seed: 3 },
        SamplingScenario::PeriodicT1,
        SamplingScenario::PeriodicT2,
    ] {
        let scenario = Scenario {
            sampling,
            ..Scenario::default()
        };
        let t = method.simulate(&plant, &r, &scenario).unwrap();
        let s = &t.report;
        assert_eq!(s.initial_error, 5f64.sqrt());
        assert!(s.final_error < 1e-3 * s.initial_error, "{s:?}");
        assert!(s.samples >= 30, "{s:?}");
        assert!(s.figure.is_none());
        assert_eq!(t.signals.len(), 5);
        assert!(t.signals.iter().all(|(_, x)| x.len() == t.t.len()));
        assert_eq!((t.j.len(), t.norm.len()), (t.t.len(), t.t.len()));
        assert!((t.t.last().unwrap() - 90.0).abs() < 1e-9, "horizon 30·T2");
    }
    // A wrong initial error is bad input; a report without design has nothing to simulate.
    let bad = Scenario {
        initial_error: Some(vec![1.0; 3]),
        ..Scenario::default()
    };
    assert!(matches!(
        method.simulate(&plant, &r, &bad),
        Err(MethodError::InvalidInput { .. })
    ));
    let failed = method
        .design(&oscillator(), &sync(2.0, 4.0), &MethodOptions::default())
        .unwrap();
    assert!(matches!(
        method.simulate(&oscillator(), &failed, &Scenario::default()),
        Err(MethodError::SimulationUnavailable { .. })
    ));
}

/// A search cut short by the budget reports the bracket it had: the largest certified `T2`,
/// the smallest failing one above it, and whether the verdicts so far are monotone (the CLI
/// once said "certified up to the search limit" for such a search).
#[test]
fn a_search_cut_short_keeps_its_first_failure() {
    use sporadic_ferrante2016::sporadic_model::{Budget, budget, largest_window_with};
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};
    let method = Ferrante2016::default();
    let plant = oscillator();
    let opts = MethodOptions::default();
    let stop = Arc::new(AtomicBool::new(false));
    let mut probes = 0;
    // Scan of [0.5, 5]: 0.5, 0.73, 1.08, 1.58, 2.32 certified, 3.41 not (detectability is lost
    // at π); the budget is cancelled as the seventh probe (the limit) starts, so that probe is
    // no verdict.
    let r = budget::within(Budget::unlimited().with_cancel(stop.clone()), || {
        largest_window_with(
            &method,
            &plant,
            &sync(0.5, 1.0),
            5.0,
            &WindowSearchOptions::default(),
            &opts,
            &mut |_| {},
            &mut |s| {
                probes += 1;
                if probes == 7 {
                    stop.store(true, Ordering::Relaxed);
                }
                method.design(&plant, s, &opts)
            },
        )
    })
    .unwrap();
    assert_eq!(r.search_end, Some(SearchEnd::BudgetExhausted));
    assert_eq!(r.probes.len(), 6);
    let (best, fail) = (r.largest_certified_t2.unwrap(), r.first_failing_t2.unwrap());
    assert!((best - 0.5 * 10f64.powf(4.0 / 6.0)).abs() < 1e-9, "{best}");
    assert!((fail - 0.5 * 10f64.powf(5.0 / 6.0)).abs() < 1e-9, "{fail}");
    assert!(r.monotone);
    assert_eq!(r.status, Status::Certified);
}
