//! Sphere: centre and radius.

use super::error::GeometryError;
use crate::geom::ray::{RayPacket, Roots};
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::{Vec3, Vec3xW};
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;

/// Whether [`Sphere::roots`] takes its steps without range tests for rays
/// near the sphere: where a saturating sum costs more than a plain one
/// (RV32, Armv6-M, 64-bit hosts), not on the Arm cores from Armv7-M on,
/// and not on WebAssembly, whose `Fixed32` keeps the general product for
/// small factors (the module's size) and so would only grow.
const NEAR_STEPS: bool = !cfg!(any(target_arch = "arm", target_arch = "wasm32")) || cfg!(armv6m);

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
        // In a scalar of limited range, rays from within 2 of the centre in
        // every component (in the fitted frame, where primitives and eye lie
        // within 1 of the origin: most rays) take the same steps by the
        // products and sums without range tests, which cannot fire there.
        // (Not on Armv7-M and later, whose saturating sum is one `qadd`:
        // there the test cost more than it saved, the `fixed32` frame 0.29 M
        // instructions longer on the Cortex-M4F and 0.39 M on the M55.)
        if S::LIMITED_RANGE && NEAR_STEPS {
            let (lo, hi) = (-S::TWO, S::TWO);
            if active.and_not(oc.in_box(Vec3::new(lo, lo, lo), Vec3::new(hi, hi, hi))).none() {
                return self.roots_near(ray, &oc, t_min, t_max, active);
            }
        }
        self.roots_from(ray, &oc, t_min, t_max, active)
    }

    /// [`Sphere::roots`] given `oc`, the vector from the centre to the ray
    /// origins, with every range test.
    #[inline(always)]
    fn roots_from<const W: usize>(
        &self,
        ray: &RayPacket<S, W>,
        oc: &Vec3xW<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Roots<S, W> {
        let oc = *oc;
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

    /// [`Sphere::roots_from`]'s steps for rays whose `oc` is within 2 of zero in
    /// every component (the active lanes), by [`Scalar::mul_small`] and its
    /// sums and differences: the same bits, as none of the general steps'
    /// range tests can fire.
    ///
    /// The bounds: `|b| = |oc·d| ≤ 2√3·|d| < 3.47` (`d` a unit vector to a
    /// few ulps), so `d·b` has factors below 4. The exact `oc − d(oc·d)` has
    /// squared length `|oc|² − b²(2 − |d|²) ≤ |oc|² ≤ 12`, so each component
    /// of `perp` is below 3.47 plus a few ulps of rounding: squares below 16,
    /// their sum below 48. `r² − |perp|²` is a difference of two terms at
    /// least 0, and `√Δ ≤ √128`, so `−b − √Δ` and `√Δ − b` stay below 16.
    #[inline(always)]
    fn roots_near<const W: usize>(
        &self,
        ray: &RayPacket<S, W>,
        oc: &Vec3xW<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Roots<S, W> {
        let d = &ray.dir;
        let b = oc.dot_small(*d);
        let perp = Vec3::new(
            oc.x.sub_small(d.x.mul_small(b)),
            oc.y.sub_small(d.y.mul_small(b)),
            oc.z.sub_small(d.z.mul_small(b)),
        );
        let disc = Lanes::splat(self.radius2).sub_small(perp.norm_squared_small());
        let valid = active & disc.ge(Lanes::zero());
        if valid.none() {
            return Roots::none();
        }
        let sq = disc.sqrt();
        let near = (-b).sub_small(sq);
        let far = sq.sub_small(b);
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

    /// The steps without range tests give the general steps' bits, roots
    /// and masks, for every ray whose `oc` lies in the box of half-size 2
    /// (its faces included): seeded spheres of radius up to 3 centred
    /// within 1 of the origin, origins at every such offset, directions
    /// towards points near the sphere (most rays hit) or anywhere, and
    /// intervals cut at random.
    fn near_steps_agree<const W: usize>() {
        use crate::num::fixed32::Fixed32;
        use crate::num::test_rng::splitmix64;
        let mut state = 0x5EED_5FE8u64 + W as u64;
        let mut raw = |lo: i32, hi: i32| lo + (splitmix64(&mut state) % ((hi - lo) as u64 + 1)) as i32;
        let fx = Fixed32::from_bits;
        const ONE: i32 = 1 << 24;
        let (mut hits, mut rays) = (0, 0);
        for _ in 0..20_000 {
            let c = Vec3::new(fx(raw(-ONE, ONE)), fx(raw(-ONE, ONE)), fx(raw(-ONE, ONE)));
            let r = raw(ONE / 64, 3 * ONE) as f32 / ONE as f32;
            let sphere = Sphere::new(c, Fixed32::from_f32(r)).unwrap();
            let mut o = [[Fixed32::ZERO; W]; 3];
            let mut d = [[Fixed32::ZERO; W]; 3];
            for l in 0..W {
                for a in 0..3 {
                    // Offsets to the box's faces exactly, one time in eight.
                    let off = match raw(0, 7) {
                        0 => 2 * ONE,
                        1 => -2 * ONE,
                        _ => raw(-2 * ONE, 2 * ONE),
                    };
                    o[a][l] = fx(c.axis(a).to_bits() + off);
                    // Towards a point within r + 0.5 of the centre, or anywhere.
                    let aim =
                        if raw(0, 3) == 0 { raw(-4 * ONE, 4 * ONE) } else { c.axis(a).to_bits() + raw(-ONE, ONE) };
                    d[a][l] = fx(aim) - o[a][l];
                }
            }
            let v = |c: [[Fixed32; W]; 3]| Vec3::new(Lanes(c[0]), Lanes(c[1]), Lanes(c[2]));
            let (ray, ok) = RayPacket::new(v(o), v(d));
            let oc = ray.origin.sub_splat(sphere.center);
            let t_max = if raw(0, 1) == 0 {
                Lanes::splat(Fixed32::MAX)
            } else {
                Lanes(core::array::from_fn(|_| fx(raw(0, 8 * ONE))))
            };
            let t_min = Lanes::splat(Fixed32::ZERO);
            let near = sphere.roots_near(&ray, &oc, t_min, t_max, ok);
            let general = sphere.roots_from(&ray, &oc, t_min, t_max, ok);
            assert_eq!((near.hit0, near.hit1), (general.hit0, general.hit1), "{sphere:?} {ray:?}");
            for l in 0..W {
                if general.hit0.get(l) {
                    assert_eq!(near.t0.0[l], general.t0.0[l], "{sphere:?} {ray:?}");
                }
                if general.hit1.get(l) {
                    assert_eq!(near.t1.0[l], general.t1.0[l], "{sphere:?} {ray:?}");
                }
            }
            hits += general.hit0.count();
            rays += ok.count();
        }
        // Most rays were aimed at the sphere: the hits were exercised.
        assert!(hits * 2 > rays, "{hits} hits of {rays} rays");
    }

    #[test]
    fn near_steps_are_the_general_steps_in_fixed_point() {
        near_steps_agree::<1>();
        near_steps_agree::<4>();
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
