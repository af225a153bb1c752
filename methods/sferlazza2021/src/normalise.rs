//! Normalisation of the plant's state coordinates before the design (issue 22: verdicts must not
//! depend on the user's units or coordinates).
//!
//! The design loop of §5.3 is not invariant under a change of state coordinates `x = T x'`: the
//! normalisation `I ⪯ P_σ ⪯ p*I` of (47), the margin `μI` of (48) and the grid spacing (49)
//! (through `‖A‖₂` and the Step 1 constant `γ`) all depend on them. The method therefore designs
//! in one of two [`Coordinates`]:
//!
//! * **balanced**: `A_b = D⁻¹AD` with the diagonal `D` of the LAPACK `gebal` iteration (scaling
//!   only, no permutation; Parlett & Reinsch 1969), whose entries are powers of 2, so that `A_b`
//!   and `C_σ D` are exact and a plant that is already balanced is left bit-for-bit unchanged.
//!   A plant written in badly scaled units (e.g. millimetres and km/s) would otherwise need a
//!   validation grid of 10³⁸ points, whereas the same plant in SI units certifies at once. The
//!   result is mapped back exactly as well: with `x_b = D⁻¹x`, `V = x_bᵀ P_b x_b =
//!   xᵀ D⁻¹P_bD⁻¹ x`, so `P = D⁻¹ P_b D⁻¹`, and `x̂_b⁺ = x̂_b + K_b(y − C_bx̂_b)` is
//!   `x̂⁺ = x̂ + D K_b (y − Cx̂)`, so `K = D K_b`. This form is only invariant under diagonal
//!   changes of coordinates;
//! * **Gramian**: `x' = Gx` with the observability Gramian of `(A, [C_1; …; C_N])` on one time
//!   unit the identity ([`sporadic_linalg::gramian_form`]), the same for every equivalent plant
//!   up to an orthogonal change of coordinates, under which (47), (48) and (49) are invariant;
//!   `P = GᵀP'G`, `K = G⁻¹K'`. It is rounded, and on short windows of chains of integrators it
//!   is far from normal (the corpus cart-pole on `[0.02, 0.1]`: `‖A'‖₂ = 131` against 21.6, and
//!   a (49) grid that did not end in 25 s).
//!
//! The design tries first the form whose `A` is nearer to normal (smaller `‖A‖_F`), then the
//! other ([`crate::Sferlazza2021`]'s `design`).
//!
//! Time scaling needs no normalisation: `Ξ_σ(τ)` of (44) depends on `A` and `τ` only through `Aτ`,
//! the spacing (49) scales with `1/‖A‖`, and Step 1's offsets with the plant's rate. Output scaling
//! needs none either: `Ξ_σ` depends on `C_σ` only through its kernel (orthonormal `C_σ^⊥`), and
//! the Gramian form balances the outputs' shares of the Gramian.

use faer::{Mat, MatRef};

use crate::error::Error;
use crate::plant::{RoundRobinPlant, Sensor};
use sporadic_linalg::balance::{
    balance_a, balance_c, balance_form, balancing_scales, unbalance_form, unbalance_gain,
};
use sporadic_linalg::gramian_form::gramian_form;
use sporadic_linalg::symmetric::symmetric_congruence;

/// The round-robin plant in the balanced coordinates `x_b = D⁻¹x` (`D = diag(d)`): `D⁻¹AD` and
/// `C_σD`, same windows, orthonormal complements.
///
/// # Errors
/// Those of [`RoundRobinPlant::new`].
pub fn balanced_plant(plant: &RoundRobinPlant, d: &[f64]) -> Result<RoundRobinPlant, Error> {
    let cs: Vec<Mat<f64>> = plant
        .sensors()
        .iter()
        .map(|s| balance_c(s.c(), d))
        .collect();
    plant.with_matrices(balance_a(plant.a(), d).as_ref(), &cs)
}

/// Largest `‖G‖_F‖G⁻¹‖_F` of a usable Gramian normal form ([`Coordinates::gramian`]): the
/// rounded plant of the form is then within about `10⁻⁸` (relative) of the user's.
pub const MAX_FORM_CONDITION: f64 = 1e8;

/// The coordinates a design is made in: the plant's own after a diagonal balancing, or the
/// observability-Gramian normal form.
///
/// The balanced coordinates are exact but only invariant under diagonal changes of
/// coordinates: a maglev written in micrometres, m/s and mA certifies up to `T2 = 0.1` in them,
/// and the same plant in coordinates `x = Tz` (random `T`, `κ(T) < 10`) nothing beyond
/// `T2 = 0.00215` in 25 s. The Gramian normal form
/// ([`sporadic_linalg::gramian_form::gramian_form`] of `(A, [C_1; …; C_N])`) is the same for
/// every such equivalent plant up to an orthogonal change of coordinates, under which the
/// normalisation `I ⪯ P_σ ⪯ p*I` of (47), the margin `μI` of (48) and the spacing (49) (through
/// `‖A‖₂`) are invariant; it is rounded (`A' = fl(GAG⁻¹)`), so the design made in it is checked
/// on that floating-point plant, as the grid (49) itself is a floating-point check.
#[derive(Debug, Clone, PartialEq)]
pub enum Coordinates {
    /// `x_b = D⁻¹x`, `D = diag(scales)` (powers of 2; all ones: the plant as given).
    Balanced(Vec<f64>),
    /// `x' = Gx` with the Gramian on the time unit `unit` the identity.
    Gramian {
        /// `G`.
        state: Mat<f64>,
        /// `G⁻¹` as computed.
        state_inverse: Mat<f64>,
        /// The time unit of the Gramian.
        unit: f64,
    },
    /// `x' = Rx` with `RᵀR = Σ_σ P_σ/‖P_σ‖_max` for a given certificate (its own coordinates,
    /// in which `verify` checks a certificate that is ill-conditioned in the balanced ones).
    Certificate {
        /// `R`.
        state: Mat<f64>,
        /// `R⁻¹` as computed.
        state_inverse: Mat<f64>,
    },
}

impl Coordinates {
    /// The balanced coordinates of `plant` ([`balancing_scales`] of `A`).
    pub fn balanced(plant: &RoundRobinPlant) -> Self {
        Self::Balanced(balancing_scales(plant.a()))
    }

    /// The Gramian normal form of `plant` (`None` when its Gramian is not usable, or the change of
    /// coordinates is too ill-conditioned, [`MAX_FORM_CONDITION`]). The time
    /// unit is `min(T_M, 1/ρ(A))` (`T_M` when `ρ(A) = 0`): similarity-invariant, and scaling as
    /// `1/c` under `(A, windows) → (cA, windows/c)`, so the form is the same for every
    /// equivalent plant. On a maglev (`ρ(A) = 100`, windows `[10⁻³, T2]`) the unit `T_M` made
    /// (47) fail from `T2 = 0.2` on, `1/ρ(A)` certified beyond it.
    pub fn gramian(plant: &RoundRobinPlant) -> Option<Self> {
        let n = plant.n();
        let rows: usize = plant.sensors().iter().map(Sensor::outputs).sum();
        let mut c = Mat::<f64>::zeros(rows, n);
        let mut at = 0;
        for s in plant.sensors() {
            c.as_mut()
                .submatrix_mut(at, 0, s.outputs(), n)
                .copy_from(s.c());
            at += s.outputs();
        }
        let rho = sporadic_linalg::spectral_radius(plant.a()).ok()?;
        let unit = if rho > 0.0 {
            plant.t_max().min(1.0 / rho)
        } else {
            plant.t_max()
        };
        let form = gramian_form(plant.a(), c.as_ref(), unit)?;
        // The design in this form is checked on the rounded plant `fl(GAG⁻¹)`, whose distance
        // to the user's plant grows like ε·κ(G): beyond [`MAX_FORM_CONDITION`] it is another
        // plant (a three-mass drive train in coordinates x = Tz, κ(T) < 5: κ(G) = 1.3e13 after
        // the passes, an eigenvalue −6.45 of e^(AT) for a plant whose eigenvalues have real
        // parts ≤ 0, and the form's Proposition 1 refused it as undetectable).
        let condition = form.state.norm_l2() * form.state_inverse.norm_l2();
        if !(condition <= MAX_FORM_CONDITION) {
            return None;
        }
        Some(Self::Gramian {
            state: form.state,
            state_inverse: form.state_inverse,
            unit,
        })
    }

    /// The coordinates of the certificate `p` (`None` when `Σ_σ P_σ/‖P_σ‖_max` is not
    /// numerically positive definite).
    pub fn of_certificate(p: &[Mat<f64>]) -> Option<Self> {
        let (r, r_inv) = sporadic_linalg::symmetric::certificate_coordinates(p)?;
        Some(Self::Certificate {
            state: r,
            state_inverse: r_inv,
        })
    }

    /// Whether this is the Gramian normal form.
    pub fn is_gramian(&self) -> bool {
        matches!(self, Self::Gramian { .. })
    }

    /// Whether these coordinates change nothing.
    pub fn is_identity(&self) -> bool {
        matches!(self, Self::Balanced(d) if d.iter().all(|&x| x == 1.0))
    }

    /// The plant in these coordinates: `D⁻¹AD`, `C_σD` (exact), or `fl(GAG⁻¹)`, `fl(C_σG⁻¹)`.
    ///
    /// # Errors
    /// Those of [`RoundRobinPlant::new`].
    pub fn plant(&self, plant: &RoundRobinPlant) -> Result<RoundRobinPlant, Error> {
        match self {
            _ if self.is_identity() => Ok(plant.clone()),
            Self::Balanced(d) => balanced_plant(plant, d),
            Self::Gramian {
                state,
                state_inverse,
                ..
            }
            | Self::Certificate {
                state,
                state_inverse,
            } => {
                let cs: Vec<Mat<f64>> = plant
                    .sensors()
                    .iter()
                    .map(|s| s.c() * state_inverse)
                    .collect();
                plant.with_matrices((state * plant.a() * state_inverse).as_ref(), &cs)
            }
        }
    }

    /// A Lyapunov matrix in the plant's coordinates: `P = D⁻¹P_bD⁻¹` or `P = GᵀP'G`
    /// (symmetrised).
    pub fn form_back(&self, p: MatRef<'_, f64>) -> Mat<f64> {
        match self {
            Self::Balanced(d) => unbalance_form(p, d),
            Self::Gramian { state, .. } | Self::Certificate { state, .. } => {
                symmetric_congruence(state.as_ref(), p)
            }
        }
    }

    /// A Lyapunov matrix given in the plant's coordinates, in these: `P_b = DPD` or
    /// `P' = G⁻ᵀPG⁻¹` (symmetrised).
    pub fn form_to(&self, p: MatRef<'_, f64>) -> Mat<f64> {
        match self {
            Self::Balanced(d) => balance_form(p, d),
            Self::Gramian { state_inverse, .. } | Self::Certificate { state_inverse, .. } => {
                symmetric_congruence(state_inverse.as_ref(), p)
            }
        }
    }

    /// A gain in the plant's coordinates: `K = DK_b` or `K = G⁻¹K'`.
    pub fn gain_back(&self, k: MatRef<'_, f64>) -> Mat<f64> {
        match self {
            Self::Balanced(d) => unbalance_gain(k, d),
            Self::Gramian { state_inverse, .. } | Self::Certificate { state_inverse, .. } => {
                state_inverse * k
            }
        }
    }
}
