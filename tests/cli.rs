//! The `sporadic` binary on the shipped plant files and on malformed input: exit codes, output
//! and error messages (no panics, no backtraces).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn sporadic(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sporadic"))
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .output()
        .expect("run the sporadic binary")
}

fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name)
        .display()
        .to_string()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sporadic-cli-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A failing run: non-zero exit, a one-line `error:` message containing `needle`, no panic.
fn assert_clean_failure(o: &Output, needle: &str) {
    let err = stderr(o);
    assert!(
        !o.status.success(),
        "expected failure, got success: {}",
        stdout(o)
    );
    assert!(err.contains(needle), "stderr lacks {needle:?}: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    assert!(!err.contains("RUST_BACKTRACE"), "backtrace hint: {err}");
}

#[test]
fn design_ferrante_json_gives_a_gain_that_stabilises_the_jump() {
    let o = sporadic(&[
        "design",
        &example("ferrante2016-example2.toml"),
        "--method",
        "ferrante2016",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!(v["method"], "ferrante2016");
    assert!(v["margin"].as_f64().unwrap() > 0.0);
    let l: Vec<f64> = v["gains"][0]["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r[0].as_f64().unwrap())
        .collect();
    assert_eq!(l.len(), 5);
    // Independent necessary condition (spec 000, Remark 3): e^{Aτ}(I − L M) is Schur for
    // every sampling interval τ in [T1, T2] = [0.2, 3].
    let a = faer::mat![
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, 0.0],
        [-2.0, 1.0, -1.0, 0.0, 0.0],
        [2.0, -2.0, 0.0, -2.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0],
    ];
    let m = [1.0, 0.0, 0.0, 0.0, 1.0];
    let reset = faer::Mat::from_fn(5, 5, |i, j| f64::from(u8::from(i == j)) - l[i] * m[j]);
    for k in 0..=28 {
        let tau = 0.2 + 0.1 * k as f64;
        let e = sporadic::linalg::expm((&a * faer::Scale(tau)).as_ref()).unwrap();
        let rho = (&e * &reset)
            .eigenvalues()
            .unwrap()
            .iter()
            .map(|z| z.norm())
            .fold(0.0, f64::max);
        assert!(rho < 1.0, "spectral radius {rho} at tau = {tau}");
    }
}

#[test]
fn design_sferlazza_human_output() {
    let o = sporadic(&[
        "design",
        &example("sferlazza2021-suspension.toml"),
        "--method",
        "sferlazza2021",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("status   certified"), "{out}");
    assert!(out.contains("K_2(T_max)"), "{out}");
}

#[test]
fn max_interval_prints_plain_progress_lines_off_a_terminal() {
    let o = sporadic(&[
        "max-interval",
        &example("ferrante2016-example2.toml"),
        "--method",
        "ferrante2016",
        "--limit",
        "6",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).lines().any(|l| l.starts_with("T2 = ")),
        "{}",
        stderr(&o)
    );
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    // Spec 000 §5 [ours]: with T1 = 0.2 the design stays feasible up to T2 = 30, so the
    // search limit 6 itself is certified.
    assert_eq!(v["largest_certified_t2"].as_f64(), Some(6.0));
    assert!(v["design"]["margin"].as_f64().unwrap() > 0.0);
}

#[test]
fn compare_writes_the_windows_figure() {
    let out = scratch("compare");
    let o = sporadic(&[
        "compare",
        &example("ferrante2016-example2.toml"),
        "--out",
        &out.display().to_string(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("ferrante2016"), "{text}");
    assert!(text.contains("not applicable"), "{text}");
    let svg = std::fs::read_to_string(out.join("certified_windows.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("ferrante2016"));
}

#[test]
fn malformed_plant_files_fail_cleanly() {
    let bad = scratch("bad.toml");
    std::fs::write(&bad, "[plant]\nA = [[0.0, 1.0], [2.0]]\nC = [[1.0, 0.0]]\n").unwrap();
    let o = sporadic(&[
        "design",
        &bad.display().to_string(),
        "--method",
        "ferrante2016",
    ]);
    assert_clean_failure(
        &o,
        "bad.toml:2: plant.A: row 2 has 1 entries but row 1 has 2",
    );

    std::fs::write(&bad, "[plant\nA = 1\n").unwrap();
    let o = sporadic(&[
        "design",
        &bad.display().to_string(),
        "--method",
        "ferrante2016",
    ]);
    assert_clean_failure(&o, "bad.toml:1: toml:");

    std::fs::write(
        &bad,
        "[plant]\nA = [[1.0]]\nC = [[1.0]]\n[sampling]\nwindow = [0.5, 0.1]\n",
    )
    .unwrap();
    let o = sporadic(&[
        "max-interval",
        &bad.display().to_string(),
        "--method",
        "ferrante2016",
    ]);
    assert_clean_failure(&o, "sampling.window: T1 = 0.5 exceeds T2 = 0.1");

    let o = sporadic(&[
        "design",
        "/nonexistent/plant.toml",
        "--method",
        "ferrante2016",
    ]);
    assert_clean_failure(&o, "/nonexistent/plant.toml");
}

#[test]
fn a_method_that_needs_missing_data_says_so() {
    let o = sporadic(&[
        "design",
        &example("ferrante2016-example2.toml"),
        "--method",
        "etienne2017",
    ]);
    assert_clean_failure(&o, "etienne2017");
}

#[test]
fn sdp_solve_reports_malformed_files_with_a_line() {
    let bad = scratch("bad.dat-s");
    std::fs::write(&bad, "2 =mdim\n1 =nblocks\n2\n1.0 x\n").unwrap();
    let o = sporadic(&["sdp", "solve", &bad.display().to_string()]);
    assert_clean_failure(&o, "bad.dat-s");
}

#[test]
fn reproduce_rejects_unknown_papers() {
    let o = sporadic(&["reproduce", "nobody1999"]);
    assert_clean_failure(&o, "unknown paper 'nobody1999'");
}
