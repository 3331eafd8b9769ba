//! A small built-in scene with every primitive kind, shadows, a mirror and a
//! glass object; used by the examples, the tests and the firmware.

use crate::geom::camera::{Camera, CameraError};
use crate::geom::primitives::Quadric;
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::Vec3;
use crate::num::scalar::Scalar;
use crate::scene::{Material, Scene, SceneError};

/// Capacity type of the demo scene.
pub type DemoScene<S> = Scene<S, 16, 32, 8, 2>;

fn v<S: Scalar>(x: f32, y: f32, z: f32) -> Vec3<S> {
    Vec3::from_f32(x, y, z)
}

/// Builds the demo scene: a floor plane, a polygon, a non-convex polygon, a
/// patch, an axis-aligned box, an oriented box, a reflective sphere, a glass
/// sphere, an ellipsoid quadric, a clipped cylinder quadric and a finite cone.
pub fn demo_scene<S: Scalar>() -> Result<DemoScene<S>, SceneError> {
    let mut s = DemoScene::<S>::new();
    build_demo_scene(&mut s)?;
    Ok(s)
}

/// Adds the demo scene's background, materials, primitives and lights to
/// `s` (normally empty; see [`demo_scene`]) where it lies, so a caller with
/// little stack (a microcontroller) can build it in a `static` without the
/// scene ever being copied. Fails only if `s` lacks room.
pub fn build_demo_scene<S: Scalar>(s: &mut DemoScene<S>) -> Result<(), SceneError> {
    s.set_background(v(0.08, 0.12, 0.25))?;
    let f = S::from_f32;
    let mat = |r: f32, g: f32, b: f32, ka: f32, kd: f32, ks: f32, shine: f32, kr: f32, kt: f32, ior: f32| Material {
        color: v(r, g, b),
        ka: f(ka),
        kd: f(kd),
        ks: f(ks),
        shine: f(shine),
        kr: f(kr),
        kt: f(kt),
        ior: f(ior),
    };
    let floor = s.add_material(mat(0.8, 0.8, 0.7, 0.1, 0.8, 0.0, 1.0, 0.0, 0.0, 1.0))?;
    let red = s.add_material(mat(0.9, 0.2, 0.15, 0.1, 0.7, 0.3, 20.0, 0.0, 0.0, 1.0))?;
    let mirror = s.add_material(mat(0.9, 0.9, 0.9, 0.0, 0.2, 0.6, 60.0, 0.7, 0.0, 1.0))?;
    let glass = s.add_material(mat(0.95, 0.95, 1.0, 0.0, 0.05, 0.5, 80.0, 0.1, 0.85, 1.5))?;
    let green = s.add_material(mat(0.2, 0.8, 0.3, 0.1, 0.8, 0.2, 10.0, 0.0, 0.0, 1.0))?;
    let blue = s.add_material(mat(0.2, 0.3, 0.9, 0.1, 0.7, 0.4, 30.0, 0.1, 0.0, 1.0))?;

    s.add_plane(f(0.0), f(0.0), f(1.0), f(0.0), floor)?; // z = 0
    s.add_polygon(&[v(-4.0, 3.0, 0.0), v(4.0, 3.0, 0.0), v(4.0, 3.0, 3.0), v(-4.0, 3.0, 3.0)], floor)?; // back wall
    s.add_polygon(&[v(2.2, 2.9, 0.5), v(3.4, 2.9, 0.5), v(3.4, 2.9, 2.2), v(2.8, 2.9, 1.2), v(2.2, 2.9, 2.2)], red)?; // non-convex "M" on the wall
    s.add_patch(
        &[v(-3.6, 2.8, 0.3), v(-2.4, 2.8, 0.3), v(-3.0, 2.8, 1.5)],
        &[v(-0.6, -1.0, 0.0), v(0.6, -1.0, 0.0), v(0.0, -1.0, 0.6)],
        green,
    )?;
    s.add_box(v(-2.6, -0.4, 0.0), v(-1.6, 0.6, 1.0), red)?;
    s.add_oriented_box(v(1.9, -0.6, 0.4), v(0.4, 0.4, 0.4), v(1.0, 1.0, 0.0), v(-1.0, 1.0, 0.0), blue)?;
    s.add_sphere(v(0.0, 0.8, 0.8), f(0.8), mirror)?;
    s.add_sphere(v(-0.6, -1.3, 0.5), f(0.5), glass)?;
    s.add_quadric(Quadric::ellipsoid(v(1.2, 1.3, 0.35), v(0.5, 0.3, 0.35))?, green)?;
    s.add_quadric(
        Quadric::cylinder(v(-1.0, 2.0, 0.0), v(0.0, 0.0, 1.0), f(0.3))?
            .with_clip(v(-1.5, 1.5, 0.0), v(-0.5, 2.5, 1.6))?,
        blue,
    )?;
    s.add_cone(v(3.0, 0.6, 0.0), f(0.4), v(3.0, 0.6, 1.2), f(0.05), red)?;
    s.add_light(v(-3.0, -4.0, 6.0), v(0.7, 0.7, 0.7))?;
    s.add_light(v(4.0, -2.0, 3.0), v(0.4, 0.4, 0.45))?;
    Ok(())
}

/// The demo camera's eye, look-at point and up vector, and its vertical
/// field of view in degrees.
pub const DEMO_VIEW: ([f32; 3], [f32; 3], [f32; 3], f32) = ([0.0, -7.0, 2.6], [0.0, 0.5, 0.8], [0.0, 0.0, 1.0], 45.0);

/// The demo scene's camera, for a `width × height` image.
pub fn demo_camera<S: Scalar>(width: u32, height: u32) -> Result<Camera<S>, CameraError> {
    let (e, a, u, fov) = DEMO_VIEW;
    Camera::new(v(e[0], e[1], e[2]), v(a[0], a[1], a[2]), v(u[0], u[1], u[2]), fov, width, height)
}

/// Builds the demo scene for scalar `S` in `scene` (empty, typically a
/// `static`) and returns the frame it lives in. A scalar that traces in a
/// frame of its own ([`Scalar::SCENE_FRAME`], the Q8.24 fixed point) gets
/// the scene built in `f32` in `described` (so set-up keeps every digit)
/// and converted ([`Scene::add_similar`]); every other scalar gets it built
/// directly, in the identity frame, and `described` is left alone.
pub fn build_demo_scene_for<S: Scalar>(
    scene: &mut DemoScene<S>,
    described: &mut DemoScene<f32>,
) -> Result<Similarity, SceneError> {
    let Some(half) = S::SCENE_FRAME else {
        build_demo_scene(scene)?;
        return Ok(Similarity::IDENTITY);
    };
    build_demo_scene(described)?;
    let (e, _, _, _) = DEMO_VIEW;
    let frame = described.view().fitting_frame(Some(Vec3::new(e[0], e[1], e[2])), half);
    scene.add_similar(&described.view(), &frame)?;
    Ok(frame)
}

/// The demo camera in `frame` (what [`build_demo_scene_for`] returned).
pub fn demo_camera_for<S: Scalar>(frame: &Similarity, width: u32, height: u32) -> Result<Camera<S>, CameraError> {
    if *frame == Similarity::IDENTITY {
        return demo_camera(width, height);
    }
    let (e, a, u, fov) = DEMO_VIEW;
    let cam = crate::scene::nff::NffCamera { from: e, at: a, up: u, angle: fov, hither: 0.0, width, height };
    cam.camera_in(frame, width, height)
}
