//! Similarity transforms (a uniform scale about a centre): how a scene
//! described in any units is brought into the small, fixed box a
//! limited-range scalar (fixed point) computes in.
//!
//! A ray-traced image does not change when the whole world (primitives,
//! lights, the camera's eye and look-at point) is moved and scaled
//! uniformly: directions, angles and therefore every shading term stay the
//! same, and every distance `t` along a ray scales by the same factor. So a
//! scene can be described and built in `f32`, in whatever units it was
//! written, and converted once, at load time, into a frame where its
//! coordinates are small ([`Similarity::fitting`]); the fixed-point tracer
//! then never sees a large number. The transform is computed in `f32`,
//! before the conversion, so the scene loses no precision to it.
//!
//! `x' = (x − origin)·scale` for points, `l' = l·scale` for lengths;
//! directions and unit normals are unchanged.

use crate::geom::vec3::Vec3;
use crate::num::scalar::Scalar;

/// A uniform scale about a point: `x' = (x − origin)·scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Similarity {
    /// The point that becomes the new origin.
    pub origin: [f32; 3],
    /// The factor every length is multiplied by (positive, finite).
    pub scale: f32,
}

impl Similarity {
    /// The identity: nothing moves.
    pub const IDENTITY: Similarity = Similarity { origin: [0.0; 3], scale: 1.0 };

    /// The transform that maps the box `[lo, hi]` into `[−half, half]³`,
    /// centred: the box's centre becomes the origin and its largest
    /// half-extent becomes `half`. A box of no extent (one point) or a
    /// non-finite one gives a pure translation (scale 1), and so does a
    /// scale that would not be a positive finite number.
    pub fn fitting(lo: [f32; 3], hi: [f32; 3], half: f32) -> Similarity {
        let mut origin = [0.0f32; 3];
        let mut extent = 0.0f32;
        for a in 0..3 {
            origin[a] = lo[a] * 0.5 + hi[a] * 0.5;
            extent = extent.max((hi[a] - lo[a]) * 0.5);
        }
        if !origin.iter().all(|v| v.is_finite()) {
            return Similarity::IDENTITY;
        }
        let scale = half / extent;
        if extent > 0.0 && scale.is_finite() && scale > 0.0 {
            Similarity { origin, scale }
        } else {
            Similarity { origin, scale: 1.0 }
        }
    }

    /// `p` in the new frame, converted to `T` (computed in `f32`).
    pub fn point<S: Scalar, T: Scalar>(&self, p: Vec3<S>) -> Vec3<T> {
        let [x, y, z] = p.to_f32();
        let [ox, oy, oz] = self.origin;
        Vec3::from_f32((x - ox) * self.scale, (y - oy) * self.scale, (z - oz) * self.scale)
    }

    /// A length in the new frame, converted to `T`.
    pub fn length<S: Scalar, T: Scalar>(&self, l: S) -> T {
        T::from_f32(l.to_f32() * self.scale)
    }

    /// A direction (or a unit normal): unchanged, converted to `T`.
    pub fn direction<S: Scalar, T: Scalar>(&self, d: Vec3<S>) -> Vec3<T> {
        let [x, y, z] = d.to_f32();
        Vec3::from_f32(x, y, z)
    }

    /// How many units of the original frame one unit of the new frame is
    /// (`1 / scale`): what distances measured in the new frame are
    /// multiplied by to report them in the original units.
    pub fn units_per_unit(&self) -> f32 {
        1.0 / self.scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fitting_centres_and_scales_the_largest_extent() {
        let s = Similarity::fitting([-1.0, 2.0, 0.0], [3.0, 4.0, 1.0], 1.0);
        assert_eq!(s.origin, [1.0, 3.0, 0.5]);
        assert_eq!(s.scale, 0.5);
        let p: Vec3<f32> = s.point(Vec3::new(3.0f32, 4.0, 1.0));
        assert_eq!(p, Vec3::new(1.0, 0.5, 0.25));
        assert_eq!(s.length::<f32, f32>(4.0), 2.0);
        assert_eq!(s.direction::<f32, f32>(Vec3::new(0.0, 1.0, 0.0)), Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(s.units_per_unit(), 2.0);
    }

    #[test]
    fn degenerate_boxes_only_translate() {
        assert_eq!(Similarity::fitting([1.0; 3], [1.0; 3], 1.0), Similarity { origin: [1.0; 3], scale: 1.0 });
        assert_eq!(Similarity::fitting([f32::NAN; 3], [1.0; 3], 1.0), Similarity::IDENTITY);
        assert_eq!(Similarity::fitting([f32::NEG_INFINITY; 3], [f32::INFINITY; 3], 1.0), Similarity::IDENTITY);
        // An extent so small that the scale overflows.
        assert_eq!(Similarity::fitting([0.0; 3], [1.0e-45; 3], 1.0e30).scale, 1.0);
    }
}
