//! Al-Mohy & Higham (2009), *A new scaling and squaring algorithm for the matrix exponential*,
//! SIAM J. Matrix Anal. Appl. 31(3):970–989 — Algorithm 6.1, written once over
//! [`SquareStorage`] so the stack kernels and the faer kernels share it.
//!
//! Notation: r_m = p_m/q_m is the [m/m] Padé approximant, evaluated as
//! r_m(A) = (V − U)⁻¹(V + U) with U the odd and V the even part; d_k = ‖A^k‖₁^{1/k}; θ_m the
//! backward-error thresholds (θ13 = 4.25 is the value the 2009 algorithm uses instead of
//! Higham's 2005 value 5.37); ℓ(A, m) the correction that increases the degree or the number of
//! squarings when |A| is strongly non-normal, so that rounding errors in evaluating r_m stay
//! below the unit roundoff relative to ‖A‖.

use super::storage::{SingularPivot, SquareStorage};

/// Padé degrees tried by Algorithm 6.1, in order.
pub(crate) const DEGREES: [usize; 5] = [3, 5, 7, 9, 13];

/// θ_m for m = 3, 5, 7, 9 (Higham 2005, SIAM J. Matrix Anal. Appl. 26(4):1179–1193; the same
/// values in Al-Mohy & Higham 2009 and `expm_new.m`) and θ13 = 4.25 (Al-Mohy & Higham 2009,
/// Algorithm 6.1).
pub(crate) const THETA: [f64; 5] = [
    1.495585217958292e-2,
    2.53939833006323e-1,
    9.504178996162932e-1,
    2.097847961257068,
    4.25,
];

/// Coefficients b_j = (2m−j)! / (j!·(m−j)!) of p_m, normalised so that b_m = 1
/// (checked against exact integer arithmetic in the unit tests).
pub(crate) const B3: [f64; 4] = [120.0, 60.0, 12.0, 1.0];
pub(crate) const B5: [f64; 6] = [30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0];
pub(crate) const B7: [f64; 8] = [
    17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0,
];
pub(crate) const B9: [f64; 10] = [
    17643225600.0,
    8821612800.0,
    2075673600.0,
    302702400.0,
    30270240.0,
    2162160.0,
    110880.0,
    3960.0,
    90.0,
    1.0,
];
pub(crate) const B13: [f64; 14] = [
    64764752532480000.0,
    32382376266240000.0,
    7771770303897600.0,
    1187353796428800.0,
    129060195264000.0,
    10559470521600.0,
    670442572800.0,
    33522128640.0,
    1323241920.0,
    40840800.0,
    960960.0,
    16380.0,
    182.0,
    1.0,
];

/// 1/|c_{2m+1}| = (2m)!·(2m+1)!/(m!)², the reciprocal of the leading coefficient of the
/// backward-error series of r_m (the constant of ℓ(A, m) in Al-Mohy & Higham 2009), computed
/// exactly in integers and rounded once.
const fn abs_c_recip(m: usize) -> f64 {
    // binomial(2m, m) · (2m+1)!, both exact in u128 for m ≤ 13 (≈ 1.1e35 < 3.4e38).
    let mut binom: u128 = 1;
    let mut k = 1;
    while k <= m {
        binom = binom * (m + k) as u128 / k as u128;
        k += 1;
    }
    let mut fact: u128 = 1;
    let mut j = 2;
    while j <= 2 * m + 1 {
        fact *= j as u128;
        j += 1;
    }
    (binom * fact) as f64
}

const ABS_C_RECIP: [f64; 5] = [
    abs_c_recip(3),
    abs_c_recip(5),
    abs_c_recip(7),
    abs_c_recip(9),
    abs_c_recip(13),
];

/// Range outside which the |A|ᵀ power-iteration vector is renormalised.
const RENORM_HIGH: f64 = 2.5822498780869086e120; // 2^400, exactly
const RENORM_LOW: f64 = 1.0 / RENORM_HIGH;

/// log₂ of the unit roundoff u = 2⁻⁵³.
const LOG2_U: f64 = -53.0;

/// Inputs with ‖A‖₁ above 2^this are first scaled by a power of two so that the powers A², …, A¹⁰
/// formed by Algorithm 6.1 cannot overflow; the extra squarings restore e^A.
const PRESCALE_LOG2: f64 = 100.0;

/// Which Padé degree and how many squarings were used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Choice {
    /// Padé degree m (0 when a structural shortcut — diagonal or zero input — was taken).
    pub(crate) degree: usize,
    /// Number of squarings s (including any pre-scaling of very large inputs).
    pub(crate) squarings: u32,
}

/// Why Algorithm 6.1 could not deliver a finite result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Failure {
    /// t·A, loaded into the workspace, has a NaN or ±∞ entry.
    NonFiniteInput,
    /// q_m(2^{-s}A) = V − U had a zero pivot or its solve produced non-finite values.
    Singular,
    /// The result overflows double precision.
    Overflow,
}

impl From<SingularPivot> for Failure {
    fn from(_: SingularPivot) -> Self {
        Failure::Singular
    }
}

/// Optional 1-norm estimator for products of workspace matrices (Higham–Tisseur, t = 2).
/// `None` means: form the powers and take exact norms.
pub(crate) type Estimator<'e, M> = Option<&'e mut dyn FnMut(&[&M]) -> f64>;

/// Sparsity structure that allows a cheaper or more accurate evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Structure {
    /// Diagonal: e^A = diag(e^{a_ii}).
    Diagonal,
    /// Upper triangular: Code Fragment 2.1 of Al-Mohy & Higham (2009).
    Upper,
    /// Lower triangular: handled as the transpose of an upper-triangular matrix.
    Lower,
    /// Upper quasi-triangular (isolated nonzero subdiagonal entries, as in a real Schur form):
    /// Code Fragment 2.1 generalised to 1×1 and 2×2 diagonal blocks.
    QuasiUpper,
    /// No usable structure.
    General,
}

impl Structure {
    #[inline(always)]
    pub(crate) fn detect<M: SquareStorage>(a: &M) -> Self {
        let n = a.order();
        let mut upper = true; // strictly lower part zero
        let mut lower = true; // strictly upper part zero
        let mut quasi = true; // zero below the first subdiagonal, no two adjacent subdiagonals
        for j in 0..n {
            if !(upper || lower || quasi) {
                return Structure::General;
            }
            for i in 0..n {
                if a.get(i, j) == 0.0 {
                    continue;
                }
                if i > j {
                    upper = false;
                    if i > j + 1 || (j > 0 && a.get(j, j - 1) != 0.0) {
                        quasi = false;
                    }
                } else if i < j {
                    lower = false;
                }
            }
        }
        match (upper, lower, quasi) {
            (true, true, _) => Structure::Diagonal,
            (true, false, _) => Structure::Upper,
            (false, true, _) => Structure::Lower,
            (false, false, true) => Structure::QuasiUpper,
            (false, false, false) => Structure::General,
        }
    }
}

/// Reusable buffers for one order n. Nothing in [`PadeWorkspace::run`] allocates.
pub(crate) struct PadeWorkspace<M: SquareStorage> {
    a: M,
    a2: M,
    a4: M,
    a6: M,
    a8: M,
    u: M,
    v: M,
    w: M,
    /// Copy of the (triangular) input for Code Fragment 2.1.
    t: M,
    /// |A|ᵀ for the power iteration of ℓ(A, m).
    abs_t: M,
    x: M::Vector,
    y: M::Vector,
    lu: M::LuScratch,
}

/// 1-norms p_k = ‖A^k‖₁ of the even powers: exact once the power is formed, otherwise an
/// upper bound (exact mode) or a Higham–Tisseur estimate (estimate mode).
struct PowerNorms {
    p2: f64,
    p4: Option<f64>,
    p6: Option<f64>,
    p8: Option<f64>,
    /// Columns of largest 1-norm of A⁴ and A⁶ (valid once formed).
    j4: usize,
    j6: usize,
    /// Lower bound for p8 (exact mode, see [`PadeWorkspace::lower_bound_8`]).
    lo8: Option<f64>,
    estimates: bool,
    est4: Option<f64>,
    est6: Option<f64>,
    est8: Option<f64>,
}

impl PowerNorms {
    fn new(p2: f64, estimates: bool) -> Self {
        Self {
            p2,
            p4: None,
            p6: None,
            p8: None,
            j4: 0,
            j6: 0,
            lo8: None,
            estimates,
            est4: None,
            est6: None,
            est8: None,
        }
    }

    /// (value, is_exact) for p_k, k ∈ {4, 6, 8}. Upper bounds: p4 ≤ p2², p6 ≤ p2·p4,
    /// p8 ≤ min(p4², p2·p6).
    #[inline(always)]
    fn value<M: SquareStorage>(
        &mut self,
        k: usize,
        estimator: &mut Estimator<'_, M>,
        a2: &M,
        a4: &M,
    ) -> (f64, bool) {
        let exact = match k {
            4 => self.p4,
            6 => self.p6,
            _ => self.p8,
        };
        if let Some(v) = exact {
            return (v, true);
        }
        if self.estimates {
            let est = estimator.as_mut().expect("estimate mode");
            let v = match k {
                4 => *self.est4.get_or_insert_with(|| est(&[a2, a2])),
                6 => *self.est6.get_or_insert_with(|| est(&[a2, a2, a2])),
                _ => *self.est8.get_or_insert_with(|| est(&[a4, a4])),
            };
            return (v, false);
        }
        let p2 = self.p2;
        let b4 = self.p4.unwrap_or(p2 * p2);
        let b6 = self.p6.unwrap_or(p2 * b4);
        let v = match k {
            4 => b4,
            6 => b6,
            _ => (b4 * b4).min(p2 * b6),
        };
        (v, false)
    }
}

/// State of the power iteration x_p = (|A|ᵀ)^p 𝟙 that gives ‖ |A|^p ‖₁ = max(x_p) exactly
/// (|A| is nonnegative). The vector is renormalised by powers of two, whose log₂ is accumulated,
/// so that ‖ |A|^{27} ‖₁ cannot overflow. The same vector serves all degrees (7, 11, 15, 19, 27
/// mat-vecs in total at most).
struct AbsPowers {
    power: usize,
    log2_scale: f64,
    /// max_i (x_p)_i of the current (renormalised) vector.
    top: f64,
}

impl<M: SquareStorage> PadeWorkspace<M> {
    /// Buffers for order `n`.
    pub(crate) fn new(n: usize) -> Self {
        Self {
            a: M::zeros(n),
            a2: M::zeros(n),
            a4: M::zeros(n),
            a6: M::zeros(n),
            a8: M::zeros(n),
            u: M::zeros(n),
            v: M::zeros(n),
            w: M::zeros(n),
            t: M::zeros(n),
            abs_t: M::zeros(n),
            x: M::zero_vector(n),
            y: M::zero_vector(n),
            lu: M::lu_scratch(n),
        }
    }

    /// The matrix whose exponential [`PadeWorkspace::run`] computes; fill it before `run`.
    pub(crate) fn input_mut(&mut self) -> &mut M {
        &mut self.a
    }

    /// Order of the workspace.
    pub(crate) fn input_mut_order(&self) -> usize {
        self.a.order()
    }

    /// e^A after a successful [`PadeWorkspace::run`].
    pub(crate) fn result(&self) -> &M {
        &self.v
    }

    /// Computes e^A for the matrix in [`PadeWorkspace::input_mut`] (which is overwritten) into
    /// [`PadeWorkspace::result`]. The input must be finite.
    #[inline(always)]
    pub(crate) fn run(&mut self, estimator: Estimator<'_, M>) -> Result<Choice, Failure> {
        let structure = Structure::detect(&self.a);
        let choice = match structure {
            Structure::Diagonal => {
                self.diagonal();
                Choice {
                    degree: 0,
                    squarings: 0,
                }
            }
            Structure::Lower => {
                transpose_in_place(&mut self.a);
                let c = self.general(Structure::Upper, estimator)?;
                transpose_in_place(&mut self.v);
                c
            }
            _ => self.general(structure, estimator)?,
        };
        if self.v.all_finite() {
            Ok(choice)
        } else {
            Err(Failure::Overflow)
        }
    }

    #[inline(always)]
    fn diagonal(&mut self) {
        let n = self.a.order();
        self.v.combine(false, 0.0, &[]);
        for i in 0..n {
            self.v.set(i, i, self.a.get(i, i).exp());
        }
    }

    /// Algorithm 6.1 for non-diagonal input (`structure` is Upper, QuasiUpper or General).
    #[inline(always)]
    fn general(
        &mut self,
        structure: Structure,
        mut estimator: Estimator<'_, M>,
    ) -> Result<Choice, Failure> {
        let triangular = matches!(structure, Structure::Upper | Structure::QuasiUpper);
        if triangular {
            self.t.assign(&self.a);
        }
        // Pre-scaling of huge inputs (keeps A^10 finite); exact, a power of two.
        let norm0 = self.a.norm1();
        let s0 = if norm0.log2() > PRESCALE_LOG2 {
            (norm0.log2() - PRESCALE_LOG2).ceil() as u32
        } else {
            0
        };
        if s0 > 0 {
            scale_pow2(&mut self.a, -(s0 as i32));
        }
        let norm = self.a.norm1();
        let mut abs = AbsPowers::start(&mut self.x);

        self.a2.assign_product(&self.a, &self.a);
        let mut pw = PowerNorms::new(self.a2.norm1(), estimator.is_some());

        // Step 1 (Al-Mohy & Higham 2009, Algorithm 6.1): degree 3.
        let mut degree = 0;
        if self.accept(&mut pw, &mut estimator, &mut abs, 0, norm, [4, 6]) {
            degree = 3;
        }
        // Step 2: degree 5 (‖A⁴‖₁ exact from here on).
        if degree == 0 {
            self.form(&mut pw, 4);
            if self.accept(&mut pw, &mut estimator, &mut abs, 1, norm, [4, 6]) {
                degree = 5;
            }
        }
        // Step 3: degrees 7 and 9 (‖A⁶‖₁ exact from here on).
        if degree == 0 {
            self.form(&mut pw, 6);
            for (idx, m) in [(2, 7), (3, 9)] {
                if self.accept(&mut pw, &mut estimator, &mut abs, idx, norm, [6, 8]) {
                    degree = m;
                    break;
                }
            }
        }
        let mut s = 0u32;
        if degree == 0 {
            // Step 4: degree 13 with s = max(⌈log₂(η5/θ13)⌉, 0) + ℓ(2^{−s}A, 13) squarings,
            // η5 = min(max(d6, d8), max(d8, d10)).
            let p6 = pw.p6.expect("A⁶ formed in step 3");
            let (p8, p10) = match estimator.as_mut() {
                Some(_) => {
                    let p8 = pw.value(8, &mut estimator, &self.a2, &self.a4).0;
                    let est = estimator.as_mut().expect("estimate mode");
                    (p8, est(&[&self.a4, &self.a6]))
                }
                None => self.norms_8_10(&mut pw),
            };
            s = squarings_13(p6, p8, p10);
            s += abs.ell(
                &self.a,
                &mut self.abs_t,
                &mut self.x,
                &mut self.y,
                4,
                norm,
                s,
            );
            degree = 13;
            // Step 5: scale A, A², A⁴, A⁶ by 2^{−s}, 2^{−2s}, 2^{−4s}, 2^{−6s}.
            if s > 0 {
                let si = s as i32;
                scale_pow2(&mut self.a, -si);
                scale_pow2(&mut self.a2, -2 * si);
                scale_pow2(&mut self.a4, -4 * si);
                scale_pow2(&mut self.a6, -6 * si);
            }
        } else {
            // Powers used by r_m.
            for k in [4, 6, 8] {
                if k < degree {
                    self.form(&mut pw, k);
                }
            }
        }

        // r_m = (V − U)⁻¹(V + U) for the chosen degree.
        self.pade_uv(degree);
        M::solve_pade(&mut self.a8, &mut self.w, &self.v, &self.u, &mut self.lu)?;
        if !self.a8.all_finite() {
            return Err(Failure::Singular);
        }

        // Squaring, with Code Fragment 2.1 for (quasi-)triangular input.
        let total = s + s0;
        if triangular {
            fragment_2_1(&mut self.a8, &self.t, total, structure);
        }
        for i in (0..total).rev() {
            self.u.assign_product(&self.a8, &self.a8);
            std::mem::swap(&mut self.u, &mut self.a8);
            if triangular {
                fragment_2_1(&mut self.a8, &self.t, i, structure);
            }
        }
        std::mem::swap(&mut self.v, &mut self.a8);
        Ok(Choice {
            degree,
            squarings: total,
        })
    }

    /// Forms A^k (k ∈ {4, 6, 8}, with its prerequisites) unless already formed, and records
    /// its exact 1-norm.
    #[inline(always)]
    fn form(&mut self, pw: &mut PowerNorms, k: usize) {
        if k >= 4 && pw.p4.is_none() {
            self.a4.assign_product(&self.a2, &self.a2);
            let (p4, j4) = self.a4.norm1_argmax();
            (pw.p4, pw.j4) = (Some(p4), j4);
        }
        if k == 6 && pw.p6.is_none() {
            self.a6.assign_product(&self.a2, &self.a4);
            let (p6, j6) = self.a6.norm1_argmax();
            (pw.p6, pw.j6) = (Some(p6), j6);
        }
        if k == 8 && pw.p8.is_none() {
            self.a8.assign_product(&self.a4, &self.a4);
            pw.p8 = Some(self.a8.norm1());
        }
    }

    /// Exact mode: a lower bound for p8 = ‖A⁸‖₁ from two matrix–vector products,
    /// max(‖A⁴·(A⁴e_{j4})‖₁, ‖A²·(A⁶e_{j6})‖₁) with e_j the column of largest 1-norm (these
    /// are 1-norms of columns of A⁸). Needs A⁴, and uses A⁶ when formed.
    #[inline(always)]
    fn lower_bound_8(&mut self, pw: &mut PowerNorms) -> f64 {
        if let Some(v) = pw.lo8 {
            return v;
        }
        let mut v = self.a4.column_product_norm1(&self.a4, pw.j4, &mut self.y);
        if pw.p6.is_some() {
            v = v.max(self.a2.column_product_norm1(&self.a6, pw.j6, &mut self.y));
        }
        pw.lo8 = Some(v);
        v
    }

    /// Exact mode, step 4: (p8, p10) with p_k = ‖A^k‖₁, or values that give the same number of
    /// squarings s as the exact ones. s is a nondecreasing function of p8 and p10
    /// ([`squarings_13`]), so when the lower bounds (matrix–vector products, see
    /// [`PadeWorkspace::lower_bound_8`]) and the submultiplicative upper bounds p8 ≤
    /// min(p4², p2·p6), p10 ≤ min(p4·p6, p2·p8) give the same s, that s is exact and the
    /// products A⁸ = A⁴A⁴ and A¹⁰ = A⁴A⁶ are not formed. Otherwise they are formed as needed.
    #[inline(always)]
    fn norms_8_10(&mut self, pw: &mut PowerNorms) -> (f64, f64) {
        let (p2, p4, p6) = (pw.p2, pw.p4.expect("A⁴ formed"), pw.p6.expect("A⁶ formed"));
        let (lo8, hi8) = match pw.p8 {
            Some(v) => (v, v),
            None => (self.lower_bound_8(pw), (p4 * p4).min(p2 * p6)),
        };
        let lo10 = self
            .a4
            .column_product_norm1(&self.a6, pw.j6, &mut self.y)
            .max(self.a6.column_product_norm1(&self.a4, pw.j4, &mut self.y));
        let hi10 = (p4 * p6).min(p2 * hi8);
        if squarings_13(p6, lo8, lo10) == squarings_13(p6, hi8, hi10) {
            return (hi8, hi10);
        }
        if pw.p8.is_none() {
            self.form(pw, 8);
            let p8 = pw.p8.expect("A⁸ formed");
            let hi10 = hi10.min(p2 * p8);
            if squarings_13(p6, p8, lo10) == squarings_13(p6, p8, hi10) {
                return (p8, hi10);
            }
        }
        self.w.assign_product(&self.a4, &self.a6);
        (pw.p8.expect("A⁸ formed"), self.w.norm1())
    }

    /// Whether degree m = DEGREES[idx] is accepted (steps 1–3 of Algorithm 6.1): d_a ≤ θ_m,
    /// d_b ≤ θ_m (p_a ≤ θ_m^a ∧ p_b ≤ θ_m^b with p_k = ‖A^k‖₁) and ℓ(A, m) = 0.
    ///
    /// Exact mode: the norm test is first made with the submultiplicative upper bounds of
    /// [`PowerNorms::value`] (and, for p8, the lower bound of
    /// [`PadeWorkspace::lower_bound_8`]); a power is formed only when the bounds leave the test
    /// open and ℓ(A, m) = 0 (ℓ costs matrix–vector products only), so the outcome is exactly
    /// that of the test with exact norms, at lower cost. Estimate mode (Algorithm 6.1 as
    /// published): unformed powers are represented by Higham–Tisseur estimates.
    #[inline(always)]
    fn accept(
        &mut self,
        pw: &mut PowerNorms,
        estimator: &mut Estimator<'_, M>,
        abs: &mut AbsPowers,
        idx: usize,
        norm: f64,
        ks: [usize; 2],
    ) -> bool {
        let theta = THETA[idx];
        let mut ell_zero = None;
        loop {
            let mut pass = true;
            let mut to_form = None;
            for k in ks {
                let (v, exact) = pw.value(k, estimator, &self.a2, &self.a4);
                if v > theta.powi(k as i32) {
                    pass = false;
                    if exact || estimator.is_some() {
                        return false;
                    }
                    // The upper bound failed; a lower bound above θ^k decides without the
                    // product.
                    if k == 8 && self.lower_bound_8(pw) > theta.powi(8) {
                        return false;
                    }
                    to_form.get_or_insert(k);
                }
            }
            match to_form {
                _ if pass => break,
                Some(k) => {
                    // A⁸ is only worth forming if the degree can still be accepted.
                    if k == 8 && ell_zero.is_none() {
                        if !self.ell_is_zero(abs, idx, norm) {
                            return false;
                        }
                        ell_zero = Some(true);
                    }
                    self.form(pw, k)
                }
                None => return false,
            }
        }
        match ell_zero {
            Some(z) => z,
            None => self.ell_is_zero(abs, idx, norm),
        }
    }

    /// ℓ(A, m) = 0 for m = DEGREES[idx] (no scaling).
    #[inline(always)]
    fn ell_is_zero(&mut self, abs: &mut AbsPowers, idx: usize, norm: f64) -> bool {
        abs.ell(
            &self.a,
            &mut self.abs_t,
            &mut self.x,
            &mut self.y,
            idx,
            norm,
            0,
        ) == 0
    }

    /// Forms U (in `u`) and V (in `v`) of r_m from the (scaled) powers; may use `w` and, for
    /// m = 13, `a8` as scratch.
    #[inline(always)]
    fn pade_uv(&mut self, m: usize) {
        let (a2, a4, a6) = (&self.a2, &self.a4, &self.a6);
        match m {
            3 => {
                self.w.combine(false, B3[1], &[(B3[3], a2)]);
                self.v.combine(false, B3[0], &[(B3[2], a2)]);
            }
            5 => {
                self.w.combine(false, B5[1], &[(B5[3], a2), (B5[5], a4)]);
                self.v.combine(false, B5[0], &[(B5[2], a2), (B5[4], a4)]);
            }
            7 => {
                self.w
                    .combine(false, B7[1], &[(B7[3], a2), (B7[5], a4), (B7[7], a6)]);
                self.v
                    .combine(false, B7[0], &[(B7[2], a2), (B7[4], a4), (B7[6], a6)]);
            }
            9 => {
                let a8 = &self.a8;
                self.w.combine(
                    false,
                    B9[1],
                    &[(B9[3], a2), (B9[5], a4), (B9[7], a6), (B9[9], a8)],
                );
                self.v.combine(
                    false,
                    B9[0],
                    &[(B9[2], a2), (B9[4], a4), (B9[6], a6), (B9[8], a8)],
                );
            }
            _ => {
                // U = A[A6(b13 A6 + b11 A4 + b9 A2) + b7 A6 + b5 A4 + b3 A2 + b1 I],
                // V = A6(b12 A6 + b10 A4 + b8 A2) + b6 A6 + b4 A4 + b2 A2 + b0 I (Higham 2005):
                // six products in total.
                self.u
                    .combine(false, 0.0, &[(B13[13], a6), (B13[11], a4), (B13[9], a2)]);
                self.w.assign_product(a6, &self.u);
                self.w
                    .combine(true, B13[1], &[(B13[7], a6), (B13[5], a4), (B13[3], a2)]);
                self.a8
                    .combine(false, 0.0, &[(B13[12], a6), (B13[10], a4), (B13[8], a2)]);
                self.v.assign_product(a6, &self.a8);
                self.v
                    .combine(true, B13[0], &[(B13[6], a6), (B13[4], a4), (B13[2], a2)]);
            }
        }
        self.u.assign_product(&self.a, &self.w);
    }
}

impl AbsPowers {
    fn start(x: &mut impl AsMut<[f64]>) -> Self {
        x.as_mut().fill(1.0);
        Self {
            power: 0,
            log2_scale: 0.0,
            top: 1.0,
        }
    }

    /// ℓ(2^{−s}A, m) for m = DEGREES[idx] (Al-Mohy & Higham 2009, Algorithm 6.1):
    /// ℓ = max(⌈log₂(α/u) / (2m)⌉, 0), α = |c_{2m+1}|·‖ |2^{−s}A|^{2m+1} ‖₁ / ‖2^{−s}A‖₁.
    #[inline(always)]
    fn ell<M: SquareStorage>(
        &mut self,
        a: &M,
        abs_t: &mut M,
        x: &mut M::Vector,
        y: &mut M::Vector,
        idx: usize,
        norm_a: f64,
        s: u32,
    ) -> u32 {
        let m = DEGREES[idx];
        let p = 2 * m + 1;
        // Algorithm 6.1 queries the degrees in increasing order, so the iteration only advances.
        debug_assert!(self.power <= p);
        if norm_a == 0.0 {
            return 0;
        }
        if self.power == 0 {
            abs_t.prepare_abs_transpose(a);
        }
        let log2_norm = norm_a.log2();
        // ℓ = 0 ⟺ log₂‖ |A|^p ‖₁ ≤ `zero_if_below`. After k steps the submultiplicative bound
        // ‖ |A|^p ‖₁ ≤ ‖ |A|^k ‖₁·‖A‖₁^{p−k} (‖ |A| ‖₁ = ‖A‖₁) often certifies ℓ = 0 long before
        // k = p; the exact value is only needed when it does not.
        let zero_if_below =
            LOG2_U + ABS_C_RECIP[idx].log2() + log2_norm + ((p - 1) as f64) * s as f64;
        let mut top = self.top;
        loop {
            if top == 0.0 || self.log2_scale == f64::NEG_INFINITY {
                return 0;
            }
            let bound = self.log2_scale + upper_log2(top) + (p - self.power) as f64 * log2_norm;
            if bound <= zero_if_below {
                return 0;
            }
            if self.power >= p {
                break;
            }
            top = abs_t.abs_transpose_matvec_max(x, y);
            std::mem::swap(x, y);
            self.power += 1;
            if top == 0.0 {
                self.log2_scale = f64::NEG_INFINITY;
                self.top = 0.0;
                return 0;
            }
            // Renormalise by an exact power of two, only when needed: one step multiplies the
            // maximum by at most ‖A‖₁ ≤ 2^100 (inputs are pre-scaled), so 2^±400 is safe.
            if !(RENORM_LOW..=RENORM_HIGH).contains(&top) {
                let e = top.log2().floor();
                let f = (-e).exp2();
                for v in x.as_mut() {
                    *v *= f;
                }
                top *= f;
                self.log2_scale += e;
            }
            self.top = top;
        }
        let log2_alpha = self.log2_scale + top.log2()
            - ABS_C_RECIP[idx].log2()
            - log2_norm
            - ((p - 1) as f64) * s as f64;
        let value = ((log2_alpha - LOG2_U) / (2 * m) as f64).ceil();
        if value > 0.0 { value as u32 } else { 0 }
    }
}

/// An upper bound for log₂(x), x > 0, from the exponent bits (no transcendental call).
fn upper_log2(x: f64) -> f64 {
    (((x.to_bits() >> 52) & 0x7ff) as i64 - 1022) as f64
}

/// Step 4 of Algorithm 6.1 before the ℓ correction: s = max(⌈log₂(η5/θ13)⌉, 0) with
/// η5 = min(max(d6, d8), max(d8, d10)) and d_k = p_k^{1/k} (s = 0 when η5 = 0, nilpotent A).
fn squarings_13(p6: f64, p8: f64, p10: f64) -> u32 {
    let (d6, d8, d10) = (root(p6, 6), root(p8, 8), root(p10, 10));
    let eta5 = d6.max(d8).min(d8.max(d10));
    let s_eta = (eta5 / THETA[4]).log2().ceil();
    if s_eta > 0.0 { s_eta as u32 } else { 0 }
}

/// x^{1/k} for the d_k = ‖A^k‖^{1/k} of Algorithm 6.1.
fn root(x: f64, k: i32) -> f64 {
    x.powf(1.0 / k as f64)
}

/// Multiplies every entry by 2^e exactly (in steps, so 2^e itself never under/overflows).
#[inline(always)]
fn scale_pow2<M: SquareStorage>(a: &mut M, e: i32) {
    let mut e = e;
    while e != 0 {
        let step = e.clamp(-1000, 1000);
        a.scale((step as f64).exp2());
        e -= step;
    }
}

/// x·2^e without intermediate under/overflow of 2^e.
fn ldexp(x: f64, e: i32) -> f64 {
    let mut y = x;
    let mut e = e;
    while e != 0 {
        let step = e.clamp(-1000, 1000);
        y *= (step as f64).exp2();
        e -= step;
    }
    y
}

#[inline(always)]
fn transpose_in_place<M: SquareStorage>(a: &mut M) {
    let n = a.order();
    for j in 0..n {
        for i in 0..j {
            let (x, y) = (a.get(i, j), a.get(j, i));
            a.set(i, j, y);
            a.set(j, i, x);
        }
    }
}

/// sinh(x)/x, with a Taylor polynomial near 0 (|x| < 0.0135, truncation error below u).
fn sinch(x: f64) -> f64 {
    if x.abs() < 0.0135 {
        let x2 = x * x;
        1.0 + (x2 / 6.0) * (1.0 + (x2 / 20.0) * (1.0 + x2 / 42.0))
    } else {
        x.sinh() / x
    }
}

/// The (1,2) entry of exp([[λ1, t12], [0, λ2]]) = t12·(e^{λ2} − e^{λ1})/(λ2 − λ1), evaluated
/// without cancellation as t12·e^{(λ1+λ2)/2}·sinch((λ1−λ2)/2) (Higham 2008, eq. (10.42);
/// Al-Mohy & Higham 2009, §2). For |λ1 − λ2| ≥ 2 the divided difference is used directly: there
/// it cannot cancel by more than a factor 1 − e⁻², and it avoids the spurious overflow of
/// sinh when e^{(λ1+λ2)/2} is tiny (SciPy's `exp_sinch_overflow` case).
fn exp_superdiagonal(l1: f64, l2: f64, t12: f64) -> f64 {
    let half_gap = 0.5 * (l1 - l2);
    if half_gap.abs() < 1.0 {
        t12 * (0.5 * (l1 + l2)).exp() * sinch(half_gap)
    } else {
        t12 * ((l1.exp() - l2.exp()) / (l1 - l2))
    }
}

/// Exact exponential of a real 2×2 block [[p, q], [r, z]] with complex eigenvalues a ± iμ:
/// e^a·(cos μ·I + (sin μ/μ)·(B − aI)) (Cayley–Hamilton). Returns `None` for real eigenvalues.
fn exp_2x2_complex(p: f64, q: f64, r: f64, z: f64) -> Option<[f64; 4]> {
    let a = 0.5 * (p + z);
    let h = 0.5 * (p - z);
    let delta = h * h + q * r;
    if delta >= 0.0 {
        return None;
    }
    let mu = (-delta).sqrt();
    let ea = a.exp();
    let (c, sn) = (mu.cos(), mu.sin() / mu);
    Some([
        ea * (c + sn * h),
        ea * sn * q,
        ea * sn * r,
        ea * (c - sn * h),
    ])
}

/// Code Fragment 2.1 of Al-Mohy & Higham (2009) for level i: X ≈ exp(2^{−i}T); overwrite the
/// diagonal with exp(2^{−i}t_kk) and the first superdiagonal with [`exp_superdiagonal`]. For a
/// quasi-triangular T, 2×2 diagonal blocks with complex eigenvalues are replaced by their exact
/// exponential, and superdiagonal entries are only recomputed between two 1×1 blocks.
fn fragment_2_1<M: SquareStorage>(x: &mut M, t: &M, i: u32, structure: Structure) {
    let n = t.order();
    let e = -(i as i32);
    let sc = |v: f64| ldexp(v, e);
    let in_block = |k: usize| -> bool {
        structure == Structure::QuasiUpper
            && ((k + 1 < n && t.get(k + 1, k) != 0.0) || (k > 0 && t.get(k, k - 1) != 0.0))
    };
    let mut k = 0;
    while k < n {
        if structure == Structure::QuasiUpper && k + 1 < n && t.get(k + 1, k) != 0.0 {
            if let Some(b) = exp_2x2_complex(
                sc(t.get(k, k)),
                sc(t.get(k, k + 1)),
                sc(t.get(k + 1, k)),
                sc(t.get(k + 1, k + 1)),
            ) {
                x.set(k, k, b[0]);
                x.set(k, k + 1, b[1]);
                x.set(k + 1, k, b[2]);
                x.set(k + 1, k + 1, b[3]);
            }
            k += 2;
        } else {
            x.set(k, k, sc(t.get(k, k)).exp());
            k += 1;
        }
    }
    for k in 0..n.saturating_sub(1) {
        if !in_block(k) && !in_block(k + 1) {
            let v = exp_superdiagonal(
                sc(t.get(k, k)),
                sc(t.get(k + 1, k + 1)),
                sc(t.get(k, k + 1)),
            );
            x.set(k, k + 1, v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expm::storage::SmallMat;
    use faer::Mat;

    fn exact_coefficients(m: u128) -> Vec<u128> {
        let fact = |k: u128| (1..=k).product::<u128>();
        (0..=m)
            .map(|j| fact(2 * m - j) / (fact(j) * fact(m - j)))
            .collect()
    }

    #[test]
    fn pade_coefficients_match_the_factorial_formula() {
        let tables: [&[f64]; 5] = [&B3, &B5, &B7, &B9, &B13];
        for (m, table) in DEGREES.iter().zip(tables) {
            let exact = exact_coefficients(*m as u128);
            let scale = exact[*m];
            for (j, b) in table.iter().enumerate() {
                // b_j normalised so that b_m = 1; all are integers exactly representable.
                assert_eq!(exact[j] % scale, 0);
                assert_eq!(*b, (exact[j] / scale) as f64, "m={m} j={j}");
            }
        }
    }

    #[test]
    fn abs_c_recip_matches_notes() {
        // 1/|c_{2m+1}| = (2m)!(2m+1)!/(m!)² for m = 3, 5, 7, 9, 13 (the leading error coefficient).
        let quoted = [
            100800.0,
            10059033600.0,
            4487938430976000.0,
            5914384781877411840000.0,
            1.1325077560602111e35,
        ];
        for (c, q) in ABS_C_RECIP.iter().zip(quoted) {
            assert!(((c - q) / q).abs() < 1e-15, "{c} vs {q}");
        }
    }

    fn run_general<const N: usize>(a: [[f64; N]; N]) -> (Choice, [[f64; N]; N]) {
        let mut ws = PadeWorkspace::<SmallMat<N>>::new(N);
        ws.input_mut().0 = a;
        let c = ws.general(Structure::General, None).unwrap();
        (c, ws.result().0)
    }

    /// SciPy `test_padecases`: s·I through the *general* path (bypassing the diagonal shortcut)
    /// hits every Padé degree; the result must be within 100 ulp of e^s.
    #[test]
    fn padecases_every_degree_within_100_ulp() {
        let cases = [
            (1e-2, 3, 0),
            (1e-1, 5, 0),
            (0.5, 7, 0),
            (1.0, 9, 0),
            (10.0, 13, 2),
        ];
        for (s, m, sq) in cases {
            let mut a = [[0.0; 3]; 3];
            for (k, col) in a.iter_mut().enumerate() {
                col[k] = s;
            }
            let (choice, x) = run_general(a);
            assert_eq!(choice.degree, m, "s = {s}");
            assert_eq!(choice.squarings, sq, "s = {s}");
            let e = f64::exp(s);
            for j in 0..3 {
                for i in 0..3 {
                    let want = if i == j { e } else { 0.0 };
                    assert!(
                        (x[j][i] - want).abs() <= 100.0 * f64::EPSILON * e,
                        "s={s} ({i},{j}) {}",
                        x[j][i]
                    );
                }
            }
        }
    }

    #[test]
    fn dense_and_small_backends_agree_bitwise_in_choice() {
        let a = [
            [0.3, -1.2, 0.5, 2.0],
            [1.1, 0.4, -0.7, 0.2],
            [-0.6, 0.9, 1.5, -1.0],
            [0.8, 0.1, -0.3, -2.2],
        ];
        for scale in [1e-3, 0.05, 0.3, 1.0, 3.0, 40.0] {
            let mut sa = a;
            for c in &mut sa {
                for v in c {
                    *v *= scale;
                }
            }
            let (c_small, x_small) = run_general(sa);
            let mut ws = PadeWorkspace::<Mat<f64>>::new(4);
            *ws.input_mut() = Mat::from_fn(4, 4, |i, j| sa[j][i]);
            let c_dense = ws.general(Structure::General, None).unwrap();
            assert_eq!(c_small, c_dense);
            for j in 0..4 {
                for i in 0..4 {
                    let (p, q) = (x_small[j][i], ws.result()[(i, j)]);
                    assert!((p - q).abs() <= 1e-13 * p.abs().max(1.0), "{p} vs {q}");
                }
            }
        }
    }

    #[test]
    fn ell_is_zero_for_normal_and_positive_for_nonnormal() {
        // A nearly-nilpotent, highly non-normal matrix forces ℓ > 0 at degree 3.
        // A = [[1, 1e6], [0, −1]]: ‖ |A|^7 ‖₁ = 7e6 + 1, ‖A‖₁ = 1e6 + 1, so
        // ℓ(A, 3) = ⌈log₂(7.000…/100800 · 2^53)/6⌉ = ⌈39.19/6⌉ = 7.
        let mut ws = PadeWorkspace::<SmallMat<2>>::new(2);
        let a = SmallMat([[1.0, 0.0], [1e6, -1.0]]);
        let mut abs = AbsPowers::start(&mut ws.x);
        assert_eq!(
            abs.ell(&a, &mut ws.abs_t, &mut ws.x, &mut ws.y, 0, a.norm1(), 0),
            7
        );
        let b = SmallMat([[1e-3, 0.0], [0.0, -1e-3]]);
        let mut abs = AbsPowers::start(&mut ws.x);
        assert_eq!(
            abs.ell(&b, &mut ws.abs_t, &mut ws.x, &mut ws.y, 0, b.norm1(), 0),
            0
        );
    }

    #[test]
    fn exp_superdiagonal_matches_divided_difference() {
        for (l1, l2) in [(0.1, 0.1000001), (1.0, -2.0), (-700.0, -750.0), (3.0, 3.0)] {
            let got = exp_superdiagonal(l1, l2, 2.0);
            let want = if l1 == l2 {
                2.0 * f64::exp(l1)
            } else {
                2.0 * (f64::exp(l1) - f64::exp(l2)) / (l1 - l2)
            };
            assert!(
                (got - want).abs() <= 1e-9 * want.abs(),
                "{l1} {l2}: {got} {want}"
            );
        }
        // sinh(−800)/(−800)·e^{−800}: sinh overflows, the value does not.
        let v = exp_superdiagonal(-1600.0, 0.0, 1.0);
        assert!((v - 1.0 / 1600.0).abs() < 1e-18);
    }

    #[test]
    fn exp_2x2_complex_rotation() {
        // exp([[0, θ], [−θ, 0]]) = rotation by θ.
        let th = 0.7;
        let b = exp_2x2_complex(0.0, th, -th, 0.0).unwrap();
        assert!((b[0] - th.cos()).abs() < 1e-15 && (b[1] - th.sin()).abs() < 1e-15);
        assert!((b[2] + th.sin()).abs() < 1e-15 && (b[3] - th.cos()).abs() < 1e-15);
        assert!(exp_2x2_complex(1.0, 1.0, 1.0, 1.0).is_none());
    }

    #[test]
    fn structure_detection() {
        let d = SmallMat([[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]]);
        assert_eq!(Structure::detect(&d), Structure::Diagonal);
        let u = SmallMat([[1.0, 0.0, 0.0], [5.0, 2.0, 0.0], [0.0, 7.0, 3.0]]);
        assert_eq!(Structure::detect(&u), Structure::Upper);
        let l = SmallMat([[1.0, 5.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]]);
        assert_eq!(Structure::detect(&l), Structure::Lower);
        let q = SmallMat([[1.0, -4.0, 0.0], [5.0, 2.0, 0.0], [1.0, 7.0, 3.0]]);
        assert_eq!(Structure::detect(&q), Structure::QuasiUpper);
        let g = SmallMat([[1.0, -4.0, 0.0], [5.0, 2.0, 1.0], [1.0, 7.0, 3.0]]);
        assert_eq!(Structure::detect(&g), Structure::General);
        let g2 = SmallMat([[1.0, 0.0, 1.0], [5.0, 2.0, 0.0], [1.0, 7.0, 3.0]]);
        assert_eq!(Structure::detect(&g2), Structure::General);
    }
}
