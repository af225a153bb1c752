//! Output-injection gains `K_σ(τ)` of the observer (11b), from the Lyapunov matrices `P_σ`.
//!
//! With `E(τ) = e^{−Aτ}` and `Φ_σ(τ) = E(τ)ᵀ P_σ E(τ)` (the matrix of the Lyapunov function (30)),
//! Theorem 4 selects
//!
//! ```text
//! K_σ(τ) = ( C_σᵀ − C_σ^⊥ W_σ(τ)⁻¹ (C_σ Φ_σ(τ) C_σ^⊥)ᵀ ) (C_σ C_σᵀ)⁻¹,   W_σ = C_σ^⊥ᵀ Φ_σ C_σ^⊥     (45)
//! ```
//!
//! (24) is (45) at `τ = T_σ`. An equivalent closed form is `K_σ = Φ_σ⁻¹C_σᵀ(C_σΦ_σ⁻¹C_σᵀ)⁻¹`
//! with `Φ_σ⁻¹ = e^{Aτ} P_σ⁻¹ e^{Aᵀτ}`, which shows that `C_σK_σ = I`, that `I − K_σC_σ` is the
//! `Φ_σ`-orthogonal projector onto `ker C_σ`, and that the gain does not depend on the choice of
//! `C_σ^⊥`. Both forms are implemented; they are cross-checked in the tests.
//!
//! The gain depends on `P_σ` only (the `P_Γ(σ)` in the proof of Theorem 4 is a typo).

use faer::linalg::solvers::Solve;
use faer::linalg::triangular_solve::solve_upper_triangular_in_place;
use faer::{Mat, MatRef, Par, Side};
use sporadic_linalg::InputError;
use sporadic_linalg::{expm_scaled, sym_part};

use crate::error::Error;
use crate::plant::RoundRobinPlant;

/// `Eᵀ P E`, made exactly symmetric with [`sym_part`].
///
/// # Errors
/// Non-finite entries.
pub(crate) fn congruence(e: MatRef<'_, f64>, p: MatRef<'_, f64>) -> Result<Mat<f64>, Error> {
    Ok(sym_part((e.transpose() * (p * e)).as_ref())?)
}

/// Checks that `p` is a finite, symmetric `n × n` matrix.
pub(crate) fn check_sym(p: MatRef<'_, f64>, n: usize, what: &str) -> Result<(), Error> {
    if p.nrows() != n || p.ncols() != n {
        return Err(
            InputError::mismatch(format!("order of {what}"), n, p.nrows().max(p.ncols())).into(),
        );
    }
    let mut scale = 0.0f64;
    for j in 0..n {
        for i in 0..n {
            let v = p[(i, j)];
            if !v.is_finite() {
                return Err(InputError::non_finite(what).into());
            }
            scale = scale.max(v.abs());
        }
    }
    for j in 0..n {
        for i in 0..j {
            if (p[(i, j)] - p[(j, i)]).abs() > 1e-10 * scale.max(1.0) {
                return Err(Error::invalid(format!(
                    "{what} is not symmetric at ({i}, {j})"
                )));
            }
        }
    }
    Ok(())
}

fn check_tau(tau: f64) -> Result<(), Error> {
    if tau.is_finite() {
        Ok(())
    } else {
        Err(InputError::non_finite("τ").into())
    }
}

/// `Φ_σ(τ) = e^{−Aᵀτ} P e^{−Aτ}` for a given `P` (`n × n`, symmetric).
///
/// # Errors
/// Shape or finiteness errors, or a failing matrix exponential.
pub fn phi(a: MatRef<'_, f64>, p: MatRef<'_, f64>, tau: f64) -> Result<Mat<f64>, Error> {
    check_sym(p, a.nrows(), "P_σ")?;
    check_tau(tau)?;
    let e = expm_scaled(a, -tau)?;
    congruence(e.as_ref(), p)
}

/// Solves `X M = B` for symmetric positive definite `M` (Cholesky), i.e. `X = B M⁻¹`.
fn right_solve_spd(b: MatRef<'_, f64>, m: MatRef<'_, f64>, what: &str) -> Result<Mat<f64>, Error> {
    let llt = m
        .llt(Side::Lower)
        .map_err(|_| Error::invalid(format!("{what} is not positive definite (is P_σ ≻ 0?)")))?;
    let xt = llt.solve(b.transpose());
    Ok(xt.transpose().to_owned())
}

/// `K_σ(τ)` by the paper's formula (45) for sensor `sigma` (0-based) and Lyapunov matrix `p_sigma`.
///
/// `W_σ⁻¹(C_σΦ_σC_σ^⊥)ᵀ` is evaluated in graded form: with `G = E(τ)C_σ^⊥ = UT` (thin QR),
/// `W_σ = Tᵀ(UᵀP_σU)T` and `(C_σΦ_σC_σ^⊥)ᵀ = TᵀUᵀP_σE(τ)C_σᵀ`, so
/// `W_σ⁻¹(C_σΦ_σC_σ^⊥)ᵀ = T⁻¹(UᵀP_σU)⁻¹UᵀP_σE(τ)C_σᵀ`. `UᵀP_σU` is as well conditioned as
/// `P_σ`, whereas `W_σ` itself has the condition number of `P_σ` times `κ(G)²`: on long
/// windows (`‖e^{−Aτ}‖ ≈ 10⁸` on a fuzzed plant of order 6 at `τ = 2.9`) forming and
/// factorising it failed although `P_σ ≻ 0`.
///
/// # Errors
/// Bad shapes, non-finite input, `P_σ` not positive definite (then `W_σ` is not invertible).
pub fn gain(
    plant: &RoundRobinPlant,
    sigma: usize,
    p_sigma: MatRef<'_, f64>,
    tau: f64,
) -> Result<Mat<f64>, Error> {
    let s = plant
        .sensors()
        .get(sigma)
        .ok_or_else(|| Error::invalid(format!("sensor index {sigma} out of range")))?;
    check_sym(p_sigma, plant.n(), "P_σ")?;
    check_tau(tau)?;
    let e = expm_scaled(plant.a(), -tau)?;
    let (c, cp) = (s.c(), s.c_perp());
    let r = cp.ncols();
    let winv_z = if r == 0 {
        Mat::zeros(0, c.nrows())
    } else {
        let g = &e * cp;
        let qr = g.qr();
        let u = qr.compute_thin_Q();
        let t = qr.thin_R();
        let pu = p_sigma * &u;
        let m = u.transpose() * &pu;
        let m = Mat::from_fn(r, r, |i, j| 0.5 * (m[(i, j)] + m[(j, i)]));
        let llt = m.llt(Side::Lower).map_err(|_| {
            Error::invalid("W_σ(τ) = C^⊥ᵀΦC^⊥ is not positive definite (is P_σ ≻ 0?)")
        })?;
        let mut x = llt.solve(pu.transpose() * (&e * c.transpose()));
        solve_upper_triangular_in_place(t, x.as_mut(), Par::Seq);
        x
    };
    if !winv_z.norm_max().is_finite() {
        return Err(Error::numerical(
            "W_σ(τ)⁻¹(C_σΦ_σC_σ^⊥)ᵀ of (45) is not finite in double precision",
        ));
    }
    let x = c.transpose() - cp * &winv_z;
    let cct = c * c.transpose();
    right_solve_spd(x.as_ref(), cct.as_ref(), "C_σ C_σᵀ")
}

/// `K_σ(τ) = Φ_σ⁻¹C_σᵀ(C_σΦ_σ⁻¹C_σᵀ)⁻¹` with `Φ_σ⁻¹ = e^{Aτ}P_σ⁻¹e^{Aᵀτ}` : the closed
/// form of (45), independent of `C_σ^⊥`.
///
/// # Errors
/// Bad shapes, non-finite input, `P_σ` not positive definite.
pub fn gain_closed_form(
    plant: &RoundRobinPlant,
    sigma: usize,
    p_sigma: MatRef<'_, f64>,
    tau: f64,
) -> Result<Mat<f64>, Error> {
    let s = plant
        .sensors()
        .get(sigma)
        .ok_or_else(|| Error::invalid(format!("sensor index {sigma} out of range")))?;
    check_sym(p_sigma, plant.n(), "P_σ")?;
    check_tau(tau)?;
    let n = plant.n();
    let llt = p_sigma
        .llt(Side::Lower)
        .map_err(|_| Error::invalid("P_σ is not positive definite"))?;
    let p_inv = llt.solve(Mat::<f64>::identity(n, n));
    let f = expm_scaled(plant.a(), tau)?; // e^{Aτ}
    let phi_inv = congruence(f.transpose(), p_inv.as_ref())?; // e^{Aτ} P⁻¹ e^{Aᵀτ}
    let c = s.c();
    let phi_inv_ct = &phi_inv * c.transpose();
    let s_mat = c * &phi_inv_ct;
    right_solve_spd(phi_inv_ct.as_ref(), s_mat.as_ref(), "C_σ Φ_σ⁻¹ C_σᵀ")
}

/// The jump matrix `I − K C` of the error dynamics (17)/(28).
pub fn jump_matrix(k: MatRef<'_, f64>, c: MatRef<'_, f64>) -> Mat<f64> {
    let kc = k * c;
    Mat::from_fn(
        kc.nrows(),
        kc.ncols(),
        |i, j| if i == j { 1.0 } else { 0.0 } - kc[(i, j)],
    )
}

/// The observer's gain schedule: the plant plus one Lyapunov matrix `P_σ ≻ 0` per sensor, from which
/// `K_σ(τ)` (45) is evaluated online (one `n × n` exponential and small solves per sample).
#[derive(Debug, Clone)]
pub struct GainSchedule {
    plant: RoundRobinPlant,
    p: Vec<Mat<f64>>,
}

impl GainSchedule {
    /// Checks that there is one symmetric positive definite `P_σ` per sensor.
    ///
    /// # Errors
    /// Wrong count or shape, non-finite, non-symmetric or not positive definite `P_σ`.
    pub fn new(plant: RoundRobinPlant, p: Vec<Mat<f64>>) -> Result<Self, Error> {
        if p.len() != plant.num_sensors() {
            return Err(InputError::mismatch("number of P_σ", plant.num_sensors(), p.len()).into());
        }
        for (k, pk) in p.iter().enumerate() {
            check_sym(pk.as_ref(), plant.n(), &format!("P_{}", k + 1))?;
            if pk.llt(Side::Lower).is_err() {
                return Err(Error::invalid(format!(
                    "P_{} is not positive definite",
                    k + 1
                )));
            }
        }
        Ok(Self { plant, p })
    }
    /// The plant.
    pub fn plant(&self) -> &RoundRobinPlant {
        &self.plant
    }
    /// The Lyapunov matrices `P_1, …, P_N`.
    pub fn p(&self) -> &[Mat<f64>] {
        &self.p
    }
    /// `K_σ(τ)` by (45) (0-based `sigma`).
    ///
    /// # Errors
    /// Index out of range or a failing kernel.
    pub fn gain(&self, sigma: usize, tau: f64) -> Result<Mat<f64>, Error> {
        let p = self
            .p
            .get(sigma)
            .ok_or_else(|| Error::invalid(format!("sensor index {sigma} out of range")))?;
        gain(&self.plant, sigma, p.as_ref(), tau)
    }
    /// `Φ_σ(τ) = e^{−Aᵀτ} P_σ e^{−Aτ}`.
    ///
    /// # Errors
    /// Index out of range or a failing kernel.
    pub fn phi(&self, sigma: usize, tau: f64) -> Result<Mat<f64>, Error> {
        let p = self
            .p
            .get(sigma)
            .ok_or_else(|| Error::invalid(format!("sensor index {sigma} out of range")))?;
        phi(self.plant.a(), p.as_ref(), tau)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::test_util::{rr, win};
    use faer::mat;
    use proptest::prelude::*;

    fn random_mat(r: usize, c: usize, v: &[f64]) -> Mat<f64> {
        Mat::from_fn(r, c, |i, j| v[(i * c + j) % v.len()])
    }

    fn spd(n: usize, v: &[f64]) -> Mat<f64> {
        let g = random_mat(n, n, v);
        let mut p = &g * g.transpose();
        for i in 0..n {
            p[(i, i)] += 0.5;
        }
        p
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        /// (45) equals the closed form, C K = I, I − KC is idempotent, and K does not
        /// change when C^⊥ → C^⊥ R.
        #[test]
        fn gain_identities(
            n in 2usize..6,
            m_raw in 1usize..3,
            av in proptest::collection::vec(-2.0f64..2.0, 36),
            cv in proptest::collection::vec(-1.0f64..1.0, 12),
            pv in proptest::collection::vec(-1.0f64..1.0, 36),
            rv in proptest::collection::vec(-1.0f64..1.0, 25),
            tau in 0.0f64..0.8,
        ) {
            let m = m_raw.min(n - 1);
            let a = random_mat(n, n, &av);
            let c = Mat::from_fn(m, n, |i, j| cv[(i * n + j) % cv.len()] + if i == j { 2.0 } else { 0.0 });
            let plant = rr(a, vec![(c.clone(), win(0.1, 0.5))]).unwrap();
            let p = spd(n, &pv);
            let k = gain(&plant, 0, p.as_ref(), tau).unwrap();
            let k2 = gain_closed_form(&plant, 0, p.as_ref(), tau).unwrap();
            let scale = 1.0 + k.norm_max();
            prop_assert!((&k - &k2).norm_max() <= 1e-9 * scale, "(45) vs closed form: {:e}", (&k - &k2).norm_max());
            let ck = &c * &k;
            for i in 0..m { for j in 0..m {
                let e = if i == j { 1.0 } else { 0.0 };
                prop_assert!((ck[(i, j)] - e).abs() <= 1e-9 * scale);
            }}
            let j = jump_matrix(k.as_ref(), c.as_ref());
            let jj = &j * &j;
            prop_assert!((&jj - &j).norm_max() <= 1e-8 * scale * scale);
            // C^⊥ → C^⊥ R with R well conditioned (identity plus a bounded perturbation).
            let r = n - m;
            let rm = Mat::from_fn(r, r, |i, j| if i == j { 3.0 } else { 0.0 } + rv[(i * r + j) % rv.len()]);
            let cp2 = plant.sensor(0).unwrap().c_perp() * &rm;
            let plant2 = plant.clone().with_complement(0, cp2.as_ref()).unwrap();
            let k3 = gain(&plant2, 0, p.as_ref(), tau).unwrap();
            prop_assert!((&k - &k3).norm_max() <= 1e-9 * scale);
        }
    }

    /// with d = 0 the quadratic form x̃ᵀΦ_σ(τ)x̃ is constant along x̃(τ) = e^{Aτ}x̃(0).
    #[test]
    fn phi_is_invariant_along_the_flow() {
        let a = mat![[0.0, 1.0], [-4.0, -0.3]];
        let p = mat![[2.0, 0.3], [0.3, 1.0]];
        let x0 = [0.7, -1.1];
        let v0 =
            p[(0, 0)] * x0[0] * x0[0] + 2.0 * p[(0, 1)] * x0[0] * x0[1] + p[(1, 1)] * x0[1] * x0[1];
        for &t in &[0.1, 0.5, 2.0] {
            let e = expm_scaled(a.as_ref(), t).unwrap();
            let x = [
                e[(0, 0)] * x0[0] + e[(0, 1)] * x0[1],
                e[(1, 0)] * x0[0] + e[(1, 1)] * x0[1],
            ];
            let f = phi(a.as_ref(), p.as_ref(), t).unwrap();
            let v =
                f[(0, 0)] * x[0] * x[0] + 2.0 * f[(0, 1)] * x[0] * x[1] + f[(1, 1)] * x[1] * x[1];
            assert!((v - v0).abs() < 1e-12 * v0, "t = {t}: {v} vs {v0}");
        }
    }

    #[test]
    fn bad_p_is_rejected() {
        let a = mat![[0.0, 1.0], [-4.0, -0.3]];
        let plant = rr(a, vec![(mat![[1.0, 0.0]], win(0.1, 0.1))]).unwrap();
        assert!(gain(&plant, 0, mat![[1.0, 0.0], [0.0, -1.0]].as_ref(), 0.1).is_err());
        assert!(gain(&plant, 0, mat![[1.0, 2.0], [0.0, 1.0]].as_ref(), 0.1).is_err());
        assert!(gain(&plant, 1, mat![[1.0, 0.0], [0.0, 1.0]].as_ref(), 0.1).is_err());
        assert!(gain(&plant, 0, mat![[1.0, 0.0], [0.0, 1.0]].as_ref(), f64::NAN).is_err());
        assert!(GainSchedule::new(plant, vec![mat![[1.0, 0.0], [0.0, -1.0]]]).is_err());
    }
}
