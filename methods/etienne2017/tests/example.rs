//! The flexible-joint robot of §5: margins of the margin problem against an independent
//! CVXPY/Clarabel reference solve, infeasible windows, the printed gains, and the discrete
//! contraction check.

use sporadic_etienne2017::verify::transition;
use sporadic_etienne2017::{
    CheckOptions, Condition, DesignOptions, Error, SamplingWindow, analyse, analyse_margin, design,
    discrete_check, example, solve_margin, solve_margin_without_dwell,
};

fn opts() -> DesignOptions {
    DesignOptions::default()
}

/// The grid of the discrete check of the reference computation (2001 points).
fn grid_2001() -> CheckOptions {
    CheckOptions {
        discrete_grid: 2001,
        ..CheckOptions::default()
    }
}

fn within(ours: f64, reference: f64, rel: f64) -> bool {
    (ours - reference).abs() <= rel * reference.abs()
}

#[test]
fn corollary2_on_paper_window() {
    let plant = example::flexible_joint().unwrap();
    let d = design(
        &plant,
        Condition::Corollary2,
        &SamplingWindow::new(0.01, 0.2).unwrap(),
        &opts(),
    )
    .unwrap();
    assert!(
        within(d.lmi.margin, 4.799e-4, 0.02),
        "t* = {:e}",
        d.lmi.margin
    );
    assert!(d.check.passed());
    // Every block strictly signed, the τ grid of (19b)/(19c) too.
    assert!(d.check.flow_vertices.value < 0.0 && d.check.jump_vertices.value > 0.0);
    assert!(d.check.flow_grid.value < 0.0 && d.check.jump_grid.value > 0.0);
    assert!(d.check.positivity.value > 0.0);
    // Each check cleared its rounding tolerance (safety factor 100), which is far below t*.
    for e in [
        d.check.flow_vertices,
        d.check.jump_vertices,
        d.check.positivity,
        d.check.flow_grid,
        d.check.jump_grid,
    ] {
        assert!(
            e.passed() && e.tolerance > 0.0 && e.tolerance < 1e-3 * d.lmi.margin,
            "{e:?}"
        );
    }
    assert!(d.gain.is_constant());
    // A static gain must be K = P1⁻¹L exactly: P1 K = L.
    let l = &d.lmi.certificate.p1 * d.gain.k0();
    let err = (&l - &d.lmi.certificate.l1).norm_max();
    assert!(err < 1e-10 * (1.0 + l.norm_max()), "{err:e}");
}

#[test]
fn theorem3_feasible_where_corollary2_is_not() {
    let plant = example::flexible_joint().unwrap();
    let w = SamplingWindow::new(0.01, 0.3).unwrap();
    let d = design(&plant, Condition::Theorem3, &w, &opts()).unwrap();
    assert!(
        within(d.lmi.margin, 1.370e-4, 0.02),
        "t* = {:e}",
        d.lmi.margin
    );
    assert!(d.check.passed());
    assert!(!d.gain.is_constant());
    // K(τ_low) = K0, K(τ̄) = K1.
    assert!((d.gain.at(0.01) - d.gain.k0()).norm_max() < 1e-14);
    assert!((d.gain.at(0.3) - d.gain.k1()).norm_max() < 1e-14);
    let c2 = solve_margin(&plant, Condition::Corollary2, &w, &opts()).unwrap();
    assert!(c2.margin < 1e-7, "Corollary 2 t* = {:e}", c2.margin);
    assert!(!c2.verified());
    assert!(matches!(
        design(&plant, Condition::Corollary2, &w, &opts()),
        Err(Error::Infeasible { .. })
    ));
}

#[test]
fn other_reference_margins() {
    let plant = example::flexible_joint().unwrap();
    let cases = [
        (Condition::Corollary2, 0.01, 0.1, 1.547e-3),
        (Condition::Corollary2, 1e-3, 0.2, 6.20e-5),
        (Condition::Theorem3, 1e-3, 0.3, 1.651e-5),
    ];
    for (c, lo, hi, t) in cases {
        let s = solve_margin(&plant, c, &SamplingWindow::new(lo, hi).unwrap(), &opts()).unwrap();
        assert!(
            within(s.margin, t, 0.02),
            "{c:?} [{lo},{hi}]: {:e} vs {t:e}",
            s.margin
        );
        assert!(s.verified());
    }
}

#[test]
fn tau_low_zero_is_infeasible() {
    let plant = example::flexible_joint().unwrap();
    for (c, hi) in [(Condition::Corollary2, 0.2), (Condition::Theorem3, 0.3)] {
        let s = solve_margin_without_dwell(&plant, c, hi, &opts()).unwrap();
        assert!(s.margin < 1e-7, "{c:?}: t* = {:e}", s.margin);
        assert!(!s.verified());
    }
}

#[test]
fn feasibility_is_monotone_in_tau_bar() {
    let plant = example::flexible_joint().unwrap();
    for c in [Condition::Corollary2, Condition::Theorem3] {
        let margins: Vec<f64> = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4]
            .iter()
            .map(|&hi| {
                solve_margin(&plant, c, &SamplingWindow::new(0.01, hi).unwrap(), &opts())
                    .unwrap()
                    .margin
            })
            .collect();
        let feasible: Vec<bool> = margins.iter().map(|&t| t > 1e-7).collect();
        // Once infeasible, infeasible for every larger τ̄; and t* decreases while feasible.
        let first_bad = feasible.iter().position(|f| !f).unwrap();
        assert!(
            feasible[first_bad..].iter().all(|f| !f),
            "{c:?}: {margins:?}"
        );
        assert!(
            margins[..first_bad].windows(2).all(|w| w[1] < w[0]),
            "{margins:?}"
        );
        let expected_first_bad = if c == Condition::Corollary2 { 5 } else { 6 };
        assert_eq!(first_bad, expected_first_bad, "{c:?}: {margins:?}");
    }
}

#[test]
fn printed_gains_are_certified() {
    let plant = example::flexible_joint().unwrap();
    // Static K on [0.01, 0.2]: t* ≈ 5.19e-4 (reference solve).
    let k = example::paper_static_schedule(SamplingWindow::new(0.01, 0.2).unwrap()).unwrap();
    let a = analyse(&plant, &k, &opts()).unwrap();
    assert!(within(a.lmi.margin, 4.575e-4, 0.02), "{:e}", a.lmi.margin);
    // … but not on [0.01, 0.25].
    let k25 = example::paper_static_schedule(SamplingWindow::new(0.01, 0.25).unwrap()).unwrap();
    let a25 = analyse_margin(&plant, &k25, &opts()).unwrap();
    assert!(a25.margin < 1e-7 && !a25.verified(), "{:e}", a25.margin);
    assert!(matches!(
        analyse(&plant, &k25, &opts()),
        Err(Error::Infeasible { .. })
    ));
    // K0, K1 on [0.01, 0.3]: t* ≈ 1.10e-4.
    let tv = example::paper_tv_schedule().unwrap();
    let a = analyse(&plant, &tv, &opts()).unwrap();
    assert!(within(a.lmi.margin, 1.048e-4, 0.02), "{:e}", a.lmi.margin);
}

#[test]
fn discrete_check_of_printed_gains() {
    // Reference: max ρ(M_p(τ)) on 2001 points = 0.9840 (static, at τ_low, p = 2) and 0.9892
    // (TV, at τ_low, p = 1); max λ(M'P1M − P1) = −9.1e-4 / −2.3e-4 with P1 of the reference's
    // fixed-gain solve of the unscaled (20a)-(20b). The maximiser P1 depends on how the blocks
    // are weighted ((20a)-(20b) are imposed multiplied by τ̄ here), so only the sign, which
    // every certificate of (20) must give, and the order of magnitude are asserted.
    let plant = example::flexible_joint().unwrap();
    let k = example::paper_static_schedule(SamplingWindow::new(0.01, 0.2).unwrap()).unwrap();
    let a = analyse_margin(&plant, &k, &opts()).unwrap();
    let d = discrete_check(&plant, &k, Some(a.certificate.p1.as_ref()), &grid_2001()).unwrap();
    assert!((d.spectral_radius.value - 0.9840).abs() < 1e-3);
    assert_eq!(d.spectral_radius.tau, 0.01);
    assert_eq!(d.spectral_radius.vertex, Some(1));
    let c = d.contraction.unwrap().value;
    assert!((-2e-3..0.0).contains(&c) && c < -4e-4, "{c:e}");

    let tv = example::paper_tv_schedule().unwrap();
    let a = analyse_margin(&plant, &tv, &opts()).unwrap();
    let d = discrete_check(&plant, &tv, Some(a.certificate.p1.as_ref()), &grid_2001()).unwrap();
    assert!((d.spectral_radius.value - 0.9892).abs() < 1e-3);
    assert_eq!(d.spectral_radius.tau, 0.01);
    assert_eq!(d.spectral_radius.vertex, Some(0));
    let c = d.contraction.unwrap().value;
    assert!((-5e-4..0.0).contains(&c) && c < -1e-4, "{c:e}");

    // At τ = τ̄ (reference): static 0.4754 (p=1), 0.5996 (p=2); TV 0.5627 (p=1), 0.4755 (p=2).
    let rho = |k: &faer::Mat<f64>, p: usize, tau: f64| {
        let m = transition(plant.vertices()[p].as_ref(), k.as_ref(), plant.c(), tau).unwrap();
        sporadic_linalg::spectral_radius(m.as_ref()).unwrap()
    };
    let ks = example::paper_static_gain();
    let (_, k1) = example::paper_tv_gains();
    for (got, want) in [
        (rho(&ks, 0, 0.2), 0.4754),
        (rho(&ks, 1, 0.2), 0.5996),
        (rho(&k1, 0, 0.3), 0.5627),
        (rho(&k1, 1, 0.3), 0.4755),
    ] {
        assert!((got - want).abs() < 1e-3, "{got} vs {want}");
    }
}

#[test]
fn periodic_case_of_remark6() {
    let plant = example::flexible_joint().unwrap();
    let d = design(
        &plant,
        Condition::Remark6,
        &SamplingWindow::periodic(0.3).unwrap(),
        &opts(),
    )
    .unwrap();
    assert!(d.gain.is_constant() && d.check.passed());
    let bad = solve_margin(
        &plant,
        Condition::Remark6,
        &SamplingWindow::periodic(0.35).unwrap(),
        &opts(),
    )
    .unwrap();
    assert!(bad.margin < 1e-7);
}
