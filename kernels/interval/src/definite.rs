//! Verified positive / negative definiteness of symmetric interval matrices (Rump 2006).

use crate::round::{ETA, add_up, div_up, gamma_up, mul_up, sub_down};
use crate::{Interval, IntervalError, IntervalMatrix};
use faer::{Mat, Side};

/// Outcome of a definiteness verification.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Verdict {
    /// Proven for **every** symmetric member of the interval matrix. `bound` is a rigorous
    /// lower bound of λ_min (> 0) for [`is_verified_positive_definite`], and a rigorous upper
    /// bound of λ_max (< 0) for [`is_verified_negative_definite`].
    Proved {
        /// The eigenvalue bound (see the variant's documentation).
        bound: f64,
    },
    /// The property could not be proven (it may be false, or too close to call in double
    /// precision).
    NotProved,
}

impl Verdict {
    /// Whether the property was proven.
    pub fn is_proved(self) -> bool {
        matches!(self, Verdict::Proved { .. })
    }
}

/// Plain (unblocked, sequential-summation) Cholesky RᵀR = A of a symmetric matrix; `None` if a
/// pivot is not strictly positive and finite. Our own loop, so the hypotheses of the error
/// analysis (Higham, *Accuracy and Stability*, Thm 10.3) hold by construction.
fn cholesky_succeeds(a: &Mat<f64>) -> Option<f64> {
    let n = a.nrows();
    let mut r = Mat::<f64>::zeros(n, n);
    let mut rmax = 0.0f64;
    for i in 0..n {
        let mut s = a[(i, i)];
        for k in 0..i {
            s -= r[(k, i)] * r[(k, i)];
        }
        if !(s > 0.0) || !s.is_finite() {
            return None;
        }
        let d = s.sqrt();
        r[(i, i)] = d;
        rmax = rmax.max(d);
        for j in (i + 1)..n {
            let mut t = a[(i, j)];
            for k in 0..i {
                t -= r[(k, i)] * r[(k, j)];
            }
            let v = t / d;
            if !v.is_finite() {
                return None;
            }
            r[(i, j)] = v;
        }
    }
    Some(rmax)
}

/// Rigorous lower bound of λ_min over all symmetric members of ⟨M, R⟩ via a floating-point
/// Cholesky of Ã = fl(M − σI), or `None` if that Cholesky fails.
///
/// **Derivation.** Let the Cholesky of the float matrix Ã (n×n) run to completion with computed
/// factor R̂. Then R̂ᵀR̂ = Ã + ΔÃ with |ΔÃ| ≤ γ_{n+1}|R̂ᵀ||R̂| (Demmel; Higham Thm 10.3; we use
/// γ_{n+2} as a margin). By Cauchy–Schwarz (|R̂ᵀ||R̂|)_ij ≤ ‖r̂_i‖‖r̂_j‖ (columns), and
/// ‖r̂_j‖² = ã_jj + Δã_jj ≤ ã_jj + γ‖r̂_j‖², so ‖r̂_j‖² ≤ ã_jj/(1 − γ) (Rump, BIT 46, 2006, Lemma 2.1).
/// Hence ‖ΔÃ‖₂ ≤ ‖|ΔÃ|‖₂ ≤ β·‖d dᵀ‖₂ = β·Σ_j ã_jj with β = γ/(1 − γ), d_j = √ã_jj. Gradual
/// underflow adds at most η(n + r̂_max) per entry (≤ η/2 per product, amplified ≤ 2 by later
/// additions, and r̂_ii·η/2 from each division; sqrt cannot underflow), i.e. υ = n·η(n + r̂_max)
/// in the 2-norm; we add 2υ and also add υ to each ã_jj in the trace term. Since R̂ᵀR̂ ⪰ 0,
/// λ_min(Ã) ≥ −(β·Σ_j(ã_jj + υ) + 2υ) =: −α.
///
/// Every symmetric member X of ⟨M, R⟩ is X = Ã + D + (X − M) with D = diag(m_jj − ã_jj) ⪰
/// (min_j δ_j)·I, δ_j a lower bound of m_jj − ã_jj (≈ σ), and ‖X − M‖₂ = ρ(X − M) ≤ ρ(|X − M|)
/// ≤ ρ(R) ≤ ‖R‖_∞ (Perron–Frobenius; R ≥ 0 symmetric), so by Weyl's inequality
/// λ_min(X) ≥ −α + min_j δ_j − ‖R‖_∞ (each term rounded downward).
fn lower_bound_with_shift(x: &IntervalMatrix, sigma: f64, rho_r: f64) -> Option<f64> {
    let n = x.nrows();
    let m = x.mid();
    let mut at = m.to_owned();
    let mut min_delta = f64::INFINITY;
    for j in 0..n {
        at[(j, j)] = m[(j, j)] - sigma;
        min_delta = min_delta.min(sub_down(m[(j, j)], at[(j, j)]));
    }
    let rmax = cholesky_succeeds(&at)?;
    let g = gamma_up(n + 2);
    let beta = div_up(g, sub_down(1.0, g));
    let nf = n as f64;
    let upsilon = mul_up(mul_up(nf, ETA), add_up(nf, rmax.next_up()));
    let mut trace = 0.0;
    for j in 0..n {
        trace = add_up(trace, add_up(at[(j, j)].max(0.0), upsilon));
    }
    let alpha = add_up(mul_up(beta, trace), mul_up(2.0, upsilon));
    let lb = sub_down(sub_down(min_delta, alpha), rho_r);
    lb.is_finite().then_some(lb)
}

fn check_symmetric(x: &IntervalMatrix) -> Result<(), IntervalError> {
    if x.nrows() != x.ncols() {
        return Err(IntervalError::NotSquare {
            what: "interval matrix",
            rows: x.nrows(),
            cols: x.ncols(),
        });
    }
    if x.nrows() == 0 {
        return Err(IntervalError::Empty {
            what: "interval matrix",
        });
    }
    if let Some((row, col)) = x.first_asymmetry() {
        return Err(IntervalError::NotSymmetric {
            what: "interval matrix",
            row,
            col,
        });
    }
    Ok(())
}

/// Proves that **every symmetric member** of the interval matrix `x` is positive definite,
/// with a rigorous lower bound of its smallest eigenvalue (Rump's method: floating-point
/// Cholesky of mid(x) − σI plus an a-priori bound of its rounding error; see the derivation on
/// the private `lower_bound_with_shift` in the source and the crate documentation).
///
/// σ is chosen heuristically (from a floating-point estimate of λ_min(mid)); the bound itself
/// does not depend on the heuristic being right. Never returns `Proved` for a member with a
/// non-positive eigenvalue; may return `NotProved` for positive definite matrices that are
/// too close to singular (λ_min ≲ (n+2)·u·trace) or have a large radius.
///
/// # Errors
/// [`IntervalError::NotSquare`], [`IntervalError::Empty`], [`IntervalError::NotSymmetric`]
/// (midpoint and radius must be exactly symmetric).
pub fn is_verified_positive_definite(x: &IntervalMatrix) -> Result<Verdict, IntervalError> {
    check_symmetric(x)?;
    let n = x.nrows();
    let rad = x.rad();
    // ‖R‖_∞ upper bound.
    let mut rho_r = 0.0f64;
    for i in 0..n {
        let mut s = 0.0;
        for j in 0..n {
            s = add_up(s, rad[(i, j)]);
        }
        rho_r = rho_r.max(s);
    }
    if !rho_r.is_finite() {
        return Ok(Verdict::NotProved);
    }
    let m = x.mid();
    // Minimal shift: σ0 ≈ β·trace + ‖R‖ (rounding margin included).
    let g = gamma_up(n + 2);
    let mut trace = 0.0;
    for j in 0..n {
        trace = add_up(trace, m[(j, j)].max(0.0));
    }
    let sigma0 = mul_up(
        add_up(mul_up(mul_up(2.0, g), trace), rho_r),
        1.0 + 1.0 / 64.0,
    )
    .max(f64::MIN_POSITIVE);
    let mut candidates = Vec::with_capacity(4);
    if let Ok(ev) = m.to_owned().self_adjoint_eigenvalues(Side::Lower)
        && let Some(&lam) = ev.first()
        && lam.is_finite()
        && lam > sigma0
    {
        let slack = lam - sigma0;
        candidates.push(lam - 1e-9 * slack);
        candidates.push(lam - 1e-6 * slack);
        candidates.push(lam - 1e-3 * slack);
        candidates.push(lam - 0.1 * slack);
        candidates.push(lam - 0.5 * slack);
    }
    candidates.push(sigma0);
    // The first shift whose Cholesky succeeds with a positive bound wins (candidates are
    // ordered from the largest shift, i.e. the best possible bound, down).
    let best = candidates
        .into_iter()
        .filter_map(|sigma| lower_bound_with_shift(x, sigma, rho_r))
        .find(|&lb| lb > 0.0);
    Ok(match best {
        Some(bound) => Verdict::Proved { bound },
        None => Verdict::NotProved,
    })
}

/// Proves that every symmetric member of `x` is negative definite (by applying
/// [`is_verified_positive_definite`] to −x); `Proved { bound }` carries a rigorous upper bound
/// (< 0) of λ_max.
///
/// # Errors
/// As [`is_verified_positive_definite`].
pub fn is_verified_negative_definite(x: &IntervalMatrix) -> Result<Verdict, IntervalError> {
    Ok(match is_verified_positive_definite(&-x)? {
        Verdict::Proved { bound } => Verdict::Proved { bound: -bound },
        Verdict::NotProved => Verdict::NotProved,
    })
}

/// A rigorous enclosure `[lo, hi]` of λ_max(X) valid for **every** symmetric member X of `x`.
///
/// * `lo` is a Rayleigh quotient: λ_max(X) ≥ vᵀXv / vᵀv for any v ≠ 0; with v the
///   floating-point eigenvector of the midpoint's largest eigenvalue, vᵀ·x·v and vᵀv are
///   evaluated in interval arithmetic and the lower end of their quotient is taken.
/// * `hi` is h + b, where b < 0 is the rigorous bound of [`is_verified_negative_definite`] for
///   x − h·I and h is a floating-point estimate of λ_max(mid) plus ‖rad‖_∞ (raised until the
///   test proves it, at most a few times; `+∞` if it never does).
///
/// # Errors
/// As [`is_verified_positive_definite`].
pub fn lambda_max_enclosure(x: &IntervalMatrix) -> Result<Interval, IntervalError> {
    check_symmetric(x)?;
    let n = x.nrows();
    let m = x.mid();
    if !x.is_bounded() {
        return Ok(Interval::ENTIRE);
    }
    let Ok(eig) = m.to_owned().self_adjoint_eigen(Side::Lower) else {
        return Ok(Interval::ENTIRE);
    };
    let vals = eig.S().column_vector();
    let top = vals[n - 1];
    if !top.is_finite() {
        return Ok(Interval::ENTIRE);
    }
    // Lower end: Rayleigh quotient of the top eigenvector, in interval arithmetic.
    let u = eig.U();
    let v = IntervalMatrix::from_fn(n, 1, |i, _| Interval::raw(u[(i, n - 1)], u[(i, n - 1)]));
    let xv = x.checked_mul(&v)?;
    let vxv = v.transpose().checked_mul(&xv)?.get(0, 0);
    let vv = v.transpose().checked_mul(&v)?.get(0, 0);
    let lo = if vv.lo() > 0.0 {
        (vxv / vv).lo()
    } else {
        f64::NEG_INFINITY
    };
    // Upper end: prove x − h·I negative definite for h slightly above the estimate.
    let rad = x.rad();
    let rad_norm = (0..n)
        .map(|i| (0..n).fold(0.0, |s, j| add_up(s, rad[(i, j)])))
        .fold(0.0f64, f64::max);
    let scale = vals
        .iter()
        .fold(0.0f64, |s, &l| s.max(l.abs()))
        .max(f64::MIN_POSITIVE);
    let mut slack = add_up(rad_norm, mul_up(gamma_up(n + 2), scale));
    let mut hi = f64::INFINITY;
    for _ in 0..4 {
        let h = add_up(top, slack);
        if !h.is_finite() {
            break;
        }
        let shifted = x.checked_sub(&IntervalMatrix::identity(n).scale(Interval::raw(h, h)))?;
        if let Verdict::Proved { bound } = is_verified_negative_definite(&shifted)? {
            hi = add_up(h, bound);
            break;
        }
        slack = mul_up(slack, 16.0).max(f64::MIN_POSITIVE);
    }
    Interval::new(lo.min(hi), hi).or(Ok(Interval::ENTIRE))
}
