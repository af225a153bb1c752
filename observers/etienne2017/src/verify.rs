//! Solver-independent checks of a certificate `(P1, P2, L0, L1)` of Theorem 3 / Corollary 2 /
//! Remark 6 and of its gain `K(τ)` (spec §3.6–§3.7), recomputed from plain matrices (not from the
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
//! Every check is strict in `f64` (no tolerance): the certified margins are orders of magnitude
//! above rounding.

use faer::{Mat, MatRef};
use sporadic_linalg::{expm_stepper, max_eigenvalue, min_eigenvalue, spectral_radius};

use crate::conditions::{
    flow_block, flow_vertex_blocks, interpolate, jump_block, jump_block_high, jump_block_low,
    lyapunov_matrix, reset_matrix,
};
use crate::error::{Error, check_shape};
use crate::gain::GainSchedule;
use crate::lmi::Condition;
use crate::system::{Plant, Window};

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

/// Grid sizes of the independent checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CheckOptions {
    /// Points of the τ grids of (19b) on `[0, τ̄]` and (19c) on `[τ_low, τ̄]` (≥ 2; default 201).
    pub lmi_grid: usize,
    /// Points of the τ grid of the discrete contraction check on `[τ_low, τ̄]` (≥ 2; default
    /// 2001).
    pub discrete_grid: usize,
}

impl Default for CheckOptions {
    fn default() -> Self {
        Self {
            lmi_grid: 201,
            discrete_grid: 2001,
        }
    }
}

impl CheckOptions {
    fn validate(&self) -> Result<(), Error> {
        for (v, name) in [
            (self.lmi_grid, "lmi_grid"),
            (self.discrete_grid, "discrete_grid"),
        ] {
            if v < 2 {
                return Err(Error::InvalidParameter {
                    name,
                    value: v as f64,
                    reason: "a τ grid needs at least 2 points",
                });
            }
        }
        Ok(())
    }
}

/// The worst value of a check and where it occurs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extremum {
    /// The worst value.
    pub value: f64,
    /// Where on the τ grid (NaN for τ-independent quantities).
    pub tau: f64,
    /// Which vertex `R_p` (0-based), if vertex-specific.
    pub vertex: Option<usize>,
}

impl Extremum {
    fn new(value: f64) -> Self {
        Self {
            value,
            tau: f64::NAN,
            vertex: None,
        }
    }

    fn update_max(&mut self, value: f64, tau: f64, vertex: Option<usize>) {
        if value > self.value || value.is_nan() {
            *self = Self { value, tau, vertex };
        }
    }

    fn update_min(&mut self, value: f64, tau: f64, vertex: Option<usize>) {
        if value < self.value || value.is_nan() {
            *self = Self { value, tau, vertex };
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

/// All independent checks of a certificate and its gain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IndependentCheck {
    /// `max_p max(λ_max(M¹_p), λ_max(M²_p))` — (20a), (20b); `tau` is 0 for `M¹`, `τ̄` for `M²`.
    pub flow_vertices: Extremum,
    /// `min(λ_min((20c)), λ_min((20d)))`; `tau` is `τ_low` or `τ̄`.
    pub jump_vertices: Extremum,
    /// `min(λ_min(P1), λ_min(P2))`.
    pub positivity: f64,
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
        let fail = |what, e: &Extremum| Error::VerificationFailed {
            what,
            value: e.value,
            tau: e.tau,
            vertex: e.vertex,
        };
        let contraction = self.discrete.contraction.unwrap_or(Extremum::new(f64::NAN));
        if !(self.flow_vertices.value < 0.0) {
            Some(fail("max λ_max of (20a)/(20b)", &self.flow_vertices))
        } else if !(self.jump_vertices.value > 0.0) {
            Some(fail("min λ_min of (20c)/(20d)", &self.jump_vertices))
        } else if !(self.positivity > 0.0) {
            Some(fail("min λ_min of P1, P2", &Extremum::new(self.positivity)))
        } else if !(self.flow_grid.value < 0.0) {
            Some(fail("max λ_max of (19b) on the τ grid", &self.flow_grid))
        } else if !(self.jump_grid.value > 0.0) {
            Some(fail("min λ_min of (19c) on the τ grid", &self.jump_grid))
        } else if !(contraction.value < 0.0) {
            Some(fail("max λ_max of M'P1M − P1", &contraction))
        } else if !(self.discrete.spectral_radius.value < 1.0) {
            Some(fail(
                "max spectral radius of (I − K(τ)C)e^(R_p τ)",
                &self.discrete.spectral_radius,
            ))
        } else {
            None
        }
    }

    /// Whether every check passed.
    pub fn passed(&self) -> bool {
        self.failure().is_none()
    }
}

/// `(X + X')/2` (products such as `M'PM` are symmetric only up to rounding).
fn sym(x: MatRef<'_, f64>) -> Mat<f64> {
    (x + x.transpose()) * 0.5
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

/// `M_p(τ) = (I − KC) e^{R τ}` for one vertex, gain and `τ` (the transition of the error over
/// an interval of length `τ` of the frozen vertex dynamics followed by the reset).
pub fn transition(
    r: MatRef<'_, f64>,
    k: MatRef<'_, f64>,
    c: MatRef<'_, f64>,
    tau: f64,
) -> Result<Mat<f64>, Error> {
    let e = sporadic_linalg::expm_scaled(r, tau)?;
    Ok(reset_matrix(k, c) * e)
}

/// The discrete contraction check (item 3 of the module docs) of `gain` on its window, on a
/// grid of `points` values of τ, with `P1` when given.
pub fn discrete_check(
    plant: &Plant,
    gain: &GainSchedule,
    p1: Option<MatRef<'_, f64>>,
    points: usize,
) -> Result<DiscreteCheck, Error> {
    let (n, q) = (plant.n(), plant.q());
    check_shape(gain.k0(), n, q, "gain K0")?;
    if let Some(p) = p1 {
        check_shape(p, n, n, "P1")?;
    }
    if points < 2 {
        return Err(Error::InvalidParameter {
            name: "points",
            value: points as f64,
            reason: "a τ grid needs at least 2 points",
        });
    }
    let w = gain.window();
    let (lo, hi) = (w.tau_low(), w.tau_bar());
    let steps = if w.is_periodic() { 0 } else { points - 1 };
    let h = if steps == 0 {
        0.0
    } else {
        (hi - lo) / steps as f64
    };
    let mut rho = Extremum::new(f64::NEG_INFINITY);
    let mut contraction = p1.map(|_| Extremum::new(f64::NEG_INFINITY));
    let mut e = Mat::<f64>::zeros(n, n);
    for (v, r) in plant.vertices().iter().enumerate() {
        let mut stepper = expm_stepper(r.as_ref(), lo, h, steps)?;
        let mut k_step = 0usize;
        while let Some(tau) = stepper.next_into(e.as_mut()) {
            let tau = if k_step == steps { hi } else { tau };
            k_step += 1;
            let m = reset_matrix(gain.at(tau).as_ref(), plant.c()) * &e;
            rho.update_max(spectral_radius(m.as_ref())?, tau, Some(v));
            if let (Some(p), Some(ext)) = (p1, contraction.as_mut()) {
                let d = m.transpose() * p * &m - p;
                ext.update_max(max_eigenvalue(sym(d.as_ref()).as_ref())?, tau, Some(v));
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
    window: &Window,
    cert: &Certificate,
    gain: &GainSchedule,
    options: &CheckOptions,
) -> Result<IndependentCheck, Error> {
    options.validate()?;
    let (n, q) = (plant.n(), plant.q());
    check_shape(cert.p1.as_ref(), n, n, "P1")?;
    check_shape(cert.p2.as_ref(), n, n, "P2")?;
    check_shape(cert.l0.as_ref(), n, q, "L0")?;
    check_shape(cert.l1.as_ref(), n, q, "L1")?;
    let (p1, p2) = (cert.p1.as_ref(), cert.p2.as_ref());
    let c = plant.c();
    let tau_bar = window.tau_bar();
    let low_jump = condition != Condition::Remark6;

    let mut flow_vertices = Extremum::new(f64::NEG_INFINITY);
    for (v, r) in plant.vertices().iter().enumerate() {
        let (m1, m2) = flow_vertex_blocks(p1, p2, r.as_ref(), tau_bar);
        flow_vertices.update_max(max_eigenvalue(sym(m1.as_ref()).as_ref())?, 0.0, Some(v));
        flow_vertices.update_max(max_eigenvalue(sym(m2.as_ref()).as_ref())?, tau_bar, Some(v));
    }
    let mut jump_vertices = Extremum::new(f64::INFINITY);
    let high = jump_block_high(p1, p2, cert.l1.as_ref(), c);
    jump_vertices.update_min(min_eigenvalue(sym(high.as_ref()).as_ref())?, tau_bar, None);
    if low_jump {
        let low = jump_block_low(p1, p2, cert.l0.as_ref(), c, window);
        let tau = window.tau_low();
        jump_vertices.update_min(min_eigenvalue(sym(low.as_ref()).as_ref())?, tau, None);
    }
    let positivity = min_eigenvalue(sym(p1).as_ref())?.min(min_eigenvalue(sym(p2).as_ref())?);

    let mut flow_grid = Extremum::new(f64::NEG_INFINITY);
    for tau in grid(0.0, tau_bar, options.lmi_grid) {
        for (v, r) in plant.vertices().iter().enumerate() {
            let nb = flow_block(p1, p2, r.as_ref(), tau_bar, tau);
            flow_grid.update_max(max_eigenvalue(sym(nb.as_ref()).as_ref())?, tau, Some(v));
        }
    }
    let mut jump_grid = Extremum::new(f64::INFINITY);
    let jump_taus = if low_jump {
        grid(window.tau_low(), tau_bar, options.lmi_grid)
    } else {
        vec![tau_bar]
    };
    for tau in jump_taus {
        let l = interpolate(cert.l0.as_ref(), cert.l1.as_ref(), window, tau);
        let p = lyapunov_matrix(p1, p2, tau_bar, tau);
        let b = jump_block(p.as_ref(), p1, l.as_ref(), c);
        jump_grid.update_min(min_eigenvalue(sym(b.as_ref()).as_ref())?, tau, None);
    }
    let discrete = discrete_check(plant, gain, Some(p1), options.discrete_grid)?;
    Ok(IndependentCheck {
        flow_vertices,
        jump_vertices,
        positivity,
        flow_grid,
        jump_grid,
        discrete,
    })
}
