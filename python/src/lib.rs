//! `sporadic._native`: the Python extension of the sporadic workbench.
//!
//! Every entry point calls the same Rust core as the `sporadic` command-line program: plants
//! are plant-file TOML texts validated by [`PlantFile::parse`], designs go through
//! [`sporadic::methods`], and reports come back as the JSON the CLI prints with `--json`
//! (`serde_json::to_string` of the same report types). The Python package (`sporadic/`) turns
//! that JSON and the nested lists below into report objects and numpy arrays.
//!
//! Long calls run on a worker thread with the GIL released, inside a
//! [`sporadic::sdp::budget::within`] scope whose cancellation flag the calling thread raises
//! when Python reports a signal (Ctrl-C): the solves stop with status `interrupted` and the
//! call raises `KeyboardInterrupt`.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{RecvTimeoutError, channel};
use std::time::Duration;

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyRuntimeError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use sporadic::faer::{Mat, MatRef};
use sporadic::model::{Proof, ProofOptions, ProofStatus, SamplingScenario, Scenario};
use sporadic::plant_file::PlantFile;
use sporadic::sdp::budget::{Budget, within};
use sporadic::sdp::{BlockKind, ProblemBuilder, Settings};
use sporadic::{MethodError, MethodOptions, SamplingWindow, methods};

create_exception!(
    _native,
    NativeError,
    PyException,
    "An error of the Rust core: args are (kind, message, details dict)."
);

/// `NativeError(kind, message, details)`.
fn native(kind: &str, message: String, details: Vec<(&str, PyObject)>) -> PyErr {
    Python::with_gil(|py| {
        let d = PyDict::new(py);
        for (k, v) in details {
            let _ = d.set_item(k, v);
        }
        NativeError::new_err((kind.to_string(), message, d.unbind()))
    })
}

/// The snake-case name of an error's variant (from its `Debug` form).
fn kind_of<E: std::fmt::Debug>(e: &E) -> String {
    let dbg = format!("{e:?}");
    let head: String = dbg
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect();
    let mut out = String::new();
    for (k, c) in head.chars().enumerate() {
        if c.is_uppercase() {
            if k > 0 {
                out.push('_');
            }
            out.extend(c.to_lowercase());
        } else {
            out.push(c);
        }
    }
    out
}

fn method_error(e: MethodError) -> PyErr {
    let kind = match &e {
        MethodError::InvalidInput { .. } => "invalid_input",
        MethodError::Numerical { .. } => "numerical",
        MethodError::SimulationUnavailable { .. } => "simulation_unavailable",
        MethodError::VerificationUnavailable { .. } => "verification_unavailable",
        #[allow(unreachable_patterns)]
        _ => "method_error",
    };
    native(kind, e.chain(), vec![])
}

fn plant_file(text: &str, path: &str) -> PyResult<PlantFile> {
    PlantFile::parse(text, Path::new(path)).map_err(|e| {
        let message = e.to_string();
        Python::with_gil(|py| {
            let details = vec![
                (
                    "path",
                    e.path
                        .display()
                        .to_string()
                        .into_pyobject(py)
                        .unwrap()
                        .into_any()
                        .unbind(),
                ),
                (
                    "line",
                    e.line.into_pyobject(py).unwrap().into_any().unbind(),
                ),
                (
                    "field",
                    e.field
                        .clone()
                        .into_pyobject(py)
                        .unwrap()
                        .into_any()
                        .unbind(),
                ),
                (
                    "reason",
                    e.message
                        .clone()
                        .into_pyobject(py)
                        .unwrap()
                        .into_any()
                        .unbind(),
                ),
            ];
            native("plant_file", message, details)
        })
    })
}

fn method(id: &str) -> PyResult<Box<dyn sporadic::ObserverMethod>> {
    methods::method(id).ok_or_else(|| {
        native(
            "unknown_method",
            format!(
                "unknown method '{id}' (known: {})",
                methods::ids().join(", ")
            ),
            vec![],
        )
    })
}

fn options(time_limit: Option<f64>) -> PyResult<MethodOptions> {
    let mut o = MethodOptions::default();
    if let Some(s) = time_limit {
        if !(s.is_finite() && s > 0.0) {
            return Err(native(
                "invalid_input",
                format!("time_limit must be a positive number of seconds or None, got {s}"),
                vec![],
            ));
        }
        o.time_limit = Some(Duration::from_secs_f64(s));
    }
    Ok(o)
}

fn json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| native("serialisation", format!("JSON: {e}"), vec![]))
}

/// Runs `f` on a worker thread with the GIL released, inside a budget scope whose cancel flag
/// is raised when Python has a pending signal (Ctrl-C); then the signal's exception is raised
/// once the worker has stopped.
fn interruptible<T: Send>(py: Python<'_>, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    let flag = Arc::new(AtomicBool::new(false));
    let (tx, rx) = channel();
    std::thread::scope(|s| {
        let cancel = flag.clone();
        s.spawn(move || {
            let r = catch_unwind(AssertUnwindSafe(|| {
                within(Budget::unlimited().with_cancel(cancel), f)
            }));
            let _ = tx.send(r);
        });
        let mut pending: Option<PyErr> = None;
        let mut rx = rx;
        loop {
            // The receiver is Send but not Sync: it moves into the GIL-free closure and back.
            let (got, back) = py.allow_threads(move || {
                let got = rx.recv_timeout(Duration::from_millis(20));
                (got, rx)
            });
            rx = back;
            match got {
                Ok(Ok(value)) => {
                    return match pending {
                        Some(e) => Err(e),
                        None => Ok(value),
                    };
                }
                Ok(Err(_)) | Err(RecvTimeoutError::Disconnected) => {
                    return Err(PyRuntimeError::new_err(
                        "internal error: the Rust core panicked (please report this input)",
                    ));
                }
                Err(RecvTimeoutError::Timeout) => {
                    if pending.is_none()
                        && let Err(e) = py.check_signals()
                    {
                        flag.store(true, Ordering::SeqCst);
                        pending = Some(e);
                    }
                }
            }
        }
    })
}

fn rows(m: MatRef<'_, f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

fn mat(name: &str, r: &[Vec<f64>]) -> PyResult<Mat<f64>> {
    let c = r.first().map_or(0, |x| x.len());
    if r.iter().any(|x| x.len() != c) {
        return Err(native(
            "invalid_input",
            format!("{name}: rows of different lengths"),
            vec![],
        ));
    }
    Ok(Mat::from_fn(r.len(), c, |i, j| r[i][j]))
}

/// Validates a plant file text (`path` names it in messages) and returns its data as a dict of
/// nested lists: name, A, B, C, window, sensors, lipschitz, bounds.
#[pyfunction]
fn parse_plant(py: Python<'_>, text: &str, path: &str) -> PyResult<PyObject> {
    let f = plant_file(text, path)?;
    let d = PyDict::new(py);
    d.set_item("name", &f.name)?;
    d.set_item("A", rows(f.a.as_ref()))?;
    d.set_item("B", f.b.as_ref().map(|b| rows(b.as_ref())))?;
    d.set_item("C", f.c.as_ref().map(|c| rows(c.as_ref())))?;
    d.set_item("window", f.window.map(|w| (w.t1(), w.t2())))?;
    let sensors = PyList::empty(py);
    for s in &f.sensors {
        sensors.append((rows(s.c.as_ref()), (s.window.t1(), s.window.t2())))?;
    }
    d.set_item("sensors", sensors)?;
    match &f.lipschitz {
        Some(l) => {
            let ld = PyDict::new(py);
            ld.set_item("G", rows(l.g.as_ref()))?;
            ld.set_item("H", rows(l.h.as_ref()))?;
            ld.set_item("jacobian_lower", rows(l.jacobian_lower.as_ref()))?;
            ld.set_item("jacobian_upper", rows(l.jacobian_upper.as_ref()))?;
            d.set_item("lipschitz", ld)?;
        }
        None => d.set_item("lipschitz", py.None())?,
    }
    match &f.bounds {
        Some(b) => {
            let bd = PyDict::new(py);
            bd.set_item("disturbance", &b.disturbance)?;
            bd.set_item("noise", &b.noise)?;
            d.set_item("bounds", bd)?;
        }
        None => d.set_item("bounds", py.None())?,
    }
    Ok(d.into_any().unbind())
}

/// The registered method ids, in registry order.
#[pyfunction]
fn method_ids() -> Vec<&'static str> {
    methods::ids()
}

/// The proof options of `--prove [--proof-pieces N]` with the call's time budget.
fn proof_options(pieces: Option<usize>, o: &MethodOptions) -> PyResult<ProofOptions> {
    let max_pieces = pieces.unwrap_or(ProofOptions::default().max_pieces);
    if max_pieces == 0 {
        return Err(native(
            "invalid_input",
            "proof_pieces must be at least 1".into(),
            vec![],
        ));
    }
    Ok(ProofOptions {
        max_pieces,
        time_limit: o.time_limit,
    })
}

/// `sporadic design FILE --method M [--prove [--proof-pieces N]] --json` on a plant-file text:
/// the report's JSON (with a `proof` section when `prove`).
#[pyfunction]
#[pyo3(signature = (text, path, method_id, time_limit=None, prove=false, proof_pieces=None))]
fn design(
    py: Python<'_>,
    text: &str,
    path: &str,
    method_id: &str,
    time_limit: Option<f64>,
    prove: bool,
    proof_pieces: Option<usize>,
) -> PyResult<String> {
    let file = plant_file(text, path)?;
    let m = method(method_id)?;
    let o = options(time_limit)?;
    let po = proof_options(proof_pieces, &o)?;
    let r = interruptible(py, || {
        let mut report = methods::design(&file, m.as_ref(), &o)?;
        if prove {
            report.proof = Some(methods::prove(&file, m.as_ref(), &report, &po)?);
        }
        Ok(report)
    })?;
    json(&r.map_err(method_error)?)
}

/// `sporadic verify FILE --method M --gains G.json [--window T1 T2] [--prove] --json`: checks
/// the gains of `gains_json` (a design report, `{"gains": [...], "certificate": [...]}` or an
/// array of gains) and returns the report's JSON, always with a `proof` section.
#[pyfunction]
#[pyo3(signature = (text, path, method_id, gains_json, window=None, prove=false, proof_pieces=None, time_limit=None))]
fn verify(
    py: Python<'_>,
    text: &str,
    path: &str,
    method_id: &str,
    gains_json: &str,
    window: Option<(f64, f64)>,
    prove: bool,
    proof_pieces: Option<usize>,
    time_limit: Option<f64>,
) -> PyResult<String> {
    let file = plant_file(text, path)?;
    let m = method(method_id)?;
    let o = options(time_limit)?;
    let (gains, certificate) = sporadic::gains_file::parse_gains(gains_json)
        .map_err(|e| native("invalid_input", e.to_string(), vec![]))?;
    let window = window
        .map(|(t1, t2)| {
            SamplingWindow::new(t1, t2)
                .map_err(|e| native("invalid_input", format!("window: {e}"), vec![]))
        })
        .transpose()?;
    let po = proof_options(proof_pieces, &o)?;
    let r = interruptible(py, || {
        let mut report = methods::verify(&file, m.as_ref(), &gains, &certificate, window, &o)?;
        report.proof = Some(if prove || !report.status.is_certified() {
            methods::prove(&file, m.as_ref(), &report, &po)?
        } else {
            Proof::not_attempted(
                ProofStatus::Inconclusive,
                "no proof was asked for (--prove)",
            )
        });
        Ok(report)
    })?;
    json(&r.map_err(method_error)?)
}

/// The default search limit of a plant file (10 × its largest T2), if it has sampling.
#[pyfunction]
fn default_limit(text: &str, path: &str) -> PyResult<Option<f64>> {
    Ok(methods::default_limit(&plant_file(text, path)?))
}

fn check_limit(l: f64) -> PyResult<f64> {
    if !(l.is_finite() && l > 0.0) {
        return Err(native(
            "invalid_input",
            format!("limit must be a positive finite number, got {l}"),
            vec![],
        ));
    }
    Ok(l)
}

/// `sporadic max-interval FILE --method M [--limit L] --json`: the report's JSON.
#[pyfunction]
#[pyo3(signature = (text, path, method_id, limit=None, time_limit=None))]
fn max_interval(
    py: Python<'_>,
    text: &str,
    path: &str,
    method_id: &str,
    limit: Option<f64>,
    time_limit: Option<f64>,
) -> PyResult<String> {
    let file = plant_file(text, path)?;
    let m = method(method_id)?;
    let o = options(time_limit)?;
    let limit = match (limit, methods::default_limit(&file)) {
        (Some(l), _) => check_limit(l)?,
        (None, Some(l)) => l,
        // No sampling in the file: the method reports it as missing data (as the CLI).
        (None, None) => f64::NAN,
    };
    let r = interruptible(py, || {
        methods::max_interval(&file, m.as_ref(), limit, &o, &mut |_| {})
    })?;
    json(&r.map_err(method_error)?)
}

/// `sporadic compare FILE [--limit L | --no-search] --json`: the report's JSON.
#[pyfunction]
#[pyo3(signature = (text, path, search=true, limit=None, time_limit=None))]
fn compare(
    py: Python<'_>,
    text: &str,
    path: &str,
    search: bool,
    limit: Option<f64>,
    time_limit: Option<f64>,
) -> PyResult<String> {
    let file = plant_file(text, path)?;
    let o = options(time_limit)?;
    let limit = match limit {
        _ if !search => None,
        Some(l) => Some(check_limit(l)?),
        None => methods::default_limit(&file),
    };
    let r = interruptible(py, || methods::compare(&file, &o, limit, &mut |_, _| {}))?;
    json(&r.map_err(method_error)?)
}

/// Designs and simulates: (design JSON, quantity, t, j, signal names, signals, norm, summary
/// JSON). Raises when the design is not certified or the method has no simulation.
#[pyfunction]
#[pyo3(signature = (text, path, method_id, horizon=None, initial_error=None, scenario="uniform", seed=1, time_limit=None, x0=None))]
fn simulate(
    py: Python<'_>,
    text: &str,
    path: &str,
    method_id: &str,
    horizon: Option<f64>,
    initial_error: Option<Vec<f64>>,
    scenario: &str,
    seed: u64,
    time_limit: Option<f64>,
    x0: Option<Vec<f64>>,
) -> PyResult<PyObject> {
    let file = plant_file(text, path)?;
    let n = file.a.nrows();
    let x0 = x0.unwrap_or_else(|| vec![0.0; n]);
    if x0.len() != n {
        return Err(native(
            "invalid_input",
            format!(
                "x0 must have {n} entries (the plant's states), got {}",
                x0.len()
            ),
            vec![],
        ));
    }
    if let Some(bad) = x0.iter().find(|v| !v.is_finite()) {
        return Err(native(
            "invalid_input",
            format!("x0 entries must be finite, got {bad}"),
            vec![],
        ));
    }
    let m = method(method_id)?;
    let o = options(time_limit)?;
    if let Some(h) = horizon
        && !(h.is_finite() && h > 0.0)
    {
        return Err(native(
            "invalid_input",
            format!("horizon must be a positive finite time, got {h}"),
            vec![],
        ));
    }
    if let Some(e) = &initial_error
        && let Some(bad) = e.iter().find(|v| !v.is_finite())
    {
        return Err(native(
            "invalid_input",
            format!("initial_error entries must be finite, got {bad}"),
            vec![],
        ));
    }
    let sampling = match scenario {
        "uniform" => SamplingScenario::Uniform { seed },
        "periodic_t1" => SamplingScenario::PeriodicT1,
        "periodic_t2" => SamplingScenario::PeriodicT2,
        other => {
            return Err(native(
                "invalid_input",
                format!(
                    "scenario must be 'uniform', 'periodic_t1' or 'periodic_t2', got '{other}'"
                ),
                vec![],
            ));
        }
    };
    let sc = Scenario {
        horizon,
        initial_error,
        sampling,
    };
    let (report, run) = interruptible(py, || {
        let mut report = methods::design(&file, m.as_ref(), &o)?;
        if !report.status.is_certified() {
            return Ok((report, None));
        }
        let run = methods::simulate(&file, m.as_ref(), &report, &sc)?;
        report.simulation = Some(run.report.clone());
        Ok((report, Some(run)))
    })?
    .map_err(method_error)?;
    let design_json = json(&report)?;
    let Some(run) = run else {
        return Err(native(
            "not_certified",
            format!(
                "{method_id} does not certify this plant (status {}), so there is no observer to simulate",
                json(&report.status)?
            ),
            vec![("report", design_json.into_pyobject(py)?.into_any().unbind())],
        ));
    };
    let names: Vec<String> = run.signals.iter().map(|(n, _)| n.clone()).collect();
    let signals: Vec<Vec<f64>> = run.signals.into_iter().map(|(_, v)| v).collect();
    let summary = json(&run.report)?;
    let x = if plant_is_linear_error(&file, method_id, signals.len()) {
        Some(linear_flow(file.a.as_ref(), &x0, &run.t)?)
    } else {
        None
    };
    Ok((
        design_json,
        run.quantity,
        run.t,
        run.j,
        names,
        signals,
        run.norm,
        summary,
        x,
    )
        .into_pyobject(py)?
        .into_any()
        .unbind())
}

/// Whether a method's simulated signals are the estimation error `x − x̂` of the plant's state
/// under the flow `ẋ = Ax` (a linear plant without input, which does not jump): ferrante2016,
/// sferlazza2021 and andrieu2014 on a plant without a Lipschitz nonlinearity.
fn plant_is_linear_error(file: &PlantFile, method_id: &str, signals: usize) -> bool {
    matches!(method_id, "ferrante2016" | "sferlazza2021" | "andrieu2014")
        && file.lipschitz.is_none()
        && signals == file.a.nrows()
}

/// `x(t_k) = e^{A t_k} x0` at every time (rows: states); consecutive equal times (a jump) share
/// one exponential.
fn linear_flow(a: MatRef<'_, f64>, x0: &[f64], t: &[f64]) -> PyResult<Vec<Vec<f64>>> {
    let n = a.nrows();
    let mut out = vec![Vec::with_capacity(t.len()); n];
    let mut last: Option<(f64, Vec<f64>)> = None;
    for &tk in t {
        let x = match &last {
            Some((tl, x)) if *tl == tk => x.clone(),
            _ => {
                let at = Mat::from_fn(n, n, |i, j| a[(i, j)] * tk);
                let e = sporadic::linalg::expm(at.as_ref())
                    .map_err(|e| native(&kind_of(&e), format!("x(t) = e^(At) x0: {e}"), vec![]))?;
                (0..n)
                    .map(|i| (0..n).map(|j| e[(i, j)] * x0[j]).sum())
                    .collect()
            }
        };
        for (i, v) in x.iter().enumerate() {
            out[i].push(*v);
        }
        last = Some((tk, x));
    }
    Ok(out)
}

/// The matrix exponential `e^A` of the linalg kernel.
#[pyfunction]
fn expm(a: Vec<Vec<f64>>) -> PyResult<Vec<Vec<f64>>> {
    let a = mat("A", &a)?;
    let e = sporadic::linalg::expm(a.as_ref())
        .map_err(|e| native(&kind_of(&e), format!("expm: {e}"), vec![]))?;
    Ok(rows(e.as_ref()))
}

fn solution_dict(py: Python<'_>, sol: &sporadic::sdp::Solution, sdpa: bool) -> PyResult<PyObject> {
    let d = PyDict::new(py);
    d.set_item("status", sol.status.as_str())?;
    if sdpa {
        let o = sporadic::sdp::sdpa_objectives(sol);
        d.set_item(
            "sdpa_status",
            sporadic::sdp::sdpa::sdpa_status_id(sol.status),
        )?;
        d.set_item("sdpa_primal_objective", o.primal)?;
        d.set_item("sdpa_dual_objective", o.dual)?;
    }
    d.set_item("primal_objective", sol.primal_objective)?;
    d.set_item("dual_objective", sol.dual_objective)?;
    d.set_item("y", &sol.y)?;
    let xs: Vec<Vec<Vec<f64>>> = sol.x.iter().map(|m| rows(m.as_ref())).collect();
    let zs: Vec<Vec<Vec<f64>>> = sol.s.iter().map(|m| rows(m.as_ref())).collect();
    d.set_item("X", xs)?;
    d.set_item("Z", zs)?;
    d.set_item("dimacs", sol.measures.dimacs.to_vec())?;
    d.set_item("iterations", sol.iterations)?;
    d.set_item("seconds", sol.solve_time.as_secs_f64())?;
    Ok(d.into_any().unbind())
}

fn sdp_error(e: sporadic::sdp::SdpError) -> PyErr {
    native(&kind_of(&e), e.to_string(), vec![])
}

fn solve_problem(
    py: Python<'_>,
    problem: &sporadic::sdp::Problem,
    time_limit: Option<f64>,
    sdpa: bool,
) -> PyResult<PyObject> {
    let limit = options(time_limit)?.time_limit;
    let sol = interruptible(py, || {
        within(Budget::for_duration(limit), || {
            sporadic::sdp::solve(problem, &Settings::default())
        })
    })?
    .map_err(sdp_error)?;
    solution_dict(py, &sol, sdpa)
}

/// Reads an SDPA sparse file (`.dat-s`) and solves it.
#[pyfunction]
#[pyo3(signature = (path, time_limit=None))]
fn solve_sdpa(py: Python<'_>, path: &str, time_limit: Option<f64>) -> PyResult<PyObject> {
    let problem = sporadic::sdp::read_sdpa_file(path).map_err(sdp_error)?;
    solve_problem(py, &problem, time_limit, true)
}

/// Solves `min ⟨C, X⟩ s.t. ⟨A_i, X⟩ = b_i, X ⪰ 0` over blocks (kind, size); the data are
/// upper-triangle triplets: `c` of (block, i, j, value), `a` of (constraint, block, i, j, value).
#[pyfunction]
#[pyo3(signature = (blocks, b, c, a, time_limit=None))]
fn solve(
    py: Python<'_>,
    blocks: Vec<(String, usize)>,
    b: Vec<f64>,
    c: Vec<(usize, usize, usize, f64)>,
    a: Vec<(usize, usize, usize, usize, f64)>,
    time_limit: Option<f64>,
) -> PyResult<PyObject> {
    let mut builder = ProblemBuilder::new(b.len());
    for (kind, size) in &blocks {
        let kind = match kind.as_str() {
            "psd" => BlockKind::Psd,
            "lp" => BlockKind::Lp,
            other => {
                return Err(native(
                    "invalid_input",
                    format!("block kind must be 'psd' or 'lp', got '{other}'"),
                    vec![],
                ));
            }
        };
        builder.add_block(kind, *size);
    }
    for (i, &v) in b.iter().enumerate() {
        builder.set_b(i, v);
    }
    for &(blk, i, j, v) in &c {
        builder.add_c(blk, i, j, v);
    }
    for &(k, blk, i, j, v) in &a {
        builder.add_a(k, blk, i, j, v);
    }
    let problem = builder.build().map_err(sdp_error)?;
    solve_problem(py, &problem, time_limit, false)
}

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("NativeError", m.py().get_type::<NativeError>())?;
    m.add_function(wrap_pyfunction!(parse_plant, m)?)?;
    m.add_function(wrap_pyfunction!(method_ids, m)?)?;
    m.add_function(wrap_pyfunction!(design, m)?)?;
    m.add_function(wrap_pyfunction!(verify, m)?)?;
    m.add_function(wrap_pyfunction!(default_limit, m)?)?;
    m.add_function(wrap_pyfunction!(max_interval, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(expm, m)?)?;
    m.add_function(wrap_pyfunction!(solve_sdpa, m)?)?;
    m.add_function(wrap_pyfunction!(solve, m)?)?;
    Ok(())
}
