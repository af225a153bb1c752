//! Bad input is reported with typed errors, never a panic.

use faer::{Mat, mat};
use sporadic_etienne2017::{
    BisectionOptions, Condition, DesignOptions, Error, GainSchedule, Plant, SamplingWindow,
    SimulationSetup, design, example, max_tau_bar, simulate_observer, solve_margin,
    solve_margin_without_dwell,
};
use sporadic_linalg::InputError;
use sporadic_sim::Periodic;

/// `A, B, C, G, H` of a valid plant (n = 2, no input, q = m = 1).
fn data() -> [Mat<f64>; 5] {
    [
        mat![[0.0, 1.0], [-1.0, 0.0]],
        Mat::zeros(2, 0),
        mat![[1.0, 0.0]],
        mat![[0.0], [1.0]],
        mat![[1.0, 0.0]],
    ]
}

#[test]
fn windows() {
    for (lo, hi) in [
        (0.3, 0.2),
        (f64::NAN, 0.2),
        (0.0, 0.2),
        (0.01, f64::INFINITY),
    ] {
        assert!(matches!(
            SamplingWindow::new(lo, hi),
            Err(InputError::InvalidWindow { .. })
        ));
    }
    assert!(matches!(
        solve_margin_without_dwell(
            &example::flexible_joint().unwrap(),
            Condition::Corollary2,
            -1.0,
            &DesignOptions::default()
        ),
        Err(Error::Input(InputError::InvalidWindow { .. }))
    ));
    let plant = example::flexible_joint().unwrap();
    let o = DesignOptions::default();
    // Theorem 3 needs τ_low < τ̄, Remark 6 needs τ_low = τ̄.
    assert!(matches!(
        solve_margin(
            &plant,
            Condition::Theorem3,
            &SamplingWindow::periodic(0.1).unwrap(),
            &o
        ),
        Err(Error::Input(InputError::InvalidWindow { .. }))
    ));
    assert!(matches!(
        design(
            &plant,
            Condition::Remark6,
            &SamplingWindow::new(0.01, 0.1).unwrap(),
            &o
        ),
        Err(Error::Input(InputError::InvalidWindow { .. }))
    ));
    let b = BisectionOptions::default();
    assert!(matches!(
        max_tau_bar(&plant, Condition::Corollary2, -0.1, &b),
        Err(Error::Input(InputError::InvalidWindow { .. }))
    ));
    assert!(matches!(
        max_tau_bar(&plant, Condition::Remark6, 0.01, &b),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));
    let bad_tol = BisectionOptions {
        tolerance: 0.0,
        ..BisectionOptions::default()
    };
    assert!(matches!(
        max_tau_bar(&plant, Condition::Corollary2, 0.01, &bad_tol),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));
    let bad_start = BisectionOptions {
        start: Some(0.005),
        ..BisectionOptions::default()
    };
    assert!(matches!(
        max_tau_bar(&plant, Condition::Corollary2, 0.01, &bad_start),
        Err(Error::Input(InputError::InvalidWindow { .. }))
    ));
}

#[test]
fn plant_data() {
    let [a, b, c, g, h] = data();
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
            Err(Error::Input(InputError::NonFinite { .. }))
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
            Err(Error::Input(InputError::NonFinite { .. }))
        ));
        assert!(matches!(
            Plant::lipschitz(ar, br, cr, gr, hr, bad),
            Err(Error::Input(InputError::NonFinite { .. }))
        ));
    }
    assert!(matches!(
        Plant::lipschitz(ar, br, cr, gr, hr, -1.0),
        Err(Error::Input(InputError::InvalidParameter { .. }))
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
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        Plant::lipschitz(ar, Mat::<f64>::zeros(3, 1).as_ref(), cr, gr, hr, 1.0),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        Plant::lipschitz(ar, br, cr, gr, three.as_ref(), 1.0),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
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
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        Plant::lipschitz(mat![[1.0, 2.0]].as_ref(), br, cr, gr, hr, 1.0),
        Err(Error::Input(InputError::NotSquare { .. }))
    ));
    assert!(matches!(
        Plant::lipschitz(ar, br, Mat::<f64>::zeros(0, 2).as_ref(), gr, hr, 1.0),
        Err(Error::Input(InputError::Empty { .. }))
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
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
}

#[test]
fn gains_and_simulation() {
    let w = SamplingWindow::new(0.01, 0.2).unwrap();
    assert!(matches!(
        GainSchedule::interpolated(mat![[1.0]].as_ref(), mat![[1.0, 2.0]].as_ref(), w),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        GainSchedule::constant(mat![[f64::NAN]].as_ref(), w),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        GainSchedule::interpolated(
            mat![[1.0]].as_ref(),
            mat![[2.0]].as_ref(),
            SamplingWindow::periodic(0.1).unwrap()
        ),
        Err(Error::Input(InputError::InvalidWindow { .. }))
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
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        sporadic_etienne2017::analyse(&plant, &wrong, &DesignOptions::default()),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
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
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    let nan = SimulationSetup::new(vec![0.0; 4], vec![f64::NAN; 4], 1.0);
    assert!(matches!(
        simulate_observer(&plant, &example::phi, &example::input, &k, &mut rule, &nan),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
}

#[test]
fn condition_matrices_and_checks() {
    use sporadic_etienne2017::conditions::{
        flow_block, gain_from, interpolate, jump_block, jump_decrease, lyapunov_matrix,
        reset_matrix,
    };
    use sporadic_etienne2017::verify::transition;
    use sporadic_etienne2017::{CheckOptions, discrete_check, worst_case_sampling};

    let i2 = Mat::<f64>::identity(2, 2);
    let i3 = Mat::<f64>::identity(3, 3);
    let c = mat![[1.0, 0.0]];
    let l = mat![[1.0], [0.0]];
    let mismatch = |r: Result<Mat<f64>, Error>| {
        matches!(r, Err(Error::Input(InputError::DimensionMismatch { .. })))
    };
    // P1, P2 of different orders; R of the wrong order; L, C, K of the wrong shapes.
    assert!(mismatch(lyapunov_matrix(
        i2.as_ref(),
        i3.as_ref(),
        0.2,
        0.1
    )));
    assert!(mismatch(flow_block(
        i2.as_ref(),
        i2.as_ref(),
        i3.as_ref(),
        0.2,
        0.1
    )));
    assert!(mismatch(jump_block(
        i2.as_ref(),
        i2.as_ref(),
        mat![[1.0]].as_ref(),
        c.as_ref()
    )));
    assert!(mismatch(jump_block(
        i2.as_ref(),
        i2.as_ref(),
        l.as_ref(),
        mat![[1.0, 0.0, 0.0]].as_ref()
    )));
    assert!(mismatch(jump_decrease(
        i2.as_ref(),
        i3.as_ref(),
        l.as_ref(),
        c.as_ref()
    )));
    assert!(mismatch(reset_matrix(
        l.as_ref(),
        mat![[1.0, 0.0], [0.0, 1.0]].as_ref()
    )));
    assert!(mismatch(gain_from(i2.as_ref(), i3.as_ref())));
    let w = SamplingWindow::new(0.01, 0.2).unwrap();
    assert!(mismatch(interpolate(l.as_ref(), c.as_ref(), &w, 0.1)));
    assert!(mismatch(transition(
        i3.as_ref(),
        l.as_ref(),
        c.as_ref(),
        0.1
    )));
    // Non-finite data, τ̄ ≤ 0, P1 not positive definite, empty matrices.
    let nan = mat![[f64::NAN, 0.0], [0.0, 1.0]];
    assert!(matches!(
        lyapunov_matrix(nan.as_ref(), i2.as_ref(), 0.2, 0.1),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        interpolate(l.as_ref(), l.as_ref(), &w, f64::NAN),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        lyapunov_matrix(i2.as_ref(), i2.as_ref(), 0.0, 0.1),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));
    assert!(matches!(
        gain_from((-&i2).as_ref(), l.as_ref()),
        Err(Error::Singular { .. })
    ));
    assert!(matches!(
        reset_matrix(Mat::<f64>::zeros(0, 1).as_ref(), c.as_ref()),
        Err(Error::Input(InputError::Empty { .. }))
    ));

    // Check options and the adversary.
    let plant = example::flexible_joint().unwrap();
    let k = example::paper_static_schedule(w).unwrap();
    let p1 = Mat::<f64>::identity(4, 4);
    for bad in [
        CheckOptions {
            safety: 0.5,
            ..CheckOptions::default()
        },
        CheckOptions {
            safety: f64::NAN,
            ..CheckOptions::default()
        },
        CheckOptions {
            discrete_grid: 1,
            ..CheckOptions::default()
        },
    ] {
        assert!(matches!(
            discrete_check(&plant, &k, Some(p1.as_ref()), &bad),
            Err(Error::Input(InputError::InvalidParameter { .. }))
        ));
    }
    assert!(matches!(
        discrete_check(&plant, &k, Some(i2.as_ref()), &CheckOptions::default()),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        worst_case_sampling(&plant, &k, p1.as_ref(), 2, 10),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        worst_case_sampling(&plant, &k, i2.as_ref(), 0, 10),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
}
