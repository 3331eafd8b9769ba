//! Seeded property tests of the core:
//! - the hit point lies on the surface (residual evaluated in f64 with
//!   independent formulas);
//! - no nearer crossing exists, and a miss really misses (the surface's
//!   implicit function, sampled in f64 along the ray, changes sign only where
//!   the core reports a hit);
//! - widths 1, 4 and 8 give bit-identical hits, normals and final pixels on
//!   random rays and random scenes.

mod common;
use common::*;
use raypack::lanes::{Lanes, Mask};
use raypack::prelude::*;
use raypack::primitives::Shape;
use raypack::ray::{Ray, RayPacket};

type V = [f64; 3];
fn d3(v: Vec3<f32>) -> V {
    [v.x as f64, v.y as f64, v.z as f64]
}
fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V, b: V) -> V {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
fn len(a: V) -> f64 {
    dot(a, a).sqrt()
}
fn scale(a: V, s: f64) -> V {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// An implicit description of a primitive in f64, independent of the core's
/// kernels: `f(p)` changes sign across the surface, `valid(p)` says whether a
/// crossing at `p` belongs to the (clipped, finite) surface, and `dist(p)`
/// approximates the distance of `p` from the surface.
struct Implicit<'a> {
    shape: &'a Shape<f32>,
    pool: &'a [Vec3<f32>],
}

impl Implicit<'_> {
    fn f(&self, p: V) -> f64 {
        match self.shape {
            Shape::Sphere(s) => {
                let r = s.radius() as f64;
                let d = sub(p, d3(s.center()));
                dot(d, d) - r * r
            }
            Shape::Plane(pl) => dot(d3(pl.normal_vector()), p) + pl.offset() as f64,
            Shape::Polygon(pg) => {
                let v = pg.vertices(self.pool);
                let n = poly_normal(v);
                dot(n, sub(p, d3(v[0])))
            }
            Shape::AaBox(b) => {
                let (lo, hi) = (d3(b.min()), d3(b.max()));
                -(0..3).map(|a| (p[a] - lo[a]).min(hi[a] - p[a])).fold(f64::INFINITY, f64::min)
            }
            Shape::OrientedBox(b) => {
                let l = obox_local(b, p);
                let h = d3(b.half_extents());
                (0..3).map(|a| l[a].abs() - h[a]).fold(f64::NEG_INFINITY, f64::max)
            }
            Shape::Quadric(q) => {
                let [a, b, c, d, e, f, g, h, i, j] = q.coefficients().map(|x| x as f64);
                let [x, y, z] = p;
                a * x * x + b * y * y + c * z * z + d * x * y + e * x * z + f * y * z + g * x + h * y + i * z + j
            }
            Shape::Cone(cn) => {
                let (rad, _z, r) = cone_local(cn, p);
                rad * rad - r * r
            }
        }
    }

    /// Whether a crossing at `p` is part of the surface, with `margin` of
    /// slack that must be clearly satisfied (points too near a boundary are
    /// "unsure" and return None).
    fn valid(&self, p: V, margin: f64) -> Option<bool> {
        let inside_box = |lo: V, hi: V| {
            let m = (0..3).map(|a| (p[a] - lo[a]).min(hi[a] - p[a])).fold(f64::INFINITY, f64::min);
            if m > margin {
                Some(true)
            } else if m < -margin {
                Some(false)
            } else {
                None
            }
        };
        match self.shape {
            Shape::Polygon(pg) => {
                if pg.is_degenerate() {
                    return Some(false);
                }
                polygon_contains(pg.vertices(self.pool), p, margin)
            }
            Shape::Quadric(q) => match q.clip_box() {
                Some((lo, hi)) => inside_box(d3(lo), d3(hi)),
                None => Some(true),
            },
            Shape::Cone(cn) => {
                let (_, z, _) = cone_local(cn, p);
                let (b, _, a, _) = cn.ends();
                let h = len(sub(d3(a), d3(b)));
                if z > margin && z < h - margin {
                    Some(true)
                } else if z < -margin || z > h + margin {
                    Some(false)
                } else {
                    None
                }
            }
            _ => Some(true),
        }
    }

    /// Approximate distance from the surface (first order).
    fn dist(&self, p: V) -> f64 {
        match self.shape {
            Shape::Sphere(s) => (len(sub(p, d3(s.center()))) - s.radius() as f64).abs(),
            Shape::Quadric(q) => {
                let [a, b, c, d, e, f, g, h, i, _] = q.coefficients().map(|x| x as f64);
                let [x, y, z] = p;
                let grad =
                    [2.0 * a * x + d * y + e * z + g, 2.0 * b * y + d * x + f * z + h, 2.0 * c * z + e * x + f * y + i];
                self.f(p).abs() / len(grad).max(1e-12)
            }
            Shape::Cone(cn) => {
                let (rad, _, r) = cone_local(cn, p);
                (rad - r).abs()
            }
            _ => self.f(p).abs(),
        }
    }
}

fn poly_normal(v: &[Vec3<f32>]) -> V {
    // Newell's normal in f64.
    let mut n = [0.0; 3];
    for i in 0..v.len() {
        let a = d3(v[i]);
        let b = d3(v[(i + 1) % v.len()]);
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    scale(n, 1.0 / len(n))
}

/// Even-odd point-in-polygon in the polygon's own 2D frame; None within
/// `margin` of an edge.
fn polygon_contains(v: &[Vec3<f32>], p: V, margin: f64) -> Option<bool> {
    let n = poly_normal(v);
    let a = if n[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
    let u = cross(a, n);
    let u = scale(u, 1.0 / len(u));
    let w = cross(n, u);
    let o = d3(v[0]);
    let pts: Vec<(f64, f64)> = v.iter().map(|q| (dot(sub(d3(*q), o), u), dot(sub(d3(*q), o), w))).collect();
    let (px, py) = (dot(sub(p, o), u), dot(sub(p, o), w));
    let mut inside = false;
    for i in 0..pts.len() {
        let (ax, ay) = pts[i];
        let (bx, by) = pts[(i + 1) % pts.len()];
        // Distance from the edge segment.
        let (ex, ey) = (bx - ax, by - ay);
        let l2 = ex * ex + ey * ey;
        let t = if l2 > 0.0 { (((px - ax) * ex + (py - ay) * ey) / l2).clamp(0.0, 1.0) } else { 0.0 };
        let (cx, cy) = (ax + t * ex - px, ay + t * ey - py);
        if (cx * cx + cy * cy).sqrt() < margin {
            return None;
        }
        if (ay > py) != (by > py) && px < ax + (py - ay) * (bx - ax) / (by - ay) {
            inside = !inside;
        }
    }
    Some(inside)
}

fn obox_local(b: &raypack::primitives::OrientedBox<f32>, p: V) -> V {
    let (u, v, w) = b.axes();
    let r = sub(p, d3(b.center()));
    [dot(r, d3(u)), dot(r, d3(v)), dot(r, d3(w))]
}

/// (radial distance from the axis, axial coordinate, cone radius there).
fn cone_local(c: &raypack::primitives::Cone<f32>, p: V) -> (f64, f64, f64) {
    let (b, rb, a, ra) = c.ends();
    let axis = sub(d3(a), d3(b));
    let h = len(axis);
    let w = scale(axis, 1.0 / h);
    let rel = sub(p, d3(b));
    let z = dot(rel, w);
    let radial = len(sub(rel, scale(w, z)));
    (radial, z, rb as f64 + (ra as f64 - rb as f64) * z / h)
}

const KINDS: [&str; 9] =
    ["sphere", "plane", "convex polygon", "star polygon", "box", "oriented box", "quadric", "quadric", "cone"];

/// One primitive of kind `k` with random rays aimed near it; checks every
/// hit against the implicit description. Returns (hits, misses) checked.
fn check_kind(seed: u64, k: u32, rays: usize) -> (usize, usize) {
    let mut rng = Rng(seed);
    let mut scene = TestScene::new();
    scene.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
    random_shape(&mut rng, &mut scene, k, 0);
    let view = scene.view();
    let prim = &view.primitives()[0];
    let imp = Implicit { shape: &prim.shape, pool: view.vertices() };
    let (target, spread) = prim
        .shape
        .bounds(view.vertices())
        .map(|(lo, hi)| ((lo + hi).scale(0.5), (hi - lo).max_abs() * 0.6))
        .unwrap_or((Vec3::ZERO, 2.0));
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..rays {
        let o = rng.vec(-6.0, 6.0);
        let aim = target + rng.vec(-1.0, 1.0).scale(spread);
        let Some(ray) = Ray::single(o, aim - o) else { continue };
        let h = BruteForce.closest_hit(&view, &ray, Lanes::splat(0.0), Lanes::splat(f32::MAX), Mask::splat(true));
        let (po, pd) = (d3(ray.origin.lane(0)), d3(ray.dir.lane(0)));
        let at = |t: f64| add(po, scale(pd, t));
        let scale_of = 1.0 + len(po);
        // Sample the implicit function for robust sign changes before t_end.
        let t_end = if h.mask.get(0) { h.t.0[0] as f64 * (1.0 - 1e-4) - 1e-4 } else { 40.0 };
        let n = 4000;
        let mut prev = (1e-3, imp.f(at(1e-3)));
        for s in 1..=n {
            let t = 1e-3 + (t_end - 1e-3) * s as f64 / n as f64;
            let f = imp.f(at(t));
            if (prev.1 < 0.0) != (f < 0.0) && prev.1.abs() > 1e-9 && f.abs() > 1e-9 {
                // Bisect the crossing and ask whether it belongs to the surface.
                let (mut lo, mut hi) = (prev.0, t);
                for _ in 0..60 {
                    let m = 0.5 * (lo + hi);
                    if (imp.f(at(m)) < 0.0) == (prev.1 < 0.0) {
                        lo = m
                    } else {
                        hi = m
                    }
                }
                let tc = 0.5 * (lo + hi);
                // Crossings that graze the surface (tiny slope) are legitimately
                // lost to rounding; demand a clear crossing.
                let slope = (imp.f(at(tc + 1e-3)) - imp.f(at(tc - 1e-3))).abs();
                if imp.valid(at(tc), 1e-3 * scale_of) == Some(true) && slope > 1e-4 && (t_end - tc) > 1e-3 * scale_of {
                    panic!(
                        "{} (seed {seed}): crossing at t = {tc} before the reported {} (hit: {}), ray {:?} {:?}",
                        KINDS[k as usize],
                        h.t.0[0],
                        h.mask.get(0),
                        po,
                        pd
                    );
                }
            }
            prev = (t, f);
        }
        if h.mask.get(0) {
            hits += 1;
            let p = at(h.t.0[0] as f64);
            let tol =
                2e-5 * (scale_of + h.t.0[0] as f64) * if matches!(prim.shape, Shape::Quadric(_)) { 20.0 } else { 1.0 };
            let dist = imp.dist(p);
            assert!(
                dist <= tol,
                "{} (seed {seed}): hit point off the surface by {dist} (tol {tol})",
                KINDS[k as usize]
            );
            assert!(
                imp.valid(p, 1e-3 * scale_of) != Some(false),
                "{}: hit outside the finite surface",
                KINDS[k as usize]
            );
        } else {
            misses += 1;
        }
    }
    (hits, misses)
}

#[test]
fn hits_lie_on_the_surface_and_nothing_nearer_is_missed() {
    for k in 0..9u32 {
        let (mut hits, mut misses) = (0, 0);
        for seed in 0..12u64 {
            let (h, m) = check_kind(1000 * k as u64 + seed, k, 60);
            hits += h;
            misses += m;
        }
        // The rays are aimed at the primitive: the test must exercise both outcomes.
        assert!(hits > 50 && misses > 5, "{}: {hits} hits, {misses} misses", KINDS[k as usize]);
    }
}

#[test]
fn widths_give_identical_hits_and_normals() {
    let mut rng = Rng(7);
    for _ in 0..20 {
        let scene = random_scene(&mut rng, 18);
        let view = scene.view();
        let tracer: Tracer<f32> = Tracer::new(view, TraceSettings::default()).unwrap();
        for _ in 0..40 {
            let mut org = Vec3::new(Lanes::<f32, 8>::zero(), Lanes::zero(), Lanes::zero());
            let mut dir = org;
            for l in 0..8 {
                org.set_lane(l, rng.vec(-8.0, 8.0));
                dir.set_lane(l, rng.vec(-1.0, 1.0));
            }
            let (p8, m8) = RayPacket::new(org, dir);
            let h8 = tracer.closest_hit(&p8, Lanes::zero(), Lanes::splat(f32::MAX), m8);
            let s8 = tracer.surface(&p8, &h8);
            let mut st = RayStats::default();
            let c8 = tracer.trace(&p8, m8, &mut st);
            // Width 4: the two halves.
            for half in 0..2 {
                let mut o4 = Vec3::new(Lanes::<f32, 4>::zero(), Lanes::zero(), Lanes::zero());
                let mut d4 = o4;
                for l in 0..4 {
                    o4.set_lane(l, org.lane(4 * half + l));
                    d4.set_lane(l, dir.lane(4 * half + l));
                }
                let (p4, m4) = RayPacket::new(o4, d4);
                let c4 = tracer.trace(&p4, m4, &mut st);
                for l in 0..4 {
                    assert_eq!(c4.lane(l), c8.lane(4 * half + l));
                }
            }
            for l in 0..8 {
                let (p1, m1) = RayPacket::<f32, 1>::new(org.lane(l).splat(), dir.lane(l).splat());
                assert_eq!(m1.get(0), m8.get(l));
                let h1 = tracer.closest_hit(&p1, Lanes::zero(), Lanes::splat(f32::MAX), m1);
                assert_eq!(h1.mask.get(0), h8.mask.get(l));
                if !h1.mask.get(0) {
                    continue;
                }
                assert_eq!(h1.t.0[0].to_bits(), h8.t.0[l].to_bits());
                assert_eq!(h1.prim[0], h8.prim[l]);
                let s1 = tracer.surface(&p1, &h1);
                assert_eq!(s1.geometric.lane(0), s8.geometric.lane(l));
                assert_eq!(s1.shading.lane(0), s8.shading.lane(l));
                let c1 = tracer.trace(&p1, m1, &mut st);
                let (a, b) = (c1.lane(0), c8.lane(l));
                assert_eq!(
                    [a.x.to_bits(), a.y.to_bits(), a.z.to_bits()],
                    [b.x.to_bits(), b.y.to_bits(), b.z.to_bits()]
                );
                assert!(a.is_finite(), "non-finite colour {a:?}");
            }
        }
    }
}

#[test]
fn widths_and_tilings_give_identical_images() {
    let mut rng = Rng(42);
    for case in 0..24 {
        let scene = random_scene(&mut rng, 14 + case % 10);
        let view = scene.view();
        // Odd sizes, so packets hang over the image edges.
        let camera = random_camera(&mut rng, 37, 23);
        for mode in [Mode::Whitted, Mode::Cast] {
            let settings = TraceSettings { mode, max_depth: 1 + rng.below(8), ..TraceSettings::default() };
            for aov in [Aov::Color, Aov::Id, Aov::Normal, Aov::Depth] {
                if mode == Mode::Cast && aov != Aov::Color {
                    continue;
                }
                let (i1, s1) = render::<1>(&view, camera, settings, aov, 5);
                let (i4, s4) = render::<4>(&view, camera, settings, aov, 13);
                let (i8, s8) = render::<8>(&view, camera, settings, aov, 64);
                assert!(i1 == i4 && i1 == i8, "case {case}: {mode:?} {aov:?} images differ between widths");
                assert_eq!(s1.rays(), s4.rays());
                assert_eq!(s1.rays(), s8.rays());
                if aov == Aov::Id {
                    // The test is only meaningful if the scene is visible.
                    assert!(i1.iter().filter(|p| **p != [0, 0, 0]).count() > 20, "case {case}: empty image");
                }
            }
        }
    }
}

#[test]
fn trace_never_returns_nan_even_for_degenerate_rays() {
    let mut rng = Rng(99);
    let scene = random_scene(&mut rng, 30);
    let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
    let mut st = RayStats::default();
    // Zero-length and non-finite directions become inactive lanes, defined as black.
    let org = Vec3::new(Lanes([0.0f32, 1.0, f32::NAN, 0.0]), Lanes([0.0, 0.0, 0.0, f32::INFINITY]), Lanes([9.0; 4]));
    let dir =
        Vec3::new(Lanes([0.0f32, 0.0, 0.0, 0.0]), Lanes([0.0, f32::NAN, 0.0, 0.0]), Lanes([0.0, -1.0, -1.0, -1.0]));
    let (p, m) = RayPacket::new(org, dir);
    assert_eq!(m.to_array(), [false, false, false, false]);
    let c = tracer.trace(&p, m, &mut st);
    for l in 0..4 {
        assert_eq!(c.lane(l), Vec3::ZERO);
    }
    assert_eq!(st.primary, 0);
}

#[test]
fn packet_counts_bound_the_ray_counts_at_every_width() {
    // Rays by kind are the same at every width; packets carry 1 to W of
    // them, so packets ≤ rays ≤ W · packets, with equality at width 1.
    let scene = raypack::demo::demo_scene::<f32>().unwrap();
    let camera = raypack::demo::demo_camera::<f32>(40, 30).unwrap();
    let mut rng = Rng(99);
    let random = random_scene(&mut rng, 24);
    let random_cam = random_camera(&mut rng, 33, 17);
    for (what, view, cam) in [("demo", scene.view(), camera), ("random", random.view(), random_cam)] {
        for aov in [Aov::Color, Aov::Id] {
            let (_, s1) = render::<1>(&view, cam, TraceSettings::default(), aov, 16);
            let (_, s4) = render::<4>(&view, cam, TraceSettings::default(), aov, 16);
            let (_, s8) = render::<8>(&view, cam, TraceSettings::default(), aov, 16);
            assert_eq!(s1.packets(), s1.rays(), "{what} {aov:?}: width 1 packets carry one ray each");
            assert_eq!(s1.primary, (cam.width() * cam.height()) as u64);
            for (w, s) in [(4u64, s4), (8, s8)] {
                assert_eq!(s.rays(), s1.rays(), "{what} {aov:?} width {w}");
                for k in 0..4 {
                    let (r, p) = (s.rays()[k], s.packets()[k]);
                    assert!(p <= r && r <= w * p, "{what} {aov:?} width {w} kind {k}: {r} rays in {p} packets");
                    assert!(s.lanes_per_packet()[k] <= w as f64);
                }
                assert!(s.primary_packets < s1.primary_packets, "{what}: width {w} packs primary rays");
            }
            if aov == Aov::Color && what == "demo" {
                // Whitted mode traces shadow and secondary rays here.
                assert!(s8.shadow > 0 && s8.reflected + s8.refracted > 0, "{what}: {s8:?}");
            }
            let mut merged = s4;
            merged.merge(&s8);
            assert_eq!(merged.packets()[1], s4.shadow_packets + s8.shadow_packets);
        }
    }
}
