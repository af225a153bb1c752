//! Round-robin sampled-data observer with jitter (Sferlazza, Tarbouriech & Zaccarian, *Automatica*
//! 129:109573, 2021) and the sequential-refinement design loop of its §5.3.
//!
//! `N` sensors `y_σ = C_σx` are read one at a time in round-robin order; sensor σ is read when the
//! time since the previous sample lies in its window `[T_mσ, T_Mσ]` (the convention of the hybrid
//! model (9)). Between samples the observer runs open loop; at a sample
//! `x̂⁺ = x̂ + K_σ(τ)(y_σ − C_σx̂)` with the gain (45) computed from a Lyapunov matrix `P_σ`.
//!
//! Modules, in the paper's vocabulary:
//! * [`plant`]: the plant, sensors, windows and the complements `C_σ^⊥` (Assumptions 1–2);
//! * [`detectability`]: the necessary condition of Proposition 1 (PBH on the lifted pair);
//! * [`gain`]: `K_σ(τ)` by (45) and by its closed form, `Φ_σ(τ)`;
//! * [`jitter_free`]: design LMI (23) with gains (24), analysis LMI (18), the monodromy (19);
//! * [`exponential_bound`], [`synthesis`], [`validation`], [`design`](mod@design): the §5.3
//!   algorithm — Step 1 (β, γ), the synthesis SDP (47), the grid validation (48)–(50) with three
//!   grid policies, and the loop with its iteration log;
//! * [`iss`]: the constants of the proof of Theorem 3;
//! * [`simulation`]: the error dynamics (53) and the Lyapunov function (30) along them;
//! * [`example`] and [`reproduce`](mod@reproduce): the quarter-car suspension of §6 and its
//!   reproduction as a [`sporadic_report::Reproduction`].
//!
//! Corrections of the printed paper (spec 001, each documented where it applies): the window
//! convention of (4)/Definition 1 is reversed with respect to (9); the noise enters the jump as
//! `−K_σw` (printed `+K_σw` in (28)/(53)); `Ψ_σ` in the proof of Theorem 4 uses `P_σ`, not `P_Γ(σ)`;
//! (46) has `−P_ΓK_σC_σC_σᵀ`; the matrices printed in (52) are not a solution (`P_2` is indefinite).

pub mod design;
pub mod detectability;
pub mod error;
pub mod example;
pub mod exponential_bound;
pub mod gain;
pub mod iss;
pub mod jitter_free;
pub mod plant;
pub mod simulation;
pub mod synthesis;
pub mod validation;

pub use error::Error;
