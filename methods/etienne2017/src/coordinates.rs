//! The state coordinates a design is made in (issue 22: a verdict must not depend on the user's
//! units or coordinates), and the maps of its gains and certificate back to the plant's.
//!
//! LMIs (20) are invariant under a change of state coordinates `x = Tx'` in exact arithmetic
//! (`R_p → T⁻¹R_pT`, `P_i → TᵀP_iT`, `L_i → TᵀL_i`), but their margin `t*` is not: the
//! normalisation `‖P_i‖₂ ≤ 1`, `P_i ⪰ tI` measures it in the coordinates of the solve, and the
//! LMI layer accepts a margin only above a verification threshold relative to the data. So a
//! window near the end of the feasible range is certified in some coordinates and not in others:
//! a reactor with a saturating feedback (order 3, one output) certified `T2` up to 4.8338 as
//! written and 4.7750 in coordinates `x = Tz` (`κ(T) < 10`), where `t* = 3.6·10⁻⁷` at
//! `T2 = 4.8` fell below the threshold `5.9·10⁻⁷`.
//!
//! A design is made in the balanced coordinates `x_b = D⁻¹x` (`D` the powers-of-two `gebal`
//! scaling of `|A| + |G||H|`, exact; [`crate::balanced_plant`]), and, when its margin there is
//! positive but not verified, once more in the coordinates of its own certificate,
//! `x' = Rx_b` with `RᵀR = P1/‖P1‖_max + P2/‖P2‖_max`
//! ([`sporadic_linalg::symmetric::certificate_root`]), where the certificate is of the order of
//! the identity and `t*` no longer carries its condition number (not in the paper). The same
//! reactor then certifies up to 4.8356 as written and 4.8353 in `x = Tz`. The design in those
//! coordinates is made and checked on the floating-point plant `(RA_bR⁻¹, RG_b, H_bR⁻¹,
//! C_bR⁻¹)`, as a design in the balanced coordinates is checked on the balanced plant.

use faer::{Mat, MatRef};
use sporadic_linalg::balance::{balance_b, unbalance_form, unbalance_gain};
use sporadic_linalg::symmetric::symmetric_congruence;

use crate::error::Error;
use crate::system::Plant;
use crate::verify::Certificate;

/// Largest condition number `‖R‖₂‖R⁻¹‖₂` of the coordinates of a certificate that a design is
/// solved again in: a larger one comes from a certificate too ill-conditioned to stand for the
/// problem's own scale (its plant would carry that rounding).
pub const MAX_CERTIFICATE_CONDITION: f64 = 1e6;

/// The coordinates of a design: the balanced ones `x_b = D⁻¹x` (`D = diag(scales)`), possibly
/// followed by those of a certificate, `x' = Rx_b`.
#[derive(Debug, Clone, PartialEq)]
pub struct Coordinates {
    scales: Vec<f64>,
    /// `(R, R⁻¹)`.
    own: Option<(Mat<f64>, Mat<f64>)>,
}

impl Coordinates {
    /// The balanced coordinates `x_b = D⁻¹x`, `D = diag(scales)`.
    pub fn balanced(scales: Vec<f64>) -> Self {
        Self { scales, own: None }
    }

    /// The coordinates `x' = Rx_b` of `certificate` (its `P1`, `P2` in the balanced
    /// coordinates), `RᵀR = P1/‖P1‖_max + P2/‖P2‖_max`; `None` when that sum is not
    /// numerically positive definite or `R` is too ill-conditioned
    /// ([`MAX_CERTIFICATE_CONDITION`]).
    pub fn of_certificate(&self, certificate: &Certificate) -> Option<Self> {
        let (r, r_inv) = sporadic_linalg::symmetric::certificate_coordinates(&[
            certificate.p1.clone(),
            certificate.p2.clone(),
        ])?;
        let s = r.singular_values().ok()?;
        let condition = s.first()? / s.last()?;
        (condition <= MAX_CERTIFICATE_CONDITION).then(|| Self {
            scales: self.scales.clone(),
            own: Some((r, r_inv)),
        })
    }

    /// The balanced plant `balanced` in these coordinates: itself, or `(RAR⁻¹, RB, CR⁻¹, RG,
    /// HR⁻¹)` with the same Jacobian bounds.
    ///
    /// # Errors
    /// Those of [`Plant::new`] (non-finite data).
    pub fn plant(&self, balanced: &Plant) -> Result<Plant, Error> {
        let Some((r, r_inv)) = &self.own else {
            return Ok(balanced.clone());
        };
        let polytope = balanced.polytope();
        Plant::new(
            (r * balanced.a() * r_inv).as_ref(),
            (r * balanced.b()).as_ref(),
            (balanced.c() * r_inv).as_ref(),
            (r * balanced.g()).as_ref(),
            (balanced.h() * r_inv).as_ref(),
            polytope.lower(),
            polytope.upper(),
        )
    }

    /// A quadratic form `x'ᵀP'x'` in the plant's coordinates: `P = D⁻¹RᵀP'RD⁻¹`.
    pub fn form_back(&self, p: MatRef<'_, f64>) -> Mat<f64> {
        let pb = match &self.own {
            Some((r, _)) => symmetric_congruence(r.as_ref(), p),
            None => p.to_owned(),
        };
        unbalance_form(pb.as_ref(), &self.scales)
    }

    /// A gain `K'` (`x̂'⁺ = x̂' + K'(y − C'x̂')`) in the plant's coordinates: `K = DR⁻¹K'`.
    pub fn gain_back(&self, k: MatRef<'_, f64>) -> Mat<f64> {
        match &self.own {
            Some((_, r_inv)) => unbalance_gain((r_inv * k).as_ref(), &self.scales),
            None => unbalance_gain(k, &self.scales),
        }
    }

    /// A multiplier `L' = P'K'` in the plant's coordinates: `L = PK = D⁻¹RᵀL'`.
    pub fn multiplier_back(&self, l: MatRef<'_, f64>) -> Mat<f64> {
        match &self.own {
            Some((r, _)) => balance_b((r.transpose() * l).as_ref(), &self.scales),
            None => balance_b(l, &self.scales),
        }
    }

    /// What the report says of these coordinates (`None` for the plant as given).
    pub fn note(&self) -> Option<String> {
        let balanced = self.scales.iter().any(|&x| x != 1.0);
        match &self.own {
            None if balanced => Some(format!(
                "designed in the balanced coordinates x_b = D⁻¹x with D = diag{:?} (powers of 2, \
                 LAPACK gebal scaling of |A| + |G||H|; exact): K and P1, P2, L are in the \
                 plant's coordinates (K = D·K_b, P = D⁻¹P_bD⁻¹, L = D⁻¹L_b); the margin and the \
                 checks are those of the balanced plant",
                self.scales
            )),
            None => None,
            Some((r, r_inv)) => {
                let condition = r.norm_l2() * r_inv.norm_l2();
                Some(format!(
                    "designed in the coordinates of the certificate of a first solve, whose \
                     margin was positive but below the verification threshold: x' = R·x_b with \
                     RᵀR = P1/‖P1‖_max + P2/‖P2‖_max (Cholesky; ‖R‖_F‖R⁻¹‖_F = {condition:.3e}), \
                     x_b = D⁻¹x the balanced coordinates (D = diag{:?}); the margin and the \
                     checks are those of the floating-point plant (RA_bR⁻¹, RG_b, H_bR⁻¹, \
                     C_bR⁻¹) there; K = D·R⁻¹K', P = D⁻¹RᵀP'RD⁻¹, L = D⁻¹RᵀL' are in the \
                     plant's coordinates",
                    self.scales
                ))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    /// The maps back are one change of coordinates: `L = PK` in the plant's coordinates when
    /// `L' = P'K'` in the certificate's, and `P` is the certificate's congruence.
    #[test]
    fn the_maps_back_keep_l_equal_to_p_times_k() {
        let balanced = Coordinates::balanced(vec![0.25, 2.0, 1.0]);
        let certificate = Certificate {
            p1: mat![[4.0, 1.0, 0.0], [1.0, 3.0, 0.5], [0.0, 0.5, 2.0]],
            p2: mat![[2.0, -0.5, 0.2], [-0.5, 5.0, 0.0], [0.2, 0.0, 1.0]],
            l0: Mat::zeros(3, 1),
            l1: Mat::zeros(3, 1),
        };
        let own = balanced.of_certificate(&certificate).unwrap();
        let (p, k) = (
            mat![[1.5, 0.2, -0.1], [0.2, 0.9, 0.3], [-0.1, 0.3, 1.2]],
            mat![[0.7], [-1.1], [0.4]],
        );
        let l = &p * &k;
        let (pb, kb, lb) = (
            own.form_back(p.as_ref()),
            own.gain_back(k.as_ref()),
            own.multiplier_back(l.as_ref()),
        );
        assert!((&pb * &kb - &lb).norm_max() <= 1e-12 * lb.norm_max());
        // The plant's P is the certificate's congruence of P': x'ᵀP'x' = xᵀPx at x = DR⁻¹x'.
        let x = mat![[0.3], [-1.0], [2.0]];
        let xb = Mat::from_fn(3, 1, |i, _| x[(i, 0)] / balanced.scales[i]);
        let (r, _) = own.own.as_ref().unwrap();
        let xp = r * &xb;
        let (v, w) = (
            (x.transpose() * &pb * &x)[(0, 0)],
            (xp.transpose() * &p * &xp)[(0, 0)],
        );
        assert!((v - w).abs() <= 1e-12 * v.abs(), "{v} vs {w}");
    }
}
