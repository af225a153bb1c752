//! Lemma 1 of Andrieu et al. (2014) (boundedness of the high gain `L`), made computable after a run.
//!
//! With `c_m` an essential upper bound of `c(x̂(t), u(t))` along the run (proof in Appendix A.1):
//! * `κ(s) = exp(a2 c_m s e^{a3 c_m s})` bounds `L(t)/L(t_k)` for `t − t_k ≤ s` (A.1);
//! * `φ(ℓ) = (1 − a1α) κ(α/ℓ) + a1α/ℓ` decreases from `+∞` to `1 − a1α < 1`; `ℓ1` solves `φ(ℓ1) = 1`;
//! * `L(t_k) ≤ max(L(0), ℓ1, ℓ1 φ(1))` for every `k` (the printed statement omits `L(0)`, but case 2 of
//!   the proof, where every `L(t_k) ≥ ℓ1`, only gives `L(t_k) ≤ L(t_0)`);
//! * `L(t) ≤ κ(α) · max(L(0), ℓ1, ℓ1 φ(1))` for every `t`, and `δ_k ≥ α / sup L`.

use crate::error::Error;
use crate::observer::Tuning;
use sporadic_linalg::InputError;

/// The bounds of Lemma 1 for a given `c_m` and `L(0)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lemma1Bound {
    /// The root `ℓ1` of `φ(ℓ1) = 1`.
    pub ell1: f64,
    /// `φ(1)`.
    pub phi_at_one: f64,
    /// Bound on the post-jump values: `max(L(0), ℓ1, ℓ1 φ(1)) ≥ L(t_k)`.
    pub sample_bound: f64,
    /// Bound on the whole trajectory: `κ(α) · sample_bound ≥ L(t)`.
    pub sup_bound: f64,
    /// Lower bound of the sampling periods: `α / sup_bound ≤ δ_k`.
    pub delta_lower: f64,
}

/// `κ(s) = exp(a2 c_m s e^{a3 c_m s})` of (A.1).
pub fn kappa(tuning: &Tuning, c_m: f64, s: f64) -> f64 {
    (tuning.a2() * c_m * s * (tuning.a3() * c_m * s).exp()).exp()
}

/// `φ(ℓ) = (1 − a1α) κ(α/ℓ) + a1α/ℓ` of Appendix A.1.
pub fn phi(tuning: &Tuning, c_m: f64, ell: f64) -> f64 {
    let a1a = tuning.a1() * tuning.alpha();
    (1.0 - a1a) * kappa(tuning, c_m, tuning.alpha() / ell) + a1a / ell
}

/// Computes the bounds of Lemma 1 for `c_m ≥ 0` and `L(0) ≥ 1` (bisection on `log ℓ`).
pub fn lemma1_bound(tuning: &Tuning, c_m: f64, l0: f64) -> Result<Lemma1Bound, Error> {
    if !(c_m.is_finite() && c_m >= 0.0) {
        return Err(InputError::parameter("c_m", c_m, "need a finite c_m >= 0").into());
    }
    if !(l0.is_finite() && l0 >= 1.0) {
        return Err(InputError::parameter("L(0)", l0, "need a finite L(0) >= 1").into());
    }
    let f = |ell: f64| phi(tuning, c_m, ell) - 1.0;
    let (mut lo, mut hi) = (1.0f64, 1.0f64);
    let no_bracket = || Error::NoConvergence {
        what: "bracketing the root ell1 of phi(ell1) = 1 (Lemma 1)".into(),
    };
    while f(lo) <= 0.0 {
        lo *= 0.5;
        if lo < 1e-300 {
            return Err(no_bracket());
        }
    }
    while f(hi) >= 0.0 {
        hi *= 2.0;
        if hi > 1e300 {
            return Err(no_bracket());
        }
    }
    // f(lo) > 0 > f(hi), lo < hi.
    for _ in 0..200 {
        if hi / lo - 1.0 <= 1e-15 {
            break;
        }
        let mid = (lo * hi).sqrt();
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let ell1 = hi;
    let phi_at_one = phi(tuning, c_m, 1.0);
    let sample_bound = l0.max(ell1).max(ell1 * phi_at_one);
    let sup_bound = kappa(tuning, c_m, tuning.alpha()) * sample_bound;
    Ok(Lemma1Bound {
        ell1,
        phi_at_one,
        sample_bound,
        sup_bound,
        delta_lower: tuning.alpha() / sup_bound,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_lipschitz_gives_ell1_one() {
        // c_m = 0: κ ≡ 1, φ(ℓ) = 1 − a1α + a1α/ℓ, so ℓ1 = 1 and sup L = max(L(0), 1).
        let t = Tuning::new(vec![-1.0], 0.5, 1.0, 3.0, 2.0).unwrap();
        let b = lemma1_bound(&t, 0.0, 2.5).unwrap();
        assert!((b.ell1 - 1.0).abs() < 1e-12);
        assert!((b.sup_bound - 2.5).abs() < 1e-12);
    }

    #[test]
    fn root_satisfies_definition() {
        let t = Tuning::new(vec![-2.0, -1.0], 0.2, 0.069328, 56.2298, 4.0).unwrap();
        let b = lemma1_bound(&t, 1.0, 1.0).unwrap();
        assert!((phi(&t, 1.0, b.ell1) - 1.0).abs() < 1e-9);
        assert!(b.sup_bound >= b.sample_bound && b.sample_bound >= b.ell1);
        assert!(lemma1_bound(&t, -1.0, 1.0).is_err());
        assert!(lemma1_bound(&t, 1.0, 0.5).is_err());
    }
}
