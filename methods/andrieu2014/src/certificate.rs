//! The Lyapunov certificate established by the proof of Theorem 2 of Andrieu et al. (2014), evaluated
//! along a run (checked sample by sample on [`crate::pendulum`] in the tests).
//!
//! With `e = x̂ − x`, `E_k = 𝓛(L(t_k))^{-1} e(t_k)` and `V(E) = E'PE`, Step 3 of the proof gives, for a
//! noise-free run with a theorem-conforming tuning ([`crate::Design::tuning`]),
//! `V(E_{k+1}) − V(E_k) ≤ −(α p1/(4 p2)) ‖𝓛(L(t_{k+1}^-))^{-1} e(t_k)‖²` at every sample.

use crate::closed_loop::Run;
use crate::design::Design;
use crate::error::Error;
use crate::observer::Tuning;
use sporadic_linalg::input::check_len;

/// The decrease condition at one sample `k → k+1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LyapunovStep {
    /// Sample time `t_{k+1}`.
    pub t: f64,
    /// `V(E_k)`.
    pub v_before: f64,
    /// `V(E_{k+1})`.
    pub v_after: f64,
    /// The proof's bound `−(α p1/(4 p2)) ‖𝓛(L(t_{k+1}^-))^{-1} e(t_k)‖²` on `V(E_{k+1}) − V(E_k)`.
    pub bound: f64,
    /// `‖e(t_k)‖`.
    pub error_norm: f64,
    /// `‖E_k‖ = ‖𝓛(L(t_k))^{-1} e(t_k)‖`, the scaled error the certificate is about. Rounding of the
    /// states limits it from below by about `ε·|x|/L(t_k)` (each `e_i` is resolved to about
    /// `L^{i−1} ε |x_1|` once the correction has multiplied the output error by `L^{i−1}`), so the
    /// decrease is only meaningful well above that floor.
    pub scaled_norm: f64,
    /// `L(t_k)`.
    pub l_start: f64,
}

impl LyapunovStep {
    /// Whether `V(E_{k+1}) − V(E_k) ≤ bound` (with a relative slack `rel` of `V(E_k)` for rounding).
    pub fn holds(&self, rel: f64) -> bool {
        self.v_after - self.v_before <= self.bound + rel * self.v_before
    }
}

/// `𝓛(L)^{-1} e = (e_1/L, e_2/L², …)`.
pub fn scaled_error(e: &[f64], l: f64) -> Vec<f64> {
    let mut s = 1.0;
    e.iter()
        .map(|v| {
            s /= l;
            v * s
        })
        .collect()
}

/// Evaluates the decrease condition at every sample of `run` (the first step starts from `e(0)`,
/// `L(0)`).
pub fn lyapunov_steps(
    design: &Design,
    tuning: &Tuning,
    run: &Run,
) -> Result<Vec<LyapunovStep>, Error> {
    let n = design.order();
    check_len(&run.x0, n, "run order vs design order")?;
    let margin = tuning.alpha() * design.p1() / (4.0 * design.p2());
    let mut e_prev: Vec<f64> = run.xhat0.iter().zip(&run.x0).map(|(a, b)| a - b).collect();
    let mut l_prev = run.l0;
    let mut out = Vec::with_capacity(run.samples.len());
    for s in &run.samples {
        let scaled = scaled_error(&e_prev, l_prev);
        let v_before = design.lyapunov(&scaled)?;
        let scaled_norm = scaled.iter().map(|v| v * v).sum::<f64>().sqrt();
        let e = s.error();
        let v_after = design.lyapunov(&scaled_error(&e, s.l_plus))?;
        let w = scaled_error(&e_prev, s.l_minus);
        let bound = -margin * w.iter().map(|v| v * v).sum::<f64>();
        let error_norm = e_prev.iter().map(|v| v * v).sum::<f64>().sqrt();
        out.push(LyapunovStep {
            t: s.t,
            v_before,
            v_after,
            bound,
            error_norm,
            scaled_norm,
            l_start: l_prev,
        });
        e_prev = e;
        l_prev = s.l_plus;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaled_error_divides_by_powers() {
        assert_eq!(scaled_error(&[2.0, 4.0, 8.0], 2.0), vec![1.0, 1.0, 1.0]);
    }
}
