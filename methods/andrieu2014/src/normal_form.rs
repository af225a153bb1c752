//! A plant file's plant brought to the observability normal form (1) of Andrieu, Nadri, Serres &
//! Vivalda (2014), Section 2.1, so that the observer (5)–(7) applies to it.
//!
//! For `ẋ = Ax + Bu [+ Gφ(Hx)]` read through one output row `y = c x`, the observability matrix
//! `O = [c; cA; …; cA^{n−1}]` gives `z = O x`, `z_i = y^{(i−1)}` of the linear part, and
//! `ż = S z + e_n a'z + O B u [+ O G φ(H O⁻¹ z)]` with `S` the upper shift of (1) and `a' = cAⁿO⁻¹`
//! (the last row of the companion matrix `OAO⁻¹`, i.e. minus the coefficients of the
//! characteristic polynomial of `A`). The input enters through `O B u`, a function of `u` alone, so
//! it is allowed in every row of (1). The remaining term is `f(z, u)` of (1); it is
//! lower-triangular, as (1) requires, when `O G φ(H O⁻¹ z)` is ([`NormalForm::new`] checks it), and
//! its incremental bound is a nonnegative lower-triangular matrix `N` with
//! `|f_j(z + e, u) − f_j(z, u)| ≤ Σ_{i ≤ j} N_{ji} |e_i|` ([`NormalForm::coupling`]), hence
//! Assumption 1, (3), with the constant `c = max N_{ji}`.
//!
//! Time and state scaling ([`NormalForm::scaled_lipschitz`]): with `τ = ω t` and
//! `z̃_i = z_i / ω^{i−1}`, the plant is again in the form (1) (unit shift) with
//! `f̃_j(z̃) = f_j(D_ω z̃)/ω^j`, `D_ω = diag(1, ω, …, ω^{n−1})`, whose constant is
//! `c̃(ω) = max_{i ≤ j} N_{ji} / ω^{j−i+1}`. The frequency `ω` is the designer's choice
//! ([`crate::plant_design`]); [`NormalForm::frequency`] is the scale `ω₀` at which `c̃(ω₀) = 1`.

use faer::linalg::solvers::{DenseSolveCore, Solve};
use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_model::Plant;

use crate::error::Error;

/// Largest condition number of the normal-form transformation accepted, `2^26 = ε^{−1/2} ≈ 6.7e7`
/// (after diagonal equilibration, see [`equilibrated_condition`]).
///
/// Why this value: the coefficients `a' = cAⁿO⁻¹` and the map back `x = O⁻¹z` are computed with a
/// relative error up to about `κ ε`; at `κ ≤ ε^{−1/2}` that is at most `√ε ≈ 1.5e-8`, so at least
/// half of the double-precision digits survive, and `√ε` is also the tolerance at which the
/// structural zeros of the nonlinearity are decided ([`STRUCTURAL_ZERO`]). Beyond it a rounding
/// error could be mistaken for structure, and the estimate `x̂ = O⁻¹ẑ` would be dominated by it
/// for a plant that is only nearly observable.
pub const CONDITION_LIMIT: f64 = 67_108_864.0;

/// Relative size (`√ε`) below which an entry of `OG` or `HO⁻¹` is treated as a structural zero:
/// relative to the same entry computed with absolute values (`|O||G|`, `|H||O⁻¹|`), which is the
/// scale of its rounding error.
pub const STRUCTURAL_ZERO: f64 = 1.4901161193847656e-8;

/// Iteration budget of the two-sided equilibration of [`equilibrated_condition`].
const EQUILIBRATION_ITERATIONS: usize = 40;

/// The observability normal form of a plant read through one output row.
#[derive(Debug, Clone)]
pub struct NormalForm {
    output: usize,
    o: Mat<f64>,
    a: Vec<f64>,
    coupling: Mat<f64>,
    condition: f64,
    raw_condition: f64,
    residual: f64,
}

impl NormalForm {
    /// The normal form of `plant` read through output row `output` (0-based) of its synchronous `C`.
    ///
    /// Errors: [`Error::Input`] for a round-robin plant or an output index out of range;
    /// [`Error::NoConvergence`] when the observability matrix or the coefficients overflow;
    /// [`Error::NotObservable`] when `(A, c)` is not observable (equilibrated `σ_min/σ_max` of `O`
    /// at or below `n ε`); [`Error::IllConditioned`] when the equilibrated condition number of `O`
    /// exceeds [`CONDITION_LIMIT`]; [`Error::NotTriangular`] when the nonlinearity `OGφ(HO⁻¹z)` is
    /// not lower-triangular in `z`; [`Error::Linalg`] if an SVD fails.
    pub fn new(plant: &Plant, output: usize) -> Result<Self, Error> {
        let c = plant.c().ok_or_else(|| {
            InputError::parameter(
                "outputs",
                plant.sensors().len() as f64,
                "the normal form needs one synchronous output matrix C (round-robin sensors given)",
            )
        })?;
        if output >= c.nrows() {
            return Err(InputError::mismatch(
                "output row (fewer rows in C)",
                output + 1,
                c.nrows(),
            )
            .into());
        }
        let a = plant.a();
        let n = plant.n();
        // Rows c A^i, i = 0..n (row n is c Aⁿ).
        let mut rows = vec![c.row(output).iter().copied().collect::<Vec<f64>>()];
        for _ in 0..n {
            let prev = rows.last().expect("at least one row");
            rows.push(
                (0..n)
                    .map(|j| (0..n).map(|k| prev[k] * a[(k, j)]).sum())
                    .collect(),
            );
        }
        if rows.iter().flatten().any(|v| !v.is_finite()) {
            return Err(Error::NoConvergence {
                what: format!(
                    "the observability matrix of output {} (rows c A^i) overflows the \
                     double-precision range",
                    output + 1
                ),
            });
        }
        let o = Mat::from_fn(n, n, |i, j| rows[i][j]);
        let (condition, raw_condition) = equilibrated_condition(o.as_ref())?;
        if !(condition.is_finite() && condition * (n as f64) * f64::EPSILON < 1.0) {
            return Err(Error::NotObservable {
                output: output + 1,
                condition,
            });
        }
        if condition > CONDITION_LIMIT {
            return Err(Error::IllConditioned {
                output: output + 1,
                condition,
                limit: CONDITION_LIMIT,
            });
        }
        let lu = o.partial_piv_lu();
        // a' = c Aⁿ O⁻¹  ⇔  O' a = (c Aⁿ)'.
        let rhs = Mat::from_fn(n, 1, |i, _| rows[n][i]);
        let a_col = lu.solve_transpose(&rhs);
        let coef: Vec<f64> = (0..n).map(|i| a_col[(i, 0)]).collect();
        if coef.iter().any(|v| !v.is_finite()) {
            return Err(Error::NoConvergence {
                what: "the normal-form coefficients a' = c A^n O^-1 overflow".into(),
            });
        }
        // Independent check of the last row of O A = (S + e_n a') O, relative to its scale.
        let mut residual = 0.0f64;
        for j in 0..n {
            let (mut r, mut s) = (rows[n][j], rows[n][j].abs());
            for i in 0..n {
                r -= coef[i] * o[(i, j)];
                s += (coef[i] * o[(i, j)]).abs();
            }
            if s > 0.0 {
                residual = residual.max(r.abs() / s);
            }
        }
        let mut coupling = Mat::zeros(n, n);
        for i in 0..n {
            coupling[(n - 1, i)] = coef[i].abs();
        }
        if let Some(lip) = plant.lipschitz() {
            let o_inv = lu.inverse();
            let og = structural(o.as_ref(), lip.g())?;
            let h_oinv = structural(lip.h(), o_inv.as_ref())?;
            let (q, r) = (lip.g().ncols(), lip.h().nrows());
            for l in 0..q {
                for m in 0..r {
                    let jmax = lip.jacobian_lower()[(l, m)]
                        .abs()
                        .max(lip.jacobian_upper()[(l, m)].abs());
                    if jmax == 0.0 {
                        continue;
                    }
                    for j in 0..n {
                        if og[(j, l)] == 0.0 {
                            continue;
                        }
                        for i in 0..n {
                            if h_oinv[(m, i)] == 0.0 {
                                continue;
                            }
                            if i > j {
                                return Err(Error::NotTriangular {
                                    row: j + 1,
                                    column: i + 1,
                                    nonlinearity: l + 1,
                                    argument: m + 1,
                                });
                            }
                            coupling[(j, i)] += og[(j, l)].abs() * jmax * h_oinv[(m, i)].abs();
                        }
                    }
                }
            }
        }
        Ok(Self {
            output,
            o,
            a: coef,
            coupling,
            condition,
            raw_condition,
            residual,
        })
    }

    /// The output row used (0-based).
    pub fn output(&self) -> usize {
        self.output
    }
    /// Order `n`.
    pub fn order(&self) -> usize {
        self.a.len()
    }
    /// The transformation `z = O x` (observability matrix of `(A, c)`), before time scaling.
    pub fn transformation(&self) -> MatRef<'_, f64> {
        self.o.as_ref()
    }
    /// `a` with `ż_n = a'z + …` (last row of the companion matrix `OAO⁻¹`).
    pub fn coefficients(&self) -> &[f64] {
        &self.a
    }
    /// The incremental bound `N` of `f` (module docs): lower-triangular, nonnegative.
    pub fn coupling(&self) -> MatRef<'_, f64> {
        self.coupling.as_ref()
    }
    /// Condition number of `O` after diagonal equilibration of rows and columns (the one compared
    /// with [`CONDITION_LIMIT`]; independent of the state units and of the time scaling).
    pub fn condition(&self) -> f64 {
        self.condition
    }
    /// Condition number of `O` as given, in the plant's own units.
    pub fn raw_condition(&self) -> f64 {
        self.raw_condition
    }
    /// Relative residual of `c Aⁿ = a'O` (the companion identity `OA = (S + e_n a')O`, last row).
    pub fn residual(&self) -> f64 {
        self.residual
    }

    /// `c̃(ω) = max_{i ≤ j} N_{ji}/ω^{j−i+1}`: the constant of Assumption 1 in the scaled
    /// coordinates `τ = ωt`, `z̃_i = z_i/ω^{i−1}` (module docs).
    ///
    /// Each term is evaluated as `(N_{ji}^{1/p}/ω)^p`, `p = j−i+1`, so that `ω^p` cannot overflow
    /// (an overflow to `+∞` would silently give `c̃ = 0`).
    pub fn scaled_lipschitz(&self, omega: f64) -> f64 {
        let n = self.order();
        let mut c = 0.0f64;
        for j in 0..n {
            for i in 0..=j {
                let v = self.coupling[(j, i)];
                if v > 0.0 {
                    let p = (j - i + 1) as i32;
                    c = c.max((v.powf(1.0 / f64::from(p)) / omega).powi(p));
                }
            }
        }
        c
    }

    /// `ω₀ = max_{i ≤ j} N_{ji}^{1/(j−i+1)}`, the frequency at which `c̃(ω₀) = 1` (0 when `f`
    /// vanishes: a pure chain of integrators, which has no time scale of its own). It is
    /// similarity-invariant for a linear plant (it depends on the characteristic polynomial only)
    /// and scales like `k` when the vector field is multiplied by `k`.
    pub fn frequency(&self) -> f64 {
        let n = self.order();
        let mut w = 0.0f64;
        for j in 0..n {
            for i in 0..=j {
                let v = self.coupling[(j, i)];
                if v > 0.0 {
                    w = w.max(v.powf(1.0 / (j - i + 1) as f64));
                }
            }
        }
        w
    }

    /// The scaled transformation `z̃ = T x`, `T = D_ω⁻¹ O`.
    pub fn scaled_transformation(&self, omega: f64) -> Mat<f64> {
        Mat::from_fn(self.order(), self.order(), |i, j| {
            self.o[(i, j)] / omega.powi(i as i32)
        })
    }
}

/// The product `X Y` with the entries below `STRUCTURAL_ZERO · (|X||Y|)` set to exactly zero
/// (module docs). For `Y = O⁻¹` the rounding error of the computed inverse is relative to the
/// condition number, already bounded by [`CONDITION_LIMIT`] = `STRUCTURAL_ZERO⁻¹`.
fn structural(x: MatRef<'_, f64>, y: MatRef<'_, f64>) -> Result<Mat<f64>, Error> {
    if x.ncols() != y.nrows() {
        return Err(InputError::mismatch("inner dimension", x.ncols(), y.nrows()).into());
    }
    Ok(Mat::from_fn(x.nrows(), y.ncols(), |i, j| {
        let (mut v, mut s) = (0.0, 0.0);
        for k in 0..x.ncols() {
            v += x[(i, k)] * y[(k, j)];
            s += (x[(i, k)] * y[(k, j)]).abs();
        }
        if v.abs() <= STRUCTURAL_ZERO * s {
            0.0
        } else {
            v
        }
    }))
}

/// `(κ_eq, κ)`: the 2-norm condition number of `m` after a two-sided diagonal equilibration
/// (Ruiz 2001, row and column scaling by powers of two until every row and column has its largest
/// entry in `[1/2, 2]`, at most 40 sweeps), and that of `m` as given. Diagonal scalings by powers of
/// two are exact and amount to a change of units of the state and of the derivatives of `y`, so
/// `κ_eq` measures what is intrinsically lost in inverting `m`; by van der Sluis (1969) column
/// equilibration is within a factor `√n` of the best column scaling. `+∞` for a singular matrix.
pub fn equilibrated_condition(m: MatRef<'_, f64>) -> Result<(f64, f64), Error> {
    let (r, c) = (m.nrows(), m.ncols());
    let mut s = m.to_owned();
    for _ in 0..EQUILIBRATION_ITERATIONS {
        let mut done = true;
        for i in 0..r {
            let mx = (0..c).fold(0.0f64, |a, j| a.max(s[(i, j)].abs()));
            if mx > 0.0 && !(0.5..=2.0).contains(&mx) {
                done = false;
                let f = pow2(1.0 / mx.sqrt());
                (0..c).for_each(|j| s[(i, j)] *= f);
            }
        }
        for j in 0..c {
            let mx = (0..r).fold(0.0f64, |a, i| a.max(s[(i, j)].abs()));
            if mx > 0.0 && !(0.5..=2.0).contains(&mx) {
                done = false;
                let f = pow2(1.0 / mx.sqrt());
                (0..r).for_each(|i| s[(i, j)] *= f);
            }
        }
        if done {
            break;
        }
    }
    Ok((condition(s.as_ref())?, condition(m)?))
}

/// The nearest power of two (exact scaling).
fn pow2(x: f64) -> f64 {
    2f64.powi(x.log2().round() as i32)
}

/// `σ_max/σ_min` (`+∞` when `σ_min = 0`).
fn condition(m: MatRef<'_, f64>) -> Result<f64, Error> {
    let sv = m.singular_values().map_err(|_| Error::NoConvergence {
        what: "SVD of the observability matrix".into(),
    })?;
    let mx = sv.iter().copied().fold(0.0f64, f64::max);
    let mn = sv.iter().copied().fold(f64::INFINITY, f64::min);
    Ok(if mn > 0.0 { mx / mn } else { f64::INFINITY })
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn equilibration_removes_units_only() {
        let (eq, raw) = equilibrated_condition(mat![[1.0, 0.0], [0.0, 1e10]].as_ref()).unwrap();
        assert!((raw - 1e10).abs() < 1e-3 * 1e10);
        // Powers of two leave each row/column maximum within [1/2, 2].
        assert!(eq < 4.0, "{eq}");
        // Nearly parallel columns: no diagonal scaling helps.
        let (eq, _) = equilibrated_condition(mat![[1.0, 1.0], [1.0, 1.0 + 1e-6]].as_ref()).unwrap();
        assert!(eq > 1e6, "{eq}");
    }

    #[test]
    fn companion_coefficients_of_a_damped_oscillator() {
        // ẍ = −4x − 0.4ẋ read in position: z = x, ż₂ = −4 z₁ − 0.4 z₂; in mm and km/s the same.
        for (a, c) in [
            (mat![[0.0, 1.0], [-4.0, -0.4]], mat![[1.0, 0.0]]),
            (mat![[0.0, 1e6], [-4e-6, -0.4]], mat![[0.001, 0.0]]),
        ] {
            let plant = Plant::linear(a.as_ref(), None, c.as_ref()).unwrap();
            let nf = NormalForm::new(&plant, 0).unwrap();
            assert!((nf.coefficients()[0] + 4.0).abs() < 1e-12);
            assert!((nf.coefficients()[1] + 0.4).abs() < 1e-12);
            assert!((nf.frequency() - 2.0).abs() < 1e-12);
            // c̃(ω) = max(4/ω², 0.4/ω).
            assert!((nf.scaled_lipschitz(4.0) - 0.25).abs() < 1e-12);
            assert!((nf.scaled_lipschitz(20.0) - 0.02).abs() < 1e-12);
        }
    }
}
