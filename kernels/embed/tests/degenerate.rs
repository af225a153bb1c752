//! Degenerate inputs: T1 = T2, invalid windows and matrices, A = 0, nilpotent and scalar A.

use faer::{Mat, mat};
use sporadic_embed::{
    Containment, EmbedError, EmbeddingMethod, Method, ResidueExpansion, ResidueOptions,
    TaylorOptions, embed_split, residue_embedding, taylor_embedding,
};
use sporadic_linalg::InputError;
use sporadic_linalg::expm_scaled;

fn methods() -> [EmbeddingMethod; 2] {
    [
        EmbeddingMethod::Residue(ResidueOptions::default()),
        EmbeddingMethod::Taylor(TaylorOptions::default()),
    ]
}

#[test]
fn periodic_window_gives_exactly_one_vertex() {
    let a = mat![[0.0, 1.0, 0.0], [-2.0, -0.5, 1.0], [0.3, 0.0, -1.0]];
    let exact = expm_scaled(a.as_ref(), 0.7).unwrap();
    for m in methods() {
        for pieces in [1, 3] {
            let e = embed_split(a.as_ref(), 0.7, 0.7, pieces, &m).unwrap();
            assert_eq!(e.vertex_count(), 1);
            assert_eq!(e.vertices()[0], exact, "bitwise e^(A T1)");
            assert_eq!(e.containment(), &Containment::Guaranteed);
            assert_eq!(e.remainder_bound(), 0.0);
        }
    }
}

#[test]
fn invalid_windows_are_rejected() {
    let a = mat![[-1.0, 0.0], [0.0, -2.0]];
    for (t1, t2) in [
        (0.5, 0.2),
        (-0.1, 0.3),
        (-1e-300, 0.0),
        (f64::NAN, 1.0),
        (0.1, f64::NAN),
        (f64::NAN, f64::NAN),
        (0.0, f64::INFINITY),
        (f64::NEG_INFINITY, 1.0),
    ] {
        assert!(matches!(
            residue_embedding(a.as_ref(), t1, t2),
            Err(EmbedError::Input(InputError::InvalidWindow { .. }))
        ));
        assert!(matches!(
            taylor_embedding(a.as_ref(), t1, t2, &TaylorOptions::default()),
            Err(EmbedError::Input(InputError::InvalidWindow { .. }))
        ));
        for m in methods() {
            assert!(matches!(
                embed_split(a.as_ref(), t1, t2, 2, &m),
                Err(EmbedError::Input(InputError::InvalidWindow { .. }))
            ));
        }
    }
    // T1 = 0 is a valid window for the embedding itself.
    let e = residue_embedding(a.as_ref(), 0.0, 1.0).unwrap();
    // Queries at a non-finite τ are errors, not panics or `false`.
    for tau in [f64::NAN, f64::INFINITY] {
        assert!(matches!(
            e.contains(tau),
            Err(EmbedError::Input(InputError::NonFinite { .. }))
        ));
        assert!(matches!(
            e.hull_distance(tau),
            Err(EmbedError::Input(InputError::NonFinite { .. }))
        ));
        assert!(matches!(
            e.max_violation(&[0.5, tau]),
            Err(EmbedError::Input(InputError::NonFinite { .. }))
        ));
    }
    for m in methods() {
        assert!(matches!(
            embed_split(a.as_ref(), 0.1, 1.0, 0, &m),
            Err(EmbedError::InvalidArgument(_))
        ));
    }
}

#[test]
fn invalid_matrices_are_rejected() {
    let rect = Mat::<f64>::zeros(2, 3);
    let empty = Mat::<f64>::zeros(0, 0);
    let nan = mat![[0.0, f64::NAN], [0.0, 0.0]];
    let inf = mat![[f64::INFINITY]];
    for m in methods() {
        assert!(matches!(
            embed_split(rect.as_ref(), 0.1, 1.0, 1, &m),
            Err(EmbedError::Input(InputError::NotSquare {
                rows: 2,
                cols: 3,
                ..
            }))
        ));
        assert!(matches!(
            embed_split(empty.as_ref(), 0.1, 1.0, 1, &m),
            Err(EmbedError::Input(InputError::Empty { .. }))
        ));
        assert!(matches!(
            embed_split(nan.as_ref(), 0.1, 1.0, 1, &m),
            Err(EmbedError::Input(InputError::NonFinite { .. }))
        ));
        assert!(matches!(
            embed_split(inf.as_ref(), 0.1, 1.0, 1, &m),
            Err(EmbedError::Input(InputError::NonFinite { .. }))
        ));
    }
    let bad = ResidueOptions {
        check_points: 1,
        ..ResidueOptions::default()
    };
    assert!(matches!(
        ResidueExpansion::with_options(mat![[1.0]].as_ref(), bad),
        Err(EmbedError::InvalidArgument(_))
    ));
}

#[test]
fn zero_matrix_gives_the_identity() {
    let a = Mat::<f64>::zeros(3, 3);
    let eye = Mat::<f64>::identity(3, 3);
    for m in methods() {
        let e = embed_split(a.as_ref(), 0.2, 3.0, 1, &m).unwrap();
        assert_eq!(e.vertex_count(), 1, "{m:?}");
        assert_eq!(e.vertices()[0], eye);
        assert_eq!(e.containment(), &Containment::Guaranteed);
        assert!(e.contains(1.3).unwrap());
    }
}

#[test]
fn nilpotent_matrix() {
    // N = Jordan block of 0: e^{Nv} = I + vN + v²/2 N², minimal polynomial s³.
    let n = mat![[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]];
    let exp = ResidueExpansion::new(n.as_ref()).unwrap();
    assert_eq!(exp.clusters().len(), 1);
    let c = &exp.clusters()[0];
    assert_eq!(c.centre().re, 0.0);
    assert!(c.is_nilpotent());
    assert_eq!(c.moment_count(), 3, "index of 0 in the minimal polynomial");
    let e = exp.embed(0.5, 2.0).unwrap();
    // Coefficients 1 (constant), v ∈ [0.5, 2], v²/2 ∈ [0.125, 2]: 4 vertices.
    assert_eq!(e.vertex_count(), 4);
    assert_eq!(e.containment(), &Containment::Guaranteed);
    let vertex = |c1: f64, c2: f64| mat![[1.0, c1, c2], [0.0, 1.0, c1], [0.0, 0.0, 1.0]];
    for (c1, c2) in [(0.5, 0.125), (2.0, 0.125), (0.5, 2.0), (2.0, 2.0)] {
        let want = vertex(c1, c2);
        assert!(
            e.vertices().iter().any(|x| (x - &want).norm_max() < 1e-10),
            "missing vertex ({c1}, {c2})"
        );
    }
    for k in 0..=6 {
        assert!(e.contains(0.5 + 0.25 * f64::from(k)).unwrap());
    }
    // Taylor: (Nh)^k = 0 exactly for k ≥ 3, so higher-order vertices are duplicates.
    let t = taylor_embedding(n.as_ref(), 0.5, 2.0, &TaylorOptions::default()).unwrap();
    assert_eq!(t.vertex_count(), 3);
    assert!(t.remainder_bound() < 1e-10);
    assert!(t.contains(1.1).unwrap());
}

#[test]
fn repeated_diagonalizable_eigenvalue_keeps_one_term() {
    // A = −I: e^{Av} = e^{−v} I, a segment with 2 vertices (no v e^{−v} term).
    let a = Mat::from_fn(3, 3, |i, j| if i == j { -1.0 } else { 0.0 });
    let e = residue_embedding(a.as_ref(), 0.2, 3.0).unwrap();
    assert_eq!(e.vertex_count(), 2);
    let Method::Residue { terms, .. } = *e.method() else {
        panic!()
    };
    assert_eq!(terms, 1);
    // Similar matrix S(−I)S⁻¹ = −I as well; a block diag(−1, −1, −2) keeps 2 terms.
    let b = mat![[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -2.0]];
    let e = residue_embedding(b.as_ref(), 0.2, 3.0).unwrap();
    assert_eq!(e.vertex_count(), 4);
    let exp = ResidueExpansion::new(b.as_ref()).unwrap();
    let double = exp
        .clusters()
        .iter()
        .find(|c| (c.centre().re + 1.0).abs() < 1e-12)
        .unwrap();
    assert_eq!(double.algebraic_multiplicity(), 2);
    assert_eq!(double.moment_count(), 1);
}

#[test]
fn scalar_unstable_system() {
    // Ferrante Example 1 data: A = 1, window [1, 1] and [0.5, 2].
    let a = mat![[1.0]];
    let e = residue_embedding(a.as_ref(), 1.0, 1.0).unwrap();
    assert_eq!(e.vertices()[0][(0, 0)], std::f64::consts::E);
    let e = residue_embedding(a.as_ref(), 0.5, 2.0).unwrap();
    assert_eq!(e.vertex_count(), 2);
    let lo = e
        .vertices()
        .iter()
        .map(|x| x[(0, 0)])
        .fold(f64::INFINITY, f64::min);
    let hi = e
        .vertices()
        .iter()
        .map(|x| x[(0, 0)])
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(lo <= 0.5f64.exp() && (lo - 0.5f64.exp()).abs() < 1e-11);
    assert!(hi >= 2.0f64.exp() && (hi - 2.0f64.exp()).abs() < 1e-11);
}
