//! Range checks for scalars of limited range (fixed point).
//!
//! A fixed-point scalar represents magnitudes only up to a bound, so a scene
//! traced with one must keep the tracer's largest intermediates inside it.
//! Those are squared distances between two scene points (the sphere test's
//! `|o − c|²`, the shading code's `|light − p|²`) and the terms of the
//! quadric and cone discriminants. Each limited-range [`Scalar`] states two
//! limits, derived in its own module from its format:
//! - [`Scalar::COORDINATE_LIMIT`]: the largest coordinate magnitude a scene
//!   may use, so that squared distances between scene points fit;
//! - [`Scalar::INTERMEDIATE_LIMIT`]: the largest single intermediate a
//!   kernel may form, leaving room for the sums it enters.
//!
//! Quadrics and cones carry coefficients (`1/r²`, a cone's slope) that scale
//! their intermediates further, so [`check_intermediates`] bounds their
//! discriminant terms from the scene's actual extent (scale-aware: a small
//! ellipsoid in a small scene is fine; the same ellipsoid in a scene 1000
//! units wide is not). The whole-scene check is
//! [`SceneView::check_range`](crate::scene::SceneView::check_range).
//!
//! Points beyond the extent arise only as hit points on unbounded primitives
//! (planes, unclipped quadrics) far along a grazing ray. Their intermediates
//! saturate: results there are defined (never a panic) but may be inexact.
//!
//! For `f32` ([`Scalar::LIMITED_RANGE`] is false) every check passes.
//!
//! This module is a leaf: it knows shapes and numbers, not scenes or cameras.

use crate::geom::primitives::Shape;
use crate::geom::vec3::Vec3;
use crate::num::scalar::Scalar;

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

impl core::error::Error for RangeError {}

fn error(item: RangeItem, magnitude: f32, limit: f32) -> RangeError {
    // `as` saturates (and maps NaN to 0, impossible here: inputs are magnitudes).
    RangeError { item, magnitude: libm::ceilf(magnitude) as u64, limit: limit as u64 }
}

/// Largest absolute coordinate of a point, in `f32`.
pub fn magnitude<S: Scalar>(p: Vec3<S>) -> f32 {
    p.max_abs().to_f32()
}

/// Checks one point against [`Scalar::COORDINATE_LIMIT`] (a light's
/// position against [`Scalar::LIGHT_LIMIT`]).
pub fn check_point<S: Scalar>(p: Vec3<S>, item: RangeItem) -> Result<(), RangeError> {
    if !S::LIMITED_RANGE {
        return Ok(());
    }
    let limit = if matches!(item, RangeItem::Light(_)) { S::LIGHT_LIMIT } else { S::COORDINATE_LIMIT };
    let m = magnitude(p);
    if m > limit {
        return Err(error(item, m, limit));
    }
    Ok(())
}

/// Magnitude of a primitive's coordinates: its bounds, or for a plane its
/// distance from the origin; `None` for an unclipped quadric (unbounded, no
/// coordinates of its own: [`check_intermediates`] bounds its coefficients
/// instead).
pub fn shape_extent<S: Scalar>(shape: &Shape<S>, pool: &[Vec3<S>]) -> Option<f32> {
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

/// Bound on a quadric's or cone's intersection intermediates (its
/// discriminant terms) for rays with unit directions starting anywhere with
/// coordinates `|oᵢ| ≤ r`; 0 for every other shape.
///
/// - quadric (full-`b` form `b² − 4ac`), `Σ` of `A..F` = `Q₂`, of `G..I` =
///   `Q₁`: `|a| ≤ Q₂`, `|b| ≤ 2Q₂R + Q₁`, `|c| ≤ Q₂R² + Q₁R + |J|`; the
///   bound is `b² + 4|a||c|`;
/// - cone (half-`b` form `b'² − ac`, in its local frame: origin
///   `|o| ≤ O = 2√3·R`, slope `k`, base radius `r_b`, so
///   `|r(o)| ≤ r_b + |k|·O`): `|a| ≤ 1 + k²`, `|b'| ≤ O + |k|·|r(o)|`
///   (Cauchy–Schwarz with a unit direction), `|c| ≤ O² + r(o)²`; the bound
///   is `b'² + |a||c|`.
pub fn intermediate_bound<S: Scalar>(shape: &Shape<S>, r: f32) -> f32 {
    match shape {
        Shape::Quadric(q) => {
            let c = q.coefficients().map(|v| v.abs().to_f32());
            // Per coordinate (|oᵢ| ≤ R, |dᵢ| ≤ 1).
            let q2 = c[0] + c[1] + c[2] + c[3] + c[4] + c[5];
            let q1 = c[6] + c[7] + c[8];
            let by_terms = disc_bound(q2, 2.0 * q2 * r + q1, q2 * r * r + q1 * r + c[9]);
            // By norms: with the symmetric matrix M of A..F (Frobenius norm
            // ‖M‖ ≥ its spectral norm) and g = (G, H, I)/2, b = 2(Mo + g)·d,
            // a = dᵀMd, c = oᵀMo + 2g·o + J, and |o| ≤ √3·R.
            let m =
                libm::sqrtf(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + 0.5 * (c[3] * c[3] + c[4] * c[4] + c[5] * c[5]));
            let g = 0.5 * libm::sqrtf(c[6] * c[6] + c[7] * c[7] + c[8] * c[8]);
            let o = libm::sqrtf(3.0) * r;
            let by_norms = disc_bound(m, 2.0 * (m * o + g), m * o * o + 2.0 * g * o + c[9]);
            by_terms.min(by_norms)
        }
        Shape::Cone(cone) => {
            let o = 2.0 * libm::sqrtf(3.0) * r;
            let k = cone.slope().abs().to_f32();
            let (_, rb, _, _) = cone.ends();
            let ro = rb.to_f32() + k * o;
            let b = o + k * ro;
            b * b + (1.0 + k * k) * (o * o + ro * ro)
        }
        _ => 0.0,
    }
}

/// Checks [`intermediate_bound`] of primitive `index` at extent `r` against
/// [`Scalar::INTERMEDIATE_LIMIT`].
pub fn check_intermediates<S: Scalar>(shape: &Shape<S>, r: f32, index: u32) -> Result<(), RangeError> {
    if !S::LIMITED_RANGE {
        return Ok(());
    }
    let bound = intermediate_bound(shape, r);
    if !(bound <= S::INTERMEDIATE_LIMIT) {
        return Err(error(RangeItem::Intermediate(index), bound, S::INTERMEDIATE_LIMIT));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::primitives::{Cone, Quadric, Sphere};
    use crate::num::fixed64::Fixed;

    fn v<S: Scalar>(x: f32, y: f32, z: f32) -> Vec3<S> {
        Vec3::from_f32(x, y, z)
    }

    #[test]
    fn points_beyond_the_limit_are_rejected_for_fixed_point_only() {
        let far = v::<Fixed>(0.0, 0.0, -5000.0);
        assert_eq!(
            check_point(far, RangeItem::Light(3)),
            Err(RangeError { item: RangeItem::Light(3), magnitude: 5000, limit: 4096 })
        );
        assert_eq!(check_point(v::<Fixed>(4096.0, -4096.0, 0.0), RangeItem::Camera), Ok(()));
        assert_eq!(check_point(v::<f32>(0.0, 1.0e30, 0.0), RangeItem::Camera), Ok(()));
    }

    #[test]
    fn shapes_are_checked_by_their_bounds() {
        let near = Shape::Sphere(Sphere::new(v::<Fixed>(4000.0, 0.0, 0.0), Fixed::from_f32(90.0)).unwrap());
        let far = Shape::Sphere(Sphere::new(v::<Fixed>(4000.0, 0.0, 0.0), Fixed::from_f32(100.0)).unwrap());
        assert_eq!(check_shape(&near, &[], 0), Ok(()));
        assert_eq!(
            check_shape(&far, &[], 7),
            Err(RangeError { item: RangeItem::Primitive(7), magnitude: 4100, limit: 4096 })
        );
    }

    #[test]
    fn intermediates_scale_with_the_extent() {
        // A small ellipsoid (coefficients 1/0.3² ≈ 11) is fine in a scene 10
        // units wide and rejected in one 2000 units wide.
        let q = Shape::Quadric(Quadric::ellipsoid(v::<Fixed>(0.0, 0.0, 0.0), v(0.3, 0.3, 0.3)).unwrap());
        assert_eq!(check_intermediates(&q, 10.0, 0), Ok(()));
        let e = check_intermediates(&q, 2000.0, 0).unwrap_err();
        assert_eq!(e.item, RangeItem::Intermediate(0));
        assert!(e.magnitude > e.limit);
        // Cones: a steep slope scales the intermediates by k⁴.
        let gentle =
            Shape::Cone(Cone::new(v::<Fixed>(0.0, 0.0, 0.0), Fixed::ONE, v(0.0, 0.0, 1.0), Fixed::HALF).unwrap());
        assert_eq!(check_intermediates(&gentle, 10.0, 0), Ok(()));
        let steep = Shape::Cone(
            Cone::new(v::<Fixed>(0.0, 0.0, 0.0), Fixed::from_f32(1000.0), v(0.0, 0.0, 0.01), Fixed::ZERO).unwrap(),
        );
        assert_eq!(check_intermediates(&steep, 10.0, 1).unwrap_err().item, RangeItem::Intermediate(1));
        // f32 has no limit.
        let q = Shape::Quadric(Quadric::ellipsoid(v::<f32>(0.0, 0.0, 0.0), v(0.3, 0.3, 0.3)).unwrap());
        assert_eq!(check_intermediates(&q, 1.0e6, 0), Ok(()));
    }
}
