//! The rigorous prover (issue 24) and the check of given gains: the example's design (and the
//! paper's printed gain, with the `P` that `verify` finds for it) is proved on [0.04, 0.3]
//! within the time target; a gain or window for which (19) fails is never proved;
//! `verify` certifies a design's own gain and certificate, refuses a gain that cannot work and
//! rejects bad input with an `Err`.
//!
//! Run with `--nocapture` to see the pieces, margins and times.

use faer::Mat;
use sporadic_model::{
    Bounds as ModelBounds, DesignReport, Gain, MethodError, MethodOptions, NamedMatrix,
    ObserverMethod, Plant as ModelPlant, ProofOptions, ProofStatus, Sampling, SamplingWindow,
    Status, prove_within,
};
use sporadic_rabehi2021::Rabehi2021;
use sporadic_rabehi2021::example::{example_window, paper_gain};

/// The §V example as a contract plant.
fn example_plant() -> ModelPlant {
    sporadic_rabehi2021::example::model_plant().unwrap()
}

fn example_design() -> DesignReport {
    let r = Rabehi2021::default()
        .design(
            &example_plant(),
            &Sampling::Synchronous(example_window()),
            &MethodOptions::default(),
        )
        .unwrap();
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    r
}

fn prove_and_print(what: &str, r: &DesignReport, design_seconds: f64) -> ProofStatus {
    let p = prove_within(
        &Rabehi2021::default(),
        &example_plant(),
        r,
        &ProofOptions::default(),
    )
    .unwrap();
    println!(
        "{what}: {} — {} pieces, margin ≥ {:?}, enclosure width {:?}, {:.4} s (design {:.4} s); {}",
        p.status,
        p.subintervals,
        p.margin_lower_bound,
        p.enclosure_width,
        p.seconds,
        design_seconds,
        p.message
    );
    if p.status == ProofStatus::Proved {
        assert!(p.margin_lower_bound.unwrap() > 0.0);
        assert!(
            p.seconds <= (10.0 * design_seconds).max(2.0),
            "{what}: the proof took {} s, the design {} s",
            p.seconds,
            design_seconds
        );
    }
    p.status
}

fn gain_l(rows: Mat<f64>) -> Gain {
    Gain::constant("L", rows.as_ref(), "")
}

#[test]
fn the_examples_design_and_the_papers_gain_are_proved() {
    let r = example_design();
    let status = prove_and_print("design on [0.04, 0.3]", &r, r.seconds);
    assert_eq!(status, ProofStatus::Proved);
    // The printed gain with the P_19 that verify finds for it.
    let v = Rabehi2021::default()
        .verify(
            &example_plant(),
            &Sampling::Synchronous(example_window()),
            &[gain_l(paper_gain())],
            &[],
            &MethodOptions::default(),
        )
        .unwrap();
    assert_eq!(v.status, Status::Certified, "{:?}", v.reason);
    let status = prove_and_print("paper's L, verify's P_19", &v, v.seconds);
    assert_eq!(status, ProofStatus::Proved);
}

#[test]
fn a_failing_condition_is_never_proved() {
    let r = example_design();
    // No correction: Γ = I and Ā has the eigenvalue 0.618, so no P satisfies (19) anywhere.
    let mut zero = r.clone();
    zero.gains[0] = gain_l(Mat::zeros(2, 1));
    assert_eq!(
        prove_and_print("L = 0", &zero, r.seconds),
        ProofStatus::NotProved
    );
    // Beyond μ* = 2.037 the width of x2 cannot contract for any gain (§8, A6): the design's
    // L and P_19 on [0.04, 2.2] fail at the long intervals only.
    let mut long = r.clone();
    long.window = Some(SamplingWindow::new(0.04, 2.2).unwrap());
    assert_ne!(
        prove_and_print("window [0.04, 2.2]", &long, r.seconds),
        ProofStatus::Proved
    );
    // −P_19 is not positive definite (Theorem 1 needs P ≻ 0 besides (19)).
    let mut negated = r.clone();
    for m in negated.certificate.iter_mut().filter(|m| m.name == "P_19") {
        for row in &mut m.rows {
            for x in row {
                *x = -*x;
            }
        }
    }
    assert_eq!(
        prove_and_print("−P_19", &negated, r.seconds),
        ProofStatus::NotProved
    );
}

#[test]
fn verify_certifies_own_gains_and_refuses_a_gain_that_cannot_work() {
    let m = Rabehi2021::default();
    let plant = example_plant();
    let s = Sampling::Synchronous(example_window());
    let o = MethodOptions::default();
    let r = example_design();
    let v = m.verify(&plant, &s, &r.gains, &r.certificate, &o).unwrap();
    assert_eq!(v.status, Status::Certified, "{:?}", v.reason);
    assert_eq!(v.gains[0].rows, r.gains[0].rows);
    assert!(v.notes[0].contains("no SDP solved"), "{:?}", v.notes);
    let zero = [gain_l(Mat::zeros(2, 1))];
    let v = m.verify(&plant, &s, &zero, &r.certificate, &o).unwrap();
    assert_ne!(v.status, Status::Certified, "{v:?}");
    println!("L = 0: {:?}", v.reason);
}

#[test]
fn verify_rejects_bad_input() {
    let m = Rabehi2021::default();
    let plant = example_plant();
    let s = Sampling::Synchronous(example_window());
    let o = MethodOptions::default();
    let r = example_design();
    let invalid = |gains: &[Gain], cert: &[NamedMatrix]| {
        let e = m.verify(&plant, &s, gains, cert, &o).unwrap_err();
        assert!(matches!(e, MethodError::InvalidInput { .. }), "{e}");
    };
    let mut renamed = r.gains.clone();
    renamed[0].name = "K".into();
    invalid(&renamed, &r.certificate);
    invalid(&[], &r.certificate);
    invalid(&[gain_l(Mat::zeros(3, 1))], &r.certificate);
    let mut ragged = r.gains.clone();
    ragged[0].rows[0].push(1.0);
    invalid(&ragged, &r.certificate);
    let mut nan = r.gains.clone();
    nan[0].rows[0][0] = f64::NAN;
    invalid(&nan, &r.certificate);
    let scheduled = Gain::scheduled("L", "", "", vec![0.04, 0.3], |_| paper_gain());
    invalid(&[scheduled], &r.certificate);
    let mut cert = r.certificate.clone();
    cert[0].name = "Q".into();
    invalid(&r.gains, &cert);
    let small = [NamedMatrix::new(
        "P_19",
        Mat::<f64>::identity(2, 2).as_ref(),
        "",
    )];
    invalid(&r.gains, &small);
    // The prover refuses a report without P_19.
    let mut bare = r.clone();
    bare.certificate.retain(|m| m.name != "P_19");
    let e = prove_within(&m, &plant, &bare, &ProofOptions::default()).unwrap_err();
    assert!(matches!(e, MethodError::InvalidInput { .. }), "{e}");
}

/// The example in the coordinates `x_s = diag(1, 1024)·x` (badly scaled units): the method
/// designs in balanced coordinates and reports `P_19` there; the proof maps it back exactly.
#[test]
fn a_badly_scaled_plant_is_proved_in_its_own_coordinates() {
    let s = 1024.0;
    let plant = ModelPlant::linear(
        faer::mat![[0.0, 1.0 / s], [-s, -1.0]].as_ref(),
        Some(faer::mat![[0.0], [s]].as_ref()),
        faer::mat![[2.0, 0.0]].as_ref(),
    )
    .unwrap()
    .named("spring-mass-damper, x2 in 1/1024 units")
    .with_bounds(ModelBounds::new(vec![1.0, s], vec![0.4]).unwrap())
    .unwrap();
    let m = Rabehi2021::default();
    let sampling = Sampling::Synchronous(example_window());
    let o = MethodOptions::default();
    let r = m.design(&plant, &sampling, &o).unwrap();
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    assert!(r.notes.iter().any(|n| n.contains("balanced coordinates")));
    let p = prove_within(&m, &plant, &r, &ProofOptions::default()).unwrap();
    println!(
        "badly scaled: {} — {} pieces, margin ≥ {:?}, {:.4} s (design {:.4} s)",
        p.status, p.subintervals, p.margin_lower_bound, p.seconds, r.seconds
    );
    assert_eq!(p.status, ProofStatus::Proved, "{}", p.message);
    let v = m
        .verify(&plant, &sampling, &r.gains, &r.certificate, &o)
        .unwrap();
    assert_eq!(v.status, Status::Certified, "{:?}", v.reason);
    assert!(v.notes[0].contains("no SDP solved"), "{:?}", v.notes);
}

/// A long window near the method's limit (Table I, `c_s = 1`): the margin is thinner and the
/// variation of `e^{Āμ}` larger, so the μ-window is bisected further; still proved.
#[test]
fn a_long_window_is_proved() {
    let m = Rabehi2021::default();
    let sampling = Sampling::Synchronous(SamplingWindow::new(0.04, 0.9).unwrap());
    let r = m
        .design(&example_plant(), &sampling, &MethodOptions::default())
        .unwrap();
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    let status = prove_and_print("design on [0.04, 0.9]", &r, r.seconds);
    assert_eq!(status, ProofStatus::Proved);
}
