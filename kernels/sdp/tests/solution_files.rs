//! Solutions out and in: CSDP-format solution files of SDPLIB problems, the DIMACS errors of
//! any given point, and warm starts from a written solution.
//!
//! The SDPLIB problems are read from the directory named by `SPORADIC_SDPLIB` (skipped with a
//! message when it is unset); the dimension checks run on a small built-in problem.

mod common;

use std::path::PathBuf;

use common::{dimacs, dimacs_max};
use faer::Mat;
use sporadic_sdp::{
    BlockKind, Point, ProblemBuilder, SdpError, Settings, Solver, Status, dimacs_errors,
    read_sdpa_file, read_solution, solve, solve_from, write_solution,
};

fn sdplib_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("SPORADIC_SDPLIB").map(PathBuf::from);
    if dir.is_none() {
        eprintln!(
            "solution-file SDPLIB tests SKIPPED: the environment variable SPORADIC_SDPLIB is not \
             set (point it at the SDPLIB directory, e.g. SPORADIC_SDPLIB=/work/shared/sdplib)"
        );
    }
    dir
}

/// Problems with PSD blocks only (control1, theta1), PSD and LP blocks (truss1: LP blocks of
/// size 1 among PSD ones) and a reduced-accuracy end (hinf1).
const PROBLEMS: &[&str] = &["control1", "theta1", "truss1", "hinf1"];

#[test]
fn written_sdplib_solutions_round_trip_and_pass_the_dimacs_check() {
    let Some(dir) = sdplib_dir() else { return };
    for name in PROBLEMS {
        let problem = read_sdpa_file(dir.join(format!("{name}.dat-s"))).unwrap();
        let sol = solve(&problem, &Settings::default()).unwrap();
        assert!(sol.status.is_solved(), "{name}: {:?}", sol.status);
        let text = write_solution(&sol.y, &sol.x, &sol.s);
        let back = read_solution(&text, &problem).unwrap();
        assert_eq!(back, sol.point(), "{name}: the point changed on the way");
        let d = dimacs_errors(&problem, &back.y, &back.x, &back.s).unwrap();
        assert_eq!(d, sol.measures.dimacs, "{name}");
        let ind = dimacs(&problem, &back.y, &back.x, &back.s);
        let (dm, im) = (dimacs_max(&d), dimacs_max(&ind));
        assert!(
            (dm - im).abs() <= 1e-3 * im.max(1e-12),
            "{name}: {d:?} vs {ind:?}"
        );
        let bound = if sol.status == Status::Optimal {
            1e-7
        } else {
            1e-6
        };
        assert!(dm <= bound, "{name}: DIMACS errors {d:?}");
    }
}

#[test]
fn warm_start_from_a_written_optimum_stops_at_once() {
    let Some(dir) = sdplib_dir() else { return };
    for name in ["control1", "theta1", "truss1"] {
        let problem = read_sdpa_file(dir.join(format!("{name}.dat-s"))).unwrap();
        let cold = solve(&problem, &Settings::default()).unwrap();
        assert_eq!(cold.status, Status::Optimal, "{name}");
        let start = read_solution(&write_solution(&cold.y, &cold.x, &cold.s), &problem).unwrap();
        let warm = solve_from(&problem, &Settings::default(), &start).unwrap();
        assert_eq!(warm.status, Status::Optimal, "{name}");
        assert!(
            warm.iterations == 0,
            "{name}: {} warm iterations ({} cold)",
            warm.iterations,
            cold.iterations
        );
        let rel =
            (warm.dual_objective - cold.dual_objective).abs() / (1.0 + cold.dual_objective.abs());
        assert!(rel <= 1e-8, "{name}: {rel:e}");
    }
}

/// A solution written at a loose tolerance (1e-4) is refined to the default one from where it
/// stopped, in fewer iterations than a cold solve.
#[test]
fn warm_start_from_a_loose_solution_refines_it() {
    let Some(dir) = sdplib_dir() else { return };
    let loose = Settings {
        tol_gap: 1e-4,
        tol_feas: 1e-4,
        ..Settings::default()
    };
    for name in ["control1", "theta1", "truss1"] {
        let problem = read_sdpa_file(dir.join(format!("{name}.dat-s"))).unwrap();
        let cold = solve(&problem, &Settings::default()).unwrap();
        let first = solve(&problem, &loose).unwrap();
        assert_eq!(first.status, Status::Optimal, "{name}");
        let start = read_solution(&write_solution(&first.y, &first.x, &first.s), &problem).unwrap();
        let warm = solve_from(&problem, &Settings::default(), &start).unwrap();
        assert_eq!(warm.status, Status::Optimal, "{name}");
        eprintln!(
            "{name}: cold {} iterations, loose {} + warm {}",
            cold.iterations, first.iterations, warm.iterations
        );
        assert!(
            warm.iterations > 0 && warm.iterations < cold.iterations,
            "{name}"
        );
        let rel =
            (warm.dual_objective - cold.dual_objective).abs() / (1.0 + cold.dual_objective.abs());
        assert!(rel <= 1e-7, "{name}: {rel:e}");
    }
}

/// A start outside the cone (`X = −I`, `S = 0`) is shifted into the interior (to the default
/// starting levels), and the solve still converges.
#[test]
fn a_start_outside_the_cone_is_shifted_inside() {
    let Some(dir) = sdplib_dir() else { return };
    let problem = read_sdpa_file(dir.join("truss1.dat-s")).unwrap();
    let cold = solve(&problem, &Settings::default()).unwrap();
    let mut start = cold.point();
    for m in &mut start.x {
        *m = Mat::from_fn(m.nrows(), m.ncols(), |i, j| {
            if i == j || m.ncols() == 1 { -1.0 } else { 0.0 }
        });
    }
    for m in &mut start.s {
        *m = Mat::zeros(m.nrows(), m.ncols());
    }
    let sol = solve_from(&problem, &Settings::default(), &start).unwrap();
    assert_eq!(sol.status, Status::Optimal, "{:?}", sol.measures);
    let rel = (sol.dual_objective - cold.dual_objective).abs() / (1.0 + cold.dual_objective.abs());
    assert!(rel <= 1e-7, "{rel:e}");
}

/// One PSD block of order 2 and one LP block of length 3, m = 2.
fn small() -> sporadic_sdp::Problem {
    let mut pb = ProblemBuilder::new(2);
    let p = pb.add_block(BlockKind::Psd, 2);
    let l = pb.add_block(BlockKind::Lp, 3);
    pb.set_b(0, 1.0).set_b(1, 1.0);
    pb.add_a(0, p, 0, 0, 1.0).add_a(0, p, 1, 1, 1.0);
    pb.add_a(1, l, 0, 0, 1.0).add_a(1, l, 2, 2, 1.0);
    pb.add_c(p, 0, 1, 1.0)
        .add_c(l, 1, 1, 1.0)
        .add_c(l, 2, 2, 2.0);
    pb.build().unwrap()
}

#[test]
fn points_that_do_not_fit_are_typed_errors() {
    let p = small();
    let good = Point {
        x: vec![Mat::identity(2, 2), Mat::from_fn(3, 1, |_, _| 1.0)],
        y: vec![0.0, 0.0],
        s: vec![Mat::identity(2, 2), Mat::from_fn(3, 1, |_, _| 1.0)],
    };
    assert!(dimacs_errors(&p, &good.y, &good.x, &good.s).is_ok());
    let mismatch = |pt: &Point, what: &str, expected: (usize, usize), found: (usize, usize)| {
        let want = SdpError::DimensionMismatch {
            what: what.into(),
            expected,
            found,
        };
        assert_eq!(dimacs_errors(&p, &pt.y, &pt.x, &pt.s), Err(want.clone()));
        let mut solver = Solver::new(&p, Settings::default()).unwrap();
        assert_eq!(solver.solve_from(&p, pt).unwrap_err(), want);
    };
    let mut bad = good.clone();
    bad.y.push(1.0);
    mismatch(&bad, "y", (2, 1), (3, 1));
    let mut bad = good.clone();
    bad.x.pop();
    mismatch(&bad, "the block list of X", (2, 1), (1, 1));
    let mut bad = good.clone();
    bad.s[1] = Mat::identity(3, 3); // an LP block must be a column
    mismatch(&bad, "S, block 1", (3, 1), (3, 3));
    let mut bad = good.clone();
    bad.x[0] = Mat::zeros(2, 1);
    mismatch(&bad, "X, block 0", (2, 2), (2, 1));
    let mut bad = good.clone();
    bad.s[0][(1, 0)] = f64::NAN;
    assert!(matches!(
        dimacs_errors(&p, &bad.y, &bad.x, &bad.s),
        Err(SdpError::NonFinite { .. })
    ));
    // A read solution of the wrong problem is caught by the reader.
    let text = write_solution(&good.y, &good.x, &good.s);
    let mut other = ProblemBuilder::new(2);
    other.add_block(BlockKind::Psd, 1);
    other.add_block(BlockKind::Lp, 3);
    let other = other.build().unwrap();
    let err = read_solution(&text, &other).unwrap_err();
    assert_eq!(err.line(), Some(3), "{err}"); // `1 1 2 2 1`: (2,2) in a block of order 1
}

#[test]
fn warm_start_on_a_small_problem_agrees_with_the_cold_solve() {
    let p = small();
    let cold = solve(&p, &Settings::default()).unwrap();
    assert_eq!(cold.status, Status::Optimal);
    let warm = solve_from(&p, &Settings::default(), &cold.point()).unwrap();
    assert_eq!(warm.status, Status::Optimal);
    assert_eq!(warm.iterations, 0);
    assert!((warm.dual_objective - cold.dual_objective).abs() <= 1e-7);
}
