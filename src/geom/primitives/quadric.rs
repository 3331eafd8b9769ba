//! General quadric `Ax² + By² + Cz² + Dxy + Exz + Fyz + Gx + Hy + Iz + J = 0`,
//! the named quadrics built on it, and an optional clip box.

use super::error::GeometryError;
use crate::geom::ray::{RayPacket, Roots};
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::{Vec3, Vec3xW};
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;

/// A quadric surface, optionally clipped to an axis-aligned box: only the part
/// inside the box exists, and a ray passes through the clipped-away part to
/// the next root.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quadric<S> {
    /// Coefficients `[A, B, C, D, E, F, G, H, I, J]`.
    k: [S; 10],
    clip: Option<(Vec3<S>, Vec3<S>)>,
}

crate::num::bake::bake_struct!("raypack::geom::primitives::Quadric", Quadric<S> { k: [S; 10], clip: Option<(Vec3<S>, Vec3<S>)> });

/// Symmetric 4×4 matrix form of a quadric: `Q(x) = xᵀ M x` with `x = (x, y, z, 1)`.
type Mat4<S> = [[S; 4]; 4];

impl<S: Scalar> Quadric<S> {
    /// The quadric with coefficients `[A, B, C, D, E, F, G, H, I, J]`.
    /// Errors: a non-finite coefficient, or all of `A..I` zero (no surface).
    pub fn new(k: [S; 10]) -> Result<Self, GeometryError> {
        if k.iter().any(|c| !c.is_finite()) {
            return Err(GeometryError::NonFinite);
        }
        if k[..9].iter().all(|&c| c == S::ZERO) {
            return Err(GeometryError::DegenerateQuadric);
        }
        Ok(Quadric { k, clip: None })
    }

    /// The same quadric, keeping only its part inside the box between the
    /// corners `a` and `b` (in any order).
    pub fn with_clip(mut self, a: Vec3<S>, b: Vec3<S>) -> Result<Self, GeometryError> {
        if !a.is_finite() || !b.is_finite() {
            return Err(GeometryError::NonFinite);
        }
        self.clip = Some((a.min_elem(b), a.max_elem(b)));
        Ok(self)
    }

    /// The same quadric in the frame of `sim`, with scalar `T`, computed in
    /// `f32`. With `x = x'/s + o`, `Q(x) = 0` is multiplied through by `s²`
    /// (and then by `1/max(|A|..|F|)`)
    /// (same surface; the tracer normalizes gradients and roots do not
    /// depend on a common factor): the quadratic coefficients stay, the
    /// linear ones become `s·(∇Q(o)/2 · 2)` per axis (`G' = s(2A·oₓ + D·o_y +
    /// E·o_z + G)`, and so on), and `J' = s²·Q(o)`.
    pub fn similar<T: Scalar>(&self, sim: &Similarity) -> Quadric<T> {
        let [a, b, c, d, e, f, g, h, i, j] = self.k.map(|v| v.to_f32());
        let [x, y, z] = sim.origin;
        let s = sim.scale;
        let gx = 2.0 * a * x + d * y + e * z + g;
        let gy = 2.0 * b * y + d * x + f * z + h;
        let gz = 2.0 * c * z + e * x + f * y + i;
        let q = a * x * x + b * y * y + c * z * z + d * x * y + e * x * z + f * y * z + g * x + h * y + i * z + j;
        // The surface does not change when every coefficient is divided by
        // the same number: the largest of `A..F` becomes 1, so a
        // limited-range scalar's intermediates stay small.
        let m = [a, b, c, d, e, f].iter().fold(0.0f32, |m, v| m.max(v.abs()));
        let norm = if m > 0.0 && m.is_finite() { 1.0 / m } else { 1.0 };
        let k = [a, b, c, d, e, f, gx * s, gy * s, gz * s, q * s * s].map(|v| T::from_f32(v * norm));
        Quadric { k, clip: self.clip.map(|(lo, hi)| (sim.point(lo), sim.point(hi))) }
    }

    /// The coefficients `[A, B, C, D, E, F, G, H, I, J]`.
    pub fn coefficients(&self) -> [S; 10] {
        self.k
    }
    /// The clip box, if any.
    pub fn clip_box(&self) -> Option<(Vec3<S>, Vec3<S>)> {
        self.clip
    }

    /// An axis-aligned box holding every point of the surface a ray can
    /// report: the clip box, narrowed to the ellipsoid's box when the
    /// quadric is a well-conditioned ellipsoid ([`Quadric::ellipsoid_box`]);
    /// `None` (unbounded) otherwise.
    pub fn bounds(&self) -> Option<(Vec3<S>, Vec3<S>)> {
        match (self.clip, self.ellipsoid_box()) {
            (Some((lo, hi)), Some((elo, ehi))) => {
                let (lo2, hi2) = (lo.max_elem(elo), hi.min_elem(ehi));
                // Disjoint boxes: nothing can be hit; the clip box is still a
                // valid (if loose) answer.
                if lo2.x <= hi2.x && lo2.y <= hi2.y && lo2.z <= hi2.z {
                    Some((lo2, hi2))
                } else {
                    Some((lo, hi))
                }
            }
            (clip, ext) => clip.or(ext),
        }
    }

    /// The box around the surface when it is an ellipsoid, grown by a
    /// sixteenth of each half-extent; `None` for every other quadric, and
    /// for ellipsoids too flat for the estimate to be safe.
    ///
    /// With `A` the symmetric matrix of the quadratic part and `b = (G, H,
    /// I)`, the quadric is `xᵀAx + bᵀx + J`. When `A` is positive definite
    /// (Sylvester: `a > 0`, the leading 2×2 minor and `det A` positive; a
    /// negative definite `A` is turned round by negating every
    /// coefficient), its centre is `c = −½A⁻¹b` and the surface is
    /// `(x − c)ᵀA(x − c) = ρ` with `ρ = −(J + ½bᵀc)`; the extent along axis
    /// `i` is `√(ρ·(A⁻¹)ᵢᵢ)`. `A⁻¹` is the cofactor matrix over `det A`.
    ///
    /// Computed in `f32` from the coefficients the kernel uses, once per
    /// frame (culling, BVH builds). The condition number of `A` is bounded
    /// by `tr(A)³/det A` (`λmax ≤ tr A`, `λmin ≥ det A/λmax²`); requiring
    /// that to be at most 1000 keeps the `f32` rounding of the inverse (and
    /// of the coefficients themselves) far below the one-sixteenth margin,
    /// and the ellipsoid close enough to round that the root rounding the
    /// culling margins cover for spheres (see `query::cull`) covers it too.
    /// Boxes outside a limited-range scalar's coordinates are refused.
    pub fn ellipsoid_box(&self) -> Option<(Vec3<S>, Vec3<S>)> {
        let k = self.k.map(|v| v.to_f32());
        let sign = if k[0] < 0.0 { -1.0 } else { 1.0 };
        let [a, b, c, d, e, f, g, h, i, j] = k.map(|v| v * sign);
        let (d, e, f) = (d * 0.5, e * 0.5, f * 0.5);
        // Cofactors of the symmetric A = [[a, d, e], [d, b, f], [e, f, c]].
        let c11 = b * c - f * f;
        let c22 = a * c - e * e;
        let c33 = a * b - d * d;
        let c12 = e * f - d * c;
        let c13 = d * f - b * e;
        let c23 = d * e - a * f;
        let det = a * c11 + d * c12 + e * c13;
        let trace = a + b + c;
        if !(a > 0.0 && c33 > 0.0 && det > 0.0 && trace * trace * trace <= 1000.0 * det) {
            return None;
        }
        // c = −½A⁻¹b, from the cofactors.
        let s = -0.5 / det;
        let cx = s * (c11 * g + c12 * h + c13 * i);
        let cy = s * (c12 * g + c22 * h + c23 * i);
        let cz = s * (c13 * g + c23 * h + c33 * i);
        let rho = -(j + 0.5 * (g * cx + h * cy + i * cz));
        if !(rho > 0.0) {
            return None;
        }
        let half = |cof: f32| libm::sqrtf(rho * cof / det) * (1.0 + 1.0 / 16.0);
        let (hx, hy, hz) = (half(c11), half(c22), half(c33));
        let lo = [cx - hx, cy - hy, cz - hz];
        let hi = [cx + hx, cy + hy, cz + hz];
        let limit = if S::LIMITED_RANGE { S::COORDINATE_LIMIT } else { f32::MAX };
        if lo.iter().chain(hi.iter()).any(|v| !v.is_finite() || v.abs() > limit) {
            return None;
        }
        Some((Vec3::from_f32(lo[0], lo[1], lo[2]), Vec3::from_f32(hi[0], hi[1], hi[2])))
    }

    /// A quadric given in a local frame (origin `center`, orthonormal axes
    /// `u, v, w` as local x, y, z), with local coefficients `local`, expressed
    /// in world coordinates: `M_world = Tᵀ M_local T` where `T` maps world to
    /// local points.
    fn from_local(local: [S; 10], center: Vec3<S>, u: Vec3<S>, v: Vec3<S>, w: Vec3<S>) -> Result<Self, GeometryError> {
        let m = to_matrix(local);
        // T = [[Rᵀ, −Rᵀc], [0, 1]]: rows are u, v, w (and the homogeneous row).
        let t: Mat4<S> = [
            [u.x, u.y, u.z, -u.dot(center)],
            [v.x, v.y, v.z, -v.dot(center)],
            [w.x, w.y, w.z, -w.dot(center)],
            [S::ZERO, S::ZERO, S::ZERO, S::ONE],
        ];
        // Compute M T, then Tᵀ (M T).
        let mut mt = [[S::ZERO; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                let mut s = S::ZERO;
                for k in 0..4 {
                    s = s + m[i][k] * t[k][j];
                }
                mt[i][j] = s;
            }
        }
        let mut out = [[S::ZERO; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                let mut s = S::ZERO;
                for k in 0..4 {
                    s = s + t[k][i] * mt[k][j];
                }
                out[i][j] = s;
            }
        }
        Self::new(from_matrix(out))
    }

    /// A frame whose local z is `axis` (normalized), around `center`: the
    /// local x, y and z axes.
    fn frame(center: Vec3<S>, axis: Vec3<S>) -> Result<[Vec3<S>; 3], GeometryError> {
        if !center.is_finite() || !axis.is_finite() {
            return Err(GeometryError::NonFinite);
        }
        let w = axis.normalize_or_zero();
        if w == Vec3::ZERO {
            return Err(GeometryError::ZeroLengthAxis);
        }
        let (u, v) = w.orthonormal_basis();
        Ok([u, v, w])
    }

    fn positive(values: &[S]) -> Result<(), GeometryError> {
        if values.iter().any(|v| !v.is_finite()) {
            return Err(GeometryError::NonFinite);
        }
        if values.iter().any(|&v| !(v > S::ZERO)) {
            return Err(GeometryError::NonPositiveRadius);
        }
        Ok(())
    }

    /// Ellipsoid with semi-axes `radii` along the world axes.
    pub fn ellipsoid(center: Vec3<S>, radii: Vec3<S>) -> Result<Self, GeometryError> {
        Self::positive(&[radii.x, radii.y, radii.z])?;
        let x = Vec3::new(S::ONE, S::ZERO, S::ZERO);
        let y = Vec3::new(S::ZERO, S::ONE, S::ZERO);
        let z = Vec3::new(S::ZERO, S::ZERO, S::ONE);
        Self::ellipsoid_oriented(center, radii, x, y, z)
    }

    /// Ellipsoid with semi-axes `radii` along the orthonormal axes `u, v, w`.
    pub fn ellipsoid_oriented(
        center: Vec3<S>,
        radii: Vec3<S>,
        u: Vec3<S>,
        v: Vec3<S>,
        w: Vec3<S>,
    ) -> Result<Self, GeometryError> {
        Self::positive(&[radii.x, radii.y, radii.z])?;
        if !center.is_finite() {
            return Err(GeometryError::NonFinite);
        }
        let inv2 = |r: S| S::ONE / (r * r);
        let z = S::ZERO;
        Self::from_local([inv2(radii.x), inv2(radii.y), inv2(radii.z), z, z, z, z, z, z, -S::ONE], center, u, v, w)
    }

    /// Infinite circular cylinder of `radius` around the line through `point`
    /// along `axis`.
    pub fn cylinder(point: Vec3<S>, axis: Vec3<S>, radius: S) -> Result<Self, GeometryError> {
        Self::positive(&[radius])?;
        let [u, v, w] = Self::frame(point, axis)?;
        let z = S::ZERO;
        Self::from_local([S::ONE, S::ONE, z, z, z, z, z, z, z, -(radius * radius)], point, u, v, w)
    }

    /// Infinite double cone with apex `apex`, axis `axis` and half-angle
    /// `half_angle` (radians, in `(0, π/2)`): `x² + y² = tan²θ · z²` locally.
    pub fn cone(apex: Vec3<S>, axis: Vec3<S>, half_angle: f32) -> Result<Self, GeometryError> {
        if !half_angle.is_finite() {
            return Err(GeometryError::NonFinite);
        }
        if !(half_angle > 0.0 && half_angle < core::f32::consts::FRAC_PI_2) {
            return Err(GeometryError::NonPositiveRadius);
        }
        let t = S::from_f32(libm::tanf(half_angle));
        let [u, v, w] = Self::frame(apex, axis)?;
        let z = S::ZERO;
        Self::from_local([S::ONE, S::ONE, -(t * t), z, z, z, z, z, z, z], apex, u, v, w)
    }

    /// Circular paraboloid with vertex `vertex`, opening along `axis`, with
    /// focal length `focal`: `x² + y² = 4f·z` locally.
    pub fn paraboloid(vertex: Vec3<S>, axis: Vec3<S>, focal: S) -> Result<Self, GeometryError> {
        Self::positive(&[focal])?;
        let [u, v, w] = Self::frame(vertex, axis)?;
        let z = S::ZERO;
        let four = S::TWO + S::TWO;
        Self::from_local([S::ONE, S::ONE, z, z, z, z, z, z, -(four * focal), z], vertex, u, v, w)
    }

    /// Hyperboloid of one sheet around `axis`: `(x² + y²)/a² − z²/c² = 1`
    /// locally (waist radius `a`).
    pub fn hyperboloid_one_sheet(center: Vec3<S>, axis: Vec3<S>, a: S, c: S) -> Result<Self, GeometryError> {
        Self::positive(&[a, c])?;
        let [u, v, w] = Self::frame(center, axis)?;
        let z = S::ZERO;
        let ia = S::ONE / (a * a);
        let ic = S::ONE / (c * c);
        Self::from_local([ia, ia, -ic, z, z, z, z, z, z, -S::ONE], center, u, v, w)
    }

    /// Hyperboloid of two sheets along `axis`: `z²/c² − (x² + y²)/a² = 1`
    /// locally (vertices at `z = ±c`).
    pub fn hyperboloid_two_sheets(center: Vec3<S>, axis: Vec3<S>, a: S, c: S) -> Result<Self, GeometryError> {
        Self::positive(&[a, c])?;
        let [u, v, w] = Self::frame(center, axis)?;
        let z = S::ZERO;
        let ia = S::ONE / (a * a);
        let ic = S::ONE / (c * c);
        Self::from_local([-ia, -ia, ic, z, z, z, z, z, z, -S::ONE], center, u, v, w)
    }

    /// The value `Q(p)` (zero on the surface).
    pub fn eval(&self, p: Vec3<S>) -> S {
        let [a, b, c, d, e, f, g, h, i, j] = self.k;
        a * p.x * p.x
            + b * p.y * p.y
            + c * p.z * p.z
            + d * p.x * p.y
            + e * p.x * p.z
            + f * p.y * p.z
            + g * p.x
            + h * p.y
            + i * p.z
            + j
    }

    /// Crossings of each active ray with the (clipped) quadric in `(t_min, t_max)`.
    // Forced inline into the query loops except on Armv6-M (Cortex-M0/M0+,
    // the one target without 32-bit atomics), where the copies would not fit
    // a small flash: there each kernel is one function per packet width.
    #[cfg_attr(all(not(debug_assertions), not(armv6m)), inline(always))]
    pub fn roots<const W: usize>(
        &self,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Roots<S, W> {
        let [a, b, c, d, e, f, g, h, i, j] = self.k;
        let dir = &ray.dir;
        // The linear and constant coefficients as lanes: a far origin (below)
        // solves with its own.
        let (mut gl, mut hl, mut il, mut jl) = (Lanes::splat(g), Lanes::splat(h), Lanes::splat(i), Lanes::splat(j));
        let mut o = ray.origin;
        let mut far_solve = None;
        if S::LIMITED_RANGE {
            // A limited-range scalar keeps this kernel's intermediates in
            // range only for origins inside the scene's coordinate box; an
            // unbounded plane puts hit points, and so shadow-ray origins, far
            // outside it, where `b_q²` and `4·a_q·c_q` would both saturate
            // and their difference report a root that is not there.
            // Those lanes solve from the ray's point nearest the frame's
            // centre, `p = o + t_s·d` with `t_s = −o·d`, as the sphere
            // solves from the point nearest its centre; where even that
            // point lies outside the box (the line misses it), in
            // coordinates scaled by `2^k` (`k ≤ 0`, exact shifts) that bring
            // `p` inside: with `X = 2^k·x` the quadric keeps `A..F`, its
            // `G, H, I` scale by `2^k` and `J` by `2^2k`, and a root `t_X`
            // is `2^k·t`. Every other lane has `t_s = 0` and `k = 0`, so it
            // computes exactly what it would without this step.
            let zero = Lanes::<S, W>::zero();
            let limit = Lanes::splat(S::from_f32(S::COORDINATE_LIMIT));
            let far = active & o.x.abs().max(o.y.abs()).max(o.z.abs()).gt(limit);
            if far.any() {
                let ts = Lanes::select(far, -(o.dot(*dir)), zero);
                let p = o + dir.scale(ts);
                let m = p.x.abs().max(p.y.abs()).max(p.z.abs());
                let outside = far & m.gt(limit);
                // m > limit ≥ 1 where outside: the exponent is negative.
                let k: [i32; W] =
                    core::array::from_fn(|l| if outside.get(l) { m.0[l].normalizing_exponent().min(0) } else { 0 });
                o = Vec3::new(p.x.mul_pow2(k), p.y.mul_pow2(k), p.z.mul_pow2(k));
                gl = gl.mul_pow2(k);
                hl = hl.mul_pow2(k);
                il = il.mul_pow2(k);
                jl = jl.mul_pow2(k.map(|k| 2 * k));
                far_solve = Some((ts, k));
            }
        }
        let (ox, oy, oz) = (o.x, o.y, o.z);
        let (dx, dy, dz) = (dir.x, dir.y, dir.z);
        // Substitute x = o + t·d into xᵀMx + gᵀx + J (M symmetric, with A,
        // B, C on its diagonal and D/2, E/2, F/2 off it; g = (G, H, I)):
        // a_q t² + b_q t + c_q = 0 with a_q = dᵀMd, b_q = dᵀ(2Mo + g) and
        // c_q = ½·oᵀ(2Mo + 2g) + J. The origin's vector u = 2Mo + g is
        // formed once and serves both b_q and c_q: 24 products instead of
        // the 49 of the expanded sums.
        let (a2, b2, c2) = (a + a, b + b, c + c);
        let ux = ox * a2 + oy * d + oz * e + gl;
        let uy = ox * d + oy * b2 + oz * f + hl;
        let uz = ox * e + oy * f + oz * c2 + il;
        // dᵀMd = dx(A dx + D dy + E dz) + dy(B dy + F dz) + C dz².
        let aq = dx * (dx * a + dy * d + dz * e) + dy * (dy * b + dz * f) + dz * dz * c;
        let bq = dx * ux + dy * uy + dz * uz;
        let half = [-1; W];
        let cq = (ox * (ux + gl) + oy * (uy + hl) + oz * (uz + il)).mul_pow2(half) + jl;
        // Compute the discriminant; with a_q = 0 the equation is linear.
        let four = S::TWO + S::TWO;
        let disc = bq * bq - aq * cq * four;
        let linear = aq.eq_lanes(Lanes::zero());
        let quad = active & !linear & disc.ge(Lanes::zero());
        let lin = active & linear & bq.ne_lanes(Lanes::zero());
        if (quad | lin).none() {
            return Roots::none();
        }
        // q = −½(b + sign(b)·√Δ): no cancellation; roots q/a and c/q.
        let sq = Lanes::select(quad, disc, Lanes::zero()).sqrt();
        let q = Lanes::select(bq.ge(Lanes::zero()), -(bq + sq), sq - bq) * S::HALF;
        let q_ok = q.ne_lanes(Lanes::zero());
        let r0 = q.div_nonzero(aq);
        let r1 = cq.div_nonzero(q);
        // Linear lanes: the single root −c/b.
        let rl = (-cq).div_nonzero(bq);
        let mut t0 = Lanes::select(lin, rl, r0);
        let mut ok0 = quad | lin;
        // q = 0 only when b = 0 and Δ = 0: a double root at q/a = 0 ... then c = 0 too.
        let mut ok1 = quad & q_ok;
        let mut t1 = r1;
        if let Some((ts, k)) = far_solve {
            // Back to the ray's own origin and scale: t = t_s + 2^−k·t_X.
            let back = k.map(|k| -k);
            t0 = ts + t0.mul_pow2(back);
            t1 = ts + t1.mul_pow2(back);
        }
        if let Some((lo, hi)) = self.clip {
            // A root outside the clip box does not exist; the ray goes on to
            // the other root.
            ok0 &= inside_box(ray.at(t0), lo, hi);
            ok1 &= inside_box(ray.at(t1), lo, hi);
        }
        t0 = Lanes::select(ok0, t0, Lanes::splat(S::MAX));
        t1 = Lanes::select(ok1, t1, Lanes::splat(S::MAX));
        Roots::from_candidates(t0, ok0, t1, ok1, t_min, t_max)
    }

    /// Outward normals (the gradient, not normalized) at the points `p`.
    #[inline(always)]
    pub fn normals<const W: usize>(&self, p: &Vec3xW<S, W>) -> Vec3xW<S, W> {
        let [a, b, c, d, e, f, g, h, i, _] = self.k;
        Vec3::new(
            p.x * (S::TWO * a) + p.y * d + p.z * e + g,
            p.y * (S::TWO * b) + p.x * d + p.z * f + h,
            p.z * (S::TWO * c) + p.x * e + p.y * f + i,
        )
    }
}

/// The symmetric matrix of coefficients `[A..J]`.
fn to_matrix<S: Scalar>(k: [S; 10]) -> Mat4<S> {
    let [a, b, c, d, e, f, g, h, i, j] = k;
    let hf = S::HALF;
    [[a, d * hf, e * hf, g * hf], [d * hf, b, f * hf, h * hf], [e * hf, f * hf, c, i * hf], [g * hf, h * hf, i * hf, j]]
}

/// Coefficients `[A..J]` of a symmetric matrix (off-diagonal pairs summed).
fn from_matrix<S: Scalar>(m: Mat4<S>) -> [S; 10] {
    [
        m[0][0],
        m[1][1],
        m[2][2],
        m[0][1] + m[1][0],
        m[0][2] + m[2][0],
        m[1][2] + m[2][1],
        m[0][3] + m[3][0],
        m[1][3] + m[3][1],
        m[2][3] + m[3][2],
        m[3][3],
    ]
}

/// Lanes whose point lies in the closed box `[lo, hi]`. A function rather
/// than a closure so that it is always inlined (see `dispatch`).
#[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
fn inside_box<S: Scalar, const W: usize>(p: crate::geom::vec3::Vec3xW<S, W>, lo: Vec3<S>, hi: Vec3<S>) -> Mask<W> {
    p.x.ge(Lanes::splat(lo.x))
        & p.x.le(Lanes::splat(hi.x))
        & p.y.ge(Lanes::splat(lo.y))
        & p.y.le(Lanes::splat(hi.y))
        & p.z.ge(Lanes::splat(lo.z))
        & p.z.le(Lanes::splat(hi.z))
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::geom::primitives::test_util::*;
    use crate::geom::primitives::Shape;
    use crate::num::fixed32::Fixed32;

    fn close(a: &[f32], b: &[f32]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-4)
    }

    /// Points of the ellipsoid `center + R·(rx cos θ cos φ, ry sin θ cos φ,
    /// rz sin φ)` on a grid of angles.
    fn ellipsoid_points(c: Vec3<f32>, r: [f32; 3], axes: [Vec3<f32>; 3]) -> impl Iterator<Item = Vec3<f32>> {
        (0..24).flat_map(move |i| {
            (0..13).map(move |j| {
                let (th, ph) =
                    (i as f32 * core::f32::consts::TAU / 24.0, (j as f32 / 12.0 - 0.5) * core::f32::consts::PI);
                c + axes[0].scale(r[0] * th.cos() * ph.cos())
                    + axes[1].scale(r[1] * th.sin() * ph.cos())
                    + axes[2].scale(r[2] * ph.sin())
            })
        })
    }

    #[test]
    fn ellipsoid_box_holds_the_surface_and_is_tight() {
        let c = Vec3::new(1.2f32, -0.5, 3.0);
        let w = Vec3::new(1.0f32, 2.0, 0.5).normalize_or_zero();
        let (u, v) = w.orthonormal_basis();
        let r = [0.5f32, 0.3, 0.9];
        let q = Quadric::ellipsoid_oriented(c, Vec3::new(r[0], r[1], r[2]), u, v, w).unwrap();
        let (lo, hi) = q.bounds().unwrap();
        let mut seen_lo = Vec3::new(f32::MAX, f32::MAX, f32::MAX);
        let mut seen_hi = -seen_lo;
        for p in ellipsoid_points(c, r, [u, v, w]) {
            assert!(p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z, "{p:?}");
            seen_lo = seen_lo.min_elem(p);
            seen_hi = seen_hi.max_elem(p);
        }
        // At most the 1/16 margin (and the grid's sampling) looser.
        for (box_span, seen_span) in [(hi.x - lo.x, seen_hi.x - seen_lo.x), (hi.z - lo.z, seen_hi.z - seen_lo.z)] {
            assert!(box_span < seen_span * 1.1, "{box_span} vs {seen_span}");
        }
        // The same quadric with every coefficient negated has the same box.
        let neg = Quadric::new(q.coefficients().map(|k| -k)).unwrap();
        assert_eq!(neg.bounds(), q.bounds());
    }

    #[test]
    fn only_round_enough_ellipsoids_are_bounded() {
        let o = Vec3::new(0.0f32, 0.0, 0.0);
        assert!(Quadric::ellipsoid(o, Vec3::new(1.0, 1.0, 1.0)).unwrap().bounds().is_some());
        // 1 : 100 is too flat for the estimate; open quadrics have no box.
        assert_eq!(Quadric::ellipsoid(o, Vec3::new(1.0, 1.0, 0.01)).unwrap().bounds(), None);
        assert_eq!(Quadric::cylinder(o, Vec3::new(0.0, 0.0, 1.0), 1.0).unwrap().bounds(), None);
        assert_eq!(Quadric::hyperboloid_two_sheets(o, Vec3::new(0.0, 0.0, 1.0), 1.0, 1.0).unwrap().bounds(), None);
        // x² + y² + z² + 1 = 0 has no points: unbounded rather than a guess.
        assert_eq!(Quadric::new([1.0f32, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]).unwrap().bounds(), None);
        // A clip box narrows to the ellipsoid's box, and the other way round.
        let clipped = Quadric::ellipsoid(o, Vec3::new(1.0, 1.0, 1.0))
            .unwrap()
            .with_clip(Vec3::new(-5.0, -5.0, 0.0), Vec3::new(5.0, 5.0, 5.0))
            .unwrap();
        let (lo, hi) = clipped.bounds().unwrap();
        assert_eq!((lo.z, hi.x), (0.0, 1.0625));
        let cyl = Quadric::cylinder(o, Vec3::new(0.0, 0.0, 1.0), 1.0).unwrap();
        let clip = (Vec3::new(-2.0, -2.0, 0.0), Vec3::new(2.0, 2.0, 1.0));
        assert_eq!(cyl.with_clip(clip.0, clip.1).unwrap().bounds(), Some(clip));
    }

    #[test]
    fn ellipsoid_box_in_q8_24_holds_the_surface() {
        use crate::geom::uniform_scale::Similarity;
        use crate::num::fixed32::Fixed32;
        let (c, r) = (Vec3::new(1.2f32, 1.3, 0.35), [0.5f32, 0.3, 0.35]);
        let q = Quadric::ellipsoid(c, Vec3::new(r[0], r[1], r[2])).unwrap();
        let sim = Similarity { origin: [0.0, 0.5, 1.0], scale: 0.2 };
        let fq: Quadric<Fixed32> = q.similar(&sim);
        let (lo, hi) = fq.bounds().unwrap();
        let (lo, hi) = (lo.to_f32(), hi.to_f32());
        let axes = [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, 1.0)];
        for p in ellipsoid_points(c, r, axes) {
            let [x, y, z] = sim.point::<f32, f32>(p).to_f32();
            assert!(x >= lo[0] && y >= lo[1] && z >= lo[2] && x <= hi[0] && y <= hi[1] && z <= hi[2]);
        }
    }

    /// The demo's small ellipsoid in Q8.24, and the crossings in
    /// `(0, t_max)` that `roots` reports for one ray at widths 1 and 4 (the
    /// ray in lane 2 of 4, among rays from the frame's centre), checked to
    /// agree.
    fn far_ray_hits(o: [f32; 3], d: [f32; 3], t_max: f32) -> (Quadric<Fixed32>, std::vec::Vec<f32>) {
        use crate::geom::uniform_scale::Similarity;
        let q = Quadric::ellipsoid(Vec3::new(0.24f32, 0.66, -0.23), Vec3::new(0.1, 0.06, 0.07)).unwrap();
        let fq: Quadric<Fixed32> = q.similar(&Similarity::IDENTITY);
        let d = Vec3::new(d[0], d[1], d[2]).normalize_or_zero();
        let o = Vec3::<Fixed32>::from_f32(o[0], o[1], o[2]);
        let d = Vec3::<Fixed32>::from_f32(d.x, d.y, d.z);
        let tmax = Fixed32::from_f32(t_max);
        // The crossings reported in `lane`, nearest first.
        fn crossings<const W: usize>(r: &Roots<Fixed32, W>, lane: usize) -> std::vec::Vec<f32> {
            [(r.hit0, r.t0), (r.hit1, r.t1)]
                .iter()
                .filter(|(hit, _)| hit.get(lane))
                .map(|(_, t)| t.0[lane].to_f32())
                .collect()
        }
        let one = {
            let (ray, active) = RayPacket::<Fixed32, 1>::new(o.splat(), d.splat());
            crossings(&fq.roots(&ray, Lanes::zero(), Lanes::splat(tmax), active), 0)
        };
        let (mut org, mut dir) = (Vec3::<Fixed32>::ZERO.splat::<4>(), Vec3::<Fixed32>::ZERO.splat::<4>());
        for l in 0..4 {
            let (oo, dd) = if l == 2 { (o, d) } else { (Vec3::ZERO, Vec3::from_f32(0.6, 0.0, 0.8)) };
            org.set_lane(l, oo);
            dir.set_lane(l, dd);
        }
        let (ray, active) = RayPacket::<Fixed32, 4>::new(org, dir);
        let four = crossings(&fq.roots(&ray, Lanes::zero(), Lanes::splat(tmax), active), 2);
        assert_eq!(one, four, "width 1 against width 4");
        (fq, one)
    }

    #[test]
    fn q8_24_far_origins_report_no_false_crossings() {
        // A shadow ray from a far floor point of the demo (where b_q² and
        // 4·a_q·c_q both saturated and a "double root" was reported), a ray
        // whose line passes outside the scene's box, and one that passes
        // beside the ellipsoid: no crossing.
        let (_, h) = far_ray_hits([-26.868412, 52.577297, -0.29464138], [0.44414008, -0.89572763, 0.020289302], 11.3);
        assert!(h.is_empty(), "{h:?}");
        let (_, h) = far_ray_hits([-60.0, 50.0, 0.0], [1.0, 0.0, 0.0], 120.0);
        assert!(h.is_empty(), "{h:?}");
        let (_, h) = far_ray_hits([-40.0, 0.76, -0.23], [1.0, 0.0, 0.0], 120.0);
        assert!(h.is_empty(), "{h:?}");
    }

    #[test]
    fn q8_24_far_origins_find_the_true_crossings() {
        // Rays from far away (outside the scene's box) aimed through the
        // ellipsoid, from the side, from above and diagonally: both
        // crossings, where the exact solution puts them.
        for (o, d) in [
            ([-40.0f32, 0.66, -0.23], [1.0f32, 0.0, 0.0]),
            ([0.24, 40.0, -0.23], [0.0, -1.0, 0.0]),
            ([30.24, 30.66, -0.23], [-1.0, -1.0, 0.0]),
            ([-20.0, 0.68, -0.2], [1.0, 0.0, 0.0]),
        ] {
            let (q, h) = far_ray_hits(o, d, 120.0);
            // The exact crossings with the Q8.24 coefficients, in f64.
            let k = q.coefficients().map(|v| v.to_f32() as f64);
            let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let (o, d) = (o.map(|v| v as f64), d.map(|v| (v / n) as f64));
            let m = [[k[0], k[3] / 2.0, k[4] / 2.0], [k[3] / 2.0, k[1], k[5] / 2.0], [k[4] / 2.0, k[5] / 2.0, k[2]]];
            let mv =
                |v: [f64; 3]| core::array::from_fn::<f64, 3, _>(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2]);
            let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            let g = [k[6], k[7], k[8]];
            let aq = dot(d, mv(d));
            let bq = 2.0 * dot(d, mv(o)) + dot(g, d);
            let cq = dot(o, mv(o)) + dot(g, o) + k[9];
            let disc = bq * bq - 4.0 * aq * cq;
            assert!(disc > 0.0);
            let want = [(-bq - disc.sqrt()) / (2.0 * aq), (-bq + disc.sqrt()) / (2.0 * aq)];
            assert_eq!(h.len(), 2, "{o:?} {d:?}: {h:?}, want {want:?}");
            for (t, w) in h.iter().zip(want) {
                assert!((*t as f64 - w).abs() < 2e-3, "{o:?} {d:?}: {h:?}, want {want:?}");
            }
        }
    }

    #[test]
    fn unit_sphere_as_quadric() {
        let q = Shape::Quadric(Quadric::new([1.0f32, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0]).unwrap());
        assert_eq!(hits(&q, [0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), vec![4.0, 6.0]);
        assert_eq!(hits(&q, [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]), vec![1.0]);
        assert!(hits(&q, [0.0, 2.0, -5.0], [0.0, 0.0, 1.0]).is_empty());
        assert!(hits(&q, [0.0, 0.0, 5.0], [0.0, 0.0, 1.0]).is_empty());
    }

    #[test]
    fn linear_case_paraboloid_along_axis() {
        // z = x² + y², hit along its axis from above: a_q = 0, one root.
        let q = Shape::Quadric(Quadric::new([1.0f32, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0]).unwrap());
        assert_eq!(hits(&q, [0.0, 0.0, 5.0], [0.0, 0.0, -1.0]), vec![5.0]);
        // A plane x = 2 written as a quadric is purely linear too.
        let p = Shape::Quadric(Quadric::new([0.0f32, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -2.0]).unwrap());
        assert_eq!(hits(&p, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]), vec![2.0]);
        assert!(hits(&p, [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]).is_empty());
    }

    #[test]
    fn cylinder_along_any_axis() {
        let axis = Vec3::new(1.0f32, 1.0, 0.0);
        let c = Shape::Quadric(Quadric::cylinder(Vec3::new(0.0, 0.0, 0.0), axis, 1.0).unwrap());
        // Shoot along z through the axis: hits at ±1.
        assert!(close(&hits(&c, [0.3, 0.3, -5.0], [0.0, 0.0, 1.0]), &[4.0, 6.0]));
        // Parallel to the axis inside: no hit; outside: no hit.
        assert!(hits(&c, [0.0, 0.0, 0.5], [1.0, 1.0, 0.0]).is_empty());
        assert!(hits(&c, [0.0, 0.0, 2.0], [1.0, 1.0, 0.0]).is_empty());
    }

    #[test]
    fn named_quadrics_hit_where_expected() {
        let o = Vec3::new(0.0f32, 0.0, 0.0);
        let z = Vec3::new(0.0f32, 0.0, 1.0);
        let e = Shape::Quadric(Quadric::ellipsoid(o, Vec3::new(1.0, 2.0, 3.0)).unwrap());
        assert!(close(&hits(&e, [0.0, -5.0, 0.0], [0.0, 1.0, 0.0]), &[3.0, 7.0]));
        assert!(close(&hits(&e, [0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), &[2.0, 8.0]));
        let cone = Shape::Quadric(Quadric::cone(o, z, core::f32::consts::FRAC_PI_4).unwrap());
        // At z = 2 the radius is 2.
        assert!(close(&hits(&cone, [-5.0, 0.0, 2.0], [1.0, 0.0, 0.0]), &[3.0, 7.0]));
        let par = Shape::Quadric(Quadric::paraboloid(o, z, 0.25).unwrap());
        // x² + y² = z: at z = 4 the radius is 2.
        assert!(close(&hits(&par, [-5.0, 0.0, 4.0], [1.0, 0.0, 0.0]), &[3.0, 7.0]));
        let h1 = Shape::Quadric(Quadric::hyperboloid_one_sheet(o, z, 1.0, 1.0).unwrap());
        // Waist radius 1 at z = 0; at z = 1 the radius is √2.
        assert!(close(&hits(&h1, [-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]), &[4.0, 6.0]));
        let s2 = 2.0f32.sqrt();
        assert!(close(&hits(&h1, [-5.0, 0.0, 1.0], [1.0, 0.0, 0.0]), &[5.0 - s2, 5.0 + s2]));
        let h2 = Shape::Quadric(Quadric::hyperboloid_two_sheets(o, z, 1.0, 1.0).unwrap());
        // Along the axis: vertices at z = ±1.
        assert!(close(&hits(&h2, [0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), &[4.0, 6.0]));
        // Between the sheets, sideways: nothing.
        assert!(hits(&h2, [-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]).is_empty());
    }

    #[test]
    fn clip_box_skips_to_next_root() {
        // Unit sphere keeping only z <= 0.5: a ray up the z axis from below
        // enters at z = -1 but its exit at z = +1 is clipped away.
        let q = Quadric::new([1.0f32, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0])
            .unwrap()
            .with_clip(Vec3::new(-2.0, -2.0, -2.0), Vec3::new(2.0, 2.0, 0.5))
            .unwrap();
        let s = Shape::Quadric(q);
        assert_eq!(hits(&s, [0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), vec![4.0]);
        // From above, the near root is clipped: the ray passes through to the far one.
        assert_eq!(hits(&s, [0.0, 0.0, 5.0], [0.0, 0.0, -1.0]), vec![6.0]);
    }

    #[test]
    fn finite_cylinder_from_clip() {
        let c = Quadric::cylinder(Vec3::new(0.0f32, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0), 1.0)
            .unwrap()
            .with_clip(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 2.0))
            .unwrap();
        let s = Shape::Quadric(c);
        assert!(close(&hits(&s, [-5.0, 0.0, 1.0], [1.0, 0.0, 0.0]), &[4.0, 6.0]));
        assert!(hits(&s, [-5.0, 0.0, 3.0], [1.0, 0.0, 0.0]).is_empty());
    }

    #[test]
    fn gradient_normal_points_outward() {
        let q = Quadric::new([1.0f32, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0]).unwrap();
        assert_eq!(q.normals::<1>(&Vec3::new(0.0, 1.0, 0.0).splat()).lane(0), Vec3::new(0.0, 2.0, 0.0));
    }

    #[test]
    fn degenerate_input_is_rejected() {
        let z = [0.0f32; 10];
        assert_eq!(Quadric::new(z), Err(GeometryError::DegenerateQuadric));
        let mut n = z;
        n[0] = f32::NAN;
        assert_eq!(Quadric::new(n), Err(GeometryError::NonFinite));
        let o = Vec3::new(0.0f32, 0.0, 0.0);
        assert_eq!(Quadric::cylinder(o, Vec3::ZERO, 1.0), Err(GeometryError::ZeroLengthAxis));
        assert_eq!(Quadric::cylinder(o, Vec3::new(0.0, 0.0, 1.0), 0.0), Err(GeometryError::NonPositiveRadius));
        assert_eq!(Quadric::ellipsoid(o, Vec3::new(1.0, -1.0, 1.0)), Err(GeometryError::NonPositiveRadius));
        assert_eq!(Quadric::cone(o, Vec3::new(0.0, 0.0, 1.0), 2.0), Err(GeometryError::NonPositiveRadius));
    }
}
