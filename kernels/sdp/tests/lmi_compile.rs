//! LMI layer: compilation to the dual standard form checked against hand-derived data, expression
//! algebra against dense arithmetic, and the typed error paths.

use faer::{Mat, mat};
use sporadic_linalg::InputError;
use sporadic_sdp::lmi::{
    ConstraintKind, Expr, FeasibilityOptions, Model, ModelError, Outcome, Shape, SolveOptions,
};
use sporadic_sdp::{BlockKind, SparseSym};

fn sparse(entries: &[(usize, usize, f64)]) -> SparseSym {
    SparseSym {
        rows: entries.iter().map(|e| e.0).collect(),
        cols: entries.iter().map(|e| e.1).collect(),
        vals: entries.iter().map(|e| e.2).collect(),
    }
}

/// `min t  s.t.  P ⪰ I,  t ≥ tr P` compiles to (hand-derived, convention C = F_0, A_k = −F_k,
/// b = −∇f): columns (t, p00, p01, p11); LP block row `t − p00 − p11 ≥ 0`; PSD block `P − I`.
#[test]
fn compiles_to_hand_derived_problem() {
    let mut m = Model::new();
    let t = m.scalar("t");
    let p = m.symmetric("P", 2);
    m.constrain(p.ge(1.0)).unwrap();
    m.constrain(t.ge(p.trace())).unwrap();
    m.minimize(&t).unwrap();
    let mut c = m.compile(&SolveOptions::default()).unwrap();
    let pr = c.problem().unwrap().clone();
    assert_eq!(pr.b, vec![-1.0, 0.0, 0.0, 0.0]);
    assert_eq!(pr.blocks.len(), 2);
    let lp = &pr.blocks[0];
    assert_eq!((lp.block.kind, lp.block.size), (BlockKind::Lp, 1));
    assert!(lp.c.is_empty());
    let lp_a: Vec<(usize, SparseSym)> = vec![
        (0, sparse(&[(0, 0, -1.0)])),
        (1, sparse(&[(0, 0, 1.0)])),
        (3, sparse(&[(0, 0, 1.0)])),
    ];
    assert_eq!(lp.a, lp_a);
    let psd = &pr.blocks[1];
    assert_eq!((psd.block.kind, psd.block.size), (BlockKind::Psd, 2));
    assert_eq!(psd.c, sparse(&[(0, 0, -1.0), (1, 1, -1.0)]));
    let psd_a: Vec<(usize, SparseSym)> = vec![
        (1, sparse(&[(0, 0, -1.0)])),
        (2, sparse(&[(0, 1, -1.0)])),
        (3, sparse(&[(1, 1, -1.0)])),
    ];
    assert_eq!(psd.a, psd_a);

    // Constraint values at a hand-picked point: P − I = [[1, .5], [.5, 0]] has
    // λ_min = (1 − √2)/2; t − tr P = 0.
    let v = c.verify(&[3.0, 2.0, 0.5, 1.0]).unwrap();
    let l = v.constraints[0].value;
    assert!((l - (1.0 - 2f64.sqrt()) / 2.0).abs() < 1e-14, "{l}");
    assert!(!v.constraints[0].passed);
    assert_eq!(v.constraints[1].value, 0.0);
    assert!(v.constraints[1].passed);

    // Optimum: P = I, t = 2.
    let sol = c.solve().unwrap();
    assert_eq!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
    assert!((sol.objective.unwrap() - 2.0).abs() < 1e-6);
    let pv = sol.value(&p).unwrap();
    assert!((&pv - Mat::<f64>::identity(2, 2)).norm_max() < 1e-4);
}

/// Equalities are eliminated (one solver column for x + y = 1), never split into two rows.
#[test]
fn equalities_are_eliminated() {
    let mut m = Model::new();
    let x = m.scalar("x");
    let y = m.scalar("y");
    m.constrain((&x + &y).equals(1.0).named("sum")).unwrap();
    m.constrain(Expr::blocks(&[[Some(x.expr()), None], [None, Some(y.expr())]]).ge(0.0))
        .unwrap();
    m.minimize(2.0 * &x + &y).unwrap();
    let mut c = m.compile(&SolveOptions::default()).unwrap();
    let pr = c.problem().unwrap();
    assert_eq!(pr.num_constraints(), 1);
    // diag(x, y) ⪰ 0 is a 2×2 PSD block; no LP rows at all.
    assert_eq!(pr.blocks.len(), 1);
    assert_eq!(pr.blocks[0].block.kind, BlockKind::Psd);
    let sol = c.solve().unwrap();
    assert_eq!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
    // Optimum x = 0, y = 1, objective 1.
    assert!((sol.objective.unwrap() - 1.0).abs() < 1e-6);
    assert!((sol.scalar(&y).unwrap() - 1.0).abs() < 1e-6);
    let r = sol.verification.get("sum").unwrap();
    assert_eq!(r.kind, ConstraintKind::Equality);
    assert!(r.value < 1e-12 && r.passed);
}

/// Products, transposes, He, blocks with ⋆ completion and Kronecker products agree with dense
/// arithmetic at a random point.
#[test]
fn expression_algebra_matches_dense_arithmetic() {
    let mut m = Model::new();
    let p = m.symmetric("P", 3);
    let f = m.full("F", 3, 2);
    let d = m.diagonal("D", 2);
    let a = mat![[1.0, -2.0, 0.5], [0.0, 3.0, 1.0], [2.0, 0.0, -1.0]];
    let b = mat![[1.0, 0.0], [0.5, 2.0], [0.0, -1.0]];
    let k = mat![[2.0, -1.0], [0.0, 1.0]];
    let top = (a.transpose() * &p + &p * &a).he() / 4.0;
    let off = &p * &b + &f * &k;
    let e = Expr::sym_blocks(&[
        [Some(top.clone()), None],
        [Some(off.t()), Some(-(&d * 2.0))],
    ]);
    let kr = Expr::kron(&k, &f);
    m.constrain(e.ge(0.0)).unwrap();
    m.constrain(kr.ge_entrywise(0.0)).unwrap();
    let mut c = m.compile(&SolveOptions::default()).unwrap();
    let y: Vec<f64> = (0..m.num_scalars())
        .map(|i| ((i * 37 % 11) as f64 - 5.0) / 3.0)
        .collect();
    // Dense values of the variables at y.
    let pv = Mat::from_fn(3, 3, |i, j| {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        y[j * (j + 1) / 2 + i]
    });
    let fv = Mat::from_fn(3, 2, |i, j| y[6 + j * 3 + i]);
    let dv = Mat::from_fn(2, 2, |i, j| if i == j { y[12 + i] } else { 0.0 });
    let top_d = {
        let l = a.transpose() * &pv + &pv * &a;
        Mat::from_fn(3, 3, |i, j| (l[(i, j)] + l[(j, i)]) / 4.0)
    };
    let off_d = &pv * &b + &fv * &k;
    let mut e_d = Mat::<f64>::zeros(5, 5);
    e_d.submatrix_mut(0, 0, 3, 3).copy_from(&top_d);
    e_d.submatrix_mut(0, 3, 3, 2).copy_from(&off_d);
    e_d.submatrix_mut(3, 0, 2, 3).copy_from(off_d.transpose());
    e_d.submatrix_mut(3, 3, 2, 2).copy_from(-2.0 * &dv);
    let lmin = e_d
        .self_adjoint_eigenvalues(faer::Side::Lower)
        .unwrap()
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    let kmin = k.kron(&fv);
    let kmin = (0..4)
        .flat_map(|i| (0..4).map(move |j| (i, j)))
        .map(|p| kmin[p])
        .fold(f64::INFINITY, f64::min);
    let v = c.verify(&y).unwrap();
    assert!((v.constraints[0].value - lmin).abs() < 1e-12 * (1.0 + lmin.abs()));
    assert!((v.constraints[1].value - kmin).abs() < 1e-14);
}

#[test]
fn dimension_mismatch_names_operands_and_shapes() {
    let mut m = Model::new();
    let p = m.symmetric("P", 2);
    let e = &p + Expr::identity(3);
    let err = m.constrain(e.gt(0.0)).unwrap_err();
    match &err {
        ModelError::DimensionMismatch {
            left,
            left_shape,
            right_shape,
            ..
        } => {
            assert!(left.contains("`P`"), "{err}");
            assert_eq!(*left_shape, Shape::new(2, 2));
            assert_eq!(*right_shape, Shape::new(3, 3));
        }
        other => panic!("unexpected {other}"),
    }
    assert!(err.to_string().contains("2×2") && err.to_string().contains("3×3"));
    // Matrix product with incompatible inner dimensions.
    let f = m.full("F", 2, 3);
    let err = (&f * &p).check().unwrap_err();
    assert!(matches!(err, ModelError::DimensionMismatch { .. }), "{err}");
    // Block rows of different heights.
    let err = Expr::blocks(&[[Some(p.expr()), Some(Expr::zeros(3, 1))]])
        .check()
        .unwrap_err();
    assert!(matches!(err, ModelError::DimensionMismatch { .. }), "{err}");
}

#[test]
fn non_symmetric_matrix_inequality_is_rejected() {
    let mut m = Model::new();
    let p = m.symmetric("P", 2);
    let a = mat![[0.0, 1.0], [-2.0, -3.0]];
    let err = m.constrain((&p * &a).lt(0.0).named("PA ≺ 0")).unwrap_err();
    match err {
        ModelError::NonSymmetric { constraint, .. } => assert_eq!(constraint, "PA ≺ 0"),
        other => panic!("unexpected {other}"),
    }
    // A non-symmetric constant term is caught too.
    let err = m
        .constrain((&p + mat![[0.0, 1.0], [0.0, 0.0]]).ge(0.0))
        .unwrap_err();
    assert!(matches!(err, ModelError::NonSymmetric { .. }), "{err}");
    // The entrywise form of the same expression is fine.
    m.constrain((&p * &a).le_entrywise(1.0)).unwrap();
    // Non-square matrix inequality.
    let f = m.full("F", 2, 3);
    let err = m.constrain(f.ge(0.0)).unwrap_err();
    assert!(matches!(err, ModelError::NotSquare { .. }), "{err}");
}

#[test]
fn non_finite_data_is_rejected() {
    let mut m = Model::new();
    let p = m.symmetric("P", 2);
    let bad = mat![[1.0, f64::NAN], [0.0, 1.0]];
    let err = m.constrain((&bad * &p).he().lt(0.0)).unwrap_err();
    assert!(matches!(err, ModelError::NonFinite { .. }), "{err}");
    let err = m.constrain(p.ge(f64::INFINITY)).unwrap_err();
    assert!(matches!(err, ModelError::NonFinite { .. }), "{err}");
    // Parameter data goes through the workspace's shared check, which names the entry.
    assert_eq!(
        m.param("E", bad.as_ref()).unwrap_err(),
        ModelError::Input(InputError::non_finite("parameter `E` at entry (0,1)"))
    );
    let e = m.param("E", Mat::<f64>::identity(2, 2).as_ref()).unwrap();
    m.constrain((e.t() * &p * &e - &p).lt(0.0)).unwrap();
    m.constrain(p.gt(0.0)).unwrap();
    let mut c = m.compile(&SolveOptions::default()).unwrap();
    assert_eq!(
        c.set_param(&e, bad.as_ref()).unwrap_err(),
        ModelError::Input(InputError::non_finite(
            "new value of parameter `E` at entry (0,1)"
        ))
    );
    assert!(matches!(
        c.set_param(&e, Mat::<f64>::identity(3, 3).as_ref())
            .unwrap_err(),
        ModelError::ParamShape { .. }
    ));
    // Overflow while combining finite data.
    let huge = mat![[1e300, 0.0], [0.0, 1e300]];
    let err = (&huge * Expr::constant(huge.as_ref()) * &p)
        .check()
        .unwrap_err();
    assert!(matches!(err, ModelError::NonFinite { .. }), "{err}");
}

#[test]
fn other_error_paths() {
    let mut m = Model::new();
    let p = m.symmetric("P", 2);
    let mut other = Model::new();
    let q = other.symmetric("Q", 2);
    // Variables of another model.
    assert!(matches!(
        m.constrain(q.gt(0.0)).unwrap_err(),
        ModelError::ForeignModel { .. }
    ));
    assert!(matches!(
        (&p + &q).check().unwrap_err(),
        ModelError::ForeignModel { .. }
    ));
    // Products of two variable expressions are not affine.
    assert!(matches!(
        (&p * &p).check().unwrap_err(),
        ModelError::NotAffine { .. }
    ));
    // Empty constraint set.
    assert!(matches!(
        m.compile(&SolveOptions::default()).unwrap_err(),
        ModelError::NoConstraints
    ));
    assert!(matches!(
        m.feasibility(&FeasibilityOptions::default()).unwrap_err(),
        ModelError::NoConstraints
    ));
    // Empty expression.
    let z = m.symmetric("Z", 0);
    assert!(matches!(
        m.constrain(z.ge(0.0)).unwrap_err(),
        ModelError::Empty { .. }
    ));
    // Objective must be 1×1.
    assert!(matches!(
        m.minimize(&p).unwrap_err(),
        ModelError::ObjectiveNotScalar { .. }
    ));
    // Inconsistent equalities.
    let x = m.scalar("x");
    m.constrain(x.equals(1.0)).unwrap();
    m.constrain((2.0 * &x).equals(3.0).named("2x = 3")).unwrap();
    m.constrain(p.ge(0.0)).unwrap();
    match m
        .compile(&SolveOptions::default())
        .unwrap()
        .problem()
        .unwrap_err()
    {
        ModelError::InconsistentEqualities { constraint, .. } => {
            assert!(constraint == "2x = 3" || constraint.starts_with('#'))
        }
        other => panic!("unexpected {other}"),
    }
    // Objective on an unconstrained scalar.
    let mut m = Model::new();
    let p = m.symmetric("P", 2);
    let s = m.scalar("s");
    m.constrain(p.ge(0.0)).unwrap();
    m.minimize(p.trace() + &s).unwrap();
    match m.solve(&SolveOptions::default()).unwrap_err() {
        ModelError::Unbounded { scalar } => assert_eq!(scalar, "s"),
        other => panic!("unexpected {other}"),
    }
    // A solution refuses variables of another model.
    m.minimize(p.trace()).unwrap();
    let sol = m.solve(&SolveOptions::default()).unwrap();
    assert!(matches!(
        sol.value(&q).unwrap_err(),
        ModelError::ForeignModel { .. }
    ));
}

/// `max x + 2y` over the triangle `x, y ≥ 0`, `x + y ≤ 1` (LP block only): optimum 2 at (0, 1).
#[test]
fn maximisation_over_lp_block() {
    let mut m = Model::new();
    let x = m.scalar("x");
    let y = m.scalar("y");
    let v = Expr::blocks(&[[Some(x.expr())], [Some(y.expr())]]);
    m.constrain(v.ge_entrywise(0.0)).unwrap();
    m.constrain((&x + &y).le_entrywise(1.0)).unwrap();
    m.maximize(&x + 2.0 * &y).unwrap();
    let sol = m.solve(&SolveOptions::default()).unwrap();
    assert_eq!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
    assert!((sol.objective.unwrap() - 2.0).abs() < 1e-6);
    assert!(sol.scalar(&x).unwrap().abs() < 1e-6);
}

/// In objective mode a strict constraint is imposed with the absolute margin `strict_margin`:
/// `min t s.t. t > 0` ends at `t = strict_margin`, which passes the strict verification rule
/// (`t ≥ τ = 10·1e-8·(1 + t)`). With `strict_margin = 0` the first solve ends on the boundary,
/// where the strict constraint cannot be verified, so the margin is raised to the `2τ` its
/// check requires and the model re-solved: `t = 2τ ≈ 2e-7`, verified.
#[test]
fn strict_constraints_in_objective_mode() {
    let mut m = Model::new();
    let t = m.scalar("t");
    m.constrain(t.gt(0.0).named("t > 0")).unwrap();
    m.constrain(t.le(5.0)).unwrap();
    m.minimize(&t).unwrap();
    let sol = m.solve(&SolveOptions::default()).unwrap();
    assert_eq!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
    assert!((sol.scalar(&t).unwrap() - 1e-6).abs() < 1e-8);
    let opts = SolveOptions {
        strict_margin: 0.0,
        ..SolveOptions::default()
    };
    let sol = m.solve(&opts).unwrap();
    assert_eq!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
    let report = sol.verification.get("t > 0").unwrap();
    assert!(
        report.passed && report.value >= report.tolerance,
        "{report:?}"
    );
    assert!(
        (sol.scalar(&t).unwrap() - 2e-7).abs() < 1e-8,
        "{}",
        sol.reason
    );
    assert!(sol.reason.contains("raised"), "{}", sol.reason);
    // The same question as a margin problem: strictly feasible.
    let sol = m.feasibility(&FeasibilityOptions::default()).unwrap();
    assert_eq!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
}

/// `FeasibilityOptions::stop_when_verified`: the margin solve of a strictly feasible Lyapunov
/// LMI ends at the first verified iterate, with fewer iterations and a positive margin at most
/// the optimal one, and the point it returns verifies (re-checked here from the matrix itself);
/// an LMI that is not strictly feasible gets the same verdict as without the option.
#[test]
fn a_margin_solve_can_stop_at_its_first_verified_point() {
    let lyapunov = |a: Mat<f64>| {
        let mut m = Model::new();
        let p = m.symmetric("P", 2);
        m.constrain(p.gt(0.0).named("P > 0")).unwrap();
        let lhs = a.transpose() * p.expr() + p.expr() * &a;
        m.constrain(lhs.lt(0.0).named("A'P + PA < 0")).unwrap();
        (m, p)
    };
    let mut stop = FeasibilityOptions::default();
    stop.stop_when_verified = true;
    let (m, p) = lyapunov(mat![[-1.0, 3.0], [-0.5, -0.2]]);
    let full = m.feasibility(&FeasibilityOptions::default()).unwrap();
    let early = m.feasibility(&stop).unwrap();
    assert_eq!(full.outcome, Outcome::Feasible, "{}", full.reason);
    assert_eq!(early.outcome, Outcome::Feasible, "{}", early.reason);
    assert_eq!(early.sdp.status, sporadic_sdp::Status::Accepted);
    assert!(early.sdp.iterations < full.sdp.iterations);
    let (t, t_star) = (early.margin.unwrap(), full.margin.unwrap());
    assert!(t > 0.0 && t <= t_star * (1.0 + 1e-9), "{t} vs {t_star}");
    assert!(
        early.reason.contains("first interior-point iterate"),
        "{}",
        early.reason
    );
    let pv = early.value(&p).unwrap();
    let a = mat![[-1.0, 3.0], [-0.5, -0.2]];
    let q = a.transpose() * &pv + &pv * &a;
    let eig = |x: &Mat<f64>| sporadic_linalg::max_eigenvalue(x.as_ref()).unwrap();
    assert!(eig(&q) < 0.0 && eig(&(-&pv)) < 0.0);
    // An unstable A: no iterate verifies, so the verdict is the full solve's.
    let (m, _) = lyapunov(mat![[0.1, 1.0], [0.0, -1.0]]);
    let full = m.feasibility(&FeasibilityOptions::default()).unwrap();
    let early = m.feasibility(&stop).unwrap();
    assert_eq!(full.outcome, Outcome::Infeasible, "{}", full.reason);
    assert_eq!(early.outcome, full.outcome);
    assert_eq!(early.sdp.status, full.sdp.status);
    assert_eq!(early.margin, full.margin);
}

/// `Compiled::solve_accepting`: the caller's own certificate test ends a margin solve at the
/// first iterate it accepts. Here the test is an independent eigenvalue check of the Lyapunov
/// LMI at the iterate's `P` (no verification threshold): the solve stops no later than the
/// verified stop, and earlier than the full solve, is shown only positive margins, and returns
/// the accepted `P`; a test that accepts nothing leaves the full solve's result; objective mode
/// refuses it.
#[test]
fn a_margin_solve_can_stop_at_a_point_its_caller_accepts() {
    let a = mat![[-1.0, 3.0], [-0.5, -0.2]];
    let mut m = Model::new();
    let p = m.symmetric("P", 2);
    m.constrain(p.gt(0.0).named("P > 0")).unwrap();
    let lhs = a.transpose() * p.expr() + p.expr() * &a;
    m.constrain(lhs.lt(0.0).named("A'P + PA < 0")).unwrap();
    let eig = |x: &Mat<f64>| sporadic_linalg::max_eigenvalue(x.as_ref()).unwrap();
    let lyapunov = |pv: &Mat<f64>| eig(&(a.transpose() * pv + pv * &a)) < 0.0 && eig(&-pv) < 0.0;
    let full = m.feasibility(&FeasibilityOptions::default()).unwrap();
    let mut verified = FeasibilityOptions::default();
    verified.stop_when_verified = true;
    let verified = m.feasibility(&verified).unwrap();

    let mut c = m
        .compile_feasibility(&FeasibilityOptions::default())
        .unwrap();
    let (mut shown, mut margins) = (0, Vec::new());
    let early = c
        .solve_accepting(&mut |it| {
            shown += 1;
            margins.push(it.margin());
            lyapunov(&it.value(&p).unwrap())
        })
        .unwrap();
    assert_eq!(early.sdp.status, sporadic_sdp::Status::Accepted);
    assert!(
        shown >= 1 && margins.iter().all(|&t| t > 0.0),
        "{margins:?}"
    );
    assert!(
        early.sdp.iterations <= verified.sdp.iterations
            && early.sdp.iterations < full.sdp.iterations,
        "{} {} {}",
        early.sdp.iterations,
        verified.sdp.iterations,
        full.sdp.iterations
    );
    assert!(lyapunov(&early.value(&p).unwrap()));
    assert_eq!(early.margin, margins.last().copied());

    let never = c.solve_accepting(&mut |_| false).unwrap();
    assert_eq!(never.sdp.status, full.sdp.status);
    assert_eq!(never.margin, full.margin);
    assert_eq!(never.outcome, full.outcome);

    let mut objective = m.compile(&SolveOptions::default()).unwrap();
    assert!(matches!(
        objective.solve_accepting(&mut |_| true),
        Err(ModelError::InvalidArgument(_))
    ));
}

/// A maximal margin at or below the verification threshold `τ` is infeasibility at the
/// resolution of `τ`, and the reason says so without claiming more: the model here is strictly
/// feasible (`p = 1` gives `diag(1, 1e-12) ≻ 0`), with a maximal margin of `1e-12` under
/// `|p| ≤ 1`, far below `τ`.
#[test]
fn a_margin_below_the_threshold_is_not_called_strict_infeasibility() {
    let mut m = Model::new();
    let p = m.symmetric("p", 1);
    m.constrain(
        (mat![[1.0, 0.0], [0.0, 1e-12]] * &p)
            .gt(0.0)
            .named("diag(1, 1e-12)·p > 0"),
    )
    .unwrap();
    let sol = m.feasibility(&FeasibilityOptions::default()).unwrap();
    let (t, tau) = (sol.margin.unwrap(), sol.margin_threshold.unwrap());
    assert!(t.abs() < 1e-9 && tau > 1e-9, "t* = {t:e}, τ = {tau:e}");
    assert_eq!(sol.outcome, Outcome::Infeasible, "{}", sol.reason);
    for claim in ["no verifiable margin", "smaller margin is not excluded"] {
        assert!(sol.reason.contains(claim), "{}", sol.reason);
    }
    assert!(
        !sol.reason.contains("not strictly feasible"),
        "{}",
        sol.reason
    );
}

/// An infeasible non-strict LMI is reported from the solver's certificate.
#[test]
fn infeasible_lmi_is_certified() {
    let mut m = Model::new();
    let p = m.symmetric("P", 2);
    m.constrain(p.ge(1.0)).unwrap();
    m.constrain(p.trace().le(1.0)).unwrap();
    m.minimize(p.trace()).unwrap();
    let sol = m.solve(&SolveOptions::default()).unwrap();
    assert_eq!(sol.outcome, Outcome::Infeasible, "{}", sol.reason);
    assert!(sol.sdp.certificate.is_some());
}

/// A 1×1 variable on one side of a matrix inequality means that variable times I:
/// `min p s.t. diag(1, 4) ⪯ P ⪯ p·I` has optimum `p = 4` (as in the normalisation of
/// Sferlazza et al.'s SDP (47)).
#[test]
fn scalar_variable_is_broadcast_to_identity() {
    let mut m = Model::new();
    let p = m.symmetric("P", 2);
    let pm = m.scalar("p_M");
    m.constrain(p.ge(mat![[1.0, 0.0], [0.0, 4.0]])).unwrap();
    m.constrain(p.le(&pm)).unwrap();
    m.minimize(&pm).unwrap();
    let sol = m.solve(&SolveOptions::default()).unwrap();
    assert_eq!(sol.outcome, Outcome::Feasible, "{}", sol.reason);
    assert!((sol.objective.unwrap() - 4.0).abs() < 1e-6);
    assert!((sol.value(&p).unwrap()[(1, 1)] - 4.0).abs() < 1e-5);
}

/// `LmiSolution::scalar` on a matrix variable names the variable and its shape.
#[test]
fn scalar_of_a_matrix_variable_is_a_precise_error() {
    let mut m = Model::new();
    let p = m.symmetric("P", 3);
    m.constrain(p.ge(1.0)).unwrap();
    m.minimize(p.trace()).unwrap();
    let sol = m.solve(&SolveOptions::default()).unwrap();
    match sol.scalar(&p) {
        Err(ModelError::NotScalar { what, shape }) => {
            assert_eq!(what, "variable `P`");
            assert_eq!(shape, Shape::new(3, 3));
        }
        other => panic!("expected NotScalar, got {other:?}"),
    }
    let e = sol.scalar(&p).unwrap_err().to_string();
    assert!(e.contains("3×3") && e.contains("`P`"), "{e}");
}
