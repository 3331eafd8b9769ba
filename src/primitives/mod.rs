//! The primitives, one module each, and [`Shape`], the closed set of them
//! that a scene stores.
//!
//! Every primitive has the same three operations, each written once for any
//! packet width `W` (the scalar path is `W = 1`):
//! - `roots`: the crossings of each active ray with the surface inside
//!   `(t_min, t_max)`, nearest first (closest-hit uses the first, shadow rays
//!   count them);
//! - `normal`: the outward geometric normal at a point on the surface;
//! - for polygon patches, an interpolated shading normal.

pub mod aabox;
pub mod cone;
pub mod obox;
pub mod plane;
pub mod polygon;
pub mod quadric;
pub mod sphere;

pub use aabox::AaBox;
pub use cone::Cone;
pub use obox::OrientedBox;
pub use plane::Plane;
pub use polygon::Polygon;
pub use quadric::Quadric;
pub use sphere::Sphere;

use crate::lanes::{Lanes, Mask};
use crate::ray::{RayPacket, Roots};
use crate::scalar::Scalar;
use crate::vec3::Vec3;

/// Why a primitive could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeometryError {
    /// A coordinate or parameter is NaN or infinite.
    NonFinite,
    /// A radius (or half-extent, angle, focal length) is zero or negative.
    NonPositiveRadius,
    /// An axis, normal or direction has zero length (or two points coincide).
    ZeroLengthAxis,
    /// A polygon has fewer than 3 vertices (the count is given).
    TooFewVertices(u32),
    /// A polygon's vertex range lies outside the vertex pool.
    VertexRange,
    /// A quadric whose coefficients A to I are all zero.
    DegenerateQuadric,
}

impl core::fmt::Display for GeometryError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            GeometryError::NonFinite => f.write_str("a number is NaN or infinite"),
            GeometryError::NonPositiveRadius => f.write_str("a radius or size is zero or negative"),
            GeometryError::ZeroLengthAxis => f.write_str("an axis, normal or direction has zero length"),
            GeometryError::TooFewVertices(n) => write!(f, "a polygon needs at least 3 vertices, got {n}"),
            GeometryError::VertexRange => f.write_str("polygon vertices outside the vertex pool"),
            GeometryError::DegenerateQuadric => f.write_str("quadric with all of A..I zero"),
        }
    }
}

/// The kinds of primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShapeKind {
    /// [`Sphere`].
    Sphere,
    /// [`Plane`].
    Plane,
    /// [`Polygon`] without vertex normals.
    Polygon,
    /// [`Polygon`] with vertex normals (NFF `pp`).
    Patch,
    /// [`AaBox`].
    AaBox,
    /// [`OrientedBox`].
    OrientedBox,
    /// [`Quadric`].
    Quadric,
    /// [`Cone`].
    Cone,
}

/// One primitive of any kind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape<S> {
    /// A sphere.
    Sphere(Sphere<S>),
    /// An infinite plane.
    Plane(Plane<S>),
    /// A polygon or polygon patch (vertices in the scene's pool).
    Polygon(Polygon<S>),
    /// An axis-aligned box.
    AaBox(AaBox<S>),
    /// An oriented box.
    OrientedBox(OrientedBox<S>),
    /// A general (optionally clipped) quadric.
    Quadric(Quadric<S>),
    /// A finite open cone or cylinder.
    Cone(Cone<S>),
}

impl<S: Scalar> Shape<S> {
    /// The kind of this primitive.
    pub fn kind(&self) -> ShapeKind {
        match self {
            Shape::Sphere(_) => ShapeKind::Sphere,
            Shape::Plane(_) => ShapeKind::Plane,
            Shape::Polygon(p) if p.is_patch() => ShapeKind::Patch,
            Shape::Polygon(_) => ShapeKind::Polygon,
            Shape::AaBox(_) => ShapeKind::AaBox,
            Shape::OrientedBox(_) => ShapeKind::OrientedBox,
            Shape::Quadric(_) => ShapeKind::Quadric,
            Shape::Cone(_) => ShapeKind::Cone,
        }
    }

    /// Crossings of each active ray with the surface in `(t_min, t_max)`.
    /// `pool` is the scene's vertex pool (used by polygons).
    #[inline(always)]
    pub fn roots<const W: usize>(
        &self,
        pool: &[Vec3<S>],
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Roots<S, W> {
        match self {
            Shape::Sphere(s) => s.roots(ray, t_min, t_max, active),
            Shape::Plane(p) => p.roots(ray, t_min, t_max, active),
            Shape::Polygon(p) => p.roots(pool, ray, t_min, t_max, active),
            Shape::AaBox(b) => b.roots(ray, t_min, t_max, active),
            Shape::OrientedBox(b) => b.roots(ray, t_min, t_max, active),
            Shape::Quadric(q) => q.roots(ray, t_min, t_max, active),
            Shape::Cone(c) => c.roots(ray, t_min, t_max, active),
        }
    }

    /// Outward geometric normal at a surface point (not normalized; may be
    /// zero at a singular point such as a cone's apex).
    #[inline]
    pub fn normal(&self, p: Vec3<S>) -> Vec3<S> {
        match self {
            Shape::Sphere(s) => s.normal(p),
            Shape::Plane(pl) => pl.normal(p),
            Shape::Polygon(pg) => pg.normal(),
            Shape::AaBox(b) => b.normal(p),
            Shape::OrientedBox(b) => b.normal(p),
            Shape::Quadric(q) => q.normal(p),
            Shape::Cone(c) => c.normal(p),
        }
    }

    /// Normal used for shading (interpolated on patches; the geometric normal
    /// elsewhere). Not normalized.
    #[inline]
    pub fn shading_normal(&self, pool: &[Vec3<S>], p: Vec3<S>, geometric: Vec3<S>) -> Vec3<S> {
        match self {
            Shape::Polygon(pg) if pg.is_patch() => pg.shading_normal(pool, p),
            _ => geometric,
        }
    }

    /// Axis-aligned bounds `(min, max)`, or `None` for unbounded primitives
    /// (planes and unclipped quadrics).
    pub fn bounds(&self, pool: &[Vec3<S>]) -> Option<(Vec3<S>, Vec3<S>)> {
        match self {
            Shape::Sphere(s) => Some(s.bounds()),
            Shape::Plane(_) => None,
            Shape::Polygon(p) => Some(p.bounds(pool)),
            Shape::AaBox(b) => Some((b.min(), b.max())),
            Shape::OrientedBox(b) => Some(b.bounds()),
            Shape::Quadric(q) => q.clip_box(),
            Shape::Cone(c) => Some(c.bounds()),
        }
    }
}

#[cfg(test)]
pub(crate) mod test_util {
    //! Helpers that run one ray through a primitive at widths 1, 4 and 8,
    //! with the ray in every lane position among unrelated rays, and check
    //! that all of them agree bit for bit with the width-1 result.
    extern crate std;
    use super::Shape;
    use crate::lanes::{Lanes, Mask};
    use crate::ray::RayPacket;
    use crate::vec3::Vec3;
    use std::vec::Vec;

    fn filler(i: usize) -> ([f32; 3], [f32; 3]) {
        // Unrelated rays for the other lanes.
        let a = i as f32 * 0.37;
        ([a - 3.0, 1.5 - a, -4.0 + 0.5 * a], [0.3 * a - 0.2, 0.5, 1.0 - 0.1 * a])
    }

    fn packet<const W: usize>(lane: usize, o: [f32; 3], d: [f32; 3]) -> (RayPacket<f32, W>, Mask<W>) {
        let mut org = Vec3::new(Lanes::splat(0.0), Lanes::splat(0.0), Lanes::splat(0.0));
        let mut dir = org;
        for i in 0..W {
            let (oo, dd) = if i == lane { (o, d) } else { filler(i) };
            org.set_lane(i, Vec3::new(oo[0], oo[1], oo[2]));
            dir.set_lane(i, Vec3::new(dd[0], dd[1], dd[2]));
        }
        RayPacket::new(org, dir)
    }

    fn run<const W: usize>(shape: &Shape<f32>, pool: &[Vec3<f32>], lane: usize, o: [f32; 3], d: [f32; 3]) -> Vec<u32> {
        let (ray, active) = packet::<W>(lane, o, d);
        let r = shape.roots(pool, &ray, Lanes::splat(0.0), Lanes::splat(f32::MAX), active);
        let mut out = Vec::new();
        if r.hit0.get(lane) {
            out.push(r.t0.0[lane].to_bits());
        }
        if r.hit1.get(lane) {
            out.push(r.t1.0[lane].to_bits());
        }
        out
    }

    /// The crossings (t values, nearest first) of the ray `o + t·d`, `t > 0`,
    /// with `shape`; asserts that widths 1, 4 and 8 agree bit for bit in
    /// every lane position.
    pub fn hits_in(shape: &Shape<f32>, pool: &[Vec3<f32>], o: [f32; 3], d: [f32; 3]) -> Vec<f32> {
        let one = run::<1>(shape, pool, 0, o, d);
        for lane in 0..4 {
            assert_eq!(run::<4>(shape, pool, lane, o, d), one, "width 4, lane {lane}");
        }
        for lane in 0..8 {
            assert_eq!(run::<8>(shape, pool, lane, o, d), one, "width 8, lane {lane}");
        }
        one.into_iter().map(f32::from_bits).collect()
    }

    /// [`hits_in`] for primitives that do not use the vertex pool.
    pub fn hits(shape: &Shape<f32>, o: [f32; 3], d: [f32; 3]) -> Vec<f32> {
        hits_in(shape, &[], o, d)
    }
}
