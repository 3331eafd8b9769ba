//! Not a user example: primary-ray throughput against a k×k grid of spheres
//! (N = k² spheres filling the view), with the BVH and by brute force, on
//! one thread. Packets are generated once; passes run interleaved, best of
//! `rounds` in thread CPU time (Linux), so both see the same machine
//! conditions. Also checks that both give the same hits.
//!
//! `cargo run --release --example bvh_probe -- [size] [rounds] [N...]`
//! (defaults: 1024, 5, N = 16 64 256 1024)
use raypack::lanes::{Lanes, Mask};
use raypack::prelude::*;
use raypack::ray::RayPacket;
use std::hint::black_box;
use std::time::Instant;

type Packets<const W: usize> = Vec<(RayPacket<f32, W>, Mask<W>)>;

/// The camera's packets, generated once (so passes time intersection only).
fn packets<const W: usize>(cam: &Camera<f32>, size: u32) -> Packets<W> {
    let (pw, ph) = raypack::camera::packet_shape(W);
    let mut ps = Vec::new();
    for y in (0..size).step_by(ph as usize) {
        for x in (0..size).step_by(pw as usize) {
            ps.push(cam.packet::<W>(x, y, cam.full_rect()));
        }
    }
    ps
}

#[inline(never)]
fn pass<const W: usize>(view: &SceneView<'_, f32>, tree: &BvhView<'_, f32>, ps: &Packets<W>, brute: bool) -> u64 {
    let mut checksum = 0u64;
    for (r, m) in ps {
        let h = if brute {
            BruteForce.closest_hit(view, r, Lanes::zero(), Lanes::splat(f32::MAX), *m)
        } else {
            tree.closest_hit(view, r, Lanes::zero(), Lanes::splat(f32::MAX), *m)
        };
        for l in 0..W {
            if h.mask.get(l) {
                checksum = checksum.wrapping_add((h.prim[l] as u64) << 32 ^ h.t.0[l].to_bits() as u64);
            }
        }
    }
    checksum
}

/// On-CPU time of this thread in seconds (Linux `schedstat`): other
/// processes on a shared machine inflate it much less than wall time.
fn cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    Some(s.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
}

fn best(t: &mut f64, f: impl FnOnce() -> u64) -> u64 {
    let (c0, start) = (cpu_seconds(), Instant::now());
    let h = f();
    let dt = match (c0, cpu_seconds()) {
        (Some(a), Some(b)) if b > a => b - a,
        _ => start.elapsed().as_secs_f64(),
    };
    *t = t.min(dt);
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
        let (view, tree) = (scene.view(), bvh.view());
        let (p8, p1) = (packets::<8>(&cam, size), packets::<1>(&cam, size));
        let mut t = [f64::MAX; 3];
        let mut sums = [0u64; 3];
        for round in 0..rounds {
            sums[0] = best(&mut t[0], || pass::<8>(black_box(&view), &tree, &p8, false));
            sums[1] = best(&mut t[1], || pass::<1>(black_box(&view), &tree, &p1, false));
            // Brute force at large N is slow: fewer rounds there.
            if n <= 256 || round == 0 {
                sums[2] = best(&mut t[2], || pass::<8>(black_box(&view), &tree, &p8, true));
            }
        }
        assert_eq!(sums[0], sums[2], "BVH and brute force disagree");
        assert_eq!(sums[0], sums[1], "widths disagree");
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
