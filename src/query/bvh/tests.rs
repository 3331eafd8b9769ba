//! Unit tests of the builder (structure properties) and of the traversal
//! (against the brute-force loops, which are the reference by definition:
//! "same bits as brute force" is the contract).

extern crate std;
use super::*;
use crate::geom::ray::{Ray, RayPacket};
use crate::geom::vec3::Vec3;
use crate::num::lanes::{Lanes, Mask};
use crate::query::{Accelerator, BruteForce, SceneMismatch};
use crate::scene::{Material, Scene};
use std::vec;

type Big = Scene<f32, 256, 1024, 4, 2>;

/// SplitMix64 (the same generator as `tests/common`).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        crate::num::test_rng::splitmix64(&mut self.0)
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next() >> 40) as f32 / (1u64 << 24) as f32)
    }
    fn vec(&mut self, lo: f32, hi: f32) -> Vec3<f32> {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
}

/// Spheres, triangles, boxes and a plane, scattered.
fn scattered(seed: u64, n: usize) -> Big {
    let mut rng = Rng(seed);
    let mut s = Big::new();
    let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
    let mut glass = Material::diffuse(Vec3::new(1.0, 1.0, 1.0));
    glass.kt = 0.7;
    let g = s.add_material(glass).unwrap();
    for i in 0..n {
        let c = rng.vec(-10.0, 10.0);
        let mat = if i % 3 == 0 { g } else { m };
        match i % 4 {
            0 | 1 => {
                s.add_sphere(c, rng.range(0.05, 1.5), mat).unwrap();
            }
            2 => {
                let tri = [c, c + rng.vec(-1.0, 1.0), c + rng.vec(-1.0, 1.0)];
                s.add_polygon(&tri, mat).unwrap();
            }
            _ => {
                if i == 3 {
                    s.add_plane(0.0, 0.0, 1.0, 12.0, mat).unwrap();
                } else {
                    s.add_box(c, c + rng.vec(0.1, 2.0), mat).unwrap();
                }
            }
        }
    }
    s
}

/// Checks the structural invariants of a built tree and returns, per
/// primitive, how many leaves (or unbounded slots) hold it.
fn check_structure<const N: usize>(scene: &SceneView<'_, f32>, bvh: &Bvh<f32, N>) {
    let tree = bvh.view();
    let stats = bvh.stats();
    let n = scene.primitives().len();
    let mut seen = vec![0u32; n];
    for &k in tree.unbounded() {
        seen[k as usize] += 1;
        assert!(
            scene.primitives()[k as usize].shape.bounds(scene.vertices()).is_none(),
            "bounded primitive {k} outside the tree"
        );
    }
    // Unbounded list in index order.
    assert!(tree.unbounded().windows(2).all(|w| w[0] < w[1]));
    let inside = |inner: (Vec3<f32>, Vec3<f32>), outer: &BvhNode<f32>| {
        inner.0.x >= outer.min.x
            && inner.0.y >= outer.min.y
            && inner.0.z >= outer.min.z
            && inner.1.x <= outer.max.x
            && inner.1.y <= outer.max.y
            && inner.1.z <= outer.max.z
    };
    let (mut nodes, mut leaves, mut max_depth) = (0u32, 0u32, 0u32);
    if !tree.nodes().is_empty() {
        let mut stack = vec![(0u32, 0u32)];
        while let Some((i, depth)) = stack.pop() {
            nodes += 1;
            max_depth = max_depth.max(depth);
            let node = tree.nodes()[i as usize];
            if node.is_leaf() {
                leaves += 1;
                let ids = tree.leaf_primitives(&node);
                assert_eq!(ids.len(), node.leaf_count() as usize);
                assert!(ids.windows(2).all(|w| w[0] < w[1]), "leaf not in index order");
                for &k in ids {
                    seen[k as usize] += 1;
                    let b = scene.primitives()[k as usize]
                        .shape
                        .bounds(scene.vertices())
                        .expect("unbounded primitive in a leaf");
                    assert!(inside(b, &node), "primitive {k} sticks out of its leaf");
                }
            } else {
                for c in [node.link(), node.link() + 1] {
                    let child = tree.nodes()[c as usize];
                    assert!(inside((child.min, child.max), &node), "child {c} outside parent {i}");
                    stack.push((c, depth + 1));
                }
            }
        }
    }
    assert!(seen.iter().all(|&c| c == 1), "every primitive exactly once: {seen:?}");
    assert_eq!(stats.nodes, nodes);
    assert_eq!(stats.leaves, leaves);
    assert_eq!(stats.depth, max_depth);
    assert!(max_depth as usize <= MAX_DEPTH);
    let bounded = n as u32 - stats.unbounded;
    assert!(nodes <= (2 * bounded).saturating_sub(1));
}

/// Random rays from inside and outside the scene, compared lane by lane
/// with brute force at widths 1, 4 and 8.
fn compare_queries(scene: &SceneView<'_, f32>, tree_view: &BvhView<'_, f32>, seed: u64, rays: usize) -> usize {
    let mut rng = Rng(seed);
    let mut hits = 0;
    for _ in 0..rays / 8 {
        let mut o = Vec3::new(Lanes::splat(0.0f32), Lanes::splat(0.0), Lanes::splat(0.0));
        let mut d = o;
        let base = rng.vec(-25.0, 25.0);
        for l in 0..8 {
            o.set_lane(l, base + rng.vec(-1.0, 1.0));
            d.set_lane(l, (rng.vec(-10.0, 10.0) - base).normalize_or_zero());
        }
        let (ray8, ok8) = RayPacket::<f32, 8>::new(o, d);
        let far = rng.range(1.0, 60.0);
        check::<8>(scene, tree_view, &ray8, ok8, far, &mut hits);
        for h in 0..2 {
            let mut ray4 = RayPacket::<f32, 4>::new(
                Vec3::new(Lanes::splat(0.0), Lanes::splat(0.0), Lanes::splat(0.0)),
                Vec3::new(Lanes::splat(1.0), Lanes::splat(0.0), Lanes::splat(0.0)),
            )
            .0;
            for l in 0..4 {
                ray4.origin.set_lane(l, ray8.origin.lane(4 * h + l));
                ray4.dir.set_lane(l, ray8.dir.lane(4 * h + l));
            }
            check::<4>(scene, tree_view, &ray4, Mask::splat(true), far, &mut hits);
        }
        for l in 0..8 {
            let r = ray8.lane(l);
            let r1 = Ray {
                origin: Vec3::new(Lanes([r.origin.x.0[0]]), Lanes([r.origin.y.0[0]]), Lanes([r.origin.z.0[0]])),
                dir: Vec3::new(Lanes([r.dir.x.0[0]]), Lanes([r.dir.y.0[0]]), Lanes([r.dir.z.0[0]])),
            };
            check::<1>(scene, tree_view, &r1, Mask::splat(true), far, &mut hits);
        }
    }
    hits
}

fn check<const W: usize>(
    scene: &SceneView<'_, f32>,
    tree: &BvhView<'_, f32>,
    ray: &RayPacket<f32, W>,
    active: Mask<W>,
    far: f32,
    hits: &mut usize,
) {
    let zero = Lanes::splat(0.0);
    assert_eq!(tree.check(scene), Ok(()));
    let a = BruteForce.closest_hit(scene, ray, zero, Lanes::splat(f32::MAX), active);
    let b = tree.closest_hit(scene, ray, zero, Lanes::splat(f32::MAX), active);
    assert_eq!(a.mask, b.mask);
    for l in 0..W {
        if a.mask.get(l) {
            *hits += 1;
            assert_eq!((a.prim[l], a.t.0[l].to_bits()), (b.prim[l], b.t.0[l].to_bits()), "lane {l}");
        }
    }
    let ta = BruteForce.transmittance(scene, ray, zero, Lanes::splat(far), active);
    let tb = tree.transmittance(scene, ray, zero, Lanes::splat(far), active);
    for l in 0..W {
        assert_eq!(ta.0[l].to_bits(), tb.0[l].to_bits(), "transmittance lane {l}");
    }
}

#[test]
fn builder_invariants_on_scattered_scenes() {
    for (seed, n) in [(1u64, 1usize), (2, 2), (3, 7), (4, 64), (5, 256)] {
        let scene = scattered(seed, n);
        let mut bvh: Bvh<f32, 256> = Bvh::new();
        let stats = bvh.build(&scene.view()).unwrap();
        assert_eq!(stats.primitives as usize, n);
        check_structure(&scene.view(), &bvh);
        // Deterministic: a second build gives the same tree.
        let mut again: Bvh<f32, 256> = Bvh::new();
        again.build(&scene.view()).unwrap();
        assert_eq!(bvh.view().nodes(), again.view().nodes());
        assert_eq!(bvh.view().order(), again.view().order());
        for settings in [
            BuildSettings { max_leaf: 1, ..BuildSettings::default() },
            BuildSettings { bins: 2, max_leaf: 16, traversal_cost: 0.1, ..BuildSettings::default() },
        ] {
            bvh.build_with(&scene.view(), &settings).unwrap();
            check_structure(&scene.view(), &bvh);
        }
    }
}

#[test]
fn queries_match_brute_force_bit_for_bit() {
    let mut total = 0;
    for (seed, n) in [(11u64, 5usize), (12, 40), (13, 256)] {
        let scene = scattered(seed, n);
        let mut bvh: Bvh<f32, 256> = Bvh::new();
        for settings in [BuildSettings::default(), BuildSettings { max_leaf: 1, ..BuildSettings::default() }] {
            bvh.build_with(&scene.view(), &settings).unwrap();
            total += compare_queries(&scene.view(), &bvh.view(), seed, 400);
        }
    }
    // The comparison would be vacuous if nothing were hit.
    assert!(total > 1000, "{total}");
}

/// Packets of 8 and 16 with a few lanes active (the ones traced one ray at
/// a time) and with many (traced as packets) answer as brute force does,
/// lane by lane, inactive lanes included.
#[test]
fn sparse_and_dense_packets_match_brute_force() {
    fn packets<const W: usize>(scene: &SceneView<'_, f32>, tree: &BvhView<'_, f32>, rng: &mut Rng) -> usize {
        let mut hits = 0;
        for _ in 0..60 {
            let mut o = Vec3::new(Lanes::splat(0.0f32), Lanes::splat(0.0), Lanes::splat(0.0));
            let mut d = o;
            let base = rng.vec(-25.0, 25.0);
            for l in 0..W {
                o.set_lane(l, base + rng.vec(-1.0, 1.0));
                d.set_lane(l, (rng.vec(-10.0, 10.0) - base).normalize_or_zero());
            }
            let (ray, ok) = RayPacket::<f32, W>::new(o, d);
            // 1 to W active lanes, at random places.
            let live = 1 + (rng.next() % W as u64) as usize;
            let mut active = Mask::splat(false);
            for _ in 0..live {
                active.set((rng.next() % W as u64) as usize, true);
            }
            let active = active & ok;
            let far = rng.range(1.0, 60.0);
            check::<W>(scene, tree, &ray, active, far, &mut hits);
        }
        hits
    }
    let mut total = 0;
    for (seed, n) in [(21u64, 9usize), (22, 120), (23, 256)] {
        let scene = scattered(seed, n);
        let mut bvh: Bvh<f32, 256> = Bvh::new();
        bvh.build(&scene.view()).unwrap();
        let mut rng = Rng(seed ^ 0x5eed);
        total += packets::<8>(&scene.view(), &bvh.view(), &mut rng);
        total += packets::<16>(&scene.view(), &bvh.view(), &mut rng);
    }
    assert!(total > 300, "{total}");
}

#[test]
fn depth_is_bounded_and_deep_leaves_still_answer() {
    // Spheres growing geometrically along x (factor 2.5): with two bins
    // every split peels off only the largest one (the next lies at 40 % of
    // the centroid range), a chain as deep as f32 can tell the centroids
    // apart (about 30 levels); the depth limit (here 12) cuts it.
    let mut s = Big::new();
    let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
    let mut x = 1.0f32;
    for _ in 0..90 {
        s.add_sphere(Vec3::new(x, 0.0, 0.0), x * 0.1, m).unwrap();
        x *= 2.5;
    }
    let mut bvh: Bvh<f32, 256> = Bvh::new();
    let stats = bvh
        .build_with(&s.view(), &BuildSettings { bins: 2, max_leaf: 1, max_depth: 12, ..BuildSettings::default() })
        .unwrap();
    assert_eq!(stats.depth, 12, "{stats:?}");
    assert!(stats.max_leaf > 4, "the depth limit made a big leaf: {stats:?}");
    check_structure(&s.view(), &bvh);
    let tree = bvh.view();
    let mut hits = 0;
    for i in 0..90 {
        let x = 2.5f32.powi(i);
        let ray = Ray::single(Vec3::new(x, 0.0, -x), Vec3::new(0.0, 0.0, 1.0)).unwrap();
        check::<1>(&s.view(), &tree, &ray, Mask::splat(true), 2.0 * x, &mut hits);
    }
    // Beyond x ≈ 1e19 the squared distances overflow f32 and both miss.
    assert!(hits >= 45, "{hits}");
}

#[test]
fn equal_distance_goes_to_the_lower_index_across_leaves() {
    // Boxes sharing the face x = 0 give the same entry distance to a ray
    // along +x (the slab kernel computes it from that face alone). Other
    // boxes in between push them into different leaves.
    let mut s = Big::new();
    let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
    s.add_box(Vec3::new(0.0, 0.0, 0.0), Vec3::new(20.0, 1.0, 1.0), m).unwrap(); // 0: long
    for i in 0..30 {
        let y = 3.0 + i as f32;
        s.add_box(Vec3::new(2.0 * i as f32, y, 0.0), Vec3::new(2.0 * i as f32 + 1.0, y + 1.0, 1.0), m).unwrap();
    }
    s.add_box(Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0), m).unwrap(); // 31: short
    let mut bvh: Bvh<f32, 256> = Bvh::new();
    bvh.build_with(&s.view(), &BuildSettings { max_leaf: 1, ..BuildSettings::default() }).unwrap();
    let tree = bvh.view();
    let leaf_of = |k: u32| tree.nodes().iter().position(|n| n.is_leaf() && tree.leaf_primitives(n).contains(&k));
    assert_ne!(leaf_of(0), leaf_of(31), "the two boxes must be in different leaves");
    let ray = Ray::single(Vec3::new(-5.0, 0.5, 0.5), Vec3::new(1.0, 0.0, 0.0)).unwrap();
    let zero = Lanes::splat(0.0);
    // The tie is real: each box alone gives the same t.
    let only = |k: usize| {
        s.view().primitives()[k].shape.roots(&[], &ray, zero, Lanes::splat(f32::MAX), Mask::splat(true)).t0.0[0]
    };
    assert_eq!(only(0).to_bits(), only(31).to_bits());
    let h = tree.closest_hit(&s.view(), &ray, zero, Lanes::splat(f32::MAX), Mask::splat(true));
    assert_eq!(h.prim[0], 0);
    assert_eq!(h.t.0[0], 5.0);
}

#[test]
fn many_transmissive_crossings_fall_back_exactly() {
    // 40 glass spheres in a row with varied Kt: more crossings than the
    // record holds, and a product whose bits depend on the order.
    let mut s: Scene<f32, 64, 8, 64, 1> = Scene::new();
    for i in 0..40 {
        let mut glass = Material::diffuse(Vec3::new(1.0, 1.0, 1.0));
        glass.kt = 0.9 + 0.0023 * i as f32;
        let g = s.add_material(glass).unwrap();
        // Built out of order so index order differs from distance order.
        let x = ((i * 17) % 40) as f32 * 2.0;
        s.add_sphere(Vec3::new(x, 0.0, 0.0), 0.5, g).unwrap();
    }
    let mut bvh: Bvh<f32, 64> = Bvh::new();
    bvh.build(&s.view()).unwrap();
    let tree = bvh.view();
    let mut hits = 0;
    for far in [5.0f32, 20.0, 50.0, 70.0, 100.0] {
        let ray = Ray::single(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0)).unwrap();
        check::<1>(&s.view(), &tree, &ray, Mask::splat(true), far, &mut hits);
    }
    let t = tree.transmittance(
        &s.view(),
        &Ray::single(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0)).unwrap(),
        Lanes::splat(0.0),
        Lanes::splat(100.0),
        Mask::splat(true),
    );
    assert!(t.0[0] > 0.0 && t.0[0] < 0.1, "{:?}", t.0);
}

#[test]
fn capacity_and_mismatch_are_errors() {
    let scene = scattered(7, 3);
    let mut small: Bvh<f32, 2> = Bvh::new();
    assert_eq!(small.build(&scene.view()), Err(BvhError { capacity: 2, needed: 3 }));
    // The failed build leaves an empty tree, which does not fit the scene.
    assert_eq!(small.view().check(&scene.view()), Err(SceneMismatch { built_for: 0, scene_has: 3 }));
    let other = scattered(8, 2);
    small.build(&other.view()).unwrap();
    assert!(small.view().check(&scene.view()).is_err());
    assert!(small.view().check(&other.view()).is_ok());
    // A tracer refuses the pairing.
    let settings = crate::trace::TraceSettings::default();
    let e = crate::trace::Tracer::<f32, _>::with_accelerator(scene.view(), small.view(), settings).err();
    assert_eq!(e, Some(crate::trace::TraceError::Accelerator(SceneMismatch { built_for: 2, scene_has: 3 })));
}

#[test]
fn empty_and_unbounded_only_scenes() {
    let mut s = Big::new();
    let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
    let mut bvh: Bvh<f32, 4> = Bvh::new();
    let stats = bvh.build(&s.view()).unwrap();
    assert_eq!(stats, BvhStats::default());
    s.add_plane(0.0, 1.0, 0.0, 0.0, m).unwrap();
    s.add_plane(0.0, 1.0, 0.0, -2.0, m).unwrap();
    let stats = bvh.build(&s.view()).unwrap();
    assert_eq!((stats.nodes, stats.unbounded), (0, 2));
    let ray = Ray::single(Vec3::new(0.0, 5.0, 0.0), Vec3::new(0.0, -1.0, 0.0)).unwrap();
    let h = bvh.view().closest_hit(&s.view(), &ray, Lanes::splat(0.0), Lanes::splat(f32::MAX), Mask::splat(true));
    assert_eq!((h.prim[0], h.t.0[0]), (1, 3.0));
}

#[test]
fn node_is_32_bytes_for_f32() {
    assert_eq!(core::mem::size_of::<BvhNode<f32>>(), 32);
}

#[test]
#[cfg(feature = "std")]
fn a_tree_with_another_scenes_camera_tiles_fails_its_check() {
    use crate::geom::camera::Camera;
    use crate::query::{HeapCameraTiles, TileSettings};
    let scene = |spheres: u32| {
        let mut s = Big::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        for k in 0..spheres {
            s.add_sphere(Vec3::new(k as f32, 0.0, -10.0), 0.5, m).unwrap();
        }
        s
    };
    let (s, more) = (scene(2), scene(3));
    let up = Vec3::new(0.0, 1.0, 0.0);
    let cam = Camera::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0), up, 90.0, 40, 40).unwrap();
    let mut tree = Bvh::<f32, 256>::new();
    tree.build(&s.view()).unwrap();
    let all = TileSettings { min_listed_percent: 0, ..TileSettings::default() };
    let own = HeapCameraTiles::build(&s.view(), &cam, all).unwrap();
    let other = HeapCameraTiles::build(&more.view(), &cam, all).unwrap();
    let (own, other) = (own.view(), other.view());
    assert!(tree.view().with_camera_tiles(&own).check(&s.view()).is_ok());
    let e = tree.view().with_camera_tiles(&other).check(&s.view());
    assert_eq!(e, Err(SceneMismatch { built_for: 3, scene_has: 2 }));
}
