//! Compilation of a [`Model`] to the solver's dual (LMI) standard form, and the re-solvable
//! [`Compiled`] handle.
//!
//! **Sign convention** (crate docs, [`crate::problem`]): an LMI `F(y) = F_0 + Σ_k y_k F_k ⪰ 0`
//! is the dual constraint `C − Σ_k y_k A_k = S ⪰ 0` with `C = F_0`, `A_k = −F_k`; the solver
//! maximises `bᵀy`, so `min f(y)` is compiled with `b = −∇f`.
//!
//! **Layout.** Solver variables are the decision scalars that remain free after equality
//! elimination ([`super::eliminate`]) and occur in some inequality, in increasing order, followed
//! by the margin `t` in feasibility mode. Block 0 is the LP block (entrywise constraints, 1×1
//! matrix inequalities, the margin cap and scalar normalisations), followed by the PSD blocks of
//! the normalisations and then one PSD block per matrix inequality, in insertion order.
//! Constraints that are constant after elimination are checked at compile time: satisfied ones are
//! left out of the problem (they would only remove its interior), violated ones are kept so that
//! the solver certifies infeasibility.

use faer::MatRef;

use super::affine::{Affine, CONST, Entry};
use super::eliminate::Elimination;
use super::error::{ModelError, Shape};
use super::expr::{Expr, Param, Var, VarKind};
use super::model::{ConstraintData, ConstraintId, ConstraintKind, Model, Sense, check_finite};
use super::solution::{self, Iterate, LmiSolution};
use crate::problem::{Block, BlockData, BlockKind, Problem, SparseSym};
use crate::{Settings, Solver, Status};

/// Options of [`Model::solve`] / [`Model::compile`] (objective mode).
#[derive(Debug, Clone)]
pub struct SolveOptions {
    /// Interior-point settings (tolerances, iteration limit, log).
    pub settings: Settings,
    /// In objective mode a strict constraint `F ≻ 0` is imposed as `F ⪰ ε·I` with at least this
    /// margin (absolute; default `1e-6`), and with more where its verification needs it: the
    /// margin is `ε = max(strict_margin, 2τ)` with `τ` the constraint's verification tolerance
    /// at the returned point (see [`super::Verification`] and [`Compiled::solve`]), so a strictly
    /// feasible model is never inconclusive because of our own tolerances. Interior-point methods
    /// cannot impose strictness; explicit, problem-scaled margins (`F.ge(eps)`) or
    /// [`Model::feasibility`] state the intent directly.
    pub strict_margin: f64,
    /// Safety factor of the verification rule (default 10; see [`super::Verification`]).
    pub safety: f64,
}

impl Default for SolveOptions {
    fn default() -> Self {
        Self {
            settings: Settings::default(),
            strict_margin: 1e-6,
            safety: 10.0,
        }
    }
}

/// Bound that makes a variable's range compact in the margin problem of [`Model::feasibility`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Normalisation {
    /// Spectral-norm bound `‖X‖₂ ≤ ρ`: `−ρI ⪯ X ⪯ ρI` for symmetric `X`,
    /// `[ρI X; Xᵀ ρI] ⪰ 0` for a full one, `|x_i| ≤ ρ` for scalar and diagonal variables.
    Norm(f64),
    /// `tr X ≤ c` (symmetric variables only; meant for variables the model already keeps
    /// positive semidefinite).
    Trace(f64),
    /// No bound (the model itself must keep the variable bounded).
    Free,
}

/// Options of [`Model::feasibility`]: the strict-LMI margin problem
///
/// ```text
/// maximise t   s.t.  F_c(y) ⪰ t·I   for every strict constraint c (entrywise: F_c ≥ t),
///                    every non-strict constraint and equality as given,
///                    t ≤ margin_cap,   a normalisation bound on every variable.
/// ```
///
/// The defaults are `margin_cap = 1` and `‖X‖₂ ≤ 1` for every variable. For a *homogeneous*
/// model (every constraint and equality has a zero constant term, as the Lyapunov and observer
/// LMIs of the papers) this normalisation loses nothing: any strictly feasible point can be scaled
/// into it, so the model is strictly feasible iff the optimal margin is positive. For a model with
/// constant terms (e.g. `P ⪰ I`) the bounds may cut off solutions; choose them with
/// [`FeasibilityOptions::normalise`], or check [`LmiSolution::reason`], which says when an
/// infeasibility verdict could be an artefact of an active bound.
#[derive(Debug, Clone)]
pub struct FeasibilityOptions {
    /// Solver settings and verification safety factor (`strict_margin` is not used: the margin
    /// is a decision variable here).
    pub solve: SolveOptions,
    /// Upper bound on the margin `t` (default 1), which keeps the problem bounded.
    pub margin_cap: f64,
    /// Normalisation of every variable without an override (default `Norm(1.0)`).
    pub default_normalisation: Normalisation,
    /// Relative accuracy asked of a positive optimal margin `t*` (default `1e-7`). The solver's
    /// stopping rule is relative to `1 + |⟨C,X⟩| + |bᵀy|`, so a margin far below 1 (the observer
    /// LMIs' `t*` are often `1e-4`) is only accurate to `tol_gap / t*` after the first solve;
    /// when the duality gap and complementarity at the returned point exceed
    /// `margin_accuracy · t*`, the solve continues from that point with `tol_gap` and `tol_feas`
    /// tightened by the missing factor (never below `1e-14`). `1.0` or more turns this off.
    pub margin_accuracy: f64,
    /// End the solve at the first interior-point iterate at which every constraint verifies
    /// (default `false`). Such a point is a certificate of strict feasibility with the margin
    /// `t` it has, in general below the optimal `t*` (which is then not computed, nor refined
    /// to [`FeasibilityOptions::margin_accuracy`]); a model that is not strictly feasible is
    /// solved as without this option, since no iterate verifies. Meant for searches that only
    /// need the verdict (e.g. the bisection of a sampling window); see [`Compiled::solve`].
    pub stop_when_verified: bool,
    overrides: Vec<(u64, usize, Normalisation)>,
}

impl Default for FeasibilityOptions {
    fn default() -> Self {
        Self {
            solve: SolveOptions::default(),
            margin_cap: 1.0,
            default_normalisation: Normalisation::Norm(1.0),
            margin_accuracy: 1e-7,
            stop_when_verified: false,
            overrides: Vec::new(),
        }
    }
}

impl FeasibilityOptions {
    /// Uses `n` instead of the default normalisation for `var`.
    pub fn normalise(mut self, var: &Var, n: Normalisation) -> Self {
        self.overrides
            .retain(|o| (o.0, o.1) != (var.model, var.index));
        self.overrides.push((var.model, var.index, n));
        self
    }
}

#[derive(Debug, Clone)]
pub(crate) enum Mode {
    Optimize {
        strict_margin: f64,
    },
    Margin {
        cap: f64,
        norms: Vec<Normalisation>,
        accuracy: f64,
        stop_when_verified: bool,
    },
}

/// Counters of the work done by a [`Compiled`] model (to check that re-solves reuse structure).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CompileStats {
    /// Constraint (or objective) expression evaluations.
    pub evaluations: usize,
    /// Equality eliminations.
    pub eliminations: usize,
    /// Assemblies of the solver's [`Problem`].
    pub assemblies: usize,
    /// Structure analyses (`Solver::new`).
    pub analyses: usize,
    /// Solver runs.
    pub solves: usize,
    /// Continuations of a margin solve to reach [`FeasibilityOptions::margin_accuracy`].
    pub refinements: usize,
}

/// A normalisation constraint of the margin problem (kept to judge whether it is active).
#[derive(Debug, Clone)]
pub(crate) struct NormConstraint {
    pub var: String,
    pub bound: f64,
    /// `F ⪰ 0` (or `F ≥ 0` entrywise) over the original decision scalars.
    pub form: Affine,
    pub is_matrix: bool,
}

/// A model compiled to the solver's standard form, ready to be solved repeatedly.
///
/// * [`Compiled::set_param`] replaces a parameter's value; only the constraints that depend on
///   it are re-evaluated, and when the sparsity pattern stays within the analysed one the
///   solver's structure analysis ([`Solver`]) is reused.
/// * [`Compiled::add`] appends a constraint (e.g. a new τ point); only that constraint is
///   evaluated, the problem is re-assembled and the structure is analysed again.
///
/// ```
/// use faer::mat;
/// use sporadic_sdp::lmi::{FeasibilityOptions, Model};
///
/// // Schur stability of E through P ≻ 0, EᵀPE − P ≺ 0, for several E without rebuilding.
/// let mut m = Model::new();
/// let p = m.symmetric("P", 2);
/// let e = m.param("E", mat![[0.5, 1.0], [0.0, 0.5]].as_ref())?;
/// m.constrain(p.gt(0.0))?;
/// m.constrain((e.t() * &p * &e - &p).lt(0.0))?;
/// let mut c = m.compile_feasibility(&FeasibilityOptions::default())?;
/// assert!(c.solve()?.is_feasible());
/// c.set_param(&e, mat![[1.1, 0.0], [0.0, 0.5]].as_ref())?; // spectral radius 1.1
/// assert!(!c.solve()?.is_feasible());
/// assert_eq!(c.stats().analyses, 1); // the solver's structure analysis was reused
/// # Ok::<(), sporadic_sdp::lmi::ModelError>(())
/// ```
pub struct Compiled {
    pub(crate) model: Model,
    pub(crate) mode: Mode,
    pub(crate) options: SolveOptions,
    /// Per constraint: the expression evaluated at the current parameters (`None` = stale).
    pub(crate) evals: Vec<Option<Affine>>,
    /// Per inequality: symmetrised, equality-substituted form (`None` = stale).
    reduced: Vec<Option<Affine>>,
    pub(crate) objective: Option<Affine>,
    objective_stale: bool,
    pub(crate) elim: Option<Elimination>,
    problem: Option<Problem>,
    /// Solver column → decision scalar.
    pub(crate) col_scalar: Vec<usize>,
    /// Column of the margin `t`.
    pub(crate) t_col: Option<usize>,
    pub(crate) homogeneous: bool,
    pub(crate) norms: Vec<NormConstraint>,
    /// Per constraint: the margin `ε` a strict constraint is imposed with in objective mode
    /// (`F ⪰ εI`); see [`SolveOptions::strict_margin`].
    pub(crate) strict_margins: Vec<f64>,
    solver: Option<(Solver, Problem)>,
    pub(crate) stats: CompileStats,
}

impl std::fmt::Debug for Compiled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Compiled")
            .field("model", &self.model)
            .field("mode", &self.mode)
            .field("stats", &self.stats)
            .finish()
    }
}

impl Model {
    /// Compiles for [`Compiled::solve`] in objective mode (the objective, if any, is optimised;
    /// without one this is a plain feasibility problem).
    pub fn compile(&self, options: &SolveOptions) -> Result<Compiled, ModelError> {
        check_solve_options(options)?;
        if !(options.strict_margin >= 0.0 && options.strict_margin.is_finite()) {
            return Err(ModelError::InvalidArgument(format!(
                "strict_margin must be finite and ≥ 0, got {}",
                options.strict_margin
            )));
        }
        let mode = Mode::Optimize {
            strict_margin: options.strict_margin,
        };
        Compiled::new(self.clone(), mode, options.clone())
    }

    /// Compiles the strict-LMI margin problem (see [`FeasibilityOptions`]); the objective is
    /// ignored.
    pub fn compile_feasibility(
        &self,
        options: &FeasibilityOptions,
    ) -> Result<Compiled, ModelError> {
        check_solve_options(&options.solve)?;
        if !(options.margin_cap > 0.0 && options.margin_cap.is_finite()) {
            return Err(ModelError::InvalidArgument(format!(
                "margin_cap must be finite and > 0, got {}",
                options.margin_cap
            )));
        }
        if !(options.margin_accuracy > 0.0 && options.margin_accuracy.is_finite()) {
            return Err(ModelError::InvalidArgument(format!(
                "margin_accuracy must be finite and > 0, got {}",
                options.margin_accuracy
            )));
        }
        let mut norms = vec![options.default_normalisation; self.vars.len()];
        for &(model, index, n) in &options.overrides {
            if model != self.id {
                return Err(ModelError::ForeignModel {
                    what: "a variable given to FeasibilityOptions::normalise".into(),
                });
            }
            norms[index] = n;
        }
        for (v, n) in self.vars.iter().zip(&norms) {
            match *n {
                Normalisation::Norm(r) | Normalisation::Trace(r) if !(r > 0.0 && r.is_finite()) => {
                    return Err(ModelError::InvalidArgument(format!(
                        "normalisation bound of `{}` must be finite and > 0, got {r}",
                        v.name
                    )));
                }
                Normalisation::Trace(_) if v.kind != VarKind::Symmetric => {
                    return Err(ModelError::InvalidArgument(format!(
                        "trace normalisation needs a symmetric variable, `{}` is {:?}",
                        v.name, v.kind
                    )));
                }
                _ => {}
            }
        }
        let mode = Mode::Margin {
            cap: options.margin_cap,
            norms,
            accuracy: options.margin_accuracy,
            stop_when_verified: options.stop_when_verified,
        };
        Compiled::new(self.clone(), mode, options.solve.clone())
    }

    /// Compiles and solves once in objective mode (YALMIP: `optimize(F, f)`).
    pub fn solve(&self, options: &SolveOptions) -> Result<LmiSolution, ModelError> {
        self.compile(options)?.solve()
    }

    /// Compiles and solves the strict-LMI margin problem once (see [`FeasibilityOptions`]).
    pub fn feasibility(&self, options: &FeasibilityOptions) -> Result<LmiSolution, ModelError> {
        self.compile_feasibility(options)?.solve()
    }
}

fn check_solve_options(o: &SolveOptions) -> Result<(), ModelError> {
    if !(o.safety >= 1.0 && o.safety.is_finite()) {
        return Err(ModelError::InvalidArgument(format!(
            "safety factor must be finite and ≥ 1, got {}",
            o.safety
        )));
    }
    Ok(())
}

/// Upper-triangle entries of one slot run (entries sorted by (col,row)).
fn upper(entries: &[Entry], sign: f64) -> SparseSym {
    let mut s = SparseSym::default();
    for e in entries.iter().filter(|e| e.row <= e.col) {
        s.rows.push(e.row as usize);
        s.cols.push(e.col as usize);
        s.vals.push(sign * e.val);
    }
    s
}

/// Runs of equal slot in a sorted entry list.
fn slot_runs(entries: &[Entry]) -> impl Iterator<Item = (u32, &[Entry])> {
    let mut k = 0;
    std::iter::from_fn(move || {
        if k == entries.len() {
            return None;
        }
        let slot = entries[k].slot;
        let start = k;
        while k < entries.len() && entries[k].slot == slot {
            k += 1;
        }
        Some((slot, &entries[start..k]))
    })
}

/// Incremental builder of the LP block.
#[derive(Default)]
struct LpRows {
    c: Vec<f64>,
    /// Per column: `(row, value)` in increasing row order.
    a: Vec<Vec<(usize, f64)>>,
}

impl LpRows {
    fn push_row(&mut self, c: f64, coeffs: &[(usize, f64)]) {
        let r = self.c.len();
        self.c.push(c);
        for &(col, v) in coeffs {
            self.a[col].push((r, v));
        }
    }
}

/// Whether `new` has the block layout of `old` and a sparsity pattern contained in it (then a
/// [`Solver`] analysed on `old` accepts it).
fn pattern_within(new: &Problem, old: &Problem) -> bool {
    fn within(n: &SparseSym, o: &SparseSym) -> bool {
        let mut e = 0;
        for (r, c, _) in n.iter() {
            while e < o.nnz() && (o.cols[e], o.rows[e]) < (c, r) {
                e += 1;
            }
            if e == o.nnz() || (o.cols[e], o.rows[e]) != (c, r) {
                return false;
            }
        }
        true
    }
    if new.b.len() != old.b.len() || new.blocks.len() != old.blocks.len() {
        return false;
    }
    new.blocks.iter().zip(&old.blocks).all(|(n, o)| {
        if n.block != o.block {
            return false;
        }
        let mut p = 0;
        n.a.iter().all(|(i, a)| {
            while p < o.a.len() && o.a[p].0 < *i {
                p += 1;
            }
            p < o.a.len() && o.a[p].0 == *i && within(a, &o.a[p].1)
        })
    })
}

impl Compiled {
    fn new(model: Model, mode: Mode, options: SolveOptions) -> Result<Self, ModelError> {
        if model.constraints.is_empty() {
            return Err(ModelError::NoConstraints);
        }
        let n = model.constraints.len();
        let strict_margins = vec![options.strict_margin; n];
        Ok(Self {
            model,
            mode,
            options,
            evals: vec![None; n],
            reduced: vec![None; n],
            objective: None,
            objective_stale: true,
            elim: None,
            problem: None,
            col_scalar: Vec::new(),
            t_col: None,
            homogeneous: false,
            norms: Vec::new(),
            strict_margins,
            solver: None,
            stats: CompileStats::default(),
        })
    }

    /// Work counters (evaluations, assemblies, structure analyses, solves).
    pub fn stats(&self) -> CompileStats {
        self.stats
    }

    /// The model (with the current parameter values).
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Replaces the value of parameter `p`; the constraints using it are re-evaluated at the
    /// next [`Compiled::solve`].
    pub fn set_param(&mut self, p: &Param, value: MatRef<'_, f64>) -> Result<(), ModelError> {
        if p.model != self.model.id || p.index >= self.model.params.len() {
            return Err(ModelError::ForeignModel {
                what: format!("parameter `{}`", p.name),
            });
        }
        let found = Shape::new(value.nrows(), value.ncols());
        if found != p.shape {
            return Err(ModelError::ParamShape {
                param: p.name.to_string(),
                expected: p.shape,
                found,
            });
        }
        check_finite(value, &format!("new value of parameter `{}`", p.name))?;
        self.model.params[p.index].copy_from(value);
        for (c, data) in self.model.constraints.iter().enumerate() {
            if data.params.binary_search(&p.index).is_ok() {
                self.evals[c] = None;
            }
        }
        if self
            .model
            .objective
            .as_ref()
            .is_some_and(|o| o.params.binary_search(&p.index).is_ok())
        {
            self.objective_stale = true;
        }
        Ok(())
    }

    /// Appends a constraint (e.g. the block of a new τ point) without touching the others.
    pub fn add(&mut self, c: super::Constraint) -> Result<ConstraintId, ModelError> {
        let data = self.model.validate(c)?;
        if let Some(&p) = data.params.last()
            && p >= self.model.params.len()
        {
            return Err(ModelError::UnknownVariable {
                what: format!("a parameter of constraint `{}`", data.name),
            });
        }
        self.model.constraints.push(data);
        self.evals.push(None);
        self.reduced.push(None);
        self.strict_margins.push(self.options.strict_margin);
        Ok(ConstraintId(self.model.constraints.len() - 1))
    }

    /// The standard-form problem handed to the solver (assembled from the current data).
    pub fn problem(&mut self) -> Result<&Problem, ModelError> {
        self.refresh()?;
        Ok(self.problem.as_ref().expect("assembled by refresh"))
    }

    fn evaluate(&self, data: &ConstraintData) -> Result<Affine, ModelError> {
        let a = data.node.eval(&self.model.params).into_owned();
        if let Some(last) = a.entries.last()
            && last.slot as usize > self.model.num_scalars
        {
            return Err(ModelError::UnknownVariable {
                what: format!("a variable of constraint `{}`", data.name),
            });
        }
        self.model.check_evaluated(data, &a)?;
        Ok(a)
    }

    /// Brings evaluations, elimination and the assembled problem up to date.
    pub(crate) fn refresh(&mut self) -> Result<(), ModelError> {
        let mut eq_changed = self.elim.is_none();
        for c in 0..self.model.constraints.len() {
            if self.evals[c].is_none() {
                let a = self.evaluate(&self.model.constraints[c])?;
                self.stats.evaluations += 1;
                self.evals[c] = Some(a);
                self.reduced[c] = None;
                self.problem = None;
                if self.model.constraints[c].kind == ConstraintKind::Equality {
                    eq_changed = true;
                }
            }
        }
        if self.objective_stale {
            self.objective = match &self.model.objective {
                Some(o) => {
                    let a = o.node.eval(&self.model.params).into_owned();
                    if let Some(e) = a.first_non_finite() {
                        return Err(ModelError::NonFinite {
                            what: "the objective".into(),
                            value: e.val,
                        });
                    }
                    self.stats.evaluations += 1;
                    Some(a)
                }
                None => None,
            };
            self.objective_stale = false;
            self.problem = None;
        }
        if eq_changed {
            let eqs: Vec<(&str, &Affine)> = self
                .model
                .constraints
                .iter()
                .zip(&self.evals)
                .filter(|(d, _)| d.kind == ConstraintKind::Equality)
                .map(|(d, a)| (d.name.as_str(), a.as_ref().expect("evaluated")))
                .collect();
            let elim = if eqs.is_empty() {
                Elimination::identity(self.model.num_scalars)
            } else {
                self.stats.eliminations += 1;
                Elimination::build(self.model.num_scalars, &eqs)?
            };
            self.elim = Some(elim);
            self.reduced.iter_mut().for_each(|r| *r = None);
            self.problem = None;
        }
        let elim = self.elim.as_ref().expect("built above");
        for c in 0..self.model.constraints.len() {
            let data = &self.model.constraints[c];
            if data.kind != ConstraintKind::Equality && self.reduced[c].is_none() {
                let a = self.evals[c].as_ref().expect("evaluated");
                let sym = if data.kind == ConstraintKind::Matrix {
                    a.symmetrized()
                } else {
                    a.clone()
                };
                self.reduced[c] = Some(elim.apply(&sym));
            }
        }
        if self.problem.is_none() {
            self.assemble()?;
        }
        Ok(())
    }

    fn assemble(&mut self) -> Result<(), ModelError> {
        self.stats.assemblies += 1;
        let model = &self.model;
        let elim = self.elim.as_ref().expect("eliminated");
        let ineqs: Vec<(usize, &ConstraintData, &Affine)> = model
            .constraints
            .iter()
            .zip(&self.reduced)
            .enumerate()
            .filter(|(_, (d, _))| d.kind != ConstraintKind::Equality)
            .map(|(c, (d, r))| (c, d, r.as_ref().expect("reduced")))
            .collect();
        // Columns: free scalars occurring in some inequality.
        let mut col_of = vec![usize::MAX; model.num_scalars];
        for (_, _, r) in &ineqs {
            for s in r.slots().filter(|&s| s != CONST) {
                col_of[s as usize - 1] = 0;
            }
        }
        let mut col_scalar = Vec::new();
        for (k, c) in col_of.iter_mut().enumerate() {
            if *c == 0 {
                *c = col_scalar.len();
                col_scalar.push(k);
            }
        }
        let margin = matches!(self.mode, Mode::Margin { .. });
        let t_col = margin.then_some(col_scalar.len());
        let m = col_scalar.len() + usize::from(margin);
        if m == 0 {
            return Err(ModelError::InvalidArgument(
                "no decision variable occurs in the inequality constraints (after equality \
                 elimination); there is nothing to optimise"
                    .into(),
            ));
        }
        self.homogeneous = elim.is_homogeneous()
            && ineqs
                .iter()
                .all(|(_, _, r)| r.entries.first().is_none_or(|e| e.slot != CONST));

        // Objective.
        let mut b = vec![0.0; m];
        match (&self.mode, &self.objective, &model.objective) {
            (Mode::Optimize { .. }, Some(f), Some(o)) => {
                let sign = if o.sense == Sense::Minimize {
                    -1.0
                } else {
                    1.0
                };
                let red = elim.apply(f);
                for e in red.entries.iter().filter(|e| e.slot != CONST) {
                    let k = e.slot as usize - 1;
                    if col_of[k] == usize::MAX {
                        return Err(ModelError::Unbounded {
                            scalar: model.scalar_name(k),
                        });
                    }
                    b[col_of[k]] += sign * e.val;
                }
            }
            (Mode::Margin { .. }, _, _) => b[m - 1] = 1.0,
            _ => {}
        }

        let mut lp = LpRows {
            c: Vec::new(),
            a: vec![Vec::new(); m],
        };
        let mut psd: Vec<BlockData> = Vec::new();
        let strict_terms = |c: usize, strict: bool| -> Strictness {
            match (&self.mode, strict) {
                (Mode::Optimize { .. }, true) => (-self.strict_margins[c], None),
                (Mode::Margin { .. }, true) => (0.0, Some(-1.0)),
                _ => (0.0, None),
            }
        };

        // Margin cap and normalisations.
        let mut norms = Vec::new();
        if let Mode::Margin {
            cap,
            norms: per_var,
            ..
        } = &self.mode
        {
            lp.push_row(*cap, &[(m - 1, -1.0)]);
            let used = |slot: u32| slot == CONST || col_of[slot as usize - 1] != usize::MAX;
            for (v, n) in model.vars.iter().zip(per_var) {
                for (bound, form, is_matrix) in normalisation_forms(model.id, v, *n) {
                    let red = elim
                        .apply(&form)
                        .substitute(|s| if used(s) { vec![(s, 1.0)] } else { Vec::new() });
                    if red.is_constant() {
                        continue;
                    }
                    push_form(
                        &red,
                        is_matrix,
                        (0.0, None),
                        &col_of,
                        t_col,
                        &mut lp,
                        &mut psd,
                    );
                    norms.push(NormConstraint {
                        var: v.name.to_string(),
                        bound,
                        form,
                        is_matrix,
                    });
                }
            }
        }

        for (c, d, red) in &ineqs {
            let (shift, t_coef) = strict_terms(*c, d.strict);
            let is_matrix = d.kind == ConstraintKind::Matrix;
            if is_matrix
                && red.rows > 1
                && red.is_constant()
                && t_coef.is_none()
                && constant_psd(red, shift)?
            {
                continue;
            }
            push_form(
                red,
                is_matrix,
                (shift, t_coef),
                &col_of,
                t_col,
                &mut lp,
                &mut psd,
            );
        }

        let mut blocks = Vec::with_capacity(psd.len() + 1);
        if !lp.c.is_empty() {
            let n = lp.c.len();
            let mut c = SparseSym::default();
            for (r, &v) in lp.c.iter().enumerate().filter(|(_, v)| **v != 0.0) {
                c.rows.push(r);
                c.cols.push(r);
                c.vals.push(v);
            }
            let a =
                lp.a.into_iter()
                    .enumerate()
                    .filter(|(_, l)| !l.is_empty())
                    .map(|(col, l)| {
                        let mut s = SparseSym::default();
                        for (r, v) in l {
                            s.rows.push(r);
                            s.cols.push(r);
                            s.vals.push(-v);
                        }
                        (col, s)
                    })
                    .collect();
            blocks.push(BlockData {
                block: Block {
                    kind: BlockKind::Lp,
                    size: n,
                },
                c,
                a,
            });
        }
        blocks.extend(psd);
        self.col_scalar = col_scalar;
        self.t_col = t_col;
        self.norms = norms;
        self.problem = Some(Problem { blocks, b });
        Ok(())
    }

    /// Solves (re-using the analysed structure when possible) and verifies the result.
    ///
    /// In objective mode every strict constraint starts with the margin
    /// [`SolveOptions::strict_margin`]. If at the returned point a strict constraint fails its
    /// verification (`λ_min(F) < τ`) while its margin is below `2τ` — the solver met the margin
    /// but the margin is smaller than what the check requires — the margin is raised to `2τ`
    /// and the model re-solved (at most [`MARGIN_ROUNDS`] times, re-using the structure
    /// analysis; `τ` depends on the point through the scale of `F`). The margins start from
    /// `strict_margin` again at every call, so a result does not depend on earlier solves.
    pub fn solve(&mut self) -> Result<LmiSolution, ModelError> {
        let default = self.options.strict_margin;
        if self.strict_margins.iter().any(|&e| e != default) {
            self.strict_margins.iter_mut().for_each(|e| *e = default);
            self.problem = None;
        }
        let mut sol = self.solve_once(None)?;
        if !matches!(self.mode, Mode::Optimize { .. }) {
            return Ok(sol);
        }
        for _ in 0..MARGIN_ROUNDS {
            let mut raised = false;
            for (c, r) in sol.verification.constraints.iter().enumerate() {
                let need = STRICT_MARGIN_FACTOR * r.tolerance;
                if r.strict && !r.passed && self.strict_margins[c] < need {
                    self.strict_margins[c] = need;
                    raised = true;
                }
            }
            if !raised {
                break;
            }
            self.problem = None;
            sol = self.solve_once(None)?;
        }
        Ok(sol)
    }

    /// Like [`Compiled::solve`] for a margin problem ([`Model::compile_feasibility`]), but the
    /// solve ends at the first interior-point iterate with a positive margin `t` that `accept`
    /// accepts (the status is then [`Status::Accepted`]). This is for a caller with a
    /// certificate test of its own, sharper than the [`super::Verification`] rule on its problem
    /// (e.g. one that knows the structure and the rounding of its data); the test replaces the
    /// stop of [`FeasibilityOptions::stop_when_verified`], which is not made. The
    /// [`LmiSolution`] still reports the verification of the returned point, and what an accepted
    /// point certifies is the caller's to decide. The continuation that refines a positive
    /// optimal margin ([`FeasibilityOptions::margin_accuracy`]) consults `accept` too; a test
    /// that accepts nothing gives the result of [`Compiled::solve`] without
    /// `stop_when_verified`. In objective mode this is [`ModelError::InvalidArgument`].
    pub fn solve_accepting(
        &mut self,
        accept: &mut (dyn FnMut(&Iterate<'_>) -> bool + Send),
    ) -> Result<LmiSolution, ModelError> {
        if !matches!(self.mode, Mode::Margin { .. }) {
            return Err(ModelError::InvalidArgument(
                "solve_accepting needs a margin problem (Model::compile_feasibility)".into(),
            ));
        }
        self.solve_once(Some(accept))
    }

    fn solve_once<'f>(
        &mut self,
        mut accept: Option<&mut (dyn FnMut(&Iterate<'_>) -> bool + Send + 'f)>,
    ) -> Result<LmiSolution, ModelError> {
        self.refresh()?;
        let problem = self.problem.as_ref().expect("assembled");
        let reuse =
            matches!(&self.solver, Some((_, analysed)) if pattern_within(problem, analysed));
        if !reuse {
            let solver = Solver::new(problem, self.options.settings.clone())?;
            self.stats.analyses += 1;
            self.solver = Some((solver, problem.clone()));
        }
        let verified = accept.is_none()
            && matches!(
                self.mode,
                Mode::Margin {
                    stop_when_verified: true,
                    ..
                }
            );
        let mut sdp = self.run_solver(None, verified, accept.as_deref_mut())?;
        self.stats.solves += 1;
        if let Some(tight) = self.margin_refinement(&sdp) {
            let (solver, _) = self.solver.as_mut().expect("created above");
            solver.set_settings(tight)?;
            // The continuation consults the caller's test only (a margin that did not verify in
            // the first run is refined to its accuracy).
            let refined = self.run_solver(Some(&sdp.point()), false, accept);
            let (solver, _) = self.solver.as_mut().expect("created above");
            solver.set_settings(self.options.settings.clone())?;
            let refined = refined?;
            self.stats.refinements += 1;
            if matches!(refined.status, Status::Optimal | Status::Accepted) {
                let first = sdp.iterations;
                sdp = refined;
                sdp.iterations += first;
            }
        }
        solution::finish(self, sdp)
    }

    /// One run of the analysed solver on the assembled problem (from `start` when given),
    /// ending at the first iterate that verifies (`verified`) or that `accept` accepts, when
    /// either is asked for in a margin problem.
    fn run_solver<'f>(
        &mut self,
        start: Option<&crate::Point>,
        verified: bool,
        accept: Option<&mut (dyn FnMut(&Iterate<'_>) -> bool + Send + 'f)>,
    ) -> Result<crate::Solution, ModelError> {
        let (mut solver, analysed) = self.solver.take().expect("created above");
        let problem = self.problem.as_ref().expect("assembled");
        let sdp = match (self.t_col, verified || accept.is_some()) {
            (Some(t_col), true) => {
                let this = &*self;
                let mut never = |_: &Iterate<'_>| false;
                let accept = accept.unwrap_or(&mut never);
                solver.solve_until(problem, start, &mut |y, _| {
                    solution::accepted_iterate(this, y, t_col, verified, accept)
                })
            }
            _ => match start {
                Some(p) => solver.solve_from(problem, p),
                None => solver.solve(problem),
            },
        };
        self.solver = Some((solver, analysed));
        Ok(sdp?)
    }

    /// Tightened settings that bring a positive optimal margin to the relative accuracy
    /// [`FeasibilityOptions::margin_accuracy`], or `None` when `sdp` already meets it (or is not
    /// an optimal margin solve with `0 < t* < margin_cap`).
    ///
    /// `t*` lies between the two objectives up to the infeasibilities, so `|⟨C,X⟩ − bᵀy|` and
    /// `⟨X,S⟩` bound its error; both must be below `accuracy · t*`, i.e. the relative measures
    /// below `accuracy · t* / (1 + |⟨C,X⟩| + |bᵀy|)`, and the feasibility tolerance is tightened
    /// by the same factor.
    fn margin_refinement(&self, sdp: &crate::Solution) -> Option<Settings> {
        const FLOOR: f64 = 1e-14;
        let (Mode::Margin { cap, accuracy, .. }, Some(t_col)) = (&self.mode, self.t_col) else {
            return None;
        };
        let t = sdp.y[t_col];
        if sdp.status != Status::Optimal || !(t > 0.0 && t < *cap) {
            return None;
        }
        let s = &self.options.settings;
        let scale = 1.0 + sdp.primal_objective.abs() + sdp.dual_objective.abs();
        let need = (accuracy * t / scale).max(FLOOR);
        let achieved = sdp.measures.rel_gap.max(sdp.measures.dimacs[5].abs());
        if achieved <= need || need >= s.tol_gap {
            return None;
        }
        let factor = need / s.tol_gap;
        let mut tight = s.clone();
        tight.tol_gap = need;
        tight.tol_feas = (s.tol_feas * factor).max(FLOOR);
        Some(tight)
    }
}

/// Re-solves of [`Compiled::solve`] that may raise strict margins.
pub const MARGIN_ROUNDS: usize = 3;

/// A strict constraint that fails verification with tolerance `τ` is re-imposed with the
/// margin `STRICT_MARGIN_FACTOR · τ` ([`Compiled::solve`]): twice the tolerance, so that the
/// solver's own error (far below `τ`, which carries a safety factor) cannot bring it below `τ`.
pub const STRICT_MARGIN_FACTOR: f64 = 2.0;

/// The normalisation constraints `F ⪰ 0` (or entrywise `≥ 0`) of variable `v` as forms over the
/// original decision scalars, each with its bound.
fn normalisation_forms(
    model: u64,
    v: &super::model::VarInfo,
    n: Normalisation,
) -> Vec<(f64, Affine, bool)> {
    let x = Expr::of_var(model, v.kind, v.shape, v.offset, v.name.clone());
    let (r, c) = (v.shape.rows, v.shape.cols);
    if r == 0 || c == 0 {
        return Vec::new();
    }
    // (bound, form, is a matrix inequality)
    let exprs: Vec<(f64, Expr, bool)> = match (n, v.kind) {
        (Normalisation::Free, _) => Vec::new(),
        (Normalisation::Trace(t), _) => vec![(t, Expr::scalar(t) - x.trace(), false)],
        (Normalisation::Norm(rho), VarKind::Scalar) => vec![
            (rho, Expr::scalar(rho) - &x, false),
            (rho, Expr::scalar(rho) + &x, false),
        ],
        (Normalisation::Norm(rho), VarKind::Diagonal) => {
            // The diagonal as a column: diag(X)·𝟙.
            let d = &x * Expr::ones(r, 1);
            let ones = Expr::ones(r, 1) * rho;
            vec![(rho, &ones - &d, false), (rho, &ones + &d, false)]
        }
        (Normalisation::Norm(rho), VarKind::Symmetric) => {
            let i = Expr::identity(r) * rho;
            vec![(rho, &i - &x, true), (rho, &i + &x, true)]
        }
        (Normalisation::Norm(rho), VarKind::Full) => {
            let blk = Expr::sym_blocks(&[
                [Some(Expr::identity(r) * rho), None],
                [Some(x.t()), Some(Expr::identity(c) * rho)],
            ]);
            vec![(rho, blk, true)]
        }
    };
    exprs
        .into_iter()
        .filter_map(|(b, e, m)| match &e.node().ok()?.kind {
            super::expr::Kind::Folded(a) => Some((b, a.clone(), m)),
            _ => None,
        })
        .collect()
}

/// Whether a constant matrix form satisfies `F_0 + shift·I ⪰ 0`.
fn constant_psd(red: &Affine, shift: f64) -> Result<bool, ModelError> {
    let f = red.eval(&[]);
    let s = faer::Mat::from_fn(f.nrows(), f.ncols(), |i, j| {
        f[(i, j)] + if i == j { shift } else { 0.0 }
    });
    Ok(sporadic_linalg::min_eigenvalue(s.as_ref())? >= 0.0)
}

/// `s + shift·I` for an upper-triangle sparse matrix of order `n`.
fn add_diagonal(s: SparseSym, n: usize, shift: f64) -> SparseSym {
    let mut entries: Vec<(usize, usize, f64)> = s.iter().map(|(i, j, v)| (j, i, v)).collect();
    entries.extend((0..n).map(|i| (i, i, shift)));
    entries.sort_by_key(|&(j, i, _)| (j, i));
    let mut merged: Vec<(usize, usize, f64)> = Vec::with_capacity(entries.len());
    for (j, i, v) in entries {
        match merged.last_mut() {
            Some(last) if (last.0, last.1) == (j, i) => last.2 += v,
            _ => merged.push((j, i, v)),
        }
    }
    let mut out = SparseSym::default();
    for (j, i, v) in merged.into_iter().filter(|e| e.2 != 0.0) {
        out.rows.push(i);
        out.cols.push(j);
        out.vals.push(v);
    }
    out
}

/// How strictness enters one constraint: a shift of its constant term on the diagonal, and the
/// coefficient of the margin `t` in `F` (on the diagonal / in every row).
type Strictness = (f64, Option<f64>);

/// Appends one constraint form `F ⪰ 0` (`is_matrix`, order > 1: a PSD block with `C = F_0`,
/// `A_col = −F_col`) or `F ≥ 0` entrywise (LP rows, column-major). Constant LP rows that hold are
/// skipped.
fn push_form(
    red: &Affine,
    is_matrix: bool,
    (shift, t_coef): Strictness,
    col_of: &[usize],
    t_col: Option<usize>,
    lp: &mut LpRows,
    psd: &mut Vec<BlockData>,
) {
    if is_matrix && red.rows > 1 {
        let n = red.rows;
        let mut c = SparseSym::default();
        let mut a = Vec::new();
        for (slot, run) in slot_runs(&red.entries) {
            if slot == CONST {
                c = upper(run, 1.0);
            } else {
                a.push((col_of[slot as usize - 1], upper(run, -1.0)));
            }
        }
        if shift != 0.0 {
            c = add_diagonal(c, n, shift);
        }
        if let (Some(tc), Some(tcol)) = (t_coef, t_col) {
            let mut d = SparseSym::default();
            for i in 0..n {
                d.rows.push(i);
                d.cols.push(i);
                d.vals.push(-tc);
            }
            a.push((tcol, d));
        }
        psd.push(BlockData {
            block: Block {
                kind: BlockKind::Psd,
                size: n,
            },
            c,
            a,
        });
    } else {
        let npos = red.rows * red.cols;
        let mut cpos = vec![0.0; npos];
        let mut coefs: Vec<Vec<(usize, f64)>> = vec![Vec::new(); npos];
        for e in &red.entries {
            let p = e.col as usize * red.rows + e.row as usize;
            if e.slot == CONST {
                cpos[p] += e.val;
            } else {
                coefs[p].push((col_of[e.slot as usize - 1], e.val));
            }
        }
        for (p, mut co) in coefs.into_iter().enumerate() {
            if let (Some(tc), Some(tcol)) = (t_coef, t_col) {
                co.push((tcol, tc));
            }
            let c = cpos[p] + shift;
            if co.is_empty() && c >= 0.0 {
                continue;
            }
            lp.push_row(c, &co);
        }
    }
}
