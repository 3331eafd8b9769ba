//! Workloads shared by the criterion benches (`benches/primary.rs`) and the
//! interleaved probe (`tools/primary_probe.rs`): packets of camera rays,
//! N-sphere grids, one primitive of each kind, and passes over them that run
//! through the instruction-set dispatcher ([`raypack::dispatch`]).
#![allow(dead_code)]

use raypack::dispatch::{Isa, IsaKernel};
use raypack::lanes::{Lanes, Mask};
use raypack::prelude::*;
use raypack::primitives::Shape;
use raypack::primitives::Sphere;
use raypack::ray::RayPacket;
use raypack::scene::Scene;

/// Packets of primary rays covering a whole image.
pub type Packets<const W: usize> = Vec<(RayPacket<f32, W>, Mask<W>)>;

/// Room for the largest grid (256 spheres) and the kind scenes.
pub type BenchScene = Scene<f32, 1024, 256, 4, 2>;

/// Every camera ray of `cam`, in packets of width `W`.
pub fn packets<const W: usize>(cam: &Camera<f32>) -> Packets<W> {
    let (pw, ph) = raypack::camera::packet_shape(W);
    let mut v = Vec::new();
    for y in (0..cam.height()).step_by(ph as usize) {
        for x in (0..cam.width()).step_by(pw as usize) {
            v.push(cam.packet::<W>(x, y, cam.full_rect()));
        }
    }
    v
}

/// The camera of all workloads: at `z = 12` looking down `−z` at the
/// origin, 40° vertical field of view, `size × size` pixels.
pub fn camera(size: u32) -> Camera<f32> {
    Camera::new(Vec3::new(0.0, 0.0, 12.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 40.0, size, size).unwrap()
}

/// `n = k²` spheres on a `k × k` grid in the plane `z = 0`, filling the view
/// of [`camera`] (the grid spans `[−4, 4]²`; sphere radius is 0.45 of the
/// spacing), one diffuse material and one light.
pub fn sphere_grid(n: usize) -> Box<BenchScene> {
    let k = (n as f64).sqrt().round() as usize;
    assert_eq!(k * k, n, "grid sizes are squares");
    let mut s = Box::new(BenchScene::new());
    let m = s.add_material(Material::diffuse(Vec3::new(0.8, 0.6, 0.4))).unwrap();
    let spacing = 8.0 / k as f32;
    for i in 0..k {
        for j in 0..k {
            let c = Vec3::new(-4.0 + spacing * (i as f32 + 0.5), -4.0 + spacing * (j as f32 + 0.5), 0.0);
            s.add_sphere(c, 0.45 * spacing, m).unwrap();
        }
    }
    s.add_light(Vec3::new(5.0, 5.0, 10.0), Vec3::new(0.7, 0.7, 0.7)).unwrap();
    s
}

/// The primitive kinds benchmarked one by one.
pub const KINDS: [&str; 5] = ["sphere", "plane", "polygon", "box", "quadric"];

/// A scene of 16 primitives of kind `kind` (see [`KINDS`]) on a 4 × 4 grid
/// in front of [`camera`], each covering about a cell (every kind is hit
/// by a good share of the rays and missed by the rest, so both paths of the
/// kernel run).
pub fn kind_scene(kind: &str) -> Box<BenchScene> {
    let mut s = Box::new(BenchScene::new());
    let m = s.add_material(Material::diffuse(Vec3::new(0.8, 0.6, 0.4))).unwrap();
    for i in 0..4 {
        for j in 0..4 {
            let (x, y) = (-3.0 + 2.0 * i as f32, -3.0 + 2.0 * j as f32);
            let c = Vec3::new(x, y, 0.0);
            match kind {
                "sphere" => {
                    s.add_sphere(c, 0.9, m).unwrap();
                }
                "plane" => {
                    // Tilted planes at different offsets, seen by part of the view.
                    let k = (4 * i + j) as f32;
                    s.add_plane(0.1 * (k - 8.0), 0.8, 0.6, -0.3 * k, m).unwrap();
                }
                "polygon" => {
                    // A convex pentagon per cell.
                    let v = [
                        Vec3::new(x - 0.8, y - 0.7, 0.0),
                        Vec3::new(x + 0.7, y - 0.8, 0.0),
                        Vec3::new(x + 0.9, y + 0.3, 0.2),
                        Vec3::new(x, y + 0.9, 0.0),
                        Vec3::new(x - 0.9, y + 0.3, -0.2),
                    ];
                    s.add_polygon(&v, m).unwrap();
                }
                "box" => {
                    s.add_box(Vec3::new(x - 0.7, y - 0.6, -0.5), Vec3::new(x + 0.8, y + 0.7, 0.5), m).unwrap();
                }
                "quadric" => {
                    s.add_quadric(Quadric::ellipsoid(c, Vec3::new(0.9, 0.6, 0.5)).unwrap(), m).unwrap();
                }
                other => panic!("unknown kind {other}"),
            }
        }
    }
    s
}

/// One closest-hit query per packet against a whole scene; returns the
/// number of lanes that hit (so nothing is optimized away, and widths can be
/// compared).
pub struct ScenePass<'v, 'p, A, const W: usize> {
    /// The scene.
    pub view: &'v SceneView<'v, f32>,
    /// What the queries go through (brute force or a tree).
    pub accel: &'v A,
    /// The packets.
    pub packets: &'p Packets<W>,
}

impl<A: Accelerator<f32>, const W: usize> IsaKernel for ScenePass<'_, '_, A, W> {
    type Output = u32;
    #[inline(always)]
    fn run(self) -> u32 {
        let mut hits = 0;
        for (ray, m) in self.packets {
            hits += self.accel.closest_hit(self.view, ray, Lanes::zero(), Lanes::splat(f32::MAX), *m).mask.count();
        }
        hits
    }
}

/// Something with a bare packet kernel: a scene primitive (through the
/// `Shape` match on its kind, as the tracer calls it) or a sphere alone.
pub trait Kernel {
    /// Crossings of each active ray in `(0, f32::MAX)`.
    fn roots<const W: usize>(
        &self,
        pool: &[Vec3<f32>],
        ray: &RayPacket<f32, W>,
        active: Mask<W>,
    ) -> raypack::ray::Roots<f32, W>;
}

impl Kernel for raypack::scene::Primitive<f32> {
    #[inline(always)]
    fn roots<const W: usize>(
        &self,
        pool: &[Vec3<f32>],
        ray: &RayPacket<f32, W>,
        active: Mask<W>,
    ) -> raypack::ray::Roots<f32, W> {
        self.shape.roots(pool, ray, Lanes::zero(), Lanes::splat(f32::MAX), active)
    }
}

impl Kernel for Sphere<f32> {
    #[inline(always)]
    fn roots<const W: usize>(
        &self,
        _: &[Vec3<f32>],
        ray: &RayPacket<f32, W>,
        active: Mask<W>,
    ) -> raypack::ray::Roots<f32, W> {
        Sphere::roots(self, ray, Lanes::zero(), Lanes::splat(f32::MAX), active)
    }
}

/// The bare kernels of a list of items for every packet: the packet stays
/// in registers while the items stream past, and only the nearest root per
/// lane is kept (no primitive ids, no closest-hit bookkeeping). Returns the
/// number of lanes that hit anything.
pub struct KernelPass<'v, 'p, K, const W: usize> {
    /// The primitives (or spheres).
    pub items: &'v [K],
    /// The scene's vertex pool (polygons).
    pub pool: &'v [Vec3<f32>],
    /// The packets.
    pub packets: &'p Packets<W>,
}

impl<K: Kernel, const W: usize> IsaKernel for KernelPass<'_, '_, K, W> {
    type Output = u32;
    #[inline(always)]
    fn run(self) -> u32 {
        let mut hits = 0;
        for (ray, m) in self.packets {
            let mut best = Lanes::splat(f32::MAX);
            for k in self.items {
                best = best.min(k.roots(self.pool, ray, *m).t0);
            }
            hits += best.lt(Lanes::splat(f32::MAX)).count();
        }
        hits
    }
}

/// The spheres of a scene (the other primitives are left out).
pub fn spheres_of(view: &SceneView<'_, f32>) -> Vec<Sphere<f32>> {
    view.primitives()
        .iter()
        .filter_map(|p| match p.shape {
            Shape::Sphere(s) => Some(s),
            _ => None,
        })
        .collect()
}

/// Runs the sphere kernel alone ([`Sphere::roots`], no dispatch on the
/// primitive kind) over `spheres`, compiled for `isa`.
#[inline(never)]
pub fn sphere_pass<const W: usize>(isa: Isa, spheres: &[Sphere<f32>], packets: &Packets<W>) -> u32 {
    isa.run(KernelPass { items: spheres, pool: &[], packets })
}

/// Runs a [`ScenePass`] compiled for `isa` (the queries inlined into it).
#[inline(never)]
pub fn scene_pass<A: Accelerator<f32>, const W: usize>(
    isa: Isa,
    view: &SceneView<'_, f32>,
    accel: &A,
    packets: &Packets<W>,
) -> u32 {
    isa.run(ScenePass { view, accel, packets })
}

/// Runs the bare kernels of a scene's primitives (through the `Shape`
/// match) compiled for `isa`.
#[inline(never)]
pub fn shape_pass<const W: usize>(isa: Isa, view: &SceneView<'_, f32>, packets: &Packets<W>) -> u32 {
    isa.run(KernelPass { items: view.primitives(), pool: view.vertices(), packets })
}

/// A full render of `renderer` (single thread, one rectangle) compiled for
/// `isa`; returns the number of rays traced.
#[inline(never)]
pub fn render_pass<A: Accelerator<f32>, const W: usize>(
    isa: Isa,
    renderer: &Renderer<'_, f32, A>,
    img: &mut [Rgb8],
) -> u64 {
    let mut st = RayStats::default();
    raypack::dispatch::render_rect::<f32, A, 8, W>(isa, renderer, renderer.camera.full_rect(), img, &mut st).unwrap();
    st.total()
}
