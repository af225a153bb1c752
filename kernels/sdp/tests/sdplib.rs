//! SDPLIB regression tests (Borchers, "SDPLIB 1.2", Optim. Methods Softw. 11, 1999).
//!
//! The problems are read from the directory named by the environment variable
//! `SPORADIC_SDPLIB` (CI sets it to `../shared/sdplib`). Expected optimal values are parsed at
//! run time from that directory's `README-SDPLIB.md` table (SDPA sign convention, compared with
//! [`sdpa_objectives`]); nothing is taken from the solver under test.
//!
//! Acceptance, per problem:
//! * feasible problems: both SDPA objectives within `1e-6` relative of the table value when it is
//!   printed with at least 7 significant digits, otherwise within one unit of its last printed
//!   digit (`hinf12`: the printed `2e-1` is known to be wrong — CSDP finds `2.1e-5`, see
//!   `shared/notes/sdp-solvers.md` §2.4 — so `|objective| ≤ 5e-4` is required instead);
//! * `hinf13`, `hinf15` ([`CERTIFIED`]): the printed `4.6e+01` and `2.5e+01` are wrong. In the
//!   SDPA convention (min `cᵀx` s.t. `F(x) = Σ x_i F_i − F_0 ⪰ 0`) every feasible `x` bounds the
//!   optimum from above. The test solves the problem with the margin `F(x) ⪰ εI`
//!   ([`MARGIN`]) and verifies that point on the data alone ([`certify`]: compensated
//!   evaluation of `F(x)`, smallest eigenvalue and a shifted Cholesky factorisation clearing a
//!   rounding bound ten times over). Its objective, an upper bound on the optimum (on this box
//!   hinf13 44.42, hinf15 24.08, see [`CERTIFYING_ITERATIONS`]), must lie below the rounding
//!   interval of the printed value (above 45.5 and 24.5: half a unit of the last printed
//!   digit); our primal and dual SDPA objectives must lie below that bound and agree within [`CERTIFIED_GAP`] (CSDP
//!   6.2 ends both with "partial success" at dual objectives 44.75 and 24.38; SDPA 7.3 reports
//!   them infeasible). No lower bound is asserted: the SDPA-primal iterates grow along a ray
//!   (the terms of `F(x)` reach about `5·10⁸` while `F(x)` stays `O(1)`), so a dual point's
//!   equality residual cannot be charged against a norm bound on `x`;
//! * the status rule of [`Status`], checked against an independent recomputation of the six
//!   DIMACS errors: `Optimal`, or `AlmostOptimal` with every DIMACS error within `1e-6`;
//!   `NumericalTrouble` only on the problems listed in [`NOT_SOLVED`] and only at a point outside
//!   the reduced tolerance (the reference solvers also stop with "partial success"/`pFEAS` on
//!   these problems);
//! * an independent recomputation of the KKT conditions from the problem data (residuals,
//!   gap, smallest eigenvalues of `X` and `S`);
//! * infeasible problems (`infp*`, `infd*`): the right status and a certificate whose defect,
//!   recomputed here, is `≤ 1e-7`;
//! * at most 40 iterations, except the problems listed in [`OPEN`] with their own cap.

mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use common::{dual_ray_defect, eig_range, kkt, primal_ray_defect};
use faer::Mat;
use sporadic_linalg::is_positive_definite;
use sporadic_sdp::{
    BlockKind, Problem, ProblemBuilder, Settings, Solution, Status, read_sdpa_file,
    sdpa_objectives, solve,
};

/// Problems of the default run: every problem of the issue-3 list (about 25 s in total in
/// release mode).
const DEFAULT: &[&str] = &[
    "control1", "control2", "control3", "control4", "control5", "control6", "control7", "control8",
    "truss1", "truss2", "truss3", "truss4", "truss5", "truss6", "truss7", "truss8", "theta1",
    "theta2", "theta3", "theta4", "hinf1", "hinf2", "hinf3", "hinf4", "hinf5", "hinf6", "hinf7",
    "hinf8", "hinf9", "hinf10", "hinf11", "hinf12", "hinf14", "qap5", "qap6", "qap7", "qap8",
    "mcp100", "mcp124-1", "mcp124-2", "mcp124-3", "mcp124-4", "gpp100", "gpp124-1", "gpp124-2",
    "gpp124-3", "gpp124-4", "arch0", "ss30", "infp1", "infp2", "infd1", "infd2", "hinf13",
    "hinf15",
];

/// Problems that miss the issue-3 cap of [`MAX_ITERATIONS`], with the cap the default run
/// holds them to instead. hinf12 takes 56 iterations: its SDPA-primal optimum is not attained
/// (`‖x‖` reaches about `1e9` while the objective falls only linearly, by about 0.6 per
/// iteration, towards `0`), and neither reference meets the cap either (CSDP 6.2 takes 65
/// iterations and stops at a relative gap of 1e-5; SDPA 7 stops after 21 with `pFEAS` and
/// objectives 3.4 and 26.3). hinf10 (42), hinf11 (41), hinf13 (50), hinf14 (46) and
/// hinf15 (50) follow a diverging dual ray (`‖y‖ ~ 1/μ`, paired eigenvalues of `X` shrinking
/// like `μ²`), along which the steps stay near 0.55 and the merit falls only about ×0.68 per
/// iteration from `μ ≈ 1` on; until the least-squares solve regularised its dependent
/// constraints (issue 23) they stopped `NumericalTrouble` at 35–39 iterations when that solve
/// broke down, outside the reduced tolerance. [`sdplib_open`] keeps the cap on all of
/// them as a reported, non-gating test.
const OPEN: &[(&str, usize)] = &[
    ("hinf10", 45),
    ("hinf11", 45),
    ("hinf12", 60),
    ("hinf13", 55),
    ("hinf14", 50),
    ("hinf15", 55),
];

/// Problems whose printed README value is replaced by a certified upper bound (module docs).
const CERTIFIED: &[&str] = &["hinf13", "hinf15"];

/// Margin `ε` of the certifying solve `F(x) ⪰ εI`: far above the dual infeasibility of our
/// solutions (about `1e-9` relative), small enough to cost little objective (about `0.06` on
/// hinf13 and `0.1` on hinf15).
const MARGIN: f64 = 1e-5;

/// Iteration limit of the certifying solve. Past about 35 iterations its iterates follow the
/// diverging dual ray of these problems (`‖y‖ ~ 1/μ`), and the rounding of `C − 𝒜ᵀ(y)`, about
/// `ε ‖A‖ ‖y‖`, outgrows [`MARGIN`]: the point of a solve run to its end (about 50 iterations
/// since the least-squares solve no longer breaks down, issue 23) is not verified, at 40
/// iterations neither. At 30 the point is verified with `λ_min F(x) ≈ 1.0e-5`, far above the
/// rounding bound (`≤ 3.3e-7`), and bounds hinf13 by 44.42 and hinf15 by 24.08.
const CERTIFYING_ITERATIONS: usize = 30;

/// Accepted relative gap `|p − d| / (1 + |p| + |d|)` between our SDPA objectives on the
/// [`CERTIFIED`] problems (the reduced accuracy of these ill-posed problems).
const CERTIFIED_GAP: f64 = 1e-3;

const MAX_ITERATIONS: usize = 40;

/// What the README table says about a problem.
#[derive(Debug, Clone, Copy)]
enum Expected {
    /// Optimal value and the accepted absolute deviation.
    Value { value: f64, tol: f64 },
    /// The printed value and one unit of its last digit, refuted by a certified feasible point; see
    /// [`CERTIFIED`].
    CertifiedBelow { printed: f64, tol: f64 },
    /// SDPA-primal infeasible (`infp*`): our (D) is infeasible.
    SdpaPrimalInfeasible,
    /// SDPA-dual infeasible (`infd*`): our (P) is infeasible.
    SdpaDualInfeasible,
}

/// Tolerance implied by a printed value: `1e-6` relative with ≥ 7 significant digits, else one
/// unit of the last printed digit.
fn printed_tolerance(text: &str) -> Option<(f64, f64)> {
    let value: f64 = text.parse().ok()?;
    let mantissa = text.split(['e', 'E']).next()?;
    let digits = mantissa.chars().filter(|c| c.is_ascii_digit()).count();
    let leading_zeros = mantissa
        .chars()
        .filter(|c| c.is_ascii_digit())
        .take_while(|&c| c == '0')
        .count();
    let significant = digits - leading_zeros.min(digits.saturating_sub(1));
    if significant >= 7 {
        return Some((value, 1e-6 * value.abs()));
    }
    let decimals = mantissa.split('.').nth(1).map_or(0, str::len) as i32;
    let exponent: i32 = text
        .split(['e', 'E'])
        .nth(1)
        .map_or(Some(0), |e| e.parse().ok())?;
    Some((value, 10f64.powi(exponent - decimals)))
}

fn references(dir: &Path) -> HashMap<String, Expected> {
    let readme = std::fs::read_to_string(dir.join("README-SDPLIB.md"))
        .expect("README-SDPLIB.md in the SDPLIB directory");
    let mut out = HashMap::new();
    for line in readme.lines() {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        if cells.len() < 6 || cells[1].is_empty() || cells[2].parse::<usize>().is_err() {
            continue;
        }
        let (name, value) = (cells[1], cells[4]);
        let expected = if value == "primal infeasible" {
            Expected::SdpaPrimalInfeasible
        } else if value == "dual infeasible" {
            Expected::SdpaDualInfeasible
        } else if name == "hinf12" {
            Expected::Value {
                value: 0.0,
                tol: 5e-4,
            }
        } else if let Some((value, tol)) = printed_tolerance(value) {
            if CERTIFIED.contains(&name) {
                Expected::CertifiedBelow {
                    printed: value,
                    tol,
                }
            } else {
                Expected::Value { value, tol }
            }
        } else {
            continue;
        };
        out.insert(name.to_string(), expected);
    }
    out
}

fn sdplib_dir() -> Option<PathBuf> {
    match std::env::var_os("SPORADIC_SDPLIB") {
        Some(d) => Some(PathBuf::from(d)),
        None => {
            eprintln!(
                "SDPLIB tests SKIPPED: the environment variable SPORADIC_SDPLIB is not set \
                 (point it at the SDPLIB directory, e.g. SPORADIC_SDPLIB=/work/shared/sdplib; \
                 CI sets ../shared/sdplib)"
            );
            None
        }
    }
}

/// Reduced tolerance of [`Status::AlmostOptimal`] (the default `Settings::tol_reduced`).
const REDUCED: f64 = 1e-6;

/// Relative slack for comparing the solver's DIMACS errors with the independent dense
/// recomputation of `common::dimacs` (different summation orders and eigenvalue solvers).
const RECOMPUTED_SLACK: f64 = 1e-3;

/// Problems on which the solver stops early at a point *outside* the reduced tolerance: status
/// `NumericalTrouble` is accepted for them (an improvement to `Optimal`/`AlmostOptimal` is too),
/// with recomputed relative infeasibilities up to the given bound. On this box (largest DIMACS
/// error, always the relative gap): hinf12 3.0e-5 (no attained optimum); hinf13 and hinf15
/// (printed values known to be wrong, see [`CERTIFIED`]) end `AlmostOptimal` at 4.3e-7 and
/// 9.9e-7, too close to the reduced tolerance to require it. The reference solvers also stop short on these (CSDP "partial success",
/// SDPA `pFEAS`). Every other feasible problem must end
/// `Optimal` or `AlmostOptimal`; hinf10, hinf11, hinf14 and qap6–8 did not before the
/// least-squares solve regularised its dependent constraints (issue 23, see
/// [`end_game_dependent_constraints`]).
const NOT_SOLVED: &[(&str, f64)] = &[("hinf12", 1e-4), ("hinf13", 1e-4), ("hinf15", 1e-4)];

/// Problems that must end `Optimal`, not merely `AlmostOptimal`: the graph-partitioning problems,
/// whose constraint `⟨eeᵀ, X⟩ = 0` leaves the primal without a strictly feasible point. Their
/// iterates followed the diverging dual ray `y_i → −∞` and stopped `AlmostOptimal` (gap about
/// 1.5e-8 on gpp100, gpp124-1, gpp124-4) until facial reduction solved them on the face
/// `X e = 0` (issue 23).
const MUST_BE_OPTIMAL: &[&str] = &["gpp100", "gpp124-1", "gpp124-2", "gpp124-3", "gpp124-4"];

/// Solves one problem and returns a description of every failed check (empty = pass).
fn check(dir: &Path, refs: &HashMap<String, Expected>, name: &str, cap: usize) -> Vec<String> {
    let mut fails = Vec::new();
    let Some(&expected) = refs.get(name) else {
        return vec![format!("{name}: no reference value in README-SDPLIB.md")];
    };
    let problem = read_sdpa_file(dir.join(format!("{name}.dat-s"))).expect("readable SDPLIB file");
    let t = Instant::now();
    let sol = solve(&problem, &Settings::default()).expect("solvable");
    let time = t.elapsed().as_secs_f64();
    let obj = sdpa_objectives(&sol);
    let k = kkt(&problem, &sol);
    let (reference, rel_err) = match expected {
        Expected::Value { value, .. } => (
            format!("{value:.6e}"),
            if value == 0.0 {
                "-".into()
            } else {
                format!("{:.1e}", (obj.primal - value).abs() / value.abs())
            },
        ),
        Expected::CertifiedBelow { printed, .. } => (format!("<{printed:.6e}"), "-".into()),
        Expected::SdpaPrimalInfeasible => ("p-infeas".into(), "-".into()),
        Expected::SdpaDualInfeasible => ("d-infeas".into(), "-".into()),
    };
    println!(
        "| {name:9} | {:+.9e} | {reference:>13} | {rel_err:>7} | {:3} | {time:7.3} | {:?} | gap {:.1e} pinf {:.1e} dinf {:.1e} | DIMACS max {:.1e} |",
        obj.primal,
        sol.iterations,
        sol.status,
        k.gap.max(k.compl),
        k.pinf,
        k.dinf,
        sol.measures.dimacs_max()
    );
    if sol.iterations > cap {
        fails.push(format!("{name}: {} iterations > {cap}", sol.iterations));
    }
    match expected {
        Expected::Value { value, tol } => {
            for (which, o) in [("primal", obj.primal), ("dual", obj.dual)] {
                if (o - value).abs() > tol {
                    fails.push(format!(
                        "{name}: SDPA {which} objective {o:.9e} differs from {value:e} by more than {tol:e}"
                    ));
                }
            }
            check_point(name, &problem, &sol, &k, &mut fails);
        }
        Expected::CertifiedBelow { printed, tol } => {
            let settings = Settings {
                max_iterations: CERTIFYING_ITERATIONS,
                ..Settings::default()
            };
            let margin =
                solve(&with_margin(&problem, MARGIN), &settings).expect("solvable with a margin");
            match certify(&problem, &margin.y) {
                None => fails.push(format!(
                    "{name}: the margin-{MARGIN:e} point is not verified strictly feasible"
                )),
                Some(c) => {
                    println!(
                        "|           | certified upper bound {:.9e} (λ_min F(x) {:.2e}, safety {:.2e}) |",
                        c.objective, c.min_eig, c.safety
                    );
                    // The printed digits stand for [printed − tol/2, printed + tol/2).
                    if c.objective >= printed - 0.5 * tol {
                        fails.push(format!(
                            "{name}: certified bound {:.9e} does not refute the printed {printed:e}",
                            c.objective
                        ));
                    }
                    for (which, o) in [("primal", obj.primal), ("dual", obj.dual)] {
                        if o > c.objective {
                            fails.push(format!(
                                "{name}: SDPA {which} objective {o:.9e} above the certified upper bound {:.9e}",
                                c.objective
                            ));
                        }
                    }
                }
            }
            let gap = (obj.primal - obj.dual).abs() / (1.0 + obj.primal.abs() + obj.dual.abs());
            if gap > CERTIFIED_GAP {
                fails.push(format!(
                    "{name}: SDPA objectives {:.9e}/{:.9e} differ by {gap:.1e} relative",
                    obj.primal, obj.dual
                ));
            }
            check_point(name, &problem, &sol, &k, &mut fails);
        }
        Expected::SdpaPrimalInfeasible => {
            // The LMI Σ x_i F_i − F_0 ⪰ 0 is infeasible: our (D) is infeasible.
            if sol.status != Status::DualInfeasible {
                fails.push(format!(
                    "{name}: status {:?}, expected DualInfeasible",
                    sol.status
                ));
            }
            match &sol.certificate {
                Some(sporadic_sdp::InfeasibilityCertificate::DualInfeasibility { x, .. }) => {
                    let d = dual_ray_defect(&problem, x);
                    if d > 1e-7 {
                        fails.push(format!("{name}: certificate defect {d:.1e}"));
                    }
                }
                other => fails.push(format!("{name}: certificate {other:?}")),
            }
        }
        Expected::SdpaDualInfeasible => {
            if sol.status != Status::PrimalInfeasible {
                fails.push(format!(
                    "{name}: status {:?}, expected PrimalInfeasible",
                    sol.status
                ));
            }
            match &sol.certificate {
                Some(sporadic_sdp::InfeasibilityCertificate::PrimalInfeasibility { y, .. }) => {
                    let d = primal_ray_defect(&problem, y);
                    if d > 1e-7 {
                        fails.push(format!("{name}: certificate defect {d:.1e}"));
                    }
                }
                other => fails.push(format!("{name}: certificate {other:?}")),
            }
        }
    }
    fails
}

/// The status, infeasibility and cone checks shared by every feasible problem.
///
/// The status must follow the rule documented at [`Status`], checked against an independent
/// recomputation of the six DIMACS errors: `Optimal` meets `1e-8` (up to recomputation), a
/// point within [`REDUCED`] in every DIMACS error is `Optimal` or `AlmostOptimal` (never
/// `NumericalTrouble`), `AlmostOptimal` is within [`REDUCED`], and only the problems of
/// [`NOT_SOLVED`] may end `NumericalTrouble`.
fn check_point(
    name: &str,
    problem: &Problem,
    sol: &Solution,
    k: &common::Kkt,
    fails: &mut Vec<String>,
) {
    let d = common::dimacs(problem, &sol.y, &sol.x, &sol.s);
    let dmax = common::dimacs_max(&d);
    let reported = sol.measures.dimacs_max();
    if (dmax - reported).abs() > RECOMPUTED_SLACK * dmax.max(1e-12) {
        fails.push(format!(
            "{name}: reported largest DIMACS error {reported:.3e}, recomputed {dmax:.3e}"
        ));
    }
    if MUST_BE_OPTIMAL.contains(&name) && sol.status != Status::Optimal {
        fails.push(format!(
            "{name}: status {:?} (largest DIMACS error {dmax:.2e}), expected Optimal",
            sol.status
        ));
    }
    let not_solved = NOT_SOLVED.iter().find(|(n, _)| *n == name).map(|&(_, b)| b);
    let limit = match (sol.status, not_solved) {
        (Status::Optimal, _) => 2e-8,
        (Status::AlmostOptimal, _) => {
            if dmax > REDUCED * (1.0 + RECOMPUTED_SLACK) {
                fails.push(format!(
                    "{name}: AlmostOptimal but the recomputed largest DIMACS error is {dmax:.2e}"
                ));
            }
            REDUCED
        }
        (Status::NumericalTrouble, Some(bound)) => {
            if dmax <= REDUCED * (1.0 - RECOMPUTED_SLACK) {
                fails.push(format!(
                    "{name}: NumericalTrouble although every DIMACS error is within {REDUCED:e} \
                     (largest {dmax:.2e}): must be AlmostOptimal"
                ));
            }
            bound
        }
        (other, _) => {
            fails.push(format!(
                "{name}: status {other:?} (largest DIMACS error {dmax:.2e}), expected Optimal or \
                 AlmostOptimal"
            ));
            0.0
        }
    };
    if k.pinf > limit || k.dinf > limit {
        fails.push(format!(
            "{name}: recomputed infeasibilities {:.1e}/{:.1e} above {limit:e}",
            k.pinf, k.dinf
        ));
    }
    if sol.status == Status::Optimal && k.gap.max(k.compl) > 2e-8 {
        fails.push(format!(
            "{name}: recomputed gap {:.1e} too large",
            k.gap.max(k.compl)
        ));
    }
    if sol.status == Status::AlmostOptimal
        && k.gap.max(k.compl) > REDUCED * (1.0 + RECOMPUTED_SLACK)
    {
        fails.push(format!(
            "{name}: recomputed gap {:.1e} above the reduced tolerance",
            k.gap.max(k.compl)
        ));
    }
    if k.min_eig_x < -1e-10 || k.min_eig_s < -1e-10 {
        fails.push(format!(
            "{name}: X or S not PSD (relative λ_min {:.1e}, {:.1e})",
            k.min_eig_x, k.min_eig_s
        ));
    }
}

/// Solves and checks `names`, each held to the iteration cap `cap(name)`.
fn run(names: &[&str], cap: impl Fn(&str) -> usize) {
    let Some(dir) = sdplib_dir() else { return };
    let refs = references(&dir);
    println!(
        "| problem | SDPA objective (ours) | reference | rel err | it | time s | status | recomputed | solver |"
    );
    let fails: Vec<String> = names
        .iter()
        .flat_map(|n| check(&dir, &refs, n, cap(n)))
        .collect();
    assert!(fails.is_empty(), "SDPLIB failures:\n{}", fails.join("\n"));
}

#[test]
fn printed_tolerance_rule() {
    assert_eq!(
        printed_tolerance("1.778463e+01"),
        Some((17.78463, 1e-6 * 17.78463))
    );
    let (v, t) = printed_tolerance("5.69e+01").unwrap();
    assert_eq!(v, 56.9);
    assert!((t - 0.1).abs() < 1e-15);
    // −436.0: four significant digits, the last one is the first decimal.
    let (_, t) = printed_tolerance("-4.360e+02").unwrap();
    assert!((t - 0.1).abs() < 1e-12);
    let (_, t) = printed_tolerance("2.3625e+02").unwrap();
    assert!((t - 0.01).abs() < 1e-15);
}

/// The iteration cap of the default run: [`MAX_ITERATIONS`], or the problem's own in [`OPEN`].
fn cap(name: &str) -> usize {
    OPEN.iter()
        .find(|(open, _)| *open == name)
        .map_or(MAX_ITERATIONS, |&(_, cap)| cap)
}

#[test]
fn sdplib_default() {
    run(DEFAULT, cap);
}

/// The problems whose least-squares solve broke down at numerically dependent constraints
/// (Δy of 1e128 from floored QR pivots) and ended `NumericalTrouble` outside the reduced
/// tolerance: hinf10 (2.9e-6), hinf11 (2.0e-6), hinf14 (1.1e-6), qap6 (1.1e-6). They must now
/// end `Optimal` or `AlmostOptimal` with the SDPLIB objective (the fast ones of issue 23's
/// list; qap7 and qap8, 1–5 s each, are checked by [`sdplib_default`] alone).
#[test]
fn end_game_dependent_constraints() {
    run(&["hinf10", "hinf11", "hinf14", "qap6"], cap);
}

/// The whole solve, including the Householder QR of the least-squares form that gpp250-1
/// switches to (m = 251) when it is solved without facial reduction (on its face it does not
/// need that form), gives the same bits on one and on two threads: faer's parallel QR gave 17
/// iterations on two threads and 19 on one before the dense factorisations were made
/// sequential (issue 23).
#[test]
fn thread_count_does_not_change_bits_least_squares() {
    let Some(dir) = sdplib_dir() else { return };
    let problem = read_sdpa_file(dir.join("gpp250-1.dat-s")).expect("gpp250-1");
    let runs: Vec<Solution> = [1, 2]
        .iter()
        .map(|&threads| {
            let settings = Settings {
                threads,
                facial_reduction: false,
                ..Settings::default()
            };
            solve(&problem, &settings).expect("solve")
        })
        .collect();
    assert_eq!(runs[0].iterations, runs[1].iterations);
    assert_eq!(runs[0].y, runs[1].y);
    assert_eq!(runs[0].x, runs[1].x);
}

#[test]
#[ignore = "the issue-3 cap of 40 iterations, unmet on hinf10–15 (see OPEN); run, not gating, by .ci/run: cargo test --workspace --release --test sdplib -- --ignored sdplib_open"]
fn sdplib_open() {
    let names: Vec<&str> = OPEN.iter().map(|&(name, _)| name).collect();
    run(&names, |_| MAX_ITERATIONS);
}

/// `problem` with `C` replaced by `C − εI` (every PSD and LP block): a dual-feasible `y` of it
/// satisfies `C − 𝒜ᵀ(y) ⪰ εI`, i.e. the SDPA point `x = y` has `F(x) ⪰ εI`.
fn with_margin(problem: &Problem, eps: f64) -> Problem {
    let mut builder = ProblemBuilder::new(problem.b.len());
    for (i, &bi) in problem.b.iter().enumerate() {
        builder.set_b(i, bi);
    }
    for (k, bd) in problem.blocks.iter().enumerate() {
        builder.add_block(bd.block.kind, bd.block.size);
        for (i, j, v) in bd.c.iter() {
            builder.add_c(k, i, j, v);
        }
        for d in 0..bd.block.size {
            builder.add_c(k, d, d, -eps);
        }
        for (con, a) in &bd.a {
            for (i, j, v) in a.iter() {
                builder.add_a(*con, k, i, j, v);
            }
        }
    }
    builder.build().expect("same data plus a diagonal shift")
}

/// An SDPA-primal point verified strictly feasible in floating point.
#[derive(Debug, Clone, Copy)]
struct Certified {
    /// `cᵀx` rounded up by a bound on its summation error: an upper bound on the optimum.
    objective: f64,
    /// Smallest computed eigenvalue of `F(x)` over the blocks.
    min_eig: f64,
    /// Largest per-block safety margin `δ` that the smallest eigenvalue had to clear (twice).
    safety: f64,
}

/// `F(x) = C − Σ y_i A_i` of block `k` (`x = y`) by compensated summation (Ogita, Rump, Oishi,
/// "Accurate sum and dot product", SIAM J. Sci. Comput. 26(6), 2005, Algorithm Dot2: error
/// `≤ u|F| + γ²_{2m+2} Σ|terms|` per entry), together with the Frobenius norm of the
/// entrywise sums of absolute terms `Σ|terms|`.
fn slack_block(problem: &Problem, k: usize, y: &[f64]) -> (Mat<f64>, f64) {
    let bd = &problem.blocks[k];
    let n = bd.block.size;
    let cols = if bd.block.kind == BlockKind::Psd {
        n
    } else {
        1
    };
    let mut sum = Mat::<f64>::zeros(n, cols);
    let mut comp = Mat::<f64>::zeros(n, cols);
    let mut abs = Mat::<f64>::zeros(n, cols);
    let mut add = |i: usize, j: usize, a: f64, b: f64| {
        let (i, j) = if cols == 1 { (i, 0) } else { (i, j) };
        let p = a * b;
        let e = a.mul_add(b, -p);
        let s = sum[(i, j)] + p;
        let z = s - sum[(i, j)];
        let t = (sum[(i, j)] - (s - z)) + (p - z);
        sum[(i, j)] = s;
        comp[(i, j)] += t + e;
        abs[(i, j)] += p.abs();
    };
    for (i, j, v) in bd.c.iter() {
        add(i, j, v, 1.0);
    }
    for (con, a) in &bd.a {
        for (i, j, v) in a.iter() {
            add(i, j, v, -y[*con]);
        }
    }
    let mut f = Mat::<f64>::zeros(n, cols);
    let mut scale = 0.0;
    for j in 0..cols {
        for i in 0..n {
            f[(i, j)] = sum[(i, j)] + comp[(i, j)];
            scale += abs[(i, j)] * abs[(i, j)];
        }
    }
    if cols > 1 {
        for j in 0..n {
            for i in 0..j {
                f[(j, i)] = f[(i, j)];
                scale += abs[(i, j)] * abs[(i, j)];
            }
        }
    }
    (f, scale.sqrt())
}

/// Checks that `F(x) = Σ x_i F_i − F_0 = C − Σ y_i A_i` (SDPA point `x = y`) is positive
/// definite with a margin far above rounding, block by block from the problem data.
///
/// Per block, `δ = 10·(2u·s + γ²_{2m+2}·s + (4n + 1)·u·‖F‖_F)` with `s` the norm of the
/// absolute terms: it bounds, ten times over, the decimal-to-binary rounding of the data
/// (`u` per term), the compensated evaluation of `F` ([`slack_block`]) and the backward error of
/// the eigenvalue solver and of a Cholesky factorisation (`O(n·u·‖F‖)`). The block passes if its
/// computed smallest eigenvalue exceeds `2δ` and `F − δI` has a Cholesky factorisation.
fn certify(problem: &Problem, y: &[f64]) -> Option<Certified> {
    let u = f64::EPSILON / 2.0;
    let m = problem.b.len() as f64;
    let gamma = (2.0 * m + 2.0) * u / (1.0 - (2.0 * m + 2.0) * u);
    let (mut min_eig, mut safety) = (f64::INFINITY, 0.0f64);
    for (k, bd) in problem.blocks.iter().enumerate() {
        let (f, s) = slack_block(problem, k, y);
        let n = bd.block.size as f64;
        let delta = 10.0 * (2.0 * u * s + gamma * gamma * s + (4.0 * n + 1.0) * u * f.norm_l2());
        let lam = eig_range(bd.block.kind, &f).0;
        // An LP block's smallest entry is `lam` itself, so `lam > 2δ` already decides it.
        let shifted_ok = match bd.block.kind {
            BlockKind::Lp => true,
            BlockKind::Psd => is_positive_definite(f.as_ref(), delta).unwrap_or(false),
        };
        if !(lam > 2.0 * delta && shifted_ok) {
            return None;
        }
        min_eig = min_eig.min(lam);
        safety = safety.max(delta);
    }
    let terms: Vec<f64> = problem.b.iter().zip(y).map(|(b, v)| -b * v).collect();
    let sum: f64 = terms.iter().sum();
    let err = 2.0 * (m + 1.0) * u * terms.iter().map(|t| t.abs()).sum::<f64>();
    Some(Certified {
        objective: sum + err,
        min_eig,
        safety,
    })
}
