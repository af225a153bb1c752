//! `sporadic design`, `sporadic max-interval` and `sporadic compare`: observer design for a
//! user's plant file, printed as text or as the typed reports of `sporadic_model::report`.

use super::{Failure, Outcome};
use sporadic::methods;
use sporadic::plant_file::PlantFile;
use sporadic_model::{
    DesignReport, MaxIntervalReport, MethodError, MethodOptions, NamedMatrix, ObserverMethod,
    Probe, SamplingScenario, Scenario, Status, Trajectory,
};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

/// How a report is printed.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct Format {
    /// Print the report as one JSON object (schema in README, "Reports").
    #[arg(long, conflicts_with = "toml")]
    pub json: bool,
    /// Print the report as a TOML document (same fields as --json).
    #[arg(long)]
    pub toml: bool,
}

/// A method id, checked against the registry.
fn method_arg(id: &str) -> Result<String, String> {
    let ids = methods::ids();
    if ids.contains(&id) {
        Ok(id.to_string())
    } else {
        Err(format!(
            "unknown method '{id}'; expected one of: {}",
            ids.join(", ")
        ))
    }
}

/// Arguments of `sporadic design`.
#[derive(Debug, clap::Args)]
pub struct DesignArgs {
    /// The plant file (TOML; `sporadic init` writes a commented template, `examples/` has more).
    pub plant: PathBuf,
    /// The observer design method (ferrante2016, sferlazza2021, andrieu2014, etienne2017,
    /// rabehi2021).
    #[arg(long, value_parser = method_arg)]
    pub method: String,
    #[command(flatten)]
    pub format: Format,
    /// Also simulate the certified observer and write an SVG figure of the estimation error
    /// (interval width for rabehi2021) into this folder. Offered by ferrante2016,
    /// sferlazza2021 and rabehi2021.
    #[arg(long, value_name = "OUT_DIR")]
    pub simulate: Option<PathBuf>,
    /// Seed of the random sampling intervals of `--simulate`.
    #[arg(long, default_value_t = 1, requires = "simulate")]
    pub seed: u64,
}

/// Arguments of `sporadic max-interval`.
#[derive(Debug, clap::Args)]
pub struct MaxIntervalArgs {
    /// The plant file (TOML).
    pub plant: PathBuf,
    /// The observer design method.
    #[arg(long, value_parser = method_arg)]
    pub method: String,
    /// Largest upper end searched (default: 10 × the file's largest T2).
    #[arg(long)]
    pub limit: Option<f64>,
    /// Wall-time budget of the search in seconds; when it runs out the search reports the
    /// bracket found so far (reason `budget_exhausted`).
    #[arg(long, value_name = "SECONDS")]
    pub time_limit: Option<f64>,
    #[command(flatten)]
    pub format: Format,
}

/// Arguments of `sporadic compare`.
#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// The plant file (TOML).
    pub plant: PathBuf,
    /// Folder for the figure of the certified windows.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    #[command(flatten)]
    pub format: Format,
}

fn read(path: &Path) -> Result<PlantFile, Failure> {
    PlantFile::read(path).map_err(|e| Failure::Input(e.to_string()))
}

fn lookup(id: &str) -> Result<Box<dyn ObserverMethod>, Failure> {
    methods::method(id).ok_or_else(|| Failure::Input(format!("unknown method '{id}'")))
}

/// Bad input is exit 2; a numerical failure reaching here (none should) is reported as such.
fn method_failure(e: MethodError) -> Failure {
    match e {
        MethodError::InvalidInput { .. } => Failure::Input(e.chain()),
        _ => Failure::Run(e.chain()),
    }
}

fn print_report<T: serde::Serialize>(format: Format, report: &T) -> Result<bool, Failure> {
    if format.json {
        let s = serde_json::to_string(report).map_err(|e| Failure::Run(format!("JSON: {e}")))?;
        println!("{s}");
        Ok(true)
    } else if format.toml {
        let s = toml::to_string(report).map_err(|e| Failure::Run(format!("TOML: {e}")))?;
        print!("{s}");
        Ok(true)
    } else {
        Ok(false)
    }
}

fn print_matrix(name: &str, rows: &[Vec<f64>]) {
    println!("{name} =");
    for row in rows {
        let cells: Vec<String> = row.iter().map(|x| format!("{x:>13.6e}")).collect();
        println!("  [{}]", cells.join(" "));
    }
}

fn windows_words(d: &DesignReport) -> String {
    let ws = d.sampling_windows();
    if ws.is_empty() {
        return "-".into();
    }
    ws.iter()
        .map(|w| w.to_string())
        .collect::<Vec<_>>()
        .join(" then ")
}

fn print_design(d: &DesignReport) {
    println!("plant    {}", d.plant);
    println!("method   {}", d.method);
    println!("window   {}", windows_words(d));
    match (&d.reason, &d.margin) {
        (Some(r), _) => println!("status   {} ({}): {}", d.status, r.kind(), r.message()),
        (None, Some(m)) => println!("status   {} (margin {:.4e})", d.status, m.value),
        (None, None) => println!("status   {}", d.status),
    }
    println!("time     {:.3} s", d.seconds);
    if !d.status.is_certified() {
        return;
    }
    println!("observer {}", d.observer);
    for g in &d.gains {
        print_matrix(&g.name, &g.rows);
        if let Some(s) = &g.schedule {
            println!(
                "  (schedule: {}; {} samples on tau in [{}, {}] in --json)",
                s.law,
                s.tau.len(),
                s.tau.first().copied().unwrap_or(f64::NAN),
                s.tau.last().copied().unwrap_or(f64::NAN)
            );
        }
    }
    for NamedMatrix { name, rows, .. } in &d.certificate {
        print_matrix(name, rows);
    }
    if let Some(m) = &d.margin {
        println!("margin: {:.4e}, {}", m.value, m.definition);
    }
    for c in &d.checks {
        let value = c.value.map(|v| format!(": {v:.4e}")).unwrap_or_default();
        let verdict = if c.passed { "passed" } else { "FAILED" };
        println!("check: {} ({}){value} {verdict}", c.what, c.how);
    }
    for n in &d.notes {
        println!("note: {n}");
    }
}

/// Exit status of a report: certified → 0, otherwise 1.
fn verdict(status: Status) -> Outcome {
    if status.is_certified() {
        Outcome::Certified
    } else {
        Outcome::NothingCertified
    }
}

/// Runs `sporadic design`.
pub fn design(args: &DesignArgs) -> Result<Outcome, Failure> {
    let file = read(&args.plant)?;
    let method = lookup(&args.method)?;
    let mut report = methods::design(&file, method.as_ref(), &MethodOptions::default())
        .map_err(method_failure)?;
    if let Some(dir) = &args.simulate
        && report.status.is_certified()
    {
        let scenario = Scenario {
            sampling: SamplingScenario::Uniform { seed: args.seed },
            ..Scenario::default()
        };
        let run =
            methods::simulate(&file, method.as_ref(), &report, &scenario).map_err(|e| match e {
                MethodError::SimulationUnavailable { .. } => Failure::Input(e.chain()),
                e => method_failure(e),
            })?;
        let mut sim = run.report.clone();
        sim.figure = Some(draw_trajectory(dir, &file.name, method.id(), &run)?);
        report.simulation = Some(sim);
    }
    if !print_report(args.format, &report)? {
        print_design(&report);
        if let Some(s) = &report.simulation {
            println!("simulation: {}", s.setup);
            println!("simulation: {}", s.result);
            if let Some(f) = &s.figure {
                println!("figure: {f}");
            }
        }
    }
    Ok(verdict(report.status))
}

/// Writes `<method>_error.svg` (or `_width.svg`): the norm of the simulated signal over
/// hybrid time `(t, j)`.
fn draw_trajectory(
    dir: &Path,
    plant: &str,
    method: &str,
    run: &Trajectory,
) -> Result<String, Failure> {
    std::fs::create_dir_all(dir).map_err(|e| Failure::Input(format!("{}: {e}", dir.display())))?;
    let width = run.quantity.contains("width");
    let path = dir.join(format!(
        "{method}_{}.svg",
        if width { "width" } else { "error" }
    ));
    let spec = sporadic_figures::PlotSpec::new(
        &format!("{method}: {}, {plant}", run.quantity),
        "time [s]",
        if width { "|width|" } else { "|x - x_hat|" },
    );
    sporadic_figures::plot_error_norm(&path, &spec, &run.t, &run.j, &run.norm, None)
        .map_err(|e| Failure::Run(format!("{}: {e}", path.display())))?;
    Ok(path.display().to_string())
}

/// Progress lines: overwritten in place on a terminal, one per line otherwise.
fn progress_printer() -> impl FnMut(&Probe) {
    let tty = std::io::stderr().is_terminal();
    move |p: &Probe| {
        let line = format!(
            "T2 = {:.6}: {}",
            p.t2,
            if p.certified {
                "certified"
            } else {
                "not certified"
            }
        );
        let mut err = std::io::stderr();
        if tty {
            let _ = write!(err, "\r\x1b[2K{line}");
        } else {
            let _ = writeln!(err, "{line}");
        }
        let _ = err.flush();
    }
}

fn default_limit(file: &PlantFile) -> Option<f64> {
    let t2 = file
        .sensors
        .iter()
        .map(|s| s.window.t2())
        .chain(file.window.map(|w| w.t2()))
        .fold(0.0, f64::max);
    (t2 > 0.0).then_some(10.0 * t2)
}

fn print_max_interval(r: &MaxIntervalReport) {
    println!("plant    {}", r.plant);
    println!("method   {}", r.method);
    match (r.largest_certified_t2, r.first_failing_t2) {
        (Some(b), None) => println!(
            "result   certified up to the search limit: T2 = {b} (raise --limit to search further)"
        ),
        (Some(b), Some(f)) => println!(
            "result   largest certified T2 = {b:.6} (fails at {f:.6}), T1 = {}",
            r.t1.unwrap_or(f64::NAN)
        ),
        (None, _) if r.status.is_not_applicable() => {}
        (None, _) => println!(
            "result   not certified even for the shortest window (T1 = {})",
            r.t1.unwrap_or(f64::NAN)
        ),
    }
    if let Some(reason) = &r.reason {
        println!(
            "status   {} ({}): {}",
            r.status,
            reason.kind(),
            reason.message()
        );
    }
    println!("time     {:.2} s", r.seconds);
    if let Some(d) = &r.design {
        println!("-- certificate at the largest certified window --");
        print_design(d);
    }
}

/// Runs `sporadic max-interval`.
pub fn max_interval(args: &MaxIntervalArgs) -> Result<Outcome, Failure> {
    let file = read(&args.plant)?;
    let method = lookup(&args.method)?;
    let mut options = MethodOptions::default();
    if let Some(s) = args.time_limit {
        if !(s.is_finite() && s > 0.0) {
            return Err(Failure::Input(format!(
                "--time-limit must be a positive number of seconds, got {s}"
            )));
        }
        options.time_limit = Some(std::time::Duration::from_secs_f64(s));
    }
    let limit = match (args.limit, default_limit(&file)) {
        (Some(l), _) if !(l.is_finite() && l > 0.0) => {
            return Err(Failure::Input(format!(
                "--limit must be a positive finite number, got {l}"
            )));
        }
        (Some(l), _) => l,
        (None, Some(l)) => l,
        // No sampling in the file: the method reports it as missing data.
        (None, None) => f64::NAN,
    };
    let mut progress = progress_printer();
    let r = methods::max_interval(&file, method.as_ref(), limit, &options, &mut progress)
        .map_err(method_failure)?;
    if std::io::stderr().is_terminal() {
        eprintln!();
    }
    if !print_report(args.format, &r)? {
        print_max_interval(&r);
    }
    Ok(verdict(r.status))
}

/// Runs `sporadic compare`.
pub fn compare(args: &CompareArgs) -> Result<Outcome, Failure> {
    let file = read(&args.plant)?;
    let report = methods::compare(&file, &MethodOptions::default()).map_err(method_failure)?;
    let any = report.results.iter().any(|d| d.status.is_certified());
    let mut bars: Vec<(String, f64, f64)> = Vec::new();
    for d in report.results.iter().filter(|d| d.status.is_certified()) {
        let ws = d.sampling_windows();
        let many = ws.len() > 1;
        bars.extend(ws.iter().enumerate().map(|(i, w)| {
            let label = if many {
                format!("{} sensor {}", d.method, i + 1)
            } else {
                d.method.clone()
            };
            (label, w.t1(), w.t2())
        }));
    }
    let figure = if bars.is_empty() {
        None
    } else {
        Some(draw_windows(&args.out, &file.name, &bars)?)
    };
    if print_report(args.format, &report)? {
        return Ok(if any {
            Outcome::Certified
        } else {
            Outcome::NothingCertified
        });
    }
    println!("plant: {}", file.name);
    println!(
        "{:<14} {:<34} {:>12} {:>9}  note",
        "method", "certified window", "margin", "time [s]"
    );
    for d in &report.results {
        match (&d.reason, &d.margin) {
            (None, m) => println!(
                "{:<14} {:<34} {:>12} {:>9.3}  certified",
                d.method,
                windows_words(d),
                m.as_ref()
                    .map_or("-".into(), |m| format!("{:.4e}", m.value)),
                d.seconds
            ),
            (Some(r), _) => println!(
                "{:<14} {:<34} {:>12} {:>9}  {}: {}",
                d.method,
                "-",
                "-",
                "-",
                d.status,
                r.message()
            ),
        }
    }
    if let Some(f) = figure {
        println!("figure: {f}");
    }
    Ok(if any {
        Outcome::Certified
    } else {
        Outcome::NothingCertified
    })
}

/// Writes `certified_windows.svg`: one horizontal segment per certified window.
fn draw_windows(out: &Path, plant: &str, bars: &[(String, f64, f64)]) -> Result<String, Failure> {
    std::fs::create_dir_all(out).map_err(|e| Failure::Input(format!("{}: {e}", out.display())))?;
    let path = out.join("certified_windows.svg");
    let series_data: Vec<(String, [f64; 2], [f64; 2])> = bars
        .iter()
        .enumerate()
        .map(|(k, (label, t1, t2))| (label.clone(), [*t1, *t2], [k as f64 + 1.0; 2]))
        .collect();
    let series: Vec<sporadic_figures::Series<'_>> = series_data
        .iter()
        .map(|(label, x, y)| sporadic_figures::Series { label, x, y })
        .collect();
    let spec = sporadic_figures::PlotSpec::new(
        &format!("certified sampling windows: {plant}"),
        "sampling interval [s]",
        "design (one row per certified window)",
    );
    sporadic_figures::plot_eigen_curves(&path, &spec, &series)
        .map_err(|e| Failure::Run(format!("{}: {e}", path.display())))?;
    Ok(path.display().to_string())
}
