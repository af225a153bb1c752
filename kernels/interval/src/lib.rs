//! Rigorous interval kernels for `sporadic` (issue 24, "Proofs, not samples").
//!
//! * [`Interval`]: scalar intervals `[lo, hi]` with outward rounding (+, −, ×, ÷, x², √, xⁿ,
//!   eˣ, hull, intersection, containment).
//! * [`IntervalMatrix`]: interval matrices in midpoint–radius form with +, −, × (rigorous
//!   error bound of the floating-point midpoint product), scaling by an interval, rigorous
//!   upper bounds of ‖·‖_∞, ‖·‖₁, ‖·‖_F, ‖·‖₂, hull, containment tests.
//! * [`expm_enclosure`]: an interval matrix containing e^{Aτ} for **every** τ in [τ0, τ1]
//!   (plus tighter per-piece enclosures), [`expm_interval`]: e^X for every X in an interval matrix.
//! * [`is_verified_positive_definite`] / [`is_verified_negative_definite`]: Rump's verified
//!   definiteness test for symmetric interval matrices, with a rigorous eigenvalue bound.
//! * [`double_double`]: double-double arithmetic for small dense matrices (products, the
//!   inverse of a triangular matrix, the matrix exponential), for evaluations whose double
//!   precision errors a later product would amplify.
//!
//! Bad input gives a typed [`IntervalError`], never a panic (the `std::ops` operators on
//! interval matrices panic on shape mismatch like faer's; use the `checked_*` methods for a
//! `Result`).
//!
//! # Rounding: own directed rounding, not `inari`
//!
//! Rust has no portable control of the FPU rounding mode. Two options were measured on the
//! project machine (2-core x86-64 with AVX-512, shared and loaded, so ±30 %): a 10×10 interval
//! matrix product with thin random entries, averaged over 200 000 repetitions.
//!
//! | implementation | build flags needed | 10×10 product |
//! |---|---|---|
//! | `inari` 2.0.0 (`default-features = false`), inf–sup, naive triple loop | **does not compile** without `-Ctarget-cpu=haswell` (`compile_error!`) | — |
//! | same, `RUSTFLAGS=-Ctarget-cpu=haswell` (AVX2/FMA, rounding via MXCSR) | workspace-wide RUSTFLAGS | 60–71 µs |
//! | same, `RUSTFLAGS=-Ctarget-cpu=native` (AVX-512 embedded rounding) | non-portable binary | 4.7–6.5 µs |
//! | own inf–sup with `f64::next_up`/`next_down`, naive triple loop | none | 14–20 µs |
//! | **own midpoint–radius product on faer GEMM + a-priori error bound (this crate)** | none | **3.5–4.2 µs** |
//!
//! (Numbers from a scratch crate in /tmp for `inari` and the naive loop, and from
//! `examples/measure.rs` for ours; same data, same machine, same timing loop.)
//!
//! Decision: **own directed rounding**. `inari` cannot be built by the workspace as it is: it
//! requires a target-CPU flag that a member crate's `Cargo.toml` cannot set (it would need a
//! root `.cargo/config.toml` or RUSTFLAGS for everybody, rebuilding the whole workspace and
//! making binaries non-portable to pre-Haswell CPUs); its default `gmp` feature also builds
//! GMP/MPFR from C. Its fast path needs AVX-512, and its AVX2 path is slower than ours. Our
//! matrix product uses three floating-point GEMMs, so it is faster than any entrywise interval
//! loop, and all our kernels (exponential enclosure, definiteness) are matrix-level.
//!
//! How rounding is made rigorous without a rounding mode (module-private `round`):
//! * scalars: TwoSum (exact error of a sum) for ±, one ulp outward (`next_up`/`next_down`) after
//!   round-to-nearest ×, ÷, √ (the exact result is within half an ulp of the rounded one, also
//!   in the subnormal range; overflow to ±∞ is mapped to ∓`f64::MAX` on the inner side);
//! * matrices, midpoint–radius ⟨Am, Ar⟩·⟨Bm, Br⟩ ⊆ ⟨Cm, Cr⟩ with Cm = fl(Am·Bm) by GEMM (any
//!   summation order, FMA or not) and
//!   Cr = (fl(|Am|·(Br + γ_k|Bm|) + Ar·(|Bm| + Br)) + 3kη)/(1 − γ_{2k}) rounded up, where
//!   γ_k = ku/(1 − ku), u = 2⁻⁵³, η = 2⁻¹⁰⁷⁴ (underflow), k the inner dimension. Terms: the
//!   exact range |Am|Br + Ar(|Bm| + Br) of XY − AmBm; the GEMM error γ_k|Am||Bm| + kη of the
//!   midpoint; and the rounding error of the radius GEMM itself (a sum of 2k non-negative
//!   products, relative error ≤ γ_{2k}, plus 2kη).
//!
//! Why midpoint–radius: products map to floating-point GEMM (fast, as above); the radius is a
//! direct measure of the width; and the overestimation of the midpoint–radius product against
//! the exact interval product is at most a factor 1.5 (Rump 1999) and negligible for the thin
//! matrices of the exponential enclosure. Entries with an unbounded radius are the whole real
//! line (midpoint 0), so overflow never produces a wrong enclosure.
//!
//! # Enclosure of e^{Aτ}
//! See [`expm_enclosure`] (method, remainder bound and its proof) and [`expm_interval`].
//! Typical relative widths over τ ∈ [0.2, 0.21] (`examples/measure.rs`, default options) are
//! those of the true variation of e^{Aτ} over the window (≈ ‖A‖·0.01, e.g. 1.0e-2 for
//! [[0, 1], [−39, −40]], 1.0e-1 for a rotation with ω = 10), per-piece widths ≤ 1.6e-3 (ω = 100:
//! 1.6e-2 with 64 pieces), and 1e-16…7e-11 for a point window τ0 = τ1 = 0.2.
//!
//! # Verified definiteness
//! See [`is_verified_positive_definite`]: Cholesky of Ã = fl(mid − σI) in floating point; if it
//! succeeds, λ_min(Ã) ≥ −(β·Σ_j(ã_jj + υ) + 2υ) with β = γ_{n+2}/(1 − γ_{n+2}) and υ a (tiny)
//! underflow term, so every symmetric member X of ⟨mid, rad⟩ has
//! λ_min(X) ≥ min_j(mid_jj − ã_jj) − β·Σ_j(ã_jj + υ) − 2υ − ‖rad‖_∞ (all rounded downward).

mod definite;
pub mod double_double;
mod error;
mod expm;
mod matrix;
mod round;
mod scalar;

pub use definite::{
    Verdict, is_verified_negative_definite, is_verified_positive_definite, lambda_max_enclosure,
};
pub use error::IntervalError;
pub use expm::{
    EnclosureOptions, EnclosurePiece, ExpmEnclosure, MAX_BASIS_CONDITION, expm_enclosure,
    expm_enclosure_interval, expm_interval,
};
pub use matrix::IntervalMatrix;
pub use scalar::Interval;

/// Rounding constants used in the bounds (u = 2⁻⁵³ and η = 2⁻¹⁰⁷⁴).
pub mod constants {
    pub use crate::round::{ETA, UNIT_ROUNDOFF};
}

/// Error-free transformations of a sum and a product (the exact rounding error as a second
/// double), for residuals computed in double-double arithmetic.
pub mod exact {
    pub use crate::round::{two_prod, two_sum};
}
