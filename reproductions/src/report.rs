//! The reproduction report a person reads: one self-contained `index.html` (no script, no network)
//! with, per paper, the claim table (status coloured, source shown), its figures inline, the notes
//! (misprints, corrections, choices where the paper is silent) and the run time.

use crate::claim::{ClaimStatus, Reproduction, Source};
use std::path::Path;
use std::time::Duration;

/// One paper's section of the report.
#[derive(Debug, Clone, Copy)]
pub struct Section<'a> {
    /// Paper id (also the sub-folder of its figures).
    pub id: &'a str,
    /// Authors, year and subject.
    pub title: &'a str,
    /// The reproduction.
    pub reproduction: &'a Reproduction,
    /// Wall time of the reproduction.
    pub elapsed: Duration,
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn status_class(s: ClaimStatus) -> &'static str {
    match s {
        ClaimStatus::Match => "match",
        ClaimStatus::Differs => "differs",
        ClaimStatus::Beats => "beats",
        ClaimStatus::NotInPaper => "nip",
    }
}

/// The report as an HTML document; figures are referenced relative to `out_dir` (the folder the
/// document is written to), so it opens from disk.
pub fn index_html(sections: &[Section<'_>], out_dir: &Path) -> String {
    let mut h = String::from(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>sporadic: paper reproductions</title><style>\
         body{font-family:sans-serif;margin:2em;max-width:1400px}\
         table{border-collapse:collapse;font-size:13px;margin-bottom:1em}\
         td,th{border:1px solid #ccc;padding:2px 6px;vertical-align:top}\
         td.num{text-align:right;font-family:monospace;white-space:nowrap}\
         .match{background:#d9f2d9}.differs{background:#f8d0d0}.beats{background:#d0e4f8}\
         .nip{background:#eeeeee}img{max-width:100%;border:1px solid #ddd;margin:4px 0}\
         .note{font-size:12px;color:#333}</style></head><body>\n\
         <h1>Paper reproductions</h1>\n<p>Sources: <b>paper</b> (printed in the paper, \
         number as printed), <b>derived</b> (implied by the paper, derivation given), \
         <b>independent</b> (an independent computation), <b>none</b> (a value of ours). \
         A printed number matches when ours rounds to it at its printed digits; any other \
         tolerance states its reason.</p>\n<table id=\"summary\"><tr><th>paper</th><th>match</th>\
         <th>differs</th><th>beats</th><th>not-in-paper</th><th>time [s]</th></tr>\n",
    );
    for s in sections {
        let [m, d, b, n] = s.reproduction.tally();
        h += &format!(
            "<tr><td><a href=\"#{id}\">{id}</a></td><td class=\"num\">{m}</td>\
             <td class=\"num\">{d}</td><td class=\"num\">{b}</td><td class=\"num\">{n}</td>\
             <td class=\"num\">{:.1}</td></tr>\n",
            s.elapsed.as_secs_f64(),
            id = escape(s.id)
        );
    }
    h += "</table>\n";
    for s in sections {
        h += &section(s, out_dir);
    }
    h += "</body></html>\n";
    h
}

fn section(s: &Section<'_>, out_dir: &Path) -> String {
    let r = s.reproduction;
    let mut h = format!(
        "<section class=\"paper\" id=\"{id}\"><h2>{id}: {title}</h2>\n<p>Run time {:.1} s.</p>\n\
         <table class=\"claims\"><tr><th>claim</th><th>source</th><th>where / how</th>\
         <th>reference</th><th>ours</th><th>rule</th><th>tolerance</th><th>status</th>\
         <th>note</th></tr>\n",
        s.elapsed.as_secs_f64(),
        id = escape(s.id),
        title = escape(s.title)
    );
    for c in &r.claims {
        let reference = match (&c.source, c.reference) {
            (Source::Paper { text: Some(t), .. }, _)
            | (Source::Independent { text: Some(t), .. }, _) => t.clone(),
            (_, Some(v)) => v.to_string(),
            (_, None) => String::new(),
        };
        let tolerance = match (c.tolerance, &c.tolerance_reason) {
            (Some(t), Some(why)) => format!("{t:.1e} ({why})"),
            (Some(t), None) => format!("{t:.1e}"),
            (None, _) => String::new(),
        };
        h += &format!(
            "<tr class=\"{cls}\"><td>{}</td><td>{}</td><td class=\"note\">{}</td>\
             <td class=\"num\">{}</td><td class=\"num\">{}</td><td>{}</td>\
             <td class=\"note\">{}</td><td>{}</td><td class=\"note\">{}</td></tr>\n",
            escape(&c.claim),
            c.source.as_str(),
            escape(c.source.detail()),
            escape(&reference),
            escape(&c.ours.to_string()),
            c.rule.as_str(),
            escape(&tolerance),
            c.status,
            escape(&c.note),
            cls = status_class(c.status)
        );
    }
    h += "</table>\n";
    if !r.notes.is_empty() {
        h += "<h3>Notes: misprints found, corrections, choices</h3>\n<ul>\n";
        for n in &r.notes {
            h += &format!("<li><pre class=\"note\">{}</pre></li>\n", escape(n));
        }
        h += "</ul>\n";
    }
    h += "<h3>Figures</h3>\n";
    for f in &r.figures {
        let rel = f.strip_prefix(out_dir).unwrap_or(f);
        let src = rel
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join("/");
        h += &format!(
            "<figure><img src=\"{src}\" alt=\"{src}\"><figcaption>{src}</figcaption></figure>\n",
            src = escape(&src)
        );
    }
    h += "</section>\n";
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::claim::Claim;

    #[test]
    fn the_report_shows_claims_sources_figures_and_escapes_text() {
        let r = Reproduction {
            claims: vec![
                Claim::paper("a<b", "0.5", "Table I").equal(0.5, "x & y"),
                Claim::not_in_paper("c", 1.0, ""),
            ],
            figures: vec![Path::new("/out/p/fig.svg").to_owned()],
            notes: vec!["misprint in (3)".into()],
        };
        let s = Section {
            id: "p",
            title: "T",
            reproduction: &r,
            elapsed: Duration::from_millis(1500),
        };
        let h = index_html(&[s], Path::new("/out"));
        assert!(h.contains("<img src=\"p/fig.svg\""), "{h}");
        assert!(h.contains("a&lt;b") && h.contains("x &amp; y"));
        assert!(h.contains("class=\"match\"") && h.contains("class=\"nip\""));
        assert!(h.contains("Table I") && h.contains("misprint in (3)"));
        assert!(h.contains("1.5"));
        assert!(!h.contains("http"), "no network references");
    }
}
