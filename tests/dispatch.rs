//! The instruction-set dispatcher changes speed, never bytes: every available
//! instruction set renders the demo scene and random scenes (every primitive
//! kind, mirrors, glass, all AOVs) at widths 1, 4, 8 and 16 to exactly the bytes
//! of the plain, undispatched baseline render (`Renderer::render_rect`
//! called directly). The reference is therefore not produced by the code
//! under test: it is the ordinary build of the same generic code, whose own
//! correctness `tests/whitted_reference.rs` checks against an f64 tracer.
//!
//! An instruction set this CPU lacks is skipped with a printed reason
//! (`cargo test --test dispatch -- --nocapture` shows it); the baseline
//! always runs.

mod common;
use common::*;
use raypack::demo::{demo_camera, demo_scene};
use raypack::dispatch::Isa;
use raypack::image::{render_tiles, Tiling};
use raypack::prelude::*;

/// `renderer`'s whole image with packets of one ray, by one plain
/// `render_rect` call (no dispatcher, no tiles): the reference.
fn plain<A: Accelerator<f32>>(renderer: &Renderer<'_, f32, A>) -> (Vec<Rgb8>, RayStats) {
    let rect = renderer.camera.full_rect();
    let mut img = vec![[0u8; 3]; (rect.w * rect.h) as usize];
    let mut stats = RayStats::default();
    renderer.render_rect::<1>(rect, &mut img, &mut stats).unwrap();
    (img, stats)
}

/// `renderer`'s whole image through the dispatcher: tiles of 16 pixels,
/// packets of `packet` rays compiled for `isa`.
fn dispatched<A: Accelerator<f32> + Sync>(
    renderer: &Renderer<'_, f32, A>,
    packet: usize,
    isa: Isa,
) -> (Vec<Rgb8>, RayStats) {
    let tiling = Tiling { packet, isa, threads: 1, tile: 16 };
    render_tiles(renderer, renderer.camera.full_rect(), &tiling, &|| {}).unwrap()
}

/// The instruction sets to compare, printing why any is skipped.
fn isas() -> Vec<Isa> {
    let mut v = Vec::new();
    for isa in Isa::ALL {
        if isa.is_available() {
            println!("dispatch test: {isa} runs on this CPU");
            v.push(isa);
        } else {
            println!("dispatch test: {isa} SKIPPED: this CPU does not support it");
        }
    }
    v
}

/// Every dispatched render equals the direct baseline render, at every width.
fn check(renderer: &Renderer<'_, f32>, what: &str) {
    check_against(renderer, plain(renderer), what)
}

/// Every dispatched render of `renderer`, at every width, equals `reference`
/// (its image and the rays it traced).
fn check_against<A: Accelerator<f32> + Sync>(
    renderer: &Renderer<'_, f32, A>,
    (reference, ref_stats): (Vec<Rgb8>, RayStats),
    what: &str,
) {
    for isa in isas() {
        for w in [1, 4, 8, 16] {
            let (img, stats) = dispatched(renderer, w, isa);
            assert!(img == reference, "{what}: {isa} width {w} differs from the reference");
            assert_eq!(stats.rays(), ref_stats.rays(), "{what}: {isa} width {w} traced different rays");
        }
    }
}

#[test]
fn every_isa_renders_the_demo_scene_to_the_same_bytes() {
    let scene = demo_scene::<f32>().unwrap();
    let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
    let renderer = Renderer::new(tracer, demo_camera(48, 36).unwrap());
    check(&renderer, "demo");
    // The image must show the scene, or the comparison proves little.
    let (img, _) = plain(&renderer);
    let distinct: std::collections::HashSet<Rgb8> = img.iter().copied().collect();
    assert!(distinct.len() > 50, "demo image has only {} colours", distinct.len());
}

#[test]
fn every_isa_renders_random_scenes_to_the_same_bytes() {
    let mut rng = Rng(2026);
    for case in 0..8 {
        let scene = random_scene(&mut rng, 12 + case * 3);
        let camera = random_camera(&mut rng, 29, 19);
        for aov in [Aov::Color, Aov::Depth, Aov::Normal, Aov::Id] {
            let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
            let renderer = Renderer { tracer, camera, aov, sampling: Sampling::Centre };
            check(&renderer, &format!("case {case} {aov:?}"));
        }
    }
}

#[test]
fn every_isa_renders_bvh_scenes_to_the_bytes_of_brute_force() {
    // With a tree, the dispatcher compiles the tree's queries (traversal
    // and leaf tests) for its instruction set too. Reference: the plain
    // render without a tree.
    let mut rng = Rng(7013);
    for case in 0..6 {
        let scene = random_scene(&mut rng, 14 + case * 5);
        let camera = random_camera(&mut rng, 27, 21);
        let mut bvh: Box<Bvh<f32, 64>> = Box::new(Bvh::new());
        bvh.build(&scene.view()).unwrap();
        for aov in [Aov::Color, Aov::Id] {
            let plain: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
            let brute_force = self::plain(&Renderer { tracer: plain, camera, aov, sampling: Sampling::Centre });
            let tree = Tracer::<f32, _>::with_accelerator(scene.view(), bvh.view(), TraceSettings::default()).unwrap();
            check_against(
                &Renderer { tracer: tree, camera, aov, sampling: Sampling::Centre },
                brute_force,
                &format!("bvh case {case} {aov:?} (vs brute force)"),
            );
        }
    }
}

#[test]
fn the_isa_used_follows_the_scalar_and_packet() {
    // Packets of 8 and 16 f32 lanes run the instruction set asked for (the
    // baseline where the CPU lacks it); narrower packets and fixed point
    // always run the baseline copy.
    for isa in Isa::ALL {
        assert_eq!(isa.used_for::<f32>(8), isa.effective(), "{isa}");
        assert_eq!(isa.used_for::<f32>(16), isa.effective(), "{isa}");
        assert_eq!(isa.used_for::<f32>(4), Isa::Baseline, "{isa}");
        assert_eq!(isa.used_for::<Fixed>(16), Isa::Baseline, "{isa}");
    }
}

#[test]
fn this_machine_runs_the_avx2_path_if_it_has_avx2() {
    // Not a speed test: only that detection and the dispatcher agree, so the
    // comparisons above really ran the AVX2 copy where the CPU has one.
    #[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
    {
        let has = std::is_x86_feature_detected!("avx2");
        assert_eq!(Isa::Avx2.is_available(), has);
        // The best copy is AVX2 or, where the CPU also has it, AVX-512.
        assert_eq!(Isa::best() != Isa::Baseline, has);
        assert_eq!(Isa::Avx2.effective(), if has { Isa::Avx2 } else { Isa::Baseline });
        println!("dispatch test: avx2 detected: {has}");
    }
}
