//! The width `w = x̄ − x̲` of the interval (not in the paper). With
//! `T = (1/√2)[[I, I], [I, −I]]`, `TĀT = diag(S, A)` and `TΓ(L)T = diag(|G|, G)`
//! ([`crate::ipr`]); the width is `√2` times the first half of `Tξ`, so it evolves
//! **deterministically**, independently of `u`, `d(t)`, `v(t)` and `y`:
//!
//! ```text
//! ẇ = S w + (d̄ − d̲),  S = A^M + A^N,          w⁺ = |G| w + 2|L|v̄,  G = I + LC.
//! ```
//!
//! * [`WidthDynamics::periodic_pre_jump`]: the pre-jump width of the periodic orbit for a constant
//!   inter-sample time `T`: `w = e^{ST}(|G|w + b) + ∫₀ᵀe^{Ss}ds·c`.
//! * [`WidthDynamics::guaranteed_bound`]: a componentwise bound valid for **every** admissible
//!   sampling sequence. All maps are monotone (`e^{Sμ} ≥ 0` since `S` is Metzler, `|G| ≥ 0`), so
//!   the post-jump map `U ↦ |G| max_μ [e^{Sμ}U + Φ(μ)c] + b` (max over `μ ∈ [τmin, τmax]`,
//!   componentwise) is iterated from the initial width to its fixed point; a slightly inflated
//!   `M` with `F(M) ≤ M` is invariant, so `max(U_1, …, U_k, M)` bounds every post-jump width. The max over `μ` is taken on a grid
//!   with the rigorous slack `(h/2)·e^{Sμ_k}e^{|S|h}|SU + c|` on the cell `[μ_k, μ_{k+1}]` (the
//!   derivative of the flow is `e^{Sμ}(SU + c)` and `0 ≤ e^{S(μ−μ_k)} ≤ e^{|S|h}`).

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite_slice;
use sporadic_linalg::{LinalgError, expm_scaled, zoh};

use crate::error::Error;
use crate::ipr::{MetzlerDecomposition, abs, reset_matrix};
use crate::system::{Bounds, Plant};
use sporadic_model::SamplingWindow;

/// The deterministic width dynamics of one observer.
#[derive(Debug, Clone)]
pub struct WidthDynamics {
    /// `S = A^M + A^N`.
    pub s: Mat<f64>,
    /// `|G|`, `G = I + LC`.
    pub g_abs: Mat<f64>,
    /// `c = d̄ − d̲`.
    pub drift: Vec<f64>,
    /// `b = 2|L|v̄`.
    pub jump_shift: Vec<f64>,
}

/// A componentwise width bound over every admissible sampling sequence.
#[derive(Debug, Clone, PartialEq)]
pub struct WidthBound {
    /// Bound on every post-jump width.
    pub post_jump: Vec<f64>,
    /// Bound on every pre-jump width (just before a sample).
    pub pre_jump: Vec<f64>,
    /// Bound on the width at any time (including the first interval from the initial width).
    pub any_time: Vec<f64>,
    /// Iterations of the monotone map until the invariant bound was found.
    pub iterations: usize,
}

/// Iteration budget of [`WidthDynamics::guaranteed_bound`].
const MAX_ITERATIONS: usize = 100_000;

/// Precomputed flow maps on a μ-grid (see [`WidthDynamics::guaranteed_bound`]): per grid point
/// `e^{Sμ_k}` and `e^{Sμ_k}e^{|S|h}` (row-major) and `Φ(μ_k)c`.
struct FlowGrid {
    n: usize,
    h: f64,
    e: Vec<f64>,
    g: Vec<f64>,
    cells: Vec<f64>,
}

fn mat_vec(m: MatRef<'_, f64>, v: &[f64]) -> Vec<f64> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|k| m[(i, k)] * v[k]).sum())
        .collect()
}

impl WidthDynamics {
    /// The width dynamics of the observer `(plant, bounds, L)`.
    ///
    /// # Errors
    /// Dimension mismatches or non-finite `L`.
    pub fn new(plant: &Plant, bounds: &Bounds, l: MatRef<'_, f64>) -> Result<Self, Error> {
        bounds.check_against(plant)?;
        let g = reset_matrix(plant, l)?;
        let abs_l = abs(l);
        let jump_shift = mat_vec(abs_l.as_ref(), bounds.v_bar())
            .into_iter()
            .map(|x| 2.0 * x)
            .collect();
        let drift = bounds
            .d_upper()
            .iter()
            .zip(bounds.d_lower())
            .map(|(u, lo)| u - lo)
            .collect();
        Ok(Self {
            s: MetzlerDecomposition::new(plant.a())?.width_matrix(),
            g_abs: abs(g.as_ref()),
            drift,
            jump_shift,
        })
    }

    fn n(&self) -> usize {
        self.s.nrows()
    }

    /// `(e^{Sμ}, ∫₀^μ e^{Ss}ds·c)` by one Van Loan exponential.
    fn flow_parts(&self, mu: f64) -> Result<(Mat<f64>, Vec<f64>), Error> {
        let n = self.n();
        let c = Mat::from_fn(n, 1, |i, _| self.drift[i]);
        let (e, g) = zoh(self.s.as_ref(), c.as_ref(), mu)?;
        Ok((e, (0..n).map(|i| g[(i, 0)]).collect()))
    }

    /// The width after flowing for `mu` from `w`.
    pub fn flow(&self, w: &[f64], mu: f64) -> Result<Vec<f64>, Error> {
        let (e, g) = self.flow_parts(mu)?;
        Ok(mat_vec(e.as_ref(), w)
            .into_iter()
            .zip(g)
            .map(|(a, b)| a + b)
            .collect())
    }

    /// The width right after a jump from `w`: `|G|w + 2|L|v̄`.
    pub fn jump(&self, w: &[f64]) -> Vec<f64> {
        mat_vec(self.g_abs.as_ref(), w)
            .into_iter()
            .zip(&self.jump_shift)
            .map(|(a, b)| a + b)
            .collect()
    }

    /// Pre-jump width of the periodic orbit with inter-sample time `period`.
    ///
    /// # Errors
    /// Non-finite or non-positive `period`, or `I − e^{ST}|G|` singular (no periodic orbit).
    pub fn periodic_pre_jump(&self, period: f64) -> Result<Vec<f64>, Error> {
        use faer::linalg::solvers::Solve;
        if !(period > 0.0 && period.is_finite()) {
            return Err(InputError::parameter("period", period, "must be finite and > 0").into());
        }
        let n = self.n();
        let (e, g) = self.flow_parts(period)?;
        let eg = &e * &self.g_abs;
        let lhs = Mat::<f64>::identity(n, n) - &eg;
        let eb = mat_vec(e.as_ref(), &self.jump_shift);
        let rhs = Mat::from_fn(n, 1, |i, _| eb[i] + g[i]);
        let w = lhs.full_piv_lu().solve(&rhs);
        let out: Vec<f64> = (0..n).map(|i| w[(i, 0)]).collect();
        check_finite_slice(&out, "periodic width (I - e^(ST)|G| singular)")?;
        Ok(out)
    }

    /// The flow maps `u ↦ e^{Sμ_k}u + Φ(μ_k)c` on `points` equally spaced `μ_k ∈ [lo, hi]`, with
    /// the cell factors for the inter-grid slack (stored flat, row-major).
    fn flow_grid(&self, lo: f64, hi: f64, points: usize) -> Result<FlowGrid, Error> {
        let n = self.n();
        let h = (hi - lo) / (points - 1) as f64;
        let cell_growth = expm_scaled(abs(self.s.as_ref()).as_ref(), h)?;
        let mut grid = FlowGrid {
            n,
            h,
            e: Vec::with_capacity(points * n * n),
            g: Vec::with_capacity(points * n),
            cells: Vec::with_capacity(points * n * n),
        };
        for k in 0..points {
            let mu = if k + 1 == points {
                hi
            } else {
                lo + k as f64 * h
            };
            let (e, g) = self.flow_parts(mu)?;
            let cell = &e * &cell_growth;
            for i in 0..n {
                for j in 0..n {
                    grid.e.push(e[(i, j)]);
                    grid.cells.push(cell[(i, j)]);
                }
            }
            grid.g.extend_from_slice(&g);
        }
        Ok(grid)
    }

    /// Componentwise `max_μ [e^{Sμ}u + Φ(μ)c]` over the grid's interval: the larger end-point value
    /// of each cell plus `(h/2)·e^{Sμ_k}e^{|S|h}|Su + c|`, which bounds the derivative
    /// `e^{Sμ}(Su + c)` on the cell `[μ_k, μ_{k+1}]` (`0 ≤ e^{S(μ−μ_k)} ≤ e^{|S|h}`).
    fn max_flow(&self, u: &[f64], grid: &FlowGrid) -> Vec<f64> {
        let n = grid.n;
        let su = mat_vec(self.s.as_ref(), u);
        let deriv: Vec<f64> = su
            .iter()
            .zip(&self.drift)
            .map(|(a, c)| (a + c).abs())
            .collect();
        let points = grid.g.len() / n;
        let value = |k: usize, i: usize| -> f64 {
            let row = &grid.e[(k * n + i) * n..(k * n + i + 1) * n];
            row.iter().zip(u).map(|(a, b)| a * b).sum::<f64>() + grid.g[k * n + i]
        };
        let mut best = vec![f64::NEG_INFINITY; n];
        for i in 0..n {
            if points == 1 {
                best[i] = value(0, i);
                continue;
            }
            let mut left = value(0, i);
            for k in 0..points - 1 {
                let right = value(k + 1, i);
                let row = &grid.cells[(k * n + i) * n..(k * n + i + 1) * n];
                let slack: f64 = row.iter().zip(&deriv).map(|(a, b)| a * b).sum();
                best[i] = best[i].max(left.max(right) + 0.5 * grid.h * slack);
                left = right;
            }
        }
        best
    }

    /// A width bound valid for every sampling sequence in `window`, starting from the initial
    /// width `initial` (module docs). `points` grid points per max over `μ`.
    ///
    /// # Errors
    /// Wrong length or negative/non-finite `initial`, `points < 2`; [`Error::Linalg`]
    /// (`NoConvergence`) when no invariant bound is found within the iteration budget (the width
    /// dynamics contracts too slowly on the window, or not at all).
    pub fn guaranteed_bound(
        &self,
        window: &SamplingWindow,
        initial: &[f64],
        points: usize,
    ) -> Result<WidthBound, Error> {
        let n = self.n();
        if initial.len() != n {
            return Err(InputError::mismatch(
                "length of the initial width (= n)",
                n,
                initial.len(),
            )
            .into());
        }
        check_finite_slice(initial, "initial width")?;
        if let Some(i) = initial.iter().position(|&w| w < 0.0) {
            return Err(Error::InvalidBounds {
                what: "initial width",
                index: i,
                reason: format!("width {} < 0", initial[i]),
            });
        }
        if points < 2 {
            return Err(InputError::parameter("points", points as f64, "need at least 2").into());
        }
        let (lo, hi) = (window.t1(), window.t2());
        let sampled = self.flow_grid(lo, hi, points)?;
        let whole = self.flow_grid(0.0, hi, points)?;
        let post_map = |u: &[f64]| self.jump(&self.max_flow(u, &sampled));
        // The first interval starts from the initial width (no jump before it). U_k bounds the
        // k-th post-jump width (monotone maps); once F(M) ≤ M for an M ≥ U_k, every later one
        // is below M, so max(U_1, …, U_k, M) bounds them all.
        let mut current = post_map(initial);
        let mut running = current.clone();
        for iteration in 1..=MAX_ITERATIONS {
            let next = post_map(&current);
            check_finite_slice(&next, "width bound iteration")?;
            let change = next
                .iter()
                .zip(&current)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            let scale = next.iter().map(|v| v.abs()).fold(0.0, f64::max);
            current = next;
            for (r, c) in running.iter_mut().zip(&current) {
                *r = r.max(*c);
            }
            if change > 1e-12 * (1.0 + scale) {
                continue;
            }
            let m: Vec<f64> = current.iter().map(|&v| v * (1.0 + 1e-6) + 1e-12).collect();
            if !post_map(&m).iter().zip(&m).all(|(a, b)| a <= b) {
                continue;
            }
            let post: Vec<f64> = running.iter().zip(&m).map(|(a, b)| a.max(*b)).collect();
            let max_of = |vs: &[&[f64]]| -> Vec<f64> {
                (0..n)
                    .map(|i| vs.iter().map(|v| v[i]).fold(f64::NEG_INFINITY, f64::max))
                    .collect()
            };
            return Ok(WidthBound {
                pre_jump: max_of(&[
                    &self.max_flow(&post, &sampled),
                    &self.max_flow(initial, &sampled),
                ]),
                any_time: max_of(&[
                    &self.max_flow(&post, &whole),
                    &self.max_flow(initial, &whole),
                    &post,
                    initial,
                ]),
                post_jump: post,
                iterations: iteration,
            });
        }
        Err(LinalgError::NoConvergence {
            what: format!(
                "no invariant width bound after {MAX_ITERATIONS} steps of the width map: the \
                 width dynamics contracts too slowly on the window, or not at all"
            ),
        }
        .into())
    }
}
