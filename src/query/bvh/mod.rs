//! A bounding volume hierarchy in fixed memory: binary, built in place with
//! binned SAH, traversed by whole packets. With `std`, [`HeapBvh`] holds the
//! same tree in `Vec`s sized for the scene.
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
//! return the same bits as [`BruteForce`](super::BruteForce)
//! (see `traverse.rs` for how ties and transmissive shadows are kept exact).
//! This needs boxes that never cull a primitive that the primitive's own
//! kernel would report as hit, so every primitive box is padded by
//! `scale · 2⁻¹⁶`, `scale` being the largest absolute coordinate of the
//! scene's bounded primitives or [`BuildSettings::reach`] if larger. The
//! kernels' own rounding is a few ulps of `|origin| + t`, far below that pad
//! for rays that start within a few hundred scene sizes of the origin. Fixed
//! point rounds absolutely, not relatively: the pad also holds
//! `8·√(ρ·(1 + scale))` for a scalar of resolution `ρ` (a ray passing within
//! about `√ρ` of a sphere can report it), which is what screen culling
//! allows for too (`query::cull`); in `f32` that term is nothing.
//!
//! # Determinism
//! The build works in `f32` (whatever `S` is) with a fixed operation order and
//! breaks every tie (equal SAH cost) towards the lower axis and lower bin, so
//! the same scene gives the same tree on every target.

mod build;
#[cfg(feature = "std")]
mod heap;
mod node;
mod traverse;

#[cfg(test)]
mod tests;

use crate::num::scalar::Scalar;
use crate::query::camera_tiles::CameraTiles;
use crate::scene::SceneView;

pub use build::BuildSettings;
#[cfg(feature = "std")]
pub use heap::{HeapBvh, HeapBvhError};
pub use node::{BvhNode, BvhStats, MAX_DEPTH};

// The demo scene's capacity (16 primitives): 2·16 nodes of 32 bytes + 16
// indices + the stats, on 32- and 64-bit targets alike.
const _: () = assert!(core::mem::size_of::<Bvh<f32, 16>>() == 2 * 16 * 32 + 16 * 4 + 24);

/// The scene has more primitives than the BVH capacity `N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BvhError {
    /// The BVH capacity `N`.
    pub capacity: usize,
    /// The number of primitives that needed room.
    pub needed: usize,
}

impl core::fmt::Display for BvhError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "BVH primitive capacity {} exceeded (needs {})", self.capacity, self.needed)
    }
}

impl core::error::Error for BvhError {}

/// A fixed-capacity BVH for scenes of up to `N` primitives (see the module
/// documentation for the layout). Build it with [`Bvh::build`], then trace
/// through its [`Bvh::view`] (an [`Accelerator`](super::Accelerator)).
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
        Bvh {
            nodes: [[BvhNode::EMPTY; 2]; N],
            order: [0; N],
            stats: BvhStats { primitives: 0, unbounded: 0, nodes: 0, leaves: 0, depth: 0, max_leaf: 0 },
        }
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
            return Err(BvhError { capacity: N, needed: n });
        }
        self.stats = build::build(scene, settings, self.nodes.as_flattened_mut(), &mut self.order[..n]);
        Ok(self.stats)
    }

    /// Figures about the tree last built.
    pub fn stats(&self) -> BvhStats {
        self.stats
    }

    /// The tree as slices: the accelerator a tracer queries through.
    pub fn view(&self) -> BvhView<'_, S> {
        view_of(self.nodes.as_flattened(), &self.order, self.stats)
    }
}

/// The view of a tree built into `nodes` (flat) and `order` with figures
/// `stats`, whatever holds the arrays.
fn view_of<'a, S>(nodes: &'a [BvhNode<S>], order: &'a [u32], stats: BvhStats) -> BvhView<'a, S> {
    let used = stats.nodes as usize + usize::from(stats.nodes > 0); // + the empty slot 1
    BvhView {
        nodes: &nodes[..used.min(nodes.len())],
        // (`get`, not indexing: no bounds check, a panic path, in code that
        // must not have one.)
        order: order.get(..stats.primitives as usize).unwrap_or(&[]),
        bounded: stats.primitives - stats.unbounded,
        camera: None,
    }
}

/// A built tree as slices: an [`Accelerator`](super::Accelerator) for the
/// scene it was built for.
#[derive(Clone, Copy, Debug)]
pub struct BvhView<'a, S> {
    /// Nodes by flat index (the root is 0; slot 1 is unused).
    nodes: &'a [BvhNode<S>],
    /// Leaf ranges, then the unbounded primitives.
    order: &'a [u32],
    /// Length of the bounded part of `order`.
    bounded: u32,
    /// Lists for packets of camera rays, if given.
    camera: Option<&'a CameraTiles<'a, S>>,
}

impl<'a, S: Scalar> BvhView<'a, S> {
    /// The same tree, with `tiles` of the scene it was built for: a packet
    /// of camera rays inside one tile with a list tests that list instead
    /// of walking the tree (the same bits: see
    /// [`camera_tiles`](crate::query::camera_tiles)).
    pub fn with_camera_tiles(self, tiles: &'a CameraTiles<'a, S>) -> Self {
        BvhView { camera: Some(tiles), ..self }
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
