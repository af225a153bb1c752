//! Sparse affine matrix forms `F(y) = F_0 + Σ_k y_k F_k`, the numeric representation behind every
//! [`Expr`](super::Expr).
//!
//! An [`Affine`] is one sorted list of triplets `(slot, col, row, value)`: slot 0 is the constant
//! term `F_0`, slot `k + 1` the coefficient `F_k` of decision scalar `y_k`. Entries are sorted by
//! `(slot, col, row)` with duplicates summed and exact zeros removed, so every coefficient matrix is
//! stored column-major and sparse, and all operations are merges or sparse–sparse products.

use faer::{Mat, MatRef};

/// Slot of the constant term.
pub(crate) const CONST: u32 = 0;

/// One stored entry of an [`Affine`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Entry {
    /// 0 = constant, `k + 1` = decision scalar `k`.
    pub slot: u32,
    /// Column index.
    pub col: u32,
    /// Row index.
    pub row: u32,
    /// Value.
    pub val: f64,
}

impl Entry {
    #[inline]
    fn key(&self) -> (u32, u32, u32) {
        (self.slot, self.col, self.row)
    }
}

/// A `rows × cols` affine matrix function of the decision scalars (see the module docs).
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct Affine {
    pub rows: usize,
    pub cols: usize,
    /// Sorted by `(slot, col, row)`, no duplicates, no exact zeros.
    pub entries: Vec<Entry>,
}

/// A constant sparse matrix in compressed-column form (used as the constant factor of products).
struct Csc {
    rows: usize,
    cols: usize,
    ptr: Vec<usize>,
    idx: Vec<u32>,
    val: Vec<f64>,
}

impl Csc {
    /// From a constant `Affine` (entries already sorted column-major).
    fn from_constant(a: &Affine) -> Self {
        let mut ptr = vec![0usize; a.cols + 1];
        for e in &a.entries {
            ptr[e.col as usize + 1] += 1;
        }
        for j in 0..a.cols {
            ptr[j + 1] += ptr[j];
        }
        Self {
            rows: a.rows,
            cols: a.cols,
            ptr,
            idx: a.entries.iter().map(|e| e.row).collect(),
            val: a.entries.iter().map(|e| e.val).collect(),
        }
    }

    fn col(&self, j: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let r = self.ptr[j]..self.ptr[j + 1];
        self.idx[r.clone()]
            .iter()
            .zip(&self.val[r])
            .map(|(&i, &v)| (i as usize, v))
    }
}

/// Dense accumulator with a touched list (the classic sparse-product workspace).
struct Accumulator {
    acc: Vec<f64>,
    mark: Vec<bool>,
    touched: Vec<u32>,
}

impl Accumulator {
    fn new(n: usize) -> Self {
        Self {
            acc: vec![0.0; n],
            mark: vec![false; n],
            touched: Vec::new(),
        }
    }

    #[inline]
    fn add(&mut self, i: usize, v: f64) {
        if !self.mark[i] {
            self.mark[i] = true;
            self.touched.push(i as u32);
        }
        self.acc[i] += v;
    }

    /// Emits the accumulated column (sorted by row) into `out` and resets.
    fn flush(&mut self, slot: u32, col: u32, out: &mut Vec<Entry>) {
        self.touched.sort_unstable();
        for &i in &self.touched {
            let v = self.acc[i as usize];
            if v != 0.0 {
                out.push(Entry {
                    slot,
                    col,
                    row: i,
                    val: v,
                });
            }
            self.acc[i as usize] = 0.0;
            self.mark[i as usize] = false;
        }
        self.touched.clear();
    }
}

impl Affine {
    /// Builds from arbitrary (unsorted, possibly duplicated) entries.
    pub fn from_entries(rows: usize, cols: usize, mut entries: Vec<Entry>) -> Self {
        entries.sort_unstable_by_key(Entry::key);
        let mut out: Vec<Entry> = Vec::with_capacity(entries.len());
        for e in entries {
            match out.last_mut() {
                Some(last) if last.key() == e.key() => last.val += e.val,
                _ => out.push(e),
            }
        }
        out.retain(|e| e.val != 0.0);
        Self {
            rows,
            cols,
            entries: out,
        }
    }

    /// The zero matrix.
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Self {
            rows,
            cols,
            entries: Vec::new(),
        }
    }

    /// `c · I_n`.
    pub fn scaled_identity(n: usize, c: f64) -> Self {
        let entries = if c == 0.0 {
            Vec::new()
        } else {
            (0..n as u32)
                .map(|i| Entry {
                    slot: CONST,
                    col: i,
                    row: i,
                    val: c,
                })
                .collect()
        };
        Self {
            rows: n,
            cols: n,
            entries,
        }
    }

    /// A dense constant. Returns the first non-finite entry as `Err((row, col, value))`.
    pub fn from_dense(m: MatRef<'_, f64>) -> Result<Self, (usize, usize, f64)> {
        let mut entries = Vec::new();
        for j in 0..m.ncols() {
            for i in 0..m.nrows() {
                let v = m[(i, j)];
                if !v.is_finite() {
                    return Err((i, j, v));
                }
                if v != 0.0 {
                    entries.push(Entry {
                        slot: CONST,
                        col: j as u32,
                        row: i as u32,
                        val: v,
                    });
                }
            }
        }
        Ok(Self {
            rows: m.nrows(),
            cols: m.ncols(),
            entries,
        })
    }

    /// Whether no decision scalar occurs (only the constant slot is stored).
    pub fn is_constant(&self) -> bool {
        self.entries.last().is_none_or(|e| e.slot == CONST)
    }

    /// First non-finite stored value, if any (overflow while combining data).
    pub fn first_non_finite(&self) -> Option<&Entry> {
        self.entries.iter().find(|e| !e.val.is_finite())
    }

    /// `α·self + β·other` (same shape; checked by the caller).
    pub fn lin_comb(&self, alpha: f64, other: &Affine, beta: f64) -> Affine {
        let (a, b) = (&self.entries, &other.entries);
        let mut out = Vec::with_capacity(a.len() + b.len());
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < b.len() {
            let take_a = j == b.len() || (i < a.len() && a[i].key() <= b[j].key());
            let take_b = i == a.len() || (j < b.len() && b[j].key() <= a[i].key());
            let mut e = if take_a { a[i] } else { b[j] };
            e.val = match (take_a, take_b) {
                (true, true) => alpha * a[i].val + beta * b[j].val,
                (true, false) => alpha * a[i].val,
                _ => beta * b[j].val,
            };
            if take_a {
                i += 1;
            }
            if take_b {
                j += 1;
            }
            if e.val != 0.0 {
                out.push(e);
            }
        }
        Affine {
            rows: self.rows,
            cols: self.cols,
            entries: out,
        }
    }

    /// `s · self`.
    pub fn scale(&self, s: f64) -> Affine {
        if s == 0.0 {
            return Affine::zeros(self.rows, self.cols);
        }
        let entries = self
            .entries
            .iter()
            .map(|e| Entry {
                val: s * e.val,
                ..*e
            })
            .collect();
        Affine {
            rows: self.rows,
            cols: self.cols,
            entries,
        }
    }

    /// `selfᵀ`.
    pub fn transpose(&self) -> Affine {
        let entries = self
            .entries
            .iter()
            .map(|e| Entry {
                slot: e.slot,
                col: e.row,
                row: e.col,
                val: e.val,
            })
            .collect();
        let mut t = Affine {
            rows: self.cols,
            cols: self.rows,
            entries,
        };
        t.entries.sort_unstable_by_key(Entry::key);
        t
    }

    /// `m · self` for a constant `m` (`m.cols == self.rows`, checked by the caller).
    pub fn left_mul_const(m: &Affine, a: &Affine) -> Affine {
        debug_assert!(m.is_constant() && m.cols == a.rows);
        let csc = Csc::from_constant(m);
        let mut acc = Accumulator::new(csc.rows);
        let mut out = Vec::new();
        let e = &a.entries;
        let mut k = 0;
        while k < e.len() {
            let (slot, col) = (e[k].slot, e[k].col);
            while k < e.len() && e[k].slot == slot && e[k].col == col {
                let v = e[k].val;
                for (q, w) in csc.col(e[k].row as usize) {
                    acc.add(q, w * v);
                }
                k += 1;
            }
            acc.flush(slot, col, &mut out);
        }
        Affine {
            rows: csc.rows,
            cols: a.cols,
            entries: out,
        }
    }

    /// `self · m` for a constant `m` (`self.cols == m.rows`, checked by the caller).
    pub fn right_mul_const(a: &Affine, m: &Affine) -> Affine {
        debug_assert!(m.is_constant() && a.cols == m.rows);
        let csc = Csc::from_constant(m);
        let mut acc = Accumulator::new(a.rows);
        let mut out = Vec::new();
        let e = &a.entries;
        let mut start = 0;
        // Column pointers of the current slot group.
        let mut colptr = vec![0usize; a.cols + 1];
        while start < e.len() {
            let slot = e[start].slot;
            let mut end = start;
            while end < e.len() && e[end].slot == slot {
                end += 1;
            }
            colptr.iter_mut().for_each(|p| *p = 0);
            for x in &e[start..end] {
                colptr[x.col as usize + 1] += 1;
            }
            for j in 0..a.cols {
                colptr[j + 1] += colptr[j];
            }
            for s in 0..csc.cols {
                for (j, w) in csc.col(s) {
                    for x in &e[start + colptr[j]..start + colptr[j + 1]] {
                        acc.add(x.row as usize, x.val * w);
                    }
                }
                acc.flush(slot, s as u32, &mut out);
            }
            start = end;
        }
        Affine {
            rows: a.rows,
            cols: csc.cols,
            entries: out,
        }
    }

    /// Kronecker product `a ⊗ b`; at least one factor must be constant (checked by the caller).
    pub fn kron(a: &Affine, b: &Affine) -> Affine {
        debug_assert!(a.is_constant() || b.is_constant());
        let (rows, cols) = (a.rows * b.rows, a.cols * b.cols);
        let mut entries = Vec::with_capacity(a.entries.len() * b.entries.len());
        for x in &a.entries {
            for z in &b.entries {
                entries.push(Entry {
                    slot: x.slot.max(z.slot),
                    col: x.col * b.cols as u32 + z.col,
                    row: x.row * b.rows as u32 + z.row,
                    val: x.val * z.val,
                });
            }
        }
        Affine::from_entries(rows, cols, entries)
    }

    /// Block matrix from a row-major grid of optional cells (`None` = zero block).
    pub fn blocks(heights: &[usize], widths: &[usize], cells: &[Option<&Affine>]) -> Affine {
        let rows = heights.iter().sum();
        let cols = widths.iter().sum();
        let mut entries = Vec::new();
        let mut r0 = 0;
        for (bi, &h) in heights.iter().enumerate() {
            let mut c0 = 0;
            for (bj, &w) in widths.iter().enumerate() {
                if let Some(cell) = cells[bi * widths.len() + bj] {
                    entries.extend(cell.entries.iter().map(|e| Entry {
                        slot: e.slot,
                        col: e.col + c0 as u32,
                        row: e.row + r0 as u32,
                        val: e.val,
                    }));
                }
                c0 += w;
            }
            r0 += h;
        }
        entries.sort_unstable_by_key(Entry::key);
        Affine {
            rows,
            cols,
            entries,
        }
    }

    /// `tr(self)` as a 1×1 form (square, checked by the caller).
    pub fn trace(&self) -> Affine {
        let entries = self
            .entries
            .iter()
            .filter(|e| e.row == e.col)
            .map(|e| Entry {
                slot: e.slot,
                col: 0,
                row: 0,
                val: e.val,
            })
            .collect();
        Affine::from_entries(1, 1, entries)
    }

    /// The `nr × nc` sub-block starting at `(r0, c0)` (in range, checked by the caller).
    pub fn submatrix(&self, r0: usize, c0: usize, nr: usize, nc: usize) -> Affine {
        let (r0, c0) = (r0 as u32, c0 as u32);
        let (r1, c1) = (r0 + nr as u32, c0 + nc as u32);
        let entries = self
            .entries
            .iter()
            .filter(|e| e.row >= r0 && e.row < r1 && e.col >= c0 && e.col < c1)
            .map(|e| Entry {
                slot: e.slot,
                col: e.col - c0,
                row: e.row - r0,
                val: e.val,
            })
            .collect();
        Affine {
            rows: nr,
            cols: nc,
            entries,
        }
    }

    /// Dense value at the point `y` (indexed by decision scalar).
    pub fn eval(&self, y: &[f64]) -> Mat<f64> {
        let mut m = Mat::<f64>::zeros(self.rows, self.cols);
        for e in &self.entries {
            let s = if e.slot == CONST {
                1.0
            } else {
                y[e.slot as usize - 1]
            };
            m[(e.row as usize, e.col as usize)] += s * e.val;
        }
        m
    }

    /// `max(‖F_0‖_max, max_k |y_k|·‖F_k‖_max)`: the magnitude of the summands that make up
    /// `F(y)`, i.e. the scale of the rounding and solver errors in its value.
    pub fn summand_scale(&self, y: &[f64]) -> f64 {
        self.entries
            .iter()
            .map(|e| {
                let s = if e.slot == CONST {
                    1.0
                } else {
                    y[e.slot as usize - 1].abs()
                };
                s * e.val.abs()
            })
            .fold(0.0, f64::max)
    }

    /// Largest asymmetry `|F_ij − F_ji|` over all slots, relative to the largest magnitude of
    /// the slot it occurs in: `(slot, row, col, asymmetry, slot scale)` of the worst entry.
    pub fn worst_asymmetry(&self) -> Option<(u32, usize, usize, f64, f64)> {
        let t = self.transpose();
        let diff = self.lin_comb(1.0, &t, -1.0);
        let mut scale = std::collections::HashMap::<u32, f64>::new();
        for e in &self.entries {
            let s = scale.entry(e.slot).or_insert(0.0);
            *s = s.max(e.val.abs());
        }
        diff.entries
            .iter()
            .map(|e| {
                let s = scale.get(&e.slot).copied().unwrap_or(0.0);
                (e.slot, e.row as usize, e.col as usize, e.val.abs(), s)
            })
            .max_by(|a, b| {
                (a.3 / a.4.max(f64::MIN_POSITIVE)).total_cmp(&(b.3 / b.4.max(f64::MIN_POSITIVE)))
            })
    }

    /// `(self + selfᵀ)/2`.
    pub fn symmetrized(&self) -> Affine {
        self.lin_comb(0.5, &self.transpose(), 0.5)
    }

    /// The distinct slots that occur, ascending.
    pub fn slots(&self) -> impl Iterator<Item = u32> + '_ {
        let mut last = None;
        self.entries.iter().filter_map(move |e| {
            if last == Some(e.slot) {
                None
            } else {
                last = Some(e.slot);
                Some(e.slot)
            }
        })
    }

    /// Maps every slot through `f`, which returns a list of `(new_slot, factor)` images (an
    /// affine substitution of the decision scalars). The result is re-sorted and merged.
    pub fn substitute(&self, mut f: impl FnMut(u32) -> Vec<(u32, f64)>) -> Affine {
        let mut entries = Vec::with_capacity(self.entries.len());
        let mut k = 0;
        while k < self.entries.len() {
            let slot = self.entries[k].slot;
            let mut end = k;
            while end < self.entries.len() && self.entries[end].slot == slot {
                end += 1;
            }
            for (new_slot, factor) in f(slot) {
                entries.extend(self.entries[k..end].iter().map(|e| Entry {
                    slot: new_slot,
                    val: factor * e.val,
                    ..*e
                }));
            }
            k = end;
        }
        Affine::from_entries(self.rows, self.cols, entries)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    fn var(k: u32, rows: usize, cols: usize, i: u32, j: u32) -> Affine {
        Affine {
            rows,
            cols,
            entries: vec![Entry {
                slot: k + 1,
                col: j,
                row: i,
                val: 1.0,
            }],
        }
    }

    /// Dense reference: evaluate at a point and compare with dense products.
    #[test]
    fn products_match_dense_evaluation() {
        let m = mat![[1.0, 2.0, 0.0], [0.0, -1.0, 3.0]];
        let n = mat![[0.5, 0.0], [1.0, 2.0], [0.0, -4.0]];
        let mut x = var(0, 3, 3, 0, 0)
            .lin_comb(1.0, &var(1, 3, 3, 1, 2), 2.0)
            .lin_comb(1.0, &var(2, 3, 3, 2, 0), -1.0);
        x = x.lin_comb(1.0, &Affine::scaled_identity(3, 0.25), 1.0);
        let y = [0.3, -1.2, 2.5];
        let xd = x.eval(&y);
        let mc = Affine::from_dense(m.as_ref()).unwrap();
        let nc = Affine::from_dense(n.as_ref()).unwrap();
        let left = Affine::left_mul_const(&mc, &x).eval(&y);
        let right = Affine::right_mul_const(&x, &nc).eval(&y);
        let both = Affine::right_mul_const(&Affine::left_mul_const(&mc, &x), &nc).eval(&y);
        assert!((&left - &m * &xd).norm_max() < 1e-14);
        assert!((&right - &xd * &n).norm_max() < 1e-14);
        assert!((&both - &m * &xd * &n).norm_max() < 1e-13);
        let t = x.transpose().eval(&y);
        assert!((&t - xd.transpose()).norm_max() == 0.0);
        let k = Affine::kron(&mc, &x).eval(&y);
        let kd = m.kron(&xd);
        assert!((&k - &kd).norm_max() < 1e-14);
        assert_eq!(
            x.trace().eval(&y)[(0, 0)],
            xd[(0, 0)] + xd[(1, 1)] + xd[(2, 2)]
        );
        let sub = x.submatrix(1, 0, 2, 3).eval(&y);
        assert!((&sub - xd.submatrix(1, 0, 2, 3)).norm_max() == 0.0);
    }

    #[test]
    fn entries_are_canonical() {
        let a = Affine::from_entries(
            2,
            2,
            vec![
                Entry {
                    slot: 2,
                    col: 1,
                    row: 0,
                    val: 1.0,
                },
                Entry {
                    slot: 0,
                    col: 0,
                    row: 0,
                    val: 1.0,
                },
                Entry {
                    slot: 2,
                    col: 1,
                    row: 0,
                    val: -1.0,
                },
                Entry {
                    slot: 1,
                    col: 0,
                    row: 1,
                    val: 3.0,
                },
            ],
        );
        assert_eq!(a.entries.len(), 2);
        assert_eq!(a.slots().collect::<Vec<_>>(), vec![0, 1]);
        assert!(!a.is_constant());
        let s = a.symmetrized();
        assert!(s.worst_asymmetry().is_none());
        let (slot, _, _, asym, scale) = a.worst_asymmetry().unwrap();
        assert_eq!((slot, asym, scale), (1, 3.0, 3.0));
    }
}
