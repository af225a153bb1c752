//! Bad input is reported with typed errors, never a panic.

use faer::{Mat, mat};
use sporadic_etienne2017::{
    BisectionOptions, Condition, DesignOptions, Error, GainSchedule, Plant, SimulationSetup,
    Window, design, example, max_tau_bar, simulate_observer, solve_margin,
};
use sporadic_sim::Periodic;

fn data() -> (Mat<f64>, Mat<f64>, Mat<f64>, Mat<f64>, Mat<f64>) {
    (
        mat![[0.0, 1.0], [-1.0, 0.0]],
        Mat::zeros(2, 0),
        mat![[1.0, 0.0]],
        mat![[0.0], [1.0]],
        mat![[1.0, 0.0]],
    )
}

#[test]
fn windows() {
    assert!(matches!(
        Window::new(0.3, 0.2),
        Err(Error::InvalidWindow { .. })
    ));
    assert!(matches!(
        Window::new(f64::NAN, 0.2),
        Err(Error::InvalidWindow { .. })
    ));
    assert!(matches!(
        Window::new(0.0, f64::INFINITY),
        Err(Error::InvalidWindow { .. })
    ));
    let plant = example::flexible_joint().unwrap();
    let o = DesignOptions::default();
    // Theorem 3 needs τ_low < τ̄, Remark 6 needs τ_low = τ̄.
    assert!(matches!(
        solve_margin(
            &plant,
            Condition::Theorem3,
            &Window::periodic(0.1).unwrap(),
            &o
        ),
        Err(Error::InvalidWindow { .. })
    ));
    assert!(matches!(
        design(
            &plant,
            Condition::Remark6,
            &Window::new(0.01, 0.1).unwrap(),
            &o
        ),
        Err(Error::InvalidWindow { .. })
    ));
    let b = BisectionOptions::default();
    assert!(matches!(
        max_tau_bar(&plant, Condition::Corollary2, -0.1, &b),
        Err(Error::InvalidWindow { .. })
    ));
    assert!(matches!(
        max_tau_bar(&plant, Condition::Remark6, 0.01, &b),
        Err(Error::InvalidParameter { .. })
    ));
    let bad_tol = BisectionOptions {
        tolerance: 0.0,
        ..BisectionOptions::default()
    };
    assert!(matches!(
        max_tau_bar(&plant, Condition::Corollary2, 0.01, &bad_tol),
        Err(Error::InvalidParameter { .. })
    ));
    let bad_start = BisectionOptions {
        start: Some(0.005),
        ..BisectionOptions::default()
    };
    assert!(matches!(
        max_tau_bar(&plant, Condition::Corollary2, 0.01, &bad_start),
        Err(Error::InvalidWindow { .. })
    ));
}

#[test]
fn plant_data() {
    let (a, b, c, g, h) = data();
    let (ar, br, cr, gr, hr) = (a.as_ref(), b.as_ref(), c.as_ref(), g.as_ref(), h.as_ref());
    assert!(Plant::lipschitz(ar, br, cr, gr, hr, 1.0).is_ok());
    // Non-finite Jacobian bounds / Lipschitz constant.
    for bad in [f64::NAN, f64::INFINITY] {
        assert!(matches!(
            Plant::new(
                ar,
                br,
                cr,
                gr,
                hr,
                mat![[bad]].as_ref(),
                mat![[1.0]].as_ref()
            ),
            Err(Error::NonFinite { .. })
        ));
        assert!(matches!(
            Plant::new(
                ar,
                br,
                cr,
                gr,
                hr,
                mat![[-1.0]].as_ref(),
                mat![[bad]].as_ref()
            ),
            Err(Error::NonFinite { .. })
        ));
        assert!(matches!(
            Plant::lipschitz(ar, br, cr, gr, hr, bad),
            Err(Error::NonFinite { .. })
        ));
    }
    assert!(matches!(
        Plant::lipschitz(ar, br, cr, gr, hr, -1.0),
        Err(Error::InvalidParameter { .. })
    ));
    assert!(matches!(
        Plant::new(
            ar,
            br,
            cr,
            gr,
            hr,
            mat![[1.0]].as_ref(),
            mat![[-1.0]].as_ref()
        ),
        Err(Error::InvalidJacobianBounds { row: 0, col: 0, .. })
    ));
    // Dimension mismatches.
    let three = mat![[1.0, 0.0, 0.0]];
    assert!(matches!(
        Plant::lipschitz(ar, br, three.as_ref(), gr, hr, 1.0),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        Plant::lipschitz(ar, Mat::<f64>::zeros(3, 1).as_ref(), cr, gr, hr, 1.0),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        Plant::lipschitz(ar, br, cr, gr, three.as_ref(), 1.0),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        Plant::new(
            ar,
            br,
            cr,
            gr,
            hr,
            Mat::<f64>::zeros(2, 2).as_ref(),
            mat![[1.0]].as_ref()
        ),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        Plant::lipschitz(mat![[1.0, 2.0]].as_ref(), br, cr, gr, hr, 1.0),
        Err(Error::NotSquare { .. })
    ));
    assert!(matches!(
        Plant::lipschitz(ar, br, Mat::<f64>::zeros(0, 2).as_ref(), gr, hr, 1.0),
        Err(Error::Empty { .. })
    ));
    assert!(matches!(
        Plant::lipschitz(
            mat![[f64::NAN, 0.0], [0.0, 0.0]].as_ref(),
            br,
            cr,
            gr,
            hr,
            1.0
        ),
        Err(Error::NonFinite { .. })
    ));
}

#[test]
fn gains_and_simulation() {
    let w = Window::new(0.01, 0.2).unwrap();
    assert!(matches!(
        GainSchedule::interpolated(mat![[1.0]].as_ref(), mat![[1.0, 2.0]].as_ref(), w),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        GainSchedule::constant(mat![[f64::NAN]].as_ref(), w),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        GainSchedule::interpolated(
            mat![[1.0]].as_ref(),
            mat![[2.0]].as_ref(),
            Window::periodic(0.1).unwrap()
        ),
        Err(Error::InvalidWindow { .. })
    ));
    let plant = example::flexible_joint().unwrap();
    // Gain of the wrong shape for the plant.
    let wrong = GainSchedule::constant(mat![[1.0]].as_ref(), w).unwrap();
    let setup = SimulationSetup::new(vec![0.0; 4], vec![1.0; 4], 1.0);
    let mut rule = Periodic::new(0.1).unwrap();
    assert!(matches!(
        simulate_observer(
            &plant,
            &example::phi,
            &example::input,
            &wrong,
            &mut rule,
            &setup
        ),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        sporadic_etienne2017::analyse(&plant, &wrong, &DesignOptions::default()),
        Err(Error::DimensionMismatch { .. })
    ));
    let k = example::paper_static_schedule(w).unwrap();
    let short = SimulationSetup::new(vec![0.0; 3], vec![1.0; 4], 1.0);
    assert!(matches!(
        simulate_observer(
            &plant,
            &example::phi,
            &example::input,
            &k,
            &mut rule,
            &short
        ),
        Err(Error::DimensionMismatch { .. })
    ));
    let nan = SimulationSetup::new(vec![0.0; 4], vec![f64::NAN; 4], 1.0);
    assert!(matches!(
        simulate_observer(&plant, &example::phi, &example::input, &k, &mut rule, &nan),
        Err(Error::NonFinite { .. })
    ));
}
