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
    #[cfg_attr(all(not(debug_assertions), not(armv6m), not(target_arch = "wasm32")), inline(always))]
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

    /// Unit outward geometric normals at the surface points `p`, as hits
    /// report them: [`Shape::normals`] normalised
    /// ([`Vec3xW::normalize_sparse`], zero where it has no length). Planes
    /// and polygons return the one they store ([`Vec3::hit_normal`]), the
    /// same bits without a square root and a division per hit.
    #[inline(always)]
    pub fn unit_normals<const W: usize>(&self, p: &Vec3xW<S, W>) -> Vec3xW<S, W> {
        match self.stored_hit_normal() {
            Some(n) => n.splat(),
            None => self.normals(p).normalize_sparse().0,
        }
    }

    /// The unit normal of every hit, for planes and polygons (see
    /// [`Shape::unit_normals`]). A match of its own: with the three arms in
    /// `unit_normals`' one match (the same bits), LLVM inlined the tracer
    /// differently and the Cortex-M55's width-4 frame took 44 020 281
    /// instructions instead of 40 896 937 (the Cortex-M0's 0.2 % fewer).
    #[inline(always)]
    fn stored_hit_normal(&self) -> Option<Vec3<S>> {
        match self {
            Shape::Plane(pl) => Some(pl.hit_normal()),
            Shape::Polygon(pg) => Some(pg.hit_normal()),
            _ => None,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::fixed32::Fixed32;
    use crate::num::test_rng::splitmix64;

    /// A coordinate in `[−2, 2)` from the generator.
    fn coord(state: &mut u64) -> f32 {
        (splitmix64(state) >> 40) as f32 / (1u64 << 22) as f32 - 2.0
    }

    /// The bits of every lane of `v`, for exact comparisons (`-0.0` and
    /// `0.0` differ).
    fn bits<S: Scalar, const W: usize>(v: &Vec3xW<S, W>, to_bits: fn(S) -> u32) -> [[u32; W]; 3] {
        [v.x.0.map(to_bits), v.y.0.map(to_bits), v.z.0.map(to_bits)]
    }

    /// Planes and polygons hand hits a stored unit normal: it must be the
    /// bits that normalising their normal at the hit gives, at any width,
    /// for each way they are built (coefficients, a point and a normal,
    /// vertices, conversion into a fixed-point frame), degenerate polygons
    /// included.
    fn stored_normals_are_the_normalised_ones<S: Scalar>(to_bits: fn(S) -> u32) {
        let mut state = 7;
        let sim = Similarity::fitting([-2.0; 3], [2.0; 3], 1.0);
        let mut checked = 0;
        for i in 0..400 {
            let mut c = || coord(&mut state);
            // Every fourth one axis-aligned, as normals of real scenes often are.
            let n = if i % 4 == 0 { [0.0, 0.0, c()] } else { [c(), c(), c()] };
            let pts = [[c(), c(), c()], [c(), c(), c()], [c(), c(), c()]];
            let f = |p: [f32; 3]| Vec3::<f32>::new(p[0], p[1], p[2]);
            let s = |p: [f32; 3]| Vec3::<S>::from_f32(p[0], p[1], p[2]);
            // A degenerate triangle (a repeated vertex) now and then.
            let tri = if i % 10 == 0 { [pts[0], pts[1], pts[1]] } else { pts };
            let mut shapes: [Option<Shape<S>>; 5] = [None; 5];
            shapes[0] =
                Plane::from_coefficients(S::from_f32(n[0]), S::from_f32(n[1]), S::from_f32(n[2]), S::from_f32(c()))
                    .ok()
                    .map(Shape::Plane);
            shapes[1] = Plane::from_point_normal(s(pts[0]), s(n)).ok().map(Shape::Plane);
            shapes[2] = Plane::from_point_normal(f(pts[0]), f(n)).ok().map(|p| Shape::Plane(p.similar(&sim)));
            let pool_s = [s(tri[0]), s(tri[1]), s(tri[2])];
            shapes[3] = Polygon::from_pool(&pool_s, 0, 3, false).ok().map(Shape::Polygon);
            let pool_f = [f(tri[0]), f(tri[1]), f(tri[2])];
            shapes[4] = Polygon::from_pool(&pool_f, 0, 3, false).ok().map(|p| Shape::Polygon(p.similar(&sim)));
            for shape in shapes.iter().flatten() {
                let p4 = Vec3::<S>::from_f32(c(), c(), c()).splat::<4>();
                let (want, _) = shape.normals(&p4).normalize_sparse();
                assert_eq!(bits(&shape.unit_normals(&p4), to_bits), bits(&want, to_bits), "{shape:?}");
                let p1 = Vec3::<S>::from_f32(c(), c(), c()).splat::<1>();
                let (want, _) = shape.normals(&p1).normalize_sparse();
                assert_eq!(bits(&shape.unit_normals(&p1), to_bits), bits(&want, to_bits), "{shape:?}");
                checked += 1;
            }
        }
        assert!(checked > 1500, "only {checked} shapes built");
    }

    #[test]
    fn stored_plane_and_polygon_normals_are_the_normalised_ones_f32() {
        stored_normals_are_the_normalised_ones::<f32>(f32::to_bits);
    }

    #[test]
    fn stored_plane_and_polygon_normals_are_the_normalised_ones_fixed32() {
        stored_normals_are_the_normalised_ones::<Fixed32>(|x| x.to_bits() as u32);
    }
}
