//! Repeated, defective and clustered eigenvalues in the residue embedding (nearly repeated
//! eigenvalues give huge cancelling residues; defective ones are computed only to ~`ε^{1/m}`):
//! closed-form references for defective matrices, the reconstruction
//! self-check, and honest containment statements when the self-check fails.

mod common;

use common::lp_hull_membership;
use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, Scale, mat};
use sporadic_embed::{Containment, Method, ResidueExpansion, ResidueOptions};

/// A fixed, well-conditioned similarity `S` (entries `I + small`), and its inverse.
fn similarity(n: usize) -> (Mat<f64>, Mat<f64>) {
    let s = Mat::from_fn(n, n, |i, j| {
        let off = 0.3 * (((3 * i + 5 * j) % 7) as f64 / 7.0 - 0.5);
        if i == j { 1.0 + off } else { off }
    });
    let inv = s.partial_piv_lu().inverse();
    (s, inv)
}

fn residue_numbers(m: &Method) -> (usize, usize, f64) {
    match *m {
        Method::Residue {
            terms,
            free_terms,
            reconstruction_error,
            ..
        } => (terms, free_terms, reconstruction_error),
        ref other => panic!("not a residue embedding: {other:?}"),
    }
}

/// `A = S N S⁻¹`, `N` a nilpotent Jordan block of order 3: computed eigenvalues are spread by
/// about `u^{1/3}`, yet the expansion must be the finite series `e^{Av} = I + vA + v²A²/2`.
#[test]
fn nilpotent_under_similarity() {
    let (s, inv) = similarity(3);
    let n = mat![[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]];
    let a = &s * &n * &inv;
    let a2 = &a * &a;
    let exp = ResidueExpansion::new(a.as_ref()).unwrap();
    assert_eq!(exp.clusters().len(), 1);
    let c = &exp.clusters()[0];
    assert!(c.is_nilpotent());
    assert_eq!(c.moment_count(), 3, "index of 0 in the minimal polynomial");
    let e = exp.embed(0.5, 2.0).unwrap();
    assert_eq!(e.containment(), &Containment::Guaranteed);
    assert_eq!(e.vertex_count(), 4);
    // Closed form: c1 = v ∈ [0.5, 2], c2 = v²/2 ∈ [0.125, 2]; the box margins are ≤ 1e-11.
    let tol = 1e-10 * a.norm_l2().max(1.0);
    for (c1, c2) in [(0.5, 0.125), (2.0, 0.125), (0.5, 2.0), (2.0, 2.0)] {
        let want = Mat::<f64>::identity(3, 3) + Scale(c1) * &a + Scale(c2) * &a2;
        assert!(
            e.vertices().iter().any(|x| (x - &want).norm_l2() < tol),
            "missing vertex ({c1}, {c2})"
        );
    }
    for k in 0..=6 {
        assert!(e.contains(0.5 + 0.25 * f64::from(k)).unwrap());
    }
}

/// `A = S (J₃(−1) ⊕ (−2)) S⁻¹`: the defective eigenvalue −1 (index 3) gets three residues, the
/// simple one a single residue, so `K = 4`, 16 vertices, and the reconstruction matches the
/// closed form `S (e^{−v}[[1, v, v²/2], [0, 1, v], [0, 0, 1]] ⊕ e^{−2v}) S⁻¹`.
#[test]
fn defective_eigenvalue_closed_form() {
    let (s, inv) = similarity(4);
    let j = mat![
        [-1.0, 1.0, 0.0, 0.0],
        [0.0, -1.0, 1.0, 0.0],
        [0.0, 0.0, -1.0, 0.0],
        [0.0, 0.0, 0.0, -2.0],
    ];
    let a = &s * &j * &inv;
    let exact = |v: f64| {
        let e1 = (-v).exp();
        let ej = mat![
            [e1, v * e1, 0.5 * v * v * e1, 0.0],
            [0.0, e1, v * e1, 0.0],
            [0.0, 0.0, e1, 0.0],
            [0.0, 0.0, 0.0, (-2.0 * v).exp()],
        ];
        &s * ej * &inv
    };
    let exp = ResidueExpansion::new(a.as_ref()).unwrap();
    let mut counts: Vec<(f64, usize, bool)> = exp
        .clusters()
        .iter()
        .map(|c| (c.centre().re, c.moment_count(), c.is_nilpotent()))
        .collect();
    counts.sort_by(|x, y| x.0.total_cmp(&y.0));
    assert_eq!(counts.len(), 2, "{counts:?}");
    assert!((counts[0].0 + 2.0).abs() < 1e-12 && counts[0].1 == 1 && counts[0].2);
    assert!((counts[1].0 + 1.0).abs() < 1e-5 && counts[1].1 == 3 && counts[1].2);
    let (t1, t2) = (0.2, 3.0);
    let truncated = exp.truncate(t1, t2).unwrap();
    assert_eq!(truncated.terms.len(), 4);
    let mut worst: f64 = 0.0;
    for k in 0..=280 {
        let v = t1 + 0.01 * f64::from(k);
        let mut sum = Mat::<f64>::zeros(4, 4);
        for t in &truncated.terms {
            sum += Scale(t.function.eval(v)) * &t.matrix;
        }
        let e = exact(v);
        worst = worst.max((&sum - &e).norm_l2() / e.norm_l2());
    }
    assert!(
        worst < 1e-10,
        "reconstruction error against the closed form: {worst:e}"
    );
    let emb = exp.embed(t1, t2).unwrap();
    assert_eq!(emb.containment(), &Containment::Guaranteed);
    assert_eq!(emb.vertex_count(), 16);
    let (terms, free, recon) = residue_numbers(emb.method());
    assert_eq!((terms, free), (4, 4));
    assert!(recon < 1e-10, "{recon:e}");
    for v in [0.2, 0.9, 1.7, 3.0] {
        let lp = lp_hull_membership(emb.vertices(), &exact(v));
        assert!(lp.violation(0.0) <= 1e-9, "v = {v}: {lp:?}");
    }
}

/// Nearly repeated eigenvalues −1 and −1 − 3e-7 (residues ∝ 1/gap that cancel). Default options
/// merge them into one cluster with moderate vertices; keeping them apart (huge projector
/// limit, and no power series of the whole spectrum on this short window) gives cancelling
/// residues of size ~1/gap, the reconstruction self-check fails, and the result must say so
/// instead of claiming `Guaranteed`.
#[test]
fn nearly_repeated_eigenvalues() {
    let gap = 3e-7;
    let a = mat![[-1.0, 1.0], [0.0, -1.0 - gap]];
    let (t1, t2) = (0.2, 3.0);

    let merged = ResidueExpansion::new(a.as_ref()).unwrap();
    assert_eq!(merged.clusters().len(), 1);
    let emb = merged.embed(t1, t2).unwrap();
    assert_eq!(emb.containment(), &Containment::Guaranteed);
    let biggest = emb
        .vertices()
        .iter()
        .map(|x| x.norm_l2())
        .fold(0.0, f64::max);
    assert!(
        biggest < 10.0,
        "merged cluster: vertices stay moderate, got {biggest:e}"
    );
    assert!(emb.vertex_count() <= 4);

    let apart = ResidueExpansion::with_options(
        a.as_ref(),
        ResidueOptions {
            max_projector_norm: 1e300,
            short_window_series: false,
            ..ResidueOptions::default()
        },
    )
    .unwrap();
    assert_eq!(apart.clusters().len(), 2);
    let emb = apart.embed(t1, t2).unwrap();
    let biggest = emb
        .vertices()
        .iter()
        .map(|x| x.norm_l2())
        .fold(0.0, f64::max);
    assert!(biggest > 1e5, "residues ∝ 1/gap: {biggest:e}");
    let (_, _, recon) = residue_numbers(emb.method());
    assert!(
        recon > 1e-10,
        "cancellation must show in the self-check: {recon:e}"
    );
    assert!(
        !emb.containment().is_guaranteed(),
        "{:?}",
        emb.containment()
    );
    // The curve is inside the (huge) box all the same: the statement is the grid verification.
    match emb.containment() {
        Containment::VerifiedOnGrid { points, max_error } => {
            assert_eq!(*points, ResidueOptions::default().check_points);
            assert!(*max_error <= 1e-9);
        }
        other => panic!("expected a grid verification, got {other:?}"),
    }
}

/// A wrong nilpotency decision (tolerance 1 treats the Jordan block's nilpotent part as zero)
/// drops the `v e^{−v}` term: the vertices `e^{−v} I` cannot contain `e^{Av}`, and the result
/// must be `NotGuaranteed` with the numbers, never a silent polytope.
#[test]
fn failed_self_check_is_reported() {
    let a = mat![[-1.0, 1.0], [0.0, -1.0]];
    let exp = ResidueExpansion::with_options(
        a.as_ref(),
        ResidueOptions {
            nilpotency_tolerance: 1.0,
            ..ResidueOptions::default()
        },
    )
    .unwrap();
    let emb = exp.embed(0.2, 3.0).unwrap();
    let (terms, _, recon) = residue_numbers(emb.method());
    assert_eq!(terms, 1);
    // The dropped term is v e^{−v} in entry (0, 1): relative error up to 1/√(2 + 1) at v = 1.
    assert!(recon > 0.5, "{recon:e}");
    let Containment::NotGuaranteed { reason } = emb.containment() else {
        panic!("{:?}", emb.containment())
    };
    assert!(reason.contains("self-check failed"), "{reason}");
    // Independent confirmation that the curve leaves the hull.
    let e = sporadic_linalg::expm_scaled(a.as_ref(), 1.0).unwrap();
    let lp = lp_hull_membership(emb.vertices(), &e);
    let d = emb.hull_distance(1.0).unwrap();
    assert!(d.lower_bound > 0.3, "{d:?}");
    assert!(lp.residual >= d.lower_bound * (1.0 - 1e-12), "{lp:?} {d:?}");
    assert!(!emb.contains(1.0).unwrap());
    assert!(emb.max_violation(&[0.5, 1.0, 2.0]).unwrap() > 0.1);
}
