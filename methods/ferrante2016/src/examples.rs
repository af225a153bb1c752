//! The data of the two numerical examples of Ferrante et al. (2016), §5.

use std::f64::consts::E;

use faer::{Mat, mat};

use crate::error::Error;
use crate::system::Plant;
use sporadic_model::SamplingWindow;

/// Example 1: scalar plant `A = 1`, `M = 1`, periodic sampling `T1 = T2 = 1`, with the hand-picked
/// Lyapunov matrix `P = 1` and gain `L = 1.1 − e^{−1} ≈ 0.7321` (satisfying `|1 − L| < e^{−1}`).
#[derive(Debug, Clone, PartialEq)]
pub struct Example1 {
    /// The pair `(A, M) = (1, 1)`.
    pub plant: Plant,
    /// `[T1, T2] = [1, 1]`.
    pub window: SamplingWindow,
    /// `L = 1.1 − e^{−1}`.
    pub l: Mat<f64>,
    /// `P = 1`.
    pub p: Mat<f64>,
}

/// The printed values of Example 1 (four significant digits as in the paper).
pub mod example1_paper {
    /// `L ≈ 0.7321`.
    pub const L: f64 = 0.7321;
    /// `β ≈ 0.4698`.
    pub const BETA: f64 = 0.4698;
    /// `θ ≈ −0.0657`.
    pub const THETA: f64 = -0.0657;
    /// `R = γ ≈ 0.0328`.
    pub const GAMMA: f64 = 0.0328;
    /// `R = γ ≈ 0.0328`.
    pub const R: f64 = 0.0328;
}

/// Builds [`Example1`].
pub fn example1() -> Result<Example1, Error> {
    Ok(Example1 {
        plant: Plant::new(mat![[1.0]].as_ref(), mat![[1.0]].as_ref())?,
        window: SamplingWindow::new(1.0, 1.0)?,
        l: mat![[1.1 - 1.0 / E]],
        p: mat![[1.0]],
    })
}

/// Example 2: the mass–spring system of Geromel & de Oliveira (2001), eq. (44), with a constant
/// sensor bias `b` appended as an exosystem state (`ḃ = 0`), so `z̄ = (z, b) ∈ R⁵`,
/// `Ā = diag(A, 0)`, `B̄ = (B, 0)`, `M = [1 0 0 0 1]`, sampled with `T1 = 0.2`, `T2 = 3`.
#[derive(Debug, Clone, PartialEq)]
pub struct Example2 {
    /// `(Ā, M)`.
    pub plant: Plant,
    /// `B̄ = (0, 0, 1, 0, 0)` (as printed: the force acts on `z3`, the speed of the first mass).
    pub b: Mat<f64>,
    /// `[T1, T2] = [0.2, 3]`.
    pub window: SamplingWindow,
    /// The published gain `L = (0.77524, 0.18123, −0.12123, −0.17406, 0.22469)`.
    pub l_paper: Mat<f64>,
}

/// The published gain of Example 2 (five decimals).
pub const EXAMPLE2_L_PAPER: [f64; 5] = [0.77524, 0.18123, -0.12123, -0.17406, 0.22469];

/// Builds [`Example2`].
pub fn example2() -> Result<Example2, Error> {
    let a = mat![
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, 0.0],
        [-2.0, 1.0, -1.0, 0.0, 0.0],
        [2.0, -2.0, 0.0, -2.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0],
    ];
    let m = mat![[1.0, 0.0, 0.0, 0.0, 1.0]];
    Ok(Example2 {
        plant: Plant::new(a.as_ref(), m.as_ref())?,
        b: mat![[0.0], [0.0], [1.0], [0.0], [0.0]],
        window: SamplingWindow::new(0.2, 3.0)?,
        l_paper: Mat::from_fn(5, 1, |i, _| EXAMPLE2_L_PAPER[i]),
    })
}
