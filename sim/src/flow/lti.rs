//! Exact propagation of linear time-invariant flows `ẋ = A x + Σ_i B_i u_i(t) + c`.
//!
//! Each known input `u_i` is either piecewise constant (zero-order hold) or the output of an exosystem
//! `ẇ = S w`, `u = C w`. Appending the input states and a constant `1` to `x` gives the autonomous
//! block-upper-triangular system `ż = Ā z`,
//!
//! ```text
//!     Ā = [ A   B_1 C_1   B_2   c ]     z = (x, w_1, u_2, 1)
//!         [ 0   S_1       0     0 ]
//!         [ 0   0         0     0 ]
//!         [ 0   0         0     0 ]
//! ```
//!
//! whose transition `e^{Āτ}` contains `e^{Aτ}` and the Van Loan (1978) input integrals
//! `∫₀^τ e^{As} B ds` etc. in its first block row. Between switching times of the piecewise-constant
//! inputs the flow is therefore exactly `z(t+τ) = e^{Āτ} z(t)`.
//!
//! [`TransitionTable`] applies `e^{Āτ}` to vectors for arbitrary `τ` at the cost of a few matrix–vector
//! products: with `h = 1/‖Ā‖₁` and `τ = k h + i h/64 + δ` (`0 <= δ < h/64`),
//! `e^{Āτ} = e^{Ākh} e^{Āih/64} e^{Āδ}`; the first two factors are tabulated (each entry computed
//! independently by [`sporadic_linalg::expm_scaled`], so there is no error accumulation), and
//! `e^{Āδ} v` is a degree-6 Taylor polynomial, whose truncation error is below
//! `θ⁷/7! · e^θ ≈ 4.6e-17` relative for `θ = ‖Āδ‖₁ <= 1/64` (the truncated-Taylor idea of
//! Al-Mohy & Higham, "Computing the action of the matrix exponential", SISC 33(2), 2011).

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_len;
use sporadic_linalg::input::{check_finite, check_finite_slice};
use sporadic_linalg::{expm_scaled, zoh};

use super::Flow;
use crate::error::SimError;
use crate::signal::{Exosystem, PiecewiseConstant};

/// A known input signal with an exact finite-dimensional realisation.
#[derive(Debug, Clone)]
pub enum InputSignal {
    /// Piecewise-constant (zero-order-hold) input.
    PiecewiseConstant(PiecewiseConstant),
    /// Output of a linear exosystem.
    Exosystem(Exosystem),
}

impl InputSignal {
    fn dim(&self) -> usize {
        match self {
            Self::PiecewiseConstant(p) => p.dim(),
            Self::Exosystem(e) => e.output_dim(),
        }
    }

    /// Dimension of the state this signal contributes to the augmented system.
    fn state_dim(&self) -> usize {
        match self {
            Self::PiecewiseConstant(p) => p.dim(),
            Self::Exosystem(e) => e.state_dim(),
        }
    }

    fn next_breakpoint(&self, t: f64) -> Option<f64> {
        match self {
            Self::PiecewiseConstant(p) => p.next_breakpoint(t),
            Self::Exosystem(_) => None,
        }
    }
}

#[derive(Debug, Clone)]
struct Channel {
    b: Mat<f64>,
    signal: InputSignal,
}

/// An LTI flow `ẋ = A x + Σ_i B_i u_i(t) + c` with known inputs.
#[derive(Debug, Clone)]
pub struct LtiFlow {
    a: Mat<f64>,
    channels: Vec<Channel>,
    affine: Option<Vec<f64>>,
}

impl LtiFlow {
    /// The homogeneous flow `ẋ = A x` (`A` square, non-empty, finite).
    pub fn new(a: MatRef<'_, f64>) -> Result<Self, SimError> {
        if a.nrows() != a.ncols() {
            return Err(
                InputError::mismatch("columns of the flow matrix A", a.nrows(), a.ncols()).into(),
            );
        }
        if a.nrows() == 0 {
            return Err(InputError::empty("flow matrix A").into());
        }
        check_finite(a, "flow matrix A")?;
        Ok(Self {
            a: a.to_owned(),
            channels: Vec::new(),
            affine: None,
        })
    }

    /// Adds an input channel `B u(t)` (`B` is `n × dim(u)`).
    pub fn with_input(mut self, b: MatRef<'_, f64>, signal: InputSignal) -> Result<Self, SimError> {
        if b.nrows() != self.dim() {
            return Err(
                InputError::mismatch("rows of the input matrix B", self.dim(), b.nrows()).into(),
            );
        }
        if b.ncols() != signal.dim() {
            return Err(InputError::mismatch(
                "columns of the input matrix B",
                signal.dim(),
                b.ncols(),
            )
            .into());
        }
        check_finite(b, "input matrix B")?;
        self.channels.push(Channel {
            b: b.to_owned(),
            signal,
        });
        Ok(self)
    }

    /// Adds a constant term `c` (e.g. the disturbance bounds `d̲`, `d̄` of an interval observer).
    pub fn with_affine(mut self, c: Vec<f64>) -> Result<Self, SimError> {
        check_len(&c, self.dim(), "affine term c")?;
        check_finite_slice(&c, "affine term c")?;
        self.affine = Some(c);
        Ok(self)
    }

    /// The state matrix `A`.
    pub fn a(&self) -> MatRef<'_, f64> {
        self.a.as_ref()
    }

    /// `true` when the flow is `ẋ = A x` (no inputs, no constant term).
    pub fn is_homogeneous(&self) -> bool {
        self.channels.is_empty() && self.affine.is_none()
    }

    /// The homogeneous transition matrix `e^{Aτ}`.
    pub fn transition(&self, tau: f64) -> Result<Mat<f64>, SimError> {
        Ok(expm_scaled(self.a.as_ref(), tau)?)
    }

    /// The zero-order-hold discretisation `(e^{Aτ}, ∫₀^τ e^{As} ds B_i)` of input channel `i`
    /// (Van Loan 1978; computed by [`sporadic_linalg::zoh`]).
    pub fn zoh(&self, channel: usize, tau: f64) -> Result<(Mat<f64>, Mat<f64>), SimError> {
        let ch = self.channels.get(channel).ok_or_else(|| {
            SimError::invalid(format!(
                "input channel {channel} of a flow with {} channels",
                self.channels.len()
            ))
        })?;
        Ok(zoh(self.a.as_ref(), ch.b.as_ref(), tau)?)
    }

    /// Dimension of the augmented state `z = (x, input states, 1)`.
    pub fn augmented_dim(&self) -> usize {
        self.dim()
            + self
                .channels
                .iter()
                .map(|c| c.signal.state_dim())
                .sum::<usize>()
            + usize::from(self.affine.is_some())
    }

    /// The augmented matrix `Ā` of the module documentation.
    pub fn augmented_matrix(&self) -> Mat<f64> {
        let n = self.dim();
        let m = self.augmented_dim();
        let mut abar = Mat::<f64>::zeros(m, m);
        abar.as_mut().submatrix_mut(0, 0, n, n).copy_from(&self.a);
        let mut off = n;
        for ch in &self.channels {
            match &ch.signal {
                InputSignal::PiecewiseConstant(p) => {
                    abar.as_mut()
                        .submatrix_mut(0, off, n, p.dim())
                        .copy_from(&ch.b);
                    off += p.dim();
                }
                InputSignal::Exosystem(e) => {
                    let k = e.state_dim();
                    let bc = &ch.b * e.c();
                    abar.as_mut().submatrix_mut(0, off, n, k).copy_from(&bc);
                    abar.as_mut().submatrix_mut(off, off, k, k).copy_from(e.s());
                    off += k;
                }
            }
        }
        if let Some(c) = &self.affine {
            for i in 0..n {
                abar[(i, off)] = c[i];
            }
        }
        abar
    }

    /// An exact propagator for this flow.
    pub fn propagator(&self) -> Result<LtiPropagator, SimError> {
        LtiPropagator::new(self.clone())
    }

    /// One-shot exact propagation: the state at `t + tau` of the solution through `x` at `t`.
    pub fn propagate(&self, t: f64, x: &[f64], tau: f64) -> Result<Vec<f64>, SimError> {
        let mut p = self.propagator()?;
        let mut out = x.to_vec();
        p.advance(t, &mut out, tau)?;
        Ok(out)
    }

    /// `A x + Σ B_i u_i + c` with the piecewise-constant inputs at `t` (`left`: their left limits).
    fn eval(&self, t: f64, left: bool, x: &[f64], dx: &mut [f64]) {
        let n = self.dim();
        for i in 0..n {
            let mut s = self.affine.as_ref().map_or(0.0, |c| c[i]);
            for k in 0..n {
                s += self.a[(i, k)] * x[k];
            }
            dx[i] = s;
        }
        for ch in &self.channels {
            let owned;
            let u: &[f64] = match &ch.signal {
                InputSignal::PiecewiseConstant(p) if left => p.left_limit(t),
                InputSignal::PiecewiseConstant(p) => p.value(t),
                InputSignal::Exosystem(e) => match e.value(t) {
                    Ok(v) => {
                        owned = v;
                        &owned
                    }
                    Err(_) => {
                        dx.fill(f64::NAN);
                        return;
                    }
                },
            };
            for i in 0..n {
                dx[i] += (0..u.len()).map(|k| ch.b[(i, k)] * u[k]).sum::<f64>();
            }
        }
    }
}

impl Flow for LtiFlow {
    fn dim(&self) -> usize {
        self.a.nrows()
    }

    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        self.eval(t, false, x, dx);
    }

    /// Exact left limit: piecewise-constant inputs take the value of the segment that ends at `t`.
    fn rhs_left(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        self.eval(t, true, x, dx);
    }

    fn next_breakpoint(&self, t: f64) -> Option<f64> {
        self.channels
            .iter()
            .filter_map(|c| c.signal.next_breakpoint(t))
            .reduce(f64::min)
    }

    fn as_lti(&self) -> Option<&LtiFlow> {
        Some(self)
    }
}

/// Number of fine subdivisions of the coarse step `h = 1/‖Ā‖₁`.
const SUB: usize = 64;
/// Degree of the Taylor polynomial for the remainder `e^{Āδ}`, `‖Āδ‖₁ <= 1/SUB`.
const TAYLOR_DEGREE: usize = 6;
/// Largest tabulated multiple of `h`; longer times are split into chunks.
const MAX_COARSE: usize = 4096;

/// Applies `e^{Āτ}` to vectors for arbitrary `τ >= 0` (see the module documentation for the method and
/// its error bound). Table entries are computed lazily, on first use.
#[derive(Debug, Clone)]
pub struct TransitionTable {
    n: usize,
    a: Mat<f64>,
    a_cm: Vec<f64>,
    h: f64,
    coarse: Vec<Option<Vec<f64>>>,
    fine: Vec<Vec<f64>>,
}

/// Column-major copy of a matrix (entry `(i, j)` at `j * nrows + i`).
fn col_major(m: MatRef<'_, f64>) -> Vec<f64> {
    let mut v = Vec::with_capacity(m.nrows() * m.ncols());
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            v.push(m[(i, j)]);
        }
    }
    v
}

/// Dispatches `$f::<N>` for orders up to 16 (fully unrolled fixed-size code) and `$dynf` otherwise.
macro_rules! dispatch {
    ($n:expr, $f:ident, $dynf:ident, ($($arg:expr),*)) => {
        match $n {
            1 => $f::<1>($($arg),*),
            2 => $f::<2>($($arg),*),
            3 => $f::<3>($($arg),*),
            4 => $f::<4>($($arg),*),
            5 => $f::<5>($($arg),*),
            6 => $f::<6>($($arg),*),
            7 => $f::<7>($($arg),*),
            8 => $f::<8>($($arg),*),
            9 => $f::<9>($($arg),*),
            10 => $f::<10>($($arg),*),
            11 => $f::<11>($($arg),*),
            12 => $f::<12>($($arg),*),
            13 => $f::<13>($($arg),*),
            14 => $f::<14>($($arg),*),
            15 => $f::<15>($($arg),*),
            16 => $f::<16>($($arg),*),
            n => $dynf(n, $($arg),*),
        }
    };
}

/// `v ← M v` for a column-major `n × n` matrix `M`, as a sum of scaled columns (the inner loop runs over
/// rows without a reduction, so it vectorises).
fn matvec(n: usize, m: &[f64], v: &mut [f64]) {
    dispatch!(n, matvec_fixed, matvec_dyn, (m, v));
}

#[inline(always)]
fn matvec_fixed<const N: usize>(m: &[f64], v: &mut [f64]) {
    let mut acc = [0.0; N];
    for (col, &vk) in m.chunks_exact(N).zip(v.iter()) {
        for i in 0..N {
            acc[i] += col[i] * vk;
        }
    }
    v.copy_from_slice(&acc);
}

fn matvec_dyn(n: usize, m: &[f64], v: &mut [f64]) {
    let mut acc = vec![0.0; n];
    for (col, &vk) in m.chunks_exact(n).zip(v.iter()) {
        for (o, c) in acc.iter_mut().zip(col) {
            *o += c * vk;
        }
    }
    v.copy_from_slice(&acc);
}

/// `v ← Σ_{d=0}^{TAYLOR_DEGREE} (Aδ)^d v / d!` for a column-major `A`.
fn taylor(n: usize, a: &[f64], delta: f64, v: &mut [f64]) {
    dispatch!(n, taylor_fixed, taylor_dyn, (a, delta, v));
}

#[inline(always)]
fn taylor_fixed<const N: usize>(a: &[f64], delta: f64, v: &mut [f64]) {
    let mut term = [0.0; N];
    term.copy_from_slice(v);
    let mut sum = term;
    for d in 1..=TAYLOR_DEGREE {
        let f = delta / d as f64;
        let mut next = [0.0; N];
        for (col, &tk) in a.chunks_exact(N).zip(term.iter()) {
            let s = tk * f;
            for i in 0..N {
                next[i] += col[i] * s;
            }
        }
        term = next;
        for i in 0..N {
            sum[i] += term[i];
        }
    }
    v.copy_from_slice(&sum);
}

fn taylor_dyn(n: usize, a: &[f64], delta: f64, v: &mut [f64]) {
    let mut term = v.to_vec();
    for d in 1..=TAYLOR_DEGREE {
        matvec_dyn(n, a, &mut term);
        let f = delta / d as f64;
        for (x, t) in v.iter_mut().zip(term.iter_mut()) {
            *t *= f;
            *x += *t;
        }
    }
}

impl TransitionTable {
    /// Prepares the table for `Ā` (square, non-empty, finite).
    pub fn new(a: MatRef<'_, f64>) -> Result<Self, SimError> {
        if a.nrows() != a.ncols() {
            return Err(InputError::mismatch(
                "columns of the transition generator",
                a.nrows(),
                a.ncols(),
            )
            .into());
        }
        if a.nrows() == 0 {
            return Err(InputError::empty("transition generator").into());
        }
        check_finite(a, "transition generator")?;
        let n = a.nrows();
        let norm1 = (0..n)
            .map(|j| (0..n).map(|i| a[(i, j)].abs()).sum::<f64>())
            .fold(0.0, f64::max);
        let h = if norm1 > 0.0 { 1.0 / norm1 } else { 0.0 };
        let mut fine = Vec::with_capacity(SUB);
        if h > 0.0 {
            for i in 0..SUB {
                fine.push(col_major(
                    expm_scaled(a, i as f64 * h / SUB as f64)?.as_ref(),
                ));
            }
        }
        Ok(Self {
            n,
            a: a.to_owned(),
            a_cm: col_major(a),
            h,
            coarse: Vec::new(),
            fine,
        })
    }

    /// Dimension of the vectors the table acts on.
    pub fn dim(&self) -> usize {
        self.n
    }

    fn coarse_entry(&mut self, k: usize) -> Result<&[f64], SimError> {
        if self.coarse.len() <= k {
            self.coarse.resize(k + 1, None);
        }
        if self.coarse[k].is_none() {
            let e = expm_scaled(self.a.as_ref(), k as f64 * self.h)?;
            check_finite(e.as_ref(), "tabulated transition matrix")?;
            self.coarse[k] = Some(col_major(e.as_ref()));
        }
        Ok(self.coarse[k].as_deref().unwrap_or_default())
    }

    /// Overwrites `v` with `e^{Āτ} v`.
    pub fn apply(&mut self, tau: f64, v: &mut [f64]) -> Result<(), SimError> {
        check_len(v, self.n, "vector propagated by the transition table")?;
        if !(tau >= 0.0 && tau.is_finite()) {
            return Err(SimError::invalid(format!(
                "propagation time must be finite and >= 0, got {tau}"
            )));
        }
        if self.h == 0.0 || tau == 0.0 {
            return Ok(());
        }
        let n = self.n;
        let hf = self.h / SUB as f64;
        let mut k = (tau / self.h).floor() as usize;
        let r = (tau - k as f64 * self.h).max(0.0);
        let i = ((r / hf).floor() as usize).min(SUB - 1);
        let delta = (r - i as f64 * hf).max(0.0);
        if delta > 0.0 {
            taylor(n, &self.a_cm, delta, v);
        }
        if i > 0 {
            matvec(n, &self.fine[i], v);
        }
        while k > 0 {
            let step = k.min(MAX_COARSE);
            matvec(n, self.coarse_entry(step)?, v);
            k -= step;
        }
        Ok(())
    }
}

/// Number of propagation segments after which a tracked exosystem state is recomputed from scratch.
const EXO_REANCHOR: usize = 128;

#[derive(Debug, Clone)]
struct ExoTrack {
    t: f64,
    w: Vec<f64>,
    uses: usize,
}

/// Exact propagator of an [`LtiFlow`]: `advance(t, x, τ)` maps `x(t)` to `x(t + τ)`, stopping at the
/// switching times of piecewise-constant inputs. The exosystem states are tracked between calls (and
/// recomputed from `w(t0)` every few segments or whenever the propagator is moved to another time).
#[derive(Debug, Clone)]
pub struct LtiPropagator {
    flow: LtiFlow,
    table: TransitionTable,
    z: Vec<f64>,
    tracks: Vec<Option<ExoTrack>>,
}

impl LtiPropagator {
    /// Builds the propagator (tabulates the fine transition matrices).
    pub fn new(flow: LtiFlow) -> Result<Self, SimError> {
        let table = TransitionTable::new(flow.augmented_matrix().as_ref())?;
        let z = vec![0.0; flow.augmented_dim()];
        let tracks = vec![None; flow.channels.len()];
        Ok(Self {
            flow,
            table,
            z,
            tracks,
        })
    }

    /// The propagated flow.
    pub fn flow(&self) -> &LtiFlow {
        &self.flow
    }

    /// Overwrites `x` (the state at time `t`) with the state at time `t + tau`.
    pub fn advance(&mut self, t: f64, x: &mut [f64], tau: f64) -> Result<(), SimError> {
        let n = self.flow.dim();
        check_len(x, n, "state propagated by the LTI flow")?;
        if !(tau >= 0.0 && tau.is_finite() && t.is_finite()) {
            return Err(SimError::invalid(format!(
                "cannot propagate from t = {t} by tau = {tau}"
            )));
        }
        if self.flow.is_homogeneous() {
            return self.table.apply(tau, x);
        }
        let end = t + tau;
        let mut tc = t;
        while tc < end {
            let seg_end = match self.flow.next_breakpoint(tc) {
                Some(b) if b < end => b,
                _ => end,
            };
            self.fill(tc, x)?;
            self.table.apply(seg_end - tc, &mut self.z)?;
            x.copy_from_slice(&self.z[..n]);
            self.store_tracks(seg_end);
            tc = seg_end;
        }
        Ok(())
    }

    fn fill(&mut self, t: f64, x: &[f64]) -> Result<(), SimError> {
        let n = x.len();
        self.z[..n].copy_from_slice(x);
        let mut off = n;
        for (c, ch) in self.flow.channels.iter().enumerate() {
            match &ch.signal {
                InputSignal::PiecewiseConstant(p) => {
                    let d = p.dim();
                    self.z[off..off + d].copy_from_slice(p.value(t));
                    off += d;
                }
                InputSignal::Exosystem(e) => {
                    let d = e.state_dim();
                    let fresh = match &self.tracks[c] {
                        Some(tr) => tr.t != t || tr.uses >= EXO_REANCHOR,
                        None => true,
                    };
                    if fresh {
                        self.tracks[c] = Some(ExoTrack {
                            t,
                            w: e.state(t)?,
                            uses: 0,
                        });
                    }
                    if let Some(tr) = &self.tracks[c] {
                        self.z[off..off + d].copy_from_slice(&tr.w);
                    }
                    off += d;
                }
            }
        }
        if self.flow.affine.is_some() {
            self.z[off] = 1.0;
        }
        Ok(())
    }

    fn store_tracks(&mut self, t: f64) {
        let mut off = self.flow.dim();
        for (c, ch) in self.flow.channels.iter().enumerate() {
            let d = ch.signal.state_dim();
            if let (InputSignal::Exosystem(_), Some(tr)) = (&ch.signal, self.tracks[c].as_mut()) {
                tr.t = t;
                tr.w.copy_from_slice(&self.z[off..off + d]);
                tr.uses += 1;
            }
            off += d;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn table_matches_closed_form_rotation() {
        // e^{Aτ} for A = [[0, w], [-w, 0]] is a rotation by wτ.
        let w = 3.0;
        let a = mat![[0.0, w], [-w, 0.0]];
        let mut tab = TransitionTable::new(a.as_ref()).unwrap();
        for &tau in &[0.0, 1e-9, 0.0123, 0.31, 1.0, 2.75, 40.0] {
            let mut v = [1.0, 0.5];
            tab.apply(tau, &mut v).unwrap();
            let (c, s) = ((w * tau).cos(), (w * tau).sin());
            let expect = [c + 0.5 * s, -s + 0.5 * c];
            for k in 0..2 {
                assert!(
                    (v[k] - expect[k]).abs() < 1e-13,
                    "tau {tau}: {v:?} vs {expect:?}"
                );
            }
        }
        assert!(tab.apply(-1.0, &mut [0.0, 0.0]).is_err());
        assert!(tab.apply(f64::NAN, &mut [0.0, 0.0]).is_err());
    }

    #[test]
    fn zero_matrix_is_identity() {
        let mut tab = TransitionTable::new(Mat::<f64>::zeros(3, 3).as_ref()).unwrap();
        let mut v = [1.0, 2.0, 3.0];
        tab.apply(5.0, &mut v).unwrap();
        assert_eq!(v, [1.0, 2.0, 3.0]);
    }

    #[test]
    fn double_integrator_with_constant_input() {
        // ẍ = u with u = 2 constant: x(t) = x0 + v0 t + t², v(t) = v0 + 2t.
        let a = mat![[0.0, 1.0], [0.0, 0.0]];
        let b = mat![[0.0], [1.0]];
        let flow = LtiFlow::new(a.as_ref())
            .unwrap()
            .with_input(
                b.as_ref(),
                InputSignal::PiecewiseConstant(PiecewiseConstant::constant(vec![2.0]).unwrap()),
            )
            .unwrap();
        let x = flow.propagate(0.0, &[1.0, -1.0], 1.7).unwrap();
        assert!((x[0] - (1.0 - 1.7 + 1.7 * 1.7)).abs() < 1e-13);
        assert!((x[1] - (-1.0 + 3.4)).abs() < 1e-13);
    }

    #[test]
    fn left_limit_at_a_switch() {
        // ẋ = −x + u, u = 1 on [0, 1), 3 after: at t = 1 the right value uses 3, the left limit 1.
        let u = PiecewiseConstant::new(vec![0.0, 1.0], vec![vec![1.0], vec![3.0]]).unwrap();
        let flow = LtiFlow::new(mat![[-1.0]].as_ref())
            .unwrap()
            .with_input(mat![[1.0]].as_ref(), InputSignal::PiecewiseConstant(u))
            .unwrap();
        let (mut right, mut left) = ([0.0], [0.0]);
        flow.rhs(1.0, &[0.5], &mut right);
        flow.rhs_left(1.0, &[0.5], &mut left);
        assert_eq!((right[0], left[0]), (2.5, 0.5));
        // Away from switches both agree; the trait's default (rhs one ulp earlier) agrees with the
        // exact override at the switch.
        flow.rhs_left(0.5, &[0.5], &mut left);
        flow.rhs(0.5, &[0.5], &mut right);
        assert_eq!(left, right);
        let mut shifted = [0.0];
        flow.rhs(1f64.next_down(), &[0.5], &mut shifted);
        assert_eq!(shifted[0], 0.5);
    }

    #[test]
    fn invalid_inputs_are_rejected() {
        assert!(LtiFlow::new(Mat::<f64>::zeros(2, 3).as_ref()).is_err());
        assert!(LtiFlow::new(mat![[f64::NAN]].as_ref()).is_err());
        let flow = LtiFlow::new(mat![[1.0]].as_ref()).unwrap();
        assert!(flow.clone().with_affine(vec![1.0, 2.0]).is_err());
        let p =
            InputSignal::PiecewiseConstant(PiecewiseConstant::constant(vec![1.0, 2.0]).unwrap());
        assert!(flow.clone().with_input(mat![[1.0]].as_ref(), p).is_err());
        assert!(flow.propagate(0.0, &[1.0, 2.0], 1.0).is_err());
    }
}
