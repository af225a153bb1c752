//! Reproductions of the examples of the five papers implemented by `sporadic`.
//!
//! Each paper has one module whose `reproduce(out_dir)` recomputes the paper's examples with
//! the paper's method crate into one record of values (writing the paper's figures as SVG files),
//! then checks its claim table against that record: every claim names its reference (a number the
//! paper prints, a value the paper implies, or an independent computation: [`Source`]) and is
//! compared under the tolerance policy of [`claim`]; [`report`] renders the results as one HTML
//! page. The method crates
//! themselves carry no reproduction code: a user who links `sporadic-ferrante2016` gets the
//! method, not this report machinery.
//!
//! [`PAPERS`] lists the reproductions in seed order; `sporadic reproduce` runs them.

pub mod claim;
pub mod report;

pub mod andrieu2014;
pub mod etienne2017;
pub mod ferrante2016;
pub mod rabehi2021;
pub mod sferlazza2021;

pub use claim::{Claim, ClaimStatus, Reproduction, Rule, Source, Value};

use std::path::Path;

/// Why a reproduction could not run (a claim that differs from the paper is not an error: it is
/// reported in the [`Reproduction`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReproductionError {
    /// Ferrante et al. (2016).
    #[error(transparent)]
    Ferrante2016(#[from] sporadic_ferrante2016::Error),
    /// Sferlazza et al. (2021).
    #[error(transparent)]
    Sferlazza2021(#[from] sporadic_sferlazza2021::Error),
    /// Andrieu et al. (2014).
    #[error(transparent)]
    Andrieu2014(#[from] sporadic_andrieu2014::Error),
    /// Etienne et al. (2017).
    #[error(transparent)]
    Etienne2017(#[from] sporadic_etienne2017::Error),
    /// Rabehi et al. (2021).
    #[error(transparent)]
    Rabehi2021(#[from] sporadic_rabehi2021::Error),
    /// A method of the common contract failed (not a verdict: bad input or a numerical
    /// failure).
    #[error(transparent)]
    Method(#[from] sporadic_model::MethodError),
    /// A simulation failed.
    #[error(transparent)]
    Simulation(#[from] sporadic_sim::SimError),
    /// A figure could not be drawn or written.
    #[error(transparent)]
    Figure(#[from] sporadic_figures::FigureError),
    /// Invalid data inside a reproduction.
    #[error(transparent)]
    Input(#[from] sporadic_linalg::InputError),
    /// A linear-algebra kernel failed.
    #[error(transparent)]
    Linalg(#[from] sporadic_linalg::LinalgError),
    /// The output folder could not be created or written.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: std::path::PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
}

/// A reproduction runner: writes figures into its folder and returns the checked claims.
pub type Runner = fn(&Path) -> Result<Reproduction, ReproductionError>;

/// One paper: its id (as on the command line), a short title, and its reproduction.
#[derive(Debug, Clone, Copy)]
pub struct Paper {
    /// The paper id, e.g. `ferrante2016`.
    pub id: &'static str,
    /// Authors, year and subject.
    pub title: &'static str,
    /// The reproduction.
    pub run: Runner,
}

/// The reproductions, in seed order.
pub const PAPERS: [Paper; 5] = [
    Paper {
        id: "ferrante2016",
        title: "Ferrante et al. 2016, observer with sporadic measurements",
        run: ferrante2016::reproduce,
    },
    Paper {
        id: "sferlazza2021",
        title: "Sferlazza et al. 2021, round-robin observer with jitter",
        run: sferlazza2021::reproduce,
    },
    Paper {
        id: "andrieu2014",
        title: "Andrieu et al. 2014, high-gain observer with updated sampling",
        run: andrieu2014::reproduce,
    },
    Paper {
        id: "etienne2017",
        title: "Etienne et al. 2017, impulsive observer for Lipschitz systems",
        run: etienne2017::reproduce,
    },
    Paper {
        id: "rabehi2021",
        title: "Rabehi et al. 2021, interval impulsive observer",
        run: rabehi2021::reproduce,
    },
];

#[cfg(test)]
mod tests {
    #[test]
    fn every_paper_has_a_unique_id() {
        let ids: Vec<&str> = super::PAPERS.iter().map(|p| p.id).collect();
        for (k, id) in ids.iter().enumerate() {
            assert!(!ids[..k].contains(id), "duplicate id {id}");
        }
    }
}
