//! From NFF text to pixels in one call (`std`): the entry point for Rust
//! programs, and what the `raypack` command line is built on.
//!
//! ```
//! use raypack::image::{Image, Options};
//!
//! let scene = "v\nfrom 0 -5 0\nat 0 0 0\nup 0 0 1\nangle 40\nhither 1\nresolution 64 48\n\
//!              l 2 -4 3\nf 1 0.2 0.2 1 0 0 0 0\ns 0 0 0 1\n";
//! let image = Image::render(scene, &Options::default())?;
//! assert_eq!((image.width, image.height), (64, 48));
//! assert_eq!(image.pixels.len(), 64 * 48);
//! assert_eq!(image.stats.primary, 64 * 48);
//! let centre = image.pixels[24 * 64 + 32];
//! assert!(centre[0] > centre[1]);                // the red sphere, lit
//! # Ok::<(), raypack::image::Error>(())
//! ```
//!
//! [`Image::render`] reads the scene into a fixed-capacity scene of the
//! smallest size tier that holds it (on a thread whose stack is sized for
//! it: scenes are single values, megabytes for the larger tiers), builds a
//! BVH, picks the fastest instruction set this CPU has, renders 32×32
//! tiles on all cores and returns the pixels with the ray counts. Every
//! choice in [`Options`] (packet width, threads, instruction set, brute
//! force or BVH) gives the same bytes; only the speed differs.
//!
//! [`with_scene`] loads a scene once and hands it to a closure that can
//! render it many times (the `raypack bench` command does that), and
//! [`render_tiles`] is the tile loop itself, for scenes built in code.

use crate::geom::camera::{CameraError, Rect};
use crate::geom::fixed_range::RangeError;
use crate::geom::uniform_scale::Similarity;
use crate::host::dispatch::{self, Isa};
use crate::num::fixed32::Fixed32;
use crate::num::scalar::Scalar;
use crate::query::{AccelChoice, Accelerator, BuildSettings, Bvh, BvhError, BvhStats};
use crate::render::{Aov, BufferTooSmall, Renderer, Rgb8, Sampling};
use crate::scene::nff::{self, NffCounts, NffError, NffInfo};
use crate::scene::{Scene, SceneError, SceneView};
use crate::trace::{Mode, RayStats, TraceError, TraceSettings, Tracer};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The deepest `Options::depth` accepted (the tracer's fixed stack).
pub const MAX_DEPTH: u32 = 16;
const DEPTH: usize = MAX_DEPTH as usize;

/// Tile height in rows of [`Image::render`] (its tiles are bands as wide
/// as the image): a multiple of every packet shape's height.
pub const TILE: u32 = 8;

/// How [`render_tiles`] cuts and runs a render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tiling {
    /// Rays per packet: 1, 4, 8 or 16 (used where it applies:
    /// [`packet_used`]).
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

/// The number type to trace with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ScalarKind {
    /// 32-bit IEEE float.
    #[default]
    F32,
    /// Q8.24 fixed point with 32-bit storage ([`Fixed32`]), for
    /// processors without an FPU; the scene is converted into its small
    /// frame at load time ([`crate::geom::uniform_scale`]).
    Fixed32,
}

impl ScalarKind {
    /// Lower-case name, as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            ScalarKind::F32 => "f32",
            ScalarKind::Fixed32 => "fixed32",
        }
    }
}

/// How rays find what they hit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AccelKind {
    /// A bounding volume hierarchy (the same image, faster).
    #[default]
    Bvh,
    /// Test every primitive.
    BruteForce,
}

/// What to render, and how. Every field but `scalar`, `mode`, `depth`,
/// `aov`, `sampling`, the size and the region leaves the bytes unchanged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Image width; `None`: the scene's `resolution` (or, with only the
    /// height given, the width that keeps its aspect ratio).
    pub width: Option<u32>,
    /// Image height; `None` as for `width`.
    pub height: Option<u32>,
    /// Rays per packet: 1, 4, 8 or 16 (default: [`best_packet`] for
    /// [`Isa::best`]).
    pub packet: usize,
    /// Worker threads; `None`: one per core.
    pub threads: Option<usize>,
    /// Ray casting or Whitted ray tracing.
    pub mode: Mode,
    /// Maximum ray depth (segments per path, primary included), 1 to
    /// [`MAX_DEPTH`].
    pub depth: u32,
    /// What each pixel shows.
    pub aov: Aov,
    /// Brute force or BVH.
    pub accel: AccelKind,
    /// The number type.
    pub scalar: ScalarKind,
    /// Instruction set of the render path (must be available on this CPU).
    pub isa: Isa,
    /// Only this rectangle of the full image (`None`: all of it). The
    /// pixels are exactly those of the same rectangle of the full render,
    /// whatever the other options and wherever the cut; it must lie inside
    /// the image.
    pub region: Option<Rect>,
    /// Camera rays per pixel of the colour AOV (anti-aliasing; see
    /// [`Sampling`]).
    pub sampling: Sampling,
}

impl Default for Options {
    /// The scene's size, packets of 8, every core, Whitted to depth 5,
    /// colour, BVH, `f32`, the best instruction set of this CPU.
    fn default() -> Self {
        Options {
            width: None,
            height: None,
            packet: best_packet(Isa::best()),
            threads: None,
            mode: Mode::Whitted,
            depth: 5,
            aov: Aov::Color,
            accel: AccelKind::Bvh,
            scalar: ScalarKind::F32,
            isa: Isa::best(),
            region: None,
            sampling: Sampling::Centre,
        }
    }
}

/// Why a scene could not be rendered.
#[derive(Debug)]
pub enum Error {
    /// The scene file is malformed or does not fit (line and column inside).
    Scene(NffError),
    /// The scene has no `v` block, so no camera.
    NoCamera,
    /// The camera was rejected.
    Camera(CameraError),
    /// The scene does not fit the fixed-point range.
    Range(RangeError),
    /// The scene could not be converted into the fixed-point frame (a
    /// light too far out, or a range error).
    Convert(SceneError),
    /// The tracer was rejected (depth out of range).
    Trace(TraceError),
    /// The BVH did not fit.
    Bvh(BvhError),
    /// A packet width other than 1, 4, 8 or 16.
    Packet(usize),
    /// Zero threads.
    Threads,
    /// The instruction set asked for is not available on this CPU.
    Isa(Isa),
    /// A worker thread could not be started.
    Thread(std::io::Error),
    /// The region asked for is empty or not inside the image.
    Region {
        /// The region asked for.
        region: Rect,
        /// The image size.
        size: (u32, u32),
    },
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Scene(e) => e.fmt(f),
            Error::NoCamera => f.write_str("the scene has no `v` block (camera)"),
            Error::Camera(e) => e.fmt(f),
            Error::Range(e) => e.fmt(f),
            Error::Convert(e) => write!(f, "in the fixed-point frame: {e}"),
            Error::Trace(e) => e.fmt(f),
            Error::Bvh(e) => e.fmt(f),
            Error::Packet(n) => write!(f, "packet width {n} is not one of 1, 4, 8, 16"),
            Error::Threads => f.write_str("at least one thread is needed"),
            Error::Isa(isa) => write!(f, "this CPU cannot run the {isa} instruction set"),
            Error::Thread(e) => write!(f, "cannot start a thread: {e}"),
            Error::Region { region: r, size: (w, h) } => {
                write!(f, "region {},{},{},{} is not inside the {w}x{h} image (X,Y,W,H: W and H at least 1, X + W <= {w}, Y + H <= {h})", r.x, r.y, r.w, r.h)
            }
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Scene(e) => Some(e),
            Error::Camera(e) => Some(e),
            Error::Range(e) => Some(e),
            Error::Convert(e) => Some(e),
            Error::Trace(e) => Some(e),
            Error::Bvh(e) => Some(e),
            Error::Thread(e) => Some(e),
            _ => None,
        }
    }
}

impl From<BufferTooSmall> for Error {
    // Tile buffers are sized by the tile loop itself, so this cannot
    // happen; it is still an error, not a panic.
    fn from(e: BufferTooSmall) -> Self {
        Error::Thread(std::io::Error::other(e.to_string()))
    }
}

/// A rendered image: `width × height` pixels, row-major, and what it took.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels (of the region, if one was asked for).
    pub width: u32,
    /// Height in pixels (of the region, if one was asked for).
    pub height: u32,
    /// Where these pixels lie in the full image (all of it without
    /// [`Options::region`]).
    pub region: Rect,
    /// Size of the full image.
    pub full_size: (u32, u32),
    /// The pixels, row-major, `width · height` of them.
    pub pixels: Vec<Rgb8>,
    /// The rays traced, by kind.
    pub stats: RayStats,
    /// The instruction set the render path ran with.
    pub isa: Isa,
    /// Rays per packet the render path ran with ([`packet_used`]).
    pub packet: usize,
    /// Worker threads used.
    pub threads: usize,
    /// The accelerator the render ran through.
    pub accel: AccelKind,
    /// Wall time of the render (tiles only: not loading or the tree).
    pub time: Duration,
}

impl Image {
    /// Reads `scene` (NFF text), builds what `options` asks for and renders
    /// it; see the module documentation.
    pub fn render(scene: &str, options: &Options) -> Result<Image, Error> {
        with_scene(scene, options.scalar, options.accel, |s| s.render(options, &|| {}))?
    }
}

/// What a loaded scene holds, besides its objects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneInfo {
    /// Camera, background, counts and lines of the file.
    pub nff: NffInfo,
    /// Zero-area polygons (kept, so primitive ids follow the file; never hit).
    pub degenerate: u32,
    /// The capacity tier used: primitives, vertices, materials, lights.
    pub capacity: (usize, usize, usize, usize),
    /// The tree and its build time, if one was built.
    pub bvh: Option<(BvhStats, Duration)>,
    /// The scalar the scene was built with.
    pub scalar: ScalarKind,
}

/// A scene loaded by [`with_scene`], ready to be rendered any number of
/// times (whatever its scalar: the scalar is fixed when loading).
pub trait LoadedScene {
    /// What the scene holds.
    fn info(&self) -> &SceneInfo;
    /// Bounds of the bounded primitives (`None` if there are none), in
    /// `f32`.
    fn bounds(&self) -> Option<([f32; 3], [f32; 3])>;
    /// Renders the scene with `options`; `progress` is called after each
    /// tile, from the worker threads. `options.scalar` is the loaded
    /// scene's and is ignored here; `options.accel` may ask for brute force
    /// even where a tree was built (a scene loaded without a tree always
    /// renders by brute force: [`Image::accel`] says which ran).
    fn render(&self, options: &Options, progress: &(dyn Fn() + Sync)) -> Result<Image, Error>;
}

/// A scene of scalar `S` and the tree it is traced through.
struct Loaded<'a, S> {
    view: SceneView<'a, S>,
    accel: AccelChoice<'a, S>,
    info: SceneInfo,
    /// The frame the scene was converted into (the identity unless the
    /// scalar asks for one: [`Scalar::SCENE_FRAME`]).
    frame: Similarity,
}

impl<S: Scalar> LoadedScene for Loaded<'_, S> {
    fn info(&self) -> &SceneInfo {
        &self.info
    }

    fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        self.view.bounds().map(|(lo, hi)| (lo.to_f32(), hi.to_f32()))
    }

    fn render(&self, options: &Options, progress: &(dyn Fn() + Sync)) -> Result<Image, Error> {
        let cam = self.info.nff.camera.ok_or(Error::NoCamera)?;
        let (width, height) = image_size(options.width, options.height, (cam.width, cam.height));
        let camera = match S::SCENE_FRAME {
            None => cam.camera::<S>(width, height),
            Some(_) => cam.camera_in::<S>(&self.frame, width, height),
        }
        .map_err(Error::Camera)?;
        let region = options.region.unwrap_or(camera.full_rect());
        if !region_inside(region, (width, height)) {
            return Err(Error::Region { region, size: (width, height) });
        }
        // Fixed point: the whole scene must fit its range (a no-op for f32).
        self.view.check_range(camera.eye()).map_err(Error::Range)?;
        let settings = TraceSettings { mode: options.mode, max_depth: options.depth, ..TraceSettings::default() };
        let (accel, kind) = match (options.accel, self.accel) {
            (AccelKind::Bvh, tree @ AccelChoice::Bvh(_)) => (tree, AccelKind::Bvh),
            _ => (AccelChoice::BruteForce, AccelKind::BruteForce),
        };
        let tracer = Tracer::<'_, S, _, DEPTH>::with_accelerator(self.view, accel, settings).map_err(Error::Trace)?;
        let mut renderer = Renderer::new(tracer, camera);
        renderer.aov = options.aov;
        renderer.sampling = options.sampling;
        let threads = threads(options.threads)?;
        let start = Instant::now();
        let tiling = Tiling { packet: options.packet, isa: options.isa, threads, tile: TILE };
        let (pixels, stats) = render_tiles(&renderer, region, &tiling, progress)?;
        let time = start.elapsed();
        let packet = packet_used::<S>(options.packet);
        let isa = options.isa.used_for::<S>(packet);
        Ok(Image {
            width: region.w,
            height: region.h,
            region,
            full_size: (width, height),
            pixels,
            stats,
            isa,
            packet,
            threads,
            accel: kind,
            time,
        })
    }
}

/// Whether `r` is a non-empty rectangle inside an image of `size`.
fn region_inside(r: Rect, size: (u32, u32)) -> bool {
    r.w >= 1
        && r.h >= 1
        && r.x.checked_add(r.w).is_some_and(|e| e <= size.0)
        && r.y.checked_add(r.h).is_some_and(|e| e <= size.1)
}

/// The number of worker threads for `asked` (`None`: one per core).
fn threads(asked: Option<usize>) -> Result<usize, Error> {
    match asked {
        Some(0) => Err(Error::Threads),
        Some(n) => Ok(n),
        None => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

/// Image size: the file's resolution, or the overrides; one override alone
/// keeps the file's aspect ratio (rounded, at least 1, at most 65 535).
pub fn image_size(width: Option<u32>, height: Option<u32>, file: (u32, u32)) -> (u32, u32) {
    let scaled = |a: u32, num: u32, den: u32| {
        ((a as u64 * num as u64 + den as u64 / 2) / den.max(1) as u64).clamp(1, 65535) as u32
    };
    match (width, height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, scaled(w, file.1, file.0)),
        (None, Some(h)) => (scaled(h, file.0, file.1), h),
        (None, None) => file,
    }
}

/// Whether counts fit a tier.
fn fits(c: &NffCounts, p: usize, v: usize, m: usize, l: usize) -> bool {
    c.primitives() <= p && c.vertices <= v && c.materials <= m && c.lights <= l
}

/// Reads `text` (NFF) into a scene of scalar `scalar` in the smallest
/// capacity tier that holds it (up to 2²⁰ primitives, 2²³ vertex slots,
/// 65 536 materials, 16 384 lights; a larger file fails with the reader's
/// capacity error), builds a BVH over it unless `accel` is brute force, and
/// runs `f` on it, on a thread whose stack holds the scene. Returns what
/// `f` returns.
pub fn with_scene<T: Send>(
    text: &str,
    scalar: ScalarKind,
    accel: AccelKind,
    f: impl FnOnce(&dyn LoadedScene) -> T + Send,
) -> Result<T, Error> {
    match scalar {
        ScalarKind::F32 => with_tier::<f32, T>(text, scalar, accel, f),
        ScalarKind::Fixed32 => with_tier::<Fixed32, T>(text, scalar, accel, f),
    }
}

fn with_tier<S: Scalar, T: Send>(
    text: &str,
    scalar: ScalarKind,
    accel: AccelKind,
    f: impl FnOnce(&dyn LoadedScene) -> T + Send,
) -> Result<T, Error> {
    let counts = nff::scan(text).map_err(Error::Scene)?.counts;
    let accel = accel == AccelKind::Bvh;
    if fits(&counts, 1 << 10, 1 << 13, 256, 64) {
        load_in::<S, { 1 << 10 }, { 1 << 13 }, 256, 64, T>(text, scalar, accel, f)
    } else if fits(&counts, 1 << 14, 1 << 17, 1024, 256) {
        load_in::<S, { 1 << 14 }, { 1 << 17 }, 1024, 256, T>(text, scalar, accel, f)
    } else if fits(&counts, 1 << 18, 1 << 21, 16384, 4096) {
        load_in::<S, { 1 << 18 }, { 1 << 21 }, 16384, 4096, T>(text, scalar, accel, f)
    } else {
        // The largest tier; beyond it the reader reports the capacity error.
        load_in::<S, { 1 << 20 }, { 1 << 23 }, 65536, 16384, T>(text, scalar, accel, f)
    }
}

/// Loads into a `Scene<S, P, V, M, L>` on a thread with room for it and
/// runs `f` there.
fn load_in<S: Scalar, const P: usize, const V: usize, const M: usize, const L: usize, T: Send>(
    text: &str,
    scalar: ScalarKind,
    accel: bool,
    f: impl FnOnce(&dyn LoadedScene) -> T + Send,
) -> Result<T, Error> {
    // Twice the scenes (and tree): an unoptimized build may build them in a
    // temporary first. Scalars with a frame read the file in f32 first.
    let tree = if accel { std::mem::size_of::<Bvh<S, P>>() } else { 0 };
    let described = if S::SCENE_FRAME.is_some() { std::mem::size_of::<Scene<f32, P, V, M, L>>() } else { 0 };
    let stack = 2 * (std::mem::size_of::<Scene<S, P, V, M, L>>() + described + tree) + (32 << 20);
    std::thread::scope(|s| {
        let worker =
            std::thread::Builder::new().name("raypack-scene".into()).stack_size(stack).spawn_scoped(s, move || {
                let mut scene = Scene::<S, P, V, M, L>::new();
                let (nff, frame) = match S::SCENE_FRAME {
                    None => (nff::parse(text, &mut scene).map_err(Error::Scene)?, Similarity::IDENTITY),
                    Some(half) => {
                        // Read in f32, in the file's units, then convert into
                        // the scalar's frame: the box of the bounded primitives
                        // and the eye, centred, its largest half-extent `half`.
                        let mut described = Scene::<f32, P, V, M, L>::new();
                        let nff = nff::parse(text, &mut described).map_err(Error::Scene)?;
                        let eye = nff.camera.map(|c| crate::geom::vec3::Vec3::new(c.from[0], c.from[1], c.from[2]));
                        let frame = described.view().fitting_frame(eye, half);
                        scene.add_similar(&described.view(), &frame).map_err(Error::Convert)?;
                        (nff, frame)
                    }
                };
                let mut info = SceneInfo {
                    nff,
                    degenerate: scene.degenerate_polygons(),
                    capacity: (P, V, M, L),
                    bvh: None,
                    scalar,
                };
                if !accel {
                    return Ok(f(&Loaded { view: scene.view(), accel: AccelChoice::BruteForce, info, frame }));
                }
                let mut bvh = Bvh::<S, P>::new();
                // Pad the boxes for rays that start as far out as the eye (in
                // the scene's frame).
                let reach = nff.camera.map_or(0.0, |c| {
                    let e: crate::geom::vec3::Vec3<f32> =
                        frame.point(crate::geom::vec3::Vec3::new(c.from[0], c.from[1], c.from[2]));
                    e.max_abs()
                });
                let start = Instant::now();
                let stats = bvh
                    .build_with(&scene.view(), &BuildSettings { reach, ..BuildSettings::default() })
                    .map_err(Error::Bvh)?;
                info.bvh = Some((stats, start.elapsed()));
                Ok(f(&Loaded { view: scene.view(), accel: AccelChoice::Bvh(bvh.view()), info, frame }))
            });
        match worker {
            Ok(handle) => handle.join().unwrap_or_else(|p| std::panic::resume_unwind(p)),
            Err(e) => Err(Error::Thread(e)),
        }
    })
}

/// Renders `rect` of `renderer`'s image (clipped to the image) in tiles,
/// bands of `tiling.tile` rows across `rect` on the image's grid of that
/// pitch, on `tiling.threads` worker threads, with packets of
/// `tiling.packet` rays ([`packet_used`]) compiled for `tiling.isa` where
/// that applies ([`Isa::used_for`]), and returns the pixels of the clipped
/// `rect` (row-major) and the rays traced; `progress` is called after each
/// tile. The one tile loop of raypack: [`Image::render`] and the command
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
    let rect = clip(rect, renderer.camera.full_rect());
    let mut pixels = vec![[0u8; 3]; rect.w as usize * rect.h as usize];
    // Each band with its rows of the result, in order.
    let mut parts: Vec<(Rect, &mut [Rgb8])> = Vec::new();
    let mut rest = pixels.as_mut_slice();
    for band in tiles(rect, tile.max(1)) {
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

/// The fastest packet width for `f32` with instruction set `isa` (as
/// [`Isa::effective`]): 16 with AVX2 or AVX-512, 8 with the baseline
/// (SSE2), where 16 lanes are four registers per value. Measured on
/// balls-2, gears-2 and the sphere grids, Whitted and primary rays, in
/// docs/performance.md. The command line's default; the bytes are the
/// same at every width.
pub fn best_packet(isa: Isa) -> usize {
    match isa.effective() {
        Isa::Avx2 | Isa::Avx512 => 16,
        Isa::Baseline => 8,
    }
}

/// The packet width [`render_tiles`] really traces `S` with when asked for
/// `packet` rays: `packet` for a [`Scalar::PACKED`] type (`f32`), 1 for
/// the integer fixed-point scalars. Their lanes do not map onto SIMD
/// instructions (each multiply is a 64-bit product), so wider packets only
/// add work (docs/performance.md measures it), and compiling them would
/// more than triple the dispatched machine code a release build compiles.
/// The bytes are the same at every width, so this changes speed only; the
/// core still traces fixed point at any width for callers of [`Renderer::render_rect`](crate::render::Renderer::render_rect).
pub fn packet_used<S: Scalar>(packet: usize) -> usize {
    if S::PACKED {
        packet
    } else {
        1
    }
}

/// The number of tiles [`render_tiles`] cuts `rect` into with tiles of
/// `pitch` rows on the image's grid (for progress bars).
pub fn tile_count(rect: Rect, pitch: u32) -> u64 {
    let p = pitch.max(1) as u64;
    if rect.w == 0 || rect.h == 0 {
        return 0;
    }
    (rect.y as u64 + rect.h as u64).div_ceil(p) - rect.y as u64 / p
}

/// `r` clipped to `to`.
fn clip(r: Rect, to: Rect) -> Rect {
    let x0 = r.x.max(to.x);
    let y0 = r.y.max(to.y);
    let x1 = r.x.saturating_add(r.w).min(to.x.saturating_add(to.w));
    let y1 = r.y.saturating_add(r.h).min(to.y.saturating_add(to.h));
    Rect { x: x0, y: y0, w: x1.saturating_sub(x0), h: y1.saturating_sub(y0) }
}

/// The tiles covering `rect`, top to bottom: bands as wide as `rect`, cut
/// at the rows of the image's grid of pitch `pitch`.
fn tiles(rect: Rect, pitch: u32) -> Vec<Rect> {
    let mut out = Vec::new();
    if rect.w == 0 || rect.h == 0 {
        return out;
    }
    let y_end = rect.y + rect.h;
    let mut y = rect.y;
    while y < y_end {
        let y_next = (y / pitch).saturating_add(1).saturating_mul(pitch).min(y_end);
        out.push(Rect { x: rect.x, y, w: rect.w, h: y_next - y });
        y = y_next;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_are_bands_that_cover_a_rectangle_once_on_the_image_grid() {
        for rect in [
            Rect { x: 0, y: 0, w: 1, h: 1 },
            Rect { x: 0, y: 0, w: 31, h: 33 },
            Rect { x: 5, y: 30, w: 64, h: 64 },
            Rect { x: 31, y: 1, w: 100, h: 7 },
        ] {
            let mut seen = vec![0u8; ((rect.x + rect.w) * (rect.y + rect.h)) as usize];
            let stride = rect.x + rect.w;
            for t in tiles(rect, TILE) {
                assert!(t.y / TILE == (t.y + t.h - 1) / TILE, "{t:?} crosses the grid");
                assert!(t.x == rect.x && t.w == rect.w, "{t:?} is not a band of {rect:?}");
                for y in t.y..t.y + t.h {
                    for x in t.x..t.x + t.w {
                        seen[(y * stride + x) as usize] += 1;
                    }
                }
            }
            for y in 0..rect.y + rect.h {
                for x in 0..stride {
                    let inside = x >= rect.x && y >= rect.y;
                    assert_eq!(seen[(y * stride + x) as usize], inside as u8, "{rect:?} at ({x}, {y})");
                }
            }
        }
        assert!(tiles(Rect { x: 3, y: 3, w: 0, h: 5 }, TILE).is_empty());
        for rect in [
            Rect { x: 0, y: 0, w: 1, h: 1 },
            Rect { x: 31, y: 1, w: 100, h: 7 },
            Rect { x: 5, y: 30, w: 64, h: 64 },
            Rect { x: 2, y: 2, w: 0, h: 9 },
        ] {
            assert_eq!(tile_count(rect, TILE), tiles(rect, TILE).len() as u64, "{rect:?}");
        }
        assert_eq!(tiles(Rect { x: 0, y: 0, w: 3, h: 2 }, 1).len(), 2);
    }

    #[test]
    fn fixed_point_runs_one_ray_per_packet_and_f32_the_width_asked() {
        assert_eq!(packet_used::<Fixed32>(16), 1);
        assert_eq!(packet_used::<Fixed32>(1), 1);
        assert_eq!(packet_used::<f32>(16), 16);
        assert_eq!(packet_used::<f32>(4), 4);
        assert_eq!(best_packet(Isa::Baseline), 8);
        let scene = "v\nfrom 0 -5 0\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.1\nresolution 12 10\nl 3 -4 5\nf 1 0 0 0.5 0.5 10 0 1\ns 0 0 0 1\n";
        let base = Options { scalar: ScalarKind::Fixed32, threads: Some(1), ..Options::default() };
        let one = Image::render(scene, &Options { packet: 1, ..base }).unwrap();
        let wide = Image::render(scene, &Options { packet: 16, ..base }).unwrap();
        assert_eq!((one.packet, wide.packet), (1, 1));
        assert_eq!(one.pixels, wide.pixels);
        assert_eq!(one.stats, wide.stats);
        let f = Image::render(scene, &Options { packet: 16, ..Options::default() }).unwrap();
        assert_eq!(f.packet, 16);
    }

    #[test]
    fn size_overrides_keep_the_aspect_ratio() {
        assert_eq!(image_size(None, None, (512, 256)), (512, 256));
        assert_eq!(image_size(Some(100), None, (512, 256)), (100, 50));
        assert_eq!(image_size(None, Some(100), (512, 256)), (200, 100));
        assert_eq!(image_size(Some(7), Some(9), (512, 256)), (7, 9));
        assert_eq!(image_size(Some(1), None, (512, 1)), (1, 1));
    }

    #[test]
    fn bad_options_are_errors() {
        let scene =
            "v\nfrom 0 -5 0\nat 0 0 0\nup 0 0 1\nangle 40\nhither 1\nresolution 8 8\nf 1 1 1 1 0 0 0 0\ns 0 0 0 1\n";
        let e = Image::render(scene, &Options { packet: 3, ..Options::default() }).unwrap_err();
        assert!(matches!(e, Error::Packet(3)), "{e}");
        let e = Image::render(scene, &Options { threads: Some(0), ..Options::default() }).unwrap_err();
        assert!(matches!(e, Error::Threads), "{e}");
        let e = Image::render(scene, &Options { depth: 0, ..Options::default() }).unwrap_err();
        assert!(matches!(e, Error::Trace(TraceError::Depth { requested: 0, .. })), "{e}");
        let e = Image::render("s 0 0 0 1\n", &Options::default()).unwrap_err();
        assert!(matches!(e, Error::Scene(_)), "{e}");
        let e = Image::render("f 1 1 1 1 0 0 0 0\ns 0 0 0 1\n", &Options::default()).unwrap_err();
        assert!(matches!(e, Error::NoCamera), "{e}");
        assert_eq!(e.to_string(), "the scene has no `v` block (camera)");
    }

    #[test]
    fn same_bytes_for_every_packet_thread_count_and_accelerator() {
        let scene = include_str!("../../tests/scenes/balls-1.nff");
        let base = Options { width: Some(40), height: Some(30), packet: 1, threads: Some(1), ..Options::default() };
        let reference = Image::render(scene, &base).unwrap();
        for packet in [4, 8, 16] {
            for threads in [1, 3] {
                for accel in [AccelKind::Bvh, AccelKind::BruteForce] {
                    let o = Options { packet, threads: Some(threads), accel, ..base };
                    let image = Image::render(scene, &o).unwrap();
                    assert_eq!(image.accel, accel);
                    assert_eq!(image.pixels, reference.pixels, "{o:?}");
                    assert_eq!(image.stats.rays(), reference.stats.rays(), "{o:?}");
                }
            }
        }
    }

    /// `rect` cut out of a `width`-wide row-major image.
    fn crop(pixels: &[Rgb8], width: u32, rect: Rect) -> Vec<Rgb8> {
        let mut out = Vec::new();
        for y in rect.y..rect.y + rect.h {
            let at = (y * width + rect.x) as usize;
            out.extend_from_slice(&pixels[at..at + rect.w as usize]);
        }
        out
    }

    #[test]
    fn regions_are_the_same_rectangle_of_the_full_render_at_any_packet_width_and_thread_count() {
        let scene = include_str!("../../tests/scenes/extensions.nff");
        for sampling in [Sampling::Centre, Sampling::Grid(2), Sampling::adaptive(3, 0.1)] {
            let base = Options {
                width: Some(45),
                height: Some(37),
                packet: 1,
                threads: Some(1),
                sampling,
                ..Options::default()
            };
            let full = Image::render(scene, &base).unwrap();
            assert_eq!((full.region, full.full_size), (Rect { x: 0, y: 0, w: 45, h: 37 }, (45, 37)));
            // Unaligned to packets (4×4), tiles (32) and adaptive blocks (16).
            for (k, region) in [
                Rect { x: 0, y: 0, w: 45, h: 37 },
                Rect { x: 3, y: 5, w: 30, h: 31 },
                Rect { x: 31, y: 15, w: 14, h: 3 },
                Rect { x: 44, y: 36, w: 1, h: 1 },
                Rect { x: 17, y: 0, w: 1, h: 37 },
            ]
            .into_iter()
            .enumerate()
            {
                let packet = [1, 4, 8, 16, 8][k];
                let o = Options { region: Some(region), packet, threads: Some(1 + k % 3), ..base };
                let part = Image::render(scene, &o).unwrap();
                assert_eq!(
                    (part.width, part.height, part.region, part.full_size),
                    (region.w, region.h, region, (45, 37))
                );
                assert!(part.pixels == crop(&full.pixels, 45, region), "{sampling:?} {o:?}");
            }
        }
        let scene = include_str!("../../tests/scenes/balls-1.nff");
        for region in [
            Rect { x: 0, y: 0, w: 0, h: 3 },
            Rect { x: 10, y: 0, w: 31, h: 3 },
            Rect { x: 0, y: 30, w: 1, h: 1 },
            Rect { x: u32::MAX, y: 0, w: 2, h: 1 },
        ] {
            let o = Options { width: Some(40), height: Some(30), region: Some(region), ..Options::default() };
            let e = Image::render(scene, &o).unwrap_err();
            assert!(matches!(e, Error::Region { size: (40, 30), .. }), "{e}");
            assert!(e.to_string().contains("not inside the 40x30 image"), "{e}");
        }
    }

    #[test]
    fn anti_aliasing_gives_the_same_bytes_and_rays_at_every_packet_width_thread_count_and_isa() {
        let scene = include_str!("../../tests/scenes/extensions.nff");
        let plain = Image::render(
            scene,
            &Options { width: Some(36), height: Some(28), packet: 1, threads: Some(1), ..Options::default() },
        )
        .unwrap();
        for sampling in [
            Sampling::Grid(1),
            Sampling::Grid(3),
            Sampling::adaptive(2, 0.3),
            Sampling::adaptive(4, 0.0),
            Sampling::adaptive(3, 3.0),
        ] {
            let base = Options {
                width: Some(36),
                height: Some(28),
                packet: 1,
                threads: Some(1),
                isa: Isa::Baseline,
                sampling,
                ..Options::default()
            };
            let reference = Image::render(scene, &base).unwrap();
            for (packet, threads) in [(4, 2), (8, 1), (16, 3)] {
                for isa in Isa::ALL.into_iter().filter(|i| i.is_available()) {
                    let o = Options { packet, threads: Some(threads), isa, ..base };
                    let image = Image::render(scene, &o).unwrap();
                    assert!(image.pixels == reference.pixels, "{o:?}");
                    assert_eq!(image.stats.rays(), reference.stats.rays(), "{o:?}");
                }
            }
            let pixels = 36 * 28;
            match sampling {
                // One subsample: the centre rays exactly.
                Sampling::Grid(1) => {
                    assert_eq!((reference.pixels.clone(), reference.stats.primary), (plain.pixels.clone(), pixels))
                }
                Sampling::Grid(n) => {
                    assert_eq!(reference.stats.primary, pixels * (n as u64).pow(2));
                    assert_ne!(reference.pixels, plain.pixels);
                }
                // Threshold 3 (765): nothing differs by more; the centres
                // alone, plus the rings of the 16×16 blocks.
                Sampling::Adaptive { threshold: 765, .. } => {
                    assert_eq!(reference.pixels, plain.pixels);
                    assert!(
                        reference.stats.primary > pixels && reference.stats.primary < pixels * 3 / 2,
                        "{:?}",
                        reference.stats
                    );
                }
                _ => {
                    assert_ne!(reference.pixels, plain.pixels);
                    assert!(reference.stats.primary > pixels, "{:?}", reference.stats);
                }
            }
        }
        // Threshold 0 supersamples every pixel that differs from a neighbour
        // at all; the supersampled pixels equal those of the full grid.
        let grid = Image::render(
            scene,
            &Options { width: Some(36), height: Some(28), sampling: Sampling::Grid(4), ..Options::default() },
        )
        .unwrap();
        let adaptive = Image::render(
            scene,
            &Options { width: Some(36), height: Some(28), sampling: Sampling::adaptive(4, 0.0), ..Options::default() },
        )
        .unwrap();
        let same = grid.pixels.iter().zip(&adaptive.pixels).filter(|(a, b)| a == b).count();
        assert!(same > 36 * 28 * 9 / 10, "{same}");
        // Other AOVs ignore the sampling.
        let id = |sampling| {
            Image::render(
                scene,
                &Options { width: Some(20), height: Some(16), aov: Aov::Id, sampling, ..Options::default() },
            )
            .unwrap()
        };
        let (a, b) = (id(Sampling::Centre), id(Sampling::Grid(3)));
        assert_eq!((a.pixels, a.stats.primary), (b.pixels, b.stats.primary));
    }
}
