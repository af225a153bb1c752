//! Jitter-free theory (§4) on random plants: Propositions 1, 3, 4 and Theorem 2 as properties.

use faer::{Mat, mat};
use proptest::prelude::*;
use sporadic_linalg::spectral_radius;
use sporadic_sdp::lmi::{FeasibilityOptions, Outcome};
use sporadic_sferlazza2021::SamplingWindow;
use sporadic_sferlazza2021::detectability::{DetectabilityOptions, pbh};
use sporadic_sferlazza2021::gain::gain;
use sporadic_sferlazza2021::jitter_free::{
    analysis_feasibility, design, design_feasibility, intervals, monodromy,
};
use sporadic_sferlazza2021::plant::RoundRobinPlant;
use sporadic_sferlazza2021::synthesis::default_solve_options;

fn options() -> FeasibilityOptions {
    let mut o = FeasibilityOptions::default();
    o.solve = default_solve_options();
    o
}

/// A random orthogonal matrix (Q factor of a random matrix).
fn orthogonal(n: usize, v: &[f64]) -> Mat<f64> {
    let g = Mat::from_fn(n, n, |i, j| {
        v[(i * n + j) % v.len()] + if i == j { 2.0 } else { 0.0 }
    });
    g.qr().compute_Q()
}

/// Random plant with `n` states and `N` scalar sensors, optionally with an unstable mode that no sensor
/// sees (then undetectable for every T), hidden by an orthogonal change of coordinates.
fn random_plant(
    n: usize,
    ns: usize,
    av: &[f64],
    cv: &[f64],
    qv: &[f64],
    t: &[f64],
    hidden: Option<f64>,
) -> RoundRobinPlant {
    let mut a = Mat::from_fn(n, n, |i, j| av[(i * n + j) % av.len()]);
    let mut cs: Vec<Mat<f64>> = (0..ns)
        .map(|s| Mat::from_fn(1, n, |_, j| cv[(s * n + j) % cv.len()]))
        .collect();
    if let Some(a11) = hidden {
        for i in 1..n {
            a[(i, 0)] = 0.0;
        }
        a[(0, 0)] = a11;
        for c in &mut cs {
            c[(0, 0)] = 0.0;
            if c.norm_max() < 0.2 {
                c[(0, 1)] = 1.0;
            }
        }
    }
    let q = orthogonal(n, qv);
    let a = q.transpose() * &a * &q;
    let cs: Vec<Mat<f64>> = cs.into_iter().map(|c| &c * &q).collect();
    let sensors: Vec<_> = cs
        .iter()
        .zip(t)
        .map(|(c, &ti)| (c.as_ref(), SamplingWindow::periodic(ti).unwrap()))
        .collect();
    RoundRobinPlant::new(a.as_ref(), &sensors).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// Proposition 4 + Theorem 2: (23) is strictly feasible iff (C, e^{AT}) is detectable (PBH), and then
    /// the gains (24) make the monodromy J_1 Schur. With a hidden unstable mode, (23) is infeasible and
    /// ρ(J_1) > 1 for any gains.
    #[test]
    fn design_lmi_feasible_iff_detectable(
        n in 2usize..4,
        ns in 2usize..4,
        av in proptest::collection::vec(-1.5f64..1.5, 9),
        cv in proptest::collection::vec(-1.0f64..1.0, 9),
        qv in proptest::collection::vec(-1.0f64..1.0, 9),
        kv in proptest::collection::vec(-1.0f64..1.0, 9),
        t in proptest::collection::vec(0.1f64..0.6, 3),
        hide in proptest::option::of(0.1f64..0.8),
    ) {
        let plant = random_plant(n, ns, &av, &cv, &qv, &t[..ns], hide);
        let chk = pbh(&plant, &t[..ns], &DetectabilityOptions::default()).unwrap();
        let margin = chk.test.worst.map_or(f64::INFINITY, |w| w.margin);
        // Skip numerically ambiguous instances (PBH margin in the grey zone).
        prop_assume!(!(1e-10..=1e-2).contains(&margin));
        let (sol, p) = design_feasibility(&plant, &options()).unwrap();
        if chk.test.detectable {
            prop_assert_eq!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
            let tt = intervals(&plant).unwrap();
            let gains: Vec<Mat<f64>> = (0..ns)
                .map(|s| gain(&plant, s, sol.value(&p[s]).unwrap().as_ref(), tt[s]).unwrap())
                .collect();
            let rho = spectral_radius(monodromy(&plant, &gains, &tt).unwrap().as_ref()).unwrap();
            prop_assert!(rho < 1.0, "ρ(J_1) = {rho}");
        } else {
            prop_assert!(hide.is_some(), "random plant unexpectedly undetectable");
            prop_assert_ne!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
            let tt = intervals(&plant).unwrap();
            let gains: Vec<Mat<f64>> = (0..ns).map(|s| Mat::from_fn(n, 1, |i, _| kv[(s * n + i) % kv.len()])).collect();
            let rho = spectral_radius(monodromy(&plant, &gains, &tt).unwrap().as_ref()).unwrap();
            prop_assert!(rho > 1.0, "ρ(J_1) = {rho} with an unobservable unstable mode");
        }
    }

    /// Proposition 3: for given gains, the analysis LMI (18) is feasible iff ρ(J_1) < 1.
    #[test]
    fn analysis_lmi_feasible_iff_schur(
        n in 2usize..4,
        av in proptest::collection::vec(-1.0f64..1.0, 9),
        cv in proptest::collection::vec(-1.0f64..1.0, 9),
        qv in proptest::collection::vec(-1.0f64..1.0, 9),
        kv in proptest::collection::vec(-1.5f64..1.5, 9),
        t in proptest::collection::vec(0.1f64..0.5, 2),
    ) {
        let plant = random_plant(n, 2, &av, &cv, &qv, &t, None);
        let gains: Vec<Mat<f64>> = (0..2).map(|s| Mat::from_fn(n, 1, |i, _| kv[(s * n + i) % kv.len()])).collect();
        let rho = spectral_radius(monodromy(&plant, &gains, &t).unwrap().as_ref()).unwrap();
        prop_assume!((rho - 1.0).abs() > 0.05);
        let sol = analysis_feasibility(&plant, &gains, &options()).unwrap();
        if rho < 1.0 {
            prop_assert_eq!(sol.outcome, Outcome::Feasible, "ρ = {}: {}", rho, sol.reason);
        } else {
            prop_assert_ne!(sol.outcome, Outcome::Feasible, "ρ = {}: {}", rho, sol.reason);
        }
    }
}

/// the harmonic oscillator sampled at half its period is undetectable, and (23) (in the
/// form (47)) is infeasible.
#[test]
fn oscillator_at_half_period_design_is_infeasible() {
    let w = 3.0;
    let plant = RoundRobinPlant::new(
        mat![[0.0, w], [-w, 0.0]].as_ref(),
        &[(
            mat![[1.0, 0.0]].as_ref(),
            SamplingWindow::periodic(std::f64::consts::PI / w).unwrap(),
        )],
    )
    .unwrap();
    let err = design(&plant, 0.01, &default_solve_options()).unwrap_err();
    assert!(
        matches!(err, sporadic_sferlazza2021::Error::Infeasible { .. }),
        "{err}"
    );
    let (sol, _) = design_feasibility(&plant, &options()).unwrap();
    assert_ne!(sol.outcome, Outcome::Feasible);
}

/// The jitter-free reference check at T = (0.05, 0.07), μ = 0.01: p* = 59.2701 ([repro]) and
/// ρ(J_1) < 1 with the gains (24).
#[test]
fn suspension_jitter_free_reference() {
    let plant = sporadic_sferlazza2021::example::suspension()
        .unwrap()
        .with_windows(&[
            SamplingWindow::periodic(0.05).unwrap(),
            SamplingWindow::periodic(0.07).unwrap(),
        ])
        .unwrap();
    let d = design(&plant, 0.01, &default_solve_options()).unwrap();
    assert!((d.p_star / 59.2701 - 1.0).abs() < 1e-4, "p* = {}", d.p_star);
    assert!(d.spectral_radius < 1.0, "ρ(J_1) = {}", d.spectral_radius);
    // Analysis LMI (18) with the designed gains is feasible (Theorem 1 ⇐ Theorem 2).
    let sol = analysis_feasibility(&plant, &d.gains, &options()).unwrap();
    assert_eq!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
}
