//! Deciding LMI (41) of Ferrante et al. (2016) at a point by more than rounding, and solving it
//! again in the coordinates of an earlier point's Lyapunov matrix (not in the paper).
//!
//! **The rounding-aware test** ([`strictly_negative`]). A point `(P, F, J)` certifies (41) on
//! the window when every vertex LMI is negative definite by more than what rounding and the
//! embedding's own error can explain ([`VertexSet::error`]). This decides without the solver's
//! verification threshold, which is relative to the margin problem's normalisation `‖P‖₂ ≤ 1`.
//!
//! **Certificate coordinates** ([`CertificateCoordinates`]). Every block of (41) holds `P` or
//! `F`, so its margin under the normalisation `‖P‖₂ ≤ 1` is at most `λmin(P)/λmax(P)`. Near the
//! end of the largest window of an unstable plant the Lyapunov matrices of (41) have condition
//! numbers like `‖e^{AT2}‖²`, so the margin falls below what the solver resolves, and the
//! verdict there is decided by rounding. (41) is invariant under a change of state coordinates
//! `x' = Rx` (congruence of every block by `R⁻ᵀ`), and in the coordinates in which the `P` of an
//! earlier solve is the identity (`RᵀR = P`) its margin is no longer bounded by that condition
//! number. A magnetic levitation (poles `±44.3/s`, `−100/s`, position measured) on
//! `[0.001, 0.17] s`: `t* = −1.7e-9` in the Gramian normal form, `5.5e-7` (verified at every
//! vertex) in the coordinates of that solve's `P`. The plant is embedded again in the new
//! coordinates (the residue box is the same set up to the similarity unless the expansion's
//! cluster choices change with the coordinates, and its error bounds are then those of the
//! computed matrix `R A R⁻¹`, as for every normal form of [`crate::normalise`]). A certificate
//! found this way is checked on the plant's own data like any other (`crate::verify`); when
//! its `P` is too ill-conditioned in the plant's coordinates for that check to resolve (12)
//! (condition number `5e14` on the magnetic levitation), the design reports the precision
//! limit of the method (`Error::PrecisionLimit`), not an infeasible LMI.
//!
//! The `P` of an undecided margin solve (`t* < 0` within the solver's threshold) is itself
//! indefinite by about `t*`; its coordinates are those of `P + 2|λmin|·I`
//! ([`MAX_INDEFINITENESS`]), and the Gramian form's solve is taken first, as it is the same
//! for every change of units or coordinates (`crate::design`). Without these two, the
//! two-wheeled robot of issue 22 ended its window searches at different `T2` in seconds and in
//! milliseconds, the corpus cart-pole at 0.77 in its coordinates and 0.71 in others; with
//! them, 1.229 s and 1229.4 ms, and 1.84 to 2.00 (the band where LMI (41) itself ends).

use faer::{Mat, MatRef, Side};
use sporadic_embed::Embedding;

use crate::system::Plant;

/// Smallest condition number `λmax(P)/λmin(P)` of an earlier solve's `P` for which a new solve in
/// its coordinates is tried: below it the margin is not limited by the conditioning of `P`.
pub const MIN_CERTIFICATE_CONDITION: f64 = 1e2;

/// Largest condition number of `P` whose coordinates are used: above it the eigenvectors of its
/// smallest eigenvalues, and `λmin(P)` itself, are not known to a relative accuracy better than
/// about `10⁻³` in double precision (`u·λmax/λmin`).
pub const MAX_CERTIFICATE_CONDITION: f64 = 1e12;

/// Largest `−λmin(P)/λmax(P)` of an indefinite `P` of a margin solve whose coordinates are
/// used ([`CertificateCoordinates::of`]): a margin `t*` this close to zero is undecided by
/// the solver (its verification threshold is `10⁻⁷` or more relative to `‖P‖₂ ≤ 1`).
pub const MAX_INDEFINITENESS: f64 = 1e-6;

/// The vertices `X_i` of LMI (41) in the coordinates of a solve, with a bound `error` on the
/// spectral-norm distance of every `e^{Av}`, `v` in the window, from their hull (in the same
/// coordinates).
#[derive(Debug, Clone, Copy)]
pub(crate) struct VertexSet<'a> {
    pub vertices: &'a [Mat<f64>],
    pub error: f64,
}

impl<'a> VertexSet<'a> {
    /// The vertices of a residue embedding: `error = max(ε_rec, 64u)·max_i‖X_i‖_F + δ`
    /// (`ε_rec` the relative reconstruction error of the residue expansion, `δ` its truncation
    /// remainder). `None` for other embeddings (a Taylor polytope's remainder is handled by the
    /// robust form of (41) instead).
    pub fn residue(embedding: &'a Embedding) -> Option<Self> {
        let rec = match embedding.method() {
            sporadic_embed::Method::Residue {
                reconstruction_error,
                projector_sum_error,
                ..
            } => reconstruction_error.max(*projector_sum_error),
            sporadic_embed::Method::Taylor { .. } => return None,
        };
        let vertices = embedding.vertices();
        let error =
            rec.max(64.0 * f64::EPSILON) * largest_norm(vertices) + embedding.remainder_bound();
        Some(Self { vertices, error })
    }
}

/// Largest Frobenius norm of a vertex.
fn largest_norm(vertices: &[Mat<f64>]) -> f64 {
    vertices.iter().map(|x| x.norm_l2()).fold(0.0, f64::max)
}

/// The change of coordinates `x' = Rx` with `RᵀR = P/λmax(P)` for the Lyapunov matrix `P` of an
/// earlier solve (`R = Λ^½Vᵀ/√λmax` from `P = VΛVᵀ`, `R⁻¹ = VΛ^{−½}√λmax`), in which that `P`
/// is the identity up to scale.
#[derive(Debug, Clone)]
pub(crate) struct CertificateCoordinates {
    /// `R`.
    pub r: Mat<f64>,
    /// `R⁻¹` (as computed).
    pub r_inv: Mat<f64>,
}

impl CertificateCoordinates {
    /// The coordinates of `p` (symmetric), or `None` when they would not help or cannot be
    /// trusted: `P` indefinite by more than a margin solve's `P` can be (see below) or its
    /// condition number below
    /// [`MIN_CERTIFICATE_CONDITION`] or above [`MAX_CERTIFICATE_CONDITION`].
    pub fn of(p: MatRef<'_, f64>) -> Option<Self> {
        let n = p.nrows();
        let sym = Mat::from_fn(n, n, |i, j| 0.5 * (p[(i, j)] + p[(j, i)]));
        let e = sym.self_adjoint_eigen(Side::Lower).ok()?;
        let s = e.S().column_vector();
        // The `P` of a margin solve with `t* < 0` has `λmin(P) ≈ t*`: indefinite by about the
        // margin. Its coordinates are taken for `P + 2|λmin|·I` then (positive definite, the same
        // eigenvectors), as long as `|λmin|` is below [`MAX_INDEFINITENESS`] times `λmax`: only
        // the coordinates are taken from it, never the certificate.
        let (lo, hi) = (s[0], s[n - 1]);
        if !(hi > 0.0 && hi.is_finite()) || lo < -MAX_INDEFINITENESS * hi {
            return None;
        }
        let shift = if lo > 0.0 { 0.0 } else { -2.0 * lo };
        let lambda: Vec<f64> = (0..n).map(|i| s[i] + shift).collect();
        let (lo, hi) = (lambda[0], lambda[n - 1]);
        if !(lo > 0.0) {
            return None;
        }
        if !(MIN_CERTIFICATE_CONDITION..=MAX_CERTIFICATE_CONDITION).contains(&(hi / lo)) {
            return None;
        }
        let scaled: Vec<f64> = lambda.iter().map(|l| l / hi).collect();
        let (r, r_inv) = sporadic_linalg::gramian_form::root_coordinates(e.U(), &scaled);
        Some(Self { r, r_inv })
    }

    /// `(R A R⁻¹, C R⁻¹)` (`None` when an entry is not finite).
    pub fn plant(&self, p: &Plant) -> Option<Plant> {
        let a = &self.r * p.a() * &self.r_inv;
        let c = p.c() * &self.r_inv;
        Plant::new(a.as_ref(), c.as_ref()).ok()
    }
}

/// Whether LMI (41) holds at a point `(P, F, J)` at every vertex of `set` by more than what
/// rounding and the embedding's own error can explain: `λmax(Φ_i) < −τ` ([`VertexTest`]).
/// The vertices are tested from `*first` on, cyclically, and a vertex that fails is stored
/// there: the iterates of one solve tend to fail at the same vertex, which is then tested
/// first (the verdict does not depend on the order).
pub(crate) fn strictly_negative(
    plant: &Plant,
    set: &VertexSet<'_>,
    (p, f, j): (MatRef<'_, f64>, MatRef<'_, f64>, MatRef<'_, f64>),
    first: &mut usize,
) -> bool {
    let count = set.vertices.len();
    VertexTest::new(plant, set, (p, f, j)).is_some_and(|test| {
        let start = *first % count.max(1);
        (start..count).chain(0..start).all(|i| {
            let passes = test.largest_eigenvalue(set.vertices[i].as_ref()) < -test.tau;
            if !passes {
                *first = i;
            }
            passes
        })
    })
}

/// LMI (41) at a point `(P, F, J)`, vertex by vertex, with the bound `τ` on what rounding and
/// the embedding's own error can explain: `τ = 2‖P‖₂·error + 64u·3n·s` (`error` the bound of
/// [`VertexSet`], `u` the unit roundoff, `s` the largest block norm of `Φ_i`). A backward-stable
/// eigenvalue computation is within `O(u)‖Φ_i‖` of the exact one, and the true `e^{Av}` is
/// within `error` of the hull, which moves `Φ` by at most `‖P‖₂` times that in its `(3,1)`
/// block: so `λmax(Φ_i) < −τ` at every vertex is Corollary 1's strict LMI, decided without the
/// solver's verification threshold (which is relative to the normalisation `‖P‖₂ ≤ 1` of the
/// margin problem and so depends on the coordinates).
pub(crate) struct VertexTest<'a> {
    p: MatRef<'a, f64>,
    f: MatRef<'a, f64>,
    /// `F − JC`.
    coupling: Mat<f64>,
    n: usize,
    /// The bound `τ`.
    pub tau: f64,
    /// The scale `s` of the blocks of `Φ_i` in `τ`.
    pub scale: f64,
}

impl<'a> VertexTest<'a> {
    /// The test at `(P, F, J)` on the vertices of `set`; `None` when `τ` is not finite (the
    /// point decides nothing).
    pub fn new(
        plant: &Plant,
        set: &VertexSet<'_>,
        (p, f, j): (MatRef<'a, f64>, MatRef<'a, f64>, MatRef<'a, f64>),
    ) -> Option<Self> {
        let (n, u) = (plant.n(), f64::EPSILON);
        let coupling = f - j * plant.c();
        let norm2 = |m: MatRef<'_, f64>| m.singular_values().map_or(f64::INFINITY, |s| s[0]);
        let (np, nf, nc) = (norm2(p), norm2(f), norm2(coupling.as_ref()));
        let xmax = largest_norm(set.vertices);
        let scale = np.max(2.0 * nf).max(nc).max(np * xmax);
        let tau = 2.0 * np * set.error + 64.0 * u * (3 * n) as f64 * scale;
        tau.is_finite().then_some(Self {
            p,
            f,
            coupling,
            n,
            tau,
            scale,
        })
    }

    /// `max_i λmax(Φ(X_i))` over `vertices`.
    pub fn largest_over(&self, vertices: &[Mat<f64>]) -> f64 {
        let each = vertices.iter().map(|x| self.largest_eigenvalue(x.as_ref()));
        each.fold(f64::NEG_INFINITY, f64::max)
    }

    /// `λmax(Φ(X))` of (41) at the vertex `x` (`+∞` when it cannot be computed).
    pub fn largest_eigenvalue(&self, x: MatRef<'_, f64>) -> f64 {
        let (n, p, f, coupling) = (self.n, self.p, self.f, &self.coupling);
        let px = p * x;
        let phi = Mat::from_fn(3 * n, 3 * n, |i, k| {
            let (bi, bk, ii, kk) = (i / n, k / n, i % n, k % n);
            match (bi, bk) {
                (0, 0) => -(f[(ii, kk)] + f[(kk, ii)]),
                (0, 1) => coupling[(ii, kk)],
                (1, 0) => coupling[(kk, ii)],
                (0, 2) => px[(kk, ii)],
                (2, 0) => px[(ii, kk)],
                (1, 1) | (2, 2) => -0.5 * (p[(ii, kk)] + p[(kk, ii)]),
                _ => 0.0,
            }
        });
        sporadic_linalg::max_eigenvalue(phi.as_ref()).unwrap_or(f64::INFINITY)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// `Q diag(λ) Qᵀ` for the orthogonal `Q` of a QR factorisation of `m`.
    fn spd(m: &Mat<f64>, lambda: &[f64]) -> Mat<f64> {
        let q = m.qr().compute_Q();
        let n = lambda.len();
        let d = Mat::from_fn(n, n, |i, j| if i == j { lambda[i] } else { 0.0 });
        &q * d * q.transpose()
    }

    proptest! {
        /// `RᵀR = P/λmax(P)` and `R R⁻¹ = I`, to rounding relative to the condition number, for
        /// every positive definite `P` whose condition number is in the accepted range; `None`
        /// outside it.
        #[test]
        fn coordinates_make_the_certificate_the_identity(
            entries in proptest::collection::vec(-1.0..1.0f64, 16),
            exponents in proptest::collection::vec(-7.0..0.0f64, 3),
            scale in -20.0..20.0f64,
        ) {
            let m = Mat::from_fn(4, 4, |i, j| entries[4 * i + j] + if i == j { 2.0 } else { 0.0 });
            let mut lambda: Vec<f64> = exponents.iter().map(|e| 10f64.powf(*e)).collect();
            lambda.push(1.0);
            let p = spd(&m, &lambda) * faer::Scale(2f64.powf(scale));
            let condition = 1.0 / lambda.iter().copied().fold(1.0, f64::min);
            let c = CertificateCoordinates::of(p.as_ref());
            if condition < 0.5 * MIN_CERTIFICATE_CONDITION {
                prop_assert!(c.is_none());
                return Ok(());
            }
            if condition < 2.0 * MIN_CERTIFICATE_CONDITION {
                return Ok(());
            }
            let c = c.expect("coordinates of a well-defined certificate");
            let lmax = p.self_adjoint_eigenvalues(Side::Lower).unwrap()[3];
            let gram = c.r.transpose() * &c.r;
            let tol = 1e-13 * condition;
            for i in 0..4 {
                for j in 0..4 {
                    prop_assert!((gram[(i, j)] - p[(i, j)] / lmax).abs() <= 1e-13);
                }
            }
            let id = &c.r * &c.r_inv;
            for i in 0..4 {
                for j in 0..4 {
                    let target = if i == j { 1.0 } else { 0.0 };
                    prop_assert!((id[(i, j)] - target).abs() <= tol);
                }
            }
        }
    }

    #[test]
    fn indefinite_or_singular_matrices_give_no_coordinates() {
        let m = Mat::from_fn(3, 3, |i, j| {
            (i + 2 * j) as f64 * 0.1 + if i == j { 1.0 } else { 0.0 }
        });
        for lambda in [[-1e-3, 0.5, 1.0], [0.0, 0.5, 1.0], [1e-14, 0.5, 1.0]] {
            assert!(
                CertificateCoordinates::of(spd(&m, &lambda).as_ref()).is_none(),
                "{lambda:?}"
            );
        }
    }
}
