//! The rigorous proof of Theorem 1's hypotheses (issue 24): the designs of Example 2 and of a
//! user's plant are proved for every v of their windows; a design is never proved where (12)
//! fails (a larger window than it was designed for, a spoiled gain, an indefinite P); `verify`
//! checks a user's gain with or without its P; bad input is an error.

use sporadic_ferrante2016::examples::{example1, example2};
use sporadic_ferrante2016::faer::{Mat, mat};
use sporadic_ferrante2016::sporadic_model::{
    DesignReport, Plant as ModelPlant, ProofOptions, ProofStatus, prove_within,
};
use sporadic_ferrante2016::{
    Ferrante2016, MethodOptions, ObserverMethod, Sampling, SamplingWindow, prove_condition12,
};

fn example2_plant() -> ModelPlant {
    let ex = example2().unwrap();
    ModelPlant::linear(ex.plant.a(), Some(ex.b.as_ref()), ex.plant.c())
        .unwrap()
        .named("Example 2")
}

fn design(plant: &ModelPlant, t1: f64, t2: f64) -> DesignReport {
    let s = Sampling::Synchronous(SamplingWindow::new(t1, t2).unwrap());
    let d = Ferrante2016::default()
        .design(plant, &s, &MethodOptions::default())
        .unwrap();
    assert!(d.status.is_certified(), "{:?}", d.reason);
    d
}

#[test]
fn example2_design_is_proved_on_its_whole_window() {
    let plant = example2_plant();
    let d = design(&plant, 0.2, 3.0);
    let proof = prove_within(
        &Ferrante2016::default(),
        &plant,
        &d,
        &ProofOptions::default(),
    )
    .unwrap();
    println!(
        "Example 2: {} on {} pieces, margin ≥ {:?}, enclosure width {:?}, {:.3} s (design {:.3} s)",
        proof.status,
        proof.subintervals,
        proof.margin_lower_bound,
        proof.enclosure_width,
        proof.seconds,
        d.seconds
    );
    assert_eq!(proof.status, ProofStatus::Proved, "{}", proof.message);
    let m = proof.margin_lower_bound.unwrap();
    assert!(m > 0.0);
    // The rigorous bound cannot exceed the grid value of the same scale-free margin by more
    // than the Δ-rounding (powers of two instead of diag(P)^(-1/2): within a factor 2 each way).
    let grid = d
        .checks
        .iter()
        .find(|c| c.what.starts_with("condition (12)"))
        .unwrap();
    assert!(grid.passed);
    let json = serde_json::to_value(&proof).unwrap();
    assert_eq!(json["status"], "proved");
    assert!(json["subintervals"].as_u64().unwrap() >= 1);
}

#[test]
fn example1_periodic_design_is_proved_at_its_single_interval() {
    let ex = example1().unwrap();
    let p = prove_condition12(
        &ex.plant,
        &ex.window,
        ex.l.as_ref(),
        ex.p.as_ref(),
        &ProofOptions::default(),
    )
    .unwrap();
    assert_eq!(p.status, ProofStatus::Proved, "{}", p.message);
    // (12) is (1 − L)²e² − 1 < 0 with (1 − L)e = 1 − 0.1e: the margin is 1 − (1 − 0.1e)²
    // (the paper's β ≈ 0.4698), the rigorous bound is below it and within 1e-6 of it.
    let m = p.margin_lower_bound.unwrap();
    let exact = 1.0 - (1.0 - 0.1 * std::f64::consts::E).powi(2);
    assert!(m <= exact && m > exact * (1.0 - 1e-6), "{m} vs {exact}");
    // |1 − L| < e^{-1} is (12): at L = 1 − e^{-1}·(1 + 1e-9) it fails, and the proof does
    // not say otherwise.
    let l_bad = mat![[1.0 - (1.0 + 1e-9) / std::f64::consts::E]];
    let p = prove_condition12(
        &ex.plant,
        &ex.window,
        l_bad.as_ref(),
        ex.p.as_ref(),
        &ProofOptions::default(),
    )
    .unwrap();
    assert_ne!(p.status, ProofStatus::Proved, "{}", p.message);
}

#[test]
fn a_design_is_not_proved_beyond_the_window_it_certifies() {
    // The oscillator ω = 1 measured in position is not detectable at v = π: no (P, L) satisfies
    // (12) on a window containing π, so a design for [0.1, 2.5] must not be proved on [0.1, 3.3].
    let plant = ModelPlant::linear(
        mat![[0.0, 1.0], [-1.0, 0.0]].as_ref(),
        None,
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap();
    let d = design(&plant, 0.1, 2.5);
    let ok = prove_within(
        &Ferrante2016::default(),
        &plant,
        &d,
        &ProofOptions::default(),
    )
    .unwrap();
    assert_eq!(ok.status, ProofStatus::Proved, "{}", ok.message);
    let mut wider = d.clone();
    wider.window = Some(SamplingWindow::new(0.1, 3.3).unwrap());
    let p = prove_within(
        &Ferrante2016::default(),
        &plant,
        &wider,
        &ProofOptions::default(),
    )
    .unwrap();
    assert_eq!(p.status, ProofStatus::NotProved, "{}", p.message);
    let f = p.failed_on.unwrap();
    assert!(f.tau[1] > 2.5 && f.enclosure[0] >= 0.0, "{f:?}");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 24, rng_seed: proptest::test_runner::RngSeed::Fixed(24), ..Default::default() })]

    /// Soundness: for random (A, C, L, P) and windows, a `proved` verdict implies that (12)
    /// holds at every point of a dense grid in f64 (with the f64 error allowance), and the
    /// spectral radius of e^{Av}(I − LC) is below one there.
    #[test]
    fn proved_implies_condition12_on_a_dense_grid(
        a in proptest::collection::vec(-1.5f64..1.5, 9),
        c in proptest::collection::vec(-1.0f64..1.0, 3),
        l in proptest::collection::vec(-1.0f64..1.0, 3),
        t1 in 0.05f64..0.5,
        len in 0.0f64..1.0,
    ) {
        let a = Mat::from_fn(3, 3, |i, j| a[3 * i + j]);
        let c = Mat::from_fn(1, 3, |_, j| c[j]);
        let l = Mat::from_fn(3, 1, |i, _| l[i]);
        let plant = sporadic_ferrante2016::Plant::new(a.as_ref(), c.as_ref()).unwrap();
        let w = SamplingWindow::new(t1, t1 + len).unwrap();
        // P from a discrete Lyapunov sum at the window's midpoint (a plausible but unverified P).
        let vm = t1 + 0.5 * len;
        let m = &sporadic_linalg::expm_scaled(a.as_ref(), vm).unwrap() * &plant.reset_matrix(l.as_ref()).unwrap();
        let mut p = Mat::<f64>::identity(3, 3);
        let mut term = Mat::<f64>::identity(3, 3);
        for _ in 0..60 {
            term = m.transpose() * &term * &m;
            p += &term;
        }
        let p = Mat::from_fn(3, 3, |i, j| 0.5 * (p[(i, j)] + p[(j, i)]));
        if !p.norm_max().is_finite() || p.norm_max() > 1e8 {
            return Ok(());
        }
        let o = ProofOptions { max_pieces: 256, ..ProofOptions::default() };
        let proof = prove_condition12(&plant, &w, l.as_ref(), p.as_ref(), &o).unwrap();
        if proof.status == ProofStatus::Proved {
            for k in 0..=200 {
                let v = t1 + len * k as f64 / 200.0;
                let e = sporadic_linalg::expm_scaled(a.as_ref(), v).unwrap();
                let g = &e * &plant.reset_matrix(l.as_ref()).unwrap();
                let q = g.transpose() * &p * &g - &p;
                let q = Mat::from_fn(3, 3, |i, j| 0.5 * (q[(i, j)] + q[(j, i)]));
                let lmax = sporadic_linalg::max_eigenvalue(q.as_ref()).unwrap();
                proptest::prop_assert!(lmax < 1e-12 * p.norm_max(), "v = {v}: λmax {lmax}");
            }
        }
    }
}

#[test]
fn an_indefinite_p_or_a_destabilising_gain_is_not_proved() {
    let plant = example2_plant();
    let d = design(&plant, 0.2, 3.0);
    let method = Ferrante2016::default();
    let mut bad_p = d.clone();
    for m in &mut bad_p.certificate {
        if m.name == "P" {
            m.rows[0][0] = -m.rows[0][0];
        }
    }
    let p = prove_within(&method, &plant, &bad_p, &ProofOptions::default()).unwrap();
    assert_ne!(p.status, ProofStatus::Proved, "{}", p.message);
    let mut bad_l = d.clone();
    for g in &mut bad_l.gains {
        if g.name == "L" {
            for r in &mut g.rows {
                r[0] *= 3.0;
            }
        }
    }
    let p = prove_within(&method, &plant, &bad_l, &ProofOptions::default()).unwrap();
    assert_eq!(p.status, ProofStatus::NotProved, "{}", p.message);
    assert!(p.failed_on.is_some());
}

#[test]
fn verify_checks_a_users_gain_with_and_without_its_p() {
    let plant = example2_plant();
    let d = design(&plant, 0.2, 3.0);
    let method = Ferrante2016::default();
    let s = Sampling::Synchronous(SamplingWindow::new(0.2, 3.0).unwrap());
    let o = MethodOptions::default();
    let with_p = method
        .verify(&plant, &s, &d.gains, &d.certificate, &o)
        .unwrap();
    assert!(with_p.status.is_certified(), "{:?}", with_p.reason);
    assert_eq!(with_p.gains[0].rows, d.gains[0].rows);
    let without_p = method.verify(&plant, &s, &d.gains, &[], &o).unwrap();
    assert!(without_p.status.is_certified(), "{:?}", without_p.reason);
    assert!(without_p.certificate.iter().any(|m| m.name == "P"));
    // The paper's published gain is certified on its window as well.
    let ex = example2().unwrap();
    let paper = vec![sporadic_ferrante2016::sporadic_model::Gain::constant(
        "L",
        ex.l_paper.as_ref(),
        "published",
    )];
    let r = method.verify(&plant, &s, &paper, &[], &o).unwrap();
    assert!(r.status.is_certified(), "{:?}", r.reason);
    // A spoiled gain is not certified, with the reason.
    let mut bad = d.gains.clone();
    for r in &mut bad[0].rows {
        r[0] *= 3.0;
    }
    let r = method.verify(&plant, &s, &bad, &d.certificate, &o).unwrap();
    assert!(r.status.is_not_certified());
    assert_eq!(r.reason.as_ref().unwrap().kind(), "verification_failed");
    // Bad input: a missing or mis-shaped gain, a mis-shaped P.
    assert!(method.verify(&plant, &s, &[], &[], &o).is_err());
    let mut wrong = d.gains.clone();
    wrong[0].rows.pop();
    assert!(method.verify(&plant, &s, &wrong, &[], &o).is_err());
    let mut wrong_p = d.certificate.clone();
    wrong_p[0].rows.pop();
    assert!(method.verify(&plant, &s, &d.gains, &wrong_p, &o).is_err());
    // A design's certificate carries the factor R of P = R'R; a P that disagrees with it is
    // refused, and R alone is checked as the certificate.
    assert!(d.certificate.iter().any(|m| m.name == "R"));
    let mut edited = d.certificate.clone();
    edited[0].rows[0][0] *= 1.01;
    let e = method
        .verify(&plant, &s, &d.gains, &edited, &o)
        .unwrap_err();
    assert!(e.to_string().contains("differs from R'R"), "{e}");
    let factor_only: Vec<_> = d
        .certificate
        .iter()
        .filter(|m| m.name == "R")
        .cloned()
        .collect();
    let r = method
        .verify(&plant, &s, &d.gains, &factor_only, &o)
        .unwrap();
    assert!(r.status.is_certified(), "{:?}", r.reason);
    assert!(r.certificate.iter().any(|m| m.name == "R"));
}
