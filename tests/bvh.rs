//! The BVH gives the same bytes as brute force: random scenes of every
//! primitive kind (tests/common), images at widths 1, 4 and 8 (colour,
//! id, normal and depth AOVs, Whitted and cast), and per-ray closest hits and
//! shadow transmittances, each compared bit for bit with brute force
//! (`raypack::query::BruteForce`, the reference by definition).

mod common;
use common::*;
use raypack::lanes::{Lanes, Mask};
use raypack::prelude::*;
use raypack::ray::RayPacket;

#[test]
fn random_scene_images_match_brute_force_at_every_width() {
    let mut rng = Rng(0xB5B5);
    let mut lit_pixels = 0;
    for case in 0..12 {
        let scene = random_scene(&mut rng, 20 + case * 2);
        let mut bvh: Bvh<f32, 48> = Bvh::new();
        bvh.build(&scene.view()).unwrap();
        let view = scene.view();
        let camera = random_camera(&mut rng, 33, 21);
        for mode in [Mode::Whitted, Mode::Cast] {
            let settings = TraceSettings { mode, max_depth: 1 + rng.below(6), ..TraceSettings::default() };
            for aov in [Aov::Color, Aov::Id, Aov::Normal, Aov::Depth] {
                if mode == Mode::Cast && aov != Aov::Color {
                    continue;
                }
                let (reference, ref_stats) = render::<4>(&view, camera, settings, aov, 16);
                let (i1, s1) = render_with(bvh.view(), &view, camera, settings, aov, 7, 1);
                let (i4, s4) = render_with(bvh.view(), &view, camera, settings, aov, 16, 4);
                let (i8, s8) = render_with(bvh.view(), &view, camera, settings, aov, 64, 8);
                assert!(
                    reference == i1 && reference == i4 && reference == i8,
                    "case {case}: {mode:?} {aov:?}: BVH image differs"
                );
                assert_eq!(ref_stats.rays(), s1.rays());
                assert_eq!(ref_stats.rays(), s4.rays());
                assert_eq!(ref_stats.rays(), s8.rays());
                if aov == Aov::Id {
                    lit_pixels += reference.iter().filter(|p| **p != [0, 0, 0]).count();
                }
            }
        }
    }
    // Only meaningful if the scenes are in view.
    assert!(lit_pixels > 12 * 50, "{lit_pixels}");
}

/// A packet of `W` rays from lanes of `o`/`d`.
fn packet<const W: usize>(o: &[Vec3<f32>], d: &[Vec3<f32>]) -> (RayPacket<f32, W>, Mask<W>) {
    let z = Lanes::splat(0.0f32);
    let mut org = Vec3::new(z, z, z);
    let mut dir = org;
    for i in 0..W {
        org.set_lane(i, o[i]);
        dir.set_lane(i, d[i]);
    }
    RayPacket::new(org, dir)
}

fn compare<const W: usize>(
    scene: &SceneView<'_, f32>,
    tree: &BvhView<'_, f32>,
    o: &[Vec3<f32>],
    d: &[Vec3<f32>],
    far: f32,
) -> usize {
    let (ray, active) = packet::<W>(o, d);
    let zero = Lanes::splat(0.0);
    let inf = Lanes::splat(f32::MAX);
    let a = BruteForce.closest_hit(scene, &ray, zero, inf, active);
    let b = tree.closest_hit(scene, &ray, zero, inf, active);
    assert_eq!(a.mask, b.mask);
    let mut hits = 0;
    for l in 0..W {
        if a.mask.get(l) {
            hits += 1;
            assert_eq!((a.prim[l], a.t.0[l].to_bits()), (b.prim[l], b.t.0[l].to_bits()));
        }
    }
    let ta = BruteForce.transmittance(scene, &ray, zero, Lanes::splat(far), active);
    let tb = tree.transmittance(scene, &ray, zero, Lanes::splat(far), active);
    assert_eq!(ta.0.map(f32::to_bits), tb.0.map(f32::to_bits));
    hits
}

#[test]
fn random_rays_hit_the_same_primitive_at_the_same_distance() {
    let mut rng = Rng(0x5EED);
    let mut hits = 0;
    let mut partial = 0;
    for case in 0..16 {
        let scene = random_scene(&mut rng, 40);
        let mut bvh: Bvh<f32, 48> = Bvh::new();
        let settings = BuildSettings { max_leaf: 1 + case % 4, ..BuildSettings::default() };
        bvh.build_with(&scene.view(), &settings).unwrap();
        let tree = bvh.view();
        for _ in 0..64 {
            // Coherent bundles (a packet's rays start close together and
            // point at nearby targets), from inside and outside the scene.
            let base = rng.vec(-12.0, 12.0);
            let aim = rng.vec(-3.0, 3.0);
            let o: Vec<_> = (0..8).map(|_| base + rng.vec(-0.3, 0.3)).collect();
            let d: Vec<_> = o.iter().map(|&p| aim + rng.vec(-0.5, 0.5) - p).collect();
            let far = rng.range(0.5, 30.0);
            hits += compare::<8>(&scene.view(), &tree, &o, &d, far);
            hits += compare::<4>(&scene.view(), &tree, &o[..4], &d[..4], far);
            hits += compare::<1>(&scene.view(), &tree, &o[..1], &d[..1], far);
            // Transmittance strictly between 0 and 1 exercises the ordered product.
            let (ray, active) = packet::<8>(&o, &d);
            let t = tree.transmittance(&scene.view(), &ray, Lanes::splat(0.0), Lanes::splat(far), active);
            partial += t.0.iter().filter(|&&v| v > 0.0 && v < 1.0).count();
        }
    }
    assert!(hits > 4000, "{hits}");
    assert!(partial > 100, "{partial}");
}

/// The demo scene (every primitive kind, mirror and glass) in `f32` and in
/// fixed point: the BVH image equals the brute-force image at widths 1, 4, 8.
#[test]
fn demo_scene_matches_brute_force_in_f32_and_fixed_point() {
    fn check<S: Scalar>() {
        let scene = raypack::demo::demo_scene::<S>().unwrap();
        let mut bvh: Bvh<S, 16> = Bvh::new();
        bvh.build(&scene.view()).unwrap();
        let view = scene.view();
        let camera = raypack::demo::demo_camera::<S>(48, 36).unwrap();
        let settings = TraceSettings::default();
        for aov in [Aov::Color, Aov::Id] {
            let (reference, rs) = render_in::<S, 8>(&view, camera, settings, aov, 64);
            for (img, st) in [
                render_with(bvh.view(), &view, camera, settings, aov, 7, 1),
                render_with(bvh.view(), &view, camera, settings, aov, 16, 4),
                render_with(bvh.view(), &view, camera, settings, aov, 64, 8),
            ] {
                assert!(img == reference, "{aov:?}: BVH image differs");
                assert_eq!(st.rays(), rs.rays());
            }
        }
    }
    check::<f32>();
    check::<Fixed>();
}
