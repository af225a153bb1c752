//! Bad input gives typed errors that say what was wrong, never a panic.

use faer::{Mat, mat};
use sporadic_linalg::InputError;
use sporadic_rabehi2021::Error;
use sporadic_rabehi2021::SamplingWindow;
use sporadic_rabehi2021::analysis::{AnalysisOptions, analyse, analyse_gain};
use sporadic_rabehi2021::example::figure_scenario;
use sporadic_rabehi2021::example::{
    example_bounds, example_window, paper_gain, spring_mass_damper,
};
use sporadic_rabehi2021::ipr::{MetzlerDecomposition, pair_blocks};
use sporadic_rabehi2021::observer::IntervalObserver;
use sporadic_rabehi2021::polytope::{PolytopeOptions, taylor_polytope};
use sporadic_rabehi2021::simulation::{Noise, simulate_interval};
use sporadic_rabehi2021::synthesis::{SynthesisOptions, synthesise, synthesise_from};
use sporadic_rabehi2021::system::{Bounds, Plant};
use sporadic_rabehi2021::width::WidthDynamics;
use sporadic_rabehi2021::window::{TauMaxOptions, largest_tau_max, necessary_tau_max};

#[test]
fn invalid_windows() {
    assert!(matches!(
        SamplingWindow::new(0.3, 0.04),
        Err(InputError::InvalidWindow { reason, .. }) if reason.contains("exceed")
    ));
    assert!(matches!(
        SamplingWindow::new(0.0, 0.3),
        Err(InputError::InvalidWindow { .. })
    ));
    assert!(matches!(
        SamplingWindow::new(-1.0, 0.3),
        Err(InputError::InvalidWindow { .. })
    ));
    assert!(matches!(
        SamplingWindow::new(0.04, f64::INFINITY),
        Err(InputError::InvalidWindow { .. })
    ));
    assert!(matches!(
        SamplingWindow::new(f64::NAN, 0.3),
        Err(InputError::InvalidWindow { .. })
    ));
    let plant = spring_mass_damper(1.0).unwrap();
    let opts = TauMaxOptions {
        upper: 0.01,
        ..TauMaxOptions::default()
    };
    assert!(matches!(
        largest_tau_max(&plant, 0.04, &opts),
        Err(Error::Input(InputError::InvalidWindow { .. }))
    ));
    assert!(matches!(
        necessary_tau_max(&plant, 0.0, 1.0),
        Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "tau_min"
    ));
}

#[test]
fn invalid_bounds() {
    assert!(matches!(
        Bounds::new(vec![0.0, f64::NAN], vec![1.0, 1.0], vec![0.4]),
        Err(Error::Input(InputError::NonFinite { what })) if what.contains("d_lower")
    ));
    assert!(matches!(
        Bounds::new(vec![0.0, 0.0], vec![1.0, f64::INFINITY], vec![0.4]),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        Bounds::new(vec![0.0, 0.0], vec![1.0, 1.0], vec![f64::NAN]),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        Bounds::new(vec![0.0, 2.0], vec![1.0, 1.0], vec![0.4]),
        Err(Error::InvalidBounds { index: 1, .. })
    ));
    assert!(matches!(
        Bounds::new(vec![0.0, 0.0], vec![1.0, 1.0], vec![-0.1]),
        Err(Error::InvalidBounds { what: "v_bar", .. })
    ));
    assert!(matches!(
        Bounds::new(vec![0.0], vec![1.0, 1.0], vec![0.4]),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    // Bounds of the wrong size for the plant.
    let plant = spring_mass_damper(1.0).unwrap();
    let three = Bounds::new(vec![0.0; 3], vec![1.0; 3], vec![0.4]).unwrap();
    assert!(matches!(
        IntervalObserver::new(&plant, &three, paper_gain().as_ref()),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    let two_noise = Bounds::new(vec![0.0; 2], vec![1.0; 2], vec![0.4, 0.4]).unwrap();
    assert!(matches!(
        WidthDynamics::new(&plant, &two_noise, paper_gain().as_ref()),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
}

#[test]
fn dimension_mismatches_and_non_finite_matrices() {
    let a = mat![[0.0, 1.0], [-1.0, -1.0]];
    let b = mat![[0.0], [1.0]];
    let c = mat![[2.0, 0.0]];
    assert!(matches!(
        Plant::new(mat![[0.0, 1.0]].as_ref(), b.as_ref(), c.as_ref()),
        Err(Error::Input(InputError::NotSquare { what, .. })) if what == "A"
    ));
    assert!(matches!(
        Plant::new(a.as_ref(), mat![[1.0]].as_ref(), c.as_ref()),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        Plant::new(a.as_ref(), b.as_ref(), mat![[1.0, 0.0, 0.0]].as_ref()),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        Plant::new(a.as_ref(), b.as_ref(), Mat::<f64>::zeros(0, 2).as_ref()),
        Err(Error::Input(InputError::Empty { .. }))
    ));
    assert!(matches!(
        Plant::new(
            mat![[f64::NAN, 1.0], [0.0, 1.0]].as_ref(),
            b.as_ref(),
            c.as_ref()
        ),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        MetzlerDecomposition::new(Mat::<f64>::zeros(0, 0).as_ref()),
        Err(Error::Input(InputError::Empty { .. }))
    ));
    let plant = Plant::new(a.as_ref(), b.as_ref(), c.as_ref()).unwrap();
    let w = example_window();
    let opts = AnalysisOptions::default();
    // Gains of the wrong size or with NaN.
    for l in [mat![[1.0, 2.0]], mat![[f64::NAN], [0.0]]] {
        assert!(analyse_gain(&plant, &w, l.as_ref(), &opts).is_err());
        assert!(IntervalObserver::new(&plant, &example_bounds(), l.as_ref()).is_err());
    }
    // Gamma of a different order than A-bar.
    let a_bar = MetzlerDecomposition::new(plant.a()).unwrap().a_bar;
    assert!(matches!(
        analyse(
            a_bar.as_ref(),
            Mat::<f64>::identity(2, 2).as_ref(),
            &w,
            &opts
        ),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        pair_blocks(Mat::<f64>::identity(3, 3).as_ref()),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));
    assert!(matches!(
        pair_blocks(mat![[1.0, 2.0], [3.0, 4.0]].as_ref()),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));
    // A warm-start slack of the wrong order.
    assert!(matches!(
        synthesise_from(
            &plant,
            &w,
            Some(Mat::<f64>::identity(2, 2).as_ref()),
            &SynthesisOptions::default()
        ),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    // Correction with a measurement of the wrong size.
    let obs = IntervalObserver::new(&plant, &example_bounds(), paper_gain().as_ref()).unwrap();
    let (mut lo, mut hi) = (vec![0.0; 2], vec![1.0; 2]);
    assert!(matches!(
        obs.correct(&mut lo, &mut hi, &[1.0, 2.0]),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        obs.correct(&mut lo, &mut hi, &[f64::NAN]),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
}

#[test]
fn invalid_options() {
    let plant = spring_mass_damper(1.0).unwrap();
    let w = example_window();
    let bad = SynthesisOptions {
        p_min: 2e3,
        ..SynthesisOptions::default()
    };
    assert!(matches!(
        synthesise(&plant, &w, &bad),
        Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "p_min"
    ));
    let bad = SynthesisOptions {
        safety: f64::NAN,
        ..SynthesisOptions::default()
    };
    assert!(matches!(
        synthesise(&plant, &w, &bad),
        Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "safety"
    ));
    let a_bar = MetzlerDecomposition::new(plant.a()).unwrap().a_bar;
    let zero_pieces = PolytopeOptions {
        pieces: Some(0),
        ..PolytopeOptions::default()
    };
    assert!(matches!(
        taylor_polytope(a_bar.as_ref(), &w, &zero_pieces),
        Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "pieces"
    ));
    let widths = WidthDynamics::new(&plant, &example_bounds(), paper_gain().as_ref()).unwrap();
    assert!(widths.periodic_pre_jump(0.0).is_err());
    assert!(matches!(
        widths.guaranteed_bound(&w, &[-1.0, 0.0], 101),
        Err(Error::InvalidBounds { .. })
    ));
}

#[test]
fn inadmissible_simulations() {
    let plant = spring_mass_damper(1.0).unwrap();
    let obs = IntervalObserver::new(&plant, &example_bounds(), paper_gain().as_ref()).unwrap();
    // Initial enclosure (5) violated.
    let mut sc = figure_scenario(true);
    sc.lower0[1] = sc.x0[1] + 0.1;
    assert!(matches!(
        simulate_interval(&obs, &sc),
        Err(Error::InitialEnclosure { index: 1, .. })
    ));
    // Noise larger than v̄ (Assumption 2).
    let mut sc = figure_scenario(true);
    sc.noise = Noise::Cosine {
        amplitude: vec![0.5],
        omega: 2.0,
    };
    assert!(matches!(
        simulate_interval(&obs, &sc),
        Err(Error::InadmissibleSignal {
            what: "noise amplitude",
            ..
        })
    ));
    // Disturbance outside [d̲, d̄] (Assumption 3).
    let mut sc = figure_scenario(true);
    if let Some(d) = sc.disturbance.as_mut() {
        d.upper = vec![1.5, 1.0];
    }
    assert!(matches!(
        simulate_interval(&obs, &sc),
        Err(Error::InadmissibleSignal { index: 0, .. })
    ));
    // NaN initial state, non-positive horizon.
    let mut sc = figure_scenario(true);
    sc.x0[0] = f64::NAN;
    assert!(matches!(
        simulate_interval(&obs, &sc),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    let mut sc = figure_scenario(true);
    sc.horizon = -1.0;
    assert!(matches!(
        simulate_interval(&obs, &sc),
        Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "horizon"
    ));
}
