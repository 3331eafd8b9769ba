//! Not a user example: exposes the 8-wide sphere kernel and closest-hit loop
//! as non-inlined symbols so their assembly can be inspected
//! (`objdump -d --no-show-raw-insn target/release/examples/asm_probe`).
use raypack::prelude::*;
use raypack::primitives::Sphere;
use raypack::ray::Roots;
use raypack::scene::Hit;

#[inline(never)]
pub fn probe_sphere8(s: &Sphere<f32>, ray: &RayPacket<f32, 8>, m: Mask<8>) -> Roots<f32, 8> {
    s.roots(ray, Lanes::zero(), Lanes::splat(f32::MAX), m)
}

#[inline(never)]
pub fn probe_closest8(v: &SceneView<'_, f32>, ray: &RayPacket<f32, 8>, m: Mask<8>) -> Hit<f32, 8> {
    v.closest_hit(ray, Lanes::zero(), Lanes::splat(f32::MAX), m)
}

fn main() {
    let mut s: Scene<f32, 4, 4> = Scene::new();
    let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
    s.add_sphere(Vec3::new(0.0, 0.0, 5.0), 1.0, m).unwrap();
    let cam = Camera::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 0.0), 30.0, 8, 8).unwrap();
    let (ray, mask) = cam.packet::<8>(0, 0, cam.full_rect());
    let sp = Sphere::new(Vec3::new(0.0, 0.0, 5.0), 1.0).unwrap();
    println!("{:?}", probe_sphere8(&sp, &ray, mask).hit0);
    println!("{:?}", probe_closest8(&s.view(), &ray, mask).mask);
}
