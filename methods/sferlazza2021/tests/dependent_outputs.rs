//! A sensor with linearly dependent outputs (two sensors reading one quantity, a row that
//! combines others) has a `C_σ` without full row rank, which Assumption 1 excludes: the method
//! reads its independent outputs `W_σy_σ` ([`sporadic_sferlazza2021::output_map`]) and reports
//! gains on all of its outputs.

use faer::{Mat, mat};
use sporadic_model::{ProofOptions, ProofStatus, Tolerance};
use sporadic_sferlazza2021::{
    DesignReport, MethodOptions, ObserverMethod, Plant, Reason, Sampling, SamplingWindow,
    Sferlazza2021, Status, output_map,
};

/// A lightly damped oscillator driven by a first-order lag (eigenvalues `−0.2 ± 1.99i`, `−0.5`).
fn a() -> Mat<f64> {
    mat![[0.0, 1.0, 0.0], [-4.0, -0.4, 1.0], [0.0, 0.0, -0.5]]
}

/// Position and lag state, read once each.
fn c_independent() -> Mat<f64> {
    mat![[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
}

/// The same two quantities read by three sensors: the position twice (the second in other units,
/// ×2.5) and the lag state once; rank 2.
fn c_dependent() -> Mat<f64> {
    mat![[1.0, 0.0, 0.0], [2.5, 0.0, 0.0], [0.0, 0.0, 1.0]]
}

fn window() -> SamplingWindow {
    SamplingWindow::new(0.05, 0.5).unwrap()
}

fn design(c: &Mat<f64>, w: SamplingWindow) -> DesignReport {
    let plant = Plant::linear(a().as_ref(), None, c.as_ref()).unwrap();
    Sferlazza2021::default()
        .design(&plant, &Sampling::Synchronous(w), &MethodOptions::default())
        .unwrap()
}

#[test]
fn the_output_map_spans_the_range_of_c_with_orthonormal_rows() {
    let c = c_dependent();
    let w = output_map(c.as_ref()).unwrap().expect("rank 2 of 3 rows");
    assert_eq!(w.shape(), (2, 3));
    let gram = &w * w.transpose();
    assert!((gram - Mat::<f64>::identity(2, 2)).norm_max() < 1e-14);
    // WᵀW is the projector onto the range of C: it leaves C unchanged.
    let back = w.transpose() * (&w * &c);
    assert!((back - &c).norm_max() < 1e-14);
    assert!(output_map(c_independent().as_ref()).unwrap().is_none());
    assert!(
        output_map(Mat::<f64>::zeros(2, 3).as_ref())
            .unwrap()
            .is_none()
    );
}

#[test]
fn dependent_outputs_are_certified_with_gains_on_every_output() {
    let r = design(&c_dependent(), window());
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    assert!(
        r.notes.iter().any(|n| n.contains("linearly dependent")),
        "{:?}",
        r.notes
    );
    let independent = design(&c_independent(), window());
    assert_eq!(independent.status, Status::Certified);
    // Every listed K(τ) acts on the three outputs, and C·K is the projector onto the range of
    // C (the gain of the independent outputs satisfies C̃K̃ = I).
    let gain = &r.gains[0];
    let schedule = gain.schedule.as_ref().unwrap();
    let c = c_dependent();
    let w = output_map(c.as_ref()).unwrap().unwrap();
    let projector = w.transpose() * &w;
    for rows in &schedule.samples {
        let k = Mat::from_fn(3, 3, |i, j| rows[i][j]);
        let ck = &c * &k;
        assert!(
            (&ck - &projector).norm_max() < 1e-8 * k.norm_max().max(1.0),
            "C·K = {ck:?}"
        );
    }
    // The report passes the method's own independent check, and a gain that differs on the
    // range of C is refused.
    let plant = Plant::linear(a().as_ref(), None, c.as_ref()).unwrap();
    let sampling = Sampling::Synchronous(window());
    let method = Sferlazza2021::default();
    let options = MethodOptions::default();
    let checked = method
        .verify(&plant, &sampling, &r.gains, &r.certificate, &options)
        .unwrap();
    assert_eq!(checked.status, Status::Certified, "{:?}", checked.reason);
    let proof = method.prove(&plant, &r, &ProofOptions::default()).unwrap();
    assert_eq!(proof.status, ProofStatus::Proved, "{proof:?}");
    let mut tampered = r.gains.clone();
    let s = tampered[0].schedule.as_mut().unwrap();
    for rows in &mut s.samples {
        rows[1][0] *= 1.5;
    }
    tampered[0].rows = s.samples.last().unwrap().clone();
    let refused = method
        .verify(&plant, &sampling, &tampered, &r.certificate, &options)
        .unwrap();
    assert_eq!(refused.status, Status::NotCertified);
}

/// Reading the position twice is an invertible mixing of the independent outputs: the largest
/// certified `T2` is the same (within 1 %).
#[test]
fn dependent_outputs_give_the_largest_window_of_the_independent_ones() {
    let largest = |c: &Mat<f64>| {
        let plant = Plant::linear(a().as_ref(), None, c.as_ref()).unwrap();
        let mut options = MethodOptions::default();
        options.search.tolerance = Tolerance::Relative(1e-3);
        Sferlazza2021::default()
            .largest_window(
                &plant,
                &Sampling::Synchronous(window()),
                4.0,
                &options,
                &mut |_| {},
            )
            .unwrap()
            .largest_certified_t2
            .expect("the window [0.05, 0.5] certifies")
    };
    let (dependent, independent) = (largest(&c_dependent()), largest(&c_independent()));
    assert!(
        (dependent / independent - 1.0).abs() <= 1e-2,
        "{dependent} vs {independent}"
    );
}

#[test]
fn a_sensor_that_measures_nothing_is_not_applicable() {
    let r = design(&Mat::zeros(1, 3), window());
    assert_eq!(r.status, Status::NotApplicable);
    match &r.reason {
        Some(Reason::UnsupportedStructure { message }) => {
            assert!(message.contains("measures nothing"), "{message}")
        }
        other => panic!("{other:?}"),
    }
}
