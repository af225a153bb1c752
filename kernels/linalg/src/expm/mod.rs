//! The matrix exponential by scaling and squaring with Padé approximants:
//! Al-Mohy & Higham (2009), *A new scaling and squaring algorithm for the matrix exponential*,
//! SIAM J. Matrix Anal. Appl. 31(3):970–989, **Algorithm 6.1**.
//!
//! * Degrees m ∈ {3, 5, 7, 9, 13} with θ13 = 4.25; the degree and the number of squarings s are
//!   chosen from d_k = ‖A^k‖₁^{1/k} (k = 4, 6, 8, 10) rather than ‖A‖₁, which avoids the
//!   overscaling of Higham (2005) for non-normal matrices (paper §§3–4).
//! * The backward-error correction ℓ(A, m) of eq. (5.1) is computed from ‖ |A|^{2m+1} ‖₁, which
//!   is exact for the nonnegative |A| and costs 2m+1 matrix–vector products.
//! * Norms ‖A^k‖₁ are exact (the powers are formed) for n < [`EXACT_NORM_MAX_ORDER`], and
//!   estimated by the Higham–Tisseur block estimator (t = 2) above.
//! * Triangular and quasi-triangular input: Code Fragment 2.1 (diagonal and first superdiagonal
//!   recomputed exactly during the squaring phase); diagonal input: e^{a_ii}.
//! * Orders 2…16 run on stack-allocated const-generic kernels (`storage::SmallMat`, orders 9…16
//!   padded to 16), larger
//!   orders on faer's GEMM and LU; the algorithm code is shared.
//!
//! The result is never silently non-finite: a singular Padé denominator q_m(2^{−s}A) gives
//! [`LinalgError::Singular`], an exponential beyond the double range [`LinalgError::Overflow`].

mod lu;
pub(crate) mod pade;
pub(crate) mod storage;

use faer::{Mat, MatMut, MatRef};

use crate::normest::Normest;
use crate::{LinalgError, check};
use pade::{Choice, Failure, PadeWorkspace};
use storage::{SmallMat, SquareStorage};

/// Orders below this use exact 1-norms of A⁴, A⁶, A⁸, A¹⁰ (the products are formed); orders
/// at or above it use the Higham–Tisseur estimator. SciPy's Python `_expm` switches at 200.
pub const EXACT_NORM_MAX_ORDER: usize = 200;

/// Degree and number of squarings chosen by Algorithm 6.1 for a given matrix (diagnostics and
/// cost models: the evaluation costs π_m + s matrix products and one LU solve, with
/// π_m = 2, 3, 4, 5, 6 for m = 3, 5, 7, 9, 13).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PadeParameters {
    /// Padé degree m ∈ {3, 5, 7, 9, 13}, or 0 if a structural shortcut (diagonal input) was taken.
    pub degree: usize,
    /// Number of squarings s.
    pub squarings: u32,
}

/// Fills a workspace input with t·A and runs Algorithm 6.1 on it.
pub(crate) trait Driver: Sized {
    /// Storage of the matrices.
    type M: SquareStorage;
    /// Buffers for order `n`.
    fn new(n: usize) -> Self;
    /// Runs `f` on a driver of order `n` (fresh by default; see [`DenseDriver`] for the cache).
    fn with_driver<R>(n: usize, f: impl FnOnce(&mut Self) -> R) -> R {
        f(&mut Self::new(n))
    }
    /// Computes e^{tA}; afterwards [`Driver::result`] holds it.
    fn exp_of(&mut self, a: MatRef<'_, f64>, t: f64) -> Result<Choice, LinalgError>;
    /// The last result.
    fn result(&self) -> &Self::M;
}

/// Loads t·A into the workspace input, padded with zeros when the workspace order exceeds n
/// (inside the dispatched kernel, see [`SquareStorage::load`]): e^{diag(A, 0)} = diag(e^A, I),
/// and every quantity Algorithm 6.1 computes (‖A^k‖₁, ‖ |A|^p ‖₁, the pivot order of the LU,
/// every rounded operation on the A block) is the same for the padded matrix, so padding
/// changes neither the chosen (m, s) nor a single bit of e^A. A non-finite t·A is reported as
/// [`Failure::NonFiniteInput`] and classified by [`input_failure`]. Inlined into the
/// dispatched entry points, so that it is compiled with their instruction set.
#[inline(always)]
fn load_and_run<M: SquareStorage>(
    ws: &mut PadeWorkspace<M>,
    a: MatRef<'_, f64>,
    t: f64,
    estimator: pade::Estimator<'_, M>,
) -> Result<Choice, Failure> {
    if !ws.input_mut().load(a, t) {
        return Err(Failure::NonFiniteInput);
    }
    ws.run(estimator)
}

/// The error for a non-finite t·A: NaN/±∞ in A itself, or an overflow of the product.
fn input_failure(a: MatRef<'_, f64>) -> LinalgError {
    match check::finite(a, "expm input A") {
        Err(e) => e.into(),
        Ok(()) => LinalgError::overflow("t·A in expm (entries beyond the double range)"),
    }
}

fn failure(f: Failure, a: MatRef<'_, f64>) -> LinalgError {
    match f {
        Failure::NonFiniteInput => input_failure(a),
        Failure::Singular => LinalgError::singular("Padé denominator q_m(2^-s·A) = V − U in expm"),
        Failure::Overflow => {
            LinalgError::overflow("expm result exceeds the double-precision range")
        }
    }
}

/// Stack-allocated driver: order N exactly for N = 2…8, and N = 16 for orders 9…16 (the input
/// is padded to diag(A, 0); see [`load`]).
pub(crate) struct SmallDriver<const N: usize>(PadeWorkspace<SmallMat<N>>);

impl<const N: usize> Driver for SmallDriver<N> {
    type M = SmallMat<N>;
    fn new(_n: usize) -> Self {
        Self(PadeWorkspace::new(N))
    }
    fn exp_of(&mut self, a: MatRef<'_, f64>, t: f64) -> Result<Choice, LinalgError> {
        pulp::Arch::new()
            .dispatch(RunSmall(&mut self.0, a, t))
            .map_err(|f| failure(f, a))
    }
    fn result(&self) -> &SmallMat<N> {
        self.0.result()
    }
}

/// Largest order whose dense workspaces are cached per thread.
const CACHE_MAX_ORDER: usize = 128;
/// Number of distinct orders cached per thread.
const CACHE_ENTRIES: usize = 4;

thread_local! {
    static DENSE_CACHE: std::cell::RefCell<Vec<DenseDriver>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Algorithm 6.1 on stack matrices, fully inlined into pulp's runtime-dispatched entry point so
/// that it is compiled for the widest instruction set available (AVX2/FMA on x86-64-v3).
struct RunSmall<'a, 'm, const N: usize>(&'a mut PadeWorkspace<SmallMat<N>>, MatRef<'m, f64>, f64);

impl<const N: usize> pulp::WithSimd for RunSmall<'_, '_, N> {
    type Output = Result<Choice, Failure>;
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        load_and_run(self.0, self.1, self.2, None)
    }
}

/// Algorithm 6.1 on faer matrices; the element-wise work (combinations, norms, the ℓ power
/// iteration) is inlined into pulp's dispatched entry point, GEMM and LU are faer's own kernels.
struct RunDense<'a, 'e, 'm>(
    &'a mut PadeWorkspace<Mat<f64>>,
    pade::Estimator<'e, Mat<f64>>,
    MatRef<'m, f64>,
    f64,
);

impl pulp::WithSimd for RunDense<'_, '_, '_> {
    type Output = Result<Choice, Failure>;
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        load_and_run(self.0, self.2, self.3, self.1)
    }
}

/// faer-backed driver for n = 1 and n > 8, with the norm estimator for large n.
pub(crate) struct DenseDriver {
    ws: PadeWorkspace<Mat<f64>>,
    normest: Option<Normest>,
}

impl Driver for DenseDriver {
    type M = Mat<f64>;
    fn new(n: usize) -> Self {
        let normest = (n >= EXACT_NORM_MAX_ORDER).then(|| Normest::new(n));
        Self {
            ws: PadeWorkspace::new(n),
            normest,
        }
    }
    /// Reuses this thread's cached workspaces for orders ≤ [`CACHE_MAX_ORDER`] (allocating nine
    /// fresh n×n matrices per call costs more than the arithmetic for moderate n).
    fn with_driver<R>(n: usize, f: impl FnOnce(&mut Self) -> R) -> R {
        if n > CACHE_MAX_ORDER {
            return f(&mut Self::new(n));
        }
        let cached = DENSE_CACHE.with(|c| {
            let mut cache = c.borrow_mut();
            let pos = cache.iter().position(|d| d.ws.input_mut_order() == n);
            pos.map(|p| cache.swap_remove(p))
        });
        let mut driver = cached.unwrap_or_else(|| Self::new(n));
        let r = f(&mut driver);
        DENSE_CACHE.with(|c| {
            let mut cache = c.borrow_mut();
            if cache.len() >= CACHE_ENTRIES {
                cache.remove(0);
            }
            cache.push(driver);
        });
        r
    }
    fn exp_of(&mut self, a: MatRef<'_, f64>, t: f64) -> Result<Choice, LinalgError> {
        let arch = pulp::Arch::new();
        let res = match self.normest.as_mut() {
            Some(est) => {
                let mut f = |factors: &[&Mat<f64>]| est.estimate_product(factors);
                arch.dispatch(RunDense(&mut self.ws, Some(&mut f), a, t))
            }
            None => arch.dispatch(RunDense(&mut self.ws, None, a, t)),
        };
        res.map_err(|f| failure(f, a))
    }
    fn result(&self) -> &Mat<f64> {
        self.ws.result()
    }
}

/// Calls `$f::<Driver>($args)` with the driver type for order `$n`.
macro_rules! with_driver {
    ($n:expr, $f:ident($($args:expr),*)) => {
        match $n {
            2 => $f::<$crate::expm::SmallDriver<2>>($($args),*),
            3 => $f::<$crate::expm::SmallDriver<3>>($($args),*),
            4 => $f::<$crate::expm::SmallDriver<4>>($($args),*),
            5 => $f::<$crate::expm::SmallDriver<5>>($($args),*),
            6 => $f::<$crate::expm::SmallDriver<6>>($($args),*),
            7 => $f::<$crate::expm::SmallDriver<7>>($($args),*),
            8 => $f::<$crate::expm::SmallDriver<8>>($($args),*),
            9..=16 => $f::<$crate::expm::SmallDriver<16>>($($args),*),
            _ => $f::<$crate::expm::DenseDriver>($($args),*),
        }
    };
}
pub(crate) use with_driver;

/// Copies a workspace matrix into a faer matrix view; returns whether all entries are finite.
pub(crate) fn store<M: SquareStorage>(src: &M, out: MatMut<'_, f64>) -> bool {
    src.store(out)
}

fn expm_with<D: Driver>(a: MatRef<'_, f64>, t: f64) -> Result<(Mat<f64>, Choice), LinalgError> {
    let n = a.nrows();
    D::with_driver(n, |d| {
        let c = d.exp_of(a, t)?;
        let r = d.result();
        Ok((r.to_mat(n), c))
    })
}

fn expm_checked(a: MatRef<'_, f64>, t: f64) -> Result<(Mat<f64>, Choice), LinalgError> {
    // The finiteness of A is checked while loading t·A (see `load_and_run`).
    let n = check::square(a)?;
    check::finite_scalar(t, "expm time t")?;
    with_driver!(n, expm_with(a, t))
}

/// The matrix exponential e^A by scaling and squaring with Padé approximants: Al-Mohy & Higham
/// (2009), *A new scaling and squaring algorithm for the matrix exponential*, SIAM J. Matrix
/// Anal. Appl. 31(3):970–989, **Algorithm 6.1**.
///
/// * Padé degrees m ∈ {3, 5, 7, 9, 13} with θ13 = 4.25; m and the number of squarings s are
///   chosen from d_k = ‖A^k‖₁^{1/k} (k = 4, 6, 8, 10) rather than ‖A‖₁, which avoids the
///   overscaling of Higham (2005) for non-normal matrices.
/// * The correction ℓ(A, m) uses ‖ |A|^{2m+1} ‖₁, computed exactly for the nonnegative |A| by
///   2m+1 matrix–vector products.
/// * ‖A^k‖₁ is exact (powers formed) for n < [`EXACT_NORM_MAX_ORDER`] and estimated by the
///   Higham–Tisseur (2000) block 1-norm estimator (t = 2) above.
/// * Upper (quasi-)triangular input: Code Fragment 2.1 of the paper (diagonal and first
///   superdiagonal recomputed from exact formulas at every squaring; 2×2 diagonal blocks with
///   complex eigenvalues recomputed in closed form); lower-triangular input via the transpose;
///   diagonal input: e^{a_ii}.
/// * Orders 2…16 run on stack-allocated kernels compiled for the best instruction set found at
///   run time (AVX2/FMA via `pulp`), larger orders on faer's GEMM and LU; both use
///   the same algorithm code. (V − U)X = V + U is solved by LU with partial pivoting.
///
/// # Errors
/// [`LinalgError::Input`] (`NotSquare`), [`LinalgError::Input`] (`Empty`), [`LinalgError::Input`] (`NonFinite`) for bad input;
/// [`LinalgError::Overflow`] if e^A is not representable in double precision;
/// [`LinalgError::Singular`] if the Padé denominator is numerically singular.
///
/// ```
/// use faer::mat;
/// let e = sporadic_linalg::expm(mat![[0.0, 1.0], [0.0, 0.0]].as_ref()).unwrap();
/// assert_eq!(e, mat![[1.0, 1.0], [0.0, 1.0]]);
/// ```
pub fn expm(a: MatRef<'_, f64>) -> Result<Mat<f64>, LinalgError> {
    expm_checked(a, 1.0).map(|r| r.0)
}

/// e^{At} for a scalar t (the product t·A is formed entrywise first; see [`expm`]).
///
/// # Errors
/// As [`expm`]; additionally [`LinalgError::Input`] (`NonFinite`) if `t` is NaN or infinite and
/// [`LinalgError::Overflow`] if t·A overflows.
pub fn expm_scaled(a: MatRef<'_, f64>, t: f64) -> Result<Mat<f64>, LinalgError> {
    expm_checked(a, t).map(|r| r.0)
}

/// Padé degree m and number of squarings s that [`expm`] uses for `a` (Algorithm 6.1).
///
/// # Errors
/// As [`expm`] (the exponential is computed).
pub fn expm_parameters(a: MatRef<'_, f64>) -> Result<PadeParameters, LinalgError> {
    let (_, c) = expm_checked(a, 1.0)?;
    Ok(PadeParameters {
        degree: c.degree,
        squarings: c.squarings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Padding to diag(A, 0) reproduces the unpadded computation bit for bit.
    #[test]
    fn padding_is_exact() {
        let rows = [
            [0.3, -1.2, 0.5, 2.0],
            [1.1, 0.4, -0.7, 0.2],
            [-0.6, 0.9, 1.5, -1.0],
            [0.8, 0.1, -0.3, -2.2],
        ];
        for (t, triangular) in [
            (0.01, false),
            (0.3, false),
            (1.0, false),
            (7.0, false),
            (2.0, true),
        ] {
            let a = Mat::from_fn(
                4,
                4,
                |i, j| if triangular && i > j { 0.0 } else { rows[i][j] },
            );
            let mut d4 = SmallDriver::<4>::new(4);
            let mut d16 = SmallDriver::<16>::new(16);
            let c4 = d4.exp_of(a.as_ref(), t).unwrap();
            let c16 = d16.exp_of(a.as_ref(), t).unwrap();
            assert_eq!(c4, c16);
            for j in 0..16 {
                for i in 0..16 {
                    let got = d16.result().get(i, j);
                    if i < 4 && j < 4 {
                        assert_eq!(
                            got.to_bits(),
                            d4.result().get(i, j).to_bits(),
                            "({i},{j}) t={t}"
                        );
                    } else if i < 4 || j < 4 {
                        assert_eq!(got, 0.0);
                    } else {
                        // The padding block is r_m(0)^(2^s) = I up to the rounding of b₀·(1/b₀).
                        let want = if i == j { 1.0 } else { 0.0 };
                        assert!((got - want).abs() <= 4.0 * f64::EPSILON, "({i},{j}) t={t}");
                    }
                }
            }
        }
    }
}
