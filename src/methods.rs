//! The observer methods behind `sporadic design`, `sporadic max-interval` and `sporadic compare`:
//! one adapter per paper crate, from a [`PlantFile`] to a certified design and a largest
//! certified sampling window.
//!
//! Every result returned here comes from the paper crate's own design routine, which re-verifies
//! its certificate in f64 (eigenvalues of the LMIs at the returned point and a dense check of
//! the original parametric condition) before reporting success; a method that cannot certify
//! the plant returns [`MethodError::NotCertified`] with the crate's reason. Andrieu et al. (2014)
//! is always [`MethodError::NotApplicable`] here: its observer chooses its own sampling instants
//! (no window to certify) for plants in observability normal form written as code.
//! [`simulate`] runs a certified design (ferrante2016, rabehi2021) and writes an SVG figure.

use crate::plant_file::{PlantFile, SamplingWindow};
use faer::Mat;
use std::fmt;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The observer designs of the five papers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// Ferrante, Gouaisbaut, Tarbouriech (2016): sporadic single-rate sampling, polytopic
    /// embedding of `e^{Aτ}`, LMI (41).
    Ferrante2016,
    /// Sferlazza, Tarbouriech, Zaccarian (2021): round-robin sensors with jitter, time-varying
    /// gains by iterative refinement of the sampling grid.
    Sferlazza2021,
    /// Etienne, Di Gennaro, Barbot (2017): impulsive observer for Lipschitz systems.
    Etienne2017,
    /// Rabehi, Meslem, Ramdani (2021): interval impulsive observer.
    Rabehi2021,
    /// Andrieu, Nadri, Serres, Vivalda (2014): high-gain observer with updated sampling.
    Andrieu2014,
}

impl Method {
    /// All methods, in seed order.
    pub const ALL: [Method; 5] = [
        Method::Ferrante2016,
        Method::Sferlazza2021,
        Method::Andrieu2014,
        Method::Etienne2017,
        Method::Rabehi2021,
    ];

    /// The paper id used on the command line.
    pub fn id(self) -> &'static str {
        match self {
            Method::Ferrante2016 => "ferrante2016",
            Method::Sferlazza2021 => "sferlazza2021",
            Method::Etienne2017 => "etienne2017",
            Method::Rabehi2021 => "rabehi2021",
            Method::Andrieu2014 => "andrieu2014",
        }
    }

    /// Parses a paper id.
    pub fn from_id(id: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.id() == id)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.id())
    }
}

/// Why a method produced no certified design.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MethodError {
    /// The plant file lacks what the method needs (e.g. a Lipschitz section).
    #[error("{method} does not apply to this plant: {why}")]
    NotApplicable {
        /// The method.
        method: Method,
        /// What is missing.
        why: String,
    },
    /// The simulation of a certified design failed, or it is not offered for the method.
    #[error("{method}: simulation: {why}")]
    Simulation {
        /// The method.
        method: Method,
        /// What went wrong.
        why: String,
    },
    /// The method ran but could not certify a design (infeasible LMIs, failed verification,
    /// non-detectable plant, …).
    #[error("{method}: no certified design: {why}")]
    NotCertified {
        /// The method.
        method: Method,
        /// The crate's reason.
        why: String,
    },
}

/// A matrix with the paper's name for it.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedMatrix {
    /// Name, e.g. `L` or `P`.
    pub name: String,
    /// Value.
    pub value: Mat<f64>,
}

impl NamedMatrix {
    fn new(name: impl Into<String>, value: Mat<f64>) -> Self {
        Self {
            name: name.into(),
            value,
        }
    }

    /// Rows as nested vectors (for JSON/TOML output).
    pub fn rows(&self) -> Vec<Vec<f64>> {
        (0..self.value.nrows())
            .map(|i| {
                (0..self.value.ncols())
                    .map(|j| self.value[(i, j)])
                    .collect()
            })
            .collect()
    }
}

/// A certified observer design.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignSummary {
    /// The method.
    pub method: Method,
    /// The sampling window(s) certified, in words (e.g. `[0.2, 3]`).
    pub window: String,
    /// The same window(s) as numbers (one per sensor for round-robin designs).
    pub windows: Vec<SamplingWindow>,
    /// Certified margin of the method's LMIs (its meaning is method-specific, see `notes`).
    pub margin: f64,
    /// The observer gain(s).
    pub gains: Vec<NamedMatrix>,
    /// The certificate (Lyapunov matrices and multipliers).
    pub certificate: Vec<NamedMatrix>,
    /// What was checked, and anything a user should know.
    pub notes: Vec<String>,
    /// Wall time of the design, seconds.
    pub seconds: f64,
}

/// Result of a largest-window search.
#[derive(Debug, Clone, PartialEq)]
pub struct MaxInterval {
    /// The method.
    pub method: Method,
    /// The lower end kept fixed (`T1`, or the shortest interval of the first sensor).
    pub t1: f64,
    /// Largest certified upper end (`None`: not even the shortest window is certified).
    pub best: Option<f64>,
    /// The first failing upper end above `best` (`None` when the search limit was certified).
    pub first_failure: Option<f64>,
    /// The design at `best`.
    pub design: Option<DesignSummary>,
    /// Wall time of the whole search, seconds.
    pub seconds: f64,
}

/// Designs an observer for the plant with the given method.
pub fn design(plant: &PlantFile, method: Method) -> Result<DesignSummary, MethodError> {
    let start = Instant::now();
    let mut d = match method {
        Method::Ferrante2016 => ferrante::design(plant)?,
        Method::Sferlazza2021 => sferlazza::design(plant)?,
        Method::Etienne2017 => etienne::design(plant)?,
        Method::Rabehi2021 => rabehi::design(plant)?,
        Method::Andrieu2014 => return Err(andrieu::not_applicable()),
    };
    d.seconds = start.elapsed().as_secs_f64();
    Ok(d)
}

/// A simulation of a certified design: the figure written and what it shows.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationSummary {
    /// The SVG figure.
    pub figure: PathBuf,
    /// The initial condition, the sampling and the horizon, in words.
    pub setup: String,
    /// The main numbers of the run (final error or width, samples, inclusion check).
    pub result: String,
}

/// Simulates a design returned by [`design`] for the same plant from a stated initial
/// condition with sampling intervals drawn uniformly at random in the certified window (seed
/// `seed`), and writes an SVG of the estimation error (ferrante2016) or of the interval width
/// (rabehi2021) to `out_dir`.
pub fn simulate(
    plant: &PlantFile,
    design: &DesignSummary,
    out_dir: &Path,
    seed: u64,
) -> Result<SimulationSummary, MethodError> {
    let method = design.method;
    let err = simulation_error(method);
    std::fs::create_dir_all(out_dir).map_err(|e| err(format!("{}: {e}", out_dir.display())))?;
    match method {
        Method::Ferrante2016 => ferrante::simulate(plant, design, out_dir, seed),
        Method::Rabehi2021 => rabehi::simulate(plant, design, out_dir, seed),
        Method::Sferlazza2021 => sferlazza::simulate(plant, design, out_dir, seed),
        _ => Err(err(
            "--simulate is available for ferrante2016, sferlazza2021 and rabehi2021 (etienne2017 would need the nonlinearity phi itself, which a plant file only bounds; andrieu2014 has its simulations in `sporadic reproduce`)".into(),
        )),
    }
}

/// The error of a simulation of `method`, with the reason.
fn simulation_error(method: Method) -> impl Fn(String) -> MethodError {
    move |why| MethodError::Simulation { method, why }
}

/// Writes `<method>_error.svg`: the estimation-error norm over hybrid time `(t, j)`.
fn write_error_figure(
    method: Method,
    plant: &PlantFile,
    out_dir: &Path,
    t: &[f64],
    j: &[usize],
    norms: &[f64],
) -> Result<PathBuf, MethodError> {
    let path = out_dir.join(format!("{method}_error.svg"));
    let spec = sporadic_figures::PlotSpec::new(
        &format!("{method}: estimation error, {}", plant.name),
        "time [s]",
        "|x - x_hat|",
    );
    sporadic_figures::plot_error_norm(&path, &spec, t, j, norms, None)
        .map_err(|e| simulation_error(method)(format!("{}: {e}", path.display())))?;
    Ok(path)
}

/// What an adapter's window search found: the fixed `T1`, the largest certified and the first
/// failing upper end, and the design at the largest certified end when the search kept it.
type Search = (f64, Option<f64>, Option<f64>, Option<DesignSummary>);

/// Largest certified window `[T1, T2]` with `T1` from the plant file and `T2 ≤ limit`
/// (bisection to about 1% relative); `progress` receives one line per probe.
pub fn max_interval(
    plant: &PlantFile,
    method: Method,
    limit: f64,
    progress: &mut dyn FnMut(&str),
) -> Result<MaxInterval, MethodError> {
    let start = Instant::now();
    let (t1, best, first_failure, kept) = match method {
        Method::Ferrante2016 => ferrante::max_interval(plant, limit, progress)?,
        Method::Sferlazza2021 => sferlazza::max_interval(plant, limit, progress)?,
        Method::Etienne2017 => etienne::max_interval(plant, limit, progress)?,
        Method::Rabehi2021 => rabehi::max_interval(plant, limit, progress)?,
        Method::Andrieu2014 => return Err(andrieu::not_applicable()),
    };
    let design = match (best, kept) {
        (_, Some(mut d)) => {
            // The design was kept from the search: its time is the search's.
            d.seconds = start.elapsed().as_secs_f64();
            Some(d)
        }
        (Some(t2), None) => {
            let mut p = plant.clone();
            p.window = Some(SamplingWindow { t1, t2 });
            if method == Method::Sferlazza2021 {
                for s in &mut p.sensors {
                    s.window.t2 = t2.max(s.window.t1);
                }
            }
            Some(self::design(&p, method)?)
        }
        (None, None) => None,
    };
    Ok(MaxInterval {
        method,
        t1,
        best,
        first_failure,
        design,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// A window `[T1, T2]` in words, ends rounded to 6 significant digits.
fn window_words(t1: f64, t2: f64) -> String {
    let num = |x: f64| format!("{}", format!("{x:.5e}").parse::<f64>().unwrap_or(x));
    format!("[{}, {}]", num(t1), num(t2))
}

/// One progress line per probe of a window search.
fn report_probe(progress: &mut dyn FnMut(&str), t2: f64, certified: bool) {
    progress(&format!(
        "T2 = {t2:.6}: {}",
        if certified {
            "certified"
        } else {
            "not certified"
        }
    ));
}

/// Bisection on the upper end `t2 ∈ [t1, limit]` of a window, assuming feasibility is monotone
/// (a larger window contains a smaller one, so a design certified on it is certified on the
/// smaller one): returns the largest certified end found and the first failing end above it.
fn bisect_upper(
    t1: f64,
    limit: f64,
    certified: &mut dyn FnMut(f64) -> bool,
    progress: &mut dyn FnMut(&str),
) -> (Option<f64>, Option<f64>) {
    let mut probe = |t2: f64| {
        let ok = certified(t2);
        report_probe(progress, t2, ok);
        ok
    };
    if probe(limit) {
        return (Some(limit), None);
    }
    if !probe(t1) {
        return (None, Some(t1));
    }
    let (mut lo, mut hi) = (t1, limit);
    while hi / lo - 1.0 > 1e-2 {
        let mid = 0.5 * (lo + hi);
        if probe(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (Some(lo), Some(hi))
}

/// The linear-plant methods do not cover a Lipschitz nonlinearity.
fn linear_only(plant: &PlantFile, method: Method) -> Result<(), MethodError> {
    match plant.lipschitz {
        Some(_) => Err(MethodError::NotApplicable {
            method,
            why: "the plant has a [lipschitz] nonlinearity; this method is for linear plants"
                .into(),
        }),
        None => Ok(()),
    }
}

fn single_output(
    plant: &PlantFile,
    method: Method,
) -> Result<(&Mat<f64>, SamplingWindow), MethodError> {
    linear_only(plant, method)?;
    let c = plant.c.as_ref().ok_or_else(|| MethodError::NotApplicable {
        method,
        why: "needs plant.C".into(),
    })?;
    let w = plant.window.ok_or_else(|| MethodError::NotApplicable {
        method,
        why: "needs [sampling] window".into(),
    })?;
    Ok((c, w))
}

mod ferrante {
    use super::*;
    use sporadic_ferrante2016 as f;
    use sporadic_sim as sim;

    fn plant_of(plant: &PlantFile) -> Result<(f::Plant, SamplingWindow), MethodError> {
        let (c, w) = single_output(plant, Method::Ferrante2016)?;
        let p = f::Plant::new(plant.a.as_ref(), c.as_ref()).map_err(|e| fail(e.to_string()))?;
        Ok((p, w))
    }

    fn fail(why: String) -> MethodError {
        MethodError::NotCertified {
            method: Method::Ferrante2016,
            why,
        }
    }

    pub(super) fn design(plant: &PlantFile) -> Result<DesignSummary, MethodError> {
        let (p, w) = plant_of(plant)?;
        let window = f::Window::new(w.t1, w.t2).map_err(|e| fail(e.to_string()))?;
        let d = f::design(&p, &window, &f::DesignOptions::default())
            .map_err(|e| fail(e.to_string()))?;
        Ok(DesignSummary {
            method: Method::Ferrante2016,
            window: window_words(w.t1, w.t2),
            windows: vec![w],
            margin: d.certificate.margin,
            gains: vec![NamedMatrix::new("L", d.l.clone())],
            certificate: vec![
                NamedMatrix::new("P", d.certificate.p.clone()),
                NamedMatrix::new("F", d.certificate.f.clone()),
                NamedMatrix::new("J", d.certificate.j.clone()),
            ],
            notes: vec![
                format!(
                    "LMI (41) at {} vertices of the embedding of e^(A v), v in [T1, T2]; margin: Phi_i <= -margin I",
                    d.embedding.vertex_count()
                ),
                format!(
                    "condition (12) re-verified on {} points of [T1, T2]: max eigenvalue {:.3e}",
                    d.verification.grid_points, d.verification.max_eigenvalue
                ),
            ],
            seconds: 0.0,
        })
    }

    /// The error system (5) from `ε(0) = (1, …, 1)` over 30 longest intervals.
    pub(super) fn simulate(
        plant: &PlantFile,
        design: &DesignSummary,
        out_dir: &Path,
        seed: u64,
    ) -> Result<SimulationSummary, MethodError> {
        let err = simulation_error(Method::Ferrante2016);
        let (p, _) = plant_of(plant)?;
        let w = design.windows[0];
        let l = &design.gains[0].value;
        let eps0 = vec![1.0; plant.n()];
        let horizon = 30.0 * w.t2;
        let mut rule = sim::UniformRandom::new(w.t1, w.t2, seed).map_err(|e| err(e.to_string()))?;
        let arc = f::simulate_error(
            &p,
            l.as_ref(),
            &mut rule,
            &eps0,
            &sim::SimOptions::new(horizon),
        )
        .map_err(|e| err(e.to_string()))?;
        let norms = arc.norms();
        let path = write_error_figure(
            Method::Ferrante2016,
            plant,
            out_dir,
            arc.times(),
            arc.jump_counters(),
            &norms,
        )?;
        Ok(SimulationSummary {
            figure: path,
            setup: format!(
                "error system (5), e(0) = (1, ..., 1), |e(0)| = {:.4}, intervals uniform in [{}, {}] (seed {seed}), horizon {horizon} s",
                (plant.n() as f64).sqrt(),
                w.t1,
                w.t2
            ),
            result: format!(
                "{} samples, |e| at the end = {:.3e}",
                arc.num_jumps(),
                norms.last().copied().unwrap_or(f64::NAN)
            ),
        })
    }

    pub(super) fn max_interval(
        plant: &PlantFile,
        limit: f64,
        progress: &mut dyn FnMut(&str),
    ) -> Result<Search, MethodError> {
        let (p, w) = plant_of(plant)?;
        let opts = f::WindowSearchOptions::default();
        let s = f::largest_t2(&p, w.t1, limit.max(w.t1), &opts).map_err(|e| fail(e.to_string()))?;
        for pr in &s.probes {
            report_probe(progress, pr.t2, pr.certified);
        }
        Ok((w.t1, s.best, s.first_failure, None))
    }
}

mod sferlazza {
    use super::*;
    use sporadic_sferlazza2021 as s;
    use sporadic_sferlazza2021::plant::{RoundRobinPlant, Window};

    fn fail(why: String) -> MethodError {
        MethodError::NotCertified {
            method: Method::Sferlazza2021,
            why,
        }
    }

    /// The round-robin sensors of the file, or its single output as one sensor.
    fn plant_of(plant: &PlantFile) -> Result<RoundRobinPlant, MethodError> {
        linear_only(plant, Method::Sferlazza2021)?;
        let sensors: Vec<(Mat<f64>, Window)> = if plant.sensors.is_empty() {
            let (c, w) = single_output(plant, Method::Sferlazza2021)?;
            vec![(c.clone(), Window::new(w.t1, w.t2))]
        } else {
            plant
                .sensors
                .iter()
                .map(|x| (x.c.clone(), Window::new(x.window.t1, x.window.t2)))
                .collect()
        };
        RoundRobinPlant::new(plant.a.clone(), sensors).map_err(|e| fail(e.to_string()))
    }

    pub(super) fn design(plant: &PlantFile) -> Result<DesignSummary, MethodError> {
        let p = plant_of(plant)?;
        let d = s::design::design(&p, &s::design::DesignSettings::default())
            .map_err(|e| fail(e.to_string()))?;
        let windows: Vec<String> = p
            .sensors()
            .iter()
            .map(|x| window_words(x.window().t_min, x.window().t_max))
            .collect();
        let mut gains = Vec::new();
        for (i, x) in p.sensors().iter().enumerate() {
            for (end, tau) in [("min", x.window().t_min), ("max", x.window().t_max)] {
                let k = d.gains().gain(i, tau).map_err(|e| fail(e.to_string()))?;
                gains.push(NamedMatrix::new(format!("K_{}(T_{end})", i + 1), k));
            }
        }
        let certificate =
            d.p.iter()
                .enumerate()
                .map(|(i, m)| NamedMatrix::new(format!("P_{}", i + 1), m.clone()))
                .collect();
        Ok(DesignSummary {
            method: Method::Sferlazza2021,
            window: windows.join(" then "),
            windows: p
                .sensors()
                .iter()
                .map(|x| SamplingWindow {
                    t1: x.window().t_min,
                    t2: x.window().t_max,
                })
                .collect(),
            margin: d.mu,
            gains,
            certificate,
            notes: vec![
                format!(
                    "gain K_s(tau) of (45) depends on the time tau since the previous sample; listed at each window's ends; p* = {:.6}",
                    d.p_star
                ),
                format!(
                    "iterative refinement converged after {} syntheses; every sensor's condition validated on its window with margin mu",
                    d.log.len()
                ),
            ],
            seconds: 0.0,
        })
    }

    /// The error system (53) without noise from `x̃(0) = (1, …, 1)`, with the gain schedule
    /// (45) of the certificate's `P_σ`, over 40 rounds of the sensors.
    pub(super) fn simulate(
        plant: &PlantFile,
        design: &DesignSummary,
        out_dir: &Path,
        seed: u64,
    ) -> Result<SimulationSummary, MethodError> {
        let err = simulation_error(Method::Sferlazza2021);
        let p = plant_of(plant)?;
        let ps: Vec<Mat<f64>> = design.certificate.iter().map(|c| c.value.clone()).collect();
        let schedule = s::gain::GainSchedule::new(p.clone(), ps).map_err(|e| err(e.to_string()))?;
        let round: f64 = p.sensors().iter().map(|x| x.window().t_max).sum();
        let horizon = 40.0 * round;
        let mut settings = s::simulation::SimulationSettings::noise_free(horizon, vec![1.0; p.n()]);
        settings.seed = seed;
        settings.record_step = horizon / 4000.0;
        let run =
            s::simulation::simulate_error(&schedule, &settings).map_err(|e| err(e.to_string()))?;
        let norms: Vec<f64> = run
            .x
            .iter()
            .map(|x| x.iter().map(|v| v * v).sum::<f64>().sqrt())
            .collect();
        let path = write_error_figure(
            Method::Sferlazza2021,
            plant,
            out_dir,
            &run.t,
            &run.j,
            &norms,
        )?;
        let worst_ratio = run
            .jumps
            .iter()
            .map(|j| j.v_after / j.v_before)
            .fold(0.0, f64::max);
        Ok(SimulationSummary {
            figure: path,
            setup: format!(
                "error system (53) without noise, e(0) = (1, ..., 1), |e(0)| = {:.4}, sensors in round-robin order, intervals uniform in each sensor's window (seed {seed}), horizon {horizon:.4} s",
                (p.n() as f64).sqrt()
            ),
            result: format!(
                "{} samples, |e| at the end = {:.3e}, largest V+/V over the jumps = {worst_ratio:.4}",
                run.jumps.len(),
                norms.last().copied().unwrap_or(f64::NAN)
            ),
        })
    }

    pub(super) fn max_interval(
        plant: &PlantFile,
        limit: f64,
        progress: &mut dyn FnMut(&str),
    ) -> Result<Search, MethodError> {
        let base = plant_of(plant)?;
        let t1 = base.t_min();
        let mut certified = |t2: f64| {
            let windows: Vec<Window> = base
                .sensors()
                .iter()
                .map(|x| Window::new(x.window().t_min, t2.max(x.window().t_min)))
                .collect();
            base.with_windows(&windows).ok().is_some_and(|p| {
                s::design::design(&p, &s::design::DesignSettings::default()).is_ok()
            })
        };
        let (best, fail) = bisect_upper(t1, limit, &mut certified, progress);
        Ok((t1, best, fail, None))
    }
}

/// `B` of the file, or an `n × 0` matrix (no input).
fn input_matrix(plant: &PlantFile) -> Mat<f64> {
    plant.b.clone().unwrap_or_else(|| Mat::zeros(plant.n(), 0))
}

mod etienne {
    use super::*;
    use sporadic_etienne2017 as e;

    fn fail(why: String) -> MethodError {
        MethodError::NotCertified {
            method: Method::Etienne2017,
            why,
        }
    }

    fn not_applicable(why: impl Into<String>) -> MethodError {
        MethodError::NotApplicable {
            method: Method::Etienne2017,
            why: why.into(),
        }
    }

    /// The Lipschitz plant (1)–(2) of the file and its single-output window.
    fn plant_of(plant: &PlantFile) -> Result<(e::Plant, SamplingWindow), MethodError> {
        let lip = plant.lipschitz.as_ref().ok_or_else(|| {
            not_applicable(
                "needs a [lipschitz] section (G, H and the Jacobian bounds of phi); for a linear plant use ferrante2016",
            )
        })?;
        let c = plant
            .c
            .as_ref()
            .ok_or_else(|| not_applicable("needs plant.C (round-robin sensors are not covered)"))?;
        let w = plant
            .window
            .ok_or_else(|| not_applicable("needs [sampling] window"))?;
        let (q, r) = (lip.g.ncols(), lip.h.nrows());
        if q != r {
            return Err(not_applicable(format!(
                "phi must map R^m to R^m (G n×m, H m×n), but G has {q} columns and H has {r} rows"
            )));
        }
        let p = e::Plant::new(
            plant.a.as_ref(),
            input_matrix(plant).as_ref(),
            c.as_ref(),
            lip.g.as_ref(),
            lip.h.as_ref(),
            lip.jacobian_lower.as_ref(),
            lip.jacobian_upper.as_ref(),
        )
        .map_err(|e| fail(e.to_string()))?;
        Ok((p, w))
    }

    fn summary(d: &e::Design, vertices: usize) -> DesignSummary {
        let w = d.lmi.window;
        let (t1, t2) = (w.tau_low(), w.tau_bar());
        let gains = if d.gain.is_constant() {
            vec![NamedMatrix::new("K", d.gain.k1().to_owned())]
        } else {
            vec![
                NamedMatrix::new("K0 = K(T1)", d.gain.k0().to_owned()),
                NamedMatrix::new("K1 = K(T2)", d.gain.k1().to_owned()),
            ]
        };
        let cert = &d.lmi.certificate;
        let gain_words = match d.lmi.condition {
            e::Condition::Theorem3 => {
                "time-varying gain K(tau) interpolating K0 and K1 over the length tau of the interval that just ended"
            }
            _ => "static gain K",
        };
        DesignSummary {
            method: Method::Etienne2017,
            window: window_words(t1, t2),
            windows: vec![SamplingWindow { t1, t2 }],
            margin: d.lmi.margin,
            gains,
            certificate: vec![
                NamedMatrix::new("P1", cert.p1.clone()),
                NamedMatrix::new("P2", cert.p2.clone()),
            ],
            notes: vec![
                format!(
                    "{} (LMIs (20), {vertices} vertices R_p of the Jacobian box, Lemma 1): {gain_words}; margin t* of formulation F",
                    d.lmi.condition.name()
                ),
                format!(
                    "independent re-check passed: (19b)/(19c) on a tau-grid, max spectral radius of (I - K(tau)C)e^(R_p tau) = {:.4}",
                    d.check.discrete.spectral_radius.value
                ),
            ],
            seconds: 0.0,
        }
    }

    /// Corollary 2 (static gain) first; Theorem 3 (time-varying gain) when it fails; Remark 6
    /// for a periodic window.
    pub(super) fn design(plant: &PlantFile) -> Result<DesignSummary, MethodError> {
        let (p, w) = plant_of(plant)?;
        let window = e::Window::new(w.t1, w.t2).map_err(|e| fail(e.to_string()))?;
        let opts = e::DesignOptions::default();
        let vertices = p.vertices().len();
        if window.is_periodic() {
            let d = e::design(&p, e::Condition::Remark6, &window, &opts)
                .map_err(|e| fail(e.to_string()))?;
            return Ok(summary(&d, vertices));
        }
        match e::design(&p, e::Condition::Corollary2, &window, &opts) {
            Ok(d) => Ok(summary(&d, vertices)),
            Err(static_err) => match e::design(&p, e::Condition::Theorem3, &window, &opts) {
                Ok(d) => Ok(summary(&d, vertices)),
                Err(tv_err) => Err(fail(format!(
                    "Corollary 2 (static gain): {static_err}; Theorem 3 (time-varying gain): {tv_err}"
                ))),
            },
        }
    }

    /// Bisection of the crate on `τ̄` for Theorem 3 (which contains Corollary 2); the returned
    /// design is the crate's re-checked one at the largest verified probe.
    pub(super) fn max_interval(
        plant: &PlantFile,
        limit: f64,
        progress: &mut dyn FnMut(&str),
    ) -> Result<Search, MethodError> {
        let (p, w) = plant_of(plant)?;
        let opts = e::BisectionOptions {
            limit: limit.max(w.t1),
            tolerance: 1e-3 * w.t2,
            start: Some((2.0 * w.t1).min(limit.max(w.t1))).filter(|&s| s > w.t1),
            ..e::BisectionOptions::default()
        };
        let r = e::max_tau_bar(&p, e::Condition::Theorem3, w.t1, &opts)
            .map_err(|e| fail(e.to_string()))?;
        for pr in &r.probes {
            report_probe(progress, pr.tau_bar, pr.feasible && pr.verified);
        }
        let vertices = p.vertices().len();
        let design = r.certified.as_ref().map(|d| summary(d, vertices));
        let best = design.as_ref().map(|d| d.windows[0].t2);
        Ok((w.t1, best, r.infeasible, design))
    }
}

mod rabehi {
    use super::*;
    use sporadic_rabehi2021::observer::IntervalObserver;
    use sporadic_rabehi2021::simulation::{Disturbance, Noise, Scenario, simulate_interval};
    use sporadic_rabehi2021::synthesis::{DesignStatus, SynthesisOptions, synthesise};
    use sporadic_rabehi2021::system::{Bounds, Plant, Window};
    use sporadic_rabehi2021::width::WidthDynamics;
    use sporadic_rabehi2021::window::{WindowSearchOptions, largest_tau_max};

    fn fail(why: String) -> MethodError {
        MethodError::NotCertified {
            method: Method::Rabehi2021,
            why,
        }
    }

    /// The plant (2)–(3), its window and the bounds of Assumptions 2–3 (`|d_i| ≤ disturbance_i`
    /// as `d̲ = −d̄`; an omitted list means zero).
    pub(super) fn plant_of(
        plant: &PlantFile,
    ) -> Result<(Plant, SamplingWindow, Bounds), MethodError> {
        let (c, w) = single_output(plant, Method::Rabehi2021)?;
        let bounds = plant
            .bounds
            .as_ref()
            .ok_or_else(|| MethodError::NotApplicable {
                method: Method::Rabehi2021,
                why:
                    "the interval observer needs a [bounds] section (disturbance and noise bounds)"
                        .into(),
            })?;
        let p = Plant::new(plant.a.as_ref(), input_matrix(plant).as_ref(), c.as_ref())
            .map_err(|e| fail(e.to_string()))?;
        let d = if bounds.disturbance.is_empty() {
            vec![0.0; p.n()]
        } else {
            bounds.disturbance.clone()
        };
        let v = if bounds.noise.is_empty() {
            vec![0.0; p.p()]
        } else {
            bounds.noise.clone()
        };
        let b =
            Bounds::new(d.iter().map(|x| -x).collect(), d, v).map_err(|e| fail(e.to_string()))?;
        Ok((p, w, b))
    }

    fn summary(
        p: &Plant,
        bounds: &Bounds,
        window: &Window,
        d: &sporadic_rabehi2021::synthesis::Design,
    ) -> DesignSummary {
        let bmi = &d.bmi;
        let mut notes = vec![format!(
            "Proposition 1: BMI (44) at {} vertices of the Taylor polytope of e^(A_bar mu) (remainder {:.2e}), re-checked in f64: max eigenvalue {:.3e} + remainder effect {:.2e} + rounding {:.1e} < 0",
            d.vertices, d.remainder, bmi.max_eigenvalue, bmi.remainder_effect, bmi.rounding
        )];
        if let Some(a) = &d.reverification {
            notes.push(format!(
                "Theorem 1 re-verified for Gamma(L) (Remark 6): dense mu-grid bound {:.3e} < 0 on {} points",
                a.grid.bound, a.grid.points
            ));
        }
        match WidthDynamics::new(p, bounds, d.l.as_ref())
            .and_then(|wd| wd.guaranteed_bound(window, &vec![0.0; p.n()], 200))
        {
            Ok(b) => notes.push(format!(
                "guaranteed interval width (exact initial enclosure, every admissible sampling): {:?}",
                b.any_time
                    .iter()
                    .map(|x| (x * 1e4).round() / 1e4)
                    .collect::<Vec<_>>()
            )),
            Err(e) => notes.push(format!("no guaranteed width bound: {e}")),
        }
        DesignSummary {
            method: Method::Rabehi2021,
            window: window_words(window.tau_min(), window.tau_max()),
            windows: vec![SamplingWindow {
                t1: window.tau_min(),
                t2: window.tau_max(),
            }],
            margin: -(bmi.max_eigenvalue + bmi.remainder_effect + bmi.rounding),
            gains: vec![NamedMatrix::new("L", d.l.clone())],
            certificate: vec![
                NamedMatrix::new("P", d.p.clone()),
                NamedMatrix::new("F", d.f.clone()),
                NamedMatrix::new("G1", d.g1.clone()),
                NamedMatrix::new("G2", d.g2.clone()),
            ],
            notes,
            seconds: 0.0,
        }
    }

    /// Plant from `x(0) = 0` with the enclosure `[−1, 1]ⁿ`, a piecewise-constant disturbance
    /// drawn uniformly within its bounds (resampled every `T1`), noise `v̄ cos(2t)`.
    pub(super) fn simulate(
        plant: &PlantFile,
        design: &DesignSummary,
        out_dir: &Path,
        seed: u64,
    ) -> Result<SimulationSummary, MethodError> {
        let err = simulation_error(Method::Rabehi2021);
        let (p, _, bounds) = plant_of(plant)?;
        let w = design.windows[0];
        let n = p.n();
        let observer = IntervalObserver::new(&p, &bounds, design.gains[0].value.as_ref())
            .map_err(|e| err(e.to_string()))?;
        let horizon = 40.0 * w.t2;
        let scenario = Scenario {
            x0: vec![0.0; n],
            lower0: vec![-1.0; n],
            upper0: vec![1.0; n],
            horizon,
            sampling: Window::new(w.t1, w.t2).map_err(|e| err(e.to_string()))?,
            sampling_seed: seed,
            disturbance: Some(Disturbance {
                lower: bounds.d_lower().to_vec(),
                upper: bounds.d_upper().to_vec(),
                period: w.t1,
                seed: seed.wrapping_add(1),
            }),
            noise: Noise::Cosine {
                amplitude: bounds.v_bar().to_vec(),
                omega: 2.0,
            },
            input: Vec::new(),
            record_step: Some(w.t1 / 4.0),
        };
        let run = simulate_interval(&observer, &scenario).map_err(|e| err(e.to_string()))?;
        let widths: Vec<(String, Vec<f64>)> = (0..n)
            .map(|k| (format!("width of x{}", k + 1), run.width(k)))
            .collect();
        let components: Vec<(&str, &[f64])> = widths
            .iter()
            .map(|(l, y)| (l.as_str(), y.as_slice()))
            .collect();
        let path = out_dir.join("rabehi2021_width.svg");
        let spec = sporadic_figures::PlotSpec::new(
            &format!(
                "rabehi2021: interval width x_upper - x_lower, {}",
                plant.name
            ),
            "time [s]",
            "width",
        );
        sporadic_figures::plot_components(&path, &spec, run.times(), run.jumps(), &components)
            .map_err(|e| err(format!("{}: {e}", path.display())))?;
        let last: Vec<String> = widths
            .iter()
            .map(|(_, y)| format!("{:.4}", y.last().copied().unwrap_or(f64::NAN)))
            .collect();
        Ok(SimulationSummary {
            figure: path,
            setup: format!(
                "x(0) = 0 enclosed in [-1, 1]^{n}, disturbance uniform within its bounds (resampled every {} s), noise = bound * cos(2t), intervals uniform in [{}, {}] (seed {seed}), horizon {horizon} s",
                w.t1, w.t1, w.t2
            ),
            result: format!(
                "{} samples, final widths [{}], enclosure x_lower <= x <= x_upper violated at {} of {} checks (worst excess {:.2e})",
                run.jumps().last().copied().unwrap_or(0),
                last.join(", "),
                run.inclusion.violations,
                run.inclusion.checked,
                run.inclusion.worst
            ),
        })
    }

    pub(super) fn design(plant: &PlantFile) -> Result<DesignSummary, MethodError> {
        let (p, w, bounds) = plant_of(plant)?;
        let window = Window::new(w.t1, w.t2).map_err(|e| fail(e.to_string()))?;
        let d = synthesise(&p, &window, &SynthesisOptions::default())
            .map_err(|e| fail(e.to_string()))?;
        match &d.status {
            DesignStatus::Certified => Ok(summary(&p, &bounds, &window, &d)),
            DesignStatus::NotCertified(why) => Err(fail(why.clone())),
        }
    }

    pub(super) fn max_interval(
        plant: &PlantFile,
        limit: f64,
        progress: &mut dyn FnMut(&str),
    ) -> Result<Search, MethodError> {
        let (p, w, bounds) = plant_of(plant)?;
        let opts = WindowSearchOptions {
            resolution: 1e-2 * w.t2,
            upper: limit.max(w.t1),
            ..WindowSearchOptions::default()
        };
        let s = largest_tau_max(&p, w.t1, &opts).map_err(|e| fail(e.to_string()))?;
        for pr in &s.probes {
            report_probe(progress, pr.tau_max, pr.certified);
        }
        let design = match (s.certified, &s.design) {
            (Some(t2), Some(d)) => {
                let window = Window::new(w.t1, t2).map_err(|e| fail(e.to_string()))?;
                Some(summary(&p, &bounds, &window, d))
            }
            _ => None,
        };
        let first_failure = match s.certified {
            Some(b) if s.refuted <= b => None,
            _ => Some(s.refuted),
        };
        Ok((w.t1, s.certified, first_failure, design))
    }
}

mod andrieu {
    use super::*;

    /// Andrieu et al. (2014) do not certify a gain for a given window (spec 002): the observer
    /// picks its own next sampling instant.
    pub(super) fn not_applicable() -> MethodError {
        MethodError::NotApplicable {
            method: Method::Andrieu2014,
            why: "this observer takes no sampling window to certify: it picks each next sample \
                  itself (rule (7), interval x high gain = alpha) for plants in observability \
                  normal form given as code; see `sporadic reproduce andrieu2014`"
                .into(),
        }
    }
}
