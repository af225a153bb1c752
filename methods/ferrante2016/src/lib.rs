//! Ferrante, Gouaisbaut, Sanfelice & Tarbouriech (2016), "State estimation of linear systems in the
//! presence of sporadic measurements", Automatica 73: an observer `ẑ` that runs open loop between
//! samples and jumps `ẑ⁺ = ẑ + L(y − Mẑ)` when a measurement arrives, for inter-sample times in a
//! window `[T1, T2]`, designed through a hybrid Lyapunov function and a polytopic embedding of `e^{Av}`.
//!
//! Modules, in the paper's vocabulary:
//! * [`system`]: the data of Problem 1, [`Plant`] `(A, M)` and [`Window`] `[T1, T2]`;
//! * [`detectability`]: the necessary condition of Remark 3 (`(e^{Av}, M)` detectable on the window,
//!   including the aliasing instants a grid would miss), with [`Error::NotDetectable`];
//! * [`design`](mod@design): Corollary 1 — LMI (41) over the vertices of a residue (default), Taylor or
//!   split embedding, margin maximisation, `L = F⁻¹J` ([`design()`]); and the same LMI with `J = FL`
//!   to certify a given gain ([`analyse`]);
//! * [`verify`](mod@verify): the embedding-independent grid check of (12) and of the Schur property of
//!   `e^{Av}(I − LM)`;
//! * [`bounds`]: the constants of Theorems 1 and 2 (`α1, α2, β, θ, γ, R, κ`, ISS gain) and the GES
//!   bound as a function of `(t, j)`;
//! * [`window`]: the largest certifiable `T2` for a given `T1` (and smallest `T1` for a given `T2`);
//! * [`simulation`]: the observer and its error system simulated with `sporadic-sim`, and the check
//!   of the Theorem 1 bound along a solution;
//! * [`examples`] and [`reproduce`](mod@reproduce): Examples 1 and 2 and Figures 1 and 2 as a
//!   [`sporadic_report::Reproduction`].
//!
//! Corrections of the printed paper (each documented where it applies): `κ = √(α2/α1)e^{R/2}` in
//! (21) (printed `e^{R/α1}`); `ρ = ‖P‖(1 + 2‖P‖/β)max‖e^{Av}‖²` in Theorem 2 (the printed
//! `‖P‖(2/β + ‖P‖)…` is also computed); `(α2/α1)e^{R}` in (34). Additions that are not in the paper:
//! the robust form of (41) for embeddings with a remainder, the equivalent reduced `2n × 2n` vertex
//! LMI ([`LmiForm::Reduced`]), interval splitting, and the window searches.
//!
//! ```
//! use sporadic_ferrante2016::examples::example1;
//! use sporadic_ferrante2016::{BoundOptions, DesignOptions, analyse, bound_constants};
//!
//! // Example 1: A = M = 1, T1 = T2 = 1, L = 1.1 − e^{−1}, P = 1.
//! let ex = example1()?;
//! let c = bound_constants(&ex.plant, &ex.window, ex.l.as_ref(), ex.p.as_ref(), &BoundOptions::default())?;
//! assert!((c.theorem1.beta - 0.4698).abs() < 5e-5);
//! assert!((c.theorem1.theta + 0.0657).abs() < 5e-5);
//! // LMI (41) with J = F·L certifies the gain.
//! assert!(analyse(&ex.plant, &ex.window, ex.l.as_ref(), &DesignOptions::default())?.certified);
//! # Ok::<(), sporadic_ferrante2016::Error>(())
//! ```

pub mod bounds;
pub mod design;
pub mod detectability;
mod error;
pub mod examples;
mod grid;
mod lmi;
pub mod simulation;
pub mod system;
pub mod verify;
pub mod window;

pub use bounds::{BoundConstants, BoundOptions, Theorem1Bound, Theorem2Bound, bound_constants};
pub use design::{
    Analysis, Certificate, Design, DesignOptions, TraceCertificate, analyse, design,
    min_trace_certificate,
};
pub use detectability::{DetectabilityOptions, DetectabilityReport, check_detectability};
pub use error::Error;
pub use lmi::{LmiForm, SolverStats};
pub use simulation::{BoundCheck, check_bound, simulate_error, simulate_observer};
pub use system::{Plant, Window};
pub use verify::{Verification, VerifyOptions, verify};
pub use window::{Probe, WindowSearch, WindowSearchOptions, largest_t2, smallest_t1};
