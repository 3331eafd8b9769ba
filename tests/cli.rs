//! The `raypack` binary, run as a user would: images, byte-identical output
//! for any thread count and packet width, exit codes, one-line errors with
//! line numbers, and no partial files.
#![cfg(feature = "cli")]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn raypack(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raypack")).args(args).output().expect("run raypack")
}

fn scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes").join(name).to_string_lossy().into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    v.sort();
    v
}

/// Renders `scene` with extra arguments into `dir/name` and returns the bytes.
fn render(dir: &Path, name: &str, scene_file: &str, extra: &[&str]) -> Vec<u8> {
    let out = dir.join(name);
    let out_s = out.to_string_lossy().into_owned();
    let mut args = vec!["render", scene_file, "-o", &out_s, "--quiet"];
    args.extend_from_slice(extra);
    let o = raypack(&args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    assert!(o.stderr.is_empty(), "--quiet printed {}", stderr(&o));
    std::fs::read(&out).unwrap()
}

#[test]
fn ppm_header_and_size() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = render(dir.path(), "balls.ppm", &scene("balls-1.nff"), &["--width", "40", "--height", "30"]);
    let header = b"P6\n40 30\n255\n";
    assert_eq!(&bytes[..header.len()], header);
    assert_eq!(bytes.len(), header.len() + 40 * 30 * 3);
    // Not a blank image: the background and the balls differ.
    let px = &bytes[header.len()..];
    assert!(px.chunks(3).any(|p| p != &px[..3]));
}

#[test]
fn png_holds_the_same_pixels_as_ppm() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["--width", "24", "--height", "20"];
    let ppm = render(dir.path(), "a.ppm", &scene("extensions.nff"), &args);
    let png_bytes = render(dir.path(), "a.PNG", &scene("extensions.nff"), &args);
    let decoder = png::Decoder::new(std::io::Cursor::new(png_bytes));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let frame = reader.next_frame(&mut buf).unwrap();
    assert_eq!((frame.width, frame.height, frame.color_type), (24, 20, png::ColorType::Rgb));
    assert_eq!(&buf[..frame.buffer_size()], &ppm[b"P6\n24 20\n255\n".len()..]);
}

#[test]
fn same_bytes_for_every_thread_count_packet_width_and_with_or_without_bvh() {
    let dir = tempfile::tempdir().unwrap();
    // Mirror, glass, every primitive kind; and patches with zero-area polygons.
    for (file, size) in [("extensions.nff", ["--width", "72", "--height", "54"]), ("teapot-1.nff", ["--width", "48", "--height", "40"])] {
        let mut reference: Option<Vec<u8>> = None;
        for (threads, packet, bvh) in [("1", "1", ""), ("2", "4", ""), ("4", "8", ""), ("3", "16", ""), ("1", "8", "--accel=none"), ("2", "16", "--accel=none"), ("4", "1", "--accel=none"), ("2", "1", "")] {
            let mut args = size.to_vec();
            args.extend_from_slice(&["--threads", threads, "--packet", packet]);
            if !bvh.is_empty() {
                args.push(bvh);
            }
            let bytes = render(dir.path(), &format!("{threads}-{packet}.ppm"), &scene(file), &args);
            match &reference {
                None => reference = Some(bytes),
                Some(r) => assert!(r == &bytes, "{file}: threads {threads}, packet {packet} {bvh} differ"),
            }
        }
    }
}

#[test]
fn aovs_differ_and_ids_are_file_order_plus_one() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["--width", "32", "--height", "24"];
    let header = b"P6\n32 24\n255\n".len();
    let mut images = Vec::new();
    for aov in ["color", "depth", "normal", "id"] {
        let mut a = args.to_vec();
        a.extend_from_slice(&["--aov", aov]);
        images.push(render(dir.path(), &format!("{aov}.ppm"), &scene("balls-1.nff"), &a));
    }
    for i in 0..4 {
        for j in i + 1..4 {
            assert_ne!(images[i], images[j]);
        }
    }
    // balls-1: 11 primitives (a floor polygon, ten spheres): ids 1 to 11 or 0.
    let ids: Vec<u32> = images[3][header..].chunks(3).map(|p| (p[0] as u32) << 16 | (p[1] as u32) << 8 | p[2] as u32).collect();
    assert!(ids.iter().all(|&k| k <= 11));
    assert!(ids.contains(&1) && ids.contains(&2));
}

#[test]
fn bad_scene_is_one_line_with_the_line_number_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.nff");
    std::fs::write(&bad, "f 1 1 1 1 0 0 0 1\ns 0 0 0 1\ns 0 0 O 1\n").unwrap();
    let out = dir.path().join("out.ppm");
    let o = raypack(&["render", bad.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("raypack: error: ") && err.contains("bad.nff: line 3, column 7: expected a number, found `O`"), "{err}");
    assert!(!out.exists());
    assert_eq!(files_in(dir.path()), [bad.clone()], "temporary files left behind");

    // An existing image is not touched by a failed render.
    std::fs::write(&out, b"old").unwrap();
    let o = raypack(&["render", bad.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(std::fs::read(&out).unwrap(), b"old");

    // `info` reports the same error.
    let o = raypack(&["info", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("line 3, column 7"), "{}", stderr(&o));
}

#[test]
fn scene_without_camera_missing_file_bad_output() {
    let dir = tempfile::tempdir().unwrap();
    let no_cam = dir.path().join("nocam.nff");
    std::fs::write(&no_cam, "f 1 1 1 1 0 0 0 1\ns 0 0 0 1\n").unwrap();
    let out = dir.path().join("x.ppm");
    let out = out.to_str().unwrap();
    let one_line_error = |o: &Output, needle: &str| {
        assert_eq!(o.status.code(), Some(1), "{}", stderr(o));
        let e = stderr(o);
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(e.contains(needle), "{e:?} lacks {needle:?}");
    };
    one_line_error(&raypack(&["render", no_cam.to_str().unwrap(), "-o", out]), "no `v` block");
    one_line_error(&raypack(&["render", "/nonexistent/scene.nff", "-o", out]), "/nonexistent/scene.nff");
    let balls = scene("balls-1.nff");
    one_line_error(&raypack(&["render", &balls, "-o", "/nonexistent/dir/x.ppm"]), "/nonexistent/dir/x.ppm");
    one_line_error(&raypack(&["render", &balls, "-o", dir.path().join("x.jpg").to_str().unwrap()]), "use a .ppm or .png");
    assert_eq!(files_in(dir.path()), [no_cam]);
}

#[test]
fn usage_errors_exit_with_2() {
    assert_eq!(raypack(&["render", &scene("balls-1.nff")]).status.code(), Some(2)); // no -o
    assert_eq!(raypack(&["render", &scene("balls-1.nff"), "-o", "x.ppm", "--packet", "3"]).status.code(), Some(2));
    assert_eq!(raypack(&["render", &scene("balls-1.nff"), "-o", "x.ppm", "--threads", "0"]).status.code(), Some(2));
    assert_eq!(raypack(&["frobnicate"]).status.code(), Some(2));
    assert!(raypack(&["--help"]).status.success());
}

#[test]
fn info_lists_counts_and_camera() {
    let o = raypack(&["info", &scene("teapot-1.nff")]);
    assert!(o.status.success());
    let s = String::from_utf8_lossy(&o.stdout);
    for needle in ["primitives  57", "patches (pp)          56", "zero-area polygons    4", "lights      2", "resolution 512x512", "bounds"] {
        assert!(s.contains(needle), "{s} lacks {needle}");
    }
}

#[test]
fn summary_and_warning_without_quiet() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t.ppm");
    let o = raypack(&["render", &scene("teapot-1.nff"), "-o", out.to_str().unwrap(), "--width", "16", "--height", "16"]);
    assert!(o.status.success());
    let e = stderr(&o);
    assert!(e.contains("warning") && e.contains("4 zero-area polygons"), "{e}");
    assert!(e.contains("16x16") && e.contains("256 primary") && e.contains("rays/s"), "{e}");
}

#[test]
fn bvh_by_default_and_accel_none_give_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    // Polygons (gears), many small overlapping spheres (shells), glass and
    // every primitive kind with planes outside the tree (extensions).
    for file in ["gears-1.nff", "shells-1.nff", "extensions.nff"] {
        let size = ["--width", "40", "--height", "32"];
        let default = render(dir.path(), "default.ppm", &scene(file), &size);
        let with = |accel: &'static str| [size.as_slice(), &["--accel", accel]].concat();
        let bvh = render(dir.path(), "bvh.ppm", &scene(file), &with("bvh"));
        let none = render(dir.path(), "none.ppm", &scene(file), &with("none"));
        assert!(default == bvh && bvh == none, "{file}: BVH and brute force differ");
    }
    let out = dir.path().join("s.ppm");
    let o = raypack(&["render", &scene("balls-1.nff"), "-o", out.to_str().unwrap(), "--width", "8", "--height", "8"]);
    assert!(stderr(&o).contains("bvh: "), "{}", stderr(&o));
    let o = raypack(&["render", &scene("balls-1.nff"), "-o", out.to_str().unwrap(), "--accel", "kd"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn scalar_fixed_renders_close_to_f32_and_rejects_out_of_range_scenes() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["--width", "32", "--height", "32"];
    let f = render(dir.path(), "f.ppm", &scene("balls-1.nff"), &args);
    let x1 = render(dir.path(), "x1.ppm", &scene("balls-1.nff"), &[&args[..], &["--scalar", "fixed", "--packet", "1", "-j", "1"]].concat());
    let x8 = render(dir.path(), "x8.ppm", &scene("balls-1.nff"), &[&args[..], &["--scalar", "fixed", "--packet", "8", "-j", "3"]].concat());
    let x16 = render(dir.path(), "x16.ppm", &scene("balls-1.nff"), &[&args[..], &["--scalar", "fixed", "--packet", "16", "-j", "2"]].concat());
    // Bit-identical across packet widths and thread counts.
    assert_eq!(x1, x8);
    assert_eq!(x1, x16);
    // Close to f32: PSNR computed over the pixel bytes (header is equal).
    assert_eq!(f.len(), x1.len());
    let se: f64 = f.iter().zip(&x1).map(|(a, b)| (*a as f64 - *b as f64).powi(2)).sum();
    let mse = se / f.len() as f64;
    assert!(mse == 0.0 || 10.0 * (255.0f64 * 255.0 / mse).log10() >= 35.0, "MSE {mse}");
    // A scene beyond the fixed-point range: a one-line error, no file; f32 renders it.
    let far = dir.path().join("far.nff");
    std::fs::write(&far, "v\nfrom 0 -9000 0\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.1\nresolution 8 8\nl 0 0 10\nf 1 1 1 1 0 1 0 1\ns 0 0 0 1\n").unwrap();
    let far_s = far.to_string_lossy().into_owned();
    let out = dir.path().join("far.ppm");
    let out_s = out.to_string_lossy().into_owned();
    let o = raypack(&["render", &far_s, "-o", &out_s, "--quiet", "--scalar", "fixed"]);
    assert!(!o.status.success());
    let msg = stderr(&o);
    assert!(msg.contains("fixed-point"), "{msg}");
    assert_eq!(msg.trim().lines().count(), 1, "{msg}");
    assert!(!out.exists());
    assert!(raypack(&["render", &far_s, "-o", &out_s, "--quiet"]).status.success());
}

#[test]
fn every_instruction_set_gives_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let mut reference: Option<Vec<u8>> = None;
    let mut ran = Vec::new();
    for isa in ["baseline", "avx2", "avx512", "auto"] {
        for packet in ["1", "8", "16"] {
            let out = dir.path().join(format!("{isa}-{packet}.ppm"));
            let o = raypack(&["render", &scene("extensions.nff"), "-o", out.to_str().unwrap(), "--width", "56", "--height", "40", "--isa", isa, "--packet", packet, "-j", "2"]);
            if !o.status.success() {
                // Only an ISA this CPU lacks may fail, with a clear message.
                assert_eq!(o.status.code(), Some(1));
                assert!(isa.starts_with("avx") && stderr(&o).contains(&format!("this CPU cannot run --isa {isa}")), "{isa}: {}", stderr(&o));
                continue;
            }
            // The summary names the instruction set the tiles ran with:
            // packets narrower than 8 always run the baseline copy, 8 and 16
            // the one asked for.
            let used = if packet == "1" { "baseline" } else if isa == "auto" { "" } else { isa };
            assert!(stderr(&o).contains(&format!(", isa {used}")), "{}", stderr(&o));
            let bytes = std::fs::read(&out).unwrap();
            match &reference {
                None => reference = Some(bytes),
                Some(r) => assert!(r == &bytes, "--isa {isa} --packet {packet} differs from baseline"),
            }
            ran.push(isa);
        }
    }
    eprintln!("instruction sets run: {ran:?}");
    assert!(ran.contains(&"baseline") && ran.contains(&"auto"));
    assert_eq!(raypack(&["render", &scene("balls-1.nff"), "-o", "x.ppm", "--isa", "sse9"]).status.code(), Some(2));
}

/// `key=value` fields of a `bench` line.
fn fields(line: &str) -> std::collections::HashMap<&str, &str> {
    line.split(' ').skip(1).filter_map(|f| f.split_once('=')).collect()
}

#[test]
fn bench_prints_one_line_per_measurement() {
    let o = raypack(&["bench", &scene("balls-1.nff"), "--width", "40", "--height", "24", "--rounds", "2", "--packet", "1,8", "-j", "1,2", "--isa", "baseline"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[0].starts_with("# raypack-bench 1 ") && lines[0].contains(" cores="), "{out}");
    assert!(lines[1].contains("scene=balls-1 primitives=11 lights=3 size=40x24 scalar=f32 accel=bvh"), "{out}");
    let bench: Vec<_> = lines.iter().filter(|l| l.starts_with("bench ")).map(|l| fields(l)).collect();
    // 2 measurements × 2 packet widths × 2 thread counts, nothing else.
    assert_eq!(bench.len(), 8, "{out}");
    assert_eq!(lines.len(), 10, "{out}");
    let mut whitted_rays = None;
    for f in &bench {
        for key in ["scene", "size", "scalar", "accel", "measure", "isa", "packet", "threads", "rays", "best_s", "median_s", "mrays_per_s", "vs_packet1", "vs_1thread", "lanes_primary", "lanes_shadow", "lanes_reflected", "lanes_refracted"] {
            assert!(f.contains_key(key), "{key} missing in {f:?}");
        }
        // Lanes per packet: 1 at packet 1, between 1 and the width otherwise
        // (40 × 24 pixels fill every primary packet of 8).
        let packet: f64 = f["packet"].parse().unwrap();
        assert_eq!(f["lanes_primary"], format!("{packet:.2}"), "{f:?}");
        for kind in ["shadow", "reflected", "refracted"] {
            let lanes: f64 = f[&*format!("lanes_{kind}")].parse().unwrap();
            let traced = f["measure"] == "whitted" && (kind == "shadow" || lanes > 0.0);
            assert!(if traced { (1.0..=packet).contains(&lanes) } else { lanes == 0.0 }, "{kind}: {f:?}");
        }
        let best: f64 = f["best_s"].parse().unwrap();
        let median: f64 = f["median_s"].parse().unwrap();
        assert!(best > 0.0 && best <= median, "{f:?}");
        let rays: u64 = f["rays"].parse().unwrap();
        match f["measure"] {
            // One primary ray per pixel.
            "primary" => assert_eq!(rays, 40 * 24),
            // Shadow and secondary rays too, the same count in every configuration.
            "whitted" => {
                assert!(rays > 40 * 24);
                assert_eq!(*whitted_rays.get_or_insert(rays), rays);
            }
            other => panic!("unknown measure {other}"),
        }
        let rate: f64 = f["mrays_per_s"].parse().unwrap();
        assert!((rate - rays as f64 / best / 1e6).abs() <= 0.001 + 1e-3 * rate, "{f:?}");
        if f["packet"] == "1" {
            assert_eq!(f["vs_packet1"], "1.00");
        }
        if f["threads"] == "1" {
            assert_eq!(f["vs_1thread"], "1.00");
        }
    }
    // Fixed point runs on the baseline whatever is asked.
    let o = raypack(&["bench", &scene("balls-1.nff"), "--width", "16", "--height", "16", "--rounds", "1", "--packet", "4", "-j", "1", "--scalar", "fixed"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    assert!(out.lines().filter(|l| l.starts_with("bench ")).all(|l| fields(l)["isa"] == "baseline" && fields(l)["scalar"] == "fixed"), "{out}");
    // Errors: a bad scene names its line; bad arguments exit with 2.
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.nff");
    std::fs::write(&bad, "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 8\nf 1 0 0 1 0 0 0 1\ns 0 0 0 zero\n").unwrap();
    let o = raypack(&["bench", bad.to_str().unwrap(), "--rounds", "1"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("bad.nff: line 9, column 9"), "{}", stderr(&o));
    assert_eq!(raypack(&["bench", &scene("balls-1.nff"), "--packet", "3"]).status.code(), Some(2));
    assert_eq!(raypack(&["bench", &scene("balls-1.nff"), "--rounds", "0"]).status.code(), Some(2));
}
