//! Rigorous proof (issue 24, "Proofs, not samples") that a design of Rabehi et al. (2021)
//! satisfies the condition of Theorem 1 for the implemented jump matrix `Γ(L)` (Remark 6),
//!
//! ```text
//! (19)   Φ(μ) = Γ(L)ᵀ e^{Āᵀμ} P e^{Āμ} Γ(L) − P ≺ 0     for every μ ∈ [τmin, τmax],
//! ```
//!
//! with the report's gain `L` and Lyapunov matrix `P_19`, for **every** `μ` of the window (not
//! on a grid), in outward-rounded interval arithmetic (`sporadic-interval`):
//!
//! * `Ā = [[A^M, A^N], [A^N, A^M]]` is exact (entries of `A` copied); `G = I + LC` is enclosed,
//!   and `Γ(L) = [[G⁺, G⁻], [G⁻, G⁺]]` is enclosed from it (`x ↦ max(x, 0)` and
//!   `x ↦ max(−x, 0)` are monotone, so the enclosure of `G` maps to enclosures of `G⁺`, `G⁻`):
//!   the proof is about the exact `Γ(L)`, not its floating-point value;
//! * on a piece `[μa, μb]` of the window, [`expm_enclosure`] encloses `e^{Āμ}` for every `μ` of
//!   the piece, `Φ` is enclosed by interval products and symmetrised, and
//!   [`is_verified_negative_definite`] (Rump's verified Cholesky test) bounds `λmax(Φ)` from
//!   above; a piece it cannot decide is bisected by [`prove_on_window`];
//! * when a piece is not proved, `Φ` at its midpoint (a point enclosure of `e^{Āμ}`) is enclosed
//!   by [`lambda_max_enclosure`]: a lower end `≥ 0` is a rigorous disproof (`not_proved`).
//!
//! The margin is `−λmax(Φ(μ))/p̄` with `p̄` a rigorous upper bound of `λmax(P)`: the relative
//! decrease, at every jump, of the Lyapunov function `V = ξᵀe^{Āᵀτ}Pe^{Āτ}ξ` of the proof of
//! Theorem 1 (scale-free).
//!
//! `P ≻ 0` (required by Theorem 1; not implied by (19) alone when `e^{Āμ}Γ(L)` is not Schur
//! stable) is proven with the same definiteness test, its margin `λmin(P)/p̄` entering the
//! minimum.
//!
//! **Coordinates.** The method designs in the balanced coordinates `x_b = D⁻¹x` (`D` the
//! powers-of-2 scaling of `A`, [`sporadic_linalg::balance`]) and reports `L` in the plant's
//! coordinates but `P_19` in the balanced ones. The proof maps the plant's `A`, `C` and the
//! report's `L` to the balanced coordinates (`D⁻¹AD`, `CD`, `D⁻¹L`: exact in floating point,
//! which is checked by mapping back; if it were not, for data near the overflow or underflow
//! range, the proof is made in the plant's coordinates with `P = D̄⁻¹P_19D̄⁻¹`, `D̄ =
//! diag(D, D)`). Both are the same statement: the interval error in the two coordinates differs
//! by the positive diagonal map `D̄`, and (19) and `P ≻ 0` are invariant under the congruence by
//! `D̄`. In the balanced coordinates the margin does not depend on the user's units.

use faer::{Mat, MatRef};
use sporadic_interval::{
    EnclosureOptions, Interval, IntervalError, IntervalMatrix, Verdict, expm_enclosure,
    is_verified_negative_definite, is_verified_positive_definite, lambda_max_enclosure,
};
use sporadic_linalg::balance::{
    balance_a, balance_b, balance_c, unbalance_a, unbalance_form, unbalance_gain,
};
use sporadic_model::{
    DesignReport, Gain, MethodError, NamedMatrix, PieceCheck, Plant as ModelPlant, Proof,
    ProofOptions, SamplingWindow, combine, prove_on_window,
};

use crate::ipr::MetzlerDecomposition;

const ID: &str = "rabehi2021";

/// Initial number of pieces of the window (bisected where the margin is thin).
const INITIAL_PIECES: usize = 4;

/// Bad input of the prover or of `verify`, as a [`MethodError::InvalidInput`].
pub(crate) fn bad(message: impl Into<String>) -> MethodError {
    MethodError::invalid(ID, message)
}

/// A failure of the interval kernels (not a verdict).
fn numerical(e: IntervalError) -> MethodError {
    MethodError::numerical(ID, e)
}

/// `rows` as a `rows × cols` matrix with finite entries, or bad input naming `what`.
fn shaped(m: &[Vec<f64>], rows: usize, cols: usize, what: &str) -> Result<Mat<f64>, MethodError> {
    sporadic_model::report::checked_mat(m, rows, cols, what).map_err(bad)
}

/// The gain `L` (`n × p`) and the certificate `P_19` (`2n × 2n`, balanced coordinates, when
/// given) of a report or of a user, with names and shapes checked.
///
/// # Errors
/// [`MethodError::InvalidInput`] for gains other than one constant `L`, a certificate matrix
/// whose name is not one of the report's (`P`, `F`, `G1`, `G2`, `P_19`), a wrong shape or a
/// non-finite entry.
pub(crate) fn read_given(
    n: usize,
    p: usize,
    gains: &[Gain],
    certificate: &[NamedMatrix],
) -> Result<(Mat<f64>, Option<Mat<f64>>), MethodError> {
    let [gain] = gains else {
        return Err(bad(format!(
            "rabehi2021 has one gain, L; {} gains were given",
            gains.len()
        )));
    };
    if gain.name != "L" || gain.schedule.is_some() {
        return Err(bad(format!(
            "rabehi2021's gain is one constant matrix named L, not {:?}{}",
            gain.name,
            if gain.schedule.is_some() {
                " with a schedule"
            } else {
                ""
            }
        )));
    }
    let l = shaped(&gain.rows, n, p, "gain L")?;
    let known = ["P", "F", "G1", "G2", "P_19"];
    if let Some(m) = certificate
        .iter()
        .find(|m| !known.contains(&m.name.as_str()))
    {
        return Err(bad(format!(
            "rabehi2021's certificate has P, F, G1, G2 (BMI (44)) and P_19 (Theorem 1); not {:?}",
            m.name
        )));
    }
    let p19 = certificate
        .iter()
        .find(|m| m.name == "P_19")
        .map(|m| shaped(&m.rows, 2 * n, 2 * n, "certificate P_19"))
        .transpose()?;
    Ok((l, p19))
}

/// Enclosure of `Γ(L) = [[G⁺, G⁻], [G⁻, G⁺]]` with `G = I + LC` enclosed.
fn gamma_enclosure(
    l: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
) -> Result<IntervalMatrix, IntervalError> {
    let n = l.nrows();
    let g = IntervalMatrix::identity(n).checked_add(
        &IntervalMatrix::from_point(l)?.checked_mul(&IntervalMatrix::from_point(c)?)?,
    )?;
    let (lo, hi) = (g.lower(), g.upper());
    let plus = |x: f64| x.max(0.0);
    let minus = |x: f64| (-x).max(0.0);
    // G⁺ ∈ [lo⁺, hi⁺], G⁻ ∈ [hi⁻, lo⁻] entrywise.
    let lower = Mat::from_fn(2 * n, 2 * n, |i, j| {
        if (i < n) == (j < n) {
            plus(lo[(i % n, j % n)])
        } else {
            minus(hi[(i % n, j % n)])
        }
    });
    let upper = Mat::from_fn(2 * n, 2 * n, |i, j| {
        if (i < n) == (j < n) {
            plus(hi[(i % n, j % n)])
        } else {
            minus(lo[(i % n, j % n)])
        }
    });
    IntervalMatrix::from_bounds(lower.as_ref(), upper.as_ref())
}

/// The data of the proof: `Ā`, the enclosure of `Γ(L)`, `P` (plant coordinates) and `p̄`.
struct Operands {
    a_bar: Mat<f64>,
    gamma: IntervalMatrix,
    p: IntervalMatrix,
    scale: Interval,
}

impl Operands {
    /// Encloses `Φ(μ)` for every `μ ∈ [a, b]`, and returns it with the relative width of the
    /// enclosure of `e^{Āμ}`.
    fn phi(&self, a: f64, b: f64) -> Result<(IntervalMatrix, f64), IntervalError> {
        let options = EnclosureOptions {
            max_pieces: 1,
            ..EnclosureOptions::default()
        };
        let e = expm_enclosure(self.a_bar.as_ref(), a, b, &options)?.enclosure;
        let eg = e.checked_mul(&self.gamma)?;
        let phi = eg
            .transpose()
            .checked_mul(&self.p)?
            .checked_mul(&eg)?
            .checked_sub(&self.p)?
            .symmetrized()?;
        Ok((phi, e.rel_width()))
    }

    /// `λmax(x)/p̄` enclosed.
    fn normalised(&self, x: &IntervalMatrix) -> Result<[f64; 2], IntervalError> {
        let e = lambda_max_enclosure(x)? / self.scale;
        Ok([e.lo(), e.hi()])
    }

    /// The check of `P ≻ 0` (margin `λmin(P)/p̄`).
    fn positive(&self) -> Result<PieceCheck, IntervalError> {
        if let Verdict::Proved { bound } = is_verified_positive_definite(&self.p)? {
            return Ok(PieceCheck::Holds {
                margin_lower_bound: (Interval::point(bound)? / self.scale).lo(),
                enclosure_width: 0.0,
            });
        }
        let e = self.normalised(&-&self.p)?;
        let enclosure = [e[0], e[1]];
        Ok(if enclosure[0] >= 0.0 {
            PieceCheck::Fails { enclosure }
        } else {
            PieceCheck::Undecided { enclosure }
        })
    }

    /// The piece check of [`prove_on_window`] on `[a, b]`.
    fn check(&self, a: f64, b: f64) -> Result<PieceCheck, IntervalError> {
        let (phi, width) = self.phi(a, b)?;
        if let Verdict::Proved { bound } = is_verified_negative_definite(&phi)? {
            return Ok(PieceCheck::Holds {
                margin_lower_bound: (Interval::point(-bound)? / self.scale).lo(),
                enclosure_width: width,
            });
        }
        let mid = a + 0.5 * (b - a);
        let (at_mid, _) = self.phi(mid, mid)?;
        let enclosure = self.normalised(&at_mid)?;
        if enclosure[0] >= 0.0 {
            return Ok(PieceCheck::Fails { enclosure });
        }
        Ok(PieceCheck::Undecided {
            enclosure: self.normalised(&phi)?,
        })
    }
}

/// Proves (19) (module docs) for the gain `L` and certificate `P_19` of `design` (a certified
/// report of this method) on the plant `plant`.
///
/// # Errors
/// [`MethodError::InvalidInput`] for a plant without an output matrix, a report without a
/// window, gain `L` or certificate `P_19`, or of the wrong shapes; [`MethodError::Numerical`]
/// for a failure of the interval kernels.
pub fn prove_design(
    plant: &ModelPlant,
    design: &DesignReport,
    options: &ProofOptions,
) -> Result<Proof, MethodError> {
    let start = std::time::Instant::now();
    let window = design
        .window
        .ok_or_else(|| bad("the design report has no sampling window [T1, T2]"))?;
    let c = plant
        .c()
        .ok_or_else(|| bad("rabehi2021 needs one output matrix C"))?;
    let (n, p) = (plant.n(), c.nrows());
    let (l, p19) = read_given(n, p, &design.gains, &design.certificate)?;
    let p19 = p19.ok_or_else(|| bad("the design report's certificate has no P_19"))?;
    let d = crate::method::balancing_scales_of(plant.a());
    let (a_b, c_b, l_b) = (
        balance_a(plant.a(), &d),
        balance_c(c, &d),
        balance_b(l.as_ref(), &d),
    );
    let exact = unbalance_a(a_b.as_ref(), &d) == plant.a()
        && Mat::from_fn(p, n, |i, j| c_b[(i, j)] / d[j]) == c
        && unbalance_gain(l_b.as_ref(), &d) == l;
    let operands = if exact {
        operands(a_b.as_ref(), l_b.as_ref(), c_b.as_ref(), &p19)?
    } else {
        let doubled: Vec<f64> = d.iter().chain(d.iter()).copied().collect();
        let p_user = unbalance_form(p19.as_ref(), &doubled);
        operands(plant.a(), l.as_ref(), c, &p_user)?
    };
    prove_operands(&operands, &window, exact, options, start)
}

/// The operands of (19) on the plant `(A, C)` with the gain `L` and `P` in its coordinates.
fn operands(
    a: MatRef<'_, f64>,
    l: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
    p: &Mat<f64>,
) -> Result<Operands, MethodError> {
    let a_bar = MetzlerDecomposition::new(a)
        .map_err(|e| MethodError::InvalidInput {
            method: ID,
            source: Box::new(e),
        })?
        .a_bar;
    let gamma = gamma_enclosure(l, c).map_err(numerical)?;
    let p = IntervalMatrix::from_point(p.as_ref())
        .and_then(|x| x.symmetrized())
        .map_err(numerical)?;
    let hi = lambda_max_enclosure(&p).map_err(numerical)?.hi();
    let scale =
        Interval::point(if hi > 0.0 && hi.is_finite() { hi } else { 1.0 }).map_err(numerical)?;
    Ok(Operands {
        a_bar,
        gamma,
        p,
        scale,
    })
}

fn prove_operands(
    operands: &Operands,
    window: &SamplingWindow,
    balanced: bool,
    options: &ProofOptions,
    start: std::time::Instant,
) -> Result<Proof, MethodError> {
    let (t1, t2) = (window.t1(), window.t2());
    let positive = prove_on_window("P ≻ 0", t1, t1, 1, options, &mut |_, _| {
        operands.positive()
    })
    .map_err(numerical)?;
    let condition = prove_on_window("(19)", t1, t2, INITIAL_PIECES, options, &mut |a, b| {
        operands.check(a, b)
    })
    .map_err(numerical)?;
    let coordinates = if balanced {
        "in the balanced coordinates of the design (A, C and L mapped exactly)"
    } else {
        "in the plant's coordinates (P_19 mapped to them)"
    };
    Ok(combine(
        format!(
            "Theorem 1 (Rabehi et al. 2021): P ≻ 0 and (19) Γ(L)ᵀe^(Āᵀμ)Pe^(Āμ)Γ(L) − P ≺ 0 for \
             every μ ∈ [{t1}, {t2}], for the implemented jump matrix Γ(L) = [[G⁺, G⁻], [G⁻, G⁺]], \
             G = I + LC (Remark 6), with the report's L and P = P_19, {coordinates}"
        ),
        "outward-rounded interval arithmetic (sporadic-interval, midpoint–radius): e^(Āμ) \
         enclosed over each μ-piece (Taylor enclosure with a rigorous remainder), G = I + LC \
         and Γ(L) enclosed, Φ by interval products and symmetrised; Rump's verified Cholesky \
         test for the sign (rigorous λmax upper bound); an undecided piece is bisected, and a \
         rigorous λmax enclosure of Φ at its midpoint disproves (19) when its lower end is ≥ 0",
        "the smaller of λmin(P)/p̄ and −λmax(Φ(μ))/p̄ minimised over the window, p̄ a rigorous \
         upper bound of λmax(P): the second is the relative decrease at every jump of \
         V = ξᵀe^(Āᵀτ)Pe^(Āτ)ξ (scale-free)",
        vec![positive, condition],
        start.elapsed().as_secs_f64(),
    ))
}
