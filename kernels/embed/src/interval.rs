//! The sampling window `[T1, T2]` of inter-sample times and input validation.
//!
//! Ferrante et al. (2016) eq. (2) require `0 < T1 ≤ T2`; the embedding of `v ↦ e^{Av}` itself is
//! well defined for `T1 = 0` as well, so `T1 = 0` is accepted here and only `T1 < 0`, `T1 > T2`
//! and non-finite ends are rejected.

use sporadic_linalg::input::{LowerEnd, check_window};

use crate::EmbedError;

/// A validated interval `[T1, T2]` with `0 ≤ T1 ≤ T2 < ∞`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    t1: f64,
    t2: f64,
}

impl Interval {
    /// Validates `0 ≤ t1 ≤ t2`, both finite.
    pub fn new(t1: f64, t2: f64) -> Result<Self, EmbedError> {
        check_window("sampling interval", t1, t2, LowerEnd::NonNegative)?;
        Ok(Self { t1, t2 })
    }

    /// Lower end `T1`.
    pub fn t1(&self) -> f64 {
        self.t1
    }

    /// Upper end `T2`.
    pub fn t2(&self) -> f64 {
        self.t2
    }

    /// Length `T2 − T1`.
    pub fn length(&self) -> f64 {
        self.t2 - self.t1
    }

    /// Whether `T1 = T2` (periodic sampling).
    pub fn is_point(&self) -> bool {
        self.t1 == self.t2
    }

    /// Whether `τ ∈ [T1, T2]`.
    pub fn contains(&self, tau: f64) -> bool {
        self.t1 <= tau && tau <= self.t2
    }

    /// Splits into `pieces` sub-intervals of equal length. The ends are reproduced exactly and
    /// consecutive pieces share their common end point.
    pub fn split(&self, pieces: usize) -> Result<Vec<Interval>, EmbedError> {
        if pieces == 0 {
            return Err(EmbedError::InvalidArgument(
                "an interval cannot be split into 0 pieces".into(),
            ));
        }
        let point = |i: usize| {
            if i == pieces {
                self.t2
            } else {
                self.t1 + self.length() * (i as f64 / pieces as f64)
            }
        };
        Ok((0..pieces)
            .map(|i| Interval {
                t1: point(i),
                t2: point(i + 1),
            })
            .collect())
    }

    /// `points ≥ 2` equally spaced points from `T1` to `T2` (both included); a single point
    /// `T1` when the interval is degenerate or `points < 2`.
    pub fn grid(&self, points: usize) -> Vec<f64> {
        if self.is_point() || points < 2 {
            return vec![self.t1];
        }
        let steps = points - 1;
        (0..=steps)
            .map(|i| {
                if i == steps {
                    self.t2
                } else {
                    self.t1 + self.length() * (i as f64 / steps as f64)
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sporadic_linalg::InputError;

    #[test]
    fn rejects_bad_intervals() {
        for (t1, t2) in [
            (0.3, 0.2),
            (-0.1, 1.0),
            (f64::NAN, 1.0),
            (0.0, f64::INFINITY),
        ] {
            assert!(matches!(
                Interval::new(t1, t2),
                Err(EmbedError::Input(InputError::InvalidWindow { .. }))
            ));
        }
        assert!(Interval::new(0.0, 0.0).unwrap().is_point());
    }

    #[test]
    fn split_and_grid_reproduce_ends() {
        let i = Interval::new(0.2, 3.0).unwrap();
        let p = i.split(7).unwrap();
        assert_eq!(p.len(), 7);
        assert_eq!(p[0].t1(), 0.2);
        assert_eq!(p[6].t2(), 3.0);
        for w in p.windows(2) {
            assert_eq!(w[0].t2(), w[1].t1());
        }
        let g = i.grid(11);
        assert_eq!(g.len(), 11);
        assert_eq!((g[0], g[10]), (0.2, 3.0));
        assert!(i.split(0).is_err());
    }
}
