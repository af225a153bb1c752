#![allow(clippy::excessive_precision)] // reference values are quoted digit for digit
//! Published reference values for e^A: SciPy's `TestExpM` (Burkardt's collection of test
//! matrices, Pascal, padecases, triangular perturbation, exp_sinch_overflow, bidiagonal), plus
//! closed forms.

use faer::{Mat, mat};
use sporadic_linalg::InputError;
use sporadic_linalg::{LinalgError, expm, expm_parameters};

fn m(rows: &[&[f64]]) -> Mat<f64> {
    Mat::from_fn(rows.len(), rows[0].len(), |i, j| rows[i][j])
}

/// ‖X − Y‖_F / ‖Y‖_F.
fn rel_frob(x: &Mat<f64>, y: &Mat<f64>) -> f64 {
    (x - y).norm_l2() / y.norm_l2()
}

fn check(name: &str, a: Mat<f64>, want: Mat<f64>, tol: f64) {
    let got = expm(a.as_ref()).unwrap_or_else(|e| panic!("{name}: {e}"));
    let err = rel_frob(&got, &want);
    assert!(
        err <= tol,
        "{name}: relative Frobenius error {err:e} > {tol:e}\n got {got:?}\nwant {want:?}"
    );
}

const E: f64 = std::f64::consts::E;

#[test]
fn burkardt_1_diagonal() {
    check(
        "burkardt_1",
        m(&[&[1.0, 0.0], &[0.0, 2.0]]),
        m(&[&[E, 0.0], &[0.0, E * E]]),
        1e-15,
    );
}

#[test]
fn burkardt_2_symmetric() {
    let want = m(&[
        &[39.322809708033859, 46.166301438885753],
        &[46.166301438885768, 54.711576854329110],
    ]);
    check("burkardt_2", m(&[&[1.0, 3.0], &[3.0, 2.0]]), want, 1e-13);
}

#[test]
fn burkardt_3_laub() {
    let e1 = 1f64.exp();
    let e39 = 39f64.exp();
    let em = (-38f64).exp_m1();
    let want = m(&[
        &[39.0 / (38.0 * e1) - 1.0 / (38.0 * e39), -em / (38.0 * e1)],
        &[
            39.0 * em / (38.0 * e1),
            -1.0 / (38.0 * e1) + 39.0 / (38.0 * e39),
        ],
    ]);
    check(
        "burkardt_3",
        m(&[&[0.0, 1.0], &[-39.0, -40.0]]),
        want,
        1e-13,
    );
}

#[test]
fn burkardt_4_moler_van_loan() {
    let u = mat![[3.0, 1.0], [4.0, 2.0]];
    let v = mat![[1.0, -0.5], [-2.0, 1.5]];
    let d = mat![[(-17f64).exp(), 0.0], [0.0, (-1f64).exp()]];
    let want = &u * &d * &v;
    check(
        "burkardt_4",
        m(&[&[-49.0, 24.0], &[-64.0, 31.0]]),
        want,
        1e-13,
    );
}

#[test]
fn burkardt_5_nilpotent_is_exact() {
    let a = m(&[
        &[0.0, 6.0, 0.0, 0.0],
        &[0.0, 0.0, 6.0, 0.0],
        &[0.0, 0.0, 0.0, 6.0],
        &[0.0, 0.0, 0.0, 0.0],
    ]);
    let want = m(&[
        &[1.0, 6.0, 18.0, 36.0],
        &[0.0, 1.0, 6.0, 18.0],
        &[0.0, 0.0, 1.0, 6.0],
        &[0.0, 0.0, 0.0, 1.0],
    ]);
    check("burkardt_5", a, want, 1e-15);
}

#[test]
fn burkardt_6_and_7_defective() {
    let want = m(&[&[E, E], &[0.0, E]]);
    check(
        "burkardt_6",
        m(&[&[1.0, 1.0], &[0.0, 1.0]]),
        want.clone(),
        1e-15,
    );
    let eps = f64::EPSILON;
    check(
        "burkardt_7",
        m(&[&[1.0 + eps, 1.0], &[0.0, 1.0 - eps]]),
        want,
        1e-15,
    );
}

#[test]
fn burkardt_8_wikipedia() {
    let (e4, e16) = (4f64.exp(), 16f64.exp());
    let want = m(&[
        &[13.0 * e16 - e4, 13.0 * e16 - 5.0 * e4, 2.0 * e16 - 2.0 * e4],
        &[
            -9.0 * e16 + e4,
            -9.0 * e16 + 5.0 * e4,
            -2.0 * e16 + 2.0 * e4,
        ],
        &[16.0 * e16, 16.0 * e16, 4.0 * e16],
    ]) * faer::Scale(0.25);
    check(
        "burkardt_8",
        m(&[&[21.0, 17.0, 6.0], &[-5.0, -1.0, -6.0], &[4.0, 4.0, 16.0]]),
        want,
        1e-13,
    );
}

#[test]
fn burkardt_9_nag_to_printed_digits() {
    let a = m(&[
        &[1.0, 2.0, 2.0, 2.0],
        &[3.0, 1.0, 1.0, 2.0],
        &[3.0, 2.0, 1.0, 2.0],
        &[3.0, 3.0, 3.0, 1.0],
    ]);
    let want = m(&[
        &[740.7038, 610.8500, 542.2743, 549.1753],
        &[731.2510, 603.5524, 535.0884, 542.2743],
        &[823.7630, 679.4257, 603.5524, 610.8500],
        &[998.4355, 823.7630, 731.2510, 740.7038],
    ]);
    let got = expm(a.as_ref()).unwrap();
    for i in 0..4 {
        for j in 0..4 {
            // Four printed decimals: |error| ≤ 0.5e-4 (+ rounding slack).
            assert!(
                (got[(i, j)] - want[(i, j)]).abs() <= 0.5e-4 + 1e-9,
                "({i},{j}) {}",
                got[(i, j)]
            );
        }
    }
}

#[test]
fn burkardt_10_ward_defective() {
    let want = m(&[
        &[147.8666224463699, 183.7651386463682, 71.79703239999647],
        &[127.7810855231823, 183.7651386463682, 91.88256932318415],
        &[127.7810855231824, 163.6796017231806, 111.9681062463718],
    ]);
    check(
        "burkardt_10",
        m(&[&[4.0, 2.0, 0.0], &[1.0, 4.0, 1.0], &[1.0, 1.0, 4.0]]),
        want,
        1e-13,
    );
}

#[test]
fn burkardt_11_ward_symmetric() {
    let a = m(&[
        &[29.87942128909879, 0.7815750847907159, -2.289519314033932],
        &[0.7815750847907159, 25.72656945571064, 8.680737820540137],
        &[-2.289519314033932, 8.680737820540137, 34.39400925519054],
    ]);
    let want = m(&[
        &[
            5.496313853692378E+15,
            -1.823188097200898E+16,
            -3.047577080858001E+16,
        ],
        &[
            -1.823188097200899E+16,
            6.060522870222108E+16,
            1.012918429302482E+17,
        ],
        &[
            -3.047577080858001E+16,
            1.012918429302482E+17,
            1.692944112408493E+17,
        ],
    ]);
    check("burkardt_11", a, want, 1e-13);
}

#[test]
fn burkardt_12_ward() {
    let a = m(&[
        &[-131.0, 19.0, 18.0],
        &[-390.0, 56.0, 54.0],
        &[-387.0, 57.0, 52.0],
    ]);
    let want = m(&[
        &[-1.509644158793135, 0.3678794391096522, 0.1353352811751005],
        &[-5.632570799891469, 1.471517758499875, 0.4060058435250609],
        &[-4.934938326088363, 1.103638317328798, 0.5413411267617766],
    ]);
    // The published 16-digit values are themselves off by 2.0e−12 (relative Frobenius) from a
    // 60-digit mpmath evaluation (mpmath 1.3 `expm`, dps = 60), which is the tighter oracle:
    check("burkardt_12 (published)", a.clone(), want, 3e-12);
    let hp = m(&[
        &[-1.5096441587960896, 0.3678794391102887, 0.13533528117545907],
        &[-5.632570799902596, 1.4715177585023085, 0.4060058435263772],
        &[-4.9349383260981075, 1.1036383173308661, 0.54134112676299],
    ]);
    check("burkardt_12 (60-digit)", a, hp, 1e-13);
}

/// Forsythe matrix: ones on the superdiagonal, 10⁻ⁿ in the corner; reference by the Taylor
/// series (all terms nonnegative, so the summation is accurate).
#[test]
fn burkardt_13_forsythe() {
    for n in [2usize, 3, 4, 10] {
        let mut a = Mat::<f64>::zeros(n, n);
        for i in 0..n - 1 {
            a[(i, i + 1)] = 1.0;
        }
        a[(n - 1, 0)] = 10f64.powi(-(n as i32));
        let mut want = Mat::<f64>::identity(n, n);
        let mut term = Mat::<f64>::identity(n, n);
        for p in 1..60 {
            term = &term * &a * faer::Scale(1.0 / p as f64);
            want += &term;
        }
        check(&format!("burkardt_13 n={n}"), a, want, 1e-14);
    }
}

#[test]
fn burkardt_14_moler_badly_scaled() {
    let a = m(&[
        &[0.0, 1e-8, 0.0],
        &[-(2e10 + 4e8 / 6.0), -3.0, 2e10],
        &[200.0 / 3.0, 0.0, -200.0 / 3.0],
    ]);
    let want = m(&[
        &[0.446849468283175, 1.54044157383952e-09, 0.462811453558774],
        &[-5743067.77947947, -0.0152830038686819, -4526542.71278401],
        &[0.447722977849494, 1.54270484519591e-09, 0.463480648837651],
    ]);
    // Reference values carry 15 significant digits; the matrix is badly scaled (‖A‖₁ ≈ 4e10).
    check("burkardt_14", a, want, 1e-12);
}

#[test]
fn bidiagonal_closed_form() {
    let (e1, e2) = (1f64.exp(), 2f64.exp());
    let want = m(&[
        &[e1, 3.0 * e1, 15.0 * (e2 - 2.0 * e1)],
        &[0.0, e1, 5.0 * (e2 - e1)],
        &[0.0, 0.0, e2],
    ]);
    check(
        "bidiagonal",
        m(&[&[1.0, 3.0, 0.0], &[0.0, 1.0, 5.0], &[0.0, 0.0, 2.0]]),
        want,
        1e-15,
    );
}

#[test]
fn two_by_two_closed_form() {
    // [[1,4],[1,1]] has eigenvalues 3 and −1.
    let e = 1f64.exp();
    let e4 = 4f64.exp();
    let want = m(&[
        &[(e4 + 1.0) / (2.0 * e), (e4 - 1.0) / e],
        &[(e4 - 1.0) / (4.0 * e), (e4 + 1.0) / (2.0 * e)],
    ]);
    check(
        "2x2 [[1,4],[1,1]]",
        m(&[&[1.0, 4.0], &[1.0, 1.0]]),
        want,
        1e-14,
    );
}

/// Pascal: A = diag(1..n, −1)·scale is nilpotent; e^A is the binomial matrix
/// (e^A)_{ij} = C(i, j)·scale^{i−j} for i ≥ j. SciPy tolerance: atol = 1e−13·max|e^A|.
#[test]
fn pascal_binomial_matrices() {
    for scale in [1.0f64, 1e-3, 1e-6] {
        for n in (1..80).step_by(3) {
            let dim = n + 1;
            if (0..=n).any(|k| scale.powi(k as i32) < 1e-300) {
                break;
            }
            let a = Mat::from_fn(
                dim,
                dim,
                |i, j| if i == j + 1 { i as f64 * scale } else { 0.0 },
            );
            let got = expm(a.as_ref()).unwrap();
            // C(i, j) by the multiplicative formula in f64 (exact up to rounding).
            let binom = |i: usize, j: usize| -> f64 {
                (0..j).fold(1.0, |acc, k| acc * (i - k) as f64 / (k + 1) as f64)
            };
            let want = Mat::from_fn(dim, dim, |i, j| {
                if i >= j {
                    binom(i, j) * scale.powi((i - j) as i32)
                } else {
                    0.0
                }
            });
            let max = want.norm_max();
            let err = (&got - &want).norm_max();
            assert!(
                err <= 1e-13 * max,
                "n={n} scale={scale}: {err:e} vs max {max:e}"
            );
        }
    }
}

/// SciPy `test_padecases`: s·I to 100 ulp (the diagonal shortcut). The general-path variant
/// that exercises every Padé degree is a unit test in `expm::pade`.
#[test]
fn padecases_scaled_identity_within_100_ulp() {
    for s in [1e-2, 1e-1, 0.5, 1.0, 10.0] {
        let a = Mat::<f64>::identity(3, 3) * faer::Scale(s);
        let got = expm(a.as_ref()).unwrap();
        let e = s.exp();
        for i in 0..3 {
            for j in 0..3 {
                let want = if i == j { e } else { 0.0 };
                assert!((got[(i, j)] - want).abs() <= 100.0 * f64::EPSILON * e);
            }
        }
    }
}

/// Same orders through a dense (non-diagonal) similarity: Q·(sI + N)·Qᵀ with an exactly
/// orthogonal permutation-with-signs Q keeps the structure general, so the Padé degree
/// selection of Algorithm 6.1 is exercised from the public API.
#[test]
fn degree_selection_on_general_matrices() {
    // A = s·[[1, 1], [−1, 1]] has ‖A^k‖₁^{1/k} = √2·s for even k, so η = √2·s in every test
    // of Algorithm 6.1, and |A| = s·𝟙𝟙ᵀ gives ‖ |A|^p ‖₁/‖A‖₁ = (2s)^{p−1}, hence
    // ℓ(A, m) = max(⌈log₂((2s)^{2m}/(|c|⁻¹·u))/(2m)⌉, 0). By hand:
    //   s = 0.005: η ≤ θ3, ℓ(A,3) = 0                      → m = 3
    //   s = 0.01:  η ≤ θ3 but ℓ(A,3) = ⌈2.52/6⌉ = 1           → m = 5
    //   s = 0.1:   θ3 < η ≤ θ5, ℓ = 0                       → m = 5
    //   s = 0.4:   θ5 < η ≤ θ7, ℓ = 0                       → m = 7
    //   s = 0.5:   η ≤ θ7 but ℓ(A,7) = ⌈0.97/14⌉ = 1, ℓ(A,9) = 0 → m = 9
    //   s = 1.0:   θ7 < η ≤ θ9, ℓ = 0                       → m = 9
    //   s = 1.2:   η ≤ θ9 but ℓ(A,9) = 1; s = 0, ℓ(A,13) = 0  → m = 13, s = 0
    //   s = 4:     s = ⌈log₂(4√2/4.25)⌉ = 1, ℓ = 0          → m = 13, s = 1
    //   s = 100:   s = ⌈log₂(100√2/4.25)⌉ = 6, ℓ = 0        → m = 13, s = 6
    let cases = [
        (0.005, 3, 0),
        (0.01, 5, 0),
        (0.1, 5, 0),
        (0.4, 7, 0),
        (0.5, 9, 0),
        (1.0, 9, 0),
        (1.2, 13, 0),
        (4.0, 13, 1),
        (100.0, 13, 6),
    ];
    for (s, m_want, sq_want) in cases {
        let a = mat![[s, s], [-s, s]];
        let p = expm_parameters(a.as_ref()).unwrap();
        assert_eq!((p.degree, p.squarings), (m_want, sq_want), "s = {s}");
        // e^{s(I + J)} = e^s·[[cos s, sin s], [−sin s, cos s]].
        let want = mat![[s.cos(), s.sin()], [-s.sin(), s.cos()]] * faer::Scale(s.exp());
        let got = expm(a.as_ref()).unwrap();
        assert!(
            rel_frob(&got, &want) <= 1e-14 * (1.0 + s),
            "s = {s}: {:e}",
            rel_frob(&got, &want)
        );
    }
}

/// Experiment (1) of Al-Mohy & Higham (2012), used by SciPy: expm(logm(A)) ≈ A to 1e−4 for
/// the upper-triangular logarithm (Code Fragment 2.1), while a 1e−17 perturbation below the
/// diagonal must visibly change the (extremely ill-conditioned) result.
#[test]
fn triangularity_perturbation() {
    let a = m(&[
        &[3.2346e-1, 3e4, 3e4, 3e4],
        &[0.0, 3.0089e-1, 3e4, 3e4],
        &[0.0, 0.0, 3.221e-1, 3e4],
        &[0.0, 0.0, 0.0, 3.0744e-1],
    ]);
    let a_logm = m(&[
        &[
            -1.12867982029050462e+00,
            9.61418377142025565e+04,
            -4.52485573953179264e+09,
            2.92496941103871812e+14,
        ],
        &[
            0.0,
            -1.20101052953082288e+00,
            9.63469687211303099e+04,
            -4.68104828911105442e+09,
        ],
        &[0.0, 0.0, -1.13289322264498393e+00, 9.53249183094775653e+04],
        &[0.0, 0.0, 0.0, -1.17947533272554850e+00],
    ]);
    let got = expm(a_logm.as_ref()).unwrap();
    for i in 0..4 {
        for j in 0..4 {
            let (g, w) = (got[(i, j)], a[(i, j)]);
            assert!(
                (g - w).abs() <= 1e-4 * w.abs() + 1e-12,
                "({i},{j}): {g} vs {w}"
            );
        }
    }
    let mut perturbed = a_logm.clone();
    perturbed[(1, 0)] = 1e-17;
    let got_p = expm(perturbed.as_ref()).unwrap();
    let close = (0..4).all(|i| {
        (0..4).all(|j| (got_p[(i, j)] - a[(i, j)]).abs() <= 1e-15 + 1e-4 * a[(i, j)].abs())
    });
    assert!(
        !close,
        "a 1e-17 perturbation of an ill-conditioned logarithm must change e^A"
    );
}

/// gh-11839: e^{−2¹¹L} = (e^{−L})^{2¹¹}; λ-gaps of 2048 make sinh overflow in a naive
/// evaluation of the superdiagonal formula.
#[test]
fn exp_sinch_overflow() {
    let mut l = Mat::<f64>::zeros(7, 7);
    for (i, j, v) in [
        (0, 0, 1.0),
        (0, 1, -0.5),
        (0, 2, -0.5),
        (1, 1, 1.0),
        (1, 3, -0.5),
        (1, 4, -0.5),
        (2, 2, 1.0),
        (2, 5, -0.5),
        (2, 6, -0.5),
    ] {
        l[(i, j)] = v;
    }
    let e0 = expm((&l * faer::Scale(-1.0)).as_ref()).unwrap();
    let e1 = expm((&l * faer::Scale(-2048.0)).as_ref()).unwrap();
    let mut e2 = e0;
    for _ in 0..11 {
        e2 = &e2 * &e2;
    }
    assert!(e1.norm_max().is_finite());
    // assert_allclose default: rtol 1e−7.
    for i in 0..7 {
        for j in 0..7 {
            assert!(
                (e1[(i, j)] - e2[(i, j)]).abs() <= 1e-7 * e2[(i, j)].abs(),
                "({i},{j})"
            );
        }
    }
    // Closed forms (divided differences of exp on the tree 0 → {1, 2}, 1 → {3, 4}, 2 → {5, 6}):
    // (0,1): 1024·e^{−2048} = 0; (1,3): 1024·(1 − e^{−2048})/2048 = 1/2;
    // (0,3): 1024²·f[−2048, −2048, 0] = 1024²·((1 − e^{−2048})/2048 − e^{−2048})/2048 = 1/4.
    assert_eq!(e1[(0, 1)], 0.0);
    assert!((e1[(1, 3)] - 0.5).abs() < 1e-15, "{}", e1[(1, 3)]);
    assert!((e1[(0, 3)] - 0.25).abs() < 1e-15, "{}", e1[(0, 3)]);
}

#[test]
fn zero_and_one_by_one() {
    let z = Mat::<f64>::zeros(5, 5);
    assert_eq!(expm(z.as_ref()).unwrap(), Mat::<f64>::identity(5, 5));
    assert_eq!(expm(mat![[2.0]].as_ref()).unwrap()[(0, 0)], 2f64.exp());
}

#[test]
fn error_paths() {
    let nan = mat![[1.0, f64::NAN], [0.0, 1.0]];
    assert!(matches!(
        expm(nan.as_ref()),
        Err(LinalgError::Input(InputError::NonFinite { .. }))
    ));
    let inf = mat![[1.0, 0.0], [f64::INFINITY, 1.0]];
    assert!(matches!(
        expm(inf.as_ref()),
        Err(LinalgError::Input(InputError::NonFinite { .. }))
    ));
    let rect = Mat::<f64>::zeros(2, 3);
    assert!(matches!(
        expm(rect.as_ref()),
        Err(LinalgError::Input(InputError::NotSquare {
            rows: 2,
            cols: 3,
            ..
        }))
    ));
    let empty = Mat::<f64>::zeros(0, 0);
    assert!(matches!(
        expm(empty.as_ref()),
        Err(LinalgError::Input(InputError::Empty { .. }))
    ));
    // e^{1000} overflows: reported, not returned as Inf/NaN.
    assert!(matches!(
        expm(mat![[1000.0, 1.0], [0.0, 1.0]].as_ref()),
        Err(LinalgError::Overflow { .. })
    ));
    assert!(matches!(
        expm(mat![[1000.0, 1.0], [2.0, 1.0]].as_ref()),
        Err(LinalgError::Overflow { .. })
    ));
    let big = Mat::from_fn(12, 12, |i, j| {
        if i == j {
            800.0
        } else {
            1.0 / (1 + i + j) as f64
        }
    });
    assert!(matches!(
        expm(big.as_ref()),
        Err(LinalgError::Overflow { .. })
    ));
    assert!(matches!(
        sporadic_linalg::expm_scaled(mat![[1.0]].as_ref(), f64::NAN),
        Err(LinalgError::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        sporadic_linalg::expm_scaled(mat![[1e300, 0.0], [1.0, 0.0]].as_ref(), 1e300),
        Err(LinalgError::Overflow { .. })
    ));
}

/// Huge norm but representable result: e^{A} for A = [[−1e200, 1], [0, −1e200]]-like matrices
/// and a strongly decaying general matrix must not produce NaN.
#[test]
fn huge_norm_with_representable_result() {
    let a = mat![[-1e200, 1.0], [0.0, -2.0]];
    let got = expm(a.as_ref()).unwrap();
    assert_eq!(got[(0, 0)], 0.0);
    assert!((got[(1, 1)] - (-2f64).exp()).abs() < 1e-16);
    // (1,2) entry: (e^{−2} − e^{−1e200})/(−2 + 1e200) ≈ e^{−2}/1e200.
    assert!((got[(0, 1)] - (-2f64).exp() / 1e200).abs() <= 1e-14 * (-2f64).exp() / 1e200);
    // General (non-triangular) with ‖A‖ ≈ 1e40: block-diagonal rotation-like decay.
    let g = mat![[-1e40, 1e39, 0.0], [-1e39, -1e40, 0.0], [0.0, 0.0, 0.5]];
    let got = expm(g.as_ref()).unwrap();
    assert!(got.norm_max().is_finite());
    assert!((got[(2, 2)] - 0.5f64.exp()).abs() < 1e-15 && got[(0, 0)].abs() < 1e-300);
}
