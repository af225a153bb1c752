//! The main loop of the infeasible primal–dual predictor–corrector method.

use std::time::Instant;

use faer::Mat;

use super::Accept;
use super::blockops::{BlockMats, Factored, Factors, factor_all, inner, step_and_factor};
use super::certificate::InfeasibilityCertificate;
use super::cost::Cost;
use super::direction::{Direction, Iterate, System};
use super::linsys::SchurSolver;
use super::lsq::LeastSquares;
use super::point::{Point, interior_start};
use super::residuals::{DataNorms, Residuals, measures, residuals};
use super::schur::assemble;
use super::settings::{IterationLog, Settings};
use super::solution::{FacialPath, Solution, Status};
use super::start::initial_point;
use super::step::{Confirm, Side, step_lengths};
use super::structure::{Analysis, Values};
use crate::problem::Problem;

/// Reusable workspaces of a [`super::Solver`].
pub(crate) struct Workspace {
    /// Row buffers of the blocks assembled together ([`assemble`]).
    pub schur_rows: Vec<f64>,
    /// Factorisation of the Schur matrix.
    pub linsys: SchurSolver,
    /// Least-squares form of the Newton system, allocated the first time it is needed.
    pub lsq: Option<LeastSquares>,
}

/// How the Newton systems are currently solved (see [`super::lsq`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// Normal equations `M Δy = r` (Cholesky).
    Normal,
    /// Least squares in the scaled space (Householder QR).
    LeastSquares,
}

/// A refined normal-equations direction whose primal error exceeds this multiple of the
/// refinement threshold is inaccurate unless conjugate gradients bring it down to the threshold
/// (`direction::krylov`); otherwise the solve continues with the least-squares form.
const ACCEPTED_ERROR: f64 = 10.0;

/// Best iterate seen so far (by [`Residuals::merit`]).
///
/// While the current iterate is the best one it is not copied: [`Best::Current`] only records
/// its merit, and the iterate is moved into [`Best::Earlier`] when a step replaces it.
enum Best {
    /// No iterate yet.
    None,
    /// The current iterate, with its merit.
    Current(f64),
    /// An earlier iterate, better than every one since.
    Earlier {
        merit: f64,
        x: BlockMats,
        y: Vec<f64>,
        s: BlockMats,
    },
}

impl Best {
    fn merit(&self) -> f64 {
        match self {
            Best::None => f64::INFINITY,
            Best::Current(merit) | Best::Earlier { merit, .. } => *merit,
        }
    }
}

/// Steps below this are tiny (SDPT3 `steptol`): [`STALLED_STEPS`] consecutive iterations with
/// a tiny `min(α_p, α_d)` count as stalling, and a single one where both steps are tiny does,
/// since the next iteration would start from the same point and repeat the same direction.
const TINY_STEP: f64 = 1e-6;
/// See [`TINY_STEP`].
const STALLED_STEPS: usize = 2;
/// A quantity "progresses" when it falls below this fraction of its value at its last progress.
const PROGRESS_FACTOR: f64 = 0.8;
/// Stop after this many iterations without progress …
///
/// Near the optimum too: an earlier rule stopped after five once the best merit was below
/// [`NEAR_OPTIMAL_MERIT`], and ended in numerical trouble at a relative gap of 1.4e-5 the
/// hull-membership LP of a random matrix of order 6 (embed's `containment` property test: 7
/// rows, 125 columns, right-hand sides from 0.27 down to 1.3e-7), where the gap wanders for five
/// iterations at μ ≈ 1.4e-7 and then falls steadily to the optimum at iteration 44.
const NO_PROGRESS_ITERATIONS: usize = 10;
/// … or this many once the best iterate is within the reduced tolerance `tol_reduced` in every
/// DIMACS error, so that the solve ends almost optimal at worst. On the default SDPLIB set no
/// iterate after two in a row without progress at that accuracy came within the full tolerance
/// (hinf1, 3, 5–8, 10, 11, 13–15, and qap6–8 with the least-squares directions they took
/// before the conjugate-gradient rescue, stay on a plateau within 1.5× of the best), while
/// ss30 reaches it after one (4.9e-8, 4.5e-8, then 1.7e-8 and optimal); waiting five
/// iterations cost hinf6, hinf10, hinf11 three more each.
const NO_PROGRESS_ITERATIONS_REDUCED: usize = 2;
/// Merit below which the iterates are close enough to the optimum that a sustained rise of `μ`
/// means the attainable accuracy has been reached.
const NEAR_OPTIMAL_MERIT: f64 = 1e-3;
/// Stop once `μ` has risen in this many consecutive iterations while the best merit is below
/// [`NEAR_OPTIMAL_MERIT`]: a path-following method decreases `μ`, so a sustained rise means the
/// rounding in the directions has taken over and the iterates are leaving the central path
/// (hinf6: `μ` rises from 5.7e-6 to 1.4e-4 over five iterations after its best point).
const MU_RISES_NEAR: usize = 3;
/// An infeasibility that grows beyond this multiple of its smallest value (and above 10× the
/// tolerance) has deteriorated (SDPT3 `sqlpcheckconvg.m`, `dual_infeas_bad`).
const DETERIORATION: f64 = 1e3;

/// Progress monitor in the spirit of SDPT3's `sqlpcheckconvg.m`: an iteration makes progress if
/// the merit (largest stopping measure) falls by [`PROGRESS_FACTOR`] below its value at its last
/// progress, or an infeasibility that is still above its tolerance falls by that factor below
/// the smallest value it ever had, and neither infeasibility has deteriorated. (Comparing with
/// the smallest value, not with the value at the last progress, keeps an infeasibility that
/// oscillates around its tolerance from counting as progress again and again.)
struct Progress {
    merit: f64,
    pinf_min: f64,
    dinf_min: f64,
    since: usize,
    /// `μ` at the previous iterate and the number of consecutive rises up to the current one.
    mu_prev: f64,
    mu_rises: usize,
}

impl Progress {
    fn new() -> Self {
        Self {
            merit: f64::INFINITY,
            pinf_min: f64::INFINITY,
            dinf_min: f64::INFINITY,
            since: 0,
            mu_prev: f64::INFINITY,
            mu_rises: 0,
        }
    }

    /// Whether the iterates have stalled: no progress for [`NO_PROGRESS_ITERATIONS`], or, once
    /// the best merit is below [`NEAR_OPTIMAL_MERIT`], `μ` rising [`MU_RISES_NEAR`] times in a
    /// row, or, once the best iterate is within the reduced tolerance (`best_reduced`), no
    /// progress for [`NO_PROGRESS_ITERATIONS_REDUCED`].
    fn stalled(&self, best_merit: f64, best_reduced: bool) -> bool {
        self.since >= NO_PROGRESS_ITERATIONS
            || (best_reduced && self.since >= NO_PROGRESS_ITERATIONS_REDUCED)
            || (best_merit <= NEAR_OPTIMAL_MERIT && self.mu_rises >= MU_RISES_NEAR)
    }

    fn update(&mut self, res: &Residuals, mu: f64, settings: &Settings) {
        if mu > self.mu_prev {
            self.mu_rises += 1;
        } else {
            self.mu_rises = 0;
        }
        self.mu_prev = mu;
        let tol = settings.tol_feas;
        let merit = res.merit();
        let mut progress = false;
        if merit < PROGRESS_FACTOR * self.merit {
            self.merit = merit;
            progress = true;
        }
        for (value, min) in [(res.pinf, self.pinf_min), (res.dinf, self.dinf_min)] {
            if value > tol && value < PROGRESS_FACTOR * min {
                progress = true;
            }
        }
        self.pinf_min = self.pinf_min.min(res.pinf);
        self.dinf_min = self.dinf_min.min(res.dinf);
        let worse = |v: f64, min: f64| v > (DETERIORATION * min).max(10.0 * tol);
        if worse(res.pinf, self.pinf_min) || worse(res.dinf, self.dinf_min) {
            progress = false;
        }
        if progress {
            self.since = 0;
        } else {
            self.since += 1;
        }
    }
}

/// Backtracking factor when the updated `X` or `S` fails its Cholesky factorisation.
const BACKTRACK: f64 = 0.8;

/// Pre-filter of [`detect_infeasibility`] during the iterations: a candidate ray is verified
/// only when its cheap defect bound is below this (or below `tol_infeas` if larger).
const PREFILTER: f64 = 1e-4;

/// Looks for a verified infeasibility certificate at the current iterate; `prefilter` bounds
/// the cheap defect estimates of the candidates that are verified ([`PREFILTER`] while
/// iterating, `∞` for the last attempt before a stall is reported).
fn detect_infeasibility(
    problem: &Problem,
    cost: &Cost,
    res: &Residuals,
    x: &[Mat<f64>],
    y: &[f64],
    settings: &Settings,
    gram: &mut Option<SchurSolver>,
    prefilter: f64,
) -> Option<(Status, InfeasibilityCertificate)> {
    // Cheap pre-filters; the certificate itself is verified on the problem data.
    let prefilter = settings.tol_infeas.max(prefilter);
    if res.dobj > 0.0 && res.pinf > settings.tol_feas {
        // ‖𝒜ᵀ(y) + S‖_F = ‖C − R_d‖_F bounds λ_max(𝒜ᵀ(y)) from above.
        let mut sq = 0.0;
        for (k, r) in res.rd.iter().enumerate() {
            cost.block(k).for_each(r.nrows(), r.ncols(), |i, j, a| {
                let b = r[(i, j)];
                sq += (a - b) * (a - b);
            });
        }
        if sq.sqrt() / res.dobj <= prefilter
            && let Some(cert) = InfeasibilityCertificate::primal(problem, y)
            && cert.verify(problem).is_ok_and(|v| v <= settings.tol_infeas)
        {
            return Some((Status::PrimalInfeasible, cert));
        }
    }
    if res.pobj < 0.0 && res.dinf > settings.tol_feas {
        let ax: f64 = problem
            .b
            .iter()
            .zip(&res.rp)
            .map(|(b, r)| (b - r) * (b - r))
            .sum::<f64>()
            .sqrt();
        if ax / -res.pobj <= prefilter
            && let Some(cert) = InfeasibilityCertificate::dual(problem, x, gram)
            && cert.verify(problem).is_ok_and(|v| v <= settings.tol_infeas)
        {
            return Some((Status::DualInfeasible, cert));
        }
    }
    None
}

/// A Newton `Δy` this many times larger (max-norm) than `max(1, ‖y‖∞)` is tested as a Farkas
/// ray by [`ray_certificate`].
const RAY_RATIO: f64 = 1e8;

/// Tests a Newton direction `Δy` as a primal-infeasibility certificate.
///
/// With linearly dependent constraints the Schur matrix `M = 𝒜 (X ⊗ S⁻¹) 𝒜ᵀ` is singular along
/// every `v` with `𝒜ᵀ(v) = 0`; when `bᵀv ≠ 0` the equations `𝒜(X) = b` are inconsistent, (P) is
/// infeasible, and `v / bᵀv` is an exact Farkas certificate (`λ_max(𝒜ᵀ(v)) = 0`). The computed
/// `Δy` of such a system is dominated by `v` (its component along `v` is `vᵀr / λ_min(M)`, with
/// `vᵀr = vᵀb` since `vᵀ𝒜(·) = 0`), so it is the certificate the iterates would take many
/// diverging steps to approximate — and the second-order term of the corrector, formed from
/// the meaningless `ΔS` of that predictor, can even flip its sign (SDPT3 removes such
/// constraints in preprocessing, `checkdepconstr.m`). The candidate is accepted only after
/// [`InfeasibilityCertificate::verify`] on the problem data.
fn ray_certificate(
    problem: &Problem,
    y: &[f64],
    dy: &[f64],
    settings: &Settings,
) -> Option<InfeasibilityCertificate> {
    let max_abs = |v: &[f64]| v.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    if !(max_abs(dy) > RAY_RATIO * max_abs(y).max(1.0)) {
        return None;
    }
    let cert = InfeasibilityCertificate::primal(problem, dy)?;
    cert.verify(problem)
        .is_ok_and(|v| v <= settings.tol_infeas)
        .then_some(cert)
}

/// Outcome of the direction computation of one iteration.
enum Next {
    /// The corrector direction and the predictor's step length `min(α_p, α_d)`.
    Step(Direction, f64),
    /// The predictor's `Δy` is a verified Farkas ray ([`ray_certificate`]).
    Ray(InfeasibilityCertificate),
    /// No direction could be computed.
    Trouble,
}

/// Takes the steps `alpha_p` along `dx` from `x` and `alpha_d` along `ds` from `s` (both
/// formed in one pass over the blocks), backtracking a side whose new point has no Cholesky
/// factorisation. Returns per side the step, the new point and its factors.
fn take_steps(
    an: &Analysis,
    (x, dx, alpha_p): (&[Mat<f64>], &[Mat<f64>], f64),
    (s, ds, alpha_d): (&[Mat<f64>], &[Mat<f64>], f64),
) -> Option<[(f64, Factored); 2]> {
    let [p, d] = step_and_factor(an, [(x, alpha_p, dx), (s, alpha_d, ds)]);
    let side = |first: Option<Factored>, cur, dir, alpha| match first {
        Some(f) => Some((alpha, f)),
        None => backtrack(an, cur, dir, alpha),
    };
    Some([side(p, x, dx, alpha_p)?, side(d, s, ds, alpha_d)?])
}

/// After a failed step `alpha` along `d` from `cur`: the step shortened by [`BACKTRACK`] until
/// the new point has a Cholesky factorisation (at most eight steps in all).
fn backtrack(
    an: &Analysis,
    cur: &[Mat<f64>],
    d: &[Mat<f64>],
    mut alpha: f64,
) -> Option<(f64, Factored)> {
    for _ in 1..8 {
        alpha *= BACKTRACK;
        let [next] = step_and_factor(an, [(cur, alpha, d)]);
        if let Some(f) = next {
            return Some((alpha, f));
        }
    }
    None
}

/// Where the interior-point method starts.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Start<'a> {
    /// SDPT3's default point ([`initial_point`]), its levels `ξ`, `η` multiplied by this factor.
    Default(f64),
    /// A given point (validated against the analysis), made interior ([`interior_start`]).
    From(&'a Point),
}

/// Runs the interior-point method on validated, analysed data from `start`.
pub(crate) fn run(
    an: &Analysis,
    vals: &Values,
    problem: &Problem,
    settings: &Settings,
    ws: &mut Workspace,
    start: Start<'_>,
    mut accept: Option<&mut Accept<'_>>,
) -> Solution {
    let started = Instant::now();
    let cd = Cost::new(an, vals);
    let norms = DataNorms::new(&vals.b, &cd);
    let nu = an.nu as f64;
    let (mut x, mut y, mut s) = match start {
        Start::From(p) => interior_start(an, vals, p),
        Start::Default(level) => initial_point(an, vals, level),
    };
    let mut fx = factor_all(an, &x);
    let mut fs = factor_all(an, &s);
    let mut steps = (0.0, 0.0);
    let mut best = Best::None;
    // Whether the best iterate is within `tol_reduced` in every DIMACS error.
    let mut best_reduced = false;
    let mut progress = Progress::new();
    let mut tiny_steps = 0usize;
    let mut iteration = 0usize;
    let mut certificate = None;
    let mut gram = None;
    let mut mode = Mode::Normal;
    let mut lsq_failed = false;
    let mut lsq_used = false;
    // Conjugate gradients stand in for the least-squares form and are tried only where it could
    // be used: without it the normal equations carry on as they are (and a step of conjugate
    // gradients on blocks of order in the thousands would cost seconds).
    let lsq_fits = LeastSquares::fits(an);
    let status = loop {
        let res = residuals(an, vals, &cd, &norms, &x, &y, &s);
        let mu = if an.nu > 0 { res.xs / nu } else { 0.0 };
        let state = IterationLog {
            iteration,
            primal_objective: res.pobj,
            dual_objective: res.dobj,
            rel_gap: res.rel_gap,
            primal_infeas: res.pinf,
            dual_infeas: res.dinf,
            mu,
            primal_step: steps.0,
            dual_step: steps.1,
        };
        if let Some(log) = &settings.log {
            log(&state);
        }
        let merit = res.merit();
        if !merit.is_finite() {
            break Status::NumericalTrouble;
        }
        if merit < best.merit() {
            best = Best::Current(merit);
            best_reduced = res.dimacs_interior(&norms) <= settings.tol_reduced;
        }
        progress.update(&res, mu, settings);
        if res.rel_gap <= settings.tol_gap
            && res.rel_compl <= settings.tol_gap
            && res.pinf <= settings.tol_feas
            && res.dinf <= settings.tol_feas
        {
            break Status::Optimal;
        }
        if let Some(accept) = accept.as_mut()
            && accept(&y, &state)
        {
            break Status::Accepted;
        }
        let at_limit = iteration >= settings.max_iterations;
        let stalled = !at_limit
            && (tiny_steps >= STALLED_STEPS || progress.stalled(best.merit(), best_reduced));
        // Iterates that stall while diverging along a ray (one side blocked by tiny steps) may
        // never bring the cheap defect bound under the pre-filter although the polished ray is
        // an exact certificate: before a stall is reported the candidates are verified anyway.
        let prefilter = if stalled { f64::INFINITY } else { PREFILTER };
        if let Some((st, cert)) =
            detect_infeasibility(problem, &cd, &res, &x, &y, settings, &mut gram, prefilter)
        {
            certificate = Some(cert);
            break st;
        }
        if at_limit {
            break Status::MaxIterations;
        }
        if crate::budget::exhausted() {
            break Status::Interrupted;
        }
        if stalled {
            break Status::NumericalTrouble;
        }
        let (Some(fxv), Some(fsv)) = (fx.take(), fs.take()) else {
            break Status::NumericalTrouble;
        };
        let f = Factors::new(an, fxv, fsv);

        // Errors of 𝒜(ΔX) = r_p below 1% of the current residual (or of the tolerance) cannot
        // spoil the step and are not refined; a normal-equations direction still off by more
        // than ten times that after refinement is inaccurate.
        let floor = 0.1 * settings.tol_feas * (1.0 + norms.b2);
        let threshold = 0.01 * res.rp_norm.max(floor);
        let it = Iterate {
            an,
            vals,
            x: &x,
            f: &f,
            rp: &res.rp,
            rd: &res.rd,
            threshold,
            accepted: if lsq_fits {
                ACCEPTED_ERROR * threshold
            } else {
                f64::INFINITY
            },
            // Conjugate gradients must reach the threshold itself, except once the primal
            // infeasibility is a tenth of its tolerance: the accepted error (a hundredth of the
            // tolerance) can then no longer spoil it (qap8 from iteration 19: the steps stall at
            // 6.5 times the threshold, and the least-squares form took two more QR iterations
            // for the same end point).
            rescued: if res.rp_norm <= floor {
                ACCEPTED_ERROR * threshold
            } else {
                threshold
            },
        };
        let gamma = settings
            .step_fraction
            .unwrap_or(0.9 + 0.09 * steps.0.min(steps.1));
        let directions = loop {
            let system = match mode {
                Mode::Normal => {
                    // Schur complement, shared by predictor and corrector.
                    let Workspace {
                        linsys, schur_rows, ..
                    } = &mut *ws;
                    assemble(an, vals, &x, &f, linsys.matrix_mut(), schur_rows);
                    if !linsys.factorize(|out| assemble(an, vals, &x, &f, out, schur_rows)) {
                        if lsq_failed {
                            break Next::Trouble;
                        }
                        mode = Mode::LeastSquares;
                        continue;
                    }
                    System::Normal(&ws.linsys)
                }
                Mode::LeastSquares => {
                    if ws.lsq.is_none() {
                        ws.lsq = LeastSquares::new(an);
                    }
                    if !ws
                        .lsq
                        .as_mut()
                        .is_some_and(|ls| ls.factorize(an, vals, &x, &f))
                    {
                        if lsq_used {
                            // Non-finite scaled constraints: the iterate itself is broken.
                            break Next::Trouble;
                        }
                        // Unavailable (too large): the normal equations carry on.
                        lsq_failed = true;
                        mode = Mode::Normal;
                        continue;
                    }
                    lsq_used = true;
                    System::LeastSquares(ws.lsq.as_ref().expect("factorised above"))
                }
            };
            let switch = |d: &Direction| system.is_normal() && !lsq_failed && d.inaccurate;

            // Predictor (affine scaling, σ = 0).
            let pred = system.direction(&it, 0.0, None);
            if let Some(cert) = ray_certificate(problem, &y, &pred.dy, settings) {
                break Next::Ray(cert);
            }
            if switch(&pred) {
                mode = Mode::LeastSquares;
                continue;
            }
            let [ap, ad] = step_lengths(
                an,
                [
                    Side {
                        cur: &x,
                        linv: &f.linv_x,
                        d: &pred.dx,
                    },
                    Side {
                        cur: &s,
                        linv: &f.linv_s,
                        d: &pred.ds,
                    },
                ],
                gamma,
                Confirm::No,
            );
            let mu_pred = if an.nu > 0 {
                (res.xs
                    + ap * inner(&pred.dx, &s)
                    + ad * inner(&x, &pred.ds)
                    + ap * ad * inner(&pred.dx, &pred.ds))
                    / nu
            } else {
                0.0
            };
            // Mehrotra's centring with SDPT3's adaptive exponent.
            let step_pred = ap.min(ad);
            let expon = if mu > 1e-6 && step_pred >= 1.0 / 3f64.sqrt() {
                (3.0 * step_pred * step_pred).max(1.0)
            } else {
                1.0
            };
            let sigma = if mu_pred < 0.0 || mu <= 0.0 {
                0.8
            } else {
                (mu_pred / mu).powf(expon).min(1.0)
            };

            // Corrector with the second-order term ΔX_a ΔS_a.
            let Direction { dx, ds, .. } = pred;
            let corr = system.direction(&it, sigma * mu, Some((dx, ds)));
            if switch(&corr) {
                mode = Mode::LeastSquares;
                continue;
            }
            break Next::Step(corr, step_pred);
        };
        let (Direction { dx, dy, ds, .. }, step_pred) = match directions {
            Next::Step(d, step_pred) => (d, step_pred),
            Next::Ray(cert) => {
                certificate = Some(cert);
                break Status::PrimalInfeasible;
            }
            Next::Trouble => break Status::NumericalTrouble,
        };
        let gamma = settings.step_fraction.unwrap_or(0.9 + 0.09 * step_pred);
        let [ap, ad] = step_lengths(
            an,
            [
                Side {
                    cur: &x,
                    linv: &f.linv_x,
                    d: &dx,
                },
                Side {
                    cur: &s,
                    linv: &f.linv_s,
                    d: &ds,
                },
            ],
            gamma,
            Confirm::Yes,
        );
        // The factors and residuals of the current iterate are dead once the step lengths are
        // known: they go before the new point and its factors are formed.
        drop(f);
        drop(res);
        let Some([(ap, (xn, fxn)), (ad, (sn, fsn))]) = take_steps(an, (&x, &dx, ap), (&s, &ds, ad))
        else {
            break Status::NumericalTrouble;
        };
        let yn = y.iter().zip(&dy).map(|(yi, di)| yi + ad * di).collect();
        let (xo, yo, so) = (
            std::mem::replace(&mut x, xn),
            std::mem::replace(&mut y, yn),
            std::mem::replace(&mut s, sn),
        );
        if let Best::Current(merit) = best {
            best = Best::Earlier {
                merit,
                x: xo,
                y: yo,
                s: so,
            };
        }
        fx = Some(fxn);
        fs = Some(fsn);
        steps = (ap, ad);
        iteration += 1;
        tiny_steps = if ap.max(ad) < TINY_STEP {
            STALLED_STEPS
        } else if ap.min(ad) < TINY_STEP {
            tiny_steps + 1
        } else {
            0
        };
    };

    if !matches!(
        status,
        Status::Optimal | Status::PrimalInfeasible | Status::DualInfeasible | Status::Accepted
    ) && let Best::Earlier {
        x: bx,
        y: by,
        s: bs,
        ..
    } = best
    {
        x = bx;
        y = by;
        s = bs;
    }
    let res = residuals(an, vals, &cd, &norms, &x, &y, &s);
    let measures = measures(an, &norms, &res, &x, &s);
    // The rule of `Status`: an early stop at a point within the reduced tolerance in every
    // DIMACS error is almost optimal (a NaN maximum fails the comparison).
    let status = if status.is_failure() && measures.dimacs_max() <= settings.tol_reduced {
        Status::AlmostOptimal
    } else {
        status
    };
    Solution {
        status,
        x,
        y,
        s,
        primal_objective: res.pobj,
        dual_objective: res.dobj,
        iterations: iteration,
        measures,
        certificate,
        solve_time: started.elapsed(),
        facial: FacialPath::NotReduced,
        restarted: false,
    }
}
