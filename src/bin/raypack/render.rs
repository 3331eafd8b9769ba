//! `raypack render`: tiles rendered in parallel, a progress bar, a summary.
//!
//! The image is cut into 32×32 tiles (a multiple of every packet shape);
//! each tile is rendered independently by the core into its own buffer, so
//! the bytes do not depend on the number of threads or on which thread
//! renders which tile, and the core guarantees they do not depend on the
//! packet width either.

use crate::load::{self, Loaded};
use crate::output::PendingImage;
use crate::{AccelArg, AovArg, Failure, ModeArg, Packet, RenderArgs, ScalarArg};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use raypack::prelude::*;
use rayon::prelude::*;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Largest `--depth` (the tracer's fixed stack).
pub const MAX_DEPTH: u32 = 16;

/// Tile side in pixels.
const TILE: u32 = 32;

/// A finished render.
struct Rendered {
    width: u32,
    height: u32,
    pixels: Vec<Rgb8>,
    stats: RayStats,
    threads: usize,
    time: Duration,
    /// The BVH used (and its build time), `None` for brute force.
    accel: Option<(BvhStats, Duration)>,
}

pub fn run(args: &RenderArgs) -> Result<(), Failure> {
    // Fails now (before rendering) on a bad extension or an unwritable place.
    let image = PendingImage::create(&args.output)?;
    let accel = args.accel == AccelArg::Bvh;
    let r = match args.scalar {
        ScalarArg::F32 => load::with_scene::<f32, _>(&args.scene, accel, &|scene| render_scene(args, scene))?,
        ScalarArg::Fixed => load::with_scene::<Fixed, _>(&args.scene, accel, &|scene| render_scene(args, scene))?,
    };
    image.finish(r.width, r.height, &r.pixels)?;
    if !args.quiet {
        let s = &r.stats;
        let secs = r.time.as_secs_f64();
        let rate = if secs > 0.0 { s.total() as f64 / secs } else { 0.0 };
        eprintln!(
            "raypack: {}: {}x{}, {:.3} s on {} thread{}, packet {}; rays: {} primary, {} shadow, {} reflected, {} refracted; {:.2} M rays/s",
            args.output.display(),
            r.width,
            r.height,
            secs,
            r.threads,
            if r.threads == 1 { "" } else { "s" },
            packet_width(args.packet),
            s.primary,
            s.shadow,
            s.reflected,
            s.refracted,
            rate / 1e6
        );
        match r.accel {
            Some((b, built)) => eprintln!(
                "raypack: bvh: {} nodes ({} leaves, depth {}), {} primitives outside the tree, built in {:.2} ms",
                b.nodes,
                b.leaves,
                b.depth,
                b.unbounded,
                built.as_secs_f64() * 1e3
            ),
            None => eprintln!("raypack: no acceleration structure (--accel none): every ray tests every primitive"),
        }
    }
    Ok(())
}

fn packet_width(p: Packet) -> usize {
    match p {
        Packet::One => 1,
        Packet::Four => 4,
        Packet::Eight => 8,
    }
}

/// Image size: the file's resolution, or the overrides; one override alone
/// keeps the file's aspect ratio.
fn image_size(args: &RenderArgs, file: (u32, u32)) -> (u32, u32) {
    let scaled = |a: u32, num: u32, den: u32| ((a as u64 * num as u64 + den as u64 / 2) / den as u64).clamp(1, 65535) as u32;
    match (args.width, args.height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, scaled(w, file.1, file.0)),
        (None, Some(h)) => (scaled(h, file.0, file.1), h),
        (None, None) => file,
    }
}

/// The tiles of a `width × height` image, row by row.
fn tiles(width: u32, height: u32) -> Vec<Rect> {
    let mut out = Vec::new();
    for y in (0..height).step_by(TILE as usize) {
        for x in (0..width).step_by(TILE as usize) {
            out.push(Rect { x, y, w: TILE.min(width - x), h: TILE.min(height - y) });
        }
    }
    out
}

fn render_scene<S: Scalar>(args: &RenderArgs, scene: Loaded<'_, S>) -> Result<Rendered, Failure> {
    let path = args.scene.display();
    let cam = scene.info.camera.ok_or_else(|| Failure(format!("{path}: the scene has no `v` block (camera)")))?;
    let (width, height) = image_size(args, (cam.width, cam.height));
    let camera = cam.camera::<S>(width, height).map_err(|e| Failure(format!("{path}: {e}")))?;
    // Fixed point: the whole scene must fit its range (a no-op for f32).
    check_scene(&scene.view, &camera).map_err(|e| Failure(format!("{path}: {e}")))?;
    let settings = TraceSettings {
        mode: match args.mode {
            ModeArg::Cast => Mode::Cast,
            ModeArg::Trace => Mode::Whitted,
        },
        max_depth: args.depth,
        ..TraceSettings::default()
    };
    let tracer: Tracer<'_, S, { MAX_DEPTH as usize }> = Tracer::new(scene.view, settings)?;
    let mut renderer = Renderer::new(tracer, camera);
    renderer.aov = match args.aov {
        AovArg::Color => Aov::Color,
        AovArg::Depth => Aov::Depth,
        AovArg::Normal => Aov::Normal,
        AovArg::Id => Aov::Id,
    };
    if scene.degenerate > 0 && !args.quiet {
        eprintln!(
            "raypack: warning: {path}: {} zero-area polygon{} (kept so primitive ids follow the file, never hit)",
            scene.degenerate,
            if scene.degenerate == 1 { "" } else { "s" }
        );
    }

    let mut pool = rayon::ThreadPoolBuilder::new().thread_name(|i| format!("raypack-tile-{i}"));
    if let Some(n) = args.threads {
        pool = pool.num_threads(n as usize);
    }
    let pool = pool.build()?;
    let tiles = tiles(width, height);

    // Progress on stderr, shown only once a render has run for a second,
    // and only to a terminal.
    let bar = ProgressBar::with_draw_target(Some(tiles.len() as u64), ProgressDrawTarget::hidden());
    if let Ok(style) = ProgressStyle::with_template("{spinner} {elapsed_precise} [{bar:40}] {percent:>3}% ({eta} left)") {
        bar.set_style(style.progress_chars("=> "));
    }
    let show_bar = !args.quiet && std::io::stderr().is_terminal();
    let shown = AtomicBool::new(false);
    let start = Instant::now();

    let results: Vec<Result<(Vec<Rgb8>, RayStats), Failure>> = pool.install(|| {
        tiles
            .par_iter()
            .map(|&rect| {
                let mut px = vec![[0u8; 3]; rect.w as usize * rect.h as usize];
                let mut stats = RayStats::default();
                match args.packet {
                    Packet::One => renderer.render_rect::<1>(rect, &mut px, &mut stats),
                    Packet::Four => renderer.render_rect::<4>(rect, &mut px, &mut stats),
                    Packet::Eight => renderer.render_rect::<8>(rect, &mut px, &mut stats),
                }?;
                if show_bar && !shown.load(Ordering::Relaxed) && start.elapsed() > Duration::from_secs(1) && !shown.swap(true, Ordering::Relaxed) {
                    bar.set_draw_target(ProgressDrawTarget::stderr());
                }
                bar.inc(1);
                Ok((px, stats))
            })
            .collect()
    });
    let time = start.elapsed();
    bar.finish_and_clear();

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
    Ok(Rendered { width, height, pixels, stats, threads: pool.current_num_threads(), time, accel: scene.bvh })
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
