//! Scalar coefficient functions of the residue expansion and their exact extrema on `[T1, T2]`.
//!
//! Ferrante et al. (2016), §4.1: with the partial-fraction expansion (42) of the resolvent,
//! `e^{Av} = Σ_k c_k(v) N_k` with real constant matrices `N_k` and the real scalar functions
//!
//! ```text
//! real λ:          b(v)  =  e^{λv} v^k / k!
//! complex a + ib:  g(v)  =  2 e^{av} cos(bv) v^k / k!      (matrix Re R)
//!                  g*(v) = −2 e^{av} sin(bv) v^k / k!      (matrix Im R)
//! ```
//!
//! and, for the power series of a short window about its centre `c` (not in the paper, see
//! [`crate::residue`]), `b_c(v) = e^{λ(v−c)} (v−c)^k / k!`.
//!
//! The box vertices (43a) need `min`/`max` of every function on `[T1, T2]` (43b). These are
//! computed **exactly** (up to rounding): the candidates are both ends plus *every* interior
//! critical point, and the final range is rounded outward.
//!
//! * real λ: `b'(v) ∝ v^{k−1}(λv + k)`, so the only interior critical point is `v* = −k/λ`.
//! * centred: with `s = v − c`, the range over `s ≥ 0` is that of `b` with the same `λ`, and
//!   for `s = −u ≤ 0` the value is `(−1)^k e^{−λu} u^k/k!`, `b` with `−λ` at `u`; the two
//!   sides are joined, the ends `t − c` widened by their rounding error.
//! * complex: write `(av + k, bv) = ρ(v)(cos φ(v), sin φ(v))` (for `k = 0`: `(a, b)`). Then
//!   `g'(v) ∝ cos(ψ(v))` and `g*'(v) ∝ sin(ψ(v))` with the phase `ψ(v) = bv + φ(v)`, and
//!   `ψ'(v) = b(1 + k/ρ(v)²) > 0` for `b > 0`. The phase is continuous and strictly increasing,
//!   so the critical points are exactly the solutions of `ψ(v) = π/2 + mπ` (cosine) or
//!   `ψ(v) = mπ` (sine) for the finitely many integers `m` with the level inside
//!   `(ψ(T1), ψ(T2))`; each is bracketed (`ψ' ≥ b` puts the next one within `(level − ψ)/b`)
//!   and refined by safeguarded Newton. Nothing is sampled, so no extremum can be missed
//!   (containment needs the true global extrema, which a grid alone cannot guarantee). For a
//!   decaying mode (`a < 0`) the enumeration stops once the envelope `2e^{av}v^k/k!`, which
//!   decreases for `v > k/|a|`, is below both extremal values found so far: no later value can
//!   be more extreme (so a window `[T1, 10³⁰⁰]` costs as many points as `[T1, ∞)` needs). At
//!   most [`MAX_CRITICAL_POINTS`] are enumerated otherwise (a non-decaying oscillation over
//!   more half periods is an error, not a hang).
//!
//! The outward rounding is relative to each candidate's own value: evaluating `c(v)` has a
//! relative error of a few ulps times `1 + (|a| + |b|)v + k` (the arguments `av`, `bv`), so the
//! margin is `max_v envelope(v)·16u·(1 + (|a| + |b|)v + k)` over the candidates, plus
//! `10⁻¹²·max|c|`. (A margin `max|c|·16u·(|a| + |b|)T2` instead — the evaluation error at `T2`
//! scaled by the largest value — inflates the box of a decaying mode by a factor 7 on
//! `[1, 10¹⁵]`, where the value at `T2` is zero.)

use sporadic_linalg::InputError;
use sporadic_linalg::input::{LowerEnd, check_window};
use std::f64::consts::{FRAC_PI_2, PI};

use crate::EmbedError;

/// Largest number of interior critical points enumerated for one coefficient function (a
/// non-decaying oscillation over more half periods of the window is refused).
pub const MAX_CRITICAL_POINTS: usize = 1_000_000;

/// Relative outward margin of a range on top of the evaluation error.
const RELATIVE_MARGIN: f64 = 1e-12;

/// One scalar coefficient function `c_k(v)` of the expansion `e^{Av} = Σ_k c_k(v) N_k`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CoefficientFunction {
    /// `b(v) = e^{λv} v^k / k!` — real eigenvalue (or real cluster centre) `λ`.
    Real {
        /// The eigenvalue `λ`.
        lambda: f64,
        /// The power `k = j − 1` (index of the residue `R_j` minus one).
        power: u32,
    },
    /// `g(v) = 2 e^{av} cos(bv) v^k / k!` — multiplies `Re R_j` of the eigenvalue `a + ib`, `b > 0`.
    Cosine {
        /// Real part `a`.
        re: f64,
        /// Imaginary part `b > 0`.
        im: f64,
        /// The power `k`.
        power: u32,
    },
    /// `g*(v) = −2 e^{av} sin(bv) v^k / k!` — multiplies `Im R_j` of the eigenvalue `a + ib`, `b > 0`.
    Sine {
        /// Real part `a`.
        re: f64,
        /// Imaginary part `b > 0`.
        im: f64,
        /// The power `k`.
        power: u32,
    },
    /// `b_c(v) = e^{λ(v−c)} (v−c)^k / k!` — the power series of the whole spectrum about the
    /// centre `c` of a short window (mean eigenvalue `λ`, matrix `e^{Ac}(A − λI)^k`; see
    /// [`crate::residue`]).
    Centred {
        /// The mean eigenvalue `λ`.
        lambda: f64,
        /// The power `k`.
        power: u32,
        /// The centre `c` of the expansion.
        centre: f64,
    },
}

/// The range of a coefficient function over an interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoefficientRange {
    /// Outward-rounded lower bound (`≤ min`); equals `min` only for an exactly constant function.
    pub lower: f64,
    /// Outward-rounded upper bound (`≥ max`).
    pub upper: f64,
    /// The computed minimum value.
    pub min: f64,
    /// Where the minimum is attained.
    pub argmin: f64,
    /// The computed maximum value.
    pub max: f64,
    /// Where the maximum is attained.
    pub argmax: f64,
    /// Number of interior critical points enumerated.
    pub critical_points: usize,
}

impl CoefficientRange {
    /// Whether the range is a single value (the coefficient contributes one vertex value only).
    pub fn is_degenerate(&self) -> bool {
        self.lower == self.upper
    }
}

/// `v^k / k!` evaluated as a product of `v/i` (no overflow of `k!`).
fn power_over_factorial(v: f64, k: u32) -> f64 {
    (1..=k).fold(1.0, |p, i| p * (v / f64::from(i)))
}

/// `e^x · factor · v^k / k!` (`|factor| ≤ 2`); in logarithms when the product is not a number
/// (`e^x = 0` and `v^k/k!` overflowing, e.g. a decaying mode at `v = 10³⁰⁰`).
fn exp_times_power(x: f64, factor: f64, v: f64, k: u32) -> f64 {
    let direct = x.exp() * factor * power_over_factorial(v, k);
    if direct.is_nan() && v > 0.0 {
        factor * (x + (1..=k).map(|i| (v / f64::from(i)).ln()).sum::<f64>()).exp()
    } else {
        direct
    }
}

impl CoefficientFunction {
    /// The power `k`.
    pub fn power(&self) -> u32 {
        match *self {
            Self::Real { power, .. }
            | Self::Cosine { power, .. }
            | Self::Sine { power, .. }
            | Self::Centred { power, .. } => power,
        }
    }

    /// Evaluates `c(v)`.
    pub fn eval(&self, v: f64) -> f64 {
        match *self {
            Self::Real { lambda, power } => exp_times_power(lambda * v, 1.0, v, power),
            Self::Cosine { re, im, power } => {
                exp_times_power(re * v, 2.0 * (im * v).cos(), v, power)
            }
            Self::Sine { re, im, power } => {
                exp_times_power(re * v, -2.0 * (im * v).sin(), v, power)
            }
            Self::Centred {
                lambda,
                power,
                centre,
            } => {
                let s = v - centre;
                exp_times_power(lambda * s, 1.0, s, power)
            }
        }
    }

    /// The envelope `|c(v)| ≤ envelope(v)`: `|b(v)|` for a real eigenvalue,
    /// `2e^{av}v^k/k!` for a complex one (the size of the evaluation error at `v`).
    fn envelope(&self, v: f64) -> f64 {
        match *self {
            Self::Real { .. } | Self::Centred { .. } => self.eval(v).abs(),
            Self::Cosine { re, power, .. } | Self::Sine { re, power, .. } => {
                exp_times_power(re * v, 2.0, v, power)
            }
        }
    }

    /// Whether the function is identically constant (`λ = 0`, `k = 0`: the value 1).
    pub fn is_constant(&self) -> bool {
        matches!(
            *self,
            Self::Real { lambda, power: 0 } | Self::Centred { lambda, power: 0, .. }
                if lambda == 0.0
        )
    }

    /// Exact range over `[t1, t2]` (`0 ≤ t1 ≤ t2`), rounded outward by a small relative margin
    /// that covers the rounding errors of the evaluation.
    pub fn range(&self, t1: f64, t2: f64) -> Result<CoefficientRange, EmbedError> {
        check_window("coefficient range interval", t1, t2, LowerEnd::NonNegative)?;
        let mut candidates = vec![t1, t2];
        let mut critical = Vec::new();
        match *self {
            Self::Real { lambda, power } => {
                if power > 0 && lambda < 0.0 {
                    let v = f64::from(power) / -lambda;
                    if t1 < v && v < t2 {
                        critical.push(v);
                    }
                }
            }
            Self::Cosine { re, im, power } => critical_points(
                (re, im, power, FRAC_PI_2),
                t1,
                t2,
                |v| self.eval(v),
                &mut critical,
            )?,
            Self::Sine { re, im, power } => critical_points(
                (re, im, power, 0.0),
                t1,
                t2,
                |v| self.eval(v),
                &mut critical,
            )?,
            Self::Centred {
                lambda,
                power,
                centre,
            } => return centred_range(lambda, power, centre, t1, t2),
        }
        candidates.extend_from_slice(&critical);
        let (mut min, mut argmin, mut max, mut argmax) = (f64::INFINITY, t1, f64::NEG_INFINITY, t1);
        for &v in &candidates {
            let c = self.eval(v);
            if !c.is_finite() {
                return Err(InputError::non_finite(format!(
                    "coefficient function {self:?} at v = {v}"
                ))
                .into());
            }
            if c < min {
                (min, argmin) = (c, v);
            }
            if c > max {
                (max, argmax) = (c, v);
            }
        }
        let (lower, upper) = if self.is_constant() {
            (min, max)
        } else {
            // Evaluation error of exp/cos/sin and of the argument products at each candidate:
            // a few ulps of its envelope times the size of the arguments there (see the module
            // docs); a relative margin of 1e-12 on top.
            let (a, b) = match *self {
                Self::Real { lambda, .. } | Self::Centred { lambda, .. } => (lambda, 0.0),
                Self::Cosine { re, im, .. } | Self::Sine { re, im, .. } => (re, im),
            };
            let rounding = candidates
                .iter()
                .map(|&v| {
                    let growth = 1.0 + (a.abs() + b.abs()) * v + f64::from(self.power());
                    let e = self.envelope(v);
                    if e == 0.0 {
                        0.0
                    } else {
                        e * 16.0 * f64::EPSILON * growth
                    }
                })
                .fold(0.0, f64::max);
            let margin = min.abs().max(max.abs()) * RELATIVE_MARGIN + rounding;
            if !margin.is_finite() {
                return Err(InputError::non_finite(format!(
                    "rounding margin of the range of {self:?} on [{t1}, {t2}]"
                ))
                .into());
            }
            (min - margin, max + margin)
        };
        Ok(CoefficientRange {
            lower,
            upper,
            min,
            argmin,
            max,
            argmax,
            critical_points: critical.len(),
        })
    }
}

/// Range of [`CoefficientFunction::Centred`] over `v ∈ [t1, t2]` (see the module docs): the
/// range of `e^{λs}s^k/k!` over `s ∈ [t1 − c, t2 − c]`, joined from the side `s ≥ 0`
/// (`b` with `λ`) and the side `s = −u ≤ 0` (`(−1)^k` times `b` with `−λ` at `u`). The ends are
/// widened by one relative unit roundoff each, which covers the rounding of `t − c`.
fn centred_range(
    lambda: f64,
    power: u32,
    centre: f64,
    t1: f64,
    t2: f64,
) -> Result<CoefficientRange, EmbedError> {
    let s1 = t1 - centre;
    let s1 = s1 - s1.abs() * f64::EPSILON;
    let s2 = t2 - centre;
    let s2 = s2 + s2.abs() * f64::EPSILON;
    let mut sides = Vec::with_capacity(2);
    if s2 >= 0.0 {
        let r = CoefficientFunction::Real { lambda, power }.range(s1.max(0.0), s2)?;
        sides.push(CoefficientRange {
            argmin: r.argmin + centre,
            argmax: r.argmax + centre,
            ..r
        });
    }
    if s1 < 0.0 {
        let r = CoefficientFunction::Real {
            lambda: -lambda,
            power,
        }
        .range((-s2).max(0.0), -s1)?;
        sides.push(if power.is_multiple_of(2) {
            CoefficientRange {
                argmin: centre - r.argmin,
                argmax: centre - r.argmax,
                ..r
            }
        } else {
            CoefficientRange {
                lower: -r.upper,
                upper: -r.lower,
                min: -r.max,
                argmin: centre - r.argmax,
                max: -r.min,
                argmax: centre - r.argmin,
                critical_points: r.critical_points,
            }
        });
    }
    // `s1 ≤ s2`, so at least one side is present.
    let mut out = sides[0];
    for r in &sides[1..] {
        out.lower = out.lower.min(r.lower);
        out.upper = out.upper.max(r.upper);
        if r.min < out.min {
            (out.min, out.argmin) = (r.min, r.argmin);
        }
        if r.max > out.max {
            (out.max, out.argmax) = (r.max, r.argmax);
        }
        out.critical_points += r.critical_points;
    }
    Ok(out)
}

/// Phase `ψ(v) = bv + φ(v)` and its derivative (see the module documentation).
fn phase(re: f64, im: f64, power: u32, v: f64) -> (f64, f64) {
    if power == 0 {
        (im * v + im.atan2(re), im)
    } else {
        let p = re * v + f64::from(power);
        let q = im * v;
        (
            im * v + q.atan2(p),
            im * (1.0 + f64::from(power) / (p * p + q * q)),
        )
    }
}

/// Appends every `v ∈ (t1, t2)` with `ψ(v) = offset + mπ` (in increasing order) for the mode
/// `(re, im, power)`, `eval` being the coefficient function; for a decaying mode it stops where
/// the envelope falls below both extremal values found so far (see the module docs).
///
/// # Errors
/// More than [`MAX_CRITICAL_POINTS`] critical points would be needed.
fn critical_points(
    (re, im, power, offset): (f64, f64, u32, f64),
    t1: f64,
    t2: f64,
    eval: impl Fn(f64) -> f64,
    out: &mut Vec<f64>,
) -> Result<(), EmbedError> {
    if im <= 0.0 || t1 == t2 {
        // Not produced by the residue expansion (b > 0 always); a zero frequency has no
        // oscillation and a degenerate interval has no interior.
        if im == 0.0 {
            // 2 e^{av} v^k / k! (cosine) has the real critical point −k/a; the sine is ≡ 0.
            if offset != 0.0 && power > 0 && re < 0.0 {
                let v = f64::from(power) / -re;
                if t1 < v && v < t2 {
                    out.push(v);
                }
            }
        }
        return Ok(());
    }
    let psi1 = phase(re, im, power, t1).0;
    let psi2 = phase(re, im, power, t2).0;
    let m_lo = ((psi1 - offset) / PI).ceil() as i64;
    let m_hi = ((psi2 - offset) / PI).floor() as i64;
    // The envelope 2e^{av}v^k/k! decreases from k/|a| on when a < 0.
    let decreasing_from = if re < 0.0 {
        f64::from(power) / -re
    } else {
        f64::INFINITY
    };
    let envelope = |v: f64| exp_times_power(re * v, 2.0, v, power);
    let (e1, e2) = (eval(t1), eval(t2));
    let (mut lowest, mut highest) = (e1.min(e2), e1.max(e2));
    let mut lo = t1;
    let mut m = m_lo;
    while m <= m_hi {
        if out.len() >= MAX_CRITICAL_POINTS {
            return Err(EmbedError::InvalidArgument(format!(
                "the coefficient function of the eigenvalue {re} ± {im}i has more than \
                 {MAX_CRITICAL_POINTS} critical points on [{t1}, {t2}] (a non-decaying \
                 oscillation over too many periods)"
            )));
        }
        let level = offset + m as f64 * PI;
        m = m.saturating_add(1);
        if level <= psi1 || level >= psi2 {
            continue;
        }
        // ψ' ≥ b: the level is reached within (level − ψ(lo))/b of lo (twice that, for the
        // rounding of ψ).
        let reach = lo + 2.0 * (level - phase(re, im, power, lo).0) / im;
        let hi = if reach > lo && reach < t2 { reach } else { t2 };
        let v = solve_monotone(|v| phase(re, im, power, v), level, lo, hi);
        if t1 < v && v < t2 {
            out.push(v);
            lo = v;
            let c = eval(v);
            (lowest, highest) = (lowest.min(c), highest.max(c));
            if v >= decreasing_from && 2.0 * envelope(v) <= (-lowest).min(highest) {
                break;
            }
        }
    }
    Ok(())
}

/// Solves `f(v) = level` for a continuous strictly increasing `f` with `f(lo) < level < f(hi)`
/// by Newton's method safeguarded with bisection (`f` returns value and derivative).
fn solve_monotone(f: impl Fn(f64) -> (f64, f64), level: f64, mut lo: f64, mut hi: f64) -> f64 {
    let mut x = 0.5 * (lo + hi);
    for _ in 0..200 {
        let (fx, dfx) = f(x);
        let r = fx - level;
        if r == 0.0 {
            return x;
        }
        if r < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let newton = x - r / dfx;
        let next = if dfx > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - x).abs() <= 2.0 * f64::EPSILON * x.abs().max(f64::MIN_POSITIVE)
            || hi - lo <= 2.0 * f64::EPSILON * hi.abs()
        {
            return next;
        }
        x = next;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    /// Brute-force range on a dense grid (a lower estimate of the true range).
    fn dense(f: &CoefficientFunction, t1: f64, t2: f64, n: usize) -> (f64, f64) {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for i in 0..=n {
            let v = t1 + (t2 - t1) * i as f64 / n as f64;
            let c = f.eval(v);
            lo = lo.min(c);
            hi = hi.max(c);
        }
        (lo, hi)
    }

    #[test]
    fn real_critical_point_closed_form() {
        // e^{-2v} v^2 / 2 has its maximum at v = 1: e^{-2}/2.
        let f = CoefficientFunction::Real {
            lambda: -2.0,
            power: 2,
        };
        let r = f.range(0.0, 3.0).unwrap();
        assert_relative_eq!(r.argmax, 1.0, epsilon = 1e-15);
        assert_relative_eq!(r.max, (-2.0f64).exp() / 2.0, max_relative = 1e-15);
        assert_eq!(r.min, 0.0);
        assert!(r.lower < r.min && r.upper > r.max);
    }

    #[test]
    fn centred_odd_power_changes_sign_at_the_centre() {
        // (v − 1)³/6 on [0, 2.5] about 1: from −1/6 at v = 0 to 1.5³/6 at v = 2.5.
        let f = CoefficientFunction::Centred {
            lambda: 0.0,
            power: 3,
            centre: 1.0,
        };
        let r = f.range(0.0, 2.5).unwrap();
        assert_relative_eq!(r.min, -1.0 / 6.0, max_relative = 1e-15);
        assert_relative_eq!(r.max, 1.5f64.powi(3) / 6.0, max_relative = 1e-15);
        assert!(r.argmin.abs() < 1e-15 && (r.argmax - 2.5).abs() < 1e-15);
        assert!(r.lower < r.min && r.upper > r.max);
        // e^{−2(v−1)}: decreasing, so its range is [e^{−3}, e^{2}] on [0, 2.5].
        let g = CoefficientFunction::Centred {
            lambda: -2.0,
            power: 0,
            centre: 1.0,
        };
        let r = g.range(0.0, 2.5).unwrap();
        assert_relative_eq!(r.min, (-3.0f64).exp(), max_relative = 1e-15);
        assert_relative_eq!(r.max, 2.0f64.exp(), max_relative = 1e-15);
    }

    #[test]
    fn constant_coefficient_is_a_single_value() {
        let f = CoefficientFunction::Real {
            lambda: 0.0,
            power: 0,
        };
        let r = f.range(0.2, 3.0).unwrap();
        assert!(r.is_degenerate());
        assert_eq!(r.lower, 1.0);
    }

    #[test]
    fn ferrante_example_2_ranges() {
        // Ferrante et al. (2016), Example 2, values from an independent reference implementation
        // (scipy): the complex pair
        // -0.6805515403 ± 1.6331702409 i and the real eigenvalues on [0.2, 3].
        let (a, b) = (-0.680_551_540_3, 1.633_170_240_9);
        let g = CoefficientFunction::Cosine {
            re: a,
            im: b,
            power: 0,
        }
        .range(0.2, 3.0)
        .unwrap();
        assert!((g.min - -0.587_720_546_6).abs() < 1e-8);
        assert!((g.argmin - 1.681_863).abs() < 1e-6);
        assert!((g.max - 1.653_204_490_3).abs() < 1e-8);
        assert_eq!(g.argmax, 0.2);
        let s = CoefficientFunction::Sine {
            re: a,
            im: b,
            power: 0,
        }
        .range(0.2, 3.0)
        .unwrap();
        assert!((s.min - -1.130_948_049_0).abs() < 1e-8);
        assert!((s.argmin - 0.720_055).abs() < 1e-6);
        assert!((s.max - 0.305_421_138_6).abs() < 1e-8);
        assert!((s.argmax - 2.643_671).abs() < 1e-6);
        let e = CoefficientFunction::Real {
            lambda: -0.638_896_919_5,
            power: 0,
        }
        .range(0.2, 3.0)
        .unwrap();
        assert!((e.min - 0.147_092_923_6).abs() < 1e-9);
        assert!((e.max - 0.880_047_510_4).abs() < 1e-9);
    }

    #[test]
    fn many_oscillations_are_all_enumerated() {
        // b (T2 − T1) / π ≈ 318 half periods: every one has a critical point.
        let f = CoefficientFunction::Cosine {
            re: -0.01,
            im: 100.0,
            power: 1,
        };
        let r = f.range(0.0, 10.0).unwrap();
        assert!(
            r.critical_points >= 317 && r.critical_points <= 320,
            "{}",
            r.critical_points
        );
        let (lo, hi) = dense(&f, 0.0, 10.0, 400_000);
        assert!(r.lower <= lo && r.upper >= hi);
        // Samples are 2.5e-3 rad apart: they miss the peaks by at most ~(2.5e-3)²/2 relative.
        assert!(
            r.max - hi < 1e-5 * hi.abs() && lo - r.min < 1e-5 * lo.abs(),
            "{r:?} {lo} {hi}"
        );
    }

    #[test]
    fn derivative_vanishes_at_the_critical_points() {
        for f in [
            CoefficientFunction::Cosine {
                re: -0.7,
                im: 2.3,
                power: 2,
            },
            CoefficientFunction::Sine {
                re: 0.4,
                im: 0.9,
                power: 3,
            },
            CoefficientFunction::Sine {
                re: -1.0,
                im: 5.0,
                power: 0,
            },
        ] {
            let mut crit = Vec::new();
            let (re, im, power, off) = match f {
                CoefficientFunction::Cosine { re, im, power } => (re, im, power, FRAC_PI_2),
                CoefficientFunction::Sine { re, im, power } => (re, im, power, 0.0),
                CoefficientFunction::Real { .. } | CoefficientFunction::Centred { .. } => {
                    unreachable!()
                }
            };
            critical_points((re, im, power, off), 0.05, 6.0, |v| f.eval(v), &mut crit).unwrap();
            assert!(!crit.is_empty());
            for v in crit {
                let h = 1e-6;
                let d = (f.eval(v + h) - f.eval(v - h)) / (2.0 * h);
                let scale = f.eval(v).abs().max(1e-3);
                assert!(d.abs() < 1e-6 * scale.max(1.0), "{f:?} v={v} d={d}");
            }
        }
    }

    /// Issue 22: on `[1, 10¹⁵]` the box of a decaying mode is its range, not seven times it
    /// (the rounding margin is relative to each candidate's value, and the value at `T2` is 0).
    #[test]
    fn long_window_range_is_not_inflated() {
        for t2 in [1e3, 1e15, 1e100, 1e308] {
            for power in [0, 2] {
                let f = CoefficientFunction::Real {
                    lambda: -2.0,
                    power,
                };
                let r = f.range(1.0, t2).unwrap();
                let peak = f.eval(1.0).max(f.eval(1.0f64.max(f64::from(power) / 2.0)));
                assert!(r.lower <= 0.0 && r.lower > -1e-11 * peak, "{t2} {r:?}");
                assert!(
                    r.upper >= r.max && r.upper < r.max * (1.0 + 1e-11),
                    "{t2} {r:?}"
                );
            }
        }
    }

    /// A decaying oscillation on `[1, 10³⁰⁰]` stops enumerating critical points once its
    /// envelope is below the extremes found; a non-decaying one over too many periods is an
    /// error, not a hang.
    #[test]
    fn long_window_oscillation_terminates() {
        let f = CoefficientFunction::Cosine {
            re: -1.0,
            im: 3.0,
            power: 1,
        };
        let r = f.range(1.0, 1e300).unwrap();
        let short = f.range(1.0, 100.0).unwrap();
        assert!(r.critical_points < 40, "{r:?}");
        assert_eq!((r.min, r.max), (short.min, short.max));
        let g = CoefficientFunction::Sine {
            re: 0.0,
            im: 1.0,
            power: 0,
        };
        assert!(matches!(
            g.range(0.0, 1e15),
            Err(EmbedError::InvalidArgument(_))
        ));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn range_encloses_dense_samples(
            re in -3.0f64..1.0, im in 0.01f64..8.0, power in 0u32..4, kind in 0u8..4,
            t1 in 0.0f64..2.0, len in 0.0f64..4.0, at in -0.5f64..1.5,
        ) {
            let f = match kind {
                0 => CoefficientFunction::Real { lambda: re, power },
                1 => CoefficientFunction::Cosine { re, im, power },
                2 => CoefficientFunction::Sine { re, im, power },
                // Centres inside, at the ends of, and outside the interval.
                _ => CoefficientFunction::Centred { lambda: re, power, centre: t1 + at * len },
            };
            let t2 = t1 + len;
            let r = f.range(t1, t2).unwrap();
            let (lo, hi) = dense(&f, t1, t2, 20_000);
            prop_assert!(r.lower <= lo && r.upper >= hi, "{:?} {:?} {} {}", f, r, lo, hi);
            // The exact extrema are at least as extreme as any sample, and not much more.
            let scale = lo.abs().max(hi.abs()).max(1e-300);
            prop_assert!(r.min <= lo + 1e-14 * scale && r.max >= hi - 1e-14 * scale);
            prop_assert!(r.upper - r.lower <= (hi - lo) + 1e-3 * scale + 1e-11 * scale);
        }
    }
}
