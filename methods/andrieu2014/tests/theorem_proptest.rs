//! Property test of Theorem 2 of Andrieu et al. (2014): random admissible designs (random Hurwitz K with
//! real poles, n = 2 or 3, α ∈ (0, α_m), a2 ≥ a2,min(α), a3 = 2n) on random globally Lipschitz
//! lower-triangular systems `f_j(x) = Σ_{i≤j} w_ji sin(x_i + φ_ji)` (`c = max|w_ji|`, `w = 0` is the
//! chain of integrators). At every sample: the structural invariants of `common`, the Lyapunov
//! decrease of Step 3 of the proof; at the end: the error has converged.

mod common;

use proptest::prelude::*;
use sporadic_andrieu2014::system::incremental_bound_ratio;
use sporadic_andrieu2014::{
    Design, Error, NormalFormPlant, RunOptions, TriangularSystem, lyapunov_steps, run,
};
use sporadic_sim::{PiecewiseConstant, ZeroNoise};

#[derive(Debug, Clone)]
struct SineChain {
    n: usize,
    /// Row-major lower triangle: w[j][i], i ≤ j.
    w: Vec<Vec<f64>>,
    phase: Vec<Vec<f64>>,
    c: f64,
}

impl TriangularSystem for SineChain {
    fn order(&self) -> usize {
        self.n
    }
    fn input_dim(&self) -> usize {
        0
    }
    fn nonlinearity(&self, x: &[f64], _u: &[f64], out: &mut [f64]) {
        for j in 0..self.n {
            out[j] = (0..=j)
                .map(|i| self.w[j][i] * (x[i] + self.phase[j][i]).sin())
                .sum();
        }
    }
    fn lipschitz(&self, _xhat: &[f64], _u: &[f64]) -> f64 {
        self.c
    }
}

/// `[c_1, …, c_n]` of `∏ (s + λ_i) = s^n + c_1 s^{n−1} + … + c_n`.
fn poly_from_poles(poles: &[f64]) -> Vec<f64> {
    let mut c = vec![1.0];
    for &l in poles {
        let mut next = vec![0.0; c.len() + 1];
        for (i, &ci) in c.iter().enumerate() {
            next[i] += ci;
            next[i + 1] += l * ci;
        }
        c = next;
    }
    c[1..].to_vec()
}

/// One random test case.
#[derive(Debug, Clone)]
struct Case {
    /// Poles `−λ_i` of `A + KC`.
    poles: Vec<f64>,
    /// Lower triangle of the weights `w_ji` (row-major).
    w: Vec<f64>,
    /// Lower triangle of the phases `φ_ji`.
    ph: Vec<f64>,
    x0: Vec<f64>,
    e0: Vec<f64>,
    /// `α / α_m`.
    frac: f64,
    /// `a2 / a2,min − 1`.
    a2_extra: f64,
    l0: f64,
    /// Lyapunov weight ratio `r − 0.05`.
    r: f64,
    /// Zero nonlinearity (chain of integrators, `c = 0`).
    linear: bool,
}

fn case() -> impl Strategy<Value = Case> {
    (2usize..=3).prop_flat_map(|n| {
        let tri = n * (n + 1) / 2;
        (
            (
                prop::collection::vec(0.6f64..2.0, n),
                prop::collection::vec(-0.5f64..0.5, tri),
                prop::collection::vec(0.0f64..6.3, tri),
                prop::collection::vec(-1.0f64..1.0, n),
                prop::collection::vec(-1.0f64..1.0, n),
            ),
            (
                0.2f64..0.95,
                0.0f64..1.0,
                1.0f64..3.0,
                0.0f64..1.0,
                proptest::bool::weighted(0.2),
            ),
        )
            .prop_map(
                |((poles, w, ph, x0, e0), (frac, a2_extra, l0, r, linear))| Case {
                    poles,
                    w,
                    ph,
                    x0,
                    e0,
                    frac,
                    a2_extra,
                    l0,
                    r,
                    linear,
                },
            )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    #[test]
    fn theorem2_invariants_and_convergence(
        case in case()
    ) {
        let Case { poles, w, ph, x0, e0, frac, a2_extra, l0, r, linear } = case;
        prop_assume!(e0.iter().map(|v| v * v).sum::<f64>() >= 0.01, "initial error too small");
        let xhat0: Vec<f64> = x0.iter().zip(&e0).map(|(a, b)| a + b).collect();
        let n = poles.len();
        let k: Vec<f64> = poly_from_poles(&poles).iter().map(|c| -c).collect();
        let weights: Vec<f64> = (0..n).map(|i| (0.05 + r).powi(i as i32)).collect();
        let design = match Design::new(&k, &weights) {
            Ok(d) => d,
            Err(Error::NotDiagonallyDominated { .. }) => return Err(TestCaseError::reject("p3 <= 0")),
            Err(e) => panic!("{e}"),
        };
        let alpha = frac * design.alpha_m();
        let tuning = design.tuning(alpha, design.a2_min(alpha).unwrap() * (1.0 + a2_extra)).unwrap();
        let mut wm = vec![vec![0.0; n]; n];
        let mut pm = vec![vec![0.0; n]; n];
        let mut idx = 0;
        for j in 0..n {
            for i in 0..=j {
                wm[j][i] = if linear { 0.0 } else { w[idx] };
                pm[j][i] = ph[idx];
                idx += 1;
            }
        }
        let c = wm.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
        let sys = SineChain { n, w: wm, phase: pm, c };
        // The system really satisfies Assumption 1 with this c.
        let e: Vec<f64> = xhat0.iter().zip(&x0).map(|(a, b)| a - b).collect();
        prop_assert!(incremental_bound_ratio(&sys, &xhat0, &e, &[]).unwrap() <= 1.0 + 1e-12);

        let input = PiecewiseConstant::constant(vec![]).unwrap();
        let opts = RunOptions { l0, record_steps: false, max_samples: Some(10_000), ..RunOptions::new(40.0) };
        let r = run(&NormalFormPlant(sys.clone()), &x0, &sys, &xhat0, &input, &tuning, &mut ZeroNoise::new(1), &opts).unwrap();
        common::assert_invariants(&r, &tuning, 1e-6);
        // Numerical floor of the scaled error ‖E_k‖: the states are resolved to ~ (rtol + ε)(1 + |x|),
        // and E_k scales the output error by 1/L_k (see `LyapunovStep::scaled_norm`).
        let floor = |l: f64| (opts.rtol + 4.0 * f64::EPSILON) * (1.0 + x0.iter().fold(0.0f64, |a, b| a.max(b.abs()))) / l;
        let steps = lyapunov_steps(&design, &tuning, &r).unwrap();
        let mut checked = 0;
        for s in steps.iter().filter(|s| s.scaled_norm > 1e4 * floor(s.l_start)) {
            checked += 1;
            prop_assert!(s.holds(1e-9), "Lyapunov decrease fails at t = {}: ΔV = {:e}, bound {:e}", s.t, s.v_after - s.v_before, s.bound);
        }
        prop_assert!(checked >= 3, "only {checked} samples above the numerical floor");
        // Convergence of the scaled error to its numerical floor (from O(‖E_0‖)).
        let last = steps.last().unwrap();
        let tail = r.samples.last().unwrap();
        let e_last = sporadic_andrieu2014::certificate::scaled_error(&tail.error(), tail.l_plus);
        let e_last = e_last.iter().map(|v| v * v).sum::<f64>().sqrt();
        prop_assert!(
            e_last <= 1e-6 * steps[0].scaled_norm + 1e4 * floor(tail.l_plus),
            "‖E‖ = {e_last:e} after {} samples (t = {}), ‖E_0‖ = {:e}, c = {c}", r.samples.len(), last.t, steps[0].scaled_norm
        );
    }
}
