//! Rigorous enclosure of e^{Aτ} for all τ in a window [τ0, τ1].

use crate::round::{UNIT_ROUNDOFF, div_up, mul_up, sub_down, sub_up};
use crate::{Interval, IntervalError, IntervalMatrix};
use faer::MatRef;

/// Options of [`expm_enclosure`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnclosureOptions {
    /// Initial subdivision: pieces of half-length r with ‖A‖_∞·r ≤ `max_step_norm` (> 0).
    pub max_step_norm: f64,
    /// Adaptive subdivision: the piece whose enclosure has the largest relative width
    /// (largest entry width / largest |midpoint|) is bisected while that width exceeds
    /// `piece_rel_width` (> 0) …
    pub piece_rel_width: f64,
    /// … and there are fewer than `max_pieces` (≥ 1) pieces.
    pub max_pieces: usize,
}

impl Default for EnclosureOptions {
    fn default() -> Self {
        Self {
            max_step_norm: 0.5,
            piece_rel_width: 1e-3,
            max_pieces: 64,
        }
    }
}

/// One piece [τa, τb] of the window with an enclosure of {e^{Aτ} : τ ∈ [τa, τb]}.
#[derive(Debug, Clone, PartialEq)]
pub struct EnclosurePiece {
    /// Lower end τa of the piece.
    pub tau0: f64,
    /// Upper end τb of the piece.
    pub tau1: f64,
    /// Contains e^{Aτ} for every τ in [τa, τb].
    pub enclosure: IntervalMatrix,
}

/// Result of [`expm_enclosure`].
#[derive(Debug, Clone, PartialEq)]
pub struct ExpmEnclosure {
    /// Contains e^{Aτ} for every τ in [τ0, τ1] (the hull of the pieces).
    pub enclosure: IntervalMatrix,
    /// The pieces, in increasing τ, covering [τ0, τ1] without gaps (piece i ends where
    /// piece i + 1 starts). Tighter than the hull; use them for piecewise checks.
    pub pieces: Vec<EnclosurePiece>,
    /// Largest entry width of [`ExpmEnclosure::enclosure`].
    pub max_width: f64,
    /// `max_width` divided by the largest |midpoint| entry of the enclosure.
    pub rel_width: f64,
    /// Largest relative width over the pieces.
    pub max_piece_rel_width: f64,
}

/// Upper bound of the Taylor remainder Σ_{j>N} xʲ/j! for x ≥ 0:
/// min( x^{N+1}/(N+1)! · 1/(1 − x/(N+2)) [if x < N+2], x^{N+1}/(N+1)! · eˣ ).
///
/// Proof: (N+1+i)! ≥ (N+1)!·(N+2)ⁱ and (N+1+i)! ≥ (N+1)!·i! for i ≥ 0, so
/// Σ_{i≥0} x^{N+1+i}/(N+1+i)! ≤ x^{N+1}/(N+1)! · Σ_i (x/(N+2))ⁱ and ≤ x^{N+1}/(N+1)! · Σ_i xⁱ/i!.
pub(crate) fn taylor_remainder_up(x: f64, n: usize) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    // t = x^{N+1}/(N+1)!, rounded up.
    let mut t = 1.0;
    for j in 1..=(n + 1) {
        t = div_up(mul_up(t, x), j as f64);
    }
    let geo = if x < (n + 2) as f64 {
        let den = sub_down(1.0, div_up(x, (n + 2) as f64));
        if den > 0.0 {
            div_up(t, den)
        } else {
            f64::INFINITY
        }
    } else {
        f64::INFINITY
    };
    let expo = mul_up(t, crate::scalar::exp_up(x));
    geo.min(expo)
}

/// Largest Taylor degree tried.
const MAX_DEGREE: usize = 40;

/// Smallest degree N ≥ 1 with remainder bound ≤ `target` (or [`MAX_DEGREE`]).
fn pick_degree(x: f64, target: f64) -> (usize, f64) {
    let mut n = 1;
    loop {
        let rho = taylor_remainder_up(x, n);
        if rho <= target || n >= MAX_DEGREE {
            return (n, rho);
        }
        n += 1;
    }
}

/// Encloses e^X for every member X of the square interval matrix `m`.
///
/// Method: k ≥ 0 with ν·2⁻ᵏ ≤ 1 where ν ≥ ‖X‖_∞ for all members; Y = 2⁻ᵏ·m (outward rounded);
/// Taylor polynomial T_N(Y) = Σ_{j≤N} Yʲ/j! by Horner's rule in interval arithmetic; the
/// remainder satisfies ‖e^Y − T_N(Y)‖_∞ ≤ ρ_N(‖Y‖_∞) (the bound proven in [`expm_enclosure`]), and every entry
/// of a matrix is bounded by its ∞-norm, so adding [−ρ, ρ] to each entry encloses e^Y. Then
/// e^X = (e^Y)^{2ᵏ}: k interval squarings.
///
/// # Errors
/// [`IntervalError::EnclosureFailed`] if a radius overflows.
pub fn expm_interval(m: &IntervalMatrix) -> Result<IntervalMatrix, IntervalError> {
    let n = m.nrows();
    if m.ncols() != n {
        return Err(IntervalError::NotSquare {
            what: "interval matrix",
            rows: n,
            cols: m.ncols(),
        });
    }
    let nu = m.norm_inf_up();
    if !nu.is_finite() {
        return Err(IntervalError::EnclosureFailed(
            "unbounded interval matrix in the exponential",
        ));
    }
    let mut k: i32 = 0;
    let mut x = nu;
    while x > 1.0 {
        x *= 0.5;
        k += 1;
    }
    let y = if k == 0 {
        m.clone()
    } else {
        // 2^-k exactly (k ≤ 1025 because ν is finite).
        let mut s = 1.0f64;
        for _ in 0..k {
            s *= 0.5;
        }
        m.scale(Interval::raw(s, s))
    };
    let x = y.norm_inf_up();
    let (deg, rho) = pick_degree(x, UNIT_ROUNDOFF / 16.0);
    let id = IntervalMatrix::identity(n);
    let mut p = id.clone();
    for j in (1..=deg).rev() {
        let inv_j = Interval::ONE / Interval::raw(j as f64, j as f64);
        p = &id + &(&y * &p).scale(inv_j);
    }
    let mut e = p.inflate(rho);
    for _ in 0..k {
        e = &e * &e;
        if !e.is_bounded() {
            return Err(IntervalError::EnclosureFailed(
                "radius overflow while squaring (matrix too stiff or non-normal for this window)",
            ));
        }
    }
    if !e.is_bounded() {
        return Err(IntervalError::EnclosureFailed("radius overflow"));
    }
    Ok(e)
}

/// Enclosure of {e^{Aτ} : τ ∈ [a, b]} for one piece (0 ≤ a ≤ b, validated by the caller).
///
/// τm ∈ [a, b] (a float), r ≥ max(τm − a, b − τm). For τ = τm + s, |s| ≤ r:
/// e^{Aτ} = e^{Aτm}·e^{As} = Σ_{j≤N} (e^{Aτm}Aʲ/j!)·sʲ + e^{Aτm}·R_N(s), with
/// ‖R_N(s)‖_∞ ≤ Σ_{j>N} (‖A‖_∞ r)ʲ/j! ≤ ρ_N(‖A‖_∞ r) ([`taylor_remainder_up`]). The
/// coefficients G_j = e^{Aτm}Aʲ/j! are enclosed in interval arithmetic starting from an
/// enclosure of e^{Aτm} ([`expm_interval`] of the interval matrix τm·A), sʲ is replaced by
/// [−rʲ, rʲ] (j odd) or [0, rʲ] (j even), and the remainder by [−ρ, ρ]·‖e^{Aτm}‖_∞ in every
/// entry. Multiplying e^{Aτm} into the coefficients (instead of enclosing e^{As} alone and
/// multiplying the two enclosures) avoids the wrapping |e^{Aτm}|·|A| ≫ |e^{Aτm}A| of
/// stiff or rotating A.
fn piece_enclosure(
    a: &IntervalMatrix,
    a_norm: f64,
    t0: f64,
    t1: f64,
) -> Result<IntervalMatrix, IntervalError> {
    let tm = (0.5 * t0 + 0.5 * t1).clamp(t0, t1);
    let r = sub_up(tm, t0).max(sub_up(t1, tm));
    let em = expm_interval(&a.scale(Interval::raw(tm, tm)))?;
    if r == 0.0 {
        return Ok(em);
    }
    let x = mul_up(a_norm, r);
    let em_norm = em.norm_inf_up();
    let (deg, rho) = pick_degree(x, UNIT_ROUNDOFF / 16.0);
    let mut g = em.clone();
    let mut acc = em.clone();
    let mut rj = 1.0f64;
    for j in 1..=deg {
        let inv_j = Interval::ONE / Interval::raw(j as f64, j as f64);
        g = (&g * a).scale(inv_j);
        rj = mul_up(rj, r);
        let sj = if j % 2 == 1 {
            Interval::raw(-rj, rj)
        } else {
            Interval::raw(0.0, rj)
        };
        acc = &acc + &g.scale(sj);
    }
    let out = acc.inflate(mul_up(em_norm, rho));
    if !out.is_bounded() {
        return Err(IntervalError::EnclosureFailed(
            "radius overflow in the τ-expansion",
        ));
    }
    Ok(out)
}

/// Largest bound `‖S‖_∞‖S⁻¹‖_∞` on the condition number of the eigenbasis `S` with which
/// [`expm_enclosure`] works on `S⁻¹AS` instead of `A`: the enclosure mapped back,
/// `S·[e^{Bτ}]·[S⁻¹]`, is wider than that of `e^{Bτ}` by roughly this factor.
pub const MAX_BASIS_CONDITION: f64 = 1e8;

/// A real eigenbasis `S` of `A` (the eigenvectors of its real eigenvalues, and `Re u, Im u` for
/// each complex pair `u, ū`, every eigenvector of unit 2-norm), an enclosure `X` of `S⁻¹`
/// ([`IntervalMatrix::verified_inverse`]) and the enclosure `B = X·A·S` of the (nearly block
/// diagonal) `S⁻¹AS`, whose norm bound is `b_norm`.
///
/// Why (not in the literature of the method, a standard preconditioning of verified matrix
/// exponentials): each of the `k ≈ log₂‖Aτ‖_∞` interval squarings of [`expm_interval`] widens
/// the enclosure by about `‖|E|‖/‖E‖` of the matrix `E` squared, which for a non-normal `A`
/// (entries far larger than its eigenvalues) is huge. A mass-spring-damper with eigenvalues
/// `−0.2 ± 2i` written in millimetres and km/s and then in coordinates `x = Tz` (random `T`,
/// `κ(T) < 10`) has `‖A‖_∞ ≈ 6.7·10⁵`; the direct enclosure of `e^{0.05A}` had a midpoint of
/// `10²¹` and radii of `10³⁷` (true entries about `3·10⁴`), while `‖S⁻¹AS‖_∞ ≈ 2` needs no
/// squaring and `S` has `κ ≈ 10⁶`. `S⁻¹AS` has the same spectrum in every coordinates of `A`, so
/// the work no longer depends on them; the radius of `B` does, about `κ(S)‖A‖_∞u` from forming
/// the products in double precision (`10⁻⁴` there).
#[derive(Clone)]
struct Eigenbasis {
    s: IntervalMatrix,
    s_inv: IntervalMatrix,
    b: IntervalMatrix,
    b_norm: f64,
}

impl Eigenbasis {
    /// The eigenbasis of the midpoint of `ai` (`‖A‖_∞ ≤ a_norm` for every member `A`), valid for
    /// every member (`B = X·ai·S`), when it pays: `S⁻¹` is proven to exist,
    /// `‖S‖_∞‖X‖_∞ ≤` [`MAX_BASIS_CONDITION`] and `‖B‖_∞ ≤ ‖A‖_∞/4` (two squarings fewer at
    /// every `τ` with `‖Aτ‖_∞ > 4`); `None` otherwise (a defective or nearly defective `A`; a
    /// normal one of order below 16, whose `‖A‖_∞ ≤ √n ρ(A) ≤ √n ‖B‖_∞`; a basis whose
    /// inverse is not proven, e.g. a non-finite one), and then [`expm_enclosure`] works on `A`
    /// itself.
    fn of(ai: &IntervalMatrix, a_norm: f64) -> Result<Option<Self>, IntervalError> {
        let Ok(Some(eigen)) = sporadic_linalg::real_eigenbasis(ai.mid()) else {
            return Ok(None);
        };
        let s = IntervalMatrix::from_point(eigen.basis.as_ref())?;
        let Ok(Some(s_inv)) = s.verified_inverse() else {
            return Ok(None);
        };
        if !(mul_up(s.norm_inf_up(), s_inv.norm_inf_up()) <= MAX_BASIS_CONDITION) {
            return Ok(None);
        }
        let b = s_inv.checked_mul(&ai.checked_mul(&s)?)?;
        let b_norm = b.norm_inf_up();
        Ok((b_norm <= 0.25 * a_norm).then_some(Self {
            s,
            s_inv,
            b,
            b_norm,
        }))
    }

    /// Whether the enclosure of `e^{Aτ1}` (`τ1` the end of the window, where both ways widen
    /// most) is narrower in the basis than directly (`‖A‖_∞ ≤ a_norm` for every member of
    /// `ai`), both tried. Neither way is narrower in general: the squarings saved by the basis
    /// decide on a long window (a rotorcraft's `e^{−Aτ}` with `‖A‖_∞τ ≈ 35`, a basis of
    /// condition `9·10⁵`: only the basis proved its bound), the widening by `S` and `X` on a
    /// short one (a random 4×4 `A` with `‖A‖_∞τ ≈ 8.8`, a basis of condition 92 and
    /// `‖B‖_∞ ≈ ‖A‖_∞/4`: relative width `2.7·10⁻¹¹` in the basis, `3.4·10⁻¹⁴` directly), and
    /// bounds on the two widenings did not tell these apart.
    ///
    /// Returns the verdict and the narrower of the two enclosures of `e^{Aτ1}` (`None` when
    /// both failed): it is the piece of a point window `[τ1, τ1]`, which is then not enclosed
    /// a third time.
    fn pays(&self, ai: &IntervalMatrix, a_norm: f64, tau1: f64) -> (bool, Option<IntervalMatrix>) {
        let direct = piece_enclosure(ai, a_norm, tau1, tau1);
        let basis = piece_enclosure(&self.b, self.b_norm, tau1, tau1).and_then(|e| self.back(&e));
        match (direct, basis) {
            (Ok(d), Ok(b)) if b.max_width() < d.max_width() => (true, Some(b)),
            (Ok(d), _) => (false, Some(d)),
            (Err(_), Ok(b)) => (true, Some(b)),
            (Err(_), Err(_)) => (false, None),
        }
    }

    /// [`Eigenbasis::of`], remembered for the last (interval) matrix of the thread: a proof
    /// calls [`expm_enclosure`] with the same `A` at hundreds of `τ`.
    fn cached(ai: &IntervalMatrix, a_norm: f64) -> Result<Option<Self>, IntervalError> {
        thread_local! {
            static LAST: std::cell::RefCell<Option<(Vec<u64>, Option<Eigenbasis>)>> =
                const { std::cell::RefCell::new(None) };
        }
        let (mid, rad) = (ai.mid(), ai.rad());
        let key: Vec<u64> = (0..mid.ncols())
            .flat_map(|j| (0..mid.nrows()).flat_map(move |i| [mid[(i, j)], rad[(i, j)]]))
            .map(f64::to_bits)
            .chain([mid.nrows() as u64])
            .collect();
        if let Some(hit) = LAST.with_borrow(|last| {
            last.as_ref()
                .filter(|(k, _)| *k == key)
                .map(|(_, b)| b.clone())
        }) {
            return Ok(hit);
        }
        let basis = Self::of(ai, a_norm)?;
        LAST.set(Some((key, basis.clone())));
        Ok(basis)
    }

    /// `S·e·X`: an enclosure of `e^{Aτ}` from one `e` of `e^{Bτ}`.
    fn back(&self, e: &IntervalMatrix) -> Result<IntervalMatrix, IntervalError> {
        let out = self.s.checked_mul(&e.checked_mul(&self.s_inv)?)?;
        if !out.is_bounded() {
            return Err(IntervalError::EnclosureFailed(
                "radius overflow mapping the enclosure back from the eigenbasis",
            ));
        }
        Ok(out)
    }
}

fn validate(a: MatRef<'_, f64>, tau0: f64, tau1: f64) -> Result<(), IntervalError> {
    if a.nrows() != a.ncols() {
        return Err(IntervalError::NotSquare {
            what: "A",
            rows: a.nrows(),
            cols: a.ncols(),
        });
    }
    if a.nrows() == 0 {
        return Err(IntervalError::Empty { what: "A" });
    }
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            if !a[(i, j)].is_finite() {
                return Err(IntervalError::NonFinite {
                    what: "A",
                    row: i,
                    col: j,
                });
            }
        }
    }
    let bad = |why| Err(IntervalError::InvalidWindow { tau0, tau1, why });
    if !tau0.is_finite() || !tau1.is_finite() {
        return bad("τ must be finite");
    }
    if tau0 < 0.0 {
        return bad("τ0 must be ≥ 0");
    }
    if tau0 > tau1 {
        return bad("τ0 > τ1");
    }
    Ok(())
}

/// Rigorous enclosure of e^{Aτ} for **every** τ in [τ0, τ1] (0 ≤ τ0 ≤ τ1).
///
/// The window is cut into pieces (first so that ‖A‖_∞·(half-length) ≤
/// [`EnclosureOptions::max_step_norm`], then by bisecting the relatively widest piece while its
/// relative width exceeds [`EnclosureOptions::piece_rel_width`] and there are fewer than
/// [`EnclosureOptions::max_pieces`] pieces). Each piece [a, b] is enclosed as follows (all in
/// outward-rounded interval arithmetic, so every floating-point error is accounted for):
///
/// 1. τm = mid of the piece, r ≥ half-length. e^{Aτm} is enclosed by [`expm_interval`]
///    (scaling by 2⁻ᵏ so that ‖2⁻ᵏAτm‖_∞ ≤ 1, Taylor polynomial of degree N with remainder,
///    k interval squarings).
/// 2. e^{Aτ} = e^{Aτm}·e^{As}, |s| ≤ r, is expanded as Σ_{j≤N} e^{Aτm}(Aʲ/j!)sʲ + e^{Aτm}R_N(s).
///
/// When `A` has a real eigenbasis `S` with `‖S‖_∞‖S⁻¹‖_∞ ≤` [`MAX_BASIS_CONDITION`] in which
/// it is at least four times smaller (`‖S⁻¹AS‖_∞ ≤ ‖A‖_∞/4`, a non-normal `A`), and which
/// encloses `e^{Aτ1}` more narrowly than `A` itself does (`Eigenbasis::pays`), steps 1–2 are
/// made for every member of the enclosure `B = X·A·S` of `S⁻¹AS` instead (`X` a verified
/// enclosure of `S⁻¹`, the pieces cut by `‖B‖_∞`), and each piece's enclosure `E` of `e^{Bτ}`
/// is mapped back as `S·E·X ∋ S e^{Bτ} S⁻¹ = e^{Aτ}`: fewer squarings of a matrix whose
/// entries do not dwarf its eigenvalues (see `Eigenbasis`).
///
/// **Remainder bound.** For x = ‖A‖_∞·r and any |s| ≤ r,
/// ‖R_N(s)‖_∞ = ‖Σ_{j>N} (As)ʲ/j!‖_∞ ≤ Σ_{j>N} xʲ/j! ≤ x^{N+1}/(N+1)! · min(1/(1 − x/(N+2)), eˣ)
/// (the first factor when x < N+2). Proof: the norm is submultiplicative, and
/// (N+1+i)! ≥ (N+1)!·max((N+2)ⁱ, i!) for every i ≥ 0, so the tail is dominated termwise by a
/// geometric series with ratio x/(N+2) and by x^{N+1}/(N+1)!·Σ xⁱ/i!. Every entry of a matrix is
/// bounded by its ∞-norm, so each entry of e^{Aτm}R_N(s) lies in [−ρ, ρ] with
/// ρ = ‖e^{Aτm}‖_∞·x^{N+1}/(N+1)!·min(…) (upper bounds used throughout). N is the smallest degree
/// with ρ/‖e^{Aτm}‖_∞ ≤ u/16 (at most 40). The same bound with s = 1 and A replaced by the scaled
/// matrix gives the remainder of step 1.
///
/// The floating-point matrix exponential of `sporadic-linalg` is not needed for the enclosure
/// itself (the enclosure's midpoint is as accurate); the tests compare against it and against
/// 50+-digit references.
///
/// # Errors
/// [`IntervalError::NotSquare`], [`IntervalError::Empty`], [`IntervalError::NonFinite`] for a bad
/// `a`; [`IntervalError::InvalidWindow`] for NaN/∞ τ, τ0 < 0 or τ0 > τ1;
/// [`IntervalError::InvalidOption`] for bad options; [`IntervalError::Overflow`] if ‖A‖_∞·τ1
/// overflows; [`IntervalError::EnclosureFailed`] if the enclosure becomes unbounded
/// (extremely stiff or non-normal A over a long window).
pub fn expm_enclosure(
    a: MatRef<'_, f64>,
    tau0: f64,
    tau1: f64,
    options: &EnclosureOptions,
) -> Result<ExpmEnclosure, IntervalError> {
    validate(a, tau0, tau1)?;
    enclose(&IntervalMatrix::from_point(a)?, tau0, tau1, options)
}

/// [`expm_enclosure`] for an interval matrix `A`: the result contains `e^{Aτ}` for every member
/// `A` and every `τ` in `[τ0, τ1]` (each step of [`expm_enclosure`] holds for every member of an
/// interval matrix with the norm bound it is given). For a plant known only up to an enclosure,
/// e.g. `G·A·[G⁻¹]` in other coordinates.
///
/// # Errors
/// As [`expm_enclosure`]; [`IntervalError::NonFinite`] for an unbounded entry.
pub fn expm_enclosure_interval(
    a: &IntervalMatrix,
    tau0: f64,
    tau1: f64,
    options: &EnclosureOptions,
) -> Result<ExpmEnclosure, IntervalError> {
    validate(a.mid(), tau0, tau1)?;
    validate(a.rad(), tau0, tau1)?;
    enclose(a, tau0, tau1, options)
}

/// The enclosure of [`expm_enclosure`] for a validated interval matrix `ai`.
fn enclose(
    ai: &IntervalMatrix,
    tau0: f64,
    tau1: f64,
    options: &EnclosureOptions,
) -> Result<ExpmEnclosure, IntervalError> {
    if !(options.max_step_norm > 0.0) {
        return Err(IntervalError::InvalidOption("max_step_norm must be > 0"));
    }
    if !(options.piece_rel_width > 0.0) {
        return Err(IntervalError::InvalidOption("piece_rel_width must be > 0"));
    }
    if options.max_pieces == 0 {
        return Err(IntervalError::InvalidOption("max_pieces must be ≥ 1"));
    }
    let a_norm = ai.norm_inf_up();
    if !a_norm.is_finite() || !mul_up(a_norm, tau1).is_finite() {
        return Err(IntervalError::Overflow("‖A‖·τ1 overflows"));
    }
    let (basis, mut at_end) = match Eigenbasis::cached(ai, a_norm)? {
        Some(b) => {
            let (pays, at_end) = b.pays(ai, a_norm, tau1);
            (pays.then_some(b), at_end)
        }
        None => (None, None),
    };
    let (ai, a_norm) = match &basis {
        Some(e) => (e.b.clone(), e.b_norm),
        None => (ai.clone(), a_norm),
    };
    let piece_enclosure = |t0: f64, t1: f64| -> Result<IntervalMatrix, IntervalError> {
        let e = piece_enclosure(&ai, a_norm, t0, t1)?;
        match &basis {
            Some(b) => b.back(&e),
            None => Ok(e),
        }
    };
    // Initial uniform partition.
    let len = sub_up(tau1, tau0);
    let want = div_up(mul_up(a_norm, len), 2.0 * options.max_step_norm).ceil();
    let p0 = if want.is_finite() {
        (want as usize).clamp(1, options.max_pieces)
    } else {
        options.max_pieces
    };
    let mut cuts: Vec<f64> = (0..=p0)
        .map(|i| {
            if i == 0 {
                tau0
            } else if i == p0 {
                tau1
            } else {
                (tau0 + (tau1 - tau0) * (i as f64 / p0 as f64)).clamp(tau0, tau1)
            }
        })
        .collect();
    cuts.dedup();
    if cuts.len() == 1 {
        cuts.push(cuts[0]);
    }
    let mut pieces: Vec<(EnclosurePiece, f64)> = Vec::with_capacity(options.max_pieces);
    for w in cuts.windows(2) {
        // A point window: the trial of `Eigenbasis::pays` is its piece.
        let trial = if w[0] == tau1 { at_end.take() } else { None };
        let e = match trial {
            Some(e) => e,
            None => piece_enclosure(w[0], w[1])?,
        };
        let rw = e.rel_width();
        pieces.push((
            EnclosurePiece {
                tau0: w[0],
                tau1: w[1],
                enclosure: e,
            },
            rw,
        ));
    }
    // Adaptive bisection of the relatively widest splittable piece.
    while pieces.len() < options.max_pieces {
        let (idx, worst) = pieces.iter().enumerate().map(|(i, p)| (i, p.1)).fold(
            (usize::MAX, f64::NEG_INFINITY),
            |b, c| {
                if c.1 > b.1 { c } else { b }
            },
        );
        if idx == usize::MAX || !(worst > options.piece_rel_width) {
            break;
        }
        let (lo, hi) = (pieces[idx].0.tau0, pieces[idx].0.tau1);
        let c = 0.5 * lo + 0.5 * hi;
        if !(c > lo && c < hi) {
            pieces[idx].1 = f64::NEG_INFINITY; // cannot be split further
            continue;
        }
        let left = piece_enclosure(lo, c)?;
        let right = piece_enclosure(c, hi)?;
        let (lw, rw) = (left.rel_width(), right.rel_width());
        pieces[idx] = (
            EnclosurePiece {
                tau0: lo,
                tau1: c,
                enclosure: left,
            },
            lw,
        );
        pieces.insert(
            idx + 1,
            (
                EnclosurePiece {
                    tau0: c,
                    tau1: hi,
                    enclosure: right,
                },
                rw,
            ),
        );
    }
    let mut hull = pieces[0].0.enclosure.clone();
    let mut max_piece_rel_width = 0.0f64;
    for (p, _) in &pieces {
        hull = hull.hull(&p.enclosure)?;
        max_piece_rel_width = max_piece_rel_width.max(p.enclosure.rel_width());
    }
    if !hull.is_bounded() {
        return Err(IntervalError::EnclosureFailed("unbounded enclosure"));
    }
    Ok(ExpmEnclosure {
        max_width: hull.max_width(),
        rel_width: hull.rel_width(),
        enclosure: hull,
        pieces: pieces.into_iter().map(|p| p.0).collect(),
        max_piece_rel_width,
    })
}
