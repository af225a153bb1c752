//! Jacobian polytope of Etienne et al. (2017), Lemma 1, on the flexible-joint robot of their
//! Section 4, and on random boxes.

use faer::{Mat, mat};
use proptest::prelude::*;
use sporadic_embed::{EmbedError, jacobian_polytope, lipschitz_box};
use sporadic_linalg::InputError;

fn robot_a() -> Mat<f64> {
    mat![
        [0.0, 1.0, 0.0, 0.0],
        [-48.6, -1.25, 48.6, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [19.5, 0.0, -19.5, 0.0],
    ]
}

/// Eigenvalues sorted by (real, imaginary) part.
fn sorted_eigs(m: &Mat<f64>) -> Vec<(f64, f64)> {
    let mut e: Vec<(f64, f64)> = m
        .eigenvalues()
        .unwrap()
        .iter()
        .map(|z| (z.re, z.im))
        .collect();
    e.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1)));
    e
}

fn assert_eigs(m: &Mat<f64>, expected: &[(f64, f64)]) {
    let mut want = expected.to_vec();
    want.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1)));
    let got = sorted_eigs(m);
    for (g, w) in got.iter().zip(&want) {
        assert!(
            (g.0 - w.0).abs() < 1e-4 && (g.1 - w.1).abs() < 1e-4,
            "{got:?} vs {want:?}"
        );
    }
}

#[test]
fn flexible_joint_vertices() {
    let a = robot_a();
    let g = Mat::from_fn(4, 1, |i, _| if i == 3 { 1.0 } else { 0.0 });
    let h = Mat::from_fn(1, 4, |_, j| if j == 2 { 1.0 } else { 0.0 });
    let (lo, hi) = lipschitz_box(1, 3.3).unwrap();
    let p =
        jacobian_polytope(a.as_ref(), g.as_ref(), h.as_ref(), lo.as_ref(), hi.as_ref()).unwrap();
    assert_eq!(p.vertex_count(), 2);
    assert_eq!(p.free_entries(), &[(0, 0)]);
    for (v, entry) in p.vertices().iter().zip([-22.8, -16.2]) {
        for i in 0..4 {
            for j in 0..4 {
                let want = if (i, j) == (3, 2) { entry } else { a[(i, j)] };
                assert!((v[(i, j)] - want).abs() < 1e-13, "({i},{j})");
            }
        }
    }
    // Eigenvalues of the two vertices (4 d.p.; computed, not printed in the paper).
    assert_eigs(
        &p.vertices()[0],
        &[
            (-0.4324, 8.2793),
            (-0.4324, -8.2793),
            (-0.1926, 1.5153),
            (-0.1926, -1.5153),
        ],
    );
    assert_eigs(
        &p.vertices()[1],
        &[
            (-0.4572, 8.1659),
            (-0.4572, -8.1659),
            (1.3897, 0.0),
            (-1.7252, 0.0),
        ],
    );
    // The same polytope from G = H = I with a Jacobian box fixed to zero except entry (3,2).
    let eye = Mat::<f64>::identity(4, 4);
    let lo4 = Mat::from_fn(4, 4, |i, j| if (i, j) == (3, 2) { -3.3 } else { 0.0 });
    let hi4 = Mat::from_fn(4, 4, |i, j| if (i, j) == (3, 2) { 3.3 } else { 0.0 });
    let q = jacobian_polytope(
        a.as_ref(),
        eye.as_ref(),
        eye.as_ref(),
        lo4.as_ref(),
        hi4.as_ref(),
    )
    .unwrap();
    assert_eq!(q.free_entries(), &[(3, 2)]);
    assert_eq!(q.vertices(), p.vertices());
    // φ'(s) = 3.3 cos s for any s gives a matrix in the polytope.
    for s in [0.0, 0.7, 2.0, 3.1] {
        let theta = Mat::from_fn(1, 1, |_, _| 3.3 * f64::cos(s));
        assert!(p.in_box(theta.as_ref()));
        assert!(p.hull_distance(theta.as_ref()).unwrap().distance < 1e-12);
    }
}

#[test]
fn fixed_entries_and_bad_input() {
    let a = Mat::<f64>::zeros(2, 2);
    let g = Mat::<f64>::identity(2, 2);
    let h = Mat::<f64>::identity(2, 2);
    // Entry (0,1) fixed at 0.5, entry (1,0) free: two vertices containing the fixed value.
    let lo = mat![[0.0, 0.5], [-1.0, 0.0]];
    let hi = mat![[0.0, 0.5], [1.0, 0.0]];
    let p =
        jacobian_polytope(a.as_ref(), g.as_ref(), h.as_ref(), lo.as_ref(), hi.as_ref()).unwrap();
    assert_eq!(p.vertex_count(), 2);
    assert_eq!(p.vertices()[0], mat![[0.0, 0.5], [-1.0, 0.0]]);
    assert_eq!(p.vertices()[1], mat![[0.0, 0.5], [1.0, 0.0]]);

    let bad = mat![[0.0, 0.6], [-1.0, 0.0]];
    assert!(matches!(
        jacobian_polytope(
            a.as_ref(),
            g.as_ref(),
            h.as_ref(),
            bad.as_ref(),
            hi.as_ref()
        ),
        Err(EmbedError::InvalidBounds { row: 0, col: 1, .. })
    ));
    let g3 = Mat::<f64>::identity(3, 2);
    assert!(matches!(
        jacobian_polytope(
            a.as_ref(),
            g3.as_ref(),
            h.as_ref(),
            lo.as_ref(),
            hi.as_ref()
        ),
        Err(EmbedError::Input(InputError::DimensionMismatch { .. }))
    ));
    let nan = mat![[0.0, f64::NAN], [-1.0, 0.0]];
    assert!(matches!(
        jacobian_polytope(
            a.as_ref(),
            g.as_ref(),
            h.as_ref(),
            nan.as_ref(),
            hi.as_ref()
        ),
        Err(EmbedError::Input(InputError::NonFinite { .. }))
    ));
    assert!(lipschitz_box(2, -1.0).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    /// A random m×m box with k free entries gives 2^k distinct vertices, and
    /// A + GΘH for a random Θ in the box lies in their hull.
    #[test]
    fn random_boxes(seed in any::<u64>(), n in 1usize..5, m in 1usize..4) {
        let mut s = seed;
        let mut rnd = move || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let a = Mat::from_fn(n, n, |_, _| 2.0 * rnd() - 1.0);
        let g = Mat::from_fn(n, m, |_, _| 2.0 * rnd() - 1.0);
        let h = Mat::from_fn(m, n, |_, _| 2.0 * rnd() - 1.0);
        let free = Mat::from_fn(m, m, |_, _| rnd() < 0.6);
        let lo = Mat::from_fn(m, m, |_, _| -rnd());
        let hi = Mat::from_fn(m, m, |i, j| if free[(i, j)] { rnd() } else { lo[(i, j)] });
        let p = jacobian_polytope(a.as_ref(), g.as_ref(), h.as_ref(), lo.as_ref(), hi.as_ref()).unwrap();
        let k = (0..m).flat_map(|i| (0..m).map(move |j| (i, j))).filter(|&(i, j)| free[(i, j)]).count();
        prop_assert_eq!(p.vertex_count(), 1 << k);
        prop_assert_eq!(p.free_entries().len(), k);
        let theta = Mat::from_fn(m, m, |i, j| lo[(i, j)] + rnd() * (hi[(i, j)] - lo[(i, j)]));
        prop_assert!(p.in_box(theta.as_ref()));
        let d = p.hull_distance(theta.as_ref()).unwrap();
        let scale = p.vertices().iter().map(|v| v.norm_l2()).fold(1.0, f64::max);
        prop_assert!(d.distance <= 1e-10 * scale, "{:?}", d);
    }
}
