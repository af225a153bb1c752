//! The illustrative example of Andrieu et al. (2014), Section 4: the Contois bioreactor (22), with the
//! misprints of the printed normal form and Lipschitz coefficients corrected (listed below).
//!
//! Model (22) with `K1 = K2 = K3 = 1`, state `z = (X, S)`, input `u = D`:
//! `Ẋ = S/(X+S)·X − uX`, `Ṡ = −S/(X+S)·X − u(S − S_in)`, measured output `X(t_k)`.
//! Coordinates `x = Φ(z) = (X, SX/(X+S))`, inverse `S = x1 x2/(x1 − x2)` (needs `x1 > x2`).
//! Normal form: `ẋ1 = x2 + f1`, `ẋ2 = f2`, `f1 = −u x1` and the **corrected**
//! `f2 = S_in u − (1 + u + 2S_in u/x1) x2 + (2/x1 + S_in u/x1²) x2²`.
//!
//! **Misprint:** the paper prints `(2−u)/x1` where `2/x1` is correct; the printed `f2` differs from the
//! true `ẋ2` by `u x2²/x1` ([`F2Form::Printed`] keeps it for the comparison claims). The printed
//! Lipschitz coefficients are also wrong: `c11 = −u` (negative), `c21`, `c22` lack absolute values and
//! `c22` has a sign slip on top of the `f2` error. [`BioreactorNormalForm`] uses the exact difference
//! quotients with absolute values, maximised over the invariant domain `M_x` (the image of `M_z`
//! under `Φ`).
//!
//! The paper does not give `u(t)`, the noise, the initial conditions, `u_min`, `u_max`, `ε2`, nor how
//! `f2` is extended outside `M_x`; [`Scenario::placeholder`] holds this reproduction's placeholder
//! choices and
//! the extension is "evaluate at the projection of `x̂` onto `M_x`".

use crate::error::Error;
use crate::observer::Tuning;
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite_slice;
use sporadic_sim::{Dopri5, Dopri5Options, NoiseSource, PiecewiseConstant};

use crate::closed_loop::{Run, RunOptions, run};
use crate::system::{Plant, TriangularSystem, vector_field};

/// Default number of `x1` grid points for maximising `c21` over `M_x` (reproduction setting, not
/// given in the paper).
pub const DEFAULT_GRID: usize = 2000;

/// `Φ(z) = (X, SX/(X+S))`.
pub fn phi(z: &[f64; 2]) -> [f64; 2] {
    let [x, s] = *z;
    [x, s * x / (x + s)]
}

/// `Φ^{-1}(x) = (x1, x1x2/(x1 − x2))`; errors unless `x1 > x2` and both are finite.
pub fn phi_inverse(x: &[f64; 2]) -> Result<[f64; 2], Error> {
    check_finite_slice(x, "x for the inverse of Phi")?;
    if x[0] <= x[1] {
        return Err(InputError::parameter(
            "x1 - x2",
            x[0] - x[1],
            "the inverse of Phi needs x1 > x2",
        )
        .into());
    }
    Ok([x[0], x[0] * x[1] / (x[0] - x[1])])
}

/// Substrate estimate `Ŝ = x̂1x̂2/(x̂1 − x̂2)` guarded for display: `NaN` when `x̂1 ≤ x̂2`.
pub fn substrate_estimate(xhat: &[f64]) -> f64 {
    phi_inverse(&[xhat[0], xhat[1]]).map_or(f64::NAN, |z| z[1])
}

/// The invariant domain `M_z = {X ≥ ε1, S ≥ ε2, X + S ≤ 1}` and the input range `[u_min, u_max]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    /// Lower bound of the dilution rate.
    pub u_min: f64,
    /// Upper bound of the dilution rate (`< K1 = 1`).
    pub u_max: f64,
    /// Lower bound `ε1` of `X`.
    pub eps1: f64,
    /// Lower bound `ε2` of `S`.
    pub eps2: f64,
}

impl Domain {
    /// The paper's `ε1 = (1 − u_max)ε2/(S_in u_max)` (kept as printed although invariance of `X = ε1`
    /// only needs `ε1 ≤ (1 − u_max)ε2/u_max`; for `S_in = 0.1` the printed value is 10× that).
    pub fn paper(u_min: f64, u_max: f64, eps2: f64, s_in: f64) -> Result<Self, Error> {
        Self::new(u_min, u_max, (1.0 - u_max) * eps2 / (s_in * u_max), eps2)
    }

    /// Validates `0 < u_min ≤ u_max < 1` and `ε1, ε2 > 0`, `ε1 + ε2 < 1`.
    pub fn new(u_min: f64, u_max: f64, eps1: f64, eps2: f64) -> Result<Self, Error> {
        check_finite_slice(&[u_min, u_max, eps1, eps2], "bioreactor domain")?;
        if !(0.0 < u_min && u_min <= u_max && u_max < 1.0) {
            return Err(
                InputError::parameter("u_min/u_max", u_max, "need 0 < u_min <= u_max < 1").into(),
            );
        }
        if !(eps1 > 0.0 && eps2 > 0.0 && eps1 + eps2 < 1.0) {
            return Err(Error::Input(InputError::InvalidParameter {
                name: "eps1/eps2".into(),
                value: eps1,
                reason: "need eps1, eps2 > 0 and eps1 + eps2 < 1".into(),
            }));
        }
        Ok(Self {
            u_min,
            u_max,
            eps1,
            eps2,
        })
    }

    /// Bounds of `x2` over `M_x` at a given `x1 ∈ [ε1, 1−ε2]`: `[ε2 x1/(x1+ε2), x1(1 − x1)]`
    /// (`x2 = SX/(X+S)` increases with `S ∈ [ε2, 1 − X]`).
    pub fn x2_bounds(&self, x1: f64) -> (f64, f64) {
        (self.eps2 * x1 / (x1 + self.eps2), x1 * (1.0 - x1))
    }

    /// Projection onto `M_x`: clip `x1` to `[ε1, 1−ε2]`, then `x2` to its bounds at the clipped `x1`.
    /// Preserves triangularity (component `j` of the result depends on `x_1..x_j` only).
    pub fn project(&self, x: &[f64]) -> [f64; 2] {
        let x1 = x[0].clamp(self.eps1, 1.0 - self.eps2);
        let (lo, hi) = self.x2_bounds(x1);
        [x1, x[1].clamp(lo, hi)]
    }

    /// Whether `z = (X, S)` lies in `M_z` (with slack `tol`).
    pub fn contains_z(&self, z: &[f64; 2], tol: f64) -> bool {
        z[0] >= self.eps1 - tol && z[1] >= self.eps2 - tol && z[0] + z[1] <= 1.0 + tol
    }
}

/// Which `f2` to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum F2Form {
    /// `(2/x1 + S_in u/x1²) x2²`: the true `ẋ2` (verified against the chain rule on (22)).
    Corrected,
    /// The paper's printed `((2−u)/x1 + S_in u/x1²) x2²` (misprint, off by `u x2²/x1`).
    Printed,
}

impl F2Form {
    fn quadratic_coefficient(self, u: f64) -> f64 {
        match self {
            F2Form::Corrected => 2.0,
            F2Form::Printed => 2.0 - u,
        }
    }
}

/// `f2(x, u)` of the normal form (no projection).
pub fn f2(form: F2Form, s_in: f64, x: &[f64], u: f64) -> f64 {
    let (x1, x2) = (x[0], x[1]);
    let q = form.quadratic_coefficient(u);
    s_in * u - (1.0 + u + 2.0 * s_in * u / x1) * x2 + (q / x1 + s_in * u / (x1 * x1)) * x2 * x2
}

/// The Contois model (22) in its own coordinates `(X, S)` as a simulation plant (`K1 = K2 = K3 = 1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contois {
    /// Inlet substrate concentration `S_in`.
    pub s_in: f64,
}

impl Plant for Contois {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, z: &[f64], u: &[f64], out: &mut [f64]) {
        let (x, s, d) = (z[0], z[1], u[0]);
        let growth = s / (x + s) * x;
        out[0] = growth - d * x;
        out[1] = -growth - d * (s - self.s_in);
    }
    fn output(&self, z: &[f64]) -> f64 {
        z[0]
    }
    fn to_normal_form(&self, z: &[f64], out: &mut [f64]) {
        out.copy_from_slice(&phi(&[z[0], z[1]]));
    }
}

/// The bioreactor in normal form (n = 2, p = 1) with `f` and `c` evaluated at the projection onto
/// `M_x` (the extension outside `M_x` that the paper leaves open).
///
/// `c(x̂, u) = max{c11, max_{x∈M_x} c21, max_{x∈M_x} c22}` with (at the projected `x̂`)
/// `c11 = u`, `c21 = |−(1+u+2S_in u/x1) + (q/x1 + S_in u/x1²)(x2 + x̂2)|` (`q = 2` corrected,
/// `2 − u` printed) maximised over the two `x2` bounds (it is affine in `x2`) and an `x1` grid, and
/// `c22 = |β1 t − β2 t²|`, `t = 1/x1`, `β1 = (2S_in u x̂2 − q x̂2²)/x̂1 − S_in u x̂2²/x̂1²`,
/// `β2 = S_in u x̂2²/x̂1`, maximised exactly (interval ends and vertex).
#[derive(Debug, Clone)]
pub struct BioreactorNormalForm {
    s_in: f64,
    domain: Domain,
    form: F2Form,
    /// `(t = 1/x1, x2_lo, x2_hi)` on the `x1` grid.
    grid: Vec<(f64, f64, f64)>,
}

impl BioreactorNormalForm {
    /// Builds the system with a grid of `grid_points ≥ 2` values of `x1` in `[ε1, 1−ε2]`.
    pub fn new(s_in: f64, domain: Domain, form: F2Form, grid_points: usize) -> Result<Self, Error> {
        if !(s_in.is_finite() && s_in > 0.0) {
            return Err(InputError::parameter("S_in", s_in, "must be positive").into());
        }
        if grid_points < 2 {
            return Err(InputError::mismatch("x1 grid points (at least)", 2, grid_points).into());
        }
        let (a, b) = (domain.eps1, 1.0 - domain.eps2);
        let grid = (0..grid_points)
            .map(|i| {
                let x1 = a + (b - a) * i as f64 / (grid_points - 1) as f64;
                let (lo, hi) = domain.x2_bounds(x1);
                (1.0 / x1, lo, hi)
            })
            .collect();
        Ok(Self {
            s_in,
            domain,
            form,
            grid,
        })
    }

    /// The domain `M_x` is built from.
    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// `S_in`.
    pub fn s_in(&self) -> f64 {
        self.s_in
    }
}

impl TriangularSystem for BioreactorNormalForm {
    fn order(&self) -> usize {
        2
    }
    fn input_dim(&self) -> usize {
        1
    }
    fn nonlinearity(&self, x: &[f64], u: &[f64], out: &mut [f64]) {
        let p = self.domain.project(x);
        out[0] = -u[0] * p[0];
        out[1] = f2(self.form, self.s_in, &p, u[0]);
    }
    fn lipschitz(&self, xhat: &[f64], u: &[f64]) -> f64 {
        let [p1, p2] = self.domain.project(xhat);
        let u = u[0];
        let s_in = self.s_in;
        let q = self.form.quadratic_coefficient(u);
        let c11 = u.abs();
        let mut c21 = 0.0f64;
        for &(t, lo, hi) in &self.grid {
            let a = -(1.0 + u) - 2.0 * s_in * u * t;
            let b = q * t + s_in * u * t * t;
            c21 = c21
                .max((a + b * (lo + p2)).abs())
                .max((a + b * (hi + p2)).abs());
        }
        let beta1 = (2.0 * s_in * u * p2 - q * p2 * p2) / p1 - s_in * u * p2 * p2 / (p1 * p1);
        let beta2 = s_in * u * p2 * p2 / p1;
        let g = |t: f64| (beta1 * t - beta2 * t * t).abs();
        let (t_lo, t_hi) = (1.0 / (1.0 - self.domain.eps2), 1.0 / self.domain.eps1);
        let mut c22 = g(t_lo).max(g(t_hi));
        if beta2 > 0.0 {
            let vertex = beta1 / (2.0 * beta2);
            if vertex > t_lo && vertex < t_hi {
                c22 = c22.max(g(vertex));
            }
        }
        c11.max(c21).max(c22)
    }
}

/// A full set of run settings for the bioreactor example.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// `S_in`.
    pub s_in: f64,
    /// Domain and input range.
    pub domain: Domain,
    /// Dilution-rate profile `u(t)`.
    pub input: PiecewiseConstant,
    /// Initial plant state `(X(0), S(0))`.
    pub z0: [f64; 2],
    /// Initial estimate `x̂(0)` (normal-form coordinates).
    pub xhat0: [f64; 2],
    /// Initial gain `L(0) ≥ 1`.
    pub l0: f64,
    /// Horizon.
    pub horizon: f64,
    /// Standard deviation of the additive Gaussian output noise (0 = noise-free).
    pub noise_std: f64,
}

impl Scenario {
    /// Placeholder reproduction settings (the paper gives only `S_in = 0.1` and the horizon 40):
    /// `u = 0.5, 0.2, 0.8, 0.4` on `[0,10), [10,20), [20,30), [30,40]`; `u_min = 0.1`, `u_max = 0.9`,
    /// `ε2 = 0.01` (so `ε1 = 0.011111`); `(X(0), S(0)) = (0.06, 0.04)`; `x̂(0) = Φ(0.06, 0.01)`;
    /// `L(0) = 1`; horizon 40; noise `N(0, 0.001²)` (set `noise_std = 0` for the noise-free runs).
    pub fn placeholder() -> Self {
        let s_in = 0.1;
        let domain = Domain::paper(0.1, 0.9, 0.01, s_in).expect("constant, valid domain");
        let input = PiecewiseConstant::new(
            vec![0.0, 10.0, 20.0, 30.0],
            vec![vec![0.5], vec![0.2], vec![0.8], vec![0.4]],
        )
        .expect("constant, valid input");
        Self {
            s_in,
            domain,
            input,
            z0: [0.06, 0.04],
            xhat0: phi(&[0.06, 0.01]),
            l0: 1.0,
            horizon: 40.0,
            noise_std: 1e-3,
        }
    }
}

/// Runs the observer (corrected normal form, `c` on a [`DEFAULT_GRID`]-point grid) on the Contois model
/// with the scenario's input, initial conditions and horizon; `noise` is added to the sampled `X`.
pub fn simulate(
    scenario: &Scenario,
    tuning: &Tuning,
    noise: &mut dyn NoiseSource,
) -> Result<Run, Error> {
    let sys = BioreactorNormalForm::new(
        scenario.s_in,
        scenario.domain,
        F2Form::Corrected,
        DEFAULT_GRID,
    )?;
    let opts = RunOptions {
        l0: scenario.l0,
        ..RunOptions::new(scenario.horizon)
    };
    run(
        &Contois {
            s_in: scenario.s_in,
        },
        &scenario.z0,
        &sys,
        &scenario.xhat0,
        &scenario.input,
        tuning,
        noise,
        &opts,
    )
}

/// `(t_k, |S(t_k) − Ŝ(t_k)|)` after the correction at every sample of a bioreactor run (`Ŝ` from
/// [`substrate_estimate`], `NaN` if `x̂1 ≤ x̂2`).
pub fn substrate_errors(run: &Run) -> Vec<(f64, f64)> {
    run.samples
        .iter()
        .map(|s| {
            let s_true = s.x[0] * s.x[1] / (s.x[0] - s.x[1]);
            (s.t, (substrate_estimate(&s.xhat_plus) - s_true).abs())
        })
        .collect()
}

/// `|S(T) − Ŝ(T)|` at the end of a bioreactor run.
pub fn final_substrate_error(run: &Run) -> f64 {
    (substrate_estimate(&run.final_estimate()) - run.final_plant_state()[1]).abs()
}

/// Consistency check of the normal form: integrates the model (22) in `(X, S)` and the normal form
/// with `f2` of the given
/// form from `Φ(z0)` side by side (Dormand–Prince, `rtol`, `atol = 1e-3 rtol`, restarted at the input
/// switches) and returns `max_t ‖Φ(z(t)) − x(t)‖∞` over the accepted steps. Tolerance level for
/// [`F2Form::Corrected`]; of order 1e-2 for the printed `f2`.
pub fn normal_form_deviation(scenario: &Scenario, form: F2Form, rtol: f64) -> Result<f64, Error> {
    let sys = BioreactorNormalForm::new(scenario.s_in, scenario.domain, form, 2)?;
    let plant = Contois {
        s_in: scenario.s_in,
    };
    let x0 = phi(&scenario.z0);
    let mut z = vec![scenario.z0[0], scenario.z0[1], x0[0], x0[1]];
    let mut dp = Dopri5::new(Dopri5Options::with_tolerances(rtol, 1e-3 * rtol))?;
    let mut worst = 0.0f64;
    let mut buf = [0.0; 4];
    let mut t = 0.0;
    while t < scenario.horizon {
        let end = scenario
            .input
            .next_breakpoint(t)
            .map_or(scenario.horizon, |b| b.min(scenario.horizon));
        let u = [scenario.input.value(t)[0]];
        let f = |_t: f64, z: &[f64], dz: &mut [f64]| {
            let (a, b) = dz.split_at_mut(2);
            plant.rhs(&z[..2], &u, a);
            vector_field(&sys, &z[2..], &u, b);
        };
        dp.integrate(&f, t, &mut z, end, &[], |step| {
            step.eval(step.t_end, &mut buf);
            let p = phi(&[buf[0], buf[1]]);
            worst = worst.max((p[0] - buf[2]).abs()).max((p[1] - buf[3]).abs());
        })?;
        dp.reset_step();
        t = end;
    }
    Ok(worst)
}

/// The observer parameters printed in Section 4: `K = [−2, 1]'`, `α = 0.9`, `a1 = 1`, `a2 = a3 = 0.1`.
/// `A + KC` then has the eigenvalues `−2.414` and `+0.414` (the minus sign of `K2` was probably
/// lost; `K = [−2, −1]'` gives the double pole −1).
pub fn printed_tuning() -> Tuning {
    Tuning::new(vec![-2.0, 1.0], 0.9, 1.0, 0.1, 0.1).expect("constant, valid tuning")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `ẋ2` from the chain rule on (22): `ẋ2 = (S²Ẋ + X²Ṡ)/(X+S)²`.
    fn x2_dot_chain_rule(z: [f64; 2], u: f64, s_in: f64) -> f64 {
        let mut dz = [0.0; 2];
        Contois { s_in }.rhs(&z, &[u], &mut dz);
        let [x, s] = z;
        (s * s * dz[0] + x * x * dz[1]) / ((x + s) * (x + s))
    }

    #[test]
    fn corrected_f2_is_the_true_derivative_and_printed_is_not() {
        // At X = 0.05, S = 0.03, u = 0.4 the true ẋ2 is 3.44e-3, the printed formula gives 6.25e-4.
        let z = [0.05, 0.03];
        let x = phi(&z);
        let truth = x2_dot_chain_rule(z, 0.4, 0.1);
        assert!((truth - 3.44e-3).abs() < 5e-6, "{truth}");
        assert!((f2(F2Form::Corrected, 0.1, &x, 0.4) - truth).abs() < 1e-15);
        let printed = f2(F2Form::Printed, 0.1, &x, 0.4);
        assert!((printed - 6.25e-4).abs() < 5e-7, "{printed}");
        assert!((truth - printed - 0.4 * x[1] * x[1] / x[0]).abs() < 1e-15);
    }

    #[test]
    fn phi_round_trip_and_guard() {
        let z = [0.06, 0.04];
        let back = phi_inverse(&phi(&z)).unwrap();
        assert!((back[0] - z[0]).abs() < 1e-15 && (back[1] - z[1]).abs() < 1e-15);
        assert!(phi_inverse(&[0.1, 0.2]).is_err());
        assert!(substrate_estimate(&[0.1, 0.2]).is_nan());
    }

    #[test]
    fn domain_validation_and_projection() {
        let d = Domain::paper(0.1, 0.9, 0.01, 0.1).unwrap();
        assert!((d.eps1 - 0.01 / 0.9).abs() < 1e-15);
        assert!(Domain::new(0.5, 0.4, 0.1, 0.1).is_err());
        assert!(Domain::new(0.1, 0.9, 0.6, 0.5).is_err());
        let p = d.project(&[2.0, -1.0]);
        assert_eq!(p[0], 0.99);
        assert!((p[1] - 0.01 * 0.99 / 1.0).abs() < 1e-15);
    }
}
