//! Normalisation of the design problem (issue 22: verdicts that do not depend on units or
//! coordinates).
//!
//! LMI (41) of Ferrante et al. (2016) is invariant in exact arithmetic under a change of time
//! unit (the set `{e^{Av} : v ∈ [T1, T2]}` does not change), of state coordinates `x' = Tx`
//! (congruence of every block of (41) by `T⁻ᵀ`) and of output units `y' = Sy`; its numerical
//! solution is not: the margin problem normalises `‖P‖₂, ‖F‖₂, ‖J‖₂ ≤ 1` and measures the margin
//! against `I`, so the same feasible problem written in other coordinates has a margin smaller by
//! up to `κ(T)²`, which near the end of the largest window falls below the solver's verification
//! threshold first (the harmonic oscillator with `ω = 10` lost 9 % of its window against
//! `ω = 1`: the two differ by the time unit and the similarity `diag(1, 1/ω)`). Before LMI (41)
//! is solved the problem is therefore brought to a normal form that is the same for every such
//! equivalent problem:
//!
//! * **time** ([`Coordinates::Gramian`] and [`Coordinates::Diagonal`]): the unit is
//!   `k = min(T2, T1 + H)` ([`time_unit`]), `A₁ = kA`, window `[T1/k, T2/k]`, where
//!   `H = 72/|α|` is the decay horizon of a Hurwitz `A` (spectral abscissa `α`;
//!   `grid::decay_horizon`, `H = ∞` otherwise). Both `T2` and `T1 + H` are
//!   similarity-invariant and scale as `1/c` under `(A, window) → (cA, window/c)`, so the normal
//!   form is the same for every equivalent problem. Every window up to the decay of all modes
//!   has `k = T2` (window `[T1/T2, 1]`); on a longer one (issue 22: `[1, 10¹⁵]` for `λ = −1, −2`)
//!   `k = T2` would make `A₁ = T2·A` with entries `~10¹⁵` (overflowing at `T2 ~ 10³⁰⁸`) and a
//!   Gramian on `[0, 1]` that sees the dynamics only on its first `10⁻¹⁵`, while beyond
//!   `T1 + H` nothing of `e^{Av}` is left to normalise;
//! * **states** ([`Coordinates::Gramian`]): `x' = Gx` with `G = Λ^½Vᵀ` from the eigenvalue
//!   decomposition `VΛVᵀ` of the observability Gramian of the normalised problem on one time
//!   unit, `W = ∫₀¹ e^{A₁ᵀs} C₁ᵀC₁ e^{A₁s} ds` (so that `W = I` in the new coordinates; computed
//!   again in the coordinates it gives, at most [`GRAMIAN_PASSES`] times, because in badly scaled
//!   coordinates its rounding errors are relative to its largest eigenvalue). Under `x → Tx` the
//!   Gramian becomes `T⁻ᵀWT⁻¹`, so the new coordinates are the same up to an orthogonal matrix
//!   `Q` — and LMI (41), its spectral-norm normalisation and its margin are invariant under
//!   orthogonal changes of coordinates. The residue embedding makes its choices on the balanced
//!   matrix (`sporadic_embed::residue`), which is only invariant under diagonal changes of
//!   coordinates: its cluster merging on `‖E_c‖_F` there decides the same in the forms of
//!   equivalent problems unless a projector norm is near the merge limit `10⁴` (on
//!   `eight-state-modal` they are below 30 in the Gramian form, below 2 in the diagonal one),
//!   and its power series on a short window (whether it is taken, its pieces and its powers)
//!   depends on the eigenvalues, the window and the clusters' indices only. Under `y → cy` the
//!   Gramian is multiplied by `c²` and `G` by `c`: `C₁G⁻¹` does not change;
//! * **outputs** (several outputs, Gramian form): `S = diag(s_k)` such that every output carries
//!   the same share `tr(s_k²W_k W⁻¹) = n/q` of the Gramian `W = Σ s_k²W_k` (the minimiser of a
//!   convex function, reached by Newton's method with a budget, `sporadic_linalg::gramian_form`;
//!   the shares are similarity-invariant, and the minimiser does not depend on the output
//!   units);
//! * [`Coordinates::Diagonal`]: exact power-of-two state scalings from the observability
//!   matrix `[C; CA₁; …; CA₁^{n−1}]` (unit columns after `x' = Dx`), then output scalings giving
//!   each row of `SCD⁻¹` the largest entry one (exactly, so that the form does not depend on the
//!   output units). This form is only invariant under diagonal changes of coordinates; it is
//!   tried last ([`scalings`]);
//! * [`Coordinates::Modal`]: the Gramian form followed by its real eigenbasis, in which `A` is
//!   block diagonal with normal blocks ([`modal`]); tried first of the normal forms, where the
//!   Gramian form is far from normal and the eigenbasis well conditioned. Like the Gramian form
//!   it is the same for every change of units or coordinates up to an orthogonal change of
//!   coordinates.
//!
//! The Gramian form is a canonical form, not an optimally conditioned one: for some plants (an
//! integrator chain, some random plants) LMI (41) written in it certifies a shorter window than
//! in the diagonal form or in the user's coordinates, so the design tries the data as given,
//! then the modal, Gramian and diagonal forms ([`crate::design()`]), and the verdict is exactly
//! invariant only when a canonical form (modal or Gramian) decides it.
//!
//! The design is done on `(k T A T⁻¹, S C T⁻¹)` and the window `[T1/k, T2/k]`, and mapped back:
//! `L = T⁻¹ L' S` (jump gains are dimensionless under time scaling), `P = TᵀP'T`, `F = TᵀF'T`,
//! `J = TᵀJ'S`. Condition (12) is re-verified on the user's data.

use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, MatRef, Side};
use sporadic_linalg::gramian_form::gramian_form;

use crate::system::Plant;
use sporadic_model::SamplingWindow;

/// Spread (in powers of two) of the rounded diagonal balancing exponents below which no diagonal
/// balancing is applied.
pub const BALANCE_DEAD_ZONE: i32 = 2;

pub use sporadic_linalg::gramian_form::{
    GRAMIAN_PASS_TOLERANCE, GRAMIAN_PASSES, MAX_GRAMIAN_CONDITION,
};

/// Largest exponent magnitude of a balancing factor (keeps every scaled entry finite).
const MAX_EXPONENT: f64 = 400.0;

/// Which coordinates LMI (41) was solved in (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coordinates {
    /// The user's data as given.
    Given,
    /// Time unit [`time_unit`], state coordinates in which the observability Gramian on one
    /// time unit is the identity, outputs with equal shares of it.
    Gramian,
    /// Time unit [`time_unit`], power-of-two diagonal state scalings, output scalings that give
    /// every row of `C` the largest entry one.
    Diagonal,
    /// The Gramian form followed by its real eigenbasis ([`modal`]): `A` block diagonal with
    /// normal blocks.
    Modal,
}

/// The change of units and coordinates taking the user's problem to the normalised one.
#[derive(Debug, Clone, PartialEq)]
pub struct Scaling {
    /// Which normal form this is.
    pub coordinates: Coordinates,
    /// Time unit `k` (new time = old time / `k`).
    pub time: f64,
    /// State transformation `T` (`x' = Tx`).
    pub state: Mat<f64>,
    /// `T⁻¹`.
    pub state_inverse: Mat<f64>,
    /// Output scaling `S` (diagonal entries; `y' = Sy`).
    pub output: Vec<f64>,
    /// Whether `T` includes, after the normal form, the change of coordinates to the
    /// certificate of an undecided solve (`crate::design`, not in the paper): `T = RT₀` with
    /// `RᵀR = P/λmax(P)` for that solve's `P`.
    pub certificate: bool,
}

impl Scaling {
    /// The identity (the problem as given) for a plant of order `n` with `q` outputs.
    pub fn identity(n: usize, q: usize) -> Self {
        Self {
            coordinates: Coordinates::Given,
            time: 1.0,
            state: Mat::identity(n, n),
            state_inverse: Mat::identity(n, n),
            output: vec![1.0; q],
            certificate: false,
        }
    }

    /// This scaling followed by the change of state coordinates `x'' = Gx'` (`G̃` the computed
    /// inverse of `G`): `T → GT`, `T⁻¹ → T⁻¹G̃`, the rest unchanged.
    pub fn then_state(&self, g: &Mat<f64>, g_inv: &Mat<f64>) -> Self {
        Self {
            state: g * &self.state,
            state_inverse: &self.state_inverse * g_inv,
            ..self.clone()
        }
    }

    /// The problem as given, each output divided by the largest modulus of its row of `C`
    /// (`y'_k = y_k / max_j |c_kj|`; a zero row is kept). LMI (41) is invariant under output
    /// units in exact arithmetic but its normalisation `‖J‖₂ ≤ 1` (`J = FL`) is not, so the
    /// same plant with its outputs in other units could certify a different window; with this
    /// scaling every choice of output units gives the same problem up to rounding. A row whose
    /// largest entry is `±1` (the papers' examples) is left exactly as it is.
    pub fn given(plant: &Plant) -> Self {
        Self {
            output: unit_rows(plant.c(), &vec![1.0; plant.n()]),
            ..Self::identity(plant.n(), plant.q())
        }
    }

    /// Whether this scaling changes nothing.
    pub fn is_identity(&self) -> bool {
        let n = self.state.nrows();
        self.time == 1.0
            && self.output.iter().all(|s| *s == 1.0)
            && (0..n).all(|j| (0..n).all(|i| self.state[(i, j)] == f64::from(u8::from(i == j))))
    }

    /// The normalised window `[T1/k, T2/k]`.
    pub fn window(&self, w: &SamplingWindow) -> Option<SamplingWindow> {
        SamplingWindow::new(w.t1() / self.time, w.t2() / self.time).ok()
    }

    /// The normalised plant `(k T A T⁻¹, S C T⁻¹)` (`None` when an entry is not finite).
    pub fn plant(&self, p: &Plant) -> Option<Plant> {
        let a1 = &self.state * p.a() * &self.state_inverse * faer::Scale(self.time);
        let c1 = p.c() * &self.state_inverse;
        let c1 = Mat::from_fn(p.q(), p.n(), |i, j| self.output[i] * c1[(i, j)]);
        Plant::new(a1.as_ref(), c1.as_ref()).ok()
    }

    /// `L = T⁻¹ L' S`.
    pub fn gain_back(&self, l: MatRef<'_, f64>) -> Mat<f64> {
        let l = &self.state_inverse * l;
        Mat::from_fn(l.nrows(), l.ncols(), |i, j| l[(i, j)] * self.output[j])
    }

    /// `X = Tᵀ X' T` (for `F`).
    pub fn congruence_back(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        self.state.transpose() * x * &self.state
    }

    /// `P = Tᵀ P' T` for a symmetric `P'`, symmetrised (the product is only symmetric up to
    /// rounding).
    pub fn symmetric_congruence_back(&self, p: MatRef<'_, f64>) -> Mat<f64> {
        sporadic_linalg::symmetric::symmetric_congruence(self.state.as_ref(), p)
    }

    /// The upper-triangular factor `R` (positive diagonal) of `P = TᵀP'T` for a symmetric
    /// positive definite `P'`: `R` is the triangular factor of the QR decomposition of
    /// `R'T`, with `P' = R'ᵀR'` (Cholesky, in the normalised coordinates, where `P'` is well
    /// conditioned), so that `RᵀR = TᵀP'T` up to the rounding of `R` alone (relative to
    /// `‖R‖`, not to `‖P‖`). `None` when `P'` is not positive definite or an entry is not
    /// finite.
    pub fn factor_back(&self, p: MatRef<'_, f64>) -> Option<Mat<f64>> {
        let n = p.nrows();
        let sym = Mat::from_fn(n, n, |i, j| 0.5 * (p[(i, j)] + p[(j, i)]));
        let llt = sym.llt(Side::Lower).ok()?;
        let rt = llt.L().transpose() * &self.state;
        let qr = rt.qr();
        let upper = qr.R();
        let r = Mat::from_fn(n, n, |i, j| {
            if i > j {
                0.0
            } else {
                upper[(i, j)] * upper[(i, i)].signum()
            }
        });
        ((0..n).all(|i| r[(i, i)] > 0.0) && r.is_all_finite()).then_some(r)
    }

    /// `J = Tᵀ J' S`.
    pub fn multiplier_gain_back(&self, j: MatRef<'_, f64>) -> Mat<f64> {
        let j = self.state.transpose() * j;
        Mat::from_fn(j.nrows(), j.ncols(), |r, c| j[(r, c)] * self.output[c])
    }
}

/// The time unit of the normal forms: `min(T2, T1 + H)` with `H` the decay horizon of a
/// Hurwitz `A` (`grid::decay_horizon`; `T2` when `A` is not Hurwitz). See the module
/// docs.
pub fn time_unit(plant: &Plant, window: &SamplingWindow) -> f64 {
    let (t1, t2) = (window.t1(), window.t2());
    crate::grid::decay_horizon(plant.a()).map_or(t2, |h| t2.min(t1 + h))
}

/// The normal forms of `plant` on `window` to try, in this order: the modal form (when there is
/// one, [`modal`]), the Gramian form (when it is usable), the diagonal form (when it changes
/// anything; see the module docs).
pub fn scalings(plant: &Plant, window: &SamplingWindow) -> Vec<Scaling> {
    let gramian = gramian_on(plant, time_unit(plant, window));
    let mut out: Vec<Scaling> = gramian
        .as_ref()
        .and_then(|g| modal(plant, g))
        .into_iter()
        .chain(gramian)
        .collect();
    let d = diagonal(plant, window);
    if !d.is_identity() {
        out.push(d);
    }
    out
}

/// Largest condition number `‖S‖₂‖S⁻¹‖₂` of the eigenbasis `S` of the Gramian form (unit
/// columns) at which [`modal`] gives a form: its rounding, about `κ(S)·u ≈ 2·10⁻¹⁰` relative,
/// stays far below the verification thresholds of LMI (41), while the eigenvectors of a
/// defective eigenvalue (integrator chains, Jordan blocks) are parallel to about `√u`
/// (`κ(S) ≳ 10⁸`). The condition depends on the time unit of the Gramian: on `eight-state-modal`
/// it is `7·10⁷` on `[0.01, 0.01]` (a Gramian over so short a time barely tells the modes
/// apart), `7·10³` on `[0.01, 0.28]`, `10³` on `[0.01, 0.53]`, `6·10²` on `[0.01, 0.65]`.
pub const MAX_MODAL_CONDITION: f64 = 1e6;

/// Departure from normality `√(‖A‖_F² − Σ|λ_i|²)/‖A‖_F` of the Gramian form's `A` (Henrici's
/// measure, relative) at or below which [`modal`] gives no form: the Gramian form is then
/// nearly normal already, and the modal form would solve nearly the same problem again.
pub const MODAL_DEPARTURE: f64 = 0.5;

/// The modal normal form after the Gramian form `gramian` (its `coordinates` must be
/// [`Coordinates::Gramian`]; `None` otherwise, or when the form would not differ, see below):
/// `x'' = S⁻¹x'` with `S` the real eigenbasis of the Gramian form's `A'` (for each eigenvalue
/// `σ ± iω`, `ω > 0`, the real and imaginary parts of its eigenvector `u`, `‖u‖₂ = 1`; for a
/// real one its unit eigenvector), so that `S⁻¹A'S` is block diagonal with the normal blocks
/// `[[σ, ω], [−ω, σ]]` and `σ`: the modal coordinates of structural dynamics.
///
/// Not in the paper. The Gramian form is canonical but can be far from normal: on the corpus
/// plant `eight-state-modal` (four lightly damped modes) its `A` has `‖A‖₂` sixteen times its
/// spectral radius, and written in random coordinates `x = Tz` (`κ(T) < 10`) the plant's
/// window search stopped at 0.586 within the budget against 0.596 as given, whose coordinates
/// are modal. The basis is determined by the Gramian form up to an orthogonal change of
/// coordinates (a rotation in each mode's plane: the phase of `u`; the Gramian form itself is
/// determined up to one), so this form is the same for every change of units or coordinates,
/// like the Gramian form. Its output weights are the Gramian form's. `None` when the basis
/// is incomplete or its condition number exceeds [`MAX_MODAL_CONDITION`], or when the
/// Gramian form's departure from normality is at most [`MODAL_DEPARTURE`].
pub fn modal(plant: &Plant, gramian: &Scaling) -> Option<Scaling> {
    if gramian.coordinates != Coordinates::Gramian {
        return None;
    }
    let a = &gramian.state * plant.a() * &gramian.state_inverse;
    let eigen = sporadic_linalg::real_eigenbasis(a.as_ref()).ok()??;
    let spectrum: f64 = eigen.eigenvalues.iter().map(|l| l.norm().powi(2)).sum();
    let frobenius = a.norm_l2();
    let departure = (frobenius.powi(2) - spectrum).max(0.0).sqrt() / frobenius;
    if !(departure > MODAL_DEPARTURE) {
        return None;
    }
    let basis = eigen.basis;
    let sigma = basis.singular_values().ok()?;
    let (largest, smallest) = (sigma.first().copied()?, sigma.last().copied()?);
    if !(largest <= MAX_MODAL_CONDITION * smallest) {
        return None;
    }
    let inverse = basis.partial_piv_lu().inverse();
    inverse.is_all_finite().then(|| Scaling {
        coordinates: Coordinates::Modal,
        ..gramian.then_state(&inverse, &basis)
    })
}

/// Largest number of doublings of the time unit in [`longer_unit_gramian`].
pub const DETECTABILITY_UNIT_DOUBLINGS: i32 = 16;

/// The Gramian form on the first of the time units `2k, 4k, …, 2^16 k` (`k` = [`time_unit`])
/// at which it is usable: where [`scalings`] holds no Gramian form, the Remark 3 precheck is
/// also tried in this one.
///
/// Detectability of `(e^{Av}, C)` does not depend on the coordinates, but its numerical test
/// does (the relative PBH margin), so a canonical form keeps the decision the same for every
/// equivalent problem. On a short window (in a window search, `[T1, T1]`) the Gramian on one
/// time unit sees too little of the dynamics to be usable (condition above
/// [`MAX_GRAMIAN_CONDITION`]); on a longer unit it is, and the unit still scales with the
/// problem (`k` is similarity-invariant and scales as `1/c` under
/// `(A, window) → (cA, window/c)`), so the form is still canonical. A marginal order-5 plant
/// with a near-triple eigenvalue at zero (one output, `T1 = 0.0117584`) has relative PBH
/// margin `6.4e-9 < 1e-8` in the diagonal form and in its own coordinates on `[T1, T1]`, and
/// `5.1e-5` in the Gramian form on `4T1`; its window `[T1, 0.312131]` is certified.
///
/// LMI (41) is not solved in these longer-unit forms: on that plant they certified no window
/// the other forms did not, at up to 15 times the cost of a failing design.
pub fn longer_unit_gramian(plant: &Plant, window: &SamplingWindow) -> Option<Scaling> {
    let unit = time_unit(plant, window);
    (1..=DETECTABILITY_UNIT_DOUBLINGS)
        .map(|j| unit * 2f64.powi(j))
        .take_while(|u| u.is_finite())
        .find_map(|u| gramian_on(plant, u))
}

/// The Gramian normal form with time unit `unit` (`None` when the Gramian is not usable;
/// [`sporadic_linalg::gramian_form::gramian_form`]).
fn gramian_on(plant: &Plant, unit: f64) -> Option<Scaling> {
    let form = gramian_form(plant.a(), plant.c(), unit)?;
    Some(Scaling {
        coordinates: Coordinates::Gramian,
        time: unit,
        state: form.state,
        state_inverse: form.state_inverse,
        output: form.output,
        certificate: false,
    })
}

/// The output scaling `S` that gives every row of `S C D⁻¹` (`D = diag(state)`) the largest
/// modulus one, exactly; a zero (or non-finite) row keeps its unit.
fn unit_rows(c: MatRef<'_, f64>, state: &[f64]) -> Vec<f64> {
    (0..c.nrows())
        .map(|k| {
            let m = (0..c.ncols())
                .map(|j| (c[(k, j)] / state[j]).abs())
                .fold(0.0, f64::max);
            if m > 0.0 && m.is_finite() {
                1.0 / m
            } else {
                1.0
            }
        })
        .collect()
}

/// The diagonal (power-of-two) normal form (see the module docs).
fn diagonal(plant: &Plant, window: &SamplingWindow) -> Scaling {
    let (n, q) = (plant.n(), plant.q());
    let time = time_unit(plant, window);
    let identity = Scaling {
        time,
        coordinates: Coordinates::Diagonal,
        ..Scaling::identity(n, q)
    };
    let (a, c) = (plant.a(), plant.c());
    // Observability scaling: D_j = largest entry of column j of O = [C; CA₁; …; CA₁^{n−1}]
    // with A₁ = kA (A₁/‖A₁‖_max instead when the powers overflow); x' = Dx gives O unit columns.
    let a1 = Mat::from_fn(n, n, |i, j| a[(i, j)] * time);
    let columns = |nu: f64| {
        let a1 = Mat::from_fn(n, n, |i, j| a1[(i, j)] / nu);
        let mut block = c.to_owned();
        let mut col = vec![0.0f64; n];
        for _ in 0..n {
            for (j, cj) in col.iter_mut().enumerate() {
                for k in 0..q {
                    *cj = cj.max(block[(k, j)].abs());
                }
            }
            block = &block * &a1;
        }
        col
    };
    let mut col = columns(1.0);
    if col.iter().any(|v| !v.is_finite()) {
        col = columns(a1.norm_max().max(1.0));
    }
    if col.iter().any(|v| !v.is_finite()) {
        return identity;
    }
    // An unobservable coordinate (zero column) keeps its unit. The exponents are taken
    // relative to the largest column, so that `C → cC`, which scales every column by `c`,
    // leaves them as they are (the output scaling below takes `c`).
    let top = col.iter().copied().fold(0.0f64, f64::max);
    let e: Vec<f64> = col
        .iter()
        .map(|v| {
            if *v > 0.0 {
                (v / top).log2().round().clamp(-MAX_EXPONENT, MAX_EXPONENT)
            } else {
                0.0
            }
        })
        .collect();
    let lo = e.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = e.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let state: Vec<f64> = if hi - lo <= f64::from(BALANCE_DEAD_ZONE) {
        vec![1.0; n]
    } else {
        e.iter().map(|x| 2f64.powi(*x as i32)).collect()
    };
    // Each output row of S C D⁻¹ with its largest entry one: exactly, not to a power of two,
    // so that the form does not depend on the output units.
    let output = unit_rows(c, &state);
    Scaling {
        state: Mat::from_fn(n, n, |i, j| if i == j { state[i] } else { 0.0 }),
        state_inverse: Mat::from_fn(n, n, |i, j| if i == j { 1.0 / state[i] } else { 0.0 }),
        output,
        ..identity
    }
}
