//! Rigorous proof, in interval arithmetic, that a design satisfies the jitter-tolerant condition
//! (44) of Theorem 4 for **every** `τ` of each sensor's window (issue 24), not only on the
//! floating-point grid (48)–(49) of the design's validation ([`crate::validation`]).
//!
//! # The condition
//!
//! For each sensor σ and every `τ ∈ [T_mσ, T_Mσ]`,
//!
//! ```text
//! Ξ_σ(τ) = [ Qᵀ Φ_σ(τ) Q   ⋆  ] ≻ 0,   Φ_σ(τ) = e^{−Aᵀτ} P_σ e^{−Aτ},                      (44)
//!          [ P_Γ Q        P_Γ ]
//! ```
//!
//! with `Q` a basis of `ker C_σ` and `P_Γ = P_Γ(σ)`. By Theorem 4 (the congruence and Schur
//! complement (46)) it is equivalent to the Lyapunov decrease (29) at the jump of the observer
//! with the gain schedule `K_σ(τ)` of (45), so it certifies the gains of the design, which are
//! (45) of the certificate `P_σ`: the prover first checks that the report's gains are (45) of its
//! certificate (in floating point, at the listed `τ`); a gain that is not is `not_proved`, with a
//! rigorous enclosure of `λ_min` of (37) `M = Φ_σ − (I − K_σC_σ)ᵀP_Γ(I − K_σC_σ)` for the given
//! gain at its worst listed `τ` (a rigorous disproof when that enclosure lies below zero).
//!
//! # How
//!
//! * **Exact kernel.** The floating-point orthonormal complement `C^⊥` is not exactly in
//!   `ker C_σ`; the prover uses `Q = C^⊥ − C_σᵀ(C_σC_σᵀ)⁻¹C_σC^⊥`, enclosed in interval
//!   arithmetic (verified inverse of `C_σC_σᵀ`), whose exact member is in `ker C_σ`; it has full
//!   column rank whenever the top block of `Ξ_σ` is proven positive definite.
//! * **Pieces.** On a piece `[a, b]` of the window, `Ξ_σ(τ)` is compared with its chord
//!   `χ(τ)` through `Ξ_σ(a)` and `Ξ_σ(b)`: `Ξ_σ(τ) − χ(τ) = −∫G(τ, s)Ξ_σ''(s)ds` with the Green
//!   kernel `G ≥ 0`, `∫G ≤ (b − a)²/8`, so `‖Ξ_σ(τ) − χ(τ)‖₂ ≤ ρ = (b − a)²/8 · sup‖QᵀΦ_σ''Q‖₂`
//!   with `Φ_σ'' = A²ᵀΦ_σ + 2AᵀΦ_σA + Φ_σA²`, enclosed with the hull of `e^{−Aτ}` over the piece
//!   (`sporadic_interval::expm_enclosure`, one piece). `λ_min` is concave, so
//!   `λ_min(Ξ_σ(τ)) ≥ min(ℓ(a), ℓ(b)) − ρ` on the piece, where `ℓ(t)` is the rigorous lower bound
//!   of Rump's verified definiteness test (`is_verified_positive_definite`) on the point
//!   enclosure of `Ξ_σ(t)`. The remainder is of second order in the piece length, so far fewer
//!   pieces are needed than with a first-order (Lipschitz) enclosure.
//! * **Verdicts.** Positive bound: the piece holds. Otherwise, if an end point's `λ_min(Ξ_σ)`
//!   is enclosed below zero (`lambda_max_enclosure` of `−Ξ_σ`) the condition fails there (a
//!   rigorous disproof); else the piece is bisected ([`sporadic_model::prove_on_window`]).
//! * **Margin.** The bounds are divided by a rigorous upper bound of `max_σ λ_max(P_σ)`, as the
//!   design's margin (scale-free: (44) is homogeneous in the `P_σ`).
//!
//! The proof runs on the plant as the user gave it (the report's gains and certificate are in
//! the user's coordinates). Where it is inconclusive there — a certificate far from the identity
//! in those coordinates, e.g. one designed in the Gramian normal form and mapped back, whose
//! `Ξ_σ(τ)` has entries far above its `λ_min` — it is made again in the certificate's own
//! coordinates `x' = Rx`, `RᵀR = Σ_σ P_σ/‖P_σ‖_max`, with the transformed data enclosed through
//! a verified inverse of `R` (`ProofData`): still a proof about the plant as given, since
//! `Ξ'_σ(τ)` is a congruence of `Ξ_σ(τ)`.
//!
//! * **Long windows.** `QᵀΦ_σ(τ)Q` grows like `‖e^{−Aτ}‖²` while `λ_min(Ξ_σ)` stays of the
//!   order of `P_Γ`, so the absolute remainder `ρ` needs pieces shrinking like
//!   `‖e^{−Aτ}‖⁻¹`. Where the chord bound fails, the piece is tested on the Schur complement
//!   `QᵀΦ_σQ − QᵀP_ΓQ` (`P_Γ ≻ 0` proven) after a congruence by a constant `F` that makes it
//!   near `I` at the piece's midpoint; its remainder is relative, of the order of
//!   `‖A‖²(b − a)²`, and the bound is mapped back to `λ_min(Ξ_σ)` by the block LDLᵀ
//!   factorisation (`SensorCondition::scaled_chord`).
//!
//! The same subdivision proves the validation (48) of the design loop, `Ξ_σ(τ) ≻ μI`, over a
//! whole window in place of its grid (49) ([`crate::validation::validate_window`]): a piece
//! holds by the chord bound on `Ξ_σ − μI` or on its Schur complement
//! `QᵀΦ_σQ − μI − QᵀP_Γ(P_Γ − μI)⁻¹P_ΓQ` (`P_Γ − μI ≻ 0` proven), whose margin grows with
//! `QᵀΦ_σQ` on long windows.

use std::collections::HashMap;
use std::time::Instant;

use faer::linalg::triangular_solve::solve_upper_triangular_in_place;
use faer::{Mat, Par};
use sporadic_interval::{
    EnclosureOptions, Interval, IntervalError, IntervalMatrix, Verdict, expm_enclosure,
    expm_enclosure_interval, is_verified_positive_definite, lambda_max_enclosure,
};
use sporadic_model::{
    Gain, PieceCheck, Proof, ProofOptions, ProofPiece, ProofStatus, WindowProof, combine,
    prove_on_window,
};

use crate::error::{Error, sig4};
use crate::gain::GainSchedule;
use crate::normalise::Coordinates;
use crate::plant::RoundRobinPlant;

/// Pieces each window starts with (the driver bisects where the margin is thin).
const INITIAL_PIECES: usize = 16;

/// Largest relative deviation of a reported gain from (45) of the certificate that counts as
/// the same gain (rounding of the design's balanced coordinates mapped back).
pub(crate) const GAIN_TOLERANCE: f64 = 1e-6;

/// The interval data of (44), or of the validation (48), for one sensor.
struct SensorCondition {
    /// Encloses `−A`.
    neg_a: IntervalMatrix,
    /// Encloses a basis of `ker C_σ` (`n × r`).
    q: IntervalMatrix,
    p: IntervalMatrix,
    p_next: IntervalMatrix,
    /// `P_Γ Q`.
    off: IntervalMatrix,
    /// The level μ of the condition `Ξ_σ(τ) ≻ μI`: 0 for (44), μ for (48).
    mu: f64,
    /// For the validation (48) (`P_Γ − μI ≻ 0` proven): an enclosure of the constant
    /// `QᵀP_Γ(P_Γ − μI)⁻¹P_ΓQ`, so that `Ξ_σ(τ) − μI ≻ 0` is also tested on its Schur complement
    /// `QᵀΦ_σ(τ)Q − R_μ`, `R_μ = μI + QᵀP_Γ(P_Γ − μI)⁻¹P_ΓQ`. `None` for (44).
    coupling: Option<IntervalMatrix>,
    /// `A²ᵀP_σ + 2AᵀP_σA + P_σA²`: `Φ_σ'' = e^{−Aᵀτ}(·)e^{−Aτ}` (`e^{−Aτ}` commutes with `A`).
    curvature: IntervalMatrix,
    /// For (44) (`P_Γ ≻ 0` proven, with the rigorous lower bound `ℓ_Γ` of `λ_min(P_Γ)`): the
    /// Schur complement constant `QᵀP_ΓQ` (`Ξ_σ ≻ 0 ⇔ QᵀΦ_σQ − QᵀP_ΓQ ≻ 0`), `ℓ_Γ` and an upper
    /// bound of `‖Q‖₂`, for [`Self::scaled_chord`]. `None` for (48) (`coupling` serves).
    plain_schur: Option<(IntervalMatrix, f64, f64)>,
    /// Rigorous lower bounds `ℓ(τ)` of `λ_min(Ξ_σ(τ) − μI)` and of `λ_min` of its Schur
    /// complement already computed (`None`: not proven positive, or no Schur complement), by
    /// the bits of τ.
    ends: HashMap<u64, [Option<f64>; 2]>,
    /// Point enclosures of `e^{−Aτ}Q` by the bits of τ (a piece's midpoint becomes the end of
    /// its halves when the driver bisects, and neighbouring pieces share an end).
    eq_cache: HashMap<u64, IntervalMatrix>,
}

/// The data of (44) as the proof uses it: `A`, each `C_σ` and `P_σ` as interval matrices, and
/// a floating-point orthonormal complement of each `C_σ` (any near basis serves: the proof
/// projects it onto the exact kernel). Point matrices in the plant's coordinates, or enclosures
/// of the same data in the coordinates of the certificate.
struct ProofData {
    a: IntervalMatrix,
    c: Vec<IntervalMatrix>,
    c_perp: Vec<Mat<f64>>,
    p: Vec<IntervalMatrix>,
    next: Vec<usize>,
}

impl ProofData {
    /// The plant's data and the certificate `p` as they are.
    fn point(plant: &RoundRobinPlant, p: &[Mat<f64>]) -> Result<Self, Error> {
        Ok(Self {
            a: point(&plant.a().to_owned())?,
            c: plant
                .sensors()
                .iter()
                .map(|s| point(&s.c().to_owned()))
                .collect::<Result<_, _>>()?,
            c_perp: plant
                .sensors()
                .iter()
                .map(|s| s.c_perp().to_owned())
                .collect(),
            p: p.iter().map(point).collect::<Result<_, _>>()?,
            next: (0..plant.num_sensors()).map(|s| plant.next(s)).collect(),
        })
    }

    /// The same data in the coordinates `x' = Rx` of the certificate, `RᵀR = Σ_σ P_σ/‖P_σ‖_max`
    /// (Cholesky), in which the `P'_σ` are near the identity however ill-conditioned the `P_σ`
    /// are in the plant's coordinates: with `X ∋ R⁻¹` (a verified inverse), `A' = R·A·X`,
    /// `C'_σ = C_σ·X` and `P'_σ = Xᵀ·P_σ·X` enclose `RAR⁻¹`, `C_σR⁻¹` and `R⁻ᵀP_σR⁻¹`. (44)
    /// of the enclosed data is (44) of the plant: with `Q' = RQ` a basis of `ker C'_σ`,
    /// `Ξ'_σ(τ) = diag(I, R⁻ᵀ) Ξ_σ(τ) diag(I, R⁻¹)`, a congruence. `None` when the sum is not
    /// numerically positive definite or the inverse of `R` is not proven.
    fn in_certificate_coordinates(
        plant: &RoundRobinPlant,
        p: &[Mat<f64>],
    ) -> Result<Option<Self>, Error> {
        let Some(r) = sporadic_linalg::symmetric::certificate_root(p) else {
            return Ok(None);
        };
        let r = point(&r)?;
        let Some(x) = r.verified_inverse()? else {
            return Ok(None);
        };
        let a = r.checked_mul(&point(&plant.a().to_owned())?.checked_mul(&x)?)?;
        let c: Vec<IntervalMatrix> = plant
            .sensors()
            .iter()
            .map(|s| point(&s.c().to_owned())?.checked_mul(&x))
            .collect::<Result<_, _>>()?;
        let c_perp = c
            .iter()
            .map(|ck| sporadic_linalg::null_space(ck.mid()))
            .collect::<Result<_, _>>()?;
        let p = p
            .iter()
            .map(|pk| x.transpose().checked_mul(&point(pk)?.checked_mul(&x)?))
            .collect::<Result<_, _>>()?;
        Ok(Some(Self {
            a,
            c,
            c_perp,
            p,
            next: (0..plant.num_sensors()).map(|s| plant.next(s)).collect(),
        }))
    }

    /// The proof of (44) on every sensor's window with this data, the bounds divided by a
    /// rigorous upper bound of `max_σ λ_max(P_σ)` (`None` when there is no positive finite one).
    fn prove(
        &self,
        plant: &RoundRobinPlant,
        options: &ProofOptions,
    ) -> Result<Option<Vec<WindowProof>>, Error> {
        let mut scale = 0.0f64;
        for pk in &self.p {
            scale = scale.max(lambda_max_enclosure(&pk.symmetrized()?)?.hi());
        }
        if !(scale > 0.0 && scale.is_finite()) {
            return Ok(None);
        }
        let mut parts: Vec<WindowProof> = Vec::with_capacity(plant.num_sensors());
        for (s, sensor) in plant.sensors().iter().enumerate() {
            let mut cond = SensorCondition::new(self, s)?;
            let w = sensor.window();
            let part = prove_on_window(
                &format!("(44), sensor {}", s + 1),
                w.t1(),
                w.t2(),
                INITIAL_PIECES,
                options,
                &mut |a, b| cond.check(a, b, scale),
            )?;
            let stop = part.status != ProofStatus::Proved;
            parts.push(part);
            if stop {
                break;
            }
        }
        Ok(Some(parts))
    }
}

/// The gain law (45) of the certificate `p` evaluated in its own coordinates `x' = Rx`
/// ([`sporadic_linalg::symmetric::certificate_root`]), `K = R⁻¹K'`: where the `P_σ` are
/// ill-conditioned in the plant's coordinates (a certificate designed in the Gramian normal
/// form and mapped back), (45) evaluated there loses about `u·κ(P_σ)` of relative accuracy, in
/// these about `u·κ(R)`.
struct LawInCertificateCoordinates {
    schedule: GainSchedule,
    own: Coordinates,
}

impl LawInCertificateCoordinates {
    fn new(plant: &RoundRobinPlant, p: &[Mat<f64>]) -> Option<Self> {
        let own = Coordinates::of_certificate(p)?;
        let ps = p.iter().map(|pk| own.form_to(pk.as_ref())).collect();
        let schedule = GainSchedule::new(own.plant(plant).ok()?, ps).ok()?;
        Some(Self { schedule, own })
    }

    fn gain(&self, sigma: usize, tau: f64) -> Option<Mat<f64>> {
        let k = self.schedule.gain(sigma, tau).ok()?;
        Some(self.own.gain_back(k.as_ref()))
    }
}

fn point(m: &Mat<f64>) -> Result<IntervalMatrix, IntervalError> {
    IntervalMatrix::from_point(m.as_ref())
}

/// A rigorous lower bound of `λ_min(x)` when `x` is proven positive definite.
fn proven_lower(x: &IntervalMatrix) -> Result<Option<f64>, Error> {
    Ok(match is_verified_positive_definite(x)? {
        Verdict::Proved { bound } => Some(bound),
        Verdict::NotProved => None,
    })
}

/// `None` when the interval evaluation left the range of double precision (far into a long
/// window, `e^{−Aτ}` and the products formed from it overflow): the piece check then declines
/// what it was computing, as for an enclosure too wide to decide, and the driver splits the
/// piece or gives it up as undecided. Other errors are kernel failures and pass through.
fn unless_overflow<T>(r: Result<T, Error>) -> Result<Option<T>, Error> {
    match r {
        Ok(v) => Ok(Some(v)),
        Err(Error::Enclosure(e)) if e.is_overflow() => Ok(None),
        Err(e) => Err(e),
    }
}

impl SensorCondition {
    /// The condition (44) `Ξ_σ(τ) ≻ 0` for sensor `sigma` and the data `data`.
    fn new(data: &ProofData, sigma: usize) -> Result<Self, Error> {
        let c = data.c[sigma].clone();
        let c_perp = point(&data.c_perp[sigma])?;
        let cct = c.checked_mul(&c.transpose())?;
        let inv = cct.verified_inverse()?.ok_or_else(|| {
            Error::invalid(format!(
                "C_{} C_{}ᵀ is not proven nonsingular: the sensor's output matrix has no verified \
                 full row rank",
                sigma + 1,
                sigma + 1
            ))
        })?;
        let q = if c_perp.ncols() == 0 {
            c_perp
        } else {
            c_perp.checked_sub(
                &c.transpose()
                    .checked_mul(&inv)?
                    .checked_mul(&c.checked_mul(&c_perp)?)?,
            )?
        };
        // Symmetrised: a certificate may be symmetric only to rounding (`check_sym`), and the
        // verified definiteness test and the block LDLᵀ bound need symmetric matrices.
        let p_next = data.p[data.next[sigma]].symmetrized()?;
        let (a, ps) = (data.a.clone(), data.p[sigma].symmetrized()?);
        let (at, pa) = (a.transpose(), ps.checked_mul(&a)?);
        let curvature = at
            .checked_mul(&at.checked_mul(&ps)?)?
            .checked_add(&at.checked_mul(&pa)?.scale(Interval::point(2.0)?))?
            .checked_add(&pa.checked_mul(&a)?)?;
        let off = if q.ncols() == 0 {
            q.clone()
        } else {
            p_next.checked_mul(&q)?
        };
        let plain_schur = match proven_lower(&p_next)? {
            Some(l) if q.ncols() > 0 => Some((
                q.transpose().checked_mul(&off)?.symmetrized()?,
                l,
                q.norm_2_up(),
            )),
            _ => None,
        };
        Ok(Self {
            // Negated exactly (`scale` by −1 would add a rounding radius to every entry).
            neg_a: -&data.a,
            q,
            p: ps,
            p_next,
            off,
            mu: 0.0,
            coupling: None,
            curvature,
            plain_schur,
            ends: HashMap::new(),
            eq_cache: HashMap::new(),
        })
    }

    /// The validation condition (48) `Ξ_σ(τ) ≻ μI` (see `coupling`).
    ///
    /// # Errors
    /// `P_Γ − μI` not proven positive definite (then (48) fails at every τ: it is a principal
    /// block of `Ξ_σ(τ) − μI`) or without a verified inverse, or a failing kernel.
    fn shifted(data: &ProofData, sigma: usize, mu: f64) -> Result<Self, Error> {
        let mut c = Self::new(data, sigma)?;
        let n = c.p_next.nrows();
        let shifted = c
            .p_next
            .checked_sub(&IntervalMatrix::identity(n).scale(Interval::point(mu)?))?
            .symmetrized()?;
        let not_definite = || {
            Error::invalid(format!(
                "P_Γ − μI of sensor {} is not proven positive definite",
                sigma + 1
            ))
        };
        if proven_lower(&shifted)?.is_none() {
            return Err(not_definite());
        }
        let inv = shifted.verified_inverse()?.ok_or_else(not_definite)?;
        c.mu = mu;
        c.plain_schur = None;
        if c.r() > 0 {
            c.coupling = Some(
                c.off
                    .transpose()
                    .checked_mul(&inv.checked_mul(&c.off)?)?
                    .symmetrized()?,
            );
        }
        Ok(c)
    }

    fn r(&self) -> usize {
        self.q.ncols()
    }

    /// Encloses `Ξ_σ(τ) − μI` ((44) with μ = 0) at `τ`.
    fn xi(&mut self, tau: f64) -> Result<IntervalMatrix, Error> {
        let (n, r) = (self.p_next.nrows(), self.r());
        let x = if r == 0 {
            self.p_next.clone()
        } else {
            let eq = self.eq_at(tau)?;
            let top = eq.transpose().checked_mul(&self.p.checked_mul(&eq)?)?;
            IntervalMatrix::from_fn(r + n, r + n, |i, j| match (i < r, j < r) {
                (true, true) => top.get(i, j),
                (false, true) => self.off.get(i - r, j),
                (true, false) => self.off.get(j - r, i),
                (false, false) => self.p_next.get(i - r, j - r),
            })
        };
        let x = if self.mu == 0.0 {
            x
        } else {
            x.checked_sub(&IntervalMatrix::identity(r + n).scale(Interval::point(self.mu)?))?
        };
        Ok(x.symmetrized()?)
    }

    /// The point enclosure of `e^{−Aτ}Q` (cached in `eq_cache`).
    fn eq_at(&mut self, tau: f64) -> Result<IntervalMatrix, Error> {
        if let Some(eq) = self.eq_cache.get(&tau.to_bits()) {
            return Ok(eq.clone());
        }
        let e = expm_enclosure_interval(&self.neg_a, tau, tau, &one_piece())?.enclosure;
        let eq = e.checked_mul(&self.q)?;
        self.eq_cache.insert(tau.to_bits(), eq.clone());
        Ok(eq)
    }

    /// `[ℓ(τ), ℓ_S(τ)]`: rigorous lower bounds of `λ_min(Ξ_σ(τ) − μI)` and, for (48), of
    /// `λ_min(QᵀΦ_σ(τ)Q − R_μ)` (the top block of `Ξ_σ(τ) − μI` minus `coupling`); `None` when
    /// not proven positive.
    fn end(&mut self, tau: f64) -> Result<[Option<f64>; 2], Error> {
        if let Some(&l) = self.ends.get(&tau.to_bits()) {
            return Ok(l);
        }
        let Some(x) = unless_overflow(self.xi(tau))? else {
            self.ends.insert(tau.to_bits(), [None, None]);
            return Ok([None, None]);
        };
        let schur = match &self.coupling {
            Some(k) => {
                let r = self.r();
                let top = IntervalMatrix::from_fn(r, r, |i, j| x.get(i, j));
                proven_lower(&top.checked_sub(k)?.symmetrized()?)?
            }
            None => None,
        };
        let l = [proven_lower(&x)?, schur];
        self.ends.insert(tau.to_bits(), l);
        Ok(l)
    }

    /// `ρ = (b − a)²/8 · sup_{[a,b]} ‖QᵀΦ_σ''Q‖₂` (rounded up), and the relative width of the
    /// hull of `e^{−Aτ}` over the piece (the only τ-dependent block of either matrix is
    /// `QᵀΦ_σQ`). The factor `(b − a)²/8` is applied to the curvature matrix before the
    /// products, which therefore hold `(b − a)²A²`-sized terms, the same in any unit of time.
    fn remainder(&self, a: f64, b: f64) -> Result<(f64, f64), Error> {
        if self.r() == 0 {
            return Ok((0.0, 0.0));
        }
        let e = expm_enclosure_interval(&self.neg_a, a, b, &one_piece())?.enclosure;
        let eq = e.checked_mul(&self.q)?;
        let d2 = eq
            .transpose()
            .checked_mul(&self.chord_curvature(a, b)?.checked_mul(&eq)?)?;
        let rho = d2.norm_2_up();
        if !rho.is_finite() {
            return Err(IntervalError::Overflow("chord remainder").into());
        }
        Ok((rho, e.rel_width()))
    }

    /// `(b − a)²/8` times the curvature matrix `A²ᵀP_σ + 2AᵀP_σA + P_σA²`, so that
    /// `sup‖Mᵀ(·)M‖₂` over the piece, `M` its enclosure of `e^{−Aτ}Q` (or of `e^{−Aτ}QF`), is
    /// the chord remainder `ρ` (module docs).
    fn chord_curvature(&self, a: f64, b: f64) -> Result<IntervalMatrix, Error> {
        let h = Interval::point(b)? - Interval::point(a)?;
        Ok(self.curvature.scale(h.sqr() / Interval::point(8.0)?))
    }

    /// The chord test of the validation's Schur complement `Y(τ) = QᵀΦ_σ(τ)Q − R_μ` after a
    /// congruence by a constant `F`: on long windows `QᵀΦ_σQ` grows like `‖e^{−Aτ}‖²`, so the
    /// remainder `ρ` of [`Self::remainder`] (absolute, `∝ ‖Φ_σ''‖`) exceeds `λ_min(Y)` unless the
    /// pieces are tiny, although `Y` varies little *relative to itself* over a piece. With
    /// `F ≈ Y(m)^{−1/2}` from the piece's midpoint `m` in floating point (any `F` is sound: the
    /// proof below needs no property of it),
    /// `FᵀY(τ)F = G(τ)ᵀP_σG(τ) − FᵀR_μF` with `G(τ) = e^{−A(τ−a)}·e^{−Aa}QF` is near `I` on the
    /// piece, its second derivative is `G(τ)ᵀ(A²ᵀP_σ + 2AᵀP_σA + P_σA²)G(τ)`, of the size of
    /// `‖A‖²` (not of `‖Φ_σ''‖`), and the chord bound `ℓ_F = min(λ_min(FᵀY(a)F),
    /// λ_min(FᵀY(b)F)) − (b − a)²/8 · sup‖(FᵀYF)''‖₂` is relative. `ℓ_F > 0` proves `Y(τ) ≻ 0` on
    /// the piece (`F` is then nonsingular, or `FᵀYF` could not be definite), and
    /// `λ_min(Y) ≥ ℓ_F/‖F‖₂²` is returned with the relative width of the hull of `e^{−As}`,
    /// `s ∈ [0, b − a]`. For (44) (`R_0 = QᵀP_ΓQ`) the returned bound is one of `λ_min(Ξ_σ)`
    /// itself: `Ξ_σ = Lᵀdiag(Y, P_Γ)L` with `L = [I 0; Q I]` (block LDLᵀ), so
    /// `λ_min(Ξ_σ) ≥ min(λ_min(Y), λ_min(P_Γ))/‖L⁻¹‖₂²` and `‖L⁻¹‖₂ ≤ 1 + ‖Q‖₂`. `None` when
    /// there is no Schur complement, or when the test does not hold.
    fn scaled_chord(&mut self, a: f64, b: f64) -> Result<Option<(f64, f64)>, Error> {
        let r = self.r();
        let r_mu = match (&self.coupling, &self.plain_schur) {
            (Some(coupling), _) => coupling
                .checked_add(&IntervalMatrix::identity(r).scale(Interval::point(self.mu)?))?,
            (None, Some((r0, ..))) => r0.clone(),
            (None, None) => return Ok(None),
        };
        // F from the midpoint in floating point, graded: with e^{−Am}Q = UT (QR), Y(m) =
        // Tᵀ(UᵀP_σU − T⁻ᵀR_μT⁻¹)T, whose middle factor is of the size of P_σ however far the
        // columns of e^{−Am}Q have grown apart (forming Y(m) itself would round its small
        // eigenvalues away); F = T⁻¹VΛ^{−1/2} with VΛVᵀ that middle factor.
        let eq = self.eq_at(a + 0.5 * (b - a))?.mid().to_owned();
        let mut t_inv = Mat::<f64>::identity(r, r);
        {
            let qr = eq.qr();
            let t = qr.R();
            solve_upper_triangular_in_place(t.get(..r, ..r), t_inv.as_mut(), Par::Seq);
        }
        let u = &eq * &t_inv;
        let (p, r_mu_mid) = (self.p.mid(), r_mu.mid());
        let y = u.transpose() * p * &u - t_inv.transpose() * r_mu_mid * &t_inv;
        let y = Mat::from_fn(r, r, |i, j| 0.5 * (y[(i, j)] + y[(j, i)]));
        if !y.norm_max().is_finite() {
            return Ok(None);
        }
        let Ok(eig) = y.self_adjoint_eigen(faer::Side::Lower) else {
            return Ok(None);
        };
        let (v, lambda) = (eig.U(), eig.S().column_vector());
        if !(0..r).all(|i| lambda[i] > 0.0 && lambda[i].is_finite()) {
            return Ok(None);
        }
        let f = &t_inv * Mat::from_fn(r, r, |i, j| v[(i, j)] / lambda[j].sqrt());
        // Non-finite data (an overflowing F, an unbounded enclosure) decline the piece.
        if !f.norm_max().is_finite() {
            return Ok(None);
        }
        let fi = point(&f)?;
        let ga = self.eq_at(a)?.checked_mul(&fi)?;
        let gb = self.eq_at(b)?.checked_mul(&fi)?;
        let frf = fi.transpose().checked_mul(&r_mu.checked_mul(&fi)?)?;
        let scaled_end = |g: &IntervalMatrix| -> Result<Option<f64>, Error> {
            let x = g
                .transpose()
                .checked_mul(&self.p.checked_mul(g)?)?
                .checked_sub(&frf)?
                .symmetrized()?;
            proven_lower(&x)
        };
        let (Some(la), Some(lb)) = (scaled_end(&ga)?, scaled_end(&gb)?) else {
            return Ok(None);
        };
        let h = Interval::point(b)? - Interval::point(a)?;
        let hull = expm_enclosure_interval(&self.neg_a, 0.0, h.hi(), &one_piece())?.enclosure;
        let g = hull.checked_mul(&ga)?;
        let d2 = g
            .transpose()
            .checked_mul(&self.chord_curvature(a, b)?.checked_mul(&g)?)?;
        let (rho, f_norm) = (d2.norm_2_up(), fi.norm_2_up());
        if !(rho.is_finite() && f_norm.is_finite()) {
            return Ok(None);
        }
        let lower = Interval::point(la.min(lb))? - Interval::point(rho)?;
        if !(lower.lo() > 0.0) {
            return Ok(None);
        }
        let f_norm = Interval::point(f_norm)?;
        let mut bound = Interval::point(lower.lo())? / f_norm.sqr();
        if let Some((_, l_gamma, q_norm)) = self.plain_schur {
            let l_inv = Interval::point(1.0)? + Interval::point(q_norm)?;
            bound = Interval::point(bound.lo().min(l_gamma))? / l_inv.sqr();
        }
        Ok(Some((bound.lo(), hull.rel_width())))
    }

    /// Enclosure of `λ_max(−(Ξ_σ(τ) − μI))` (the decisive quantity: the condition needs it
    /// below 0).
    fn decisive(&mut self, tau: f64) -> Result<Interval, Error> {
        let x = self.xi(tau)?;
        Ok(lambda_max_enclosure(&x.scale(Interval::point(-1.0)?))?)
    }

    /// The check of the condition on one piece, with the bounds divided by `scale` (rounded
    /// outward).
    ///
    /// Both matrices (`Ξ_σ − μI`, and for (48) its Schur complement) vary with τ only through
    /// `QᵀΦ_σQ`, so the chord bound `min(ℓ(a), ℓ(b)) − ρ` holds for either; the piece holds if
    /// it is positive for one of them. Where neither holds, the congruence-scaled chord test of
    /// the Schur complement ([`Self::scaled_chord`]) is tried. An undecided piece reports an enclosure of the decisive
    /// quantity's maximum over the piece: from its value at the midpoint up to the chord bound
    /// (negated) when an end pair is proven, else up to the enclosures at the ends. Its width
    /// shrinks with the piece while the variation over the piece decides, and stops shrinking
    /// once rounding does, which is what the driver's stall test needs.
    ///
    /// Where the interval evaluation overflows (far into a long window), the test that needed
    /// it is declined ([`unless_overflow`]) and the enclosure is unbounded on that side.
    fn check(&mut self, a: f64, b: f64, scale: f64) -> Result<PieceCheck, Error> {
        let (la, lb) = (self.end(a)?, self.end(b)?);
        let chord = (0..2)
            .filter_map(|k| Some(la[k]?.min(lb[k]?)))
            .reduce(f64::max);
        let mut upper = f64::NEG_INFINITY;
        if let Some(m) = chord {
            match unless_overflow(self.remainder(a, b))? {
                Some((rho, width)) => {
                    let lower = (Interval::point(m)? - Interval::point(rho)?).lo();
                    if lower > 0.0 {
                        return Ok(PieceCheck::Holds {
                            margin_lower_bound: divided(lower, scale)?[0],
                            enclosure_width: width,
                        });
                    }
                    upper = -lower;
                }
                None => upper = f64::INFINITY,
            }
        }
        if let Some((lower, width)) = unless_overflow(self.scaled_chord(a, b))?.flatten() {
            return Ok(PieceCheck::Holds {
                margin_lower_bound: divided(lower, scale)?[0],
                enclosure_width: width,
            });
        }
        for (t, l) in [(a, la), (b, lb)] {
            if l.iter().all(Option::is_none) {
                let [lo, hi] = self.decisive_or_unbounded(t)?;
                if lo >= 0.0 {
                    return Ok(PieceCheck::Fails {
                        enclosure: [divided(lo, scale)?[0], divided(hi, scale)?[1]],
                    });
                }
                upper = upper.max(hi);
            }
        }
        let [lo, hi] = self.decisive_or_unbounded(a + 0.5 * (b - a))?;
        Ok(PieceCheck::Undecided {
            enclosure: [divided(lo, scale)?[0], divided(upper.max(hi), scale)?[1]],
        })
    }

    /// [`Self::decisive`] as `[lo, hi]`, `[−∞, ∞]` where the evaluation overflows.
    fn decisive_or_unbounded(&mut self, tau: f64) -> Result<[f64; 2], Error> {
        Ok(unless_overflow(self.decisive(tau))?
            .map_or([f64::NEG_INFINITY, f64::INFINITY], |d| [d.lo(), d.hi()]))
    }
}

/// `[lo, hi]` enclosing `x/scale`; an infinite `x` stays infinite.
fn divided(x: f64, scale: f64) -> Result<[f64; 2], Error> {
    if x.is_infinite() {
        return Ok([x, x]);
    }
    let q = Interval::point(x)? / Interval::point(scale)?;
    Ok([q.lo(), q.hi()])
}

fn one_piece() -> EnclosureOptions {
    EnclosureOptions {
        max_pieces: 1,
        ..Default::default()
    }
}

/// The gains of `design` checked against (45) of `p`: `None` when every listed `K_σ(τ)`
/// matches, else the sensor, `τ`, the given gain and the relative deviation of the worst one.
///
/// # Errors
/// A missing or misshapen gain, or one listed outside the window that is not (45) of `p`
/// ([`Error::Input`]); a failing kernel.
pub(crate) fn gain_mismatch(
    plant: &RoundRobinPlant,
    p: &[Mat<f64>],
    gains: &[Gain],
) -> Result<Option<(usize, f64, Mat<f64>, f64)>, Error> {
    let schedule = GainSchedule::new(plant.clone(), p.to_vec())?;
    // Set up at the first deviation above the tolerance.
    let mut alternative: Option<Option<LawInCertificateCoordinates>> = None;
    let mut worst: Option<(usize, f64, Mat<f64>, f64)> = None;
    for (s, sensor) in plant.sensors().iter().enumerate() {
        let name = format!("K_{}", s + 1);
        let g = gains
            .iter()
            .find(|g| g.name == name)
            .ok_or_else(|| Error::invalid(format!("no gain {name}")))?;
        let listed: Vec<(f64, Mat<f64>)> = match &g.schedule {
            Some(sch) => {
                if sch.tau.len() != sch.samples.len() {
                    return Err(Error::invalid(format!(
                        "gain {name}: {} values of τ but {} samples",
                        sch.tau.len(),
                        sch.samples.len()
                    )));
                }
                sch.tau
                    .iter()
                    .zip(&sch.samples)
                    .map(|(&t, rows)| Ok((t, matrix(&name, rows)?)))
                    .collect::<Result<_, Error>>()?
            }
            None => vec![(sensor.window().t2(), g.to_mat())],
        };
        // A schedule listed beyond the window (a design of a larger window checked on a
        // sub-window) is checked at every listed τ: the listing must be (45) of the
        // certificate. A mismatch inside the window is the verdict's (a jump there); one
        // outside it is bad input (no jump happens there).
        let w = sensor.window();
        for (tau, k) in listed {
            if !(tau.is_finite() && tau >= 0.0) {
                return Err(Error::invalid(format!(
                    "gain {name} is listed at τ = {}, not a finite τ ≥ 0",
                    sig4(tau)
                )));
            }
            let inside = tau >= w.t1() && tau <= w.t2();
            if (k.nrows(), k.ncols()) != (plant.n(), sensor.outputs()) {
                return Err(Error::invalid(format!(
                    "gain {name} is {} × {}, expected {} × {}",
                    k.nrows(),
                    k.ncols(),
                    plant.n(),
                    sensor.outputs()
                )));
            }
            let deviation = |law: &Mat<f64>| {
                let dev = (&k - law).norm_max() / law.norm_max().max(f64::MIN_POSITIVE);
                if dev.is_nan() { f64::INFINITY } else { dev }
            };
            let mut dev = deviation(&schedule.gain(s, tau)?);
            if dev > GAIN_TOLERANCE
                && let Some(law) = alternative
                    .get_or_insert_with(|| LawInCertificateCoordinates::new(plant, p))
                    .as_ref()
                    .and_then(|l| l.gain(s, tau))
            {
                dev = dev.min(deviation(&law));
            }
            if dev > GAIN_TOLERANCE && !inside {
                return Err(Error::invalid(format!(
                    "gain {name} listed at τ = {} (outside the window {w}) is not (45) of the \
                     certificate (relative deviation {})",
                    sig4(tau),
                    sig4(dev)
                )));
            }
            if dev > GAIN_TOLERANCE && worst.as_ref().is_none_or(|w| dev > w.3) {
                worst = Some((s, tau, k, dev));
            }
        }
    }
    Ok(worst)
}

/// A gain's rows as a matrix (rows of equal length).
fn matrix(name: &str, rows: &[Vec<f64>]) -> Result<Mat<f64>, Error> {
    let cols = rows.first().map_or(0, Vec::len);
    if rows.iter().any(|r| r.len() != cols) || rows.is_empty() || cols == 0 {
        return Err(Error::invalid(format!("gain {name}: ragged or empty rows")));
    }
    Ok(Mat::from_fn(rows.len(), cols, |i, j| rows[i][j]))
}

/// Enclosure of `λ_max(−M)` for (37) `M = Φ_σ(τ) − (I − KC_σ)ᵀP_Γ(I − KC_σ)` with the given
/// gain `k` at `τ` (point enclosure of `e^{−Aτ}`): a lower end ≥ 0 disproves (29) there.
fn jump_decisive(
    plant: &RoundRobinPlant,
    p: &[Mat<f64>],
    sigma: usize,
    tau: f64,
    k: &Mat<f64>,
) -> Result<Interval, Error> {
    let n = plant.n();
    let neg_a = Mat::from_fn(n, n, |i, j| -plant.a()[(i, j)]);
    let e = expm_enclosure(neg_a.as_ref(), tau, tau, &one_piece())?.enclosure;
    let ps = point(&p[sigma])?;
    let phi = e.transpose().checked_mul(&ps.checked_mul(&e)?)?;
    let c = point(&plant.sensor(sigma)?.c().to_owned())?;
    let jump = IntervalMatrix::identity(n).checked_sub(&point(k)?.checked_mul(&c)?)?;
    let pn = point(&p[plant.next(sigma)])?;
    let m = phi.checked_sub(&jump.transpose().checked_mul(&pn.checked_mul(&jump)?)?)?;
    Ok(lambda_max_enclosure(
        &m.symmetrized()?.scale(Interval::point(-1.0)?),
    )?)
}

/// Proves (44) for every sensor and every `τ` of its window (see the module documentation)
/// for the certificate `p` (in the coordinates of `plant`), after checking that `gains` are
/// (45) of `p`.
///
/// # Errors
/// Bad input (missing or misshapen gains, a certificate of the wrong size) or a failing
/// kernel.
pub fn prove_design(
    plant: &RoundRobinPlant,
    p: &[Mat<f64>],
    gains: &[Gain],
    options: &ProofOptions,
) -> Result<Proof, Error> {
    let start = Instant::now();
    let condition = format!(
        "(44) of Theorem 4, Ξ_σ(τ) ≻ 0 for every sensor σ = 1…{} and every τ of its window, with \
         the certificate P_σ of the report; with the gains K_σ(τ) of (45) (checked to be those \
         of the report) it is the decrease (29) of V at every jump",
        plant.num_sensors()
    );
    let how = "exact kernel basis Q = C^⊥ − Cᵀ(CCᵀ)⁻¹CC^⊥ enclosed with a verified inverse; on \
               each τ-piece [a, b], Ξ_σ(τ) ⪰ chord − ρI with ρ = (b − a)²/8·sup‖QᵀΦ''Q‖₂ \
               (Φ'' enclosed with the hull of e^{−Aτ} over the piece, sporadic_interval::\
               expm_enclosure), λ_min concave, Rump's verified definiteness test at the piece \
               ends; where that fails, the same chord test on the Schur complement \
               QᵀΦQ − QᵀP_ΓQ after a congruence by F ≈ (·)^(−1/2) at the piece's midpoint \
               (remainder relative to QᵀΦQ, which grows like ‖e^{−Aτ}‖² on long windows), mapped \
               back to λ_min(Ξ_σ) by the block LDLᵀ bound; adaptive bisection; outward-rounded \
               interval arithmetic";
    let definition = "rigorous lower bound of min_σ min_τ λ_min(Ξ_σ(τ)) over the whole windows, \
                      divided by a rigorous upper bound of max_σ λ_max(P_σ) (the design's margin \
                      over the continuum of τ)";
    if let Some((s, tau, k, dev)) = gain_mismatch(plant, p, gains)? {
        let d = jump_decisive(plant, p, s, tau, &k)?;
        let disproved = d.lo() >= 0.0;
        let mut proof = Proof::not_attempted(
            ProofStatus::NotProved,
            format!(
                "the report's gain K_{}(τ) at τ = {} is not (45) of its certificate P_{} \
                 (relative deviation {}): the certificate does not certify it; λ_max(−M) of \
                 (37) for that gain there lies in [{}, {}]{}",
                s + 1,
                sig4(tau),
                s + 1,
                sig4(dev),
                sig4(d.lo()),
                sig4(d.hi()),
                if disproved {
                    ", so V increases at that jump (rigorous disproof of (29))"
                } else {
                    ""
                }
            ),
        );
        proof.condition = condition;
        proof.how = how.into();
        proof.margin_definition = definition.into();
        proof.failed_on = Some(ProofPiece {
            condition: format!("(29)/(37) with the reported K_{}", s + 1),
            tau: [tau, tau],
            enclosure: [d.lo(), d.hi()],
        });
        proof.seconds = start.elapsed().as_secs_f64();
        return Ok(proof);
    }
    let Some(parts) = ProofData::point(plant, p)?.prove(plant, options)? else {
        return Ok(Proof::not_attempted(
            ProofStatus::NotProved,
            "the certificate has no positive finite largest eigenvalue",
        ));
    };
    let proof = combine(
        condition.clone(),
        how,
        definition,
        parts,
        start.elapsed().as_secs_f64(),
    );
    // Undecided in the plant's coordinates (an ill-conditioned certificate, e.g. one designed in
    // the Gramian normal form and mapped back, whose Ξ_σ(τ) has entries far above its λ_min
    // there): the same condition in the certificate's own coordinates, with the change of
    // coordinates enclosed. A proof there replaces the undecided one; a refutation stands.
    if proof.status != ProofStatus::Inconclusive {
        return Ok(proof);
    }
    if let Some(data) = ProofData::in_certificate_coordinates(plant, p)?
        && let Some(parts) = data.prove(plant, options)?
        && parts.iter().all(|w| w.status == ProofStatus::Proved)
    {
        return Ok(combine(
            condition,
            format!(
                "{how}; in the coordinates x' = Rx of the certificate (RᵀR = Σ_σ P_σ/‖P_σ‖_max, \
                 Cholesky), with A' ∋ RAR⁻¹, C'_σ ∋ C_σR⁻¹ and P'_σ ∋ R⁻ᵀP_σR⁻¹ enclosed through \
                 a verified inverse of R (Ξ'_σ(τ) is a congruence of Ξ_σ(τ)), because the proof \
                 in the plant's coordinates was inconclusive"
            ),
            "rigorous lower bound of min_σ min_τ λ_min(Ξ'_σ(τ)) over the whole windows, divided \
             by a rigorous upper bound of max_σ λ_max(P'_σ), in the coordinates x' = Rx of the \
             certificate",
            parts,
            start.elapsed().as_secs_f64(),
        ));
    }
    Ok(proof)
}

/// The condition (44) of one sensor for fixed Lyapunov matrices, enclosed at single `τ` as the
/// proof tests a piece end (point enclosure of `e^{−Aτ}`, exact kernel basis `Q`): set up once
/// and queried at as many `τ` as needed.
pub(crate) struct XiDecisive(SensorCondition);

impl XiDecisive {
    /// The condition of sensor `sigma` for the Lyapunov matrices `p`.
    ///
    /// # Errors
    /// A failing kernel (e.g. `C_σC_σᵀ` not proven nonsingular).
    pub(crate) fn new(
        plant: &RoundRobinPlant,
        p: &[Mat<f64>],
        sigma: usize,
    ) -> Result<Self, Error> {
        Ok(Self(SensorCondition::new(
            &ProofData::point(plant, p)?,
            sigma,
        )?))
    }

    /// Encloses `λ_max(−Ξ_σ(τ))`: a lower end ≥ 0 shows that `Ξ_σ(τ)` is not positive definite,
    /// so (44) and, for every μ > 0, (48) fail at `τ`.
    ///
    /// # Errors
    /// A failing kernel, or an enclosure that overflows.
    pub(crate) fn at(&mut self, tau: f64) -> Result<Interval, Error> {
        self.0.decisive(tau)
    }
}

/// Tries to prove the validation condition (48), `Ξ_σ(τ) ≻ μI`, for **every** `τ` of sensor
/// σ's window (not only on the grid (49)), for the Lyapunov matrices `p` of the synthesis (47)
/// (scaled `I ⪯ P_σ`), by the adaptive subdivision of [`prove_design`] with at most
/// `max_pieces` pieces. With `P_Γ − μI ≻ 0` proven, a piece holds by the chord bound on
/// `Ξ_σ(τ) − μI` or on its Schur complement `QᵀΦ_σ(τ)Q − R_μ`,
/// `R_μ = μI + QᵀP_Γ(P_Γ − μI)⁻¹P_ΓQ` (the form of the grid's test): the first's margin stays
/// below `λ_min(P_Γ)` while `QᵀΦ_σQ` grows (long windows, fast stable modes), the second's
/// grows with it, and either may be the larger. A `proved` result implies (48) at every point
/// of any grid of the window, so it decides the validation step of §5.3 in place of the grid;
/// any other result (a failing point, the piece or time budget) leaves the decision to the
/// grid. Its margin lower bound is that of one of the two forms, not of `λ_min(Ξ_σ(τ))`.
///
/// # Errors
/// A failing kernel (e.g. `C_σC_σᵀ` not proven nonsingular, `P_Γ − μI` not proven positive
/// definite).
pub(crate) fn prove_validation(
    plant: &RoundRobinPlant,
    p: &[Mat<f64>],
    sigma: usize,
    mu: f64,
    max_pieces: usize,
) -> Result<WindowProof, Error> {
    let mut cond = SensorCondition::shifted(&ProofData::point(plant, p)?, sigma, mu)?;
    let w = plant.sensor(sigma)?.window();
    let options = ProofOptions {
        max_pieces,
        time_limit: None,
    };
    prove_on_window(
        &format!("(48), sensor {}", sigma + 1),
        w.t1(),
        w.t2(),
        INITIAL_PIECES,
        &options,
        &mut |a, b| cond.check(a, b, 1.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plant::test_util::{rr, win};
    use crate::validation::{UniformGrid, XiFamily, validate_naive};
    use faer::mat;

    /// The proof of (48) agrees with a fine grid: it is never `proved` at a level μ above the
    /// grid minimum of `λ_min(Ξ_σ)`, and it is proved at levels below it (by `Ξ_σ − μI` or its
    /// Schur complement, whichever holds on each piece). Two cases: two sensors whose `P_σ` fail
    /// (44) somewhere, and a stable plant with `P = I`, for which `Ξ(τ) ≻ 0` (its Schur
    /// complement `Qᵀ(e^{−Aᵀτ}e^{−Aτ} − I)Q` is positive definite).
    #[test]
    fn validation_proof_agrees_with_the_grid() {
        let two = rr(
            mat![[0.0, 1.0, 0.0], [-2.0, -0.3, 1.0], [0.5, 0.0, -1.0]],
            vec![
                (mat![[1.0, 0.0, 0.0]], win(0.1, 0.9)),
                (mat![[0.0, 0.0, 1.0]], win(0.2, 0.6)),
            ],
        )
        .unwrap();
        let p_two = vec![
            mat![[3.0, 0.5, 0.1], [0.5, 2.0, -0.3], [0.1, -0.3, 1.5]],
            mat![[2.0, -0.2, 0.0], [-0.2, 1.0, 0.4], [0.0, 0.4, 2.5]],
        ];
        let stable = rr(
            mat![[-1.0, 0.2, 0.0], [0.0, -2.0, 0.5], [0.0, 0.0, -0.5]],
            vec![(mat![[1.0, 0.0, 0.0]], win(0.1, 0.5))],
        )
        .unwrap();
        let p_stable = vec![Mat::identity(3, 3)];
        let mut proved = 0;
        for (plant, p) in [(&two, &p_two), (&stable, &p_stable)] {
            for sigma in 0..plant.num_sensors() {
                let fam = XiFamily::new(plant, p, sigma).unwrap();
                let w = plant.sensor(sigma).unwrap().window();
                let grid = UniformGrid::covering(w, 1e-4, 1e9).unwrap();
                let (_, lmin, _) = validate_naive(&fam, grid, 0.0).unwrap();
                for mu in [lmin + 1e-3, lmin + 0.1, 1.0] {
                    if let Ok(w) = prove_validation(plant, p, sigma, mu, 4096) {
                        assert_ne!(w.status, ProofStatus::Proved, "σ = {sigma}, μ = {mu}");
                    }
                }
                if lmin > 0.0 {
                    let w = prove_validation(plant, p, sigma, 0.5 * lmin, 4096).unwrap();
                    assert_eq!(w.status, ProofStatus::Proved, "σ = {sigma}: {}", w.message);
                    proved += 1;
                }
            }
        }
        assert!(proved >= 1);
    }

    /// A ship-heading plant (heading measured through `C = [1 0 0 0]`): an integrator, yaw and
    /// sway modes at −0.19 and −0.71, a rudder actuator at −2.5.
    fn ship_heading() -> Mat<f64> {
        mat![
            [0.0, 1.0, 0.0, 0.0],
            [0.0, -0.3, 0.05, 0.2],
            [0.0, 0.8, -0.6, 0.4],
            [0.0, 0.0, 0.0, -2.5]
        ]
    }

    /// On long windows the entries of `QᵀΦ_σ(τ)Q` grow like `‖e^{−Aτ}‖²` while the Schur
    /// complement's smallest eigenvalue stays of the order of `P`: a ship-heading plant
    /// (integrator, yaw and sway modes at −0.19 and −0.71, a rudder actuator at −2.5) with
    /// `P = I`, whose `λ_min(Ξ(τ))` (0.065 at `τ = T_m`, a float grid of spacing 10⁻³) is
    /// smallest at the short end. The absolute chord remainder needed more than 16384 pieces
    /// on `[0.5, 5.848]` (the window search then ran the 1.7·10⁹-point grid (49) for minutes);
    /// the congruence-scaled chord test proves `[0.5, 6]` and `[0.5, 12]` (`‖e^{−12A}‖ ≈ 10¹³`)
    /// in a few hundred pieces, and still refuses a level μ above the grid minimum.
    #[test]
    fn long_windows_are_proved_by_the_scaled_chord_test() {
        let a = ship_heading();
        let c = mat![[1.0, 0.0, 0.0, 0.0]];
        let p = vec![Mat::identity(4, 4)];
        let short = rr(a.clone(), vec![(c.clone(), win(0.5, 6.0))]).unwrap();
        let fam = XiFamily::new(&short, &p, 0).unwrap();
        let grid = UniformGrid::covering(win(0.5, 6.0), 1e-3, 1e9).unwrap();
        let (_, lmin, _) = validate_naive(&fam, grid, 0.0).unwrap();
        assert!((lmin - 0.065).abs() < 1e-3, "{lmin}");
        for t2 in [6.0, 12.0] {
            let plant = rr(a.clone(), vec![(c.clone(), win(0.5, t2))]).unwrap();
            let w = prove_validation(&plant, &p, 0, 0.5 * lmin, 16384).unwrap();
            assert_eq!(w.status, ProofStatus::Proved, "T_M = {t2}: {}", w.message);
            assert!(w.pieces < 1000, "T_M = {t2}: {} pieces", w.pieces);
        }
        // At μ = 1, P − μI is singular: the proof cannot be set up (an error, not a proof).
        for mu in [lmin + 1e-3, 0.5, 1.0] {
            if let Ok(w) = prove_validation(&short, &p, 0, mu, 4096) {
                assert_ne!(w.status, ProofStatus::Proved, "μ = {mu}");
            }
        }
    }

    /// A large grid on which the proof refutes (48) is not run: the validation fails at the
    /// refuted point at once (`points` 0). Ship-heading plant with `P = I`, whose `λ_min(Ξ)` is
    /// 0.065 at `τ = 0.5`, checked at μ = 0.5 on `[0.5, 12]` with a grid of 1.15·10⁸ points.
    #[test]
    fn a_refuted_large_grid_is_not_run() {
        use crate::validation::{
            REFUTED_POINT_FROM, ValidationOptions, WindowGrid, validate_window,
        };
        let a = ship_heading();
        let plant = rr(a, vec![(mat![[1.0, 0.0, 0.0, 0.0]], win(0.5, 12.0))]).unwrap();
        let p = vec![Mat::identity(4, 4)];
        let fam = XiFamily::new(&plant, &p, 0).unwrap();
        let grid = WindowGrid::covering(win(0.5, 12.0), 1e-7, 4e9).unwrap();
        assert!(grid.points() > REFUTED_POINT_FROM as f64);
        let v = validate_window(
            &fam,
            &plant,
            &p,
            grid,
            0.5,
            Some(16384),
            &ValidationOptions::default(),
        )
        .unwrap();
        assert!(!v.passed());
        assert_eq!(v.points, 0, "the grid was run");
        assert!(v.min_eigenvalue < 0.5, "{}", v.min_eigenvalue);
        assert!(v.argmin_tau >= 0.5 && v.argmin_tau <= 12.0);
    }
}
