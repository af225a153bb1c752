//! Theorem 1 for the printed gain (spec 004 §8 A3, A4, A8, A12). Reference values: the spec's
//! independent CVXPY/Clarabel computation ([ours] in the spec) and closed forms.

use faer::Mat;
use sporadic_rabehi2021::SamplingWindow;
use sporadic_rabehi2021::analysis::{AnalysisOptions, analyse, analyse_gain};
use sporadic_rabehi2021::example::{example_window, paper_gain, spring_mass_damper};
use sporadic_rabehi2021::ipr::{MetzlerDecomposition, abs, gamma_of_gain, reset_matrix};
use sporadic_rabehi2021::lyapunov::theorem1_constants;
use sporadic_rabehi2021::polytope::{PolytopeOptions, taylor_polytope};
use sporadic_rabehi2021::verify::{GridOptions, verify_theorem1};
use sporadic_rabehi2021::{TaylorOrder, window::largest_tau_max_for_gain};

fn spectral_norm(m: &Mat<f64>) -> f64 {
    m.singular_values().unwrap().into_iter().fold(0.0, f64::max)
}

/// A3: with P = I, ‖e^{Āμ}Γ(L)‖₂ ≤ 0.96706 on [0.04, 0.3] (max at τmin, 0.8254 at 0.3), so
/// λmax(Φ) ≤ −0.0648 on a 1001-point grid and at the Taylor vertices for N = 3..8.
#[test]
fn identity_certifies_the_printed_gain() {
    let plant = spring_mass_damper(1.0).unwrap();
    let d = MetzlerDecomposition::new(plant.a()).unwrap();
    let gamma = gamma_of_gain(&plant, paper_gain().as_ref()).unwrap();
    let eye = Mat::<f64>::identity(4, 4);
    let window = example_window();
    let check = verify_theorem1(
        d.a_bar.as_ref(),
        gamma.as_ref(),
        eye.as_ref(),
        &window,
        &GridOptions::default(),
    )
    .unwrap();
    assert!(check.certified, "{check:?}");
    let max_norm = (1.0 + check.max_eigenvalue).sqrt();
    assert!((max_norm - 0.96706).abs() < 5e-6, "{max_norm}");
    assert!((check.at - 0.04).abs() < 1e-12);
    assert!(check.max_eigenvalue <= -0.0648 + 5e-5);
    // The spectral radius never reaches 1 (Remark 5).
    assert!(check.max_spectral_radius < 0.97);
    let at_end =
        spectral_norm(&(sporadic_linalg::expm_scaled(d.a_bar.as_ref(), 0.3).unwrap() * &gamma));
    assert!((at_end - 0.8254).abs() < 5e-5, "{at_end}");
    for order in 3..=8 {
        let poly = taylor_polytope(
            d.a_bar.as_ref(),
            &window,
            &PolytopeOptions {
                order: TaylorOrder::Fixed(order),
                pieces: Some(1),
                ..PolytopeOptions::default()
            },
        )
        .unwrap();
        for v in poly.vertices() {
            let vg = v * &gamma;
            let phi = vg.transpose() * &vg - &eye;
            let lam = sporadic_linalg::max_eigenvalue(
                sporadic_linalg::sym_part(phi.as_ref()).unwrap().as_ref(),
            )
            .unwrap();
            assert!(lam <= -0.0648 + 5e-5, "order {order}: {lam}");
        }
    }
    // Theorem 1 proof constants for P = I (spec A3).
    let fine = GridOptions {
        points: 20_001,
        ..GridOptions::default()
    };
    let c = theorem1_constants(
        d.a_bar.as_ref(),
        gamma.as_ref(),
        eye.as_ref(),
        &window,
        3001,
        &fine,
    )
    .unwrap();
    for (got, want, tol) in [
        (c.l1, 0.3788, 1e-4),
        (c.l2, 1.4489, 1e-4),
        (c.eta, 0.0648, 1e-4),
        (c.theta1, -0.0458, 1e-4),
        (c.gamma, 0.0352, 1e-4),
        (c.omega, 0.0106, 1e-4),
    ] {
        assert!((got - want).abs() < tol, "{got} vs {want}");
    }
    // Lemma 1 closed form: (ρ + γ(1 + τmax))j + γτmax ≤ ω holds with equality in the first term.
    assert!((c.theta1 + c.gamma * 1.3).abs() < 1e-15 && (c.omega - 0.3 * c.gamma).abs() < 1e-15);
}

/// Theorem 1 by SDP for the printed gain: certified on the polytope and on the grid.
#[test]
fn sdp_certifies_the_printed_gain() {
    let plant = spring_mass_damper(1.0).unwrap();
    let a = analyse_gain(
        &plant,
        &example_window(),
        paper_gain().as_ref(),
        &AnalysisOptions::default(),
    )
    .unwrap();
    assert!(a.certified, "{}", a.reason);
    assert!(a.polytope_certified && a.vertex_margin > 1e3 * a.remainder_effect);
    assert!(a.grid.bound < 0.0 && a.grid.max_eigenvalue < -0.05);
    // P ≻ 0, normalised.
    assert!(sporadic_linalg::min_eigenvalue(a.p.as_ref()).unwrap() > 0.0);
}

/// A4: the analysis stays feasible up to τmax ≈ 1.77 for the printed gain (c_s = 1).
#[test]
fn printed_gain_window_limit() {
    let plant = spring_mass_damper(1.0).unwrap();
    let l = paper_gain();
    let opts = AnalysisOptions::default();
    let ok = analyse_gain(
        &plant,
        &SamplingWindow::new(0.04, 1.75).unwrap(),
        l.as_ref(),
        &opts,
    )
    .unwrap();
    assert!(ok.certified, "{}", ok.reason);
    let bad = analyse_gain(
        &plant,
        &SamplingWindow::new(0.04, 1.8).unwrap(),
        l.as_ref(),
        &opts,
    )
    .unwrap();
    assert!(!bad.certified);
    // At 1.8 the spectral radius of e^{Āμ}Γ(L) exceeds 1 somewhere: no P exists at all.
    assert!(bad.grid.max_spectral_radius > 1.0, "{:?}", bad.grid);
    let search = largest_tau_max_for_gain(&plant, l.as_ref(), 0.04, 5.0, 0.01, &opts).unwrap();
    let found = search.best.unwrap();
    assert!((1.75..1.80).contains(&found), "{search:?}");
    assert!(search.first_failure.unwrap() - found <= 0.01);
}

/// A12: (19) on the 4×4 system is feasible iff both 2×2 blocks — width (S, |G|) and centre
/// (A, G) — are (TĀT = diag(S, A), TΓT = diag(|G|, G)).
#[test]
fn decoupled_blocks_agree() {
    let plant = spring_mass_damper(1.0).unwrap();
    let d = MetzlerDecomposition::new(plant.a()).unwrap();
    let l = paper_gain();
    let g = reset_matrix(&plant, l.as_ref()).unwrap();
    let gamma = gamma_of_gain(&plant, l.as_ref()).unwrap();
    let opts = AnalysisOptions::default();
    for (tau_max, expect) in [(0.3, true), (1.5, true), (1.8, false)] {
        let w = SamplingWindow::new(0.04, tau_max).unwrap();
        let full = analyse(d.a_bar.as_ref(), gamma.as_ref(), &w, &opts).unwrap();
        let width = analyse(
            d.width_matrix().as_ref(),
            abs(g.as_ref()).as_ref(),
            &w,
            &opts,
        )
        .unwrap();
        let centre = analyse(plant.a(), g.as_ref(), &w, &opts).unwrap();
        assert_eq!(full.certified, expect, "tau_max {tau_max}");
        assert_eq!(full.certified, width.certified && centre.certified);
    }
}
