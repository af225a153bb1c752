//! The finite LMIs (20) of Theorem 3 (Etienne et al. 2017), Corollary 2 (static gain) and the
//! periodic case of Remark 6, modelled with the LMI layer of `sporadic-sdp` and solved as one
//! margin problem (the strict LMIs become one SDP; "formulation F"):
//!
//! ```text
//! maximise t   over (P1, P2, L0, L1, t)
//! s.t.  −τ̄M¹_p ⪰ tI,  −τ̄M²_p ⪰ tI                                 p = 1..2^k    (20a), (20b)
//!       [He(L0C) − (τ_low/τ̄)(P1 − P2), C'L0'; ⋆, P1] ⪰ tI                          (20c)
//!       [He(L1C) − (P1 − P2),          C'L1'; ⋆, P1] ⪰ tI                          (20d)
//!       P1 ⪰ tI,  P2 ⪰ tI,   ‖P1‖₂ ≤ 1,  ‖P2‖₂ ≤ 1   (normalisation; L0, L1 free)
//! ```
//!
//! with `M^i_p = He(P_i R_p) + (P2 − P1)/τ̄`, imposed as `τ̄M^i_p = He(P_i R_pτ̄) + P2 − P1`
//! (same LMI, `τ̄ > 0`): every block is then on the scale of `P` and depends on the data only
//! through `R_pτ̄`, `τ_low/τ̄`, `LC`, so `t*` and the verification threshold do not depend on
//! the time unit. All LMIs are positively homogeneous in
//! `(P1, P2, L0, L1)` (any positive multiple of a solution is one, with the same `K0, K1`), so
//! the normalisation loses no generality: (20) is strictly feasible iff `t* > 0`. Since `P ⪰ tI` with `t ≥ 0` makes `−I ⪯ P` redundant, the
//! bound `‖P‖₂ ≤ 1` of the layer is exactly the `P ⪯ I` of formulation F.
//!
//! * [`Condition::Corollary2`]: `L0 = L1 = L` (one variable), both (20c) and (20d) kept.
//! * [`Condition::Remark6`] (`τ_low = τ̄ = h`): (20c) dropped, static `K = P1⁻¹L1`.
//! * **Fixed gain** (analysis of a given schedule `K0, K1`): `L0 = P1K0`, `L1 = P1K1` are linear
//!   in `P1`, so (20) is an LMI in `(P1, P2)` only ("fixed-gain analysis").
//!
//! `τ̄` and `τ_low/τ̄` enter as parameters, so a compiled model is re-solved for a new window
//! without rebuilding it or re-analysing the solver structure (used by the bisection of
//! [`crate::bisection`]).

use sporadic_linalg::InputError;
use sporadic_linalg::input::{LowerEnd, check_finite, check_shape, check_window};

use faer::{Mat, MatRef, mat};
use sporadic_model::{SamplingWindow, SolverStats};
use sporadic_sdp::lmi::{Compiled, Expr, FeasibilityOptions, Model, Normalisation, Param, Var};

use crate::error::Error;
use crate::gain::GainSchedule;
use crate::system::Plant;

/// The bounds `0 ≤ τ_low ≤ τ̄`, `τ̄ > 0` at which (20) is posed. Every sampling window is a
/// [`SamplingWindow`] (`τ_low > 0`); these bounds also admit `τ_low = 0`, which is no sampling
/// window (intervals may be arbitrarily short) but at which the LMIs are defined, so that their
/// infeasibility there can be observed ([`crate::design::solve_margin_without_dwell`],
/// [`crate::bisection::max_tau_bar`] with `τ_low = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bounds {
    pub tau_low: f64,
    pub tau_bar: f64,
}

impl Bounds {
    /// The bounds of a sampling window.
    pub fn of(window: &SamplingWindow) -> Self {
        Self {
            tau_low: window.t1(),
            tau_bar: window.t2(),
        }
    }

    /// Validates `0 ≤ τ_low ≤ τ̄ < ∞`, `τ̄ > 0`.
    pub fn new(tau_low: f64, tau_bar: f64) -> Result<Self, Error> {
        const WHAT: &str = "sampling window [τ_low, τ̄]";
        check_window(WHAT, tau_low, tau_bar, LowerEnd::NonNegative)?;
        if tau_bar <= 0.0 {
            return Err(InputError::window(WHAT, tau_low, tau_bar, "τ̄ must be > 0").into());
        }
        Ok(Self { tau_low, tau_bar })
    }

    /// `τ_low = τ̄`.
    pub fn is_periodic(&self) -> bool {
        self.tau_low == self.tau_bar
    }
}

/// Which finite condition of the paper is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Condition {
    /// Theorem 3: time-varying gain `K(τ)` from `L0`, `L1` (needs `τ_low < τ̄`).
    Theorem3,
    /// Corollary 2: static gain, `L0 = L1 = L`.
    Corollary2,
    /// Remark 6: periodic sampling `τ_low = τ̄ = h`, (20a), (20b), (20d), static gain.
    Remark6,
}

impl Condition {
    /// Short name used in errors and reports.
    pub fn name(self) -> &'static str {
        match self {
            Condition::Theorem3 => "Theorem 3",
            Condition::Corollary2 => "Corollary 2",
            Condition::Remark6 => "Remark 6",
        }
    }

    /// Checks that the window suits the condition (Theorem 3: `τ_low < τ̄`; Remark 6:
    /// `τ_low = τ̄`).
    pub fn check_window(self, window: &SamplingWindow) -> Result<(), Error> {
        self.check_bounds(&Bounds::of(window))
    }

    pub(crate) fn check_bounds(self, window: &Bounds) -> Result<(), Error> {
        let err = |reason| {
            Err(InputError::window(
                "sampling window [τ_low, τ̄]",
                window.tau_low,
                window.tau_bar,
                reason,
            )
            .into())
        };
        match self {
            Condition::Theorem3 if window.is_periodic() => err(
                "Theorem 3 interpolates K on [τ_low, τ̄] and needs τ_low < τ̄ (use Remark 6 for periodic sampling)",
            ),
            Condition::Remark6 if !window.is_periodic() => {
                err("Remark 6 is the periodic case and needs τ_low = τ̄")
            }
            _ => Ok(()),
        }
    }

    fn has_low_jump(self) -> bool {
        self != Condition::Remark6
    }
}

/// How the gain enters the LMIs.
#[derive(Debug, Clone)]
pub(crate) enum GainTerm {
    /// Synthesis: `L0`, `L1` (or the single `L`) are decision variables.
    Free,
    /// Analysis of a given schedule: `L0 = P1 K0`, `L1 = P1 K1`.
    Fixed { k0: Mat<f64>, k1: Mat<f64> },
}

/// A solved instance of (20).
#[derive(Debug, Clone)]
pub(crate) struct LmiResult {
    /// Optimal common margin `t*` of formulation F.
    pub margin: f64,
    /// `P1, P2, L0, L1` at the returned point (`L0 = L1` for a static gain; `L_i = P1 K_i` for a
    /// fixed gain).
    pub p1: Mat<f64>,
    pub p2: Mat<f64>,
    pub l0: Mat<f64>,
    pub l1: Mat<f64>,
    pub stats: SolverStats,
}

/// A compiled instance of (20) for one plant, condition and gain term; the window is a
/// parameter.
pub(crate) struct Lmi20 {
    compiled: Compiled,
    condition: Condition,
    tau_bar: Param,
    ratio: Option<Param>,
    p1: Var,
    p2: Var,
    l0: Option<Var>,
    l1: Option<Var>,
    fixed: Option<(Mat<f64>, Mat<f64>)>,
}

fn scalar(x: f64) -> Mat<f64> {
    mat![[x]]
}

impl Lmi20 {
    /// Builds (20) for `plant` and `condition` at `window` (checked against the condition).
    pub fn new(
        plant: &Plant,
        condition: Condition,
        window: &Bounds,
        gain: GainTerm,
        options: &FeasibilityOptions,
    ) -> Result<Self, Error> {
        condition.check_bounds(window)?;
        let (n, q) = (plant.n(), plant.q());
        let c = plant.c().to_owned();
        let mut m = Model::new();
        let p1 = m.symmetric("P1", n);
        let p2 = m.symmetric("P2", n);
        let tau_bar = m.param("τ̄", scalar(window.tau_bar).as_ref())?;
        let ratio = if condition.has_low_jump() {
            Some(m.param("τ_low/τ̄", scalar(window.tau_low / window.tau_bar).as_ref())?)
        } else {
            None
        };
        let (l0, l1, l0_expr, l1_expr, fixed) = match gain {
            GainTerm::Free => match condition {
                Condition::Theorem3 => {
                    let l0 = m.full("L0", n, q);
                    let l1 = m.full("L1", n, q);
                    let (e0, e1) = (l0.expr(), l1.expr());
                    (Some(l0), Some(l1), e0, e1, None)
                }
                Condition::Corollary2 | Condition::Remark6 => {
                    let l = m.full("L", n, q);
                    let e = l.expr();
                    (None, Some(l), e.clone(), e, None)
                }
            },
            GainTerm::Fixed { k0, k1 } => {
                for (k, what) in [(&k0, "K0"), (&k1, "K1")] {
                    check_shape(k.as_ref(), n, q, what)?;
                    check_finite(k.as_ref(), what)?;
                }
                let e0 = &p1 * &k0;
                let e1 = &p1 * &k1;
                (None, None, e0, e1, Some((k0, k1)))
            }
        };
        let derivative = &p2 - &p1;
        for (i, r) in plant.vertices().iter().enumerate() {
            let m1 = (&p1 * r).he() * &tau_bar + &derivative;
            let m2 = (&p2 * r).he() * &tau_bar + &derivative;
            m.constrain(m1.lt(0.0).named(format!("(20a) p={}", i + 1)))?;
            m.constrain(m2.lt(0.0).named(format!("(20b) p={}", i + 1)))?;
        }
        let jump = |l: &Expr, shift: Expr| {
            let lc = l * &c;
            Expr::sym_blocks(&[[Some(lc.he() + shift), None], [Some(lc), Some(p1.expr())]])
        };
        if let Some(ratio) = &ratio {
            let shift = -((&p1 - &p2) * ratio);
            m.constrain(jump(&l0_expr, shift).gt(0.0).named("(20c)"))?;
        }
        m.constrain(jump(&l1_expr, -(&p1 - &p2)).gt(0.0).named("(20d)"))?;
        m.constrain(p1.gt(0.0).named("P1 ≻ 0"))?;
        m.constrain(p2.gt(0.0).named("P2 ≻ 0"))?;
        let mut opts = options
            .clone()
            .normalise(&p1, Normalisation::Norm(1.0))
            .normalise(&p2, Normalisation::Norm(1.0));
        for l in l0.iter().chain(l1.iter()) {
            opts = opts.normalise(l, Normalisation::Free);
        }
        let compiled = m.compile_feasibility(&opts)?;
        Ok(Self {
            compiled,
            condition,
            tau_bar,
            ratio,
            p1,
            p2,
            l0,
            l1,
            fixed,
        })
    }

    /// Moves the model to a new window (same condition) without rebuilding it.
    pub fn set_window(&mut self, window: &Bounds) -> Result<(), Error> {
        self.condition.check_bounds(window)?;
        self.compiled
            .set_param(&self.tau_bar, scalar(window.tau_bar).as_ref())?;
        if let Some(ratio) = &self.ratio {
            self.compiled
                .set_param(ratio, scalar(window.tau_low / window.tau_bar).as_ref())?;
        }
        Ok(())
    }

    /// Solves the margin problem and reads the certificate.
    pub fn solve(&mut self) -> Result<LmiResult, Error> {
        let sol = self.compiled.solve()?;
        let p1 = sol.value(&self.p1)?;
        let p2 = sol.value(&self.p2)?;
        let (l0, l1) = match (&self.fixed, &self.l0, &self.l1) {
            (Some((k0, k1)), _, _) => (&p1 * k0, &p1 * k1),
            (None, Some(l0), Some(l1)) => (sol.value(l0)?, sol.value(l1)?),
            (None, None, Some(l)) => {
                let l = sol.value(l)?;
                (l.clone(), l)
            }
            (None, _, None) => {
                return Err(InputError::empty("gain variable L1 of a free-gain model").into());
            }
        };
        let margin = sol.margin.unwrap_or(f64::NAN);
        // Decision scalars (the margin `t` not counted): `n(n+1) + 2nq` (Theorem 3),
        // `n(n+1) + nq` (Corollary 2, Remark 6), `n(n+1)` (fixed gain).
        let stats = SolverStats::of(&sol, self.compiled.model().num_scalars());
        Ok(LmiResult {
            margin,
            p1,
            p2,
            l0,
            l1,
            stats,
        })
    }
}

/// The gain term for the analysis of a given schedule.
pub(crate) fn fixed_term(plant: &Plant, gain: &GainSchedule) -> Result<GainTerm, Error> {
    let (n, q) = (plant.n(), plant.q());
    let check = |k: MatRef<'_, f64>, what| check_shape(k, n, q, what);
    check(gain.k0(), "K0")?;
    check(gain.k1(), "K1")?;
    Ok(GainTerm::Fixed {
        k0: gain.k0().to_owned(),
        k1: gain.k1().to_owned(),
    })
}
