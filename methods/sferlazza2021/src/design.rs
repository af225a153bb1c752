//! The sequential-refinement design algorithm of §5.3 for the jitter-tolerant LMI (44).
//!
//! 1. **Initialisation** ([`crate::exponential_bound`]): β, γ with `‖e^{−Aτ}‖ ≤ γe^{βτ}`.
//! 2. **Synthesis** ([`crate::synthesis`]): solve (47) on the finite sets `T_σ` (initially
//!    `{T_mσ, T_Mσ}`) → `(P*, p*)`.
//! 3. **Analysis** ([`crate::validation`]): check `Ξ_σ(τ) ≻ μI` (48) on a grid of each window with
//!    spacing from the [`GridPolicy`] ((49) by default). If every sensor passes, stop. Otherwise add the
//!    worst point τ̄_σ of (50) to `T_σ` for every failing σ and go back to 2. With
//!    [`DesignOptions::proof_pieces`], a large grid is replaced by a proof of (48) for every τ of
//!    the window ([`crate::prove`]) when one succeeds; the grid decides otherwise. A grid above
//!    the cap ([`ValidationOptions::max_points`]) is never run: without `proof_pieces` the step
//!    ends with [`Error::GridTooLarge`]; with it the proof decides alone (a disproof adds the
//!    failing τ to `T_σ`, an undecided proof ends with [`Error::GridTooLarge`]).
//!
//! Theorem 5: if (44) is feasible the loop ends after finitely many iterations. Failure exits:
//! (47) infeasible ([`Error::Infeasible`], which certifies that (44) is infeasible), `max_iterations`
//! reached ([`Error::NotConverged`]), and a worst point that is already in `T_σ`
//! ([`Error::Stalled`]: the SDP accuracy is too coarse for the chosen μ).

use std::time::{Duration, Instant};

use faer::Mat;
use sporadic_model::SolverStats;
use sporadic_sdp::lmi::SolveOptions;

use crate::detectability::{DetectabilityOptions, DetectabilityReport, require_detectable};
use crate::error::{Error, check_at_least, check_positive};
use crate::exponential_bound::{BoundOptions, CertifiedBound, exponential_bound};
use crate::gain::GainSchedule;
use crate::plant::RoundRobinPlant;
use crate::synthesis::{Synthesis, default_solve_options};
use crate::validation::{
    GridPolicy, MIN_PROOF_PIECES, SensorValidation, UniformGrid, ValidationOptions, WindowGrid,
    XiFamily, grid_spacing, validate_window,
};
use sporadic_linalg::InputError;

/// Options of the §5.3 loop. The defaults are those of the reproduction of §6: μ = 0.01, the
/// paper's grid (49), at most 50 iterations, the default validation, Step 1 search, solver and
/// detectability options, and Step 1 run (no fixed bound).
#[derive(Debug, Clone)]
pub struct DesignOptions {
    /// Margin μ (synthesis enforces `2μI`, validation checks `μI`). The paper does not report its
    /// value. Default 0.01.
    pub mu: f64,
    /// Validation grid spacing. Default [`GridPolicy::Paper`].
    pub grid: GridPolicy,
    /// Iteration cap (a safeguard; Theorem 5 bounds the count in terms of `cond(P_σ)`). Default 50.
    pub max_iterations: usize,
    /// Validation tuning. Default [`ValidationOptions::default`].
    pub validation: ValidationOptions,
    /// Step 1 search options. Default [`BoundOptions::default`].
    pub bound: BoundOptions,
    /// Use these β, γ instead of running Step 1 (taken as given: not certified, the reported
    /// `lyapunov_margin` is NaN). Default `None`.
    pub fixed_bound: Option<crate::validation::ExponentialBound>,
    /// Options of the synthesis SDP. Default [`crate::synthesis::default_solve_options`].
    pub solve: SolveOptions,
    /// Run the Proposition 1 screen first (`None`: skip). Default: the screen with
    /// [`DetectabilityOptions::default`].
    pub detectability: Option<DetectabilityOptions>,
    /// Before a sensor's (49) grid is run, try to prove (48) for every `τ` of its window in
    /// interval arithmetic ([`crate::prove`]) with at most this many pieces
    /// ([`crate::validation::validate_window`]). A proof decides the validation in place of the grid (it implies
    /// (48) at every grid point); otherwise the grid decides, as in the paper. A grid above
    /// [`ValidationOptions::max_points`] is decided by the proof alone, after a floating-point
    /// screen of the window that can only refute (48)
    /// ([`crate::validation::WindowGrid::OverCap`]). `None`: the grid only, and a grid above the
    /// cap ends the step with [`Error::GridTooLarge`]. Default `None`, the paper's loop
    /// ([`crate::Sferlazza2021`] sets it to [`crate::method::SEARCH_PROOF_PIECES`] unless given).
    pub proof_pieces: Option<usize>,
}

impl DesignOptions {
    /// Checks every field; the error names the offending one.
    ///
    /// # Errors
    /// [`InputError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<(), InputError> {
        check_positive("mu", self.mu)?;
        if let GridPolicy::Spacing(h) = self.grid {
            check_positive("grid (spacing)", h)?;
        }
        check_at_least("max_iterations", self.max_iterations, 1)?;
        self.validation.validate()?;
        self.bound.validate()?;
        if let Some(b) = self.fixed_bound {
            if !(b.gamma >= 1.0 && b.gamma.is_finite()) {
                return Err(InputError::parameter(
                    "fixed_bound.gamma",
                    b.gamma,
                    "must be finite and at least 1",
                ));
            }
            if !b.beta.is_finite() {
                return Err(InputError::parameter(
                    "fixed_bound.beta",
                    b.beta,
                    "must be finite",
                ));
            }
        }
        if let Some(d) = &self.detectability {
            d.validate()?;
        }
        if let Some(k) = self.proof_pieces {
            check_at_least("proof_pieces", k, 1)?;
        }
        Ok(())
    }
}

impl Default for DesignOptions {
    fn default() -> Self {
        Self {
            mu: 0.01,
            grid: GridPolicy::Paper,
            max_iterations: 50,
            validation: ValidationOptions::default(),
            bound: BoundOptions::default(),
            fixed_bound: None,
            solve: default_solve_options(),
            detectability: Some(DetectabilityOptions::default()),
            proof_pieces: None,
        }
    }
}

/// One iteration of the loop.
#[derive(Debug, Clone)]
pub struct IterationRecord {
    /// Iteration number (1-based, as in the paper).
    pub iteration: usize,
    /// Optimal value p* of (47).
    pub p_star: f64,
    /// `P_1*, …, P_N*` of this iteration.
    pub p: Vec<Mat<f64>>,
    /// The sets `T_σ` used by this synthesis.
    pub points: Vec<Vec<f64>>,
    /// Statistics of the synthesis solve (a stalled solve whose point passed verification is
    /// accepted, see [`crate::synthesis::ACCEPT_GAP`]).
    pub sdp: SolverStats,
    /// Synthesis wall time (compile/assemble + solve).
    pub sdp_time: Duration,
    /// Validation of each sensor.
    pub sensors: Vec<SensorValidation>,
    /// Validation wall time (all sensors).
    pub validation_time: Duration,
    /// τ̄_σ added to `T_σ` after this iteration (`None`: sensor passed).
    pub added: Vec<Option<f64>>,
}

impl IterationRecord {
    /// Whether every sensor passed validation.
    pub fn passed(&self) -> bool {
        self.sensors.iter().all(SensorValidation::passed)
    }
    /// Validation throughput (grid points per second, all sensors, wall clock).
    pub fn validation_rate(&self) -> f64 {
        let pts: usize = self.sensors.iter().map(|s| s.points).sum();
        pts as f64 / self.validation_time.as_secs_f64().max(1e-12)
    }
}

/// A successful design.
#[derive(Debug, Clone)]
pub struct Design {
    /// The final `P_σ*` (solutions of (44), up to the validation grid).
    pub p: Vec<Mat<f64>>,
    /// Final p*.
    pub p_star: f64,
    /// μ used.
    pub mu: f64,
    /// Step 1 constants.
    pub bound: CertifiedBound,
    /// Proposition 1 screen (if run).
    pub detectability: Option<DetectabilityReport>,
    /// Iteration log.
    pub log: Vec<IterationRecord>,
    /// Total wall time (Step 1 included).
    pub total_time: Duration,
    /// Wall time of Step 1.
    pub bound_time: Duration,
    gains: GainSchedule,
}

impl Design {
    /// The observer's gain schedule `K_σ(τ)` (45) from the final `P_σ`.
    pub fn gains(&self) -> &GainSchedule {
        &self.gains
    }
    /// The plant.
    pub fn plant(&self) -> &RoundRobinPlant {
        self.gains.plant()
    }
    /// Number of iterations.
    pub fn iterations(&self) -> usize {
        self.log.len()
    }

    /// For each sensor, the exact minimum of `λ_min(Ξ_σ(τ))` of (44) over every point of the last
    /// validation grid (48), the one that passed. Validation itself only decides `λ_min > μ` at every
    /// point (its reported minimum is that of a subsample); this re-runs the grid at the level of that
    /// subsample minimum, so that every point at or below it is evaluated exactly. A sensor whose
    /// validation was a proof over the whole window ([`SensorValidation::proof_pieces`]) gets μ,
    /// the lower bound the proof shows, and no grid is run.
    ///
    /// # Errors
    /// Bad `options` or a failing kernel.
    pub fn grid_minima(&self, options: &ValidationOptions) -> Result<Vec<GridMinimum>, Error> {
        let plant = self.plant();
        let last = self
            .log
            .last()
            .ok_or_else(|| Error::invalid("the design has no iteration"))?;
        let mut out = Vec::with_capacity(plant.num_sensors());
        for (s, v) in last.sensors.iter().enumerate() {
            let grid = UniformGrid {
                t_min: plant.sensor(s)?.window().t1(),
                spacing: v.spacing,
                points: v.points,
            };
            let (min_eigenvalue, argmin_tau) = if v.min_is_exact || v.proof_pieces.is_some() {
                (v.min_eigenvalue, v.argmin_tau)
            } else {
                let fam = XiFamily::new(plant, &self.p, s)?;
                let r = fam.validate_grid(grid, v.min_eigenvalue, options)?;
                if r.failures > 0 {
                    (r.min_eigenvalue, r.argmin_tau)
                } else {
                    // No point lies below the subsample minimum: it is the grid minimum.
                    (v.min_eigenvalue, v.argmin_tau)
                }
            };
            out.push(GridMinimum {
                sigma: s,
                grid,
                min_eigenvalue,
                argmin_tau,
                proof_pieces: v.proof_pieces,
            });
        }
        Ok(out)
    }

    /// The slack of the validated condition (44): `min_σ min_τ λ_min(Ξ_σ(τ)) / max_σ λ_max(P_σ)` over
    /// the points of the last validation grid (`minima` from [`Design::grid_minima`]). `Ξ_σ` is
    /// linear in `(P_1, …, P_N)`, so this is the smallest eigenvalue of the `Ξ_σ(τ)` on the grid
    /// once the Lyapunov matrices are scaled to `max_σ ‖P_σ‖₂ = 1` (independent of the scaling the
    /// SDP chose). Positive when (44) holds on the grid.
    ///
    /// # Errors
    /// A failing eigenvalue kernel.
    pub fn normalised_margin(&self, minima: &[GridMinimum]) -> Result<f64, Error> {
        let mut p_max = 0.0f64;
        for p in &self.p {
            p_max = p_max.max(sporadic_linalg::max_eigenvalue(p.as_ref())?);
        }
        let m = minima
            .iter()
            .map(|g| g.min_eigenvalue)
            .fold(f64::INFINITY, f64::min);
        Ok(m / p_max)
    }
}

/// The exact minimum of `λ_min(Ξ_σ(τ))` over one sensor's validation grid ([`Design::grid_minima`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridMinimum {
    /// Sensor (0-based).
    pub sigma: usize,
    /// The grid.
    pub grid: UniformGrid,
    /// `min_k λ_min(Ξ_σ(τ_k))`.
    pub min_eigenvalue: f64,
    /// Where it is attained.
    pub argmin_tau: f64,
    /// `Some(k)`: the validation was a proof of (48) over the whole window on `k` pieces, and
    /// `min_eigenvalue` is μ, a lower bound of `λ_min(Ξ_σ(τ))` at every τ of the window
    /// (`argmin_tau` NaN; see [`SensorValidation::proof_pieces`]).
    pub proof_pieces: Option<usize>,
}

/// The loop as a state machine, for callers that want to watch or drive it step by step.
#[derive(Debug)]
pub struct DesignLoop {
    plant: RoundRobinPlant,
    settings: DesignOptions,
    bound: CertifiedBound,
    bound_time: Duration,
    detectability: Option<DetectabilityReport>,
    synthesis: Synthesis,
    log: Vec<IterationRecord>,
    started: Instant,
}

impl DesignLoop {
    /// Step 1 (and the Proposition 1 screen), then builds (47) with `T_σ = {T_mσ, T_Mσ}`.
    ///
    /// # Errors
    /// [`Error::NotDetectable`] from the screen, an invalid μ, a failing Step 1 search.
    pub fn new(plant: &RoundRobinPlant, settings: &DesignOptions) -> Result<Self, Error> {
        let started = Instant::now();
        settings.validate()?;
        let detectability = match &settings.detectability {
            Some(s) => Some(require_detectable(plant, s)?),
            None => None,
        };
        let t0 = Instant::now();
        let bound = match settings.fixed_bound {
            Some(b) => CertifiedBound {
                bound: b,
                pi: Mat::identity(plant.n(), plant.n()),
                lyapunov_margin: f64::NAN,
                horizon: plant.t_max(),
                sdp_solves: 0,
            },
            None => exponential_bound(&plant.a().to_owned(), plant.t_max(), &settings.bound)?,
        };
        let bound_time = t0.elapsed();
        let synthesis = Synthesis::new(plant, settings.mu, &settings.solve)?;
        Ok(Self {
            plant: plant.clone(),
            settings: settings.clone(),
            bound,
            bound_time,
            detectability,
            synthesis,
            log: Vec::new(),
            started,
        })
    }

    /// The iterations so far.
    pub fn log(&self) -> &[IterationRecord] {
        &self.log
    }

    /// Step 1 constants.
    pub fn bound(&self) -> &CertifiedBound {
        &self.bound
    }

    /// One synthesis + validation (+ insertion of the worst points). Returns `true` when validation
    /// passed.
    ///
    /// # Errors
    /// Infeasible or failed SDP, a grid above the cap, a stalled refinement.
    pub fn step(&mut self) -> Result<bool, Error> {
        self.step_screened(None)
    }

    /// [`DesignLoop::step`] with a cheap screen first: the synthesis' `P_σ` is validated on a
    /// coarse uniform grid of at most `coarse_points` points per window (never finer than the
    /// grid of the policy). If some sensor fails there at a point τ̄ not yet in its `T_σ`, the
    /// coarse worst points (50) are added and the step ends, not passed, without the full grid.
    /// Otherwise (every sensor passes the screen, or a coarse worst point is already in `T_σ`)
    /// the step validates the same `P_σ` on the full grid of the policy exactly as
    /// [`DesignLoop::step`] does (or by a proof over the window, [`DesignOptions::proof_pieces`]);
    /// so a step reports `true` only after the full validation (48) on the (49) grid or on every
    /// τ of the window. The screen saves the full grid on every iteration whose `P_σ` fails
    /// on the coarse grid (the window search runs many such iterations); it changes which τ̄
    /// are added, hence the iterates, but not the acceptance test.
    ///
    /// # Errors
    /// As [`DesignLoop::step`].
    pub fn step_screened(&mut self, coarse_points: Option<usize>) -> Result<bool, Error> {
        let mu = self.settings.mu;
        let points = self.synthesis.points().to_vec();
        let t0 = Instant::now();
        let res = self.synthesis.solve()?;
        let sdp_time = t0.elapsed();
        let t1 = Instant::now();
        let mut grids = Vec::with_capacity(self.plant.num_sensors());
        let mut families = Vec::with_capacity(self.plant.num_sensors());
        for s in 0..self.plant.num_sensors() {
            let spacing = grid_spacing(
                &self.plant,
                s,
                self.settings.grid,
                mu,
                res.p_star,
                &self.bound.bound,
            )?;
            let grid = WindowGrid::covering(
                self.plant.sensor(s)?.window(),
                spacing,
                self.settings.validation.max_points,
            )?;
            // A grid above the cap is decided only by a proof of (48) over the window, or
            // refuted by its screen (validate_window); without a proof, the step ends here,
            // before any grid is run.
            if let WindowGrid::OverCap { points, cap, .. } = grid
                && self
                    .settings
                    .proof_pieces
                    .is_none_or(|k| k < MIN_PROOF_PIECES)
            {
                return Err(Error::GridTooLarge {
                    sigma: s + 1,
                    points,
                    cap,
                    proof: String::new(),
                    unresolved: false,
                });
            }
            grids.push(grid);
            families.push(XiFamily::new(&self.plant, &res.p, s)?);
        }
        let validate = |grids: &[UniformGrid]| -> Result<Vec<SensorValidation>, Error> {
            grids
                .iter()
                .zip(&families)
                .map(|(g, f)| f.validate_grid(*g, mu, &self.settings.validation))
                .collect()
        };
        // The full validation: a proof of (48) over the window where the grid is large enough
        // for one to pay off (DesignOptions::proof_pieces), the grid otherwise.
        let validate_full = |grids: &[WindowGrid]| -> Result<Vec<SensorValidation>, Error> {
            grids
                .iter()
                .zip(&families)
                .map(|(g, f)| {
                    validate_window(
                        f,
                        &self.plant,
                        &res.p,
                        *g,
                        mu,
                        self.settings.proof_pieces,
                        &self.settings.validation,
                    )
                })
                .collect()
        };
        let stalled = |v: &SensorValidation| {
            let tol = 0.5 * v.spacing.max(f64::EPSILON * v.argmin_tau.abs());
            points[v.sigma]
                .iter()
                .any(|&t| (t - v.argmin_tau).abs() <= tol)
        };
        let mut screened = None;
        if let Some(k) = coarse_points {
            let coarse: Vec<UniformGrid> = grids
                .iter()
                .zip(self.plant.sensors())
                .map(|(g, sensor)| {
                    let w = sensor.window();
                    let h = (w.t2() - w.t1()) / (k.max(2) - 1) as f64;
                    match g {
                        WindowGrid::Grid(g) if g.points <= k || !(h > g.spacing) => Ok(*g),
                        _ => UniformGrid::covering(w, h, self.settings.validation.max_points),
                    }
                })
                .collect::<Result<_, _>>()?;
            if coarse
                .iter()
                .zip(&grids)
                .any(|(c, g)| WindowGrid::Grid(*c) != *g)
            {
                let v = validate(&coarse)?;
                let failing: Vec<&SensorValidation> = v.iter().filter(|v| !v.passed()).collect();
                if !failing.is_empty() && !failing.iter().any(|v| stalled(v)) {
                    screened = Some(v);
                }
            }
        }
        let sensors = match screened {
            Some(v) => v,
            None => validate_full(&grids)?,
        };
        let validation_time = t1.elapsed();
        let mut added = vec![None; sensors.len()];
        for v in sensors.iter().filter(|v| !v.passed()) {
            if stalled(v) {
                return Err(Error::Stalled {
                    sigma: v.sigma + 1,
                    tau: v.argmin_tau,
                    lambda: v.min_eigenvalue,
                    mu,
                });
            }
            added[v.sigma] = Some(v.argmin_tau);
        }
        for (s, t) in added.iter().enumerate() {
            if let Some(t) = t {
                self.synthesis.add_point(&self.plant, s, *t)?;
            }
        }
        let rec = IterationRecord {
            iteration: self.log.len() + 1,
            p_star: res.p_star,
            p: res.p,
            points,
            sdp: res.stats,
            sdp_time,
            sensors,
            validation_time,
            added,
        };
        let passed = rec.passed();
        self.log.push(rec);
        Ok(passed)
    }

    /// Turns a loop whose last step passed into a [`Design`].
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] if the last step did not pass.
    pub fn finish(self) -> Result<Design, Error> {
        let last = self
            .log
            .last()
            .filter(|r| r.passed())
            .ok_or_else(|| Error::invalid("the design loop has not passed validation"))?;
        let gains = GainSchedule::new(self.plant.clone(), last.p.clone())?;
        Ok(Design {
            p: last.p.clone(),
            p_star: last.p_star,
            mu: self.settings.mu,
            bound: self.bound,
            detectability: self.detectability,
            total_time: self.started.elapsed(),
            bound_time: self.bound_time,
            log: self.log,
            gains,
        })
    }
}

/// Runs the §5.3 algorithm to completion.
///
/// # Errors
/// See [`DesignLoop::new`] and [`DesignLoop::step`]; [`Error::NotConverged`] after `max_iterations`.
pub fn design(plant: &RoundRobinPlant, settings: &DesignOptions) -> Result<Design, Error> {
    design_screened(plant, settings, None)
}

/// [`design()`] with the coarse screen of [`DesignLoop::step_screened`] in every iteration
/// (`None`: exactly [`design()`]). The design it returns passed the same full validation (48)
/// on the grid of the policy as one of [`design()`]; its `P_σ` may differ (other points τ̄).
///
/// # Errors
/// As [`design()`].
pub fn design_screened(
    plant: &RoundRobinPlant,
    settings: &DesignOptions,
    coarse_points: Option<usize>,
) -> Result<Design, Error> {
    let mut lp = DesignLoop::new(plant, settings)?;
    for _ in 0..settings.max_iterations {
        if lp.step_screened(coarse_points)? {
            return lp.finish();
        }
    }
    Err(Error::NotConverged {
        iterations: settings.max_iterations,
    })
}
