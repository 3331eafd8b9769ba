//! Every scene in `tests/scenes/` (the 17 SPD databases and raypack's
//! extension sample) reads without error, and the scanner's counts match the
//! scene that the reader builds.

mod common;

use common::{Big, Rng, SCENES};
use raypack::nff;
use raypack::prelude::*;
use raypack::primitives::ShapeKind;

/// Runs `f` on a thread whose stack holds a `Big` scene.
fn with_big_stack(f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new().stack_size(64 << 20).spawn(f).unwrap().join().unwrap();
}

#[test]
fn every_scene_reads_and_counts_agree() {
    with_big_stack(|| {
        for (name, text) in SCENES {
            let info = nff::scan(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            let mut scene = Big::new();
            let read = nff::parse(text, &mut scene).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(read, info, "{name}");
            let view = scene.view();
            let c = info.counts;
            assert_eq!(view.primitives().len(), c.primitives(), "{name}");
            assert_eq!(view.vertices().len(), c.vertices, "{name}");
            assert_eq!(view.materials().len(), c.materials, "{name}");
            assert_eq!(view.lights().len(), c.lights, "{name}");
            assert_eq!(view.count(ShapeKind::Sphere), c.spheres, "{name}");
            assert_eq!(view.count(ShapeKind::Polygon), c.polygons, "{name}");
            assert_eq!(view.count(ShapeKind::Patch), c.patches, "{name}");
            assert_eq!(view.count(ShapeKind::Cone), c.cones, "{name}");
            let cam = info.camera.unwrap_or_else(|| panic!("{name}: no camera"));
            assert!(cam.camera::<f32>(cam.width, cam.height).is_ok(), "{name}");
            println!(
                "{name:>10}: {:5} primitives ({} s, {} p, {} pp, {} c), {:6} vertex slots, {:2} materials, {} lights, {} degenerate, {}x{}",
                c.primitives(), c.spheres, c.polygons, c.patches, c.cones, c.vertices, c.materials, c.lights,
                scene.degenerate_polygons(), cam.width, cam.height
            );
        }
    });
}

#[test]
fn teapot_1_has_four_zero_area_polygons() {
    with_big_stack(|| {
        let mut scene = Big::new();
        nff::parse(SCENES[11].1, &mut scene).unwrap();
        assert_eq!(scene.degenerate_polygons(), 4);
    });
}

#[test]
fn gears_2_needs_more_than_a_small_scene_and_says_so() {
    with_big_stack(|| {
        let text = SCENES[3].1;
        let needs = nff::scan(text).unwrap().counts;
        let mut small: Scene<f32, 1024, 4096> = Scene::new();
        let e = nff::parse(text, &mut small).unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains(&format!("capacity 1024 exceeded (needs {})", needs.primitives()))
                || msg.contains(&format!("capacity 4096 exceeded (needs {})", needs.vertices)),
            "{msg}"
        );
    });
}

/// Seeded mutations of real files (bytes replaced, inserted, deleted, lines
/// duplicated or cut, tokens swapped for odd numbers): the reader never
/// panics, the scanner reports the same error as the reader (except
/// capacity, which only the reader has), a success builds exactly the
/// counted scene, and every message names a line inside the text.
#[test]
fn mutated_scenes_never_panic_and_scan_agrees_with_parse() {
    with_big_stack(|| {
        let mut rng = Rng(0x005e_ed0f_4e44);
        let odd = [
            "nan",
            "-inf",
            "1e39",
            "-0",
            "0",
            "-3",
            "2",
            "1e-45",
            "é",
            "#",
            "p",
            "pp",
            "v",
            "c",
            "q",
            "\r",
            "9999999999",
        ];
        let sources = [SCENES[0].1, SCENES[4].1, SCENES[5].1, SCENES[11].1, SCENES[17].1];
        for round in 0..3000 {
            let src = sources[round % sources.len()];
            let mut bytes = src.as_bytes().to_vec();
            for _ in 0..1 + rng.below(4) {
                let at = rng.below(bytes.len() as u32 + 1) as usize;
                match rng.below(6) {
                    0 if at < bytes.len() => bytes[at] = b" 019.-e\nabcpslvfqx#"[rng.below(19) as usize],
                    1 => bytes.insert(at, b" \n-0.e"[rng.below(6) as usize]),
                    2 if at < bytes.len() => {
                        let end = (at + 1 + rng.below(12) as usize).min(bytes.len());
                        bytes.drain(at..end);
                    }
                    3 => {
                        let tok = odd[rng.below(odd.len() as u32) as usize];
                        bytes.splice(at..at, tok.bytes().chain([b' ']));
                    }
                    4 => {
                        // Duplicate the line containing `at`.
                        let start = bytes[..at].iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
                        let end = bytes[at..].iter().position(|&b| b == b'\n').map_or(bytes.len(), |i| at + i + 1);
                        let line = bytes[start..end].to_vec();
                        bytes.splice(start..start, line);
                    }
                    _ => bytes.truncate(at),
                }
            }
            let Ok(text) = std::str::from_utf8(&bytes) else { continue };
            let scanned = nff::scan(text);
            let mut scene: Scene<f32, 128, 512, 32, 8> = Scene::new();
            let parsed = nff::parse(text, &mut scene);
            match (&scanned, &parsed) {
                (Ok(a), Ok(b)) => {
                    assert_eq!(a, b, "round {round}");
                    assert_eq!(scene.len(), a.counts.primitives(), "round {round}");
                    assert_eq!(scene.vertex_count(), a.counts.vertices, "round {round}");
                }
                (Err(a), Err(b)) => assert_eq!(a, b, "round {round}: {text:?}"),
                (Ok(_), Err(e)) => assert!(matches!(e.kind, nff::NffErrorKind::Capacity(_)), "round {round}: {e}"),
                (Err(e), Ok(_)) => panic!("round {round}: only the scanner failed: {e}"),
            }
            if let Err(e) = parsed {
                let lines = text.split('\n').count() as u32;
                assert!(e.line >= 1 && e.line <= lines + 1, "round {round}: {e} (text has {lines} lines)");
                assert!(!e.to_string().is_empty());
            }
        }
    });
}
