//! Solver-independent checks of a certificate `(P1, P2, L0, L1)` of Theorem 3 / Corollary 2 /
//! Remark 6 and of its gain `K(τ)`, recomputed from plain matrices (not from the
//! LMI model's expressions):
//!
//! 1. **Blocks of (20)**: `λ_max(M¹_p), λ_max(M²_p) < 0`, `λ_min((20c)), λ_min((20d)) > 0`,
//!    `P1, P2 ≻ 0`.
//! 2. **τ grid of Corollary 1**: `N_p(τ) = He(P(τ)R_p) + (P2 − P1)/τ̄ ≺ 0` on `[0, τ̄]` (19b)
//!    and `J(P(τ), P1, L(τ)) ≻ 0` on `[τ_low, τ̄]` (19c), with the interpolations of the proof of
//!    Theorem 3.
//! 3. **Discrete contraction** (a necessary consequence of any certificate, needing `e^{R_pτ}`):
//!    `M_p(τ) = (I − K(τ)C) e^{R_p τ}` satisfies `M_p(τ)'P1M_p(τ) − P1 ≺ 0`, hence
//!    `ρ(M_p(τ)) < 1`, for every vertex and every `τ ∈ [τ_low, τ̄]` — the flow along a frozen
//!    vertex decreases `z'P(τ)z`, and the jump brings it below `z'P1z`. The exponentials on the
//!    grid come from [`sporadic_linalg::expm_stepper`].
//!
//! **Safety factor.** A block `X = Σ_i S_i` formed in `f64` carries rounding errors of order
//! `n·ε·Σ‖S_i‖`, and the symmetric eigensolver adds a backward error of the same order; the
//! exponential adds a relative error growing with `‖R_pτ‖`. Each check therefore requires its
//! eigenvalue to clear the bound by `safety · dim · ε · scale` ([`CheckOptions::safety`],
//! default 100), `scale` being the Frobenius norms of the summands (times `1 + ‖R_pτ‖_F` for the
//! discrete check): a check that passes holds for the exact matrices, not only for their rounded
//! values. The margins of the example are `~1e-4`, the tolerances `~1e-11`.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::{check_finite, check_shape};
use sporadic_linalg::{expm_stepper, max_eigenvalue, min_eigenvalue, spectral_radius};

use crate::conditions::{
    flow_block, interpolate_checked, jump_block, jump_block_high, jump_block_low, lyapunov_matrix,
    reset_matrix,
};
use crate::error::Error;
use crate::gain::GainSchedule;
use crate::lmi::Condition;
use crate::system::Plant;
use sporadic_model::SamplingWindow;

/// A certificate of (20): the Lyapunov matrices `P(0) = P1`, `P(τ̄) = P2` and `L0, L1`.
#[derive(Debug, Clone, PartialEq)]
pub struct Certificate {
    /// `P1 = P(0)`.
    pub p1: Mat<f64>,
    /// `P2 = P(τ̄)`.
    pub p2: Mat<f64>,
    /// `L0 = P1 K0` (equal to `L1` for a static gain).
    pub l0: Mat<f64>,
    /// `L1 = P1 K1`.
    pub l1: Mat<f64>,
}

/// Grid sizes and safety factor of the independent checks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckOptions {
    /// Points of the τ grids of (19b) on `[0, τ̄]` and (19c) on `[τ_low, τ̄]` (≥ 2; default 201).
    pub lmi_grid: usize,
    /// Points of the τ grid of the discrete contraction check on `[τ_low, τ̄]` (≥ 2; default
    /// 2001).
    pub discrete_grid: usize,
    /// Safety factor on the rounding-error bound every eigenvalue must clear (≥ 1; default
    /// 100; module docs).
    pub safety: f64,
}

impl Default for CheckOptions {
    fn default() -> Self {
        Self {
            lmi_grid: 201,
            discrete_grid: 2001,
            safety: 100.0,
        }
    }
}

impl CheckOptions {
    /// Checks every field (`lmi_grid`, `discrete_grid` ≥ 2, `safety` finite and ≥ 1); the error
    /// names the offending one.
    pub fn validate(&self) -> Result<(), Error> {
        for (v, name) in [
            (self.lmi_grid, "lmi_grid"),
            (self.discrete_grid, "discrete_grid"),
        ] {
            if v < 2 {
                return Err(InputError::parameter(
                    name,
                    v as f64,
                    "a τ grid needs at least 2 points",
                )
                .into());
            }
        }
        if !(self.safety >= 1.0 && self.safety.is_finite()) {
            return Err(InputError::parameter(
                "safety",
                self.safety,
                "the safety factor must be finite and ≥ 1",
            )
            .into());
        }
        Ok(())
    }
}

/// Which side of a bound a checked quantity must lie on.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Sense {
    /// `value < bound − tolerance`.
    Below(f64),
    /// `value > bound + tolerance`.
    Above(f64),
}

/// The worst value of a check and where it occurs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extremum {
    /// The checked quantity at the worst point (an extreme eigenvalue or a spectral radius).
    pub value: f64,
    /// The rounding-error bound (times the safety factor) it had to clear there.
    pub tolerance: f64,
    /// Distance of `value` beyond its bound and tolerance: the check passes iff `slack > 0`
    /// (NaN fails). The worst point is the one of smallest slack.
    pub slack: f64,
    /// Where on the τ grid (NaN for τ-independent quantities).
    pub tau: f64,
    /// Which vertex `R_p` (0-based), if vertex-specific.
    pub vertex: Option<usize>,
}

impl Extremum {
    fn empty() -> Self {
        Self {
            value: f64::NAN,
            tolerance: 0.0,
            slack: f64::INFINITY,
            tau: f64::NAN,
            vertex: None,
        }
    }

    /// Whether the check passed at every point.
    pub fn passed(&self) -> bool {
        self.slack > 0.0
    }

    fn update(
        &mut self,
        sense: Sense,
        value: f64,
        tolerance: f64,
        tau: f64,
        vertex: Option<usize>,
    ) {
        let slack = match sense {
            Sense::Below(b) => b - tolerance - value,
            Sense::Above(b) => value - b - tolerance,
        };
        if !(slack >= self.slack) {
            *self = Self {
                value,
                tolerance,
                slack,
                tau,
                vertex,
            };
        }
    }
}

/// The discrete contraction check of a gain schedule (item 3 of the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscreteCheck {
    /// `max_{p,τ} ρ(M_p(τ))` (must be `< 1`).
    pub spectral_radius: Extremum,
    /// `max_{p,τ} λ_max(M_p(τ)'P1M_p(τ) − P1)` (must be `< 0`), when `P1` was given.
    pub contraction: Option<Extremum>,
}

impl DiscreteCheck {
    /// Whether every part of the check passed.
    pub fn passed(&self) -> bool {
        self.spectral_radius.passed() && self.contraction.is_none_or(|c| c.passed())
    }
}

/// All independent checks of a certificate and its gain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IndependentCheck {
    /// `max_p max(λ_max(M¹_p), λ_max(M²_p))` — (20a), (20b); `tau` is 0 for `M¹`, `τ̄` for `M²`.
    pub flow_vertices: Extremum,
    /// `min(λ_min((20c)), λ_min((20d)))`; `tau` is `τ_low` or `τ̄`.
    pub jump_vertices: Extremum,
    /// `min(λ_min(P1), λ_min(P2))`; `tau` is 0 for `P1`, `τ̄` for `P2`.
    pub positivity: Extremum,
    /// `max_{p,τ∈[0,τ̄]} λ_max(N_p(τ))` — (19b) on the grid.
    pub flow_grid: Extremum,
    /// `min_{τ∈[τ_low,τ̄]} λ_min(J(P(τ), P1, L(τ)))` — (19c) on the grid.
    pub jump_grid: Extremum,
    /// The discrete contraction check with `P1`.
    pub discrete: DiscreteCheck,
}

impl IndependentCheck {
    /// The first failing check, as an error.
    pub fn failure(&self) -> Option<Error> {
        let contraction = self.discrete.contraction.unwrap_or(Extremum {
            slack: f64::NAN,
            ..Extremum::empty()
        });
        [
            ("max λ_max of (20a)/(20b)", &self.flow_vertices),
            ("min λ_min of (20c)/(20d)", &self.jump_vertices),
            ("min λ_min of P1, P2", &self.positivity),
            ("max λ_max of (19b) on the τ grid", &self.flow_grid),
            ("min λ_min of (19c) on the τ grid", &self.jump_grid),
            ("max λ_max of M'P1M − P1", &contraction),
            (
                "max spectral radius of (I − K(τ)C)e^(R_p τ)",
                &self.discrete.spectral_radius,
            ),
        ]
        .into_iter()
        .find(|(_, e)| !e.passed())
        .map(|(what, e)| Error::VerificationFailed {
            what,
            value: e.value,
            tolerance: e.tolerance,
            tau: e.tau,
            vertex: e.vertex,
        })
    }

    /// Whether every check passed.
    pub fn passed(&self) -> bool {
        self.failure().is_none()
    }
}

/// `k` evenly spaced points from `a` to `b` (both included; one point when `a = b`).
fn grid(a: f64, b: f64, k: usize) -> Vec<f64> {
    if a == b {
        return vec![a];
    }
    (0..k)
        .map(|i| {
            if i + 1 == k {
                b
            } else {
                a + (b - a) * i as f64 / (k - 1) as f64
            }
        })
        .collect()
}

/// Frobenius norm.
fn fro(x: MatRef<'_, f64>) -> f64 {
    x.norm_l2()
}

/// `safety · dim · ε · scale`: the rounding-error bound (with safety factor) of an extreme
/// eigenvalue of a `dim × dim` block whose summands have Frobenius norms adding up to `scale`.
fn rounding(safety: f64, dim: usize, scale: f64) -> f64 {
    safety * dim as f64 * f64::EPSILON * scale
}

/// `M_p(τ) = (I − KC) e^{R τ}` for one vertex, gain and `τ` (the transition of the error over
/// an interval of length `τ` of the frozen vertex dynamics followed by the reset).
pub fn transition(
    r: MatRef<'_, f64>,
    k: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
    tau: f64,
) -> Result<Mat<f64>, Error> {
    check_shape(k, r.nrows(), k.ncols(), "gain K (rows vs the order of R)")?;
    let reset = reset_matrix(k, c)?;
    let e = sporadic_linalg::expm_scaled(r, tau)?;
    Ok(reset * e)
}

/// The discrete contraction check (item 3 of the module docs) of `gain` on its window, on
/// `options.discrete_grid` values of τ with the safety factor `options.safety`, with `P1` when
/// given.
pub fn discrete_check(
    plant: &Plant,
    gain: &GainSchedule,
    p1: Option<MatRef<'_, f64>>,
    options: &CheckOptions,
) -> Result<DiscreteCheck, Error> {
    options.validate()?;
    let (n, q) = (plant.n(), plant.q());
    check_shape(gain.k0(), n, q, "gain K0")?;
    if let Some(p) = p1 {
        check_shape(p, n, n, "P1")?;
        check_finite(p, "P1")?;
    }
    let (points, safety) = (options.discrete_grid, options.safety);
    let w = gain.window();
    let (lo, hi) = (w.t1(), w.t2());
    let steps = if w.is_periodic() { 0 } else { points - 1 };
    let h = if steps == 0 {
        0.0
    } else {
        (hi - lo) / steps as f64
    };
    let p1_norm = p1.map_or(0.0, fro);
    let mut rho = Extremum::empty();
    let mut contraction = p1.map(|_| Extremum::empty());
    let mut e = Mat::<f64>::zeros(n, n);
    for (v, r) in plant.vertices().iter().enumerate() {
        let r_norm = fro(r.as_ref());
        let mut stepper = expm_stepper(r.as_ref(), lo, h, steps)?;
        let mut k_step = 0usize;
        while let Some(tau) = stepper.next_into(e.as_mut()) {
            let tau = if k_step == steps { hi } else { tau };
            k_step += 1;
            let m = reset_matrix(gain.at(tau).as_ref(), plant.c())? * &e;
            // Relative error of the computed exponential grows like ‖Rτ‖.
            let growth = 1.0 + r_norm * tau;
            let m_norm = fro(m.as_ref());
            rho.update(
                Sense::Below(1.0),
                spectral_radius(m.as_ref())?,
                rounding(safety, n, growth * m_norm),
                tau,
                Some(v),
            );
            if let (Some(p), Some(ext)) = (p1, contraction.as_mut()) {
                let d = m.transpose() * p * &m - p;
                let scale = growth * (m_norm * m_norm * p1_norm + p1_norm);
                ext.update(
                    Sense::Below(0.0),
                    max_eigenvalue(d.as_ref())?,
                    rounding(safety, n, scale),
                    tau,
                    Some(v),
                );
            }
        }
        if let Some(err) = stepper.error() {
            return Err(err.clone().into());
        }
    }
    Ok(DiscreteCheck {
        spectral_radius: rho,
        contraction,
    })
}

/// Runs every independent check (module docs) of `cert` for `condition` on `window`, with the
/// gain `K0 = P1⁻¹L0`, `K1 = P1⁻¹L1` given as `gain`.
pub fn check_certificate(
    plant: &Plant,
    condition: Condition,
    window: &SamplingWindow,
    cert: &Certificate,
    gain: &GainSchedule,
    options: &CheckOptions,
) -> Result<IndependentCheck, Error> {
    options.validate()?;
    condition.check_window(window)?;
    let (n, q) = (plant.n(), plant.q());
    for (x, rows, cols, what) in [
        (&cert.p1, n, n, "P1"),
        (&cert.p2, n, n, "P2"),
        (&cert.l0, n, q, "L0"),
        (&cert.l1, n, q, "L1"),
    ] {
        check_shape(x.as_ref(), rows, cols, what)?;
        check_finite(x.as_ref(), what)?;
    }
    let (p1, p2) = (cert.p1.as_ref(), cert.p2.as_ref());
    let c = plant.c();
    let (tau_low, tau_bar) = (window.t1(), window.t2());
    let safety = options.safety;
    let low_jump = condition != Condition::Remark6;
    let (p1n, p2n, cn) = (fro(p1), fro(p2), fro(c));

    // Flow: N_p(τ) = He(P(τ)R_p) + (P2 − P1)/τ̄ ≺ 0; M¹_p = N_p(0), M²_p = N_p(τ̄).
    let flow = |tau: f64, ext: &mut Extremum| -> Result<(), Error> {
        let s = tau / tau_bar;
        let p_norm = (1.0 - s) * p1n + s * p2n;
        for (v, r) in plant.vertices().iter().enumerate() {
            let nb = flow_block(p1, p2, r.as_ref(), tau_bar, tau)?;
            let scale = 2.0 * p_norm * fro(r.as_ref()) + (p1n + p2n) / tau_bar;
            let tol = rounding(safety, n, scale);
            ext.update(
                Sense::Below(0.0),
                max_eigenvalue(nb.as_ref())?,
                tol,
                tau,
                Some(v),
            );
        }
        Ok(())
    };
    // Jump: J(P(τ), P1, L) ≻ 0.
    let jump = |b: &Mat<f64>, l: MatRef<'_, f64>, tau: f64, ext: &mut Extremum| {
        let s = tau / tau_bar;
        let scale = 3.0 * fro(l) * cn + (1.0 - s) * p1n + s * p2n + p1n;
        let tol = rounding(safety, 2 * n, scale);
        ext.update(
            Sense::Above(0.0),
            min_eigenvalue(b.as_ref())?,
            tol,
            tau,
            None,
        );
        Ok::<(), Error>(())
    };

    let mut flow_vertices = Extremum::empty();
    flow(0.0, &mut flow_vertices)?;
    flow(tau_bar, &mut flow_vertices)?;
    let mut jump_vertices = Extremum::empty();
    let high = jump_block_high(p1, p2, cert.l1.as_ref(), c)?;
    jump(&high, cert.l1.as_ref(), tau_bar, &mut jump_vertices)?;
    if low_jump {
        let low = jump_block_low(p1, p2, cert.l0.as_ref(), c, window)?;
        jump(&low, cert.l0.as_ref(), tau_low, &mut jump_vertices)?;
    }
    let mut positivity = Extremum::empty();
    for (p, norm, tau) in [(p1, p1n, 0.0), (p2, p2n, tau_bar)] {
        let tol = rounding(safety, n, norm);
        positivity.update(Sense::Above(0.0), min_eigenvalue(p)?, tol, tau, None);
    }

    let mut flow_grid = Extremum::empty();
    for tau in grid(0.0, tau_bar, options.lmi_grid) {
        flow(tau, &mut flow_grid)?;
    }
    let mut jump_grid = Extremum::empty();
    let jump_taus = if low_jump {
        grid(tau_low, tau_bar, options.lmi_grid)
    } else {
        vec![tau_bar]
    };
    for tau in jump_taus {
        let l = interpolate_checked(cert.l0.as_ref(), cert.l1.as_ref(), window, tau);
        let p = lyapunov_matrix(p1, p2, tau_bar, tau)?;
        let b = jump_block(p.as_ref(), p1, l.as_ref(), c)?;
        jump(&b, l.as_ref(), tau, &mut jump_grid)?;
    }
    let discrete = discrete_check(plant, gain, Some(p1), options)?;
    Ok(IndependentCheck {
        flow_vertices,
        jump_vertices,
        positivity,
        flow_grid,
        jump_grid,
        discrete,
    })
}
