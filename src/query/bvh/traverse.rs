//! Packet traversal: closest hit and shadow transmittance, bit-identical to
//! [`BruteForce`](crate::query::BruteForce).
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
//!
//! Sparse packets (at most an eighth of 8 or more lanes active, as
//! secondary rays may be) go one ray at a time: a packet's slab test
//! costs every lane, so a few live lanes pay for all `W` at each node,
//! while a single ray's walk visits only its own nodes. Each lane's answer
//! is the width-1 query's, which is the brute-force answer like every
//! width's, so the bytes do not change.

use super::node::{BvhNode, MAX_DEPTH};
use super::BvhView;
use crate::geom::ray::{Ray, RayPacket};
use crate::geom::vec3::Vec3xW;
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;
use crate::query::accelerator::{Accelerator, Hit, SceneMismatch};
use crate::query::brute;
use crate::scene::SceneView;
use heapless::Vec as HVec;

/// Transmissive crossings a shadow query records before falling back.
const RECORDS: usize = 32;

/// A shadow query's record of transmissive crossings.
type Records<const W: usize> = HVec<(u32, Mask<W>, Mask<W>), RECORDS>;

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
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn new(ray: &RayPacket<S, W>, active: Mask<W>) -> Self {
        // A zero direction component would give 0·∞ = NaN at a slab plane
        // through the origin; replace |d| < 2⁻⁶⁰ by ±2⁻⁶⁰, which moves the
        // ray by at most 2⁻⁶⁰·t along that axis, far inside the padding.
        let inv_dir = Vec3xW::new(guarded_recip(ray.dir.x), guarded_recip(ray.dir.y), guarded_recip(ray.dir.z));
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

    /// Slab rays for a walk that visits no node ([`Start::List`]): no
    /// reciprocals worked out.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn unused(ray: &RayPacket<S, W>) -> Self {
        SlabRays { origin: ray.origin, inv_dir: ray.dir, dir_neg: [false; 3] }
    }

    /// Lanes of `active` whose segment `[t_min, t_far]` meets the box.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn hits(&self, node: &BvhNode<S>, t_min: Lanes<S, W>, t_far: Lanes<S, W>, active: Mask<W>) -> Mask<W> {
        // One loop with each lane's whole test in its body (the same
        // operations, in the same order, as lane-wise `Lanes` arithmetic),
        // so that the vectoriser keeps all W lanes in whole registers:
        // written as twenty separate lane operations, the AVX-512 query
        // split 16 lanes into 4 + 8 + 4 pieces with spills
        // (docs/performance.md, "Packets of 16 and the slab test").
        let (o, inv) = (&self.origin, &self.inv_dir);
        let (lo, hi) = (node.min, node.max);
        let (mut near, mut far) = (t_min.0, t_far.0);
        for i in 0..W {
            let x0 = (lo.x - o.x.0[i]) * inv.x.0[i];
            let x1 = (hi.x - o.x.0[i]) * inv.x.0[i];
            let y0 = (lo.y - o.y.0[i]) * inv.y.0[i];
            let y1 = (hi.y - o.y.0[i]) * inv.y.0[i];
            let z0 = (lo.z - o.z.0[i]) * inv.z.0[i];
            let z1 = (hi.z - o.z.0[i]) * inv.z.0[i];
            near[i] = x0.min(x1).max(y0.min(y1)).max(z0.min(z1)).max(near[i]);
            far[i] = x0.max(x1).min(y0.max(y1)).min(z0.max(z1)).min(far[i]);
        }
        active & Lanes(near).le(Lanes(far))
    }
}

/// `1/d` with `|d| < 2⁻⁶⁰` replaced by `±2⁻⁶⁰` (see [`SlabRays::new`]).
/// (A function, not a closure: closures are not `inline(always)`, and
/// code left out of line is compiled for the baseline instruction set only.)
#[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
fn guarded_recip<S: Scalar, const W: usize>(d: Lanes<S, W>) -> Lanes<S, W> {
    let tiny = Lanes::splat(S::from_f32(8.673617e-19));
    let small = d.abs().lt(tiny);
    let signed = Lanes::select(d.lt(Lanes::zero()), -tiny, tiny);
    Lanes::splat(S::ONE) / Lanes::select(small, signed, d)
}

/// `t` a little beyond `best` where `found` (so that roots equal to `best`
/// come back), `best` elsewhere.
#[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
fn tie_limit<S: Scalar, const W: usize>(best: Lanes<S, W>, found: Mask<W>) -> Lanes<S, W> {
    // best·(1 + 2⁻²²) is at least two ulps above a normal `best`; the
    // smallest normal covers subnormal ones.
    let rel = Lanes::splat(S::from_f32(1.0 / 4_194_304.0));
    let abs = Lanes::splat(S::from_f32(f32::MIN_POSITIVE));
    Lanes::select(found, best + best.abs() * rel + abs, best)
}

/// Lanes where `k` is below the current best index.
#[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
fn index_below<const W: usize>(k: u32, best: &[u32; W]) -> Mask<W> {
    let mut m = [false; W];
    for i in 0..W {
        m[i] = k < best[i];
    }
    Mask::from_array(m)
}

/// What a descent does at the leaves: the one tree walk ([`walk`]) serves
/// closest-hit and shadow queries through this trait. (A trait with
/// `inline(always)` methods rather than closures: closures cannot be marked
/// `inline(always)`, and the instruction-set dispatcher compiles only what
/// is inlined into its entry points for AVX2/AVX-512.)
trait LeafVisitor<S, const W: usize> {
    /// The far end of the segments still of interest, the lanes still
    /// live, and whether to go on at all.
    fn state(&self) -> (Lanes<S, W>, Mask<W>, bool);
    /// Tests primitives `ids` for the lanes `m`. [`walk`] has one call site
    /// for it, so its kernels are compiled once per query. Forced inline on
    /// x86 (the dispatcher's copies need it); a function of its own
    /// elsewhere, where every byte of flash counts.
    fn leaf(&mut self, ids: &[u32], m: Mask<W>);
}

/// Visits the primitives outside the tree (for the lanes `outside`), then
/// the leaves whose boxes some lane of the visitor's live lanes reaches,
/// nearest child first. The visitor's state is re-read at every node so
/// that closer hits prune the rest and a finished query stops.
#[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
fn walk<'a, S: Scalar, const W: usize, V: LeafVisitor<S, W>>(
    bvh: &BvhView<'a, S>,
    slab: &SlabRays<S, W>,
    t_min: Lanes<S, W>,
    outside: Mask<W>,
    visitor: &mut V,
    start: Start<'a>,
) {
    // The builder bounds the depth by MAX_DEPTH, and each level leaves at
    // most one sibling on the stack.
    // (A `heapless::Vec`, so that nothing is zeroed per query.)
    let mut stack: HVec<u32, { MAX_DEPTH + 1 }> = HVec::new();
    // The next node to visit (the root first, if the tree has nodes) and the
    // leaf to test before it (the primitives outside the tree first, or a
    // camera tile's list and no node): one call site for the leaf tests, so
    // they are compiled once.
    let (mut next, mut leaf) = match start {
        Start::Root => (if bvh.nodes.is_empty() { None } else { Some(0u32) }, bvh.unbounded()),
        Start::List(ids) => (None, ids),
    };
    let mut leaf_mask = outside;
    loop {
        if !leaf.is_empty() {
            visitor.leaf(leaf, leaf_mask);
            leaf = &[];
        }
        let (t_far, live, go_on) = visitor.state();
        if !go_on {
            return;
        }
        let Some(index) = next else { return };
        if let Some(n) = bvh.nodes.get(index as usize) {
            let m = slab.hits(n, t_min, t_far, live);
            if m.any() {
                if n.is_leaf() {
                    leaf = bvh.leaf_primitives(n);
                    leaf_mask = m;
                } else {
                    let first = n.link();
                    let (near, far) = if slab.dir_neg.get(n.axis()).copied().unwrap_or(false) {
                        (first + 1, first)
                    } else {
                        (first, first + 1)
                    };
                    if stack.push(far).is_ok() {
                        next = Some(near);
                        continue;
                    }
                }
            }
        }
        // Pop the next sibling; with none left, the last leaf found is
        // still tested.
        next = stack.pop();
        if next.is_none() && leaf.is_empty() {
            return;
        }
    }
}

/// Where [`walk`] starts.
#[derive(Clone, Copy)]
enum Start<'a> {
    /// The primitives outside the tree, then the root.
    Root,
    /// Only these primitives (a camera tile's list): no node.
    List(&'a [u32]),
}

/// Closest-hit query state: per lane the nearest root so far and its
/// primitive (the lowest index among equal roots, as brute force keeps).
struct ClosestHit<'q, 'a, S, const W: usize> {
    scene: &'q SceneView<'a, S>,
    ray: &'q RayPacket<S, W>,
    t_min: Lanes<S, W>,
    active: Mask<W>,
    best_t: Lanes<S, W>,
    best_id: [u32; W],
    found: Mask<W>,
}

impl<S: Scalar, const W: usize> LeafVisitor<S, W> for ClosestHit<'_, '_, S, W> {
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn state(&self) -> (Lanes<S, W>, Mask<W>, bool) {
        (self.best_t, self.active, true)
    }

    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    #[cfg_attr(not(any(target_arch = "x86", target_arch = "x86_64")), inline(never))]
    fn leaf(&mut self, ids: &[u32], m: Mask<W>) {
        let prims = self.scene.primitives();
        let verts = self.scene.vertices();
        for &k in ids {
            let Some(p) = prims.get(k as usize) else { continue };
            let limit = tie_limit(self.best_t, self.found);
            let (t, hit) = p.shape.roots(verts, self.ray, self.t_min, limit, m).nearest();
            if hit.none() {
                continue;
            }
            // Nearer, or as near with a lower index (brute force's order).
            let closer = hit & (t.lt(self.best_t) | (t.eq_lanes(self.best_t) & index_below(k, &self.best_id)));
            self.best_t = Lanes::select(closer, t, self.best_t);
            self.best_id = closer.select_u32([k; W], self.best_id);
            self.found |= closer;
        }
    }
}

/// Shadow query state: lanes not yet blocked by an opaque primitive, and
/// the transmissive crossings met so far (applied later in index order).
struct Shadow<'q, 'a, S, const W: usize> {
    scene: &'q SceneView<'a, S>,
    ray: &'q RayPacket<S, W>,
    t_min: Lanes<S, W>,
    t_max: Lanes<S, W>,
    live: Mask<W>,
    /// Transmissive crossings: (primitive, first crossing, second crossing).
    /// A `heapless::Vec`, so nothing is written until a crossing is
    /// recorded; the caller's and borrowed, because as a field beside
    /// `overflow` LLVM merges the vector's length and the flag into one
    /// `memset` over the whole unwritten buffer (2 KB per shadow query).
    records: &'q mut Records<W>,
    /// More transmissive crossings than `records` holds.
    overflow: bool,
}

impl<S: Scalar, const W: usize> LeafVisitor<S, W> for Shadow<'_, '_, S, W> {
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn state(&self) -> (Lanes<S, W>, Mask<W>, bool) {
        (self.t_max, self.live, self.live.any() && !self.overflow)
    }

    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    #[cfg_attr(not(any(target_arch = "x86", target_arch = "x86_64")), inline(never))]
    fn leaf(&mut self, ids: &[u32], m: Mask<W>) {
        let prims = self.scene.primitives();
        let verts = self.scene.vertices();
        for &k in ids {
            // Only the lanes still live.
            let m = m & self.live;
            if m.none() {
                return;
            }
            let Some(p) = prims.get(k as usize) else { continue };
            let r = p.shape.roots(verts, self.ray, self.t_min, self.t_max, m);
            if r.hit0.none() {
                continue;
            }
            let kt = self.scene.kt_of_material(p.material);
            if kt == S::ZERO {
                // Opaque: exactly 0 whatever else these lanes cross.
                self.live = self.live.and_not(r.hit0);
            } else if self.records.push((k, r.hit0, r.hit1)).is_err() {
                self.overflow = true;
                return;
            }
        }
    }
}

/// Whether a packet is traced one ray at a time: 8 or more lanes, at most an
/// eighth of them active (one of 8, two of 16). Measured on x86 with
/// AVX-512 (`raypack bench`, docs/performance.md): packets of 16 trace
/// Whitted frames 3–16 % faster with it, packets of 8 within ±4 %; a
/// quarter of the lanes was slower at packet 8 (gears-2), half slower still.
#[inline(always)]
fn sparse<const W: usize>(active: Mask<W>) -> bool {
    W >= 8 && active.count() as usize <= W / 8
}

impl<'a, S: Scalar> BvhView<'a, S> {
    /// The width-1 closest hit of one ray, out of line: one copy per scalar
    /// that every width's sparse packets share.
    #[inline(never)]
    fn closest_hit_one(&self, scene: &SceneView<'_, S>, ray: &Ray<S>, t_min: S, t_max: S) -> (S, u32, bool) {
        let h = self.closest_hit(scene, ray, Lanes([t_min]), Lanes([t_max]), Mask::splat(true));
        (h.t.0[0], h.prim[0], h.mask.get(0))
    }

    /// The width-1 transmittance of one ray, out of line (as above).
    #[inline(never)]
    fn transmittance_one(&self, scene: &SceneView<'_, S>, ray: &Ray<S>, t_min: S, t_max: S) -> S {
        self.transmittance(scene, ray, Lanes([t_min]), Lanes([t_max]), Mask::splat(true)).0[0]
    }
}

impl<S: Scalar> Accelerator<S> for BvhView<'_, S> {
    fn check(&self, scene: &SceneView<'_, S>) -> Result<(), SceneMismatch> {
        // The tree, and its camera tiles if it has them, for this scene.
        let scene_has = scene.primitives().len();
        let tiles = self.camera.map_or(scene_has, |c| c.primitives());
        for built_for in [self.primitive_count(), tiles] {
            if built_for != scene_has {
                return Err(SceneMismatch { built_for, scene_has });
            }
        }
        Ok(())
    }

    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn closest_hit<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Hit<S, W> {
        if sparse(active) {
            let mut hit = Hit { t: t_max, prim: [u32::MAX; W], mask: Mask::splat(false) };
            for i in 0..W {
                if active.get(i) {
                    let (t, prim, found) = self.closest_hit_one(scene, &ray.lane(i), t_min.0[i], t_max.0[i]);
                    hit.t.0[i] = t;
                    hit.prim[i] = prim;
                    hit.mask.set(i, found);
                }
            }
            return hit;
        }
        let mut q =
            ClosestHit { scene, ray, t_min, active, best_t: t_max, best_id: [u32::MAX; W], found: Mask::splat(false) };
        if active.any() {
            // A packet of camera rays in one tile: its list. Otherwise the
            // primitives outside the tree first, then the tree.
            let (start, slab) = match self.camera.and_then(|c| c.list(ray, active)) {
                Some(ids) => (Start::List(ids), SlabRays::unused(ray)),
                None => (Start::Root, SlabRays::new(ray, active)),
            };
            walk(self, &slab, t_min, active, &mut q, start);
        }
        Hit { t: q.best_t, prim: q.best_id, mask: q.found }
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
        let zero = Lanes::zero();
        if active.none() {
            return zero;
        }
        if sparse(active) {
            let mut trans = zero;
            for i in 0..W {
                if active.get(i) {
                    trans.0[i] = self.transmittance_one(scene, &ray.lane(i), t_min.0[i], t_max.0[i]);
                }
            }
            return trans;
        }
        let mut records = Records::<W>::new();
        let mut q = Shadow { scene, ray, t_min, t_max, live: active, records: &mut records, overflow: false };
        // Primitives outside the tree first, then the tree.
        let slab = SlabRays::new(ray, active);
        walk(self, &slab, t_min, active, &mut q, Start::Root);
        let live = q.live;
        if live.none() {
            return zero;
        }
        if q.overflow {
            return brute::transmittance(scene, ray, t_min, t_max, active);
        }
        // Apply the factors in primitive order, as brute force does.
        let records = q.records.as_mut_slice();
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
        let prims = scene.primitives();
        let mut trans = Lanes::select(live, Lanes::splat(S::ONE), zero);
        for &(k, hit0, hit1) in records.iter() {
            let kt = prims.get(k as usize).map_or(S::ZERO, |p| scene.kt_of_material(p.material));
            trans = Lanes::select(hit0, trans * kt, trans);
            trans = Lanes::select(hit1, trans * kt, trans);
        }
        Lanes::select(live, trans, zero)
    }
}
