//! Rendering rectangles of the image into caller-provided buffers.
//!
//! [`Renderer::render_rect`] renders any rectangle (a tile, or a band of
//! rows) into a slice of RGB888 pixels, so callers never need a full
//! framebuffer: firmware renders a band of a few rows at a time, the CLI
//! renders tiles on several threads. Output is the same for any packet width
//! and any tiling.

use crate::camera::{packet_shape, Camera, Rect};
use crate::lanes::{Lanes, Mask};
use crate::query::{Accelerator, BruteForce};
use crate::scalar::Scalar;
use crate::trace::{RayStats, Tracer};

/// One 8-bit RGB pixel.
pub type Rgb8 = [u8; 3];

/// What a render writes per pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Aov {
    /// The traced colour: linear, clamped to `[0, 1]`, quantized as `round(v·255)`.
    #[default]
    Color,
    /// Distance `t` along the primary ray (the camera rays have unit
    /// direction, so `t` is the distance from the eye), as a 24-bit number
    /// `round(t·256)` (8 fractional bits; r = high byte, g = middle, b = low),
    /// saturating at `2²⁴ − 2`; background is `2²⁴ − 1` (white).
    Depth,
    /// Shading normal at the primary hit, turned towards the camera, as
    /// `0.5·n + 0.5` per channel; background 0.
    Normal,
    /// The 0-based index `k` of the primitive hit, written as the 24-bit
    /// number `k + 1` (r = high byte, g = middle, b = low); background 0.
    Id,
}

/// The output buffer is smaller than the rectangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BufferTooSmall {
    /// Pixels needed.
    pub needed: usize,
    /// Pixels provided.
    pub provided: usize,
}

impl core::fmt::Display for BufferTooSmall {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "buffer of {} pixels for a rectangle of {}", self.provided, self.needed)
    }
}

/// A tracer, a camera and an AOV: everything needed to render pixels.
#[derive(Clone, Copy, Debug)]
pub struct Renderer<'a, S, A = BruteForce, const D: usize = 8> {
    /// The tracer (scene, accelerator and settings).
    pub tracer: Tracer<'a, S, A, D>,
    /// The camera (and image size).
    pub camera: Camera<S>,
    /// What to write per pixel.
    pub aov: Aov,
}

fn u24(v: u32) -> Rgb8 {
    [(v >> 16) as u8, (v >> 8) as u8, v as u8]
}

impl core::error::Error for BufferTooSmall {}

impl<'a, S: Scalar, A: Accelerator<S>, const D: usize> Renderer<'a, S, A, D> {
    /// A renderer of the colour AOV.
    pub fn new(tracer: Tracer<'a, S, A, D>, camera: Camera<S>) -> Self {
        Renderer { tracer, camera, aov: Aov::Color }
    }

    /// The same renderer with its tracer's accelerator replaced by `f(accel)`
    /// (see [`Tracer::map_accelerator`]).
    pub fn map_accelerator<B: Accelerator<S>>(self, f: impl FnOnce(A) -> B) -> Renderer<'a, S, B, D> {
        Renderer { tracer: self.tracer.map_accelerator(f), camera: self.camera, aov: self.aov }
    }

    /// Renders the pixels of `rect` (clipped to the image) with packets of
    /// width `W` into `out`, row-major with row stride `rect.w`. Ray counts
    /// are added to `stats`.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn render_rect<const W: usize>(&self, rect: Rect, out: &mut [Rgb8], stats: &mut RayStats) -> Result<(), BufferTooSmall> {
        // Saturating (a 32-bit usize can overflow): an impossible size is
        // simply larger than any buffer.
        let needed = (rect.w as usize).saturating_mul(rect.h as usize);
        if out.len() < needed {
            return Err(BufferTooSmall { needed, provided: out.len() });
        }
        let (pw, ph) = packet_shape(W);
        let mut by = 0;
        while by < rect.h {
            let mut bx = 0;
            while bx < rect.w {
                let (ray, active) = self.camera.packet::<W>(rect.x.saturating_add(bx), rect.y.saturating_add(by), rect);
                let px = self.shade_packet(&ray, active, stats);
                for (l, p) in px.iter().enumerate() {
                    if !active.get(l) {
                        continue;
                    }
                    // Active lanes lie inside `rect`, so `y·w + x < w·h <= out.len()`;
                    // the checked arithmetic only keeps panics out of the code.
                    let x = bx.saturating_add(l as u32 % pw);
                    let y = by.saturating_add(l as u32 / pw);
                    let index = (y as usize).checked_mul(rect.w as usize).and_then(|i| i.checked_add(x as usize));
                    if let Some(slot) = index.and_then(|i| out.get_mut(i)) {
                        *slot = *p;
                    }
                }
                bx = bx.saturating_add(pw);
            }
            by = by.saturating_add(ph);
        }
        Ok(())
    }

    /// The pixels of one packet of primary rays.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn shade_packet<const W: usize>(&self, ray: &crate::ray::RayPacket<S, W>, active: Mask<W>, stats: &mut RayStats) -> [Rgb8; W] {
        let mut px = [[0u8; 3]; W];
        match self.aov {
            Aov::Color => {
                let c = self.tracer.trace(ray, active, stats);
                // Quantization as lane code, one channel at a time.
                let (r, g, b) = (c.x.to_unorm8(), c.y.to_unorm8(), c.z.to_unorm8());
                for (l, p) in px.iter_mut().enumerate() {
                    *p = [r[l], g[l], b[l]];
                }
            }
            aov => {
                stats.add_primary(active.count() as u64);
                let hit = self.tracer.closest_hit(ray, Lanes::zero(), Lanes::splat(S::MAX), active);
                // Each encoding as lane code over the whole packet; lanes
                // outside `active` are not written out by the caller.
                let mut code = [0u32; W];
                match aov {
                    Aov::Depth => {
                        for l in 0..W {
                            // In f32 for every scalar (fixed point's range would
                            // overflow t·256), in the description's units.
                            let v = hit.t.0[l].to_f32() * self.camera.units() * 256.0 + 0.5;
                            let v = if v >= 16_777_214.0 { 16_777_214 } else { v as u32 };
                            code[l] = if hit.mask.get(l) { v } else { 0xFF_FFFF };
                        }
                    }
                    Aov::Id => {
                        for l in 0..W {
                            code[l] = if hit.mask.get(l) { hit.prim[l].saturating_add(1).min(0xFF_FFFF) } else { 0 };
                        }
                    }
                    _ => {
                        let n = self.tracer.surface(ray, &hit).shading;
                        let half = Lanes::splat(S::HALF);
                        let (x, y, z) = ((n.x * half + half).to_unorm8(), (n.y * half + half).to_unorm8(), (n.z * half + half).to_unorm8());
                        for (l, p) in px.iter_mut().enumerate() {
                            *p = if hit.mask.get(l) { [x[l], y[l], z[l]] } else { [0, 0, 0] };
                        }
                        return px;
                    }
                }
                for (p, c) in px.iter_mut().zip(code) {
                    *p = u24(c);
                }
            }
        }
        px
    }
}
