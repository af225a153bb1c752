//! Etienne, Hetel, Efimov & Petreczky (2017), "Observer synthesis under time-varying sampling for
//! Lipschitz nonlinear systems", Automatica 85: an impulsive observer that copies the plant
//! `ẋ = Ax + Bu + Gφ(Hx)` between samples and resets `x̂⁺ = x̂ + K(τ)(y − Cx̂)` with a gain
//! depending on the length `τ` of the interval that just ended, for every sampling sequence with
//! `t_{k+1} − t_k ∈ [τ_low, τ̄]` (a [`SamplingWindow`] `[T1, T2]`). Finite LMIs (no matrix
//! exponential) certify it.
//!
//! Modules, in the paper's vocabulary:
//! * [`method`]: the [`ObserverMethod`] contract ([`Etienne2017`]): Corollary 2 first, Theorem 3
//!   when it fails, Remark 6 for a periodic window; the largest window by the shared search;
//! * [`system`]: the plant (1)–(2) with Jacobian bounds and the vertices `R_p` of Lemma 1
//!   ([`Plant`]);
//! * [`conditions`]: the matrices of (16c), (19b)–(19c) and (20a)–(20d) at given numbers, the
//!   interpolations of the proof of Theorem 3, and the gain recovery `K = P1⁻¹L`;
//! * [`lmi`]: LMIs (20) as one margin problem, for Theorem 3, Corollary 2 and Remark 6
//!   ([`Condition`]);
//! * [`design`](mod@design): synthesis ([`design()`]), analysis of a given gain ([`analyse`]) and
//!   the raw margin ([`solve_margin`]);
//! * [`gain`]: the schedule `K(τ)` ([`GainSchedule`]);
//! * [`verify`]: the solver-independent checks (eigenvalues of every block, τ-grid check of
//!   (19b)/(19c), contraction of `z'P1z` across `(I − K(τ)C)e^{R_pτ}`);
//! * [`prove`](mod@prove): the rigorous proof, in interval arithmetic, of Corollary 1's
//!   conditions for a design's `K(τ)`, `P1`, `P2` for every `τ` of the window and every member
//!   of the Jacobian polytope ([`prove_design`], issue 24);
//! * [`bisection`]: the largest `τ̄` for a given `τ_low` ([`max_tau_bar`]) and the largest
//!   period ([`max_period`]), on the shared window search;
//! * [`simulation`]: the nonlinear plant and observer with `sporadic-sim`;
//! * [`example`]: the flexible-joint robot of §5 and the printed gains.
//!
//! The OCR of the paper garbles (16c), (19c) and the block `B(τ)` of the proof of Theorem 3;
//! the forms used here are the only ones consistent with the stated Schur complement and with
//! (20c)/(20d). Remark 6 says "periodic sampling (τ̄ > τ_low)": it is `τ̄ = τ_low`.
//!
//! Through the common contract, for a damped pendulum `ẍ = −sin x − 0.5ẋ` (the nonlinearity
//! `φ(s) = −sin s` has its derivative in `[−1, 1]`) whose angle is sampled every 0.05 to 0.2 s:
//!
//! ```
//! use sporadic_etienne2017::faer::mat;
//! use sporadic_etienne2017::sporadic_model::{Lipschitz, Plant};
//! use sporadic_etienne2017::{
//!     Etienne2017, MethodOptions, ObserverMethod, Sampling, SamplingWindow,
//! };
//!
//! let lipschitz = Lipschitz::new(
//!     mat![[0.0], [1.0]].as_ref(), // G
//!     mat![[1.0, 0.0]].as_ref(),   // H
//!     mat![[-1.0]].as_ref(),       // lower bound of φ'
//!     mat![[1.0]].as_ref(),        // upper bound of φ'
//! )?;
//! let plant = Plant::linear(mat![[0.0, 1.0], [0.0, -0.5]].as_ref(), None, mat![[1.0, 0.0]].as_ref())?
//!     .with_lipschitz(lipschitz)?
//!     .named("pendulum");
//! let sampling = Sampling::Synchronous(SamplingWindow::new(0.05, 0.2)?);
//! let report = Etienne2017::default().design(&plant, &sampling, &MethodOptions::default())?;
//! assert!(report.status.is_certified());
//! let k = report.gain("K").unwrap().to_mat();
//! assert_eq!((k.nrows(), k.ncols()), (2, 1)); // n × q
//! assert!(report.margin.unwrap().value > 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! With the crate's own entry points, on the paper's example:
//!
//! ```
//! use sporadic_etienne2017::{Condition, DesignOptions, SamplingWindow, design, example};
//!
//! let plant = example::flexible_joint()?;
//! // Theorem 3 on [0.01, 0.3] (Corollary 2 is infeasible there).
//! let w = SamplingWindow::new(0.01, 0.3)?;
//! let d = design(&plant, Condition::Theorem3, &w, &DesignOptions::default())?;
//! let k = d.gain.at(0.15); // K(τ) between K0 = K(0.01) and K1 = K(0.3)
//! assert_eq!((k.nrows(), k.ncols()), (4, 2));
//! assert!(d.check.passed());
//! # Ok::<(), sporadic_etienne2017::Error>(())
//! ```

pub mod bisection;
pub mod conditions;
pub mod coordinates;
pub mod design;
mod error;
pub mod example;
pub mod gain;
pub mod lmi;
pub mod method;
pub mod prove;
pub mod simulation;
pub mod system;
pub mod verify;

pub use bisection::{
    BisectionOptions, MaxTauBar, TableRow, max_period, max_tau_bar, max_tau_bar_table,
};
pub use design::{
    Design, DesignOptions, DwellFreeMargin, MarginSolution, analyse, analyse_margin, design,
    solve_margin, solve_margin_without_dwell,
};
pub use error::Error;
pub use gain::GainSchedule;
pub use lmi::Condition;
pub use method::{Conditions, Etienne2017, balanced_plant};
pub use prove::prove_design;
pub use simulation::{
    Input, Nonlinearity, SimulationSetup, error_norm_after, error_norm_after_sample,
    lyapunov_at_samples, simulate_observer, worst_case_sampling,
};
pub use system::Plant;
pub use verify::{
    Certificate, CheckOptions, DiscreteCheck, Extremum, IndependentCheck, check_certificate,
    discrete_check,
};

// The crates whose types appear in this crate's API, and their items at the root, so that a user
// needs no other crate (and no version-pinned faer). `sporadic_model::Plant` (the plant of the
// common contract) is reached as `sporadic_model::Plant`: this crate's `Plant` is the Lipschitz
// plant (1)–(2) with its vertices.
pub use faer;
pub use sporadic_embed;
pub use sporadic_embed::{EmbedError, JacobianPolytope};
pub use sporadic_linalg::{InputError, LinalgError};
pub use sporadic_model;
pub use sporadic_model::{
    Bracketing, DesignReport, MaxIntervalReport, MethodError, MethodOptions, NotApplicable,
    ObserverMethod, Probe, Reason, Sampling, SamplingWindow, SolverStats, Status, Tolerance,
    WindowSearch, WindowSearchOptions,
};
pub use sporadic_sdp;
pub use sporadic_sdp::lmi::{FeasibilityOptions, ModelError, Outcome};
pub use sporadic_sim;
pub use sporadic_sim::{Adversarial, Dopri5Options, HybridArc, SamplingRule, SimError, Simulation};
