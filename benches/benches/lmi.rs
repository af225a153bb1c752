//! LMI modelling layer (`sporadic_sdp::lmi`) on a 64-vertex, 15×15 design: LMI (41) of Ferrante
//! et al. (Automatica 2016) for their Example 2 (`Ā` 5×5 with the bias state, `M = [1 0 0 0 1]`),
//! with 64 vertices `X_i = e^{Ā v_i}` at equispaced `v_i ∈ [0.2, 3]` (a gridding workload, not the
//! paper's polytopic embedding). Decision variables P (sym 5×5), F (5×5), J (5×1): 45 scalars plus
//! the margin.
//!
//! * `lmi/compile`: build the model from constant data and assemble the solver's `Problem`.
//! * `lmi/rebuild_solve` (reference): build + compile + structure analysis + margin solve.
//! * `lmi/update_all_solve`: the same model compiled once with the vertices as parameters; per
//!   iteration all 64 vertices get new values (two alternating grids) and the model is re-solved
//!   (structure analysis reused).
//! * `lmi/update_one_solve`: one vertex changes per iteration (a refined τ point).
//! * `lmi/analyse`: the solver's structure analysis alone (`Solver::new`), and
//!   `lmi/resolve_unchanged`: a re-solve with no update at all (solver time only).
//!
//! A small SDP of the kind bisections solve hundreds of times: LMIs (20) of Etienne et al.
//! (Corollary 2, flexible-joint robot, 29 scalars + margin, blocks 4×4 and 8×8) with `τ̄` a
//! parameter (`1/τ̄` and `τ_low/τ̄` enter as 1×1 parameters):
//!
//! * `lmi_small/rebuild_solve` (reference): build the model for a new `τ̄` and solve;
//! * `lmi_small/update_solve`: `set_param` on the compiled model and re-solve.
//!
//! The 64-vertex problem exported from the modelling layer (`write_sdpa` of the compiled
//! feasibility problem: 64 blocks of order 15 plus the margin normalisation, in 46 shared
//! variables) is written to `$TMPDIR/sporadic-lmi64x15.dat-s` and timed from the file:
//!
//! * `lmi_vs_csdp/ours`: `read_sdpa_file` + `solve` in process;
//! * `lmi_vs_csdp/csdp` (reference): the `csdp` binary on the same file, whole process (when
//!   `/usr/bin/csdp` exists). `benches/scripts/vs_csdp.sh` also compares whole processes with
//!   hyperfine.
//!
//! Run: `cargo bench -p sporadic-benches --bench lmi -- --warm-up-time 1 --measurement-time 5`

use std::hint::black_box;
use std::path::Path;
use std::process::{Command, Stdio};

use criterion::{Criterion, criterion_group, criterion_main};
use faer::{Mat, mat};
use sporadic_linalg::expm_scaled;
use sporadic_sdp::lmi::{Compiled, Expr, FeasibilityOptions, Model, Normalisation, Param};
use sporadic_sdp::{Settings, Solver, read_sdpa_file, solve, write_sdpa};

const VERTICES: usize = 64;

fn plant() -> (Mat<f64>, Mat<f64>) {
    let a = mat![
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, 0.0],
        [-2.0, 1.0, -1.0, 0.0, 0.0],
        [2.0, -2.0, 0.0, -2.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0],
    ];
    let m = mat![[1.0, 0.0, 0.0, 0.0, 1.0]];
    (a, m)
}

/// `e^{Ā v_i}` on an equispaced grid of `[0.2 + shift, 3]`.
fn vertices(a: &Mat<f64>, shift: f64) -> Vec<Mat<f64>> {
    (0..VERTICES)
        .map(|i| {
            let v = 0.2 + shift + (3.0 - 0.2 - shift) * i as f64 / (VERTICES - 1) as f64;
            expm_scaled(a.as_ref(), v).expect("expm")
        })
        .collect()
}

/// Φ_i of LMI (41) for a vertex given as an expression (constant or parameter).
fn phi(x: Expr, p: &Expr, f: &Expr, j: &Expr, m: &Mat<f64>) -> Expr {
    let n = m.ncols();
    Expr::sym_blocks(&[
        [Some(-f.he()), None, None],
        [Some((f - j * m).t()), Some(-p), None],
        [Some(p * &x), Some(Expr::zeros(n, n)), Some(-p)],
    ])
}

fn build_constant(xs: &[Mat<f64>]) -> Model {
    let (_, m) = plant();
    let mut model = Model::new();
    let p = model.symmetric("P", 5).expr();
    let f = model.full("F", 5, 5).expr();
    let j = model.full("J", 5, 1).expr();
    for x in xs {
        model
            .constrain(phi(Expr::from(x), &p, &f, &j, &m).lt(0.0))
            .expect("constraint");
    }
    model
}

fn build_parametric(xs: &[Mat<f64>]) -> (Model, Vec<Param>) {
    let (_, m) = plant();
    let mut model = Model::new();
    let p = model.symmetric("P", 5).expr();
    let f = model.full("F", 5, 5).expr();
    let j = model.full("J", 5, 1).expr();
    let mut params = Vec::new();
    for (i, x) in xs.iter().enumerate() {
        let xp = model.param(&format!("X_{i}"), x.as_ref()).expect("param");
        model
            .constrain(phi(xp.expr(), &p, &f, &j, &m).lt(0.0))
            .expect("constraint");
        params.push(xp);
    }
    (model, params)
}

fn bench(c: &mut Criterion) {
    let (a, _) = plant();
    let grid0 = vertices(&a, 0.0);
    let grid1 = vertices(&a, 0.01);
    let opts = FeasibilityOptions::default();

    {
        let mut compiled = build_constant(&grid0)
            .compile_feasibility(&opts)
            .expect("compile");
        let pr = compiled.problem().expect("problem");
        let nnz: usize = pr
            .blocks
            .iter()
            .map(|b| b.a.iter().map(|(_, s)| s.nnz()).sum::<usize>())
            .sum();
        eprintln!(
            "lmi bench: m = {}, {} blocks (sizes {:?}…), {} stored A entries",
            pr.num_constraints(),
            pr.blocks.len(),
            pr.blocks
                .iter()
                .take(4)
                .map(|b| b.block.size)
                .collect::<Vec<_>>(),
            nnz
        );
        let sol = compiled.solve().expect("solve");
        eprintln!(
            "lmi bench: {:?}, margin {:?}, {} iterations, solver time {:?}",
            sol.outcome, sol.margin, sol.sdp.iterations, sol.sdp.solve_time
        );
    }

    let mut g = c.benchmark_group("lmi");
    g.sample_size(10);
    g.bench_function("compile", |b| {
        b.iter(|| {
            let mut compiled = build_constant(black_box(&grid0))
                .compile_feasibility(&opts)
                .expect("compile");
            compiled.problem().expect("problem").num_constraints()
        })
    });
    let problem = build_constant(&grid0)
        .compile_feasibility(&opts)
        .expect("compile")
        .problem()
        .expect("problem")
        .clone();
    g.bench_function("analyse", |b| {
        b.iter(|| Solver::new(black_box(&problem), opts.solve.settings.clone()).expect("analyse"))
    });
    g.bench_function("rebuild_solve", |b| {
        let mut flip = false;
        b.iter(|| {
            flip = !flip;
            let xs = if flip { &grid1 } else { &grid0 };
            build_constant(black_box(xs))
                .feasibility(&opts)
                .expect("solve")
                .margin
        })
    });
    let (model, params) = build_parametric(&grid0);
    let mut compiled: Compiled = model.compile_feasibility(&opts).expect("compile");
    g.bench_function("update_all_solve", |b| {
        let mut flip = false;
        b.iter(|| {
            flip = !flip;
            let xs = if flip { &grid1 } else { &grid0 };
            for (p, x) in params.iter().zip(xs) {
                compiled.set_param(p, x.as_ref()).expect("set");
            }
            compiled.solve().expect("solve").margin
        })
    });
    g.bench_function("update_one_solve", |b| {
        let mut flip = false;
        b.iter(|| {
            flip = !flip;
            let x = if flip { &grid1[17] } else { &grid0[17] };
            compiled.set_param(&params[17], x.as_ref()).expect("set");
            compiled.solve().expect("solve").margin
        })
    });
    g.bench_function("resolve_unchanged", |b| {
        b.iter(|| compiled.solve().expect("solve").margin)
    });
    g.finish();
    eprintln!("lmi bench: compiled-model stats {:?}", compiled.stats());
}

/// LMIs (20) of Etienne et al. with `L0 = L1` (Corollary 2); returns the model, the parameters
/// `1/τ̄` and `τ_low/τ̄`, and the options (gain variable left out of the normalisation, as in the
/// formulation of the independent reference implementation: maximise `t` with `P1, P2 ⪯ I`).
fn etienne(tau_low: f64, tau_bar: f64) -> (Model, Param, Param, FeasibilityOptions) {
    let a = mat![
        [0.0, 1.0, 0.0, 0.0],
        [-48.6, -1.25, 48.6, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [19.5, 0.0, -19.5, 0.0],
    ];
    let c = mat![[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]];
    let mut m = Model::new();
    let p1 = m.symmetric("P1", 4);
    let p2 = m.symmetric("P2", 4);
    let l = m.full("L", 4, 2);
    let inv = m
        .param("1/τ̄", mat![[1.0 / tau_bar]].as_ref())
        .expect("param");
    let ratio = m
        .param("τ_low/τ̄", mat![[tau_low / tau_bar]].as_ref())
        .expect("param");
    let dp = (&p2 - &p1) * &inv;
    for s in [-3.3, 3.3] {
        let mut r = a.clone();
        r[(3, 2)] += s;
        m.constrain(((&p1 * &r).he() + &dp).lt(0.0))
            .expect("constraint");
        m.constrain(((&p2 * &r).he() + &dp).lt(0.0))
            .expect("constraint");
    }
    let lc = &l * &c;
    for w in [(&p1 - &p2) * &ratio, &p1 - &p2] {
        let blk = Expr::sym_blocks(&[
            [Some(lc.he() - w), None],
            [Some(lc.clone()), Some(p1.expr())],
        ]);
        m.constrain(blk.gt(0.0)).expect("constraint");
    }
    m.constrain(p1.gt(0.0)).expect("constraint");
    m.constrain(p2.gt(0.0)).expect("constraint");
    let opts = FeasibilityOptions::default().normalise(&l, Normalisation::Free);
    (m, inv, ratio, opts)
}

fn bench_small(c: &mut Criterion) {
    let taus = [0.2, 0.25, 0.28, 0.29, 0.3];
    let mut g = c.benchmark_group("lmi_small");
    g.bench_function("rebuild_solve", |b| {
        let mut k = 0;
        b.iter(|| {
            k = (k + 1) % taus.len();
            let (m, _, _, opts) = etienne(0.01, black_box(taus[k]));
            m.feasibility(&opts).expect("solve").margin
        })
    });
    let (m, inv, ratio, opts) = etienne(0.01, 0.2);
    let mut compiled = m.compile_feasibility(&opts).expect("compile");
    g.bench_function("update_solve", |b| {
        let mut k = 0;
        b.iter(|| {
            k = (k + 1) % taus.len();
            let tb = black_box(taus[k]);
            compiled
                .set_param(&inv, mat![[1.0 / tb]].as_ref())
                .expect("set");
            compiled
                .set_param(&ratio, mat![[0.01 / tb]].as_ref())
                .expect("set");
            compiled.solve().expect("solve").margin
        })
    });
    g.finish();
    eprintln!(
        "lmi_small bench: compiled-model stats {:?}",
        compiled.stats()
    );
}

const CSDP: &str = "/usr/bin/csdp";

/// Exports the 64-vertex feasibility problem and times ours against CSDP from the file.
fn bench_vs_csdp(c: &mut Criterion) {
    let (a, _) = plant();
    let opts = FeasibilityOptions::default();
    let problem = build_constant(&vertices(&a, 0.0))
        .compile_feasibility(&opts)
        .expect("compile")
        .problem()
        .expect("problem")
        .clone();
    let file = std::env::temp_dir().join("sporadic-lmi64x15.dat-s");
    std::fs::write(&file, write_sdpa(&problem)).expect("write the exported problem");
    eprintln!("lmi bench: exported {}", file.display());
    let mut g = c.benchmark_group("lmi_vs_csdp");
    g.sample_size(10);
    g.bench_function("ours", |b| {
        b.iter(|| {
            let p = read_sdpa_file(black_box(&file)).expect("read");
            solve(&p, &Settings::default()).expect("solve").iterations
        })
    });
    if Path::new(CSDP).exists() {
        let out = std::env::temp_dir().join("sporadic-lmi64x15.csdp.sol");
        g.bench_function("csdp", |b| {
            b.iter(|| {
                let status = Command::new(CSDP)
                    .arg(black_box(&file))
                    .arg(&out)
                    .stdout(Stdio::null())
                    .stderr(Stdio::null())
                    .status()
                    .expect("csdp runs");
                // 0: success, 3: partial success.
                assert!(
                    matches!(status.code(), Some(0 | 3)),
                    "csdp failed: {status}"
                );
            })
        });
    } else {
        eprintln!("lmi bench: {CSDP} not found, CSDP reference SKIPPED");
    }
    g.finish();
}

criterion_group!(benches, bench, bench_small, bench_vs_csdp);
criterion_main!(benches);
