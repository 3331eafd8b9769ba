//! Infinite plane `Ax + By + Cz + D = 0`.

use super::error::GeometryError;
use crate::geom::ray::{RayPacket, Roots};
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::Vec3;
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;

/// An infinite plane, stored with a unit normal: `n·x + d = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane<S> {
    normal: Vec3<S>,
    d: S,
    /// The normal of a hit: `normal` normalised again as the tracer
    /// normalises every geometric normal ([`Vec3::hit_normal`]), worked out
    /// once here rather than at every hit.
    hit_normal: Vec3<S>,
}

crate::num::bake::bake_struct!("raypack::geom::primitives::Plane", Plane<S> { normal: Vec3<S>, d: S, hit_normal: Vec3<S> });

impl<S: Scalar> Plane<S> {
    /// The plane `Ax + By + Cz + D = 0`; `(A, B, C)` must not be zero.
    pub fn from_coefficients(a: S, b: S, c: S, d: S) -> Result<Self, GeometryError> {
        let n = Vec3::new(a, b, c);
        if !n.is_finite() || !d.is_finite() {
            return Err(GeometryError::NonFinite);
        }
        let len = n.length();
        if !(len > S::ZERO) || !len.is_finite() {
            return Err(GeometryError::ZeroLengthAxis);
        }
        let inv = S::ONE / len;
        Ok(Plane::with_normal(n.scale(inv), d * inv))
    }

    /// The plane through `point` with normal `normal` (any non-zero length).
    pub fn from_point_normal(point: Vec3<S>, normal: Vec3<S>) -> Result<Self, GeometryError> {
        if !point.is_finite() {
            return Err(GeometryError::NonFinite);
        }
        let n = normal.normalize_or_zero();
        if n == Vec3::ZERO {
            return Err(if normal.is_finite() { GeometryError::ZeroLengthAxis } else { GeometryError::NonFinite });
        }
        Ok(Plane::with_normal(n, -n.dot(point)))
    }

    /// The plane `normal·x + d = 0` (unit `normal`).
    fn with_normal(normal: Vec3<S>, d: S) -> Self {
        Plane { normal, d, hit_normal: normal.hit_normal() }
    }

    /// The same plane in the frame of `sim`, with scalar `T`: with
    /// `x = x'/s + o`, `n·x + d = 0` becomes `n·x' + s·(d + n·o) = 0`.
    pub fn similar<T: Scalar>(&self, sim: &Similarity) -> Plane<T> {
        Plane::with_normal(sim.direction(self.normal), T::from_f32(moved_offset(self.normal, self.d, sim)))
    }

    /// Unit normal.
    pub fn normal_vector(&self) -> Vec3<S> {
        self.normal
    }
    /// The normal of every hit: the unit normal as the tracer normalises
    /// geometric normals ([`Vec3::hit_normal`]).
    #[inline(always)]
    pub fn hit_normal(&self) -> Vec3<S> {
        self.hit_normal
    }
    /// Offset `d` of `n·x + d = 0` for the unit normal.
    pub fn offset(&self) -> S {
        self.d
    }

    /// Crossing of each active ray with the plane inside `(t_min, t_max)`.
    // Forced inline into the query loops except on Armv6-M (Cortex-M0/M0+,
    // the one target without 32-bit atomics), where the copies would not fit
    // a small flash: there each kernel is one function per packet width.
    #[cfg_attr(all(not(debug_assertions), not(armv6m)), inline(always))]
    pub fn roots<const W: usize>(
        &self,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Roots<S, W> {
        plane_crossing(self.normal, self.d, ray, t_min, t_max, active)
    }

    /// Normal at any point (unit).
    #[inline]
    pub fn normal(&self, _p: Vec3<S>) -> Vec3<S> {
        self.normal
    }
}

/// The crossing of rays with the plane `n·x + d = 0`, shared with polygons.
/// Rays parallel to the plane (`n·dir = 0`) miss.
#[inline(always)]
pub(crate) fn plane_crossing<S: Scalar, const W: usize>(
    n: Vec3<S>,
    d: S,
    ray: &RayPacket<S, W>,
    t_min: Lanes<S, W>,
    t_max: Lanes<S, W>,
    active: Mask<W>,
) -> Roots<S, W> {
    // Rate at which the signed distance changes along the ray (a unit
    // direction and a unit normal: products of small factors).
    let denom = ray.dir.dot_splat_small(n);
    let valid = active & denom.ne_lanes(Lanes::zero());
    if valid.none() {
        return Roots::none();
    }
    // Signed distance of the origin, divided by the rate.
    let dist = ray.origin.dot_splat(n) + d;
    // The crossing lies ahead (t = −dist/rate > 0) only where the distance
    // and the rate have opposite signs: elsewhere the quotient would be at
    // most 0 and fail `t > t_min` for the usual `t_min ≥ 0`, so those lanes
    // skip the division (a long routine in fixed point and in soft float)
    // with the same result. On x86, where a division is one instruction,
    // the extra test and branch cost more than they save (gears-2).
    #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
    let valid = {
        let zero = Lanes::zero();
        let ahead = (dist.gt(zero) & denom.lt(zero)) | (dist.lt(zero) & denom.gt(zero)) | t_min.lt(zero);
        let valid = valid & ahead;
        if valid.none() {
            return Roots::none();
        }
        valid
    };
    let t = (-dist).div_nonzero(denom);
    Roots::from_candidates(t, valid, t, Mask::splat(false), t_min, t_max)
}

/// The offset `d` of the plane `n·x + d = 0` (unit `n`) in the frame of
/// `sim`: `s·(d + n·o)`, in `f32`.
pub(crate) fn moved_offset<S: Scalar>(n: Vec3<S>, d: S, sim: &Similarity) -> f32 {
    let [nx, ny, nz] = n.to_f32();
    let [ox, oy, oz] = sim.origin;
    (d.to_f32() + (nx * ox + ny * oy + nz * oz)) * sim.scale
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::primitives::test_util::*;
    use crate::geom::primitives::Shape;

    #[test]
    fn analytic_hit_both_sides() {
        let p = Plane::from_coefficients(0.0f32, 0.0, 2.0, -2.0).unwrap(); // z = 1
        {
            assert_eq!(hits(&Shape::Plane(p), [0.0, 0.0, -3.0], [0.0, 0.0, 1.0]), vec![4.0]);
            assert_eq!(hits(&Shape::Plane(p), [0.0, 0.0, 5.0], [0.0, 0.0, -1.0]), vec![4.0]);
        }
    }

    #[test]
    fn parallel_and_behind_miss() {
        let p = Plane::from_point_normal(Vec3::new(0.0f32, 0.0, 1.0), Vec3::new(0.0, 0.0, 3.0)).unwrap();
        {
            assert!(hits(&Shape::Plane(p), [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]).is_empty());
            assert!(hits(&Shape::Plane(p), [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]).is_empty());
            assert!(hits(&Shape::Plane(p), [0.0, 0.0, 2.0], [0.0, 0.0, 1.0]).is_empty());
        }
    }

    #[test]
    fn a_crossing_behind_the_origin_counts_only_for_a_negative_t_min() {
        // z = 1, the ray leaving it upwards from z = 3: the crossing is at t = −2.
        let p = Shape::Plane(Plane::from_coefficients(0.0f32, 0.0, 1.0, -1.0).unwrap());
        assert_eq!(first_after(&p, 0.0, [0.0, 0.0, 3.0], [0.0, 0.0, 1.0]), None);
        assert_eq!(first_after(&p, -10.0, [0.0, 0.0, 3.0], [0.0, 0.0, 1.0]), Some(-2.0));
        assert_eq!(first_after(&p, -1.0, [0.0, 0.0, 3.0], [0.0, 0.0, 1.0]), None);
        // On the plane: t = 0, kept only below 0.
        assert_eq!(first_after(&p, 0.0, [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]), None);
        assert_eq!(first_after(&p, -1.0, [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]), Some(0.0));
    }

    #[test]
    fn degenerate_input_is_rejected() {
        assert_eq!(Plane::from_coefficients(0.0f32, 0.0, 0.0, 1.0), Err(GeometryError::ZeroLengthAxis));
        assert_eq!(Plane::from_coefficients(f32::NAN, 0.0, 1.0, 1.0), Err(GeometryError::NonFinite));
        assert_eq!(
            Plane::from_point_normal(Vec3::new(0.0f32, 0.0, 0.0), Vec3::ZERO),
            Err(GeometryError::ZeroLengthAxis)
        );
    }
}
