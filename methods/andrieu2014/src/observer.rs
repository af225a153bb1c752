//! The continuous–discrete observer with updated sampling period, eqs. (5), (6a–d), (7) of Andrieu,
//! Nadri, Serres & Vivalda (2014), with the index of (5) fixed as the proof's eq. (12) requires.
//!
//! * Flow on `[t_k, t_{k+1})`: `x̂' = A x̂ + f(x̂, u)`, `L' = a2 L M c(x̂, u)`, `M' = a3 M c(x̂, u)`.
//!   With `I(t) = ∫_{t_k}^t c(x̂, u)` the gain has the closed form (integrate `M'`, then `L'`)
//!   `M = e^{a3 I}`, `L = L(t_k) exp((a2/a3)(M − 1))` ([`high_gain`]).
//! * Sampling rule (7): `δ_k = min{s ≥ 0 : s L((t_k + s)^-) = α}` ([`sampling_function`]); since `L ≥ 1`
//!   is nondecreasing on the interval the root is unique in `(0, α/L(t_k)]`.
//! * Jump at `t_{k+1}` ([`jump`]), in this order: measure `y_{k+1}`; correct with the **pre-jump**
//!   `L^- = L(t_{k+1}^-)` and the **just-elapsed** `δ_k`,
//!   `x̂ ← x̂^- + δ_k 𝓛(L^-) K (x̂_1^- − y_{k+1})`, `𝓛(L) = diag(L, …, L^n)` (the printed (5) writes
//!   `𝓛(t_k^-)` with `δ_k`; the proof (12) and causality need the period that ends at the sample);
//!   then `L ← (1 − a1α) L^- + a1α` (6c) and `M ← 1` (6d).

use crate::error::Error;
use sporadic_linalg::InputError;
use sporadic_linalg::input::{check_dimension, check_finite_slice};

/// Observer parameters `(K, α, a1, a2, a3)` of (5)–(7). [`Tuning::new`] only checks that the observer
/// is well defined (`α, a1, a2, a3 > 0`, `a1α < 1`, finite `K`); whether Theorem 2 covers the choice is
/// decided by [`crate::Design::tuning`]. This split lets the crate run the paper's printed,
/// non-certified example too.
#[derive(Debug, Clone, PartialEq)]
pub struct Tuning {
    k: Vec<f64>,
    alpha: f64,
    a1: f64,
    a2: f64,
    a3: f64,
}

impl Tuning {
    /// Validates and stores the parameters.
    pub fn new(k: Vec<f64>, alpha: f64, a1: f64, a2: f64, a3: f64) -> Result<Self, Error> {
        if k.is_empty() {
            return Err(InputError::mismatch("K (order n ≥ 1)", 1, 0).into());
        }
        check_finite_slice(&k, "K")?;
        for (name, v) in [("alpha", alpha), ("a1", a1), ("a2", a2), ("a3", a3)] {
            if !v.is_finite() {
                return Err(InputError::non_finite(name).into());
            }
            if v <= 0.0 {
                return Err(InputError::parameter(name, v, "must be positive").into());
            }
        }
        if a1 * alpha >= 1.0 {
            return Err(InputError::parameter(
                "a1*alpha",
                a1 * alpha,
                "the jump (6c) needs a1*alpha < 1",
            )
            .into());
        }
        Ok(Self {
            k,
            alpha,
            a1,
            a2,
            a3,
        })
    }

    /// Order `n` (length of `K`).
    pub fn order(&self) -> usize {
        self.k.len()
    }
    /// Gain vector `K`.
    pub fn gain(&self) -> &[f64] {
        &self.k
    }
    /// Sampling parameter `α` of (7).
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
    /// Forgetting rate `a1` of (6c).
    pub fn a1(&self) -> f64 {
        self.a1
    }
    /// Gain growth rate `a2` of (6a).
    pub fn a2(&self) -> f64 {
        self.a2
    }
    /// Rate `a3` of (6b).
    pub fn a3(&self) -> f64 {
        self.a3
    }
}

/// Closed form of (6a)–(6b) on `[t_k, t_{k+1})`: returns `(L, M)` with `M = e^{a3 I}` and
/// `L = L(t_k) exp((a2/a3)(M − 1))`, where `I = ∫_{t_k}^t c(x̂, u) ≥ 0`. `expm1` keeps the small-`I`
/// regime accurate.
pub fn high_gain(tuning: &Tuning, l_k: f64, integral: f64) -> (f64, f64) {
    let m_minus_one = (tuning.a3 * integral).exp_m1();
    (
        l_k * (tuning.a2 / tuning.a3 * m_minus_one).exp(),
        1.0 + m_minus_one,
    )
}

/// The sampling function of (7): `g(s) = s · L − α`, zero at the next sample time `t_k + δ_k`.
pub fn sampling_function(tuning: &Tuning, s: f64, l: f64) -> f64 {
    s * l - tuning.alpha
}

/// The gain jump (6c): `L(t_{k+1}) = (1 − a1α) L(t_{k+1}^-) + a1α`. Maps `[1, ∞)` into `[1, ∞)`.
pub fn gain_jump(tuning: &Tuning, l_minus: f64) -> f64 {
    (1.0 - tuning.a1 * tuning.alpha) * l_minus + tuning.a1 * tuning.alpha
}

/// Result of one jump of the observer at a sample time.
#[derive(Debug, Clone, PartialEq)]
pub struct Jump {
    /// Corrected estimate `x̂(t_{k+1})`.
    pub xhat: Vec<f64>,
    /// Post-jump gain `L(t_{k+1})` from (6c).
    pub l: f64,
    /// Output error `x̂_1^- − y_{k+1}` used by the correction.
    pub innovation: f64,
    /// The correction `x̂ − x̂^- = δ_k 𝓛(L^-) K (x̂_1^- − y)`.
    pub correction: Vec<f64>,
}

/// The jump of the observer at `t_{k+1}` (see the module docs for the order of the operations).
/// `delta` is the just-elapsed period `δ_k`, `l_minus = L(t_{k+1}^-)`, `y` the measurement.
pub fn jump(
    tuning: &Tuning,
    xhat_minus: &[f64],
    l_minus: f64,
    delta: f64,
    y: f64,
) -> Result<Jump, Error> {
    let n = tuning.order();
    check_dimension("x̂(t^-)", n, xhat_minus.len())?;
    check_finite_slice(xhat_minus, "x̂(t^-)")?;
    check_finite_slice(&[l_minus, delta, y], "L^-, δ or y at a jump")?;
    if l_minus < 1.0 || delta <= 0.0 {
        return Err(InputError::parameter(
            "L^- / delta",
            if l_minus < 1.0 { l_minus } else { delta },
            "a jump needs L^- >= 1 and delta > 0",
        )
        .into());
    }
    let innovation = xhat_minus[0] - y;
    let mut correction = Vec::with_capacity(n);
    let mut li = 1.0;
    for i in 0..n {
        li *= l_minus;
        correction.push(delta * li * tuning.k[i] * innovation);
    }
    let xhat: Vec<f64> = xhat_minus
        .iter()
        .zip(&correction)
        .map(|(a, b)| a + b)
        .collect();
    check_finite_slice(&xhat, "corrected estimate")?;
    Ok(Jump {
        xhat,
        l: gain_jump(tuning, l_minus),
        innovation,
        correction,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tuning() -> Tuning {
        Tuning::new(vec![-2.0, -1.0], 0.5, 1.0, 0.1, 0.1).unwrap()
    }

    #[test]
    fn tuning_validation() {
        assert!(Tuning::new(vec![], 0.5, 1.0, 0.1, 0.1).is_err());
        assert!(Tuning::new(vec![f64::NAN], 0.5, 1.0, 0.1, 0.1).is_err());
        assert!(matches!(
            Tuning::new(vec![-1.0], 0.0, 1.0, 0.1, 0.1),
            Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "alpha"
        ));
        assert!(matches!(
            Tuning::new(vec![-1.0], 0.5, 2.0, 0.1, 0.1),
            Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "a1*alpha"
        ));
        assert!(matches!(
            Tuning::new(vec![-1.0], 0.5, 1.0, -0.1, 0.1),
            Err(Error::Input(InputError::InvalidParameter { name, .. })) if name == "a2"
        ));
        assert!(matches!(
            Tuning::new(vec![-1.0], 0.5, 1.0, 0.1, f64::INFINITY),
            Err(Error::Input(InputError::NonFinite { .. }))
        ));
    }

    #[test]
    fn closed_form_gain_constant_c() {
        // c ≡ 2 for s = 0.3: I = 0.6, M = e^{0.06}, L = 1.5·exp((0.1/0.1)(e^{0.06} − 1)).
        let (l, m) = high_gain(&tuning(), 1.5, 0.6);
        assert!((m - 0.06f64.exp()).abs() < 1e-15);
        assert!((l - 1.5 * (0.06f64.exp() - 1.0).exp()).abs() < 1e-14);
    }

    #[test]
    fn jump_follows_6c_and_correction_formula() {
        let t = tuning();
        let j = jump(&t, &[1.0, 2.0], 2.0, 0.25, 0.5).unwrap();
        // δ L^- = 0.5 = α ⇒ correction_i = α (L^-)^{i-1} K_i (x̂1 − y).
        assert_eq!(j.innovation, 0.5);
        // α K_1 (x̂1 − y) = 0.5·(−2)·0.5 and α L^- K_2 (x̂1 − y) = 0.5·2·(−1)·0.5.
        assert!((j.correction[0] + 0.5).abs() < 1e-15);
        assert!((j.correction[1] + 0.5).abs() < 1e-15);
        assert!((j.l - (0.5 * 2.0 + 0.5)).abs() < 1e-15);
        assert!(jump(&t, &[1.0], 2.0, 0.25, 0.5).is_err());
        assert!(jump(&t, &[1.0, 2.0], 0.5, 0.25, 0.5).is_err());
        assert!(jump(&t, &[1.0, 2.0], 2.0, 0.25, f64::NAN).is_err());
    }
}
