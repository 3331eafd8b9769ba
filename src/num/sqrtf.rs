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
//! square root that stable Rust can reach; packets there take
//! [`sqrtf_lanes`], the same bits in a form LLVM vectorises.
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

/// Which of [`root_bits`]' two equal last steps [`sqrtf_lanes`] takes:
/// whichever LLVM's SLP vectoriser turns into vector code on the target.
/// For packets of 4 on Helium only the stepwise one (three steps up)
/// became vector code, on RISC-V's vectors only the closed form; both did
/// at 8 (checked in the disassembly: the other form stayed scalar, lane
/// by lane).
const CLOSED_ROUNDING: bool = cfg!(target_arch = "riscv32");

/// `√x` of every lane, bit for bit [`sqrtf`]'s, in a form the vectorisers
/// turn into vector code: no table, no 64-bit product, no branch per lane.
/// For the packets of targets with vector `f32` lanes (the Cortex-M55's
/// Helium, RISC-V's vectors), where [`sqrtf`] runs lane by lane: its table
/// lookups and 32×32→64 products stay scalar there (Helium's `vmulh` is
/// not what LLVM's vectorisers form from a 64-bit product), this is one
/// vector sequence for four lanes (`Scalar::LANE_SQRT` for `f32`).
///
/// Out of line, one copy per width: written in line at every use, the
/// vector code lost to the register pressure around it (the Cortex-M55's
/// width 4 took 32.75 M instructions against 32.19 M, the image 14.6 KB
/// larger; `./scripts/firmware.sh`).
///
/// Each lane of a positive normal `x` gets [`root_bits`]; `±0` and `+∞`
/// are their own roots and NaN and negative numbers give NaN, as from
/// [`sqrtf`], chosen lane by lane; positive subnormals (which no scene
/// forms in practice) take [`sqrtf`] itself afterwards, lane by lane.
#[inline(never)]
#[cfg_attr(not(hard_float), allow(dead_code))]
pub(crate) fn sqrtf_lanes<const W: usize>(x: [f32; W]) -> [f32; W] {
    let mut out = x;
    // (Every lane's root, then the selections, each without a branch.)
    for o in out.iter_mut() {
        *o = f32::from_bits(root_bits::<CLOSED_ROUNDING>(o.to_bits()));
    }
    // The smallest `ix − 1` (wrapping): below 2²³ − 1 exactly when some
    // lane is a positive subnormal (a reduction, not a branch per lane).
    let mut least = u32::MAX;
    for (o, &v) in out.iter_mut().zip(x.iter()) {
        let ix = v.to_bits();
        // All-ones masks, combined with `&` and `|` (a comparison chosen
        // with `if` or `||` became a branch per lane).
        let mask = |c: bool| 0u32.wrapping_sub(c as u32);
        let normal = mask(ix.wrapping_sub(0x0080_0000) < 0x7f80_0000 - 0x0080_0000);
        // Zero keeps its sign, +∞ is itself; NaN and negatives: NaN.
        let own = mask(ix << 1 == 0) | mask(ix == 0x7f80_0000);
        let special = (ix & own) | (f32::NAN.to_bits() & !own);
        least = least.min(ix.wrapping_sub(1));
        *o = f32::from_bits((o.to_bits() & normal) | (special & !normal));
    }
    // Positive subnormals: 1 ..= 2²³ − 1.
    if least < 0x007f_ffff {
        for (o, &v) in out.iter_mut().zip(x.iter()) {
            if v.to_bits().wrapping_sub(1) < 0x007f_ffff {
                *o = sqrtf(v);
            }
        }
    }
    out
}

/// The bits of `√x` for the bits `ix` of a positive normal `x`, correctly
/// rounded; another `ix` gives some value (no panic).
///
/// An estimate first, in `f32` arithmetic: the bit trick
/// `y₀ = 0x5f3759df − ix/2` gives `1/√x` to 3.5 %; three Newton steps
/// `y ← (y/2)·(3 − (x·y)·y)` bring it to a few units in the last place
/// (the products in that order, so that no intermediate is subnormal or
/// overflows for any normal `x`), and `s = x·y`. Then exact integer
/// arithmetic, as in [`sqrtf`]: with `m` the significand in U2.30 (the
/// exponent's parity folded in) and `M = m·2¹⁶`, the candidate
/// significand `g` (24 bits, the implicit one included; `s`'s offset
/// from the result's binade, clamped into it) has the residual
/// `d = M − g²`, exact in wrapping 32-bit arithmetic as it is small. The
/// candidate lies within −2 … +3 of the rounded root (found by checking
/// every positive normal `f32`). Each step down (`d < 0`: `g` is past
/// `⌊√M⌋`) moves `g` by one and `d` with it; after three, `g` is at most
/// `⌊√M⌋` and at least the rounded root minus two. The rounding then adds
/// one for each of `g + ½` and `g + 3/2` that `√M` lies past (no ties:
/// `(g + ½)²` is not an integer), either by steps up or in closed form
/// (`CLOSED`; the same result). The tests compare both forms with
/// `f32::sqrt` for every 97th bit pattern; both were checked once for all
/// 2³² patterns.
#[inline(always)]
#[cfg_attr(not(hard_float), allow(dead_code))]
fn root_bits<const CLOSED: bool>(ix: u32) -> u32 {
    let x = f32::from_bits(ix);
    let mut y = f32::from_bits(0x5f37_59df_u32.wrapping_sub(ix >> 1));
    for _ in 0..3 {
        let t = (x * y) * y;
        y = (0.5 * y) * (3.0 - t);
    }
    let s = x * y;
    // `m` and the result's exponent field `ey`, as in `sqrtf`.
    let even = ix & 0x0080_0000 != 0;
    let m = if even { (ix << 7) & 0x7fff_ffff } else { (ix << 8) | 0x8000_0000 };
    let ey = ((ix >> 1).wrapping_add(0x3f80_0000 >> 1)) & 0x7f80_0000;
    // `s` in units of the result's last place, kept within its binade.
    let k = (s.to_bits() as i32).wrapping_sub(ey as i32).clamp(0, 0x007f_ffff) as u32;
    let mut g = k | 0x0080_0000;
    let mut d = (m << 16).wrapping_sub(g.wrapping_mul(g)) as i32;
    for _ in 0..3 {
        // (g − 1)² = g² − 2(g − 1) − 1: the residual grows by 2(g − 1) + 1.
        let down = d < 0;
        let h = g.wrapping_sub(down as u32);
        d = if down { d.wrapping_add(h.wrapping_mul(2).wrapping_add(1) as i32) } else { d };
        g = h;
    }
    if CLOSED {
        // The rounded root is `g`, plus one past `g + ½` (`M ≥ g² + g + 1`,
        // that is `d > g`), plus one more past `g + 3/2` (`M ≥ g² + 3g + 3`,
        // that is `d > 3g + 2`).
        let half = d > g as i32;
        let three_halves = d > g.wrapping_mul(3).wrapping_add(2) as i32;
        g = g.wrapping_add(half as u32).wrapping_add(three_halves as u32);
    } else {
        // The same in steps: up to `⌊√M⌋` (`d > 2g`: `(g + 1)² ≤ M`), three
        // times where once is enough (once `g` is the floor a step changes
        // nothing; see `CLOSED_ROUNDING`), then one more past `g + ½`.
        for _ in 0..3 {
            let up = d > g.wrapping_mul(2) as i32;
            d = if up { d.wrapping_sub(g.wrapping_mul(2).wrapping_add(1) as i32) } else { d };
            g = g.wrapping_add(up as u32);
        }
        g = g.wrapping_add((d > g as i32) as u32);
    }
    (g & 0x007f_ffff).wrapping_add(ey)
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

    /// The lane routine gives `sqrtf`'s bits, that is `f32::sqrt`'s (NaN
    /// where it gives NaN), in packets of 4 and 8 of every 97th bit
    /// pattern, with special values and subnormals mixed into packets of
    /// normal numbers, and on inputs whose estimate needs all three steps
    /// down (found by checking every positive normal `f32`).
    #[test]
    fn sqrtf_lanes_is_the_correctly_rounded_root() {
        fn check<const W: usize>(x: [f32; W]) {
            let got = sqrtf_lanes(x);
            for (g, v) in got.iter().zip(x) {
                let want = v.sqrt();
                if want.is_nan() {
                    assert!(g.is_nan(), "{v:e} ({:#x}): {g:e}", v.to_bits());
                } else {
                    assert_eq!(g.to_bits(), want.to_bits(), "{v:e} ({:#x})", v.to_bits());
                }
            }
        }
        let mut bits = 0u32;
        let mut next = || {
            let b = bits;
            bits = bits.wrapping_add(97);
            f32::from_bits(b)
        };
        for _ in 0..(u32::MAX / 97 / 12) {
            check([next(), next(), next(), next()]);
            check([next(), next(), next(), next(), next(), next(), next(), next()]);
        }
        let odd = [0.0, -0.0, f32::INFINITY, f32::NEG_INFINITY, f32::NAN, -1.0, f32::MIN_POSITIVE, f32::MAX];
        let sub =
            [f32::from_bits(1), f32::from_bits(0x7f_ffff), f32::from_bits(0x40_0000), f32::from_bits(0x8000_0001)];
        for (i, &v) in odd.iter().chain(&sub).enumerate() {
            let mut p = [2.0, 0.25, 1.0e-30, 7.0e30];
            p[i % 4] = v;
            check(p);
        }
        check(sub);
        // Inputs whose estimate lies three above the floor of the root.
        check([0x0140_11a6, 0x0d40_8104, 0x1a40_11a6, 0x2640_8104].map(f32::from_bits));
        check([0x3340_11a6, 0x3f40_8104, 0x4c40_11a6, 0x5840_8104].map(f32::from_bits));
    }

    /// Both last steps of `root_bits` (the lanes take one per target) give
    /// `f32::sqrt`'s bits for every 97th positive normal number and for
    /// estimates three above the floor of the root.
    #[test]
    fn both_roundings_of_the_lane_root_are_correct() {
        let check = |ix: u32| {
            let want = f32::from_bits(ix).sqrt().to_bits();
            assert_eq!(root_bits::<true>(ix), want, "{ix:#x}, closed");
            assert_eq!(root_bits::<false>(ix), want, "{ix:#x}, in steps");
        };
        let mut ix = 0x0080_0000u32;
        while ix < 0x7f80_0000 {
            check(ix);
            ix += 97;
        }
        for ix in [0x0140_11a6, 0x0d40_8104, 0x0080_0000, 0x7f7f_ffff, 0x3f80_0000, 0x4080_0000] {
            check(ix);
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
