//! Fixed point against `f32` on the SPD scenes, read from `tests/scenes/`
//! by the NFF reader, traced through the BVH, and compared by PSNR (colour)
//! and ID-AOV agreement:
//! - the Q8.24 `Fixed32` (scene converted into its frame at load time) on
//!   **every** SPD scene at 256×256, the size and floors;
//! - the 32.32 `Fixed` (the accurate reference) on the size-1 databases
//!   and three size-2 ones at small sizes.
//!
//! The `f32` renders are the reference (the tracer's `f32` path is checked
//! against an independent `f64` tracer in `tests/whitted_reference.rs`).

mod common;
use common::{agreement, psnr};
use raypack::image::{AccelKind, Image, Options, ScalarKind};
use raypack::prelude::*;

/// Quality floors from the fixed-point issue.
const MIN_PSNR_DB: f64 = 35.0;
const MIN_ID_AGREEMENT: f64 = 0.995;

const SCENES: [(&str, &str, u32); 14] = [
    ("balls-1", include_str!("scenes/balls-1.nff"), 96),
    ("gears-1", include_str!("scenes/gears-1.nff"), 96),
    ("jacks-1", include_str!("scenes/jacks-1.nff"), 96),
    ("lattice-1", include_str!("scenes/lattice-1.nff"), 96),
    ("mount-1", include_str!("scenes/mount-1.nff"), 96),
    ("rings-1", include_str!("scenes/rings-1.nff"), 96),
    ("shells-1", include_str!("scenes/shells-1.nff"), 96),
    ("sombrero-1", include_str!("scenes/sombrero-1.nff"), 96),
    ("teapot-1", include_str!("scenes/teapot-1.nff"), 96),
    ("tetra-1", include_str!("scenes/tetra-1.nff"), 96),
    ("tree-1", include_str!("scenes/tree-1.nff"), 96),
    ("balls-2", include_str!("scenes/balls-2.nff"), 64),
    ("teapot-2", include_str!("scenes/teapot-2.nff"), 64),
    ("gears-2", include_str!("scenes/gears-2.nff"), 64),
];

/// Renders `text` with `scalar` at `size × size` through the BVH (colour
/// and ID, packets of 8; and, when `widths` is set, also packets of 1 and
/// 4, asserted bit-identical).
fn render_scene(name: &str, text: &str, size: u32, scalar: ScalarKind, widths: bool) -> (Vec<Rgb8>, Vec<Rgb8>) {
    let base = Options {
        width: Some(size),
        height: Some(size),
        scalar,
        accel: AccelKind::Bvh,
        threads: Some(2),
        ..Options::default()
    };
    let render = |o: Options| Image::render(text, &o).unwrap_or_else(|e| panic!("{name}: {e}")).pixels;
    let color = render(base);
    let id = render(Options { aov: Aov::Id, ..base });
    if widths {
        let c1 = render(Options { packet: 1, ..base });
        let c4 = render(Options { packet: 4, ..base });
        assert!(c1 == color && c4 == color, "{name}: widths 1/4/8 differ");
    }
    (color, id)
}

/// Every SPD database in `tests/scenes` (the extension sample is raypack's
/// own, not SPD).
const SPD: [&str; 17] = [
    "balls-1",
    "balls-2",
    "gears-1",
    "gears-2",
    "jacks-1",
    "lattice-1",
    "mount-1",
    "mount-2",
    "rings-1",
    "shells-1",
    "sombrero-1",
    "teapot-1",
    "teapot-2",
    "tetra-1",
    "tetra-2",
    "tree-1",
    "tree-2",
];

#[test]
fn every_spd_scene_in_fixed32_matches_f32_at_256() {
    let mut failures = Vec::new();
    for (k, name) in SPD.iter().enumerate() {
        let text = common::SCENES.iter().find(|(n, _)| n == name).map(|(_, t)| *t).unwrap();
        let (cf, idf) = render_scene(name, text, 256, ScalarKind::F32, false);
        // Every fourth scene also checks packets of 1 and 4 in fixed32.
        let (cx, idx) = render_scene(name, text, 256, ScalarKind::Fixed32, k % 4 == 0);
        let (p, a) = (psnr(&cf, &cx), agreement(&idf, &idx));
        println!("{name:>10} 256² fixed32: PSNR {p:6.2} dB, ID agreement {:7.3} %", a * 100.0);
        if !(p >= MIN_PSNR_DB && a >= MIN_ID_AGREEMENT) {
            failures.push(format!("{name}: PSNR {p:.2} dB, ID {:.3} %", a * 100.0));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

/// `text` read into a scene of scalar `S` in the file's own units (no frame:
/// what the 32.32 `Fixed` traces), rendered through its BVH at
/// `size × size` (colour and ID, packets of 8).
fn render_library<S: Scalar>(name: &str, text: &str, size: u32) -> (Vec<Rgb8>, Vec<Rgb8>) {
    let mut scene = Box::new(common::BigOf::<S>::new());
    let info = raypack::nff::parse(text, &mut *scene).unwrap_or_else(|e| panic!("{name}: {e}"));
    let camera = info.camera.unwrap().camera::<S>(size, size).unwrap();
    scene.view().check_range(camera.eye()).unwrap_or_else(|e| panic!("{name}: {e}"));
    let mut bvh = Box::new(Bvh::<S, 16384>::new());
    bvh.build(&scene.view()).unwrap();
    let settings = TraceSettings::default();
    let (color, _) = common::render_with(bvh.view(), &scene.view(), camera, settings, Aov::Color, 32, 8);
    let (id, _) = common::render_with(bvh.view(), &scene.view(), camera, settings, Aov::Id, 32, 8);
    (color, id)
}

/// The 32.32 `Fixed` (a library type, not in the command line), the accurate
/// fixed-point reference, traced in the files' own units.
#[test]
fn spd_scenes_fixed_matches_f32() {
    // A big stack: the scenes are built in place, then boxed.
    std::thread::Builder::new().stack_size(256 << 20).spawn(spd_scenes_fixed).unwrap().join().unwrap();
}

fn spd_scenes_fixed() {
    let mut failures = Vec::new();
    for (name, text, size) in SCENES.iter() {
        let (cf, idf) = render_library::<f32>(name, text, *size);
        let (cx, idx) = render_library::<Fixed>(name, text, *size);
        let (p, a) = (psnr(&cf, &cx), agreement(&idf, &idx));
        println!("{name:>10} {size}²: PSNR {p:6.2} dB, ID agreement {:7.3} %", a * 100.0);
        if !(p >= MIN_PSNR_DB && a >= MIN_ID_AGREEMENT) {
            failures.push(format!("{name}: PSNR {p:.2} dB, ID {:.3} %", a * 100.0));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}
