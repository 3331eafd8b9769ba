//! A tree node, the depth bound, and the figures of a built tree.

use crate::geom::vec3::Vec3;
use crate::num::scalar::Scalar;

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

/// One node: its box and a link.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhNode<S> {
    /// Lower corner of the (padded) box.
    pub min: Vec3<S>,
    /// Upper corner of the (padded) box.
    pub max: Vec3<S>,
    /// Leaf: first entry in the order array. Interior: flat index of the
    /// first child (the second is `link + 1`).
    pub(super) link: u32,
    /// Leaf: `count << 2` (count ≥ 1). Interior: the split axis (0..=2).
    pub(super) meta: u32,
}

impl<S: Scalar> BvhNode<S> {
    pub(super) const EMPTY: Self = BvhNode { min: Vec3::ZERO, max: Vec3::ZERO, link: 0, meta: 0 };

    /// Number of primitives of a leaf; 0 for an interior node.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn leaf_count(&self) -> u32 {
        self.meta >> 2
    }
    /// Whether the node is a leaf.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn is_leaf(&self) -> bool {
        self.leaf_count() != 0
    }
    /// Leaf: index of its first entry in the order array; interior: flat
    /// index of its first child.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn link(&self) -> u32 {
        self.link
    }
    /// Split axis of an interior node (0 = x, 1 = y, 2 = z).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn axis(&self) -> usize {
        (self.meta & AXIS_MASK) as usize
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
