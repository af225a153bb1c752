//! The polytopic over-approximation of `{e^{Āμ} : μ ∈ [τmin, τmax]}` used by (44) (Rabehi et al.
//! 2021, §IV-B, "Taylor's series" method of Hetel, Daafouz & Iung): a thin wrapper around
//! [`sporadic_embed::taylor_embedding`] / [`sporadic_embed::embed_split`].
//!
//! On a piece `[t1, t2]` (`h = t2 − t1`, `E0 = e^{Ā t1}`) the vertices are
//! `M_j = E0 Σ_{k≤j} (Āh)^k/k!`, `j = 0..N`, and `e^{Āμ} = Σ_j w_j(μ) M_j + Δ(μ)` with barycentric
//! weights `w_j ≥ 0` and `‖Δ‖_F ≤ δ` (the embedding's `remainder_bound`). The paper gives neither
//! the order nor the remainder treatment. By default the order is the smallest one meeting a
//! remainder tolerance and the window is split into pieces of bounded `‖Ā‖₂·h`: a long single
//! piece has vertices `E0(I + Āh)`, `E0(I + Āh + (Āh)²/2)`, … far from the curve, i.e. a much
//! larger hull, and the hull grows with `N` (the vertex sets are nested). [`PolytopeOptions::paper`]
//! is the single-piece construction of the paper (one polytope on the whole window), with a fixed
//! order. The factor
//! `e^{Āτmin}` is always kept: a hull containing `I` would make (44) infeasible whenever `Γ` has
//! an eigenvalue `1` (e.g. `G e_j = e_j` for an unmeasured state `j`).

use faer::MatRef;
use sporadic_embed::{Embedding, EmbeddingMethod, TaylorOptions, TaylorOrder, embed_split};
use sporadic_linalg::InputError;

use crate::error::Error;
use sporadic_model::SamplingWindow;

/// How the Taylor polytope is built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolytopeOptions {
    /// Truncation order `N` per piece: fixed, or the smallest one whose remainder bound (Frobenius
    /// norm of `Δ(μ)`) meets a tolerance. Default `Tolerance(1e-9)`.
    pub order: TaylorOrder,
    /// Largest `‖Ā‖₂·h` of one piece; the window is split into `⌈‖Ā‖₂(τmax − τmin)/x⌉` equal
    /// pieces. Default `0.5`.
    pub max_piece_spread: f64,
    /// Fixed number of pieces, overriding `max_piece_spread`.
    pub pieces: Option<usize>,
}

impl Default for PolytopeOptions {
    fn default() -> Self {
        Self {
            order: TaylorOrder::Tolerance(1e-9),
            max_piece_spread: 0.5,
            pieces: None,
        }
    }
}

impl PolytopeOptions {
    /// One Taylor polytope on the whole window with the fixed order `order` (the construction the
    /// paper describes; `N = 10` gives the reference values of Table I with the convex restriction
    /// `F = I`).
    pub fn paper(order: usize) -> Self {
        Self {
            order: TaylorOrder::Fixed(order),
            max_piece_spread: 0.5,
            pieces: Some(1),
        }
    }

    pub(crate) fn validate(&self) -> Result<(), Error> {
        if let TaylorOrder::Tolerance(tol) = self.order
            && !(tol > 0.0 && tol.is_finite())
        {
            return Err(InputError::parameter(
                "Taylor remainder tolerance",
                tol,
                "must be finite and > 0",
            )
            .into());
        }
        if !(self.max_piece_spread > 0.0 && self.max_piece_spread.is_finite()) {
            return Err(InputError::parameter(
                "max_piece_spread",
                self.max_piece_spread,
                "must be finite and > 0",
            )
            .into());
        }
        if self.pieces == Some(0) {
            return Err(InputError::parameter("pieces", 0.0, "must be at least 1").into());
        }
        Ok(())
    }
}

/// Number of pieces for a window under the options.
pub(crate) fn piece_count(
    a_norm: f64,
    window: &SamplingWindow,
    options: &PolytopeOptions,
) -> usize {
    options.pieces.unwrap_or_else(|| {
        let spread = a_norm * (window.t2() - window.t1());
        ((spread / options.max_piece_spread).ceil() as usize).max(1)
    })
}

/// Spectral norm `‖M‖₂ = √λmax(MᵀM)` (via `sporadic_linalg::max_eigenvalue`).
pub(crate) fn norm2(m: MatRef<'_, f64>) -> Result<f64, Error> {
    let g = m.transpose() * m;
    let sym = sporadic_linalg::sym_part(g.as_ref())?;
    Ok(sporadic_linalg::max_eigenvalue(sym.as_ref())?
        .max(0.0)
        .sqrt())
}

/// The Taylor polytope of `e^{Āμ}`, `μ ∈ [τmin, τmax]` (see the module docs).
///
/// # Errors
/// Invalid options, a bad `Ā`, or an embedding failure (e.g. an unreachable tolerance).
pub fn taylor_polytope(
    a_bar: MatRef<'_, f64>,
    window: &SamplingWindow,
    options: &PolytopeOptions,
) -> Result<Embedding, Error> {
    options.validate()?;
    let pieces = piece_count(norm2(a_bar)?, window, options);
    let method = EmbeddingMethod::Taylor(TaylorOptions {
        order: options.order,
        ..TaylorOptions::default()
    });
    Ok(embed_split(
        a_bar,
        window.t1(),
        window.t2(),
        pieces,
        &method,
    )?)
}
