//! Rigorous proofs that a design's condition holds for **every** sampling interval `τ` of a
//! window (issue "Proofs, not samples"), not only on the floating-point grid of the design's
//! re-verification.
//!
//! A method proves its central condition (e.g. Ferrante et al. 2016, (12)) with interval
//! arithmetic (`sporadic-interval`): it encloses the condition's matrix over a piece
//! `[τa, τb]` of the window and either proves it negative definite there, shows that it fails
//! at a point of the piece, or cannot decide. [`prove_on_window`] drives that check over an
//! adaptive subdivision of the window (a piece that cannot be decided is bisected, so pieces
//! are short where the margin is thin), within a piece budget and the time budget of the
//! enclosing [`crate::budget`] scope, and summarises the run as a [`Proof`].

use serde::{Deserialize, Serialize};
use std::time::{Duration, Instant};

/// Outcome of a proof, serialised as `proved`, `not_proved`, `inconclusive`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProofStatus {
    /// The condition holds for every `τ` of the window (and every member of the sets the
    /// theorem quantifies over), proven in outward-rounded interval arithmetic.
    Proved,
    /// The condition fails: at a point of [`Proof::failed_on`] the enclosure of its decisive
    /// eigenvalue lies on the wrong side of zero (or the design's floating-point check failed
    /// before any proof was attempted).
    NotProved,
    /// Neither: a piece could not be decided within the piece or time budget, or the method
    /// has no prover.
    Inconclusive,
}

impl ProofStatus {
    /// The string used in reports.
    pub fn as_str(self) -> &'static str {
        match self {
            ProofStatus::Proved => "proved",
            ProofStatus::NotProved => "not_proved",
            ProofStatus::Inconclusive => "inconclusive",
        }
    }
}

impl std::fmt::Display for ProofStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.as_str())
    }
}

/// A piece of a window where a proof failed or stopped, with what was found there.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProofPiece {
    /// The condition (e.g. "(12)", or "(44), sensor 2").
    pub condition: String,
    /// The piece `[τa, τb]`.
    pub tau: [f64; 2],
    /// Enclosure `[lo, hi]` of the decisive quantity on the piece (the largest eigenvalue of
    /// the condition's matrix, normalised as [`Proof::margin_definition`] says; the condition
    /// needs it `< 0`).
    pub enclosure: [f64; 2],
}

/// The `proof` section of a design report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Proof {
    /// The outcome.
    pub status: ProofStatus,
    /// What was proven (the condition, its paper and equation, the set of `τ` and of any
    /// polytope it quantifies over).
    pub condition: String,
    /// How: the enclosure of `e^{Aτ}`, the definiteness test, the arithmetic.
    pub how: String,
    /// Number of `τ`-pieces checked in the final subdivision (all windows together).
    pub subintervals: usize,
    /// Rigorous lower bound of the margin over the whole window (`proved` only).
    pub margin_lower_bound: Option<f64>,
    /// What the margin is (scale-free where the condition allows it).
    pub margin_definition: String,
    /// Where the proof failed (`not_proved`) or stopped (`inconclusive`).
    pub failed_on: Option<ProofPiece>,
    /// Largest relative width of the enclosures of `e^{Aτ}` over the pieces used.
    pub enclosure_width: Option<f64>,
    /// The result in words.
    pub message: String,
    /// Wall time of the proof, seconds.
    pub seconds: f64,
}

impl Proof {
    /// A proof that was not attempted, with status `status` and the reason in `message`
    /// (e.g. the method has no prover; the design is not certified).
    pub fn not_attempted(status: ProofStatus, message: impl Into<String>) -> Self {
        Self {
            status,
            condition: String::new(),
            how: String::new(),
            subintervals: 0,
            margin_lower_bound: None,
            margin_definition: String::new(),
            failed_on: None,
            enclosure_width: None,
            message: message.into(),
            seconds: 0.0,
        }
    }
}

/// A bisection whose enclosure is wider than this share of its parent's has not narrowed it.
const STALL_RATIO: f64 = 0.9;

/// Consecutive bisections without narrowing after which a piece is given up as `inconclusive`.
const MAX_STALLS: u32 = 6;

/// Budgets of a proof.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProofOptions {
    /// Largest number of pieces of one window (≥ 1).
    pub max_pieces: usize,
    /// Wall-time budget (`None`: only the enclosing [`crate::budget`] scope's).
    pub time_limit: Option<Duration>,
}

impl Default for ProofOptions {
    fn default() -> Self {
        Self {
            max_pieces: 4096,
            time_limit: None,
        }
    }
}

/// What a method's check found on one piece `[τa, τb]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PieceCheck {
    /// The condition holds on the whole piece, with this rigorous lower bound of the margin.
    Holds {
        /// Rigorous lower bound of the margin on the piece (> 0).
        margin_lower_bound: f64,
        /// Relative width of the enclosure of `e^{Aτ}` used.
        enclosure_width: f64,
    },
    /// The condition fails at a point of the piece: `enclosure` (of the decisive eigenvalue
    /// there) lies at or above zero.
    Fails {
        /// Enclosure `[lo, hi]` of the decisive eigenvalue, `lo ≥ 0`.
        enclosure: [f64; 2],
    },
    /// Neither could be shown on this piece (the enclosure is too wide): bisect it.
    Undecided {
        /// Enclosure `[lo, hi]` of the decisive eigenvalue on the piece.
        enclosure: [f64; 2],
    },
}

/// What stopped an `inconclusive` [`prove_on_window`] ([`WindowProof::stop`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProofStop {
    /// The time budget ran out.
    Time,
    /// The piece budget ([`ProofOptions::max_pieces`]) ran out.
    Pieces,
    /// The interval evaluation no longer resolves the condition: bisections stopped narrowing
    /// the enclosure, or the piece cannot be split in floating point. More time or pieces
    /// would not decide it.
    Resolution,
}

/// The result of [`prove_on_window`] for one window.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowProof {
    /// The outcome on this window.
    pub status: ProofStatus,
    /// Pieces checked in the final subdivision (proved ones plus the one it stopped on).
    pub pieces: usize,
    /// Smallest margin lower bound over the proved pieces (`None` if none).
    pub margin_lower_bound: Option<f64>,
    /// Largest relative enclosure width over the proved pieces.
    pub enclosure_width: Option<f64>,
    /// Where it failed or stopped.
    pub failed_on: Option<ProofPiece>,
    /// Why it stopped, when it is not `proved`.
    pub message: String,
    /// Which limit stopped an `inconclusive` subdivision (`None` otherwise, and for a proof
    /// that is not a subdivision).
    pub stop: Option<ProofStop>,
}

/// Proves `check` on every piece of an adaptive subdivision of `[t1, t2]` (a point window
/// when `t1 == t2`).
///
/// The window starts as `initial_pieces` equal pieces; an [`PieceCheck::Undecided`] piece is
/// bisected (depth first, in increasing `τ`) until every piece holds, one fails (status
/// `not_proved`), a piece can no longer be split in floating point, six bisections in a row
/// leave its enclosure as wide as before (rounding, not the variation over the piece, decides:
/// the margin there is below what the evaluation resolves), the number of pieces reaches
/// [`ProofOptions::max_pieces`], or the time budget runs out (status `inconclusive`).
/// `condition` names the condition in [`ProofPiece::condition`].
///
/// # Errors
/// The first error of `check` (a kernel failure that is not a verdict).
pub fn prove_on_window<E>(
    condition: &str,
    t1: f64,
    t2: f64,
    initial_pieces: usize,
    options: &ProofOptions,
    check: &mut dyn FnMut(f64, f64) -> Result<PieceCheck, E>,
) -> Result<WindowProof, E> {
    let start = Instant::now();
    let n0 = if t1 < t2 { initial_pieces.max(1) } else { 1 };
    let max_pieces = options.max_pieces.max(1).max(n0);
    // Stack of pieces still to check, the next one on top.
    // Pieces to check, the next one on top, each with the width of its parent's enclosure and
    // the number of consecutive bisections that did not narrow the enclosure.
    let mut todo: Vec<(f64, f64, f64, u32)> = (0..n0)
        .rev()
        .map(|k| {
            let a = if k == 0 {
                t1
            } else {
                t1 + (t2 - t1) * k as f64 / n0 as f64
            };
            let b = if k + 1 == n0 {
                t2
            } else {
                t1 + (t2 - t1) * (k + 1) as f64 / n0 as f64
            };
            (a, b, f64::INFINITY, 0)
        })
        .collect();
    let mut pieces = n0;
    let mut proved = 0usize;
    let mut lower: Option<f64> = None;
    let mut width: Option<f64> = None;
    let stopped = |what: &str, a: f64, b: f64, enclosure: [f64; 2], message: String| {
        (
            ProofPiece {
                condition: what.to_string(),
                tau: [a, b],
                enclosure,
            },
            message,
        )
    };
    while let Some((a, b, parent_width, stalls)) = todo.pop() {
        let out_of_time =
            crate::budget::exhausted() || options.time_limit.is_some_and(|l| start.elapsed() >= l);
        if out_of_time {
            let (p, m) = stopped(
                condition,
                a,
                b,
                [f64::NEG_INFINITY, f64::INFINITY],
                format!(
                    "the time budget ran out after {proved} of the pieces were proved; \
                     τ ∈ [{}, {}] was not yet checked",
                    crate::significant(a),
                    crate::significant(b)
                ),
            );
            return Ok(WindowProof {
                status: ProofStatus::Inconclusive,
                pieces: proved + 1,
                margin_lower_bound: lower,
                enclosure_width: width,
                failed_on: Some(p),
                message: m,
                stop: Some(ProofStop::Time),
            });
        }
        match check(a, b)? {
            PieceCheck::Holds {
                margin_lower_bound,
                enclosure_width,
            } => {
                proved += 1;
                lower = Some(lower.map_or(margin_lower_bound, |l| l.min(margin_lower_bound)));
                width = Some(width.map_or(enclosure_width, |w| w.max(enclosure_width)));
            }
            PieceCheck::Fails { enclosure } => {
                let (p, m) = stopped(
                    condition,
                    a,
                    b,
                    enclosure,
                    format!(
                        "{condition} fails in τ ∈ [{}, {}]: the decisive eigenvalue there lies in \
                         [{}, {}], not below 0",
                        crate::significant(a),
                        crate::significant(b),
                        crate::significant(enclosure[0]),
                        crate::significant(enclosure[1])
                    ),
                );
                return Ok(WindowProof {
                    status: ProofStatus::NotProved,
                    pieces: proved + 1,
                    margin_lower_bound: None,
                    enclosure_width: width,
                    failed_on: Some(p),
                    message: m,
                    stop: None,
                });
            }
            PieceCheck::Undecided { enclosure } => {
                let mid = a + 0.5 * (b - a);
                let splittable = mid > a && mid < b;
                // Bisection narrows an enclosure dominated by the variation over the piece by
                // about half; one dominated by rounding does not narrow at all, and an unbounded
                // one (the evaluation overflowed) has not narrowed either.
                let piece_width = enclosure[1] - enclosure[0];
                let stalls = if !piece_width.is_finite() || piece_width > STALL_RATIO * parent_width
                {
                    stalls + 1
                } else {
                    0
                };
                if !splittable || pieces >= max_pieces || stalls >= MAX_STALLS {
                    let (stop, why) = if !splittable {
                        (
                            ProofStop::Resolution,
                            "the piece cannot be split further in floating point".to_string(),
                        )
                    } else if stalls >= MAX_STALLS {
                        (
                            ProofStop::Resolution,
                            format!(
                                "{MAX_STALLS} bisections in a row did not narrow the enclosure \
                                 (the margin there is below the accuracy of the interval \
                                 evaluation)"
                            ),
                        )
                    } else {
                        (
                            ProofStop::Pieces,
                            format!("the budget of {max_pieces} pieces ran out"),
                        )
                    };
                    let (p, m) = stopped(
                        condition,
                        a,
                        b,
                        enclosure,
                        format!(
                            "{condition} could not be decided in τ ∈ [{}, {}] (the decisive \
                             eigenvalue lies in [{}, {}]) and {why}",
                            crate::significant(a),
                            crate::significant(b),
                            crate::significant(enclosure[0]),
                            crate::significant(enclosure[1])
                        ),
                    );
                    return Ok(WindowProof {
                        status: ProofStatus::Inconclusive,
                        pieces: proved + 1,
                        margin_lower_bound: lower,
                        enclosure_width: width,
                        failed_on: Some(p),
                        message: m,
                        stop: Some(stop),
                    });
                }
                pieces += 1;
                todo.push((mid, b, piece_width, stalls));
                todo.push((a, mid, piece_width, stalls));
            }
        }
    }
    Ok(WindowProof {
        status: ProofStatus::Proved,
        pieces: proved,
        margin_lower_bound: lower,
        enclosure_width: width,
        failed_on: None,
        message: String::new(),
        stop: None,
    })
}

/// A [`Proof`] of several windows (e.g. one per round-robin sensor, or one per condition),
/// each proven with [`prove_on_window`]: proved when every part is; otherwise the first part
/// that is not proved decides (a `not_proved` part before an `inconclusive` one).
pub fn combine(
    condition: impl Into<String>,
    how: impl Into<String>,
    margin_definition: impl Into<String>,
    parts: Vec<WindowProof>,
    seconds: f64,
) -> Proof {
    let subintervals = parts.iter().map(|p| p.pieces).sum();
    let width = parts
        .iter()
        .filter_map(|p| p.enclosure_width)
        .fold(None, |w: Option<f64>, x| Some(w.map_or(x, |w| w.max(x))));
    let decisive = parts
        .iter()
        .find(|p| p.status == ProofStatus::NotProved)
        .or_else(|| parts.iter().find(|p| p.status == ProofStatus::Inconclusive));
    let condition = condition.into();
    match decisive {
        None => {
            let lower = parts
                .iter()
                .filter_map(|p| p.margin_lower_bound)
                .fold(f64::INFINITY, f64::min);
            let lower = lower.is_finite().then_some(lower);
            Proof {
                status: ProofStatus::Proved,
                message: format!(
                    "proved on {subintervals} τ-pieces; the margin is at least {}",
                    lower.map_or_else(|| "—".into(), crate::significant)
                ),
                condition,
                how: how.into(),
                subintervals,
                margin_lower_bound: lower,
                margin_definition: margin_definition.into(),
                failed_on: None,
                enclosure_width: width,
                seconds,
            }
        }
        Some(p) => Proof {
            status: p.status,
            message: p.message.clone(),
            condition,
            how: how.into(),
            subintervals,
            margin_lower_bound: None,
            margin_definition: margin_definition.into(),
            failed_on: p.failed_on.clone(),
            enclosure_width: width,
            seconds,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A toy condition: margin 1 − τ/τ* holds below τ*; the enclosure of −margin over a piece
    /// is exact, so the check decides a piece once it lies on one side of τ*.
    fn toy(tau_star: f64) -> impl FnMut(f64, f64) -> Result<PieceCheck, ()> {
        move |a, b| {
            let hi = b / tau_star - 1.0;
            let lo = a / tau_star - 1.0;
            Ok(if hi < 0.0 {
                PieceCheck::Holds {
                    margin_lower_bound: -hi,
                    enclosure_width: 0.0,
                }
            } else if lo >= 0.0 || (b - a) < 1e-3 {
                // at τ = b the condition fails (the toy's point check)
                PieceCheck::Fails {
                    enclosure: [hi, hi],
                }
            } else {
                PieceCheck::Undecided {
                    enclosure: [lo, hi],
                }
            })
        }
    }

    #[test]
    fn proves_inside_and_refuses_outside() {
        let o = ProofOptions::default();
        let p = prove_on_window("toy", 0.1, 0.9, 4, &o, &mut toy(1.0)).unwrap();
        assert_eq!((p.status, p.stop), (ProofStatus::Proved, None));
        assert!((p.margin_lower_bound.unwrap() - 0.1).abs() < 1e-12);
        let p = prove_on_window("toy", 0.1, 1.5, 4, &o, &mut toy(1.0)).unwrap();
        assert_eq!((p.status, p.stop), (ProofStatus::NotProved, None));
        let f = p.failed_on.unwrap();
        assert!(f.tau[0] <= 1.0 + 1e-3 && f.tau[1] >= 1.0 - 1e-3, "{f:?}");
    }

    #[test]
    fn a_thin_margin_refines_and_a_small_budget_is_inconclusive() {
        let o = ProofOptions {
            max_pieces: 8,
            time_limit: None,
        };
        // An enclosure as wide as the piece (variation-dominated: bisection halves it) with its
        // upper end above zero: refined until the piece budget runs out.
        let mut narrowing = |a: f64, b: f64| -> Result<PieceCheck, ()> {
            Ok(PieceCheck::Undecided {
                enclosure: [-(b - a), b - a],
            })
        };
        let p = prove_on_window("c", 0.0, 1.0, 1, &o, &mut narrowing).unwrap();
        assert_eq!(p.status, ProofStatus::Inconclusive);
        assert!(p.message.contains("budget of 8 pieces"), "{}", p.message);
        assert_eq!(p.stop, Some(ProofStop::Pieces));
        let mut undecided = |_: f64, _: f64| -> Result<PieceCheck, ()> {
            Ok(PieceCheck::Undecided {
                enclosure: [-1.0, 1.0],
            })
        };
        // An enclosure that never narrows is given up after a few bisections, not at the budget.
        let big = ProofOptions::default();
        let p = prove_on_window("c", 0.0, 1.0, 1, &big, &mut undecided).unwrap();
        assert_eq!(p.status, ProofStatus::Inconclusive);
        assert!(p.message.contains("did not narrow"), "{}", p.message);
        assert_eq!(p.stop, Some(ProofStop::Resolution));
        assert!(p.pieces <= 8, "{}", p.pieces);
        // No time: stopped before the first piece.
        let none = ProofOptions {
            time_limit: Some(Duration::ZERO),
            ..big
        };
        let p = prove_on_window("c", 0.0, 1.0, 1, &none, &mut undecided).unwrap();
        assert_eq!(
            (p.status, p.stop),
            (ProofStatus::Inconclusive, Some(ProofStop::Time))
        );
        // A point window is one piece and cannot be split.
        let p = prove_on_window("c", 0.5, 0.5, 7, &o, &mut undecided).unwrap();
        assert_eq!(p.status, ProofStatus::Inconclusive);
        assert!(p.message.contains("cannot be split"), "{}", p.message);
        assert_eq!(p.stop, Some(ProofStop::Resolution));
    }

    #[test]
    fn combine_takes_the_failed_part_and_the_smallest_margin() {
        let o = ProofOptions::default();
        let good = prove_on_window("a", 0.1, 0.5, 2, &o, &mut toy(1.0)).unwrap();
        let bad = prove_on_window("b", 0.1, 2.0, 2, &o, &mut toy(1.0)).unwrap();
        let p = combine("c", "h", "m", vec![good.clone(), good.clone()], 0.0);
        assert_eq!(p.status, ProofStatus::Proved);
        assert!((p.margin_lower_bound.unwrap() - 0.5).abs() < 1e-12);
        let p = combine("c", "h", "m", vec![good, bad], 0.0);
        assert_eq!(p.status, ProofStatus::NotProved);
        assert_eq!(p.failed_on.unwrap().condition, "b");
        let v = serde_json::to_value(ProofStatus::NotProved).unwrap();
        assert_eq!(v, "not_proved");
    }
}
