//! Disturbance and measurement-noise generators, all seeded and reproducible.
//!
//! Examples from the papers' numerical examples: uniform bounded noise `|d_i| <= d̄_i`
//! (Sferlazza et al. 2021, §6), the sinusoidal measurement noise `v(t_k) = 0.4 cos(2 t_k)`
//! (Rabehi et al., §V), Gaussian output noise `N(0, 0.001²)` (Andrieu et al. 2014, §4; the law
//! and level are a reproduction setting, not given in the paper), and the noise-free case.

use crate::error::SimError;
use crate::rng::SimRng;
use sporadic_linalg::InputError;
use sporadic_linalg::input::check_finite_slice;

/// A vector-valued noise or disturbance generator, sampled at given times.
pub trait NoiseSource {
    /// Dimension of the samples.
    fn dim(&self) -> usize;
    /// Writes the sample for time `t` into `out` (`out.len() == self.dim()`).
    fn sample(&mut self, t: f64, out: &mut [f64]);
}

/// Identically zero noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ZeroNoise {
    dim: usize,
}

impl ZeroNoise {
    /// Zero noise of dimension `dim`.
    pub fn new(dim: usize) -> Self {
        Self { dim }
    }
}

impl NoiseSource for ZeroNoise {
    fn dim(&self) -> usize {
        self.dim
    }
    fn sample(&mut self, _t: f64, out: &mut [f64]) {
        out.fill(0.0);
    }
}

/// Independent uniform samples with per-component bounds `lower_i <= v_i <= upper_i`.
#[derive(Debug)]
pub struct BoundedUniform {
    lower: Vec<f64>,
    upper: Vec<f64>,
    rng: SimRng,
}

impl BoundedUniform {
    /// Uniform noise in the box `[lower, upper]` (componentwise), seeded.
    pub fn new(lower: Vec<f64>, upper: Vec<f64>, seed: u64) -> Result<Self, SimError> {
        if lower.len() != upper.len() {
            return Err(
                InputError::mismatch("upper noise bounds", lower.len(), upper.len()).into(),
            );
        }
        check_finite_slice(&lower, "lower noise bounds")?;
        check_finite_slice(&upper, "upper noise bounds")?;
        if let Some(i) = (0..lower.len()).find(|&i| lower[i] > upper[i]) {
            return Err(SimError::invalid(format!(
                "noise bounds of component {i}: lower {} > upper {}",
                lower[i], upper[i]
            )));
        }
        Ok(Self {
            lower,
            upper,
            rng: SimRng::new(seed),
        })
    }

    /// Zero-mean uniform noise `|v_i| <= bound_i`.
    pub fn symmetric(bound: Vec<f64>, seed: u64) -> Result<Self, SimError> {
        if let Some(i) = bound.iter().position(|&b| b < 0.0) {
            return Err(SimError::invalid(format!(
                "noise bound {i} is negative: {}",
                bound[i]
            )));
        }
        let lower = bound.iter().map(|b| -b).collect();
        Self::new(lower, bound, seed)
    }
}

impl NoiseSource for BoundedUniform {
    fn dim(&self) -> usize {
        self.lower.len()
    }
    fn sample(&mut self, _t: f64, out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.rng.uniform(self.lower[i], self.upper[i]);
        }
    }
}

/// Deterministic sinusoids `v_i(t) = a_i sin(ω_i t + φ_i)` (use `φ_i = π/2` for a cosine).
#[derive(Debug, Clone, PartialEq)]
pub struct Sinusoidal {
    amplitude: Vec<f64>,
    omega: Vec<f64>,
    phase: Vec<f64>,
}

impl Sinusoidal {
    /// Sinusoids with the given amplitudes, angular frequencies and phases.
    pub fn new(amplitude: Vec<f64>, omega: Vec<f64>, phase: Vec<f64>) -> Result<Self, SimError> {
        let n = amplitude.len();
        if omega.len() != n {
            return Err(InputError::mismatch("sinusoid frequencies", n, omega.len()).into());
        }
        if phase.len() != n {
            return Err(InputError::mismatch("sinusoid phases", n, phase.len()).into());
        }
        check_finite_slice(&amplitude, "sinusoid amplitudes")?;
        check_finite_slice(&omega, "sinusoid frequencies")?;
        check_finite_slice(&phase, "sinusoid phases")?;
        Ok(Self {
            amplitude,
            omega,
            phase,
        })
    }

    /// Sinusoids whose phases are drawn uniformly in `[0, 2π)` from `seed`.
    pub fn random_phases(
        amplitude: Vec<f64>,
        omega: Vec<f64>,
        seed: u64,
    ) -> Result<Self, SimError> {
        let mut rng = SimRng::new(seed);
        let phase = (0..amplitude.len())
            .map(|_| std::f64::consts::TAU * rng.uniform01())
            .collect();
        Self::new(amplitude, omega, phase)
    }
}

impl NoiseSource for Sinusoidal {
    fn dim(&self) -> usize {
        self.amplitude.len()
    }
    fn sample(&mut self, t: f64, out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.amplitude[i] * (self.omega[i] * t + self.phase[i]).sin();
        }
    }
}

/// Independent Gaussian samples `v_i ~ N(0, σ_i²)`.
#[derive(Debug)]
pub struct Gaussian {
    std_dev: Vec<f64>,
    rng: SimRng,
}

impl Gaussian {
    /// Zero-mean Gaussian noise with per-component standard deviations, seeded.
    pub fn new(std_dev: Vec<f64>, seed: u64) -> Result<Self, SimError> {
        check_finite_slice(&std_dev, "noise standard deviations")?;
        if let Some(i) = std_dev.iter().position(|&s| s < 0.0) {
            return Err(SimError::invalid(format!(
                "standard deviation {i} is negative: {}",
                std_dev[i]
            )));
        }
        Ok(Self {
            std_dev,
            rng: SimRng::new(seed),
        })
    }
}

impl NoiseSource for Gaussian {
    fn dim(&self) -> usize {
        self.std_dev.len()
    }
    fn sample(&mut self, _t: f64, out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.std_dev[i] * self.rng.standard_normal();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounded_uniform_respects_bounds_and_seed() {
        let mut a = BoundedUniform::new(vec![-0.004, 0.0], vec![0.004, 2.0], 11).unwrap();
        let mut b = BoundedUniform::new(vec![-0.004, 0.0], vec![0.004, 2.0], 11).unwrap();
        let mut c = BoundedUniform::new(vec![-0.004, 0.0], vec![0.004, 2.0], 12).unwrap();
        let (mut va, mut vb, mut vc) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        let mut differ = false;
        for k in 0..1000 {
            a.sample(k as f64, &mut va);
            b.sample(k as f64, &mut vb);
            c.sample(k as f64, &mut vc);
            assert_eq!(va, vb);
            differ |= va != vc;
            assert!(va[0].abs() <= 0.004 && (0.0..=2.0).contains(&va[1]));
        }
        assert!(differ);
        assert!(BoundedUniform::new(vec![1.0], vec![0.0], 0).is_err());
        assert!(BoundedUniform::symmetric(vec![-1.0], 0).is_err());
        assert!(BoundedUniform::new(vec![0.0], vec![0.0, 1.0], 0).is_err());
    }

    #[test]
    fn sinusoid_matches_formula() {
        // Rabehi et al. §V: v(t_k) = 0.4 cos(2 t_k).
        let mut s =
            Sinusoidal::new(vec![0.4], vec![2.0], vec![std::f64::consts::FRAC_PI_2]).unwrap();
        let mut v = [0.0];
        for &t in &[0.0, 0.3, 1.7] {
            s.sample(t, &mut v);
            assert!((v[0] - 0.4 * (2.0 * t).cos()).abs() < 1e-15);
        }
        let mut z = ZeroNoise::new(3);
        let mut w = [1.0; 3];
        z.sample(1.0, &mut w);
        assert_eq!(w, [0.0; 3]);
    }
}
