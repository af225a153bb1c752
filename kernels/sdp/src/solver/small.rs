//! Dense kernels for small blocks (order `n ≤` [`SMALL`]) on column-major slices.
//!
//! The blocks of control LMIs and of most SDPLIB problems are of order 2–16. At these sizes a
//! general dense routine spends more time in dispatch, scratch allocation and blocking logic
//! than in arithmetic (measured with callgrind on hinf1, blocks 4/4/6: faer's triangular
//! products, Cholesky scratch buffers and eigenvalue solver took over half of the solve's
//! instructions). These kernels are plain loops over columns, allocate nothing, and work on
//! stack arrays sized by [`with_bufs`]; [`super::blockops`], [`super::step`] and
//! [`super::lsq`] use them for small blocks and faer above that size.
//!
//! Every kernel reads and writes column-major `n×n` arrays whose leading dimension is `n`.

/// Largest block order handled by these kernels.
pub(crate) const SMALL: usize = 16;

/// Largest block order whose products ([`mul`], [`congruence`]) use these kernels: above it,
/// faer's SIMD micro-kernels win over plain loops compiled for the baseline target.
pub(crate) const SMALL_PRODUCT: usize = 8;

/// Largest block order whose smallest eigenvalue is computed by [`min_eig`] (Jacobi) rather
/// than by faer's tridiagonal solver: Jacobi costs `O(n³)` per sweep, which pays off only while
/// the general solver's fixed overhead dominates.
pub(crate) const JACOBI_MAX: usize = 10;

/// Runs `f` on `K` zeroed stack buffers of `n²` entries each (`n ≤` [`SMALL`]).
///
/// The buffers come from arrays of 16, 64 or 256 entries by the size class of `n`, so a block of
/// order 2 does not pay for clearing and copying `SMALL²` entries per buffer (truss1, blocks of
/// order 2: memset and memmove of full-size buffers took 15% of the solve).
pub(crate) fn with_bufs<const K: usize, R>(n: usize, f: impl FnOnce([&mut [f64]; K]) -> R) -> R {
    fn run<const K: usize, const C: usize, R>(n: usize, f: impl FnOnce([&mut [f64]; K]) -> R) -> R {
        let mut bufs = [[0.0; C]; K];
        f(bufs.each_mut().map(|b| &mut b[..n * n]))
    }
    assert!(n <= SMALL, "small kernel called on an order-{n} block");
    match n {
        0..=4 => run::<K, 16, R>(n, f),
        5..=8 => run::<K, 64, R>(n, f),
        _ => run::<K, { SMALL * SMALL }, R>(n, f),
    }
}

/// In-place lower Cholesky factorisation `A = L Lᵀ` (left-looking, Golub–Van Loan Alg. 4.2.2).
///
/// Reads the lower triangle of `a`, writes `L` there and zeros the strict upper triangle.
/// Returns `false` (contents unspecified) when a pivot is not positive and finite, i.e. `A` is
/// not numerically positive definite.
pub(crate) fn cholesky_in_place(a: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let (left, right) = a.split_at_mut(j * n);
        let col = &mut right[..n];
        for k in 0..j {
            let lk = &left[k * n..(k + 1) * n];
            let ljk = lk[j];
            if ljk != 0.0 {
                for i in j..n {
                    col[i] -= lk[i] * ljk;
                }
            }
        }
        let d = col[j];
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        let d = d.sqrt();
        col[j] = d;
        let inv = 1.0 / d;
        for v in &mut col[j + 1..] {
            *v *= inv;
        }
        col[..j].fill(0.0);
    }
    true
}

/// `out = L⁻¹` for lower-triangular `l` with non-zero diagonal (column-oriented forward
/// substitution on the unit vectors); the strict upper triangle of `out` is zero.
pub(crate) fn lower_inverse(l: &[f64], n: usize, out: &mut [f64]) {
    out[..n * n].fill(0.0);
    for j in 0..n {
        let x = &mut out[j * n..(j + 1) * n];
        x[j] = 1.0;
        for k in j..n {
            let lk = &l[k * n..(k + 1) * n];
            let xk = x[k] / lk[k];
            x[k] = xk;
            if xk != 0.0 {
                for i in k + 1..n {
                    x[i] -= lk[i] * xk;
                }
            }
        }
    }
}

/// `out = Linvᵀ Linv` (full symmetric) for lower-triangular `linv`: the inverse of `L Lᵀ`.
pub(crate) fn gram_of_lower(linv: &[f64], n: usize, out: &mut [f64]) {
    for j in 0..n {
        let cj = &linv[j * n..(j + 1) * n];
        for i in j..n {
            let ci = &linv[i * n..(i + 1) * n];
            // Column i of a lower-triangular matrix vanishes above row i.
            let mut s = 0.0;
            for k in i..n {
                s += ci[k] * cj[k];
            }
            out[i + j * n] = s;
            out[j + i * n] = s;
        }
    }
}

/// `out = a · b` for `n×n` `a` and `b`.
pub(crate) fn mul(a: &[f64], b: &[f64], n: usize, out: &mut [f64]) {
    for j in 0..n {
        let bj = &b[j * n..(j + 1) * n];
        let oj = &mut out[j * n..(j + 1) * n];
        oj.fill(0.0);
        for k in 0..n {
            let bkj = bj[k];
            if bkj != 0.0 {
                let ak = &a[k * n..(k + 1) * n];
                for i in 0..n {
                    oj[i] += ak[i] * bkj;
                }
            }
        }
    }
}

/// `out = Linv · D · Linvᵀ` (full symmetric) for lower-triangular `linv` and symmetric `d`;
/// `tmp` is scratch of the same size.
pub(crate) fn congruence(linv: &[f64], d: &[f64], n: usize, tmp: &mut [f64], out: &mut [f64]) {
    // tmp = Linv · D: column j is Σ_k Linv[:, k] D[k, j], and Linv[:, k] vanishes above row k.
    for j in 0..n {
        let dj = &d[j * n..(j + 1) * n];
        let tj = &mut tmp[j * n..(j + 1) * n];
        tj.fill(0.0);
        for k in 0..n {
            let dkj = dj[k];
            if dkj != 0.0 {
                let lk = &linv[k * n..(k + 1) * n];
                for i in k..n {
                    tj[i] += lk[i] * dkj;
                }
            }
        }
    }
    // out = tmp · Linvᵀ: out[i, j] = Σ_{k ≤ j} tmp[i, k] Linv[j, k]; lower triangle, mirrored.
    for j in 0..n {
        let oj = &mut out[j * n..(j + 1) * n];
        oj.fill(0.0);
        for k in 0..=j {
            let ljk = linv[j + k * n];
            if ljk != 0.0 {
                let tk = &tmp[k * n..(k + 1) * n];
                for i in j..n {
                    oj[i] += tk[i] * ljk;
                }
            }
        }
    }
    for j in 0..n {
        for i in j + 1..n {
            out[j + i * n] = out[i + j * n];
        }
    }
}

/// Sweeps after which the cyclic Jacobi iteration gives up (it converges quadratically; 6–10
/// sweeps suffice for `n ≤ 16` in double precision).
const MAX_SWEEPS: usize = 40;

/// Smallest eigenvalue of a symmetric `n×n` matrix (lower triangle read) by the cyclic Jacobi
/// method (Golub–Van Loan Alg. 8.5.3), run until the off-diagonal part is at the rounding
/// level of the matrix; `NaN` for non-finite input or if the sweeps do not converge.
pub(crate) fn min_eig(a: &[f64], n: usize) -> f64 {
    if n == 0 {
        return f64::INFINITY;
    }
    with_bufs(n, |[w]| jacobi_min_eig(a, n, w))
}

/// [`min_eig`] with the working copy in `w` (`n²` entries).
fn jacobi_min_eig(a: &[f64], n: usize, w: &mut [f64]) -> f64 {
    for j in 0..n {
        for i in j..n {
            let v = a[i + j * n];
            if !v.is_finite() {
                return f64::NAN;
            }
            w[i + j * n] = v;
            w[j + i * n] = v;
        }
    }
    let total: f64 = w.iter().map(|v| v * v).sum();
    // Each rotation leaves off-diagonal rounding of order ε‖A‖, so the iteration stops once
    // ‖off(A)‖_F ≤ n ε ‖A‖_F; the eigenvalues then carry an absolute error of that order
    // (Weyl), the accuracy of any backward-stable symmetric eigensolver.
    let floor = (n as f64 * f64::EPSILON).powi(2) * total;
    for _ in 0..MAX_SWEEPS {
        let mut off = 0.0;
        for j in 0..n {
            for i in j + 1..n {
                off += w[i + j * n] * w[i + j * n];
            }
        }
        if 2.0 * off <= floor {
            return (0..n).map(|i| w[i + i * n]).fold(f64::INFINITY, f64::min);
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = w[p + q * n];
                if apq == 0.0 {
                    continue;
                }
                let (app, aqq) = (w[p + p * n], w[q + q * n]);
                let tau = (aqq - app) / (2.0 * apq);
                let t = if tau >= 0.0 {
                    1.0 / (tau + (1.0 + tau * tau).sqrt())
                } else {
                    -1.0 / (-tau + (1.0 + tau * tau).sqrt())
                };
                let c = 1.0 / (1.0 + t * t).sqrt();
                let s = t * c;
                // A ← Jᵀ A J with J = [c s; −s c] in rows/columns (p, q).
                for k in 0..n {
                    let (akp, akq) = (w[k + p * n], w[k + q * n]);
                    w[k + p * n] = c * akp - s * akq;
                    w[k + q * n] = s * akp + c * akq;
                }
                for k in 0..n {
                    let (apk, aqk) = (w[p + k * n], w[q + k * n]);
                    w[p + k * n] = c * apk - s * aqk;
                    w[q + k * n] = s * apk + c * aqk;
                }
            }
        }
    }
    f64::NAN
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;
    use proptest::prelude::*;

    fn to_vec(m: &Mat<f64>) -> Vec<f64> {
        let n = m.nrows();
        (0..n * n).map(|e| m[(e % n, e / n)]).collect()
    }

    fn random_sym(n: usize, entries: &[f64]) -> Mat<f64> {
        Mat::from_fn(n, n, |i, j| {
            let (a, b) = if i >= j { (i, j) } else { (j, i) };
            entries[a * SMALL + b]
        })
    }

    /// `B Bᵀ + n I` for a random `B`: well-conditioned positive definite.
    fn random_spd(n: usize, entries: &[f64]) -> Mat<f64> {
        let b = Mat::from_fn(n, n, |i, j| entries[i * SMALL + j]);
        let mut a = &b * b.transpose();
        for i in 0..n {
            a[(i, i)] += n as f64;
        }
        a
    }

    fn max_abs_diff(a: &[f64], b: &Mat<f64>) -> f64 {
        let n = b.nrows();
        (0..n * n).fold(0.0f64, |m, e| m.max((a[e] - b[(e % n, e / n)]).abs()))
    }

    fn entries() -> impl Strategy<Value = Vec<f64>> {
        proptest::collection::vec(-1.0f64..1.0, SMALL * SMALL)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// `L Lᵀ` reproduces `A`, `L⁻¹ L = I`, `L⁻ᵀL⁻¹ = A⁻¹` (checked as `A · A⁻¹ = I`).
        #[test]
        fn cholesky_inverse_and_gram(n in 1usize..=SMALL, e in entries()) {
            let a = random_spd(n, &e);
            let mut l = to_vec(&a);
            prop_assert!(cholesky_in_place(&mut l, n));
            let lm = Mat::from_fn(n, n, |i, j| l[i + j * n]);
            let scale = (n * n) as f64;
            prop_assert!(max_abs_diff(&to_vec(&(&lm * lm.transpose())), &a) <= 1e-13 * scale);
            let mut linv = vec![0.0; n * n];
            lower_inverse(&l, n, &mut linv);
            let li = Mat::from_fn(n, n, |i, j| linv[i + j * n]);
            prop_assert!(max_abs_diff(&to_vec(&(&li * &lm)), &Mat::identity(n, n)) <= 1e-13 * scale);
            let mut inv = vec![0.0; n * n];
            gram_of_lower(&linv, n, &mut inv);
            let im = Mat::from_fn(n, n, |i, j| inv[i + j * n]);
            prop_assert!(max_abs_diff(&to_vec(&(&a * &im)), &Mat::identity(n, n)) <= 1e-12 * scale);
        }

        /// Products and congruences against faer's dense products.
        #[test]
        fn products_match_faer(n in 1usize..=SMALL, e1 in entries(), e2 in entries()) {
            let a = Mat::from_fn(n, n, |i, j| e1[i * SMALL + j]);
            let d = random_sym(n, &e2);
            let mut out = vec![0.0; n * n];
            mul(&to_vec(&a), &to_vec(&d), n, &mut out);
            prop_assert!(max_abs_diff(&out, &(&a * &d)) <= 1e-14 * n as f64);
            let lower = Mat::from_fn(n, n, |i, j| if i >= j { a[(i, j)] } else { 0.0 });
            let mut tmp = vec![0.0; n * n];
            congruence(&to_vec(&lower), &to_vec(&d), n, &mut tmp, &mut out);
            let reference = &lower * &d * lower.transpose();
            prop_assert!(max_abs_diff(&out, &reference) <= 1e-13 * (n * n) as f64);
        }

        /// Jacobi's smallest eigenvalue agrees with faer's symmetric eigensolver, and Cholesky of
        /// the shifted matrix succeeds exactly above it (away from the boundary).
        #[test]
        fn min_eig_matches_faer(n in 1usize..=SMALL, e in entries(), scale in -3i32..4) {
            let a = random_sym(n, &e) * faer::Scale(10f64.powi(scale));
            let reference = a.self_adjoint_eigenvalues(faer::Side::Lower).unwrap()[0];
            let norm = a.norm_l2().max(f64::MIN_POSITIVE);
            let lam = min_eig(&to_vec(&a), n);
            prop_assert!((lam - reference).abs() <= 1e-13 * norm, "{lam} vs {reference}");
            let margin = 1e-8 * norm;
            let shifted = |shift: f64| {
                let mut t = to_vec(&a);
                for i in 0..n {
                    t[i + i * n] += shift;
                }
                cholesky_in_place(&mut t, n)
            };
            prop_assert!(shifted(-reference + margin));
            prop_assert!(!shifted(-reference - margin));
        }
    }

    #[test]
    fn cholesky_rejects_indefinite_and_non_finite() {
        let mut a = vec![1.0, 2.0, 2.0, 1.0];
        assert!(!cholesky_in_place(&mut a, 2));
        let mut b = vec![f64::NAN, 0.0, 0.0, 1.0];
        assert!(!cholesky_in_place(&mut b, 2));
        assert!(min_eig(&[1.0, f64::INFINITY, 0.0, 1.0], 2).is_nan());
    }

    /// Closed form: the eigenvalues of `[[2, 1], [1, 2]]` are 1 and 3; of the `n×n` matrix with
    /// 2 on the diagonal and −1 beside it, `2 − 2 cos(π/(n+1))` is the smallest.
    #[test]
    fn min_eig_closed_forms() {
        assert!((min_eig(&[2.0, 1.0, 1.0, 2.0], 2) - 1.0).abs() < 1e-15);
        for n in [3, 7, 16] {
            let t = Mat::from_fn(n, n, |i, j| match i.abs_diff(j) {
                0 => 2.0,
                1 => -1.0,
                _ => 0.0,
            });
            let exact = 2.0 - 2.0 * (std::f64::consts::PI / (n + 1) as f64).cos();
            assert!((min_eig(&to_vec(&t), n) - exact).abs() < 1e-14, "n = {n}");
        }
    }
}
