//! Etienne, Di Gennaro, Barbot — LMIs (20) for the flexible-joint robot example, in the spec's
//! "formulation F" (`shared/papers/003-etienne-lipschitz-impulsive.md` §3.6): maximise `t` with
//! every strict LMI `⪰ tI` (resp. `⪯ −tI`), `P1, P2 ⪯ I`, gains free. The spec's reference values
//! (§4.5, CVXPY 1.9.3 + Clarabel, an independent solver) are `t* = 5.402e-4` for Corollary 2 on
//! `[0.01, 0.2]`, `t* = 1.458e-4` for Theorem 3 on `[0.01, 0.3]`, and `t* ≈ 0` (infeasible) for
//! Corollary 2 on `[0.01, 0.3]` (§5, checks 3–4, give a ±2% band; the values are printed to 4
//! significant digits and we match them to 0.1%).

use faer::{Mat, MatRef, Side, mat};
use sporadic_sdp::lmi::{
    Expr, FeasibilityOptions, LmiSolution, Model, Normalisation, Outcome, Var,
};

fn robot() -> (Mat<f64>, Mat<f64>, [Mat<f64>; 2]) {
    let a = mat![
        [0.0, 1.0, 0.0, 0.0],
        [-48.6, -1.25, 48.6, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [19.5, 0.0, -19.5, 0.0],
    ];
    let c = mat![[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]];
    // Lemma 1 (DMVT): R_{1,2} = A ∓ 3.3 e4 e3ᵀ.
    let mut r1 = a.clone();
    r1[(3, 2)] -= 3.3;
    let mut r2 = a.clone();
    r2[(3, 2)] += 3.3;
    (a, c, [r1, r2])
}

struct Lmi20 {
    sol: LmiSolution,
    p1: Var,
    p2: Var,
    l0: Var,
    l1: Var,
    c: Mat<f64>,
}

/// LMIs (20a)–(20d) with `P1, P2 ≻ 0`; `static_gain` imposes `L0 = L1` (Corollary 2).
fn lmi20(tau_low: f64, tau_bar: f64, static_gain: bool) -> Lmi20 {
    lmi20_with(tau_low, tau_bar, static_gain, FeasibilityOptions::default())
}

fn lmi20_with(tau_low: f64, tau_bar: f64, static_gain: bool, opts: FeasibilityOptions) -> Lmi20 {
    let (_, c, rs) = robot();
    let mut m = Model::new();
    let p1 = m.symmetric("P1", 4);
    let p2 = m.symmetric("P2", 4);
    let l0 = m.full("L0", 4, 2);
    let l1 = m.full("L1", 4, 2);
    let dp = (&p2 - &p1) / tau_bar;
    for (k, r) in rs.iter().enumerate() {
        m.constrain(((&p1 * r).he() + &dp).lt(0.0).named(format!("M1_{k}")))
            .unwrap();
        m.constrain(((&p2 * r).he() + &dp).lt(0.0).named(format!("M2_{k}")))
            .unwrap();
    }
    let jump = |l: &Var, w: f64| {
        let lc = l * &c;
        Expr::sym_blocks(&[
            [Some(lc.he() - (&p1 - &p2) * w), None],
            [Some(lc), Some(p1.expr())],
        ])
    };
    m.constrain(jump(&l0, tau_low / tau_bar).gt(0.0).named("(20c)"))
        .unwrap();
    m.constrain(jump(&l1, 1.0).gt(0.0).named("(20d)")).unwrap();
    m.constrain(p1.gt(0.0)).unwrap();
    m.constrain(p2.gt(0.0)).unwrap();
    if static_gain {
        m.constrain(l0.equals(&l1)).unwrap();
    }
    let opts = opts
        .normalise(&l0, Normalisation::Free)
        .normalise(&l1, Normalisation::Free);
    let sol = m.feasibility(&opts).unwrap();
    Lmi20 {
        sol,
        p1,
        p2,
        l0,
        l1,
        c,
    }
}

fn max_eig(s: MatRef<'_, f64>) -> f64 {
    s.self_adjoint_eigenvalues(Side::Lower)
        .unwrap()
        .into_iter()
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Independent eigenvalue check of every block of (20) at the returned point.
fn check(r: &Lmi20, tau_low: f64, tau_bar: f64) {
    let (_, _, rs) = robot();
    let v = |x: &Var| r.sol.value(x).unwrap();
    let (p1, p2, l0, l1) = (v(&r.p1), v(&r.p2), v(&r.l0), v(&r.l1));
    let he = |x: &Mat<f64>| x + x.transpose();
    let dp = (&p2 - &p1) * (1.0 / tau_bar);
    for rp in &rs {
        assert!(max_eig((he(&(&p1 * rp)) + &dp).as_ref()) < 0.0);
        assert!(max_eig((he(&(&p2 * rp)) + &dp).as_ref()) < 0.0);
    }
    for (l, w) in [(&l0, tau_low / tau_bar), (&l1, 1.0)] {
        let lc = l * &r.c;
        let mut b = Mat::<f64>::zeros(8, 8);
        b.submatrix_mut(0, 0, 4, 4)
            .copy_from(he(&lc) - (&p1 - &p2) * w);
        b.submatrix_mut(4, 0, 4, 4).copy_from(&lc);
        b.submatrix_mut(0, 4, 4, 4).copy_from(lc.transpose());
        b.submatrix_mut(4, 4, 4, 4).copy_from(&p1);
        assert!(max_eig((-&b).as_ref()) < 0.0);
    }
    assert!(max_eig((-&p1).as_ref()) < 0.0 && max_eig((-&p2).as_ref()) < 0.0);
}

#[test]
fn corollary2_on_short_window_matches_reference_margin() {
    let r = lmi20(0.01, 0.2, true);
    assert_eq!(r.sol.outcome, Outcome::Feasible, "{}", r.sol.reason);
    let t = r.sol.margin.unwrap();
    assert!((t - 5.402e-4).abs() < 1e-3 * 5.402e-4, "t* = {t:e}");
    check(&r, 0.01, 0.2);
    let (l0, l1) = (r.sol.value(&r.l0).unwrap(), r.sol.value(&r.l1).unwrap());
    assert!((&l0 - &l1).norm_max() < 1e-9 * (1.0 + l0.norm_max()));
}

#[test]
fn theorem3_matches_reference_margin_and_corollary2_fails() {
    let r = lmi20(0.01, 0.3, false);
    assert_eq!(r.sol.outcome, Outcome::Feasible, "{}", r.sol.reason);
    let t = r.sol.margin.unwrap();
    assert!((t - 1.458e-4).abs() < 1e-3 * 1.458e-4, "t* = {t:e}");
    check(&r, 0.01, 0.3);

    let r = lmi20(0.01, 0.3, true);
    assert_eq!(r.sol.outcome, Outcome::Infeasible, "{}", r.sol.reason);
    assert!(r.sol.margin.unwrap() < 1e-7);
}

/// The margins reach `1e-7` relative accuracy at the default settings
/// ([`FeasibilityOptions::margin_accuracy`]): compared with a run at `tol_gap = tol_feas = 1e-13`
/// whose six DIMACS errors are checked to be below `1e-11` (a KKT point to near machine accuracy).
#[test]
fn margins_are_accurate_to_1e7_relative() {
    for (lo, hi, static_gain) in [(0.01, 0.2, true), (0.01, 0.3, false)] {
        let d = lmi20(lo, hi, static_gain);
        let mut o = FeasibilityOptions::default();
        o.solve.settings.tol_gap = 1e-13;
        o.solve.settings.tol_feas = 1e-13;
        let r = lmi20_with(lo, hi, static_gain, o);
        assert_eq!(r.sol.outcome, Outcome::Feasible, "{}", r.sol.reason);
        let kkt = r.sol.sdp.measures.dimacs_max();
        assert!(kkt < 1e-11, "reference run: DIMACS errors up to {kkt:e}");
        let (t, t_ref) = (d.sol.margin.unwrap(), r.sol.margin.unwrap());
        assert!(
            (t - t_ref).abs() <= 1e-7 * t_ref,
            "window [{lo}, {hi}]: t* = {t:e} against the reference {t_ref:e}"
        );
    }
}
