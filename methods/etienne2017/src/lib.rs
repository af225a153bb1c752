//! Etienne, Hetel, Efimov & Petreczky (2017), "Observer synthesis under time-varying sampling for
//! Lipschitz nonlinear systems", Automatica 85: an impulsive observer that copies the plant
//! `ẋ = Ax + Bu + Gφ(Hx)` between samples and resets `x̂⁺ = x̂ + K(τ)(y − Cx̂)` with a gain
//! depending on the length `τ` of the interval that just ended, for every sampling sequence with
//! `t_{k+1} − t_k ∈ [τ_low, τ̄]`. Finite LMIs (no matrix exponential) certify it.
//!
//! Modules, in the paper's vocabulary:
//! * [`system`]: the plant (1)–(2) with Jacobian bounds and the vertices `R_p` of Lemma 1
//!   ([`Plant`]), and the sampling class `S[τ_low, τ̄]` ([`Window`]);
//! * [`conditions`]: the matrices of (16c), (19b)–(19c) and (20a)–(20d) at given numbers, the
//!   interpolations of the proof of Theorem 3, and the gain recovery `K = P1⁻¹L`;
//! * [`lmi`]: LMIs (20) as the margin problem "formulation F" of the spec, for Theorem 3,
//!   Corollary 2 and Remark 6 ([`Condition`]);
//! * [`design`](mod@design): synthesis ([`design()`]), analysis of a given gain ([`analyse`]) and
//!   the raw margin ([`solve_margin`]);
//! * [`gain`]: the schedule `K(τ)` ([`GainSchedule`]);
//! * [`verify`]: the solver-independent checks (eigenvalues of every block, τ-grid check of
//!   (19b)/(19c), contraction of `z'P1z` across `(I − K(τ)C)e^{R_pτ}`);
//! * [`bisection`]: the largest `τ̄` for a given `τ_low` ([`max_tau_bar`]) and the largest
//!   period ([`max_period`]);
//! * [`simulation`]: the nonlinear plant and observer with `sporadic-sim`;
//! * [`example`] and [`reproduce`](mod@reproduce): the flexible-joint robot of §5, the printed
//!   gains, and the reproduction of every claim and of Figures 1–2.
//!
//! The OCR of the paper garbles (16c), (19c) and the block `B(τ)` of the proof of Theorem 3;
//! the forms used here are those of the spec (the only ones consistent with the stated Schur
//! complement and with (20c)/(20d)). Remark 6 says "periodic sampling (τ̄ > τ_low)": it is
//! `τ̄ = τ_low`.
//!
//! ```
//! use sporadic_etienne2017::{Condition, DesignOptions, Window, design, example};
//!
//! let plant = example::flexible_joint()?;
//! // Theorem 3 on [0.01, 0.3] (Corollary 2 is infeasible there).
//! let d = design(&plant, Condition::Theorem3, &Window::new(0.01, 0.3)?, &DesignOptions::default())?;
//! let k = d.gain.at(0.15); // K(τ) between K0 = K(0.01) and K1 = K(0.3)
//! assert_eq!((k.nrows(), k.ncols()), (4, 2));
//! assert!(d.check.passed());
//! # Ok::<(), sporadic_etienne2017::Error>(())
//! ```

pub mod bisection;
pub mod conditions;
pub mod design;
mod error;
pub mod example;
pub mod gain;
pub mod lmi;
pub mod simulation;
pub mod system;
pub mod verify;

pub use bisection::{
    BisectionOptions, MaxTauBar, Probe, TableRow, max_period, max_tau_bar, max_tau_bar_table,
};
pub use design::{
    Design, DesignOptions, MarginSolution, analyse, analyse_margin, design, solve_margin,
};
pub use error::Error;
pub use gain::GainSchedule;
pub use lmi::{Condition, SolverStats};
pub use simulation::{
    SimulationSetup, error_norm_after, error_norm_after_sample, lyapunov_at_samples,
    simulate_observer, worst_case_sampling,
};
pub use system::{Plant, Window};
pub use verify::{
    Certificate, CheckOptions, DiscreteCheck, Extremum, IndependentCheck, check_certificate,
    discrete_check,
};
