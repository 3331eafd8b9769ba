//! `raypack info`: what a scene holds.

use crate::Failure;
use raypack::image::{self, AccelKind, ScalarKind};
use std::path::Path;

pub fn run(path: &Path) -> Result<(), Failure> {
    let text = crate::read_scene(path)?;
    let out = image::with_scene(&text, ScalarKind::F32, AccelKind::Bvh, |s| {
        let info = *s.info();
        let c = info.nff.counts;
        let mut out = String::new();
        let mut line = |t: String| {
            out.push_str(&t);
            out.push('\n');
        };
        line(format!("scene       {}", path.display()));
        line(format!("lines       {}", info.nff.lines));
        line(format!("primitives  {}", c.primitives()));
        for (name, n) in [
            ("spheres (s)", c.spheres),
            ("cones (c)", c.cones),
            ("polygons (p)", c.polygons),
            ("patches (pp)", c.patches),
            ("planes (pl)", c.planes),
            ("boxes (box)", c.boxes),
            ("oriented boxes (obox)", c.oriented_boxes),
            ("quadrics (q)", c.quadrics),
        ] {
            if n > 0 {
                line(format!("  {name:<22}{n}"));
            }
        }
        if info.degenerate > 0 {
            line(format!("  zero-area polygons    {} (never hit)", info.degenerate));
        }
        line(format!("vertices    {} pool slots (a patch uses 2 per vertex)", c.vertices));
        line(format!("materials   {}", c.materials));
        line(format!("lights      {}", c.lights));
        match s.bounds() {
            Some((lo, hi)) => line(format!("bounds      ({}, {}, {}) to ({}, {}, {})", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2])),
            None => line("bounds      none (only unbounded primitives)".into()),
        }
        let b = info.nff.background;
        line(format!("background  {} {} {}", b[0], b[1], b[2]));
        match info.nff.camera {
            Some(cam) => {
                let v = |a: [f32; 3]| format!("({}, {}, {})", a[0], a[1], a[2]);
                line(format!("camera      from {} at {} up {}", v(cam.from), v(cam.at), v(cam.up)));
                line(format!("            angle {}° (vertical), hither {}, resolution {}x{}", cam.angle, cam.hither, cam.width, cam.height));
            }
            None => line("camera      none (no `v` block)".into()),
        }
        if let Some((b, built)) = info.bvh {
            line(format!("bvh         {} nodes, {} leaves, depth {}, largest leaf {}, {} unbounded primitives, built in {:.2} ms", b.nodes, b.leaves, b.depth, b.max_leaf, b.unbounded, built.as_secs_f64() * 1e3));
        }
        let per = info.bytes as f64 / c.primitives().max(1) as f64;
        line(format!("memory      {} bytes for the scene and its tree ({per:.1} per primitive), read in {:.2} ms", info.bytes, info.parse.as_secs_f64() * 1e3));
        out
    })
    .map_err(|e| Failure(format!("{}: {e}", path.display())))?;
    // A closed pipe (`raypack info … | head -1`) ends quietly.
    crate::output::print(&out)?;
    Ok(())
}
