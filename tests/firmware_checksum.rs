//! The host renders the firmware's scene (the demo scene at 160×128, see
//! `targets/`) through the same core and must get the checksums recorded in
//! `targets/checksums.txt`, at packet widths 1, 4 and 8 alike, for `f32` and
//! for the Q8.24 `Fixed32` scalar (its scene built in `f32` and converted
//! into its frame, as the firmware builds it).
//!
//! How the recorded values were verified: they were produced independently
//! by this host and by the firmware builds under QEMU (f32: Cortex-M4F with
//! hardware f32, Cortex-M0 and RV32IMAC with soft-float; Q8.24 fixed point:
//! Cortex-M4F, Cortex-M0 and RV32IMAC) and agreed bit for bit; `scripts/firmware.sh`
//! re-checks the boards on every run. The f32 image itself is checked
//! against an independent f64 tracer in `tests/whitted_reference.rs`, the
//! fixed-point one against f32 in `tests/fixed_point.rs`. Here the checksum
//! is also recomputed with a separate, inline FNV-1a over a full-frame
//! render, so the band helper and the hasher are checked too.

use raypack::demo::{build_demo_scene_for, demo_camera_for, DemoScene};
use raypack::output::{rgb565, Dither, ImageChecksums};
use raypack::prelude::*;

const RECORDED: &str = include_str!("../targets/checksums.txt");

fn recorded(scalar: &str, key: &str) -> String {
    RECORDED
        .lines()
        .filter(|l| !l.starts_with('#'))
        .find_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.len() == 3 && f[0] == scalar && f[1] == key).then(|| f[2].to_string())
        })
        .unwrap_or_else(|| panic!("targets/checksums.txt has no `{scalar} {key}` line"))
}

fn checksums<S: Scalar, const W: usize>(renderer: &Renderer<'_, S>, band_rows: usize) -> ImageChecksums {
    let mut band = vec![[0u8; 3]; 160 * band_rows];
    renderer.checksums::<W>(&mut band).unwrap()
}

fn check<S: Scalar>(name: &str) -> Vec<Rgb8> {
    let mut scene = Box::new(DemoScene::<S>::new());
    let mut described = Box::new(DemoScene::<f32>::new());
    let frame = build_demo_scene_for(&mut scene, &mut described).unwrap();
    let camera = demo_camera_for::<S>(&frame, 160, 128).unwrap();
    let tracer: Tracer<S> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
    let renderer = Renderer::new(tracer, camera);

    // The firmware configurations: width 1 with one-row bands (Cortex-M0),
    // 4 (RISC-V) and 8 (Cortex-M4F) with two-row bands; plus another band size.
    let one = checksums::<S, 1>(&renderer, 1);
    let (four, eight, eight_tall) =
        (checksums::<S, 4>(&renderer, 2), checksums::<S, 8>(&renderer, 2), checksums::<S, 8>(&renderer, 7));
    assert!(one.same_render(&four), "{name}: widths 1 and 4 differ: {one:?} {four:?}");
    assert!(one.same_render(&eight), "{name}: widths 1 and 8 differ: {one:?} {eight:?}");
    assert!(eight.same_render(&eight_tall), "{name}: band height changes the result: {eight:?} {eight_tall:?}");
    assert_eq!(one.pixels, 160 * 128);

    assert_eq!(format!("{:#010x}", one.rgb888), recorded(name, "rgb888"), "{name}: RGB888 checksum");
    assert_eq!(format!("{:#010x}", one.rgb565), recorded(name, "rgb565-bayer4"), "{name}: RGB565 checksum");
    assert_eq!(one.rays.total().to_string(), recorded(name, "rays"), "{name}: ray count");

    // Independent recomputation: one full-frame render, FNV-1a written out.
    let mut full = vec![[0u8; 3]; 160 * 128];
    renderer.render_rect::<4>(camera.full_rect(), &mut full, &mut RayStats::default()).unwrap();
    let fnv = |bytes: &mut dyn Iterator<Item = u8>| {
        bytes.fold(0x811c_9dc5u32, |h, b| (h ^ b as u32).wrapping_mul(16_777_619))
    };
    let rgb888 = fnv(&mut full.iter().flat_map(|p| p.iter().copied()));
    let rgb565 = fnv(&mut full
        .iter()
        .enumerate()
        .flat_map(|(i, p)| rgb565(*p, (i % 160) as u32, (i / 160) as u32, Dither::Bayer4).to_be_bytes()));
    assert_eq!((rgb888, rgb565), (one.rgb888, one.rgb565), "{name}: independent FNV-1a");
    full
}

#[test]
fn host_matches_recorded_firmware_checksums_at_every_width() {
    let f = check::<f32>("f32");
    let x = check::<raypack::Fixed32>("fixed32");
    // The two scalars give nearly the same picture (see tests/fixed_point.rs),
    // so few pixels differ, by little; report it.
    let differing: Vec<usize> = (0..f.len()).filter(|&i| f[i] != x[i]).collect();
    let max = differing
        .iter()
        .flat_map(|&i| (0..3).map(|c| (f[i][c] as i32 - x[i][c] as i32).abs()).collect::<Vec<_>>())
        .max();
    eprintln!("f32 vs fixed32: {} of {} pixels differ, by at most {:?}", differing.len(), f.len(), max);
}
