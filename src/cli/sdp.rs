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
    /// Solve every `.dat-s` file in a directory, each in its own process (`sdp solve --json`:
    /// whole-process wall time and peak memory), and compare with the optimal values listed in
    /// the directory's `README-SDPLIB.md` (if present; its footnotes that correct a value are
    /// applied); with `--vs-csdp`, run the `csdp` binary the same way and report both, their
    /// ratios, and the problems on which both solvers agree with each other but not with the
    /// README's value; `--table DIR` writes the table
    /// as `sdplib.md` and `sdplib.csv`. A problem whose first run takes less than a second is
    /// run again (ours and CSDP alternately) until each has used a second or run five times,
    /// and the shortest time of each is reported: process start-up and the machine's noise
    /// would otherwise decide the ratio of a 20 ms solve.
    Bench {
        /// Directory with `.dat-s` files.
        dir: PathBuf,
        /// Also run the `csdp` binary on each file and show both times and their ratio.
        #[arg(long)]
        vs_csdp: bool,
        /// Only files whose name contains this string.
        #[arg(long)]
        filter: Option<String>,
        /// Skip problems whose matrix order n (sum of the block sizes) exceeds this (they are
        /// listed as skipped, with their size).
        #[arg(long, value_name = "N", default_value_t = 2000)]
        max_n: usize,
        /// Write the table to DIR/sdplib.md and DIR/sdplib.csv.
        #[arg(long, value_name = "DIR")]
        table: Option<PathBuf>,
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
    /// Solve the problem as given, without first removing constraints `⟨A_i, X⟩ = 0` with a
    /// semidefinite `A_i` by facial reduction (for comparisons).
    #[arg(long)]
    no_facial_reduction: bool,
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
        s.facial_reduction = !self.no_facial_reduction;
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
            max_n,
            table,
        } => {
            bench(dir, *vs_csdp, filter.as_deref(), *max_n, table.as_deref()).map(|()| EXIT_SOLVED)
        }
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
                "facial": solution.facial.to_string(),
                "restarted": solution.restarted,
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
        if solution.facial != sporadic_sdp::FacialPath::NotReduced {
            println!("facial      {}", solution.facial);
        }
        if solution.restarted {
            println!(
                "restarted   the first run from the default point ended in numerical trouble; \
                 the iterations count both runs"
            );
        }
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
/// float is taken as the optimum. Infeasible problems have no value. A footnote of the form
/// ``The optimal objective value for `name` was found to be `value` `` replaces the table's
/// value (SDPLIB 1.2's README corrects qap10, printed `-1.093e+01`, to `-1.093e+03` this way).
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
    for line in text.lines() {
        if let Some((name, value)) = corrected_optimum(line) {
            optima.insert(name.to_string(), value);
        }
    }
    optima
}

/// The problem and value of a README footnote
/// ``… optimal objective value for `name` was found to be `value` …``.
fn corrected_optimum(line: &str) -> Option<(&str, f64)> {
    let rest = line.split_once("optimal objective value for `")?.1;
    let (name, rest) = rest.split_once('`')?;
    let value = rest.split_once("found to be `")?.1.split_once('`')?.0;
    Some((name, value.parse().ok()?))
}

/// Most runs of one program on one problem in `sdp bench` (see `sdp bench --help`).
const REPEATS: usize = 5;
/// A program is run again while its runs on the problem have used less than this many seconds.
const REPEAT_SECONDS: f64 = 1.0;

/// One measured child process: wall time, peak resident memory, exit code, standard output.
struct Measured {
    seconds: f64,
    peak_mib: Option<f64>,
    code: Option<i32>,
    stdout: String,
}

/// Runs `program args` to completion and measures its wall time and, when GNU time is
/// installed at `/usr/bin/time`, its peak resident set size (`%M`, the kernel's `ru_maxrss` of
/// the child).
fn measure(program: &Path, args: &[&std::ffi::OsStr]) -> Result<Measured, String> {
    let gnu_time = Path::new("/usr/bin/time");
    let rss_file = std::env::temp_dir().join(format!("sporadic-bench-rss-{}", std::process::id()));
    let mut cmd = if gnu_time.exists() {
        let mut c = Process::new(gnu_time);
        c.arg("-f").arg("%M").arg("-o").arg(&rss_file).arg(program);
        c
    } else {
        Process::new(program)
    };
    cmd.args(args).stderr(std::process::Stdio::null());
    let start = Instant::now();
    let out = cmd
        .output()
        .map_err(|e| format!("cannot run {}: {e}", program.display()))?;
    let seconds = start.elapsed().as_secs_f64();
    let peak_mib = std::fs::read_to_string(&rss_file)
        .ok()
        .and_then(|t| t.lines().last()?.trim().parse::<f64>().ok())
        .map(|kib| kib / 1024.0);
    let _ = std::fs::remove_file(&rss_file);
    Ok(Measured {
        seconds,
        peak_mib,
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
    })
}

/// `m` and the matrix order `n` (sum of the block sizes) from the header of an SDPA file.
fn sdpa_size(file: &Path) -> Result<(usize, usize), String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let mut numbers = text
        .lines()
        .filter(|l| !l.trim_start().starts_with(['"', '*']) && !l.trim().is_empty())
        .take(3)
        .map(|l| {
            l.split(|c: char| c.is_whitespace() || "{}(),".contains(c))
                .filter_map(|f| f.parse::<i64>().ok())
                .collect::<Vec<_>>()
        });
    let bad = || format!("{}: malformed SDPA header", file.display());
    let m = *numbers
        .next()
        .and_then(|v| v.first().copied())
        .as_ref()
        .ok_or_else(bad)?;
    let blocks = numbers
        .next()
        .and_then(|v| v.first().copied())
        .ok_or_else(bad)?;
    let sizes = numbers.next().ok_or_else(bad)?;
    if m < 0 || blocks < 1 || sizes.len() < blocks as usize {
        return Err(bad());
    }
    let n = sizes[..blocks as usize]
        .iter()
        .map(|b| b.unsigned_abs() as usize)
        .sum();
    Ok((m as usize, n))
}

/// CSDP's result from its standard output.
struct CsdpSummary {
    status: String,
    iterations: Option<usize>,
    /// `Primal objective value:` (CSDP prints it in SDPLIB's sign convention).
    objective: Option<f64>,
    /// Largest DIMACS error.
    dimacs: Option<f64>,
}

/// Reads [`CsdpSummary`] from CSDP's exit code and standard output.
fn csdp_summary(code: Option<i32>, stdout: &str) -> CsdpSummary {
    let status = match code {
        Some(0) => "success",
        Some(1) => "primal infeasible",
        Some(2) => "dual infeasible",
        Some(3) => "partial success",
        Some(4) => "iteration limit",
        Some(5) => "stuck at edge of primal feasibility",
        Some(6) => "stuck at edge of dual infeasibility",
        Some(7) => "lack of progress",
        Some(8) => "singular matrix",
        Some(_) => "failed",
        None => "killed",
    };
    let iterations = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("Iter:"))
        .filter_map(|l| l.split_whitespace().next()?.parse::<usize>().ok())
        .next_back();
    let dimacs = stdout
        .lines()
        .find_map(|l| l.strip_prefix("DIMACS error measures:"))
        .map(|l| {
            l.split_whitespace()
                .filter_map(|f| f.parse::<f64>().ok())
                .map(f64::abs)
                .fold(0.0, f64::max)
        });
    let objective = stdout
        .lines()
        .find_map(|l| l.strip_prefix("Primal objective value:"))
        .and_then(|v| v.trim().parse().ok());
    CsdpSummary {
        status: status.into(),
        iterations,
        objective,
        dimacs,
    }
}

/// Relative distance `|a − b| / max(|b|, 1)` of an objective from a reference.
fn rel_err(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1.0)
}

/// One row of the benchmark table.
#[derive(Default)]
struct Row {
    name: String,
    m: usize,
    n: usize,
    cells: Vec<String>,
    time_ratio: Option<f64>,
    memory_ratio: Option<f64>,
    /// Set when ours and CSDP agree on an objective the README does not print.
    disputed: Option<String>,
}

fn fmt_opt(x: Option<f64>, f: impl Fn(f64) -> String) -> String {
    x.map_or_else(|| "-".into(), f)
}

/// Solves every problem of `dir` (n ≤ `max_n`) in its own process, with CSDP beside it when
/// asked, prints the table and writes it when asked.
fn bench(
    dir: &Path,
    vs_csdp: bool,
    filter: Option<&str>,
    max_n: usize,
    table: Option<&Path>,
) -> Result<(), String> {
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
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?;
    if vs_csdp && Process::new("csdp").arg("-h").output().is_err() {
        return Err("--vs-csdp: the csdp binary is not on PATH (Debian: coinor-csdp)".into());
    }
    let optima = read_optima(dir);
    let mut header = vec![
        "problem",
        "m",
        "n",
        "status",
        "iter",
        "rel. err",
        "DIMACS max",
        "time [s]",
        "peak [MiB]",
    ];
    if vs_csdp {
        header.extend([
            "CSDP status",
            "CSDP iter",
            "CSDP rel. err",
            "CSDP DIMACS max",
            "CSDP time [s]",
            "CSDP peak [MiB]",
            "time ours/CSDP",
            "memory ours/CSDP",
        ]);
    }
    println!("{}", header.join(" | "));
    let mut rows = Vec::new();
    let mut skipped = Vec::new();
    for file in &files {
        let name = file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let (m, n) = sdpa_size(file)?;
        if n > max_n {
            skipped.push(format!("{name} (m = {m}, n = {n})"));
            continue;
        }
        let mut row = Row {
            name: name.clone(),
            m,
            n,
            ..Row::default()
        };
        let ours_args: [&std::ffi::OsStr; 4] = [
            "sdp".as_ref(),
            "solve".as_ref(),
            "--json".as_ref(),
            file.as_os_str(),
        ];
        let csdp_out =
            std::env::temp_dir().join(format!("sporadic-csdp-{}.sol", std::process::id()));
        let csdp_args = [file.as_os_str(), csdp_out.as_os_str()];
        let mut run = measure(&exe, &ours_args)?;
        let mut csdp = if vs_csdp {
            Some(measure(Path::new("csdp"), &csdp_args)?)
        } else {
            None
        };
        let _ = std::fs::remove_file(&csdp_out);
        let (mut used, mut used_csdp) = (run.seconds, csdp.as_ref().map_or(0.0, |c| c.seconds));
        for _ in 1..REPEATS {
            if used >= REPEAT_SECONDS && (csdp.is_none() || used_csdp >= REPEAT_SECONDS) {
                break;
            }
            let again = measure(&exe, &ours_args)?;
            used += again.seconds;
            run.seconds = run.seconds.min(again.seconds);
            if let Some(c) = csdp.as_mut() {
                let again = measure(Path::new("csdp"), &csdp_args)?;
                let _ = std::fs::remove_file(&csdp_out);
                used_csdp += again.seconds;
                c.seconds = c.seconds.min(again.seconds);
            }
        }
        let json: Option<serde_json::Value> = serde_json::from_str(run.stdout.trim()).ok();
        let get = |k: &str| json.as_ref().and_then(|j| j.get(k)).cloned();
        let primal = get("primal_objective_sdpa").and_then(|v| v.as_f64());
        let reference = optima.get(&name).copied();
        let rel = primal.zip(reference).map(|(p, r)| rel_err(p, r));
        row.cells = vec![
            get("status")
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_else(|| format!("failed (exit {:?})", run.code)),
            fmt_opt(get("iterations").and_then(|v| v.as_f64()), |x| {
                format!("{x:.0}")
            }),
            fmt_opt(rel, |x| format!("{x:.1e}")),
            fmt_opt(get("dimacs_max").and_then(|v| v.as_f64()), |x| {
                format!("{x:.1e}")
            }),
            format!("{:.3}", run.seconds),
            fmt_opt(run.peak_mib, |x| format!("{x:.0}")),
        ];
        if let Some(c) = csdp {
            let CsdpSummary {
                status,
                iterations,
                objective,
                dimacs,
            } = csdp_summary(c.code, &c.stdout);
            // Both solvers agree with each other (1e-6) but not with the README (1e-4): the
            // README's optimum is doubtful.
            if let (Some(p), Some(q), Some(r)) = (primal, objective, reference)
                && rel_err(p, q) <= 1e-6
                && rel_err(p, r) > 1e-4
                && rel_err(q, r) > 1e-4
            {
                row.disputed = Some(format!("{name} (README {r:e}, ours {p:.7e}, CSDP {q:.7e})"));
            }
            row.time_ratio = Some(run.seconds / c.seconds);
            row.memory_ratio = run.peak_mib.zip(c.peak_mib).map(|(a, b)| a / b);
            row.cells.extend([
                status,
                fmt_opt(iterations.map(|i| i as f64), |x| format!("{x:.0}")),
                fmt_opt(objective.zip(reference).map(|(q, r)| rel_err(q, r)), |x| {
                    format!("{x:.1e}")
                }),
                fmt_opt(dimacs, |x| format!("{x:.1e}")),
                format!("{:.3}", c.seconds),
                fmt_opt(c.peak_mib, |x| format!("{x:.0}")),
                fmt_opt(row.time_ratio, |x| format!("{x:.2}")),
                fmt_opt(row.memory_ratio, |x| format!("{x:.2}")),
            ]);
        }
        println!("{name} | {m} | {n} | {}", row.cells.join(" | "));
        rows.push(row);
    }
    let summary = bench_summary(&rows, &skipped, max_n, vs_csdp);
    for line in &summary {
        println!("{line}");
    }
    if let Some(out) = table {
        write_table(out, &header, &rows, &summary)?;
    }
    Ok(())
}

/// The median and extremes of the ratios, and the skipped problems.
fn bench_summary(rows: &[Row], skipped: &[String], max_n: usize, vs_csdp: bool) -> Vec<String> {
    let mut out = vec![format!("{} problems run (n ≤ {max_n})", rows.len())];
    if vs_csdp {
        let mut ratios: Vec<(f64, &str)> = rows
            .iter()
            .filter_map(|r| r.time_ratio.map(|t| (t, r.name.as_str())))
            .collect();
        ratios.sort_by(|a, b| a.0.total_cmp(&b.0));
        if let Some(&(worst, name)) = ratios.last() {
            let median = ratios[ratios.len() / 2].0;
            let above = ratios.iter().filter(|r| r.0 > 1.5).count();
            out.push(format!(
                "time ours/CSDP (whole process): median {median:.2}, largest {worst:.2} ({name}), \
                 {above} above 1.5"
            ));
        }
        let mut mem: Vec<f64> = rows.iter().filter_map(|r| r.memory_ratio).collect();
        mem.sort_by(f64::total_cmp);
        if let Some(&worst) = mem.last() {
            out.push(format!(
                "peak memory ours/CSDP: median {:.2}, largest {worst:.2}",
                mem[mem.len() / 2]
            ));
        }
    }
    let disputed: Vec<&str> = rows.iter().filter_map(|r| r.disputed.as_deref()).collect();
    if !disputed.is_empty() {
        out.push(format!(
            "README optimum doubtful (ours and CSDP agree within 1e-6 relative, both more than \
             1e-4 from the README's value): {}",
            disputed.join("; ")
        ));
    }
    if !skipped.is_empty() {
        out.push(format!("skipped (n > {max_n}): {}", skipped.join(", ")));
    }
    out
}

/// Writes `sdplib.md` and `sdplib.csv` into `dir`.
fn write_table(
    dir: &Path,
    header: &[&str],
    rows: &[Row],
    summary: &[String],
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("--table {}: {e}", dir.display()))?;
    let mut md = String::new();
    md.push_str(&format!("| {} |\n", header.join(" | ")));
    md.push_str(&format!(
        "|{}\n",
        header.iter().map(|_| "---|").collect::<String>()
    ));
    let mut csv = header
        .iter()
        .map(|h| h.replace(' ', "_"))
        .collect::<Vec<_>>()
        .join(",");
    csv.push('\n');
    for r in rows {
        let mut cells = vec![r.name.clone(), r.m.to_string(), r.n.to_string()];
        cells.extend(r.cells.iter().cloned());
        md.push_str(&format!("| {} |\n", cells.join(" | ")));
        csv.push_str(&cells.join(","));
        csv.push('\n');
    }
    md.push('\n');
    for line in summary {
        md.push_str(&format!("{line}\n\n"));
    }
    for (name, text) in [("sdplib.md", md), ("sdplib.csv", csv)] {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_readme_footnote_corrects_the_table() {
        let dir = std::env::temp_dir().join(format!("sporadic-optima-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for name in ["qap10", "qap9"] {
            std::fs::write(dir.join(format!("{name}.dat-s")), "").unwrap();
        }
        std::fs::write(
            dir.join("README-SDPLIB.md"),
            "| qap9 | 748 | 82 | -1.409e+03 | 9 |\n\
             | qap10 | 1021 | 101 | -1.093e+01 | 9, 14 |\n\
             14. The optimal objective value for `qap10` was found to be `-1.093e+03`\n",
        )
        .unwrap();
        let optima = read_optima(&dir);
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(optima.get("qap9"), Some(&-1409.0));
        assert_eq!(optima.get("qap10"), Some(&-1093.0));
        assert_eq!(corrected_optimum("14. no value here"), None);
    }

    #[test]
    fn csdp_output_is_read() {
        let out = "Iter: 13 Ap: 1.00e+00 Pobj:  2.2615735e+02 Ad: 1.00e+00 Dobj:  2.2615735e+02\n\
                   Success: SDP solved\n\
                   Primal objective value: 2.2615735e+02 \n\
                   Dual objective value: 2.2615736e+02 \n\
                   DIMACS error measures: 1.19e-15 0.00e+00 2.31e-15 0.00e+00 -4.11e-09 -4.15e-09\n";
        let c = csdp_summary(Some(0), out);
        assert_eq!(c.status, "success");
        assert_eq!(c.iterations, Some(13));
        assert_eq!(c.objective, Some(226.15735));
        assert_eq!(c.dimacs, Some(4.15e-9));
    }
}
