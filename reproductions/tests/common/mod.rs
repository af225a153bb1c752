//! The claim-record schema every paper's `--json` lines must satisfy (shared by the paper tests).

use serde_json::Value;
use sporadic_figures::is_distrusted_label;
use sporadic_reproductions::Reproduction;

/// Half a unit of the last digit of `text` as printed (`"0.4698"` → 5e-5, `"9.9e-5"` → 5e-7).
fn half_unit(text: &str) -> f64 {
    let (mantissa, exponent) = match text.to_ascii_lowercase().split_once('e') {
        Some((m, e)) => (m.to_owned(), e.parse::<i32>().expect("exponent")),
        None => (text.to_owned(), 0),
    };
    let decimals = mantissa.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
    0.5 * 10f64.powi(exponent - decimals)
}

fn non_empty(j: &Value, key: &str) -> bool {
    j[key].as_str().is_some_and(|s| !s.trim().is_empty())
}

/// Checks the JSON record of every claim of `r`: the fields, the source and its detail, the
/// tolerance policy (half a unit of the last printed digit, or a stated reason), booleans as
/// booleans, and that no note cites documents outside the repository.
pub fn check_claim_records(paper: &str, r: &Reproduction) {
    assert!(!r.claims.is_empty());
    for c in &r.claims {
        let j = c.to_json(paper);
        let ctx = j.to_string();
        for key in [
            "paper",
            "claim",
            "source",
            "reference",
            "ours",
            "rule",
            "tolerance",
            "tolerance_reason",
            "status",
            "note",
        ] {
            assert!(j.get(key).is_some(), "missing {key}: {ctx}");
        }
        assert_eq!(j["paper"], paper);
        assert!(non_empty(&j, "claim"), "{ctx}");
        let status = j["status"].as_str().unwrap();
        assert!(
            ["match", "differs", "beats", "not-in-paper"].contains(&status),
            "{ctx}"
        );
        let source = j["source"].as_str().unwrap();
        match source {
            "paper" => assert!(non_empty(&j, "where"), "{ctx}"),
            "derived" => assert!(non_empty(&j, "derivation"), "{ctx}"),
            "independent" => assert!(non_empty(&j, "how"), "{ctx}"),
            "none" => {
                assert_eq!(status, "not-in-paper", "{ctx}");
                assert!(j["reference"].is_null() && j["rule"] == "none", "{ctx}");
                assert!(j["tolerance"].is_null(), "{ctx}");
            }
            other => panic!("unknown source {other}: {ctx}"),
        }
        if source != "none" {
            assert_ne!(status, "not-in-paper", "{ctx}");
            assert!(
                ["equal", "at_least", "at_most"].contains(&j["rule"].as_str().unwrap()),
                "{ctx}"
            );
        }
        // Verdicts are booleans on both sides and carry no tolerance.
        if j["reference"].is_boolean() || j["ours"].is_boolean() {
            assert!(j["reference"].is_boolean() || source == "none", "{ctx}");
            assert!(j["ours"].is_boolean(), "{ctx}");
            assert!(j["tolerance"].is_null(), "{ctx}");
            assert!(j.get("paper_text").is_none_or(Value::is_null), "{ctx}");
            assert!(j.get("reference_text").is_none_or(Value::is_null), "{ctx}");
            continue;
        }
        if source == "none" {
            continue;
        }
        let reference = j["reference"].as_f64().expect("numeric reference");
        let tolerance = j["tolerance"]
            .as_f64()
            .expect("a numeric comparison has a tolerance");
        // Printed numbers (the paper's and the independent records'): the number exactly as
        // printed, and a tolerance of at most half a unit of its last digit unless a reason is
        // stated.
        if source == "paper" {
            let text = j["paper_text"].as_str().expect("paper_text");
            assert_eq!(text.parse::<f64>().unwrap(), reference, "{ctx}");
            assert!(
                tolerance <= half_unit(text) * (1.0 + 1e-12) || non_empty(&j, "tolerance_reason"),
                "{ctx}"
            );
        }
        if source == "independent" {
            let text = j["reference_text"].as_str().expect("reference_text");
            assert_eq!(text.parse::<f64>().unwrap(), reference, "{ctx}");
            assert!(
                tolerance <= half_unit(text) * (1.0 + 1e-12) || non_empty(&j, "tolerance_reason"),
                "{ctx}"
            );
        }
        if source == "derived" && tolerance > 0.0 {
            assert!(non_empty(&j, "tolerance_reason"), "{ctx}");
        }
        // A match is within the tolerance.
        if status == "match" {
            let ours = j["ours"].as_f64().expect("numeric ours");
            assert!(
                (ours - reference).abs() <= tolerance * (1.0 + 1e-9),
                "{ctx}"
            );
        }
    }
    for text in r
        .claims
        .iter()
        .map(|c| c.note.as_str())
        .chain(r.notes.iter().map(String::as_str))
    {
        assert!(
            !text.contains("spec §") && !text.contains("spec 00") && !text.contains("/work/"),
            "cites a document outside the repository: {text}"
        );
    }
}

/// Scans the text of every `<text>` element of every figure of `r`.
pub fn check_figure_texts(r: &Reproduction) {
    assert!(is_distrusted_label("9.999999999999999e-5") && is_distrusted_label("-0.0"));
    assert!(!is_distrusted_label("-0.5") && !is_distrusted_label("1e-5"));
    for f in &r.figures {
        let svg = std::fs::read_to_string(f).unwrap();
        let mut texts = 0;
        for chunk in svg.split("<text").skip(1) {
            let body = chunk.split_once('>').map_or("", |(_, b)| b);
            let content = body.split("</text>").next().unwrap_or("");
            texts += 1;
            assert!(
                !is_distrusted_label(content),
                "{}: label {content:?}",
                f.display()
            );
        }
        assert!(texts > 3, "{}: no labels", f.display());
    }
}
