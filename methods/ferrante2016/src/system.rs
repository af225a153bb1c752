//! The data of Problem 1 (Ferrante et al. 2016, §2): the pair `(A, M)` of plant (1) and the window
//! `[T1, T2]` of admissible inter-sample times (2).
//!
//! The input matrix `B` does not enter the error dynamics (5), so the design and analysis only need
//! `(A, M)`; simulations of the plant/observer pair take `B` separately.

use faer::{Mat, MatRef};
use sporadic_embed::Interval;
use sporadic_linalg::InputError;

use sporadic_linalg::input::{LowerEnd, check_finite, check_window};

use crate::error::Error;

/// The pair `(A, M)` of plant (1): `ż = Az + Bu`, `y = Mz`, with `A ∈ R^{n×n}`, `M ∈ R^{q×n}`.
#[derive(Debug, Clone, PartialEq)]
pub struct Plant {
    a: Mat<f64>,
    m: Mat<f64>,
}

impl Plant {
    /// Validates `A` (square, non-empty, finite) and `M` (`q × n` with `q ≥ 1`, finite).
    pub fn new(a: MatRef<'_, f64>, m: MatRef<'_, f64>) -> Result<Self, Error> {
        if a.nrows() != a.ncols() {
            return Err(Error::Input(InputError::NotSquare {
                what: "A".into(),
                rows: a.nrows(),
                cols: a.ncols(),
            }));
        }
        if a.nrows() == 0 {
            return Err(InputError::empty("A (n = 0)").into());
        }
        if m.nrows() == 0 {
            return Err(InputError::empty("M (no measured output, q = 0)").into());
        }
        if m.ncols() != a.nrows() {
            return Err(
                InputError::mismatch("columns of M vs order of A", a.nrows(), m.ncols()).into(),
            );
        }
        check_finite(a, "A")?;
        check_finite(m, "M")?;
        Ok(Self {
            a: a.to_owned(),
            m: m.to_owned(),
        })
    }

    /// The state matrix `A`.
    pub fn a(&self) -> MatRef<'_, f64> {
        self.a.as_ref()
    }

    /// The output matrix `M`.
    pub fn m(&self) -> MatRef<'_, f64> {
        self.m.as_ref()
    }

    /// State dimension `n`.
    pub fn n(&self) -> usize {
        self.a.nrows()
    }

    /// Output dimension `q`.
    pub fn q(&self) -> usize {
        self.m.nrows()
    }

    /// Checks that `L` is a finite `n × q` matrix.
    pub fn check_gain(&self, l: MatRef<'_, f64>) -> Result<(), Error> {
        if l.nrows() != self.n() {
            return Err(InputError::mismatch("rows of L vs n", self.n(), l.nrows()).into());
        }
        if l.ncols() != self.q() {
            return Err(InputError::mismatch("columns of L vs q", self.q(), l.ncols()).into());
        }
        Ok(check_finite(l, "L")?)
    }

    /// Checks that `P` is a finite symmetric `n × n` matrix (relative asymmetry at most `1e-10`).
    pub fn check_lyapunov_matrix(&self, p: MatRef<'_, f64>) -> Result<(), Error> {
        if p.nrows() != p.ncols() {
            return Err(Error::Input(InputError::NotSquare {
                what: "P".into(),
                rows: p.nrows(),
                cols: p.ncols(),
            }));
        }
        if p.nrows() != self.n() {
            return Err(InputError::mismatch("order of P vs n", self.n(), p.nrows()).into());
        }
        check_finite(p, "P")?;
        let scale = p.norm_max().max(f64::MIN_POSITIVE);
        for j in 0..p.ncols() {
            for i in 0..j {
                if (p[(i, j)] - p[(j, i)]).abs() > 1e-10 * scale {
                    return Err(InputError::parameter(
                        "P",
                        p[(i, j)] - p[(j, i)],
                        "P must be symmetric (the value is P_ij − P_ji)",
                    )
                    .into());
                }
            }
        }
        Ok(())
    }

    /// The jump matrix `I − LM` of the error dynamics (5).
    pub fn reset_matrix(&self, l: MatRef<'_, f64>) -> Result<Mat<f64>, Error> {
        self.check_gain(l)?;
        let lm = l * self.m();
        Ok(Mat::from_fn(self.n(), self.n(), |i, j| {
            f64::from(u8::from(i == j)) - lm[(i, j)]
        }))
    }
}

/// The window `[T1, T2]` of inter-sample times of (2), with `0 < T1 ≤ T2 < ∞`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Window {
    interval: Interval,
}

impl Window {
    /// Validates `0 < T1 ≤ T2 < ∞` (`T1 > 0` excludes Zeno behaviour, §2.1).
    pub fn new(t1: f64, t2: f64) -> Result<Self, Error> {
        check_window("sampling window", t1, t2, LowerEnd::Positive)?;
        Ok(Self {
            interval: Interval::new(t1, t2)?,
        })
    }

    /// Minimal inter-sample time `T1`.
    pub fn t1(&self) -> f64 {
        self.interval.t1()
    }

    /// Maximal inter-sample time `T2`.
    pub fn t2(&self) -> f64 {
        self.interval.t2()
    }

    /// Whether `T1 = T2` (periodic sampling).
    pub fn is_periodic(&self) -> bool {
        self.interval.is_point()
    }

    /// `points` equally spaced inter-sample times covering `[T1, T2]` (both ends included; a single
    /// point `T1` when the window is periodic or `points ≤ 1`).
    pub fn grid(&self, points: usize) -> Vec<f64> {
        self.interval.grid(points)
    }

    /// The window as an [`Interval`] of `sporadic-embed`.
    pub fn interval(&self) -> Interval {
        self.interval
    }
}
