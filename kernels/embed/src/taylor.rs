//! Truncated-Taylor polytope of `τ ↦ e^{Aτ}` on `[T1, T2]` (Rabehi et al. 2021, §IV, which cites
//! the Taylor method of Hetel, Daafouz & Iung 2011 but gives no order, vertex count or remainder
//! treatment; the construction below follows that method).
//!
//! With `h = T2 − T1`, `E0 = e^{A T1}` and `θ = τ − T1 ∈ [0, h]`, the vertices are
//!
//! ```text
//! M_j = E0 · Σ_{k ≤ j} (Ah)^k / k!,     j = 0..N     (N + 1 vertices).
//! ```
//!
//! For `s = θ/h` the weights `w_j = s^j − s^{j+1}` (`j < N`), `w_N = s^N` are nonnegative, sum
//! to one, and reproduce the truncated series exactly: `Σ_j w_j M_j = E0 Σ_{k≤N} (Aθ)^k/k!`
//! ([`taylor_weights`]). The factor `E0` is kept: in the example of Rabehi et al. `I + LC` always
//! has the eigenvalue 1, so a polytope containing `I` (`μ = 0`) would make the LMIs (44)
//! infeasible. What is left out is
//! `Δ(τ) = E0 Σ_{k>N} (Aθ)^k/k!` with
//!
//! ```text
//! ‖Δ‖_F ≤ ‖E0‖₂ · (‖A‖_F/‖A‖₂) · Σ_{k>N} (‖A‖₂ h)^k / k!      (since ‖A^k‖_F ≤ ‖A‖_F ‖A‖₂^{k−1}),
//! ```
//!
//! reported as [`crate::Embedding::remainder_bound`] together with a first-order estimate of
//! the rounding error of forming the partial sums (`≈ 2(n+1)(1+x) u ‖E0‖_F e^{x}`, `x = ‖A‖₂h`),
//! which also makes very long windows fail loudly instead of returning garbage: split them
//! ([`crate::embed_split`]). The order `N` is either fixed or the smallest one meeting a
//! requested bound.

use faer::{Mat, MatRef, Scale};
use sporadic_linalg::InputError;
use sporadic_linalg::expm_scaled;

use crate::EmbedError;
use crate::embedding::{Containment, Embedding, Method};
use crate::interval::Interval;
use sporadic_linalg::input::check_square_finite;

/// How the truncation order `N` is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TaylorOrder {
    /// Use exactly this order (`N + 1` vertices).
    Fixed(usize),
    /// Smallest order whose remainder bound is at most this (absolute, Frobenius norm).
    Tolerance(f64),
}

/// Options of the Taylor embedding.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaylorOptions {
    /// Order selection. Default: `Tolerance(1e-10)`.
    pub order: TaylorOrder,
    /// Largest admissible order. Default `60`.
    pub max_order: usize,
}

impl Default for TaylorOptions {
    fn default() -> Self {
        Self {
            order: TaylorOrder::Tolerance(1e-10),
            max_order: 60,
        }
    }
}

/// Upper bound on `Σ_{k > order} x^k / k!` for `x ≥ 0` (the Taylor tail of `e^x`), summed
/// term by term without cancellation, closed by a geometric bound and rounded up.
pub fn truncation_tail(x: f64, order: usize) -> f64 {
    if x <= 0.0 || x.is_nan() {
        return 0.0;
    }
    if x.is_infinite() {
        return f64::INFINITY;
    }
    // First dropped term x^{N+1}/(N+1)!.
    let mut term = 1.0;
    for i in 1..=order + 1 {
        term *= x / i as f64;
    }
    let mut sum = 0.0;
    let mut k = order + 1;
    loop {
        sum += term;
        let next = term * x / (k + 1) as f64;
        // Once the ratio x/(k+2) < 1/2, the rest is at most next/(1 − x/(k+2)) ≤ 2·next.
        if (k + 2) as f64 > 2.0 * x && next <= sum * f64::EPSILON {
            sum += next / (1.0 - x / (k + 2) as f64);
            break;
        }
        if !sum.is_finite() {
            return f64::INFINITY;
        }
        term = next;
        k += 1;
    }
    sum * (1.0 + 4.0 * f64::EPSILON * (k as f64 + 2.0))
}

/// Barycentric weights of the Taylor vertices for `s = θ/h ∈ [0, 1]`: `w_j = s^j − s^{j+1}`
/// (`j < order`), `w_order = s^order`. They are nonnegative and sum to one.
pub fn taylor_weights(s: f64, order: usize) -> Vec<f64> {
    let s = s.clamp(0.0, 1.0);
    let mut w = Vec::with_capacity(order + 1);
    let mut p = 1.0;
    for _ in 0..order {
        w.push(p - p * s);
        p *= s;
    }
    w.push(p);
    w
}

/// Spectral norm (largest singular value), rounded up slightly.
fn spectral_norm(m: MatRef<'_, f64>) -> Result<f64, EmbedError> {
    let sv = m
        .singular_values()
        .map_err(|e| EmbedError::Numerical(format!("singular values: {e:?}")))?;
    Ok(sv.into_iter().fold(0.0, f64::max) * (1.0 + 1e-13))
}

/// Taylor-polytope embedding of `{e^{Aτ} : τ ∈ [t1, t2]}` (see the module documentation).
/// `t1 = t2` gives the single vertex `e^{A t1}`.
pub fn taylor_embedding(
    a: MatRef<'_, f64>,
    t1: f64,
    t2: f64,
    options: &TaylorOptions,
) -> Result<Embedding, EmbedError> {
    let n = check_square_finite(a, "A")?;
    let iv = Interval::new(t1, t2)?;
    if let TaylorOrder::Tolerance(tol) = options.order
        && !(tol.is_finite() && tol > 0.0)
    {
        return Err(EmbedError::InvalidArgument(format!(
            "Taylor remainder tolerance must be positive and finite, got {tol}"
        )));
    }
    let e0 = expm_scaled(a, iv.t1())?;
    if iv.is_point() {
        return Ok(Embedding::new(
            a.to_owned(),
            iv,
            vec![e0],
            Method::Taylor { order: 0 },
            Containment::Guaranteed,
            0.0,
        ));
    }
    let h = iv.length();
    let norm_a2 = spectral_norm(a)?;
    let ratio = if norm_a2 > 0.0 {
        a.norm_l2() / norm_a2
    } else {
        1.0
    };
    let e0_2 = spectral_norm(e0.as_ref())?;
    let x = norm_a2 * h;
    let rounding = 2.0 * (n as f64 + 1.0) * (1.0 + x) * f64::EPSILON * e0.norm_l2() * x.exp();
    let remainder =
        |order: usize| e0_2 * ratio * truncation_tail(x, order) * (1.0 + 1e-12) + rounding;
    let order = match options.order {
        TaylorOrder::Fixed(order) => {
            if order > options.max_order {
                return Err(EmbedError::InvalidArgument(format!(
                    "Taylor order {order} exceeds max_order {}",
                    options.max_order
                )));
            }
            order
        }
        TaylorOrder::Tolerance(tol) => (0..=options.max_order)
            .find(|&k| remainder(k) <= tol)
            .ok_or(EmbedError::ToleranceUnreachable {
                requested: tol,
                achieved: remainder(options.max_order),
                order: options.max_order,
            })?,
    };
    let remainder_bound = remainder(order);
    if !remainder_bound.is_finite() {
        return Err(InputError::non_finite("Taylor remainder bound").into());
    }
    let ah = Scale(h) * a;
    let mut term = Mat::<f64>::identity(n, n);
    let mut partial = Mat::<f64>::identity(n, n);
    let mut vertices = Vec::with_capacity(order + 1);
    vertices.push(e0.clone());
    for k in 1..=order {
        term = Scale(1.0 / k as f64) * (&term * &ah);
        partial += &term;
        vertices.push(&e0 * &partial);
    }
    Ok(Embedding::new(
        a.to_owned(),
        iv,
        vertices,
        Method::Taylor { order },
        Containment::Guaranteed,
        remainder_bound,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn tail_matches_closed_form() {
        // Σ_{k>N} x^k/k! = e^x − Σ_{k≤N} x^k/k!, computed here where cancellation is harmless.
        for &(x, n) in &[(1.0f64, 0usize), (1.0, 3), (0.5, 8), (3.0, 10)] {
            let partial: f64 = (0..=n)
                .map(|k| x.powi(k as i32) / (1..=k).map(|i| i as f64).product::<f64>())
                .sum();
            let exact = f64::exp(x) - partial;
            let bound = truncation_tail(x, n);
            // The reference itself carries the cancellation error of e^x − partial.
            let slack = 4.0 * f64::EPSILON * f64::exp(x);
            assert!(
                bound >= exact - slack && bound <= exact * (1.0 + 1e-12) + slack,
                "{x} {n}"
            );
        }
        assert_eq!(truncation_tail(0.0, 3), 0.0);
        // Very small tail: no cancellation (e^x − partial would be 0 in floating point).
        let t = truncation_tail(0.01, 10);
        let first = 0.01f64.powi(11) / (1..=11).map(|i| i as f64).product::<f64>();
        assert!(t >= first && t <= first * 1.001);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn weights_form_a_partition_of_unity(s in 0.0f64..=1.0, order in 0usize..20) {
            let w = taylor_weights(s, order);
            prop_assert_eq!(w.len(), order + 1);
            prop_assert!(w.iter().all(|&x| x >= 0.0));
            prop_assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            // Σ_{j ≥ k} w_j = s^k reproduces the monomials of the truncated series.
            for k in 0..=order {
                let tail: f64 = w[k..].iter().sum();
                prop_assert!((tail - s.powi(k as i32)).abs() < 1e-14);
            }
        }
    }
}
