//! Independent checks of solver output, shared by the integration tests.
//!
//! Everything here is recomputed from the public [`Problem`] data with straightforward dense
//! code (no solver internals): residuals `𝒜(X) − b` and `C − 𝒜ᵀ(y) − S`, objectives, and the
//! extreme eigenvalues of `X`, `S` and of certificate matrices.

#![allow(dead_code)]

use faer::{Mat, Side};
use sporadic_sdp::{BlockKind, Problem, Settings, Solution, Status, read_sdpa_file, solve};

/// Dense `Σ_i w_i A_i^k + c·C^k` of block `k` (PSD: symmetric `n×n`; LP: `n×1` diagonal).
pub fn dense_combination(problem: &Problem, k: usize, w: &[f64], c: f64) -> Mat<f64> {
    let bd = &problem.blocks[k];
    let n = bd.block.size;
    let psd = bd.block.kind == BlockKind::Psd;
    let mut out = if psd {
        Mat::zeros(n, n)
    } else {
        Mat::zeros(n, 1)
    };
    let mut add = |i: usize, j: usize, v: f64| {
        if psd {
            out[(i, j)] += v;
            if i != j {
                out[(j, i)] += v;
            }
        } else {
            out[(i, 0)] += v;
        }
    };
    for (i, j, v) in bd.c.iter() {
        add(i, j, c * v);
    }
    for (con, a) in &bd.a {
        for (i, j, v) in a.iter() {
            add(i, j, w[*con] * v);
        }
    }
    out
}

/// Extreme eigenvalues `(min, max)` of a block (LP: extreme entries).
pub fn eig_range(kind: BlockKind, m: &Mat<f64>) -> (f64, f64) {
    match kind {
        BlockKind::Lp => {
            let v: Vec<f64> = (0..m.nrows()).map(|i| m[(i, 0)]).collect();
            (
                v.iter().copied().fold(f64::INFINITY, f64::min),
                v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            )
        }
        BlockKind::Psd => {
            let sym = Mat::from_fn(m.nrows(), m.ncols(), |i, j| 0.5 * (m[(i, j)] + m[(j, i)]));
            let e = sym
                .self_adjoint_eigenvalues(Side::Lower)
                .expect("eigenvalues converge");
            (e[0], e[e.len() - 1])
        }
    }
}

/// `⟨M_k, X_k⟩` for a dense block and a matching iterate block.
fn dot(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
    let mut s = 0.0;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            s += a[(i, j)] * b[(i, j)];
        }
    }
    s
}

/// `𝒜(X)` computed block by block from the sparse data.
pub fn apply_a(problem: &Problem, x: &[Mat<f64>]) -> Vec<f64> {
    let mut out = vec![0.0; problem.b.len()];
    for (k, bd) in problem.blocks.iter().enumerate() {
        let psd = bd.block.kind == BlockKind::Psd;
        for (con, a) in &bd.a {
            for (i, j, v) in a.iter() {
                out[*con] += if !psd {
                    v * x[k][(i, 0)]
                } else if i == j {
                    v * x[k][(i, i)]
                } else {
                    v * (x[k][(i, j)] + x[k][(j, i)])
                };
            }
        }
    }
    out
}

/// KKT quantities of a solution, recomputed from the problem.
#[derive(Debug, Clone, Copy)]
pub struct Kkt {
    /// `⟨C, X⟩`.
    pub pobj: f64,
    /// `bᵀy`.
    pub dobj: f64,
    /// `‖𝒜(X) − b‖₂ / (1 + ‖b‖₂)`.
    pub pinf: f64,
    /// `‖C − 𝒜ᵀ(y) − S‖_F / (1 + ‖C‖_F)`.
    pub dinf: f64,
    /// `|pobj − dobj| / (1 + |pobj| + |dobj|)`.
    pub gap: f64,
    /// `⟨X, S⟩ / (1 + |pobj| + |dobj|)`.
    pub compl: f64,
    /// `λ_min(X)` relative to `1 + λ_max(X)`.
    pub min_eig_x: f64,
    /// `λ_min(S)` relative to `1 + λ_max(S)`.
    pub min_eig_s: f64,
}

/// Recomputes every KKT measure of `sol` from `problem`.
pub fn kkt(problem: &Problem, sol: &Solution) -> Kkt {
    let m = problem.b.len();
    assert_eq!(sol.y.len(), m);
    assert_eq!(sol.x.len(), problem.blocks.len());
    let ax = apply_a(problem, &sol.x);
    let rp: f64 = ax
        .iter()
        .zip(&problem.b)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt();
    let bnorm = problem.b.iter().map(|v| v * v).sum::<f64>().sqrt();
    let (mut rd2, mut c2, mut pobj, mut xs) = (0.0, 0.0, 0.0, 0.0);
    let (mut lx, mut ls) = (f64::INFINITY, f64::INFINITY);
    let (mut ux, mut us) = (0.0f64, 0.0f64);
    let zero = vec![0.0; m];
    for (k, bd) in problem.blocks.iter().enumerate() {
        let c = dense_combination(problem, k, &zero, 1.0);
        // C − Σ y_i A_i − S
        let mut r = dense_combination(
            problem,
            k,
            &sol.y.iter().map(|v| -v).collect::<Vec<_>>(),
            1.0,
        );
        r -= &sol.s[k];
        rd2 += dot(&r, &r);
        c2 += dot(&c, &c);
        pobj += dot(&c, &sol.x[k]);
        xs += dot(&sol.x[k], &sol.s[k]);
        let (a, b) = eig_range(bd.block.kind, &sol.x[k]);
        lx = lx.min(a);
        ux = ux.max(b);
        let (a, b) = eig_range(bd.block.kind, &sol.s[k]);
        ls = ls.min(a);
        us = us.max(b);
    }
    let dobj: f64 = problem.b.iter().zip(&sol.y).map(|(b, y)| b * y).sum();
    let denom = 1.0 + pobj.abs() + dobj.abs();
    Kkt {
        pobj,
        dobj,
        pinf: rp / (1.0 + bnorm),
        dinf: rd2.sqrt() / (1.0 + c2.sqrt()),
        gap: (pobj - dobj).abs() / denom,
        compl: xs / denom,
        min_eig_x: lx / (1.0 + ux),
        min_eig_s: ls / (1.0 + us),
    }
}

/// Defect of a (P)-infeasibility ray `y`: `max(0, λ_max(Σ y_i A_i)) / bᵀy` (requires `bᵀy > 0`).
pub fn primal_ray_defect(problem: &Problem, y: &[f64]) -> f64 {
    let by: f64 = problem.b.iter().zip(y).map(|(b, v)| b * v).sum();
    assert!(by > 0.0, "bᵀy = {by} must be positive");
    let mut lam = f64::NEG_INFINITY;
    for (k, bd) in problem.blocks.iter().enumerate() {
        let a = dense_combination(problem, k, y, 0.0);
        lam = lam.max(eig_range(bd.block.kind, &a).1);
    }
    lam.max(0.0) / by
}

/// Defect of a (D)-infeasibility ray `X`: `max(‖𝒜(X)‖₂, −λ_min(X)) / (−⟨C,X⟩)` (requires
/// `⟨C,X⟩ < 0`).
pub fn dual_ray_defect(problem: &Problem, x: &[Mat<f64>]) -> f64 {
    let zero = vec![0.0; problem.b.len()];
    let mut cx = 0.0;
    let mut lam = f64::INFINITY;
    for (k, bd) in problem.blocks.iter().enumerate() {
        cx += dot(&dense_combination(problem, k, &zero, 1.0), &x[k]);
        lam = lam.min(eig_range(bd.block.kind, &x[k]).0);
    }
    assert!(cx < 0.0, "⟨C,X⟩ = {cx} must be negative");
    let ax = apply_a(problem, x);
    let res = ax.iter().map(|v| v * v).sum::<f64>().sqrt();
    res.max(-lam) / -cx
}

/// The six DIMACS errors of `(y, X, S)` recomputed with dense code from the problem data
/// (Mittelmann 2003; the definitions of `sporadic_sdp::Measures::dimacs`):
/// `‖𝒜(X)−b‖₂/(1+‖b‖_∞)`, `max(0,−λ_min(X))/(1+‖b‖_∞)`, `‖𝒜ᵀ(y)+S−C‖_F/(1+‖C‖_max)`,
/// `max(0,−λ_min(S))/(1+‖C‖_max)`, `(⟨C,X⟩−bᵀy)/(1+|⟨C,X⟩|+|bᵀy|)`,
/// `⟨X,S⟩/(1+|⟨C,X⟩|+|bᵀy|)`.
pub fn dimacs(problem: &Problem, y: &[f64], x: &[Mat<f64>], s: &[Mat<f64>]) -> [f64; 6] {
    let m = problem.b.len();
    let ax = apply_a(problem, x);
    let rp: f64 = ax
        .iter()
        .zip(&problem.b)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt();
    let b_inf = problem.b.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let zero = vec![0.0; m];
    let minus_y: Vec<f64> = y.iter().map(|v| -v).collect();
    let (mut rd2, mut c_max, mut pobj, mut xs) = (0.0, 0.0f64, 0.0, 0.0);
    let (mut lx, mut ls) = (f64::INFINITY, f64::INFINITY);
    for (k, bd) in problem.blocks.iter().enumerate() {
        let c = dense_combination(problem, k, &zero, 1.0);
        for j in 0..c.ncols() {
            for i in 0..c.nrows() {
                c_max = c_max.max(c[(i, j)].abs());
            }
        }
        let mut r = dense_combination(problem, k, &minus_y, 1.0);
        r -= &s[k];
        rd2 += dot(&r, &r);
        pobj += dot(&c, &x[k]);
        xs += dot(&x[k], &s[k]);
        lx = lx.min(eig_range(bd.block.kind, &x[k]).0);
        ls = ls.min(eig_range(bd.block.kind, &s[k]).0);
    }
    let dobj: f64 = problem.b.iter().zip(y).map(|(b, v)| b * v).sum();
    let denom = 1.0 + pobj.abs() + dobj.abs();
    let (bi, cm) = (1.0 + b_inf, 1.0 + c_max);
    [
        rp / bi,
        (-lx).max(0.0) / bi,
        rd2.sqrt() / cm,
        (-ls).max(0.0) / cm,
        (pobj - dobj) / denom,
        xs / denom,
    ]
}

/// Largest absolute value of six DIMACS errors.
pub fn dimacs_max(e: &[f64; 6]) -> f64 {
    e.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Solves `tests/data/{name}` with the default settings and asserts an optimal point that the
/// independent [`kkt`] check confirms: relative infeasibilities, gap and complementarity at most
/// `2e-8`, `X` and `S` positive semidefinite to `1e-12` relative.
pub fn solve_data_file_to_optimality(name: &str) -> (Problem, Solution) {
    let path = format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"));
    let problem = read_sdpa_file(&path).expect("readable test data");
    let sol = solve(&problem, &Settings::default()).expect("solve");
    assert_eq!(sol.status, Status::Optimal, "{name}: {:?}", sol.measures);
    let k = kkt(&problem, &sol);
    assert!(k.pinf <= 2e-8 && k.dinf <= 2e-8, "{name}: {k:?}");
    assert!(k.gap <= 2e-8 && k.compl <= 2e-8, "{name}: {k:?}");
    assert!(
        k.min_eig_x >= -1e-12 && k.min_eig_s >= -1e-12,
        "{name}: {k:?}"
    );
    (problem, sol)
}
