//! The public face of [`crate::host::image`]: what to render ([`Options`]),
//! why it failed ([`Error`]) and what came out ([`Image`]).

use super::policy::best_packet;
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
pub(super) const DEPTH: usize = MAX_DEPTH as usize;

/// The number type to trace with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ScalarKind {
    /// 32-bit IEEE float.
    #[default]
    F32,
    /// Q8.24 fixed point with 32-bit storage ([`Fixed32`](crate::num::fixed32::Fixed32)), for
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
    /// Rays per packet the render path ran with ([`packet_used`](super::packet_used)).
    pub packet: usize,
    /// Worker threads used.
    pub threads: usize,
    /// The accelerator the render ran through.
    pub accel: AccelKind,
    /// Wall time of the render (tiles only: not loading or the tree).
    pub time: Duration,
}

/// The number of worker threads for `asked` (`None`: one per core).
pub(super) fn threads(asked: Option<usize>) -> Result<usize, Error> {
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
