//! Computable design constants of Theorem 2 of Andrieu et al. (2014): the steps (D1)–(D4) of the
//! proof, made numeric.
//!
//! * (D1) `K`, `P ≻ 0` with (8) `p1 I ≼ P ≼ p2 I`, (9) `(A+KC)'P + P(A+KC) ≼ −I` and
//!   (9b) `p3 P ≼ PD + DP ≼ p4 P`, `D = diag(1, …, n)`. Recipe (not from the paper, which gives
//!   no numeric one): choose `K` and a diagonal `W ≻ 0`, solve
//!   `(A+KC)'P̃ + P̃(A+KC) = −W` with `sporadic_linalg::lyap_continuous` and set `P = P̃/λmin(W)`;
//!   `p1, p2` are the extreme eigenvalues of `P`, `p3, p4` those of the pencil `(PD+DP, P)`.
//! * (D2) `a1 = 1/(2 p2 p4)`.
//! * (D3) `α_m`: the first `α > 0` at which the checkable form of Lemma 4 (17),
//!   `λmax(P^{-1} Q(α)'ψ0(α)Pψ0(α)Q(α)) ≤ 1 − α/(4p2)` with `Q(α) = (I + αKC)e^{Aα}` and
//!   `ψ0(α) = diag((1−a1α)^{-1}, …, (1−a1α)^{-n})` (Lemma 6), or `a1α < 1`, fails. Found by a
//!   geometric scan from `α = 1e-6` (ratio 1.01) followed by bisection.
//! * (D4) `a3 = 2n` and `a2 ≥ 2n (N1(α) + N2(α))/(p3 p1)` (Step 3 of the proof; the design paragraph's
//!   `2(N1+N2)/(p3p1)` drops the factor `n`, a misprint), with `N1, N2` of Lemma 5.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::{check_dimension, check_finite_slice};
use sporadic_linalg::{
    is_positive_definite, lyap_continuous, max_eigenvalue, min_eigenvalue, sym_part,
};

use crate::error::Error;
use crate::observer::Tuning;
use crate::pencil::{pencil_extremes, spectral_norm};
use crate::system::shift_exponential;

/// First `α` of the scan for `α_m`.
const ALPHA_SCAN_START: f64 = 1e-6;
/// Ratio between consecutive scan points (1 % relative resolution).
const ALPHA_SCAN_RATIO: f64 = 1.01;

/// `K_i = −binom(n, i)`, `i = 1..n`: all poles of `A + KC` at −1 (the gain of
/// [`Design::binomial`]). For `n = 2` this is `K = [−2, −1]'`.
pub fn binomial_gain(n: usize) -> Vec<f64> {
    let mut k = Vec::with_capacity(n);
    let mut b = 1.0;
    for i in 1..=n {
        b = b * (n + 1 - i) as f64 / i as f64;
        k.push(-b);
    }
    k
}

/// The weight `W = diag(1, r, …, r^{n−1})` of the Lyapunov equation (used by
/// [`Design::binomial`]). `r = 1` gives `p3 > 0` for `n ≤ 3` only; `r = 0.1` or `0.01` repairs
/// `n = 4..6`.
pub fn geometric_weights(n: usize, r: f64) -> Vec<f64> {
    (0..n).map(|i| r.powi(i as i32)).collect()
}

/// The matrix `I + αKC` (the correction factor of (12)/(13) after the scaling identity `δ_k L^- = α`).
pub fn correction_matrix(k: &[f64], alpha: f64) -> Mat<f64> {
    let n = k.len();
    Mat::from_fn(n, n, |i, j| {
        f64::from(i == j) + if j == 0 { alpha * k[i] } else { 0.0 }
    })
}

/// `Q(α) = (I + αKC) e^{Aα}`, the linear part of the scaled error map of the proof of Theorem 2 (after
/// (14)). For `n = 2`, `det Q(α) = 1 + αK_1` (`= 1 − 2α` for `K = [−2, −1]'`).
pub fn q_matrix(k: &[f64], alpha: f64) -> Result<Mat<f64>, Error> {
    check_finite_slice(k, "K")?;
    if !alpha.is_finite() {
        return Err(InputError::non_finite("alpha").into());
    }
    if k.is_empty() {
        return Err(InputError::mismatch("K (order n ≥ 1)", 1, 0).into());
    }
    Ok(correction_matrix(k, alpha) * shift_exponential(k.len(), alpha))
}

/// The design of Theorem 2 for a given gain `K` and Lyapunov weight `W`: `P`, `p1..p4`, `a1`, `α_m`.
#[derive(Debug, Clone)]
pub struct Design {
    k: Vec<f64>,
    weights: Vec<f64>,
    p: Mat<f64>,
    p1: f64,
    p2: f64,
    p3: f64,
    p4: f64,
    a1: f64,
    alpha_m: f64,
}

impl Design {
    /// (D1)–(D3) for the gain `k` (length `n ≥ 1`) and the diagonal weight `weights` (length `n`,
    /// positive): solves the Lyapunov equation, computes `p1..p4`, `a1` and scans for `α_m`.
    ///
    /// Errors: [`Error::Input`] (`DimensionMismatch`), [`Error::Input`] (`NonFinite`), [`Error::Input`] (`InvalidParameter`) (weights),
    /// [`Error::NotHurwitz`] when `A + KC` is not Hurwitz (e.g. the paper's printed `K = [−2, 1]'`,
    /// poles −2.414 and +0.414), [`Error::NotDiagonallyDominated`] when `p3 ≤ 0`.
    pub fn new(k: &[f64], weights: &[f64]) -> Result<Self, Error> {
        let n = k.len();
        if n == 0 {
            return Err(InputError::mismatch("K (order n ≥ 1)", 1, 0).into());
        }
        check_dimension("Lyapunov weights W", n, weights.len())?;
        check_finite_slice(k, "K")?;
        check_finite_slice(weights, "Lyapunov weights W")?;
        if let Some(&w) = weights.iter().find(|&&w| w <= 0.0) {
            return Err(InputError::parameter("W", w, "Lyapunov weights must be positive").into());
        }
        // A + KC: upper shift plus K in the first column.
        let acl = Mat::from_fn(n, n, |i, j| {
            f64::from(j == i + 1) + if j == 0 { k[i] } else { 0.0 }
        });
        let w = Mat::from_fn(n, n, |i, j| if i == j { weights[i] } else { 0.0 });
        let not_hurwitz = || Error::NotHurwitz { k: k.to_vec() };
        let p_tilde = match lyap_continuous(acl.as_ref(), w.as_ref()) {
            Ok(p) => sym_part(p.as_ref())?,
            Err(sporadic_linalg::LinalgError::Singular { .. }) => return Err(not_hurwitz()),
            Err(e) => return Err(e.into()),
        };
        if !is_positive_definite(p_tilde.as_ref(), 0.0)? {
            return Err(not_hurwitz());
        }
        let wmin = weights.iter().copied().fold(f64::INFINITY, f64::min);
        let p = Mat::from_fn(n, n, |i, j| p_tilde[(i, j)] / wmin);
        let p1 = min_eigenvalue(p.as_ref())?;
        let p2 = max_eigenvalue(p.as_ref())?;
        let pd = Mat::from_fn(n, n, |i, j| p[(i, j)] * (i + 1 + j + 1) as f64);
        let (p3, p4) = pencil_extremes(pd.as_ref(), p.as_ref())?;
        if p3 <= 0.0 {
            return Err(Error::NotDiagonallyDominated { p3 });
        }
        let a1 = 1.0 / (2.0 * p2 * p4);
        let mut design = Self {
            k: k.to_vec(),
            weights: weights.to_vec(),
            p,
            p1,
            p2,
            p3,
            p4,
            a1,
            alpha_m: 0.0,
        };
        design.alpha_m = design.scan_alpha_m()?;
        Ok(design)
    }

    /// The recipe of the module docs with the binomial `K` ([`binomial_gain`], all poles of
    /// `A + KC` at −1) and `W = diag(1, r, …, r^{n−1})` ([`geometric_weights`]).
    pub fn binomial(n: usize, r: f64) -> Result<Self, Error> {
        if !(r.is_finite() && r > 0.0) {
            return Err(InputError::parameter("r", r, "weight ratio must be positive").into());
        }
        Self::new(&binomial_gain(n), &geometric_weights(n, r))
    }

    /// System order `n`.
    pub fn order(&self) -> usize {
        self.k.len()
    }
    /// The gain `K`.
    pub fn gain(&self) -> &[f64] {
        &self.k
    }
    /// The Lyapunov weights `W` (diagonal).
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }
    /// The matrix `P` of (8)–(9b).
    pub fn p(&self) -> MatRef<'_, f64> {
        self.p.as_ref()
    }
    /// `p1 = λmin(P)` (8).
    pub fn p1(&self) -> f64 {
        self.p1
    }
    /// `p2 = λmax(P)` (8).
    pub fn p2(&self) -> f64 {
        self.p2
    }
    /// `p3 = λmin(PD+DP, P)` (9b).
    pub fn p3(&self) -> f64 {
        self.p3
    }
    /// `p4 = λmax(PD+DP, P)` (9b).
    pub fn p4(&self) -> f64 {
        self.p4
    }
    /// `a1 = 1/(2 p2 p4)` (D2).
    pub fn a1(&self) -> f64 {
        self.a1
    }
    /// `a3 = 2n` (D4).
    pub fn a3(&self) -> f64 {
        2.0 * self.order() as f64
    }
    /// `α_m`: the checkable form of (17) holds on `(0, α_m)` (scan resolution 1 %, bisection to 1e-13
    /// relative) and fails just above.
    pub fn alpha_m(&self) -> f64 {
        self.alpha_m
    }

    /// `ψ0(α) = diag((1−a1α)^{-1}, …, (1−a1α)^{-n})` of Lemma 6.
    fn psi0(&self, alpha: f64) -> Mat<f64> {
        let n = self.order();
        let r = 1.0 / (1.0 - self.a1 * alpha);
        Mat::from_fn(n, n, |i, j| if i == j { r.powi(i as i32 + 1) } else { 0.0 })
    }

    /// `λmax(P^{-1} Q(α)'ψ0(α)Pψ0(α)Q(α))`: the left side of the checkable form of (17).
    pub fn lemma4_lambda(&self, alpha: f64) -> Result<f64, Error> {
        let q = q_matrix(&self.k, alpha)?;
        let psi = self.psi0(alpha);
        let r = &psi * &q;
        let m = r.transpose() * &self.p * &r;
        Ok(pencil_extremes(m.as_ref(), self.p.as_ref())?.1)
    }

    /// `1 − α/(4 p2)`: the right side of (17).
    pub fn lemma4_rhs(&self, alpha: f64) -> f64 {
        1.0 - alpha / (4.0 * self.p2)
    }

    /// Whether `a1α < 1` and the checkable form of (17) hold at `α > 0`.
    pub fn lemma4_holds(&self, alpha: f64) -> Result<bool, Error> {
        if !(alpha > 0.0 && self.a1 * alpha < 1.0) {
            return Ok(false);
        }
        Ok(self.lemma4_lambda(alpha)? <= self.lemma4_rhs(alpha))
    }

    fn scan_alpha_m(&self) -> Result<f64, Error> {
        let cap = 1.0 / self.a1;
        let mut lo = ALPHA_SCAN_START;
        if !self.lemma4_holds(lo)? {
            return Err(Error::NoAdmissibleAlpha { alpha: lo });
        }
        let mut hi = loop {
            let next = lo * ALPHA_SCAN_RATIO;
            if next >= cap {
                break cap;
            }
            if !self.lemma4_holds(next)? {
                break next;
            }
            lo = next;
        };
        while hi - lo > 1e-13 * hi {
            let mid = 0.5 * (lo + hi);
            if self.lemma4_holds(mid)? {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Ok(lo)
    }

    /// `N1(α) = 2‖Q(α)‖‖I+αKC‖e^{‖A‖α}‖P‖/(1−a1α)^{2n}` (Lemma 5, spectral norms).
    pub fn n1(&self, alpha: f64) -> Result<f64, Error> {
        let (q, ikc, ea, den) = self.lemma5_parts(alpha)?;
        Ok(2.0 * q * ikc * ea * self.p2 / den)
    }

    /// `N2(α) = ‖I+αKC‖² e^{2‖A‖α}‖P‖/(1−a1α)^{2n}` (Lemma 5, spectral norms).
    pub fn n2(&self, alpha: f64) -> Result<f64, Error> {
        let (_, ikc, ea, den) = self.lemma5_parts(alpha)?;
        Ok(ikc * ikc * ea * ea * self.p2 / den)
    }

    fn lemma5_parts(&self, alpha: f64) -> Result<(f64, f64, f64, f64), Error> {
        if !(alpha > 0.0 && self.a1 * alpha < 1.0) {
            return Err(
                InputError::parameter("alpha", alpha, "need 0 < alpha and a1*alpha < 1").into(),
            );
        }
        let n = self.order();
        let norm_a = if n >= 2 { 1.0 } else { 0.0 };
        let q = spectral_norm(q_matrix(&self.k, alpha)?.as_ref())?;
        let ikc = spectral_norm(correction_matrix(&self.k, alpha).as_ref())?;
        let den = (1.0 - self.a1 * alpha).powi(2 * n as i32);
        Ok((q, ikc, (norm_a * alpha).exp(), den))
    }

    /// `a2,min(α) = 2n (N1(α) + N2(α))/(p3 p1)` (Step 3 of the proof of Theorem 2).
    pub fn a2_min(&self, alpha: f64) -> Result<f64, Error> {
        let n = self.order() as f64;
        Ok(2.0 * n * (self.n1(alpha)? + self.n2(alpha)?) / (self.p3 * self.p1))
    }

    /// Theorem-conforming tuning: checks `0 < α < α_m` ([`Error::AlphaNotAdmissible`]) and
    /// `a2 ≥ a2,min(α)` ([`Error::GainRateTooSmall`]); `a1` and `a3 = 2n` come from the design.
    pub fn tuning(&self, alpha: f64, a2: f64) -> Result<Tuning, Error> {
        if !alpha.is_finite() || !a2.is_finite() {
            return Err(InputError::non_finite("alpha / a2").into());
        }
        if !(alpha > 0.0 && alpha < self.alpha_m) {
            return Err(Error::AlphaNotAdmissible {
                alpha,
                alpha_m: self.alpha_m,
            });
        }
        let a2_min = self.a2_min(alpha)?;
        if a2 < a2_min {
            return Err(Error::GainRateTooSmall { a2, a2_min });
        }
        Tuning::new(self.k.clone(), alpha, self.a1, a2, self.a3())
    }

    /// [`Design::tuning`] with the smallest admissible `a2 = a2,min(α)`.
    pub fn theorem_tuning(&self, alpha: f64) -> Result<Tuning, Error> {
        if !(alpha > 0.0 && alpha < self.alpha_m) {
            return Err(Error::AlphaNotAdmissible {
                alpha,
                alpha_m: self.alpha_m,
            });
        }
        let a2 = self.a2_min(alpha)?;
        self.tuning(alpha, a2)
    }

    /// The Lyapunov function `V(E) = E'PE` of the proof of Theorem 2.
    pub fn lyapunov(&self, e: &[f64]) -> Result<f64, Error> {
        let n = self.order();
        check_dimension("E", n, e.len())?;
        let mut v = 0.0;
        for i in 0..n {
            for j in 0..n {
                v += e[i] * self.p[(i, j)] * e[j];
            }
        }
        Ok(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binomial_gain_values() {
        assert_eq!(binomial_gain(1), vec![-1.0]);
        assert_eq!(binomial_gain(2), vec![-2.0, -1.0]);
        assert_eq!(binomial_gain(4), vec![-4.0, -6.0, -4.0, -1.0]);
    }

    #[test]
    fn scalar_design_closed_form() {
        // n = 1, K = −k: P = w/(2k)/w = 1/(2k), PD+DP = 2P ⇒ p3 = p4 = 2, a1 = 1/(2·(1/(2k))·2) = k/2.
        let d = Design::new(&[-3.0], &[5.0]).unwrap();
        assert!((d.p1() - 1.0 / 6.0).abs() < 1e-14);
        assert!((d.p3() - 2.0).abs() < 1e-13 && (d.p4() - 2.0).abs() < 1e-13);
        assert!((d.a1() - 1.5).abs() < 1e-13);
    }
}
