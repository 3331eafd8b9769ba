//! Not a user example: whole-scene throughput of an NFF file (through the
//! BVH and the instruction-set dispatcher), for the performance figures in
//! the README and for thread scaling. Configurations run interleaved, best
//! of N rounds, so they share the machine's conditions.
//!
//! ```text
//! cargo run --release --example scene_probe -- SCENE.nff [SIZE] [ROUNDS] [WIDTH] [THREADS...]
//! ```
//! Defaults: 512 pixels square, 5 rounds, width 8, threads 1 and 2. Prints
//! one line per measurement: primary rays only (ray casting) and the full
//! Whitted render, for each thread count, with the best ISA.
use raypack::bvh::Bvh;
use raypack::dispatch::{self, Isa};
use raypack::nff;
use raypack::prelude::*;
use std::sync::Mutex;
use std::time::Instant;

type Big = Scene<f32, 16384, 65536, 64, 16>;

/// Renders the whole image with `threads` threads pulling bands of 8 rows
/// from a shared queue (each band is a disjoint slice of the image, so no
/// copying and no locking while tracing). Returns the rays traced.
fn render<const W: usize>(isa: Isa, r: &Renderer<'_, f32>, img: &mut [Rgb8], threads: usize) -> u64 {
    let width = r.camera.width() as usize;
    const BAND: usize = 8;
    let bands = Mutex::new(img.chunks_mut(width * BAND).enumerate());
    let total = Mutex::new(0u64);
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| {
                let mut stats = RayStats::default();
                loop {
                    let next = bands.lock().unwrap().next();
                    let Some((i, band)) = next else { break };
                    let h = (band.len() / width) as u32;
                    let rect = Rect { x: 0, y: (i * BAND) as u32, w: width as u32, h };
                    dispatch::render_rect::<f32, 8, W>(isa, r, rect, band, &mut stats).unwrap();
                }
                *total.lock().unwrap() += stats.total();
            });
        }
    });
    total.into_inner().unwrap()
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let Some(path) = a.get(1) else {
        eprintln!("usage: scene_probe SCENE.nff [SIZE] [ROUNDS] [WIDTH] [THREADS...]");
        std::process::exit(2);
    };
    let size: u32 = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(512);
    let rounds: u32 = a.get(3).and_then(|s| s.parse().ok()).unwrap_or(5);
    let width: usize = a.get(4).and_then(|s| s.parse().ok()).unwrap_or(8);
    let mut threads: Vec<usize> = a.iter().skip(5).filter_map(|s| s.parse().ok()).collect();
    if threads.is_empty() {
        threads = vec![1, 2];
    }
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut scene: Box<Big> = Box::new(Scene::new());
    let info = nff::parse(&text, &mut *scene).unwrap_or_else(|e| panic!("{path}: {e}"));
    let camera = info.camera.expect("the file has a camera").camera::<f32>(size, size).unwrap();
    let mut bvh: Box<Bvh<f32, 16384>> = Box::new(Bvh::new());
    let st = bvh.build(&scene.view()).unwrap();
    let view = scene.view().with_bvh(&bvh).unwrap();
    let isa = Isa::best();
    let name = std::path::Path::new(path).file_stem().unwrap().to_string_lossy().to_string();
    println!("# {name}: {} primitives, BVH {} nodes depth {}; best of {rounds} interleaved rounds; isa={isa}", scene.len(), st.nodes, st.depth);

    let mut configs = Vec::new();
    for mode in [Mode::Cast, Mode::Whitted] {
        for &t in &threads {
            configs.push((mode, t, f64::MAX, 0u64));
        }
    }
    let mut imgs: Vec<Vec<Rgb8>> = configs.iter().map(|_| vec![[0u8; 3]; (size * size) as usize]).collect();
    for _ in 0..rounds {
        for (c, img) in configs.iter_mut().zip(imgs.iter_mut()) {
            let settings = TraceSettings { mode: c.0, ..TraceSettings::default() };
            let r = Renderer::new(Tracer::new(view, settings).unwrap(), camera);
            let start = Instant::now();
            c.3 = match width {
                1 => render::<1>(isa, &r, img, c.1),
                4 => render::<4>(isa, &r, img, c.1),
                16 => render::<16>(isa, &r, img, c.1),
                _ => render::<8>(isa, &r, img, c.1),
            };
            c.2 = c.2.min(start.elapsed().as_secs_f64());
        }
    }
    for (i, c) in configs.iter().enumerate() {
        let one = configs.iter().find(|o| o.0 == c.0 && o.1 == 1).map(|o| o.2);
        let what = if c.0 == Mode::Cast { "primary" } else { "whitted" };
        print!(
            "scene={name} size={size} mode={what} isa={isa} width={width} threads={} best_s={:.4} rays={} rays_per_s={:.4e}",
            c.1, c.2, c.3, c.3 as f64 / c.2
        );
        if let Some(t1) = one {
            print!(" speedup_vs_1_thread={:.2}", t1 / c.2);
        }
        println!();
        // Same bytes whatever the thread count.
        let same = configs.iter().position(|o| o.0 == c.0).unwrap();
        assert!(imgs[i] == imgs[same], "thread counts disagree");
    }
}
