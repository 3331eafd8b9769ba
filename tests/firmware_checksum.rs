//! The host renders the firmware's scene (the demo scene at 160×128, see
//! `targets/`) through the same core and must get the checksums recorded in
//! `targets/checksums.txt`, at packet widths 1, 4 and 8 alike.
//!
//! How the recorded values were verified: they were produced independently
//! by this host and by three firmware builds under QEMU (Cortex-M4F with
//! hardware f32, Cortex-M0 and RV32IMAC with soft-float) and agreed bit for
//! bit; `scripts/firmware.sh` re-checks the boards on every run. The image
//! itself is checked against an independent f64 tracer in
//! `tests/whitted_reference.rs`. Here the checksum is also recomputed with a
//! separate, inline FNV-1a over a full-frame render, so the band helper and
//! the hasher are checked too.

use raypack::demo::{demo_camera, demo_scene};
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

fn checksums<const W: usize>(renderer: &Renderer<'_, f32>, band_rows: usize) -> ImageChecksums {
    let mut band = vec![[0u8; 3]; 160 * band_rows];
    renderer.checksums::<W>(&mut band).unwrap()
}

#[test]
fn host_matches_recorded_firmware_checksums_at_every_width() {
    let scene = demo_scene::<f32>().unwrap();
    let camera = demo_camera::<f32>(160, 128).unwrap();
    let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
    let renderer = Renderer::new(tracer, camera);

    // The firmware configurations: width 1 with one-row bands (Cortex-M0),
    // 4 (RISC-V) and 8 (Cortex-M4F) with two-row bands; plus other band sizes.
    let one = checksums::<1>(&renderer, 1);
    let four = checksums::<4>(&renderer, 2);
    let eight = checksums::<8>(&renderer, 2);
    assert_eq!(one, four, "widths 1 and 4 differ");
    assert_eq!(one, eight, "widths 1 and 8 differ");
    assert_eq!(one, checksums::<8>(&renderer, 7), "band height changes the result");
    assert_eq!(one.pixels, 160 * 128);

    assert_eq!(format!("{:#010x}", one.rgb888), recorded("f32", "rgb888"), "RGB888 checksum");
    assert_eq!(format!("{:#010x}", one.rgb565), recorded("f32", "rgb565-bayer4"), "RGB565 checksum");
    assert_eq!(one.rays.total().to_string(), recorded("f32", "rays"), "ray count");

    // Independent recomputation: one full-frame render, FNV-1a written out.
    let mut full = vec![[0u8; 3]; 160 * 128];
    renderer.render_rect::<4>(camera.full_rect(), &mut full, &mut RayStats::default()).unwrap();
    let fnv = |bytes: &mut dyn Iterator<Item = u8>| bytes.fold(0x811c_9dc5u32, |h, b| (h ^ b as u32).wrapping_mul(16_777_619));
    let rgb888 = fnv(&mut full.iter().flat_map(|p| p.iter().copied()));
    let rgb565 = fnv(&mut full
        .iter()
        .enumerate()
        .flat_map(|(i, p)| rgb565(*p, (i % 160) as u32, (i / 160) as u32, Dither::Bayer4).to_be_bytes()));
    assert_eq!((rgb888, rgb565), (one.rgb888, one.rgb565));
}
