//! Packet traversal: closest hit and shadow transmittance, bit-identical to
//! the brute-force loops of [`SceneView`].
//!
//! Why the answers cannot differ:
//! - A node is skipped only when no lane's ray segment meets its padded box,
//!   and the padding exceeds the rounding of every primitive kernel (see the
//!   module documentation of `bvh`), so a skipped primitive would not have
//!   reported a crossing.
//! - Closest hit: brute force keeps, per lane, the nearest root and among
//!   equal roots the lowest primitive index. The tree visits primitives in
//!   another order, so each primitive is asked for roots up to just beyond
//!   the best distance so far (one part in 2²² further) and a root exactly
//!   equal to the best replaces it when its index is lower. A primitive's
//!   nearest root does not depend on the interval's far end, only whether it
//!   is reported, so the winner is the same primitive with the same `t`.
//! - Shadows: any opaque crossing makes the result exactly 0 whatever the
//!   order, so opaque hits end a lane at once (any-hit). Transmissive
//!   crossings multiply the light by `Kt` in primitive order in brute force,
//!   and float products depend on order, so they are recorded and applied
//!   afterwards sorted by primitive index. If a packet crosses more
//!   transmissive primitives than the record holds, the packet falls back to
//!   the brute-force loop.

use super::{BvhNode, BvhView, MAX_DEPTH};
use crate::lanes::{Lanes, Mask};
use crate::ray::RayPacket;
use crate::scalar::Scalar;
use crate::scene::{Hit, SceneView};
use crate::vec3::Vec3xW;

/// Transmissive crossings a shadow query records before falling back.
const RECORDS: usize = 32;

/// What a packet needs for slab tests: origins and guarded reciprocal
/// directions.
struct SlabRays<S, const W: usize> {
    origin: Vec3xW<S, W>,
    inv_dir: Vec3xW<S, W>,
    /// For each axis, whether the first active lane travels towards −axis
    /// (then the upper child is nearer).
    dir_neg: [bool; 3],
}

impl<S: Scalar, const W: usize> SlabRays<S, W> {
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn new(ray: &RayPacket<S, W>, active: Mask<W>) -> Self {
        // A zero direction component would give 0·∞ = NaN at a slab plane
        // through the origin; replace |d| < 2⁻⁶⁰ by ±2⁻⁶⁰, which moves the
        // ray by at most 2⁻⁶⁰·t along that axis, far inside the padding.
        let tiny = Lanes::splat(S::from_f32(8.673617e-19));
        let guard = |d: Lanes<S, W>| {
            let small = d.abs().lt(tiny);
            let signed = Lanes::select(d.lt(Lanes::zero()), -tiny, tiny);
            Lanes::splat(S::ONE) / Lanes::select(small, signed, d)
        };
        let inv_dir = Vec3xW::new(guard(ray.dir.x), guard(ray.dir.y), guard(ray.dir.z));
        let mut first = 0;
        for i in 0..W {
            if active.get(i) {
                first = i;
                break;
            }
        }
        let d = ray.dir.lane(first);
        SlabRays { origin: ray.origin, inv_dir, dir_neg: [d.x < S::ZERO, d.y < S::ZERO, d.z < S::ZERO] }
    }

    /// Lanes of `active` whose segment `[t_min, t_far]` meets the box.
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn hits(&self, node: &BvhNode<S>, t_min: Lanes<S, W>, t_far: Lanes<S, W>, active: Mask<W>) -> Mask<W> {
        let x0 = (Lanes::splat(node.min.x) - self.origin.x) * self.inv_dir.x;
        let x1 = (Lanes::splat(node.max.x) - self.origin.x) * self.inv_dir.x;
        let y0 = (Lanes::splat(node.min.y) - self.origin.y) * self.inv_dir.y;
        let y1 = (Lanes::splat(node.max.y) - self.origin.y) * self.inv_dir.y;
        let z0 = (Lanes::splat(node.min.z) - self.origin.z) * self.inv_dir.z;
        let z1 = (Lanes::splat(node.max.z) - self.origin.z) * self.inv_dir.z;
        let near = x0.min(x1).max(y0.min(y1)).max(z0.min(z1)).max(t_min);
        let far = x0.max(x1).min(y0.max(y1)).min(z0.max(z1)).min(t_far);
        active & near.le(far)
    }
}

/// `t` a little beyond `best` where `found` (so that roots equal to `best`
/// come back), `best` elsewhere.
#[cfg_attr(not(debug_assertions), inline(always))]
fn tie_limit<S: Scalar, const W: usize>(best: Lanes<S, W>, found: Mask<W>) -> Lanes<S, W> {
    // best·(1 + 2⁻²²) is at least two ulps above a normal `best`; the
    // smallest normal covers subnormal ones.
    let rel = Lanes::splat(S::from_f32(1.0 / 4_194_304.0));
    let abs = Lanes::splat(S::from_f32(f32::MIN_POSITIVE));
    Lanes::select(found, best + best.abs() * rel + abs, best)
}

/// Lanes where `k` is below the current best index.
#[cfg_attr(not(debug_assertions), inline(always))]
fn index_below<const W: usize>(k: u32, best: &[u32; W]) -> Mask<W> {
    let mut m = [false; W];
    for i in 0..W {
        m[i] = k < best[i];
    }
    Mask::from_array(m)
}

/// Visits the leaves whose boxes some lane of `live()` reaches, nearest
/// child first; `far()` is re-read at every node so that closer hits prune
/// the rest. `visit` gets each leaf's primitives with the lanes that reach
/// the leaf and returns `false` to stop.
#[cfg_attr(not(debug_assertions), inline(always))]
fn walk<S: Scalar, const W: usize>(
    bvh: &BvhView<'_, S>,
    slab: &SlabRays<S, W>,
    t_min: Lanes<S, W>,
    mut state: impl FnMut(Option<(&[u32], Mask<W>)>) -> (Lanes<S, W>, Mask<W>, bool),
) {
    if bvh.nodes.is_empty() {
        return;
    }
    // The builder bounds the depth by MAX_DEPTH, and each level leaves at
    // most one sibling on the stack.
    let mut stack = [0u32; MAX_DEPTH + 1];
    let mut sp = 0usize;
    let mut node = 0u32;
    loop {
        let (t_far, live, go_on) = state(None);
        if !go_on {
            return;
        }
        if let Some(n) = bvh.nodes.get(node as usize) {
            let m = slab.hits(n, t_min, t_far, live);
            if m.any() {
                if n.is_leaf() {
                    let (_, _, go_on) = state(Some((bvh.leaf_primitives(n), m)));
                    if !go_on {
                        return;
                    }
                } else if let Some(slot) = stack.get_mut(sp) {
                    let first = n.link();
                    let (near, far) = if slab.dir_neg.get(n.axis()).copied().unwrap_or(false) { (first + 1, first) } else { (first, first + 1) };
                    *slot = far;
                    sp += 1;
                    node = near;
                    continue;
                }
            }
        }
        if sp == 0 {
            return;
        }
        sp -= 1;
        // (`get`, not indexing: the render path has no panic path.)
        match stack.get(sp) {
            Some(&next) => node = next,
            None => return,
        }
    }
}

impl<'a, S: Scalar> BvhView<'a, S> {
    /// [`SceneView::closest_hit`] through the tree.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn closest_hit<const W: usize>(
        &self,
        scene: &SceneView<'a, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Hit<S, W> {
        let mut best_t = t_max;
        let mut best_id = [u32::MAX; W];
        let mut found = Mask::splat(false);
        if active.any() {
            let prims = scene.primitives();
            let verts = scene.vertices();
            let test = |ids: &[u32], m: Mask<W>, best_t: &mut Lanes<S, W>, best_id: &mut [u32; W], found: &mut Mask<W>| {
                for &k in ids {
                    let Some(p) = prims.get(k as usize) else { continue };
                    let limit = tie_limit(*best_t, *found);
                    let (t, hit) = p.shape.roots(verts, ray, t_min, limit, m).nearest();
                    if hit.none() {
                        continue;
                    }
                    // Nearer, or as near with a lower index (brute force's order).
                    let closer = hit & (t.lt(*best_t) | (t.eq_lanes(*best_t) & index_below(k, best_id)));
                    *best_t = Lanes::select(closer, t, *best_t);
                    *best_id = closer.select_u32([k; W], *best_id);
                    *found |= closer;
                }
            };
            test(self.unbounded(), active, &mut best_t, &mut best_id, &mut found);
            let slab = SlabRays::new(ray, active);
            walk(self, &slab, t_min, |leaf| {
                if let Some((ids, m)) = leaf {
                    test(ids, m, &mut best_t, &mut best_id, &mut found);
                }
                (best_t, active, true)
            });
        }
        Hit { t: best_t, prim: best_id, mask: found }
    }

    /// [`SceneView::transmittance`] through the tree.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(crate) fn transmittance<const W: usize>(
        &self,
        scene: &SceneView<'a, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Lanes<S, W> {
        let zero = Lanes::zero();
        if active.none() {
            return zero;
        }
        let prims = scene.primitives();
        let verts = scene.vertices();
        let materials = scene.materials();
        // Transmissive crossings: (primitive, first crossing, second crossing).
        let mut records = [(0u32, Mask::<W>::splat(false), Mask::<W>::splat(false)); RECORDS];
        let mut recorded = 0usize;
        let mut overflow = false;
        let mut live = active;
        // Tests primitives `ids` for the lanes `m` (narrowed to the live ones).
        let mut test = |ids: &[u32], m: Mask<W>, live: &mut Mask<W>, overflow: &mut bool| {
            for &k in ids {
                let m = m & *live;
                if m.none() {
                    return;
                }
                let Some(p) = prims.get(k as usize) else { continue };
                let r = p.shape.roots(verts, ray, t_min, t_max, m);
                if r.hit0.none() {
                    continue;
                }
                let kt = materials.get(p.material as usize).map(|m| m.kt).unwrap_or(S::ZERO);
                if kt == S::ZERO {
                    // Opaque: exactly 0 whatever else these lanes cross.
                    *live = live.and_not(r.hit0);
                } else if let Some(slot) = records.get_mut(recorded) {
                    *slot = (k, r.hit0, r.hit1);
                    recorded += 1;
                } else {
                    *overflow = true;
                    return;
                }
            }
        };
        test(self.unbounded(), live, &mut live, &mut overflow);
        let slab = SlabRays::new(ray, active);
        walk(self, &slab, t_min, |leaf| {
            if let Some((ids, m)) = leaf {
                test(ids, m, &mut live, &mut overflow);
            }
            (t_max, live, live.any() && !overflow)
        });
        if live.none() {
            return zero;
        }
        if overflow {
            return scene.transmittance_brute_force(ray, t_min, t_max, active);
        }
        // Apply the factors in primitive order, as brute force does.
        // (Checked slicing and access: the render path has no panic path.)
        let records = records.get_mut(..recorded).unwrap_or(&mut []);
        for i in 1..records.len() {
            let mut j = i;
            while j > 0 {
                match records.get_mut(j - 1..=j) {
                    Some([a, b]) if a.0 > b.0 => core::mem::swap(a, b),
                    _ => break,
                }
                j -= 1;
            }
        }
        let mut trans = Lanes::select(live, Lanes::splat(S::ONE), zero);
        for &(k, hit0, hit1) in records.iter() {
            let kt = prims
                .get(k as usize)
                .and_then(|p| materials.get(p.material as usize))
                .map(|m| m.kt)
                .unwrap_or(S::ZERO);
            trans = Lanes::select(hit0, trans * kt, trans);
            trans = Lanes::select(hit1, trans * kt, trans);
        }
        Lanes::select(live, trans, zero)
    }
}
