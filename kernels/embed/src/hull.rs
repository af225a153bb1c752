//! Distance from a matrix to the convex hull of a finite set of matrices.
//!
//! Deciding `E ∈ co{X_1, …, X_ν}` is the convex-combination feasibility problem
//! `μ ≥ 0, Σ μ_i = 1, Σ μ_i X_i = E`. We solve the slightly stronger problem
//! `min ‖Σ μ_i X_i − E‖_F` over the simplex with **Wolfe's minimum-norm-point algorithm**
//! (P. Wolfe, "Finding the nearest point in a polytope", Math. Programming 11, 1976): an
//! active-set method that terminates finitely in exact arithmetic and returns the barycentric
//! weights together with the distance, so "how far outside" is available as well as yes/no.
//! Affine sub-problems are solved as least-squares problems by column-pivoted QR. The stopping
//! test certifies the distance: at termination `min_j ⟨x, p_j⟩ / ‖x‖` (a lower bound on the
//! distance) is within `1e-12` (relative to the largest `‖X_i − E‖_F`) of `‖x‖` (an upper bound).
//! Both bounds are reported; when rounding stalls the iteration first, they bracket the
//! distance less tightly and [`HullDistance::converged`] is `false`.

use faer::linalg::solvers::SolveLstsq;
use faer::{Mat, MatRef};
use sporadic_linalg::InputError;

use crate::EmbedError;

/// Result of [`hull_distance`].
#[derive(Debug, Clone, PartialEq)]
pub struct HullDistance {
    /// Frobenius distance from the target to the point `Σ μ_i X_i` (an upper bound on the true
    /// distance to the hull: that point lies in the hull).
    pub distance: f64,
    /// A lower bound on the true distance (from the separating direction at termination).
    pub lower_bound: f64,
    /// Barycentric weights `μ` (one per vertex, `μ ≥ 0`, `Σ μ = 1`).
    pub weights: Vec<f64>,
    /// Whether Wolfe's optimality test was met (otherwise the iteration limit stopped it; the
    /// distance is still a valid upper bound).
    pub converged: bool,
}

/// Frobenius distance from `target` to `co{vertices}` (all of equal shape, at least one).
///
/// Wolfe's iteration runs on the points themselves; if it stalls before its optimality test
/// is met (very flat polytopes, whose barycentric weights are ill-determined along the thin
/// directions), it is rerun in whitened coordinates (principal axes of the vertex cloud scaled
/// to unit length), and the better of the two convex combinations is returned.
pub fn hull_distance(
    vertices: &[Mat<f64>],
    target: MatRef<'_, f64>,
) -> Result<HullDistance, EmbedError> {
    if vertices.is_empty() {
        return Err(InputError::empty("vertex set").into());
    }
    let (r, c) = (target.nrows(), target.ncols());
    for (k, x) in vertices.iter().enumerate() {
        if x.nrows() != r || x.ncols() != c {
            return Err(InputError::mismatch(
                format!("vertex {k} (rows·cols) vs target"),
                r * c,
                x.nrows() * x.ncols(),
            )
            .into());
        }
    }
    sporadic_linalg::input::check_finite(target, "hull target")?;
    let points: Vec<Vec<f64>> = vertices
        .iter()
        .map(|x| {
            let mut p = Vec::with_capacity(r * c);
            for j in 0..c {
                for i in 0..r {
                    p.push(x[(i, j)] - target[(i, j)]);
                }
            }
            p
        })
        .collect();
    for (k, p) in points.iter().enumerate() {
        if p.iter().any(|v| !v.is_finite()) {
            return Err(InputError::non_finite(format!("vertex {k}")).into());
        }
    }
    let scale = points.iter().map(|p| dot(p, p)).fold(0.0, f64::max).sqrt();
    if scale == 0.0 {
        let mut weights = vec![0.0; points.len()];
        weights[0] = 1.0;
        return Ok(HullDistance {
            distance: 0.0,
            lower_bound: 0.0,
            weights,
            converged: true,
        });
    }
    // Unit-scale copies for the iteration.
    let unit: Vec<Vec<f64>> = points
        .iter()
        .map(|p| p.iter().map(|v| v / scale).collect())
        .collect();
    let (weights, converged) = wolfe(&unit);
    let mut best = assess(&points, weights, converged);
    if !best.converged
        && best.distance > 0.0
        && let Some(weights) = whitened(&unit)
    {
        let alt = assess(&points, weights, false);
        best.lower_bound = best.lower_bound.max(alt.lower_bound);
        if alt.distance < best.distance {
            best.distance = alt.distance;
            best.weights = alt.weights;
        }
    }
    Ok(best)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Distance of the convex combination `x = Σ w_i p_i` (an upper bound) and the separation
/// bound `max(0, min_j ⟨x, p_j⟩ / ‖x‖)` (a lower bound: no hull point is closer).
fn assess(points: &[Vec<f64>], weights: Vec<f64>, converged: bool) -> HullDistance {
    let d = points[0].len();
    let mut x = vec![0.0; d];
    for (w, p) in weights.iter().zip(points) {
        if *w != 0.0 {
            for (xi, pi) in x.iter_mut().zip(p) {
                *xi += w * pi;
            }
        }
    }
    let distance = dot(&x, &x).sqrt();
    let lower_bound = if distance > 0.0 {
        let worst = points
            .iter()
            .map(|p| dot(&x, p))
            .fold(f64::INFINITY, f64::min);
        (worst / distance).clamp(0.0, distance)
    } else {
        0.0
    };
    HullDistance {
        distance,
        lower_bound,
        weights,
        converged,
    }
}

/// Reruns Wolfe's iteration in whitened coordinates: with the centred points
/// `P − p̄ = U Σ Vᵀ`, the points `Σ⁻¹ Uᵀ (p_i − p̄)` and the target `Σ⁻¹ Uᵀ (−p̄)` (directions
/// with `σ ≤ 1e-13 σ_max` dropped). Convex combinations are preserved by this affine map, so
/// the weights found are valid for the original points.
fn whitened(pts: &[Vec<f64>]) -> Option<Vec<f64>> {
    let m = pts.len();
    let d = pts[0].len();
    let mean: Vec<f64> = (0..d)
        .map(|i| pts.iter().map(|p| p[i]).sum::<f64>() / m as f64)
        .collect();
    let centred = Mat::<f64>::from_fn(d, m, |i, k| pts[k][i] - mean[i]);
    let svd = centred.thin_svd().ok()?;
    let (u, sigma) = (svd.U(), svd.S());
    let smax = (0..sigma.dim()).map(|i| sigma[i]).fold(0.0, f64::max);
    let keep: Vec<usize> = (0..sigma.dim())
        .filter(|&i| sigma[i] > 1e-13 * smax)
        .collect();
    if keep.is_empty() {
        return None;
    }
    let project = |v: &dyn Fn(usize) -> f64| -> Vec<f64> {
        keep.iter()
            .map(|&k| (0..d).map(|i| u[(i, k)] * v(i)).sum::<f64>() / sigma[k])
            .collect()
    };
    let target = project(&|i| -mean[i]);
    let shifted: Vec<Vec<f64>> = pts
        .iter()
        .map(|p| {
            let q = project(&|i| p[i] - mean[i]);
            q.iter().zip(&target).map(|(a, b)| a - b).collect()
        })
        .collect();
    let scale = shifted.iter().map(|p| dot(p, p)).fold(0.0, f64::max).sqrt();
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let unit: Vec<Vec<f64>> = shifted
        .iter()
        .map(|p| p.iter().map(|v| v / scale).collect())
        .collect();
    Some(wolfe(&unit).0)
}

/// Wolfe's minimum-norm-point iteration on unit-scale points; returns the weights (one per
/// point) and whether the optimality test `‖x‖² − min_j ⟨x, p_j⟩ ≤ 1e-12 ‖x‖` was met.
fn wolfe(pts: &[Vec<f64>]) -> (Vec<f64>, bool) {
    let m = pts.len();
    let d = pts[0].len();
    let i0 = (0..m)
        .min_by(|&a, &b| dot(&pts[a], &pts[a]).total_cmp(&dot(&pts[b], &pts[b])))
        .expect("nonempty");
    // Certified gap between the upper bound ‖x‖ and the lower bound min_j ⟨x, p_j⟩/‖x‖.
    let gap = 1e-12;
    let mut active = vec![i0];
    let mut lambda = vec![1.0];
    let mut x = pts[i0].clone();
    let mut converged = false;
    let mut dots = vec![0.0; m];
    let mut stalls = 0;
    let mut last = f64::INFINITY;
    for _ in 0..10 * (m + d) + 100 {
        let xx = dot(&x, &x);
        // Rounding can make a descent step useless (ill-determined weights): give up after a
        // few major iterations without decrease.
        if xx >= last * (1.0 - 1e-14) {
            stalls += 1;
            if stalls >= 3 {
                break;
            }
        } else {
            stalls = 0;
        }
        last = last.min(xx);
        for (k, p) in pts.iter().enumerate() {
            dots[k] = dot(&x, p);
        }
        let j = (0..m)
            .min_by(|&a, &b| dots[a].total_cmp(&dots[b]))
            .expect("nonempty");
        if xx == 0.0 || xx - dots[j] <= gap * xx.sqrt() {
            converged = true;
            break;
        }
        if active.contains(&j) {
            // No progress possible in floating point.
            break;
        }
        active.push(j);
        lambda.push(0.0);
        // Minor cycle: move towards the affine minimiser of the active set while staying in
        // the simplex; drop points whose weight reaches zero.
        loop {
            let Some(alpha) = affine_minimiser(pts, &active) else {
                // Numerically dependent active set: discard the newest point.
                active.pop();
                lambda.pop();
                break;
            };
            if alpha.iter().all(|&a| a > 0.0) {
                lambda = alpha;
                break;
            }
            let mut theta = 1.0f64;
            let mut hit = 0;
            for (k, (&l, &a)) in lambda.iter().zip(&alpha).enumerate() {
                if a <= 0.0 {
                    let t = l / (l - a);
                    if t < theta {
                        theta = t;
                        hit = k;
                    }
                }
            }
            for (l, a) in lambda.iter_mut().zip(&alpha) {
                *l = (1.0 - theta) * *l + theta * a;
            }
            lambda[hit] = 0.0;
            let mut k = 0;
            while k < active.len() {
                if lambda[k] <= 0.0 {
                    active.remove(k);
                    lambda.remove(k);
                } else {
                    k += 1;
                }
            }
            let s: f64 = lambda.iter().sum();
            lambda.iter_mut().for_each(|l| *l /= s);
        }
        x = vec![0.0; d];
        for (&i, &l) in active.iter().zip(&lambda) {
            for (xi, pi) in x.iter_mut().zip(&pts[i]) {
                *xi += l * pi;
            }
        }
    }
    let mut weights = vec![0.0; m];
    for (&i, &l) in active.iter().zip(&lambda) {
        weights[i] = l;
    }
    (weights, converged)
}

/// `argmin ‖Σ α_k p_k‖` subject to `Σ α_k = 1` over the active points. With `p_0` the first
/// active point, `α = e_0 + Σ_k β_k (e_k − e_0)` turns this into the least-squares problem
/// `min ‖p_0 + D β‖`, `D = [p_k − p_0]`, solved by QR (no Gram matrix: the conditioning of flat
/// polytopes is not squared).
fn affine_minimiser(pts: &[Vec<f64>], active: &[usize]) -> Option<Vec<f64>> {
    let s = active.len();
    if s == 1 {
        return Some(vec![1.0]);
    }
    let d = pts[0].len();
    if s - 1 > d {
        return None;
    }
    let p0 = &pts[active[0]];
    let dm = Mat::<f64>::from_fn(d, s - 1, |i, k| pts[active[k + 1]][i] - p0[i]);
    let rhs = Mat::<f64>::from_fn(d, 1, |i, _| -p0[i]);
    let beta = dm.col_piv_qr().solve_lstsq(&rhs);
    let mut alpha = Vec::with_capacity(s);
    let rest: f64 = (0..s - 1).map(|k| beta[(k, 0)]).sum();
    alpha.push(1.0 - rest);
    alpha.extend((0..s - 1).map(|k| beta[(k, 0)]));
    alpha.iter().all(|a| a.is_finite()).then_some(alpha)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn scalar(v: f64) -> Mat<f64> {
        Mat::from_fn(1, 1, |_, _| v)
    }

    #[test]
    fn interval_in_one_dimension() {
        let v = [scalar(-1.0), scalar(2.0)];
        let inside = hull_distance(&v, scalar(0.5).as_ref()).unwrap();
        assert!(inside.distance < 1e-15 && inside.converged);
        assert!((2.0 * inside.weights[1] - inside.weights[0] - 0.5).abs() < 1e-15);
        let outside = hull_distance(&v, scalar(3.5).as_ref()).unwrap();
        assert!((outside.distance - 1.5).abs() < 1e-14);
        assert!((outside.lower_bound - 1.5).abs() < 1e-14);
    }

    #[test]
    fn square_in_the_plane() {
        // Unit square corners; the point (2, 0.5) is at distance 1 from the edge x = 1.
        let pts: Vec<Mat<f64>> = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
            .iter()
            .map(|&(a, b)| Mat::from_fn(2, 1, |i, _| if i == 0 { a } else { b }))
            .collect();
        let t = Mat::from_fn(2, 1, |i, _| if i == 0 { 2.0 } else { 0.5 });
        let h = hull_distance(&pts, t.as_ref()).unwrap();
        assert!((h.distance - 1.0).abs() < 1e-14, "{h:?}");
        let t = Mat::from_fn(2, 1, |i, _| if i == 0 { 0.3 } else { 0.9 });
        assert!(hull_distance(&pts, t.as_ref()).unwrap().distance < 1e-14);
    }

    #[test]
    fn rejects_bad_shapes() {
        assert!(matches!(
            hull_distance(&[], scalar(0.0).as_ref()),
            Err(EmbedError::Input(InputError::Empty { .. }))
        ));
        let v = [Mat::<f64>::zeros(2, 2)];
        assert!(matches!(
            hull_distance(&v, scalar(0.0).as_ref()),
            Err(EmbedError::Input(InputError::DimensionMismatch { .. }))
        ));
        assert!(hull_distance(&[scalar(0.0)], scalar(f64::NAN).as_ref()).is_err());
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// A random convex combination is inside (distance ≈ 0); its reflection through the
        /// farthest vertex direction is outside, with the distance bracketed correctly.
        #[test]
        fn random_points(seed in 0u64..10_000, m in 1usize..30, d in 1usize..10) {
            let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let mut rnd = || {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
            };
            let pts: Vec<Mat<f64>> = (0..m).map(|_| Mat::from_fn(d, 1, |_, _| rnd())).collect();
            let w: Vec<f64> = (0..m).map(|_| rnd().abs() + 0.01).collect();
            let sum: f64 = w.iter().sum();
            let inside = Mat::from_fn(d, 1, |i, _| {
                (0..m).map(|k| w[k] / sum * pts[k][(i, 0)]).sum::<f64>()
            });
            let h = hull_distance(&pts, inside.as_ref()).unwrap();
            prop_assert!(h.distance < 1e-12, "{:?}", h);
            prop_assert!(h.weights.iter().all(|&w| w >= 0.0));
            prop_assert!((h.weights.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            // Far away along the first axis: distance ≥ gap to the largest first coordinate.
            let xmax = pts.iter().map(|p| p[(0, 0)]).fold(f64::NEG_INFINITY, f64::max);
            let far = Mat::from_fn(d, 1, |i, _| if i == 0 { xmax + 5.0 } else { inside[(i, 0)] });
            let h = hull_distance(&pts, far.as_ref()).unwrap();
            prop_assert!(h.distance >= 5.0 - 1e-12 && h.lower_bound <= h.distance + 1e-12);
            prop_assert!(h.lower_bound >= 5.0 - 1e-9, "{:?}", h);
        }
    }
}
