//! Contois bioreactor (Section 4 of Andrieu et al. 2014, corrected normal form) with placeholder
//! reproduction settings (input profile, domain, initial conditions are not in the paper).

mod common;

use proptest::prelude::*;
use sporadic_andrieu2014::bioreactor::{
    self, BioreactorNormalForm, Contois, DEFAULT_GRID, F2Form, Scenario, final_substrate_error,
    normal_form_deviation, phi, printed_tuning, substrate_errors,
};
use sporadic_andrieu2014::system::{incremental_bound_ratio, triangularity_defect};
use sporadic_andrieu2014::{Error, Run, RunOptions, TriangularSystem, Tuning, run};
use sporadic_linalg::InputError;
use sporadic_sim::{BoundedUniform, NoiseSource, PiecewiseConstant, ZeroNoise};

fn system(form: F2Form) -> (Scenario, BioreactorNormalForm) {
    let sc = Scenario::placeholder();
    let sys = BioreactorNormalForm::new(sc.s_in, sc.domain, form, DEFAULT_GRID).unwrap();
    (sc, sys)
}

fn simulate(k: [f64; 2], alpha: f64, noise: &mut dyn NoiseSource) -> (Run, Tuning) {
    let tuning = Tuning::new(k.to_vec(), alpha, 1.0, 0.1, 0.1).unwrap();
    (
        bioreactor::simulate(&Scenario::placeholder(), &tuning, noise).unwrap(),
        tuning,
    )
}

/// The corrected normal form integrated from Φ(z0) stays on Φ(z(t)); the printed f2 does not.
#[test]
fn d1_normal_form_matches_the_model() {
    let sc = Scenario::placeholder();
    let corrected = normal_form_deviation(&sc, F2Form::Corrected, 1e-11).unwrap();
    let printed = normal_form_deviation(&sc, F2Form::Printed, 1e-11).unwrap();
    println!("D1: max |Φ(z) − x| corrected {corrected:.2e}, printed {printed:.2e}");
    assert!(
        corrected < 1e-10,
        "corrected normal form deviates by {corrected}"
    );
    assert!(
        printed > 1e-3,
        "printed normal form should deviate, got {printed}"
    );
}

/// Noise-free convergence and the structural invariants: K = [−2, −1]', α = 0.5, a1 = 1,
/// a2 = a3 = 0.1.
#[test]
fn d2_noise_free_convergence_and_invariants() {
    let (r, tuning) = simulate([-2.0, -1.0], 0.5, &mut ZeroNoise::new(1));
    common::assert_invariants(&r, &tuning, 1e-7);
    let dmin = r
        .samples
        .iter()
        .map(|s| s.delta)
        .fold(f64::INFINITY, f64::min);
    let dmax = r.samples.iter().map(|s| s.delta).fold(0.0, f64::max);
    let errs = substrate_errors(&r);
    let late = errs
        .iter()
        .filter(|(t, _)| *t >= 20.0)
        .map(|e| e.1)
        .fold(0.0, f64::max);
    let fin = final_substrate_error(&r);
    println!(
        "D2: {} corrections, δ in [{dmin:.3}, {dmax:.3}], max |S−Ŝ| on [20, 40] {late:.2e}, at 40 {fin:.2e}",
        r.samples.len()
    );
    // Independent reference implementation: 147 sampling instants (t_0 = 0 included; 146
    // corrections), δ in [0.22, 0.42].
    let instants = r.sampling_times().len();
    assert_eq!(instants, r.samples.len() + 1);
    assert!(
        (146..=148).contains(&instants),
        "{instants} sampling instants"
    );
    assert!(dmin >= 0.2 && dmax <= 0.45, "δ range [{dmin}, {dmax}]");
    assert!(
        fin < 1e-8 && late < 1e-8,
        "|S − Ŝ| = {fin} at 40, {late} on [20, 40]"
    );
    // The plant stays in the invariant domain M_z the Lipschitz function c is computed on.
    let domain = Scenario::placeholder().domain;
    for (_, z) in r.arc.iter() {
        assert!(
            domain.contains_z(&[z[0], z[1]], 0.0),
            "plant left M_z: {z:?}"
        );
    }
    // The estimate really had to converge: the initial substrate error is 0.03.
    assert!(errs[0].1 > 1e-3);
}

/// Bounded output noise |v| ≤ 1e-3 keeps the error at the noise level after the transient.
#[test]
fn d3_bounded_noise_gives_bounded_error() {
    let bound = 1e-3;
    let mut noise = BoundedUniform::symmetric(vec![bound], 2014).unwrap();
    let (r, tuning) = simulate([-2.0, -1.0], 0.5, &mut noise);
    common::assert_invariants(&r, &tuning, 1e-7);
    let after: Vec<_> = r.samples.iter().filter(|s| s.t >= 10.0).collect();
    let e_max = after
        .iter()
        .flat_map(|s| s.error())
        .map(f64::abs)
        .fold(0.0, f64::max);
    let s_max = substrate_errors(&r)
        .iter()
        .filter(|(t, _)| *t >= 10.0)
        .map(|e| e.1)
        .fold(0.0, f64::max);
    let noise_max = after
        .iter()
        .map(|s| (s.y - s.output).abs())
        .fold(0.0, f64::max);
    println!(
        "D3: max |v| {noise_max:.2e}, max ‖e_k‖∞ {e_max:.2e}, max |S − Ŝ| {s_max:.2e} on [10, 40]"
    );
    assert!(noise_max <= bound && noise_max > 0.5 * bound);
    assert!(
        e_max <= 2.0 * bound && e_max > 0.1 * bound,
        "‖e‖∞ = {e_max}"
    );
    assert!(s_max <= 1e-2, "|S − Ŝ| = {s_max}");
}

/// The printed gain and α do not converge (`K = [−2, 1]'` makes `A + KC` unstable; `α = 0.9` is
/// beyond the Schur limit `2√2 − 2 ≈ 0.828` of `Q(α)` for `K = [−2, −1]'`); the corrected ones do.
#[test]
fn d4_printed_parameters_do_not_converge() {
    let printed = printed_tuning();
    let (sc, sys) = system(F2Form::Corrected);
    let r = run(
        &Contois { s_in: sc.s_in },
        &sc.z0,
        &sys,
        &sc.xhat0,
        &sc.input,
        &printed,
        &mut ZeroNoise::new(1),
        &RunOptions::new(40.0),
    )
    .unwrap();
    common::assert_invariants(&r, &printed, 1e-7);
    let late = |r: &Run| {
        substrate_errors(r)
            .iter()
            .filter(|(t, _)| *t >= 20.0)
            .map(|e| e.1)
            .fold(0.0, f64::max)
    };
    let printed_late = late(&r);
    let (r09, _) = simulate([-2.0, -1.0], 0.9, &mut ZeroNoise::new(1));
    let (r08, _) = simulate([-2.0, -1.0], 0.8, &mut ZeroNoise::new(1));
    let (r11, _) = simulate([-1.0, -1.0], 0.9, &mut ZeroNoise::new(1));
    println!(
        "D4: max |S−Ŝ| on [20,40]: printed {printed_late:.2e}, K=[-2,-1] α=0.9 {:.2e}, α=0.8 {:.2e}, K=[-1,-1] α=0.9 {:.2e}",
        late(&r09),
        late(&r08),
        late(&r11)
    );
    assert!(printed_late > 1e-3 && final_substrate_error(&r) > 1e-3);
    assert!(
        late(&r09) > 1e-3,
        "α = 0.9 > 2√2 − 2 should not converge for K = [−2, −1]'"
    );
    assert!(late(&r08) < 1e-6 && final_substrate_error(&r08) < 1e-10);
    assert!(late(&r11) < 1e-8);
}

#[test]
fn bad_inputs_give_typed_errors() {
    let (sc, sys) = system(F2Form::Corrected);
    let plant = Contois { s_in: sc.s_in };
    let tuning = Tuning::new(vec![-2.0, -1.0], 0.5, 1.0, 0.1, 0.1).unwrap();
    let opts = RunOptions::new(1.0);
    let mut z = ZeroNoise::new(1);
    let go = |z0: &[f64],
              xhat0: &[f64],
              input: &PiecewiseConstant,
              t: &Tuning,
              noise: &mut dyn NoiseSource,
              o: &RunOptions| { run(&plant, z0, &sys, xhat0, input, t, noise, o) };
    assert!(matches!(
        go(&[0.06], &sc.xhat0, &sc.input, &tuning, &mut z, &opts),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        go(&sc.z0, &[0.1, f64::NAN], &sc.input, &tuning, &mut z, &opts),
        Err(Error::Input(InputError::NonFinite { .. }))
    ));
    let t3 = Tuning::new(vec![-3.0, -3.0, -1.0], 0.5, 1.0, 0.1, 0.1).unwrap();
    assert!(matches!(
        go(&sc.z0, &sc.xhat0, &sc.input, &t3, &mut z, &opts),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    let no_input = PiecewiseConstant::constant(vec![]).unwrap();
    assert!(matches!(
        go(&sc.z0, &sc.xhat0, &no_input, &tuning, &mut z, &opts),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        go(
            &sc.z0,
            &sc.xhat0,
            &sc.input,
            &tuning,
            &mut ZeroNoise::new(2),
            &opts
        ),
        Err(Error::Input(InputError::DimensionMismatch { .. }))
    ));
    let bad_l0 = RunOptions {
        l0: 0.5,
        ..RunOptions::new(1.0)
    };
    assert!(matches!(
        go(&sc.z0, &sc.xhat0, &sc.input, &tuning, &mut z, &bad_l0),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));
    let bad_h = RunOptions::new(f64::NAN);
    assert!(matches!(
        go(&sc.z0, &sc.xhat0, &sc.input, &tuning, &mut z, &bad_h),
        Err(Error::Input(InputError::InvalidParameter { .. }))
    ));

    /// A system whose "Lipschitz estimate" goes negative: must be rejected with a typed error.
    struct NegativeC;
    impl TriangularSystem for NegativeC {
        fn order(&self) -> usize {
            2
        }
        fn input_dim(&self) -> usize {
            0
        }
        fn nonlinearity(&self, _x: &[f64], _u: &[f64], out: &mut [f64]) {
            out.fill(0.0);
        }
        fn lipschitz(&self, xhat: &[f64], _u: &[f64]) -> f64 {
            xhat[1]
        }
    }
    let plant = sporadic_andrieu2014::NormalFormPlant(NegativeC);
    let r = run(
        &plant,
        &[0.0, 1.0],
        &NegativeC,
        &[0.0, -1.0],
        &no_input,
        &tuning,
        &mut z,
        &opts,
    );
    assert!(
        matches!(r, Err(Error::NegativeLipschitz { c, .. }) if c < 0.0),
        "{r:?}"
    );
    /// A system with a finite escape time (ẋ1 = x1² from x1 = 5): the run must fail with an error.
    struct Escape;
    impl TriangularSystem for Escape {
        fn order(&self) -> usize {
            2
        }
        fn input_dim(&self) -> usize {
            0
        }
        fn nonlinearity(&self, x: &[f64], _u: &[f64], out: &mut [f64]) {
            out[0] = x[0] * x[0];
            out[1] = 0.0;
        }
        fn lipschitz(&self, xhat: &[f64], _u: &[f64]) -> f64 {
            2.0 * xhat[0].abs()
        }
    }
    let escape = sporadic_andrieu2014::NormalFormPlant(Escape);
    let r = run(
        &escape,
        &[5.0, 0.0],
        &Escape,
        &[5.0, 0.0],
        &no_input,
        &tuning,
        &mut z,
        &opts,
    );
    assert!(
        matches!(
            r,
            Err(Error::Sim(_)) | Err(Error::Input(InputError::NonFinite { .. }))
        ),
        "{r:?}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Assumption 1 centred at the estimate holds for the corrected c on M_x (x̂ anywhere, x in M_x),
    /// and f is lower-triangular.
    #[test]
    fn corrected_lipschitz_bound_holds_on_the_domain(
        x_s in (0.0f64..1.0, 0.0f64..1.0),
        xh in (-0.2f64..1.2, -0.2f64..0.5),
        u in 0.1f64..0.9,
    ) {
        let (sc, sys) = system(F2Form::Corrected);
        let d = sc.domain;
        // A point of M_z: X in [ε1, 1 − ε2], S in [ε2, 1 − X].
        let x_big = d.eps1 + x_s.0 * (1.0 - d.eps2 - d.eps1);
        let s = d.eps2 + x_s.1 * (1.0 - x_big - d.eps2);
        let x = phi(&[x_big, s]);
        // Estimate: projected onto M_x as the observer does.
        let xhat = d.project(&[xh.0, xh.1]);
        let e = [xhat[0] - x[0], xhat[1] - x[1]];
        let ratio = incremental_bound_ratio(&sys, &xhat, &e, &[u]).unwrap();
        prop_assert!(ratio <= 1.0 + 1e-6, "ratio {ratio} at x = {x:?}, x̂ = {xhat:?}");
        prop_assert_eq!(triangularity_defect(&sys, &x, &[0.0, 0.3], &[u]).unwrap(), 0.0);
    }
}
