//! The largest certifiable sampling window: the largest `T2` for a given `T1` ([`largest_t2`]), and
//! the smallest `T1` for a given `T2` ([`smallest_t1`]), with a full [`design`](crate::design())
//! (Remark 3 precheck, LMI (41), grid verification) at every probe.
//!
//! Both are thin code over the shared window search of `sporadic-model`
//! ([`search_upper`] / [`search_lower`]); the only thing added here is the probe, which re-solves
//! a compiled instance of LMI (41) per form of the problem (as given, and each normal form of
//! [`crate::normalise`]) with the new vertices whenever their number allows it (the residue box
//! of a form mostly keeps its number of vertices from one window to the next), instead of
//! building the model anew at every probe, and tries first the form that certified the previous
//! probe (the verdict does not depend on the order).
//!
//! With the default [`WindowSearchOptions`] (`Scan { points: 6 }`, `Relative(4e-3)`) the search
//! probes the periodic window, then 6 geometrically spaced values up to the limit, and bisects at
//! geometric midpoints inside the first certified → failed transition until the bracket is within
//! 0.4 % (relative).
//!
//! **Monotonicity caveat.** Condition (12) itself is monotone in the window (a larger window only
//! adds values of `v`), and for the single-piece residue box a larger window gives a larger box
//! whose hull contains the smaller one's vertices, so LMI (41) is monotone too in exact
//! arithmetic. Split or Taylor embeddings, and the solver's verdicts near the feasibility
//! boundary, need not be: the search reports whether the verdicts on *all* probed points are
//! consistent with monotone feasibility ([`WindowSearch::monotone`]), and answers with the
//! bracket `[last certified, first failed]` of the first transition.

use crate::design::{Design, DesignOptions, LmiCache};
use crate::error::Error;
use crate::refine::{Refinement, refined};
use crate::system::Plant;
use sporadic_model::{
    SamplingWindow, SearchError, Verdict, WindowSearch, WindowSearchOptions, search_lower,
    search_upper,
};

/// Largest `T2 ∈ [t1, t2_limit]` for which a verified design exists (see the module docs).
///
/// A probe that is not certified (LMI (41) infeasible, solver inconclusive, verification
/// failed, `(e^{Av}, C)` not detectable in the window, …: every error with an
/// [`Error::reason`]) is a verdict of the search, recorded with its
/// [`Reason`](sporadic_model::Reason); any other error (bad input, bad options) ends the search
/// with that error.
pub fn largest_t2(
    plant: &Plant,
    t1: f64,
    t2_limit: f64,
    design: &DesignOptions,
    search: &WindowSearchOptions,
) -> Result<WindowSearch, Error> {
    design.validate()?;
    let design = &probe_options(design);
    let mut cache = LmiCache::for_search();
    let mut run = |t2: f64| -> Result<Verdict, Error> {
        let window = SamplingWindow::new(t1, t2)?;
        Ok(probe(plant, &window, design, &mut cache, &Refinement::none())?.0)
    };
    search_upper(t1, t2_limit, search, &mut run).map_err(from_search)
}

/// Smallest `T1 ∈ [t1_limit, t2]` for which a verified design exists (see the module docs and
/// [`largest_t2`]).
pub fn smallest_t1(
    plant: &Plant,
    t2: f64,
    t1_limit: f64,
    design: &DesignOptions,
    search: &WindowSearchOptions,
) -> Result<WindowSearch, Error> {
    design.validate()?;
    let design = &probe_options(design);
    let mut cache = LmiCache::for_search();
    let mut run = |t1: f64| -> Result<Verdict, Error> {
        let window = SamplingWindow::new(t1, t2)?;
        Ok(probe(plant, &window, design, &mut cache, &Refinement::none())?.0)
    };
    search_lower(t2, t1_limit, search, &mut run).map_err(from_search)
}

/// The options of a window search's probes: `design`'s, with the margin solves of LMI (41)
/// ending at their first iterate that is a certificate
/// ([`FeasibilityOptions::stop_when_verified`](sporadic_sdp::lmi::FeasibilityOptions); with the
/// residue box the design's own test of (41) at the vertices, see [`crate::design()`]): a probe
/// needs a certificate, not the largest margin.
pub(crate) fn probe_options(design: &DesignOptions) -> DesignOptions {
    let mut options = design.clone();
    options.lmi.stop_when_verified = true;
    options
}

/// One probe of a window search: the design at `window` with the compiled LMI kept in `cache`
/// (and the embedding refined as `refinement` allows, [`crate::refine`]), as a verdict (and the
/// design, when certified, or the rounding level below which a refusal of LMI (41) does not
/// resolve margins, [`Error::Infeasible`]'s `threshold`); errors that are not verdicts on the
/// plant ([`Error::reason`] is `None`) are passed on.
pub(crate) fn probe(
    plant: &Plant,
    window: &SamplingWindow,
    design: &DesignOptions,
    cache: &mut LmiCache,
    refinement: &Refinement,
) -> Result<(Verdict, Result<Design, Option<f64>>), Error> {
    match refined(plant, window, design, cache, refinement) {
        Ok(d) => Ok((Verdict::certified(Some(d.certificate.margin)), Ok(d))),
        Err(e) => match e.reason() {
            Some(r) => {
                let threshold = match e {
                    Error::Infeasible { threshold, .. } => threshold,
                    _ => None,
                };
                Ok((Verdict::failed(r), Err(threshold)))
            }
            None => Err(e),
        },
    }
}

fn from_search(e: SearchError<Error>) -> Error {
    match e {
        SearchError::Input(e) => Error::Input(e),
        SearchError::Probe(e) => e,
    }
}
