//! # raypack
//!
//! A `no_std`, allocation-free, bit-for-bit deterministic Whitted ray tracer
//! that traces ray packets of any width (1, 4, 8 and 16 are the usual ones).
//!
//! Everything on the rendering path is generic over the scalar `S`
//! ([`Scalar`]: `f32`, or fixed point) and the packet width `W`; width 1 is
//! the scalar tracer, so there is no second copy of any algorithm.
//!
//! ```
//! use raypack::prelude::*;
//!
//! let mut scene: Scene<f32, 16, 64> = Scene::new();
//! let red = scene.add_material(Material::diffuse(Vec3::new(1.0, 0.2, 0.2))).unwrap();
//! scene.add_sphere(Vec3::new(0.0, 0.0, 0.0), 1.0, red).unwrap();
//! scene.add_light(Vec3::new(5.0, 5.0, 5.0), Vec3::new(1.0, 1.0, 1.0)).unwrap();
//! let camera = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, 0.0),
//!                          Vec3::new(0.0, 1.0, 0.0), 45.0, 32, 32).unwrap();
//! let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
//! let renderer = Renderer::new(tracer, camera);
//! let mut row = [[0u8; 3]; 32 * 2];               // a band of two rows
//! let mut stats = RayStats::default();
//! renderer.render_rect::<8>(Rect { x: 0, y: 15, w: 32, h: 2 }, &mut row, &mut stats).unwrap();
//! assert!(row[16][0] > 0);                         // the sphere, lit
//! ```
#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]
#![deny(unsafe_code)]

pub mod camera;
pub mod demo;
// Drawing into embedded-graphics displays, band by band (feature `embedded-graphics`).
#[cfg(feature = "embedded-graphics")]
pub mod draw_target;
pub mod fixed;
pub mod lanes;
pub mod nff;
pub mod output;
pub mod primitives;
pub mod query;
pub mod range;
pub mod ray;
pub mod render;
pub mod scalar;
pub mod scene;
pub mod similarity;
pub mod trace;
pub mod vec3;

// Run-time instruction-set dispatch (std only; the one module allowed `unsafe`).
#[cfg(feature = "std")]
pub mod dispatch;
// From NFF text to pixels in one call, on threads (std only).
#[cfg(feature = "std")]
pub mod image;

#[cfg(feature = "std")]
pub use image::{Image, Options};
pub use fixed::Fixed;
pub use scalar::Scalar;

/// The types most programs need.
pub mod prelude {
    pub use crate::camera::{Camera, CameraError, Rect};
    pub use crate::fixed::Fixed;
    pub use crate::primitives::Quadric;
    pub use crate::query::{AccelChoice, Accelerator, BruteForce, BuildSettings, Bvh, BvhError, BvhView};
    pub use crate::render::{Aov, Renderer, Rgb8, Sampling};
    pub use crate::scalar::Scalar;
    pub use crate::scene::{Material, Scene, SceneError, SceneView};
    pub use crate::trace::{Mode, RayStats, TraceError, TraceSettings, Tracer};
    pub use crate::vec3::Vec3;
}
