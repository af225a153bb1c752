//! Interval splitting: embed `e^{Aτ}` on sub-intervals of `[T1, T2]` and take the union of the
//! vertex sets.
//!
//! An optional refinement (not in the papers): a wide
//! window gives a wide coefficient box (residue method) or a large `‖A‖h` (Taylor method), hence
//! conservatism. On `p` pieces the union `∪_i co(V_i) ⊂ co(∪_i V_i)` still contains the curve,
//! the vertex count grows **linearly** in `p` (`p · 2^K` or `p · (N + 1)`), and each piece is
//! tighter. The residue decomposition is computed once and reused on every piece (it does not
//! depend on the window, Remark 9 of Ferrante et al. 2016).

use faer::MatRef;

use crate::EmbedError;
use crate::embedding::Embedding;
use crate::interval::Interval;
use crate::residue::{ResidueExpansion, ResidueOptions};
use crate::taylor::{TaylorOptions, taylor_embedding};

/// Which construction to use on each (sub-)interval.
#[derive(Debug, Clone, PartialEq)]
pub enum EmbeddingMethod {
    /// Residue box (Ferrante et al. 2016, §4.1).
    Residue(ResidueOptions),
    /// Truncated Taylor polytope (Rabehi et al. 2021, §IV).
    Taylor(TaylorOptions),
}

/// Embedding of `{e^{Aτ} : τ ∈ [t1, t2]}` with the chosen method on the whole window.
pub fn embed(
    a: MatRef<'_, f64>,
    t1: f64,
    t2: f64,
    method: &EmbeddingMethod,
) -> Result<Embedding, EmbedError> {
    embed_split(a, t1, t2, 1, method)
}

/// Embedding on `pieces` equal sub-intervals of `[t1, t2]`, vertex sets united (exact duplicates
/// removed). The containment statement is the weakest of the pieces', the remainder bound the
/// largest.
pub fn embed_split(
    a: MatRef<'_, f64>,
    t1: f64,
    t2: f64,
    pieces: usize,
    method: &EmbeddingMethod,
) -> Result<Embedding, EmbedError> {
    let iv = Interval::new(t1, t2)?;
    if pieces == 0 {
        return Err(EmbedError::InvalidArgument(
            "the sampling window cannot be split into 0 pieces".into(),
        ));
    }
    let parts = if iv.is_point() {
        vec![iv]
    } else {
        iv.split(pieces)?
    };
    let embeddings = match method {
        EmbeddingMethod::Residue(options) => {
            let expansion = ResidueExpansion::with_options(a, options.clone())?;
            parts
                .iter()
                .map(|p| expansion.embed(p.t1(), p.t2()))
                .collect::<Result<Vec<_>, _>>()?
        }
        EmbeddingMethod::Taylor(options) => parts
            .iter()
            .map(|p| taylor_embedding(a, p.t1(), p.t2(), options))
            .collect::<Result<Vec<_>, _>>()?,
    };
    Ok(if embeddings.len() == 1 {
        embeddings.into_iter().next().expect("one piece")
    } else {
        Embedding::union(iv, embeddings)
    })
}
