//! Property tests of the interior-point solver on problems with a known answer.
//!
//! * **Planted optimum** — blocks with a random orthogonal basis `Q`, `X* = Q diag(λ, 0) Qᵀ`,
//!   `S* = Q diag(0, σ) Qᵀ` (strictly complementary: `X* S* = 0`, `rank X* + rank S* = n`), random
//!   `A_i`, random `y*`, then `C = Σ y*_i A_i + S*`, `b = 𝒜(X*)`. `(X*, y*, S*)` satisfies the
//!   KKT conditions, so the optimal value is `⟨C, X*⟩ = bᵀy*`.
//! * **Planted strictly feasible LMI** — `C = Σ y⁰_i A_i + S⁰` with `S⁰ ≻ 0` and `b = 𝒜(X⁰)` with
//!   `X⁰ ≻ 0`: both problems are strictly feasible, `bᵀy⁰ ≤ optimum ≤ ⟨C, X⁰⟩`.
//! * **Planted infeasibility** — a hidden Farkas ray (`Σ y_i A_i = −I`, `bᵀy = 1` after a random
//!   change of basis of the constraints, or `X⁰ ≻ 0` orthogonal to every `A_i` with
//!   `⟨C, X⁰⟩ = −1`).
//!
//! Every solution is checked with the independent recomputation of `common::kkt`.

mod common;

use std::sync::{Arc, Mutex};

use common::{dimacs, dimacs_max, dual_ray_defect, eig_range, kkt, primal_ray_defect};
use faer::Mat;
use proptest::prelude::*;
use sporadic_sdp::{
    BlockKind, FacialPath, InfeasibilityCertificate, IterationLog, Problem, ProblemBuilder,
    SdpError, Settings, Solver, Status, dimacs_errors, solve,
};

/// SplitMix64: a tiny deterministic generator so that a proptest seed fixes a whole problem.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[lo, hi)`.
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// Random dense matrix with entries in `[-1, 1)`.
fn random_mat(rng: &mut Rng, r: usize, c: usize) -> Mat<f64> {
    Mat::from_fn(r, c, |_, _| rng.uniform(-1.0, 1.0))
}

/// Random orthogonal matrix (Q factor of a random matrix).
fn random_orthogonal(rng: &mut Rng, n: usize) -> Mat<f64> {
    random_mat(rng, n, n).qr().compute_Q()
}

/// Random symmetric positive definite matrix with eigenvalues in `[lo, hi]`.
fn random_spd(rng: &mut Rng, n: usize, lo: f64, hi: f64) -> Mat<f64> {
    let q = random_orthogonal(rng, n);
    let d = Mat::from_fn(n, n, |i, j| if i == j { rng.uniform(lo, hi) } else { 0.0 });
    &q * &d * q.transpose()
}

/// Block layout: `(kind, size)`.
type Layout = Vec<(BlockKind, usize)>;

/// Dense block data of a problem under construction.
struct DenseProblem {
    layout: Layout,
    /// `a[i][k]`: constraint `i`, block `k` (LP blocks as `n×1` columns).
    a: Vec<Vec<Mat<f64>>>,
    c: Vec<Mat<f64>>,
    b: Vec<f64>,
}

fn zero_block(kind: BlockKind, n: usize) -> Mat<f64> {
    match kind {
        BlockKind::Psd => Mat::zeros(n, n),
        BlockKind::Lp => Mat::zeros(n, 1),
    }
}

/// Random symmetric constraint block with the given density of nonzero (upper) entries.
fn random_block(rng: &mut Rng, kind: BlockKind, n: usize, density: f64) -> Mat<f64> {
    let mut m = zero_block(kind, n);
    match kind {
        BlockKind::Lp => {
            for i in 0..n {
                if rng.uniform(0.0, 1.0) < density {
                    m[(i, 0)] = rng.uniform(-1.0, 1.0);
                }
            }
        }
        BlockKind::Psd => {
            for j in 0..n {
                for i in 0..=j {
                    if rng.uniform(0.0, 1.0) < density {
                        let v = rng.uniform(-1.0, 1.0);
                        m[(i, j)] = v;
                        m[(j, i)] = v;
                    }
                }
            }
        }
    }
    m
}

fn inner(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
    let mut s = 0.0;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            s += a[(i, j)] * b[(i, j)];
        }
    }
    s
}

impl DenseProblem {
    fn random(rng: &mut Rng, layout: Layout, m: usize, density: f64) -> Self {
        let a = (0..m)
            .map(|_| {
                layout
                    .iter()
                    .map(|&(kind, n)| random_block(rng, kind, n, density))
                    .collect()
            })
            .collect();
        let c = layout.iter().map(|&(k, n)| zero_block(k, n)).collect();
        Self {
            layout,
            a,
            c,
            b: vec![0.0; m],
        }
    }

    /// `Σ_i w_i A_i` per block.
    fn combine(&self, w: &[f64]) -> Vec<Mat<f64>> {
        let mut out: Vec<Mat<f64>> = self.layout.iter().map(|&(k, n)| zero_block(k, n)).collect();
        for (wi, ai) in w.iter().zip(&self.a) {
            for (o, a) in out.iter_mut().zip(ai) {
                *o += a * faer::Scale(*wi);
            }
        }
        out
    }

    /// `𝒜(X)`.
    fn apply(&self, x: &[Mat<f64>]) -> Vec<f64> {
        self.a
            .iter()
            .map(|ai| ai.iter().zip(x).map(|(a, xk)| inner(a, xk)).sum())
            .collect()
    }

    fn build(&self) -> Problem {
        let mut pb = ProblemBuilder::new(self.b.len());
        for &(kind, n) in &self.layout {
            pb.add_block(kind, n);
        }
        for (i, &bi) in self.b.iter().enumerate() {
            pb.set_b(i, bi);
        }
        let mut put = |con: Option<usize>, k: usize, m: &Mat<f64>| {
            let (kind, n) = self.layout[k];
            for j in 0..n {
                let rows = if kind == BlockKind::Psd { 0..=j } else { j..=j };
                for i in rows {
                    let v = if kind == BlockKind::Psd {
                        m[(i, j)]
                    } else {
                        m[(i, 0)]
                    };
                    if v != 0.0 {
                        match con {
                            None => pb.add_c(k, i, j, v),
                            Some(c) => pb.add_a(c, k, i, j, v),
                        };
                    }
                }
            }
        };
        for (k, ck) in self.c.iter().enumerate() {
            put(None, k, ck);
        }
        for (i, ai) in self.a.iter().enumerate() {
            for (k, aik) in ai.iter().enumerate() {
                put(Some(i), k, aik);
            }
        }
        pb.build().expect("valid generated problem")
    }
}

fn random_layout(rng: &mut Rng, max_blocks: usize, max_n: usize, lp: bool) -> Layout {
    let nb = 1 + rng.below(max_blocks);
    (0..nb)
        .map(|_| {
            let kind = if lp && rng.below(3) == 0 {
                BlockKind::Lp
            } else {
                BlockKind::Psd
            };
            (kind, 1 + rng.below(max_n))
        })
        .collect()
}

fn dims(layout: &Layout) -> usize {
    layout
        .iter()
        .map(|&(k, n)| {
            if k == BlockKind::Psd {
                n * (n + 1) / 2
            } else {
                n
            }
        })
        .sum()
}

/// A problem with planted strictly complementary optimum; returns it with the optimal value.
fn planted_optimum(seed: u64, lp_only: bool) -> (Problem, f64) {
    let mut rng = Rng(seed);
    let layout: Layout = if lp_only {
        vec![(BlockKind::Lp, 3 + rng.below(10))]
    } else {
        random_layout(&mut rng, 3, 6, true)
    };
    let m = 1 + rng.below(dims(&layout).min(12));
    let density = rng.uniform(0.3, 1.0);
    let mut dp = DenseProblem::random(&mut rng, layout.clone(), m, density);
    let mut xs = Vec::new();
    let mut ss = Vec::new();
    for &(kind, n) in &layout {
        let r = rng.below(n + 1);
        // Eigenvalues: the first r belong to X*, the others to S*.
        let lam: Vec<f64> = (0..n).map(|_| rng.uniform(0.5, 2.0)).collect();
        match kind {
            BlockKind::Lp => {
                xs.push(Mat::from_fn(n, 1, |i, _| if i < r { lam[i] } else { 0.0 }));
                ss.push(Mat::from_fn(n, 1, |i, _| if i < r { 0.0 } else { lam[i] }));
            }
            BlockKind::Psd => {
                let q = random_orthogonal(&mut rng, n);
                let dx = Mat::from_fn(n, n, |i, j| if i == j && i < r { lam[i] } else { 0.0 });
                let ds = Mat::from_fn(n, n, |i, j| if i == j && i >= r { lam[i] } else { 0.0 });
                xs.push(&q * &dx * q.transpose());
                ss.push(&q * &ds * q.transpose());
            }
        }
    }
    let y: Vec<f64> = (0..m).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let ay = dp.combine(&y);
    dp.c = ay.iter().zip(&ss).map(|(a, s)| a + s).collect();
    dp.b = dp.apply(&xs);
    let opt: f64 = dp.b.iter().zip(&y).map(|(b, v)| b * v).sum();
    (dp.build(), opt)
}

/// Strictly feasible pair with planted interior points; returns `(problem, bᵀy⁰, ⟨C, X⁰⟩)`.
fn planted_lmi(seed: u64) -> (Problem, f64, f64) {
    let mut rng = Rng(seed);
    let layout = random_layout(&mut rng, 4, 7, true);
    let m = 1 + rng.below(10);
    let density = rng.uniform(0.2, 1.0);
    let mut dp = DenseProblem::random(&mut rng, layout.clone(), m, density);
    let y0: Vec<f64> = (0..m).map(|_| rng.uniform(-2.0, 2.0)).collect();
    let ay = dp.combine(&y0);
    let mut x0 = Vec::new();
    dp.c = Vec::new();
    for (k, &(kind, n)) in layout.iter().enumerate() {
        let (s0, x) = match kind {
            BlockKind::Psd => (
                random_spd(&mut rng, n, 0.1, 3.0),
                random_spd(&mut rng, n, 0.1, 3.0),
            ),
            BlockKind::Lp => (
                Mat::from_fn(n, 1, |_, _| rng.uniform(0.1, 3.0)),
                Mat::from_fn(n, 1, |_, _| rng.uniform(0.1, 3.0)),
            ),
        };
        dp.c.push(&ay[k] + &s0);
        x0.push(x);
    }
    dp.b = dp.apply(&x0);
    let lower: f64 = dp.b.iter().zip(&y0).map(|(b, v)| b * v).sum();
    let upper: f64 = dp.c.iter().zip(&x0).map(|(c, x)| inner(c, x)).sum();
    (dp.build(), lower, upper)
}

/// Whether the equality constraints determine the primal point or are linearly dependent: `m`
/// is at least the dimension of the space (Σ n(n+1)/2 over PSD blocks, Σ n over LP blocks).
/// With `m` equal to it, `X* = 𝒜⁻¹(b)` is the only feasible point and a planted singular `X*`
/// leaves (P) without a Slater point; with `m` above it the Schur matrix is singular (SDPT3
/// removes such constraints in preprocessing, `checkdepconstr.m`; CSDP rejects an empty one).
fn constraints_degenerate(p: &Problem) -> bool {
    let dim: usize = p
        .blocks
        .iter()
        .map(|bd| match bd.block.kind {
            BlockKind::Psd => bd.block.size * (bd.block.size + 1) / 2,
            BlockKind::Lp => bd.block.size,
        })
        .sum();
    p.b.len() >= dim
}

/// [`assert_optimal_kkt`], except where [`constraints_degenerate`]: there the solver may stop
/// early at a reduced accuracy of 1e-6 (as on the ill-posed SDPLIB problems): `AlmostOptimal`,
/// or `NumericalTrouble` only when some DIMACS error exceeds the reduced tolerance.
/// Open weakness, seeds kept: without a Slater point, on 17613675850095599600 (one LP block of
/// 4, m = 4) it stalls at a relative gap of 6e-8 and on 6548234211887345630 (LP block of 5,
/// m = 5) at 3e-7, where CSDP reaches 2e-9 and 3e-11 (on the second the normal equations alone
/// would converge, gap 4e-9; the least-squares fallback, entered when the corrector misses the
/// primal equation at μ ≈ 1e-7, returns steps of 1e-6); with dependent constraints, on
/// `planted_lmi` 16643636388220218415 (LP block of 6, m = 7, one empty constraint) the primal
/// residual stays at 6e-11 and the gap at 1.1e-8.
fn assert_planted_kkt(p: &Problem, sol: &sporadic_sdp::Solution) {
    if !(constraints_degenerate(p)
        && matches!(sol.status, Status::AlmostOptimal | Status::NumericalTrouble))
    {
        return assert_optimal_kkt(p, sol);
    }
    let m = &sol.measures;
    assert_eq!(
        sol.status == Status::AlmostOptimal,
        m.dimacs_max() <= Settings::default().tol_reduced,
        "{:?} {m:?}",
        sol.status
    );
    assert!(
        m.rel_gap <= 1e-6 && m.primal_infeas <= 1e-6 && m.dual_infeas <= 1e-6,
        "{m:?}"
    );
    assert_kkt(p, sol, 2e-6);
}

fn assert_optimal_kkt(p: &Problem, sol: &sporadic_sdp::Solution) {
    assert_eq!(sol.status, Status::Optimal, "measures {:?}", sol.measures);
    assert_kkt(p, sol, 2e-8);
}

/// Independent KKT check of a returned point: infeasibilities, gap and complementarity at most
/// `tol`, both sides positive semidefinite, and at most 40 iterations.
fn assert_kkt(p: &Problem, sol: &sporadic_sdp::Solution, tol: f64) {
    let k = kkt(p, sol);
    assert!(k.pinf <= tol && k.dinf <= tol, "{k:?}");
    assert!(k.gap <= tol && k.compl <= tol, "{k:?}");
    assert!(k.min_eig_x >= -1e-12 && k.min_eig_s >= -1e-12, "{k:?}");
    assert!(sol.iterations <= 40, "{} iterations", sol.iterations);
}

/// A planted problem found by `finds_planted_optimum` in a CI run (2026-11-26): the solve
/// stopped at relative gap 1.6e-6 (DIMACS 5 and 6 at 1.6e-6 and 3.2e-6), short of the 1e-8 the
/// property asks, when the least-squares solve broke down at numerically dependent constraints
/// (issue 23); a regression test since that solve regularises them.
#[test]
fn planted_optimum_seed_5105783315184303210() {
    let (p, _) = planted_optimum(5105783315184303210, false);
    let sol = solve(&p, &Settings::default()).unwrap();
    assert_planted_kkt(&p, &sol);
}

proptest! {
    // A fixed seed, so that CI runs the same 48 planted problems every time; the property
    // found the seed of `planted_optimum_seed_5105783315184303210` with a random seed.
    #![proptest_config(ProptestConfig {
        cases: 48,
        rng_seed: proptest::test_runner::RngSeed::Fixed(23),
        ..ProptestConfig::default()
    })]

    #[test]
    fn finds_planted_optimum(seed in any::<u64>()) {
        let (p, opt) = planted_optimum(seed, false);
        let sol = solve(&p, &Settings::default()).unwrap();
        assert_planted_kkt(&p, &sol);
        let scale = 1.0 + opt.abs();
        prop_assert!((sol.primal_objective - opt).abs() <= 1e-6 * scale,
            "pobj {} vs planted {}", sol.primal_objective, opt);
        prop_assert!((sol.dual_objective - opt).abs() <= 1e-6 * scale);
    }

    #[test]
    fn finds_planted_lp_optimum(seed in any::<u64>()) {
        let (p, opt) = planted_optimum(seed, true);
        let sol = solve(&p, &Settings::default()).unwrap();
        assert_planted_kkt(&p, &sol);
        prop_assert!((sol.primal_objective - opt).abs() <= 1e-6 * (1.0 + opt.abs()));
    }

    #[test]
    fn planted_lmi_bounds(seed in any::<u64>()) {
        let (p, lower, upper) = planted_lmi(seed);
        let sol = solve(&p, &Settings::default()).unwrap();
        assert_planted_kkt(&p, &sol);
        let tol = 1e-6 * (1.0 + lower.abs() + upper.abs());
        prop_assert!(sol.dual_objective >= lower - tol, "{} < {}", sol.dual_objective, lower);
        prop_assert!(sol.primal_objective <= upper + tol, "{} > {}", sol.primal_objective, upper);
    }

    #[test]
    fn dimacs_errors_agree_with_the_solver_and_grow_under_perturbation(seed in any::<u64>()) {
        let (p, _) = planted_optimum(seed, false);
        let sol = solve(&p, &Settings::default()).unwrap();
        let d = dimacs_errors(&p, &sol.y, &sol.x, &sol.s).unwrap();
        // The same kernels as the solver's report: bitwise equal.
        prop_assert_eq!(d, sol.measures.dimacs);
        // And close to an independent dense recomputation: to 1e-6 relative, or 1e-9 absolute
        // where the residuals are rounding noise (on degenerate seeds `y` drifts along a ray
        // and `C − 𝒜ᵀ(y) − S` cancels terms far larger than itself).
        let ind = dimacs(&p, &sol.y, &sol.x, &sol.s);
        for (a, b) in d.iter().zip(&ind) {
            prop_assert!((a - b).abs() <= 1e-9 + 1e-6 * a.abs().max(b.abs()), "{:?} vs {:?}", d, ind);
        }
        // X − (λ_min(X) + δ)I leaves the cone (error 2 > 0) and S + δI breaks the dual
        // equation (error 3).
        let delta = 1e-3;
        let shifted = |v: &[Mat<f64>], t: &dyn Fn(BlockKind, &Mat<f64>) -> f64| -> Vec<Mat<f64>> {
            p.blocks.iter().zip(v).map(|(bd, m)| {
                let shift = t(bd.block.kind, m);
                let mut m = m.clone();
                let n = m.nrows();
                if bd.block.kind == BlockKind::Lp {
                    (0..n).for_each(|i| m[(i, 0)] += shift);
                } else {
                    (0..n).for_each(|i| m[(i, i)] += shift);
                }
                m
            }).collect()
        };
        let out = shifted(&sol.x, &|kind, m| -(eig_range(kind, m).0 + delta));
        let px = dimacs_errors(&p, &sol.y, &out, &sol.s).unwrap();
        prop_assert!(px[1] > d[1] && dimacs_max(&px) > dimacs_max(&d), "{:?} vs {:?}", px, d);
        let ps = dimacs_errors(&p, &sol.y, &sol.x, &shifted(&sol.s, &|_, _| delta)).unwrap();
        prop_assert!(ps[2] > d[2] && dimacs_max(&ps) > dimacs_max(&d), "{:?} vs {:?}", ps, d);
    }

    #[test]
    fn detects_planted_primal_infeasibility(seed in any::<u64>()) {
        let mut rng = Rng(seed);
        let layout = random_layout(&mut rng, 3, 5, true);
        let m = 2 + rng.below(5);
        let mut dp = DenseProblem::random(&mut rng, layout.clone(), m, 0.7);
        // Hidden ray: A_last = −I, b_last = 1, then a random unit-lower-triangular mix.
        dp.a[m - 1] = layout.iter().map(|&(kind, n)| match kind {
            BlockKind::Psd => Mat::from_fn(n, n, |i, j| if i == j { -1.0 } else { 0.0 }),
            BlockKind::Lp => Mat::from_fn(n, 1, |_, _| -1.0),
        }).collect();
        let mut b: Vec<f64> = (0..m).map(|_| rng.uniform(-1.0, 1.0)).collect();
        b[m - 1] = 1.0;
        let t = Mat::from_fn(m, m, |i, j| if i == j { 1.0 } else if j < i { rng.uniform(-1.0, 1.0) } else { 0.0 });
        let mixed_a: Vec<Vec<Mat<f64>>> = (0..m).map(|i| {
            let w: Vec<f64> = (0..m).map(|j| t[(i, j)]).collect();
            dp.combine(&w)
        }).collect();
        dp.b = (0..m).map(|i| (0..m).map(|j| t[(i, j)] * b[j]).sum()).collect();
        dp.a = mixed_a;
        // Dual strictly feasible: C = S⁰ ≻ 0 (y = 0).
        dp.c = layout.iter().map(|&(kind, n)| match kind {
            BlockKind::Psd => random_spd(&mut rng, n, 0.5, 2.0),
            BlockKind::Lp => Mat::from_fn(n, 1, |_, _| rng.uniform(0.5, 2.0)),
        }).collect();
        let p = dp.build();
        let sol = solve(&p, &Settings::default()).unwrap();
        prop_assert_eq!(sol.status, Status::PrimalInfeasible);
        let Some(InfeasibilityCertificate::PrimalInfeasibility { y, .. }) = &sol.certificate else {
            panic!("missing certificate: {:?}", sol.certificate);
        };
        prop_assert!(primal_ray_defect(&p, y) <= 1e-8);
        prop_assert!(sol.certificate.as_ref().unwrap().verify(&p).unwrap() <= 1e-8);
    }

    #[test]
    fn detects_planted_dual_infeasibility(seed in any::<u64>()) {
        let p = planted_dual_infeasible(seed);
        let sol = solve(&p, &Settings::default()).unwrap();
        prop_assert_eq!(sol.status, Status::DualInfeasible);
        let Some(InfeasibilityCertificate::DualInfeasibility { x, .. }) = &sol.certificate else {
            panic!("missing certificate: {:?}", sol.certificate);
        };
        prop_assert!(dual_ray_defect(&p, x) <= 1e-8);
    }
}

/// Dual infeasible problem: `X⁰ ≻ 0` orthogonal to every `A_i`, `⟨C, X⁰⟩ = −1`, and a strictly
/// feasible primal (`b = 𝒜(X¹)`, `X¹ ≻ 0`).
fn planted_dual_infeasible(seed: u64) -> Problem {
    let mut rng = Rng(seed);
    let layout = random_layout(&mut rng, 3, 5, true);
    let m = 1 + rng.below(dims(&layout).saturating_sub(1).clamp(1, 6));
    let mut dp = DenseProblem::random(&mut rng, layout.clone(), m, 0.7);
    let x0: Vec<Mat<f64>> = layout
        .iter()
        .map(|&(kind, n)| match kind {
            BlockKind::Psd => random_spd(&mut rng, n, 0.5, 2.0),
            BlockKind::Lp => Mat::from_fn(n, 1, |_, _| rng.uniform(0.5, 2.0)),
        })
        .collect();
    let xx: f64 = x0.iter().map(|x| inner(x, x)).sum();
    // Make every A_i orthogonal to X⁰ and ⟨C, X⁰⟩ = −1.
    for ai in dp.a.iter_mut() {
        let f: f64 = ai.iter().zip(&x0).map(|(a, x)| inner(a, x)).sum::<f64>() / xx;
        for (a, x) in ai.iter_mut().zip(&x0) {
            *a -= x * faer::Scale(f);
            // Rounding residue of the projection (e.g. a 1×1 block, where A_i must vanish)
            // would leave a dual feasible point with |y| ~ 1e16: make it an exact zero.
            for j in 0..a.ncols() {
                for i in 0..a.nrows() {
                    if a[(i, j)].abs() < 1e-12 {
                        a[(i, j)] = 0.0;
                    }
                }
            }
        }
    }
    let r: Vec<Mat<f64>> = layout
        .iter()
        .map(|&(kind, n)| random_block(&mut rng, kind, n, 1.0))
        .collect();
    let f = (r.iter().zip(&x0).map(|(a, x)| inner(a, x)).sum::<f64>() + 1.0) / xx;
    dp.c = r
        .iter()
        .zip(&x0)
        .map(|(a, x)| a - x * faer::Scale(f))
        .collect();
    // Primal strictly feasible: b = 𝒜(X¹) with X¹ ≻ 0.
    let x1: Vec<Mat<f64>> = layout
        .iter()
        .map(|&(kind, n)| match kind {
            BlockKind::Psd => random_spd(&mut rng, n, 0.5, 2.0),
            BlockKind::Lp => Mat::from_fn(n, 1, |_, _| rng.uniform(0.5, 2.0)),
        })
        .collect();
    dp.b = dp.apply(&x1);
    dp.build()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// `solve` gives the same bits on any thread count, with facial reduction (which applies
    /// when a block of `X*` or some of its LP entries vanish and a constraint touching only
    /// them is semidefinite) and without; without it, so does a [`Solver`] solving twice.
    #[test]
    fn deterministic_and_reusable(seed in any::<u64>()) {
        let (p, _) = planted_optimum(seed, false);
        let off = Settings { facial_reduction: false, ..Settings::default() };
        let a = solve(&p, &Settings::default()).unwrap();
        let b = solve(&p, &Settings { threads: 1, ..Settings::default() }).unwrap();
        let a0 = solve(&p, &off).unwrap();
        let b0 = solve(&p, &Settings { threads: 1, ..off.clone() }).unwrap();
        let mut solver = Solver::new(&p, Settings { threads: 2, ..off }).unwrap();
        let c = solver.solve(&p).unwrap();
        let d = solver.solve(&p).unwrap();
        for (first, other) in [(&a, &b), (&a0, &b0), (&a0, &c), (&a0, &d)] {
            prop_assert_eq!(first.iterations, other.iterations);
            prop_assert_eq!(&first.y, &other.y);
            prop_assert_eq!(&first.x, &other.x);
            prop_assert_eq!(&first.s, &other.s);
            prop_assert_eq!(first.primal_objective.to_bits(), other.primal_objective.to_bits());
        }
    }
}

/// Structure reuse: a problem with the same pattern and new numbers gives bitwise the result of
/// a fresh solve; a problem with a subset of the pattern is accepted; a new entry is rejected.
#[test]
fn solver_reuses_structure() {
    // A seed whose problem has a constraint with at least two entries in some block.
    let seed = (0..)
        .find(|&s| {
            planted_optimum(s, false)
                .0
                .blocks
                .iter()
                .any(|bd| bd.a.iter().any(|(_, a)| a.nnz() > 1))
        })
        .expect("such a seed exists");
    let (p1, _) = planted_optimum(seed, false);
    let (mut p2, _) = planted_optimum(seed, false);
    // Same pattern, new numbers: scale every A_i and C (the optimum scales accordingly).
    for bd in &mut p2.blocks {
        bd.c.vals.iter_mut().for_each(|v| *v *= 2.0);
    }
    let mut solver = Solver::new(&p1, Settings::default()).unwrap();
    let fresh = solve(&p2, &Settings::default()).unwrap();
    let reused = solver.solve(&p2).unwrap();
    assert_eq!(fresh.y, reused.y);
    assert_eq!(fresh.x, reused.x);
    assert_optimal_kkt(&p2, &reused);

    // Subset pattern: drop one entry of one constraint.
    let mut p3 = p1.clone();
    let (blk, pos) = p3
        .blocks
        .iter()
        .enumerate()
        .find_map(|(k, bd)| {
            bd.a.iter()
                .position(|(_, a)| a.nnz() > 1)
                .map(|pos| (k, pos))
        })
        .expect("some constraint with two entries");
    let a = &mut p3.blocks[blk].a[pos].1;
    a.rows.pop();
    a.cols.pop();
    a.vals.pop();
    let sub = solver.solve(&p3).unwrap();
    let direct = solve(&p3, &Settings::default()).unwrap();
    assert_eq!(sub.status, direct.status);
    assert!(
        (sub.primal_objective - direct.primal_objective).abs()
            <= 1e-7 * (1.0 + direct.primal_objective.abs())
    );

    // Entry outside the analysed pattern.
    let mut p4 = p3.clone();
    let mut solver3 = Solver::new(&p3, Settings::default()).unwrap();
    p4.blocks[blk].a[pos].1 = p1.blocks[blk].a[pos].1.clone();
    assert!(matches!(solver3.solve(&p4), Err(SdpError::Structure(_))));
    // Different block layout.
    let (p5, _) = planted_optimum(seed + 1, false);
    if p5.blocks.len() != p1.blocks.len() || p5.b.len() != p1.b.len() {
        assert!(matches!(solver.solve(&p5), Err(SdpError::Structure(_))));
    }
}

/// The dense Cholesky (on one thread for any thread count, here with m = 210) and the rayon
/// Schur assembly give the same bits for any number of threads.
#[test]
fn thread_count_does_not_change_bits() {
    let mut rng = Rng(42);
    let layout: Layout = (0..8)
        .map(|_| (BlockKind::Psd, 12))
        .chain([(BlockKind::Lp, 40)])
        .collect();
    let m = 210;
    let mut dp = DenseProblem::random(&mut rng, layout.clone(), m, 0.15);
    let y0: Vec<f64> = (0..m).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let ay = dp.combine(&y0);
    let x0: Vec<Mat<f64>> = layout
        .iter()
        .map(|&(kind, n)| match kind {
            BlockKind::Psd => random_spd(&mut rng, n, 0.5, 2.0),
            BlockKind::Lp => Mat::from_fn(n, 1, |_, _| rng.uniform(0.5, 2.0)),
        })
        .collect();
    dp.c = ay
        .iter()
        .zip(&layout)
        .map(|(a, &(kind, n))| {
            a + &match kind {
                BlockKind::Psd => random_spd(&mut rng, n, 0.5, 2.0),
                BlockKind::Lp => Mat::from_fn(n, 1, |_, _| rng.uniform(0.5, 2.0)),
            }
        })
        .collect::<Vec<_>>();
    dp.b = dp.apply(&x0);
    let p = dp.build();
    let runs: Vec<_> = [0, 1, 2, 2]
        .iter()
        .map(|&t| {
            solve(
                &p,
                &Settings {
                    threads: t,
                    ..Settings::default()
                },
            )
            .unwrap()
        })
        .collect();
    assert_optimal_kkt(&p, &runs[0]);
    for r in &runs[1..] {
        assert_eq!(r.iterations, runs[0].iterations);
        assert_eq!(r.y, runs[0].y);
        assert_eq!(r.x, runs[0].x);
    }
}

#[test]
fn no_constraints() {
    // m = 0, C ≻ 0: optimum 0 at X = 0, S = C.
    let mut pb = ProblemBuilder::new(0);
    let k = pb.add_block(BlockKind::Psd, 3);
    pb.add_c(k, 0, 0, 2.0)
        .add_c(k, 1, 1, 1.0)
        .add_c(k, 2, 2, 3.0)
        .add_c(k, 0, 1, 0.5);
    let p = pb.build().unwrap();
    let sol = solve(&p, &Settings::default()).unwrap();
    assert_optimal_kkt(&p, &sol);
    assert!(sol.primal_objective.abs() < 1e-8);
    // m = 0, C indefinite: no S = C ⪰ 0, so (D) is infeasible.
    let mut pb = ProblemBuilder::new(0);
    let k = pb.add_block(BlockKind::Psd, 2);
    pb.add_c(k, 0, 0, 1.0).add_c(k, 1, 1, -1.0);
    let p = pb.build().unwrap();
    let sol = solve(&p, &Settings::default()).unwrap();
    assert_eq!(sol.status, Status::DualInfeasible);
    let Some(InfeasibilityCertificate::DualInfeasibility { x, .. }) = &sol.certificate else {
        panic!("{:?}", sol.certificate)
    };
    assert!(dual_ray_defect(&p, x) <= 1e-8);
}

/// Duplicate, empty (free) and zero-right-hand-side constraints keep the Schur matrix singular;
/// the regularised factorisation must still converge.
#[test]
fn dependent_and_empty_constraints() {
    let (p, opt) = planted_optimum(3, false);
    let m = p.b.len();
    let mut q = p.clone();
    q.b.push(p.b[0]); // duplicate of constraint 0
    q.b.push(0.0); // empty constraint: 0 = 0
    for bd in &mut q.blocks {
        if let Some((_, a0)) = bd.a.iter().find(|(i, _)| *i == 0).cloned() {
            bd.a.push((m, a0));
        }
    }
    let sol = solve(&q, &Settings::default()).unwrap();
    assert_optimal_kkt(&q, &sol);
    assert!((sol.primal_objective - opt).abs() <= 1e-6 * (1.0 + opt.abs()));

    // Inconsistent duplicate: ⟨A_0, X⟩ = b_0 and ⟨A_0, X⟩ = b_0 + 1.
    let mut r = q.clone();
    r.b[m] = p.b[0] + 1.0;
    let sol = solve(&r, &Settings::default()).unwrap();
    assert_eq!(sol.status, Status::PrimalInfeasible);
    let Some(InfeasibilityCertificate::PrimalInfeasibility { y, .. }) = &sol.certificate else {
        panic!("{:?}", sol.certificate)
    };
    assert!(primal_ray_defect(&r, y) <= 1e-8);
}

#[test]
fn log_callback_sees_every_iteration() {
    let (p, _) = planted_optimum(11, false);
    let seen: Arc<Mutex<Vec<IterationLog>>> = Arc::default();
    let sink = seen.clone();
    let settings = Settings {
        log: Some(Arc::new(move |l: &IterationLog| {
            sink.lock().unwrap().push(*l)
        })),
        ..Settings::default()
    };
    let sol = solve(&p, &settings).unwrap();
    let seen = seen.lock().unwrap();
    assert_eq!(seen.len(), sol.iterations + 1);
    assert!(seen.iter().enumerate().all(|(i, l)| l.iteration == i));
    let last = seen.last().unwrap();
    assert_eq!(last.primal_objective, sol.primal_objective);
    assert!(last.rel_gap <= 1e-8 && last.primal_infeas <= 1e-8 && last.dual_infeas <= 1e-8);
}

/// A solve inside an exhausted budget scope stops at its first iteration with
/// `Interrupted` (its start point is far from optimal), a raised cancellation flag likewise, and
/// the same solve outside the scope is optimal.
#[test]
fn an_exhausted_budget_interrupts_the_solve() {
    use sporadic_sdp::budget::{Budget, within};
    let (p, _) = planted_optimum(11, false);
    let sol = within(Budget::until(std::time::Instant::now()), || {
        solve(&p, &Settings::default()).unwrap()
    });
    assert_eq!(sol.status, Status::Interrupted);
    assert_eq!(sol.iterations, 0);
    // Also when the iteration runs on a worker of a thread pool (threads = 2).
    let two = Settings {
        threads: 2,
        ..Settings::default()
    };
    let sol = within(Budget::until(std::time::Instant::now()), || {
        solve(&p, &two).unwrap()
    });
    assert_eq!(sol.status, Status::Interrupted);
    let flag = Arc::new(std::sync::atomic::AtomicBool::new(true));
    let sol = within(Budget::unlimited().with_cancel(flag), || {
        solve(&p, &Settings::default()).unwrap()
    });
    assert_eq!(sol.status, Status::Interrupted);
    assert_eq!(
        solve(&p, &Settings::default()).unwrap().status,
        Status::Optimal
    );
}

/// `Solver::solve_until`: a test that accepts nothing leaves the solve exactly as
/// `Solver::solve` (bitwise); one that accepts from iteration 5 ends the solve there with
/// `Accepted` and returns that iterate (the `y` it was shown), not the best point.
#[test]
fn an_acceptance_test_ends_the_solve_at_the_iterate_it_accepts() {
    let (p, _) = planted_optimum(17, false);
    let plain = Solver::new(&p, Settings::default())
        .unwrap()
        .solve(&p)
        .unwrap();
    let mut seen = 0usize;
    let never = Solver::new(&p, Settings::default())
        .unwrap()
        .solve_until(&p, None, &mut |_, _| {
            seen += 1;
            false
        })
        .unwrap();
    assert_eq!(never.status, plain.status);
    assert_eq!(never.y, plain.y);
    assert_eq!(never.iterations, plain.iterations);
    // Shown every iterate but the optimal one.
    assert_eq!(seen, plain.iterations);
    let mut shown = Vec::new();
    let at_five = Solver::new(&p, Settings::default())
        .unwrap()
        .solve_until(&p, None, &mut |y, state| {
            shown = y.to_vec();
            state.iteration >= 5
        })
        .unwrap();
    assert!(plain.iterations > 5, "{}", plain.iterations);
    assert_eq!(at_five.status, Status::Accepted);
    assert_eq!(at_five.iterations, 5);
    assert_eq!(at_five.y, shown);
    // Its measures are those of that iterate, which is not optimal.
    assert!(
        at_five.measures.dimacs_max() > 1e-8,
        "{:?}",
        at_five.measures
    );
}

#[test]
fn invalid_input_is_an_error() {
    let (p, _) = planted_optimum(5, false);
    let mut bad = p.clone();
    bad.blocks[0].c.rows.push(0);
    bad.blocks[0].c.cols.push(0);
    bad.blocks[0].c.vals.push(f64::NAN);
    assert!(solve(&bad, &Settings::default()).is_err());

    let mut bad = p.clone();
    bad.b[0] = f64::INFINITY;
    assert!(matches!(
        solve(&bad, &Settings::default()),
        Err(SdpError::NonFinite { .. })
    ));

    let mut bad = p.clone();
    let size = bad.blocks[0].block.size;
    if let Some((_, a)) = bad.blocks[0].a.first_mut() {
        a.rows.push(0);
        a.cols.push(size); // out of range
        a.vals.push(1.0);
        assert!(matches!(
            solve(&bad, &Settings::default()),
            Err(SdpError::Structure(_))
        ));
    }

    let mut bad = p.clone();
    bad.blocks[0].a.push((p.b.len() + 3, Default::default()));
    assert!(matches!(
        solve(&bad, &Settings::default()),
        Err(SdpError::Structure(_))
    ));

    let mut bad = p.clone();
    bad.blocks[0].block.size = usize::MAX / 2;
    assert!(matches!(
        solve(&bad, &Settings::default()),
        Err(SdpError::Structure(_))
    ));

    for settings in [
        Settings {
            tol_gap: 0.0,
            ..Settings::default()
        },
        Settings {
            tol_feas: f64::NAN,
            ..Settings::default()
        },
        Settings {
            step_fraction: Some(1.5),
            ..Settings::default()
        },
    ] {
        assert!(matches!(
            solve(&p, &settings),
            Err(SdpError::InvalidSettings(_))
        ));
    }
}

/// Regression (seed found by `finds_planted_optimum`): the planted problem has an empty
/// constraint `A_4 = 0` with `b_4 = 0` (CSDP refuses it: "Constraint 4 is empty"). Once the
/// normal equations became inaccurate the solver switched to the least-squares form, whose
/// Householder QR of the zero column made `Δy` overflow (steps of 1e-150, `NumericalTrouble`
/// with a relative gap of 5e-7); it must reach the planted optimum with verified KKT residuals.
#[test]
fn empty_constraint_keeps_normal_equations() {
    let (p, opt) = planted_optimum(5007805108508768314, false);
    assert!(
        p.blocks.iter().all(|b| b
            .a
            .iter()
            .all(|(i, a)| *i != 3 || a.vals.iter().all(|v| *v == 0.0))),
        "the case must keep its empty constraint"
    );
    let sol = solve(&p, &Settings::default()).unwrap();
    assert_optimal_kkt(&p, &sol);
    let scale = 1.0 + opt.abs();
    assert!(
        (sol.primal_objective - opt).abs() <= 1e-6 * scale,
        "pobj {} vs {opt}",
        sol.primal_objective
    );
    assert!(
        (sol.dual_objective - opt).abs() <= 1e-6 * scale,
        "dobj {} vs {opt}",
        sol.dual_objective
    );
}

/// A planted problem whose primal has no strictly feasible point, its optimal value, and the
/// same problem written directly on its face. Block 0 (PSD, order `n`) meets the exposing
/// constraint `0`, `⟨−U D Uᵀ, X_0⟩ − x_0 − 2x_1 = 0` (`U` the last `r` columns of a random
/// orthogonal `Q`, `D ≻ 0`, `x` the LP block): negative semidefinite with `b_0 = 0`, so every
/// feasible point has `X_0 = V Y Vᵀ` (`V` the other columns of `Q`) and `x_0 = x_1 = 0`. Block 1
/// (PSD) is untouched. Constraint 1 is the trace of everything, the rest are random.
///
/// The optimum is planted with an attained dual (as in gpp; without one no finite `y_0` makes
/// `S` semidefinite to the tolerance): `X*_0 = V Y* Vᵀ`, and with `S̃` complementary to `Y*` on
/// the face, `S*_0 = [V U] [[S̃, S̃L], [LᵀS̃, LᵀS̃L + G]] [V U]ᵀ ⪰ 0` (random `L`, `G ≻ 0`), which
/// couples the face to its complement and still has `⟨S*_0, X*_0⟩ = ⟨S̃, Y*⟩ = 0`; blocks 1 and 2
/// get strictly complementary pairs, `C = Σ y*_i A_i + S*`, `b = 𝒜(X*)` with `b_0 = 0`. The
/// second problem has `VᵀC_0V`, `VᵀA_{i,0}V` in block 0, LP entries 2 and 3, no constraint 0.
///
/// With `attained` false, `S*_0` is instead a random positive definite matrix: (D) stays strictly
/// feasible, but `⟨S*_0, X*_0⟩ > 0`, the planted point is not optimal (the value returned is
/// then meaningless) and the optimum of (D) is in general not attained.
fn planted_face(seed: u64, attained: bool) -> (Problem, f64, Problem) {
    let mut rng = Rng(seed);
    let (n, r, n1) = (4 + rng.below(4), 1 + rng.below(2), 2 + rng.below(3));
    let nf = n - r;
    let layout = vec![
        (BlockKind::Psd, n),
        (BlockKind::Psd, n1),
        (BlockKind::Lp, 4),
    ];
    let m = 3 + rng.below(4);
    let mut dp = DenseProblem::random(&mut rng, layout.clone(), m, 0.7);
    let q = random_orthogonal(&mut rng, n);
    let v = q.subcols(0, nf).to_owned();
    let u = q.subcols(nf, r).to_owned();
    let d = Mat::from_fn(
        r,
        r,
        |i, j| if i == j { rng.uniform(0.5, 2.0) } else { 0.0 },
    );
    dp.a[0] = vec![
        -(&u * &d * u.transpose()),
        zero_block(BlockKind::Psd, n1),
        faer::mat![[-1.0], [-2.0], [0.0], [0.0]],
    ];
    dp.a[1] = vec![
        Mat::identity(n, n),
        Mat::identity(n1, n1),
        Mat::from_fn(4, 1, |_, _| 1.0),
    ];
    // Strictly complementary pair of order `n` with `X` of rank `k`.
    let pair = |rng: &mut Rng, n: usize, k: usize| {
        let p = random_orthogonal(rng, n);
        let lam: Vec<f64> = (0..n).map(|_| rng.uniform(0.5, 2.0)).collect();
        let dx = Mat::from_fn(n, n, |i, j| if i == j && i < k { lam[i] } else { 0.0 });
        let ds = Mat::from_fn(n, n, |i, j| if i == j && i >= k { lam[i] } else { 0.0 });
        (&p * dx * p.transpose(), &p * ds * p.transpose())
    };
    let k = 1 + rng.below(nf);
    let (y_face, s_face) = pair(&mut rng, nf, k);
    let k1 = rng.below(n1 + 1);
    let (x1, s1) = pair(&mut rng, n1, k1);
    let l = random_mat(&mut rng, nf, r);
    let sl = &s_face * &l;
    let g = l.transpose() * &sl + random_spd(&mut rng, r, 0.5, 2.0);
    let s0 = if attained {
        &v * &s_face * v.transpose()
            + &v * &sl * u.transpose()
            + &u * sl.transpose() * v.transpose()
            + &u * &g * u.transpose()
    } else {
        random_spd(&mut rng, n, 0.5, 2.0)
    };
    let xs = vec![
        &v * &y_face * v.transpose(),
        x1,
        faer::mat![[0.0], [0.0], [rng.uniform(0.5, 2.0)], [0.0]],
    ];
    let ss = vec![
        s0,
        s1,
        faer::mat![
            [rng.uniform(0.5, 2.0)],
            [rng.uniform(0.5, 2.0)],
            [0.0],
            [rng.uniform(0.5, 2.0)]
        ],
    ];
    let y: Vec<f64> = (0..m).map(|_| rng.uniform(-1.0, 1.0)).collect();
    dp.c = dp.combine(&y).iter().zip(&ss).map(|(a, s)| a + s).collect();
    dp.b = dp.apply(&xs);
    dp.b[0] = 0.0;
    let opt: f64 = dp.b.iter().zip(&y).map(|(b, v)| b * v).sum();
    let on_face = |blocks: &[Mat<f64>]| {
        vec![
            v.transpose() * &blocks[0] * &v,
            blocks[1].clone(),
            blocks[2].subrows(2, 2).to_owned(),
        ]
    };
    let face = DenseProblem {
        layout: vec![
            (BlockKind::Psd, nf),
            (BlockKind::Psd, n1),
            (BlockKind::Lp, 2),
        ],
        a: dp.a[1..].iter().map(|a| on_face(a)).collect(),
        c: on_face(&dp.c),
        b: dp.b[1..].to_vec(),
    };
    (dp.build(), opt, face.build())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Facial reduction: the planted problem without a Slater point (with an attained dual) ends
    /// `Optimal` with a point from the face (plain or corrected lift, never the fallback
    /// solve), every DIMACS error within the default tolerance `1e-8` (recomputed
    /// independently against the original data), its LP entries fixed by the exposing
    /// constraint exactly zero, and its objective within `1e-7` (relative) of the planted
    /// optimum and of the optimum of the problem written directly on the face — which has a
    /// Slater point, so facial reduction leaves its solve bitwise unchanged.
    #[test]
    fn facial_reduction_solves_on_the_face(seed in any::<u64>()) {
        let (p, opt, face) = planted_face(seed, true);
        let sol = solve(&p, &Settings::default()).unwrap();
        let e = dimacs(&p, &sol.y, &sol.x, &sol.s);
        prop_assert_eq!(sol.status, Status::Optimal, "DIMACS {:?}", e);
        prop_assert!(
            matches!(sol.facial, FacialPath::Lifted | FacialPath::Corrected), "{}", sol.facial
        );
        prop_assert!(dimacs_max(&e) <= 1e-8, "DIMACS {:?}", e);
        let (x0, x1) = (sol.x[2][(0, 0)], sol.x[2][(1, 0)]);
        prop_assert!(x0 == 0.0 && x1 == 0.0, "LP entries fixed at zero: {} {}", x0, x1);
        let reference = solve(&face, &Settings::default()).unwrap();
        prop_assert_eq!(reference.status, Status::Optimal);
        let off = Settings { facial_reduction: false, ..Settings::default() };
        let plain = solve(&face, &off).unwrap();
        prop_assert_eq!((&plain.x, &plain.y, &plain.s), (&reference.x, &reference.y, &reference.s));
        let (f, g) = (sol.primal_objective, reference.primal_objective);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-7 * (1.0 + b.abs());
        prop_assert!(close(f, g) && close(f, opt), "objective {} vs {} on the face, {} planted", f, g, opt);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Facial reduction when the optimum of (D) is in general not attained: the multiplier of
    /// the exposing constraint may have to be large, and the status must say what the lifted
    /// point reaches — `Optimal` only with the gap, complementarity and cone errors within
    /// `1e-8`, `Optimal`/`AlmostOptimal` only with every DIMACS error within `1e-6`, and any
    /// other status only outside it (recomputed independently against the original data; the
    /// smallest eigenvalue of `S` is known to `8ε‖S‖_F`, allowed either way). A solved point
    /// has the optimum of the problem written on the face.
    #[test]
    fn facial_reduction_status_is_honest(seed in any::<u64>()) {
        let (p, _, face) = planted_face(seed, false);
        let sol = solve(&p, &Settings::default()).unwrap();
        let mut e = dimacs(&p, &sol.y, &sol.x, &sol.s);
        // Eigenvalues of S, which carries the multiplier of the exposing constraint, are
        // computed to about ε‖S‖ (both here and by the solver): that much is allowed.
        let s_fro: f64 = sol.s.iter().map(|m| inner(m, m)).sum::<f64>().sqrt();
        let c_max = p.dense_objective().iter().fold(0.0f64, |a, m| {
            (0..m.ncols()).fold(a, |a, j| m.col_as_slice(j).iter().fold(a, |a, v| a.max(v.abs())))
        });
        let accuracy = 8.0 * f64::EPSILON * s_fro / (1.0 + c_max);
        let mut upper = e;
        upper[3] += accuracy;
        e[3] = (e[3] - accuracy).max(0.0);
        let slack = 1.0 + 1e-3;
        // Never worse than without reduction: a status class at least as good, and the point
        // of the solve without reduction itself when the face lost.
        let off = Settings { facial_reduction: false, ..Settings::default() };
        let plain = solve(&p, &off).unwrap();
        prop_assert!(
            status_class(sol.status) <= status_class(plain.status),
            "{:?} ({}) vs {:?} without reduction", sol.status, sol.facial, plain.status
        );
        if let FacialPath::Unreduced { face: lost } = sol.facial {
            // The face lost by the rule (a point from the face, not a reduced infeasibility).
            prop_assert!(
                lost.is_infeasible() || status_class(lost) >= status_class(plain.status),
                "{:?}",
                lost
            );
            prop_assert_eq!((&sol.x, &sol.y, &sol.s), (&plain.x, &plain.y, &plain.s));
        }
        if sol.status == Status::Optimal {
            prop_assert!(
                [e[1], e[3], e[4].abs(), e[5]].iter().all(|&v| v <= 1e-8 * slack),
                "Optimal with DIMACS {:?}", e
            );
        }
        if sol.status.is_solved() {
            prop_assert!(dimacs_max(&e) <= 1e-6 * slack, "{:?} with DIMACS {:?}", sol.status, e);
            let reference = solve(&face, &Settings::default()).unwrap();
            let (f, g) = (sol.primal_objective, reference.primal_objective);
            prop_assert!((f - g).abs() <= 1e-6 * (1.0 + g.abs()), "objective {} vs {}", f, g);
        } else {
            prop_assert!(
                dimacs_max(&upper) > 1e-6 / slack, "{:?} with DIMACS {:?}", sol.status, upper
            );
        }
    }
}

/// Rank of a status for "at least as good": optimal, almost optimal, a verified infeasibility
/// certificate, anything else (the classes of the rule in module `facial`).
fn status_class(status: Status) -> u8 {
    if status.is_optimal() {
        0
    } else if status.is_almost_optimal() {
        1
    } else if status.is_infeasible() {
        2
    } else {
        3
    }
}

/// The seed CI found (commit 8baa302): the reduced solve is optimal, but its dual is not the
/// projection of an original dual solution, and the plain lift needed a multiplier `6.3e9`
/// for the exposing constraint, whose rounding left a complementarity of `1.6e-8`
/// (`NumericalTrouble`). The dual corrected to `S X = 0` lifts to an optimal point.
#[test]
fn facial_reduction_corrects_the_dual() {
    let (p, opt, _) = planted_face(18151260962617390670, true);
    let sol = solve(&p, &Settings::default()).unwrap();
    let e = dimacs(&p, &sol.y, &sol.x, &sol.s);
    assert_eq!(sol.facial, FacialPath::Corrected, "DIMACS {e:?}");
    assert_eq!(sol.status, Status::Optimal, "DIMACS {e:?}");
    assert!(dimacs_max(&e) <= 1e-8, "DIMACS {e:?}");
    let f = sol.primal_objective;
    assert!(
        (f - opt).abs() <= 1e-7 * (1.0 + opt.abs()),
        "objective {f} vs {opt}"
    );
}

/// How the facial reduction ends on `PROPTEST_CASES` (default 2000) planted problems of each
/// kind, against the solve without reduction: a table of (status, path, status without
/// reduction), and no case in a worse status class. The figures of the module documentation
/// of `facial` come from it (`cargo test --release --test solver_props facial_reduction_survey
/// -- --ignored --nocapture`).
#[test]
#[ignore = "a survey of 4000 solves (~5 s), kept out of the default run; run, gating, by .ci/run: cargo test --release -p sporadic-sdp --test solver_props -- --ignored facial_reduction_survey"]
fn facial_reduction_survey() {
    use std::collections::BTreeMap;
    let cases: u64 = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2000);
    let off = Settings {
        facial_reduction: false,
        ..Settings::default()
    };
    for attained in [true, false] {
        let mut table: BTreeMap<String, usize> = BTreeMap::new();
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for _ in 0..cases {
            let seed = rng.next_u64();
            let (p, _, _) = planted_face(seed, attained);
            let on = solve(&p, &Settings::default()).unwrap();
            let plain = solve(&p, &off).unwrap();
            assert!(
                status_class(on.status) <= status_class(plain.status),
                "seed {seed}: {:?} ({}) vs {:?} without reduction",
                on.status,
                on.facial,
                plain.status
            );
            let row = format!("{} | {} | without: {}", on.status, on.facial, plain.status);
            *table.entry(row).or_default() += 1;
        }
        println!("attained dual: {attained}");
        table.iter().for_each(|(row, n)| println!("{n:6}  {row}"));
    }
}
