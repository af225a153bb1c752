//! Lyapunov equations by the Bartels–Stewart algorithm: Bartels & Stewart (1972), *Solution of
//! the matrix equation AX + XB = C*, Comm. ACM 15(9):820–826 (Algorithm 432); the discrete
//! (Stein) variant follows Barraud (1977), *A numerical algorithm to solve AᵀXA − X = Q*,
//! IEEE Trans. Automat. Control 22(5):883–885.
//!
//! With the real Schur form A = U·T·Uᵀ ([`crate::schur`]) and X = U·Y·Uᵀ the equations become
//! Tᵀ·Y + Y·T = C and Tᵀ·Y·T − Y = C with C = −UᵀQU, solved block by block (1×1 and 2×2
//! diagonal blocks of T, column blocks left to right, row blocks top to bottom) in O(n³); each
//! block is a Sylvester equation of order ≤ 4 solved by Gaussian elimination with partial
//! pivoting. This is the method of SLICOT SB03MD and MATLAB `lyap`/`dlyap`. A Kronecker
//! formulation would cost O(n⁶) and is used only as a test oracle.
//!
//! The equations have a unique solution iff λ_i + λ_j ≠ 0 (continuous) resp. λ_i·λ_j ≠ 1
//! (discrete) for all eigenvalue pairs of A; a numerically zero pivot in a block solve
//! (|pivot| ≤ 4ε times the magnitude of the terms forming the block matrix) is reported as [`LinalgError::Singular`].

use crate::InputError;
use faer::{Mat, MatRef};

use crate::schur::real_schur;
use crate::{LinalgError, check};

#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// AᵀX + XA + Q = 0.
    Continuous,
    /// AᵀXA − X + Q = 0.
    Discrete,
}

/// Solves K·y = r (order m ≤ 4) with partial pivoting; `None` if a pivot is ≤ 4ε·`scale`,
/// where `scale` bounds the magnitude of the terms that were summed into K (so cancellation
/// such as λ_i + λ_j ≈ 0 is detected).
fn solve_small(mut k: [[f64; 4]; 4], mut r: [f64; 4], m: usize, scale: f64) -> Option<[f64; 4]> {
    let smin = (4.0 * f64::EPSILON * scale).max(f64::MIN_POSITIVE);
    for c in 0..m {
        let p = (c..m).max_by(|&x, &y| k[x][c].abs().total_cmp(&k[y][c].abs()))?;
        if k[p][c].abs() <= smin {
            return None;
        }
        k.swap(c, p);
        r.swap(c, p);
        for row in c + 1..m {
            let l = k[row][c] / k[c][c];
            for col in c..m {
                k[row][col] -= l * k[c][col];
            }
            r[row] -= l * r[c];
        }
    }
    for c in (0..m).rev() {
        let mut v = r[c];
        for col in c + 1..m {
            v -= k[c][col] * r[col];
        }
        r[c] = v / k[c][c];
    }
    Some(r)
}

/// Solves Tᵀ·Y + Y·T = C or Tᵀ·Y·T − Y = C for quasi-triangular T with the given blocks.
fn solve_quasi_triangular(
    t: &Mat<f64>,
    blocks: &[(usize, usize)],
    c: &Mat<f64>,
    kind: Kind,
) -> Result<Mat<f64>, LinalgError> {
    let n = t.nrows();
    let mut y = Mat::<f64>::zeros(n, n);
    let mut z = Mat::<f64>::zeros(n, 2);
    for &(sj, q) in blocks {
        if kind == Kind::Discrete {
            // Z = Y[:, ..sj]·T[..sj, J] (all earlier columns of Y are final).
            for cc in 0..q {
                for row in 0..n {
                    z[(row, cc)] = (0..sj).map(|k| y[(row, k)] * t[(k, sj + cc)]).sum();
                }
            }
        }
        for &(si, p) in blocks {
            let mut rhs = [0.0; 4];
            for cc in 0..q {
                for rr in 0..p {
                    let (i, j) = (si + rr, sj + cc);
                    let mut v = c[(i, j)];
                    match kind {
                        Kind::Continuous => {
                            // − Σ_{l < si} T[l, i]·Y[l, j] − Σ_{k < sj} Y[i, k]·T[k, j]
                            v -= (0..si).map(|l| t[(l, i)] * y[(l, j)]).sum::<f64>();
                            v -= (0..sj).map(|k| y[(i, k)] * t[(k, j)]).sum::<f64>();
                        }
                        Kind::Discrete => {
                            // − Σ_{l < si+p} T[l, i]·Z[l, cc] − Σ_{l < si} Σ_{c'} T[l, i]·Y[l, sj+c']·T[sj+c', j]
                            v -= (0..si + p).map(|l| t[(l, i)] * z[(l, cc)]).sum::<f64>();
                            for c2 in 0..q {
                                let tj = t[(sj + c2, j)];
                                if tj != 0.0 {
                                    v -= tj
                                        * (0..si).map(|l| t[(l, i)] * y[(l, sj + c2)]).sum::<f64>();
                                }
                            }
                        }
                    }
                    rhs[rr + p * cc] = v;
                }
            }
            // K·vec(Y_IJ) = vec(R): continuous K = I_q ⊗ T_IIᵀ + T_JJᵀ ⊗ I_p,
            // discrete K = T_JJᵀ ⊗ T_IIᵀ − I.
            let mut k = [[0.0; 4]; 4];
            let mut scale = 0.0f64;
            for c1 in 0..q {
                for r1 in 0..p {
                    for c2 in 0..q {
                        for r2 in 0..p {
                            let tii_t = t[(si + r2, si + r1)]; // (T_IIᵀ)[r1, r2]
                            let tjj_t = t[(sj + c2, sj + c1)]; // (T_JJᵀ)[c1, c2]
                            let same_r = if r1 == r2 { 1.0 } else { 0.0 };
                            let same_c = if c1 == c2 { 1.0 } else { 0.0 };
                            let (value, magnitude) = match kind {
                                Kind::Continuous => (
                                    same_c * tii_t + tjj_t * same_r,
                                    same_c * tii_t.abs() + tjj_t.abs() * same_r,
                                ),
                                Kind::Discrete => (
                                    tjj_t * tii_t - same_c * same_r,
                                    (tjj_t * tii_t).abs() + same_c * same_r,
                                ),
                            };
                            k[r1 + p * c1][r2 + p * c2] = value;
                            scale = scale.max(magnitude);
                        }
                    }
                }
            }
            let sol = solve_small(k, rhs, p * q, scale).ok_or_else(|| {
                LinalgError::singular(match kind {
                    Kind::Continuous => {
                        "lyap_continuous: AᵀX + XA + Q = 0 (eigenvalues with λ_i + λ_j ≈ 0)"
                    }
                    Kind::Discrete => {
                        "lyap_discrete: AᵀXA − X + Q = 0 (eigenvalues with λ_i·λ_j ≈ 1)"
                    }
                })
            })?;
            for cc in 0..q {
                for rr in 0..p {
                    y[(si + rr, sj + cc)] = sol[rr + p * cc];
                }
            }
        }
    }
    Ok(y)
}

fn lyap(
    a: MatRef<'_, f64>,
    q: MatRef<'_, f64>,
    kind: Kind,
    name: &str,
) -> Result<Mat<f64>, LinalgError> {
    let n = check::square_finite(a, &format!("{name}: A"))?;
    if q.nrows() != n || q.ncols() != n {
        let found = if q.nrows() != n { q.nrows() } else { q.ncols() };
        return Err(
            InputError::mismatch(format!("{name}: order of Q (= order of A)"), n, found).into(),
        );
    }
    check::finite(q, &format!("{name}: Q"))?;
    let sch = real_schur(a)?;
    let c = -(sch.u.transpose() * q * &sch.u);
    let y = solve_quasi_triangular(&sch.t, &sch.blocks, &c, kind)?;
    let mut x = &sch.u * &y * sch.u.transpose();
    let symmetric = (0..n).all(|j| (0..j).all(|i| q[(i, j)] == q[(j, i)]));
    if symmetric {
        x = Mat::from_fn(n, n, |i, j| 0.5 * (x[(i, j)] + x[(j, i)]));
    }
    check::finite(x.as_ref(), name)
        .map_err(|_| LinalgError::overflow(&format!("{name}: solution")))?;
    Ok(x)
}

/// Solves the continuous Lyapunov equation AᵀX + XA + Q = 0 (Bartels–Stewart; see the module
/// docs). For exactly symmetric Q the returned X is symmetrised.
///
/// # Errors
/// Bad shapes or non-finite input; [`LinalgError::Singular`] if some λ_i(A) + λ_j(A) ≈ 0;
/// [`LinalgError::NoConvergence`] if the Schur form cannot be computed.
pub fn lyap_continuous(a: MatRef<'_, f64>, q: MatRef<'_, f64>) -> Result<Mat<f64>, LinalgError> {
    lyap(a, q, Kind::Continuous, "lyap_continuous")
}

/// Solves the discrete Lyapunov (Stein) equation AᵀXA − X + Q = 0 (Bartels–Stewart/Barraud;
/// see the module docs). For exactly symmetric Q the returned X is symmetrised.
///
/// # Errors
/// Bad shapes or non-finite input; [`LinalgError::Singular`] if some λ_i(A)·λ_j(A) ≈ 1;
/// [`LinalgError::NoConvergence`] if the Schur form cannot be computed.
pub fn lyap_discrete(a: MatRef<'_, f64>, q: MatRef<'_, f64>) -> Result<Mat<f64>, LinalgError> {
    lyap(a, q, Kind::Discrete, "lyap_discrete")
}
