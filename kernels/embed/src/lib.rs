//! `sporadic-embed`: polytopic over-approximations used by LMI observer designs for sporadic
//! sampling.
//!
//! * **Residue embedding** ([`residue`]) of `{e^{Av} : v ∈ [T1, T2]}` — Ferrante, Gouaisbaut,
//!   Sanfelice & Tarbouriech, *State estimation of linear systems in the presence of sporadic
//!   measurements*, Automatica 2016, §4.1 eqs. (42)–(43): residues of the resolvent (contour
//!   moments, any multiplicity, clustered eigenvalues), exact extrema of the scalar
//!   coefficient functions ([`coefficient`]), box corners as vertices.
//! * **Taylor embedding** ([`taylor`]) — Rabehi, Meslem, El Amraoui & Ramdani, *Interval
//!   impulsive observer for linear systems with aperiodic discrete measurements*, IEEE TAC 2021
//!   (§IV, Taylor method of Hetel et al.): `e^{AT1} Σ_{k≤j} (Ah)^k/k!`, with a rigorous
//!   remainder bound and automatic order.
//! * **Interval splitting** ([`split`]): any method on sub-intervals, union of vertex sets.
//! * **Jacobian polytope** ([`jacobian`]) — Etienne, Hetel, Efimov & Petreczky, *Observer
//!   synthesis under time-varying sampling for Lipschitz nonlinear systems*, Automatica 2017,
//!   Lemma 1: `A + GΘH` over a box of Jacobian bounds.
//!
//! Every embedding of the exponential is returned as an [`Embedding`]: vertices, window,
//! [`Method`], a [`Containment`] statement and a remainder bound, with hull-membership tools
//! ([`Embedding::contains`], [`Embedding::max_violation`]) built on Wolfe's minimum-norm-point
//! algorithm ([`hull`]).
//!
//! ```
//! use faer::mat;
//! use sporadic_embed::{ResidueExpansion, Containment};
//!
//! let a = mat![[0.0, 1.0], [-2.0, -3.0]]; // eigenvalues −1, −2
//! let e = ResidueExpansion::new(a.as_ref())?.embed(0.2, 3.0)?;
//! assert_eq!(e.vertex_count(), 4);
//! assert_eq!(e.containment(), &Containment::Guaranteed);
//! assert!(e.contains(1.0)?);
//! # Ok::<(), sporadic_embed::EmbedError>(())
//! ```

pub mod coefficient;
mod corners;
pub mod embedding;
pub mod error;
pub mod hull;
pub mod interval;
pub mod jacobian;
pub mod residue;
pub mod split;
pub mod taylor;

pub use coefficient::{CoefficientFunction, CoefficientRange};
pub use embedding::{Containment, Embedding, Method};
pub use error::EmbedError;
pub use hull::{HullDistance, hull_distance};
pub use interval::Interval;
pub use jacobian::{JacobianPolytope, jacobian_polytope, lipschitz_box};
pub use residue::{
    Contour, DECAY_EXPONENTS, EigenCluster, ExpansionTerm, ResidueExpansion, ResidueOptions,
    SERIES_SPLIT_DEPTH, SHORT_WINDOW_EXTRA_TERMS, TruncatedExpansion, residue_embedding,
};
pub use split::{EmbeddingMethod, embed, embed_split};
pub use taylor::{TaylorOptions, TaylorOrder, taylor_embedding, taylor_weights, truncation_tail};
