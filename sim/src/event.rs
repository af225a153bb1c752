//! Event functions (state/time-triggered jumps `g(t, x) = 0`) and their location by bracketing plus
//! Brent's method (R. P. Brent, *Algorithms for Minimization without Derivatives*, 1973, Ch. 4: the
//! `zeroin` combination of bisection, secant and inverse quadratic interpolation, which keeps the bracket
//! and converges superlinearly on smooth functions).

use crate::error::SimError;
use sporadic_linalg::InputError;

/// Which zero crossings of an event function trigger the event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// `g` goes from negative to nonnegative.
    Rising,
    /// `g` goes from positive to nonpositive.
    Falling,
    /// Either of the above.
    Either,
}

impl Direction {
    /// Whether the change of sign `g0 → g1` over a step is a triggering crossing. A step that *starts* on
    /// `g = 0` never triggers (the event was handled when the previous step ended there).
    pub fn crosses(self, g0: f64, g1: f64) -> bool {
        let rising = g0 < 0.0 && g1 >= 0.0;
        let falling = g0 > 0.0 && g1 <= 0.0;
        match self {
            Self::Rising => rising,
            Self::Falling => falling,
            Self::Either => rising || falling,
        }
    }
}

/// An event `g(t, x) = 0` crossed in a given direction.
pub struct Event<'a> {
    /// The event function.
    pub g: &'a dyn Fn(f64, &[f64]) -> f64,
    /// Which crossings count.
    pub direction: Direction,
}

impl<'a> Event<'a> {
    /// Event triggered by `g` crossing zero in `direction`.
    pub fn new(g: &'a dyn Fn(f64, &[f64]) -> f64, direction: Direction) -> Self {
        Self { g, direction }
    }
}

/// Finds a zero of `f` in the bracket `[a, b]` with `f(a) = fa`, `f(b) = fb` of opposite signs (or one of
/// them zero), to an absolute tolerance `xtol` in `x` (plus four units in the last place of the iterate),
/// by Brent's method. Returns the end of the final bracket that has the sign of `f(b)` (or an exact zero),
/// so that the crossing has certainly happened at the returned point.
pub fn brent<F: FnMut(f64) -> f64>(
    mut f: F,
    a: f64,
    b: f64,
    fa: f64,
    fb: f64,
    xtol: f64,
) -> Result<f64, SimError> {
    if !(a.is_finite() && b.is_finite() && fa.is_finite() && fb.is_finite()) {
        return Err(InputError::non_finite("root bracket").into());
    }
    if fa == 0.0 {
        return Ok(a);
    }
    if fb == 0.0 {
        return Ok(b);
    }
    if fa.signum() == fb.signum() {
        return Err(SimError::invalid(format!(
            "no sign change on [{a}, {b}]: f = {fa}, {fb}"
        )));
    }
    let after_sign = fb.signum();
    // Notation of Brent (1973): b is the best iterate, c the contrapoint, a the previous iterate.
    let (mut a, mut fa) = (a, fa);
    let (mut b, mut fb) = (b, fb);
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..200 {
        if fb.signum() == fc.signum() {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * xtol;
        let m = 0.5 * (c - b);
        if fb == 0.0 {
            return Ok(b);
        }
        if m.abs() <= tol {
            // The bracket [b, c] is small enough: return its end on the post-crossing side.
            return Ok(if fb.signum() == after_sign { b } else { c });
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            // Interpolation: secant (two points) or inverse quadratic (three points).
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol.copysign(m) };
        fb = f(b);
        if !fb.is_finite() {
            return Err(InputError::non_finite(format!("event function at t = {b}")).into());
        }
    }
    Err(SimError::invalid(
        "Brent's method did not converge in 200 iterations",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        /// f(x) = (x − r)(1 + (x − r)²)·s has the single root r; Brent finds it to the requested tolerance
        /// and returns a point on the post-crossing side.
        #[test]
        fn brent_locates_random_roots(r in -5.0f64..5.0, w1 in 1e-3f64..3.0, w2 in 1e-3f64..3.0, s in prop_oneof![Just(-1.0), Just(1.0)]) {
            let f = |x: f64| s * (x - r) * (1.0 + (x - r).powi(2));
            let (a, b) = (r - w1, r + w2);
            let root = brent(f, a, b, f(a), f(b), 1e-13).unwrap();
            prop_assert!((root - r).abs() <= 1e-13 + 8.0 * f64::EPSILON * r.abs().max(1.0), "{} vs {}", root, r);
            prop_assert!(f(root) == 0.0 || f(root).signum() == f(b).signum());
        }
    }

    #[test]
    fn brent_finds_known_roots() {
        let r = brent(|x| x * x - 2.0, 0.0, 2.0, -2.0, 2.0, 1e-14).unwrap();
        assert!((r - std::f64::consts::SQRT_2).abs() < 1e-13);
        let r = brent(|x: f64| x.cos(), 0.0, 3.0, 1.0, 3f64.cos(), 1e-15).unwrap();
        assert!((r - std::f64::consts::FRAC_PI_2).abs() < 1e-14);
        // A function with a flat region and a kink.
        let f = |x: f64| if x < 0.3 { -1.0 } else { (x - 0.3) * 1e-3 };
        let r = brent(f, 0.0, 1.0, -1.0, f(1.0), 1e-13).unwrap();
        assert!((r - 0.3).abs() < 1e-12);
        assert!(brent(|x| x, 1.0, 2.0, 1.0, 2.0, 1e-12).is_err());
    }

    #[test]
    fn directions() {
        assert!(Direction::Rising.crosses(-1.0, 0.0));
        assert!(!Direction::Rising.crosses(1.0, -1.0));
        assert!(Direction::Falling.crosses(1.0, -1.0));
        assert!(Direction::Either.crosses(1.0, -1.0));
        assert!(!Direction::Either.crosses(0.0, 1.0));
    }
}
