//! The Whitted integrator and plain ray casting, iterative and bounded, for
//! packets of any width.
//!
//! A packet's pending secondary rays (reflected, refracted) live on a
//! fixed-capacity stack whose capacity `D` is the largest depth the tracer
//! accepts: depth-first order leaves at most one pending sibling per level,
//! so `D` entries always suffice. Lanes stay bound to their pixel all the way
//! down; a lane that finishes (misses, runs out of depth or of weight) simply
//! drops out of the packet's mask, and a packet with no lanes left is not
//! traced.
//!
//! Determinism: every lane performs exactly the operations the width-1 tracer
//! performs for it, in the same order (contributions are added in the same
//! depth-first order, lights in scene order), so the result does not depend
//! on the packet width.

use crate::geom::ray::RayPacket;
use crate::geom::vec3::{Vec3, Vec3xW};
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;
use crate::query::cull::{Candidates, ShadowCull, ALL};
use crate::query::{Accelerator, BruteForce, Hit, PacketJob, SceneMismatch};
use crate::scene::{Material, Primitive, SceneView};
use heapless::Vec as HVec;

/// Whether a single ray's shadow query is one out-of-line call, the
/// shadow culling and the brute-force loop in line in it (RV32 without
/// hardware floats, where `ShadowCull` keeps its candidates in line and the
/// brute-force transmittance is in line too): there both were calls of their own, each saving a
/// dozen registers and spilling the ray, about 50 instructions a shadow
/// ray (the `fixed32` frame 97.5 M → 95.6 M instructions, `f32` the same).
/// Elsewhere it is not: on the Cortex-M0, whose fixed-point culling is in
/// line in the tracer, the `fixed32` frame took 0.53 M instructions more
/// and `f32` 0.42 M; on the Cortex-M4F `f32` 0.70 M more; on the
/// Cortex-M55 width 1 alone gained (0.07 M, `fixed32` 0.34 M).
const SHADOW_QUERY_APART: bool = cfg!(rv32_soft_float);

/// How rays are traced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Primary rays only: local shading at the first hit, no shadows, no
    /// secondary rays.
    Cast,
    /// Whitted ray tracing: shadows, reflection and refraction.
    Whitted,
}

/// Settings of the tracer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceSettings<S> {
    /// Cast or Whitted.
    pub mode: Mode,
    /// Maximum number of ray segments in a path (primary = 1); a ray beyond it
    /// contributes black.
    pub max_depth: u32,
    /// Secondary rays whose weight falls to this or below are not traced.
    pub min_weight: S,
}

impl<S: Scalar> Default for TraceSettings<S> {
    fn default() -> Self {
        TraceSettings { mode: Mode::Whitted, max_depth: 5, min_weight: S::MIN_WEIGHT }
    }
}

/// Numbers of rays traced, by kind (one per active lane), and of the
/// packets that carried them.
///
/// The ray counts do not depend on the packet width ([`RayStats::rays`]);
/// the packet counts do, and rays ÷ (packets × width) is how full the
/// packets were ([`RayStats::lanes_per_packet`]): what regrouping the live
/// lanes of several packets (compaction) could at best recover.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayStats {
    /// Camera rays.
    pub primary: u64,
    /// Shadow rays (one per lit lane and light).
    pub shadow: u64,
    /// Mirror-reflected rays.
    pub reflected: u64,
    /// Refracted rays.
    pub refracted: u64,
    /// Packets of camera rays traced (each with at least one active lane).
    pub primary_packets: u64,
    /// Packets of shadow rays traced (one per packet, light and lit lane set).
    pub shadow_packets: u64,
    /// Packets of reflected rays traced.
    pub reflected_packets: u64,
    /// Packets of refracted rays traced.
    pub refracted_packets: u64,
}

impl RayStats {
    /// All rays (saturating: the counters never panic).
    pub fn total(&self) -> u64 {
        self.primary.saturating_add(self.shadow).saturating_add(self.reflected).saturating_add(self.refracted)
    }
    /// Rays by kind: primary, shadow, reflected, refracted. The same for
    /// every packet width.
    pub fn rays(&self) -> [u64; 4] {
        [self.primary, self.shadow, self.reflected, self.refracted]
    }
    /// Packets by kind, in the order of [`RayStats::rays`].
    pub fn packets(&self) -> [u64; 4] {
        [self.primary_packets, self.shadow_packets, self.reflected_packets, self.refracted_packets]
    }
    /// Average active lanes per packet, by kind (order of
    /// [`RayStats::rays`]); 0 for a kind with no packets. At most the
    /// packet width.
    pub fn lanes_per_packet(&self) -> [f64; 4] {
        let (r, p) = (self.rays(), self.packets());
        let mut out = [0.0; 4];
        for i in 0..4 {
            if p[i] > 0 {
                out[i] = r[i] as f64 / p[i] as f64;
            }
        }
        out
    }
    /// Counts one packet of `n` active rays into `rays` and `packets` (a
    /// packet with no active lane is not a packet). Wrapping, which never
    /// panics: a counter would wrap after 2⁶⁴ rays, 585 years at a billion
    /// rays a second, and on 32-bit cores a saturating 64-bit add at every
    /// packet cost the Cortex-M0 `fixed32` frame 1 % of its instructions.
    fn tally(rays: &mut u64, packets: &mut u64, n: u64) {
        *rays = rays.wrapping_add(n);
        *packets = packets.wrapping_add(u64::from(n > 0));
    }
    /// Counts a packet of `n` camera rays.
    pub(crate) fn add_primary(&mut self, n: u64) {
        Self::tally(&mut self.primary, &mut self.primary_packets, n);
    }
    /// Adds another tally to this one (saturating).
    pub fn merge(&mut self, o: &RayStats) {
        self.primary = self.primary.saturating_add(o.primary);
        self.shadow = self.shadow.saturating_add(o.shadow);
        self.reflected = self.reflected.saturating_add(o.reflected);
        self.refracted = self.refracted.saturating_add(o.refracted);
        self.primary_packets = self.primary_packets.saturating_add(o.primary_packets);
        self.shadow_packets = self.shadow_packets.saturating_add(o.shadow_packets);
        self.reflected_packets = self.reflected_packets.saturating_add(o.reflected_packets);
        self.refracted_packets = self.refracted_packets.saturating_add(o.refracted_packets);
    }
}

/// Why a tracer could not be made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraceError {
    /// The settings ask for a depth of 0, or more than the tracer's stack
    /// holds.
    Depth {
        /// The depth asked for.
        requested: u32,
        /// The largest depth this tracer supports (its `D`).
        supported: u32,
    },
    /// The accelerator was built for another scene.
    Accelerator(SceneMismatch),
}

impl core::fmt::Display for TraceError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            TraceError::Depth { requested, supported } => {
                write!(f, "depth {requested} not supported (1 to {supported})")
            }
            TraceError::Accelerator(m) => m.fmt(f),
        }
    }
}

impl core::error::Error for TraceError {}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RayKind {
    Primary,
    Reflected,
    Refracted,
}

/// A packet waiting on the stack.
#[derive(Clone, Copy)]
struct Pending<S, const W: usize> {
    ray: RayPacket<S, W>,
    /// Weight of this ray's contribution to its pixel.
    weight: Lanes<S, W>,
    active: Mask<W>,
    depth: u32,
    kind: RayKind,
}

/// What shading needs at the hit point of each lane.
pub struct SurfacePacket<S, const W: usize> {
    /// Hit points.
    pub point: Vec3xW<S, W>,
    /// Geometric normal, unit, turned to face the incoming ray.
    pub geometric: Vec3xW<S, W>,
    /// Shading normal, unit, on the same side as `geometric`.
    pub shading: Vec3xW<S, W>,
    /// Lanes where the ray arrives on the outer side of the surface.
    pub entering: Mask<W>,
}

/// A tracer over one scene, querying it through the accelerator `A`, with
/// a bounded stack of `D` pending packets (so depths 1 to `D` are
/// supported).
#[derive(Clone, Copy, Debug)]
pub struct Tracer<'a, S, A = BruteForce, const D: usize = 8> {
    scene: SceneView<'a, S>,
    accel: A,
    settings: TraceSettings<S>,
    /// Whether local shading's products take [`Scalar::mul_small`] (see
    /// [`small_shading`]).
    small_shading: bool,
}

/// Whether every product of local shading (`Tracer::local`) has factors at
/// most 4 in magnitude, so that [`Scalar::mul_small`] is that product bit for
/// bit: true when every material's colour, `Ka`, `Kd`, `Ks` and `Kt` and
/// every light's colour lie in `[−1, 1]` (NFF's colours and weights do).
/// Then, for a lit lane, with unit vectors the tracer made (`N·L` at most
/// `1 + 2⁻¹²`): `Ka·colour`, `Kd·(N·L)` and `colour·diffuse` are at most
/// about 1, the Phong term `Ks·max(0, R·V)^n` at most 1, so `shade` at most
/// about 2, its product with the light's colour at most about 2, and the
/// transmittance (1 times each crossed occluder's `Kt`) at most 1. A scalar
/// of unlimited range has no other product ([`Scalar::LIMITED_RANGE`]).
///
/// With at most [`SMALL_SHADING_LIGHTS`] lights its sums are bounded too,
/// and take [`Scalar::add_small`] (sums at most 64 in magnitude): `shade`
/// at most about 2, and the local colour, ambient plus one such term per
/// light, at most about `1 + 2·16`.
fn small_shading<S: Scalar>(scene: &SceneView<'_, S>) -> bool {
    let unit = |v: S| v.abs() <= S::ONE;
    let unit3 = |v: Vec3<S>| unit(v.x) && unit(v.y) && unit(v.z);
    S::LIMITED_RANGE
        && scene.lights().len() <= SMALL_SHADING_LIGHTS
        && scene.materials().iter().all(|m| unit3(m.color) && unit(m.ka) && unit(m.kd) && unit(m.ks) && unit(m.kt))
        && scene.lights().iter().all(|l| unit3(l.color))
}

/// Most lights for which local shading takes its small products and sums
/// (see [`small_shading`]).
const SMALL_SHADING_LIGHTS: usize = 16;

impl<'a, S: Scalar, const D: usize> Tracer<'a, S, BruteForce, D> {
    /// A tracer that tests every primitive ([`BruteForce`]); errors if
    /// `settings.max_depth` is 0 or exceeds `D`.
    pub fn new(scene: SceneView<'a, S>, settings: TraceSettings<S>) -> Result<Self, TraceError> {
        Self::with_accelerator(scene, BruteForce, settings)
    }
}

impl<'a, S: Scalar, A: Accelerator<S>, const D: usize> Tracer<'a, S, A, D> {
    /// A tracer querying `scene` through `accel` (for example a
    /// [`BvhView`](crate::query::BvhView)); errors if `settings.max_depth`
    /// is 0 or exceeds `D`, or if `accel` was built for another scene.
    pub fn with_accelerator(scene: SceneView<'a, S>, accel: A, settings: TraceSettings<S>) -> Result<Self, TraceError> {
        if settings.max_depth == 0 || settings.max_depth as usize > D {
            return Err(TraceError::Depth { requested: settings.max_depth, supported: D as u32 });
        }
        accel.check(&scene).map_err(TraceError::Accelerator)?;
        let small_shading = small_shading(&scene);
        Ok(Tracer { scene, accel, settings, small_shading })
    }

    /// The same tracer with its accelerator replaced by `f(accel)`, which
    /// must answer every query exactly as the old one did (the dispatcher
    /// wraps accelerators in copies compiled for other instruction sets).
    pub fn map_accelerator<B: Accelerator<S>>(self, f: impl FnOnce(A) -> B) -> Tracer<'a, S, B, D> {
        Tracer { scene: self.scene, accel: f(self.accel), settings: self.settings, small_shading: self.small_shading }
    }

    /// The scene traced.
    pub fn scene(&self) -> &SceneView<'a, S> {
        &self.scene
    }
    /// The accelerator queries go through.
    pub fn accelerator(&self) -> &A {
        &self.accel
    }
    /// The nearest hit of each active ray in `(t_min, t_max)` (see
    /// [`Accelerator::closest_hit`]).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn closest_hit<const W: usize>(
        &self,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Hit<S, W> {
        self.accel.closest_hit(&self.scene, ray, t_min, t_max, active)
    }
    /// [`Tracer::closest_hit`] for rays that can hit only `candidates` (see
    /// [`Accelerator::closest_hit_among`]).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn closest_hit_among<const W: usize>(
        &self,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
        candidates: Candidates,
    ) -> Hit<S, W> {
        self.accel.closest_hit_among(&self.scene, ray, t_min, t_max, active, candidates)
    }
    /// The settings.
    pub fn settings(&self) -> &TraceSettings<S> {
        &self.settings
    }

    /// Surface data at the closest hits of `ray` (lanes outside `hit.mask`
    /// hold zeros).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn surface<const W: usize>(&self, ray: &RayPacket<S, W>, hit: &Hit<S, W>) -> SurfacePacket<S, W> {
        self.surface_and_materials(ray, hit).0
    }

    /// Surface data and materials at the closest hits, as packet code: one
    /// pass per distinct primitive among the hit lanes (in a coherent
    /// packet, one or two), each running that primitive's packet normal
    /// kernel and splatting its material under the mask of the lanes that
    /// share it. A lane goes through exactly the operations the one-ray
    /// tracer performs for it, so the bits do not depend on the width.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn surface_and_materials<const W: usize>(
        &self,
        ray: &RayPacket<S, W>,
        hit: &Hit<S, W>,
    ) -> (SurfacePacket<S, W>, Materials<S, W>) {
        let point = ray.at(hit.t);
        let zero = Vec3::new(Lanes::zero(), Lanes::zero(), Lanes::zero());
        let mut ng = zero;
        let mut ns = zero;
        let mut mat = Materials::empty();
        let prims = self.scene.primitives();
        let pool = self.scene.vertices();
        let mut remaining = hit.mask;
        while let Some(first) = remaining.first_set() {
            // The lanes that hit the same primitive as the first remaining one.
            let k = hit.prim.get(first).copied().unwrap_or(u32::MAX);
            let same = remaining & Mask::from_eq_u32(&hit.prim, k);
            remaining = remaining.and_not(same);
            let Some(p) = prims.get(k as usize) else { continue };
            // Unit geometric normal (zero where it has no length).
            let g = p.shape.unit_normals(&point);
            ng = Vec3xW::select(same, g, ng);
            // Shading normal: the geometric one, except on patches, whose
            // interpolation runs per lane (rare, and branchy by nature).
            let s = if p.shape.has_shading_normals() { self.patch_normals(p, pool, &point, &g, same) } else { g };
            ns = Vec3xW::select(same, s, ns);
            mat.splat(same, &self.scene.material_of(k));
        }
        // Turn both normals to face the ray (visibility is two-sided).
        // (Unit vectors, or a zero normal: products of small factors. Here
        // and below, the small forms only where they differ, in a scalar
        // of limited range: `f32` keeps the code it was measured with.)
        let cos = if S::LIMITED_RANGE { ng.dot_sparse_small(ray.dir) } else { ng.dot_sparse(ray.dir) };
        let entering = cos.le(Lanes::zero());
        let flip = !entering;
        // (In a scalar of limited range a negation saturates, about four
        // instructions a component: none where no lane turns.)
        let (geometric, shading) = if S::LIMITED_RANGE && flip.none() {
            (ng, ns)
        } else {
            (Vec3xW::select(flip, -ng, ng), Vec3xW::select(flip, -ns, ns))
        };
        let surf = SurfacePacket { point, geometric, shading, entering };
        (surf, mat)
    }

    /// Unit interpolated normals of patch `p` in the lanes `m` (falling back
    /// to the unit geometric normal `g` where the interpolation has no
    /// length).
    #[inline(never)]
    fn patch_normals<const W: usize>(
        &self,
        p: &Primitive<S>,
        pool: &[Vec3<S>],
        point: &Vec3xW<S, W>,
        g: &Vec3xW<S, W>,
        m: Mask<W>,
    ) -> Vec3xW<S, W> {
        let mut out = *g;
        for l in 0..W {
            if !m.get(l) {
                continue;
            }
            let gl = g.lane(l);
            let s = p.shape.shading_normal(pool, point.lane(l), gl).normalize_or_zero();
            out.set_lane(l, if s == Vec3::ZERO { gl } else { s });
        }
        out
    }

    /// Traces a packet of rays (unit directions) and returns the linear
    /// colour of each active lane (zero elsewhere). The work runs through
    /// the accelerator ([`Accelerator::run`]), so a renderer has one
    /// compiled copy of the tracer however many places call this.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn trace<const W: usize>(&self, ray: &RayPacket<S, W>, active: Mask<W>, stats: &mut RayStats) -> Vec3xW<S, W> {
        self.trace_among(ray, active, ALL, None, stats)
    }

    /// [`Tracer::trace`] for camera rays that can hit only the primitives
    /// in `candidates` (see [`Accelerator::closest_hit_among`]; the
    /// renderer's screen culling, [`crate::query::cull`]): the same bits,
    /// fewer tests. Shadow, reflected and refracted rays test the
    /// primitives `shadows` says they can reach (every primitive without
    /// it).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn trace_among<const W: usize>(
        &self,
        ray: &RayPacket<S, W>,
        active: Mask<W>,
        candidates: Candidates,
        shadows: Option<&ShadowCull<S>>,
        stats: &mut RayStats,
    ) -> Vec3xW<S, W> {
        self.accel.run(TraceJob { tracer: self, ray, active, candidates, shadows, stats })
    }

    /// [`Tracer::trace_among`]'s work.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn trace_here<const W: usize>(
        &self,
        ray: &RayPacket<S, W>,
        active: Mask<W>,
        candidates: Candidates,
        shadows: Option<&ShadowCull<S>>,
        stats: &mut RayStats,
    ) -> Vec3xW<S, W> {
        let zero = Lanes::<S, W>::zero();
        let mut color = Vec3::new(zero, zero, zero);
        let mut stack: HVec<Pending<S, W>, D> = HVec::new();
        // The camera packet first, then the secondary packets its hits
        // push. The camera packet is not pushed itself: that copied it onto
        // the stack and back (136 bytes at 4 lanes, a `memcpy` call each
        // way on the Cortex-M55).
        let mut p = Pending { ray: *ray, weight: Lanes::splat(S::ONE), active, depth: 1, kind: RayKind::Primary };
        let whitted = self.settings.mode == Mode::Whitted;
        let bg = self.scene.background();
        loop {
            // One packet's work; `break 'packet` ends it early.
            'packet: {
                let n = p.active.count() as u64;
                match p.kind {
                    RayKind::Primary => stats.add_primary(n),
                    RayKind::Reflected => RayStats::tally(&mut stats.reflected, &mut stats.reflected_packets, n),
                    RayKind::Refracted => RayStats::tally(&mut stats.refracted, &mut stats.refracted_packets, n),
                }
                // Camera rays test only their candidates, reflected and
                // refracted rays the primitives whose spheres they reach.
                let among = match (p.kind, shadows) {
                    (RayKind::Primary, _) => candidates,
                    (_, Some(c)) => c.reach_candidates(&p.ray, p.active),
                    (_, None) => ALL,
                };
                let hit =
                    self.accel.closest_hit_among(&self.scene, &p.ray, zero, Lanes::splat(S::MAX), p.active, among);
                // Rays that hit nothing see the background.
                let miss = p.active.and_not(hit.mask);
                if miss.any() {
                    let w = Lanes::select(miss, p.weight, zero);
                    color = color + bg.splat::<W>().scale(w);
                }
                if hit.mask.none() {
                    break 'packet;
                }
                let (surf, mat) = self.surface_and_materials(&p.ray, &hit);
                // The offset of rays leaving the hit points (shadow, reflected,
                // refracted), once per hit: `eps` scales with the coordinates,
                // `off` is the geometric normal times it.
                let eps = offset_scale(&surf.point);
                let off = surf.geometric.scale_sparse(eps);
                // (A constant test first: scalars of unlimited range have one
                // copy, and so does the Armv6-M image built for size, where
                // the second took about 4 KB.)
                let small_copy = S::LIMITED_RANGE && !cfg!(all(armv6m, not(armv6m_inline_mul)));
                let local = if small_copy && self.small_shading {
                    self.local::<W, true>(&p.ray, &hit, &surf, &mat, (eps, &off), whitted, shadows, stats)
                } else {
                    self.local::<W, false>(&p.ray, &hit, &surf, &mat, (eps, &off), whitted, shadows, stats)
                };
                // Local light, weighted by (1 − Kt) in Whitted mode.
                let w_local = if whitted { p.weight * (Lanes::splat(S::ONE) - mat.kt) } else { p.weight };
                let w_local = Lanes::select(hit.mask, w_local, zero);
                color = color + local.scale_unless_one(w_local);

                if !whitted || p.depth >= self.settings.max_depth {
                    break 'packet;
                }
                self.spawn(&p, &hit, &surf, &mat, &off, &mut stack);
            }
            match stack.pop() {
                Some(next) => p = next,
                None => break,
            }
        }
        color
    }

    /// Local shading (ambient, diffuse, Phong highlight) of the hit lanes,
    /// with shadow rays in Whitted mode; with `SMALL` (the scene's
    /// [`small_shading`]) its products by material and light colours and
    /// weights are [`Scalar::mul_small`]s, the same bits.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    // Private and inlined: the arguments are the packet's state at one
    // bounce, which a struct would only carry here to be unpacked again.
    #[allow(clippy::too_many_arguments)]
    fn local<const W: usize, const SMALL: bool>(
        &self,
        ray: &RayPacket<S, W>,
        hit: &Hit<S, W>,
        surf: &SurfacePacket<S, W>,
        mat: &Materials<S, W>,
        (eps, off): (Lanes<S, W>, &Vec3xW<S, W>),
        shadows: bool,
        cull: Option<&ShadowCull<S>>,
        stats: &mut RayStats,
    ) -> Vec3xW<S, W> {
        let zero = Lanes::<S, W>::zero();
        // The products of colours and weights: with `SMALL` their short
        // forms (see `small_shading`). In a scalar of limited range through
        // `mul` and `scale` (both copies: the Cortex-M0's frame was 1.1 M
        // instructions shorter than with `Vec3`'s methods in the general
        // copy); `f32` keeps `Vec3`'s methods (through the closures, x86
        // compiled its shading differently, Whitted renders 1–3 % slower at
        // packets of 16).
        let mul = |a: Lanes<S, W>, b: Lanes<S, W>| if SMALL { a.mul_small(b) } else { a * b };
        let scale = |v: Vec3xW<S, W>, k: Lanes<S, W>| Vec3::new(mul(v.x, k), mul(v.y, k), mul(v.z, k));
        let add = |a: Lanes<S, W>, b: Lanes<S, W>| if SMALL { a.add_small(b) } else { a + b };
        let mut local = if S::LIMITED_RANGE { scale(mat.color, mat.ka) } else { mat.color.scale(mat.ka) };
        let shadow_origin = surf.point + *off;
        let lights = self.scene.lights();
        // The geometric normal is the shading one except on patches; where
        // every lane's are equal, so are their products with a light's
        // direction (worked out once per hit packet, not per light).
        let (g, n) = (&surf.geometric, &surf.shading);
        let flat = (g.x.eq_lanes(n.x) & g.y.eq_lanes(n.y) & g.z.eq_lanes(n.z)).all();
        for (li, light) in (0..lights.len()).zip(lights.iter()) {
            // Direction and distance to the light.
            let to_light = light.position.splat::<W>() - surf.point;
            let (l_dir, dist, ok) = to_light.normalize_with_length();
            // (Normals are often axis-aligned: `*_sparse` skips their
            // zero components' products in fixed point, the same bits.)
            // (Unit vectors the tracer made: products of small factors.)
            let n_dot_l = surf.shading.dot_sparse_small(l_dir);
            let g_dot_l = if flat { n_dot_l } else { surf.geometric.dot_sparse_small(l_dir) };
            // Only lights on the lit side of both the geometric and the shading surface.
            let lit = hit.mask & ok & n_dot_l.gt(zero) & g_dot_l.gt(zero);
            if lit.none() {
                continue;
            }
            let trans = if shadows {
                RayStats::tally(&mut stats.shadow, &mut stats.shadow_packets, lit.count() as u64);
                let shadow = RayPacket { origin: shadow_origin, dir: l_dir };
                // Only the primitives some of these rays can reach.
                if SHADOW_QUERY_APART && W == 1 {
                    self.shadow_transmittance_apart(cull, li, &shadow, eps, dist, lit)
                } else {
                    let among = cull.map_or(ALL, |c| c.candidates_from(li, &shadow_origin, &l_dir, eps, lit));
                    self.accel.transmittance_among(&self.scene, &shadow, zero, dist, lit, among)
                }
            } else {
                Lanes::select(lit, Lanes::splat(S::ONE), zero)
            };
            let lit = lit & trans.gt(zero);
            if lit.none() {
                continue;
            }
            // Phong: R = 2(N·L)N − L, highlight Ks·max(0, R·V)^shine, for
            // the lanes with a specular coefficient.
            let shiny = lit & mat.ks.ne_lanes(zero);
            let spec = if shiny.any() {
                // (N a unit vector, N·L at most 1 + 2⁻¹².)
                let r = if S::LIMITED_RANGE {
                    surf.shading.scale_sparse_small(n_dot_l.mul_small(Lanes::splat(S::TWO))) - l_dir
                } else {
                    surf.shading.scale_sparse(n_dot_l * S::TWO) - l_dir
                };
                // (R is at most 3 in each component, V a unit vector.)
                // (The view vector −d here, where it is used: most hits
                // have no highlight.)
                let view = -ray.dir;
                let r_dot_v = if S::LIMITED_RANGE { r.dot_small(view) } else { r.dot(view) };
                // The highlight as lane code: the power of every lane at once
                // (a branch-free `powf`), kept where it applies.
                let highlight = shiny & r_dot_v.gt(zero);
                if highlight.any() {
                    Lanes::select(highlight, mat.ks * r_dot_v.min(Lanes::splat(S::ONE)).powf(mat.shine), zero)
                } else {
                    zero
                }
            } else {
                zero
            };
            let diffuse = if S::LIMITED_RANGE { mul(mat.kd, n_dot_l) } else { mat.kd * n_dot_l };
            let shade = if S::LIMITED_RANGE { scale(mat.color, diffuse) } else { mat.color.scale(diffuse) };
            let shade = if S::LIMITED_RANGE {
                Vec3::new(add(shade.x, spec), add(shade.y, spec), add(shade.z, spec))
            } else {
                Vec3::new(shade.x + spec, shade.y + spec, shade.z + spec)
            };
            let lc = light.color.splat::<W>();
            let contrib = if S::LIMITED_RANGE {
                Vec3::new(mul(shade.x, lc.x), mul(shade.y, lc.y), mul(shade.z, lc.z))
            } else {
                shade.mul_elem(lc)
            };
            // Unshadowed lanes carry exactly 1 (x·1 = x in every scalar): skip
            // the three products when no lit lane is partly shadowed (unlit
            // lanes are dropped below).
            let partly = lit.and_not(trans.eq_lanes(Lanes::splat(S::ONE)));
            let contrib = if partly.none() {
                contrib
            } else if S::LIMITED_RANGE {
                scale(contrib, trans)
            } else {
                contrib.scale(trans)
            };
            let contrib = Vec3xW::select(lit, contrib, Vec3::new(zero, zero, zero));
            local = if S::LIMITED_RANGE {
                Vec3::new(add(local.x, contrib.x), add(local.y, contrib.y), add(local.z, contrib.z))
            } else {
                local + contrib
            };
        }
        Vec3xW::select(hit.mask, local, Vec3::new(zero, zero, zero))
    }

    /// The transmittance of the shadow rays `shadow` (from the hit points
    /// moved off by at most `eps`, towards light `light` at distances
    /// `dist`) in the lanes `lit`, as one out-of-line call (see
    /// [`SHADOW_QUERY_APART`]): the candidates the shadow culling leaves
    /// them ([`ShadowCull::candidates_from`], in line there), then the
    /// accelerator's transmittance among those, in line too.
    #[inline(never)]
    fn shadow_transmittance_apart<const W: usize>(
        &self,
        cull: Option<&ShadowCull<S>>,
        light: usize,
        shadow: &RayPacket<S, W>,
        eps: Lanes<S, W>,
        dist: Lanes<S, W>,
        lit: Mask<W>,
    ) -> Lanes<S, W> {
        let among = cull.map_or(ALL, |c| c.candidates_from(light, &shadow.origin, &shadow.dir, eps, lit));
        self.accel.transmittance_among(&self.scene, shadow, Lanes::zero(), dist, lit, among)
    }

    /// Pushes the reflected and refracted packets of a hit packet.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn spawn<const W: usize>(
        &self,
        p: &Pending<S, W>,
        hit: &Hit<S, W>,
        surf: &SurfacePacket<S, W>,
        mat: &Materials<S, W>,
        off: &Vec3xW<S, W>,
        stack: &mut HVec<Pending<S, W>, D>,
    ) {
        let zero = Lanes::<S, W>::zero();
        let one = Lanes::<S, W>::splat(S::ONE);
        let d = p.ray.dir;
        let n = surf.shading;
        // cos θi = −d·N (N faces the ray).
        // (Both unit vectors the tracer made: products of small factors.)
        let cos_i = -(if S::LIMITED_RANGE { n.dot_sparse_small(d) } else { n.dot_sparse(d) });
        // Relative index η = n₁/n₂: entering goes from outside (1) into the material.
        let has_t = hit.mask & mat.kt.gt(zero);
        // η, k and the transmitted weight only matter where there is
        // transmission: without any, no division and no products (and the
        // same weights: `x + 0` is `x` for the non-negative weights).
        let (eta, k, tir, w_refl, w_refr) = if has_t.any() {
            let ior = mat.ior;
            let eta = Lanes::select(surf.entering, one.div_nonzero(ior), ior);
            // k = 1 − η²(1 − cos²θi); negative means total internal reflection.
            let k = one - eta * eta * (one - cos_i.square());
            let tir = has_t & k.lt(zero);
            let w_refl = p.weight * mat.kr + Lanes::select(tir, p.weight * mat.kt, zero);
            let w_refr = Lanes::select(has_t.and_not(tir), p.weight * mat.kt, zero);
            (eta, k, tir, w_refl, w_refr)
        } else {
            (one, zero, Mask::splat(false), p.weight * mat.kr + zero, zero)
        };
        let min_w = Lanes::splat(self.settings.min_weight);
        let refl = hit.mask & w_refl.gt(min_w);
        let refr = has_t.and_not(tir) & w_refr.gt(min_w);

        // Refracted: T = η d + (η cos θi − √k) N, leaving from the far side.
        if refr.any() {
            let sq = Lanes::select(refr, k, zero).sqrt();
            let t_dir = d.scale(eta) + n.scale_sparse(eta * cos_i - sq);
            let (t_dir, ok) = t_dir.normalize();
            let _ = stack.push(Pending {
                ray: RayPacket { origin: surf.point - *off, dir: t_dir },
                weight: Lanes::select(refr, w_refr, zero),
                active: refr & ok,
                depth: p.depth.saturating_add(1),
                kind: RayKind::Refracted,
            });
        }
        // Reflected: R = d + 2 cos θi N, leaving from the near side.
        if refl.any() {
            let r_dir = if S::LIMITED_RANGE {
                d + n.scale_sparse_small(cos_i.mul_small(Lanes::splat(S::TWO)))
            } else {
                d + n.scale_sparse(cos_i * S::TWO)
            };
            let (r_dir, ok) = r_dir.normalize();
            let _ = stack.push(Pending {
                ray: RayPacket { origin: surf.point + *off, dir: r_dir },
                weight: Lanes::select(refl, w_refl, zero),
                active: refl & ok,
                depth: p.depth.saturating_add(1),
                kind: RayKind::Reflected,
            });
        }
    }
}

/// One packet's trace, as a job an accelerator runs.
struct TraceJob<'t, 'a, 'r, 's, S, A, const D: usize, const W: usize> {
    tracer: &'t Tracer<'a, S, A, D>,
    ray: &'r RayPacket<S, W>,
    active: Mask<W>,
    candidates: Candidates,
    shadows: Option<&'r ShadowCull<S>>,
    stats: &'s mut RayStats,
}

impl<S: Scalar, A: Accelerator<S>, const D: usize, const W: usize> PacketJob for TraceJob<'_, '_, '_, '_, S, A, D, W> {
    type Output = Vec3xW<S, W>;
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn run(self) -> Vec3xW<S, W> {
        self.tracer.trace_here(self.ray, self.active, self.candidates, self.shadows, self.stats)
    }
}

/// Size of the offset that moves secondary-ray origins off a surface:
/// `RAY_EPSILON · (1 + max|P|)`, so it scales with the coordinates' magnitude.
#[inline(always)]
fn offset_scale<S: Scalar, const W: usize>(p: &Vec3xW<S, W>) -> Lanes<S, W> {
    let m = p.x.abs().max(p.y.abs()).max(p.z.abs());
    (m + S::ONE) * S::RAY_EPSILON
}

/// Material parameters gathered per lane.
struct Materials<S, const W: usize> {
    color: Vec3xW<S, W>,
    ka: Lanes<S, W>,
    kd: Lanes<S, W>,
    ks: Lanes<S, W>,
    shine: Lanes<S, W>,
    kr: Lanes<S, W>,
    kt: Lanes<S, W>,
    ior: Lanes<S, W>,
}

impl<S: Scalar, const W: usize> Materials<S, W> {
    /// No material in any lane (the index of refraction 1, everything else 0).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn empty() -> Self {
        let z = Lanes::zero();
        Materials { color: Vec3::new(z, z, z), ka: z, kd: z, ks: z, shine: z, kr: z, kt: z, ior: Lanes::splat(S::ONE) }
    }

    /// Sets material `m` in the lanes `lanes`.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn splat(&mut self, lanes: Mask<W>, m: &Material<S>) {
        let put = |v: S, old: Lanes<S, W>| Lanes::select(lanes, Lanes::splat(v), old);
        self.color = Vec3xW::select(lanes, m.color.splat(), self.color);
        self.ka = put(m.ka, self.ka);
        self.kd = put(m.kd, self.kd);
        self.ks = put(m.ks, self.ks);
        self.shine = put(m.shine, self.shine);
        self.kr = put(m.kr, self.kr);
        self.kt = put(m.kt, self.kt);
        self.ior = put(m.ior, self.ior);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::camera::Camera;
    use crate::num::fixed32::Fixed32;
    use crate::num::fixed64::Fixed;
    use crate::scene::Scene;

    type Small<S> = Scene<S, 8, 8, 8, 2>;

    /// A seeded scene in the box `[−1, 1]³`: a floor, spheres (one of them
    /// glass, so shadow rays cross it and weights split) and two lights,
    /// every colour and weight drawn from `[−lim, lim]` and a few set to
    /// the bounds themselves.
    fn scene<S: Scalar>(seed: u64, lim: f32) -> Small<S> {
        let mut x = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut w = || match (next() * 8.0) as u32 {
            0 => lim,
            1 => -lim,
            _ => (next() * 2.0 - 1.0) * lim,
        };
        let f = S::from_f32;
        let v = |x: f32, y: f32, z: f32| Vec3::from_f32(x, y, z);
        let mut s = Small::<S>::new();
        let mut mats = [0u16; 4];
        for (i, m) in mats.iter_mut().enumerate() {
            let material = Material {
                color: v(w(), w(), w()),
                ka: f(w()),
                kd: f(w()),
                ks: f(w()),
                shine: f(1.0 + 30.0 * i as f32),
                kr: f(w().abs()),
                kt: f(if i == 3 { 0.5 + 0.5 * w().abs() / lim.max(1.0) } else { 0.0 }),
                ior: f(1.5),
            };
            *m = s.add_material(material).unwrap();
        }
        s.add_plane(f(0.0), f(0.0), f(1.0), f(0.6), mats[0]).unwrap();
        s.add_sphere(v(-0.4, 0.2, -0.1), f(0.4), mats[1]).unwrap();
        s.add_sphere(v(0.5, 0.3, 0.0), f(0.3), mats[2]).unwrap();
        s.add_sphere(v(0.0, -0.3, 0.1), f(0.25), mats[3]).unwrap();
        s.add_light(v(-0.8, -0.9, 0.9), v(w(), w(), w())).unwrap();
        s.add_light(v(0.9, -0.5, 0.6), v(w(), w(), w())).unwrap();
        s
    }

    /// Every pixel's colour bits at width `W`, tracing with local shading's
    /// small products or without them.
    fn image<S: Scalar, const W: usize>(scene: &Small<S>, small: bool) -> std::vec::Vec<[S; 3]> {
        let mut tracer = Tracer::<S>::new(scene.view(), TraceSettings::default()).unwrap();
        tracer.small_shading = small;
        let v = |x: f32, y: f32, z: f32| Vec3::from_f32(x, y, z);
        let camera = Camera::new(v(0.0, -1.0, 0.5), v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0), 60.0, 24, 20).unwrap();
        let mut out = std::vec::Vec::new();
        let mut stats = RayStats::default();
        for y in 0..camera.height() {
            for x in (0..camera.width()).step_by(W) {
                let (ray, active) = camera.packet::<W>(x, y, camera.full_rect());
                let c = tracer.trace::<W>(&ray, active, &mut stats);
                for l in 0..W {
                    if active.get(l) {
                        out.push([c.x.0[l], c.y.0[l], c.z.0[l]]);
                    }
                }
            }
        }
        out
    }

    #[test]
    fn small_shading_needs_unit_colours_and_weights_in_a_limited_range() {
        assert!(small_shading(&scene::<Fixed32>(1, 1.0).view()));
        assert!(small_shading(&scene::<Fixed>(1, 1.0).view()));
        // Unlimited range: the products are the same operation.
        assert!(!small_shading(&scene::<f32>(1, 1.0).view()));
        let mut s = scene::<Fixed32>(1, 1.0);
        let m = Material { color: Vec3::from_f32(0.5, 1.01, 0.5), ..Material::diffuse(Vec3::from_f32(0.5, 0.5, 0.5)) };
        s.add_material(m).unwrap();
        assert!(!small_shading(&s.view()));
        assert!(!small_shading(&scene::<Fixed32>(1, 1.5).view()));
        // A light's colour.
        for (c, small) in [(-1.0, true), (-1.5, false)] {
            let mut s = Small::<Fixed32>::new();
            let m = s.add_material(Material::diffuse(Vec3::from_f32(0.5, 0.5, 0.5))).unwrap();
            s.add_sphere(Vec3::from_f32(0.0, 0.0, 0.0), Fixed32::from_f32(0.5), m).unwrap();
            s.add_light(Vec3::from_f32(0.0, 0.0, 0.9), Vec3::from_f32(0.2, 0.2, c)).unwrap();
            assert_eq!(small_shading(&s.view()), small, "{c}");
        }
        let mut t = scene::<Fixed32>(1, 1.0);
        let kt = Material { kt: Fixed32::from_f32(1.25), ..Material::diffuse(Vec3::from_f32(0.5, 0.5, 0.5)) };
        t.add_material(kt).unwrap();
        assert!(!small_shading(&t.view()));
    }

    /// Local shading's sums are bounded only for so many lights: past
    /// [`SMALL_SHADING_LIGHTS`], the general products and sums.
    #[test]
    fn small_shading_needs_at_most_so_many_lights() {
        let mut s = crate::scene::Scene::<Fixed32, 4, 4, 4, 32>::new();
        let m = s.add_material(Material::diffuse(Vec3::from_f32(0.5, 0.5, 0.5))).unwrap();
        s.add_sphere(Vec3::from_f32(0.0, 0.0, 0.0), Fixed32::from_f32(0.5), m).unwrap();
        // From no light to SMALL_SHADING_LIGHTS of them: the small forms.
        for i in 0..=SMALL_SHADING_LIGHTS {
            assert!(small_shading(&s.view()), "{i} lights");
            s.add_light(Vec3::from_f32(0.0, 0.0, 0.9 + i as f32), Vec3::from_f32(1.0, 1.0, 1.0)).unwrap();
        }
        // One more: the general ones.
        assert!(!small_shading(&s.view()));
    }

    /// The small products give the bits of the general ones wherever
    /// [`small_shading`] allows them, at widths 1 and 4, in both scalars of
    /// limited range.
    fn small_products_agree<S: Scalar>() {
        let mut lit = 0;
        for seed in 0..24 {
            let s = scene::<S>(seed, 1.0);
            assert!(small_shading(&s.view()));
            let general = image::<S, 1>(&s, false);
            assert_eq!(image::<S, 1>(&s, true), general, "seed {seed}, width 1");
            assert_eq!(image::<S, 4>(&s, true), image::<S, 4>(&s, false), "seed {seed}, width 4");
            lit += general.iter().filter(|c| c.iter().any(|v| *v != S::ZERO)).count();
        }
        // Not a comparison of black images.
        assert!(lit > 24 * 24 * 20 / 2, "{lit}");
    }

    #[test]
    fn small_shading_products_are_the_general_ones_in_fixed32() {
        small_products_agree::<Fixed32>();
    }

    #[test]
    fn small_shading_products_are_the_general_ones_in_fixed() {
        small_products_agree::<Fixed>();
    }
}
