//! Three-component vectors, for single values ([`Vec3<S>`]) and for packets
//! ([`Vec3<Lanes<S, W>>`], structure of arrays: three lane vectors).
//!
//! The same generic operations serve both forms, so scalar set-up code and
//! packet kernels share one definition of `dot`, `cross` and friends.

use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;
use core::ops::{Add, Mul, Neg, Sub};

/// A vector with components of type `T` (a scalar, or lanes of scalars).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Vec3<T> {
    /// x component.
    pub x: T,
    /// y component.
    pub y: T,
    /// z component.
    pub z: T,
}

/// A packet of vectors: `W` vectors stored as three lane arrays.
pub type Vec3xW<S, const W: usize> = Vec3<Lanes<S, W>>;

impl<T> Vec3<T> {
    /// A vector from its components.
    #[inline(always)]
    pub const fn new(x: T, y: T, z: T) -> Self {
        Vec3 { x, y, z }
    }
}

impl<T: Copy + Add<Output = T> + Sub<Output = T> + Mul<Output = T>> Vec3<T> {
    /// Dot product, summed as `x + y + z` (this order, always).
    #[inline(always)]
    pub fn dot(self, o: Self) -> T {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Cross product.
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        Vec3::new(self.y * o.z - self.z * o.y, self.z * o.x - self.x * o.z, self.x * o.y - self.y * o.x)
    }
    /// Squared length.
    #[inline(always)]
    pub fn length_squared(self) -> T {
        self.dot(self)
    }
    /// Every component multiplied by `s`.
    #[inline(always)]
    pub fn scale(self, s: T) -> Self {
        Vec3::new(self.x * s, self.y * s, self.z * s)
    }
    /// Component-wise product.
    #[inline(always)]
    pub fn mul_elem(self, o: Self) -> Self {
        Vec3::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
}

impl<T: Add<Output = T>> Add for Vec3<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Vec3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl<T: Sub<Output = T>> Sub for Vec3<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Vec3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl<T: Neg<Output = T>> Neg for Vec3<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Vec3::new(-self.x, -self.y, -self.z)
    }
}

impl<S: Scalar> Vec3<S> {
    /// The zero vector.
    pub const ZERO: Self = Vec3::new(S::ZERO, S::ZERO, S::ZERO);

    /// A vector from `f32` components (set-up time).
    #[inline]
    pub fn from_f32(x: f32, y: f32, z: f32) -> Self {
        Vec3::new(S::from_f32(x), S::from_f32(y), S::from_f32(z))
    }
    /// The components as `f32` (for reports and tests).
    #[inline]
    pub fn to_f32(self) -> [f32; 3] {
        [self.x.to_f32(), self.y.to_f32(), self.z.to_f32()]
    }
    /// Length.
    #[inline(always)]
    pub fn length(self) -> S {
        self.length_squared().sqrt()
    }
    /// Unit vector in the same direction; the zero vector (and any vector
    /// whose length is not a positive number) gives the zero vector. The
    /// packet form [`Vec3xW::normalize`] at one lane.
    #[inline]
    pub fn normalize_or_zero(self) -> Self {
        self.splat::<1>().normalize().0.lane(0)
    }
    /// The unit vector the tracer makes of a hit's geometric normal
    /// ([`Vec3xW::normalize_sparse`], zero where it has no length), for
    /// primitives whose normal is one vector: stored with the primitive, it
    /// spares a square root and a division per hit, with the same bits at
    /// every packet width (normalising is lane-wise).
    pub fn hit_normal(self) -> Self {
        self.splat::<1>().normalize_sparse().0.lane(0)
    }
    /// Whether every component is finite.
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
    /// Largest absolute component.
    #[inline(always)]
    pub fn max_abs(self) -> S {
        self.x.abs().max(self.y.abs()).max(self.z.abs())
    }
    /// Component-wise minimum.
    #[inline]
    pub fn min_elem(self, o: Self) -> Self {
        Vec3::new(self.x.min(o.x), self.y.min(o.y), self.z.min(o.z))
    }
    /// Component-wise maximum.
    #[inline]
    pub fn max_elem(self, o: Self) -> Self {
        Vec3::new(self.x.max(o.x), self.y.max(o.y), self.z.max(o.z))
    }
    /// Component `axis` (0 = x, 1 = y, anything else = z).
    #[inline(always)]
    pub fn axis(self, axis: usize) -> S {
        match axis {
            0 => self.x,
            1 => self.y,
            _ => self.z,
        }
    }
    /// The same vector in every lane of a packet.
    #[inline(always)]
    pub fn splat<const W: usize>(self) -> Vec3xW<S, W> {
        Vec3::new(Lanes::splat(self.x), Lanes::splat(self.y), Lanes::splat(self.z))
    }
    /// An orthonormal basis `(u, v)` completing the unit vector `self` (as
    /// `w`) to a right-handed frame `u × v = w`. Deterministic: the same
    /// input always gives the same frame.
    pub fn orthonormal_basis(self) -> (Self, Self) {
        // Pick the world axis least aligned with w, so the cross product is
        // well conditioned.
        let a = if self.x.abs() <= self.y.abs() && self.x.abs() <= self.z.abs() {
            Vec3::new(S::ONE, S::ZERO, S::ZERO)
        } else if self.y.abs() <= self.z.abs() {
            Vec3::new(S::ZERO, S::ONE, S::ZERO)
        } else {
            Vec3::new(S::ZERO, S::ZERO, S::ONE)
        };
        let u = a.cross(self).normalize_or_zero();
        let v = self.cross(u);
        (u, v)
    }
}

/// A dot product's partial sum: [`Lanes::add_small`] if `SMALL`, else the
/// sum (a const parameter, not a closure: a closure for the sum changed the
/// Cortex-M55's packet code, 0.3 % more instructions at width 4).
#[inline(always)]
fn add<S: Scalar, const W: usize, const SMALL: bool>(a: Lanes<S, W>, b: Lanes<S, W>) -> Lanes<S, W> {
    if SMALL {
        a.add_small(b)
    } else {
        a + b
    }
}

impl<S: Scalar, const W: usize> Vec3xW<S, W> {
    /// The vector of lane `i`.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> Vec3<S> {
        Vec3::new(self.x.0[i], self.y.0[i], self.z.0[i])
    }
    /// Stores `v` into lane `i`.
    #[inline(always)]
    pub fn set_lane(&mut self, i: usize, v: Vec3<S>) {
        self.x.0[i] = v.x;
        self.y.0[i] = v.y;
        self.z.0[i] = v.z;
    }
    /// Squared length of every lane, bit for bit [`Vec3::length_squared`]
    /// (the same sum in the same order), from [`Scalar::square`]s.
    #[inline(always)]
    pub fn norm_squared(self) -> Lanes<S, W> {
        self.x.square() + self.y.square() + self.z.square()
    }
    /// [`Vec3xW::norm_squared`] without the terms of components that are
    /// zero in every lane where [`Scalar::SPARSE_PRODUCTS`] holds (bit for
    /// bit `self.dot_sparse(self)`).
    #[inline(always)]
    pub fn norm_squared_sparse(self) -> Lanes<S, W> {
        if S::SPARSE_PRODUCTS {
            let zero = Lanes::zero();
            let (zx, zy, zz) = (self.x.eq_lanes(zero).all(), self.y.eq_lanes(zero).all(), self.z.eq_lanes(zero).all());
            // Left to right, as `dot` adds.
            let mut sum = if zx { zero } else { self.x.square() };
            if !zy {
                sum = sum + self.y.square();
            }
            if !zz {
                sum = sum + self.z.square();
            }
            sum
        } else {
            self.norm_squared()
        }
    }
    /// [`Vec3::dot`] of vectors whose components are at most 4 in
    /// magnitude, by [`Scalar::mul_small`], and [`Scalar::add_small`] (three
    /// products of at most 16; on RV32IMAC one `add` where the saturating
    /// sum is four): the same bits. (Armv6-M keeps the saturating sum,
    /// which tests the overflow flag in one branch there: with
    /// `add_small` its `fixed32` frame was 0.23 M instructions longer.)
    #[inline(always)]
    pub fn dot_small(self, o: Self) -> Lanes<S, W> {
        if cfg!(armv6m) {
            self.x.mul_small(o.x) + self.y.mul_small(o.y) + self.z.mul_small(o.z)
        } else {
            self.x.mul_small(o.x).add_small(self.y.mul_small(o.y)).add_small(self.z.mul_small(o.z))
        }
    }
    /// [`Vec3xW::norm_squared`] of a vector whose components are at most 4
    /// in magnitude, by [`Scalar::square_small`] (and summed as
    /// [`Vec3xW::dot_small`] sums): the same bits.
    #[inline(always)]
    pub fn norm_squared_small(self) -> Lanes<S, W> {
        if cfg!(armv6m) {
            self.x.square_small() + self.y.square_small() + self.z.square_small()
        } else {
            self.x.square_small().add_small(self.y.square_small()).add_small(self.z.square_small())
        }
    }
    /// Lane-wise `select` of whole vectors.
    #[inline(always)]
    pub fn select(m: Mask<W>, a: Self, b: Self) -> Self {
        Vec3::new(Lanes::select(m, a.x, b.x), Lanes::select(m, a.y, b.y), Lanes::select(m, a.z, b.z))
    }
    /// Per-lane unit vectors; lanes whose length is zero (or not finite)
    /// become zero vectors and are cleared in the returned mask.
    #[inline(always)]
    pub fn normalize(self) -> (Self, Mask<W>) {
        let (n, _, ok) = self.normalize_with_length();
        (n, ok)
    }
    /// [`Vec3xW::normalize`] and each lane's length: the one the unit
    /// vector was scaled by, brought back to the vector's own scale. With
    /// [`Scalar::NORMALIZE_PRESCALE`] that is the prescaled length (with
    /// [`Scalar::NORMALIZE_BY_INVERSE_SQRT`], the squared length times its
    /// reciprocal root) times `2^−k` (one rounding more, for `k > 0`;
    /// saturating past the range), which spares a second square root;
    /// otherwise `length_squared().sqrt()` bit for bit. Meaningless in the
    /// lanes the mask clears.
    #[inline(always)]
    pub fn normalize_with_length(self) -> (Self, Lanes<S, W>, Mask<W>) {
        self.normalize_impl::<false>()
    }
    /// [`Vec3xW::normalize`] for vectors that are often axis-aligned (the
    /// normals of planes, polygons and boxes): the squares and products of
    /// components zero in every lane are left out where
    /// [`Scalar::SPARSE_PRODUCTS`] holds ([`Vec3xW::dot_sparse`]); the same
    /// bits.
    #[inline(always)]
    pub fn normalize_sparse(self) -> (Self, Mask<W>) {
        let (n, _, ok) = self.normalize_impl::<true>();
        (n, ok)
    }
    /// The normalisation, with or without the sparse products.
    #[inline(always)]
    fn normalize_impl<const SPARSE: bool>(self) -> (Self, Lanes<S, W>, Mask<W>) {
        // A scalar's shorter route where every lane takes it (the same bits).
        if S::NORMALIZE_PRESCALE {
            let (mut n, mut len) = (self, Lanes::zero());
            let mut every = true;
            for l in 0..W {
                let Some(([x, y, z], d)) = S::unit_and_length([self.x.0[l], self.y.0[l], self.z.0[l]]) else {
                    every = false;
                    break;
                };
                n.set_lane(l, Vec3::new(x, y, z));
                len.0[l] = d;
            }
            if every {
                return (n, len, Mask::splat(true));
            }
        }
        self.normalize_general::<SPARSE>()
    }

    /// [`Vec3xW::normalize_impl`]'s lane code, for every scalar and vector.
    #[inline(always)]
    pub(crate) fn normalize_general<const SPARSE: bool>(self) -> (Self, Lanes<S, W>, Mask<W>) {
        // Fixed point: the largest component brought near 1 first, exactly
        // (see `Scalar::NORMALIZE_PRESCALE`).
        let (v, k) = if S::NORMALIZE_PRESCALE {
            let m = self.x.abs().max(self.y.abs()).max(self.z.abs());
            let k = m.0.map(S::normalizing_exponent);
            (Vec3::new(self.x.mul_pow2(k), self.y.mul_pow2(k), self.z.mul_pow2(k)), k)
        } else {
            (self, [0; W])
        };
        let squared = if SPARSE { v.norm_squared_sparse() } else { v.norm_squared() };
        let (len, inv, ok) = if S::NORMALIZE_BY_INVERSE_SQRT {
            // Fixed point: one reciprocal root, then the length from it
            // (|v|²·(1/|v|) = |v|, one product).
            let ok = squared.gt(Lanes::zero());
            let inv = squared.map(S::inverse_sqrt);
            (squared * inv, inv, ok)
        } else {
            let len = squared.sqrt();
            let ok = len.gt(Lanes::zero()) & len.finite();
            (len, Lanes::splat(S::ONE).div_nonzero(Lanes::select(ok, len, Lanes::splat(S::ZERO))), ok)
        };
        let n = if SPARSE { v.scale_sparse(inv) } else { v.scale(inv) };
        let length = if S::NORMALIZE_PRESCALE { len.mul_pow2(k.map(|k| -k)) } else { len };
        (Self::select(ok, n, Vec3::new(Lanes::zero(), Lanes::zero(), Lanes::zero())), length, ok)
    }
    /// Component `axis` (0 = x, 1 = y, anything else = z) of every lane.
    #[inline(always)]
    pub fn axis(&self, axis: usize) -> Lanes<S, W> {
        match axis {
            0 => self.x,
            1 => self.y,
            _ => self.z,
        }
    }
    /// Every component multiplied by the lanes `s` (a packet of vectors
    /// splatted from one vector, scaled per lane).
    #[inline(always)]
    pub fn scale_lanes(self, s: Lanes<S, W>) -> Self {
        Vec3::new(self.x * s, self.y * s, self.z * s)
    }
    /// Adds the scalar vector `v` to every lane.
    #[inline(always)]
    pub fn add_splat(self, v: Vec3<S>) -> Self {
        Vec3::new(self.x + v.x, self.y + v.y, self.z + v.z)
    }
    /// Subtracts the scalar vector `v` from every lane.
    #[inline(always)]
    pub fn sub_splat(self, v: Vec3<S>) -> Self {
        Vec3::new(self.x - v.x, self.y - v.y, self.z - v.z)
    }
    /// The lanes whose vector lies in the box `[lo, hi]` (every component
    /// between its bounds, both included; NaN in none), as one loop with
    /// each lane's six comparisons in its body, so that a vectoriser keeps
    /// the lanes in whole registers (lane-wise `ge`/`le` masks combined
    /// with `&` were compared lane by lane on the Cortex-M55).
    #[inline(always)]
    pub fn in_box(&self, lo: Vec3<S>, hi: Vec3<S>) -> Mask<W> {
        let mut m = [false; W];
        for (i, m) in m.iter_mut().enumerate() {
            let (x, y, z) = (self.x.0[i], self.y.0[i], self.z.0[i]);
            *m = (x >= lo.x) & (x <= hi.x) & (y >= lo.y) & (y <= hi.y) & (z >= lo.z) & (z <= hi.z);
        }
        Mask::from_array(m)
    }
    /// Dot product of every lane with the scalar vector `v`.
    ///
    /// Where [`Scalar::SPARSE_PRODUCTS`] holds, the terms of `v`'s zero
    /// components are left out (one branch each, the same for every lane):
    /// they are exactly zero and add nothing, so the sum is the same, bit
    /// for bit, and an axis-aligned `v` costs one product, not three.
    #[inline(always)]
    pub fn dot_splat(self, v: Vec3<S>) -> Lanes<S, W> {
        self.dot_splat_by::<false>(v, |a, b| a * b)
    }
    /// [`Vec3xW::dot_splat`] of vectors whose components are at most 4 in
    /// magnitude (unit vectors), by [`Scalar::mul_small`] and
    /// [`Scalar::add_small`] (three products of at most 16): the same bits.
    #[inline(always)]
    pub fn dot_splat_small(self, v: Vec3<S>) -> Lanes<S, W> {
        self.dot_splat_by::<true>(v, Lanes::mul_small)
    }
    /// [`Vec3xW::dot_splat`] with the lane product `mul`, summed by
    /// [`Lanes::add_small`] if `SMALL`.
    #[inline(always)]
    fn dot_splat_by<const SMALL: bool>(
        self,
        v: Vec3<S>,
        mul: impl Fn(Lanes<S, W>, Lanes<S, W>) -> Lanes<S, W>,
    ) -> Lanes<S, W> {
        let m = |a: Lanes<S, W>, b: S| mul(a, Lanes::splat(b));
        if S::SPARSE_PRODUCTS {
            // Left to right, as `x·vx + y·vy + z·vz` adds (`0 + p = p`).
            let mut sum = if v.x != S::ZERO { m(self.x, v.x) } else { Lanes::zero() };
            if v.y != S::ZERO {
                sum = add::<S, W, SMALL>(sum, m(self.y, v.y));
            }
            if v.z != S::ZERO {
                sum = add::<S, W, SMALL>(sum, m(self.z, v.z));
            }
            sum
        } else {
            let xy = add::<S, W, SMALL>(m(self.x, v.x), m(self.y, v.y));
            add::<S, W, SMALL>(xy, m(self.z, v.z))
        }
    }
    /// [`Vec3::dot`] lane by lane, leaving out (where
    /// [`Scalar::SPARSE_PRODUCTS`] holds) the terms of components that are
    /// zero in every lane of `self`: they are exactly zero and add nothing
    /// (`0 + p = p`), so the sum is the same, bit for bit. For normals,
    /// which are often axis-aligned (floors, walls, box faces): one compare
    /// instead of a product.
    #[inline(always)]
    pub fn dot_sparse(self, o: Self) -> Lanes<S, W> {
        self.dot_sparse_by::<false>(o, |a, b| a * b)
    }
    /// [`Vec3xW::dot_sparse`] of vectors whose components are at most 4 in
    /// magnitude (unit vectors), by [`Scalar::mul_small`] and
    /// [`Scalar::add_small`]: the same bits.
    #[inline(always)]
    pub fn dot_sparse_small(self, o: Self) -> Lanes<S, W> {
        self.dot_sparse_by::<true>(o, Lanes::mul_small)
    }
    /// [`Vec3xW::dot_sparse`] with the lane product `mul`, summed by
    /// [`Lanes::add_small`] if `SMALL`.
    #[inline(always)]
    fn dot_sparse_by<const SMALL: bool>(
        self,
        o: Self,
        mul: impl Fn(Lanes<S, W>, Lanes<S, W>) -> Lanes<S, W>,
    ) -> Lanes<S, W> {
        if S::SPARSE_PRODUCTS {
            let zero = Lanes::zero();
            let (zx, zy, zz) = (self.x.eq_lanes(zero).all(), self.y.eq_lanes(zero).all(), self.z.eq_lanes(zero).all());
            // Left to right, as `dot` adds.
            let mut sum = if zx { zero } else { mul(self.x, o.x) };
            if !zy {
                sum = add::<S, W, SMALL>(sum, mul(self.y, o.y));
            }
            if !zz {
                sum = add::<S, W, SMALL>(sum, mul(self.z, o.z));
            }
            sum
        } else {
            let xy = add::<S, W, SMALL>(mul(self.x, o.x), mul(self.y, o.y));
            add::<S, W, SMALL>(xy, mul(self.z, o.z))
        }
    }
    /// [`Vec3::scale`] lane by lane, a component that is zero in every lane
    /// staying zero without its products where [`Scalar::SPARSE_PRODUCTS`]
    /// holds (`0·s = 0` exactly: the same bits).
    #[inline(always)]
    pub fn scale_sparse(self, s: Lanes<S, W>) -> Self {
        self.scale_sparse_by(s, |v, s| v * s)
    }
    /// [`Vec3xW::scale_sparse`] of a vector and a factor at most 4 in
    /// magnitude (a unit normal and twice a cosine), by
    /// [`Scalar::mul_small`]: the same bits.
    #[inline(always)]
    pub fn scale_sparse_small(self, s: Lanes<S, W>) -> Self {
        self.scale_sparse_by(s, Lanes::mul_small)
    }
    /// [`Vec3xW::scale_sparse`] with the lane product `mul`.
    #[inline(always)]
    fn scale_sparse_by(self, s: Lanes<S, W>, mul: impl Fn(Lanes<S, W>, Lanes<S, W>) -> Lanes<S, W>) -> Self {
        if S::SPARSE_PRODUCTS {
            let zero = Lanes::zero();
            let c = |v: Lanes<S, W>| if v.eq_lanes(zero).all() { zero } else { mul(v, s) };
            Vec3::new(c(self.x), c(self.y), c(self.z))
        } else {
            self.scale(s)
        }
    }
    /// [`Vec3::scale`] lane by lane, but `self` itself where every lane of
    /// `s` is exactly one (`x·1 = x` in every scalar: the same bits) and
    /// [`Scalar::SPARSE_PRODUCTS`] says a compare is cheaper than a
    /// product: the weights of camera rays on opaque surfaces.
    #[inline(always)]
    pub fn scale_unless_one(self, s: Lanes<S, W>) -> Self {
        if S::SPARSE_PRODUCTS && s.eq_lanes(Lanes::splat(S::ONE)).all() {
            self
        } else {
            self.scale(s)
        }
    }
    /// The scalar vector `v` times every lane of `s`, added to `self`:
    /// `self + v·s`. Where [`Scalar::SPARSE_PRODUCTS`] holds, `v`'s zero
    /// components add nothing (`p + 0 = p` and `0·s = 0` exactly), so they
    /// are left out, bit for bit the same.
    #[inline(always)]
    pub fn add_splat_scaled(self, v: Vec3<S>, s: Lanes<S, W>) -> Self {
        if S::SPARSE_PRODUCTS {
            let term = |acc: Lanes<S, W>, c: S| if c != S::ZERO { acc + Lanes::splat(c) * s } else { acc };
            Vec3::new(term(self.x, v.x), term(self.y, v.y), term(self.z, v.z))
        } else {
            self + v.splat::<W>().scale(s)
        }
    }
    /// [`Vec3xW::add_splat_scaled`] where `v`'s components and the lanes of
    /// `s` are at most 4 in magnitude and every sum at most 64, by
    /// [`Scalar::mul_small`] and [`Scalar::add_small`]: the same bits.
    #[inline(always)]
    pub fn add_splat_scaled_small(self, v: Vec3<S>, s: Lanes<S, W>) -> Self {
        let term = |acc: Lanes<S, W>, c: S| {
            if S::SPARSE_PRODUCTS && c == S::ZERO {
                acc
            } else {
                acc.add_small(Lanes::splat(c).mul_small(s))
            }
        };
        Vec3::new(term(self.x, v.x), term(self.y, v.y), term(self.z, v.z))
    }
}

impl<T: crate::num::bake::Bake> crate::num::bake::Bake for Vec3<T> {
    fn bake(&self, w: &mut dyn core::fmt::Write) -> core::fmt::Result {
        crate::num::bake::call(w, "raypack::geom::vec3::Vec3::new", &[&self.x, &self.y, &self.z])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cross_is_right_handed() {
        let x = Vec3::new(1.0f32, 0.0, 0.0);
        let y = Vec3::new(0.0f32, 1.0, 0.0);
        assert_eq!(x.cross(y), Vec3::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn normalize_zero_is_zero() {
        assert_eq!(Vec3::<f32>::ZERO.normalize_or_zero(), Vec3::ZERO);
        let p: Vec3xW<f32, 2> = Vec3::new(Lanes([0.0, 3.0]), Lanes([0.0, 4.0]), Lanes([0.0, 0.0]));
        let (n, ok) = p.normalize();
        assert_eq!(ok.to_array(), [false, true]);
        assert_eq!(n.lane(0), Vec3::ZERO);
        assert_eq!(n.lane(1), Vec3::new(0.6, 0.8, 0.0));
    }

    #[test]
    fn in_box_is_the_six_comparisons_of_each_lane() {
        let (lo, hi) = (Vec3::new(-1.0f32, 0.0, 0.5), Vec3::new(1.0, 0.0, 2.0));
        // Inside, on each bound, just outside each bound, NaN in each component.
        let pts = [
            (Vec3::new(0.0, 0.0, 1.0), true),
            (Vec3::new(-1.0, 0.0, 0.5), true),
            (Vec3::new(1.0, 0.0, 2.0), true),
            (Vec3::new(-1.0000001, 0.0, 1.0), false),
            (Vec3::new(1.0000001, 0.0, 1.0), false),
            (Vec3::new(0.0, -1e-30, 1.0), false),
            (Vec3::new(0.0, 1e-30, 1.0), false),
            (Vec3::new(0.0, 0.0, 0.4999999), false),
            (Vec3::new(0.0, 0.0, 2.0000002), false),
            (Vec3::new(f32::NAN, 0.0, 1.0), false),
            (Vec3::new(0.0, f32::NAN, 1.0), false),
            (Vec3::new(0.0, 0.0, f32::NAN), false),
        ];
        for chunk in pts.chunks(4) {
            let mut p = Vec3xW::<f32, 4>::new(Lanes::zero(), Lanes::zero(), Lanes::zero());
            for (i, (v, _)) in chunk.iter().enumerate() {
                p.set_lane(i, *v);
            }
            let m = p.in_box(lo, hi);
            for (i, (v, inside)) in chunk.iter().enumerate() {
                assert_eq!(m.get(i), *inside, "{v:?}");
            }
        }
    }

    #[test]
    fn basis_is_orthonormal_and_right_handed() {
        for w in [Vec3::new(0.0f32, 0.0, 1.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 2.0, -3.0).normalize_or_zero()]
        {
            let (u, v) = w.orthonormal_basis();
            assert!((u.length() - 1.0).abs() < 1e-6);
            assert!((v.length() - 1.0).abs() < 1e-6);
            assert!(u.dot(v).abs() < 1e-6 && u.dot(w).abs() < 1e-6);
            assert!((u.cross(v) - w).length() < 1e-6);
        }
    }
}
