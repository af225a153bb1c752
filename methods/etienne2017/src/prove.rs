//! Rigorous proof (issue 24, "Proofs, not samples") that a design of Etienne et al. (2017)
//! satisfies the hypotheses of Corollary 1 — hence the conclusion of Theorem 3 (Corollary 2,
//! Remark 6) — for **every** sampling interval `τ` of its window and **every** member of the
//! Jacobian polytope of Lemma 1, with the gain `K(τ)` the observer implements.
//!
//! With `P(τ) = (1 − τ/τ̄)P1 + (τ/τ̄)P2` (proof of Theorem 3) the conditions are
//!
//! ```text
//! (19a)  P(τ) ≻ 0                                              τ ∈ [0, τ̄]
//! (19b)  N_p(τ) = He(P(τ)R_p) + (P2 − P1)/τ̄ ≺ 0                 τ ∈ [0, τ̄], every vertex R_p
//! (16c)  J(τ) = (I − K(τ)C)'P1(I − K(τ)C) − P(τ) ≺ 0            τ ∈ [τ_low, τ̄]
//! ```
//!
//! ((16c) is the Schur form of (19c) with `L(τ) = P1K(τ)`, written with the implemented `K`
//! rather than with `L`, so the proof is about the observer as reported, not about the solver's
//! `L`.) They are proven on the exact sets, without sampling:
//!
//! * **τ**: `P(τ)` and `N_p(τ)` are affine in `τ`; `J(τ)` is convex in `τ` in the Loewner order
//!   (`K(τ)` is affine and `X ↦ X'P1X` is matrix-convex for `P1 ⪰ 0`: the gap of the chord is
//!   `θ(1 − θ)(X − Y)'P1(X − Y) ⪰ 0`). The set of negative definite matrices is convex, so each
//!   condition holds on its whole interval iff it holds at the interval's two ends: `τ = 0, τ̄`
//!   ((20a), (20b) and `P1, P2 ≻ 0`) and `τ = τ_low, τ̄` (the Schur forms of (20c), (20d)).
//! * **Jacobian set**: `N_p` is affine in `R`, so the vertices `R_p = A + GΘ_pH` of the box of
//!   Jacobians (each free entry of `Θ` at its lower or upper bound, Lemma 1) cover its convex
//!   hull, which contains every `A + GΘH` of the box.
//!
//! Each end is checked in outward-rounded interval arithmetic (`sporadic-interval`): `R_p`,
//! `P(τ_low)`, `(P2 − P1)/τ̄` and the products are enclosed, the matrix is symmetrised and
//! [`is_verified_negative_definite`] (Rump's verified Cholesky test) gives a rigorous upper
//! bound of its largest eigenvalue. When it does not prove the sign,
//! [`lambda_max_enclosure`] encloses the largest eigenvalue: a lower end `≥ 0` is a rigorous
//! disproof (`not_proved`). No matrix exponential is involved: the paper's conditions (20) need
//! none, and the discrete contraction `(I − K(τ)C)'e^{R_pτ}'P1e^{R_pτ}(I − K(τ)C) ≺ P1` that the
//! floating-point re-verification also samples is a consequence of (19b) and (16c).
//!
//! **Coordinates.** The report's `K`, `P1`, `P2` are in the plant's coordinates. The proof maps
//! the plant and `K` to the balanced coordinates `x_b = D⁻¹x` the method designs in
//! ([`crate::balanced_plant`]: `D⁻¹AD`, `CD`, `D⁻¹G`, `HD`, `D⁻¹K`, powers of 2, exact in
//! floating point, which is checked by mapping back) and `P ↦ DPD`; the conditions are
//! invariant under this congruence, and the margin then does not depend on the user's units.
//! Should the map not be exact (data near the overflow or underflow range) the proof is made in
//! the plant's coordinates.

use faer::{Mat, MatRef};
use sporadic_interval::{
    Interval, IntervalError, IntervalMatrix, Verdict, is_verified_negative_definite,
    lambda_max_enclosure,
};
use sporadic_linalg::balance::{balance_b, unbalance_a, unbalance_gain};
use sporadic_model::{
    DesignReport, Gain, MethodError, NamedMatrix, PieceCheck, Plant as ModelPlant, Proof,
    ProofOptions, SamplingWindow, WindowProof, combine, prove_on_window,
};

const ID: &str = "etienne2017";

/// Largest number of free Jacobian entries (`2^k` vertices), as in Lemma 1's builder.
const MAX_FREE_ENTRIES: usize = 20;

/// Bad input of the prover or of `verify` (a message, as a [`MethodError::InvalidInput`]).
pub(crate) fn bad(message: impl Into<String>) -> MethodError {
    MethodError::invalid(ID, message)
}

/// A failure of the interval kernels (not a verdict).
fn numerical(e: IntervalError) -> MethodError {
    MethodError::numerical(ID, e)
}

/// A gain schedule and certificate read from a report (or brought by the user), in the plant's
/// coordinates, with every shape checked.
#[derive(Debug, Clone)]
pub(crate) struct Given {
    /// `K0 = K(τ_low)`.
    pub k0: Mat<f64>,
    /// `K1 = K(τ̄)` (equal to `K0` for a static gain).
    pub k1: Mat<f64>,
    /// `(P1, P2)`, when the certificate has them.
    pub p: Option<(Mat<f64>, Mat<f64>)>,
    /// `(L0, L1)`, when the certificate has them (`L` of a static gain for both).
    pub l: Option<(Mat<f64>, Mat<f64>)>,
}

/// `rows` as a `rows × cols` matrix with finite entries, or bad input naming `what`.
fn shaped(m: &[Vec<f64>], rows: usize, cols: usize, what: &str) -> Result<Mat<f64>, MethodError> {
    sporadic_model::report::checked_mat(m, rows, cols, what).map_err(bad)
}

impl Given {
    /// Reads the gain `K` (constant, or the schedule `K(τ)` of Theorem 3 sampled from `T1` to
    /// `T2`) and the certificate `P1, P2` with `L` (static) or `L0, L1` (time-varying), for a
    /// plant with `n` states and `q` outputs on `window`.
    ///
    /// # Errors
    /// [`MethodError::InvalidInput`] for a gain other than one named `K`, a certificate matrix
    /// of another name, a wrong shape, a non-finite entry, a schedule that does not start at `T1`
    /// and end at `T2`, or a time-varying gain on a periodic window.
    pub fn read(
        n: usize,
        q: usize,
        window: &SamplingWindow,
        gains: &[Gain],
        certificate: &[NamedMatrix],
    ) -> Result<Self, MethodError> {
        let [gain] = gains else {
            return Err(bad(format!(
                "etienne2017 has one gain, K; {} gains were given",
                gains.len()
            )));
        };
        if gain.name != "K" {
            return Err(bad(format!(
                "etienne2017's gain is named K, not {:?}",
                gain.name
            )));
        }
        let (k0, k1) = match &gain.schedule {
            None => {
                let k = shaped(&gain.rows, n, q, "gain K")?;
                (k.clone(), k)
            }
            Some(s) => {
                let (Some(first), Some(last)) = (s.samples.first(), s.samples.last()) else {
                    return Err(bad("the schedule of K has no samples"));
                };
                if s.tau.len() != s.samples.len()
                    || s.tau.first() != Some(&window.t1())
                    || s.tau.last() != Some(&window.t2())
                {
                    return Err(bad(format!(
                        "the schedule of K must sample K(τ) from T1 = {} to T2 = {} (one sample \
                         per τ); K(τ) = K0 + (τ − T1)/(T2 − T1)·(K1 − K0) is read from its ends",
                        window.t1(),
                        window.t2()
                    )));
                }
                let k0 = shaped(first, n, q, "gain K(T1)")?;
                let k1 = shaped(last, n, q, "gain K(T2)")?;
                if window.is_periodic() && k0 != k1 {
                    return Err(bad(
                        "a periodic window has a static gain (Remark 6), but K(τ) varies",
                    ));
                }
                (k0, k1)
            }
        };
        let known = ["P1", "P2", "L", "L0", "L1"];
        if let Some(m) = certificate
            .iter()
            .find(|m| !known.contains(&m.name.as_str()))
        {
            return Err(bad(format!(
                "etienne2017's certificate has P1, P2 and L (static gain) or L0, L1; not {:?}",
                m.name
            )));
        }
        let get = |name: &str, rows: usize, cols: usize| -> Result<Option<Mat<f64>>, MethodError> {
            certificate
                .iter()
                .find(|m| m.name == name)
                .map(|m| shaped(&m.rows, rows, cols, &format!("certificate {name}")))
                .transpose()
        };
        let p = match (get("P1", n, n)?, get("P2", n, n)?) {
            (Some(p1), Some(p2)) => Some((p1, p2)),
            (None, None) => None,
            _ => return Err(bad("the certificate needs both P1 and P2")),
        };
        let l = match (get("L", n, q)?, get("L0", n, q)?, get("L1", n, q)?) {
            (Some(l), None, None) => Some((l.clone(), l)),
            (None, Some(l0), Some(l1)) => Some((l0, l1)),
            (None, None, None) => None,
            _ => {
                return Err(bad(
                    "the certificate has L (static gain) or both L0 and L1 (K(τ)), not a mix",
                ));
            }
        };
        Ok(Self { k0, k1, p, l })
    }
}

/// The vertices `R_p = A + GΘ_pH` of Lemma 1, enclosed in interval arithmetic (bit `j` of `p`
/// picks the upper bound of the `j`-th free entry of `Θ`, in row-major order, as the crate's
/// [`crate::Plant::vertices`]; fixed entries keep their value).
fn vertex_enclosures(
    a: MatRef<'_, f64>,
    g: MatRef<'_, f64>,
    h: MatRef<'_, f64>,
    lo: MatRef<'_, f64>,
    hi: MatRef<'_, f64>,
) -> Result<Vec<IntervalMatrix>, MethodError> {
    let m = lo.nrows();
    let free: Vec<(usize, usize)> = (0..m)
        .flat_map(|i| (0..m).map(move |j| (i, j)))
        .filter(|&(i, j)| lo[(i, j)] < hi[(i, j)])
        .collect();
    if free.len() > MAX_FREE_ENTRIES {
        return Err(bad(format!(
            "{} free Jacobian entries: more than {MAX_FREE_ENTRIES} (2^k vertices)",
            free.len()
        )));
    }
    let point = |x: MatRef<'_, f64>| IntervalMatrix::from_point(x).map_err(numerical);
    let (a, g, h) = (point(a)?, point(g)?, point(h)?);
    (0..1usize << free.len())
        .map(|v| {
            let mut theta = lo.to_owned();
            for (bit, &(i, j)) in free.iter().enumerate() {
                if v >> bit & 1 == 1 {
                    theta[(i, j)] = hi[(i, j)];
                }
            }
            let gth = g
                .checked_mul(&point(theta.as_ref())?)
                .and_then(|x| x.checked_mul(&h))
                .map_err(numerical)?;
            a.checked_add(&gth).map_err(numerical)
        })
        .collect()
}

/// The verdict on one symmetric condition matrix `x` that must be negative definite, with the
/// margin `−λmax(x)·factor/scale` (a rigorous lower bound when proved).
fn decide(
    x: &IntervalMatrix,
    factor: Interval,
    scale: Interval,
) -> Result<PieceCheck, IntervalError> {
    let x = x.symmetrized()?;
    if let Verdict::Proved { bound } = is_verified_negative_definite(&x)? {
        let margin = (Interval::point(-bound)? * factor) / scale;
        return Ok(PieceCheck::Holds {
            margin_lower_bound: margin.lo(),
            enclosure_width: x.rel_width(),
        });
    }
    let e = (lambda_max_enclosure(&x)? * factor) / scale;
    let enclosure = [e.lo(), e.hi()];
    Ok(if e.lo() >= 0.0 {
        PieceCheck::Fails { enclosure }
    } else {
        PieceCheck::Undecided { enclosure }
    })
}

/// One condition at one `τ` (a point window of [`prove_on_window`]).
fn at_point(
    condition: &str,
    tau: f64,
    x: &IntervalMatrix,
    factor: Interval,
    scale: Interval,
    options: &ProofOptions,
) -> Result<WindowProof, MethodError> {
    prove_on_window(condition, tau, tau, 1, options, &mut |_, _| {
        decide(x, factor, scale)
    })
    .map_err(numerical)
}

/// A rigorous upper bound of `max(λmax(P1), λmax(P2))` (the scale of the margins; 1 when it is
/// not positive, the positivity check then fails).
fn lyapunov_scale(p1: &IntervalMatrix, p2: &IntervalMatrix) -> Result<Interval, IntervalError> {
    let hi = lambda_max_enclosure(p1)?
        .hi()
        .max(lambda_max_enclosure(p2)?.hi());
    Interval::point(if hi > 0.0 && hi.is_finite() { hi } else { 1.0 })
}

/// The margin's definition in [`Proof::margin_definition`].
const MARGIN: &str = "the smallest of λmin(P1)/p̄, λmin(P2)/p̄ ((19a)), −τ̄·λmax(N_p(τ))/p̄ \
    ((19b), every vertex, τ = 0 and τ̄) and −λmax(J(τ))/p̄ ((16c), τ = τ_low and τ̄), with p̄ a \
    rigorous upper bound of max(λmax(P1), λmax(P2)): scale-free (invariant under scaling the \
    certificate and under a change of time unit); by affinity/convexity in τ these ends bound \
    the margin on the whole window from below";

/// Proves the conditions of the module docs for the gain and certificate of `design` (a
/// certified report of this method) on the plant `plant`.
///
/// # Errors
/// [`MethodError::InvalidInput`] for a report without a window, gain `K` or certificate
/// `P1, P2`, or of the wrong shapes; [`MethodError::Numerical`] for a failure of the interval
/// kernels.
pub fn prove_design(
    plant: &ModelPlant,
    design: &DesignReport,
    options: &ProofOptions,
) -> Result<Proof, MethodError> {
    let start = std::time::Instant::now();
    let window = design
        .window
        .ok_or_else(|| bad("the design report has no sampling window [T1, T2]"))?;
    let c = plant
        .c()
        .ok_or_else(|| bad("etienne2017 needs one output matrix C"))?;
    let lip = plant
        .lipschitz()
        .ok_or_else(|| bad("etienne2017 needs a Lipschitz nonlinearity (G, H, Jacobian bounds)"))?;
    let (n, q) = (plant.n(), c.nrows());
    let given = Given::read(n, q, &window, &design.gains, &design.certificate)?;
    let Some((p1, p2)) = &given.p else {
        return Err(bad("the design report's certificate has no P1, P2"));
    };
    let (balanced, d) =
        crate::method::balanced_plant(plant).map_err(|e| MethodError::InvalidInput {
            method: ID,
            source: Box::new(e),
        })?;
    // The balanced data, if the similarity is exact on the plant and the gain (checked by
    // mapping back; the certificate need not be exact: any P1, P2 that passes is a certificate).
    let (k0, k1) = (
        balance_b(given.k0.as_ref(), &d),
        balance_b(given.k1.as_ref(), &d),
    );
    let exact = unbalance_a(balanced.a(), &d) == plant.a()
        && unbalance_gain(balanced.g(), &d) == lip.g()
        && Mat::from_fn(q, n, |i, j| balanced.c()[(i, j)] / d[j]) == c
        && Mat::from_fn(lip.h().nrows(), n, |i, j| balanced.h()[(i, j)] / d[j]) == lip.h()
        && unbalance_gain(k0.as_ref(), &d) == given.k0
        && unbalance_gain(k1.as_ref(), &d) == given.k1;
    let form = |p: &Mat<f64>| Mat::from_fn(n, n, |i, j| p[(i, j)] * d[i] * d[j]);
    let (a, c, g, h, k0, k1, p1, p2) = if exact {
        (
            balanced.a(),
            balanced.c(),
            balanced.g(),
            balanced.h(),
            k0,
            k1,
            form(p1),
            form(p2),
        )
    } else {
        (
            plant.a(),
            c,
            lip.g(),
            lip.h(),
            given.k0.clone(),
            given.k1.clone(),
            p1.clone(),
            p2.clone(),
        )
    };
    let vertices = vertex_enclosures(a, g, h, lip.jacobian_lower(), lip.jacobian_upper())?;
    let point = |x: MatRef<'_, f64>| IntervalMatrix::from_point(x).map_err(numerical);
    // V = z'Pz sees only the symmetric part of P: enclose (P + P')/2.
    let sym = |x: &Mat<f64>| point(x.as_ref())?.symmetrized().map_err(numerical);
    let (p1, p2, c) = (sym(&p1)?, sym(&p2)?, point(c)?);
    let (t1, t2) = (window.t1(), window.t2());
    let tau_bar = Interval::point(t2).map_err(numerical)?;
    let one = Interval::ONE;
    let scale = lyapunov_scale(&p1, &p2).map_err(numerical)?;
    let dp = p2.checked_sub(&p1).map_err(numerical)?;
    let dp_rate = dp.scale(one / tau_bar);
    let mut parts = Vec::new();
    // (19a) at τ = 0 and τ̄: P1, P2 ≻ 0.
    for (name, tau, p) in [("P1", 0.0, &p1), ("P2", t2, &p2)] {
        parts.push(at_point(
            &format!("(19a) P(τ) ≻ 0 at τ = {tau} (P(τ) = {name})"),
            tau,
            &-p,
            one,
            scale,
            options,
        )?);
    }
    // (19b) at τ = 0 and τ̄, every vertex: (20a), (20b).
    for (v, r) in vertices.iter().enumerate() {
        for (eq, tau, p) in [("(20a)", 0.0, &p1), ("(20b)", t2, &p2)] {
            let pr = p.checked_mul(r).map_err(numerical)?;
            let x = pr
                .checked_add(&pr.transpose())
                .and_then(|x| x.checked_add(&dp_rate))
                .map_err(numerical)?;
            parts.push(at_point(
                &format!("(19b) at τ = {tau}, vertex R_{} (= {eq})", v + 1),
                tau,
                &x,
                tau_bar,
                scale,
                options,
            )?);
        }
    }
    // (16c) at τ_low and τ̄ (τ̄ only for a periodic window).
    let jump = |k: &Mat<f64>, tau: f64| -> Result<IntervalMatrix, MethodError> {
        let kc = point(k.as_ref())?.checked_mul(&c).map_err(numerical)?;
        let x = IntervalMatrix::identity(n)
            .checked_sub(&kc)
            .map_err(numerical)?;
        let p_tau = if tau == t2 {
            p2.clone()
        } else {
            let s = Interval::point(tau).map_err(numerical)? / tau_bar;
            p1.checked_add(&dp.scale(s)).map_err(numerical)?
        };
        x.transpose()
            .checked_mul(&p1)
            .and_then(|y| y.checked_mul(&x))
            .and_then(|y| y.checked_sub(&p_tau))
            .map_err(numerical)
    };
    let mut ends = vec![(t2, &k1, "(20d)")];
    if !window.is_periodic() {
        ends.insert(0, (t1, &k0, "(20c)"));
    }
    for (tau, k, eq) in ends {
        parts.push(at_point(
            &format!("(16c) at τ = {tau} (Schur form of {eq} with the implemented K({tau}))"),
            tau,
            &jump(k, tau)?,
            one,
            scale,
            options,
        )?);
    }
    let condition = format!(
        "Corollary 1 for the design's K(τ) and P(τ) = (1 − τ/τ̄)P1 + (τ/τ̄)P2 (Etienne et al. \
         2017, proof of Theorem 3): (19a) P(τ) ≻ 0 and (19b) He(P(τ)R_p) + (P2 − P1)/τ̄ ≺ 0 for \
         every τ ∈ [0, {t2}] and every member of the convex hull of the {} vertices R_p of the \
         Jacobian box (Lemma 1), and (16c) (I − K(τ)C)'P1(I − K(τ)C) − P(τ) ≺ 0 (the Schur form \
         of (19c)) for every τ ∈ [{t1}, {t2}]; proven at the ends of the τ-intervals, which \
         suffices because (19a), (19b) are affine and (16c) is Loewner-convex in τ, and (19b) is \
         affine in R_p; {}",
        vertices.len(),
        if exact {
            "in the balanced coordinates x_b = D⁻¹x of the design (A, C, G, H and K mapped \
             exactly, P ↦ DPD), where the margin does not depend on the user's units"
        } else {
            "in the plant's coordinates"
        }
    );
    let how = "outward-rounded interval arithmetic (sporadic-interval, midpoint–radius): the \
               vertices R_p = A + GΘ_pH, P(τ_low), (P2 − P1)/τ̄ and the products enclosed from \
               the report's K, P1, P2 and the plant's A, C, G, H and Jacobian bounds; Rump's \
               verified Cholesky test for the sign (rigorous λmax upper bound), a rigorous \
               λmax enclosure for a disproof; enclosure_width is the relative width of the \
               condition matrices (no exponential is needed)";
    Ok(combine(
        condition,
        how,
        MARGIN,
        parts,
        start.elapsed().as_secs_f64(),
    ))
}
