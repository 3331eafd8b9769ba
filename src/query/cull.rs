//! Frame-level culling: before a frame, what its rays can hit. For camera
//! rays ([`ScreenCull`]), the rectangle of pixels whose rays can hit each
//! primitive, so that a packet of camera rays tests only the primitives
//! whose rectangle it overlaps; for shadow rays ([`ShadowCull`]), the cone
//! of directions from each light that reaches each primitive; for reflected
//! and refracted rays ([`ShadowCull::reach_candidates`]), each primitive's
//! grown bounding sphere.
//!
//! Exact by construction: a primitive is left out of a packet only where no
//! ray of that packet can report a crossing with it, so the closest hit (and
//! its tie-break by lowest index, which [`BruteForce`](crate::query::BruteForce)
//! keeps by testing the candidates in index order) is the same, bit for bit,
//! as when every primitive is tested.
//!
//! # The rectangle
//!
//! A camera ray starts at the eye `E` and runs along the pixel's direction.
//! If the ray reports a crossing at `t`, the point `X = E + t·d` lies on the
//! primitive up to the rounding of the root computation, so inside its
//! axis-aligned bounds grown by a margin `m` (below). If the grown box lies
//! wholly in front of the eye (every corner at depth `z = (X − E)·f > m`),
//! the directions from the eye to its points are inside the projection of
//! its eight corners, `(x/z, y/z)` with `x = (X − E)·r`, `y = (X − E)·u`;
//! their bounding rectangle, turned into the continuous pixel coordinates
//! `cx = (sx/sx_scale + 1)·W/2`, `cy = (1 − sy/sy_scale)·H/2` (pixel `i`
//! covers `cx ∈ [i, i + 1]`, so its subsamples are covered too), grown by
//! the direction error `δ` and one more pixel each side, is the rectangle.
//! A primitive without bounds (a plane, an unclipped quadric), with bounds
//! that reach behind or around the eye, or with non-finite numbers gets the
//! whole image.
//!
//! The margins, in the frame's units (computed in `f32`, once per frame):
//! - `m = 4·ε·(1 + s) + 8·√(ρ·(1 + s))`, where `ε` is the scalar's
//!   [`Scalar::RAY_EPSILON`] (the tracer's own scale of "the same point"),
//!   `s` the largest coordinate magnitude of the eye and the box, and `ρ`
//!   the scalar's resolution (the smallest power of two it holds: 2⁻²⁴ for
//!   Q8.24). The first term covers rounding relative to the coordinates;
//!   the second covers fixed point's absolute rounding of squared
//!   distances (a sphere's discriminant `r² − |perp|²` is rounded to `ρ`,
//!   so a ray passing within about `√ρ` of a tiny sphere can report it);
//! - `δ = 1024·max(ρ, 2⁻²⁴)·(1 + sx_scale² + sy_scale²)` in screen units,
//!   the rounding of the camera's ray directions (a few units of `ρ` in
//!   each component, turned into screen units by the perspective divide).
//!
//! Both are hundreds of times the rounding they cover and far below a pixel
//! at ordinary image sizes, so they cost nothing measurable; the property
//! tests (tests/culling.rs) render random scenes and cameras both ways and
//! compare every byte.

use crate::geom::camera::Camera;
use crate::geom::primitives::Shape;
use crate::geom::ray::RayPacket;
use crate::geom::vec3::{Vec3, Vec3xW};
use crate::num::bins;
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;
use crate::scene::SceneView;

/// Which primitives a packet of rays may hit: bit `k` for primitive `k`
/// (primitives from index 32 on are always tested).
pub type Candidates = u32;

/// Every primitive a candidate.
pub const ALL: Candidates = u32::MAX;

/// The indices of the primitives to test among `len`, in increasing
/// order: the set bits of `candidates` below `len`, then every index from
/// 32 on (see [`Candidates`]).
///
/// Why an iterator over the bits: a packet's list is short (2.8 of the
/// demo's 11 primitives on average), and a loop over every index that
/// skips the clear bits costs a test and a shift for each.
#[inline(always)]
pub(crate) fn candidate_indices(candidates: Candidates, len: usize) -> CandidateIndices {
    let bits = if len >= 32 { candidates } else { candidates & ((1u32 << len) - 1) };
    CandidateIndices { bits: SetBits(bits), next: 32, len }
}

/// See [`candidate_indices`].
pub(crate) struct CandidateIndices {
    bits: SetBits,
    next: usize,
    len: usize,
}

/// The indices of the set bits of a mask, lowest first (and nothing past
/// bit 31: the tables here hold at most 32 entries, where
/// [`candidate_indices`]' tail past bit 32 cost the Cortex-M0 `fixed32`
/// frame 0.35 % and the M55's width 1 1.3 %).
#[derive(Clone, Copy)]
pub(crate) struct SetBits(pub(crate) u32);

impl Iterator for SetBits {
    type Item = usize;
    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let k = lowest_bit(self.0);
        // Clear the lowest set bit.
        self.0 &= self.0.wrapping_sub(1);
        Some(k)
    }
}

/// The index of the lowest set bit of `bits`, which is not zero.
///
/// Why a table on Armv6-M and on RISC-V without hardware floats: without
/// a count-trailing-zeros instruction `trailing_zeros` is a de Bruijn
/// product and a table load, about eight instructions; the lowest byte's
/// index from a 256-byte table is three, and a scene's first eight
/// primitives are all in it. (The RISC-V board with vectors and `F` lost
/// 0.4 % and 1.7 % at widths 1 and 8 with the table, so it keeps
/// `trailing_zeros`.)
#[inline(always)]
pub(crate) fn lowest_bit(bits: u32) -> usize {
    #[cfg(any(armv6m, rv32_soft_float))]
    {
        let low = bits as u8;
        if low != 0 {
            return LOWEST_BIT[low as usize] as usize;
        }
    }
    bits.trailing_zeros() as usize
}

/// `LOWEST_BIT[b]`: the index of `b`'s lowest set bit (0 for 0, never read).
#[cfg(any(armv6m, rv32_soft_float, test))]
static LOWEST_BIT: [u8; 256] = {
    let mut t = [0u8; 256];
    let mut b = 1;
    while b < 256 {
        t[b] = (b as u32).trailing_zeros() as u8;
        b += 1;
    }
    t
};

impl Iterator for CandidateIndices {
    type Item = usize;
    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if let Some(k) = self.bits.next() {
            return Some(k);
        }
        if self.next < self.len {
            let k = self.next;
            self.next += 1;
            return Some(k);
        }
        None
    }
}

/// Most primitives a [`ScreenCull`] holds (one bit each in [`Candidates`]).
pub const CULL_CAPACITY: usize = 32;

/// Why a [`ScreenCull`] could not be made (the renderer then tests every
/// primitive: culling is only ever a saving).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CullError {
    /// The scene has more primitives than [`CULL_CAPACITY`].
    Capacity {
        /// Primitives in the scene.
        primitives: usize,
    },
}

impl core::fmt::Display for CullError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            CullError::Capacity { primitives } => {
                write!(f, "{primitives} primitives, screen culling holds at most {CULL_CAPACITY}")
            }
        }
    }
}

impl core::error::Error for CullError {}

/// Inclusive pixel ranges `[x0, x1] × [y0, y1]`; empty when `x0 > x1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct PixelRect {
    x0: u16,
    x1: u16,
    y0: u16,
    y1: u16,
}

impl PixelRect {
    const EMPTY: PixelRect = PixelRect { x0: 1, x1: 0, y0: 1, y1: 0 };

    fn overlaps(&self, x0: u32, x1: u32, y0: u32, y1: u32) -> bool {
        (self.x0 as u32) <= x1 && x0 <= self.x1 as u32 && (self.y0 as u32) <= y1 && y0 <= self.y1 as u32
    }
}

/// Per primitive, the pixels whose camera rays can hit it (see the module
/// docs), for one scene and one camera.
#[derive(Clone, Copy, Debug)]
pub struct ScreenCull {
    rects: [PixelRect; CULL_CAPACITY],
    len: usize,
    full: PixelRect,
}

/// The smallest power of two `S` holds (`f32`: its smallest subnormal).
pub(crate) fn resolution<S: Scalar>() -> f32 {
    let mut v = 1.0f32;
    for _ in 0..160 {
        let h = v * 0.5;
        if h == 0.0 || S::from_f32(h).to_f32() != h {
            break;
        }
        v = h;
    }
    v
}

/// A primitive's bounds in `f32`.
fn bounds_f32<S: Scalar>(shape: &Shape<S>, pool: &[Vec3<S>]) -> Option<([f32; 3], [f32; 3])> {
    shape.cull_bounds(pool).map(|(lo, hi)| (lo.to_f32(), hi.to_f32()))
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The largest magnitude of `a`'s components (out of line, as
/// [`bounds_f32`]).
#[inline(never)]
fn max_abs(a: [f32; 3]) -> f32 {
    a[0].abs().max(a[1].abs()).max(a[2].abs())
}

/// What the camera says about directions, in `f32`.
struct View {
    eye: [f32; 3],
    f: [f32; 3],
    r: [f32; 3],
    u: [f32; 3],
    sx: f32,
    sy: f32,
    w: f32,
    h: f32,
    full: PixelRect,
}

/// Per primitive of a scene, in index order, the pixels whose camera rays
/// can hit it: `Some([x0, x1, y0, y1])`, inclusive, or `None` where no
/// pixel's can. The rectangles [`ScreenCull`] holds for the first
/// [`CULL_CAPACITY`] primitives, for any number of them (the host's
/// [`CameraTiles`](crate::query::CameraTiles) are built from them).
pub fn screen_rects<'s, S: Scalar>(
    scene: &'s SceneView<'_, S>,
    camera: &Camera<S>,
) -> impl Iterator<Item = Option<[u32; 4]>> + 's {
    let (view, [eps, rho, delta]) = View::new(camera);
    let pool = scene.vertices();
    scene.primitives().iter().map(move |p| {
        let r = match bounds_f32(&p.shape, pool) {
            None => view.full,
            Some((lo, hi)) => view.rect(lo, hi, eps, rho, delta),
        };
        (r.x0 <= r.x1 && r.y0 <= r.y1).then_some([r.x0 as u32, r.x1 as u32, r.y0 as u32, r.y1 as u32])
    })
}

impl ScreenCull {
    /// The rectangles of `scene`'s primitives for `camera`'s rays; an error
    /// if the scene has more than [`CULL_CAPACITY`] primitives.
    pub fn new<S: Scalar>(scene: &SceneView<'_, S>, camera: &Camera<S>) -> Result<Self, CullError> {
        let prims = scene.primitives();
        if prims.len() > CULL_CAPACITY {
            return Err(CullError::Capacity { primitives: prims.len() });
        }
        // (`View::new`'s work, written out: through the helper, even in
        // line, LLVM compiled the firmware's render loop differently and
        // the Cortex-M4F's `f32` frame took 56.66 M instructions, not
        // 54.45 M.)
        let (f, r, u) = camera.frame();
        let (sx, sy) = camera.screen_scale();
        let (w, h) = (camera.width(), camera.height());
        let full = PixelRect {
            x0: 0,
            x1: w.saturating_sub(1).min(65535) as u16,
            y0: 0,
            y1: h.saturating_sub(1).min(65535) as u16,
        };
        let view = View {
            eye: camera.eye().to_f32(),
            f: f.to_f32(),
            r: r.to_f32(),
            u: u.to_f32(),
            sx: sx.to_f32(),
            sy: sy.to_f32(),
            w: w as f32,
            h: h as f32,
            full,
        };
        let rho = resolution::<S>();
        let eps = S::RAY_EPSILON.to_f32();
        let delta = 1024.0 * rho.max(1.0 / 16_777_216.0) * (1.0 + view.sx * view.sx + view.sy * view.sy);
        let mut rects = [PixelRect::EMPTY; CULL_CAPACITY];
        for (slot, p) in rects.iter_mut().zip(prims) {
            *slot = match bounds_f32(&p.shape, scene.vertices()) {
                None => full,
                Some((lo, hi)) => view.rect(lo, hi, eps, rho, delta),
            };
        }
        Ok(ScreenCull { rects, len: prims.len(), full })
    }

    /// Primitives held.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether it holds no primitive.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The primitives whose rectangle meets the rows `y0 ..= y1` (what a
    /// band of rows narrows [`ScreenCull::candidates`] to; a primitive no
    /// pixel sees may stay in, as the packets' own test leaves it out).
    pub fn rows(&self, y0: u32, y1: u32) -> Candidates {
        self.candidates(ALL, 0, u32::MAX, y0, y1)
    }

    /// The primitives among `within` whose rectangle meets the pixels
    /// `[x0, x1] × [y0, y1]` (inclusive).
    pub fn candidates(&self, within: Candidates, x0: u32, x1: u32, y0: u32, y1: u32) -> Candidates {
        let mut m = within & !low_bits(self.len);
        // The candidates not yet tested, lowest first; done when none is left.
        let mut rest = within & low_bits(self.len);
        let mut bit: Candidates = 1;
        for r in self.rects.iter() {
            if rest == 0 {
                break;
            }
            if rest & bit != 0 {
                rest ^= bit;
                if r.overlaps(x0, x1, y0, y1) {
                    m |= bit;
                }
            }
            bit <<= 1;
        }
        m
    }

    /// [`ScreenCull::candidates`] of the packet of `w` columns starting at
    /// `x0` from `rows`, the candidates of its rows (what
    /// [`ScreenCull::candidates`] gives for columns `0 ..= u32::MAX`): only
    /// the columns are tested, the same set (a rectangle meets the pixels
    /// iff it meets both their rows and their columns). With it, the last
    /// `x` from `x0` on up to which every packet `[x, x + w − 1]` has those
    /// same candidates, so that a row's packets, left to right, look them up
    /// again only past it: each rectangle `[a, b]` meets the packet at `x`
    /// for `x` in `[a − (w − 1), b]`, and the set changes only where one of
    /// those ranges begins or ends.
    pub fn columns_from(&self, rows: Candidates, x0: u32, w: u32) -> (Candidates, u32) {
        let reach = w.saturating_sub(1);
        let mut m = rows & !low_bits(self.len);
        let mut until = u32::MAX;
        let mut rest = rows & low_bits(self.len);
        let mut bit: Candidates = 1;
        for r in self.rects.iter() {
            if rest == 0 {
                break;
            }
            if rest & bit != 0 {
                rest ^= bit;
                let (a, b) = ((r.x0 as u32).saturating_sub(reach), r.x1 as u32);
                if a > b {
                    // An empty rectangle: no packet meets it.
                } else if x0 < a {
                    // Met from `a` on.
                    until = until.min(a - 1);
                } else if x0 <= b {
                    m |= bit;
                    until = until.min(b);
                }
            }
            bit <<= 1;
        }
        (m, until)
    }

    /// Whether primitive `k`'s rectangle covers pixel `(x, y)` (true for
    /// primitives it does not hold).
    pub fn covers(&self, k: usize, x: u32, y: u32) -> bool {
        match self.rects.get(k) {
            Some(r) if k < self.len => r.overlaps(x, x, y, y),
            _ => true,
        }
    }

    /// How many of the primitives it holds have a rectangle smaller than
    /// the whole image (for reports).
    pub fn bounded(&self) -> usize {
        self.rects.iter().take(self.len).filter(|r| **r != self.full).count()
    }
}

/// The `n` lowest bits set (all 32 for `n >= 32`).
fn low_bits(n: usize) -> Candidates {
    if n >= 32 {
        ALL
    } else {
        (1 << n) - 1
    }
}

impl View {
    /// What `camera` says about directions, and the margins of scalar `S`:
    /// its [`Scalar::RAY_EPSILON`], its resolution `ρ` and the direction
    /// error `δ` (see the module docs), for [`screen_rects`].
    fn new<S: Scalar>(camera: &Camera<S>) -> (Self, [f32; 3]) {
        let (f, r, u) = camera.frame();
        let (sx, sy) = camera.screen_scale();
        let (w, h) = (camera.width(), camera.height());
        let full = PixelRect {
            x0: 0,
            x1: w.saturating_sub(1).min(65535) as u16,
            y0: 0,
            y1: h.saturating_sub(1).min(65535) as u16,
        };
        let view = View {
            eye: camera.eye().to_f32(),
            f: f.to_f32(),
            r: r.to_f32(),
            u: u.to_f32(),
            sx: sx.to_f32(),
            sy: sy.to_f32(),
            w: w as f32,
            h: h as f32,
            full,
        };
        let rho = resolution::<S>();
        let eps = S::RAY_EPSILON.to_f32();
        let delta = 1024.0 * rho.max(1.0 / 16_777_216.0) * (1.0 + view.sx * view.sx + view.sy * view.sy);
        (view, [eps, rho, delta])
    }

    /// The pixel rectangle of the box `[lo, hi]` (see the module docs).
    fn rect(&self, lo: [f32; 3], hi: [f32; 3], eps: f32, rho: f32, delta: f32) -> PixelRect {
        let s = 1.0 + max_abs(self.eye).max(max_abs(lo)).max(max_abs(hi));
        let m = 4.0 * eps * s + 8.0 * libm::sqrtf(rho * s);
        if !m.is_finite() {
            return self.full;
        }
        let (mut sx0, mut sx1, mut sy0, mut sy1) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
        for c in 0..8 {
            let pick = |i: usize| if c & (1 << i) == 0 { lo[i] - m } else { hi[i] + m };
            let v = [pick(0) - self.eye[0], pick(1) - self.eye[1], pick(2) - self.eye[2]];
            let z = dot(v, self.f);
            // A corner at or behind the eye's plane (or not a number): the
            // box reaches around the eye; every pixel may see it.
            if !(z > m) {
                return self.full;
            }
            let (x, y) = (dot(v, self.r) / z, dot(v, self.u) / z);
            sx0 = sx0.min(x);
            sx1 = sx1.max(x);
            sy0 = sy0.min(y);
            sy1 = sy1.max(y);
        }
        // Continuous pixel coordinates; rows grow downwards as `sy` falls.
        let cx0 = ((sx0 - delta) / self.sx + 1.0) * (self.w * 0.5);
        let cx1 = ((sx1 + delta) / self.sx + 1.0) * (self.w * 0.5);
        let cy0 = (1.0 - (sy1 + delta) / self.sy) * (self.h * 0.5);
        let cy1 = (1.0 - (sy0 - delta) / self.sy) * (self.h * 0.5);
        let (Some((x0, x1)), Some((y0, y1))) = (span(cx0, cx1, self.full.x1), span(cy0, cy1, self.full.y1)) else {
            return PixelRect::EMPTY;
        };
        PixelRect { x0, x1, y0, y1 }
    }
}

/// The pixels `i` (of `0 ..= last`) with `[i, i + 1]` meeting `[c0, c1]`
/// grown by one pixel each side, or `None` if there are none. Non-finite
/// bounds give every pixel.
fn span(c0: f32, c1: f32, last: u16) -> Option<(u16, u16)> {
    if !c0.is_finite() || !c1.is_finite() {
        return Some((0, last));
    }
    // From `floor(c0) − 2` to `floor(c1) + 1`, in unsigned integers: for
    // `c >= 0` the conversion (which truncates, and saturates: no panic,
    // no wrap) is the floor; a negative `c0` starts at pixel 0 anyway, and
    // a `c1` in `[−1, 0)` ends there.
    let i0 = if c0 >= 0.0 { (c0 as u32).saturating_sub(2) } else { 0 };
    let i1 = if c1 >= 0.0 {
        (c1 as u32).saturating_add(1)
    } else if c1 >= -1.0 {
        0
    } else {
        return None;
    };
    if i0 > last as u32 || i0 > i1 {
        return None;
    }
    Some((i0 as u16, i1.min(last as u32) as u16))
}

/// Most lights a [`ShadowCull`] holds (the shadow rays of further lights
/// test every primitive).
pub const SHADOW_LIGHTS: usize = 2;

/// Most primitives a [`ShadowCull`] holds per light (and for reflected and
/// refracted rays): the first ones of the scene; rays test every further
/// primitive. The table lives on the stack: 56 bytes per entry with
/// 32-bit scalars and two lights, so 32-bit targets (microcontrollers,
/// WebAssembly) hold 12 entries, 64-bit hosts 24.
pub const SHADOW_OCCLUDERS: usize = if cfg!(target_pointer_width = "64") { 24 } else { 12 };

/// Most planes per light whose side [`ShadowCull`] tests (further planes
/// are always candidates).
pub const SHADOW_PLANES: usize = 2;

/// A plane `n·x + d = 0` as seen from one light, the light well away from
/// it on the side `up` (`n·L + d > 0`) or the other: a shadow ray whose
/// origin lies on the light's side, by more than the margin, cannot cross
/// it before the light (see [`ShadowCull`]).
#[derive(Clone, Copy, Debug)]
struct PlaneSide<S> {
    k: u8,
    normal: Vec3<S>,
    d: S,
    up: bool,
    /// The axis of a normal that is `±1` on it and zero elsewhere (floors
    /// and walls) and whose offset is at most [`AXIS_PLANE_OFFSET`], 3
    /// otherwise. For those, the origins on the light's side are those
    /// whose component lies `above` (or else below) `limit`.
    axis: u8,
    above: bool,
    limit: S,
}

/// The largest offset `|d|` of an axis plane whose side [`PlaneSide`]
/// tells from one comparison: `−d` is exact in every scalar, and in fixed
/// point `±c + d` saturates only where its sign is the exact one.
const AXIS_PLANE_OFFSET: f32 = 64.0;

impl<S: Scalar> PlaneSide<S> {
    /// An unused entry.
    const NONE: Self =
        PlaneSide { k: 0, normal: Vec3::ZERO, d: S::ZERO, up: true, axis: 3, above: true, limit: S::ZERO };

    /// Plane `k`, `n·x + d = 0`, with the light on the side `up`. For an
    /// axis normal `±1` of small offset the kernel's signed distance is
    /// `±c + d` (`x·1 = x`, `x·(−1) = −x` and `0 + x = x` exactly, up to the
    /// sign of a zero, which no comparison with zero sees), and its sign is
    /// that of the exact sum: floating point rounds no nonzero sum to zero
    /// (nor changes its sign), and fixed point's saturation keeps the sign
    /// (`−c` saturates only at the bottom value, where `−c + d` is positive
    /// both ways for such a `d`). So `c + d > 0` is `c > −d`, and `−c + d >
    /// 0` is `c < d`: one comparison with `limit` instead of the sum.
    fn new(k: u8, normal: Vec3<S>, d: S, up: bool) -> Self {
        let (one, zero) = (S::ONE, S::ZERO);
        let unit = |a: S, b: S, c: S| (a == one || a == -one) && b == zero && c == zero;
        let axis = if !(d.abs() <= S::from_f32(AXIS_PLANE_OFFSET)) {
            3
        } else if unit(normal.x, normal.y, normal.z) {
            0
        } else if unit(normal.y, normal.z, normal.x) {
            1
        } else if unit(normal.z, normal.x, normal.y) {
            2
        } else {
            3
        };
        let flip = normal.x + normal.y + normal.z < zero;
        PlaneSide { k, normal, d, up, axis, above: up != flip, limit: if flip { d } else { -d } }
    }

    /// The plane's signed distance of the points `o` as its kernel computes
    /// it (`o·n + d`, [`Vec3xW::dot_splat`]).
    #[inline(always)]
    fn distance<const W: usize>(&self, o: &Vec3xW<S, W>) -> Lanes<S, W> {
        o.dot_splat(self.normal) + Lanes::splat(self.d)
    }

    /// The lanes whose points `o` lie on the light's side of the plane, not
    /// on it: the kernel's own signed distance is positive on the side
    /// `up`, negative on the other (for axis planes from one comparison,
    /// see [`PlaneSide::new`]).
    #[inline(always)]
    fn clear<const W: usize>(&self, o: &Vec3xW<S, W>) -> Mask<W> {
        let c = match self.axis {
            0 => o.x,
            1 => o.y,
            2 => o.z,
            _ => {
                let dist = self.distance(o);
                return if self.up { dist.gt(Lanes::zero()) } else { dist.lt(Lanes::zero()) };
            }
        };
        let limit = Lanes::splat(self.limit);
        if self.above {
            c.gt(limit)
        } else {
            c.lt(limit)
        }
    }
}

/// One primitive as seen from one light: shadow rays whose direction `d`
/// (towards the light) lies outside the box `[dlo, dhi]`, or has
/// `d·axis > limit`, cannot reach it. The box is tested first: six
/// comparisons, no product. (Primitives that are always candidates are
/// bits of [`ShadowCull`]'s `always` masks, not entries.)
#[derive(Clone, Copy, Debug)]
struct Occluder<S> {
    dlo: Vec3<S>,
    dhi: Vec3<S>,
    axis: Vec3<S>,
    limit: S,
}

impl<S: Scalar> Occluder<S> {
    /// An unused entry.
    const NONE: Self = Occluder { dlo: Vec3::ZERO, dhi: Vec3::ZERO, axis: Vec3::ZERO, limit: S::MAX };

    /// Whether some lane of `inside` (the lanes whose direction lies in the
    /// box) has its direction in the cone: `d·axis <= limit`. (The lanes
    /// inside the box have direction components within 1 + 2⁻¹²: products
    /// of small factors, exact there; the other lanes' values are not used.)
    #[inline(always)]
    fn cone_holds<const W: usize>(&self, dir: &Vec3xW<S, W>, inside: Mask<W>) -> bool {
        if self.limit == S::MAX {
            return true;
        }
        // Lanes a scalar's estimate of the product settles (the same
        // answers), then the product for the rest.
        let mut rest = inside;
        if S::UNIT_DOT_ESTIMATE {
            let axis = [self.axis.x, self.axis.y, self.axis.z];
            for l in 0..W {
                if inside.get(l) {
                    match S::unit_dot_le([dir.x.0[l], dir.y.0[l], dir.z.0[l]], axis, self.limit) {
                        Some(true) => return true,
                        Some(false) => rest.set(l, false),
                        None => {}
                    }
                }
            }
            if rest.none() {
                return false;
            }
        }
        (rest & dir.dot_splat_small(self.axis).le(Lanes::splat(self.limit))).any()
    }
}

/// A set of entries of one light's occluder row: bit `e` for entry `e`
/// (the row holds at most [`SHADOW_OCCLUDERS`] ≤ 32).
type EntryMask = u32;

const _: () = assert!(SHADOW_OCCLUDERS <= EntryMask::BITS as usize);

/// Lights whose shadow directions have cells (see [`use_cells`]): none on
/// WebAssembly, where `use_cells` leaves them out and filling them anyway
/// (for every scalar the module renders) made the module 13.5 KB larger
/// (197.6 → 211.1 KB), past its 200 KB budget.
const CELL_LIGHTS: usize = if cfg!(target_arch = "wasm32") { 0 } else { SHADOW_LIGHTS };

/// Cells per component of the shadow directions (see [`DirectionCells`]).
const DIRECTION_CELLS: usize = 16;

/// One component of the shadow directions towards one light, cut into
/// [`DIRECTION_CELLS`] cells, with the entries whose direction box meets
/// each cell: the three components' cells of a direction, intersected,
/// hold every entry whose box holds the direction, so a shadow ray tests
/// only those entries' boxes and cones (most rays: one or two of the
/// row's entries).
///
/// A component `v` falls in cell `clamp(⌊(v − origin)·2^shift⌋, 0, N − 1)`
/// ([`bins::bin`]). That is a non-decreasing function of `v` in every
/// scalar, so `lo ≤ v ≤ hi` puts `v`'s cell between those of `lo` and
/// `hi`: an entry marked in every cell from its box's `dlo` component's
/// to its `dhi` component's is marked in the cell of every direction its
/// box holds. The bounds and the directions are placed by the same
/// function on the same numbers, so no margin is needed, and the set of
/// candidates is the one testing every entry gives, bit for bit.
/// `origin` and `shift` only decide how well the cells separate the
/// entries: the window spans the entries' boxes on this axis.
#[derive(Clone, Copy, Debug)]
struct DirectionCells<S> {
    origin: S,
    shift: i32,
    /// `2^shift`, for scalars whose product by a power of two is not a
    /// shift ([`Scalar::SPARSE_PRODUCTS`] false).
    scale: S,
    cells: [EntryMask; DIRECTION_CELLS],
}

impl<S: Scalar> DirectionCells<S> {
    /// No entries.
    const NONE: Self = DirectionCells { origin: S::ZERO, shift: 0, scale: S::ZERO, cells: [0; DIRECTION_CELLS] };

    /// The cells of component `axis` for the entries `row`.
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    fn new(row: &[Occluder<S>], axis: usize) -> Self {
        let mut c = Self::NONE;
        let (mut lo, mut hi) = (f32::MAX, f32::MIN);
        for o in row {
            lo = lo.min(o.dlo.axis(axis).to_f32());
            hi = hi.max(o.dhi.axis(axis).to_f32());
        }
        if !(lo <= hi) {
            return c;
        }
        // The largest power of two (within 2⁻⁴ … 2¹⁶) that brings the
        // window's width to at most N cells.
        let width = (hi - lo).max(1.0 / 65536.0);
        let shift = bins::fit_shift::<-4, 16>(width, DIRECTION_CELLS);
        c.origin = S::from_f32(lo);
        c.shift = shift;
        c.scale = bins::scale_of(shift);
        for (e, o) in row.iter().enumerate() {
            let (first, last) = (c.cell(o.dlo.axis(axis)), c.cell(o.dhi.axis(axis)));
            for cell in c.cells.iter_mut().take(last + 1).skip(first) {
                *cell |= 1 << e;
            }
        }
        c
    }

    /// The cell of the component `v` (see [`DirectionCells`]).
    #[inline(always)]
    fn cell(&self, v: S) -> usize {
        bins::bin(v, self.origin, self.shift, self.scale, DIRECTION_CELLS)
    }

    /// The entries whose direction box may hold a direction with component `v`.
    #[inline(always)]
    fn entries(&self, v: S) -> EntryMask {
        self.cells.get(self.cell(v)).copied().unwrap_or(EntryMask::MAX)
    }
}

/// One primitive for reflected and refracted rays: its bounds' sphere,
/// grown (see [`ShadowCull`]), as its centre, radius and squared radius.
#[derive(Clone, Copy, Debug)]
struct Reach<S> {
    centre: Vec3<S>,
    r: S,
    /// `−r` (a saturating negation in fixed point: once, not per ray).
    neg_r: S,
    r2: S,
}

impl<S: Scalar> Reach<S> {
    /// An unused entry.
    /// (Never tested: its bit is in `reach_always` or past `reach_len`.)
    const NONE: Self = Reach { centre: Vec3::ZERO, r: S::MAX, neg_r: S::ZERO, r2: S::MAX };
}

/// Largest `|C − O|` (each component) of a bounding sphere's centre `C`
/// from a ray's origin `O` for which a scalar of limited range
/// ([`Scalar::LIMITED_RANGE`]) culls: the test's squares then stay below
/// 3·4² = 48, inside Q8.24's range. Rays from further out test everything.
const REACH_RANGE: f32 = 4.0;

/// Per light and primitive, the shadow-ray directions that can reach the
/// primitive, for the shadow rays the tracer casts (see below); with it
/// the tracer tests a shadow packet only against the primitives some of
/// its rays can reach.
///
/// A shadow ray leaves `O = P + off` (the hit point `P` moved off the
/// surface by `|off| <= eps`, [`Scalar::RAY_EPSILON`]`·(1 + max|P|)`) along
/// `d = normalize(L − P)`, for `t` in `(0, |L − P|)`. Any of its points is
/// `X = L − s·d + E` with `s > 0` and `|E| <= eps` plus rounding: it lies
/// within `e` of the ray from the light along `−d`. So a primitive whose
/// bounds, grown by `e` and the margin `m` of [`ScreenCull`], lie in the
/// cone around `axis` (the direction from the light to the centre of the
/// bounds' sphere, radius `R`, distance `D`) of half-angle
/// `asin((R + e + m)/D)`, can be reached only by rays with
/// `−d·axis >= cos` of that angle (less `2⁻¹²` for the rounding of `d` and
/// of the dot product). Likewise `−d = (Y − L)/|Y − L|` for a point `Y` of
/// the grown box, so each component of `−d` lies between the extremes of
/// `(Yᵢ − Lᵢ)/|Y − L|` over the box: with `Yᵢ − Lᵢ ∈ [a, b]` and `|Y − L| ∈
/// [dmin, dmax]` (the box's nearest and farthest points), between `a/dmin`
/// (`a/dmax` if `a >= 0`) and `b/dmin` (`b/dmax` if `b < 0`), widened by
/// `2⁻¹²`; a test of the direction's components against that box needs no
/// product, so it runs first and the cone's dot product only where it
/// passes. A primitive with no bounds, or whose grown sphere holds the
/// light, is always a candidate. `e` is fixed per frame for hit
/// points within twice the scene's extent (`eps <= e_lim`); lanes further
/// out (a far point of a plane) test every primitive.
///
/// Planes have no bounds, but a plane `n·x + d = 0` with the light `L`
/// at `h = n·L + d ≥ H` (or `≤ −H`) is crossed by no shadow ray whose
/// origin's signed distance, as the plane's kernel computes it
/// (`δ = n·O + d`, the same expression), is positive (negative). Along the
/// ray `O + t·d` the plane's exact signed distance `f(t)` is linear, and
/// at `D = |L − P|`, where the ray ends, `f(D) ≥ h − |O − P| − D·|d − u|`
/// (`u` the exact direction to the light, `d` the rounded one), which the
/// margin keeps positive. The kernel reports a crossing only for
/// `δ > 0` with a negative rate `n·d`; then `f(0) = f(D) + |n·d|·D`, the
/// crossing lies beyond the ray's end by at least `f(D)`, and its rounded
/// `t = δ/|n·d|` stays above the rounded `D` (the rounding of `δ`, of the
/// rate times `D`, and of the quotient are far below `f(D)`); with a rate
/// near zero `t` is larger still. `H` is twice the cones' growth (which
/// holds `|O − P|`) plus `64·max(ρ, 2⁻²⁴)·(1 + 6·extent)` for the
/// direction's rounding over the distances to the light, hundreds of times
/// those roundings. A plane whose light lies nearer is always tested, as
/// is every plane for lanes on its other side or on it. At most
/// [`SHADOW_PLANES`] per light.
///
/// Reflected and refracted rays (their origin `O` anywhere, unit direction
/// `d`, `t > 0`) are culled by each bounded primitive's sphere: the sphere
/// around its bounds, grown by `m` and by a 64th of its radius, centre
/// `C`, radius `R`. With `b = (C − O)·d` and `q = |C − O|² − b²` (the
/// squared distance from `C` to the ray's line), no point of the sphere
/// lies on the ray if `q > R²` (the line passes outside) or `b < −R`
/// (the sphere is behind the origin); each test has a slack of
/// `|C − O|²/1024` for the rounding of `d` and of the products. Before
/// them, with comparisons only, a ray whose origin lies more than `R`
/// beyond `C` along an axis and whose direction does not head back along
/// it misses too. Spheres and planes are always tested (their kernel is that test or cheaper),
/// and so are lanes whose origin is far from the centre in a scalar of
/// limited range (more than 4 units along an axis), where the squares would
/// not fit.
#[derive(Clone, Copy, Debug)]
pub struct ShadowCull<S> {
    /// Per light, the entries of the primitives that are not always
    /// tested, packed at the front (`tested` of them) so that a shadow ray
    /// visits only those; `index` holds each entry's primitive.
    occluders: [[Occluder<S>; SHADOW_OCCLUDERS]; SHADOW_LIGHTS],
    index: [[u8; SHADOW_OCCLUDERS]; SHADOW_LIGHTS],
    tested: [u8; SHADOW_LIGHTS],
    /// Per light, the primitives always tested (bit `k`, below `len`).
    always: [Candidates; SHADOW_LIGHTS],
    /// Per light, the planes tested by the side of the ray's origin
    /// (`plane_count` of them; their bits are in `always`).
    planes: [[PlaneSide<S>; SHADOW_PLANES]; SHADOW_LIGHTS],
    plane_count: [u8; SHADOW_LIGHTS],
    /// Per light and axis, which entries' direction boxes meet each cell
    /// of that component of the direction (see [`DirectionCells`]).
    cells: [[DirectionCells<S>; 3]; CELL_LIGHTS],
    lights: usize,
    len: usize,
    /// Largest offset scale of a hit point whose shadow rays may be culled.
    eps_limit: S,
    /// The spheres for reflected and refracted rays, and the primitives
    /// they always test; `reach_len` entries (0: the rays test everything).
    reach: [Reach<S>; SHADOW_OCCLUDERS],
    reach_always: Candidates,
    reach_len: usize,
}

impl<S: Scalar> ShadowCull<S> {
    /// A table that culls nothing (every primitive a candidate).
    pub fn empty() -> Self {
        ShadowCull {
            occluders: [[Occluder::NONE; SHADOW_OCCLUDERS]; SHADOW_LIGHTS],
            index: [[0; SHADOW_OCCLUDERS]; SHADOW_LIGHTS],
            tested: [0; SHADOW_LIGHTS],
            always: [ALL; SHADOW_LIGHTS],
            planes: [[PlaneSide::NONE; SHADOW_PLANES]; SHADOW_LIGHTS],
            plane_count: [0; SHADOW_LIGHTS],
            cells: [[DirectionCells::NONE; 3]; CELL_LIGHTS],
            lights: 0,
            len: 0,
            eps_limit: S::ZERO,
            reach: [Reach::NONE; SHADOW_OCCLUDERS],
            reach_always: ALL,
            reach_len: 0,
        }
    }

    /// The cones of `scene`'s primitives from its lights, written in place
    /// (the table is a few hundred bytes to a kilobyte: no copies on a
    /// small stack); an error, and a table that culls nothing, if the
    /// scene has more than [`CULL_CAPACITY`] primitives.
    pub fn fill(&mut self, scene: &SceneView<'_, S>) -> Result<(), CullError> {
        self.lights = 0;
        self.len = 0;
        self.reach_len = 0;
        self.plane_count = [0; SHADOW_LIGHTS];
        let prims = scene.primitives();
        if prims.len() > CULL_CAPACITY {
            return Err(CullError::Capacity { primitives: prims.len() });
        }
        let pool = scene.vertices();
        // The scene's extent: lights and bounded primitives.
        let mut extent = 0.0f32;
        for l in scene.lights() {
            extent = extent.max(max_abs(l.position.to_f32()));
        }
        for p in prims {
            if let Some((lo, hi)) = bounds_f32(&p.shape, pool) {
                extent = extent.max(max_abs(lo)).max(max_abs(hi));
            }
        }
        let rho = resolution::<S>();
        let eps = S::RAY_EPSILON.to_f32();
        // Hit points with max|P| <= 2·extent: eps <= e_lim.
        let e_lim = eps * (1.0 + 2.0 * extent);
        // Distances within reach: light to hit point.
        let s = 1.0 + 4.0 * extent;
        let m = 4.0 * eps * s + 8.0 * libm::sqrtf(rho * s);
        let grow = 1.01 * e_lim + m;
        if !grow.is_finite() {
            return Ok(());
        }
        let rows = self
            .occluders
            .iter_mut()
            .zip(self.index.iter_mut())
            .zip(self.always.iter_mut().zip(self.tested.iter_mut()));
        for (((row, index), (always, tested)), l) in rows.zip(scene.lights()) {
            let lp = l.position.to_f32();
            *always = 0;
            let mut n = 0;
            for (k, p) in prims.iter().enumerate().take(SHADOW_OCCLUDERS) {
                match bounds_f32(&p.shape, pool).and_then(|(lo, hi)| cone(lp, lo, hi, grow)) {
                    Some(o) => {
                        if let (Some(slot), Some(ix)) = (row.get_mut(n), index.get_mut(n)) {
                            *slot = o;
                            *ix = k as u8;
                        }
                        n += 1;
                    }
                    None => *always |= 1 << k,
                }
            }
            *tested = n as u8;
        }
        // Planes by side: lights at least `h_min` from them (distances
        // from hit points to lights up to `1 + 6·extent`).
        let h_min = 2.0 * grow + 64.0 * rho.max(1.0 / 16_777_216.0) * (1.0 + 6.0 * extent);
        for ((planes, count), l) in self.planes.iter_mut().zip(self.plane_count.iter_mut()).zip(scene.lights()) {
            let lp = l.position.to_f32();
            for (k, p) in prims.iter().enumerate().take(SHADOW_OCCLUDERS) {
                let Shape::Plane(plane) = &p.shape else { continue };
                let (n, d) = (plane.normal_vector(), plane.offset());
                let h = dot(n.to_f32(), lp) + d.to_f32();
                if !(h.abs() >= h_min) {
                    continue;
                }
                let Some(slot) = planes.get_mut(*count as usize) else { break };
                *slot = PlaneSide::new(k as u8, n, d, h > 0.0);
                *count += 1;
            }
        }
        // (No cells on WebAssembly: see `CELL_LIGHTS`.)
        #[cfg(not(target_arch = "wasm32"))]
        for ((cells, row), &n) in self.cells.iter_mut().zip(&self.occluders).zip(&self.tested) {
            let row = row.get(..n as usize).unwrap_or(&[]);
            for (axis, c) in cells.iter_mut().enumerate() {
                *c = DirectionCells::new(row, axis);
            }
        }
        self.lights = scene.lights().len().min(SHADOW_LIGHTS);
        // Reflected and refracted rays: the bounds' spheres, grown by the
        // margin `m` (their origins need no offset term: the test is of
        // the ray as the kernels see it) and by a 64th of the radius. A
        // radius whose square would not fit the scalar is always tested.
        // (In a scalar of limited range, radii whose square the test's
        // range holds, and centres well inside the range.)
        let (r2_max, c_max) =
            if S::LIMITED_RANGE { (3.0 * REACH_RANGE * REACH_RANGE, 64.0) } else { (f32::MAX / 4.0, f32::MAX) };
        self.reach_always = 0;
        for (k, (slot, p)) in self.reach.iter_mut().zip(prims).enumerate() {
            let bounds = match p.shape {
                Shape::Sphere(_) | Shape::Plane(_) => None,
                _ => bounds_f32(&p.shape, pool),
            };
            let sphere = bounds.and_then(|(lo, hi)| {
                let c = [(lo[0] + hi[0]) * 0.5, (lo[1] + hi[1]) * 0.5, (lo[2] + hi[2]) * 0.5];
                let h = [hi[0] - c[0], hi[1] - c[1], hi[2] - c[2]];
                let r = (libm::sqrtf(dot(h, h)) * 1.0001 + m) * (1.0 + 1.0 / 64.0);
                let r2 = r * r;
                (r2 <= r2_max && max_abs(c) <= c_max).then(|| Reach {
                    centre: Vec3::from_f32(c[0], c[1], c[2]),
                    r: S::from_f32(r),
                    neg_r: -S::from_f32(r),
                    r2: S::from_f32(r2),
                })
            });
            match sphere {
                Some(e) => *slot = e,
                None => self.reach_always |= 1 << k,
            }
        }
        self.reach_len = prims.len().min(SHADOW_OCCLUDERS);
        // Primitives past the table stay candidates (`candidates` sets
        // every bit from `len` up).
        self.len = prims.len().min(SHADOW_OCCLUDERS);
        self.eps_limit = S::from_f32(e_lim);
        Ok(())
    }

    /// The primitives the shadow rays towards light `light` with unit
    /// directions `dir`, leaving hit points of offset scale `eps`, in the
    /// lanes `lit`, can reach (planes are always candidates: see
    /// [`ShadowCull::candidates_from`]).
    #[inline(always)]
    pub fn candidates<const W: usize>(
        &self,
        light: usize,
        dir: &Vec3xW<S, W>,
        eps: Lanes<S, W>,
        lit: Mask<W>,
    ) -> Candidates {
        self.candidates_with(light, None, dir, eps, lit)
    }

    /// [`ShadowCull::candidates`] for shadow rays from `origin` (the hit
    /// points moved off their surfaces by at most `eps`) that end at the
    /// light (`t` below the distance from the hit point to it): planes
    /// whose light side the origins clear are left out too.
    #[inline(always)]
    pub fn candidates_from<const W: usize>(
        &self,
        light: usize,
        origin: &Vec3xW<S, W>,
        dir: &Vec3xW<S, W>,
        eps: Lanes<S, W>,
        lit: Mask<W>,
    ) -> Candidates {
        self.candidates_with(light, Some(origin), dir, eps, lit)
    }

    /// [`ShadowCull::candidates`] in line or out of line (see [`apart`]),
    /// always in line on RV32 without hardware floats, where the tracer's
    /// whole shadow query of a single ray is one out-of-line call
    /// (`Tracer::shadow_transmittance_apart`).
    #[inline(always)]
    fn candidates_with<const W: usize>(
        &self,
        light: usize,
        origin: Option<&Vec3xW<S, W>>,
        dir: &Vec3xW<S, W>,
        eps: Lanes<S, W>,
        lit: Mask<W>,
    ) -> Candidates {
        if apart::<S, W>() && !cfg!(rv32_soft_float) {
            self.candidates_apart(light, origin, dir, eps, lit)
        } else {
            self.candidates_here(light, origin, dir, eps, lit, use_cells::<W>())
        }
    }

    /// [`ShadowCull::candidates`] out of line (see [`apart`]).
    #[inline(never)]
    fn candidates_apart<const W: usize>(
        &self,
        light: usize,
        origin: Option<&Vec3xW<S, W>>,
        dir: &Vec3xW<S, W>,
        eps: Lanes<S, W>,
        lit: Mask<W>,
    ) -> Candidates {
        self.candidates_here(light, origin, dir, eps, lit, use_cells::<W>())
    }

    /// [`ShadowCull::candidates`]' work; with `cells_first` from the
    /// direction cells, otherwise from every entry (the same candidates).
    #[inline(always)]
    fn candidates_here<const W: usize>(
        &self,
        light: usize,
        origin: Option<&Vec3xW<S, W>>,
        dir: &Vec3xW<S, W>,
        eps: Lanes<S, W>,
        lit: Mask<W>,
        cells_first: bool,
    ) -> Candidates {
        let Some(row) = self.occluders.get(light).filter(|_| light < self.lights) else { return ALL };
        // A hit point too far out for the frame's margin: everything.
        if lit.and_not(eps.le(Lanes::splat(self.eps_limit))).any() {
            return ALL;
        }
        let always = self.always.get(light).copied().unwrap_or(ALL);
        let mut m = !low_bits(self.len) | always;
        let (Some(index), Some(&n)) = (self.index.get(light), self.tested.get(light)) else { return ALL };
        // Whether entry `o` (primitive `k`) can be reached: the box of
        // directions first (comparisons only, one axis at a time: most
        // occluders are left behind by the first), then the cone for the
        // lanes inside it.
        let reached = |o: &Occluder<S>| {
            let (lo, hi) = (o.dlo, o.dhi);
            let mut inside = lit & dir.x.ge(Lanes::splat(lo.x)) & dir.x.le(Lanes::splat(hi.x));
            if inside.none() {
                return false;
            }
            inside &= dir.y.ge(Lanes::splat(lo.y)) & dir.y.le(Lanes::splat(hi.y));
            if inside.none() {
                return false;
            }
            inside &= dir.z.ge(Lanes::splat(lo.z)) & dir.z.le(Lanes::splat(hi.z));
            if inside.none() {
                return false;
            }
            o.cone_holds(dir, inside)
        };
        // The same for every lane of a packet: at widths 2 to 4 each lane's
        // six box comparisons at once (on the Cortex-M55 one vector compare
        // and five predicated ones, where the axis-by-axis form of `reached`
        // compares lane by lane); at width 8 LLVM made all 48 comparisons of
        // that form scalar, so wider packets, and single rays, keep
        // `reached`.
        let packet_reaches = |o: &Occluder<S>| {
            if W > 1 && W <= 4 {
                let inside = lit & dir.in_box(o.dlo, o.dhi);
                inside.any() && o.cone_holds(dir, inside)
            } else {
                reached(o)
            }
        };
        if let (true, true, Some([cx, cy, cz])) = (cells_first, W > 1, self.cells.get(light)) {
            // A packet: only the entries whose direction box can hold some
            // lit lane's direction, those in the cells of each lane's three
            // components (what each lane alone would test, together).
            // (Apart from the one-ray branch below: one branch for both made
            // the Cortex-M55's `fixed32` frame at width 1 3 % longer.)
            let mut entries: EntryMask = 0;
            for l in 0..W {
                if lit.get(l) {
                    entries |= cx.entries(dir.x.0[l]) & cy.entries(dir.y.0[l]) & cz.entries(dir.z.0[l]);
                }
            }
            for e in SetBits(entries) {
                let (Some(o), Some(&k)) = (row.get(e), index.get(e)) else { break };
                if packet_reaches(o) {
                    m |= 1 << k;
                }
            }
        } else if let (true, Some([cx, cy, cz])) = (cells_first, self.cells.get(light)) {
            // One ray: only the entries whose direction box can hold its
            // direction, from the cells of its three components (a few
            // comparisons and loads, where testing every entry's box took
            // up to six comparisons per entry).
            let entries =
                if lit.get(0) { cx.entries(dir.x.0[0]) & cy.entries(dir.y.0[0]) & cz.entries(dir.z.0[0]) } else { 0 };
            for e in SetBits(entries) {
                let (Some(o), Some(&k)) = (row.get(e), index.get(e)) else { break };
                if reached(o) {
                    m |= 1 << k;
                }
            }
        } else {
            // Without the cells (x86, WebAssembly): every entry.
            for (o, &k) in row.iter().zip(index).take(n as usize) {
                if packet_reaches(o) {
                    m |= 1 << k;
                }
            }
        }
        // Planes the origins clear on the light's side (see above).
        if let (Some(o), Some(planes), Some(&count)) = (origin, self.planes.get(light), self.plane_count.get(light)) {
            for p in planes.iter().take(count as usize) {
                if lit.and_not(p.clear(o)).none() {
                    m &= !(1 << p.k);
                }
            }
        }
        m
    }

    /// The primitives the reflected or refracted rays `ray` (unit
    /// directions, `t > 0`) in the lanes `active` can reach.
    #[inline(always)]
    pub fn reach_candidates<const W: usize>(&self, ray: &RayPacket<S, W>, active: Mask<W>) -> Candidates {
        if apart::<S, W>() {
            self.reach_apart(ray, active)
        } else {
            self.reach_here(ray, active)
        }
    }

    /// [`ShadowCull::reach_candidates`] out of line (see [`apart`]).
    #[inline(never)]
    fn reach_apart<const W: usize>(&self, ray: &RayPacket<S, W>, active: Mask<W>) -> Candidates {
        self.reach_here(ray, active)
    }

    /// [`ShadowCull::reach_candidates`]' work.
    #[inline(always)]
    fn reach_here<const W: usize>(&self, ray: &RayPacket<S, W>, active: Mask<W>) -> Candidates {
        let mut m = !low_bits(self.reach_len) | self.reach_always;
        if self.reach_len == 0 {
            return m;
        }
        let range = Lanes::splat(if S::LIMITED_RANGE { S::from_f32(REACH_RANGE) } else { S::MAX });
        let neg_range = -range;
        let slack = Lanes::splat(S::from_f32(1.0 / 1024.0));
        let zero = Lanes::<S, W>::zero();
        // The products below take unit directions as small factors: a
        // packet with a direction component beyond 4 (not a unit vector,
        // so not the tracer's) tests everything.
        let four = Lanes::splat(S::from_f32(4.0));
        let d = &ray.dir;
        if active.and_not(d.x.abs().le(four) & d.y.abs().le(four) & d.z.abs().le(four)).any() {
            return ALL;
        }
        // The table's entries, all below bit 32 ([`SHADOW_OCCLUDERS`]).
        for k in SetBits(!self.reach_always & low_bits(self.reach_len)) {
            let Some(e) = self.reach.get(k) else { break };
            let oc = e.centre.splat::<W>() - ray.origin;
            // First, comparisons only: lanes whose origin lies more than
            // `R` beyond the centre along an axis and whose direction does
            // not head back along it. (`C − O` is exact in fixed point, and
            // within one rounding of its own magnitude in floating point,
            // far less than `R`'s growth; saturated components keep their
            // sign.)
            let (r, nr) = (Lanes::splat(e.r), Lanes::splat(e.neg_r));
            let away = |c: Lanes<S, W>, dc: Lanes<S, W>| (c.gt(r) & dc.le(zero)) | (c.lt(nr) & dc.ge(zero));
            let active = if one_ray_off_x86::<W>() {
                // One ray (not on x86): axis by axis, each ending the entry
                // early (all six tests at once kept every comparison's
                // result in a register or on the stack: about 80
                // instructions per entry on the Cortex-M0).
                let mut a = active.and_not(away(oc.x, d.x));
                if a.none() {
                    continue;
                }
                a = a.and_not(away(oc.y, d.y));
                if a.none() {
                    continue;
                }
                a.and_not(away(oc.z, d.z))
            } else {
                active.and_not(away(oc.x, d.x) | away(oc.y, d.y) | away(oc.z, d.z))
            };
            if active.none() {
                continue;
            }
            // Lanes too far out for the scalar's range: a candidate, with
            // no products.
            // (In a scalar of limited range `|c| ≤ R` as `−R ≤ c ≤ R`: the
            // same lanes, without the saturating absolute values; a
            // floating-point absolute value is one operation.)
            let within =
                |c: Lanes<S, W>| if S::LIMITED_RANGE { c.le(range) & c.ge(neg_range) } else { c.abs().le(range) };
            let near = within(oc.x) & within(oc.y) & within(oc.z);
            if active.and_not(near).any() {
                m |= 1 << k;
                continue;
            }
            // Every active lane's `C − O` is now within 4 on each axis in a
            // scalar of limited range, and `d` is a unit vector: products
            // of small factors (the other lanes' vectors zeroed; at width 1
            // the one lane is active).
            let oc = if W == 1 { oc } else { Vec3xW::select(active, oc, Vec3::new(zero, zero, zero)) };
            let b = oc.dot_small(ray.dir);
            let oc2 = oc.norm_squared_small();
            let bb = b.square();
            // (The slack as a shift in fixed point, where a product is a
            // routine; a product by the constant in floating point.)
            let r2 = Lanes::splat(e.r2) + if S::SPARSE_PRODUCTS { oc2.mul_pow2([-10; W]) } else { oc2 * slack };
            // Outside the line's reach, or wholly behind the origin.
            let missed = (oc2 - bb).gt(r2) | (b.lt(zero) & bb.gt(r2));
            if active.and_not(missed).any() {
                m |= 1 << k;
            }
        }
        m
    }
}

/// Whether [`ShadowCull`]'s per-packet tests run out of line for scalar
/// `S` at packet width `W`: at width 1 on every target but x86, except
/// fixed point on Armv6-M. Out of line the tracer's stack frame stays
/// smaller and the width-1 frame retires fewer instructions (Cortex-M55:
/// 62.9 M against 64.0 M in `f32`, 129.2 M against 141.6 M in `fixed32`;
/// the Cortex-M0's soft-float `f32` 860.1 M against 862.6 M); wider
/// packets on the Cortex-M55 gain from the tests inline (width 4: 43.6 M
/// against 48.8 M), and so does the Cortex-M0's `fixed32` frame (183.6 M
/// against 184.9 M, the test image's stack 7 328 bytes against 7 256).
/// x86 keeps everything inline.
const fn apart<S: Scalar, const W: usize>() -> bool {
    one_ray_off_x86::<W>() && !(cfg!(armv6m) && S::SPARSE_PRODUCTS)
}

/// A packet of one ray on a target other than x86: where [`ShadowCull`]'s
/// tests take their single-ray forms (out of line, from the direction
/// cells, axis by axis), which x86, with the tests inline in the tracer,
/// measured slower.
const fn one_ray_off_x86<const W: usize>() -> bool {
    W == 1 && !cfg!(any(target_arch = "x86", target_arch = "x86_64"))
}

/// Whether [`ShadowCull`]'s shadow-ray test starts from the direction
/// cells: at every width on every target but x86 (the unit test
/// `direction_cells_leave_the_candidates_as_they_are` compares both ways
/// on the host, at widths 1, 4 and 8). On x86 the tracer's code (the cull
/// inline in it) compiled differently with them and rendered `gears-2` at
/// packet 1 2.4 % slower (`raypack bench`, 8 interleaved rounds), a scene
/// the cull does not even serve (more than 32 primitives).
///
/// A packet looks up its lit lanes' cells, which paid at every width
/// measured when packets came to use them: the Cortex-M55's width 4 took
/// 33 461 281 instructions instead of 34 787 531 and width 8 42 417 375
/// instead of 47 057 875; RVV's width 8 29 303 000 instead of 30 409 100;
/// soft float too, RV32IMAC at width 4 (not a board's setting) 701 748 700
/// instead of 728 051 100 in `f32` and 305 621 800 instead of 320 207 000
/// in `fixed32`.
///
/// Nor on WebAssembly, where there are none ([`CELL_LIGHTS`]).
const fn use_cells<const W: usize>() -> bool {
    !cfg!(any(target_arch = "x86", target_arch = "x86_64")) && CELL_LIGHTS > 0
}

/// The cone and the box of directions from the light `l` reaching the box
/// `[lo, hi]` grown by `grow` (see [`ShadowCull`]), as an occluder entry;
/// `None` if it must always be tested.
fn cone<S: Scalar>(l: [f32; 3], lo: [f32; 3], hi: [f32; 3], grow: f32) -> Option<Occluder<S>> {
    let (dlo, dhi) = direction_box(l, lo, hi, grow)?;
    let c = [(lo[0] + hi[0]) * 0.5, (lo[1] + hi[1]) * 0.5, (lo[2] + hi[2]) * 0.5];
    let h = [hi[0] - c[0], hi[1] - c[1], hi[2] - c[2]];
    // Sphere around the box (grown by one part in 10⁴ for the rounding of
    // this arithmetic) plus the margins.
    let r = libm::sqrtf(dot(h, h)) * 1.0001 + grow;
    let v = [c[0] - l[0], c[1] - l[1], c[2] - l[2]];
    let dist = libm::sqrtf(dot(v, v));
    let (axis, limit) = if dist > r * 1.001 && r.is_finite() && dist.is_finite() {
        let sin = r / dist;
        let cos = libm::sqrtf(1.0 - sin * sin);
        // `−d·axis >= cos − slack` ⇔ `d·axis <= slack − cos`; the axis
        // points from the light to the centre.
        (Vec3::from_f32(v[0] / dist, v[1] / dist, v[2] / dist), S::from_f32(1.0 / 4096.0 - cos))
    } else {
        // The light inside the sphere (beside a long box): the box of
        // directions alone.
        (Vec3::ZERO, S::MAX)
    };
    Some(Occluder {
        dlo: Vec3::from_f32(dlo[0], dlo[1], dlo[2]),
        dhi: Vec3::from_f32(dhi[0], dhi[1], dhi[2]),
        axis,
        limit,
    })
}

/// The box holding every shadow direction `d` (towards the light `l`) of a
/// ray that can reach the box `[lo, hi]` grown by `grow` (see
/// [`ShadowCull`]); `None` if the light lies in the grown box.
fn direction_box(l: [f32; 3], lo: [f32; 3], hi: [f32; 3], grow: f32) -> Option<([f32; 3], [f32; 3])> {
    let mut a = [0.0f32; 3];
    let mut b = [0.0f32; 3];
    let mut near = [0.0f32; 3];
    let mut far = [0.0f32; 3];
    for i in 0..3 {
        // Yᵢ − Lᵢ over the grown box, and its smallest and largest magnitude.
        a[i] = lo[i] - grow - l[i];
        b[i] = hi[i] + grow - l[i];
        near[i] = if a[i] > 0.0 {
            a[i]
        } else if b[i] < 0.0 {
            -b[i]
        } else {
            0.0
        };
        far[i] = a[i].abs().max(b[i].abs());
    }
    // Distances from the light to the box's nearest and farthest points,
    // loosened by one part in 10³ for this arithmetic's rounding.
    let dmin = libm::sqrtf(dot(near, near)) * 0.999;
    let dmax = libm::sqrtf(dot(far, far)) * 1.001;
    if !(dmin > 0.0) || !dmax.is_finite() {
        return None;
    }
    let slack = 1.0 / 4096.0;
    let mut dlo = [0.0f32; 3];
    let mut dhi = [0.0f32; 3];
    for i in 0..3 {
        // −dᵢ = (Yᵢ − Lᵢ)/|Y − L| ∈ [u_lo, u_hi]: d ∈ [−u_hi, −u_lo].
        let u_lo = if a[i] < 0.0 { a[i] / dmin } else { a[i] / dmax };
        let u_hi = if b[i] < 0.0 { b[i] / dmax } else { b[i] / dmin };
        dlo[i] = (-u_hi).max(-1.0) - slack;
        dhi[i] = (-u_lo).min(1.0) + slack;
    }
    if dlo.iter().chain(dhi.iter()).all(|v| v.is_finite()) {
        Some((dlo, dhi))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::fixed32::Fixed32;
    use crate::scene::{Material, Scene};

    /// An axis plane's side from one comparison is the side of the
    /// kernel's signed distance (`o·n + d` compared with zero), for every
    /// axis, sign, side and offset up to [`AXIS_PLANE_OFFSET`], at the
    /// limits and the ends of the range.
    fn axis_plane_sides_are_the_distances_signs<S: Scalar>(c_of: impl Fn(u64) -> S, d_of: impl Fn(u64) -> S, low: S) {
        let mut state = 0x005e_ed0f_51de_u64;
        let one = S::ONE;
        for axis in 0..3 {
            for sign in [one, -one] {
                let n = match axis {
                    0 => Vec3::new(sign, S::ZERO, S::ZERO),
                    1 => Vec3::new(S::ZERO, sign, S::ZERO),
                    _ => Vec3::new(S::ZERO, S::ZERO, sign),
                };
                for up in [true, false] {
                    for i in 0..400 {
                        let d = d_of(crate::num::test_rng::splitmix64(&mut state) ^ i);
                        let p = PlaneSide::new(0, n, d, up);
                        assert_eq!(p.axis as usize, axis, "{d:?}");
                        let mut cs = [d, -d, S::MAX, low, S::ZERO, d, d];
                        cs[5] = c_of(crate::num::test_rng::splitmix64(&mut state));
                        cs[6] = -d + c_of(crate::num::test_rng::splitmix64(&mut state) | 1).mul_pow2(-20);
                        for c in cs {
                            let other = c_of(crate::num::test_rng::splitmix64(&mut state)).mul_pow2(-1);
                            let o = match axis {
                                0 => Vec3::new(c, other, other),
                                1 => Vec3::new(other, c, other),
                                _ => Vec3::new(other, other, c),
                            };
                            let o: Vec3xW<S, 1> = o.splat();
                            let dist = p.distance(&o);
                            let want = if up { dist.gt(Lanes::zero()) } else { dist.lt(Lanes::zero()) };
                            assert_eq!(p.clear(&o).get(0), want.get(0), "axis {axis} {sign:?} up {up} d {d:?} c {c:?}");
                        }
                    }
                }
            }
        }
        // Offsets past the bound take the dot product.
        let far = PlaneSide::new(0, Vec3::new(S::ZERO, one, S::ZERO), S::from_f32(2.0 * AXIS_PLANE_OFFSET), true);
        assert_eq!(far.axis, 3);
    }

    #[test]
    fn axis_plane_sides_are_the_distances_signs_in_fixed_point() {
        // Offsets within the bound, points anywhere in the range (the
        // bottom value included), near `−d` too.
        let bound = (AXIS_PLANE_OFFSET as i64) << 24;
        axis_plane_sides_are_the_distances_signs::<Fixed32>(
            |r| Fixed32::from_bits(r as i32),
            |r| Fixed32::from_bits(((r % (2 * bound as u64 + 1)) as i64 - bound) as i32),
            Fixed32::from_bits(i32::MIN),
        );
    }

    #[test]
    fn axis_plane_sides_are_the_distances_signs_in_floating_point() {
        let f = |r: u64, scale: f32| ((r >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) as f32 * scale;
        axis_plane_sides_are_the_distances_signs::<f32>(|r| f(r, 1.0e6), |r| f(r, AXIS_PLANE_OFFSET), f32::MIN);
    }

    /// The lowest set bit's table and function give `trailing_zeros`.
    #[test]
    fn lowest_bits_are_the_trailing_zeros() {
        assert_eq!(LOWEST_BIT[1], 0);
        assert_eq!(LOWEST_BIT[128], 7);
        for b in 1..256u32 {
            assert_eq!(LOWEST_BIT[b as usize] as u32, b.trailing_zeros(), "{b:#b}");
        }
        let mut x = 0x9E37_79B9u32;
        for _ in 0..10_000 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            for bits in [x, x & 0xFFFF_FF00, x & 0x8000_0000, x | 1] {
                if bits != 0 {
                    assert_eq!(lowest_bit(bits), bits.trailing_zeros() as usize, "{bits:#x}");
                }
            }
        }
    }

    /// The shadow candidates of width-1 rays from the direction cells and
    /// from every entry, for the demo scene's lights and seeded hit points
    /// (inside and beyond the scene), and for directions whose components
    /// are exactly the entries' box bounds (the cells' edges).
    fn cells_agree<S: Scalar>(name: &str) {
        // (In its own frame for Q8.24, as the firmware builds it.)
        let mut scene = crate::scene::demo::DemoScene::<S>::new();
        let mut described = crate::scene::demo::DemoScene::<f32>::new();
        crate::scene::demo::build_demo_scene_for(&mut scene, &mut described).unwrap();
        let view = scene.view();
        let mut cull = ShadowCull::<S>::empty();
        cull.fill(&view).unwrap();
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 40) as f32 / (1u64 << 24) as f32
        };
        let eps = Lanes::<S, 1>::splat(S::from_f32(1e-4));
        let lit = Mask::<1>::splat(true);
        let mut culled = 0;
        // Hit points around the segment between the two lights, reaching
        // past the scene.
        let (a, b) = (view.lights()[0].position.to_f32(), view.lights()[1].position.to_f32());
        let span = (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0f32, f32::max);
        for (li, l) in view.lights().iter().enumerate() {
            let lp = l.position.to_f32();
            let mut dirs = std::vec::Vec::new();
            for _ in 0..4000 {
                let t = next();
                let p: [f32; 3] = core::array::from_fn(|i| a[i] + (b[i] - a[i]) * t + (next() - 0.5) * 1.5 * span);
                let d = Vec3::from_f32(lp[0] - p[0], lp[1] - p[1], lp[2] - p[2]);
                dirs.push(d.splat::<1>().normalize().0);
            }
            let row = &cull.occluders[li][..cull.tested[li] as usize];
            for o in row {
                for axis in 0..3 {
                    for bound in [o.dlo.axis(axis), o.dhi.axis(axis)] {
                        let mut d = dirs[dirs.len() % 97];
                        match axis {
                            0 => d.x = Lanes::splat(bound),
                            1 => d.y = Lanes::splat(bound),
                            _ => d.z = Lanes::splat(bound),
                        }
                        dirs.push(d);
                    }
                }
            }
            for d in &dirs {
                let with = cull.candidates_here(li, None, d, eps, lit, true);
                let without = cull.candidates_here(li, None, d, eps, lit, false);
                assert_eq!(with, without, "{name}: light {li}, direction {:?}", d.lane(0));
                culled += (with & low_bits(view.primitives().len())).count_zeros();
            }
            // Packets of those directions, with seeded lit lanes (none to all).
            packets_agree::<S, 4>(name, &cull, li, &dirs, &mut next);
            packets_agree::<S, 8>(name, &cull, li, &dirs, &mut next);
        }
        // The table culls something (the comparison is not between two
        // empty tables).
        assert!(culled > 1000, "{name}: {culled}");
    }

    /// [`cells_agree`] for packets of `W` lanes: each lane a direction of
    /// `dirs` picked by the seeded `next`, lit with probability 0.7.
    fn packets_agree<S: Scalar, const W: usize>(
        name: &str,
        cull: &ShadowCull<S>,
        light: usize,
        dirs: &[Vec3xW<S, 1>],
        next: &mut impl FnMut() -> f32,
    ) {
        let eps = Lanes::<S, W>::splat(S::from_f32(1e-4));
        let mut tested = 0;
        for _ in 0..dirs.len() {
            let mut d = Vec3::new(Lanes::zero(), Lanes::zero(), Lanes::zero());
            let mut lit = [false; W];
            for (l, lit) in lit.iter_mut().enumerate() {
                let i = ((next() * dirs.len() as f32) as usize).min(dirs.len() - 1);
                d.set_lane(l, dirs[i].lane(0));
                *lit = next() < 0.7;
            }
            let lit = Mask::from_array(lit);
            let with = cull.candidates_here(light, None, &d, eps, lit, true);
            let without = cull.candidates_here(light, None, &d, eps, lit, false);
            assert_eq!(with, without, "{name}: light {light}, {W} lanes {lit:?}: {d:?}");
            tested += usize::from(with != ALL);
        }
        assert!(tested > dirs.len() / 2, "{name}: {tested}");
    }

    #[test]
    fn direction_cells_leave_the_candidates_as_they_are() {
        cells_agree::<f32>("f32");
        cells_agree::<Fixed32>("fixed32");
        cells_agree::<crate::num::fixed64::Fixed>("fixed");
    }

    #[test]
    fn candidate_indices_are_the_set_bits_then_every_index_from_32() {
        // Against the plain loop over every index, on seeded masks and
        // lengths around 32.
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for len in [0usize, 1, 2, 5, 11, 31, 32, 33, 40] {
            for _ in 0..200 {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                let c = (x >> 16) as u32;
                let want: std::vec::Vec<usize> =
                    (0..len).filter(|&k| c.checked_shr(k as u32).is_none_or(|b| b & 1 == 1)).collect();
                let got: std::vec::Vec<usize> = candidate_indices(c, len).collect();
                assert_eq!(got, want, "{c:#x} of {len}");
            }
        }
        assert_eq!(candidate_indices(ALL, 3).collect::<std::vec::Vec<_>>(), [0, 1, 2]);
        assert_eq!(candidate_indices(0, 34).collect::<std::vec::Vec<_>>(), [32, 33]);
    }

    type Small = Scene<f32, 8, 8, 2, 2>;

    fn camera() -> Camera<f32> {
        let up = Vec3::new(0.0, 1.0, 0.0);
        Camera::new(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0), up, 90.0, 40, 40).unwrap()
    }

    /// A row's packets find the candidates `candidates` gives, and keep them
    /// up to the column `columns_from` says: seeded rectangles (empty ones
    /// and ones at the image's edge among them), rows' candidate sets and
    /// packet widths 1 to 4.
    #[test]
    fn packets_of_a_row_keep_their_candidates_up_to_where_they_change() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut next = |n: u32| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 33) as u32 % n
        };
        let mut changes = 0;
        for case in 0..200 {
            let len = 1 + next(32) as usize;
            let mut cull = ScreenCull { rects: [PixelRect::EMPTY; CULL_CAPACITY], len, full: PixelRect::EMPTY };
            for r in cull.rects.iter_mut().take(len) {
                *r = match next(6) {
                    0 => PixelRect::EMPTY,
                    _ => {
                        let (x0, y0) = (next(40) as u16, next(8) as u16);
                        PixelRect { x0, x1: x0 + next(12) as u16, y0, y1: y0 + next(4) as u16 }
                    }
                };
            }
            let within = if case % 3 == 0 { ALL } else { (next(u32::MAX) << 1) ^ next(u32::MAX) };
            for w in 1..=4 {
                for y in 0..9 {
                    let rows = cull.candidates(within, 0, u32::MAX, y, y + 1);
                    for x0 in 0..60 {
                        let (m, until) = cull.columns_from(rows, x0, w);
                        assert_eq!(m, cull.candidates(within, x0, x0 + w - 1, y, y + 1), "case {case}: {x0}, {w}");
                        assert!(until >= x0);
                        for x in x0..=until.min(70) {
                            assert_eq!(
                                cull.candidates(within, x, x + w - 1, y, y + 1),
                                m,
                                "case {case}: {x} ≤ {until}"
                            );
                        }
                        if until < 70 && cull.candidates(within, until + 1, until + w, y, y + 1) != m {
                            changes += 1;
                        }
                    }
                }
            }
        }
        // The sets do change along rows (the spans are not all the whole row).
        assert!(changes > 10_000, "{changes}");
    }

    #[test]
    fn a_small_sphere_ahead_gets_a_small_rectangle_and_a_plane_the_image() {
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        s.add_sphere(Vec3::new(0.0, 0.0, -10.0), 0.5, m).unwrap();
        s.add_plane(0.0, 1.0, 0.0, 1.0, m).unwrap();
        let c = ScreenCull::new(&s.view(), &camera()).unwrap();
        assert_eq!(c.bounded(), 1);
        // The sphere spans about ±1 pixel around the centre (tan = 0.05 of
        // a half-width of 20 pixels), plus the margins.
        assert!(c.covers(0, 20, 20) && c.covers(0, 19, 19));
        assert!(!c.covers(0, 25, 20) && !c.covers(0, 20, 14) && !c.covers(0, 0, 0));
        assert!(c.covers(1, 0, 0) && c.covers(1, 39, 39));
        assert_eq!(c.candidates(ALL, 0, 3, 0, 3) & 3, 0b10);
        assert_eq!(c.candidates(ALL, 18, 21, 18, 21) & 3, 0b11);
        assert_eq!(c.rows(0, 5) & 3, 0b10);
    }

    #[test]
    fn bounds_around_or_behind_the_eye_get_the_whole_image() {
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        s.add_box(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(1.0, 1.0, 1.0), m).unwrap();
        s.add_sphere(Vec3::new(0.0, 0.0, 3.0), 1.0, m).unwrap();
        let c = ScreenCull::new(&s.view(), &camera()).unwrap();
        assert!(c.covers(0, 0, 0) && c.covers(0, 39, 39));
        // Wholly behind the eye: no camera ray reaches it, but the
        // projection is only used for boxes in front, so it stays in
        // (conservative; a possible refinement).
        assert!(c.covers(1, 20, 20) && c.covers(1, 0, 0));
    }

    #[test]
    fn shadow_rays_reach_only_what_lies_towards_the_light() {
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        s.add_sphere(Vec3::new(0.0, 5.0, 0.0), 1.0, m).unwrap();
        s.add_light(Vec3::new(0.0, 10.0, 0.0), Vec3::new(1.0, 1.0, 1.0)).unwrap();
        let mut c = ShadowCull::<f32>::empty();
        c.fill(&s.view()).unwrap();
        let dir = |x: f32, y: f32, z: f32| Vec3::new(Lanes([x]), Lanes([y]), Lanes([z]));
        let eps = Lanes([1.0e-4]);
        let lit = Mask::splat(true);
        // From below, straight up to the light: through the sphere.
        assert_eq!(c.candidates(0, &dir(0.0, 1.0, 0.0), eps, lit) & 1, 1);
        // From the side, horizontally: nowhere near it.
        assert_eq!(c.candidates(0, &dir(1.0, 0.0, 0.0), eps, lit) & 1, 0);
        // A hit point too far out for the margin: everything.
        assert_eq!(c.candidates(0, &dir(1.0, 0.0, 0.0), Lanes([1.0]), lit), ALL);
        // No table: everything.
        assert_eq!(ShadowCull::<f32>::empty().candidates(0, &dir(1.0, 0.0, 0.0), eps, lit), ALL);
    }

    #[test]
    fn the_box_of_directions_cuts_what_a_long_occluders_cone_lets_through() {
        // A wall-like box 20 long in x, 0.2 thick, in the plane z ∈ [4.9, 5.1]
        // below a light at height 10: its bounding sphere's cone from the
        // light is wide in every direction, its directions' box is not.
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        s.add_box(Vec3::new(-10.0, -0.1, 4.9), Vec3::new(10.0, 0.1, 5.1), m).unwrap();
        s.add_light(Vec3::new(0.0, 0.0, 10.0), Vec3::new(1.0, 1.0, 1.0)).unwrap();
        let mut c = ShadowCull::<f32>::empty();
        c.fill(&s.view()).unwrap();
        let o = c.occluders[0][0];
        let unit = |x: f32, y: f32, z: f32| {
            let n = (x * x + y * y + z * z).sqrt();
            Vec3::new(Lanes([x / n]), Lanes([y / n]), Lanes([z / n]))
        };
        let (eps, lit) = (Lanes([1.0e-4]), Mask::splat(true));
        // Straight up through the wall, and slanted along it: candidates.
        assert_eq!(c.candidates(0, &unit(0.0, 0.0, 1.0), eps, lit) & 1, 1);
        assert_eq!(c.candidates(0, &unit(1.0, 0.0, 1.0), eps, lit) & 1, 1);
        // Slanted across it (y), inside the cone but outside the box: not.
        let d = unit(0.0, 0.5, 1.0);
        assert!(d.dot_splat(o.axis).le(Lanes::splat(o.limit)).all(), "the cone alone keeps it");
        assert_eq!(c.candidates(0, &d, eps, lit) & 1, 0);
    }

    #[test]
    fn reach_culls_boxes_a_ray_passes_or_leaves_behind() {
        fn one<S: Scalar>() {
            let f = S::from_f32;
            let v = |x: f32, y: f32, z: f32| Vec3::new(f(x), f(y), f(z));
            let mut s = Scene::<S, 8, 8, 2, 2>::new();
            let m = s.add_material(Material::diffuse(v(1.0, 1.0, 1.0))).unwrap();
            s.add_box(v(0.5, -0.25, -0.25), v(1.0, 0.25, 0.25), m).unwrap(); // 0
            s.add_sphere(v(-1.0, 1.0, 0.0), f(0.25), m).unwrap(); // 1: always
            s.add_plane(f(0.0), f(0.0), f(1.0), f(1.5), m).unwrap(); // 2: always
            let mut c = ShadowCull::<S>::empty();
            c.fill(&s.view()).unwrap();
            let ray = |o: Vec3<S>, d: Vec3<S>| RayPacket::<S, 1>::new(o.splat(), d.splat());
            let at = |o: Vec3<S>, d: Vec3<S>| {
                let (r, ok) = ray(o, d);
                c.reach_candidates(&r, ok) & 0b111
            };
            // Towards the box, away from it, and past it.
            assert_eq!(at(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)), 0b111);
            assert_eq!(at(v(0.0, 0.0, 0.0), v(-1.0, 0.0, 0.0)), 0b110);
            assert_eq!(at(v(0.0, 0.0, 0.0), v(0.0, 1.0, 0.0)), 0b110);
            // From inside it, any way.
            assert_eq!(at(v(0.75, 0.0, 0.0), v(-1.0, 0.0, 0.0)), 0b111);
            // No active lane: only the primitives always tested.
            let (r, _) = ray(v(0.0, 0.0, 0.0), v(0.0, 1.0, 0.0));
            assert_eq!(c.reach_candidates(&r, Mask::splat(false)) & 0b111, 0b110);
            // A direction that is not a unit vector (a component beyond 4,
            // where the products of small factors do not hold): everything,
            // even heading away from the box.
            let far = RayPacket::<S, 1> { origin: v(0.0, 0.0, 0.0).splat(), dir: v(-5.0, 0.0, 0.0).splat() };
            assert_eq!(c.reach_candidates(&far, Mask::splat(true)), ALL);
        }
        one::<f32>();
        one::<Fixed32>();
    }

    #[test]
    fn reach_tests_everything_from_far_origins_in_fixed_point() {
        // A Q8.24 origin 100 units out: the squares would saturate, so a
        // ray heading past the box stays a candidate; comparisons alone
        // still cull one that leaves the box behind.
        let f = Fixed32::from_f32;
        let v = |x: f32, y: f32, z: f32| Vec3::new(f(x), f(y), f(z));
        let mut s = Scene::<Fixed32, 8, 8, 2, 2>::new();
        let m = s.add_material(Material::diffuse(v(1.0, 1.0, 1.0))).unwrap();
        s.add_box(v(0.5, -0.25, -0.25), v(1.0, 0.25, 0.25), m).unwrap();
        let mut c = ShadowCull::<Fixed32>::empty();
        c.fill(&s.view()).unwrap();
        let at = |o: Vec3<Fixed32>, d: Vec3<Fixed32>| {
            let (r, ok) = RayPacket::<Fixed32, 1>::new(o.splat(), d.splat());
            c.reach_candidates(&r, ok) & 1
        };
        // Towards the box, passing 0.99 above it: a miss, but untested.
        assert_eq!(at(v(100.0, 0.0, 0.0), v(-1.0, 0.01, 0.0)), 1);
        // Away from it: culled by comparisons.
        assert_eq!(at(v(100.0, 0.0, 0.0), v(1.0, 0.0, 0.0)), 0);
        // Near, passing above it: culled by the full test.
        assert_eq!(at(v(3.0, 0.0, 0.0), v(-1.0, 0.5, 0.0)), 0);
    }

    #[test]
    fn primitives_past_the_shadow_table_stay_candidates() {
        let mut s = Scene::<f32, 32, 8, 2, 2>::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        for k in 0..SHADOW_OCCLUDERS + 2 {
            s.add_sphere(Vec3::new(k as f32 * 3.0, 5.0, 0.0), 1.0, m).unwrap();
        }
        s.add_light(Vec3::new(0.0, 10.0, 0.0), Vec3::new(1.0, 1.0, 1.0)).unwrap();
        let mut c = ShadowCull::<f32>::empty();
        c.fill(&s.view()).unwrap();
        // Straight down, away from every sphere: only the ones past the table.
        let dir = Vec3::new(Lanes([0.0]), Lanes([-1.0]), Lanes([0.0]));
        let got = c.candidates(0, &dir, Lanes([1.0e-4]), Mask::splat(true));
        assert_eq!(got & low_bits(SHADOW_OCCLUDERS + 2), 0b11 << SHADOW_OCCLUDERS);
    }

    #[test]
    fn the_box_of_directions_holds_every_direction_to_the_box() {
        // Directions from points of the box towards lights around it are
        // inside the box of directions (seeded samples).
        let mut seed = 0x5eed_u32;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            (seed % 20_001) as f32 / 10_000.0 - 1.0
        };
        for _ in 0..200 {
            let l = [next() * 8.0, next() * 8.0, next() * 8.0];
            let c = [next() * 3.0, next() * 3.0, next() * 3.0];
            let h = [next().abs() + 0.01, next().abs() * 2.0 + 0.01, next().abs() * 0.5 + 0.01];
            let lo = [c[0] - h[0], c[1] - h[1], c[2] - h[2]];
            let hi = [c[0] + h[0], c[1] + h[1], c[2] + h[2]];
            let Some((dlo, dhi)) = direction_box(l, lo, hi, 0.0) else { continue };
            for _ in 0..50 {
                let y = [0, 1, 2].map(|i| c[i] + h[i] * next());
                let v = [l[0] - y[0], l[1] - y[1], l[2] - y[2]];
                let n = dot(v, v).sqrt();
                for i in 0..3 {
                    let d = v[i] / n;
                    assert!(d >= dlo[i] && d <= dhi[i], "{d} outside [{}, {}]", dlo[i], dhi[i]);
                }
            }
        }
    }
}
