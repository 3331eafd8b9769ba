//! Brute force: every query tests every primitive, in index order. The
//! reference every other accelerator must match bit for bit, and the
//! accelerator of choice for small scenes and for firmware (no memory, and
//! no tree code in the image).

use super::accelerator::{Accelerator, Hit};
use super::cull::{candidate_indices, Candidates, ALL};
use crate::geom::primitives::Shape;
use crate::geom::ray::{RayPacket, Roots};
use crate::geom::vec3::Vec3;
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;
use crate::scene::SceneView;

/// Tests every primitive of the scene, in index order.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BruteForce;

impl<S: Scalar> Accelerator<S> for BruteForce {
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn closest_hit<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Hit<S, W> {
        closest_hit(scene, ray, t_min, t_max, active, ALL)
    }

    const CULLS: bool = true;

    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn closest_hit_among<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
        candidates: Candidates,
    ) -> Hit<S, W> {
        closest_hit(scene, ray, t_min, t_max, active, candidates)
    }

    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn transmittance<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Lanes<S, W> {
        transmittance_among(scene, ray, t_min, t_max, active, ALL)
    }

    // (In line on RV32 without hardware floats too, where the tracer's
    // shadow query is one out-of-line call holding it.)
    #[cfg_attr(
        all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64", rv32_soft_float)),
        inline(always)
    )]
    fn transmittance_among<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
        candidates: Candidates,
    ) -> Lanes<S, W> {
        transmittance_among(scene, ray, t_min, t_max, active, candidates)
    }
}

/// [`Accelerator::closest_hit`] by testing every candidate primitive
/// (bit `k` of `candidates`; from 32 on, every primitive) in index order.
#[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
pub(crate) fn closest_hit<S: Scalar, const W: usize>(
    scene: &SceneView<'_, S>,
    ray: &RayPacket<S, W>,
    t_min: Lanes<S, W>,
    t_max: Lanes<S, W>,
    active: Mask<W>,
    candidates: Candidates,
) -> Hit<S, W> {
    let mut best_t = t_max;
    let mut best_id = [u32::MAX; W];
    if active.any() {
        let prims = scene.primitives();
        let verts = scene.vertices();
        // Only the candidates: the others no active ray can cross.
        for k in candidate_indices(candidates, prims.len()) {
            let Some(p) = prims.get(k) else { break };
            // Only roots strictly nearer than the best so far come back, so a
            // later primitive at the same distance never replaces an earlier one.
            let r = roots(&p.shape, verts, ray, t_min, best_t, active);
            let (t, m) = r.nearest();
            if m.none() {
                continue;
            }
            best_t = Lanes::select(m, t, best_t);
            best_id = m.select_u32([k as u32; W], best_id);
        }
    }
    // Which lanes found something follows from the ids (kept out of the
    // loop to leave registers for the ray).
    let mut found = Mask::splat(false);
    for i in 0..W {
        found.set(i, best_id[i] != u32::MAX);
    }
    Hit { t: best_t, prim: best_id, mask: found }
}

/// [`Accelerator::transmittance`] by testing every primitive in index order.
#[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
pub(crate) fn transmittance<S: Scalar, const W: usize>(
    scene: &SceneView<'_, S>,
    ray: &RayPacket<S, W>,
    t_min: Lanes<S, W>,
    t_max: Lanes<S, W>,
    active: Mask<W>,
) -> Lanes<S, W> {
    transmittance_among(scene, ray, t_min, t_max, active, ALL)
}

/// [`Accelerator::transmittance`] by testing every candidate primitive
/// (as for [`closest_hit`]) in index order.
#[cfg_attr(
    all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64", rv32_soft_float)),
    inline(always)
)]
pub(crate) fn transmittance_among<S: Scalar, const W: usize>(
    scene: &SceneView<'_, S>,
    ray: &RayPacket<S, W>,
    t_min: Lanes<S, W>,
    t_max: Lanes<S, W>,
    active: Mask<W>,
    candidates: Candidates,
) -> Lanes<S, W> {
    let mut trans = Lanes::select(active, Lanes::splat(S::ONE), Lanes::zero());
    let mut live = active;
    let verts = scene.vertices();
    let prims = scene.primitives();
    // Only the candidates: the others no active ray can reach.
    for k in candidate_indices(candidates, prims.len()) {
        if live.none() {
            break;
        }
        let Some(p) = prims.get(k) else { break };
        let r = roots(&p.shape, verts, ray, t_min, t_max, live);
        if r.hit0.none() {
            continue;
        }
        let kt = scene.kt_of_material(p.material);
        if kt == S::ZERO {
            // Opaque: these lanes are in shadow; stop tracing them.
            trans = Lanes::select(r.hit0, Lanes::zero(), trans);
            live = live.and_not(r.hit0);
        } else {
            // One factor per crossing, in primitive order.
            trans = Lanes::select(r.hit0, trans * kt, trans);
            trans = Lanes::select(r.hit1, trans * kt, trans);
        }
    }
    trans
}

/// [`Shape::roots`] for the query loops. On RV32 the kernels of oriented
/// boxes, quadrics and cones (and, in soft float, of polygons and
/// axis-aligned boxes too) are one out-of-line copy per scalar and width
/// ([`roots_apart`]) shared by both loops, not one inlined into each: every
/// fixed-point product is inline code and every soft-float operation a
/// call, so the copies are large, and the 128 KiB test image holds both
/// scalars. Neither frame is slower for it (`scripts/firmware.sh`: with
/// polygons and boxes out of line too, soft-float `f32` retires 537.9 M
/// instructions against 539.5 M, and the image is 128 776 bytes of
/// `.text` against 132 600). Elsewhere every kernel stays where it was: on
/// the host and the Cortex-M4/M55 speed comes first, and on Armv6-M
/// [`Shape::roots`] is out of line already.
#[inline(always)]
fn roots<S: Scalar, const W: usize>(
    shape: &Shape<S>,
    pool: &[Vec3<S>],
    ray: &RayPacket<S, W>,
    t_min: Lanes<S, W>,
    t_max: Lanes<S, W>,
    active: Mask<W>,
) -> Roots<S, W> {
    const RV32: bool = cfg!(target_arch = "riscv32");
    const SOFT_FLOAT: bool = cfg!(not(target_feature = "f"));
    if RV32
        && (S::LIMITED_RANGE || SOFT_FLOAT)
        && (matches!(shape, Shape::OrientedBox(_) | Shape::Quadric(_) | Shape::Cone(_))
            || SOFT_FLOAT && !S::LIMITED_RANGE && matches!(shape, Shape::Polygon(_) | Shape::AaBox(_)))
    {
        return roots_apart(shape, pool, ray, t_min, t_max, active);
    }
    shape.roots(pool, ray, t_min, t_max, active)
}

/// [`Shape::roots`] out of line (see [`roots`]).
#[inline(never)]
fn roots_apart<S: Scalar, const W: usize>(
    shape: &Shape<S>,
    pool: &[Vec3<S>],
    ray: &RayPacket<S, W>,
    t_min: Lanes<S, W>,
    t_max: Lanes<S, W>,
    active: Mask<W>,
) -> Roots<S, W> {
    shape.roots(pool, ray, t_min, t_max, active)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::vec3::Vec3;
    use crate::scene::{Material, Scene};

    type Small = Scene<f32, 4, 8, 2, 1>;

    #[test]
    fn closest_hit_prefers_nearest_then_lowest_index() {
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        s.add_sphere(Vec3::new(0.0, 0.0, 10.0), 1.0, m).unwrap();
        s.add_sphere(Vec3::new(0.0, 0.0, 5.0), 1.0, m).unwrap();
        s.add_sphere(Vec3::new(0.0, 0.0, 5.0), 1.0, m).unwrap(); // same surface as 1
        let ray = crate::geom::ray::Ray::single(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0)).unwrap();
        let h = BruteForce.closest_hit(&s.view(), &ray, Lanes::splat(0.0), Lanes::splat(f32::MAX), Mask::splat(true));
        assert!(h.mask.get(0));
        assert_eq!(h.prim[0], 1);
        assert_eq!(h.t.0[0], 4.0);
    }

    #[test]
    fn transmittance_multiplies_kt_per_crossing() {
        let mut s = Small::new();
        let mut glass = Material::diffuse(Vec3::new(1.0, 1.0, 1.0));
        glass.kt = 0.5;
        let g = s.add_material(glass).unwrap();
        let o = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        s.add_sphere(Vec3::new(0.0, 0.0, 5.0), 1.0, g).unwrap();
        let ray = crate::geom::ray::Ray::single(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0)).unwrap();
        let all = Mask::splat(true);
        let shadow = |s: &Small, far: f32| {
            BruteForce.transmittance(&s.view(), &ray, Lanes::splat(0.0), Lanes::splat(far), all).0[0]
        };
        assert_eq!(shadow(&s, 10.0), 0.25);
        assert_eq!(shadow(&s, 5.0), 0.5);
        s.add_sphere(Vec3::new(0.0, 0.0, 8.0), 0.5, o).unwrap();
        assert_eq!(shadow(&s, 10.0), 0.0);
        // Inactive lanes return 0.
        assert_eq!(
            BruteForce.transmittance(&s.view(), &ray, Lanes::splat(0.0), Lanes::splat(1.0), Mask::splat(false)).0[0],
            0.0
        );
    }
}
