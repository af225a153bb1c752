//! Normalisation of the design problem (issue 22: scale-invariant verdicts).
//!
//! LMI (41) is invariant in exact arithmetic under a change of time unit (the set
//! `{e^{Av} : v ∈ [T1, T2]}` does not change), of state coordinates `x' = Dx` (congruence of
//! every block by `D⁻ᵀ`) and of output units `y' = Sy`; its numerical solution is not: with the
//! normalisation `‖P‖₂ ≤ 1` of the margin problem, a badly scaled plant has a certificate with
//! tiny entries in some directions and a margin far below the solver's verification threshold.
//! Before the LMI is solved the problem is therefore brought to a normal form, with every
//! scaling a power of two (so that it is exact in floating point and leaves already
//! well-scaled data untouched):
//!
//! * **time**: `k = 2^round(log₂ T2)`, `A₁ = kA`, window `[T1/k, T2/k]` (`T2/k ∈ [0.7, 1.4]`);
//! * **states and outputs**: `D = diag(2^δ)` with `2^δ_j` the largest entry of column `j` of the
//!   observability matrix `[C; CA₁; …; CA₁^{n−1}]` rounded to a power of two (so that it has unit
//!   columns in the new coordinates), then `S = diag(2^σ)` making the largest entry of each row of
//!   `S C D⁻¹` about one;
//!   it is applied only when the exponents `δ` spread over more than a factor
//!   `2^BALANCE_DEAD_ZONE` (well-scaled data is left as it is; then only `S`, from the geometric
//!   mean of each row of `C`). `O` is equivariant under `x → Tx` (`O → OT⁻¹`) and `y → cy`, so
//!   the normalised problem is the same up to a power of two per coordinate.
//!
//! The design is done on `(D A₁ D⁻¹, S C D⁻¹)` and the window `[T1/k, T2/k]`, and mapped back:
//! `L = D⁻¹ L' S` (jump gains are dimensionless under time scaling), `P = DᵀP'D`,
//! `F = DᵀF'D`, `J = DᵀJ'S`. Condition (12) is re-verified on the user's data.

use faer::{Mat, MatRef};

use crate::system::Plant;
use sporadic_model::SamplingWindow;

/// Spread (in powers of two) of the rounded balancing exponents below which no balancing is
/// applied.
pub const BALANCE_DEAD_ZONE: i32 = 2;

/// Largest exponent magnitude of a balancing factor (keeps every scaled entry finite).
const MAX_EXPONENT: f64 = 400.0;

/// The exact (power-of-two) scalings taking the user's problem to the normalised one.
#[derive(Debug, Clone, PartialEq)]
pub struct Scaling {
    /// Time unit `k` (new time = old time / `k`).
    pub time: f64,
    /// State scaling `D` (diagonal entries; `x' = Dx`).
    pub state: Vec<f64>,
    /// Output scaling `S` (diagonal entries; `y' = Sy`).
    pub output: Vec<f64>,
}

impl Scaling {
    /// Whether this scaling changes nothing.
    pub fn is_identity(&self) -> bool {
        self.time == 1.0
            && self.state.iter().all(|d| *d == 1.0)
            && self.output.iter().all(|s| *s == 1.0)
    }

    /// The normalised window `[T1/k, T2/k]`.
    pub fn window(&self, w: &SamplingWindow) -> Option<SamplingWindow> {
        SamplingWindow::new(w.t1() / self.time, w.t2() / self.time).ok()
    }

    /// The normalised plant `(k D A D⁻¹, S C D⁻¹)` (`None` when an entry is not finite).
    pub fn plant(&self, p: &Plant) -> Option<Plant> {
        let (a, c, d, s) = (p.a(), p.c(), &self.state, &self.output);
        let a1 = Mat::from_fn(p.n(), p.n(), |i, j| self.time * (d[i] * a[(i, j)] / d[j]));
        let c1 = Mat::from_fn(p.q(), p.n(), |i, j| s[i] * c[(i, j)] / d[j]);
        Plant::new(a1.as_ref(), c1.as_ref()).ok()
    }

    /// `L = D⁻¹ L' S`.
    pub fn gain_back(&self, l: MatRef<'_, f64>) -> Mat<f64> {
        Mat::from_fn(l.nrows(), l.ncols(), |i, j| {
            l[(i, j)] / self.state[i] * self.output[j]
        })
    }

    /// `X = Dᵀ X' D` (for `P` and `F`).
    pub fn congruence_back(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        let d = &self.state;
        Mat::from_fn(x.nrows(), x.ncols(), |i, j| d[i] * x[(i, j)] * d[j])
    }

    /// `J = Dᵀ J' S`.
    pub fn multiplier_gain_back(&self, j: MatRef<'_, f64>) -> Mat<f64> {
        Mat::from_fn(j.nrows(), j.ncols(), |r, c| {
            self.state[r] * j[(r, c)] * self.output[c]
        })
    }
}

/// `2^round(log₂ x)` for a positive finite `x` (1 otherwise).
fn power_of_two(x: f64) -> f64 {
    if x.is_finite() && x > 0.0 {
        2f64.powi(x.log2().round().clamp(-MAX_EXPONENT, MAX_EXPONENT) as i32)
    } else {
        1.0
    }
}

/// The normalising scaling of `plant` on `window` (see the module docs).
pub fn scaling(plant: &Plant, window: &SamplingWindow) -> Scaling {
    let (n, q) = (plant.n(), plant.q());
    let time = power_of_two(window.t2());
    let identity = Scaling {
        time,
        state: vec![1.0; n],
        output: vec![1.0; q],
    };
    let (a, c) = (plant.a(), plant.c());
    // Observability scaling: D_j = largest entry of column j of O = [C; CA₁; …; CA₁^{n−1}]
    // with A₁ = kA (A₁/‖A₁‖_max instead when the powers overflow); x' = Dx gives O unit columns.
    let a1 = Mat::from_fn(n, n, |i, j| a[(i, j)] * time);
    let columns = |nu: f64| {
        let a1 = Mat::from_fn(n, n, |i, j| a1[(i, j)] / nu);
        let mut block = c.to_owned();
        let mut col = vec![0.0f64; n];
        for _ in 0..n {
            for (j, cj) in col.iter_mut().enumerate() {
                for k in 0..q {
                    *cj = cj.max(block[(k, j)].abs());
                }
            }
            block = &block * &a1;
        }
        col
    };
    let mut col = columns(1.0);
    if col.iter().any(|v| !v.is_finite()) {
        col = columns(a1.norm_max().max(1.0));
    }
    if col.iter().any(|v| !v.is_finite()) {
        return identity;
    }
    // An unobservable coordinate (zero column) keeps its unit.
    let e: Vec<f64> = col
        .iter()
        .map(|v| {
            if *v > 0.0 {
                v.log2().round().clamp(-MAX_EXPONENT, MAX_EXPONENT)
            } else {
                0.0
            }
        })
        .collect();
    let lo = e[..n].iter().copied().fold(f64::INFINITY, f64::min);
    let hi = e[..n].iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if hi - lo <= f64::from(BALANCE_DEAD_ZONE) {
        // States left as they are; each output row still scaled to unit geometric mean.
        let output = (0..q)
            .map(|k| {
                let logs: Vec<f64> = (0..n)
                    .map(|j| c[(k, j)].abs())
                    .filter(|v| *v > 0.0 && v.is_finite())
                    .map(f64::log2)
                    .collect();
                if logs.is_empty() {
                    1.0
                } else {
                    let mean = -logs.iter().sum::<f64>() / logs.len() as f64;
                    2f64.powi(mean.round().clamp(-MAX_EXPONENT, MAX_EXPONENT) as i32)
                }
            })
            .collect();
        return Scaling { output, ..identity };
    }
    let state: Vec<f64> = e.iter().map(|x| 2f64.powi(*x as i32)).collect();
    let output = (0..q)
        .map(|k| {
            let m = (0..n)
                .map(|j| (c[(k, j)] / state[j]).abs())
                .fold(0.0, f64::max);
            if m > 0.0 && m.is_finite() {
                1.0 / power_of_two(m)
            } else {
                1.0
            }
        })
        .collect();
    Scaling {
        time,
        state,
        output,
    }
}
