//! Shared helpers for the integration tests: a seeded RNG and random scenes.
#![allow(dead_code)]

use raypack::prelude::*;
use raypack::primitives::{AaBox, Cone, OrientedBox, Plane, Quadric, Sphere};

/// SplitMix64: a tiny, seeded, reproducible generator.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let u = (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
        lo + (hi - lo) * u
    }
    pub fn below(&mut self, n: u32) -> u32 {
        (self.next_u64() % n as u64) as u32
    }
    pub fn vec(&mut self, lo: f32, hi: f32) -> Vec3<f32> {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
    pub fn unit(&mut self) -> Vec3<f32> {
        loop {
            let v = self.vec(-1.0, 1.0);
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v.scale(1.0 / l);
            }
        }
    }
}

pub type TestScene = Scene<f32, 48, 512, 16, 4>;

/// A random primitive of kind `k` (0..=8, see the match).
pub fn random_shape(rng: &mut Rng, scene: &mut TestScene, k: u32, mat: u16) {
    let c = rng.vec(-3.0, 3.0);
    let r = match k {
        0 => scene.add_shape(Shape::Sphere(Sphere::new(c, rng.range(0.2, 1.5)).unwrap()), mat),
        1 => {
            let n = rng.unit();
            scene.add_shape(Shape::Plane(Plane::from_point_normal(c.scale(2.0), n).unwrap()), mat)
        }
        2 | 3 => {
            // A polygon in a random plane: convex (regular) or star-shaped (random radii).
            let n = rng.unit();
            let (u, v) = n.orthonormal_basis();
            let count = 3 + rng.below(6);
            let convex = k == 2;
            let base = rng.range(0.5, 2.0);
            let verts: Vec<Vec3<f32>> = (0..count)
                .map(|i| {
                    let a = i as f32 / count as f32 * std::f32::consts::TAU;
                    let rad = if convex { base } else { base * rng.range(0.3, 1.0) };
                    c + u.scale(rad * a.cos()) + v.scale(rad * a.sin())
                })
                .collect();
            if rng.below(2) == 0 {
                scene.add_polygon(&verts, mat)
            } else {
                let normals: Vec<Vec3<f32>> = verts.iter().map(|_| (n + rng.vec(-0.3, 0.3)).normalize_or_zero()).collect();
                scene.add_patch(&verts, &normals, mat)
            }
        }
        4 => scene.add_shape(Shape::AaBox(AaBox::new(c, c + rng.vec(0.2, 2.0)).unwrap()), mat),
        5 => {
            let u = rng.unit();
            let v = rng.unit();
            match OrientedBox::new(c, rng.vec(0.2, 1.0), u, v) {
                Ok(b) => scene.add_shape(Shape::OrientedBox(b), mat),
                Err(_) => return,
            }
        }
        6 => {
            let axis = rng.unit();
            let q = match rng.below(6) {
                0 => Quadric::ellipsoid(c, rng.vec(0.3, 1.5)),
                1 => Quadric::cylinder(c, axis, rng.range(0.2, 1.0)),
                2 => Quadric::cone(c, axis, rng.range(0.2, 1.0)),
                3 => Quadric::paraboloid(c, axis, rng.range(0.1, 1.0)),
                4 => Quadric::hyperboloid_one_sheet(c, axis, rng.range(0.2, 1.0), rng.range(0.3, 1.5)),
                _ => Quadric::hyperboloid_two_sheets(c, axis, rng.range(0.2, 1.0), rng.range(0.3, 1.5)),
            }
            .unwrap();
            let q = if rng.below(2) == 0 { q.with_clip(c - rng.vec(0.5, 2.0), c + rng.vec(0.5, 2.0)).unwrap() } else { q };
            scene.add_shape(Shape::Quadric(q), mat)
        }
        _ => {
            let apex = c + rng.unit().scale(rng.range(0.5, 2.5));
            let rb = rng.range(0.0, 1.0);
            let ra = if rng.below(3) == 0 { rb } else { rng.range(0.0, 1.0) };
            match Cone::new(c, rb + 0.05, apex, ra) {
                Ok(cn) => scene.add_shape(Shape::Cone(cn), mat),
                Err(_) => return,
            }
        }
    };
    r.unwrap();
}

/// A random scene of `n` primitives of every kind, with random materials
/// (some mirrors, some glass) and lights.
pub fn random_scene(rng: &mut Rng, n: usize) -> TestScene {
    let mut s = TestScene::new();
    s.set_background(rng.vec(0.0, 0.5)).unwrap();
    for _ in 0..6 {
        let m = Material {
            color: rng.vec(0.1, 1.0),
            ka: rng.range(0.0, 0.2),
            kd: rng.range(0.2, 0.9),
            ks: rng.range(0.0, 0.8),
            shine: rng.range(1.0, 100.0),
            kr: if rng.below(3) == 0 { rng.range(0.2, 0.9) } else { 0.0 },
            kt: if rng.below(3) == 0 { rng.range(0.2, 0.9) } else { 0.0 },
            ior: rng.range(1.0, 2.0),
        };
        s.add_material(m).unwrap();
    }
    for i in 0..n {
        let k = (i as u32) % 9;
        let mat = rng.below(6) as u16;
        random_shape(rng, &mut s, k, mat);
    }
    for _ in 0..1 + rng.below(3) {
        s.add_light(rng.vec(-8.0, 8.0), rng.vec(0.2, 1.0)).unwrap();
    }
    s
}

/// A camera looking at the origin from a random direction.
pub fn random_camera(rng: &mut Rng, w: u32, h: u32) -> Camera<f32> {
    let eye = rng.unit().scale(rng.range(8.0, 14.0));
    Camera::new(eye, rng.vec(-0.5, 0.5), Vec3::new(0.0, 0.0, 1.0), rng.range(30.0, 70.0), w, h).unwrap()
}

/// Renders a whole image with packet width `W`, tile by tile.
pub fn render<const W: usize>(scene: &SceneView<'_, f32>, camera: Camera<f32>, settings: TraceSettings<f32>, aov: Aov, tile: u32) -> (Vec<Rgb8>, RayStats) {
    let tracer: Tracer<f32> = Tracer::new(*scene, settings).unwrap();
    let renderer = Renderer { tracer, camera, aov };
    let (w, h) = (camera.width(), camera.height());
    let mut img = vec![[0u8; 3]; (w * h) as usize];
    let mut stats = RayStats::default();
    let mut buf = vec![[0u8; 3]; (tile * tile) as usize];
    let mut y = 0;
    while y < h {
        let mut x = 0;
        while x < w {
            let rect = Rect { x, y, w: tile.min(w - x), h: tile.min(h - y) };
            renderer.render_rect::<W>(rect, &mut buf, &mut stats).unwrap();
            for j in 0..rect.h {
                for i in 0..rect.w {
                    img[((y + j) * w + x + i) as usize] = buf[(j * rect.w + i) as usize];
                }
            }
            x += tile;
        }
        y += tile;
    }
    (img, stats)
}
