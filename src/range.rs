//! Range checks for scalars of limited range (fixed point).
//!
//! A 32.32 [`crate::fixed::Fixed`] holds magnitudes below 2³¹ ≈ 2.1·10⁹. The
//! tracer's largest intermediates are squared distances between two scene
//! points (the sphere test's `|o − c|²`, the shading code's `|light − p|²`)
//! and the terms of the quadric and cone discriminants. With every coordinate
//! of magnitude at most `R`, a difference of two points has components up to
//! `2R` and a squared length up to `3·(2R)² = 12R²`. Keeping that below a
//! quarter of the range (`2²⁹`, room for the sums it enters) gives
//! `R ≤ √(2²⁹/12) ≈ 6689`; the limit is the power of two below it,
//! [`FIXED_COORDINATE_LIMIT`] `= 4096`.
//!
//! Quadrics and cones carry coefficients (`1/r²`, a cone's slope) that scale
//! their intermediates further, so [`check_scene`] bounds their discriminant
//! terms from the scene's actual extent (scale-aware: a small ellipsoid in a
//! small scene is fine; the same ellipsoid in a scene 1000 units wide is not).
//!
//! Points beyond the extent arise only as hit points on unbounded primitives
//! (planes, unclipped quadrics) far along a grazing ray. Their intermediates
//! saturate: results there are defined (never a panic) but may be inexact.
//!
//! For `f32` ([`Scalar::LIMITED_RANGE`] is false) every check passes.

use crate::camera::Camera;
use crate::primitives::Shape;
use crate::scalar::Scalar;
use crate::scene::SceneView;
use crate::vec3::Vec3;

/// Largest coordinate magnitude accepted for [`crate::fixed::Fixed`] scenes
/// (see the module documentation for its derivation).
pub const FIXED_COORDINATE_LIMIT: f32 = 4096.0;

/// Budget for a single intermediate of the kernels: a quarter of the 32.32
/// range, leaving room for the sums the intermediate enters.
pub const FIXED_INTERMEDIATE_BUDGET: f32 = 536_870_912.0; // 2²⁹

/// What exceeded the representable range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RangeItem {
    /// Primitive `k` (0-based insertion index) has a coordinate beyond the limit.
    Primitive(u32),
    /// Light `k` (0-based) is beyond the limit.
    Light(u32),
    /// The camera's eye or look-at point is beyond the limit.
    Camera,
    /// Quadric or cone `k`: its intersection intermediates (discriminant
    /// terms) would exceed the budget at the scene's extent.
    Intermediate(u32),
}

/// A scene does not fit the scalar's range: what, how large (rounded up), and
/// the limit it exceeded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RangeError {
    /// What is out of range.
    pub item: RangeItem,
    /// Its magnitude (a coordinate, or the bound of an intermediate), rounded
    /// up, saturating at `u64::MAX`.
    pub magnitude: u64,
    /// The limit it exceeded.
    pub limit: u64,
}

impl core::fmt::Display for RangeError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.item {
            RangeItem::Primitive(k) => write!(f, "primitive {k} has a coordinate of magnitude {}", self.magnitude)?,
            RangeItem::Light(k) => write!(f, "light {k} has a coordinate of magnitude {}", self.magnitude)?,
            RangeItem::Camera => write!(f, "the camera has a coordinate of magnitude {}", self.magnitude)?,
            RangeItem::Intermediate(k) => write!(f, "primitive {k} needs intermediates up to {}", self.magnitude)?,
        }
        write!(f, ", beyond the fixed-point limit {} (scale the scene down)", self.limit)
    }
}

fn error(item: RangeItem, magnitude: f32, limit: f32) -> RangeError {
    // `as` saturates (and maps NaN to 0, impossible here: inputs are magnitudes).
    RangeError { item, magnitude: libm::ceilf(magnitude) as u64, limit: limit as u64 }
}

/// Largest absolute coordinate of a point, in `f32`.
fn magnitude<S: Scalar>(p: Vec3<S>) -> f32 {
    p.max_abs().to_f32()
}

/// Checks one point against [`Scalar::COORDINATE_LIMIT`].
pub fn check_point<S: Scalar>(p: Vec3<S>, item: RangeItem) -> Result<(), RangeError> {
    if !S::LIMITED_RANGE {
        return Ok(());
    }
    let m = magnitude(p);
    if m > S::COORDINATE_LIMIT {
        return Err(error(item, m, S::COORDINATE_LIMIT));
    }
    Ok(())
}

/// Magnitude of a primitive's coordinates: its bounds, or for a plane its
/// distance from the origin; `None` for an unclipped quadric (unbounded, no
/// coordinates of its own: [`check_scene`] bounds its coefficients instead).
fn shape_extent<S: Scalar>(shape: &Shape<S>, pool: &[Vec3<S>]) -> Option<f32> {
    match shape {
        Shape::Plane(p) => Some(p.offset().abs().to_f32()),
        _ => shape.bounds(pool).map(|(lo, hi)| magnitude(lo).max(magnitude(hi))),
    }
}

/// Checks one primitive's coordinates against [`Scalar::COORDINATE_LIMIT`]
/// (done by every `Scene::add_*` for limited-range scalars).
pub fn check_shape<S: Scalar>(shape: &Shape<S>, pool: &[Vec3<S>], index: u32) -> Result<(), RangeError> {
    if !S::LIMITED_RANGE {
        return Ok(());
    }
    match shape_extent(shape, pool) {
        Some(m) if m > S::COORDINATE_LIMIT => Err(error(RangeItem::Primitive(index), m, S::COORDINATE_LIMIT)),
        _ => Ok(()),
    }
}

/// Bound on the discriminant terms `b² + |4ac|` of a quadratic `a t² + b t + c`
/// whose coefficients are bounded by `a`, `b`, `c`.
fn disc_bound(a: f32, b: f32, c: f32) -> f32 {
    b * b + 4.0 * a * c
}

/// The whole-scene check for limited-range scalars: every coordinate (camera,
/// lights, primitives) within [`Scalar::COORDINATE_LIMIT`], and every quadric
/// and cone's intersection intermediates within [`FIXED_INTERMEDIATE_BUDGET`]
/// for ray origins anywhere in the scene's extent `R` (the largest coordinate
/// magnitude, at least 1). Returns `R`. Always `Ok` for `f32`.
///
/// Bounds (rays have unit directions, origins `|oᵢ| ≤ R`):
/// - quadric `Σ` of `A..F` = `Q₂`, of `G..I` = `Q₁`: `|a| ≤ Q₂`,
///   `|b| ≤ 2Q₂R + Q₁`, `|c| ≤ Q₂R² + Q₁R + |J|`;
/// - cone (local origin `|o| ≤ 2√3·R`, slope `k`, base radius `r_b`):
///   `r(o) ≤ |o|·|k| + r_b`, `|a| ≤ 1 + k²`, `|b| ≤ 2|o| + r(o)·|k|`,
///   `|c| ≤ 2|o|² + r(o)²`.
pub fn check_scene<S: Scalar>(scene: &SceneView<'_, S>, camera: &Camera<S>) -> Result<f32, RangeError> {
    if !S::LIMITED_RANGE {
        return Ok(f32::MAX);
    }
    let limit = S::COORDINATE_LIMIT;
    let mut extent = magnitude(camera.eye());
    if extent > limit {
        return Err(error(RangeItem::Camera, extent, limit));
    }
    for (k, light) in scene.lights().iter().enumerate() {
        let m = magnitude(light.position);
        if m > limit {
            return Err(error(RangeItem::Light(k as u32), m, limit));
        }
        extent = extent.max(m);
    }
    let pool = scene.vertices();
    for (k, p) in scene.primitives().iter().enumerate() {
        if let Some(m) = shape_extent(&p.shape, pool) {
            if m > limit {
                return Err(error(RangeItem::Primitive(k as u32), m, limit));
            }
            extent = extent.max(m);
        }
    }
    let r = extent.max(1.0);
    let budget = FIXED_INTERMEDIATE_BUDGET;
    for (k, p) in scene.primitives().iter().enumerate() {
        let bound = match &p.shape {
            Shape::Quadric(q) => {
                let c = q.coefficients().map(|v| v.abs().to_f32());
                let q2 = c[0] + c[1] + c[2] + c[3] + c[4] + c[5];
                let q1 = c[6] + c[7] + c[8];
                disc_bound(q2, 2.0 * q2 * r + q1, q2 * r * r + q1 * r + c[9])
            }
            Shape::Cone(cone) => {
                let o = 2.0 * libm::sqrtf(3.0) * r;
                let slope = cone.slope().abs().to_f32();
                let (_, rb, _, _) = cone.ends();
                let ro = o * slope + rb.to_f32();
                disc_bound(1.0 + slope * slope, 2.0 * o + ro * slope, 2.0 * o * o + ro * ro)
            }
            _ => 0.0,
        };
        if !(bound <= budget) {
            return Err(error(RangeItem::Intermediate(k as u32), bound, budget));
        }
    }
    Ok(r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::Fixed;
    use crate::prelude::*;

    type Small<S> = Scene<S, 8, 16, 2, 2>;

    fn v<S: Scalar>(x: f32, y: f32, z: f32) -> Vec3<S> {
        Vec3::from_f32(x, y, z)
    }

    fn cam<S: Scalar>(eye: Vec3<S>) -> Camera<S> {
        Camera::new(eye, v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0), 45.0, 8, 8).unwrap()
    }

    #[test]
    fn limit_keeps_squared_distances_in_budget() {
        // The derivation in the module docs: 12·R² within the budget, and the
        // budget a quarter of the 32.32 range.
        let r = FIXED_COORDINATE_LIMIT as f64;
        assert!(12.0 * r * r <= FIXED_INTERMEDIATE_BUDGET as f64);
        assert_eq!(FIXED_INTERMEDIATE_BUDGET as f64 * 4.0, 2f64.powi(31));
        // The farthest points of an accepted scene: the squared distance is
        // representable and exact.
        let a = Vec3::<Fixed>::from_f32(4096.0, 4096.0, 4096.0);
        let d = a - (-a);
        assert_eq!(d.length_squared().to_f32(), 12.0 * 4096.0 * 4096.0);
    }

    #[test]
    fn far_primitives_are_rejected_when_added() {
        let mut s = Small::<Fixed>::new();
        let m = s.add_material(Material::diffuse(v(1.0, 1.0, 1.0))).unwrap();
        s.add_sphere(v(4000.0, 0.0, 0.0), Fixed::from_f32(90.0), m).unwrap();
        let e = s.add_sphere(v(4000.0, 0.0, 0.0), Fixed::from_f32(100.0), m).unwrap_err();
        assert_eq!(
            e,
            SceneError::OutOfRange(RangeError { item: RangeItem::Primitive(1), magnitude: 4100, limit: 4096 })
        );
        // A coordinate that saturated on conversion is caught too.
        let e = s.add_sphere(v(0.0, 1.0e12, 0.0), Fixed::ONE, m).unwrap_err();
        assert!(matches!(e, SceneError::OutOfRange(RangeError { item: RangeItem::Primitive(1), .. })), "{e:?}");
        let e = s.add_light(v(0.0, 0.0, -5000.0), v(1.0, 1.0, 1.0)).unwrap_err();
        assert!(matches!(e, SceneError::OutOfRange(RangeError { item: RangeItem::Light(0), magnitude: 5000, .. })), "{e:?}");
        assert!(s.add_plane(Fixed::ZERO, Fixed::ZERO, Fixed::ONE, Fixed::from_f32(-5000.0), m).is_err());
        assert_eq!(s.len(), 1);
        // The same scene in f32 is accepted.
        let mut s = Small::<f32>::new();
        let m = s.add_material(Material::diffuse(v(1.0, 1.0, 1.0))).unwrap();
        s.add_sphere(v(0.0, 1.0e12, 0.0), 1.0, m).unwrap();
        assert_eq!(check_scene(&s.view(), &cam(v(0.0, -5.0, 1.0))), Ok(f32::MAX));
    }

    #[test]
    fn camera_beyond_the_limit_is_rejected() {
        let r = Camera::<Fixed>::new(v(0.0, 0.0, 5000.0), v(0.0, 0.0, 0.0), v(0.0, 1.0, 0.0), 45.0, 8, 8);
        assert_eq!(r, Err(CameraError::OutOfRange));
        assert!(Camera::<f32>::new(v(0.0, 0.0, 5000.0), v(0.0, 0.0, 0.0), v(0.0, 1.0, 0.0), 45.0, 8, 8).is_ok());
    }

    #[test]
    fn quadric_check_is_scale_aware() {
        // A small ellipsoid (coefficients 1/0.3² ≈ 11) is fine in a scene 10
        // units wide and rejected in one 2000 units wide.
        let build = |far: f32| {
            let mut s = Small::<Fixed>::new();
            let m = s.add_material(Material::diffuse(v(1.0, 1.0, 1.0))).unwrap();
            let q = Quadric::ellipsoid(v(0.0, 0.0, 0.0), v(0.3, 0.3, 0.3)).unwrap();
            s.add_quadric(q, m).unwrap();
            s.add_light(v(far, 0.0, 0.0), v(1.0, 1.0, 1.0)).unwrap();
            s
        };
        let near = build(10.0);
        assert_eq!(check_scene(&near.view(), &cam(v(0.0, -5.0, 1.0))), Ok(10.0));
        let far = build(2000.0);
        let e = check_scene(&far.view(), &cam(v(0.0, -5.0, 1.0))).unwrap_err();
        assert_eq!(e.item, RangeItem::Intermediate(0));
        assert!(e.magnitude > e.limit);
        // Cones: a steep slope scales the intermediates by k⁴.
        let mut s = Small::<Fixed>::new();
        let m = s.add_material(Material::diffuse(v(1.0, 1.0, 1.0))).unwrap();
        s.add_cone(v(0.0, 0.0, 0.0), Fixed::from_f32(1.0), v(0.0, 0.0, 1.0), Fixed::from_f32(0.5), m).unwrap();
        assert!(check_scene(&s.view(), &cam(v(0.0, -5.0, 1.0))).is_ok());
        s.add_cone(v(0.0, 0.0, 0.0), Fixed::from_f32(100.0), v(0.0, 0.0, 0.01), Fixed::from_f32(0.0), m).unwrap();
        assert_eq!(check_scene(&s.view(), &cam(v(0.0, -5.0, 1.0))).unwrap_err().item, RangeItem::Intermediate(1));
    }

    #[test]
    fn demo_scene_fits() {
        let s = crate::demo::demo_scene::<Fixed>().unwrap();
        let c = crate::demo::demo_camera::<Fixed>(16, 16).unwrap();
        assert!(check_scene(&s.view(), &c).is_ok());
    }
}
