//! Step 1 of the §5.3 algorithm: constants β, γ with `‖e^{−Aτ}‖₂ ≤ γ e^{βτ}` for τ ≥ 0 ([34, Lemma 3]).
//!
//! If `Π ≻ 0` satisfies `(A + βI)ᵀΠ + Π(A + βI) ≻ 0`, then `z(τ) = e^{−Aτ}z₀` obeys
//! `d/dτ (zᵀΠz) = −zᵀ(AᵀΠ + ΠA)z < 2β zᵀΠz`, hence `‖e^{−Aτ}‖₂ ≤ γ e^{βτ}` with
//! `γ = √(λ_M(Π)/λ_m(Π))`. β must exceed the spectral abscissa of −A, `α = −min Re λ(A)`.
//!
//! The grid spacing (49) is proportional to `1/(γ e^{βT_M})`, so the choice matters: `Π = I` gives
//! `γ = 1` but a huge β for a non-normal A (for the §6 example β = 193.9, `γ e^{βT_M} ≈ 3.8·10⁷`, about
//! 10¹³ grid points). Instead, for each β the small SDP
//!
//! ```text
//! minimise κ   s.t.   I ⪯ Π ⪯ κI,   (A + βI)ᵀΠ + Π(A + βI) ⪰ εI
//! ```
//!
//! gives the best γ(β) = √κ, and a 1-D search over β minimises `γ(β) e^{βT_M}`: a geometric grid of
//! offsets `β − α`, refined by golden-section search (`sporadic_linalg::golden_section`) on
//! `ln γ(β) + βT_M` around the best grid point.
//! The returned γ is recomputed from the eigenvalues of the returned Π, and the Lyapunov inequality is
//! checked at that Π, so the bound is certified independently of the solver's accuracy.

use faer::{Mat, Side};
use sporadic_linalg::{golden_section, min_eigenvalue};
use sporadic_sdp::Status;
use sporadic_sdp::lmi::{Compiled, Model, Param, SolveOptions, Var};

use crate::error::{Error, check_at_least, check_positive};
use crate::validation::{ExponentialBound, spectral_norm};
use sporadic_linalg::InputError;

/// Options of the β search. Defaults: ε = 10⁻⁶, 41 grid points over offsets `[10⁻⁵, 30]·s`,
/// 30 golden-section refinements, the crate's [`crate::synthesis::default_solve_options`].
#[derive(Debug, Clone)]
pub struct BoundOptions {
    /// `ε` in `(A+βI)ᵀΠ + Π(A+βI) ⪰ εI` (absolute; Π ⪰ I fixes the scale).
    pub epsilon: f64,
    /// Number of points of the geometric grid of offsets `β − α`.
    pub grid_points: usize,
    /// Smallest and largest offset `β − α`, relative to `s = max(|α|, 1/T, ‖A‖₂/100)`.
    pub offset_range: (f64, f64),
    /// Golden-section iterations after the grid (on `ln(β − α)`).
    pub refinements: usize,
    /// Options of the small SDPs.
    pub solve: SolveOptions,
}

impl BoundOptions {
    /// Checks every field; the error names the offending one.
    ///
    /// # Errors
    /// [`InputError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<(), InputError> {
        check_positive("bound.epsilon", self.epsilon)?;
        check_at_least("bound.grid_points", self.grid_points, 3)?;
        let (lo, hi) = self.offset_range;
        check_positive("bound.offset_range (lower)", lo)?;
        check_positive("bound.offset_range (upper)", hi)?;
        if hi <= lo {
            return Err(InputError::parameter(
                "bound.offset_range (upper)",
                hi,
                format!("must exceed the lower end {}", crate::error::sig4(lo)),
            ));
        }
        Ok(())
    }
}

impl Default for BoundOptions {
    fn default() -> Self {
        Self {
            epsilon: 1e-6,
            grid_points: 41,
            offset_range: (1e-5, 30.0),
            refinements: 30,
            solve: crate::synthesis::default_solve_options(),
        }
    }
}

/// The exponential bound with its certificate.
#[derive(Debug, Clone)]
pub struct CertifiedBound {
    /// β and γ.
    pub bound: ExponentialBound,
    /// The Lyapunov matrix Π.
    pub pi: Mat<f64>,
    /// `λ_min((A+βI)ᵀΠ + Π(A+βI))` at the returned Π (> 0: the bound is certified).
    pub lyapunov_margin: f64,
    /// The horizon `T` for which `γ e^{βT}` was minimised.
    pub horizon: f64,
    /// Number of SDPs solved during the search.
    pub sdp_solves: usize,
}

struct Problem {
    compiled: Compiled,
    a_beta: Param,
    pi: Var,
    n: usize,
    a: Mat<f64>,
    solves: usize,
}

impl Problem {
    fn new(a: &Mat<f64>, settings: &BoundOptions) -> Result<Self, Error> {
        let n = a.nrows();
        let mut m = Model::new();
        let pi = m.symmetric("Π", n);
        let kappa = m.scalar("κ");
        let a_beta = m.param("A+βI", a.as_ref())?;
        m.constrain(pi.ge(1.0).named("Π ⪰ I"))?;
        m.constrain(pi.le(&kappa).named("Π ⪯ κI"))?;
        let lyap = a_beta.t() * &pi + &pi * &a_beta;
        m.constrain(lyap.ge(settings.epsilon).named("(A+βI)ᵀΠ + Π(A+βI) ⪰ εI"))?;
        m.minimize(&kappa)?;
        let compiled = m.compile(&settings.solve)?;
        Ok(Self {
            compiled,
            a_beta,
            pi,
            n,
            a: a.clone(),
            solves: 0,
        })
    }

    /// `Some((γ, Π, margin))` with γ from the eigenvalues of the returned Π, or `None` if infeasible or
    /// the certificate fails at the returned point.
    fn gamma(&mut self, beta: f64) -> Result<Option<(f64, Mat<f64>, f64)>, Error> {
        let n = self.n;
        let ab = Mat::from_fn(n, n, |i, j| {
            self.a[(i, j)] + if i == j { beta } else { 0.0 }
        });
        self.compiled.set_param(&self.a_beta, ab.as_ref())?;
        self.solves += 1;
        let sol = self.compiled.solve()?;
        if !sol.is_feasible() {
            if sol.sdp.status == Status::Interrupted {
                return Err(Error::Interrupted {
                    during: "the exponential bound of Step 1",
                });
            }
            return Ok(None);
        }
        let pi = sol.value(&self.pi)?;
        let ev = pi
            .self_adjoint_eigenvalues(Side::Lower)
            .map_err(|_| Error::numerical("eigenvalues of Π did not converge"))?;
        if ev[0] <= 0.0 {
            return Ok(None);
        }
        let lyap = ab.transpose() * &pi + &pi * &ab;
        let margin = min_eigenvalue(lyap.as_ref())?;
        if margin <= 0.0 {
            return Ok(None);
        }
        Ok(Some(((ev[n - 1] / ev[0]).sqrt(), pi, margin)))
    }
}

/// Finds β, γ minimising `γ e^{β·horizon}` (use `horizon = T_M`), as described in the module docs.
///
/// # Errors
/// Non-finite/empty `A`, a non-positive horizon, no β of the search admitting a certificate, or
/// [`Error::Interrupted`] when the time budget runs out (an interrupted solve is no evidence of
/// infeasibility).
pub fn exponential_bound(
    a: &Mat<f64>,
    horizon: f64,
    settings: &BoundOptions,
) -> Result<CertifiedBound, Error> {
    let n = a.nrows();
    if n == 0 || a.ncols() != n {
        return Err(Error::invalid("A must be square and non-empty"));
    }
    if !(horizon > 0.0 && horizon.is_finite()) {
        return Err(Error::invalid(format!(
            "horizon must be positive (got {})",
            crate::error::sig4(horizon)
        )));
    }
    settings.validate()?;
    let eig = a
        .eigenvalues()
        .map_err(|_| Error::numerical("eigenvalues of A did not converge"))?;
    let alpha = -eig.iter().map(|z| z.re).fold(f64::INFINITY, f64::min);
    let norm = spectral_norm(a.as_ref())?;
    let scale = alpha.abs().max(1.0 / horizon).max(norm / 100.0);
    let mut prob = Problem::new(a, settings)?;
    let (lo, hi) = (settings.offset_range.0.ln(), settings.offset_range.1.ln());
    let k = settings.grid_points;
    // β = α + scale·e^u; the objective is ln(γ(β) e^{β·horizon}).
    let evaluate = |prob: &mut Problem, u: f64| -> Result<Option<Candidate>, Error> {
        let beta = alpha + scale * u.exp();
        Ok(prob.gamma(beta)?.map(|(gamma, pi, margin)| Candidate {
            objective: gamma.ln() + beta * horizon,
            beta,
            gamma,
            pi,
            margin,
            u,
        }))
    };
    let mut best: Option<Candidate> = None;
    for i in 0..k {
        let u = lo + (hi - lo) * i as f64 / (k - 1) as f64;
        Candidate::keep_better(&mut best, evaluate(&mut prob, u)?);
    }
    let Some(u_best) = best.as_ref().map(|b| b.u) else {
        return Err(Error::Infeasible {
            what: "no β on the search grid admits the Lyapunov certificate of Step 1".into(),
        });
    };
    // Golden-section refinement on the bracket of neighbouring grid points; an infeasible β counts as
    // +∞, and every evaluated candidate competes for the best.
    let step = (hi - lo) / (k - 1) as f64;
    golden_section(u_best - step, u_best + step, settings.refinements, |u| {
        let candidate = evaluate(&mut prob, u)?;
        let objective = candidate.as_ref().map_or(f64::INFINITY, |c| c.objective);
        Candidate::keep_better(&mut best, candidate);
        Ok::<_, Error>(objective)
    })?;
    let b = best.expect("checked above");
    Ok(CertifiedBound {
        bound: ExponentialBound {
            beta: b.beta,
            gamma: b.gamma,
        },
        pi: b.pi,
        lyapunov_margin: b.margin,
        horizon,
        sdp_solves: prob.solves,
    })
}

/// One evaluated β of the search.
struct Candidate {
    objective: f64,
    beta: f64,
    gamma: f64,
    pi: Mat<f64>,
    margin: f64,
    u: f64,
}

impl Candidate {
    fn keep_better(best: &mut Option<Candidate>, c: Option<Candidate>) {
        if let Some(c) = c
            && best.as_ref().is_none_or(|b| c.objective < b.objective)
        {
            *best = Some(c);
        }
    }
}

/// `‖e^{−Aτ}‖₂` maximised over a uniform grid of `[0, horizon]` (`points` points): the quantity the
/// bound of Step 1 must dominate (an independent check).
///
/// # Errors
/// A failing exponential or SVD.
pub fn sampled_growth(a: &Mat<f64>, horizon: f64, points: usize) -> Result<f64, Error> {
    let neg = Mat::from_fn(a.nrows(), a.ncols(), |i, j| -a[(i, j)]);
    let h = horizon / (points.max(2) - 1) as f64;
    let mut worst = 0.0f64;
    for e in sporadic_linalg::expm_stepper(neg.as_ref(), 0.0, h, points.max(2) - 1)? {
        worst = worst.max(spectral_norm(e.as_ref())?);
    }
    Ok(worst)
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    /// For a normal A the best certificate is Π = I with β just above the spectral abscissa of −A:
    /// `γ e^{βT} → e^{αT}` (here `‖e^{−Aτ}‖ = e^{2τ}` exactly).
    #[test]
    fn normal_matrix_reaches_the_exact_growth() {
        let a = mat![[-1.0, 0.0], [0.0, -2.0]];
        let b = exponential_bound(&a, 0.5, &BoundOptions::default()).unwrap();
        let growth = b.bound.at(0.5);
        assert!(
            (growth / 1f64.exp() - 1.0).abs() < 1e-3,
            "γe^(βT) = {growth}"
        );
        assert!(b.bound.beta > 2.0 && b.lyapunov_margin > 0.0);
        assert!(growth >= sampled_growth(&a, 0.5, 501).unwrap() * (1.0 - 1e-12));
    }

    /// A non-normal A: the certified bound dominates the sampled growth of `‖e^{−Aτ}‖` and beats Π = I
    /// (which needs β ≥ λ_max(−(A + Aᵀ)/2)).
    #[test]
    fn non_normal_bound_is_valid_and_better_than_identity() {
        let a = mat![[-1.0, 10.0], [0.0, -2.0]];
        let t = 0.3;
        let b = exponential_bound(&a, t, &BoundOptions::default()).unwrap();
        assert!(b.lyapunov_margin > 0.0);
        let sampled = sampled_growth(&a, t, 3001).unwrap();
        assert!(b.bound.at(t) >= sampled, "{} < {sampled}", b.bound.at(t));
        let sym = Mat::from_fn(2, 2, |i, j| -0.5 * (a[(i, j)] + a[(j, i)]));
        let beta_identity = sym.self_adjoint_eigenvalues(Side::Lower).unwrap()[1];
        assert!(b.bound.at(t) < (beta_identity * t).exp());
    }

    #[test]
    fn bad_arguments() {
        let a = mat![[-1.0, 0.0], [0.0, -2.0]];
        assert!(exponential_bound(&a, 0.0, &BoundOptions::default()).is_err());
        let s = BoundOptions {
            grid_points: 2,
            ..BoundOptions::default()
        };
        assert!(exponential_bound(&a, 1.0, &s).is_err());
        assert!(exponential_bound(&Mat::zeros(2, 3), 1.0, &BoundOptions::default()).is_err());
    }
}
