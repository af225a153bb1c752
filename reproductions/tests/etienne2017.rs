//! `reproduce` end to end (issue 9 item 5): every claim matches the paper or the independent
//! reference computation, the largest certified `τ̄` beats the single window the paper reports, and Figures 1–2
//! are written as SVG files.

use sporadic_reproductions::claim::ClaimStatus;
use sporadic_reproductions::etienne2017::reproduce;

#[test]
fn every_claim_matches_and_figures_are_written() {
    let dir = std::env::temp_dir().join(format!("etienne2017-reproduce-{}", std::process::id()));
    let rep = reproduce(&dir).unwrap();
    let table = rep.table("etienne2017");
    for c in &rep.claims {
        let expected = if c.claim.contains("certified_tau_bar") {
            ClaimStatus::Beats
        } else if c.paper_value.is_none() {
            ClaimStatus::NotInPaper
        } else {
            ClaimStatus::Match
        };
        assert_eq!(c.status, expected, "{}\n{table}", c.claim);
    }
    // The paper's own statements are all present.
    for id in [
        "cor2.[0.01,0.2].feasible",
        "thm3.[0.01,0.3].feasible",
        "cor2.[0.01,0.3].feasible",
        "paper_K.[0.01,0.2].certified",
        "paper_K0K1.[0.01,0.3].certified",
        "cor2.max_tau_bar(tau_low=0.01)",
        "thm3.max_tau_bar(tau_low=0.01)",
        "remark6.max_h",
        "sim.paper_K0K1.tau=0.3.|z(4)|",
    ] {
        assert!(rep.get(id).is_some(), "missing claim {id}");
    }
    assert_eq!(rep.tally(), [39, 0, 2, 2], "{table}");
    // Figures 1–2: SVG documents, and the runs behind them converged.
    assert_eq!(rep.figures.len(), 2);
    for f in &rep.figures {
        let text = std::fs::read_to_string(f).unwrap();
        assert!(
            text.contains("<svg") && text.trim_end().ends_with("</svg>"),
            "{f:?}"
        );
    }
    for id in ["fig1.|z(5)|/|z(0)|", "fig2.|z(5)|/|z(0)|"] {
        assert!(rep.get(id).unwrap().ours < 1e-3, "{table}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
