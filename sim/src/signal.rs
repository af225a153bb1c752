//! Known input signals with an exact finite-dimensional representation, so that LTI flows driven by them
//! can be propagated exactly by one block-triangular exponential (Van Loan 1978): piecewise-constant
//! signals (zero-order hold: the held value is a state with zero derivative) and exosystem outputs
//! (`ẇ = S w`, `u = C w`, which covers constants, sinusoids and polynomials in `t`).

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::expm_scaled;
use sporadic_linalg::input::{check_finite, check_finite_slice};

use crate::error::SimError;
use crate::noise::NoiseSource;

/// A piecewise-constant signal `u(t) = v_k` for `s_k <= t < s_{k+1}` (the last value is held forever and
/// the first value is also used before `s_0`).
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseConstant {
    dim: usize,
    starts: Vec<f64>,
    values: Vec<f64>,
}

impl PiecewiseConstant {
    /// Builds the signal from strictly increasing segment start times and one value vector per segment.
    pub fn new(starts: Vec<f64>, values: Vec<Vec<f64>>) -> Result<Self, SimError> {
        if starts.is_empty() {
            return Err(InputError::empty("piecewise-constant signal").into());
        }
        if values.len() != starts.len() {
            return Err(InputError::mismatch(
                "piecewise-constant values",
                starts.len(),
                values.len(),
            )
            .into());
        }
        check_finite_slice(&starts, "piecewise-constant start times")?;
        if starts.windows(2).any(|w| w[1] <= w[0]) {
            return Err(SimError::invalid(
                "piecewise-constant start times must increase strictly",
            ));
        }
        let dim = values[0].len();
        let mut flat = Vec::with_capacity(dim * values.len());
        for (k, v) in values.iter().enumerate() {
            if v.len() != dim {
                return Err(InputError::mismatch(
                    format!("value {k} of the piecewise-constant signal"),
                    dim,
                    v.len(),
                )
                .into());
            }
            check_finite_slice(v, "piecewise-constant values")?;
            flat.extend_from_slice(v);
        }
        Ok(Self {
            dim,
            starts,
            values: flat,
        })
    }

    /// A constant signal.
    pub fn constant(value: Vec<f64>) -> Result<Self, SimError> {
        Self::new(vec![0.0], vec![value])
    }

    /// Samples `source` at `t0, t0 + period, …` (strictly before `horizon`) and holds each sample for one
    /// period, e.g. a random disturbance resampled every `period` seconds.
    pub fn sample_and_hold(
        source: &mut dyn NoiseSource,
        t0: f64,
        period: f64,
        horizon: f64,
    ) -> Result<Self, SimError> {
        if !(period > 0.0
            && period.is_finite()
            && t0.is_finite()
            && horizon.is_finite()
            && horizon > t0)
        {
            return Err(SimError::invalid(format!(
                "sample-and-hold needs period > 0 and t0 < horizon, got period {period}, [{t0}, {horizon}]"
            )));
        }
        let count = ((horizon - t0) / period).ceil() as usize;
        let mut starts = Vec::with_capacity(count);
        let mut values = Vec::with_capacity(count);
        for k in 0..count {
            let t = t0 + k as f64 * period;
            let mut v = vec![0.0; source.dim()];
            source.sample(t, &mut v);
            starts.push(t);
            values.push(v);
        }
        Self::new(starts, values)
    }

    /// Dimension of the values.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Index of the segment containing `t`.
    fn segment(&self, t: f64) -> usize {
        self.starts.partition_point(|&s| s <= t).saturating_sub(1)
    }

    /// The value at time `t` (right-continuous: at a switching time, the new value).
    pub fn value(&self, t: f64) -> &[f64] {
        let k = self.segment(t);
        &self.values[k * self.dim..(k + 1) * self.dim]
    }

    /// The left limit `u(t⁻)`: at a switching time `s_k` the value of the segment that ends there,
    /// elsewhere the same as [`PiecewiseConstant::value`]. This is the input of a flow interval that
    /// ends at `t`.
    pub fn left_limit(&self, t: f64) -> &[f64] {
        let k = self.starts.partition_point(|&s| s < t).saturating_sub(1);
        &self.values[k * self.dim..(k + 1) * self.dim]
    }

    /// The first switching time strictly after `t`, if any.
    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        let k = self.starts.partition_point(|&s| s <= t);
        self.starts.get(k).copied()
    }
}

/// An autonomous linear exosystem `ẇ = S w`, `w(t0) = w0`, with output `u = C w`.
#[derive(Debug, Clone)]
pub struct Exosystem {
    s: Mat<f64>,
    c: Mat<f64>,
    w0: Vec<f64>,
    t0: f64,
}

impl Exosystem {
    /// Builds the exosystem; `S` must be square, `C` must have as many columns as `S`.
    pub fn new(
        s: MatRef<'_, f64>,
        c: MatRef<'_, f64>,
        w0: Vec<f64>,
        t0: f64,
    ) -> Result<Self, SimError> {
        if s.nrows() != s.ncols() {
            return Err(InputError::mismatch(
                "columns of the exosystem matrix S",
                s.nrows(),
                s.ncols(),
            )
            .into());
        }
        if s.nrows() == 0 {
            return Err(InputError::empty("exosystem").into());
        }
        if c.ncols() != s.nrows() {
            return Err(InputError::mismatch(
                "columns of the exosystem output C",
                s.nrows(),
                c.ncols(),
            )
            .into());
        }
        if w0.len() != s.nrows() {
            return Err(
                InputError::mismatch("exosystem initial state", s.nrows(), w0.len()).into(),
            );
        }
        check_finite(s, "exosystem matrix S")?;
        check_finite(c, "exosystem output C")?;
        check_finite_slice(&w0, "exosystem initial state")?;
        if !t0.is_finite() {
            return Err(InputError::non_finite("exosystem initial time").into());
        }
        Ok(Self {
            s: s.to_owned(),
            c: c.to_owned(),
            w0,
            t0,
        })
    }

    /// The scalar signal `u(t) = Σ_i a_i sin(ω_i t + φ_i)` for `terms = [(a_i, ω_i, φ_i)]`, realised with
    /// `w_i = (sin(ω_i t + φ_i), cos(ω_i t + φ_i))`, `S_i = [[0, ω_i], [−ω_i, 0]]`, `C_i = [a_i, 0]`.
    pub fn sinusoid_sum(terms: &[(f64, f64, f64)]) -> Result<Self, SimError> {
        if terms.is_empty() {
            return Err(InputError::empty("sinusoid terms").into());
        }
        let m = 2 * terms.len();
        let mut s = Mat::<f64>::zeros(m, m);
        let mut c = Mat::<f64>::zeros(1, m);
        let mut w0 = vec![0.0; m];
        for (i, &(a, w, phi)) in terms.iter().enumerate() {
            s[(2 * i, 2 * i + 1)] = w;
            s[(2 * i + 1, 2 * i)] = -w;
            c[(0, 2 * i)] = a;
            w0[2 * i] = phi.sin();
            w0[2 * i + 1] = phi.cos();
        }
        Self::new(s.as_ref(), c.as_ref(), w0, 0.0)
    }

    /// Dimension of the exosystem state `w`.
    pub fn state_dim(&self) -> usize {
        self.s.nrows()
    }

    /// Dimension of the output `u`.
    pub fn output_dim(&self) -> usize {
        self.c.nrows()
    }

    /// The matrix `S`.
    pub fn s(&self) -> MatRef<'_, f64> {
        self.s.as_ref()
    }

    /// The output matrix `C`.
    pub fn c(&self) -> MatRef<'_, f64> {
        self.c.as_ref()
    }

    /// The exosystem state `w(t) = e^{S(t − t0)} w0`.
    pub fn state(&self, t: f64) -> Result<Vec<f64>, SimError> {
        let e = expm_scaled(self.s.as_ref(), t - self.t0)?;
        let n = self.state_dim();
        Ok((0..n)
            .map(|i| (0..n).map(|k| e[(i, k)] * self.w0[k]).sum())
            .collect())
    }

    /// The output `u(t) = C w(t)`.
    pub fn value(&self, t: f64) -> Result<Vec<f64>, SimError> {
        let w = self.state(t)?;
        Ok((0..self.output_dim())
            .map(|i| (0..w.len()).map(|k| self.c[(i, k)] * w[k]).sum())
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::BoundedUniform;

    #[test]
    fn piecewise_constant_lookup() {
        let p = PiecewiseConstant::new(vec![0.0, 1.0, 2.5], vec![vec![1.0], vec![2.0], vec![3.0]])
            .unwrap();
        assert_eq!(p.value(-1.0), &[1.0]);
        assert_eq!(p.value(0.99), &[1.0]);
        assert_eq!(p.value(1.0), &[2.0]);
        assert_eq!(p.value(7.0), &[3.0]);
        // Left limits: the previous segment's value exactly at a switch, the value elsewhere.
        assert_eq!(p.left_limit(1.0), &[1.0]);
        assert_eq!(p.left_limit(2.5), &[2.0]);
        assert_eq!(p.left_limit(1.7), &[2.0]);
        assert_eq!(p.left_limit(0.0), &[1.0]);
        assert_eq!(p.left_limit(-3.0), &[1.0]);
        assert_eq!(p.left_limit(1f64.next_up()), &[2.0]);
        assert_eq!(p.next_breakpoint(0.0), Some(1.0));
        assert_eq!(p.next_breakpoint(1.0), Some(2.5));
        assert_eq!(p.next_breakpoint(2.5), None);
        assert!(PiecewiseConstant::new(vec![0.0, 0.0], vec![vec![1.0], vec![2.0]]).is_err());
        assert!(PiecewiseConstant::new(vec![0.0], vec![vec![f64::NAN]]).is_err());
    }

    #[test]
    fn sample_and_hold_stays_in_bounds() {
        let mut src = BoundedUniform::symmetric(vec![1.0, 0.5], 3).unwrap();
        let p = PiecewiseConstant::sample_and_hold(&mut src, 0.0, 0.1, 1.0).unwrap();
        assert_eq!(p.starts.len(), 10);
        for k in 0..10 {
            let v = p.value(0.1 * k as f64 + 0.05);
            assert!(v[0].abs() <= 1.0 && v[1].abs() <= 0.5);
        }
    }

    #[test]
    fn sinusoid_exosystem_matches_closed_form() {
        let exo = Exosystem::sinusoid_sum(&[(20.0, 10.0, 0.0), (10.0, 16.0, 0.3)]).unwrap();
        for &t in &[0.0, 0.37, 1.9, 4.2] {
            let u = exo.value(t).unwrap()[0];
            let expected = 20.0 * (10.0 * t).sin() + 10.0 * (16.0 * t + 0.3).sin();
            assert!(
                (u - expected).abs() < 1e-11 * 30.0,
                "t = {t}: {u} vs {expected}"
            );
        }
    }
}
