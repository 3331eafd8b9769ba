//! The pinhole camera, in raypack's one convention.
//!
//! Right-handed; eye `E`, look-at `L`, up `U`, vertical field of view `vfov`
//! (full angle between the top and bottom image edges), image `W × H`:
//! `f = normalize(L − E)`, `r = normalize(f × U)`, `u = r × f`. Pixel
//! `(i, j)` (column from the left, row from the top) is sampled at its centre:
//! `sx = (2(i + ½)/W − 1)·tan(vfov/2)·W/H`, `sy = (1 − 2(j + ½)/H)·tan(vfov/2)`,
//! `dir = normalize(f + sx·r + sy·u)`.
//!
//! Packets cover adjacent pixels: 1×1 for width 1, 2×2 for 4, 4×2 for 8,
//! 4×4 for 16 (see [`packet_shape`]).

use crate::geom::fixed_range::{self, RangeError, RangeItem};
use crate::geom::ray::RayPacket;
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::Vec3;
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::{Divisor, Scalar};

/// Why a camera could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraError {
    /// A number is NaN or infinite.
    NonFinite,
    /// The eye and the look-at point coincide.
    EyeAtTarget,
    /// The up vector is zero or parallel to the view direction.
    UpParallel,
    /// The field of view is not strictly between 0 and 180 degrees.
    FieldOfView,
    /// The image has no pixels, or more than 65 535 in a dimension.
    ImageSize,
    /// The eye or look-at point is beyond the scalar type's coordinate
    /// limit (fixed point; see [`crate::geom::fixed_range`]).
    OutOfRange(RangeError),
}

impl core::fmt::Display for CameraError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            CameraError::NonFinite => "camera numbers must be finite",
            CameraError::EyeAtTarget => "the camera's eye and look-at point coincide",
            CameraError::UpParallel => "the up vector is zero or parallel to the view direction",
            CameraError::FieldOfView => "the field of view must be between 0 and 180 degrees",
            CameraError::ImageSize => "the image size must be between 1 and 65535 pixels per side",
            CameraError::OutOfRange(e) => return e.fmt(f),
        })
    }
}

impl core::error::Error for CameraError {}

/// Pixels covered by a packet of width `W`: `(columns, rows)`.
pub const fn packet_shape(w: usize) -> (u32, u32) {
    match w {
        1 => (1, 1),
        2 => (2, 1),
        4 => (2, 2),
        8 => (4, 2),
        16 => (4, 4),
        n => (n as u32, 1),
    }
}

pub use crate::geom::rect::Rect;

/// A pinhole camera for an image of a given size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera<S> {
    eye: Vec3<S>,
    forward: Vec3<S>,
    right: Vec3<S>,
    up: Vec3<S>,
    width: u32,
    height: u32,
    /// `width` and `height` as divisors of pixel coordinates.
    width_div: Divisor,
    height_div: Divisor,
    /// `tan(vfov/2)·W/H`.
    sx_scale: S,
    /// `tan(vfov/2)`.
    sy_scale: S,
    /// Units of the scene's description per unit of the frame the camera
    /// (and its scene) lives in: 1 unless the scene was brought into a
    /// small frame for a limited-range scalar ([`crate::geom::uniform_scale`]). The
    /// depth AOV reports distances in the description's units.
    units: f32,
}

crate::num::bake::bake_struct!("raypack::geom::camera::Camera", Camera<S> { eye: Vec3<S>, forward: Vec3<S>, right: Vec3<S>, up: Vec3<S>, width: u32, height: u32, width_div: Divisor, height_div: Divisor, sx_scale: S, sy_scale: S, units: f32 });

impl<S: Scalar> Camera<S> {
    /// A camera at `eye` looking at `look_at`, with `up` (any length, not
    /// parallel to the view direction), vertical field of view `vfov_deg`
    /// degrees, for a `width × height` image.
    pub fn new(
        eye: Vec3<S>,
        look_at: Vec3<S>,
        up: Vec3<S>,
        vfov_deg: f32,
        width: u32,
        height: u32,
    ) -> Result<Self, CameraError> {
        if !eye.is_finite() || !look_at.is_finite() || !up.is_finite() || !vfov_deg.is_finite() {
            return Err(CameraError::NonFinite);
        }
        if width == 0 || height == 0 || width > 65535 || height > 65535 {
            return Err(CameraError::ImageSize);
        }
        if !(vfov_deg > 0.0 && vfov_deg < 180.0) {
            return Err(CameraError::FieldOfView);
        }
        fixed_range::check_point(eye, RangeItem::Camera).map_err(CameraError::OutOfRange)?;
        fixed_range::check_point(look_at, RangeItem::Camera).map_err(CameraError::OutOfRange)?;
        let forward = (look_at - eye).normalize_or_zero();
        if forward == Vec3::ZERO {
            return Err(CameraError::EyeAtTarget);
        }
        let right = forward.cross(up).normalize_or_zero();
        if right == Vec3::ZERO {
            return Err(CameraError::UpParallel);
        }
        let up = right.cross(forward);
        // tan of the half angle, from libm (bit-identical on every target),
        // converted once.
        let half = vfov_deg * (core::f32::consts::PI / 360.0);
        let tan_half = S::from_f32(libm::tanf(half));
        let aspect = S::ratio(width, height);
        Ok(Camera {
            eye,
            forward,
            right,
            up,
            width,
            height,
            width_div: Divisor::new(width),
            height_div: Divisor::new(height),
            sx_scale: tan_half * aspect,
            sy_scale: tan_half,
            units: 1.0,
        })
    }

    /// The camera of a view described in `f32`, in a scene's own units (eye
    /// `from`, look-at point `at`, up vector `up`, vertical field of view
    /// `vfov_deg`), in the frame `frame` the scene is traced in (see
    /// [`crate::geom::uniform_scale`]). A scalar without a frame of its own
    /// ([`Scalar::SCENE_FRAME`] `None`) gets [`Camera::new`] of the numbers
    /// as they are, and `frame` is not used. One with a frame gets the eye
    /// moved and scaled by `frame`, the look-at point replaced by the point
    /// one unit from the eye in the same direction (so it lies near the
    /// scene, however far away the description puts it), the up vector
    /// unchanged, and distances reported in the description's units.
    pub fn in_frame(
        from: [f32; 3],
        at: [f32; 3],
        up: [f32; 3],
        vfov_deg: f32,
        width: u32,
        height: u32,
        frame: &Similarity,
    ) -> Result<Self, CameraError> {
        let v = |a: [f32; 3]| Vec3::<S>::from_f32(a[0], a[1], a[2]);
        if S::SCENE_FRAME.is_none() {
            return Camera::new(v(from), v(at), v(up), vfov_deg, width, height);
        }
        let eye = Vec3::new(from[0], from[1], from[2]);
        let dir = (Vec3::new(at[0], at[1], at[2]) - eye).normalize_or_zero();
        if dir == Vec3::ZERO {
            return Err(if eye.is_finite() { CameraError::EyeAtTarget } else { CameraError::NonFinite });
        }
        let e: Vec3<f32> = frame.point(eye);
        let c = |v: Vec3<f32>| Vec3::<S>::from_f32(v.x, v.y, v.z);
        Camera::new(c(e), c(e + dir), v(up), vfov_deg, width, height).map(|c| c.with_units(frame.units_per_unit()))
    }

    /// The same camera, saying that one unit of its frame is `units` units
    /// of the scene's description (see [`crate::geom::uniform_scale`]); `units` is
    /// what distances (the depth AOV) are multiplied by to be reported in
    /// the description's units. Non-finite or non-positive values are
    /// ignored.
    pub fn with_units(self, units: f32) -> Self {
        if units.is_finite() && units > 0.0 {
            Camera { units, ..self }
        } else {
            self
        }
    }

    /// Units of the scene's description per unit of the camera's frame
    /// (1 unless set by [`Camera::with_units`]).
    pub fn units(&self) -> f32 {
        self.units
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }
    /// The eye point.
    pub fn eye(&self) -> Vec3<S> {
        self.eye
    }
    /// The orthonormal frame `(forward, right, up)`.
    pub fn frame(&self) -> (Vec3<S>, Vec3<S>, Vec3<S>) {
        (self.forward, self.right, self.up)
    }
    /// The screen scales `(tan(vfov/2)·W/H, tan(vfov/2))`: the pixel whose
    /// centre is at `(u, v)` of `[0, 2]²` (see the module docs) looks along
    /// `forward + (u − 1)·sx·right + (1 − v)·sy·up`.
    pub fn screen_scale(&self) -> (S, S) {
        (self.sx_scale, self.sy_scale)
    }
    /// The whole image as a rectangle.
    pub fn full_rect(&self) -> Rect {
        Rect { x: 0, y: 0, w: self.width, h: self.height }
    }

    /// The packet of primary rays whose top-left pixel is `(x, y)`, laid out
    /// as [`packet_shape`]`(W)`; lanes whose pixel falls outside `clip` (or
    /// the image) are inactive in the returned mask.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn packet<const W: usize>(&self, x: u32, y: u32, clip: Rect) -> (RayPacket<S, W>, Mask<W>) {
        self.subpixel_packet(x, y, clip, 1, 0, 0)
    }

    /// The packet of rays through subpixel `(a, b)` of an `n × n` regular
    /// grid in each pixel (column `a`, row `b`, both `0..n`, clamped), for
    /// the pixels of [`Camera::packet`]`(x, y, clip)`. The subpixel's centre
    /// is at `((a + ½)/n, (b + ½)/n)` of the pixel from its top-left corner.
    /// With `n = 1` these are exactly [`Camera::packet`]'s rays.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn subpixel_packet<const W: usize>(
        &self,
        x: u32,
        y: u32,
        clip: Rect,
        n: u32,
        a: u32,
        b: u32,
    ) -> (RayPacket<S, W>, Mask<W>) {
        let n = n.clamp(1, 256);
        let (a, b) = (a.min(n - 1), b.min(n - 1));
        let (pw, _) = packet_shape(W);
        // Screen coordinates of the subpixel centres (see the module docs):
        // with `i + (a + ½)/n` for the pixel centre `i + ½`, twice it over
        // `W` is `u = ((2i + 1)·n + 2a + 1 − n) / (n·W)` per lane, one
        // rounded quotient of two integers (for `n = 1`: `(2i + 1)/W`);
        // the same for `v`. Then lane arithmetic.
        let mut un = [0u32; W];
        let mut vn = [0u32; W];
        let mut inside = [false; W];
        for l in 0..W {
            // Saturating: a pixel past u32::MAX is outside any image anyway.
            let i = x.saturating_add(l as u32 % pw);
            let j = y.saturating_add(l as u32 / pw);
            // `&`, not `&&`: no branch per lane, so the loop vectorises
            // (a wrapped difference only matters where `i < clip.x` has
            // already cleared the lane).
            let inside_l = (i >= clip.x)
                & (i.wrapping_sub(clip.x) < clip.w)
                & (j >= clip.y)
                & (j.wrapping_sub(clip.y) < clip.h)
                & (i < self.width)
                & (j < self.height);
            inside[l] = inside_l;
            let i = if inside_l { i } else { 0 };
            let j = if inside_l { j } else { 0 };
            // At most (2·65535 + 1)·256 < 2³²: no overflow.
            un[l] = (2 * i + 1) * n + 2 * a + 1 - n;
            vn[l] = (2 * j + 1) * n + 2 * b + 1 - n;
        }
        // The quotients in a loop of their own, one per lane with one
        // divisor: for `f32` a packed conversion and a packed division.
        // (Without supersampling, the camera's own divisors, whose
        // reciprocals it keeps; with, plain divisions.)
        let (ud, vd) = if n == 1 {
            (self.width_div, self.height_div)
        } else {
            (Divisor::plain(n * self.width), Divisor::plain(n * self.height))
        };
        let mut u = Lanes::<S, W>::zero();
        let mut v = Lanes::<S, W>::zero();
        for l in 0..W {
            u.0[l] = S::ratio_by(un[l], &ud);
            v.0[l] = S::ratio_by(vn[l], &vd);
        }
        let one = Lanes::splat(S::ONE);
        let sx = (u - one) * self.sx_scale;
        let sy = (one - v) * self.sy_scale;
        // forward + right·sx + up·sy, left to right (in fixed point without
        // the products of zero components, the same bits).
        let dir = self.forward.splat::<W>().add_splat_scaled(self.right, sx).add_splat_scaled(self.up, sy);
        let (ray, ok) = RayPacket::new(self.eye.splat(), dir);
        (ray, ok & Mask::from_array(inside))
    }
}

/// The terms of a row of packets of camera rays that depend only on the
/// row ([`Camera::packet_row`]): for each lane, whether its pixel row is
/// inside the clip and the image, and `up·sy` for that row and for row 0
/// (which [`Camera::subpixel_packet`] uses for lanes outside the clip).
/// With it, [`Camera::packet_in_row`] forms the packets of the row with
/// the same bits as [`Camera::packet`], without the per-row quotient and
/// products at every packet.
#[derive(Clone, Copy, Debug)]
pub struct PacketRow<S, const W: usize> {
    y: u32,
    clip: Rect,
    rows_inside: [bool; W],
    up_sy: Vec3<Lanes<S, W>>,
    up_sy0: Vec3<Lanes<S, W>>,
}

impl<S: Scalar, const W: usize> PacketRow<S, W> {
    /// The top pixel row of the packets this row serves.
    pub fn y(&self) -> u32 {
        self.y
    }
}

impl<S: Scalar> Camera<S> {
    /// The row terms of the packets whose top-left pixels lie on row `y`,
    /// clipped to `clip` (see [`PacketRow`]).
    // Inline on x86 like the rest of the packet code: a dispatched
    // render's copy is compiled for its instruction set
    // (scripts/check-asm.sh).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn packet_row<const W: usize>(&self, y: u32, clip: Rect) -> PacketRow<S, W> {
        let (pw, _) = packet_shape(W);
        let mut vn = [1u32; W];
        let mut rows_inside = [false; W];
        for l in 0..W {
            let j = y.saturating_add(l as u32 / pw);
            let inside = (j >= clip.y) & (j.wrapping_sub(clip.y) < clip.h) & (j < self.height);
            rows_inside[l] = inside;
            // As `subpixel_packet` with one sample: `2j + 1`, row 0's for
            // lanes outside (below 2·65535 + 1: no overflow).
            vn[l] = if inside { 2 * j + 1 } else { 1 };
        }
        PacketRow { y, clip, rows_inside, up_sy: self.up_sy(vn), up_sy0: self.up_sy([1; W]) }
    }

    /// Whether the screen offsets `sx_scale` and `sy_scale` are at most 4
    /// (a field of view up to about 150°), so that a packet's terms can
    /// take their short forms ([`Camera::packet_in_row`]).
    #[inline(always)]
    fn short_terms(&self) -> bool {
        let four = S::TWO + S::TWO;
        self.sx_scale.abs() <= four && self.sy_scale.abs() <= four
    }

    /// `up·sy` for the rows `(vn − 1)/2` of each lane.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn up_sy<const W: usize>(&self, vn: [u32; W]) -> Vec3<Lanes<S, W>> {
        let mut v = Lanes::<S, W>::zero();
        for l in 0..W {
            v.0[l] = S::ratio_by(vn[l], &self.height_div);
        }
        let sy = (Lanes::splat(S::ONE) - v) * self.sy_scale;
        // The products `add_splat_scaled` forms (a zero component's is
        // never added where products of zero are skipped).
        Vec3::new(Lanes::splat(self.up.x) * sy, Lanes::splat(self.up.y) * sy, Lanes::splat(self.up.z) * sy)
    }

    /// The packet of [`Camera::packet`]`(x, row.y(), clip)` (the row's
    /// clip), bit for bit, from the row's terms.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn packet_in_row<const W: usize>(&self, row: &PacketRow<S, W>, x: u32) -> (RayPacket<S, W>, Mask<W>) {
        let (pw, _) = packet_shape(W);
        let clip = row.clip;
        let mut un = [0u32; W];
        let mut inside = [false; W];
        for l in 0..W {
            let i = x.saturating_add(l as u32 % pw);
            let inside_l = (i >= clip.x) & (i.wrapping_sub(clip.x) < clip.w) & (i < self.width) & row.rows_inside[l];
            inside[l] = inside_l;
            un[l] = 2 * (if inside_l { i } else { 0 }) + 1;
        }
        let mut u = Lanes::<S, W>::zero();
        for l in 0..W {
            u.0[l] = S::ratio_by(un[l], &self.width_div);
        }
        // In a scalar of limited range, with screen offsets of at most 4
        // ([`Camera::short_terms`]) the products and sums take their short
        // forms, the same bits: `u − 1` lies in (−1, 1), so `sx` and the
        // unit `right`'s components are at most 4; `forward + right·sx` is
        // at most 5 in each component, and `up·sy` at most 4 more.
        let small = S::LIMITED_RANGE && self.short_terms();
        let u1 = u - Lanes::splat(S::ONE);
        let base = if small {
            let sx = u1.mul_small(Lanes::splat(self.sx_scale));
            self.forward.splat::<W>().add_splat_scaled_small(self.right, sx)
        } else {
            self.forward.splat::<W>().add_splat_scaled(self.right, u1 * self.sx_scale)
        };
        let m = Mask::from_array(inside);
        // `+ up·sy` as `add_splat_scaled` adds it, the row's products.
        let term = |acc: Lanes<S, W>, c: S, t: Lanes<S, W>, t0: Lanes<S, W>| {
            if S::SPARSE_PRODUCTS && c == S::ZERO {
                acc
            } else if small {
                acc.add_small(Lanes::select(m, t, t0))
            } else {
                acc + Lanes::select(m, t, t0)
            }
        };
        let dir = Vec3::new(
            term(base.x, self.up.x, row.up_sy.x, row.up_sy0.x),
            term(base.y, self.up.y, row.up_sy.y, row.up_sy0.y),
            term(base.z, self.up.z, row.up_sy.z, row.up_sy0.z),
        );
        let (ray, ok) = RayPacket::new(self.eye.splat(), dir);
        (ray, ok & m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rays from a packet row's terms are [`Camera::packet`]'s, bit for
    /// bit, in every lane (active or not), for tilted cameras (in fixed
    /// point with the short products and sums, and with a field of view
    /// too wide for them), clips inside,
    /// across and outside the image, every packet position of a band
    /// (including those hanging over the edges) and widths 1 to 16.
    fn rows_agree<S: Scalar + PartialEq + core::fmt::Debug, const W: usize>() {
        let v = |x: f32, y: f32, z: f32| Vec3::new(S::from_f32(x), S::from_f32(y), S::from_f32(z));
        let cams = [
            Camera::new(v(0.0, 0.0, 0.0), v(0.0, 0.0, -1.0), v(0.0, 1.0, 0.0), 60.0, 13, 9),
            Camera::new(v(0.3, -0.2, 0.9), v(-0.1, 0.2, -0.4), v(0.2, 1.0, 0.1), 75.0, 13, 9),
            Camera::new(v(0.5, 0.5, 0.5), v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0), 40.0, 7, 16),
            // Screen offsets past 4 (tan 85° ≈ 11.4): the general products
            // and sums in fixed point.
            Camera::new(v(0.1, 0.2, 0.3), v(0.4, -0.3, 0.2), v(0.0, 0.0, 1.0), 170.0, 11, 7),
        ];
        for cam in cams.into_iter().map(|c| c.unwrap()) {
            let (w, h) = (cam.width(), cam.height());
            let clips = [
                cam.full_rect(),
                Rect { x: 2, y: 1, w: 7, h: 5 },
                Rect { x: 3, y: 2, w: 40, h: 40 },
                Rect { x: 50, y: 0, w: 3, h: 3 },
            ];
            let (pw, ph) = packet_shape(W);
            for clip in clips {
                for y in (0..h + 2).step_by(ph as usize) {
                    let row = cam.packet_row::<W>(y, clip);
                    for x in (0..w + 2).step_by(pw as usize) {
                        let (want, want_m) = cam.packet::<W>(x, y, clip);
                        let (got, got_m) = cam.packet_in_row(&row, x);
                        assert_eq!(got_m, want_m, "({x}, {y}) in {clip:?}");
                        assert_eq!(got.origin, want.origin);
                        assert_eq!(got.dir, want.dir, "({x}, {y}) in {clip:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn packet_rows_give_the_packets() {
        rows_agree::<f32, 1>();
        rows_agree::<f32, 4>();
        rows_agree::<f32, 8>();
        rows_agree::<f32, 16>();
        rows_agree::<crate::num::fixed32::Fixed32, 1>();
        rows_agree::<crate::num::fixed32::Fixed32, 4>();
        rows_agree::<crate::num::fixed32::Fixed32, 16>();
    }

    fn cam(w: u32, h: u32) -> Camera<f32> {
        Camera::new(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 1.0, 0.0), 90.0, w, h).unwrap()
    }

    #[test]
    fn frame_follows_convention() {
        let c = cam(4, 2);
        let (f, r, u) = c.frame();
        assert_eq!(f, Vec3::new(0.0, 0.0, -1.0));
        assert_eq!(r, Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(u, Vec3::new(0.0, 1.0, 0.0));
    }

    #[test]
    fn corner_pixel_direction() {
        // 90° vfov: tan = 1; 4×2 image: aspect 2. Pixel (0,0): sx = (1/4 − 1)·2 = −1.5, sy = 1 − 1/2 = 0.5.
        let c = cam(4, 2);
        let (ray, m) = c.packet::<1>(0, 0, c.full_rect());
        assert!(m.get(0));
        let d = ray.dir.lane(0);
        let e = Vec3::new(-1.5f32, 0.5, -1.0).normalize_or_zero();
        assert!((d - e).length() < 1e-6, "{d:?}");
    }

    #[test]
    fn packet_lanes_are_adjacent_pixels_and_clip() {
        let c = cam(5, 3);
        let (p8, m8) = c.packet::<8>(4, 2, c.full_rect());
        // Only the top-left lane (4, 2) is inside a 5×3 image.
        assert_eq!(m8.to_array(), [true, false, false, false, false, false, false, false]);
        let (p1, _) = c.packet::<1>(4, 2, c.full_rect());
        assert_eq!(p8.dir.lane(0), p1.dir.lane(0));
        let (p4, m4) = c.packet::<4>(0, 0, c.full_rect());
        assert!(m4.all());
        let (q, _) = c.packet::<1>(1, 1, c.full_rect());
        assert_eq!(p4.dir.lane(3), q.dir.lane(0));
    }

    #[test]
    fn subpixels_of_a_one_sample_grid_are_the_centres_and_others_lie_inside_the_pixel() {
        let c = cam(6, 4);
        for w in [(0u32, 0u32), (3, 1), (5, 3)] {
            let (p, m) = c.packet::<4>(w.0, w.1, c.full_rect());
            let (q, n) = c.subpixel_packet::<4>(w.0, w.1, c.full_rect(), 1, 0, 0);
            assert_eq!((p.dir, m), (q.dir, n));
        }
        // 90° vfov, 6×4: sx = (2u/6 − 1)·1.5, sy = 1 − 2v/4 with u = i + 1/6
        // (subpixel 0 of 3), v = j + 5/6 (subpixel 2 of 3).
        let (q, _) = c.subpixel_packet::<1>(2, 1, c.full_rect(), 3, 0, 2);
        let (u, v) = (2.0 + 1.0 / 6.0, 1.0 + 5.0 / 6.0);
        let e = Vec3::new((2.0 * u / 6.0 - 1.0) * 1.5, 1.0 - 2.0 * v / 4.0, -1.0f32).normalize_or_zero();
        assert!((q.dir.lane(0) - e).length() < 1e-6, "{:?}", q.dir.lane(0));
    }

    #[test]
    fn bad_cameras_are_errors() {
        let o = Vec3::new(0.0f32, 0.0, 0.0);
        let z = Vec3::new(0.0f32, 0.0, 1.0);
        let y = Vec3::new(0.0f32, 1.0, 0.0);
        assert_eq!(Camera::new(o, o, y, 45.0, 4, 4), Err(CameraError::EyeAtTarget));
        assert_eq!(Camera::new(o, z, z, 45.0, 4, 4), Err(CameraError::UpParallel));
        assert_eq!(Camera::new(o, z, Vec3::ZERO, 45.0, 4, 4), Err(CameraError::UpParallel));
        assert_eq!(Camera::new(o, z, y, 180.0, 4, 4), Err(CameraError::FieldOfView));
        assert_eq!(Camera::new(o, z, y, f32::NAN, 4, 4), Err(CameraError::NonFinite));
        assert_eq!(Camera::new(o, z, y, 45.0, 0, 4), Err(CameraError::ImageSize));
    }

    #[test]
    fn camera_beyond_the_fixed_point_limit_is_an_error_naming_it() {
        use crate::num::fixed64::Fixed;
        let v = |x, y, z| Vec3::<Fixed>::from_f32(x, y, z);
        let r = Camera::<Fixed>::new(v(0.0, 0.0, 5000.0), v(0.0, 0.0, 0.0), v(0.0, 1.0, 0.0), 45.0, 8, 8);
        assert_eq!(
            r,
            Err(CameraError::OutOfRange(RangeError { item: RangeItem::Camera, magnitude: 5000, limit: 4096 }))
        );
        let far = Vec3::new(0.0f32, 0.0, 5000.0);
        assert!(Camera::<f32>::new(far, Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 8).is_ok());
    }
}
