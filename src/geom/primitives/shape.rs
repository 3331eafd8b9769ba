//! [`Shape`]: the closed set of primitives a scene stores, and the three
//! operations every primitive has, dispatched on its kind.

use super::{AaBox, Cone, OrientedBox, Plane, Polygon, Quadric, Sphere};
use crate::geom::ray::{RayPacket, Roots};
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::{Vec3, Vec3xW};
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;

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

impl<S: crate::num::bake::Bake> crate::num::bake::Bake for Shape<S> {
    fn bake(&self, w: &mut dyn core::fmt::Write) -> core::fmt::Result {
        let (variant, inner): (&str, &dyn crate::num::bake::Bake) = match self {
            Shape::Sphere(p) => ("Sphere", p),
            Shape::Plane(p) => ("Plane", p),
            Shape::Polygon(p) => ("Polygon", p),
            Shape::AaBox(p) => ("AaBox", p),
            Shape::OrientedBox(p) => ("OrientedBox", p),
            Shape::Quadric(p) => ("Quadric", p),
            Shape::Cone(p) => ("Cone", p),
        };
        write!(w, "raypack::geom::primitives::Shape::{variant}(")?;
        inner.bake(w)?;
        w.write_str(")")
    }
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

    /// The same primitive in the frame of `sim`, with scalar `T` (see
    /// [`crate::geom::uniform_scale`]); a polygon refers to the scene's vertex pool
    /// converted in the same order.
    pub fn similar<T: Scalar>(&self, sim: &Similarity) -> Shape<T> {
        match self {
            Shape::Sphere(s) => Shape::Sphere(s.similar(sim)),
            Shape::Plane(p) => Shape::Plane(p.similar(sim)),
            Shape::Polygon(p) => Shape::Polygon(p.similar(sim)),
            Shape::AaBox(b) => Shape::AaBox(b.similar(sim)),
            Shape::OrientedBox(b) => Shape::OrientedBox(b.similar(sim)),
            Shape::Quadric(q) => Shape::Quadric(q.similar(sim)),
            Shape::Cone(c) => Shape::Cone(c.similar(sim)),
        }
    }

    /// Crossings of each active ray with the surface in `(t_min, t_max)`.
    /// `pool` is the scene's vertex pool (used by polygons).
    // Forced inline into the query loops except on Armv6-M (Cortex-M0/M0+,
    // the one target without 32-bit atomics), where the copies would not fit
    // a small flash, and on WebAssembly, whose module a browser downloads
    // (web/): there each kernel is one function per packet width.
    #[cfg_attr(
        all(
            not(debug_assertions),
            not(all(target_arch = "arm", not(target_has_atomic = "32"))),
            not(target_arch = "wasm32")
        ),
        inline(always)
    )]
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
    /// zero at a singular point such as a cone's apex): [`Shape::normals`]
    /// at one lane.
    #[inline]
    pub fn normal(&self, p: Vec3<S>) -> Vec3<S> {
        self.normals::<1>(&p.splat()).lane(0)
    }

    /// Outward geometric normals at the surface points `p` (for the lanes
    /// that hit this primitive; others hold whatever the formula gives).
    #[inline(always)]
    pub fn normals<const W: usize>(&self, p: &Vec3xW<S, W>) -> Vec3xW<S, W> {
        match self {
            Shape::Sphere(s) => s.normals(p),
            Shape::Plane(pl) => pl.normal_vector().splat(),
            Shape::Polygon(pg) => pg.normal().splat(),
            Shape::AaBox(b) => b.normals(p),
            Shape::OrientedBox(b) => b.normals(p),
            Shape::Quadric(q) => q.normals(p),
            Shape::Cone(c) => c.normals(p),
        }
    }

    /// Whether the shading normal differs from the geometric one (polygon
    /// patches interpolate vertex normals).
    #[inline(always)]
    pub fn has_shading_normals(&self) -> bool {
        matches!(self, Shape::Polygon(pg) if pg.is_patch())
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

    /// The box frame culling uses: [`Shape::bounds`], and for a quadric its
    /// clip box narrowed to (or replaced by) its ellipsoid's box
    /// ([`Quadric::bounds`]). The BVH keeps [`Shape::bounds`].
    pub fn cull_bounds(&self, pool: &[Vec3<S>]) -> Option<(Vec3<S>, Vec3<S>)> {
        match self {
            Shape::Quadric(q) => q.bounds(),
            _ => self.bounds(pool),
        }
    }
}
