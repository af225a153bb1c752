//! The data of the problem (Etienne, Hetel, Efimov & Petreczky 2017, §2, eqs. (1)–(2)): the
//! Lipschitz plant
//!
//! ```text
//! ẋ = A x + B u + G φ(H x),     y_k = C x(t_k),
//! a_ij ≤ ∂φ_i/∂s_j ≤ b_ij       (Jacobian bounds; [−γ, γ] from a Lipschitz constant γ),
//! ```
//!
//! with the vertices `R_p = A + G Θ^{(p)} H` of Lemma 1 (built by
//! [`sporadic_embed::jacobian_polytope`]). The sampling class
//! `S[τ_low, τ̄] = {(t_k) : t_{k+1} − t_k ∈ [τ_low, τ̄]}` is a [`SamplingWindow`]
//! `[T1, T2] = [τ_low, τ̄]`.
//!
//! [`SamplingWindow`]: sporadic_model::SamplingWindow
//!
//! `B` and the nonlinearity `φ` itself do not enter the error dynamics' polytopic embedding, so
//! the LMIs only need `(R_p, C)`; simulations take `φ` separately
//! ([`crate::simulation::Nonlinearity`]).

use faer::{Mat, MatRef};
use sporadic_embed::{JacobianPolytope, jacobian_polytope, lipschitz_box};
use sporadic_linalg::InputError;
use sporadic_linalg::input::{check_finite, check_shape};

use crate::error::Error;

/// Plant (1)–(2) with Jacobian bounds on `φ`, and its Lemma 1 vertices `R_p`.
#[derive(Debug, Clone)]
pub struct Plant {
    a: Mat<f64>,
    b: Mat<f64>,
    c: Mat<f64>,
    g: Mat<f64>,
    h: Mat<f64>,
    polytope: JacobianPolytope,
}

impl Plant {
    /// Validates the data (`A` n×n, `B` n×l (l may be 0), `C` q×n, `G` n×m, `H` m×n, the Jacobian
    /// bounds m×m with `lower ≤ upper` entrywise; everything finite, `n, q, m ≥ 1`) and builds the
    /// vertices `R_p` (Lemma 1).
    pub fn new(
        a: MatRef<'_, f64>,
        b: MatRef<'_, f64>,
        c: MatRef<'_, f64>,
        g: MatRef<'_, f64>,
        h: MatRef<'_, f64>,
        jacobian_lower: MatRef<'_, f64>,
        jacobian_upper: MatRef<'_, f64>,
    ) -> Result<Self, Error> {
        if a.nrows() != a.ncols() {
            return Err(Error::Input(InputError::NotSquare {
                what: "A".into(),
                rows: a.nrows(),
                cols: a.ncols(),
            }));
        }
        let n = a.nrows();
        if n == 0 {
            return Err(InputError::empty("A (n = 0)").into());
        }
        if c.nrows() == 0 {
            return Err(InputError::empty("C (no measured output, q = 0)").into());
        }
        if g.ncols() == 0 {
            return Err(InputError::empty("G (no nonlinearity, m = 0)").into());
        }
        let m = g.ncols();
        check_shape(b, n, b.ncols(), "B")?;
        check_shape(c, c.nrows(), n, "C")?;
        check_shape(g, n, m, "G")?;
        check_shape(h, m, n, "H")?;
        check_shape(jacobian_lower, m, m, "lower Jacobian bound")?;
        check_shape(jacobian_upper, m, m, "upper Jacobian bound")?;
        for (x, what) in [
            (a, "A"),
            (b, "B"),
            (c, "C"),
            (g, "G"),
            (h, "H"),
            (jacobian_lower, "lower Jacobian bound"),
            (jacobian_upper, "upper Jacobian bound"),
        ] {
            check_finite(x, what)?;
        }
        for j in 0..m {
            for i in 0..m {
                let (lo, hi) = (jacobian_lower[(i, j)], jacobian_upper[(i, j)]);
                if lo > hi {
                    return Err(Error::InvalidJacobianBounds {
                        row: i,
                        col: j,
                        lower: lo,
                        upper: hi,
                    });
                }
            }
        }
        let polytope = jacobian_polytope(a, g, h, jacobian_lower, jacobian_upper)?;
        Ok(Self {
            a: a.to_owned(),
            b: b.to_owned(),
            c: c.to_owned(),
            g: g.to_owned(),
            h: h.to_owned(),
            polytope,
        })
    }

    /// As [`Plant::new`] with the box `[−γ, γ]^{m×m}` implied by a Lipschitz constant `γ ≥ 0`
    /// (valid but conservative: `|∂φ_i/∂s_j| ≤ γ` for a `γ`-Lipschitz `φ`).
    pub fn lipschitz(
        a: MatRef<'_, f64>,
        b: MatRef<'_, f64>,
        c: MatRef<'_, f64>,
        g: MatRef<'_, f64>,
        h: MatRef<'_, f64>,
        gamma: f64,
    ) -> Result<Self, Error> {
        if !gamma.is_finite() {
            return Err(InputError::non_finite("Lipschitz constant γ").into());
        }
        if gamma < 0.0 {
            return Err(InputError::parameter(
                "gamma",
                gamma,
                "a Lipschitz constant is nonnegative",
            )
            .into());
        }
        let (lo, hi) = lipschitz_box(g.ncols(), gamma)?;
        Self::new(a, b, c, g, h, lo.as_ref(), hi.as_ref())
    }

    /// State dimension `n`.
    pub fn n(&self) -> usize {
        self.a.nrows()
    }

    /// Output dimension `q`.
    pub fn q(&self) -> usize {
        self.c.nrows()
    }

    /// Dimension `m` of the nonlinearity.
    pub fn m(&self) -> usize {
        self.g.ncols()
    }

    /// `A`.
    pub fn a(&self) -> MatRef<'_, f64> {
        self.a.as_ref()
    }

    /// `B` (n×l).
    pub fn b(&self) -> MatRef<'_, f64> {
        self.b.as_ref()
    }

    /// `C`.
    pub fn c(&self) -> MatRef<'_, f64> {
        self.c.as_ref()
    }

    /// `G`.
    pub fn g(&self) -> MatRef<'_, f64> {
        self.g.as_ref()
    }

    /// `H`.
    pub fn h(&self) -> MatRef<'_, f64> {
        self.h.as_ref()
    }

    /// The vertices `R_p = A + G Θ^{(p)} H` of Lemma 1 (`2^k` for `k` free Jacobian entries;
    /// vertex `p` takes the upper bound of the `f`-th free entry iff bit `f` of `p` is set).
    pub fn vertices(&self) -> &[Mat<f64>] {
        self.polytope.vertices()
    }

    /// The Jacobian polytope (free entries, hull membership of `A + GΘH`).
    pub fn polytope(&self) -> &JacobianPolytope {
        &self.polytope
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn plant_input_is_validated() {
        let a = mat![[0.0, 1.0], [-1.0, 0.0]];
        let b = Mat::<f64>::zeros(2, 0);
        let c = mat![[1.0, 0.0]];
        let g = mat![[0.0], [1.0]];
        let h = mat![[1.0, 0.0]];
        let p = Plant::lipschitz(
            a.as_ref(),
            b.as_ref(),
            c.as_ref(),
            g.as_ref(),
            h.as_ref(),
            1.0,
        )
        .unwrap();
        assert_eq!(p.vertices().len(), 2);
        assert!(matches!(
            Plant::lipschitz(
                a.as_ref(),
                b.as_ref(),
                mat![[1.0, 0.0, 0.0]].as_ref(),
                g.as_ref(),
                h.as_ref(),
                1.0
            ),
            Err(Error::Input(InputError::DimensionMismatch { .. }))
        ));
        assert!(matches!(
            Plant::new(
                a.as_ref(),
                b.as_ref(),
                c.as_ref(),
                g.as_ref(),
                h.as_ref(),
                mat![[f64::NEG_INFINITY]].as_ref(),
                mat![[1.0]].as_ref()
            ),
            Err(Error::Input(InputError::NonFinite { .. }))
        ));
        assert!(matches!(
            Plant::new(
                a.as_ref(),
                b.as_ref(),
                c.as_ref(),
                g.as_ref(),
                h.as_ref(),
                mat![[1.0]].as_ref(),
                mat![[0.0]].as_ref()
            ),
            Err(Error::InvalidJacobianBounds { .. })
        ));
    }
}
