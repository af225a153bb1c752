//! Issue 24: the rigorous proof of (44) over every τ of the windows, and the check of given gains
//! (`verify`).

use std::time::Instant;

use faer::mat;
use sporadic_model::{ProofOptions, ProofStatus, prove_within};
use sporadic_sferlazza2021::{
    DesignReport, MethodError, MethodOptions, ObserverMethod, Plant, RoundRobinPlant, Sampling,
    SamplingWindow, Sferlazza2021, Status, XiFamily,
};

fn win(t1: f64, t2: f64) -> SamplingWindow {
    SamplingWindow::new(t1, t2).unwrap()
}

/// The quarter car of §6 (the paper's example), round-robin over its two windows.
fn suspension() -> (Plant, Sampling) {
    sporadic_sferlazza2021::example::model_plant().unwrap()
}

/// The oscillator of the crate docs, position and velocity read in turn.
fn oscillator() -> (Plant, Sampling) {
    let a = mat![[0.0, 1.0], [-4.0, -0.2]];
    let (c1, c2) = (mat![[1.0, 0.0]], mat![[0.0, 1.0]]);
    let plant = Plant::round_robin(a.as_ref(), None, &[c1.as_ref(), c2.as_ref()]).unwrap();
    (
        plant,
        Sampling::RoundRobin(vec![win(0.1, 0.3), win(0.1, 0.3)]),
    )
}

fn designed(plant: &Plant, sampling: &Sampling) -> DesignReport {
    let r = Sferlazza2021::default()
        .design(plant, sampling, &MethodOptions::default())
        .unwrap();
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    r
}

/// Multiplies every listed value of gain `K_{sensor}` by `factor`.
fn spoil_gain(r: &mut DesignReport, sensor: usize, factor: f64) {
    let g = &mut r.gains[sensor];
    for row in &mut g.rows {
        row.iter_mut().for_each(|x| *x *= factor);
    }
    if let Some(s) = &mut g.schedule {
        for k in &mut s.samples {
            k.iter_mut().flatten().for_each(|x| *x *= factor);
        }
    }
}

/// The paper's example design is proved over the continuum of both windows, fast enough.
#[test]
fn paper_example_design_is_proved() {
    let (plant, sampling) = suspension();
    let t = Instant::now();
    let r = designed(&plant, &sampling);
    let design_s = t.elapsed().as_secs_f64();
    let m = Sferlazza2021::default();
    let p = prove_within(&m, &plant, &r, &ProofOptions::default()).unwrap();
    println!(
        "quarter car: {} on {} pieces, margin ≥ {:?} (design margin {:?}), enclosure width {:?}, \
         proof {:.3} s vs design {:.3} s; {}",
        p.status,
        p.subintervals,
        p.margin_lower_bound,
        r.margin.as_ref().map(|m| m.value),
        p.enclosure_width,
        p.seconds,
        design_s,
        p.message
    );
    assert_eq!(p.status, ProofStatus::Proved, "{}", p.message);
    // The proof runs in the user's coordinates, the design's margin is that of the balanced
    // ones: only the sign is comparable.
    assert!(p.margin_lower_bound.unwrap() > 0.0);
    assert!(p.seconds <= (10.0 * design_s).max(2.0), "{} s", p.seconds);
}

/// A small design is proved too, and its proof is not slower than a few designs.
#[test]
fn oscillator_design_is_proved() {
    let (plant, sampling) = oscillator();
    design_and_prove("oscillator", &plant, &sampling);
}

/// Designs, proves with the default options, prints the figures and asserts `proved`.
fn design_and_prove(
    what: &str,
    plant: &Plant,
    sampling: &Sampling,
) -> (DesignReport, sporadic_model::Proof) {
    let r = designed(plant, sampling);
    let p = prove_within(
        &Sferlazza2021::default(),
        plant,
        &r,
        &ProofOptions::default(),
    )
    .unwrap();
    println!(
        "{what}: {} on {} pieces, margin ≥ {:?}, width {:?}, {:.3} s (design {:.3} s)",
        p.status, p.subintervals, p.margin_lower_bound, p.enclosure_width, p.seconds, r.seconds
    );
    assert_eq!(p.status, ProofStatus::Proved, "{}", p.message);
    (r, p)
}

/// A long window: a ship-heading plant (heading measured; yaw and sway modes at −0.19 and
/// −0.71, a rudder actuator at −2.5) on [0.5, 12], where `‖e^{−12A}‖ ≈ 10¹³` and the entries
/// of `Ξ(τ)` reach 10²⁶ while its smallest eigenvalue stays of the order of `P`. The design
/// (its (48) by proof, in place of a (49) grid of 10²² points) and the proof of (44) over the
/// window both need the congruence-scaled chord test; before it the design ran out of its
/// budget and no proof succeeded within 16384 pieces.
#[test]
fn long_window_design_is_proved() {
    let a = mat![
        [0.0, 1.0, 0.0, 0.0],
        [0.0, -0.3, 0.05, 0.2],
        [0.0, 0.8, -0.6, 0.4],
        [0.0, 0.0, 0.0, -2.5]
    ];
    let c = mat![[1.0, 0.0, 0.0, 0.0]];
    let plant = Plant::round_robin(a.as_ref(), None, &[c.as_ref()]).unwrap();
    let sampling = Sampling::RoundRobin(vec![win(0.5, 12.0)]);
    let (r, p) = design_and_prove("ship heading", &plant, &sampling);
    let margin = p.margin_lower_bound.unwrap();
    assert!(margin > 0.0);
    // The proven margin bounds min_τ λ_min(Ξ(τ))/λ_max(P) from below: compare with floating
    // point on the short end of the window, where λ_min is smallest and Ξ is well scaled.
    let p1 = r.certificate[0].to_mat();
    let rr = RoundRobinPlant::new(a.as_ref(), &[(c.as_ref(), win(0.5, 12.0))]).unwrap();
    let fam = XiFamily::new(&rr, std::slice::from_ref(&p1), 0).unwrap();
    let p_max = sporadic_linalg::max_eigenvalue(p1.as_ref()).unwrap();
    let grid_min = (0..=50)
        .map(|k| fam.min_eigenvalue(0.5 + 0.03 * k as f64).unwrap())
        .fold(f64::INFINITY, f64::min);
    assert!(
        margin <= grid_min / p_max,
        "{margin} > {}",
        grid_min / p_max
    );
}

/// Spoiled gains (the jump map of sensor 1 scaled by 3, unstable) and a spoiled certificate
/// (P_2 scaled by 20, so (44) fails for sensor 1) are never proved.
#[test]
fn spoiled_designs_are_never_proved() {
    let (plant, sampling) = oscillator();
    let m = Sferlazza2021::default();
    let r = designed(&plant, &sampling);
    let mut bad = r.clone();
    spoil_gain(&mut bad, 0, 3.0);
    let p = prove_within(&m, &plant, &bad, &ProofOptions::default()).unwrap();
    println!("spoiled gain: {} — {}", p.status, p.message);
    assert_eq!(p.status, ProofStatus::NotProved);
    assert!(p.failed_on.is_some());
    let mut bad = r.clone();
    let p2 = &mut bad.certificate[1];
    p2.rows.iter_mut().flatten().for_each(|x| *x *= 20.0);
    let p = prove_within(&m, &plant, &bad, &ProofOptions::default()).unwrap();
    println!("spoiled certificate: {} — {}", p.status, p.message);
    assert_ne!(p.status, ProofStatus::Proved);
}

/// `verify` certifies a design's own gains and certificate, refuses spoiled gains, and rejects
/// gains or certificates of the wrong names or shapes.
#[test]
fn verify_own_spoiled_and_bad_input() {
    let (plant, sampling) = oscillator();
    let m = Sferlazza2021::default();
    let o = MethodOptions::default();
    let r = designed(&plant, &sampling);
    let v = m
        .verify(&plant, &sampling, &r.gains, &r.certificate, &o)
        .unwrap();
    assert_eq!(v.status, Status::Certified, "{:?}", v.reason);
    assert!(v.margin.unwrap().value > 0.0);
    let mut bad = r.clone();
    spoil_gain(&mut bad, 1, 0.5);
    let v = m
        .verify(&plant, &sampling, &bad.gains, &bad.certificate, &o)
        .unwrap();
    assert_eq!(v.status, Status::NotCertified);
    println!("spoiled gains: {:?}", v.reason);
    // Wrong names.
    let mut renamed = r.gains.clone();
    renamed[0].name = "L".into();
    assert!(matches!(
        m.verify(&plant, &sampling, &renamed, &r.certificate, &o),
        Err(MethodError::InvalidInput { .. })
    ));
    let mut cert = r.certificate.clone();
    cert[1].name = "Q".into();
    assert!(matches!(
        m.verify(&plant, &sampling, &r.gains, &cert, &o),
        Err(MethodError::InvalidInput { .. })
    ));
    // Wrong shapes.
    let mut short = r.gains.clone();
    short[0].rows.pop();
    if let Some(s) = &mut short[0].schedule {
        s.samples.iter_mut().for_each(|k| {
            k.pop();
        });
    }
    assert!(matches!(
        m.verify(&plant, &sampling, &short, &r.certificate, &o),
        Err(MethodError::InvalidInput { .. })
    ));
    let mut cert = r.certificate.clone();
    cert[0].rows.pop();
    assert!(matches!(
        m.verify(&plant, &sampling, &r.gains, &cert, &o),
        Err(MethodError::InvalidInput { .. })
    ));
    // A report of another method, or without its certificate, is bad input for the prover.
    let mut other = r.clone();
    other.method = "ferrante2016".into();
    assert!(matches!(
        m.prove(&plant, &other, &ProofOptions::default()),
        Err(MethodError::InvalidInput { .. })
    ));
    let mut uncertified = r.clone();
    uncertified.certificate.clear();
    assert!(matches!(
        m.prove(&plant, &uncertified, &ProofOptions::default()),
        Err(MethodError::InvalidInput { .. })
    ));
}

/// A sensor that measures the whole state (`m_σ = n`, no kernel): (44) is `P_Γ ≻ 0`, proved on
/// one piece per window; a periodic window is one point.
#[test]
fn full_state_sensor_and_periodic_window_are_proved() {
    let plant = Plant::linear(mat![[-1.0]].as_ref(), None, mat![[1.0]].as_ref()).unwrap();
    let m = Sferlazza2021::default();
    for sampling in [
        Sampling::Synchronous(win(0.1, 1.0)),
        Sampling::Synchronous(SamplingWindow::periodic(0.5).unwrap()),
    ] {
        let r = designed(&plant, &sampling);
        let p = prove_within(&m, &plant, &r, &ProofOptions::default()).unwrap();
        assert_eq!(p.status, ProofStatus::Proved, "{}", p.message);
    }
    let (plant, _) = oscillator();
    let periodic = SamplingWindow::periodic(0.2).unwrap();
    let sampling = Sampling::RoundRobin(vec![periodic, periodic]);
    let r = designed(&plant, &sampling);
    let p = prove_within(&m, &plant, &r, &ProofOptions::default()).unwrap();
    assert_eq!(p.status, ProofStatus::Proved, "{}", p.message);
    assert_eq!(p.subintervals, 2);
}
