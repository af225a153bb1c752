//! Jacobian (Lipschitz) polytope of the error vector field — Etienne, Hetel, Efimov & Petreczky
//! (2017), Lemma 1 (the paper gives no formula; construction by the differential mean-value
//! theorem of Zemouche, Boutayeb & Bara 2008).
//!
//! For `f(x) = Ax + Gφ(Hx)` the differential mean-value theorem gives, componentwise,
//! `φ(Hx) − φ(H(x − z)) = Θ H z` with `Θ_ij = ∂φ_i/∂s_j` evaluated at points of the segment.
//! If every entry is bounded, `a_ij ≤ ∂φ_i/∂s_j ≤ b_ij`, then `Θ` lies in a box and
//!
//! ```text
//! Az + G[φ(Hx) − φ(H(x − z))] = (A + GΘH) z ∈ co{ R_v z },   R_v = A + G Θ^{(v)} H,
//! ```
//!
//! with `Θ^{(v)}` the box corners. Entries with `a_ij = b_ij` (structurally fixed) are not
//! vertices, so there are `2^k` vertices for `k` free entries. The map `Θ ↦ A + GΘH` is affine:
//! `A + Σ_ij Θ_ij G_{:,i} H_{j,:}`.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;

use crate::EmbedError;
use crate::corners::box_vertices;
use crate::hull::{HullDistance, hull_distance};
use sporadic_linalg::input::check_finite;
use sporadic_linalg::input::check_square_finite;

/// Largest number of free Jacobian entries accepted (`2^20` vertices).
pub const MAX_FREE_ENTRIES: usize = 20;

/// The vertices `R_v = A + G Θ^{(v)} H` of Lemma 1 of Etienne et al. (2017).
#[derive(Debug, Clone)]
pub struct JacobianPolytope {
    vertices: Vec<Mat<f64>>,
    free_entries: Vec<(usize, usize)>,
    a: Mat<f64>,
    g: Mat<f64>,
    h: Mat<f64>,
    lower: Mat<f64>,
    upper: Mat<f64>,
}

/// Entrywise box `[−γ, γ]^{m×m}` for the Jacobian of a `γ`-Lipschitz `φ : R^m → R^m`
/// (`|∂φ_i/∂s_j| ≤ ‖∇φ‖₂ ≤ γ`; valid but conservative when only the Lipschitz constant is known).
pub fn lipschitz_box(m: usize, gamma: f64) -> Result<(Mat<f64>, Mat<f64>), EmbedError> {
    if !(gamma.is_finite() && gamma >= 0.0) {
        return Err(EmbedError::InvalidArgument(format!(
            "Lipschitz constant must be finite and nonnegative, got {gamma}"
        )));
    }
    Ok((
        Mat::from_fn(m, m, |_, _| -gamma),
        Mat::from_fn(m, m, |_, _| gamma),
    ))
}

/// Vertices `A + G Θ^{(v)} H` for `lower ≤ Θ ≤ upper` (entrywise; `A` n×n, `G` n×m, `H` m×n,
/// bounds m×m). Free entries (`lower < upper`) are enumerated row by row; vertex `v` takes the
/// upper bound of the `f`-th free entry iff bit `f` of `v` is set.
pub fn jacobian_polytope(
    a: MatRef<'_, f64>,
    g: MatRef<'_, f64>,
    h: MatRef<'_, f64>,
    lower: MatRef<'_, f64>,
    upper: MatRef<'_, f64>,
) -> Result<JacobianPolytope, EmbedError> {
    let n = check_square_finite(a, "A")?;
    let m = g.ncols();
    let mismatch = |what: &str, expected: usize, found: usize| {
        Err(EmbedError::Input(InputError::DimensionMismatch {
            what: what.to_owned(),
            expected,
            found,
        }))
    };
    if g.nrows() != n {
        return mismatch("rows of G", n, g.nrows());
    }
    if h.nrows() != m {
        return mismatch("rows of H (= columns of G)", m, h.nrows());
    }
    if h.ncols() != n {
        return mismatch("columns of H", n, h.ncols());
    }
    for (b, what) in [
        (lower, "lower Jacobian bound"),
        (upper, "upper Jacobian bound"),
    ] {
        if b.nrows() != m {
            return mismatch(&format!("rows of the {what}"), m, b.nrows());
        }
        if b.ncols() != m {
            return mismatch(&format!("columns of the {what}"), m, b.ncols());
        }
        check_finite(b, what)?;
    }
    check_finite(g, "G")?;
    check_finite(h, "H")?;
    let mut free_entries = Vec::new();
    let mut matrices = Vec::new();
    let mut ranges = Vec::new();
    for i in 0..m {
        for j in 0..m {
            let (lo, hi) = (lower[(i, j)], upper[(i, j)]);
            if lo > hi {
                return Err(EmbedError::InvalidBounds {
                    row: i,
                    col: j,
                    lower: lo,
                    upper: hi,
                });
            }
            if lo == 0.0 && hi == 0.0 {
                continue;
            }
            if lo < hi {
                free_entries.push((i, j));
            }
            // Rank-one direction G_{:,i} H_{j,:}.
            matrices.push(Mat::from_fn(n, n, |r, c| g[(r, i)] * h[(j, c)]));
            ranges.push((lo, hi));
        }
    }
    let refs: Vec<MatRef<'_, f64>> = matrices.iter().map(|x| x.as_ref()).collect();
    let (vertices, free) = box_vertices(Some(a), &refs, &ranges, 1 << MAX_FREE_ENTRIES, (n, n))?;
    debug_assert_eq!(free, free_entries.len());
    Ok(JacobianPolytope {
        vertices,
        free_entries,
        a: a.to_owned(),
        g: g.to_owned(),
        h: h.to_owned(),
        lower: lower.to_owned(),
        upper: upper.to_owned(),
    })
}

impl JacobianPolytope {
    /// The vertices `R_v` (`2^k` of them).
    pub fn vertices(&self) -> &[Mat<f64>] {
        &self.vertices
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    /// The entrywise lower bounds of `Θ` (m×m).
    pub fn lower(&self) -> MatRef<'_, f64> {
        self.lower.as_ref()
    }

    /// The entrywise upper bounds of `Θ` (m×m).
    pub fn upper(&self) -> MatRef<'_, f64> {
        self.upper.as_ref()
    }

    /// The free entries `(i, j)` of `Θ` in bit order.
    pub fn free_entries(&self) -> &[(usize, usize)] {
        &self.free_entries
    }

    /// `A + G Θ H` for a given `Θ` (m×m; need not lie in the box).
    pub fn matrix_at(&self, theta: MatRef<'_, f64>) -> Result<Mat<f64>, EmbedError> {
        let m = self.g.ncols();
        if theta.nrows() != m || theta.ncols() != m {
            return Err(InputError::mismatch(
                "Θ (rows·cols)",
                m * m,
                theta.nrows() * theta.ncols(),
            )
            .into());
        }
        check_finite(theta, "Θ")?;
        Ok(&self.a + &self.g * theta * &self.h)
    }

    /// Whether `Θ` satisfies the entrywise bounds.
    pub fn in_box(&self, theta: MatRef<'_, f64>) -> bool {
        theta.nrows() == self.lower.nrows()
            && theta.ncols() == self.lower.ncols()
            && (0..theta.nrows()).all(|i| {
                (0..theta.ncols()).all(|j| {
                    self.lower[(i, j)] <= theta[(i, j)] && theta[(i, j)] <= self.upper[(i, j)]
                })
            })
    }

    /// Frobenius distance from `A + GΘH` to `co{R_v}` (Wolfe's algorithm).
    pub fn hull_distance(&self, theta: MatRef<'_, f64>) -> Result<HullDistance, EmbedError> {
        let x = self.matrix_at(theta)?;
        hull_distance(&self.vertices, x.as_ref())
    }
}
