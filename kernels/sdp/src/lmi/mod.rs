//! LMI modelling layer: decision variables, affine matrix expressions, matrix inequalities,
//! compilation to the solver's standard form, re-solvable compiled models, and independent
//! verification of every result.
//!
//! # Worked example: an observer gain from an LMI
//!
//! For `ẋ = Ax`, `y = Cx`, find `P ≻ 0` and `Y` with `He(PA − YC) ≺ 0`; then `L = P⁻¹Y` makes
//! `A − LC` Hurwitz (the standard change of variables `Y = PL`). The LMIs are strict, so we ask
//! for the largest common margin ([`Model::feasibility`]) rather than optimise:
//!
//! ```
//! use faer::{mat, Mat};
//! use faer::linalg::solvers::Solve;
//! use sporadic_sdp::lmi::{Expr, FeasibilityOptions, Model, Outcome};
//!
//! let a = mat![[0.0, 1.0], [2.0, -1.0]]; // unstable: eigenvalues 1 and −2
//! let c = mat![[1.0, 0.0]];
//!
//! let mut m = Model::new();
//! let p = m.symmetric("P", 2);               // sdpvar(2)
//! let y = m.full("Y", 2, 1);                 // sdpvar(2, 1, 'full')
//! let lyap = (&p * &a - &y * &c).he();       // He(PA − YC)
//! m.constrain(p.gt(0.0).named("P ≻ 0"))?;    // P > 0
//! m.constrain(lyap.lt(0.0).named("decrease"))?;
//!
//! let sol = m.feasibility(&FeasibilityOptions::default())?;
//! assert_eq!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
//! assert!(sol.margin.unwrap() > 0.0);
//! // Every constraint was re-evaluated from its own data at the returned point:
//! assert!(sol.verification.get("decrease").unwrap().value > 0.0); // λ_min(−He(PA − YC))
//!
//! let (pv, yv) = (sol.value(&p)?, sol.value(&y)?);
//! let l = pv.llt(faer::Side::Lower).unwrap().solve(&yv); // L = P⁻¹Y
//! let closed = &a - &l * &c;
//! let eig = closed.eigenvalues().unwrap();
//! assert!(eig.iter().all(|z| z.re < 0.0));
//! # Ok::<(), sporadic_sdp::lmi::ModelError>(())
//! ```
//!
//! # From YALMIP
//!
//! | YALMIP | here |
//! |---|---|
//! | `P = sdpvar(n)`, `X = sdpvar(r,c,'full')`, `t = sdpvar(1)` | [`Model::symmetric`], [`Model::full`], [`Model::scalar`] (also [`Model::diagonal`]) |
//! | `A'*P + P*A`, `[X, Y; Y', Z]`, `kron(K, X)`, `trace(P)` | `a.transpose() * &p + &p * &a`, [`Expr::blocks`] / [`Expr::sym_blocks`] (⋆ completion), [`Expr::kron`], [`Expr::trace`]; also [`Expr::he`], [`Expr::t`] |
//! | `F = [P > 0, L <= -eps*eye(n), x >= 0, A*x == b]` | `p.gt(0.0)`, `l.le(-eps)`, `x.ge_entrywise(0.0)`, `(&a * &x).equals(&b)`, each passed to [`Model::constrain`] |
//! | `optimize(F, trace(P))` | [`Model::minimize`] then [`Model::solve`] |
//! | strict feasibility (`feasp` in the LMI toolbox) | [`Model::feasibility`] |
//! | `optimizer(F, obj, [], param, P)` | [`Model::param`] + [`Model::compile`] + [`Compiled::set_param`] + [`Compiled::solve`] |
//!
//! A scalar on either side of a matrix inequality means that scalar times the identity
//! (`x.ge(eps)` is `X ⪰ εI`); of an entrywise inequality or equality, that scalar in every entry.
//! A `*` with a 1×1 factor scales. Unlike YALMIP, a matrix inequality on a non-symmetric
//! expression is an error ([`ModelError::NonSymmetric`]), never silently turned entrywise.
//!
//! # Representation
//!
//! Every expression is stored sparsely as `F(y) = F_0 + Σ_k y_k F_k` over the decision scalars
//! (module `affine`): one sorted triplet list, with products by constants done as sparse–sparse
//! products. A symmetric `n×n` variable contributes `n(n+1)/2` scalars, a full one `rows·cols`,
//! a diagonal one `n`. Expressions involving a [`Param`] keep the parameter-dependent operations
//! as a small tree that is re-evaluated when the parameter changes.
//!
//! # Constraints and compilation
//!
//! * Matrix inequalities become PSD blocks of the dual (LMI) form: `C = F_0`, `A_k = −F_k`
//!   (order 1 ones go to the LP block); entrywise inequalities become LP rows.
//! * **Equalities are eliminated**, not split into two inequalities (which would leave the
//!   problem without interior points): Gauss–Jordan elimination with complete pivoting solves
//!   them for some scalars, and the substitution is applied to every inequality (module
//!   `eliminate`). Redundant equalities are dropped; inconsistent ones are an error.
//! * **Strict inequalities.** In objective mode ([`Model::solve`]) a strict `F ≻ 0` is imposed as
//!   `F ⪰ ε I` and verified as `λ_min(F) ≥ τ` (the scale-aware tolerance of [`Verification`]),
//!   with the same margin on both sides: `ε = max(`[`SolveOptions::strict_margin`]`, 2τ)`, the
//!   default `1e-6` raised by a re-solve where `τ` at the returned point requires it
//!   ([`Compiled::solve`]), so a strictly feasible model is not reported inconclusive because
//!   of our own tolerances. For feasibility
//!   questions use [`Model::feasibility`]: it maximises a common margin `t` (`F ⪰ tI` for every
//!   strict constraint) under a normalisation (default `‖X‖₂ ≤ 1` per variable and `t ≤ 1`; see
//!   [`FeasibilityOptions`]) and reports `t*`; the model is declared strictly feasible only when the
//!   returned point passes verification, i.e. every strict constraint has `λ_min` above its
//!   tolerance.
//!
//! # Verification and outcome
//!
//! After every solve, each constraint is recomputed in `f64` from its own expression data at the
//! returned point ([`Verification`]); [`Outcome::Feasible`] requires every constraint to pass
//! with the safety factor, and infeasibility is only reported on a solver certificate or, in
//! feasibility mode, a maximal margin at or below the verification threshold under a
//! normalisation that loses no generality (infeasibility at the resolution of the threshold: a
//! strictly feasible point with a smaller margin is not excluded, and the reason says so).
//! Everything else is [`Outcome::Inconclusive`], with the reason spelled out in
//! [`LmiSolution::reason`].
//!
//! # Re-solving
//!
//! [`Model::compile`] returns a [`Compiled`] handle. [`Compiled::set_param`] updates a parameter
//! (only the constraints using it are re-evaluated) and [`Compiled::add`] appends a constraint;
//! [`Compiled::solve`] reuses the solver's structure analysis ([`crate::Solver`]) whenever the
//! sparsity pattern stays within the analysed one ([`Compiled::stats`] counts the analyses).

mod affine;
mod compile;
mod eliminate;
mod error;
mod expr;
mod model;
mod solution;

pub use compile::{
    CompileStats, Compiled, FeasibilityOptions, MARGIN_ROUNDS, Normalisation, STRICT_MARGIN_FACTOR,
    SolveOptions,
};
pub use error::{ModelError, Shape};
pub use expr::{Expr, Param, Var, VarKind, he};
pub use model::{Constraint, ConstraintId, ConstraintKind, Model, SYMMETRY_TOL, Sense};
pub use solution::{ConstraintReport, Iterate, LmiSolution, Outcome, Verification};
