//! Sphere: centre and radius.

use super::error::GeometryError;
use crate::num::lanes::{Lanes, Mask};
use crate::geom::ray::{RayPacket, Roots};
use crate::num::scalar::Scalar;
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::{Vec3, Vec3xW};

/// A sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere<S> {
    center: Vec3<S>,
    radius: S,
    radius2: S,
}

impl<S: Scalar> Sphere<S> {
    /// A sphere of positive, finite `radius` around a finite `center`.
    pub fn new(center: Vec3<S>, radius: S) -> Result<Self, GeometryError> {
        if !center.is_finite() || !radius.is_finite() {
            return Err(GeometryError::NonFinite);
        }
        if !(radius > S::ZERO) {
            return Err(GeometryError::NonPositiveRadius);
        }
        Ok(Sphere { center, radius, radius2: radius * radius })
    }

    /// Centre.
    pub fn center(&self) -> Vec3<S> {
        self.center
    }
    /// Radius.
    pub fn radius(&self) -> S {
        self.radius
    }

    /// The same sphere in the frame of `sim`, with scalar `T` (computed in
    /// `f32`, then converted; see [`crate::geom::uniform_scale`]).
    pub fn similar<T: Scalar>(&self, sim: &Similarity) -> Sphere<T> {
        let r = self.radius.to_f32() * sim.scale;
        Sphere { center: sim.point(self.center), radius: T::from_f32(r), radius2: T::from_f32(r * r) }
    }

    /// Crossings of each active ray with the sphere inside `(t_min, t_max)`.
    ///
    /// Rays must have unit directions (every `RayPacket` constructor ensures
    /// it), so the quadratic is `t² + 2bt + c = 0` with `b = oc·d`.
    // Forced inline into the query loops except on Armv6-M (Cortex-M0/M0+,
    // the one target without 32-bit atomics), where the copies would not fit
    // a small flash: there each kernel is one function per packet width.
    #[cfg_attr(
        all(not(debug_assertions), not(all(target_arch = "arm", not(target_has_atomic = "32")))),
        inline(always)
    )]
    pub fn roots<const W: usize>(
        &self,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Roots<S, W> {
        // Vector from the centre to the ray origin.
        let oc = ray.origin.sub_splat(self.center);
        let b = oc.dot(ray.dir);
        // Compute the discriminant as r² − |oc − b·d|² (Haines et al., Ray
        // Tracing Gems ch. 7): the squared distance of the centre from the
        // line is formed from a short vector, so it does not suffer the
        // cancellation of the textbook b² − c when the origin is far away.
        let perp = oc - ray.dir.scale(b);
        let disc = Lanes::splat(self.radius2) - perp.dot(perp);
        let valid = active & disc.ge(Lanes::zero());
        if valid.none() {
            return Roots::none();
        }
        let c = oc.dot(oc) - Lanes::splat(self.radius2);
        let sq = disc.sqrt();
        // q = −(b + sign(b)·√Δ) avoids subtracting nearly equal numbers; the
        // roots are then q and c/q (a = 1). Their sum is −2b, so q lies on
        // the far side of −b from the other root: q is the smaller root when
        // b >= 0 and the larger when b < 0. That orders them without a compare.
        let b_pos = b.ge(Lanes::zero());
        let q = Lanes::select(b_pos, -b - sq, sq - b);
        // c/q guarded against q = 0 (tangent ray starting on the surface: the
        // double root is 0, outside any interval with t_min >= 0).
        let q_ok = q.ne_lanes(Lanes::zero());
        let cq = c.div_nonzero(q);
        let near = Lanes::select(b_pos, q, cq);
        let far = Lanes::select(b_pos, cq, q);
        Roots::from_ordered(near, far, valid & q_ok, t_min, t_max)
    }

    /// Outward normal (not normalized) at a point on the surface.
    #[inline]
    pub fn normal(&self, p: Vec3<S>) -> Vec3<S> {
        p - self.center
    }

    /// [`Sphere::normal`] of every lane of `p` (the same operations per lane).
    #[inline(always)]
    pub fn normals<const W: usize>(&self, p: &Vec3xW<S, W>) -> Vec3xW<S, W> {
        p.sub_splat(self.center)
    }

    /// Axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> (Vec3<S>, Vec3<S>) {
        let r = Vec3::new(self.radius, self.radius, self.radius);
        (self.center - r, self.center + r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::primitives::test_util::*;
    use crate::geom::primitives::Shape;

    fn unit() -> Sphere<f32> {
        Sphere::new(Vec3::new(0.0, 0.0, 0.0), 1.0).unwrap()
    }

    #[test]
    fn analytic_hit_from_outside() {
        {
            let r = hits(&Shape::Sphere(unit()), [0.0, 0.0, -5.0], [0.0, 0.0, 1.0]);
            assert_eq!(r, vec![4.0, 6.0]);
        }
    }

    #[test]
    fn miss_and_tangent() {
        {
            let miss = hits(&Shape::Sphere(unit()), [0.0, 1.5, -5.0], [0.0, 0.0, 1.0]);
            assert!(miss.is_empty());
            let tangent = hits(&Shape::Sphere(unit()), [0.0, 1.0, -5.0], [0.0, 0.0, 1.0]);
            assert_eq!(tangent, vec![5.0, 5.0]);
        }
    }

    #[test]
    fn origin_inside_gives_one_root() {
        {
            let r = hits(&Shape::Sphere(unit()), [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
            assert_eq!(r, vec![1.0]);
        }
    }

    #[test]
    fn behind_origin_misses() {
        {
            let r = hits(&Shape::Sphere(unit()), [0.0, 0.0, 5.0], [0.0, 0.0, 1.0]);
            assert!(r.is_empty());
        }
    }

    #[test]
    fn far_origin_keeps_precision() {
        // 1e4 units away the textbook formula loses most digits of c.
        let s = Sphere::new(Vec3::new(0.0f32, 0.0, 0.0), 1.0).unwrap();
        let r = hits(&Shape::Sphere(s), [0.0, 0.5, -1.0e4], [0.0, 0.0, 1.0]);
        let exact = 1.0e4 - (0.75f64).sqrt();
        assert!((r[0] as f64 - exact).abs() < 1e-3, "{r:?}");
    }

    #[test]
    fn degenerate_input_is_rejected() {
        assert_eq!(Sphere::new(Vec3::new(0.0f32, 0.0, 0.0), 0.0), Err(GeometryError::NonPositiveRadius));
        assert_eq!(Sphere::new(Vec3::new(0.0f32, 0.0, 0.0), -1.0), Err(GeometryError::NonPositiveRadius));
        assert_eq!(Sphere::new(Vec3::new(f32::NAN, 0.0, 0.0), 1.0), Err(GeometryError::NonFinite));
        assert_eq!(Sphere::new(Vec3::new(0.0f32, 0.0, 0.0), f32::INFINITY), Err(GeometryError::NonFinite));
    }
}
