//! `raypack render`: the library's tile loop ([`raypack::image`]), a
//! progress bar, a summary.

use crate::output::{Region, Sink};
use crate::{Failure, RenderArgs};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use raypack::image::{self, LoadedScene, TILE};
use raypack::output::Fnv1a;
use raypack::render::Sampling;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

pub fn run(args: &RenderArgs) -> Result<(), Failure> {
    let options = args.options()?;
    // Without -o: SCENE_STEM.png here, never over an existing file unless
    // --force.
    let (path, no_clobber) = match &args.output {
        Some(p) => (p.clone(), false),
        None if args.scene.as_os_str() == "-" => crate::usage_error(
            "the scene comes from standard input: name the output with -o FILE (or -o - for standard output)",
        ),
        None => {
            let stem = args.scene.file_stem().map_or_else(|| "raypack".into(), |s| s.to_os_string());
            let mut name = std::path::PathBuf::from(stem);
            name.set_extension(args.format.map_or("png", |f| f.name()));
            (name, !args.force)
        }
    };
    // Fails now (before rendering) on a bad extension or an unwritable place.
    let sink = Sink::create(&path, args.format, no_clobber)?;
    let text = crate::read_scene(&args.scene)?;
    let name = crate::scene_name(&args.scene);
    let (img, info) =
        image::with_scene(&text, options.scalar, options.accel, |scene| render_scene(args, &options, scene))
            .map_err(|e| Failure(format!("{name}: {e}")))?;
    let img = img.map_err(|e| Failure(format!("{name}: {e}")))?;
    let region = options.region.map(|rect| Region {
        rect,
        full: img.full_size,
        render: render_hash(&text, &options, img.full_size),
    });
    let out_name = sink.name();
    sink.finish(img.width, img.height, &img.pixels, region.as_ref())?;
    if !args.quiet {
        let s = &img.stats;
        let secs = img.time.as_secs_f64();
        let rate = if secs > 0.0 { s.total() as f64 / secs } else { 0.0 };
        let part = match options.region {
            Some(r) => format!(" (region {},{},{},{} of {}x{})", r.x, r.y, r.w, r.h, img.full_size.0, img.full_size.1),
            None => String::new(),
        };
        note!(
            "raypack: {}: {}x{}{part}, {:.3} s on {} thread{}, packet {}, isa {}; rays: {} primary, {} shadow, {} reflected, {} refracted; {:.2} M rays/s",
            out_name,
            img.width,
            img.height,
            secs,
            img.threads,
            if img.threads == 1 { "" } else { "s" },
            img.packet,
            img.isa,
            s.primary,
            s.shadow,
            s.reflected,
            s.refracted,
            rate / 1e6
        );
        let pixels = (img.width as u64 * img.height as u64).max(1) as f64;
        match options.sampling {
            Sampling::Centre => {}
            Sampling::Grid(_) => note!(
                "raypack: anti-aliasing: {n}x{n} samples per pixel: {:.2} primary rays per pixel (1 without), {:.2} rays per pixel in all",
                s.primary as f64 / pixels,
                s.total() as f64 / pixels,
                n = options.sampling.grid()
            ),
            Sampling::Adaptive { threshold, .. } => note!(
                "raypack: anti-aliasing: adaptive {n}x{n}, threshold {:.3} (a difference of {threshold} in the sum of the three 8-bit channels): {:.2} primary rays per pixel (1 without), {:.2} rays per pixel in all",
                threshold as f64 / 255.0,
                s.primary as f64 / pixels,
                s.total() as f64 / pixels,
                n = options.sampling.grid()
            ),
        }
        let l = s.lanes_per_packet();
        note!(
            "raypack: active lanes per packet of {}: {:.2} primary, {:.2} shadow, {:.2} reflected, {:.2} refracted",
            img.packet,
            l[0],
            l[1],
            l[2],
            l[3]
        );
        note!(
            "raypack: scene: {} primitives read in {:.3} s; {:.1} MB for the scene and its tree ({:.1} bytes per primitive)",
            info.nff.counts.primitives(),
            info.parse.as_secs_f64(),
            info.bytes as f64 / 1e6,
            info.bytes as f64 / info.nff.counts.primitives().max(1) as f64
        );
        match info.bvh {
            Some((b, built)) => note!(
                "raypack: bvh: {} nodes ({} leaves, depth {}), {} primitives outside the tree, built in {:.2} ms",
                b.nodes,
                b.leaves,
                b.depth,
                b.unbounded,
                built.as_secs_f64() * 1e3
            ),
            None => note!("raypack: no acceleration structure (--accel none): every ray tests every primitive"),
        }
    }
    Ok(())
}

/// The `render=` hash of a part: FNV-1a of the scene text and of every
/// option that changes the bytes (not the packet width, threads, ISA or
/// accelerator), so that parts of different renders do not stitch.
fn render_hash(text: &str, o: &image::Options, full: (u32, u32)) -> String {
    let mut h = Fnv1a::new();
    h.write(text.as_bytes());
    h.write(
        format!("\0{}x{} {:?} {} {:?} {:?} {:?}", full.0, full.1, o.mode, o.depth, o.aov, o.scalar, o.sampling)
            .as_bytes(),
    );
    format!("{:08x}", h.finish())
}

/// Warns about zero-area polygons unless quiet.
pub fn warn_degenerate(args_scene: &std::path::Path, info: &image::SceneInfo, quiet: bool) {
    if info.degenerate > 0 && !quiet {
        note!(
            "raypack: warning: {}: {} zero-area polygon{} (kept so primitive ids follow the file, never hit)",
            crate::scene_name(args_scene),
            info.degenerate,
            if info.degenerate == 1 { "" } else { "s" }
        );
    }
}

fn render_scene(
    args: &RenderArgs,
    options: &image::Options,
    scene: &LoadedScene,
) -> (Result<image::Image, image::Error>, image::SceneInfo) {
    let info = *scene.info();
    warn_degenerate(&args.scene, &info, args.quiet);
    let size =
        info.nff.camera.map_or((1, 1), |c| image::image_size(options.width, options.height, (c.width, c.height)));
    let full = raypack::camera::Rect { x: 0, y: 0, w: size.0, h: size.1 };
    let count = options.region.unwrap_or(full).band_count(TILE);

    // Progress on stderr, shown only once a render has run for a second,
    // and only to a terminal.
    let bar = ProgressBar::with_draw_target(Some(count), ProgressDrawTarget::hidden());
    if let Ok(style) = ProgressStyle::with_template("{spinner} {elapsed_precise} [{bar:40}] {percent:>3}% ({eta} left)")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    let show_bar = !args.quiet && std::io::stderr().is_terminal();
    let shown = AtomicBool::new(false);
    let start = Instant::now();
    let done = || {
        if show_bar
            && !shown.load(Ordering::Relaxed)
            && start.elapsed() > Duration::from_secs(1)
            && !shown.swap(true, Ordering::Relaxed)
        {
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        bar.inc(1);
    };
    let img = scene.render(options, &done);
    bar.finish_and_clear();
    (img, info)
}
