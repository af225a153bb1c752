//! The class of systems of Andrieu, Nadri, Serres & Vivalda (2014), Section 2.1: the observability
//! normal form `ẋ = A x + f(x, u)`, eq. (1), with `A` the `n×n` upper shift, `f` lower-triangular,
//! output `y_k = C x(t_k)` with `C = [1 0 … 0]`, eq. (2), and the incremental bound of Assumption 1, (3).

use faer::Mat;
use sporadic_linalg::input::check_len;
use sporadic_linalg::input::{check_dimension, check_finite_slice};

use crate::error::Error;

/// A plant in the observability normal form (1) of Andrieu et al. (2014), implemented by the user.
///
/// The state is `x ∈ R^n` (`n = order()`), the input `u ∈ R^p` (`p = input_dim()`, possibly 0).
/// The linear part `A x` (upper shift, `(Ax)_i = x_{i+1}`) is added by the crate; the user supplies only
/// the lower-triangular nonlinearity `f` and the function `c` of Assumption 1:
///
/// `|f_j(x̂, u) − f_j(x̂ − e, u)| ≤ c(x̂, u) · Σ_{i ≤ j} |e_i|` for all `j, x̂, e, u`,
///
/// i.e. the incremental bound (3) *centred at the estimate*, which is how the proof of Theorem 2 uses it
/// (the observer evaluates `c` at `(x̂(t), u(t))`). `c` must be nonnegative and finite; a constant `c` is
/// the globally Lipschitz case. [`incremental_bound_ratio`] and [`triangularity_defect`] test a
/// user implementation at given points.
pub trait TriangularSystem {
    /// State dimension `n ≥ 1`.
    fn order(&self) -> usize;
    /// Input dimension `p ≥ 0`.
    fn input_dim(&self) -> usize;
    /// Writes `f(x, u)` into `out` (length `n`). Component `j` may depend only on `x_1..x_j` and `u`.
    fn nonlinearity(&self, x: &[f64], u: &[f64], out: &mut [f64]);
    /// The Lipschitz function `c(x̂, u) ≥ 0` of Assumption 1, evaluated at the estimate.
    fn lipschitz(&self, xhat: &[f64], u: &[f64]) -> f64;
}

/// Writes the full vector field `A x + f(x, u)` of (1) into `out`.
pub fn vector_field<S: TriangularSystem + ?Sized>(sys: &S, x: &[f64], u: &[f64], out: &mut [f64]) {
    sys.nonlinearity(x, u, out);
    let n = x.len();
    for i in 0..n.saturating_sub(1) {
        out[i] += x[i + 1];
    }
}

/// The `n×n` upper shift matrix `A` of (1) (`A_{i,i+1} = 1`).
pub fn shift_matrix(n: usize) -> Mat<f64> {
    Mat::from_fn(n, n, |i, j| if j == i + 1 { 1.0 } else { 0.0 })
}

/// `e^{Aα}` for the nilpotent shift `A`, in closed form: entry `(i, j)` is `α^{j−i}/(j−i)!` for
/// `j ≥ i` and 0 below the diagonal (the exponential series terminates after `n` terms).
pub fn shift_exponential(n: usize, alpha: f64) -> Mat<f64> {
    let mut coef = vec![1.0; n];
    for m in 1..n {
        coef[m] = coef[m - 1] * alpha / m as f64;
    }
    Mat::from_fn(n, n, |i, j| if j >= i { coef[j - i] } else { 0.0 })
}

/// The worst ratio `|f_j(x̂) − f_j(x̂ − e)| / (c(x̂,u) Σ_{i≤j}|e_i|)` over `j` at one point: Assumption 1
/// (3) holds there iff the result is `≤ 1`. Returns 0 when `e = 0`, and `+∞` if `c = 0` while `f`
/// changes. Used by tests to validate a user's `c` on samples of its domain.
pub fn incremental_bound_ratio<S: TriangularSystem + ?Sized>(
    sys: &S,
    xhat: &[f64],
    e: &[f64],
    u: &[f64],
) -> Result<f64, Error> {
    let n = sys.order();
    check_dimension("x̂", n, xhat.len())?;
    check_dimension("e", n, e.len())?;
    check_len(u, sys.input_dim(), "u")?;
    check_finite_slice(xhat, "x̂")?;
    check_finite_slice(e, "e")?;
    check_finite_slice(u, "u")?;
    let x: Vec<f64> = xhat.iter().zip(e).map(|(a, b)| a - b).collect();
    let (mut fa, mut fb) = (vec![0.0; n], vec![0.0; n]);
    sys.nonlinearity(xhat, u, &mut fa);
    sys.nonlinearity(&x, u, &mut fb);
    let c = sys.lipschitz(xhat, u);
    let mut worst = 0.0f64;
    let mut partial = 0.0;
    for j in 0..n {
        partial += e[j].abs();
        let diff = (fa[j] - fb[j]).abs();
        if diff == 0.0 {
            continue;
        }
        let ratio = if c * partial > 0.0 {
            diff / (c * partial)
        } else {
            f64::INFINITY
        };
        worst = worst.max(ratio);
    }
    Ok(worst)
}

/// Largest change of `f_j` when only the components `x_{j+1}, …, x_n` are perturbed by `dx`: zero for a
/// lower-triangular `f` (the structure (1) requires). Tests call it at sample points.
pub fn triangularity_defect<S: TriangularSystem + ?Sized>(
    sys: &S,
    x: &[f64],
    dx: &[f64],
    u: &[f64],
) -> Result<f64, Error> {
    let n = sys.order();
    check_dimension("x", n, x.len())?;
    check_dimension("dx", n, dx.len())?;
    check_len(u, sys.input_dim(), "u")?;
    let (mut f0, mut f1) = (vec![0.0; n], vec![0.0; n]);
    sys.nonlinearity(x, u, &mut f0);
    let mut worst = 0.0f64;
    for j in 0..n.saturating_sub(1) {
        let mut y = x.to_vec();
        for i in j + 1..n {
            y[i] += dx[i];
        }
        sys.nonlinearity(&y, u, &mut f1);
        worst = worst.max((f1[j] - f0[j]).abs());
    }
    Ok(worst)
}

/// The true plant of a simulation, in any coordinates `z ∈ R^m` (e.g. the bioreactor's `(X, S)`), with a
/// scalar measured output and a map to the observer's normal-form coordinates `x = Φ(z)` (used only to
/// report the estimation error `e = x̂ − Φ(z)`).
pub trait Plant {
    /// State dimension `m`.
    fn dim(&self) -> usize;
    /// Writes `ż = F(z, u)` into `out`.
    fn rhs(&self, z: &[f64], u: &[f64], out: &mut [f64]);
    /// Noise-free measured output `y = h(z)` (`= x_1` in normal-form coordinates).
    fn output(&self, z: &[f64]) -> f64;
    /// Writes the normal-form coordinates `x = Φ(z)` (length `n` of the observer) into `out`.
    fn to_normal_form(&self, z: &[f64], out: &mut [f64]);
}

/// A [`TriangularSystem`] used as its own plant: `ż = A z + f(z, u)`, `y = z_1`, `Φ = id`.
#[derive(Debug, Clone)]
pub struct NormalFormPlant<S>(pub S);

impl<S: TriangularSystem> Plant for NormalFormPlant<S> {
    fn dim(&self) -> usize {
        self.0.order()
    }
    fn rhs(&self, z: &[f64], u: &[f64], out: &mut [f64]) {
        vector_field(&self.0, z, u, out);
    }
    fn output(&self, z: &[f64]) -> f64 {
        z[0]
    }
    fn to_normal_form(&self, z: &[f64], out: &mut [f64]) {
        out.copy_from_slice(z);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shift_exponential_matches_general_expm() {
        for n in 1..6 {
            let a = shift_matrix(n);
            let e = sporadic_linalg::expm_scaled(a.as_ref(), 0.7).unwrap();
            let c = shift_exponential(n, 0.7);
            for i in 0..n {
                for j in 0..n {
                    assert!((e[(i, j)] - c[(i, j)]).abs() < 1e-14, "n={n} ({i},{j})");
                }
            }
        }
    }
}
