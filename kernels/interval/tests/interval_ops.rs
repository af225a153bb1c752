//! Property tests: interval operations contain the exact results of the point operations on
//! members. Exact results come from error-free transformations (TwoSum, FMA-based TwoProduct,
//! FMA remainders of ÷ and √) or from dyadic data whose products and sums are exact in f64.

use faer::Mat;
use proptest::prelude::*;
use sporadic_interval::{Interval, IntervalMatrix};

/// Whether f ≤ s + e exactly, for s = fl(x) and e = x − s exact (|e| ≤ half an ulp of s).
fn le_exact(f: f64, s: f64, e: f64) -> bool {
    f < s || (f == s && e >= 0.0)
}

/// Whether s + e ≤ f exactly.
fn ge_exact(f: f64, s: f64, e: f64) -> bool {
    f > s || (f == s && e <= 0.0)
}

fn contains_exact(iv: Interval, s: f64, e: f64) -> bool {
    le_exact(iv.lo(), s, e) && ge_exact(iv.hi(), s, e)
}

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

fn float() -> impl Strategy<Value = f64> {
    // Full 53-bit mantissas over a moderate exponent range (no underflow in TwoProduct).
    (-1.0f64..1.0, -40i32..40).prop_map(|(m, e)| m * 2f64.powi(e))
}

fn interval_and_member() -> impl Strategy<Value = (Interval, f64)> {
    (float(), float(), 0.0f64..=1.0).prop_map(|(a, b, f)| {
        let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
        let x = match f {
            f if f < 0.1 => lo,
            f if f > 0.9 => hi,
            f => (lo + f * (hi - lo)).clamp(lo, hi),
        };
        (Interval::new(lo, hi).unwrap(), x)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn scalar_add_sub_mul_div((a, x) in interval_and_member(), (b, y) in interval_and_member()) {
        let (s, e) = two_sum(x, y);
        prop_assert!(contains_exact(a + b, s, e));
        let (s, e) = two_sum(x, -y);
        prop_assert!(contains_exact(a - b, s, e));
        let (p, e) = two_prod(x, y);
        prop_assert!(contains_exact(a * b, p, e));
        prop_assert!(contains_exact(a.sqr(), two_prod(x, x).0, two_prod(x, x).1));
        prop_assert!(contains_exact(-a, -x, 0.0));
        if y != 0.0 {
            let q = x / y;
            // x/y − q = r/y with r = x − q·y exact (FMA).
            let r = (-q).mul_add(y, x);
            let sign = if r == 0.0 { 0.0 } else if (r > 0.0) == (y > 0.0) { 1.0 } else { -1.0 };
            // Represent x/y as q + sign·tiny (only the sign matters for the comparison).
            prop_assert!(contains_exact(a / b, q, sign * f64::MIN_POSITIVE));
        }
        prop_assert!((a.hull(b)).contains(x) && a.hull(b).contains(y));
        prop_assert!(a.abs().contains(x.abs()));
        prop_assert!(a.mag() >= x.abs() && a.mig() <= x.abs());
    }

    #[test]
    fn scalar_sqrt_exp_powi((a, x) in interval_and_member()) {
        let ax = a.abs();
        let q = x.abs().sqrt();
        let r = (-q).mul_add(q, x.abs()); // |x| − q² exactly
        prop_assert!(contains_exact(ax.sqrt(), q, r.signum() * f64::MIN_POSITIVE * (r != 0.0) as u8 as f64));
        // exp: f64::exp is within 1 ulp of e^x (not guaranteed by libm, so this is a sanity check
        // with one extra ulp), and the enclosure is tight.
        if x.abs() < 700.0 {
            let e = x.exp();
            let ea = Interval::new(x, x).unwrap().exp();
            prop_assert!(ea.lo() <= e.next_up() && ea.hi() >= e.next_down());
            prop_assert!(ea.width_up() <= 2e-10 * e, "{ea} vs {e}");
            prop_assert!(a.exp().lo() <= ea.lo() && a.exp().hi() >= ea.hi());
        }
        let c = a.powi(3);
        let (p, pe) = two_prod(x, x);
        // x³ = x·p + x·pe; enclose x·pe (tiny) crudely and check with a sum of intervals.
        let xp = Interval::new(x, x).unwrap() * Interval::new(p, p).unwrap() + Interval::new(x, x).unwrap() * Interval::new(pe, pe).unwrap();
        prop_assert!(c.intersect(xp).is_some());
    }
}

/// Dyadic numbers k·2⁻¹⁰ with |k| < 2²⁰: products are exact, and sums of ≤ 8 products too.
fn dyadic() -> impl Strategy<Value = f64> {
    (-(1i64 << 20) + 1..(1i64 << 20)).prop_map(|k| k as f64 / 1024.0)
}

fn dyadic_rad() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.0), (0i64..(1 << 12)).prop_map(|k| k as f64 / 1024.0)]
}

/// An interval matrix with dyadic mid/rad and one of its members (also dyadic).
fn imat_with_member(r: usize, c: usize) -> impl Strategy<Value = (IntervalMatrix, Mat<f64>)> {
    (
        prop::collection::vec(dyadic(), r * c),
        prop::collection::vec(dyadic_rad(), r * c),
        prop::collection::vec(-1.0f64..=1.0, r * c),
    )
        .prop_map(move |(m, rd, f)| {
            let mid = Mat::from_fn(r, c, |i, j| m[i * c + j]);
            let rad = Mat::from_fn(r, c, |i, j| rd[i * c + j]);
            let member = Mat::from_fn(r, c, |i, j| {
                let k = (f[i * c + j] * rd[i * c + j] * 1024.0).round() / 1024.0;
                let k = if f[i * c + j].abs() > 0.95 {
                    f[i * c + j].signum() * rd[i * c + j]
                } else {
                    k
                };
                m[i * c + j] + k
            });
            (IntervalMatrix::from_mid_rad(mid, rad).unwrap(), member)
        })
}

fn exact_product(x: &Mat<f64>, y: &Mat<f64>) -> Mat<f64> {
    Mat::from_fn(x.nrows(), y.ncols(), |i, j| {
        (0..x.ncols()).map(|k| x[(i, k)] * y[(k, j)]).sum()
    })
}

fn dims() -> impl Strategy<Value = (usize, usize, usize)> {
    (1usize..=8, 1usize..=8, 1usize..=8)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn matrix_ops_contain_exact_member_results(
        ((a, x), (b, y), (c, z)) in dims().prop_flat_map(|(m, k, n)| (imat_with_member(m, k), imat_with_member(k, n), imat_with_member(m, k))),
        s in dyadic(), srad in dyadic_rad(), sf in -1.0f64..=1.0,
    ) {
        // product (exact for dyadic members, see `dyadic`)
        let p = &a * &b;
        prop_assert!(p.contains_point(exact_product(&x, &y).as_ref()));
        // sum and difference (exact)
        let sum = Mat::from_fn(x.nrows(), x.ncols(), |i, j| x[(i, j)] + z[(i, j)]);
        let dif = Mat::from_fn(x.nrows(), x.ncols(), |i, j| x[(i, j)] - z[(i, j)]);
        prop_assert!((&a + &c).contains_point(sum.as_ref()));
        prop_assert!((&a - &c).contains_point(dif.as_ref()));
        prop_assert!((-&a).contains_point(Mat::from_fn(x.nrows(), x.ncols(), |i, j| -x[(i, j)]).as_ref()));
        // scaling by an interval (member t of [s ± srad], product exact)
        let t = s + ((sf * srad * 1024.0).round() / 1024.0);
        let si = Interval::new(s - srad, s + srad).unwrap();
        prop_assert!(a.scale(si).contains_point(Mat::from_fn(x.nrows(), x.ncols(), |i, j| t * x[(i, j)]).as_ref()));
        // hull, containment, transpose
        let h = a.hull(&c).unwrap();
        prop_assert!(h.contains(&a) && h.contains(&c));
        prop_assert!(h.contains_point(x.as_ref()) && h.contains_point(z.as_ref()));
        prop_assert!(a.transpose().contains_point(x.transpose()));
        // norms: exact for dyadic members
        let ninf = (0..x.nrows()).map(|i| (0..x.ncols()).map(|j| x[(i, j)].abs()).sum::<f64>()).fold(0.0, f64::max);
        let n1 = (0..x.ncols()).map(|j| (0..x.nrows()).map(|i| x[(i, j)].abs()).sum::<f64>()).fold(0.0, f64::max);
        let fro2: f64 = (0..x.nrows()).flat_map(|i| (0..x.ncols()).map(move |j| (i, j))).map(|(i, j)| x[(i, j)] * x[(i, j)]).sum();
        prop_assert!(ninf <= a.norm_inf_up());
        prop_assert!(n1 <= a.norm_1_up());
        let f = a.norm_fro_up();
        let (pp, pe) = two_prod(f, f);
        prop_assert!(ge_exact(pp, fro2, 0.0) || (pp == fro2 && pe >= 0.0) || pp > fro2);
        prop_assert!(f <= a.norm_inf_up().max(a.norm_1_up()) * (x.nrows().max(x.ncols()) as f64).sqrt() * 1.0001 + 1e-300);
    }

    #[test]
    fn matrix_product_contains_accurate_product_of_full_precision_members(
        n in 1usize..=10,
        v in prop::collection::vec(-1.0f64..1.0, 200),
        e in -30i32..30,
        rad in prop_oneof![Just(0.0), 0.0f64..1e-6],
    ) {
        let sc = 2f64.powi(e);
        let a = Mat::from_fn(n, n, |i, j| v[i * 10 + j] * sc);
        let b = Mat::from_fn(n, n, |i, j| v[100 + i * 10 + j]);
        let ia = IntervalMatrix::from_mid_rad(a.clone(), Mat::from_fn(n, n, |_, _| rad * sc)).unwrap();
        let ib = IntervalMatrix::from_point(b.as_ref()).unwrap();
        let p = &ia * &ib;
        // Compensated dot products (Ogita–Rump–Oishi Dot2): faithful for these data, within an
        // ulp of the exact result; the enclosure's radius is ≥ γ_n|A||B| ≫ 1 ulp.
        let dot2 = Mat::from_fn(n, n, |i, j| {
            let (mut s, mut c) = (0.0f64, 0.0f64);
            for k in 0..n {
                let (p, pe) = two_prod(a[(i, k)], b[(k, j)]);
                let (t, te) = two_sum(s, p);
                s = t;
                c += pe + te;
            }
            s + c
        });
        prop_assert!(p.contains_point(dot2.as_ref()));
        // Tightness: radius within a small multiple of n·u·|A||B| + rad·|B|.
        for i in 0..n { for j in 0..n {
            let ab: f64 = (0..n).map(|k| a[(i, k)].abs() * b[(k, j)].abs()).sum();
            let rb: f64 = (0..n).map(|k| rad * sc * b[(k, j)].abs()).sum();
            prop_assert!(p.rad()[(i, j)] <= 4.0 * (n as f64) * 1.2e-16 * ab + 1.01 * rb + 1e-300);
        } }
    }
}

#[test]
fn point_containment_is_exact_at_the_boundary() {
    let x = IntervalMatrix::from_mid_rad(
        Mat::from_fn(1, 1, |_, _| 1.0),
        Mat::from_fn(1, 1, |_, _| 0.5),
    )
    .unwrap();
    assert!(x.contains_point(Mat::from_fn(1, 1, |_, _| 1.5).as_ref()));
    assert!(x.contains_point(Mat::from_fn(1, 1, |_, _| 0.5).as_ref()));
    assert!(!x.contains_point(Mat::from_fn(1, 1, |_, _| 1.5f64.next_up()).as_ref()));
    assert!(!x.contains_point(Mat::from_fn(1, 1, |_, _| 0.5f64.next_down()).as_ref()));
    // mid + rad not representable: 1 + 2^-60 exactly; 1 + 2^-52 is outside, 1 is inside.
    let tiny = 2f64.powi(-60);
    let y = IntervalMatrix::from_mid_rad(
        Mat::from_fn(1, 1, |_, _| 1.0),
        Mat::from_fn(1, 1, |_, _| tiny),
    )
    .unwrap();
    assert!(!y.contains_point(Mat::from_fn(1, 1, |_, _| 1f64.next_up()).as_ref()));
    assert!(y.contains_point(Mat::from_fn(1, 1, |_, _| 1.0).as_ref()));
    // Overflow never yields a wrong enclosure: the entry becomes the whole real line.
    let big = IntervalMatrix::from_point(Mat::from_fn(1, 1, |_, _| f64::MAX).as_ref()).unwrap();
    let s = &big + &big;
    assert!(s.get(0, 0).contains(f64::MAX) && s.get(0, 0).hi() == f64::INFINITY);
    let p = &big * &big;
    assert!(!p.is_bounded());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The Frobenius and spectral bounds are finite whenever the norm itself is (entries up to
    /// 2^1000, whose squares overflow), and scale exactly with a power-of-two factor: they
    /// bound `2^e·X` by `2^e` times bounds of `X` up to rounding.
    #[test]
    fn norm_bounds_do_not_overflow_before_the_norm(
        n in 1usize..=6,
        v in prop::collection::vec(-1.0f64..1.0, 36),
        e in -900i32..1000,
    ) {
        let x = Mat::from_fn(n, n, |i, j| v[i * 6 + j]);
        let sc = 2f64.powi(e);
        let ix = IntervalMatrix::from_point(x.as_ref()).unwrap();
        let iy = IntervalMatrix::from_point(Mat::from_fn(n, n, |i, j| x[(i, j)] * sc).as_ref()).unwrap();
        let fro: f64 = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| x[(i, j)] * x[(i, j)]).sum::<f64>().sqrt();
        let sigma = x.singular_values().unwrap().into_iter().fold(0.0f64, f64::max);
        let (fy, ny) = (iy.norm_fro_up(), iy.norm_2_up());
        prop_assert!(fy.is_finite() && ny.is_finite(), "{fy} {ny}");
        // Lower: the exact norms, up to the rounding of the references (relative 1e-14).
        prop_assert!(fy / sc >= fro * (1.0 - 1e-14), "{} < {fro}", fy / sc);
        prop_assert!(ny / sc >= sigma * (1.0 - 1e-14), "{} < {sigma}", ny / sc);
        // Upper: as tight as the unscaled bounds, up to rounding.
        prop_assert!(fy / sc <= ix.norm_fro_up() * (1.0 + 1e-13));
        prop_assert!(ny / sc <= ix.norm_2_up() * (1.0 + 1e-13));
    }
}

/// The norm bounds at the edges of the floating-point range: a zero matrix, subnormal entries,
/// entries near `f64::MAX` (upper bounds, possibly `∞`), and a radius as large as the midpoint.
#[test]
fn norm_bounds_at_the_edges_of_the_range() {
    let zero = IntervalMatrix::from_point(Mat::<f64>::zeros(3, 3).as_ref()).unwrap();
    assert_eq!((zero.norm_fro_up(), zero.norm_2_up()), (0.0, 0.0));
    let tiny = f64::from_bits(1);
    let sub = IntervalMatrix::from_point(Mat::from_fn(2, 2, |_, _| tiny).as_ref()).unwrap();
    // ‖·‖_F = 2·tiny, ‖·‖₂ = 2·tiny exactly.
    assert!(sub.norm_fro_up() >= 2.0 * tiny && sub.norm_fro_up() <= 8.0 * tiny);
    assert!(sub.norm_2_up() >= 2.0 * tiny && sub.norm_2_up() <= 8.0 * tiny);
    let big = IntervalMatrix::from_point(Mat::from_fn(1, 1, |_, _| f64::MAX).as_ref()).unwrap();
    assert!(big.norm_fro_up() >= f64::MAX && big.norm_2_up() >= f64::MAX);
    let half = f64::MAX / 4.0;
    let wide = IntervalMatrix::from_mid_rad(
        Mat::from_fn(2, 2, |_, _| half / 2.0),
        Mat::from_fn(2, 2, |_, _| half / 2.0),
    )
    .unwrap();
    // Every member has entries up to `half`: ‖·‖_F ≤ 2·half, and the bounds cover it.
    assert!(wide.norm_fro_up() >= 2.0 * half && wide.norm_fro_up().is_finite());
    assert!(wide.norm_2_up() >= 2.0 * half && wide.norm_2_up().is_finite());
}
