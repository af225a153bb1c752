//! The [`ObserverMethod`] contract for Andrieu et al. (2014).
//!
//! The observer (5)–(7) chooses its own next sampling instant (rule (7): the interval times the
//! high gain `L` equals `α`), for triangular systems in observability normal form (1)–(4) given
//! as code. A plant described by matrices and a sampling window is therefore outside what this
//! implementation covers today: [`ObserverMethod::applies`] says so with a typed reason, and the
//! reproduction of the paper's examples runs the method on its own systems.

use sporadic_model::{
    DesignReport, MethodError, MethodOptions, NotApplicable, ObserverMethod, Plant, Sampling,
};

/// Andrieu, Nadri, Serres & Vivalda (2014): high-gain observer with updated sampling period.
#[derive(Debug, Clone, Default)]
pub struct Andrieu2014;

const ID: &str = "andrieu2014";

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
        "between samples x̂' = f(x̂, u) − L(t)·Δ(L)K·(ŷ(t_k) − y(t_k)) with L' = a2·c(x̂, u)·L; \
         next sample at t_{k+1} with (t_{k+1} − t_k)·L(t_{k+1}⁻) = α (rule (7)); \
         at a sample the correction uses the new measurement (5)"
    }

    fn applies(&self, _plant: &Plant, _sampling: &Sampling) -> Result<(), NotApplicable> {
        Err(not_applicable())
    }

    fn design(
        &self,
        plant: &Plant,
        sampling: &Sampling,
        _options: &MethodOptions,
    ) -> Result<DesignReport, MethodError> {
        Ok(DesignReport::without_design(
            self,
            plant.name(),
            Some(sampling),
            not_applicable().reason,
        ))
    }
}

/// Why no plant file is covered (see the module docs).
fn not_applicable() -> NotApplicable {
    NotApplicable::unsupported(
        ID,
        "this observer takes no sampling window to certify: it picks each next sample itself \
         (rule (7), interval x high gain = alpha), for plants in observability normal form \
         given as code; see `sporadic reproduce andrieu2014`",
    )
}
