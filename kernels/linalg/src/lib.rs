//! Dense linear-algebra kernels for `sporadic`.
//!
//! * [`expm()`], [`expm_scaled`]: matrix exponential by Al-Mohy & Higham (2009), Algorithm 6.1
//!   (see [`expm()`]); [`expm_stepper`] for e^{Aτ} on long uniform grids.
//! * Van Loan (1978) integrals: [`zoh`], [`expm_integral`], [`gramian_integral`].
//! * Symmetric helpers: [`he`], [`sym_part`], [`min_eigenvalue`], [`max_eigenvalue`],
//!   [`is_positive_definite`], [`svec`], [`smat`]; general ones: [`kron`], [`null_space`],
//!   [`spectral_radius`], [`lyap_continuous`], [`lyap_discrete`].
//! * [`pbh_detectability`]: the Popov–Belevitch–Hautus test of detectability of a discrete-time
//!   pair `(Φ, C)`, e.g. a sampled plant `(e^{AT}, C)`.
//! * [`golden_section`]: one-dimensional minimisation by golden-section search.
//!
//! Every fallible function returns [`LinalgError`] ([`golden_section`]: the objective's own error
//! type, which wraps [`InputError`]); bad input (wrong shape, empty, NaN/Inf) never panics.

pub mod balance;
mod check;
mod detectability;
mod error;
mod expm;
pub mod gramian_form;
pub mod input;
mod kronecker;
mod lyapunov;
mod minimize;
mod normest;
mod schur;
mod spectral;
mod stepper;
mod subspace;
pub mod symmetric;
mod van_loan;

pub use detectability::{PbhMode, PbhOptions, PbhTest, aliasing_instants, pbh_detectability};
pub use error::LinalgError;
pub use expm::{EXACT_NORM_MAX_ORDER, PadeParameters, expm, expm_parameters, expm_scaled};
pub use input::InputError;
pub use kronecker::kron;
pub use lyapunov::{lyap_continuous, lyap_discrete};
pub use minimize::{Minimum, golden_section};
pub use spectral::{RealEigenbasis, real_eigenbasis, spectral_radius};
pub use stepper::{DEFAULT_REANCHOR, ExpmStepper, expm_stepper};
pub use subspace::null_space;
pub use symmetric::{
    he, is_positive_definite, max_eigenvalue, min_eigenvalue, smat, svec, sym_part,
};
pub use van_loan::{expm_integral, gramian_integral, zoh};
