//! Hybrid time domains and hybrid arcs (Goebel, Sanfelice & Teel, *Hybrid Dynamical Systems*, 2012, Ch. 2).
//!
//! A hybrid arc is a function on a hybrid time domain `E = ∪_j [t_j, t_{j+1}] × {j}`: time `t` flows
//! continuously inside each interval and the jump counter `j` increments by one at each jump instant
//! `t_{j+1}`, where the arc takes two values (the pre-jump state `φ(t_{j+1}, j)` and the post-jump state
//! `φ(t_{j+1}, j+1)`). [`HybridArc`] stores samples of such an arc compactly as a struct of arrays
//! (times, jump counters, states in one flat row-major buffer). The invariants of a hybrid time domain
//! are enforced on insertion:
//!
//! * `t` is nondecreasing;
//! * `j` either stays constant (flow sample, `t` may advance) or increases by exactly one at the same `t`
//!   (jump: the pre-jump sample is immediately followed by the post-jump sample).

use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite_slice;
use std::io::Write;
use std::path::Path;

use crate::error::SimError;

/// A hybrid time `(t, j)`: ordinary time `t` and jump counter `j`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HybridTime {
    /// Ordinary (continuous) time.
    pub t: f64,
    /// Number of jumps that occurred before this point.
    pub j: usize,
}

/// Which value of an arc to return at a jump instant when projecting onto ordinary time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JumpSide {
    /// The value just before the jump, `φ(t_k, k-1)` (e.g. the open-loop prediction `x̂(t_k^-)`).
    Before,
    /// The value just after the jump, `φ(t_k, k)` (e.g. the corrected estimate `x̂(t_k^+)`).
    After,
}

/// One jump of a recorded arc.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JumpRecord {
    /// Jump instant `t_{j+1}`.
    pub t: f64,
    /// Jump counter before the jump (the counter after it is `j_before + 1`).
    pub j_before: usize,
    /// Sample index of the pre-jump state.
    pub before: usize,
    /// Sample index of the post-jump state (`before + 1`).
    pub after: usize,
}

/// Samples of a hybrid arc `φ : E → R^dim`, stored as a struct of arrays.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HybridArc {
    dim: usize,
    t: Vec<f64>,
    j: Vec<usize>,
    x: Vec<f64>,
}

impl HybridArc {
    /// An empty arc with values in `R^dim`.
    pub fn new(dim: usize) -> Self {
        Self {
            dim,
            t: Vec::new(),
            j: Vec::new(),
            x: Vec::new(),
        }
    }

    /// An empty arc with room for `samples` samples.
    pub fn with_capacity(dim: usize, samples: usize) -> Self {
        Self {
            dim,
            t: Vec::with_capacity(samples),
            j: Vec::with_capacity(samples),
            x: Vec::with_capacity(samples * dim),
        }
    }

    /// Builds an arc from its three arrays (`x` row-major, `t.len() * dim` entries), checking every
    /// hybrid-time-domain invariant.
    pub fn from_parts(
        dim: usize,
        t: Vec<f64>,
        j: Vec<usize>,
        x: Vec<f64>,
    ) -> Result<Self, SimError> {
        if j.len() != t.len() {
            return Err(InputError::mismatch("jump counters of the arc", t.len(), j.len()).into());
        }
        if x.len() != t.len() * dim {
            return Err(InputError::mismatch("states of the arc", t.len() * dim, x.len()).into());
        }
        let mut arc = Self::with_capacity(dim, t.len());
        for i in 0..t.len() {
            arc.push(t[i], j[i], &x[i * dim..(i + 1) * dim])?;
        }
        Ok(arc)
    }

    /// Appends a sample, enforcing the invariants of a hybrid time domain (see the module docs).
    pub fn push(&mut self, t: f64, j: usize, x: &[f64]) -> Result<(), SimError> {
        if x.len() != self.dim {
            return Err(InputError::mismatch("sample pushed to the arc", self.dim, x.len()).into());
        }
        if !t.is_finite() {
            return Err(InputError::non_finite("sample time").into());
        }
        check_finite_slice(x, "sample state")?;
        if let (Some(&t0), Some(&j0)) = (self.t.last(), self.j.last()) {
            let ok = if j == j0 {
                t >= t0
            } else {
                j == j0 + 1 && t == t0
            };
            if !ok {
                return Err(SimError::invalid(format!(
                    "sample ({t}, {j}) cannot follow ({t0}, {j0}) in a hybrid time domain"
                )));
            }
        }
        self.push_unchecked(t, j, x);
        Ok(())
    }

    /// Reserves room for `additional` more samples.
    pub fn reserve(&mut self, additional: usize) {
        self.t.reserve(additional);
        self.j.reserve(additional);
        self.x.reserve(additional * self.dim);
    }

    /// Appends without checks (the simulation driver guarantees the invariants).
    pub(crate) fn push_unchecked(&mut self, t: f64, j: usize, x: &[f64]) {
        debug_assert_eq!(x.len(), self.dim);
        self.t.push(t);
        self.j.push(j);
        self.x.extend_from_slice(x);
    }

    /// Dimension of the state space.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of stored samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// `true` when no sample is stored.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Sample times (nondecreasing).
    pub fn times(&self) -> &[f64] {
        &self.t
    }

    /// Jump counters of the samples.
    pub fn jump_counters(&self) -> &[usize] {
        &self.j
    }

    /// All states, row-major (`len() * dim()` entries).
    pub fn states_flat(&self) -> &[f64] {
        &self.x
    }

    /// State of sample `i` (panics if `i >= len()`, like slice indexing).
    pub fn state(&self, i: usize) -> &[f64] {
        &self.x[i * self.dim..(i + 1) * self.dim]
    }

    /// Hybrid time of sample `i` (panics if `i >= len()`).
    pub fn hybrid_time(&self, i: usize) -> HybridTime {
        HybridTime {
            t: self.t[i],
            j: self.j[i],
        }
    }

    /// Iterates over `(hybrid time, state)` pairs.
    pub fn iter(&self) -> impl Iterator<Item = (HybridTime, &[f64])> + '_ {
        (0..self.len()).map(move |i| (self.hybrid_time(i), self.state(i)))
    }

    /// Last sample, if any.
    pub fn last(&self) -> Option<(HybridTime, &[f64])> {
        self.len()
            .checked_sub(1)
            .map(|i| (self.hybrid_time(i), self.state(i)))
    }

    /// Number of jumps contained in the stored samples.
    pub fn num_jumps(&self) -> usize {
        match (self.j.first(), self.j.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0,
        }
    }

    /// The jumps of the arc, in order.
    pub fn jumps(&self) -> Vec<JumpRecord> {
        (1..self.len())
            .filter(|&i| self.j[i] == self.j[i - 1] + 1)
            .map(|i| JumpRecord {
                t: self.t[i],
                j_before: self.j[i - 1],
                before: i - 1,
                after: i,
            })
            .collect()
    }

    /// Jump instants `t_1, t_2, …`.
    pub fn jump_times(&self) -> Vec<f64> {
        self.jumps().into_iter().map(|r| r.t).collect()
    }

    /// The interval `[t_j, t_{j+1}]` of the hybrid time domain on which the counter equals `j`
    /// (restricted to the stored samples), or `None` if no sample has counter `j`.
    pub fn interval(&self, j: usize) -> Option<(f64, f64)> {
        let lo = self.j.partition_point(|&v| v < j);
        let hi = self.j.partition_point(|&v| v <= j);
        (lo < hi).then(|| (self.t[lo], self.t[hi - 1]))
    }

    /// Time series of component `k`.
    pub fn component(&self, k: usize) -> Result<Vec<f64>, SimError> {
        if k >= self.dim {
            return Err(SimError::invalid(format!(
                "component {k} of an arc of dimension {}",
                self.dim
            )));
        }
        Ok((0..self.len()).map(|i| self.x[i * self.dim + k]).collect())
    }

    /// Applies a scalar function (e.g. a norm or a Lyapunov function) to every stored state.
    pub fn map<F: FnMut(&[f64]) -> f64>(&self, mut f: F) -> Vec<f64> {
        (0..self.len()).map(|i| f(self.state(i))).collect()
    }

    /// Euclidean norm of every stored state.
    pub fn norms(&self) -> Vec<f64> {
        self.map(|x| x.iter().map(|v| v * v).sum::<f64>().sqrt())
    }

    /// The arc restricted to the components `range` (e.g. the observer part of a joint arc).
    pub fn select(&self, range: std::ops::Range<usize>) -> Result<HybridArc, SimError> {
        if range.start > range.end || range.end > self.dim {
            return Err(SimError::invalid(format!(
                "component range {range:?} of an arc of dimension {}",
                self.dim
            )));
        }
        let d = range.len();
        let mut out = HybridArc::with_capacity(d, self.len());
        for i in 0..self.len() {
            out.push_unchecked(self.t[i], self.j[i], &self.state(i)[range.clone()]);
        }
        Ok(out)
    }

    /// Projection onto ordinary time: the value at time `t`. At a jump instant `side` chooses the pre- or
    /// post-jump value (the first resp. last stored sample at that instant); strictly between two samples
    /// of the same flow interval the value is interpolated linearly, so it is exact at the stored samples
    /// and as accurate as the recording density elsewhere.
    pub fn value_at(&self, t: f64, side: JumpSide) -> Result<Vec<f64>, SimError> {
        if self.is_empty() {
            return Err(InputError::empty("hybrid arc").into());
        }
        if !t.is_finite() || t < self.t[0] || t > self.t[self.len() - 1] {
            return Err(SimError::invalid(format!(
                "time {t} outside the arc's range [{}, {}]",
                self.t[0],
                self.t[self.len() - 1]
            )));
        }
        let lo = self.t.partition_point(|&s| s < t);
        let hi = self.t.partition_point(|&s| s <= t);
        if lo < hi {
            let i = match side {
                JumpSide::Before => lo,
                JumpSide::After => hi - 1,
            };
            return Ok(self.state(i).to_vec());
        }
        // t[lo-1] < t < t[lo], same flow interval by the domain invariants.
        let (a, b) = (lo - 1, lo);
        let w = (t - self.t[a]) / (self.t[b] - self.t[a]);
        Ok(self
            .state(a)
            .iter()
            .zip(self.state(b))
            .map(|(xa, xb)| xa + w * (xb - xa))
            .collect())
    }

    /// Writes the arc as CSV: header `t,j,<names>` (default names `x0, x1, …`), one sample per line,
    /// numbers in Rust's shortest round-trip representation.
    pub fn write_csv<W: Write>(&self, mut w: W, names: Option<&[&str]>) -> Result<(), SimError> {
        if let Some(n) = names
            && n.len() != self.dim
        {
            return Err(InputError::mismatch("CSV column names", self.dim, n.len()).into());
        }
        let mut line = String::from("t,j");
        for k in 0..self.dim {
            line.push(',');
            match names {
                Some(n) => line.push_str(n[k]),
                None => line.push_str(&format!("x{k}")),
            }
        }
        writeln!(w, "{line}")?;
        for i in 0..self.len() {
            line.clear();
            line.push_str(&format!("{},{}", self.t[i], self.j[i]));
            for v in self.state(i) {
                line.push_str(&format!(",{v}"));
            }
            writeln!(w, "{line}")?;
        }
        Ok(())
    }

    /// Writes the arc as a CSV file (see [`HybridArc::write_csv`]).
    pub fn save_csv(&self, path: impl AsRef<Path>, names: Option<&[&str]>) -> Result<(), SimError> {
        let f = std::io::BufWriter::new(std::fs::File::create(path)?);
        self.write_csv(f, names)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_arc() -> HybridArc {
        let mut a = HybridArc::new(2);
        a.push(0.0, 0, &[1.0, 0.0]).unwrap();
        a.push(0.5, 0, &[2.0, 1.0]).unwrap();
        a.push(1.0, 0, &[3.0, 2.0]).unwrap();
        a.push(1.0, 1, &[0.0, 0.0]).unwrap();
        a.push(2.0, 1, &[1.0, 4.0]).unwrap();
        a
    }

    #[test]
    fn invariants_are_enforced() {
        let mut a = sample_arc();
        assert!(a.push(1.5, 1, &[0.0, 0.0]).is_err(), "time went backwards");
        assert!(
            a.push(2.5, 2, &[0.0, 0.0]).is_err(),
            "jump with time advance"
        );
        assert!(a.push(2.0, 3, &[0.0, 0.0]).is_err(), "j skipped");
        assert!(a.push(2.0, 1, &[0.0]).is_err(), "wrong dimension");
        assert!(a.push(2.0, 1, &[f64::NAN, 0.0]).is_err());
        assert!(a.push(2.0, 2, &[5.0, 5.0]).is_ok());
    }

    #[test]
    fn jumps_intervals_and_projection() {
        let a = sample_arc();
        assert_eq!(a.num_jumps(), 1);
        assert_eq!(a.jump_times(), vec![1.0]);
        assert_eq!(a.jumps()[0].before, 2);
        assert_eq!(a.interval(0), Some((0.0, 1.0)));
        assert_eq!(a.interval(1), Some((1.0, 2.0)));
        assert_eq!(a.interval(2), None);
        assert_eq!(a.value_at(1.0, JumpSide::Before).unwrap(), vec![3.0, 2.0]);
        assert_eq!(a.value_at(1.0, JumpSide::After).unwrap(), vec![0.0, 0.0]);
        assert_eq!(a.value_at(0.25, JumpSide::After).unwrap(), vec![1.5, 0.5]);
        assert_eq!(a.value_at(1.5, JumpSide::After).unwrap(), vec![0.5, 2.0]);
        assert!(a.value_at(2.5, JumpSide::After).is_err());
        assert_eq!(a.component(1).unwrap(), vec![0.0, 1.0, 2.0, 0.0, 4.0]);
        assert_eq!(a.select(1..2).unwrap().state(4), &[4.0]);
    }

    #[test]
    fn csv_round_trip_text() {
        let a = sample_arc();
        let mut buf = Vec::new();
        a.write_csv(&mut buf, Some(&["p", "v"])).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let lines: Vec<_> = text.lines().collect();
        assert_eq!(lines[0], "t,j,p,v");
        assert_eq!(lines[4], "1,1,0,0");
        assert_eq!(lines.len(), 6);
        let back: Vec<f64> = lines[2].split(',').map(|s| s.parse().unwrap()).collect();
        assert_eq!(back, vec![0.5, 0.0, 2.0, 1.0]);
    }
}
