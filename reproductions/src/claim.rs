//! Checked claims of a paper reproduction, as data.
//!
//! Every paper module's `reproduce` returns a [`Reproduction`]: the list of [`Claim`]s it checked
//! and the figures it wrote. A claim records where its reference value comes from
//! ([`Source`]), the reference, our value, the comparison [`Rule`], the tolerance (and why, when it
//! is not the default), and the verdict. The `sporadic reproduce` command prints them as a table
//! or, with `--json`, one JSON object per claim (see [`Claim::to_json`]).
//!
//! # Tolerance policy
//!
//! A reference value is given as the text it is printed with (in the paper, or in the record of
//! an independent computation), e.g. `"0.4698"` or `"9.9e-5"`. It matches when our value rounds to
//! it at its printed digits: the default tolerance is half a unit of the last printed digit
//! ([`half_unit`]). Any other tolerance is set with [`Reference::tolerance`], which requires the
//! reason; the reason is part of the record (`tolerance_reason`). Values derived in closed form
//! (not printed) carry an explicit tolerance with its reason.

use std::fmt;
use std::path::PathBuf;

/// How our value compares with the reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ClaimStatus {
    /// Within the stated tolerance of the reference.
    Match,
    /// Outside the tolerance, or contradicting a statement of the paper.
    Differs,
    /// Better than the reference (e.g. a larger certified window).
    Beats,
    /// A value of ours without a reference to compare it with.
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

/// A claimed value: a number or a yes/no verdict.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A number.
    Number(f64),
    /// A verdict (e.g. "the LMI is feasible").
    Bool(bool),
}

impl Value {
    /// The value as JSON (`null` for a non-finite number).
    pub fn to_json(self) -> serde_json::Value {
        match self {
            Value::Number(v) if v.is_finite() => serde_json::json!(v),
            Value::Number(_) => serde_json::Value::Null,
            Value::Bool(b) => serde_json::json!(b),
        }
    }

    /// The number, if this is one.
    pub fn as_f64(self) -> Option<f64> {
        match self {
            Value::Number(v) => Some(v),
            Value::Bool(_) => None,
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Number(v) if *v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e6) => {
                write!(f, "{v:.4e}")
            }
            Value::Number(v) => write!(f, "{v:.6}"),
            Value::Bool(b) => write!(f, "{b}"),
        }
    }
}

/// Where a claim's reference value comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    /// Printed in the paper.
    Paper {
        /// The number exactly as printed (e.g. `"0.4698"`); `None` for a verdict the paper states
        /// in words (e.g. "the LMI is feasible on [0.01, 0.2]").
        text: Option<String>,
        /// Where: section, equation, table or figure.
        location: String,
    },
    /// Implied by the paper (e.g. a closed form of its example): the derivation.
    Derived(String),
    /// From an independent computation (not printed in the paper).
    Independent {
        /// The number as that computation records it (e.g. `"0.95882"`); `None` for a verdict.
        text: Option<String>,
        /// How it was obtained.
        how: String,
    },
    /// No reference: a value of ours reported for the reader.
    None,
}

impl Source {
    /// The machine-readable name used in the JSON output.
    pub fn as_str(&self) -> &'static str {
        match self {
            Source::Paper { .. } => "paper",
            Source::Derived(_) => "derived",
            Source::Independent { .. } => "independent",
            Source::None => "none",
        }
    }

    /// The detail shown to a reader: where in the paper, the derivation, or how.
    pub fn detail(&self) -> &str {
        match self {
            Source::Paper { location, .. } => location,
            Source::Derived(s) | Source::Independent { how: s, .. } => s,
            Source::None => "",
        }
    }
}

/// How our value is compared with the reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// `|ours − reference| ≤ tolerance` (verdicts: equal).
    Equal,
    /// Larger is better: within the tolerance matches, above it beats, below it differs.
    AtLeast,
    /// Smaller is better: the mirror image of [`Rule::AtLeast`].
    AtMost,
    /// No comparison (no reference).
    None,
}

impl Rule {
    /// The machine-readable name used in the JSON output.
    pub fn as_str(self) -> &'static str {
        match self {
            Rule::Equal => "equal",
            Rule::AtLeast => "at_least",
            Rule::AtMost => "at_most",
            Rule::None => "none",
        }
    }
}

/// Half a unit of the last digit of a number printed as `text` (`"0.4698"` → `5e-5`,
/// `"9.9e-5"` → `5e-7`, `"137"` → `0.5`), with the value it denotes. `None` if `text` is not a
/// decimal number.
pub fn half_unit(text: &str) -> Option<(f64, f64)> {
    let value: f64 = text.trim().parse().ok()?;
    let lower = text.trim().to_ascii_lowercase();
    let (mantissa, exponent) = match lower.split_once('e') {
        Some((m, e)) => (m, e.parse::<i32>().ok()?),
        None => (lower.as_str(), 0),
    };
    let decimals = mantissa.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
    Some((value, 0.5 * 10f64.powi(exponent - decimals)))
}

/// A claim under construction: its id, source and reference, before our value is known.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    claim: String,
    source: Source,
    reference: Value,
    tolerance: Option<f64>,
    tolerance_reason: Option<String>,
}

impl Reference {
    fn printed(claim: String, source: Source, text: &str) -> Self {
        let (value, tol) = half_unit(text).unwrap_or((f64::NAN, 0.0));
        Self {
            claim,
            source,
            reference: Value::Number(value),
            tolerance: Some(tol),
            tolerance_reason: None,
        }
    }

    /// A tolerance other than the default half unit of the last printed digit, with its reason.
    pub fn tolerance(mut self, tolerance: f64, reason: impl Into<String>) -> Self {
        self.tolerance = Some(tolerance);
        self.tolerance_reason = Some(reason.into());
        self
    }

    fn finish(self, ours: Value, rule: Rule, note: impl Into<String>) -> Claim {
        let status = match (self.reference, ours) {
            (Value::Bool(r), Value::Bool(o)) => {
                if r == o {
                    ClaimStatus::Match
                } else {
                    ClaimStatus::Differs
                }
            }
            (Value::Number(r), Value::Number(o)) => {
                let tol = self.tolerance.unwrap_or(0.0) * (1.0 + 1e-9);
                if (o - r).abs() <= tol {
                    ClaimStatus::Match
                } else if (rule == Rule::AtLeast && o > r) || (rule == Rule::AtMost && o < r) {
                    ClaimStatus::Beats
                } else {
                    ClaimStatus::Differs
                }
            }
            _ => ClaimStatus::Differs,
        };
        let tolerance = match ours {
            Value::Bool(_) => None,
            Value::Number(_) => self.tolerance,
        };
        Claim {
            claim: self.claim,
            source: self.source,
            reference: Some(self.reference),
            ours,
            rule,
            tolerance,
            tolerance_reason: self.tolerance_reason,
            status,
            note: note.into(),
        }
    }

    /// Compares our number with the reference: match iff within the tolerance.
    pub fn equal(self, ours: f64, note: impl Into<String>) -> Claim {
        self.finish(Value::Number(ours), Rule::Equal, note)
    }

    /// Larger is better (e.g. a certified window): match within the tolerance, beats above it.
    pub fn at_least(self, ours: f64, note: impl Into<String>) -> Claim {
        self.finish(Value::Number(ours), Rule::AtLeast, note)
    }

    /// Smaller is better (e.g. an error): match within the tolerance, beats below it.
    pub fn at_most(self, ours: f64, note: impl Into<String>) -> Claim {
        self.finish(Value::Number(ours), Rule::AtMost, note)
    }

    /// Compares our verdict with the reference verdict.
    pub fn verdict(self, ours: bool, note: impl Into<String>) -> Claim {
        self.finish(Value::Bool(ours), Rule::Equal, note)
    }
}

/// One checked claim.
#[derive(Debug, Clone, PartialEq)]
pub struct Claim {
    /// Short stable identifier, e.g. `"ex1.beta"`.
    pub claim: String,
    /// Where the reference comes from.
    pub source: Source,
    /// The reference value (`None` for [`ClaimStatus::NotInPaper`]).
    pub reference: Option<Value>,
    /// Our value.
    pub ours: Value,
    /// How ours is compared with the reference.
    pub rule: Rule,
    /// Absolute tolerance of the comparison of numbers.
    pub tolerance: Option<f64>,
    /// Why the tolerance is not half a unit of the reference's last printed digit.
    pub tolerance_reason: Option<String>,
    /// Verdict.
    pub status: ClaimStatus,
    /// Anything a reader should know (what is computed, how, caveats).
    pub note: String,
}

impl Claim {
    /// A number printed in the paper, as printed (`text`, e.g. `"0.4698"`), and where
    /// (`location`: section, equation, table, figure).
    pub fn paper(claim: impl Into<String>, text: &str, location: impl Into<String>) -> Reference {
        let source = Source::Paper {
            text: Some(text.to_owned()),
            location: location.into(),
        };
        Reference::printed(claim.into(), source, text)
    }

    /// A verdict the paper states in words (e.g. "feasible on [0.01, 0.2]"), and where.
    pub fn paper_states(
        claim: impl Into<String>,
        verdict: bool,
        location: impl Into<String>,
    ) -> Reference {
        Reference {
            claim: claim.into(),
            source: Source::Paper {
                text: None,
                location: location.into(),
            },
            reference: Value::Bool(verdict),
            tolerance: None,
            tolerance_reason: None,
        }
    }

    /// A number from an independent computation, as that computation records it (`text`), and
    /// how it was obtained.
    pub fn independent(claim: impl Into<String>, text: &str, how: impl Into<String>) -> Reference {
        let source = Source::Independent {
            text: Some(text.to_owned()),
            how: how.into(),
        };
        Reference::printed(claim.into(), source, text)
    }

    /// A verdict of an independent computation, and how it was obtained.
    pub fn independent_verdict(
        claim: impl Into<String>,
        verdict: bool,
        how: impl Into<String>,
    ) -> Reference {
        Reference {
            claim: claim.into(),
            source: Source::Independent {
                text: None,
                how: how.into(),
            },
            reference: Value::Bool(verdict),
            tolerance: None,
            tolerance_reason: None,
        }
    }

    /// A number the paper implies (e.g. a closed form of its example data), with the derivation.
    /// Exact unless a tolerance (with its reason) is set.
    pub fn derived(
        claim: impl Into<String>,
        value: f64,
        derivation: impl Into<String>,
    ) -> Reference {
        Reference {
            claim: claim.into(),
            source: Source::Derived(derivation.into()),
            reference: Value::Number(value),
            tolerance: Some(0.0),
            tolerance_reason: None,
        }
    }

    /// A verdict the paper implies, with the derivation.
    pub fn derived_verdict(
        claim: impl Into<String>,
        verdict: bool,
        derivation: impl Into<String>,
    ) -> Reference {
        Reference {
            claim: claim.into(),
            source: Source::Derived(derivation.into()),
            reference: Value::Bool(verdict),
            tolerance: None,
            tolerance_reason: None,
        }
    }

    /// A number of ours with no reference to compare it with.
    pub fn not_in_paper(claim: impl Into<String>, ours: f64, note: impl Into<String>) -> Self {
        Self::report(claim, Value::Number(ours), note)
    }

    /// A verdict of ours with no reference to compare it with.
    pub fn not_in_paper_verdict(
        claim: impl Into<String>,
        ours: bool,
        note: impl Into<String>,
    ) -> Self {
        Self::report(claim, Value::Bool(ours), note)
    }

    fn report(claim: impl Into<String>, ours: Value, note: impl Into<String>) -> Self {
        Self {
            claim: claim.into(),
            source: Source::None,
            reference: None,
            ours,
            rule: Rule::None,
            tolerance: None,
            tolerance_reason: None,
            status: ClaimStatus::NotInPaper,
            note: note.into(),
        }
    }

    /// Our value as a number (`NaN` for a verdict).
    pub fn ours_f64(&self) -> f64 {
        self.ours.as_f64().unwrap_or(f64::NAN)
    }

    /// The claim as one JSON object, tagged with the paper id: `paper`, `claim`, `source`
    /// (`paper`, `derived`, `independent` or `none`) with its detail (`paper_text` and `where`
    /// for `paper`, `derivation` for `derived`, `reference_text` and `how` for `independent`),
    /// `reference`, `ours`,
    /// `rule`, `tolerance`, `tolerance_reason`, `status`, `note`.
    pub fn to_json(&self, paper: &str) -> serde_json::Value {
        let mut j = serde_json::json!({
            "paper": paper,
            "claim": self.claim,
            "source": self.source.as_str(),
            "reference": self.reference.map(Value::to_json),
            "ours": self.ours.to_json(),
            "rule": self.rule.as_str(),
            "tolerance": self.tolerance,
            "tolerance_reason": self.tolerance_reason,
            "status": self.status.as_str(),
            "note": self.note,
        });
        match &self.source {
            Source::Paper { text, location } => {
                j["paper_text"] = serde_json::json!(text);
                j["where"] = serde_json::json!(location);
            }
            Source::Derived(d) => j["derivation"] = serde_json::json!(d),
            Source::Independent { text, how } => {
                j["reference_text"] = serde_json::json!(text);
                j["how"] = serde_json::json!(how);
            }
            Source::None => {}
        }
        j
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
            "== {paper} ==\n{:<40} {:<11} {:>14} {:>14} {:>9}  {:<12} note\n",
            "claim", "source", "reference", "ours", "tol", "status"
        );
        for c in &self.claims {
            let reference = match (&c.source, c.reference) {
                (Source::Paper { text: Some(t), .. }, _)
                | (Source::Independent { text: Some(t), .. }, _) => t.clone(),
                (_, Some(r)) => r.to_string(),
                (_, None) => "-".into(),
            };
            let tol = c.tolerance.map_or("-".into(), |v| format!("{v:.0e}"));
            out += &format!(
                "{:<40} {:<11} {:>14} {:>14} {:>9}  {:<12} {}\n",
                c.claim,
                c.source.as_str(),
                reference,
                c.ours.to_string(),
                tol,
                c.status,
                c.note
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

/// The claim that a certified design of a paper's example is proved for every sampling
/// interval of its window (issue "Proofs, not samples"): the reference is `proved` (the design
/// is certified, so its condition holds everywhere if the certificate is right), ours the
/// prover's status; the note gives the pieces, the margin bound, the enclosure width and the
/// time, or where and why the proof stopped.
pub fn proof_claim(id: impl Into<String>, design: &str, proof: &sporadic_model::Proof) -> Claim {
    let proved = proof.status == sporadic_model::ProofStatus::Proved;
    let note = if proved {
        format!(
            "{design}: proved in interval arithmetic on {} τ-pieces in {:.2} s; margin ≥ {} ({}); \
             largest relative width of the e^(Aτ) enclosures {}",
            proof.subintervals,
            proof.seconds,
            proof
                .margin_lower_bound
                .map_or_else(|| "—".into(), sporadic_model::significant),
            proof.margin_definition,
            proof
                .enclosure_width
                .map_or_else(|| "—".into(), sporadic_model::significant),
        )
    } else {
        format!("{design}: {} — {}", proof.status, proof.message)
    };
    Claim::derived_verdict(
        id,
        true,
        format!("{design} is certified: its condition holds for every τ of the window"),
    )
    .verdict(proved, note)
}

/// The design of `method` for an example plant at `sampling`, through the common contract, and
/// its [`proof_claim`] (a design that is not certified gives a claim that says so).
///
/// # Errors
/// A method error that is not a verdict.
pub fn design_and_prove(
    method: &dyn sporadic_model::ObserverMethod,
    plant: &sporadic_model::Plant,
    sampling: &sporadic_model::Sampling,
    id: &str,
    what: &str,
) -> Result<Claim, crate::ReproductionError> {
    let d = method.design(plant, sampling, &sporadic_model::MethodOptions::default())?;
    let proof =
        sporadic_model::prove_within(method, plant, &d, &sporadic_model::ProofOptions::default())?;
    Ok(proof_claim(id, what, &proof))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_unit_of_the_last_printed_digit() {
        assert_eq!(half_unit("0.4698"), Some((0.4698, 5e-5)));
        let (v, t) = half_unit("9.9e-5").unwrap();
        assert_eq!(v, 9.9e-5);
        assert!((t - 5e-7).abs() < 1e-20);
        assert_eq!(half_unit("137"), Some((137.0, 0.5)));
        assert_eq!(half_unit("-22.8").map(|p| p.0), Some(-22.8));
        assert!((half_unit("-22.8").unwrap().1 - 0.05).abs() < 1e-15);
        assert_eq!(half_unit("n/a"), None);
    }

    #[test]
    fn printed_numbers_match_when_ours_rounds_to_them() {
        assert_eq!(
            Claim::paper("a", "0.4698", "Ex. 1")
                .equal(0.46976, "")
                .status,
            ClaimStatus::Match
        );
        assert_eq!(
            Claim::paper("a", "0.4698", "Ex. 1")
                .equal(0.46974, "")
                .status,
            ClaimStatus::Differs
        );
        // 1.749e-9 does not round to 1.8e-9.
        assert_eq!(
            Claim::independent("z", "1.8e-9", "RK4")
                .equal(1.749e-9, "")
                .status,
            ClaimStatus::Differs
        );
        let c = Claim::paper("w", "0.2", "§4").at_least(0.29, "");
        assert_eq!(c.status, ClaimStatus::Beats);
        assert_eq!(
            Claim::paper("w", "0.5", "T").at_least(0.3, "").status,
            ClaimStatus::Differs
        );
        assert_eq!(
            Claim::paper("r", "0.5", "T").at_most(0.3, "").status,
            ClaimStatus::Beats
        );
        let loose = Claim::independent("x", "1.25", "closed form").tolerance(0.1, "because");
        assert_eq!(
            loose.equal(1.3, "").tolerance_reason.as_deref(),
            Some("because")
        );
        assert_eq!(
            Claim::paper("n", "0.1", "T").equal(f64::NAN, "").status,
            ClaimStatus::Differs
        );
    }

    #[test]
    fn verdicts_are_booleans() {
        let c = Claim::paper_states("f", true, "§4").verdict(false, "");
        assert_eq!(c.status, ClaimStatus::Differs);
        assert_eq!(c.tolerance, None);
        let j = c.to_json("p");
        assert_eq!(j["ours"], false);
        assert_eq!(j["reference"], true);
        assert!(j["paper_text"].is_null());
    }

    #[test]
    fn json_has_the_documented_fields() {
        let j = Claim::paper("ex1.beta", "0.4698", "Ex. 1, (18)")
            .equal(0.46976, "n")
            .to_json("ferrante2016");
        assert_eq!(j["paper"], "ferrante2016");
        assert_eq!(j["claim"], "ex1.beta");
        assert_eq!(j["status"], "match");
        assert_eq!(j["source"], "paper");
        assert_eq!(j["paper_text"], "0.4698");
        assert_eq!(j["where"], "Ex. 1, (18)");
        assert_eq!(j["reference"], 0.4698);
        assert_eq!(j["rule"], "equal");
        let d = Claim::derived("x", 2.0, "e^0 + 1")
            .equal(2.0, "")
            .to_json("p");
        assert_eq!(d["derivation"], "e^0 + 1");
        let nan = Claim::not_in_paper("x", f64::NAN, "").to_json("p");
        assert!(nan["ours"].is_null());
        assert_eq!(nan["source"], "none");
    }

    #[test]
    fn tally_counts_statuses() {
        let r = Reproduction {
            claims: vec![
                Claim::derived("a", 1.0, "d").equal(1.0, ""),
                Claim::derived("b", 1.0, "d").equal(2.0, ""),
                Claim::not_in_paper("c", 1.0, ""),
            ],
            ..Default::default()
        };
        assert_eq!(r.tally(), [1, 1, 0, 1]);
        assert!(r.table("p").contains("differs"));
    }
}
