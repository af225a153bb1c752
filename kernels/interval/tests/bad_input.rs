//! Bad input gives typed errors, never a panic or a wrong answer.

use faer::{Mat, mat};
use sporadic_interval::{
    EnclosureOptions, Interval, IntervalError, IntervalMatrix, expm_enclosure,
    is_verified_negative_definite, is_verified_positive_definite,
};

fn opts() -> EnclosureOptions {
    EnclosureOptions::default()
}

#[test]
fn expm_enclosure_rejects_bad_matrices() {
    let rect = Mat::<f64>::zeros(2, 3);
    assert!(matches!(
        expm_enclosure(rect.as_ref(), 0.0, 1.0, &opts()),
        Err(IntervalError::NotSquare {
            rows: 2,
            cols: 3,
            ..
        })
    ));
    let empty = Mat::<f64>::zeros(0, 0);
    assert!(matches!(
        expm_enclosure(empty.as_ref(), 0.0, 1.0, &opts()),
        Err(IntervalError::Empty { .. })
    ));
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let a = mat![[1.0, 0.0], [0.0, bad]];
        assert!(matches!(
            expm_enclosure(a.as_ref(), 0.0, 1.0, &opts()),
            Err(IntervalError::NonFinite { row: 1, col: 1, .. })
        ));
    }
}

#[test]
fn expm_enclosure_rejects_bad_windows() {
    let a = mat![[0.0, 1.0], [-1.0, 0.0]];
    for (t0, t1) in [
        (0.5, 0.4),
        (-0.1, 0.4),
        (-1.0, -0.5),
        (f64::NAN, 1.0),
        (0.0, f64::NAN),
        (0.0, f64::INFINITY),
        (f64::NEG_INFINITY, 0.0),
    ] {
        assert!(
            matches!(
                expm_enclosure(a.as_ref(), t0, t1, &opts()),
                Err(IntervalError::InvalidWindow { .. })
            ),
            "[{t0}, {t1}]"
        );
    }
}

#[test]
fn expm_enclosure_rejects_overflow_and_bad_options() {
    let a = mat![[1e300, 0.0], [0.0, 1.0]];
    assert!(matches!(
        expm_enclosure(a.as_ref(), 0.0, 1e10, &opts()),
        Err(IntervalError::Overflow(_))
    ));
    let big = mat![[f64::MAX, f64::MAX], [0.0, 1.0]];
    assert!(matches!(
        expm_enclosure(big.as_ref(), 0.0, 1.0, &opts()),
        Err(IntervalError::Overflow(_))
    ));
    // Finite ‖A‖τ1 but e^{Aτ} far beyond double range: refused, not a wrong enclosure.
    let huge = mat![[1e3, 0.0], [0.0, 1.0]];
    assert!(matches!(
        expm_enclosure(huge.as_ref(), 0.0, 1.0, &opts()),
        Err(IntervalError::EnclosureFailed(_))
    ));
    let a = mat![[0.0, 1.0], [-1.0, 0.0]];
    for o in [
        EnclosureOptions {
            max_pieces: 0,
            ..opts()
        },
        EnclosureOptions {
            piece_rel_width: 0.0,
            ..opts()
        },
        EnclosureOptions {
            piece_rel_width: f64::NAN,
            ..opts()
        },
        EnclosureOptions {
            max_step_norm: -1.0,
            ..opts()
        },
    ] {
        assert!(matches!(
            expm_enclosure(a.as_ref(), 0.0, 1.0, &o),
            Err(IntervalError::InvalidOption(_))
        ));
    }
}

#[test]
fn constructors_reject_bad_input() {
    assert!(matches!(
        Interval::new(2.0, 1.0),
        Err(IntervalError::InvalidInterval { .. })
    ));
    assert!(Interval::new(f64::NAN, 1.0).is_err());
    assert!(Interval::new(f64::INFINITY, f64::INFINITY).is_err());
    assert!(Interval::point(f64::NAN).is_err());
    let m = mat![[1.0, f64::NAN]];
    assert!(matches!(
        IntervalMatrix::from_point(m.as_ref()),
        Err(IntervalError::NonFinite { row: 0, col: 1, .. })
    ));
    assert!(matches!(
        IntervalMatrix::from_mid_rad(Mat::zeros(2, 2), Mat::zeros(2, 3)),
        Err(IntervalError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        IntervalMatrix::from_mid_rad(Mat::zeros(1, 1), mat![[-1.0]]),
        Err(IntervalError::InvalidInterval { .. })
    ));
    assert!(IntervalMatrix::from_mid_rad(Mat::zeros(1, 1), mat![[f64::NAN]]).is_err());
    assert!(matches!(
        IntervalMatrix::from_bounds(mat![[2.0]].as_ref(), mat![[1.0]].as_ref()),
        Err(IntervalError::InvalidInterval { .. })
    ));
    let a = IntervalMatrix::zeros(2, 3);
    let b = IntervalMatrix::zeros(2, 3);
    assert!(matches!(
        a.checked_mul(&b),
        Err(IntervalError::DimensionMismatch { .. })
    ));
    assert!(a.checked_add(&IntervalMatrix::zeros(3, 2)).is_err());
    assert!(a.hull(&IntervalMatrix::zeros(3, 2)).is_err());
}

#[test]
fn definiteness_rejects_bad_input() {
    assert!(matches!(
        is_verified_positive_definite(&IntervalMatrix::zeros(2, 3)),
        Err(IntervalError::NotSquare { .. })
    ));
    assert!(matches!(
        is_verified_positive_definite(&IntervalMatrix::zeros(0, 0)),
        Err(IntervalError::Empty { .. })
    ));
    let x = IntervalMatrix::from_point(mat![[2.0, 1.0], [0.0, 2.0]].as_ref()).unwrap();
    assert!(matches!(
        is_verified_negative_definite(&x),
        Err(IntervalError::NotSymmetric { row: 1, col: 0, .. })
    ));
    let r =
        IntervalMatrix::from_mid_rad(mat![[2.0, 0.0], [0.0, 2.0]], mat![[0.0, 1.0], [0.0, 0.0]])
            .unwrap();
    assert!(matches!(
        is_verified_positive_definite(&r),
        Err(IntervalError::NotSymmetric { .. })
    ));
}
