//! Fixed point (Q8.24 `Fixed32` and 32.32 `Fixed`) against `f32` on the host: the full Whitted
//! render of the demo scene at 64×48, packet widths 1 and 8.
//!
//! `cargo bench --bench fixed`. Criterion reports each configuration's time;
//! `tools/fixed_speed.rs` measures the same four configurations
//! interleaved (best of N) for the ratios quoted in the README.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use raypack::demo::{build_demo_scene_for, demo_camera_for, DemoScene};
use raypack::prelude::*;
use std::hint::black_box;
use std::time::Duration;

const W: u32 = 64;
const H: u32 = 48;

fn render<S: Scalar, const L: usize>(renderer: &Renderer<'_, S>, img: &mut [Rgb8]) -> u64 {
    let mut stats = RayStats::default();
    renderer.render_rect::<L>(renderer.camera.full_rect(), img, &mut stats).unwrap();
    stats.total()
}

fn bench_scalar<S: Scalar>(c: &mut Criterion, name: &str) {
    let mut scene = Box::new(DemoScene::<S>::new());
    let mut described = Box::new(DemoScene::<f32>::new());
    let frame = build_demo_scene_for(&mut scene, &mut described).unwrap();
    let camera = demo_camera_for::<S>(&frame, W, H).unwrap();
    let tracer: Tracer<S> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
    let renderer = Renderer::new(tracer, camera);
    let mut img = vec![[0u8; 3]; (W * H) as usize];
    let mut g = c.benchmark_group(format!("demo_whitted_{W}x{H}"));
    g.throughput(Throughput::Elements((W * H) as u64));
    g.bench_function(BenchmarkId::new(name, "width1"), |b| b.iter(|| render::<S, 1>(black_box(&renderer), &mut img)));
    g.bench_function(BenchmarkId::new(name, "width8"), |b| b.iter(|| render::<S, 8>(black_box(&renderer), &mut img)));
    g.finish();
}

fn bench(c: &mut Criterion) {
    bench_scalar::<f32>(c, "f32");
    bench_scalar::<Fixed>(c, "fixed");
    bench_scalar::<raypack::Fixed32>(c, "fixed32");
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(2));
    targets = bench
}
criterion_main!(benches);
