//! Scene data: the store (fixed capacities, or the heap with `std`) and its
//! [`SceneView`] of slices, the
//! NFF reader that fills it, and the built-in demo scene. Built on
//! [`crate::geom`]; how a scene is searched is [`crate::query`]'s business.

pub mod bake;
pub mod demo;
pub mod nff;
mod store;

pub use store::{
    CapacityError, CapacityKind, Fixed, Light, Material, MemoryError, Pool, PoolFull, Primitive, Scene, SceneError,
    SceneStore, SceneView, Storage,
};
#[cfg(feature = "std")]
pub use store::{Heap, HeapScene};
