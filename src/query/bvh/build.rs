//! Binned SAH build, in place, without allocation or recursion.
//!
//! All build arithmetic is `f32` whatever the scene's scalar, done in a fixed
//! order, so every target builds the same tree. Ties in cost go to the lower
//! axis and then the lower bin; leaves list their primitives in index order.

use super::node::{BvhNode, BvhStats, MAX_DEPTH};
use crate::geom::vec3::Vec3;
use crate::num::scalar::Scalar;
use crate::query::cull::resolution;
use crate::scene::SceneView;

/// Most bins a build may use per axis.
pub const MAX_BINS: usize = 32;

/// Knobs of the SAH build.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildSettings {
    /// Bins per axis for the SAH sweep (clamped to `2..=32`).
    pub bins: u32,
    /// Largest leaf the build accepts when a split does not pay; bigger
    /// ranges are always split while a split exists.
    pub max_leaf: u32,
    /// Cost of visiting one node (box test for the packet), relative to
    /// `intersection_cost`.
    pub traversal_cost: f32,
    /// Cost of one primitive test.
    pub intersection_cost: f32,
    /// Largest distance from the world origin at which rays start (for
    /// example the camera's eye); widens the box padding when rays start far
    /// outside the scene. 0 means "within the scene".
    pub reach: f32,
    /// Deepest leaf (root = 0); clamped to [`MAX_DEPTH`], which bounds the
    /// traversal stack. A range at this depth becomes a leaf whatever its size.
    pub max_depth: u32,
}

impl Default for BuildSettings {
    fn default() -> Self {
        BuildSettings {
            bins: 16,
            max_leaf: 4,
            traversal_cost: 1.0,
            intersection_cost: 1.0,
            reach: 0.0,
            max_depth: MAX_DEPTH as u32,
        }
    }
}

/// An `f32` box `[min, max]` per axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Aabb {
    pub min: [f32; 3],
    pub max: [f32; 3],
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb { min: [f32::INFINITY; 3], max: [f32::NEG_INFINITY; 3] };

    fn grow(&mut self, o: &Aabb) {
        for a in 0..3 {
            if o.min[a] < self.min[a] {
                self.min[a] = o.min[a];
            }
            if o.max[a] > self.max[a] {
                self.max[a] = o.max[a];
            }
        }
    }
    fn grow_point(&mut self, p: [f32; 3]) {
        self.grow(&Aabb { min: p, max: p });
    }
    /// Half the surface area (the SAH only compares ratios), in this order.
    fn half_area(&self) -> f32 {
        let dx = self.max[0] - self.min[0];
        let dy = self.max[1] - self.min[1];
        let dz = self.max[2] - self.min[2];
        if !(dx >= 0.0 && dy >= 0.0 && dz >= 0.0) {
            return 0.0;
        }
        dx * dy + dy * dz + dz * dx
    }
    fn centroid(&self) -> [f32; 3] {
        [(self.min[0] + self.max[0]) * 0.5, (self.min[1] + self.max[1]) * 0.5, (self.min[2] + self.max[2]) * 0.5]
    }
}

/// The unpadded `f32` bounds of primitive `id`, or `None` when it is
/// unbounded (or its bounds are not finite numbers).
fn raw_bounds<S: Scalar>(scene: &SceneView<'_, S>, id: u32) -> Option<Aabb> {
    let p = scene.primitives().get(id as usize)?;
    let (lo, hi) = p.shape.bounds(scene.vertices())?;
    let b = Aabb { min: lo.to_f32(), max: hi.to_f32() };
    let finite = b.min.iter().chain(b.max.iter()).all(|v| v.is_finite());
    if finite && b.min[0] <= b.max[0] && b.min[1] <= b.max[1] && b.min[2] <= b.max[2] {
        Some(b)
    } else {
        None
    }
}

/// The padded box of a bounded primitive (see the module documentation).
fn padded_bounds<S: Scalar>(scene: &SceneView<'_, S>, id: u32, pad: f32) -> Aabb {
    match raw_bounds(scene, id) {
        Some(b) => Aabb {
            min: [b.min[0] - pad, b.min[1] - pad, b.min[2] - pad],
            max: [b.max[0] + pad, b.max[1] + pad, b.max[2] + pad],
        },
        // Not reached for entries of the bounded part of `order`.
        None => Aabb { min: [f32::MIN; 3], max: [f32::MAX; 3] },
    }
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: u32,
}

/// A range of `order` waiting to become the node at flat index `node`.
#[derive(Clone, Copy, Default)]
struct Task {
    node: u32,
    begin: u32,
    end: u32,
    depth: u32,
}

/// The bin of centroid coordinate `c`: `floor((c − lo)·k)`, clamped.
#[inline]
fn bin_of(c: f32, lo: f32, k: f32, bins: usize) -> usize {
    let x = (c - lo) * k;
    // `as` floors non-negative values and saturates (NaN → 0).
    let i = if x > 0.0 { x as usize } else { 0 };
    if i >= bins {
        bins - 1
    } else {
        i
    }
}

fn box_to_node<S: Scalar>(b: &Aabb) -> (Vec3<S>, Vec3<S>) {
    (Vec3::from_f32(b.min[0], b.min[1], b.min[2]), Vec3::from_f32(b.max[0], b.max[1], b.max[2]))
}

/// The bounded primitives first in `order` (index order), then the
/// unbounded ones; returns the number of bounded primitives and the box
/// padding: 2⁻¹⁶ of the scene's scale `s` (its largest bounded coordinate,
/// or `reach` if larger), never zero, plus `8·√(ρ·(1 + s))` for a scalar of
/// resolution `ρ` (the smallest power of two it holds). That second term is
/// the screen culling's for fixed point's absolute rounding of squared
/// distances (`query::cull`): a sphere's discriminant `r² − |perp|²` is
/// rounded to `ρ`, so a ray passing within about `√ρ` of a sphere can
/// report it, which at small scales is far more than 2⁻¹⁶ of the scene
/// (Q8.24 at a scene size of 0.1: `√ρ = 2⁻¹²` against `1.5·10⁻⁶`). In
/// `f32` (`ρ = 2⁻¹⁴⁹`) it is far below a rounding of the first term.
fn order_bounded_first<S: Scalar>(scene: &SceneView<'_, S>, reach: f32, order: &mut [u32]) -> (usize, f32) {
    let n = order.len();
    let mut scale = if reach.is_finite() { reach.abs() } else { 0.0 };
    let mut bounded = 0usize;
    for id in 0..n as u32 {
        if let Some(b) = raw_bounds(scene, id) {
            for v in b.min.iter().chain(b.max.iter()) {
                if v.abs() > scale {
                    scale = v.abs();
                }
            }
            // (`get_mut`: `bounded` ≤ `id` < n, but a bounds check, a panic
            // path, would stay in the code.)
            if let Some(o) = order.get_mut(bounded) {
                *o = id;
            }
            bounded += 1;
        }
    }
    let mut next = bounded;
    for id in 0..n as u32 {
        if raw_bounds(scene, id).is_none() {
            if let Some(o) = order.get_mut(next) {
                *o = id;
            }
            next += 1;
        }
    }
    let fixed = 8.0 * libm::sqrtf(resolution::<S>() * (1.0 + scale));
    (bounded, (scale * (1.0 / 65536.0) + fixed).max(f32::MIN_POSITIVE))
}

/// The costs and bins of a build, from its settings.
#[derive(Clone, Copy)]
struct Sah {
    bins: usize,
    c_trav: f32,
    c_isect: f32,
}

/// The cheapest binned split of the primitives `ids` (centroid box
/// `cent_box`, node box area `parent_area`) over all axes: `(cost, axis,
/// last bin on the left)`, or `None` if no axis can be split. Ties go to
/// the lower axis, then the lower bin.
fn best_split<S: Scalar>(
    scene: &SceneView<'_, S>,
    ids: &[u32],
    pad: f32,
    cent_box: &Aabb,
    parent_area: f32,
    sah: Sah,
) -> Option<(f32, usize, usize)> {
    let Sah { bins, c_trav, c_isect } = sah;
    // (Already so; said again so that no bin index needs a bounds check.)
    let bins = bins.clamp(2, MAX_BINS);
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        let c_lo = cent_box.min[axis];
        let extent = cent_box.max[axis] - c_lo;
        if !(extent > 0.0) {
            continue;
        }
        let k = bins as f32 / extent;
        let mut bin = [Bin { bounds: Aabb::EMPTY, count: 0 }; MAX_BINS];
        for &id in ids {
            let b = padded_bounds(scene, id, pad);
            let i = bin_of(b.centroid()[axis], c_lo, k, bins);
            bin[i].bounds.grow(&b);
            bin[i].count += 1;
        }
        // Right-to-left sweep: area·count of bins i+1.. for each split i.
        let mut right_cost = [0.0f32; MAX_BINS];
        let mut acc = Aabb::EMPTY;
        let mut acc_n = 0u32;
        for i in (1..bins).rev() {
            acc.grow(&bin[i].bounds);
            acc_n += bin[i].count;
            right_cost[i - 1] = if acc_n > 0 { acc.half_area() * acc_n as f32 } else { -1.0 };
        }
        let mut acc = Aabb::EMPTY;
        let mut acc_n = 0u32;
        for i in 0..bins - 1 {
            acc.grow(&bin[i].bounds);
            acc_n += bin[i].count;
            if acc_n == 0 || right_cost[i] < 0.0 {
                continue;
            }
            let cost = c_trav + c_isect * ((acc.half_area() * acc_n as f32 + right_cost[i]) / parent_area);
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, i));
            }
        }
    }
    best
}

/// Splits `order[begin..end]` in place: the primitives whose centroid
/// falls in bins `0..=last` on `axis` to the left. Returns the first index
/// of the right part.
fn partition<S: Scalar>(
    scene: &SceneView<'_, S>,
    order: &mut [u32],
    (begin, end): (usize, usize),
    pad: f32,
    cent_box: &Aabb,
    (axis, last, bins): (usize, usize, usize),
) -> usize {
    let c_lo = cent_box.min[axis];
    let k = bins as f32 / (cent_box.max[axis] - c_lo);
    // (`end` ≤ `order.len()`; the `min` spares the bounds checks.)
    let (mut i, mut j) = (begin, end.min(order.len()));
    while i < j {
        let Some(&id) = order.get(i) else { break };
        let b = padded_bounds(scene, id, pad);
        if bin_of(b.centroid()[axis], c_lo, k, bins) <= last {
            i += 1;
        } else {
            j -= 1;
            // `order.swap(i, j)` (i < j), without its bounds check.
            if let Some([first, .., last]) = order.get_mut(i..=j) {
                core::mem::swap(first, last);
            }
        }
    }
    i
}

/// Sorts a leaf's primitives into index order (insertion sort: leaves are
/// small).
fn sort_leaf(leaf: &mut [u32]) {
    for i in 1..leaf.len() {
        let mut j = i;
        while j > 0 && leaf[j - 1] > leaf[j] {
            leaf.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// Builds the tree of `scene` into `nodes` (flat, pairs) and `order`
/// (exactly the scene's primitive count long). The caller checked capacity.
pub(super) fn build<S: Scalar>(
    scene: &SceneView<'_, S>,
    settings: &BuildSettings,
    nodes: &mut [BvhNode<S>],
    order: &mut [u32],
) -> BvhStats {
    let n = order.len();
    let bins = (settings.bins as usize).clamp(2, MAX_BINS);
    let max_leaf = settings.max_leaf.max(1);
    let max_depth = (settings.max_depth as usize).min(MAX_DEPTH);
    let c_trav = if settings.traversal_cost.is_finite() { settings.traversal_cost.max(0.0) } else { 1.0 };
    let c_isect = if settings.intersection_cost.is_finite() && settings.intersection_cost > 0.0 {
        settings.intersection_cost
    } else {
        1.0
    };
    let sah = Sah { bins, c_trav, c_isect };

    let (bounded, pad) = order_bounded_first(scene, settings.reach, order);
    let mut stats = BvhStats { primitives: n as u32, unbounded: (n - bounded) as u32, ..BvhStats::default() };
    if bounded == 0 {
        return stats;
    }

    // Depth-first over an explicit stack: each task pushes at most two, and
    // the stack holds at most one pending sibling per level.
    let mut tasks = [Task::default(); MAX_DEPTH + 2];
    tasks[0] = Task { node: 0, begin: 0, end: bounded as u32, depth: 0 };
    let mut sp = 1usize;
    let mut next_pair = 1usize;
    while sp > 0 {
        sp -= 1;
        // (`get`, and `get_mut` below: the indices are in range, by the
        // depth bound and the partition; a bounds check would be a panic
        // path.)
        let Some(&task) = tasks.get(sp) else { break };
        let (begin, end) = (task.begin as usize, task.end as usize);
        let count = end - begin;
        let Some(ids) = order.get_mut(begin..end) else { break };

        // Node bounds and centroid bounds.
        let mut node_box = Aabb::EMPTY;
        let mut cent_box = Aabb::EMPTY;
        for &id in ids.iter() {
            let b = padded_bounds(scene, id, pad);
            node_box.grow(&b);
            cent_box.grow_point(b.centroid());
        }
        let (lo, hi) = box_to_node::<S>(&node_box);
        stats.nodes += 1;

        // Best split over all axes: cost relative to the parent's area.
        let parent_area = node_box.half_area();
        let can_split = count > 1 && (task.depth as usize) < max_depth && parent_area > 0.0;
        let best = if can_split { best_split(scene, ids, pad, &cent_box, parent_area, sah) } else { None };
        let leaf_cost = c_isect * count as f32;
        let split = match best {
            Some((cost, axis, last)) if count as u32 > max_leaf || cost < leaf_cost => Some((axis, last)),
            _ => None,
        };

        let Some((axis, last)) = split else {
            // Leaf: its primitives in index order.
            sort_leaf(ids);
            if let Some(node) = nodes.get_mut(task.node as usize) {
                *node = BvhNode { min: lo, max: hi, link: begin as u32, meta: (count as u32) << 2 };
            }
            stats.leaves += 1;
            stats.depth = stats.depth.max(task.depth);
            stats.max_leaf = stats.max_leaf.max(count as u32);
            continue;
        };

        // Partition in place: bins 0..=last to the left.
        let mid = partition(scene, order, (begin, end), pad, &cent_box, (axis, last, bins));
        let child = 2 * next_pair;
        next_pair += 1;
        if let Some(node) = nodes.get_mut(task.node as usize) {
            *node = BvhNode { min: lo, max: hi, link: child as u32, meta: axis as u32 };
        }
        let depth = task.depth + 1;
        let Some([right, left]) = tasks.get_mut(sp..sp + 2) else { break };
        *right = Task { node: child as u32 + 1, begin: mid as u32, end: task.end, depth };
        *left = Task { node: child as u32, begin: task.begin, end: mid as u32, depth };
        sp += 2;
    }
    stats
}
