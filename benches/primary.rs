//! Primary-ray intersection of a sphere-heavy scene at packet widths 1, 4, 8
//! (rays per second), plus the full Whitted render of the demo scene.
//!
//! `cargo bench --bench primary`; add `RUSTFLAGS="-C target-cpu=native"` to
//! let LLVM use AVX2/AVX-512 for the 8-wide lanes.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use raypack::demo::{demo_camera, demo_scene};
use raypack::prelude::*;
use std::hint::black_box;
use std::time::Duration;

const SIZE: u32 = 256;

/// A 4×4 grid of spheres filling the view, on a floor plane, lit by two lights.
fn sphere_grid() -> (Scene<f32, 32, 8>, Camera<f32>) {
    let mut s: Scene<f32, 32, 8> = Scene::new();
    let m = s.add_material(Material::diffuse(Vec3::new(0.8, 0.6, 0.4))).unwrap();
    for i in 0..4 {
        for j in 0..4 {
            let c = Vec3::new(-3.0 + 2.0 * i as f32, -3.0 + 2.0 * j as f32, 0.0);
            s.add_sphere(c, 0.9, m).unwrap();
        }
    }
    s.add_light(Vec3::new(5.0, 5.0, 10.0), Vec3::new(0.7, 0.7, 0.7)).unwrap();
    let cam = Camera::new(Vec3::new(0.0, 0.0, 12.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 40.0, SIZE, SIZE).unwrap();
    (s, cam)
}

fn packets<const W: usize>(cam: &Camera<f32>) -> Vec<(RayPacket<f32, W>, Mask<W>)> {
    let (pw, ph) = raypack::camera::packet_shape(W);
    let mut v = Vec::new();
    for y in (0..cam.height()).step_by(ph as usize) {
        for x in (0..cam.width()).step_by(pw as usize) {
            v.push(cam.packet::<W>(x, y, cam.full_rect()));
        }
    }
    v
}

fn intersect_all<const W: usize>(view: &SceneView<'_, f32>, ps: &[(RayPacket<f32, W>, Mask<W>)]) -> u32 {
    let mut hits = 0;
    for (ray, m) in ps {
        let h = view.closest_hit(ray, Lanes::zero(), Lanes::splat(f32::MAX), *m);
        hits += h.mask.count();
    }
    hits
}

fn bench_primary(c: &mut Criterion) {
    let (scene, cam) = sphere_grid();
    let view = scene.view();
    let mut g = c.benchmark_group("primary_16_spheres");
    g.throughput(Throughput::Elements((SIZE * SIZE) as u64));
    let p1 = packets::<1>(&cam);
    let p4 = packets::<4>(&cam);
    let p8 = packets::<8>(&cam);
    // Same hits at every width.
    assert_eq!(intersect_all(&view, &p1), intersect_all(&view, &p8));
    g.bench_function(BenchmarkId::new("width", 1), |b| b.iter(|| intersect_all(&view, black_box(&p1))));
    g.bench_function(BenchmarkId::new("width", 4), |b| b.iter(|| intersect_all(&view, black_box(&p4))));
    g.bench_function(BenchmarkId::new("width", 8), |b| b.iter(|| intersect_all(&view, black_box(&p8))));
    g.finish();
}

/// The bare ray-sphere kernel: every packet against one sphere it partly
/// covers (about half the rays hit), no scene loop.
fn kernel_all<const W: usize>(s: &raypack::primitives::Sphere<f32>, ps: &[(RayPacket<f32, W>, Mask<W>)]) -> u32 {
    let mut hits = 0;
    for (ray, m) in ps {
        let r = s.roots(ray, Lanes::zero(), Lanes::splat(f32::MAX), *m);
        hits += r.hit0.count();
    }
    hits
}

fn bench_kernel(c: &mut Criterion) {
    let cam = Camera::new(Vec3::new(0.0, 0.0, 12.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 40.0, SIZE, SIZE).unwrap();
    let s = raypack::primitives::Sphere::new(Vec3::new(0.5, -0.3, 0.0), 2.5).unwrap();
    let p1 = packets::<1>(&cam);
    let p4 = packets::<4>(&cam);
    let p8 = packets::<8>(&cam);
    assert_eq!(kernel_all(&s, &p1), kernel_all(&s, &p8));
    let mut g = c.benchmark_group("sphere_kernel");
    g.throughput(Throughput::Elements((SIZE * SIZE) as u64));
    g.bench_function(BenchmarkId::new("width", 1), |b| b.iter(|| kernel_all(black_box(&s), black_box(&p1))));
    g.bench_function(BenchmarkId::new("width", 4), |b| b.iter(|| kernel_all(black_box(&s), black_box(&p4))));
    g.bench_function(BenchmarkId::new("width", 8), |b| b.iter(|| kernel_all(black_box(&s), black_box(&p8))));
    g.finish();
}

fn render<const W: usize>(r: &Renderer<'_, f32>, img: &mut [Rgb8]) -> u64 {
    let mut st = RayStats::default();
    r.render_rect::<W>(r.camera.full_rect(), img, &mut st).unwrap();
    st.total()
}

fn bench_whitted(c: &mut Criterion) {
    let scene = demo_scene::<f32>().unwrap();
    let cam = demo_camera::<f32>(SIZE, SIZE).unwrap();
    let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
    let r = Renderer::new(tracer, cam);
    let mut img = vec![[0u8; 3]; (SIZE * SIZE) as usize];
    let mut g = c.benchmark_group("whitted_demo");
    g.throughput(Throughput::Elements((SIZE * SIZE) as u64));
    g.bench_function(BenchmarkId::new("width", 1), |b| b.iter(|| render::<1>(&r, &mut img)));
    g.bench_function(BenchmarkId::new("width", 4), |b| b.iter(|| render::<4>(&r, &mut img)));
    g.bench_function(BenchmarkId::new("width", 8), |b| b.iter(|| render::<8>(&r, &mut img)));
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    targets = bench_kernel, bench_primary, bench_whitted
}
criterion_main!(benches);
