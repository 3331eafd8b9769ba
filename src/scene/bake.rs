//! Scenes baked on a host into `static` data for a firmware.
//!
//! A firmware that always renders the same scene need not carry the code
//! that builds it: the checks and derived values of `add_sphere`, the
//! polygon set-up, the quadric and cone frames, the conversion of an `f32`
//! description into a fixed-point frame, the camera's basis. The host builds
//! the scene as usual, [`bake_scene`] writes it out as Rust source (one
//! `static` array per slice of a [`SceneView`], and the camera), and the
//! firmware compiles that file and renders [`SceneView::new`] over the
//! statics: no scene code, no scene RAM (the arrays stay in flash), and the
//! same bits, because every field is written as its exact bit pattern and
//! put back by a `const fn` (`from_baked`) that only moves it into place.
//!
//! ```
//! use raypack::scene::bake::bake_scene;
//! use raypack::prelude::*;
//!
//! let mut scene: Scene<f32, 4, 4, 1, 1> = Scene::new();
//! let m = scene.add_material(Material::diffuse(Vec3::new(1.0, 0.5, 0.2))).unwrap();
//! scene.add_sphere(Vec3::new(0.0, 0.0, -5.0), 1.0, m).unwrap();
//! let camera = Camera::<f32>::new(
//!     Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 1.0, 0.0), 45.0, 64, 48,
//! ).unwrap();
//! let mut source = String::new();
//! bake_scene(&scene.view(), &camera, &mut source).unwrap();
//! assert!(source.contains("pub static PRIMITIVES: [raypack::scene::Primitive<f32>; 1]"));
//! ```
//!
//! `from_baked` does not check what it is given: values other than the ones
//! [`Bake`] wrote give a primitive whose answers are unspecified (never a
//! panic; [`SceneView::new`] still checks material indices and vertex
//! ranges). `raypack bake scene.nff -o scene.rs` bakes an NFF scene
//! (`LoadedScene::bake` in the `std` harness); `examples/bake_scene.rs`
//! bakes the firmware's demo scene.

use crate::geom::camera::Camera;
use crate::scene::SceneView;
use core::fmt::{self, Write};

pub use crate::num::bake::Bake;
use crate::num::fixed32::Fixed32;
use crate::num::fixed64::Fixed;
use crate::num::scalar::Scalar;

/// A scalar type [`bake_scene`] can write: its path, for the statics' types.
pub trait BakeScalar: Scalar + Bake {
    /// The type's path as the baked source names it.
    const PATH: &'static str;
}
impl BakeScalar for f32 {
    const PATH: &'static str = "f32";
}
impl BakeScalar for Fixed32 {
    const PATH: &'static str = "raypack::Fixed32";
}
impl BakeScalar for Fixed {
    const PATH: &'static str = "raypack::Fixed";
}

/// Writes `view` and `camera` as Rust source: `pub static PRIMITIVES`,
/// `VERTICES`, `MATERIALS`, `LIGHTS` (arrays of the view's slices),
/// `pub const BACKGROUND` and `pub static CAMERA`, for a firmware to
/// `include!` (or keep as a module) and render through
/// `SceneView::new(&PRIMITIVES, &VERTICES, &MATERIALS, &LIGHTS, BACKGROUND)`.
/// The output depends only on the scene's bits: the same scene gives the
/// same bytes.
pub fn bake_scene<S: BakeScalar>(view: &SceneView<'_, S>, camera: &Camera<S>, w: &mut dyn Write) -> fmt::Result {
    let t = S::PATH;
    writeln!(w, "// A raypack scene baked by raypack::scene::bake::bake_scene: generated, do not edit.")?;
    writeln!(w)?;
    fn items<T: Bake>(w: &mut dyn Write, doc: &str, decl: &str, ty: [&str; 3], items: &[T]) -> fmt::Result {
        writeln!(w, "/// {doc}")?;
        write!(w, "pub static {decl}: [{}{}{}; {}] = [", ty[0], ty[1], ty[2], items.len())?;
        w.write_str("\n")?;
        for v in items {
            w.write_str("    ")?;
            v.bake(w)?;
            w.write_str(",\n")?;
        }
        writeln!(w, "];")
    }
    items(w, "The primitives.", "PRIMITIVES", ["raypack::scene::Primitive<", t, ">"], view.primitives())?;
    items(w, "The polygon vertex pool.", "VERTICES", ["raypack::geom::vec3::Vec3<", t, ">"], view.vertices())?;
    items(w, "The materials.", "MATERIALS", ["raypack::scene::Material<", t, ">"], view.materials())?;
    items(w, "The lights.", "LIGHTS", ["raypack::scene::Light<", t, ">"], view.lights())?;
    writeln!(w, "/// The background colour.")?;
    write!(w, "pub const BACKGROUND: raypack::geom::vec3::Vec3<{t}> = ")?;
    view.background().bake(w)?;
    writeln!(w, ";")?;
    writeln!(w, "/// The camera.")?;
    write!(w, "pub static CAMERA: raypack::geom::camera::Camera<{t}> = ")?;
    camera.bake(w)?;
    writeln!(w, ";")
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::geom::primitives::{Shape, Sphere};
    use crate::geom::vec3::Vec3;
    use crate::scene::{Material, Primitive, Scene};
    use std::string::String;

    #[test]
    fn scalars_are_written_as_their_bits() {
        let mut s = String::new();
        (-0.0f32).bake(&mut s).unwrap();
        assert_eq!(s, "f32::from_bits(0x80000000)");
        s.clear();
        Fixed32::from_bits(-7).bake(&mut s).unwrap();
        assert_eq!(s, "raypack::Fixed32::from_bits(-7)");
        s.clear();
        Some((1u8, true)).bake(&mut s).unwrap();
        assert_eq!(s, "Some((1, true))");
    }

    #[test]
    fn a_sphere_is_written_field_by_field_and_from_baked_rebuilds_it() {
        let sphere = Sphere::new(Vec3::new(1.0f32, 2.0, 3.0), 0.5).unwrap();
        let mut s = String::new();
        sphere.bake(&mut s).unwrap();
        assert!(s.starts_with("raypack::geom::primitives::Sphere::from_baked(raypack::geom::vec3::Vec3::new("));
        // radius 0.5 and radius² 0.25, in that order.
        assert!(s.ends_with("f32::from_bits(0x3f000000), f32::from_bits(0x3e800000))"), "{s}");
        let again = Sphere::from_baked(Vec3::new(1.0f32, 2.0, 3.0), 0.5, 0.25);
        assert_eq!(Shape::Sphere(again), Shape::Sphere(sphere));
    }

    #[test]
    fn a_scene_lists_every_slice_with_its_length() {
        let mut scene: Scene<Fixed32, 4, 8, 2, 2> = Scene::new();
        let m = scene.add_material(Material::diffuse(Vec3::new(Fixed32::ONE, Fixed32::HALF, Fixed32::ZERO))).unwrap();
        let v = |x: f32, y: f32| Vec3::new(Fixed32::from_f32(x), Fixed32::from_f32(y), Fixed32::ZERO);
        scene.add_polygon(&[v(0.0, 0.0), v(0.5, 0.0), v(0.0, 0.5)], m).unwrap();
        scene.add_plane(Fixed32::ZERO, Fixed32::ONE, Fixed32::ZERO, Fixed32::ONE, m).unwrap();
        let camera = Camera::<Fixed32>::new(v(0.0, 0.0), v(0.0, 0.1), v(1.0, 0.0), 45.0, 8, 8).unwrap();
        let mut s = String::new();
        bake_scene(&scene.view(), &camera, &mut s).unwrap();
        for line in [
            "pub static PRIMITIVES: [raypack::scene::Primitive<raypack::Fixed32>; 2] = [",
            "pub static VERTICES: [raypack::geom::vec3::Vec3<raypack::Fixed32>; 3] = [",
            "pub static MATERIALS: [raypack::scene::Material<raypack::Fixed32>; 1] = [",
            "pub static LIGHTS: [raypack::scene::Light<raypack::Fixed32>; 0] = [",
            "pub const BACKGROUND: raypack::geom::vec3::Vec3<raypack::Fixed32> = raypack::geom::vec3::Vec3::new(",
            "pub static CAMERA: raypack::geom::camera::Camera<raypack::Fixed32> = raypack::geom::camera::Camera::from_baked(",
        ] {
            assert!(s.lines().any(|l| l.starts_with(line)), "missing {line:?} in\n{s}");
        }
        assert_eq!(s.matches("raypack::geom::primitives::Polygon::from_baked(").count(), 1);
        assert_eq!(s.matches("raypack::geom::primitives::Plane::from_baked(").count(), 1);
        // Deterministic.
        let mut again = String::new();
        bake_scene(&scene.view(), &camera, &mut again).unwrap();
        assert_eq!(s, again);
        let _ = Primitive {
            shape: Shape::Sphere(Sphere::from_baked(v(0.0, 0.0), Fixed32::ONE, Fixed32::ONE)),
            material: 0,
        };
    }

    /// `from_baked` takes any fields; the view over them still checks
    /// vertex ranges and material indices (an error, never a panic).
    #[test]
    fn views_over_baked_data_are_checked() {
        use crate::geom::primitives::Polygon;
        use crate::scene::SceneView;
        let n = Vec3::new(0.0f32, 0.0, 1.0);
        let poly = Polygon::from_baked(
            u32::MAX - 1,
            u32::MAX,
            true,
            true,
            false,
            0,
            1,
            true,
            n,
            0.0,
            n,
            0.0,
            1.0,
            255,
            [[7, 3]; crate::geom::primitives::polygon::EDGE_BLOCKS],
        );
        let prims = [Primitive { shape: Shape::Polygon(poly), material: 0 }];
        let mats = [Material::diffuse(Vec3::new(1.0f32, 1.0, 1.0))];
        let verts = [n; 4];
        assert!(SceneView::new(&prims, &verts, &mats, &[], n).is_err());
        let sphere = [Primitive { shape: Shape::Sphere(Sphere::from_baked(n, 1.0, 1.0)), material: 3 }];
        assert!(SceneView::new(&sphere, &verts, &mats, &[], n).is_err());
        assert!(SceneView::new(&sphere[..0], &verts, &mats, &[], n).is_ok());
    }
}
