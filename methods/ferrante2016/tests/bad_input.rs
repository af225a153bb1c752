//! Bad input never panics: every public entry point returns a typed error naming the problem.

use faer::{Mat, mat};
use sporadic_ferrante2016::examples::{example1, example2};
use sporadic_ferrante2016::{
    BoundOptions, DesignOptions, DetectabilityOptions, Error, Plant, SamplingWindow, VerifyOptions,
    analyse, bound_constants, check_detectability, design, verify,
};
use sporadic_linalg::InputError;

#[test]
fn windows() {
    for (t1, t2) in [
        (2.0, 1.0),
        (0.0, 1.0),
        (-1.0, 1.0),
        (f64::NAN, 1.0),
        (1.0, f64::INFINITY),
    ] {
        assert!(
            matches!(
                SamplingWindow::new(t1, t2),
                Err(InputError::InvalidWindow { .. })
            ),
            "[{t1}, {t2}] accepted"
        );
    }
    assert!(SamplingWindow::new(1.0, 1.0).unwrap().is_periodic());
}

#[test]
fn plants() {
    let m = mat![[1.0, 0.0]];
    assert!(matches!(
        Plant::new(Mat::<f64>::zeros(2, 3).as_ref(), m.as_ref()),
        Err(Error::Input(InputError::NotSquare { what, .. })) if what == "A"
    ));
    assert!(matches!(
        Plant::new(
            Mat::<f64>::zeros(0, 0).as_ref(),
            Mat::<f64>::zeros(1, 0).as_ref()
        ),
        Err(Error::Input(InputError::Empty { .. }))
    ));
    assert!(matches!(
        Plant::new(Mat::<f64>::identity(3, 3).as_ref(), m.as_ref()),
        Err(Error::Input(InputError::DimensionMismatch {
            expected: 3,
            found: 2,
            ..
        }))
    ));
    assert!(matches!(
        Plant::new(
            Mat::<f64>::identity(2, 2).as_ref(),
            Mat::<f64>::zeros(0, 2).as_ref()
        ),
        Err(Error::Input(InputError::Empty { .. }))
    ));
    assert!(matches!(
        Plant::new(mat![[1.0, f64::NAN], [0.0, 1.0]].as_ref(), m.as_ref()),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        Plant::new(
            Mat::<f64>::identity(2, 2).as_ref(),
            mat![[f64::INFINITY, 0.0]].as_ref()
        ),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
}

#[test]
fn gains_and_lyapunov_matrices() {
    let ex = example2().unwrap();
    let opts = DesignOptions::default();
    let p = Mat::<f64>::identity(5, 5);
    // L of the wrong shape or with NaN.
    assert!(matches!(
        analyse(
            &ex.plant,
            &ex.window,
            Mat::<f64>::zeros(4, 1).as_ref(),
            &opts
        ),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    let mut l = ex.l_paper.clone();
    l[(2, 0)] = f64::NAN;
    assert!(matches!(
        analyse(&ex.plant, &ex.window, l.as_ref(), &opts),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        verify(
            &ex.plant,
            &ex.window,
            ex.l_paper.as_ref(),
            Mat::<f64>::identity(4, 4).as_ref(),
            &VerifyOptions::default()
        ),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    let mut asym = p.clone();
    asym[(0, 1)] = 1.0;
    assert!(matches!(
        verify(
            &ex.plant,
            &ex.window,
            ex.l_paper.as_ref(),
            asym.as_ref(),
            &VerifyOptions::default()
        ),
        Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "P"
    ));
    // P not positive definite / (12) violated ⇒ Theorem 1 gives no constants.
    let ex1 = example1().unwrap();
    assert!(matches!(
        bound_constants(
            &ex1.plant,
            &ex1.window,
            ex1.l.as_ref(),
            mat![[-1.0]].as_ref(),
            &BoundOptions::default()
        ),
        Err(Error::ConditionViolated { .. })
    ));
    assert!(matches!(
        bound_constants(
            &ex1.plant,
            &ex1.window,
            mat![[0.5]].as_ref(),
            ex1.p.as_ref(),
            &BoundOptions::default()
        ),
        Err(Error::ConditionViolated { .. })
    ));
    assert!(matches!(
        bound_constants(
            &ex1.plant,
            &ex1.window,
            ex1.l.as_ref(),
            ex1.p.as_ref(),
            &BoundOptions { grid_points: 1 }
        ),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));
}

#[test]
fn undetectable_pair_and_bad_options() {
    // Unstable mode invisible in the output.
    let plant = Plant::new(
        mat![[0.5, 0.0], [0.0, -1.0]].as_ref(),
        mat![[0.0, 1.0]].as_ref(),
    )
    .unwrap();
    let w = SamplingWindow::new(0.1, 1.0).unwrap();
    assert!(matches!(
        design(&plant, &w, &DesignOptions::default()),
        Err(Error::NotDetectable { .. })
    ));
    let opts = DesignOptions {
        pieces: 0,
        ..Default::default()
    };
    let ex = example2().unwrap();
    assert!(matches!(
        design(&ex.plant, &ex.window, &opts),
        Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "pieces"
    ));
    let mut opts = DetectabilityOptions::default();
    opts.pbh.unit_circle_tol = 1.5;
    assert!(matches!(
        check_detectability(&ex.plant, &ex.window, &opts),
        Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "unit_circle_tol"
    ));
}
