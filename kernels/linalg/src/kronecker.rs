//! Kronecker products (a thin wrapper over faer's `kron`, kept for a stable crate API).

use faer::{Mat, MatRef};

/// Kronecker product A ⊗ B: the (i·p + k, j·q + l) entry is a_ij·b_kl for B of size p×q
/// (so vec(AXB) = (Bᵀ ⊗ A)·vec(X) with column-major vec). Any shapes, including empty ones.
pub fn kron(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    a.kron(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn small_example_and_vec_identity() {
        let a = mat![[1.0, 2.0], [3.0, 4.0]];
        let b = mat![[0.0, 5.0, 1.0]];
        let k = kron(a.as_ref(), b.as_ref());
        assert_eq!(
            k,
            mat![
                [0.0, 5.0, 1.0, 0.0, 10.0, 2.0],
                [0.0, 15.0, 3.0, 0.0, 20.0, 4.0]
            ]
        );
        // vec(AXB) = (Bᵀ ⊗ A) vec(X) for A 2×2, X 2×3, B 3×2.
        let x = mat![[1.0, -2.0, 0.5], [3.0, 0.0, -1.0]];
        let bb = mat![[1.0, 2.0], [0.0, -1.0], [4.0, 1.0]];
        let lhs = &a * &x * &bb;
        let vecx = Mat::from_fn(6, 1, |k, _| x[(k % 2, k / 2)]);
        let rhs = kron(bb.transpose(), a.as_ref()) * &vecx;
        for k in 0..4 {
            assert!((lhs[(k % 2, k / 2)] - rhs[(k, 0)]).abs() < 1e-14);
        }
        assert_eq!(
            kron(Mat::<f64>::zeros(0, 2).as_ref(), a.as_ref()).shape(),
            (0, 4)
        );
    }
}
