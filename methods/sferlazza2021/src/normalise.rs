//! Normalisation of the plant's state coordinates before the design (issue 22: verdicts must not
//! depend on the user's units).
//!
//! The design loop of §5.3 is not invariant under a change of state coordinates `x = D x_b`: the
//! normalisation `I ⪯ P_σ ⪯ p*I` of (47), the margin `μI` of (48) and the grid spacing (49)
//! (through `‖A‖₂` and the Step 1 constant `γ`) all depend on them. A plant written in badly
//! scaled units (e.g. millimetres and km/s) then needs a validation grid of 10³⁸ points, whereas the
//! same plant in SI units certifies at once. The method therefore designs in *balanced*
//! coordinates: `A_b = D⁻¹AD` with the diagonal `D` of the LAPACK `gebal` iteration (scaling only,
//! no permutation; Parlett & Reinsch 1969), whose entries are powers of 2, so that `A_b` and
//! `C_σ D` are exact and a plant that is already balanced is left bit-for-bit unchanged. The
//! result is mapped back exactly as well: with `x_b = D⁻¹x`,
//!
//! * `V = x_bᵀ P_b x_b = xᵀ D⁻¹P_bD⁻¹ x`, so `P = D⁻¹ P_b D⁻¹`;
//! * `x̂_b⁺ = x̂_b + K_b(y − C_bx̂_b)` is `x̂⁺ = x̂ + D K_b (y − Cx̂)`, so `K = D K_b`.
//!
//! Time scaling needs no normalisation: `Ξ_σ(τ)` of (44) depends on `A` and `τ` only through `Aτ`,
//! the spacing (49) scales with `1/‖A‖`, and Step 1's offsets with the plant's rate. Output scaling
//! needs none either: `Ξ_σ` depends on `C_σ` only through its kernel (orthonormal `C_σ^⊥`).

use faer::Mat;

use crate::error::Error;
use crate::plant::RoundRobinPlant;
use sporadic_linalg::balance::{balance_a, balance_c};

/// The round-robin plant in the balanced coordinates `x_b = D⁻¹x` (`D = diag(d)`): `D⁻¹AD` and
/// `C_σD`, same windows, orthonormal complements.
///
/// # Errors
/// Those of [`RoundRobinPlant::new`].
pub fn balanced_plant(plant: &RoundRobinPlant, d: &[f64]) -> Result<RoundRobinPlant, Error> {
    let a = balance_a(plant.a(), d);
    let cs: Vec<Mat<f64>> = plant
        .sensors()
        .iter()
        .map(|s| balance_c(s.c(), d))
        .collect();
    let sensors: Vec<_> = cs
        .iter()
        .zip(plant.sensors())
        .map(|(c, s)| (c.as_ref(), s.window()))
        .collect();
    RoundRobinPlant::new(a.as_ref(), &sensors)
}
