//! The observer methods behind `sporadic design`, `sporadic max-interval` and `sporadic compare`:
//! one adapter per paper crate, from a [`PlantFile`] to a certified design and a largest
//! certified sampling window.
//!
//! Every result returned here comes from the paper crate's own design routine, which re-verifies
//! its certificate in f64 (eigenvalues of the LMIs at the returned point and a dense check of
//! the original parametric condition) before reporting success; a method that cannot certify
//! the plant returns [`MethodError::NotCertified`] with the crate's reason.

use crate::plant_file::{PlantFile, SamplingWindow};
use faer::Mat;
use std::fmt;
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
        _ => {
            return Err(MethodError::NotApplicable {
                method,
                why: "plant-file designs with this method are not available yet; run `sporadic reproduce` for the paper's example".into(),
            });
        }
    };
    d.seconds = start.elapsed().as_secs_f64();
    Ok(d)
}

/// Largest certified window `[T1, T2]` with `T1` from the plant file and `T2 ≤ limit`
/// (bisection to 1% relative); `progress` receives one line per probe.
pub fn max_interval(
    plant: &PlantFile,
    method: Method,
    limit: f64,
    progress: &mut dyn FnMut(&str),
) -> Result<MaxInterval, MethodError> {
    let start = Instant::now();
    let (t1, best, first_failure) = match method {
        Method::Ferrante2016 => ferrante::max_interval(plant, limit, progress)?,
        Method::Sferlazza2021 => sferlazza::max_interval(plant, limit, progress)?,
        _ => {
            return Err(MethodError::NotApplicable {
                method,
                why: "window search from plant files is not available for this method yet".into(),
            });
        }
    };
    let design = match best {
        Some(t2) => {
            let mut p = plant.clone();
            p.window = Some(SamplingWindow { t1, t2 });
            if method == Method::Sferlazza2021 {
                for s in &mut p.sensors {
                    s.window.t2 = t2;
                }
            }
            Some(self::design(&p, method)?)
        }
        None => None,
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
        progress(&format!(
            "T2 = {t2:.6}: {}",
            if ok { "certified" } else { "not certified" }
        ));
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
            window: format!("[{}, {}]", w.t1, w.t2),
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

    pub(super) fn max_interval(
        plant: &PlantFile,
        limit: f64,
        progress: &mut dyn FnMut(&str),
    ) -> Result<(f64, Option<f64>, Option<f64>), MethodError> {
        let (p, w) = plant_of(plant)?;
        let opts = f::WindowSearchOptions::default();
        let s = f::largest_t2(&p, w.t1, limit.max(w.t1), &opts).map_err(|e| fail(e.to_string()))?;
        for pr in &s.probes {
            progress(&format!(
                "T2 = {:.6}: {}",
                pr.t2,
                if pr.certified {
                    "certified"
                } else {
                    "not certified"
                }
            ));
        }
        Ok((w.t1, s.best, s.first_failure))
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
            .map(|x| format!("[{}, {}]", x.window().t_min, x.window().t_max))
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

    pub(super) fn max_interval(
        plant: &PlantFile,
        limit: f64,
        progress: &mut dyn FnMut(&str),
    ) -> Result<(f64, Option<f64>, Option<f64>), MethodError> {
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
        Ok((t1, best, fail))
    }
}
