//! The [`ObserverMethod`] contract for Ferrante et al. (2016): design by Corollary 1 (LMI (41) at
//! the vertices of a polytopic embedding of `e^{Av}`), largest window by the shared search with
//! compiled LMIs re-used across the probes, and simulation of the error system (5).

use std::time::Instant;

use faer::Mat;

use sporadic_model::{
    Check, DesignReport, Gain, Margin, MaxIntervalReport, MethodError, MethodOptions, NamedMatrix,
    NotApplicable, ObserverMethod, Outputs, Plant as ModelPlant, Probe, Proof, ProofOptions,
    Reason, Sampling, SamplingScenario, SamplingWindow, Scenario, SearchEnd, SimulationReport,
    Trajectory, check_simulatable, largest_window_with, power_of_two, significant,
};
use sporadic_sdp::lmi::Normalisation;
use sporadic_sim::{Adversarial, JumpMap, Periodic, SamplingRule, SimOptions, UniformRandom};

/// Candidate intervals of the worst-case sampling scenario's greedy adversary.
const WORST_CASE_GRID: usize = 64;

use crate::design::{Design, DesignOptions, LmiCache};
use crate::error::Error;
use crate::normalise::Coordinates;
use crate::prove::prove_condition12;
use crate::refine::{Refinement, refined, refined_analysis};
use crate::simulation::simulate_error;
use crate::system::Plant;
use crate::verify::{Verification, factor_product};
use crate::window::{probe, probe_options};

const ID: &str = "ferrante2016";

/// Ferrante, Gouaisbaut, Sanfelice & Tarbouriech (2016): observer with a constant jump gain `L`
/// for a linear plant whose output is sampled with every inter-sample time in a window
/// `[T1, T2]`, designed by LMI (41) (Corollary 1) and re-verified on a grid of `[T1, T2]`.
///
/// ```
/// use sporadic_ferrante2016::Ferrante2016;
/// use sporadic_ferrante2016::ObserverMethod;
///
/// let method = Ferrante2016::default(); // the paper's construction (residue embedding, 1 piece)
/// assert_eq!(method.id(), "ferrante2016");
/// assert_eq!(method.design.pieces, 1);
/// // … refined up to 16 pieces when LMI (41) is infeasible on it
/// assert_eq!(method.refinement.max_pieces, 16);
/// ```
#[derive(Debug, Clone, Default)]
pub struct Ferrante2016 {
    /// Options of the design at every window (default [`DesignOptions::default`]: residue
    /// embedding of §4.1 on one piece, LMI (41) in its reduced form, margin problem with every
    /// variable normalised by `‖·‖₂ ≤ 1` and the margin capped at 1, grid check of (12) on 2801 points,
    /// Remark 3 precheck on 1001 points plus the aliasing instants).
    pub design: DesignOptions,
    /// How far the embedding is split when LMI (41) is infeasible on the design's own
    /// ([`crate::refine`]; [`Refinement::none`] for the paper's construction alone).
    pub refinement: Refinement,
}

impl Ferrante2016 {
    /// The crate's plant `(A, C)` of a plant the method applies to.
    fn plant_of(&self, plant: &ModelPlant) -> Result<Plant, MethodError> {
        let c = plant.c().ok_or_else(|| MethodError::InvalidInput {
            method: ID,
            source: "ferrante2016 needs one synchronously sampled output matrix C".into(),
        })?;
        Plant::new(plant.a(), c).map_err(invalid)
    }

    /// The report of a verified design at `window`.
    fn report(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        d: &Design,
        seconds: f64,
    ) -> DesignReport {
        let mut r = DesignReport::certified(self, plant.name(), sampling);
        r.gains.push(Gain::constant(
            "L",
            d.l.as_ref(),
            "jump gain of observer (3): ẑ⁺ = ẑ + L(y − Cẑ) at each sample (the paper's M is C), \
             ẑ' = Aẑ + Bu between samples; the error ε = z − ẑ jumps by ε⁺ = (I − LC)ε (5); \
             L = F⁻¹J (Remark 8)",
        ));
        let cert = &d.certificate;
        r.certificate.push(NamedMatrix::new(
            "P",
            cert.p.as_ref(),
            "Lyapunov matrix of Theorem 1: (12) (I − LC)'e^{A'v}Pe^{Av}(I − LC) − P ≺ 0 for every \
             v ∈ [T1, T2]; V(ε, τ) = ε'e^{A'τ}Pe^{Aτ}ε (13), τ the time to the next sample",
        ));
        if let Some(factor) = &cert.factor {
            r.certificate.push(NamedMatrix::new(
                "R",
                factor.as_ref(),
                "upper-triangular factor of the certificate, P = R'R exactly: the P that the \
                 check of (12) verified (P above is this product rounded to doubles, which for \
                 a condition number near 1e16 no longer determines its smallest eigenvalue)",
            ));
        }
        r.certificate.push(NamedMatrix::new(
            "F",
            cert.f.as_ref(),
            "multiplier of Proposition 1 / LMI (41) (F + F' ≻ 0)",
        ));
        r.certificate.push(NamedMatrix::new(
            "J",
            cert.j.as_ref(),
            "J = FL, the decision variable of LMI (41) (Remark 8)",
        ));
        if let Some(mu) = cert.robust_multiplier {
            r.certificate.push(NamedMatrix::new(
                "mu",
                faer::mat![[mu]].as_ref(),
                "multiplier μ of the robust form of (41) for an embedding with a remainder",
            ));
        }
        r.margin = Some(Margin {
            value: cert.margin,
            definition: margin_definition(&self.design, d),
        });
        r.checks = checks(&self.design, d);
        r.notes.push(format!(
            "LMI (41) at {} vertices of the {} embedding of e^(Av), v in {} ({} piece(s)); {} \
             interior-point iterations, {} decision scalars",
            d.embedding.vertex_count(),
            match (d.embedding.method(), &self.design.embedding) {
                (sporadic_embed::Method::Residue { .. }, _) => "residue (§4.1)",
                (sporadic_embed::Method::Taylor { .. }, crate::EmbeddingMethod::Taylor(_)) =>
                    "Taylor",
                (sporadic_embed::Method::Taylor { .. }, _) =>
                    "Taylor (fallback: the residue box of §4.1 certified no form)",
            },
            SamplingWindow::new(
                d.embedding.interval().t1() * d.scaling.time,
                d.embedding.interval().t2() * d.scaling.time
            )
            .map_or_else(|_| String::from("[T1, T2]"), |w| w.to_string()),
            d.embedding.pieces().len(),
            d.stats.iterations,
            d.stats.decision_scalars,
        ));
        if !d.embedding.containment().is_guaranteed() {
            r.notes.push(format!(
                "the embedding's containment of e^(Av) is not proven ({:?}): the grid check of \
                 (12) is the evidence for the certificate",
                d.embedding.containment()
            ));
        }
        if plant.bounds().is_some() {
            r.notes.push(
                "the disturbance/noise bounds of the plant are not used: the design is for the \
                 noise-free error (5); by Theorem 2 the same (P, L) gives ISS with respect to \
                 measurement noise"
                    .into(),
            );
        }
        match d.scaling.coordinates {
            _ if d.scaling.certificate => r.notes.push(format!(
                "no form of the problem certified the window by its own solve: LMI (41) was \
                 solved again in the coordinates x'' = Tx in which the Lyapunov matrix of an \
                 undecided solve (margin below its verification threshold) of the {} form is \
                 the identity up to scale (T = RT0, T0 that form's change of coordinates, \
                 R'R = P'/lambda_max(P')), time unit k = {} in the plant's time unit, the \
                 plant embedded again in those \
                 coordinates; L, P, F, J mapped back with T and (12) re-verified on the user's \
                 data",
                match d.scaling.coordinates {
                    Coordinates::Given => "given",
                    Coordinates::Gramian => "Gramian",
                    Coordinates::Diagonal => "diagonal",
                    Coordinates::Modal => "modal",
                },
                significant(d.scaling.time),
            )),
            Coordinates::Given => {
                if d.scaling.output.iter().any(|s| *s != 1.0) {
                    r.notes.push(format!(
                        "LMI (41) solved with each output in units of its largest coefficient \
                         in C (y' = Sy, S = diag{}), so that the verdict does not depend on the \
                         output units; L and J mapped back (L = L'S, J = J'S)",
                        power_words(&d.scaling.output),
                    ));
                }
            }
            Coordinates::Gramian => r.notes.push(format!(
                "LMI (41) solved on the normalised problem: time unit k = {} in the plant's \
                 time unit (T2, or T1 plus \
                 the decay horizon 72/|α| of A when the window is longer), state coordinates \
                 x' = Tx in which the observability Gramian over one time unit is the identity, output scaling y' = Sy with S = diag{}; L, P, F, J mapped back \
                 (L = T^-1 L' S, P = T'P'T, F = T'F'T, J = T'J'S) and (12) re-verified on the \
                 user's data",
                significant(d.scaling.time),
                power_words(&d.scaling.output),
            )),
            Coordinates::Modal => r.notes.push(format!(
                "LMI (41) solved on the normalised problem in modal coordinates: time unit k = \
                 {} in the plant's time unit (as for the Gramian form), state coordinates \
                 x' = Tx in which A is block diagonal with normal blocks [[s, w], [-w, s]] (the \
                 real eigenbasis of the Gramian normal form, one unit vector per mode), output \
                 scaling y' = Sy with S = diag{}; L, P, F, J mapped back (L = T^-1 L' S, \
                 P = T'P'T, F = T'F'T, J = T'J'S) and (12) re-verified on the user's data",
                significant(d.scaling.time),
                power_words(&d.scaling.output),
            )),
            Coordinates::Diagonal => r.notes.push(format!(
                "LMI (41) solved on the normalised problem: time unit k = {} in the plant's \
                 time unit (T2, or T1 plus \
                 the decay horizon 72/|α| of A when the window is longer), state scaling x' = Dx with D = diag{} (powers of two), output scaling y' = Sy with S = diag{}; \
                 L, P, F, J mapped back (L = D^-1 L' S, P = D'P'D, F = D'F'D, J = D'J'S) and (12) \
                 re-verified on the user's data",
                significant(d.scaling.time),
                power_words(
                    &d.scaling
                        .state
                        .diagonal()
                        .column_vector()
                        .iter()
                        .copied()
                        .collect::<Vec<_>>()
                ),
                power_words(&d.scaling.output),
            )),
        }

        r.notes.push(if d.stats.status.is_accepted() {
            "L is not unique: any gain satisfying (12) solves Problem 1; this one is the first \
             point of the margin solve of LMI (41) at which every vertex LMI verified (a window \
             search needs a certificate, not the largest margin, and stops the solve there)"
                .into()
        } else {
            "L is not unique: any gain satisfying (12) solves Problem 1; this one maximises the \
             margin of LMI (41)"
                .into()
        });
        r.seconds = seconds;
        r
    }

    /// A report without design for the verdict `reason`.
    fn failed(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        reason: Reason,
        seconds: f64,
    ) -> DesignReport {
        let mut r = DesignReport::without_design(self, plant.name(), Some(sampling), reason);
        r.seconds = seconds;
        r
    }
}

/// Bad input, with the crate's error as the source.
fn invalid(e: Error) -> MethodError {
    MethodError::InvalidInput {
        method: ID,
        source: Box::new(e),
    }
}

/// A converged search whose first failing `T2` is a refusal of LMI (41) with a rounding level
/// `τ` above the margin of the design at the largest certified `T2` (`thresholds`: `(T2, τ)` of
/// every refusal) did not resolve its bracket: a margin of the size that certified the window
/// below would not have been seen at that level, so the refusal is no evidence that the
/// window above is not certifiable. The search is then undecided (its largest certified `T2` a
/// lower bound). At such a bracket the margins of (41) are at the limit of double precision and
/// the verdicts near it need not be monotone in `T2` (an unstable pitch short period in
/// milliseconds and degrees: certified at 13 395 ms with margin `2.6e-10`, refused at 13 428 ms
/// at `τ = 4.1e-6`, certified again at 14 000 ms).
fn resolve_bracket(report: &mut MaxIntervalReport, thresholds: &[(f64, f64)]) {
    if report.search_end != Some(SearchEnd::Converged)
        || !matches!(
            report.first_failure_reason(),
            Some(Reason::InfeasibleLmi { .. })
        )
    {
        return;
    }
    let (Some(fail), Some(margin)) = (
        report.first_failing_t2,
        report
            .design
            .as_ref()
            .and_then(|d| d.margin.as_ref())
            .map(|m| m.value),
    ) else {
        return;
    };
    let Some(&(_, tau)) = thresholds.iter().rev().find(|(t2, _)| *t2 == fail) else {
        return;
    };
    if margin <= tau {
        report.search_end = Some(SearchEnd::Undecided);
        report.reason = Some(Reason::NumericalFailure {
            message: format!(
                "the probe at T2 = {} was not decided: it was refused with no verifiable margin \
                 at the rounding level {tau:.3e} of LMI (41), above the margin {margin:.3e} that \
                 certified the window below it, so a margin of that size would not have been \
                 seen there (the limit of double precision); the largest certified T2 is a \
                 lower bound",
                significant(fail)
            ),
        });
    }
}

/// An error that is not a verdict on the plant: bad input, or a failure that is neither.
fn not_a_verdict(e: Error) -> MethodError {
    if e.is_input() {
        invalid(e)
    } else {
        MethodError::Numerical {
            method: ID,
            source: Box::new(e),
        }
    }
}

/// What the margin of a design is, with the normalisation of `options`.
fn margin_definition(options: &DesignOptions, d: &Design) -> String {
    let robust = d.certificate.robust_multiplier.is_some();
    // The order of the vertex LMIs tells the form solved (a normal form is solved in the
    // reduced form whatever `options.form`, see `crate::design`).
    let reduced = d.size.block_size < if robust { 4 } else { 3 } * d.l.nrows();
    let form = match (robust, reduced) {
        (true, false) => "the robust 4n × 4n form of (41) (embedding with a remainder)",
        (true, true) => {
            "the robust reduced 3n × 3n form of (41) (embedding with a remainder, Schur \
             complement of the robust form with respect to its (3,3) block −P)"
        }
        (false, true) => "the reduced 2n × 2n form (39) of (41)",
        (false, false) => "the 3n × 3n matrix of (41) as printed",
    };
    let norm = match options.lmi.default_normalisation {
        Normalisation::Norm(r) => format!(
            "‖P‖₂ ≤ {r}, ‖F‖₂ ≤ {r}, ‖J‖₂ ≤ {r}{}",
            if robust {
                format!(", |μ| ≤ {r}")
            } else {
                String::new()
            }
        ),
        Normalisation::Trace(c) => format!("tr P ≤ {c} (F, J unbounded)"),
        Normalisation::Free => "no bound on P, F, J".into(),
    };
    let which = if d.stats.status.is_accepted() {
        "the t of an interior-point iterate that is already a certificate (not maximised: a \
         window search stops the solve at the first such iterate, and a design returns the last \
         one when its optimal point is none) with"
    } else {
        "the largest t with"
    };
    format!(
        "LMI (41) margin: {which} Φ_i(P, F, J) ⪯ −t·I at every vertex X_i of the \
         polytopic embedding of e^(Av), v in [T1, T2] (Φ_i is {form}), under the normalisation \
         {norm} (spectral norms) and the cap t ≤ {}; (41) is homogeneous, so t > 0 iff (41) is \
         strictly feasible, and t is the slack of the certificate relative to that scale",
        significant(options.lmi.margin_cap)
    )
}

/// A matrix of a report (`found`), or bad input naming what is missing.
fn named(found: Option<Mat<f64>>, name: &str, what: &str) -> Result<Mat<f64>, MethodError> {
    found.ok_or_else(|| MethodError::InvalidInput {
        method: ID,
        source: format!("the design report has no {what} {name}").into(),
    })
}

/// The grid checks of (12) and of the Schur property of a verification.
fn verification_checks(v: &Verification, tol: f64) -> Vec<Check> {
    vec![
        Check {
            what: "condition (12) of Theorem 1 on a v-grid, independent of the embedding".into(),
            how: format!(
                "the contraction of e^(Av)(I − LC) in the norm of P, γ(v) = ‖R e^(Av)(I − LC) \
                 R⁻¹‖₂² with P = R'R ({}; (12) iff γ < 1), on {} equally spaced v in \
                 [T1, T2] plus a golden-section refinement (60 steps) of the worst cell, e^(Av) \
                 in f64, a point it does not decide again with a fresh exponential, then in \
                 double-double arithmetic; passes when γ − 1 + allowance < −{tol:e} at every \
                 point, the allowance for rounding being {} times a first-order estimate \
                 (products, the exponential's error){} ({:.1e} at the worst point, relative \
                 value γ − 1 = {:.3e} at v = {:.6}; the value is \
                 λmax((I − LC)'e^(A'v)Pe^(Av)(I − LC) − P) there)",
                if v.factor_given {
                    "R the certificate's factor, P = R'R exactly"
                } else {
                    "R the Cholesky factor of P"
                },
                v.grid_points,
                crate::verify::SAFETY,
                if v.factor_given {
                    String::new()
                } else {
                    format!(
                        " plus {} times the measured effect of the residual of the Cholesky \
                         factor, formed in double-double",
                        crate::verify::MEASURED
                    )
                },
                v.rounding,
                v.relative_max_eigenvalue,
                v.max_eigenvalue_at
            ),
            value: Some(v.max_eigenvalue),
            passed: v.condition12_holds,
        },
        Check {
            what: "e^(Av)(I − LC) Schur for every v in [T1, T2] (Remark 3)".into(),
            how: format!(
                "spectral radius on the same grid plus refinement; passes when below 1 − {tol:e} \
                 (worst at v = {:.6})",
                v.max_spectral_radius_at
            ),
            value: Some(v.max_spectral_radius),
            passed: v.schur_holds,
        },
    ]
}

/// Every re-verification of a design.
fn checks(options: &DesignOptions, d: &Design) -> Vec<Check> {
    let det = &d.detectability;
    let v = &d.verification;
    let tol = options.verify.tolerance;
    let mut out = vec![Check {
        what: "necessary condition of Remark 3: (e^(Av), C) detectable for every v in [T1, T2]"
            .into(),
        how: format!(
            "PBH test at {} values of v ({} grid points plus {} aliasing instants of the \
             non-decaying modes), eigenvalues of e^(Av) by spectral mapping; rank tolerance {:e} \
             on the normalised PBH matrix, |μ| ≥ 1 − {:e} counted as non-decaying; the value is \
             the smallest PBH margin (+inf: A Hurwitz)",
            det.points_tested,
            options.detectability.grid_points.max(1),
            det.aliasing_instants.len(),
            options.detectability.pbh.rank_tol,
            options.detectability.pbh.unit_circle_tol,
        ),
        value: det.min_margin.is_finite().then_some(det.min_margin),
        passed: true,
    }];
    // A margin at or below the solver's threshold was accepted by the rounding-based vertex
    // test of the design (`strictly_negative`), and the text says so.
    let acceptance = match d.stats.margin_threshold {
        _ if d.size.imposed < d.size.lmi_count => format!(
            "imposed at {} of the vertices, those found to bind in earlier solves (constraint \
             generation, not in the paper); accepted because every vertex LMI's largest \
             eigenvalue at the returned point is below −τ, τ bounding rounding and the \
             embedding's reconstruction error and remainder",
            d.size.imposed
        ),
        Some(t) if d.certificate.margin <= t => format!(
            "the margin is below the solver's verification threshold {t:.2e} (relative to the \
             summands of the LMI solved); accepted because every vertex LMI's largest eigenvalue at \
             the returned point is below −τ, τ bounding rounding and the embedding's \
             reconstruction error and remainder"
        ),
        Some(t) => format!(
            "every constraint's eigenvalues re-computed at the returned point, margin above the \
             verification threshold {t:.2e}"
        ),
        None => "every constraint's eigenvalues re-computed at the returned point".into(),
    };
    out.push(Check {
        what: "LMI (41) at the vertices of the embedding, re-verified at the solver's point".into(),
        how: format!(
            "{} vertex LMIs of order {}; interior point {} after {} iterations (relative gap \
             {:.1e}); {acceptance}",
            d.size.lmi_count,
            d.size.block_size,
            d.stats.status.as_str(),
            d.stats.iterations,
            d.stats.rel_gap,
        ),
        value: Some(d.certificate.margin),
        passed: true,
    });
    out.push(Check {
        what: "polytopic embedding contains e^(Av) for every v in [T1, T2] (hypothesis of \
               Corollary 1)"
            .into(),
        how: format!(
            "{:?}; remainder bound {:.3e}",
            d.embedding.containment(),
            d.embedding.remainder_bound()
        ),
        value: None,
        passed: !matches!(
            d.embedding.containment(),
            sporadic_embed::Containment::NotGuaranteed { .. }
        ),
    });
    out.extend(verification_checks(v, tol));
    out
}

impl ObserverMethod for Ferrante2016 {
    fn id(&self) -> &'static str {
        ID
    }

    fn citation(&self) -> &'static str {
        "F. Ferrante, F. Gouaisbaut, R. G. Sanfelice, S. Tarbouriech (2016), State estimation of \
         linear systems in the presence of sporadic measurements, Automatica 73, 101–109"
    }

    fn summary(&self) -> &'static str {
        "constant-gain jump observer for a linear plant with every inter-sample time in [T1, T2], \
         by LMI (41) over a polytopic embedding of e^(Av)"
    }

    fn observer(&self) -> &'static str {
        "between samples ẑ' = Aẑ + Bu; at a sample ẑ⁺ = ẑ + L(y − Cẑ) (observer (3), the paper's \
         M is C); error ε = z − ẑ: ε' = Aε, ε⁺ = (I − LC)ε (5)"
    }

    fn applies(&self, plant: &ModelPlant, sampling: &Sampling) -> Result<(), NotApplicable> {
        if plant.lipschitz().is_some() {
            return Err(NotApplicable::unsupported(
                ID,
                "the plant has a Lipschitz nonlinearity; Ferrante et al. (2016) is for linear \
                 plants (use etienne2017)",
            ));
        }
        if let Outputs::RoundRobin(_) = plant.output_structure() {
            return Err(NotApplicable::unsupported(
                ID,
                "the plant has round-robin sensors; Ferrante et al. (2016) samples one output \
                 matrix at once (use sferlazza2021)",
            ));
        }
        if let Sampling::RoundRobin(_) = sampling {
            return Err(NotApplicable::unsupported(
                ID,
                "the sampling is round-robin (one window per sensor); Ferrante et al. (2016) \
                 needs one window [T1, T2] for all outputs",
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
        if let Err(na) = self.applies(plant, sampling) {
            return Ok(DesignReport::without_design(
                self,
                plant.name(),
                Some(sampling),
                na.reason,
            ));
        }
        let Sampling::Synchronous(window) = sampling else {
            unreachable_round_robin()?
        };
        let p = self.plant_of(plant)?;
        let mut cache = LmiCache::default();
        match refined(&p, window, &self.design, &mut cache, &self.refinement) {
            Ok(d) => Ok(self.report(plant, sampling, &d, start.elapsed().as_secs_f64())),
            Err(e) => match e.reason() {
                Some(r) => Ok(self.failed(plant, sampling, r, start.elapsed().as_secs_f64())),
                None => Err(not_a_verdict(e)),
            },
        }
    }

    /// The shared [`largest_window_with`] with a probe that re-solves compiled LMIs (41) (see
    /// [`crate::window`]), reported exactly as
    /// [`sporadic_model::default_largest_window`] reports it.
    fn largest_window(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        limit: f64,
        options: &MethodOptions,
        progress: &mut dyn FnMut(&Probe),
    ) -> Result<MaxIntervalReport, MethodError> {
        if let Err(na) = self.applies(plant, sampling) {
            return Ok(MaxIntervalReport::without_search(
                ID,
                plant.name(),
                Some(sampling),
                Some(limit),
                na.reason,
            ));
        }
        let p = self.plant_of(plant)?;
        self.design.validate().map_err(invalid)?;
        let options_of_probes = probe_options(&self.design);
        let mut cache = LmiCache::for_search();
        // The rounding level of every refusal of LMI (41), by its T2.
        let mut thresholds: Vec<(f64, f64)> = Vec::new();
        let mut run = |s: &Sampling| -> Result<DesignReport, MethodError> {
            let probe_start = Instant::now();
            let Sampling::Synchronous(window) = s else {
                unreachable_round_robin()?
            };
            let (v, d) = probe(&p, window, &options_of_probes, &mut cache, &self.refinement)
                .map_err(not_a_verdict)?;
            if let Err(Some(tau)) = d {
                thresholds.push((window.t2(), tau));
            }
            Ok(match (d, v.reason) {
                (Ok(d), _) => self.report(plant, s, &d, probe_start.elapsed().as_secs_f64()),
                (Err(_), Some(reason)) => {
                    DesignReport::without_design(self, plant.name(), Some(s), reason)
                }
                (Err(_), None) => DesignReport::without_design(
                    self,
                    plant.name(),
                    Some(s),
                    Reason::NumericalFailure {
                        message: "the probe returned neither a design nor a reason".into(),
                    },
                ),
            })
        };
        let mut report = largest_window_with(
            self,
            plant,
            sampling,
            limit,
            &options.search,
            options,
            progress,
            &mut run,
        )?;
        resolve_bracket(&mut report, &thresholds);
        let embedding_limit = report.search_end == Some(SearchEnd::Converged)
            && matches!(
                report.first_failure_reason(),
                Some(Reason::InfeasibleLmi { .. })
            );
        if let (true, Some(fail), Some(d)) = (
            embedding_limit,
            report.first_failing_t2,
            report.design.as_mut(),
        ) {
            d.notes.push(format!(
                "the search ends where LMI (41) on the polytopic embedding of e^(Av) stops being \
                 verifiably feasible (T2 = {}): that is the limit of Corollary 1's sufficient \
                 condition on this embedding, not necessarily a property of the plant; \
                 condition (12) of Theorem 1 may hold on longer windows (an embedding box can \
                 contain non-contracting matrices, e.g. for a lightly damped mode that no output \
                 sees); check a gain on a longer window with `verify --prove`",
                significant(fail)
            ));
        }
        Ok(report)
    }

    /// Proves Theorem 1's hypotheses for the report's `(P, L)` on its window in interval
    /// arithmetic ([`prove_condition12`]).
    fn prove(
        &self,
        plant: &ModelPlant,
        design: &DesignReport,
        options: &ProofOptions,
    ) -> Result<Proof, MethodError> {
        let p = self.plant_of(plant)?;
        let window = design.window.ok_or_else(|| MethodError::InvalidInput {
            method: ID,
            source: "the design report has no window [T1, T2]".into(),
        })?;
        let l = named(design.gain("L").map(Gain::to_mat), "L", "gain")?;
        let pm = named(
            design
                .certificate
                .iter()
                .find(|m| m.name == "P")
                .map(NamedMatrix::to_mat),
            "P",
            "certificate matrix",
        )?;
        prove_condition12(&p, &window, l.as_ref(), pm.as_ref(), options).map_err(not_a_verdict)
    }

    /// Checks a user's gain `L` on `sampling`: with the given `P` when there is one (the grid
    /// check of (12) and of the Schur property, as a design is checked), else with the `P` of
    /// LMI (41) for the fixed gain (`J = FL`, margin maximisation, [`crate::analyse`]).
    fn verify(
        &self,
        plant: &ModelPlant,
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
        let Sampling::Synchronous(window) = sampling else {
            unreachable_round_robin()?
        };
        let p = self.plant_of(plant)?;
        let l = gains
            .iter()
            .find(|g| g.name == "L")
            .map(Gain::to_mat)
            .ok_or_else(|| MethodError::InvalidInput {
                method: ID,
                source: format!(
                    "ferrante2016 needs the gain L (n × q); the gains given are [{}]",
                    gains
                        .iter()
                        .map(|g| g.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
                .into(),
            })?;
        p.check_gain(l.as_ref()).map_err(invalid)?;
        let named_matrix = |name: &str| {
            certificate
                .iter()
                .find(|m| m.name == name)
                .map(NamedMatrix::to_mat)
        };
        // A factor `R` (as a design reports it) is the certificate `P = R'R` itself, and takes
        // the place of a `P` given with it (that `P` is the product rounded).
        let given_factor = named_matrix("R");
        if let Some(rf) = &given_factor {
            p.check_lyapunov_factor(rf.as_ref()).map_err(invalid)?;
        }
        let given_p = match (&given_factor, named_matrix("P")) {
            (Some(rf), given) => {
                let product = factor_product(rf.as_ref());
                if let Some(pm) = given {
                    p.check_lyapunov_matrix(pm.as_ref()).map_err(invalid)?;
                    let off = (&pm - &product).norm_max();
                    if !(off <= 1e-10 * product.norm_max()) {
                        return Err(MethodError::InvalidInput {
                            method: ID,
                            source: format!(
                                "the certificate gives P and its factor R, and P differs from \
                                 R'R by {off:.3e} (largest entry; P has largest entry {:.3e}): \
                                 give one of them",
                                product.norm_max()
                            )
                            .into(),
                        });
                    }
                }
                Some(product)
            }
            (None, given) => given,
        };
        let (pm, extra, found) = match given_p {
            Some(pm) => {
                p.check_lyapunov_matrix(pm.as_ref()).map_err(invalid)?;
                (pm, Vec::new(), false)
            }
            None => {
                match refined_analysis(&p, window, l.as_ref(), &self.design, &self.refinement) {
                    Ok(an) => match an.certificate {
                        Some(c) => (
                            c.p,
                            vec![
                                NamedMatrix::new("F", c.f.as_ref(), "multiplier of LMI (41)"),
                                NamedMatrix::new("J", c.j.as_ref(), "J = FL in LMI (41)"),
                            ],
                            true,
                        ),
                        None => {
                            let reason = Reason::InfeasibleLmi {
                                message: format!(
                                    "LMI (41) with the given L fixed (J = FL) has no P with a \
                                     verifiable margin on the {} vertices of the embedding \
                                     (maximal margin {}); Corollary 1 is only sufficient",
                                    an.embedding.vertex_count(),
                                    an.margin
                                        .map_or_else(|| "none".into(), sporadic_model::significant)
                                ),
                            };
                            return Ok(self.failed(
                                plant,
                                sampling,
                                reason,
                                start.elapsed().as_secs_f64(),
                            ));
                        }
                    },
                    Err(e) => {
                        return match e.reason() {
                            Some(r) => {
                                Ok(self.failed(plant, sampling, r, start.elapsed().as_secs_f64()))
                            }
                            None => Err(not_a_verdict(e)),
                        };
                    }
                }
            }
        };
        let v = match &given_factor {
            Some(rf) => {
                crate::verify_factor(&p, window, l.as_ref(), rf.as_ref(), &self.design.verify)
            }
            None => crate::verify(&p, window, l.as_ref(), pm.as_ref(), &self.design.verify),
        }
        .map_err(not_a_verdict)?;
        let tol = self.design.verify.tolerance;
        let mut r = if v.passed() {
            DesignReport::certified(self, plant.name(), sampling)
        } else {
            let e = crate::design::verification_failed(&v, &self.design.verify);
            let mut r = DesignReport::without_design(
                self,
                plant.name(),
                Some(sampling),
                e.reason().unwrap_or(Reason::VerificationFailed {
                    tau: None,
                    message: e.to_string(),
                }),
            );
            r.checks = verification_checks(&v, tol);
            r.seconds = start.elapsed().as_secs_f64();
            return Ok(r);
        };
        r.gains.push(Gain::constant(
            "L",
            l.as_ref(),
            "jump gain of observer (3), given by the user: ẑ⁺ = ẑ + L(y − Cẑ) at each sample",
        ));
        r.certificate.push(NamedMatrix::new(
            "P",
            pm.as_ref(),
            if found {
                "Lyapunov matrix of Theorem 1 found for the given L by LMI (41) with J = FL"
            } else {
                "Lyapunov matrix of Theorem 1, given by the user"
            },
        ));
        if let Some(rf) = &given_factor {
            r.certificate.push(NamedMatrix::new(
                "R",
                rf.as_ref(),
                "upper-triangular factor of P given by the user, P = R'R exactly: the P checked",
            ));
        }
        r.certificate.extend(extra);
        r.margin = Some(Margin {
            value: -v.relative_max_eigenvalue,
            definition: "1 − max γ(v) over the v-grid: the contraction of e^(Av)(I − LC) in the norm of P, γ(v) = ‖R e^(Av)(I − LC) R⁻¹‖₂² with P = R'R, i.e. −λmax(P^(−½) Q(v) P^(−½)) with Q(v) the left-hand side of (12); the same in every state coordinates and for every scale of P"
                .into(),
        });
        r.checks = verification_checks(&v, tol);
        r.notes.push(
            "gain checked as given (sporadic verify): no design was run; the checks are those of a design's re-verification"
                .into(),
        );
        r.seconds = start.elapsed().as_secs_f64();
        Ok(r)
    }

    /// The error system (5) with the report's gain `L`: `ε' = Aε` between samples,
    /// `ε⁺ = (I − LC)ε` at the samples. Defaults: `ε(0) = (1, …, 1)`, horizon `30·T2`.
    fn simulate(
        &self,
        plant: &ModelPlant,
        design: &DesignReport,
        scenario: &Scenario,
    ) -> Result<Trajectory, MethodError> {
        let unavailable = |why: String| MethodError::SimulationUnavailable { method: ID, why };
        check_simulatable(ID, design)?;
        let window = design
            .window
            .ok_or_else(|| unavailable("the report has no single sampling window".into()))?;
        let l = design
            .gain("L")
            .ok_or_else(|| unavailable("the report has no gain L".into()))?
            .to_mat();
        let p = self.plant_of(plant)?;
        p.check_gain(l.as_ref()).map_err(invalid)?;
        let n = p.n();
        let eps0 = scenario
            .initial_error
            .clone()
            .unwrap_or_else(|| vec![1.0; n]);
        if eps0.len() != n {
            return Err(invalid(
                sporadic_linalg::InputError::mismatch(
                    "entries of the initial error",
                    n,
                    eps0.len(),
                )
                .into(),
            ));
        }
        let horizon = scenario.horizon.unwrap_or(30.0 * window.t2());
        if !(horizon.is_finite() && horizon > 0.0) {
            return Err(invalid(
                sporadic_linalg::InputError::parameter(
                    "horizon",
                    horizon,
                    "must be a positive finite time",
                )
                .into(),
            ));
        }
        let sim_err = |e: sporadic_sim::SimError| not_a_verdict(e.into());
        let (mut rule, sampling_words): (Box<dyn SamplingRule>, String) = match scenario.sampling {
            SamplingScenario::Uniform { seed } => (
                Box::new(UniformRandom::new(window.t1(), window.t2(), seed).map_err(sim_err)?),
                format!("intervals uniform in {window} (seed {seed})"),
            ),
            SamplingScenario::PeriodicT1 => (
                Box::new(Periodic::new(window.t1()).map_err(sim_err)?),
                format!("periodic, every interval T1 = {}", significant(window.t1())),
            ),
            SamplingScenario::PeriodicT2 => (
                Box::new(Periodic::new(window.t2()).map_err(sim_err)?),
                format!("periodic, every interval T2 = {}", significant(window.t2())),
            ),
            SamplingScenario::WorstCase => {
                let cert = design
                    .certificate
                    .iter()
                    .find(|m| m.name == "P")
                    .ok_or_else(|| unavailable("the report has no certificate P".into()))?
                    .to_mat();
                let jump = Mat::<f64>::identity(n, n) - &l * p.c();
                let v = Box::new(move |e: &[f64]| {
                    let e = faer::ColRef::from_slice(e);
                    (e.transpose() * &cert * e).abs()
                });
                (
                    Box::new(
                        Adversarial::new(
                            p.a(),
                            JumpMap::Matrix(jump),
                            v,
                            window.t1(),
                            window.t2(),
                            WORST_CASE_GRID,
                        )
                        .map_err(sim_err)?,
                    ),
                    format!(
                        "worst case: each interval of a {WORST_CASE_GRID}-point grid of {window} \
                         chosen to maximise ε⁺ᵀPε⁺ just after the next sample (greedy per-sample \
                         adversary, P the certificate)"
                    ),
                )
            }
        };
        let arc = simulate_error(
            &p,
            l.as_ref(),
            rule.as_mut(),
            &eps0,
            &SimOptions::new(horizon),
        )
        .map_err(not_a_verdict)?;
        let norm = arc.norms();
        let signals = (0..n)
            .map(|k| {
                arc.component(k)
                    .map(|x| (format!("ε_{}", k + 1), x))
                    .map_err(sim_err)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let initial_error = norm.first().copied().unwrap_or(f64::NAN);
        let final_error = norm.last().copied().unwrap_or(f64::NAN);
        let samples = arc.num_jumps();
        Ok(Trajectory {
            quantity: "estimation error ε = z − ẑ of the error system (5)".into(),
            t: arc.times().to_vec(),
            j: arc.jump_counters().to_vec(),
            signals,
            norm,
            report: SimulationReport {
                setup: format!(
                    "error system (5) with the designed L, ε(0) = {}, |ε(0)| = {:.4}, \
                     {sampling_words}, horizon {} s",
                    vector_words(&eps0),
                    initial_error,
                    significant(horizon)
                ),
                samples,
                initial_error,
                final_error,
                result: format!(
                    "{samples} samples, |ε| at the end = {final_error:.3e} ({:.3e} of |ε(0)|)",
                    final_error / initial_error
                ),
                settling_time: None,
                ends_early_at: None,
                figure: None,
            },
        })
    }
}

/// `(x1, …, xn)` with `(1, ..., 1)` abbreviated, each entry with [`significant`] digits.
fn vector_words(x: &[f64]) -> String {
    words(x, significant)
}

/// [`vector_words`] for power-of-two scalings: an entry `2^k` other than 1 as `2^k` (exact and
/// short, e.g. `2^-17` instead of `0.00000762939453125`).
fn power_words(x: &[f64]) -> String {
    words(x, |v| power_of_two(v).unwrap_or_else(|| significant(v)))
}

fn words(x: &[f64], word: impl Fn(f64) -> String) -> String {
    if x.len() > 3 && x.iter().all(|v| *v == x[0]) {
        let w = word(x[0]);
        return format!("({w}, …, {w})");
    }
    let parts: Vec<String> = x.iter().map(|v| word(*v)).collect();
    format!("({})", parts.join(", "))
}

/// The error for a round-robin sampling past [`ObserverMethod::applies`] (cannot happen: it is
/// rejected there).
fn unreachable_round_robin<T>() -> Result<T, MethodError> {
    Err(MethodError::InvalidInput {
        method: ID,
        source: "ferrante2016 needs one sampling window [T1, T2]".into(),
    })
}
