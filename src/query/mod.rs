//! Queries against a scene: the closest hit of each ray of a packet, and the
//! light a shadow ray lets through. This module is the one place that knows
//! how a scene is searched.
//!
//! The scene itself ([`crate::scene::SceneView`]) is plain data: primitives,
//! the vertex pool, materials and lights. An [`Accelerator`] answers queries
//! over that data:
//! - [`BruteForce`] tests every primitive in index order; it needs no memory
//!   and is what firmware without a tree links (nothing else);
//! - [`BvhView`], a view of a fixed-memory [`Bvh`], visits only the
//!   primitives whose boxes a ray reaches, with the same bits as brute force;
//! - [`ScreenCull`] (module [`cull`]) narrows the camera rays of a packet
//!   to the primitives whose screen rectangle it overlaps; brute force
//!   takes the narrowed set ([`Accelerator::closest_hit_among`]), the tree
//!   has no use for it;
//! - [`CameraTiles`] (module [`camera_tiles`]) gives the tree, per tile of
//!   the image, the short list of primitives its camera rays can hit, which
//!   a packet of camera rays inside the tile tests instead of walking;
//! - [`AccelChoice`] is either of the two, chosen at run time (the CLI's
//!   `--accel`), for programs that want both without two compiled copies of
//!   the renderer.
//!
//! The accelerator is a type parameter of the tracer, so the choice costs
//! nothing at run time and code that is never chosen is never compiled. The
//! instruction-set dispatcher (`crate::host::dispatch`, std only) compiles queries
//! for AVX2 and AVX-512 by wrapping an accelerator in a type of its own.
//!
//! Every accelerator gives the same answer, bit for bit: ties between
//! primitives at the same distance go to the lower index, and transmissive
//! occluders multiply the light in primitive order.

mod accel_choice;
mod accelerator;
mod brute;
pub mod bvh;
pub mod camera_tiles;
pub mod cull;

pub use accel_choice::AccelChoice;
pub use accelerator::{Accelerator, Hit, PacketJob, SceneMismatch};
pub use brute::BruteForce;
pub use bvh::{BuildSettings, Bvh, BvhError, BvhStats, BvhView};
#[cfg(feature = "std")]
pub use bvh::{HeapBvh, HeapBvhError};
pub use camera_tiles::CameraTiles;
#[cfg(feature = "std")]
pub use camera_tiles::{HeapCameraTiles, TileSettings};
pub use cull::{Candidates, CullError, ScreenCull, ShadowCull};
