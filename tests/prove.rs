//! `sporadic design --prove` and `sporadic verify` (issue 24): the proof section, the exit
//! status, gains brought from a file (a design report, an object, an array), a window override,
//! and bad gain files.

use sporadic::model::{DesignReport, ProofStatus};
use std::process::Output;

mod common;
use common::{example, scratch, sporadic};

fn report(o: &Output) -> DesignReport {
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| {
        panic!(
            "{e}: {}\n{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        )
    })
}

#[test]
fn design_with_prove_adds_a_proved_section_and_verify_reproves_the_gain() {
    let plant = example("ferrante2016-example2.toml");
    let o = sporadic(&[
        "design",
        &plant,
        "--method",
        "ferrante2016",
        "--prove",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0));
    let d = report(&o);
    let proof = d.proof.as_ref().expect("a proof section");
    assert_eq!(proof.status, ProofStatus::Proved, "{}", proof.message);
    assert!(proof.subintervals >= 1 && proof.margin_lower_bound.unwrap() > 0.0);
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["proof"]["status"], "proved");

    // The report itself is a gains file; verify finds the same gain certified and proved.
    let file = scratch("design.json");
    std::fs::write(&file, &o.stdout).unwrap();
    let file = file.display().to_string();
    let o = sporadic(&[
        "verify",
        &plant,
        "--method",
        "ferrante2016",
        "--gains",
        &file,
        "--prove",
        "--json",
    ]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v = report(&o);
    assert!(v.status.is_certified());
    assert_eq!(v.gains[0].rows, d.gains[0].rows);
    assert_eq!(v.proof.unwrap().status, ProofStatus::Proved);

    // Without --prove the section is there and says no proof was asked for.
    let o = sporadic(&[
        "verify",
        &plant,
        "--method",
        "ferrante2016",
        "--gains",
        &file,
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(report(&o).proof.unwrap().status, ProofStatus::Inconclusive);
}

#[test]
fn verify_of_a_spoiled_gain_is_not_certified_and_not_proved() {
    let plant = example("ferrante2016-example2.toml");
    // Only the gain, as an array, spoiled ×3: the jump is no longer contractive somewhere.
    let gains = r#"[{"name": "L", "rows": [[2.3], [0.54], [-0.36], [-0.52], [0.67]]}]"#;
    let file = scratch("spoiled.json");
    std::fs::write(&file, gains).unwrap();
    let file = file.display().to_string();
    let o = sporadic(&[
        "verify",
        &plant,
        "--method",
        "ferrante2016",
        "--gains",
        &file,
        "--json",
    ]);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v = report(&o);
    assert!(!v.status.is_certified());
    assert_eq!(v.proof.unwrap().status, ProofStatus::NotProved);
    // The paper's gain as {"gains": [...]} on a window override: certified on [0.2, 3].
    let paper = r#"{"gains": [{"name": "L", "rows": [[0.77524], [0.18123], [-0.12123], [-0.17406], [0.22469]]}]}"#;
    let file = scratch("paper.json");
    std::fs::write(&file, paper).unwrap();
    let file = file.display().to_string();
    let o = sporadic(&[
        "verify",
        &plant,
        "--method",
        "ferrante2016",
        "--gains",
        &file,
        "--window",
        "0.2",
        "3",
        "--prove",
    ]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{out}");
    assert!(out.contains("proof    proved"), "{out}");
}

#[test]
fn a_method_that_does_not_apply_proves_nothing_and_disproves_nothing() {
    // rabehi2021 needs disturbance bounds, which this file lacks.
    let o = sporadic(&[
        "design",
        &example("ferrante2016-example2.toml"),
        "--method",
        "rabehi2021",
        "--prove",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let d = report(&o);
    assert!(d.status.is_not_applicable());
    assert_eq!(d.proof.unwrap().status, ProofStatus::Inconclusive);
}

#[test]
fn bad_gain_files_are_input_errors() {
    let plant = example("ferrante2016-example2.toml");
    for (name, text, needle) in [
        ("notjson.json", "L = 1", "not JSON"),
        ("noname.json", r#"[{"rows": [[1.0]]}]"#, "\"name\""),
        (
            "ragged.json",
            r#"[{"name": "L", "rows": [[1.0], [1.0, 2.0]]}]"#,
            "rectangular",
        ),
        ("empty.json", r#"{"gains": []}"#, "no gains"),
        (
            "shape.json",
            r#"[{"name": "L", "rows": [[1.0, 2.0]]}]"#,
            "L",
        ),
        (
            "missing.json",
            r#"[{"name": "K", "rows": [[1.0]]}]"#,
            "needs the gain L",
        ),
    ] {
        let file = scratch(name);
        std::fs::write(&file, text).unwrap();
        let o = sporadic(&[
            "verify",
            &plant,
            "--method",
            "ferrante2016",
            "--gains",
            &file.display().to_string(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(needle), "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
    }
    let o = sporadic(&[
        "verify",
        &plant,
        "--method",
        "ferrante2016",
        "--gains",
        "/nonexistent.json",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let file = scratch("ok.json");
    std::fs::write(
        &file,
        r#"[{"name": "L", "rows": [[0.7], [0.2], [-0.1], [-0.2], [0.2]]}]"#,
    )
    .unwrap();
    let o = sporadic(&[
        "verify",
        &plant,
        "--method",
        "ferrante2016",
        "--gains",
        &file.display().to_string(),
        "--window",
        "3",
        "0.2",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--window"));
}
