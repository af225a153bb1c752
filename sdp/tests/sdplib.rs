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
//! * status `Optimal`, or `NumericalTrouble` with a point of reduced but bounded accuracy
//!   (the reference solvers also stop with "partial success"/`pFEAS` on these problems);
//! * an independent recomputation of the KKT conditions from the problem data (residuals,
//!   gap, smallest eigenvalues of `X` and `S`);
//! * infeasible problems (`infp*`, `infd*`): the right status and a certificate whose defect,
//!   recomputed here, is `≤ 1e-7`;
//! * at most 40 iterations.

mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use common::{dual_ray_defect, kkt, primal_ray_defect};
use sporadic_sdp::{Settings, Status, read_sdpa_file, sdpa_objectives, solve};

/// Problems of the default run: every problem of the issue-3 list except [`OPEN`] (about
/// 25 s in total in release mode).
const DEFAULT: &[&str] = &[
    "control1", "control2", "control3", "control4", "control5", "control6", "control7", "control8",
    "truss1", "truss2", "truss3", "truss4", "truss5", "truss6", "truss7", "truss8", "theta1",
    "theta2", "theta3", "theta4", "hinf1", "hinf2", "hinf3", "hinf4", "hinf5", "hinf6", "hinf7",
    "hinf8", "hinf9", "hinf10", "hinf11", "hinf14", "qap5", "qap6", "qap7", "qap8", "mcp100",
    "mcp124-1", "mcp124-2", "mcp124-3", "mcp124-4", "gpp100", "gpp124-1", "gpp124-2", "gpp124-3",
    "gpp124-4", "arch0", "ss30", "infp1", "infp2", "infd1", "infd2",
];

/// Problems on which the issue-3 goals are still open: hinf12 takes 51 iterations (> 40; CSDP
/// 6.2 takes 66), hinf13 and hinf15 end about 4 % below the README values 46 and 25 (CSDP
/// ends both with "partial success", dual objectives 44.75 and 24.38).
const OPEN: &[&str] = &["hinf12", "hinf13", "hinf15"];

const MAX_ITERATIONS: usize = 40;

/// What the README table says about a problem.
#[derive(Debug, Clone, Copy)]
enum Expected {
    /// Optimal value and the accepted absolute deviation.
    Value { value: f64, tol: f64 },
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
            Expected::Value { value, tol }
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

/// Largest relative infeasibility accepted for a `NumericalTrouble` point.
fn reduced_accuracy(name: &str) -> f64 {
    if name.starts_with("hinf") { 1e-4 } else { 1e-6 }
}

/// Solves one problem and returns a description of every failed check (empty = pass).
fn check(dir: &Path, refs: &HashMap<String, Expected>, name: &str) -> Vec<String> {
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
            format!(
                "{:.1e}",
                (obj.primal - value).abs() / value.abs().max(1e-300)
            ),
        ),
        Expected::SdpaPrimalInfeasible => ("p-infeas".into(), "-".into()),
        Expected::SdpaDualInfeasible => ("d-infeas".into(), "-".into()),
    };
    println!(
        "| {name:9} | {:+.9e} | {reference:>13} | {rel_err:>7} | {:3} | {time:7.3} | {:?} | gap {:.1e} pinf {:.1e} dinf {:.1e} |",
        obj.primal,
        sol.iterations,
        sol.status,
        k.gap.max(k.compl),
        k.pinf,
        k.dinf
    );
    if sol.iterations > MAX_ITERATIONS {
        fails.push(format!(
            "{name}: {} iterations > {MAX_ITERATIONS}",
            sol.iterations
        ));
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
            let limit = match sol.status {
                Status::Optimal => 2e-8,
                Status::NumericalTrouble => reduced_accuracy(name),
                other => {
                    fails.push(format!("{name}: status {other:?}"));
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
            if k.min_eig_x < -1e-10 || k.min_eig_s < -1e-10 {
                fails.push(format!(
                    "{name}: X or S not PSD (relative λ_min {:.1e}, {:.1e})",
                    k.min_eig_x, k.min_eig_s
                ));
            }
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

fn run(names: &[&str]) {
    let Some(dir) = sdplib_dir() else { return };
    let refs = references(&dir);
    println!(
        "| problem | SDPA objective (ours) | reference | rel err | it | time s | status | recomputed |"
    );
    let fails: Vec<String> = names.iter().flat_map(|n| check(&dir, &refs, n)).collect();
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

#[test]
fn sdplib_default() {
    run(DEFAULT);
}

#[test]
#[ignore = "known open in issue 3 (see OPEN); run, not gating, by .ci/run: cargo test --release -p sporadic-sdp --test sdplib -- --ignored"]
fn sdplib_open() {
    run(OPEN);
}
