//! Screen culling (src/query/cull.rs) changes no byte: seeded random scenes
//! and cameras rendered by brute force with culling (what `Renderer` does
//! for `BruteForce`) and without (the same brute force behind an
//! accelerator that takes no candidates), compared byte for byte, for
//! `f32`, `Fixed32` and `Fixed`, packet widths 1, 4, 8 and 16, the colour
//! (Whitted and cast) and ID AOVs, supersampling, cameras inside objects,
//! beside grazing spheres, lights inside and beside primitives, and tiny
//! and huge scales. Culled renders cull camera rays (`ScreenCull`) and, in
//! Whitted colour renders, shadow rays (`ShadowCull`). The same cases
//! rendered through a BVH, and through a BVH with camera tiles
//! (`CameraTiles`, tiles of 4 × 4 pixels), give the same bytes too.

mod common;
use common::*;
use raypack::camera::packet_shape;
use raypack::lanes::{Lanes, Mask};
use raypack::prelude::*;
use raypack::query::{HeapBvh, HeapCameraTiles, Hit, ScreenCull, ShadowCull, TileSettings};
use raypack::ray::RayPacket;
use raypack::{Fixed, Fixed32};

/// Brute force that ignores candidates (the trait's default): the
/// reference the culled renders must equal.
#[derive(Clone, Copy, Debug)]
struct NoCull;

impl<S: Scalar> Accelerator<S> for NoCull {
    fn closest_hit<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Hit<S, W> {
        BruteForce.closest_hit(scene, ray, t_min, t_max, active)
    }
    fn transmittance<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Lanes<S, W> {
        BruteForce.transmittance(scene, ray, t_min, t_max, active)
    }
}

fn render<S: Scalar, A: Accelerator<S>, const W: usize>(
    accel: A,
    scene: &SceneView<'_, S>,
    camera: Camera<S>,
    mode: Mode,
    aov: Aov,
    sampling: Sampling,
) -> (Vec<Rgb8>, [u64; 4]) {
    let settings = TraceSettings { mode, ..TraceSettings::default() };
    let tracer: Tracer<S, A> = Tracer::with_accelerator(*scene, accel, settings).unwrap();
    let renderer = Renderer { tracer, camera, aov, sampling };
    let mut out = vec![[0u8; 3]; (camera.width() * camera.height()) as usize];
    let mut stats = RayStats::default();
    renderer.render_rect::<W>(camera.full_rect(), &mut out, &mut stats).unwrap();
    (out, stats.rays())
}

/// Culled and unculled renders of one scene and camera agree at every
/// width; returns how many primitives had a rectangle smaller than the
/// image.
fn check<S: Scalar>(scene: &SceneView<'_, S>, camera: Camera<S>, what: &str, rng: &mut Rng) -> usize {
    let mode = if rng.below(4) == 0 { Mode::Cast } else { Mode::Whitted };
    let aov = if rng.below(5) == 0 { Aov::Id } else { Aov::Color };
    let sampling = match rng.below(8) {
        0 => Sampling::Grid(2),
        1 => Sampling::adaptive(2, 0.1),
        _ => Sampling::Centre,
    };
    let reference = render::<S, _, 1>(NoCull, scene, camera, mode, aov, sampling);
    let label = format!("{what} {mode:?} {aov:?} {sampling:?}");
    assert_eq!(render::<S, _, 1>(BruteForce, scene, camera, mode, aov, sampling), reference, "{label} width 1");
    assert_eq!(render::<S, _, 4>(BruteForce, scene, camera, mode, aov, sampling), reference, "{label} width 4");
    assert_eq!(render::<S, _, 8>(BruteForce, scene, camera, mode, aov, sampling), reference, "{label} width 8");
    assert_eq!(render::<S, _, 16>(BruteForce, scene, camera, mode, aov, sampling), reference, "{label} width 16");
    // Through a tree (its boxes padded for rays from the eye, as the CLI's
    // are), then with camera tiles of 4 × 4 pixels, lists of any length.
    let reach = camera.eye().to_f32().iter().fold(0.0f32, |m, c| m.max(c.abs()));
    let bvh = HeapBvh::build_with(scene, &BuildSettings { reach, ..BuildSettings::default() }).unwrap();
    let tiles =
        HeapCameraTiles::build(scene, &camera, TileSettings { shift: 2, budget: u32::MAX, min_listed_percent: 0 })
            .unwrap();
    let tiles = tiles.view();
    let tree = bvh.view();
    assert_eq!(render::<S, _, 1>(tree, scene, camera, mode, aov, sampling), reference, "{label} tree, width 1");
    assert_eq!(render::<S, _, 4>(tree, scene, camera, mode, aov, sampling), reference, "{label} tree, width 4");
    assert_eq!(render::<S, _, 8>(tree, scene, camera, mode, aov, sampling), reference, "{label} tree, width 8");
    assert_eq!(render::<S, _, 16>(tree, scene, camera, mode, aov, sampling), reference, "{label} tree, width 16");
    let tree = tree.with_camera_tiles(&tiles);
    assert_eq!(render::<S, _, 1>(tree, scene, camera, mode, aov, sampling), reference, "{label} tiles, width 1");
    assert_eq!(render::<S, _, 4>(tree, scene, camera, mode, aov, sampling), reference, "{label} tiles, width 4");
    assert_eq!(render::<S, _, 8>(tree, scene, camera, mode, aov, sampling), reference, "{label} tiles, width 8");
    assert_eq!(render::<S, _, 16>(tree, scene, camera, mode, aov, sampling), reference, "{label} tiles, width 16");
    // How many of the camera packets of 4 took a tile's list (the rest
    // walked the tree): the test must exercise the lists.
    let (pw, ph) = packet_shape(4);
    let (mut listed, mut packets) = (0, 0);
    for y in (0..camera.height()).step_by(ph as usize) {
        for x in (0..camera.width()).step_by(pw as usize) {
            let (ray, active) = camera.packet::<4>(x, y, camera.full_rect());
            packets += 1;
            listed += usize::from(tiles.list(&ray, active).is_some());
        }
    }
    LISTED.with(|c| c.set((c.get().0 + listed, c.get().1 + packets)));
    ScreenCull::new(scene, &camera).map(|c| c.bounded()).unwrap_or(0)
}

thread_local! {
    /// Camera packets of 4 that took a tile's list, of those formed, in
    /// this thread's cases so far.
    static LISTED: std::cell::Cell<(usize, usize)> = const { std::cell::Cell::new((0, 0)) };
}

/// A camera for `S` from `f32` numbers (`None` where `S` refuses it).
fn camera<S: Scalar>(eye: Vec3<f32>, at: Vec3<f32>, fov: f32, w: u32, h: u32) -> Option<Camera<S>> {
    Camera::new(cv(eye), cv(at), cv(Vec3::new(0.0, 0.0, 1.0)), fov, w, h).ok()
}

/// A sphere tangent to the camera ray of pixel `(i, j)` (to `f32`
/// rounding), at distance `t` along it: the ray grazes it.
fn grazing_sphere(cam: &Camera<f32>, i: u32, j: u32, t: f32, r: f32, rng: &mut Rng) -> (Vec3<f32>, f32) {
    let (ray, _) = cam.packet::<1>(i, j, cam.full_rect());
    let d = ray.dir.lane(0);
    let (u, v) = d.orthonormal_basis();
    let a = rng.range(0.0, std::f32::consts::TAU);
    let side = u.scale(a.cos()) + v.scale(a.sin());
    (cam.eye() + d.scale(t) + side.scale(r), r)
}

/// Random scenes of every primitive kind (drawn in `f32`, then scaled by
/// `scale` and converted to `S`), seen from outside, from inside
/// primitives and beside grazing spheres.
fn random_cases<S: Scalar>(seed: u64, cases: u32, scale: f32, name: &str) {
    let mut rng = Rng(seed);
    let mut bounded = 0;
    let mut ran = 0;
    for case in 0..cases {
        let n = 1 + rng.below(14) as usize;
        let mut scene = random_scene_in::<f32>(&mut rng, n);
        let (w, h) = (8 + rng.below(20), 6 + rng.below(14));
        // Where the camera is: outside, at a primitive's bounds centre
        // (inside it), or beside grazing spheres.
        let kind = rng.below(4);
        let mut eye = rng.unit().scale(rng.range(4.0, 14.0));
        let at = rng.vec(-1.0, 1.0);
        if kind == 1 {
            let view = scene.view();
            if let Some(p) = view.primitives().get(rng.below(n as u32) as usize) {
                if let Some((lo, hi)) = p.shape.bounds(view.vertices()) {
                    eye = (lo + hi).scale(0.5);
                }
            }
        }
        let fov = rng.range(10.0, 120.0);
        let Some(cam_f) = camera::<f32>(eye, at, fov, w, h) else { continue };
        if kind == 2 {
            // Grazing spheres: tangent to random pixels' rays, some tiny.
            let m = scene.add_material(Material::diffuse(Vec3::new(0.9, 0.5, 0.2))).unwrap();
            for _ in 0..3 {
                let r = if rng.below(2) == 0 { 0.003 } else { rng.range(0.1, 1.0) };
                let t = rng.range(2.0, 12.0);
                let (c, r) = grazing_sphere(&cam_f, rng.below(w), rng.below(h), t, r, &mut rng);
                let _ = scene.add_sphere(c, r, m);
            }
        }
        if kind == 3 {
            // A light inside or just outside a primitive's bounds: shadow
            // rays start beside or graze the occluders around it.
            let view = scene.view();
            let near =
                view.primitives().get(rng.below(n as u32) as usize).and_then(|p| p.shape.bounds(view.vertices()));
            if let Some((lo, hi)) = near {
                let c = (lo + hi).scale(0.5);
                let out = if rng.below(2) == 0 { Vec3::ZERO } else { (hi - lo).scale(0.5 + rng.range(0.0, 0.05)) };
                let _ = scene.add_light(c + out, Vec3::new(0.6, 0.6, 0.6));
            }
        }
        let Some(cam) = camera::<S>(eye.scale(scale), at.scale(scale), fov, w, h) else { continue };
        let Some(scaled) = scaled_scene::<S>(&scene.view(), scale) else { continue };
        bounded += check(&scaled.view(), cam, &format!("{name} case {case} kind {kind}"), &mut rng);
        ran += 1;
    }
    assert!(ran >= cases / 2, "{name}: only {ran} of {cases} cases could be built");
    // Most camera packets took a tile's list (those that did not straddle
    // tiles or left the eye's view; cameras inside a primitive included).
    let (listed, packets) = LISTED.with(|c| c.replace((0, 0)));
    assert!(listed * 2 > packets, "{name}: {listed} of {packets} camera packets took a tile's list");
    // Culling did something: most primitives are bounded and in front.
    assert!(bounded > ran as usize, "{name}: {bounded} bounded rectangles in {ran} cases");
}

/// `view` with every coordinate times `scale`, in `S` (`None` if `S`
/// cannot hold it).
fn scaled_scene<S: Scalar>(view: &SceneView<'_, f32>, scale: f32) -> Option<TestSceneOf<S>> {
    let mut s = TestSceneOf::<S>::new();
    let sim = raypack::similarity::Similarity { origin: [0.0; 3], scale };
    s.add_similar(view, &sim).ok()?;
    Some(s)
}

#[test]
fn culling_changes_no_byte_in_f32() {
    random_cases::<f32>(0xC011, 60, 1.0, "f32");
}

#[test]
fn culling_changes_no_byte_in_f32_at_tiny_and_huge_scales() {
    random_cases::<f32>(0xC012, 25, 1.0e-3, "f32 x1e-3");
    random_cases::<f32>(0xC013, 25, 1.0e4, "f32 x1e4");
}

#[test]
fn culling_changes_no_byte_in_fixed32() {
    // Q8.24 holds coordinates up to 2: the scenes at a fifth of their size
    // and smaller.
    random_cases::<Fixed32>(0xC014, 40, 0.12, "fixed32");
    random_cases::<Fixed32>(0xC015, 20, 0.01, "fixed32 x0.01");
}

#[test]
fn culling_changes_no_byte_in_fixed() {
    random_cases::<Fixed>(0xC016, 30, 1.0, "fixed");
    random_cases::<Fixed>(0xC017, 15, 100.0, "fixed x100");
}

#[test]
fn demo_frame_culls_and_matches_band_by_band() {
    use raypack::demo::{build_demo_scene_for, demo_camera_for, DemoScene};
    fn one<S: Scalar>() {
        let mut scene = DemoScene::<S>::new();
        let mut described = DemoScene::<f32>::new();
        let frame = build_demo_scene_for(&mut scene, &mut described).unwrap();
        let camera = demo_camera_for::<S>(&frame, 64, 48).unwrap();
        let view = scene.view();
        let cull = ScreenCull::new(&view, &camera).unwrap();
        // The floor plane is everywhere, and the back wall spans the view;
        // the nine other primitives cover less than the image, and so does
        // the ellipsoid quadric (bounded by its ellipsoid's box).
        assert_eq!(cull.bounded(), 10);
        let tracer: Tracer<S> = Tracer::new(view, TraceSettings::default()).unwrap();
        let plain: Tracer<S, NoCull> = Tracer::with_accelerator(view, NoCull, TraceSettings::default()).unwrap();
        let mut band = vec![[0u8; 3]; 64 * 3];
        let a = Renderer::new(tracer, camera).checksums::<1>(&mut band).unwrap();
        let b = Renderer::new(plain, camera).checksums::<1>(&mut band).unwrap();
        assert_eq!(a, b);
        let c = Renderer::new(tracer, camera).checksums::<8>(&mut band).unwrap();
        assert!(c.same_render(&a));
    }
    one::<f32>();
    one::<Fixed32>();
    one::<Fixed>();
}

/// Every pixel whose camera ray (at the pixel's centre, and at the corner
/// subpixels of a 3 × 3 grid) reports a crossing with a primitive lies in
/// that primitive's rectangle: seeded random scenes and cameras, every
/// primitive tested directly with no culling. Returns the crossings seen.
fn rectangles_hold_hits<S: Scalar>(seed: u64, cases: u32, scale: f32, name: &str) -> usize {
    let mut rng = Rng(seed);
    let mut crossings = 0;
    for case in 0..cases {
        let n = 1 + rng.below(14) as usize;
        let scene = random_scene_in::<f32>(&mut rng, n);
        let (w, h) = (8 + rng.below(24), 6 + rng.below(18));
        let eye = rng.unit().scale(rng.range(3.0, 14.0));
        let at = rng.vec(-1.0, 1.0);
        let fov = rng.range(10.0, 120.0);
        let Some(cam) = camera::<S>(eye.scale(scale), at.scale(scale), fov, w, h) else { continue };
        let Some(scaled) = scaled_scene::<S>(&scene.view(), scale) else { continue };
        let view = scaled.view();
        let cull = ScreenCull::new(&view, &cam).unwrap();
        for (y, x) in (0..h).flat_map(|y| (0..w).map(move |x| (y, x))) {
            for (a, b, g) in [(0, 0, 1), (0, 0, 3), (2, 0, 3), (0, 2, 3), (2, 2, 3)] {
                let (ray, active) = cam.subpixel_packet::<1>(x, y, cam.full_rect(), g, a, b);
                for (k, p) in view.primitives().iter().enumerate() {
                    let r = p.shape.roots(view.vertices(), &ray, Lanes::splat(S::ZERO), Lanes::splat(S::MAX), active);
                    if r.hit0.any() || r.hit1.any() {
                        crossings += 1;
                        assert!(cull.covers(k, x, y), "{name} case {case}: primitive {k} hit at pixel ({x}, {y})");
                    }
                }
            }
        }
    }
    crossings
}

#[test]
fn cull_rectangles_hold_every_hit_pixel() {
    assert!(rectangles_hold_hits::<f32>(0xC018, 40, 1.0, "f32") > 1000);
    assert!(rectangles_hold_hits::<f32>(0xC019, 15, 1.0e-3, "f32 x1e-3") > 100);
    assert!(rectangles_hold_hits::<Fixed32>(0xC01A, 30, 0.12, "fixed32") > 1000);
    assert!(rectangles_hold_hits::<Fixed32>(0xC01B, 15, 0.01, "fixed32 x0.01") > 100);
    assert!(rectangles_hold_hits::<Fixed>(0xC01C, 20, 1.0, "fixed") > 1000);
}

/// Every crossing of a ray with a primitive (at `t > 0`, from an origin
/// anywhere: inside and beside the primitives, on their surfaces, far
/// out) leaves that primitive among the candidates of
/// `ShadowCull::reach_candidates`, the reflected and refracted rays'
/// culling: seeded random scenes and rays, every primitive tested
/// directly. Returns (crossings, culled tests): both must be many, or the
/// test proves nothing.
fn reach_holds_hits<S: Scalar>(seed: u64, cases: u32, scale: f32, name: &str) -> (usize, usize) {
    let mut rng = Rng(seed);
    let (mut crossings, mut culled) = (0, 0);
    for case in 0..cases {
        let n = 1 + rng.below(12) as usize;
        let scene = random_scene_in::<f32>(&mut rng, n);
        let Some(scaled) = scaled_scene::<S>(&scene.view(), scale) else { continue };
        let view = scaled.view();
        let mut cull = ShadowCull::<S>::empty();
        cull.fill(&view).unwrap();
        for _ in 0..400 {
            // Origins: random, at a primitive's bounds centre (inside it),
            // or on the segment between two bounds' corners.
            let mut o = rng.vec(-8.0, 8.0);
            if rng.below(2) == 0 {
                let k = rng.below(n as u32) as usize;
                if let Some((lo, hi)) = scene.view().primitives()[k].shape.bounds(scene.view().vertices()) {
                    let t = rng.range(-0.2, 1.2);
                    o = lo + (hi - lo).scale(t);
                }
            }
            let d = rng.unit();
            let o = Vec3::new(S::from_f32(o.x * scale), S::from_f32(o.y * scale), S::from_f32(o.z * scale));
            let (ray, active) = RayPacket::<S, 1>::new(
                o.splat(),
                Vec3::new(S::from_f32(d.x), S::from_f32(d.y), S::from_f32(d.z)).splat(),
            );
            if active.none() {
                continue;
            }
            let among = cull.reach_candidates(&ray, active);
            for (k, p) in view.primitives().iter().enumerate() {
                let r = p.shape.roots(view.vertices(), &ray, Lanes::splat(S::ZERO), Lanes::splat(S::MAX), active);
                let hit = r.hit0.any() || r.hit1.any();
                let kept = among.checked_shr(k as u32).is_none_or(|b| b & 1 == 1);
                if hit {
                    crossings += 1;
                    assert!(kept, "{name} case {case}: primitive {k} crossed by a ray the reach culls");
                } else if !kept {
                    culled += 1;
                }
            }
        }
    }
    (crossings, culled)
}

#[test]
fn reach_spheres_hold_every_crossing() {
    for (c, name) in [
        (reach_holds_hits::<f32>(0xC01D, 40, 1.0, "f32"), "f32"),
        (reach_holds_hits::<f32>(0xC01E, 15, 1.0e-3, "f32 x1e-3"), "f32 x1e-3"),
        (reach_holds_hits::<f32>(0xC01F, 15, 1.0e4, "f32 x1e4"), "f32 x1e4"),
        (reach_holds_hits::<Fixed32>(0xC020, 30, 0.12, "fixed32"), "fixed32"),
        (reach_holds_hits::<Fixed32>(0xC021, 15, 0.01, "fixed32 x0.01"), "fixed32 x0.01"),
        (reach_holds_hits::<Fixed>(0xC022, 20, 1.0, "fixed"), "fixed"),
    ] {
        assert!(c.0 > 500 && c.1 > 2000, "{name}: {} crossings, {} culled tests", c.0, c.1);
    }
}

/// Shadow rays as the tracer casts them (from a point `P` moved off its
/// surface by `eps` along a normal, towards a light, `t` in `(0, |L − P|)`)
/// never cross a plane that `ShadowCull::candidates_from` leaves out:
/// planes with lights well above, just past the side margin and far away,
/// origins on the plane itself (hit points of the floor), just above and
/// below it, and anywhere in the scene. Returns (crossings, plane tests
/// left out): both must be many, or the test proves nothing.
fn planes_hold_shadow_crossings<S: Scalar>(seed: u64, cases: u32, scale: f32) -> (usize, usize) {
    let mut rng = Rng(seed);
    let (mut crossings, mut culled) = (0, 0);
    let f = |x: f32| S::from_f32(x * scale);
    let v = |p: Vec3<f32>| Vec3::new(f(p.x), f(p.y), f(p.z));
    for _ in 0..cases {
        let mut scene = Scene::<S, 8, 8, 2, 2>::new();
        let m = scene.add_material(Material::diffuse(Vec3::new(S::ONE, S::ONE, S::ONE))).unwrap();
        // One or two planes through points of [−1, 1]³, a box for extent.
        let planes: Vec<(Vec3<f32>, f32)> = (0..1 + rng.below(2))
            .map(|_| {
                // Axis normals (floors, walls) either way, or any.
                let n = match rng.below(4) {
                    0 => Vec3::new(0.0, 0.0, 1.0),
                    1 => Vec3::new(0.0, -1.0, 0.0),
                    _ => rng.unit(),
                };
                (n, -n.dot(rng.vec(-1.0, 1.0)))
            })
            .collect();
        for &(n, d) in &planes {
            scene.add_plane(S::from_f32(n.x), S::from_f32(n.y), S::from_f32(n.z), f(d), m).unwrap();
        }
        let (lo, hi) = (rng.vec(-1.5, 0.0), rng.vec(0.0, 1.5));
        scene.add_box(v(lo), v(hi), m).unwrap();
        // Lights: beside the first plane at a random height (some just
        // past the margin, some on the plane's other side), or anywhere.
        let (n0, d0) = planes[0];
        for _ in 0..2 {
            let q = rng.vec(-2.0, 2.0);
            let h = match rng.below(3) {
                0 => rng.range(-0.05, 0.05),
                1 => rng.range(-2.0, 2.0),
                _ => n0.dot(q) + d0,
            };
            let l = q - n0.scale(n0.dot(q) + d0 - h);
            scene.add_light(v(l), Vec3::new(S::ONE, S::ONE, S::ONE)).unwrap();
        }
        let view = scene.view();
        let mut cull = ShadowCull::<S>::empty();
        cull.fill(&view).unwrap();
        for _ in 0..300 {
            // Hit points: on the first plane, or anywhere in the box.
            let q = rng.vec(-2.0, 2.0);
            let p = if rng.below(2) == 0 { q - n0.scale(n0.dot(q) + d0) } else { q };
            let p = v(p);
            let eps = S::RAY_EPSILON * (p.x.abs().max(p.y.abs()).max(p.z.abs()) + S::ONE);
            // Moved off along ±n (a surface seen from either side) or a
            // random unit normal.
            let g = match rng.below(3) {
                0 => n0,
                1 => -n0,
                _ => rng.unit(),
            };
            let g = Vec3::new(S::from_f32(g.x), S::from_f32(g.y), S::from_f32(g.z));
            let o = p + g.scale(eps);
            for (li, l) in view.lights().iter().enumerate() {
                let (dir, dist, ok) = (l.position - p).splat::<1>().normalize_with_length();
                if ok.none() {
                    continue;
                }
                let among = cull.candidates_from(li, &o.splat(), &dir, Lanes::splat(eps), ok);
                let ray = RayPacket { origin: o.splat(), dir };
                for (k, prim) in view.primitives().iter().enumerate() {
                    if !matches!(prim.shape, raypack::primitives::Shape::Plane(_)) {
                        continue;
                    }
                    let r = prim.shape.roots(view.vertices(), &ray, Lanes::splat(S::ZERO), dist, ok);
                    let kept = among >> k & 1 == 1;
                    if r.hit0.any() {
                        crossings += 1;
                        assert!(kept, "plane {k} crossed by a shadow ray the cull leaves out (light {li})");
                    } else if !kept {
                        culled += 1;
                    }
                }
            }
        }
    }
    (crossings, culled)
}

#[test]
fn shadow_planes_hold_every_crossing() {
    for (c, name) in [
        (planes_hold_shadow_crossings::<f32>(0x9A1, 200, 1.0), "f32"),
        (planes_hold_shadow_crossings::<f32>(0x9A2, 60, 1.0e4), "f32 x1e4"),
        (planes_hold_shadow_crossings::<Fixed32>(0x9A3, 200, 0.25), "fixed32"),
        (planes_hold_shadow_crossings::<Fixed>(0x9A4, 100, 1.0), "fixed"),
    ] {
        assert!(c.0 > 1000 && c.1 > 10_000, "{name}: {} crossings, {} culled plane tests", c.0, c.1);
    }
}
