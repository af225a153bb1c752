//! LMI (41) of Ferrante et al. (2016) solved on the vertices that bind (constraint generation;
//! not in the paper).
//!
//! A residue box split into pieces has many vertices (`1024` for a plant of order 8 on 16
//! pieces), the cost of an interior-point iteration grows linearly with their number, and few
//! of them bind: on the eight-state modal plant of the corpus, 99 % of the optimal dual weight
//! sits on the vertices of the piece at `T1`. A window search only needs a point at which (41)
//! holds at **every** vertex by more than rounding and the embedding's error can explain
//! ([`crate::certificate::strictly_negative`]), so its probes solve (41) on a subset of the
//! vertices ([`ActiveSet`]), test every vertex at the returned point, add the ones that fail
//! (most violated first) and solve again (`crate::design`):
//! - a point that passes the test at every vertex is a certificate of the whole polytope,
//!   whatever subset produced it;
//! - a subset without a positive margin decides the window: (41) at fewer vertices is a
//!   relaxation, so its optimal margin bounds the whole polytope's from above;
//! - a point that fails only at the subset's own vertices, or a round whose added vertices
//!   lower the margin by less than 1 %, ends the search with the subset's point: its margin,
//!   an upper bound of the whole polytope's, is taken as that margin, undecided by the test;
//! - a subset that grows past half of the vertices is given up for a solve at every vertex.
//!
//! What can differ from a solve at every vertex is only the point returned at an undecided
//! margin (the optimum of a relaxation instead of the analytic centre of the whole optimal
//! face), and with it the coordinates in which the design tries again (`crate::certificate`).

use faer::Mat;

use crate::certificate::{VertexSet, VertexTest};

/// Vertex count from which a window search's probe solves (41) on a subset of the vertices
/// first (measured on the corpus: from 128 on, two-mass-flexible's search took 3.2 s instead of
/// 4.8 s but ended one bisection step lower; from 256 on, every corpus plant keeps its bracket).
pub(crate) const ACTIVE_FROM: usize = 256;

/// Number of vertices of the first subset (evenly spaced in the embedding's order, which runs
/// from `T1` to `T2` piece by piece), and the largest number added in one round (measured on
/// the eight-state modal plant: 32 resolved its search within 0.5 % in 17 s, 64 needed 35 s
/// and 128 needed 72 s, each round's solve costing in proportion to its vertices).
pub(crate) const ROUND: usize = 32;

/// The vertices of LMI (41) that a solve imposes: a subset of the embedding's, in its order.
pub(crate) struct ActiveSet {
    /// Whether each vertex is imposed.
    imposed: Vec<bool>,
}

impl ActiveSet {
    /// [`ROUND`] vertices evenly spaced over `count` (all of them when `count ≤ ROUND`), the
    /// first and the last included.
    pub fn new(count: usize) -> Self {
        let mut imposed = vec![false; count];
        if count <= ROUND {
            imposed.fill(true);
        } else {
            for k in 0..ROUND {
                imposed[k * (count - 1) / (ROUND - 1)] = true;
            }
        }
        Self { imposed }
    }

    /// Number of imposed vertices.
    pub fn len(&self) -> usize {
        self.imposed.iter().filter(|&&b| b).count()
    }

    /// The imposed vertices of `set`.
    pub fn vertices(&self, set: &VertexSet<'_>) -> Vec<Mat<f64>> {
        set.vertices
            .iter()
            .zip(&self.imposed)
            .filter(|(_, b)| **b)
            .map(|(x, _)| x.clone())
            .collect()
    }

    /// Imposes the vertices outside the set at which `test` fails (`λmax(Φ_i) ≥ −τ`), the most
    /// violated first and at most [`ROUND`] of them; returns how many were added.
    pub fn add_failing(&mut self, set: &VertexSet<'_>, test: &VertexTest<'_>) -> usize {
        let mut failing: Vec<(f64, usize)> = set
            .vertices
            .iter()
            .enumerate()
            .filter(|(i, _)| !self.imposed[*i])
            .map(|(i, x)| (test.largest_eigenvalue(x.as_ref()), i))
            .filter(|(l, _)| !(*l < -test.tau))
            .collect();
        failing.sort_by(|a, b| b.0.total_cmp(&a.0));
        failing.truncate(ROUND);
        for &(_, i) in &failing {
            self.imposed[i] = true;
        }
        failing.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_subset_spans_the_vertices() {
        for count in [1, 5, ROUND, ROUND + 1, 257, 1024] {
            let set = ActiveSet::new(count);
            assert_eq!(set.len(), count.min(ROUND), "{count}");
            assert!(set.imposed[0] && set.imposed[count - 1], "{count}");
        }
    }
}
