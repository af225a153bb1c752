//! Verified definiteness: never "PD" for a matrix with a non-positive eigenvalue (exactly known
//! spectra near the boundary, down to the rounding level), "PD" proven for well-conditioned
//! matrices, the bound is a true lower bound of λ_min.

use faer::Mat;
use faer::linalg::solvers::DenseSolveCore;
use proptest::prelude::*;
use sporadic_interval::{
    Interval, IntervalMatrix, Verdict, is_verified_negative_definite,
    is_verified_positive_definite, lambda_max_enclosure,
};

/// Sylvester–Hadamard matrix of order 8 (entries ±1, H = Hᵀ, H² = 8I).
fn hadamard8(i: usize, j: usize) -> i128 {
    if (i & j).count_ones().is_multiple_of(2) {
        1
    } else {
        -1
    }
}

/// M = P·H·diag(λ)·H·Pᵀ/8 with exactly representable entries and exactly known eigenvalues
/// λ = (sign·2^-j, λ1, …, λ7) (λi integers); P a signed permutation. Returns None if an entry
/// would need more than 53 bits.
fn exact_spectrum_matrix(
    sign: i128,
    j: u32,
    lam: &[i128; 7],
    perm: &[usize],
    flips: &[bool],
) -> Option<Mat<f64>> {
    let mut l = [0i128; 8];
    l[0] = sign; // sign·2^-j scaled by 2^j
    for k in 0..7 {
        l[k + 1] = lam[k] << j;
    }
    let mut out = Mat::<f64>::zeros(8, 8);
    for a in 0..8 {
        for b in 0..8 {
            let s: i128 = (0..8)
                .map(|k| hadamard8(a, k) * hadamard8(b, k) * l[k])
                .sum();
            if s.abs() >= (1i128 << 53) {
                return None;
            }
            // value = s / 2^(j+3), exact (power-of-two scaling of a 53-bit integer).
            let v = (s as f64) * 2f64.powi(-(j as i32) - 3);
            let (pa, pb) = (perm[a], perm[b]);
            let sg = if flips[a] != flips[b] { -1.0 } else { 1.0 };
            out[(pa, pb)] = sg * v;
        }
    }
    Some(out)
}

fn perm8() -> impl Strategy<Value = (Vec<usize>, Vec<bool>)> {
    (
        Just((0..8).collect::<Vec<usize>>()).prop_shuffle(),
        prop::collection::vec(any::<bool>(), 8),
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn lambda_max_enclosure_contains_the_exact_largest_eigenvalue(
        j in 0u32..45,
        lam in prop::array::uniform7(1i128..16),
        (perm, flips) in perm8(),
        negate in any::<bool>(),
        eps_exp in 1u32..50,
    ) {
        // Spectrum exactly {−2^-j, λ1..λ7} (λi ∈ 1..15): λ_max = max λi. Negated: −λ spectrum,
        // λ_max = 2^-j. With a radius ε on the diagonal, the members' λ_max lie within ±ε of it.
        let Some(m) = exact_spectrum_matrix(-1, j, &lam, &perm, &flips) else { return Ok(()); };
        let (m, exact) = if negate {
            (Mat::from_fn(8, 8, |a, b| -m[(a, b)]), 2f64.powi(-(j as i32)))
        } else {
            (m, *lam.iter().max().unwrap() as f64)
        };
        let x = IntervalMatrix::from_point(m.as_ref()).unwrap();
        let e = lambda_max_enclosure(&x).unwrap();
        prop_assert!(e.contains(exact), "{e:?} ∌ {exact}");
        prop_assert!(e.hi() - e.lo() <= 1e-12 * 16.0, "too wide: {e:?}");
        let eps = 2f64.powi(-(eps_exp as i32));
        let rad = Mat::from_fn(8, 8, |a, b| if a == b { eps } else { 0.0 });
        let xr = IntervalMatrix::from_mid_rad(m.clone(), rad).unwrap();
        let er = lambda_max_enclosure(&xr).unwrap();
        prop_assert!(er.lo() <= exact - eps && er.hi() >= exact + eps, "{er:?} vs {exact} ± {eps}");
    }

    #[test]
    fn never_pd_with_a_nonpositive_eigenvalue_exact_spectrum(
        j in 0u32..45,
        lam in prop::array::uniform7(1i128..16),
        (perm, flips) in perm8(),
        zero in any::<bool>(),
    ) {
        // λ_min = −2^-j (down to ~2^-50 relative to ‖M‖ ≤ 16: the rounding level) or 0.
        let sign = if zero { 0 } else { -1 };
        let Some(m) = exact_spectrum_matrix(sign, j, &lam, &perm, &flips) else { return Ok(()); };
        let x = IntervalMatrix::from_point(m.as_ref()).unwrap();
        prop_assert_eq!(is_verified_positive_definite(&x).unwrap(), Verdict::NotProved);
        // …and −M has a non-negative eigenvalue, so it is never proven negative definite.
        prop_assert_eq!(is_verified_negative_definite(&x).unwrap(), Verdict::NotProved);
    }

    #[test]
    fn tiny_positive_eigenvalue_bound_is_sound(
        j in 0u32..45,
        lam in prop::array::uniform7(1i128..16),
        (perm, flips) in perm8(),
        eps_exp in 0u32..50,
        with_rad in any::<bool>(),
    ) {
        // λ_min = +2^-j exactly. If proven, the bound must be ≤ 2^-j; a radius ε·I with
        // ε ≥ 2^-j makes a singular/indefinite member, so then it must not be proven.
        let Some(m) = exact_spectrum_matrix(1, j, &lam, &perm, &flips) else { return Ok(()); };
        let lmin = 2f64.powi(-(j as i32));
        let eps = if with_rad { 2f64.powi(-(eps_exp as i32)) } else { 0.0 };
        let rad = Mat::from_fn(8, 8, |a, b| if a == b { eps } else { 0.0 });
        let x = IntervalMatrix::from_mid_rad(m.clone(), rad).unwrap();
        match is_verified_positive_definite(&x).unwrap() {
            Verdict::Proved { bound } => {
                prop_assert!(bound > 0.0 && bound <= lmin - eps, "bound {bound} λmin {lmin} ε {eps}");
            }
            Verdict::NotProved => {
                // Must be proven when the margin is comfortable (λ_min ≥ 2^-10·‖M‖, ε small).
                prop_assert!(!(j <= 6 && eps <= lmin / 4.0), "not proved: j={j} ε={eps}");
            }
        }
        // Negative definiteness of −X mirrors it.
        let neg = -&x;
        match is_verified_negative_definite(&neg).unwrap() {
            Verdict::Proved { bound } => prop_assert!(bound < 0.0 && bound >= -(lmin - eps)),
            Verdict::NotProved => prop_assert!(!(j <= 6 && eps <= lmin / 4.0)),
        }
    }

    #[test]
    fn random_orthogonal_conjugates(
        n in 2usize..=10,
        v in prop::collection::vec(-1.0f64..1.0, 20),
        lam in prop::collection::vec(1.0f64..100.0, 10),
        neg_exp in 1i32..40,
    ) {
        // Q = H(v1)·H(v2) (Householder reflections), M = fl(Q diag(λ) Qᵀ) symmetrised.
        let house = |w: &[f64]| {
            let nn: f64 = w.iter().map(|x| x * x).sum::<f64>().max(1e-3);
            Mat::from_fn(n, n, |i, j| (if i == j { 1.0 } else { 0.0 }) - 2.0 * w[i] * w[j] / nn)
        };
        let q = &house(&v[..n]) * &house(&v[10..10 + n]);
        let build = |l: &[f64]| {
            let full = &q * &Mat::from_fn(n, n, |i, j| if i == j { l[i] } else { 0.0 }) * q.transpose();
            Mat::from_fn(n, n, |i, j| { let (a, b) = (i.min(j), i.max(j)); 0.5 * full[(a, b)] + 0.5 * full[(b, a)] })
        };
        // Well conditioned PD: must be proven; bound below the smallest eigenvalue (≈ min λ).
        let lmin = lam[..n].iter().copied().fold(f64::INFINITY, f64::min);
        let m = build(&lam[..n]);
        let x = IntervalMatrix::from_point(m.as_ref()).unwrap();
        match is_verified_positive_definite(&x).unwrap() {
            Verdict::Proved { bound } => prop_assert!(bound > 0.0 && bound <= lmin * (1.0 + 1e-10)),
            Verdict::NotProved => prop_assert!(false, "well-conditioned PD not proven"),
        }
        prop_assert!(is_verified_negative_definite(&(-&x)).unwrap().is_proved());
        // λ_min = −δ, δ = 2^-k·max λ: whenever the Rayleigh quotient of the first column of Q
        // is certified negative (interval arithmetic), the verdict must be NotProved.
        let mut l2 = lam[..n].to_vec();
        let lmax = l2.iter().copied().fold(0.0, f64::max);
        l2[0] = -lmax * 2f64.powi(-neg_exp);
        let m2 = build(&l2);
        let mut quad = Interval::ZERO;
        for i in 0..n {
            for j in 0..n {
                quad = quad + Interval::new(q[(i, 0)], q[(i, 0)]).unwrap() * Interval::new(m2[(i, j)], m2[(i, j)]).unwrap() * Interval::new(q[(j, 0)], q[(j, 0)]).unwrap();
            }
        }
        let x2 = IntervalMatrix::from_point(m2.as_ref()).unwrap();
        if quad.is_negative() {
            prop_assert_eq!(is_verified_positive_definite(&x2).unwrap(), Verdict::NotProved);
        }
        prop_assert_eq!(is_verified_positive_definite(&x2).unwrap() == Verdict::NotProved || !quad.is_negative(), true);
    }
}

#[test]
fn interval_radius_is_accounted_for() {
    // mid = diag(1, 2, 3) with all radii 0.2: ‖R‖_∞ = 0.6 < 1, proven, bound ≤ 1 − ρ(R) … here ρ(R)=0.6.
    let mid = Mat::from_fn(3, 3, |i, j| if i == j { (i + 1) as f64 } else { 0.0 });
    let x = IntervalMatrix::from_mid_rad(mid.clone(), Mat::from_fn(3, 3, |_, _| 0.2)).unwrap();
    match is_verified_positive_definite(&x).unwrap() {
        Verdict::Proved { bound } => assert!(bound > 0.0 && bound <= 0.4 + 1e-12, "{bound}"),
        Verdict::NotProved => panic!("should be proven"),
    }
    // Radius 0.4 everywhere: member diag(1,2,3) − 0.4·ones has λ_min < 0 (ρ(R) = 1.2).
    let y = IntervalMatrix::from_mid_rad(mid, Mat::from_fn(3, 3, |_, _| 0.4)).unwrap();
    assert_eq!(
        is_verified_positive_definite(&y).unwrap(),
        Verdict::NotProved
    );
    // Indefinite / negative definite / zero / unbounded.
    let z = IntervalMatrix::from_point(
        Mat::from_fn(2, 2, |i, j| if i == j { -1.0 } else { 0.0 }).as_ref(),
    )
    .unwrap();
    assert_eq!(
        is_verified_positive_definite(&z).unwrap(),
        Verdict::NotProved
    );
    assert!(
        matches!(is_verified_negative_definite(&z).unwrap(), Verdict::Proved { bound } if (-1.0..0.0).contains(&bound))
    );
    assert_eq!(
        is_verified_positive_definite(&IntervalMatrix::zeros(2, 2)).unwrap(),
        Verdict::NotProved
    );
    let inf = IntervalMatrix::from_mid_rad(
        Mat::identity(2, 2),
        Mat::from_fn(2, 2, |_, _| f64::INFINITY),
    )
    .unwrap();
    assert_eq!(
        is_verified_positive_definite(&inf).unwrap(),
        Verdict::NotProved
    );
    // Tiny scales (subnormal range) and huge scales do not break soundness.
    let tiny = IntervalMatrix::from_point(
        Mat::from_fn(2, 2, |i, j| if i == j { 1e-310 } else { -1e-310 }).as_ref(),
    )
    .unwrap();
    assert_eq!(
        is_verified_positive_definite(&tiny).unwrap(),
        Verdict::NotProved
    ); // singular
    let huge = IntervalMatrix::from_point(
        Mat::from_fn(2, 2, |i, j| if i == j { 1e300 } else { 0.5e300 }).as_ref(),
    )
    .unwrap();
    assert!(is_verified_positive_definite(&huge).unwrap().is_proved());
}

#[test]
fn symmetrized_contains_the_symmetric_members_of_a_product() {
    // GᵀPG in interval arithmetic is not exactly symmetric; its symmetrized form is, and it
    // contains the exact symmetric product of point members.
    let g = Mat::from_fn(3, 3, |i, j| 0.1 * (i as f64 + 1.0) - 0.37 * j as f64 + 0.01);
    let p = Mat::from_fn(3, 3, |i, j| if i == j { 2.0 } else { 0.3 });
    let gi = IntervalMatrix::from_point(g.as_ref()).unwrap();
    let pi = IntervalMatrix::from_point(p.as_ref()).unwrap();
    let q = gi
        .transpose()
        .checked_mul(&pi.checked_mul(&gi).unwrap())
        .unwrap();
    let s = q.symmetrized().unwrap();
    assert!(s.is_symmetric());
    let exact = g.transpose() * &p * &g;
    let exact = Mat::from_fn(3, 3, |i, j| 0.5 * exact[(i, j)] + 0.5 * exact[(j, i)]);
    assert!(s.contains_point(exact.as_ref()));
    assert!(IntervalMatrix::zeros(2, 3).symmetrized().is_err());
}

#[test]
fn verified_inverse_contains_the_inverse_and_refuses_singular_members() {
    let a = faer::mat![[4.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 2.0]];
    let x = IntervalMatrix::from_point(a.as_ref()).unwrap();
    let inv = x.verified_inverse().unwrap().expect("nonsingular");
    let f = a.partial_piv_lu().inverse();
    assert!(inv.contains_point(f.as_ref()));
    assert!(inv.max_rad() < 1e-14);
    // Exactly: A·A⁻¹ = I must be in the product of the enclosures.
    let prod = x.checked_mul(&inv).unwrap();
    assert!(prod.contains_point(Mat::<f64>::identity(3, 3).as_ref()));
    // A radius that admits a singular member: not proven.
    let s = faer::mat![[1.0, 1.0], [1.0, 1.0 + 1e-3]];
    let wide = IntervalMatrix::from_mid_rad(s, Mat::from_fn(2, 2, |_, _| 1e-3)).unwrap();
    assert!(wide.verified_inverse().unwrap().is_none());
    assert!(IntervalMatrix::zeros(2, 3).verified_inverse().is_err());
}
