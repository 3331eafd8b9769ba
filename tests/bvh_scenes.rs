//! Every scene in `tests/scenes/` (the 17 SPD databases and the extension
//! sample) renders to the same bytes with and without the BVH. The reference
//! is brute force (`raypack::query::BruteForce`), the contract by
//! definition. Small images keep the dev-profile test time modest; the BVH
//! images are rendered at widths 1 (a band), 4 and 8 (whole image).

mod common;
use common::*;
use raypack::nff;
use raypack::prelude::*;

type BigBvh = Bvh<f32, 16384>;

/// Image size: small, the scenes are large.
const SIZE: u32 = 64;

#[test]
fn every_scene_renders_identically_with_and_without_the_bvh() {
    std::thread::Builder::new()
        .stack_size(64 << 20)
        .spawn(|| {
            let mut scene: Box<Big> = Box::new(Big::new());
            let mut bvh: Box<BigBvh> = Box::new(BigBvh::new());
            for (name, text) in SCENES {
                *scene = Big::new();
                let info = nff::parse(text, &mut *scene).unwrap_or_else(|e| panic!("{name}: {e}"));
                let stats = bvh.build(&scene.view()).unwrap();
                assert_eq!(stats.primitives as usize, scene.len());
                let view = scene.view();
                let camera = info.camera.expect("SPD scenes have a camera").camera::<f32>(SIZE, SIZE).unwrap();
                let settings = TraceSettings::default();
                let (reference, ref_stats) = render::<8>(&view, camera, settings, Aov::Color, SIZE);
                let (i8, s8) = render_with(bvh.view(), &view, camera, settings, Aov::Color, SIZE, 8);
                assert!(reference == i8, "{name}: BVH image differs (width 8)");
                assert_eq!(ref_stats.rays(), s8.rays(), "{name}");
                let (i4, _) = render_with(bvh.view(), &view, camera, settings, Aov::Color, 16, 4);
                assert!(reference == i4, "{name}: BVH image differs (width 4)");
                // Width 1 is slow in the dev profile: a band through the middle.
                let (i1, _) = render_band::<1>(&view, bvh.view(), camera, settings, SIZE / 2 - 4, 8);
                let band = &reference[((SIZE / 2 - 4) * SIZE) as usize..((SIZE / 2 + 4) * SIZE) as usize];
                assert!(band == &i1[..], "{name}: BVH image differs (width 1)");
                // The comparison means something only if the scene is in view
                // (ids are primitive + 1, 0 for the background).
                let (ids, _) = render::<8>(&view, camera, settings, Aov::Id, SIZE);
                assert!(
                    ids.iter().filter(|p| **p != [0, 0, 0]).count() > (SIZE * SIZE / 20) as usize,
                    "{name}: scene not in view"
                );
            }
        })
        .unwrap()
        .join()
        .unwrap();
}

/// Rows `y .. y + h` of the image, width `W`.
fn render_band<const W: usize>(
    scene: &SceneView<'_, f32>,
    tree: BvhView<'_, f32>,
    camera: Camera<f32>,
    settings: TraceSettings<f32>,
    y: u32,
    h: u32,
) -> (Vec<Rgb8>, RayStats) {
    let tracer = Tracer::<f32, _>::with_accelerator(*scene, tree, settings).unwrap();
    let renderer = Renderer { tracer, camera, aov: Aov::Color, sampling: Sampling::Centre };
    let mut buf = vec![[0u8; 3]; (camera.width() * h) as usize];
    let mut stats = RayStats::default();
    renderer.render_rect::<W>(Rect { x: 0, y, w: camera.width(), h }, &mut buf, &mut stats).unwrap();
    (buf, stats)
}
