//! The LMIs of Proposition 1 / Corollary 1 (Ferrante et al. 2016, eqs. (36) and (41)) over a vertex
//! set `X_1, …, X_ν` of a polytopic embedding of `e^{Av}` on `[T1, T2]`:
//!
//! ```text
//!          [ −He(F)        F − JM    X_i'P ]
//! Φ_i  =   [ (F − JM)'     −P        0     ]  ≺ 0,     i = 1..ν                          (41)
//!          [ P X_i          0        −P    ]
//! ```
//!
//! in the decision variables `P` (symmetric), `F` (full `n×n`) and `J` (`n×q`), with `L = F⁻¹J`
//! (Remark 8). For the **analysis of a given gain** `L`, `J` is replaced by `FL`, which turns (41) into
//! (36) at the vertices (linear in `P` and `F` only).
//!
//! The strict LMIs are solved by margin maximisation (`sporadic_sdp::lmi::Model::feasibility`:
//! maximise `t` with `−Φ_i ⪰ tI`, every variable normalised by `‖·‖₂ ≤ 1`). (41) is positively
//! homogeneous in `(P, F, J)`, so this normalisation loses no generality: (41) is strictly feasible
//! iff the optimal margin is positive.
//!
//! The same instance can instead be solved for the certificate with the smallest `tr P` under the
//! well-scaled non-strict normalisation `P ⪰ I`, `Φ_i ⪯ −I` (equivalent to the strict LMIs by
//! homogeneity, and better scaled than a margin-normalised point); the bound constants of
//! Theorems 1–2 are reported for that certificate.
//!
//! **Embeddings with a remainder** (`e^{Av} ∈ co{X_i} ⊕ {‖Δ‖ ≤ δ}`, e.g. the Taylor polytope).
//! `Φ` depends on `E(v)` only through the `(3,1)` block `P E`, so `Φ(X + Δ) = Φ(X) + He(E₃ P Δ E₁')`
//! with the block selectors `E₁ = [I; 0; 0]`, `E₃ = [0; 0; I]`. Young's inequality with a multiplier
//! `μ > 0` and a Schur complement give the sufficient LMI (not in the paper)
//!
//! ```text
//! [ Φ_i + μδ² E₁E₁'   E₃ P ]
//! [ P E₃'             −μ I ]  ≺ 0,
//! ```
//!
//! still homogeneous and linear in `(P, F, J, μ)`; it is used whenever `δ > 0`.
//!
//! **Reduced form** ([`LmiForm::Reduced`], not in the paper). At a *constant* vertex `X_i`, the Schur
//! complement of (41) with respect to its `(3,3)` block `−P ≺ 0` is the projection-lemma form (39):
//!
//! ```text
//! [ X_i'P X_i − He(F)   F − JM ]
//! [ (F − JM)'           −P     ]  ≺ 0,
//! ```
//!
//! which is still linear in `(P, F, J)` (`X_i` is data) and has exactly the same feasible set vertex by
//! vertex, with blocks of order `2n` instead of `3n` (cheaper interior-point iterations). The vertex
//! argument stays valid because `E ↦ E'PE` is matrix-convex for `P ≻ 0`:
//! `(Σμ_i X_i)'P(Σμ_i X_i) ⪯ Σμ_i X_i'PX_i`. Only the margin `t*` is measured on different matrices.
//! With a remainder, the same Schur complement of the robust form (with respect to its `(3,3)`
//! block `−P`) gives the equivalent robust reduced LMI, of order `3n` instead of `4n`:
//!
//! ```text
//! [ X_i'P X_i − He(F) + μδ²I   F − JM    X_i'P   ]
//! [ (F − JM)'                  −P        0       ]  ≺ 0.
//! [ P X_i                      0         P − μI  ]
//! ```

use sporadic_linalg::InputError;
use sporadic_model::SolverStats;

use faer::{Mat, MatRef};
use sporadic_sdp::lmi::{
    Compiled, Expr, FeasibilityOptions, Model, Outcome, Param, SolveOptions, Var,
};

use crate::error::Error;
use crate::system::Plant;

/// Which matrix inequality is imposed at each vertex (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LmiForm {
    /// The `3n × 3n` LMI (41) of Corollary 1, as printed.
    Corollary1,
    /// Its vertex-wise Schur complement, the `2n × 2n` form (39) at the vertices (same feasible set,
    /// cheaper; the default).
    #[default]
    Reduced,
}

/// How the gain enters (41).
#[derive(Debug, Clone)]
pub(crate) enum GainTerm {
    /// `J` is a decision variable (design, Corollary 1).
    Free,
    /// `J = FL` for the given `L` (analysis, (36) at the vertices).
    Fixed(Mat<f64>),
}

/// The size of one instance of LMI (41): how many vertex LMIs, of which order. (The solver
/// statistics of a solve are a [`SolverStats`]; its `decision_scalars` counts
/// `n(n+1)/2 + n² + nq` scalars, plus `μ` for a robust model, the margin `t` not counted.)
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LmiSize {
    /// Number of vertex LMIs `ν`.
    pub lmi_count: usize,
    /// Number of them imposed in the solve that returned the point: `ν`, or fewer when a
    /// window search's probe imposed only those found to bind (every vertex is then tested at
    /// the returned point by more than rounding; constraint generation, `crate::active`).
    pub imposed: usize,
    /// Order of each vertex LMI (`3n`; `2n` in the reduced form; `4n` with a remainder).
    pub block_size: usize,
}

/// How `J` is read back from a solution.
enum GainValue {
    /// `J` is a decision variable.
    Variable(Var),
    /// `J = FL` for this `L`.
    Fixed(Mat<f64>),
}

/// What is optimised over the feasible set of (41).
#[derive(Debug, Clone, Copy)]
pub(crate) enum Objective<'a> {
    /// Margin maximisation of the strict LMIs (every variable normalised, see the module docs).
    Margin(&'a FeasibilityOptions),
    /// `min tr P` subject to the well-scaled non-strict form `P ⪰ I`, `Φ_i ⪯ −I` (equivalent to the
    /// strict LMIs by homogeneity; the reference certificate of the bound constants).
    MinTrace(&'a SolveOptions),
}

/// A solved instance of (41) (or (36) at the vertices for a fixed `L`).
#[derive(Debug, Clone)]
pub(crate) struct LmiResult {
    /// Whether the returned point is a certificate: strict feasibility with a verified positive
    /// margin (margin mode), or every constraint verified at the returned point (min-trace mode).
    pub feasible: bool,
    /// Optimal common margin `t*` (margin mode).
    pub margin: Option<f64>,
    /// `P`, `F`, `J` at the returned point (`J = FL` for a fixed gain).
    pub p: Mat<f64>,
    pub f: Mat<f64>,
    pub j: Mat<f64>,
    /// Robustness multiplier `μ` (when the remainder is positive).
    pub mu: Option<f64>,
    pub stats: SolverStats,
    pub size: LmiSize,
}

/// An interior-point iterate of the margin problem of (41), as shown to the test of
/// [`Lmi41::solve_accepting`].
pub(crate) struct Point41 {
    /// The margin `t` of the iterate (positive).
    pub margin: f64,
    pub p: Mat<f64>,
    pub f: Mat<f64>,
    pub j: Mat<f64>,
    pub mu: Option<f64>,
}

impl Point41 {
    /// This point in place of the returned one of `r`, whose solver statistics are kept but
    /// for the status ([`Status::Accepted`](sporadic_sdp::Status::Accepted): the point is an
    /// iterate accepted by the caller's test) and the reason, which says so.
    pub fn into_result(self, mut r: LmiResult, reason: &str) -> LmiResult {
        r.stats.status = sporadic_sdp::Status::Accepted;
        r.stats.reason = format!("{reason}; the solve ended: {}", r.stats.reason);
        LmiResult {
            feasible: false,
            margin: Some(self.margin),
            p: self.p,
            f: self.f,
            j: self.j,
            mu: self.mu,
            ..r
        }
    }
}

/// A compiled instance of (41) whose vertices can be replaced (same count, same remainder sign)
/// and re-solved with the solver's structure analysis reused.
pub(crate) struct Lmi41 {
    compiled: Compiled,
    vertices: Vec<Param>,
    delta: Option<Param>,
    /// The output matrix `C` as a parameter (free gain only), with the plant's order.
    output: Option<Param>,
    order: usize,
    p: Var,
    f: Var,
    gain: GainValue,
    mu: Option<Var>,
    block_size: usize,
    form: LmiForm,
    min_trace: bool,
}

impl Lmi41 {
    /// Builds (41) for `vertices` (at least one, each `n×n`) with remainder `delta ≥ 0`.
    pub fn new(
        plant: &Plant,
        vertices: &[Mat<f64>],
        delta: f64,
        gain: GainTerm,
        form: LmiForm,
        objective: Objective<'_>,
    ) -> Result<Self, Error> {
        let n = plant.n();
        if vertices.is_empty() {
            return Err(InputError::empty("vertex set of the embedding").into());
        }
        let mut m = Model::new();
        let p = m.symmetric("P", n);
        let f = m.full("F", n, n);
        let (gain, coupling, output) = match gain {
            GainTerm::Free => {
                let j = m.full("J", n, plant.q());
                let c = m.param("C", plant.c())?;
                let coupling = &f - &j * &c;
                (GainValue::Variable(j), coupling, Some(c))
            }
            GainTerm::Fixed(l) => {
                let coupling = &f * plant.reset_matrix(l.as_ref())?;
                (GainValue::Fixed(l), coupling, None)
            }
        };
        let robust = delta > 0.0;
        let mu = robust.then(|| m.scalar("mu"));
        let delta_param = if robust {
            Some(m.param("delta^2", faer::mat![[delta * delta]].as_ref())?)
        } else {
            None
        };
        let min_trace = matches!(objective, Objective::MinTrace(_));
        let mut params = Vec::with_capacity(vertices.len());
        for (i, x) in vertices.iter().enumerate() {
            let x = m.param(&format!("X_{}", i + 1), x.as_ref())?;
            let px = &p * &x;
            let corner = -f.expr().he();
            let phi = match (&mu, &delta_param) {
                (Some(mu), Some(d2)) if form == LmiForm::Reduced => {
                    let corner = x.t() * &p * &x + corner + (mu * d2) * Expr::identity(n);
                    Expr::sym_blocks(&[
                        vec![Some(corner), None, None],
                        vec![Some(coupling.t()), Some(-&p), None],
                        vec![Some(px), None, Some(p.expr() - mu * Expr::identity(n))],
                    ])
                }
                (Some(mu), Some(d2)) => {
                    let corner = corner + (mu * d2) * Expr::identity(n);
                    Expr::sym_blocks(&[
                        vec![Some(corner), None, None, None],
                        vec![Some(coupling.t()), Some(-&p), None, None],
                        vec![Some(px), None, Some(-&p), None],
                        vec![None, None, Some(p.expr()), Some(-(mu * Expr::identity(n)))],
                    ])
                }
                _ if form == LmiForm::Reduced => Expr::sym_blocks(&[
                    vec![Some(x.t() * &p * &x + corner), None],
                    vec![Some(coupling.t()), Some(-&p)],
                ]),
                _ => Expr::sym_blocks(&[
                    vec![Some(corner), None, None],
                    vec![Some(coupling.t()), Some(-&p), None],
                    vec![Some(px), None, Some(-&p)],
                ]),
            };
            let c = if min_trace { phi.le(-1.0) } else { phi.lt(0.0) };
            m.constrain(c.named(format!("Phi_{}", i + 1)))?;
            params.push(x);
        }
        let compiled = match objective {
            Objective::Margin(options) => m.compile_feasibility(options)?,
            Objective::MinTrace(options) => {
                m.constrain(p.ge(1.0).named("P >= I"))?;
                m.minimize(p.trace())?;
                m.compile(options)?
            }
        };
        Ok(Self {
            compiled,
            vertices: params,
            delta: delta_param,
            output,
            order: n,
            p,
            f,
            gain,
            mu,
            block_size: n * match (robust, form) {
                (true, LmiForm::Corollary1) => 4,
                (true, LmiForm::Reduced) | (false, LmiForm::Corollary1) => 3,
                (false, LmiForm::Reduced) => 2,
            },
            form,
            min_trace,
        })
    }

    /// Whether a design (free gain) for `plant` with a vertex set of this size and remainder, in
    /// this form, can reuse this instance.
    pub fn fits(&self, plant: &Plant, count: usize, delta: f64, form: LmiForm) -> bool {
        self.output.is_some()
            && self.order == plant.n()
            && self.gain_columns() == Some(plant.q())
            && self.vertices.len() == count
            && (delta > 0.0) == self.delta.is_some()
            && self.form == form
    }

    /// Number of outputs of the free gain `J` (`None` for a fixed gain).
    fn gain_columns(&self) -> Option<usize> {
        match &self.gain {
            GainValue::Variable(j) => Some(j.shape().cols),
            GainValue::Fixed(_) => None,
        }
    }

    /// Replaces the output matrix, the vertices and the remainder without rebuilding the model.
    pub fn set_data(
        &mut self,
        plant: &Plant,
        vertices: &[Mat<f64>],
        delta: f64,
    ) -> Result<(), Error> {
        if !self.fits(plant, vertices.len(), delta, self.form) {
            return Err(InputError::mismatch(
                "vertex count of a re-solved LMI (41)",
                self.vertices.len(),
                vertices.len(),
            )
            .into());
        }
        if let Some(c) = &self.output {
            self.compiled.set_param(c, plant.c())?;
        }
        for (param, x) in self.vertices.iter().zip(vertices) {
            self.compiled.set_param(param, x.as_ref())?;
        }
        if let Some(d) = &self.delta {
            self.compiled
                .set_param(d, faer::mat![[delta * delta]].as_ref())?;
        }
        Ok(())
    }

    /// Solves the margin (or min-trace) problem and reads the certificate.
    pub fn solve(&mut self) -> Result<LmiResult, Error> {
        let sol = self.compiled.solve()?;
        self.result(sol)
    }

    /// Solves the margin problem, showing every interior-point iterate with a positive margin
    /// to `accept` and ending at the first one it accepts
    /// ([`Compiled::solve_accepting`](sporadic_sdp::lmi::Compiled::solve_accepting)); what an
    /// accepted point certifies is the caller's to decide (`LmiResult::feasible` is the LMI
    /// layer's verdict as for [`Lmi41::solve`]).
    pub fn solve_accepting(
        &mut self,
        accept: &mut (dyn FnMut(Point41) -> bool + Send),
    ) -> Result<LmiResult, Error> {
        let (p, f, gain, mu) = (&self.p, &self.f, &self.gain, &self.mu);
        let sol = self.compiled.solve_accepting(&mut |it| {
            let read = || -> Result<Point41, sporadic_sdp::lmi::ModelError> {
                let f = it.value(f)?;
                let j = match gain {
                    GainValue::Variable(j) => it.value(j)?,
                    GainValue::Fixed(l) => &f * l,
                };
                let mu = match mu {
                    Some(mu) => Some(it.value(mu)?[(0, 0)]),
                    None => None,
                };
                Ok(Point41 {
                    margin: it.margin(),
                    p: it.value(p)?,
                    f,
                    j,
                    mu,
                })
            };
            read().is_ok_and(&mut *accept)
        })?;
        self.result(sol)
    }

    /// Reads the certificate of a solve.
    fn result(&self, sol: sporadic_sdp::lmi::LmiSolution) -> Result<LmiResult, Error> {
        let p = sol.value(&self.p)?;
        let f = sol.value(&self.f)?;
        let j = match &self.gain {
            GainValue::Variable(j) => sol.value(j)?,
            GainValue::Fixed(l) => &f * l,
        };
        let mu = match &self.mu {
            Some(mu) => Some(sol.scalar(mu)?),
            None => None,
        };
        let feasible = if self.min_trace {
            sol.verification.passed()
        } else {
            sol.outcome == Outcome::Feasible && sol.margin.is_some_and(|t| t > 0.0)
        };
        let stats = SolverStats::of(&sol, self.compiled.model().num_scalars());
        let size = LmiSize {
            lmi_count: self.vertices.len(),
            imposed: self.vertices.len(),
            block_size: self.block_size,
        };
        Ok(LmiResult {
            feasible,
            margin: sol.margin,
            p,
            f,
            j,
            mu,
            stats,
            size,
        })
    }
}

/// `L = F⁻¹J` (Remark 8); `F + F' ≻ 0` makes `F` invertible for a feasible point.
pub(crate) fn gain_from(f: MatRef<'_, f64>, j: MatRef<'_, f64>) -> Result<Mat<f64>, Error> {
    use faer::linalg::solvers::Solve;
    let lu = f.full_piv_lu();
    let l = lu.solve(j);
    if (0..l.ncols()).all(|c| (0..l.nrows()).all(|r| l[(r, c)].is_finite())) {
        Ok(l)
    } else {
        Err(Error::Singular {
            what: "F of the LMI certificate (L = F^-1 J)".into(),
        })
    }
}
