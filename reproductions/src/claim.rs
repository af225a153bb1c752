//! Checked claims of a paper reproduction.
//!
//! Every paper crate's `reproduce` returns a [`Reproduction`]: the list of [`Claim`]s it checked
//! (the paper's number, ours, the tolerance and the verdict) and the figures it wrote. The
//! `sporadic reproduce` command prints them as a table or, with `--json`, one JSON object per claim:
//!
//! ```text
//! {"paper": "...", "claim": "<short id>", "paper_value": ..., "ours": ..., "tolerance": ..., "status": "match|differs|beats|not-in-paper"}
//! ```

use std::fmt;
use std::path::PathBuf;

/// How our value compares with the paper's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ClaimStatus {
    /// Within the stated tolerance of the paper's value.
    Match,
    /// Outside the tolerance, or contradicting a statement of the paper.
    Differs,
    /// Better than the paper (e.g. a larger certified window).
    Beats,
    /// A check of ours without a number in the paper.
    NotInPaper,
}

impl ClaimStatus {
    /// The machine-readable name used in the JSON output.
    pub fn as_str(self) -> &'static str {
        match self {
            ClaimStatus::Match => "match",
            ClaimStatus::Differs => "differs",
            ClaimStatus::Beats => "beats",
            ClaimStatus::NotInPaper => "not-in-paper",
        }
    }
}

impl fmt::Display for ClaimStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One checked claim.
#[derive(Debug, Clone, PartialEq)]
pub struct Claim {
    /// Short stable identifier, e.g. `"ex1.beta"`.
    pub claim: String,
    /// The paper's (or the spec's documented corrected) value, if it prints one.
    pub paper_value: Option<f64>,
    /// Our value.
    pub ours: f64,
    /// Absolute tolerance of the comparison, if any.
    pub tolerance: Option<f64>,
    /// Verdict.
    pub status: ClaimStatus,
    /// Where the reference comes from and anything a reader should know.
    pub note: String,
}

impl Claim {
    /// A comparison with a paper value: [`ClaimStatus::Match`] iff `|ours − paper| ≤ tolerance`.
    pub fn compare(
        claim: impl Into<String>,
        paper: f64,
        ours: f64,
        tolerance: f64,
        note: impl Into<String>,
    ) -> Self {
        let status = if (ours - paper).abs() <= tolerance {
            ClaimStatus::Match
        } else {
            ClaimStatus::Differs
        };
        Self {
            claim: claim.into(),
            paper_value: Some(paper),
            ours,
            tolerance: Some(tolerance),
            status,
            note: note.into(),
        }
    }

    /// A comparison where a larger value is better (e.g. a certified sampling window): within
    /// `tolerance` of the paper's value is [`ClaimStatus::Match`], above it
    /// [`ClaimStatus::Beats`], below it [`ClaimStatus::Differs`].
    pub fn at_least(
        claim: impl Into<String>,
        paper: f64,
        ours: f64,
        tolerance: f64,
        note: impl Into<String>,
    ) -> Self {
        let mut c = Self::compare(claim, paper, ours, tolerance, note);
        if ours > paper + tolerance {
            c.status = ClaimStatus::Beats;
        }
        c
    }

    /// A comparison where a smaller value is better (e.g. a decay-rate bound or an error):
    /// the mirror image of [`Claim::at_least`].
    pub fn at_most(
        claim: impl Into<String>,
        paper: f64,
        ours: f64,
        tolerance: f64,
        note: impl Into<String>,
    ) -> Self {
        let mut c = Self::compare(claim, paper, ours, tolerance, note);
        if ours < paper - tolerance {
            c.status = ClaimStatus::Beats;
        }
        c
    }

    /// A value of ours with no counterpart in the paper.
    pub fn not_in_paper(claim: impl Into<String>, ours: f64, note: impl Into<String>) -> Self {
        Self {
            claim: claim.into(),
            paper_value: None,
            ours,
            tolerance: None,
            status: ClaimStatus::NotInPaper,
            note: note.into(),
        }
    }

    /// The claim as one JSON object, tagged with the paper id.
    pub fn to_json(&self, paper: &str) -> serde_json::Value {
        serde_json::json!({
            "paper": paper,
            "claim": self.claim,
            "paper_value": self.paper_value,
            "ours": finite_or_null(self.ours),
            "tolerance": self.tolerance,
            "status": self.status.as_str(),
            "note": self.note,
        })
    }
}

fn finite_or_null(v: f64) -> serde_json::Value {
    if v.is_finite() {
        serde_json::json!(v)
    } else {
        serde_json::Value::Null
    }
}

/// The result of a paper reproduction.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Reproduction {
    /// Every claim checked, in the order of the paper.
    pub claims: Vec<Claim>,
    /// Figures written.
    pub figures: Vec<PathBuf>,
    /// Free-text remarks (misprints found, choices made where the paper is silent).
    pub notes: Vec<String>,
}

impl Reproduction {
    /// The claim with the given id.
    pub fn get(&self, id: &str) -> Option<&Claim> {
        self.claims.iter().find(|c| c.claim == id)
    }

    /// Number of claims per status, in the order match, differs, beats, not-in-paper.
    pub fn tally(&self) -> [usize; 4] {
        let mut t = [0; 4];
        for c in &self.claims {
            t[match c.status {
                ClaimStatus::Match => 0,
                ClaimStatus::Differs => 1,
                ClaimStatus::Beats => 2,
                ClaimStatus::NotInPaper => 3,
            }] += 1;
        }
        t
    }

    /// The human-readable table (one line per claim, then notes and figures).
    pub fn table(&self, paper: &str) -> String {
        let mut out = format!(
            "== {paper} ==\n{:<40} {:>14} {:>14} {:>9}  {:<12} note\n",
            "claim", "paper", "ours", "tol", "status"
        );
        for c in &self.claims {
            let paper_value = c.paper_value.map_or("-".into(), |v| format!("{v:.6}"));
            let tol = c.tolerance.map_or("-".into(), |v| format!("{v:.0e}"));
            out += &format!(
                "{:<40} {:>14} {:>14.6} {:>9}  {:<12} {}\n",
                c.claim, paper_value, c.ours, tol, c.status, c.note
            );
        }
        for n in &self.notes {
            out += &format!("note: {n}\n");
        }
        for f in &self.figures {
            out += &format!("figure: {}\n", f.display());
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compare_applies_the_tolerance() {
        assert_eq!(
            Claim::compare("a", 1.0, 1.05, 0.1, "").status,
            ClaimStatus::Match
        );
        assert_eq!(
            Claim::compare("a", 1.0, 1.2, 0.1, "").status,
            ClaimStatus::Differs
        );
        assert_eq!(
            Claim::at_least("w", 0.5, 0.7, 0.01, "").status,
            ClaimStatus::Beats
        );
        assert_eq!(
            Claim::at_least("w", 0.5, 0.3, 0.01, "").status,
            ClaimStatus::Differs
        );
        assert_eq!(
            Claim::at_most("r", 0.5, 0.3, 0.01, "").status,
            ClaimStatus::Beats
        );
        assert_eq!(
            Claim::at_most("r", 0.5, 0.505, 0.01, "").status,
            ClaimStatus::Match
        );
        assert_eq!(
            Claim::not_in_paper("a", 1.0, "").status,
            ClaimStatus::NotInPaper
        );
    }

    #[test]
    fn json_has_the_documented_fields() {
        let j = Claim::compare("ex1.beta", 0.4698, 0.46976, 5e-5, "Ex. 1").to_json("ferrante2016");
        assert_eq!(j["paper"], "ferrante2016");
        assert_eq!(j["claim"], "ex1.beta");
        assert_eq!(j["status"], "match");
        assert_eq!(j["paper_value"], 0.4698);
        let nan = Claim::not_in_paper("x", f64::NAN, "").to_json("p");
        assert!(nan["ours"].is_null());
    }

    #[test]
    fn tally_counts_statuses() {
        let r = Reproduction {
            claims: vec![
                Claim::compare("a", 1.0, 1.0, 0.0, ""),
                Claim::compare("b", 1.0, 2.0, 0.0, ""),
                Claim::not_in_paper("c", 1.0, ""),
            ],
            ..Default::default()
        };
        assert_eq!(r.tally(), [1, 1, 0, 1]);
        assert!(r.table("p").contains("differs"));
    }
}
