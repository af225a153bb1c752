//! The necessary condition of Remark 3 (Ferrante et al. 2016): if (12) holds then
//! `e^{Av}(I − LM)` is Schur for every `v ∈ [T1, T2]`, hence the sampled pair `(e^{Av}, M)` must be
//! **detectable** (not necessarily observable) for every such `v`.
//!
//! The test is the PBH test on `e^{Av}`: for every eigenvalue `μ` of `e^{Av}` with `|μ| ≥ 1`, the
//! matrix `[μI − e^{Av}; M]` must have full column rank. It is evaluated on a uniform grid of
//! `[T1, T2]` (on a window longer than the decay of every mode of a Hurwitz `A`, uniform up to
//! that decay and geometric beyond, see the `grid` module) **plus every aliasing instant** of the non-decaying modes: two eigenvalues `λ ≠ λ'` of `A`
//! with `Re λ = Re λ' ≥ 0` give the same eigenvalue of `e^{Av}` exactly when
//! `v · |Im λ − Im λ'| ∈ 2πℕ`, and only at those isolated instants can the eigenspaces of `e^{Av}`
//! merge and detectability be lost while `(A, M)` is detectable (a grid alone would miss them).
//! Aliasing among *decaying* modes (e.g. Example 2 at `v = π/1.63317 ≈ 1.92362`, where the damped
//! complex pair of the mass–spring system becomes a double real eigenvalue of `e^{Av}` and
//! observability is lost) does not matter for detectability and is not flagged.
//!
//! The rank test is [`sporadic_linalg::pbh_detectability`] (block-normalised PBH matrix, its smallest
//! singular value is the *PBH margin*), with the eigenvalues of `e^{Av}` taken by spectral mapping
//! `μ = e^{λv}` from those of `A`, exact also at the aliasing instants.

use faer::c64;
use sporadic_linalg::{LinalgError, PbhOptions, aliasing_instants, pbh_detectability};

use crate::error::Error;
use crate::grid::{expm_far, window_grid};
use crate::system::Plant;
use sporadic_model::SamplingWindow;

/// Options of [`check_detectability`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DetectabilityOptions {
    /// Number of uniform grid points on `[T1, T2]` (the aliasing instants are added; see
    /// the `grid` module for long windows). Default 1001.
    pub grid_points: usize,
    /// Tolerances of the PBH test: smallest admissible margin `rank_tol` (default `1e-8`); eigenvalues
    /// of `e^{Av}` with `|μ| ≥ 1 − unit_circle_tol` are treated as non-decaying (default `1e-9`).
    pub pbh: PbhOptions,
}

impl DetectabilityOptions {
    /// Checks the options; the error names the offending field (`rank_tol`, `unit_circle_tol`;
    /// `grid_points = 0` is taken as 1).
    pub fn validate(&self) -> Result<(), Error> {
        Ok(self.pbh.validate()?)
    }
}

impl Default for DetectabilityOptions {
    fn default() -> Self {
        Self {
            grid_points: 1001,
            pbh: PbhOptions {
                rank_tol: 1e-8,
                unit_circle_tol: 1e-9,
            },
        }
    }
}

/// Outcome of a successful [`check_detectability`].
#[derive(Debug, Clone, PartialEq)]
pub struct DetectabilityReport {
    /// Number of inter-sample times tested (grid plus aliasing instants).
    pub points_tested: usize,
    /// Aliasing instants of non-decaying modes inside `[T1, T2]` (all were tested).
    pub aliasing_instants: Vec<f64>,
    /// Smallest PBH margin met over all tested `v` and all non-decaying eigenvalues (`+∞` when
    /// `e^{Av}` has no eigenvalue on or outside the unit circle, i.e. `A` is Hurwitz).
    pub min_margin: f64,
    /// Where the smallest margin occurred.
    pub min_margin_at: f64,
}

/// Upper limit on the number of aliasing instants (a window spanning more than this many aliasing
/// periods is rejected instead of being tested point by point).
const MAX_ALIASING_INSTANTS: usize = 100_000;

/// Checks the necessary condition of Remark 3 on `[T1, T2]`; returns [`Error::NotDetectable`] with the
/// offending `v` and eigenvalue when it fails.
pub fn check_detectability(
    plant: &Plant,
    window: &SamplingWindow,
    options: &DetectabilityOptions,
) -> Result<DetectabilityReport, Error> {
    options.validate()?;
    let a = plant.a();
    let lambdas = a.eigenvalues().map_err(|_| LinalgError::NoConvergence {
        what: "eigenvalues of A".into(),
    })?;
    let aliasing = aliasing_instants(
        &lambdas,
        window.t1(),
        window.t2(),
        options.pbh.unit_circle_tol,
        MAX_ALIASING_INSTANTS,
    )?;
    let mut points = window_grid(a, window, options.grid_points.max(1))?;
    points.extend_from_slice(&aliasing);
    points.sort_by(f64::total_cmp);
    points.dedup();

    let mut report = DetectabilityReport {
        points_tested: points.len(),
        aliasing_instants: aliasing,
        min_margin: f64::INFINITY,
        min_margin_at: window.t1(),
    };
    for &v in &points {
        let e = expm_far(a, v)?;
        let mus: Vec<c64> = lambdas
            .iter()
            .map(|l| (l * c64::new(v, 0.0)).exp())
            .collect();
        let test = pbh_detectability(e.as_ref(), plant.c(), &mus, &options.pbh)?;
        let Some(worst) = test.worst else { continue };
        if worst.margin < report.min_margin {
            report.min_margin = worst.margin;
            report.min_margin_at = v;
        }
        if !test.detectable {
            return Err(Error::NotDetectable {
                v,
                mu_re: worst.eigenvalue.re,
                mu_im: worst.eigenvalue.im,
                modulus: worst.eigenvalue.norm(),
                margin: worst.margin,
            });
        }
    }
    Ok(report)
}
