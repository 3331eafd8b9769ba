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
use raypack::dispatch::{self, Isa};
use raypack::prelude::*;

/// Renders `renderer`'s whole image in tiles of `tile` pixels with width
/// `W`, either directly (`isa = None`) or through the dispatcher.
fn render<const W: usize>(renderer: &Renderer<'_, f32>, isa: Option<Isa>, tile: u32) -> (Vec<Rgb8>, RayStats) {
    let (w, h) = (renderer.camera.width(), renderer.camera.height());
    let mut img = vec![[0u8; 3]; (w * h) as usize];
    let mut stats = RayStats::default();
    let mut buf = vec![[0u8; 3]; (tile * tile) as usize];
    let mut y = 0;
    while y < h {
        let mut x = 0;
        while x < w {
            let rect = Rect { x, y, w: tile.min(w - x), h: tile.min(h - y) };
            match isa {
                None => renderer.render_rect::<W>(rect, &mut buf, &mut stats).unwrap(),
                Some(isa) => dispatch::render_rect::<f32, 8, W>(isa, renderer, rect, &mut buf, &mut stats).unwrap(),
            }
            for j in 0..rect.h {
                for i in 0..rect.w {
                    img[((y + j) * w + x + i) as usize] = buf[(j * rect.w + i) as usize];
                }
            }
            x += tile;
        }
        y += tile;
    }
    (img, stats)
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
    check_against(renderer, render::<1>(renderer, None, 16), what)
}

/// Every dispatched render of `renderer`, at every width, equals `reference`
/// (its image and the rays it traced).
fn check_against(renderer: &Renderer<'_, f32>, (reference, ref_stats): (Vec<Rgb8>, RayStats), what: &str) {
    for isa in isas() {
        for (w, (img, stats)) in [
            (1, render::<1>(renderer, Some(isa), 16)),
            (4, render::<4>(renderer, Some(isa), 16)),
            (8, render::<8>(renderer, Some(isa), 16)),
            (16, render::<16>(renderer, Some(isa), 16)),
        ] {
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
    let (img, _) = render::<8>(&renderer, None, 16);
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
            let renderer = Renderer { tracer, camera, aov };
            check(&renderer, &format!("case {case} {aov:?}"));
        }
    }
}

#[test]
fn every_isa_renders_bvh_scenes_to_the_bytes_of_brute_force() {
    // With a tree attached, the dispatcher also switches the BVH leaf tests
    // (compiled apart from the inlined path, `raypack::bvh::isa`) to its
    // instruction set. Reference: the plain render without a tree.
    let mut rng = Rng(7013);
    for case in 0..6 {
        let scene = random_scene(&mut rng, 14 + case * 5);
        let camera = random_camera(&mut rng, 27, 21);
        let mut bvh: Box<Bvh<f32, 64>> = Box::new(Bvh::new());
        bvh.build(&scene.view()).unwrap();
        for aov in [Aov::Color, Aov::Id] {
            let plain: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
            let brute_force = render::<1>(&Renderer { tracer: plain, camera, aov }, None, 16);
            let tree: Tracer<f32> = Tracer::new(scene.view().with_bvh(&bvh).unwrap(), TraceSettings::default()).unwrap();
            check_against(&Renderer { tracer: tree, camera, aov }, brute_force, &format!("bvh case {case} {aov:?} (vs brute force)"));
        }
    }
}

#[test]
fn isa_views_carry_the_leaf_tests_of_their_isa() {
    // The token that picks the compiled copy of the BVH leaf tests follows
    // the instruction set actually used (baseline where the CPU lacks one).
    let mut rng = Rng(5);
    let scene = random_scene(&mut rng, 10);
    let mut bvh: Box<Bvh<f32, 16>> = Box::new(Bvh::new());
    bvh.build(&scene.view()).unwrap();
    let view = scene.view().with_bvh(&bvh).unwrap();
    assert_eq!(view.bvh().unwrap().leaf_isa().name(), "plain");
    for isa in Isa::ALL {
        let expect = match isa.effective() {
            Isa::Baseline => "plain",
            other => other.name(),
        };
        assert_eq!(isa.view(view).bvh().unwrap().leaf_isa().name(), expect, "{isa}");
        assert_eq!(isa.leaf_isa().name(), expect, "{isa}");
    }
    // A view without a tree stays without one.
    assert!(Isa::best().view(scene.view()).bvh().is_none());
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
