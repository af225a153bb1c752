//! Issue 22, "any plant, any window": a stable plant stays certified on windows `[1, T2]` up to
//! `T2 = 10³⁰⁸` (LMI (41) of Ferrante et al. 2016 over the residue box of §4.1 is feasible for
//! every `T2`: the box of a decaying real mode over `[T1, T2]` lies in the one over `[T1, ∞)`),
//! the grid check of (12) looks where `e^{Av}` varies, the rigorous proof covers the tail beyond
//! the decay of every mode at once, and an unstable plant's verdicts do not change.

use std::time::Instant;

use sporadic_ferrante2016::faer::{Mat, mat};
use sporadic_ferrante2016::sporadic_model::{ProofOptions, ProofStatus};
use sporadic_ferrante2016::{
    Design, DesignOptions, Error, Plant, SamplingWindow, VerifyOptions, design, prove_condition12,
    verify,
};

/// The plant of the issue: `λ = −1, −2`, the slow state measured.
fn stable() -> Plant {
    Plant::new(
        mat![[-1.0, 0.5], [0.0, -2.0]].as_ref(),
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap()
}

/// The same with the measured mode unstable (`λ = +1`).
fn unstable() -> Plant {
    Plant::new(
        mat![[1.0, 0.5], [0.0, -2.0]].as_ref(),
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap()
}

fn run(p: &Plant, t1: f64, t2: f64) -> (Result<Design, Error>, f64) {
    let start = Instant::now();
    let w = SamplingWindow::new(t1, t2).unwrap();
    let r = design(p, &w, &DesignOptions::default());
    (r, start.elapsed().as_secs_f64())
}

#[test]
fn stable_plant_is_certified_on_every_long_window() {
    for t2 in [1e3, 1e15, 1e20, 1e100, 1e300, 1e308] {
        let (r, seconds) = run(&stable(), 1.0, t2);
        let d = r.unwrap_or_else(|e| panic!("T2 = {t2}: {e}"));
        assert!(seconds < 10.0, "T2 = {t2}: {seconds} s");
        // The worst v of (12) is near T1 (where e^{Av} is largest), found by the grid.
        assert!(
            d.verification.max_eigenvalue_at < 50.0,
            "T2 = {t2}: worst at {}",
            d.verification.max_eigenvalue_at
        );
        assert!(d.verification.relative_max_eigenvalue < -0.1, "T2 = {t2}");
    }
}

/// The certificate on `[1, 10¹⁵]` is proved rigorously for every `v`, the tail beyond the decay
/// of every mode in one piece.
#[test]
fn long_window_design_is_proved() {
    for t2 in [1e15, 1e300] {
        let p = stable();
        let w = SamplingWindow::new(1.0, t2).unwrap();
        let d = design(&p, &w, &DesignOptions::default()).unwrap();
        let start = Instant::now();
        let proof = prove_condition12(
            &p,
            &w,
            d.l.as_ref(),
            d.certificate.p.as_ref(),
            &ProofOptions::default(),
        )
        .unwrap();
        assert_eq!(proof.status, ProofStatus::Proved, "{}", proof.message);
        assert!(proof.margin_lower_bound.is_some_and(|m| m > 0.0));
        assert!(start.elapsed().as_secs_f64() < 10.0);
    }
}

/// A `P` for which (12) fails near `T1` is never proved on a long window.
#[test]
fn long_window_proof_is_not_fooled() {
    let p = stable();
    let w = SamplingWindow::new(0.01, 1e15).unwrap();
    // L = 0, P = diag(1, 10⁻⁴): from x = (0, 1), e^{Av}x has the first component
    // (e^{−v} − e^{−2v})/2 (0.12 at v = 1), so x'(e^{A'v}Pe^{Av} − P)x ≈ 0.0136 > 0 there.
    let bad = mat![[1.0, 0.0], [0.0, 1e-4]];
    let l = Mat::<f64>::zeros(2, 1);
    let proof =
        prove_condition12(&p, &w, l.as_ref(), bad.as_ref(), &ProofOptions::default()).unwrap();
    assert_ne!(proof.status, ProofStatus::Proved, "{}", proof.message);
}

/// The grid check of (12) on `[0.01, 10¹⁵]` finds the violation near `v = 1` (an equally
/// spaced grid has its second point at `3.6·10¹¹`).
#[test]
fn long_window_grid_finds_a_violation_near_t1() {
    let w = SamplingWindow::new(0.01, 1e15).unwrap();
    let bad = mat![[1.0, 0.0], [0.0, 1e-4]];
    let l = Mat::<f64>::zeros(2, 1);
    let v = verify(
        &stable(),
        &w,
        l.as_ref(),
        bad.as_ref(),
        &VerifyOptions::default(),
    )
    .unwrap();
    assert!(!v.condition12_holds, "{v:?}");
    assert!(
        v.max_eigenvalue_at > 0.1 && v.max_eigenvalue_at < 10.0,
        "{v:?}"
    );
}

/// The unstable plant: certified on a short window as before, refused on long ones.
#[test]
fn unstable_plant_verdicts_are_unchanged() {
    let (r, _) = run(&unstable(), 0.1, 0.5);
    assert!(r.is_ok(), "{:?}", r.err());
    for t2 in [1e3, 1e15, 1e300] {
        let (r, seconds) = run(&unstable(), 1.0, t2);
        assert!(r.is_err(), "T2 = {t2}");
        assert!(seconds < 10.0);
    }
}

/// Time scaling `(A, [T1, T2]) → (kA, [T1/k, T2/k])` on a long window: the same verdict.
#[test]
fn long_window_time_scaling() {
    let p = stable();
    for k in [1e-3, 7.0, 1e4] {
        let a = Mat::from_fn(2, 2, |i, j| k * p.a()[(i, j)]);
        let scaled = Plant::new(a.as_ref(), p.c()).unwrap();
        let (r, _) = run(&scaled, 1.0 / k, 1e15 / k);
        assert!(r.is_ok(), "k = {k}: {:?}", r.err());
    }
}

/// Issue 22: a lightly damped oscillator (`A = [[0, 1], [−1, −0.01]]`, position measured) on
/// `[0.1, T2]` up to the largest double is certified within 10 s. The residue box of §4.1 is
/// the same for every `T2` beyond the decay of both modes, and so is the certificate; the
/// embedding's self-check used to step an equally spaced grid of the whole window, whose step
/// `e^{Ah}` overflowed for `T2` above about `10¹⁷` (a numerical failure instead of a verdict).
#[test]
fn lightly_damped_oscillator_up_to_the_largest_double() {
    let p = Plant::new(
        mat![[0.0, 1.0], [-1.0, -0.01]].as_ref(),
        mat![[1.0, 0.0]].as_ref(),
    )
    .unwrap();
    for t2 in [1e15, 1e17, 1e18, 1e30, 1e100, 1e300, 1e308, f64::MAX] {
        let (r, seconds) = run(&p, 0.1, t2);
        let d = r.unwrap_or_else(|e| panic!("T2 = {t2:e}: {e}"));
        assert!(d.embedding.containment().is_guaranteed(), "T2 = {t2:e}");
        assert!(d.verification.passed(), "T2 = {t2:e}");
        assert!(seconds < 10.0, "T2 = {t2:e}: {seconds} s");
    }
}
