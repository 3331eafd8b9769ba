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
mod error;
pub mod obox;
pub mod plane;
pub mod polygon;
pub mod quadric;
mod shape;
pub mod sphere;

pub use aabox::AaBox;
pub use cone::Cone;
pub use error::GeometryError;
pub use obox::OrientedBox;
pub use plane::Plane;
pub use polygon::Polygon;
pub use quadric::Quadric;
pub use shape::{Shape, ShapeKind};
pub use sphere::Sphere;

#[cfg(test)]
pub(crate) mod test_util {
    //! Helpers that run one ray through a primitive at widths 1, 4 and 8,
    //! with the ray in every lane position among unrelated rays, and check
    //! that all of them agree bit for bit with the width-1 result.
    extern crate std;
    use super::Shape;
    use crate::geom::ray::RayPacket;
    use crate::geom::vec3::Vec3;
    use crate::num::lanes::{Lanes, Mask};
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

    /// The nearer crossing in `(t_min, ∞)` of the ray `o + t·d` (unit `d`),
    /// width 1; `None` if none.
    pub fn first_after(shape: &Shape<f32>, t_min: f32, o: [f32; 3], d: [f32; 3]) -> Option<f32> {
        use crate::geom::ray::RayPacket;
        use crate::num::lanes::{Lanes, Mask};
        let o = Vec3::new(o[0], o[1], o[2]).splat::<1>();
        let d = Vec3::new(d[0], d[1], d[2]).splat::<1>();
        let ray = RayPacket { origin: o, dir: d };
        let r = shape.roots(&[], &ray, Lanes::splat(t_min), Lanes::splat(f32::MAX), Mask::splat(true));
        r.hit0.any().then_some(r.t0.0[0])
    }

    /// [`hits_in`] for primitives that do not use the vertex pool.
    pub fn hits(shape: &Shape<f32>, o: [f32; 3], d: [f32; 3]) -> Vec<f32> {
        hits_in(shape, &[], o, d)
    }
}
