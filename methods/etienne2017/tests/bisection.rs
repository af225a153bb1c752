//! The largest τ̄ for τ_low = 0.01 (tolerance 1e-4) against an independent reference bisection
//! (CVXPY + Clarabel: Corollary 2 0.2898, Theorem 3 0.3417, Remark 6 0.3417).

use sporadic_etienne2017::{BisectionOptions, Condition, example, max_period, max_tau_bar};

fn options() -> BisectionOptions {
    BisectionOptions {
        tolerance: 1e-4,
        ..BisectionOptions::default()
    }
}

#[test]
fn largest_tau_bar_at_tau_low_001() {
    let plant = example::flexible_joint().unwrap();
    let c2 = max_tau_bar(&plant, Condition::Corollary2, 0.01, &options()).unwrap();
    let t3 = max_tau_bar(&plant, Condition::Theorem3, 0.01, &options()).unwrap();
    for (r, lo, hi) in [(&c2, 0.2895, 0.2900), (&t3, 0.3414, 0.3419)] {
        let (f, i) = (r.feasible().unwrap(), r.infeasible().unwrap());
        assert!(i - f <= 1e-4 && f < i, "{f} {i}");
        assert!(
            lo <= f && i <= hi,
            "{:?}: bracket ({f}, {i}) not in [{lo}, {hi}]",
            r.condition
        );
        assert!(r.monotone_by_proof);
        // The verified design sits just below the numerical boundary and passed every check.
        let cert = r.certified.as_ref().unwrap();
        assert!(cert.check.passed());
        assert!(cert.lmi.window.t2() <= f && cert.lmi.window.t2() > f - 1e-3);
        // Probes are consistent with monotone feasibility.
        for p in r.probes() {
            assert_eq!(p.certified, p.t2 <= f, "{p:?}");
            assert_eq!(p.t1, 0.01);
        }
        assert!(r.search.monotone);
    }
    assert!(t3.estimate().unwrap() >= c2.estimate().unwrap());
    let per = max_period(&plant, &options()).unwrap();
    let (f, i) = (per.feasible().unwrap(), per.infeasible().unwrap());
    assert!(0.3414 <= f && i <= 0.3419, "periodic bracket ({f}, {i})");
    assert!(per.probes().iter().all(|p| p.t1 == p.t2));
    assert!(!per.monotone_by_proof);
}

#[test]
fn tau_low_zero_has_no_feasible_tau_bar() {
    let plant = example::flexible_joint().unwrap();
    let o = BisectionOptions {
        tolerance: 1e-3,
        start: Some(0.1),
        ..BisectionOptions::default()
    };
    for c in [Condition::Corollary2, Condition::Theorem3] {
        let r = max_tau_bar(&plant, c, 0.0, &o).unwrap();
        assert_eq!(r.feasible(), None, "{c:?}");
        assert!(r.certified.is_none());
        assert!(
            r.probes()
                .iter()
                .all(|p| p.margin.unwrap() < 1e-7 && p.t1 == 0.0 && p.reason.is_some())
        );
    }
}
