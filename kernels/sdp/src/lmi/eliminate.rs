//! Elimination of linear equality constraints `G y = h` on the decision scalars.
//!
//! The dual (LMI) form `max bᵀy s.t. C − Σ y_i A_i ⪰ 0` has free `y` but no equality rows, and
//! writing `g(y) = 0` as `g ≥ 0, g ≤ 0` would destroy every interior point (the notes, §5: IPMs
//! stall or lose accuracy on such models). Instead the equalities are solved exactly: Gauss–Jordan
//! elimination with complete pivoting brings `[G | h]` to reduced row-echelon form, every pivot
//! scalar becomes `y_p = ĥ_p − Σ_f R_pf y_f` in terms of the free scalars, and that substitution
//! is applied to every inequality before compiling. Redundant equalities (rank deficiency) are
//! dropped; inconsistent ones are reported as [`ModelError::InconsistentEqualities`].

use super::affine::{Affine, CONST};
use super::error::ModelError;

/// Pivot threshold of the elimination, relative to the (row-equilibrated) largest coefficient.
const PIVOT_TOL: f64 = 1e-11;
/// Coefficients of the substitution below this magnitude are dropped (rows are pivot-normalised).
const DROP_TOL: f64 = 1e-14;

/// One solved pivot: `y[scalar] = rhs − Σ coeffs`.
#[derive(Debug, Clone, PartialEq)]
struct PivotRow {
    rhs: f64,
    /// `(free scalar, R_pf)`.
    coeffs: Vec<(usize, f64)>,
}

/// The solution map of the equality constraints.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct Elimination {
    /// For every decision scalar: `Some(row)` if it is a pivot (eliminated).
    pivot_of: Vec<Option<usize>>,
    rows: Vec<PivotRow>,
}

impl Elimination {
    /// No equalities.
    pub fn identity(num_scalars: usize) -> Self {
        Self {
            pivot_of: vec![None; num_scalars],
            rows: Vec::new(),
        }
    }

    /// Eliminates the equalities `a = 0` for every `(name, a)` (all entries of every `a`).
    pub fn build(num_scalars: usize, equalities: &[(&str, &Affine)]) -> Result<Self, ModelError> {
        // Columns: the scalars that occur in some equality.
        let mut col_of = vec![usize::MAX; num_scalars];
        let mut cols: Vec<usize> = Vec::new();
        // Rows: (equality index, position) → row.
        let mut row_of = std::collections::HashMap::<(usize, u32, u32), usize>::new();
        let mut origin: Vec<usize> = Vec::new();
        for (q, (_, a)) in equalities.iter().enumerate() {
            for e in &a.entries {
                row_of.entry((q, e.row, e.col)).or_insert_with(|| {
                    origin.push(q);
                    origin.len() - 1
                });
                if e.slot != CONST {
                    let k = e.slot as usize - 1;
                    if col_of[k] == usize::MAX {
                        col_of[k] = cols.len();
                        cols.push(k);
                    }
                }
            }
        }
        let (m, n) = (origin.len(), cols.len());
        let mut g = vec![0.0; m * n]; // row-major
        let mut h = vec![0.0; m];
        for (q, (_, a)) in equalities.iter().enumerate() {
            for e in &a.entries {
                let r = row_of[&(q, e.row, e.col)];
                if e.slot == CONST {
                    h[r] -= e.val;
                } else {
                    g[r * n + col_of[e.slot as usize - 1]] += e.val;
                }
            }
        }
        // Row equilibration.
        let h_scale = h.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        for r in 0..m {
            let s = g[r * n..(r + 1) * n]
                .iter()
                .fold(0.0f64, |s, v| s.max(v.abs()));
            if s > 0.0 {
                g[r * n..(r + 1) * n].iter_mut().for_each(|v| *v /= s);
                h[r] /= s;
            }
        }
        // Gauss–Jordan with complete pivoting.
        let mut pivot_cols = Vec::new();
        let mut is_pivot = vec![false; n];
        let mut rank = 0;
        while rank < m {
            let mut best = (0.0, 0, 0);
            for r in rank..m {
                for c in 0..n {
                    let v = g[r * n + c].abs();
                    if !is_pivot[c] && v > best.0 {
                        best = (v, r, c);
                    }
                }
            }
            let (v, pr, pc) = best;
            if v <= PIVOT_TOL {
                break;
            }
            if pr != rank {
                for c in 0..n {
                    g.swap(pr * n + c, rank * n + c);
                }
                h.swap(pr, rank);
                origin.swap(pr, rank);
            }
            let piv = g[rank * n + pc];
            for c in 0..n {
                g[rank * n + c] /= piv;
            }
            h[rank] /= piv;
            for r in 0..m {
                if r != rank {
                    let f = g[r * n + pc];
                    if f != 0.0 {
                        for c in 0..n {
                            g[r * n + c] -= f * g[rank * n + c];
                        }
                        h[r] -= f * h[rank];
                    }
                }
            }
            is_pivot[pc] = true;
            pivot_cols.push(pc);
            rank += 1;
        }
        for r in rank..m {
            if h[r].abs() > 1e-9 * (1.0 + h_scale) {
                return Err(ModelError::InconsistentEqualities {
                    constraint: equalities[origin[r]].0.to_string(),
                    residual: h[r],
                });
            }
        }
        let mut pivot_of = vec![None; num_scalars];
        let mut rows = Vec::with_capacity(rank);
        for (r, &pc) in pivot_cols.iter().enumerate() {
            let coeffs = (0..n)
                .filter(|&c| !is_pivot[c] && g[r * n + c].abs() > DROP_TOL)
                .map(|c| (cols[c], g[r * n + c]))
                .collect();
            pivot_of[cols[pc]] = Some(r);
            rows.push(PivotRow { rhs: h[r], coeffs });
        }
        Ok(Self { pivot_of, rows })
    }

    /// Whether every pivot has a zero right-hand side (the equalities are homogeneous).
    pub fn is_homogeneous(&self) -> bool {
        self.rows.iter().all(|r| r.rhs == 0.0)
    }

    /// Substitutes the eliminated scalars in `a`; the result only involves free scalars.
    pub fn apply(&self, a: &Affine) -> Affine {
        if self.rows.is_empty() {
            return a.clone();
        }
        a.substitute(|slot| {
            if slot == CONST {
                return vec![(CONST, 1.0)];
            }
            match self.pivot_of[slot as usize - 1] {
                None => vec![(slot, 1.0)],
                Some(r) => {
                    let row = &self.rows[r];
                    let mut img = Vec::with_capacity(row.coeffs.len() + 1);
                    if row.rhs != 0.0 {
                        img.push((CONST, row.rhs));
                    }
                    img.extend(row.coeffs.iter().map(|&(f, c)| (f as u32 + 1, -c)));
                    img
                }
            }
        })
    }

    /// Fills in the eliminated scalars of `y` from its free ones.
    pub fn recover(&self, y: &mut [f64]) {
        for (k, p) in self.pivot_of.iter().enumerate() {
            if let Some(r) = p {
                let row = &self.rows[*r];
                y[k] = row.rhs - row.coeffs.iter().map(|&(f, c)| c * y[f]).sum::<f64>();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::affine::Entry;
    use super::*;

    fn row(terms: &[(u32, f64)], rhs: f64) -> Affine {
        // Σ terms − rhs = 0 as a 1×1 form.
        let mut e: Vec<Entry> = terms
            .iter()
            .map(|&(k, v)| Entry {
                slot: k + 1,
                col: 0,
                row: 0,
                val: v,
            })
            .collect();
        e.push(Entry {
            slot: CONST,
            col: 0,
            row: 0,
            val: -rhs,
        });
        Affine::from_entries(1, 1, e)
    }

    #[test]
    fn solves_redundant_system_and_recovers() {
        // y0 + y1 = 3, 2 y0 + 2 y1 = 6 (redundant), y1 − y2 = 1.
        let a = row(&[(0, 1.0), (1, 1.0)], 3.0);
        let b = row(&[(0, 2.0), (1, 2.0)], 6.0);
        let c = row(&[(1, 1.0), (2, -1.0)], 1.0);
        let el = Elimination::build(4, &[("a", &a), ("b", &b), ("c", &c)]).unwrap();
        assert_eq!(el.rows.len(), 2);
        let free: Vec<usize> = (0..4).filter(|&k| el.pivot_of[k].is_none()).collect();
        assert_eq!(free.len(), 2);
        let mut y = vec![0.0; 4];
        for (i, &f) in free.iter().enumerate() {
            y[f] = 0.7 + i as f64;
        }
        el.recover(&mut y);
        assert!((y[0] + y[1] - 3.0).abs() < 1e-14);
        assert!((y[1] - y[2] - 1.0).abs() < 1e-14);
        // Substituting into y0 + 5 y2 gives the same value at the recovered point.
        let f = row(&[(0, 1.0), (2, 5.0)], 0.0);
        let g = el.apply(&f);
        assert!(
            g.slots()
                .all(|s| s == CONST || el.pivot_of[s as usize - 1].is_none())
        );
        assert!((g.eval(&y)[(0, 0)] - f.eval(&y)[(0, 0)]).abs() < 1e-13);
    }

    #[test]
    fn reports_inconsistency() {
        let a = row(&[(0, 1.0)], 1.0);
        let b = row(&[(0, 1.0)], 2.0);
        let e = Elimination::build(1, &[("a", &a), ("b", &b)]).unwrap_err();
        assert!(
            matches!(e, ModelError::InconsistentEqualities { .. }),
            "{e}"
        );
    }
}
