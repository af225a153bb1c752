//! Detectability of a discrete-time pair `(Φ, C)` by the Popov–Belevitch–Hautus (PBH) rank test.
//!
//! `x⁺ = Φx, y = Cx` is detectable iff every eigenvalue `z` of `Φ` with `|z| ≥ 1` satisfies
//! `rank [zI − Φ; C] = n` (Hautus 1969; e.g. Zhou, Doyle & Glover, *Robust and Optimal Control*,
//! Theorem 3.7, in its discrete-time form). A sampled plant `ẋ = Ax` read every `T` seconds gives
//! `Φ = e^{AT}`; its eigenvalues are best supplied by spectral mapping, `z_i = e^{λ_i(A) T}`, which
//! stays exact when distinct `λ_i` alias onto the same `z` (eigenvalues computed from a rounded
//! `e^{AT}` split such a multiple eigenvalue by up to `√ε`).
//!
//! The rank test is numerical. The two block rows are normalised separately, the first by the
//! modulus of the tested eigenvalue,
//!
//! ```text
//! H(z) = [ (zI − Φ)/|z| ;  C/‖C‖_F ]
//! ```
//!
//! and the *PBH margin* `σ_min(H(z))` is compared with a tolerance. The margin does not change when
//! `C` is scaled (a change of output units) or when `Φ` and `z` are scaled together, and it is at
//! most `‖Cv‖/(‖C‖_F‖v‖)` for an eigenvector `v` of `z`: how well the output sees that mode.
//! Dividing by `‖Φ‖_F` instead made a mode with `|z| ≪ ‖Φ‖` look unobservable: beside the
//! unstable mode of an inverted pendulum (`‖e^{AT}‖ ≈ 3·10⁸`), the cart's position (`z = 1`,
//! measured directly, margin 0.32 relative to `|z|`) had the margin `7·10⁻⁹` relative to `‖Φ‖_F`,
//! below the tolerance.

use faer::{Mat, MatRef, c64};

use crate::input::{InputError, check_dimension, check_finite};
use crate::{LinalgError, check};

/// Tolerances of [`pbh_detectability`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PbhOptions {
    /// `[zI − Φ; C]` counts as rank deficient when its PBH margin (module docs) is at most
    /// `rank_tol`. Default `1e-8`.
    pub rank_tol: f64,
    /// Eigenvalues with `|z| ≥ 1 − unit_circle_tol` are tested: numerically marginal modes count as
    /// not asymptotically stable. Default `1e-10`.
    pub unit_circle_tol: f64,
}

impl Default for PbhOptions {
    fn default() -> Self {
        Self {
            rank_tol: 1e-8,
            unit_circle_tol: 1e-10,
        }
    }
}

impl PbhOptions {
    /// Checks `rank_tol > 0` (finite) and `0 ≤ unit_circle_tol < 1`.
    ///
    /// # Errors
    /// [`InputError::InvalidParameter`] naming the offending field.
    pub fn validate(&self) -> Result<(), InputError> {
        if !(self.rank_tol.is_finite() && self.rank_tol > 0.0) {
            return Err(InputError::parameter(
                "rank_tol",
                self.rank_tol,
                "must be a positive number",
            ));
        }
        if !(0.0..1.0).contains(&self.unit_circle_tol) {
            return Err(InputError::parameter(
                "unit_circle_tol",
                self.unit_circle_tol,
                "must lie in [0, 1)",
            ));
        }
        Ok(())
    }
}

/// A tested eigenvalue of `Φ` (on or outside the unit circle, up to the tolerance) and its PBH margin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PbhMode {
    /// The eigenvalue `z`.
    pub eigenvalue: c64,
    /// `σ_min` of the block-normalised PBH matrix `H(z)` (module docs).
    pub margin: f64,
}

/// Outcome of [`pbh_detectability`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PbhTest {
    /// Spectral radius `max |z_i|` of `Φ` (from the supplied eigenvalues).
    pub spectral_radius: f64,
    /// The tested eigenvalue with the smallest margin; `None` when `Φ` is Schur (nothing to test).
    pub worst: Option<PbhMode>,
    /// Whether every tested eigenvalue has a margin above `rank_tol`.
    pub detectable: bool,
}

/// The sampling intervals `v ∈ [lo, hi]` at which two non-decaying eigenvalues `λ ≠ λ'` of `A`
/// with equal real parts alias under `e^{Av}`: `v |Im λ − Im λ'| = 2πk`, `k ≥ 1`. Only at these
/// isolated `v` can two eigenvalues of `e^{Av}` merge while `(A, C)` is detectable, so a grid of
/// `v` alone would miss them (Ferrante et al. 2016, Remark 3; Sferlazza et al. 2021,
/// Proposition 1, for the period of a round of sensors).
///
/// A mode counts as non-decaying when `|e^{λv}| ≥ 1 − unit_circle_tol` for some `v ≥ lo`, i.e.
/// `Re λ ≥ ln(1 − unit_circle_tol)/lo`; eigenvalues are compared relative to their modulus, so
/// the result does not depend on the time unit. Sorted, without duplicates.
///
/// # Errors
/// [`InputError`] when `0 < lo ≤ hi` fails, and when the window holds more than `max` aliasing
/// instants (a window that long is to be split, not tested point by point).
pub fn aliasing_instants(
    lambdas: &[c64],
    lo: f64,
    hi: f64,
    unit_circle_tol: f64,
    max: usize,
) -> Result<Vec<f64>, InputError> {
    crate::input::check_window("aliasing window", lo, hi, crate::input::LowerEnd::Positive)?;
    let re_floor = (-unit_circle_tol).ln_1p() / lo;
    let slow: Vec<c64> = lambdas
        .iter()
        .copied()
        .filter(|l| l.re >= re_floor)
        .collect();
    let mut out = Vec::new();
    for (i, li) in slow.iter().enumerate() {
        for lj in &slow[i + 1..] {
            let scale = li.norm().max(lj.norm());
            let d = (li.im - lj.im).abs();
            // Equal real parts up to rounding of the eigenvalue solver, distinct imaginary parts.
            if (li.re - lj.re).abs() > 1e-9 * scale || d <= 1e-12 * scale {
                continue;
            }
            let tau = std::f64::consts::TAU;
            let k_lo = (lo * d / tau).ceil().max(1.0);
            let k_hi = (hi * d / tau).floor();
            if k_hi - k_lo + 1.0 + out.len() as f64 > max as f64 {
                return Err(InputError::parameter(
                    "T2 - T1",
                    hi - lo,
                    format!(
                        "the window spans more than {max} aliasing instants of the non-decaying \
                         modes; split it"
                    ),
                ));
            }
            let mut k = k_lo;
            while k <= k_hi {
                out.push(tau * k / d);
                k += 1.0;
            }
        }
    }
    out.sort_by(f64::total_cmp);
    out.dedup();
    Ok(out)
}

/// PBH test of detectability of `(Φ, C)` (module docs), given the `n` eigenvalues of `Φ` (with
/// multiplicity). For a general `Φ` pass `Φ.eigenvalues()`; for `Φ = e^{AT}` pass `e^{λ_i(A) T}`.
///
/// A `C` with no rows (or `C = 0`) observes nothing: the pair is then detectable iff `Φ` is Schur.
///
/// # Errors
/// `Φ` not square, empty or non-finite; `C` with a column count other than `n` or non-finite
/// entries; a number of eigenvalues other than `n` or a non-finite one; invalid options
/// ([`PbhOptions::validate`]); [`LinalgError::NoConvergence`] if an SVD fails.
pub fn pbh_detectability(
    phi: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
    eigenvalues: &[c64],
    options: &PbhOptions,
) -> Result<PbhTest, LinalgError> {
    let n = check::square_finite(phi, "pbh_detectability: Φ")?;
    check_dimension("pbh_detectability: columns of C", n, c.ncols())?;
    check_finite(c, "pbh_detectability: C")?;
    check_dimension(
        "pbh_detectability: number of eigenvalues of Φ",
        n,
        eigenvalues.len(),
    )?;
    if let Some(i) = eigenvalues
        .iter()
        .position(|z| !(z.re.is_finite() && z.im.is_finite()))
    {
        return Err(
            InputError::non_finite(format!("pbh_detectability: eigenvalue {i} of Φ")).into(),
        );
    }
    options.validate()?;

    let m = c.nrows();
    let c_scale = c.norm_l2().max(f64::MIN_POSITIVE);
    let mut spectral_radius = 0.0f64;
    let mut worst: Option<PbhMode> = None;
    for &z in eigenvalues {
        let modulus = z.norm();
        spectral_radius = spectral_radius.max(modulus);
        if modulus < 1.0 - options.unit_circle_tol {
            continue;
        }
        let h = Mat::<c64>::from_fn(n + m, n, |i, j| {
            if i < n {
                let diag = if i == j { z } else { c64::new(0.0, 0.0) };
                (diag - c64::new(phi[(i, j)], 0.0)) / modulus
            } else {
                c64::new(c[(i - n, j)] / c_scale, 0.0)
            }
        });
        let margin = h
            .singular_values()
            .map_err(|_| LinalgError::no_convergence("SVD of the PBH matrix"))?
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        if worst.is_none_or(|w| margin < w.margin) {
            worst = Some(PbhMode {
                eigenvalue: z,
                margin,
            });
        }
    }
    Ok(PbhTest {
        spectral_radius,
        worst,
        detectable: worst.is_none_or(|w| w.margin > options.rank_tol),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;
    use proptest::prelude::*;
    use std::f64::consts::PI;

    fn eig(a: &Mat<f64>) -> Vec<c64> {
        a.eigenvalues().unwrap()
    }

    /// `Φ = diag(2, 1/2)`: the unstable mode `e₁` is invisible through `C = [0 1]` (margin exactly 0)
    /// and visible through `C = [1 0]`, where `H(2)` has orthogonal columns of norms `1` and
    /// `1.5/|z| = 0.75`.
    #[test]
    fn diagonal_pair_closed_form() {
        let phi = mat![[2.0, 0.0], [0.0, 0.5]];
        let o = PbhOptions::default();
        let hidden =
            pbh_detectability(phi.as_ref(), mat![[0.0, 1.0]].as_ref(), &eig(&phi), &o).unwrap();
        assert!(!hidden.detectable);
        assert_eq!(hidden.spectral_radius, 2.0);
        let w = hidden.worst.unwrap();
        assert_eq!(
            (w.eigenvalue.re, w.eigenvalue.im, w.margin),
            (2.0, 0.0, 0.0)
        );
        // Scaling C does not change the verdict or the margin.
        let seen =
            pbh_detectability(phi.as_ref(), mat![[-7.0, 0.0]].as_ref(), &eig(&phi), &o).unwrap();
        assert!(seen.detectable);
        assert!((seen.worst.unwrap().margin - 0.75).abs() < 1e-15);
    }

    /// A linearised inverted pendulum on a cart (states: position, velocity, angle, angular
    /// velocity), position and angle measured, sampled every `T = 2.66765`: `e^{AT}` has norm
    /// `≈ 3·10⁸` from the unstable pendulum mode, while the cart's position (`z = 1`) is
    /// measured directly. Its margin relative to `|z|` is that of a visible mode; relative to
    /// `‖Φ‖_F` it was `7·10⁻⁹` and the pair was reported undetectable.
    #[test]
    fn a_measured_slow_mode_beside_a_fast_unstable_one_is_detectable() {
        let a = mat![
            [0.0, 1.0, 0.0, 0.0],
            [0.0, -0.2, -3.924, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [0.0, 2.0 / 3.0, 45.78, 0.0]
        ];
        let c = mat![[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]];
        let t = 2.66765;
        let at = Mat::from_fn(4, 4, |i, j| a[(i, j)] * t);
        let phi = crate::expm(at.as_ref()).unwrap();
        assert!(phi.norm_l2() > 1e8);
        let z: Vec<c64> = eig(&a).iter().map(|l| (*l * t).exp()).collect();
        let test = pbh_detectability(phi.as_ref(), c.as_ref(), &z, &PbhOptions::default()).unwrap();
        assert!(test.detectable);
        let worst = test.worst.unwrap();
        assert!(worst.margin > 0.1, "{worst:?}");
        // Without the angle sensor the unstable mode is still seen through the cart's position,
        // and without the position sensor the cart's position is not seen at all.
        let angle = mat![[0.0, 0.0, 1.0, 0.0]];
        let blind =
            pbh_detectability(phi.as_ref(), angle.as_ref(), &z, &PbhOptions::default()).unwrap();
        assert!(!blind.detectable, "{blind:?}");
    }

    /// The harmonic oscillator `ẋ = [0 ω; −ω 0]x` read through `C = [1 0]` every `T = π/ω`:
    /// `e^{AT} = −I`, both modes alias onto `z = −1` and the pair is not detectable; at `T = 0.7π/ω`
    /// it is. Eigenvalues by spectral mapping `e^{±iωT}`.
    #[test]
    fn oscillator_aliasing_by_spectral_mapping() {
        let w = 3.0;
        let c = mat![[1.0, 0.0]];
        for (t, detectable) in [(PI / w, false), (0.7 * PI / w, true)] {
            let (co, si) = ((w * t).cos(), (w * t).sin());
            let phi = mat![[co, si], [-si, co]];
            let z = [c64::new(co, si), c64::new(co, -si)];
            let r =
                pbh_detectability(phi.as_ref(), c.as_ref(), &z, &PbhOptions::default()).unwrap();
            assert_eq!(r.detectable, detectable, "T = {t}");
            assert!((r.spectral_radius - 1.0).abs() < 1e-15);
        }
    }

    /// A Schur `Φ` is detectable whatever `C` is, even with no outputs at all.
    #[test]
    fn schur_matrix_needs_no_output() {
        let none = Mat::<f64>::zeros(0, 2);
        // (Φ, ρ(Φ), detectable): the same C with an unstable Φ is not detectable.
        for (phi, rho, detectable) in [
            (mat![[0.5, 10.0], [0.0, -0.9]], 0.9, true),
            (mat![[1.5, 10.0], [0.0, -0.9]], 1.5, false),
        ] {
            let o = PbhOptions::default();
            let r = pbh_detectability(phi.as_ref(), none.as_ref(), &eig(&phi), &o).unwrap();
            assert_eq!((r.detectable, r.worst.is_none()), (detectable, detectable));
            assert!((r.spectral_radius - rho).abs() < 1e-15);
        }
    }

    #[test]
    fn bad_input_is_reported() {
        let phi = mat![[2.0, 0.0], [0.0, 0.5]];
        let c = mat![[1.0, 0.0]];
        let z = eig(&phi);
        let o = PbhOptions::default();
        let rect = Mat::<f64>::zeros(2, 3);
        assert!(matches!(
            pbh_detectability(rect.as_ref(), c.as_ref(), &z, &o),
            Err(LinalgError::Input(InputError::NotSquare { .. }))
        ));
        assert_eq!(
            pbh_detectability(phi.as_ref(), mat![[1.0]].as_ref(), &z, &o),
            Err(InputError::mismatch("pbh_detectability: columns of C", 2, 1).into())
        );
        assert_eq!(
            pbh_detectability(phi.as_ref(), mat![[1.0, f64::NAN]].as_ref(), &z, &o),
            Err(InputError::non_finite("pbh_detectability: C at entry (0,1)").into())
        );
        assert!(pbh_detectability(phi.as_ref(), c.as_ref(), &z[..1], &o).is_err());
        let nan = [z[0], c64::new(f64::NAN, 0.0)];
        assert_eq!(
            pbh_detectability(phi.as_ref(), c.as_ref(), &nan, &o),
            Err(InputError::non_finite("pbh_detectability: eigenvalue 1 of Φ").into())
        );
        for (rank_tol, unit_circle_tol, name) in [
            (0.0, 0.0, "rank_tol"),
            (f64::NAN, 0.0, "rank_tol"),
            (1e-8, 1.0, "unit_circle_tol"),
            (1e-8, -1e-3, "unit_circle_tol"),
        ] {
            let o = PbhOptions {
                rank_tol,
                unit_circle_tol,
            };
            assert!(matches!(
                pbh_detectability(phi.as_ref(), c.as_ref(), &z, &o),
                Err(LinalgError::Input(InputError::InvalidParameter { name: got, .. })) if got == name
            ));
        }
    }

    /// `Φ = Q T Qᵀ` with `T` upper triangular, `T₀₀ = z_u`, the other diagonal entries inside the
    /// disc of radius 0.8 and `Q` a random orthogonal matrix, so `Qe₁` is an eigenvector for `z_u`;
    /// `C = C₀Qᵀ` with `C₀e₁ = 0` when the mode is hidden and `C₀₀ ∈ ±[0.5, 1]` otherwise.
    fn planted(
        n: usize,
        m: usize,
        z_u: f64,
        hidden: bool,
        entries: &[f64],
    ) -> (Mat<f64>, Mat<f64>, Vec<c64>) {
        let mut k = 0;
        let mut next = || {
            k += 1;
            entries[k % entries.len()]
        };
        let t = Mat::from_fn(n, n, |i, j| match (i, j) {
            (0, 0) => z_u,
            _ if i == j => 0.8 * next(),
            _ if i < j => 0.5 * next(),
            _ => 0.0,
        });
        let mut c0 = Mat::from_fn(m, n, |_, _| next());
        c0[(0, 0)] = if hidden {
            0.0
        } else {
            (0.5 + 0.5 * next().abs()).copysign(next())
        };
        for i in 1..m {
            c0[(i, 0)] = if hidden { 0.0 } else { c0[(i, 0)] };
        }
        let q = Mat::from_fn(n, n, |_, _| next()).qr().compute_Q();
        let phi = &q * &t * q.transpose();
        let c = &c0 * q.transpose();
        let z = (0..n).map(|i| c64::new(t[(i, i)], 0.0)).collect();
        (phi, c, z)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// A planted unstable (or marginal) mode with `Cv = 0` is always rejected, and the witness is
        /// that mode; made visible (`C₀e₁ ≠ 0`) the same pair passes, and so does the hidden one once
        /// the mode is moved inside the unit disc (only stable modes are unobservable: detectable).
        #[test]
        fn planted_unobservable_mode(
            n in 2usize..5,
            m in 1usize..3,
            z_u in prop_oneof![1.0f64..3.0, -3.0f64..-1.0],
            entries in proptest::collection::vec(-1.0f64..1.0, 40),
        ) {
            let o = PbhOptions::default();
            let (phi, c, z) = planted(n, m, z_u, true, &entries);
            let r = pbh_detectability(phi.as_ref(), c.as_ref(), &z, &o).unwrap();
            prop_assert!(!r.detectable);
            let w = r.worst.unwrap();
            prop_assert_eq!(w.eigenvalue.re, z_u);
            prop_assert!(w.margin < 1e-13, "margin {}", w.margin);
            prop_assert!((r.spectral_radius - z_u.abs()).abs() < 1e-15);

            let (phi, c, z) = planted(n, m, z_u, false, &entries);
            let r = pbh_detectability(phi.as_ref(), c.as_ref(), &z, &o).unwrap();
            prop_assert!(r.detectable, "{r:?}");
            prop_assert!(r.worst.unwrap().margin > 1e-6, "{r:?}");

            let (phi, c, z) = planted(n, m, 0.9 / z_u, true, &entries);
            let r = pbh_detectability(phi.as_ref(), c.as_ref(), &z, &o).unwrap();
            prop_assert!(r.detectable && r.worst.is_none(), "{r:?}");
        }
    }
}

#[cfg(test)]
mod aliasing_tests {
    use super::*;

    #[test]
    fn aliasing_instants_of_an_oscillator_are_the_multiples_of_pi_over_omega() {
        let w = 10.0;
        let l = [c64::new(0.0, w), c64::new(0.0, -w)];
        let v = aliasing_instants(&l, 0.1, 1.0, 1e-9, 100).unwrap();
        let want: Vec<f64> = (1..=3)
            .map(|k| std::f64::consts::PI * k as f64 / w)
            .collect();
        assert_eq!(v.len(), want.len(), "{v:?}");
        for (a, b) in v.iter().zip(&want) {
            assert!((a - b).abs() <= 1e-15 * b, "{a} {b}");
        }
        // Time scaling: (kA, window/k) gives the instants / k.
        let l10: Vec<c64> = l.iter().map(|x| x * c64::new(10.0, 0.0)).collect();
        let v10 = aliasing_instants(&l10, 0.01, 0.1, 1e-9, 100).unwrap();
        for (a, b) in v10.iter().zip(&v) {
            assert!((a * 10.0 - b).abs() <= 1e-14 * b, "{a} {b}");
        }
        // Decaying modes do not alias; too many instants is an error; bad windows too.
        let decaying = [c64::new(-5.0, w), c64::new(-5.0, -w)];
        assert!(
            aliasing_instants(&decaying, 0.1, 1.0, 1e-9, 100)
                .unwrap()
                .is_empty()
        );
        assert!(aliasing_instants(&l, 0.1, 1e6, 1e-9, 100).is_err());
        assert!(aliasing_instants(&l, 1.0, 0.1, 1e-9, 100).is_err());
    }
}
