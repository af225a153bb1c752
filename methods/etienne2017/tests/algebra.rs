//! The Lemma 1 vertices of the example, the vertex set of a random
//! Jacobian box, and the algebraic identities of the proof of Theorem 3 on random data.

use faer::{Mat, MatRef, mat};
use proptest::prelude::*;
use sporadic_etienne2017::conditions::{
    flow_block, flow_vertex_blocks, gain_from, interpolate, jump_block, jump_block_high,
    jump_block_low, jump_decrease, lyapunov_matrix,
};
use sporadic_etienne2017::{Plant, SamplingWindow, example};
use sporadic_sim::SimRng;

fn max_abs_diff(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> f64 {
    assert_eq!((a.nrows(), a.ncols()), (b.nrows(), b.ncols()));
    (0..a.nrows())
        .flat_map(|i| (0..a.ncols()).map(move |j| (a[(i, j)] - b[(i, j)]).abs()))
        .fold(0.0, f64::max)
}

/// Sorted (re, im) eigenvalues.
fn eigs(r: &Mat<f64>) -> Vec<(f64, f64)> {
    let mut e: Vec<(f64, f64)> = r
        .eigenvalues()
        .unwrap()
        .iter()
        .map(|z| (z.re, z.im))
        .collect();
    e.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    e
}

#[test]
fn example_vertices_match_the_dmvt_vertices() {
    let plant = example::flexible_joint().unwrap();
    let r = plant.vertices();
    assert_eq!(r.len(), 2);
    // Entry (4,3): −19.5 ∓ 3.3; everything else equal to A.
    for (v, expect) in [(0, -22.8), (1, -16.2)] {
        for i in 0..4 {
            for j in 0..4 {
                let want = if (i, j) == (3, 2) {
                    expect
                } else {
                    plant.a()[(i, j)]
                };
                assert!((r[v][(i, j)] - want).abs() < 1e-12, "R_{} ({i},{j})", v + 1);
            }
        }
    }
    // Eigenvalues of the DMVT vertices (4 decimals).
    let e1 = [
        (-0.4324, -8.2793),
        (-0.4324, 8.2793),
        (-0.1926, -1.5153),
        (-0.1926, 1.5153),
    ];
    let e2 = [
        (-1.7252, 0.0),
        (-0.4572, -8.1659),
        (-0.4572, 8.1659),
        (1.3897, 0.0),
    ];
    for (got, want) in [(eigs(&r[0]), e1), (eigs(&r[1]), e2)] {
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g.0 - w.0).abs() < 1e-4 && (g.1 - w.1).abs() < 1e-4,
                "{g:?} vs {w:?}"
            );
        }
    }
}

#[test]
fn expm_of_vertex_matches_reference() {
    // Reference value of e^{0.3 R_2}, row-major, 6 significant figures.
    let plant = example::flexible_joint().unwrap();
    let e = sporadic_linalg::expm_scaled(plant.vertices()[1].as_ref(), 0.3).unwrap();
    let reference = mat![
        [-0.130035, 0.117380, 1.171707, 0.149894],
        [-2.781727, -0.276759, 3.276377, 1.171707],
        [0.545308, 0.060143, 0.588648, 0.247445],
        [1.902258, 0.470130, -1.085687, 0.588648],
    ];
    assert!(max_abs_diff(e.as_ref(), reference.as_ref()) < 1e-6);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// A random box with k free entries (the others fixed, some at zero) has 2^k distinct
    /// vertices, and A + GΘH for a random interior Θ lies in their convex hull.
    #[test]
    fn random_box_vertices(seed in any::<u64>(), n in 2usize..5, m in 1usize..4) {
        let mut rng = SimRng::new(seed);
        let a = Mat::from_fn(n, n, |_, _| rng.uniform(-2.0, 2.0));
        let b = Mat::<f64>::zeros(n, 1);
        let c = Mat::from_fn(1, n, |_, _| rng.uniform(-1.0, 1.0));
        let g = Mat::from_fn(n, m, |_, _| rng.uniform(-1.0, 1.0));
        let h = Mat::from_fn(m, n, |_, _| rng.uniform(-1.0, 1.0));
        let mut lo = Mat::<f64>::zeros(m, m);
        let mut hi = Mat::<f64>::zeros(m, m);
        let mut k = 0;
        for i in 0..m {
            for j in 0..m {
                match rng.next_u64() % 3 {
                    0 => {} // structurally zero
                    1 => { let v = rng.uniform(-1.0, 1.0); lo[(i, j)] = v; hi[(i, j)] = v; }
                    _ => { lo[(i, j)] = rng.uniform(-2.0, 0.0); hi[(i, j)] = lo[(i, j)] + rng.uniform(0.1, 2.0); k += 1; }
                }
            }
        }
        let plant = Plant::new(a.as_ref(), b.as_ref(), c.as_ref(), g.as_ref(), h.as_ref(), lo.as_ref(), hi.as_ref()).unwrap();
        let v = plant.vertices();
        prop_assert_eq!(v.len(), 1usize << k);
        for x in 0..v.len() {
            for y in 0..x {
                prop_assert!(max_abs_diff(v[x].as_ref(), v[y].as_ref()) > 1e-9);
            }
        }
        let theta = Mat::from_fn(m, m, |i, j| rng.uniform(lo[(i, j)], hi[(i, j)]));
        let d = plant.polytope().hull_distance(theta.as_ref()).unwrap();
        prop_assert!(d.distance < 1e-8, "distance {}", d.distance);
    }

    /// The identities of the proof of Theorem 3 (`P(τ)`, the flow block and `B(τ)` affine in `τ`) and the
    /// Schur form of (16c), on random data.
    #[test]
    fn theorem3_interpolation_identities(seed in any::<u64>(), n in 1usize..5, q in 1usize..3) {
        let mut rng = SimRng::new(seed);
        let sym = |rng: &mut SimRng| {
            let x = Mat::from_fn(n, n, |_, _| rng.uniform(-1.0, 1.0));
            &x * x.transpose() + Mat::<f64>::identity(n, n) * 0.1
        };
        let (p1, p2) = (sym(&mut rng), sym(&mut rng));
        let r = Mat::from_fn(n, n, |_, _| rng.uniform(-3.0, 3.0));
        let c = Mat::from_fn(q, n, |_, _| rng.uniform(-1.0, 1.0));
        let l0 = Mat::from_fn(n, q, |_, _| rng.uniform(-1.0, 1.0));
        let l1 = Mat::from_fn(n, q, |_, _| rng.uniform(-1.0, 1.0));
        let tau_low = rng.uniform(1e-3, 0.5);
        let tau_bar = tau_low + rng.uniform(0.01, 0.5);
        let w = SamplingWindow::new(tau_low, tau_bar).unwrap();
        let tau = rng.uniform(0.0, tau_bar);
        let s = tau / tau_bar;

        // 1. P(0) = P1, P(τ̄) = P2.
        prop_assert!(max_abs_diff(lyapunov_matrix(p1.as_ref(), p2.as_ref(), tau_bar, 0.0).unwrap().as_ref(), p1.as_ref()) < 1e-14);
        prop_assert!(max_abs_diff(lyapunov_matrix(p1.as_ref(), p2.as_ref(), tau_bar, tau_bar).unwrap().as_ref(), p2.as_ref()) < 1e-12);
        // 2. N(τ) = (1 − τ/τ̄) M¹ + (τ/τ̄) M², written out from He(·) directly.
        let (m1, m2) = flow_vertex_blocks(p1.as_ref(), p2.as_ref(), r.as_ref(), tau_bar).unwrap();
        let interp = &m1 * (1.0 - s) + &m2 * s;
        let nb = flow_block(p1.as_ref(), p2.as_ref(), r.as_ref(), tau_bar, tau).unwrap();
        prop_assert!(max_abs_diff(nb.as_ref(), interp.as_ref()) < 1e-10 * (1.0 + interp.norm_max()));
        let p_tau = &p1 * (1.0 - s) + &p2 * s;
        let direct = &p_tau * &r + r.transpose() * &p_tau + (&p2 - &p1) * (1.0 / tau_bar);
        prop_assert!(max_abs_diff(nb.as_ref(), direct.as_ref()) < 1e-10 * (1.0 + direct.norm_max()));
        // 3. B(τ) on [τ_low, τ̄] is the interpolation of (20c) and (20d).
        let tj = rng.uniform(tau_low, tau_bar);
        let sj = (tj - tau_low) / (tau_bar - tau_low);
        let l = interpolate(l0.as_ref(), l1.as_ref(), &w, tj).unwrap();
        let b = jump_block(lyapunov_matrix(p1.as_ref(), p2.as_ref(), tau_bar, tj).unwrap().as_ref(), p1.as_ref(), l.as_ref(), c.as_ref()).unwrap();
        let b_low = jump_block_low(p1.as_ref(), p2.as_ref(), l0.as_ref(), c.as_ref(), &w).unwrap();
        let b_high = jump_block_high(p1.as_ref(), p2.as_ref(), l1.as_ref(), c.as_ref()).unwrap();
        let b_interp = &b_low * (1.0 - sj) + &b_high * sj;
        prop_assert!(max_abs_diff(b.as_ref(), b_interp.as_ref()) < 1e-10 * (1.0 + b.norm_max()));
        // (20c) written as printed: He(L0C) − (τ_low/τ̄)(P1 − P2) in the (1,1) block.
        let lc = &l0 * &c;
        let printed = &lc + lc.transpose() - (&p1 - &p2) * (tau_low / tau_bar);
        prop_assert!(max_abs_diff(b_low.submatrix(0, 0, n, n), printed.as_ref()) < 1e-12 * (1.0 + printed.norm_max()));
        // Schur form: with K = P1⁻¹L, the Schur complement of B w.r.t. P1 equals
        // P(τ) − (I − KC)'P1(I − KC).
        let k = gain_from(p1.as_ref(), l.as_ref()).unwrap();
        let lc = &l * &c;
        let p1inv_lc = gain_from(p1.as_ref(), lc.as_ref()).unwrap();
        let schur = b.submatrix(0, 0, n, n) - lc.transpose() * &p1inv_lc;
        let dec = jump_decrease(lyapunov_matrix(p1.as_ref(), p2.as_ref(), tau_bar, tj).unwrap().as_ref(), p1.as_ref(), k.as_ref(), c.as_ref()).unwrap();
        prop_assert!(max_abs_diff(schur.as_ref(), dec.as_ref()) < 1e-8 * (1.0 + dec.norm_max()));
    }
}
