//! Rendering: rectangles of the image into caller-provided buffers
//! ([`Renderer`]), band by band into sinks with pixel formats and checksums
//! ([`bands`]), and straight into embedded-graphics displays
//! ([`draw_target`], feature `embedded-graphics`). Built on [`crate::trace`].

pub mod bands;
// Drawing into embedded-graphics displays, band by band (feature `embedded-graphics`).
#[cfg(feature = "embedded-graphics")]
pub mod draw_target;
mod rect;

pub use rect::{Aov, BufferTooSmall, Renderer, Rgb8, Sampling, ADAPTIVE_BLOCK, MAX_SAMPLES};
