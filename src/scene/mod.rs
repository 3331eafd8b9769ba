//! Scene data: the fixed-capacity store and its [`SceneView`] of slices, the
//! NFF reader that fills it, and the built-in demo scene. Built on
//! [`crate::geom`]; how a scene is searched is [`crate::query`]'s business.

pub mod demo;
pub mod nff;
mod store;

pub use store::{CapacityError, CapacityKind, Light, Material, Primitive, Scene, SceneError, SceneView};
