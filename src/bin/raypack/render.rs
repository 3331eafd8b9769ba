//! `raypack render`: the library's tile loop ([`raypack::image`]), a
//! progress bar, a summary.

use crate::output::PendingImage;
use crate::{Failure, RenderArgs};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use raypack::image::{self, LoadedScene, TILE};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

pub fn run(args: &RenderArgs) -> Result<(), Failure> {
    // Fails now (before rendering) on a bad extension or an unwritable place.
    let pending = PendingImage::create(&args.output)?;
    let text = crate::read_scene(&args.scene)?;
    let options = args.options()?;
    let path = args.scene.display();
    let (img, info) = image::with_scene(&text, options.scalar, options.accel, |scene| render_scene(args, &options, scene))
        .map_err(|e| Failure(format!("{path}: {e}")))?;
    let img = img.map_err(|e| Failure(format!("{path}: {e}")))?;
    pending.finish(img.width, img.height, &img.pixels)?;
    if !args.quiet {
        let s = &img.stats;
        let secs = img.time.as_secs_f64();
        let rate = if secs > 0.0 { s.total() as f64 / secs } else { 0.0 };
        eprintln!(
            "raypack: {}: {}x{}, {:.3} s on {} thread{}, packet {}, isa {}; rays: {} primary, {} shadow, {} reflected, {} refracted; {:.2} M rays/s",
            args.output.display(),
            img.width,
            img.height,
            secs,
            img.threads,
            if img.threads == 1 { "" } else { "s" },
            options.packet,
            img.isa,
            s.primary,
            s.shadow,
            s.reflected,
            s.refracted,
            rate / 1e6
        );
        let l = s.lanes_per_packet();
        eprintln!(
            "raypack: active lanes per packet of {}: {:.2} primary, {:.2} shadow, {:.2} reflected, {:.2} refracted",
            options.packet, l[0], l[1], l[2], l[3]
        );
        match info.bvh {
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

/// Warns about zero-area polygons unless quiet.
pub fn warn_degenerate(args_scene: &std::path::Path, info: &image::SceneInfo, quiet: bool) {
    if info.degenerate > 0 && !quiet {
        eprintln!(
            "raypack: warning: {}: {} zero-area polygon{} (kept so primitive ids follow the file, never hit)",
            args_scene.display(),
            info.degenerate,
            if info.degenerate == 1 { "" } else { "s" }
        );
    }
}

fn render_scene(args: &RenderArgs, options: &image::Options, scene: &dyn LoadedScene) -> (Result<image::Image, image::Error>, image::SceneInfo) {
    let info = *scene.info();
    warn_degenerate(&args.scene, &info, args.quiet);
    let size = info.nff.camera.map_or((1, 1), |c| image::image_size(options.width, options.height, (c.width, c.height)));
    let full = raypack::camera::Rect { x: 0, y: 0, w: size.0, h: size.1 };
    let count = image::tile_count(options.region.unwrap_or(full), TILE);

    // Progress on stderr, shown only once a render has run for a second,
    // and only to a terminal.
    let bar = ProgressBar::with_draw_target(Some(count), ProgressDrawTarget::hidden());
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
    let img = scene.render(options, &done);
    bar.finish_and_clear();
    (img, info)
}
