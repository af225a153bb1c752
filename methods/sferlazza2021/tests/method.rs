//! The [`ObserverMethod`] contract of Sferlazza et al. (2021): same results as the crate's own
//! design entry point, typed verdicts, invalid input, the window search and the simulation.

use faer::mat;
use sporadic_linalg::balance::{balancing_scales, unbalance_form, unbalance_gain};
use sporadic_model::{ProofOptions, ProofStatus, prove_within};
use sporadic_sferlazza2021::example::{QuarterCar, WINDOWS};
use sporadic_sferlazza2021::normalise::balanced_plant;
use sporadic_sferlazza2021::{
    DesignOptions, GridPolicy, MethodError, MethodOptions, ObserverMethod, Plant, Sampling,
    SamplingScenario, SamplingWindow, Scenario, Sferlazza2021, design,
};
use sporadic_sferlazza2021::{Lipschitz, Reason, SearchEnd, Status};

fn win(t1: f64, t2: f64) -> SamplingWindow {
    SamplingWindow::new(t1, t2).unwrap()
}

/// The quarter car of §6 as a plant of the contract (orthonormal complements `C_σ^⊥`).
fn suspension() -> (Plant, Sampling) {
    let a = QuarterCar::default().a();
    let (c1, c2) = (mat![[1.0, 0.0, 0.0, 0.0]], mat![[0.0, 0.0, 1.0, 0.0]]);
    let plant = Plant::round_robin(a.as_ref(), None, &[c1.as_ref(), c2.as_ref()])
        .unwrap()
        .named("suspension");
    let sampling = Sampling::RoundRobin(WINDOWS.iter().map(|&(a, b)| win(a, b)).collect());
    (plant, sampling)
}

/// The lightly damped oscillator of the crate docs, position and velocity read in turn.
fn oscillator(t1: f64, t2: f64) -> (Plant, Sampling) {
    let a = mat![[0.0, 1.0], [-4.0, -0.2]];
    let (c1, c2) = (mat![[1.0, 0.0]], mat![[0.0, 1.0]]);
    let plant = Plant::round_robin(a.as_ref(), None, &[c1.as_ref(), c2.as_ref()]).unwrap();
    (plant, Sampling::RoundRobin(vec![win(t1, t2), win(t1, t2)]))
}

/// The round-robin plant in the balanced coordinates the contract designs in.
fn balanced(plant: &Plant, sampling: &Sampling) -> sporadic_sferlazza2021::RoundRobinPlant {
    let rr = Sferlazza2021::round_robin_plant(plant, sampling).unwrap();
    balanced_plant(&rr, &balancing_scales(rr.a())).unwrap()
}

fn fast() -> Sferlazza2021 {
    Sferlazza2021 {
        design: DesignOptions {
            grid: GridPolicy::Spacing(1e-5),
            ..DesignOptions::default()
        },
        ..Sferlazza2021::default()
    }
}

/// The report's gain schedules, certificate and margin are those of `design()` on the same
/// round-robin plant, bitwise; the margin is the normalised exact grid minimum and exceeds
/// μ / max λ_max(P).
#[test]
fn trait_design_equals_the_crate_design() {
    let (plant, sampling) = suspension();
    let m = Sferlazza2021::default();
    let r = m
        .design(&plant, &sampling, &MethodOptions::default())
        .unwrap();
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    // The contract designs in balanced coordinates (powers of 2, exact) and maps back.
    let rr = balanced(&plant, &sampling);
    let scales = balancing_scales(
        Sferlazza2021::round_robin_plant(&plant, &sampling)
            .unwrap()
            .a(),
    );
    let d = design(&rr, &m.design).unwrap();
    assert_eq!(r.gains.len(), 2);
    for s in 0..2 {
        let g = r.gain(&format!("K_{}", s + 1)).unwrap();
        let sch = g.schedule.as_ref().unwrap();
        assert_eq!(sch.tau.len(), 11);
        assert_eq!(sch.tau[0], WINDOWS[s].0);
        assert_eq!(*sch.tau.last().unwrap(), WINDOWS[s].1);
        for (t, k) in sch.tau.iter().zip(&sch.samples) {
            let ours = unbalance_gain(d.gains().gain(s, *t).unwrap().as_ref(), &scales);
            assert_eq!(k.len(), 4);
            for (i, row) in k.iter().enumerate() {
                assert_eq!(row, &vec![ours[(i, 0)]], "K_{}({t})", s + 1);
            }
        }
        let p = r.certificate[s].to_mat();
        assert_eq!(p, unbalance_form(d.p[s].as_ref(), &scales), "P_{}", s + 1);
    }
    let minima = d.grid_minima(&m.design.validation).unwrap();
    let margin = d.normalised_margin(&minima).unwrap();
    let reported = r.margin.as_ref().unwrap();
    assert_eq!(reported.value, margin);
    let p_max =
        d.p.iter()
            .map(|p| sporadic_linalg::max_eigenvalue(p.as_ref()).unwrap())
            .fold(0.0, f64::max);
    assert!(margin > d.mu / p_max, "{margin}");
    assert!(reported.definition.contains("max_σ λ_max(P_σ) = 1"));
    // Each grid minimum is attained on its grid and is not above any validated point.
    for g in &minima {
        let fam = sporadic_sferlazza2021::XiFamily::new(d.plant(), &d.p, g.sigma).unwrap();
        let k = ((g.argmin_tau - g.grid.t_min) / g.grid.spacing).round() as usize;
        assert!((g.grid.tau(k) - g.argmin_tau).abs() < 1e-15);
        for j in [0, g.grid.points / 2, g.grid.points - 1] {
            assert!(fam.min_eigenvalue(g.grid.tau(j)).unwrap() >= g.min_eigenvalue - 1e-9);
        }
    }
    assert!(r.checks.iter().all(|c| c.passed) && r.checks.len() >= 5);
}

#[test]
fn not_applicable_cases_are_typed() {
    let m = Sferlazza2021::default();
    let (plant, sampling) = oscillator(0.1, 0.3);
    let lip = Lipschitz::new(
        mat![[0.0], [1.0]].as_ref(),
        mat![[1.0, 0.0]].as_ref(),
        mat![[-1.0]].as_ref(),
        mat![[1.0]].as_ref(),
    )
    .unwrap();
    let nonlinear = plant.clone().with_lipschitz(lip).unwrap();
    let r = m
        .design(&nonlinear, &sampling, &MethodOptions::default())
        .unwrap();
    assert_eq!(r.status, Status::NotApplicable);
    assert!(matches!(
        r.reason,
        Some(Reason::UnsupportedStructure { .. })
    ));
    assert!(m.applies(&nonlinear, &sampling).is_err());
    // Assumption 1: a sensor that measures nothing (dependent outputs are read through their
    // independent combinations, tests/dependent_outputs.rs).
    let a = mat![[0.0, 1.0], [-4.0, -0.2]];
    let c = mat![[0.0, 0.0], [0.0, 0.0]];
    let blind = Plant::linear(a.as_ref(), None, c.as_ref()).unwrap();
    let r = m
        .design(
            &blind,
            &Sampling::Synchronous(win(0.1, 0.3)),
            &MethodOptions::default(),
        )
        .unwrap();
    assert_eq!(r.status, Status::NotApplicable);
    assert!(
        matches!(&r.reason, Some(Reason::UnsupportedStructure { message }) if message.contains("Assumption 1"))
    );
}

/// A window containing the aliasing interval π/ω of an oscillator seen through its position:
/// the Proposition 1 screen finds a τ; without the screen (47) is infeasible; one iteration is
/// not enough for the suspension.
#[test]
fn not_certified_cases_have_typed_reasons() {
    let w = 3.0;
    let t = std::f64::consts::PI / w;
    let a = mat![[0.0, w], [-w, 0.0]];
    let plant = Plant::linear(a.as_ref(), None, mat![[1.0, 0.0]].as_ref()).unwrap();
    let sampling = Sampling::Synchronous(win(t - 0.2, t));
    let m = fast();
    let r = m
        .design(&plant, &sampling, &MethodOptions::default())
        .unwrap();
    assert_eq!(r.status, Status::NotCertified);
    match &r.reason {
        Some(Reason::Undetectable { tau, .. }) => {
            assert!((tau - t).abs() < 1e-9, "τ = {tau}, π/ω = {t}")
        }
        other => panic!("{other:?}"),
    }
    let mut no_screen = fast();
    no_screen.design.detectability = None;
    let r = no_screen
        .design(&plant, &sampling, &MethodOptions::default())
        .unwrap();
    assert!(
        matches!(r.reason, Some(Reason::InfeasibleLmi { .. })),
        "{:?}",
        r.reason
    );
    let mut one = fast();
    one.design.max_iterations = 1;
    let (plant, sampling) = suspension();
    // One iteration certifies the §6 windows in balanced coordinates; a wider window needs more.
    let sampling = sampling.with_t2(0.6).unwrap();
    let r = one
        .design(&plant, &sampling, &MethodOptions::default())
        .unwrap();
    assert!(
        matches!(r.reason, Some(Reason::BudgetExhausted { .. })),
        "{:?}",
        r.reason
    );
    assert!(r.gains.is_empty() && r.margin.is_none());
}

#[test]
fn invalid_input_is_an_error() {
    let (plant, sampling) = oscillator(0.1, 0.3);
    let mut m = Sferlazza2021::default();
    m.design.mu = -1.0;
    let e = m
        .design(&plant, &sampling, &MethodOptions::default())
        .unwrap_err();
    assert!(matches!(e, MethodError::InvalidInput { .. }), "{e}");
    assert!(e.chain().contains("mu"), "{}", e.chain());
    let m = Sferlazza2021 {
        schedule_points: 1,
        ..Sferlazza2021::default()
    };
    let e = m
        .design(&plant, &sampling, &MethodOptions::default())
        .unwrap_err();
    assert!(e.chain().contains("schedule_points"), "{}", e.chain());
    // Three windows for two sensors.
    let three = Sampling::RoundRobin(vec![win(0.1, 0.2); 3]);
    let e = Sferlazza2021::default()
        .design(&plant, &three, &MethodOptions::default())
        .unwrap_err();
    assert!(matches!(e, MethodError::InvalidInput { .. }), "{e}");
}

/// The bisection of the former facade (on the balanced plant the contract designs in): probe the limit, then `T1`, then halve `[lo, hi]` until
/// `hi/lo − 1 ≤ 10⁻²`, moving every sensor's upper end to `max(T1σ, t2)`.
fn former_search(m: &Sferlazza2021, plant: &Plant, sampling: &Sampling, limit: f64) -> (f64, f64) {
    let ok = |t2: f64| {
        let s = sampling.with_t2(t2).unwrap();
        design(&balanced(plant, &s), &m.design).is_ok()
    };
    let t1 = sampling.t1();
    assert!(!ok(limit) && ok(t1));
    let (mut lo, mut hi) = (t1, limit);
    while hi / lo - 1.0 > 1e-2 {
        let mid = 0.5 * (lo + hi);
        if ok(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo, hi)
}

#[test]
fn largest_window_reaches_past_the_balanced_search() {
    let (plant, sampling) = suspension();
    let m = fast();
    let limit = 2.0;
    let mut probes = 0;
    let r = m
        .largest_window(
            &plant,
            &sampling,
            limit,
            &MethodOptions::default(),
            &mut |_| probes += 1,
        )
        .unwrap();
    assert_eq!(r.status, Status::Certified);
    // The failing end (T2 ≈ 1.59) is the §5.3 loop stalling with its worst τ already in the
    // synthesis set (`solver_inconclusive`) or running out of its 50 iterations, in both forms,
    // not a verdict of the method: the search says `undecided` (or, where the stalling loops
    // use up the time budget, `budget_exhausted`), and the largest certified T2 is a lower
    // bound.
    assert!(
        matches!(
            r.search_end,
            Some(SearchEnd::Undecided | SearchEnd::BudgetExhausted)
        ),
        "{:?}",
        r.search_end
    );
    assert!(matches!(
        r.first_failure_reason(),
        Some(Reason::SolverInconclusive { .. } | Reason::BudgetExhausted { .. })
    ));
    let best = r.largest_certified_t2.unwrap();
    if r.search_end == Some(SearchEnd::Undecided) {
        let fail = r.first_failing_t2.unwrap();
        assert!(fail / best - 1.0 <= 1e-2 + 1e-12);
    }
    assert_eq!(probes, r.probes.len());
    let (lo, hi) = former_search(&m, &plant, &sampling, limit);
    println!(
        "new [{best}, {:?}] in {} probes, former [{lo}, {hi}]",
        r.first_failing_t2,
        r.probes.len()
    );
    // The former search designed in the balanced coordinates only, whose loop stalls near
    // T2 = 1.40; the method also designs in the Gramian normal form, which certifies up to
    // about 1.58. The search is not worse, and its largest certified design is proved over
    // the continuum of τ in interval arithmetic.
    assert!(lo <= best, "new {best}, former [{lo}, {hi}]");
    let d = r.design.unwrap();
    assert!(d.status.is_certified());
    assert_eq!(d.windows.clone().unwrap()[1], win(0.04, best));
    let proof = prove_within(&m, &plant, &d, &ProofOptions::default()).unwrap();
    assert_eq!(proof.status, ProofStatus::Proved, "{}", proof.message);
}

#[test]
fn simulation_of_a_certified_design_converges() {
    let (plant, sampling) = oscillator(0.1, 0.3);
    let m = Sferlazza2021::default();
    let r = m
        .design(&plant, &sampling, &MethodOptions::default())
        .unwrap();
    assert!(r.status.is_certified());
    for sampling in [
        SamplingScenario::Uniform { seed: 3 },
        SamplingScenario::PeriodicT1,
        SamplingScenario::PeriodicT2,
    ] {
        let tr = m
            .simulate(
                &plant,
                &r,
                &Scenario {
                    sampling,
                    ..Scenario::default()
                },
            )
            .unwrap();
        let rep = &tr.report;
        assert_eq!(rep.initial_error, 2f64.sqrt());
        assert!(
            rep.final_error < 1e-2 * rep.initial_error,
            "{sampling:?}: {}",
            rep.result
        );
        // 40 rounds of the two sensors: 80 samples with the longest intervals (the last one may
        // fall at the horizon).
        assert!(rep.samples >= 79, "{}", rep.samples);
        assert_eq!(tr.signals.len(), 2);
        assert_eq!(tr.t.len(), tr.norm.len());
        assert!(rep.figure.is_none());
    }
    let not_certified = sporadic_sferlazza2021::DesignReport::without_design(
        &m,
        "x",
        None,
        Reason::InfeasibleLmi {
            message: String::new(),
        },
    );
    assert!(matches!(
        m.simulate(&plant, &not_certified, &Scenario::default()),
        Err(MethodError::SimulationUnavailable { .. })
    ));
}
