//! Vertices of the image of a coefficient box: `X = B + Σ_k c_k N_k`, `c_k ∈ {lower_k, upper_k}`.
//!
//! This is the common last step of the residue embedding (Ferrante et al. 2016, (43a)) and of
//! the Jacobian polytope (Etienne et al. 2017, Lemma 1): the map from coefficients to matrices
//! is affine, so the image of the box is the convex hull of the images of its corners.
//! Coefficients whose range is a single value are folded into the base matrix, so they do not
//! double the vertex count.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par, Scale};

use crate::EmbedError;

/// Corners of `{B + Σ_k c_k N_k : c_k ∈ [lower_k, upper_k]}`.
///
/// Returns the vertices and the number `F` of non-degenerate coefficients (`2^F` vertices).
/// Vertex `v` takes the upper value of the `f`-th non-degenerate coefficient iff bit `f` of `v`
/// is set (coefficients in the order given). Errors if `2^F > limit`.
pub(crate) fn box_vertices(
    base: Option<MatRef<'_, f64>>,
    matrices: &[MatRef<'_, f64>],
    ranges: &[(f64, f64)],
    limit: usize,
    shape: (usize, usize),
) -> Result<(Vec<Mat<f64>>, usize), EmbedError> {
    debug_assert_eq!(matrices.len(), ranges.len());
    let (r, c) = shape;
    let mut fixed = match base {
        Some(b) => b.to_owned(),
        None => Mat::zeros(r, c),
    };
    let mut free: Vec<(MatRef<'_, f64>, f64, f64)> = Vec::new();
    for (m, &(lo, hi)) in matrices.iter().zip(ranges) {
        if lo == hi {
            if lo != 0.0 {
                fixed += Scale(lo) * m;
            }
        } else {
            free.push((*m, lo, hi));
        }
    }
    let f = free.len();
    if f >= usize::BITS as usize - 1 || (1usize << f) > limit {
        return Err(EmbedError::TooManyVertices { free: f, limit });
    }
    // All corners at once: column v of `stacked` is vec(X_v) = vec(B) + Σ_k c_k^{(v)} vec(N_k),
    // one matrix product instead of 2^F · F small matrix updates.
    let count = 1usize << f;
    let dirs = Mat::from_fn(r * c, f, |p, k| free[k].0[(p % r, p / r)]);
    let coefs = Mat::from_fn(f, count, |k, v| {
        let (_, lo, hi) = free[k];
        if v >> k & 1 == 1 { hi } else { lo }
    });
    let mut stacked = Mat::from_fn(r * c, count, |p, _| fixed[(p % r, p / r)]);
    matmul(
        stacked.as_mut(),
        Accum::Add,
        dirs.as_ref(),
        coefs.as_ref(),
        1.0,
        Par::Seq,
    );
    let vertices = (0..count)
        .map(|v| Mat::from_fn(r, c, |i, j| stacked[(i + r * j, v)]))
        .collect();
    Ok((vertices, f))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degenerate_coefficients_do_not_double_vertices() {
        let n1 = Mat::<f64>::identity(2, 2);
        let n2 = Mat::from_fn(2, 2, |i, j| (i + 2 * j) as f64);
        let n3 = Mat::from_fn(2, 2, |i, j| if i == j { 0.0 } else { 1.0 });
        let (v, f) = box_vertices(
            None,
            &[n1.as_ref(), n2.as_ref(), n3.as_ref()],
            &[(1.0, 1.0), (-1.0, 2.0), (0.5, 0.75)],
            16,
            (2, 2),
        )
        .unwrap();
        assert_eq!((v.len(), f), (4, 2));
        // bit 0 ↔ n2 (upper = 2), bit 1 ↔ n3 (upper = 0.75)
        let expect = &n1 + Scale(2.0) * &n2 + Scale(0.5) * &n3;
        assert_eq!(v[1], expect);
        let too_many = box_vertices(
            None,
            &[n2.as_ref(), n3.as_ref()],
            &[(0.0, 1.0), (0.0, 1.0)],
            3,
            (2, 2),
        );
        assert!(matches!(
            too_many,
            Err(EmbedError::TooManyVertices { free: 2, limit: 3 })
        ));
    }
}
