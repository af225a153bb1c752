//! Double-double matrix kernels: identities that hold to about 10⁻³⁰ relative, and agreement
//! with the double-precision exponential of `sporadic-linalg`.

use faer::Mat;
use proptest::prelude::*;
use sporadic_interval::double_double::{
    DdMatrix, DoubleDouble, UNIT_ROUNDOFF_DD, expm, upper_triangular_inverse,
};

/// `‖X − I‖_max` of a double-double matrix, each entry's difference formed in double-double.
fn distance_to_identity(x: &DdMatrix) -> f64 {
    let n = x.nrows();
    let mut worst = 0.0f64;
    for j in 0..n {
        for i in 0..n {
            let one = if i == j { 1.0 } else { 0.0 };
            worst = worst.max((x.get(i, j) - one.into()).to_f64().abs());
        }
    }
    worst
}

fn matrix(n: usize, entries: &[f64]) -> Mat<f64> {
    Mat::from_fn(n, n, |i, j| entries[i * n + j])
}

#[test]
fn division_and_product_are_exact_to_double_double_precision() {
    let third = DoubleDouble::ONE / 3.0.into();
    let back = third * 3.0.into() - DoubleDouble::ONE;
    assert!(back.to_f64().abs() < 4.0 * UNIT_ROUNDOFF_DD, "{back:?}");
    // 1/3 in double-double is 1/3 to about 106 bits: its trailing part is the error of the
    // double 1/3, which is 1/3 − fl(1/3) = 1/(3·2⁵⁴)·(±1).
    assert!(
        (third.lo.abs() - 2f64.powi(-54) / 3.0).abs() < 1e-33,
        "{third:?}"
    );
}

#[test]
fn exponential_of_a_rotation_generator_is_the_rotation() {
    // e^{[[0, w], [−w, 0]]v} = [[cos wv, sin wv], [−sin wv, cos wv]]; at wv = π/2·k the
    // entries are 0 and ±1 up to the double-double value of π/2 in v, so compare the
    // orthogonality Q'Q = I instead, which holds for every v.
    for (w, v) in [(1.0, 0.3), (10.0, 1.7), (100.0, 3.1)] {
        let a = matrix(2, &[0.0, w, -w, 0.0]);
        let q = expm(a.as_ref(), v).expect("finite");
        let qt = DdMatrix::from_fn(2, 2, |i, j| q.get(j, i));
        let d = distance_to_identity(&qt.mul(&q));
        assert!(d < 1e-28, "w = {w}, v = {v}: |Q'Q − I| = {d:e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// `e^{Av}·e^{−Av} = I` to double-double precision, and `e^{Av}` agrees with the
    /// double-precision exponential to its accuracy.
    #[test]
    fn exponential_times_its_inverse_is_the_identity(
        n in 1usize..=5,
        entries in prop::collection::vec(-3.0f64..3.0, 25),
        v in 0.01f64..2.0,
    ) {
        let a = matrix(n, &entries);
        let e = expm(a.as_ref(), v).expect("finite");
        let f = expm(a.as_ref(), -v).expect("finite");
        let scale = e.norm_l1() * f.norm_l1();
        let d = distance_to_identity(&e.mul(&f));
        prop_assert!(d < 1e4 * UNIT_ROUNDOFF_DD * scale * (1.0 + a.norm_l1() * v),
            "|e^(Av) e^(-Av) - I| = {d:e}, scale {scale:e}");
        let reference = sporadic_linalg::expm((&a * faer::Scale(v)).as_ref()).expect("finite");
        let diff = (e.to_f64() - &reference).norm_max();
        prop_assert!(diff < 1e-12 * reference.norm_max().max(1.0),
            "double-double vs double exponential: {diff:e}");
    }

    /// `R·R⁻¹ = I` to double-double precision for well and badly conditioned triangular `R`.
    #[test]
    fn triangular_inverse_is_an_inverse(
        n in 1usize..=8,
        entries in prop::collection::vec(-1.0f64..1.0, 64),
        grading in 0.0f64..8.0,
    ) {
        // A graded diagonal 1, 10^(−grading/n), … makes κ(R) up to about 10⁸.
        let r = Mat::from_fn(n, n, |i, j| {
            if i > j {
                0.0
            } else if i == j {
                10f64.powf(-grading * i as f64 / n as f64) * (1.0 + entries[i * 8 + j].abs())
            } else {
                entries[i * 8 + j]
            }
        });
        let x = upper_triangular_inverse(r.as_ref()).expect("nonsingular");
        // Back substitution has a small componentwise residual,
        // |RX − I| ≤ c·n·u·|R||X| (Higham, Accuracy and Stability, Thm. 8.5), here with the
        // double-double unit roundoff.
        let rx = DdMatrix::from_f64(r.as_ref()).mul(&x);
        for i in 0..n {
            for j in 0..n {
                let one = if i == j { 1.0 } else { 0.0 };
                let residual = (rx.get(i, j) - one.into()).to_f64().abs();
                let scale: f64 = (0..n).map(|k| r[(i, k)].abs() * x.get(k, j).to_f64().abs()).sum();
                prop_assert!(residual <= 4.0 * n as f64 * UNIT_ROUNDOFF_DD * scale,
                    "|RX − I|_({i},{j}) = {residual:e}, (|R||X|)_({i},{j}) = {scale:e}");
            }
        }
    }
}

#[test]
fn singular_triangular_matrix_and_overflow_give_none() {
    let r = matrix(2, &[1.0, 2.0, 0.0, 0.0]);
    assert!(upper_triangular_inverse(r.as_ref()).is_none());
    let a = matrix(1, &[1e3]);
    assert!(expm(a.as_ref(), 1e3).is_none(), "e^(10^6) overflows");
}
