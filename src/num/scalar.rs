//! The [`Scalar`] trait: the number type every algorithm in raypack is written
//! against.
//!
//! Two implementations exist: `f32` (here) and the fixed-point scalar. All
//! geometry, shading and camera code is generic over `Scalar`, so a scene
//! traced with `f32` and with fixed point runs the very same code.
//!
//! # Determinism
//! Every operation must give the same bits on every target. For `f32` that
//! means: plain IEEE operations (correctly rounded in hardware and in
//! soft-float alike), no `mul_add`, no reassociation, and transcendental
//! functions from the pure-Rust `libm` crate, never from the platform's C
//! library. `sqrt` is correctly rounded by IEEE 754, so its result is
//! unique: the compiler intrinsic (with `std`, and on WebAssembly SIMD
//! through `core::arch`), which vectorizes, and elsewhere the integer
//! algorithm of `src/num/sqrtf.rs` (musl's, as in `libm`) agree
//! bit for bit.

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// [`Scalar::bin`]'s general form for the difference `x = self − origin`:
/// `⌊x·2^shift⌋` with the product rounded (a shift where
/// [`Scalar::SPARSE_PRODUCTS`] holds, `x · scale` otherwise), clamped to
/// `[0, n − 1]`.
#[inline(always)]
pub(crate) fn bin_rounded<S: Scalar>(x: S, shift: i32, scale: S, n: usize) -> usize {
    let x = if S::SPARSE_PRODUCTS { x.mul_pow2(shift) } else { x * scale };
    x.floor_clamped(n as i32 - 1) as usize
}

/// `clamp(trunc(x), 0, hi)` (`as`: saturating, NaN 0), which is
/// `clamp(⌊x⌋, 0, hi)` for `hi ≥ 0`: `f32`'s [`Scalar::floor_clamped`]
/// off x86.
#[inline(always)]
#[cfg_attr(any(target_arch = "x86", target_arch = "x86_64"), allow(dead_code))]
fn truncated_clamped(x: f32, hi: i32) -> i32 {
    (x as i32).max(0).min(hi)
}

/// A real-number type the tracer computes with.
///
/// Implementations must be total: no operation may panic, whatever the
/// operands (division by zero included). Results of meaningless operations
/// (such as `0 / 0`) may be arbitrary but must be deterministic; the tracer
/// masks such lanes out before it uses them.
pub trait Scalar:
    Copy
    + Debug
    + PartialEq
    + PartialOrd
    + Default
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Zero.
    const ZERO: Self;
    /// One.
    const ONE: Self;
    /// One half.
    const HALF: Self;
    /// Two.
    const TWO: Self;
    /// The largest finite value. Stands for "infinitely far" (the initial
    /// `t_max` of a ray, an unbounded slab), so it must compare greater than
    /// every distance a scene can produce.
    const MAX: Self;
    /// Relative size of the offset that moves a secondary ray's origin off the
    /// surface it leaves; the offset is `RAY_EPSILON · (1 + max|P|)`.
    const RAY_EPSILON: Self;
    /// Weights below this end a path (the "minimum contribution" cut-off).
    const MIN_WEIGHT: Self;
    /// Whether the type's range is small enough that scenes must be checked
    /// against [`Scalar::COORDINATE_LIMIT`] (fixed point); `false` for `f32`.
    const LIMITED_RANGE: bool = false;
    /// The largest coordinate magnitude a scene may use with this type, so
    /// that the tracer's largest intermediates (squared distances between
    /// scene points) stay representable; see [`crate::geom::fixed_range`]. Unlimited
    /// (`f32::MAX`) for `f32`.
    const COORDINATE_LIMIT: f32 = f32::MAX;
    /// The largest coordinate magnitude a light may have with this type
    /// (lights only enter the tracer through directions and distances to
    /// them, which the tracer forms without squaring large values, so they
    /// may lie further out than the scene). Unlimited for `f32`.
    const LIGHT_LIMIT: f32 = f32::MAX;
    /// The largest single intermediate a kernel may form with this type
    /// (quadric and cone discriminant terms are checked against it; see
    /// [`crate::geom::fixed_range`]). Unlimited (`f32::MAX`) for `f32`.
    const INTERMEDIATE_LIMIT: f32 = f32::MAX;
    /// Whether wider vector units speed this type up: the instruction-set
    /// dispatcher (`dispatch`, std) compiles AVX2 and AVX-512 copies of the
    /// render path only for such scalars (each copy costs compile time).
    /// `true` for `f32`; `false` by default (integer fixed point gains
    /// little from them).
    const PACKED: bool = false;

    /// The half-extent of the box a scene is converted into before tracing
    /// with this type ([`crate::geom::uniform_scale`]: the scene's bounded
    /// primitives and the eye, centred, scaled uniformly), or `None` to
    /// trace scenes in their own units. `None` for `f32` and 32.32 fixed
    /// point; the Q8.24 fixed point needs the small box for its range.
    const SCENE_FRAME: Option<f32> = None;
    /// Whether vectors are brought to a magnitude near 1 before they are
    /// normalized ([`Scalar::normalizing_factor`]): for fixed point, whose
    /// squares overflow for long vectors and lose their digits for short
    /// ones. `false` for `f32`, whose exponent does that for free.
    const NORMALIZE_PRESCALE: bool = false;
    /// Whether [`Vec3xW::normalize`](crate::geom::vec3::Vec3xW::normalize)
    /// multiplies by [`Scalar::inverse_sqrt`] of the squared length
    /// (and takes the length as the squared length times it) rather than
    /// dividing by the square root: for fixed point, where the reciprocal
    /// root costs a third of a square root and a division. `false` for
    /// `f32`, whose `sqrt` and `/` are correctly rounded and, on most
    /// targets, instructions.
    const NORMALIZE_BY_INVERSE_SQRT: bool = false;
    /// Whether code may skip a product whose constant factor is zero: `true`
    /// when `x·0 = 0` and `x + 0 = x` hold bit for bit for every `x` (no
    /// signed zeros, no NaN) and a product costs more than a compare and a
    /// branch. Fixed point: a product is a long integer routine on small
    /// cores, and axis-aligned normals (floors, walls, box faces) make a
    /// third of a frame's products zero. `false` for `f32` (`x·0` is `−0`
    /// or NaN for some `x`).
    const SPARSE_PRODUCTS: bool = false;

    /// `self * self`, bit for bit. A scalar may form a square more cheaply
    /// than a general product (Q8.24 on Armv6-M: three partial products,
    /// not four); the default is the product.
    #[inline(always)]
    fn square(self) -> Self {
        self * self
    }

    /// `(a / d, b / d)`, bit for bit: two quotients by one divisor, which a
    /// scalar whose division is a long routine may form sharing the
    /// divisor's preparation. The default divides twice.
    #[inline(always)]
    fn div_pair(a: Self, b: Self, d: Self) -> (Self, Self) {
        (a / d, b / d)
    }
    /// Whether [`Scalar::unit_dot_le`] settles anything.
    const UNIT_DOT_ESTIMATE: bool = false;
    /// Whether `a·b <= limit`, with `a·b` as [`Vec3xW::dot_splat_small`]
    /// forms it (`Σ aᵢ.mul_small(bᵢ)`), for vectors whose components are at
    /// most 1.0625 in magnitude (unit vectors; beyond that the answer is
    /// unspecified, never a panic) and `|limit| <= 2`, where an estimate
    /// cheaper than the three products settles it: `Some` of the answer,
    /// `None` where the estimate lies too close to `limit` (the caller
    /// then forms the product). The default settles nothing
    /// ([`Scalar::UNIT_DOT_ESTIMATE`]).
    ///
    /// [`Vec3xW::dot_splat_small`]: crate::geom::vec3::Vec3xW::dot_splat_small
    #[inline(always)]
    fn unit_dot_le(a: [Self; 3], b: [Self; 3], limit: Self) -> Option<bool> {
        let _ = (a, b, limit);
        None
    }
    /// `self * o` for factors at most 4 in magnitude (components of unit
    /// vectors the tracer made itself: directions, normals, cosines), bit
    /// for bit the product there; a scalar of limited range
    /// ([`Scalar::LIMITED_RANGE`]) may leave out the range tests of its
    /// product that cannot fire for such factors, and for larger factors
    /// gives an unspecified value (never a panic), which callers keep only
    /// in lanes they mask out. Other scalars give the product: the default.
    #[inline(always)]
    fn mul_small(self, o: Self) -> Self {
        self * o
    }
    /// [`Scalar::square`] for `self` at most 4 in magnitude, as
    /// [`Scalar::mul_small`] is the product.
    #[inline(always)]
    fn square_small(self) -> Self {
        self.square()
    }
    /// `self + o` for operands whose sum is at most 64 in magnitude (the
    /// terms of a dot product of [`Scalar::mul_small`]'s factors: at most
    /// 3 × 16), bit for bit the sum there; a scalar of limited range may
    /// leave out the saturation that cannot happen for them, and otherwise
    /// gives an unspecified value (never a panic), as `mul_small` does.
    #[inline(always)]
    fn add_small(self, o: Self) -> Self {
        self + o
    }
    /// `self - o` for operands whose difference is at most 64 in magnitude,
    /// as [`Scalar::add_small`] is the sum.
    #[inline(always)]
    fn sub_small(self, o: Self) -> Self {
        self - o
    }

    /// One vector's unit vector and length (components `v`), bit for bit
    /// what the general lane code of `Vec3xW::normalize_with_length` gives
    /// it (whose length is then positive), where a scalar has a shorter
    /// route to the same bits; `None` sends the vector, and its packet, to
    /// the general code. Used only when [`Scalar::NORMALIZE_PRESCALE`]
    /// holds; the default has no shorter route.
    #[inline(always)]
    fn unit_and_length(_v: [Self; 3]) -> Option<([Self; 3], Self)> {
        None
    }

    /// A power of two `f` (so `v·f` is exact) that brings a magnitude
    /// `self >= 0` near 1; used only when [`Scalar::NORMALIZE_PRESCALE`]
    /// is set. The default is 1.
    #[inline(always)]
    fn normalizing_factor(self) -> Self {
        Self::ONE
    }

    /// The exponent `k` of [`Scalar::normalizing_factor`] (`f = 2^k`): 0 by
    /// default.
    #[inline(always)]
    fn normalizing_exponent(self) -> i32 {
        0
    }

    /// `self · 2^k` for a `k` from [`Scalar::normalizing_exponent`], bit for
    /// bit the product `self * self_type(2^k)` (a type whose product rounds
    /// overrides it with a shift that rounds the same way). The default
    /// multiplies by the factor `2^k`, formed exactly.
    #[inline(always)]
    fn mul_pow2(self, k: i32) -> Self {
        if k == 0 {
            return self;
        }
        // 2^k, exactly (powers of two are representable; |k| is small).
        let (step, n) = if k > 0 { (Self::TWO, k) } else { (Self::HALF, -k) };
        let mut f = Self::ONE;
        for _ in 0..n.min(64) {
            f = f * step;
        }
        self * f
    }

    /// The bin of `self` among `n` over a window: `⌊(self − origin)·2^shift⌋`
    /// clamped to `[0, n − 1]`, up to the rounding of the subtraction and of
    /// the product, and non-decreasing in `self` (what the crate's bins over a
    /// window need: bins built from bounds with this same function hold every
    /// value between them). `scale` is `2^shift` in `Self`. The default
    /// rounds the product (a shift where [`Scalar::SPARSE_PRODUCTS`]
    /// holds); fixed point shifts the raw difference, which floors exactly.
    #[inline(always)]
    fn bin(self, origin: Self, shift: i32, scale: Self, n: usize) -> usize {
        bin_rounded(self - origin, shift, scale, n)
    }

    /// `num / den` for image coordinates (the camera's pixel centres:
    /// `(2i + 1)/W`), `den > 0`. The default divides the two numbers in the
    /// type, which is exact for `f32` and 32.32; a type whose range does
    /// not hold image sizes overrides it.
    #[inline(always)]
    fn ratio(num: u32, den: u32) -> Self {
        Self::from_i32(num as i32) / Self::from_i32(den as i32)
    }

    /// [`Scalar::ratio`]`(num, den.get())`, for a divisor used again and
    /// again (the camera's image width and height). The default is that
    /// call; a type whose division is a long routine uses the reciprocal
    /// the [`Divisor`] carries. The same bits either way.
    #[inline(always)]
    fn ratio_by(num: u32, den: &Divisor) -> Self {
        Self::ratio(num, den.get())
    }

    /// Converts from `f32` (set-up time only: scene input, camera angles).
    /// Out-of-range values saturate; NaN becomes zero.
    fn from_f32(v: f32) -> Self;
    /// Converts from a (small) integer, exactly where the type allows.
    fn from_i32(v: i32) -> Self;
    /// Converts to `f32` (for reports and tests, never on the render path).
    fn to_f32(self) -> f32;
    /// Square root, correctly rounded. Negative input gives a value the caller
    /// must mask out (NaN for `f32`).
    fn sqrt(self) -> Self;
    /// Whether packets of four lanes and more take their square roots from
    /// [`Scalar::sqrt_lanes`] (`Lanes::sqrt`): `f32` on the firmware with
    /// a hardware FPU, whose packets run on vector `f32` lanes (the
    /// Cortex-M55's Helium, RISC-V's vectors).
    const LANE_SQRT: bool = false;
    /// [`Scalar::sqrt`] of every lane, bit for bit, in a form that
    /// vectorises (see [`Scalar::LANE_SQRT`]); by default lane by lane.
    #[inline(always)]
    fn sqrt_lanes<const W: usize>(x: [Self; W]) -> [Self; W] {
        let mut r = x;
        for v in r.iter_mut() {
            *v = v.sqrt();
        }
        r
    }
    /// `1/√self` for `self > 0`, used by the normalisation where
    /// [`Scalar::NORMALIZE_BY_INVERSE_SQRT`] holds; other input gives a
    /// value the caller must mask out. The default divides one by the
    /// square root.
    #[inline(always)]
    fn inverse_sqrt(self) -> Self {
        Self::ONE / self.sqrt()
    }
    /// `self` raised to the power `e`, for `self` in `[0, 1]` and `e >= 0`
    /// (the Phong highlight). Deterministic on every target.
    fn powf(self, e: Self) -> Self;
    /// `floor(self)` as an integer, saturating; NaN gives 0.
    fn floor_to_i32(self) -> i32;
    /// [`Scalar::floor_to_i32`] clamped to `[0, hi]` (`hi ≥ 0`): a bin
    /// index. A type may round towards zero instead of down, which gives
    /// the same index: the two differ only on negative non-integers, which
    /// both bring below 1 and the clamp to 0.
    #[inline(always)]
    fn floor_clamped(self, hi: i32) -> i32 {
        self.floor_to_i32().clamp(0, hi)
    }
    /// Whether the value is a finite number (always true for fixed point).
    fn is_finite(self) -> bool;

    /// Absolute value.
    #[inline(always)]
    fn abs(self) -> Self {
        if self < Self::ZERO {
            -self
        } else {
            self
        }
    }
    /// The smaller of two values (`other` when they are unordered).
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        if self < other {
            self
        } else {
            other
        }
    }
    /// The larger of two values (`other` when they are unordered).
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        if self > other {
            self
        } else {
            other
        }
    }
    /// `a` where `mask` is set, else `b`: the per-lane step of
    /// [`crate::num::lanes::Lanes::select`]. `mask` is a lane word of a
    /// [`crate::num::lanes::Mask`], all ones or zero. `f32` overrides it with a
    /// bitwise blend of the two bit patterns (same result, every bit): LLVM's
    /// vectorizer keeps a bitwise select of 16 lanes in whole 512-bit
    /// registers, where the branchy form made it split 16-lane packets into
    /// shuffled 2/2/4/8-lane pieces with stack spills (3× slower sphere tests).
    #[inline(always)]
    fn blend(mask: u32, a: Self, b: Self) -> Self {
        if mask != 0 {
            a
        } else {
            b
        }
    }
    /// Clamps to `[0, 1]`; anything unordered (NaN) becomes 0.
    #[inline(always)]
    fn clamp01(self) -> Self {
        // `max` returns its argument for NaN, so NaN becomes 0 here.
        self.max(Self::ZERO).min(Self::ONE)
    }
    /// Quantizes a linear value in `[0, 1]` to 8 bits: `round(clamp(v)·255)`.
    #[inline(always)]
    fn to_unorm8(self) -> u8 {
        let v = self.clamp01() * Self::from_i32(255) + Self::HALF;
        let i = v.floor_to_i32();
        if i < 0 {
            0
        } else if i > 255 {
            255
        } else {
            i as u8
        }
    }
}

/// A divisor for [`Scalar::ratio_by`]: `den` with what a quotient
/// `round(num·2^k/den)` needs to be formed without a division instruction
/// (a library loop of about 130 instructions on the Cortex-M0), worked out
/// once (two divisions) for many quotients.
///
/// With `A = ⌊2²⁴/den⌋`, `B = 2²⁴ mod den` and the reciprocal
/// `m = ⌊(2³² − 1)/den⌋` (kept for `0 < den < 2¹⁶`),
/// `num·2²⁴ + h = num·A·den + (num·B + h)`, so the quotient is
/// `num·A + ⌊(num·B + h)/den⌋`, and the second quotient comes from
/// `⌊(num·B + h)·m/2³²⌋`, at most 2 below it, raised by the exact remainder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Divisor {
    den: u32,
    whole: u32,
    rest: u32,
    recip: u32,
}

impl crate::num::bake::Bake for Divisor {
    /// `Divisor::new(den)` or `Divisor::plain(den)`, whichever it is: its
    /// reciprocal is recomputed (at compile time) rather than written out, so
    /// a baked divisor is always a consistent one.
    fn bake(&self, w: &mut dyn core::fmt::Write) -> core::fmt::Result {
        let how = if *self == Divisor::new(self.den) { "new" } else { "plain" };
        write!(w, "raypack::num::scalar::Divisor::{how}({})", self.den)
    }
}

impl Divisor {
    /// `den` with its reciprocal (none for `0` or from 2¹⁶ on: those
    /// quotients take [`Scalar::ratio`]'s route).
    pub const fn new(den: u32) -> Self {
        if den == 0 || den >= 1 << 16 {
            return Self::plain(den);
        }
        Divisor { den, whole: (1 << 24) / den, rest: (1 << 24) % den, recip: u32::MAX / den }
    }
    /// `den` without a reciprocal: [`Scalar::ratio_by`] is then
    /// [`Scalar::ratio`] (for a divisor used only a few times).
    pub const fn plain(den: u32) -> Self {
        Divisor { den, whole: 0, rest: 0, recip: 0 }
    }
    /// The divisor.
    #[inline(always)]
    pub const fn get(&self) -> u32 {
        self.den
    }
    /// `⌊(num·2²⁴ + ⌊den/2⌋)/den⌋` for `num < 2¹⁶` and `num < 2⁷·den`
    /// (so below 2³¹), or `None` where that does not hold or `den` has no
    /// reciprocal. `wmul_hi` is the high word of a 32×32-bit product.
    #[inline(always)]
    pub(crate) fn rounded_q24(&self, num: u32, wmul_hi: impl Fn(u32, u32) -> u32) -> Option<u32> {
        if self.recip == 0 || num >= 1 << 16 || num >= self.den << 7 {
            return None;
        }
        // num·B + h < (2¹⁶ − 1)·(2¹⁶ − 2) + 2¹⁵ < 2³²: exact. (Wrapping
        // forms only spare the overflow checks; every step is exact.)
        let n2 = num.wrapping_mul(self.rest).wrapping_add(self.den >> 1);
        // m·den ∈ (2³² − 1 − den, 2³² − 1], so n2·m/2³² lies within
        // n2·(den + 1)/(den·2³²) < 2 below n2/den.
        let mut q2 = wmul_hi(n2, self.recip);
        // The remainder is below 3·den < 2¹⁸: exact modulo 2³².
        let mut r = n2.wrapping_sub(q2.wrapping_mul(self.den));
        while r >= self.den {
            r = r.wrapping_sub(self.den);
            q2 = q2.wrapping_add(1);
        }
        // num < 2⁷·den: the quotient, num·A + q2, is below 2³¹.
        Some(num.wrapping_mul(self.whole).wrapping_add(q2))
    }
}

impl Scalar for f32 {
    const PACKED: bool = true;
    /// Bitwise blend (see [`Scalar::blend`]): exactly `a` or `b`, NaN
    /// payloads and signed zeros included, as `mask` is all ones or zero.
    #[inline(always)]
    fn blend(mask: u32, a: Self, b: Self) -> Self {
        f32::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
    }
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const HALF: Self = 0.5;
    const TWO: Self = 2.0;
    const MAX: Self = f32::MAX;
    const RAY_EPSILON: Self = 1.0e-4;
    const MIN_WEIGHT: Self = 1.0 / 512.0;

    #[inline(always)]
    fn from_f32(v: f32) -> Self {
        v
    }
    #[inline(always)]
    fn from_i32(v: i32) -> Self {
        v as f32
    }
    #[inline(always)]
    fn to_f32(self) -> f32 {
        self
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // Both are correctly rounded (IEEE 754 requires it), so the bits are
        // the same; only the intrinsic lets LLVM emit packed `sqrtps`.
        #[cfg(feature = "std")]
        {
            f32::sqrt(self)
        }
        // WebAssembly SIMD without std: the square root instruction (lane 0
        // of `f32x4.sqrt`, which LLVM reduces to `f32.sqrt` and packs across
        // lanes again), where libm would run its software square root.
        #[cfg(all(not(feature = "std"), target_arch = "wasm32", target_feature = "simd128"))]
        {
            use core::arch::wasm32::{f32x4_extract_lane, f32x4_splat, f32x4_sqrt};
            f32x4_extract_lane::<0>(f32x4_sqrt(f32x4_splat(self)))
        }
        // Elsewhere (the firmware): `libm::sqrtf`'s algorithm without its
        // inexact flag's addition (`num::sqrtf`).
        #[cfg(all(not(feature = "std"), not(all(target_arch = "wasm32", target_feature = "simd128"))))]
        {
            crate::num::sqrtf::sqrtf(self)
        }
    }
    // `num::sqrtf`'s table and 64-bit products stay scalar on vector
    // lanes; its lane form vectorises (the same bits: both are correctly
    // rounded).
    const LANE_SQRT: bool =
        cfg!(all(not(feature = "std"), hard_float, not(all(target_arch = "wasm32", target_feature = "simd128"))));
    #[inline(always)]
    fn sqrt_lanes<const W: usize>(x: [f32; W]) -> [f32; W] {
        #[cfg(all(not(feature = "std"), hard_float, not(all(target_arch = "wasm32", target_feature = "simd128"))))]
        {
            crate::num::sqrtf::sqrtf_lanes(x)
        }
        #[cfg(not(all(
            not(feature = "std"),
            hard_float,
            not(all(target_arch = "wasm32", target_feature = "simd128"))
        )))]
        {
            let mut r = x;
            for v in r.iter_mut() {
                *v = Scalar::sqrt(*v);
            }
            r
        }
    }
    #[inline(always)]
    fn powf(self, e: Self) -> Self {
        // Our own branch-free x^e for the highlight's domain (src/num/unit_pow.rs):
        // plain IEEE operations in a fixed order, the same bits on every
        // target, and it vectorises where libm::powf stayed scalar.
        crate::num::unit_pow::powf_unit(self, e)
    }
    #[inline(always)]
    fn floor_to_i32(self) -> i32 {
        if cfg!(hard_float) {
            // With hardware conversions: truncate, and step down where that
            // rounded up (a negative non-integer). `t as f32` is exact: a
            // truncated `f32` below 2³¹ is an integer `f32` holds. `as`
            // saturates (±∞ and beyond ±2³¹ give the ends, NaN 0), which
            // the step leaves there. The same result as below, every input
            // (`floor_by_truncation_is_floorf`).
            let t = self as i32;
            if t as f32 > self {
                t.saturating_sub(1)
            } else {
                t
            }
        } else {
            // In soft float, where each conversion and comparison above is
            // a library call, `floorf`'s bit operations cost less (the
            // Cortex-M0's `f32` frame took 864.7 M instructions with the
            // truncation, 856.4 M with `floorf`). `as` saturates and maps
            // NaN to 0.
            libm::floorf(self) as i32
        }
    }
    /// Truncation (`as`, saturating, NaN 0) in place of the floor: one
    /// conversion, without the floor's step down or `floorf`. Not on x86,
    /// where the polygons' edge blocks, which bin too, compiled longer with
    /// it (`valgrind --tool=callgrind` of `raypack render gears-2.nff
    /// --width 128 --height 128 -j 1 --packet 1`: 466.8 M instructions
    /// against 464.9 M).
    #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
    #[inline(always)]
    fn floor_clamped(self, hi: i32) -> i32 {
        truncated_clamped(self, hi)
    }
    /// [`Scalar::to_unorm8`] without a call to `floorf`: after the clamp the
    /// value `v·255 + ½` lies in `[½, 255½]`, where truncation equals the
    /// floor. Same result, every input.
    #[inline(always)]
    fn to_unorm8(self) -> u8 {
        let v = self.clamp01() * 255.0 + 0.5;
        // Truncation in integer operations, which vectorise across a
        // packet where a saturating float-to-int conversion (`as`) left a
        // per-lane fix-up: v = 1.f·2^(E−127) with the biased exponent E in
        // [126, 134], so its integer part is the 24-bit significand shifted
        // right by 150 − E (16 to 24 places; `& 31` only keeps the shift in
        // range for the compiler, it never changes it).
        let bits = v.to_bits();
        let significand = (bits & 0x007f_ffff) | 0x0080_0000;
        let shift = 150u32.wrapping_sub(bits >> 23) & 31;
        (significand >> shift).min(255) as u8
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // Clearing the sign bit is what `f32::abs` does; core has it stably.
        f32::abs(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sqrt_is_correctly_rounded_like_libm() {
        let mut x = 1.0e-30f32;
        while x < 1.0e30 {
            assert_eq!(Scalar::sqrt(x).to_bits(), libm::sqrtf(x).to_bits(), "{x}");
            x *= 1.37;
        }
    }

    /// `f32`'s `floor_clamped` off x86 (the truncation) and here is the
    /// floor clamped, for the bound of the direction cells' index (15) and
    /// others, on the special values and every 13th float of magnitude up
    /// to 2³².
    #[test]
    fn floor_clamped_is_the_clamped_floor() {
        let check = |x: f32| {
            for hi in [0, 1, 15, 255, i32::MAX] {
                let want = (libm::floorf(x) as i32).clamp(0, hi);
                assert_eq!(truncated_clamped(x, hi), want, "{x:e} ({:#x}), {hi}", x.to_bits());
                assert_eq!(Scalar::floor_clamped(x, hi), want, "{x:e} ({:#x}), {hi}", x.to_bits());
            }
        };
        for x in [0.0, -0.0, -0.5, -1.0, -1.5, f32::INFINITY, f32::NEG_INFINITY, f32::NAN, f32::MAX, f32::MIN] {
            check(x);
        }
        for bits in (0..4.3e9f32.to_bits()).step_by(13) {
            check(f32::from_bits(bits));
            check(-f32::from_bits(bits));
        }
    }

    /// `floor_to_i32` is `floorf` then a saturating conversion: every 7th
    /// float of magnitude in [2⁻², 8·10⁹] (past both ends of `i32`), every
    /// 97th bit pattern, and the special values.
    #[test]
    fn floor_by_truncation_is_floorf() {
        let check = |x: f32| assert_eq!(Scalar::floor_to_i32(x), libm::floorf(x) as i32, "{x:e} ({:#x})", x.to_bits());
        for x in [
            0.0,
            -0.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MAX,
            f32::MIN,
            2147483648.0,
            -2147483648.0,
            -2147483904.0,
        ] {
            check(x);
        }
        for bits in (0.25f32.to_bits()..8.0e9f32.to_bits()).step_by(7) {
            check(f32::from_bits(bits));
            check(-f32::from_bits(bits));
        }
        for bits in (0..u32::MAX).step_by(97) {
            check(f32::from_bits(bits));
        }
    }

    /// The integer truncation equals `floor(clamp(v)·255 + ½)` computed
    /// with a float-to-int conversion: on every float of `[0, 1]` near the
    /// 8-bit steps and their midpoints, and on seeded random bit patterns
    /// (NaN, infinities, negatives, huge values included).
    #[test]
    fn unorm8_equals_the_float_conversion() {
        fn reference(x: f32) -> u8 {
            ((x.clamp01() * 255.0 + 0.5) as i32).clamp(0, 255) as u8
        }
        for k in 0..=510u32 {
            let centre = k as f32 / 510.0;
            let bits = centre.to_bits();
            for d in 0..64u32 {
                for b in [bits.wrapping_add(d), bits.wrapping_sub(d)] {
                    let x = f32::from_bits(b);
                    assert_eq!(x.to_unorm8(), reference(x), "{x:e}");
                }
            }
        }
        let mut state = 0x6e6f_726d_5f38u64;
        for _ in 0..1_000_000 {
            let x = f32::from_bits((crate::num::test_rng::splitmix64(&mut state) >> 32) as u32);
            assert_eq!(x.to_unorm8(), reference(x), "{x:e}");
        }
        for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.0, f32::MIN_POSITIVE, 0.5 / 255.0, 1.5 / 255.0] {
            assert_eq!(x.to_unorm8(), reference(x), "{x:e}");
        }
    }

    #[test]
    fn unorm8_rounds_and_clamps() {
        assert_eq!(0.0f32.to_unorm8(), 0);
        assert_eq!(1.0f32.to_unorm8(), 255);
        assert_eq!(2.0f32.to_unorm8(), 255);
        assert_eq!((-1.0f32).to_unorm8(), 0);
        assert_eq!(f32::NAN.to_unorm8(), 0);
        assert_eq!(f32::INFINITY.to_unorm8(), 255);
        assert_eq!((0.5f32).to_unorm8(), 128);
        assert_eq!((1.0f32 / 255.0).to_unorm8(), 1);
    }

    #[test]
    fn min_max_ignore_nan_in_first_operand() {
        assert_eq!(Scalar::max(f32::NAN, 0.0), 0.0);
        assert_eq!(Scalar::min(f32::NAN, 1.0), 1.0);
    }
}
