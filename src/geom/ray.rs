//! Rays and ray packets.
//!
//! A [`RayPacket<S, W>`] is `W` rays in structure-of-arrays form. The single
//! ray is the width-1 packet ([`Ray<S>`]), so the scalar tracer and the packet
//! tracer are one and the same code.

use crate::geom::vec3::{Vec3, Vec3xW};
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;

/// `W` rays: origins and unit directions, structure of arrays.
#[derive(Clone, Copy, Debug)]
pub struct RayPacket<S, const W: usize> {
    /// Ray origins.
    pub origin: Vec3xW<S, W>,
    /// Ray directions, unit length in every active lane.
    pub dir: Vec3xW<S, W>,
}

/// A single ray: the width-1 packet.
pub type Ray<S> = RayPacket<S, 1>;

impl<S: Scalar, const W: usize> RayPacket<S, W> {
    /// A packet from origins and (not necessarily unit) directions.
    ///
    /// Directions are normalized. The returned mask clears every lane whose
    /// direction has zero length or whose numbers are not finite: such a ray
    /// is a defined "hits nothing" ray, never a NaN.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn new(origin: Vec3xW<S, W>, dir: Vec3xW<S, W>) -> (Self, Mask<W>) {
        let (d, ok) = dir.normalize();
        let ok = ok & origin.x.finite() & origin.y.finite() & origin.z.finite();
        let zero = Vec3::new(Lanes::zero(), Lanes::zero(), Lanes::zero());
        (RayPacket { origin: Vec3xW::select(ok, origin, zero), dir: d }, ok)
    }

    /// The ray of lane `i`.
    #[inline]
    pub fn lane(&self, i: usize) -> Ray<S> {
        let o = self.origin.lane(i);
        let d = self.dir.lane(i);
        RayPacket { origin: o.splat(), dir: d.splat() }
    }

    /// The points at distance `t` along each ray.
    #[inline(always)]
    pub fn at(&self, t: Lanes<S, W>) -> Vec3xW<S, W> {
        self.origin + self.dir.scale(t)
    }
}

impl<S: Scalar> Ray<S> {
    /// A single ray from an origin and a (not necessarily unit) direction.
    /// `None` when the direction has zero length or a number is not finite.
    pub fn single(origin: Vec3<S>, dir: Vec3<S>) -> Option<Self> {
        let (r, ok) = RayPacket::new(origin.splat(), dir.splat());
        if ok.get(0) {
            Some(r)
        } else {
            None
        }
    }
}

/// Up to two surface crossings of each ray with one primitive, inside the
/// query interval `(t_min, t_max)`, nearest first.
///
/// Closest-hit queries use the first valid root; shadow queries count
/// crossings (a sphere crossed through attenuates the light twice).
#[derive(Clone, Copy, Debug)]
pub struct Roots<S, const W: usize> {
    /// Nearer root.
    pub t0: Lanes<S, W>,
    /// Farther root.
    pub t1: Lanes<S, W>,
    /// Lanes where `t0` is a valid crossing in the interval.
    pub hit0: Mask<W>,
    /// Lanes where `t1` is a valid crossing in the interval.
    pub hit1: Mask<W>,
}

impl<S: Scalar, const W: usize> Roots<S, W> {
    /// No crossing in any lane.
    #[inline(always)]
    pub fn none() -> Self {
        Roots { t0: Lanes::splat(S::MAX), t1: Lanes::splat(S::MAX), hit0: Mask::splat(false), hit1: Mask::splat(false) }
    }

    /// Builds the result from two candidate roots (in any order) and the
    /// masks of lanes where each candidate exists, keeping only roots strictly
    /// inside `(t_min, t_max)` and ordering them nearest first.
    #[inline(always)]
    pub fn from_candidates(
        a: Lanes<S, W>,
        ok_a: Mask<W>,
        b: Lanes<S, W>,
        ok_b: Mask<W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
    ) -> Self {
        // Keep roots inside the open interval; NaN compares false and drops out.
        let va = ok_a & a.gt(t_min) & a.lt(t_max);
        let vb = ok_b & b.gt(t_min) & b.lt(t_max);
        // Swap so that t0 <= t1 wherever both exist.
        let swap = vb & (!va | b.lt(a));
        let t0 = Lanes::select(swap, b, a);
        let t1 = Lanes::select(swap, a, b);
        let hit0 = va | vb;
        let hit1 = va & vb;
        Roots {
            t0: Lanes::select(hit0, t0, Lanes::splat(S::MAX)),
            t1: Lanes::select(hit1, t1, Lanes::splat(S::MAX)),
            hit0,
            hit1,
        }
    }

    /// Builds the result from two roots already ordered (`near <= far`
    /// wherever `ok` is set), both existing where `ok` is set: cheaper than
    /// [`Roots::from_candidates`] because nothing needs swapping.
    #[inline(always)]
    pub fn from_ordered(
        near: Lanes<S, W>,
        far: Lanes<S, W>,
        ok: Mask<W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
    ) -> Self {
        let near_in = ok & near.gt(t_min) & near.lt(t_max);
        let far_in = ok & far.gt(t_min) & far.lt(t_max);
        // The first crossing is the near root if it is in the interval, else the far one.
        Roots {
            t0: Lanes::select(near_in, near, Lanes::select(far_in, far, Lanes::splat(S::MAX))),
            t1: Lanes::select(near_in & far_in, far, Lanes::splat(S::MAX)),
            hit0: near_in | far_in,
            hit1: near_in & far_in,
        }
    }

    /// The nearest crossing per lane and where one exists.
    #[inline(always)]
    pub fn nearest(&self) -> (Lanes<S, W>, Mask<W>) {
        (self.t0, self.hit0)
    }

    /// Number of crossings per lane (0, 1 or 2).
    #[inline(always)]
    pub fn count(&self, lane: usize) -> u32 {
        self.hit0.get(lane) as u32 + self.hit1.get(lane) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_direction_lane_is_inactive() {
        let o = Vec3::new(Lanes([0.0f32, 0.0]), Lanes([0.0, 0.0]), Lanes([0.0, 0.0]));
        let d = Vec3::new(Lanes([0.0f32, 2.0]), Lanes([0.0, 0.0]), Lanes([0.0, 0.0]));
        let (r, ok) = RayPacket::new(o, d);
        assert_eq!(ok.to_array(), [false, true]);
        assert_eq!(r.dir.lane(1), Vec3::new(1.0, 0.0, 0.0));
        assert!(Ray::single(Vec3::new(0.0f32, 0.0, 0.0), Vec3::ZERO).is_none());
        assert!(Ray::single(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0)).is_none());
    }

    #[test]
    fn roots_are_ordered_and_clipped() {
        let r = Roots::<f32, 4>::from_candidates(
            Lanes([3.0, 1.0, -1.0, 5.0]),
            Mask::splat(true),
            Lanes([1.0, 3.0, 2.0, 6.0]),
            Mask::from_array([true, true, true, false]),
            Lanes::splat(0.0),
            Lanes::splat(10.0),
        );
        assert_eq!(r.hit0.to_array(), [true, true, true, true]);
        assert_eq!(r.hit1.to_array(), [true, true, false, false]);
        assert_eq!(r.t0.0, [1.0, 1.0, 2.0, 5.0]);
        assert_eq!(r.t1.0[..2], [3.0, 3.0]);
    }
}
