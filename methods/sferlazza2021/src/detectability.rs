//! The necessary detectability condition of Proposition 1 as a computable PBH test.
//!
//! For inter-sample intervals `(T_1, …, T_N)` with `T_σ ∈ [T_mσ, T_Mσ]`, `T = Σ T_σ` and
//! `T̄_k = T_1 + … + T_k`, the lifted output matrix is `C = col(C_1 e^{AT̄_1}, …, C_N e^{AT̄_N})` (8).
//! Goal 1 can only be solved if `(C, e^{AT})` is detectable in the discrete-time sense for every
//! admissible tuple. The Popov–Belevitch–Hautus test checks, for each eigenvalue `z` of `e^{AT}` with
//! `|z| ≥ 1`, that `[zI − e^{AT}; C]` has full column rank. The eigenvalues are `z = e^{λ_i(A) T}`
//! (spectral mapping), which is exact also when distinct `λ_i` alias onto the same `z`.
//!
//! The rank test itself is [`sporadic_linalg::pbh_detectability`] (block-normalised PBH matrix; its
//! smallest singular value is the *PBH margin*), on the rows of (8) referred to the end of the
//! round, `C_σ e^{A(T̄_σ − T)}`, each sensor's block normalised (the same kernel; see [`pbh`]).
//!
//! * Jitter-free plants have one tuple: the test is exact, and by Proposition 4 it is equivalent to
//!   feasibility of the design LMI (23).
//! * Jitter-tolerant plants: the box of windows is screened on a uniform grid. This is a necessary
//!   screen only, not a proof over the continuum.

use faer::{Mat, c64};
use sporadic_linalg::{
    InputError, PbhOptions, PbhTest, aliasing_instants, expm_scaled, pbh_detectability,
};

use crate::error::{Error, check_at_least};
use crate::plant::{RoundRobinPlant, window_grid};

/// Tolerances and grid of the PBH test. Defaults: 26 points per window, the kernel's
/// [`PbhOptions::default`], at most 10⁶ tuples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DetectabilityOptions {
    /// Grid points per window in the jitter-tolerant screen (a fixed window always uses 1 point).
    pub points_per_axis: usize,
    /// Tolerances of the PBH test (rank tolerance on the margin, and which eigenvalues of `e^{AT}`
    /// count as not asymptotically stable).
    pub pbh: PbhOptions,
    /// Cap on the number of tuples of the screen (`points_per_axis^N`).
    pub max_tuples: usize,
}

impl DetectabilityOptions {
    /// Checks the grid fields (the PBH tolerances are checked by the kernel); the error names the
    /// offending field.
    ///
    /// # Errors
    /// [`InputError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<(), InputError> {
        check_at_least("detectability.points_per_axis", self.points_per_axis, 2)?;
        check_at_least("detectability.max_tuples", self.max_tuples, 1)
    }
}

impl Default for DetectabilityOptions {
    fn default() -> Self {
        Self {
            points_per_axis: 26,
            pbh: PbhOptions::default(),
            max_tuples: 1_000_000,
        }
    }
}

/// Result of the PBH test for one tuple of intervals.
#[derive(Debug, Clone, PartialEq)]
pub struct PbhCheck {
    /// `(T_1, …, T_N)`.
    pub intervals: Vec<f64>,
    /// The PBH test of `(e^{AT}, C)`: spectral radius of `e^{AT}`, the tested eigenvalue with the
    /// smallest margin (`None`: `e^{AT}` is Schur), and whether `(C, e^{AT})` is detectable.
    pub test: PbhTest,
}

/// Result of [`check_detectability`].
#[derive(Debug, Clone, PartialEq)]
pub struct DetectabilityReport {
    /// `true` in the jitter-free case (one tuple, the test is exact); `false` for the grid screen.
    pub exact: bool,
    /// Number of tuples tested.
    pub tuples: usize,
    /// Largest spectral radius of `e^{AT}` over the tuples.
    pub max_spectral_radius: f64,
    /// The tuple with the smallest PBH margin among tested eigenvalues (if any was tested).
    pub worst: Option<PbhCheck>,
    /// Whether every tested tuple is detectable.
    pub detectable: bool,
}

/// PBH test of Proposition 1 for one tuple `intervals = (T_1, …, T_N)` (sensor order, 0-based).
///
/// # Errors
/// Wrong number of intervals, non-finite or negative intervals, invalid tolerances, failing
/// eigen/SVD/expm kernels.
pub fn pbh(
    plant: &RoundRobinPlant,
    intervals: &[f64],
    settings: &DetectabilityOptions,
) -> Result<PbhCheck, Error> {
    let n_s = plant.num_sensors();
    if intervals.len() != n_s {
        return Err(InputError::mismatch("number of intervals", n_s, intervals.len()).into());
    }
    if intervals.iter().any(|t| !t.is_finite() || *t < 0.0) {
        return Err(Error::invalid(format!(
            "intervals must be finite and nonnegative: {}",
            crate::error::sig4_list(intervals)
        )));
    }
    let n = plant.n();
    let a = plant.a();
    let total: f64 = intervals.iter().sum();
    let mono = expm_scaled(a, total)?;
    // Lifted output (8), referred to the end of the round and each sensor's block normalised:
    // the rows `C_σ e^{A(T̄_σ − T)}/‖·‖_F`, i.e. (8) times `e^{−AT}` on the right and an
    // invertible scaling of each block on the left, which keep the kernel of the PBH matrix at
    // every eigenvalue `z ≠ 0` of `e^{AT}` (`C e^{−AT}v = Cv/z` on it). Its rows then do not
    // carry the growth `e^{AT}` of the fast unstable modes, which, through the kernel's single
    // normalisation of the output block, made a slow mode seen directly look unobservable (the
    // cart's position beside an inverted pendulum: margin 1e-8 instead of 0.3 at T = 3.08). The
    // rows of (8) itself are used where referring them back overflows.
    let m_tot: usize = plant.sensors().iter().map(|s| s.outputs()).sum();
    let lift = |shift: f64| -> Result<Option<Mat<f64>>, Error> {
        let mut lifted = Mat::<f64>::zeros(m_tot, n);
        let (mut t_acc, mut row) = (0.0, 0);
        for (s, &t) in plant.sensors().iter().zip(intervals) {
            t_acc += t;
            let e = match expm_scaled(a, t_acc - shift) {
                Ok(e) => e,
                Err(sporadic_linalg::LinalgError::Overflow { .. }) => return Ok(None),
                Err(e) => return Err(e.into()),
            };
            let mut block = s.c() * e;
            let norm = block.norm_l2();
            if !norm.is_finite() {
                return Ok(None);
            }
            if norm > 0.0 {
                block *= faer::Scale(1.0 / norm);
            }
            lifted
                .submatrix_mut(row, 0, s.outputs(), n)
                .copy_from(&block);
            row += s.outputs();
        }
        Ok(Some(lifted))
    };
    let lifted = match lift(total)? {
        Some(l) => l,
        None => lift(0.0)?.ok_or_else(|| Error::numerical("the lifted output (8) overflows"))?,
    };
    // Eigenvalues of e^{AT} by spectral mapping (exact also when distinct λ_i alias).
    let eigs: Vec<c64> = a
        .eigenvalues()
        .map_err(|_| Error::numerical("eigenvalues of A did not converge"))?
        .into_iter()
        .map(|lam| (lam * c64::new(total, 0.0)).exp())
        .collect();
    Ok(PbhCheck {
        intervals: intervals.to_vec(),
        test: pbh_detectability(mono.as_ref(), lifted.as_ref(), &eigs, &settings.pbh)?,
    })
}

/// Proposition 1 over the plant's windows: exact in the jitter-free case, a grid screen of the box
/// `Π_σ [T_mσ, T_Mσ]` (`points_per_axis` points per non-degenerate window) otherwise.
///
/// # Errors
/// More tuples than `max_tuples`, `points_per_axis < 2`, or a failing kernel.
pub fn check_detectability(
    plant: &RoundRobinPlant,
    settings: &DetectabilityOptions,
) -> Result<DetectabilityReport, Error> {
    settings.validate()?;
    let axes: Vec<Vec<f64>> = plant
        .sensors()
        .iter()
        .map(|s| window_grid(s.window(), settings.points_per_axis))
        .collect::<Result<_, _>>()?;
    let tuples = axes
        .iter()
        .try_fold(1usize, |acc, ax| acc.checked_mul(ax.len()));
    let tuples = match tuples {
        Some(t) if t <= settings.max_tuples => t,
        _ => {
            return Err(Error::invalid(format!(
                "detectability screen exceeds {} tuples",
                settings.max_tuples
            )));
        }
    };
    // The aliasing tuples first: they are where detectability is lost, and testing them first
    // makes an undetectable plant fail fast.
    let aliasing = aliasing_tuples(plant, settings)?;
    let extra = aliasing.len();
    let mut idx = vec![0usize; axes.len()];
    let mut max_rho = 0.0f64;
    let mut worst: Option<PbhCheck> = None;
    let mut detectable = true;
    for k in 0..tuples + extra {
        let t: Vec<f64> = if k < extra {
            aliasing[k].clone()
        } else {
            idx.iter().zip(&axes).map(|(&i, ax)| ax[i]).collect()
        };
        let chk = pbh(plant, &t, settings)?;
        max_rho = max_rho.max(chk.test.spectral_radius);
        detectable &= chk.test.detectable;
        let better = match (&worst, &chk.test.worst) {
            (_, None) => false,
            (None, Some(_)) => true,
            (Some(w), Some(c)) => w.test.worst.is_none_or(|ww| c.margin < ww.margin),
        };
        if better {
            worst = Some(chk);
        }
        if k < extra {
            continue;
        }
        for (i, ax) in idx.iter_mut().zip(&axes) {
            *i += 1;
            if *i < ax.len() {
                break;
            }
            *i = 0;
        }
    }
    Ok(DetectabilityReport {
        exact: plant.is_jitter_free(),
        tuples: tuples + extra,
        max_spectral_radius: max_rho,
        worst,
        detectable,
    })
}

/// Upper limit on the number of aliasing periods tested (a window spanning more than this many is
/// screened on its grid only; the cap keeps the screen's cost bounded for huge windows).
const MAX_ALIASING_INSTANTS: usize = 10_000;

/// The periods `T ∈ [Σ T_mσ, Σ T_Mσ]` at which two non-decaying eigenvalues `λ ≠ λ'` of `A` with
/// equal real parts alias under `e^{AT}`, `T |Im λ − Im λ'| = 2πk`, `k ≥ 1`, each as one tuple of
/// intervals on the segment `T_σ = T_mσ + θ(T_Mσ − T_mσ)` of the box with `Σ T_σ = T`. Only at
/// these isolated periods can the eigenspaces of `e^{AT}` merge while `(A, C)` is detectable, so a
/// grid alone would miss them (as in Ferrante et al. 2016, Remark 3; the rank test is the shared
/// kernel [`pbh_detectability`]). The comparisons of eigenvalues are relative to `|λ|`, and the
/// non-decaying test is the PBH one on `|e^{λT}|`: both are unit-free.
fn aliasing_tuples(
    plant: &RoundRobinPlant,
    settings: &DetectabilityOptions,
) -> Result<Vec<Vec<f64>>, Error> {
    let lo: f64 = plant.sensors().iter().map(|s| s.window().t1()).sum();
    let hi: f64 = plant.sensors().iter().map(|s| s.window().t2()).sum();
    let lambdas = plant
        .a()
        .eigenvalues()
        .map_err(|_| Error::numerical("eigenvalues of A did not converge"))?;
    // A window spanning more aliasing periods than the cap is screened on its grid only (the
    // screen is a necessary condition; the design's own validation still decides).
    let periods = aliasing_instants(
        &lambdas,
        lo.max(f64::MIN_POSITIVE),
        hi.max(f64::MIN_POSITIVE),
        settings.pbh.unit_circle_tol,
        MAX_ALIASING_INSTANTS,
    )
    .unwrap_or_default();
    Ok(periods
        .into_iter()
        .map(|t| {
            let theta = if hi > lo {
                ((t - lo) / (hi - lo)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            plant
                .sensors()
                .iter()
                .map(|s| {
                    let w = s.window();
                    if plant.num_sensors() == 1 {
                        t.clamp(w.t1(), w.t2())
                    } else {
                        w.t1() + theta * (w.t2() - w.t1())
                    }
                })
                .collect()
        })
        .collect())
}

/// [`check_detectability`], turning a failure into [`Error::NotDetectable`] with the failing tuple.
///
/// # Errors
/// [`Error::NotDetectable`] when some tested tuple fails the PBH test, and the errors of
/// [`check_detectability`].
pub fn require_detectable(
    plant: &RoundRobinPlant,
    settings: &DetectabilityOptions,
) -> Result<DetectabilityReport, Error> {
    let rep = check_detectability(plant, settings)?;
    if rep.detectable {
        return Ok(rep);
    }
    let chk = rep
        .worst
        .expect("an undetectable tuple always has a tested eigenvalue");
    let w = chk
        .test
        .worst
        .expect("an undetectable tuple always has a tested eigenvalue");
    Err(Error::NotDetectable {
        intervals: chk.intervals,
        eig_re: w.eigenvalue.re,
        eig_im: w.eigenvalue.im,
        modulus: w.eigenvalue.norm(),
        sigma_min: w.margin,
        rank_tol: settings.pbh.rank_tol,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::test_util::{rr, win};
    use faer::mat;
    use std::f64::consts::PI;

    /// a harmonic oscillator sampled at half its period through `C = [1 0]` is not
    /// detectable (e^{AT} = −I and both modes alias), while a generic period is.
    #[test]
    fn oscillator_at_half_period_is_not_detectable() {
        let w = 3.0;
        let a = mat![[0.0, w], [-w, 0.0]];
        let s = DetectabilityOptions::default();
        let plant = rr(a.clone(), vec![(mat![[1.0, 0.0]], win(PI / w, PI / w))]).unwrap();
        let rep = check_detectability(&plant, &s).unwrap();
        assert!(rep.exact && !rep.detectable);
        assert!((rep.max_spectral_radius - 1.0).abs() < 1e-12);
        match require_detectable(&plant, &s) {
            Err(Error::NotDetectable {
                intervals,
                eig_re,
                sigma_min,
                ..
            }) => {
                assert_eq!(intervals, vec![PI / w]);
                assert!((eig_re + 1.0).abs() < 1e-12);
                assert!(sigma_min < 1e-12);
            }
            other => panic!("expected NotDetectable, got {other:?}"),
        }
        let plant = rr(
            a.clone(),
            vec![(mat![[1.0, 0.0]], win(0.7 * PI / w, 0.7 * PI / w))],
        )
        .unwrap();
        assert!(require_detectable(&plant, &s).is_ok());
        // Jitter box containing the bad period: the screen must catch it (grid hits T = π/ω exactly).
        let plant = rr(a, vec![(mat![[1.0, 0.0]], win(0.5 * PI / w, 1.5 * PI / w))]).unwrap();
        let s3 = DetectabilityOptions {
            points_per_axis: 3,
            ..s
        };
        let rep = check_detectability(&plant, &s3).unwrap();
        // 3 grid tuples + the aliasing period π/ω.
        assert!(!rep.exact && !rep.detectable && rep.tuples == 4);
        // A grid that misses π/ω (issue 22): the aliasing tuple still catches it.
        let s2 = DetectabilityOptions {
            points_per_axis: 2,
            ..s
        };
        match require_detectable(&plant, &s2) {
            Err(Error::NotDetectable { intervals, .. }) => {
                assert!((intervals[0] - PI / w).abs() < 1e-12)
            }
            other => panic!("expected NotDetectable, got {other:?}"),
        }
    }

    /// An unstable mode seen by no sensor is undetectable; a second sensor that sees it fixes that.
    #[test]
    fn unobservable_unstable_mode() {
        let a = mat![[0.5, 0.0], [0.0, -1.0]];
        let s = DetectabilityOptions::default();
        let bad = rr(a.clone(), vec![(mat![[0.0, 1.0]], win(0.2, 0.2))]).unwrap();
        assert!(!check_detectability(&bad, &s).unwrap().detectable);
        let good = rr(
            a,
            vec![
                (mat![[0.0, 1.0]], win(0.1, 0.2)),
                (mat![[1.0, 0.0]], win(0.1, 0.3)),
            ],
        )
        .unwrap();
        let rep = check_detectability(&good, &s).unwrap();
        assert!(rep.detectable && rep.tuples == 26 * 26);
        assert!((rep.max_spectral_radius - (0.5f64 * 0.5).exp()).abs() < 1e-12);
    }

    #[test]
    fn bad_arguments() {
        let a = mat![[0.0, 1.0], [0.0, 0.0]];
        let plant = rr(a, vec![(mat![[1.0, 0.0]], win(0.1, 0.1))]).unwrap();
        let s = DetectabilityOptions::default();
        assert!(pbh(&plant, &[0.1, 0.2], &s).is_err());
        assert!(pbh(&plant, &[f64::NAN], &s).is_err());
        let mut bad_tol = s;
        bad_tol.pbh.rank_tol = -1.0;
        assert!(matches!(
            pbh(&plant, &[0.1], &bad_tol),
            Err(Error::Linalg(sporadic_linalg::LinalgError::Input(InputError::InvalidParameter { name, .. }))) if name == "rank_tol"
        ));
        assert!(
            check_detectability(
                &plant,
                &DetectabilityOptions {
                    points_per_axis: 1,
                    ..s
                }
            )
            .is_err()
        );
    }
}
