//! Not a user example: primary-ray throughput against a k×k grid of spheres
//! (N = k² spheres filling the view), with the BVH and by brute force, on
//! one thread. Passes run interleaved, best of `rounds`, so both see the same
//! machine conditions. Also checks that both give the same hits.
//!
//! `cargo run --release --example bvh_probe -- [size] [rounds] [N...]`
//! (defaults: 1024, 5, N = 16 64 256 1024)
use raypack::prelude::*;
use std::hint::black_box;
use std::time::Instant;

#[inline(never)]
fn pass<const W: usize>(view: &SceneView<'_, f32>, cam: &Camera<f32>, size: u32, brute: bool) -> u64 {
    let (pw, ph) = raypack::camera::packet_shape(W);
    let mut checksum = 0u64;
    for y in (0..size).step_by(ph as usize) {
        for x in (0..size).step_by(pw as usize) {
            let (r, m) = cam.packet::<W>(x, y, cam.full_rect());
            let h = if brute {
                view.closest_hit_brute_force(&r, Lanes::zero(), Lanes::splat(f32::MAX), m)
            } else {
                view.closest_hit(&r, Lanes::zero(), Lanes::splat(f32::MAX), m)
            };
            for l in 0..W {
                if h.mask.get(l) {
                    checksum = checksum.wrapping_mul(31).wrapping_add(h.prim[l] as u64 ^ h.t.0[l].to_bits() as u64);
                }
            }
        }
    }
    checksum
}

fn best(t: &mut f64, f: impl FnOnce() -> u64) -> u64 {
    let start = Instant::now();
    let h = f();
    *t = t.min(start.elapsed().as_secs_f64());
    h
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let size: u32 = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(1024);
    let rounds: u32 = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    let mut ns: Vec<usize> = a.iter().skip(3).filter_map(|s| s.parse().ok()).collect();
    if ns.is_empty() {
        ns = vec![16, 64, 256, 1024];
    }
    println!("{size}x{size} primary rays, one thread, best of {rounds} interleaved rounds");
    println!("{:>6} {:>9} {:>7} {:>11} {:>11} {:>11} {:>8}", "N", "build ms", "nodes", "bvh w8", "bvh w1", "brute w8", "speedup");
    for &n in &ns {
        let k = (n as f64).sqrt().round() as usize;
        let mut scene: Box<Scene<f32, 4096, 8>> = Box::new(Scene::new());
        let m = scene.add_material(Material::diffuse(Vec3::new(0.8, 0.6, 0.4))).unwrap();
        let half = (k as f32 - 1.0) * 0.5;
        for i in 0..k {
            for j in 0..k {
                scene.add_sphere(Vec3::new(2.0 * (i as f32 - half), 2.0 * (j as f32 - half), 0.0), 0.9, m).unwrap();
            }
        }
        // Distance so that the grid (2k wide) just fills a 40° view.
        let cam = Camera::new(Vec3::new(0.0, 0.0, 2.75 * k as f32 + 1.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 40.0, size, size).unwrap();
        let mut bvh: Box<Bvh<f32, 4096>> = Box::new(Bvh::new());
        let start = Instant::now();
        let stats = bvh.build(&scene.view()).unwrap();
        let build_ms = start.elapsed().as_secs_f64() * 1e3;
        let view = scene.view().with_bvh(&bvh).unwrap();
        let mut t = [f64::MAX; 3];
        let mut sums = [0u64; 3];
        for round in 0..rounds {
            sums[0] = best(&mut t[0], || pass::<8>(black_box(&view), &cam, size, false));
            sums[1] = best(&mut t[1], || pass::<1>(black_box(&view), &cam, size, false));
            // Brute force at large N is slow: fewer rounds there.
            if n <= 256 || round == 0 {
                sums[2] = best(&mut t[2], || pass::<8>(black_box(&view), &cam, size, true));
            }
        }
        assert_eq!(sums[0], sums[2], "BVH and brute force disagree");
        let rays = (size as f64) * (size as f64);
        let mr = |t: f64| rays / t / 1e6;
        println!(
            "{:>6} {:>9.2} {:>7} {:>6.1} Mr/s {:>6.1} Mr/s {:>6.1} Mr/s {:>7.1}x",
            n,
            build_ms,
            stats.nodes,
            mr(t[0]),
            mr(t[1]),
            mr(t[2]),
            t[2] / t[0]
        );
    }
}
