//! A bounding volume hierarchy in fixed memory: binary, built in place with
//! binned SAH, traversed by whole packets.
//!
//! # Layout
//! [`Bvh<S, N>`] holds room for a scene of up to `N` primitives:
//! - `nodes: [[BvhNode<S>; 2]; N]`: node pairs. The two children of an
//!   interior node are always stored side by side in one pair, and the root
//!   sits alone in pair 0. A binary tree over `n ≤ N` leaves has at most
//!   `n − 1` interior nodes, so at most `1 + (n − 1) = N` pairs are ever used:
//!   the `2N − 1` bound, expressed with the one const generic stable Rust
//!   allows (no `2 * N − 1` in types).
//! - `order: [u32; N]`: primitive indices. Leaves own contiguous ranges of
//!   `order[..bounded]` (sorted by primitive index inside each leaf); the
//!   unbounded primitives (planes, unclipped quadrics, anything whose bounds
//!   are not finite) follow in `order[bounded..count]`, in index order, and
//!   are tested by every query.
//!
//! A node is 32 bytes for `f32` on every target: the box (six scalars) and two
//! `u32`s (leaf: first entry in `order` and count; interior: index of its
//! child pair and split axis).
//!
//! # Exactness
//! The tree changes which primitives are tested, never the answer: queries
//! return the same bits as the brute-force loops of [`SceneView`]
//! (see `traverse.rs` for how ties and transmissive shadows are kept exact).
//! This needs boxes that never cull a primitive that the primitive's own
//! kernel would report as hit, so every primitive box is padded by
//! `scale · 2⁻¹⁶`, `scale` being the largest absolute coordinate of the
//! scene's bounded primitives or [`BuildSettings::reach`] if larger. The
//! kernels' own rounding is a few ulps of `|origin| + t`, far below that pad
//! for rays that start within a few hundred scene sizes of the origin.
//!
//! # Determinism
//! The build works in `f32` (whatever `S` is) with a fixed operation order and
//! breaks every tie (equal SAH cost) towards the lower axis and lower bin, so
//! the same scene gives the same tree on every target.

mod build;
pub mod isa;
mod traverse;

#[cfg(test)]
mod tests;

use crate::scalar::Scalar;
pub use isa::LeafIsa;
use crate::scene::SceneView;
use crate::vec3::Vec3;

pub use build::BuildSettings;

/// The deepest a tree can be (root at depth 0). The builder makes a leaf at
/// this depth whatever its size, so the traversal stack (`MAX_DEPTH + 1`
/// entries) can never overflow.
pub const MAX_DEPTH: usize = 48;

/// `meta` of an interior node: count 0 in the high bits, split axis in the
/// low two.
const AXIS_MASK: u32 = 3;

// The footprint on every target (all fields are 4-byte scalars or u32, so
// 32-bit targets have the same layout): 32-byte nodes, and for the demo
// scene's capacity (16 primitives) 2·16 nodes + 16 indices + the stats.
const _: () = assert!(core::mem::size_of::<BvhNode<f32>>() == 32);
const _: () = assert!(core::mem::size_of::<Bvh<f32, 16>>() == 2 * 16 * 32 + 16 * 4 + 24);

/// One node: its box and a link.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhNode<S> {
    /// Lower corner of the (padded) box.
    pub min: Vec3<S>,
    /// Upper corner of the (padded) box.
    pub max: Vec3<S>,
    /// Leaf: first entry in the order array. Interior: flat index of the
    /// first child (the second is `link + 1`).
    link: u32,
    /// Leaf: `count << 2` (count ≥ 1). Interior: the split axis (0..=2).
    meta: u32,
}

impl<S: Scalar> BvhNode<S> {
    const EMPTY: Self = BvhNode { min: Vec3::ZERO, max: Vec3::ZERO, link: 0, meta: 0 };

    /// Number of primitives of a leaf; 0 for an interior node.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn leaf_count(&self) -> u32 {
        self.meta >> 2
    }
    /// Whether the node is a leaf.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn is_leaf(&self) -> bool {
        self.leaf_count() != 0
    }
    /// Leaf: index of its first entry in the order array; interior: flat
    /// index of its first child.
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn link(&self) -> u32 {
        self.link
    }
    /// Split axis of an interior node (0 = x, 1 = y, 2 = z).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub fn axis(&self) -> usize {
        (self.meta & AXIS_MASK) as usize
    }
}

/// The BVH of a scene did not fit, or the tree belongs to another scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BvhError {
    /// The scene has more primitives than the BVH capacity `N`.
    Capacity {
        /// The BVH capacity `N`.
        capacity: usize,
        /// The number of primitives that needed room.
        needed: usize,
    },
    /// [`SceneView::with_bvh`] with a tree built for a scene with a different
    /// number of primitives.
    SceneMismatch {
        /// Primitives the tree was built for.
        built_for: usize,
        /// Primitives the view has.
        view_has: usize,
    },
}

impl core::fmt::Display for BvhError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            BvhError::Capacity { capacity, needed } => {
                write!(f, "BVH primitive capacity {capacity} exceeded (needs {needed})")
            }
            BvhError::SceneMismatch { built_for, view_has } => {
                write!(f, "BVH built for {built_for} primitives, scene has {view_has}")
            }
        }
    }
}

/// Figures about a built tree.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BvhStats {
    /// Primitives in the scene.
    pub primitives: u32,
    /// Primitives outside the tree (always tested).
    pub unbounded: u32,
    /// Nodes (interior and leaves).
    pub nodes: u32,
    /// Leaves.
    pub leaves: u32,
    /// Depth of the deepest leaf (root = 0).
    pub depth: u32,
    /// Most primitives in one leaf.
    pub max_leaf: u32,
}

/// A fixed-capacity BVH for scenes of up to `N` primitives (see the module
/// documentation for the layout). Build it with [`Bvh::build`], then trace
/// through `scene.view().with_bvh(&bvh)`.
#[derive(Clone)]
pub struct Bvh<S, const N: usize> {
    nodes: [[BvhNode<S>; 2]; N],
    order: [u32; N],
    stats: BvhStats,
}

impl<S: Scalar, const N: usize> Default for Bvh<S, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<S: Scalar, const N: usize> Bvh<S, N> {
    /// An empty tree (usable as a `static`).
    pub const fn new() -> Self {
        Bvh { nodes: [[BvhNode::EMPTY; 2]; N], order: [0; N], stats: BvhStats { primitives: 0, unbounded: 0, nodes: 0, leaves: 0, depth: 0, max_leaf: 0 } }
    }

    /// Builds the tree for `scene` with the default settings, in place (no
    /// allocation, nothing but this struct and a small fixed stack).
    pub fn build(&mut self, scene: &SceneView<'_, S>) -> Result<BvhStats, BvhError> {
        self.build_with(scene, &BuildSettings::default())
    }

    /// Builds the tree for `scene` with explicit settings.
    pub fn build_with(&mut self, scene: &SceneView<'_, S>, settings: &BuildSettings) -> Result<BvhStats, BvhError> {
        let n = scene.primitives().len();
        if n > N || n > u32::MAX as usize / 4 {
            // Leave an empty, consistent tree behind.
            self.stats = BvhStats::default();
            return Err(BvhError::Capacity { capacity: N, needed: n });
        }
        self.stats = build::build(scene, settings, self.nodes.as_flattened_mut(), &mut self.order[..n]);
        Ok(self.stats)
    }

    /// Figures about the tree last built.
    pub fn stats(&self) -> BvhStats {
        self.stats
    }

    /// The tree as slices, for [`SceneView::with_bvh`].
    pub fn view(&self) -> BvhView<'_, S> {
        let flat = self.nodes.as_flattened();
        let used = self.stats.nodes as usize + usize::from(self.stats.nodes > 0); // + the empty slot 1
        BvhView {
            nodes: &flat[..used.min(flat.len())],
            order: &self.order[..self.stats.primitives as usize],
            bounded: self.stats.primitives - self.stats.unbounded,
            leaf_isa: LeafIsa::default(),
        }
    }
}

/// A built tree as slices: what a [`SceneView`] carries.
#[derive(Clone, Copy, Debug)]
pub struct BvhView<'a, S> {
    /// Nodes by flat index (the root is 0; slot 1 is unused).
    nodes: &'a [BvhNode<S>],
    /// Leaf ranges, then the unbounded primitives.
    order: &'a [u32],
    /// Length of the bounded part of `order`.
    bounded: u32,
    /// Which compiled copy of the leaf tests the traversal calls.
    leaf_isa: LeafIsa,
}

impl<'a, S: Scalar> BvhView<'a, S> {
    /// The same view, its traversals calling the leaf tests of `isa`.
    // (Only the std dispatcher switches instruction sets.)
    #[cfg_attr(not(feature = "std"), allow(dead_code))]
    pub(crate) fn with_leaf_isa(self, leaf_isa: LeafIsa) -> Self {
        BvhView { leaf_isa, ..self }
    }
    /// The instruction set of the leaf tests its traversals call.
    pub fn leaf_isa(&self) -> LeafIsa {
        self.leaf_isa
    }
    /// Number of primitives the tree was built for.
    pub fn primitive_count(&self) -> usize {
        self.order.len()
    }
    /// The nodes by flat index: root 0, children of an interior node at
    /// `link` and `link + 1` (slot 1 is unused).
    pub fn nodes(&self) -> &'a [BvhNode<S>] {
        self.nodes
    }
    /// Primitive indices: the leaves' ranges, then the unbounded primitives.
    pub fn order(&self) -> &'a [u32] {
        self.order
    }
    /// The primitives outside the tree, in index order.
    pub fn unbounded(&self) -> &'a [u32] {
        self.order.get(self.bounded as usize..).unwrap_or(&[])
    }
    /// The primitives of a leaf (empty for an interior node or a bad range).
    pub fn leaf_primitives(&self, node: &BvhNode<S>) -> &'a [u32] {
        let first = node.link as usize;
        let end = first + node.leaf_count() as usize;
        if end > self.bounded as usize {
            return &[];
        }
        self.order.get(first..end).unwrap_or(&[])
    }
}
