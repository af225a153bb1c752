//! A test system that satisfies every condition of Theorem 2 of Andrieu et al. (2014) globally,
//! used for the closed-loop checks of the theorem: `n = 2`, `f1 = 0`, `f2 = −sin(x1)` (a
//! frictionless pendulum in normal form), with the constant Lipschitz function `c ≡ 1`
//! (`|sin a − sin b| ≤ |a − b|`).

use crate::system::TriangularSystem;

/// `ẋ1 = x2`, `ẋ2 = −sin(x1)`, `c ≡ 1`, no input.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Pendulum;

impl TriangularSystem for Pendulum {
    fn order(&self) -> usize {
        2
    }
    fn input_dim(&self) -> usize {
        0
    }
    fn nonlinearity(&self, x: &[f64], _u: &[f64], out: &mut [f64]) {
        out[0] = 0.0;
        out[1] = -x[0].sin();
    }
    fn lipschitz(&self, _xhat: &[f64], _u: &[f64]) -> f64 {
        1.0
    }
}
