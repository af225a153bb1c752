//! Enclosures of e^{Aτ}: containment of 50+-digit references (tests/data/expm_refs.txt,
//! produced by tests/data/gen_expm_refs.py with mpmath), property tests against closed forms and
//! the floating-point expm, structure of the pieces.

use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, mat};
use proptest::prelude::*;
use sporadic_interval::{
    EnclosureOptions, IntervalError, IntervalMatrix, expm_enclosure, expm_enclosure_interval,
    expm_interval,
};

struct RefCase {
    name: String,
    tau0: f64,
    tau1: f64,
    tau: f64,
    /// Entry v (row-major) bracketed as s + e_lo ≤ v ≤ s + e_hi (exact reals).
    s: Vec<f64>,
    e_lo: Vec<f64>,
    e_hi: Vec<f64>,
}

fn load() -> Vec<(String, Mat<f64>, Vec<RefCase>)> {
    let text = include_str!("data/expm_refs.txt");
    let mut out: Vec<(String, Mat<f64>, Vec<RefCase>)> = Vec::new();
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        match f.first() {
            Some(&"matrix") => {
                let n: usize = f[2].parse().unwrap();
                let v: Vec<f64> = f[3..].iter().map(|s| s.parse().unwrap()).collect();
                assert_eq!(v.len(), n * n);
                out.push((
                    f[1].to_owned(),
                    Mat::from_fn(n, n, |i, j| v[i * n + j]),
                    vec![],
                ));
            }
            Some(&"ref") => {
                let v: Vec<f64> = f[2..].iter().map(|s| s.parse().unwrap()).collect();
                let last = out.last_mut().unwrap();
                assert_eq!(last.0, f[1]);
                let ent = &v[3..];
                last.2.push(RefCase {
                    name: f[1].to_owned(),
                    tau0: v[0],
                    tau1: v[1],
                    tau: v[2],
                    s: ent.iter().step_by(3).copied().collect(),
                    e_lo: ent.iter().skip(1).step_by(3).copied().collect(),
                    e_hi: ent.iter().skip(2).step_by(3).copied().collect(),
                });
            }
            _ => {}
        }
    }
    out
}

/// Exact sign of a sum of floats: Shewchuk's Grow-Expansion turns the terms into a
/// non-overlapping expansion (increasing magnitude) whose sign is that of its largest component.
fn sign_of_sum(terms: &[f64]) -> f64 {
    let mut h: Vec<f64> = Vec::new();
    for &x in terms {
        let mut q = x;
        for hi in h.iter_mut() {
            let s = q + *hi;
            let bb = s - q;
            let err = (q - (s - bb)) + (*hi - bb);
            *hi = err;
            q = s;
        }
        h.push(q);
    }
    h.iter()
        .rev()
        .find(|v| **v != 0.0)
        .map_or(0.0, |v| v.signum())
}

/// Rigorous: both double-double brackets of the reference lie in ⟨m, r⟩ entrywise.
fn contains_ref(e: &IntervalMatrix, c: &RefCase) -> bool {
    let n = e.nrows();
    (0..n).all(|i| {
        (0..n).all(|j| {
            let k = i * n + j;
            let (m, r) = (e.mid()[(i, j)], e.rad()[(i, j)]);
            if r == f64::INFINITY {
                return true;
            }
            // m + r − (s + e_hi) ≥ 0 and (s + e_lo) − (m − r) ≥ 0, exactly.
            sign_of_sum(&[m, r, -c.s[k], -c.e_hi[k]]) >= 0.0
                && sign_of_sum(&[c.s[k], c.e_lo[k], -m, r]) >= 0.0
        })
    })
}

#[test]
fn enclosures_contain_high_precision_references() {
    let data = load();
    assert!(data.len() >= 15);
    let mut checked = 0;
    for (name, a, cases) in &data {
        for c in cases {
            let r = expm_enclosure(a.as_ref(), c.tau0, c.tau1, &EnclosureOptions::default())
                .unwrap_or_else(|e| panic!("{name} [{}, {}]: {e}", c.tau0, c.tau1));
            assert!(
                contains_ref(&r.enclosure, c),
                "{} τ={} not in the hull enclosure over [{}, {}]",
                c.name,
                c.tau,
                c.tau0,
                c.tau1
            );
            // The piece(s) whose τ-range contains τ must contain the reference too.
            let mut found = false;
            for p in &r.pieces {
                if p.tau0 <= c.tau && c.tau <= p.tau1 {
                    found = true;
                    assert!(
                        contains_ref(&p.enclosure, c),
                        "{} τ={} not in piece [{}, {}]",
                        c.name,
                        c.tau,
                        p.tau0,
                        p.tau1
                    );
                }
            }
            assert!(found);
            // Thin windows give thin enclosures.
            if c.tau0 == c.tau1 && name != "stiff_triangular" {
                assert!(
                    r.rel_width < 1e-11,
                    "{name} point window rel width {}",
                    r.rel_width
                );
            }
            checked += 1;
        }
    }
    assert!(checked >= 150, "{checked}");
}

#[test]
fn widths_over_short_window_are_useful() {
    // Regression guard on the tightness: relative hull width over [0.2, 0.21] stays within a
    // small multiple of the true variation ‖A e^{Aτ}‖·0.01 / ‖e^{Aτ}‖.
    for (name, a, _) in load() {
        let r = expm_enclosure(a.as_ref(), 0.2, 0.21, &EnclosureOptions::default()).unwrap();
        assert!(r.rel_width < 2.0, "{name}: rel width {}", r.rel_width);
        assert!(
            r.max_piece_rel_width < 0.05,
            "{name}: piece rel width {}",
            r.max_piece_rel_width
        );
    }
}

#[test]
fn pieces_cover_the_window() {
    let a = mat![[0.0, 10.0], [-10.0, 0.0]];
    let r = expm_enclosure(a.as_ref(), 0.3, 0.7, &EnclosureOptions::default()).unwrap();
    assert_eq!(r.pieces.first().unwrap().tau0, 0.3);
    assert_eq!(r.pieces.last().unwrap().tau1, 0.7);
    for w in r.pieces.windows(2) {
        assert_eq!(w[0].tau1, w[1].tau0);
        assert!(w[0].tau0 <= w[0].tau1);
    }
    assert!(r.pieces.len() <= EnclosureOptions::default().max_pieces);
    for p in &r.pieces {
        assert!(r.enclosure.contains(&p.enclosure));
    }
}

#[test]
fn hard_badly_scaled_matrix_is_enclosed_or_refused() {
    // Burkardt 14 (Moler): entries up to 2e10. A wide enclosure or a typed refusal are both
    // acceptable; a wrong enclosure is not (checked against the floating-point expm loosely).
    let a = mat![
        [0.0, 1e-8, 0.0],
        [-(2e10 + 4e8 / 6.0), -3.0, 2e10],
        [200.0 / 3.0, 0.0, -200.0 / 3.0]
    ];
    match expm_enclosure(a.as_ref(), 1.0, 1.0, &EnclosureOptions::default()) {
        Ok(r) => {
            let e = sporadic_linalg::expm(a.as_ref()).unwrap();
            assert!(
                r.enclosure.intersects(
                    &IntervalMatrix::from_point(e.as_ref())
                        .unwrap()
                        .inflate(1e-6 * 6e6)
                )
            );
        }
        Err(IntervalError::EnclosureFailed(_)) => {}
        Err(e) => panic!("unexpected error {e}"),
    }
}

fn rotation(w: f64, t: f64) -> Mat<f64> {
    let (s, c) = (w * t).sin_cos();
    mat![[c, s], [-s, c]]
}

/// `x` lies in `e` up to a tolerance `tol` (absolute), for non-rigorous f64 references.
fn near(e: &IntervalMatrix, x: &Mat<f64>, tol: f64) -> bool {
    e.inflate(tol).contains_point(x.as_ref())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn rotation_closed_form(w in 0.1f64..50.0, t0 in 0.0f64..2.0, len in 0.0f64..0.05, f in 0.0f64..=1.0) {
        let a = mat![[0.0, w], [-w, 0.0]];
        let t1 = t0 + len;
        let t = (t0 + f * len).clamp(t0, t1);
        let r = expm_enclosure(a.as_ref(), t0, t1, &EnclosureOptions::default()).unwrap();
        // f64 sin/cos of a rounded product: error ≲ 1e-14 for |wt| ≤ 100.
        prop_assert!(near(&r.enclosure, &rotation(w, t), 1e-13));
    }

    #[test]
    fn jordan_closed_form(lam in -30.0f64..3.0, t0 in 0.0f64..1.0, len in 0.0f64..0.02, f in 0.0f64..=1.0) {
        // e^{Jt} for J = [[λ, 1], [0, λ]] is e^{λt}·[[1, t], [0, 1]].
        let a = mat![[lam, 1.0], [0.0, lam]];
        let t1 = t0 + len;
        let t = (t0 + f * len).clamp(t0, t1);
        let r = expm_enclosure(a.as_ref(), t0, t1, &EnclosureOptions::default()).unwrap();
        let e = (lam * t).exp();
        let x = mat![[e, t * e], [0.0, e]];
        prop_assert!(near(&r.enclosure, &x, 1e-13 * e.max(1e-300)));
    }

    #[test]
    fn random_matrices_vs_float_expm(
        n in 1usize..6,
        v in prop::collection::vec(-3.0f64..3.0, 36),
        t0 in 0.0f64..1.0,
        len in 0.0f64..0.05,
        f in 0.0f64..=1.0,
    ) {
        let a = Mat::from_fn(n, n, |i, j| v[i * 6 + j]);
        let t1 = t0 + len;
        let t = (t0 + f * len).clamp(t0, t1);
        let r = expm_enclosure(a.as_ref(), t0, t1, &EnclosureOptions::default()).unwrap();
        let e = sporadic_linalg::expm_scaled(a.as_ref(), t).unwrap();
        let scale = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| e[(i, j)].abs()).fold(0.0, f64::max);
        prop_assert!(near(&r.enclosure, &e, 1e-12 * scale.max(1.0)));
        // Point windows: thin enclosure.
        let p = expm_enclosure(a.as_ref(), t, t, &EnclosureOptions::default()).unwrap();
        prop_assert!(p.rel_width < 1e-11, "point rel width {}", p.rel_width);
        prop_assert!(near(&p.enclosure, &e, 1e-12 * scale.max(1.0)));
    }

    #[test]
    fn expm_interval_contains_members(d in prop::collection::vec(-2.0f64..2.0, 4), r in 0.0f64..1e-3, f in prop::collection::vec(-1.0f64..=1.0, 4)) {
        // e^X for X in ⟨D, r⟩ with diagonal D: any member X = D + diag(f)·r has e^X = diag(e^{x_ii}).
        let mid = Mat::from_fn(2, 2, |i, j| if i == j { d[i] } else { 0.0 });
        let rad = Mat::from_fn(2, 2, |_, _| r);
        let x = IntervalMatrix::from_mid_rad(mid, rad).unwrap();
        let e = expm_interval(&x).unwrap();
        let member = Mat::from_fn(2, 2, |i, j| if i == j { (d[i] + f[i] * r).exp() } else { 0.0 });
        prop_assert!(near(&e, &member, 1e-14));
    }
}

/// `e^{Aτ}` to about 30 digits ([`sporadic_interval::double_double::expm`]), rounded to f64.
fn expm_dd(a: &Mat<f64>, tau: f64) -> Mat<f64> {
    sporadic_interval::double_double::expm(a.as_ref(), tau)
        .expect("finite")
        .to_f64()
}

#[test]
fn a_non_normal_matrix_is_enclosed_in_its_eigenbasis() {
    // A mass-spring-damper (eigenvalues −0.2 ± 1.99i) in millimetres and km/s, then in the
    // coordinates x = Tz of a random T with κ(T) < 10 (the corpus plant `badly-scaled-units`
    // as a user could write it): ‖A‖_∞ ≈ 6.7e5. Squaring the Taylor polynomial of e^{A/2^17}
    // gave an enclosure of e^{0.05A} with midpoint 1e21 and radius 6e37.
    let a = mat![
        [-132111.39560073803, 534641.4499382566],
        [-32644.99602309561, 132110.99560073798]
    ];
    for (t0, t1) in [(0.05, 0.05), (0.05, 0.06), (1.0, 1.0), (0.5, 1.5)] {
        let r = expm_enclosure(a.as_ref(), t0, t1, &EnclosureOptions::default()).unwrap();
        let points = if t0 == t1 { 0 } else { 10 };
        for k in 0..=points {
            let t = t0 + (t1 - t0) * f64::from(k) / 10.0;
            let e = expm_dd(&a, t);
            assert!(
                r.enclosure.contains_point(e.as_ref()),
                "[{t0}, {t1}] misses e^(A·{t})"
            );
        }
        // Point windows: measured 2.7e-5 and 1.1e-4; the pieces of [0.05, 0.06] and
        // [0.5, 1.5] (64 at most): 3.1e-3 and 4.9e-2.
        if t0 == t1 {
            assert!(r.rel_width < 1e-3, "[{t0}, {t1}]: {}", r.rel_width);
        } else {
            assert!(
                r.max_piece_rel_width < 0.1,
                "[{t0}, {t1}]: {}",
                r.max_piece_rel_width
            );
        }
    }
}

#[test]
fn a_moderately_non_normal_matrix_is_enclosed_directly() {
    // Found by `random_matrices_vs_float_expm`: eigenvalues 0.94 ± 1.73i, −1.87, −1.63, an
    // eigenbasis with ‖S‖_∞‖S⁻¹‖_∞ ≈ 92 in which ‖B‖_∞ ≈ 2.7, ‖A‖_∞τ ≈ 8.8. Enclosed in the
    // eigenbasis, the point enclosure was 2.7e-11 wide (relative); directly, as now, 3.4e-14
    // (measured).
    let a = mat![
        [
            1.3923900013766446,
            0.8389861298109975,
            -0.2535334646538825,
            0.0
        ],
        [
            -2.920876494384397,
            1.9073870089372325,
            -1.4997736232431473,
            0.0
        ],
        [
            2.3444501231766526,
            2.8243023966233785,
            -2.605015000235219,
            2.9322772714652614
        ],
        [
            -2.366218161692613,
            0.31188135657151217,
            -0.2123750257088159,
            -2.319209185129478
        ]
    ];
    let t = 0.8181188147291977;
    let r = expm_enclosure(a.as_ref(), t, t, &EnclosureOptions::default()).unwrap();
    assert!(r.enclosure.contains_point(expm_dd(&a, t).as_ref()));
    assert!(r.rel_width < 1e-13, "{}", r.rel_width);
}

/// A real matrix with the eigenvalues `re ± i·im` and `real` in the coordinates
/// `x = D T z` (`T` mixes the states, `D = diag(1, 10^k, 10^{−k})`): non-normal, with entries
/// up to about `10^{2k}` times its eigenvalues.
fn non_normal(re: f64, im: f64, real: f64, mix: &[f64], k: i32) -> Mat<f64> {
    let blocks = mat![[re, im, 0.0], [-im, re, 0.0], [0.0, 0.0, real]];
    let t = Mat::from_fn(3, 3, |i, j| mix[3 * i + j] + if i == j { 2.0 } else { 0.0 });
    let d = Mat::from_fn(3, 3, |i, j| match (i, j) {
        (0, 0) => 1.0,
        (1, 1) => 10f64.powi(k),
        (2, 2) => 10f64.powi(-k),
        _ => 0.0,
    });
    let s = &d * &t;
    let s_inv = s.partial_piv_lu().inverse();
    &s * blocks * s_inv
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Strongly non-normal matrices of order 3 (entries up to 1e6 times the eigenvalues; at 1e8
    /// the basis's condition number reaches `MAX_BASIS_CONDITION`):
    /// the enclosure of a point τ contains the double-double exponential and is thin.
    #[test]
    fn non_normal_matrices_are_enclosed_thinly(
        re in -1.0f64..0.3,
        im in 0.5f64..3.0,
        real in -2.0f64..0.5,
        mix in prop::collection::vec(-0.5f64..0.5, 9),
        k in 2i32..4,
        tau in 0.01f64..2.0,
    ) {
        let a = non_normal(re, im, real, &mix, k);
        let r = expm_enclosure(a.as_ref(), tau, tau, &EnclosureOptions::default()).unwrap();
        prop_assert!(r.enclosure.contains_point(expm_dd(&a, tau).as_ref()));
        prop_assert!(r.rel_width < 1e-3, "rel width {}", r.rel_width);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// `expm_enclosure_interval` contains `e^{Aτ}` of members of an interval matrix (its
    /// midpoint and corners, by the double-double exponential) over a window, and on a point
    /// matrix it is `expm_enclosure` itself.
    #[test]
    fn interval_matrices_are_enclosed_for_every_member(
        entries in proptest::collection::vec(-3.0f64..3.0, 9),
        corner in proptest::collection::vec(-1.0f64..1.0, 9),
        rel in 1e-9f64..1e-4,
        (t0, len) in (0.0f64..1.0, 0.0f64..0.5),
    ) {
        let mid = Mat::from_fn(3, 3, |i, j| entries[3 * i + j]);
        let rad = Mat::from_fn(3, 3, |i, j| rel * (1.0 + entries[3 * i + j].abs()));
        let a = IntervalMatrix::from_mid_rad(mid.clone(), rad.clone()).unwrap();
        let options = EnclosureOptions::default();
        let e = expm_enclosure_interval(&a, t0, t0 + len, &options).unwrap();
        let member = Mat::from_fn(3, 3, |i, j| mid[(i, j)] + corner[3 * i + j] * rad[(i, j)]);
        for tau in [t0, t0 + 0.5 * len, t0 + len] {
            for m in [&mid, &member] {
                let x = expm_dd(m, tau);
                prop_assert!(e.enclosure.contains_point(x.as_ref()), "τ = {tau}");
            }
        }
        let point = IntervalMatrix::from_point(mid.as_ref()).unwrap();
        prop_assert_eq!(
            expm_enclosure_interval(&point, t0, t0 + len, &options).unwrap(),
            expm_enclosure(mid.as_ref(), t0, t0 + len, &options).unwrap()
        );
    }
}
