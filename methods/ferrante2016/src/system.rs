//! The data of Problem 1 (Ferrante et al. 2016, §2): the pair `(A, M)` of plant (1). The window
//! `[T1, T2]` of admissible inter-sample times (2) is a [`sporadic_model::SamplingWindow`].
//!
//! The paper calls the output matrix `M` (`y = Mz`); this crate's API calls it `C`, as every
//! other method of `sporadic` does ([`Plant::new`]'s `c`, [`Plant::c`]).
//!
//! The input matrix `B` does not enter the error dynamics (5), so the design and analysis only need
//! `(A, C)`; simulations of the plant/observer pair take `B` separately.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite;

use crate::error::Error;

/// The pair `(A, C)` of plant (1): `ż = Az + Bu`, `y = Cz`, with `A ∈ R^{n×n}`, `C ∈ R^{q×n}`
/// (`C` is the paper's `M`).
#[derive(Debug, Clone, PartialEq)]
pub struct Plant {
    a: Mat<f64>,
    c: Mat<f64>,
}

impl Plant {
    /// Validates `A` (square, non-empty, finite) and the output matrix `c` (the paper's `M`:
    /// `q × n` with `q ≥ 1`, finite). Errors name the matrix as the paper does (`M`).
    pub fn new(a: MatRef<'_, f64>, c: MatRef<'_, f64>) -> Result<Self, Error> {
        let m = c;
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
            c: m.to_owned(),
        })
    }

    /// The state matrix `A`.
    pub fn a(&self) -> MatRef<'_, f64> {
        self.a.as_ref()
    }

    /// The output matrix `C` (the paper's `M`).
    pub fn c(&self) -> MatRef<'_, f64> {
        self.c.as_ref()
    }

    /// State dimension `n`.
    pub fn n(&self) -> usize {
        self.a.nrows()
    }

    /// Output dimension `q`.
    pub fn q(&self) -> usize {
        self.c.nrows()
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

    /// Checks that `m` (named `what` in the error) is a finite `n × n` matrix.
    fn check_state_matrix(&self, m: MatRef<'_, f64>, what: &str) -> Result<(), Error> {
        if m.nrows() != m.ncols() {
            return Err(Error::Input(InputError::NotSquare {
                what: what.into(),
                rows: m.nrows(),
                cols: m.ncols(),
            }));
        }
        if m.nrows() != self.n() {
            return Err(
                InputError::mismatch(format!("order of {what} vs n"), self.n(), m.nrows()).into(),
            );
        }
        Ok(check_finite(m, what)?)
    }

    /// Checks that `P` is a finite symmetric `n × n` matrix (relative asymmetry at most `1e-10`).
    pub fn check_lyapunov_matrix(&self, p: MatRef<'_, f64>) -> Result<(), Error> {
        self.check_state_matrix(p, "P")?;
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

    /// Checks that `R` is a finite upper-triangular `n × n` matrix (the factor of `P = RᵀR`).
    pub fn check_lyapunov_factor(&self, r: MatRef<'_, f64>) -> Result<(), Error> {
        self.check_state_matrix(r, "R")?;
        for j in 0..r.ncols() {
            for i in j + 1..r.nrows() {
                if r[(i, j)] != 0.0 {
                    return Err(InputError::parameter(
                        "R",
                        r[(i, j)],
                        "the factor R of P = R'R must be upper triangular (the value is an \
                         entry below its diagonal)",
                    )
                    .into());
                }
            }
        }
        Ok(())
    }

    /// The jump matrix `I − LC` of the error dynamics (5) (`I − LM` in the paper).
    pub fn reset_matrix(&self, l: MatRef<'_, f64>) -> Result<Mat<f64>, Error> {
        self.check_gain(l)?;
        let lm = l * self.c();
        Ok(Mat::from_fn(self.n(), self.n(), |i, j| {
            f64::from(u8::from(i == j)) - lm[(i, j)]
        }))
    }
}
