//! Largest certifiable window (the shared search on T2 for given T1, on T1 for given T2).

use sporadic_linalg::InputError;
use std::f64::consts::PI;

use faer::mat;
use sporadic_ferrante2016::examples::example2;
use sporadic_ferrante2016::{
    Bracketing, DesignOptions, Error, Plant, Reason, SearchEnd, WindowSearchOptions, largest_t2,
    smallest_t1,
};

fn oscillator() -> Plant {
    // Undamped oscillator measured in position: (e^{Av}, M) is not detectable at v = π.
    Plant::new(
        mat![[0.0, 1.0], [-1.0, 0.0]].as_ref(),
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap()
}

#[test]
fn largest_t2_of_an_oscillator_stays_below_the_pathological_period() {
    let w = largest_t2(
        &oscillator(),
        0.5,
        5.0,
        &DesignOptions::default(),
        &WindowSearchOptions::default(),
    )
    .unwrap();
    let best = w.best.unwrap();
    let fail = w.first_failure.unwrap();
    assert_eq!(w.end, SearchEnd::Converged);
    assert!(
        best < PI,
        "certified T2 = {best} beyond the detectability loss at π"
    );
    assert!(best < fail && fail / best - 1.0 <= 1e-2 + 1e-12);
    assert!(w.monotone);
    // Every certified probe lies below every failed one.
    let max_ok = w
        .probes
        .iter()
        .filter(|p| p.certified)
        .map(|p| p.t2)
        .fold(0.0, f64::max);
    let min_bad = w
        .probes
        .iter()
        .filter(|p| !p.certified)
        .map(|p| p.t2)
        .fold(f64::INFINITY, f64::min);
    assert!(max_ok < min_bad);
    assert!(w.probes.iter().all(|p| p.certified == p.reason.is_none()));
    assert!(w.probes.iter().all(|p| p.certified == p.margin.is_some()));
}

#[test]
fn smallest_t1_of_example2_is_bracketed() {
    // Independent [ours] values: T2 = 3 stays feasible at T1 = 0.1, the margin is lost near T1 ≈ 0.05
    // (solver- and normalisation-dependent, so only a loose range is asserted).
    let ex = example2().unwrap();
    let w = smallest_t1(
        &ex.plant,
        3.0,
        0.01,
        &DesignOptions::default(),
        &WindowSearchOptions::default(),
    )
    .unwrap();
    let best = w.best.unwrap();
    let fail = w.first_failure.unwrap();
    assert_eq!(w.end, SearchEnd::Converged);
    assert!(0.03 < best && best < 0.1, "smallest certified T1 = {best}");
    assert!(fail < best && best / fail - 1.0 <= 1e-2 + 1e-12);
    assert!(w.monotone);
    assert!(w.probes.iter().any(|p| p.certified && p.t1 <= 0.1));
}

#[test]
fn oscillator_windows_down_to_tiny_t1_are_certified() {
    // (e^{Av}, M) is detectable for every v ∈ (0, π): no positive lower limit on T1 exists for
    // (12), and the LMI follows it down to the search limit.
    let w = smallest_t1(
        &oscillator(),
        2.0,
        1e-2,
        &DesignOptions::default(),
        &WindowSearchOptions::default(),
    )
    .unwrap();
    assert!(w.end == SearchEnd::ReachedLimit && w.monotone);
    assert_eq!(w.best, Some(1e-2));
}

#[test]
fn periodic_window_failure_is_reported_not_an_error() {
    // T1 = T2 = π: not detectable even periodically.
    let w = largest_t2(
        &oscillator(),
        PI,
        4.0,
        &DesignOptions::default(),
        &WindowSearchOptions::default(),
    )
    .unwrap();
    assert_eq!(w.best, None);
    assert_eq!(w.end, SearchEnd::NothingCertified);
    assert_eq!(w.probes.len(), 1);
    match &w.probes[0].reason {
        Some(Reason::Undetectable { tau, message }) => {
            assert_eq!(*tau, PI);
            assert!(message.contains("not detectable"), "{message}");
        }
        r => panic!("{r:?}"),
    }
}

#[test]
fn bad_search_input_is_a_typed_error() {
    let (d, o) = (DesignOptions::default(), WindowSearchOptions::default());
    assert!(matches!(
        largest_t2(&oscillator(), 1.0, 0.5, &d, &o),
        Err(Error::Input(InputError::InvalidWindow { .. }))
    ));
    assert!(matches!(
        smallest_t1(&oscillator(), 1.0, 0.0, &d, &o),
        Err(Error::Input(InputError::InvalidWindow { .. }))
    ));
    let o = WindowSearchOptions {
        bracketing: Bracketing::Scan { points: 0 },
        ..Default::default()
    };
    assert!(matches!(
        largest_t2(&oscillator(), 0.5, 1.0, &d, &o),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));
    let d = DesignOptions {
        pieces: 0,
        ..Default::default()
    };
    assert!(matches!(
        largest_t2(&oscillator(), 0.5, 1.0, &d, &WindowSearchOptions::default()),
        Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "pieces"
    ));
}
