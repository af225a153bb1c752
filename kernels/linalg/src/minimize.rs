//! One-dimensional minimisation by golden-section search (Kiefer 1953; Press et al., *Numerical
//! Recipes*, 3rd ed., §10.2).
//!
//! The bracket `[lo, hi]` holds two interior points `x₁ = hi − r(hi − lo)`, `x₂ = lo + r(hi − lo)`,
//! `r = (√5 − 1)/2 ≈ 0.618`. Each iteration drops the end beyond the worse interior point; the
//! better one becomes an interior point of the new bracket at the golden ratio, so one new
//! evaluation per iteration shrinks the bracket by the factor `r`. For a unimodal objective the
//! minimiser stays in the bracket. Near a smooth minimum the objective is flat to rounding over a
//! width of order `√ε` (relative), which bounds the attainable accuracy of the argument.

use crate::input::InputError;

/// Result of [`golden_section`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Minimum {
    /// The best point evaluated.
    pub at: f64,
    /// The objective there.
    pub value: f64,
    /// Number of objective evaluations (`iterations + 2`).
    pub evaluations: usize,
}

/// Golden-section search for a minimiser of `f` on `[lo, hi]` with `iterations` bracket reductions
/// (module docs): the returned point is the best one evaluated, within `0.618^iterations · (hi − lo)`
/// of the minimiser when `f` is unimodal on `[lo, hi]` (up to the rounding-limited flatness of `f`).
///
/// `f` may return `+∞` where the objective is undefined (e.g. an infeasible parameter); such points
/// lose every comparison. On a tie (both `+∞` included) the left end of the bracket is dropped. Errors of `f` are passed through unchanged. To maximise, minimise `−f`.
///
/// # Errors
/// [`InputError::InvalidWindow`] unless `lo ≤ hi` are finite; [`InputError::NonFinite`] if `f`
/// returns NaN; any error of `f`.
pub fn golden_section<E, F>(lo: f64, hi: f64, iterations: usize, mut f: F) -> Result<Minimum, E>
where
    E: From<InputError>,
    F: FnMut(f64) -> Result<f64, E>,
{
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(InputError::window(
            "golden-section bracket",
            lo,
            hi,
            "both ends must be finite",
        )
        .into());
    }
    if lo > hi {
        return Err(InputError::window(
            "golden-section bracket",
            lo,
            hi,
            "the lower end must not exceed the upper end",
        )
        .into());
    }
    let mut eval = |x: f64| -> Result<f64, E> {
        let v = f(x)?;
        if v.is_nan() {
            return Err(
                InputError::non_finite(format!("golden-section objective at x = {x}")).into(),
            );
        }
        Ok(v)
    };
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (lo, hi);
    let mut x1 = hi - r * (hi - lo);
    let mut x2 = lo + r * (hi - lo);
    let mut f1 = eval(x1)?;
    let mut f2 = eval(x2)?;
    for _ in 0..iterations {
        if f1 < f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - r * (hi - lo);
            f1 = eval(x1)?;
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + r * (hi - lo);
            f2 = eval(x2)?;
        }
    }
    let (at, value) = if f1 <= f2 { (x1, f1) } else { (x2, f2) };
    Ok(Minimum {
        at,
        value,
        evaluations: iterations + 2,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::LinalgError;
    use proptest::prelude::*;

    fn min_of(
        lo: f64,
        hi: f64,
        iterations: usize,
        f: impl Fn(f64) -> f64,
    ) -> Result<Minimum, InputError> {
        golden_section(lo, hi, iterations, |x| Ok(f(x)))
    }

    /// `(x − 0.3)² + 2` on `[0, 1]`: the bracket after 60 iterations is `0.618⁶⁰ ≈ 3·10⁻¹³` wide, so
    /// the argument is limited by the flatness of the objective (`√ε ≈ 1.5·10⁻⁸` relative).
    #[test]
    fn quadratic_and_evaluation_count() {
        let mut calls = 0;
        let m = golden_section(0.0, 1.0, 60, |x| {
            calls += 1;
            Ok::<_, InputError>((x - 0.3) * (x - 0.3) + 2.0)
        })
        .unwrap();
        assert!((m.at - 0.3).abs() < 1e-7, "{m:?}");
        assert!(m.value - 2.0 < 1e-15);
        assert_eq!((m.evaluations, calls), (62, 62));
        // Zero iterations: the better of the two initial interior points, 1 − r and r.
        let r = 0.5 * (5f64.sqrt() - 1.0);
        let m0 = min_of(0.0, 1.0, 0, |x| (x - 0.3) * (x - 0.3)).unwrap();
        assert_eq!((m0.at, m0.evaluations), (1.0 - r, 2));
    }

    /// A monotone objective drives the search to the end of the bracket; a degenerate bracket
    /// returns its single point.
    #[test]
    fn monotone_and_degenerate_brackets() {
        let m = min_of(-2.0, 5.0, 80, |x| -x).unwrap();
        assert!(5.0 - m.at < 1e-12 && m.at <= 5.0, "{m:?}");
        let m = min_of(1.5, 1.5, 10, |x| x * x).unwrap();
        assert_eq!((m.at, m.value), (1.5, 2.25));
    }

    /// `+∞` marks undefined points: the minimiser of `(x − x*)²` on the defined part `x ≥ edge`. With
    /// `edge = 0.9` both initial interior points are undefined: ties drop the left end, towards it.
    #[test]
    fn infinite_values_lose_comparisons() {
        for (edge, x_star) in [(0.5, 0.7), (0.9, 0.95)] {
            let m = min_of(0.0, 1.0, 60, |x| {
                if x < edge {
                    f64::INFINITY
                } else {
                    (x - x_star) * (x - x_star)
                }
            })
            .unwrap();
            assert!((m.at - x_star).abs() < 1e-7, "{m:?}");
        }
    }

    #[test]
    fn bad_bracket_nan_objective_and_errors_of_f() {
        assert!(matches!(
            min_of(1.0, 0.0, 5, |x| x),
            Err(InputError::InvalidWindow { .. })
        ));
        assert!(matches!(
            min_of(0.0, f64::INFINITY, 5, |x| x),
            Err(InputError::InvalidWindow { .. })
        ));
        assert!(matches!(
            min_of(f64::NAN, 1.0, 5, |x| x),
            Err(InputError::InvalidWindow { .. })
        ));
        assert!(matches!(
            min_of(0.0, 1.0, 5, |_| f64::NAN),
            Err(InputError::NonFinite { .. })
        ));
        let err = golden_section(0.0, 1.0, 5, |x| {
            if x > 0.5 {
                Err(LinalgError::singular("test objective"))
            } else {
                Ok(x)
            }
        });
        assert_eq!(err, Err(LinalgError::singular("test objective")));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        /// Random convex quadratics `a(x − x*)² + b`: with `x*` inside the bracket the minimiser is
        /// found to the flatness limit `√(ε|b|/a)` (here below 10⁻⁶); with `x*` outside, the nearer end.
        #[test]
        fn convex_quadratics(
            a in 0.1f64..10.0,
            b in -10.0f64..10.0,
            lo in -5.0f64..5.0,
            width in 0.1f64..10.0,
            s in -0.5f64..1.5,
        ) {
            let hi = lo + width;
            let x_star = lo + s * width;
            let m = min_of(lo, hi, 60, |x| a * (x - x_star) * (x - x_star) + b).unwrap();
            let target = x_star.clamp(lo, hi);
            prop_assert!((m.at - target).abs() < 1e-6, "{m:?}, target {target}");
            let f_target = a * (target - x_star) * (target - x_star) + b;
            prop_assert!(m.value >= f_target - 1e-14 * (1.0 + b.abs()));
            prop_assert!(m.value - f_target < 1e-10 * (1.0 + b.abs() + a * width * width), "{m:?}");
            prop_assert!(lo <= m.at && m.at <= hi);
        }
    }
}
