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
//! [`Image::render`] reads the scene into a scene on the heap (as large as
//! memory: running out of it is an error, not an abort), builds a BVH into
//! `Vec`s, picks the fastest instruction set this CPU has, renders bands of
//! [`TILE`] rows on all cores and returns the pixels with the ray counts.
//! Every choice in [`Options`] (packet width, threads, instruction set,
//! brute force or BVH) gives the same bytes; only the speed differs. The
//! tracer runs on the same slices ([`crate::scene::SceneView`],
//! [`crate::query::BvhView`]) as with the fixed-capacity scenes of the core.
//!
//! The module's parts: this file (the options, errors and the image),
//! `load` ([`LoadedScene`]: a scene loaded once and rendered any number of
//! times, as the `raypack bench` command does), `bands` ([`render_tiles`]:
//! the threaded band loop itself, for scenes built in code) and `policy`
//! (which packet width runs: [`best_packet`], [`packet_used`]).

mod bands;
mod load;
mod policy;

pub use bands::{render_tiles, tile_count, Tiling, TILE};
pub use load::{with_scene, LoadedScene, SceneInfo};
pub use policy::{best_packet, packet_used};

use crate::geom::camera::{CameraError, Rect};
use crate::geom::fixed_range::RangeError;
use crate::host::dispatch::Isa;
use crate::query::HeapBvhError;
use crate::render::{Aov, BufferTooSmall, Rgb8, Sampling};
use crate::scene::nff::NffError;
use crate::scene::SceneError;
use crate::trace::{Mode, RayStats, TraceError};
use std::time::Duration;

/// The deepest `Options::depth` accepted (the tracer's fixed stack).
pub const MAX_DEPTH: u32 = 16;
const DEPTH: usize = MAX_DEPTH as usize;

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
    /// The BVH could not be built (too many primitives, or out of memory).
    Bvh(HeapBvhError),
    /// A packet width other than 1, 4, 8 or 16.
    Packet(usize),
    /// Zero threads.
    Threads,
    /// The instruction set asked for is not available on this CPU.
    Isa(Isa),
    /// A worker thread could not be started.
    Thread(std::io::Error),
    /// The memory ran out for something other than the scene or the tree.
    Memory {
        /// What was being allocated.
        what: &'static str,
        /// The bytes asked for.
        bytes: usize,
    },
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
            Error::Memory { what, bytes } => write!(f, "out of memory for {what} ({bytes} bytes)"),
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

#[cfg(test)]
mod tests {
    use super::*;

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
        let scene = include_str!("../../../tests/scenes/balls-1.nff");
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
        let scene = include_str!("../../../tests/scenes/extensions.nff");
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
            // Unaligned to packets (4×4), bands (8 rows) and adaptive blocks (16).
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
        let scene = include_str!("../../../tests/scenes/balls-1.nff");
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
        let scene = include_str!("../../../tests/scenes/extensions.nff");
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
