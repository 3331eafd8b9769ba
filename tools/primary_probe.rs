//! Not a user example: fixed workloads for width and instruction-set
//! comparisons on a noisy, shared machine, and for profilers. Every
//! configuration (instruction set × packet width 1, 4, 8, 16) of a workload runs once
//! per round, interleaved, for many rounds; the best time of each is
//! reported, so all configurations see the same machine conditions.
//!
//! ```text
//! cargo run --release --example primary_probe -- WORKLOAD [ROUNDS]
//!   scene    primary rays vs 16 spheres, 256×256 (the historical figure)
//!   kernel   the bare ray-sphere kernel, 256×256 rays vs 16 spheres:
//!            through `Shape::roots` (the kind dispatch the tracer uses)
//!            and `Sphere::roots` alone
//!   grid     primary rays vs N = 1, 16, 64, 256 spheres, 1024×1024
//!   grid-bvh the same grids and N = 1024 through a BVH
//!   kinds    the bare kernel of each primitive kind, 256×256 rays vs 16 of it
//!   render   Whitted render of the demo scene, 256×256
//! ```
//! Output: one line per measurement, `key=value` fields.
#[path = "../benches/workloads/mod.rs"]
mod workloads;

use raypack::demo::{demo_camera, demo_scene};
use raypack::dispatch::Isa;
use raypack::prelude::*;
use std::hint::black_box;
use std::time::Instant;
use workloads::*;

/// One configuration: a label and a pass returning a checksum.
struct Config<'a> {
    isa: Isa,
    width: usize,
    pass: Box<dyn FnMut() -> u64 + 'a>,
    best: f64,
    check: u64,
}

fn config<'a>(isa: Isa, width: usize, pass: impl FnMut() -> u64 + 'a) -> Config<'a> {
    Config { isa, width, pass: Box::new(pass), best: f64::MAX, check: 0 }
}

/// Runs the configurations interleaved for `rounds` rounds, checks that they
/// agree, and prints one line each: items per second and the ratio to the
/// width-1 baseline-ISA configuration.
fn measure(workload: &str, unit: &str, items: f64, rounds: u32, configs: &mut [Config<'_>]) {
    for _ in 0..rounds {
        for c in configs.iter_mut() {
            let start = Instant::now();
            c.check = black_box((c.pass)());
            c.best = c.best.min(start.elapsed().as_secs_f64());
        }
    }
    let check = configs[0].check;
    assert!(configs.iter().all(|c| c.check == check), "configurations disagree");
    let base = configs.iter().find(|c| c.width == 1 && c.isa == Isa::Baseline).map(|c| c.best);
    let w1 = |isa: Isa| configs.iter().find(|c| c.width == 1 && c.isa == isa).map(|c| c.best);
    for c in configs.iter() {
        let rate = items / c.best;
        print!("{workload} isa={} width={} {unit}_per_s={:.4e} best_s={:.6}", c.isa, c.width, rate, c.best);
        if let Some(t1) = w1(c.isa) {
            print!(" vs_width1_same_isa={:.2}", t1 / c.best);
        }
        if let Some(b) = base {
            print!(" vs_baseline_width1={:.2}", b / c.best);
        }
        println!();
    }
}

fn isas() -> Vec<Isa> {
    let v: Vec<Isa> = Isa::ALL.into_iter().filter(|i| i.is_available()).collect();
    for i in Isa::ALL {
        if !i.is_available() {
            println!("# {i} not available on this CPU: skipped");
        }
    }
    v
}

fn scene_workload(name: &str, n: usize, size: u32, rounds: u32, with_bvh: bool) {
    let scene = sphere_grid(n);
    let mut bvh: Box<Bvh<f32, 1024>> = Box::new(Bvh::new());
    let view = scene.view();
    let accel = if with_bvh {
        bvh.build(&scene.view()).unwrap();
        AccelChoice::Bvh(bvh.view())
    } else {
        AccelChoice::BruteForce
    };
    let name = if with_bvh { format!("{name} accel=bvh") } else { name.to_string() };
    let cam = camera(size);
    let (p1, p4, p8, p16) = (packets::<1>(&cam), packets::<4>(&cam), packets::<8>(&cam), packets::<16>(&cam));
    let (view, accel, p1, p4, p8, p16) = (&view, &accel, &p1, &p4, &p8, &p16);
    let mut cs = Vec::new();
    for isa in isas() {
        cs.push(config(isa, 1, move || scene_pass(isa, view, accel, black_box(p1)) as u64));
        cs.push(config(isa, 4, move || scene_pass(isa, view, accel, black_box(p4)) as u64));
        cs.push(config(isa, 8, move || scene_pass(isa, view, accel, black_box(p8)) as u64));
        cs.push(config(isa, 16, move || scene_pass(isa, view, accel, black_box(p16)) as u64));
    }
    measure(&format!("{name} spheres={n} size={size}"), "rays", (size * size) as f64, rounds, &mut cs);
}

fn kind_workload(kind: &str, rounds: u32) {
    let scene = kind_scene(kind);
    let view = scene.view();
    let cam = camera(256);
    let (p1, p4, p8, p16) = (packets::<1>(&cam), packets::<4>(&cam), packets::<8>(&cam), packets::<16>(&cam));
    let (view, p1, p4, p8, p16) = (&view, &p1, &p4, &p8, &p16);
    let mut cs = Vec::new();
    for isa in isas() {
        cs.push(config(isa, 1, move || shape_pass(isa, view, black_box(p1)) as u64));
        cs.push(config(isa, 4, move || shape_pass(isa, view, black_box(p4)) as u64));
        cs.push(config(isa, 8, move || shape_pass(isa, view, black_box(p8)) as u64));
        cs.push(config(isa, 16, move || shape_pass(isa, view, black_box(p16)) as u64));
    }
    let tests = 65536.0 * view.primitives().len() as f64;
    measure(&format!("kernel kind={kind} prims=16 size=256"), "tests", tests, rounds, &mut cs);
}

fn sphere_kernel_workload(rounds: u32) {
    let scene = kind_scene("sphere");
    let view = scene.view();
    let spheres = spheres_of(&view);
    let cam = camera(256);
    let (p1, p4, p8, p16) = (packets::<1>(&cam), packets::<4>(&cam), packets::<8>(&cam), packets::<16>(&cam));
    let (s, p1, p4, p8, p16) = (&spheres[..], &p1, &p4, &p8, &p16);
    let mut cs = Vec::new();
    for isa in isas() {
        cs.push(config(isa, 1, move || sphere_pass(isa, s, black_box(p1)) as u64));
        cs.push(config(isa, 4, move || sphere_pass(isa, s, black_box(p4)) as u64));
        cs.push(config(isa, 8, move || sphere_pass(isa, s, black_box(p8)) as u64));
        cs.push(config(isa, 16, move || sphere_pass(isa, s, black_box(p16)) as u64));
    }
    let tests = 65536.0 * spheres.len() as f64;
    measure(&format!("kernel kind=sphere-alone prims={} size=256", spheres.len()), "tests", tests, rounds, &mut cs);
}

fn render_workload(rounds: u32) {
    let scene = demo_scene::<f32>().unwrap();
    let cam = demo_camera::<f32>(256, 256).unwrap();
    let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
    let r = Renderer::new(tracer, cam);
    let mut imgs: Vec<Vec<Rgb8>> = (0..16).map(|_| vec![[0u8; 3]; 256 * 256]).collect();
    let mut it = imgs.iter_mut();
    let mut cs = Vec::new();
    for isa in isas() {
        let (a, b, c, d) = (it.next().unwrap(), it.next().unwrap(), it.next().unwrap(), it.next().unwrap());
        let r = &r;
        cs.push(config(isa, 1, move || render_pass::<_, 1>(isa, r, a)));
        cs.push(config(isa, 4, move || render_pass::<_, 4>(isa, r, b)));
        cs.push(config(isa, 8, move || render_pass::<_, 8>(isa, r, c)));
        cs.push(config(isa, 16, move || render_pass::<_, 16>(isa, r, d)));
    }
    measure("render scene=demo size=256 threads=1", "pixels", 65536.0, rounds, &mut cs);
    drop(cs);
    let n = 4 * Isa::ALL.iter().filter(|i| i.is_available()).count();
    assert!(imgs.iter().take(n).all(|i| *i == imgs[0]), "images differ");
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let workload = a.get(1).map(String::as_str).unwrap_or("scene");
    let rounds: u32 = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(30);
    println!("# best of {rounds} interleaved rounds; best ISA here: {}", Isa::best());
    match workload {
        "scene" => scene_workload("primary", 16, 256, rounds, false),
        "kernel" => {
            kind_workload("sphere", rounds);
            sphere_kernel_workload(rounds);
        }
        "grid" => {
            for n in [1, 16, 64, 256] {
                scene_workload("primary", n, 1024, rounds, false);
            }
        }
        "kinds" => {
            for k in KINDS {
                kind_workload(k, rounds);
            }
        }
        "grid-bvh" => {
            for n in [1, 16, 64, 256, 1024] {
                scene_workload("primary", n, 1024, rounds, true);
            }
        }
        "render" => render_workload(rounds),
        other => {
            eprintln!("unknown workload {other}: scene, kernel, grid, grid-bvh, kinds or render");
            std::process::exit(2);
        }
    }
}
