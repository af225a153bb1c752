//! Proposition 1: at a fixed v, condition (12) holds iff some F makes (36)
//! negative definite; and the congruence of (39) with S = [(I − LM); I] reproduces (12) exactly.
//! The oracle for (12) is a direct eigenvalue computation; the one for (36) an SDP in F alone.

use faer::Mat;
use sporadic_linalg::{expm_scaled, lyap_discrete, max_eigenvalue, spectral_radius};
use sporadic_sdp::lmi::{Expr, FeasibilityOptions, Model, Normalisation, Outcome};
use sporadic_sim::SimRng;

fn random(rng: &mut SimRng, r: usize, c: usize, s: f64) -> Mat<f64> {
    Mat::from_fn(r, c, |_, _| rng.uniform(-s, s))
}

fn sym(m: &Mat<f64>) -> Mat<f64> {
    Mat::from_fn(m.nrows(), m.ncols(), |i, j| 0.5 * (m[(i, j)] + m[(j, i)]))
}

/// λmax of (12)'s left-hand side, normalised by ‖P‖.
fn condition12(e: &Mat<f64>, reset: &Mat<f64>, p: &Mat<f64>) -> f64 {
    let er = e * reset;
    let lhs = sym(&(er.transpose() * p * &er - p));
    max_eigenvalue(lhs.as_ref()).unwrap() / max_eigenvalue(p.as_ref()).unwrap()
}

/// Whether (36) with P, L fixed is strictly feasible in F (margin problem, F normalised generously).
fn lmi36_feasible(e: &Mat<f64>, reset: &Mat<f64>, p: &Mat<f64>) -> bool {
    let n = p.nrows();
    let mut m = Model::new();
    let f = m.full("F", n, n);
    let ep = e.transpose() * p;
    let phi = Expr::sym_blocks(&[
        vec![Some(-f.expr().he()), None, None],
        vec![
            Some((&f * reset.clone()).t()),
            Some(Expr::constant((-p).as_ref())),
            None,
        ],
        vec![
            Some(Expr::constant(ep.transpose().as_ref())),
            None,
            Some(Expr::constant((-p).as_ref())),
        ],
    ]);
    m.constrain(phi.lt(0.0).named("(36)")).unwrap();
    let opts = FeasibilityOptions::default().normalise(&f, Normalisation::Norm(1e3));
    let sol = m.feasibility(&opts).unwrap();
    assert_ne!(sol.outcome, Outcome::Inconclusive, "{}", sol.reason);
    sol.outcome == Outcome::Feasible
}

#[test]
fn lmi36_is_equivalent_to_condition12_at_fixed_v() {
    let mut rng = SimRng::new(36);
    let (mut yes, mut no) = (0, 0);
    let mut tested = 0;
    while tested < 30 {
        let n = 2 + (tested % 2);
        // Shifted left so that the closed loop is Schur in a fair share of the instances.
        let a = random(&mut rng, n, n, 1.0) - Mat::<f64>::identity(n, n);
        let mm = random(&mut rng, 1, n, 1.0);
        let l = random(&mut rng, n, 1, 1.0);
        let v = rng.uniform(0.2, 1.5);
        let e = expm_scaled(a.as_ref(), v).unwrap();
        let reset = Mat::<f64>::identity(n, n) - &l * &mm;
        let closed = &e * &reset;
        // Half of the instances use the discrete Lyapunov P of a Schur closed loop (then (12) holds).
        let p = if spectral_radius(closed.as_ref()).unwrap() < 0.95 && rng.uniform01() < 0.7 {
            lyap_discrete(closed.as_ref(), Mat::<f64>::identity(n, n).as_ref()).unwrap()
        } else {
            let b = random(&mut rng, n, n, 1.0);
            &b * b.transpose() + Mat::<f64>::identity(n, n) * 0.3
        };
        let p = sym(&p);
        let c12 = condition12(&e, &reset, &p);
        if c12.abs() < 0.02 {
            continue; // too close to the boundary for a tolerance-free verdict
        }
        tested += 1;
        let feasible = lmi36_feasible(&e, &reset, &p);
        assert_eq!(
            feasible,
            c12 < 0.0,
            "instance {tested}: λmax(12)/‖P‖ = {c12}"
        );
        if feasible { yes += 1 } else { no += 1 }
    }
    assert!(
        yes >= 5 && no >= 5,
        "unbalanced sample: {yes} feasible, {no} infeasible"
    );
}

#[test]
fn congruence_of_39_reproduces_condition12() {
    let mut rng = SimRng::new(39);
    for _ in 0..50 {
        let n = 3;
        let a = random(&mut rng, n, n, 1.0);
        let mm = random(&mut rng, 2, n, 1.0);
        let l = random(&mut rng, n, 2, 1.0);
        let f = random(&mut rng, n, n, 2.0);
        let b = random(&mut rng, n, n, 1.0);
        let p = &b * b.transpose() + Mat::<f64>::identity(n, n);
        let e = expm_scaled(a.as_ref(), rng.uniform(0.1, 2.0)).unwrap();
        let reset = Mat::<f64>::identity(n, n) - &l * &mm;
        let fh = &f + f.transpose();
        let top_left = e.transpose() * &p * &e - &fh;
        let top_right = &f * &reset; // F − FLM
        let m39 = faer::concat![[top_left, top_right.clone()], [top_right.transpose(), -&p]];
        let s = faer::concat![[reset.clone()], [Mat::<f64>::identity(n, n)]];
        let congr = s.transpose() * &m39 * &s;
        let er = &e * &reset;
        let c12 = er.transpose() * &p * &er - &p;
        let scale = c12.norm_max().max(1.0);
        assert!(
            (&congr - &c12).norm_max() <= 1e-12 * scale * 10.0,
            "{:e}",
            (&congr - &c12).norm_max()
        );
    }
}
