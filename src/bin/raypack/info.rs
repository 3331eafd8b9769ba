//! `raypack info`: what a scene holds.

use crate::load;
use crate::Failure;
use raypack::primitives::ShapeKind;
use std::path::Path;

pub fn run(path: &Path) -> Result<(), Failure> {
    let text = load::with_scene::<f32, _>(path, true, &|s| {
        let c = s.info.counts;
        let mut out = String::new();
        let mut line = |t: String| {
            out.push_str(&t);
            out.push('\n');
        };
        line(format!("scene       {}", path.display()));
        line(format!("lines       {}", s.info.lines));
        line(format!("primitives  {}", c.primitives()));
        for (name, kind, n) in [
            ("spheres (s)", ShapeKind::Sphere, c.spheres),
            ("cones (c)", ShapeKind::Cone, c.cones),
            ("polygons (p)", ShapeKind::Polygon, c.polygons),
            ("patches (pp)", ShapeKind::Patch, c.patches),
            ("planes (pl)", ShapeKind::Plane, c.planes),
            ("boxes (box)", ShapeKind::AaBox, c.boxes),
            ("oriented boxes (obox)", ShapeKind::OrientedBox, c.oriented_boxes),
            ("quadrics (q)", ShapeKind::Quadric, c.quadrics),
        ] {
            debug_assert_eq!(s.view.count(kind), n);
            if n > 0 {
                line(format!("  {name:<22}{n}"));
            }
        }
        if s.degenerate > 0 {
            line(format!("  zero-area polygons    {} (never hit)", s.degenerate));
        }
        line(format!("vertices    {} pool slots (a patch uses 2 per vertex)", c.vertices));
        line(format!("materials   {}", c.materials));
        line(format!("lights      {}", c.lights));
        match s.view.bounds() {
            Some((lo, hi)) => line(format!("bounds      ({}, {}, {}) to ({}, {}, {})", lo.x, lo.y, lo.z, hi.x, hi.y, hi.z)),
            None => line("bounds      none (only unbounded primitives)".into()),
        }
        let b = s.info.background;
        line(format!("background  {} {} {}", b[0], b[1], b[2]));
        match s.info.camera {
            Some(cam) => {
                let v = |a: [f32; 3]| format!("({}, {}, {})", a[0], a[1], a[2]);
                line(format!("camera      from {} at {} up {}", v(cam.from), v(cam.at), v(cam.up)));
                line(format!("            angle {}° (vertical), hither {}, resolution {}x{}", cam.angle, cam.hither, cam.width, cam.height));
            }
            None => line("camera      none (no `v` block)".into()),
        }
        if let Some((b, built)) = s.bvh {
            line(format!("bvh         {} nodes, {} leaves, depth {}, largest leaf {}, {} unbounded primitives, built in {:.2} ms", b.nodes, b.leaves, b.depth, b.max_leaf, b.unbounded, built.as_secs_f64() * 1e3));
        }
        let (p, v, m, l) = s.capacity;
        line(format!("capacity    {p} primitives, {v} vertices, {m} materials, {l} lights"));
        Ok(out)
    })?;
    print!("{text}");
    Ok(())
}
