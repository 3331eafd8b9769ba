//! The same tree in `Vec`s (`std`): sized for the scene it is built for, so
//! a host scene is as large as memory. The build and every query are those
//! of the fixed-capacity [`Bvh`](super::Bvh); only the storage differs.

use super::build::{self, BuildSettings};
use super::node::{BvhNode, BvhStats};
use super::{view_of, BvhError, BvhView};
use crate::num::scalar::Scalar;
use crate::scene::SceneView;
use std::vec::Vec;

/// Why a [`HeapBvh`] could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HeapBvhError {
    /// More primitives than a tree indexes (`u32::MAX / 4`).
    TooLarge(BvhError),
    /// The allocator could not provide the tree's arrays.
    OutOfMemory {
        /// The bytes asked for.
        bytes: usize,
    },
}

impl core::fmt::Display for HeapBvhError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            HeapBvhError::TooLarge(e) => e.fmt(f),
            HeapBvhError::OutOfMemory { bytes } => write!(f, "out of memory for the BVH ({bytes} bytes)"),
        }
    }
}

impl core::error::Error for HeapBvhError {}

/// A BVH on the heap: `2n` nodes and `n` indices for a scene of `n`
/// primitives (32 + 32 + 4 = 68 bytes per primitive for `f32`), allocated
/// with `try_reserve_exact`, so running out of memory is an error.
#[derive(Clone, Debug)]
pub struct HeapBvh<S> {
    nodes: Vec<BvhNode<S>>,
    order: Vec<u32>,
    stats: BvhStats,
}

impl<S: Scalar> HeapBvh<S> {
    /// Builds the tree for `scene` with `settings`.
    pub fn build_with(scene: &SceneView<'_, S>, settings: &BuildSettings) -> Result<Self, HeapBvhError> {
        let n = scene.primitives().len();
        if n > u32::MAX as usize / 4 {
            return Err(HeapBvhError::TooLarge(BvhError { capacity: u32::MAX as usize / 4, needed: n }));
        }
        let bytes = 2 * n * core::mem::size_of::<BvhNode<S>>() + n * core::mem::size_of::<u32>();
        let mut nodes = Vec::new();
        let mut order = Vec::new();
        nodes.try_reserve_exact(2 * n).map_err(|_| HeapBvhError::OutOfMemory { bytes })?;
        order.try_reserve_exact(n).map_err(|_| HeapBvhError::OutOfMemory { bytes })?;
        // Node pairs: at most `n` are used (see the module documentation).
        nodes.resize(2 * n, BvhNode::EMPTY);
        order.resize(n, 0);
        let stats = build::build(scene, settings, &mut nodes, &mut order);
        Ok(HeapBvh { nodes, order, stats })
    }

    /// Figures about the tree.
    pub fn stats(&self) -> BvhStats {
        self.stats
    }

    /// Bytes of heap the tree holds.
    pub fn heap_bytes(&self) -> usize {
        self.nodes.capacity() * core::mem::size_of::<BvhNode<S>>() + self.order.capacity() * core::mem::size_of::<u32>()
    }

    /// The tree as slices: the accelerator a tracer queries through.
    pub fn view(&self) -> BvhView<'_, S> {
        view_of(&self.nodes, &self.order, self.stats)
    }
}
