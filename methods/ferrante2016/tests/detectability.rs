//! Remark 3 precheck: detectability (not observability) of (e^{Av}, M) on [T1, T2].

use sporadic_linalg::{InputError, PbhOptions};
use std::f64::consts::PI;

use faer::mat;
use sporadic_ferrante2016::examples::example2;
use sporadic_ferrante2016::{
    DetectabilityOptions, Error, Plant, SamplingWindow, check_detectability,
};

#[test]
fn example2_is_detectable_although_observability_is_lost() {
    let ex = example2().unwrap();
    let r = check_detectability(&ex.plant, &ex.window, &DetectabilityOptions::default()).unwrap();
    // Only the bias mode λ = 0 is non-decaying: no aliasing instants, comfortable margin.
    assert!(r.aliasing_instants.is_empty());
    assert!(r.min_margin > 1e-3, "margin {}", r.min_margin);
    // Observability of (e^{Av}, M) is lost at v = π/1.6331702409: the observability
    // matrix there is rank deficient, yet the check above passed.
    let v = PI / 1.6331702409;
    let e = sporadic_linalg::expm_scaled(ex.plant.a(), v).unwrap();
    let mut obs = faer::Mat::<f64>::zeros(5, 5);
    let mut row = ex.plant.c().to_owned();
    for k in 0..5 {
        for j in 0..5 {
            obs[(k, j)] = row[(0, j)];
        }
        row = &row * &e;
    }
    let sv = obs.singular_values().unwrap();
    let smin = sv.iter().copied().fold(f64::INFINITY, f64::min);
    let smax = sv.iter().copied().fold(0.0, f64::max);
    assert!(
        smin / smax < 1e-8,
        "observability should be lost: {}",
        smin / smax
    );
}

#[test]
fn unobservable_unstable_mode_is_rejected() {
    let plant = Plant::new(
        mat![[1.0, 0.0], [0.0, -1.0]].as_ref(),
        mat![[0.0, 1.0]].as_ref(),
    )
    .unwrap();
    let w = SamplingWindow::new(0.5, 1.0).unwrap();
    match check_detectability(&plant, &w, &DetectabilityOptions::default()) {
        Err(Error::NotDetectable { modulus, .. }) => assert!(modulus > 1.0),
        other => panic!("expected NotDetectable, got {other:?}"),
    }
    // The same plant with an unobservable *stable* mode is fine.
    let plant = Plant::new(
        mat![[1.0, 0.0], [0.0, -1.0]].as_ref(),
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap();
    assert!(check_detectability(&plant, &w, &DetectabilityOptions::default()).is_ok());
}

#[test]
fn defective_unobservable_mode_is_rejected() {
    // Double integrator measuring the velocity only: the position is unobservable and not decaying.
    let plant = Plant::new(
        mat![[0.0, 1.0], [0.0, 0.0]].as_ref(),
        mat![[0.0, 1.0]].as_ref(),
    )
    .unwrap();
    let w = SamplingWindow::new(0.1, 2.0).unwrap();
    assert!(matches!(
        check_detectability(&plant, &w, &DetectabilityOptions::default()),
        Err(Error::NotDetectable { .. })
    ));
    // Measuring the position is fine for every v.
    let plant = Plant::new(
        mat![[0.0, 1.0], [0.0, 0.0]].as_ref(),
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap();
    assert!(check_detectability(&plant, &w, &DetectabilityOptions::default()).is_ok());
}

#[test]
fn pathological_sampling_of_an_oscillator_is_found_off_grid() {
    // Undamped oscillator, position measured: (e^{Av}, M) loses detectability exactly at v = kπ.
    let plant = Plant::new(
        mat![[0.0, 1.0], [-1.0, 0.0]].as_ref(),
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap();
    // A coarse grid (3 points: 3.0, 3.25, 3.5) does not contain π; the aliasing
    // instant is added analytically.
    let opts = DetectabilityOptions {
        grid_points: 3,
        ..Default::default()
    };
    match check_detectability(&plant, &SamplingWindow::new(3.0, 3.5).unwrap(), &opts) {
        Err(Error::NotDetectable { v, .. }) => assert!((v - PI).abs() < 1e-12, "v = {v}"),
        other => panic!("expected NotDetectable at π, got {other:?}"),
    }
    let ok = check_detectability(&plant, &SamplingWindow::new(1.0, 3.0).unwrap(), &opts).unwrap();
    assert!(ok.aliasing_instants.is_empty());
}

#[test]
fn bad_options_are_typed_errors() {
    let ex = example2().unwrap();
    let opts = DetectabilityOptions {
        pbh: PbhOptions {
            rank_tol: f64::NAN,
            ..PbhOptions::default()
        },
        ..Default::default()
    };
    assert!(matches!(
        check_detectability(&ex.plant, &ex.window, &opts),
        Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "rank_tol"
    ));
}
