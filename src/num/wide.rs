//! The unsigned 32×32→64 product, picked per target: [`wmul`]. The wide
//! primitive of `Fixed32`'s division, square root and power, and of `f32`'s
//! software square root (`num::sqrtf`). It uses nothing else of the crate.
//!
//! The limb variant is chosen on 32-bit Arm without 32-bit atomics, i.e.
//! Armv6-M (Cortex-M0/M0+/M1), which has no long multiply
//! (`umull`/`smull`): there LLVM would call `__aeabi_lmul`, a full 64×64
//! product. Stable `cfg` exposes no Arm ISA features, so the absence of
//! atomics (which Armv7-M and later have) is the discriminator; both
//! variants are compiled and tested against each other on every host
//! (`fixed32`'s `wide_products_agree`), and give the same bits everywhere.

/// Unsigned 32×32→64 product, native (`u64` multiply).
#[inline(always)]
#[cfg_attr(armv6m, allow(dead_code))]
pub(crate) fn wmul_native(a: u32, b: u32) -> u64 {
    a as u64 * b as u64
}

/// Unsigned 32×32→64 product from four 16×16→32 products (schoolbook on
/// 16-bit limbs), for cores without a long multiply. The two cross products
/// may sum past 2³²; that carry has weight 2⁴⁸.
#[inline(always)]
#[cfg_attr(not(armv6m), allow(dead_code))]
pub(crate) fn wmul_limbs(a: u32, b: u32) -> u64 {
    let (al, ah, bl, bh) = (a & 0xFFFF, a >> 16, b & 0xFFFF, b >> 16);
    let (mid, c_mid) = (al * bh).overflowing_add(ah * bl);
    let (lo, c_lo) = (al * bl).overflowing_add(mid << 16);
    // The true high word is below 2³², so these sums cannot overflow.
    let hi = ah * bh + (mid >> 16) + ((c_mid as u32) << 16) + c_lo as u32;
    ((hi as u64) << 32) | lo as u64
}

/// Unsigned 32×32→64 product: [`wmul_limbs`] on Armv6-M, [`wmul_native`]
/// elsewhere.
#[inline(always)]
pub(crate) fn wmul(a: u32, b: u32) -> u64 {
    #[cfg(armv6m)]
    {
        wmul_limbs(a, b)
    }
    #[cfg(not(armv6m))]
    {
        wmul_native(a, b)
    }
}
