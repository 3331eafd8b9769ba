//! Rendering: rectangles of the image into caller-provided buffers
//! ([`Renderer`]), band by band into sinks with pixel formats and checksums
//! ([`bands`]), and straight into embedded-graphics displays
//! (`draw_target`, with the feature `embedded-graphics`). Built on [`crate::trace`].
//!
//! `impl Renderer` is split by output, one block per file: `renderer`
//! (the type, and any rectangle of the image into a caller's buffer,
//! `render_rect`), [`bands`] (the whole image band by band into a sink, and
//! its checksums) and `draw_target` (onto an embedded-graphics display).
//! Rectangle arithmetic itself is [`crate::geom::rect`]'s.

pub mod bands;
// Drawing into embedded-graphics displays, band by band (feature `embedded-graphics`).
#[cfg(feature = "embedded-graphics")]
pub mod draw_target;
mod renderer;

pub use renderer::{Aov, BufferTooSmall, Renderer, Rgb8, Sampling, ADAPTIVE_BLOCK, MAX_SAMPLES};
