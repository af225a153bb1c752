//! The internal positive representation (IPR, Cacace, Germani & Manes 2015) used by Rabehi et al.
//! (2021), §III: elementwise positive/negative parts, the Metzler decomposition `A = A^M − A^N`,
//! the doubled flow matrix `Ā` of (6) and the jump matrices `Γ(L)` of (9) and `Γ(G1, G2)` of (33).
//!
//! Notation (elementwise): `A⁺ = max(A, 0)`, `A⁻ = A⁺ − A` (so `A = A⁺ − A⁻`, both `≥ 0`),
//! `|A| = A⁺ + A⁻`; `d_A` is the diagonal part of `A`,
//!
//! ```text
//! A^M = d_A + (A − d_A)⁺   (Metzler),   A^N = A^M − A ≥ 0,   Ā = [[A^M, A^N], [A^N, A^M]].
//! ```
//!
//! **Block structure** (not in the paper). Every matrix `[[X, Y], [Y, X]]` is
//! block-diagonalised by the orthogonal involution `T = (1/√2)[[I, I], [I, −I]]`:
//! `T [[X, Y], [Y, X]] T = diag(X + Y, X − Y)` ([`pair_blocks`]). Hence `TĀT = diag(S, A)` with
//! `S = A^M + A^N` and `TΓ(L)T = diag(|G|, G)`, `G = I + LC`: the interval *width* `x̄ − x̲` and the
//! *centre* error evolve separately.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_square_finite;

use crate::error::Error;
use crate::system::Plant;

/// `A⁺ = max(A, 0)` elementwise.
pub fn positive_part(a: MatRef<'_, f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)].max(0.0))
}

/// `A⁻ = A⁺ − A = max(−A, 0)` elementwise.
pub fn negative_part(a: MatRef<'_, f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| (-a[(i, j)]).max(0.0))
}

/// `|A| = A⁺ + A⁻` elementwise.
pub fn abs(a: MatRef<'_, f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)].abs())
}

/// Whether every off-diagonal entry is `≥ 0` (Definition 1: `ẋ = Ax` is cooperative).
pub fn is_metzler(a: MatRef<'_, f64>) -> bool {
    (0..a.ncols()).all(|j| (0..a.nrows()).all(|i| i == j || a[(i, j)] >= 0.0))
}

/// Whether every entry is `≥ 0` (`x⁺ = Ax` is cooperative).
pub fn is_nonnegative(a: MatRef<'_, f64>) -> bool {
    (0..a.ncols()).all(|j| (0..a.nrows()).all(|i| a[(i, j)] >= 0.0))
}

/// `[[X, Y], [Y, X]]` for two `n × n` blocks (the shape of `Ā`, `Γ(L)` and `Γ(G1, G2)`).
pub fn pair_matrix(x: MatRef<'_, f64>, y: MatRef<'_, f64>) -> Mat<f64> {
    let n = x.nrows();
    Mat::from_fn(2 * n, 2 * n, |i, j| {
        let same = (i < n) == (j < n);
        let (r, c) = (i % n, j % n);
        if same { x[(r, c)] } else { y[(r, c)] }
    })
}

/// For `M = [[X, Y], [Y, X]]` (checked up to rounding), the blocks `(X + Y, X − Y)` of
/// `TMT = diag(X + Y, X − Y)`, `T = (1/√2)[[I, I], [I, −I]]` (see the module docs).
///
/// # Errors
/// [`Error::Input`] (`NotSquare`)/[`Error::Input`] (`Empty`)/[`Error::Input`] (`NonFinite`) for bad input;
/// [`Error::Input`] (`InvalidParameter`) for an odd order or when `M` does not have the pair structure (`max|M11 − M22| + max|M12 − M21|` above `1e-12·max|M|`).
pub fn pair_blocks(m: MatRef<'_, f64>) -> Result<(Mat<f64>, Mat<f64>), Error> {
    let two_n = check_square_finite(m, "pair matrix [[X, Y], [Y, X]]")?;
    if two_n % 2 != 0 {
        return Err(InputError::parameter(
            "order of a pair matrix",
            two_n as f64,
            "must be even (2n)",
        )
        .into());
    }
    let n = two_n / 2;
    let scale = m.norm_max();
    let mut defect: f64 = 0.0;
    for j in 0..n {
        for i in 0..n {
            defect = defect.max((m[(i, j)] - m[(n + i, n + j)]).abs());
            defect = defect.max((m[(i, n + j)] - m[(n + i, j)]).abs());
        }
    }
    if defect > 1e-12 * scale {
        return Err(Error::Input(InputError::InvalidParameter {
            name: "pair-structure defect of M".into(),
            value: defect,
            reason: "M must be of the form [[X, Y], [Y, X]]".into(),
        }));
    }
    let x = m.submatrix(0, 0, n, n);
    let y = m.submatrix(0, n, n, n);
    Ok((x + y, x - y))
}

/// The Metzler decomposition of `A` and the doubled flow matrix of the interval error (6).
#[derive(Debug, Clone, PartialEq)]
pub struct MetzlerDecomposition {
    /// `A^M = d_A + (A − d_A)⁺` (Metzler).
    pub a_m: Mat<f64>,
    /// `A^N = A^M − A` (nonnegative, zero diagonal).
    pub a_n: Mat<f64>,
    /// `Ā = [[A^M, A^N], [A^N, A^M]]` (Metzler by construction).
    pub a_bar: Mat<f64>,
}

impl MetzlerDecomposition {
    /// Builds `A^M`, `A^N`, `Ā` from a square finite `A`.
    ///
    /// # Errors
    /// [`Error::Input`] (`NotSquare`), [`Error::Input`] (`Empty`), [`Error::Input`] (`NonFinite`).
    pub fn new(a: MatRef<'_, f64>) -> Result<Self, Error> {
        let n = check_square_finite(a, "A")?;
        let a_m = Mat::from_fn(n, n, |i, j| {
            if i == j {
                a[(i, j)]
            } else {
                a[(i, j)].max(0.0)
            }
        });
        // A^N = A^M − A: off-diagonal magnitudes of the negative entries, exact in floating point.
        let a_n = Mat::from_fn(
            n,
            n,
            |i, j| {
                if i == j { 0.0 } else { (-a[(i, j)]).max(0.0) }
            },
        );
        let a_bar = pair_matrix(a_m.as_ref(), a_n.as_ref());
        Ok(Self { a_m, a_n, a_bar })
    }

    /// The width flow matrix `S = A^M + A^N` (`TĀT = diag(S, A)`): `ẇ = Sw + (d̄ − d̲)` for the
    /// interval width `w = x̄ − x̲`.
    pub fn width_matrix(&self) -> Mat<f64> {
        &self.a_m + &self.a_n
    }

    /// The equilibrium `ξ_ueq = −Ā⁻¹Ξ̄` of the comparison system (11) (Assumption 4).
    ///
    /// # Errors
    /// [`Error::Input`] (`DimensionMismatch`) for `Ξ̄` not of length `2n`, [`Error::SingularABar`] when `Ā`
    /// is numerically singular (A4 fails).
    pub fn xi_ueq(&self, xi_bar: &[f64]) -> Result<Vec<f64>, Error> {
        use faer::linalg::solvers::Solve;
        let two_n = self.a_bar.nrows();
        if xi_bar.len() != two_n {
            return Err(
                InputError::mismatch("length of Xi-bar (= 2n)", two_n, xi_bar.len()).into(),
            );
        }
        let rcond = assumption_a4(self.a_bar.as_ref())?;
        let rhs = Mat::from_fn(two_n, 1, |i, _| -xi_bar[i]);
        let sol = self.a_bar.full_piv_lu().solve(&rhs);
        let out: Vec<f64> = (0..two_n).map(|i| sol[(i, 0)]).collect();
        if out.iter().any(|v| !v.is_finite()) {
            return Err(Error::SingularABar { rcond });
        }
        Ok(out)
    }
}

/// Assumption 4: `Ā` non-singular. Returns `σ_min(Ā)/σ_max(Ā)`.
///
/// # Errors
/// [`Error::SingularABar`] when the ratio is below `1e-12`.
pub fn assumption_a4(a_bar: MatRef<'_, f64>) -> Result<f64, Error> {
    let sv = a_bar
        .singular_values()
        .map_err(|_| InputError::non_finite("singular values of A-bar (no convergence)"))?;
    let max = sv.iter().copied().fold(0.0, f64::max);
    let min = sv.iter().copied().fold(f64::INFINITY, f64::min);
    let rcond = if max > 0.0 { min / max } else { 0.0 };
    if rcond < 1e-12 {
        return Err(Error::SingularABar { rcond });
    }
    Ok(rcond)
}

/// `G = I + LC`, the reset matrix of the fictitious correction (7) (sign convention
/// `x⁺ = x + L(Cx + v − y)`).
///
/// # Errors
/// `L` not `n × p` or not finite.
pub fn reset_matrix(plant: &Plant, l: MatRef<'_, f64>) -> Result<Mat<f64>, Error> {
    plant.check_gain(l)?;
    let n = plant.n();
    Ok(Mat::<f64>::identity(n, n) + l * plant.c())
}

/// `Γ(G1, G2) = [[G1, G2], [G2, G1]]` of (33).
pub fn jump_matrix(g1: MatRef<'_, f64>, g2: MatRef<'_, f64>) -> Mat<f64> {
    pair_matrix(g1, g2)
}

/// `Γ(L) = [[G⁺, G⁻], [G⁻, G⁺]]`, `G = I + LC`: the error reset of (9), nonnegative for every `L`.
///
/// # Errors
/// `L` not `n × p` or not finite.
pub fn gamma_of_gain(plant: &Plant, l: MatRef<'_, f64>) -> Result<Mat<f64>, Error> {
    let g = reset_matrix(plant, l)?;
    Ok(jump_matrix(
        positive_part(g.as_ref()).as_ref(),
        negative_part(g.as_ref()).as_ref(),
    ))
}
