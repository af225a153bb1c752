//! Typed errors of `sporadic-andrieu2014`. Bad input is reported with what was wrong and where; nothing
//! in this crate panics on user data.

use sporadic_linalg::{InputError, LinalgError};
use sporadic_sim::SimError;

/// Everything that can go wrong while designing, running or reproducing the observer.
///
/// The variants are this crate's own checks (inputs of the design and of a run, the conditions of
/// Theorem 2); failures inside `sporadic-linalg` and `sporadic-sim` are wrapped as they are
/// ([`Error::Linalg`], [`Error::Sim`]), not restated.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input: what was wrong and where (a matrix not square or empty, mismatched
    /// dimensions, NaN/Inf, a parameter out of range, an invalid sampling window).
    #[error(transparent)]
    Input(#[from] InputError),
    /// The gain `K` does not make `A + KC` Hurwitz, so (9) has no solution `P ≻ 0` (Andrieu et al. 2014,
    /// proof of Theorem 2). Detected by the Lyapunov solution `P̃` of
    /// `(A+KC)'P̃ + P̃(A+KC) = −W` not being positive definite (or not existing).
    #[error(
        "gain K = {k:?} does not make A + KC Hurwitz (Lyapunov solution not positive definite)"
    )]
    NotHurwitz {
        /// The offending gain.
        k: Vec<f64>,
    },
    /// Condition (9b) `p3 P ≼ PD + DP` fails with `p3 > 0`: the smallest generalised eigenvalue of the
    /// pencil `(PD + DP, P)` is not positive. Happens e.g. for `n ≥ 4`, binomial `K` and `W = I`;
    /// a geometric weight `W = diag(1, r, …, r^{n−1})` with small `r` repairs it.
    #[error("condition (9b) fails: p3 = λmin(PD+DP, P) = {p3} is not positive")]
    NotDiagonallyDominated {
        /// The computed `p3`.
        p3: f64,
    },
    /// The sampling parameter `α` lies outside the admissible range `(0, α_m)` of Lemma 4 / (17).
    #[error(
        "alpha = {alpha} is not admissible: Lemma 4 (17) certifies only 0 < alpha < alpha_m = {alpha_m}"
    )]
    AlphaNotAdmissible {
        /// The value requested.
        alpha: f64,
        /// The bound `α_m` of the design.
        alpha_m: f64,
    },
    /// The scan for `α_m` found no `α > 0` at which the checkable form of (17) holds.
    #[error("no admissible alpha: the checkable form of (17) already fails at alpha = {alpha}")]
    NoAdmissibleAlpha {
        /// Smallest `α` tested.
        alpha: f64,
    },
    /// `a2` is below the minimum `2n(N1+N2)/(p3 p1)` required by Step 3 of the proof of Theorem 2.
    #[error("a2 = {a2} is below the minimum 2n(N1+N2)/(p3 p1) = {a2_min} of Theorem 2")]
    GainRateTooSmall {
        /// The value requested.
        a2: f64,
        /// The minimum for the chosen `α`.
        a2_min: f64,
    },
    /// The user's Lipschitz estimate `c(x̂, u)` returned a negative value (Assumption 1 needs `c ≥ 0`,
    /// and the gain dynamics (6a) rely on `L̇ ≥ 0`).
    #[error("Lipschitz estimate c(x̂, u) = {c} < 0 at t = {t}")]
    NegativeLipschitz {
        /// The value returned.
        c: f64,
        /// Time of the evaluation.
        t: f64,
    },
    /// The pair `(A, c)` of a plant file read through one output row `c` is not observable, so the
    /// normal form (1) does not exist for it ([`crate::normal_form`]): the observability matrix is
    /// singular to working precision (equilibrated condition number at or above `1/(n ε)`).
    #[error(
        "output {output} does not observe the state: its observability matrix is singular to working \
         precision (equilibrated condition number {condition:.3e})"
    )]
    NotObservable {
        /// The output row (1-based).
        output: usize,
        /// Equilibrated condition number of the observability matrix (`+∞` when exactly singular).
        condition: f64,
    },
    /// The transformation to the normal form (1) through one output row is too ill-conditioned to
    /// be computed reliably ([`crate::normal_form::CONDITION_LIMIT`]): the plant is nearly
    /// unobservable from that output, or its state coordinates are badly scaled in a way that
    /// equilibration (a diagonal scaling) does not undo; the condition number is that of the
    /// coordinates given, not a property of the plant (a triple integrator with a Padé delay,
    /// order 5, gave 821 as written and 1.4e8 in coordinates `x = Tz` with `κ(T) < 5`).
    #[error(
        "output {output}: the transformation to observability normal form has condition number \
         {condition:.3e} (after equilibration) above the limit {limit:.3e} = 1/sqrt(eps) in the \
         coordinates given: the plant is nearly unobservable from this output, or its \
         coordinates are badly scaled"
    )]
    IllConditioned {
        /// The output row (1-based).
        output: usize,
        /// Equilibrated condition number of the observability matrix.
        condition: f64,
        /// The limit it exceeds.
        limit: f64,
    },
    /// The nonlinearity `Gφ(Hx)` is not lower-triangular in the normal-form coordinates `z = Ox`,
    /// as (1) requires: component `row` of `OGφ(HO⁻¹z)` depends on `z_column`, `column > row`.
    #[error(
        "the nonlinearity is not triangular in observability normal form: component {row} of \
         O G phi(H O^-1 z) depends on z_{column} (through phi_{nonlinearity} and its argument \
         {argument}); (1) needs f_j to depend on z_1..z_j only"
    )]
    NotTriangular {
        /// Row `j` of `f` (1-based).
        row: usize,
        /// Coordinate `z_i` it depends on, `i > j` (1-based).
        column: usize,
        /// The component of `φ` (1-based).
        nonlinearity: usize,
        /// The component of `Hx` (1-based).
        argument: usize,
    },
    /// A numerical step of this crate could not produce its result: the Lemma 1 root could not be
    /// bracketed, or the Cholesky factor of `P` / the eigenvalues of `A + KC` could not be computed.
    #[error("no convergence: {what}")]
    NoConvergence {
        /// Which computation failed.
        what: String,
    },
    /// An error from the dense linear-algebra kernels.
    #[error("linear algebra: {0}")]
    Linalg(#[from] LinalgError),
    /// An error from the hybrid simulator (integrator failure, bad options, figure output, …).
    #[error("simulation: {0}")]
    Sim(#[from] SimError),
    /// An I/O error while writing the reproduction's outputs.
    #[error("I/O error on {path}: {source}")]
    Io {
        /// The file or directory concerned.
        path: String,
        /// The underlying error.
        source: std::io::Error,
    },
}
