//! Taylor embedding on the example of Rabehi et al. (2021), §V (Taylor polytope of §IV):
//! `Ā = [[A^M, A^N], [A^N, A^M]]` of the spring–mass–damper with `c_s = 1`, `[τmin, τmax] =
//! [0.04, 0.3]`.

use faer::{Mat, MatRef, mat};
use sporadic_embed::{
    Containment, EmbedError, EmbeddingMethod, Method, TaylorOptions, TaylorOrder, embed_split,
    taylor_embedding, taylor_weights, truncation_tail,
};
use sporadic_linalg::expm_scaled;

fn a_bar() -> Mat<f64> {
    mat![
        [0.0, 1.0, 0.0, 0.0],
        [0.0, -1.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0, -1.0],
    ]
}

fn spectral_norm(m: MatRef<'_, f64>) -> f64 {
    m.singular_values().unwrap().into_iter().fold(0.0, f64::max)
}

#[test]
fn spec_remainder_numbers() {
    // ‖E0‖(e^{‖Ā‖h} − Σ_{k≤8}(‖Ā‖h)^k/k!) = 1.2e-9 on [0.04, 0.3] and 4.4e-4 on [0.04, 1.1]
    // (spectral norms; independent reference implementation).
    let a = a_bar();
    let na = spectral_norm(a.as_ref());
    let e0 = spectral_norm(expm_scaled(a.as_ref(), 0.04).unwrap().as_ref());
    let short = e0 * truncation_tail(na * 0.26, 8);
    let long = e0 * truncation_tail(na * 1.06, 8);
    assert!((short / 1.2e-9 - 1.0).abs() < 0.05, "{short:e}");
    assert!((long / 4.4e-4 - 1.0).abs() < 0.05, "{long:e}");
}

#[test]
fn automatic_order_meets_1e_8() {
    let a = a_bar();
    let opts = TaylorOptions {
        order: TaylorOrder::Tolerance(1e-8),
        ..TaylorOptions::default()
    };
    let e = taylor_embedding(a.as_ref(), 0.04, 0.3, &opts).unwrap();
    let Method::Taylor { order } = *e.method() else {
        panic!("{:?}", e.method())
    };
    assert!(e.remainder_bound() < 1e-8 && e.remainder_bound() > 0.0);
    assert_eq!(e.vertex_count(), order + 1);
    assert_eq!(e.containment(), &Containment::Guaranteed);
    // Minimality: one order less misses the tolerance.
    let lower = TaylorOptions {
        order: TaylorOrder::Fixed(order - 1),
        ..opts
    };
    let e_lower = taylor_embedding(a.as_ref(), 0.04, 0.3, &lower).unwrap();
    assert!(e_lower.remainder_bound() > 1e-8);
    // First vertex is e^{Ā τmin} (the factor must be kept: a polytope containing I would make the
    // LMIs (44) infeasible).
    let e0 = expm_scaled(a.as_ref(), 0.04).unwrap();
    assert_eq!(e.vertices()[0], e0);
    assert!(order <= 8, "order {order}");
}

/// Σ_j w_j M_j reproduces e^{Āμ} within the remainder bound, weights ≥ 0 summing to 1; every μ
/// is contained up to the remainder. The "≈ 4e-10 observed, N = 8" of the independent reference
/// implementation is the largest entry of the error (3.77e-10 here); its Frobenius/spectral norm
/// is 1.02e-9.
#[test]
fn weights_reproduce_the_exponential() {
    let a = a_bar();
    let opts = TaylorOptions {
        order: TaylorOrder::Fixed(8),
        ..TaylorOptions::default()
    };
    let e = taylor_embedding(a.as_ref(), 0.04, 0.3, &opts).unwrap();
    assert_eq!(e.vertex_count(), 9);
    let mut worst: f64 = 0.0;
    let mut worst_entry: f64 = 0.0;
    for k in 0..=100 {
        let mu = 0.04 + 0.26 * f64::from(k) / 100.0;
        let w = taylor_weights((mu - 0.04) / 0.26, 8);
        assert!(w.iter().all(|&x| x >= 0.0));
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        let mut comb = Mat::<f64>::zeros(4, 4);
        for (wj, mj) in w.iter().zip(e.vertices()) {
            comb += faer::Scale(*wj) * mj;
        }
        let exact = expm_scaled(a.as_ref(), mu).unwrap();
        let err = (&comb - &exact).norm_l2();
        assert!(
            err <= e.remainder_bound(),
            "μ = {mu}: {err:e} > {:e}",
            e.remainder_bound()
        );
        worst = worst.max(err);
        worst_entry = worst_entry.max((&comb - &exact).norm_max());
        if k % 20 == 0 {
            assert!(e.contains(mu).unwrap());
        }
    }
    assert!(
        worst > 5e-10 && worst < 1.2e-9,
        "observed truncation error {worst:e}"
    );
    assert!(
        (worst_entry / 4e-10 - 1.0).abs() < 0.1,
        "largest entry error {worst_entry:e}"
    );
}

#[test]
fn splitting_grows_vertices_linearly_and_tightens_the_remainder() {
    let a = a_bar();
    let opts = TaylorOptions {
        order: TaylorOrder::Fixed(6),
        ..TaylorOptions::default()
    };
    let method = EmbeddingMethod::Taylor(opts);
    let whole = embed_split(a.as_ref(), 0.04, 1.1, 1, &method).unwrap();
    let split = embed_split(a.as_ref(), 0.04, 1.1, 4, &method).unwrap();
    assert_eq!(whole.vertex_count(), 7);
    assert_eq!(split.vertex_count(), 28);
    assert_eq!(split.pieces().len(), 4);
    assert!(split.remainder_bound() < whole.remainder_bound() / 100.0);
    for k in 0..=10 {
        assert!(split.contains(0.04 + 1.06 * f64::from(k) / 10.0).unwrap());
    }
}

#[test]
fn unreachable_tolerance_is_an_error() {
    // ‖A‖h = 200: the partial sums lose everything to cancellation.
    let a = mat![[0.0, 5.0], [-5.0, -0.1]];
    let r = taylor_embedding(a.as_ref(), 0.0, 40.0, &TaylorOptions::default());
    assert!(
        matches!(r, Err(EmbedError::ToleranceUnreachable { .. })),
        "{r:?}"
    );
    // Splitting into short pieces makes it reachable.
    let e = embed_split(
        a.as_ref(),
        0.0,
        40.0,
        200,
        &EmbeddingMethod::Taylor(TaylorOptions::default()),
    )
    .unwrap();
    assert!(e.remainder_bound() <= 1e-10);
    assert!(e.contains(17.3).unwrap());
}
