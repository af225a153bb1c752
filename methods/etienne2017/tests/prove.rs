//! The rigorous prover (issue 24) and the check of given gains: the example's designs are
//! proved (Corollary 2 on [0.01, 0.2], Theorem 3 on [0.01, 0.3]) within the time target,
//! a spoiled gain is never proved, and `verify` certifies a design's own gain and certificate,
//! refuses a spoiled gain and rejects bad input with an `Err`.
//!
//! Run with `--nocapture` to see the pieces, margins and times.

use faer::{Mat, mat};
use sporadic_etienne2017::sporadic_model::{
    Gain, Lipschitz, NamedMatrix, Plant as ModelPlant, ProofOptions, ProofStatus, prove_within,
};
use sporadic_etienne2017::{
    DesignReport, Etienne2017, MethodError, MethodOptions, ObserverMethod, Sampling,
    SamplingWindow, Status, example,
};

/// The flexible-joint robot of §5 as a plant of the common contract.
fn flexible_joint() -> ModelPlant {
    example::model_plant().unwrap()
}

fn sampling(t1: f64, t2: f64) -> Sampling {
    Sampling::Synchronous(SamplingWindow::new(t1, t2).unwrap())
}

fn design(t1: f64, t2: f64) -> DesignReport {
    let r = Etienne2017::default()
        .design(
            &flexible_joint(),
            &sampling(t1, t2),
            &MethodOptions::default(),
        )
        .unwrap();
    assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
    r
}

/// The gain with every sample multiplied by `f` (`first_only`: only `K(T1)` of a schedule).
fn spoiled(g: &Gain, f: f64, first_only: bool) -> Gain {
    let scale = |rows: &Vec<Vec<f64>>| -> Vec<Vec<f64>> {
        rows.iter()
            .map(|r| r.iter().map(|x| f * x).collect())
            .collect()
    };
    let mut g = g.clone();
    match &mut g.schedule {
        Some(s) if first_only => s.samples[0] = scale(&s.samples[0]),
        Some(s) => {
            for x in &mut s.samples {
                *x = scale(x);
            }
            g.rows = s.samples.last().unwrap().clone();
        }
        None => g.rows = scale(&g.rows),
    }
    g
}

fn prove_and_print(what: &str, r: &DesignReport) -> ProofStatus {
    let p = prove_within(
        &Etienne2017::default(),
        &flexible_joint(),
        r,
        &ProofOptions::default(),
    )
    .unwrap();
    println!(
        "{what}: {} — {} pieces, margin ≥ {:?}, enclosure width {:?}, {:.4} s (design {:.4} s); {}",
        p.status,
        p.subintervals,
        p.margin_lower_bound,
        p.enclosure_width,
        p.seconds,
        r.seconds,
        p.message
    );
    if p.status == ProofStatus::Proved {
        assert!(p.margin_lower_bound.unwrap() > 0.0);
        assert!(
            p.seconds <= (10.0 * r.seconds).max(2.0),
            "{what}: the proof took {} s, the design {} s",
            p.seconds,
            r.seconds
        );
    }
    p.status
}

#[test]
fn the_examples_designs_are_proved() {
    for (t1, t2) in [(0.01, 0.2), (0.01, 0.3)] {
        let r = design(t1, t2);
        let status = prove_and_print(&format!("design on [{t1}, {t2}]"), &r);
        assert_eq!(status, ProofStatus::Proved);
    }
}

#[test]
fn a_spoiled_gain_is_never_proved() {
    for (t1, t2) in [(0.01, 0.2), (0.01, 0.3)] {
        let r = design(t1, t2);
        for (f, first_only) in [(3.0, false), (0.2, false), (2.5, true)] {
            let mut bad = r.clone();
            bad.gains[0] = spoiled(&r.gains[0], f, first_only);
            let status = prove_and_print(
                &format!(
                    "[{t1}, {t2}], K × {f}{}",
                    if first_only { " at T1" } else { "" }
                ),
                &bad,
            );
            assert_ne!(status, ProofStatus::Proved);
        }
    }
}

#[test]
fn verify_certifies_own_gains_and_refuses_spoiled_ones() {
    let m = Etienne2017::default();
    let plant = flexible_joint();
    let o = MethodOptions::default();
    for (t1, t2) in [(0.01, 0.2), (0.01, 0.3)] {
        let r = design(t1, t2);
        let s = sampling(t1, t2);
        let v = m.verify(&plant, &s, &r.gains, &r.certificate, &o).unwrap();
        assert_eq!(v.status, Status::Certified, "{:?}", v.reason);
        assert_eq!(v.gains[0].rows, r.gains[0].rows);
        // Without a certificate, LMIs (20) are solved for the fixed gain.
        let v = m.verify(&plant, &s, &r.gains, &[], &o).unwrap();
        assert_eq!(v.status, Status::Certified, "{:?}", v.reason);
        let bad = [spoiled(&r.gains[0], 3.0, false)];
        let v = m.verify(&plant, &s, &bad, &r.certificate, &o).unwrap();
        assert_eq!(v.status, Status::NotCertified, "{v:?}");
        println!("[{t1}, {t2}], K × 3: {:?}", v.reason);
    }
}

#[test]
fn verify_rejects_bad_input() {
    let m = Etienne2017::default();
    let plant = flexible_joint();
    let o = MethodOptions::default();
    let r = design(0.01, 0.2);
    let s = sampling(0.01, 0.2);
    let invalid = |gains: &[Gain], cert: &[NamedMatrix]| {
        let e = m.verify(&plant, &s, gains, cert, &o).unwrap_err();
        assert!(matches!(e, MethodError::InvalidInput { .. }), "{e}");
    };
    let mut renamed = r.gains.clone();
    renamed[0].name = "L".into();
    invalid(&renamed, &r.certificate);
    invalid(&[], &r.certificate);
    let mut short = r.gains.clone();
    short[0].rows.pop();
    invalid(&short, &r.certificate);
    let mut ragged = r.gains.clone();
    ragged[0].rows[0].push(1.0);
    invalid(&ragged, &r.certificate);
    let mut nan = r.gains.clone();
    nan[0].rows[0][0] = f64::NAN;
    invalid(&nan, &r.certificate);
    let mut cert = r.certificate.clone();
    cert[0].name = "Q".into();
    invalid(&r.gains, &cert);
    let mut cert = r.certificate.clone();
    cert[0] = NamedMatrix::new("P1", Mat::<f64>::identity(3, 3).as_ref(), "");
    invalid(&r.gains, &cert);
    let only_p1: Vec<NamedMatrix> = r.certificate[..1].to_vec();
    invalid(&r.gains, &only_p1);
    // A schedule that does not span the window.
    let tv = design(0.01, 0.3);
    let mut off = tv.gains.clone();
    off[0].schedule.as_mut().unwrap().tau[0] = 0.02;
    let e = m
        .verify(&plant, &sampling(0.01, 0.3), &off, &tv.certificate, &o)
        .unwrap_err();
    assert!(matches!(e, MethodError::InvalidInput { .. }), "{e}");
    // The prover refuses a report without its certificate.
    let mut bare = r.clone();
    bare.certificate.clear();
    let e = prove_within(&m, &plant, &bare, &ProofOptions::default()).unwrap_err();
    assert!(matches!(e, MethodError::InvalidInput { .. }), "{e}");
}

/// The example in the coordinates `x_s = diag(1, 1, 1, 1024)·x` (badly scaled units): the
/// design is made in balanced coordinates and reported in these; the proof is made in these.
#[test]
fn a_badly_scaled_plant_is_proved_in_its_own_coordinates() {
    let s = 1024.0;
    let a = mat![
        [0.0, 1.0, 0.0, 0.0],
        [-48.6, -1.25, 48.6, 0.0],
        [0.0, 0.0, 0.0, 1.0 / s],
        [19.5 * s, 0.0, -19.5 * s, 0.0],
    ];
    let b = mat![[0.0], [21.6], [0.0], [0.0]];
    let c = mat![[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]];
    let lip = Lipschitz::new(
        mat![[0.0], [0.0], [0.0], [s]].as_ref(),
        mat![[0.0, 0.0, 1.0, 0.0]].as_ref(),
        mat![[-example::GAMMA]].as_ref(),
        mat![[example::GAMMA]].as_ref(),
    )
    .unwrap();
    let plant = ModelPlant::linear(a.as_ref(), Some(b.as_ref()), c.as_ref())
        .unwrap()
        .with_lipschitz(lip)
        .unwrap()
        .named("flexible joint, x4 in 1/1024 units");
    let m = Etienne2017::default();
    let o = MethodOptions::default();
    for (t1, t2) in [(0.01, 0.2), (0.01, 0.3)] {
        let r = m.design(&plant, &sampling(t1, t2), &o).unwrap();
        assert_eq!(r.status, Status::Certified, "{:?}", r.reason);
        let p = prove_within(&m, &plant, &r, &ProofOptions::default()).unwrap();
        println!(
            "badly scaled [{t1}, {t2}]: {} — {} pieces, margin ≥ {:?}, {:.4} s (design {:.4} s)",
            p.status, p.subintervals, p.margin_lower_bound, p.seconds, r.seconds
        );
        assert_eq!(p.status, ProofStatus::Proved, "{}", p.message);
        let v = m
            .verify(&plant, &sampling(t1, t2), &r.gains, &r.certificate, &o)
            .unwrap();
        assert_eq!(v.status, Status::Certified, "{:?}", v.reason);
    }
}

/// The gains printed in the paper (§5): `verify` finds `P1, P2` for them (LMIs (20) with the
/// gain fixed) on the windows the paper states, and the result is proved; the static gain on
/// [0.01, 0.25] is not certified (the fixed-gain LMI is infeasible there).
#[test]
fn the_papers_gains_are_verified_and_proved() {
    let m = Etienne2017::default();
    let plant = flexible_joint();
    let o = MethodOptions::default();
    let k = example::paper_static_gain();
    let (k0, k1) = example::paper_tv_gains();
    let static_gain = Gain::constant("K", k.as_ref(), "");
    let w = SamplingWindow::new(0.01, 0.3).unwrap();
    let tv_gain = Gain::scheduled("K", "", "", vec![0.01, 0.155, 0.3], |t| {
        if t == w.t1() {
            k0.clone()
        } else if t == w.t2() {
            k1.clone()
        } else {
            &k0 + (t - w.t1()) / (w.t2() - w.t1()) * (&k1 - &k0)
        }
    });
    for (what, g, (t1, t2)) in [
        ("static K", &static_gain, (0.01, 0.2)),
        ("K(τ)", &tv_gain, (0.01, 0.3)),
    ] {
        let v = m
            .verify(&plant, &sampling(t1, t2), std::slice::from_ref(g), &[], &o)
            .unwrap();
        assert_eq!(v.status, Status::Certified, "{what}: {:?}", v.reason);
        let status = prove_and_print(&format!("paper's {what} on [{t1}, {t2}]"), &v);
        assert_eq!(status, ProofStatus::Proved);
    }
    let v = m
        .verify(&plant, &sampling(0.01, 0.25), &[static_gain], &[], &o)
        .unwrap();
    assert_eq!(v.status, Status::NotCertified, "{v:?}");
}
