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
//! (most violated first) and solve again ([`solve_binding`]):
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
use crate::error::Error;
use crate::lmi::LmiResult;
use crate::system::Plant;

/// Vertex count from which a window search's probe solves (41) on a subset of the vertices
/// first (measured on the corpus: from 128 on, two-mass-flexible's search took 3.2 s instead of
/// 4.8 s but ended one bisection step lower; from 256 on, every corpus plant keeps its bracket).
pub(crate) const ACTIVE_FROM: usize = 256;

/// Number of vertices of the first subset (evenly spaced in the embedding's order, which runs
/// from `T1` to `T2` piece by piece), and the largest number added in one round (measured on
/// the eight-state modal plant: 32 resolved its search within 0.5 % in 17 s, 64 needed 35 s
/// and 128 needed 72 s, each round's solve costing in proportion to its vertices).
pub(crate) const ROUND: usize = 32;

/// Relative decrease of the margin below which vertices added to a subset ([`ActiveSet`]) are
/// taken not to bind: the subset's optimal margin is then taken as the whole polytope's (it is
/// an upper bound of it), and the window as undecided by the rounding-aware test, which the
/// subset's point fails (measured on eight-state-modal near its largest `T2`: margins 3.7e-8,
/// 9.89e-9, 9.88e-9, 9.88e-9 in four rounds, the last two adding vertices that fail the test
/// only within `τ`).
const STALL: f64 = 1e-2;

/// LMI (41) at the vertices of `set` by constraint generation (see the module docs): `solve`
/// solves it at the vertices it is given and says whether the returned point passes the
/// rounding-aware test at every vertex of `set`.
pub(crate) fn solve_binding(
    plant: &Plant,
    set: &VertexSet<'_>,
    mut solve: impl FnMut(&[Mat<f64>]) -> Result<(LmiResult, bool), Error>,
) -> Result<(LmiResult, bool), Error> {
    let count = set.vertices.len();
    let mut active = ActiveSet::new(count);
    let mut previous: Option<f64> = None;
    for round in 1.. {
        let subset = active.vertices(set);
        let (mut r, certified) = solve(&subset)?;
        r.size.lmi_count = count;
        if certified {
            return Ok((r, true));
        }
        let margin = r.margin.filter(|t| *t > 0.0);
        let stalled = margin
            .zip(previous)
            .is_some_and(|(t, p)| t > (1.0 - STALL) * p);
        let added = match (margin, stalled) {
            (Some(_), false) => {
                VertexTest::new(plant, set, (r.p.as_ref(), r.f.as_ref(), r.j.as_ref()))
                    .map_or(0, |test| active.add_failing(set, &test))
            }
            _ => 0,
        };
        if added == 0 {
            // The subset decides: a relaxation without a positive margin, or a point that
            // fails the test only at the subset's own vertices, or vertices added without
            // lowering the margin (so not binding).
            r.feasible = false;
            r.stats.reason = format!(
                "{}; (41) imposed at {} of the {count} vertices, those found to bind in \
                 {round} solve(s) (constraint generation, not in the paper): a relaxation of \
                 (41) at every vertex, whose margin bounds theirs from above",
                r.stats.reason,
                subset.len(),
            );
            return Ok((r, false));
        }
        if 2 * active.len() > count {
            break;
        }
        previous = margin;
    }
    solve(set.vertices)
}

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
