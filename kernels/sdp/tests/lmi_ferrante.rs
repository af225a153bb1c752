//! Ferrante, Gouaisbaut, Sanfelice, Tarbouriech (Automatica 2016), Example 1: scalar plant
//! `A = 1`, `M = 1`, `T1 = T2 = 1`, so one vertex `X_1 = e^{A·1} = e`. LMI (41),
//!
//! ```text
//! Φ(P,F,J) = [ −(F + Fᵀ)    F − J M    X_1ᵀ P ]
//!            [ (F − J M)ᵀ   −P         0      ]  ≺ 0,
//!            [ P X_1         0         −P     ]
//! ```
//!
//! is feasible iff `L = J/F` satisfies `|1 − L| < e^{−1}`, i.e. `L ∈ (0.6321206, 1.3678794)`
//! (spec `shared/papers/000-ferrante-sporadic.md` §5; from (12): `(1 − L)² e² < 1`).

use faer::{Mat, MatRef, Side};
use sporadic_sdp::lmi::{Expr, FeasibilityOptions, Model, Outcome, Var};

const E: f64 = std::f64::consts::E;

struct Design {
    model: Model,
    p: Var,
    f: Var,
    j: Var,
    phi: Expr,
}

/// LMI (41) of Corollary 1 for the scalar example, written as in the paper with ⋆ completion.
fn lmi41() -> Design {
    let mut m = Model::new();
    let p = m.symmetric("P", 1);
    let f = m.full("F", 1, 1);
    let j = m.full("J", 1, 1);
    let x1 = Expr::scalar(E);
    let mm = Expr::scalar(1.0); // M
    let phi = Expr::sym_blocks(&[
        [Some(-f.he()), None, None],
        [Some((&f - &j * &mm).t()), Some(-&p), None],
        [Some(&p * &x1), Some(Expr::zeros(1, 1)), Some(-&p)],
    ]);
    m.constrain(phi.lt(0.0).named("Φ_1 ≺ 0")).unwrap();
    Design {
        model: m,
        p,
        f,
        j,
        phi,
    }
}

fn max_eig(s: MatRef<'_, f64>) -> f64 {
    s.self_adjoint_eigenvalues(Side::Lower)
        .unwrap()
        .into_iter()
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Independent check of a returned (P, F, J): Φ evaluated by hand, its eigenvalues, and the
/// original nonlinear condition (12) with L = J/F.
fn check_certificate(p: f64, f: f64, j: f64) -> f64 {
    let phi = faer::mat![[-2.0 * f, f - j, E * p], [f - j, -p, 0.0], [E * p, 0.0, -p],];
    assert!(max_eig(phi.as_ref()) < 0.0, "Φ = {phi:?}");
    let l = j / f;
    assert!((1.0 - l).powi(2) * E * E * p - p < 0.0);
    l
}

#[test]
fn fixed_gain_feasibility_matches_closed_form() {
    // The paper's gain, the two infeasible gains of the brief, and gains 1e-4 on either side of
    // both ends of the interval (1 − e⁻¹, 1 + e⁻¹) = (0.63212056, 1.36787944).
    let cases = [
        (0.7321206, true),
        (0.6, false),
        (1.4, false),
        (0.6322, true),
        (0.6320, false),
        (1.3678, true),
        (1.3680, false),
    ];
    for (l, feasible) in cases {
        let mut d = lmi41();
        // J = F·L fixed (an equality, eliminated before solving).
        d.model
            .constrain(d.j.equals(l * &d.f).named("J = F L"))
            .unwrap();
        let sol = d.model.feasibility(&FeasibilityOptions::default()).unwrap();
        if feasible {
            assert_eq!(sol.outcome, Outcome::Feasible, "L = {l}: {}", sol.reason);
            assert!(sol.verification.passed());
            let (p, f, j) = (
                sol.value(&d.p).unwrap()[(0, 0)],
                sol.value(&d.f).unwrap()[(0, 0)],
                sol.value(&d.j).unwrap()[(0, 0)],
            );
            let got = check_certificate(p, f, j);
            assert!((got - l).abs() < 1e-9);
            // The verification value is λ_min(−Φ) at the point.
            let phi = sol.eval(&d.phi).unwrap();
            let lam = -max_eig(phi.as_ref());
            let rep = sol.verification.get("Φ_1 ≺ 0").unwrap();
            assert!((rep.value - lam).abs() < 1e-12 * (1.0 + lam));
        } else {
            assert_eq!(sol.outcome, Outcome::Infeasible, "L = {l}: {}", sol.reason);
            assert!(sol.margin.unwrap() <= sol.margin_threshold.unwrap());
        }
    }
}

#[test]
fn free_design_returns_gain_in_feasible_interval() {
    let d = lmi41();
    let sol = d.model.feasibility(&FeasibilityOptions::default()).unwrap();
    assert_eq!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
    let value = |v: &Var| -> f64 {
        let m: Mat<f64> = sol.value(v).unwrap();
        m[(0, 0)]
    };
    let l = check_certificate(value(&d.p), value(&d.f), value(&d.j));
    assert!(
        l > 1.0 - 1.0 / E && l < 1.0 + 1.0 / E,
        "L = {l} outside (0.6321206, 1.3678794)"
    );
}

/// Margins of LMI (41) with a fixed gain reach `1e-7` relative accuracy at the default settings
/// (`FeasibilityOptions::margin_accuracy`), against a run at `tol_gap = tol_feas = 1e-13`
/// whose DIMACS errors are checked to be below `1e-11`. Near the end of the feasible gain
/// interval (`L = 0.6322`, 1e-4 inside it) the margin is `2.7e-5`, and the default stopping rule
/// alone (relative to `1 + |objective|`) leaves it off by `7e-5` relative.
#[test]
fn fixed_gain_margins_are_accurate_to_1e7_relative() {
    for l in [0.7321206, 0.6322] {
        let margin = |opts: &FeasibilityOptions| {
            let mut d = lmi41();
            d.model
                .constrain(d.j.equals(l * &d.f).named("J = F L"))
                .unwrap();
            let sol = d.model.feasibility(opts).unwrap();
            assert_eq!(sol.outcome, Outcome::Feasible, "L = {l}: {}", sol.reason);
            (sol.margin.unwrap(), sol.sdp.measures.dimacs_max())
        };
        let mut tight = FeasibilityOptions::default();
        tight.solve.settings.tol_gap = 1e-13;
        tight.solve.settings.tol_feas = 1e-13;
        let (t_ref, kkt) = margin(&tight);
        assert!(
            kkt < 1e-11,
            "L = {l}: reference DIMACS errors up to {kkt:e}"
        );
        let (t, _) = margin(&FeasibilityOptions::default());
        assert!(
            (t - t_ref).abs() <= 1e-7 * t_ref,
            "L = {l}: t* = {t:e} against the reference {t_ref:e}"
        );
    }
}
