//! Not a user example: BVH against brute force on NFF scenes. For each file:
//! build time (best of 5), node counts, memory, and Whitted render times at
//! `size`² (width 8, one thread) with and without the tree, interleaved
//! (brute force once per round, BVH every round, best of `rounds`). Checks
//! that both images are the same bytes. Times are the thread's CPU time
//! (Linux), so a shared machine disturbs them less.
//!
//! `cargo run --release --example bvh_spd -- [size] [rounds] files...`
use raypack::nff;
use raypack::prelude::*;
use std::time::Instant;

type Big = Scene<f32, 16384, 65536, 64, 16>;
type BigBvh = Bvh<f32, 16384>;

/// On-CPU time of this thread in seconds (Linux `schedstat`), so that
/// other processes on a shared machine do not inflate the figures; wall
/// time where that file does not exist.
fn cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// Seconds spent in `f` (CPU time where available).
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let (c0, w0) = (cpu_seconds(), Instant::now());
    let r = f();
    let t = match (c0, cpu_seconds()) {
        (Some(a), Some(b)) if b > a => b - a,
        _ => w0.elapsed().as_secs_f64(),
    };
    (r, t)
}

fn render(view: &SceneView<'_, f32>, camera: Camera<f32>) -> (Vec<Rgb8>, RayStats, f64) {
    let tracer: Tracer<f32> = Tracer::new(*view, TraceSettings::default()).unwrap();
    let renderer = Renderer { tracer, camera, aov: Aov::Color };
    let (w, h) = (camera.width(), camera.height());
    let mut img = vec![[0u8; 3]; (w * h) as usize];
    let mut stats = RayStats::default();
    let ((), t) = timed(|| {
        // Bands of 8 rows, as a harness would.
        let mut y = 0;
        while y < h {
            let rows = 8.min(h - y);
            let band = &mut img[(y * w) as usize..((y + rows) * w) as usize];
            renderer.render_rect::<8>(Rect { x: 0, y, w, h: rows }, band, &mut stats).unwrap();
            y += rows;
        }
    });
    (img, stats, t)
}

/// Build settings, overridable for experiments with `BVH_LEAF`, `BVH_TRAV`
/// and `BVH_BINS`.
fn settings() -> BuildSettings {
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<f32>().ok());
    let mut s = BuildSettings::default();
    if let Some(v) = env("BVH_LEAF") {
        s.max_leaf = v as u32;
    }
    if let Some(v) = env("BVH_TRAV") {
        s.traversal_cost = v;
    }
    if let Some(v) = env("BVH_BINS") {
        s.bins = v as u32;
    }
    s
}

fn run(size: u32, rounds: u32, files: Vec<String>) {
    let mut scene: Box<Big> = Box::new(Big::new());
    let mut bvh: Box<BigBvh> = Box::new(BigBvh::new());
    // BVH_SKIP_BRUTE=1: tuning runs that only time the tree.
    let skip_brute = std::env::var("BVH_SKIP_BRUTE").is_ok();
    println!("{size}x{size}, Whitted, width 8, one thread; BVH best of {rounds}, brute force best of {}", rounds.div_ceil(3));
    println!(
        "{:<12} {:>6} {:>8} {:>6} {:>6} {:>5} {:>7} {:>9} {:>9} {:>9} {:>8}",
        "scene", "prims", "build ms", "nodes", "leaves", "depth", "maxleaf", "bytes", "brute s", "bvh s", "speedup"
    );
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{file}: {e}"));
        *scene = Big::new();
        let info = nff::parse(&text, &mut *scene).unwrap_or_else(|e| panic!("{file}: {e}"));
        let camera = info.camera.expect("camera").camera::<f32>(size, size).unwrap();
        let mut build = f64::MAX;
        let mut stats = BvhStats::default();
        for _ in 0..5 {
            let (s, t) = timed(|| bvh.build_with(&scene.view(), &settings()).unwrap());
            stats = s;
            build = build.min(t);
        }
        // Bytes the tree uses (nodes + the order array), not its capacity.
        let used = (stats.nodes as usize + 1) * std::mem::size_of::<raypack::bvh::BvhNode<f32>>() + stats.primitives as usize * 4;
        let brute = scene.view().without_bvh();
        let tree = scene.view().with_bvh(&bvh).unwrap();
        let (mut t_brute, mut t_bvh) = (f64::MAX, f64::MAX);
        let mut images = None;
        for round in 0..rounds {
            let (ib, sb, tb) = if round % 3 == 0 && !skip_brute { let r = render(&brute, camera); (Some(r.0), Some(r.1), r.2) } else { (None, None, f64::MAX) };
            let (it, st, tt) = render(&tree, camera);
            t_brute = t_brute.min(tb);
            t_bvh = t_bvh.min(tt);
            if let (Some(ib), Some(sb)) = (ib, sb) {
                assert!(ib == it, "{file}: images differ");
                assert_eq!(sb, st, "{file}: ray counts differ");
                images = Some(it);
            }
        }
        assert!(images.is_some() || skip_brute);
        let name = std::path::Path::new(&file).file_stem().unwrap().to_string_lossy().into_owned();
        println!(
            "{:<12} {:>6} {:>8.2} {:>6} {:>6} {:>5} {:>7} {:>9} {:>9.3} {:>9.3} {:>7.1}x",
            name,
            stats.primitives,
            build * 1e3,
            stats.nodes,
            stats.leaves,
            stats.depth,
            stats.max_leaf,
            used,
            if skip_brute { f64::NAN } else { t_brute },
            t_bvh,
            if skip_brute { f64::NAN } else { t_brute / t_bvh }
        );
    }
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let size: u32 = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(512);
    let rounds: u32 = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(3);
    let files: Vec<String> = a.iter().skip(3).cloned().collect();
    std::thread::Builder::new().stack_size(64 << 20).spawn(move || run(size, rounds, files)).unwrap().join().unwrap();
}
