//! An independent, slow f64 Whitted tracer (its own intersection code for
//! every primitive kind, recursive, no packets) checks the core's renders of
//! the demo scene, which has every primitive kind, shadows, a mirror and a
//! glass sphere (reflection, refraction, total internal reflection).
//!
//! Only the scene *data* is shared (read through the public accessors); every
//! algorithm here is written separately, in f64, textbook-style. Pixels are
//! compared where the light path is stable: the reference traces the pixel
//! centre and four jittered rays (±0.05 pixel) and records the sequence of
//! primitives hit and shadow outcomes; where all five agree, the core must
//! match the reference within 1/255 in every channel. Near silhouettes and
//! shadow edges the path itself changes under tiny perturbations, and f32
//! versus f64 legitimately pick different sides.

use raypack::demo::{demo_camera, demo_scene};
use raypack::prelude::*;
use raypack::primitives::Shape;

type V = [f64; 3];
fn d3(v: Vec3<f32>) -> V {
    [v.x as f64, v.y as f64, v.z as f64]
}
fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn mul(a: V, s: f64) -> V {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V, b: V) -> V {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
fn norm(a: V) -> V {
    let l = dot(a, a).sqrt();
    if l > 0.0 {
        mul(a, 1.0 / l)
    } else {
        [0.0; 3]
    }
}

struct Reference<'a> {
    view: SceneView<'a, f32>,
}

impl Reference<'_> {
    fn pool(&self) -> &[Vec3<f32>] {
        self.view.vertices()
    }

    /// All crossings t > 0 of the ray with primitive `shape`, ascending.
    fn crossings(&self, shape: &Shape<f32>, o: V, d: V) -> Vec<f64> {
        let mut ts = match shape {
            Shape::Sphere(s) => {
                // Textbook: |o + td − c|² = r² with |d| = 1.
                let oc = sub(o, d3(s.center()));
                let b = dot(oc, d);
                let c = dot(oc, oc) - (s.radius() as f64).powi(2);
                let disc = b * b - c;
                if disc < 0.0 {
                    vec![]
                } else {
                    vec![-b - disc.sqrt(), -b + disc.sqrt()]
                }
            }
            Shape::Plane(p) => {
                let n = d3(p.normal_vector());
                let den = dot(n, d);
                if den == 0.0 {
                    vec![]
                } else {
                    vec![-(dot(n, o) + p.offset() as f64) / den]
                }
            }
            Shape::Polygon(pg) => {
                if pg.is_degenerate() {
                    return vec![];
                }
                let vs: Vec<V> = pg.vertices(self.pool()).iter().map(|v| d3(*v)).collect();
                let n = newell(&vs);
                let den = dot(n, d);
                if den == 0.0 {
                    return vec![];
                }
                let t = dot(n, sub(vs[0], o)) / den;
                if even_odd(&vs, n, add(o, mul(d, t))) {
                    vec![t]
                } else {
                    vec![]
                }
            }
            Shape::AaBox(b) => slabs(o, d, d3(b.min()), d3(b.max())),
            Shape::OrientedBox(b) => {
                let (u, v, w) = b.axes();
                let (u, v, w) = (d3(u), d3(v), d3(w));
                let r = sub(o, d3(b.center()));
                let lo = [dot(r, u), dot(r, v), dot(r, w)];
                let ld = [dot(d, u), dot(d, v), dot(d, w)];
                let h = d3(b.half_extents());
                slabs(lo, ld, mul(h, -1.0), h)
            }
            Shape::Quadric(q) => {
                let [a, b, c, dd, e, f, g, h, i, j] = q.coefficients().map(|x| x as f64);
                let qf = |p: V| {
                    a * p[0] * p[0]
                        + b * p[1] * p[1]
                        + c * p[2] * p[2]
                        + dd * p[0] * p[1]
                        + e * p[0] * p[2]
                        + f * p[1] * p[2]
                        + g * p[0]
                        + h * p[1]
                        + i * p[2]
                        + j
                };
                // Q(o + td) is quadratic in t: recover its coefficients by evaluation.
                let c0 = qf(o);
                let c1p = qf(add(o, d));
                let c1m = qf(sub(o, d));
                let qa = 0.5 * (c1p + c1m) - c0;
                let qb = 0.5 * (c1p - c1m);
                let mut ts = if qa.abs() < 1e-12 {
                    if qb == 0.0 {
                        vec![]
                    } else {
                        vec![-c0 / qb]
                    }
                } else {
                    let disc = qb * qb - 4.0 * qa * c0;
                    if disc < 0.0 {
                        vec![]
                    } else {
                        vec![(-qb - disc.sqrt()) / (2.0 * qa), (-qb + disc.sqrt()) / (2.0 * qa)]
                    }
                };
                if let Some((lo, hi)) = q.clip_box() {
                    let (lo, hi) = (d3(lo), d3(hi));
                    ts.retain(|&t| {
                        let p = add(o, mul(d, t));
                        (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k])
                    });
                }
                ts
            }
            Shape::Cone(cn) => {
                let (b, rb, a, ra) = cn.ends();
                let (b, a) = (d3(b), d3(a));
                let (rb, ra) = (rb as f64, ra as f64);
                let axis = sub(a, b);
                let h = dot(axis, axis).sqrt();
                let w = mul(axis, 1.0 / h);
                let k = (ra - rb) / h;
                // |rel − (rel·w)w|² = (rb + k·(rel·w))², rel = o + td − b.
                let rel = sub(o, b);
                let (oz, dz) = (dot(rel, w), dot(d, w));
                let (op, dp) = (sub(rel, mul(w, oz)), sub(d, mul(w, dz)));
                let qa = dot(dp, dp) - k * k * dz * dz;
                let qb = 2.0 * (dot(op, dp) - k * dz * (rb + k * oz));
                let qc = dot(op, op) - (rb + k * oz).powi(2);
                let mut ts = if qa.abs() < 1e-12 {
                    if qb == 0.0 {
                        vec![]
                    } else {
                        vec![-qc / qb]
                    }
                } else {
                    let disc = qb * qb - 4.0 * qa * qc;
                    if disc < 0.0 {
                        vec![]
                    } else {
                        vec![(-qb - disc.sqrt()) / (2.0 * qa), (-qb + disc.sqrt()) / (2.0 * qa)]
                    }
                };
                ts.retain(|&t| {
                    let z = oz + t * dz;
                    (0.0..=h).contains(&z)
                });
                ts
            }
        };
        ts.retain(|&t| t > 0.0);
        ts.sort_by(|a, b| a.partial_cmp(b).unwrap());
        ts
    }

    fn nearest(&self, o: V, d: V) -> Option<(f64, usize)> {
        let mut best: Option<(f64, usize)> = None;
        for (k, p) in self.view.primitives().iter().enumerate() {
            if let Some(&t) = self.crossings(&p.shape, o, d).first() {
                if best.is_none_or(|(bt, _)| t < bt) {
                    best = Some((t, k));
                }
            }
        }
        best
    }

    /// Outward geometric normal and shading normal (unit) at p.
    fn normals(&self, shape: &Shape<f32>, p: V) -> (V, V) {
        let g = match shape {
            Shape::Sphere(s) => sub(p, d3(s.center())),
            Shape::Plane(pl) => d3(pl.normal_vector()),
            Shape::Polygon(pg) => newell(&pg.vertices(self.pool()).iter().map(|v| d3(*v)).collect::<Vec<_>>()),
            Shape::AaBox(b) => box_normal(p, d3(b.min()), d3(b.max())),
            Shape::OrientedBox(b) => {
                let (u, v, w) = b.axes();
                let (u, v, w) = (d3(u), d3(v), d3(w));
                let r = sub(p, d3(b.center()));
                let h = d3(b.half_extents());
                let n = box_normal([dot(r, u), dot(r, v), dot(r, w)], mul(h, -1.0), h);
                add(add(mul(u, n[0]), mul(v, n[1])), mul(w, n[2]))
            }
            Shape::Quadric(q) => {
                let [a, b, c, dd, e, f, g, h, i, _] = q.coefficients().map(|x| x as f64);
                [
                    2.0 * a * p[0] + dd * p[1] + e * p[2] + g,
                    2.0 * b * p[1] + dd * p[0] + f * p[2] + h,
                    2.0 * c * p[2] + e * p[0] + f * p[1] + i,
                ]
            }
            Shape::Cone(cn) => {
                let (b, rb, a, ra) = cn.ends();
                let (b, a) = (d3(b), d3(a));
                let axis = sub(a, b);
                let h = dot(axis, axis).sqrt();
                let w = mul(axis, 1.0 / h);
                let k = (ra as f64 - rb as f64) / h;
                let rel = sub(p, b);
                let z = dot(rel, w);
                let radial = sub(rel, mul(w, z));
                sub(radial, mul(w, k * (rb as f64 + k * z)))
            }
        };
        let g = norm(g);
        let s = match shape {
            Shape::Polygon(pg) if pg.is_patch() && pg.vertex_count() == 3 => {
                // Barycentric interpolation of the vertex normals (triangles).
                let vs: Vec<V> = pg.vertices(self.pool()).iter().map(|v| d3(*v)).collect();
                let ns: Vec<V> = pg.vertex_normals(self.pool()).iter().map(|v| d3(*v)).collect();
                let area = |a: V, b: V, c: V| dot(cross(sub(b, a), sub(c, a)), g);
                let full = area(vs[0], vs[1], vs[2]);
                let l0 = area(p, vs[1], vs[2]) / full;
                let l1 = area(vs[0], p, vs[2]) / full;
                let l2 = 1.0 - l0 - l1;
                norm(add(add(mul(ns[0], l0), mul(ns[1], l1)), mul(ns[2], l2)))
            }
            Shape::Polygon(pg) if pg.is_patch() => panic!("reference handles triangle patches only"),
            _ => g,
        };
        (g, s)
    }

    /// Light reaching the end of the segment: Kt per surface crossed.
    fn transmittance(&self, o: V, d: V, dist: f64, path: &mut Vec<i64>) -> f64 {
        let mut tr = 1.0;
        for p in self.view.primitives() {
            let n = self.crossings(&p.shape, o, d).iter().filter(|&&t| t < dist).count();
            tr *= (self.view.materials()[p.material as usize].kt as f64).powi(n as i32);
        }
        path.push(if tr > 0.0 { -1 } else { -2 });
        tr
    }

    /// Colour of a ray (unit weight), following the model in the README;
    /// `weight` is the path weight for the 1/512 cut-off, `path` records events.
    fn trace(&self, o: V, d: V, depth: u32, weight: f64, path: &mut Vec<i64>) -> V {
        let bg = d3(self.view.background());
        let Some((t, k)) = self.nearest(o, d) else {
            path.push(-3);
            return bg;
        };
        path.push(k as i64);
        let prim = &self.view.primitives()[k];
        let m = self.view.materials()[prim.material as usize];
        let color = d3(m.color);
        let [ka, kd, ks, shine, kr, kt, ior] = [m.ka, m.kd, m.ks, m.shine, m.kr, m.kt, m.ior].map(|x| x as f64);
        let p = add(o, mul(d, t));
        let (mut ng, mut ns) = self.normals(&prim.shape, p);
        let entering = dot(d, ng) <= 0.0;
        if !entering {
            ng = mul(ng, -1.0);
            ns = mul(ns, -1.0);
        }
        let eps = 1e-4 * (1.0 + p[0].abs().max(p[1].abs()).max(p[2].abs()));
        let mut local = mul(color, ka);
        for light in self.view.lights() {
            let to = sub(d3(light.position), p);
            let dist = dot(to, to).sqrt();
            let l = mul(to, 1.0 / dist);
            let ndl = dot(ns, l);
            if !(ndl > 0.0 && dot(ng, l) > 0.0) {
                continue;
            }
            let tr = self.transmittance(add(p, mul(ng, eps)), l, dist, path);
            if tr <= 0.0 {
                continue;
            }
            let r = sub(mul(ns, 2.0 * ndl), l);
            let rv = -dot(r, d);
            let spec = if rv > 0.0 && ks != 0.0 { ks * rv.min(1.0).powf(shine) } else { 0.0 };
            let lc = d3(light.color);
            for c in 0..3 {
                local[c] += lc[c] * tr * (kd * ndl * color[c] + spec);
            }
        }
        let mut out = mul(local, 1.0 - kt);
        if depth >= 5 {
            return out;
        }
        // Refraction (Snell) and total internal reflection.
        let cos_i = -dot(d, ns);
        let eta = if entering { 1.0 / ior } else { ior };
        let k2 = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
        let tir = kt > 0.0 && k2 < 0.0;
        let w_refl = kr + if tir { kt } else { 0.0 };
        let w_refr = if kt > 0.0 && !tir { kt } else { 0.0 };
        if w_refr > 0.0 && weight * w_refr > 1.0 / 512.0 {
            let tdir = norm(add(mul(d, eta), mul(ns, eta * cos_i - k2.sqrt())));
            let c = self.trace(sub(p, mul(ng, eps)), tdir, depth + 1, weight * w_refr, path);
            out = add(out, mul(c, w_refr));
        }
        if weight * w_refl > 1.0 / 512.0 {
            let rdir = norm(add(d, mul(ns, 2.0 * cos_i)));
            let c = self.trace(add(p, mul(ng, eps)), rdir, depth + 1, weight * w_refl, path);
            out = add(out, mul(c, w_refl));
        }
        out
    }
}

fn newell(vs: &[V]) -> V {
    let mut n = [0.0; 3];
    for i in 0..vs.len() {
        let (a, b) = (vs[i], vs[(i + 1) % vs.len()]);
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    norm(n)
}

fn even_odd(vs: &[V], n: V, p: V) -> bool {
    // Project away the dominant axis of the normal.
    let k = (0..3).max_by(|&a, &b| n[a].abs().partial_cmp(&n[b].abs()).unwrap()).unwrap();
    let (u, v) = ((k + 1) % 3, (k + 2) % 3);
    let mut inside = false;
    for i in 0..vs.len() {
        let (a, b) = (vs[i], vs[(i + 1) % vs.len()]);
        if (a[v] > p[v]) != (b[v] > p[v]) && p[u] < a[u] + (p[v] - a[v]) * (b[u] - a[u]) / (b[v] - a[v]) {
            inside = !inside;
        }
    }
    inside
}

fn slabs(o: V, d: V, lo: V, hi: V) -> Vec<f64> {
    let (mut tn, mut tf) = (f64::NEG_INFINITY, f64::INFINITY);
    for a in 0..3 {
        if d[a] == 0.0 {
            if o[a] < lo[a] || o[a] > hi[a] {
                return vec![];
            }
        } else {
            let (t1, t2) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
            tn = tn.max(t1.min(t2));
            tf = tf.min(t1.max(t2));
        }
    }
    if tn <= tf {
        vec![tn, tf]
    } else {
        vec![]
    }
}

fn box_normal(p: V, lo: V, hi: V) -> V {
    let mut best = (f64::INFINITY, [0.0; 3]);
    for a in 0..3 {
        for (dist, s) in [((p[a] - lo[a]).abs(), -1.0), ((hi[a] - p[a]).abs(), 1.0)] {
            if dist < best.0 {
                let mut n = [0.0; 3];
                n[a] = s;
                best = (dist, n);
            }
        }
    }
    best.1
}

fn quantize(v: f64) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0 + 0.5).floor() as u8
}

#[test]
fn demo_scene_matches_independent_f64_reference() {
    let (w, h) = (96u32, 72u32);
    let scene = demo_scene::<f32>().unwrap();
    let camera = demo_camera::<f32>(w, h).unwrap();
    let view = scene.view();
    let tracer: Tracer<f32> = Tracer::new(view, TraceSettings::default()).unwrap();
    let renderer = Renderer::new(tracer, camera);
    let mut img = vec![[0u8; 3]; (w * h) as usize];
    let mut stats = RayStats::default();
    renderer.render_rect::<8>(camera.full_rect(), &mut img, &mut stats).unwrap();
    assert!(stats.reflected > 0 && stats.refracted > 0 && stats.shadow > 0);

    // The reference camera, in f64, from the same description.
    let reference = Reference { view };
    let (eye, at, up) = ([0.0, -7.0, 2.6], [0.0, 0.5, 0.8], [0.0, 0.0, 1.0]);
    let f = norm(sub(at, eye));
    let r = norm(cross(f, up));
    let u = cross(r, f);
    let tan = (45.0f64.to_radians() / 2.0).tan();
    let ray = |x: f64, y: f64| {
        let sx = (2.0 * x / w as f64 - 1.0) * tan * w as f64 / h as f64;
        let sy = (1.0 - 2.0 * y / h as f64) * tan;
        norm(add(add(f, mul(r, sx)), mul(u, sy)))
    };
    let (mut stable, mut checked_glass, mut checked_mirror, mut worst) = (0, 0, 0, 0i32);
    let mut mismatches = vec![];
    for j in 0..h {
        for i in 0..w {
            let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
            let mut path = vec![];
            let c = reference.trace(eye, ray(x, y), 1, 1.0, &mut path);
            let steady = [(0.05, 0.0), (-0.05, 0.0), (0.0, 0.05), (0.0, -0.05)].iter().all(|(dx, dy)| {
                let mut p2 = vec![];
                reference.trace(eye, ray(x + dx, y + dy), 1, 1.0, &mut p2);
                p2 == path
            });
            if !steady {
                continue;
            }
            stable += 1;
            if path.first() == Some(&7) {
                checked_glass += 1;
            }
            if path.first() == Some(&6) {
                checked_mirror += 1;
            }
            let expect = c.map(quantize);
            let got = img[(j * w + i) as usize];
            let diff = (0..3).map(|k| (expect[k] as i32 - got[k] as i32).abs()).max().unwrap();
            worst = worst.max(diff);
            if diff > 1 {
                mismatches.push((i, j, expect, got));
            }
        }
    }
    eprintln!(
        "stable pixels: {stable} of {} (glass {checked_glass}, mirror {checked_mirror}); worst difference {worst}/255",
        w * h
    );
    assert!(stable > (w * h) as usize * 3 / 4, "too few stable pixels to mean anything: {stable}");
    assert!(checked_glass > 50 && checked_mirror > 50);
    assert!(
        mismatches.is_empty(),
        "{} stable pixels differ from the f64 reference by more than 1/255: {:?}",
        mismatches.len(),
        &mismatches[..mismatches.len().min(10)]
    );
}
