//! The registry of observer methods: one [`ObserverMethod`] per paper crate, and the adapters
//! from a [`PlantFile`] to the method contract.
//!
//! Nothing here is specific to a paper: every decision of a method (which theorem to try, how
//! to search its window, what to simulate) lives in that method's crate. A plant file can
//! describe two sampling setups (all outputs sampled at once with `[sampling] window`, and
//! `[[sensors]]` polled round-robin); each method runs on the first setup it applies to,
//! round-robin first ([`PlantFile::setups`]).

use crate::plant_file::PlantFile;
use sporadic_model::{
    CompareEntry, CompareReport, DesignReport, Gain, MaxIntervalReport, MethodError, MethodOptions,
    NamedMatrix, ObserverMethod, Plant, Probe, Proof, ProofOptions, ProofStatus, Reason, Sampling,
    SamplingWindow, Scenario, Trajectory,
};

/// Every method, in the order of the seed papers.
pub fn registry() -> Vec<Box<dyn ObserverMethod>> {
    vec![
        Box::new(sporadic_ferrante2016::Ferrante2016::default()),
        Box::new(sporadic_sferlazza2021::Sferlazza2021::default()),
        Box::new(sporadic_andrieu2014::Andrieu2014),
        Box::new(sporadic_etienne2017::Etienne2017::default()),
        Box::new(sporadic_rabehi2021::Rabehi2021::default()),
    ]
}

/// The ids of the registered methods, in registry order.
pub fn ids() -> Vec<&'static str> {
    registry().iter().map(|m| m.id()).collect()
}

/// The method with this id.
pub fn method(id: &str) -> Option<Box<dyn ObserverMethod>> {
    registry().into_iter().find(|m| m.id() == id)
}

/// The setup (plant and sampling) `method` runs on: the first of the file's setups it applies
/// to, or the reason it applies to none: missing data if one setup lacks data the method needs
/// (the actionable reason), else the reason for the first setup, else missing sampling.
pub fn setup(
    file: &PlantFile,
    method: &dyn ObserverMethod,
) -> Result<(Plant, Sampling), (Option<Sampling>, Reason)> {
    let setups = file.setups();
    let mut reasons = Vec::new();
    for (plant, sampling) in setups {
        match method.applies(&plant, &sampling) {
            Ok(()) => return Ok((plant, sampling)),
            Err(na) => reasons.push((Some(sampling), na.reason)),
        }
    }
    let missing = reasons
        .iter()
        .position(|(_, r)| matches!(r, Reason::MissingData { .. }));
    if let Some(k) = missing {
        return Err(reasons.swap_remove(k));
    }
    Err(reasons.into_iter().next().unwrap_or((
        None,
        Reason::MissingData {
            message: "the plant file has no sampling: give a [sampling] window (with plant.C) or \
                      [[sensors]] with their windows"
                .into(),
        },
    )))
}

/// A numerical failure of a method is a verdict (`not_certified`, reason `numerical_failure`),
/// not an error; invalid input stays an error.
fn numerical_as_verdict(
    method: &dyn ObserverMethod,
    plant: &Plant,
    sampling: &Sampling,
    r: Result<DesignReport, MethodError>,
) -> Result<DesignReport, MethodError> {
    match r {
        Err(e @ MethodError::Numerical { .. }) => Ok(DesignReport::without_design(
            method,
            plant.name(),
            Some(sampling),
            Reason::NumericalFailure { message: e.chain() },
        )),
        other => other,
    }
}

/// Designs with `method` for the plant file.
pub fn design(
    file: &PlantFile,
    method: &dyn ObserverMethod,
    options: &MethodOptions,
) -> Result<DesignReport, MethodError> {
    let start = std::time::Instant::now();
    let mut report = match setup(file, method) {
        Ok((plant, sampling)) => {
            let r = sporadic_model::design_within(method, &plant, &sampling, options);
            numerical_as_verdict(method, &plant, &sampling, r)?
        }
        Err((sampling, reason)) => {
            DesignReport::without_design(method, &file.name, sampling.as_ref(), reason)
        }
    };
    report.plant = file.name.clone();
    if report.seconds == 0.0 {
        report.seconds = start.elapsed().as_secs_f64();
    }
    Ok(report)
}

/// The largest certified `T2 ≤ limit` of `method` for the plant file, with the file's `T1`.
pub fn max_interval(
    file: &PlantFile,
    method: &dyn ObserverMethod,
    limit: f64,
    options: &MethodOptions,
    progress: &mut dyn FnMut(&Probe),
) -> Result<MaxIntervalReport, MethodError> {
    match setup(file, method) {
        Ok((plant, sampling)) => {
            match method.largest_window(&plant, &sampling, limit, options, progress) {
                Err(e @ MethodError::Numerical { .. }) => Ok(not_searched(
                    file,
                    method,
                    Some(&sampling),
                    limit,
                    Reason::NumericalFailure { message: e.chain() },
                )),
                other => other,
            }
        }
        Err((sampling, reason)) => Ok(not_searched(file, method, sampling.as_ref(), limit, reason)),
    }
}

/// A window-search report without a search.
fn not_searched(
    file: &PlantFile,
    method: &dyn ObserverMethod,
    sampling: Option<&Sampling>,
    limit: f64,
    reason: Reason,
) -> MaxIntervalReport {
    MaxIntervalReport::without_search(method.id(), &file.name, sampling, Some(limit), reason)
}

/// The default upper end of a window search: 10 × the largest `T2` of the file (`None` when the
/// file has no sampling).
pub fn default_limit(file: &PlantFile) -> Option<f64> {
    let t2 = file
        .sensors
        .iter()
        .map(|s| s.window.t2())
        .chain(file.window.map(|w| w.t2()))
        .fold(0.0, f64::max);
    (t2 > 0.0).then_some(10.0 * t2)
}

/// Every registered method on the plant file: the design at the file's own sampling and,
/// when `limit` is given, the largest certified `T2 ≤ limit` with the file's `T1` (not for a
/// method that picks its own sampling instants).
///
/// [`MethodOptions::time_limit`] is the budget of the whole comparison. The designs run first,
/// each with an equal share of what is left when its turn comes; then the searches of the
/// methods that apply, again each with an equal share of what is left (so time a fast method
/// leaves unused goes to the later ones).
pub fn compare(
    file: &PlantFile,
    options: &MethodOptions,
    limit: Option<f64>,
    progress: &mut dyn FnMut(&str, &Probe),
) -> Result<CompareReport, MethodError> {
    let start = std::time::Instant::now();
    let share = |turns_left: usize| MethodOptions {
        time_limit: options
            .time_limit
            .map(|t| t.saturating_sub(start.elapsed()) / turns_left.max(1) as u32),
        ..*options
    };
    let methods = registry();
    let mut designs = Vec::with_capacity(methods.len());
    for (k, m) in methods.iter().enumerate() {
        designs.push(design(file, m.as_ref(), &share(methods.len() - k))?);
    }
    let searched: Vec<bool> = designs
        .iter()
        .zip(&methods)
        .map(|(d, m)| limit.is_some() && !d.status.is_not_applicable() && !m.chooses_its_sampling())
        .collect();
    let mut searches_left = searched.iter().filter(|&&s| s).count();
    let mut results = Vec::with_capacity(methods.len());
    for ((m, design), search) in methods.iter().zip(designs).zip(searched) {
        let largest_window = match limit {
            Some(limit) if search => {
                let mut report = |p: &Probe| progress(m.id(), p);
                let r = max_interval(file, m.as_ref(), limit, &share(searches_left), &mut report)?;
                searches_left -= 1;
                Some(r)
            }
            _ => None,
        };
        results.push(CompareEntry {
            method: m.id().to_string(),
            chooses_its_sampling: m.chooses_its_sampling(),
            design,
            largest_window,
        });
    }
    Ok(CompareReport::new(
        file.name.clone(),
        limit,
        results,
        start.elapsed().as_secs_f64(),
    ))
}

/// Proves a design of `method` for the plant file rigorously ([`ObserverMethod::prove`] through
/// [`sporadic_model::prove_within`]); a file the method does not apply to gives an
/// `inconclusive` proof with the reason (nothing was shown to fail).
pub fn prove(
    file: &PlantFile,
    method: &dyn ObserverMethod,
    design: &DesignReport,
    options: &ProofOptions,
) -> Result<Proof, MethodError> {
    match setup(file, method) {
        Ok((plant, _)) => match sporadic_model::prove_within(method, &plant, design, options) {
            Err(e @ MethodError::Numerical { .. }) => Ok(Proof::not_attempted(
                ProofStatus::Inconclusive,
                format!("the proof failed numerically: {}", e.chain()),
            )),
            other => other,
        },
        Err((_, reason)) => Ok(Proof::not_attempted(
            ProofStatus::Inconclusive,
            format!("{} does not apply: {reason}", method.id()),
        )),
    }
}

/// Checks gains the user brings ([`ObserverMethod::verify`]) on the plant file's sampling, or
/// on `window` (every sensor's window, for round-robin sampling) when given.
pub fn verify(
    file: &PlantFile,
    method: &dyn ObserverMethod,
    gains: &[Gain],
    certificate: &[NamedMatrix],
    window: Option<SamplingWindow>,
    options: &MethodOptions,
) -> Result<DesignReport, MethodError> {
    let start = std::time::Instant::now();
    let mut report = match setup(file, method) {
        Ok((plant, sampling)) => {
            let sampling = match (window, sampling) {
                (None, s) => s,
                (Some(w), Sampling::Synchronous(_)) => Sampling::Synchronous(w),
                (Some(w), Sampling::RoundRobin(ws)) => Sampling::RoundRobin(vec![w; ws.len()]),
            };
            let r = sporadic_sdp::budget::within(
                sporadic_sdp::budget::Budget::for_duration(options.time_limit),
                || method.verify(&plant, &sampling, gains, certificate, options),
            );
            numerical_as_verdict(method, &plant, &sampling, r)?
        }
        Err((sampling, reason)) => {
            DesignReport::without_design(method, &file.name, sampling.as_ref(), reason)
        }
    };
    report.plant = file.name.clone();
    if report.seconds == 0.0 {
        report.seconds = start.elapsed().as_secs_f64();
    }
    Ok(report)
}

/// Simulates a certified design of `method` for the plant file.
pub fn simulate(
    file: &PlantFile,
    method: &dyn ObserverMethod,
    design: &DesignReport,
    scenario: &Scenario,
) -> Result<Trajectory, MethodError> {
    let (plant, _) =
        setup(file, method).map_err(|(_, reason)| MethodError::SimulationUnavailable {
            method: method.id(),
            why: reason.message().to_string(),
        })?;
    let mut run = method.simulate(&plant, design, scenario)?;
    run.report.settling_time = run.settling_time(SETTLING_BAND);
    Ok(run)
}

/// The band of [`sporadic_model::SimulationReport::settling_time`] reported by [`simulate`]:
/// 2% of the initial error, the usual settling-time band of control engineering.
pub const SETTLING_BAND: f64 = 0.02;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_unique_and_every_method_is_found_by_its_id() {
        let ids = ids();
        assert_eq!(ids.len(), 5);
        for (k, id) in ids.iter().enumerate() {
            assert!(!ids[..k].contains(id), "duplicate id {id}");
            assert_eq!(method(id).unwrap().id(), *id);
        }
        assert!(method("nobody1999").is_none());
    }

    /// `sporadic reproduce` lists the reproductions in registry order: each method has one.
    #[cfg(feature = "cli")]
    #[test]
    fn every_method_has_a_reproduction() {
        for id in ids() {
            assert!(
                sporadic_reproductions::PAPERS.iter().any(|p| p.id == id),
                "no reproduction for {id}"
            );
        }
        assert_eq!(sporadic_reproductions::PAPERS.len(), ids().len());
    }
}
