//! `sporadic design`, `sporadic max-interval` and `sporadic compare`: observer design for a
//! user's plant file, printed as text or as the typed reports of `sporadic_model::report`.

use super::{Failure, Outcome};
use sporadic::methods;
use sporadic::plant_file::PlantFile;
use sporadic_model::{
    CompareReport, DesignReport, Gain, MaxIntervalReport, MethodError, MethodOptions, NamedMatrix,
    ObserverMethod, Probe, Proof, ProofOptions, ProofStatus, SamplingScenario, SamplingWindow,
    Scenario, SearchEnd, Status, Trajectory, significant,
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

/// The wall-time budget of a command.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct TimeBudget {
    /// Wall-time budget in seconds. Every solve stops once it runs out, and a design or search
    /// not decided by then reports `budget_exhausted` (a search keeps the windows certified so
    /// far). `compare` shares it among the methods.
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = DEFAULT_TIME_LIMIT,
        allow_negative_numbers = true
    )]
    pub time_limit: f64,
    /// Run without a time budget.
    #[arg(long, conflicts_with = "time_limit")]
    pub no_time_limit: bool,
}

/// The default of `--time-limit`, seconds: every command answers within 30 s.
pub const DEFAULT_TIME_LIMIT: f64 = 25.0;

impl TimeBudget {
    /// The method options with this budget.
    fn options(self) -> Result<MethodOptions, Failure> {
        let mut options = MethodOptions::default();
        if !self.no_time_limit {
            let s = self.time_limit;
            if !(s.is_finite() && s > 0.0) {
                return Err(Failure::Input(format!(
                    "--time-limit must be a positive number of seconds, got {s}"
                )));
            }
            options.time_limit = Some(std::time::Duration::from_secs_f64(s));
        }
        Ok(options)
    }
}

/// How the sampling intervals of a simulation are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ScenarioArg {
    /// Uniformly at random in the window (each sensor's, for round-robin), with `--seed`.
    Uniform,
    /// Always the shortest interval T1.
    PeriodicT1,
    /// Always the longest interval T2.
    PeriodicT2,
    /// The worst case the certificate sees: each interval chosen in the window to maximise
    /// its Lyapunov function just after the next sample (greedy adversary; ferrante2016).
    WorstCase,
}

/// The simulation options of `sporadic design`.
#[derive(Debug, Clone, clap::Args)]
pub struct SimulationArgs {
    /// Simulate the certified observer and write an SVG figure of the estimation error
    /// (interval width for rabehi2021) into this folder. Offered by ferrante2016,
    /// sferlazza2021 and rabehi2021.
    #[arg(long, value_name = "OUT_DIR")]
    pub simulate: Option<PathBuf>,
    /// Simulate and write the time series as CSV (columns t, j, norm, then one per signal).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Simulated time in seconds (default: the method's, a few dozen longest intervals).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub horizon: Option<f64>,
    /// Initial estimation error x(0) - x_hat(0), comma-separated, one entry per state (for
    /// rabehi2021 the half-width of the initial enclosure; default: all ones).
    #[arg(
        long,
        value_name = "E1,E2,...",
        value_delimiter = ',',
        allow_negative_numbers = true
    )]
    pub initial_error: Option<Vec<f64>>,
    /// How the sampling intervals are drawn.
    #[arg(long, value_enum, default_value_t = ScenarioArg::Uniform)]
    pub scenario: ScenarioArg,
    /// Seed of the random sampling intervals of `--scenario uniform`.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

impl SimulationArgs {
    /// Whether a simulation was asked for.
    fn wanted(&self) -> bool {
        self.simulate.is_some() || self.csv.is_some()
    }

    /// The scenario, or why the options are invalid.
    fn scenario(&self) -> Result<Scenario, Failure> {
        if let Some(h) = self.horizon
            && !(h.is_finite() && h > 0.0)
        {
            return Err(Failure::Input(format!(
                "--horizon must be a positive finite time, got {h}"
            )));
        }
        if let Some(e) = &self.initial_error
            && let Some(bad) = e.iter().find(|v| !v.is_finite())
        {
            return Err(Failure::Input(format!(
                "--initial-error entries must be finite, got {bad}"
            )));
        }
        Ok(Scenario {
            horizon: self.horizon,
            initial_error: self.initial_error.clone(),
            sampling: match self.scenario {
                ScenarioArg::Uniform => SamplingScenario::Uniform { seed: self.seed },
                ScenarioArg::PeriodicT1 => SamplingScenario::PeriodicT1,
                ScenarioArg::PeriodicT2 => SamplingScenario::PeriodicT2,
                ScenarioArg::WorstCase => SamplingScenario::WorstCase,
            },
        })
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
    #[command(flatten)]
    pub budget: TimeBudget,
    #[command(flatten)]
    pub simulation: SimulationArgs,
    #[command(flatten)]
    pub proof: ProofArgs,
}

/// The rigorous proof of a design (issue "Proofs, not samples").
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct ProofArgs {
    /// Prove the design's condition for every sampling interval of the window in interval
    /// arithmetic and add a `proof` section (proved | not_proved | inconclusive). With it, the
    /// exit status is 0 only when the design is certified and proved.
    #[arg(long)]
    pub prove: bool,
    /// Largest number of τ-pieces of the proof's adaptive subdivision, per window.
    #[arg(long, value_name = "N", default_value_t = ProofOptions::default().max_pieces, requires = "prove")]
    pub proof_pieces: usize,
}

impl ProofArgs {
    /// The proof options with the command's time budget.
    fn options(&self, budget: &MethodOptions) -> Result<ProofOptions, Failure> {
        if self.proof_pieces == 0 {
            return Err(Failure::Input("--proof-pieces must be at least 1".into()));
        }
        Ok(ProofOptions {
            max_pieces: self.proof_pieces,
            time_limit: budget.time_limit,
        })
    }
}

/// Arguments of `sporadic verify`.
#[derive(Debug, clap::Args)]
pub struct VerifyArgs {
    /// The plant file (TOML).
    pub plant: PathBuf,
    /// The method whose condition the gains are checked against (ferrante2016, sferlazza2021,
    /// andrieu2014, etienne2017, rabehi2021).
    #[arg(long, value_parser = method_arg)]
    pub method: String,
    /// The gains: a design report (`sporadic design --json`; its `gains` and, when present,
    /// its `certificate` are used), an object `{"gains": [...], "certificate": [...]}`, or an
    /// array of gains; each gain `{"name": "L", "rows": [[...], ...]}` (a `schedule` is kept).
    #[arg(long, value_name = "FILE.json")]
    pub gains: PathBuf,
    /// Check on this window instead of the file's (every sensor's, for round-robin sampling).
    #[arg(long, num_args = 2, value_names = ["T1", "T2"], allow_negative_numbers = true)]
    pub window: Option<Vec<f64>>,
    #[command(flatten)]
    pub proof: ProofArgs,
    #[command(flatten)]
    pub budget: TimeBudget,
    #[command(flatten)]
    pub format: Format,
}

/// Arguments of `sporadic max-interval`.
#[derive(Debug, clap::Args)]
pub struct MaxIntervalArgs {
    /// The plant file (TOML).
    pub plant: PathBuf,
    /// The observer design method (ferrante2016, sferlazza2021, andrieu2014, etienne2017,
    /// rabehi2021).
    #[arg(long, value_parser = method_arg)]
    pub method: String,
    /// Largest upper end searched (default: 10 × the file's largest T2). With round-robin
    /// sensors, T2 is every sensor's upper end, at least that sensor's T1.
    #[arg(long, allow_negative_numbers = true)]
    pub limit: Option<f64>,
    #[command(flatten)]
    pub budget: TimeBudget,
    #[command(flatten)]
    pub format: Format,
}

/// Arguments of `sporadic compare`.
#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// The plant file (TOML).
    pub plant: PathBuf,
    /// Largest upper end T2 searched for each method (default: 10 × the file's largest T2).
    /// With round-robin sensors, T2 is every sensor's upper end, at least that sensor's T1.
    #[arg(long, allow_negative_numbers = true)]
    pub limit: Option<f64>,
    /// Only certify the file's own sampling; do not search the largest T2.
    #[arg(long, conflicts_with = "limit")]
    pub no_search: bool,
    /// Folder for the figure of the certified windows.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    #[command(flatten)]
    pub budget: TimeBudget,
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
        (None, Some(m)) => println!("status   {} (margin {:.3e})", d.status, m.value),
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
        println!("margin: {:.3e}, {}", m.value, m.definition);
    }
    for c in &d.checks {
        let value = c.value.map(|v| format!(": {v:.3e}")).unwrap_or_default();
        let verdict = if c.passed { "passed" } else { "FAILED" };
        println!("check: {} ({}){value} {verdict}", c.what, c.how);
    }
    for n in &d.notes {
        println!("note: {n}");
    }
}

fn print_proof(p: &Proof) {
    println!("proof    {}: {}", p.status, p.message);
    if !p.condition.is_empty() {
        println!("proof: condition: {}", p.condition);
    }
    if let Some(m) = p.margin_lower_bound {
        println!(
            "proof: margin ≥ {} ({}), {} τ-pieces{}, {:.3} s",
            significant(m),
            p.margin_definition,
            p.subintervals,
            p.enclosure_width.map_or_else(String::new, |w| format!(
                ", largest relative width of the e^(Aτ) enclosures {}",
                significant(w)
            )),
            p.seconds
        );
    }
    if let Some(f) = &p.failed_on {
        println!(
            "proof: {} on τ in [{}, {}]: decisive eigenvalue in [{}, {}]",
            f.condition,
            significant(f.tau[0]),
            significant(f.tau[1]),
            significant(f.enclosure[0]),
            significant(f.enclosure[1])
        );
    }
    if !p.how.is_empty() {
        println!("proof: how: {}", p.how);
    }
}

/// Exit status of a report with an optional proof: certified (and proved, when a proof was
/// asked for) → 0, otherwise 1.
fn proved_verdict(report: &DesignReport, asked: bool) -> Outcome {
    let proved = report
        .proof
        .as_ref()
        .is_some_and(|p| p.status == ProofStatus::Proved);
    if report.status.is_certified() && (!asked || proved) {
        Outcome::Certified
    } else {
        Outcome::NothingCertified
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
    let sim = &args.simulation;
    let scenario = sim.scenario()?;
    let options = args.budget.options()?;
    let mut report = methods::design(&file, method.as_ref(), &options).map_err(method_failure)?;
    if sim.wanted() && report.status.is_certified() {
        let run =
            methods::simulate(&file, method.as_ref(), &report, &scenario).map_err(|e| match e {
                MethodError::SimulationUnavailable { .. } => Failure::Input(e.chain()),
                e => method_failure(e),
            })?;
        let mut summary = run.report.clone();
        if let Some(dir) = &sim.simulate {
            summary.figure = Some(draw_trajectory(dir, &file.name, method.id(), &run)?);
        }
        if let Some(path) = &sim.csv {
            write_csv(path, &run)?;
        }
        report.simulation = Some(summary);
    }
    if args.proof.prove {
        let proof_options = args.proof.options(&options)?;
        report.proof = Some(
            methods::prove(&file, method.as_ref(), &report, &proof_options)
                .map_err(method_failure)?,
        );
    }
    if !print_report(args.format, &report)? {
        print_design(&report);
        if let Some(p) = &report.proof {
            print_proof(p);
        }
        if let Some(s) = &report.simulation {
            println!("simulation: {}", s.setup);
            println!("simulation: {}", s.result);
            match s.settling_time {
                Some(t) => println!(
                    "simulation: settled: the norm stays below {}% of its initial value from t = {} s",
                    100.0 * methods::SETTLING_BAND,
                    significant(t)
                ),
                None => match s.ends_early_at {
                    Some(t) => println!(
                        "simulation: not settled by t = {} s, where the run ends before its horizon (see above)",
                        significant(t)
                    ),
                    None => println!(
                        "simulation: not settled: the norm is not below {}% of its initial value at the end of the run (raise --horizon)",
                        100.0 * methods::SETTLING_BAND
                    ),
                },
            }
            if let Some(f) = &s.figure {
                println!("figure: {f}");
            }
            if let Some(c) = &sim.csv {
                println!("time series: {}", c.display());
            }
        }
    }
    Ok(proved_verdict(&report, args.proof.prove))
}

/// The gains (and certificate, if any) of a `--gains` file.
fn read_gains(path: &Path) -> Result<(Vec<Gain>, Vec<NamedMatrix>), Failure> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Failure::Input(format!("{}: {e}", path.display())))?;
    sporadic::gains_file::parse_gains(&text)
        .map_err(|e| Failure::Input(format!("{}: {e}", path.display())))
}

/// Runs `sporadic verify`.
pub fn verify(args: &VerifyArgs) -> Result<Outcome, Failure> {
    let file = read(&args.plant)?;
    let method = lookup(&args.method)?;
    let options = args.budget.options()?;
    let (gains, certificate) = read_gains(&args.gains)?;
    let window = match args.window.as_deref() {
        None => None,
        Some(&[t1, t2]) => Some(
            SamplingWindow::new(t1, t2).map_err(|e| Failure::Input(format!("--window: {e}")))?,
        ),
        Some(_) => return Err(Failure::Input("--window takes two numbers T1 T2".into())),
    };
    let proof_options = args.proof.options(&options)?;
    let mut report = methods::verify(
        &file,
        method.as_ref(),
        &gains,
        &certificate,
        window,
        &options,
    )
    .map_err(method_failure)?;
    report.proof = Some(if args.proof.prove || !report.status.is_certified() {
        methods::prove(&file, method.as_ref(), &report, &proof_options).map_err(method_failure)?
    } else {
        Proof::not_attempted(
            ProofStatus::Inconclusive,
            "no proof was asked for (--prove)",
        )
    });
    if !print_report(args.format, &report)? {
        print_design(&report);
        if let Some(p) = &report.proof {
            print_proof(p);
        }
    }
    Ok(proved_verdict(&report, args.proof.prove))
}

/// Writes the simulated time series as CSV: `t,j,norm,<signal>...`, one row per hybrid time.
fn write_csv(path: &Path, run: &Trajectory) -> Result<(), Failure> {
    let mut out = String::from("t,j,norm");
    for (name, _) in &run.signals {
        out.push(',');
        out.push_str(&name.replace(',', ";"));
    }
    out.push('\n');
    for (k, t) in run.t.iter().enumerate() {
        out.push_str(&format!("{t:e},{},{:e}", run.j[k], run.norm[k]));
        for (_, v) in &run.signals {
            out.push_str(&format!(",{:e}", v[k]));
        }
        out.push('\n');
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| Failure::Input(format!("{}: {e}", dir.display())))?;
    }
    std::fs::write(path, out).map_err(|e| Failure::Input(format!("{}: {e}", path.display())))
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
fn progress_printer() -> impl FnMut(&str, &Probe) {
    let tty = std::io::stderr().is_terminal();
    move |prefix: &str, p: &Probe| {
        let verdict = match (p.certified, &p.reason) {
            (true, _) => "certified".to_string(),
            (false, Some(reason)) => format!("not certified ({})", reason.kind()),
            (false, None) => "not certified".to_string(),
        };
        let line = format!("{prefix}T2 = {}: {verdict}", significant(p.t2));
        let mut err = std::io::stderr();
        if tty {
            let _ = write!(err, "\r\x1b[2K{line}");
        } else {
            let _ = writeln!(err, "{line}");
        }
        let _ = err.flush();
    }
}

fn print_max_interval(r: &MaxIntervalReport) {
    println!("plant    {}", r.plant);
    println!("method   {}", r.method);
    let budget = r.search_end == Some(SearchEnd::BudgetExhausted);
    match (r.largest_certified_t2, r.first_failing_t2) {
        (Some(b), Some(f)) if r.search_end == Some(SearchEnd::Undecided) => println!(
            "result   largest certified T2 = {}, a lower bound: T2 = {} was not decided ({}), \
             T1 = {}",
            significant(b),
            significant(f),
            r.reason
                .as_ref()
                .or(r.first_failure_reason())
                .map_or("?", |why| why.kind()),
            significant(r.t1.unwrap_or(f64::NAN))
        ),
        (Some(b), f) if budget => println!(
            "result   largest certified T2 = {}, a lower bound: a budget ran out ({}), T1 = {}",
            significant(b),
            f.map_or_else(
                || "no failing T2 found yet".to_string(),
                |f| format!("not certified at {}", significant(f))
            ),
            significant(r.t1.unwrap_or(f64::NAN))
        ),
        (Some(b), None) => println!(
            "result   certified up to the search limit: T2 = {} (raise --limit to search further)",
            significant(b)
        ),
        (Some(b), Some(f)) => println!(
            "result   largest certified T2 = {} (fails at {}), T1 = {}",
            significant(b),
            significant(f),
            significant(r.t1.unwrap_or(f64::NAN))
        ),
        (None, _) if r.status.is_not_applicable() => {}
        (None, _) => println!(
            "result   not certified even for the shortest window (T1 = {})",
            significant(r.t1.unwrap_or(f64::NAN))
        ),
    }
    match &r.reason {
        // A search that certified windows: the reason is why it stopped.
        Some(reason) if r.status.is_certified() => println!(
            "status   {}, search stopped by {}: {}",
            r.status,
            reason.kind(),
            reason.message()
        ),
        Some(reason) => println!(
            "status   {} ({}): {}",
            r.status,
            reason.kind(),
            reason.message()
        ),
        None => {}
    }
    if let Some(reason) = r.first_failure_reason() {
        println!(
            "failure  T2 = {} not certified ({}): {}",
            significant(r.first_failing_t2.unwrap_or(f64::NAN)),
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
    let options = args.budget.options()?;
    let limit = match (args.limit, methods::default_limit(&file)) {
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
    let mut printer = progress_printer();
    let mut progress = |p: &Probe| printer("", p);
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
    let options = args.budget.options()?;
    let limit = match args.limit {
        _ if args.no_search => None,
        Some(l) if !(l.is_finite() && l > 0.0) => {
            return Err(Failure::Input(format!(
                "--limit must be a positive finite number, got {l}"
            )));
        }
        Some(l) => Some(l),
        None => methods::default_limit(&file),
    };
    let mut printer = progress_printer();
    let mut progress = |id: &str, p: &Probe| printer(&format!("{id}: "), p);
    let report = methods::compare(&file, &options, limit, &mut progress).map_err(method_failure)?;
    if std::io::stderr().is_terminal() && limit.is_some() {
        eprintln!();
    }
    let outcome = if report
        .results
        .iter()
        .any(|e| e.certifies_the_files_sampling())
    {
        Outcome::Certified
    } else {
        Outcome::NothingCertified
    };
    let figure = draw_windows(&args.out, &file, &report)?;
    if print_report(args.format, &report)? {
        return Ok(outcome);
    }
    print_compare(&file, &report);
    println!("figure: {figure}");
    Ok(outcome)
}

/// The file's windows in words, e.g. `[0.02, 0.05]` or `[0.1, 0.2] then [0.1, 0.3]`.
fn file_windows(file: &PlantFile) -> Vec<SamplingWindow> {
    file.window
        .into_iter()
        .chain(file.sensors.iter().map(|s| s.window))
        .collect()
}

fn print_compare(file: &PlantFile, report: &CompareReport) {
    println!("plant: {}", file.name);
    let ws: Vec<String> = file_windows(file).iter().map(|w| w.to_string()).collect();
    println!("file's sampling: {}", ws.join(", "));
    if let Some(l) = report.limit {
        println!(
            "search: largest certified T2 <= {} with the file's T1",
            significant(l)
        );
    }
    println!(
        "{:<14} {:<15} {:>10} {:<38} {:>9}  note",
        "method", "file's window", "margin", "largest certified T2", "time [s]"
    );
    for e in &report.results {
        let d = &e.design;
        // A method that picks its own sampling instants certifies no window of arbitrary
        // sampling: its search does not apply.
        let own_rule = e.chooses_its_sampling;
        let at_file = if d.status.is_certified() && own_rule {
            "own rule".to_string()
        } else if d.status.is_certified() {
            "certified".to_string()
        } else {
            d.status.to_string()
        };
        let margin = d
            .margin
            .as_ref()
            .filter(|_| d.status.is_certified())
            .map_or("-".into(), |m| format!("{:.3e}", m.value));
        let largest = match &e.largest_window {
            None => "-".to_string(),
            Some(_) if own_rule => "-".to_string(),
            Some(r) => match (r.largest_certified_t2, r.first_failing_t2) {
                (Some(b), _) if r.search_end == Some(SearchEnd::BudgetExhausted) => {
                    format!("{} (budget ran out)", significant(b))
                }
                (Some(b), Some(f)) => {
                    let undecided = r.search_end == Some(SearchEnd::Undecided);
                    // An undecided search names its own reason (a refusal it could not
                    // resolve, see `max-interval`), else the failing probe's.
                    let why = r
                        .reason
                        .as_ref()
                        .filter(|_| undecided)
                        .or(r.first_failure_reason())
                        .map_or(String::new(), |why| format!(": {}", why.kind()));
                    let end = if undecided { "undecided" } else { "fails" };
                    format!("{} ({end} {}{why})", significant(b), significant(f))
                }
                (Some(b), None) => format!("{} (= limit)", significant(b)),
                (None, _) => "none".to_string(),
            },
        };
        let seconds = d.seconds + e.largest_window.as_ref().map_or(0.0, |r| r.seconds);
        let note = match (
            &d.reason,
            e.largest_window.as_ref().and_then(|r| r.reason.as_ref()),
        ) {
            (None, _) if own_rule => format!(
                "its own sampling rule takes intervals in {}",
                windows_words(d)
            ),
            (Some(r), _) if d.status.is_not_applicable() => {
                format!("{}: {}", r.kind(), r.message())
            }
            // The time column adds the design and the search: say which one the reason ends.
            (Some(r), _) => format!("file's window: {}: {}", r.kind(), r.message()),
            (None, Some(r)) => format!("search: {}: {}", r.kind(), r.message()),
            (None, None) => String::new(),
        };
        println!(
            "{:<14} {:<15} {:>10} {:<38} {:>9.2}  {}",
            e.method, at_file, margin, largest, seconds, note
        );
    }
}

/// Writes `certified_windows.svg`: per method (per sensor for round-robin) the largest
/// certified window with the file's `T1` as a bar, the file's window shaded.
fn draw_windows(out: &Path, file: &PlantFile, report: &CompareReport) -> Result<String, Failure> {
    std::fs::create_dir_all(out).map_err(|e| Failure::Input(format!("{}: {e}", out.display())))?;
    let path = out.join("certified_windows.svg");
    let mut rows = Vec::new();
    for e in &report.results {
        // The widest certified design: the search's, else the file's own.
        let best = e
            .largest_window
            .as_ref()
            .and_then(|r| r.design.as_ref())
            .or(Some(&e.design).filter(|d| d.status.is_certified()));
        let reason = e
            .design
            .reason
            .as_ref()
            .map_or(String::new(), |r| r.kind().replace('_', " "));
        match best {
            Some(d) => {
                let ws = d.sampling_windows();
                let many = ws.len() > 1;
                let own_rule = e.chooses_its_sampling;
                for (i, w) in ws.iter().enumerate() {
                    rows.push(sporadic_figures::WindowBar {
                        label: if many {
                            format!("{} sensor {}", e.method, i + 1)
                        } else {
                            e.method.clone()
                        },
                        window: Some((w.t1(), w.t2())),
                        note: if own_rule {
                            format!("its rule's intervals, T2 = {}", significant(w.t2()))
                        } else {
                            format!("T2 = {}", significant(w.t2()))
                        },
                    });
                }
            }
            None => rows.push(sporadic_figures::WindowBar {
                label: e.method.clone(),
                window: None,
                note: format!("{}: {reason}", e.design.status),
            }),
        }
    }
    let ws = file_windows(file);
    let marked = (!ws.is_empty()).then(|| {
        (
            ws.iter().map(|w| w.t1()).fold(f64::INFINITY, f64::min),
            ws.iter().map(|w| w.t2()).fold(0.0, f64::max),
        )
    });
    sporadic_figures::plot_window_bars(
        &path,
        &format!("certified sampling windows: {}", file.name),
        "sampling interval [s]",
        &rows,
        marked,
        sporadic_figures::FigureStyle::default(),
    )
    .map_err(|e| Failure::Run(format!("{}: {e}", path.display())))?;
    Ok(path.display().to_string())
}
