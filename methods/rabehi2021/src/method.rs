//! The [`ObserverMethod`] contract for Rabehi et al. (2021): design by Proposition 1 (BMI (44) at
//! the vertices of a Taylor polytope of `e^{Āμ}`, solved by the convex restriction, alternation
//! and sequential convex steps of [`crate::synthesis`]) with the Theorem 1 re-verification for
//! the implemented `Γ(L)` (Remark 6); largest window by the shared search, capped by the
//! necessary condition of [`crate::window`]; simulation of the interval observer with random
//! admissible disturbance, noise and sampling.

use std::time::Instant;

use faer::{Mat, MatRef};

use sporadic_linalg::balance::{
    balance_a, balance_b, balance_c, complete_balancing_scales, unbalance_a, unbalance_gain,
};

use sporadic_model::{
    Check, DesignReport, Gain, Margin, MaxIntervalReport, MethodError, MethodOptions, NamedMatrix,
    NotApplicable, ObserverMethod, Outputs, Plant as ModelPlant, Probe, Proof, ProofOptions,
    Reason, Sampling, SamplingScenario, SamplingWindow, Scenario, SimulationReport, Trajectory,
    check_simulatable, default_largest_window, significant,
};

use crate::analysis::{Analysis, analyse};
use crate::error::Error;
use crate::ipr::{MetzlerDecomposition, gamma_of_gain};
use crate::observer::IntervalObserver;
use crate::prove::{prove_design, read_given};
use crate::simulation::{Disturbance, Noise, Scenario as SimScenario, simulate_interval};
use crate::synthesis::{Design, DesignStatus, SynthesisOptions, synthesise};
use crate::system::{Bounds, Plant};
use crate::verify::{GridCheck, verify_theorem1};
use crate::width::WidthDynamics;
use crate::window::{beyond_cap, necessary_limit};

const ID: &str = "rabehi2021";

/// Grid points per maximum over `μ` of the guaranteed width bound reported in the notes.
const WIDTH_POINTS: usize = 200;

/// Largest number of scan steps of the necessary-condition pre-check of
/// [`Rabehi2021::largest_window`] (a coarser scan only loosens the cap).
const NECESSARY_SCAN_STEPS: usize = 20_000;

/// Largest number of recorded flow points of a simulation.
const MAX_RECORDED: f64 = 20_000.0;

/// Rabehi, Meslem, El Amraoui & Ramdani (2021): interval impulsive observer for a linear plant
/// `ẋ = Ax + Bu + d`, `y(t_k) = Cx(t_k) + v(t_k)` with bounded disturbance and noise
/// (`|d_i| ≤ d̄_i`, `|v_j| ≤ v̄_j`, from the plant's bounds), sampled with every inter-sample time
/// in a window `[T1, T2]`. The gain `L` is designed by Proposition 1 (BMI (44)) and certified by
/// Theorem 1 for the implemented jump matrix `Γ(L)` (polytope SDP plus a dense μ-grid check).
///
/// ```
/// use sporadic_rabehi2021::Rabehi2021;
/// use sporadic_rabehi2021::ObserverMethod;
///
/// let method = Rabehi2021::default(); // split Taylor polytope, full pipeline
/// assert_eq!(method.id(), "rabehi2021");
/// assert_eq!(method.synthesis.max_alternations, 12);
/// ```
#[derive(Debug, Clone, Default)]
pub struct Rabehi2021 {
    /// Options of the Proposition 1 pipeline at every window (default
    /// [`SynthesisOptions::default`]: Taylor polytope of `e^{Āμ}` split into pieces with
    /// `‖Ā‖₂h ≤ 0.5` and order chosen for a remainder `≤ 1e-9`; `1e-3·I ⪯ P ⪯ 1e3·I`,
    /// `G1, G2 ≤ 1e3` entrywise; convex restriction `F = I`, then up to 12 alternation cycles and
    /// 12 sequential convex steps, stall tolerance `1e-4`; Theorem 1 re-verification with a split
    /// polytope and a μ-grid of 1001 points refined up to 65 537).
    pub synthesis: SynthesisOptions,
}

/// A crate error that is bad input.
fn invalid(e: Error) -> MethodError {
    MethodError::InvalidInput {
        method: ID,
        source: Box::new(e),
    }
}

/// The message of an error with its chain of causes.
fn chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut cur = e.source();
    while let Some(c) = cur {
        let m = c.to_string();
        if !s.contains(&m) {
            s.push_str(": ");
            s.push_str(&m);
        }
        cur = c.source();
    }
    s
}

/// A crate error of the design: a verdict on the plant (`Ok(reason)`) or a failure that is not
/// one (`Err`).
fn verdict_of(e: Error) -> Result<Reason, MethodError> {
    use sporadic_sdp::lmi::ModelError;
    match e {
        Error::SolverInconclusive { .. } | Error::Lmi(ModelError::Solver(_)) => {
            Ok(Reason::SolverInconclusive { message: chain(&e) })
        }
        Error::Linalg(_)
        | Error::Embed(_)
        | Error::SingularABar { .. }
        | Error::Lmi(ModelError::NonFinite { .. } | ModelError::Linalg(_)) => {
            Ok(Reason::NumericalFailure { message: chain(&e) })
        }
        Error::Input(_)
        | Error::InvalidBounds { .. }
        | Error::InitialEnclosure { .. }
        | Error::InadmissibleSignal { .. } => Err(invalid(e)),
        _ => Err(MethodError::Numerical {
            method: ID,
            source: Box::new(e),
        }),
    }
}

/// The crate's plant and bounds of a plant the method applies to (`d̲ = −d̄`; an empty bound
/// list is zero).
fn plant_of(plant: &ModelPlant) -> Result<(Plant, Bounds), MethodError> {
    let c = plant.c().ok_or_else(|| MethodError::InvalidInput {
        method: ID,
        source: "rabehi2021 needs one synchronously sampled output matrix C".into(),
    })?;
    let p = Plant::new(plant.a(), plant.b(), c).map_err(invalid)?;
    let given = plant.bounds().ok_or_else(|| MethodError::InvalidInput {
        method: ID,
        source: "rabehi2021 needs disturbance and noise bounds".into(),
    })?;
    let d = if given.disturbance().is_empty() {
        vec![0.0; p.n()]
    } else {
        given.disturbance().to_vec()
    };
    let v = if given.noise().is_empty() {
        vec![0.0; p.p()]
    } else {
        given.noise().to_vec()
    };
    let bounds = Bounds::new(d.iter().map(|x| -x).collect(), d, v).map_err(invalid)?;
    bounds.check_against(&p).map_err(invalid)?;
    Ok((p, bounds))
}

/// The plant in the balanced coordinates `x_b = D⁻¹x` (`D = diag(scales)`, powers of 2):
/// `(D⁻¹AD, D⁻¹B, CD)`. The interval observer is equivariant under a positive diagonal change of
/// coordinates (it keeps the order `x̲ ≤ x ≤ x̄`), so a design there is one for the plant; the
/// Taylor polytope of `e^(Āμ)` and the normalisations of the BMI (44), which are not invariant,
/// then see the same matrix whatever units the user chose (issue 22), including the units of a
/// state `gebal` leaves free, such as the angle of a motor ([`complete_balancing_scales`]).
fn balanced_plant(p: &Plant, scales: &[f64]) -> Result<Plant, MethodError> {
    Plant::new(
        balance_a(p.a(), scales).as_ref(),
        balance_b(p.b(), scales).as_ref(),
        balance_c(p.c(), scales).as_ref(),
    )
    .map_err(invalid)
}

/// The scales of the balanced coordinates of a plant with state matrix `a`:
/// [`complete_balancing_scales`] with the coupling of a state that LAPACK's balancing leaves free
/// set to the slowest nonzero rate on the diagonal of `A`, `min |a_ii|`
/// over `a_ii ≠ 0` (it scales with `A` under a change of time unit and does not depend on the
/// state units). A coupling larger than the plant's rates inflates `Ā` and with it the Taylor
/// polytope of `e^(Āμ)`: a cart (position, velocity with friction 0.2, force lag 5) written with
/// couplings 0.25, 1, 4, 16 was certified up to `T2` = 2, 2, 1.24 and 0.093. When the diagonal
/// is zero there is no such rate and the user's units of the free states stand.
pub(crate) fn balancing_scales_of(a: MatRef<'_, f64>) -> Vec<f64> {
    let slowest = (0..a.nrows())
        .map(|i| a[(i, i)].abs())
        .filter(|&r| r > 0.0)
        .fold(f64::INFINITY, f64::min);
    complete_balancing_scales(a, slowest)
}

/// The gain and the split of a design made in balanced coordinates, in the plant's:
/// `L = D·L_b` and `G_i = D·G_ib·D⁻¹` (so `I + LC = D(I + L_bC_b)D⁻¹`).
fn unbalanced_design(mut d: Design, scales: &[f64]) -> Design {
    d.l = unbalance_gain(d.l.as_ref(), scales);
    d.g1 = unbalance_a(d.g1.as_ref(), scales);
    d.g2 = unbalance_a(d.g2.as_ref(), scales);
    d
}

/// What the gain `L` is, in a report.
const L_MEANING: &str = "output-injection gain of the jump (8): with G = I + LC = G⁺ − G⁻, at \
    each sample x̲⁺ = G⁺x̲ − G⁻x̄ − |L|v̄ − Ly and x̄⁺ = G⁺x̄ − G⁻x̲ + |L|v̄ − Ly (both bounds \
    corrected); sign convention x̂⁺ = x̂ + L(Cx̂ − y) = (I + LC)x̂ − Ly, i.e. L multiplies the \
    output estimate minus the measurement";

/// What the certificate `P_19` is, in a report.
const P19_MEANING: &str = "Lyapunov matrix (2n × 2n, ‖P‖₂ ≤ 1) of Theorem 1 (19) for the \
    implemented jump matrix Γ(L) = [[G⁺, G⁻], [G⁻, G⁺]] (Remark 6): Γᵀe^(Āᵀμ)Pe^(Āμ)Γ − P ≺ 0 \
    on [T1, T2]";

/// The report check of a grid verification of (19) ([`verify_theorem1`]).
fn grid_check(g: &GridCheck, window: &SamplingWindow, which: &str) -> Check {
    Check {
        what: format!("Theorem 1 (19) for Γ(L) on the whole window {which}"),
        how: format!(
            "dense μ-grid of {} points on {} with a rigorous bound on the variation of \
             λmax(Γᵀe^(Āᵀμ)Pe^(Āμ)Γ − P) between points; passes if max + slack < 0 \
             (max {:.3e} at μ = {:.4}, slack {:.2e})",
            g.points, window, g.max_eigenvalue, g.at, g.slack
        ),
        value: Some(g.bound),
        passed: g.certified,
    }
}

/// A vector rounded to 4 decimals, in words.
fn vector_words(x: &[f64]) -> String {
    let parts: Vec<String> = x.iter().map(|v| format!("{:.4}", v)).collect();
    format!("[{}]", parts.join(", "))
}

impl Rabehi2021 {
    /// The definition of the margin of a design.
    fn margin_definition(&self) -> String {
        format!(
            "−(max_i λmax(Ψ_i) + ‖P‖₂δ + rounding) for BMI (44) of Proposition 1, recomputed in f64 \
             at the returned (P, F, G1, G2): Ψ_i at the vertices M_i of the Taylor polytope of \
             e^(Ā μ), μ ∈ [T1, T2], δ the polytope's remainder bound (‖P‖₂δ bounds the change of \
             any Ψ it can cause), rounding = {}·6n·ε·max|Ψ_ij|; positive: (44) holds on the whole \
             window. Normalisation: {:e}·I ⪯ P ⪯ {:e}·I, G1, G2 ≤ {:e} entrywise, F unnormalised \
             (Ψ is jointly homogeneous of degree 1 in (F, P), so the value scales with this \
             normalisation). The observer's certificate is Theorem 1 for Γ(L) (checks)",
            self.synthesis.safety, self.synthesis.p_min, self.synthesis.p_max, self.synthesis.g_max
        )
    }

    /// [`ObserverMethod::verify`] for the plant `p` (balanced by `scales`, giving `balanced`):
    /// (19) for `Γ(L)` with the given `P_19` on the μ-grid, else Theorem 1's SDP for `P`.
    #[allow(clippy::too_many_arguments)]
    fn verify_given(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        window: &SamplingWindow,
        balanced: &Plant,
        scales: &[f64],
        l: &Mat<f64>,
        p19: Option<Mat<f64>>,
    ) -> Result<DesignReport, MethodError> {
        let start = Instant::now();
        // In the balanced coordinates (exact): L_b = D⁻¹L.
        let l_b = balance_b(l.as_ref(), scales);
        let a_bar = MetzlerDecomposition::new(balanced.a())
            .map_err(invalid)?
            .a_bar;
        let gamma = gamma_of_gain(balanced, l_b.as_ref()).map_err(invalid)?;
        let grid = &self.synthesis.analysis.grid;
        let certified = |p: &Mat<f64>, checks: Vec<Check>, note: String| {
            let mut r = DesignReport::certified(self, plant.name(), sampling);
            r.gains.push(Gain::constant("L", l.as_ref(), L_MEANING));
            r.certificate
                .push(NamedMatrix::new("P_19", p.as_ref(), P19_MEANING));
            r.checks = checks;
            r.notes.push(note);
            if scales.iter().any(|&x| x != 1.0) {
                r.notes.push(format!(
                    "checked in the balanced coordinates x_b = D⁻¹x with D = diag{} (powers of \
                     2; exact): L is in the plant's coordinates, P_19 in the balanced ones",
                    vector_words(scales)
                ));
            }
            r.seconds = start.elapsed().as_secs_f64();
            r
        };
        let mut notes = Vec::new();
        if let Some(p) = p19 {
            let g = match verify_theorem1(a_bar.as_ref(), gamma.as_ref(), p.as_ref(), window, grid)
            {
                Ok(g) => g,
                Err(e) => {
                    return Ok(DesignReport::without_design(
                        self,
                        plant.name(),
                        Some(sampling),
                        verdict_of(e)?,
                    ));
                }
            };
            if g.certified {
                return Ok(certified(
                    &p,
                    vec![grid_check(&g, window, "with the given P_19")],
                    "given gain L and certificate P_19 verified (no SDP solved): Theorem 1 (19) \
                     for Γ(L) on the μ-grid with a rigorous bound between points"
                        .into(),
                ));
            }
            notes.push(format!(
                "the given P_19 does not verify (19) for Γ(L) (grid bound {:.3e}, max {:.3e} at \
                 μ = {:.4}); Theorem 1's SDP was solved for P with L fixed",
                g.bound, g.max_eigenvalue, g.at
            ));
        } else {
            notes.push(
                "no P_19 given: Theorem 1's SDP was solved for P with L fixed (Taylor polytope \
                 of e^(Āμ), then the μ-grid check)"
                    .into(),
            );
        }
        let a: Analysis = match analyse(
            a_bar.as_ref(),
            gamma.as_ref(),
            window,
            &self.synthesis.analysis,
        ) {
            Ok(a) => a,
            Err(e) => {
                let mut r = DesignReport::without_design(
                    self,
                    plant.name(),
                    Some(sampling),
                    verdict_of(e)?,
                );
                r.notes = notes;
                return Ok(r);
            }
        };
        let polytope = Check {
            what: "Theorem 1 (19) for Γ(L) on the Taylor polytope".into(),
            how: format!(
                "margin-maximising SDP for Q(M_i) = [[P, ΓᵀM_iᵀP], [PM_iΓ, P]] ≻ 0 at {} \
                 vertices under ‖P‖₂ ≤ 1 (remainder δ = {:.2e}); passes if min_i λmin(Q(M_i)) = \
                 {:.3e} exceeds ‖P‖₂‖Γ‖₂δ = {:.2e} plus rounding",
                a.vertices, a.remainder, a.vertex_margin, a.remainder_effect
            ),
            value: Some(a.vertex_margin - a.remainder_effect),
            passed: a.polytope_certified,
        };
        if a.certified {
            let checks = vec![
                polytope,
                grid_check(&a.grid, window, "with the P of the SDP"),
            ];
            return Ok(certified(&a.p, checks, notes.join("; ")));
        }
        let reason = if a.polytope_certified {
            Reason::VerificationFailed {
                tau: Some(a.grid.at),
                message: format!(
                    "(19) for Γ(L) is not certified on the μ-grid with the P of the SDP (bound \
                     {:.3e}, max {:.3e} at μ = {:.4})",
                    a.grid.bound, a.grid.max_eigenvalue, a.grid.at
                ),
            }
        } else {
            Reason::InfeasibleLmi {
                message: format!(
                    "Theorem 1's SDP for the given L is not certified on the Taylor polytope \
                     (vertex margin {:.3e}, remainder effect {:.2e}): {}",
                    a.vertex_margin, a.remainder_effect, a.reason
                ),
            }
        };
        let mut r = DesignReport::without_design(self, plant.name(), Some(sampling), reason);
        r.notes = notes;
        r.seconds = start.elapsed().as_secs_f64();
        Ok(r)
    }

    /// The report of a certified design.
    fn report(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        p: &Plant,
        bounds: &Bounds,
        window: &SamplingWindow,
        d: &Design,
    ) -> DesignReport {
        let mut r = DesignReport::certified(self, plant.name(), sampling);
        r.gains.push(Gain::constant("L", d.l.as_ref(), L_MEANING));
        r.certificate.push(NamedMatrix::new(
            "P",
            d.p.as_ref(),
            "Lyapunov matrix (2n × 2n) of BMI (44) of Proposition 1 at every vertex of the Taylor \
             polytope of e^(Ā μ), μ ∈ [T1, T2]",
        ));
        r.certificate.push(NamedMatrix::new(
            "F",
            d.f.as_ref(),
            "slack matrix (2n × 2n) of the projection lemma in (44), block (1, 2) = FΓ(G1, G2)",
        ));
        r.certificate.push(NamedMatrix::new(
            "G1",
            d.g1.as_ref(),
            "nonnegative part of the split I + LC = G1 − G2 of (35b)–(35d); Γ(G1, G2) = \
             [[G1, G2], [G2, G1]] in (44)",
        ));
        r.certificate.push(NamedMatrix::new(
            "G2",
            d.g2.as_ref(),
            "nonnegative part of the split I + LC = G1 − G2 of (35b)–(35d)",
        ));
        if let Some(a) = &d.reverification {
            r.certificate
                .push(NamedMatrix::new("P_19", a.p.as_ref(), P19_MEANING));
        }
        r.margin = Some(Margin {
            value: d.bmi.margin(),
            definition: self.margin_definition(),
        });
        let b = &d.bmi;
        r.checks.push(Check {
            what: format!(
                "BMI (44) at the {} vertices of the Taylor polytope of e^(Ā μ) on {} (remainder \
                 δ = {:.2e})",
                d.vertices, window, d.remainder
            ),
            how: format!(
                "f64 eigenvalues of Ψ_i at the returned (P, F, G1, G2); passes if max_i \
                 λmax(Ψ_i) + ‖P‖₂δ + rounding < 0 (max λmax {:.3e}, remainder effect {:.2e}, \
                 rounding {:.1e})",
                b.max_eigenvalue, b.remainder_effect, b.rounding
            ),
            value: Some(b.max_eigenvalue + b.remainder_effect + b.rounding),
            passed: b.certified,
        });
        r.checks.push(Check {
            what: "split I + LC = G1 − G2, G1, G2 ≥ 0 ((35b)–(35d))".into(),
            how: format!(
                "entrywise in f64 after the repair onto G⁺ + Δ, G⁻ + Δ: residual ≤ 1e-9 and \
                 smallest entry ≥ 0 (smallest entry {:.3e})",
                b.min_g_entry
            ),
            value: Some(b.equality_residual),
            passed: b.equality_residual <= 1e-9 && b.min_g_entry >= 0.0,
        });
        if let Some(a) = &d.reverification {
            r.checks.push(Check {
                what: "Theorem 1 (19) for Γ(L) on the Taylor polytope (Remark 6)".into(),
                how: format!(
                    "margin-maximising SDP for Q(M_i) = [[P, ΓᵀM_iᵀP], [PM_iΓ, P]] ≻ 0 at {} \
                     vertices under ‖P‖₂ ≤ 1 (remainder δ = {:.2e}); λmin recomputed in f64; \
                     passes if min_i λmin(Q(M_i)) = {:.3e} exceeds ‖P‖₂‖Γ‖₂δ = {:.2e} plus \
                     rounding",
                    a.vertices, a.remainder, a.vertex_margin, a.remainder_effect
                ),
                value: Some(a.vertex_margin - a.remainder_effect),
                passed: a.polytope_certified,
            });
            r.checks
                .push(grid_check(&a.grid, window, "with the P of the SDP"));
        }
        let kinds: Vec<String> = d
            .log
            .iter()
            .map(|s| format!("{:?} t = {:.3e}", s.kind, s.t))
            .collect();
        r.notes.push(format!(
            "Proposition 1 pipeline: {} LMI steps [{}]",
            d.log.len(),
            kinds.join(", ")
        ));
        if let Some(a) = &d.reverification
            && a.grid.max_spectral_radius.is_finite()
        {
            r.notes.push(format!(
                "max over the grid of ρ(e^(Ā μ)Γ(L)) = {:.4} at μ = {:.4} (Remark 5: < 1 is \
                 necessary)",
                a.grid.max_spectral_radius, a.grid.radius_at
            ));
        }
        match WidthDynamics::new(p, bounds, d.l.as_ref())
            .and_then(|wd| wd.guaranteed_bound(window, &vec![0.0; p.n()], WIDTH_POINTS))
        {
            Ok(b) => r.notes.push(format!(
                "guaranteed interval width x̄ − x̲ at any time, for every admissible sampling, \
                 disturbance and noise, from an exact initial enclosure ({WIDTH_POINTS} grid \
                 points per max over μ): {}",
                vector_words(&b.any_time)
            )),
            Err(e) => r
                .notes
                .push(format!("no guaranteed width bound: {}", chain(&e))),
        }
        r
    }
}

impl ObserverMethod for Rabehi2021 {
    fn id(&self) -> &'static str {
        ID
    }

    fn citation(&self) -> &'static str {
        "S. Rabehi, N. Meslem, M. El Amraoui and N. Ramdani (2021), \"Interval impulsive observer \
         for linear systems with aperiodic discrete measurements\", IEEE Transactions on \
         Automatic Control 66(11):5407–5413"
    }

    fn summary(&self) -> &'static str {
        "interval observer: guaranteed bounds x̲ ≤ x ≤ x̄ under bounded disturbance and noise, \
         corrected at each sample by a constant gain L designed by BMI (44)"
    }

    fn observer(&self) -> &'static str {
        "interval observer (4), (8) on the bounds (x̲, x̄), with A = A^M − A^N (A^M Metzler: the \
         diagonal and the nonnegative off-diagonal entries of A; A^N ≥ 0): between samples \
         x̲' = A^M x̲ − A^N x̄ + Bu + d̲ and x̄' = A^M x̄ − A^N x̲ + Bu + d̄ (d̲ = −d̄); at a sample, \
         with G = I + LC = G⁺ − G⁻ (entrywise positive and negative parts), \
         x̲⁺ = G⁺x̲ − G⁻x̄ − |L|v̄ − Ly and x̄⁺ = G⁺x̄ − G⁻x̲ + |L|v̄ − Ly. Sign convention: for a \
         point estimate the jump is x̂⁺ = x̂ + L(Cx̂ − y) (L multiplies the output estimate minus \
         the measurement). x̲ ≤ x ≤ x̄ holds for every L; the design makes the width bounded"
    }

    fn applies(&self, plant: &ModelPlant, sampling: &Sampling) -> Result<(), NotApplicable> {
        if plant.lipschitz().is_some() {
            return Err(NotApplicable::unsupported(
                ID,
                "the plant has a Lipschitz nonlinearity; the interval observer of Rabehi et al. \
                 (2021) is for linear plants",
            ));
        }
        if let Outputs::RoundRobin(_) = plant.output_structure() {
            return Err(NotApplicable::unsupported(
                ID,
                "round-robin sensors; the method measures the whole output y = Cx at every sample",
            ));
        }
        if let Sampling::RoundRobin(_) = sampling {
            return Err(NotApplicable::unsupported(
                ID,
                "round-robin sampling; the method has one window for all outputs",
            ));
        }
        if plant.bounds().is_none() {
            return Err(NotApplicable::missing(
                ID,
                "the interval observer needs disturbance and noise bounds (|d_i| ≤ d̄_i, \
                 |v_j| ≤ v̄_j, Assumptions 2–3); the plant has none",
            ));
        }
        Ok(())
    }

    fn design(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        options: &MethodOptions,
    ) -> Result<DesignReport, MethodError> {
        let _ = options;
        let start = Instant::now();
        if let Err(na) = self.applies(plant, sampling) {
            return Ok(DesignReport::without_design(
                self,
                plant.name(),
                Some(sampling),
                na.reason,
            ));
        }
        self.synthesis.validate().map_err(invalid)?;
        let (p, bounds) = plant_of(plant)?;
        let window = sampling.windows()[0];
        let scales = balancing_scales_of(p.a());
        let balanced = balanced_plant(&p, &scales)?;
        let mut report = match synthesise(&balanced, &window, &self.synthesis) {
            Ok(d) => match &d.status {
                DesignStatus::Certified => {
                    let d = unbalanced_design(d, &scales);
                    let mut r = self.report(plant, sampling, &p, &bounds, &window, &d);
                    if scales.iter().any(|&x| x != 1.0) {
                        r.notes.push(format!(
                            "designed in the balanced coordinates x_b = D⁻¹x with D = diag{} \
                             (powers of 2, LAPACK gebal scaling of A, where a state that no \
                             other state drives or that drives none has its coupling set to \
                             min |a_ii|; exact): L and G1, G2 are \
                             in the plant's coordinates (L = D·L_b, G_i = D·G_ib·D⁻¹); P, F and \
                             P_19 and the margin are those of the balanced plant, whose interval \
                             error is D⁻¹ times the plant's",
                            vector_words(&scales)
                        ));
                    }
                    r
                }
                DesignStatus::NotCertified(why) => {
                    let mut r = DesignReport::without_design(
                        self,
                        plant.name(),
                        Some(sampling),
                        why.reason(),
                    );
                    r.notes.push(format!(
                        "Proposition 1 pipeline: {} LMI steps, best max_i λmax(Ψ_i) = {:.3e}",
                        d.log.len(),
                        d.best_t()
                    ));
                    r
                }
            },
            Err(e) => {
                DesignReport::without_design(self, plant.name(), Some(sampling), verdict_of(e)?)
            }
        };
        report.seconds = start.elapsed().as_secs_f64();
        Ok(report)
    }

    /// The shared search ([`default_largest_window`], i.e. [`sporadic_model::search_upper`] with
    /// [`design`](Self::design) as the probe) with the limit capped by the necessary condition of
    /// [`crate::window::necessary_tau_max`] (scanned with at most 20 000 steps): a probe at or
    /// beyond the cap fails at once with [`Reason::InfeasibleLmi`] stating the cap (no
    /// Proposition 1 run), and the design at the largest certified window gets a note with the
    /// cap.
    fn largest_window(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        limit: f64,
        options: &MethodOptions,
        progress: &mut dyn FnMut(&Probe),
    ) -> Result<MaxIntervalReport, MethodError> {
        let t1 = sampling.t1();
        let cap = if self.applies(plant, sampling).is_ok() && limit.is_finite() && limit > t1 {
            let (p, _) = plant_of(plant)?;
            let p = balanced_plant(&p, &balancing_scales_of(p.a()))?;
            match necessary_limit(&p, t1, limit, Some(NECESSARY_SCAN_STEPS)) {
                Ok(c) => c,
                Err(e) => {
                    verdict_of(e)?;
                    None
                }
            }
        } else {
            None
        };
        let Some(cap) = cap else {
            return default_largest_window(self, plant, sampling, limit, options, progress);
        };
        let capped = Capped { method: self, cap };
        let mut report = default_largest_window(&capped, plant, sampling, cap, options, progress)?;
        report.limit = Some(limit);
        if let Some(d) = &mut report.design {
            d.notes.push(format!(
                "necessary condition: no window [T1, T2] with T2 ≥ {cap:.6} is certifiable by any \
                 gain (the interval width of a state that C does not see cannot contract over a \
                 sampling interval that long), so the search stopped there instead of at {limit}"
            ));
        }
        Ok(report)
    }

    /// The rigorous proof of [`crate::prove`]: Theorem 1's (19) for the implemented `Γ(L)`
    /// with the report's `L` and `P_19`, for every `μ` of the window, in interval arithmetic.
    fn prove(
        &self,
        plant: &ModelPlant,
        design: &DesignReport,
        options: &ProofOptions,
    ) -> Result<Proof, MethodError> {
        prove_design(plant, design, options)
    }

    /// Checks a gain `L` on `sampling`: Theorem 1's (19) for the implemented `Γ(L)` with the
    /// given `P_19` (balanced coordinates, as a design report writes it) on the μ-grid of a
    /// design's re-verification ([`verify_theorem1`]); without `P_19`, or when it does not
    /// verify, Theorem 1's SDP is solved for `P` with `L` fixed ([`analyse`]: Taylor polytope,
    /// then the grid). The BMI variables `P, F, G1, G2` of a report are accepted and not used.
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
        self.synthesis.validate().map_err(invalid)?;
        let (p, _) = plant_of(plant)?;
        let window = sampling.windows()[0];
        let (l, p19) = read_given(p.n(), p.p(), gains, certificate)?;
        let scales = balancing_scales_of(p.a());
        let balanced = balanced_plant(&p, &scales)?;
        self.verify_given(plant, sampling, &window, &balanced, &scales, &l, p19)
    }

    /// Simulates the plant and the interval observer of a certified design: `x(0) = 0` enclosed
    /// in `[−h, h]` (`h` = |`scenario.initial_error`|, default all ones), disturbance drawn
    /// uniformly within its bounds and held for `T1` (seed + 1), noise `v̄ cos(2t)`, horizon
    /// `40·T2` by default; the signals are the interval widths `x̄_k − x̲_k`, and the result
    /// reports any violation of the enclosure `x̲ ≤ x ≤ x̄`.
    fn simulate(
        &self,
        plant: &ModelPlant,
        design: &DesignReport,
        scenario: &Scenario,
    ) -> Result<Trajectory, MethodError> {
        check_simulatable(ID, design)?;
        let Some(window) = design.window else {
            return Err(MethodError::SimulationUnavailable {
                method: ID,
                why: "the design report has no sampling window".into(),
            });
        };
        let l = design
            .gain("L")
            .ok_or_else(|| MethodError::SimulationUnavailable {
                method: ID,
                why: "the design report has no gain L".into(),
            })?
            .to_mat();
        let (p, bounds) = plant_of(plant)?;
        let n = p.n();
        let observer = IntervalObserver::new(&p, &bounds, l.as_ref()).map_err(invalid)?;
        let half: Vec<f64> = match &scenario.initial_error {
            Some(e) => {
                if e.len() != n {
                    return Err(invalid(
                        sporadic_linalg::InputError::mismatch(
                            "entries of the initial half-width (= n)",
                            n,
                            e.len(),
                        )
                        .into(),
                    ));
                }
                e.iter().map(|x| x.abs()).collect()
            }
            None => vec![1.0; n],
        };
        let (t1, t2) = (window.t1(), window.t2());
        let horizon = scenario.horizon.unwrap_or(40.0 * t2);
        let (sampling, seed, words) = match scenario.sampling {
            SamplingScenario::WorstCase => {
                return Err(MethodError::SimulationUnavailable {
                    method: ID,
                    why: "no worst-case sampling for the interval observer (the width's worst \
                          case is stated in the design report's guaranteed bound); use uniform \
                          or periodic sampling"
                        .into(),
                });
            }
            SamplingScenario::Uniform { seed } => (
                window,
                seed,
                format!("intervals uniform in {window} (seed {seed})"),
            ),
            SamplingScenario::PeriodicT1 => (
                SamplingWindow::periodic(t1).map_err(|e| invalid(e.into()))?,
                1,
                format!("periodic sampling every T1 = {t1}"),
            ),
            SamplingScenario::PeriodicT2 => (
                SamplingWindow::periodic(t2).map_err(|e| invalid(e.into()))?,
                1,
                format!("periodic sampling every T2 = {t2}"),
            ),
        };
        let sim = SimScenario {
            x0: vec![0.0; n],
            lower0: half.iter().map(|h| -h).collect(),
            upper0: half.clone(),
            horizon,
            sampling,
            sampling_seed: seed,
            disturbance: Some(Disturbance {
                lower: bounds.d_lower().to_vec(),
                upper: bounds.d_upper().to_vec(),
                period: t1,
                seed: seed.wrapping_add(1),
            }),
            noise: Noise::Cosine {
                amplitude: bounds.v_bar().to_vec(),
                omega: 2.0,
            },
            input: Vec::new(),
            record_step: Some((t1 / 4.0).max(horizon / MAX_RECORDED)),
        };
        let run = simulate_interval(&observer, &sim).map_err(|e| match e {
            Error::Input(_) | Error::InitialEnclosure { .. } | Error::InadmissibleSignal { .. } => {
                invalid(e)
            }
            e => MethodError::Numerical {
                method: ID,
                source: Box::new(e),
            },
        })?;
        // Only the part of the run whose widths double precision resolves is returned
        // (`Inclusion::unresolved_from`).
        let inc = run.inclusion;
        let len = match inc.unresolved_from {
            Some(t0) => run.times().iter().take_while(|&&t| t < t0).count().max(1),
            None => run.times().len(),
        };
        let signals: Vec<(String, Vec<f64>)> = (0..n)
            .map(|k| {
                let mut w = run.width(k);
                w.truncate(len);
                (format!("width of x{}", k + 1), w)
            })
            .collect();
        let norm: Vec<f64> = (0..len)
            .map(|i| signals.iter().map(|(_, y)| y[i] * y[i]).sum::<f64>().sqrt())
            .collect();
        let last: Vec<f64> = signals
            .iter()
            .map(|(_, y)| y.last().copied().unwrap_or(f64::NAN))
            .collect();
        let samples = run.sim.arc.num_jumps();
        let mut result = format!(
            "{samples} samples, final widths {}, enclosure x̲ ≤ x ≤ x̄ {} ({} violations of {} \
             checks at tolerance 1e-9 relative to the state, worst excess {:.2e})",
            vector_words(&last),
            if inc.violations == 0 {
                "held at every recorded point"
            } else {
                "VIOLATED"
            },
            inc.violations,
            inc.checked,
            inc.worst
        );
        if let Some(t) = inc.unresolved_from {
            let largest = (0..run.times().len())
                .flat_map(|i| run.sim.arc.state(i)[..n].iter().map(|v| v.abs()))
                .fold(0.0, f64::max);
            result.push_str(&format!(
                "; from t = {} a width is below the double-precision resolution of the state \
                 (|x| reaches {:.1e}), so the widths are returned, and the final widths given, \
                 up to that time only",
                significant(t),
                largest
            ));
        }
        Ok(Trajectory {
            quantity: "interval width x̄ − x̲".into(),
            t: run.times()[..len].to_vec(),
            j: run.jumps()[..len].to_vec(),
            signals,
            norm: norm.clone(),
            report: SimulationReport {
                setup: format!(
                    "x(0) = 0 enclosed in [−h, h], h = {}, disturbance uniform within its bounds \
                     (resampled every {t1} s, seed {}), noise = bound·cos(2t), {words}, horizon \
                     {horizon} s",
                    vector_words(&half),
                    seed.wrapping_add(1)
                ),
                samples,
                initial_error: norm.first().copied().unwrap_or(f64::NAN),
                final_error: norm.last().copied().unwrap_or(f64::NAN),
                result,
                settling_time: None,
                ends_early_at: inc.unresolved_from,
                figure: None,
            },
        })
    }
}

/// The method with every window reaching `cap` refused at once (the necessary condition).
struct Capped<'a> {
    method: &'a Rabehi2021,
    cap: f64,
}

impl ObserverMethod for Capped<'_> {
    fn id(&self) -> &'static str {
        self.method.id()
    }
    fn citation(&self) -> &'static str {
        self.method.citation()
    }
    fn summary(&self) -> &'static str {
        self.method.summary()
    }
    fn observer(&self) -> &'static str {
        self.method.observer()
    }
    fn applies(&self, plant: &ModelPlant, sampling: &Sampling) -> Result<(), NotApplicable> {
        self.method.applies(plant, sampling)
    }
    fn design(
        &self,
        plant: &ModelPlant,
        sampling: &Sampling,
        options: &MethodOptions,
    ) -> Result<DesignReport, MethodError> {
        if sampling.t2() >= self.cap {
            let reason = beyond_cap(self.cap, "the necessary condition of (19)");
            return Ok(DesignReport::without_design(
                self.method,
                plant.name(),
                Some(sampling),
                reason,
            ));
        }
        self.method.design(plant, sampling, options)
    }
}
