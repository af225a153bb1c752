//! `sporadic design`, `sporadic max-interval` and `sporadic compare`: observer design for a
//! user's plant file.

use sporadic::methods::{
    self, DesignSummary, MaxInterval, Method, MethodError, NamedMatrix, SimulationSummary,
};
use sporadic::plant_file::PlantFile;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

/// A method name on the command line.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum MethodArg {
    /// Ferrante et al. 2016 (sporadic sampling, polytopic embedding).
    Ferrante2016,
    /// Sferlazza et al. 2021 (round-robin sensors with jitter).
    Sferlazza2021,
    /// Etienne et al. 2017 (Lipschitz nonlinearity, impulsive observer).
    Etienne2017,
    /// Rabehi et al. 2021 (interval observer).
    Rabehi2021,
    /// Andrieu et al. 2014 (high-gain observer, updated sampling).
    Andrieu2014,
}

impl From<MethodArg> for Method {
    fn from(m: MethodArg) -> Self {
        match m {
            MethodArg::Ferrante2016 => Method::Ferrante2016,
            MethodArg::Sferlazza2021 => Method::Sferlazza2021,
            MethodArg::Etienne2017 => Method::Etienne2017,
            MethodArg::Rabehi2021 => Method::Rabehi2021,
            MethodArg::Andrieu2014 => Method::Andrieu2014,
        }
    }
}

/// Arguments of `sporadic design`.
#[derive(Debug, clap::Args)]
pub struct DesignArgs {
    /// The plant file (TOML; see `examples/`).
    pub plant: PathBuf,
    /// The observer design method.
    #[arg(long)]
    pub method: MethodArg,
    /// Print the gains and certificate as one JSON object.
    #[arg(long, conflicts_with = "toml")]
    pub json: bool,
    /// Print the gains and certificate as a TOML document.
    #[arg(long)]
    pub toml: bool,
    /// Also simulate the observer (random sampling in the certified window) and write an SVG
    /// figure of the estimation error into this folder (ferrante2016, rabehi2021).
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
    #[arg(long)]
    pub method: MethodArg,
    /// Largest upper end searched (default: 10 × the file's T2).
    #[arg(long)]
    pub limit: Option<f64>,
    /// Print the result as one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `sporadic compare`.
#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// The plant file (TOML).
    pub plant: PathBuf,
    /// Folder for the figure of the certified windows.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
}

fn read(path: &Path) -> Result<PlantFile, String> {
    PlantFile::read(path).map_err(|e| e.to_string())
}

fn matrix_json(m: &NamedMatrix) -> serde_json::Value {
    serde_json::json!({ "name": m.name, "rows": m.rows() })
}

fn design_json(d: &DesignSummary) -> serde_json::Value {
    serde_json::json!({
        "method": d.method.id(),
        "window": d.window,
        "margin": d.margin,
        "gains": d.gains.iter().map(matrix_json).collect::<Vec<_>>(),
        "certificate": d.certificate.iter().map(matrix_json).collect::<Vec<_>>(),
        "notes": d.notes,
        "seconds": d.seconds,
    })
}

fn print_matrix(m: &NamedMatrix) {
    println!("{} =", m.name);
    for row in m.rows() {
        let cells: Vec<String> = row.iter().map(|x| format!("{x:>13.6e}")).collect();
        println!("  [{}]", cells.join(" "));
    }
}

fn print_design(plant: &PlantFile, d: &DesignSummary) {
    println!("plant    {}", plant.name);
    println!("method   {}", d.method);
    println!("window   {}", d.window);
    println!("status   certified (margin {:.4e})", d.margin);
    println!("time     {:.3} s", d.seconds);
    for g in &d.gains {
        print_matrix(g);
    }
    for c in &d.certificate {
        print_matrix(c);
    }
    for n in &d.notes {
        println!("note: {n}");
    }
}

/// The design as a TOML document: scalars first, then one `[[gains]]` / `[[certificate]]`
/// table per matrix (`name`, `rows`).
fn design_toml<'a>(
    d: &'a DesignSummary,
    simulation: Option<&'a SimulationSummary>,
) -> Result<String, String> {
    #[derive(serde::Serialize)]
    struct Matrix<'a> {
        name: &'a str,
        rows: Vec<Vec<f64>>,
    }
    #[derive(serde::Serialize)]
    struct Simulation<'a> {
        figure: String,
        setup: &'a str,
        result: &'a str,
    }
    #[derive(serde::Serialize)]
    struct Doc<'a> {
        method: &'a str,
        window: &'a str,
        margin: f64,
        seconds: f64,
        notes: &'a [String],
        gains: Vec<Matrix<'a>>,
        certificate: Vec<Matrix<'a>>,
        #[serde(skip_serializing_if = "Option::is_none")]
        simulation: Option<Simulation<'a>>,
    }
    let matrices = |ms: &'a [NamedMatrix]| -> Vec<Matrix<'a>> {
        ms.iter()
            .map(|m| Matrix {
                name: &m.name,
                rows: m.rows(),
            })
            .collect()
    };
    let doc = Doc {
        method: d.method.id(),
        window: &d.window,
        margin: d.margin,
        seconds: d.seconds,
        notes: &d.notes,
        gains: matrices(&d.gains),
        certificate: matrices(&d.certificate),
        simulation: simulation.map(|s| Simulation {
            figure: s.figure.display().to_string(),
            setup: &s.setup,
            result: &s.result,
        }),
    };
    toml::to_string(&doc).map_err(|e| format!("TOML output: {e}"))
}

fn simulation_json(s: &SimulationSummary) -> serde_json::Value {
    serde_json::json!({
        "figure": s.figure.display().to_string(),
        "setup": s.setup,
        "result": s.result,
    })
}

/// Runs `sporadic design`.
pub fn design(args: &DesignArgs) -> Result<(), String> {
    let plant = read(&args.plant)?;
    let d = methods::design(&plant, args.method.into()).map_err(|e| e.to_string())?;
    let simulation = args
        .simulate
        .as_ref()
        .map(|dir| methods::simulate(&plant, &d, dir, args.seed))
        .transpose()
        .map_err(|e| e.to_string())?;
    if args.json {
        let mut v = design_json(&d);
        if let Some(s) = &simulation {
            v["simulation"] = simulation_json(s);
        }
        println!("{v}");
    } else if args.toml {
        print!("{}", design_toml(&d, simulation.as_ref())?);
    } else {
        print_design(&plant, &d);
        if let Some(s) = &simulation {
            println!("simulation: {}", s.setup);
            println!("simulation: {}", s.result);
            println!("figure: {}", s.figure.display());
        }
    }
    Ok(())
}

/// Progress lines: overwritten in place on a terminal, one per line otherwise.
fn progress_printer() -> impl FnMut(&str) {
    let tty = std::io::stderr().is_terminal();
    move |line: &str| {
        let mut err = std::io::stderr();
        if tty {
            let _ = write!(err, "\r\x1b[2K{line}");
        } else {
            let _ = writeln!(err, "{line}");
        }
        let _ = err.flush();
    }
}

fn default_limit(plant: &PlantFile) -> f64 {
    let t2 = plant
        .sensors
        .iter()
        .map(|s| s.window.t2)
        .chain(plant.window.map(|w| w.t2))
        .fold(0.0, f64::max);
    10.0 * t2
}

fn max_interval_json(r: &MaxInterval) -> serde_json::Value {
    serde_json::json!({
        "method": r.method.id(),
        "t1": r.t1,
        "largest_certified_t2": r.best,
        "first_failing_t2": r.first_failure,
        "design": r.design.as_ref().map(design_json),
        "seconds": r.seconds,
    })
}

/// Runs `sporadic max-interval`.
pub fn max_interval(args: &MaxIntervalArgs) -> Result<(), String> {
    let plant = read(&args.plant)?;
    let limit = args.limit.unwrap_or_else(|| default_limit(&plant));
    if !(limit.is_finite() && limit > 0.0) {
        return Err(format!("--limit must be a positive number, got {limit}"));
    }
    let mut progress = progress_printer();
    let r = methods::max_interval(&plant, args.method.into(), limit, &mut progress)
        .map_err(|e| e.to_string())?;
    if std::io::stderr().is_terminal() {
        eprintln!();
    }
    if args.json {
        println!("{}", max_interval_json(&r));
        return Ok(());
    }
    println!("plant    {}", plant.name);
    println!("method   {}", r.method);
    match (r.best, r.first_failure) {
        (Some(b), None) => println!(
            "result   certified up to the search limit: T2 = {b} (raise --limit to search further)"
        ),
        (Some(b), Some(f)) => println!(
            "result   largest certified T2 = {b:.6} (fails at {f:.6}), T1 = {}",
            r.t1
        ),
        (None, _) => println!(
            "result   not certified even for the shortest window (T1 = {})",
            r.t1
        ),
    }
    println!("time     {:.2} s", r.seconds);
    if let Some(d) = &r.design {
        println!("-- certificate at the largest certified window --");
        print_design(&plant, d);
    }
    Ok(())
}

/// Runs `sporadic compare`.
pub fn compare(args: &CompareArgs) -> Result<(), String> {
    let plant = read(&args.plant)?;
    println!("plant: {}", plant.name);
    println!(
        "{:<14} {:<34} {:>12} {:>9}  note",
        "method", "certified window", "margin", "time [s]"
    );
    let mut bars: Vec<(String, f64, f64)> = Vec::new();
    for method in Method::ALL {
        match methods::design(&plant, method) {
            Ok(d) => {
                let many = d.windows.len() > 1;
                bars.extend(d.windows.iter().enumerate().map(|(i, w)| {
                    let label = if many {
                        format!("{method} sensor {}", i + 1)
                    } else {
                        method.to_string()
                    };
                    (label, w.t1, w.t2)
                }));
                println!(
                    "{:<14} {:<34} {:>12.4e} {:>9.3}  certified",
                    method, d.window, d.margin, d.seconds
                );
            }
            Err(MethodError::NotApplicable { why, .. }) => {
                println!(
                    "{:<14} {:<34} {:>12} {:>9}  not applicable: {why}",
                    method, "-", "-", "-"
                );
            }
            Err(e) => {
                println!("{:<14} {:<34} {:>12} {:>9}  {e}", method, "-", "-", "-");
            }
        }
    }
    if !bars.is_empty() {
        std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
        let path = args.out.join("certified_windows.svg");
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
            &format!("certified sampling windows: {}", plant.name),
            "sampling interval [s]",
            "design (one row per certified window)",
        );
        sporadic_figures::plot_eigen_curves(&path, &spec, &series)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        println!("figure: {}", path.display());
    }
    Ok(())
}
