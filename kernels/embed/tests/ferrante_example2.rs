//! Ferrante et al. (2016), Example 2 (mass–spring with sensor bias): eigenvalues, residues and
//! coefficient ranges against an independent reference implementation (numpy/scipy), and
//! containment of `e^{Av}` for random `v ∈ [0.2, 3]`.

use faer::{Mat, mat};
use sporadic_embed::{CoefficientFunction, Containment, Method, ResidueExpansion};
use sporadic_linalg::expm_scaled;

fn a_bar() -> Mat<f64> {
    let a = mat![
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [-2.0, 1.0, -1.0, 0.0],
        [2.0, -2.0, 0.0, -2.0],
    ];
    Mat::from_fn(5, 5, |i, j| if i < 4 && j < 4 { a[(i, j)] } else { 0.0 })
}

/// Index of the cluster whose centre is closest to `z`.
fn cluster_near(e: &ResidueExpansion, re: f64, im: f64) -> usize {
    let d = |k: usize| {
        let c = e.clusters()[k].centre();
        ((c.re - re).powi(2) + (c.im - im).powi(2)).sqrt()
    };
    (0..e.clusters().len())
        .min_by(|&x, &y| d(x).total_cmp(&d(y)))
        .unwrap()
}

#[test]
fn eigenvalues_and_residues() {
    let e = ResidueExpansion::new(a_bar().as_ref()).unwrap();
    assert!(
        e.projector_sum_error() < 1e-12,
        "{}",
        e.projector_sum_error()
    );
    // eig(Ā) = {0, −1, −0.6388969195, −0.6805515403 ± 1.6331702409 i}, all simple.
    let expected = [
        (0.0, 0.0),
        (-1.0, 0.0),
        (-0.638_896_919_5, 0.0),
        (-0.680_551_540_3, 1.633_170_240_9),
    ];
    assert_eq!(e.clusters().len(), 4);
    for &(re, im) in &expected {
        let c = &e.clusters()[cluster_near(&e, re, im)];
        assert!((c.centre().re - re).abs() < 1e-9 && (c.centre().im - im).abs() < 1e-9);
        assert_eq!(c.algebraic_multiplicity(), 1);
        assert!(c.is_nilpotent());
        assert_eq!(c.moment_count(), 1, "simple eigenvalue: one residue");
        assert_eq!(c.is_conjugate_pair(), im != 0.0);
    }
    // The bias eigenvalue 0 is exactly zero and its residue is e5 e5ᵀ.
    let zero = &e.clusters()[cluster_near(&e, 0.0, 0.0)];
    assert_eq!(zero.centre().re, 0.0);
    let r0 = zero.residue(1).unwrap();
    for i in 0..5 {
        for j in 0..5 {
            let want = if i == 4 && j == 4 { 1.0 } else { 0.0 };
            assert!((r0[(i, j)].re - want).abs() < 1e-12);
        }
    }
    // Residue of λ = −1 (4×4 block, padded with zeros).
    let r1 = e.clusters()[cluster_near(&e, -1.0, 0.0)]
        .residue(1)
        .unwrap();
    let want = [
        [0.0, -1.0, -1.0, -1.0],
        [0.0, -2.0, -2.0, -2.0],
        [0.0, 1.0, 1.0, 1.0],
        [0.0, 2.0, 2.0, 2.0],
    ];
    for i in 0..5 {
        for j in 0..5 {
            let w = if i < 4 && j < 4 { want[i][j] } else { 0.0 };
            assert!(
                (r1[(i, j)].re - w).abs() < 1e-10,
                "({i},{j}) {}",
                r1[(i, j)].re
            );
            assert_eq!(r1[(i, j)].im, 0.0);
        }
    }
    // Residue of λ = −0.63889692 (6 d.p.).
    let r2 = e.clusters()[cluster_near(&e, -0.638_896_919_5, 0.0)]
        .residue(1)
        .unwrap();
    let want = [
        [0.423531, 1.412259, 1.172881, 1.037584],
        [0.749350, 2.498700, 2.075169, 1.835790],
        [-0.270593, -0.902288, -0.749350, -0.662910],
        [-0.478757, -1.596412, -1.325819, -1.172881],
    ];
    for i in 0..4 {
        for j in 0..4 {
            assert!((r2[(i, j)].re - want[i][j]).abs() < 6e-7, "({i},{j})");
        }
    }
    // Complex residue (Im > 0 member): first rows of Re and Im parts.
    let rc = e.clusters()[cluster_near(&e, -0.68, 1.63)]
        .residue(1)
        .unwrap();
    let re_row = [0.288235, -0.206130, -0.086440, -0.018792];
    let im_row = [-0.202952, 0.115810, -0.193396, 0.111032];
    for j in 0..4 {
        assert!((rc[(0, j)].re - re_row[j]).abs() < 6e-7, "Re col {j}");
        assert!((rc[(0, j)].im - im_row[j]).abs() < 6e-7, "Im col {j}");
    }
}

#[test]
fn coefficient_ranges_and_sixteen_vertices() {
    let e = ResidueExpansion::new(a_bar().as_ref()).unwrap();
    let truncated = e.truncate(0.2, 3.0).unwrap();
    assert_eq!(truncated.terms.len(), 5, "K = deg minimal polynomial = 5");
    assert_eq!(truncated.remainder_bound, 0.0);
    let mut seen = 0;
    for t in &truncated.terms {
        let r = t.function.range(0.2, 3.0).unwrap();
        let close = |x: f64, y: f64| (x - y).abs() < 1e-8;
        match t.function {
            CoefficientFunction::Cosine { .. } => {
                assert!(close(r.min, -0.587_720_546_6) && close(r.max, 1.653_204_490_3));
                assert!((r.argmin - 1.681_863).abs() < 1e-6);
                seen += 1;
            }
            CoefficientFunction::Sine { .. } => {
                assert!(close(r.min, -1.130_948_049_0) && close(r.max, 0.305_421_138_6));
                assert!((r.argmin - 0.720_055).abs() < 1e-6 && (r.argmax - 2.643_671).abs() < 1e-6);
                seen += 1;
            }
            CoefficientFunction::Real { lambda: 0.0, .. } => {
                assert!(r.is_degenerate() && r.lower == 1.0);
                seen += 1;
            }
            CoefficientFunction::Real { lambda, .. } if (lambda + 1.0).abs() < 1e-9 => {
                assert!(close(r.min, 0.049_787_068_4) && close(r.max, 0.818_730_753_1));
                seen += 1;
            }
            CoefficientFunction::Real { .. } => {
                assert!(close(r.min, 0.147_092_923_6) && close(r.max, 0.880_047_510_4));
                seen += 1;
            }
            CoefficientFunction::Centred { .. } => panic!("a window this long takes no series"),
        }
    }
    assert_eq!(seen, 5);

    let emb = e.embed(0.2, 3.0).unwrap();
    assert_eq!(
        emb.vertex_count(),
        16,
        "32 corners before removing the constant λ = 0 term"
    );
    assert_eq!(emb.containment(), &Containment::Guaranteed);
    assert_eq!(emb.remainder_bound(), 0.0);
    match emb.method() {
        Method::Residue {
            terms,
            free_terms,
            reconstruction_error,
            projector_sum_error,
        } => {
            assert_eq!((*terms, *free_terms), (5, 4));
            assert!(*reconstruction_error < 1e-10, "{reconstruction_error}");
            assert!(*projector_sum_error < 1e-10);
        }
        m => panic!("unexpected method {m:?}"),
    }
}

/// For 10⁴ random v ∈ [0.2, 3] the box coefficients c_k(v) lie in their
/// ranges (which is the paper's containment proof) and the expansion reproduces e^{Av}
/// (to 1e-12 relative); a sample is also checked by solving the hull problem.
#[test]
fn random_instants_are_contained() {
    let a = a_bar();
    let e = ResidueExpansion::new(a.as_ref()).unwrap();
    let truncated = e.truncate(0.2, 3.0).unwrap();
    let ranges: Vec<_> = truncated
        .terms
        .iter()
        .map(|t| t.function.range(0.2, 3.0).unwrap())
        .collect();
    let emb = e.embed(0.2, 3.0).unwrap();
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut worst: f64 = 0.0;
    for k in 0..10_000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let v = 0.2 + 2.8 * ((state >> 11) as f64 / (1u64 << 53) as f64);
        let mut approx = Mat::<f64>::zeros(5, 5);
        for (t, r) in truncated.terms.iter().zip(&ranges) {
            let c = t.function.eval(v);
            assert!(r.lower <= c && c <= r.upper, "{:?} at v = {v}", t.function);
            approx += faer::Scale(c) * &t.matrix;
        }
        if k % 10 == 0 {
            let exact = expm_scaled(a.as_ref(), v).unwrap();
            worst = worst.max((&approx - &exact).norm_l2() / exact.norm_l2());
        }
        if k % 500 == 0 {
            assert!(emb.contains(v).unwrap(), "v = {v}");
        }
    }
    assert!(worst < 1e-12, "reconstruction error {worst}");
}
