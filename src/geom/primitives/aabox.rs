//! Axis-aligned box, by the slab test; the slab code is shared with the
//! oriented box, which runs it in the box's own frame.

use super::error::GeometryError;
use crate::geom::ray::{RayPacket, Roots};
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::{Vec3, Vec3xW};
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;

/// An axis-aligned box `[min, max]` (solid for visibility: a ray crosses its
/// surface where it enters and where it leaves).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AaBox<S> {
    min: Vec3<S>,
    max: Vec3<S>,
}

crate::num::bake::bake_struct!("raypack::geom::primitives::AaBox", AaBox<S> { min: Vec3<S>, max: Vec3<S> });

impl<S: Scalar> AaBox<S> {
    /// The same box in the frame of `sim`, with scalar `T`.
    pub fn similar<T: Scalar>(&self, sim: &Similarity) -> AaBox<T> {
        AaBox { min: sim.point(self.min), max: sim.point(self.max) }
    }

    /// The box between two opposite corners, given in any order. A box may be
    /// flat (zero thickness along an axis); it is then a rectangle.
    pub fn new(a: Vec3<S>, b: Vec3<S>) -> Result<Self, GeometryError> {
        if !a.is_finite() || !b.is_finite() {
            return Err(GeometryError::NonFinite);
        }
        Ok(AaBox { min: a.min_elem(b), max: a.max_elem(b) })
    }

    /// Minimum corner.
    pub fn min(&self) -> Vec3<S> {
        self.min
    }
    /// Maximum corner.
    pub fn max(&self) -> Vec3<S> {
        self.max
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
        slab_roots(ray.origin, ray.dir, self.min, self.max, t_min, t_max, active, LEAVE_EARLY)
    }

    /// Outward normal at a point on the surface: the axis of the face the
    /// point is nearest to (ties resolved x, then y, then z).
    #[inline(always)]
    pub fn normals<const W: usize>(&self, p: &Vec3xW<S, W>) -> Vec3xW<S, W> {
        face_normals(p, self.min, self.max)
    }
}

/// Whether the kernels' slab tests leave out, after each axis, the lanes
/// that can no longer hit ([`slab_roots`]): where a division is a long
/// routine (fixed point, soft float), not on x86, where it is one
/// instruction and the tests would cost more than they spare.
pub(crate) const LEAVE_EARLY: bool = !cfg!(any(target_arch = "x86", target_arch = "x86_64"));

/// Entry and exit of rays through the slabs `min <= x <= max` on each axis.
///
/// Each axis gives an interval `[t_near, t_far]`; the box is hit where the
/// largest `t_near` is no greater than the smallest `t_far`. A ray parallel to
/// an axis (direction component exactly zero) is handled without dividing by
/// zero: the slab is the whole line when the origin lies between its planes,
/// and empty otherwise.
///
/// With `leave` (the kernels pass [`LEAVE_EARLY`]), lanes that can no
/// longer hit are left out after each axis; the result is the same either
/// way, and both are tested on every host.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn slab_roots<S: Scalar, const W: usize>(
    origin: Vec3xW<S, W>,
    dir: Vec3xW<S, W>,
    min: Vec3<S>,
    max: Vec3<S>,
    t_min: Lanes<S, W>,
    t_max: Lanes<S, W>,
    active: Mask<W>,
    leave: bool,
) -> Roots<S, W> {
    // A ray outside a slab and not moving into it (the origin below `min`
    // with the direction component at most 0, or above `max` with it at
    // least 0) has its whole slab interval at `t <= 0`, which no `t_min ≥ 0`
    // keeps: those lanes skip the six divisions with the same result.
    let zero = Lanes::zero();
    let away =
        away(origin.x, dir.x, min.x, max.x) | away(origin.y, dir.y, min.y, max.y) | away(origin.z, dir.z, min.z, max.z);
    let active = active & (!away | t_min.lt(zero));
    if active.none() {
        return Roots::none();
    }
    let (nx, fx) = slab_axis(origin.x, dir.x, min.x, max.x);
    // With `leave`: lanes whose interval so far already lies outside
    // `(t_min, t_max)`, or is empty, are left out before the next axis's
    // two divisions. The final interval lies inside every partial one (the
    // entry only grows, the exit only shrinks), so none of their roots
    // would count: the same result. (A NaN compares false and stays in,
    // as it would.)
    let active = if leave { active.and_not(nx.ge(t_max) | fx.le(t_min)) } else { active };
    if leave && active.none() {
        return Roots::none();
    }
    let (ny, fy) = slab_axis(origin.y, dir.y, min.y, max.y);
    let (n, f) = (nx.max(ny), fx.min(fy));
    let active = if leave { active.and_not(n.gt(f) | n.ge(t_max) | f.le(t_min)) } else { active };
    if leave && active.none() {
        return Roots::none();
    }
    let (nz, fz) = slab_axis(origin.z, dir.z, min.z, max.z);
    // The ray is inside the box between the last entry and the first exit.
    let t_near = n.max(nz);
    let t_far = f.min(fz);
    let hit = active & t_near.le(t_far);
    if hit.none() {
        return Roots::none();
    }
    Roots::from_candidates(t_near, hit, t_far, hit & t_far.gt(t_near), t_min, t_max)
}

/// Lanes outside the slab `[lo, hi]` and not moving into it (a function,
/// not a closure, so that it is inlined: see `dispatch`).
#[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
fn away<S: Scalar, const W: usize>(o: Lanes<S, W>, d: Lanes<S, W>, lo: S, hi: S) -> Mask<W> {
    let zero = Lanes::zero();
    (o.lt(Lanes::splat(lo)) & d.le(zero)) | (o.gt(Lanes::splat(hi)) & d.ge(zero))
}

/// Entry and exit distances `(near, far)` of one slab `lo <= o + t·d <= hi`.
///
/// A function rather than a closure so that it is inlined (and compiled for
/// the instruction set of the caller; see `dispatch`).
#[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
fn slab_axis<S: Scalar, const W: usize>(o: Lanes<S, W>, d: Lanes<S, W>, lo: S, hi: S) -> (Lanes<S, W>, Lanes<S, W>) {
    let big = Lanes::splat(S::MAX);
    {
        let parallel = d.eq_lanes(Lanes::zero());
        // Distances to both slab planes; the division is guarded for parallel lanes.
        let (t1, t2) = (Lanes::splat(lo) - o).div_pair_nonzero(Lanes::splat(hi) - o, d);
        let near = t1.min(t2);
        let far = t1.max(t2);
        // Parallel: all of the line inside the slab, or none of it.
        let inside = o.ge(Lanes::splat(lo)) & o.le(Lanes::splat(hi));
        let near = Lanes::select(parallel, Lanes::select(inside, -big, big), near);
        let far = Lanes::select(parallel, Lanes::select(inside, big, -big), far);
        (near, far)
    }
}

/// Outward normals of the faces of `[min, max]` nearest to the points `p`:
/// the first axis with the smallest distance; on an axis, the `max` face
/// when strictly nearer.
#[inline(always)]
pub(crate) fn face_normals<S: Scalar, const W: usize>(p: &Vec3xW<S, W>, min: Vec3<S>, max: Vec3<S>) -> Vec3xW<S, W> {
    let (one, zero) = (Lanes::splat(S::ONE), Lanes::<S, W>::zero());
    let mut best = Lanes::splat(S::MAX);
    let mut n = Vec3::new(zero, zero, zero);
    for axis in 0..3 {
        let pa = p.axis(axis);
        let lo = (pa - Lanes::splat(min.axis(axis))).abs();
        let hi = (Lanes::splat(max.axis(axis)) - pa).abs();
        let upper = hi.lt(lo);
        let d = Lanes::select(upper, hi, lo);
        let s = Lanes::select(upper, one, -one);
        let nearer = d.lt(best);
        best = Lanes::select(nearer, d, best);
        let face = match axis {
            0 => Vec3::new(s, zero, zero),
            1 => Vec3::new(zero, s, zero),
            _ => Vec3::new(zero, zero, s),
        };
        n = Vec3xW::select(nearer, face, n);
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::primitives::test_util::*;
    use crate::geom::primitives::Shape;

    fn cube() -> Shape<f32> {
        Shape::AaBox(AaBox::new(Vec3::new(1.0, 1.0, 1.0), Vec3::new(-1.0, -1.0, -1.0)).unwrap())
    }

    #[test]
    fn analytic_hit_and_normals() {
        assert_eq!(hits(&cube(), [0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), vec![4.0, 6.0]);
        assert_eq!(hits(&cube(), [3.0, 0.5, 0.5], [-1.0, 0.0, 0.0]), vec![2.0, 4.0]);
        let b = AaBox::new(Vec3::new(-1.0f32, -1.0, -1.0), Vec3::new(1.0, 1.0, 1.0)).unwrap();
        let n = |p: Vec3<f32>| b.normals::<1>(&p.splat()).lane(0);
        assert_eq!(n(Vec3::new(0.2, 1.0, 0.3)), Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(n(Vec3::new(-1.0, 0.1, 0.3)), Vec3::new(-1.0, 0.0, 0.0));
    }

    #[test]
    fn a_box_behind_the_origin_counts_only_for_a_negative_t_min() {
        // The cube lies at t ∈ [−6, −4] along +z from z = 5, and along −x
        // from x = −3 at t ∈ [−4, −2].
        assert_eq!(first_after(&cube(), 0.0, [0.0, 0.0, 5.0], [0.0, 0.0, 1.0]), None);
        assert_eq!(first_after(&cube(), -10.0, [0.0, 0.0, 5.0], [0.0, 0.0, 1.0]), Some(-6.0));
        assert_eq!(first_after(&cube(), -5.0, [0.0, 0.0, 5.0], [0.0, 0.0, 1.0]), Some(-4.0));
        assert_eq!(first_after(&cube(), 0.0, [-3.0, 0.5, 0.5], [-1.0, 0.0, 0.0]), None);
        assert_eq!(first_after(&cube(), -10.0, [-3.0, 0.5, 0.5], [-1.0, 0.0, 0.0]), Some(-4.0));
        // Outside a slab and parallel to it: never.
        assert_eq!(first_after(&cube(), -10.0, [0.0, 2.0, 5.0], [0.0, 0.0, 1.0]), None);
    }

    #[test]
    fn miss_inside_and_behind() {
        assert!(hits(&cube(), [0.0, 2.0, -5.0], [0.0, 0.0, 1.0]).is_empty());
        assert_eq!(hits(&cube(), [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]), vec![1.0]);
        assert!(hits(&cube(), [0.0, 0.0, 5.0], [0.0, 0.0, 1.0]).is_empty());
    }

    #[test]
    fn ray_parallel_to_slab() {
        // In the slab planes' interior: hits; outside: misses; on a face plane: grazes.
        assert_eq!(hits(&cube(), [-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]), vec![4.0, 6.0]);
        assert!(hits(&cube(), [-5.0, 1.5, 0.0], [1.0, 0.0, 0.0]).is_empty());
        assert_eq!(hits(&cube(), [-5.0, 1.0, 1.0], [1.0, 0.0, 0.0]), vec![4.0, 6.0]);
    }

    #[test]
    fn diagonal_through_corner_region() {
        let h = hits(&cube(), [-3.0, -3.0, -3.0], [1.0, 1.0, 1.0]);
        let s3 = 3.0f32.sqrt();
        assert_eq!(h.len(), 2);
        assert!((h[0] - 2.0 * s3).abs() < 1e-5 && (h[1] - 4.0 * s3).abs() < 1e-5, "{h:?}");
    }

    #[test]
    fn flat_box_is_a_rectangle() {
        let flat = Shape::AaBox(AaBox::new(Vec3::new(-1.0f32, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)).unwrap());
        assert_eq!(hits(&flat, [0.0, 0.0, -2.0], [0.0, 0.0, 1.0]), vec![2.0]);
    }

    #[test]
    fn degenerate_input_is_rejected() {
        assert_eq!(
            AaBox::new(Vec3::new(f32::INFINITY, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0)),
            Err(GeometryError::NonFinite)
        );
    }

    /// Leaving out lanes after each axis gives the same roots, bit for bit,
    /// at widths 1 and 4, in f32 and Q8.24 (the early exits run on the
    /// firmware targets, not on x86, so they are checked here): seeded
    /// boxes and rays from inside and outside, directions with zero
    /// components, intervals cut short and reaching behind the origin.
    fn leaving_lanes_early_changes_no_root<S: Scalar, const W: usize>(to_bits: fn(S) -> u32) {
        let mut x = 0x5ab5_u64 + W as u64;
        let mut u = || (crate::num::test_rng::splitmix64(&mut x) >> 40) as f32 / (1u64 << 24) as f32;
        let (mut hits, mut left) = (0, 0);
        for _ in 0..3000 {
            let c = [u() * 2.0 - 1.0, u() * 2.0 - 1.0, u() * 2.0 - 1.0];
            let h = [u() * 0.5 + 0.01, u() * 0.5 + 0.01, u() * 0.5 + 0.01];
            let min = Vec3::<S>::from_f32(c[0] - h[0], c[1] - h[1], c[2] - h[2]);
            let max = Vec3::<S>::from_f32(c[0] + h[0], c[1] + h[1], c[2] + h[2]);
            let lane = |u: &mut dyn FnMut() -> f32| {
                let o = [u() * 4.0 - 2.0, u() * 4.0 - 2.0, u() * 4.0 - 2.0];
                // Towards the box, or anywhere; a zero component now and then.
                let toward = u() < 0.6;
                let mut d = [0.0f32; 3];
                for a in 0..3 {
                    d[a] = if u() < 0.15 {
                        0.0
                    } else if toward {
                        c[a] - o[a] + u() - 0.5
                    } else {
                        u() * 2.0 - 1.0
                    };
                }
                let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-3);
                let t_min = [0.0, 1.0e-4, -1.0, u()][(u() * 4.0) as usize % 4];
                let t_max = if u() < 0.5 { f32::MAX } else { u() * 3.0 };
                (o, [d[0] / n, d[1] / n, d[2] / n], t_min, t_max)
            };
            let lanes: [([f32; 3], [f32; 3], f32, f32); W] = core::array::from_fn(|_| lane(&mut u));
            let v = |f: &dyn Fn(usize) -> [f32; 3]| -> Vec3xW<S, W> {
                Vec3::new(
                    Lanes(core::array::from_fn(|i| S::from_f32(f(i)[0]))),
                    Lanes(core::array::from_fn(|i| S::from_f32(f(i)[1]))),
                    Lanes(core::array::from_fn(|i| S::from_f32(f(i)[2]))),
                )
            };
            let (o, d) = (v(&|i| lanes[i].0), v(&|i| lanes[i].1));
            let t_min = Lanes(core::array::from_fn(|i| S::from_f32(lanes[i].2)));
            let t_max =
                Lanes(core::array::from_fn(|i| if lanes[i].3 == f32::MAX { S::MAX } else { S::from_f32(lanes[i].3) }));
            let active = Mask::from_array(core::array::from_fn(|_| u() < 0.9));
            let all = slab_roots(o, d, min, max, t_min, t_max, active, false);
            let leaving = slab_roots(o, d, min, max, t_min, t_max, active, true);
            let bits =
                |r: &Roots<S, W>| (r.t0.0.map(to_bits), r.t1.0.map(to_bits), r.hit0.to_array(), r.hit1.to_array());
            assert_eq!(bits(&leaving), bits(&all), "{lanes:?}");
            hits += all.hit0.to_array().iter().filter(|&&h| h).count();
            // Lanes the first axis alone would leave out.
            let (nx, fx) = slab_axis(o.x, d.x, min.x, max.x);
            left += (active & (nx.ge(t_max) | fx.le(t_min))).to_array().iter().filter(|&&a| a).count();
        }
        assert!(hits > 250 && left > 250, "{hits} hits, {left} lanes left out after x: too few to tell");
    }

    #[test]
    fn leaving_lanes_early_changes_no_root_f32() {
        leaving_lanes_early_changes_no_root::<f32, 1>(f32::to_bits);
        leaving_lanes_early_changes_no_root::<f32, 4>(f32::to_bits);
    }

    #[test]
    fn leaving_lanes_early_changes_no_root_fixed32() {
        use crate::num::fixed32::Fixed32;
        leaving_lanes_early_changes_no_root::<Fixed32, 1>(|x| x.to_bits() as u32);
        leaving_lanes_early_changes_no_root::<Fixed32, 4>(|x| x.to_bits() as u32);
    }
}
