//! Table I of Rabehi et al. (2021): the largest `τmax` (with `τmin = 0.04`) for which the design
//! problem of Proposition 1 is solved, as a function of the damping `c_s` of the example.
//! One [`largest_tau_max`] search per damping value, run in parallel (rayon).

use rayon::prelude::*;

use crate::error::Error;
use crate::example::{TABLE1_DAMPING, TABLE1_TAU_MAX, TAU_MIN, spring_mass_damper};
use crate::window::{TauMaxOptions, TauMaxSearch, largest_tau_max};

/// One row of Table I.
#[derive(Debug, Clone)]
pub struct TableRow {
    /// Damping `c_s`.
    pub damping: f64,
    /// The paper's value (`None`: "–", no gain found).
    pub paper: Option<f64>,
    /// Our search.
    pub search: TauMaxSearch,
}

/// Recomputes Table I with `options` for every damping value of the paper.
///
/// # Errors
/// The first error of any search.
pub fn table1(options: &TauMaxOptions) -> Result<Vec<TableRow>, Error> {
    TABLE1_DAMPING
        .par_iter()
        .zip(TABLE1_TAU_MAX.par_iter())
        .map(|(&damping, &paper)| {
            let plant = spring_mass_damper(damping)?;
            Ok(TableRow {
                damping,
                paper,
                search: largest_tau_max(&plant, TAU_MIN, options)?,
            })
        })
        .collect()
}
