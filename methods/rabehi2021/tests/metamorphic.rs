//! Issue 22: the verdict and the largest certified window of the interval observer of Rabehi et
//! al. (2021) do not depend on the user's units. For `ẋ = Ax + d`, `y = Cx + v` with
//! `|d| ≤ d̄`, `|v| ≤ v̄`:
//! * time scaling `t → t/k` gives `(kA, kd̄)` and the window `[T1, T2]/k`: the largest certified
//!   `T2` times `k` is unchanged;
//! * a change of units `x = Dz` with `D` positive diagonal gives `(D⁻¹AD, CD, D⁻¹d̄)`: the same
//!   largest `T2` (interval observers depend on the coordinates, so only positive diagonal maps,
//!   which keep the order of vectors, are required to leave the answer unchanged);
//! * output scaling `(C, v̄) → (cC, cv̄)`: the same largest `T2`;
//! * window inclusion: a certified window certifies its sub-windows.
//!
//! 1% is the tolerance; the search resolves `T2` to 0.4%.

use faer::{Mat, mat};
use sporadic_model::{Bounds, MethodOptions, ObserverMethod, Plant, Sampling, SamplingWindow};
use sporadic_rabehi2021::Rabehi2021;

/// The mass-spring-damper of the paper's §V (`m_s = k_s = c_s = 1`, `C = [2 0]`,
/// `|d_i| ≤ 1`, `|v| ≤ 0.4`).
struct Data {
    a: Mat<f64>,
    c: Mat<f64>,
    d: Vec<f64>,
    v: Vec<f64>,
}

fn example() -> Data {
    Data {
        a: mat![[0.0, 1.0], [-1.0, -1.0]],
        c: mat![[2.0, 0.0]],
        d: vec![1.0, 1.0],
        v: vec![0.4],
    }
}

fn plant(x: &Data) -> Plant {
    Plant::linear(x.a.as_ref(), None, x.c.as_ref())
        .unwrap()
        .with_bounds(Bounds::new(x.d.clone(), x.v.clone()).unwrap())
        .unwrap()
}

fn largest(x: &Data, t1: f64, limit: f64) -> f64 {
    let s = Sampling::Synchronous(SamplingWindow::new(t1, t1).unwrap());
    let r = Rabehi2021::default()
        .largest_window(&plant(x), &s, limit, &MethodOptions::default(), &mut |_| {})
        .unwrap();
    r.largest_certified_t2.expect("certified")
}

/// The plant in the units `x = diag(dg)·z`: `(D⁻¹AD, CD, D⁻¹d̄)`, the same output and noise.
fn in_units(x: &Data, dg: &[f64]) -> Data {
    let (n, p) = (x.a.nrows(), x.c.nrows());
    Data {
        a: Mat::from_fn(n, n, |i, j| x.a[(i, j)] * dg[j] / dg[i]),
        c: Mat::from_fn(p, n, |i, j| x.c[(i, j)] * dg[j]),
        d: x.d.iter().zip(dg).map(|(v, s)| v / s).collect(),
        v: x.v.clone(),
    }
}

/// Asserts that `x` as given and in the units `diag(dg)` both certify the window `(t1, t2)`.
fn certified_in_both_units(x: &Data, dg: &[f64], (t1, t2): (f64, f64)) {
    let s = Sampling::Synchronous(SamplingWindow::new(t1, t2).unwrap());
    for (what, x) in [("as given", x), ("in other units", &in_units(x, dg))] {
        let r = Rabehi2021::default()
            .design(&plant(x), &s, &MethodOptions::default())
            .unwrap();
        assert!(r.status.is_certified(), "{what}: {:?}", r.reason);
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 0.01 * a.abs().max(b.abs())
}

#[test]
fn time_scaling_scales_the_largest_window() {
    let base = largest(&example(), 0.04, 3.0);
    let k = 10.0;
    let x = example();
    let scaled = Data {
        a: &x.a * faer::Scale(k),
        d: x.d.iter().map(|v| k * v).collect(),
        ..x
    };
    let s = largest(&scaled, 0.04 / k, 3.0 / k);
    assert!(close(base, k * s), "{base} vs {}", k * s);
}

#[test]
fn units_and_output_scaling_keep_the_largest_window() {
    let base = largest(&example(), 0.04, 3.0);
    // Position in millimetres, velocity in km/s.
    let dg = [1e-3, 1e3];
    let x = example();
    let units = in_units(&x, &dg);
    let s = largest(&units, 0.04, 3.0);
    assert!(close(base, s), "units: {base} vs {s}");
    let c = 250.0;
    let out = Data {
        c: &x.c * faer::Scale(c),
        v: x.v.iter().map(|v| c * v).collect(),
        ..example()
    };
    let s = largest(&out, 0.04, 3.0);
    assert!(close(base, s), "output scaling: {base} vs {s}");
}

#[test]
fn a_certified_window_certifies_its_sub_windows() {
    let x = example();
    let t2 = largest(&x, 0.04, 3.0);
    for (a, b) in [(0.04, 0.5 * t2), (0.5 * t2, t2), (0.3 * t2, 0.31 * t2)] {
        let s = Sampling::Synchronous(SamplingWindow::new(a, b).unwrap());
        let r = Rabehi2021::default()
            .design(&plant(&x), &s, &MethodOptions::default())
            .unwrap();
        assert!(
            r.status.is_certified(),
            "[{a}, {b}] ⊂ [0.04, {t2}]: {:?}",
            r.reason
        );
    }
}

/// A DC motor (angle, speed, current; angle measured): the angle drives no other state, so `gebal`
/// has no scale for it and kept the user's unit. With the angle in mrad, the speed in 10 rad/s and
/// the current in 0.5 A, `[0.01, 1.5]` was refused after the 25 s budget (best
/// `max λmax(Ψ_i) = −1.89`, rounding bound 13.7), while the same motor in SI units certified it in
/// one LMI step. `complete_balancing_scales` now fixes the angle's scale (its coupling to the
/// speed gets the plant's slowest rate, 0.8), and both get the same balanced matrix up to powers
/// of 2.
#[test]
fn an_undriven_state_in_other_units_keeps_the_verdict() {
    let motor = Data {
        a: mat![[0.0, 1.0, 0.0], [0.0, -0.8, 4.0], [0.0, -1.5, -12.0]],
        c: mat![[1.0, 0.0, 0.0]],
        d: vec![0.0, 0.2, 0.05],
        v: vec![0.002],
    };
    certified_in_both_units(&motor, &[1e-3, 10.0, 0.5], (0.01, 1.5));
}

/// A cart (position, velocity with friction 0.2, force with a lag of rate 5; position measured):
/// the position drives nothing and no state drives the force, so the balancing left both scales
/// to the user. In SI units `[0.02, 2]` was certified; with the position in mm, the velocity in
/// units of 0.3 m/s and the force in units of 50 N not even `[0.02, 0.02]` was. The free states'
/// couplings now get the plant's slowest rate (0.2), whatever the units.
#[test]
fn a_cart_in_other_units_keeps_the_verdict() {
    let cart = Data {
        a: mat![[0.0, 1.0, 0.0], [0.0, -0.2, 1.0], [0.0, 0.0, -5.0]],
        c: mat![[1.0, 0.0, 0.0]],
        d: vec![0.0, 0.1, 0.5],
        v: vec![0.01],
    };
    certified_in_both_units(&cart, &[1e-3, 0.3, 50.0], (0.02, 2.0));
}
