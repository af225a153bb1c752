//! Andrieu, Nadri, Serres & Vivalda (2014), "Continuous discrete observer with updated sampling period
//! (long version)", HAL hal-00828578v2: a high-gain observer for triangular systems in observability
//! normal form whose **next output sample is taken when `(time since last sample) · L = α`**, where the
//! high gain `L` grows with an online estimate `c(x̂, u)` of the local Lipschitz constant.
//!
//! Modules, in the paper's vocabulary:
//! * [`system`]: the class of systems (1)–(4) ([`TriangularSystem`]), inputs and plants;
//! * [`observer`]: the observer (5)–(7) ([`Tuning`], closed-form gain [`high_gain`], [`jump`]);
//! * [`design`]: the computable constants of Theorem 2 (`P`, `p1..p4`, `a1`, `α_m`, `N1`, `N2`, `a2`);
//! * [`closed_loop`]: plant + observer on the hybrid simulator `sporadic-sim` ([`run`]);
//! * [`lemma1`]: the a-posteriori bound of Lemma 1 on `L`;
//! * [`certificate`]: the Lyapunov decrease of the proof of Theorem 2 along a run;
//! * [`bioreactor`]: the Contois example of Section 4 with its misprints corrected;
//! * [`normal_form`]: a plant file's plant (linear, or with a triangular Lipschitz nonlinearity)
//!   in the observability normal form (1) through one output ([`NormalForm`]);
//! * [`plant_design`]: Theorem 2's observer for such a plant, with the range of inter-sample
//!   intervals its rule (7) guarantees ([`PlantDesign`]); [`simulation`]: its closed loop;
//! * [`method`]: the [`sporadic_model::ObserverMethod`] contract ([`Andrieu2014`]);
//! * [`pendulum`]: a globally Lipschitz pendulum in normal form, used to check Theorem 2's
//!   constants on a system where every bound is known in closed form.
//!
//! The reproduction of the paper's examples lives in the `sporadic-reproductions` crate.
//!
//! Deviations from the printed paper (all documented where they apply): the index of the correction (5)
//! (the multiplier is the period that ends at the sample, as the proof's (12) requires); `a2 ≥ 2n(N1 +
//! N2)/(p3 p1)` (Step 3) instead of the design paragraph's `2(N1+N2)/(p3p1)`; Lemma 1's bound includes
//! `L(0)`; the bioreactor's `f2` uses `2/x1` instead of the printed `(2−u)/x1`, and its Lipschitz
//! coefficients are the exact difference quotients with absolute values.

//! ```
//! use sporadic_andrieu2014::pendulum::Pendulum;
//! use sporadic_andrieu2014::{Design, NormalFormPlant, RunOptions, run};
//! use sporadic_sim::{PiecewiseConstant, ZeroNoise};
//!
//! // (D1)–(D4) for n = 2, K = [−2, −1]', W = I; α = 0.2 < α_m ≈ 0.418, a2 = a2,min(0.2) ≈ 56.23.
//! let design = Design::binomial(2, 1.0)?;
//! let tuning = design.theorem_tuning(0.2)?;
//! let no_input = PiecewiseConstant::constant(vec![])?;
//! let r = run(&NormalFormPlant(Pendulum), &[1.0, 0.0], &Pendulum, &[-1.0, 2.0], &no_input, &tuning,
//!             &mut ZeroNoise::new(1), &RunOptions::new(1.0))?;
//! for s in &r.samples {
//!     // Sampling rule (7): δ_k L(t_{k+1}^-) = α.
//!     assert!((s.delta * s.l_minus - tuning.alpha()).abs() < 1e-9 * tuning.alpha());
//! }
//! let e = r.samples.last().unwrap().error();
//! assert!(e.iter().all(|v| v.abs() < 1e-10));
//! # Ok::<(), sporadic_andrieu2014::Error>(())
//! ```

pub mod bioreactor;
pub mod certificate;
pub mod closed_loop;
pub mod design;
mod error;
pub mod lemma1;
pub mod method;
pub mod normal_form;
pub mod observer;
mod pencil;
pub mod pendulum;
pub mod plant_design;
pub mod simulation;
pub mod system;

pub use certificate::{LyapunovStep, lyapunov_steps};
pub use closed_loop::{Run, RunOptions, SampleRecord, run};
pub use design::{Design, binomial_gain, geometric_weights, q_matrix};
pub use error::Error;
pub use lemma1::{Lemma1Bound, lemma1_bound};
pub use method::Andrieu2014;
pub use normal_form::NormalForm;
pub use observer::{Jump, Tuning, gain_jump, high_gain, jump, sampling_function};
pub use plant_design::PlantDesign;
pub use system::{NormalFormPlant, Plant, TriangularSystem};
