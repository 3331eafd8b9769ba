//! Ray–primitive tests per ray, by ray kind, of one firmware frame (the
//! demo scene at 160×128, one ray at a time, Whitted, as the Cortex-M0
//! board renders it), with and without the renderer's culling of camera
//! and shadow rays (src/query/cull.rs), for `f32` and `Fixed32`. Both renders go through a
//! brute force that counts every primitive it tests; the images are
//! compared byte for byte.
//!
//! `cargo run --release --example cull_count`
use raypack::demo::{build_demo_scene_for, demo_camera_for, DemoScene};
use raypack::lanes::{Lanes, Mask};
use raypack::prelude::*;
use raypack::query::{Candidates, Hit, ScreenCull};
use raypack::ray::RayPacket;
use raypack::Fixed32;
use std::cell::Cell;

/// Tests by kind: primary, secondary (reflected and refracted), shadow.
#[derive(Default)]
struct Tally {
    tests: [Cell<u64>; 3],
    /// Shadow tests by primitive (the demo's 11; the last cell sums the rest).
    shadow_by_primitive: [Cell<u64>; 12],
}

thread_local! {
    static TALLY: Tally = Tally::default();
    static EYE: Cell<[u32; 3]> = const { Cell::new([0; 3]) };
}

fn add(kind: usize, n: u64) {
    TALLY.with(|t| t.tests[kind].set(t.tests[kind].get() + n));
}

fn add_shadow(k: usize, n: u64) {
    TALLY.with(|t| {
        let c = &t.shadow_by_primitive[k.min(11)];
        c.set(c.get() + n)
    });
}

/// Brute force that counts its tests; `CULL` says whether it takes the
/// renderer's candidates.
#[derive(Clone, Copy, Debug)]
struct Counting<const CULL: bool>;

impl<S: Scalar, const CULL: bool> Accelerator<S> for Counting<CULL> {
    const CULLS: bool = CULL;

    fn closest_hit<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Hit<S, W> {
        self.closest_hit_among(scene, ray, t_min, t_max, active, u32::MAX)
    }

    fn closest_hit_among<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
        candidates: Candidates,
    ) -> Hit<S, W> {
        let n = scene.primitives().len();
        let tested = (0..n).filter(|&k| k >= 32 || candidates & (1 << k) != 0).count() as u64;
        // Camera rays start at the eye, bit for bit; secondary rays do not.
        let o = ray.origin.lane(0).to_f32().map(f32::to_bits);
        let kind = if EYE.with(|e| e.get()) == o { 0 } else { 1 };
        if active.any() {
            add(kind, tested * active.count() as u64);
        }
        BruteForce.closest_hit_among(scene, ray, t_min, t_max, active, candidates)
    }

    fn transmittance<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Lanes<S, W> {
        self.transmittance_among(scene, ray, t_min, t_max, active, u32::MAX)
    }

    fn transmittance_among<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
        candidates: Candidates,
    ) -> Lanes<S, W> {
        // Brute force's loop, counting the primitives it reaches.
        let mut live = active;
        let verts = scene.vertices();
        for (k, p) in scene.primitives().iter().enumerate() {
            if live.none() {
                break;
            }
            if k < 32 && candidates & (1 << k) == 0 {
                continue;
            }
            add(2, live.count() as u64);
            add_shadow(k, live.count() as u64);
            let r = p.shape.roots(verts, ray, t_min, t_max, live);
            if r.hit0.any() && scene.kt_of_material(p.material) == S::ZERO {
                live = live.and_not(r.hit0);
            }
        }
        BruteForce.transmittance_among(scene, ray, t_min, t_max, active, candidates)
    }
}

fn frame<S: Scalar, const CULL: bool>(name: &str) -> Vec<Rgb8> {
    let mut scene = DemoScene::<S>::new();
    let mut described = DemoScene::<f32>::new();
    let frame = build_demo_scene_for(&mut scene, &mut described).unwrap();
    let camera = demo_camera_for::<S>(&frame, 160, 128).unwrap();
    EYE.with(|e| e.set(camera.eye().to_f32().map(f32::to_bits)));
    TALLY.with(|t| t.tests.iter().chain(&t.shadow_by_primitive).for_each(|c| c.set(0)));
    let tracer: Tracer<S, Counting<CULL>> =
        Tracer::with_accelerator(scene.view(), Counting::<CULL>, TraceSettings::default()).unwrap();
    let renderer = Renderer::new(tracer, camera);
    let mut img = vec![[0u8; 3]; 160 * 128];
    let mut stats = RayStats::default();
    // The firmware's band loop: one row per band, one ray per packet.
    let mut band = vec![[0u8; 3]; 160];
    let mut y = 0;
    renderer
        .render_bands::<1, ()>(&mut band, &mut stats, |rect, px| {
            img[(rect.y * 160) as usize..][..px.len()].copy_from_slice(px);
            y += rect.h;
            Ok(())
        })
        .unwrap();
    let t: [u64; 3] = TALLY.with(|t| [t.tests[0].get(), t.tests[1].get(), t.tests[2].get()]);
    let rays = [stats.primary, stats.reflected + stats.refracted, stats.shadow];
    let per = |i: usize| if rays[i] == 0 { 0.0 } else { t[i] as f64 / rays[i] as f64 };
    let total: u64 = t.iter().sum();
    println!(
        "{name} culling={} primitives={} bounded={} tests={} per_ray={:.3} primary={:.3} secondary={:.3} shadow={:.3} rays={}/{}/{}",
        if CULL { "on" } else { "off" },
        scene.view().primitives().len(),
        ScreenCull::new(&scene.view(), &camera).map(|c| c.bounded()).unwrap_or(0),
        total,
        total as f64 / stats.total() as f64,
        per(0),
        per(1),
        per(2),
        rays[0],
        rays[1],
        rays[2],
    );
    let by: Vec<u64> = TALLY.with(|t| t.shadow_by_primitive.iter().map(Cell::get).collect());
    println!("{name} culling={} shadow tests by primitive (scene order): {by:?}", if CULL { "on" } else { "off" });
    img
}

fn main() {
    let a = frame::<f32, false>("f32");
    let b = frame::<f32, true>("f32");
    assert!(a == b, "f32: culling changed the image");
    let a = frame::<Fixed32, false>("fixed32");
    let b = frame::<Fixed32, true>("fixed32");
    assert!(a == b, "fixed32: culling changed the image");
    println!("images identical with and without culling (f32, fixed32)");
}
