//! The observability-Gramian normal form of a pair `(A, C)`: state coordinates `x' = Gx` in
//! which the observability Gramian on one time unit is the identity, and output weights that
//! give every output the same share of it.
//!
//! Both the design LMI (41) of Ferrante et al. (2016) and the jitter-tolerant condition (44) of
//! Sferlazza et al. (2021) are invariant under a change of state coordinates in exact
//! arithmetic, their numerical solutions are not; a method that solves them in this form gets
//! the same problem, up to an orthogonal change of coordinates, whatever coordinates and output
//! units the user wrote the plant in. Under `x → Tx` the Gramian
//! `W = ∫₀ᵘ e^{Aᵀs}CᵀCe^{As} ds` becomes `T⁻ᵀWT⁻¹`, so `G` (with `GᵀG = W`) becomes `QGT⁻¹` for
//! an orthogonal `Q`; under `y_k → c_k y_k` the output weights absorb `c_k`.
//!
//! The Gramian computed in badly scaled coordinates has rounding errors relative to its largest
//! eigenvalue, so it is computed again in the coordinates it gives (its small eigenvalues floored
//! at `λmax/`[`MAX_GRAMIAN_CONDITION`]) until it is the identity to within
//! [`GRAMIAN_PASS_TOLERANCE`], at most [`GRAMIAN_PASSES`] times.

use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef, Side};

use crate::gramian_integral;

/// Largest condition number `λmax(W)/λmin(W)` of the observability Gramian of each pass for
/// which the form is usable (each pass's change of coordinates then has a condition number up
/// to `10⁵`; the product of the passes can be far worse, and a caller that designs on the
/// rounded form bounds it itself).
pub const MAX_GRAMIAN_CONDITION: f64 = 1e10;

/// Largest number of passes of the normalisation (each recomputes the Gramian in the
/// coordinates of the previous one).
pub const GRAMIAN_PASSES: usize = 6;

/// Relative deviation from the identity (eigenvalues, output weights) at which the passes stop.
/// Two equivalent problems get forms that agree to about this tolerance (or to the Gramian's
/// rounding, when that is larger), and LMI margins at the end of a sampling window are far
/// smaller than `10⁻⁶`: with `10⁻⁶` here, a two-output robot (pitch unstable at `7.5/s`) written in
/// seconds and in milliseconds got forms `10⁻⁷` apart, and windows certified by ferrante2016 0.6 %
/// apart, where its LMI (41) margins are about `10⁻⁹`.
pub const GRAMIAN_PASS_TOLERANCE: f64 = 1e-10;

/// Largest number of Newton steps of the output-share balancing.
const OUTPUT_BALANCE_ITERATIONS: usize = 60;

/// Relative deviation of every output share from `n/q` at which the output balancing stops:
/// below [`GRAMIAN_PASS_TOLERANCE`] (Newton's steps converge quadratically), or the weights'
/// own error keeps the passes from reaching the identity.
const OUTPUT_BALANCE_TOLERANCE: f64 = 1e-12;

/// The Gramian normal form of `(A, C)` on the time unit `u`: `(u·GAG̃, diag(s)·C·G̃)` with
/// `G̃` the computed inverse of `G`.
#[derive(Debug, Clone, PartialEq)]
pub struct GramianForm {
    /// `G` (`x' = Gx`).
    pub state: Mat<f64>,
    /// `G⁻¹` as computed.
    pub state_inverse: Mat<f64>,
    /// Output weights `s_k` (`y'_k = s_k y_k`).
    pub output: Vec<f64>,
}

/// The Gramian normal form of `(A, C)` on the time unit `unit` (see the module docs); `None`
/// when the Gramian is not usable (not positive definite, condition number above
/// [`MAX_GRAMIAN_CONDITION`] after the last pass, a non-finite entry or a failing kernel).
pub fn gramian_form(a: MatRef<'_, f64>, c: MatRef<'_, f64>, unit: f64) -> Option<GramianForm> {
    let (n, q) = (a.nrows(), c.nrows());
    if n == 0 || a.ncols() != n || c.ncols() != n || q == 0 {
        return None;
    }
    let mut form = GramianForm {
        state: Mat::identity(n, n),
        state_inverse: Mat::identity(n, n),
        output: vec![1.0; q],
    };
    for pass in 0..GRAMIAN_PASSES {
        let a1 = &form.state * a * &form.state_inverse * faer::Scale(unit);
        let c1 = c * &form.state_inverse;
        let c1 = Mat::from_fn(q, n, |i, j| form.output[i] * c1[(i, j)]);
        if !(a1.is_all_finite() && c1.is_all_finite()) {
            return None;
        }
        let parts = (0..q)
            .map(|k| {
                let ck = c1.row(k);
                let qk = Mat::from_fn(n, n, |i, j| ck[i] * ck[j]);
                gramian_integral(a1.as_ref(), qk.as_ref(), 1.0).ok()
            })
            .collect::<Option<Vec<_>>>()?;
        let mut weights = vec![1.0; q];
        let (lambda, v) = balance_outputs(&parts, &mut weights)?;
        let (lo, hi) = (lambda[0], lambda[n - 1]);
        if !(hi > 0.0 && hi.is_finite()) {
            return None;
        }
        let identity = lambda
            .iter()
            .all(|l| (l / hi - 1.0).abs() <= GRAMIAN_PASS_TOLERANCE)
            && weights
                .iter()
                .all(|w| (w / weights[0] - 1.0).abs() <= GRAMIAN_PASS_TOLERANCE);
        if identity {
            return Some(form);
        }
        if pass + 1 == GRAMIAN_PASSES && !(lo > 0.0 && hi <= MAX_GRAMIAN_CONDITION * lo) {
            return None;
        }
        let floor = hi / MAX_GRAMIAN_CONDITION;
        let floored: Vec<f64> = lambda.iter().map(|l| l.max(floor)).collect();
        let (g, gi) = root_coordinates(v.as_ref(), &floored);
        form = GramianForm {
            state: g * &form.state,
            state_inverse: &form.state_inverse * gi,
            output: form
                .output
                .iter()
                .zip(&weights)
                .map(|(s, w)| s * w)
                .collect(),
        };
    }
    Some(form)
}

/// The coordinates `x' = Gx` in which the symmetric positive definite matrix `VΛVᵀ` is the
/// identity: `G = Λ^½Vᵀ` and `G⁻¹ = VΛ^{−½}` (as computed), for `V` orthogonal and every
/// `λ_i > 0`.
pub fn root_coordinates(v: MatRef<'_, f64>, lambda: &[f64]) -> (Mat<f64>, Mat<f64>) {
    let n = lambda.len();
    let root: Vec<f64> = lambda.iter().map(|l| l.sqrt()).collect();
    (
        Mat::from_fn(n, n, |i, j| root[i] * v[(j, i)]),
        Mat::from_fn(n, n, |i, j| v[(i, j)] / root[j]),
    )
}

/// Eigenvalues (ascending) and eigenvectors of a symmetric matrix.
fn eigen(w: &Mat<f64>) -> Option<(Vec<f64>, Mat<f64>)> {
    let e = w.self_adjoint_eigen(Side::Lower).ok()?;
    let s = e.S().column_vector();
    let lambda: Vec<f64> = (0..w.nrows()).map(|i| s[i]).collect();
    lambda
        .iter()
        .all(|x| x.is_finite())
        .then(|| (lambda, e.U().to_owned()))
}

/// Output weights `s` with equal shares `tr(s_k²W_k W⁻¹) = n/q` of `W = Σ s_k²W_k` (one output
/// needs none and keeps `s`; several start from `s_k² = 1/tr W_k`); the eigenvalues and
/// eigenvectors of the weighted Gramian. The shares are similarity-invariant, and the weights
/// that equalise them do not depend on the output units (up to their common scale).
///
/// With `t_k = ln s_k²`, the shares minus `n/q` are the gradient of the convex function
/// `f(t) = ln det Σ_k e^{t_k}W_k − (n/q)Σ_k t_k` (convex: by the Cauchy–Binet formula the
/// determinant is a polynomial in the `e^{t_k}` with non-negative coefficients), whose Hessian is
/// `diag(share) − [tr(M_k M_l)]` with `M_k = e^{t_k}W_kW⁻¹`; `f` is constant along `t + c·1`
/// (the common scale, which `W = I` fixes later). Newton's method with a backtracking line search
/// on `f`, with a budget, reaches the equal shares in a few steps; the multiplicative
/// fixed-point iteration `s_k ← s_k·(n/q/share_k)^½` used before needed far more than 60
/// iterations on some plants (two outputs, a double zero eigenvalue), so the same plant with its
/// outputs in other units got another form.
fn balance_outputs(parts: &[Mat<f64>], s: &mut [f64]) -> Option<(Vec<f64>, Mat<f64>)> {
    let (n, q) = (parts[0].nrows(), parts.len());
    let total = |t: &[f64]| {
        let mut w = Mat::<f64>::zeros(n, n);
        for (p, tk) in parts.iter().zip(t) {
            w += p * faer::Scale(tk.exp());
        }
        w
    };
    let target = n as f64 / q as f64;
    // `f(t)` from the eigenvalues of `W(t)` (infinite where `W(t)` is not positive definite).
    let objective = |t: &[f64], lambda: &[f64]| -> f64 {
        if lambda[0] > 0.0 {
            lambda.iter().map(|l| l.ln()).sum::<f64>() - target * t.iter().sum::<f64>()
        } else {
            f64::INFINITY
        }
    };
    // Start from every part scaled to unit trace (`t_k = −ln tr W_k`): a start that does not
    // depend on the output units, from which Newton's steps stay short.
    let mut t: Vec<f64> = if q == 1 {
        s.iter().map(|x| (x * x).ln()).collect()
    } else {
        parts
            .iter()
            .map(|w| {
                let tr: f64 = (0..n).map(|i| w[(i, i)]).sum();
                if tr > 0.0 && tr.is_finite() {
                    -tr.ln()
                } else {
                    0.0
                }
            })
            .collect()
    };
    let (mut lambda, mut v) = eigen(&total(&t))?;
    for _ in 0..OUTPUT_BALANCE_ITERATIONS {
        if q == 1 || lambda[0] <= 0.0 {
            break;
        }
        let w_inv = &v
            * Mat::from_fn(n, n, |i, j| if i == j { 1.0 / lambda[i] } else { 0.0 })
            * v.transpose();
        let m: Vec<Mat<f64>> = parts
            .iter()
            .zip(&t)
            .map(|(w, tk)| w * &w_inv * faer::Scale(tk.exp()))
            .collect();
        let share: Vec<f64> = m
            .iter()
            .map(|mk| (0..n).map(|i| mk[(i, i)]).sum())
            .collect();
        if share.iter().any(|x| !(*x > 0.0 && x.is_finite()))
            || share
                .iter()
                .all(|x| (x / target - 1.0).abs() <= OUTPUT_BALANCE_TOLERANCE)
        {
            break;
        }
        let g: Vec<f64> = share.iter().map(|x| x - target).collect();
        // Hessian plus the projector on the common scale (g ⊥ 1, so the step stays ⊥ 1).
        let h = Mat::from_fn(q, q, |k, l| {
            let cross: f64 = (0..n)
                .map(|i| (0..n).map(|j| m[k][(i, j)] * m[l][(j, i)]).sum::<f64>())
                .sum();
            f64::from(u8::from(k == l)) * share[k] - cross + target / q as f64
        });
        let rhs = Mat::from_fn(q, 1, |k, _| -g[k]);
        let d = h.partial_piv_lu().solve(&rhs);
        if !d.is_all_finite() {
            break;
        }
        let slope: f64 = (0..q).map(|k| g[k] * d[(k, 0)]).sum();
        let f0 = objective(&t, &lambda);
        let mut step = 1.0;
        let next = loop {
            let trial: Vec<f64> = (0..q).map(|k| t[k] + step * d[(k, 0)]).collect();
            // The eigenvalues of an accepted trial are those of the next iterate.
            let accepted = eigen(&total(&trial))
                .filter(|(l, _)| objective(&trial, l) <= f0 + 1e-4 * step * slope);
            if let Some(e) = accepted {
                break Some((trial, e));
            }
            step *= 0.5;
            if step < 1e-10 {
                break None;
            }
        };
        let Some((next, e)) = next else { break };
        t = next;
        (lambda, v) = e;
    }
    for (sk, tk) in s.iter_mut().zip(&t) {
        *sk = (0.5 * tk).exp();
    }
    Some((lambda, v))
}
