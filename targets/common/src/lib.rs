//! What every raypack firmware shares: the demo scene rendered band by band
//! into a small buffer and drawn into an embedded-graphics `DrawTarget`
//! ([`draw::render_demo_into`]: a real panel on the Raspberry Pi Pico, a
//! [`ChecksumPanel`] on the QEMU boards), the frame time ([`timing`]: a
//! [`Clock`], instructions under QEMU's `-icount`), stack painting and
//! scanning, and the report printed over semihosting.
//!
//! Each board crate supplies only its start-up, its memory map, its console
//! and fault handlers (on the Arm QEMU boards, the module `semihosting`'s,
//! defined by `arm_handlers!`), and its timer. The rendering is the
//! core's own `Renderer::draw_bands` over `Renderer::render_bands`, the band
//! loop the host's `Renderer::checksums` runs for `tests/firmware_checksum.rs`,
//! so a checksum that differs from the host's is a difference in
//! arithmetic, not in code.
//!
//! Nothing here formats with `core::fmt`: numbers are printed digit by digit,
//! which keeps the Cortex-M0 image small and keeps `core::fmt`'s panic paths
//! out of the `panic-never` build.
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]

/// The demo scene for [`Fixed32`] at 160×128, in its frame, baked on the
/// host into `static` data (`cargo run --example bake_scene` in the
/// repository's root writes this file; a host test checks that it is
/// current and renders the same bytes). What [`run_baked`] renders: no
/// scene code and no scene RAM in the image.
#[rustfmt::skip]
pub mod baked_demo;
pub mod console;
pub mod draw;
pub mod dual;
#[cfg(feature = "panel")]
pub mod panel;
#[cfg(all(feature = "ram-code", target_arch = "arm", target_os = "none"))]
pub mod ram_code;
#[cfg(all(feature = "arm-semihosting", target_arch = "arm", target_os = "none"))]
pub mod semihosting;
#[cfg(feature = "panel")]
pub mod spi_panel;
pub mod stack;
pub mod timing;

pub use console::Console;
pub use timing::{measure, Clock, TickRate};

use raypack::camera::CameraError;
use raypack::output::ImageChecksums;
use raypack::render::{BufferTooSmall, Rgb8};
use raypack::scene::SceneError;
use raypack::trace::TraceError;
use raypack::Scalar;

pub use raypack::demo::DemoScene;
pub use raypack::Fixed32;

/// Memory for the demo scene of either scalar, meant to live in a `static`
/// so the scene is built where it lies and never copied on the stack: the
/// scene itself (a board that renders with `f32` and then with [`Fixed32`]
/// reuses the same bytes), and the `f32` description the Q8.24 scene is
/// converted from ([`raypack::demo::build_demo_scene_for`]).
pub struct SceneSlot {
    scene: SceneUnion,
    described: DemoScene<f32>,
}

/// One demo scene of either scalar, in the same bytes.
union SceneUnion {
    f32: core::mem::ManuallyDrop<DemoScene<f32>>,
    fixed32: core::mem::ManuallyDrop<DemoScene<Fixed32>>,
}

impl SceneSlot {
    /// A slot holding an empty `f32` scene.
    pub const fn new() -> Self {
        SceneSlot {
            scene: SceneUnion { f32: core::mem::ManuallyDrop::new(DemoScene::new()) },
            described: DemoScene::new(),
        }
    }
}

impl Default for SceneSlot {
    fn default() -> Self {
        Self::new()
    }
}

/// A scalar the firmware renders with: its report name and its place in a
/// [`SceneSlot`].
pub trait SlotScalar: Scalar + ScalarName {
    /// Empties `slot` as a scene of this scalar (any previous scene is
    /// forgotten; scenes own no resources) and returns it with the (empty)
    /// `f32` description it may be converted from.
    fn empty(slot: &mut SceneSlot) -> (&mut DemoScene<Self>, &mut DemoScene<f32>);
}

impl SlotScalar for f32 {
    fn empty(slot: &mut SceneSlot) -> (&mut DemoScene<f32>, &mut DemoScene<f32>) {
        slot.scene.f32 = core::mem::ManuallyDrop::new(DemoScene::new());
        slot.described = DemoScene::new();
        // SAFETY: the `f32` field was written just above.
        (unsafe { &mut slot.scene.f32 }, &mut slot.described)
    }
}

impl SlotScalar for Fixed32 {
    fn empty(slot: &mut SceneSlot) -> (&mut DemoScene<Fixed32>, &mut DemoScene<f32>) {
        slot.scene.fixed32 = core::mem::ManuallyDrop::new(DemoScene::new());
        slot.described = DemoScene::new();
        // SAFETY: the `fixed32` field was written just above.
        (unsafe { &mut slot.scene.fixed32 }, &mut slot.described)
    }
}

/// The name a scalar is reported under: the first column of
/// `targets/checksums.txt` and the `SCALAR` of `SCALAR.key=value`.
pub trait ScalarName {
    /// `f32`, `fixed32`, ...
    const NAME: &'static str;
}

impl ScalarName for f32 {
    const NAME: &'static str = "f32";
}

impl ScalarName for Fixed32 {
    const NAME: &'static str = "fixed32";
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
    /// The draw target (the display) returned an error, or the image does
    /// not lie inside it (the two-core frame does not clip).
    Target,
    /// The other core failed, or handed over a band out of turn
    /// ([`dual`]).
    Peer,
}

impl Failure {
    /// A short name for the report.
    pub fn name(&self) -> &'static str {
        match self {
            Failure::Scene(_) => "scene",
            Failure::Camera(_) => "camera",
            Failure::Trace(_) => "tracer",
            Failure::Buffer(_) => "band buffer",
            Failure::Target => "display",
            Failure::Peer => "other core",
        }
    }
}

pub use draw::{
    baked_demo_renderer, demo_renderer, render_baked_demo, render_demo, render_demo_into, ChecksumPanel, Probe,
};

/// [`render_demo`] timed by `clock` (scene build, render and checksum
/// fold; not the report), then [`report_render`] (or [`report_failure`])
/// under the name `scalar`, with the time as instructions retired under
/// QEMU's `-icount shift=0` (`SCALAR.instructions=N`); returns whether the
/// render ran.
pub fn run<S: SlotScalar, const W: usize>(
    c: &mut impl Console,
    clock: &mut impl Clock,
    scalar: &str,
    slot: &mut SceneSlot,
    band: &mut [Rgb8],
) -> bool {
    run_timed(c, clock, scalar, W, || render_demo::<S, W>(slot, band))
}

/// [`run`] for the baked demo scene ([`render_baked_demo`], `fixed32`):
/// the time is the render and the checksum fold (and the view's check),
/// as there is no scene to build.
pub fn run_baked<const W: usize>(c: &mut impl Console, clock: &mut impl Clock, band: &mut [Rgb8]) -> bool {
    run_timed(c, clock, "fixed32", W, || render_baked_demo::<W>(band))
}

fn run_timed(
    c: &mut impl Console,
    clock: &mut impl Clock,
    scalar: &str,
    width: usize,
    render: impl FnOnce() -> Result<ImageChecksums, Failure>,
) -> bool {
    let rate = clock.rate();
    let (r, ticks) = measure(clock, render);
    match r {
        Ok(r) => {
            report_render(c, scalar, width, &r);
            key(c, scalar, "instructions");
            c.write_u64(rate.instructions(ticks));
            c.write_str("\n");
            true
        }
        Err(e) => {
            report_failure(c, scalar, &e);
            false
        }
    }
}

/// Checks the clock against a loop of known length ([`timing::calibrate`])
/// and prints the timer line; returns whether the clock counts
/// instructions (QEMU with `-icount shift=0` and the timer at the
/// frequency the board says).
#[cfg(all(target_os = "none", any(target_arch = "arm", target_arch = "riscv32")))]
pub fn check_clock(c: &mut impl Console, clock: &mut impl Clock, timer: &str) -> bool {
    let rate = clock.rate();
    let cal = timing::calibrate(clock);
    c.write_str("timer=");
    c.write_str(timer);
    c.write_str(" clock=");
    c.write_u32(rate.hz());
    c.write_str(" Hz resolution=");
    c.write_u64(rate.resolution());
    c.write_str(" instructions calibration=");
    c.write_u64(cal.measured);
    c.write_str(" of ");
    c.write_u64(cal.expected);
    c.write_str(if cal.ok() {
        " instructions (ok: -icount shift=0)\n"
    } else {
        " instructions: NOT COUNTING INSTRUCTIONS (run QEMU with -icount shift=0)\n"
    });
    cal.ok()
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `baked_demo.rs` is what `bake_scene` writes for the demo today (so
    /// it cannot go stale), its statics are the built scene and camera
    /// field for field, and it renders the built scene's checksums.
    #[test]
    fn baked_demo_is_current_and_renders_the_same_bytes() {
        use raypack::demo::{build_demo_scene_for, demo_camera_for};
        let mut scene = Box::new(DemoScene::<Fixed32>::new());
        let mut described = Box::new(DemoScene::<f32>::new());
        let frame = build_demo_scene_for(&mut scene, &mut described).unwrap();
        let camera = demo_camera_for::<Fixed32>(&frame, IMAGE_WIDTH, IMAGE_HEIGHT).unwrap();
        let mut source = String::new();
        raypack::scene::bake::bake_scene(&scene.view(), &camera, &mut source).unwrap();
        assert!(
            source == include_str!("baked_demo.rs"),
            "targets/common/src/baked_demo.rs is stale: run `cargo run --example bake_scene > targets/common/src/baked_demo.rs`"
        );
        let view = scene.view();
        assert_eq!(&baked_demo::PRIMITIVES[..], view.primitives());
        assert_eq!(&baked_demo::VERTICES[..], view.vertices());
        assert_eq!(&baked_demo::MATERIALS[..], view.materials());
        assert_eq!(&baked_demo::LIGHTS[..], view.lights());
        assert_eq!(baked_demo::BACKGROUND, view.background());
        assert_eq!(baked_demo::CAMERA, camera);
        let mut band = vec![[0u8; 3]; band_pixels(1)];
        let baked = render_baked_demo::<1>(&mut band).unwrap();
        let mut slot = Box::new(SceneSlot::new());
        assert_eq!(baked, render_demo::<Fixed32, 1>(&mut slot, &mut band).unwrap());
    }

    /// FNV-1a 32, written out again (not raypack's) for the tests.
    pub(crate) struct Fnv(u32);
    impl Fnv {
        pub(crate) fn new() -> Self {
            Fnv(0x811c_9dc5)
        }
        pub(crate) fn write(&mut self, bytes: &[u8]) {
            for &b in bytes {
                self.0 = (self.0 ^ b as u32).wrapping_mul(0x0100_0193);
            }
        }
        pub(crate) fn finish(&self) -> u32 {
            self.0
        }
    }

    /// The value `targets/checksums.txt` records for `scalar` and `key`.
    pub(crate) fn recorded(scalar: &str, key: &str) -> u32 {
        let text = include_str!("../../checksums.txt");
        for line in text.lines().filter(|l| !l.starts_with('#')) {
            let f: Vec<&str> = line.split_whitespace().collect();
            if f.len() == 3 && f[0] == scalar && f[1] == key {
                return match f[2].strip_prefix("0x") {
                    Some(hex) => u32::from_str_radix(hex, 16).unwrap(),
                    None => f[2].parse().unwrap(),
                };
            }
        }
        panic!("no {scalar} {key} in targets/checksums.txt")
    }

    fn checksums<S: SlotScalar, const W: usize>(rows: usize) -> ImageChecksums {
        let mut slot = Box::new(SceneSlot::new());
        let mut band = vec![[0u8; 3]; band_pixels(rows)];
        render_demo::<S, W>(&mut slot, &mut band).unwrap()
    }

    #[test]
    fn the_checksum_panel_gives_the_recorded_checksums() {
        // The widths and bands of the QEMU boards: mps2-an386 (8, 2 rows),
        // microbit (1, 1 row), riscv-virt (4, 2 rows).
        for (name, c) in [
            ("f32", checksums::<f32, 8>(2)),
            ("f32", checksums::<f32, 1>(1)),
            ("fixed32", checksums::<Fixed32, 1>(1)),
            ("fixed32", checksums::<Fixed32, 4>(2)),
            ("fixed32", checksums::<Fixed32, 8>(2)),
        ] {
            assert_eq!(c.rgb888, recorded(name, "rgb888"), "{name} rgb888");
            assert_eq!(c.rgb565, recorded(name, "rgb565-bayer4"), "{name} rgb565");
            assert_eq!(c.rays.total(), recorded(name, "rays") as u64, "{name} rays");
            assert_eq!(c.pixels, IMAGE_WIDTH * IMAGE_HEIGHT);
        }
    }

    #[test]
    fn a_band_shorter_than_a_row_is_reported() {
        let mut slot = Box::new(SceneSlot::new());
        let mut band = vec![[0u8; 3]; 10];
        assert!(matches!(render_demo::<f32, 1>(&mut slot, &mut band), Err(Failure::Buffer(_))));
    }

    /// A clock advancing 40 ticks (at 25 MHz: 1600 instructions) per reading.
    struct Fake(u64);
    impl Clock for Fake {
        fn now(&mut self) -> u64 {
            self.0 += 40;
            self.0
        }
        fn rate(&self) -> TickRate {
            TickRate::from_hz(25_000_000)
        }
    }

    /// Collects the report.
    struct Text(String);
    impl Console for Text {
        fn write_str(&mut self, s: &str) {
            self.0.push_str(s);
        }
    }

    #[test]
    fn the_report_names_each_key_after_the_scalar() {
        let mut slot = Box::new(SceneSlot::new());
        let mut band = vec![[0u8; 3]; band_pixels(2)];
        let mut out = Text(String::new());
        assert!(run::<f32, 4>(&mut out, &mut Fake(0), "fixed32", &mut slot, &mut band));
        let lines: Vec<&str> = out.0.lines().collect();
        assert!(lines.contains(&"fixed32.instructions=1600"), "{lines:?}");
        assert!(lines.contains(&"fixed32.pixels=20480"), "{lines:?}");
        assert!(lines.iter().any(|l| l.starts_with("fixed32.rays=65678 ")), "{lines:?}");
    }
}
