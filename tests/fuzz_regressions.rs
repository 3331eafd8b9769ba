//! Inputs the fuzz targets (fuzz/, docs/fuzzing.md) found or reached, kept
//! as tests of the normal suite: each asserts a clean error or a defined
//! result. The targets found no panic in the library; what they did find is
//! here:
//! - ways the `f32` BVH and brute-force renders differ (`render_tiny`
//!   with RAYPACK_FUZZ_EXACT=1): rays starting far out on an unbounded
//!   plane (beyond the BVH's documented reach); false hits of the cone
//!   and sphere kernels for ray origins far from a thin cone or a small
//!   sphere (fixed: both solve from the ray's point nearest them); an
//!   oriented box with parallel axes that the reader accepted (fixed in
//!   `OrientedBox::new`);
//! - the reader's order of errors: a capacity error stops the reader before
//!   an error further on that the scanner reports (`nff_scene`);
//! - minimized corpus entries that reach the reader's less common errors.

use raypack::image::{self, AccelKind, Error, Image, Options, ScalarKind};
use raypack::nff::{self, NffErrorKind};
use raypack::prelude::*;
use raypack::render::{Aov, Sampling};
use raypack::trace::Mode;

mod common;

/// `render_tiny`, minimized (from extensions.nff): a mirror-free scene over
/// the plane `z = -655350`; reflected rays of the glossy objects hit the
/// plane some 150 000 scene sizes out, and the shadow rays from there are
/// beyond the BVH's exactness ("rays that start within a few hundred scene
/// sizes of the origin", src/query/bvh/mod.rs): a few pixels differ from
/// brute force. `{D}` is the plane's offset.
const FAR_PLANE: &str =
    "b 0.1 0.12 0.2\nv\nfrom 0 -8 3\nat 0 0 0.8\nup 0 0 1\nangle 40\nhither 0.01\nresolution 320 240\n\
l -4 -5 7\nl 5 -3 4 0.5 0.45 0.4\nfx 0.8 0.8 0.7 0.1 0.8 0 1 0 0 1\npl 0 0 1 {D}\nf 0.9 0.2 0.15 0.7 0.3 20 0 1\n\
box -2.6 -0.4 0 -1.6 0.6 1\nfx 0.2 0.3 0.9 0.1 0.7 0.4 30 00.1 0 1\nobox 1.9 -0.6 0.4 0.4 0.4 0.4 1 1 0 -1 1 0\n\
fx 0.2 0.8 0.3 0.1 0.8 0.2 10 0 0 1\nc\n-3 0.6 0 0.3\n-3 0.6 0.9 0.3\np 4\n-4 3 0\n4 3 0\n4 3 3\n-4 3 3\n\
pp 3\n-0.6 2.8 0.3 -0.6 -1 0\n-2.4 2.8 0.3 0.6 -1 0\n-3 2.8 1.5 0 -0 0.6\n";

/// `render_tiny`, minimized: a thin cone at the origin, a sphere of radius
/// 421 290 around everything (the eye and the light inside it) and a small
/// sphere. Shadow rays start on the big sphere, 421 290 out, inside the
/// scene's box (so within the BVH's documented reach); for some of them the
/// cone kernel reports a hit about 7 units from the cone (radius 0.075): the
/// cylinder's `c = x² + y² − r²` and `b² − a·c` lose everything to rounding
/// at that distance. The BVH's box (padded by scale·2⁻¹⁶ = 6.4) rightly
/// never offers the cone to those rays, so brute force shadows pixels the
/// BVH lights.
const FAR_CONE: &str = "v\nfrom 0 0 -8\nat 0 0 0\nup 0 1 0\nangle 25\nhither 0.201\nresolution 256 256\nl -10 3 -20\n\
f 0.737 0.561 0.561 0.7 0.7 11.1434 0 1\nc 0 -0.649519 0.375 0.075 0 0.649519 -0.375 0.075\n\
s 0.704769 0.128258 0.2 421290.15\ns 0.256515 -0.352385 -0.610348 0.15\n";

fn tiny(w: u32, h: u32, accel: AccelKind) -> Options {
    Options {
        width: Some(w),
        height: Some(h),
        packet: 4,
        threads: Some(1),
        depth: 3,
        accel,
        sampling: Sampling::Centre,
        ..Options::default()
    }
}

/// Both accelerators render `text` cleanly at `w × h`; the pixels of each.
fn both(text: &str, w: u32, h: u32) -> (Vec<Rgb8>, Vec<Rgb8>) {
    let mut out = Vec::new();
    for accel in [AccelKind::Bvh, AccelKind::BruteForce] {
        let img = Image::render(text, &tiny(w, h, accel)).unwrap_or_else(|e| panic!("{accel:?}: {e}"));
        assert_eq!((img.width, img.height, img.pixels.len(), img.accel), (w, h, (w * h) as usize, accel));
        out.push(img.pixels);
    }
    let b = out.pop().unwrap_or_default();
    (out.pop().unwrap_or_default(), b)
}

#[test]
fn far_plane_renders_cleanly_and_matches_brute_force_within_the_documented_reach() {
    // Far out: a defined image from both (a few pixels differ; see FAR_PLANE).
    both(&FAR_PLANE.replace("{D}", "655350"), 64, 48);
    // The same scene with the plane 655 below (some 150 scene sizes): the
    // same bytes.
    let (bvh, brute) = both(&FAR_PLANE.replace("{D}", "655"), 128, 96);
    assert!(bvh == brute, "BVH and brute force differ with the plane at z = -655");
}

#[test]
fn far_cone_renders_cleanly() {
    both(FAR_CONE, 16, 16);
    // The scene also loads and renders in fixed point, or is refused for
    // its range (the big sphere): an error, never a panic.
    match Image::render(FAR_CONE, &Options { scalar: ScalarKind::Fixed32, ..tiny(16, 16, AccelKind::Bvh) }) {
        Ok(img) => assert_eq!(img.pixels.len(), 256),
        Err(e) => assert!(matches!(e, Error::Convert(_) | Error::Range(_) | Error::Camera(_)), "{e}"),
    }
}

/// The cone kernel's false hits for far ray origins (see FAR_CONE): fixed by
/// solving from the point of the ray nearest the cone (`Cone::roots`).
#[test]
fn far_cone_bvh_and_brute_force_give_the_same_bytes() {
    let (bvh, brute) = both(FAR_CONE, 16, 16);
    let differ = bvh.iter().zip(&brute).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "{differ} of 256 pixels differ");
}

/// `render_tiny` (RAYPACK_FUZZ_EXACT=1, 2026-12-05), minimized: a polygon
/// whose first vertex left its plane (`5.22625` became `55.22625`) and a
/// mirror cylinder. The kernel hits Newell's plane through the first vertex
/// inside the projected outline, and there the plane runs below the
/// vertices' lowest `y`: the BVH's box of the vertices passed over hits
/// that brute force found (reflected rays). `Polygon::bounds` now bounds
/// the plane over the outline too.
const NON_PLANAR_POLYGON: &str =
    "v\nfrom -1 -2.61313 0.5\nat -1 -1.61313 0.5\nup 0 0 1\nangle 45\nhither 1\nresolution 512 512\n\
l 2 -2.61313 -4\nf 1 1 1 1 0 100000 0 0\n\
p 4\n2.2796 55.22625 3.77965\n-4.27965 5.22625 3.77965\n-4.27965 5.22625 -2.77965\n2.27965 5.22625 -2.77965\n\
f 1 1 0 0.5 0.2 3.0827 0 0\nc -0.753191 2.85785 -0.489453 0.07412 -0.465497 3.25383 0.489453 0.07412\n";

#[test]
fn a_non_planar_polygon_gives_the_same_bytes_by_bvh_and_brute_force() {
    let (bvh, brute) = both(NON_PLANAR_POLYGON, 64, 64);
    let differ = bvh.iter().zip(&brute).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "{differ} of 4096 pixels differ");
}

/// `render_tiny` (RAYPACK_FUZZ_EXACT=1, 2026-12-05), minimized: a cone
/// 655 350 units long with base radius 0.4 and its apex at x = 3 (a half
/// angle of 6·10⁻⁷). The kernel solved from the ray's point nearest the
/// base, which for a cone this long lies a whole length away from where the
/// ray passes it: camera rays were reported hitting it on 4 917 of 16 384
/// ID pixels, although in exact arithmetic no camera ray of the image meets
/// it, and shadow rays' false hits made BVH and brute force differ on 1 082
/// pixels. `Cone::roots` now solves from the ray's point nearest the axis,
/// held on the cone's length.
const THIN_LONG_CONE: &str = "v\nfrom -1.6 1.6 1.7\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0.01\nresolution 512 512\n\
b 0.1 0.1 0.1\nl -100 -100 100\nf 1 0 0 0.8 0.2 20 0 0\ns -0.8 0.8 1.20821 0.13\nc 655353 0.6 0 0.4 3 0.6 1.2 0\n";

#[test]
fn a_thin_long_cone_is_hit_only_where_it_is() {
    let (bvh, brute) = both(THIN_LONG_CONE, 64, 64);
    let differ = bvh.iter().zip(&brute).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "{differ} of 4096 pixels differ");
    // No camera ray of the image meets the cone (its radius is below 2·10⁻⁶
    // where it is in view): the ID image shows the sphere (ID 1) and the
    // background (0), never the cone (2).
    let opts = Options { aov: Aov::Id, ..tiny(64, 64, AccelKind::BruteForce) };
    let img = Image::render(THIN_LONG_CONE, &opts).unwrap_or_else(|e| panic!("{e}"));
    let ids = |k: u8| img.pixels.iter().filter(|p| **p == [0, 0, k]).count();
    assert!(ids(1) > 0, "the sphere is in view");
    assert_eq!(ids(1) + ids(0), 4096, "the cone reported hit on {} pixels", ids(2));
}

/// `render_tiny` (RAYPACK_FUZZ_EXACT=1), minimized from extensions.nff: the
/// `obox` line lost a minus sign (`-1 1 0` became `\r1 1 0`), so its `u`
/// and `v` are both (1, 1, 0). Gram-Schmidt left rounding noise that
/// normalized to `u` itself, the reader accepted a box with `w = 0`, and
/// BVH and brute force differed on 251 of 256 pixels. `OrientedBox::new`
/// now rejects it, as it always meant to ("`v` parallel to `u`").
const PARALLEL_OBOX: &str = "v\nfrom 0 -8 3\nat 0 0 0.8\nup 0 0 1\nangle 40\nhither 0.01\nresolution 320 240\n\
f 0.9 0.2 0.15 0.7 0.3 20 0 1\nobox 1.9 -0.6 0.4 0.4 0.4 0.4 1 1 0 \r1 1 0\nfx 0.2 0.8 0.3 0.1 0.8 0.2 10 0 0 1\n\
c\n-3 0.6 0 0.3\n-3 0.6 0.9 0.3\np 4\n-4 3 0\n4 3 0\n4 3 3\n-4 3 3\n\
pp 3\n-3.6 2.8 0.3 -0.6 -1 0\n-2.4 2.8 1.3 0.6 -1 0\n-3 2.8 1.5 0 -1 0.6\n";

#[test]
fn an_obox_with_parallel_axes_is_refused_on_its_line() {
    let e = nff::scan(PARALLEL_OBOX).unwrap_err();
    assert_eq!(e.to_string(), "line 9, column 1: invalid `obox`: an axis, normal or direction has zero length");
    let Err(Error::Scene(loaded)) = image::with_scene(PARALLEL_OBOX, ScalarKind::F32, AccelKind::Bvh, |_| ()) else {
        panic!("loaded")
    };
    assert_eq!(loaded, e);
    // With the minus sign back, the box is fine and both accelerators give
    // the same bytes.
    let fixed = PARALLEL_OBOX.replace("\r1 1 0", "-1 1 0");
    let (bvh, brute) = both(&fixed, 16, 16);
    assert!(bvh == brute, "BVH and brute force differ");
}

#[test]
fn a_capacity_error_stops_the_reader_before_a_later_error_the_scanner_reports() {
    // `nff_scene` found this order (with a 130-vertex polygon in a
    // 128-slot scene and a bad number 46 lines further on).
    let mut text = String::from("f 1 1 1 1 0 0 0 1\np 9\n");
    for i in 0..9 {
        text += &format!("{} {} 0\n", i % 3, i / 3);
    }
    text += "s 0 0 0 -0.4103\u{b}5\n";
    let scanned = nff::scan(&text).unwrap_err();
    assert_eq!((scanned.line, scanned.column), (12, 9));
    assert_eq!(scanned.kind, NffErrorKind::BadNumber(nff::Token::new("-0.4103\u{b}5")));
    let mut small: Scene<f32, 8, 8, 2, 2> = Scene::new();
    let e = nff::parse(&text, &mut small).unwrap_err();
    assert_eq!(e.line, 2);
    // The rest of the file cannot be counted (it has an error), so the
    // capacity error says what the reader knew: the polygon's 9 slots.
    assert_eq!(e.to_string(), "line 2, column 1: scene too large: vertex capacity 8 exceeded (needs 9)");
    // Nothing of the polygon stays behind.
    assert_eq!((small.len(), small.vertex_count()), (0, 0));
    // The command line's loader reads it with the scanner's error.
    let Err(Error::Scene(loaded)) = image::with_scene(&text, ScalarKind::F32, AccelKind::Bvh, |_| ()) else {
        panic!("loaded")
    };
    assert_eq!(loaded, scanned);
}

/// Minimized `nff_scene` corpus entries and the reader's exact answer.
#[test]
fn minimized_corpus_entries_reach_the_readers_errors() {
    let cases: &[(&str, &str)] = &[
        // The reader's white space is ASCII's (space, \t, \n, \x0C, \r):
        // a NUL is a word (quoted as is), a form feed separates.
        ("\0", "line 1, column 1: unknown entity `\0` (expected one of v b l f fx s c p pp pl box obox q)"),
        ("F\u{c}", "line 1, column 1: unknown entity `F` (expected one of v b l f fx s c p pp pl box obox q)"),
        // -0 is not negative: too few vertices, not a negative count.
        ("p -0", "line 1, column 3: a polygon needs at least 3 vertices, got 0"),
        ("p -09", "line 1, column 3: negative vertex count `-09`"),
        // A two-line cone cut off after its keyword: the missing line is
        // the one after the end.
        ("c", "line 2, column 1: file ends early: expected 4 numbers (bx by bz br) for the entity on line 1"),
        ("l", "line 1, column 2: `l` takes 3 numbers (x y z) or 6 (x y z r g b), found 0 fields"),
        (" up", "line 1, column 2: `up` outside a `v` block (it belongs right after `v`, in order)"),
        ("v\n a", "line 2, column 2: `v` block out of order: expected `from` (order: from, at, up, angle, hither, resolution), found `a`"),
        // A resolution that parses as a u32 but is out of range.
        (
            "b 0.2 0.05 0.2\nv\nfrom 0 0 -8\nat 0 0 0\nup 0 1 0\nangle 25\nhither 0.001\nresolution 254228258 -1\n5\n",
            "line 8, column 12: resolution must be between 1 and 65535 pixels per side",
        ),
        (
            "v\nfrom 0 -8 3\nat 0 0 0.8\nup 0 0 1\nangle 40\nhither 0.01\nresolution 8 6\nl 4 -5 7\nf 0.9 0.2 0.15 0.7 0.3 20 0 1\nc\n0 0 0 0.5\n0 0 1.5 -inf",
            "line 12, column 9: `-inf` is not a finite number (NaN, infinity or too large)",
        ),
        ("f 1 1 1 1 0 0 0 1\ns 0 0 0 0", "line 2, column 1: invalid `s`: a radius or size is zero or negative"),
    ];
    for (text, message) in cases {
        let e = nff::scan(text).unwrap_err();
        assert_eq!(e.to_string(), *message, "{text:?}");
        let mut s: Scene<f32, 8, 8, 2, 2> = Scene::new();
        assert_eq!(nff::parse(text, &mut s), Err(e), "{text:?}");
    }
    // An eye at the largest f32 (the fuzzer's `03.4028235e38`): the reader
    // checks the camera and refuses it as a value, on the `at` line (where
    // an eye-at-target camera is reported).
    let text = "                      v\nfrom 03.4028235e38 0 -8\nat 0 0 0\nup 0 1 0\nangle 25\nhither 0.001\nresolution 256 256\n";
    let e = nff::scan(text).unwrap_err();
    assert_eq!((e.line, e.column), (3, 1));
    assert!(matches!(e.kind, NffErrorKind::Camera(_)), "{e}");
}

#[test]
fn a_light_outside_the_fixed_point_frame_is_a_whole_scene_error() {
    // `nff_scene`: f32 loads it; fixed point fits its frame to the
    // primitives and the eye, so a light far out is refused by index.
    let text = "v\nfrom 0 -8 3\nat 0 0 0.8\nup 0 0 1\nangle 40\nhither 0.01\nresolution 8 6\nl 420 0 2";
    assert!(image::with_scene(text, ScalarKind::F32, AccelKind::Bvh, |_| ()).is_ok());
    let e = image::with_scene(text, ScalarKind::Fixed32, AccelKind::Bvh, |_| ()).map(|_| ()).unwrap_err();
    assert!(matches!(e, Error::Convert(SceneError::OutOfRange(_))), "{e}");
    assert!(e.to_string().starts_with("in the fixed-point frame: light 0 has a coordinate of magnitude"), "{e}");
}

/// Findings 2 and 3 of docs/fuzzing.md as a seeded property: small cones and
/// spheres (radius 0.05 to 0.4) near the origin, inside a sphere 2 500 to
/// 4·10¹⁰ times larger that holds the eye and the light, so shadow and
/// reflected rays start far out on it. BVH and brute force must give the
/// same bytes: a kernel may only report hits near its primitive (where the
/// BVH's padded box offers it).
#[test]
fn far_ray_origins_give_the_same_bytes_by_bvh_and_brute_force() {
    let mut rng = common::Rng(0x0fa7_0c0e);
    for case in 0..24 {
        let big = 2_500.0 * 10f32.powf(rng.range(0.0, 7.2));
        let mut text = format!(
            "v\nfrom 0 0 -8\nat 0 0 0\nup 0 1 0\nangle 25\nhither 0.2\nresolution 16 16\nl -10 3 -20\n\
             f 0.74 0.56 0.56 0.7 0.7 11 0.3 1\ns {} {} {} {big}\n",
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0)
        );
        for _ in 0..3 {
            let (p, q, r) = (rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0), rng.range(0.05, 0.4));
            if rng.below(2) == 0 {
                text += &format!("c {} {} {} {r} {} {} {} {r}\n", p.x, p.y, p.z, q.x, q.y, q.z);
            } else {
                text += &format!("s {} {} {} {r}\n", p.x, p.y, p.z);
            }
        }
        let (bvh, brute) = both(&text, 16, 16);
        let differ = bvh.iter().zip(&brute).filter(|(a, b)| a != b).count();
        assert_eq!(differ, 0, "case {case}: {differ} of 256 pixels differ:\n{text}");
    }
}

/// The committed `render_tiny` seed corpus (fuzz/corpus/render_tiny, in
/// the repository but not in the published crate) replayed as the fuzz
/// target does with RAYPACK_FUZZ_EXACT=1: the options picked from the
/// input's hash, and for scenes of up to 64 primitives without unbounded
/// ones, the same bytes through the BVH and by brute force.
#[test]
fn the_render_tiny_corpus_gives_the_same_bytes_by_bvh_and_brute_force() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/render_tiny");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        eprintln!("{} not found (a packaged copy): nothing to replay", dir.display());
        return;
    };
    let (mut files, mut compared) = (0, 0);
    for entry in entries {
        let path = entry.unwrap().path();
        let data = std::fs::read(&path).unwrap();
        files += 1;
        if data.len() > 4096 {
            continue;
        }
        let text = String::from_utf8_lossy(&data);
        let Ok(info) = nff::scan(&text) else { continue };
        if info.counts.primitives() > 64 || info.camera.is_none() {
            continue;
        }
        let unbounded =
            image::with_scene(&text, ScalarKind::F32, AccelKind::Bvh, |s| s.info().bvh.map_or(0, |(b, _)| b.unbounded));
        if !matches!(unbounded, Ok(0)) {
            continue;
        }
        // The fuzz target's choice of options (FNV-1a of the input).
        let h = data.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x100_0000_01b3));
        let (w, ht) = [(8, 8), (16, 16), (13, 7), (1, 1)][(h & 3) as usize];
        let aovs = [Aov::Color, Aov::Color, Aov::Depth, Aov::Normal, Aov::Id, Aov::Color, Aov::Color, Aov::Color];
        let samplings = [Sampling::Centre, Sampling::Centre, Sampling::Grid(2), Sampling::adaptive(2, 0.1)];
        let o = Options {
            width: Some(w),
            height: Some(ht),
            packet: [1, 4, 8, 16][((h >> 2) & 3) as usize],
            threads: Some(1),
            mode: if (h >> 9) & 7 == 0 { Mode::Cast } else { Mode::Whitted },
            depth: 3,
            aov: aovs[((h >> 4) & 7) as usize],
            sampling: samplings[((h >> 7) & 3) as usize],
            ..Options::default()
        };
        let bvh = Image::render(&text, &o).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let brute = Image::render(&text, &Options { accel: AccelKind::BruteForce, ..o })
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(bvh.pixels == brute.pixels, "{}: BVH and brute force differ ({o:?})", path.display());
        compared += 1;
    }
    eprintln!("{files} corpus files, {compared} compared");
    assert!(compared >= 50, "only {compared} of {files} corpus files compared");
}
