//! The largest certifiable window: bisection on `τmax` for a given `τmin` (Rabehi et al. 2021,
//! Table I), bracketed above by a necessary condition.
//!
//! **Necessary condition** (not in the paper). If column `j` of `C` is zero, then
//! `G e_j = e_j` for every `L` (`G = I + LC`), so column `j` of `|G|` (and of `G1 + G2 ≥ |G|`) is
//! `e_j` (resp. `≥ e_j`). In the width block of `TĀT = diag(S, A)`, `TΓT = diag(|G|, G)`, the
//! nonnegative matrix `e^{Sμ}|G|` has diagonal entry `(e^{Sμ}|G|)_jj = (e^{Sμ})_jj`, and the
//! spectral radius of a nonnegative matrix is at least its largest diagonal entry. Since (19)
//! (and (44)) forces `ρ(e^{Āμ}Γ) < 1` on the window (Remark 5), no gain can be certified once
//! `max_j (e^{Sμ})_jj ≥ 1` for some `μ ∈ [τmin, τmax]`, `j` ranging over the unmeasured states:
//! [`necessary_tau_max`] returns the first such `μ`.
//!
//! The same argument applies vertex by vertex to (44) on a polytope ([`polytope_tau_max`]): a
//! vertex whose width block is nonnegative with a diagonal entry `≥ 1` at an unmeasured state
//! excludes every gain. For the single Taylor polytope of the paper this limit is far below the
//! exact one (its low-order vertices `e^{Āτmin}(I + Āh + …)` are far from the curve).
//!
//! **Search.** The searches are thin code around the shared window search
//! [`sporadic_model::search_upper`] (a probe of the top of the bracket, then an arithmetic
//! bisection to an absolute resolution). The top is the search's upper end, capped by the
//! necessary limits (which no certificate can reach); when capped, the top probe is made just
//! below the cap (`cap − 0.9·resolution`: the pipeline often reaches the limit, and then one
//! probe settles it), otherwise at the upper end itself (a certified upper end is the answer,
//! with no failing `τmax`). Probes are full Proposition 1 runs ([`crate::synthesis`]); a probe
//! counts as feasible only when its design is certified (including the Theorem 1
//! re-verification with `Γ(L)`). Feasibility is assumed monotone in `τmax` (a design for a
//! window is valid for every sub-window), which holds for the problem itself but not
//! necessarily for a local BMI method: the result is the largest *certified* `τmax` the search
//! found, not a proven supremum (the shared search reports whether its verdicts were monotone).

use sporadic_linalg::InputError;

use faer::MatRef;
use sporadic_linalg::expm_scaled;
use sporadic_model::{
    Bracketing, Reason, SamplingWindow, SearchError, Tolerance, Verdict, WindowSearch,
    WindowSearchOptions, search_upper,
};

use crate::analysis::{AnalysisOptions, analyse_gain};
use crate::error::Error;
use crate::ipr::{MetzlerDecomposition, pair_blocks};
use crate::polytope::{PolytopeOptions, taylor_polytope};
use crate::synthesis::{Design, DesignStatus, SynthesisOptions, synthesise_from};
use crate::system::Plant;

/// The states that no output sees (zero columns of `C`).
fn unmeasured_states(plant: &Plant) -> Vec<usize> {
    let c = plant.c();
    (0..plant.n())
        .filter(|&j| (0..c.nrows()).all(|i| c[(i, j)] == 0.0))
        .collect()
}

/// Whether the nonnegative matrix `m` (the width block of `e^{Āμ}` or of a vertex) has
/// `m_jj ≥ 1` for an unmeasured `j`: then `ρ(mΓ_w) ≥ 1` for every admissible width jump `Γ_w`.
/// Matrices with a negative entry give no conclusion.
fn blocks_every_gain(m: MatRef<'_, f64>, unmeasured: &[usize]) -> bool {
    let nonnegative = (0..m.ncols()).all(|j| (0..m.nrows()).all(|i| m[(i, j)] >= 0.0));
    nonnegative && unmeasured.iter().any(|&j| m[(j, j)] >= 1.0)
}

fn check_range(tau_min: f64, horizon: f64) -> Result<(), Error> {
    if !(tau_min > 0.0 && tau_min.is_finite()) {
        return Err(InputError::parameter("tau_min", tau_min, "must be finite and > 0").into());
    }
    if !(horizon > tau_min && horizon.is_finite()) {
        return Err(
            InputError::parameter("horizon", horizon, "must be finite and > tau_min").into(),
        );
    }
    Ok(())
}

/// The first `τ ∈ [tau_min, horizon]` where `blocked(τ)` holds: a scan with step `0.01` (or
/// `τmin/10` when smaller; at least `(horizon − τmin)/max_steps` when given) and a bisection to `1e-8` inside the first blocked step; the returned
/// point is one where `blocked` was evaluated true.
fn first_blocked(
    tau_min: f64,
    horizon: f64,
    max_steps: Option<usize>,
    mut blocked: impl FnMut(f64) -> Result<bool, Error>,
) -> Result<Option<f64>, Error> {
    if blocked(tau_min)? {
        return Ok(Some(tau_min));
    }
    let mut step = 0.01f64.min(0.1 * tau_min);
    if let Some(k) = max_steps {
        // A coarser scan may miss a first blocked point, never report an unblocked one.
        step = step.max((horizon - tau_min) / k.max(1) as f64);
    }
    let mut lo = tau_min;
    loop {
        let hi = (lo + step).min(horizon);
        if blocked(hi)? {
            let (mut a, mut b) = (lo, hi);
            while b - a > 1e-8 {
                let mid = 0.5 * (a + b);
                if blocked(mid)? {
                    b = mid;
                } else {
                    a = mid;
                }
            }
            return Ok(Some(b));
        }
        if hi >= horizon {
            return Ok(None);
        }
        lo = hi;
    }
}

/// The necessary upper limit on `τmax` for the exact condition (19) (module docs): the first
/// `μ ≥ τmin` with `max_j (e^{Sμ})_jj ≥ 1` over the states `j` that `C` does not see; `None` if
/// every state is measured or the growth stays below 1 up to `horizon`.
///
/// # Errors
/// Non-finite or non-positive `tau_min`, `horizon ≤ tau_min`, or a failure of the matrix
/// exponential.
pub fn necessary_tau_max(plant: &Plant, tau_min: f64, horizon: f64) -> Result<Option<f64>, Error> {
    necessary_limit(plant, tau_min, horizon, None)
}

/// [`necessary_tau_max`] with a scan of at most `max_steps` steps (when given): a coarser scan
/// may return a later blocked point than the first one, which is still a valid limit.
pub(crate) fn necessary_limit(
    plant: &Plant,
    tau_min: f64,
    horizon: f64,
    max_steps: Option<usize>,
) -> Result<Option<f64>, Error> {
    check_range(tau_min, horizon)?;
    let unmeasured = unmeasured_states(plant);
    if unmeasured.is_empty() {
        return Ok(None);
    }
    let s = MetzlerDecomposition::new(plant.a())?.width_matrix();
    first_blocked(tau_min, horizon, max_steps, |mu| {
        Ok(blocks_every_gain(
            expm_scaled(s.as_ref(), mu)?.as_ref(),
            &unmeasured,
        ))
    })
}

/// The same limit for (44) on the Taylor polytope of [`crate::polytope`]: the first `τmax` for
/// which a vertex `M_i` of the polytope of `[τmin, τmax]` has a nonnegative width block (first
/// block of `pair_blocks(M_i)`) with a unit-or-larger diagonal entry at an unmeasured state. Then
/// `ρ(M_iΓ(G1, G2)) ≥ 1` for every admissible `(G1, G2)`, which (44) at that vertex excludes. No
/// solver can certify (44) on that polytope for this or (in practice) larger windows.
///
/// # Errors
/// As [`necessary_tau_max`], plus invalid polytope options or an embedding failure.
pub fn polytope_tau_max(
    plant: &Plant,
    tau_min: f64,
    polytope: &PolytopeOptions,
    horizon: f64,
) -> Result<Option<f64>, Error> {
    check_range(tau_min, horizon)?;
    polytope.validate()?;
    let unmeasured = unmeasured_states(plant);
    if unmeasured.is_empty() {
        return Ok(None);
    }
    let a_bar = MetzlerDecomposition::new(plant.a())?.a_bar;
    first_blocked(tau_min, horizon, None, |tau_max| {
        let window = SamplingWindow::new(tau_min, tau_max)?;
        let poly = taylor_polytope(a_bar.as_ref(), &window, polytope)?;
        for v in poly.vertices() {
            let (width_block, _) = pair_blocks(v.as_ref())?;
            if blocks_every_gain(width_block.as_ref(), &unmeasured) {
                return Ok(true);
            }
        }
        Ok(false)
    })
}

/// Options of [`largest_tau_max`] (defaults: [`TauMaxOptions::default`]).
#[derive(Debug, Clone)]
pub struct TauMaxOptions {
    /// Stop when the bracket `(certified, refuted)` is at most this wide. Default `0.01`.
    pub resolution: f64,
    /// Upper end of the search (capped by the necessary limits). Default `5`.
    pub upper: f64,
    /// Largest number of probes (Proposition 1 runs). Default 60.
    pub max_probes: usize,
    /// Options of every probe.
    pub synthesis: SynthesisOptions,
}

impl Default for TauMaxOptions {
    fn default() -> Self {
        Self {
            resolution: 0.01,
            upper: 5.0,
            max_probes: 60,
            synthesis: SynthesisOptions::default(),
        }
    }
}

impl TauMaxOptions {
    /// Checks every field; the error names the offending one.
    ///
    /// # Errors
    /// [`Error::Input`] for a non-positive or non-finite `resolution` or `upper`, fewer than two
    /// probes, or invalid synthesis options.
    pub fn validate(&self) -> Result<(), Error> {
        check_resolution(self.resolution)?;
        if !(self.upper > 0.0 && self.upper.is_finite()) {
            return Err(
                InputError::parameter("upper", self.upper, "must be finite and > 0").into(),
            );
        }
        if self.max_probes < 2 {
            return Err(InputError::parameter(
                "max_probes",
                self.max_probes as f64,
                "at least two probes are needed",
            )
            .into());
        }
        self.synthesis.validate()
    }
}

fn check_resolution(resolution: f64) -> Result<(), Error> {
    if !(resolution > 0.0 && resolution.is_finite()) {
        return Err(
            InputError::parameter("resolution", resolution, "must be finite and > 0").into(),
        );
    }
    Ok(())
}

/// The shared search's options for a probe of the top followed by an arithmetic bisection to
/// `resolution`.
fn bisection(resolution: f64, max_probes: usize) -> WindowSearchOptions {
    WindowSearchOptions {
        bracketing: Bracketing::Scan { points: 1 },
        tolerance: Tolerance::Absolute(resolution),
        max_probes,
    }
}

/// Why a `τmax` at or beyond the necessary limit `cap` is not certified (no probe is run): a
/// necessary condition of the design inequalities fails there, so they have no feasible point.
/// The plant may well be detectable at `cap`; it is the interval-width contraction that no gain
/// achieves.
pub(crate) fn beyond_cap(cap: f64, what: &str) -> Reason {
    Reason::InfeasibleLmi {
        message: format!(
            "{what} fails at mu = {cap:.6}: no gain makes the interval width of an unmeasured state contract over a sampling interval of that length (e^(S mu) |I + LC| has a diagonal entry >= 1 whatever L), so no window reaching it is certifiable"
        ),
    }
}

/// The search errors of this crate.
fn search_error(e: SearchError<Error>) -> Error {
    match e {
        SearchError::Input(e) => e.into(),
        SearchError::Probe(e) => e,
    }
}

/// Result of [`largest_tau_max`]: the shared search with the necessary limits around it.
#[derive(Debug, Clone)]
pub struct TauMaxSearch {
    /// `τmin`.
    pub tau_min: f64,
    /// The necessary limit of [`necessary_tau_max`] (no certificate of (19) can reach it).
    pub necessary_limit: Option<f64>,
    /// The limit of [`polytope_tau_max`] for the polytope of the probes (no certificate of (44)
    /// on that polytope can reach it).
    pub polytope_limit: Option<f64>,
    /// The smaller of the two limits when it is below the search's upper end: the top of the
    /// bracket, known not to be certifiable.
    pub cap: Option<f64>,
    /// The shared search (its probes, bracket and end).
    pub search: WindowSearch,
    /// The design at the largest certified `τmax`.
    pub design: Option<Design>,
}

impl TauMaxSearch {
    /// Largest `τmax` with a certified design (`None`: not even `[τmin, τmin]`).
    pub fn certified(&self) -> Option<f64> {
        self.search.best
    }

    /// Smallest `τmax` known not to be certifiable: the first failed probe above the certified
    /// one, or the cap when the search reached its capped top (`None`: the upper end itself is
    /// certified).
    pub fn refuted(&self) -> Option<f64> {
        self.search.first_failure.or(self.cap)
    }
}

/// Largest certified `τmax ≤ options.upper` for the window `[tau_min, τmax]` (module docs).
///
/// # Errors
/// Invalid `tau_min` or options, or a failure of a numerical kernel or of the LMI layer.
pub fn largest_tau_max(
    plant: &Plant,
    tau_min: f64,
    options: &TauMaxOptions,
) -> Result<TauMaxSearch, Error> {
    options.validate()?;
    SamplingWindow::new(tau_min, options.upper)?;
    let exact_limit = necessary_tau_max(plant, tau_min, options.upper)?;
    let vertex_limit =
        polytope_tau_max(plant, tau_min, &options.synthesis.polytope, options.upper)?;
    let cap = [exact_limit, vertex_limit]
        .into_iter()
        .flatten()
        .reduce(f64::min)
        .filter(|c| *c < options.upper);
    // The top probe: just below a cap, or the upper end itself.
    let top = match cap {
        Some(c) => (c - 0.9 * options.resolution).max(tau_min),
        None => options.upper,
    };
    let mut design = None;
    let search = search_upper(
        tau_min,
        top,
        &bisection(options.resolution, options.max_probes),
        |tau_max| -> Result<Verdict, Error> {
            if let Some(c) = cap
                && tau_max >= c
            {
                return Ok(Verdict::failed(beyond_cap(
                    c,
                    "the necessary condition of (19)/(44)",
                )));
            }
            let window = SamplingWindow::new(tau_min, tau_max)?;
            let d = synthesise_from(plant, &window, None, &options.synthesis)?;
            Ok(match &d.status {
                DesignStatus::Certified => {
                    let v = Verdict::certified(Some(d.bmi.margin()));
                    design = Some((tau_max, d));
                    v
                }
                DesignStatus::NotCertified(why) => Verdict::failed(why.reason()),
            })
        },
    )
    .map_err(search_error)?;
    let design = design
        .filter(|(t, _)| Some(*t) == search.best)
        .map(|(_, d)| d);
    Ok(TauMaxSearch {
        tau_min,
        necessary_limit: exact_limit,
        polytope_limit: vertex_limit,
        cap,
        search,
        design,
    })
}

/// Largest `τmax ≤ upper` at which Theorem 1 is certified for a **given** gain `L`
/// ([`analyse_gain`]): the shared search (probe of the top, then arithmetic bisection to
/// `resolution`), the top being `upper` or, below it, [`necessary_tau_max`] (valid for every
/// gain; the probe there fails without an analysis).
///
/// # Errors
/// Invalid `tau_min`/`upper`/`resolution`, a bad gain, or a failure of the analysis.
pub fn largest_tau_max_for_gain(
    plant: &Plant,
    l: MatRef<'_, f64>,
    tau_min: f64,
    upper: f64,
    resolution: f64,
    options: &AnalysisOptions,
) -> Result<WindowSearch, Error> {
    check_resolution(resolution)?;
    SamplingWindow::new(tau_min, upper)?;
    let cap = necessary_tau_max(plant, tau_min, upper)?;
    search_upper(
        tau_min,
        cap.unwrap_or(upper),
        &bisection(resolution, usize::MAX),
        |tau_max| -> Result<Verdict, Error> {
            if let Some(c) = cap
                && tau_max >= c
            {
                return Ok(Verdict::failed(beyond_cap(c, "the necessary condition of (19)")));
            }
            let a = analyse_gain(plant, &SamplingWindow::new(tau_min, tau_max)?, l, options)?;
            Ok(if a.certified {
                Verdict::certified(Some(a.vertex_margin - a.remainder_effect))
            } else {
                Verdict::failed(Reason::VerificationFailed {
                    tau: (!a.grid.certified).then_some(a.grid.at),
                    message: format!(
                        "Theorem 1 not certified for the gain: polytope {} (vertex margin {:.3e}, remainder effect {:.3e}), grid bound {:.3e}",
                        a.polytope_certified, a.vertex_margin, a.remainder_effect, a.grid.bound
                    ),
                })
            })
        },
    )
    .map_err(search_error)
}
