//! Rendering rectangles of the image into caller-provided buffers.
//!
//! [`Renderer::render_rect`] renders any rectangle (a tile, or a band of
//! rows) into a slice of RGB888 pixels, so callers never need a full
//! framebuffer: firmware renders a band of a few rows at a time, the CLI
//! renders tiles on several threads. Output is the same for any packet width
//! and any tiling.
//!
//! # Anti-aliasing
//!
//! [`Renderer::sampling`] sets how many camera rays a pixel of the colour
//! AOV gets ([`Sampling`]): one through its centre (the default), a regular
//! `n × n` grid averaged with a box filter, or that grid only where the
//! centre colour differs from a neighbour's by more than a threshold
//! (adaptive, as POV-Ray's `+A`). Every choice keeps the guarantees above:
//! the subsamples of a packet are the same subpixel of adjacent pixels (so
//! the packet stays as coherent as a packet of centres), each lane is
//! summed in a fixed order, and the adaptive decision depends only on
//! centre colours of the pixel and its neighbours in the *image*, never on
//! the rectangle being rendered. Nothing is allocated: the adaptive
//! renderer works through blocks of [`ADAPTIVE_BLOCK`]² pixels with the
//! block's centre colours (and a one-pixel ring around it) in a small
//! array on the stack.

use crate::geom::camera::{packet_shape, Camera, Rect};
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;
use crate::query::cull::{Candidates, ALL};
use crate::query::{Accelerator, BruteForce, ScreenCull, ShadowCull};
use crate::trace::{Mode, RayStats, Tracer};

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

/// Side in pixels of the blocks an adaptive render works through: each
/// block traces the centre rays of itself and of a one-pixel ring around it
/// (clipped to the image) into a stack array of `(ADAPTIVE_BLOCK + 2)²`
/// pixels, then supersamples the pixels that need it. The ring's centre
/// rays are traced again by the neighbouring block: the cost of needing no
/// buffer from the caller (at most `4·(ADAPTIVE_BLOCK + 1)` extra centre
/// rays per block, about a quarter more centre rays).
pub const ADAPTIVE_BLOCK: u32 = 16;

/// The largest grid side [`Sampling`] uses (larger values are clamped).
pub const MAX_SAMPLES: u8 = 16;

/// Camera rays per pixel of the colour AOV (the other AOVs always use one
/// ray through the pixel centre).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Sampling {
    /// One ray through the pixel centre.
    #[default]
    Centre,
    /// An `n × n` regular grid of rays per pixel (subpixel centres at
    /// `((a + ½)/n, (b + ½)/n)`), averaged with a box filter: each
    /// subsample's linear colour times `1/n²`, summed row by row, then
    /// clamped and quantized like a single ray's. `n` is clamped to
    /// `1..=`[`MAX_SAMPLES`]; `Grid(1)` gives the same bytes as `Centre`.
    Grid(u8),
    /// Adaptive supersampling in POV-Ray's `+A` manner: one centre ray per
    /// pixel; a pixel whose 8-bit centre colour differs from that of one of
    /// its four neighbours (left, right, up, down; inside the image) by more
    /// than `threshold` is rendered as [`Sampling::Grid`]`(n)` instead. The
    /// difference is the sum of the absolute differences of the three 8-bit
    /// channels (0 to 765); POV-Ray's `+A0.3` is `threshold = 77`
    /// (`round(0.3·255)`; see [`Sampling::adaptive`]). Four neighbours
    /// rather than POV-Ray's two (left, above) make the decision symmetric
    /// and independent of the order pixels are rendered in.
    Adaptive {
        /// Grid side of a supersampled pixel (clamped as for `Grid`).
        n: u8,
        /// Largest difference that does not supersample, in 8-bit units
        /// summed over the three channels.
        threshold: u16,
    },
}

impl Sampling {
    /// Adaptive sampling with POV-Ray's threshold `t` (colour differences
    /// on `[0, 1]` channels, summed; 0 to 3): `round(t·255)` in 8-bit units,
    /// clamped to 0..=765 (NaN gives 0).
    pub fn adaptive(n: u8, t: f32) -> Sampling {
        let v = t * 255.0 + 0.5;
        let threshold = if v >= 765.0 {
            765
        } else if v >= 0.0 {
            v as u16
        } else {
            0
        };
        Sampling::Adaptive { n, threshold }
    }

    /// The grid side of a supersampled pixel (1 for `Centre`).
    pub fn grid(self) -> u32 {
        match self {
            Sampling::Centre => 1,
            Sampling::Grid(n) | Sampling::Adaptive { n, .. } => n.clamp(1, MAX_SAMPLES) as u32,
        }
    }
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
    /// Camera rays per pixel of the colour AOV (anti-aliasing).
    pub sampling: Sampling,
}

fn u24(v: u32) -> Rgb8 {
    [(v >> 16) as u8, (v >> 8) as u8, v as u8]
}

impl core::error::Error for BufferTooSmall {}

/// Packet columns of [`Renderer`]'s render loop, in pixels (a multiple of
/// every packet width): 32 on x86, where packets that follow each other
/// then meet the same nodes of the tree in cache; the whole width
/// elsewhere, for firmware, whose bands are narrow and whose cores have no
/// data cache (columns of 32 cost the Cortex-M0 0.7 % more instructions
/// per frame, `scripts/firmware.sh`).
#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
const BLOCK: u32 = 32;
#[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
const BLOCK: u32 = u32::MAX;

/// What a frame's rays can hit ([`Renderer::frame_cull`]), worked out once
/// per frame.
pub(crate) struct FrameCull<S> {
    screen: Option<ScreenCull>,
    shadow: ShadowCull<S>,
    /// Whether `shadow` was filled.
    shadowed: bool,
}

impl<S: Scalar> FrameCull<S> {
    /// Nothing culled.
    pub(crate) fn empty() -> Self {
        FrameCull { screen: None, shadow: ShadowCull::empty(), shadowed: false }
    }
}

/// A frame's culling and the primitives the rows being rendered can see.
struct Culling<'c, S> {
    cull: Option<&'c ScreenCull>,
    band: Candidates,
    shadow: Option<&'c ShadowCull<S>>,
}

impl<S> Culling<'_, S> {
    /// The candidates of the width-`W` packet whose top-left pixel is
    /// `(x, y)` (every primitive without culling).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn at<const W: usize>(&self, x: u32, y: u32) -> Candidates {
        let Some(c) = self.cull else { return ALL };
        let (pw, ph) = const { packet_shape(W) };
        c.candidates(self.band, x, x.saturating_add(pw - 1), y, y.saturating_add(ph - 1))
    }

    /// The candidates of the row of width-`W` packets whose top is `y`
    /// (their rows' primitives), for [`Culling::in_row`].
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    fn row<const W: usize>(&self, y: u32) -> Candidates {
        let Some(c) = self.cull else { return ALL };
        let (_, ph) = const { packet_shape(W) };
        c.candidates(self.band, 0, u32::MAX, y, y.saturating_add(ph - 1))
    }

    /// [`Culling::at`]`(x, y)` from `row`, the candidates of the packets'
    /// row ([`Culling::row`]`(y)`), testing only columns, and the last `x`
    /// up to which the row's packets keep them ([`ScreenCull::columns_from`]).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    fn in_row<const W: usize>(&self, row: Candidates, x: u32) -> (Candidates, u32) {
        let Some(c) = self.cull else { return (ALL, u32::MAX) };
        let (pw, _) = const { packet_shape(W) };
        c.columns_from(row, x, pw)
    }
}

/// Writes the pixels `px` of the lanes `active` of the packet at `(x0, y0)`
/// into `out`, row-major with the origin and stride of `frame`.
#[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
fn put<const W: usize>(x0: u32, y0: u32, frame: Rect, out: &mut [Rgb8], px: &[Rgb8; W], active: Mask<W>) {
    let (pw, ph) = const { packet_shape(W) };
    if active.all() {
        // The whole packet is inside the frame: its rows go out as slices
        // (the same bytes as lane by lane below). Element by element, not
        // `copy_from_slice`, whose length check is a panic path firmware
        // must not link.
        let (x, y) = (x0.wrapping_sub(frame.x) as usize, y0.wrapping_sub(frame.y) as usize);
        let pw = pw as usize;
        for r in 0..ph as usize {
            // (Rows of more than one pixel as ranges of exactly `pw`, so
            // that the copy below has a length known at compile time: a few
            // loads and stores, not a call to `memcpy`. Single pixels keep
            // the saturating end, with which x86 renders packets of 1 about
            // 3 % faster.)
            let at = (y + r).saturating_mul(frame.w as usize).saturating_add(x);
            let end = if pw == 1 {
                at.saturating_add(pw)
            } else {
                let Some(end) = at.checked_add(pw) else { continue };
                end
            };
            let (Some(d), Some(row)) = (out.get_mut(at..end), px.get(r * pw..(r + 1) * pw)) else {
                continue;
            };
            for (d, p) in d.iter_mut().zip(row) {
                *d = *p;
            }
        }
        return;
    }
    for (l, p) in px.iter().enumerate() {
        if !active.get(l) {
            continue;
        }
        // Active lanes lie inside the frame, so the index is below
        // `frame.w·frame.h <= out.len()`; the checked arithmetic only keeps
        // panics out of the code.
        let x = x0.saturating_add(l as u32 % pw).wrapping_sub(frame.x);
        let y = y0.saturating_add(l as u32 / pw).wrapping_sub(frame.y);
        let index = (y as usize).checked_mul(frame.w as usize).and_then(|i| i.checked_add(x as usize));
        if let Some(slot) = index.and_then(|i| out.get_mut(i)) {
            *slot = *p;
        }
    }
}

impl<'a, S: Scalar, A: Accelerator<S>, const D: usize> Renderer<'a, S, A, D> {
    /// A renderer of the colour AOV, one ray per pixel.
    pub fn new(tracer: Tracer<'a, S, A, D>, camera: Camera<S>) -> Self {
        Renderer { tracer, camera, aov: Aov::Color, sampling: Sampling::Centre }
    }

    /// The same renderer with its tracer's accelerator replaced by `f(accel)`
    /// (see [`Tracer::map_accelerator`]).
    pub fn map_accelerator<B: Accelerator<S>>(self, f: impl FnOnce(A) -> B) -> Renderer<'a, S, B, D> {
        Renderer { tracer: self.tracer.map_accelerator(f), camera: self.camera, aov: self.aov, sampling: self.sampling }
    }

    /// Renders the pixels of `rect` (clipped to the image) with packets of
    /// width `W` into `out`, row-major with row stride `rect.w`, with
    /// [`Renderer::sampling`]. Ray counts are added to `stats` (every camera
    /// ray, subsamples included, counts as primary).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn render_rect<const W: usize>(
        &self,
        rect: Rect,
        out: &mut [Rgb8],
        stats: &mut RayStats,
    ) -> Result<(), BufferTooSmall> {
        let mut cull = FrameCull::empty();
        self.frame_cull(&mut cull);
        self.render_rect_culled::<W>(rect, out, &cull, stats)
    }

    /// The frame's culling ([`crate::query::cull`]): of camera rays, and in
    /// Whitted mode of shadow rays, if the accelerator takes candidates and
    /// the scene fits the tables; `None` (every primitive tested)
    /// otherwise.
    pub(crate) fn frame_cull(&self, cull: &mut FrameCull<S>) {
        if !A::CULLS {
            return;
        }
        let scene = self.tracer.scene();
        cull.screen = ScreenCull::new(scene, &self.camera).ok();
        if self.tracer.settings().mode == Mode::Whitted && self.aov == Aov::Color {
            // Filled in place (see `ShadowCull::fill`).
            cull.shadowed = cull.shadow.fill(scene).is_ok();
        }
    }

    /// [`Renderer::render_rect`] with the frame's culling worked out
    /// ([`Renderer::screen_cull`]; the band loop works it out once per
    /// frame).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub(crate) fn render_rect_culled<const W: usize>(
        &self,
        rect: Rect,
        out: &mut [Rgb8],
        frame: &FrameCull<S>,
        stats: &mut RayStats,
    ) -> Result<(), BufferTooSmall> {
        // The primitives the rows of `rect` (and the ring of neighbours an
        // adaptive render traces around it) can see.
        let cull = frame.screen.as_ref();
        let band = cull.map_or(ALL, |c| c.rows(rect.y.saturating_sub(1), rect.y.saturating_add(rect.h)));
        let shadow = if frame.shadowed { Some(&frame.shadow) } else { None };
        let cull = Culling { cull, band, shadow };
        // Saturating (a 32-bit usize can overflow): an impossible size is
        // simply larger than any buffer.
        let needed = (rect.w as usize).saturating_mul(rect.h as usize);
        if out.len() < needed {
            return Err(BufferTooSmall { needed, provided: out.len() });
        }
        let sampling = if self.aov == Aov::Color { self.sampling } else { Sampling::Centre };
        match sampling {
            // The closures are inlined like the functions around them: under
            // a dispatched instruction set an out-of-line closure would be
            // compiled for the baseline only (scripts/check-asm.sh checks).
            Sampling::Centre => {
                // The terms of the packets' row, kept while the row lasts
                // (`packets` walks a block's rows, each from left to right).
                // Not on WebAssembly: the row code took the browser module
                // (web/) past its 200 KB budget, so it forms each packet
                // whole.
                #[cfg(not(target_arch = "wasm32"))]
                let mut row = self.camera.packet_row::<W>(rect.y, rect);
                // And the primitives the row's packets can see: those of the
                // packets from `from` to `until` (left to right) and of the row.
                #[cfg(not(target_arch = "wasm32"))]
                let mut row_candidates = cull.row::<W>(rect.y);
                #[cfg(not(target_arch = "wasm32"))]
                let (mut from, mut until, mut candidates) = (1, 0, ALL);
                self.packets::<W>(
                    rect,
                    rect,
                    out,
                    #[cfg_attr(
                        all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")),
                        inline(always)
                    )]
                    |x, y| {
                        #[cfg(not(target_arch = "wasm32"))]
                        let (ray, active, candidates) = {
                            if row.y() != y {
                                row = self.camera.packet_row::<W>(y, rect);
                                row_candidates = cull.row::<W>(y);
                                (from, until) = (1, 0);
                            }
                            if !(from <= x && x <= until) {
                                (candidates, until) = cull.in_row::<W>(row_candidates, x);
                                from = x;
                            }
                            let (ray, active) = self.camera.packet_in_row(&row, x);
                            (ray, active, candidates)
                        };
                        #[cfg(target_arch = "wasm32")]
                        let (ray, active, candidates) = {
                            let (ray, active) = self.camera.packet::<W>(x, y, rect);
                            (ray, active, cull.at::<W>(x, y))
                        };
                        (self.shade_packet(&ray, active, candidates, cull.shadow, stats), active)
                    },
                )
            }
            Sampling::Grid(_) => {
                let n = sampling.grid();
                self.packets::<W>(
                    rect,
                    rect,
                    out,
                    #[cfg_attr(
                        all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")),
                        inline(always)
                    )]
                    |x, y| {
                        let all = Mask::splat(true);
                        let (c, active) = self.supersample::<W>(x, y, rect, n, all, &cull, stats);
                        (c, active)
                    },
                )
            }
            Sampling::Adaptive { threshold, .. } => {
                self.adaptive_rect::<W>(rect, out, sampling.grid(), threshold, &cull, stats)
            }
        }
        Ok(())
    }

    /// Runs `shade(x, y)` for every packet position of `area` (packets of
    /// [`packet_shape`]`(W)` from its top-left corner) and writes the
    /// returned pixels of the returned lanes into `out`, row-major with
    /// the origin and stride of `frame` (which contains `area`).
    ///
    /// Packets are visited in columns of [`BLOCK`] pixels, each column top
    /// to bottom, so that neighbouring packets follow each other (they
    /// traverse the same part of the tree) even in a wide band; each
    /// packet is independent, so the order changes no byte.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn packets<const W: usize>(
        &self,
        area: Rect,
        frame: Rect,
        out: &mut [Rgb8],
        mut shade: impl FnMut(u32, u32) -> ([Rgb8; W], Mask<W>),
    ) {
        let (pw, ph) = packet_shape(W);
        let mut cx = 0;
        while cx < area.w {
            let column_end = cx.saturating_add(BLOCK).min(area.w);
            let mut by = 0;
            while by < area.h {
                let mut bx = cx;
                while bx < column_end {
                    let (x0, y0) = (area.x.saturating_add(bx), area.y.saturating_add(by));
                    let (px, active) = shade(x0, y0);
                    put(x0, y0, frame, out, &px, active);
                    bx = bx.saturating_add(pw);
                }
                by = by.saturating_add(ph);
            }
            cx = column_end;
        }
    }

    /// The colours of the packet at `(x, y)` (clipped to `clip`) as the
    /// box-filtered mean of an `n × n` grid of subsamples, tracing only the
    /// lanes in `want`; returns them and the lanes traced.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    // Private and inlined: a struct for the packet's position, rectangle and
    // lanes would only be unpacked again here.
    #[allow(clippy::too_many_arguments)]
    fn supersample<const W: usize>(
        &self,
        x: u32,
        y: u32,
        clip: Rect,
        n: u32,
        want: Mask<W>,
        cull: &Culling<'_, S>,
        stats: &mut RayStats,
    ) -> ([Rgb8; W], Mask<W>) {
        let candidates = cull.at::<W>(x, y);
        let weight = Lanes::splat(S::ONE / S::from_i32((n * n) as i32));
        let zero = Lanes::<S, W>::zero();
        let (mut r, mut g, mut b) = (zero, zero, zero);
        let mut traced = Mask::splat(false);
        // Row by row, the same order for every lane: the sum's bits do not
        // depend on the packet a pixel is in. Each term is weighted before
        // it is added, so the sum never exceeds the largest colour (no
        // overflow for limited-range scalars).
        for sb in 0..n {
            for sa in 0..n {
                let (ray, active) = self.camera.subpixel_packet::<W>(x, y, clip, n, sa, sb);
                let active = active & want;
                if active.none() {
                    continue;
                }
                let c = self.tracer.trace_among(&ray, active, candidates, cull.shadow, stats);
                r = r + Lanes::select(active, c.x * weight, zero);
                g = g + Lanes::select(active, c.y * weight, zero);
                b = b + Lanes::select(active, c.z * weight, zero);
                traced |= active;
            }
        }
        let (r, g, b) = (r.to_unorm8(), g.to_unorm8(), b.to_unorm8());
        let mut px = [[0u8; 3]; W];
        for (l, p) in px.iter_mut().enumerate() {
            *p = [r[l], g[l], b[l]];
        }
        (px, traced)
    }

    /// [`Sampling::Adaptive`] over `rect`, block by block (see
    /// [`ADAPTIVE_BLOCK`]).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn adaptive_rect<const W: usize>(
        &self,
        rect: Rect,
        out: &mut [Rgb8],
        n: u32,
        threshold: u16,
        cull: &Culling<'_, S>,
        stats: &mut RayStats,
    ) {
        const SIDE: usize = ADAPTIVE_BLOCK as usize + 2;
        let (width, height) = (self.camera.width(), self.camera.height());
        // Clipped to the image, as every renderer clips.
        let x_end = rect.x.saturating_add(rect.w).min(width);
        let y_end = rect.y.saturating_add(rect.h).min(height);
        let mut centre = [[0u8; 3]; SIDE * SIDE];
        let mut y0 = rect.y;
        while y0 < y_end {
            let mut x0 = rect.x;
            while x0 < x_end {
                let block = Rect { x: x0, y: y0, w: ADAPTIVE_BLOCK.min(x_end - x0), h: ADAPTIVE_BLOCK.min(y_end - y0) };
                // The block and its ring of neighbours inside the image:
                // whatever `rect` is, a pixel's neighbours are traced.
                let ex = block.x.saturating_sub(1);
                let ey = block.y.saturating_sub(1);
                let ring = Rect {
                    x: ex,
                    y: ey,
                    w: (block.x + block.w + 1).min(width) - ex,
                    h: (block.y + block.h + 1).min(height) - ey,
                };
                self.packets::<W>(
                    ring,
                    ring,
                    &mut centre,
                    #[cfg_attr(
                        all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")),
                        inline(always)
                    )]
                    |x, y| {
                        let (ray, active) = self.camera.packet::<W>(x, y, ring);
                        (self.shade_packet(&ray, active, cull.at::<W>(x, y), cull.shadow, stats), active)
                    },
                );
                let at = |x: u32, y: u32| {
                    centre
                        .get((y - ring.y) as usize * ring.w as usize + (x - ring.x) as usize)
                        .copied()
                        .unwrap_or([0; 3])
                };
                let differs = |a: Rgb8, b: Rgb8| (0..3).map(|k| a[k].abs_diff(b[k]) as u16).sum::<u16>() > threshold;
                let (pw, _) = packet_shape(W);
                self.packets::<W>(
                    block,
                    rect,
                    out,
                    #[cfg_attr(
                        all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")),
                        inline(always)
                    )]
                    |x, y| {
                        let mut inside = Mask::<W>::splat(false);
                        let mut marked = Mask::<W>::splat(false);
                        let mut px = [[0u8; 3]; W];
                        for (l, p) in px.iter_mut().enumerate() {
                            let (i, j) = (x.saturating_add(l as u32 % pw), y.saturating_add(l as u32 / pw));
                            if i < block.x || i - block.x >= block.w || j < block.y || j - block.y >= block.h {
                                continue;
                            }
                            inside.set(l, true);
                            let c = at(i, j);
                            *p = c;
                            let left = i > 0 && differs(c, at(i - 1, j));
                            let right = i + 1 < width && differs(c, at(i + 1, j));
                            let up = j > 0 && differs(c, at(i, j - 1));
                            let down = j + 1 < height && differs(c, at(i, j + 1));
                            marked.set(l, left || right || up || down);
                        }
                        if marked.any() {
                            let (fine, traced) = self.supersample::<W>(x, y, block, n, marked, cull, stats);
                            for (l, p) in px.iter_mut().enumerate() {
                                if traced.get(l) {
                                    *p = fine[l];
                                }
                            }
                        }
                        (px, inside)
                    },
                );
                x0 += block.w;
            }
            y0 += ADAPTIVE_BLOCK.min(y_end - y0);
        }
    }

    /// The pixels of one packet of primary rays.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn shade_packet<const W: usize>(
        &self,
        ray: &crate::geom::ray::RayPacket<S, W>,
        active: Mask<W>,
        candidates: Candidates,
        shadows: Option<&ShadowCull<S>>,
        stats: &mut RayStats,
    ) -> [Rgb8; W] {
        let mut px = [[0u8; 3]; W];
        match self.aov {
            Aov::Color => {
                let c = self.tracer.trace_among(ray, active, candidates, shadows, stats);
                // Quantization as lane code, one channel at a time.
                let (r, g, b) = (c.x.to_unorm8(), c.y.to_unorm8(), c.z.to_unorm8());
                for (l, p) in px.iter_mut().enumerate() {
                    *p = [r[l], g[l], b[l]];
                }
            }
            aov => {
                stats.add_primary(active.count() as u64);
                let hit = self.tracer.closest_hit_among(ray, Lanes::zero(), Lanes::splat(S::MAX), active, candidates);
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
                        let (x, y, z) = (
                            (n.x * half + half).to_unorm8(),
                            (n.y * half + half).to_unorm8(),
                            (n.z * half + half).to_unorm8(),
                        );
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
