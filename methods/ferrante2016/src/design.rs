//! Observer design by Corollary 1 (Ferrante et al. 2016, §4) and certification of a given gain.
//!
//! **Design** ([`design`]): Remark 3 precheck → polytopic embedding `X_1..X_ν` of `e^{Av}` on
//! `[T1, T2]` (residue box of §4.1 by default; Taylor polytope or interval splitting selectable) →
//! margin maximisation for LMI (41) in `(P, F, J)` → `L = F⁻¹J` → independent grid verification of
//! (12) and of the Schur property of `e^{Av}(I − LM)` ([`crate::verify()`]). A design is returned only
//! when all of these succeed; every failure is a typed [`Error`].
//!
//! The precheck is made on the Gramian normal form of the problem ([`crate::normalise`]), the
//! LMI on the data as given, then on the normal forms (time unit `T2`, or `T1` plus the decay
//! horizon of a Hurwitz `A` on a longer window, with Gramian coordinates,
//! then with power-of-two diagonal scalings), the first certificate being mapped back.
//! With the residue box, every interior-point iterate with a positive margin is tested for
//! every vertex LMI of (41) being negative definite by more than rounding and the embedding's
//! reconstruction error can explain (`strictly_negative`), a certificate decided without the
//! solver's verification threshold (which is relative to the margin problem's normalisation
//! `‖P‖₂ ≤ 1`, hence to the coordinates, and passes near the end of the largest window much
//! later than this test, if at all). A probe of a window search ends its solve at the first
//! such iterate; a design solves for the largest margin and returns the last such iterate when
//! the optimal point is not one, so that it certifies every window a probe certifies. The grid
//! check of (12) on the user's data is made in every case.
//! A residue box with a truncation remainder `δ` ([`TAIL_TOLERANCE`]) is solved first without
//! it, at the vertices: a failure there is a failure of the robust form too (which implies
//! (41) at the vertices), and a point at which every vertex LMI is negative definite by more
//! than `2‖P‖₂δ` and rounding (`strictly_negative`) certifies the window as it stands; only a
//! point in between is solved again in the robust form.
//! A probe whose embedding has many vertices solves each form on the vertices found to bind
//! (constraint generation, module `active`, not in the paper), every vertex being tested at
//! the returned point.
//! When no form certifies, the solves whose margin was undecided (within the solver's
//! verification threshold of zero) are repeated, the largest margin first and until one gives a
//! certificate, in the coordinates in which their own `P` is the identity (module
//! `certificate`, not in the paper), where the margin is not bounded by the condition number of
//! `P`; a certificate found there whose grid check of (12) in the plant's coordinates cannot
//! resolve it (its contraction in the norm of `P` within the check's resolution, the spectral
//! radius below one; [`crate::verify()`]) is reported as the
//! precision limit of the method ([`Error::PrecisionLimit`], `numerical_failure`), not as an
//! infeasible LMI.
//! The normal forms (not in the paper) are solved in the equivalent reduced form of
//! [`LmiForm::Reduced`] (order `2n`, or `3n` with a remainder, instead of `3n` or `4n`), and a
//! form whose embedding remainder makes the robust (41) infeasible on its face
//! (`remainder_too_large`) is refused without a solve: a numerical failure of that form, not a
//! verdict (on the data as given, the robust (41) on the method's own polytope is infeasible).
//!
//! **Taylor fallback** (not in the paper; opt-in, [`DesignOptions::taylor_fallback`]). With the
//! residue box of §4.1 (the default), when no form certifies, the normal forms are tried once more with the truncated-Taylor polytope of
//! `e^{Av}` ([`sporadic_embed::taylor_embedding`], `N + 1` vertices and a remainder handled by
//! the robust form of (41)): Corollary 1 holds for any polytope containing `e^{Av}` on the
//! window, and the residue box grows as `2^K` in its number `K` of coefficient terms, which on
//! a window where the residue expansion degenerates to a long power series (all eigenvalues in
//! one cluster, e.g. a normal form with ill-conditioned spectral projectors) is both far more
//! conservative and far costlier than the Taylor polytope. The fallback only adds certificates
//! (a failure of it leaves the verdict of the residue forms), and a design certified by the
//! residue box is returned unchanged. It is not on by default because it is decided by the
//! diagonal normal form more often than the residue box is, and that form is only invariant
//! under diagonal changes of coordinates: on the Jordan block of order 4 with eigenvalue `0.2`
//! (`tests/metamorphic.rs`) it certifies `[0.05, 2.07]` as given but not `[0.05, 2.056]` after
//! a similarity with condition number up to 10 (margin `1.4e-7` under the solver's verification
//! threshold `2.4e-7` there), where the residue box certifies neither. On `three-mass-chain`
//! (`[0.02, 0.3]`, not certified by the residue box) it certifies windows up to `T2 ≈ 0.65` at
//! 14–20 vertices instead of the 256 of the residue box of the diagonal form.
//!
//! **Analysis** ([`analyse`]): the same LMI with `J = FL` for a given `L` (linear in `P`, `F`), i.e.
//! (36) at the vertices; certifies e.g. the gain published for Example 2.
//! [`min_trace_certificate`] solves the same LMI for the certificate with the smallest `tr P`
//! (the reference certificate of the bound constants of Theorems 1–2 for Example 2).

use sporadic_linalg::InputError;
use std::cmp::Ordering;
use std::time::{Duration, Instant};

use faer::{Mat, MatRef};
use sporadic_embed::{
    EmbedError, Embedding, EmbeddingMethod, ResidueOptions, TaylorOptions, TaylorOrder, embed_split,
};
use sporadic_sdp::lmi::{FeasibilityOptions, Outcome};

use crate::active::{ACTIVE_FROM, solve_binding};
use crate::certificate::{CertificateCoordinates, VertexSet, VertexTest, strictly_negative};
use crate::detectability::{DetectabilityOptions, DetectabilityReport, check_detectability};
use crate::error::Error;
use crate::lmi::{GainTerm, Lmi41, LmiForm, LmiResult, LmiSize, Objective, Point41, gain_from};
use crate::normalise;
use crate::system::Plant;
use crate::verify::{Verification, VerifyOptions, factor_product, verify, verify_factor};
use sporadic_model::SamplingWindow;
use sporadic_model::SolverStats;
use sporadic_sdp::lmi::Normalisation;

/// Options of [`design`], [`analyse`] and [`min_trace_certificate`]; the defaults are the
/// paper's construction (see each field) but for the vertex LMI, which is (41) in its reduced
/// form (the same feasible set; `form: LmiForm::Corollary1` for (41) as printed).
/// [`DesignOptions::validate`] checks them; every entry point calls it.
#[derive(Debug, Clone)]
pub struct DesignOptions {
    /// Polytopic embedding of `e^{Av}` (default: the residue box of §4.1,
    /// `EmbeddingMethod::Residue` with [`ResidueOptions::default`] but the tail tolerance
    /// [`TAIL_TOLERANCE`]).
    pub embedding: EmbeddingMethod,
    /// Number of equal sub-intervals of `[T1, T2]` whose vertex sets are united (default 1 = the
    /// paper's construction; more pieces reduce conservatism at a linear cost in vertices).
    pub pieces: usize,
    /// LMI imposed at each vertex: (41) as printed (the paper's construction, as its
    /// reproduction uses) or its equivalent reduced `2n × 2n` form (default: the same feasible
    /// set at a fraction of the cost; [`LmiForm`]). The problem as given is solved in this form
    /// whatever its output units, the normal forms always in the reduced one.
    pub form: LmiForm,
    /// Margin problem: solver settings, verification safety factor, normalisation (default
    /// `‖·‖₂ ≤ 1` on every variable, margin cap 1; lossless since (41) is homogeneous).
    pub lmi: FeasibilityOptions,
    /// Grid verification of (12) (default 2801 points, relative tolerance `1e-9`).
    pub verify: VerifyOptions,
    /// Remark 3 precheck (design only; default 1001 grid points plus the aliasing instants).
    pub detectability: DetectabilityOptions,
    /// With the residue embedding, whether the normal forms are tried once more with the
    /// Taylor polytope when no form certifies with the residue box (default `false`: opt-in,
    /// see the module docs). Design only (not [`analyse`] or [`min_trace_certificate`]).
    pub taylor_fallback: bool,
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
            embedding: EmbeddingMethod::Residue(ResidueOptions {
                tail_tolerance: TAIL_TOLERANCE,
                ..ResidueOptions::default()
            }),
            pieces: 1,
            form: LmiForm::Reduced,
            lmi: FeasibilityOptions::default(),
            verify: VerifyOptions::default(),
            detectability: DetectabilityOptions::default(),
            taylor_fallback: false,
        }
    }
}

/// The tail tolerance of the residue expansion in a design (relative to the largest
/// `‖e^{Av}‖_F` on the window; the embedding's own default is `1e-13`): only expansions that do
/// not end (clusters of distinct eigenvalues, e.g. the power series of the whole spectrum on a
/// short window, whose powers are chosen for this tolerance in coordinates in which `A` is normal,
/// see `sporadic_embed::residue`) are truncated, each dropped moment halving the vertex count. The
/// remainder `δ` it leaves is covered by the margin when LMI (41) holds at the vertices by more
/// than `2‖P‖₂δ` (`strictly_negative`; with `‖P‖₂ ≤ 1` and `δ ≈ 10⁻⁹‖e^{Av}‖_F` far below the
/// margins of a certified window), and by the robust form of (41) otherwise.
pub const TAIL_TOLERANCE: f64 = 1e-9;

/// The LMI certificate of a design or analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct Certificate {
    /// Lyapunov matrix `P ≻ 0` of (12)/(13) (for a design, the product `RᵀR` of
    /// [`Certificate::factor`] rounded to doubles).
    pub p: Mat<f64>,
    /// For a design, the upper-triangular factor `R` (positive diagonal) with `P = RᵀR` exactly:
    /// the certificate the check of (12) verified ([`crate::verify_factor`]). A certificate at
    /// the end of a long window of an unstable plant can have `κ(P)` near `1/u`, where `P`
    /// rounded to doubles does not determine its smallest eigenvalue, while `R`
    /// (`κ(R) = √κ(P)`) still determines `P`. `None` for an analysis (its `P` is checked as
    /// given, [`crate::verify()`]).
    pub factor: Option<Mat<f64>>,
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

/// Solves the margin problem of LMI (41) at `vertices` with remainder `delta`; with
/// `certifies` (the same vertices, with their error bound), the returned flag says whether the
/// returned point passes `strictly_negative` on that set. A window search's probe on many
/// vertices ([`ACTIVE_FROM`]) solves it on the vertices found to bind
/// ([`crate::active::solve_binding`]).
fn solve_on(
    plant: &Plant,
    (vertices, delta): (&[Mat<f64>], f64),
    gain: GainTerm,
    (options, form): (&DesignOptions, LmiForm),
    cache: &mut LmiCache,
    certifies: Option<&VertexSet<'_>>,
) -> Result<(LmiResult, bool), Error> {
    let mut at = |imposed: &[Mat<f64>]| {
        let (options, gain) = ((options, form), gain.clone());
        solve_at(plant, (imposed, delta), gain, options, cache, certifies)
    };
    match certifies {
        Some(set) if options.lmi.stop_when_verified && vertices.len() >= ACTIVE_FROM => {
            solve_binding(plant, set, at)
        }
        _ => at(vertices),
    }
}

/// Builds (or re-uses, when one of the cached instances fits the vertex count and the sign of
/// the remainder) the margin-problem instance of LMI (41) and solves it.
fn solve_at(
    plant: &Plant,
    (vertices, delta): (&[Mat<f64>], f64),
    gain: GainTerm,
    (options, form): (&DesignOptions, LmiForm),
    cache: &mut LmiCache,
    certifies: Option<&VertexSet<'_>>,
) -> Result<(LmiResult, bool), Error> {
    budget_left()?;
    let lmis = &mut cache.lmis;
    let reusable = lmis
        .iter()
        .position(|lmi| lmi.fits(plant, vertices.len(), delta, form));
    let lmi = match reusable {
        Some(k) => {
            let mut lmi = lmis.remove(k);
            lmi.set_data(plant, vertices, delta)?;
            lmi
        }
        None => Lmi41::new(
            plant,
            vertices,
            delta,
            gain,
            form,
            Objective::Margin(&options.lmi),
        )?,
    };
    if lmis.len() >= CACHED_INSTANCES {
        lmis.remove(0);
    }
    lmis.push(lmi);
    let lmi = lmis.last_mut().expect("pushed above");
    let Some(set) = certifies else {
        return Ok((lmi.solve()?, false));
    };
    // Every iterate with a positive margin is tested for (41) holding by more than rounding and
    // the embedding's error (`strictly_negative`), a sound certificate that the LMI layer's
    // verification threshold (relative to the margin problem's normalisation) passes much
    // later, if at all. A probe of a window search, which needs a certificate and not the
    // largest margin, ends at the first such iterate; a design goes on to the optimal margin and
    // keeps the last such iterate for the case that the optimal point itself is no certificate
    // (the margin measures (41) against the normalisation, not against rounding), so that a
    // design certifies every window a probe certifies.
    let stop = options.lmi.stop_when_verified;
    let mut last: Option<Point41> = None;
    let mut first = 0;
    let r = lmi.solve_accepting(&mut |point| {
        let at = (point.p.as_ref(), point.f.as_ref(), point.j.as_ref());
        if !strictly_negative(plant, set, at, &mut first) {
            return false;
        }
        if !stop {
            last = Some(point);
        }
        stop
    })?;
    let mut certified = |r: &LmiResult| {
        r.margin.is_some_and(|t| t > 0.0)
            && strictly_negative(
                plant,
                set,
                (r.p.as_ref(), r.f.as_ref(), r.j.as_ref()),
                &mut first,
            )
    };
    Ok(match last {
        _ if certified(&r) => (r, true),
        Some(point) => (
            point.into_result(
                r,
                "the last interior-point iterate at which (41) holds at every vertex by more \
                 than rounding and the embedding's error (the optimal point does not)",
            ),
            true,
        ),
        None => (r, false),
    })
}

/// What a window search keeps across its probes.
#[derive(Default)]
pub(crate) struct LmiCache {
    /// Compiled LMIs (41), each re-used with new vertices and a new output matrix while the
    /// orders, the vertex count, the sign of the remainder and the form match; at most
    /// [`CACHED_INSTANCES`], the least recently used dropped first.
    lmis: Vec<Lmi41>,
    /// The normal form (and whether with the Taylor fallback) that certified the last
    /// certified probe, tried first at the next one.
    preferred: Option<(normalise::Coordinates, bool)>,
    /// Whether the certificate passes of the window being designed are made or not wanted:
    /// they are made with the window's own embedding, not again with a refined one, whose
    /// vertex count makes them costly and which could only reach the precision limit of the
    /// plant's coordinates again ([`crate::refine`] clears this when it starts a window and
    /// sets it before the refined design).
    pub certificate_pass_made: bool,
    /// The undecided solves of the window being designed (one per form at most).
    undecided: Vec<Undecided>,
}

impl LmiCache {
    /// The cache of a window search: its first probe tries the modal form first
    /// ([`normalise::modal`], where there is one), which is canonical and normal, so that
    /// the search does not solve the problem as given at every probe before it where the data
    /// are far from normal (`eight-state-modal` in coordinates `x = Tz`: each probe near the end
    /// of the window failed as given before the modal form certified it). The verdicts do not
    /// depend on the order; `design` keeps the problem as given first (the paper's
    /// construction).
    pub(crate) fn for_search() -> Self {
        Self {
            preferred: Some((normalise::Coordinates::Modal, false)),
            ..Self::default()
        }
    }
}

/// Compiled instances of LMI (41) kept by a window search: one per form of the problem tried
/// at every probe (the data as given, the modal, Gramian and diagonal normal forms of
/// [`crate::normalise`], and the three with the Taylor fallback), whose embeddings have in
/// general different vertex counts.
const CACHED_INSTANCES: usize = 7;

/// The options of the Taylor fallback (see the module docs) for `plant` on `window`, whose
/// normal forms are `forms`: `None` unless it is asked for and the embedding of `options` is
/// the residue box.
///
/// The order `N` is the same for every equivalent problem, so that the vertices
/// `e^{A T1} Σ_{k ≤ j} (Ah)^k/k!` of the normal forms of equivalent problems are similar to each
/// other (and (41) at them equivalent): it is the smallest order whose tail bound
/// `x^{N+1}/(N+1)!·e^x` is at most [`TAYLOR_FALLBACK_TAIL`], with `x = ‖A₁‖₂h₁` in the Gramian
/// form (`A₁`, `h₁` its matrix and window length; the form is unique up to an orthogonal change of
/// coordinates, which leaves `‖A₁‖₂` unchanged), at most [`TaylorOptions::max_order`] (also when
/// there is no Gramian form). The remainder bound of the embedding is rigorous in the coordinates
/// of each form and handled by the robust form of (41), as for any remainder.
fn taylor_fallback(
    plant: &Plant,
    window: &SamplingWindow,
    forms: &[normalise::Scaling],
    options: &DesignOptions,
) -> Option<DesignOptions> {
    if !(options.taylor_fallback && matches!(options.embedding, EmbeddingMethod::Residue(_))) {
        return None;
    }
    let max_order = TaylorOptions::default().max_order;
    let x = forms
        .iter()
        .find(|s| s.coordinates == normalise::Coordinates::Gramian)
        .and_then(|s| Some((s.plant(plant)?, s.window(window)?)))
        .and_then(|(p, w)| {
            let norm = p.a().singular_values().ok()?.first().copied()?;
            Some(norm * (w.t2() - w.t1()))
        })
        .filter(|x| x.is_finite());
    let order = x.map_or(max_order, |x| {
        // x^{N+1}/(N+1)! by its recurrence, times e^x.
        let (mut order, mut term) = (0usize, x);
        while term * x.exp() > TAYLOR_FALLBACK_TAIL && order < max_order {
            order += 1;
            term *= x / (order + 1) as f64;
        }
        order
    });
    Some(DesignOptions {
        embedding: EmbeddingMethod::Taylor(TaylorOptions {
            order: TaylorOrder::Fixed(order),
            ..TaylorOptions::default()
        }),
        ..options.clone()
    })
}

/// The bound on the scaled tail `Σ_{k > N} x^k/k!` of the Gramian form below which the order of
/// the Taylor fallback is taken ([`DesignOptions::taylor_fallback`]).
pub const TAYLOR_FALLBACK_TAIL: f64 = 1e-12;

/// Whether `d` was certified with the Taylor fallback.
fn by_taylor(d: &Design) -> bool {
    matches!(d.embedding.method(), sporadic_embed::Method::Taylor { .. })
}

fn certificate_of(r: &LmiResult, factor: Option<Mat<f64>>) -> Certificate {
    Certificate {
        p: r.p.clone(),
        factor,
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
    design_cached(plant, window, options, &mut LmiCache::default())
}

/// [`design`] with re-usable compiled LMIs and the form that certified last (used by the window
/// searches, see [`crate::window`]).
pub(crate) fn design_cached(
    plant: &Plant,
    window: &SamplingWindow,
    options: &DesignOptions,
    cache: &mut LmiCache,
) -> Result<Design, Error> {
    let start = Instant::now();
    options.validate()?;
    cache.undecided.clear();
    let forms = normalise::scalings(plant, window);
    let longer = forms
        .iter()
        .all(|s| s.coordinates != normalise::Coordinates::Gramian)
        .then(|| normalise::longer_unit_gramian(plant, window))
        .flatten();
    let detectability = detectability_any(
        forms.iter().chain(&longer),
        plant,
        window,
        &options.detectability,
    )?;
    // The problem as given (the paper's embedding, outputs in units of their largest
    // coefficient: `normalise::Scaling::given`, the vertex LMI in the options' form), then the
    // normal forms of `crate::normalise`: the modal and Gramian forms are the same for every
    // change of units or coordinates of the user's data, the diagonal form for every change of
    // units. The verdict (certified when any of them is) does not depend on the order, only
    // which certificate is returned.
    let context = (start, &detectability);
    // In a window search the normal form that certified the previous probe is tried first: a
    // nearby window is most often certified by the same form, and the others are then not
    // solved. Its failure is no verdict by itself (the verdict and the reason reported are
    // those of the loop below, which skips it; the Gramian form's infeasibility is kept for
    // that verdict).
    let taylor = taylor_fallback(plant, window, &forms, options);
    let preferred = cache.preferred.and_then(|(c, t)| {
        let k = forms.iter().position(|s| s.coordinates == c)?;
        Some((k, t))
    });
    // The failure of the Gramian form (default options), for the verdict.
    let mut gramian_failure: Option<Error> = None;
    let gramian = |k: usize| forms[k].coordinates == normalise::Coordinates::Gramian;
    if let Some((k, t)) = preferred
        && let Some(o) = if t { taylor.as_ref() } else { Some(options) }
    {
        match attempt(plant, window, o, cache, &forms[k], context) {
            Ok(d) => return Ok(d),
            Err(f) if !t && gramian(k) => gramian_failure = Some(f),
            Err(_) => {}
        }
    }
    let given = normalise::Scaling::given(plant);
    let mut result = attempt(plant, window, options, cache, &given, context);
    for (k, scaling) in forms.iter().enumerate() {
        if preferred == Some((k, false)) {
            continue;
        }
        result = match result {
            // Any failure of a normal form (even a numerical one that is no verdict) leaves
            // the verdict of the problem as given, but for the Gramian form's infeasibility
            // (below).
            Err(e) if e.reason().is_some() => {
                attempt(plant, window, options, cache, scaling, context).map_err(|f| {
                    if gramian(k) {
                        gramian_failure = Some(f);
                    }
                    e
                })
            }
            done => {
                result = done;
                break;
            }
        };
    }
    // When every form failed, the verdict is the Gramian form's infeasibility: it is the same
    // in every unit and coordinates, while the data as given are not (a
    // two-wheeled robot refused at [0.002, 1.4] s as `infeasible_lmi` was `solver_inconclusive`
    // at [2, 1400] ms, and a window search in milliseconds reported a margin threshold of 6.9
    // for its failing probe, 3.4e-4 in seconds, beside certified margins of 1e-9).
    // An infeasible or inconclusive solve of the Gramian form replaces an infeasible or
    // inconclusive solve of the data as given (a precision-limit or verification verdict of the
    // data is kept, and so is every verdict when the time budget ran out, whose failures say
    // nothing of the form); the refinement (`crate::refine`) then runs exactly where it ran
    // before. (The same robot at [0.002, 1.4] s and [2, 1400] ms: the Gramian form's solve ends
    // `almost_optimal` with its margin undecided in both units, while the data as given were
    // `infeasible_lmi` in seconds and `solver_inconclusive` in milliseconds.)
    if let (Err(e), Some(f @ (Error::Infeasible { .. } | Error::Inconclusive { .. }))) =
        (&result, gramian_failure)
        && matches!(e, Error::Infeasible { .. } | Error::Inconclusive { .. })
        && !sporadic_sdp::budget::exhausted()
    {
        result = Err(in_gramian_form(f));
    }
    // Every form failed: those whose margin was undecided are solved once more in the
    // coordinates of their own certificates (`crate::certificate`), the Gramian form first,
    // until one gives a certificate; once per window.
    if let Err(e) = &result
        && e.reason().is_some()
        && !cache.certificate_pass_made
        && !cache.undecided.is_empty()
    {
        cache.certificate_pass_made = true;
        let mut undecided = std::mem::take(&mut cache.undecided);
        // The Gramian form first (it is the same for every change of units or coordinates, so
        // its pass is too), then the others, the largest margin first.
        let not_gramian = |u: &Undecided| u.scaling.coordinates != normalise::Coordinates::Gramian;
        undecided.sort_by(|a, b| {
            not_gramian(a)
                .cmp(&not_gramian(b))
                .then(b.margin.partial_cmp(&a.margin).unwrap_or(Ordering::Equal))
        });
        for u in &undecided {
            if sporadic_sdp::budget::exhausted() {
                break;
            }
            // The first certificate that passes the check of (12) ends the passes; one at the
            // precision limit is kept as the verdict unless a later one passes; one whose
            // check fails for another reason leaves the verdict of the forms. (Each form's
            // pass gives another certificate, checked as its own factor: one failing does not
            // make the next fail.)
            if let Some((r, embedding, scaling)) = certificate_pass(u, options, cache) {
                match finish((plant, window, options), (r, embedding, scaling), context) {
                    Ok(d) => {
                        result = Ok(d);
                        break;
                    }
                    Err(e @ Error::PrecisionLimit { .. }) => {
                        if !matches!(result, Err(Error::PrecisionLimit { .. })) {
                            result = Err(e);
                        }
                    }
                    Err(_) => {}
                }
            }
        }
    }
    if let (Err(e), Some(taylor)) = (&result, &taylor)
        && e.reason().is_some()
    {
        for (k, scaling) in forms.iter().enumerate() {
            if preferred == Some((k, true)) {
                continue;
            }
            if let Ok(d) = attempt(plant, window, taylor, cache, scaling, context) {
                result = Ok(d);
                break;
            }
        }
    }
    // The problem as given, tried before the normal forms anyway, replaces a preferred form
    // only where that form was tried (a window search's modal form is kept over the short
    // windows that have none).
    if let Ok(d) = &result
        && (d.scaling.coordinates != normalise::Coordinates::Given || preferred.is_some())
    {
        cache.preferred = Some((d.scaling.coordinates, by_taylor(d)));
    }
    unless_cut(result)
}

/// `result`, or [`Error::Inconclusive`] when it is an infeasible LMI (41) and the time budget
/// has run out: a form, the certificate pass or a refinement it cut short might have certified
/// the window (the design is certified when any of them is), so the others' infeasibility is
/// no verdict on it.
pub(crate) fn unless_cut(result: Result<Design, Error>) -> Result<Design, Error> {
    match result {
        Err(Error::Infeasible { .. }) if sporadic_sdp::budget::exhausted() => {
            Err(Error::Inconclusive {
                reason: "the time budget ran out before every form of LMI (41) was decided".into(),
            })
        }
        r => r,
    }
}

/// `e` (an infeasible or inconclusive solve of LMI (41) in the Gramian normal form) with its
/// message saying so: its margin, threshold and solver status are those of that form, not of
/// the data as given.
fn in_gramian_form(e: Error) -> Error {
    const FORM: &str = "(LMI (41) in the Gramian normal form of the problem, the form that does \
                        not depend on units or coordinates)";
    match e {
        Error::Infeasible {
            margin,
            reason,
            unverified,
            threshold,
        } => Error::Infeasible {
            margin,
            reason: format!("{reason} {FORM}"),
            unverified,
            threshold,
        },
        Error::Inconclusive { reason } => Error::Inconclusive {
            reason: format!("{reason} {FORM}"),
        },
        e => e,
    }
}

/// Why the robust form of LMI (41) is infeasible without solving it (`None` when this is not
/// shown, e.g. without a remainder or when `C` has no kernel). The robust form implies (41),
/// hence (36) and `(I − LC)'X'PX(I − LC) ≺ P` of (12) with `L = F⁻¹J`, at every
/// `X = X₀ + Δ` with `X₀` in the hull of the vertices and `‖Δ‖₂ ≤ δ` (the remainder), so every
/// such `X(I − LC)` would be Schur. For a unit `z` with `Cz = 0`, `(I − LC)z = z`, and
/// `Δ = (z − X₀z)z'` gives `Xz = z`, an eigenvalue `1`, with `‖Δ‖₂ = ‖(I − X₀)z‖`. So when
/// `δ ≥ σ_min((I − X₀)Z)` (`Z` an orthonormal basis of the kernel of `C`) at some vertex or at
/// the centre of the vertices, the LMI is infeasible; the test asks for twice that, to stay
/// clear of rounding. A normal form of a badly conditioned problem can have such a
/// remainder (e.g. `10¹³` for `‖e^{Av}‖ ≈ 1`), whose margin problem would only run to the
/// iteration limit.
fn remainder_too_large(plant: &Plant, embedding: &Embedding) -> Option<String> {
    let delta = embedding.remainder_bound();
    if delta == 0.0 {
        return None;
    }
    let z = sporadic_linalg::null_space(plant.c()).ok()?;
    if z.ncols() == 0 {
        return None;
    }
    let vertices = embedding.vertices();
    let n = plant.n();
    let centre = Mat::from_fn(n, n, |i, j| {
        vertices.iter().map(|x| x[(i, j)]).sum::<f64>() / vertices.len() as f64
    });
    let distance = |x: &Mat<f64>| {
        let d = (Mat::<f64>::identity(n, n) - x) * &z;
        d.singular_values()
            .ok()
            .and_then(|s| s.last().copied())
            .unwrap_or(f64::INFINITY)
    };
    let nearest = vertices
        .iter()
        .chain(std::iter::once(&centre))
        .map(distance)
        .fold(f64::INFINITY, f64::min);
    (delta >= 2.0 * nearest).then(|| {
        format!(
            "the remainder bound {delta:.3e} of the embedding of e^(Av) is at least twice the \
             distance {nearest:.3e} from the hull of its vertices to a matrix X with Xz = z for a \
             z in the kernel of C: the robust form of LMI (41) would make X(I − LC) Schur \
             there, which its eigenvalue 1 forbids"
        )
    })
}

/// Relative PBH margin ([`sporadic_linalg::pbh_detectability`]) at or below which the pair is
/// unobservable to working precision in the Remark 3 precheck of [`design()`], where it is
/// tested in the diagonal normal form at an interval too short to alias any modes (`v* =
/// k/(2‖A₁‖₂)`): a window is then refused whatever the other forms say. `10⁴ ε ≈ 2.2·10⁻¹²`.
/// An exactly unobservable mode written in other coordinates `x = Tz` is observable only
/// through the rounding of `TAT⁻¹` and `CT⁻¹`, with a margin of order `κ(T)·ε` (`1.5·10⁻¹⁶` for
/// `diag(1, −1)`, `C = [0, 1]` under a random `T` with `κ(T) < 10`), and the passes of the
/// Gramian form amplify that rounding into an observable direction.
pub const ROUNDING_PBH_MARGIN: f64 = 1e4 * f64::EPSILON;

/// The Remark 3 precheck in the first of the forms `forms` (the normal forms, and
/// [`normalise::longer_unit_gramian`] when they hold no Gramian form), then the next, then the
/// data as given, until one passes; when none does, the error of the form with the largest PBH
/// margin. A pass in any coordinates is evidence enough: the rank test is a numerical decision
/// on a quantity (the relative PBH margin) that changes with the coordinates, while
/// detectability itself does not (see [`normalise::longer_unit_gramian`] for a plant whose
/// diagonal form alone called the pair not detectable).
///
/// Except for a pair whose *continuous* part is unobservable to working precision: first, the
/// PBH test runs in the diagonal form (exact power-of-two scalings, the same in every unit; the
/// data as given when that form is the identity) at the single interval `v* = k/(2‖A₁‖₂)`
/// (`A₁ = kDAD⁻¹` that form's matrix), where no two eigenvalues of `A₁v*/k` differ by `2πi`, so
/// that `e^{Av*}` aliases no pair of modes: a non-decaying eigenvalue unobservable there is an
/// eigenvalue of `A` that `C` does not see, and `(e^{Av}, C)` is not detectable for any `v`. A
/// margin at most [`ROUNDING_PBH_MARGIN`] (or the options' smaller rank tolerance) there
/// refuses the window whatever the other forms say (with the error of the whole window in that
/// form, or at `v*` when that one passes). A weakly observable pair (a near-triple eigenvalue at
/// zero whose margin on a short `[T1, T1]` is `6·10⁻⁹`) has an `O(1)`-scaled margin at `v*`.
fn detectability_any<'a>(
    forms: impl Iterator<Item = &'a normalise::Scaling> + Clone,
    plant: &Plant,
    window: &SamplingWindow,
    options: &DetectabilityOptions,
) -> Result<DetectabilityReport, Error> {
    let diagonal = forms
        .clone()
        .find(|s| s.coordinates == normalise::Coordinates::Diagonal);
    let v_star = match diagonal {
        Some(d) => d
            .plant(plant)
            .map(|p| d.time / (2.0 * p.a().norm_l2()))
            .unwrap_or(f64::NAN),
        None => 1.0 / (2.0 * plant.a().norm_l2()),
    };
    if let Ok(at) = SamplingWindow::new(v_star, v_star)
        && let Err(e @ Error::NotDetectable { margin, .. }) =
            detectability_in(diagonal, plant, &at, options)
        && margin <= ROUNDING_PBH_MARGIN.min(options.pbh.rank_tol)
    {
        return match detectability_in(diagonal, plant, window, options) {
            Err(whole @ Error::NotDetectable { .. }) => Err(whole),
            _ => Err(e),
        };
    }
    let mut refusal: Option<Error> = None;
    for form in forms.map(Some).chain([None]) {
        match detectability_in(form, plant, window, options) {
            Ok(report) => return Ok(report),
            Err(e @ Error::NotDetectable { .. }) => {
                let margin = |e: &Error| match e {
                    Error::NotDetectable { margin, .. } => *margin,
                    _ => f64::NEG_INFINITY,
                };
                if refusal.as_ref().is_none_or(|r| margin(&e) > margin(r)) {
                    refusal = Some(e);
                }
            }
            Err(e) => return Err(e),
        }
    }
    Err(refusal.expect("at least the data as given was checked"))
}

/// The Remark 3 precheck on the problem in the normal form `scaling`, with the times of the
/// report and of the error in the user's unit; on the data as given without one.
fn detectability_in(
    scaling: Option<&normalise::Scaling>,
    plant: &Plant,
    window: &SamplingWindow,
    options: &DetectabilityOptions,
) -> Result<DetectabilityReport, Error> {
    let Some((np, nw, k)) =
        scaling.and_then(|s| Some((s.plant(plant)?, s.window(window)?, s.time)))
    else {
        return check_detectability(plant, window, options);
    };
    match check_detectability(&np, &nw, options) {
        Ok(mut r) => {
            r.aliasing_instants.iter_mut().for_each(|v| *v *= k);
            r.min_margin_at *= k;
            Ok(r)
        }
        Err(Error::NotDetectable {
            v,
            mu_re,
            mu_im,
            modulus,
            margin,
        }) => Err(Error::NotDetectable {
            v: v * k,
            mu_re,
            mu_im,
            modulus,
            margin,
        }),
        Err(e) => Err(e),
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
    budget_left()?;
    let given = normalise::Scaling::identity(plant.n(), plant.q());
    let (np, nw, scaling) = match (scaling.plant(plant), scaling.window(window)) {
        (Some(p), Some(w)) => (p, w, scaling),
        // Not representable (overflow): the problem as given.
        _ => (plant.clone(), *window, &given),
    };
    // An overflow inside the embedding's bounds (e.g. the residue tail bound `e^{(λ̄+‖N‖)v}`,
    // whose `‖N‖` depends on the coordinates) is a numerical failure of this form of the
    // problem, not bad input: the next form is tried.
    let embedding = match embed_split(np.a(), nw.t1(), nw.t2(), options.pieces, &options.embedding)
    {
        Err(EmbedError::Input(InputError::NonFinite { what })) if !scaling.is_identity() => {
            return Err(Error::Embed(EmbedError::Numerical(format!(
                "overflow in the embedding of e^(Av) of the normalised problem: {what}"
            ))));
        }
        other => other?,
    };
    if !embedding.remainder_bound().powi(2).is_finite() {
        return Err(Error::Embed(EmbedError::Numerical(format!(
            "the remainder bound of the embedding of e^(Av) is {:.3e}",
            embedding.remainder_bound()
        ))));
    }
    // On the data as given the residue box is the method's own polytope, and the robust (41)
    // on it is infeasible. In a normal form such a remainder is an artefact of the form's
    // rounding, not a property of the problem (a random plant of order 6 with one output: the
    // Gramian form's A, ‖A‖₂ = 35 for a spectral radius of 0.7 on its time unit, fell into
    // one cluster with the remainder 1.8e15, where the data as given and the diagonal form
    // have 256 vertices and 1.4e-9), so it is a numerical failure of that form: no verdict,
    // and not the one that replaces the data's ([`design()`]).
    if let Some(reason) = remainder_too_large(&np, &embedding) {
        return Err(if scaling.is_identity() {
            Error::Infeasible {
                margin: None,
                reason,
                unverified: false,
                threshold: None,
            }
        } else {
            Error::Embed(EmbedError::Numerical(format!(
                "{reason}, so this normal form of the problem cannot decide it"
            )))
        });
    }
    // The problem as given is solved in the form of the options (by default the reduced form,
    // vertex-wise Schur complement, order 2n, or 3n with a remainder, instead of 3n or 4n; see
    // `crate::lmi`; it has the same feasible set and costs a fraction), whatever its output
    // units; a normal form, which is not in the paper, in the reduced form. (The form of the
    // given problem was (41) as printed when every row of `C` had largest entry 1 and the
    // reduced one otherwise: a kite certified up to T2 = 2.763 with outputs in m and rad, 2.839
    // in mm and µrad.)
    let form = if scaling.coordinates == normalise::Coordinates::Given {
        options.form
    } else {
        LmiForm::Reduced
    };
    // A residue box with a remainder `δ` (a truncated expansion) is first solved without it:
    // the robust form implies (41) at the vertices, so a failure there is a failure of the
    // robust form too, and a point at which (41) holds at the vertices by more than `δ` and
    // rounding can explain (`strictly_negative`) certifies the window; only a point in between
    // needs the robust form.
    let delta = embedding.remainder_bound();
    let vertices = embedding.vertices();
    let absorb =
        delta > 0.0 && matches!(embedding.method(), sporadic_embed::Method::Residue { .. });
    let exact = if absorb { 0.0 } else { delta };
    let set = VertexSet::residue(&embedding);
    let certifies = set.as_ref();
    // `negative`: the returned point passes `strictly_negative` (tested by `solve_on` for a
    // residue box, which has a positive margin then; never for a Taylor polytope).
    let (mut r, negative) = solve_on(
        &np,
        (vertices, exact),
        GainTerm::Free,
        (options, form),
        cache,
        certifies,
    )?;
    let margin = r.margin.is_some_and(|t| t > 0.0);
    if absorb {
        r.feasible = negative;
        if margin && !r.feasible {
            let negative;
            (r, negative) = solve_on(
                &np,
                (vertices, delta),
                GainTerm::Free,
                (options, form),
                cache,
                certifies,
            )?;
            r.feasible |= negative;
        }
    } else {
        r.feasible |= negative;
    }
    if !r.feasible {
        // The vertex test is set up (and every vertex's eigenvalues computed) only for the
        // message of a refusal, before `np` moves into the undecided list.
        let rounding = match r.stats.outcome {
            Outcome::Inconclusive => None,
            _ => set.as_ref().and_then(|set| rounding_reason(&np, set, &r)),
        };
        let (unverified, threshold) = rounding
            .as_ref()
            .map_or((false, None), |&(_, above, tau)| (above, Some(tau)));
        if set.is_some()
            && undecided(&r)
            && let Some(coordinates) = CertificateCoordinates::of(r.p.as_ref())
        {
            cache.undecided.push(Undecided {
                plant: np,
                window: nw,
                margin: r.margin,
                scaling: scaling.clone(),
                coordinates,
            });
        }
        return Err(match r.stats.outcome {
            Outcome::Inconclusive => Error::Inconclusive {
                reason: r.stats.reason,
            },
            _ => Error::Infeasible {
                margin: r.margin,
                reason: rounding.map_or(r.stats.reason, |(why, _, _)| why),
                unverified,
                threshold,
            },
        });
    }
    finish(
        (plant, window, options),
        (r, embedding, scaling.clone()),
        (start, detectability),
    )
}

/// A solved form of LMI (41) mapped back to the plant's coordinates and verified on its data
/// ([`crate::verify()`]); a failed verification is [`Error::PrecisionLimit`] when
/// [`precision_limit`] says so.
fn finish(
    (plant, window, options): (&Plant, &SamplingWindow, &DesignOptions),
    (mut r, embedding, scaling): (LmiResult, Embedding, normalise::Scaling),
    (start, detectability): (Instant, &DetectabilityReport),
) -> Result<Design, Error> {
    let l = scaling.gain_back(gain_from(r.f.as_ref(), r.j.as_ref())?.as_ref());
    let factor = scaling.factor_back(r.p.as_ref());
    r.p = match &factor {
        Some(f) => factor_product(f.as_ref()),
        None => scaling.symmetric_congruence_back(r.p.as_ref()),
    };
    r.f = scaling.congruence_back(r.f.as_ref());
    r.j = scaling.multiplier_gain_back(r.j.as_ref());
    let verification = match &factor {
        Some(f) => verify_factor(plant, window, l.as_ref(), f.as_ref(), &options.verify)?,
        None => verify(plant, window, l.as_ref(), r.p.as_ref(), &options.verify)?,
    };
    if !verification.passed() {
        return Err(
            match precision_limit(
                &r,
                factor.as_ref(),
                &scaling,
                &verification,
                &options.verify,
            ) {
                Some(e) => e,
                None => verification_failed(&verification, &options.verify),
            },
        );
    }
    Ok(Design {
        certificate: certificate_of(&r, factor),
        l,
        embedding,
        verification,
        scaling,
        detectability: detectability.clone(),
        stats: r.stats,
        size: r.size,
        total_time: start.elapsed(),
    })
}

/// The solve of a form of LMI (41) whose margin was undecided ([`undecided`]) and whose `P`
/// gives usable certificate coordinates, kept for a certificate pass ([`certificate_pass`]).
pub(crate) struct Undecided {
    /// The certificate coordinates of the solve's `P`.
    coordinates: CertificateCoordinates,
    /// The plant in the form's coordinates.
    plant: Plant,
    /// The window in the form's time unit.
    window: SamplingWindow,
    /// The solve's margin `t*`.
    margin: Option<f64>,
    /// The form.
    scaling: normalise::Scaling,
}

/// `Err(Error::Inconclusive)` when the time budget of the enclosing scope
/// ([`sporadic_sdp::budget`]) is spent: the set-up of a form of the problem (its embedding and
/// the compilation of LMI (41), a large share of a design's time at order 8) is not started
/// then, as the interior-point solve itself would not be.
fn budget_left() -> Result<(), Error> {
    if sporadic_sdp::budget::exhausted() {
        return Err(Error::Inconclusive {
            reason: "the time budget ran out before LMI (41) was set up".into(),
        });
    }
    Ok(())
}

/// Why a margin solve on a residue box gave no certificate, against the rounding level of what
/// decides one (`strictly_negative`): `τ` of [`VertexTest`] at the returned point, relative to
/// the scale `s` of the blocks of (41) there. (The LMI layer's threshold `safety·tol·(1 + s')` is
/// relative to the summands `s'` of the form solved, `‖P‖‖X_i‖²` in the reduced one: with the
/// large vertices of a degenerate residue box it exceeds every margin the normalisation admits,
/// `t ≤ λmin(P) ≤ 1`, e.g. 1.357 for a free-free beam on `[0.05, 0.4]`.) The flag is `true`
/// when `t*` (the margin of the form solved) is above `τ` but the point fails the test: the
/// precision, not the window, is what failed (an unstable pitch short period on
/// `[0.01, 13.5]` s: `t* = 1.2e-8`, `τ = 9.4e-10`, largest vertex eigenvalue `−5.6e-12`).
fn rounding_reason(
    plant: &Plant,
    set: &VertexSet<'_>,
    r: &LmiResult,
) -> Option<(String, bool, f64)> {
    use sporadic_sdp::Status::{DualInfeasible, PrimalInfeasible};
    if matches!(r.stats.status, DualInfeasible | PrimalInfeasible) {
        return None; // the solver's certificate, not a threshold, decided
    }
    let t = r.margin?;
    let test = VertexTest::new(plant, set, (r.p.as_ref(), r.f.as_ref(), r.j.as_ref()))?;
    let (tau, s) = (test.tau, test.scale);
    let largest = test.largest_over(set.vertices);
    let above = t > tau;
    // The rounding level, stated alike in both refusals.
    let level = format!(
        "the verification threshold {tau:.3e}, the rounding level of LMI (41) at the returned \
         point (τ = 2‖P‖₂e + 64u·3n·s = {:.1e}·s, s = {s:.3e} the largest block norm of (41), \
         e = {:.1e} the embedding's error)",
        tau / s,
        set.error,
    );
    let message = if above {
        // The solver claims a margin it cannot show at its own point.
        format!(
            "double-precision limit: the solver's maximal common margin t* = {t:.3e} is above \
             {level}, but the largest vertex eigenvalue there is {largest:.3e}, not below −τ: \
             the margin of the form solved does not carry over to a margin of (41) that \
             rounding can resolve, which says nothing of the window's feasibility"
        )
    } else {
        format!(
            "no verifiable margin: the maximal common margin t* = {t:.3e} is at or below \
             {level}, where the largest vertex eigenvalue is {largest:.3e}, not below −τ; a \
             strictly feasible point with a smaller margin is not excluded"
        )
    };
    Some((message, above, tau))
}

/// Whether the margin `t*` of a solve that did not certify is within the solver's verification
/// threshold of zero (undecided by the solve: a new solve in other coordinates may decide it).
fn undecided(r: &LmiResult) -> bool {
    let threshold = r.stats.margin_threshold.unwrap_or(0.0);
    r.margin.is_some_and(|t| t > -threshold)
}

/// A new solve of the reduced LMI (41) in the certificate coordinates of an undecided solve's
/// `P` ([`Undecided::coordinates`]), on the residue embedding of the plant in those
/// coordinates: the point, if it passes `strictly_negative`, with its embedding and the
/// scaling composed with the coordinates. `None` when the plant or its embedding in those
/// coordinates is not finite, or the point is no certificate (the verdict is then that of the forms already solved).
fn certificate_pass(
    u: &Undecided,
    options: &DesignOptions,
    cache: &mut LmiCache,
) -> Option<(LmiResult, Embedding, normalise::Scaling)> {
    let c = &u.coordinates;
    let plant = c.plant(&u.plant)?;
    let embedding = embed_split(
        plant.a(),
        u.window.t1(),
        u.window.t2(),
        options.pieces,
        &options.embedding,
    )
    .ok()?;
    let set = VertexSet::residue(&embedding)?;
    // A solve that fails here (e.g. a non-finite value) leaves the verdict of the forms.
    let (mut r, negative) = solve_on(
        &plant,
        (set.vertices, 0.0),
        GainTerm::Free,
        (options, LmiForm::Reduced),
        cache,
        Some(&set),
    )
    .ok()?;
    negative.then(|| {
        r.feasible = true;
        let scaling = normalise::Scaling {
            certificate: true,
            ..u.scaling.then_state(&c.r, &c.r_inv)
        };
        (r, embedding, scaling)
    })
}

/// The error of a design whose LMI (41) holds in certificate coordinates but whose grid check of
/// (12) in the plant's coordinates cannot decide the certificate ([`Error::PrecisionLimit`]):
/// the spectral radius of `e^{Av}(I − LM)` (which does not involve `P`) is below one on the
/// grid, and the largest eigenvalue of (12) relative to `P` is below the check's rounding
/// allowance ([`crate::Verification::rounding`]): within rounding of zero, or a contraction the
/// check cannot resolve.
/// `None` for any other failure.
fn precision_limit(
    r: &LmiResult,
    factor: Option<&Mat<f64>>,
    scaling: &normalise::Scaling,
    v: &Verification,
    options: &VerifyOptions,
) -> Option<Error> {
    if !scaling.certificate || !v.schur_holds {
        return None;
    }
    let resolution = options.tolerance + v.rounding;
    // A contraction within the rounding allowance of none (either side of it); a value above
    // that is a resolved violation.
    if !(v.relative_max_eigenvalue < v.rounding) {
        return None;
    }
    // `κ(P) = κ(R)²` from the singular values of the factor: the eigenvalues of `P` rounded
    // to doubles do not resolve its smallest one when `κ(P)` is near `1/u`.
    let condition = match factor {
        Some(f) => crate::verify::spectral_condition(f.as_ref()).map_or(f64::INFINITY, |k| k * k),
        None => {
            let n = r.p.nrows();
            let s = r.p.self_adjoint_eigenvalues(faer::Side::Lower).ok()?;
            if s[0] > 0.0 {
                s[n - 1] / s[0]
            } else {
                f64::INFINITY
            }
        }
    };
    Some(Error::PrecisionLimit {
        margin: r.margin?,
        condition,
        relative_max_eigenvalue: v.relative_max_eigenvalue,
        rounding: v.rounding,
        tolerance: options.tolerance,
        resolution,
        max_spectral_radius: v.max_spectral_radius,
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
                unverified: false,
                threshold: None,
            },
            _ => Error::Inconclusive {
                reason: r.stats.reason,
            },
        });
    }
    let verification = verify(plant, window, l, r.p.as_ref(), &options.verify)?;
    if !verification.passed() {
        return Err(verification_failed(&verification, &options.verify));
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
pub(crate) fn verification_failed(v: &Verification, options: &VerifyOptions) -> Error {
    Error::VerificationFailed {
        relative_max_eigenvalue: v.relative_max_eigenvalue,
        resolution: options.tolerance + v.rounding,
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

/// Certifies a given gain `L` with LMI (41) where `J = FL` (see the module docs). Within a spent
/// time budget ([`sporadic_sdp::budget`]) the LMI is not set up, and the error is
/// [`Error::Inconclusive`].
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
    let (r, _) = solve_on(
        plant,
        (embedding.vertices(), embedding.remainder_bound()),
        GainTerm::Fixed(l.to_owned()),
        (options, options.form),
        &mut LmiCache::default(),
        None,
    )?;
    let (certificate, verification) = if r.feasible {
        let v = verify(plant, window, l, r.p.as_ref(), &options.verify)?;
        (Some(certificate_of(&r, None)), Some(v))
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

#[cfg(test)]
mod tests {
    use super::*;
    use sporadic_sdp::budget::{self, Budget};

    /// A form's infeasibility is the verdict while the budget lasts, and no verdict once it has
    /// run out (a form, the certificate pass or a refinement it cut might have certified).
    #[test]
    fn an_infeasibility_is_no_verdict_once_the_budget_has_run_out() {
        let infeasible = || {
            Err(Error::Infeasible {
                margin: Some(-8.6e-10),
                reason: "no verifiable margin".into(),
                unverified: false,
                threshold: None,
            })
        };
        assert!(matches!(
            unless_cut(infeasible()),
            Err(Error::Infeasible { .. })
        ));
        let cut = budget::within(Budget::until(Instant::now()), || unless_cut(infeasible()));
        assert!(matches!(cut, Err(Error::Inconclusive { .. })), "{cut:?}");
    }
}
