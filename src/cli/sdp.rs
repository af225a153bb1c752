//! `sporadic sdp`: solve SDPA sparse files and benchmark the solver on a directory of them.
//!
//! Exit status of `sdp solve` ([`run`]): [`EXIT_SOLVED`] (0) when the status is optimal or
//! almost optimal, [`EXIT_NOT_SOLVED`] (1) for any other status (infeasible, iteration limit,
//! interrupted by `--time-limit`, numerical trouble), [`EXIT_BAD_INPUT`] (2) for input that
//! could not be used (unreadable or malformed problem or solution file, a starting point that
//! does not fit the problem, invalid options, an unwritable `--write-solution` path). `sdp bench` exits with 0 once the table is
//! printed and with 2 on bad input.

use sporadic_sdp::sdpa::{SdpaObjectives, sdpa_status_id, sdpa_status_name};
use sporadic_sdp::{
    Problem, Settings, Solution, read_sdpa_file, read_solution_file, sdpa_objectives,
    write_solution_file,
};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command as Process, ExitCode};
use std::time::Instant;

/// Exit code of a solve that ended optimal or almost optimal.
pub const EXIT_SOLVED: u8 = 0;
/// Exit code of a solve that ended with any other status.
pub const EXIT_NOT_SOLVED: u8 = 1;
/// Exit code for input that could not be used (files, starting point, options).
pub const EXIT_BAD_INPUT: u8 = 2;

/// The help text on exit codes of `sdp solve`.
const SOLVE_EXIT_HELP: &str = "Exit status:
  0  solved: status optimal, or almost optimal (stopped early with every DIMACS error
     within the reduced tolerance, --tol-reduced)
  1  not solved: infeasible (SDPA primal or dual), iteration limit, interrupted
     (--time-limit ran out), numerical trouble
  2  bad input: unreadable or malformed problem or solution file, a starting point that
     does not fit the problem, invalid options, an unwritable --write-solution path

Solution files use CSDP's format: the first line holds y; then lines `1 b i j v` give the
dual slack Z = S and lines `2 b i j v` the primal X (block b, entry (i,j), upper triangle,
1-based; LP blocks as diagonal entries i = j).";

/// Arguments of `sporadic sdp`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    command: SdpCommand,
}

#[derive(Debug, clap::Subcommand)]
enum SdpCommand {
    /// Solve one SDPA sparse file (`.dat-s`) and print status, objectives, iterations, DIMACS
    /// errors and time.
    #[command(after_help = SOLVE_EXIT_HELP)]
    Solve {
        /// The `.dat-s` file.
        file: PathBuf,
        /// Print one JSON object instead of the human summary.
        #[arg(long)]
        json: bool,
        /// Print one line per interior-point iteration (to standard error).
        #[arg(long, short)]
        verbose: bool,
        /// Write the returned point (whatever the status) to this file in CSDP's solution
        /// format.
        #[arg(long, value_name = "OUT")]
        write_solution: Option<PathBuf>,
        /// Start the interior-point method from the point in this CSDP-format solution file;
        /// blocks of X or Z that are not positive definite are shifted to the default starting
        /// level by a multiple of the identity.
        #[arg(long, value_name = "IN")]
        initial_solution: Option<PathBuf>,
        #[command(flatten)]
        options: SolveOptions,
    },
    /// Solve every `.dat-s` file in a directory and compare with the optimal values listed in
    /// the directory's `README-SDPLIB.md` (if present).
    Bench {
        /// Directory with `.dat-s` files.
        dir: PathBuf,
        /// Also run the `csdp` binary on each file and show both times and their ratio.
        #[arg(long)]
        vs_csdp: bool,
        /// Only files whose name contains this string.
        #[arg(long)]
        filter: Option<String>,
    },
}

/// Stopping rule and threads of `sdp solve` (the solver's defaults when omitted).
#[derive(Debug, clap::Args)]
struct SolveOptions {
    /// Relative duality gap and complementarity to stop at (default 1e-8).
    #[arg(long, value_name = "TOL")]
    tol_gap: Option<f64>,
    /// Relative primal and dual infeasibility to stop at (default 1e-8).
    #[arg(long, value_name = "TOL")]
    tol_feas: Option<f64>,
    /// Reduced tolerance: an early stop with every DIMACS error within it is "almost optimal"
    /// (default 1e-6).
    #[arg(long, value_name = "TOL")]
    tol_reduced: Option<f64>,
    /// Iteration limit (default 100).
    #[arg(long, value_name = "N")]
    max_iterations: Option<usize>,
    /// Worker threads: 1 = the calling thread only, 0 = automatic (default).
    #[arg(long, value_name = "N")]
    threads: Option<usize>,
    /// Wall-time budget in seconds; when it runs out the solve stops with status
    /// `interrupted` (or `almost optimal` if the point it has is accurate to the reduced
    /// tolerance) and returns the best point found.
    #[arg(long, value_name = "SECONDS")]
    time_limit: Option<f64>,
}

impl SolveOptions {
    /// The solver settings with these overrides; the solver rejects non-positive or non-finite
    /// tolerances with a typed error.
    fn settings(&self) -> Settings {
        let mut s = Settings::default();
        s.tol_gap = self.tol_gap.unwrap_or(s.tol_gap);
        s.tol_feas = self.tol_feas.unwrap_or(s.tol_feas);
        s.tol_reduced = self.tol_reduced.unwrap_or(s.tol_reduced);
        s.max_iterations = self.max_iterations.unwrap_or(s.max_iterations);
        s.threads = self.threads.unwrap_or(s.threads);
        s
    }

    /// The budget of `--time-limit`.
    fn budget(&self) -> Result<sporadic_sdp::Budget, String> {
        match self.time_limit {
            Some(t) if !(t.is_finite() && t > 0.0) => Err(format!(
                "--time-limit must be a positive number of seconds, got {t}"
            )),
            t => Ok(sporadic_sdp::Budget::for_duration(
                t.map(std::time::Duration::from_secs_f64),
            )),
        }
    }
}

/// Runs `sporadic sdp ...` and returns its exit code (see the [module documentation](self));
/// errors are printed to standard error as one `error: ...` line.
pub fn run(args: &Args) -> ExitCode {
    let result = match &args.command {
        SdpCommand::Solve {
            file,
            json,
            verbose,
            write_solution,
            initial_solution,
            options,
        } => options.budget().and_then(|budget| {
            sporadic_sdp::budget::within(budget, || {
                solve(
                    file,
                    *json,
                    *verbose,
                    options.settings(),
                    initial_solution.as_deref(),
                    write_solution.as_deref(),
                )
            })
        }),
        SdpCommand::Bench {
            dir,
            vs_csdp,
            filter,
        } => bench(dir, *vs_csdp, filter.as_deref()).map(|()| EXIT_SOLVED),
    };
    ExitCode::from(result.unwrap_or_else(|message| {
        eprintln!("error: {message}");
        EXIT_BAD_INPUT
    }))
}

/// Reads a problem file.
fn read_problem(file: &Path) -> Result<Problem, String> {
    read_sdpa_file(file).map_err(|e| format!("{}: {e}", file.display()))
}

/// Solves a problem read from `file` (from `start` if given); returns the solution and the
/// SDPA-convention objectives.
fn solve_problem(
    file: &Path,
    problem: &Problem,
    settings: &Settings,
    start: Option<&sporadic_sdp::Point>,
) -> Result<(Solution, SdpaObjectives), String> {
    let solution = match start {
        Some(p) => sporadic_sdp::solve_from(problem, settings, p),
        None => sporadic_sdp::solve(problem, settings),
    }
    .map_err(|e| format!("{}: {e}", file.display()))?;
    let objectives = sdpa_objectives(&solution);
    Ok((solution, objectives))
}

fn solve(
    file: &Path,
    json: bool,
    verbose: bool,
    mut settings: Settings,
    initial: Option<&Path>,
    write: Option<&Path>,
) -> Result<u8, String> {
    if verbose {
        eprintln!(
            "iter  primal obj         dual obj           rel gap   p.infeas  d.infeas  mu        step p    step d"
        );
        settings.log = Some(std::sync::Arc::new(|l: &sporadic_sdp::IterationLog| {
            eprintln!(
                "{:4}  {:+.10e} {:+.10e} {:.2e}  {:.2e}  {:.2e}  {:.2e}  {:.2e}  {:.2e}",
                l.iteration,
                l.primal_objective,
                l.dual_objective,
                l.rel_gap,
                l.primal_infeas,
                l.dual_infeas,
                l.mu,
                l.primal_step,
                l.dual_step
            );
        }));
    }
    let started = Instant::now();
    let problem = read_problem(file)?;
    let start = initial
        .map(|path| {
            read_solution_file(path, &problem).map_err(|e| format!("{}: {e}", path.display()))
        })
        .transpose()?;
    let (solution, objectives) = solve_problem(file, &problem, &settings, start.as_ref())?;
    let seconds = started.elapsed().as_secs_f64();
    let (sdpa_primal, sdpa_dual) = (objectives.primal, objectives.dual);
    let m = &solution.measures;
    let status = solution.status;
    if json {
        println!(
            "{}",
            serde_json::json!({
                "file": file.display().to_string(),
                "status": sdpa_status_id(status),
                "solved": status.is_solved(),
                "primal_objective_sdpa": sdpa_primal,
                "dual_objective_sdpa": sdpa_dual,
                "iterations": solution.iterations,
                "rel_gap": m.rel_gap,
                "primal_infeasibility": m.primal_infeas,
                "dual_infeasibility": m.dual_infeas,
                "dimacs": m.dimacs,
                "dimacs_max": m.dimacs_max(),
                "tol_reduced": settings.tol_reduced,
                "initial_solution": initial.map(|p| p.display().to_string()),
                "seconds": seconds,
            })
        );
    } else {
        println!("file        {}", file.display());
        if let Some(p) = initial {
            println!("start       {}", p.display());
        }
        let detail = match status {
            sporadic_sdp::Status::AlmostOptimal => format!(
                " (reduced accuracy: every DIMACS error ≤ {:.0e}, largest {:.2e})",
                settings.tol_reduced,
                m.dimacs_max()
            ),
            _ => String::new(),
        };
        println!("status      {}{detail}", sdpa_status_name(status));
        println!("objective   {sdpa_primal:.10e} (SDPA primal)   {sdpa_dual:.10e} (SDPA dual)");
        println!("iterations  {}", solution.iterations);
        println!(
            "rel. gap    {:.2e}   rel. primal infeas. {:.2e}   rel. dual infeas. {:.2e}",
            m.rel_gap, m.primal_infeas, m.dual_infeas
        );
        let d = m.dimacs;
        println!(
            "DIMACS      {:.2e} {:.2e} {:.2e} {:.2e} {:.2e} {:.2e}",
            d[0], d[1], d[2], d[3], d[4], d[5]
        );
        println!("time        {seconds:.4} s");
    }
    if let Some(out) = write {
        write_solution_file(out, &solution.y, &solution.x, &solution.s)
            .map_err(|e| format!("--write-solution {}: {e}", out.display()))?;
    }
    Ok(if status.is_solved() {
        EXIT_SOLVED
    } else {
        EXIT_NOT_SOLVED
    })
}

/// Optimal values from SDPLIB's README table: lines `| name | m | n | ... | optimum |` or
/// whitespace-separated `name m n ... optimum`; the last numeric-looking field that parses as a
/// float is taken as the optimum. Infeasible problems have no value.
fn read_optima(dir: &Path) -> BTreeMap<String, f64> {
    let mut optima = BTreeMap::new();
    let Ok(text) = std::fs::read_to_string(dir.join("README-SDPLIB.md")) else {
        return optima;
    };
    for line in text.lines() {
        let fields: Vec<&str> = line
            .split(|c: char| c == '|' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let Some(name) = fields.first() else { continue };
        if !dir.join(format!("{name}.dat-s")).exists() {
            continue;
        }
        if let Some(v) = fields.iter().rev().find_map(|f| {
            let f = f.trim_matches('*');
            (f.contains('e') || f.contains('.'))
                .then(|| f.parse::<f64>().ok())
                .flatten()
        }) {
            optima.insert((*name).to_string(), v);
        }
    }
    optima
}

/// Runs `csdp` on a file and returns its wall time in seconds, or a reason it could not run.
fn time_csdp(file: &Path) -> Result<f64, String> {
    let out = std::env::temp_dir().join(format!("sporadic-csdp-{}.sol", std::process::id()));
    let start = Instant::now();
    let status = Process::new("csdp")
        .arg(file)
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .map_err(|e| format!("cannot run csdp: {e}"))?;
    let seconds = start.elapsed().as_secs_f64();
    let _ = std::fs::remove_file(&out);
    // CSDP exits with 0 (success) .. 4 (partial success) for a completed run.
    match status.code() {
        Some(0..=4) => Ok(seconds),
        other => Err(format!("csdp exited with {other:?}")),
    }
}

fn bench(dir: &Path, vs_csdp: bool, filter: Option<&str>) -> Result<(), String> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("cannot read directory {}: {e}", dir.display()))?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "dat-s"))
        .filter(|p| filter.is_none_or(|f| p.to_string_lossy().contains(f)))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(format!("no .dat-s files in {}", dir.display()));
    }
    let optima = read_optima(dir);
    print!(
        "{:<12} {:>18} {:>16} {:>9} {:>5} {:>22} {:>10} {:>9}",
        "problem",
        "ours (SDPA obj.)",
        "reference",
        "rel.err",
        "iter",
        "status",
        "DIMACS max",
        "time[s]"
    );
    if vs_csdp {
        print!(" {:>9} {:>7}", "csdp[s]", "ratio");
    }
    println!();
    for file in &files {
        let name = file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        // Wall time of reading plus solving.
        let started = Instant::now();
        let solved =
            read_problem(file).and_then(|p| solve_problem(file, &p, &Settings::default(), None));
        let seconds = started.elapsed().as_secs_f64();
        let (solution, objectives) = match solved {
            Ok(r) => r,
            Err(e) => {
                println!("{name:<12} error: {e}");
                continue;
            }
        };
        let primal = objectives.primal;
        let reference = optima.get(&name).copied();
        let rel = reference
            .map(|r| format!("{:.1e}", (primal - r).abs() / r.abs().max(1.0)))
            .unwrap_or_else(|| "-".into());
        let reference = reference
            .map(|r| format!("{r:.6e}"))
            .unwrap_or_else(|| "-".into());
        print!(
            "{name:<12} {primal:>18.9e} {reference:>16} {rel:>9} {:>5} {:>22} {:>10.1e} {seconds:>9.4}",
            solution.iterations,
            sdpa_status_name(solution.status),
            solution.measures.dimacs_max()
        );
        if vs_csdp {
            match time_csdp(file) {
                Ok(t) => print!(" {t:>9.4} {:>7.2}", seconds / t),
                Err(e) => print!(" {e}"),
            }
        }
        println!();
    }
    Ok(())
}
