//! The [`ObserverMethod`] contract for Sferlazza, Tarbouriech & Zaccarian (2021).
//!
//! The plant's sensors are read in round-robin order, sensor `σ` when the time `τ` since the
//! previous sample lies in its window `[T_mσ, T_Mσ]` (a plant with one output matrix `C` sampled
//! synchronously is one sensor; round-robin sensors sampled synchronously are stacked into one
//! sensor). [`Sferlazza2021::design`] runs the sequential-refinement loop of §5.3
//! ([`crate::design::design`]) and reports:
//!
//! * one gain schedule `K_σ(τ)` of (45) per sensor, on a grid of `τ` over that sensor's window;
//! * the Lyapunov matrices `P_σ` of (44) as the certificate;
//! * as margin, the smallest eigenvalue of the matrices `Ξ_σ(τ)` of (44) over every point of the
//!   final validation grid (48), with the `P_σ` scaled to `max_σ λ_max(P_σ) = 1`
//!   ([`crate::design::Design::normalised_margin`]);
//! * the checks made: the Proposition 1 screen, the Step 1 certificate, the grid validation (48)
//!   of each sensor and a spot check of (44) with fresh exponentials.
//!
//! [`Sferlazza2021::simulate`] runs the noise-free error system (53) with the reported `P_σ`.

use std::time::Instant;

use faer::Mat;
use sporadic_linalg::{InputError, LinalgError};
use sporadic_model::{
    Check, DesignReport, Gain, Margin, MaxIntervalReport, MethodError, MethodOptions, NamedMatrix,
    NotApplicable, ObserverMethod, Outputs, Plant, Probe, Proof, ProofOptions, Reason, Sampling,
    SamplingScenario, SamplingWindow, Scenario, SimulationReport, Status, Trajectory,
    check_simulatable, largest_window_with, power_of_two,
};
use sporadic_sdp::budget::{self, Budget};

use crate::design::{Design, DesignOptions, design_screened};
use crate::detectability::require_detectable;
use crate::error::{Error, check_at_least, sig4, sig4_list};
use crate::exponential_bound::exponential_bound;
use crate::gain::GainSchedule;
use crate::gain::check_sym;
use crate::normalise::Coordinates;
use crate::plant::{RoundRobinPlant, window_grid};
use crate::prove::{GAIN_TOLERANCE, XiDecisive, gain_mismatch, prove_design};
use crate::simulation::{SimulationOptions, simulate_error};
use crate::validation::{GridPolicy, XiFamily, spectral_norm};
use crate::validation::{WindowGrid, grid_spacing, validate_window};

const ID: &str = "sferlazza2021";

/// Sferlazza, Tarbouriech & Zaccarian (2021): round-robin sampled-data observer with jitter,
/// designed by the sequential refinement of §5.3, as an [`ObserverMethod`].
#[derive(Debug, Clone)]
pub struct Sferlazza2021 {
    /// Options of the design loop. Default [`DesignOptions::default`] (μ = 0.01, the paper's
    /// validation grid (49)).
    pub design: DesignOptions,
    /// Number of points of the `τ`-grid on which each gain schedule `K_σ(τ)` is reported
    /// (equally spaced over the sensor's window, ends included; one point for a periodic
    /// window). Default 11.
    pub schedule_points: usize,
}

impl Default for Sferlazza2021 {
    fn default() -> Self {
        Self {
            design: DesignOptions::default(),
            schedule_points: 11,
        }
    }
}

impl Sferlazza2021 {
    /// Checks every option; the error names the offending field.
    ///
    /// # Errors
    /// [`InputError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<(), InputError> {
        self.design.validate()?;
        check_at_least("schedule_points", self.schedule_points, 2)
    }

    /// The round-robin plant of the crate for a plant and sampling of the contract: one sensor per
    /// round-robin output with its window, or the (stacked) outputs as a single sensor for
    /// synchronous sampling.
    ///
    /// A sensor whose outputs are linearly dependent (`C_σ` of rank `0 < r < p_σ`) is read
    /// through its `r` independent outputs `W_σy_σ` ([`output_map`]).
    ///
    /// # Errors
    /// A number of windows that does not match the number of sensors, or the crate's plant
    /// checks ([`RoundRobinPlant::new`]).
    pub fn round_robin_plant(plant: &Plant, sampling: &Sampling) -> Result<RoundRobinPlant, Error> {
        let (sensors, _) = independent_sensors(plant, sampling)?;
        let refs: Vec<_> = sensors.iter().map(|(c, w)| (c.as_ref(), *w)).collect();
        RoundRobinPlant::new(plant.a(), &refs)
    }

    /// The output map [`output_map`] of every sensor of
    /// [`Sferlazza2021::round_robin_plant`] (`None` for a sensor read as given).
    ///
    /// # Errors
    /// As [`Sferlazza2021::round_robin_plant`].
    pub fn output_maps(plant: &Plant, sampling: &Sampling) -> Result<Vec<Option<Mat<f64>>>, Error> {
        Ok(independent_sensors(plant, sampling)?.1)
    }
}

/// The independent outputs of a sensor whose `C_σ` (`p_σ` rows) has numerical rank
/// `0 < r < p_σ` (the rank rule of [`sporadic_linalg::null_space`]): `W_σ = U_rᵀ`, the left
/// singular vectors of its `r` nonzero singular values as rows, orthonormal and spanning the
/// range of `C_σ` (`W_σᵀW_σC_σ = C_σ`). Two sensors reading one quantity, or a row that
/// combines others, make such a `C_σ`, which Assumption 1 (full row rank) excludes.
///
/// The design reads the outputs `W_σy_σ` of `C̃_σ = W_σC_σ`, which has full row rank and the
/// same kernel as `C_σ`: (44), (47) and their certificates `P_σ` depend on `C_σ` only through
/// its kernel, so they are unchanged. A gain `K̃_σ` of `C̃_σ` acts on `y_σ` as
/// `K_σ = K̃_σW_σ` (`K_σC_σ = K̃_σC̃_σ`: the same error dynamics (53)); conversely a gain
/// `K_σ` of `y_σ` acts on noise-free outputs, which lie in the range of `C_σ`, as the gain
/// `K_σW_σᵀ` of `C̃_σ`. `None` for a `C_σ` of full row rank, and for `C_σ = 0`, which
/// [`RoundRobinPlant::new`] refuses.
///
/// # Errors
/// [`Error::Linalg`] for non-finite entries or a failing SVD.
pub fn output_map(c: faer::MatRef<'_, f64>) -> Result<Option<Mat<f64>>, Error> {
    let rank = c.ncols() - sporadic_linalg::null_space(c)?.ncols();
    if rank == 0 || rank >= c.nrows() {
        return Ok(None);
    }
    let svd = c.thin_svd().map_err(|_| LinalgError::NoConvergence {
        what: "SVD of an output matrix C_σ".into(),
    })?;
    Ok(Some(svd.U().subcols(0, rank).transpose().to_owned()))
}

/// The given gains `K_σ` of the outputs `y_σ` as the gains `K_σW_σᵀ` of the independent outputs
/// of [`output_map`] (as given for a sensor read as given), to be compared with (45) for
/// [`Sferlazza2021::round_robin_plant`].
///
/// # Errors
/// [`Error::InvalidArgument`] for a gain row whose length is not the sensor's number of outputs.
fn on_independent_outputs(gains: &[Gain], maps: &[Option<Mat<f64>>]) -> Result<Vec<Gain>, Error> {
    gains
        .iter()
        .map(|g| {
            let map = g
                .name
                .strip_prefix("K_")
                .and_then(|s| s.parse::<usize>().ok())
                .and_then(|s| maps.get(s.checked_sub(1)?))
                .and_then(Option::as_ref);
            let Some(w) = map else {
                return Ok(g.clone());
            };
            let on = |rows: &Vec<Vec<f64>>| -> Result<Vec<Vec<f64>>, Error> {
                rows.iter()
                    .map(|row| {
                        if row.len() != w.ncols() {
                            return Err(Error::invalid(format!(
                                "gain {}: a row of {} entries, but the sensor has {} outputs",
                                g.name,
                                row.len(),
                                w.ncols()
                            )));
                        }
                        Ok((0..w.nrows())
                            .map(|j| row.iter().enumerate().map(|(l, k)| k * w[(j, l)]).sum())
                            .collect())
                    })
                    .collect()
            };
            let mut out = g.clone();
            out.rows = on(&g.rows)?;
            if let Some(schedule) = &mut out.schedule {
                schedule.samples = schedule.samples.iter().map(on).collect::<Result<_, _>>()?;
            }
            Ok(out)
        })
        .collect()
}

/// Sensors `(C_σ, window_σ)` in round-robin order.
type Sensors = Vec<(Mat<f64>, SamplingWindow)>;

/// [`sensor_list`] with every `C_σ` of [`output_map`] `W_σ` replaced by `W_σC_σ`, and the maps.
fn independent_sensors(
    plant: &Plant,
    sampling: &Sampling,
) -> Result<(Sensors, Vec<Option<Mat<f64>>>), Error> {
    let mut maps = Vec::new();
    let sensors = sensor_list(plant, sampling)?
        .into_iter()
        .map(|(c, w)| {
            let map = output_map(c.as_ref())?;
            let c = match &map {
                Some(m) => m * &c,
                None => c,
            };
            maps.push(map);
            Ok((c, w))
        })
        .collect::<Result<_, Error>>()?;
    Ok((sensors, maps))
}

/// The sensors `(C_σ, window_σ)` of `plant` under `sampling` (see
/// [`Sferlazza2021::round_robin_plant`]).
fn sensor_list(plant: &Plant, sampling: &Sampling) -> Result<Sensors, Error> {
    let windows = sampling.windows();
    Ok(match (plant.output_structure(), sampling) {
        (Outputs::Synchronous(_), _) | (Outputs::RoundRobin(_), Sampling::Synchronous(_))
            if windows.len() == 1 =>
        {
            let c = match plant.output_structure() {
                Outputs::Synchronous(c) => c.clone(),
                Outputs::RoundRobin(cs) => stack(cs),
            };
            vec![(c, windows[0])]
        }
        (Outputs::RoundRobin(cs), Sampling::RoundRobin(ws)) if cs.len() == ws.len() => {
            cs.iter().cloned().zip(ws.iter().copied()).collect()
        }
        _ => {
            let sensors = match plant.output_structure() {
                Outputs::Synchronous(_) => 1,
                Outputs::RoundRobin(cs) => cs.len(),
            };
            return Err(InputError::mismatch(
                "number of sampling windows (one per round-robin sensor)",
                sensors,
                windows.len(),
            )
            .into());
        }
    })
}

/// The rows of every `C_σ`, stacked.
fn stack(cs: &[Mat<f64>]) -> Mat<f64> {
    let n = cs.first().map_or(0, |c| c.ncols());
    let rows: Vec<(usize, usize)> = cs
        .iter()
        .enumerate()
        .flat_map(|(k, c)| (0..c.nrows()).map(move |i| (k, i)))
        .collect();
    Mat::from_fn(rows.len(), n, |r, j| {
        let (k, i) = rows[r];
        cs[k][(i, j)]
    })
}

/// A crate error as a verdict on the plant (`Ok`) or as an error of the call (`Err`).
fn verdict(e: Error) -> Result<Reason, MethodError> {
    let message = e.to_string();
    let invalid = |e: Error| MethodError::InvalidInput {
        method: ID,
        source: Box::new(e),
    };
    Ok(match e {
        Error::NotDetectable { ref intervals, .. } => Reason::Undetectable {
            // One sensor: the failing interval; several: the period Σ T_σ of the lifted pair (8)
            // (the whole tuple is in the message).
            tau: intervals.iter().sum(),
            message,
        },
        Error::Infeasible { .. } => Reason::InfeasibleLmi { message },
        Error::SolverFailed { .. } | Error::Stalled { .. } => {
            Reason::SolverInconclusive { message }
        }
        Error::VerificationFailed { .. } => Reason::VerificationFailed { tau: None, message },
        Error::GridTooLarge {
            unresolved: true, ..
        } => Reason::NumericalFailure { message },
        Error::NotConverged { .. } | Error::GridTooLarge { .. } | Error::Interrupted { .. } => {
            Reason::BudgetExhausted { message }
        }
        Error::Numerical(_) | Error::Lmi(_) | Error::Enclosure(_) => {
            Reason::NumericalFailure { message }
        }
        Error::Linalg(LinalgError::Input(_)) => return Err(invalid(e)),
        Error::Linalg(_) => Reason::NumericalFailure { message },
        Error::Sim(_) | Error::Io(_) => {
            return Err(MethodError::Numerical {
                method: ID,
                source: Box::new(e),
            });
        }
        Error::Interval(_)
        | Error::Input(_)
        | Error::NoSuchSensor { .. }
        | Error::InvalidArgument(_)
        | Error::RankDeficientOutput { .. }
        | Error::InvalidComplement { .. } => return Err(invalid(e)),
    })
}

/// The number of points of a (49) grid for a message: exact when it is run, with the cap when
/// it is above it.
fn grid_points(grid: &WindowGrid) -> String {
    match grid {
        WindowGrid::Grid(g) => format!("{} points", g.points),
        WindowGrid::OverCap { points, cap, .. } => {
            format!("{points:.3e} points (above the cap {cap:.3e}, not run)")
        }
    }
}

/// The balancing scales (powers of 2) for messages, exactly: `(1, 2^-3, 2^5)`.
fn powers_of_two(scales: &[f64]) -> String {
    let items: Vec<String> = scales
        .iter()
        .map(|&d| power_of_two(d).unwrap_or_else(|| sig4(d)))
        .collect();
    format!("({})", items.join(", "))
}

fn invalid_input(e: impl std::error::Error + Send + Sync + 'static) -> MethodError {
    MethodError::InvalidInput {
        method: ID,
        source: Box::new(e),
    }
}

impl ObserverMethod for Sferlazza2021 {
    fn id(&self) -> &'static str {
        ID
    }

    fn citation(&self) -> &'static str {
        "A. Sferlazza, S. Tarbouriech, L. Zaccarian (2021), State observer with round-robin \
         aperiodic sampled measurements with jitter, Automatica 129:109573"
    }

    fn summary(&self) -> &'static str {
        "round-robin sensors with jitter: time-varying gains K_σ(τ) of (45) from Lyapunov matrices \
         P_σ found by iterative refinement of a τ-grid (§5.3)"
    }

    fn observer(&self) -> &'static str {
        "between samples x̂' = Ax̂ + Bu; at a sample of sensor σ, after τ ∈ [T_mσ, T_Mσ] since the \
         previous sample (of any sensor), x̂⁺ = x̂ + K_σ(τ)(y_σ − C_σx̂), then σ⁺ = σ + 1 mod N \
         (round-robin); the gain schedule K_σ(τ) is (45) from P_σ"
    }

    fn applies(&self, plant: &Plant, sampling: &Sampling) -> Result<(), NotApplicable> {
        if plant.lipschitz().is_some() {
            return Err(NotApplicable::unsupported(
                ID,
                "the plant has a Lipschitz nonlinearity; this method designs observers for linear \
                 plants",
            ));
        }
        // A sensor count that does not match the windows is bad input, reported by `design`.
        let Ok(sensors) = sensor_list(plant, sampling) else {
            return Ok(());
        };
        // Dependent outputs are read through their independent combinations (output_map);
        // a sensor that measures nothing cannot be.
        for (k, (c, _)) in sensors.iter().enumerate() {
            if c.nrows() > 0 && c.norm_max() == 0.0 {
                return Err(NotApplicable::unsupported(
                    ID,
                    format!(
                        "sensor {}: C_σ = 0, the sensor measures nothing (Assumption 1 needs \
                         C_σ of full row rank)",
                        k + 1
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The §5.3 loop ([`design_screened`] without the coarse screen) in the balanced
    /// coordinates of the plant and in its Gramian normal form ([`crate::normalise`]): first in
    /// the one whose `A` has the smaller Frobenius norm, within half the remaining time budget,
    /// then in the other where the first does not certify; Proposition 1 failing in the balanced
    /// coordinates is final.
    /// Its validation (48) first tries a proof for every `τ` of each window where the (49)
    /// grid is large (at most [`SEARCH_PROOF_PIECES`] pieces unless
    /// [`DesignOptions::proof_pieces`] says otherwise; `Some(0)` turns it off), which implies
    /// (48) on the grid; the grid decides wherever the proof does not prove, so the loop's
    /// iterates are the paper's, except on grids above the cap or above
    /// [`crate::validation::REFUTED_POINT_FROM`] points after a refutation, where the refuted
    /// point stands in for the worst grid point (50).
    fn design(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        _options: &MethodOptions,
    ) -> Result<DesignReport, MethodError> {
        self.design_report(plant, sampling, None)
    }

    /// The largest `T2` by [`sporadic_model::largest_window_with`], whose probe is the design
    /// with the coarse screen of [`crate::design::DesignLoop::step_screened`] (at most
    /// [`SEARCH_SCREEN_POINTS`] points per window): an iteration whose `P_σ` fails on the
    /// coarse grid skips the full grid (49), whose size grows with p* near the largest
    /// window. The full validation of a probe first tries to prove (48) for every `τ` of each
    /// window in interval arithmetic (at most [`SEARCH_PROOF_PIECES`] pieces,
    /// [`DesignOptions::proof_pieces`]), which implies it on the (49) grid, and runs the grid
    /// only where that proof does not succeed. The Proposition 1 screen of a probe (a necessary
    /// condition) is coarser, at most [`SEARCH_DETECTABILITY_TUPLES`] grid tuples plus the
    /// aliasing tuples (its check in the report says how many). Every certified probe, the
    /// reported design included, passed the full validation (48) (proven over the window, or
    /// on the (49) grid; its checks say which) and every other check of a design.
    fn largest_window(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        limit: f64,
        options: &MethodOptions,
        progress: &mut dyn FnMut(&Probe),
    ) -> Result<MaxIntervalReport, MethodError> {
        largest_window_with(
            self,
            plant,
            sampling,
            limit,
            &options.search,
            options,
            progress,
            &mut |s| self.design_report(plant, s, Some(SEARCH_SCREEN_POINTS)),
        )
    }

    /// Proves (44) for every `τ` of every window in interval arithmetic ([`crate::prove`]),
    /// after checking that the report's gains are (45) of its certificate.
    fn prove(
        &self,
        plant: &Plant,
        design: &DesignReport,
        options: &ProofOptions,
    ) -> Result<Proof, MethodError> {
        let (rr, ps) = design_data(plant, design)?;
        let maps = Self::output_maps(plant, &report_sampling(design)?).map_err(invalid_input)?;
        let gains = on_independent_outputs(&design.gains, &maps).map_err(invalid_input)?;
        prove_design(&rr, &ps, &gains, options).map_err(crate_error)
    }

    /// Checks given gains and Lyapunov matrices: the certificate `P_1, …, P_N` (scaled so that
    /// `I ⪯ P_σ`, as in (47)) must pass the validation (48) at μ on the grid (49) of each window
    /// (Step 1 run for β, γ), or a proof of (48) over the whole window, tried first on a large
    /// grid and, after a floating-point screen of the window that can only refute (48), the
    /// only decision for a grid above the cap (at most [`SEARCH_PROOF_PIECES`]
    /// pieces unless [`DesignOptions::proof_pieces`] says otherwise, the same rule as the window
    /// search; [`crate::validation::validate_window`]), and the gains must be (45) of it at
    /// every listed `τ`. (45) is checked in the coordinates given; Step 1 and (48) in the
    /// balanced coordinates of the design (exact powers of 2; `Ξ_σ(τ) ≻ 0` does not depend on
    /// the coordinates). `μ` sets the resolution of (48)–(49), not the verdict: where
    /// `0 < λ_min(Ξ_σ(τ)) ≤ μ` the check lowers `μ` and refines (a certificate scaled to
    /// `λ_min(P_σ) = 1` may meet only a smaller `μ` than the design's `P_σ ⪰ I`); only
    /// `λ_min ≤ 0`, or a margin below `10⁻¹⁰·p*`, fails.
    fn verify(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        gains: &[Gain],
        certificate: &[NamedMatrix],
        _options: &MethodOptions,
    ) -> Result<DesignReport, MethodError> {
        let start = Instant::now();
        if let Err(na) = self.applies(plant, sampling) {
            return Ok(DesignReport::without_design(
                self,
                plant.name(),
                Some(sampling),
                na.reason,
            ));
        }
        self.validate().map_err(invalid_input)?;
        let rr = Self::round_robin_plant(plant, sampling).map_err(invalid_input)?;
        let ps = certificate_of(&rr, certificate)?;
        let mut report = match self.verify_certificate(plant, sampling, &rr, &ps, gains) {
            Ok(r) => r,
            Err(e @ (Error::Input(_) | Error::InvalidArgument(_))) => {
                return Err(invalid_input(e));
            }
            Err(e) => DesignReport::without_design(self, plant.name(), Some(sampling), verdict(e)?),
        };
        report.seconds = start.elapsed().as_secs_f64();
        Ok(report)
    }

    fn simulate(
        &self,
        plant: &Plant,
        design: &DesignReport,
        scenario: &Scenario,
    ) -> Result<Trajectory, MethodError> {
        self.simulate_design(plant, design, scenario)
    }
}

/// A crate error of [`ObserverMethod::prove`]: bad input, or a failing kernel.
fn crate_error(e: Error) -> MethodError {
    match e {
        Error::Input(_) | Error::InvalidArgument(_) | Error::NoSuchSensor { .. } => {
            invalid_input(e)
        }
        e => MethodError::Numerical {
            method: ID,
            source: Box::new(e),
        },
    }
}

/// The sampling of a report (its window, or one window per sensor).
fn report_sampling(design: &DesignReport) -> Result<Sampling, MethodError> {
    match (&design.window, &design.windows) {
        (Some(w), _) => Ok(Sampling::Synchronous(*w)),
        (None, Some(ws)) => Ok(Sampling::RoundRobin(ws.clone())),
        (None, None) => Err(invalid_input(Error::invalid(
            "the report has no sampling window",
        ))),
    }
}

/// `P_1, …, P_N` from a certificate (each `n × n`, finite, symmetric).
fn certificate_of(
    rr: &RoundRobinPlant,
    certificate: &[NamedMatrix],
) -> Result<Vec<Mat<f64>>, MethodError> {
    (1..=rr.num_sensors())
        .map(|s| {
            let name = format!("P_{s}");
            let m = certificate
                .iter()
                .find(|m| m.name == name)
                .map(NamedMatrix::to_mat)
                .ok_or_else(|| {
                    invalid_input(Error::invalid(format!("the certificate has no {name}")))
                })?;
            check_sym(m.as_ref(), rr.n(), &name).map_err(invalid_input)?;
            Ok(m)
        })
        .collect()
}

/// The round-robin plant and the certificate of a design report of this method.
fn design_data(
    plant: &Plant,
    design: &DesignReport,
) -> Result<(RoundRobinPlant, Vec<Mat<f64>>), MethodError> {
    if design.method != ID {
        return Err(invalid_input(Error::invalid(format!(
            "the report is a design of {}, not of {ID}",
            design.method
        ))));
    }
    let rr = Sferlazza2021::round_robin_plant(plant, &report_sampling(design)?)
        .map_err(invalid_input)?;
    let ps = certificate_of(&rr, &design.certificate)?;
    Ok((rr, ps))
}

/// Points per window of the coarse screen in the window search
/// ([`Sferlazza2021::largest_window`](ObserverMethod::largest_window)).
pub const SEARCH_SCREEN_POINTS: usize = 2048;

/// Largest number of pieces of the proof of (48) over a window that a design (and every probe
/// of the window search) tries before running the (49) grid, unless
/// [`DesignOptions::proof_pieces`] says otherwise.
pub const SEARCH_PROOF_PIECES: usize = 16384;

/// Most times `verify` lowers μ for a given certificate (in its
/// check of (48)): each round at least halves μ and doubles the grid.
const VERIFY_MU_ROUNDS: usize = 8;

/// Smallest μ `verify` checks (48) with, relative to `p*` (the largest eigenvalue of the given
/// `P_σ` scaled to `λ_min = 1`): below it `λ_min(Ξ_σ(τ))` is at the level of the rounding of
/// `Ξ_σ(τ)`'s entries, and no grid decides its sign.
const VERIFY_MU_FLOOR: f64 = 1e-10;

/// Largest number of grid tuples of the Proposition 1 screen in a probe of the window search
/// (the aliasing tuples come on top); a design's own screen uses
/// [`crate::DetectabilityOptions::default`].
pub const SEARCH_DETECTABILITY_TUPLES: usize = 4096;

impl Sferlazza2021 {
    /// [`ObserverMethod::design`], with the coarse screen of
    /// [`crate::design::DesignLoop::step_screened`] when `screen` is `Some`.
    fn design_report(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        screen: Option<usize>,
    ) -> Result<DesignReport, MethodError> {
        if let Err(na) = self.applies(plant, sampling) {
            return Ok(DesignReport::without_design(
                self,
                plant.name(),
                Some(sampling),
                na.reason,
            ));
        }
        self.validate().map_err(invalid_input)?;
        let start = Instant::now();
        let rr = Self::round_robin_plant(plant, sampling).map_err(invalid_input)?;
        // Guard before any exponential: (44) needs e^(−Aτ) up to τ = T_M, whose norm is at least
        // e^(α T_M) with α = −min Re λ(A) (similarity- and time-scale-invariant); past
        // ln(f64::MAX) ≈ 709 it cannot be represented in double precision.
        let alpha = rr
            .a()
            .eigenvalues()
            .map(|e| e.iter().map(|z| -z.re).fold(f64::NEG_INFINITY, f64::max))
            .unwrap_or(f64::NAN);
        if alpha * rr.t_max() > f64::MAX.ln() {
            let mut r = DesignReport::without_design(
                self,
                plant.name(),
                Some(sampling),
                Reason::NumericalFailure {
                    message: format!(
                        "e^(−Aτ) of (44) exceeds the double-precision range on the window: A has a \
                         stable mode with Re λ = {} and T_M = {}, so ‖e^(−A T_M)‖ ≥ e^{} > 1.8e308 \
                         (the formulation of (44) cannot represent such a fast mode over such a \
                         long interval)",
                        sig4(-alpha),
                        sig4(rr.t_max()),
                        sig4(alpha * rr.t_max())
                    ),
                },
            );
            r.seconds = start.elapsed().as_secs_f64();
            return Ok(r);
        }
        // Two coordinates to design in (crate::normalise): the balanced ones of the plant as
        // given (exact, the identity for a plant that is already balanced) and the Gramian
        // normal form (the same for every equivalent plant up to an orthogonal change of
        // coordinates). The one whose A is nearer to normal (smaller ‖A‖_F, whose infimum over
        // all coordinates is (Σ|λ_i|²)^½ for a diagonalisable A) is tried first, within half
        // the remaining budget; the other where it does not certify.
        let mut forms: Vec<(f64, Coordinates, RoundRobinPlant)> = Vec::with_capacity(2);
        let balanced = Coordinates::balanced(&rr);
        let in_balanced = balanced.plant(&rr).map_err(invalid_input)?;
        forms.push((in_balanced.a().norm_l2(), balanced, in_balanced));
        // A Gramian form that overflows or loses the rank of a C_σ is not usable.
        if let Some(gramian) = Coordinates::gramian(&rr)
            && let Ok(in_gramian) = gramian.plant(&rr)
        {
            let norm = in_gramian.a().norm_l2();
            let at = usize::from(norm >= forms[0].0);
            forms.insert(at, (norm, gramian, in_gramian));
        }
        // In the window search, the Proposition 1 screen (a necessary condition, never what
        // certifies) runs on at most SEARCH_DETECTABILITY_TUPLES grid tuples plus its aliasing
        // tuples: 26 points per axis are 26^N tuples per probe (4.6·10⁵ for N = 4, seconds).
        let mut options = self.design.clone();
        if screen.is_some()
            && let Some(det) = &mut options.detectability
        {
            let per_axis = (SEARCH_DETECTABILITY_TUPLES as f64)
                .powf(1.0 / rr.num_sensors() as f64)
                .floor() as usize;
            det.points_per_axis = det.points_per_axis.min(per_axis.max(2));
        }
        // (48) is first attempted by proof over each whole window where the (49) grid is large
        // (validate_window): the grid grows like e^(βT_M)·p* (1.7·10⁹ points on a ship-heading
        // plant at T_M = 5.8, minutes), the proof adapts its pieces to where the margin is thin.
        // A proof implies (48) on the grid, and a grid within its cap still decides whenever the
        // proof does not prove, so the iterates are those of the paper's loop, except where a
        // grid is above its cap or too large to run after a refutation (validate_window): the
        // refuted point then stands in for the grid's worst point (50).
        options.proof_pieces.get_or_insert(SEARCH_PROOF_PIECES);
        // Proposition 1 in the balanced coordinates decides, also when the Gramian form goes
        // first (screened here) or certifies after it: a non-decaying mode that the output sees only through rounding (the corpus
        // plant `undetectable-unstable` in coordinates x = Tz, relative PBH margin 1.5e-16)
        // looks observable in the Gramian form, whose passes amplify that rounding, and the
        // plant was certified there.
        if forms[0].1.is_gramian()
            && let Some(det) = &options.detectability
            && let Some((_, _, in_balanced)) = forms.iter().find(|f| !f.1.is_gramian())
            && let Err(e @ Error::NotDetectable { .. }) = require_detectable(in_balanced, det)
        {
            let mut r =
                DesignReport::without_design(self, plant.name(), Some(sampling), verdict(e)?);
            r.seconds = start.elapsed().as_secs_f64();
            return Ok(r);
        }
        let mut refusals: Vec<(bool, Reason)> = Vec::new();
        for (k, (_, coordinates, in_form)) in forms.iter().enumerate() {
            let gramian = coordinates.is_gramian();
            let attempt =
                || self.design_in(plant, sampling, in_form, coordinates, &options, screen);
            let deadline = budget::current().deadline();
            let res = match deadline {
                Some(d) if k + 1 < forms.len() => {
                    let now = Instant::now();
                    budget::within(
                        Budget::until(now + d.saturating_duration_since(now) / 2),
                        attempt,
                    )
                }
                _ => attempt(),
            };
            match res {
                Ok(report) => {
                    let mut report = report;
                    report.seconds = start.elapsed().as_secs_f64();
                    return Ok(report);
                }
                Err(e) => match verdict(e) {
                    // Proposition 1 failing in the balanced coordinates is final (see above).
                    Ok(r @ Reason::Undetectable { .. }) if !gramian => {
                        let mut out =
                            DesignReport::without_design(self, plant.name(), Some(sampling), r);
                        out.seconds = start.elapsed().as_secs_f64();
                        return Ok(out);
                    }
                    Ok(r) => refusals.push((gramian, r)),
                    Err(e) if !gramian => return Err(e),
                    Err(_) => {}
                },
            }
        }
        // Neither form certified: a refusal of the Gramian form that does not depend on the
        // coordinates ((47) infeasible, which certifies (44) infeasible; Proposition 1) is
        // reported, else that of the plant as given.
        let invariant = |r: &Reason| {
            matches!(
                r,
                Reason::InfeasibleLmi { .. } | Reason::Undetectable { .. }
            )
        };
        let reason = match refusals.iter().position(|(g, r)| *g && invariant(r)) {
            Some(k) => refusals.swap_remove(k).1,
            None => refusals
                .pop()
                .map(|(_, r)| r)
                .ok_or_else(|| invalid_input(Error::invalid("no coordinates to design in")))?,
        };
        let mut r = DesignReport::without_design(self, plant.name(), Some(sampling), reason);
        r.seconds = start.elapsed().as_secs_f64();
        Ok(r)
    }

    /// The §5.3 loop on `in_form`, the plant in `coordinates`, and the certified report of its
    /// design in the plant's coordinates.
    fn design_in(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        in_form: &RoundRobinPlant,
        coordinates: &Coordinates,
        options: &DesignOptions,
        screen: Option<usize>,
    ) -> Result<DesignReport, Error> {
        let d = design_screened(in_form, options, screen)?;
        self.report(plant, sampling, &d, coordinates)
    }

    /// [`ObserverMethod::simulate`].
    fn simulate_design(
        &self,
        plant: &Plant,
        design: &DesignReport,
        scenario: &Scenario,
    ) -> Result<Trajectory, MethodError> {
        let unavailable = |why: String| MethodError::SimulationUnavailable { method: ID, why };
        check_simulatable(ID, design)?;
        let sampling = match (&design.window, &design.windows) {
            (Some(w), _) => Sampling::Synchronous(*w),
            (None, Some(ws)) => Sampling::RoundRobin(ws.clone()),
            (None, None) => return Err(unavailable("the report has no sampling window".into())),
        };
        let rr = Self::round_robin_plant(plant, &sampling).map_err(invalid_input)?;
        let ps: Vec<Mat<f64>> = (1..=rr.num_sensors())
            .map(|s| {
                design
                    .certificate
                    .iter()
                    .find(|m| m.name == format!("P_{s}"))
                    .map(NamedMatrix::to_mat)
                    .ok_or_else(|| unavailable(format!("the report has no certificate P_{s}")))
            })
            .collect::<Result<_, _>>()?;
        let windows: Vec<SamplingWindow> = rr.sensors().iter().map(|s| s.window()).collect();
        if scenario.sampling == SamplingScenario::WorstCase {
            return Err(unavailable(
                "no worst-case sampling for the round-robin observer: its Lyapunov function \
                 switches with the sensor; use uniform or periodic sampling"
                    .into(),
            ));
        }
        let (rule, seed) = match scenario.sampling {
            SamplingScenario::Uniform { seed } => (
                format!("intervals uniform in each sensor's window (seed {seed})"),
                seed,
            ),
            SamplingScenario::PeriodicT1 => ("every interval T_mσ".to_string(), 1),
            SamplingScenario::PeriodicT2 | SamplingScenario::WorstCase => {
                ("every interval T_Mσ".to_string(), 1)
            }
        };
        let fixed = |t: fn(&SamplingWindow) -> f64| -> Result<Vec<SamplingWindow>, MethodError> {
            windows
                .iter()
                .map(|w| SamplingWindow::periodic(t(w)))
                .collect::<Result<_, _>>()
                .map_err(invalid_input)
        };
        let sim_plant = match scenario.sampling {
            SamplingScenario::Uniform { .. } => rr.clone(),
            SamplingScenario::PeriodicT1 => rr
                .with_windows(&fixed(SamplingWindow::t1)?)
                .map_err(invalid_input)?,
            SamplingScenario::PeriodicT2 | SamplingScenario::WorstCase => rr
                .with_windows(&fixed(SamplingWindow::t2)?)
                .map_err(invalid_input)?,
        };
        let schedule = GainSchedule::new(sim_plant, ps).map_err(invalid_input)?;
        let round: f64 = windows.iter().map(SamplingWindow::t2).sum();
        let horizon = scenario.horizon.unwrap_or(40.0 * round);
        let x0 = scenario
            .initial_error
            .clone()
            .unwrap_or_else(|| vec![1.0; rr.n()]);
        let mut options = SimulationOptions::noise_free(horizon, x0.clone());
        options.seed = seed;
        options.record_step = horizon / 4000.0;
        let run = simulate_error(&schedule, &options).map_err(|e| match e {
            Error::Input(_) | Error::InvalidArgument(_) => invalid_input(e),
            e => MethodError::Numerical {
                method: ID,
                source: Box::new(e),
            },
        })?;
        let norm = |x: &[f64]| x.iter().map(|v| v * v).sum::<f64>().sqrt();
        let norms: Vec<f64> = run.x.iter().map(|x| norm(x)).collect();
        let worst_ratio = run
            .jumps
            .iter()
            .map(|j| j.v_after / j.v_before)
            .fold(0.0, f64::max);
        let initial = norm(&x0);
        let last = norms.last().copied().unwrap_or(f64::NAN);
        let signals = (0..rr.n())
            .map(|i| (format!("x̃_{}", i + 1), run.x.iter().map(|x| x[i]).collect()))
            .collect();
        Ok(Trajectory {
            quantity: "estimation error x̃ = x − x̂".into(),
            t: run.t.clone(),
            j: run.j.clone(),
            signals,
            norm: norms,
            report: SimulationReport {
                setup: format!(
                    "error system (53) without noise, x̃(0) = {} (|x̃(0)| = {}), sensors in \
                     round-robin order, {rule}, horizon {} s",
                    sig4_list(&x0),
                    sig4(initial),
                    sig4(horizon)
                ),
                samples: run.jumps.len(),
                initial_error: initial,
                final_error: last,
                result: format!(
                    "{} samples, |x̃| at the end = {last:.3e}, largest V⁺/V over the jumps = \
                     {} (V = x̃ᵀΦ_σ(τ)x̃ of (30) with ρ = 0)",
                    run.jumps.len(),
                    sig4(worst_ratio)
                ),
                settling_time: None,
                ends_early_at: None,
                figure: None,
            },
        })
    }
}

impl Sferlazza2021 {
    /// The report of [`ObserverMethod::verify`] for the certificate `ps` (in the coordinates of
    /// `rr`) and the given `gains`.
    fn verify_certificate(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        rr: &RoundRobinPlant,
        ps: &[Mat<f64>],
        gains: &[Gain],
    ) -> Result<DesignReport, Error> {
        let failed =
            |tau: Option<f64>, message: String| self.refused(plant, sampling, tau, message);
        let mut lo = f64::INFINITY;
        for p in ps {
            lo = lo.min(sporadic_linalg::min_eigenvalue(p.as_ref())?);
        }
        if !(lo > 0.0) {
            return Ok(failed(
                None,
                format!(
                    "the certificate is not positive definite (smallest eigenvalue {})",
                    sig4(lo)
                ),
            ));
        }
        let on_rr = on_independent_outputs(gains, &Self::output_maps(plant, sampling)?)?;
        if let Some((s, tau, _, dev)) = gain_mismatch(rr, ps, &on_rr)? {
            return Ok(failed(
                Some(tau),
                format!(
                    "the given gain K_{}(τ) at τ = {} is not (45) of the certificate P_{} \
                    (relative deviation {}): the certificate does not certify it",
                    s + 1,
                    sig4(tau),
                    s + 1,
                    sig4(dev)
                ),
            ));
        }
        // (48) is checked in the balanced coordinates x_b = D⁻¹x of the design (exact powers of
        // 2, the identity for a balanced plant): Ξ_σ(τ) ≻ 0 does not depend on the coordinates,
        // while its grid, proof and margin are those of the well-scaled plant, as in the design.
        // A certificate that is ill-conditioned there (one designed in the Gramian normal form
        // and mapped back to coordinates x = Tz) is checked again in its own coordinates.
        let first = self.verify_in(plant, sampling, rr, ps, gains, &Coordinates::balanced(rr));
        if first.as_ref().is_ok_and(|r| r.status == Status::Certified) {
            return first;
        }
        if let Some(own) = Coordinates::of_certificate(ps)
            && let Ok(second) = self.verify_in(plant, sampling, rr, ps, gains, &own)
            && second.status == Status::Certified
        {
            return Ok(second);
        }
        first
    }

    /// The report of a verification that failed (at `tau`, when known).
    fn refused(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        tau: Option<f64>,
        message: String,
    ) -> DesignReport {
        DesignReport::without_design(
            self,
            plant.name(),
            Some(sampling),
            Reason::VerificationFailed { tau, message },
        )
    }

    /// The check (48) of [`Self::verify_certificate`] in `coordinates`.
    fn verify_in(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        rr: &RoundRobinPlant,
        ps: &[Mat<f64>],
        gains: &[Gain],
        coordinates: &Coordinates,
    ) -> Result<DesignReport, Error> {
        let mu = self.design.mu;
        let failed =
            |tau: Option<f64>, message: String| self.refused(plant, sampling, tau, message);
        let rr_b = coordinates.plant(rr)?;
        let ps_b: Vec<Mat<f64>> = ps.iter().map(|p| coordinates.form_to(p.as_ref())).collect();
        let rr = &rr_b;
        // Scale to I ⪯ P_σ ⪯ p*I, the normalisation of (47) under which μ and (49) apply.
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for p in &ps_b {
            lo = lo.min(sporadic_linalg::min_eigenvalue(p.as_ref())?);
            hi = hi.max(sporadic_linalg::max_eigenvalue(p.as_ref())?);
        }
        let coordinates = match coordinates {
            _ if coordinates.is_identity() => String::new(),
            Coordinates::Balanced(scales) => format!(
                " (in the balanced coordinates x_b = D⁻¹x, D = {}, P_bσ = DP_σD)",
                powers_of_two(scales)
            ),
            Coordinates::Gramian { .. } => " (in the Gramian normal form x' = Gx)".to_string(),
            Coordinates::Certificate { .. } => {
                " (in the coordinates x' = Rx of the certificate, RᵀR = Σ_σ P_σ/‖P_σ‖_max, \
                 P'_σ = R⁻ᵀP_σR⁻¹, A' = RAR⁻¹ in floating point: in the balanced coordinates of \
                 the plant the check failed)"
                    .to_string()
            }
        };
        let normalised: Vec<Mat<f64>> = ps_b.iter().map(|p| p * (1.0 / lo)).collect();
        let p_star = hi / lo;
        let bound = exponential_bound(&rr.a().to_owned(), rr.t_max(), &self.design.bound)?;
        let mut report = DesignReport::certified(self, plant.name(), sampling);
        report.gains = gains.to_vec();
        report.certificate = ps
            .iter()
            .enumerate()
            .map(|(s, p)| {
                NamedMatrix::new(
                    format!("P_{}", s + 1),
                    p.as_ref(),
                    format!("Lyapunov matrix of sensor {} in (44), as given", s + 1),
                )
            })
            .collect();
        let mut margin = f64::INFINITY;
        for (s, sensor) in rr.sensors().iter().enumerate() {
            let fam = XiFamily::new(rr, &normalised, s)?;
            // μ only sets the resolution of the check: (48) at the points of a grid of spacing
            // (49) ∝ μ/p* implies Ξ_σ(τ) ≻ 0 between them, whatever μ > 0. The design meets μ
            // with its own P_σ ⪰ I, which may lie above I; scaled to λ_min = 1 here the same
            // certificate may meet only a smaller μ. So a point with 0 < λ_min(Ξ_σ(τ)) ≤ μ
            // lowers μ to half that value and refines the grid (at most VERIFY_MU_ROUNDS times,
            // not below VERIFY_MU_FLOOR·p*); only λ_min ≤ 0, or a margin below that floor,
            // fails.
            let mut mu_s = mu;
            let mut rounds = 0;
            let (v, grid) = loop {
                let spacing = grid_spacing(rr, s, self.design.grid, mu_s, p_star, &bound.bound)?;
                let grid = WindowGrid::covering(
                    sensor.window(),
                    spacing,
                    self.design.validation.max_points,
                )?;
                let v = validate_window(
                    &fam,
                    rr,
                    &normalised,
                    grid,
                    mu_s,
                    Some(self.design.proof_pieces.unwrap_or(SEARCH_PROOF_PIECES)),
                    &self.design.validation,
                )?;
                let lower = 0.5 * v.min_eigenvalue.min(mu_s);
                if v.passed() || !(lower >= VERIFY_MU_FLOOR * p_star) || rounds == VERIFY_MU_ROUNDS
                {
                    break (v, grid);
                }
                mu_s = lower;
                rounds += 1;
            };
            let lowered = if mu_s < mu {
                format!(
                    ", μ lowered from the design's {} as the given P_σ's scale allows",
                    sig4(mu)
                )
            } else {
                String::new()
            };
            if !v.passed() {
                let at = match grid {
                    WindowGrid::Grid(g) => {
                        format!("grid of {} points, spacing {}", g.points, sig4(g.spacing))
                    }
                    WindowGrid::OverCap { points, cap, .. } if v.points > 0 => format!(
                        "the least λ_min(Ξ_{}(τ))/‖Ξ_{}(τ)‖_F among {} τ of a floating-point \
                         screen of the window, run in place of the uniform grid of {points:.3e} \
                         points above the cap {cap:.3e}; Ξ_{}(τ) there is shown not positive \
                         definite in interval arithmetic",
                        s + 1,
                        s + 1,
                        v.points,
                        s + 1
                    ),
                    WindowGrid::OverCap { points, cap, .. } => format!(
                        "an end of a τ-piece where the proof of (48) over the window, tried in \
                         place of the uniform grid of {points:.3e} points above the cap \
                         {cap:.3e}, shows in interval arithmetic that it fails"
                    ),
                };
                let why = if v.min_eigenvalue > 0.0 {
                    format!(
                        "{} ≤ μ = {}{lowered}, and half of it is below {} = {}·p*, the smallest \
                         margin checked",
                        sig4(v.min_eigenvalue),
                        sig4(mu_s),
                        sig4(VERIFY_MU_FLOOR * p_star),
                        sig4(VERIFY_MU_FLOOR)
                    )
                } else {
                    format!(
                        "{} ≤ 0: Ξ_{}(τ) is not positive definite",
                        sig4(v.min_eigenvalue),
                        s + 1
                    )
                };
                return Ok(failed(
                    Some(v.argmin_tau),
                    format!(
                        "(48) fails for sensor {}: λ_min(Ξ_{}(τ)) = {why} at τ = {} ({at}; \
                         P_σ scaled to I ⪯ P_σ{coordinates})",
                        s + 1,
                        s + 1,
                        sig4(v.argmin_tau),
                    ),
                ));
            }
            margin = margin.min(v.min_eigenvalue / p_star);
            report.checks.push(match v.proof_pieces {
                Some(pieces) => Check {
                    what: format!(
                        "(48): λ_min(Ξ_{}(τ)) > μ = {} for every τ of the window {} of sensor {}",
                        s + 1,
                        sig4(mu_s),
                        sensor.window(),
                        s + 1
                    ),
                    how: format!(
                        "proven in interval arithmetic on {pieces} τ-pieces (crate::prove), in \
                         place of the uniform grid of {}, spacing {} (the design's grid \
                         policy, p* = {}), which it implies; the given P_σ scaled to I ⪯ P_σ{lowered}{coordinates}",
                        grid_points(&grid),
                        sig4(grid.spacing()),
                        sig4(p_star)
                    ),
                    value: None,
                    passed: true,
                },
                None => Check {
                    what: format!(
                        "(48): λ_min(Ξ_{}(τ)) > μ = {} on the window {} of sensor {}",
                        s + 1,
                        sig4(mu_s),
                        sensor.window(),
                        s + 1
                    ),
                    how: format!(
                        "uniform grid of {}, spacing {} (the design's grid policy, p* = {}), \
                         the given P_σ scaled to I ⪯ P_σ{lowered}{coordinates}; value: λ_min on a subsample",
                        grid_points(&grid),
                        sig4(grid.spacing()),
                        sig4(p_star)
                    ),
                    value: Some(v.min_eigenvalue),
                    passed: true,
                },
            });
        }
        report.checks.push(Check {
            what: "the given gains are (45) of the given P_σ at every listed τ".into(),
            how: format!("K_σ(τ) recomputed from P_σ, relative deviation ≤ {GAIN_TOLERANCE}"),
            value: None,
            passed: true,
        });
        report.margin = Some(Margin {
            value: margin,
            definition: "min over the sensors of λ_min(Ξ_σ(τ)) on a subsample of the validation \
            grid (48)–(49), or μ for a sensor whose (48) is proven over the window in place of the \
            grid (a lower bound of λ_min(Ξ_σ(τ)) at every τ), with the P_σ scaled to \
            max_σ λ_max(P_σ) = 1"
                .into(),
        });
        report.notes.push(
            "verification of given gains and certificate (no design): Step 1, the validation \
            (48) on the grid (49) or proven over the window in its place (in the balanced \
            coordinates of the plant, or where they do not certify, in the certificate's own \
            coordinates: see the checks), and the gain law (45) (in the coordinates given, or \
            in the certificate's where it deviates in them)"
                .into(),
        );
        Ok(report)
    }

    /// The certified report of a successful design `d`.
    ///
    /// `d` was designed in `coordinates` ([`crate::normalise`]); the gains and Lyapunov
    /// matrices are reported in the user's coordinates (`K = DK_b`, `P = D⁻¹P_bD⁻¹`, exact up to
    /// one rounding; or `K = G⁻¹K'`, `P = GᵀP'G`), the checks are made in the coordinates of the
    /// design (positive definiteness of `Ξ_σ(τ)` is invariant under the congruence).
    fn report(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        d: &Design,
        coordinates: &Coordinates,
    ) -> Result<DesignReport, Error> {
        let rr = d.plant();
        let mu = d.mu;
        let mut report = DesignReport::certified(self, plant.name(), sampling);
        let maps = Self::output_maps(plant, sampling)?;
        // Gains: one schedule per sensor over its window, on all of its outputs.
        let mut spot: Vec<(usize, f64, f64, bool)> = Vec::new();
        for (s, sensor) in rr.sensors().iter().enumerate() {
            let taus = window_grid(sensor.window(), self.schedule_points)?;
            let ks = taus
                .iter()
                .map(|&t| {
                    d.gains().gain(s, t).map(|k| {
                        let k = coordinates.gain_back(k.as_ref());
                        match &maps[s] {
                            Some(w) => &k * w,
                            None => k,
                        }
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            let fam = XiFamily::new(rr, &d.p, s)?;
            // Set up once per sensor, at its first floating-point λ_min ≤ 0.
            let mut enclosure: Option<XiDecisive> = None;
            for &t in &taus {
                // A floating-point λ_min ≤ 0 refutes (44) only where interval arithmetic
                // shows Ξ_σ(τ) not positive definite: on long windows its entries grow like
                // ‖e^(−Aτ)‖² (10¹⁹ on a ship-heading plant at τ = 8.9) while λ_min stays of the
                // order of P_Γ, and a computed λ_min of −32 there was rounding.
                let lambda = fam.min_eigenvalue(t)?;
                let refuted = lambda <= 0.0 && {
                    let c = match &mut enclosure {
                        Some(c) => c,
                        None => enclosure.insert(XiDecisive::new(rr, &d.p, s)?),
                    };
                    c.at(t)?.lo() >= 0.0
                };
                spot.push((s, t, lambda, refuted));
            }
            let mut ks = ks.into_iter();
            let law = match &maps[s] {
                None => format!(
                    "(45) from P_{0}: K_{0}(τ) = (C_{0}ᵀ − C_{0}^⊥ W(τ)⁻¹ C_{0}^⊥ᵀ Φ(τ) C_{0}ᵀ)\
                     (C_{0}C_{0}ᵀ)⁻¹ with Φ(τ) = e^(−Aᵀτ) P_{0} e^(−Aτ), W(τ) = C_{0}^⊥ᵀ Φ(τ) \
                     C_{0}^⊥ (equivalently Φ⁻¹C_{0}ᵀ(C_{0}Φ⁻¹C_{0}ᵀ)⁻¹, so C_{0}K_{0} = I)",
                    s + 1
                ),
                Some(w) => format!(
                    "K_{0}(τ) = K̃_{0}(τ)W_{0} with K̃_{0}(τ) = Φ⁻¹C̃_{0}ᵀ(C̃_{0}Φ⁻¹C̃_{0}ᵀ)⁻¹, \
                     (45) from P_{0} for the {1} independent outputs W_{0}y_{0} of C̃_{0} = \
                     W_{0}C_{0} (W_{0}: orthonormal rows spanning the range of C_{0}, which has \
                     rank {1} for {2} outputs), Φ(τ) = e^(−Aᵀτ) P_{0} e^(−Aτ); K_{0}C_{0} = \
                     K̃_{0}C̃_{0}, C̃_{0}K̃_{0} = I",
                    s + 1,
                    w.nrows(),
                    w.ncols()
                ),
            };
            report.gains.push(Gain::scheduled(
                format!("K_{}", s + 1),
                format!(
                    "x̂⁺ = x̂ + K_{0}(τ)(y_{0} − C_{0}x̂) at a sample of sensor {0}, τ = time since \
                     the previous sample, τ ∈ {1}; rows = K_{0} at τ = T_M{0}",
                    s + 1,
                    sensor.window()
                ),
                law,
                taus.clone(),
                move |_| ks.next().unwrap_or_else(|| Mat::zeros(0, 0)),
            ));
        }
        let designed_in = match coordinates {
            _ if coordinates.is_identity() => String::new(),
            Coordinates::Balanced(scales) => format!(
                " in the balanced coordinates x_b = D⁻¹x, D = diag{}, mapped back as \
                 P_σ = D⁻¹P_bD⁻¹",
                powers_of_two(scales)
            ),
            Coordinates::Gramian { .. } | Coordinates::Certificate { .. } => {
                " in the Gramian normal form x' = Gx, mapped back as P_σ = GᵀP'G".to_string()
            }
        };
        for (s, p) in d.p.iter().enumerate() {
            report.certificate.push(NamedMatrix::new(
                format!("P_{}", s + 1),
                coordinates.form_back(p.as_ref()).as_ref(),
                format!(
                    "Lyapunov matrix of sensor {} in (44), solution of (47): I ⪯ P_σ ⪯ p*·I with \
                     p* = {}{designed_in}; V = e^(−ρτ) x̃ᵀ e^(−Aᵀτ) P_σ e^(−Aτ) x̃ is (30)",
                    s + 1,
                    sig4(d.p_star)
                ),
            ));
        }
        // Margin: exact minimum over the final validation grid, normalised.
        let minima = d.grid_minima(&self.design.validation)?;
        let margin = d.normalised_margin(&minima)?;
        let proven = minima.iter().filter(|g| g.proof_pieces.is_some()).count();
        let mut definition =
            "min over the sensors σ and the points τ of the final validation grid \
                              (48)–(49) of λ_min(Ξ_σ(τ)), Ξ_σ(τ) the matrix of (44), with the \
                              Lyapunov matrices scaled so that max_σ λ_max(P_σ) = 1 (i.e. divided \
                              by that largest eigenvalue); positive: (44) holds on the grid with \
                              this slack. The design's acceptance test was λ_min(Ξ_σ(τ)) > μ at \
                              every grid point with the unscaled P_σ (I ⪯ P_σ)"
                .to_string();
        if proven > 0 {
            definition.push_str(
                "; for a sensor whose acceptance test was a proof of (48) over its whole window \
                 instead of the grid, its term is μ, the lower bound of λ_min(Ξ_σ(τ)) at every τ \
                 of the window that the proof shows",
            );
        }
        report.margin = Some(Margin {
            value: margin,
            definition,
        });
        // Checks.
        if let Some(det) = &d.detectability {
            report.checks.push(Check {
                what: "Proposition 1: (C, e^(AT)) of the lifted output (8) detectable for the \
                       sampled interval tuples (necessary condition)"
                    .into(),
                how: format!(
                    "PBH test (block-normalised, smallest singular value) on {} tuple(s){}",
                    det.tuples,
                    if det.exact {
                        " (jitter-free: exact)"
                    } else {
                        " of a uniform grid of the windows (a screen, not a proof)"
                    }
                ),
                value: det
                    .worst
                    .as_ref()
                    .and_then(|w| w.test.worst.map(|e| e.margin)),
                passed: det.detectable,
            });
        }
        let b = &d.bound;
        report.checks.push(Check {
            what: format!(
                "Step 1: ‖e^(−Aτ)‖₂ ≤ γe^(βτ) with β = {}, γ = {} (enters the grid spacing (49))",
                sig4(b.bound.beta),
                sig4(b.bound.gamma)
            ),
            how: if b.lyapunov_margin.is_nan() {
                "β, γ given in the options (not checked)".into()
            } else {
                "λ_min((A + βI)ᵀΠ + Π(A + βI)) at the returned Π, in f64".into()
            },
            value: Some(b.lyapunov_margin),
            passed: b.lyapunov_margin.is_nan() || b.lyapunov_margin > 0.0,
        });
        let policy = match self.design.grid {
            GridPolicy::Paper => "spacing 2δ* of (49)".to_string(),
            GridPolicy::Rigorous => "the rigorous Lipschitz spacing".to_string(),
            GridPolicy::Spacing(h) => format!("spacing at most {}", sig4(h)),
        };
        for g in &minima {
            if let Some(pieces) = g.proof_pieces {
                report.checks.push(Check {
                    what: format!(
                        "(48): λ_min(Ξ_{}(τ)) > μ = {} for every τ of the window {} of sensor {}",
                        g.sigma + 1,
                        sig4(mu),
                        rr.sensor(g.sigma)?.window(),
                        g.sigma + 1
                    ),
                    how: format!(
                        "proven in interval arithmetic on {pieces} τ-pieces (crate::prove on the \
                         Schur complement C^⊥ᵀΦ_σ(τ)C^⊥ − R_μ ≻ 0, P_Γ − μI ≻ 0 proven: chord \
                         between the piece ends minus the second-order remainder, Rump's verified \
                         definiteness test, outward rounding), in place of the uniform grid of \
                         spacing {} ({policy}), which it implies",
                        sig4(g.grid.spacing)
                    ),
                    value: None,
                    passed: true,
                });
                continue;
            }
            report.checks.push(Check {
                what: format!(
                    "(48): λ_min(Ξ_{}(τ)) > μ = {} on the window {} of sensor {}",
                    g.sigma + 1,
                    sig4(mu),
                    rr.sensor(g.sigma)?.window(),
                    g.sigma + 1
                ),
                how: format!(
                    "uniform grid of {} points, spacing {} ({policy}), e^(−Aτ) by stepping with \
                     re-anchoring, Schur complement + Cholesky at each point, exact λ_min at every \
                     point at or below the minimum; value: min λ_min (at τ = {})",
                    g.grid.points,
                    sig4(g.grid.spacing),
                    sig4(g.argmin_tau)
                ),
                value: Some(g.min_eigenvalue),
                passed: g.min_eigenvalue > mu,
            });
        }
        let worst = spot
            .iter()
            .copied()
            .min_by(|a, b| a.2.total_cmp(&b.2))
            .unwrap_or((0, f64::NAN, f64::NAN, false));
        report.checks.push(Check {
            what:
                "(44): Ξ_σ(τ) ≻ 0 with fresh exponentials at the τ of the reported gain schedules"
                    .into(),
            how: format!(
                "{} points ({} per window), e^(−Aτ) by a fresh scaling-and-squaring, full \
                 symmetric eigenvalue decomposition; where that λ_min is ≤ 0, Ξ_σ(τ) is \
                 enclosed in interval arithmetic and the check fails only if it is proven not \
                 positive definite (on a long window Ξ_σ(τ) has entries far above its λ_min, \
                 which rounding can then make negative); value: smallest λ_min (sensor {}, \
                 τ = {})",
                spot.len(),
                self.schedule_points,
                worst.0 + 1,
                sig4(worst.1)
            ),
            value: Some(worst.2),
            passed: !spot.iter().any(|p| p.3),
        });
        if let Some(c) = report.checks.iter().find(|c| !c.passed) {
            return Err(Error::VerificationFailed {
                what: format!("{} ({})", c.what, c.how),
                value: c.value.unwrap_or(f64::NAN),
            });
        }
        // Notes.
        let added: Vec<String> =
            d.log
                .iter()
                .flat_map(|r| {
                    r.added.iter().enumerate().filter_map(move |(s, t)| {
                        t.map(|t| format!("σ = {}: τ̄ = {}", s + 1, sig4(t)))
                    })
                })
                .collect();
        report.notes.push(format!(
            "iterative refinement (§5.3) passed validation after {} synthesis SDP(s) (47) with μ = \
             {}; points τ̄ of (50) added: {}; final p* = {}",
            d.iterations(),
            sig4(mu),
            if added.is_empty() {
                "none".to_string()
            } else {
                added.join(", ")
            },
            sig4(d.p_star)
        ));
        match coordinates {
            _ if coordinates.is_identity() => {}
            Coordinates::Balanced(scales) => report.notes.push(format!(
                "designed in the balanced coordinates x_b = D⁻¹x with D = diag{} (powers of \
                 2, LAPACK gebal scaling of A; exact): the margin and the checks are those of the \
                 balanced plant, the gains K_σ = D·K_bσ and certificates P_σ = D⁻¹P_bσD⁻¹ are in \
                 the plant's coordinates",
                powers_of_two(scales)
            )),
            Coordinates::Gramian {
                state,
                state_inverse,
                unit,
            } => report.notes.push(format!(
                "designed in the Gramian normal form x' = Gx, in which the observability Gramian \
                 of (A, [C_1; …; C_N]) on [0, {}] is the identity (the same form for the plant in \
                 any coordinates, up to an orthogonal change of them; ‖G‖₂‖G⁻¹‖₂ = {}): the \
                 margin and the checks are those of the floating-point plant (GAG⁻¹, C_σG⁻¹) \
                 there, the gains K_σ = G⁻¹K'_σ and certificates P_σ = GᵀP'_σG are in the \
                 plant's coordinates",
                sig4(*unit),
                sig4(spectral_norm(state.as_ref())? * spectral_norm(state_inverse.as_ref())?)
            )),
            // A design is never made in a certificate's coordinates (only `verify` checks there).
            Coordinates::Certificate { .. } => {}
        }
        for (s, w) in maps.iter().enumerate() {
            if let Some(w) = w {
                report.notes.push(format!(
                    "sensor {0}: its {1} outputs are linearly dependent (C_{0} has rank {2}); the \
                     design reads the {2} independent outputs W_{0}y_{0} (W_{0}: orthonormal rows \
                     spanning the range of C_{0}, from its SVD), which change neither the kernel \
                     of C_{0} nor (44), and K_{0} = K̃_{0}W_{0} acts on all {1} outputs",
                    s + 1,
                    w.ncols(),
                    w.nrows()
                ));
            }
        }
        report.notes.push(format!(
            "the gain K_σ(τ) of (45) depends on the time τ since the previous sample; each schedule \
             is listed on {} points of its window and is evaluated online from P_σ",
            self.schedule_points
        ));
        if self.design.grid == GridPolicy::Paper && proven < minima.len() {
            report.notes.push(
                "the grid spacing (49) bounds the variation of e^(−Aτ), not of Ξ_σ(τ): the \
                 validation is faithful to the paper but not a proof over the continuum of τ \
                 (GridPolicy::Rigorous gives one)"
                    .into(),
            );
        }
        if let (Outputs::RoundRobin(cs), Sampling::Synchronous(_)) =
            (plant.output_structure(), sampling)
            && cs.len() > 1
        {
            report.notes.push(format!(
                "synchronous sampling of {} round-robin sensors: their outputs are stacked into \
                 one sensor",
                cs.len()
            ));
        }
        Ok(report)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The balancing scales print exactly, as powers of 2 (not `0.0009765625`).
    #[test]
    fn scales_print_as_powers_of_two() {
        assert_eq!(
            powers_of_two(&[1.0, 0.5, 1024.0, 2f64.powi(-10), 3.0]),
            "(1, 2^-1, 2^10, 2^-10, 3)"
        );
    }
}
