//! Refinement of the polytopic embedding when LMI (41) fails on the paper's polytope.
//!
//! Corollary 1 needs only a polytope whose hull contains `e^{Av}` for every `v ∈ [T1, T2]`. The
//! residue box of §4.1 lets every coefficient of the expansion (42) range independently over its
//! values on the whole window, which is loose when the window is long compared with the modes:
//! for a Jordan block the curve `(e^{λv}, v e^{λv})` is one-dimensional and the box around it
//! two-dimensional. Splitting the window into `k` equal pieces and taking the union of the
//! pieces' vertices gives a polytope that still contains the curve and is tighter (a piece's box
//! lies in the whole window's box). When (41) is infeasible at the paper's polytope, the method
//! contract ([`crate::Ferrante2016`]) then tries the finest split into 2, 4, 8, … pieces that
//! fits the vertex, work and piece limits of [`Refinement`] (and the time budget) before it reports
//! the window as not certified.
//!
//! Measured on a plant with an unstable double pole (`A = [[0.5, 1], [0, 0.5]]`, `C = [1, 0]`,
//! `T1 = 0.05`): the paper's box certifies up to `T2 ≈ 0.39` (margin 1.0e-5 at 0.38, the optimal
//! margin −5.3e-10 at 0.5), 2 pieces `T2 = 0.5` (margin 5.7e-5), 16 pieces `T2 = 1` (margin
//! 7.1e-4, 64 vertices, 0.03 s).
//!
//! The pieces are equal in `v`, so a refined design is the same for the plant in other units of
//! time or in other state coordinates (given that the embedding of each piece is).

use crate::design::{
    Analysis, Design, DesignOptions, LmiCache, analyse, design_cached, unless_cut,
};
use crate::error::Error;
use crate::system::Plant;
use faer::MatRef;
use sporadic_embed::{EmbeddingMethod, ResidueOptions, embed_split};
use sporadic_model::SamplingWindow;

/// Limits of the refinement (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refinement {
    /// Most pieces of a refined embedding (the design's own `pieces`, then twice that, … up to
    /// this); at most the design's `pieces` turns the refinement off.
    pub max_pieces: usize,
    /// Most vertices of a refined embedding (all pieces together, counted on the plant as
    /// given): each vertex is one LMI of order `3n` in the margin problem.
    pub max_vertices: usize,
    /// Most `vertices × n⁶` of a refined embedding (`n` the plant's order): an interior-point
    /// iteration of the margin problem forms, for each vertex LMI of order `3n`, a share of a
    /// Schur matrix over about `1.5n²` decision scalars, so its cost grows like `vertices × n⁶`.
    /// The default `2²⁰` allows the 256 vertices at order 4 and 22 at order 6: on the corpus
    /// plant three-mass-chain (order 6) the refinement to 256 vertices raised the largest
    /// certified `T2` from 0.2999 to 0.4142 but `compare` from 6.1 s to 12.7 s, above the 10 s
    /// that a comparison on a plant of order ≤ 6 is to take.
    pub max_work: f64,
}

impl Default for Refinement {
    /// Up to 16 pieces, 256 vertices and `vertices × n⁶ ≤ 2²⁰`.
    fn default() -> Self {
        Self {
            max_pieces: 16,
            max_vertices: 256,
            max_work: (1u64 << 20) as f64,
        }
    }
}

impl Refinement {
    /// No refinement: the design's own embedding only (the paper's construction).
    pub fn none() -> Self {
        Self {
            max_pieces: 1,
            max_vertices: 0,
            max_work: 0.0,
        }
    }
}

/// The design at `window` ([`design_cached`]), refined when LMI (41) is infeasible (see the
/// module docs): the design's own embedding first (so a window it certifies gets the paper's
/// construction exactly), then at once the finest split within the limits: with one embedding
/// method it is the tightest polytope on offer (a piece of a finer split lies in a piece of a
/// coarser one, and the residue box of a sub-window lies in the box of the window; the clusters'
/// box that [`finest`] may fall back to is looser on a short piece than the power series it
/// replaces, but it is what the limits admit at that split), so the intermediate splits would mostly
/// cost time (`max-interval` on the corpus plant two-mass-flexible: 13.8 s with 2, 4, 8 and 16
/// pieces tried in turn, 6.4 s with the finest at once, the same answer). When neither
/// certifies, the infeasibility of the finest one is returned (its
/// reason says how many pieces and vertices that was); an error of the refined design that is
/// not an infeasible LMI (the solver inconclusive, a failed verification, …) returns the first
/// infeasibility, and any other first verdict (undetectable, …) is returned as it is. A
/// design at the precision limit ([`Error::PrecisionLimit`]: (41) holds, (12) cannot be
/// resolved in the plant's coordinates) is refined in the same way, and its evidence of
/// feasibility is kept over an infeasibility of the other polytope.
pub(crate) fn refined(
    plant: &Plant,
    window: &SamplingWindow,
    options: &DesignOptions,
    cache: &mut LmiCache,
    refinement: &Refinement,
) -> Result<Design, Error> {
    cache.certificate_pass_made = false;
    let first = match design_cached(plant, window, options, cache) {
        Err(e @ (Error::Infeasible { .. } | Error::PrecisionLimit { .. })) => e,
        done => return done,
    };
    let Some((finer, vertices)) = finest(plant, window, options, refinement) else {
        return Err(first);
    };
    if sporadic_sdp::budget::exhausted() {
        return unless_cut(Err(first));
    }
    let pieces = finer.pieces;
    let boxes = match &finer.embedding {
        EmbeddingMethod::Residue(r) if !r.short_window_series => {
            ", the clusters' box on every piece"
        }
        _ => "",
    };
    cache.certificate_pass_made = true;
    match design_cached(plant, window, &finer, cache) {
        Ok(d) => Ok(d),
        Err(e @ Error::PrecisionLimit { .. }) if matches!(first, Error::Infeasible { .. }) => {
            Err(e)
        }
        Err(Error::Infeasible {
            margin,
            reason,
            unverified,
            threshold,
        }) if matches!(first, Error::Infeasible { .. }) => Err(Error::Infeasible {
            margin,
            unverified,
            threshold,
            reason: format!(
                "{reason} (also with the embedding refined to {pieces} pieces, {vertices} \
                     vertices{boxes})"
            ),
        }),
        Err(_) => unless_cut(Err(first)),
    }
}

/// The analysis of a given gain `L` at `window` ([`analyse`], LMI (41) with `J = FL`), refined
/// as [`refined`] refines a design: when the design's own embedding gives no certificate, the
/// finest split within the limits is analysed, and its analysis is returned (certified or not,
/// so that a failure reports the vertices it was decided on). A gain that the method's design
/// certified on a refined embedding is then certified by its check too.
pub(crate) fn refined_analysis(
    plant: &Plant,
    window: &SamplingWindow,
    l: MatRef<'_, f64>,
    options: &DesignOptions,
    refinement: &Refinement,
) -> Result<Analysis, Error> {
    let first = analyse(plant, window, l, options)?;
    if first.certificate.is_some() || sporadic_sdp::budget::exhausted() {
        return Ok(first);
    }
    let Some((finer, _)) = finest(plant, window, options, refinement) else {
        return Ok(first);
    };
    Ok(analyse(plant, window, l, &finer).unwrap_or(first))
}

/// The finest split of `window` within `refinement` (pieces a power-of-two multiple of the
/// design's own, above it; vertices and work counted on the plant as given): the design's
/// options for it, with its vertex count; `None` when no split above the design's own fits, or
/// when the window is one interval (`T1 = T2`: there is nothing to split).
///
/// Each split is embedded as the design would embed it; when that exceeds the limits and the
/// residue embedding took the power series of the whole spectrum on some short piece
/// ([`sporadic_embed::ResidueOptions::short_window_series`]), the same split is tried with the
/// clusters' box on every piece, before a coarser split. The series keeps up to two more box
/// coordinates than the clusters, four times the vertices of a piece, and whether it does
/// depends on the piece's length and on truncation bounds in the coordinates of `A`: without
/// this fallback the split chosen jumped with `T2` and with the state coordinates (the corpus
/// plant multi-output-unstable, a Jordan block at 0.2: on [0.05, 1.4] 8 pieces took 512
/// vertices and only 4 pieces fitted, which left (41) infeasible, while [0.05, 1.58] took
/// 128 at 8 pieces and was certified; the largest certified `T2` was 1.222 as given and 1.649
/// in coordinates `x = Tz` with `κ(T) < 10`). The clusters' box of 16 pieces has 256 vertices
/// in both coordinates.
fn finest(
    plant: &Plant,
    window: &SamplingWindow,
    options: &DesignOptions,
    refinement: &Refinement,
) -> Option<(DesignOptions, usize)> {
    if window.t1() == window.t2() {
        return None;
    }
    let mut candidates = Vec::new();
    let mut pieces = options.pieces.saturating_mul(2);
    while pieces <= refinement.max_pieces {
        candidates.push(pieces);
        pieces = pieces.saturating_mul(2);
    }
    let clusters_only = match &options.embedding {
        EmbeddingMethod::Residue(r) if r.short_window_series => {
            Some(EmbeddingMethod::Residue(ResidueOptions {
                short_window_series: false,
                ..r.clone()
            }))
        }
        _ => None,
    };
    let methods: Vec<&EmbeddingMethod> = std::iter::once(&options.embedding)
        .chain(clusters_only.as_ref())
        .collect();
    candidates.into_iter().rev().find_map(|pieces| {
        methods.iter().find_map(|&method| {
            let e = embed_split(plant.a(), window.t1(), window.t2(), pieces, method).ok()?;
            let vertices = e.vertex_count();
            let work = vertices as f64 * (plant.n() as f64).powi(6);
            (vertices <= refinement.max_vertices && work <= refinement.max_work).then(|| {
                let finer = DesignOptions {
                    pieces,
                    embedding: method.clone(),
                    ..options.clone()
                };
                (finer, vertices)
            })
        })
    })
}
