//! Oriented box: centre, half-extents and an orthonormal frame.

use super::aabox::{face_normals, slab_roots, LEAVE_EARLY};
use super::error::GeometryError;
use crate::geom::ray::{RayPacket, Roots};
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::{Vec3, Vec3xW};
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;

/// A box with its own axes `u`, `v`, `w = u × v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrientedBox<S> {
    center: Vec3<S>,
    half: Vec3<S>,
    u: Vec3<S>,
    v: Vec3<S>,
    w: Vec3<S>,
}

crate::num::bake::bake_struct!("raypack::geom::primitives::OrientedBox", OrientedBox<S> { center: Vec3<S>, half: Vec3<S>, u: Vec3<S>, v: Vec3<S>, w: Vec3<S> });

impl<S: Scalar> OrientedBox<S> {
    /// A box around `center` with half-extents `half` (along `u`, `v`, `w`).
    /// `u` is normalized, `v` is made orthogonal to `u` and normalized, and
    /// `w = u × v`. Errors: non-finite numbers, a negative half-extent, `u` of
    /// zero length or `v` parallel to `u`.
    pub fn new(center: Vec3<S>, half: Vec3<S>, u: Vec3<S>, v: Vec3<S>) -> Result<Self, GeometryError> {
        if !center.is_finite() || !half.is_finite() || !u.is_finite() || !v.is_finite() {
            return Err(GeometryError::NonFinite);
        }
        if half.x < S::ZERO || half.y < S::ZERO || half.z < S::ZERO {
            return Err(GeometryError::NonPositiveRadius);
        }
        let u = u.normalize_or_zero();
        if u == Vec3::ZERO {
            return Err(GeometryError::ZeroLengthAxis);
        }
        // Gram-Schmidt: remove v's component along u. For a `v` parallel to
        // `u` what is left is rounding noise, which normalizes to no direction
        // orthogonal to `u` (for u = v = (1, 1, 0), to `u` itself): parallel
        // too, or the frame (so `bounds`) would not be the box the kernel
        // intersects. A true residual leaves `u·v` at rounding level.
        let v = (v - u.scale(u.dot(v))).normalize_or_zero();
        if v == Vec3::ZERO || u.dot(v).abs() > S::from_f32(1e-5) {
            return Err(GeometryError::ZeroLengthAxis);
        }
        let w = u.cross(v);
        Ok(OrientedBox { center, half, u, v, w })
    }

    /// The same box in the frame of `sim`, with scalar `T`.
    pub fn similar<T: Scalar>(&self, sim: &Similarity) -> OrientedBox<T> {
        let [hx, hy, hz] = self.half.to_f32();
        let s = sim.scale;
        OrientedBox {
            center: sim.point(self.center),
            half: Vec3::from_f32(hx * s, hy * s, hz * s),
            u: sim.direction(self.u),
            v: sim.direction(self.v),
            w: sim.direction(self.w),
        }
    }

    /// Centre.
    pub fn center(&self) -> Vec3<S> {
        self.center
    }
    /// Half-extents along the box axes.
    pub fn half_extents(&self) -> Vec3<S> {
        self.half
    }
    /// The box axes `(u, v, w)`.
    pub fn axes(&self) -> (Vec3<S>, Vec3<S>, Vec3<S>) {
        (self.u, self.v, self.w)
    }

    /// Crossings of each active ray with the box surface in `(t_min, t_max)`.
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
        // Transform the ray into box space; the frame is orthonormal, so t is
        // unchanged.
        let rel = ray.origin.sub_splat(self.center);
        let o = Vec3::new(rel.dot_splat(self.u), rel.dot_splat(self.v), rel.dot_splat(self.w));
        // (Unit vectors: products of small factors.)
        let d = Vec3::new(
            ray.dir.dot_splat_small(self.u),
            ray.dir.dot_splat_small(self.v),
            ray.dir.dot_splat_small(self.w),
        );
        slab_roots(o, d, -self.half, self.half, t_min, t_max, active, LEAVE_EARLY)
    }

    /// Outward normals at the points `p` on the surface: the nearest face's
    /// normal in the box's frame, rotated back.
    #[inline(always)]
    pub fn normals<const W: usize>(&self, p: &Vec3xW<S, W>) -> Vec3xW<S, W> {
        let rel = p.sub_splat(self.center);
        let local = Vec3::new(rel.dot_splat(self.u), rel.dot_splat(self.v), rel.dot_splat(self.w));
        let n = face_normals(&local, -self.half, self.half);
        self.u.splat::<W>().scale_lanes(n.x)
            + self.v.splat::<W>().scale_lanes(n.y)
            + self.w.splat::<W>().scale_lanes(n.z)
    }

    /// Axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> (Vec3<S>, Vec3<S>) {
        // Extent along each world axis: Σ |axis component| · half-extent.
        let e = |a: usize| {
            self.u.axis(a).abs() * self.half.x + self.v.axis(a).abs() * self.half.y + self.w.axis(a).abs() * self.half.z
        };
        let ext = Vec3::new(e(0), e(1), e(2));
        (self.center - ext, self.center + ext)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::primitives::test_util::*;
    use crate::geom::primitives::Shape;

    fn rotated() -> OrientedBox<f32> {
        // A unit cube rotated 45 degrees about z.
        OrientedBox::new(
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        )
        .unwrap()
    }

    #[test]
    fn rotated_cube_hits_at_corner_distance() {
        // Along x the rotated cube reaches out to sqrt(2).
        let h = hits(&Shape::OrientedBox(rotated()), [-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let s2 = 2.0f32.sqrt();
        assert_eq!(h.len(), 2);
        assert!((h[0] - (5.0 - s2)).abs() < 1e-5 && (h[1] - (5.0 + s2)).abs() < 1e-5, "{h:?}");
        // Past the corner it misses.
        assert!(hits(&Shape::OrientedBox(rotated()), [-5.0, 1.5, 0.0], [1.0, 0.0, 0.0]).is_empty());
    }

    #[test]
    fn normal_is_rotated_face_normal() {
        let b = rotated();
        let n = b.normals::<1>(&Vec3::new(0.5, 0.5, 0.2).scale(2.0f32.sqrt()).splat()).lane(0);
        let e = Vec3::new(1.0, 1.0, 0.0).normalize_or_zero();
        assert!((n - e).length() < 1e-6, "{n:?}");
    }

    #[test]
    fn inside_and_behind() {
        let h = hits(&Shape::OrientedBox(rotated()), [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        assert!(h.len() == 1 && (h[0] - 1.0).abs() < 1e-6, "{h:?}");
        assert!(hits(&Shape::OrientedBox(rotated()), [0.0, 0.0, 3.0], [0.0, 0.0, 1.0]).is_empty());
    }

    #[test]
    fn degenerate_input_is_rejected() {
        let c = Vec3::new(0.0f32, 0.0, 0.0);
        let h = Vec3::new(1.0f32, 1.0, 1.0);
        let x = Vec3::new(1.0f32, 0.0, 0.0);
        assert_eq!(OrientedBox::new(c, h, Vec3::ZERO, x), Err(GeometryError::ZeroLengthAxis));
        assert_eq!(OrientedBox::new(c, h, x, x.scale(2.0)), Err(GeometryError::ZeroLengthAxis));
        // Parallel, with a rounding residual (fuzzing found this one).
        let d = Vec3::new(1.0f32, 1.0, 0.0);
        assert_eq!(OrientedBox::new(c, h, d, d), Err(GeometryError::ZeroLengthAxis));
        assert_eq!(OrientedBox::new(c, h, d, d.scale(-3.0)), Err(GeometryError::ZeroLengthAxis));
        assert_eq!(OrientedBox::new(c, -h, x, Vec3::new(0.0, 1.0, 0.0)), Err(GeometryError::NonPositiveRadius));
        assert_eq!(OrientedBox::new(c, h, Vec3::new(f32::NAN, 0.0, 0.0), x), Err(GeometryError::NonFinite));
    }
}
