//! Host speed of the Q8.24 fixed point (`Fixed32`) against `f32`: the
//! Whitted render of the demo scene (the fixed-point one converted into its
//! frame, as firmware builds it), packet widths 1 and 8, the four
//! configurations interleaved round by round, best of N rounds each, with
//! the ratios.
//!
//! ```sh
//! cargo run --release --example fixed_speed -- [WIDTH HEIGHT ROUNDS]
//! ```
use raypack::demo::{build_demo_scene_for, demo_camera, demo_camera_for, demo_scene, DemoScene};
use raypack::prelude::*;
use raypack::Fixed32;
use std::time::Instant;

fn time<S: Scalar, const L: usize>(renderer: &Renderer<'_, S>, img: &mut [Rgb8]) -> (f64, u64) {
    let mut stats = RayStats::default();
    let t = Instant::now();
    renderer.render_rect::<L>(renderer.camera.full_rect(), img, &mut stats).unwrap();
    (t.elapsed().as_secs_f64(), stats.total())
}

fn checksum(img: &[Rgb8]) -> u64 {
    // FNV-1a over the bytes.
    img.iter().flatten().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x100_0000_01b3))
}

fn main() {
    let a: Vec<u32> = std::env::args().skip(1).filter_map(|s| s.parse().ok()).collect();
    let (w, h, rounds) = (*a.first().unwrap_or(&160), *a.get(1).unwrap_or(&120), *a.get(2).unwrap_or(&10));
    let sf = demo_scene::<f32>().unwrap();
    let mut sx = Box::new(DemoScene::<Fixed32>::new());
    let mut described = Box::new(DemoScene::<f32>::new());
    let frame = build_demo_scene_for(&mut sx, &mut described).unwrap();
    let rf =
        Renderer::new(Tracer::<f32>::new(sf.view(), TraceSettings::default()).unwrap(), demo_camera(w, h).unwrap());
    let rx = Renderer::new(
        Tracer::<Fixed32>::new(sx.view(), TraceSettings::default()).unwrap(),
        demo_camera_for(&frame, w, h).unwrap(),
    );
    let mut img = vec![[0u8; 3]; (w * h) as usize];
    let mut best = [f64::MAX; 4];
    let mut rays = [0u64; 4];
    for _ in 0..rounds {
        let r = [
            time::<f32, 1>(&rf, &mut img),
            time::<f32, 8>(&rf, &mut img),
            time::<Fixed32, 1>(&rx, &mut img),
            time::<Fixed32, 8>(&rx, &mut img),
        ];
        for i in 0..4 {
            best[i] = best[i].min(r[i].0);
            rays[i] = r[i].1;
        }
    }
    let _ = time::<Fixed32, 8>(&rx, &mut img);
    let fixed_sum = checksum(&img);
    let names = ["f32 width 1", "f32 width 8", "fixed width 1", "fixed width 8"];
    println!("demo scene {w}×{h}, Whitted, best of {rounds} interleaved rounds:");
    for i in 0..4 {
        println!("  {:<14} {:8.2} ms  {:7.2} M rays/s", names[i], best[i] * 1e3, rays[i] as f64 / best[i] / 1e6);
    }
    println!("  fixed/f32 time: width 1 {:.2}×, width 8 {:.2}×", best[2] / best[0], best[3] / best[1]);
    println!("  width 8 speed-up: f32 {:.2}×, fixed {:.2}×", best[0] / best[1], best[2] / best[3]);
    println!("  fixed-point image checksum (FNV-1a of RGB bytes): {fixed_sum:016x}");
}
