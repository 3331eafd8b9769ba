//! `raypack render`: tiles rendered in parallel (see `tiles.rs`), a
//! progress bar, a summary.

use crate::load::{self, Loaded};
use crate::output::PendingImage;
use crate::tiles::{self, TileScalar, DEPTH};
use crate::{AccelArg, AovArg, Failure, ModeArg, RenderArgs, ScalarArg};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use raypack::dispatch::Isa;
use raypack::prelude::*;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

pub use crate::tiles::MAX_DEPTH;

/// A finished render.
struct Rendered {
    width: u32,
    height: u32,
    pixels: Vec<Rgb8>,
    stats: RayStats,
    threads: usize,
    /// The instruction set the tiles ran with.
    isa: Isa,
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
            "raypack: {}: {}x{}, {:.3} s on {} thread{}, packet {}, isa {}; rays: {} primary, {} shadow, {} reflected, {} refracted; {:.2} M rays/s",
            args.output.display(),
            r.width,
            r.height,
            secs,
            r.threads,
            if r.threads == 1 { "" } else { "s" },
            args.packet.width(),
            r.isa,
            s.primary,
            s.shadow,
            s.reflected,
            s.refracted,
            rate / 1e6
        );
        let l = s.lanes_per_packet();
        eprintln!(
            "raypack: active lanes per packet of {}: {:.2} primary, {:.2} shadow, {:.2} reflected, {:.2} refracted",
            args.packet.width(),
            l[0],
            l[1],
            l[2],
            l[3]
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

/// Image size: the file's resolution, or the overrides; one override alone
/// keeps the file's aspect ratio.
pub fn image_size(width: Option<u32>, height: Option<u32>, file: (u32, u32)) -> (u32, u32) {
    let scaled = |a: u32, num: u32, den: u32| ((a as u64 * num as u64 + den as u64 / 2) / den as u64).clamp(1, 65535) as u32;
    match (width, height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, scaled(w, file.1, file.0)),
        (None, Some(h)) => (scaled(h, file.0, file.1), h),
        (None, None) => file,
    }
}

/// The scene's renderer at `width × height` (the file's camera), after the
/// range check of fixed point; warns about zero-area polygons unless quiet.
pub fn make_renderer<'a, S: Scalar>(
    path: &std::path::Path,
    scene: &Loaded<'a, S>,
    size: (u32, u32),
    settings: TraceSettings<S>,
    aov: Aov,
    quiet: bool,
) -> Result<Renderer<'a, S, DEPTH>, Failure> {
    let path = path.display();
    let cam = scene.info.camera.ok_or_else(|| Failure(format!("{path}: the scene has no `v` block (camera)")))?;
    let camera = cam.camera::<S>(size.0, size.1).map_err(|e| Failure(format!("{path}: {e}")))?;
    // Fixed point: the whole scene must fit its range (a no-op for f32).
    check_scene(&scene.view, &camera).map_err(|e| Failure(format!("{path}: {e}")))?;
    let tracer: Tracer<'_, S, DEPTH> = Tracer::new(scene.view, settings)?;
    let mut renderer = Renderer::new(tracer, camera);
    renderer.aov = aov;
    if scene.degenerate > 0 && !quiet {
        eprintln!(
            "raypack: warning: {path}: {} zero-area polygon{} (kept so primitive ids follow the file, never hit)",
            scene.degenerate,
            if scene.degenerate == 1 { "" } else { "s" }
        );
    }
    Ok(renderer)
}

fn render_scene<S: TileScalar>(args: &RenderArgs, scene: Loaded<'_, S>) -> Result<Rendered, Failure> {
    let file = scene.info.camera.map_or((1, 1), |c| (c.width, c.height));
    let (width, height) = image_size(args.width, args.height, file);
    let settings = TraceSettings {
        mode: match args.mode {
            ModeArg::Cast => Mode::Cast,
            ModeArg::Trace => Mode::Whitted,
        },
        max_depth: args.depth,
        ..TraceSettings::default()
    };
    let aov = match args.aov {
        AovArg::Color => Aov::Color,
        AovArg::Depth => Aov::Depth,
        AovArg::Normal => Aov::Normal,
        AovArg::Id => Aov::Id,
    };
    let renderer = make_renderer(&args.scene, &scene, (width, height), settings, aov, args.quiet)?;
    let isa = args.isa.resolve()?;
    let pool = tiles::pool(args.threads)?;
    let count = tiles::tiles(width, height).len();

    // Progress on stderr, shown only once a render has run for a second,
    // and only to a terminal.
    let bar = ProgressBar::with_draw_target(Some(count as u64), ProgressDrawTarget::hidden());
    if let Ok(style) = ProgressStyle::with_template("{spinner} {elapsed_precise} [{bar:40}] {percent:>3}% ({eta} left)") {
        bar.set_style(style.progress_chars("=> "));
    }
    let show_bar = !args.quiet && std::io::stderr().is_terminal();
    let shown = AtomicBool::new(false);
    let start = Instant::now();
    let done = || {
        if show_bar && !shown.load(Ordering::Relaxed) && start.elapsed() > Duration::from_secs(1) && !shown.swap(true, Ordering::Relaxed) {
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        bar.inc(1);
    };
    let (pixels, stats) = tiles::render_image(&renderer, args.packet.width(), isa, &pool, &done)?;
    let time = start.elapsed();
    bar.finish_and_clear();
    Ok(Rendered { width, height, pixels, stats, threads: pool.current_num_threads(), isa: S::isa_used(isa, args.packet.width()), time, accel: scene.bvh })
}
