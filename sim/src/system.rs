//! Observer-agnostic interfaces: a plant is a flow plus an output map read at the sampling instants; an
//! observer is a flow plus a jump map that consumes the measurement. Together with a
//! [`crate::SamplingRule`] they form the hybrid closed loop simulated by [`crate::simulate()`].
//!
//! Ready-made parts cover the linear case of the papers: linear sampled outputs `y = C_σ x + v`
//! ([`LinearOutputs`]), the Luenberger-type correction `x̂⁺ = x̂ + L_σ(τ)(y − C_σ x̂)` with a constant or
//! interval-dependent gain ([`LinearCorrection`]; Ferrante et al. 2016 (3), Sferlazza et al. 2021 (11b),
//! Etienne et al. 2017 (3)), and the linear reset `x⁺ = J x` of an error system ([`LinearJump`]).
//! Nonlinear and interval observers plug in through closures or their own trait implementations.

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite;

use crate::error::SimError;
use crate::flow::{EmptyFlow, Flow};
use crate::noise::NoiseSource;

/// Information about one sample, passed to output and jump maps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleEvent {
    /// Sampling instant `t_k`.
    pub t: f64,
    /// Jump counter before this sample (the `k − 1` of `t_k` when samples are counted from 1).
    pub j: usize,
    /// Sensor that delivers the measurement.
    pub sensor: usize,
    /// Time elapsed since the previous sample (or since the start): the `τ` of `L_σ(τ)`.
    pub elapsed: f64,
}

/// An output map read at the sampling instants.
pub trait Output {
    /// Writes the measurement `y` of `x` at the sample `ev` (`y` is cleared by the caller).
    fn measure(&mut self, ev: &SampleEvent, x: &[f64], y: &mut Vec<f64>) -> Result<(), SimError>;
}

impl<G: FnMut(&SampleEvent, &[f64], &mut Vec<f64>) -> Result<(), SimError>> Output for G {
    fn measure(&mut self, ev: &SampleEvent, x: &[f64], y: &mut Vec<f64>) -> Result<(), SimError> {
        self(ev, x, y)
    }
}

/// A jump map `x⁺ = g(x, y)` applied at the sampling instants.
pub trait Jump {
    /// Overwrites `x` with its post-jump value, given the measurement `y`.
    fn jump(&mut self, ev: &SampleEvent, y: &[f64], x: &mut [f64]) -> Result<(), SimError>;
}

impl<G: FnMut(&SampleEvent, &[f64], &mut [f64]) -> Result<(), SimError>> Jump for G {
    fn jump(&mut self, ev: &SampleEvent, y: &[f64], x: &mut [f64]) -> Result<(), SimError> {
        self(ev, y, x)
    }
}

/// A plant: flows continuously and is measured at the sampling instants.
pub trait Plant {
    /// The plant's flow.
    fn flow(&self) -> &dyn Flow;
    /// Measurement at a sample.
    fn measure(&mut self, ev: &SampleEvent, x: &[f64], y: &mut Vec<f64>) -> Result<(), SimError>;
    /// Reset of the plant at a sample (default: none).
    fn jump(&mut self, _ev: &SampleEvent, _x: &mut [f64]) -> Result<(), SimError> {
        Ok(())
    }
}

/// An observer: flows between samples and jumps when a measurement arrives.
pub trait Observer {
    /// The observer's flow.
    fn flow(&self) -> &dyn Flow;
    /// Correction at a sample, given the measurement `y`.
    fn jump(&mut self, ev: &SampleEvent, y: &[f64], xhat: &mut [f64]) -> Result<(), SimError>;
}

/// A plant assembled from a flow and an output map.
pub struct SampledPlant<F, H> {
    /// The flow.
    pub flow: F,
    /// The output map.
    pub output: H,
}

impl<F: Flow, H: Output> Plant for SampledPlant<F, H> {
    fn flow(&self) -> &dyn Flow {
        &self.flow
    }
    fn measure(&mut self, ev: &SampleEvent, x: &[f64], y: &mut Vec<f64>) -> Result<(), SimError> {
        self.output.measure(ev, x, y)
    }
}

/// An observer assembled from a flow and a jump map.
pub struct HybridObserver<F, J> {
    /// The flow.
    pub flow: F,
    /// The jump map.
    pub jump: J,
}

impl<F: Flow, J: Jump> Observer for HybridObserver<F, J> {
    fn flow(&self) -> &dyn Flow {
        &self.flow
    }
    fn jump(&mut self, ev: &SampleEvent, y: &[f64], xhat: &mut [f64]) -> Result<(), SimError> {
        self.jump.jump(ev, y, xhat)
    }
}

/// The empty plant, for simulating a closed hybrid system (e.g. an error system) on its own.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoPlant;

impl Plant for NoPlant {
    fn flow(&self) -> &dyn Flow {
        &EmptyFlow
    }
    fn measure(
        &mut self,
        _ev: &SampleEvent,
        _x: &[f64],
        _y: &mut Vec<f64>,
    ) -> Result<(), SimError> {
        Ok(())
    }
}

fn check_output_matrices(c: &[Mat<f64>], what: &str) -> Result<usize, SimError> {
    let first = c.first().ok_or_else(|| InputError::empty(what))?;
    let n = first.ncols();
    for (s, m) in c.iter().enumerate() {
        if m.ncols() != n {
            return Err(
                InputError::mismatch(format!("columns of {what} {s}"), n, m.ncols()).into(),
            );
        }
        check_finite(m.as_ref(), what)?;
    }
    Ok(n)
}

#[inline]
fn mat_vec_into(m: MatRef<'_, f64>, x: &[f64], out: &mut Vec<f64>) {
    out.extend((0..m.nrows()).map(|i| (0..m.ncols()).map(|k| m[(i, k)] * x[k]).sum::<f64>()));
}

/// Linear sampled outputs `y = C_σ x + v_σ(t)` with optional per-sensor noise.
pub struct LinearOutputs {
    c: Vec<Mat<f64>>,
    noise: Vec<Option<Box<dyn NoiseSource>>>,
    buf: Vec<f64>,
}

impl LinearOutputs {
    /// One output matrix per sensor (all with the plant's number of columns).
    pub fn new(c: Vec<Mat<f64>>) -> Result<Self, SimError> {
        check_output_matrices(&c, "output matrix")?;
        let noise = c.iter().map(|_| None).collect();
        Ok(Self {
            c,
            noise,
            buf: Vec::new(),
        })
    }

    /// Adds noise to the measurements of `sensor` (dimension must match the sensor's outputs).
    pub fn with_noise(
        mut self,
        sensor: usize,
        noise: Box<dyn NoiseSource>,
    ) -> Result<Self, SimError> {
        let c = self.c.get(sensor).ok_or_else(|| {
            SimError::invalid(format!("sensor {sensor} of {} sensors", self.c.len()))
        })?;
        if noise.dim() != c.nrows() {
            return Err(InputError::mismatch(
                format!("noise of sensor {sensor}"),
                c.nrows(),
                noise.dim(),
            )
            .into());
        }
        self.noise[sensor] = Some(noise);
        Ok(self)
    }

    /// Number of columns of the output matrices (the plant dimension).
    pub fn state_dim(&self) -> usize {
        self.c[0].ncols()
    }
}

impl Output for LinearOutputs {
    fn measure(&mut self, ev: &SampleEvent, x: &[f64], y: &mut Vec<f64>) -> Result<(), SimError> {
        let c = self.c.get(ev.sensor).ok_or_else(|| {
            SimError::invalid(format!(
                "sample from sensor {} but only {} output matrices",
                ev.sensor,
                self.c.len()
            ))
        })?;
        if x.len() != c.ncols() {
            return Err(InputError::mismatch(
                "plant state measured by the linear outputs",
                c.ncols(),
                x.len(),
            )
            .into());
        }
        mat_vec_into(c.as_ref(), x, y);
        if let Some(noise) = self.noise[ev.sensor].as_mut() {
            self.buf.resize(c.nrows(), 0.0);
            noise.sample(ev.t, &mut self.buf);
            let start = y.len() - c.nrows();
            for (yi, v) in y[start..].iter_mut().zip(&self.buf) {
                *yi += v;
            }
        }
        Ok(())
    }
}

/// An observer gain, constant or scheduled on the elapsed time `τ` since the previous sample.
pub enum Gain {
    /// Constant gain `L`.
    Constant(Mat<f64>),
    /// Gain `L(τ)` computed at each sample (e.g. (45) of Sferlazza et al. 2021).
    Scheduled(Box<dyn Fn(f64) -> Result<Mat<f64>, SimError>>),
}

/// The correction `x̂⁺ = x̂ + L_σ(τ) (y − C_σ x̂)`.
pub struct LinearCorrection {
    c: Vec<Mat<f64>>,
    gains: Vec<Gain>,
    innovation: Vec<f64>,
}

impl LinearCorrection {
    /// One output matrix and one gain per sensor.
    pub fn new(c: Vec<Mat<f64>>, gains: Vec<Gain>) -> Result<Self, SimError> {
        let n = check_output_matrices(&c, "observer output matrix")?;
        if gains.len() != c.len() {
            return Err(
                InputError::mismatch("number of observer gains", c.len(), gains.len()).into(),
            );
        }
        for (s, g) in gains.iter().enumerate() {
            if let Gain::Constant(l) = g {
                if l.nrows() != n || l.ncols() != c[s].nrows() {
                    return Err(SimError::invalid(format!(
                        "gain of sensor {s} is {}×{}, expected {}×{}",
                        l.nrows(),
                        l.ncols(),
                        n,
                        c[s].nrows()
                    )));
                }
                check_finite(l.as_ref(), "observer gain")?;
            }
        }
        Ok(Self {
            c,
            gains,
            innovation: Vec::new(),
        })
    }

    /// Single sensor with a constant gain.
    pub fn constant(c: Mat<f64>, l: Mat<f64>) -> Result<Self, SimError> {
        Self::new(vec![c], vec![Gain::Constant(l)])
    }
}

/// `x ← x + L (y − C x)`, with `innovation` as scratch space.
fn correct(
    ev: &SampleEvent,
    c: MatRef<'_, f64>,
    l: MatRef<'_, f64>,
    y: &[f64],
    x: &mut [f64],
    innovation: &mut Vec<f64>,
) -> Result<(), SimError> {
    if l.nrows() != x.len() || l.ncols() != c.nrows() {
        return Err(SimError::invalid(format!(
            "gain at τ = {} is {}×{}, expected {}×{}",
            ev.elapsed,
            l.nrows(),
            l.ncols(),
            x.len(),
            c.nrows()
        )));
    }
    innovation.clear();
    mat_vec_into(c, x, innovation);
    for (r, yi) in innovation.iter_mut().zip(y) {
        *r = yi - *r;
    }
    for (i, xi) in x.iter_mut().enumerate() {
        *xi += (0..l.ncols())
            .map(|k| l[(i, k)] * innovation[k])
            .sum::<f64>();
    }
    Ok(())
}

impl Jump for LinearCorrection {
    fn jump(&mut self, ev: &SampleEvent, y: &[f64], x: &mut [f64]) -> Result<(), SimError> {
        let c = self.c.get(ev.sensor).ok_or_else(|| {
            SimError::invalid(format!(
                "sample from sensor {} but only {} gains",
                ev.sensor,
                self.c.len()
            ))
        })?;
        if x.len() != c.ncols() {
            return Err(InputError::mismatch("observer state", c.ncols(), x.len()).into());
        }
        if y.len() != c.nrows() {
            return Err(InputError::mismatch(
                format!("measurement of sensor {}", ev.sensor),
                c.nrows(),
                y.len(),
            )
            .into());
        }
        match &self.gains[ev.sensor] {
            Gain::Constant(l) => correct(ev, c.as_ref(), l.as_ref(), y, x, &mut self.innovation),
            Gain::Scheduled(f) => {
                let l = f(ev.elapsed)?;
                check_finite(l.as_ref(), "scheduled observer gain")?;
                correct(ev, c.as_ref(), l.as_ref(), y, x, &mut self.innovation)
            }
        }
    }
}

/// The linear reset `x⁺ = J x` (ignores the measurement), e.g. `J = I − LM` for the error system (5) of
/// Ferrante et al. 2016.
#[derive(Debug, Clone)]
pub struct LinearJump {
    j: Mat<f64>,
    buf: Vec<f64>,
}

impl LinearJump {
    /// The reset with matrix `J` (square, finite).
    pub fn new(j: Mat<f64>) -> Result<Self, SimError> {
        if j.nrows() != j.ncols() {
            return Err(
                InputError::mismatch("columns of the jump matrix", j.nrows(), j.ncols()).into(),
            );
        }
        check_finite(j.as_ref(), "jump matrix")?;
        let n = j.nrows();
        Ok(Self {
            j,
            buf: Vec::with_capacity(n),
        })
    }
}

impl Jump for LinearJump {
    fn jump(&mut self, _ev: &SampleEvent, _y: &[f64], x: &mut [f64]) -> Result<(), SimError> {
        if x.len() != self.j.nrows() {
            return Err(InputError::mismatch(
                "state reset by the jump matrix",
                self.j.nrows(),
                x.len(),
            )
            .into());
        }
        self.buf.clear();
        mat_vec_into(self.j.as_ref(), x, &mut self.buf);
        x.copy_from_slice(&self.buf);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::BoundedUniform;
    use faer::mat;

    fn ev(sensor: usize, elapsed: f64) -> SampleEvent {
        SampleEvent {
            t: 1.0,
            j: 0,
            sensor,
            elapsed,
        }
    }

    #[test]
    fn linear_outputs_and_noise_bounds() {
        let mut out = LinearOutputs::new(vec![mat![[1.0, 0.0]], mat![[0.0, 2.0]]])
            .unwrap()
            .with_noise(
                1,
                Box::new(BoundedUniform::symmetric(vec![0.1], 1).unwrap()),
            )
            .unwrap();
        let mut y = Vec::new();
        out.measure(&ev(0, 0.1), &[3.0, 4.0], &mut y).unwrap();
        assert_eq!(y, vec![3.0]);
        y.clear();
        out.measure(&ev(1, 0.1), &[3.0, 4.0], &mut y).unwrap();
        assert!((y[0] - 8.0).abs() <= 0.1);
        assert!(out.measure(&ev(2, 0.1), &[3.0, 4.0], &mut y).is_err());
        assert!(LinearOutputs::new(vec![mat![[1.0, 0.0]], mat![[1.0]]]).is_err());
        assert!(LinearOutputs::new(vec![]).is_err());
    }

    #[test]
    fn correction_matches_formula() {
        // x̂⁺ = x̂ + L (y − C x̂) with C = [1 0], L = [0.5; 0.25], x̂ = (1, 2), y = 3 ⇒ innovation 2.
        let mut corr = LinearCorrection::constant(mat![[1.0, 0.0]], mat![[0.5], [0.25]]).unwrap();
        let mut x = [1.0, 2.0];
        corr.jump(&ev(0, 0.3), &[3.0], &mut x).unwrap();
        assert_eq!(x, [2.0, 2.5]);
        // Scheduled gain L(τ) = τ·[1; 0].
        let mut corr = LinearCorrection::new(
            vec![mat![[1.0, 0.0]]],
            vec![Gain::Scheduled(Box::new(|tau| Ok(mat![[tau], [0.0]])))],
        )
        .unwrap();
        let mut x = [1.0, 2.0];
        corr.jump(&ev(0, 0.5), &[3.0], &mut x).unwrap();
        assert_eq!(x, [2.0, 2.0]);
        assert!(corr.jump(&ev(0, 0.5), &[3.0, 1.0], &mut x).is_err());
        assert!(LinearCorrection::constant(mat![[1.0, 0.0]], mat![[0.5]]).is_err());
        let mut lj = LinearJump::new(mat![[0.0, 1.0], [1.0, 0.0]]).unwrap();
        let mut x = [1.0, 2.0];
        lj.jump(&ev(0, 0.0), &[], &mut x).unwrap();
        assert_eq!(x, [2.0, 1.0]);
    }
}
