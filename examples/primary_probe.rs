//! Not a user example: a fixed workload for profilers (perf, callgrind) and
//! for width comparisons on a noisy machine. Runs widths 1, 4 and 8
//! interleaved, many times, and reports the best time of each, so all widths
//! see the same machine conditions within one run.
//!
//! `cargo run --release --example primary_probe -- [scene|kernel] [rounds]`
use raypack::prelude::*;
use raypack::primitives::Sphere;
use std::hint::black_box;
use std::time::Instant;

const SIZE: u32 = 256;

fn camera() -> Camera<f32> {
    Camera::new(Vec3::new(0.0, 0.0, 12.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 40.0, SIZE, SIZE).unwrap()
}

fn packets<const W: usize>(cam: &Camera<f32>) -> Vec<(RayPacket<f32, W>, Mask<W>)> {
    let (pw, ph) = raypack::camera::packet_shape(W);
    let mut ps = Vec::new();
    for y in (0..SIZE).step_by(ph as usize) {
        for x in (0..SIZE).step_by(pw as usize) {
            ps.push(cam.packet::<W>(x, y, cam.full_rect()));
        }
    }
    ps
}

#[inline(never)]
fn scene_pass<const W: usize>(view: &SceneView<'_, f32>, ps: &[(RayPacket<f32, W>, Mask<W>)]) -> u32 {
    ps.iter()
        .map(|(r, m)| view.closest_hit(r, Lanes::zero(), Lanes::splat(f32::MAX), *m).mask.count())
        .sum()
}

#[inline(never)]
fn kernel_pass<const W: usize>(s: &Sphere<f32>, ps: &[(RayPacket<f32, W>, Mask<W>)]) -> u32 {
    ps.iter()
        .map(|(r, m)| s.roots(r, Lanes::zero(), Lanes::splat(f32::MAX), *m).hit0.count())
        .sum()
}

fn best(t: &mut f64, f: impl FnOnce() -> u32) -> u32 {
    let start = Instant::now();
    let h = f();
    *t = t.min(start.elapsed().as_secs_f64());
    h
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let kernel = a.get(1).map(|s| s == "kernel").unwrap_or(false);
    let rounds: u32 = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(30);
    let mut s: Scene<f32, 32, 8> = Scene::new();
    let m = s.add_material(Material::diffuse(Vec3::new(0.8, 0.6, 0.4))).unwrap();
    for i in 0..4 {
        for j in 0..4 {
            s.add_sphere(Vec3::new(-3.0 + 2.0 * i as f32, -3.0 + 2.0 * j as f32, 0.0), 0.9, m).unwrap();
        }
    }
    let view = s.view();
    let sphere = Sphere::new(Vec3::new(0.5, -0.3, 0.0), 2.5).unwrap();
    let cam = camera();
    let (p1, p4, p8) = (packets::<1>(&cam), packets::<4>(&cam), packets::<8>(&cam));
    let mut t = [f64::MAX; 3];
    let mut hits = [0; 3];
    for _ in 0..rounds {
        if kernel {
            hits[0] = best(&mut t[0], || kernel_pass(black_box(&sphere), black_box(&p1)));
            hits[1] = best(&mut t[1], || kernel_pass(black_box(&sphere), black_box(&p4)));
            hits[2] = best(&mut t[2], || kernel_pass(black_box(&sphere), black_box(&p8)));
        } else {
            hits[0] = best(&mut t[0], || scene_pass(black_box(&view), black_box(&p1)));
            hits[1] = best(&mut t[1], || scene_pass(black_box(&view), black_box(&p4)));
            hits[2] = best(&mut t[2], || scene_pass(black_box(&view), black_box(&p8)));
        }
    }
    assert!(hits[0] == hits[1] && hits[1] == hits[2]);
    let what = if kernel { "ray-sphere kernel (1 sphere)" } else { "primary rays vs 16 spheres" };
    let rays = (SIZE * SIZE) as f64;
    for (i, w) in [1, 4, 8].iter().enumerate() {
        println!("{what}: width {w}: {:7.1} Mrays/s  ({:.2}x width 1)", rays / t[i] / 1e6, t[0] / t[i]);
    }
}
