//! The plant every method designs for, validated once:
//! `ẋ = Ax + Bu + Gφ(Hx) + w`, `y = Cx + v` (or round-robin sensors `y_σ = C_σx`).

use faer::{Mat, MatRef};
use sporadic_linalg::InputError;
use sporadic_linalg::input::{check_finite, check_finite_slice, check_shape, check_square_finite};

/// A Lipschitz nonlinearity `Gφ(Hx)` with elementwise bounds on the Jacobian of `φ`:
/// `∂φ_i/∂v_j ∈ [lower_ij, upper_ij]` (Etienne et al. 2017, (1)–(2) and Lemma 1).
#[derive(Debug, Clone, PartialEq)]
pub struct Lipschitz {
    g: Mat<f64>,
    h: Mat<f64>,
    jacobian_lower: Mat<f64>,
    jacobian_upper: Mat<f64>,
}

impl Lipschitz {
    /// `G` (`n × q`), `H` (`r × n`), and the `q × r` Jacobian bounds, `lower ≤ upper`
    /// elementwise; all entries finite.
    pub fn new(
        g: MatRef<'_, f64>,
        h: MatRef<'_, f64>,
        jacobian_lower: MatRef<'_, f64>,
        jacobian_upper: MatRef<'_, f64>,
    ) -> Result<Self, InputError> {
        for (m, what) in [
            (g, "lipschitz G"),
            (h, "lipschitz H"),
            (jacobian_lower, "lipschitz jacobian_lower"),
            (jacobian_upper, "lipschitz jacobian_upper"),
        ] {
            check_finite(m, what)?;
        }
        let (q, r) = (g.ncols(), h.nrows());
        check_shape(jacobian_lower, q, r, "lipschitz jacobian_lower")?;
        check_shape(jacobian_upper, q, r, "lipschitz jacobian_upper")?;
        for i in 0..q {
            for j in 0..r {
                if jacobian_lower[(i, j)] > jacobian_upper[(i, j)] {
                    return Err(InputError::parameter(
                        format!("lipschitz jacobian_lower ({}, {})", i + 1, j + 1),
                        jacobian_lower[(i, j)],
                        format!("exceeds the upper bound {}", jacobian_upper[(i, j)]),
                    ));
                }
            }
        }
        Ok(Self {
            g: g.to_owned(),
            h: h.to_owned(),
            jacobian_lower: jacobian_lower.to_owned(),
            jacobian_upper: jacobian_upper.to_owned(),
        })
    }

    /// `G` (`n × q`).
    pub fn g(&self) -> MatRef<'_, f64> {
        self.g.as_ref()
    }
    /// `H` (`r × n`).
    pub fn h(&self) -> MatRef<'_, f64> {
        self.h.as_ref()
    }
    /// Lower Jacobian bounds (`q × r`).
    pub fn jacobian_lower(&self) -> MatRef<'_, f64> {
        self.jacobian_lower.as_ref()
    }
    /// Upper Jacobian bounds (`q × r`).
    pub fn jacobian_upper(&self) -> MatRef<'_, f64> {
        self.jacobian_upper.as_ref()
    }
}

/// Bounds on the disturbance and the measurement noise: `|w_i| ≤ disturbance_i`,
/// `|v_j| ≤ noise_j` (Rabehi et al. 2021, Assumptions 2–3, with `d̲ = −d̄`).
#[derive(Debug, Clone, PartialEq)]
pub struct Bounds {
    disturbance: Vec<f64>,
    noise: Vec<f64>,
}

impl Bounds {
    /// Finite, non-negative bounds; an empty list means zero.
    pub fn new(disturbance: Vec<f64>, noise: Vec<f64>) -> Result<Self, InputError> {
        for (x, what) in [(&disturbance, "disturbance bound"), (&noise, "noise bound")] {
            check_finite_slice(x, what)?;
            if let Some(i) = x.iter().position(|b| *b < 0.0) {
                return Err(InputError::parameter(
                    format!("{what} {}", i + 1),
                    x[i],
                    "must be non-negative",
                ));
            }
        }
        Ok(Self { disturbance, noise })
    }

    /// `|w_i| ≤ disturbance_i` (empty: no disturbance).
    pub fn disturbance(&self) -> &[f64] {
        &self.disturbance
    }
    /// `|v_j| ≤ noise_j` (empty: no noise).
    pub fn noise(&self) -> &[f64] {
        &self.noise
    }
}

/// The outputs of a plant: one output matrix sampled at once, or round-robin sensors polled in
/// order (Sferlazza et al. 2021, (1)–(2)).
#[derive(Debug, Clone, PartialEq)]
pub enum Outputs {
    /// `y = Cx`, `C` is `p × n`.
    Synchronous(Mat<f64>),
    /// `y_σ = C_σx`, one `p_σ × n` matrix per sensor in polling order.
    RoundRobin(Vec<Mat<f64>>),
}

/// A validated plant: `ẋ = Ax + Bu [+ Gφ(Hx)] [+ w]`, outputs [`Outputs`], optional Lipschitz
/// nonlinearity and disturbance/noise bounds. Construct with [`Plant::linear`] or
/// [`Plant::round_robin`], then add the optional parts.
///
/// ```
/// use faer::mat;
/// use sporadic_model::Plant;
///
/// let plant = Plant::linear(mat![[0.0, 1.0], [-2.0, -0.3]].as_ref(), None, mat![[1.0, 0.0]].as_ref())?
///     .named("mass-spring");
/// assert_eq!((plant.n(), plant.outputs()), (2, 1));
/// # Ok::<(), sporadic_linalg::InputError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Plant {
    name: String,
    a: Mat<f64>,
    b: Mat<f64>,
    outputs: Outputs,
    lipschitz: Option<Lipschitz>,
    bounds: Option<Bounds>,
}

impl Plant {
    fn checked(
        a: MatRef<'_, f64>,
        b: Option<MatRef<'_, f64>>,
    ) -> Result<(usize, Mat<f64>), InputError> {
        let n = check_square_finite(a, "A")?;
        if n == 0 {
            return Err(InputError::empty("A"));
        }
        let b = match b {
            Some(b) => {
                check_finite(b, "B")?;
                if b.nrows() != n {
                    return Err(InputError::mismatch("rows of B", n, b.nrows()));
                }
                b.to_owned()
            }
            None => Mat::zeros(n, 0),
        };
        Ok((n, b))
    }

    fn check_output(c: MatRef<'_, f64>, n: usize, what: &str) -> Result<(), InputError> {
        check_finite(c, what)?;
        if c.nrows() == 0 {
            return Err(InputError::empty(what));
        }
        if c.ncols() != n {
            return Err(InputError::mismatch(
                format!("columns of {what}"),
                n,
                c.ncols(),
            ));
        }
        Ok(())
    }

    /// A linear plant `ẋ = Ax + Bu`, `y = Cx` (`B` may be omitted: no input).
    pub fn linear(
        a: MatRef<'_, f64>,
        b: Option<MatRef<'_, f64>>,
        c: MatRef<'_, f64>,
    ) -> Result<Self, InputError> {
        let (n, b) = Self::checked(a, b)?;
        Self::check_output(c, n, "C")?;
        Ok(Self {
            name: String::new(),
            a: a.to_owned(),
            b,
            outputs: Outputs::Synchronous(c.to_owned()),
            lipschitz: None,
            bounds: None,
        })
    }

    /// A plant with round-robin sensors `y_σ = C_σx` polled in the given order (at least one).
    pub fn round_robin(
        a: MatRef<'_, f64>,
        b: Option<MatRef<'_, f64>>,
        sensors: &[MatRef<'_, f64>],
    ) -> Result<Self, InputError> {
        let (n, b) = Self::checked(a, b)?;
        if sensors.is_empty() {
            return Err(InputError::empty("round-robin sensors"));
        }
        for (i, c) in sensors.iter().enumerate() {
            Self::check_output(*c, n, &format!("C of sensor {}", i + 1))?;
        }
        Ok(Self {
            name: String::new(),
            a: a.to_owned(),
            b,
            outputs: Outputs::RoundRobin(sensors.iter().map(|c| c.to_owned()).collect()),
            lipschitz: None,
            bounds: None,
        })
    }

    /// The plant with a name (used in reports and figures).
    pub fn named(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// Adds the Lipschitz nonlinearity `Gφ(Hx)` (`G` must have `n` rows, `H` `n` columns).
    pub fn with_lipschitz(mut self, lipschitz: Lipschitz) -> Result<Self, InputError> {
        let n = self.n();
        if lipschitz.g.nrows() != n {
            return Err(InputError::mismatch(
                "rows of lipschitz G",
                n,
                lipschitz.g.nrows(),
            ));
        }
        if lipschitz.h.ncols() != n {
            return Err(InputError::mismatch(
                "columns of lipschitz H",
                n,
                lipschitz.h.ncols(),
            ));
        }
        self.lipschitz = Some(lipschitz);
        Ok(self)
    }

    /// Adds disturbance and noise bounds (`n` disturbance entries and one noise entry per output
    /// row, or empty lists for zero).
    pub fn with_bounds(mut self, bounds: Bounds) -> Result<Self, InputError> {
        let (n, p) = (self.n(), self.outputs());
        if !bounds.disturbance.is_empty() && bounds.disturbance.len() != n {
            return Err(InputError::mismatch(
                "entries of the disturbance bound",
                n,
                bounds.disturbance.len(),
            ));
        }
        if !bounds.noise.is_empty() && bounds.noise.len() != p {
            return Err(InputError::mismatch(
                "entries of the noise bound",
                p,
                bounds.noise.len(),
            ));
        }
        self.bounds = Some(bounds);
        Ok(self)
    }

    /// The name (empty if none was given).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// State dimension `n`.
    pub fn n(&self) -> usize {
        self.a.nrows()
    }
    /// Number of output rows (all sensors together for round-robin).
    pub fn outputs(&self) -> usize {
        match &self.outputs {
            Outputs::Synchronous(c) => c.nrows(),
            Outputs::RoundRobin(cs) => cs.iter().map(|c| c.nrows()).sum(),
        }
    }
    /// `A` (`n × n`).
    pub fn a(&self) -> MatRef<'_, f64> {
        self.a.as_ref()
    }
    /// `B` (`n × m`; `n × 0` when the plant has no input).
    pub fn b(&self) -> MatRef<'_, f64> {
        self.b.as_ref()
    }
    /// The output structure.
    pub fn output_structure(&self) -> &Outputs {
        &self.outputs
    }
    /// `C` of a synchronously sampled plant (`None` for round-robin sensors).
    pub fn c(&self) -> Option<MatRef<'_, f64>> {
        match &self.outputs {
            Outputs::Synchronous(c) => Some(c.as_ref()),
            Outputs::RoundRobin(_) => None,
        }
    }
    /// The sensors' output matrices: the round-robin `C_σ`, or `C` as a single sensor.
    pub fn sensors(&self) -> Vec<MatRef<'_, f64>> {
        match &self.outputs {
            Outputs::Synchronous(c) => vec![c.as_ref()],
            Outputs::RoundRobin(cs) => cs.iter().map(|c| c.as_ref()).collect(),
        }
    }
    /// The Lipschitz nonlinearity, if any.
    pub fn lipschitz(&self) -> Option<&Lipschitz> {
        self.lipschitz.as_ref()
    }
    /// The disturbance and noise bounds, if any.
    pub fn bounds(&self) -> Option<&Bounds> {
        self.bounds.as_ref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::mat;

    #[test]
    fn shapes_and_values_are_checked() {
        let a = mat![[0.0, 1.0], [-1.0, 0.0]];
        let c = mat![[1.0, 0.0]];
        assert!(Plant::linear(a.as_ref(), None, c.as_ref()).is_ok());
        assert!(Plant::linear(a.as_ref(), None, mat![[1.0]].as_ref()).is_err());
        assert!(Plant::linear(mat![[1.0, 2.0]].as_ref(), None, c.as_ref()).is_err());
        assert!(
            Plant::linear(mat![[f64::NAN, 0.0], [0.0, 0.0]].as_ref(), None, c.as_ref()).is_err()
        );
        assert!(Plant::linear(a.as_ref(), Some(mat![[1.0]].as_ref()), c.as_ref()).is_err());
        assert!(Plant::round_robin(a.as_ref(), None, &[]).is_err());
        let p = Plant::linear(a.as_ref(), None, c.as_ref()).unwrap();
        assert!(
            p.clone()
                .with_bounds(Bounds::new(vec![0.1], vec![]).unwrap())
                .is_err()
        );
        assert!(Bounds::new(vec![-0.1], vec![]).is_err());
        let lip = Lipschitz::new(
            mat![[0.0], [1.0]].as_ref(),
            mat![[1.0, 0.0]].as_ref(),
            mat![[1.0]].as_ref(),
            mat![[-1.0]].as_ref(),
        );
        assert!(lip.is_err());
        assert_eq!(p.b().ncols(), 0);
    }
}
