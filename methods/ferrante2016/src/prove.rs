//! Rigorous proof of Theorem 1's hypotheses for a given `(P, L)` (Ferrante et al. 2016): `P ≻ 0`
//! and condition (12),
//! `(I − LC)'e^{A'v}Pe^{Av}(I − LC) − P ≺ 0` for **every** `v ∈ [T1, T2]`,
//! in outward-rounded interval arithmetic (`sporadic-interval`), not on a grid.
//!
//! On a piece `[va, vb]` of the window, `e^{Av}` is enclosed for every `v` of the piece
//! ([`expm_enclosure`]); `G = e^{Av}(I − LC)` and `Q = G'PG − P` are formed in interval
//! arithmetic and symmetrised (every member that is a value of (12)'s left-hand side is
//! symmetric); `Q` is scaled by the exact power-of-two congruence `Δ = diag(2^{k_i})`,
//! `2^{k_i} ≈ P_ii^{-1/2}`, which leaves its definiteness unchanged and makes the test
//! independent of a diagonal change of state units; Rump's verified negative-definiteness test
//! then decides the piece. A piece that is not proven is checked at its midpoint (a point
//! enclosure): if the enclosure of `λmax` there is at or above zero, (12) fails there; otherwise
//! the piece is bisected ([`sporadic_model::prove_on_window`]).
//!
//! **Long windows** (issue 22). For a Hurwitz `A` and a window longer than the decay of every
//! mode (`T2 > S = T1 + 72/|α|`, the `grid` module), the pieces above cover `[T1, S]` only, and the
//! tail `[S, T2]` is proved at once (`prove_tail`): with `X ≻ 0` solving `A'X + XA = −I`
//! (both properties proven in interval arithmetic), `‖e^{Aw}‖₂² ≤ κ = λmax(X)/λmin(X)` for every
//! `w ≥ 0`, so for every `v ≥ S`, writing `e^{Av} = e^{A(v−S)}e^{AS}`,
//! `λmax(Δ Q(v) Δ) ≤ λmax(P)·κ·‖e^{AS}(I − LC)Δ‖₂² − λmin(ΔPΔ)`, which is negative when `e^{AS}`
//! (enclosed rigorously) is small enough — as it is, `‖e^{AS}‖ ~ e^{−72}` times the plant's
//! transient. Otherwise the tail is `inconclusive` (never `proved` without that bound).
//!
//! The margin is scale-free: `−λmax(Δ Q Δ)/λmax(Δ P Δ)`, bounded below over the window. (The
//! design's grid check measures instead the contraction in the norm of `P`, which is also
//! invariant under non-diagonal changes of coordinates, see [`crate::verify()`]; a certificate
//! whose diagonally scaled `P` is very ill-conditioned can pass that check and leave this
//! proof `inconclusive`.)

use faer::{Mat, MatRef};
use sporadic_interval::{
    EnclosureOptions, Interval, IntervalError, IntervalMatrix, Verdict, expm_enclosure,
    is_verified_negative_definite, is_verified_positive_definite, lambda_max_enclosure,
};
use sporadic_linalg::lyap_continuous;
use sporadic_model::{
    PieceCheck, Proof, ProofOptions, ProofPiece, ProofStatus, SamplingWindow, WindowProof, combine,
    prove_on_window,
};

use crate::error::Error;
use crate::system::Plant;

/// What the proof's margin is.
pub const PROOF_MARGIN_DEFINITION: &str = "min over v in [T1, T2] of −λmax(Δ Q(v) Δ) / \
     λmax(Δ P Δ), Q(v) = (I − LC)'e^(A'v)Pe^(Av)(I − LC) − P the left-hand side of (12), Δ = \
     diag(2^k_i) with 2^k_i ≈ P_ii^(-1/2) (an exact congruence; the value does not depend on the \
     units of the states)";

/// `Δ X Δ` in interval arithmetic (a rigorous product with the exact diagonal `Δ`).
fn congruence(delta: &IntervalMatrix, x: &IntervalMatrix) -> Result<IntervalMatrix, IntervalError> {
    delta.checked_mul(x)?.checked_mul(delta)?.symmetrized()
}

/// Rigorously proves `P ≻ 0` and (12) for every `v` in `window` for the gain `l` and the
/// Lyapunov matrix `p` (the hypotheses of Theorem 1), within `options`' budgets.
///
/// `not_proved` is reported only with evidence: `P` is not positive definite, or (12)'s
/// left-hand side has an enclosure of `λmax` at or above zero at a point of the window.
///
/// # Errors
/// Bad input ([`Error::Input`]: shapes, non-finite or non-symmetric `P`).
pub fn prove_condition12(
    plant: &Plant,
    window: &SamplingWindow,
    l: MatRef<'_, f64>,
    p: MatRef<'_, f64>,
    options: &ProofOptions,
) -> Result<Proof, Error> {
    plant.check_lyapunov_matrix(p)?;
    let reset = plant.reset_matrix(l)?;
    let start = std::time::Instant::now();
    let n = plant.n();
    let how = "e^(Av) enclosed for every v of a piece by a Taylor model in v with a rigorous \
               remainder (sporadic-interval), (12)'s left-hand side in outward-rounded \
               midpoint–radius arithmetic, Rump's verified negative definiteness (floating-point \
               Cholesky with an a-priori rounding bound) on adaptively bisected pieces; P ≻ 0 by \
               the same test";
    let condition = "Theorem 1: P ≻ 0 and (12) (I − LC)'e^(A'v)Pe^(Av)(I − LC) − P ≺ 0 for \
                     every v in [T1, T2]";
    let numerical = |e: IntervalError| Proof {
        status: ProofStatus::Inconclusive,
        message: format!("the interval evaluation failed: {e}"),
        ..Proof::not_attempted(ProofStatus::Inconclusive, String::new())
    };
    let delta_v = crate::verify::power_of_two_scaling(p);
    let delta = Mat::from_fn(n, n, |i, j| if i == j { delta_v[i] } else { 0.0 });
    let (pi, di, ri) = match (
        IntervalMatrix::from_point(p),
        IntervalMatrix::from_point(delta.as_ref()),
        IntervalMatrix::from_point(reset.as_ref()),
    ) {
        (Ok(a), Ok(b), Ok(c)) => (a, b, c),
        (Err(e), _, _) | (_, Err(e), _) | (_, _, Err(e)) => return Ok(numerical(e)),
    };
    let ps = match congruence(&di, &pi) {
        Ok(x) => x,
        Err(e) => return Ok(numerical(e)),
    };
    // P ≻ 0 (Theorem 1), and an upper bound of λmax(ΔPΔ) for the scale-free margin.
    let (p_scale, ps_min) = match (
        is_verified_positive_definite(&ps),
        lambda_max_enclosure(&ps),
    ) {
        (Ok(Verdict::Proved { bound }), Ok(e)) if e.hi().is_finite() => (e.hi(), bound),
        (Ok(Verdict::Proved { .. }), _) => {
            return Ok(Proof {
                condition: condition.into(),
                how: how.into(),
                margin_definition: PROOF_MARGIN_DEFINITION.into(),
                ..Proof::not_attempted(
                    ProofStatus::Inconclusive,
                    "no finite bound of λmax(P) could be proven",
                )
            });
        }
        (Ok(Verdict::NotProved), _) => {
            // Evidence that P is not positive definite, or only too close to call?
            let lmin = lambda_max_enclosure(&-&ps).map(|e| -e.lo()).ok();
            let status = if lmin.is_some_and(|m| m <= 0.0) {
                ProofStatus::NotProved
            } else {
                ProofStatus::Inconclusive
            };
            return Ok(Proof {
                condition: condition.into(),
                how: how.into(),
                margin_definition: PROOF_MARGIN_DEFINITION.into(),
                ..Proof::not_attempted(
                    status,
                    "P ≻ 0 could not be proven (Theorem 1 needs a positive definite P)",
                )
            });
        }
        (Err(e), _) => return Ok(numerical(e)),
    };
    let a = plant.a();
    let enclosure_options = EnclosureOptions {
        max_pieces: 1,
        ..EnclosureOptions::default()
    };
    // λmax of Δ Q Δ for every v in [va, vb], as an interval matrix.
    let lhs = |va: f64, vb: f64| -> Result<(IntervalMatrix, f64), IntervalError> {
        let e = expm_enclosure(a, va, vb, &enclosure_options)?;
        let g = e.enclosure.checked_mul(&ri)?;
        let q = g
            .transpose()
            .checked_mul(&pi.checked_mul(&g)?)?
            .checked_sub(&pi)?;
        Ok((congruence(&di, &q.symmetrized()?)?, e.rel_width))
    };
    let relative = |x: f64| -> f64 {
        // x / p_scale rounded toward −∞ (x < 0 gives a margin bound −x/p_scale rounded down).
        (Interval::point(x).unwrap_or(Interval::ENTIRE)
            / Interval::point(p_scale).unwrap_or(Interval::ENTIRE))
        .lo()
    };
    let relative_up = |x: f64| -> f64 {
        (Interval::point(x).unwrap_or(Interval::ENTIRE)
            / Interval::point(p_scale).unwrap_or(Interval::ENTIRE))
        .hi()
    };
    let mut check = |va: f64, vb: f64| -> Result<PieceCheck, IntervalError> {
        let (q, width) = lhs(va, vb)?;
        if let Verdict::Proved { bound } = is_verified_negative_definite(&q)? {
            return Ok(PieceCheck::Holds {
                margin_lower_bound: relative(-bound),
                enclosure_width: width,
            });
        }
        let vm = va + 0.5 * (vb - va);
        let (qm, _) = lhs(vm, vm)?;
        let at_mid = lambda_max_enclosure(&qm)?;
        if at_mid.lo() >= 0.0 {
            return Ok(PieceCheck::Fails {
                enclosure: [relative(at_mid.lo()), relative_up(at_mid.hi())],
            });
        }
        let whole = lambda_max_enclosure(&q)?;
        Ok(PieceCheck::Undecided {
            enclosure: [relative(whole.lo()), relative_up(whole.hi())],
        })
    };
    let (t1, t2) = (window.t1(), window.t2());
    // A window longer than the decay of every mode: pieces on [T1, S], the tail at once.
    let split = crate::grid::split_point(a, t1, t2);
    let head_end = split.unwrap_or(t2);
    let norm_a = (0..n)
        .map(|i| (0..n).map(|j| a[(i, j)].abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let initial = ((norm_a * (head_end - t1)).ceil() as usize).clamp(1, 1024);
    let mut parts = match prove_on_window("(12)", t1, head_end, initial, options, &mut check) {
        Ok(p) => vec![p],
        Err(e) => return Ok(numerical(e)),
    };
    if let Some(s) = split {
        let tail = Tail {
            p: &pi,
            reset: &ri,
            delta: &di,
            ps_min,
            p_scale,
        };
        parts.push(match prove_tail(a, s, t2, &tail) {
            Ok(p) => p,
            Err(e) => return Ok(numerical(e)),
        });
    }
    let how = if split.is_some() {
        format!(
            "{how}; for v beyond the decay of every mode, at once from ‖e^(Av)‖ ≤ ‖e^(A(v−S))‖·‖e^(AS)‖ with a Lyapunov bound of ‖e^(Aw)‖, w ≥ 0"
        )
    } else {
        how.to_string()
    };
    Ok(combine(
        condition,
        how,
        PROOF_MARGIN_DEFINITION,
        parts,
        start.elapsed().as_secs_f64(),
    ))
}

/// What [`prove_tail`] needs of the certificate: `P`, `I − LC` and `Δ` as interval matrices, a
/// rigorous lower bound of `λmin(ΔPΔ)` and an upper bound of `λmax(ΔPΔ)` (the margin's scale).
struct Tail<'a> {
    p: &'a IntervalMatrix,
    reset: &'a IntervalMatrix,
    delta: &'a IntervalMatrix,
    ps_min: f64,
    p_scale: f64,
}

/// Proves (12) for every `v ∈ [s, t2]` at once (see the module docs): `proved` with the margin
/// lower bound `(λmin(ΔPΔ) − λmax(P)·κ·‖e^{As}(I − LC)Δ‖_F²)/λmax(ΔPΔ)` when it is positive,
/// `inconclusive` otherwise (the bound is only sufficient).
fn prove_tail(
    a: MatRef<'_, f64>,
    s: f64,
    t2: f64,
    tail: &Tail<'_>,
) -> Result<WindowProof, IntervalError> {
    let n = a.nrows();
    let undecided = |message: String| WindowProof {
        status: ProofStatus::Inconclusive,
        pieces: 1,
        margin_lower_bound: None,
        enclosure_width: None,
        failed_on: Some(ProofPiece {
            condition: "(12)".into(),
            tau: [s, t2],
            enclosure: [f64::NEG_INFINITY, f64::INFINITY],
        }),
        message,
        stop: None,
    };
    // κ = λmax(X)/λmin(X) for X ≻ 0 with A'X + XA ≺ 0 (both proven): ‖e^{Aw}‖₂² ≤ κ, w ≥ 0.
    let Ok(x) = lyap_continuous(a, Mat::<f64>::identity(n, n).as_ref()) else {
        return Ok(undecided(
            "no Lyapunov matrix of A for the tail beyond the decay of every mode".into(),
        ));
    };
    let (ai, xi) = (
        IntervalMatrix::from_point(a)?,
        IntervalMatrix::from_point(x.as_ref())?,
    );
    let lyapunov = ai
        .transpose()
        .checked_mul(&xi)?
        .checked_add(&xi.checked_mul(&ai)?)?
        .symmetrized()?;
    let x_min = match (
        is_verified_negative_definite(&lyapunov)?,
        is_verified_positive_definite(&xi.symmetrized()?)?,
    ) {
        (Verdict::Proved { .. }, Verdict::Proved { bound }) => bound,
        _ => {
            return Ok(undecided(
                "A'X + XA ≺ 0, X ≻ 0 could not be proven for the tail beyond the decay of \
                 every mode"
                    .into(),
            ));
        }
    };
    let x_max = lambda_max_enclosure(&xi.symmetrized()?)?.hi();
    let p_max = lambda_max_enclosure(tail.p)?.hi();
    let e = expm_enclosure(a, s, s, &EnclosureOptions::default())?;
    let g = e
        .enclosure
        .checked_mul(tail.reset)?
        .checked_mul(tail.delta)?
        .norm_fro_up();
    let point = |v: f64| Interval::point(v).unwrap_or(Interval::ENTIRE);
    let growth = point(p_max) * (point(x_max) / point(x_min)) * point(g).sqr();
    let margin = ((point(tail.ps_min) - growth) / point(tail.p_scale)).lo();
    if margin.is_nan() || margin <= 0.0 {
        return Ok(undecided(format!(
            "the tail bound λmax(P)·κ·‖e^(AS)(I − LC)Δ‖² = {:.3e} is not below λmin(ΔPΔ) = {:.3e} \
             (S = {s})",
            growth.hi(),
            tail.ps_min
        )));
    }
    Ok(WindowProof {
        status: ProofStatus::Proved,
        pieces: 1,
        margin_lower_bound: Some(margin),
        enclosure_width: Some(e.rel_width),
        failed_on: None,
        message: String::new(),
        stop: None,
    })
}
