//! Criterion benches of the packet kernels and whole renders, all through
//! the instruction-set dispatcher with the ISA it picks on this machine
//! (`Isa::best()`; printed at the start):
//! - `kernel/<kind>`: the bare kernel of each primitive kind (16 of it, the
//!   packet in registers), widths 1, 4, 8 (16 too where AVX-512 runs);
//!   throughput in ray-primitive tests;
//! - `primary_grid_1024/<N>`: primary rays (closest hit) of a 1024×1024
//!   image against N = 1, 16, 64, 256 spheres, width 8, single thread;
//! - `whitted_demo_256`: the full Whitted render of the demo scene, widths
//!   1, 4, 8;
//! - `whitted_spd_256/<scene>`: SPD balls-2, gears-2, teapot-2 through the
//!   BVH, width 8, 256×256, single thread.
//!
//! `cargo bench --bench primary` (about 2 minutes of measuring). Ratios in
//! the README come from `tools/primary_probe.rs` and `raypack
//! bench`, which interleave the configurations.
mod workloads;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use raypack::demo::{demo_camera, demo_scene};
use raypack::dispatch::Isa;
use raypack::nff;
use raypack::prelude::*;
use std::hint::black_box;
use std::time::Duration;
use workloads::*;

fn bench_kernels(c: &mut Criterion) {
    let isa = Isa::best();
    println!("instruction set: {isa}");
    let cam = camera(256);
    let (p1, p4, p8, p16) = (packets::<1>(&cam), packets::<4>(&cam), packets::<8>(&cam), packets::<16>(&cam));
    for kind in KINDS {
        let scene = kind_scene(kind);
        let view = scene.view();
        let tests = 256 * 256 * view.primitives().len() as u64;
        assert_eq!(shape_pass(isa, &view, &p1), shape_pass(isa, &view, &p8));
        let mut g = c.benchmark_group(format!("kernel/{kind}"));
        g.throughput(Throughput::Elements(tests));
        g.bench_function(BenchmarkId::new(isa.name(), 1), |b| b.iter(|| shape_pass(isa, &view, black_box(&p1))));
        g.bench_function(BenchmarkId::new(isa.name(), 4), |b| b.iter(|| shape_pass(isa, &view, black_box(&p4))));
        g.bench_function(BenchmarkId::new(isa.name(), 8), |b| b.iter(|| shape_pass(isa, &view, black_box(&p8))));
        if isa == Isa::Avx512 {
            g.bench_function(BenchmarkId::new(isa.name(), 16), |b| b.iter(|| shape_pass(isa, &view, black_box(&p16))));
        }
        g.finish();
    }
    // The ray-sphere kernel alone (no dispatch on the primitive kind).
    let scene = kind_scene("sphere");
    let spheres = spheres_of(&scene.view());
    let mut g = c.benchmark_group("kernel/sphere-alone");
    g.throughput(Throughput::Elements(256 * 256 * spheres.len() as u64));
    g.bench_function(BenchmarkId::new(isa.name(), 1), |b| b.iter(|| sphere_pass(isa, &spheres, black_box(&p1))));
    g.bench_function(BenchmarkId::new(isa.name(), 8), |b| b.iter(|| sphere_pass(isa, &spheres, black_box(&p8))));
    if isa == Isa::Avx512 {
        g.bench_function(BenchmarkId::new(isa.name(), 16), |b| b.iter(|| sphere_pass(isa, &spheres, black_box(&p16))));
    }
    g.finish();
}

fn bench_grid(c: &mut Criterion) {
    let isa = Isa::best();
    let cam = camera(1024);
    let p8 = packets::<8>(&cam);
    let mut g = c.benchmark_group("primary_grid_1024");
    g.throughput(Throughput::Elements(1024 * 1024));
    g.sample_size(10);
    for n in [1, 16, 64, 256] {
        let scene = sphere_grid(n);
        let view = scene.view();
        g.bench_function(BenchmarkId::new(format!("{isa}_w8"), n), |b| {
            b.iter(|| scene_pass(isa, &view, &BruteForce, black_box(&p8)))
        });
    }
    g.finish();
}

fn bench_whitted(c: &mut Criterion) {
    let isa = Isa::best();
    let scene = demo_scene::<f32>().unwrap();
    let cam = demo_camera::<f32>(256, 256).unwrap();
    let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
    let r = Renderer::new(tracer, cam);
    let mut img = vec![[0u8; 3]; 256 * 256];
    let mut g = c.benchmark_group("whitted_demo_256");
    g.throughput(Throughput::Elements(256 * 256));
    g.bench_function(BenchmarkId::new(isa.name(), 1), |b| b.iter(|| render_pass::<_, 1>(isa, &r, &mut img)));
    g.bench_function(BenchmarkId::new(isa.name(), 4), |b| b.iter(|| render_pass::<_, 4>(isa, &r, &mut img)));
    g.bench_function(BenchmarkId::new(isa.name(), 8), |b| b.iter(|| render_pass::<_, 8>(isa, &r, &mut img)));
    g.finish();
}

type Big = raypack::scene::Scene<f32, 16384, 65536, 64, 16>;

fn bench_spd(c: &mut Criterion) {
    let isa = Isa::best();
    let mut g = c.benchmark_group("whitted_spd_256");
    g.throughput(Throughput::Elements(256 * 256));
    g.sample_size(10);
    for name in ["balls-2", "gears-2", "teapot-2"] {
        let path = format!("{}/tests/scenes/{name}.nff", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).unwrap();
        let mut scene: Box<Big> = Box::new(Big::new());
        let info = nff::parse(&text, &mut *scene).unwrap();
        let cam = info.camera.unwrap().camera::<f32>(256, 256).unwrap();
        let mut bvh: Box<Bvh<f32, 16384>> = Box::new(Bvh::new());
        bvh.build(&scene.view()).unwrap();
        let r = Renderer::new(
            Tracer::<f32, _>::with_accelerator(scene.view(), bvh.view(), TraceSettings::default()).unwrap(),
            cam,
        );
        let mut img = vec![[0u8; 3]; 256 * 256];
        g.bench_function(BenchmarkId::new(format!("{isa}_w8"), name), |b| {
            b.iter(|| render_pass::<_, 8>(isa, &r, &mut img))
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(2));
    targets = bench_kernels, bench_grid, bench_whitted, bench_spd
}
criterion_main!(benches);
