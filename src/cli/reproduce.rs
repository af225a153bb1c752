//! `sporadic reproduce`: runs the paper reproductions and prints their checked claims.

use super::{Failure, Outcome};
use sporadic::methods;
use sporadic_reproductions::report::{Section, index_html};
use sporadic_reproductions::{PAPERS, Paper, Reproduction};
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Arguments of `sporadic reproduce`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// `all`, or one of the paper ids listed by `sporadic reproduce all`.
    pub paper: String,
    /// Print one JSON object per checked claim, then one `{"paper", "figure"}` object per figure
    /// written, instead of the human table.
    #[arg(long)]
    pub json: bool,
    /// Folder for the figures (one sub-folder per paper) and the report `index.html`.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
}

/// The reproductions in the order of the method registry (every registered method has one; a
/// test checks it).
fn papers() -> Vec<&'static Paper> {
    methods::ids()
        .into_iter()
        .filter_map(|id| PAPERS.iter().find(|p| p.id == id))
        .collect()
}

/// Runs the requested reproductions and writes `index.html` (claims, figures, notes, timing) into
/// the output folder; fails if any reproduction fails to run (a claim that differs from the paper
/// is reported, not an error).
pub fn run(args: &Args) -> Result<Outcome, Failure> {
    let selected: Vec<&Paper> = papers()
        .into_iter()
        .filter(|p| args.paper == "all" || p.id == args.paper)
        .collect();
    if selected.is_empty() {
        let ids: Vec<&str> = papers().iter().map(|p| p.id).collect();
        return Err(Failure::Input(format!(
            "unknown paper '{}'; expected 'all' or one of: {}",
            args.paper,
            ids.join(", ")
        )));
    }
    let mut summary = Vec::new();
    let mut done: Vec<(&Paper, Reproduction, Duration)> = Vec::new();
    for paper in selected {
        let (id, title) = (paper.id, paper.title);
        let dir = args.out.join(id);
        let start = Instant::now();
        let reproduction = (paper.run)(&dir).map_err(|e| Failure::Run(format!("{id}: {e}")))?;
        let elapsed = start.elapsed();
        if args.json {
            for claim in &reproduction.claims {
                println!("{}", claim.to_json(id));
            }
            for figure in &reproduction.figures {
                println!(
                    "{}",
                    serde_json::json!({"paper": id, "figure": figure.display().to_string()})
                );
            }
        } else {
            println!("{}", reproduction.table(&format!("{id} ({title})")));
        }
        summary.push((id, reproduction.tally()));
        done.push((paper, reproduction, elapsed));
    }
    let sections: Vec<Section<'_>> = done
        .iter()
        .map(|(p, r, elapsed)| Section {
            id: p.id,
            title: p.title,
            reproduction: r,
            elapsed: *elapsed,
        })
        .collect();
    let index = args.out.join("index.html");
    std::fs::write(&index, index_html(&sections, &args.out))
        .map_err(|e| Failure::Run(format!("{}: {e}", index.display())))?;
    if !args.json {
        println!(
            "{:<14} {:>6} {:>8} {:>6} {:>13}",
            "paper", "match", "differs", "beats", "not-in-paper"
        );
        for (id, [m, d, b, n]) in summary {
            println!("{id:<14} {m:>6} {d:>8} {b:>6} {n:>13}");
        }
    }
    Ok(Outcome::Certified)
}
