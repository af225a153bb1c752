//! The [`ObserverMethod`] contract for Etienne et al. (2017): design by Corollary 2 (static
//! gain) and, when it fails, Theorem 3 (gain `K(τ)` scheduled on the length of the interval that
//! just ended), Remark 6 for a periodic window; largest window by the shared search with one
//! compiled LMI (20) re-used across the probes. No simulation: the observer copies the
//! nonlinearity `φ`, which a plant description only bounds.

use std::time::Instant;

use faer::{Mat, MatRef};
use sporadic_linalg::balance::{balance_a, balance_b, balance_c, balancing_scales, unbalance_gain};

use sporadic_model::{
    Bracketing, Check, DesignReport, Gain, Margin, MaxIntervalReport, MethodError, MethodOptions,
    NamedMatrix, NotApplicable, ObserverMethod, Outputs, Plant as ModelPlant, Probe, Proof,
    ProofOptions, Reason, Sampling, SamplingWindow, Scenario, Tolerance, Trajectory,
    WindowSearchOptions, largest_window_with,
};

use crate::bisection::CompiledProbe;
use crate::coordinates::Coordinates;
use crate::design::{
    Design, DesignOptions, MarginSolution, analyse, analysis_condition, design, finish,
    solve_margin,
};
use crate::error::Error;
use crate::gain::GainSchedule;
use crate::lmi::{Bounds, Condition};
use crate::prove::{Given, prove_design};
use crate::system::Plant;
use crate::verify::{Certificate, Extremum, IndependentCheck, check_certificate};

const ID: &str = "etienne2017";

/// Number of points of the `τ`-grid on which a gain schedule `K(τ)` is reported.
const SCHEDULE_POINTS: usize = 11;

/// Which of the paper's conditions [`ObserverMethod::design`] tries on a window `[T1, T2]` with
/// `T1 < T2` (a periodic window `T1 = T2` always uses Remark 6, with a static gain).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Conditions {
    /// Corollary 2 (static gain `K`) first; Theorem 3 (gain `K(τ)`) when Corollary 2 is not
    /// certified. The default: a static gain when one suffices (the observer then needs no
    /// clock), the larger class of Theorem 3 otherwise.
    #[default]
    Corollary2ThenTheorem3,
    /// Corollary 2 only (static gain).
    Corollary2,
    /// Theorem 3 only (gain `K(τ)`).
    Theorem3,
}

/// Etienne, Hetel, Efimov & Petreczky (2017): impulsive observer for a plant
/// `ẋ = Ax + Bu + Gφ(Hx)` with elementwise bounds on the Jacobian of `φ`, whose output
/// `y = Cx` is sampled with every inter-sample time in a window `[T1, T2] = [τ_low, τ̄]`;
/// designed by the finite LMIs (20) over the vertices of Lemma 1 and re-verified independently.
///
/// ```
/// use sporadic_etienne2017::{Conditions, Etienne2017, ObserverMethod};
///
/// let method = Etienne2017::default();
/// assert_eq!(method.id(), "etienne2017");
/// assert_eq!(method.conditions, Conditions::Corollary2ThenTheorem3);
/// assert!(method.search.is_none()); // the crate's bisection, see `search`
/// ```
#[derive(Debug, Clone, Default)]
pub struct Etienne2017 {
    /// Options of the design at every window (default [`DesignOptions::default`]: the margin
    /// problem of the LMI layer with `‖P1‖₂, ‖P2‖₂ ≤ 1`, independent checks on 201-point τ grids
    /// for (19b)/(19c) and 2001 points for the discrete contraction, rounding safety factor 100).
    pub design: DesignOptions,
    /// The conditions tried (default [`Conditions::Corollary2ThenTheorem3`]).
    pub conditions: Conditions,
    /// The window search of [`ObserverMethod::largest_window`]. Default `None`: this crate's
    /// bisection — doubling from `2·T1`, then bisection to an absolute tolerance of `10⁻³·T2`
    /// (`T2` of the sampling given), at most [`MethodOptions::search`]`.max_probes` probes;
    /// `Some(o)`: the options `o` instead.
    pub search: Option<WindowSearchOptions>,
}

/// Bad input, with the crate's error as the source.
fn invalid(e: Error) -> MethodError {
    MethodError::InvalidInput {
        method: ID,
        source: Box::new(e),
    }
}

/// The verdict an error stands for, or the `Err` when it is not one (bad input, or a failure
/// that is neither).
fn verdict_of(e: Error) -> Result<Reason, MethodError> {
    if let Some(r) = e.reason() {
        return Ok(r);
    }
    if e.is_input() {
        Err(invalid(e))
    } else {
        Err(MethodError::Numerical {
            method: ID,
            source: Box::new(e),
        })
    }
}

/// `reason` with the message `message` (same kind and `τ`).
fn with_message(reason: Reason, message: String) -> Reason {
    match reason {
        Reason::InfeasibleLmi { .. } => Reason::InfeasibleLmi { message },
        Reason::Undetectable { tau, .. } => Reason::Undetectable { tau, message },
        Reason::VerificationFailed { tau, .. } => Reason::VerificationFailed { tau, message },
        Reason::SolverInconclusive { .. } => Reason::SolverInconclusive { message },
        Reason::BudgetExhausted { .. } => Reason::BudgetExhausted { message },
        Reason::MissingData { .. } => Reason::MissingData { message },
        Reason::UnsupportedStructure { .. } => Reason::UnsupportedStructure { message },
        _ => Reason::NumericalFailure { message },
    }
}

/// The crate's plant (1)–(2) of a model plant the method applies to, in the balanced
/// coordinates `x_b = D⁻¹x` (`D` the powers-of-2 `gebal` scaling of `|A| + |G||H|`, returned):
/// `D⁻¹AD`,
/// `D⁻¹B`, `CD`, `D⁻¹G`, `HD`, the same Jacobian bounds. The LMIs (20) are solved there, so their
/// normalisation and margin do not depend on the user's units (issue 22); the report
/// maps gains and certificates back exactly. A plant that is already balanced is unchanged.
pub fn balanced_plant(plant: &ModelPlant) -> Result<(Plant, Vec<f64>), Error> {
    let (Some(lip), Some(c)) = (plant.lipschitz(), plant.c()) else {
        return Err(sporadic_linalg::InputError::empty(
            "etienne2017 needs a Lipschitz nonlinearity and one output matrix C",
        )
        .into());
    };
    // Balanced with the coupling the nonlinearity adds (|A| + |G||H|): a plant whose A alone is
    // reducible (e.g. a chain closed only through φ) is balanced as a whole.
    let (g, h) = (lip.g(), lip.h());
    let coupled = Mat::from_fn(plant.n(), plant.n(), |i, j| {
        plant.a()[(i, j)].abs()
            + (0..g.ncols())
                .map(|k| g[(i, k)].abs() * h[(k, j)].abs())
                .sum::<f64>()
    });
    let d = balancing_scales(coupled.as_ref());
    let p = Plant::new(
        balance_a(plant.a(), &d).as_ref(),
        balance_b(plant.b(), &d).as_ref(),
        balance_c(c, &d).as_ref(),
        balance_b(lip.g(), &d).as_ref(),
        balance_c(lip.h(), &d).as_ref(),
        lip.jacobian_lower(),
        lip.jacobian_upper(),
    )?;
    Ok((p, d))
}

/// The window of a single-rate sampling (rejected by `applies` otherwise).
fn window_of(sampling: &Sampling) -> Result<SamplingWindow, MethodError> {
    match sampling {
        Sampling::Synchronous(w) => Ok(*w),
        Sampling::RoundRobin(_) => Err(MethodError::InvalidInput {
            method: ID,
            source: "etienne2017 needs one sampling window [T1, T2]".into(),
        }),
    }
}

/// A design, or the verdict why not.
enum Outcome {
    Certified {
        design: Box<Design>,
        /// The coordinates it was made in.
        coordinates: Coordinates,
        /// Why Corollary 2 was not used, when Theorem 3 was.
        static_failure: Option<String>,
    },
    Failed(Reason),
}

impl Etienne2017 {
    /// Corollary 2 first, Theorem 3 when it fails (per [`Etienne2017::conditions`]); Remark 6
    /// for a periodic window.
    fn design_at(
        &self,
        plant: &Plant,
        balanced: &Coordinates,
        window: &SamplingWindow,
    ) -> Result<Outcome, MethodError> {
        let run = |condition| {
            let designed = solve_margin(plant, condition, window, &self.design)
                .and_then(|sol| self.finish_in(plant, balanced, sol));
            match designed {
                Ok(d) => Ok(Ok(d)),
                Err(e) => verdict_of(e).map(|r| Err((e_message(&r), r))),
            }
        };
        let certified =
            |(d, coordinates): (Design, Coordinates), static_failure| Outcome::Certified {
                design: Box::new(d),
                coordinates,
                static_failure,
            };
        if window.is_periodic() {
            return Ok(match run(Condition::Remark6)? {
                Ok(d) => certified(d, None),
                Err((_, r)) => Outcome::Failed(r),
            });
        }
        let first = match self.conditions {
            Conditions::Theorem3 => Condition::Theorem3,
            _ => Condition::Corollary2,
        };
        let static_err = match run(first)? {
            Ok(d) => return Ok(certified(d, None)),
            Err(e) => e,
        };
        if self.conditions != Conditions::Corollary2ThenTheorem3 {
            return Ok(Outcome::Failed(static_err.1));
        }
        Ok(match run(Condition::Theorem3)? {
            Ok(d) => certified(d, Some(static_err.0)),
            Err((tv_msg, tv_reason)) => Outcome::Failed(with_message(
                tv_reason,
                format!(
                    "Corollary 2 (static gain): {}; Theorem 3 (time-varying gain): {tv_msg}",
                    static_err.0
                ),
            )),
        })
    }

    /// `sol`, solved on the balanced plant `plant`, as a verified design ([`finish`]), with
    /// the coordinates it was made in; when its margin is positive but not verified by the LMI
    /// layer (below its threshold), the same condition solved once more in the coordinates of
    /// its own certificate ([`crate::coordinates`], not in the paper). A failure there leaves
    /// the verdict of the first solve.
    fn finish_in(
        &self,
        plant: &Plant,
        balanced: &Coordinates,
        sol: MarginSolution,
    ) -> Result<(Design, Coordinates), Error> {
        let own = if sol.margin > 0.0 && !sol.verified() {
            balanced.of_certificate(&sol.certificate)
        } else {
            None
        };
        let (condition, window) = (sol.condition, sol.window);
        let first = match finish(plant, sol, None, &self.design.check) {
            Ok(d) => return Ok((d, balanced.clone())),
            Err(e) => e,
        };
        let Some(own) = own else {
            return Err(first);
        };
        match own
            .plant(plant)
            .and_then(|q| design(&q, condition, &window, &self.design))
        {
            Ok(d) => Ok((d, own)),
            Err(_) => Err(first),
        }
    }

    /// The report of a verified design made in `coordinates`.
    #[allow(clippy::too_many_arguments)]
    fn report(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        vertices: usize,
        d: &Design,
        coordinates: &Coordinates,
        notes: Vec<String>,
        seconds: f64,
    ) -> DesignReport {
        let mut r = DesignReport::certified(self, plant.name(), sampling);
        let condition = d.lmi.condition;
        r.gains.push(gain_entry(&d.gain, condition, coordinates));
        r.certificate = certificate_entries(&d.lmi.certificate, d.gain.is_constant(), coordinates);
        r.margin = Some(Margin {
            value: d.lmi.margin,
            definition: margin_definition(condition),
        });
        r.checks = checks(&self.design, d, vertices);
        r.notes.push(format!(
            "{} (LMIs (20) at the {vertices} vertices R_p of the Jacobian box, Lemma 1): {}; {} \
             interior-point iterations, {} decision scalars",
            condition.name(),
            if d.gain.is_constant() {
                "static gain K"
            } else {
                "gain K(τ) interpolating K0 and K1 over the length τ of the interval that just \
                 ended"
            },
            d.lmi.stats.iterations,
            d.lmi.stats.decision_scalars,
        ));
        r.notes.extend(notes);
        r.notes.extend(coordinates.note());
        r.notes.push(
            "B and u do not enter the error dynamics (4): the design holds for every input".into(),
        );
        if plant.bounds().is_some() {
            r.notes.push(
                "the disturbance/noise bounds of the plant are not used: the design is for the \
                 noise-free error (4)"
                    .into(),
            );
        }
        r.notes.push(
            "K is not unique: (20) has a continuum of solutions; this one maximises the margin t*"
                .into(),
        );
        r.seconds = seconds;
        r
    }
}

impl Etienne2017 {
    /// [`ObserverMethod::verify`] on a plant the method applies to, in its balanced
    /// coordinates `(p, scales)`.
    fn verify_given(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        window: &SamplingWindow,
        (p, scales): (&Plant, &[f64]),
        given: &Given,
    ) -> Result<DesignReport, MethodError> {
        let start = Instant::now();
        // To the balanced coordinates x_b = D⁻¹x (exact, powers of 2): K_b = D⁻¹K,
        // P_b = DPD, L_b = DL.
        let k = |m: &Mat<f64>| balance_b(m.as_ref(), scales);
        let form = |m: &Mat<f64>| {
            Mat::from_fn(m.nrows(), m.ncols(), |i, j| {
                m[(i, j)] * scales[i] * scales[j]
            })
        };
        let gain =
            GainSchedule::interpolated(k(&given.k0).as_ref(), k(&given.k1).as_ref(), *window)
                .map_err(invalid)?;
        let condition = analysis_condition(&gain);
        let mut notes = Vec::new();
        if let Some((p1, p2)) = &given.p {
            let (p1, p2) = (form(p1), form(p2));
            // L = P1·K when the certificate has no L.
            let (l0, l1) = match &given.l {
                Some((l0, l1)) => (
                    unbalance_gain(l0.as_ref(), scales),
                    unbalance_gain(l1.as_ref(), scales),
                ),
                None => (&p1 * gain.k0(), &p1 * gain.k1()),
            };
            let cert = Certificate { p1, p2, l0, l1 };
            let check =
                match check_certificate(p, condition, window, &cert, &gain, &self.design.check) {
                    Ok(c) => c,
                    Err(e) => {
                        let reason = verdict_of(e)?;
                        return Ok(DesignReport::without_design(
                            self,
                            plant.name(),
                            Some(sampling),
                            reason,
                        ));
                    }
                };
            match check.failure() {
                None => {
                    let mut r = DesignReport::certified(self, plant.name(), sampling);
                    let balanced = Coordinates::balanced(scales.to_vec());
                    r.gains.push(gain_entry(&gain, condition, &balanced));
                    r.certificate = certificate_entries(&cert, gain.is_constant(), &balanced);
                    r.checks = independent_checks(&self.design, &check);
                    r.notes.push(format!(
                        "given gain and certificate verified for {} (no LMI solved): the \
                         independent checks of a design, in the balanced coordinates",
                        condition.name()
                    ));
                    r.seconds = start.elapsed().as_secs_f64();
                    return Ok(r);
                }
                Some(e) => notes.push(format!(
                    "the given certificate does not verify ({e}); LMIs (20) were solved for \
                     P1, P2 with the given gain fixed (L0 = P1K0, L1 = P1K1)"
                )),
            }
        } else {
            notes.push(
                "no certificate given: LMIs (20) were solved for P1, P2 with the given gain \
                 fixed (L0 = P1K0, L1 = P1K1)"
                    .into(),
            );
        }
        match analyse(p, &gain, &self.design) {
            Ok(d) => Ok(self.report(
                plant,
                sampling,
                p.vertices().len(),
                &d,
                &Coordinates::balanced(scales.to_vec()),
                notes,
                start.elapsed().as_secs_f64(),
            )),
            Err(e) => {
                let mut r = DesignReport::without_design(
                    self,
                    plant.name(),
                    Some(sampling),
                    verdict_of(e)?,
                );
                r.notes = notes;
                r.seconds = start.elapsed().as_secs_f64();
                Ok(r)
            }
        }
    }
}

/// The gain `K` (or the schedule `K(τ)`) of a design made in `coordinates`, in the plant's
/// ([`Coordinates::gain_back`]).
fn gain_entry(g: &GainSchedule, condition: Condition, coordinates: &Coordinates) -> Gain {
    let gain = |k: MatRef<'_, f64>| coordinates.gain_back(k);
    let w = *g.window();
    let jump = "jump of observer (3) at each sample t_k: x̂(t_k) = x̂(t_k⁻) + K(τ)(y_k − \
                Cx̂(t_k⁻)), τ = t_k − t_{k−1} the length of the interval that just ended; \
                the error z = x − x̂ jumps by z⁺ = (I − K(τ)C)z (4)";
    if g.is_constant() {
        Gain::constant(
            "K",
            gain(g.k1()).as_ref(),
            format!(
                "{jump}; here K does not depend on τ: K = P1⁻¹L ({})",
                condition.name()
            ),
        )
    } else {
        let (t1, t2) = (w.t1(), w.t2());
        let tau: Vec<f64> = (0..SCHEDULE_POINTS)
            .map(|i| {
                if i + 1 == SCHEDULE_POINTS {
                    t2
                } else {
                    t1 + (t2 - t1) * i as f64 / (SCHEDULE_POINTS - 1) as f64
                }
            })
            .collect();
        Gain::scheduled(
            "K",
            format!("{jump}; the reported value is K1 = K(T2)"),
            "K(τ) = K0 + (τ − T1)/(T2 − T1)·(K1 − K0) for τ in [T1, T2], with K0 = P1⁻¹L0 = \
             K(T1) and K1 = P1⁻¹L1 = K(T2) (Theorem 3, gain recovery of Remark 6)",
            tau,
            |t| gain(g.at(t).as_ref()),
        )
    }
}

/// The certificate `P1, P2` and `L` (static gain) or `L0, L1` of a design made in
/// `coordinates`, in the plant's ([`Coordinates::form_back`], [`Coordinates::multiplier_back`]).
fn certificate_entries(
    cert: &Certificate,
    constant: bool,
    coordinates: &Coordinates,
) -> Vec<NamedMatrix> {
    let form = |p: MatRef<'_, f64>| coordinates.form_back(p);
    let rows_down = |m: MatRef<'_, f64>| coordinates.multiplier_back(m);
    let mut out = vec![
        NamedMatrix::new(
            "P1",
            form(cert.p1.as_ref()).as_ref(),
            "P(0) = P1 of the Lyapunov matrix P(τ) = (1 − τ/T2)P1 + (τ/T2)P2 of Theorem 3 \
             (V = z'P(τ)z, τ the time since the last sample): z'P1z decreases from sample to \
             sample",
        ),
        NamedMatrix::new(
            "P2",
            form(cert.p2.as_ref()).as_ref(),
            "P(T2) = P2 of the Lyapunov matrix of Theorem 3",
        ),
    ];
    if constant {
        out.push(NamedMatrix::new(
            "L",
            rows_down(cert.l1.as_ref()).as_ref(),
            "L = P1·K, the decision variable of (20c)/(20d) (L0 = L1 = L)",
        ));
    } else {
        out.push(NamedMatrix::new(
            "L0",
            rows_down(cert.l0.as_ref()).as_ref(),
            "L0 = P1·K0, the decision variable of (20c)",
        ));
        out.push(NamedMatrix::new(
            "L1",
            rows_down(cert.l1.as_ref()).as_ref(),
            "L1 = P1·K1, the decision variable of (20d)",
        ));
    }
    out
}

/// The message of a reason (the crate's error message).
fn e_message(r: &Reason) -> String {
    r.message().to_string()
}

/// What the margin of a design is.
fn margin_definition(condition: Condition) -> String {
    let jumps = if condition == Condition::Remark6 {
        "the jump block (20d) ⪰ t·I (Remark 6 drops (20c))"
    } else {
        "the jump blocks (20c) and (20d) ⪰ t·I"
    };
    format!(
        "optimal margin t* of LMIs (20) ({}): the largest t with T2·M¹_p ⪯ −t·I and T2·M²_p ⪯ \
         −t·I (T2·M^i_p = He(P_i R_p T2) + P2 − P1, free of the time unit) at every vertex R_p of \
         Lemma 1 ((20a), (20b)), {jumps}, and P1, P2 ⪰ t·I, under the \
         normalisation ‖P1‖₂ ≤ 1, ‖P2‖₂ ≤ 1 (spectral norms; L0, L1 free); (20) is homogeneous, \
         so t* > 0 iff it is strictly feasible, and t* is the slack of the certificate relative \
         to that scale",
        condition.name()
    )
}

/// A check from the worst point of an independent check.
fn check(what: &str, how: String, e: &Extremum) -> Check {
    let at = match (e.tau.is_finite(), e.vertex) {
        (true, Some(v)) => format!("; worst at τ = {:.6}, vertex {}", e.tau, v + 1),
        (true, None) => format!("; worst at τ = {:.6}", e.tau),
        (false, Some(v)) => format!("; worst at vertex {}", v + 1),
        (false, None) => String::new(),
    };
    Check {
        what: what.into(),
        how: format!(
            "{how}; must clear the rounding bound {:.2e} (safety factor × dimension × ε × scale \
             of the summands){at}",
            e.tolerance
        ),
        value: e.value.is_finite().then_some(e.value),
        passed: e.passed(),
    }
}

/// Every re-verification of a design.
fn checks(options: &DesignOptions, d: &Design, vertices: usize) -> Vec<Check> {
    let stats = &d.lmi.stats;
    let mut out = vec![Check {
        what: "LMIs (20) re-verified at the solver's point by the LMI layer".into(),
        how: format!(
            "{} vertices R_p; interior point {:?} after {} iterations (relative gap {:.1e}); \
             every constraint's eigenvalues recomputed at the returned point, margin required \
             above the verification threshold {}",
            vertices,
            stats.status,
            stats.iterations,
            stats.rel_gap,
            stats
                .margin_threshold
                .map_or_else(|| "(none)".into(), |t| format!("{t:.2e}")),
        ),
        value: Some(d.lmi.margin),
        passed: true,
    }];
    out.extend(independent_checks(options, &d.check));
    out
}

/// The independent checks of a certificate ([`crate::verify::check_certificate`]) as report
/// checks.
fn independent_checks(options: &DesignOptions, c: &IndependentCheck) -> Vec<Check> {
    let (lmi_grid, discrete_grid, safety) = (
        options.check.lmi_grid,
        options.check.discrete_grid,
        options.check.safety,
    );
    let eig = format!(
        "symmetric eigensolver in f64 on matrices recomputed from (P1, P2, L0, L1), safety factor {safety}"
    );
    let mut out = Vec::new();
    out.push(check(
        "(20a)/(20b): max λ_max(M¹_p), λ_max(M²_p) over the vertices (must be < 0)",
        eig.clone(),
        &c.flow_vertices,
    ));
    out.push(check(
        "(20c)/(20d): min λ_min of the jump blocks (must be > 0)",
        eig.clone(),
        &c.jump_vertices,
    ));
    out.push(check(
        "P1 ≻ 0, P2 ≻ 0: min λ_min (must be > 0)",
        eig.clone(),
        &c.positivity,
    ));
    out.push(check(
        "(19b) of Corollary 1 on a τ grid: max λ_max(He(P(τ)R_p) + (P2 − P1)/T2) (must be < 0)",
        format!("{lmi_grid} equally spaced τ in [0, T2], every vertex; {eig}"),
        &c.flow_grid,
    ));
    out.push(check(
        "(19c) of Corollary 1 on a τ grid: min λ_min of the jump block with P(τ) and L(τ) \
         (must be > 0)",
        format!("{lmi_grid} equally spaced τ in [T1, T2] (T2 only for Remark 6); {eig}"),
        &c.jump_grid,
    ));
    if let Some(e) = &c.discrete.contraction {
        out.push(check(
            "discrete contraction: max λ_max(M_p(τ)'P1M_p(τ) − P1), M_p(τ) = (I − K(τ)C)e^(R_p τ) \
             (a necessary consequence of the certificate; must be < 0)",
            format!(
                "{discrete_grid} equally spaced τ in [T1, T2], every vertex, e^(R_p τ) by an \
                 exponential stepper in f64, safety factor {safety} × (1 + ‖R_p τ‖)"
            ),
            e,
        ));
    }
    out.push(check(
        "discrete contraction: max spectral radius of (I − K(τ)C)e^(R_p τ) (must be < 1)",
        format!("same {discrete_grid}-point grid and vertices"),
        &c.discrete.spectral_radius,
    ));
    out
}

impl ObserverMethod for Etienne2017 {
    fn id(&self) -> &'static str {
        ID
    }

    fn citation(&self) -> &'static str {
        "L. Etienne, L. Hetel, D. Efimov, M. Petreczky (2017), Observer synthesis under \
         time-varying sampling for Lipschitz nonlinear systems, Automatica 85, 433–440"
    }

    fn summary(&self) -> &'static str {
        "impulsive observer for a Lipschitz nonlinear plant with every inter-sample time in \
         [T1, T2], static gain (Corollary 2) or gain K(τ) scheduled on the last interval \
         (Theorem 3), by finite LMIs (20) without matrix exponential"
    }

    fn observer(&self) -> &'static str {
        "between samples x̂' = Ax̂ + Bu + Gφ(Hx̂) (observer (3), a copy of the plant); at a sample \
         t_k x̂⁺ = x̂ + K(τ)(y − Cx̂), τ = t_k − t_{k−1} the length of the interval that just \
         ended (K constant for Corollary 2 and Remark 6); error z = x − x̂: z' = Az + G[φ(Hx) − \
         φ(H(x − z))] ∈ co{R_p z} (Lemma 1), z⁺ = (I − K(τ)C)z (4)"
    }

    fn applies(&self, plant: &ModelPlant, sampling: &Sampling) -> Result<(), NotApplicable> {
        let Some(lip) = plant.lipschitz() else {
            return Err(NotApplicable::missing(
                ID,
                "needs a [lipschitz] section (G, H and the Jacobian bounds of phi); for a linear \
                 plant use ferrante2016",
            ));
        };
        if let Outputs::RoundRobin(_) = plant.output_structure() {
            return Err(NotApplicable::unsupported(
                ID,
                "the plant has round-robin sensors; Etienne et al. (2017) sample one output \
                 y = Cx at once",
            ));
        }
        if let Sampling::RoundRobin(_) = sampling {
            return Err(NotApplicable::unsupported(
                ID,
                "the sampling is round-robin (one window per sensor); Etienne et al. (2017) \
                 need one window [T1, T2] for all outputs",
            ));
        }
        let (q, r) = (lip.g().ncols(), lip.h().nrows());
        if q != r {
            return Err(NotApplicable::unsupported(
                ID,
                format!(
                    "phi must map R^m to R^m (G n×m, H m×n), but G has {q} columns and H has \
                     {r} rows"
                ),
            ));
        }
        if q == 0 {
            return Err(NotApplicable::unsupported(
                ID,
                "the nonlinearity has dimension 0 (G has no column): the plant is linear, use \
                 ferrante2016",
            ));
        }
        Ok(())
    }

    fn design(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        _options: &MethodOptions,
    ) -> Result<DesignReport, MethodError> {
        let start = Instant::now();
        let failed = |reason: Reason| {
            let mut r = DesignReport::without_design(self, plant.name(), Some(sampling), reason);
            r.seconds = start.elapsed().as_secs_f64();
            r
        };
        if let Err(na) = self.applies(plant, sampling) {
            return Ok(failed(na.reason));
        }
        let window = window_of(sampling)?;
        self.design.validate().map_err(invalid)?;
        let (p, scales) = match balanced_plant(plant) {
            Ok(p) => p,
            Err(e) => return verdict_of(e).map(failed),
        };
        let balanced = Coordinates::balanced(scales);
        match self.design_at(&p, &balanced, &window)? {
            Outcome::Certified {
                design,
                coordinates,
                static_failure,
            } => {
                let notes = static_failure
                    .map(|e| {
                        format!(
                            "Corollary 2 (static gain) is not certified on this window ({e}); \
                             Theorem 3 (time-varying gain) is"
                        )
                    })
                    .into_iter()
                    .collect();
                Ok(self.report(
                    plant,
                    sampling,
                    p.vertices().len(),
                    &design,
                    &coordinates,
                    notes,
                    start.elapsed().as_secs_f64(),
                ))
            }
            Outcome::Failed(reason) => Ok(failed(reason)),
        }
    }

    /// The shared [`largest_window_with`] with a probe that re-solves one compiled LMI (20) of
    /// Theorem 3 (which contains Corollary 2; Corollary 2 alone for
    /// [`Conditions::Corollary2`]), the window entering through parameters, and re-verifies
    /// every certified probe independently as [`ObserverMethod::design`] does; a periodic probe
    /// `T2 = T1` is designed by Remark 6. The search options are [`Etienne2017::search`]
    /// (default: doubling from `2·T1`, absolute tolerance `1e-3·T2`).
    fn largest_window(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        limit: f64,
        options: &MethodOptions,
        progress: &mut dyn FnMut(&Probe),
    ) -> Result<MaxIntervalReport, MethodError> {
        if let Err(na) = self.applies(plant, sampling) {
            let r = MaxIntervalReport::without_search(
                ID,
                plant.name(),
                Some(sampling),
                Some(limit),
                na.reason,
            );
            return Ok(r);
        }
        let start = Instant::now();
        let window = window_of(sampling)?;
        self.design.validate().map_err(invalid)?;
        let (p, scales) = match balanced_plant(plant) {
            Ok(p) => p,
            Err(e) => {
                let reason = verdict_of(e)?;
                let mut r = MaxIntervalReport::without_search(
                    ID,
                    plant.name(),
                    Some(sampling),
                    Some(limit),
                    reason,
                );
                r.seconds = start.elapsed().as_secs_f64();
                return Ok(r);
            }
        };
        let vertices = p.vertices().len();
        let balanced = Coordinates::balanced(scales);
        let condition = match self.conditions {
            Conditions::Corollary2 => Condition::Corollary2,
            _ => Condition::Theorem3,
        };
        let search_options = self.search.unwrap_or(WindowSearchOptions {
            bracketing: Bracketing::Doubling { start: None },
            tolerance: Tolerance::Absolute(1e-3 * window.t2()),
            max_probes: options.search.max_probes,
        });
        let note = format!(
            "largest-window search: {} at every probe (compiled once, the window entering \
             through parameters)",
            if condition == Condition::Theorem3 {
                "Theorem 3 (which contains Corollary 2)"
            } else {
                "Corollary 2"
            }
        );
        let mut compiled: Option<CompiledProbe> = None;
        let mut probe = |s: &Sampling| -> Result<DesignReport, MethodError> {
            let probe_start = Instant::now();
            let w = window_of(s)?;
            let result = if w.is_periodic() {
                solve_margin(&p, Condition::Remark6, &w, &self.design)
                    .and_then(|sol| self.finish_in(&p, &balanced, sol))
            } else {
                if compiled.is_none() {
                    let c =
                        CompiledProbe::new(&p, condition, Bounds::of(&w), &self.design.feasibility);
                    compiled = Some(match c {
                        Ok(c) => c,
                        Err(e) => {
                            let reason = verdict_of(e)?;
                            return Ok(DesignReport::without_design(
                                self,
                                plant.name(),
                                Some(s),
                                reason,
                            ));
                        }
                    });
                }
                match compiled.as_mut() {
                    Some(c) => c
                        .solve_window(w)
                        .and_then(|sol| self.finish_in(&p, &balanced, sol)),
                    None => {
                        return Err(invalid(
                            sporadic_linalg::InputError::empty("LMI (20)").into(),
                        ));
                    }
                }
            };
            Ok(match result {
                Ok((d, coordinates)) => {
                    let seconds = probe_start.elapsed().as_secs_f64();
                    self.report(
                        plant,
                        s,
                        vertices,
                        &d,
                        &coordinates,
                        vec![note.clone()],
                        seconds,
                    )
                }
                Err(e) => DesignReport::without_design(self, plant.name(), Some(s), verdict_of(e)?),
            })
        };
        largest_window_with(
            self,
            plant,
            sampling,
            limit,
            &search_options,
            options,
            progress,
            &mut probe,
        )
    }

    /// The rigorous proof of [`crate::prove`]: Corollary 1's conditions (19a), (19b) and the
    /// Schur form (16c) of (19c) for the design's `K(τ)`, `P1`, `P2`, for every `τ` of the
    /// window and every member of the Jacobian polytope, in interval arithmetic.
    fn prove(
        &self,
        plant: &ModelPlant,
        design: &DesignReport,
        options: &ProofOptions,
    ) -> Result<Proof, MethodError> {
        prove_design(plant, design, options)
    }

    /// Checks a gain `K` (constant, or the schedule `K(τ)` of a Theorem 3 report) on `sampling`
    /// with the certificate `P1, P2` (and `L` or `L0, L1`; `L = P1K` when absent) by the
    /// independent checks of a design ([`check_certificate`], in the balanced coordinates);
    /// without a certificate, or when it does not verify, LMIs (20) are solved for `P1, P2`
    /// with the gain fixed ([`analyse`]). Certified when the checks pass; otherwise not
    /// certified with the reason.
    fn verify(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        gains: &[Gain],
        certificate: &[NamedMatrix],
        _options: &MethodOptions,
    ) -> Result<DesignReport, MethodError> {
        if let Err(na) = self.applies(plant, sampling) {
            return Ok(DesignReport::without_design(
                self,
                plant.name(),
                Some(sampling),
                na.reason,
            ));
        }
        let window = window_of(sampling)?;
        self.design.validate().map_err(invalid)?;
        let (p, scales) = match balanced_plant(plant) {
            Ok(p) => p,
            Err(e) => {
                let reason = verdict_of(e)?;
                return Ok(DesignReport::without_design(
                    self,
                    plant.name(),
                    Some(sampling),
                    reason,
                ));
            }
        };
        let given = Given::read(p.n(), p.q(), &window, gains, certificate)?;
        self.verify_given(plant, sampling, &window, (&p, &scales), &given)
    }

    /// Not available: the observer (3) copies the nonlinearity `φ` between samples, and a plant
    /// description only bounds it (`G`, `H` and the Jacobian bounds). With `φ` as a function,
    /// use [`crate::simulate_observer`].
    fn simulate(
        &self,
        _plant: &ModelPlant,
        _design: &DesignReport,
        _scenario: &Scenario,
    ) -> Result<Trajectory, MethodError> {
        Err(MethodError::SimulationUnavailable {
            method: ID,
            why: "etienne2017 would need the nonlinearity phi itself, which a plant description \
                  only bounds (G, H and the Jacobian bounds of phi); with phi as a function, \
                  simulate with sporadic_etienne2017::simulate_observer"
                .into(),
        })
    }
}
