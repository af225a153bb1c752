//! The library entry point `reproduce(out_dir)`: every claim carries a verdict, the only `Differs` are the
//! paper's misprints (explained in their notes), and the SVG figures are written.

mod common;

use sporadic_reproductions::claim::Value;

use sporadic_reproductions::andrieu2014::reproduce;
use sporadic_reproductions::claim::ClaimStatus;

#[test]
fn reproduce_checks_claims_and_writes_figures() {
    let dir = std::env::temp_dir().join(format!("sporadic_andrieu2014_{}", std::process::id()));
    let rep = reproduce(&dir).unwrap();
    common::check_claim_records("andrieu2014", &rep);
    common::check_figure_texts(&rep);
    println!("{}", rep.table("andrieu2014"));
    // The paper's misprints, and only they, differ.
    let expected_differs = [
        "design.printed_K_hurwitz",
        "bioreactor.f2_at_X0.05_S0.03_u0.4",
        "bioreactor.paper_fig3_tracking_with_printed_parameters",
    ];
    for c in &rep.claims {
        if let Value::Number(v) = c.ours {
            assert!(v.is_finite(), "{c:?}");
        }
        if expected_differs.contains(&c.claim.as_str()) {
            assert_eq!(c.status, ClaimStatus::Differs, "{c:?}");
            assert!(!c.note.is_empty());
        } else {
            assert_ne!(c.status, ClaimStatus::Differs, "{c:?}");
        }
    }
    // Independent closed forms for the misprint claims: ρ(Q(0.9)) from trace 1.01 and det −0.8 of Q;
    // the printed and corrected f2 values of the normal form at (0.05, 0.03), u = 0.4.
    let get = |id: &str| rep.get(id).unwrap_or_else(|| panic!("missing claim {id}"));
    assert_eq!(get("design.printed_K_hurwitz").ours, Value::Bool(false));
    let rho = (1.01 + (1.01f64 * 1.01 + 3.2).sqrt()) / 2.0;
    assert!((get("design.printed_K_rho_Q_at_0.9").ours_f64() - rho).abs() < 1e-12);
    let f2 = get("bioreactor.f2_at_X0.05_S0.03_u0.4");
    assert!(
        (f2.ours_f64() - 3.44e-3).abs() < 5e-6
            && (f2.reference.unwrap().as_f64().unwrap() - 6.25e-4).abs() < 5e-7
    );
    assert_eq!(
        get("bioreactor.paper_fig3_tracking_with_printed_parameters").ours,
        Value::Bool(false)
    );
    assert_eq!(
        get("design.printed_tuning_certified").ours,
        Value::Bool(false)
    );
    // Converging and non-converging runs of the reference table.
    assert_eq!(
        get("bioreactor.K21_alpha_0.9.converges").ours,
        Value::Bool(false)
    );
    assert_eq!(
        get("bioreactor.K11_alpha_0.9.converges").ours,
        Value::Bool(true)
    );
    assert_eq!(get("pendulum.lyapunov_violations").ours_f64(), 0.0);
    assert!(get("pendulum.sampling_rule_residual").ours_f64() < 1e-9);

    // The output says that the corrected example was run, and why the printed one fails.
    assert!(
        rep.notes
            .iter()
            .any(|n| n.contains("CORRECTED normal form"))
    );
    assert!(rep.notes.iter().any(|n| n.contains("K = [-2, 1]'")));
    assert_eq!(rep.figures.len(), 7);
    for f in &rep.figures {
        let text = std::fs::read_to_string(f).unwrap();
        assert!(
            text.starts_with("<svg") && text.len() > 2_000,
            "{}",
            f.display()
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
