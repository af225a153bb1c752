//! The largest certifiable window: bisection on `τmax` for a given `τmin` (Rabehi et al. 2021,
//! Table I), bracketed above by a necessary condition.
//!
//! **Necessary condition** (spec 004 §8 A6, not in the paper). If column `j` of `C` is zero, then
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
//! **Bisection.** The bracket starts at `[τmin, min(limits, upper)]`; its top is probed first
//! (the pipeline often reaches the limit, and then one probe settles it), then the bracket is
//! bisected down to the resolution. Probes are full Proposition 1 runs ([`crate::synthesis`]); a
//! probe counts as feasible only when its design is certified (including the Theorem 1
//! re-verification with `Γ(L)`). Feasibility is assumed monotone in `τmax` (a design for a window is valid for every
//! sub-window), which holds for the problem itself but not necessarily for a local BMI method:
//! the result is the largest *certified* `τmax` the bisection found, not a proven supremum.

use sporadic_linalg::InputError;
use std::time::{Duration, Instant};

use faer::MatRef;
use sporadic_linalg::expm_scaled;

use crate::analysis::{AnalysisOptions, analyse_gain};
use crate::error::Error;
use crate::ipr::{MetzlerDecomposition, pair_blocks};
use crate::polytope::{PolytopeOptions, taylor_polytope};
use crate::synthesis::{Design, SynthesisOptions, synthesise_from};
use crate::system::{Plant, Window};

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
/// `τmin/10` when smaller) and a bisection to `1e-8` inside the first blocked step; the returned
/// point is one where `blocked` was evaluated true.
fn first_blocked(
    tau_min: f64,
    horizon: f64,
    mut blocked: impl FnMut(f64) -> Result<bool, Error>,
) -> Result<Option<f64>, Error> {
    if blocked(tau_min)? {
        return Ok(Some(tau_min));
    }
    let step = 0.01f64.min(0.1 * tau_min);
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
    check_range(tau_min, horizon)?;
    let unmeasured = unmeasured_states(plant);
    if unmeasured.is_empty() {
        return Ok(None);
    }
    let s = MetzlerDecomposition::new(plant.a())?.width_matrix();
    first_blocked(tau_min, horizon, |mu| {
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
    first_blocked(tau_min, horizon, |tau_max| {
        let window = Window::new(tau_min, tau_max)?;
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

/// Shrinks the bracket `(lo, hi)` (certified, refuted) to `resolution` by bisection; `probe`
/// returns whether its argument is certified.
fn bisect(
    mut lo: f64,
    mut hi: f64,
    resolution: f64,
    mut probe: impl FnMut(f64) -> Result<bool, Error>,
) -> Result<(), Error> {
    while hi - lo > resolution {
        let mid = 0.5 * (lo + hi);
        if probe(mid)? {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(())
}

/// Settings of [`largest_tau_max`].
#[derive(Debug, Clone)]
pub struct WindowSearchOptions {
    /// Stop when the bracket `(certified, refuted)` is at most this wide. Default `0.01`.
    pub resolution: f64,
    /// Upper end of the search when the necessary condition gives none. Default `5`.
    pub upper: f64,
    /// Settings of every probe.
    pub synthesis: SynthesisOptions,
}

impl Default for WindowSearchOptions {
    fn default() -> Self {
        Self {
            resolution: 0.01,
            upper: 5.0,
            synthesis: SynthesisOptions::default(),
        }
    }
}

/// One probe of the bisection.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// The `τmax` probed.
    pub tau_max: f64,
    /// Whether the design was certified.
    pub certified: bool,
    /// Best `max_i λmax(Ψ_i)` reached.
    pub best_t: f64,
    /// Number of LMI steps.
    pub steps: usize,
    /// Wall time.
    pub time: Duration,
}

/// Result of [`largest_tau_max`].
#[derive(Debug, Clone)]
pub struct WindowSearch {
    /// `τmin`.
    pub tau_min: f64,
    /// The necessary limit of [`necessary_tau_max`] (no certificate of (19) can reach it).
    pub necessary_limit: Option<f64>,
    /// The limit of [`polytope_tau_max`] for the polytope of the probes (no certificate of (44)
    /// on that polytope can reach it).
    pub polytope_limit: Option<f64>,
    /// Largest `τmax` with a certified design (`None`: not even `[τmin, τmin]`).
    pub certified: Option<f64>,
    /// Smallest `τmax` found not certifiable: a failed probe, or one of the two necessary limits
    /// (or the upper end of the search).
    pub refuted: f64,
    /// The design at [`WindowSearch::certified`].
    pub design: Option<Design>,
    /// Every probe, in order.
    pub probes: Vec<Probe>,
}

/// Bisection on `τmax` for the window `[tau_min, τmax]` (module docs).
///
/// # Errors
/// Invalid `tau_min` or options, or a failure of a numerical kernel or of the LMI layer.
pub fn largest_tau_max(
    plant: &Plant,
    tau_min: f64,
    options: &WindowSearchOptions,
) -> Result<WindowSearch, Error> {
    if !(options.resolution > 0.0 && options.resolution.is_finite()) {
        return Err(InputError::parameter(
            "resolution",
            options.resolution,
            "must be finite and > 0",
        )
        .into());
    }
    Window::new(tau_min, options.upper)?;
    let exact_limit = necessary_tau_max(plant, tau_min, options.upper)?;
    let vertex_limit =
        polytope_tau_max(plant, tau_min, &options.synthesis.polytope, options.upper)?;
    let top = [exact_limit, vertex_limit]
        .into_iter()
        .flatten()
        .fold(options.upper, f64::min);
    let mut search = WindowSearch {
        tau_min,
        necessary_limit: exact_limit,
        polytope_limit: vertex_limit,
        certified: None,
        refuted: top,
        design: None,
        probes: Vec::new(),
    };
    let probe = |tau_max: f64, search: &mut WindowSearch| -> Result<bool, Error> {
        let start = Instant::now();
        let window = Window::new(tau_min, tau_max)?;
        let design = synthesise_from(plant, &window, None, &options.synthesis)?;
        let certified = design.is_certified();
        search.probes.push(Probe {
            tau_max,
            certified,
            best_t: design.best_t(),
            steps: design.log.len(),
            time: start.elapsed(),
        });
        if certified {
            search.certified = Some(tau_max);
            search.design = Some(design);
        } else {
            search.refuted = search.refuted.min(tau_max);
        }
        Ok(certified)
    };
    if top <= tau_min || !probe(tau_min, &mut search)? {
        return Ok(search);
    }
    // The top of the bracket first: the pipeline often reaches the necessary limit.
    let near_top = top - 0.9 * options.resolution;
    if near_top > tau_min && probe(near_top, &mut search)? {
        return Ok(search);
    }
    let hi = search.refuted;
    bisect(tau_min, hi, options.resolution, |mid| {
        probe(mid, &mut search)
    })?;
    Ok(search)
}

/// Result of [`largest_tau_max_for_gain`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GainWindow {
    /// Largest `τmax` at which Theorem 1 was certified for the gain (`None`: not at `τmin`).
    pub certified: Option<f64>,
    /// Smallest `τmax` found not certifiable (or the necessary limit / upper end).
    pub refuted: f64,
    /// Number of analyses run.
    pub probes: usize,
}

/// Bisection on `τmax` for the Theorem 1 analysis of a **given** gain `L` ([`analyse_gain`]),
/// bracketed above by [`necessary_tau_max`] (valid for every gain) and `upper`.
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
) -> Result<GainWindow, Error> {
    if !(resolution > 0.0 && resolution.is_finite()) {
        return Err(
            InputError::parameter("resolution", resolution, "must be finite and > 0").into(),
        );
    }
    Window::new(tau_min, upper)?;
    let top = necessary_tau_max(plant, tau_min, upper)?.unwrap_or(upper);
    let mut out = GainWindow {
        certified: None,
        refuted: top,
        probes: 0,
    };
    let probe = |tau_max: f64, out: &mut GainWindow| -> Result<bool, Error> {
        out.probes += 1;
        let ok = analyse_gain(plant, &Window::new(tau_min, tau_max)?, l, options)?.certified;
        if ok {
            out.certified = Some(tau_max);
        } else {
            out.refuted = out.refuted.min(tau_max);
        }
        Ok(ok)
    };
    if top <= tau_min || !probe(tau_min, &mut out)? {
        return Ok(out);
    }
    let hi = out.refuted;
    bisect(tau_min, hi, resolution, |mid| probe(mid, &mut out))?;
    Ok(out)
}
