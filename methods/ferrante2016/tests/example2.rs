//! Example 2 of Ferrante et al. (2016): mass–spring system with sensor bias, T1 = 0.2, T2 = 3.
//! Expected values: the paper (published L, feasibility of (41) on [0.2, 3]) and independent
//! [ours] numbers (Python/scipy/Clarabel).

use approx::assert_relative_eq;
use sporadic_embed::Containment;
use sporadic_ferrante2016::examples::example2;
use sporadic_ferrante2016::{
    DesignOptions, LmiForm, VerifyOptions, analyse, check_bound, design, simulate_error, verify,
};
use sporadic_sim::{Periodic, SimOptions, SimRng, UniformRandom};

/// The paper's construction: LMI (41) as printed (the library's default is its reduced form).
fn paper() -> DesignOptions {
    DesignOptions {
        form: LmiForm::Corollary1,
        ..DesignOptions::default()
    }
}

#[test]
fn design_is_feasible_and_verified() {
    let ex = example2().unwrap();
    let d = design(&ex.plant, &ex.window, &paper()).unwrap();
    // K = 5 coefficients, the λ = 0 one constant ⇒ 16 distinct vertices, 15×15 LMIs.
    assert_eq!(d.embedding.vertex_count(), 16);
    assert_eq!(d.embedding.containment(), &Containment::Guaranteed);
    assert_eq!(d.size.lmi_count, 16);
    assert_eq!(d.size.block_size, 15);
    assert_eq!(d.stats.decision_scalars, 15 + 25 + 5);
    assert!(d.certificate.margin > 0.0);
    // the returned L passes the 2801-point grid test of (12) (done inside design, redone here).
    let v = verify(
        &ex.plant,
        &ex.window,
        d.l.as_ref(),
        d.certificate.p.as_ref(),
        &VerifyOptions::default(),
    )
    .unwrap();
    assert_eq!(v.grid_points, 2801);
    assert!(
        v.passed() && v.max_eigenvalue < 0.0 && v.max_spectral_radius < 1.0,
        "{v:?}"
    );
    // L = F⁻¹J.
    let fl = &d.certificate.f * &d.l;
    for i in 0..5 {
        assert_relative_eq!(fl[(i, 0)], d.certificate.j[(i, 0)], epsilon = 1e-10);
    }
}

#[test]
fn embedding_contains_the_exponential_curve() {
    // Reduced sample: e^{Av} ∈ co{X_i} for random v ∈ [0.2, 3] (the embedding is of the
    // normalised problem, whose time unit is `d.scaling.time`).
    let ex = example2().unwrap();
    let d = design(&ex.plant, &ex.window, &paper()).unwrap();
    let mut rng = SimRng::new(5);
    for _ in 0..200 {
        let v = rng.uniform(0.2, 3.0);
        assert!(
            d.embedding.contains(v / d.scaling.time).unwrap(),
            "e^(Av) outside the polytope at v = {v}"
        );
    }
}

#[test]
fn paper_gain_is_certified() {
    // Reference value (±1e-4).
    let ex = example2().unwrap();
    let a = analyse(&ex.plant, &ex.window, ex.l_paper.as_ref(), &paper()).unwrap();
    assert!(a.certified, "{:?}", a.stats);
    let v = a.verification.unwrap();
    assert_eq!(v.grid_points, 2801);
    assert!(v.max_eigenvalue < 0.0);
    assert_relative_eq!(v.max_spectral_radius, 0.95882, epsilon = 1e-4);
    assert!(
        (v.max_spectral_radius_at - 0.2).abs() < 1e-9,
        "at v = {}",
        v.max_spectral_radius_at
    );
    // M·L_paper = 0.99993.
    assert_relative_eq!(
        ex.l_paper[(0, 0)] + ex.l_paper[(4, 0)],
        0.99993,
        epsilon = 1e-12
    );
}

fn sq_ratio(arc: &sporadic_sim::HybridArc) -> f64 {
    let (_, last) = arc.last().unwrap();
    let n = |x: &[f64]| x.iter().map(|v| v * v).sum::<f64>();
    n(last) / n(arc.state(0))
}

#[test]
fn simulated_error_converges_with_the_published_gain() {
    let ex = example2().unwrap();
    // Slowest case: all intervals 0.2, ε0 = ones: 3.86e-6 after 100 jumps.
    let arc = simulate_error(
        &ex.plant,
        ex.l_paper.as_ref(),
        &mut Periodic::new(0.2).unwrap(),
        &[1.0; 5],
        &SimOptions::jumps(100),
    )
    .unwrap();
    assert_eq!(arc.num_jumps(), 100);
    assert_relative_eq!(sq_ratio(&arc), 3.86e-6, max_relative = 5e-3);
    // Uniform intervals, 5 random initial errors: ≲ 1e-16 after 100 jumps (reference: 1e-16…1e-20).
    let mut rng = SimRng::new(7);
    for seed in 0..5u64 {
        let eps0: Vec<f64> = (0..5).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let mut rule = UniformRandom::new(0.2, 3.0, seed).unwrap();
        let arc = simulate_error(
            &ex.plant,
            ex.l_paper.as_ref(),
            &mut rule,
            &eps0,
            &SimOptions::jumps(100),
        )
        .unwrap();
        let r = sq_ratio(&arc);
        assert!(r < 1e-12, "seed {seed}: ratio {r:e}");
    }
}

#[test]
fn simulated_error_converges_with_our_gain_within_the_bound() {
    let ex = example2().unwrap();
    let d = design(&ex.plant, &ex.window, &paper()).unwrap();
    let k = sporadic_ferrante2016::bound_constants(
        &ex.plant,
        &ex.window,
        d.l.as_ref(),
        d.certificate.p.as_ref(),
        &Default::default(),
    )
    .unwrap();
    for seed in 0..3u64 {
        let mut rule = UniformRandom::new(0.2, 3.0, seed)
            .unwrap()
            .with_first_window(0.0, 3.0)
            .unwrap();
        let arc = simulate_error(
            &ex.plant,
            d.l.as_ref(),
            &mut rule,
            &[1.0, -1.0, 0.5, 0.0, 1.0],
            &SimOptions::jumps(100).record(sporadic_sim::Record::Every(0.05)),
        )
        .unwrap();
        let check = check_bound(&arc, &k.theorem1).unwrap();
        assert!(check.max_ratio <= 1.0, "seed {seed}: {check:?}");
        assert!(
            sq_ratio(&arc) < 1e-12,
            "seed {seed}: ratio {:e}",
            sq_ratio(&arc)
        );
    }
}

#[test]
fn taylor_and_split_embeddings_are_selectable() {
    use sporadic_embed::{EmbeddingMethod, TaylorOptions};
    let ex = example2().unwrap();
    // Residue box on 2 pieces: twice the vertices, still verified.
    let split = DesignOptions {
        pieces: 2,
        ..paper()
    };
    let d = design(&ex.plant, &ex.window, &split).unwrap();
    assert_eq!(d.embedding.vertex_count(), 32);
    assert_eq!(d.embedding.pieces().len(), 2);
    assert!(d.verification.passed());
    // Taylor polytope (with a rigorous remainder ⇒ the robust 4n × 4n form with multiplier μ).
    let taylor = DesignOptions {
        embedding: EmbeddingMethod::Taylor(TaylorOptions::default()),
        pieces: 4,
        ..paper()
    };
    let d = design(&ex.plant, &ex.window, &taylor).unwrap();
    assert!(d.embedding.remainder_bound() > 0.0);
    assert_eq!(d.size.block_size, 20);
    assert!(d.certificate.robust_multiplier.unwrap() > 0.0);
    assert!(d.verification.passed());
    // The reduced 2n × 2n vertex form has the same feasible set: it certifies the published gain too.
    let reduced = DesignOptions {
        form: LmiForm::Reduced,
        ..paper()
    };
    let d = design(&ex.plant, &ex.window, &reduced).unwrap();
    assert_eq!(d.size.block_size, 10);
    assert!(d.verification.passed());
    let a = analyse(&ex.plant, &ex.window, ex.l_paper.as_ref(), &reduced).unwrap();
    assert!(a.certified);
}

#[test]
fn bound_constants_of_the_spec_certificate() {
    // Independent [ours] values: for L_paper, the certificate P of `min tr P s.t. P ⪰ I, Φ_i ⪯ −I` (J = F·L_paper)
    // gives α1 ≈ 0.01567, α2 ≈ 712.35, β ≈ 2.895, θ ≈ −0.004072 (scipy + Clarabel). Re-solve that
    // objective-mode SDP on our 16 vertices and compare the constants (4 printed digits).
    use sporadic_sdp::lmi::{Expr, Model, SolveOptions};
    let ex = example2().unwrap();
    let emb = sporadic_embed::residue_embedding(ex.plant.a(), 0.2, 3.0).unwrap();
    assert_eq!(emb.vertex_count(), 16);
    let mut m = Model::new();
    let p = m.symmetric("P", 5);
    let f = m.full("F", 5, 5);
    let reset = ex.plant.reset_matrix(ex.l_paper.as_ref()).unwrap();
    m.constrain(p.ge(1.0).named("P ⪰ I")).unwrap();
    for (i, x) in emb.vertices().iter().enumerate() {
        let phi = Expr::sym_blocks(&[
            vec![Some(-f.expr().he()), None, None],
            vec![Some((&f * reset.clone()).t()), Some(-&p), None],
            vec![Some(&p * x.clone()), None, Some(-&p)],
        ]);
        m.constrain(phi.le(-1.0).named(format!("Phi_{i}"))).unwrap();
    }
    m.minimize(p.trace()).unwrap();
    let sol = m.solve(&SolveOptions::default()).unwrap();
    eprintln!(
        "{:?} {} obj {:?} iters {}",
        sol.outcome, sol.reason, sol.objective, sol.sdp.iterations
    );
    let pv = sol.value(&p).unwrap();
    let k = sporadic_ferrante2016::bound_constants(
        &ex.plant,
        &ex.window,
        ex.l_paper.as_ref(),
        pv.as_ref(),
        &Default::default(),
    )
    .unwrap()
    .theorem1;
    eprintln!("{k:?}");
    assert_relative_eq!(k.alpha1, 0.01567, max_relative = 5e-4);
    assert_relative_eq!(k.alpha2, 712.35, max_relative = 5e-5);
    assert_relative_eq!(k.beta, 2.895, max_relative = 5e-4);
    assert_relative_eq!(k.theta, -0.004072, max_relative = 5e-4);
}
