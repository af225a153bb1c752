//! The observer of Andrieu, Nadri, Serres & Vivalda (2014) designed for a plant file's plant: the
//! normal form of [`crate::normal_form`], the constants (D1)–(D4) of Theorem 2 ([`Design`]), and
//! the inter-sample range that the sampling rule (7) guarantees.
//!
//! **Time scaling.** The design runs in the time `τ = ωt` and the coordinates
//! `z̃ = T x`, `T = D_ω⁻¹O` ([`NormalForm::scaled_transformation`]), where the plant is in the form
//! (1) with the constant `c̃(ω)` of Assumption 1 ([`NormalForm::scaled_lipschitz`]). In the plant's
//! time the rule (7) reads: next sample when `(t − t_k)·ω·L(t) = α`. Since `L ≥ 1` (Section 2.2),
//! every interval is at most `α/ω`; by Lemma 1 with the constant `c_m = c̃(ω)`,
//! `L ≤ L̄ = κ(α)·max(L(0), ℓ1, ℓ1φ(1))` along every run, so every interval is at least `α/(ωL̄)`
//! ([`crate::lemma1`]). Both ends are in seconds, and they scale like `1/k` when the vector
//! field is multiplied by `k` (then `ω → kω` and `c̃` is unchanged).
//!
//! **Choice of `ω`, `α`, `W`.** Every `ω > 0`, every `α ∈ (0, α_m)` and every weight `W` of
//! (D1) give a valid observer; the design takes the one that maximises the guaranteed shortest
//! interval `α/(ωL̄)`: `W = diag(1, r, …, r^{n−1})` for `r ∈ {1, 0.1, 0.01, 0.001}`,
//! `α ∈ {0.1, 0.2, …, 0.9}·α_m`, `a2 = a2,min(α)`, `a3 = 2n`, `L(0) = 1`, and `ω = sω₀` with `s`
//! on a grid of 10 points per decade over `[1, 10¹²]` refined by golden section
//! ([`sporadic_linalg::golden_section`]). For `s ≥ 1`, `c̃ ≤ 1/s`, and for `s → ∞` the bound tends
//! to `0` like `1/s`; the maximiser is near `s` where `a2 c̃/a1` (roughly `ℓ1 − 1`) is of order
//! one, i.e. `s ≈ a2/a1`, which reaches `10⁹` for `n = 5` (`a1` is small there).
//!
//! **Chains of integrators.** When `f ≡ 0` (the plant is a chain of integrators, `c̃ = 0` for every
//! `ω`), `L ≡ 1` and the rule samples periodically with the period `α/ω`, which any `ω > 0` makes
//! what one wants: the plant has no time scale. The design then takes the period from the caller
//! (`period`, the plant file's longest interval) with `α = α_m/2`.

use faer::Mat;
use sporadic_linalg::{golden_section, max_eigenvalue, sym_part};
use sporadic_model::Plant;

use crate::design::Design;
use crate::error::Error;
use crate::lemma1::{Lemma1Bound, lemma1_bound};
use crate::normal_form::NormalForm;
use crate::observer::Tuning;

/// Weight ratios `r` of `W = diag(1, r, …, r^{n−1})` tried for (D1).
const WEIGHT_RATIOS: [f64; 4] = [1.0, 0.1, 0.01, 0.001];
/// `α/α_m` tried.
const ALPHA_FRACTIONS: [f64; 9] = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9];
/// Grid of `log10 s`: `[0, 12]` with 10 points per decade.
const SCALE_DECADES: f64 = 12.0;
const SCALE_POINTS_PER_DECADE: f64 = 10.0;
/// Golden-section refinement of `log10 s` around the best grid point (bracket `±0.1`; 40
/// reductions reach the flatness of the objective).
const SCALE_REFINE_ITERATIONS: usize = 40;

/// Every output row tried, with its equilibrated condition number or why it was rejected.
#[derive(Debug, Clone)]
pub struct OutputCandidate {
    /// Output row (0-based).
    pub output: usize,
    /// The equilibrated condition number of its observability matrix, or the error message.
    pub outcome: Result<f64, String>,
}

/// The observer designed for a plant file's plant (module docs).
#[derive(Debug, Clone)]
pub struct PlantDesign {
    /// The normal form through the chosen output.
    pub normal_form: NormalForm,
    /// Every output row tried.
    pub candidates: Vec<OutputCandidate>,
    /// (D1)–(D3) for the chosen weight.
    pub design: Design,
    /// The weight ratio `r` of `W` used.
    pub weight_ratio: f64,
    /// `(K, α, a1, a2, a3)` in the scaled time `τ = ωt`.
    pub tuning: Tuning,
    /// The frequency `ω` of the time scaling (rad per unit of the plant's time).
    pub omega: f64,
    /// `c̃(ω)`, the constant of Assumption 1 in the scaled coordinates.
    pub c_scaled: f64,
    /// Lemma 1 with `c_m = c̃(ω)` and `L(0) = 1`.
    pub lemma1: Lemma1Bound,
    /// Guaranteed shortest interval `α/(ω L̄)` (seconds).
    pub shortest: f64,
    /// Guaranteed longest interval `α/ω` (seconds).
    pub longest: f64,
    /// Whether `f ≡ 0` (chain of integrators): the period was taken from the caller.
    pub chain: bool,
}

impl PlantDesign {
    /// Designs the observer for `plant` (module docs); `period` (seconds) is used only for a chain
    /// of integrators.
    ///
    /// Errors: those of [`NormalForm::new`] for the best output when no output gives a normal form
    /// ([`Error::IllConditioned`] before [`Error::NotTriangular`] before [`Error::NotObservable`]);
    /// [`Error::Input`] for a non-positive `period`; the errors of [`Design::new`] when no
    /// weight gives the constants of (D1)–(D3).
    pub fn new(plant: &Plant, period: f64) -> Result<Self, Error> {
        if !(period.is_finite() && period > 0.0) {
            return Err(sporadic_linalg::InputError::parameter(
                "period",
                period,
                "need a finite positive period",
            )
            .into());
        }
        let p = plant.c().map_or(0, |c| c.nrows());
        let mut candidates = Vec::with_capacity(p);
        let mut best: Option<NormalForm> = None;
        let mut worst_error: Option<Error> = None;
        for i in 0..p.max(1) {
            match NormalForm::new(plant, i) {
                Ok(nf) => {
                    candidates.push(OutputCandidate {
                        output: i,
                        outcome: Ok(nf.condition()),
                    });
                    if best.as_ref().is_none_or(|b| nf.condition() < b.condition()) {
                        best = Some(nf);
                    }
                }
                Err(e) => {
                    candidates.push(OutputCandidate {
                        output: i,
                        outcome: Err(e.to_string()),
                    });
                    if worst_error.as_ref().is_none_or(|w| rank(&e) > rank(w)) {
                        worst_error = Some(e);
                    }
                }
            }
        }
        let Some(normal_form) = best else {
            return Err(worst_error.expect("at least one output was tried"));
        };
        let n = normal_form.order();
        let omega0 = normal_form.frequency();
        let chain = omega0 == 0.0;
        let mut best: Option<Candidate> = None;
        let mut last_error = None;
        for &r in &WEIGHT_RATIOS {
            let design = match Design::binomial(n, r) {
                Ok(d) => d,
                Err(e) => {
                    last_error = Some(e);
                    continue;
                }
            };
            if chain {
                let tuning = design.theorem_tuning(0.5 * design.alpha_m())?;
                let omega = tuning.alpha() / period;
                best = Some(Candidate {
                    value: period,
                    design,
                    weight_ratio: r,
                    tuning,
                    omega,
                });
                break;
            }
            for &f in &ALPHA_FRACTIONS {
                let tuning = design.theorem_tuning(f * design.alpha_m())?;
                let (omega, value) = best_frequency(&normal_form, &tuning, omega0)?;
                if best.as_ref().is_none_or(|b| value > b.value) {
                    best = Some(Candidate {
                        value,
                        design: design.clone(),
                        weight_ratio: r,
                        tuning,
                        omega,
                    });
                }
            }
        }
        let Some(best) = best else {
            return Err(last_error.expect("a weight was tried"));
        };
        let c_scaled = normal_form.scaled_lipschitz(best.omega);
        let lemma1 = lemma1_bound(&best.tuning, c_scaled, 1.0).map_err(|e| match e {
            Error::NoConvergence { what } => Error::NoConvergence {
                what: format!(
                    "{what}, for every weight and alpha tried: Lemma 1 gives no bound on L in \
                     double precision for n = {n} (a1·alpha = {:.3e})",
                    best.tuning.a1() * best.tuning.alpha()
                ),
            },
            e => e,
        })?;
        let shortest = lemma1.delta_lower / best.omega;
        let longest = best.tuning.alpha() / best.omega;
        Ok(Self {
            normal_form,
            candidates,
            design: best.design,
            weight_ratio: best.weight_ratio,
            tuning: best.tuning,
            omega: best.omega,
            c_scaled,
            lemma1,
            shortest,
            longest,
            chain,
        })
    }

    /// The margin of the checkable form of Lemma 4 (17) at the design `α`:
    /// `1 − α/(4p2) − λmax(P⁻¹Q(α)'ψ0Pψ0Q(α))` (positive: (17) holds strictly).
    pub fn lemma4_margin(&self) -> Result<f64, Error> {
        let a = self.tuning.alpha();
        Ok(self.design.lemma4_rhs(a) - self.design.lemma4_lambda(a)?)
    }

    /// `λmax((A+KC)'P + P(A+KC))`, recomputed from `P` and `K`; (9) requires `≤ −1`.
    pub fn condition9(&self) -> Result<f64, Error> {
        let n = self.normal_form.order();
        let k = self.design.gain();
        let acl = Mat::from_fn(n, n, |i, j| {
            f64::from(j == i + 1) + if j == 0 { k[i] } else { 0.0 }
        });
        let p = self.design.p();
        let m = acl.transpose() * p + p * &acl;
        Ok(max_eigenvalue(sym_part(m.as_ref())?.as_ref())?)
    }

    /// The correction gain in the plant's coordinates as a function of the elapsed interval `δ`:
    /// `G(δ) = α T⁻¹ diag(1, L⁻, …, (L⁻)^{n−1}) K` with `L⁻ = α/(ωδ)` (rule (7)), so that the jump
    /// (5) reads `x̂ ← x̂ + G(δ)(c x̂ − y)` (`c` the output row used, `T = D_ω⁻¹O`).
    pub fn plant_gain(&self, delta: f64) -> Result<Mat<f64>, Error> {
        use faer::linalg::solvers::Solve;
        let n = self.normal_form.order();
        let alpha = self.tuning.alpha();
        let l = alpha / (self.omega * delta);
        let k = self.tuning.gain();
        let rhs = Mat::from_fn(n, 1, |i, _| alpha * l.powi(i as i32) * k[i]);
        let t = self.normal_form.scaled_transformation(self.omega);
        let g = t.partial_piv_lu().solve(&rhs);
        sporadic_linalg::input::check_finite(g.as_ref(), "correction gain G(δ)")?;
        Ok(g)
    }
}

/// The tuning and frequency of one candidate, with its guaranteed shortest interval.
struct Candidate {
    value: f64,
    design: Design,
    weight_ratio: f64,
    tuning: Tuning,
    omega: f64,
}

/// Order of preference of the errors reported when no output gives a normal form: the one that
/// got furthest.
fn rank(e: &Error) -> u8 {
    match e {
        Error::IllConditioned { .. } => 3,
        Error::NotTriangular { .. } => 2,
        Error::NotObservable { .. } => 1,
        _ => 0,
    }
}

/// The guaranteed shortest interval `α/(ω L̄(c̃(ω)))` (seconds) at `ω = ω₀·10^{x}`, 0 where
/// Lemma 1 gives no bound.
fn shortest_at(nf: &NormalForm, tuning: &Tuning, omega0: f64, x: f64) -> Result<f64, Error> {
    let omega = omega0 * 10f64.powf(x);
    match lemma1_bound(tuning, nf.scaled_lipschitz(omega), 1.0) {
        Ok(b) => {
            let v = b.delta_lower / omega;
            Ok(if v.is_finite() { v } else { 0.0 })
        }
        // The root ℓ1 cannot be bracketed in double precision (e.g. `a1α` below `ε`, so that
        // `1 − a1α` rounds to 1): no bound at this point.
        Err(Error::NoConvergence { .. }) => Ok(0.0),
        Err(e) => Err(e),
    }
}

/// `(ω, shortest)` maximising the guaranteed shortest interval over `ω = sω₀`, `s ∈ [1, 10¹²]`.
fn best_frequency(nf: &NormalForm, tuning: &Tuning, omega0: f64) -> Result<(f64, f64), Error> {
    let points = (SCALE_DECADES * SCALE_POINTS_PER_DECADE) as usize;
    let step = 1.0 / SCALE_POINTS_PER_DECADE;
    let (mut bx, mut bv) = (0.0, shortest_at(nf, tuning, omega0, 0.0)?);
    for i in 1..=points {
        let x = i as f64 * step;
        let v = shortest_at(nf, tuning, omega0, x)?;
        if v > bv {
            (bx, bv) = (x, v);
        }
    }
    let m = golden_section(
        (bx - step).max(0.0),
        (bx + step).min(SCALE_DECADES),
        SCALE_REFINE_ITERATIONS,
        |x| Ok::<f64, Error>(-shortest_at(nf, tuning, omega0, x)?),
    )?;
    if -m.value > bv {
        (bx, bv) = (m.at, -m.value);
    }
    Ok((omega0 * 10f64.powf(bx), bv))
}
