//! Exact LTI propagation versus closed forms, Van Loan discretisations and the adaptive integrator.

use faer::{Mat, mat};
use proptest::prelude::*;
use sporadic_sim::{
    Dopri5, Dopri5Options, Exosystem, InputSignal, LtiFlow, PiecewiseConstant, TransitionTable,
    integrate_flow,
};

/// Mass–spring system of Ferrante et al. (2016), Example 2, augmented with the constant sensor bias.
fn mass_spring_bias() -> Mat<f64> {
    mat![
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, 0.0],
        [-2.0, 1.0, -1.0, 0.0, 0.0],
        [2.0, -2.0, 0.0, -2.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0],
    ]
}

#[test]
fn exosystem_input_matches_closed_form() {
    // ẋ = a x + b sin(ωt): x(t) = e^{at}(x0 − b·xp(0)) + b·xp(t), xp(t) = −(a sin ωt + ω cos ωt)/(a² + ω²).
    let (a, b, w, x0) = (-0.7, 2.5, 3.0, 1.3);
    let xp = |t: f64| -(a * (w * t).sin() + w * (w * t).cos()) / (a * a + w * w);
    let flow = LtiFlow::new(mat![[a]].as_ref())
        .unwrap()
        .with_input(
            mat![[b]].as_ref(),
            InputSignal::Exosystem(Exosystem::sinusoid_sum(&[(1.0, w, 0.0)]).unwrap()),
        )
        .unwrap();
    let mut prop = flow.propagator().unwrap();
    let mut x = [x0];
    let mut t = 0.0;
    // Uneven steps, so the tracked exosystem state is exercised too.
    for k in 0..300 {
        let tau = 0.01 + 0.003 * (k % 7) as f64;
        prop.advance(t, &mut x, tau).unwrap();
        t += tau;
        let exact = (a * t).exp() * (x0 - b * xp(0.0)) + b * xp(t);
        assert!((x[0] - exact).abs() < 1e-12, "t = {t}: {} vs {exact}", x[0]);
    }
}

#[test]
fn piecewise_constant_input_matches_van_loan_zoh() {
    // Between switches, x⁺ = e^{Aτ} x + (∫₀^τ e^{As} ds B) u (zero-order hold, sporadic_linalg::zoh).
    let a = mass_spring_bias();
    let b = mat![[0.0], [0.0], [1.0], [0.0], [0.0]];
    let starts = vec![0.0, 0.4, 1.1, 1.5];
    let values = vec![vec![1.0], vec![-2.0], vec![0.5], vec![3.0]];
    let pwc = PiecewiseConstant::new(starts.clone(), values.clone()).unwrap();
    let flow = LtiFlow::new(a.as_ref())
        .unwrap()
        .with_input(b.as_ref(), InputSignal::PiecewiseConstant(pwc))
        .unwrap();
    let x0 = [0.3, -0.2, 0.1, 0.5, 1.0];
    let got = flow.propagate(0.0, &x0, 2.3).unwrap();
    // Reference: chain of ZOH steps over the segments [0,0.4], [0.4,1.1], [1.1,1.5], [1.5,2.3].
    let mut x = Mat::<f64>::from_fn(5, 1, |i, _| x0[i]);
    let ends = [0.4, 1.1, 1.5, 2.3];
    for k in 0..4 {
        let (ad, bd) = flow.zoh(0, ends[k] - starts[k]).unwrap();
        x = &ad * &x + Mat::<f64>::from_fn(5, 1, |i, _| bd[(i, 0)] * values[k][0]);
    }
    for i in 0..5 {
        assert!(
            (got[i] - x[(i, 0)]).abs() < 1e-12,
            "component {i}: {} vs {}",
            got[i],
            x[(i, 0)]
        );
    }
}

/// Integrates `flow` with DP5 from `x0` over `[0, t_end]`, stopping at the flow's breakpoints.
fn integrate(flow: &LtiFlow, x0: &[f64], t_end: f64) -> Vec<f64> {
    let mut dp = Dopri5::new(Dopri5Options::with_tolerances(1e-12, 1e-14)).unwrap();
    let mut x = x0.to_vec();
    let (t, _) = integrate_flow(flow, &mut dp, 0.0, &mut x, t_end, &[], |_| {}).unwrap();
    assert_eq!(t, t_end);
    x
}

#[test]
fn exact_flow_agrees_with_dopri5() {
    // Ferrante Example 2 with u = sin t (exosystem), a piecewise-constant disturbance and a constant term.
    let a = mass_spring_bias();
    let b = mat![[0.0], [0.0], [1.0], [0.0], [0.0]];
    let d = PiecewiseConstant::new(
        vec![0.0, 0.7, 1.3, 2.9],
        vec![
            vec![0.1, -0.3],
            vec![0.2, 0.0],
            vec![-0.4, 0.5],
            vec![0.0, 0.1],
        ],
    )
    .unwrap();
    let bd = mat![[1.0, 0.0], [0.0, 1.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]];
    let flow = LtiFlow::new(a.as_ref())
        .unwrap()
        .with_input(
            b.as_ref(),
            InputSignal::Exosystem(Exosystem::sinusoid_sum(&[(1.0, 1.0, 0.0)]).unwrap()),
        )
        .unwrap()
        .with_input(bd.as_ref(), InputSignal::PiecewiseConstant(d))
        .unwrap()
        .with_affine(vec![0.0, 0.05, 0.0, -0.05, 0.0])
        .unwrap();
    let x0 = [1.0, -0.5, 0.2, 0.0, 1.0];
    for &t_end in &[0.5, 2.0, 4.0] {
        let exact = flow.propagate(0.0, &x0, t_end).unwrap();
        let num = integrate(&flow, &x0, t_end);
        for i in 0..5 {
            assert!(
                (exact[i] - num[i]).abs() < 1e-9,
                "t = {t_end}, x{i}: exact {} vs DP5 {}",
                exact[i],
                num[i]
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// The transition table reproduces a direct matrix exponential for random matrices and times.
    #[test]
    fn table_matches_direct_expm(
        entries in proptest::collection::vec(-3.0f64..3.0, 9),
        v in proptest::collection::vec(-1.0f64..1.0, 3),
        tau in 0.0f64..4.0,
    ) {
        let a = Mat::<f64>::from_fn(3, 3, |i, j| entries[3 * i + j]);
        let e = sporadic_linalg::expm_scaled(a.as_ref(), tau).unwrap();
        let mut tab = TransitionTable::new(a.as_ref()).unwrap();
        let mut w = v.clone();
        tab.apply(tau, &mut w).unwrap();
        let scale = (0..3).map(|i| (0..3).map(|k| (e[(i, k)] * v[k]).abs()).sum::<f64>()).fold(1.0, f64::max);
        for i in 0..3 {
            let expect: f64 = (0..3).map(|k| e[(i, k)] * v[k]).sum();
            prop_assert!((w[i] - expect).abs() <= 1e-12 * scale, "{} vs {}", w[i], expect);
        }
    }
}
