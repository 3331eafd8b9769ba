//! A deterministic, packet-friendly power function for the Phong highlight:
//! [`powf_unit`]`(x, e) = x^e` for `x ∈ [0, 1]`, `e ≥ 0`.
//!
//! # Why not `libm::powf`
//! `libm::powf` is correct to the last bit and deterministic, but it is a
//! scalar function full of branches (special cases, a table, an `f64`-free
//! but long path): called per lane it stays scalar and cost 8–10 % of a
//! profile. The highlight needs neither the full domain nor the last bit:
//! its result is scaled by `ks` and quantised to 8 bits. [`powf_unit`]
//! covers exactly the highlight's domain with straight-line code:
//!
//! - `log₂x = k + log₂(1 + u)`: the bit pattern gives `k` and a mantissa
//!   `m = 1 + u ∈ [√½, √2)` (musl's `logf` split: subtracting the bits of
//!   `√½` before taking the exponent centres `m` on 1, so `u = m − 1` is
//!   exact and small); `log₂(1 + u) = u·P(u)` with a degree-8 polynomial
//!   (near-minimax for the relative error on `[√½ − 1, √2 − 1]`, fitted for
//!   this module and rounded to `f32`). The product form keeps the relative
//!   accuracy for `x` near 1, where `log₂x → 0` and a large exponent
//!   amplifies absolute errors.
//! - `2^z`, `z ≤ 0`: `z = n + f` with `n` the nearest integer (the
//!   `1.5·2²³` addition, which also leaves `n` in the low mantissa bits),
//!   `f ∈ [−½, ½]` exact, `2^f = 1 + f·Q(f)` with a degree-5 polynomial, and
//!   `2ⁿ` built from its exponent bits.
//! - Special cases by bit masks, not branches, so that a `for i in 0..W`
//!   loop over lanes vectorises into packed SSE/AVX/AVX-512 code (checked on
//!   x86-64 with `+avx2`: one `ymm` body, no calls, no branches).
//!
//! Only IEEE `+`, `−`, `×` (correctly rounded on every target, hardware or
//! soft-float; Rust never contracts them into FMAs), integer operations on
//! the bit patterns, and `i32 → f32` conversions of small integers (exact):
//! the same bits on every target. No division, no `mul_add`, no tables.
//!
//! # Accuracy
//! Measured by the unit test `accuracy_against_f64_pow` against `f64`
//! `pow` of the same `f32` operands, on a grid of 4 785 values of `x` (a
//! uniform grid, geometric steps down to 10⁻³⁸, subnormals, and dense near
//! 1) × 1 326 values of `e ∈ [0, 1000]` (6.3 million points):
//! - absolute error ≤ `8.4·10⁻⁸` everywhere (about 1.4 ulp at ½; one 8-bit
//!   step is `1/255 ≈ 3.9·10⁻³`);
//! - relative error ≤ `1.3·10⁻⁶` where the result is ≥ 10⁻³: the relative
//!   error of `z = e·log₂x` (a few ulp) becomes `|z|·ln 2` times that in
//!   `2^z`, so smaller results have larger relative errors (≤ `1.1·10⁻⁵` for
//!   results down to 10⁻³⁰), at ever smaller absolute errors.
//!
//! # Domain
//! - `x` NaN → 0;
//! - otherwise `e ≤ 0` or `e` NaN → 1 (`x⁰ = 1`, also for `x = 0`);
//! - otherwise `x ≤ 0` → 0, `x ≥ 1` (and `+∞`) → 1;
//! - results below `2⁻¹²⁵ ≈ 2.4·10⁻³⁸` (including `e = +∞`) → 0.
//!
//! # Fixed point
//! [`crate::Fixed32`]'s `powf` is a different algorithm on purpose: integer
//! shift-and-add `log₂`/`2^f` (a 14-entry table, no multiplies in the loops)
//! suits an FPU-less core, where every `f32` operation above would be a
//! soft-float call. It follows the same domain rules; this module stays a
//! leaf that depends on no scalar type.

/// `log₂(1 + u)/u` on `u ∈ [√½ − 1, √2 − 1]`, degree 8, constant term
/// first, as `f32` bit patterns (≈ 1.442695, −0.72134733, 0.48091063,
/// −0.36070368, 0.28791624, −0.2389448, 0.21571557, −0.20726988,
/// 0.12583728). Evaluated by Horner in `f32`, `u·P(u)` is within 2.4 ulp
/// (relative) of `log₂(1 + u)`.
const LOG2_POLY: [u32; 9] = [
    0x3fb8_aa3b,
    0xbf38_aa38,
    0x3ef6_39eb,
    0xbeb8_ae27,
    0x3e93_69c2,
    0xbe74_adf2,
    0x3e5c_e48b,
    0xbe54_3e8e,
    0x3e00_db7d,
];

/// `(2^f − 1)/f` on `f ∈ [−½, ½]`, degree 5, constant term first, as `f32`
/// bit patterns (≈ 0.6931472, 0.24022649, 0.055503573, 0.009618238,
/// 0.0013390735, 0.00015403554). `1 + f·Q(f)` is within 1.6 ulp of `2^f`.
const EXP2_POLY: [u32; 6] = [0x3f31_7218, 0x3e75_fdef, 0x3d63_57b7, 0x3c1d_95d0, 0x3aaf_83da, 0x3921_849a];

/// Bits of `√½` (0.70710677): the mantissa split point.
const SQRT_HALF_BITS: u32 = 0x3f35_04f3;
/// `1.5·2²³`: adding it rounds any `|z| < 2²²` to an integer (to nearest,
/// ties to even) and leaves that integer in the low mantissa bits.
const ROUND_MAGIC: f32 = 12_582_912.0;
/// Smallest `z` handled: `2^z` stays a normal number (no subnormal rounding,
/// whatever a target's flush-to-zero setting).
const Z_MIN: f32 = -125.0;

/// All ones if `c`, else zero.
#[inline(always)]
fn mask(c: bool) -> u32 {
    (c as u32).wrapping_neg()
}

/// `a` where `m` is all ones, `b` where it is zero (a bitwise blend).
#[inline(always)]
fn select(m: u32, a: f32, b: f32) -> f32 {
    f32::from_bits((a.to_bits() & m) | (b.to_bits() & !m))
}

/// Horner evaluation of a polynomial given as bit patterns, highest
/// coefficient last, in a fixed order.
#[inline(always)]
fn horner<const N: usize>(c: &[u32; N], u: f32) -> f32 {
    let mut p = match c.last() {
        Some(&top) => f32::from_bits(top),
        None => 0.0,
    };
    let mut i = N.saturating_sub(1);
    while i > 0 {
        i -= 1;
        p = p * u + f32::from_bits(c[i]);
    }
    p
}

/// `log₂x` for finite `x > 0` (subnormals included), within a few ulp; any
/// other input gives a value the caller masks out.
#[inline(always)]
fn log2_positive(x: f32) -> f32 {
    // Subnormals: scale into the normal range (exact) and remember it.
    let sub = mask(x < f32::MIN_POSITIVE);
    let xs = select(sub, x * 8_388_608.0, x); // × 2²³
                                              // x = 2^k·m with m ∈ [√½, √2): subtracting √½'s bits makes the exponent
                                              // field of the difference k; the mantissa bits then re-attach to √½'s
                                              // exponent.
    let ix = xs.to_bits().wrapping_sub(SQRT_HALF_BITS);
    let k = ((ix as i32) >> 23) - (sub & 23) as i32;
    let m = f32::from_bits((ix & 0x007f_ffff).wrapping_add(SQRT_HALF_BITS));
    // u = m − 1 is exact (Sterbenz), |u| < 0.415.
    let u = m - 1.0;
    // k is a small integer: the conversion is exact.
    k as f32 + u * horner(&LOG2_POLY, u)
}

/// `2^z` for `z ∈ [−125, 0]` (clamped below), a normal number.
#[inline(always)]
fn exp2_nonpositive(z: f32) -> f32 {
    let z = select(mask(z > Z_MIN), z, Z_MIN); // NaN also becomes Z_MIN
                                               // n = round(z) in the low bits of t; n_f = n exactly; f = z − n ∈ [−½, ½]
                                               // exactly (z and n are within ½ of each other).
    let t = z + ROUND_MAGIC;
    let n_f = t - ROUND_MAGIC;
    let f = z - n_f;
    let n = (t.to_bits() as i32).wrapping_sub(ROUND_MAGIC.to_bits() as i32);
    // 2ⁿ from its exponent field (n + 127 ∈ [2, 127]).
    let scale = f32::from_bits(((n + 127) as u32) << 23);
    (1.0 + f * horner(&EXP2_POLY, f)) * scale
}

/// `x^e` for `x ∈ [0, 1]`, `e ≥ 0`, as `2^(e·log₂x)`: branch-free, the same
/// bits on every target, absolute error ≤ 8.4·10⁻⁸ (see the module
/// documentation for the accuracy and for results outside the domain).
#[inline(always)]
pub fn powf_unit(x: f32, e: f32) -> f32 {
    let z = e * log2_positive(x);
    // Results below 2⁻¹²⁵ (z = −∞ included) and NaN z become 0.
    let y = select(mask(z >= Z_MIN), exp2_nonpositive(z), 0.0);
    // Domain rules, applied in this order (later ones win).
    let y = select(mask(x >= 1.0), 1.0, y);
    let y = select(mask(!(x > 0.0)), 0.0, y);
    let y = select(mask(!(e > 0.0)), 1.0, y);
    select(mask(x.is_nan()), 0.0, y)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    #[test]
    // The polynomials' leading coefficients are within an ulp of log2(e) and
    // ln 2 but are fitted values, written out as documented.
    #[allow(clippy::approx_constant)]
    fn coefficients_are_the_documented_values() {
        let log2 = [
            1.442695f32,
            -0.72134733,
            0.48091063,
            -0.36070368,
            0.28791624,
            -0.2389448,
            0.21571557,
            -0.20726988,
            0.12583728,
        ];
        for (b, v) in LOG2_POLY.iter().zip(log2) {
            assert_eq!(*b, v.to_bits());
        }
        let exp2 = [0.6931472f32, 0.24022649, 0.055503573, 0.009618238, 0.0013390735, 0.00015403554];
        for (b, v) in EXP2_POLY.iter().zip(exp2) {
            assert_eq!(*b, v.to_bits());
        }
        assert_eq!(f32::from_bits(SQRT_HALF_BITS), core::f32::consts::FRAC_1_SQRT_2);
    }

    #[test]
    fn log2_and_exp2_are_within_a_few_ulp() {
        // log₂ relative to its value, over many binades and subnormals.
        let mut worst_log: f64 = 0.0;
        let mut x = 1.0e-45f32;
        while x < 4.0 {
            let got = log2_positive(x) as f64;
            let want = libm::log2(x as f64);
            if want != 0.0 {
                worst_log = worst_log.max(((got - want) / want).abs());
            }
            x = f32::from_bits(x.to_bits() + 9_973);
        }
        assert!(worst_log < 3.0 * f32::EPSILON as f64, "log2 relative error {worst_log:e}");
        let mut worst_exp: f64 = 0.0;
        let mut z = 0.0f32;
        while z > -125.0 {
            let got = exp2_nonpositive(z) as f64;
            let want = libm::exp2(z as f64);
            worst_exp = worst_exp.max(((got - want) / want).abs());
            z -= 0.000_731;
        }
        assert!(worst_exp < 2.5 * f32::EPSILON as f64, "exp2 relative error {worst_exp:e}");
    }

    #[test]
    fn domain_rules() {
        let nan = f32::NAN;
        assert_eq!(powf_unit(nan, 2.0), 0.0);
        assert_eq!(powf_unit(nan, 0.0), 0.0);
        assert_eq!(powf_unit(0.5, 0.0), 1.0);
        assert_eq!(powf_unit(0.5, -3.0), 1.0);
        assert_eq!(powf_unit(0.5, nan), 1.0);
        assert_eq!(powf_unit(0.0, 0.0), 1.0);
        assert_eq!(powf_unit(-0.0, 0.0), 1.0);
        assert_eq!(powf_unit(0.0, 5.0), 0.0);
        assert_eq!(powf_unit(-0.0, 5.0), 0.0);
        assert_eq!(powf_unit(-0.5, 5.0), 0.0);
        assert_eq!(powf_unit(f32::NEG_INFINITY, 5.0), 0.0);
        assert_eq!(powf_unit(1.0, 5.0), 1.0);
        assert_eq!(powf_unit(2.0, 5.0), 1.0);
        assert_eq!(powf_unit(f32::INFINITY, 5.0), 1.0);
        assert_eq!(powf_unit(1.0, f32::INFINITY), 1.0);
        assert_eq!(powf_unit(0.999, f32::INFINITY), 0.0);
        assert_eq!(powf_unit(0.5, 200.0), 0.0); // 2⁻²⁰⁰ underflows
        assert_eq!(powf_unit(1.0e-45, 0.001), libm::powf(1.0e-45, 0.001));
        // Exact for powers of two with integer exponents.
        assert_eq!(powf_unit(0.5, 2.0), 0.25);
        assert_eq!(powf_unit(0.25, 3.0), 1.0 / 64.0);
        assert_eq!(powf_unit(0.5, 1.0), 0.5);
    }

    /// The documented accuracy, against `f64` `pow` of the same operands.
    #[test]
    fn accuracy_against_f64_pow() {
        let mut xs: Vec<f32> = Vec::new();
        for k in 0..=2_000 {
            xs.push(k as f32 / 2_000.0);
        }
        for k in 1..=2_000 {
            xs.push(1.0 - k as f32 * 1.0e-5); // near 1: large-e highlights
        }
        for k in 1..=64 {
            xs.push(1.0 - k as f32 * f32::EPSILON / 2.0);
        }
        let mut t = 1.0e-38f32;
        while t < 1.0 {
            xs.push(t);
            t *= 1.13;
        }
        xs.extend([1.0e-40, 1.0e-45, f32::MIN_POSITIVE, 0.999_999_94]);
        let mut es: Vec<f32> = (0..=1_000).map(|k| k as f32).collect();
        es.extend((0..200).map(|k| k as f32 * 0.05));
        es.extend((1..=125).map(|k| k as f32 * 7.77));
        let (mut worst_abs, mut worst_rel, mut worst_rel_tiny): (f64, f64, f64) = (0.0, 0.0, 0.0);
        for &x in &xs {
            for &e in &es {
                let got = powf_unit(x, e) as f64;
                let want = if e == 0.0 { 1.0 } else { libm::pow(x as f64, e as f64) };
                let want = if want < libm::exp2(-125.0) { 0.0 } else { want };
                let abs = (got - want).abs();
                worst_abs = worst_abs.max(abs);
                if want >= 1.0e-3 {
                    worst_rel = worst_rel.max(abs / want);
                } else if want >= 1.0e-30 {
                    worst_rel_tiny = worst_rel_tiny.max(abs / want);
                }
                assert!(abs <= 8.4e-8 && (want < 1.0e-30 || abs / want < 1.2e-5), "{x:e}^{e} = {got:e}, want {want:e}");
            }
        }
        assert!(worst_abs <= 8.4e-8, "max abs error {worst_abs:e}");
        assert!(worst_rel <= 1.3e-6, "max rel error (results ≥ 1e-3) {worst_rel:e}");
        assert!(worst_rel_tiny <= 1.2e-5, "max rel error (1e-30 ≤ results < 1e-3) {worst_rel_tiny:e}");
        std::println!("powf_unit: max abs {worst_abs:e}, max rel (≥1e-3) {worst_rel:e}, max rel (≥1e-30) {worst_rel_tiny:e} over {} points", xs.len() * es.len());
    }
}
