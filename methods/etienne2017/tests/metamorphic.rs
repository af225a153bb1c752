//! Issue 22: the verdict and the largest certified window of Etienne et al. (2017) do not depend
//! on the user's units or coordinates. For `ẋ = Ax + Gφ(Hx)`, `y = Cx` with Jacobian bounds on
//! `φ`:
//! * time scaling `t → t/k` gives `(kA, kG)` with the same `H`, `C` and bounds, and the window
//!   `[T1, T2]/k`: the largest certified `T2` times `k` is unchanged;
//! * a state similarity `x = Tz` gives `(T⁻¹AT, T⁻¹G, HT, CT)`: the same largest `T2`;
//! * output scaling `C → cC` changes nothing but the gain;
//! * window inclusion: a certified window certifies its sub-windows.
//!
//! The plants are the flexible-joint robot of the paper's §5 and a pendulum-like plant of order 2
//! that nobody tuned for. 1% is the tolerance; the search resolves `T2` to 0.4%.

use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef, mat};
use proptest::prelude::*;
use sporadic_etienne2017::sporadic_model::{
    Lipschitz, Plant as ModelPlant, ProofOptions, ProofStatus, prove_within,
};
use sporadic_etienne2017::{
    Etienne2017, MethodOptions, ObserverMethod, Sampling, SamplingWindow, example,
};

struct Data {
    a: Mat<f64>,
    g: Mat<f64>,
    h: Mat<f64>,
    c: Mat<f64>,
    gamma: f64,
}

fn flexible_joint() -> Data {
    Data {
        a: mat![
            [0.0, 1.0, 0.0, 0.0],
            [-48.6, -1.25, 48.6, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [19.5, 0.0, -19.5, 0.0],
        ],
        g: mat![[0.0], [0.0], [0.0], [1.0]],
        h: mat![[0.0, 0.0, 1.0, 0.0]],
        c: mat![[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]],
        gamma: example::GAMMA,
    }
}

/// `θ'' = −0.5 θ' − 2 sin θ`-like plant with the position measured: `φ(θ) = sin θ`, `|φ'| ≤ 2`
/// entering through the velocity equation.
fn pendulum() -> Data {
    Data {
        a: mat![[0.0, 1.0], [0.0, -0.5]],
        g: mat![[0.0], [1.0]],
        h: mat![[1.0, 0.0]],
        c: mat![[1.0, 0.0]],
        gamma: 2.0,
    }
}

fn plant(d: &Data) -> ModelPlant {
    let lip = Lipschitz::new(
        d.g.as_ref(),
        d.h.as_ref(),
        mat![[-d.gamma]].as_ref(),
        mat![[d.gamma]].as_ref(),
    )
    .unwrap();
    ModelPlant::linear(d.a.as_ref(), None, d.c.as_ref())
        .unwrap()
        .with_lipschitz(lip)
        .unwrap()
}

fn scaled(d: &Data, k: f64) -> Data {
    Data {
        a: &d.a * faer::Scale(k),
        g: &d.g * faer::Scale(k),
        h: d.h.clone(),
        c: d.c.clone(),
        gamma: d.gamma,
    }
}

fn similar(d: &Data, t: MatRef<'_, f64>) -> Data {
    let tinv = t
        .full_piv_lu()
        .solve(Mat::<f64>::identity(t.nrows(), t.nrows()));
    Data {
        a: &tinv * &d.a * t,
        g: &tinv * &d.g,
        h: &d.h * t,
        c: &d.c * t,
        gamma: d.gamma,
    }
}

/// The largest certified `T2 ≤ limit` with `T1` fixed (`None`: nothing certified).
fn largest(d: &Data, t1: f64, limit: f64) -> Option<f64> {
    largest_of(&plant(d), t1, limit)
}

/// [`largest`] for a plant.
fn largest_of(p: &ModelPlant, t1: f64, limit: f64) -> Option<f64> {
    let s = Sampling::Synchronous(SamplingWindow::new(t1, t1).unwrap());
    let r = Etienne2017::default()
        .largest_window(p, &s, limit, &MethodOptions::default(), &mut |_| {})
        .unwrap();
    r.largest_certified_t2
}

fn certified(d: &Data, t1: f64, t2: f64) -> bool {
    let s = Sampling::Synchronous(SamplingWindow::new(t1, t2).unwrap());
    Etienne2017::default()
        .design(&plant(d), &s, &MethodOptions::default())
        .unwrap()
        .status
        .is_certified()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 0.01 * a.abs().max(b.abs())
}

#[test]
fn time_scaling_scales_the_largest_window() {
    for (d, t1, limit) in [(flexible_joint(), 0.01, 1.0), (pendulum(), 0.05, 5.0)] {
        let base = largest(&d, t1, limit).expect("certified");
        for k in [0.1, 8.0] {
            let s = largest(&scaled(&d, k), t1 / k, limit / k).expect("certified");
            assert!(close(base, k * s), "k = {k}: {base} vs {} (= {s}·k)", k * s);
        }
    }
}

/// A motor-driven pendulum in s and in units 1000 times shorter (and 10⁴ times longer):
/// before (20a)/(20b) were scaled by τ̄, `t*` stayed at the jump blocks' `1.19e-5` in the short
/// unit while the threshold grew with `‖R_p‖`, `1/τ̄` to `8.7e-4` (refused), and in the long
/// unit `t* = 9.4e-8` fell below `2.1e-7` (refused).
#[test]
fn the_margin_does_not_depend_on_the_time_unit() {
    let d = Data {
        a: mat![[0.0, 1.0, 0.0], [0.0, -0.2, 4.0], [0.0, -0.5, -10.0]],
        g: mat![[0.0], [-20.0], [0.0]],
        h: mat![[1.0, 0.0, 0.0]],
        c: mat![[1.0, 0.0, 0.0]],
        gamma: 1.0,
    };
    let margin = |k: f64| {
        let s = Sampling::Synchronous(SamplingWindow::new(0.005 / k, 0.1 / k).unwrap());
        let r = Etienne2017::default()
            .design(&plant(&scaled(&d, k)), &s, &MethodOptions::default())
            .unwrap();
        assert!(r.status.is_certified(), "k = {k}: {:?}", r.reason);
        r.margin.unwrap().value
    };
    let base = margin(1.0);
    for k in [1e-4, 1e3] {
        let m = margin(k);
        assert!(close(base, m), "k = {k}: {base} vs {m}");
    }
}

#[test]
fn output_scaling_changes_nothing_but_the_gain() {
    let d = flexible_joint();
    let base = largest(&d, 0.01, 1.0).unwrap();
    for c in [1e-3, 1e3] {
        let mut e = flexible_joint();
        e.c = &e.c * faer::Scale(c);
        let s = largest(&e, 0.01, 1.0).unwrap();
        assert!(close(base, s), "c = {c}: {base} vs {s}");
    }
}

#[test]
fn a_certified_window_certifies_its_sub_windows() {
    let d = flexible_joint();
    let t2 = largest(&d, 0.01, 1.0).unwrap();
    for (a, b) in [(0.01, 0.5 * t2), (0.5 * t2, t2), (0.3 * t2, 0.31 * t2)] {
        assert!(certified(&d, a, b), "[{a}, {b}] ⊂ [0.01, {t2}]");
    }
}

/// The flexible-joint robot with its states in odd units (`x = Dz`, `D` spanning five decades):
/// before the design moved to balanced coordinates nothing was certified (LMIs (20) not strictly
/// feasible even at T1), against 0.3416 in SI units.
#[test]
fn odd_units_of_the_flexible_joint_keep_the_largest_window() {
    let d = flexible_joint();
    let base = largest(&d, 0.01, 1.0).unwrap();
    let units = Mat::from_fn(4, 4, |i, j| {
        if i == j {
            [1e-3, 1e2, 3e-2, 10.0][i]
        } else {
            0.0
        }
    });
    let s = largest(&similar(&d, units.as_ref()), 0.01, 1.0).expect("certified in odd units");
    assert!(close(base, s), "{base} vs {s}");
}

/// Found by the property below on the code before the design moved to balanced coordinates:
/// units `D = diag(8.332, 0.1524)` gave 0.3652 against 0.3714 (1.7%).
#[test]
fn a_change_of_units_keeps_the_largest_window() {
    let d = pendulum();
    let base = largest(&d, 0.05, 5.0).unwrap();
    let units = mat![[8.33202294606219, 0.0], [0.0, 0.15244238550923062]];
    let s = largest(&similar(&d, units.as_ref()), 0.05, 5.0).unwrap();
    assert!(close(base, s), "{base} vs {s}");
}

proptest! {
    // A fixed seed: the same transformations on every run.
    #![proptest_config(ProptestConfig {
        cases: 6,
        rng_seed: proptest::test_runner::RngSeed::Fixed(22),
        ..ProptestConfig::default()
    })]

    /// Well-conditioned random `T = I + U(−0.4, 0.4)` (condition number below 10), and a
    /// diagonal unit change spanning three decades.
    #[test]
    fn similarity_keeps_the_largest_window(
        entries in proptest::collection::vec(-0.4f64..0.4, 4),
        decades in proptest::collection::vec(-1.5f64..1.5, 2),
    ) {
        let d = pendulum();
        let base = largest(&d, 0.05, 5.0).unwrap();
        let t = Mat::from_fn(2, 2, |i, j| f64::from(u8::from(i == j)) + entries[2 * i + j]);
        let s = largest(&similar(&d, t.as_ref()), 0.05, 5.0).unwrap();
        prop_assert!(close(base, s), "T = {t:?}: {base} vs {s}");
        let diag = Mat::from_fn(2, 2, |i, j| if i == j { 10f64.powf(decades[i]) } else { 0.0 });
        let s = largest(&similar(&d, diag.as_ref()), 0.05, 5.0).unwrap();
        prop_assert!(close(base, s), "D = {diag:?}: {base} vs {s}");
    }
}

/// A reactor with a saturating feedback written for this check (order 3, one output):
/// `ẋ1 = x2`, `ẋ2 = −x1 − 0.5x2 + 2φ(x3)`, `ẋ3 = x1 − 2x3`, `φ = tanh` (`φ' ∈ [0, 1]`),
/// `y = x1`, in the coordinates `x = Tz` given by `t` (the identity: as written).
fn reactor(t: MatRef<'_, f64>) -> ModelPlant {
    let tinv = t.full_piv_lu().solve(Mat::<f64>::identity(3, 3));
    let a = mat![[0.0, 1.0, 0.0], [-1.0, -0.5, 0.0], [1.0, 0.0, -2.0]];
    let (g, h, c) = (
        mat![[0.0], [2.0], [0.0]],
        mat![[0.0, 0.0, 1.0]],
        mat![[1.0, 0.0, 0.0]],
    );
    let lip = Lipschitz::new(
        (&tinv * &g).as_ref(),
        (&h * t).as_ref(),
        mat![[0.0]].as_ref(),
        mat![[1.0]].as_ref(),
    )
    .unwrap();
    ModelPlant::linear((&tinv * &a * t).as_ref(), None, (&c * t).as_ref())
        .unwrap()
        .with_lipschitz(lip)
        .unwrap()
}

/// The reactor certified `T2` up to 4.8338 as written and 4.7750 in coordinates `x = Tz`
/// (`κ(T) < 10`), 1.2 % apart: the margin `t*` of (20) is measured in the coordinates of the
/// solve, and in these it fell below the verification threshold first (`t* = 3.6·10⁻⁷` against
/// `5.9·10⁻⁷` at `T2 = 4.8`). A positive margin below the threshold is now solved once more in
/// the coordinates of its own certificate (`crate::coordinates`): both reach 4.835 (0.01 %
/// apart), and so does the reactor in coordinates whose units span two decades. The design at
/// `[0.01, 4.8]` in `x = Tz`, made in those coordinates and mapped back,
/// passes `verify` and is proved in interval arithmetic on the plant as given.
#[test]
fn a_reactor_keeps_its_largest_window_in_other_coordinates() {
    let t = mat![[1.0, 0.5, -0.3], [0.2, 1.0, 0.4], [-0.1, 0.3, 1.0]];
    let reach = |p: &ModelPlant| largest_of(p, 0.01, 20.0).expect("certified");
    let written = reach(&reactor(Mat::<f64>::identity(3, 3).as_ref()));
    let other = reach(&reactor(t.as_ref()));
    assert!(close(written, other), "{written} vs {other}");
    assert!(other > 4.8, "{other}");
    // Units spanning two decades on top of a mixing (`κ(T) = 110`): 4.748 before (1.8 %).
    let units = mat![
        [0.10160008497588109, 1.8368234066807025, -1.1052033255939753],
        [0.04583771004758763, 4.739695815585673, 1.2035324460326529],
        [-0.01336548994791684, 1.8504680707463743, 3.48542255073102]
    ];
    let mixed = reach(&reactor(units.as_ref()));
    assert!(close(written, mixed), "{written} vs {mixed}");

    let (m, plant) = (Etienne2017::default(), reactor(t.as_ref()));
    let s = Sampling::Synchronous(SamplingWindow::new(0.01, 4.8).unwrap());
    let r = m.design(&plant, &s, &MethodOptions::default()).unwrap();
    assert!(r.status.is_certified(), "{:?}", r.reason);
    assert!(
        r.notes
            .iter()
            .any(|n| n.contains("coordinates of the certificate")),
        "{:?}",
        r.notes
    );
    let checked = m
        .verify(
            &plant,
            &s,
            &r.gains,
            &r.certificate,
            &MethodOptions::default(),
        )
        .unwrap();
    assert!(checked.status.is_certified(), "{:?}", checked.reason);
    let proof = prove_within(&m, &plant, &r, &ProofOptions::default()).unwrap();
    assert_eq!(proof.status, ProofStatus::Proved, "{}", proof.message);
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 4,
        rng_seed: proptest::test_runner::RngSeed::Fixed(23),
        ..ProptestConfig::default()
    })]

    /// The reactor in random coordinates `x = (I + U(−0.4, 0.4))·diag(10^U(−1.5, 1.5)) z`: the
    /// largest window within 1 % of the one as written. (One draw of this kind, made outside
    /// the test, gave 4.748 against 4.834 before the design in the coordinates of its own
    /// certificate, and is in the test above; the four draws of this seed passed before too.)
    #[test]
    fn the_reactor_keeps_its_largest_window_under_similarity(
        entries in proptest::collection::vec(-0.4f64..0.4, 9),
        decades in proptest::collection::vec(-1.5f64..1.5, 3),
    ) {
        let reach = |t: MatRef<'_, f64>| largest_of(&reactor(t), 0.01, 20.0).expect("certified");
        let base = reach(Mat::<f64>::identity(3, 3).as_ref());
        let t = Mat::from_fn(3, 3, |i, j| {
            (f64::from(u8::from(i == j)) + entries[3 * i + j]) * 10f64.powf(decades[j])
        });
        let other = reach(t.as_ref());
        prop_assert!(close(base, other), "T = {t:?}: {base} vs {other}");
    }
}
