//! Fixed point against `f32` on the SPD scenes: every database at size
//! factor 1, and balls-2, teapot-2 and gears-2, read from `tests/scenes/` by
//! the NFF reader in both scalars, traced through the BVH, and compared by
//! PSNR (colour) and ID-AOV agreement. Images are small here (the test runs
//! unoptimized); `examples/fixed_formats.rs` renders the same comparison at
//! full size in release (the README's table).
//!
//! The `f32` renders are the reference (the tracer's `f32` path is checked
//! against an independent `f64` tracer in `tests/whitted_reference.rs`).

mod common;
use common::{agreement, psnr, render_in};
use raypack::bvh::Bvh;
use raypack::nff;
use raypack::prelude::*;

/// Quality floors from the fixed-point issue.
const MIN_PSNR_DB: f64 = 35.0;
const MIN_ID_AGREEMENT: f64 = 0.995;

/// Big enough for every file here (gears-2 is the largest).
type Big<S> = Scene<S, 16384, 65536, 64, 16>;
type Tree<S> = Bvh<S, 16384>;

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

/// Renders `text` with scalar `S` at `size × size` (colour and ID, width 8;
/// and, when `widths` is set, also widths 1 and 4, asserted bit-identical).
fn render_scene<S: Scalar>(name: &str, text: &str, size: u32, widths: bool) -> (Vec<Rgb8>, Vec<Rgb8>) {
    let mut scene = Box::new(Big::<S>::new());
    let info = nff::parse(text, &mut *scene).unwrap_or_else(|e| panic!("{name}: {e}"));
    let camera = info.camera.unwrap().camera::<S>(size, size).unwrap();
    assert!(check_scene(&scene.view(), &camera).is_ok(), "{name}: range");
    let mut bvh = Box::new(Tree::<S>::new());
    bvh.build(&scene.view()).unwrap();
    let view = scene.view().with_bvh(&bvh).unwrap();
    let settings = TraceSettings::default();
    let (color, _) = render_in::<S, 8>(&view, camera, settings, Aov::Color, 32);
    let (id, _) = render_in::<S, 8>(&view, camera, settings, Aov::Id, 32);
    if widths {
        let (c1, _) = render_in::<S, 1>(&view, camera, settings, Aov::Color, 16);
        let (c4, _) = render_in::<S, 4>(&view, camera, settings, Aov::Color, 24);
        assert!(c1 == color && c4 == color, "{name}: widths 1/4/8 differ");
    }
    (color, id)
}

#[test]
fn spd_scenes_fixed_matches_f32() {
    // A big stack for the scenes and trees (built in place, then boxed).
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(|| {
            let mut failures = Vec::new();
            for (k, (name, text, size)) in SCENES.iter().enumerate() {
                let (cf, idf) = render_scene::<f32>(name, text, *size, false);
                // Every third scene also checks widths 1/4/8 in fixed point.
                let (cx, idx) = render_scene::<Fixed>(name, text, *size, k % 3 == 0);
                let (p, a) = (psnr(&cf, &cx), agreement(&idf, &idx));
                println!("{name:>10} {size}²: PSNR {p:6.2} dB, ID agreement {:7.3} %", a * 100.0);
                if !(p >= MIN_PSNR_DB && a >= MIN_ID_AGREEMENT) {
                    failures.push(format!("{name}: PSNR {p:.2} dB, ID {:.3} %", a * 100.0));
                }
            }
            assert!(failures.is_empty(), "{failures:?}");
        })
        .unwrap()
        .join()
        .unwrap();
}
