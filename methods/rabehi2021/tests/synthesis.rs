//! Proposition 1 (spec 004 §8 A5, A6): the design on [0.04, 0.3], an honest "not certified"
//! beyond what the polytope allows, monotone progress of the LMI steps, and the necessary limits.

use faer::Mat;
use sporadic_rabehi2021::SamplingWindow;
use sporadic_rabehi2021::example::{TABLE1_DAMPING, example_window, spring_mass_damper};
use sporadic_rabehi2021::ipr::{MetzlerDecomposition, gamma_of_gain, pair_blocks};
use sporadic_rabehi2021::polytope::{PolytopeOptions, taylor_polytope};
use sporadic_rabehi2021::synthesis::{
    DesignStatus, NotCertified, StepKind, SynthesisOptions, synthesise, synthesise_from,
};
use sporadic_rabehi2021::verify::{GridOptions, verify_theorem1};
use sporadic_rabehi2021::window::{necessary_tau_max, polytope_tau_max};

/// A5: the pipeline returns a certified design for c_s = 1 on [0.04, 0.3] with 1 + 2L1 ≈ 0,
/// G1, G2 ≥ 0, (35b) to 1e-9, and Theorem 1 re-verified for Γ(L) (Remark 6).
#[test]
fn design_on_the_example_window() {
    let plant = spring_mass_damper(1.0).unwrap();
    let window = example_window();
    let d = synthesise(&plant, &window, &SynthesisOptions::default()).unwrap();
    assert_eq!(d.status, DesignStatus::Certified);
    assert_eq!(d.log[0].kind, StepKind::ConvexRestriction);
    assert!((1.0 + 2.0 * d.l[(0, 0)]).abs() < 1e-2, "{:?}", d.l);
    assert!(d.l[(1, 0)].abs() < 0.1);
    assert!(d.bmi.certified && d.bmi.max_eigenvalue < 0.0);
    assert!(d.bmi.min_g_entry >= 0.0 && d.bmi.equality_residual <= 1e-9);
    let g = Mat::<f64>::identity(2, 2) + &d.l * plant.c();
    assert!((&g - (&d.g1 - &d.g2)).norm_max() <= 1e-9);
    let re = d.reverification.as_ref().unwrap();
    assert!(re.certified && re.polytope_certified && re.grid.certified);
    // Independent of the pipeline: the returned P of the re-verification passes the grid check.
    let a_bar = MetzlerDecomposition::new(plant.a()).unwrap().a_bar;
    let gamma = gamma_of_gain(&plant, d.l.as_ref()).unwrap();
    let check = verify_theorem1(
        a_bar.as_ref(),
        gamma.as_ref(),
        re.p.as_ref(),
        &window,
        &GridOptions::default(),
    )
    .unwrap();
    assert!(check.certified && check.max_spectral_radius < 1.0);
}

/// Beyond the vertex limit of the single Taylor polytope (c_s = 1: ≈ 1.059), no gain can satisfy
/// (44) on it: the pipeline must say "not certified", after trying every stage, with a
/// non-increasing value of t.
#[test]
fn stalls_honestly_beyond_the_polytope_limit() {
    let plant = spring_mass_damper(1.0).unwrap();
    let options = SynthesisOptions {
        polytope: PolytopeOptions {
            pieces: Some(1),
            ..PolytopeOptions::default()
        },
        ..SynthesisOptions::default()
    };
    let limit = polytope_tau_max(&plant, 0.04, &options.polytope, 5.0)
        .unwrap()
        .unwrap();
    assert!(limit < 1.1, "{limit}");
    // At the limit a vertex has a nonnegative width block with (2,2) entry ≥ 1.
    let a_bar = MetzlerDecomposition::new(plant.a()).unwrap().a_bar;
    let poly = taylor_polytope(
        a_bar.as_ref(),
        &SamplingWindow::new(0.04, limit).unwrap(),
        &options.polytope,
    )
    .unwrap();
    assert!(poly.vertices().iter().any(|v| {
        let (w, _) = pair_blocks(v.as_ref()).unwrap();
        w[(1, 1)] >= 1.0 && (0..2).all(|i| (0..2).all(|j| w[(i, j)] >= 0.0))
    }));
    let d = synthesise(&plant, &SamplingWindow::new(0.04, 1.1).unwrap(), &options).unwrap();
    assert!(
        matches!(
            &d.status,
            DesignStatus::NotCertified(
                NotCertified::Infeasible { .. } | NotCertified::BudgetExhausted { .. }
            )
        ),
        "{:?}",
        d.status
    );
    assert!(d.best_t() > 0.0);
    let kinds: Vec<StepKind> = d.log.iter().map(|s| s.kind).collect();
    assert!(kinds.contains(&StepKind::FixedGamma) && kinds.contains(&StepKind::FixedF));
    assert!(kinds.contains(&StepKind::Sequential), "{kinds:?}");
    // Monotone progress: each step's feasible set contains the best point so far, so its
    // optimum cannot be worse (up to the solver's accuracy).
    let mut best = f64::INFINITY;
    for s in &d.log {
        assert!(
            s.t <= best + 1e-6 * (1.0 + best.abs()) || !best.is_finite(),
            "{:?}",
            d.log
        );
        best = best.min(s.t);
    }
    assert_eq!(best, d.best_t());
}

/// A6: no gain can be certified once (e^{Sμ})₂₂ ≥ 1 (x2 is never measured); spec values.
#[test]
fn necessary_limits_per_damping() {
    let spec = [2.037, 1.822, 1.613, 1.407, 1.203, 1.001, 0.800, 0.600];
    for (&c_s, want) in TABLE1_DAMPING.iter().zip(spec) {
        let plant = spring_mass_damper(c_s).unwrap();
        let got = necessary_tau_max(&plant, 0.04, 5.0).unwrap().unwrap();
        assert!((got - want).abs() < 1e-3, "c_s = {c_s}: {got} vs {want}");
        // Just below the limit the diagonal entry is below 1, at it at least 1.
        let s = MetzlerDecomposition::new(plant.a()).unwrap().width_matrix();
        let e = |mu: f64| sporadic_linalg::expm_scaled(s.as_ref(), mu).unwrap()[(1, 1)];
        assert!(e(got) >= 1.0 && e(got - 1e-6) < 1.0);
    }
    // With every state measured there is no such limit.
    let full = sporadic_rabehi2021::system::Plant::new(
        faer::mat![[0.0, 1.0], [-1.0, -1.0]].as_ref(),
        faer::mat![[0.0], [1.0]].as_ref(),
        faer::mat![[1.0, 0.0], [0.0, 1.0]].as_ref(),
    )
    .unwrap();
    assert_eq!(necessary_tau_max(&full, 0.04, 5.0).unwrap(), None);
}

/// A warm start from the slack F of a previous design certifies the same window.
#[test]
fn warm_start_from_a_previous_slack() {
    let plant = spring_mass_damper(0.3).unwrap();
    let window = SamplingWindow::new(0.04, 0.5).unwrap();
    let first = synthesise(&plant, &window, &SynthesisOptions::default()).unwrap();
    assert!(first.is_certified(), "{:?}", first.status);
    // c_s = 0.3 needs more than the convex restriction (spec §6: one alternation suffices).
    assert!(first.log.len() >= 2);
    let again = synthesise_from(
        &plant,
        &window,
        Some(first.f.as_ref()),
        &SynthesisOptions::default(),
    )
    .unwrap();
    assert!(again.is_certified());
    assert_eq!(again.log.len(), 1);
}
