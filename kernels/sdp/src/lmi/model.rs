//! The [`Model`]: decision variables, parameters, constraints and objective.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use faer::{Mat, MatRef};

use super::affine::{Affine, CONST};
use super::error::{ModelError, Shape};
use super::expr::{Expr, Kind, Node, Param, Var, VarKind};

// Finiteness of parameter data: the workspace's shared check; its `InputError` converts into
// `ModelError::Input`.
pub(crate) use sporadic_linalg::input::check_finite;

static NEXT_MODEL_ID: AtomicU64 = AtomicU64::new(1);

/// Relative asymmetry tolerated in a matrix inequality: every part `F_k` of the expression
/// (constant term and the coefficient of each decision scalar) must satisfy
/// `max |F_k − F_kᵀ| ≤ SYMMETRY_TOL · max |F_k|`; the symmetric part is then used.
pub const SYMMETRY_TOL: f64 = 1e-9;

/// What a constraint requires of its (oriented) expression `F`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ConstraintKind {
    /// `F ⪰ 0` or `F ≻ 0` for a symmetric `F` (a PSD block; 1×1 ones go to the LP block).
    Matrix,
    /// Every entry `≥ 0` (or `> 0`): rows of the LP block.
    Entrywise,
    /// Every entry `= 0`: eliminated before solving (see the module docs).
    Equality,
}

/// A constraint built by [`Expr::gt`], [`Expr::ge`], [`Expr::lt`], [`Expr::le`],
/// [`Expr::ge_entrywise`] (and friends) or [`Expr::equals`], not yet added to a model.
#[derive(Debug, Clone)]
pub struct Constraint {
    pub(crate) kind: ConstraintKind,
    pub(crate) strict: bool,
    /// Oriented: the requirement is `expr ⪰ 0` / `≻ 0` / `≥ 0` / `= 0`.
    pub(crate) expr: Expr,
    pub(crate) name: Option<String>,
}

impl Constraint {
    pub(crate) fn matrix(expr: Expr, strict: bool) -> Self {
        Self {
            kind: ConstraintKind::Matrix,
            strict,
            expr,
            name: None,
        }
    }
    pub(crate) fn entrywise(expr: Expr, strict: bool) -> Self {
        Self {
            kind: ConstraintKind::Entrywise,
            strict,
            expr,
            name: None,
        }
    }
    pub(crate) fn equality(expr: Expr) -> Self {
        Self {
            kind: ConstraintKind::Equality,
            strict: false,
            expr,
            name: None,
        }
    }

    /// Gives the constraint a name (used in reports and errors).
    pub fn named(mut self, name: impl Into<String>) -> Self {
        self.name = Some(name.into());
        self
    }

    /// Its kind.
    pub fn kind(&self) -> ConstraintKind {
        self.kind
    }

    /// Whether it is strict (`≻`, `≺`, `>`, `<`).
    pub fn is_strict(&self) -> bool {
        self.strict
    }

    /// The oriented expression `F` of the requirement `F ⪰ 0` (`≻ 0`, `≥ 0`, `= 0`).
    pub fn expr(&self) -> &Expr {
        &self.expr
    }
}

/// Handle of a constraint added to a model (its position in insertion order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ConstraintId(pub(crate) usize);

impl ConstraintId {
    /// Position of the constraint in the model (and in [`super::Verification::constraints`]).
    pub fn index(self) -> usize {
        self.0
    }
}

#[derive(Debug, Clone)]
pub(crate) struct VarInfo {
    pub name: Arc<str>,
    pub kind: VarKind,
    pub shape: Shape,
    pub offset: usize,
}

#[derive(Clone)]
pub(crate) struct ConstraintData {
    pub name: String,
    pub kind: ConstraintKind,
    pub strict: bool,
    pub node: Arc<Node>,
    /// Parameters the expression depends on (sorted, deduplicated).
    pub params: Vec<usize>,
}

/// Direction of the objective.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Sense {
    /// Minimise.
    Minimize,
    /// Maximise.
    Maximize,
}

#[derive(Clone)]
pub(crate) struct Objective {
    pub sense: Sense,
    pub node: Arc<Node>,
    pub params: Vec<usize>,
}

/// An LMI model: decision variables, parameters, constraints and an optional linear objective.
///
/// See the [module documentation](super) for a worked example.
#[derive(Clone)]
pub struct Model {
    pub(crate) id: u64,
    pub(crate) vars: Vec<VarInfo>,
    pub(crate) num_scalars: usize,
    /// Current parameter values.
    pub(crate) params: Vec<Mat<f64>>,
    pub(crate) constraints: Vec<ConstraintData>,
    pub(crate) objective: Option<Objective>,
}

impl Default for Model {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Model")
            .field("variables", &self.vars.len())
            .field("decision_scalars", &self.num_scalars)
            .field("parameters", &self.params.len())
            .field("constraints", &self.constraints.len())
            .field("objective", &self.objective.as_ref().map(|o| o.sense))
            .finish()
    }
}

impl Model {
    /// An empty model.
    pub fn new() -> Self {
        Self {
            id: NEXT_MODEL_ID.fetch_add(1, Ordering::Relaxed),
            vars: Vec::new(),
            num_scalars: 0,
            params: Vec::new(),
            constraints: Vec::new(),
            objective: None,
        }
    }

    fn add_var(&mut self, name: &str, kind: VarKind, rows: usize, cols: usize) -> Var {
        let shape = Shape::new(rows, cols);
        let name: Arc<str> = Arc::from(name);
        let too_big = rows > (u32::MAX / 4) as usize
            || cols > (u32::MAX / 4) as usize
            || kind
                .num_scalars(rows, cols)
                .checked_add(self.num_scalars)
                .is_none_or(|n| n > (u32::MAX / 2) as usize);
        let offset = self.num_scalars;
        let expr = if too_big {
            Expr {
                repr: Err(Arc::new(ModelError::InvalidArgument(format!(
                    "variable `{name}` of shape {shape} is too large"
                )))),
            }
        } else {
            self.num_scalars += kind.num_scalars(rows, cols);
            Expr::of_var(self.id, kind, shape, offset, name.clone())
        };
        self.vars.push(VarInfo {
            name: name.clone(),
            kind,
            shape,
            offset,
        });
        Var {
            model: self.id,
            index: self.vars.len() - 1,
            kind,
            shape,
            offset,
            name,
            expr,
        }
    }

    /// A scalar decision variable (YALMIP: `sdpvar(1)`).
    pub fn scalar(&mut self, name: &str) -> Var {
        self.add_var(name, VarKind::Scalar, 1, 1)
    }

    /// A symmetric `n × n` decision matrix, `n(n+1)/2` scalars (YALMIP: `sdpvar(n)`).
    pub fn symmetric(&mut self, name: &str, n: usize) -> Var {
        self.add_var(name, VarKind::Symmetric, n, n)
    }

    /// An unstructured `rows × cols` decision matrix (YALMIP: `sdpvar(r, c, 'full')`).
    pub fn full(&mut self, name: &str, rows: usize, cols: usize) -> Var {
        self.add_var(name, VarKind::Full, rows, cols)
    }

    /// A diagonal `n × n` decision matrix, `n` scalars (YALMIP: `diag(sdpvar(n, 1))`).
    pub fn diagonal(&mut self, name: &str, n: usize) -> Var {
        self.add_var(name, VarKind::Diagonal, n, n)
    }

    /// A parameter: a constant matrix that may be reset after compilation
    /// ([`super::Compiled::set_param`]).
    pub fn param(&mut self, name: &str, value: MatRef<'_, f64>) -> Result<Param, ModelError> {
        check_finite(value, &format!("parameter `{name}`"))?;
        let shape = Shape::new(value.nrows(), value.ncols());
        let name: Arc<str> = Arc::from(name);
        self.params.push(value.to_owned());
        let index = self.params.len() - 1;
        let expr = Expr::from_parts(
            shape,
            Some(self.id),
            name.clone(),
            Kind::Param(index),
            false,
        );
        Ok(Param {
            model: self.id,
            index,
            shape,
            name,
            expr,
        })
    }

    /// Adds a constraint (YALMIP: `F = [F, constraint]`).
    ///
    /// Checks that the expression is valid, belongs to this model, is not empty, and — for a
    /// matrix inequality — is square and symmetric (structurally and numerically, within
    /// [`SYMMETRY_TOL`]); parameter-dependent expressions are re-checked at every evaluation.
    pub fn constrain(&mut self, c: Constraint) -> Result<ConstraintId, ModelError> {
        let data = self.validate(c)?;
        self.constraints.push(data);
        Ok(ConstraintId(self.constraints.len() - 1))
    }

    /// Sets the objective `min f` (YALMIP: `optimize(F, f)`); `f` must be 1×1.
    pub fn minimize(&mut self, f: impl Into<Expr>) -> Result<(), ModelError> {
        self.set_objective(Sense::Minimize, f.into())
    }

    /// Sets the objective `max f`; `f` must be 1×1.
    pub fn maximize(&mut self, f: impl Into<Expr>) -> Result<(), ModelError> {
        self.set_objective(Sense::Maximize, f.into())
    }

    /// Removes the objective (pure feasibility problem).
    pub fn clear_objective(&mut self) {
        self.objective = None;
    }

    /// Number of decision scalars.
    pub fn num_scalars(&self) -> usize {
        self.num_scalars
    }

    /// Number of constraints.
    pub fn num_constraints(&self) -> usize {
        self.constraints.len()
    }

    fn set_objective(&mut self, sense: Sense, f: Expr) -> Result<(), ModelError> {
        let n = f.node()?;
        self.check_owner(n, "the objective")?;
        if n.shape != Shape::new(1, 1) {
            return Err(ModelError::ObjectiveNotScalar { shape: n.shape });
        }
        self.objective = Some(Objective {
            sense,
            node: n.clone(),
            params: params_of(n),
        });
        Ok(())
    }

    pub(crate) fn check_owner(&self, n: &Node, what: &str) -> Result<(), ModelError> {
        match n.model {
            Some(m) if m != self.id => Err(ModelError::ForeignModel { what: what.into() }),
            _ => Ok(()),
        }
    }

    pub(crate) fn validate(&self, c: Constraint) -> Result<ConstraintData, ModelError> {
        let kind_name = match (c.kind, c.strict) {
            (ConstraintKind::Matrix, true) => "strict matrix inequality",
            (ConstraintKind::Matrix, false) => "matrix inequality",
            (ConstraintKind::Entrywise, true) => "strict entrywise inequality",
            (ConstraintKind::Entrywise, false) => "entrywise inequality",
            (ConstraintKind::Equality, _) => "equality",
        };
        let name = c
            .name
            .clone()
            .unwrap_or_else(|| format!("#{} ({kind_name})", self.constraints.len()));
        let n = c.expr.node()?;
        self.check_owner(n, &format!("constraint `{name}`"))?;
        if n.shape.rows == 0 || n.shape.cols == 0 {
            return Err(ModelError::Empty {
                what: format!("constraint `{name}` has an empty ({}) expression", n.shape),
            });
        }
        if c.kind == ConstraintKind::Matrix && n.shape.rows != n.shape.cols {
            return Err(ModelError::NotSquare {
                what: format!("the expression of matrix inequality `{name}`"),
                shape: n.shape,
            });
        }
        let data = ConstraintData {
            name,
            kind: c.kind,
            strict: c.strict,
            node: n.clone(),
            params: params_of(n),
        };
        if let Kind::Folded(a) = &n.kind {
            self.check_evaluated(&data, a)?;
        }
        Ok(data)
    }

    /// Checks an evaluated constraint expression: finite, and symmetric for matrix inequalities.
    pub(crate) fn check_evaluated(&self, c: &ConstraintData, a: &Affine) -> Result<(), ModelError> {
        if let Some(e) = a.first_non_finite() {
            return Err(ModelError::NonFinite {
                what: format!(
                    "constraint `{}`, {}, entry ({},{})",
                    c.name,
                    self.part_name(e.slot),
                    e.row,
                    e.col
                ),
                value: e.val,
            });
        }
        if c.kind == ConstraintKind::Matrix
            && let Some((slot, row, col, asym, scale)) = a.worst_asymmetry()
            && asym > SYMMETRY_TOL * scale
        {
            return Err(ModelError::NonSymmetric {
                constraint: c.name.clone(),
                part: self.part_name(slot),
                row,
                col,
                asymmetry: asym,
                scale,
            });
        }
        Ok(())
    }

    /// `"the constant term"` or `"the coefficient of `P[0,1]`"`.
    pub(crate) fn part_name(&self, slot: u32) -> String {
        if slot == CONST {
            "the constant term".into()
        } else {
            format!(
                "the coefficient of `{}`",
                self.scalar_name(slot as usize - 1)
            )
        }
    }

    /// Human-readable name of decision scalar `k`, e.g. `P[0,1]`.
    pub(crate) fn scalar_name(&self, k: usize) -> String {
        let idx = self
            .vars
            .partition_point(|v| v.offset <= k)
            .saturating_sub(1);
        match self.vars.get(idx) {
            Some(v) => {
                if v.kind == VarKind::Scalar {
                    v.name.to_string()
                } else {
                    let (i, j) = v.kind.position(v.shape.rows, k - v.offset);
                    format!("{}[{i},{j}]", v.name)
                }
            }
            None => format!("y[{k}]"),
        }
    }
}

pub(crate) fn params_of(n: &Node) -> Vec<usize> {
    let mut p = Vec::new();
    n.collect_params(&mut p);
    p.sort_unstable();
    p.dedup();
    p
}
