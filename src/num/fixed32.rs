//! [`Fixed32`]: a fast fixed-point [`Scalar`] with 32-bit storage, signed
//! Q8.24 (an `i32` raw value `r` stands for `r·2⁻²⁴`), for FPU-less
//! microcontrollers where the 64-bit [`crate::num::fixed64::Fixed`] is too slow.
//!
//! # Why Q8.24, and the coordinate box
//! On a Cortex-M0 (Armv6-M: no FPU, no divide, no CLZ, no 32×32→64
//! multiply) a 32.32 product costs a 64×64→128 multiply built from sixteen
//! 16-bit partial products; a Q8.24 product needs one 32×32→64 product, four
//! 16-bit partial products. The price is range: 8 integer bits.
//!
//! - Fraction bits: [`FRAC`] `= 24`, the one constant every derived constant,
//!   algorithm and test below is written in (change it and the tests re-check
//!   the format; 16 ≤ `FRAC` ≤ 26 is asserted at compile time).
//! - Resolution: one unit in the last place is `2⁻²⁴ ≈ 5.96·10⁻⁸` (`f32`
//!   near 1 has `2⁻²³`, near 2 has `2⁻²²`: Q8.24 is finer inside the box).
//! - Representable range: `[−2⁷, MAX]` with `MAX = 2⁷ − 2⁻²⁴ ≈ 127.99999994`
//!   (raw `i32::MIN ..= i32::MAX`). Only sums and differences reach the
//!   bottom value `−2⁷` (raw `i32::MIN`); every other operation saturates
//!   symmetrically, to `±MAX`, so negation and `abs` are exact except on
//!   `−2⁷`, which they take to `MAX`.
//! - The box rule: a scene must lie in the box `|x|, |y|, |z| ≤`
//!   [`COORDINATE_LIMIT`] `= 2` (scenes are normalised into it at load time).
//!   A difference of two points then has components up to `4` and a squared
//!   length up to `3·4² = 12·2² = 48`, below half the range (64), which
//!   leaves room for the sums that squared lengths enter (`b² − c` of the
//!   sphere test, the quadric discriminants). In general the limit is the
//!   largest power of two `R` with `12·R² ≤ ½·2^(31−FRAC)`.
//! - Phong exponents are numbers of the format too: a `shine` above `MAX`
//!   saturates to `MAX ≈ 128` (see [`Scalar::powf`] below).
//!
//! # Arithmetic (all total: nothing here can panic, in debug or release)
//! - `+`, `−`: two's-complement saturating arithmetic (`i32::saturating_add`):
//!   exact whenever the result fits, else `−2⁷` or `MAX`. Why not `±MAX`:
//!   keeping `i32::MIN` out took a compare with a constant after every sum
//!   (three instructions a sum on the Cortex-M0, where the overflow test
//!   itself is one branch on the V flag).
//! - Negation: exact, saturating (`−(−2⁷)` is `MAX`).
//! - `×`: the exact 32×32→64 product, rounded to nearest with ties towards
//!   +∞ (`⌊(a·b + 2²³)/2²⁴⌋`, the rule of [`crate::num::fixed64::Fixed`]),
//!   saturating. Three implementations give the same bits: an `i64` product
//!   and a clamp on 64-bit hosts and WebAssembly (one `imul`, `i64.mul`); on 32-bit targets with a long
//!   multiply (`mul`+`mulh` on RV32IMAC, `smull` on Armv7-M) the product's
//!   two words, half an ulp added with its carry, and a range test that is
//!   one compare for products below 64 in magnitude; and on 32-bit Arm
//!   without 32-bit atomics (Armv6-M, where LLVM would call `__aeabi_lmul`,
//!   a full 64×64 product) the same words from four 16×16→32 `muls` of
//!   signed 16-bit limbs, the rounding folded into a cross term (see
//!   `mul_raw_limbs`). The unit tests run all three on the host against each
//!   other and against an exact `i128` reference.
//! - `÷`: `a·2^FRAC / b` correctly rounded, ties away from zero,
//!   saturating; `x / 0` is `MAX` for `x > 0`, `−MAX` for `x < 0`, and `0`
//!   for `0 / 0`. No 64-bit library division: the divisor is normalised
//!   (software leading-zero count) and the resulting two-word by one-word
//!   division, whose remainder gives the exact rounding, is done per target
//!   with the same exact result (tested against each other): the native
//!   `u64` division on 64-bit hosts and WebAssembly; two 32/32-bit hardware divisions
//!   (Knuth's algorithm D on 16-bit digits) on RV32IMAC and Armv7-M; and on
//!   Armv6-M, which has no divide instruction, schoolbook division in base
//!   2¹⁶ with a 16-bit reciprocal of the divisor's top half (a linear seed
//!   and two Newton–Raphson steps in 32-bit arithmetic, checked for all 2¹⁵
//!   inputs): each quotient digit is estimated from below with 16×32-bit
//!   products and raised by the exact remainder (one or two steps).
//! - `sqrt`: correctly rounded `√(raw·2^FRAC)` (the integer square root of a
//!   55-bit number, rounded to nearest; no ties exist); negative input gives
//!   0. A reciprocal square root from a 24-byte table and two Newton steps
//!   gives the top 16 bits of the root, an exact 32-bit residual fixes them
//!   and yields the next 16, and a final exact residual (computed modulo 2³²)
//!   rounds. Checked for all 2³¹ positive inputs by the ignored test
//!   `exhaustive_sqrt`.
//! - `powf(x, e)` for `x ∈ [0, 1]`, `e ≥ 0`: `2^(e·log₂x)` with `log₂` and
//!   `2^f` by shift-and-add (multiplicative normalisation by factors
//!   `1 + 2⁻ⁱ`, one 14-entry table of `log₂(1 + 2⁻ⁱ)` shared by both) and a
//!   first-order finish: no floating point, no 64-bit division, the same
//!   bits on every target. Measured absolute error ≤ `2⁻¹⁹` over the unit
//!   test's grid (`powf_matches_f64_pow`: x over the whole unit interval, e up
//!   to `MAX`), far below one 8-bit step (`2⁻⁸`).
//! - `from_f32`: round to nearest (ties away from zero), saturate, NaN → 0,
//!   from the bit pattern alone (integer shifts; no float arithmetic, so
//!   firmware links no soft-float routine for it).
//!
//! # Cost on a Cortex-M0 and on RV32IMAC
//! Executed instructions per operation, measured under QEMU
//! (`qemu-system-arm -M microbit -cpu cortex-m0 -icount shift=0`, where the
//! SysTick then counts instructions, and `qemu-system-riscv32 -M virt
//! -icount shift=0`, reading `minstret`) by a scratch firmware, not in the
//! repository, that calls each operation through a function pointer on 2048
//! seeded operand pairs (`a ∈ [−4, 4]`, `b ∈ [0.05, 4]`; `powf`: `x ∈ [0, 1)`,
//! `e ∈ [1, 100]`) and subtracts the same loop around an identity function,
//! so the figures include the cost of a call (about 6 instructions).
//! Release build with fat LTO as `targets/` builds firmware (Rust 1.95):
//!
//! | operation | M0 `Fixed32` | M0 soft-float `f32` | M0 32.32 `Fixed` | RV32 `Fixed32` | RV32 soft-float `f32` |
//! |-----------|------:|------:|------:|------:|------:|
//! | `+`       | 9 (former sum, see below) | 115   | 35    | 10 (former) | 79    |
//! | `×`       | 50 (former product: see below) | 112   | 350   | 26 (former) | 51    |
//! | `÷`       | 193   | 175   | 3552  | 100   | 98    |
//! | `sqrt`    | 119   | 419 (`libm::sqrtf`; now about 145, see below) | 4016 | 97 | 124 (`libm::sqrtf`) |
//! | `powf`    | 328   | 10138 (`libm::powf`), 4367 ([`crate::num::unit_pow::powf_unit`]) | 9960 | 267 | 5781, 2395 |
//! | `from_f32`| 31    | —     | —     | 26    | —     |
//!
//! The `+` figures were measured for the former sum, which also kept
//! `i32::MIN` out of the range (a compare after every sum); inline, the sum
//! is now `adds`, `cmp` and `bvc` on the M0. The `×` figures were measured for the former products (magnitudes and a
//! sign fix-up on Armv6-M, an `i64` clamp on RV32). The current ones,
//! measured the same way on the same operands (a scratch harness calling
//! the product and an identity function through function pointers, 512
//! pairs; the difference per product, so prologue, epilogue and the
//! operands' `from_bits` are included but not the call): Cortex-M0 33.5
//! against 44.0 for the former, RV32IMAC 18.2 against 23.6, Cortex-M4 18.0
//! against 18.0. Inline, as the renderer uses it, the fast path is 29
//! instructions with 4 `muls` on the M0, 14 with `mul`+`mulh` on RV32IMAC
//! and about 10 with one `smull` on the M4 (`llvm-objdump` of the firmware
//! images). Per frame of the firmware demo (15.5 M products) the M0
//! retires 115 M fewer instructions, RV32IMAC 53 M and the M4 62 M
//! (docs/firmware.md).
//!
//! Code sizes on the M0 (`llvm-nm --size-sort -S`, bytes): `+` inlined,
//! 10; `×` inlined, about 60 (with the feature `compact-mul`, one 70-byte
//! function and a call at each use); `÷` 532; `sqrt` 428 + 24 (table); `powf`
//! 1084 + 56 (table). Soft-float: `__addsf3` 504, `__mulsf3` 416 (+ 74 for
//! `__aeabi_lmul`), `__divsf3` 528, `libm::sqrtf` 284 + 256 (table).
//!
//! `f32`'s square root on the firmware is now `crate::num::sqrtf` (libm's
//! algorithm without the soft-float addition that only raises the inexact
//! flag, its products' high words from `num::wide`'s limbs): about 145
//! instructions a call in the demo frame where the row above measured
//! libm's 419 (`docs/fixed-point.md`).
//!
//! A quotient needs 31 correct bits where an `f32` quotient needs 24, which
//! is why `÷` alone does not beat soft-float; the sums and products that
//! dominate a ray tracer are 2–12× cheaper. Every operation links without
//! a reachable panic on thumbv6m, thumbv7em and riscv32imac, also with
//! overflow checks on (checked with a `panic-never`-style link).

use crate::num::scalar::{Divisor, Scalar};
use crate::num::wide::wmul;
#[cfg(test)]
use crate::num::wide::{wmul_limbs, wmul_native};
use core::ops::{Add, Div, Mul, Neg, Sub};

/// Number of fractional bits: the one constant that defines the format
/// (value = raw·2⁻ᶠᴿᴬᶜ).
pub const FRAC: u32 = 24;

// The algorithms below budget their shifts for this range: `MIN_WEIGHT`
// (2⁻⁹) and `TWO` must be representable, the square root's final residual
// must fit 31 bits, and `powf`'s logarithm must fit its Q5.26 format.
const _: () = assert!(FRAC >= 16 && FRAC <= 26);

/// Raw value of one.
const RAW_ONE: i32 = 1 << FRAC;
/// Raw value of the largest representable number, `2^(31−FRAC) − 2^−FRAC`.
const RAW_MAX: i32 = i32::MAX;
/// Raw value of `−MAX`, the bottom of every saturation but the sums'
/// (which reach `i32::MIN`, −2⁷).
const RAW_MIN: i32 = -i32::MAX;
/// Half a unit in the last place of a product's 2·FRAC fractional bits.
const HALF_ULP: i64 = 1 << (FRAC - 1);

/// `log₂` of the coordinate limit: the largest `c` with
/// `12·(2^c)² ≤ ½·2^(31−FRAC)` (squared distances within half the range).
const fn coordinate_limit_log2() -> i32 {
    let budget: i64 = 1 << (30 - FRAC);
    // Scaled by 4⁸ so that c may start at −8: 12·4^(c+1) ≤ budget ⇔
    // 12·4^(c+9) ≤ budget·2¹⁶.
    let mut c: i32 = -8;
    while c < 8 && 12 * (1i64 << (2 * (c + 9))) <= budget << 16 {
        c += 1;
    }
    c
}

/// Largest coordinate magnitude a [`Fixed32`] scene may use: scenes are
/// normalised into the box `[−2, 2]³` at load time (see the module
/// documentation for the derivation).
pub const COORDINATE_LIMIT: f32 = f32::from_bits(((127 + coordinate_limit_log2()) as u32) << 23);

/// Largest coordinate magnitude of a light (see [`Scalar::LIGHT_LIMIT`]).
pub const LIGHT_LIMIT: f32 = 100.0;

/// Budget for the quadric and cone discriminants ([`crate::geom::fixed_range`]
/// bounds them, and each of the two terms they are the sum of): the largest
/// sums those kernels form, kept below the top of the range (128) with a
/// margin for rounding.
pub const INTERMEDIATE_LIMIT: f32 = 120.0;

/// A signed Q8.24 fixed-point number with 32-bit storage: the fast
/// [`Scalar`] for FPU-less 32-bit targets.
///
/// Ordering, equality and hashing are those of the raw integer (the value
/// order). See the module documentation for the exact semantics of every
/// operation.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[repr(transparent)]
pub struct Fixed32(i32);

impl Fixed32 {
    /// The number whose raw two's-complement bits are `raw` (value
    /// `raw·2^−FRAC`).
    #[inline]
    pub const fn from_bits(raw: i32) -> Self {
        Fixed32(raw)
    }
    /// The raw bits (value `raw·2^−FRAC`).
    #[inline]
    pub const fn to_bits(self) -> i32 {
        self.0
    }
    /// The smaller of two values. (Inherent, so that `a.min(b)` on a
    /// concrete `Fixed32` is not ambiguous between `Ord` and `Scalar`; all
    /// three agree.)
    #[inline]
    pub const fn min(self, o: Self) -> Self {
        if self.0 < o.0 {
            self
        } else {
            o
        }
    }
    /// The larger of two values (inherent, like [`Fixed32::min`]).
    #[inline]
    pub const fn max(self, o: Self) -> Self {
        if self.0 > o.0 {
            self
        } else {
            o
        }
    }
    /// Converts from `f64`, rounded to nearest (ties away from zero),
    /// saturating, NaN to 0. A test and report helper: it uses `f64`
    /// arithmetic, which the render path never does.
    pub fn from_f64(v: f64) -> Self {
        if v.is_nan() {
            return Fixed32(0);
        }
        // Scaling by a power of two is exact; `as` saturates.
        let scaled = libm::round(v * RAW_ONE as f64);
        Fixed32::from_bits((scaled as i64).clamp(RAW_MIN as i64, RAW_MAX as i64) as i32)
    }
    /// Converts to `f64` (exact: 31 significant bits). A test and report
    /// helper, like [`Fixed32::from_f64`].
    pub fn to_f64(self) -> f64 {
        self.0 as f64 / RAW_ONE as f64
    }
}

// ---------------------------------------------------------------------------
// Decimal output without floating point.

impl core::fmt::Display for Fixed32 {
    /// The shortest decimal that reads back (rounded to nearest) as the same
    /// number, e.g. `0.1` for raw 1677722, `-2.5`, `127.99999994`; integers
    /// print without a point (`-128` for the bottom value, which reads back
    /// as `−MAX`: conversions saturate symmetrically). Computed with integer
    /// arithmetic only.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let mag = self.0.unsigned_abs();
        let (int, frac) = (mag >> FRAC, (mag & (RAW_ONE as u32 - 1)) as u64);
        // Up to 24 characters: sign, 3 integer digits, point, 9 fraction digits.
        let mut buf = [0u8; 24];
        let mut n = 0;
        if self.0 < 0 {
            buf[0] = b'-';
            n = 1;
        }
        // Integer part (at most 2^(31−FRAC) ≤ 32768: five digits).
        let mut digits = [0u8; 5];
        let (mut k, mut v) = (0, int);
        loop {
            if let Some(d) = digits.get_mut(k) {
                *d = b'0' + (v % 10) as u8;
            }
            k += 1;
            v /= 10;
            if v == 0 || k >= digits.len() {
                break;
            }
        }
        while k > 0 {
            k -= 1;
            if let (Some(dst), Some(&src)) = (buf.get_mut(n), digits.get(k)) {
                *dst = src;
            }
            n += 1;
        }
        if frac != 0 {
            // The fewest digits p with round(D·2^FRAC/10^p) = frac for
            // D = round(frac·10^p/2^FRAC): 10^p ≥ 2^(FRAC+1) always works,
            // so p ≤ 9 for FRAC ≤ 26 (and frac·10^p < 2^56 fits u64).
            let one = 1u64 << FRAC;
            let mut p = 1;
            let mut pow = 10u64;
            let mut dec = (frac * pow + one / 2) >> FRAC;
            while p < 9 && ((dec << FRAC) + pow / 2) / pow != frac {
                p += 1;
                pow *= 10;
                dec = (frac * pow + one / 2) >> FRAC;
            }
            if let Some(dst) = buf.get_mut(n) {
                *dst = b'.';
            }
            n += 1;
            // p digits of dec, zero-padded on the left, then trailing zeros dropped.
            let mut i = p;
            let start = n;
            while i > 0 {
                i -= 1;
                if let Some(dst) = buf.get_mut(start + i) {
                    *dst = b'0' + (dec % 10) as u8;
                }
                dec /= 10;
            }
            n = start + p;
            while n > start + 1 && buf.get(n - 1) == Some(&b'0') {
                n -= 1;
            }
        }
        let s = buf.get(..n).and_then(|b| core::str::from_utf8(b).ok()).unwrap_or("?");
        f.pad(s)
    }
}

impl core::fmt::Debug for Fixed32 {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(self, f)
    }
}

// ---------------------------------------------------------------------------
// Integer building blocks: leading zeros and the 32×32→64 product.

/// Multiplier of [`clz_soft`]: `(2ᵏ − 1)·CLZ_MUL >> 27` differs for every
/// `k` in `1..=32` (a de Bruijn-like constant; `k = 0` shares `k = 1`'s).
const CLZ_MUL: u32 = 0x07C4_ACDD;

/// [`clz_soft`]'s table: `32 − k` at the index of `2ᵏ − 1`.
const CLZ_TABLE: [u8; 32] = {
    let mut t = [0u8; 32];
    let mut k = 1;
    while k <= 32 {
        let v = if k == 32 { u32::MAX } else { (1u32 << k) - 1 };
        t[(v.wrapping_mul(CLZ_MUL) >> 27) as usize] = 32 - k as u8;
        k += 1;
    }
    t
};

/// Leading zeros of `x` (31 for `x = 0`, which no caller passes) without
/// a CLZ instruction, which Armv6-M lacks (`u32::leading_zeros` would call `__clzsi2`, about 35
/// instructions): the bits below the top one are set (`x` becomes `2ᵏ − 1`,
/// `k = 32 − clz`), and a multiplication turns that into a table index.
/// About 15 instructions and no branch.
#[inline(always)]
#[cfg_attr(wide_mul, allow(dead_code))]
fn clz_soft(x: u32) -> u32 {
    let mut v = x;
    v |= v >> 1;
    v |= v >> 2;
    v |= v >> 4;
    v |= v >> 8;
    v |= v >> 16;
    match CLZ_TABLE.get((v.wrapping_mul(CLZ_MUL) >> 27) as usize) {
        Some(&n) => n as u32,
        None => 0, // unreachable: the index is below 32
    }
}

/// Leading zeros of a nonzero `x`: the instruction on 64-bit hosts and WebAssembly, the
/// binary search elsewhere (same result, tested).
#[inline(always)]
fn clz(x: u32) -> u32 {
    #[cfg(wide_mul)]
    {
        x.leading_zeros()
    }
    #[cfg(not(wide_mul))]
    {
        clz_soft(x)
    }
}

/// `w·d` for `w < 2¹⁶` (a 16×32 product is all the reciprocal and root
/// refinements need): [`mul16x32_halves`] on Armv6-M, where [`wmul`] takes
/// four partial products; elsewhere [`wmul`], the same exact product (on
/// RV32IMAC `mul` and `mulhu`, about seven instructions fewer than two
/// partial products and their carry).
#[inline(always)]
fn mul16x32(w: u32, d: u32) -> u64 {
    #[cfg(armv6m)]
    {
        mul16x32_halves(w, d)
    }
    #[cfg(not(armv6m))]
    {
        wmul(w, d)
    }
}

/// `w·d` for `w < 2¹⁶` from two 16×16→32 products.
#[inline(always)]
#[cfg_attr(not(any(armv6m, test)), allow(dead_code))]
fn mul16x32_halves(w: u32, d: u32) -> u64 {
    // (Wrapping only to spare overflow checks: w < 2¹⁶ keeps both exact.)
    ((w.wrapping_mul(d >> 16) as u64) << 16) + w.wrapping_mul(d & 0xFFFF) as u64
}

// The product `⌊(a·b + 2^(FRAC−1)) / 2^FRAC⌋`, clamped to `[−MAX, MAX]`
// (round half up of the exact product), has three implementations with the
// same bits for every pair, chosen per target and tested against each
// other and against an `i128` reference on the host:
// - 64-bit hosts and WebAssembly (native `i64` arithmetic): one `i64` product and a clamp ([`mul_raw_native`]);
// - 32-bit targets with a long multiply (RV32IMAC's `mul`+`mulh`, Armv7-M's
//   `smull`): the 64-bit product as two words ([`mul_raw_words`]);
// - Armv6-M, which has none (LLVM would call `__aeabi_lmul`, a full 64×64
//   product): four 16×16→32 `muls` of signed 16-bit limbs
//   ([`mul_raw_limbs`]).
// The two 32-bit forms have a range test that is one compare for every
// product below about 2^(30−FRAC) in magnitude (64 for Q8.24: all a scene
// in the coordinate box normally forms), and the exact clamp out of line
// for the rest: [`round_words`] on the exact product's two words, and
// the limbs' test of their high partial product.

/// The portable product (64-bit hosts and WebAssembly): one exact `i64`
/// product, then [`round_clamp`].
#[inline(always)]
#[cfg_attr(not(any(wide_mul, armv6m)), allow(dead_code))]
fn mul_raw_native(a: i32, b: i32) -> i32 {
    round_clamp(a as i64 * b as i64)
}

/// An exact product `p` (|p| ≤ 2⁶², so adding half an ulp cannot overflow)
/// rounded half up to the format and clamped: an arithmetic shift (which
/// floors, so ties go towards +∞), then the clamp.
#[inline(always)]
fn round_clamp(p: i64) -> i32 {
    let r = (p + HALF_ULP) >> FRAC;
    if r > RAW_MAX as i64 {
        RAW_MAX
    } else if r < RAW_MIN as i64 {
        RAW_MIN
    } else {
        r as i32
    }
}

/// The rounded product from the words of the exact product `p = a·b`
/// (`hi` signed, `lo` unsigned): `⌊(p + 2^(FRAC−1)) / 2^FRAC⌋`, clamped.
///
/// `h = ⌊p / 2^(FRAC−1)⌋` is `hi·2^(33−FRAC) | lo >> (FRAC − 1)` when it fits
/// 32 bits, that is when `hi` lies in `[−2^(FRAC−2), 2^(FRAC−2))`; the test
/// is that `h` shifted back right gives `hi` again. Then the result is
/// `⌊(h + 1)/2⌋ = h − ⌊h/2⌋` (`⌈h/2⌉`: no sum that could overflow, and no
/// carry of half an ulp through the low word), of magnitude at most 2³⁰,
/// inside the clamp. Larger products take [`clamp_words`].
///
/// Why this form: on RV32IMAC it is `mul`, `mulh` and seven instructions;
/// adding half an ulp to the low word first, with its carry into the high
/// one, took eleven.
#[inline(always)]
#[cfg_attr(wide_mul, allow(dead_code))]
fn round_words(hi: i32, lo: u32) -> i32 {
    let h = half_ulps(hi, lo);
    if h >> (33 - FRAC) != hi {
        return clamp_words(hi, lo);
    }
    halve_up(h)
}

/// The low 32 bits of `⌊p / 2^(FRAC−1)⌋` from `p`'s words (all of it when
/// it fits, see [`round_words`]).
#[inline(always)]
#[cfg_attr(any(wide_mul, armv6m), allow(dead_code))]
fn half_ulps(hi: i32, lo: u32) -> i32 {
    (hi << (33 - FRAC)) | (lo >> (FRAC - 1)) as i32
}

/// `⌈h/2⌉ = ⌊(h + 1)/2⌋`, without a sum that could overflow.
#[inline(always)]
#[cfg_attr(any(wide_mul, armv6m), allow(dead_code))]
fn halve_up(h: i32) -> i32 {
    h.wrapping_sub(h >> 1)
}

/// [`round_words`] for products of magnitude `2^(30−FRAC)` and up (rare:
/// out of line): the exact `i64` product rebuilt from its words, then
/// [`round_clamp`].
#[cold]
#[inline(never)]
#[cfg_attr(wide_mul, allow(dead_code))]
fn clamp_words(hi: i32, lo: u32) -> i32 {
    round_clamp(((hi as i64) << 32) | lo as i64)
}

/// The product on 32-bit targets with a 32×32→64 multiply: the `i64`
/// product's two words (`mulh`/`mul` or `smull`), then [`round_words`].
#[inline(always)]
#[cfg_attr(any(wide_mul, armv6m), allow(dead_code))]
fn mul_raw_words(a: i32, b: i32) -> i32 {
    let p = a as i64 * b as i64;
    round_words((p >> 32) as i32, p as u32)
}

/// The product on Armv6-M, from signed 16-bit limbs: `a = aₕ·2¹⁶ + aₗ` with
/// `aₕ = a >> 16 ∈ [−2¹⁵, 2¹⁵)` (arithmetic shift) and `aₗ = a & 0xFFFF ∈
/// [0, 2¹⁶)`, the same for `b`, so
///
/// `a·b = H·2³² + (C₁ + C₂)·2¹⁶ + L`, `H = aₕbₕ`, `C₁ = aₕbₗ`, `C₂ = aₗbₕ`,
/// `L = aₗbₗ`.
///
/// Each partial product fits its 32-bit `muls` exactly (`|H| ≤ 2³⁰`,
/// `|C| < 2³¹`, `L < 2³²` unsigned). The bits of `L` below 2¹⁶ cannot
/// reach bit `FRAC ≥ 16` of the sum except through a carry, so with `h`
/// half an ulp, `L + (h mod 2¹⁶) = q·2¹⁶ + ρ` (`ρ < 2¹⁶`; no overflow:
/// `L ≤ (2¹⁶ − 1)²`) and, with `C₁' = C₁ + q + ⌊h/2¹⁶⌋` and `F = FRAC − 16`,
///
/// `⌊(a·b + h)/2^FRAC⌋ = ⌊(H·2¹⁶ + C₁' + C₂)/2^F⌋ = H·2^(16−F) + ((C₁' + C₂) >> F)`
///
/// (dropping `ρ` changes no bit from `FRAC` up). `C₁'` still fits an `i32`
/// (below `2³¹ − 2¹⁵ + 2¹⁰`), and so does `C₁' + C₂` on the fast path below
/// unless one term lies within `2²⁴` of `±2³¹`, which takes one operand
/// within about 1 of ±128 and the other below 1 in magnitude (a high limb
/// below 2⁸, since `|H| < 2²²`): that sum is formed with `adds`, and its
/// signed overflow (the V flag, one branch) hands the pair to the exact
/// path. When `H` lies in `[−2^(FRAC−2), 2^(FRAC−2))` the result lies
/// within `2^30 + 2^24` of zero: in range, and the sum above is exact in
/// wrapping 32-bit arithmetic; the test is that `H` shifted right by
/// `FRAC − 2` is its own sign (all a scene in the coordinate box normally
/// forms: products below 64 in magnitude). Larger products, and the rare
/// overflowing cross sums, take the exact `i64` form out of line
/// ([`mul_raw_wide`]). Bit for bit the rounding of [`mul_raw_native`]; 4
/// `muls` and about 22 instructions on the fast path (no magnitudes, no
/// sign fix-up, no 64-bit library call, no carry between words).
#[inline(always)]
#[cfg_attr(not(armv6m), allow(dead_code))]
fn mul_raw_limbs(a: i32, b: i32) -> i32 {
    const _: () = assert!(FRAC >= 16 && FRAC < 32);
    const F: u32 = FRAC - 16;
    let (ah, bh) = (a >> 16, b >> 16);
    // (Wrapping only to spare overflow checks: the bounds above keep every
    // partial product, C₁' and the sum exact.)
    let h = ah.wrapping_mul(bh);
    if h >> (FRAC - 2) != h >> 31 {
        return mul_raw_wide(a, b);
    }
    let (c1, c2) = cross_limbs(a, b);
    // (`adds` and a branch on V: past 32 bits only near ±128, see above.)
    let (s, carried) = c1.overflowing_add(c2);
    if carried {
        return mul_raw_wide(a, b);
    }
    (h << (32 - FRAC)).wrapping_add(s >> F)
}

/// [`mul_raw_limbs`] for `b = a`, bit for bit, from three `muls`: the two
/// cross terms are one, `C = aₕaₗ`, so `a² = H·2³² + 2C·2¹⁶ + L` with
/// `H = aₕ² ≥ 0` and `L = aₗ²`. Half an ulp `h` has no bits below 2¹⁶
/// (FRAC ≥ 17), so with `t = ⌊L/2¹⁶⌋ + h/2¹⁶` the rounded product is
/// `H·2^(16−F) + ⌊(2C + t)/2^F⌋` (`F = FRAC − 16`, as for the product), and
/// `⌊(2C + t)/2^F⌋ = ⌊(C + ⌊t/2⌋)/2^(F−1)⌋`: `2C + t` is `2·(C + ⌊t/2⌋)`
/// plus 0 or 1, and adding 1 to an even number cannot reach the next
/// multiple of the even `2^F`. The fast path needs `H < 2^(FRAC−2)`, so
/// `|aₕ| < 2^(FRAC/2−1)` and `|C| < 2^(FRAC/2+15)`: no sum can overflow,
/// and there is no cross-sum test. About 14 instructions.
#[inline(always)]
#[cfg_attr(not(armv6m), allow(dead_code))]
fn square_raw_limbs(a: i32) -> i32 {
    const _: () = assert!(FRAC >= 17 && FRAC < 32 && HALF_ULP & 0xFFFF == 0);
    let ah = a >> 16;
    let h = ah.wrapping_mul(ah);
    if h >> (FRAC - 2) != 0 {
        return mul_raw_wide(a, a);
    }
    square_limbs_fast(a, h)
}

/// [`square_raw_limbs`]' fast path, given `h = aₕ²` below `2^(FRAC−2)`.
#[inline(always)]
#[cfg_attr(not(armv6m), allow(dead_code))]
fn square_limbs_fast(a: i32, h: i32) -> i32 {
    const F: u32 = FRAC - 16;
    let (ah, al) = (a >> 16, a & 0xFFFF);
    let l = (al as u32).wrapping_mul(al as u32);
    let t = (l >> 16).wrapping_add((HALF_ULP >> 16) as u32);
    let c = ah.wrapping_mul(al).wrapping_add((t >> 1) as i32);
    (h << (32 - FRAC)).wrapping_add(c >> (F - 1))
}

/// Operands at most 4 in magnitude (raw `|a|, |b| ≤ 2²⁶`), whose product
/// every form of the product takes by its fast path: `|aₕbₕ| ≤ 2²⁰`, the
/// limbs' cross sum below `2²⁸`, the result at most 16 (no clamp).
#[cfg_attr(not(test), allow(dead_code))]
const SMALL: i32 = 1 << 26;

/// The rounded product `a·b` for operands at most 4 in magnitude
/// ([`SMALL`]): bit for bit the product, without its range tests, which
/// cannot fire there. Larger operands give some value (wrapping
/// arithmetic: no panic), which callers leave in lanes they mask out.
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
#[inline(always)]
fn mul_raw_small(a: i32, b: i32) -> i32 {
    #[cfg(armv6m)]
    {
        mul_limbs_small(a, b)
    }
    #[cfg(wide_mul)]
    {
        ((a as i64 * b as i64 + HALF_ULP) >> FRAC) as i32
    }
    #[cfg(not(any(armv6m, wide_mul)))]
    {
        mul_words_small(a, b)
    }
}

/// [`mul_raw_small`] on 32-bit targets with a long multiply, from the
/// product of the operands scaled by 2⁴: with `|a|, |b| ≤ 2²⁶` ([`SMALL`])
/// the scaled operands fit 32 bits and `(2⁴a)(2⁴b) = 2⁸·ab` is exact, so
/// its high word is `⌊ab/2²⁴⌋` (`mulh` floors) and the top bit of its low
/// word is bit 23 of `ab`, the half ulp that rounds `⌊(ab + 2²³)/2²⁴⌋` up.
/// On RV32IMAC six instructions, one fewer than [`round_words`] without
/// its range test, and five where an operand's scaling is shared (a
/// square, or the normalisation's four products by one reciprocal root).
#[inline(always)]
#[cfg_attr(any(wide_mul, armv6m), allow(dead_code))]
fn mul_words_small(a: i32, b: i32) -> i32 {
    // (Wrapping shifts: larger operands give some value, never a panic.)
    let p = a.wrapping_shl(4) as i64 * b.wrapping_shl(4) as i64;
    ((p >> 32) as i32).wrapping_add(((p as u32) >> 31) as i32)
}

/// The product's cross terms from 16-bit limbs, `C₁' = C₁ + q + ⌊h/2¹⁶⌋`
/// (the low partial product and half an ulp `h` carried in) and `C₂`, as
/// [`mul_raw_limbs`] defines them; shared with [`mul_limbs_small`].
#[inline(always)]
#[cfg_attr(not(armv6m), allow(dead_code))]
fn cross_limbs(a: i32, b: i32) -> (i32, i32) {
    let (ah, bh, al, bl) = (a >> 16, b >> 16, a & 0xFFFF, b & 0xFFFF);
    let l = (al as u32).wrapping_mul(bl as u32).wrapping_add((HALF_ULP & 0xFFFF) as u32);
    let c1 = ah.wrapping_mul(bl).wrapping_add((l >> 16) as i32).wrapping_add((HALF_ULP >> 16) as i32);
    (c1, al.wrapping_mul(bh))
}

/// [`mul_raw_limbs`] without its two tests, for [`mul_raw_small`] on Armv6-M.
#[inline(always)]
#[cfg_attr(not(armv6m), allow(dead_code))]
fn mul_limbs_small(a: i32, b: i32) -> i32 {
    const F: u32 = FRAC - 16;
    let h = (a >> 16).wrapping_mul(b >> 16);
    let (c1, c2) = cross_limbs(a, b);
    (h << (32 - FRAC)).wrapping_add(c1.wrapping_add(c2) >> F)
}

/// `a²` rounded, for `|a|` at most 4 ([`SMALL`]): bit for bit the product,
/// without its range tests.
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
#[inline(always)]
fn square_raw_small(a: i32) -> i32 {
    #[cfg(armv6m)]
    {
        let ah = a >> 16;
        square_limbs_fast(a, ah.wrapping_mul(ah))
    }
    #[cfg(wide_mul)]
    {
        ((a as i64 * a as i64 + HALF_ULP) >> FRAC) as i32
    }
    #[cfg(not(any(armv6m, wide_mul)))]
    {
        mul_words_small(a, a)
    }
}

/// `[f(x), f(y), f(z)]`, written out: `array::map` at opt-level `s` stays
/// a call to a generic routine (about 70 instructions for three words on
/// the Cortex-M0, twice per normalisation).
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
#[inline(always)]
fn map3<T, U>([x, y, z]: [T; 3], mut f: impl FnMut(T) -> U) -> [U; 3] {
    [f(x), f(y), f(z)]
}

/// The unit vector and length of the raw vector `c`, bit for bit what the
/// general lane code gives (`Vec3xW::normalize_with_length`: the prescale
/// by `2^k`, the sum of squares, one reciprocal root, four products, the
/// length scaled back), for vectors whose largest component magnitude has
/// its top bit at 17 … 30 (from 2⁻⁷ up: `k = 23 − top ∈ [−7, 6]`, inside
/// the exponent's clamp); `None` for the rest (zero, tiny vectors,
/// `i32::MIN`), which take the general code.
///
/// There the range tests of the general code cannot fire, so they are
/// left out: the prescaled components lie within `2²⁴` (1; `2^k` brings the
/// largest to `[2²³, 2²⁴)`, and rounding a right shift up reaches `2²⁴` at
/// most), so each square is at most 1, their sum `S ∈ [¼, 3]` does not
/// saturate and is positive, `1/√S ∈ [0.57, 2]`, and every product has
/// operands below 4 ([`mul_raw_small`]). Only the length's scaling back by
/// `2^−k` can saturate, and keeps its test.
///
/// Out of line with `compact-mul` (the image held to 48 KiB): inline at
/// each normalisation it took 1.9 KB more there.
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
#[cfg_attr(not(all(armv6m, not(armv6m_inline_mul))), inline(always))]
#[cfg_attr(all(armv6m, not(armv6m_inline_mul)), inline(never))]
fn unit_and_length_raw(c: [i32; 3]) -> Option<([i32; 3], i32)> {
    let [x, y, z] = map3(c, i32::unsigned_abs);
    let m = x.max(y).max(z);
    let top = 31 - clz(m) as i32;
    if !(17..=30).contains(&top) {
        return None;
    }
    let k = FRAC as i32 - 1 - top;
    // `mul_pow2(k)`: a shift left that stays below 2²⁴, or a right shift
    // rounded half up.
    let v = if k >= 0 {
        map3(c, |c| c << k)
    } else {
        let s = k.unsigned_abs();
        map3(c, |c| (c >> s).wrapping_add((c >> (s - 1)) & 1))
    };
    let [sx, sy, sz] = map3(v, square_raw_small);
    let squared = sx.wrapping_add(sy).wrapping_add(sz);
    // `squared ∈ [2²², 3·2²⁴]`: `inverse_sqrt` without its range cases.
    let inv = rsqrt_raw_unit(squared as u32) as i32;
    let len = mul_raw_small(squared, inv);
    Some((map3(v, |v| mul_raw_small(v, inv)), Fixed32(len).mul_pow2(-k).0))
}

/// [`Scalar::unit_dot_le`] on raw values: `a·b` from the components
/// truncated to `2⁻¹⁴` (`aᵢ >> 10`, within `[0, 2⁻¹⁴)` of `aᵢ`), one `muls`
/// each on Armv6-M where the products themselves take about 18
/// instructions each.
///
/// With `|aᵢ|, |bᵢ| <= 1.0625` (raw `17·2²⁰`) the truncations are at most
/// `17 408` in magnitude, so each product is below `2²⁹` and their sum `c`
/// (units of `2⁻²⁸`) cannot overflow. Each term differs from `aᵢbᵢ` by at
/// most `(|aᵢ| + |bᵢ|)·2⁻¹⁴ + 2⁻²⁸ <= 2.125·2⁻¹⁴ + 2⁻²⁸`, and the product the
/// caller would form rounds each term within `2⁻²⁵`: with
/// `E = 3·(2.125·2¹⁴ + 1 + 8) < 2¹⁷` (units of `2⁻²⁸`), that product `p`
/// satisfies `c − E < 16·p < c + E` (`p` in raw units of `2⁻²⁴`). So
/// `c + E <= 16·limit` gives `p <= limit` and `c − E >= 16·limit` gives
/// `p > limit`; between the two it is left to the product.
#[inline(always)]
fn unit_dot_le_raw(a: [i32; 3], b: [i32; 3], limit: i32) -> Option<bool> {
    const _: () = assert!(FRAC == 24);
    const E: i32 = 1 << 17;
    // `|limit| <= 2`: `16·limit` fits.
    if limit.unsigned_abs() > 2 << FRAC {
        return None;
    }
    let t = |v: i32| v >> 10;
    // (Wrapping only keeps components beyond the bound from a panic.)
    let c = t(a[0])
        .wrapping_mul(t(b[0]))
        .wrapping_add(t(a[1]).wrapping_mul(t(b[1])))
        .wrapping_add(t(a[2]).wrapping_mul(t(b[2])));
    let l = limit << 4;
    if c <= l - E {
        Some(true)
    } else if c >= l + E {
        Some(false)
    } else {
        None
    }
}

/// [`mul_raw_limbs`] for products of magnitude about `2^(30−FRAC)` and up
/// and for cross sums past 32 bits (rare: out of line): the exact `i64`
/// product and clamp.
#[cold]
#[inline(never)]
#[cfg_attr(not(armv6m), allow(dead_code))]
fn mul_raw_wide(a: i32, b: i32) -> i32 {
    mul_raw_native(a, b)
}

// ---------------------------------------------------------------------------
// Division: a 16-bit reciprocal and two 16-bit quotient digits.

/// Seeds of [`reciprocal16`]: for the 256 intervals `dh − 1 ∈
/// [2¹⁵ + 2⁷·i, 2¹⁵ + 2⁷·(i + 1))`, `⌊2³²/top⌋ − 2¹⁶` with `top = 2¹⁵ +
/// 2⁷·(i + 1)` the interval's largest `dh`: a lower bound of `2³²/dh` on the
/// whole interval, within 2⁻⁸ of it (at most 65 025: a `u16`).
const RECIPROCAL_SEED: [u16; 256] = {
    let mut t = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        t[i] = ((1u64 << 32) / ((1u64 << 15) + ((i as u64 + 1) << 7)) - (1 << 16)) as u16;
        i += 1;
    }
    t
};

/// `W ≈ 2³²/dh` for `dh ∈ (2¹⁵, 2¹⁶]` (a divisor's top half, rounded up),
/// returned as `W − 2¹⁶ ∈ [0, 2¹⁶)`, never above the true value and at most
/// a few units (2⁻¹⁵ relative) below it (`reciprocal16_is_a_tight_lower_bound`
/// checks all 2¹⁵ inputs).
///
/// The seed is [`RECIPROCAL_SEED`]'s bound for `dh`'s interval (relative
/// error below 2⁻⁸; the byte of the index is all of `(dh − 1) >> 7` but its
/// leading one, so no bounds test), then one Newton step `W ← W + W·(1 −
/// Dh·W)` (`Dh = dh/2¹⁶`): the residual `e = 2³² − dh·W` is small (`|e| <
/// 2³¹`, so the wrapped product read as `i32` is exact) and `W·e/2³²` is
/// formed as `(W/2)·(e/2¹⁵)/2¹⁶` within 32 bits. The relative error goes
/// 2⁻⁸ → 2⁻¹⁶ plus the truncations; an exact Newton step lands below `1/Dh`
/// and every truncation rounds down, so `W` stays a lower bound.
///
/// Why a table: the linear seed it replaced (4 bits) needed two Newton
/// steps; the 512-byte table saves one, about 10 instructions of every
/// division on the Cortex-M0.
#[inline(always)]
fn reciprocal16(dh: u32) -> u32 {
    let i = ((dh.wrapping_sub(1) >> 7) as u8) as usize;
    let mut w = match RECIPROCAL_SEED.get(i) {
        Some(&s) => s as u32 + (1 << 16),
        None => 1 << 16, // unreachable: a byte indexes 256 entries
    };
    let e = dh.wrapping_mul(w).wrapping_neg() as i32;
    w = w.wrapping_add((((w >> 1) as i32).wrapping_mul(e >> 15) >> 16) as u32);
    // W may fall just below 2¹⁶ for dh = 2¹⁶ (where 2³²/dh = 2¹⁶): clamp.
    w.saturating_sub(1 << 16) & 0xFFFF
}

/// `⌊m·W/2³²⌋` for the reciprocal `W = 2¹⁶ + wl`: `m·2¹⁶ + m·wl` from two
/// 16×16 products.
#[inline(always)]
fn mul_recip(m: u32, wl: u32) -> u32 {
    ((((m as u64) << 16).wrapping_add(mul16x32(wl, m))) >> 32) as u32
}

// The two-word division `(u1·2³² + u0)/d` (normalised `d ≥ 2³¹`, `u1 < d`,
// quotient below 2³²) has three implementations with the same exact result,
// chosen per target and tested against each other on the host:
// - 64-bit targets: the native `u64` division (one instruction);
// - 32-bit targets with a 32-bit hardware divide (RV32 with the M extension,
//   Armv7-M and later): two 32/32-bit divisions (Knuth's algorithm D with
//   16-bit digits, as in Hacker's Delight's `divlu`);
// - 32-bit targets without one (Armv6-M, RV32 without M): two 16-bit digits
//   from a 16-bit reciprocal (no division at all).

/// The exact `(⌊n/d⌋, n mod d)` of `n = u1·2³² + u0`, by the native `u64`
/// division.
#[inline(always)]
#[cfg_attr(not(wide_mul), allow(dead_code))]
fn div_words_native(u1: u32, u0: u32, d: u32) -> (u32, u32) {
    let n = ((u1 as u64) << 32) | u0 as u64;
    // d ≥ 2³¹ (normalised); `NonZeroU64` lets the compiler drop the
    // divide-by-zero panic (the `None` arm is unreachable).
    let Some(d) = core::num::NonZeroU64::new(d as u64) else {
        return (0, 0);
    };
    ((n / d) as u32, (n % d) as u32)
}

/// The same with two 32/32-bit hardware divisions: each 16-bit quotient
/// digit is first estimated from the divisor's top half (at most two too
/// large, as `d` is normalised) and lowered while the next digit shows it is
/// too large (the test `q·d_lo > r̂·2¹⁶ + next digit` of algorithm D).
#[inline(always)]
#[allow(dead_code)]
fn div_words_hw32(u1: u32, u0: u32, d: u32) -> (u32, u32) {
    const B: u32 = 1 << 16;
    // d ≥ 2³¹, so its top half is nonzero; `NonZeroU32` lets the compiler
    // drop the divide-by-zero panic (the `None` arm is unreachable).
    let Some(dh_nz) = core::num::NonZeroU32::new(d >> 16) else {
        return (0, 0);
    };
    let (dh, dl) = (dh_nz.get(), d & 0xFFFF);
    let (n1, n0) = (u0 >> 16, u0 & 0xFFFF);
    // High digit from u1 (< d, so the digit is below 2¹⁶ once corrected);
    // r̂ < 2¹⁶ inside the loop, so r̂·2¹⁶ + n1 cannot overflow. (All steps
    // are exact; the wrapping forms only spare unprovable overflow checks.)
    let mut q1 = u1 / dh_nz;
    let mut rhat = u1.wrapping_sub(q1.wrapping_mul(dh));
    while q1 >= B || q1.wrapping_mul(dl) > (rhat << 16).wrapping_add(n1) {
        q1 = q1.wrapping_sub(1);
        rhat = rhat.wrapping_add(dh);
        if rhat >= B {
            break;
        }
    }
    // The partial remainder is below d: exact modulo 2³².
    let u21 = (u1 << 16).wrapping_add(n1).wrapping_sub(q1.wrapping_mul(d));
    let mut q0 = u21 / dh_nz;
    let mut rhat = u21.wrapping_sub(q0.wrapping_mul(dh));
    while q0 >= B || q0.wrapping_mul(dl) > (rhat << 16).wrapping_add(n0) {
        q0 = q0.wrapping_sub(1);
        rhat = rhat.wrapping_add(dh);
        if rhat >= B {
            break;
        }
    }
    let r = (u21 << 16).wrapping_add(n0).wrapping_sub(q0.wrapping_mul(d));
    ((q1 << 16).wrapping_add(q0), r)
}

/// The same without any division: schoolbook in base 2¹⁶ with the 16-bit
/// reciprocal of `d`'s top half. Each digit is estimated from below (never
/// too large, so the remainder never goes negative) from a 16×32 product and
/// raised by the exact remainder, one or two steps at most.
#[inline(always)]
#[allow(dead_code)]
fn div_words_reciprocal(u1: u32, u0: u32, d: u32) -> (u32, u32) {
    div_words_by_reciprocal(u1, u0, d, divisor_reciprocal(d))
}

/// 1/d ≈ W/2⁴⁸ from below, with dh = ⌈d/2¹⁶⌉ (d ≥ 2¹⁶·(dh − 1) + 1), as
/// [`reciprocal16`] returns it: what [`div_words_by_reciprocal`] needs of
/// the divisor, which divisions by the same `d` can share.
#[inline(always)]
#[allow(dead_code)]
fn divisor_reciprocal(d: u32) -> u32 {
    reciprocal16((d >> 16) + 1)
}

/// [`div_words_reciprocal`] given `wl = divisor_reciprocal(d)`.
#[inline(always)]
#[allow(dead_code)]
fn div_words_by_reciprocal(u1: u32, u0: u32, d: u32, wl: u32) -> (u32, u32) {
    let n = ((u1 as u64) << 32) | u0 as u64;
    let d16 = (d as u64) << 16;
    // (Every step below is exact by the bounds stated; the wrapping forms
    // only spare overflow checks that LLVM cannot discharge.)
    // High digit: q1 = ⌊n/(d·2¹⁶)⌋ < 2¹⁶ (u1 < d), estimated as
    // ⌊u1·W/2³²⌋ ≤ u1·2¹⁶/d ≤ n/(d·2¹⁶); the remainder n − q1·d·2¹⁶ then
    // stays ≥ 0 and ends below d·2¹⁶ < 2⁴⁸.
    let mut q1 = mul_recip(u1, wl);
    let mut n1 = n.wrapping_sub(mul16x32(q1, d) << 16);
    while n1 >= d16 {
        n1 = n1.wrapping_sub(d16);
        q1 = q1.wrapping_add(1);
    }
    // Low digit: q0 = ⌊n1/d⌋ < 2¹⁶ from the top 32 bits of n1, likewise.
    let mut q0 = mul_recip((n1 >> 16) as u32, wl);
    let mut r = n1.wrapping_sub(mul16x32(q0, d));
    while r >= d as u64 {
        r = r.wrapping_sub(d as u64);
        q0 = q0.wrapping_add(1);
    }
    ((q1 << 16).wrapping_add(q0), r as u32)
}

/// The two-word division of this target (see above).
#[inline(always)]
fn div_words(u1: u32, u0: u32, d: u32) -> (u32, u32) {
    #[cfg(wide_mul)]
    {
        div_words_native(u1, u0, d)
    }
    #[cfg(div_by_reciprocal)]
    {
        div_words_reciprocal(u1, u0, d)
    }
    #[cfg(not(any(wide_mul, div_by_reciprocal)))]
    {
        div_words_hw32(u1, u0, d)
    }
}

/// `a·2^FRAC / b` rounded to nearest (ties away from zero), saturating; see
/// [`Fixed32`]'s `Div` for the zero-divisor results. `words` is the
/// two-word division (a parameter so that the tests can run every variant).
///
/// Why this route: normalising the divisor turns the 55-by-31-bit division
/// into a two-word by one-word division with a quotient below 2³¹, which
/// every target can do exactly without a 64-bit library division (a long
/// loop on 32-bit cores: `__aeabi_uldivmod`, `__udivdi3`); its remainder
/// gives the exact rounding.
#[inline(always)]
fn div_raw_with(a: i32, b: i32, words: impl Fn(u32, u32, u32) -> (u32, u32)) -> i32 {
    if b == 0 {
        return div_raw_by_zero(a);
    }
    div_raw_normalised(a, b, clz(b.unsigned_abs()), words)
}

/// The quotient by zero (see [`Fixed32`]'s `Div`).
#[inline(always)]
fn div_raw_by_zero(a: i32) -> i32 {
    if a == 0 {
        0
    } else if a > 0 {
        RAW_MAX
    } else {
        RAW_MIN
    }
}

/// [`div_raw_with`] for `b ≠ 0`, given `s = clz(|b|)` (which divisions by
/// the same `b` can share).
#[inline(always)]
fn div_raw_normalised(a: i32, b: i32, s: u32, words: impl Fn(u32, u32, u32) -> (u32, u32)) -> i32 {
    let neg = (a ^ b) < 0;
    let (x, y) = (a.unsigned_abs(), b.unsigned_abs());
    if quotient_saturates(x, y) {
        return if neg { RAW_MIN } else { RAW_MAX };
    }
    // Normalise: d = y·2^s ∈ [2³¹, 2³²). The numerator N = x·2^(FRAC+s) then
    // satisfies N < 2³¹·d (from x < 2^(31−FRAC)·y), so its high word is
    // below d and ⌊N/d⌋ = ⌊x·2^FRAC/y⌋ < 2³¹. Only 32-bit shifts: a
    // variable 64-bit shift is a library call on Armv6-M.
    let d = y.wrapping_shl(s);
    let k = FRAC + s; // ∈ [FRAC, FRAC + 31]
    let (u1, u0) = if k >= 32 { (x.wrapping_shl(k - 32), 0) } else { (x.wrapping_shr(32 - k), x.wrapping_shl(k)) };
    // r = 2^s·(x·2^FRAC mod y) < d: the same halfway test as against y.
    let (q, r) = words(u1, u0, d);
    round_quotient(q, r, d, neg)
}

/// Whether the quotient `x·2^FRAC/y` of magnitudes is ≥ 2³¹ (saturates):
/// iff x ≥ 2^(31−FRAC)·y, i.e. iff ⌊x/2^(31−FRAC)⌋ ≥ y (y is an integer).
/// Otherwise ⌊x·2^FRAC/y⌋ < 2³¹.
#[inline(always)]
fn quotient_saturates(x: u32, y: u32) -> bool {
    x >> (31 - FRAC) >= y
}

/// The signed quotient from its magnitude's `q = ⌊n/d⌋ < 2³¹` and
/// remainder `r < d`: the remainder is at least half the divisor iff
/// r ≥ d − r, and the magnitude then rounds up (away from zero); q + 1 ≤
/// 2³¹ fits, and only 2³¹ itself saturates.
#[inline(always)]
fn round_quotient(q: u32, r: u32, d: u32, neg: bool) -> i32 {
    let q = q.wrapping_add((r >= d.wrapping_sub(r)) as u32);
    let m = if q > RAW_MAX as u32 { RAW_MAX } else { q as i32 };
    if neg {
        -m
    } else {
        m
    }
}

/// `(a₁/b, a₂/b)`, bit for bit two [`div_raw`]s, sharing what depends on
/// the divisor alone: its leading zeros and, where the two-word division
/// goes through a reciprocal, that reciprocal (about 50 instructions of
/// the second division on Armv6-M).
#[inline(always)]
#[cfg_attr(not(armv6m_inline_mul), allow(dead_code))]
fn div2_raw(a1: i32, a2: i32, b: i32) -> (i32, i32) {
    if b == 0 {
        return (div_raw_by_zero(a1), div_raw_by_zero(a2));
    }
    let s = clz(b.unsigned_abs());
    // Where `div_words` is `div_words_reciprocal`, its reciprocal once.
    let reciprocal = cfg!(div_by_reciprocal);
    if reciprocal {
        let wl = divisor_reciprocal(b.unsigned_abs().wrapping_shl(s));
        let words = |u1: u32, u0: u32, d: u32| div_words_by_reciprocal(u1, u0, d, wl);
        (div_raw_normalised(a1, b, s, words), div_raw_normalised(a2, b, s, words))
    } else {
        (div_raw_normalised(a1, b, s, div_words), div_raw_normalised(a2, b, s, div_words))
    }
}

/// `a·2^FRAC / b` with this target's two-word division; on 32-bit cores
/// with a divide instruction, divisors below 2^(32−8) (|b| < 1: the
/// denominators of the plane and slab tests, a unit direction's
/// components) by [`div_raw_short`] instead.
#[inline(always)]
fn div_raw(a: i32, b: i32) -> i32 {
    #[cfg(not(any(wide_mul, div_by_reciprocal)))]
    {
        if b.unsigned_abs() < SHORT_DIVISOR_LIMIT {
            return div_raw_short(a, b);
        }
    }
    // (A closure, not the function: passed as a function, at opt-level `s`
    // the two-word division stayed a call through a shim, about 5
    // instructions more per division on the Cortex-M0.)
    #[allow(clippy::redundant_closure)]
    div_raw_with(a, b, |u1, u0, d| div_words(u1, u0, d))
}

/// Bits per digit of [`div_raw_short`]'s long division.
#[cfg_attr(any(wide_mul, div_by_reciprocal), allow(dead_code))]
const SHORT_DIGIT: u32 = 8;
/// Divisors (raw magnitudes) below this take [`div_raw_short`]: a
/// remainder below the divisor then still fits 32 bits after a shift by
/// one digit.
#[cfg_attr(any(wide_mul, div_by_reciprocal), allow(dead_code))]
const SHORT_DIVISOR_LIMIT: u32 = 1 << (32 - SHORT_DIGIT);
const _: () = assert!(FRAC == 3 * SHORT_DIGIT);

/// [`div_raw_with`]'s quotient, bit for bit, for `|b| <`
/// [`SHORT_DIVISOR_LIMIT`] (zero included), by long division with 32-bit
/// divides: the integer part `⌊x/y⌋`, then three digits of 8 bits (`FRAC` = 24), each
/// `⌊r·2⁸/y⌋` from the previous remainder `r < y` (so `r·2⁸ < 2³²`), and
/// the last remainder rounds.
///
/// Why this route where the core divides 32 bits (RV32 with `M`,
/// Armv7-M): the normalised two-word division needs the divisor's leading
/// zeros (a dozen instructions without a count instruction), 64-bit shifts
/// of the numerator and algorithm D's corrections, about 90 instructions
/// a call on RV32IMAC; this is about 45, four of them divides instead of
/// two (a divide takes 18 to 34 cycles on common RV32 cores, 2 to 12 on
/// the Cortex-M4).
#[inline(always)]
#[cfg_attr(any(wide_mul, div_by_reciprocal), allow(dead_code))]
fn div_raw_short(a: i32, b: i32) -> i32 {
    let Some(y_nz) = core::num::NonZeroU32::new(b.unsigned_abs()) else {
        return div_raw_by_zero(a);
    };
    let neg = (a ^ b) < 0;
    let (x, y) = (a.unsigned_abs(), y_nz.get());
    // Past this, x < 2^(31−FRAC)·y: the integer part below is under
    // 2^(31−FRAC) and the finished quotient under 2³¹.
    if quotient_saturates(x, y) {
        return if neg { RAW_MIN } else { RAW_MAX };
    }
    // Integer part, then one digit at a time: q·y + r = x·2^(8i) after
    // digit i, with r < y < 2^(32−8) (the wrapping forms only spare
    // overflow checks: every step is exact).
    // (Three digits written out: at opt-level `s` a loop stays a loop,
    // two instructions more per digit.)
    let digit = |q: u32, r: u32| {
        let t = r << SHORT_DIGIT;
        let d = t / y_nz;
        ((q << SHORT_DIGIT) | d, t.wrapping_sub(d.wrapping_mul(y)))
    };
    let q = x / y_nz;
    let (q, r) = digit(q, x.wrapping_sub(q.wrapping_mul(y)));
    let (q, r) = digit(q, r);
    let (q, r) = digit(q, r);
    // q = ⌊x·2^FRAC/y⌋, r its remainder.
    round_quotient(q, r, y, neg)
}

/// [`ratio_raw`] with this target's two-word division, out of line (rare:
/// coordinates of images wider than 65 535 pixels).
#[inline(never)]
fn ratio_wide(num: u32, den: u32) -> i32 {
    ratio_raw(num, den, div_words)
}

/// `round(num·2^FRAC/den)` (ties up), saturating at `RAW_MAX`; `den = 0`
/// gives `RAW_MAX`. `words` is the two-word division, as for
/// [`div_raw_with`].
///
/// Why this route: it is the same normalised two-word division as `div`,
/// so no target links the 64-bit library division (a long loop on 32-bit
/// cores, and about 1 KB of flash) for it.
#[inline(always)]
fn ratio_raw(num: u32, den: u32, words: impl Fn(u32, u32, u32) -> (u32, u32)) -> i32 {
    if den == 0 {
        return RAW_MAX;
    }
    // round(num·2^FRAC/den) = ⌊M/den⌋ with M = num·2^FRAC + ⌊den/2⌋, as two
    // words (below 2^(32+FRAC) + 2³¹: no carry out of the high word).
    let lo = num << FRAC;
    let (m0, carry) = lo.overflowing_add(den >> 1);
    let m1 = (num >> (32 - FRAC)) + carry as u32;
    // Saturation, exactly: M ≥ 2³¹·den iff ⌊M/2³¹⌋ ≥ den (den integral).
    if (m1 << 1) | (m0 >> 31) >= den {
        return RAW_MAX;
    }
    // Normalise: d = den·2^s ∈ [2³¹, 2³²); M·2^s's high word is below d
    // (M < 2³¹·den), so the quotient is below 2³¹ and is ⌊M/den⌋.
    let s = clz(den);
    let d = den << s;
    let (u1, u0) = if s == 0 { (m1, m0) } else { ((m1 << s) | (m0 >> (32 - s)), m0 << s) };
    let (q, _) = words(u1, u0, d);
    q as i32
}

// ---------------------------------------------------------------------------
// Square root.

/// Seeds for `2³¹/√t`, `t ∈ [2³⁰, 2³²)`, indexed by `t >> 27` (8..=31): the
/// value at each interval's midpoint as `(y − 2¹⁵)/2⁷`, rounded (≈ 5 bits).
const RSQRT_SEED: [u8; 24] =
    [241, 214, 191, 171, 154, 138, 124, 112, 101, 90, 81, 72, 64, 56, 49, 43, 37, 31, 25, 20, 15, 11, 6, 2];

/// `y ≈ 2³¹/√t` for `t ∈ [2³⁰, 2³²)`, `y ∈ (2¹⁵, 2¹⁶)`, to 2⁻¹⁵
/// (the resolution of `y`): the 16-bit reciprocal square root that
/// [`sqrt_raw`] and [`rsqrt_raw`] refine.
#[inline(always)]
fn rsqrt16(t: u32) -> u32 {
    // y ≈ 2³¹/√t = 2¹⁵/√T (T = t/2³² ∈ [¼, 1)), y ∈ (2¹⁵, 2¹⁶): seed, then
    // Newton y ← y + y·(1 − T·y²)/2 (converges from below).
    let seed = match RSQRT_SEED.get(((t >> 27) as usize).wrapping_sub(8)) {
        Some(&s) => s as u32,
        None => 0, // unreachable: t >> 27 ∈ [8, 31]
    };
    let mut y = (1u32 << 15) + (seed << 7);
    // First step with T's top 16 bits (error 2⁻⁵ → 2⁻⁹·⁵): T·y² in Q.16 as
    // (t/2¹⁶)·(y²/2¹⁶)/2¹⁴; h = 1 − T·y² in Q.16 is small and signed.
    let u = (t >> 16).wrapping_mul(y.wrapping_mul(y) >> 16) >> 14;
    let h = (1i32 << 16).wrapping_sub(u as i32);
    y = y.wrapping_add((((y >> 1) as i32).wrapping_mul(h) >> 16) as u32);
    // Second step with the full t (error → 2⁻¹⁵, the resolution of y):
    // T·y = t·y/2³² as Q.31 from a 16×32 product, then T·y² = (T·y)·y.
    let ty = (mul16x32(y, t) >> 16) as u32;
    let u = (ty >> 15).wrapping_mul(y) >> 15;
    let h = (1i32 << 16).wrapping_sub(u as i32);
    y = y.wrapping_add((((y >> 1) as i32).wrapping_mul(h) >> 16) as u32);
    y
}

/// `2³⁶/√a` for `0 < a < 2³¹`, saturating at `RAW_MAX`:
/// the Q8.24 reciprocal square root of `a/2^FRAC` (FRAC = 24).
///
/// Why this route: normalising a vector took a correctly rounded square
/// root and a correctly rounded division (about 310 instructions on the
/// Cortex-M0); the reciprocal root is what the normalisation multiplies
/// by, and one Newton step at full precision on [`rsqrt16`]'s estimate
/// gives it in a third of that.
///
/// With `a = t·4^(−j)` (`t ∈ [2³⁰, 2³²)`, an even shift) and `T = t/2³²`,
/// `2³⁶/√a = 2^(20+j)/√T = Y·2^(j−10)` for `Y = 2³⁰/√T ∈ (2³⁰, 2³¹]`. From
/// `y ≈ 2¹⁵/√T` (relative error `ε ≤ 2⁻¹⁵`), one Newton step
/// `Y = y·2¹⁵·(1 + h/2)`, `h = 1 − T·y²/2³⁰`, leaves `1.5·ε² < 2⁻²⁸`:
/// `T·y²·2³² = t·y²` is an exact 64-bit product (`y² < 2³²`), so `h·2⁶²`
/// is exact, and the correction `y·2¹⁵·h/2 = y·(h·2⁶²)/2⁴⁸` (about 2¹⁶) is
/// formed from `h`'s top 16 bits, within a few units of `Y`'s 2⁻³⁰. The
/// shift to `2^(j−10)` rounds half up: the result is within half a unit
/// plus `2⁻²⁷` of itself of `2³⁶/√a` (so within 0.6 of a unit for every `a`
/// of at least 2²², a squared length of at least ¼, which the
/// normalisation's prescale gives); `a` below 2¹⁰ saturates.
#[inline(always)]
fn rsqrt_raw(a: u32) -> u32 {
    const _: () = assert!(FRAC == 24);
    let z = clz(a) & !1;
    // Y·2^(j−10), j = z/2: a right shift by 10 − j ≥ 1, rounded half up,
    // or (j ≥ 10) at least 2³⁰·2^(j−10): saturated from j = 11 on.
    let big_y = rsqrt_scaled(a, z);
    let sh = 10i32.wrapping_sub((z / 2) as i32);
    if sh >= 1 {
        big_y.wrapping_add(1 << (sh - 1)) >> sh
    } else if sh == 0 {
        big_y.min(RAW_MAX as u32)
    } else {
        RAW_MAX as u32
    }
}

/// [`rsqrt_raw`] for `a ∈ [2²², 2²⁶)` (a squared length from ¼ up to 4,
/// what the normalisation's prescale gives: [`unit_and_length_raw`]), bit
/// for bit: there `z = clz(a) & !1` is 8 below 2²⁴ and 6 from it on, and
/// the final shift `10 − z/2` is 6 or 7, so neither the leading zeros nor
/// the saturating cases are needed (about 30 of its 130 instructions on
/// the Cortex-M0). Other `a` give an unspecified value, never a panic.
///
/// Out of line (one copy; its callers are the normalisation's copies),
/// except on RV32, where the call and its register moves were about 5
/// instructions of its 55 and inline copies cost 1.5 KB (RV32IMAC `fixed32`
/// frame 0.40 M instructions shorter).
#[cfg_attr(not(target_arch = "riscv32"), inline(never))]
#[cfg_attr(target_arch = "riscv32", inline(always))]
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
fn rsqrt_raw_unit(a: u32) -> u32 {
    // (`sh = 10 − z/2`, chosen with `z` rather than computed from it: the
    // Cortex-M0 frame about 49 000 instructions shorter.)
    let below = a < 1 << 24;
    let z = if below { 8 } else { 6 };
    let sh = if below { 6 } else { 7 };
    rsqrt_scaled(a, z).wrapping_add(1 << (sh - 1)) >> sh
}

/// `Y ≈ 2³⁰/√T` for `T = t/2³²`, `t = a·2^z ∈ [2³⁰, 2³²)` (`z` even), at
/// most 2³¹ + a few: [`rsqrt_raw`] before its final shift.
#[inline(always)]
fn rsqrt_scaled(a: u32, z: u32) -> u32 {
    let t = a.wrapping_shl(z); // z ≤ 30
    let y = rsqrt16(t);
    // h·2⁶² = 2⁶² − t·y² (|h| < 2⁻¹³: fits an i64 with room).
    let h = ((1u64 << 62) as i64).wrapping_sub(wmul(t, y.wrapping_mul(y)) as i64);
    // y·(h·2⁶²)/2⁴⁸ = (y/2)·(h·2⁶²/2³³)/2¹⁴: both factors below 2¹⁶ in magnitude.
    let c = ((y >> 1) as i32).wrapping_mul((h >> 33) as i32) >> 14;
    // Y ≈ 2³⁰/√T, at most 2³¹ + a few.
    (y << 15).wrapping_add_signed(c)
}

/// `round(√(a·2^FRAC))` for `0 < a < 2³¹`.
///
/// Why this route: the bit-by-bit integer square root of a 55-bit number is
/// a 28-iteration loop of 64-bit operations (≈ 300 instructions on a 32-bit
/// core); a reciprocal-square-root estimate needs a few 16-bit products, and
/// residuals computed exactly in 32 bits turn the estimate into the
/// correctly rounded root.
#[inline(always)]
fn sqrt_raw(a: u32) -> u32 {
    // n = a·2^FRAC = g·2^F' with F' = FRAC rounded down to even.
    let odd = FRAC & 1;
    let g = a << odd; // < 2³²
                      // Normalise by an even shift: t = g·4^(z/2) ∈ [2³⁰, 2³²), so that
                      // √n = √(t·2³²)·2^−k with k = 16 − F'/2 + z/2 ≥ 3.
    let z = clz(g) & !1;
    let t = g.wrapping_shl(z); // z ≤ 30
    let k = (16 - (FRAC - odd) / 2).wrapping_add(z / 2);
    // y ≈ 2³¹/√t, to 16 bits.
    let y = rsqrt16(t);
    // Top 16 bits: s ≈ √t = t·y/2³¹ (within −1…+2 of ⌊√t⌋); make it exact
    // with the residual δ = t − s² (exact: |δ| < 2³¹, wrapped arithmetic).
    let mut s = (mul16x32(y, t) >> 31) as u32;
    let mut delta = t.wrapping_sub(s.wrapping_mul(s)) as i32;
    // (The bounds make every step below exact; wrapping operations keep
    // them free of overflow checks, which LLVM cannot discharge.)
    while delta < 0 {
        s = s.wrapping_sub(1);
        delta = delta.wrapping_add(s.wrapping_mul(2).wrapping_add(1) as i32);
    }
    while delta > s.wrapping_mul(2) as i32 {
        delta = delta.wrapping_sub(s.wrapping_mul(2).wrapping_add(1) as i32);
        s = s.wrapping_add(1);
    }
    // Next 16 bits: √t = s + δ/(2s) − δ²/(8s³) + … with 0 ≤ δ ≤ 2s, so
    // √(t·2³²) ≈ s·2¹⁶ + δ·2¹⁵/s, and 1/s ≈ y/2³¹: f = (δ/2)·y/2¹⁵ (< 2³²;
    // error a few units, the dropped term below one).
    let f = (delta as u32 >> 1).wrapping_mul(y) >> 15;
    let root = (s << 16).wrapping_add(f); // ≈ √(t·2³²), within a few units
                                          // Scale to √n and round: r̂ = round(root/2^k), within ±1 of the answer.
    let mut r = (root >> (k.wrapping_sub(1) & 31)).wrapping_add(1) >> 1;
    // Exact final rounding with D = n − r̂² (|D| < 2³¹, so modulo 2³² is
    // exact): r is round(√n) iff −r < D ≤ r (as (r − ½)² ≤ n < (r + ½)²,
    // and n is an integer).
    let mut dd = (a << FRAC).wrapping_sub(r.wrapping_mul(r)) as i32;
    while dd > r as i32 {
        dd = dd.wrapping_sub(r.wrapping_mul(2).wrapping_add(1) as i32);
        r = r.wrapping_add(1);
    }
    while dd <= (r as i32).wrapping_neg() {
        dd = dd.wrapping_add(r.wrapping_mul(2).wrapping_sub(1) as i32);
        r = r.wrapping_sub(1);
    }
    r
}

// ---------------------------------------------------------------------------
// Power: shift-and-add log₂ and exp₂.

/// Number of shift-and-add steps of `log₂` and `2^f`: the residual factor
/// after them is below `1 + 2⁻¹⁴`, finished to first order (error `< 2⁻²⁸`).
const POW_STEPS: usize = 14;

/// `log₂(1 + 2⁻ⁱ)` for `i = 1 ..= 14` as Q.30, rounded to nearest (from
/// 60-digit decimal arithmetic; `pow_table_matches_f64` checks each entry).
const LOG2_STEP: [u32; POW_STEPS] = [
    628_098_702,
    345_667_660,
    182_455_581,
    93_912_511,
    47_667_823,
    24_017_256,
    12_055_174,
    6_039_314,
    3_022_600,
    1_512_037,
    756_203,
    378_148,
    189_085,
    94_546,
];

/// `1/ln 2` in Q.15 and `ln 2` in Q.16 (the first-order finishes).
const INV_LN2_Q15: u32 = 47_274;
const LN2_Q16: u32 = 45_426;

/// `log₂(m/2³¹)` in Q.30 for `m ∈ [2³¹, 2³²)` (a mantissa in [1, 2)).
///
/// Multiplies `m` by those factors `1 + 2⁻ⁱ` (a shift and an add each) that
/// keep it below 2, summing their logarithms from the table: `m·Π = p` with
/// `p ∈ [2/(1 + 2⁻¹⁴), 2)`, so `log₂m = 1 − Σ − log₂(2/p)` and
/// `log₂(2/p) ≈ (2 − p)/(2·ln 2)` to within `2⁻²⁸`.
#[inline(always)]
fn log2_mantissa(m: u32) -> u32 {
    let mut p = m;
    let mut acc = 0u32;
    let mut i = 0;
    while i < POW_STEPS {
        // p·(1 + 2^−(i+1)); the carry out of bit 31 means "≥ 2": skip.
        let (t, over) = p.overflowing_add(p >> (i + 1));
        if !over {
            p = t;
            acc = acc.wrapping_add(LOG2_STEP[i]);
        }
        i += 1;
    }
    // 2 − p in units of 2⁻³¹ is 2³² − p (< 2¹⁸ here); times 1/(2 ln 2) in
    // Q.30: (2³² − p)/2²·(1/ln 2)/2¹⁵.
    let gap = p.wrapping_neg();
    let tail = (gap >> 2).wrapping_mul(INV_LN2_Q15) >> 15;
    // At m = 1 the rounded table sum may exceed 1 by a few units: clamp at 0.
    (1u32 << 30).saturating_sub(acc.wrapping_add(tail))
}

/// `2^f` in Q1.31 for `f ∈ [0, 1)` given as Q.26.
///
/// Subtracts from `f` those table logarithms that fit, multiplying `p` by
/// the matching factors `1 + 2⁻ⁱ` (greedy: each factor is at most the
/// product of all later ones, so the remainder ends below `log₂(1 + 2⁻¹⁴)`),
/// then `p·2^rem ≈ p·(1 + rem·ln 2)`.
#[inline(always)]
fn exp2_fraction(f: u32) -> u32 {
    let mut rem = f << 4; // Q.30
    let mut p = 1u32 << 31;
    let mut i = 0;
    while i < POW_STEPS {
        if rem >= LOG2_STEP[i] {
            rem = rem.wrapping_sub(LOG2_STEP[i]);
            p = p.wrapping_add(p >> (i + 1));
        }
        i += 1;
    }
    // rem < 2¹⁷ (Q.30); rem·ln 2 in Q.30, then p·that/2³⁰ from 15 × 16 bits.
    let x = (rem >> 1).wrapping_mul(LN2_Q16) >> 15;
    // (Exact by the bounds above; wrapping spares unprovable overflow checks.)
    p.wrapping_add((p >> 17).wrapping_mul(x) >> 13)
}

/// `x^e` for raw `0 < x < 2^FRAC` (x in (0, 1)) and raw `e > 0`.
#[inline(always)]
fn powf_raw(x: i32, e: i32) -> i32 {
    // With j the index of x's top bit, x·2^−FRAC = (m/2³¹)·2^(j−FRAC) with
    // the mantissa m = x·2^(31−j) ∈ [2³¹, 2³²).
    let lz = clz(x as u32);
    let j = 31u32.wrapping_sub(lz);
    let m = (x as u32).wrapping_shl(lz);
    // |log₂x| = (FRAC − j) − log₂(m/2³¹) ∈ (0, FRAC] in Q.26 (rounded from Q.30).
    let l_mag = (FRAC.wrapping_sub(j) << 26).wrapping_sub(log2_mantissa(m).wrapping_add(8) >> 4);
    // w = e·|log₂x| in Q.26 from one 32×32→64 product (e in Q.FRAC).
    let w = wmul(e as u32, l_mag) >> FRAC;
    // 2^−w < 2^−(FRAC+1) rounds to zero (below half an ulp).
    if w > ((FRAC as u64 + 1) << 26) {
        return 0;
    }
    let w = w as u32;
    // 2^−w = 2^f·2^−kk with kk = ⌈w⌉ and f = kk − w ∈ [0, 1) (f = 0 when w is
    // an integer).
    let f = w.wrapping_neg() & ((1 << 26) - 1);
    let kk = w.wrapping_add((1 << 26) - 1) >> 26; // ≤ FRAC + 1
    let p = exp2_fraction(f); // 2^f in Q1.31
                              // raw = round(p·2^−kk·2^FRAC/2³¹): shift by 31 − FRAC + kk ∈ [7, 32], rounding.
    let sh = (31 - FRAC).wrapping_add(kk);
    ((p >> (sh.wrapping_sub(1) & 31)).wrapping_add(1) >> 1) as i32
}

// ---------------------------------------------------------------------------
// Conversions.

/// Raw value of an `f32`, rounded to nearest (ties away from zero),
/// saturating, NaN to 0, from its bits alone.
const fn raw_from_f32(v: f32) -> i32 {
    let bits = v.to_bits();
    let neg = bits >> 31 != 0;
    let exp = ((bits >> 23) & 0xFF) as i32;
    let man = bits & 0x7F_FFFF;
    let sat = if neg { RAW_MIN } else { RAW_MAX };
    if exp == 0xFF {
        // Infinity saturates; NaN is 0.
        return if man != 0 { 0 } else { sat };
    }
    // |v| = sig·2^e2: normal numbers have the implicit bit, subnormals
    // (exponent field 0) the exponent of the smallest normal.
    let (sig, e2) = if exp == 0 { (man, -149) } else { (man | 0x80_0000, exp - 150) };
    // raw = round(sig·2^(e2 + FRAC)).
    let sh = e2 + FRAC as i32;
    let mag = if sh >= 0 {
        // A left shift: exact, or beyond MAX.
        if sig == 0 {
            0
        } else if sh >= 31 || sig > (RAW_MAX as u32) >> sh {
            return sat;
        } else {
            sig << sh
        }
    } else {
        let n = (-sh) as u32;
        if n > 24 {
            // sig < 2²⁴ ≤ 2^(n−1): below half an ulp.
            0
        } else {
            // Add half of the last kept bit's weight and truncate: the
            // magnitude rounds half up, i.e. ties away from zero.
            sig.wrapping_add(1 << (n - 1)) >> n
        }
    };
    // mag < 2²⁴ or checked against MAX above (so the negation is exact).
    if neg {
        (mag as i32).wrapping_neg()
    } else {
        mag as i32
    }
}

// ---------------------------------------------------------------------------
// Operators.

// The sum and the difference are `i32`'s saturating ones. On Armv6-M with
// the product inline, written as the wrapped result unless the V flag is
// set (one branch), the rare rest out of line: `saturating_add` there
// forms its saturated value branch-free after every sum. Only there, and
// not with `compact-mul`: the out-of-line calls made the size-optimised
// `fixed32` image larger and no faster, and on RV32IMAC (no flags) the
// test image larger and slower.

/// The saturated sum's rare case (overflow).
#[cfg_attr(not(armv6m_inline_mul), allow(dead_code))]
#[cold]
#[inline(never)]
fn add_rare(a: i32, b: i32) -> i32 {
    a.saturating_add(b)
}

/// The saturated difference's rare case (overflow).
#[cfg_attr(not(armv6m_inline_mul), allow(dead_code))]
#[cold]
#[inline(never)]
fn sub_rare(a: i32, b: i32) -> i32 {
    a.saturating_sub(b)
}

impl Add for Fixed32 {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        #[cfg(armv6m_inline_mul)]
        {
            let (s, v) = self.0.overflowing_add(o.0);
            if v {
                return Fixed32(add_rare(self.0, o.0));
            }
            Fixed32(s)
        }
        #[cfg(not(armv6m_inline_mul))]
        {
            Fixed32(self.0.saturating_add(o.0))
        }
    }
}

impl Sub for Fixed32 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        #[cfg(armv6m_inline_mul)]
        {
            let (s, v) = self.0.overflowing_sub(o.0);
            if v {
                return Fixed32(sub_rare(self.0, o.0));
            }
            Fixed32(s)
        }
        #[cfg(not(armv6m_inline_mul))]
        {
            Fixed32(self.0.saturating_sub(o.0))
        }
    }
}

impl Neg for Fixed32 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        // Exact, except on the bottom value −2⁷ (raw `i32::MIN`), whose
        // negation saturates to MAX.
        Fixed32(self.0.saturating_neg())
    }
}

impl Mul for Fixed32 {
    type Output = Self;
    // Out of line on WebAssembly, whose module a browser downloads (web/):
    // inlined at every use, the products are 13 KB of the module.
    #[cfg_attr(not(target_arch = "wasm32"), inline(always))]
    #[cfg_attr(target_arch = "wasm32", inline(never))]
    fn mul(self, o: Self) -> Self {
        #[cfg(armv6m)]
        {
            Fixed32(mul_raw_armv6m(self.0, o.0))
        }
        #[cfg(wide_mul)]
        {
            Fixed32(mul_raw_native(self.0, o.0))
        }
        #[cfg(not(any(wide_mul, armv6m)))]
        {
            Fixed32(mul_raw_words(self.0, o.0))
        }
    }
}

/// The Armv6-M product: [`mul_raw_limbs`] inline at every use (about 22
/// instructions each), or with the feature `compact-mul` one
/// shared copy that every use calls (a few more instructions per product,
/// a few bytes per use).
#[cfg(armv6m)]
#[cfg_attr(feature = "compact-mul", inline(never))]
#[cfg_attr(not(feature = "compact-mul"), inline(always))]
fn mul_raw_armv6m(a: i32, b: i32) -> i32 {
    mul_raw_limbs(a, b)
}

impl Div for Fixed32 {
    type Output = Self;
    // Out of line: ≈ 540 bytes of code on Armv6-M, too much to inline into
    // every lane.
    #[inline(never)]
    fn div(self, o: Self) -> Self {
        Fixed32(div_raw(self.0, o.0))
    }
}

impl Scalar for Fixed32 {
    const ZERO: Self = Fixed32(0);
    const ONE: Self = Fixed32(RAW_ONE);
    const HALF: Self = Fixed32(RAW_ONE / 2);
    const TWO: Self = Fixed32(2 * RAW_ONE);
    const MAX: Self = Fixed32(RAW_MAX);
    /// `round(10⁻⁴·2^FRAC)` (1678 for FRAC = 24), the value
    /// `from_f32(1e-4)` gives (unit-tested).
    const RAY_EPSILON: Self = Fixed32((((1i64 << FRAC) + 5_000) / 10_000) as i32);
    const MIN_WEIGHT: Self = Fixed32(RAW_ONE >> 9);
    const LIMITED_RANGE: bool = true;
    const COORDINATE_LIMIT: f32 = COORDINATE_LIMIT;
    /// Lights only enter through directions and distances to them, which the
    /// tracer forms without squaring large values (normalisation prescales:
    /// [`Scalar::NORMALIZE_PRESCALE`]), so they may lie well outside the box:
    /// a light–point difference then stays below `100 + 2`, inside the range.
    const LIGHT_LIMIT: f32 = LIGHT_LIMIT;
    const INTERMEDIATE_LIMIT: f32 = INTERMEDIATE_LIMIT;
    /// Scenes are converted into the box `[−1, 1]³` (half the coordinate
    /// limit, so values rounded on conversion stay inside the limit).
    const SCENE_FRAME: Option<f32> = Some(1.0);
    const NORMALIZE_PRESCALE: bool = true;
    const SPARSE_PRODUCTS: bool = true;

    /// On Armv6-M three partial products (`square_raw_limbs`), elsewhere
    /// the product; the same bits.
    #[inline(always)]
    fn square(self) -> Self {
        #[cfg(armv6m)]
        {
            Fixed32(square_raw_limbs(self.0))
        }
        #[cfg(not(armv6m))]
        {
            self * self
        }
    }

    /// `div2_raw`: the two quotients share the divisor's normalisation
    /// and reciprocal. Out of line, like the division. Armv6-M only, and
    /// not with `compact-mul` (1.3 KB more code there, for the image held
    /// to 48 KiB); on RV32IMAC (a hardware word division) the shared
    /// function made the two-scalar test image 2.5 KB larger, past 128 KiB,
    /// for 0.2 % fewer instructions. Elsewhere two divisions.
    #[cfg(armv6m_inline_mul)]
    #[inline(never)]
    fn div_pair(a: Self, b: Self, d: Self) -> (Self, Self) {
        let (p, q) = div2_raw(a.0, b.0, d.0);
        (Fixed32(p), Fixed32(q))
    }
    const UNIT_DOT_ESTIMATE: bool = true;
    #[inline(always)]
    fn unit_dot_le(a: [Self; 3], b: [Self; 3], limit: Self) -> Option<bool> {
        unit_dot_le_raw([a[0].0, a[1].0, a[2].0], [b[0].0, b[1].0, b[2].0], limit.0)
    }
    /// `mul_raw_small`: the product without its range tests. (Not on
    /// WebAssembly, whose module keeps one out-of-line product for size:
    /// see `Mul`.)
    #[cfg(not(target_arch = "wasm32"))]
    #[inline(always)]
    fn mul_small(self, o: Self) -> Self {
        Fixed32(mul_raw_small(self.0, o.0))
    }
    /// `square_raw_small`: the square without its range test (not on
    /// WebAssembly, as `mul_small`).
    #[cfg(not(target_arch = "wasm32"))]
    #[inline(always)]
    fn square_small(self) -> Self {
        Fixed32(square_raw_small(self.0))
    }
    /// The wrapping sum: the saturating one wherever the sum is in range,
    /// which it is for `add_small`'s operands (on RV32IMAC one `add`, where
    /// the saturating sum is four instructions).
    #[inline(always)]
    fn add_small(self, o: Self) -> Self {
        Fixed32(self.0.wrapping_add(o.0))
    }
    /// The wrapping difference, as `add_small`.
    #[inline(always)]
    fn sub_small(self, o: Self) -> Self {
        Fixed32(self.0.wrapping_sub(o.0))
    }

    /// `unit_and_length_raw`: the general code without the range tests
    /// that cannot fire, for every vector from 2⁻⁷ up. Not on WebAssembly,
    /// where its copy at every normalisation took the browser module past
    /// its 200 KB budget.
    #[cfg(not(target_arch = "wasm32"))]
    #[inline(always)]
    fn unit_and_length(v: [Self; 3]) -> Option<([Self; 3], Self)> {
        unit_and_length_raw(map3(v, |c| c.0)).map(|(n, len)| (map3(n, Fixed32), Fixed32(len)))
    }

    /// `2^k` for the `k` that brings `self` into `[½, 1)`, with `k` clamped to
    /// `[−8, 6]` (so `2^k` is representable and a vector of components up to
    /// the range's top comes down to below 1); 1 for zero. A multiplication
    /// by it is a shift: exact for `k ≥ 0`, rounded once for `k < 0`.
    #[inline]
    fn normalizing_factor(self) -> Self {
        Fixed32(1 << (FRAC as i32 + self.normalizing_exponent()))
    }
    /// The `k` of [`Scalar::normalizing_factor`]: 0 for zero.
    #[inline]
    fn normalizing_exponent(self) -> i32 {
        let raw = self.0.max(0) as u32;
        if raw == 0 {
            return 0;
        }
        // Position of the top bit; [½, 1) has its top bit at FRAC − 1.
        // (`clz`: `leading_zeros` is a library call on Armv6-M.)
        let top = 31 - clz(raw) as i32;
        (FRAC as i32 - 1 - top).clamp(-8, 6)
    }
    /// The product by `2^k` as a shift, bit for bit `self * 2^k` where
    /// `2^k` is representable (`k ∈ [−24, 6]`; beyond, the same rounding and
    /// saturation of `a·2^k`): that product is `⌊(a·2^(FRAC+k) + 2^(FRAC−1))/2^FRAC⌋`
    /// clamped, which is `a·2^k` clamped for `k >= 0` and, with `s = −k`,
    /// `⌊(a + 2^(s−1))/2^s⌋ = (a >> s) + bit s−1 of a` (the half added
    /// carries into bit `s` exactly when that bit is set) for `k < 0`.
    #[inline]
    fn mul_pow2(self, k: i32) -> Self {
        let a = self.0;
        if k >= 0 {
            let k = (k as u32).min(30);
            // In range iff shifting back gives `a` again (and not i32::MIN).
            let r = a.wrapping_shl(k);
            if r.wrapping_shr(k) == a && r != i32::MIN {
                Fixed32(r)
            } else if a < 0 {
                Fixed32(RAW_MIN)
            } else {
                Fixed32(RAW_MAX)
            }
        } else {
            let s = (k.unsigned_abs()).min(31);
            Fixed32(a.wrapping_shr(s).wrapping_add(a.wrapping_shr(s - 1) & 1))
        }
    }
    /// `round(clamp(v)·255)` (ties up) from the raw bits: `255` itself is not
    /// representable in Q8.24, so the generic formula cannot be used.
    #[inline]
    fn to_unorm8(self) -> u8 {
        let raw = self.0.clamp(0, RAW_ONE) as u32;
        // raw·255 < 2³², and adding half an ulp of the result rounds.
        ((raw * 255 + (1 << (FRAC - 1))) >> FRAC) as u8
    }
    /// `num / den` correctly rounded (ties away from zero) from the
    /// integers, without forming `num` or `den` in the format (an image 512
    /// pixels wide is beyond its range).
    #[inline(never)]
    fn ratio(num: u32, den: u32) -> Self {
        if den == 0 {
            return Self::MAX;
        }
        // round(num·2^FRAC/den) = ⌊(num·2^FRAC + ⌊den/2⌋)/den⌋. Image
        // coordinates (num, den < 2¹⁶) take two 32-bit divisions, a long
        // division in base 2¹⁶: a 64-bit one is a chain of library calls
        // on 32-bit cores without a divide instruction.
        if num < 1 << 16 && den < 1 << 16 {
            let a = num << (FRAC - 16); // < 2²⁴
            let (q1, r1) = (a / den, a % den);
            // r1 < den < 2¹⁶: r1·2¹⁶ + ⌊den/2⌋ < 2³².
            let q0 = ((r1 << 16) + den / 2) / den;
            let q = ((q1 as u64) << 16) + q0 as u64;
            return Fixed32(q.min(RAW_MAX as u64) as i32);
        }
        Fixed32(ratio_wide(num, den))
    }

    /// [`Fixed32::ratio`] from the divisor's reciprocal where it has one
    /// (no division; see [`Divisor`]), the same bits.
    #[inline(never)]
    fn ratio_by(num: u32, den: &Divisor) -> Self {
        const _: () = assert!(FRAC == 24);
        match den.rounded_q24(num, |a, b| (wmul(a, b) >> 32) as u32) {
            // FRAC = 24: the quotient is the raw value, below 2³¹.
            Some(q) => Fixed32(q as i32),
            None => Self::ratio(num, den.get()),
        }
    }

    #[inline]
    fn from_f32(v: f32) -> Self {
        Fixed32(raw_from_f32(v))
    }
    #[inline]
    fn from_i32(v: i32) -> Self {
        // Exact for |v| ≤ MAX's integer part, else saturating.
        const LIM: i32 = RAW_MAX >> FRAC;
        Fixed32(if v > LIM {
            RAW_MAX
        } else if v < -LIM {
            RAW_MIN
        } else {
            v << FRAC
        })
    }
    #[inline]
    fn to_f32(self) -> f32 {
        // raw·2⁻²⁴ with one rounding (i32 → f32, to nearest even). The
        // power-of-two scale is exact, and is applied to the exponent
        // field rather than as a product: a nonzero raw converts to
        // |f| ≥ 1 (biased exponent ≥ 127), so subtracting 24 from the
        // exponent gives a normal number, bit for bit `f · 2⁻²⁴`, and zero
        // stays zero. (The product form, vectorised for Helium, is what
        // LLVM 22 folds into MVE's fixed-point `vcvt`, whose fraction-bit
        // count it sometimes emits as a register: garbage bits
        // (`scripts/firmware.sh` rejects such images).)
        let f = self.0 as f32;
        let scaled = f32::from_bits(f.to_bits().wrapping_sub(FRAC << 23));
        if self.0 == 0 {
            0.0
        } else {
            scaled
        }
    }
    // Out of line, like `div`.
    #[inline(never)]
    fn sqrt(self) -> Self {
        if self.0 <= 0 {
            return Self::ZERO;
        }
        // r < 2^(15.5 + FRAC/2) ≤ 2²⁹: always fits.
        Fixed32(sqrt_raw(self.0 as u32) as i32)
    }
    const NORMALIZE_BY_INVERSE_SQRT: bool = true;
    /// Within half a unit plus `2⁻²⁷` of itself of `1/√self` (so not
    /// always the correctly rounded value; see docs/fixed-point.md,
    /// "Normalisation by a reciprocal square root"); `MAX` for
    /// `self <= 0`. Out of line, like `sqrt`.
    #[inline(never)]
    fn inverse_sqrt(self) -> Self {
        if self.0 <= 0 {
            return Self::MAX;
        }
        Fixed32(rsqrt_raw(self.0 as u32) as i32)
    }
    /// `self^e` for `self ∈ [0, 1]`, `e ≥ 0`: `e ≤ 0` or `self ≥ 1` give 1,
    /// `self ≤ 0` (with `e > 0`) gives 0. Absolute error ≤ 2⁻¹⁹ measured
    /// (see the module documentation).
    #[inline(never)]
    fn powf(self, e: Self) -> Self {
        let (x, e) = (self.0, e.0);
        if e <= 0 || x >= RAW_ONE {
            return Self::ONE;
        }
        if x <= 0 {
            return Self::ZERO;
        }
        Fixed32(powf_raw(x, e))
    }
    /// `⌊(self − origin)·2^shift⌋` exactly, clamped: bin 0 below `origin`;
    /// from it up, the raw difference, exact as an unsigned word (it lies
    /// in `[0, 2³²)`), shifted right by `FRAC − shift`, which floors. (The
    /// general form rounds the product, then floors: about 40 instructions
    /// a bin on the Cortex-M0; this one is a comparison, a subtraction, a
    /// shift and the upper clamp.) Shifts past `FRAC`, or below
    /// `FRAC − 31`, take the general form.
    #[inline(always)]
    fn bin(self, origin: Self, shift: i32, scale: Self, n: usize) -> usize {
        let k = (FRAC as i32).wrapping_sub(shift) as u32;
        if k > 31 {
            return crate::num::scalar::bin_rounded(self - origin, shift, scale, n);
        }
        if self.0 < origin.0 {
            return 0;
        }
        let x = (self.0 as u32).wrapping_sub(origin.0 as u32) >> k;
        (x as usize).min(n.saturating_sub(1))
    }
    #[inline]
    fn floor_to_i32(self) -> i32 {
        // An arithmetic shift floors.
        self.0 >> FRAC
    }
    #[inline]
    fn is_finite(self) -> bool {
        true
    }
    #[inline]
    fn abs(self) -> Self {
        Fixed32(self.0.saturating_abs())
    }
}

impl crate::num::bake::Bake for Fixed32 {
    /// `raypack::Fixed32::from_bits(…)`: the raw value, exactly.
    fn bake(&self, w: &mut dyn core::fmt::Write) -> core::fmt::Result {
        write!(w, "raypack::Fixed32::from_bits({})", self.to_bits())
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn mul_pow2_is_the_product_by_the_power() {
        let mut rng = Rng(0x2b0d);
        let edges = [
            0,
            1,
            -1,
            2,
            -2,
            3,
            -3,
            127,
            -128,
            255,
            256,
            -257,
            RAW_MAX,
            RAW_MIN,
            RAW_MAX / 64,
            RAW_MIN / 64,
            RAW_MAX / 64 + 1,
        ];
        for k in -8..=6 {
            let f = Fixed32(1 << (FRAC as i32 + k));
            let check = |a: i32| {
                let x = Fixed32(a);
                assert_eq!(x.mul_pow2(k), x * f, "{a} * 2^{k}");
            };
            edges.iter().for_each(|&a| check(a));
            for _ in 0..20_000 {
                check(rng.raw());
            }
        }
        // The exponent is the factor's.
        for a in [0, 1, 5_000, RAW_ONE / 3, RAW_ONE, RAW_MAX] {
            let x = Fixed32(a);
            assert_eq!(Fixed32(1 << (FRAC as i32 + x.normalizing_exponent())), x.normalizing_factor());
        }
    }

    extern crate std;
    use super::*;
    use std::format;
    use std::vec::Vec;

    const ULP: f64 = 1.0 / RAW_ONE as f64;

    fn fx(v: f64) -> Fixed32 {
        Fixed32::from_f64(v)
    }

    #[test]
    fn ratio_is_the_rounded_quotient() {
        // Against the 64-bit formula: every numerator for small
        // denominators, then image-sized ones, and the 2¹⁶ boundary.
        let want = |num: u32, den: u32| {
            let (n, d) = ((num as u64) << FRAC, den as u64);
            ((n + d / 2) / d).min(RAW_MAX as u64) as i32
        };
        for den in 1..=300u32 {
            for num in 0..=2 * den + 3 {
                assert_eq!(Fixed32::ratio(num, den).to_bits(), want(num, den), "{num}/{den}");
            }
        }
        let mut rng = Rng(0x5eed_0f7a_7100_0001);
        for _ in 0..200_000 {
            let den = 1 + rng.u32() % 0xFFFF;
            let num = rng.u32() % (1 << 16);
            assert_eq!(Fixed32::ratio(num, den).to_bits(), want(num, den), "{num}/{den}");
        }
        for (num, den) in [(0xFFFF, 1), (0xFFFF, 0xFFFF), (0x1_0000, 3), (5, 0x1_0000), (u32::MAX, 7)] {
            assert_eq!(Fixed32::ratio(num, den).to_bits(), want(num, den), "{num}/{den}");
        }
        // Any 32-bit pair (saturated or not), around the saturation edge
        // num ≈ 2⁷·den, and with every two-word division of the targets.
        let mut rng = Rng(0x5eed_0f7a_7100_0002);
        for k in 0..300_000u32 {
            let den = match k % 3 {
                0 => rng.u32().max(1),
                1 => 1 + rng.u32() % 0xFFFF,
                _ => (rng.u32() >> (rng.u32() % 32)).max(1),
            };
            let num = match k % 4 {
                0 => rng.u32(),
                1 => rng.u32() % (1 << 16),
                2 => den.saturating_mul(128).wrapping_add(rng.u32() % 5).wrapping_sub(2),
                _ => den.saturating_mul(128).saturating_sub(1 + (rng.u32() & 1)),
            };
            let w = want(num, den);
            assert_eq!(Fixed32::ratio(num, den).to_bits(), w, "{num}/{den}");
            assert_eq!(ratio_raw(num, den, div_words_native), w, "native {num}/{den}");
            assert_eq!(ratio_raw(num, den, div_words_hw32), w, "hw32 {num}/{den}");
            assert_eq!(ratio_raw(num, den, div_words_reciprocal), w, "reciprocal {num}/{den}");
        }
        assert_eq!(Fixed32::ratio(5, 0).to_bits(), RAW_MAX);
    }

    #[test]
    fn ratio_by_a_divisor_is_ratio() {
        // Every numerator up to 2·den + 3 for small divisors, image-sized
        // ones, saturating quotients, the 2¹⁶ limits, and the wide product
        // of every target (`wmul` here, the limb product of Armv6-M).
        let check = |num: u32, den: u32| {
            let want = Fixed32::ratio(num, den).to_bits();
            assert_eq!(Fixed32::ratio_by(num, &Divisor::new(den)).to_bits(), want, "{num}/{den}");
            assert_eq!(Fixed32::ratio_by(num, &Divisor::plain(den)).to_bits(), want, "plain {num}/{den}");
            let limbs = Divisor::new(den).rounded_q24(num, |a, b| (wmul_limbs(a, b) >> 32) as u32);
            if let Some(q) = limbs {
                assert_eq!(q as i32, want, "limbs {num}/{den}");
            }
        };
        for den in 0..=300u32 {
            for num in 0..=2 * den + 3 {
                check(num, den);
            }
            check(den << 7, den);
            check((den << 7).saturating_sub(1), den);
        }
        let mut rng = Rng(0x5eed_0f7a_7100_0003);
        for k in 0..300_000u32 {
            let den = if k % 2 == 0 { 1 + rng.u32() % 0xFFFF } else { 1 + rng.u32() % 4096 };
            let num = match k % 3 {
                0 => rng.u32() % (2 * den + 1),
                1 => rng.u32() % (1 << 16),
                _ => rng.u32() >> (rng.u32() % 32),
            };
            check(num, den);
        }
        for (num, den) in [
            (0xFFFF, 0xFFFF),
            (0xFFFF, 1),
            (0xFFFF, 0x1_0000),
            (0x1_0000, 0xFFFF),
            (1, 0xFFFF),
            (0xFFFF, 0xFFFE),
            (0xFFFE, 0xFFFF),
        ] {
            check(num, den);
        }
    }

    #[test]
    fn to_f32_is_the_scaled_conversion_bit_for_bit() {
        // The exponent-field form against `raw as f32 · 2⁻²⁴`, on the
        // extremes, every power of two and seeded random raws.
        let check = |raw: i32| {
            let want = raw as f32 * (1.0 / RAW_ONE as f32);
            let got = Fixed32::from_bits(raw).to_f32();
            assert_eq!(got.to_bits(), want.to_bits(), "raw {raw}");
        };
        for raw in [0, 1, -1, 2, -2, RAW_MAX, RAW_MIN, i32::MIN, i32::MAX, RAW_ONE, -RAW_ONE, 0x00FF_FFFF, 0x0100_0001]
        {
            check(raw);
        }
        for k in 0..31 {
            check(1 << k);
            check(-(1 << k));
            check((1 << k) + 1);
            check((1i32 << k).wrapping_sub(1));
        }
        let mut rng = Rng(0x0f32_70f3_2000_0001);
        for _ in 0..1_000_000 {
            check(rng.raw());
            check(rng.u32() as i32);
        }
    }

    /// xorshift64*, seeded: operands for the property tests.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
        }
        fn u32(&mut self) -> u32 {
            (self.next() >> 32) as u32
        }
        /// Raw operands: extremes, small values, values near one and near
        /// the saturation thresholds, and random bits at every magnitude.
        fn raw(&mut self) -> i32 {
            let special = [
                0,
                1,
                -1,
                2,
                RAW_MAX,
                RAW_MIN,
                RAW_MAX - 1,
                i32::MIN,
                RAW_ONE,
                -RAW_ONE,
                RAW_ONE - 1,
                RAW_ONE + 1,
                RAW_ONE / 2,
                1 << 30,
                -(1 << 30),
                1 << 15,
                46_341 << 12,
                0xB504,
            ];
            let r = self.u32();
            match self.next() % 5 {
                0 => special[(self.next() % special.len() as u64) as usize],
                1 => (r as i32) >> (self.next() % 32),
                2 => RAW_ONE.wrapping_add((r as i32) >> 12),
                // Near √MAX, where products cross the saturation threshold.
                3 => (0xB504_F333u32 >> ((32 - FRAC) / 2)) as i32 + ((r as i32) >> 20),
                _ => r as i32,
            }
        }
    }

    fn clamp(v: i128) -> i32 {
        v.clamp(RAW_MIN as i128, RAW_MAX as i128) as i32
    }

    #[test]
    fn constants() {
        assert_eq!(Fixed32::ONE.to_f64(), 1.0);
        assert_eq!(Fixed32::HALF.to_f64(), 0.5);
        assert_eq!(Fixed32::TWO.to_f64(), 2.0);
        assert_eq!(Fixed32::MIN_WEIGHT.to_f64(), 1.0 / 512.0);
        assert_eq!(Fixed32::MAX.to_f64(), (1u64 << (31 - FRAC)) as f64 - ULP);
        assert_eq!(Fixed32::RAY_EPSILON, Fixed32::from_f32(1.0e-4));
        assert_eq!(Fixed32::RAY_EPSILON, fx(1.0e-4));
        assert_eq!(COORDINATE_LIMIT, 2.0);
        // The box rule: 12·R² within half the range.
        let r = COORDINATE_LIMIT as f64;
        assert!(12.0 * r * r <= Fixed32::MAX.to_f64() / 2.0 && 12.0 * 4.0 * r * r > Fixed32::MAX.to_f64() / 2.0);
    }

    #[test]
    fn integer_conversions_and_floor() {
        assert_eq!(Fixed32::from_i32(-7).to_f64(), -7.0);
        assert_eq!(Fixed32::from_i32(127), fx(127.0));
        assert_eq!(Fixed32::from_i32(128), Fixed32::MAX);
        assert_eq!(Fixed32::from_i32(i32::MIN), -Fixed32::MAX);
        assert_eq!(Fixed32::from_i32(i32::MAX), Fixed32::MAX);
        assert_eq!(fx(1.5).floor_to_i32(), 1);
        assert_eq!(fx(-1.5).floor_to_i32(), -2);
        assert_eq!(Fixed32::from_bits(-1).floor_to_i32(), -1);
        assert_eq!(Fixed32::MAX.floor_to_i32(), RAW_MAX >> FRAC);
        assert_eq!(Fixed32::from_bits(i32::MIN).to_bits(), i32::MIN);
        assert_eq!(Fixed32::from_bits(i32::MIN).floor_to_i32(), -128);
        assert!(Fixed32::MAX.is_finite());
    }

    #[test]
    fn from_f32_edge_cases() {
        assert_eq!(Fixed32::from_f32(f32::NAN), Fixed32::ZERO);
        assert_eq!(Fixed32::from_f32(-f32::NAN), Fixed32::ZERO);
        assert_eq!(Fixed32::from_f32(f32::INFINITY), Fixed32::MAX);
        assert_eq!(Fixed32::from_f32(f32::NEG_INFINITY), -Fixed32::MAX);
        assert_eq!(Fixed32::from_f32(0.0), Fixed32::ZERO);
        assert_eq!(Fixed32::from_f32(-0.0), Fixed32::ZERO);
        assert_eq!(Fixed32::from_f32(f32::MIN_POSITIVE), Fixed32::ZERO);
        assert_eq!(Fixed32::from_f32(1.0e-45), Fixed32::ZERO);
        assert_eq!(Fixed32::from_f32(3.0e38), Fixed32::MAX);
        assert_eq!(Fixed32::from_f32(-3.0e38), -Fixed32::MAX);
        assert_eq!(Fixed32::from_f32(128.0), Fixed32::MAX);
        assert_eq!(Fixed32::from_f32(-128.0), -Fixed32::MAX);
        assert_eq!(Fixed32::from_f32(127.99999), fx(127.99999237060547));
        assert_eq!(Fixed32::from_f32(-2.5).to_f32(), -2.5);
        // Exact halves of an ulp round away from zero; just below rounds down.
        let half = 0.5 * ULP as f32;
        assert_eq!(Fixed32::from_f32(half).to_bits(), 1);
        assert_eq!(Fixed32::from_f32(-half).to_bits(), -1);
        assert_eq!(Fixed32::from_f32(half * 0.999_999).to_bits(), 0);
        assert_eq!(Fixed32::from_f32(1.5 * ULP as f32).to_bits(), 2);
        assert_eq!(Fixed32::from_f32(2.5 * ULP as f32).to_bits(), 3);
        // 0.1f32 = 13421773·2⁻²⁷ → 13421773/8 = 1677721.625 → 1677722.
        assert_eq!(Fixed32::from_f32(0.1).to_bits(), 1_677_722);
    }

    /// `from_f32` against the f64 reference (exact for every f32) over every
    /// exponent with edge and random mantissas, both signs.
    #[test]
    fn from_f32_matches_f64_reference() {
        let mut rng = Rng(0xF32);
        let check = |bits: u32| {
            let v = f32::from_bits(bits);
            assert_eq!(Fixed32::from_f32(v), Fixed32::from_f64(v as f64), "{v:e} ({bits:#x})");
        };
        for exp in 0..=255u32 {
            for man in [0, 1, 2, 0x40_0000, 0x7F_FFFF, 0x7F_FFFE, 0x3F_FFFF, 0x40_0001] {
                check(exp << 23 | man);
                check(1 << 31 | exp << 23 | man);
            }
            for _ in 0..2_000 {
                let man = rng.u32() & 0x7F_FFFF;
                check(exp << 23 | man | (rng.u32() & (1 << 31)));
            }
        }
        for _ in 0..1_000_000 {
            check(rng.u32());
        }
    }

    #[test]
    fn clz_soft_matches_hardware() {
        assert_eq!(clz_soft(0), 31);
        let mut rng = Rng(3);
        for s in 0..32 {
            let x = 1u32 << s;
            assert_eq!(clz_soft(x), x.leading_zeros());
            assert_eq!(clz_soft(x | (x - 1)), x.leading_zeros());
        }
        for _ in 0..100_000 {
            let x = rng.u32() >> (rng.u32() % 32);
            if x != 0 {
                assert_eq!(clz_soft(x), x.leading_zeros(), "{x:#x}");
            }
        }
    }

    #[test]
    fn wide_products_agree() {
        let mut rng = Rng(0x11AB);
        let edges = [0, 1, 0xFFFF, 0x1_0000, 0x8000_0000, 0xFFFF_FFFF, 0x7FFF_FFFF, 0xFFFF_0000, 0x0000_FFFF];
        for &a in &edges {
            for &b in &edges {
                assert_eq!(wmul_limbs(a, b), wmul_native(a, b), "{a:#x}·{b:#x}");
            }
        }
        for _ in 0..1_000_000 {
            let (a, b) = (rng.u32(), rng.u32());
            assert_eq!(wmul_limbs(a, b), wmul_native(a, b), "{a:#x}·{b:#x}");
            let w = a & 0xFFFF;
            assert_eq!(mul16x32_halves(w, b), wmul_native(w, b));
            assert_eq!(mul16x32(w, b), wmul_native(w, b));
        }
    }

    /// The exact product rounded half up and clamped, from `i128`.
    fn mul_reference(a: i32, b: i32) -> i32 {
        clamp((a as i128 * b as i128 + (1 << (FRAC - 1))).div_euclid(1 << FRAC))
    }

    /// All three products (64-bit host, two words, Armv6-M limbs) against
    /// the exact reference.
    fn check_mul(a: i32, b: i32) {
        let want = mul_reference(a, b);
        assert_eq!(mul_raw_native(a, b), want, "{a} * {b}");
        assert_eq!(mul_raw_words(a, b), want, "{a} * {b} (words)");
        assert_eq!(mul_raw_limbs(a, b), want, "{a} * {b} (limbs)");
    }

    /// Products at the two-word form's range test (`|a·b|` about
    /// `2^(54)`, a result about ±64, where it hands over to the exact clamp),
    /// and where `⌊p/2²³⌋` reaches `i32`'s ends, give the exact product.
    #[test]
    fn word_products_at_their_range_test_are_exact() {
        let mut rng = Rng(0x2054);
        for _ in 0..200_000 {
            let a = (rng.u32() >> (rng.u32() % 16)) as i32 | 1;
            for target in [1i64 << 54, (1i64 << 54) - (1 << 23), 1i64 << 53] {
                let b = (target / a as i64) as i32;
                for k in -2..=2 {
                    let b = b.saturating_add(k);
                    for (a, b) in [(a, b), (-a, b), (a, -b), (-a, -b)] {
                        check_mul(a, b);
                    }
                }
            }
        }
    }

    /// The Armv6-M product, the two-word one and the portable one give the
    /// same bits, and all match the exact product rounded half up, on edge
    /// cases and millions of seeded pairs (including i32::MIN raws, which
    /// `from_bits` never lets through, and pairs near the saturation
    /// threshold).
    #[test]
    fn mul_variants_agree_and_round_half_up() {
        let mut rng = Rng(0x5EED);
        let check = check_mul;
        let edges = [
            0,
            1,
            -1,
            2,
            -2,
            RAW_MAX,
            RAW_MIN,
            i32::MIN,
            RAW_ONE,
            -RAW_ONE,
            RAW_ONE / 2,
            -RAW_ONE / 2,
            0x0B50_4F33,
            -0x0B50_4F33,
            0x0B50_4F34,
            0xFFFF,
            0x10000,
            -0x10000,
            // Limb boundaries: the low limb's top bit, the high limb's
            // extremes.
            0x7FFF,
            0x8000,
            -0x8000,
            0x7FFF_8000,
            -0x7FFF_8000,
            0x7FFF_0000,
            0x8000_FFFFu32 as i32,
            // ±64 and ±2 (their product is the first past the fast path),
            // and their neighbours.
            1 << 30,
            -(1 << 30),
            (1 << 30) - 1,
            1 - (1 << 30),
            2 * RAW_ONE,
            -2 * RAW_ONE,
        ];
        for &a in &edges {
            for &b in &edges {
                check(a, b);
            }
        }
        for _ in 0..3_000_000 {
            check(rng.raw(), rng.raw());
        }
        // Ties: ±½ ulp products go up.
        assert_eq!((Fixed32::from_bits(1) * Fixed32::HALF).to_bits(), 1);
        assert_eq!((Fixed32::from_bits(-1) * Fixed32::HALF).to_bits(), 0);
        assert_eq!((Fixed32::from_bits(3) * Fixed32::HALF).to_bits(), 2);
        assert_eq!((Fixed32::from_bits(-3) * Fixed32::HALF).to_bits(), -1);
    }

    /// The Armv6-M product's cross sum `C₁' + C₂` overflows 32 bits on its
    /// fast path only for one operand near ±128 and the other below 1 in
    /// magnitude; there the product takes the exact path. Seeded pairs of
    /// that shape (thousands of them overflow) against the reference.
    #[test]
    fn limbs_cross_sum_past_32_bits_takes_the_exact_path() {
        let mut rng = Rng(0xC4A7);
        let mut overflowing = 0;
        for _ in 0..400_000 {
            // `a` near ±128 (a high limb of −2¹⁵ or 2¹⁵ − 1), `b` below ½ in
            // magnitude with a low limb near 2¹⁶ (so `|C₁|` nears 2³¹).
            let near = (rng.u32() >> (16 + rng.u32() % 16)) as i32;
            let a = if rng.u32() & 1 == 0 { i32::MIN.wrapping_add(near) } else { i32::MAX - near };
            let bh = (rng.u32() % 255) as i32 - 127;
            let bl = 0xFFFF - (rng.u32() >> (16 + rng.u32() % 16)) as i32;
            let b = (bh << 16) | bl;
            for (a, b) in [(a, b), (b, a)] {
                let (ah, bh, al, bl) = (a >> 16, b >> 16, a & 0xFFFF, b & 0xFFFF);
                let l = (al as u32).wrapping_mul(bl as u32);
                let c1 = ah.wrapping_mul(bl).wrapping_add((l >> 16) as i32).wrapping_add((HALF_ULP >> 16) as i32);
                let fast = (ah * bh) >> (FRAC - 2) == (ah * bh) >> 31;
                overflowing += (fast && c1.overflowing_add(al.wrapping_mul(bh)).1) as u32;
                check_mul(a, b);
            }
        }
        assert!(overflowing > 10_000, "{overflowing} pairs overflowed the cross sum");
    }

    /// The Armv6-M square equals the product of a value by itself rounded
    /// half up: every high limb (so both sides of the fast path's bound,
    /// `|aₕ| = 2¹¹`, and the saturation at 128) with the low limbs at their
    /// edges and seeded ones, and `i32::MIN`.
    #[test]
    fn square_limbs_is_the_product_by_itself() {
        let mut rng = Rng(0x5A0A);
        let want = |a: i32| mul_reference(a, a);
        assert_eq!(square_raw_limbs(i32::MIN), want(i32::MIN));
        for ah in -(1i32 << 15)..(1 << 15) {
            let seeded = [rng.u32() & 0xFFFF, rng.u32() & 0xFFFF, rng.u32() >> 16];
            for al in [0, 1, 0x7F, 0x80, 0x7FFF, 0x8000, 0x8001, 0xFFFE, 0xFFFF].into_iter().chain(seeded) {
                let a = (ah << 16) | al as i32;
                assert_eq!(square_raw_limbs(a), want(a), "{a}²");
            }
        }
        for _ in 0..1_000_000 {
            let a = (rng.u32() >> (rng.u32() % 20)) as i32;
            let a = if rng.u32() & 1 == 0 { a } else { a.wrapping_neg() };
            assert_eq!(square_raw_limbs(a), want(a), "{a}²");
            assert_eq!(Fixed32(a).square(), Fixed32(a) * Fixed32(a));
        }
    }

    /// The wrapping sum (`add_small`) is the saturating one for sums up to
    /// 64 in magnitude, and a dot product of unit components stays far
    /// inside that.
    #[test]
    fn small_sums_are_the_saturating_ones() {
        let mut rng = Rng(0xADD5);
        let bound = 64i32 << FRAC;
        for _ in 0..1_000_000 {
            let a = (rng.u32() as i32) >> (rng.u32() % 8);
            let b = (rng.u32() as i32) >> (rng.u32() % 8);
            let (fa, fb) = (Fixed32(a), Fixed32(b));
            if (a as i64 + b as i64).abs() <= bound as i64 {
                assert_eq!(fa.add_small(fb), fa + fb, "{a} + {b}");
            }
        }
        // Three products of components at most 4: at most 48.
        let four = Fixed32::from_f32(4.0);
        let p = four.mul_small(four);
        assert_eq!(p.add_small(p).add_small(p), p + p + p);
        let m = -p;
        assert_eq!(m.add_small(m).add_small(m), m + m + m);
    }

    /// The products without range tests equal the product for operands
    /// at most 4 in magnitude, the bound itself included: the Armv6-M limbs
    /// and the 32-bit targets' words (both tested here on the host), and
    /// the portable form.
    #[test]
    fn small_products_are_the_product_up_to_four() {
        let mut rng = Rng(0x5A11);
        let edge = SMALL;
        let edges = [0, 1, -1, 0xFFFF, 0x10000, -0x10000, RAW_ONE, -RAW_ONE, edge, -edge, edge - 0xFFFF, 1 - edge];
        let seeded = (0..1_000_000).map(|_| {
            let a = (rng.u32() >> (6 + rng.u32() % 24)) as i32;
            if rng.u32() & 1 == 0 {
                a
            } else {
                -a
            }
        });
        let all: Vec<i32> = edges.into_iter().chain(seeded).collect();
        for w in all.windows(2) {
            let (a, b) = (w[0], w[1]);
            for (a, b) in [(a, b), (a, edges[(b & 7) as usize + 4])] {
                let want = mul_reference(a, b);
                assert_eq!(mul_limbs_small(a, b), want, "{a} * {b} (limbs)");
                assert_eq!(mul_words_small(a, b), want, "{a} * {b} (words)");
                assert_eq!(mul_raw_small(a, b), want, "{a} * {b}");
            }
            assert_eq!(mul_words_small(a, a), mul_reference(a, a), "{a}² (words)");
            assert_eq!(square_limbs_fast(a, (a >> 16) * (a >> 16)), mul_reference(a, a), "{a}² (limbs)");
            assert_eq!(square_raw_small(a), mul_reference(a, a), "{a}²");
        }
    }

    /// The shorter normalisation gives the general code's bits wherever it
    /// answers, and answers for every vector from 2⁻⁷ up (top bit 17 …
    /// 30); zero, tiny vectors and `i32::MIN` go to the general code.
    #[test]
    fn unit_and_length_is_the_general_normalisation() {
        use crate::geom::vec3::Vec3;
        let mut rng = Rng(0x0417);
        let mut answered = 0;
        for i in 0..300_000 {
            // Every magnitude: a random shift per component, some zeros.
            let mut c = [0i32; 3];
            for v in c.iter_mut() {
                let r = (rng.u32() >> (1 + rng.u32() % 31)) as i32;
                *v = match rng.u32() % 8 {
                    0 => 0,
                    1 => -r,
                    _ => r,
                };
            }
            if i == 0 {
                c = [RAW_MIN, 0, 0];
            }
            let v = Vec3::new(Fixed32(c[0]), Fixed32(c[1]), Fixed32(c[2]));
            let packet: crate::geom::vec3::Vec3xW<Fixed32, 1> = v.splat();
            let (n, len, ok) = packet.normalize_general::<false>();
            let top = 31 - c.iter().map(|c| c.unsigned_abs()).max().unwrap_or(0).leading_zeros() as i32;
            match unit_and_length_raw(c) {
                Some((fast_n, fast_len)) => {
                    answered += 1;
                    assert!((17..=30).contains(&top), "{c:?}");
                    assert!(ok.get(0), "{c:?}");
                    assert_eq!(fast_n, [n.x.0[0].0, n.y.0[0].0, n.z.0[0].0], "{c:?}");
                    assert_eq!(fast_len, len.0[0].0, "{c:?}");
                }
                None => assert!(!(17..=30).contains(&top) || c.contains(&i32::MIN), "{c:?}"),
            }
        }
        assert!(answered > 200_000, "{answered}");
    }

    /// Two quotients by one divisor equal two divisions: seeded operands of
    /// every magnitude and sign, zero divisors and numerators, saturation.
    #[test]
    fn div_pair_is_two_divisions() {
        let mut rng = Rng(0xD1F2);
        let any = |rng: &mut Rng| {
            let v = (rng.u32() >> (rng.u32() % 32)) as i32;
            if rng.u32() & 1 == 0 {
                v
            } else {
                -v
            }
        };
        for i in 0..500_000 {
            let (a1, a2) = (any(&mut rng), if i % 7 == 0 { 0 } else { any(&mut rng) });
            let b = if i % 101 == 0 { 0 } else { any(&mut rng) };
            assert_eq!(div2_raw(a1, a2, b), (div_raw(a1, b), div_raw(a2, b)), "{a1}, {a2} / {b}");
            let (ra, rb) = (Fixed32(a1), Fixed32(a2));
            let one = |v: Fixed32| crate::num::lanes::Lanes([v]);
            let (p, q) = one(ra).div_pair_nonzero(one(rb), one(Fixed32(b)));
            let d = if b == 0 { Fixed32::ONE } else { Fixed32(b) };
            assert_eq!((p.0[0], q.0[0]), (ra / d, rb / d));
        }
    }

    /// Products next to every threshold of the two-word rounding: ±64 (where
    /// the fast range test hands over to the exact clamp), ±128 (saturation)
    /// and exactly −128 (raw `i32::MIN`, which must become `−MAX`), from
    /// seeded operands of every magnitude and their exact cofactors ± a few
    /// ulps.
    #[test]
    fn mul_is_exact_at_the_rounding_thresholds() {
        let mut rng = Rng(0x7A6);
        // −128 exactly: −2³¹ raw.
        assert_eq!(mul_reference(-(1 << 30), 2 * RAW_ONE), RAW_MIN);
        check_mul(-(1 << 30), 2 * RAW_ONE);
        check_mul(1 << 30, -2 * RAW_ONE);
        for target in [-128i64, -64, 64, 128] {
            let product = target << (2 * FRAC); // the exact a·b wanted
            for _ in 0..200_000 {
                // |a| from 2^(FRAC−4) up, so that the cofactor fits.
                let a = (rng.u32() >> (rng.u32() % 8)) as i32 | (1 << (FRAC - 4));
                let a = if rng.u32() & 1 == 0 { a } else { -a };
                let b = product / a as i64;
                for d in -3..=3 {
                    if let Ok(b) = i32::try_from(b + d) {
                        check_mul(a, b);
                        check_mul(b, a);
                    }
                }
            }
        }
    }

    #[test]
    fn add_sub_neg_exact_and_saturating() {
        assert_eq!(fx(1.5) + fx(2.25), fx(3.75));
        assert_eq!(fx(1.5) - fx(2.25), fx(-0.75));
        assert_eq!(Fixed32::MAX + Fixed32::ONE, Fixed32::MAX);
        assert_eq!(Fixed32::MAX - -Fixed32::MAX, Fixed32::MAX);
        assert_eq!((-Fixed32::MAX).to_bits(), RAW_MIN);
        assert_eq!((-Fixed32::MAX).abs(), Fixed32::MAX);
        // Sums and differences reach the bottom value −2⁷ (raw i32::MIN)
        // and saturate there; negation and abs take it to MAX.
        let bottom = Fixed32::from_bits(i32::MIN);
        assert_eq!(-Fixed32::MAX - Fixed32::from_bits(1), bottom);
        assert_eq!(-Fixed32::MAX - Fixed32::ONE, bottom);
        assert_eq!(-Fixed32::MAX - Fixed32::MAX, bottom);
        assert_eq!(-Fixed32::MAX + -Fixed32::from_bits(1), bottom);
        assert_eq!(bottom + Fixed32::from_bits(1), -Fixed32::MAX);
        assert_eq!(-bottom, Fixed32::MAX);
        assert_eq!(bottom.abs(), Fixed32::MAX);
        assert!(bottom < -Fixed32::MAX);
        // i32's saturating sum and difference of the exact values.
        let sat = |v: i128| v.clamp(i32::MIN as i128, i32::MAX as i128) as i32;
        let mut rng = Rng(77);
        for _ in 0..1_000_000 {
            let (a, b) = (Fixed32::from_bits(rng.raw()), Fixed32::from_bits(rng.raw()));
            let (ea, eb) = (a.to_bits() as i128, b.to_bits() as i128);
            assert_eq!((a + b).to_bits(), sat(ea + eb));
            assert_eq!((a - b).to_bits(), sat(ea - eb));
            assert_eq!((-a).to_bits(), clamp(-ea));
            assert_eq!(a.abs().to_bits(), clamp(ea.abs()));
            assert_eq!(a < b, ea < eb);
            assert_eq!(a.cmp(&b), ea.cmp(&eb));
        }
    }

    /// The exact reference: `round(a·2^FRAC/b)`, ties away from zero, clamped.
    fn div_reference(a: i32, b: i32) -> i32 {
        if b == 0 {
            return if a > 0 {
                RAW_MAX
            } else if a < 0 {
                RAW_MIN
            } else {
                0
            };
        }
        let (n, d) = ((a as i128) << FRAC, b as i128);
        let (q, r) = (n / d, n % d); // truncated: r has n's sign
        let q = if 2 * r.abs() >= d.abs() { q + if (n < 0) == (d < 0) { 1 } else { -1 } } else { q };
        clamp(q)
    }

    #[test]
    fn div_is_correctly_rounded() {
        assert_eq!(fx(-3.375) / fx(1.5), fx(-2.25));
        assert_eq!((fx(1.0) / fx(3.0)).to_bits(), (RAW_ONE + 1) / 3);
        assert_eq!((fx(2.0) / fx(3.0)).to_bits(), div_reference(2 * RAW_ONE, 3 * RAW_ONE));
        assert_eq!(fx(3.0) / Fixed32::ZERO, Fixed32::MAX);
        assert_eq!(fx(-3.0) / Fixed32::ZERO, -Fixed32::MAX);
        assert_eq!(Fixed32::ZERO / Fixed32::ZERO, Fixed32::ZERO);
        assert_eq!(Fixed32::MAX / fx(-1.0), -Fixed32::MAX);
        assert_eq!((-Fixed32::MAX) / fx(-1.0), Fixed32::MAX);
        assert_eq!(Fixed32::ONE / Fixed32::from_bits(1), Fixed32::MAX);
        // Ties: 1 ulp / 2 = ½ ulp → 1 ulp, and −½ ulp → −1 ulp (away from 0).
        assert_eq!((Fixed32::from_bits(1) / Fixed32::TWO).to_bits(), 1);
        assert_eq!((Fixed32::from_bits(-1) / Fixed32::TWO).to_bits(), -1);
        let mut rng = Rng(0xD1D);
        let check = |a: i32, b: i32| {
            let want = div_reference(a, b);
            assert_eq!(div_raw(a, b), want, "{a} / {b}");
            assert_eq!(div_raw_with(a, b, div_words_hw32), want, "{a} / {b} (hw32)");
            assert_eq!(div_raw_with(a, b, div_words_reciprocal), want, "{a} / {b} (reciprocal)");
            if b.unsigned_abs() < SHORT_DIVISOR_LIMIT {
                assert_eq!(div_raw_short(a, b), want, "{a} / {b} (short)");
            }
        };
        let edges = [
            0,
            1,
            -1,
            2,
            3,
            RAW_MAX,
            RAW_MIN,
            i32::MIN,
            RAW_ONE,
            -RAW_ONE,
            RAW_ONE - 1,
            RAW_ONE + 1,
            1 << 30,
            (1 << 30) + 1,
            0x7FFF,
            0x8000,
            0xFFFF,
            0x1_0000,
            0x1_0001,
            RAW_MAX >> (31 - FRAC),
            (RAW_MAX >> (31 - FRAC)) + 1,
            SHORT_DIVISOR_LIMIT as i32 - 1,
            SHORT_DIVISOR_LIMIT as i32,
            1 - SHORT_DIVISOR_LIMIT as i32,
            -(SHORT_DIVISOR_LIMIT as i32),
        ];
        for &a in &edges {
            for &b in &edges {
                check(a, b);
            }
        }
        for _ in 0..2_000_000 {
            let (a, b) = (rng.raw(), rng.raw());
            check(a, b);
            // Divisors of every magnitude below the short division's limit.
            check(a, b >> (rng.u32() % 32));
            // Quotients near the saturation threshold: b ≈ a/2^(31−FRAC).
            let b2 = (a >> (31 - FRAC)).wrapping_add((rng.u32() % 5) as i32 - 2);
            check(a, b2);
        }
    }

    /// The three two-word divisions agree with `u64` division, on edge
    /// cases and random normalised divisors and numerators.
    #[test]
    fn two_word_divisions_agree() {
        let mut rng = Rng(0x2D1);
        let check = |u1: u32, u0: u32, d: u32| {
            let n = ((u1 as u64) << 32) | u0 as u64;
            let want = ((n / d as u64) as u32, (n % d as u64) as u32);
            assert_eq!(div_words_native(u1, u0, d), want);
            assert_eq!(div_words_hw32(u1, u0, d), want, "hw32 {u1:#x}:{u0:#x} / {d:#x}");
            assert_eq!(div_words_reciprocal(u1, u0, d), want, "reciprocal {u1:#x}:{u0:#x} / {d:#x}");
        };
        for d in [0x8000_0000u32, 0x8000_0001, 0xFFFF_FFFF, 0xFFFF_0000, 0x8000_FFFF, 0xC000_0000, 0xFFFE_0001] {
            for u1 in [0, 1, d >> 1, d - 1, d - 2, 0x7FFF_FFFF.min(d - 1)] {
                for u0 in [0, 1, 0xFFFF, 0x1_0000, 0x8000_0000, u32::MAX] {
                    check(u1, u0, d);
                }
            }
        }
        for i in 0..2_000_000u32 {
            let d = rng.u32() | 0x8000_0000;
            let d = match i % 4 {
                0 => d | 0xFFFF,
                1 => d & 0xFFFF_0000,
                _ => d,
            };
            let u1 = match i % 3 {
                0 => d - 1 - (rng.u32() & 0xFF).min(d - 1),
                1 => rng.u32() % d,
                _ => (rng.u32() >> (rng.u32() % 32)) % d,
            };
            check(u1, rng.u32(), d);
        }
    }

    /// The 16-bit reciprocal for every input: a lower bound of 2³²/dh
    /// within 4 units (what the digit estimates rely on).
    #[test]
    fn reciprocal16_is_a_tight_lower_bound() {
        let mut worst = 0;
        for dh in (1u32 << 15) + 1..=1 << 16 {
            let w = (1u64 << 16) + reciprocal16(dh) as u64;
            assert!(w * dh as u64 <= 1 << 32, "{dh}: W = {w} too large");
            let gap = (1u64 << 32) / dh as u64 - w;
            worst = worst.max(gap);
        }
        assert!(worst <= 4, "reciprocal16 up to {worst} units low");
    }

    fn sqrt_ok(raw: i32) {
        let r = Fixed32::from_bits(raw).sqrt().to_bits() as i128;
        if raw <= 0 {
            assert_eq!(r, 0);
            return;
        }
        // (r − ½)² ≤ n < (r + ½)², i.e. (2r − 1)² ≤ 4n < (2r + 1)².
        let n = (raw as i128) << FRAC;
        assert!((2 * r - 1) * (2 * r - 1) <= 4 * n && 4 * n < (2 * r + 1) * (2 * r + 1), "sqrt({raw}) = {r}");
    }

    #[test]
    fn inverse_sqrt_is_within_half_a_unit_and_two_to_the_minus_27() {
        // |r − 2³⁶/√raw| ≤ ½ + 2⁻²⁷·2³⁶/√raw (the exact value saturated at
        // RAW_MAX): at most 0.6 of a unit for squared lengths of ¼ and up,
        // where the normalisation uses it.
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let seeded = (0..200_000).map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            // Spread over every magnitude: a random mantissa, a random shift.
            ((x >> 33) as u32 >> ((x & 31) as u32)).max(1) as i32
        });
        let edges = (0..31).flat_map(|k| [(1i32 << k) - 1, 1 << k, (1 << k) + 1]).filter(|&a| a > 0);
        let sweep = (1u32 << 10..RAW_MAX as u32).step_by(9_973).map(|a| a as i32);
        for raw in (1..4096).chain(edges).chain(seeded).chain(sweep).chain([RAW_MAX, RAW_ONE, 3 * RAW_ONE]) {
            let r = Fixed32::from_bits(raw).inverse_sqrt().to_bits() as f64;
            let exact = 2f64.powi(36) / (raw as f64).sqrt();
            let err = (r - exact.min(RAW_MAX as f64)).abs();
            assert!(err <= 0.5 + exact * 2f64.powi(-27), "inverse_sqrt({raw}) = {r}, off by {err} units");
            if raw >= 1 << 22 {
                assert!(err <= 0.6, "inverse_sqrt({raw}) = {r}, off by {err} units");
            }
        }
        assert_eq!(Fixed32::from_bits(0).inverse_sqrt(), Fixed32::MAX);
        assert_eq!(Fixed32::from_bits(-5).inverse_sqrt(), Fixed32::MAX);
        assert_eq!(Fixed32::ONE.inverse_sqrt(), Fixed32::ONE);
        assert_eq!(Fixed32::from_f32(4.0).inverse_sqrt(), Fixed32::HALF);
    }

    #[test]
    fn the_unit_range_reciprocal_root_is_the_general_one() {
        // Every a near the ends and the 2²⁴ boundary, and a sweep between.
        let near = |c: u32| c - 4096..c + 4096;
        let ends = near(1 << 24).chain((1 << 22)..(1 << 22) + 4096).chain((1 << 26) - 4096..1 << 26);
        for a in ends.chain(((1 << 22)..(1 << 26)).step_by(97)) {
            assert_eq!(rsqrt_raw_unit(a), rsqrt_raw(a), "{a}");
        }
    }

    #[test]
    fn sqrt_is_correctly_rounded() {
        for raw in (0..4096).chain([
            RAW_MAX,
            RAW_MAX - 1,
            RAW_ONE,
            RAW_ONE - 1,
            4 * RAW_ONE,
            -1,
            RAW_MIN,
            1 << 30,
            (1 << 30) - 1,
        ]) {
            sqrt_ok(raw);
        }
        for s in 0..31 {
            for delta in -3..=3 {
                sqrt_ok((1i32 << s).wrapping_add(delta));
            }
        }
        // Around perfect squares and the midpoints between them.
        for r in (1..46_341i64).step_by(97) {
            for n in [r * r, r * r + r, r * r + r + 1, r * r - 1] {
                if n >> FRAC > 0 && n <= RAW_MAX as i64 {
                    sqrt_ok(n as i32);
                }
            }
        }
        let mut rng = Rng(0x5C27);
        for _ in 0..1_000_000 {
            sqrt_ok(rng.raw());
        }
        assert_eq!(fx(4.0).sqrt(), fx(2.0));
        assert_eq!(fx(2.0).sqrt(), fx(core::f64::consts::SQRT_2));
        assert_eq!(fx(-4.0).sqrt(), Fixed32::ZERO);
    }

    /// All 2³¹ − 1 positive inputs (about a minute in release:
    /// `cargo test --release --lib exhaustive_sqrt -- --ignored`).
    #[test]
    #[ignore]
    fn exhaustive_sqrt() {
        for raw in 1..=RAW_MAX {
            sqrt_ok(raw);
        }
    }

    #[test]
    fn pow_table_matches_f64() {
        for (i, &t) in LOG2_STEP.iter().enumerate() {
            let want = libm::log2(1.0 + libm::exp2(-((i + 1) as f64))) * (1u64 << 30) as f64;
            assert!((t as f64 - want).abs() <= 0.5, "entry {i}: {t} vs {want}");
        }
        assert_eq!(INV_LN2_Q15, libm::round((1u64 << 15) as f64 / core::f64::consts::LN_2) as u32);
        assert_eq!(LN2_Q16, libm::round((1u64 << 16) as f64 * core::f64::consts::LN_2) as u32);
        for (i, &s) in RSQRT_SEED.iter().enumerate() {
            let y = (1u64 << 31) as f64 / libm::sqrt((i as f64 + 8.5) * (1u64 << 27) as f64);
            assert_eq!(s as f64, libm::round((y - 32768.0) / 128.0), "seed {i}");
        }
    }

    #[test]
    fn log2_and_exp2_pieces_are_accurate() {
        let mut worst_log: f64 = 0.0;
        for m in (0x8000_0000u32..=u32::MAX).step_by(4_099) {
            let got = log2_mantissa(m) as f64 / (1u64 << 30) as f64;
            worst_log = worst_log.max((got - libm::log2(m as f64 / (1u64 << 31) as f64)).abs());
        }
        assert!(worst_log < libm::exp2(-27.0), "log2 error {worst_log:e}");
        let mut worst_exp: f64 = 0.0;
        for f in (0..1u32 << 26).step_by(1_031) {
            let got = exp2_fraction(f) as f64 / (1u64 << 31) as f64;
            worst_exp = worst_exp.max((got - libm::exp2(f as f64 / (1u64 << 26) as f64)).abs());
        }
        assert!(worst_exp < libm::exp2(-26.0), "exp2 error {worst_exp:e}");
    }

    /// Every input of the two shift-and-add kernels (2³¹ mantissas, 2²⁶
    /// fractions): within their error bounds, and no overflow (run it with
    /// overflow checks: `CARGO_PROFILE_RELEASE_OVERFLOW_CHECKS=true cargo
    /// test --release --lib exhaustive_log2_exp2 -- --ignored`).
    #[test]
    #[ignore]
    fn exhaustive_log2_exp2() {
        for m in 0x8000_0000u32..=u32::MAX {
            let got = log2_mantissa(m) as f64 / (1u64 << 30) as f64;
            let want = libm::log2(m as f64 / (1u64 << 31) as f64);
            assert!((got - want).abs() < libm::exp2(-27.0), "log2 {m:#x}");
        }
        for f in 0..1u32 << 26 {
            let got = exp2_fraction(f) as f64 / (1u64 << 31) as f64;
            assert!((got - libm::exp2(f as f64 / (1u64 << 26) as f64)).abs() < libm::exp2(-26.0), "exp2 {f}");
        }
    }

    /// `powf` against f64 `pow` of the same (quantised) operands on a grid of
    /// x over (0, 1) (dense near 1, where large exponents are most
    /// sensitive) and e up to MAX: absolute error ≤ 2⁻¹⁹.
    #[test]
    fn powf_matches_f64_pow() {
        let mut worst: f64 = 0.0;
        let mut xs: Vec<i32> = (1..=RAW_ONE).step_by(4_093).collect();
        xs.extend((1..20_000).map(|k| RAW_ONE - k * 7));
        xs.extend((0..24).map(|s| 1 << s));
        let es: Vec<f64> =
            [0.001, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 5.0, 7.7, 10.0, 16.0, 20.0, 32.0, 50.0, 64.0, 100.0, 127.0, 127.99]
                .into_iter()
                .collect();
        for &x in &xs {
            for &e in &es {
                let (xf, ef) = (Fixed32::from_bits(x), fx(e));
                let want = libm::pow(xf.to_f64(), ef.to_f64());
                let got = xf.powf(ef).to_f64();
                worst = worst.max((got - want).abs());
                assert!((got - want).abs() <= libm::exp2(-19.0), "{xf}^{ef} = {got}, want {want}");
            }
        }
        assert!(worst > 0.0);
        assert_eq!(fx(0.5).powf(fx(2.0)), fx(0.25));
        assert_eq!(fx(0.5).powf(Fixed32::ZERO), Fixed32::ONE);
        assert_eq!(fx(0.5).powf(fx(-1.0)), Fixed32::ONE);
        assert_eq!(Fixed32::ZERO.powf(fx(3.0)), Fixed32::ZERO);
        assert_eq!(fx(-0.5).powf(fx(3.0)), Fixed32::ZERO);
        assert_eq!(Fixed32::ONE.powf(Fixed32::MAX), Fixed32::ONE);
        assert_eq!(fx(2.0).powf(fx(3.0)), Fixed32::ONE);
        assert_eq!(fx(0.5).powf(Fixed32::MAX), Fixed32::ZERO);
        // The integer algorithm and the f32 one agree to well under an 8-bit step.
        assert!((fx(0.8).powf(fx(12.5)).to_f64() - crate::num::unit_pow::powf_unit(0.8, 12.5) as f64).abs() < 1.0e-5);
    }

    #[test]
    fn display_is_shortest_round_trip() {
        assert_eq!(format!("{}", fx(0.1)), "0.1");
        assert_eq!(format!("{}", fx(-2.5)), "-2.5");
        assert_eq!(format!("{}", fx(3.0)), "3");
        assert_eq!(format!("{}", Fixed32::ZERO), "0");
        assert_eq!(format!("{:?}", fx(0.25)), "0.25");
        assert_eq!(format!("{:>6}", fx(1.5)), "   1.5");
        let mut rng = Rng(0xD15);
        for _ in 0..100_000 {
            let x = Fixed32::from_bits(rng.raw());
            let s = format!("{x}");
            let back: f64 = s.parse().unwrap();
            if x.to_bits() == i32::MIN {
                // −2⁷, which only sums reach: conversions saturate at −MAX.
                assert_eq!((s.as_str(), Fixed32::from_f64(back)), ("-128", -Fixed32::MAX));
                continue;
            }
            assert_eq!(Fixed32::from_f64(back), x, "{s}");
            // Shortest: one digit fewer does not round-trip.
            if let Some(dot) = s.find('.') {
                let digits = s.len() - dot - 1;
                let shorter = format!("{:.*}", digits - 1, back);
                assert_ne!(Fixed32::from_f64(shorter.parse().unwrap()), x, "{s} vs {shorter}");
            }
        }
        assert_eq!(format!("{}", Fixed32::MAX), format!("{}", Fixed32::MAX.to_f64()).get(..12).unwrap());
    }

    /// Nothing panics on any operands (overflow checks are on in tests).
    #[test]
    fn property_no_panics() {
        let mut rng = Rng(0xBADC0DE);
        for _ in 0..300_000 {
            let (a, b) = (Fixed32::from_bits(rng.raw()), Fixed32::from_bits(rng.raw()));
            let _ = (a + b, a - b, a * b, a / b, -a, a.abs(), a.sqrt(), a.floor_to_i32(), a.to_unorm8(), a.to_f32());
            let _ = a.abs().min(Fixed32::ONE).powf(b.abs());
            let _ = a.powf(b);
        }
    }

    /// `unit_dot_le`'s answers are those of the three small products it
    /// stands for (`Vec3xW::dot_splat_small`'s sum), for unit vectors,
    /// components at the bound 1.0625 and limits a few units from the
    /// product, where the margins are thinnest; and it settles most of them.
    #[test]
    fn unit_dot_estimate_agrees_with_the_products() {
        let mut rng = Rng(0x05ee_dd07);
        let bound = 17 << 20;
        let (mut settled, mut cases) = (0, 0);
        for i in 0..200_000 {
            let mut v = || -> [i32; 3] {
                match i % 4 {
                    // Components anywhere within the bound.
                    0 => core::array::from_fn(|_| (rng.raw() % (bound + 1)).max(-bound)),
                    // On the bound.
                    1 => core::array::from_fn(|_| if rng.raw() & 1 == 0 { bound } else { -bound }),
                    // Unit vectors.
                    _ => {
                        let w: [f64; 3] = core::array::from_fn(|_| (rng.raw() as f64) / (i32::MAX as f64));
                        let n = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt().max(1e-9);
                        core::array::from_fn(|k| Fixed32::from_f64(w[k] / n).0)
                    }
                }
            };
            let (a, b) = (v(), v());
            let p = (0..3).fold(0i32, |s, k| s.wrapping_add(mul_raw_small(a[k], b[k])));
            // Limits at and around the product, and anywhere in [−2, 2].
            let limit = match rng.raw() & 3 {
                0 => rng.raw() % (2 << FRAC),
                1 => p.saturating_add(rng.raw() % 4096),
                _ => p.saturating_add(rng.raw() % (1 << 16)),
            };
            let limit = limit.clamp(-(2 << FRAC), 2 << FRAC);
            cases += 1;
            if let Some(le) = unit_dot_le_raw(a, b, limit) {
                settled += 1;
                assert_eq!(le, p <= limit, "{a:?}·{b:?} = {p} against {limit}");
            }
        }
        assert!(settled > cases / 2, "{settled} of {cases}");
    }
}
