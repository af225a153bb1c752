//! Re-solving a compiled LMI model with new parameter values or appended constraints gives the
//! same results as building the model afresh, and reuses the solver's structure analysis.

use faer::{Mat, mat};
use sporadic_sdp::lmi::{Expr, FeasibilityOptions, LmiSolution, Model, Outcome, Param, Var};

const E: f64 = std::f64::consts::E;

/// LMI (41) of Ferrante et al. (scalar Example 1) with the gain `L` a parameter: `J = L·F`.
fn ferrante(l: f64) -> (Model, Param) {
    let mut m = Model::new();
    let p = m.symmetric("P", 1);
    let f = m.full("F", 1, 1);
    let j = m.full("J", 1, 1);
    let lp = m.param("L", mat![[l]].as_ref()).unwrap();
    let phi = Expr::sym_blocks(&[
        [Some(-f.he()), None, None],
        [Some((&f - &j).t()), Some(-&p), None],
        [Some(&p * E), Some(Expr::zeros(1, 1)), Some(-&p)],
    ]);
    m.constrain(phi.lt(0.0)).unwrap();
    m.constrain(j.equals(&lp * &f)).unwrap();
    (m, lp)
}

fn same(a: &LmiSolution, b: &LmiSolution) {
    assert_eq!(a.outcome, b.outcome, "{} / {}", a.reason, b.reason);
    let (ta, tb) = (a.margin.unwrap(), b.margin.unwrap());
    assert!((ta - tb).abs() < 1e-9 * (1.0 + ta.abs()), "{ta} vs {tb}");
    for (x, y) in a.decision_scalars().iter().zip(b.decision_scalars()) {
        assert!((x - y).abs() < 1e-6 * (1.0 + x.abs()), "{x} vs {y}");
    }
}

#[test]
fn parameter_update_matches_fresh_build() {
    let opts = FeasibilityOptions::default();
    let (m, lp) = ferrante(0.7321206);
    let mut c = m.compile_feasibility(&opts).unwrap();
    let first = c.solve().unwrap();
    assert_eq!(first.outcome, Outcome::Feasible);
    for l in [0.6, 1.4, 0.6322, 1.3678, 0.95, 0.7321206] {
        c.set_param(&lp, mat![[l]].as_ref()).unwrap();
        let updated = c.solve().unwrap();
        let fresh = ferrante(l).0.feasibility(&opts).unwrap();
        same(&updated, &fresh);
        let expect = (1.0 - l).abs() < 1.0 / E;
        assert_eq!(updated.is_feasible(), expect, "L = {l}");
    }
    same(&c.solve().unwrap(), &first);
    // Only the equality depends on L: one evaluation per update (+ the 2 initial ones).
    assert_eq!(c.stats().evaluations, 2 + 6);
    assert_eq!(c.stats().solves, 8);
}

/// Discrete-time Lyapunov LMI with the transition matrix a parameter:
/// `P ≻ 0`, `EᵀPE − P ≺ 0` (feasible iff ρ(E) < 1).
fn discrete(e0: &Mat<f64>) -> (Model, Var, Param) {
    let mut m = Model::new();
    let p = m.symmetric("P", 2);
    let e = m.param("E", e0.as_ref()).unwrap();
    m.constrain(p.gt(0.0)).unwrap();
    m.constrain((e.t() * &p * &e - &p).lt(0.0).named("decrease"))
        .unwrap();
    (m, p, e)
}

/// `r·R(θ)` with a shear, spectral radius `r`.
fn transition(r: f64, theta: f64) -> Mat<f64> {
    let (s, c) = theta.sin_cos();
    let rot = mat![[c, -s], [s, c]];
    let shear = mat![[1.0, 0.7], [0.0, 1.0]];
    let inv = mat![[1.0, -0.7], [0.0, 1.0]];
    &shear * (rot * r) * &inv
}

#[test]
fn structure_is_analysed_once_across_updates() {
    let opts = FeasibilityOptions::default();
    let (m, p, e) = discrete(&transition(0.9, 0.3));
    let mut c = m.compile_feasibility(&opts).unwrap();
    let cases = [(0.9, 0.3), (0.5, 1.0), (1.1, 0.2), (0.99, 2.0), (1.5, 0.0)];
    for &(r, th) in &cases {
        let ev = transition(r, th);
        c.set_param(&e, ev.as_ref()).unwrap();
        let updated = c.solve().unwrap();
        let fresh = discrete(&ev).0.feasibility(&opts).unwrap();
        same(&updated, &fresh);
        assert_eq!(
            updated.is_feasible(),
            r < 1.0,
            "r = {r}: {}",
            updated.reason
        );
        if updated.is_feasible() {
            // Independent check of EᵀPE − P ≺ 0 and P ≻ 0.
            let pv = updated.value(&p).unwrap();
            let d = ev.transpose() * &pv * &ev - &pv;
            let eig = |x: &Mat<f64>| {
                x.self_adjoint_eigenvalues(faer::Side::Lower)
                    .unwrap()
                    .into_iter()
                    .fold(f64::NEG_INFINITY, f64::max)
            };
            assert!(eig(&d) < 0.0 && eig(&(-&pv)) < 0.0);
        }
    }
    let st = c.stats();
    assert_eq!(st.analyses, 1, "{st:?}");
    assert_eq!(st.solves, cases.len());
    // P ≻ 0 does not depend on E: evaluated once; the decrease LMI once per update.
    assert_eq!(st.evaluations, 1 + cases.len());
}

#[test]
fn appended_constraint_matches_fresh_build() {
    let opts = FeasibilityOptions::default();
    let e1 = transition(0.8, 0.4);
    let e2 = transition(0.95, 1.3);
    let (m, p, _) = discrete(&e1);
    let mut c = m.compile_feasibility(&opts).unwrap();
    assert!(c.solve().unwrap().is_feasible());
    // A second vertex (a new τ point): a common P must work for both.
    let id = c
        .add((e2.transpose() * &p * &e2 - &p).lt(0.0).named("vertex 2"))
        .unwrap();
    assert_eq!(id.index(), 2);
    let appended = c.solve().unwrap();
    let (mut fresh_model, p2, _) = discrete(&e1);
    fresh_model
        .constrain((e2.transpose() * &p2 * &e2 - &p2).lt(0.0).named("vertex 2"))
        .unwrap();
    let fresh = fresh_model.feasibility(&opts).unwrap();
    same(&appended, &fresh);
    assert_eq!(c.stats().evaluations, 3);
    assert_eq!(c.stats().analyses, 2);
    // Appending an unstable vertex makes the set infeasible.
    let e3 = transition(1.2, 0.0);
    c.add((e3.transpose() * &p * &e3 - &p).lt(0.0)).unwrap();
    assert_eq!(c.solve().unwrap().outcome, Outcome::Infeasible);
}
