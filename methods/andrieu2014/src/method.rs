//! The [`ObserverMethod`] contract for Andrieu, Nadri, Serres & Vivalda (2014).
//!
//! The observer (5)–(7) chooses its own sampling instants (rule (7): the interval times the high
//! gain `L` equals `α`) for triangular systems in observability normal form (1). A plant file's
//! plant is brought to that form through one output row ([`crate::normal_form`]; for several
//! outputs, the one whose transformation is best conditioned) and the observer is designed there
//! with the constants of Theorem 2 ([`crate::plant_design`]). The report's `window` is the range of
//! inter-sample intervals that the rule guarantees, not the plant file's window: the rule, not the
//! user, picks the instants, so [`ObserverMethod::largest_window`] does not apply.
//!
//! Verdicts: `certified` for a plant observable from some output whose nonlinearity (if any) is
//! triangular in the normal form; `not_applicable` (`unsupported_structure`) for round-robin
//! sensors, a plant observable from no single output, or a non-triangular nonlinearity;
//! `not_certified` (`numerical_failure`) when the transformation is too ill-conditioned
//! ([`crate::normal_form::CONDITION_LIMIT`]).

use std::time::Instant;

use sporadic_model::report::Check;
use sporadic_model::{
    DesignReport, Gain, Margin, MethodError, MethodOptions, NamedMatrix, NotApplicable,
    ObserverMethod, Plant, Reason, Sampling, SamplingWindow, Scenario, Trajectory,
    check_simulatable, sig4,
};

use crate::error::Error;
use crate::normal_form::{CONDITION_LIMIT, NormalForm};
use crate::plant_design::PlantDesign;
use crate::simulation::simulate_linear;

/// Andrieu, Nadri, Serres & Vivalda (2014): high-gain observer with updated sampling period.
#[derive(Debug, Clone, Default)]
pub struct Andrieu2014;

const ID: &str = "andrieu2014";

/// Points of the reported gain schedule `G(δ)` (geometric in `δ` over the guaranteed range).
const SCHEDULE_POINTS: usize = 11;

/// Relative slack of the re-verification of (9) (`λmax ≤ −1`) and of the companion identity.
const CHECK_TOL: f64 = 1e-9;

impl ObserverMethod for Andrieu2014 {
    fn id(&self) -> &'static str {
        ID
    }

    fn citation(&self) -> &'static str {
        "V. Andrieu, M. Nadri, U. Serres, J.-C. Vivalda (2014), Continuous discrete observer with \
         updated sampling period (long version), HAL hal-00828578v2"
    }

    fn summary(&self) -> &'static str {
        "high-gain observer whose next sample is taken when (time since last sample) x gain = alpha"
    }

    fn observer(&self) -> &'static str {
        "in normal-form coordinates z = T x (time t scaled by omega): between samples the observer \
         copies the model, x̂' = A x̂ + B u (+ G phi(H x̂)), and L' = a2·omega·c·L·M, \
         M' = a3·omega·c·M (6a-b); next sample when (t − t_k)·omega·L(t) = alpha (rule (7)); at a \
         sample ẑ ← ẑ + alpha·diag(1, L⁻, …, (L⁻)^(n−1))·K·(ẑ_1 − y) with K_i < 0 (5), i.e. \
         x̂ ← x̂ + G(δ)(c x̂ − y) with G(δ) = alpha T⁻¹ diag(1, L⁻, …) K and L⁻ = alpha/(omega δ), \
         then L ← (1 − a1 alpha) L⁻ + a1 alpha, M ← 1 (6c-d)"
    }

    /// The rule (7) picks every sampling instant.
    fn chooses_its_sampling(&self) -> bool {
        true
    }

    fn applies(&self, plant: &Plant, sampling: &Sampling) -> Result<(), NotApplicable> {
        let (Sampling::Synchronous(_), Some(c)) = (sampling, plant.c()) else {
            return Err(NotApplicable::unsupported(
                ID,
                "round-robin sensors: the observer (5)-(7) reads one output at instants it picks \
                 itself",
            ));
        };
        let mut errors = Vec::new();
        for i in 0..c.nrows() {
            match NormalForm::new(plant, i) {
                Err(e @ (Error::NotObservable { .. } | Error::NotTriangular { .. })) => {
                    errors.push(e)
                }
                // A normal form, or a numerical verdict that `design` reports.
                _ => return Ok(()),
            }
        }
        if let Some(e) = errors
            .iter()
            .find(|e| matches!(e, Error::NotTriangular { .. }))
        {
            return Err(NotApplicable::unsupported(
                ID,
                format!(
                    "{e}; the observer needs a nonlinearity O G phi(H O^-1 z) that is \
                     lower-triangular in z = O x (O the observability matrix of one output), as in \
                     (1)"
                ),
            ));
        }
        Err(NotApplicable::unsupported(
            ID,
            format!(
                "not observable from any single output row ({}): the observability normal form \
                 (1) needs (A, c_i) observable for some output row c_i",
                errors
                    .iter()
                    .map(|e| e.to_string())
                    .collect::<Vec<_>>()
                    .join("; ")
            ),
        ))
    }

    fn design(
        &self,
        plant: &Plant,
        sampling: &Sampling,
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
        let mut report = match PlantDesign::new(plant, sampling.t2()) {
            Ok(d) => self.report(plant, sampling, &d)?,
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
        let unavailable = |why: String| MethodError::SimulationUnavailable { method: ID, why };
        check_simulatable(ID, design)?;
        if plant.lipschitz().is_some() {
            return Err(unavailable(
                "the plant file gives only bounds on the Jacobian of phi, not phi itself, so the \
                 plant cannot be simulated"
                    .into(),
            ));
        }
        let Some(window) = design.window else {
            return Err(unavailable("the report has no window".into()));
        };
        let d = PlantDesign::new(plant, window.t2()).map_err(|e| MethodError::Numerical {
            method: ID,
            source: Box::new(e),
        })?;
        simulate_linear(plant, &d, scenario).map_err(|e| match e {
            Error::Input(_) => MethodError::InvalidInput {
                method: ID,
                source: Box::new(e),
            },
            e => MethodError::Numerical {
                method: ID,
                source: Box::new(e),
            },
        })
    }
}

/// The report of a verdict `e` on the plant, or `Err` for a failure that is not one.
fn verdict(e: Error) -> Result<Reason, MethodError> {
    Ok(match e {
        Error::IllConditioned { .. } | Error::NoConvergence { .. } | Error::Linalg(_) => {
            Reason::NumericalFailure {
                message: e.to_string(),
            }
        }
        Error::NotObservable { .. } | Error::NotTriangular { .. } => Reason::UnsupportedStructure {
            message: e.to_string(),
        },
        Error::NotHurwitz { .. }
        | Error::NotDiagonallyDominated { .. }
        | Error::NoAdmissibleAlpha { .. } => Reason::InfeasibleLmi {
            message: format!(
                "no constants (D1)-(D3) of Theorem 2 for this order with the binomial gain and the \
                 weights W = diag(1, r, …, r^(n−1)), r in {{1, 0.1, 0.01, 0.001}}: {e}"
            ),
        },
        e => {
            return Err(MethodError::InvalidInput {
                method: ID,
                source: Box::new(e),
            });
        }
    })
}

impl Andrieu2014 {
    /// The certified report of `d`, after the re-verification of its conditions (a failed check
    /// gives `not_certified`, `verification_failed`).
    fn report(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        d: &PlantDesign,
    ) -> Result<DesignReport, MethodError> {
        let numerical = |e: Error| MethodError::Numerical {
            method: ID,
            source: Box::new(e),
        };
        let nf = &d.normal_form;
        let n = nf.order();
        let alpha = d.tuning.alpha();
        let margin = d.lemma4_margin().map_err(numerical)?;
        let c9 = d.condition9().map_err(numerical)?;
        let checks = vec![
            Check {
                what: "condition (9): (A+KC)'P + P(A+KC) ≼ −I".into(),
                how: format!(
                    "largest eigenvalue of (A+KC)'P + P(A+KC) recomputed from P and K (symmetric \
                     eigenvalues), must be ≤ −1 + {CHECK_TOL:e}"
                ),
                value: Some(c9),
                passed: c9 <= -1.0 + CHECK_TOL,
            },
            Check {
                what: "Lemma 4, (17), in its checkable form (Lemma 6) at the design alpha".into(),
                how: format!(
                    "1 − α/(4p2) − λmax(P⁻¹Q(α)'ψ0(α)Pψ0(α)Q(α)) with Q(α) = (I + αKC)e^(Aα) at \
                     α = {} (Cholesky and symmetric eigenvalues), must be > 0",
                    sig4(alpha)
                ),
                value: Some(margin),
                passed: margin > 0.0,
            },
            Check {
                what: "normal form: c Aⁿ = a'O (companion identity O A = (S + e_n a')O)".into(),
                how: format!(
                    "largest |c Aⁿ − a'O|_j / (|c Aⁿ|_j + (|a'||O|)_j), must be ≤ {CHECK_TOL:e}"
                ),
                value: Some(nf.residual()),
                passed: nf.residual() <= CHECK_TOL,
            },
            Check {
                what: "conditioning of the transformation to normal form".into(),
                how: format!(
                    "2-norm condition number of the observability matrix after power-of-two \
                     row/column equilibration (SVD), must be ≤ {} = 1/sqrt(eps)",
                    sig4(CONDITION_LIMIT)
                ),
                value: Some(nf.condition()),
                passed: nf.condition() <= CONDITION_LIMIT,
            },
            Check {
                what: "Lemma 1: the high gain stays bounded, so the intervals have a positive \
                       lower bound"
                    .into(),
                how: format!(
                    "root ℓ1 of φ(ℓ1) = 1 by bisection with c_m = c̃ = {}, L̄ = κ(α)·max(L(0), ℓ1, \
                     ℓ1φ(1)), must be finite",
                    sig4(d.c_scaled)
                ),
                value: Some(d.lemma1.sup_bound),
                passed: d.lemma1.sup_bound.is_finite() && d.shortest > 0.0,
            },
        ];
        if let Some(failed) = checks.iter().find(|c| !c.passed) {
            let mut r = DesignReport::without_design(
                self,
                plant.name(),
                Some(sampling),
                Reason::VerificationFailed {
                    tau: None,
                    message: format!(
                        "{} failed: {} (value {:?})",
                        failed.what, failed.how, failed.value
                    ),
                },
            );
            r.checks = checks;
            return Ok(r);
        }
        let window =
            SamplingWindow::new(d.shortest, d.longest).map_err(|e| MethodError::Numerical {
                method: ID,
                source: Box::new(e),
            })?;
        let mut r = DesignReport::certified(self, plant.name(), &Sampling::Synchronous(window));
        let k = faer::Mat::from_fn(n, 1, |i, _| d.tuning.gain()[i]);
        r.gains.push(Gain::constant(
            "K",
            k.as_ref(),
            "gain of (5) in the scaled normal-form coordinates z̃ = T x: at a sample \
             z̃ ← z̃ + α·diag(1, L⁻, …, (L⁻)^(n−1))·K·(z̃_1 − y), binomial (all poles of A + KC \
             at −1)",
        ));
        let ratio = d.longest / d.shortest;
        let tau: Vec<f64> = (0..SCHEDULE_POINTS)
            .map(|i| d.shortest * ratio.powf(i as f64 / (SCHEDULE_POINTS - 1) as f64))
            .collect();
        let gains = tau
            .iter()
            .map(|&t| d.plant_gain(t))
            .collect::<Result<Vec<_>, _>>()
            .map_err(numerical)?;
        let mut it = gains.into_iter();
        r.gains.push(Gain::scheduled(
            "G",
            format!(
                "correction in the plant's coordinates: x̂ ← x̂ + G(δ)(c x̂ − y) at a sample, δ the \
                 interval that ends there and c = row {} of C",
                nf.output() + 1
            ),
            "G(δ) = α T⁻¹ diag(1, L⁻, …, (L⁻)^(n−1)) K with L⁻ = α/(ω δ) (rule (7))",
            tau,
            |_| it.next().unwrap_or_else(|| faer::Mat::zeros(n, 1)),
        ));
        r.certificate.push(NamedMatrix::new(
            "P",
            d.design.p(),
            "Lyapunov matrix of (8)-(9b): V(E) = E'PE with E = 𝓛(L)⁻¹(ẑ − z̃) decreases at every \
             sample (proof of Theorem 2)",
        ));
        r.certificate.push(NamedMatrix::new(
            "T",
            nf.scaled_transformation(d.omega).as_ref(),
            "z̃ = T x: scaled observability normal form, z̃_i = y^(i−1)/ω^(i−1) of the linear part \
             (T = D_ω⁻¹O, O the observability matrix of the output used)",
        ));
        r.margin = Some(Margin {
            value: margin,
            definition: "1 − α/(4p2) − λmax(P⁻¹Q(α)'ψ0(α)Pψ0(α)Q(α)) at the design α: the \
                         checkable form of Lemma 4, (17) (dimensionless, in the scaled time)"
                .into(),
        });
        r.checks = checks;
        r.notes = self.notes(plant, sampling, d);
        Ok(r)
    }

    fn notes(&self, plant: &Plant, sampling: &Sampling, d: &PlantDesign) -> Vec<String> {
        let nf = &d.normal_form;
        let t = &d.tuning;
        let mut notes = Vec::new();
        notes.push(format!(
            "sampling rule (7): next sample when (t − t_k)·ω·L(t) = α, α = {}, ω = {} rad per unit of the plant's time; \
             between samples L(t) = L(t_k)·exp((a2/a3)(exp(a3·ω·c̃·(t − t_k)) − 1)), at a sample \
             L ← (1 − a1α)L⁻ + a1α, L(0) = 1",
            sig4(t.alpha()),
            sig4(d.omega)
        ));
        notes.push(format!(
            "guaranteed intervals: every interval lies in the window [{}, {}] (the plant's time unit): at most α/ω since \
             L ≥ 1, at least α/(ω L̄) with L̄ = {} the bound of Lemma 1 on L (c_m = c̃ = {}, ℓ1 = \
             {}); the run itself decides where in this range each interval falls",
            sig4(d.shortest),
            sig4(d.longest),
            sig4(d.lemma1.sup_bound),
            sig4(d.c_scaled),
            sig4(d.lemma1.ell1)
        ));
        let w = sampling.windows()[0];
        notes.push(if d.chain {
            format!(
                "the plant is a chain of integrators in normal form (f = 0, no time scale of its \
                 own): L stays 1 and the rule samples periodically with period α/ω; any period is \
                 certified, and ω was chosen so that it is the plant file's longest interval T2 = \
                 {}",
                sig4(w.t2())
            )
        } else {
            format!(
                "the plant file's window {w} is not used by this method: the rule picks the \
                 instants, at most every {} (time units of the plant file){}",
                sig4(d.longest),
                if d.longest < w.t2() {
                    " (faster than the file's T2)"
                } else {
                    ""
                }
            )
        });
        notes.push(format!(
            "normal form through output {} of {}: z = O x, z_i = y^(i−1) (zero input), \
             ż = S z + e_n a'z + O B u{}, a = {:?}; condition number of O {} after equilibration \
             ({} as given, limit {}); the design runs in τ = ω t, z̃ = D_ω⁻¹ z, where Assumption 1 \
             holds with the constant c̃ = {}",
            nf.output() + 1,
            plant.outputs(),
            if plant.lipschitz().is_some() {
                " + O G phi(H O⁻¹ z) (triangular)"
            } else {
                ""
            },
            nf.coefficients(),
            sig4(nf.condition()),
            sig4(nf.raw_condition()),
            sig4(CONDITION_LIMIT),
            sig4(d.c_scaled)
        ));
        if d.candidates.len() > 1 {
            notes.push(format!(
                "outputs tried (the best-conditioned is used, the others are not read): {}",
                d.candidates
                    .iter()
                    .map(|c| match &c.outcome {
                        Ok(k) => format!("output {}: condition {}", c.output + 1, sig4(*k)),
                        Err(m) => format!("output {}: {m}", c.output + 1),
                    })
                    .collect::<Vec<_>>()
                    .join("; ")
            ));
        }
        notes.push(format!(
            "Theorem 2 constants: W = diag(1, r, …) with r = {}, p1 = {}, p2 = {}, p3 = {}, p4 = {}, \
             a1 = 1/(2p2p4) = {}, α_m = {}, α = {}, a2 = a2,min(α) = 2n(N1+N2)/(p3p1) = {}, a3 = 2n \
             = {}; ω and α maximise the guaranteed shortest interval",
            d.weight_ratio,
            sig4(d.design.p1()),
            sig4(d.design.p2()),
            sig4(d.design.p3()),
            sig4(d.design.p4()),
            sig4(t.a1()),
            sig4(d.design.alpha_m()),
            sig4(t.alpha()),
            sig4(t.a2()),
            t.a3()
        ));
        notes.push(
            "guarantee (Theorem 2): x̂ → x for every initial condition, noise-free, asymptotically \
             (no rate is stated); disturbance and noise bounds of the plant file are not used. The \
             constants of the proof are very conservative (the paper says so): the range is what \
             Theorem 2 and Lemma 1 guarantee; in a run the intervals usually stay well above the \
             guaranteed shortest one (see --simulate)"
                .into(),
        );
        notes
    }
}
