//! The tile loop shared by `render` and `bench`: the image is cut into
//! 32×32 tiles (a multiple of every packet shape), each rendered
//! independently by the core into its own buffer on a rayon pool, so the
//! bytes depend neither on the number of threads nor on which thread renders
//! which tile; the core guarantees they do not depend on the packet width
//! or (for `f32`) on the instruction set either.

use crate::Failure;
use raypack::dispatch::{self, Isa};
use raypack::prelude::*;
use raypack::render::BufferTooSmall;
use rayon::prelude::*;

/// The tracer's fixed stack: the largest `--depth`.
pub const MAX_DEPTH: u32 = 16;
/// [`MAX_DEPTH`] as the tracer's const generic.
pub const DEPTH: usize = MAX_DEPTH as usize;

/// Tile side in pixels.
pub const TILE: u32 = 32;

/// A scalar type the CLI renders with, and how its packets of 8 and 16 reach
/// the core. (Packets of 1 and 4 always run the plain, baseline `render_rect`.)
pub trait TileScalar: Scalar {
    /// The instruction set tiles of `packet`-wide packets really run with
    /// when `isa` is asked for.
    fn isa_used(isa: Isa, packet: usize) -> Isa;
    /// Renders one tile with packets of `W` (8 or 16) rays, compiled for
    /// `isa` where the scalar is dispatched.
    fn render_tile_wide<const W: usize>(
        isa: Isa,
        renderer: &Renderer<'_, Self, DEPTH>,
        rect: Rect,
        out: &mut [Rgb8],
        stats: &mut RayStats,
    ) -> Result<(), BufferTooSmall>;
}

/// Packets of 8 and 16 `f32` rays go through the dispatcher: the render path
/// compiled for the instruction set asked for. Narrower packets always run
/// the baseline copy: 1 and 4 lanes of `f32` fit SSE2's 128-bit registers,
/// so AVX2 and AVX-512 would only re-encode the same work, and every
/// dispatched copy of the whole (fully inlined) render path costs minutes
/// of release compile time.
impl TileScalar for f32 {
    fn isa_used(isa: Isa, packet: usize) -> Isa {
        if packet >= 8 {
            isa.effective()
        } else {
            Isa::Baseline
        }
    }
    fn render_tile_wide<const W: usize>(
        isa: Isa,
        renderer: &Renderer<'_, f32, DEPTH>,
        rect: Rect,
        out: &mut [Rgb8],
        stats: &mut RayStats,
    ) -> Result<(), BufferTooSmall> {
        dispatch::render_rect::<f32, DEPTH, W>(isa, renderer, rect, out, stats)
    }
}

impl TileScalar for Fixed {
    /// Fixed point is integer code: wider vector units do not help it (its
    /// 128-bit products do not vectorize), so it is not compiled per ISA.
    fn isa_used(_: Isa, _: usize) -> Isa {
        Isa::Baseline
    }
    fn render_tile_wide<const W: usize>(
        _: Isa,
        renderer: &Renderer<'_, Fixed, DEPTH>,
        rect: Rect,
        out: &mut [Rgb8],
        stats: &mut RayStats,
    ) -> Result<(), BufferTooSmall> {
        renderer.render_rect::<W>(rect, out, stats)
    }
}

/// The tiles of a `width × height` image, row by row.
pub fn tiles(width: u32, height: u32) -> Vec<Rect> {
    let mut out = Vec::new();
    for y in (0..height).step_by(TILE as usize) {
        for x in (0..width).step_by(TILE as usize) {
            out.push(Rect { x, y, w: TILE.min(width - x), h: TILE.min(height - y) });
        }
    }
    out
}

/// Renders the whole image of `renderer` on `pool` with packets of
/// `packet` rays compiled for `isa`; `done` is called after each tile.
/// Returns the pixels (row-major) and the rays traced.
pub fn render_image<S: TileScalar>(
    renderer: &Renderer<'_, S, DEPTH>,
    packet: usize,
    isa: Isa,
    pool: &rayon::ThreadPool,
    done: &(dyn Fn() + Sync),
) -> Result<(Vec<Rgb8>, RayStats), Failure> {
    let (width, height) = (renderer.camera.width(), renderer.camera.height());
    let tiles = tiles(width, height);
    let results: Vec<Result<(Vec<Rgb8>, RayStats), Failure>> = pool.install(|| {
        tiles
            .par_iter()
            .map(|&rect| {
                let mut px = vec![[0u8; 3]; rect.w as usize * rect.h as usize];
                let mut stats = RayStats::default();
                match packet {
                    1 => renderer.render_rect::<1>(rect, &mut px, &mut stats),
                    4 => renderer.render_rect::<4>(rect, &mut px, &mut stats),
                    8 => S::render_tile_wide::<8>(isa, renderer, rect, &mut px, &mut stats),
                    16 => S::render_tile_wide::<16>(isa, renderer, rect, &mut px, &mut stats),
                    other => return Err(Failure(format!("packet width {other} is not one of 1, 4, 8, 16"))),
                }?;
                done();
                Ok((px, stats))
            })
            .collect()
    });

    // Assemble the tiles; ray counts are sums, the same in any order.
    let mut pixels = vec![[0u8; 3]; width as usize * height as usize];
    let mut stats = RayStats::default();
    for (rect, result) in tiles.iter().zip(results) {
        let (px, s) = result?;
        stats.merge(&s);
        for row in 0..rect.h as usize {
            let dst = (rect.y as usize + row) * width as usize + rect.x as usize;
            let src = row * rect.w as usize;
            pixels[dst..dst + rect.w as usize].copy_from_slice(&px[src..src + rect.w as usize]);
        }
    }
    Ok((pixels, stats))
}

/// A rayon pool of `threads` workers (default: one per core).
pub fn pool(threads: Option<u32>) -> Result<rayon::ThreadPool, Failure> {
    let mut pool = rayon::ThreadPoolBuilder::new().thread_name(|i| format!("raypack-tile-{i}"));
    if let Some(n) = threads {
        pool = pool.num_threads(n as usize);
    }
    Ok(pool.build()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_the_image_once() {
        for (w, h) in [(1, 1), (31, 33), (64, 64), (100, 7)] {
            let mut seen = vec![0u8; w as usize * h as usize];
            for t in tiles(w, h) {
                for y in t.y..t.y + t.h {
                    for x in t.x..t.x + t.w {
                        seen[(y * w + x) as usize] += 1;
                    }
                }
            }
            assert!(seen.iter().all(|&c| c == 1), "{w}x{h}");
        }
    }
}
