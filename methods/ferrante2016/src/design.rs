//! Observer design by Corollary 1 (Ferrante et al. 2016, §4) and certification of a given gain.
//!
//! **Design** ([`design`]): Remark 3 precheck → polytopic embedding `X_1..X_ν` of `e^{Av}` on
//! `[T1, T2]` (residue box of §4.1 by default; Taylor polytope or interval splitting selectable) →
//! margin maximisation for LMI (41) in `(P, F, J)` → `L = F⁻¹J` → independent grid verification of
//! (12) and of the Schur property of `e^{Av}(I − LM)` ([`crate::verify()`]). A design is returned only
//! when all of these succeed; every failure is a typed [`Error`].
//!
//! **Analysis** ([`analyse`]): the same LMI with `J = FL` for a given `L` (linear in `P`, `F`), i.e.
//! (36) at the vertices; certifies e.g. the gain published for Example 2.
//! [`min_trace_certificate`] solves the same LMI for the certificate with the smallest `tr P`
//! (the reference certificate of the bound constants of Theorems 1–2 for Example 2).

use sporadic_linalg::InputError;
use std::time::{Duration, Instant};

use faer::{Mat, MatRef};
use sporadic_embed::{Embedding, EmbeddingMethod, ResidueOptions, embed_split};
use sporadic_sdp::lmi::{FeasibilityOptions, Outcome};

use crate::detectability::{DetectabilityOptions, DetectabilityReport, check_detectability};
use crate::error::Error;
use crate::lmi::{GainTerm, Lmi41, LmiForm, LmiResult, LmiSize, Objective, gain_from};
use crate::normalise;
use crate::system::Plant;
use crate::verify::{Verification, VerifyOptions, verify};
use sporadic_model::SamplingWindow;
use sporadic_model::SolverStats;
use sporadic_sdp::lmi::Normalisation;

/// Options of [`design`], [`analyse`] and [`min_trace_certificate`]; the defaults are the
/// paper's construction (see each field). [`DesignOptions::validate`] checks them; every entry
/// point calls it.
#[derive(Debug, Clone)]
pub struct DesignOptions {
    /// Polytopic embedding of `e^{Av}` (default: the residue box of §4.1,
    /// `EmbeddingMethod::Residue(ResidueOptions::default())`).
    pub embedding: EmbeddingMethod,
    /// Number of equal sub-intervals of `[T1, T2]` whose vertex sets are united (default 1 = the
    /// paper's construction; more pieces reduce conservatism at a linear cost in vertices).
    pub pieces: usize,
    /// LMI imposed at each vertex: (41) as printed (default) or its equivalent reduced `2n × 2n`
    /// form ([`LmiForm`]).
    pub form: LmiForm,
    /// Margin problem: solver settings, verification safety factor, normalisation (default
    /// `‖·‖₂ ≤ 1` on every variable, margin cap 1; lossless since (41) is homogeneous).
    pub lmi: FeasibilityOptions,
    /// Grid verification of (12) (default 2801 points, relative tolerance `1e-9`).
    pub verify: VerifyOptions,
    /// Remark 3 precheck (design only; default 1001 grid points plus the aliasing instants).
    pub detectability: DetectabilityOptions,
}

impl DesignOptions {
    /// Checks every field; the error names the offending one (`pieces`, `lmi.margin_cap`,
    /// `lmi.default_normalisation`, and those of [`VerifyOptions::validate`] and
    /// [`DetectabilityOptions::validate`]).
    pub fn validate(&self) -> Result<(), Error> {
        if self.pieces == 0 {
            return Err(InputError::parameter(
                "pieces",
                0.0,
                "the window must be split into at least one piece",
            )
            .into());
        }
        let cap = self.lmi.margin_cap;
        if !(cap.is_finite() && cap > 0.0) {
            return Err(InputError::parameter(
                "lmi.margin_cap",
                cap,
                "must be a positive finite number",
            )
            .into());
        }
        match self.lmi.default_normalisation {
            Normalisation::Norm(r) | Normalisation::Trace(r) if !(r.is_finite() && r > 0.0) => {
                return Err(InputError::parameter(
                    "lmi.default_normalisation",
                    r,
                    "the bound must be a positive finite number",
                )
                .into());
            }
            _ => {}
        }
        self.verify.validate()?;
        self.detectability.validate()?;
        Ok(())
    }
}

impl Default for DesignOptions {
    fn default() -> Self {
        Self {
            embedding: EmbeddingMethod::Residue(ResidueOptions::default()),
            pieces: 1,
            form: LmiForm::Corollary1,
            lmi: FeasibilityOptions::default(),
            verify: VerifyOptions::default(),
            detectability: DetectabilityOptions::default(),
        }
    }
}

/// The LMI certificate of a design or analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct Certificate {
    /// Lyapunov matrix `P ≻ 0` of (12)/(13).
    pub p: Mat<f64>,
    /// Multiplier `F` of Proposition 1 (`F + F' ≻ 0`).
    pub f: Mat<f64>,
    /// `J = FL` (Remark 8).
    pub j: Mat<f64>,
    /// Optimal common margin `t*`: `Φ_i ⪯ −t*·I` for every vertex.
    pub margin: f64,
    /// Multiplier `μ` of the robust form (only for embeddings with a remainder).
    pub robust_multiplier: Option<f64>,
}

/// A verified observer design (Corollary 1).
#[derive(Debug, Clone)]
pub struct Design {
    /// The observer gain `L = F⁻¹J` (`n × q`).
    pub l: Mat<f64>,
    /// `(P, F, J, margin)`.
    pub certificate: Certificate,
    /// The embedding used (of the normalised problem, see [`Design::scaling`]): vertices, method, containment statement, remainder bound. When its
    /// containment is not [`sporadic_embed::Containment::Guaranteed`] (e.g. clustered eigenvalues
    /// with a truncated expansion), Corollary 1's hypothesis is not proven and the grid
    /// [`Design::verification`] is the only evidence for (12).
    pub embedding: Embedding,
    /// The grid verification of (12) (passed), on the user's data.
    pub verification: Verification,
    /// The exact power-of-two scaling of time, states and outputs under which LMI (41) was
    /// solved ([`crate::normalise`]); the embedding and the margin are those of the normalised
    /// problem, the gain and the certificate are mapped back to the user's coordinates.
    pub scaling: normalise::Scaling,
    /// The Remark 3 precheck (passed).
    pub detectability: DetectabilityReport,
    /// Solver statistics.
    pub stats: SolverStats,
    /// Number and order of the vertex LMIs.
    pub size: LmiSize,
    /// Wall time of the whole design (precheck, embedding, LMI, verification).
    pub total_time: Duration,
}

/// Result of [`analyse`]: whether LMI (36)/(41) with `J = FL` certifies a given gain.
#[derive(Debug, Clone)]
pub struct Analysis {
    /// LMI strictly feasible **and** grid verification passed.
    pub certified: bool,
    /// Optimal common margin `t*` of the margin problem (`≤ 0`, or below the verification
    /// threshold, when the gain is not certified).
    pub margin: Option<f64>,
    /// The certificate `(P, F, FL, margin)` when the LMI was strictly feasible.
    pub certificate: Option<Certificate>,
    /// Grid verification with the certificate's `P` (when there is one).
    pub verification: Option<Verification>,
    /// The embedding used.
    pub embedding: Embedding,
    /// Solver statistics (outcome and reason say why a gain was not certified).
    pub stats: SolverStats,
    /// Number and order of the vertex LMIs.
    pub size: LmiSize,
}

/// Builds (or re-uses, when the vertex count fits) the margin-problem instance and solves it.
fn solve_on(
    plant: &Plant,
    embedding: &Embedding,
    gain: GainTerm,
    options: &DesignOptions,
    cache: &mut LmiCache,
) -> Result<LmiResult, Error> {
    let vertices = embedding.vertices();
    let delta = embedding.remainder_bound();
    let lmi = match cache.take() {
        Some((cached, mut lmi)) if cached == *plant && lmi.fits(vertices.len(), delta) => {
            lmi.set_vertices(vertices, delta)?;
            lmi
        }
        _ => Lmi41::new(
            plant,
            vertices,
            delta,
            gain,
            options.form,
            Objective::Margin(&options.lmi),
        )?,
    };
    cache.insert((plant.clone(), lmi)).1.solve()
}

/// A compiled LMI (41) kept across the probes of a window search, with the (normalised) plant
/// it was built for.
pub(crate) type LmiCache = Option<(Plant, Lmi41)>;

fn certificate_of(r: &LmiResult) -> Certificate {
    Certificate {
        p: r.p.clone(),
        f: r.f.clone(),
        j: r.j.clone(),
        margin: r.margin.unwrap_or(f64::NAN),
        robust_multiplier: r.mu,
    }
}

/// Designs `L` by Corollary 1 (see the module docs).
pub fn design(
    plant: &Plant,
    window: &SamplingWindow,
    options: &DesignOptions,
) -> Result<Design, Error> {
    design_cached(plant, window, options, &mut None)
}

/// [`design`] with a re-usable compiled LMI (used by the window searches: the vertex count of the
/// residue box does not depend on the window, so every probe re-solves the same compiled model).
pub(crate) fn design_cached(
    plant: &Plant,
    window: &SamplingWindow,
    options: &DesignOptions,
    cache: &mut LmiCache,
) -> Result<Design, Error> {
    let start = Instant::now();
    options.validate()?;
    let detectability = check_detectability(plant, window, &options.detectability)?;
    // The problem as given first (the paper's construction, unchanged on well-scaled data);
    // when that is no certificate, the normalised problem (exact power-of-two scalings of
    // time, states and outputs, see `crate::normalise`).
    let first = attempt(
        plant,
        window,
        options,
        cache,
        &identity_scaling(plant),
        (start, &detectability),
    );
    let scaling = normalise::scaling(plant, window);
    match first {
        Err(e) if e.reason().is_some() && !scaling.is_identity() => attempt(
            plant,
            window,
            options,
            cache,
            &scaling,
            (start, &detectability),
        )
        .map_err(|_| e),
        other => other,
    }
}

fn identity_scaling(plant: &Plant) -> normalise::Scaling {
    normalise::Scaling {
        time: 1.0,
        state: vec![1.0; plant.n()],
        output: vec![1.0; plant.q()],
    }
}

/// One design of LMI (41) under `scaling`, mapped back and verified on the user's data.
fn attempt(
    plant: &Plant,
    window: &SamplingWindow,
    options: &DesignOptions,
    cache: &mut LmiCache,
    scaling: &normalise::Scaling,
    (start, detectability): (Instant, &DetectabilityReport),
) -> Result<Design, Error> {
    let (np, nw) = match (scaling.plant(plant), scaling.window(window)) {
        (Some(p), Some(w)) => (p, w),
        _ => (plant.clone(), *window),
    };
    let embedding = embed_split(np.a(), nw.t1(), nw.t2(), options.pieces, &options.embedding)?;
    let mut r = solve_on(&np, &embedding, GainTerm::Free, options, cache)?;
    if !r.feasible {
        return Err(match r.stats.outcome {
            Outcome::Inconclusive => Error::Inconclusive {
                reason: r.stats.reason,
            },
            _ => Error::Infeasible {
                margin: r.margin,
                reason: r.stats.reason,
            },
        });
    }
    let l = scaling.gain_back(gain_from(r.f.as_ref(), r.j.as_ref())?.as_ref());
    r.p = scaling.congruence_back(r.p.as_ref());
    r.f = scaling.congruence_back(r.f.as_ref());
    r.j = scaling.multiplier_gain_back(r.j.as_ref());
    let verification = verify(plant, window, l.as_ref(), r.p.as_ref(), &options.verify)?;
    if !verification.passed() {
        return Err(verification_failed(&verification));
    }
    Ok(Design {
        certificate: certificate_of(&r),
        l,
        embedding,
        verification,
        scaling: scaling.clone(),
        detectability: detectability.clone(),
        stats: r.stats,
        size: r.size,
        total_time: start.elapsed(),
    })
}

/// The certificate of a given gain with the smallest trace (see [`min_trace_certificate`]).
#[derive(Debug, Clone)]
pub struct TraceCertificate {
    /// Lyapunov matrix `P ⪰ I` of (12)/(13).
    pub p: Mat<f64>,
    /// Multiplier `F` of Proposition 1.
    pub f: Mat<f64>,
    /// `J = FL`.
    pub j: Mat<f64>,
    /// `tr P` at the returned point.
    pub trace: f64,
    /// Whether the solver reached its optimality tolerances (`false`: the point is a verified
    /// certificate, but `tr P` may exceed the minimum, see [`TraceCertificate::stats`]).
    pub optimal: bool,
    /// Grid verification of (12) with this `P` (passed).
    pub verification: Verification,
    /// The embedding used.
    pub embedding: Embedding,
    /// Solver statistics.
    pub stats: SolverStats,
    /// Number and order of the vertex LMIs.
    pub size: LmiSize,
}

/// Certifies a given gain `L` with LMI (41) where `J = FL`, choosing the certificate that
/// minimises `tr P` under the normalisation `P ⪰ I`, `Φ_i ⪯ −I` (by homogeneity this is the same
/// feasible set as the strict LMIs, scaled; the reference bound constants of Example 2 are those
/// of this certificate). The bound constants of Theorems 1–2 depend on `P`; this choice keeps
/// `P` well scaled and reproducible up to the solver's accuracy.
///
/// Errors: bad input; [`Error::Infeasible`] on a solver infeasibility certificate;
/// [`Error::Inconclusive`] when the solver stopped at a point that fails the LMI layer's
/// verification; [`Error::VerificationFailed`] when the grid check of (12) fails.
pub fn min_trace_certificate(
    plant: &Plant,
    window: &SamplingWindow,
    l: MatRef<'_, f64>,
    options: &DesignOptions,
) -> Result<TraceCertificate, Error> {
    plant.check_gain(l)?;
    options.validate()?;
    let embedding = embed_split(
        plant.a(),
        window.t1(),
        window.t2(),
        options.pieces,
        &options.embedding,
    )?;
    let mut lmi = Lmi41::new(
        plant,
        embedding.vertices(),
        embedding.remainder_bound(),
        GainTerm::Fixed(l.to_owned()),
        options.form,
        Objective::MinTrace(&options.lmi.solve),
    )?;
    let r = lmi.solve()?;
    if !r.feasible {
        return Err(match r.stats.outcome {
            Outcome::Infeasible => Error::Infeasible {
                margin: None,
                reason: r.stats.reason,
            },
            _ => Error::Inconclusive {
                reason: r.stats.reason,
            },
        });
    }
    let verification = verify(plant, window, l, r.p.as_ref(), &options.verify)?;
    if !verification.passed() {
        return Err(verification_failed(&verification));
    }
    Ok(TraceCertificate {
        trace: (0..r.p.nrows()).map(|i| r.p[(i, i)]).sum(),
        optimal: r.stats.outcome == Outcome::Feasible && r.stats.status.is_optimal(),
        p: r.p,
        f: r.f,
        j: r.j,
        verification,
        embedding,
        stats: r.stats,
        size: r.size,
    })
}

/// The error of a failed grid verification; its `tau` is where (12) fails, or where the Schur
/// test fails when (12) passed.
fn verification_failed(v: &Verification) -> Error {
    Error::VerificationFailed {
        max_eigenvalue: v.max_eigenvalue,
        at: v.max_eigenvalue_at,
        max_spectral_radius: v.max_spectral_radius,
        radius_at: v.max_spectral_radius_at,
        tau: if v.condition12_holds {
            v.max_spectral_radius_at
        } else {
            v.max_eigenvalue_at
        },
    }
}

/// Certifies a given gain `L` with LMI (41) where `J = FL` (see the module docs).
pub fn analyse(
    plant: &Plant,
    window: &SamplingWindow,
    l: MatRef<'_, f64>,
    options: &DesignOptions,
) -> Result<Analysis, Error> {
    plant.check_gain(l)?;
    options.validate()?;
    let embedding = embed_split(
        plant.a(),
        window.t1(),
        window.t2(),
        options.pieces,
        &options.embedding,
    )?;
    let r = solve_on(
        plant,
        &embedding,
        GainTerm::Fixed(l.to_owned()),
        options,
        &mut None,
    )?;
    let (certificate, verification) = if r.feasible {
        let v = verify(plant, window, l, r.p.as_ref(), &options.verify)?;
        (Some(certificate_of(&r)), Some(v))
    } else {
        (None, None)
    };
    Ok(Analysis {
        certified: r.feasible && verification.as_ref().is_some_and(Verification::passed),
        margin: r.margin,
        certificate,
        verification,
        embedding,
        stats: r.stats,
        size: r.size,
    })
}
