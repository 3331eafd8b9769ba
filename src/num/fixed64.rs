//! [`Fixed`]: the fixed-point [`Scalar`], a signed 32.32 number
//! (an `i64` raw value: 64-bit storage, 32 integer and 32 fractional
//! bits), for processors without a floating-point unit.
//!
//! # Why 32.32
//! A ray tracer's largest intermediates are squared lengths (`|o − c|²` in the
//! sphere test, `b² − 4ac` of a quadric) and its smallest are the last bits of
//! unit directions. 16.16 overflows at a squared distance of 32 768 (a scene
//! 100 units wide) and resolves directions only to 1.5·10⁻⁵; measured on the
//! demo scene it reaches 14.9 dB PSNR against `f32`. 32.32 keeps 2⁻³² ≈ 2.3·10⁻¹⁰
//! resolution (finer than `f32` near 1) and squares up to 2³¹ ≈ 2.1·10⁹, which
//! is what [`crate::geom::fixed_range`] budgets for.
//!
//! # Arithmetic (all total: nothing here can panic, in debug or release)
//! - Representable range: `[−MAX, MAX]` with `MAX = 2³¹ − 2⁻³²`; the raw value
//!   `i64::MIN` is never produced, so negation and `abs` are exact.
//! - `+`, `−`: exact, saturating to `±MAX`.
//! - `×`: the exact 128-bit product, rounded to nearest (ties towards +∞),
//!   saturating.
//! - `÷`: the exact 128-bit quotient, rounded to nearest (ties away from 0),
//!   saturating. `x / 0` is `MAX` for `x > 0`, `−MAX` for `x < 0`, and `0` for
//!   `0 / 0` (the tracer masks such lanes out before it uses them).
//! - `sqrt`: correctly rounded (integer square root of the 96-bit value
//!   `raw·2³²`, rounded to nearest); negative input gives 0.
//! - `powf`: `x^e = 2^(e·log₂x)` with `log₂` and `2^f` computed by integer
//!   bit-by-bit algorithms (squaring, and a table of `2^(2⁻ⁱ)`), no floating
//!   point: the same bits on every target.
//!
//! Conversions from `f32` (set-up time only) round to nearest, saturate, and
//! map NaN to 0.
//!
//! # Range limits
//! The tracer's largest intermediates are squared distances between two
//! scene points. With every coordinate of magnitude at most `R`, a difference
//! of two points has components up to `2R` and a squared length up to
//! `3·(2R)² = 12R²`. Keeping that below a quarter of the range
//! ([`INTERMEDIATE_LIMIT`] `= 2²⁹`, room for the sums it enters) gives
//! `R ≤ √(2²⁹/12) ≈ 6689`; the limit is the power of two below it,
//! [`COORDINATE_LIMIT`] `= 4096` (see [`crate::geom::fixed_range`] for the checks).

use crate::num::scalar::Scalar;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// Raw value of the largest representable number, `2³¹ − 2⁻³²`.
const RAW_MAX: i64 = i64::MAX;
/// Raw value of the smallest representable number, `−(2³¹ − 2⁻³²)`.
const RAW_MIN: i64 = -i64::MAX;
/// Number of fractional bits.
const FRAC: u32 = 32;
/// Raw value of one.
const RAW_ONE: i64 = 1 << FRAC;

/// Largest coordinate magnitude accepted for [`Fixed`] scenes (see the
/// module documentation for its derivation).
pub const COORDINATE_LIMIT: f32 = 4096.0;

/// Budget for a single intermediate of the kernels: a quarter of the 32.32
/// range, leaving room for the sums the intermediate enters.
pub const INTERMEDIATE_LIMIT: f32 = 536_870_912.0; // 2²⁹

/// A signed 32.32 fixed-point number: the [`Scalar`] for FPU-less targets.
///
/// See the module documentation for the exact semantics of every operation.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Hash, Default)]
#[repr(transparent)]
pub struct Fixed(i64);

impl core::fmt::Debug for Fixed {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(self, f)
    }
}

impl core::fmt::Display for Fixed {
    /// The value as the shortest decimal of its nearest `f64` (exact for raw
    /// values that fit 53 bits).
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Display::fmt(&self.to_f64(), f)
    }
}

/// Clamps a wide intermediate to the representable range.
#[cfg_attr(not(debug_assertions), inline(always))]
const fn saturate(v: i128) -> i64 {
    if v > RAW_MAX as i128 {
        RAW_MAX
    } else if v < RAW_MIN as i128 {
        RAW_MIN
    } else {
        v as i64
    }
}

impl Fixed {
    /// The number whose raw two's-complement bits are `raw` (value
    /// `raw·2⁻³²`); `i64::MIN` becomes `−MAX`.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub const fn from_bits(raw: i64) -> Self {
        Fixed(if raw == i64::MIN { RAW_MIN } else { raw })
    }
    /// The raw bits (value `raw·2⁻³²`).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub const fn to_bits(self) -> i64 {
        self.0
    }
    /// Converts from `f64` (rounded to nearest, saturating, NaN gives 0).
    /// For set-up and tests.
    pub fn from_f64(v: f64) -> Self {
        if v.is_nan() {
            return Fixed::from_bits(0);
        }
        // Scaling by a power of two is exact; `as` saturates.
        let scaled = libm::round(v * (RAW_ONE as f64));
        Fixed::from_bits((scaled as i64).max(RAW_MIN))
    }
    /// Converts to `f64` (exact for values whose raw bits fit 53 bits).
    pub fn to_f64(self) -> f64 {
        self.to_bits() as f64 / RAW_ONE as f64
    }
}

impl Add for Fixed {
    type Output = Self;
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn add(self, o: Self) -> Self {
        Fixed::from_bits(self.to_bits().saturating_add(o.to_bits()))
    }
}

impl Sub for Fixed {
    type Output = Self;
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn sub(self, o: Self) -> Self {
        Fixed::from_bits(self.to_bits().saturating_sub(o.to_bits()))
    }
}

impl Neg for Fixed {
    type Output = Self;
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn neg(self) -> Self {
        // Raw values lie in [−MAX, MAX], so this never overflows; saturating
        // anyway costs nothing and keeps the operation total.
        Fixed::from_bits(self.to_bits().saturating_neg())
    }
}

impl Mul for Fixed {
    type Output = Self;
    // Inlined on 64-bit hosts (a few instructions there); called on 32-bit
    // targets, where the 128-bit arithmetic expands to a long sequence and
    // inlining it everywhere overflows a Cortex-M0's 256 KiB of flash.
    #[cfg_attr(target_pointer_width = "64", inline(always))]
    #[cfg_attr(not(target_pointer_width = "64"), inline(never))]
    fn mul(self, o: Self) -> Self {
        // The exact product has 64 fractional bits; round to 32 by adding half
        // an ulp and shifting (arithmetic shift: ties go towards +∞).
        let p = self.to_bits() as i128 * o.to_bits() as i128;
        Fixed(saturate((p + (1i128 << (FRAC - 1))) >> FRAC))
    }
}

impl Div for Fixed {
    type Output = Self;
    // Never inlined: a division costs tens of cycles anyway (a call adds
    // little), and its branches and 128-bit paths, inlined into every lane
    // of every packet operation of the fully inlined render path, made
    // release builds of the CLI take many minutes to compile (and overflowed
    // a Cortex-M0's 256 KiB of flash on 32-bit targets).
    #[inline(never)]
    fn div(self, o: Self) -> Self {
        let (a, b) = (self.to_bits(), o.to_bits());
        if b == 0 {
            // Documented result for division by zero: the signed maximum.
            return Fixed::from_bits(if a > 0 {
                RAW_MAX
            } else if a < 0 {
                RAW_MIN
            } else {
                0
            });
        }
        // Quotient of a·2³² by b, rounded to nearest (ties away from zero).
        // When |a| < 2³¹ the numerator fits 64 bits and the cheaper native
        // division gives the same exact quotient and remainder.
        let (q, r) = if a > i32::MIN as i64 && a <= i32::MAX as i64 {
            let n = a << FRAC;
            ((n / b) as i128, (n % b) as i128)
        } else {
            let n = (a as i128) << FRAC;
            (n / b as i128, n % b as i128)
        };
        let b = b as i128;
        // |r| ≥ |b|/2 ⇔ 2|r| ≥ |b|; the quotient moves away from zero, in the
        // direction of the exact quotient's sign (that of a·b, and of r·b).
        let q = if 2 * r.abs() >= b.abs() {
            if (r < 0) == (b < 0) {
                q + 1
            } else {
                q - 1
            }
        } else {
            q
        };
        Fixed(saturate(q))
    }
}

/// `2^(2⁻ⁱ)` for `i = 1 ..= 32`, as unsigned 1.62 fixed point, rounded to
/// nearest (computed with 60-digit decimal arithmetic; the unit test
/// `exp2_table_matches_f64` checks every entry against `f64`).
const EXP2_TABLE: [u64; 32] = [
    0x5A827999FCEF3242,
    0x4C1BF828C6DC54B8,
    0x45CAE0F1F545EB73,
    0x42D561B3E6243D8A,
    0x4166C34C5615D0EC,
    0x40B268F9DE0183BA,
    0x4058F6A7ECCCD5B6,
    0x402C6BE96AF2FB58,
    0x4016321B687027A8,
    0x400B18178BA33B14,
    0x40058BCE410147E8,
    0x4002C5D7BFF71DAF,
    0x400162E807EE7E5B,
    0x4000B1730DF6A524,
    0x400058B9497B8152,
    0x40002C5C955DD701,
    0x4000162E46D6F26C,
    0x40000B1722757B1B,
    0x4000058B90FD3E0C,
    0x400002C5C86F3F26,
    0x40000162E433C79B,
    0x400000B17218EDD0,
    0x40000058B90C3968,
    0x4000002C5C860D54,
    0x400000162E4302D2,
    0x4000000B17218073,
    0x400000058B90BFFC,
    0x40000002C5C85FEF,
    0x4000000162E42FF3,
    0x40000000B17217F9,
    0x4000000058B90BFC,
    0x400000002C5C85FE,
];

/// One in unsigned 1.62 fixed point.
const Q62_ONE: u64 = 1 << 62;

/// Product of two unsigned 1.62 numbers below 4, rounded to nearest.
#[cfg_attr(not(debug_assertions), inline(always))]
fn mul_q62(a: u64, b: u64) -> u64 {
    let p = a as u128 * b as u128;
    ((p + (1u128 << 61)) >> 62) as u64
}

/// `log₂(raw·2⁻³²)` as raw 32.32 bits, for `0 < raw < 2³²` (a value in
/// `(0, 1)`): the integer part from the leading bit, then 32 fractional bits
/// by repeated squaring of the mantissa (each squaring yields one bit).
fn log2_unit(raw: u64) -> i64 {
    // raw = m·2^p with m in [1, 2): p from the position of the top bit.
    let p = 63 - raw.leading_zeros() as i64;
    let mut m = raw << (62 - p); // m in [1, 2), as 1.62
    let mut frac: i64 = 0;
    for i in 1..=FRAC {
        m = mul_q62(m, m);
        // m² in [1, 4): a value of 2 or more means this bit of log₂ is one.
        if m >= 2 * Q62_ONE {
            frac |= 1 << (FRAC - i);
            m >>= 1;
        }
    }
    ((p - FRAC as i64) << FRAC) + frac
}

/// `2^z` for `z <= 0` given as raw 32.32 bits, rounded, as raw bits.
fn exp2_nonpositive(z: i64) -> i64 {
    // z = k + f with integer k <= 0 and f in [0, 1).
    let k = z >> FRAC;
    let f = (z & (RAW_ONE - 1)) as u64;
    // Results below 2⁻³³ round to zero.
    if k < -(FRAC as i64) - 1 {
        return 0;
    }
    // 2^f = Π 2^(2⁻ⁱ) over the set bits i of f.
    let mut r = Q62_ONE;
    for i in 1..=FRAC {
        if f & (1 << (FRAC - i)) != 0 {
            r = mul_q62(r, EXP2_TABLE[(i - 1) as usize]);
        }
    }
    // r·2^k as 32.32: shift the 1.62 value right by 30 − k (≥ 30), rounding.
    let s = (62 - FRAC as i64 - k) as u32;
    ((r + (1u64 << (s - 1))) >> s) as i64
}

impl Scalar for Fixed {
    const ZERO: Self = Fixed::from_bits(0);
    const ONE: Self = Fixed::from_bits(RAW_ONE);
    const HALF: Self = Fixed::from_bits(RAW_ONE / 2);
    const TWO: Self = Fixed::from_bits(2 * RAW_ONE);
    const MAX: Self = Fixed::from_bits(RAW_MAX);
    /// `round(10⁻⁴·2³²)`, the value `from_f32(1e-4)` gives (unit-tested).
    const RAY_EPSILON: Self = Fixed::from_bits(429_497);
    const MIN_WEIGHT: Self = Fixed::from_bits(RAW_ONE / 512);
    const LIMITED_RANGE: bool = true;
    const COORDINATE_LIMIT: f32 = COORDINATE_LIMIT;
    const LIGHT_LIMIT: f32 = COORDINATE_LIMIT;
    const INTERMEDIATE_LIMIT: f32 = INTERMEDIATE_LIMIT;

    #[inline]
    fn from_f32(v: f32) -> Self {
        Fixed::from_f64(v as f64)
    }
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn from_i32(v: i32) -> Self {
        Fixed::from_bits((v as i64) << FRAC)
    }
    #[inline]
    fn to_f32(self) -> f32 {
        self.to_f64() as f32
    }
    // Out of line like `div`: a 128-bit integer square root loop.
    #[inline(never)]
    fn sqrt(self) -> Self {
        let a = self.to_bits();
        if a <= 0 {
            return Self::ZERO;
        }
        // √(a·2⁻³²)·2³² = √(a·2³²): the integer square root of a 96-bit number,
        // rounded to nearest. With r = ⌊√n⌋, √n ≥ r + ½ ⇔ n ≥ r² + r + ¼ ⇔
        // n − r² > r (integers), so rounding needs no wider arithmetic.
        let n = (a as u128) << FRAC;
        let r = n.isqrt();
        let r = if n - r * r > r { r + 1 } else { r };
        // r ≤ 2^47.5: always fits.
        Fixed::from_bits(r as i64)
    }
    fn powf(self, e: Self) -> Self {
        let (x, e_raw) = (self.to_bits(), e.to_bits());
        if e_raw <= 0 || x >= RAW_ONE {
            // x⁰ = 1, and the documented domain is x <= 1.
            return Self::ONE;
        }
        if x <= 0 {
            return Self::ZERO;
        }
        // x^e = 2^(e·log₂x); e·log₂x <= 0 here (saturating product).
        let z = e * Fixed::from_bits(log2_unit(x as u64));
        Fixed::from_bits(exp2_nonpositive(z.to_bits()))
    }
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn floor_to_i32(self) -> i32 {
        // An arithmetic shift floors; the result always fits an i32.
        (self.to_bits() >> FRAC) as i32
    }
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn is_finite(self) -> bool {
        true
    }
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn abs(self) -> Self {
        Fixed::from_bits(self.to_bits().saturating_abs())
    }
}

impl crate::num::bake::Bake for Fixed {
    /// `raypack::Fixed::from_bits(…)`: the raw value, exactly.
    fn bake(&self, w: &mut dyn core::fmt::Write) -> core::fmt::Result {
        write!(w, "raypack::Fixed::from_bits({})", self.to_bits())
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    fn fx(v: f64) -> Fixed {
        Fixed::from_f64(v)
    }
    const ULP: f64 = 1.0 / 4294967296.0;

    /// SplitMix64, seeded: operands for the property tests.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            crate::num::test_rng::splitmix64(&mut self.0)
        }
        /// Raw operands: extremes, small integers, values near one, and
        /// uniformly random bits at every magnitude.
        fn raw(&mut self) -> i64 {
            let special = [
                0,
                1,
                -1,
                RAW_MAX,
                RAW_MIN,
                i64::MIN,
                RAW_ONE,
                -RAW_ONE,
                RAW_ONE - 1,
                RAW_ONE + 1,
                1 << 62,
                -(1 << 62),
                1 << 31,
            ];
            match self.next() % 4 {
                0 => special[(self.next() % special.len() as u64) as usize],
                1 => (self.next() as i64) >> (self.next() % 64),
                2 => RAW_ONE + ((self.next() as i64) >> 40),
                _ => self.next() as i64,
            }
        }
    }

    /// Exact rational value of a raw number, as an i128 over 2³².
    fn exact(x: Fixed) -> i128 {
        x.to_bits() as i128
    }

    #[test]
    fn constants() {
        assert_eq!(Fixed::ONE.to_f64(), 1.0);
        assert_eq!(Fixed::HALF.to_f64(), 0.5);
        assert_eq!(Fixed::TWO.to_f64(), 2.0);
        assert_eq!(Fixed::MIN_WEIGHT.to_f64(), 1.0 / 512.0);
        assert_eq!(Fixed::RAY_EPSILON, Fixed::from_f32(1.0e-4));
        assert_eq!(Fixed::from_i32(-7).to_f64(), -7.0);
        assert_eq!(Fixed::from_i32(i32::MIN).to_bits(), RAW_MIN);
    }

    #[test]
    fn conversions_round_saturate_and_map_nan_to_zero() {
        assert_eq!(Fixed::from_f32(f32::NAN), Fixed::ZERO);
        assert_eq!(Fixed::from_f32(f32::INFINITY), Fixed::MAX);
        assert_eq!(Fixed::from_f32(f32::NEG_INFINITY), -Fixed::MAX);
        assert_eq!(Fixed::from_f32(3.0e9), Fixed::MAX);
        assert_eq!(Fixed::from_f32(0.1).to_bits(), 429_496_736); // 0.1f32 = 13421773·2⁻²⁷: exactly 13421773·2⁵
        assert_eq!(Fixed::from_f64(0.1).to_bits(), 429_496_730); // round(429496729.6)
        assert_eq!(Fixed::from_f32(-2.5).to_f32(), -2.5);
        assert_eq!(Fixed::from_bits(i64::MIN).to_bits(), RAW_MIN);
        assert_eq!(fx(1.5).floor_to_i32(), 1);
        assert_eq!(fx(-1.5).floor_to_i32(), -2);
        assert_eq!(Fixed::MAX.floor_to_i32(), i32::MAX);
        assert_eq!((-Fixed::MAX).floor_to_i32(), i32::MIN);
    }

    #[test]
    fn arithmetic_is_exact_or_rounded_to_nearest() {
        assert_eq!(fx(1.5) + fx(2.25), fx(3.75));
        assert_eq!(fx(1.5) - fx(2.25), fx(-0.75));
        assert_eq!(fx(1.5) * fx(-2.25), fx(-3.375));
        assert_eq!(fx(-3.375) / fx(1.5), fx(-2.25));
        assert_eq!(fx(1.0) / fx(3.0), Fixed::from_bits(1_431_655_765)); // 2³²/3 = 1431655765.33
        assert_eq!(fx(2.0) / fx(3.0), Fixed::from_bits(2_863_311_531)); // 2863311530.67 rounds up
        assert_eq!(fx(-2.0) / fx(3.0), Fixed::from_bits(-2_863_311_531));
        // The smallest product rounds half up: 2⁻³²·½ = ½ ulp → 1 ulp; −½ ulp → 0.
        assert_eq!(Fixed::from_bits(1) * Fixed::HALF, Fixed::from_bits(1));
        assert_eq!(Fixed::from_bits(-1) * Fixed::HALF, Fixed::from_bits(0));
    }

    #[test]
    fn saturation_and_division_by_zero() {
        let big = fx(2.0e9);
        assert_eq!(big + big, Fixed::MAX);
        assert_eq!(-big - big, -Fixed::MAX);
        assert_eq!(big * big, Fixed::MAX);
        assert_eq!(big * -big, -Fixed::MAX);
        assert_eq!(big / fx(0.001), Fixed::MAX);
        assert_eq!(fx(3.0) / Fixed::ZERO, Fixed::MAX);
        assert_eq!(fx(-3.0) / Fixed::ZERO, -Fixed::MAX);
        assert_eq!(Fixed::ZERO / Fixed::ZERO, Fixed::ZERO);
        assert_eq!(-Fixed::MAX, Fixed::from_bits(RAW_MIN));
        assert_eq!((-Fixed::MAX).abs(), Fixed::MAX);
        assert_eq!(Fixed::MAX / fx(-1.0), -Fixed::MAX);
        assert_eq!((-Fixed::MAX) / fx(-1.0), Fixed::MAX);
    }

    /// The exact result of every operation, computed independently in i128
    /// (and rounded as documented), against the implementation, over seeded
    /// random operands that include the extremes; nothing may panic (the
    /// test profile has overflow checks on).
    #[test]
    fn property_ops_match_exact_reference_and_never_panic() {
        let mut rng = Rng(0x5EED_F1CE);
        let clamp = |v: i128| v.clamp(RAW_MIN as i128, RAW_MAX as i128) as i64;
        for _ in 0..200_000 {
            let (a, b) = (Fixed::from_bits(rng.raw()), Fixed::from_bits(rng.raw()));
            let (ea, eb) = (exact(a), exact(b));
            assert_eq!((a + b).to_bits(), clamp(ea + eb));
            assert_eq!((a - b).to_bits(), clamp(ea - eb));
            assert_eq!((-a).to_bits(), clamp(-ea));
            // Product: floor((p + 2³¹)/2³²) = round half up.
            let p = ea * eb;
            assert_eq!((a * b).to_bits(), clamp((p + (1 << 31)).div_euclid(1 << 32)), "{a:?} * {b:?}");
            // Quotient: nearest to ea·2³²/eb, ties away from zero, checked
            // with the defining inequality |q·eb − n| ≤ |eb|/2.
            let d = a / b;
            if eb != 0 {
                let n = ea << 32;
                let q = d.to_bits() as i128;
                let saturated = q == RAW_MAX as i128 || q == RAW_MIN as i128;
                let err = (q * eb - n).abs();
                assert!(saturated || 2 * err <= eb.abs(), "{a:?} / {b:?} = {d:?}");
                if saturated {
                    // Saturation only when the exact quotient is out of range.
                    assert!((n / eb).abs() >= RAW_MAX as i128 - 1, "{a:?} / {b:?}");
                }
            }
            // Comparisons agree with the raw integers.
            assert_eq!(a < b, ea < eb);
            let _ = a.sqrt();
            let _ = a.abs().min(Fixed::ONE).powf(b.abs());
            let _ = a.floor_to_i32();
            let _ = a.to_unorm8();
        }
    }

    #[test]
    fn sqrt_is_correctly_rounded() {
        // Against f64 where f64 is exact enough, and by the defining
        // inequality (r − ½)² ≤ n < (r + ½)² everywhere.
        let mut rng = Rng(7);
        let mut inputs: Vec<i64> = (0..100_000).map(|_| rng.raw()).collect();
        inputs.extend([1, 2, 3, RAW_ONE, 4 * RAW_ONE, RAW_MAX, RAW_ONE - 1]);
        for raw in inputs {
            let x = Fixed::from_bits(raw);
            let r = x.sqrt().to_bits() as i128;
            if raw <= 0 {
                assert_eq!(r, 0);
                continue;
            }
            let n = (raw as u128 as i128) << 32;
            // 4(r − ½)² = (2r − 1)² ≤ 4n < (2r + 1)².
            assert!((2 * r - 1) * (2 * r - 1) <= 4 * n && 4 * n < (2 * r + 1) * (2 * r + 1), "sqrt({raw})");
            let f = (raw as f64 * ULP).sqrt();
            assert!((x.sqrt().to_f64() - f).abs() <= ULP * 0.5 + f * 1.0e-15, "sqrt({x:?})");
        }
        assert_eq!(fx(2.0).sqrt(), Fixed::from_bits(6_074_001_000)); // √2·2³² = 6074000999.95
        assert_eq!(fx(4.0).sqrt(), fx(2.0));
        assert_eq!(fx(-4.0).sqrt(), Fixed::ZERO);
    }

    #[test]
    fn exp2_table_matches_f64() {
        for (i, &t) in EXP2_TABLE.iter().enumerate() {
            let want = libm::exp2(libm::exp2(-((i + 1) as f64)));
            let got = t as f64 / Q62_ONE as f64;
            assert!((got - want).abs() <= 2.0 * f64::EPSILON, "entry {i}: {got} vs {want}");
        }
    }

    #[test]
    fn powf_matches_f64_pow() {
        let mut worst: f64 = 0.0;
        let mut rng = Rng(99);
        for k in 0..20_000 {
            let x = fx((rng.next() >> 11) as f64 / (1u64 << 53) as f64);
            let e = match k % 4 {
                0 => fx((rng.next() % 8) as f64),
                1 => fx((rng.next() >> 11) as f64 / (1u64 << 53) as f64 * 200.0),
                2 => fx(100_000.0),
                _ => fx(0.5),
            };
            let want = libm::pow(x.to_f64(), e.to_f64());
            let got = x.powf(e).to_f64();
            // 1 ulp of the result, plus the effect of a 2⁻³⁰ error in log₂x
            // amplified by the exponent.
            let tol = 2.0 * ULP + want * (e.to_f64() * 2.0e-9 + 1.0e-9);
            worst = worst.max((got - want).abs() / tol);
            assert!((got - want).abs() <= tol, "{x:?}^{e:?} = {got}, want {want}");
        }
        assert!(worst > 0.0);
        assert_eq!(fx(0.5).powf(fx(2.0)), fx(0.25));
        assert_eq!(fx(0.5).powf(Fixed::ZERO), Fixed::ONE);
        assert_eq!(Fixed::ZERO.powf(fx(3.0)), Fixed::ZERO);
        assert_eq!(Fixed::ONE.powf(fx(1.0e5)), Fixed::ONE);
        assert_eq!(fx(0.999).powf(fx(1.0e5)), Fixed::ZERO); // e^(−100): far below 2⁻³³
    }

    #[test]
    fn unorm8_quantization() {
        assert_eq!(fx(0.5).to_unorm8(), 128);
        assert_eq!(fx(1.0 / 255.0).to_unorm8(), 1);
        assert_eq!(fx(-3.0).to_unorm8(), 0);
        assert_eq!(Fixed::MAX.to_unorm8(), 255);
    }
}
