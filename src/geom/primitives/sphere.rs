//! Sphere: centre and radius.

use super::error::GeometryError;
use crate::geom::ray::{RayPacket, Roots};
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::{Vec3, Vec3xW};
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;

/// A sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere<S> {
    center: Vec3<S>,
    radius: S,
    radius2: S,
}

crate::num::bake::bake_struct!("raypack::geom::primitives::Sphere", Sphere<S> { center: Vec3<S>, radius: S, radius2: S });

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
    #[cfg_attr(all(not(debug_assertions), not(armv6m)), inline(always))]
    pub fn roots<const W: usize>(
        &self,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Roots<S, W> {
        // Vector from the centre to the ray origin; the point of the ray
        // nearest the centre is at t = −b.
        let oc = ray.origin.sub_splat(self.center);
        let b = oc.dot(ray.dir);
        // Solve from that nearest point rather than from the origin (Haines
        // et al., Ray Tracing Gems ch. 7): `perp = oc − b·d` is the centre's
        // offset from the line, a short vector when the ray passes near the
        // sphere however far away its origin is, so the discriminant
        // r² − |perp|² is formed from numbers of the sphere's own size and
        // does not suffer the cancellation of the textbook b² − c (whose
        // c = |oc|² − r² keeps nothing of r² for a far origin).
        let perp = oc - ray.dir.scale(b);
        let disc = Lanes::splat(self.radius2) - perp.norm_squared();
        let valid = active & disc.ge(Lanes::zero());
        if valid.none() {
            return Roots::none();
        }
        // The crossings lie ±√Δ from the nearest point: t = −b ∓ √Δ, already
        // ordered. Each is off by at most a rounding of |b| and of √Δ ≤ r, so
        // a hit is never reported further than that from the sphere (what
        // keeps brute force and the BVH's padded boxes in agreement).
        let sq = disc.sqrt();
        let near = -b - sq;
        let far = sq - b;
        Roots::from_ordered(near, far, valid, t_min, t_max)
    }

    /// Outward normals (not normalized) at the points `p` on the surface.
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
