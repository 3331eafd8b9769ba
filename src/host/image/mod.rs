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
//! The module's parts: `options` (the options, errors and the image),
//! `load` ([`LoadedScene`]: a scene loaded once and rendered any number of
//! times, as the `raypack bench` command does), `bands` ([`render_tiles`]:
//! the threaded band loop itself, for scenes built in code) and `policy`
//! (which packet width runs: [`best_packet`], [`packet_used`]).

mod bands;
mod load;
mod options;
mod policy;

pub use bands::{render_tiles, tile_count, Tiling, TILE};
pub use load::{with_scene, LoadedScene, SceneInfo};
pub use options::{image_size, AccelKind, Error, Image, Options, ScalarKind, MAX_DEPTH};
pub use policy::{best_packet, packet_used};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::camera::Rect;
    use crate::host::dispatch::Isa;
    use crate::render::{Aov, Rgb8, Sampling};
    use crate::trace::TraceError;

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
