//! Results: [`LmiSolution`], the independent [`Verification`] of every constraint, and the
//! [`Outcome`] rule.

use faer::Mat;

use super::compile::{Compiled, Mode};
use super::error::ModelError;
use super::expr::{Expr, Var, VarKind};
use super::model::ConstraintKind;
use crate::{Solution, Status};

/// A normalisation bound counts as active when its slack is below this fraction of the bound.
const ACTIVE_BOUND_REL: f64 = 1e-5;

/// What a solve established.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Outcome {
    /// The returned point satisfies every constraint by the [`Verification`] rule (strict ones
    /// with a positive margin); in objective mode the solver also reached its optimality
    /// tolerances, the full ones ([`Status::Optimal`]) or the reduced ones
    /// ([`Status::AlmostOptimal`]: the objective is optimal to reduced accuracy only; check
    /// `sdp.status`). In feasibility mode any verified point is feasible, whatever the status.
    Feasible,
    /// The constraints have no (strictly, for strict constraints) feasible point: a solver
    /// infeasibility certificate, or in feasibility mode a maximal margin at or below the
    /// verification threshold under a normalisation that loses no generality. The latter is
    /// infeasibility at the resolution of that threshold: no point satisfies the strict
    /// constraints by more than it, while a strictly feasible point with a smaller margin is not
    /// excluded (a homogeneous model always has `t* ≥ 0`, and a weakly detectable sampled pair
    /// can have a strictly feasible observer LMI whose margin is far below rounding); the reason
    /// says which of the two it is.
    Infeasible,
    /// The objective is unbounded (solver certificate).
    Unbounded,
    /// Neither could be established (solver inaccuracy, iteration limit, a margin-mode verdict
    /// that may be an artefact of an active normalisation bound): see [`LmiSolution::reason`].
    Inconclusive,
}

/// Verification of one constraint at a point.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintReport {
    /// Constraint name.
    pub name: String,
    /// Its kind.
    pub kind: ConstraintKind,
    /// Whether it is strict.
    pub strict: bool,
    /// `λ_min(F)` of the symmetric part (matrix), `min_ij F_ij` (entrywise) or `max_ij |F_ij|`
    /// (equality), computed in `f64` from the constraint's own expression data.
    pub value: f64,
    /// Summand scale `s = max(‖F_0‖_max, max_k |y_k|·‖F_k‖_max)`.
    pub scale: f64,
    /// `τ = safety · tol_feas · (1 + s)`.
    pub tolerance: f64,
    /// Non-strict: `value ≥ −τ`; strict: `value ≥ τ`; equality: `value ≤ τ`.
    pub passed: bool,
}

/// Independent a-posteriori check of every model constraint at a point.
///
/// Each constraint `F(y) = F_0 + Σ_k y_k F_k` is re-evaluated from its original expression data
/// (with the current parameter values — not from the compiled [`crate::Problem`], and including
/// the equalities that compilation eliminated), and judged against the tolerance
/// `τ = safety · tol_feas · (1 + s)`, where `s` is the magnitude of the summands of `F(y)` (the
/// scale of rounding and solver errors in its value) and `tol_feas` the solver's relative
/// feasibility tolerance:
///
/// * non-strict `F ⪰ 0` (`≥ 0` entrywise) passes iff `λ_min(F) ≥ −τ` (`min F_ij ≥ −τ`), i.e.
///   it holds up to the solver's accuracy;
/// * strict `F ≻ 0` (`> 0`) passes iff `λ_min(F) ≥ +τ`: the constraint holds with a margin that
///   rounding and solver error cannot explain, so it holds for the exact data;
/// * `F = 0` passes iff `max |F_ij| ≤ τ`.
///
/// Explicit margins (`X.ge(eps)`) are part of `F` (`F = X − εI`).
#[derive(Debug, Clone, PartialEq)]
pub struct Verification {
    /// One report per model constraint, in insertion order.
    pub constraints: Vec<ConstraintReport>,
    /// The solver's relative feasibility tolerance used.
    pub tol: f64,
    /// The safety factor used.
    pub safety: f64,
}

impl Verification {
    /// Whether every constraint passed.
    pub fn passed(&self) -> bool {
        self.constraints.iter().all(|c| c.passed)
    }

    /// The first constraint that failed, if any.
    pub fn first_failure(&self) -> Option<&ConstraintReport> {
        self.constraints.iter().find(|c| !c.passed)
    }

    /// The report of the constraint named `name`.
    pub fn get(&self, name: &str) -> Option<&ConstraintReport> {
        self.constraints.iter().find(|c| c.name == name)
    }
}

/// Result of [`Compiled::solve`] / [`super::Model::solve`] / [`super::Model::feasibility`].
#[derive(Debug, Clone)]
pub struct LmiSolution {
    /// What was established.
    pub outcome: Outcome,
    /// Why (human-readable, names the deciding constraint or certificate).
    pub reason: String,
    /// Objective value at the returned point (objective mode with an objective).
    pub objective: Option<f64>,
    /// Optimal common margin `t*` of the strict constraints (feasibility mode).
    pub margin: Option<f64>,
    /// Largest verification tolerance of a strict constraint: in feasibility mode a margin at
    /// or below it is not a strict-feasibility certificate.
    pub margin_threshold: Option<f64>,
    /// Per-constraint verification at the returned point.
    pub verification: Verification,
    /// The raw solver result (status, iterations, measures, certificate).
    pub sdp: Solution,
    y: Vec<f64>,
    model: u64,
    params: Vec<Mat<f64>>,
}

impl LmiSolution {
    /// Whether the outcome is [`Outcome::Feasible`].
    pub fn is_feasible(&self) -> bool {
        self.outcome == Outcome::Feasible
    }

    /// All decision scalars at the returned point (variables in creation order; symmetric ones by
    /// upper triangle column by column, full ones column-major).
    pub fn decision_scalars(&self) -> &[f64] {
        &self.y
    }

    /// Value of a variable at the returned point.
    pub fn value(&self, v: &Var) -> Result<Mat<f64>, ModelError> {
        var_value(self.model, &self.y, v)
    }

    /// Value of a scalar (or any 1×1) variable; [`ModelError::NotScalar`] for a larger one.
    pub fn scalar(&self, v: &Var) -> Result<f64, ModelError> {
        if (v.shape.rows, v.shape.cols) != (1, 1) {
            return Err(ModelError::NotScalar {
                what: format!("variable `{}`", v.name),
                shape: v.shape,
            });
        }
        Ok(self.value(v)?[(0, 0)])
    }

    /// Value of any expression of the model at the returned point (with the parameter values
    /// of this solve).
    pub fn eval(&self, e: &Expr) -> Result<Mat<f64>, ModelError> {
        let n = e.node()?;
        if n.model.is_some_and(|m| m != self.model) {
            return Err(ModelError::ForeignModel {
                what: "the expression".into(),
            });
        }
        if super::model::params_of(n)
            .last()
            .is_some_and(|&p| p >= self.params.len())
        {
            return Err(ModelError::UnknownVariable {
                what: "a parameter of the expression".into(),
            });
        }
        let a = n.eval(&self.params);
        if a.entries
            .last()
            .is_some_and(|e| e.slot as usize > self.y.len())
        {
            return Err(ModelError::UnknownVariable {
                what: "a variable of the expression".into(),
            });
        }
        Ok(a.eval(&self.y))
    }
}

impl Compiled {
    /// Verifies every model constraint at the decision scalars `y` (see [`Verification`]).
    pub fn verify(&mut self, y: &[f64]) -> Result<Verification, ModelError> {
        if y.len() != self.model.num_scalars {
            return Err(ModelError::InvalidArgument(format!(
                "verify: {} decision scalars given, the model has {}",
                y.len(),
                self.model.num_scalars
            )));
        }
        if let Some((k, v)) = y.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(ModelError::NonFinite {
                what: format!("decision scalar `{}`", self.model.scalar_name(k)),
                value: *v,
            });
        }
        self.refresh()?;
        verify_point(self, y)
    }
}

fn verify_point(c: &Compiled, y: &[f64]) -> Result<Verification, ModelError> {
    let tol = c.options.settings.tol_feas;
    let safety = c.options.safety;
    let mut reports = Vec::with_capacity(c.model.constraints.len());
    for (d, a) in c.model.constraints.iter().zip(&c.evals) {
        let a = a.as_ref().expect("evaluated by refresh");
        let f = a.eval(y);
        let scale = a.summand_scale(y);
        let tau = safety * tol * (1.0 + scale);
        let entries = || (0..f.ncols()).flat_map(|j| (0..f.nrows()).map(move |i| (i, j)));
        let value = match d.kind {
            ConstraintKind::Matrix => {
                let s = Mat::from_fn(f.nrows(), f.ncols(), |i, j| 0.5 * (f[(i, j)] + f[(j, i)]));
                sporadic_linalg::min_eigenvalue(s.as_ref())?
            }
            ConstraintKind::Entrywise => entries().map(|p| f[p]).fold(f64::INFINITY, f64::min),
            ConstraintKind::Equality => entries().map(|p| f[p].abs()).fold(0.0, f64::max),
        };
        let passed = match (d.kind, d.strict) {
            (ConstraintKind::Equality, _) => value <= tau,
            (_, true) => value >= tau,
            (_, false) => value >= -tau,
        };
        reports.push(ConstraintReport {
            name: d.name.clone(),
            kind: d.kind,
            strict: d.strict,
            value,
            scale,
            tolerance: tau,
            passed,
        });
    }
    Ok(Verification {
        constraints: reports,
        tol,
        safety,
    })
}

/// The acceptance test of a margin solve with
/// [`super::FeasibilityOptions::stop_when_verified`]: whether every constraint verifies at the
/// iterate whose solver vector is `cols` (the same check as at a returned point).
///
/// The check is made once the margin `t` of the iterate is positive (before that the iterate is
/// far from a certificate in general). It costs an evaluation and an eigenvalue computation per
/// constraint, a fraction of an interior-point iteration, whose Schur complement is `m` times
/// larger (three-mass-chain's 256 vertex LMIs of order 18: about 5 ms against 45 ms). Checking
/// only once the dual residual is below `t/2`, which would imply `λ_min(F_c(y)) ≥ t/2`, stopped
/// later: three-mass-chain's `compare` took 5–10% longer.
pub(crate) fn verified_iterate(c: &Compiled, cols: &[f64], t_col: usize) -> bool {
    if !(cols[t_col] > 0.0) {
        return false;
    }
    let y = scalars(c, cols);
    verify_point(c, &y).is_ok_and(|v| v.passed())
}

/// An interior-point iterate of a margin solve, as shown to the caller's acceptance test of
/// [`Compiled::solve_accepting`]: the margin `t` and the decision variables there.
#[derive(Debug)]
pub struct Iterate<'a> {
    model: u64,
    margin: f64,
    y: &'a [f64],
}

impl Iterate<'_> {
    /// The margin `t` of the iterate (positive whenever the test is consulted).
    pub fn margin(&self) -> f64 {
        self.margin
    }

    /// Value of a variable at the iterate (as [`LmiSolution::value`]).
    pub fn value(&self, v: &Var) -> Result<Mat<f64>, ModelError> {
        var_value(self.model, self.y, v)
    }
}

/// The acceptance test of a margin solve at the iterate whose solver vector is `cols`:
/// [`verified_iterate`] when `verified`, and the caller's `accept`
/// ([`Compiled::solve_accepting`]), at an iterate with a positive margin only.
pub(crate) fn accepted_iterate(
    c: &Compiled,
    cols: &[f64],
    t_col: usize,
    verified: bool,
    accept: &mut (dyn FnMut(&Iterate<'_>) -> bool + Send + '_),
) -> bool {
    if !(cols[t_col] > 0.0) {
        return false;
    }
    if verified && verified_iterate(c, cols, t_col) {
        return true;
    }
    let y = scalars(c, cols);
    accept(&Iterate {
        model: c.model.id,
        margin: cols[t_col],
        y: &y,
    })
}

/// The value of variable `v` of model `model` in the decision scalars `y`.
fn var_value(model: u64, y: &[f64], v: &Var) -> Result<Mat<f64>, ModelError> {
    if v.model != model {
        return Err(ModelError::ForeignModel {
            what: format!("variable `{}`", v.name),
        });
    }
    let n = v.num_scalars();
    if v.offset + n > y.len() {
        return Err(ModelError::UnknownVariable {
            what: format!("variable `{}`", v.name),
        });
    }
    let (r, c) = (v.shape.rows, v.shape.cols);
    let mut m = Mat::<f64>::zeros(r, c);
    for k in 0..n {
        let (i, j) = v.kind.position(r, k);
        let val = y[v.offset + k];
        m[(i, j)] = val;
        if v.kind == VarKind::Symmetric {
            m[(j, i)] = val;
        }
    }
    Ok(m)
}

/// The decision scalars of the solver vector `cols` (eliminated scalars recovered).
fn scalars(c: &Compiled, cols: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; c.model.num_scalars];
    for (col, &k) in c.col_scalar.iter().enumerate() {
        y[k] = cols[col];
    }
    c.elim.as_ref().expect("eliminated").recover(&mut y);
    y
}

/// Names of the variables whose normalisation bound is active (slack ≤ 1e-5·bound) at `y`.
fn active_bounds(c: &Compiled, y: &[f64]) -> Result<Vec<String>, ModelError> {
    let mut active = Vec::new();
    for n in &c.norms {
        let f = n.form.eval(y);
        let slack = if n.is_matrix {
            sporadic_linalg::min_eigenvalue(f.as_ref())?
        } else {
            (0..f.nrows())
                .map(|i| f[(i, 0)])
                .fold(f64::INFINITY, f64::min)
        };
        if slack <= ACTIVE_BOUND_REL * n.bound && !active.contains(&n.var) {
            active.push(n.var.clone());
        }
    }
    Ok(active)
}

/// Recovers the decision scalars, verifies and decides the outcome.
pub(crate) fn finish(c: &Compiled, sdp: Solution) -> Result<LmiSolution, ModelError> {
    let y = scalars(c, &sdp.y);
    let verification = verify_point(c, &y)?;
    let objective = match (&c.mode, &c.objective) {
        (Mode::Optimize { .. }, Some(f)) => Some(f.eval(&y)[(0, 0)]),
        _ => None,
    };
    let strict: Vec<_> = verification
        .constraints
        .iter()
        .filter(|r| r.strict)
        .collect();
    let margin_mode = matches!(c.mode, Mode::Margin { .. });
    let margin = (margin_mode && !strict.is_empty())
        .then(|| c.t_col.map(|t| sdp.y[t]))
        .flatten();
    let margin_threshold =
        (!strict.is_empty()).then(|| strict.iter().map(|r| r.tolerance).fold(0.0, f64::max));
    let failure = verification.first_failure().map(|r| {
        format!(
            "constraint `{}` fails verification: {} = {:.3e} against tolerance {:.3e}",
            r.name,
            match r.kind {
                ConstraintKind::Matrix => "λ_min",
                ConstraintKind::Entrywise => "min entry",
                ConstraintKind::Equality => "max |residual|",
            },
            r.value,
            r.tolerance
        )
    });
    let status = sdp.status;
    let (outcome, reason) = match &c.mode {
        Mode::Optimize { strict_margin } => {
            let raised: Vec<String> = verification
                .constraints
                .iter()
                .zip(&c.strict_margins)
                .filter(|(r, e)| r.strict && **e != *strict_margin)
                .map(|(r, e)| format!("`{}` with {e:.3e}", r.name))
                .collect();
            let raised_note = if raised.is_empty() {
                String::new()
            } else {
                format!(
                    " (strict margins raised to twice the verification tolerance: {})",
                    raised.join(", ")
                )
            };
            let strict_note = match (strict.is_empty(), raised.is_empty()) {
                (true, _) => String::new(),
                (false, true) => {
                    format!(" (strict constraints were imposed as ⪰ {strict_margin:.3e}·I)")
                }
                (false, false) => format!(
                    " (strict constraints were imposed as ⪰ ε·I with ε = {strict_margin:.3e}, \
                     raised to twice the verification tolerance for {})",
                    raised.join(", ")
                ),
            };
            match (status, &failure) {
                (Status::Optimal, None) => (
                    Outcome::Feasible,
                    format!(
                        "optimal; every constraint verified at the returned point{raised_note}"
                    ),
                ),
                (Status::DualInfeasible, _) => (
                    Outcome::Infeasible,
                    format!(
                        "the LMIs are infeasible (solver certificate X ⪰ 0, 𝒜(X) ≈ 0, ⟨C,X⟩ < 0){strict_note}"
                    ),
                ),
                (Status::PrimalInfeasible, _) => (
                    Outcome::Unbounded,
                    "the objective is unbounded (solver certificate: a ray of the feasible set)"
                        .to_string(),
                ),
                (Status::AlmostOptimal, None) => (
                    Outcome::Feasible,
                    format!(
                        "almost optimal (solved to reduced accuracy: largest DIMACS error {:.3e}); \
                         every constraint verified at the returned point{raised_note}",
                        sdp.measures.dimacs_max()
                    ),
                ),
                (Status::Optimal | Status::AlmostOptimal, Some(f)) => (
                    Outcome::Inconclusive,
                    format!(
                        "the solver reports {} but {f}{strict_note}",
                        if status.is_optimal() {
                            "an optimum"
                        } else {
                            "an almost optimal point"
                        }
                    ),
                ),
                (s, None) => (
                    Outcome::Inconclusive,
                    format!(
                        "solver stopped with {}; the returned point is verified feasible but optimality is not established",
                        s.as_str()
                    ),
                ),
                (s, Some(f)) => (
                    Outcome::Inconclusive,
                    format!("solver stopped with {}; {f}", s.as_str()),
                ),
            }
        }
        Mode::Margin { .. } => {
            let infeasible_status =
                matches!(status, Status::DualInfeasible | Status::PrimalInfeasible);
            let active = if c.homogeneous {
                Vec::new()
            } else {
                active_bounds(c, &y)?
            };
            let wlog = c.homogeneous || (active.is_empty() && !infeasible_status);
            let artefact = || {
                format!(
                    "the model has constant terms and the normalisation bound on {} is active, so \
                     the bound may cut off feasible points; relax it with FeasibilityOptions::normalise",
                    if active.is_empty() {
                        "some variable".to_string()
                    } else {
                        format!("`{}`", active.join("`, `"))
                    }
                )
            };
            match (status, &failure, margin, margin_threshold) {
                (Status::Accepted, None, Some(t), _) => (
                    Outcome::Feasible,
                    format!(
                        "strictly feasible: margin t = {t:.3e} at the first interior-point \
                         iterate at which every constraint verifies (the solve stops there; the \
                         optimal margin is at least t)"
                    ),
                ),
                (s, None, _, _) if !infeasible_status && s != Status::PrimalInfeasible => (
                    Outcome::Feasible,
                    match margin {
                        Some(t) => format!(
                            "strictly feasible: margin t* = {t:.3e}; every constraint verified"
                        ),
                        None => "feasible; every constraint verified".to_string(),
                    },
                ),
                (Status::DualInfeasible, _, _, _) => {
                    if wlog {
                        (
                            Outcome::Infeasible,
                            "the non-strict constraints are infeasible (solver certificate)"
                                .to_string(),
                        )
                    } else {
                        (
                            Outcome::Inconclusive,
                            format!("solver certificate of infeasibility, but {}", artefact()),
                        )
                    }
                }
                (Status::Optimal, _, Some(t), Some(thr)) if t <= thr => {
                    if wlog {
                        (
                            Outcome::Infeasible,
                            format!(
                                "no verifiable margin: the maximal common margin t* = {t:.3e} is \
                                 at or below the verification threshold {thr:.3e}, so no point \
                                 satisfies the strict constraints by more than the threshold (a \
                                 strictly feasible point with a smaller margin is not excluded)"
                            ),
                        )
                    } else {
                        (
                            Outcome::Inconclusive,
                            format!(
                                "maximal margin t* = {t:.3e} ≤ {thr:.3e}, but {}",
                                artefact()
                            ),
                        )
                    }
                }
                (s, Some(f), _, _) => (
                    Outcome::Inconclusive,
                    format!("solver status {}; {f}", s.as_str()),
                ),
                (s, None, _, _) => (
                    Outcome::Inconclusive,
                    format!("solver status {}", s.as_str()),
                ),
            }
        }
    };
    Ok(LmiSolution {
        outcome,
        reason,
        objective,
        margin,
        margin_threshold,
        verification,
        sdp,
        y,
        model: c.model.id,
        params: c.model.params.clone(),
    })
}
