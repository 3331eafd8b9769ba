//! Geometry: vectors, rays and ray packets, pixel rectangles, the camera, the primitives with
//! their packet kernels, and what fixed point needs of geometry (range checks
//! and the uniform scale that brings a scene into its range). Built on
//! [`crate::num`].

pub mod camera;
pub mod fixed_range;
pub mod primitives;
pub mod ray;
pub mod rect;
pub mod uniform_scale;
pub mod vec3;
