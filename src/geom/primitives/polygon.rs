//! Planar polygons, convex or not, and polygon patches (a normal per vertex).
//!
//! Vertices live in the scene's shared vertex pool; a polygon holds the range
//! of its vertices (a patch stores its `n` normals right after its `n`
//! positions). The plane comes from Newell's method, which is exact for
//! triangles and robust for slightly non-planar input. The inside test runs
//! in the projection that drops the normal's dominant axis:
//! - convex polygons: every edge function has the polygon's orientation sign;
//! - non-convex polygons: crossing number (even-odd rule), division-free;
//!   an outline of many edges keeps, per block of consecutive edges, the
//!   bins of its lowest and highest `v`, so a packet passes over the blocks
//!   no line of its points meets (see [`EDGE_BLOCKS`]).
//!
//! A polygon whose area is zero (collinear or repeated vertices, which real
//! meshes contain) is kept, so primitive indices stay stable, but never hit.

use super::error::GeometryError;
use super::plane::{moved_offset, plane_crossing};
use crate::geom::ray::{RayPacket, Roots};
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::{Vec3, Vec3xW};
use crate::num::bins;
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;

/// Blocks of consecutive edges of a many-sided non-convex outline (at least
/// [`BLOCKED_EDGES`] edges): each keeps the bins (one of 256 over the
/// outline's `v` range, a non-decreasing function of `v`) of its edges'
/// lowest and highest `v`. An edge
/// straddles a line `v = pv` only if `lo ≤ pv < hi` for its end points'
/// `v` in order, so a block whose bins `[b_lo, b_hi]` lie wholly below the
/// bin of the packet's smallest `pv` or above that of its largest holds no
/// edge that changes a count, and is passed over: the bin is
/// non-decreasing, so no margin is needed and the counts, hence the bits,
/// are those of testing every edge. A gear face of `gears-2` has 144
/// edges; most packets' lines meet a few of its 12 blocks. (Twelve blocks
/// keep a polygon within the size of the largest primitive, so a
/// [`crate::geom::primitives::Shape`] is no larger for them.)
pub const EDGE_BLOCKS: usize = 12;

/// Fewest edges for [`EDGE_BLOCKS`] (two per block); smaller outlines test
/// every edge.
pub const BLOCKED_EDGES: u32 = 2 * EDGE_BLOCKS as u32;

/// The lanes whose line `v = pv` the edge `a → b` (in `(u, v)`) straddles
/// and crosses to the right of the point `(pu, pv)`: without division, the
/// crossing is right of the point when the edge function has the sign of
/// `b.v − a.v`.
#[inline(always)]
fn crossing<S: Scalar, const W: usize>(pu: Lanes<S, W>, pv: Lanes<S, W>, a: (S, S), b: (S, S)) -> Mask<W> {
    let straddle = pv.lt(Lanes::splat(a.1)) ^ pv.lt(Lanes::splat(b.1));
    let e = edge_function(pu, pv, a, b, SKIP_AXIS_PRODUCTS);
    let right = if b.1 > a.1 { e.gt(Lanes::zero()) } else { e.lt(Lanes::zero()) };
    straddle & right
}

/// Whether the polygon kernel leaves out an axis edge's zero product
/// ([`edge_function`]): on Armv6-M, where a `fixed32` product is a routine
/// of about 22 instructions (the Cortex-M0 demo frame 0.4 % shorter), and
/// on RV32, where it is `mul`, `mulh` and seven (the RV32IMAC `fixed32`
/// demo frame 0.7 % shorter, for 1.5 KB of flash). Elsewhere a product is
/// an instruction or a few, and the branches cost more than they save.
const SKIP_AXIS_PRODUCTS: bool = cfg!(any(armv6m, target_arch = "riscv32"));

/// The edge function of the points `(pu, pv)` for the edge `a → b`:
/// `(pv − a.v)·(b.u − a.u) − (pu − a.u)·(b.v − a.v)`, positive to the left
/// of the edge. With `skip` where products may skip a zero factor
/// ([`Scalar::SPARSE_PRODUCTS`]), an edge along an axis (a rectangle's,
/// a wall's) forms only its other product, bit for bit the same: the
/// skipped product is exactly zero, and `x − 0 = x`.
#[inline(always)]
fn edge_function<S: Scalar, const W: usize>(
    pu: Lanes<S, W>,
    pv: Lanes<S, W>,
    a: (S, S),
    b: (S, S),
    skip: bool,
) -> Lanes<S, W> {
    let (du, dv) = (b.0 - a.0, b.1 - a.1);
    if skip && S::SPARSE_PRODUCTS && du == S::ZERO {
        Lanes::zero() - (pu - a.0) * dv
    } else if skip && S::SPARSE_PRODUCTS && dv == S::ZERO {
        (pv - a.1) * du
    } else {
        (pv - a.1) * du - (pu - a.0) * dv
    }
}

/// Whether polygons keep edge blocks and the kernel passes over them: on
/// 64-bit hosts. Not on WebAssembly, where the browser module's size
/// budget (`scripts/web.sh`) did not leave room for the 6.6 KB they added,
/// nor on 32-bit microcontrollers, whose images they made 0.6–12.8 KB
/// larger (RV32IMAC's past 128 KiB) and whose demo frame (no outline of
/// many edges) up to 2.2 % longer. There polygons keep no blocks and test
/// every edge, in the loop the boards were measured with.
const BLOCKS_HERE: bool = cfg!(target_pointer_width = "64");

/// Bins of the edge blocks' `v` bounds.
const V_BINS: usize = 256;

/// A block spanning every bin: never passed over.
const EVERY_BIN: [u8; 2] = [0, (V_BINS - 1) as u8];

/// Edge blocks that pass over nothing (a polygon without blocks).
const NO_BLOCKS: [[u8; 2]; EDGE_BLOCKS] = [EVERY_BIN; EDGE_BLOCKS];

/// A planar polygon (or patch) whose vertices are in a vertex pool.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polygon<S> {
    first: u32,
    count: u32,
    patch: bool,
    convex: bool,
    degenerate: bool,
    /// Projection axes `(u, v)`: the two axes other than the normal's dominant one.
    axis_u: u8,
    axis_v: u8,
    /// Orientation of the projected outline: counter-clockwise in `(u, v)`.
    ccw: bool,
    normal: Vec3<S>,
    d: S,
    /// The geometric normal of a hit: `normal` normalised again as the
    /// tracer normalises every geometric normal ([`Vec3::hit_normal`]),
    /// worked out once here rather than at every hit.
    hit_normal: Vec3<S>,
    /// The window of the edge blocks' bins ([`bins::bin`]): its origin,
    /// `2^shift` as a factor, and `shift + 128` (unused below
    /// [`BLOCKED_EDGES`] edges and for convex outlines).
    v_origin: S,
    v_scale: S,
    v_shift: u8,
    /// Per block of [`EDGE_BLOCKS`], the bins of its edges' lowest and
    /// highest `v`.
    blocks: [[u8; 2]; EDGE_BLOCKS],
}

crate::num::bake::bake_struct!("raypack::geom::primitives::Polygon", Polygon<S> { first: u32, count: u32, patch: bool, convex: bool, degenerate: bool, axis_u: u8, axis_v: u8, ccw: bool, normal: Vec3<S>, d: S, hit_normal: Vec3<S>, v_origin: S, v_scale: S, v_shift: u8, blocks: [[u8; 2]; EDGE_BLOCKS] });

/// The component `axis` of every lane.
#[inline(always)]
fn lanes_axis<S: Scalar, const W: usize>(v: &Vec3xW<S, W>, axis: u8) -> Lanes<S, W> {
    match axis {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

/// Whether a polygon's kernel forms only the two components of its hit
/// points that it projects (the same bits either way): for packets of 4
/// and more off x86. The Cortex-M55's width-4 frame retired 37.4 M
/// instructions with it against 39.5 M (`scripts/firmware.sh`, RVV's
/// widths 4 and 8 a little fewer too), while width 1 retired more on the
/// M55, RVV and the Cortex-M0 (57.9 M against 57.8 M, 63.4 M against
/// 62.9 M, 196.9 M against 196.7 M), and x86 rendered `gears-2` at packet
/// 16 4.6 % slower (interleaved `raypack bench`).
const fn project_two<const W: usize>() -> bool {
    W >= 4 && !cfg!(any(target_arch = "x86", target_arch = "x86_64"))
}

impl<S: Scalar> Polygon<S> {
    /// The same polygon in the frame of `sim`, with scalar `T`, over a pool
    /// converted in the same order (positions by `sim`, normals unchanged).
    /// Its shape flags are the original's (a similarity keeps them). Its
    /// edge blocks are empty until [`Polygon::with_edge_blocks`] works them
    /// out over the converted pool; until then every edge is tested.
    pub fn similar<T: Scalar>(&self, sim: &Similarity) -> Polygon<T> {
        let normal = sim.direction(self.normal);
        Polygon {
            first: self.first,
            count: self.count,
            patch: self.patch,
            convex: self.convex,
            degenerate: self.degenerate,
            axis_u: self.axis_u,
            axis_v: self.axis_v,
            ccw: self.ccw,
            normal,
            d: T::from_f32(moved_offset(self.normal, self.d, sim)),
            hit_normal: normal.hit_normal(),
            v_origin: T::ZERO,
            v_scale: T::ZERO,
            v_shift: 0,
            blocks: NO_BLOCKS,
        }
    }

    /// The polygon with its edge blocks worked out over `pool` (the pool it
    /// is built against): see [`EDGE_BLOCKS`]. Convex outlines, outlines of
    /// fewer than [`BLOCKED_EDGES`] edges, and every polygon on targets
    /// whose kernel passes over no blocks (32-bit ones: WebAssembly and
    /// microcontrollers) are returned as they are.
    pub fn with_edge_blocks(mut self, pool: &[Vec3<S>]) -> Self {
        let verts = self.vertices(pool);
        let n = verts.len();
        if !BLOCKS_HERE || self.convex || self.degenerate || self.count < BLOCKED_EDGES || n != self.count as usize {
            return self;
        }
        let iv = self.axis_v as usize;
        let (mut lo, mut hi) = (f32::MAX, f32::MIN);
        for v in verts {
            lo = lo.min(v.axis(iv).to_f32());
            hi = hi.max(v.axis(iv).to_f32());
        }
        // The largest power of two that spreads the outline's `v` range
        // over at most 256 bins.
        let shift = bins::fit_shift::<-120, 100>((hi - lo).max(1.0e-30), V_BINS);
        self.v_origin = S::from_f32(lo);
        self.v_shift = (shift + 128) as u8;
        self.v_scale = bins::scale_of(shift);
        let size = n.div_ceil(EDGE_BLOCKS);
        let mut blocks = self.blocks;
        for (j, block) in blocks.iter_mut().enumerate() {
            // Edge `i` runs from vertex `i − 1` (the last, for edge 0) to
            // vertex `i`: block `j`'s edges `[j·size, (j + 1)·size)` touch
            // vertices `j·size − 1 … (j + 1)·size − 1`.
            let (start, end) = ((j * size).min(n), ((j + 1) * size).min(n));
            *block = if start == end {
                [(V_BINS - 1) as u8, 0]
            } else {
                let prev = if start == 0 { n - 1 } else { start - 1 };
                let mut b = [u8::MAX, 0];
                for k in core::iter::once(prev).chain(start..end) {
                    let bin = verts.get(k).map_or(0, |v| self.v_bin(v.axis(iv))) as u8;
                    b = [b[0].min(bin), b[1].max(bin)];
                }
                b
            };
        }
        self.blocks = blocks;
        self
    }

    /// The bin of `v` among the edge blocks' (see [`EDGE_BLOCKS`]).
    #[inline(always)]
    fn v_bin(&self, v: S) -> usize {
        bins::bin(v, self.v_origin, self.v_shift as i32 - 128, self.v_scale, V_BINS)
    }

    /// The same polygon over pool slots starting at `first` (a pool copied
    /// elsewhere).
    pub(crate) fn at_first(self, first: u32) -> Self {
        Polygon { first, ..self }
    }

    /// A polygon over `pool[first .. first + count]` (for a patch, the normals
    /// follow at `pool[first + count .. first + 2·count]`, already checked to
    /// be non-zero by the caller).
    ///
    /// Errors: fewer than 3 vertices, a range outside the pool, a non-finite
    /// coordinate. A zero-area polygon is accepted and marked degenerate.
    pub fn from_pool(pool: &[Vec3<S>], first: u32, count: u32, patch: bool) -> Result<Self, GeometryError> {
        if count < 3 {
            return Err(GeometryError::TooFewVertices(count));
        }
        // Checked: on a 32-bit target `2·count` or `first + slots` can wrap.
        let n_slots = if patch { (count as usize).checked_mul(2) } else { Some(count as usize) };
        let end = n_slots.and_then(|n| (first as usize).checked_add(n));
        let all = end.and_then(|end| pool.get(first as usize..end)).ok_or(GeometryError::VertexRange)?;
        if all.iter().any(|v| !v.is_finite()) {
            return Err(GeometryError::NonFinite);
        }
        let verts = all.get(..count as usize).ok_or(GeometryError::VertexRange)?;

        // Newell's method: the normal's components are twice the signed areas
        // of the projections onto the coordinate planes. Relative to the first
        // vertex, to keep the products small.
        let o = verts[0];
        let mut n = Vec3::ZERO;
        let mut lo = o;
        let mut hi = o;
        let mut prev = verts[count as usize - 1] - o;
        for &v in verts {
            let cur = v - o;
            n.x = n.x + (prev.y - cur.y) * (prev.z + cur.z);
            n.y = n.y + (prev.z - cur.z) * (prev.x + cur.x);
            n.z = n.z + (prev.x - cur.x) * (prev.y + cur.y);
            lo = lo.min_elem(v);
            hi = hi.max_elem(v);
            prev = cur;
        }
        // Zero area: the normal vanishes (exactly, for repeated or collinear
        // vertices in exact arithmetic), or is negligible against the extent.
        let extent = (hi - lo).max_abs();
        let n_len = n.length();
        let degenerate = !(n_len > S::ZERO) || !(n_len > extent * extent * S::from_f32(1.0e-7));

        let normal = if degenerate { Vec3::ZERO } else { n.scale(S::ONE / n_len) };
        // Drop the dominant axis of the normal for the 2D inside test; (u, v)
        // are the next two axes cyclically, so the projected signed area has
        // the sign of the dropped component.
        let ax = normal.x.abs();
        let ay = normal.y.abs();
        let az = normal.z.abs();
        let drop: u8 = if ax >= ay && ax >= az {
            0
        } else if ay >= az {
            1
        } else {
            2
        };
        let axis_u = (drop + 1) % 3;
        let axis_v = (drop + 2) % 3;
        let ccw = normal.axis(drop as usize) > S::ZERO;

        let mut poly = Polygon {
            first,
            count,
            patch,
            convex: false,
            degenerate,
            axis_u,
            axis_v,
            ccw,
            normal,
            d: -normal.dot(o),
            hit_normal: normal.hit_normal(),
            v_origin: S::ZERO,
            v_scale: S::ZERO,
            v_shift: 0,
            blocks: NO_BLOCKS,
        };
        poly.convex = !degenerate && poly.is_convex_outline(verts);
        Ok(poly.with_edge_blocks(pool))
    }

    /// Convexity of the projected outline: every turn has the same sign and
    /// the outline goes around once (each coordinate's direction changes sign
    /// at most twice), which excludes star polygons.
    fn is_convex_outline(&self, verts: &[Vec3<S>]) -> bool {
        let n = verts.len();
        let (mut pos, mut neg) = (false, false);
        let (mut du_changes, mut dv_changes) = (0u32, 0u32);
        let (mut last_du, mut last_dv) = (0i8, 0i8);
        // Two passes over the edges: the first primes the last seen signs, the
        // second counts every cyclic sign change exactly once.
        for k in 0..2 * n {
            let a = verts[k % n];
            let b = verts[(k + 1) % n];
            let c = verts[(k + 2) % n];
            let e1 = (
                b.axis(self.axis_u as usize) - a.axis(self.axis_u as usize),
                b.axis(self.axis_v as usize) - a.axis(self.axis_v as usize),
            );
            let e2 = (
                c.axis(self.axis_u as usize) - b.axis(self.axis_u as usize),
                c.axis(self.axis_v as usize) - b.axis(self.axis_v as usize),
            );
            if k < n {
                let turn = e1.0 * e2.1 - e1.1 * e2.0;
                pos |= turn > S::ZERO;
                neg |= turn < S::ZERO;
            }
            let sgn = |x: S| {
                if x > S::ZERO {
                    1i8
                } else if x < S::ZERO {
                    -1
                } else {
                    0
                }
            };
            let (su, sv) = (sgn(e1.0), sgn(e1.1));
            if su != 0 {
                if last_du != 0 && su != last_du && k >= n {
                    du_changes = du_changes.saturating_add(1);
                }
                last_du = su;
            }
            if sv != 0 {
                if last_dv != 0 && sv != last_dv && k >= n {
                    dv_changes = dv_changes.saturating_add(1);
                }
                last_dv = sv;
            }
        }
        !(pos && neg) && du_changes <= 2 && dv_changes <= 2
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> u32 {
        self.count
    }
    /// Index of the first vertex in the pool.
    pub fn first_vertex(&self) -> u32 {
        self.first
    }
    /// Whether this is a patch (per-vertex normals).
    pub fn is_patch(&self) -> bool {
        self.patch
    }
    /// Whether the outline is convex (the fast inside test applies).
    pub fn is_convex(&self) -> bool {
        self.convex
    }
    /// Whether the polygon has zero area (it is never hit).
    pub fn is_degenerate(&self) -> bool {
        self.degenerate
    }
    /// The vertex positions, from the pool (empty if the pool is not the
    /// one the polygon was built against).
    #[inline]
    pub fn vertices<'a>(&self, pool: &'a [Vec3<S>]) -> &'a [Vec3<S>] {
        let end = (self.first as usize).saturating_add(self.count as usize);
        pool.get(self.first as usize..end).unwrap_or(&[])
    }
    /// The per-vertex normals of a patch (empty for a plain polygon).
    #[inline]
    pub fn vertex_normals<'a>(&self, pool: &'a [Vec3<S>]) -> &'a [Vec3<S>] {
        if !self.patch {
            return &[];
        }
        let start = (self.first as usize).saturating_add(self.count as usize);
        let end = start.saturating_add(self.count as usize);
        pool.get(start..end).unwrap_or(&[])
    }

    /// Crossing of each active ray with the polygon in `(t_min, t_max)`.
    // Forced inline into the query loops except on Armv6-M (Cortex-M0/M0+,
    // the one target without 32-bit atomics), where the copies would not fit
    // a small flash: there each kernel is one function per packet width.
    #[cfg_attr(all(not(debug_assertions), not(armv6m)), inline(always))]
    pub fn roots<const W: usize>(
        &self,
        pool: &[Vec3<S>],
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Roots<S, W> {
        let verts = self.vertices(pool);
        let Some(&last) = verts.last() else {
            return Roots::none();
        };
        if self.degenerate {
            return Roots::none();
        }
        // Intersect the supporting plane first.
        let mut r = plane_crossing(self.normal, self.d, ray, t_min, t_max, active);
        if r.hit0.none() {
            return r;
        }
        // Project the hit points onto the (u, v) plane.
        let (iu, iv) = (self.axis_u, self.axis_v);
        let (pu, pv) = if project_two::<W>() {
            // Only the two projected components of `ray.at(t0)`, each as
            // `at` forms it (`o + d·t`).
            let at = |axis: u8| lanes_axis(&ray.origin, axis) + lanes_axis(&ray.dir, axis) * r.t0;
            (at(iu), at(iv))
        } else {
            let p = ray.at(r.t0);
            (lanes_axis(&p, iu), lanes_axis(&p, iv))
        };
        let mut a = (last.axis(iu as usize), last.axis(iv as usize));
        if self.convex {
            // Every edge function must have the outline's orientation sign
            // (zero, on the edge, counts as inside).
            let mut inside = r.hit0;
            for v in verts {
                let b = (v.axis(iu as usize), v.axis(iv as usize));
                let e = edge_function(pu, pv, a, b, SKIP_AXIS_PRODUCTS);
                inside &= if self.ccw { e.ge(Lanes::zero()) } else { e.le(Lanes::zero()) };
                if inside.none() {
                    return Roots::none();
                }
                a = b;
            }
            r.hit0 = inside;
        } else {
            // Crossing number of a ray from the point in +u: count edges that
            // straddle the line v = pv and cross it to the right of the point
            // ([`crossing`]).
            //
            // An edge straddles a line when `lo ≤ pv < hi` (its end points'
            // v in order). An edge outside the packet's span of lines
            // `[v_lo, v_hi]` straddles none of them and changes no count, so
            // it is skipped on two scalar comparisons: most edges of a
            // many-sided outline (a gear's 144) lie wholly above or below a
            // packet's points. (A lane whose v is NaN straddles nothing; the
            // comparisons below never take a NaN into the span.) Packets of
            // 8 and 16 lanes work out every edge of a block they do not pass
            // over, branch-free: there the span and a branch per edge cost
            // more than the skipped edges (x86 with AVX-512, `raypack bench`
            // on gears-2).
            let n = verts.len();
            let blocked = BLOCKS_HERE && self.count >= BLOCKED_EDGES;
            let skip = W < 8;
            let (mut v_lo, mut v_hi) = (S::MAX, -S::MAX);
            if skip || blocked {
                for (i, &v) in pv.0.iter().enumerate() {
                    if r.hit0.get(i) {
                        if v < v_lo {
                            v_lo = v;
                        }
                        if v > v_hi {
                            v_hi = v;
                        }
                    }
                }
            }
            let mut odd = Mask::splat(false);
            // Whether the edge `a → b` lies wholly above or below the span.
            let outside = |a: (S, S), b: (S, S)| {
                let (lo, hi) = if a.1 < b.1 { (a.1, b.1) } else { (b.1, a.1) };
                v_hi < lo || v_lo >= hi
            };
            if BLOCKS_HERE {
                // Only the blocks whose bins meet those of the span (see
                // `EDGE_BLOCKS`); a smaller outline is one block of every
                // edge, never passed over.
                let (size, blocks, b_lo, b_hi) = if blocked {
                    (n.div_ceil(EDGE_BLOCKS), &self.blocks[..], self.v_bin(v_lo), self.v_bin(v_hi))
                } else {
                    (n, &[EVERY_BIN][..], 0, V_BINS - 1)
                };
                for (j, &[lo, hi]) in blocks.iter().enumerate() {
                    if b_hi < lo as usize || b_lo > hi as usize {
                        continue;
                    }
                    let start = j * size;
                    let Some(first) = (if start == 0 { Some(&last) } else { verts.get(start - 1) }) else { break };
                    let mut a = (first.axis(iu as usize), first.axis(iv as usize));
                    for v in verts.iter().take((start + size).min(n)).skip(start) {
                        let b = (v.axis(iu as usize), v.axis(iv as usize));
                        if !(skip && outside(a, b)) {
                            odd ^= crossing(pu, pv, a, b);
                        }
                        a = b;
                    }
                }
            } else {
                // Every edge, with the span's test and `crossing` written out:
                // through the two helpers the Cortex-M4F's `f32` frame took
                // 0.36 % more instructions.
                for v in verts {
                    let b = (v.axis(iu as usize), v.axis(iv as usize));
                    let (lo, hi) = if a.1 < b.1 { (a.1, b.1) } else { (b.1, a.1) };
                    if skip && (v_hi < lo || v_lo >= hi) {
                        a = b;
                        continue;
                    }
                    let straddle = pv.lt(Lanes::splat(a.1)) ^ pv.lt(Lanes::splat(b.1));
                    let e = edge_function(pu, pv, a, b, SKIP_AXIS_PRODUCTS);
                    let right = if b.1 > a.1 { e.gt(Lanes::zero()) } else { e.lt(Lanes::zero()) };
                    odd ^= straddle & right;
                    a = b;
                }
            }
            r.hit0 &= odd;
        }
        r.t0 = Lanes::select(r.hit0, r.t0, Lanes::splat(S::MAX));
        r
    }

    /// Geometric normal (unit; zero for a degenerate polygon): the front side
    /// is the one from which the vertices run counter-clockwise.
    #[inline]
    pub fn normal(&self) -> Vec3<S> {
        self.normal
    }

    /// The geometric normal of every hit: the unit normal as the tracer
    /// normalises geometric normals ([`Vec3::hit_normal`]; zero for a
    /// degenerate polygon).
    #[inline(always)]
    pub fn hit_normal(&self) -> Vec3<S> {
        self.hit_normal
    }

    /// Shading normal at a point on the polygon: for a patch, the vertex
    /// normals interpolated with mean value coordinates (Floater 2003; they
    /// reduce to barycentric coordinates on triangles and are defined for any
    /// polygon), computed in the 2D projection; for a plain polygon, or where
    /// the interpolation vanishes, the geometric normal. Not normalized.
    pub fn shading_normal(&self, pool: &[Vec3<S>], p: Vec3<S>) -> Vec3<S> {
        let verts = self.vertices(pool);
        let normals = self.vertex_normals(pool);
        if normals.len() != verts.len() || verts.is_empty() {
            return self.normal;
        }
        let (iu, iv) = (self.axis_u as usize, self.axis_v as usize);
        let n = verts.len();
        // Fixed point: a common power-of-two factor brings the vertex offsets
        // near 1, so their products keep their digits; the weights below are
        // ratios of degree-2 terms divided by a length, so a common factor
        // scales every weight alike and the normalized result is unchanged.
        let f = if S::NORMALIZE_PRESCALE {
            let m = verts
                .iter()
                .fold(S::ZERO, |m, v| m.max((v.axis(iu) - p.axis(iu)).abs()).max((v.axis(iv) - p.axis(iv)).abs()));
            m.normalizing_factor()
        } else {
            S::ONE
        };
        // Vertex and normal `i` (indices wrap once; `get`, not indexing:
        // the render path has no panic path).
        let wrap = |i: usize| if i >= n { i - n } else { i };
        let normal_at = |i: usize| normals.get(wrap(i)).copied().unwrap_or(self.normal);
        // s_i: vertex i relative to p; r_i: its length.
        let s = |i: usize| {
            let v = verts.get(wrap(i)).copied().unwrap_or(p);
            let d = (v.axis(iu) - p.axis(iu), v.axis(iv) - p.axis(iv));
            if S::NORMALIZE_PRESCALE {
                (d.0 * f, d.1 * f)
            } else {
                d
            }
        };
        let len = |a: (S, S)| (a.0 * a.0 + a.1 * a.1).sqrt();
        // tan(α_i / 2) for the angle at p subtended by edge (i, i+1):
        // (r_i r_{i+1} − s_i·s_{i+1}) / (s_i × s_{i+1}).
        let half_tan = |a: (S, S), b: (S, S), ra: S, rb: S| {
            let cross = a.0 * b.1 - a.1 * b.0;
            let dot = a.0 * b.0 + a.1 * b.1;
            if cross == S::ZERO {
                S::ZERO
            } else {
                (ra * rb - dot) / cross
            }
        };
        let mut sum = Vec3::ZERO;
        let mut wsum = S::ZERO;
        let mut s_prev = s(n - 1);
        let mut r_prev = len(s_prev);
        let mut s_cur = s(0);
        let mut r_cur = len(s_cur);
        for i in 0..n {
            let s_next = s(i + 1);
            let r_next = len(s_next);
            // At a vertex: its own normal.
            if r_cur == S::ZERO {
                return normal_at(i);
            }
            // On edge (i, i+1): interpolate linearly along it.
            let cross = s_cur.0 * s_next.1 - s_cur.1 * s_next.0;
            let dot = s_cur.0 * s_next.0 + s_cur.1 * s_next.1;
            if cross == S::ZERO && dot < S::ZERO {
                let ni = normal_at(i);
                let nj = normal_at(i + 1);
                return ni.scale(r_next) + nj.scale(r_cur);
            }
            let w = (half_tan(s_prev, s_cur, r_prev, r_cur) + half_tan(s_cur, s_next, r_cur, r_next)) / r_cur;
            sum = sum + normal_at(i).scale(w);
            wsum = wsum + w;
            s_prev = s_cur;
            r_prev = r_cur;
            s_cur = s_next;
            r_cur = r_next;
        }
        if wsum == S::ZERO {
            return self.normal;
        }
        let interp = sum.scale(S::ONE / wsum);
        if interp.length_squared() > S::ZERO {
            interp
        } else {
            self.normal
        }
    }

    /// Axis-aligned bounds `(min, max)` of every point the kernel can hit:
    /// the vertices, and the points of the kernel's plane that lie above
    /// them along the dropped axis. The two differ for an outline that is
    /// not planar (NFF asks for planar polygons; a file need not keep to
    /// it): the kernel hits its plane (Newell's, through the first vertex)
    /// inside the projected outline, and on the plane the dropped
    /// coordinate is a linear function of `(u, v)`, so over the outline its
    /// extremes are at the vertices. Bounding the vertices alone let the
    /// BVH pass over hits that brute force found.
    pub fn bounds(&self, pool: &[Vec3<S>]) -> (Vec3<S>, Vec3<S>) {
        let verts = self.vertices(pool);
        let first = verts.first().copied().unwrap_or(Vec3::ZERO);
        let (lo, hi) = verts.iter().fold((first, first), |(lo, hi), &p| (lo.min_elem(p), hi.max_elem(p)));
        if self.degenerate {
            return (lo, hi);
        }
        // Only the dropped axis `w` can grow: the plane's points above the
        // vertices share their `(u, v)`.
        let (u, v) = (self.axis_u as usize, self.axis_v as usize);
        let w = 3 - u - v;
        let (nu, nv, nw) = (self.normal.axis(u), self.normal.axis(v), self.normal.axis(w));
        let (mut w_lo, mut w_hi) = (lo.axis(w), hi.axis(w));
        for p in verts {
            // The plane's dropped coordinate over p's (u, v): `nw` is the
            // normal's largest component (at least 1/√3), so the quotient
            // is well conditioned.
            let on = -(self.d + nu * p.axis(u) + nv * p.axis(v)) / nw;
            // (Defensive: a sum past `f32`'s range would make the bound
            // infinite or NaN; Newell's normal is not finite for outlines
            // that large, which are degenerate, so this does not arise.)
            if on.is_finite() {
                w_lo = w_lo.min(on);
                w_hi = w_hi.max(on);
            }
        }
        match w {
            0 => (Vec3::new(w_lo, lo.y, lo.z), Vec3::new(w_hi, hi.y, hi.z)),
            1 => (Vec3::new(lo.x, w_lo, lo.z), Vec3::new(hi.x, w_hi, hi.z)),
            _ => (Vec3::new(lo.x, lo.y, w_lo), Vec3::new(hi.x, hi.y, w_hi)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::primitives::test_util::*;
    use crate::geom::primitives::Shape;
    use crate::num::fixed32::Fixed32;

    fn v(x: f32, y: f32, z: f32) -> Vec3<f32> {
        Vec3::new(x, y, z)
    }

    fn poly(pool: &[Vec3<f32>]) -> Polygon<f32> {
        Polygon::from_pool(pool, 0, pool.len() as u32, false).unwrap()
    }

    #[test]
    fn convex_square_hit_and_miss() {
        let pool = [v(-1.0, -1.0, 0.0), v(1.0, -1.0, 0.0), v(1.0, 1.0, 0.0), v(-1.0, 1.0, 0.0)];
        let p = poly(&pool);
        assert!(p.is_convex());
        assert_eq!(p.normal(), v(0.0, 0.0, 1.0));
        let s = Shape::Polygon(p);
        assert_eq!(hits_in(&s, &pool, [0.5, 0.5, 3.0], [0.0, 0.0, -1.0]), vec![3.0]);
        assert_eq!(hits_in(&s, &pool, [0.5, 0.5, -3.0], [0.0, 0.0, 1.0]), vec![3.0]);
        assert!(hits_in(&s, &pool, [1.5, 0.5, 3.0], [0.0, 0.0, -1.0]).is_empty());
        // Parallel to the plane, and behind the origin.
        assert!(hits_in(&s, &pool, [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]).is_empty());
        assert!(hits_in(&s, &pool, [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]).is_empty());
    }

    #[test]
    fn clockwise_outline_also_hits() {
        let pool = [v(-1.0, 1.0, 0.0), v(1.0, 1.0, 0.0), v(1.0, -1.0, 0.0), v(-1.0, -1.0, 0.0)];
        let p = poly(&pool);
        assert_eq!(p.normal(), v(0.0, 0.0, -1.0));
        assert_eq!(hits_in(&Shape::Polygon(p), &pool, [0.2, -0.3, 2.0], [0.0, 0.0, -1.0]), vec![2.0]);
    }

    #[test]
    fn non_convex_l_shape() {
        // An L in the y = 0 plane; the notch at x, z in (0, 1) x (0, 1)... is empty.
        let pool = [
            v(-1.0, 0.0, -1.0),
            v(1.0, 0.0, -1.0),
            v(1.0, 0.0, 0.0),
            v(0.0, 0.0, 0.0),
            v(0.0, 0.0, 1.0),
            v(-1.0, 0.0, 1.0),
        ];
        let p = poly(&pool);
        assert!(!p.is_convex());
        let s = Shape::Polygon(p);
        assert_eq!(hits_in(&s, &pool, [-0.5, 2.0, 0.5], [0.0, -1.0, 0.0]), vec![2.0]);
        assert_eq!(hits_in(&s, &pool, [0.5, 2.0, -0.5], [0.0, -1.0, 0.0]), vec![2.0]);
        assert!(hits_in(&s, &pool, [0.5, 2.0, 0.5], [0.0, -1.0, 0.0]).is_empty());
    }

    /// Per point `(x, y)`, whether the ray from `(x, y, 1)` straight down
    /// crosses `p` (in z = 0), traced in packets of `W` of the points.
    fn crossings<const W: usize>(p: &Polygon<f32>, pool: &[Vec3<f32>], pts: &[(f32, f32)]) -> Vec<bool> {
        let mut out = Vec::new();
        for chunk in pts.chunks(W) {
            let mut origin = Vec3xW::<f32, W>::new(Lanes::zero(), Lanes::zero(), Lanes::zero());
            let dir = Vec3::new(0.0, 0.0, -1.0).splat::<W>();
            let mut active = Mask::splat(false);
            for (l, &(x, y)) in chunk.iter().enumerate() {
                origin.set_lane(l, v(x, y, 1.0));
                active.set(l, true);
            }
            let r = p.roots(pool, &RayPacket { origin, dir }, Lanes::zero(), Lanes::splat(f32::MAX), active);
            for l in 0..chunk.len() {
                assert!(!r.hit0.get(l) || r.t0.0[l] == 1.0);
                out.push(r.hit0.get(l));
            }
        }
        out
    }

    #[test]
    fn axis_edges_skip_a_product_bit_for_bit() {
        // Fixed point: the edge function of an edge along u or v, with its
        // zero product left out, is the full expression, bit for bit.
        let mut state = 0x5eed_ed9e_u64;
        let mut rnd = || {
            let r = (crate::num::test_rng::splitmix64(&mut state) >> 40) as f32 / (1u64 << 24) as f32;
            Fixed32::from_f32(8.0 * r - 4.0)
        };
        for _ in 0..20_000 {
            let (pu, pv) = (Lanes::<Fixed32, 4>([rnd(), rnd(), rnd(), rnd()]), Lanes([rnd(), rnd(), rnd(), rnd()]));
            let (a, c) = ((rnd(), rnd()), rnd());
            for b in [(a.0, c), (c, a.1), (a.0, a.1)] {
                let full = (pv - a.1) * (b.0 - a.0) - (pu - a.0) * (b.1 - a.1);
                assert_eq!(edge_function(pu, pv, a, b, true).0, full.0, "{a:?} → {b:?}");
            }
        }
    }

    #[test]
    fn many_sided_outline_crosses_alike_at_every_width() {
        // A gear of 144 vertices in z = 0: teeth of three vertices at radius
        // 1, gaps of three at 0.8. Packets of 1 and 4 skip the edges outside
        // their span of lines, packets of 8 and 16 test every edge.
        let pool: Vec<Vec3<f32>> = (0..144)
            .map(|k| {
                let a = k as f32 * core::f32::consts::TAU / 144.0;
                let r = if (k / 3) % 2 == 0 { 1.0 } else { 0.8 };
                v(r * libm::cosf(a), r * libm::sinf(a), 0.0)
            })
            .collect();
        let p = poly(&pool);
        assert!(!p.is_convex());
        // The points: the lines through every vertex (where an edge begins
        // or ends exactly on a packet's line) and a grid, row by row and
        // column by column, so that packets span one line or many.
        let mut ys: Vec<f32> = pool.iter().map(|q| q.y).collect();
        ys.extend((0..=60).map(|i| -1.1 + i as f32 * (2.2 / 60.0)));
        let xs: Vec<f32> = (0..=46).map(|i| -1.1 + i as f32 * (2.2 / 46.0)).collect();
        let rows: Vec<(f32, f32)> = ys.iter().flat_map(|&y| xs.iter().map(move |&x| (x, y))).collect();
        let cols: Vec<(f32, f32)> = xs.iter().flat_map(|&x| ys.iter().map(move |&y| (x, y))).collect();
        for pts in [&rows, &cols] {
            let one = crossings::<1>(&p, &pool, pts);
            assert_eq!(crossings::<4>(&p, &pool, pts), one);
            assert_eq!(crossings::<8>(&p, &pool, pts), one);
            assert_eq!(crossings::<16>(&p, &pool, pts), one);
            // Even-odd in f64 agrees wherever a point is clear of the outline.
            let (mut inside, mut outside) = (0, 0);
            for (&(x, y), &hit) in pts.iter().zip(&one) {
                let (x, y) = (x as f64, y as f64);
                let mut odd = false;
                let mut clear = true;
                for k in 0..pool.len() {
                    let (a, b) = (pool[k], pool[(k + 1) % pool.len()]);
                    let (ax, ay, bx, by) = (a.x as f64, a.y as f64, b.x as f64, b.y as f64);
                    let (ex, ey) = (bx - ax, by - ay);
                    let s = (((x - ax) * ex + (y - ay) * ey) / (ex * ex + ey * ey)).clamp(0.0, 1.0);
                    clear &= (x - ax - s * ex).hypot(y - ay - s * ey) > 1e-4;
                    if (ay > y) != (by > y) && x < ax + (y - ay) * ex / ey {
                        odd = !odd;
                    }
                }
                if clear {
                    assert_eq!(hit, odd, "point ({x}, {y})");
                    if hit {
                        inside += 1;
                    } else {
                        outside += 1;
                    }
                }
            }
            assert!(inside > 1000 && outside > 1000, "{inside} inside, {outside} outside");
        }
    }

    #[test]
    fn star_polygon_is_not_convex() {
        // A pentagram: every turn has the same sign, but it winds twice.
        let mut pool = [Vec3::ZERO; 5];
        for (k, p) in pool.iter_mut().enumerate() {
            let a = (k as f32) * 4.0 * core::f32::consts::PI / 5.0;
            *p = v(libm::cosf(a), libm::sinf(a), 0.0);
        }
        let p = poly(&pool);
        assert!(!p.is_convex());
        // The centre (inner pentagon) is covered twice: even-odd says outside.
        assert!(hits_in(&Shape::Polygon(p), &pool, [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]).is_empty());
        // A point tip is inside.
        assert_eq!(hits_in(&Shape::Polygon(p), &pool, [0.9, 0.0, 1.0], [0.0, 0.0, -1.0]), vec![1.0]);
    }

    #[test]
    fn zero_area_polygon_is_kept_but_never_hit() {
        let pool = [v(0.0, 0.0, 0.0), v(1.0, 1.0, 1.0), v(2.0, 2.0, 2.0)];
        let p = poly(&pool);
        assert!(p.is_degenerate());
        let repeated = [v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)];
        assert!(poly(&repeated).is_degenerate());
        assert!(hits_in(&Shape::Polygon(p), &pool, [1.0, 1.0, 3.0], [0.0, 0.0, -1.0]).is_empty());
    }

    #[test]
    fn bad_input_is_rejected() {
        let pool = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(f32::NAN, 1.0, 0.0)];
        assert_eq!(Polygon::from_pool(&pool, 0, 2, false), Err(GeometryError::TooFewVertices(2)));
        assert_eq!(Polygon::from_pool(&pool, 0, 3, false), Err(GeometryError::NonFinite));
        assert_eq!(Polygon::from_pool(&pool, 1, 3, false), Err(GeometryError::VertexRange));
    }

    #[test]
    fn patch_interpolates_barycentrically_on_triangles() {
        let pool = [
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.0, 1.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.0, 1.0, 0.0),
            v(0.0, 0.0, 1.0),
        ];
        let p = Polygon::from_pool(&pool, 0, 3, true).unwrap();
        let n = p.shading_normal(&pool, v(0.25, 0.25, 0.0));
        let n = n.scale(1.0 / (n.x + n.y + n.z));
        assert!((n - v(0.5, 0.25, 0.25)).length() < 1e-6, "{n:?}");
        // At a vertex and on an edge.
        assert_eq!(p.shading_normal(&pool, v(1.0, 0.0, 0.0)), v(0.0, 1.0, 0.0));
        let e = p.shading_normal(&pool, v(0.5, 0.0, 0.0)).normalize_or_zero();
        assert!((e - v(1.0, 1.0, 0.0).normalize_or_zero()).length() < 1e-6, "{e:?}");
    }

    #[test]
    fn patch_quad_center_averages() {
        let z = v(0.0, 0.0, 1.0);
        let pool = [
            v(-1.0, -1.0, 0.0),
            v(1.0, -1.0, 0.0),
            v(1.0, 1.0, 0.0),
            v(-1.0, 1.0, 0.0),
            v(1.0, 0.0, 1.0),
            z,
            v(-1.0, 0.0, 1.0),
            z,
        ];
        let p = Polygon::from_pool(&pool, 0, 4, true).unwrap();
        let n = p.shading_normal(&pool, v(0.0, 0.0, 0.0)).normalize_or_zero();
        assert!((n - z).length() < 1e-6, "{n:?}");
    }

    /// A gear outline of `n` vertices (teeth of two vertices at radius 1,
    /// gaps at 0.8) in the plane `z = 0`, turned by `turn`, in the pool.
    fn gear<S: Scalar>(n: usize, turn: f32) -> Vec<Vec3<S>> {
        (0..n)
            .map(|i| {
                let a = turn + core::f32::consts::TAU * i as f32 / n as f32;
                let r = if (i / 2) % 2 == 0 { 1.0 } else { 0.8 };
                Vec3::from_f32(r * libm::cosf(a), r * libm::sinf(a), 0.0)
            })
            .collect()
    }

    /// The crossings of packets of `W` rays straight down at the points
    /// `(x, y)` of `lanes`: `t` bits and hit flags per lane.
    fn packet_hits<S: Scalar, const W: usize>(
        p: &Polygon<S>,
        pool: &[Vec3<S>],
        lanes: &[(f32, f32)],
    ) -> Vec<(bool, u32)> {
        let mut out = Vec::new();
        for chunk in lanes.chunks(W) {
            let mut org = Vec3::<S>::ZERO.splat::<W>();
            let mut dir = org;
            for (i, &(x, y)) in chunk.iter().enumerate() {
                org.set_lane(i, Vec3::from_f32(x, y, 2.0));
                dir.set_lane(i, Vec3::from_f32(0.0, 0.0, -1.0));
            }
            let (ray, ok) = RayPacket::new(org, dir);
            let mut active = ok;
            for i in chunk.len()..W {
                active.set(i, false);
            }
            let r = p.roots(pool, &ray, Lanes::splat(S::ZERO), Lanes::splat(S::MAX), active);
            for i in 0..chunk.len() {
                out.push((r.hit0.get(i), r.t0.0[i].to_f32().to_bits()));
            }
        }
        out
    }

    /// Every hit lies inside `bounds`, also for outlines that are not
    /// planar: quads with one vertex lifted off the others' plane by up to
    /// five times their size (seeded), so that the plane's dominant axis
    /// changes, hit by rays from all around towards the quad. With the
    /// vertices' box alone, hits escape it.
    #[test]
    fn bounds_hold_every_hit_of_a_non_planar_outline() {
        let mut state = 0x6e6f_6e70;
        let mut rnd = || (crate::num::test_rng::splitmix64(&mut state) >> 40) as f32 / (1u64 << 24) as f32;
        let (mut hits, mut outside_vertex_box) = (0, 0);
        for _ in 0..60 {
            let lift = 10.0 * rnd();
            let pool = [v(-1.0, -1.0, lift), v(1.0, -1.0, 0.0), v(1.0, 1.0, 0.0), v(-1.0, 1.0, 0.0)];
            let p = poly(&pool);
            let (lo, hi) = p.bounds(&pool);
            let (vlo, vhi) = pool.iter().fold((pool[0], pool[0]), |(a, b), &q| (a.min_elem(q), b.max_elem(q)));
            for _ in 0..200 {
                let mut org = Vec3::<f32>::ZERO.splat::<8>();
                let mut dir = org;
                for l in 0..8 {
                    let o = v(40.0 * rnd() - 20.0, 40.0 * rnd() - 20.0, 40.0 * rnd() - 20.0);
                    let at = v(8.0 * rnd() - 4.0, 8.0 * rnd() - 4.0, 12.0 * rnd() - 6.0);
                    org.set_lane(l, o);
                    dir.set_lane(l, (at - o).normalize_or_zero());
                }
                let (ray, ok) = RayPacket::new(org, dir);
                let r = p.roots(&pool, &ray, Lanes::splat(0.0), Lanes::splat(f32::MAX), ok);
                for l in 0..8 {
                    if !r.hit0.get(l) {
                        continue;
                    }
                    hits += 1;
                    let q = ray.origin.lane(l) + ray.dir.lane(l).scale(r.t0.0[l]);
                    let slack = 1.0e-4 * (1.0 + q.max_abs());
                    let inside = |a: Vec3<f32>, b: Vec3<f32>| {
                        q.x >= a.x - slack
                            && q.x <= b.x + slack
                            && q.y >= a.y - slack
                            && q.y <= b.y + slack
                            && q.z >= a.z - slack
                            && q.z <= b.z + slack
                    };
                    assert!(inside(lo, hi), "hit {q:?} outside {lo:?}..{hi:?} (lift {lift})");
                    if !inside(vlo, vhi) {
                        outside_vertex_box += 1;
                    }
                }
            }
        }
        // Vacuous if no hit left the vertices' box.
        assert!(hits > 2000 && outside_vertex_box > 50, "{hits} hits, {outside_vertex_box} outside");
    }

    /// Many-sided outlines pass over edge blocks (`EDGE_BLOCKS`) and give
    /// every lane the crossings of testing every edge: at widths 1, 4, 8
    /// and 16, in `f32` and `Fixed32`, for coherent packets (seeded
    /// clusters) and for points on the lines through the vertices, where a
    /// block's bounds are met exactly. Widening a block's bins by one
    /// changes nothing; shrinking one is caught.
    #[test]
    fn edge_blocks_give_the_crossings_of_every_edge() {
        fn check<S: Scalar>(n: usize, turn: f32, seed: u64) {
            if !BLOCKS_HERE {
                return;
            }
            let pool = gear::<S>(n, turn);
            let p = Polygon::from_pool(&pool, 0, n as u32, false).unwrap();
            assert!(!p.is_convex());
            let every = Polygon { blocks: NO_BLOCKS, ..p };
            // Some block must be narrower than the whole outline, or the
            // test tests nothing.
            assert!(p.blocks.iter().any(|&[lo, hi]| hi - lo < 128), "{:?}", p.blocks);
            let mut state = seed;
            let mut rnd = || (crate::num::test_rng::splitmix64(&mut state) >> 40) as f32 / (1u64 << 24) as f32;
            let mut lanes = Vec::new();
            for _ in 0..400 {
                let (cx, cy) = (2.2 * rnd() - 1.1, 2.2 * rnd() - 1.1);
                let spread = [0.002, 0.02, 0.2][(rnd() * 3.0) as usize % 3];
                for _ in 0..16 {
                    lanes.push((cx + spread * (rnd() - 0.5), cy + spread * (rnd() - 0.5)));
                }
            }
            for v in &pool {
                let [x, y, _] = v.to_f32();
                for dx in [-0.3, -0.01, 0.0, 0.01, 0.3] {
                    lanes.push((x + dx, y));
                }
            }
            let reference = packet_hits::<S, 1>(&every, &pool, &lanes);
            assert!(reference.iter().filter(|h| h.0).count() > lanes.len() / 4);
            assert_eq!(packet_hits::<S, 1>(&p, &pool, &lanes), reference, "width 1");
            assert_eq!(packet_hits::<S, 4>(&p, &pool, &lanes), reference, "width 4");
            assert_eq!(packet_hits::<S, 8>(&p, &pool, &lanes), reference, "width 8");
            assert_eq!(packet_hits::<S, 16>(&p, &pool, &lanes), reference, "width 16");
            // Bins one wider on each side still hold every crossing.
            let mut wide = p;
            for b in wide.blocks.iter_mut() {
                *b = [b[0].saturating_sub(1), b[1].saturating_add(1)];
            }
            assert_eq!(packet_hits::<S, 8>(&wide, &pool, &lanes), reference, "wider blocks");
            // One bin narrower at the top of every block loses crossings.
            let mut narrow = p;
            for b in narrow.blocks.iter_mut() {
                b[1] = b[1].saturating_sub(1).max(b[0]);
            }
            assert_ne!(packet_hits::<S, 8>(&narrow, &pool, &lanes), reference, "narrower blocks");
        }
        check::<f32>(144, 0.0, 1);
        check::<f32>(100, 0.3, 2);
        check::<f32>(BLOCKED_EDGES as usize, 0.1, 3);
        check::<Fixed32>(144, 0.0, 4);
        check::<Fixed32>(61, 0.7, 5);
    }

    /// Outlines below `BLOCKED_EDGES` edges and convex ones keep no blocks;
    /// a polygon converted to another scalar gets its blocks over the
    /// converted pool (`SceneStore::add_similar`).
    #[test]
    fn edge_blocks_only_where_they_serve() {
        if !BLOCKS_HERE {
            return;
        }
        let few = gear::<f32>(BLOCKED_EDGES as usize - 2, 0.0);
        let p = Polygon::from_pool(&few, 0, few.len() as u32, false).unwrap();
        assert_eq!(p.blocks, NO_BLOCKS);
        let round: Vec<Vec3<f32>> = (0..64)
            .map(|i| {
                let a = core::f32::consts::TAU * i as f32 / 64.0;
                v(libm::cosf(a), libm::sinf(a), 0.0)
            })
            .collect();
        let p = Polygon::from_pool(&round, 0, 64, false).unwrap();
        assert!(p.is_convex());
        assert_eq!(p.blocks, NO_BLOCKS);
        let many = gear::<f32>(144, 0.0);
        let p = Polygon::from_pool(&many, 0, 144, false).unwrap();
        let f: Polygon<Fixed32> = p.similar(&Similarity::IDENTITY);
        assert_eq!(f.blocks, NO_BLOCKS);
        let fpool: Vec<Vec3<Fixed32>> = many.iter().map(|v| Vec3::from_f32(v.x, v.y, v.z)).collect();
        let built = Polygon::from_pool(&fpool, 0, 144, false).unwrap();
        assert_ne!(built.blocks, f.blocks);
        assert_eq!(f.with_edge_blocks(&fpool).blocks, built.blocks);
    }
}
