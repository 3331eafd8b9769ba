//! The threaded band loop: a rectangle cut into bands of rows on the
//! image's grid ([`Rect::bands`]), each rendered by whichever worker takes
//! it next, straight into its rows of one pixel buffer.

use super::options::Error;
use crate::geom::rect::Rect;
use crate::host::dispatch::{self, Isa};
use crate::num::scalar::Scalar;
use crate::query::Accelerator;
use crate::render::{Renderer, Rgb8};
use crate::trace::RayStats;
use std::sync::Mutex;

/// Tile height in rows of [`Image::render`](super::Image::render) (its tiles are bands as wide
/// as the image): a multiple of every packet shape's height.
pub const TILE: u32 = 8;

/// How [`render_tiles`] cuts and runs a render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tiling {
    /// Rays per packet: 1, 4, 8 or 16 (used where it applies:
    /// [`packet_used`](super::packet_used)).
    pub packet: usize,
    /// Instruction set (used where it applies: [`Isa::used_for`]).
    pub isa: Isa,
    /// Worker threads, at least 1.
    pub threads: usize,
    /// Tile height in rows, at least 1. A tile is a band of that many
    /// rows across the whole rectangle, on a grid of this pitch from the
    /// image's top row; bands are rows of the result, so each is rendered
    /// straight into it.
    pub tile: u32,
}

/// Renders `rect` of `renderer`'s image (clipped to the image) in tiles,
/// bands of `tiling.tile` rows across `rect` on the image's grid of that
/// pitch, on `tiling.threads` worker threads, with packets of
/// `tiling.packet` rays ([`packet_used`](super::packet_used)) compiled for `tiling.isa` where
/// that applies ([`Isa::used_for`]), and returns the pixels of the clipped
/// `rect` (row-major) and the rays traced; `progress` is called after each
/// tile. The one tile loop of raypack: [`Image::render`](super::Image::render) and the command
/// line use it.
///
/// A band's pixels are consecutive rows of the result, so each tile is
/// rendered straight into its own part of the one buffer (nothing is
/// allocated per tile or copied afterwards), and the bytes depend neither
/// on the number of threads nor on which thread renders which tile; the
/// core guarantees that they do not depend on the packet width or the
/// instruction set either.
pub fn render_tiles<S: Scalar, A: Accelerator<S> + Sync, const D: usize>(
    renderer: &Renderer<'_, S, A, D>,
    rect: Rect,
    tiling: &Tiling,
    progress: &(dyn Fn() + Sync),
) -> Result<(Vec<Rgb8>, RayStats), Error> {
    let Tiling { packet, isa, threads, tile } = *tiling;
    if !matches!(packet, 1 | 4 | 8 | 16) {
        return Err(Error::Packet(packet));
    }
    if threads == 0 {
        return Err(Error::Threads);
    }
    if !isa.is_available() {
        return Err(Error::Isa(isa));
    }
    let rect = rect.clip(renderer.camera.full_rect());
    let count = rect.w as usize * rect.h as usize;
    let mut pixels = Vec::new();
    pixels.try_reserve_exact(count).map_err(|_| Error::Memory { what: "the image", bytes: count * 3 })?;
    pixels.resize(count, [0u8; 3]);
    // Each band with its rows of the result, in order.
    let mut parts: Vec<(Rect, &mut [Rgb8])> = Vec::new();
    let mut rest = pixels.as_mut_slice();
    for band in rect.bands(tile) {
        let Some((this, tail)) = rest.split_at_mut_checked(band.w as usize * band.h as usize) else { break };
        parts.push((band, this));
        rest = tail;
    }
    let count = parts.len();
    let queue = Mutex::new(parts.into_iter());
    let failure: Mutex<Option<Error>> = Mutex::new(None);
    // A worker takes the next band until none is left, and returns the
    // rays it traced (sums: the same in any order).
    let work = || {
        let mut stats = RayStats::default();
        loop {
            let next = queue.lock().ok().and_then(|mut q| q.next());
            let Some((band, out)) = next else { return stats };
            // The rule of `packet_used`, as a constant condition per scalar,
            // so that only `f32` compiles the wider copies.
            let done = if const { !S::PACKED } {
                dispatch::render_rect::<S, A, D, 1>(isa, renderer, band, out, &mut stats)
            } else {
                match packet {
                    1 => dispatch::render_rect::<S, A, D, 1>(isa, renderer, band, out, &mut stats),
                    4 => dispatch::render_rect::<S, A, D, 4>(isa, renderer, band, out, &mut stats),
                    8 => dispatch::render_rect::<S, A, D, 8>(isa, renderer, band, out, &mut stats),
                    _ => dispatch::render_rect::<S, A, D, 16>(isa, renderer, band, out, &mut stats),
                }
            };
            match done {
                Ok(()) => progress(),
                Err(e) => {
                    if let Ok(mut f) = failure.lock() {
                        *f = Some(e.into());
                    }
                    return stats;
                }
            }
        }
    };
    let workers = threads.min(count).max(1);
    let stats = std::thread::scope(|s| -> Result<RayStats, Error> {
        let mut handles = Vec::new();
        for k in 1..workers {
            handles.push(
                std::thread::Builder::new()
                    .name(format!("raypack-tile-{k}"))
                    .spawn_scoped(s, work)
                    .map_err(Error::Thread)?,
            );
        }
        let mut stats = work();
        for h in handles {
            stats.merge(&h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)));
        }
        Ok(stats)
    })?;
    // (The queue borrows the pixels; every band has been taken.)
    drop(queue);
    if let Some(e) = failure.into_inner().ok().flatten() {
        return Err(e);
    }
    Ok((pixels, stats))
}

/// The number of tiles [`render_tiles`] cuts `rect` into with tiles of
/// `pitch` rows on the image's grid (for progress bars).
pub fn tile_count(rect: Rect, pitch: u32) -> u64 {
    rect.band_count(pitch)
}
