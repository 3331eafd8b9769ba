//! The correctly rounded `f32` square root in integer arithmetic:
//! [`sqrtf`].
//!
//! # Why not `libm::sqrtf`
//! Without `std`, `core` offers no `f32::sqrt` on stable Rust, so the
//! firmware's `f32` took `libm::sqrtf`, which after the root adds a tiny
//! value to the result only to raise the floating-point environment's
//! "inexact" flag: a sum that cannot change the result in round-to-nearest,
//! for a flag raypack never reads. With soft float that sum is a library
//! call of its own; with an FPU it is still about 8 of the routine's 48
//! instructions. [`sqrtf`] is the same algorithm without it, and with the
//! rare inputs (zero, subnormals, infinity, NaN, negatives) behind one
//! comparison. The Cortex-M55's Helium and RISC-V's vectors have no vector
//! square root that stable Rust can reach, so packets take it lane by lane.
//!
//! One copy, called: written in line at every use it made the Cortex-M55's
//! packet frames longer (width 4: 33.4 M instructions against 32.6 M) and
//! its image 14 KB larger (`./scripts/firmware.sh`).
//!
//! # The algorithm (musl's `sqrtf`, by Szabolcs Nagy; as in the `libm` crate)
//! `x = 4^e·m` with `m ∈ [1, 4)`, so `√x = 2^e·√m`. A 128-entry table gives
//! `r ≈ 1/√m` to 2⁻⁸; two Goldschmidt iterations in 32-bit fixed point
//! refine `r` and `s = m·r ≈ √m` together (each step
//! `u = 3 − s·r`, `r ← r·u/2`, `s ← s·u/2` roughly squares the error),
//! leaving `s < √m < s + 1.04·2⁻²³` in the significand's units. The correctly
//! rounded result is then `s` or `s + 1 ulp`: the sign of
//! `2^(2p)·m − (s + ½)²`, formed exactly in wrapping 32-bit arithmetic,
//! chooses. The only operations are integer ones (`mulh` as a 32×32→64
//! product's high word), so the result is the same on every target, and it
//! equals IEEE 754's correctly rounded square root: unique, so also
//! `f32::sqrt`'s and `sqrtss`'s (the host tests compare every 97th bit
//! pattern against `f32::sqrt`).

use crate::num::wide::wmul;

/// `1/√m` estimates: entry `i` is for the mantissa's top bits `i` (the
/// exponent's last bit and six fraction bits), in 0.16 fixed point. The
/// table of musl and of the `libm` crate (MIT licence).
static RSQRT_TAB: [u16; 128] = [
    0xb451, 0xb2f0, 0xb196, 0xb044, 0xaef9, 0xadb6, 0xac79, 0xab43, 0xaa14, 0xa8eb, 0xa7c8, 0xa6aa, 0xa592, 0xa480,
    0xa373, 0xa26b, 0xa168, 0xa06a, 0x9f70, 0x9e7b, 0x9d8a, 0x9c9d, 0x9bb5, 0x9ad1, 0x99f0, 0x9913, 0x983a, 0x9765,
    0x9693, 0x95c4, 0x94f8, 0x9430, 0x936b, 0x92a9, 0x91ea, 0x912e, 0x9075, 0x8fbe, 0x8f0a, 0x8e59, 0x8daa, 0x8cfe,
    0x8c54, 0x8bac, 0x8b07, 0x8a64, 0x89c4, 0x8925, 0x8889, 0x87ee, 0x8756, 0x86c0, 0x862b, 0x8599, 0x8508, 0x8479,
    0x83ec, 0x8361, 0x82d8, 0x8250, 0x81c9, 0x8145, 0x80c2, 0x8040, 0xff02, 0xfd0e, 0xfb25, 0xf947, 0xf773, 0xf5aa,
    0xf3ea, 0xf234, 0xf087, 0xeee3, 0xed47, 0xebb3, 0xea27, 0xe8a3, 0xe727, 0xe5b2, 0xe443, 0xe2dc, 0xe17a, 0xe020,
    0xdecb, 0xdd7d, 0xdc34, 0xdaf1, 0xd9b3, 0xd87b, 0xd748, 0xd61a, 0xd4f1, 0xd3cd, 0xd2ad, 0xd192, 0xd07b, 0xcf69,
    0xce5b, 0xcd51, 0xcc4a, 0xcb48, 0xca4a, 0xc94f, 0xc858, 0xc764, 0xc674, 0xc587, 0xc49d, 0xc3b7, 0xc2d4, 0xc1f4,
    0xc116, 0xc03c, 0xbf65, 0xbe90, 0xbdbe, 0xbcef, 0xbc23, 0xbb59, 0xba91, 0xb9cc, 0xb90a, 0xb84a, 0xb78c, 0xb6d0,
    0xb617, 0xb560,
];

/// The high word of the unsigned 32×32→64 product: `umull` or `mulhu`
/// where there is a long multiply, 16-bit limbs on Armv6-M (`wmul`, where
/// LLVM would call `__aeabi_lmul`, a full 64×64 product).
#[inline(always)]
fn mulh(a: u32, b: u32) -> u32 {
    (wmul(a, b) >> 32) as u32
}

/// `√x`, correctly rounded (round to nearest, ties to even), bit for bit
/// IEEE 754's: `±0` for `±0`, `+∞` for `+∞`, NaN for NaN and for negative
/// `x`.
#[inline(never)]
pub(crate) fn sqrtf(x: f32) -> f32 {
    let ix = x.to_bits();
    // One unsigned comparison sends zero, subnormals, infinity, NaN and
    // every negative number (sign bit set) to `special`.
    if ix.wrapping_sub(0x0080_0000) >= 0x7f80_0000 - 0x0080_0000 {
        return special(x);
    }
    // `m`: the significand as a U2.30 number in [1, 4), the exponent's
    // parity folded in (an odd unbiased exponent doubles it); `ey`: the result's
    // exponent field, half the input's (rebiased).
    let even = ix & 0x0080_0000 != 0;
    let m = if even { (ix << 7) & 0x7fff_ffff } else { (ix << 8) | 0x8000_0000 };
    let ey = ((ix >> 1).wrapping_add(0x3f80_0000 >> 1)) & 0x7f80_0000;
    // `r ≈ 1/√m` (U0.32) to 2⁻⁸ from the table, indexed by the exponent's
    // last bit and the top six fraction bits.
    let three = 0xc000_0000u32; // 3 in U2.30
    let mut r = (RSQRT_TAB[((ix >> 17) & 127) as usize] as u32) << 16;
    // First Goldschmidt step from `m` itself (no accumulated error):
    // `s = m·r ≈ √m`, `u = 3 − s·r ≈ 2`, then `r·u/2`, `s·u/2` (the
    // products' units and the halving together are one left shift):
    // `|r·√m − 1| < 1.48·2⁻¹⁶`.
    let mut s = mulh(m, r);
    let d = mulh(s, r);
    let u = three.wrapping_sub(d);
    r = mulh(r, u) << 1;
    s = mulh(s, u) << 1;
    // Second step from `s` and `r` alone; `s` ends in U3.29 with
    // −1.02·2⁻²⁸ < s/√m − 1 < 1.99·2⁻²⁴ (musl's bounds).
    let d = mulh(s, r);
    let u = three.wrapping_sub(d);
    s = mulh(s, u);
    // The significand's 24 bits (1 ulp = 2⁻²³ of `m`'s units), truncated
    // after stepping below: `s < √m < s + 1.04 ulp`.
    s = s.wrapping_sub(1) >> 6;
    // Round: `d0 = (m << 16) − s²` and `d1 = s − d0` are, modulo 2³²,
    // `s² + s − M` with `M` the value `m` in the units of `s²`; that
    // difference is small, so the wrapped word keeps its sign: negative
    // exactly when `(s + ½)² < M`, that is when the root lies past the
    // midpoint `s + ½`, where the result is `s + 1` (no tie: `(s + ½)²` is
    // not an integer).
    let d0 = (m << 16).wrapping_sub(s.wrapping_mul(s));
    let d1 = s.wrapping_sub(d0);
    s = s.wrapping_add(d1 >> 31);
    f32::from_bits((s & 0x007f_ffff) | ey)
}

/// The inputs outside the normal positive numbers: `±0` and `+∞` are their
/// own roots, NaN and negative numbers give NaN (like `libm::sqrtf`), and
/// the rare subnormals go to `libm` (which scales them into the normal
/// range first).
#[inline(always)]
fn special(x: f32) -> f32 {
    let ix = x.to_bits();
    if ix << 1 == 0 || ix == 0x7f80_0000 {
        x
    } else if ix > 0x7f80_0000 {
        f32::NAN
    } else {
        subnormal(x)
    }
}

/// A subnormal's root, out of line (no scene forms one in practice).
#[cold]
#[inline(never)]
fn subnormal(x: f32) -> f32 {
    libm::sqrtf(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same bits as `f32::sqrt` (the hardware's correctly rounded
    /// root) for every 97th bit pattern, positive and negative, and for the
    /// special values and the neighbours of every power of two; NaN where
    /// it gives NaN.
    #[test]
    fn sqrtf_is_the_correctly_rounded_root() {
        let check = |x: f32| {
            let (got, want) = (sqrtf(x), x.sqrt());
            if want.is_nan() {
                assert!(got.is_nan(), "{x:e} ({:#x}): {got:e}", x.to_bits());
            } else {
                assert_eq!(got.to_bits(), want.to_bits(), "{x:e} ({:#x})", x.to_bits());
            }
        };
        let mut bits = 0u32;
        loop {
            check(f32::from_bits(bits));
            match bits.checked_add(97) {
                Some(b) => bits = b,
                None => break,
            }
        }
        for x in [0.0, -0.0, f32::INFINITY, f32::NEG_INFINITY, f32::NAN, f32::MIN_POSITIVE, f32::MAX, 1.0, 4.0, 2.0] {
            check(x);
        }
        for e in 0..255u32 {
            let p = e << 23;
            for b in [p, p.wrapping_sub(1), p + 1, p | 0x7f_ffff, p | 0x40_0000] {
                check(f32::from_bits(b));
            }
        }
    }

    /// Perfect squares come out exact (the rounding step's tie-free case).
    #[test]
    fn sqrtf_of_a_square_is_exact() {
        for k in 1..=4096u32 {
            let k = k as f32;
            assert_eq!(sqrtf(k * k), k);
            assert_eq!(sqrtf(k * k / 65536.0), k / 256.0);
        }
    }
}
