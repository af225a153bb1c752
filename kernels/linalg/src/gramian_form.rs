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

use faer::{Mat, MatRef, Side};

use crate::gramian_integral;

/// Largest condition number `λmax(W)/λmin(W)` of the observability Gramian for which the form is
/// usable (the change of coordinates then has a condition number up to `10⁵`).
pub const MAX_GRAMIAN_CONDITION: f64 = 1e10;

/// Largest number of passes of the normalisation (each recomputes the Gramian in the
/// coordinates of the previous one).
pub const GRAMIAN_PASSES: usize = 4;

/// Relative deviation from the identity (eigenvalues, output weights) at which the passes stop.
pub const GRAMIAN_PASS_TOLERANCE: f64 = 1e-6;

/// Largest number of iterations of the output-share balancing.
const OUTPUT_BALANCE_ITERATIONS: usize = 60;

/// Relative deviation of every output share from `n/q` at which the output balancing stops.
const OUTPUT_BALANCE_TOLERANCE: f64 = 1e-6;

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

/// `tr(W_k V Λ⁻¹ Vᵀ)` for every `W_k`.
fn shares(parts: &[Mat<f64>], v: MatRef<'_, f64>, lambda: &[f64]) -> Vec<f64> {
    parts
        .iter()
        .map(|w| {
            let m = v.transpose() * w * v;
            (0..lambda.len()).map(|i| m[(i, i)] / lambda[i]).sum()
        })
        .collect()
}

/// Output weights `s` with equal shares `tr(s_k²W_k W⁻¹) = n/q` of `W = Σ s_k²W_k`, by a
/// multiplicative fixed-point iteration from `s` with a budget (one output needs none); the
/// eigenvalues and eigenvectors of the weighted Gramian. The shares are similarity-invariant,
/// and the fixed point does not depend on the output units.
fn balance_outputs(parts: &[Mat<f64>], s: &mut [f64]) -> Option<(Vec<f64>, Mat<f64>)> {
    let n = parts[0].nrows();
    let total = |s: &[f64]| {
        let mut w = Mat::<f64>::zeros(n, n);
        for (p, sk) in parts.iter().zip(s) {
            w += p * faer::Scale(sk * sk);
        }
        w
    };
    let target = n as f64 / s.len() as f64;
    let (mut lambda, mut v) = eigen(&total(s))?;
    for _ in 0..OUTPUT_BALANCE_ITERATIONS {
        if s.len() == 1 || lambda[0] <= 0.0 {
            break;
        }
        let share: Vec<f64> = shares(parts, v.as_ref(), &lambda)
            .iter()
            .zip(s.iter())
            .map(|(t, sk)| t * sk * sk)
            .collect();
        if share
            .iter()
            .all(|x| (x / target - 1.0).abs() <= OUTPUT_BALANCE_TOLERANCE || *x <= 0.0)
        {
            break;
        }
        for (sk, x) in s.iter_mut().zip(&share) {
            if *x > 0.0 && x.is_finite() {
                *sk *= (target / x).sqrt().clamp(1e-3, 1e3);
            }
        }
        (lambda, v) = eigen(&total(s))?;
    }
    Some((lambda, v))
}
