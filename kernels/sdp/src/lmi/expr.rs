//! Affine matrix expressions in the decision variables: [`Expr`], [`Var`], [`Param`].
//!
//! An expression is either *folded* — a sparse [`Affine`] form, computed eagerly — or, when it
//! involves a [`Param`] (a constant whose value can be reset after compilation), a small tree of
//! operations whose leaves are folded forms and parameters. Every sub-expression without a
//! parameter is folded as soon as it is built, so the tree only keeps the parameter-dependent
//! spine, and re-evaluating it after a parameter update is as cheap as building it once.

use std::borrow::Cow;
use std::fmt;
use std::ops::{Add, Div, Mul, Neg, Sub};
use std::sync::Arc;

use faer::{Mat, MatRef};

use super::affine::{Affine, Entry};
use super::error::{ModelError, Shape};

/// Kind (structure) of a matrix decision variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum VarKind {
    /// A 1×1 scalar.
    Scalar,
    /// A symmetric `n × n` matrix: `n(n+1)/2` scalars (upper triangle, column by column).
    Symmetric,
    /// An unstructured `rows × cols` matrix: `rows·cols` scalars (column-major).
    Full,
    /// A diagonal `n × n` matrix: `n` scalars.
    Diagonal,
}

impl VarKind {
    /// Number of decision scalars of a variable of this kind and shape.
    pub(crate) fn num_scalars(self, rows: usize, cols: usize) -> usize {
        match self {
            VarKind::Scalar => 1,
            VarKind::Symmetric => rows * (rows + 1) / 2,
            VarKind::Full => rows * cols,
            VarKind::Diagonal => rows,
        }
    }

    /// Position `(row, col)` of local scalar `k` (the upper-triangle one for symmetric).
    pub(crate) fn position(self, rows: usize, k: usize) -> (usize, usize) {
        match self {
            VarKind::Scalar => (0, 0),
            VarKind::Symmetric => {
                // k = j(j+1)/2 + i, i ≤ j.
                let mut j = 0;
                while (j + 1) * (j + 2) / 2 <= k {
                    j += 1;
                }
                (k - j * (j + 1) / 2, j)
            }
            VarKind::Full => (k % rows, k / rows),
            VarKind::Diagonal => (k, k),
        }
    }
}

/// A matrix decision variable of a [`Model`](super::Model).
///
/// Cheap to clone; use it wherever an expression is expected (`&p + &q`, `a.t() * &p`,
/// [`Var::expr`]). Its value in a solution is read with
/// [`LmiSolution::value`](super::LmiSolution::value).
#[derive(Clone)]
pub struct Var {
    pub(crate) model: u64,
    pub(crate) index: usize,
    pub(crate) kind: VarKind,
    pub(crate) shape: Shape,
    /// First decision scalar.
    pub(crate) offset: usize,
    pub(crate) name: Arc<str>,
    pub(crate) expr: Expr,
}

impl fmt::Debug for Var {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Var({} {:?} {})", self.name, self.kind, self.shape)
    }
}

impl std::ops::Deref for Var {
    type Target = Expr;
    fn deref(&self) -> &Expr {
        &self.expr
    }
}

impl Var {
    /// The variable as an expression.
    pub fn expr(&self) -> Expr {
        self.expr.clone()
    }
    /// Its name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Its kind.
    pub fn kind(&self) -> VarKind {
        self.kind
    }
    /// Its shape.
    pub fn shape(&self) -> Shape {
        self.shape
    }
    /// Number of decision scalars it contributes.
    pub fn num_scalars(&self) -> usize {
        self.kind.num_scalars(self.shape.rows, self.shape.cols)
    }
}

/// A named constant matrix whose value can be reset after compilation
/// ([`Compiled::set_param`](super::Compiled::set_param)) without rebuilding the model.
///
/// Use it like a constant matrix in expressions (`p.t() * &x * &p`); the expressions that depend
/// on it are re-evaluated on every update.
#[derive(Clone)]
pub struct Param {
    pub(crate) model: u64,
    pub(crate) index: usize,
    pub(crate) shape: Shape,
    pub(crate) name: Arc<str>,
    pub(crate) expr: Expr,
}

impl fmt::Debug for Param {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Param({} {})", self.name, self.shape)
    }
}

impl std::ops::Deref for Param {
    type Target = Expr;
    fn deref(&self) -> &Expr {
        &self.expr
    }
}

impl Param {
    /// The parameter as an expression.
    pub fn expr(&self) -> Expr {
        self.expr.clone()
    }
    /// Its name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Its shape.
    pub fn shape(&self) -> Shape {
        self.shape
    }
}

/// One node of an expression.
pub(crate) struct Node {
    pub shape: Shape,
    /// Owning model (`None` for pure constants).
    pub model: Option<u64>,
    /// Whether decision variables occur.
    pub has_vars: bool,
    /// Short description for error messages (variable/parameter name).
    pub label: Option<Arc<str>>,
    pub kind: Kind,
}

pub(crate) enum Kind {
    /// Parameter-free, folded.
    Folded(Affine),
    /// A parameter leaf.
    Param(usize),
    /// `α a + β b`.
    LinComb(Arc<Node>, f64, Arc<Node>, f64),
    /// `s · a`.
    Scale(f64, Arc<Node>),
    /// Matrix product (one factor is variable-free).
    Mul(Arc<Node>, Arc<Node>),
    /// Kronecker product (one factor is variable-free).
    Kron(Arc<Node>, Arc<Node>),
    Transpose(Arc<Node>),
    Trace(Arc<Node>),
    Sub(Arc<Node>, usize, usize),
    Blocks {
        heights: Vec<usize>,
        widths: Vec<usize>,
        cells: Vec<Option<Arc<Node>>>,
    },
}

impl Node {
    fn folded(&self) -> Option<&Affine> {
        match &self.kind {
            Kind::Folded(a) => Some(a),
            _ => None,
        }
    }

    fn describe(&self) -> String {
        match &self.label {
            Some(l) => format!("`{l}`"),
            None => "expression".into(),
        }
    }

    /// Evaluates with the given parameter values.
    pub(crate) fn eval<'a>(&'a self, params: &[Mat<f64>]) -> Cow<'a, Affine> {
        match &self.kind {
            Kind::Folded(a) => Cow::Borrowed(a),
            Kind::Param(i) => Cow::Owned(
                Affine::from_dense(params[*i].as_ref())
                    .expect("parameter values are checked finite"),
            ),
            Kind::LinComb(a, al, b, be) => {
                Cow::Owned(a.eval(params).lin_comb(*al, &b.eval(params), *be))
            }
            Kind::Scale(s, a) => Cow::Owned(a.eval(params).scale(*s)),
            Kind::Mul(a, b) => Cow::Owned(product(&a.eval(params), a.has_vars, &b.eval(params))),
            Kind::Kron(a, b) => Cow::Owned(Affine::kron(&a.eval(params), &b.eval(params))),
            Kind::Transpose(a) => Cow::Owned(a.eval(params).transpose()),
            Kind::Trace(a) => Cow::Owned(a.eval(params).trace()),
            Kind::Sub(a, r0, c0) => {
                Cow::Owned(
                    a.eval(params)
                        .submatrix(*r0, *c0, self.shape.rows, self.shape.cols),
                )
            }
            Kind::Blocks {
                heights,
                widths,
                cells,
            } => {
                let vals: Vec<Option<Cow<'_, Affine>>> = cells
                    .iter()
                    .map(|c| c.as_ref().map(|n| n.eval(params)))
                    .collect();
                let refs: Vec<Option<&Affine>> = vals.iter().map(|c| c.as_deref()).collect();
                Cow::Owned(Affine::blocks(heights, widths, &refs))
            }
        }
    }

    /// Indices of the parameters this expression depends on (with repetitions).
    pub(crate) fn collect_params(&self, out: &mut Vec<usize>) {
        match &self.kind {
            Kind::Folded(_) => {}
            Kind::Param(i) => out.push(*i),
            Kind::LinComb(a, _, b, _) | Kind::Mul(a, b) | Kind::Kron(a, b) => {
                a.collect_params(out);
                b.collect_params(out);
            }
            Kind::Scale(_, a) | Kind::Transpose(a) | Kind::Trace(a) | Kind::Sub(a, ..) => {
                a.collect_params(out)
            }
            Kind::Blocks { cells, .. } => {
                cells.iter().flatten().for_each(|c| c.collect_params(out))
            }
        }
    }
}

/// `a · b` where `a` (if `a_has_vars`) or else `b` may contain variables; a 1×1 factor scales.
fn product(a: &Affine, a_has_vars: bool, b: &Affine) -> Affine {
    if (a.rows, a.cols) == (1, 1) || (b.rows, b.cols) == (1, 1) {
        return Affine::kron(a, b);
    }
    if a_has_vars {
        Affine::right_mul_const(a, b)
    } else {
        Affine::left_mul_const(a, b)
    }
}

/// An affine matrix expression in the decision variables of one [`Model`](super::Model).
///
/// Build it from [`Var`]s, [`Param`]s and constants (`faer` matrices, `f64`) with `+`, `-`, `*`
/// (matrix product, or scaling when one factor is 1×1), unary `-`, `/ f64`, and the methods below.
/// Operations never panic: an invalid one (shape mismatch, product of two variable expressions,
/// NaN data, mixing models) produces an expression that carries a [`ModelError`], reported by the
/// first fallible call that uses it ([`Expr::check`], [`Model::constrain`](super::Model::constrain)).
#[derive(Clone)]
pub struct Expr {
    pub(crate) repr: Result<Arc<Node>, Arc<ModelError>>,
}

impl fmt::Debug for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.repr {
            Ok(n) => {
                let what = match &n.kind {
                    Kind::Folded(a) => format!("{} stored entries", a.entries.len()),
                    _ => "parameter-dependent".into(),
                };
                write!(f, "Expr({}, {what})", n.shape)
            }
            Err(e) => write!(f, "Expr(error: {e})"),
        }
    }
}

fn err(e: ModelError) -> Expr {
    Expr {
        repr: Err(Arc::new(e)),
    }
}

fn node(shape: Shape, model: Option<u64>, has_vars: bool, kind: Kind) -> Expr {
    Expr {
        repr: Ok(Arc::new(Node {
            shape,
            model,
            has_vars,
            label: None,
            kind,
        })),
    }
}

fn folded(shape: Shape, model: Option<u64>, a: Affine) -> Expr {
    debug_assert_eq!((a.rows, a.cols), (shape.rows, shape.cols));
    if let Some(e) = a.first_non_finite() {
        return err(ModelError::NonFinite {
            what: format!("an expression entry ({},{}) (overflow)", e.row, e.col),
            value: e.val,
        });
    }
    let has_vars = !a.is_constant();
    node(shape, model, has_vars, Kind::Folded(a))
}

/// Common model of two operands, or the foreign-model error.
fn join_model(op: &str, a: &Node, b: &Node) -> Result<Option<u64>, ModelError> {
    match (a.model, b.model) {
        (Some(x), Some(y)) if x != y => Err(ModelError::ForeignModel {
            what: format!("an operand of {op} ({} or {})", a.describe(), b.describe()),
        }),
        (x, y) => Ok(x.or(y)),
    }
}

fn mismatch(op: &str, a: &Node, b: &Node) -> ModelError {
    ModelError::DimensionMismatch {
        op: op.to_string(),
        left: format!("the left operand ({})", a.describe()),
        left_shape: a.shape,
        right: format!("the right operand ({})", b.describe()),
        right_shape: b.shape,
    }
}

/// Largest dimension an expression may have (indices are stored as `u32`).
const MAX_DIM: usize = (u32::MAX / 2) as usize;

impl Expr {
    /// The node, or the carried error.
    pub(crate) fn node(&self) -> Result<&Arc<Node>, ModelError> {
        self.repr.as_ref().map_err(|e| (**e).clone())
    }

    /// Returns the error carried by this expression, if any.
    pub fn check(&self) -> Result<(), ModelError> {
        self.node().map(|_| ())
    }

    /// Its shape (or the carried error).
    pub fn shape(&self) -> Result<Shape, ModelError> {
        self.node().map(|n| n.shape)
    }

    /// Whether the expression depends on a [`Param`].
    pub fn has_params(&self) -> bool {
        matches!(&self.repr, Ok(n) if n.folded().is_none())
    }

    /// A constant matrix (NaN/∞ entries give an error-carrying expression).
    pub fn constant(m: MatRef<'_, f64>) -> Expr {
        if m.nrows() > MAX_DIM || m.ncols() > MAX_DIM {
            return err(ModelError::InvalidArgument(format!(
                "matrix of shape {}×{} is too large",
                m.nrows(),
                m.ncols()
            )));
        }
        match Affine::from_dense(m) {
            Ok(a) => folded(Shape::new(m.nrows(), m.ncols()), None, a),
            Err((i, j, v)) => err(ModelError::NonFinite {
                what: format!("constant matrix entry ({i},{j})"),
                value: v,
            }),
        }
    }

    /// The 1×1 constant `c`.
    pub fn scalar(c: f64) -> Expr {
        Expr::constant(faer::mat![[c]].as_ref())
    }

    /// The identity `I_n`.
    pub fn identity(n: usize) -> Expr {
        if n > MAX_DIM {
            return err(ModelError::InvalidArgument(format!(
                "identity of order {n} is too large"
            )));
        }
        folded(Shape::new(n, n), None, Affine::scaled_identity(n, 1.0))
    }

    /// The `rows × cols` zero matrix.
    pub fn zeros(rows: usize, cols: usize) -> Expr {
        if rows > MAX_DIM || cols > MAX_DIM {
            return err(ModelError::InvalidArgument(format!(
                "zero matrix of shape {rows}×{cols} is too large"
            )));
        }
        folded(Shape::new(rows, cols), None, Affine::zeros(rows, cols))
    }

    /// The `rows × cols` all-ones matrix.
    pub fn ones(rows: usize, cols: usize) -> Expr {
        Expr::constant(Mat::<f64>::ones(rows, cols).as_ref())
    }

    pub(crate) fn from_parts(
        shape: Shape,
        model: Option<u64>,
        label: Arc<str>,
        kind: Kind,
        has_vars: bool,
    ) -> Expr {
        Expr {
            repr: Ok(Arc::new(Node {
                shape,
                model,
                has_vars,
                label: Some(label),
                kind,
            })),
        }
    }

    /// A variable's expression: the coefficient of its local scalar `k` is `E_ij` (plus `E_ji` for
    /// an off-diagonal entry of a symmetric variable).
    pub(crate) fn of_var(
        model: u64,
        kind: VarKind,
        shape: Shape,
        offset: usize,
        name: Arc<str>,
    ) -> Expr {
        let n = kind.num_scalars(shape.rows, shape.cols);
        let mut entries = Vec::with_capacity(2 * n);
        for k in 0..n {
            let (i, j) = kind.position(shape.rows, k);
            let slot = (offset + k + 1) as u32;
            entries.push(Entry {
                slot,
                col: j as u32,
                row: i as u32,
                val: 1.0,
            });
            if kind == VarKind::Symmetric && i != j {
                entries.push(Entry {
                    slot,
                    col: i as u32,
                    row: j as u32,
                    val: 1.0,
                });
            }
        }
        let a = Affine::from_entries(shape.rows, shape.cols, entries);
        Expr::from_parts(shape, Some(model), name, Kind::Folded(a), n > 0)
    }

    fn lin_comb(a: &Expr, alpha: f64, b: &Expr, beta: f64, op: &str) -> Expr {
        let (x, y) = match (a.node(), b.node()) {
            (Ok(x), Ok(y)) => (x, y),
            (Err(e), _) | (_, Err(e)) => return err(e),
        };
        if x.shape != y.shape {
            return err(mismatch(op, x, y));
        }
        let model = match join_model(op, x, y) {
            Ok(m) => m,
            Err(e) => return err(e),
        };
        match (x.folded(), y.folded()) {
            (Some(p), Some(q)) => folded(x.shape, model, p.lin_comb(alpha, q, beta)),
            _ => node(
                x.shape,
                model,
                x.has_vars || y.has_vars,
                Kind::LinComb(x.clone(), alpha, y.clone(), beta),
            ),
        }
    }

    fn scaled(&self, s: f64) -> Expr {
        if !s.is_finite() {
            return err(ModelError::NonFinite {
                what: "a scalar factor".into(),
                value: s,
            });
        }
        match self.node() {
            Ok(x) => match x.folded() {
                Some(p) => folded(x.shape, x.model, p.scale(s)),
                None => node(x.shape, x.model, x.has_vars, Kind::Scale(s, x.clone())),
            },
            Err(e) => err(e),
        }
    }

    /// Matrix product; a 1×1 factor scales the other one (as in MATLAB/YALMIP).
    pub fn matmul(&self, rhs: &Expr) -> Expr {
        let (x, y) = match (self.node(), rhs.node()) {
            (Ok(x), Ok(y)) => (x, y),
            (Err(e), _) | (_, Err(e)) => return err(e),
        };
        let scalar = x.shape == Shape::new(1, 1) || y.shape == Shape::new(1, 1);
        let op = if scalar {
            "scalar product"
        } else {
            "matrix product"
        };
        if !scalar && x.shape.cols != y.shape.rows {
            return err(mismatch(op, x, y));
        }
        if x.has_vars && y.has_vars {
            return err(ModelError::NotAffine {
                op: format!("{op} of {} and {}", x.describe(), y.describe()),
            });
        }
        let model = match join_model(op, x, y) {
            Ok(m) => m,
            Err(e) => return err(e),
        };
        let shape = if scalar {
            Shape::new(x.shape.rows * y.shape.rows, x.shape.cols * y.shape.cols)
        } else {
            Shape::new(x.shape.rows, y.shape.cols)
        };
        match (x.folded(), y.folded()) {
            (Some(p), Some(q)) => folded(shape, model, product(p, x.has_vars, q)),
            _ => node(
                shape,
                model,
                x.has_vars || y.has_vars,
                Kind::Mul(x.clone(), y.clone()),
            ),
        }
    }

    /// Kronecker product `a ⊗ b` (one factor must be free of decision variables).
    pub fn kron(a: impl Into<Expr>, b: impl Into<Expr>) -> Expr {
        let (a, b) = (a.into(), b.into());
        let (x, y) = match (a.node(), b.node()) {
            (Ok(x), Ok(y)) => (x, y),
            (Err(e), _) | (_, Err(e)) => return err(e),
        };
        if x.has_vars && y.has_vars {
            return err(ModelError::NotAffine {
                op: format!("Kronecker product of {} and {}", x.describe(), y.describe()),
            });
        }
        let model = match join_model("Kronecker product", x, y) {
            Ok(m) => m,
            Err(e) => return err(e),
        };
        let (rows, cols) = (x.shape.rows * y.shape.rows, x.shape.cols * y.shape.cols);
        if rows > MAX_DIM || cols > MAX_DIM {
            return err(ModelError::InvalidArgument(format!(
                "Kronecker product of shape {rows}×{cols} is too large"
            )));
        }
        let shape = Shape::new(rows, cols);
        match (x.folded(), y.folded()) {
            (Some(p), Some(q)) => folded(shape, model, Affine::kron(p, q)),
            _ => node(
                shape,
                model,
                x.has_vars || y.has_vars,
                Kind::Kron(x.clone(), y.clone()),
            ),
        }
    }

    /// Transpose `Xᵀ`.
    pub fn t(&self) -> Expr {
        let x = match self.node() {
            Ok(x) => x,
            Err(e) => return err(e),
        };
        let shape = Shape::new(x.shape.cols, x.shape.rows);
        match x.folded() {
            Some(p) => folded(shape, x.model, p.transpose()),
            None => node(shape, x.model, x.has_vars, Kind::Transpose(x.clone())),
        }
    }

    /// `He(X) = X + Xᵀ` (X square).
    pub fn he(&self) -> Expr {
        match self.node() {
            Ok(x) if x.shape.rows != x.shape.cols => err(ModelError::NotSquare {
                what: format!("the argument of He(·) ({})", x.describe()),
                shape: x.shape,
            }),
            Ok(_) => Expr::lin_comb(self, 1.0, &self.t(), 1.0, "He(·)"),
            Err(e) => err(e),
        }
    }

    /// Trace (X square), a 1×1 expression.
    pub fn trace(&self) -> Expr {
        let x = match self.node() {
            Ok(x) => x,
            Err(e) => return err(e),
        };
        if x.shape.rows != x.shape.cols {
            return err(ModelError::NotSquare {
                what: format!("the argument of trace ({})", x.describe()),
                shape: x.shape,
            });
        }
        let shape = Shape::new(1, 1);
        match x.folded() {
            Some(p) => folded(shape, x.model, p.trace()),
            None => node(shape, x.model, x.has_vars, Kind::Trace(x.clone())),
        }
    }

    /// The `nr × nc` sub-block starting at `(r0, c0)`.
    pub fn submatrix(&self, r0: usize, c0: usize, nr: usize, nc: usize) -> Expr {
        let x = match self.node() {
            Ok(x) => x,
            Err(e) => return err(e),
        };
        if r0.checked_add(nr).is_none_or(|r| r > x.shape.rows)
            || c0.checked_add(nc).is_none_or(|c| c > x.shape.cols)
        {
            return err(ModelError::Empty {
                what: format!(
                    "sub-block {nr}×{nc} at ({r0},{c0}) lies outside {} of shape {}",
                    x.describe(),
                    x.shape
                ),
            });
        }
        let shape = Shape::new(nr, nc);
        match x.folded() {
            Some(p) => folded(shape, x.model, p.submatrix(r0, c0, nr, nc)),
            None => node(shape, x.model, x.has_vars, Kind::Sub(x.clone(), r0, c0)),
        }
    }

    /// Entry `(i, j)` as a 1×1 expression.
    pub fn get(&self, i: usize, j: usize) -> Expr {
        self.submatrix(i, j, 1, 1)
    }

    /// Block matrix from rows of cells; `None` is a zero block whose size is taken from the
    /// other blocks of its block row and block column.
    ///
    /// ```
    /// # use sporadic_sdp::lmi::{Expr, Model};
    /// let mut m = Model::new();
    /// let x = m.full("X", 2, 3);
    /// let b = Expr::blocks(&[[Some(x.expr()), None], [None, Some(Expr::identity(1))]]);
    /// assert_eq!(b.shape().unwrap().to_string(), "3×4");
    /// ```
    pub fn blocks<R: AsRef<[Option<Expr>]>>(rows: &[R]) -> Expr {
        let grid: Vec<Vec<Option<Expr>>> = rows.iter().map(|r| r.as_ref().to_vec()).collect();
        Expr::assemble(grid, false)
    }

    /// Symmetric block matrix with ⋆ completion: give the blocks on and below the diagonal;
    /// a `None` above the diagonal is the transpose of its mirror block (as the ⋆ of the papers).
    /// A `None` on the diagonal, or a `None` whose mirror is also `None`, is a zero block.
    ///
    /// ```
    /// # use sporadic_sdp::lmi::{Expr, Model};
    /// let mut m = Model::new();
    /// let p = m.symmetric("P", 2);
    /// let f = m.full("F", 2, 2);
    /// // [ -He(F)  ⋆ ]
    /// // [   F    -P ]
    /// let phi = Expr::sym_blocks(&[[Some(-f.expr().he()), None], [Some(f.expr()), Some(-&p)]]);
    /// assert_eq!(phi.shape().unwrap().to_string(), "4×4");
    /// ```
    pub fn sym_blocks<R: AsRef<[Option<Expr>]>>(rows: &[R]) -> Expr {
        let mut grid: Vec<Vec<Option<Expr>>> = rows.iter().map(|r| r.as_ref().to_vec()).collect();
        let n = grid.len();
        if let Some((i, r)) = grid.iter().enumerate().find(|(_, r)| r.len() != n) {
            return err(ModelError::DimensionMismatch {
                op: "sym_blocks (the block layout must be square)".into(),
                left: "the number of block rows".into(),
                left_shape: Shape::new(n, 1),
                right: format!("the number of cells in block row {i}"),
                right_shape: Shape::new(r.len(), 1),
            });
        }
        for i in 0..n {
            for j in 0..n {
                if i != j
                    && grid[i][j].is_none()
                    && let Some(m) = grid[j][i].clone()
                {
                    grid[i][j] = Some(m.t());
                }
            }
        }
        Expr::assemble(grid, true)
    }

    /// Block-diagonal matrix `diag(X_1, …, X_k)`.
    pub fn block_diag(blocks: &[Expr]) -> Expr {
        let k = blocks.len();
        let grid: Vec<Vec<Option<Expr>>> = (0..k)
            .map(|i| {
                (0..k)
                    .map(|j| (i == j).then(|| blocks[i].clone()))
                    .collect()
            })
            .collect();
        Expr::assemble(grid, false)
    }

    fn assemble(grid: Vec<Vec<Option<Expr>>>, square_layout: bool) -> Expr {
        let nr = grid.len();
        let nc = grid.first().map_or(0, |r| r.len());
        if nr == 0 || nc == 0 {
            return err(ModelError::Empty {
                what: "a block matrix needs at least one block".into(),
            });
        }
        if let Some((i, r)) = grid.iter().enumerate().find(|(_, r)| r.len() != nc) {
            return err(ModelError::DimensionMismatch {
                op: "block matrix layout".into(),
                left: "block row 0".into(),
                left_shape: Shape::new(1, nc),
                right: format!("block row {i}"),
                right_shape: Shape::new(1, r.len()),
            });
        }
        let mut heights: Vec<Option<(usize, usize)>> = vec![None; nr]; // (size, from column)
        let mut widths: Vec<Option<(usize, usize)>> = vec![None; nc];
        let mut nodes: Vec<Option<Arc<Node>>> = Vec::with_capacity(nr * nc);
        let mut model = None;
        for (i, row) in grid.iter().enumerate() {
            for (j, cell) in row.iter().enumerate() {
                let Some(cell) = cell else {
                    nodes.push(None);
                    continue;
                };
                let x = match cell.node() {
                    Ok(x) => x,
                    Err(e) => return err(e),
                };
                match (model, x.model) {
                    (Some(a), Some(b)) if a != b => {
                        return err(ModelError::ForeignModel {
                            what: format!("block ({i},{j}) ({})", x.describe()),
                        });
                    }
                    (None, m) => model = m,
                    _ => {}
                }
                match heights[i] {
                    Some((h, j0)) if h != x.shape.rows => {
                        return err(ModelError::DimensionMismatch {
                            op: format!(
                                "block row {i} (all blocks of a block row need equal heights)"
                            ),
                            left: format!("block ({i},{j0})"),
                            left_shape: grid[i][j0]
                                .as_ref()
                                .and_then(|c| c.shape().ok())
                                .unwrap_or(Shape::new(h, 0)),
                            right: format!("block ({i},{j}) ({})", x.describe()),
                            right_shape: x.shape,
                        });
                    }
                    None => heights[i] = Some((x.shape.rows, j)),
                    _ => {}
                }
                match widths[j] {
                    Some((w, i0)) if w != x.shape.cols => {
                        return err(ModelError::DimensionMismatch {
                            op: format!(
                                "block column {j} (all blocks of a block column need equal widths)"
                            ),
                            left: format!("block ({i0},{j})"),
                            left_shape: grid[i0][j]
                                .as_ref()
                                .and_then(|c| c.shape().ok())
                                .unwrap_or(Shape::new(0, w)),
                            right: format!("block ({i},{j}) ({})", x.describe()),
                            right_shape: x.shape,
                        });
                    }
                    None => widths[j] = Some((x.shape.cols, i)),
                    _ => {}
                }
                nodes.push(Some(x.clone()));
            }
        }
        if square_layout {
            for i in 0..nr {
                match (heights[i], widths[i]) {
                    (Some((h, _)), Some((w, _))) if h != w => {
                        return err(ModelError::NotSquare {
                            what: format!("diagonal block ({i},{i}) of a symmetric block matrix"),
                            shape: Shape::new(h, w),
                        });
                    }
                    (Some(h), None) => widths[i] = Some(h),
                    (None, Some(w)) => heights[i] = Some(w),
                    _ => {}
                }
            }
        }
        let heights: Option<Vec<usize>> = heights.iter().map(|h| h.map(|x| x.0)).collect();
        let widths: Option<Vec<usize>> = widths.iter().map(|w| w.map(|x| x.0)).collect();
        let (Some(heights), Some(widths)) = (heights, widths) else {
            return err(ModelError::Empty {
                what: "a block row or block column has only `None` cells, so its size is unknown; \
                       use Expr::zeros(rows, cols)"
                    .into(),
            });
        };
        let shape = Shape::new(heights.iter().sum(), widths.iter().sum());
        if shape.rows > MAX_DIM || shape.cols > MAX_DIM {
            return err(ModelError::InvalidArgument(format!(
                "block matrix of shape {shape} is too large"
            )));
        }
        let has_vars = nodes.iter().flatten().any(|n| n.has_vars);
        let all_folded: Option<Vec<Option<&Affine>>> = nodes
            .iter()
            .map(|c| match c {
                None => Some(None),
                Some(n) => n.folded().map(Some),
            })
            .collect();
        match all_folded {
            Some(cells) => folded(shape, model, Affine::blocks(&heights, &widths, &cells)),
            None => node(
                shape,
                model,
                has_vars,
                Kind::Blocks {
                    heights,
                    widths,
                    cells: nodes,
                },
            ),
        }
    }

    /// `self − rhs`, where a 1×1 side is broadcast to `c·I` (`identity = true`, matrix
    /// inequalities) or to `c·𝟙` (entrywise and equality constraints).
    pub(crate) fn difference(&self, rhs: &Expr, identity: bool, op: &str) -> Expr {
        let (x, y) = match (self.node(), rhs.node()) {
            (Ok(x), Ok(y)) => (x, y),
            (Err(e), _) | (_, Err(e)) => return err(e),
        };
        let one = Shape::new(1, 1);
        let broadcast = |s: &Expr, to: Shape| {
            if identity {
                if to.rows != to.cols {
                    return err(ModelError::NotSquare {
                        what: format!("the other side of {op} (a scalar side means scalar·I)"),
                        shape: to,
                    });
                }
                Expr::kron(Expr::identity(to.rows), s.clone())
            } else {
                Expr::kron(Expr::ones(to.rows, to.cols), s.clone())
            }
        };
        if x.shape == y.shape {
            Expr::lin_comb(self, 1.0, rhs, -1.0, op)
        } else if y.shape == one {
            Expr::lin_comb(self, 1.0, &broadcast(rhs, x.shape), -1.0, op)
        } else if x.shape == one {
            Expr::lin_comb(&broadcast(self, y.shape), 1.0, rhs, -1.0, op)
        } else {
            err(mismatch(op, x, y))
        }
    }

    /// `self ≻ rhs` (strict matrix inequality; a scalar side means scalar·I).
    pub fn gt(&self, rhs: impl Into<Expr>) -> super::Constraint {
        super::Constraint::matrix(self.difference(&rhs.into(), true, "≻"), true)
    }
    /// `self ⪰ rhs` (non-strict; `x.ge(eps)` is the explicit-margin form `X ⪰ εI`).
    pub fn ge(&self, rhs: impl Into<Expr>) -> super::Constraint {
        super::Constraint::matrix(self.difference(&rhs.into(), true, "⪰"), false)
    }
    /// `self ≺ rhs` (strict matrix inequality).
    pub fn lt(&self, rhs: impl Into<Expr>) -> super::Constraint {
        super::Constraint::matrix(-self.difference(&rhs.into(), true, "≺"), true)
    }
    /// `self ⪯ rhs` (non-strict; `x.le(-eps)` is `X ⪯ −εI`).
    pub fn le(&self, rhs: impl Into<Expr>) -> super::Constraint {
        super::Constraint::matrix(-self.difference(&rhs.into(), true, "⪯"), false)
    }
    /// Entrywise `self ≥ rhs` (an LP block; a scalar side is broadcast to every entry).
    pub fn ge_entrywise(&self, rhs: impl Into<Expr>) -> super::Constraint {
        super::Constraint::entrywise(self.difference(&rhs.into(), false, "≥ (entrywise)"), false)
    }
    /// Entrywise `self > rhs`.
    pub fn gt_entrywise(&self, rhs: impl Into<Expr>) -> super::Constraint {
        super::Constraint::entrywise(self.difference(&rhs.into(), false, "> (entrywise)"), true)
    }
    /// Entrywise `self ≤ rhs`.
    pub fn le_entrywise(&self, rhs: impl Into<Expr>) -> super::Constraint {
        super::Constraint::entrywise(-self.difference(&rhs.into(), false, "≤ (entrywise)"), false)
    }
    /// Entrywise `self < rhs`.
    pub fn lt_entrywise(&self, rhs: impl Into<Expr>) -> super::Constraint {
        super::Constraint::entrywise(-self.difference(&rhs.into(), false, "< (entrywise)"), true)
    }
    /// Linear equality `self = rhs` (entrywise; a scalar side is broadcast).
    pub fn equals(&self, rhs: impl Into<Expr>) -> super::Constraint {
        super::Constraint::equality(self.difference(&rhs.into(), false, "="))
    }
}

// ---------------------------------------------------------------------------------------------
// Conversions and operators.

impl From<&Expr> for Expr {
    fn from(e: &Expr) -> Self {
        e.clone()
    }
}
impl From<Var> for Expr {
    fn from(v: Var) -> Self {
        v.expr
    }
}
impl From<&Var> for Expr {
    fn from(v: &Var) -> Self {
        v.expr.clone()
    }
}
impl From<Param> for Expr {
    fn from(p: Param) -> Self {
        p.expr
    }
}
impl From<&Param> for Expr {
    fn from(p: &Param) -> Self {
        p.expr.clone()
    }
}
impl From<f64> for Expr {
    fn from(c: f64) -> Self {
        Expr::scalar(c)
    }
}
impl From<&Mat<f64>> for Expr {
    fn from(m: &Mat<f64>) -> Self {
        Expr::constant(m.as_ref())
    }
}
impl From<Mat<f64>> for Expr {
    fn from(m: Mat<f64>) -> Self {
        Expr::constant(m.as_ref())
    }
}
impl From<MatRef<'_, f64>> for Expr {
    fn from(m: MatRef<'_, f64>) -> Self {
        Expr::constant(m)
    }
}

macro_rules! expr_like_ops {
    ($($t:ty),*) => {$(
        impl<R: Into<Expr>> Add<R> for $t {
            type Output = Expr;
            fn add(self, rhs: R) -> Expr {
                Expr::lin_comb(&Expr::from(self), 1.0, &rhs.into(), 1.0, "+")
            }
        }
        impl<R: Into<Expr>> Sub<R> for $t {
            type Output = Expr;
            fn sub(self, rhs: R) -> Expr {
                Expr::lin_comb(&Expr::from(self), 1.0, &rhs.into(), -1.0, "−")
            }
        }
        impl<R: Into<Expr>> Mul<R> for $t {
            type Output = Expr;
            fn mul(self, rhs: R) -> Expr {
                Expr::from(self).matmul(&rhs.into())
            }
        }
        impl Div<f64> for $t {
            type Output = Expr;
            fn div(self, rhs: f64) -> Expr {
                if rhs == 0.0 {
                    return err(ModelError::NonFinite { what: "division by zero".into(), value: rhs });
                }
                Expr::from(self).scaled(1.0 / rhs)
            }
        }
        impl Neg for $t {
            type Output = Expr;
            fn neg(self) -> Expr {
                Expr::from(self).scaled(-1.0)
            }
        }
    )*};
}
expr_like_ops!(Expr, &Expr, Var, &Var, Param, &Param);

macro_rules! const_lhs_ops {
    ($lhs:ty; $($t:ty),*) => {$(
        impl Add<$t> for $lhs {
            type Output = Expr;
            fn add(self, rhs: $t) -> Expr {
                Expr::lin_comb(&Expr::from(self), 1.0, &Expr::from(rhs), 1.0, "+")
            }
        }
        impl Sub<$t> for $lhs {
            type Output = Expr;
            fn sub(self, rhs: $t) -> Expr {
                Expr::lin_comb(&Expr::from(self), 1.0, &Expr::from(rhs), -1.0, "−")
            }
        }
        impl Mul<$t> for $lhs {
            type Output = Expr;
            fn mul(self, rhs: $t) -> Expr {
                Expr::from(self).matmul(&Expr::from(rhs))
            }
        }
    )*};
}
const_lhs_ops!(f64; Expr, &Expr, Var, &Var, Param, &Param);
const_lhs_ops!(&Mat<f64>; Expr, &Expr, Var, &Var, Param, &Param);
const_lhs_ops!(Mat<f64>; Expr, &Expr, Var, &Var, Param, &Param);

macro_rules! matref_lhs_ops {
    ($($t:ty),*) => {$(
        impl Add<$t> for MatRef<'_, f64> {
            type Output = Expr;
            fn add(self, rhs: $t) -> Expr {
                Expr::lin_comb(&Expr::from(self), 1.0, &Expr::from(rhs), 1.0, "+")
            }
        }
        impl Sub<$t> for MatRef<'_, f64> {
            type Output = Expr;
            fn sub(self, rhs: $t) -> Expr {
                Expr::lin_comb(&Expr::from(self), 1.0, &Expr::from(rhs), -1.0, "−")
            }
        }
        impl Mul<$t> for MatRef<'_, f64> {
            type Output = Expr;
            fn mul(self, rhs: $t) -> Expr {
                Expr::from(self).matmul(&Expr::from(rhs))
            }
        }
    )*};
}
matref_lhs_ops!(Expr, &Expr, Var, &Var, Param, &Param);

/// `He(X) = X + Xᵀ` as a free function (see [`Expr::he`]).
pub fn he(x: impl Into<Expr>) -> Expr {
    x.into().he()
}
