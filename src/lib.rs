//! # raypack
//!
//! A `no_std`, allocation-free, bit-for-bit deterministic Whitted ray tracer
//! that traces ray packets of any width (1, 4, 8 and 16 are the usual ones).
//!
//! Everything on the rendering path is generic over the scalar `S`
//! ([`Scalar`]: `f32`, the Q8.24 fixed point [`Fixed32`] for processors
//! without an FPU, or the 32.32 [`Fixed`]) and the packet width `W`; width 1
//! is the scalar tracer, so there is no second copy of any algorithm.
//!
//! ## With `std`: one call
//! [`Image::render`] reads an NFF scene, builds a BVH, picks the instruction
//! set and renders on every core (see [`image`]):
//!
//! ```
//! let scene = std::fs::read_to_string("tests/scenes/balls-1.nff")?;
//! let options = raypack::Options { width: Some(64), height: Some(64), ..Default::default() };
//! let image = raypack::Image::render(&scene, &options)?;
//! assert_eq!(image.pixels.len(), 64 * 64);           // row-major RGB8
//! println!("{} rays, instruction set {}", image.stats.total(), image.isa.name());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Without `std`: band by band
//! Firmware builds a scene in fixed memory and renders it a band of rows at
//! a time into one small buffer, handing each band to a sink (a display
//! driver, a checksum); nothing allocates:
//!
//! ```
//! use raypack::prelude::*;
//!
//! let mut scene: Scene<f32, 16, 64> = Scene::new();
//! let red = scene.add_material(Material::diffuse(Vec3::new(1.0, 0.2, 0.2)))?;
//! scene.add_sphere(Vec3::new(0.0, 0.0, 0.0), 1.0, red)?;
//! scene.add_light(Vec3::new(5.0, 5.0, 5.0), Vec3::new(1.0, 1.0, 1.0))?;
//! let camera = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 32, 32)?;
//! let renderer = Renderer::new(Tracer::<f32>::new(scene.view(), TraceSettings::default())?, camera);
//! let mut band = [[0u8; 3]; 32 * 2];               // two rows
//! let mut stats = RayStats::default();
//! let mut lit = 0;
//! renderer.render_bands::<8, core::convert::Infallible>(&mut band, &mut stats, |_rect, pixels| {
//!     lit += pixels.iter().filter(|p| p[0] > 0).count(); // a display would draw `rect`
//!     Ok(())
//! })?;
//! assert!(lit > 0 && stats.primary == 32 * 32);
//! # Ok::<(), Box<dyn core::error::Error>>(())
//! ```
#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]
#![deny(unsafe_code)]

// The layers, bottom to top: num, geom, scene, query, trace, render, host. A
// module uses only its own layer and those below (scripts/module-graph.py).
pub mod geom;
#[cfg(feature = "std")]
pub mod host;
pub mod num;
pub mod query;
pub mod render;
pub mod scene;
pub mod trace;

// The paths of the flat layout, kept working for users.
#[doc(hidden)]
pub use geom::{camera, fixed_range as range, primitives, ray, uniform_scale as similarity, vec3};
#[cfg(feature = "std")]
#[doc(hidden)]
pub use host::{dispatch, image};
#[doc(hidden)]
pub use num::{fixed32, fixed64 as fixed, lanes, scalar, unit_pow as pow};
#[doc(hidden)]
pub use render::bands as output;
#[cfg(feature = "embedded-graphics")]
#[doc(hidden)]
pub use render::draw_target;
#[doc(hidden)]
pub use scene::{demo, nff};

#[cfg(feature = "std")]
pub use host::image::{Image, Options};
pub use num::fixed32::Fixed32;
pub use num::fixed64::Fixed;
pub use num::scalar::Scalar;

/// The types most programs need.
pub mod prelude {
    pub use crate::geom::camera::{Camera, CameraError, Rect};
    pub use crate::geom::primitives::Quadric;
    pub use crate::geom::vec3::Vec3;
    pub use crate::num::fixed64::Fixed;
    pub use crate::num::scalar::Scalar;
    pub use crate::query::{AccelChoice, Accelerator, BruteForce, BuildSettings, Bvh, BvhError, BvhView};
    pub use crate::render::{Aov, Renderer, Rgb8, Sampling};
    pub use crate::scene::{Material, Scene, SceneError, SceneView};
    pub use crate::trace::{Mode, RayStats, TraceError, TraceSettings, Tracer};
}
