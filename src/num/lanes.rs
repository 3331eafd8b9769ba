//! Structure-of-arrays lanes and masks: the vocabulary of packet code.
//!
//! [`Lanes<S, W>`] is `W` scalars side by side; every operation is a plain
//! loop over `W` that LLVM turns into packed instructions once the width is
//! known. [`Mask<W>`] says which lanes take part. Packet code is written as
//! straight-line lane arithmetic with masks as its control flow:
//!
//! ```
//! use raypack::lanes::{Lanes, Mask};
//! let t = Lanes::<f32, 4>([1.0, -2.0, 3.0, 0.5]);
//! let mut valid = Mask::<4>::splat(true);
//! valid &= t.gt(Lanes::splat(0.0));        // narrow the active lanes
//! if valid.none() { return; }              // early exit: nothing left
//! let best = Lanes::select(valid, t, Lanes::splat(f32::MAX)); // masked commit
//! assert_eq!(best.0, [1.0, f32::MAX, 3.0, 0.5]);
//! ```
//!
//! The scalar tracer is the width-1 packet: `Lanes<S, 1>` runs the same code.

use crate::num::scalar::Scalar;
use core::ops::{Add, BitAnd, BitAndAssign, BitOr, BitOrAssign, BitXor, BitXorAssign, Div, Mul, Neg, Not, Sub};

/// `W` scalars processed together, one per ray of a packet.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(transparent)]
pub struct Lanes<S, const W: usize>(pub [S; W]);

/// Which lanes of a packet are active, or have some property.
///
/// Stored as one 32-bit word per lane, all ones (set) or all zeros (clear):
/// the form that packed compares (`cmpps`) produce and blends (`blendvps`,
/// `vpblendmd`) and `movmskps` consume, so masks stay in vector registers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(transparent)]
pub struct Mask<const W: usize>([u32; W]);

const SET: u32 = u32::MAX;

#[inline(always)]
const fn word(v: bool) -> u32 {
    if v {
        SET
    } else {
        0
    }
}

impl<const W: usize> Mask<W> {
    /// Every lane set to `v`.
    #[inline(always)]
    pub const fn splat(v: bool) -> Self {
        Mask([word(v); W])
    }
    /// A mask from one flag per lane.
    #[inline(always)]
    pub fn from_array(v: [bool; W]) -> Self {
        let mut r = [0; W];
        for i in 0..W {
            r[i] = word(v[i]);
        }
        Mask(r)
    }
    /// One flag per lane.
    #[inline(always)]
    pub fn to_array(self) -> [bool; W] {
        let mut r = [false; W];
        for i in 0..W {
            r[i] = self.0[i] != 0;
        }
        r
    }
    /// Whether lane `i` is set (`false` for a lane index out of range).
    #[inline(always)]
    pub fn get(self, i: usize) -> bool {
        match self.0.get(i) {
            Some(&w) => w != 0,
            None => false,
        }
    }
    /// Sets or clears lane `i` (no effect for a lane index out of range).
    #[inline(always)]
    pub fn set(&mut self, i: usize, v: bool) {
        if let Some(w) = self.0.get_mut(i) {
            *w = word(v);
        }
    }
    /// Whether any lane is set.
    #[inline(always)]
    pub fn any(self) -> bool {
        let mut r = 0;
        for i in 0..W {
            r |= self.0[i];
        }
        r != 0
    }
    /// Whether no lane is set.
    #[inline(always)]
    pub fn none(self) -> bool {
        !self.any()
    }
    /// Whether every lane is set.
    #[inline(always)]
    pub fn all(self) -> bool {
        let mut r = SET;
        for i in 0..W {
            r &= self.0[i];
        }
        r != 0
    }
    /// Number of set lanes.
    #[inline(always)]
    pub fn count(self) -> u32 {
        let mut n = 0;
        for i in 0..W {
            n += self.0[i] & 1;
        }
        n
    }
    /// Lanes set here and not in `other`.
    #[inline(always)]
    pub fn and_not(self, other: Self) -> Self {
        self & !other
    }
    /// The lowest set lane, if any.
    #[inline(always)]
    pub fn first_set(self) -> Option<usize> {
        (0..W).find(|&i| self.0[i] != 0)
    }
    /// Lanes whose integer `ids[i]` equals `k` (for example the lanes of a
    /// packet that hit primitive `k`).
    #[inline(always)]
    pub fn from_eq_u32(ids: &[u32; W], k: u32) -> Self {
        let mut r = [0; W];
        for i in 0..W {
            r[i] = word(ids[i] == k);
        }
        Mask(r)
    }
    /// Lane `i` from `a` where set, from `b` elsewhere, for integer lanes
    /// (such as primitive indices).
    #[inline(always)]
    pub fn select_u32(self, a: [u32; W], b: [u32; W]) -> [u32; W] {
        let mut r = [0; W];
        for i in 0..W {
            r[i] = (a[i] & self.0[i]) | (b[i] & !self.0[i]);
        }
        r
    }
}

macro_rules! mask_binop {
    ($tr:ident, $f:ident, $tra:ident, $fa:ident, $op:tt, $opa:tt) => {
        impl<const W: usize> $tr for Mask<W> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                let mut r = self.0;
                for i in 0..W {
                    r[i] $opa o.0[i];
                }
                Mask(r)
            }
        }
        impl<const W: usize> $tra for Mask<W> {
            #[inline(always)]
            fn $fa(&mut self, o: Self) {
                *self = *self $op o;
            }
        }
    };
}
mask_binop!(BitAnd, bitand, BitAndAssign, bitand_assign, &, &=);
mask_binop!(BitOr, bitor, BitOrAssign, bitor_assign, |, |=);
mask_binop!(BitXor, bitxor, BitXorAssign, bitxor_assign, ^, ^=);

impl<const W: usize> Not for Mask<W> {
    type Output = Self;
    /// The negation written into a fresh array: at width 1 a copy inverted
    /// in place stayed a one-trip loop after inlining into the tracer on
    /// the 32-bit cores (about five instructions where one does; the
    /// RV32IMAC `fixed32` frame 5.5 % longer). On x86 the copy inverted in
    /// place: there the fresh array made width-1 renders 1–3 % slower
    /// (interleaved `raypack bench`).
    #[inline(always)]
    fn not(self) -> Self {
        #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
        {
            let mut r = [0; W];
            for i in 0..W {
                r[i] = !self.0[i];
            }
            Mask(r)
        }
        #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
        {
            let mut r = self.0;
            for i in 0..W {
                r[i] = !r[i];
            }
            Mask(r)
        }
    }
}

macro_rules! lane_cmp {
    ($(#[$m:meta])* $name:ident, $op:tt) => {
        $(#[$m])*
        #[inline(always)]
        pub fn $name(self, o: Self) -> Mask<W> {
            let mut r = [0u32; W];
            for i in 0..W {
                r[i] = word(self.0[i] $op o.0[i]);
            }
            Mask(r)
        }
    };
}

impl<S: Scalar, const W: usize> Lanes<S, W> {
    /// Every lane set to `v`.
    #[inline(always)]
    pub fn splat(v: S) -> Self {
        Lanes([v; W])
    }
    /// Every lane zero.
    #[inline(always)]
    pub fn zero() -> Self {
        Self::splat(S::ZERO)
    }
    /// Lanes that are finite (neither infinite nor NaN).
    #[inline(always)]
    pub fn finite(self) -> Mask<W> {
        let mut r = [0u32; W];
        for i in 0..W {
            r[i] = word(self.0[i].is_finite());
        }
        Mask(r)
    }
    /// Lane `i` from `a` where `m` is set, from `b` elsewhere.
    #[inline(always)]
    pub fn select(m: Mask<W>, a: Self, b: Self) -> Self {
        let mut r = b.0;
        if W == 1 {
            // One lane: a plain choice (a branch or a conditional move), as
            // there is no vectorizer to please.
            if m.0[0] != 0 {
                r[0] = a.0[0];
            }
        } else {
            for i in 0..W {
                r[i] = S::blend(m.0[i], a.0[i], b.0[i]);
            }
        }
        Lanes(r)
    }
    lane_cmp!(/// `self < o` per lane (false for NaN).
        lt, <);
    lane_cmp!(/// `self <= o` per lane (false for NaN).
        le, <=);
    lane_cmp!(/// `self > o` per lane (false for NaN).
        gt, >);
    lane_cmp!(/// `self >= o` per lane (false for NaN).
        ge, >=);
    lane_cmp!(/// `self == o` per lane.
        eq_lanes, ==);
    lane_cmp!(/// `self != o` per lane (true for NaN).
        ne_lanes, !=);

    /// Every lane squared ([`Scalar::square`]: bit for bit `self * self`).
    #[inline(always)]
    pub fn square(self) -> Self {
        self.map(S::square)
    }

    /// Lane-wise [`Scalar::mul_small`]: the product, for factors at most 4
    /// in magnitude.
    #[inline(always)]
    pub fn mul_small(self, o: Self) -> Self {
        let mut r = self.0;
        for i in 0..W {
            r[i] = r[i].mul_small(o.0[i]);
        }
        Lanes(r)
    }

    /// Lane-wise [`Scalar::square_small`].
    #[inline(always)]
    pub fn square_small(self) -> Self {
        self.map(S::square_small)
    }

    /// Lane-wise [`Scalar::add_small`]: the sum, for sums at most 64 in
    /// magnitude.
    #[inline(always)]
    pub fn add_small(self, o: Self) -> Self {
        let mut r = self.0;
        for i in 0..W {
            r[i] = r[i].add_small(o.0[i]);
        }
        Lanes(r)
    }

    /// Lane-wise [`Scalar::sub_small`]: the difference, for differences at
    /// most 64 in magnitude.
    #[inline(always)]
    pub fn sub_small(self, o: Self) -> Self {
        let mut r = self.0;
        for i in 0..W {
            r[i] = r[i].sub_small(o.0[i]);
        }
        Lanes(r)
    }

    /// Applies `f` to every lane.
    #[inline(always)]
    pub fn map(self, f: impl Fn(S) -> S) -> Self {
        let mut r = self.0;
        for i in 0..W {
            r[i] = f(r[i]);
        }
        Lanes(r)
    }
    /// Each lane times `2^k[i]` ([`Scalar::mul_pow2`]).
    #[inline(always)]
    pub fn mul_pow2(self, k: [i32; W]) -> Self {
        let mut r = self.0;
        for i in 0..W {
            r[i] = r[i].mul_pow2(k[i]);
        }
        Lanes(r)
    }
    /// Square root per lane.
    #[inline(always)]
    pub fn sqrt(self) -> Self {
        if S::LANE_SQRT && W >= 4 {
            Lanes(S::sqrt_lanes(self.0))
        } else {
            self.map(S::sqrt)
        }
    }
    /// `self` raised to the power `e` per lane ([`Scalar::powf`]: for
    /// `self` in `[0, 1]` and `e >= 0`).
    #[inline(always)]
    pub fn powf(self, e: Self) -> Self {
        let mut r = self.0;
        for i in 0..W {
            r[i] = r[i].powf(e.0[i]);
        }
        Lanes(r)
    }
    /// [`Scalar::to_unorm8`] of every lane.
    #[inline(always)]
    pub fn to_unorm8(self) -> [u8; W] {
        let mut r = [0u8; W];
        for i in 0..W {
            r[i] = self.0[i].to_unorm8();
        }
        r
    }
    /// Absolute value per lane.
    #[inline(always)]
    pub fn abs(self) -> Self {
        self.map(S::abs)
    }
    /// Per-lane minimum ([`Scalar::min`] semantics).
    #[inline(always)]
    pub fn min(self, o: Self) -> Self {
        let mut r = self.0;
        for i in 0..W {
            r[i] = r[i].min(o.0[i]);
        }
        Lanes(r)
    }
    /// Per-lane maximum ([`Scalar::max`] semantics).
    #[inline(always)]
    pub fn max(self, o: Self) -> Self {
        let mut r = self.0;
        for i in 0..W {
            r[i] = r[i].max(o.0[i]);
        }
        Lanes(r)
    }
    /// `self / d` where `d != 0`, and `self` elsewhere: division that never
    /// divides by zero, for fixed-point scalars. Callers mask out the lanes
    /// whose divisor was zero.
    #[inline(always)]
    pub fn div_nonzero(self, d: Self) -> Self {
        let zero = d.eq_lanes(Self::zero());
        self / Self::select(zero, Self::splat(S::ONE), d)
    }
    /// `(self.div_nonzero(d), b.div_nonzero(d))`, bit for bit; in a scalar
    /// of limited range each lane's two quotients share the divisor's
    /// preparation ([`Scalar::div_pair`]), elsewhere two packed divisions.
    #[inline(always)]
    pub fn div_pair_nonzero(self, b: Self, d: Self) -> (Self, Self) {
        let zero = d.eq_lanes(Self::zero());
        let d = Self::select(zero, Self::splat(S::ONE), d);
        if !S::LIMITED_RANGE {
            return (self / d, b / d);
        }
        let (mut p, mut q) = (self, b);
        for l in 0..W {
            (p.0[l], q.0[l]) = S::div_pair(self.0[l], b.0[l], d.0[l]);
        }
        (p, q)
    }
}

macro_rules! lane_binop {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<S: Scalar, const W: usize> $tr for Lanes<S, W> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                let mut r = self.0;
                for i in 0..W {
                    r[i] = r[i] $op o.0[i];
                }
                Lanes(r)
            }
        }
        impl<S: Scalar, const W: usize> $tr<S> for Lanes<S, W> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: S) -> Self {
                let mut r = self.0;
                for i in 0..W {
                    r[i] = r[i] $op o;
                }
                Lanes(r)
            }
        }
    };
}
lane_binop!(Add, add, +);
lane_binop!(Sub, sub, -);
lane_binop!(Mul, mul, *);
lane_binop!(Div, div, /);

impl<S: Scalar, const W: usize> Neg for Lanes<S, W> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|v| -v)
    }
}

impl<S: Scalar, const W: usize> Default for Lanes<S, W> {
    fn default() -> Self {
        Self::zero()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn select_and_masks() {
        let a = Lanes::<f32, 4>([1.0, 2.0, 3.0, 4.0]);
        let b = Lanes::<f32, 4>::splat(0.0);
        let m = a.gt(Lanes::splat(2.5));
        assert_eq!(m.to_array(), [false, false, true, true]);
        assert_eq!(Lanes::select(m, a, b).0, [0.0, 0.0, 3.0, 4.0]);
        assert!(m.any() && !m.all() && !m.none());
        assert_eq!(m.count(), 2);
        assert_eq!((!m).to_array(), [true, true, false, false]);
        assert_eq!(m.and_not(Mask::from_array([false, false, true, false])).to_array(), [false, false, false, true]);
    }

    #[test]
    fn finite_clears_nan_and_infinities() {
        let a = Lanes::<f32, 4>([1.0, f32::NAN, f32::INFINITY, -f32::MAX]);
        assert_eq!(a.finite().to_array(), [true, false, false, true]);
        assert_eq!(Lanes::<f32, 1>([f32::NEG_INFINITY]).finite().to_array(), [false]);
    }

    /// `select` blends bit patterns: NaN payloads, signed zeros and
    /// subnormals come through untouched, at every width (the `f32` select is
    /// a bitwise blend, the fixed-point one a plain choice).
    #[test]
    fn select_keeps_exact_bits() {
        fn check<const W: usize>() {
            let odd = [f32::from_bits(0x7fc0_1234), -0.0, f32::from_bits(1), f32::NEG_INFINITY, 0.0];
            let a = Lanes::<f32, W>(core::array::from_fn(|i| odd[i % odd.len()]));
            let b = Lanes::<f32, W>(core::array::from_fn(|i| -(i as f32) - 0.5));
            let pick: [bool; W] = core::array::from_fn(|i| (i * 7) % 3 == 0);
            let r = Lanes::select(Mask::from_array(pick), a, b);
            for i in 0..W {
                let want = if pick[i] { a.0[i] } else { b.0[i] };
                assert_eq!(r.0[i].to_bits(), want.to_bits(), "lane {i} of {W}");
            }
            let fa = Lanes::<crate::Fixed, W>(core::array::from_fn(|i| crate::Fixed::from_f32(b.0[i])));
            let fb = Lanes::<crate::Fixed, W>::splat(crate::Fixed::ONE);
            let fr = Lanes::select(Mask::from_array(pick), fa, fb);
            for i in 0..W {
                assert_eq!(fr.0[i], if pick[i] { fa.0[i] } else { fb.0[i] });
            }
        }
        check::<1>();
        check::<3>();
        check::<4>();
        check::<8>();
        check::<16>();
    }

    /// The mask reductions agree with a plain count at every width,
    /// odd ones included.
    #[test]
    fn reductions_at_odd_and_wide_widths() {
        fn check<const W: usize>(seed: u32) {
            let mut x = seed;
            for _ in 0..64 {
                let bits: [bool; W] = core::array::from_fn(|_| {
                    x ^= x << 13;
                    x ^= x >> 17;
                    x ^= x << 5;
                    x & 4 != 0
                });
                let m = Mask::from_array(bits);
                let n = bits.iter().filter(|b| **b).count();
                assert_eq!(m.count() as usize, n);
                assert_eq!(m.any(), n > 0);
                assert_eq!(m.all(), n == W);
                assert_eq!(m.none(), n == 0);
            }
            assert!(Mask::<W>::splat(true).all() && Mask::<W>::splat(true).count() as usize == W);
        }
        check::<1>(1);
        check::<2>(2);
        check::<3>(3);
        check::<5>(5);
        check::<7>(7);
        check::<8>(8);
        check::<16>(16);
    }

    #[test]
    fn first_set_and_integer_equality() {
        let m = Mask::<4>::from_array([false, false, true, true]);
        assert_eq!(m.first_set(), Some(2));
        assert_eq!(Mask::<4>::splat(false).first_set(), None);
        assert_eq!(Mask::<1>::splat(true).first_set(), Some(0));
        assert_eq!(Mask::from_eq_u32(&[7, 3, 7, 9], 7).to_array(), [true, false, true, false]);
    }

    #[test]
    fn nan_compares_false() {
        let a = Lanes::<f32, 2>([f32::NAN, 1.0]);
        assert_eq!(a.lt(Lanes::splat(2.0)).to_array(), [false, true]);
        assert_eq!(a.ge(Lanes::splat(0.0)).to_array(), [false, true]);
    }

    #[test]
    fn div_nonzero_never_divides_by_zero() {
        let a = Lanes::<f32, 2>([3.0, 5.0]);
        let d = Lanes::<f32, 2>([0.0, 2.0]);
        assert_eq!(a.div_nonzero(d).0, [3.0, 2.5]);
    }
}
