//! Finite open cone or cylinder between two points with two radii (the NFF
//! `c` entity), exact: intersected in its own frame and cut by the axial
//! coordinate, not by an axis-aligned clip box.

use super::error::GeometryError;
use crate::geom::ray::{RayPacket, Roots};
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::{Vec3, Vec3xW};
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;

/// An open truncated cone (a cylinder when both radii are equal) from `base`
/// (radius `base_radius`) to `apex` (radius `apex_radius`), without caps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone<S> {
    base: Vec3<S>,
    apex: Vec3<S>,
    base_radius: S,
    apex_radius: S,
    /// Local frame: `w` along the axis, `u × v = w`.
    u: Vec3<S>,
    v: Vec3<S>,
    w: Vec3<S>,
    /// Axis length.
    height: S,
    /// Radius change per unit of axial distance.
    slope: S,
}

crate::num::bake::bake_struct!("raypack::geom::primitives::Cone", Cone<S> { base: Vec3<S>, apex: Vec3<S>, base_radius: S, apex_radius: S, u: Vec3<S>, v: Vec3<S>, w: Vec3<S>, height: S, slope: S });

impl<S: Scalar> Cone<S> {
    /// A cone between two distinct points; radii must be non-negative and not
    /// both zero.
    pub fn new(base: Vec3<S>, base_radius: S, apex: Vec3<S>, apex_radius: S) -> Result<Self, GeometryError> {
        if !base.is_finite() || !apex.is_finite() || !base_radius.is_finite() || !apex_radius.is_finite() {
            return Err(GeometryError::NonFinite);
        }
        if base_radius < S::ZERO || apex_radius < S::ZERO || (base_radius == S::ZERO && apex_radius == S::ZERO) {
            return Err(GeometryError::NonPositiveRadius);
        }
        let axis = apex - base;
        let height = axis.length();
        if !(height > S::ZERO) || !height.is_finite() {
            return Err(GeometryError::ZeroLengthAxis);
        }
        let w = axis.scale(S::ONE / height);
        let (u, v) = w.orthonormal_basis();
        Ok(Cone { base, apex, base_radius, apex_radius, u, v, w, height, slope: (apex_radius - base_radius) / height })
    }

    /// Change of radius per unit of height, `(r_apex − r_base)/h`.
    pub fn slope(&self) -> S {
        self.slope
    }

    /// The same cone in the frame of `sim`, with scalar `T` (the slope has
    /// no unit and stays).
    pub fn similar<T: Scalar>(&self, sim: &Similarity) -> Cone<T> {
        Cone {
            base: sim.point(self.base),
            apex: sim.point(self.apex),
            base_radius: sim.length(self.base_radius),
            apex_radius: sim.length(self.apex_radius),
            u: sim.direction(self.u),
            v: sim.direction(self.v),
            w: sim.direction(self.w),
            height: sim.length(self.height),
            slope: T::from_f32(self.slope.to_f32()),
        }
    }

    /// `(base, base radius, apex, apex radius)`.
    pub fn ends(&self) -> (Vec3<S>, S, Vec3<S>, S) {
        (self.base, self.base_radius, self.apex, self.apex_radius)
    }

    /// Crossings of each active ray with the cone's side in `(t_min, t_max)`.
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
        // Solve from a point of the ray near the cone rather than from its
        // origin: from a far origin, c = x² + y² − r² and b² − a·c keep
        // nothing of the radius, and a thin cone would be reported hit units
        // away from it. The point is the ray's nearest to the axis, moved
        // along the ray until its axial coordinate lies on the piece [0, h]:
        // where the ray passes near the cone, that point is within the
        // cone's radius of the axis and on its length, however long the
        // cone is, so the numbers below are of the cone's own size across
        // the axis. (The ray's nearest point to the base is not: for a cone
        // much longer than it is wide it can lie a whole length away.)
        //
        // Work in the cone's frame (orthonormal: distances along the ray
        // unchanged): the origin at (px, py, pz) from the base, the
        // direction (dx, dy, dz).
        let from_base = ray.origin.sub_splat(self.base);
        let (px, py, pz) = (from_base.dot_splat(self.u), from_base.dot_splat(self.v), from_base.dot_splat(self.w));
        // (Unit vectors: products of small factors.)
        let (dx, dy, dz) =
            (ray.dir.dot_splat_small(self.u), ray.dir.dot_splat_small(self.v), ray.dir.dot_splat_small(self.w));
        // Across the axis the ray is (px, py) + t·(dx, dy): nearest the axis
        // at t_axis = −(px·dx + py·dy)/(dx² + dy²), formed from the origin's
        // distance to the axis, not from its distance along it (so a far
        // base costs no precision). A ray parallel to the axis
        // (dx = dy = 0) takes t = 0, the numerator (`div_nonzero` returns it).
        let across = dx * dx + dy * dy;
        let t_axis = (-(px * dx + py * dy)).div_nonzero(across);
        // Where that point's axial coordinate z leaves [0, h], move to the
        // ray's point nearest the axis point at the end: along the ray that
        // is (z_end − z)·dz further (the connecting segment stays across the
        // axis). Any shift is exact in theory, t = shift + s; only the
        // rounding depends on it.
        let z_axis = pz + t_axis * dz;
        let h = Lanes::splat(self.height);
        let shift = t_axis + (z_axis.max(Lanes::zero()).min(h) - z_axis) * dz;
        let (ox, oy, oz) = (px + dx * shift, py + dy * shift, pz + dz * shift);
        // Surface: x² + y² = r(z)², r(z) = r_b + k·z. With x = o + t·d this is
        // a t² + 2b' t + c = 0 (half-b form).
        let k = self.slope;
        let r_o = oz * k + self.base_radius;
        let a = across - dz * dz * (k * k);
        let b = ox * dx + oy * dy - dz * r_o * k;
        let c = ox * ox + oy * oy - r_o * r_o;
        // Compute the discriminant (of the half-b form); a = 0 is linear.
        let disc = b * b - a * c;
        let linear = a.eq_lanes(Lanes::zero());
        let quad = active & !linear & disc.ge(Lanes::zero());
        let lin = active & linear & b.ne_lanes(Lanes::zero());
        if (quad | lin).none() {
            return Roots::none();
        }
        // q = −(b' + sign(b')·√Δ'): roots q/a and c/q, without cancellation.
        let sq = Lanes::select(quad, disc, Lanes::zero()).sqrt();
        let q = Lanes::select(b.ge(Lanes::zero()), -(b + sq), sq - b);
        // The first root is q/a, or −c/(2b') where the equation is linear
        // (2b' t + c = 0): one division of the selected operands, the same
        // bits as either division alone.
        let s0 = Lanes::select(lin, -c, q).div_nonzero(Lanes::select(lin, b * S::TWO, a));
        let s1 = c.div_nonzero(q);
        // Keep roots whose axial coordinate lies on the finite piece [0, h]
        // (this also removes the mirror nappe of a true cone).
        // (Written out twice rather than as a closure, which LLVM may leave
        // un-inlined and so compiled for the baseline instruction set.)
        let z0 = oz + dz * s0;
        let z1 = oz + dz * s1;
        let ok0 = (quad | lin) & z0.ge(Lanes::zero()) & z0.le(h);
        let ok1 = quad & q.ne_lanes(Lanes::zero()) & z1.ge(Lanes::zero()) & z1.le(h);
        Roots::from_candidates(shift + s0, ok0, shift + s1, ok1, t_min, t_max)
    }

    /// Outward normals (not normalized) at the points `p` on the side.
    #[inline(always)]
    pub fn normals<const W: usize>(&self, p: &Vec3xW<S, W>) -> Vec3xW<S, W> {
        let rel = p.sub_splat(self.base);
        let (x, y, z) = (rel.dot_splat(self.u), rel.dot_splat(self.v), rel.dot_splat(self.w));
        // Gradient of x² + y² − r(z)², halved: (x, y, −k·r(z)).
        let r = Lanes::splat(self.base_radius) + z * self.slope;
        self.u.splat::<W>().scale_lanes(x) + self.v.splat::<W>().scale_lanes(y)
            - self.w.splat::<W>().scale_lanes(r * self.slope)
    }

    /// Axis-aligned bounds `(min, max)`: the union of the two end discs.
    pub fn bounds(&self) -> (Vec3<S>, Vec3<S>) {
        // A disc of radius r with unit normal w extends r·√(1 − w_a²) along axis a.
        let ext = |r: S| {
            let e = |wa: S| r * (S::ONE - wa * wa).max(S::ZERO).sqrt();
            Vec3::new(e(self.w.x), e(self.w.y), e(self.w.z))
        };
        let (eb, ea) = (ext(self.base_radius), ext(self.apex_radius));
        let lo = (self.base - eb).min_elem(self.apex - ea);
        let hi = (self.base + eb).max_elem(self.apex + ea);
        (lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::primitives::test_util::*;
    use crate::geom::primitives::Shape;

    fn close(a: &[f32], b: &[f32]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-4)
    }

    #[test]
    fn cylinder_side_and_open_ends() {
        let c = Shape::Cone(Cone::new(Vec3::new(0.0f32, 0.0, 0.0), 1.0, Vec3::new(0.0, 0.0, 2.0), 1.0).unwrap());
        assert!(close(&hits(&c, [-5.0, 0.0, 1.0], [1.0, 0.0, 0.0]), &[4.0, 6.0]));
        // Beyond the ends: miss; through the open end along the axis: miss.
        assert!(hits(&c, [-5.0, 0.0, 3.0], [1.0, 0.0, 0.0]).is_empty());
        assert!(hits(&c, [0.0, 0.0, -5.0], [0.0, 0.0, 1.0]).is_empty());
        // Inside, sideways: one root.
        assert!(close(&hits(&c, [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]), &[1.0]));
        // Into the open end at a slant: hits the inside wall once.
        let d = [1.0f32, 0.0, 1.0];
        let h = hits(&c, [0.0, 0.0, 0.5], d);
        assert!(close(&h, &[2.0f32.sqrt()]), "{h:?}");
    }

    #[test]
    fn true_cone_excludes_mirror_nappe() {
        // Radius 1 at z = 0 to a point at z = 1.
        let c = Shape::Cone(Cone::new(Vec3::new(0.0f32, 0.0, 0.0), 1.0, Vec3::new(0.0, 0.0, 1.0), 0.0).unwrap());
        assert!(close(&hits(&c, [-5.0, 0.0, 0.5], [1.0, 0.0, 0.0]), &[4.5, 5.5]));
        // At z = 1.5 only the mirror nappe would be hit.
        assert!(hits(&c, [-5.0, 0.0, 1.5], [1.0, 0.0, 0.0]).is_empty());
    }

    #[test]
    fn slanted_axis_matches_exact_geometry() {
        // Cylinder from (0,0,0) to (1,1,1), radius 0.5; a ray through the axis
        // midpoint perpendicular to the axis meets the side at ±0.5.
        let c = Shape::Cone(Cone::new(Vec3::new(0.0f32, 0.0, 0.0), 0.5, Vec3::new(1.0, 1.0, 1.0), 0.5).unwrap());
        let m = 0.5f32;
        let d = [1.0f32, -1.0, 0.0];
        let s = 1.0 / 2.0f32.sqrt();
        let o = [m - 3.0 * s, m + 3.0 * s, m];
        assert!(close(&hits(&c, o, d), &[2.5, 3.5]));
    }

    #[test]
    fn outward_normal() {
        let c = Cone::new(Vec3::new(0.0f32, 0.0, 0.0), 1.0, Vec3::new(0.0, 0.0, 1.0), 0.0).unwrap();
        let n = c.normals::<1>(&Vec3::new(0.5, 0.0, 0.5).splat()).lane(0).normalize_or_zero();
        let e = Vec3::new(1.0, 0.0, 1.0).normalize_or_zero();
        assert!((n - e).length() < 1e-6, "{n:?}");
    }

    #[test]
    fn long_thin_cones_are_hit_only_on_their_side() {
        // Cones up to 10⁶ times longer than they are wide, rays from within
        // a few units of a random point of the axis, aimed across the axis
        // at up to three radii from it. Every reported crossing must lie on
        // the side (checked in f64 from the f32 ray and t), and a ray aimed
        // through the axis inside the piece must cross it.
        let mut state = 0x5eed_c0e5u64;
        let mut unit = || (crate::num::test_rng::splitmix64(&mut state) >> 40) as f64 / (1u64 << 24) as f64;
        let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let f64s = |v: Vec3<f32>| [v.x as f64, v.y as f64, v.z as f64];
        let (mut checked, mut through) = (0, 0);
        for _ in 0..1000 {
            let len = 10f64.powf(1.0 + 5.0 * unit());
            let (rb, ra) = (0.05 + 0.4 * unit(), if unit() < 0.5 { 0.0 } else { 0.05 + 0.4 * unit() });
            let base = [len, 0.6 + unit(), unit() - 0.5];
            let apex = [3.0 * unit(), 0.6, 1.2 * unit()];
            let Ok(cone) = Cone::new(
                Vec3::new(base[0] as f32, base[1] as f32, base[2] as f32),
                rb as f32,
                Vec3::new(apex[0] as f32, apex[1] as f32, apex[2] as f32),
                ra as f32,
            ) else {
                continue;
            };
            // The cone exactly as stored (f32 ends and radii), in f64.
            let (b, rb, a, ra) = cone.ends();
            let (b, a, rb, ra) = (f64s(b), f64s(a), rb as f64, ra as f64);
            let ax: [f64; 3] = core::array::from_fn(|i| a[i] - b[i]);
            let h = dot(&ax, &ax).sqrt();
            let w = ax.map(|x| x / h);
            // A point on the axis at fraction f, and a perpendicular offset.
            let near_apex = unit() < 0.5;
            let f = if near_apex { 1.0 - (30.0 / h).min(0.98) * unit() } else { 0.02 + 0.96 * unit() };
            let z = f * h;
            let r_z = rb + (ra - rb) * f;
            let on_axis = [b[0] + w[0] * z, b[1] + w[1] * z, b[2] + w[2] * z];
            let rho = if unit() < 0.25 { 0.0 } else { 3.0 * r_z * unit() };
            let side = [-w[1], w[0], 0.0];
            let sn = (side[0] * side[0] + side[1] * side[1]).sqrt();
            let target = [on_axis[0] + side[0] / sn * rho, on_axis[1] + side[1] / sn * rho, on_axis[2]];
            // Rays from within a few units of the target; for targets within
            // 30 units of the apex, half of them from above the axis up to
            // 40 units either side of the apex (a camera near a thin cone's
            // tip, looking along it or across it).
            let o = if !near_apex || unit() < 0.5 {
                [target[0] + 4.0 * (unit() - 0.5), target[1] + 4.0 * (unit() - 0.5), target[2] + 2.0 + unit()]
            } else {
                let (back, up) = (80.0 * unit() - 40.0, 2.0 + 10.0 * unit());
                [a[0] - w[0] * back, a[1] - w[1] * back + up * (unit() - 0.5), a[2] + up]
            };
            let d = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
            let dl = dot(&d, &d).sqrt();
            let (o32, d32) = (o.map(|x| x as f32), d.map(|x| (x / dl) as f32));
            let found = hits(&Shape::Cone(cone), o32, d32);
            // The cone as the kernel defines it: its f32 frame (u, v, w),
            // base and slope taken exactly into f64, so the check measures
            // the kernel's arithmetic, not the rounding of its frame.
            let (ku, kv, kw) = (f64s(cone.u), f64s(cone.v), f64s(cone.w));
            let (k, hk) = (cone.slope as f64, cone.height as f64);
            for t in &found {
                let p: [f64; 3] = core::array::from_fn(|i| o32[i] as f64 + d32[i] as f64 * *t as f64 - b[i]);
                let (x, y, zp) = (dot(&p, &ku), dot(&p, &kv), dot(&p, &kw));
                let dist = (x * x + y * y).sqrt();
                let r = rb + k * zp;
                // Allowance: the rounding of t (its last bit moves the point
                // along the ray), of the axial coordinate times the slope,
                // and of numbers of the ray's size near the cone.
                let tol = 2e-5
                    + 1e-7 * (*t as f64) * (1.0 - dot(&kw, &d32.map(|x| x as f64)).powi(2)).max(0.0).sqrt()
                    + 1e-7 * zp.abs() * k.abs();
                assert!((dist - r).abs() <= tol && zp >= -1e-7 * hk && zp <= hk * (1.0 + 1e-7),
                    "len {len}: a crossing at t = {t} is {dist} from the axis where the radius is {r} (z {zp} of {hk}; allowed {tol}; ray {o32:?} + t·{d32:?})");
                checked += 1;
            }
            if rho == 0.0 && f > 0.05 && f < 0.95 {
                assert!(!found.is_empty(), "len {len}: a ray through the axis at {f} of the length missed");
                through += 1;
            }
        }
        assert!(checked > 700 && through > 100, "{checked} crossings, {through} rays through the axis");
    }

    #[test]
    fn degenerate_input_is_rejected() {
        let o = Vec3::new(0.0f32, 0.0, 0.0);
        assert_eq!(Cone::new(o, 1.0, o, 1.0), Err(GeometryError::ZeroLengthAxis));
        let z = Vec3::new(0.0f32, 0.0, 1.0);
        assert_eq!(Cone::new(o, 0.0, z, 0.0), Err(GeometryError::NonPositiveRadius));
        assert_eq!(Cone::new(o, -1.0, z, 1.0), Err(GeometryError::NonPositiveRadius));
        assert_eq!(Cone::new(o, f32::NAN, z, 1.0), Err(GeometryError::NonFinite));
    }
}
