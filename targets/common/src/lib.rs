//! What every raypack firmware shares: the demo scene rendered band by band
//! into a small buffer and folded into checksums, stack painting and
//! scanning, and the report printed over semihosting.
//!
//! Each board crate supplies only its start-up, its memory map, its console
//! (semihosting) and its fault handlers. The rendering is the core's own
//! [`Renderer::checksums`](raypack::render::Renderer), the very code the host
//! test `tests/firmware_checksum.rs` runs, so a checksum that differs from
//! the host's is a difference in arithmetic, not in code.
//!
//! Nothing here formats with `core::fmt`: numbers are printed digit by digit,
//! which keeps the Cortex-M0 image small and keeps `core::fmt`'s panic paths
//! out of the `panic-never` build.
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]

pub mod console;
pub mod stack;

pub use console::Console;

use raypack::camera::CameraError;
use raypack::demo::{build_demo_scene, demo_camera};
use raypack::output::ImageChecksums;
use raypack::render::{BufferTooSmall, Renderer, Rgb8};
use raypack::scene::SceneError;
use raypack::trace::{TraceError, TraceSettings, Tracer};
use raypack::Scalar;

pub use raypack::demo::DemoScene;
pub use raypack::Fixed;

/// Memory for one demo scene, of either scalar: a board that renders with
/// `f32` and then with [`Fixed`] reuses the same bytes (as big as the larger
/// scene) instead of holding both. Meant to live in a `static`, so the scene
/// is built where it lies and never copied on the stack.
pub union SceneSlot {
    f32: core::mem::ManuallyDrop<DemoScene<f32>>,
    fixed: core::mem::ManuallyDrop<DemoScene<Fixed>>,
}

impl SceneSlot {
    /// A slot holding an empty `f32` scene.
    pub const fn new() -> Self {
        SceneSlot { f32: core::mem::ManuallyDrop::new(DemoScene::new()) }
    }
    /// Empties the slot as an `f32` scene and returns it (any previous
    /// scene is forgotten; scenes own no resources).
    pub fn empty_f32(&mut self) -> &mut DemoScene<f32> {
        self.f32 = core::mem::ManuallyDrop::new(DemoScene::new());
        // SAFETY: the `f32` field was written just above.
        unsafe { &mut self.f32 }
    }
    /// Empties the slot as a [`Fixed`] scene and returns it.
    pub fn empty_fixed(&mut self) -> &mut DemoScene<Fixed> {
        self.fixed = core::mem::ManuallyDrop::new(DemoScene::new());
        // SAFETY: the `fixed` field was written just above.
        unsafe { &mut self.fixed }
    }
}

impl Default for SceneSlot {
    fn default() -> Self {
        Self::new()
    }
}

/// Image width rendered by every firmware.
pub const IMAGE_WIDTH: u32 = 160;
/// Image height rendered by every firmware.
pub const IMAGE_HEIGHT: u32 = 128;

/// Pixels in a band buffer of `rows` image rows.
pub const fn band_pixels(rows: usize) -> usize {
    IMAGE_WIDTH as usize * rows
}

/// Why a render could not run (none of these happen with the built-in
/// scene and a band buffer of at least one row; they are reported, not
/// assumed away).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    /// The scene did not fit its capacities (or was not empty).
    Scene(SceneError),
    /// The camera was rejected.
    Camera(CameraError),
    /// The tracer was rejected (depth).
    Trace(TraceError),
    /// The band buffer holds less than one row.
    Buffer(BufferTooSmall),
}

impl Failure {
    /// A short name for the report.
    pub fn name(&self) -> &'static str {
        match self {
            Failure::Scene(_) => "scene",
            Failure::Camera(_) => "camera",
            Failure::Trace(_) => "tracer",
            Failure::Buffer(_) => "band buffer",
        }
    }
}

/// Builds the core's demo scene in `scene` (which must be empty, typically
/// a `static`, so the scene is never copied on the stack), then renders it
/// at [`IMAGE_WIDTH`]×[`IMAGE_HEIGHT`] with packets of width `W`, band by
/// band through `band`, and returns the image's checksums and ray counts.
pub fn render_demo<S: Scalar, const W: usize>(scene: &mut DemoScene<S>, band: &mut [Rgb8]) -> Result<ImageChecksums, Failure> {
    build_demo_scene(scene).map_err(Failure::Scene)?;
    let camera = demo_camera::<S>(IMAGE_WIDTH, IMAGE_HEIGHT).map_err(Failure::Camera)?;
    let tracer: Tracer<'_, S> = Tracer::new(scene.view(), TraceSettings::default()).map_err(Failure::Trace)?;
    let renderer = Renderer::new(tracer, camera);
    renderer.checksums::<W>(band).map_err(Failure::Buffer)
}

/// [`render_demo`], then [`report_render`] (or [`report_failure`]) under the
/// name `scalar`; returns whether the render ran.
pub fn run<S: Scalar, const W: usize>(c: &mut impl Console, scalar: &str, scene: &mut DemoScene<S>, band: &mut [Rgb8]) -> bool {
    match render_demo::<S, W>(scene, band) {
        Ok(r) => {
            report_render(c, scalar, W, &r);
            true
        }
        Err(e) => {
            report_failure(c, scalar, &e);
            false
        }
    }
}

/// Identity of a firmware run, printed first.
#[derive(Clone, Copy, Debug)]
pub struct Board {
    /// Board (QEMU machine) name.
    pub name: &'static str,
    /// CPU and float support.
    pub cpu: &'static str,
}

/// Memory figures measured on the chip.
#[derive(Clone, Copy, Debug)]
pub struct Footprint {
    /// Deepest stack use seen by [`stack::high_water`], in bytes.
    pub stack_used: usize,
    /// Bytes of stack that were painted and watched.
    pub stack_watched: usize,
    /// Bytes of RAM taken by statics (`.data`, `.bss`, `.uninit`).
    pub static_ram: usize,
}

/// Prints the first line of a run.
pub fn report_start(c: &mut impl Console, board: &Board) {
    c.write_str("raypack firmware: board=");
    c.write_str(board.name);
    c.write_str(" cpu=");
    c.write_str(board.cpu);
    c.write_str(" image=");
    c.write_u32(IMAGE_WIDTH);
    c.write_str("x");
    c.write_u32(IMAGE_HEIGHT);
    c.write_str("\n");
}

/// Writes `scalar.key=`.
fn key(c: &mut impl Console, scalar: &str, key: &str) {
    c.write_str(scalar);
    c.write_str(".");
    c.write_str(key);
    c.write_str("=");
}

/// Prints one render's results, one `scalar.key=value` line each (the
/// scalar is `f32`, or the fixed-point type), for `scripts/firmware.sh` to
/// compare with the host's.
pub fn report_render(c: &mut impl Console, scalar: &str, width: usize, r: &ImageChecksums) {
    key(c, scalar, "width");
    c.write_u32(width as u32);
    c.write_str("\n");
    key(c, scalar, "pixels");
    c.write_u32(r.pixels);
    c.write_str("\n");
    key(c, scalar, "rays");
    c.write_u64(r.rays.total());
    c.write_str(" (primary ");
    c.write_u64(r.rays.primary);
    c.write_str(", shadow ");
    c.write_u64(r.rays.shadow);
    c.write_str(", reflected ");
    c.write_u64(r.rays.reflected);
    c.write_str(", refracted ");
    c.write_u64(r.rays.refracted);
    c.write_str(")\n");
    key(c, scalar, "rgb888");
    c.write_hex32(r.rgb888);
    c.write_str("\n");
    key(c, scalar, "rgb565-bayer4");
    c.write_hex32(r.rgb565);
    c.write_str("\n");
}

/// Prints a failed render.
pub fn report_failure(c: &mut impl Console, scalar: &str, f: &Failure) {
    c.write_str(scalar);
    c.write_str(".error=");
    c.write_str(f.name());
    c.write_str("\n");
}

/// Prints the memory figures and the closing line.
pub fn report_footprint(c: &mut impl Console, fp: &Footprint) {
    c.write_str("stack-high-water=");
    c.write_u32(fp.stack_used as u32);
    c.write_str(" bytes (");
    if fp.stack_used >= fp.stack_watched {
        c.write_str("at least: the whole watched window of ");
    } else {
        c.write_str("of ");
    }
    c.write_u32(fp.stack_watched as u32);
    c.write_str(" watched)\nstatic-ram=");
    c.write_u32(fp.static_ram as u32);
    c.write_str(" bytes\n");
}

/// The panic handler of the `panic-never` build: it calls a function that
/// exists nowhere, so the link fails (naming this symbol) if, after LTO,
/// any panic is still reachable from the firmware.
#[cfg(all(feature = "panic-never", not(test)))]
#[panic_handler]
fn panic_never(_: &core::panic::PanicInfo) -> ! {
    extern "Rust" {
        fn raypack_firmware_reachable_panic_detected_see_panic_never_build() -> !;
    }
    // SAFETY: never executes; the symbol is undefined, so the program only
    // links if this function is unreachable and removed.
    unsafe { raypack_firmware_reachable_panic_detected_see_panic_never_build() }
}
