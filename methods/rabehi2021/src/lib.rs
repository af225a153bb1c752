//! Rabehi, Meslem, El Amraoui & Ramdani (2021), "Interval impulsive observer for linear systems
//! with aperiodic discrete measurements", IEEE TAC 66(11):5407–5413: a continuous-time LTI plant
//! with bounded disturbance, measured with bounded noise at instants whose spacing lies in
//! `[τmin, τmax]`; an interval predictor runs open loop between samples and both bounds are
//! corrected impulsively at every sample.
//!
//! Modules, in the paper's vocabulary:
//! * [`system`]: the plant (2)–(3), the window of Assumption 1 and the bounds of Assumptions 2–3;
//! * [`ipr`]: the internal positive representation — `A^M`, `A^N`, `Ā`, `Γ(L)`, `Γ(G1, G2)` and
//!   the width/centre block structure;
//! * [`observer`]: the interval observer (4), (8) (flows, jumps, a `sporadic-sim` observer);
//! * [`polytope`]: the Taylor polytope of `e^{Āμ}` (paper's single-piece construction or split);
//! * [`analysis`]: Theorem 1 for a given `L` — SDP over the polytope, re-verified on a dense
//!   μ-grid ([`verify`]);
//! * [`lyapunov`]: the constants of Theorem 1's proof and Lemma 1;
//! * [`synthesis`]: Proposition 1 — convex restriction `F = I`, alternating LMI steps, sequential
//!   convex inner approximation, Remark 6 re-verification with `Γ(L)`;
//! * [`window`]: necessary limits on `τmax` and the bisection for the largest certified window;
//!   [`table`]: Table I;
//! * [`width`]: the deterministic interval width, its periodic orbits and guaranteed bounds;
//! * [`simulation`]: plant + observer with random admissible `d`, `v` and sampling, inclusion
//!   check;
//! * [`example`] and [`reproduce`](mod@reproduce): §V, Table I and Figures 1–2.
//!
//! ```
//! use sporadic_rabehi2021::analysis::{AnalysisOptions, analyse_gain};
//! use sporadic_rabehi2021::example::{example_window, paper_gain, spring_mass_damper};
//!
//! // Theorem 1 for the gain printed in §V on [0.04, 0.3].
//! let plant = spring_mass_damper(1.0)?;
//! let a = analyse_gain(&plant, &example_window(), paper_gain().as_ref(), &AnalysisOptions::default())?;
//! assert!(a.certified && a.grid.bound < 0.0);
//! # Ok::<(), sporadic_rabehi2021::Error>(())
//! ```

pub mod analysis;
mod error;
pub mod example;
pub mod ipr;
pub mod lyapunov;
pub mod observer;
pub mod polytope;
pub mod simulation;
pub mod synthesis;
pub mod system;
pub mod table;
pub mod verify;
pub mod width;
pub mod window;

pub use error::Error;
pub use sporadic_embed::TaylorOrder;
