//! `sporadic compare` on every plant of our corpus (`tests/corpus/*.toml`: 43 plants of order
//! 1–8 that nobody tuned for — oscillators around their aliasing intervals, integrator chains,
//! unstable linearisations, lightly damped structures, stiff and badly scaled plants,
//! multi-output and round-robin plants, undetectable, Lipschitz and bounded-disturbance ones):
//! every answer comes within the default time budget (25 s, `--time-limit`) and parses as the
//! compare report, and the verdicts listed in `tests/corpus/expected.toml` hold for the file's
//! own sampling (`--no-search`; the window searches are timed in `benches/`); every design
//! certified there passes `verify` with its own gains and certificate. Timing goals live
//! in benchmarks; the 40 s bound here only catches a command that overruns its budget.

use sporadic::model::{CompareReport, Status};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Runs `compare --json` on `file`, killing it after `limit`.
fn compare(file: &Path, out: &Path, limit: Duration) -> Result<(i32, String), String> {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_sporadic"));
    cmd.args([
        "compare",
        &file.display().to_string(),
        "--no-search",
        "--json",
        "--out",
    ])
    .arg(out);
    run(cmd, limit)
}

/// Runs `verify --method METHOD --gains DESIGN` on `file`, killing it after `limit`.
fn verify(
    file: &Path,
    method: &str,
    design: &Path,
    limit: Duration,
) -> Result<(i32, String), String> {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_sporadic"));
    cmd.args(["verify", "--method", method, "--gains"])
        .arg(design)
        .arg(file);
    run(cmd, limit)
}

/// Runs `cmd` to completion (standard output captured), killing it after `limit`.
fn run(mut cmd: Command, limit: Duration) -> Result<(i32, String), String> {
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            let mut text = String::new();
            std::io::Read::read_to_string(child.stdout.as_mut().unwrap(), &mut text)
                .map_err(|e| e.to_string())?;
            return Ok((status.code().unwrap_or(-1), text));
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            return Err(format!("no answer within {limit:?}"));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn compare_answers_every_corpus_plant_in_time_with_the_expected_verdicts() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/corpus");
    let expected: toml::Table =
        toml::from_str(&std::fs::read_to_string(dir.join("expected.toml")).unwrap()).unwrap();
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter(|p| p.file_stem().is_some_and(|s| s != "expected"))
        .collect();
    files.sort();
    assert!(files.len() >= 30, "{} corpus plants", files.len());
    for stem in expected.keys() {
        assert!(
            files
                .iter()
                .any(|f| f.file_stem().unwrap().to_str() == Some(stem)),
            "expected.toml names {stem}, which is not in the corpus"
        );
    }
    let out = std::env::temp_dir().join(format!("sporadic-corpus-{}", std::process::id()));
    let mut failures = Vec::new();
    for file in &files {
        let stem = file.file_stem().unwrap().to_str().unwrap();
        let (code, text) = match compare(file, &out, Duration::from_secs(40)) {
            Ok(r) => r,
            Err(e) => {
                failures.push(format!("{stem}: {e}"));
                continue;
            }
        };
        let report: CompareReport = match serde_json::from_str(text.trim()) {
            Ok(r) => r,
            Err(e) => {
                failures.push(format!("{stem}: exit {code}, unparsable report ({e})"));
                continue;
            }
        };
        let any = report
            .results
            .iter()
            .any(|e| e.certifies_the_files_sampling());
        if code != if any { 0 } else { 1 } {
            failures.push(format!("{stem}: exit {code} with certified = {any}"));
        }
        // Every design certified on the file's window passes `verify` with its own gains and
        // certificate (issue 22: a design's gain, re-verified on the window, passes).
        // (A method that picks its own sampling instants has no window to verify on.)
        for e in &report.results {
            if e.design.status != Status::Certified || e.chooses_its_sampling {
                continue;
            }
            let design = out.join(format!("{stem}-{}.json", e.method));
            std::fs::create_dir_all(&out).unwrap();
            std::fs::write(&design, serde_json::to_string(&e.design).unwrap()).unwrap();
            match verify(file, &e.method, &design, Duration::from_secs(40)) {
                Ok((0, _)) => {}
                Ok((code, text)) => failures.push(format!(
                    "{stem}: {}'s certified design fails verify (exit {code}): {}",
                    e.method,
                    text.lines()
                        .find(|l| l.starts_with("status"))
                        .unwrap_or(text.trim())
                )),
                Err(err) => failures.push(format!("{stem}: verify {}: {err}", e.method)),
            }
        }
        let Some(want) = expected.get(stem).and_then(|t| t.as_table()) else {
            continue;
        };
        for (method, verdict) in want {
            let verdict = verdict.as_str().unwrap();
            let (status, kind) = verdict.split_once('/').unwrap_or((verdict, ""));
            let Some(d) = report.entry(method).map(|e| &e.design) else {
                failures.push(format!("{stem}: no result for {method}"));
                continue;
            };
            let got_kind = d.reason.as_ref().map_or("", |r| r.kind());
            let status_ok = match status {
                "certified" => d.status == Status::Certified,
                "not_certified" => d.status == Status::NotCertified,
                "not_applicable" => d.status == Status::NotApplicable,
                other => panic!("{stem}: unknown status {other} in expected.toml"),
            };
            if !status_ok || (!kind.is_empty() && kind != got_kind) {
                failures.push(format!(
                    "{stem}: {method} expected {verdict}, got {}/{got_kind} ({})",
                    d.status,
                    d.reason.as_ref().map_or("", |r| r.message())
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
