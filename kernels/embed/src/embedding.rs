//! The common result type of every embedding of `τ ↦ e^{Aτ}` on a sampling window.
//!
//! Corollary 1 of Ferrante et al. (2016) and Proposition 1 of Rabehi et al. (2021) only need
//! matrices `X_1, …, X_ν` with `{e^{Aτ} : τ ∈ [T1, T2]} ⊂ co{X_i}`. An [`Embedding`] carries the
//! vertices, how they were built ([`Method`]), an honest [`Containment`] statement, and a
//! norm bound on what the vertices may miss (`remainder_bound`, for robust LMIs):
//!
//! ```text
//! e^{Aτ} = Σ_i μ_i(τ) X_i + Δ(τ),   μ ≥ 0, Σ μ = 1,   ‖Δ(τ)‖_F ≤ remainder_bound   ∀τ ∈ [T1, T2].
//! ```

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::expm_scaled;

use crate::EmbedError;
use crate::hull::{HullDistance, hull_distance};
use crate::interval::Interval;

/// Relative Frobenius tolerance of hull-membership tests (`contains`, grid verification).
pub(crate) const HULL_TOLERANCE: f64 = 1e-9;

/// How much of `{e^{Aτ} : τ ∈ [T1, T2]} ⊂ co{X_i} ⊕ {‖Δ‖_F ≤ remainder_bound}` is established.
#[derive(Debug, Clone, PartialEq)]
pub enum Containment {
    /// Proven for every `τ ∈ [T1, T2]` by the construction's argument (exact coefficient
    /// extrema with outward rounding / rigorous truncation bounds), and the construction's
    /// self-check passed.
    ///
    /// For the residue method the argument applies to the *computed* expansion
    /// `Σ_k c_k(τ) N_k`; that it reproduces `e^{Aτ}` is the self-check (relative error
    /// `reconstruction_error ≤ check_tolerance`, default `1e-10`, on the check grid, see
    /// [`Method::Residue`]), so the hull contains `e^{Aτ}` up to that relative error.
    Guaranteed,
    /// Not proven, but `e^{Aτ}` was found within `max_error` (relative Frobenius distance beyond
    /// the remainder bound, see [`Embedding::max_violation`]) of the hull at `points` grid points.
    VerifiedOnGrid {
        /// Number of grid points checked.
        points: usize,
        /// Largest relative violation found.
        max_error: f64,
    },
    /// Neither proven nor verified; the reason says what failed, with numbers.
    NotGuaranteed {
        /// Why containment cannot be claimed.
        reason: String,
    },
}

impl Containment {
    /// Whether the statement is [`Containment::Guaranteed`].
    pub fn is_guaranteed(&self) -> bool {
        matches!(self, Self::Guaranteed)
    }
}

/// Which construction produced the vertices (per piece maxima for split embeddings).
#[derive(Debug, Clone, PartialEq)]
pub enum Method {
    /// Residue box of Ferrante et al. (2016), §4.1, eqs. (42)–(43).
    Residue {
        /// Number of expansion terms `K` (coefficient functions) kept.
        terms: usize,
        /// Number of terms with a non-degenerate range (`2^free_terms` vertices per piece).
        free_terms: usize,
        /// Largest relative reconstruction error beyond the truncation remainder `δ`,
        /// `(‖Σ c_k(v) N_k − e^{Av}‖_F − δ)⁺ / ‖e^{Av}‖_F`, on the self-check grid.
        reconstruction_error: f64,
        /// `‖Σ_c E_c − I‖_F / √n`.
        projector_sum_error: f64,
    },
    /// Truncated Taylor polytope around `e^{A T1}` (Rabehi et al. 2021, §IV; Hetel et al. 2011).
    Taylor {
        /// Truncation order `N` (`N + 1` vertices per piece).
        order: usize,
    },
}

/// Vertices `X_i` with `{e^{Aτ} : τ ∈ [T1, T2]} ⊂ co{X_i} ⊕ {‖Δ‖_F ≤ remainder_bound}`.
#[derive(Debug, Clone)]
pub struct Embedding {
    a: Mat<f64>,
    interval: Interval,
    vertices: Vec<Mat<f64>>,
    method: Method,
    pieces: Vec<Interval>,
    containment: Containment,
    remainder_bound: f64,
}

impl Embedding {
    pub(crate) fn new(
        a: Mat<f64>,
        interval: Interval,
        vertices: Vec<Mat<f64>>,
        method: Method,
        containment: Containment,
        remainder_bound: f64,
    ) -> Self {
        let mut e = Self {
            a,
            interval,
            vertices: Vec::new(),
            method,
            pieces: vec![interval],
            containment,
            remainder_bound,
        };
        e.vertices = dedup_exact(vertices);
        e
    }

    pub(crate) fn set_containment(&mut self, containment: Containment) {
        self.containment = containment;
    }

    /// Union of the embeddings of consecutive sub-intervals of `interval`.
    pub(crate) fn union(interval: Interval, parts: Vec<Embedding>) -> Self {
        let a = parts[0].a.clone();
        let mut pieces = Vec::new();
        let mut vertices = Vec::new();
        let mut remainder: f64 = 0.0;
        let mut reasons = Vec::new();
        let mut verified: Option<(usize, f64)> = None;
        let mut method = parts[0].method.clone();
        for p in parts {
            remainder = remainder.max(p.remainder_bound);
            match p.containment {
                Containment::Guaranteed => {}
                Containment::VerifiedOnGrid { points, max_error } => {
                    let (n, e) = verified.unwrap_or((0, 0.0));
                    verified = Some((n + points, e.max(max_error)));
                }
                Containment::NotGuaranteed { reason } => reasons.push(format!(
                    "piece [{}, {}]: {reason}",
                    p.interval.t1(),
                    p.interval.t2()
                )),
            }
            method = merge_methods(method, p.method);
            pieces.extend(p.pieces);
            vertices.extend(p.vertices);
        }
        let containment = if !reasons.is_empty() {
            Containment::NotGuaranteed {
                reason: reasons.join("; "),
            }
        } else if let Some((points, max_error)) = verified {
            Containment::VerifiedOnGrid { points, max_error }
        } else {
            Containment::Guaranteed
        };
        let mut e = Self::new(a, interval, vertices, method, containment, remainder);
        e.pieces = pieces;
        e
    }

    /// The vertices `X_i`.
    pub fn vertices(&self) -> &[Mat<f64>] {
        &self.vertices
    }

    /// Consumes the embedding, returning its vertices.
    pub fn into_vertices(self) -> Vec<Mat<f64>> {
        self.vertices
    }

    /// Number of (distinct) vertices `ν`.
    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    /// The sampling window `[T1, T2]`.
    pub fn interval(&self) -> Interval {
        self.interval
    }

    /// The sub-intervals the vertices were built on (one unless the window was split).
    pub fn pieces(&self) -> &[Interval] {
        &self.pieces
    }

    /// The construction used.
    pub fn method(&self) -> &Method {
        &self.method
    }

    /// What is established about the containment.
    pub fn containment(&self) -> &Containment {
        &self.containment
    }

    /// Bound `ρ` with `e^{Aτ} ∈ co{X_i} ⊕ {‖Δ‖_F ≤ ρ}` for all `τ ∈ [T1, T2]` (also a bound on
    /// `‖Δ‖₂`): the number to put into a robust LMI with a norm-bounded perturbation. Zero for
    /// exact constructions.
    pub fn remainder_bound(&self) -> f64 {
        self.remainder_bound
    }

    /// The matrix `A`.
    pub fn system_matrix(&self) -> MatRef<'_, f64> {
        self.a.as_ref()
    }

    /// Frobenius distance from `e^{Aτ}` to `co{X_i}` (Wolfe's algorithm; any finite `τ ≥ 0`).
    pub fn hull_distance(&self, tau: f64) -> Result<HullDistance, EmbedError> {
        let e = self.exp_at(tau)?;
        hull_distance(&self.vertices, e.as_ref())
    }

    /// Whether `e^{Aτ}` lies in `co{X_i} ⊕ {‖Δ‖_F ≤ remainder_bound}` up to a relative
    /// tolerance of `1e-9` (relative to `max(‖e^{Aτ}‖_F, max_i ‖X_i‖_F)`), decided by solving the
    /// convex-combination problem `μ ≥ 0, Σμ = 1, min ‖Σ μ_i X_i − e^{Aτ}‖_F`.
    pub fn contains(&self, tau: f64) -> Result<bool, EmbedError> {
        let e = self.exp_at(tau)?;
        Ok(self.violation(e.as_ref())? <= HULL_TOLERANCE)
    }

    /// Largest relative violation over the grid:
    /// `max_τ max(0, dist_F(e^{Aτ}, co X) − remainder_bound) / max(‖e^{Aτ}‖_F, max_i ‖X_i‖_F)`.
    /// Zero (up to rounding) when every grid point is contained.
    pub fn max_violation(&self, grid: &[f64]) -> Result<f64, EmbedError> {
        let mut worst: f64 = 0.0;
        for &tau in grid {
            let e = self.exp_at(tau)?;
            worst = worst.max(self.violation(e.as_ref())?);
        }
        Ok(worst)
    }

    /// Checks containment on `points` equally spaced grid points of `[T1, T2]` and returns the
    /// corresponding statement (`VerifiedOnGrid` or `NotGuaranteed`); does not modify `self`.
    pub fn verify_on_grid(&self, points: usize) -> Result<Containment, EmbedError> {
        let grid = self.interval.grid(points);
        let exact = grid
            .iter()
            .map(|&t| self.exp_at(t))
            .collect::<Result<Vec<_>, _>>()?;
        let (max_error, at) = self.grid_violation(&grid, &exact)?;
        Ok(if max_error <= HULL_TOLERANCE {
            Containment::VerifiedOnGrid {
                points: grid.len(),
                max_error,
            }
        } else {
            Containment::NotGuaranteed {
                reason: format!(
                    "e^(Aτ) lies {max_error:.2e} (relative) outside the hull at τ = {at}"
                ),
            }
        })
    }

    /// Largest relative violation and where, for precomputed `e^{Aτ}` on a grid.
    fn grid_violation(&self, grid: &[f64], exact: &[Mat<f64>]) -> Result<(f64, f64), EmbedError> {
        let mut worst = (0.0, grid.first().copied().unwrap_or(0.0));
        for (&tau, e) in grid.iter().zip(exact) {
            let v = self.violation(e.as_ref())?;
            if v > worst.0 {
                worst = (v, tau);
            }
        }
        Ok(worst)
    }

    /// `max(‖E‖_F, max_i ‖X_i‖_F)`: the scale of relative hull distances.
    pub(crate) fn relative_scale(&self, e: MatRef<'_, f64>) -> f64 {
        self.vertices
            .iter()
            .map(|x| x.norm_l2())
            .fold(e.norm_l2(), f64::max)
    }

    /// Relative violation `max(0, dist_F(E, co X) − remainder_bound) / scale`.
    pub(crate) fn violation(&self, e: MatRef<'_, f64>) -> Result<f64, EmbedError> {
        let d = hull_distance(&self.vertices, e)?;
        let scale = self.relative_scale(e);
        if scale == 0.0 {
            return Ok(0.0);
        }
        Ok((d.distance - self.remainder_bound).max(0.0) / scale)
    }

    fn exp_at(&self, tau: f64) -> Result<Mat<f64>, EmbedError> {
        if !tau.is_finite() {
            return Err(InputError::non_finite("τ").into());
        }
        Ok(expm_scaled(self.a.as_ref(), tau)?)
    }
}

fn merge_methods(a: Method, b: Method) -> Method {
    match (a, b) {
        (
            Method::Residue {
                terms: t1,
                free_terms: f1,
                reconstruction_error: r1,
                projector_sum_error: p1,
            },
            Method::Residue {
                terms: t2,
                free_terms: f2,
                reconstruction_error: r2,
                projector_sum_error: p2,
            },
        ) => Method::Residue {
            terms: t1.max(t2),
            free_terms: f1.max(f2),
            reconstruction_error: r1.max(r2),
            projector_sum_error: p1.max(p2),
        },
        (Method::Taylor { order: o1 }, Method::Taylor { order: o2 }) => {
            Method::Taylor { order: o1.max(o2) }
        }
        (a, _) => a,
    }
}

/// Removes exact (bitwise, with `-0 = +0`) duplicates, keeping the first occurrence.
fn dedup_exact(vertices: Vec<Mat<f64>>) -> Vec<Mat<f64>> {
    let key = |x: &Mat<f64>| -> Vec<u64> {
        let mut k = Vec::with_capacity(x.nrows() * x.ncols());
        for j in 0..x.ncols() {
            for i in 0..x.nrows() {
                let v = x[(i, j)];
                k.push(if v == 0.0 { 0 } else { v.to_bits() });
            }
        }
        k
    };
    let mut seen = std::collections::HashSet::new();
    vertices
        .into_iter()
        .filter(|x| seen.insert(key(x)))
        .collect()
}
