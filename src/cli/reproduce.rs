//! `sporadic reproduce`: runs the paper reproductions and prints their checked claims.

use sporadic_report::Reproduction;
use std::path::{Path, PathBuf};

/// Arguments of `sporadic reproduce`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// `all`, or one of the paper ids listed by `sporadic reproduce all`.
    pub paper: String,
    /// Print one JSON object per checked claim, then one `{"paper", "figure"}` object per figure
    /// written, instead of the human table.
    #[arg(long)]
    pub json: bool,
    /// Folder for the figures (one sub-folder per paper).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
}

type Runner = fn(&Path) -> Result<Reproduction, String>;

/// The papers of the project, in seed order: id, title, and the reproduction if it has landed.
const PAPERS: [(&str, &str, Option<Runner>); 5] = [
    (
        "ferrante2016",
        "Ferrante et al. 2016, observer with sporadic measurements",
        Some(ferrante2016),
    ),
    (
        "sferlazza2021",
        "Sferlazza et al. 2021, round-robin observer with jitter",
        Some(sferlazza2021),
    ),
    (
        "andrieu2014",
        "Andrieu et al. 2014, high-gain observer with updated sampling",
        Some(andrieu2014),
    ),
    (
        "etienne2017",
        "Etienne et al. 2017, impulsive observer for Lipschitz systems",
        Some(etienne2017),
    ),
    (
        "rabehi2021",
        "Rabehi et al. 2021, interval impulsive observer",
        Some(rabehi2021),
    ),
];

fn ferrante2016(out: &Path) -> Result<Reproduction, String> {
    sporadic_ferrante2016::reproduce(out).map_err(|e| e.to_string())
}

fn sferlazza2021(out: &Path) -> Result<Reproduction, String> {
    sporadic_sferlazza2021::reproduce(out).map_err(|e| e.to_string())
}

fn andrieu2014(out: &Path) -> Result<Reproduction, String> {
    sporadic_andrieu2014::reproduce(out).map_err(|e| e.to_string())
}

fn etienne2017(out: &Path) -> Result<Reproduction, String> {
    sporadic_etienne2017::reproduce(out).map_err(|e| e.to_string())
}

fn rabehi2021(out: &Path) -> Result<Reproduction, String> {
    sporadic_rabehi2021::reproduce(out).map_err(|e| e.to_string())
}

/// Runs the requested reproductions; fails if any reproduction fails to run (a claim that
/// differs from the paper is reported, not an error).
pub fn run(args: &Args) -> Result<(), String> {
    let selected: Vec<_> = PAPERS
        .iter()
        .filter(|(id, _, _)| args.paper == "all" || *id == args.paper)
        .collect();
    if selected.is_empty() {
        let ids: Vec<&str> = PAPERS.iter().map(|(id, _, _)| *id).collect();
        return Err(format!(
            "unknown paper '{}'; expected 'all' or one of: {}",
            args.paper,
            ids.join(", ")
        ));
    }
    let mut summary = Vec::new();
    for (id, title, runner) in selected {
        let Some(runner) = runner else {
            if args.json {
                println!(
                    "{}",
                    serde_json::json!({"paper": id, "claim": "reproduction", "paper_value": null,
                        "ours": null, "tolerance": null, "status": "not-implemented"})
                );
            } else {
                println!("== {id} ({title}) ==\nreproduction not implemented yet\n");
            }
            continue;
        };
        let dir = args.out.join(id);
        let reproduction = runner(&dir).map_err(|e| format!("{id}: {e}"))?;
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
        summary.push((*id, reproduction.tally()));
    }
    if !args.json {
        println!(
            "{:<14} {:>6} {:>8} {:>6} {:>13}",
            "paper", "match", "differs", "beats", "not-in-paper"
        );
        for (id, [m, d, b, n]) in summary {
            println!("{id:<14} {m:>6} {d:>8} {b:>6} {n:>13}");
        }
    }
    Ok(())
}
