//! Shared helpers for the integration tests: a seeded RNG and random scenes.
#![allow(dead_code)]

use raypack::dispatch::Isa;
use raypack::image::{render_tiles, Tiling};
use raypack::prelude::*;
use raypack::primitives::{AaBox, Cone, OrientedBox, Plane, Quadric, Shape, Sphere};

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

/// The random test scenes' capacities, for any scalar.
pub type TestSceneOf<S> = Scene<S, 48, 512, 16, 4>;
pub type TestScene = TestSceneOf<f32>;

/// An `f32` vector (what the generator draws) converted to the scalar `S`
/// (the identity for `f32`).
pub fn cv<S: Scalar>(v: Vec3<f32>) -> Vec3<S> {
    Vec3::from_f32(v.x, v.y, v.z)
}

/// A random primitive of kind `k` (0..=8, see the match).
pub fn random_shape(rng: &mut Rng, scene: &mut TestScene, k: u32, mat: u16) {
    random_shape_in::<f32>(rng, scene, k, mat)
}

/// [`random_shape`] for any scalar: the same draws from `rng`, computed in
/// `f32` and converted where they enter the scene, so the `f32` scene is
/// bit-identical to the one [`random_shape`] always built.
pub fn random_shape_in<S: Scalar>(rng: &mut Rng, scene: &mut TestSceneOf<S>, k: u32, mat: u16) {
    let c = rng.vec(-3.0, 3.0);
    let f = S::from_f32;
    let r = match k {
        0 => scene.add_shape(Shape::Sphere(Sphere::new(cv(c), f(rng.range(0.2, 1.5))).unwrap()), mat),
        1 => {
            let n = rng.unit();
            scene.add_shape(Shape::Plane(Plane::from_point_normal(cv(c.scale(2.0)), cv(n)).unwrap()), mat)
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
            let verts_s: Vec<Vec3<S>> = verts.iter().map(|&v| cv(v)).collect();
            if rng.below(2) == 0 {
                scene.add_polygon(&verts_s, mat)
            } else {
                let normals: Vec<Vec3<S>> =
                    verts.iter().map(|_| cv((n + rng.vec(-0.3, 0.3)).normalize_or_zero())).collect();
                scene.add_patch(&verts_s, &normals, mat)
            }
        }
        4 => scene.add_shape(Shape::AaBox(AaBox::new(cv(c), cv(c + rng.vec(0.2, 2.0))).unwrap()), mat),
        5 => {
            let u = rng.unit();
            let v = rng.unit();
            match OrientedBox::new(cv(c), cv(rng.vec(0.2, 1.0)), cv(u), cv(v)) {
                Ok(b) => scene.add_shape(Shape::OrientedBox(b), mat),
                Err(_) => return,
            }
        }
        6 => {
            let axis = rng.unit();
            let (cs, axs) = (cv::<S>(c), cv::<S>(axis));
            let q = match rng.below(6) {
                0 => {
                    // Axis-aligned or turned (about the drawn axis), from the
                    // same draws.
                    let radii = rng.vec(0.3, 1.5);
                    if radii.x < 0.9 {
                        let (u, v) = axis.orthonormal_basis();
                        Quadric::ellipsoid_oriented(cs, cv(radii), cv(u), cv(v), axs)
                    } else {
                        Quadric::ellipsoid(cs, cv(radii))
                    }
                }
                1 => Quadric::cylinder(cs, axs, f(rng.range(0.2, 1.0))),
                2 => Quadric::cone(cs, axs, rng.range(0.2, 1.0)),
                3 => Quadric::paraboloid(cs, axs, f(rng.range(0.1, 1.0))),
                4 => Quadric::hyperboloid_one_sheet(cs, axs, f(rng.range(0.2, 1.0)), f(rng.range(0.3, 1.5))),
                _ => Quadric::hyperboloid_two_sheets(cs, axs, f(rng.range(0.2, 1.0)), f(rng.range(0.3, 1.5))),
            }
            .unwrap();
            let q = if rng.below(2) == 0 {
                q.with_clip(cv(c - rng.vec(0.5, 2.0)), cv(c + rng.vec(0.5, 2.0))).unwrap()
            } else {
                q
            };
            scene.add_shape(Shape::Quadric(q), mat)
        }
        _ => {
            let apex = c + rng.unit().scale(rng.range(0.5, 2.5));
            let rb = rng.range(0.0, 1.0);
            let ra = if rng.below(3) == 0 { rb } else { rng.range(0.0, 1.0) };
            match Cone::new(cv(c), f(rb + 0.05), cv(apex), f(ra)) {
                Ok(cn) => scene.add_shape(Shape::Cone(cn), mat),
                Err(_) => return,
            }
        }
    };
    r.unwrap();
}

/// Peak signal-to-noise ratio of `b` against `a` over all 8-bit channel
/// samples, in dB: `10·log₁₀(255²/MSE)`; infinite for identical images.
pub fn psnr(a: &[Rgb8], b: &[Rgb8]) -> f64 {
    assert_eq!(a.len(), b.len());
    let mut se = 0.0f64;
    for (p, q) in a.iter().zip(b) {
        for c in 0..3 {
            let d = p[c] as f64 - q[c] as f64;
            se += d * d;
        }
    }
    let mse = se / (3 * a.len()) as f64;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0 * 255.0 / mse).log10()
    }
}

/// Fraction of pixels whose (ID AOV) values agree.
pub fn agreement(a: &[Rgb8], b: &[Rgb8]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).filter(|(p, q)| p == q).count() as f64 / a.len() as f64
}

/// A random scene of `n` primitives of every kind, with random materials
/// (some mirrors, some glass) and lights.
pub fn random_scene(rng: &mut Rng, n: usize) -> TestScene {
    random_scene_in::<f32>(rng, n)
}

/// [`random_scene`] for any scalar (the same draws; see [`random_shape_in`]).
pub fn random_scene_in<S: Scalar>(rng: &mut Rng, n: usize) -> TestSceneOf<S> {
    let mut s = TestSceneOf::<S>::new();
    let f = S::from_f32;
    s.set_background(cv(rng.vec(0.0, 0.5))).unwrap();
    for _ in 0..6 {
        let m = Material {
            color: cv(rng.vec(0.1, 1.0)),
            ka: f(rng.range(0.0, 0.2)),
            kd: f(rng.range(0.2, 0.9)),
            ks: f(rng.range(0.0, 0.8)),
            shine: f(rng.range(1.0, 100.0)),
            kr: f(if rng.below(3) == 0 { rng.range(0.2, 0.9) } else { 0.0 }),
            kt: f(if rng.below(3) == 0 { rng.range(0.2, 0.9) } else { 0.0 }),
            ior: f(rng.range(1.0, 2.0)),
        };
        s.add_material(m).unwrap();
    }
    for i in 0..n {
        let k = (i as u32) % 9;
        let mat = rng.below(6) as u16;
        random_shape_in(rng, &mut s, k, mat);
    }
    for _ in 0..1 + rng.below(3) {
        s.add_light(cv(rng.vec(-8.0, 8.0)), cv(rng.vec(0.2, 1.0))).unwrap();
    }
    s
}

/// A camera looking at the origin from a random direction.
pub fn random_camera(rng: &mut Rng, w: u32, h: u32) -> Camera<f32> {
    random_camera_in::<f32>(rng, w, h)
}

/// [`random_camera`] for any scalar (the same draws).
pub fn random_camera_in<S: Scalar>(rng: &mut Rng, w: u32, h: u32) -> Camera<S> {
    let eye = rng.unit().scale(rng.range(8.0, 14.0));
    Camera::new(cv(eye), cv(rng.vec(-0.5, 0.5)), cv(Vec3::new(0.0, 0.0, 1.0)), rng.range(30.0, 70.0), w, h).unwrap()
}

/// Renders a whole image with packet width `W`, tile by tile (tiles of
/// side `tile`, one thread, the baseline instruction set).
pub fn render<const W: usize>(
    scene: &SceneView<'_, f32>,
    camera: Camera<f32>,
    settings: TraceSettings<f32>,
    aov: Aov,
    tile: u32,
) -> (Vec<Rgb8>, RayStats) {
    render_in::<f32, W>(scene, camera, settings, aov, tile)
}

/// [`render`] for any scalar.
pub fn render_in<S: Scalar, const W: usize>(
    scene: &SceneView<'_, S>,
    camera: Camera<S>,
    settings: TraceSettings<S>,
    aov: Aov,
    tile: u32,
) -> (Vec<Rgb8>, RayStats) {
    render_with(BruteForce, scene, camera, settings, aov, tile, W)
}

/// [`render_in`] through the accelerator `accel`, with packets of `packet`.
pub fn render_with<S: Scalar, A: Accelerator<S> + Sync>(
    accel: A,
    scene: &SceneView<'_, S>,
    camera: Camera<S>,
    settings: TraceSettings<S>,
    aov: Aov,
    tile: u32,
    packet: usize,
) -> (Vec<Rgb8>, RayStats) {
    let tracer: Tracer<S, A> = Tracer::with_accelerator(*scene, accel, settings).unwrap();
    let renderer = Renderer { tracer, camera, aov, sampling: Sampling::Centre };
    let tiling = Tiling { packet, isa: Isa::Baseline, threads: 1, tile };
    render_tiles(&renderer, camera.full_rect(), &tiling, &|| {}).unwrap()
}

/// Every scene file in `tests/scenes/`: the 17 SPD databases and the
/// extension sample, by name.
pub const SCENES: [(&str, &str); 18] = [
    ("balls-1", include_str!("../scenes/balls-1.nff")),
    ("balls-2", include_str!("../scenes/balls-2.nff")),
    ("gears-1", include_str!("../scenes/gears-1.nff")),
    ("gears-2", include_str!("../scenes/gears-2.nff")),
    ("jacks-1", include_str!("../scenes/jacks-1.nff")),
    ("lattice-1", include_str!("../scenes/lattice-1.nff")),
    ("mount-1", include_str!("../scenes/mount-1.nff")),
    ("mount-2", include_str!("../scenes/mount-2.nff")),
    ("rings-1", include_str!("../scenes/rings-1.nff")),
    ("shells-1", include_str!("../scenes/shells-1.nff")),
    ("sombrero-1", include_str!("../scenes/sombrero-1.nff")),
    ("teapot-1", include_str!("../scenes/teapot-1.nff")),
    ("teapot-2", include_str!("../scenes/teapot-2.nff")),
    ("tetra-1", include_str!("../scenes/tetra-1.nff")),
    ("tetra-2", include_str!("../scenes/tetra-2.nff")),
    ("tree-1", include_str!("../scenes/tree-1.nff")),
    ("tree-2", include_str!("../scenes/tree-2.nff")),
    ("extensions", include_str!("../scenes/extensions.nff")),
];

/// A scene big enough for every file of [`SCENES`] (gears-2 is the largest).
pub type Big = BigOf<f32>;

/// [`Big`] for any scalar.
pub type BigOf<S> = Scene<S, 16384, 65536, 64, 16>;
