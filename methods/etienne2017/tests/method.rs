//! The [`ObserverMethod`] contract of `Etienne2017`: the same gains and margins as the crate's
//! own design, typed verdicts (not applicable, not certified), bad input as `Err`, the largest
//! window against the crate's bisection, and no simulation.

use faer::{Mat, MatRef, mat};
use sporadic_etienne2017::sporadic_model::{Lipschitz, Plant as ModelPlant};
use sporadic_etienne2017::{
    BisectionOptions, CheckOptions, Condition, Conditions, DesignOptions, DesignReport,
    Etienne2017, MethodError, MethodOptions, ObserverMethod, Reason, Sampling, SamplingWindow,
    Status, balanced_plant, design, example, max_tau_bar,
};
use sporadic_linalg::balance::{unbalance_form, unbalance_gain};

/// The flexible-joint robot of §5 as a plant of the common contract.
fn flexible_joint() -> ModelPlant {
    let a = mat![
        [0.0, 1.0, 0.0, 0.0],
        [-48.6, -1.25, 48.6, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [19.5, 0.0, -19.5, 0.0],
    ];
    let b = mat![[0.0], [21.6], [0.0], [0.0]];
    let c = mat![[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]];
    let lip = Lipschitz::new(
        mat![[0.0], [0.0], [0.0], [1.0]].as_ref(),
        mat![[0.0, 0.0, 1.0, 0.0]].as_ref(),
        mat![[-example::GAMMA]].as_ref(),
        mat![[example::GAMMA]].as_ref(),
    )
    .unwrap();
    ModelPlant::linear(a.as_ref(), Some(b.as_ref()), c.as_ref())
        .unwrap()
        .with_lipschitz(lip)
        .unwrap()
        .named("flexible joint")
}

fn sampling(t1: f64, t2: f64) -> Sampling {
    Sampling::Synchronous(SamplingWindow::new(t1, t2).unwrap())
}

fn run(method: &Etienne2017, t1: f64, t2: f64) -> DesignReport {
    method
        .design(
            &flexible_joint(),
            &sampling(t1, t2),
            &MethodOptions::default(),
        )
        .unwrap()
}

fn rows(m: MatRef<'_, f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

#[test]
fn design_matches_the_crate_design_bitwise() {
    // The method designs in balanced coordinates x_b = D⁻¹x and maps back K = D·K_b,
    // P = D⁻¹P_bD⁻¹ exactly (powers of 2): the crate's design on the balanced plant, mapped.
    let (plant, scales) = balanced_plant(&flexible_joint()).unwrap();
    let gain = |k: MatRef<'_, f64>| rows(unbalance_gain(k, &scales).as_ref());
    let o = DesignOptions::default();
    let method = Etienne2017::default();

    // [0.01, 0.2]: Corollary 2 (static gain) suffices.
    let r = run(&method, 0.01, 0.2);
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    let w = SamplingWindow::new(0.01, 0.2).unwrap();
    let d = design(&plant, Condition::Corollary2, &w, &o).unwrap();
    let k = r.gain("K").unwrap();
    assert!(k.schedule.is_none());
    assert_eq!(k.rows, gain(d.gain.k1()));
    assert_eq!(r.margin.as_ref().unwrap().value, d.lmi.margin);
    assert!(r.margin.as_ref().unwrap().definition.contains("‖P1‖₂ ≤ 1"));
    let p1 = r.certificate.iter().find(|m| m.name == "P1").unwrap();
    assert_eq!(
        p1.to_mat(),
        unbalance_form(d.lmi.certificate.p1.as_ref(), &scales)
    );
    assert!(r.notes.iter().any(|n| n.contains("balanced coordinates")));
    assert!(r.checks.len() >= 7 && r.checks.iter().all(|c| c.passed));
    assert_eq!(r.window, Some(w));

    // [0.01, 0.3]: Corollary 2 fails, Theorem 3 gives K(τ).
    let r = run(&method, 0.01, 0.3);
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    let w = SamplingWindow::new(0.01, 0.3).unwrap();
    let d = design(&plant, Condition::Theorem3, &w, &o).unwrap();
    let k = r.gain("K").unwrap();
    let schedule = k.schedule.as_ref().unwrap();
    assert_eq!(schedule.tau.len(), 11);
    assert_eq!((schedule.tau[0], schedule.tau[10]), (0.01, 0.3));
    assert_eq!(schedule.samples[0], gain(d.gain.k0()));
    assert_eq!(schedule.samples[10], gain(d.gain.k1()));
    assert_eq!(
        schedule.samples[5],
        gain(d.gain.at(schedule.tau[5]).as_ref())
    );
    assert_eq!(k.rows, gain(d.gain.k1()));
    assert!(schedule.law.contains("K0") && k.meaning.contains("interval that just ended"));
    assert_eq!(r.margin.as_ref().unwrap().value, d.lmi.margin);
    assert!(
        r.notes
            .iter()
            .any(|n| n.contains("Corollary 2 (static gain) is not certified"))
    );
    assert!(r.certificate.iter().any(|m| m.name == "L0"));

    // Periodic window: Remark 6.
    let r = run(&method, 0.3, 0.3);
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    let d = design(
        &plant,
        Condition::Remark6,
        &SamplingWindow::periodic(0.3).unwrap(),
        &o,
    )
    .unwrap();
    assert_eq!(r.gain("K").unwrap().rows, gain(d.gain.k1()));
    let margin = r.margin.unwrap();
    assert_eq!(margin.value, d.lmi.margin);
    assert!(margin.definition.contains("Remark 6"));
}

#[test]
fn not_applicable_cases_are_typed() {
    let method = Etienne2017::default();
    let a = mat![[0.0, 1.0], [-1.0, 0.0]];
    let c = mat![[1.0, 0.0]];
    let s = sampling(0.05, 0.2);
    let o = MethodOptions::default();
    // A linear plant: the [lipschitz] section is missing.
    let linear = ModelPlant::linear(a.as_ref(), None, c.as_ref()).unwrap();
    let r = method.design(&linear, &s, &o).unwrap();
    assert_eq!(r.status, Status::NotApplicable);
    assert!(
        matches!(&r.reason, Some(Reason::MissingData { message }) if message.contains("ferrante2016")),
        "{:?}",
        r.reason
    );
    // φ: R^1 → R^2 (G n×2, H 1×n).
    let lip = Lipschitz::new(
        Mat::<f64>::identity(2, 2).as_ref(),
        mat![[1.0, 0.0]].as_ref(),
        mat![[-1.0], [-1.0]].as_ref(),
        mat![[1.0], [1.0]].as_ref(),
    )
    .unwrap();
    let skew = linear.clone().with_lipschitz(lip.clone()).unwrap();
    let r = method.design(&skew, &s, &o).unwrap();
    assert_eq!(r.status, Status::NotApplicable);
    assert!(matches!(
        r.reason,
        Some(Reason::UnsupportedStructure { .. })
    ));
    // Round-robin sensors and round-robin sampling.
    let square = Lipschitz::new(
        mat![[0.0], [1.0]].as_ref(),
        mat![[1.0, 0.0]].as_ref(),
        mat![[-1.0]].as_ref(),
        mat![[1.0]].as_ref(),
    )
    .unwrap();
    let rr = ModelPlant::round_robin(a.as_ref(), None, &[c.as_ref(), mat![[0.0, 1.0]].as_ref()])
        .unwrap()
        .with_lipschitz(square.clone())
        .unwrap();
    let rr_sampling = Sampling::RoundRobin(vec![
        SamplingWindow::new(0.05, 0.1).unwrap(),
        SamplingWindow::new(0.05, 0.1).unwrap(),
    ]);
    let r = method.design(&rr, &rr_sampling, &o).unwrap();
    assert_eq!(r.status, Status::NotApplicable);
    assert!(matches!(
        r.reason,
        Some(Reason::UnsupportedStructure { .. })
    ));
    let lipschitz = linear.with_lipschitz(square).unwrap();
    assert!(matches!(
        method.applies(&lipschitz, &rr_sampling),
        Err(na) if matches!(na.reason, Reason::UnsupportedStructure { .. })
    ));
    assert!(method.applies(&lipschitz, &s).is_ok());
    // The window search reports it too.
    let m = method
        .largest_window(&skew, &s, 1.0, &o, &mut |_| {})
        .unwrap();
    assert_eq!(m.status, Status::NotApplicable);
}

#[test]
fn a_window_too_long_is_not_certified_with_both_failures() {
    let r = run(&Etienne2017::default(), 0.01, 0.5);
    assert_eq!(r.status, Status::NotCertified);
    match &r.reason {
        Some(Reason::InfeasibleLmi { message }) => {
            assert!(
                message.contains("Corollary 2 (static gain)")
                    && message.contains("Theorem 3 (time-varying gain)"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(r.gains.is_empty() && r.margin.is_none());
    // Corollary 2 alone does not reach [0.01, 0.3].
    let only_static = Etienne2017 {
        conditions: Conditions::Corollary2,
        ..Etienne2017::default()
    };
    let r = run(&only_static, 0.01, 0.3);
    assert_eq!(r.status, Status::NotCertified);
    assert!(matches!(r.reason, Some(Reason::InfeasibleLmi { .. })));
}

#[test]
fn bad_options_are_invalid_input() {
    let method = Etienne2017 {
        design: DesignOptions {
            check: CheckOptions {
                lmi_grid: 1,
                ..CheckOptions::default()
            },
            ..DesignOptions::default()
        },
        ..Etienne2017::default()
    };
    let e = method
        .design(
            &flexible_joint(),
            &sampling(0.01, 0.2),
            &MethodOptions::default(),
        )
        .unwrap_err();
    assert!(
        matches!(
            &e,
            MethodError::InvalidInput {
                method: "etienne2017",
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.chain().contains("lmi_grid"), "{}", e.chain());
    let e = method
        .largest_window(
            &flexible_joint(),
            &sampling(0.01, 0.2),
            1.0,
            &MethodOptions::default(),
            &mut |_| {},
        )
        .unwrap_err();
    assert!(matches!(e, MethodError::InvalidInput { .. }));
}

#[test]
fn largest_window_brackets_the_crate_bisection() {
    // The method searches on the balanced plant (see `design_matches_the_crate_design_bitwise`).
    let (plant, _) = balanced_plant(&flexible_joint()).unwrap();
    let crate_search = max_tau_bar(
        &plant,
        Condition::Theorem3,
        0.01,
        &BisectionOptions::default(),
    )
    .unwrap();
    let (feasible, infeasible) = (
        crate_search.feasible().unwrap(),
        crate_search.infeasible().unwrap(),
    );
    let mut seen = 0;
    let r = Etienne2017::default()
        .largest_window(
            &flexible_joint(),
            &sampling(0.01, 0.2),
            10.0,
            &MethodOptions::default(),
            &mut |_| seen += 1,
        )
        .unwrap();
    assert_eq!(r.status, Status::Certified);
    assert_eq!(r.probes.len(), seen);
    let (best, fail) = (r.largest_certified_t2.unwrap(), r.first_failing_t2.unwrap());
    // The certified end lies below the numerical boundary of the crate's bisection, the first
    // failure above its last feasible probe, within the tolerance 1e-3·T2.
    assert!(
        best <= infeasible && fail >= feasible,
        "{best} {fail} vs ({feasible}, {infeasible})"
    );
    assert!(
        fail - best <= 1e-3 * 0.2 + 1e-12 && best > 0.34,
        "{best} {fail}"
    );
    assert!(r.monotone);
    // First probe 2·T1, then doubling.
    assert_eq!((r.probes[0].t2, r.probes[1].t2), (0.02, 0.04));
    let d = r.design.as_ref().unwrap();
    assert_eq!(d.status, Status::Certified);
    assert_eq!(d.window.unwrap().t2(), best);
    assert!(d.gain("K").unwrap().schedule.is_some());
    // Its certificate is the crate's Theorem 3 design at that window, or, where that design's
    // margin is positive but below the verification threshold (the end of the search), the
    // design made in the coordinates of its certificate.
    let direct = design(
        &plant,
        Condition::Theorem3,
        &SamplingWindow::new(0.01, best).unwrap(),
        &DesignOptions::default(),
    );
    match direct {
        Ok(direct) => assert_eq!(d.margin.as_ref().unwrap().value, direct.lmi.margin),
        Err(sporadic_etienne2017::Error::Infeasible {
            margin: Some(t), ..
        }) => {
            assert!(t > 0.0, "{t}");
            assert!(
                d.notes
                    .iter()
                    .any(|n| n.contains("coordinates of the certificate")),
                "{:?}",
                d.notes
            );
        }
        Err(e) => panic!("{e:?}"),
    }
    // A limit below the boundary is certified.
    let r = Etienne2017::default()
        .largest_window(
            &flexible_joint(),
            &sampling(0.01, 0.2),
            0.25,
            &MethodOptions::default(),
            &mut |_| {},
        )
        .unwrap();
    assert_eq!(
        (r.largest_certified_t2, r.first_failing_t2),
        (Some(0.25), None)
    );
}

#[test]
fn simulation_is_unavailable_with_the_reason() {
    let method = Etienne2017::default();
    let r = run(&method, 0.01, 0.2);
    let e = method
        .simulate(&flexible_joint(), &r, &Default::default())
        .unwrap_err();
    match e {
        MethodError::SimulationUnavailable { method, why } => {
            assert_eq!(method, "etienne2017");
            assert!(why.contains("nonlinearity phi itself"), "{why}");
        }
        other => panic!("{other:?}"),
    }
    assert!(method.citation().contains("Automatica 85"));
    assert!(method.observer().contains("K(τ)"));
}
