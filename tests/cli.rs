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
    for (file, size) in
        [("extensions.nff", ["--width", "72", "--height", "54"]), ("teapot-1.nff", ["--width", "48", "--height", "40"])]
    {
        let mut reference: Option<Vec<u8>> = None;
        for (threads, packet, bvh) in [
            ("1", "1", ""),
            ("2", "4", ""),
            ("4", "8", ""),
            ("3", "16", ""),
            ("1", "8", "--accel=none"),
            ("2", "16", "--accel=none"),
            ("4", "1", "--accel=none"),
            ("2", "1", ""),
        ] {
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
    let ids: Vec<u32> =
        images[3][header..].chunks(3).map(|p| (p[0] as u32) << 16 | (p[1] as u32) << 8 | p[2] as u32).collect();
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
    assert!(
        err.starts_with("raypack: error: ") && err.contains("bad.nff: line 3, column 7: expected a number, found `O`"),
        "{err}"
    );
    assert!(!out.exists());
    assert_eq!(files_in(dir.path()), std::slice::from_ref(&bad), "temporary files left behind");

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
    one_line_error(
        &raypack(&["render", &balls, "-o", dir.path().join("x.jpg").to_str().unwrap()]),
        "use a .ppm or .png",
    );
    assert_eq!(files_in(dir.path()), [no_cam]);
}

#[test]
fn usage_errors_exit_with_2() {
    assert_eq!(raypack(&["render"]).status.code(), Some(2)); // no scene
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
    for needle in [
        "primitives  57",
        "patches (pp)          56",
        "zero-area polygons    4",
        "lights      2",
        "resolution 512x512",
        "bounds",
    ] {
        assert!(s.contains(needle), "{s} lacks {needle}");
    }
}

#[test]
fn summary_and_warning_without_quiet() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t.ppm");
    let o =
        raypack(&["render", &scene("teapot-1.nff"), "-o", out.to_str().unwrap(), "--width", "16", "--height", "16"]);
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
    let x1 = render(
        dir.path(),
        "x1.ppm",
        &scene("balls-1.nff"),
        &[&args[..], &["--scalar", "fixed32", "--packet", "1", "-j", "1"]].concat(),
    );
    let x8 = render(
        dir.path(),
        "x8.ppm",
        &scene("balls-1.nff"),
        &[&args[..], &["--scalar", "fixed32", "--packet", "8", "-j", "3"]].concat(),
    );
    let x16 = render(
        dir.path(),
        "x16.ppm",
        &scene("balls-1.nff"),
        &[&args[..], &["--scalar", "fixed32", "--packet", "16", "-j", "2"]].concat(),
    );
    // Bit-identical across packet widths and thread counts.
    assert_eq!(x1, x8);
    assert_eq!(x1, x16);
    // Close to f32: PSNR computed over the pixel bytes (header is equal).
    assert_eq!(f.len(), x1.len());
    let se: f64 = f.iter().zip(&x1).map(|(a, b)| (*a as f64 - *b as f64).powi(2)).sum();
    let mse = se / f.len() as f64;
    assert!(mse == 0.0 || 10.0 * (255.0f64 * 255.0 / mse).log10() >= 35.0, "MSE {mse}");
    // A scene beyond the fixed-point range (a light 10⁵ scene sizes away,
    // beyond what the frame allows lights): a one-line error, no file; f32
    // renders it.
    let far = dir.path().join("far.nff");
    std::fs::write(&far, "v\nfrom 0 -5 0\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.1\nresolution 8 8\nl 0 0 500000\nf 1 1 1 1 0 1 0 1\ns 0 0 0 1\n").unwrap();
    let far_s = far.to_string_lossy().into_owned();
    let out = dir.path().join("far.ppm");
    let out_s = out.to_string_lossy().into_owned();
    let o = raypack(&["render", &far_s, "-o", &out_s, "--quiet", "--scalar", "fixed32"]);
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
            let o = raypack(&[
                "render",
                &scene("extensions.nff"),
                "-o",
                out.to_str().unwrap(),
                "--width",
                "56",
                "--height",
                "40",
                "--isa",
                isa,
                "--packet",
                packet,
                "-j",
                "2",
            ]);
            if !o.status.success() {
                // Only an ISA this CPU lacks may fail, with a clear message.
                assert_eq!(o.status.code(), Some(1));
                assert!(
                    isa.starts_with("avx") && stderr(&o).contains(&format!("this CPU cannot run --isa {isa}")),
                    "{isa}: {}",
                    stderr(&o)
                );
                continue;
            }
            // The summary names the instruction set the tiles ran with:
            // packets narrower than 8 always run the baseline copy, 8 and 16
            // the one asked for.
            let used = if packet == "1" {
                "baseline"
            } else if isa == "auto" {
                ""
            } else {
                isa
            };
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
    let o = raypack(&[
        "bench",
        &scene("balls-1.nff"),
        "--width",
        "40",
        "--height",
        "24",
        "--rounds",
        "2",
        "--packet",
        "1,8",
        "-j",
        "1,2",
        "--isa",
        "baseline",
    ]);
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
        for key in [
            "scene",
            "size",
            "scalar",
            "accel",
            "measure",
            "isa",
            "packet",
            "threads",
            "rays",
            "best_s",
            "median_s",
            "mrays_per_s",
            "mrays_min",
            "mrays_max",
            "vs_packet1",
            "vs_1thread",
            "lanes_primary",
            "lanes_shadow",
            "lanes_reflected",
            "lanes_refracted",
        ] {
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
        // The rate of the median time, with the slowest and fastest round's.
        let close = |a: f64, b: f64| (a - b).abs() <= 0.001 + 1e-3 * a;
        let rate: f64 = f["mrays_per_s"].parse().unwrap();
        let (lo, hi): (f64, f64) = (f["mrays_min"].parse().unwrap(), f["mrays_max"].parse().unwrap());
        assert!(close(rate, rays as f64 / median / 1e6), "{f:?}");
        assert!(close(hi, rays as f64 / best / 1e6), "{f:?}");
        assert!(lo <= rate && rate <= hi, "{f:?}");
        if f["packet"] == "1" {
            assert_eq!(f["vs_packet1"], "1.00");
        }
        if f["threads"] == "1" {
            assert_eq!(f["vs_1thread"], "1.00");
        }
    }
    // Fixed point runs on the baseline whatever is asked.
    let o = raypack(&[
        "bench",
        &scene("balls-1.nff"),
        "--width",
        "16",
        "--height",
        "16",
        "--rounds",
        "1",
        "--packet",
        "4",
        "-j",
        "1",
        "--scalar",
        "fixed32",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    assert!(
        out.lines()
            .filter(|l| l.starts_with("bench "))
            .all(|l| fields(l)["isa"] == "baseline" && fields(l)["scalar"] == "fixed32"),
        "{out}"
    );
    // Errors: a bad scene names its line; bad arguments exit with 2.
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.nff");
    std::fs::write(
        &bad,
        "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 8\nf 1 0 0 1 0 0 0 1\ns 0 0 0 zero\n",
    )
    .unwrap();
    let o = raypack(&["bench", bad.to_str().unwrap(), "--rounds", "1"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("bad.nff: line 9, column 9"), "{}", stderr(&o));
    // An error of the measurement itself (a scene without a camera loads,
    // but cannot be rendered) names the file too.
    let nocam = dir.path().join("nocam.nff");
    std::fs::write(&nocam, "f 1 0 0 1 0 0 0 1\ns 0 0 0 1\n").unwrap();
    let o = raypack(&["bench", nocam.to_str().unwrap(), "--rounds", "1"]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.starts_with("raypack: error: ") && err.contains("nocam.nff: "), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    // A file that cannot be read, and an instruction set this CPU lacks
    // (where it lacks one), name the file as well.
    let missing = dir.path().join("missing.nff");
    let o = raypack(&["bench", missing.to_str().unwrap(), "--rounds", "1"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).starts_with(&format!("raypack: error: {}: ", missing.display())), "{}", stderr(&o));
    let o = raypack(&[
        "bench",
        &scene("balls-1.nff"),
        "--rounds",
        "1",
        "--width",
        "8",
        "--height",
        "8",
        "--isa",
        "avx2,avx512",
    ]);
    if !o.status.success() {
        let err = stderr(&o);
        assert!(err.contains("balls-1.nff: this CPU cannot run --isa"), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
    assert_eq!(raypack(&["bench", &scene("balls-1.nff"), "--packet", "3"]).status.code(), Some(2));
    assert_eq!(raypack(&["bench", &scene("balls-1.nff"), "--rounds", "0"]).status.code(), Some(2));
}

/// Runs raypack in `dir` with `stdin` as standard input.
fn raypack_in(dir: &Path, args: &[&str], stdin: &[u8]) -> Output {
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_raypack"))
        .args(args)
        .current_dir(dir)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run raypack");
    // A run that fails before reading its input (a usage error) may have
    // exited already: its closed pipe is not the test's failure.
    match child.stdin.take().unwrap().write_all(stdin) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {}
        other => other.unwrap(),
    }
    child.wait_with_output().unwrap()
}

#[test]
fn pipes_standard_input_and_output() {
    let dir = tempfile::tempdir().unwrap();
    let size = ["--width", "24", "--height", "18"];
    let file = render(dir.path(), "f.ppm", &scene("balls-1.nff"), &size);
    let text = std::fs::read(scene("balls-1.nff")).unwrap();
    // `balls | raypack render - -o -`: PPM on standard output by default.
    let o = raypack_in(dir.path(), &[&["render", "-", "-o", "-", "-q"][..], &size].concat(), &text);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(o.stdout == file);
    // --format png on standard output; the summary (stderr) names it.
    let o = raypack_in(dir.path(), &[&["render", "-", "-o", "-", "--format", "png"][..], &size].concat(), &text);
    assert!(o.status.success() && o.stdout.starts_with(b"\x89PNG"), "{}", stderr(&o));
    assert!(stderr(&o).contains("raypack: standard output: 24x18"), "{}", stderr(&o));
    // --format where the name has no extension; a conflicting one is an error.
    let o =
        raypack_in(dir.path(), &[&["render", "-", "-o", "noext", "--format", "ppm", "-q"][..], &size].concat(), &text);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read(dir.path().join("noext")).unwrap() == file);
    let o = raypack_in(dir.path(), &["render", "-", "-o", "x.png", "--format", "ppm"], &text);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("the extension says png but --format says ppm"), "{}", stderr(&o));
    // Errors in a piped scene name standard input and the line.
    let o = raypack_in(
        dir.path(),
        &["render", "-", "-o", "-"],
        b"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 8\ns 0 0 zero 1\n",
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("standard input: line 8"), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
    // Without -o, a piped scene has no name to derive one from: a usage error.
    assert_eq!(raypack_in(dir.path(), &["render", "-"], &text).status.code(), Some(2));
    // `info -` reads standard input too.
    let o = raypack_in(dir.path(), &["info", "-"], &text);
    assert!(o.status.success() && String::from_utf8_lossy(&o.stdout).contains("primitives  11"));
}

#[test]
fn default_output_is_the_scene_stem_and_never_overwrites_without_force() {
    let dir = tempfile::tempdir().unwrap();
    let size = ["--width", "16", "--height", "12"];
    let o = raypack_in(dir.path(), &[&["render", &scene("balls-1.nff")][..], &size].concat(), b"");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).starts_with("raypack: balls-1.png: 16x12"), "{}", stderr(&o));
    let out = dir.path().join("balls-1.png");
    let first = std::fs::read(&out).unwrap();
    assert!(first.starts_with(b"\x89PNG"));
    // A second run refuses, and leaves the file (and nothing else) there.
    std::fs::write(&out, b"mine").unwrap();
    let o = raypack_in(dir.path(), &[&["render", &scene("balls-1.nff")][..], &size].concat(), b"");
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("balls-1.png: already exists (use --force"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&out).unwrap(), b"mine");
    assert_eq!(files_in(dir.path()), std::slice::from_ref(&out));
    // --force replaces it; --format ppm changes the default extension.
    assert!(raypack_in(dir.path(), &[&["render", &scene("balls-1.nff"), "--force", "-q"][..], &size].concat(), b"")
        .status
        .success());
    assert_eq!(std::fs::read(&out).unwrap(), first);
    assert!(raypack_in(
        dir.path(),
        &[&["render", &scene("balls-1.nff"), "--format", "ppm", "-q"][..], &size].concat(),
        b""
    )
    .status
    .success());
    assert!(dir.path().join("balls-1.ppm").exists());
}

/// The pixels of a PPM, PNG or part file (header and metadata skipped).
fn pixels_of(bytes: &[u8]) -> (u32, u32, Vec<u8>) {
    if bytes.starts_with(b"\x89PNG") {
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes)).read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let frame = reader.next_frame(&mut buf).unwrap();
        buf.truncate(frame.buffer_size());
        return (frame.width, frame.height, buf);
    }
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(200)]).into_owned();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(lines.next(), Some("P6"));
    let (w, h) = lines.next().unwrap().split_once(' ').unwrap();
    let header: usize = text.lines().take_while(|l| *l != "255").map(|l| l.len() + 1).sum::<usize>() + 4;
    (w.parse().unwrap(), h.parse().unwrap(), bytes[header..].to_vec())
}

fn crop(px: &[u8], width: u32, x: u32, y: u32, w: u32, h: u32) -> Vec<u8> {
    (y..y + h).flat_map(|r| px[((r * width + x) * 3) as usize..((r * width + x + w) * 3) as usize].to_vec()).collect()
}

#[test]
fn regions_are_byte_identical_crops_at_any_width_thread_count_isa_and_sampling() {
    let dir = tempfile::tempdir().unwrap();
    for aa in [&[][..], &["--samples", "2"][..], &["--adaptive", "0.2"][..]] {
        let size = [&["--width", "50", "--height", "38"][..], aa].concat();
        let (_, _, full) = pixels_of(&render(dir.path(), "full.ppm", &scene("extensions.nff"), &size));
        for (k, (region, packet, threads, isa)) in [
            ("0,0,50,38", "1", "1", "baseline"),
            ("3,5,30,31", "16", "2", "auto"),
            ("33,1,17,2", "4", "3", "auto"),
            ("49,37,1,1", "8", "1", "avx2"),
            ("7,0,9,38", "8", "2", "baseline"),
        ]
        .into_iter()
        .enumerate()
        {
            let args = [&size[..], &["--region", region, "--packet", packet, "-j", threads, "--isa", isa]].concat();
            let out = dir.path().join(format!("part{k}.ppm"));
            let o = raypack(
                &[&["render", &scene("extensions.nff"), "-o", out.to_str().unwrap(), "-q"][..], &args].concat(),
            );
            if !o.status.success() {
                assert!(stderr(&o).contains("this CPU cannot run --isa avx2"), "{}", stderr(&o));
                continue;
            }
            let bytes = std::fs::read(&out).unwrap();
            let text = String::from_utf8_lossy(&bytes[..60]).into_owned();
            let r: Vec<u32> = region.split(',').map(|v| v.parse().unwrap()).collect();
            assert!(
                text.starts_with(&format!(
                    "P6\n# raypack-region x={} y={} w={} h={} full=50x38 render=",
                    r[0], r[1], r[2], r[3]
                )),
                "{text}"
            );
            let (w, h, px) = pixels_of(&bytes);
            assert_eq!((w, h), (r[2], r[3]));
            assert!(px == crop(&full, 50, r[0], r[1], r[2], r[3]), "{aa:?} region {region} packet {packet}");
        }
    }
    // Not inside the image: exit 1 naming the image size; bad syntax: exit 2.
    let o = raypack(&[
        "render",
        &scene("balls-1.nff"),
        "-o",
        dir.path().join("x.ppm").to_str().unwrap(),
        "--width",
        "20",
        "--height",
        "10",
        "--region",
        "10,0,11,5",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("region 10,0,11,5 is not inside the 20x10 image"), "{}", stderr(&o));
    for bad in ["1,2,3", "0,0,0,4", "a,b,c,d", "1,2,3,4,5"] {
        assert_eq!(
            raypack(&["render", &scene("balls-1.nff"), "-o", "x.ppm", "--region", bad]).status.code(),
            Some(2),
            "{bad}"
        );
    }
}

/// The render farm of docs/render-farm.md: four parts, rendered one
/// process each as a batch scheduler would run them, stitched, and compared
/// byte for byte with the one-piece render (PNG and PPM).
#[test]
fn split_render_stitch_on_four_parts_equals_the_one_piece_render() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["png", "ppm"] {
        let size = ["--width", "61", "--height", "45", "--adaptive", "0.3"];
        let whole = render(dir.path(), &format!("whole.{ext}"), &scene("balls-1.nff"), &size);
        // Four horizontal strips of ceil(45 / 4) = 12 rows, the last one shorter.
        let mut parts = Vec::new();
        for i in 0..4u32 {
            let (y, h) = (i * 12, 12.min(45 - i * 12));
            let part = format!("part-{i}.{ext}");
            let region = format!("0,{y},61,{h}");
            render(
                dir.path(),
                &part,
                &scene("balls-1.nff"),
                &[&size[..], &["--region", &region, "--packet", ["1", "4", "8", "16"][i as usize]]].concat(),
            );
            parts.push(dir.path().join(part).to_string_lossy().into_owned());
        }
        let out = dir.path().join(format!("stitched.{ext}"));
        let o = raypack(
            &[&["stitch"][..], &parts.iter().map(String::as_str).collect::<Vec<_>>(), &["-o", out.to_str().unwrap()]]
                .concat(),
        );
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(stderr(&o).contains("61x45 from 4 parts"), "{}", stderr(&o));
        assert!(std::fs::read(&out).unwrap() == whole, "{ext}: stitched differs from the one-piece render");
    }
}

#[test]
fn stitch_refuses_parts_that_do_not_tile_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let part = |name: &str, region: &str, extra: &[&str]| {
        render(
            dir.path(),
            name,
            &scene("balls-1.nff"),
            &[&["--width", "20", "--height", "10", "--region", region][..], extra].concat(),
        );
        dir.path().join(name).to_string_lossy().into_owned()
    };
    let a = part("a.ppm", "0,0,10,10", &[]);
    let b = part("b.png", "10,0,10,10", &[]);
    let over = part("over.ppm", "5,0,10,10", &[]);
    let other = part("other.ppm", "10,0,10,10", &["--samples", "2"]);
    let out = dir.path().join("out.png");
    let out_s = out.to_string_lossy().into_owned();
    let fails = |parts: &[&str], needle: &str| {
        let o = raypack(&[&["stitch"][..], parts, &["-o", &out_s]].concat());
        assert_eq!(o.status.code(), Some(1), "{parts:?}: {}", stderr(&o));
        assert_eq!(stderr(&o).lines().count(), 1, "{}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{parts:?}: {} lacks {needle}", stderr(&o));
        assert!(!out.exists());
    };
    // A PPM part and a PNG part stitch together.
    assert!(raypack(&["stitch", &a, &b, "-o", &out_s, "-q"]).status.success());
    std::fs::remove_file(&out).unwrap();
    fails(&[&a], "the parts leave a gap: no part covers pixel (10, 0) (100 pixels of the 20x10 image uncovered)");
    fails(&[&a, &over, &b], "overlap at pixel (5, 0)");
    fails(&[&a, &other], "part of another render");
    let big = {
        render(
            dir.path(),
            "big.ppm",
            &scene("balls-1.nff"),
            &["--width", "30", "--height", "10", "--region", "10,0,10,10"],
        );
        dir.path().join("big.ppm").to_string_lossy().into_owned()
    };
    fails(&[&a, &big], "part of a 30x10 image, but");
    let plain = {
        render(dir.path(), "plain.ppm", &scene("balls-1.nff"), &["--width", "20", "--height", "10"]);
        dir.path().join("plain.ppm").to_string_lossy().into_owned()
    };
    fails(&[&plain], "no raypack-region");
    // A part whose pixels disagree with its region, and files that are no image.
    let bytes = std::fs::read(&a).unwrap();
    let cut = dir.path().join("cut.ppm");
    std::fs::write(&cut, &bytes[..bytes.len() - 3]).unwrap();
    fails(&[cut.to_str().unwrap()], "bytes of pixels");
    let lie = dir.path().join("lie.ppm");
    let at = bytes.windows(4).position(|w| w == b"w=10").unwrap();
    let mut lied = bytes.clone();
    lied[at + 3] = b'1';
    std::fs::write(&lie, lied).unwrap();
    fails(&[lie.to_str().unwrap()], "10x10 pixels, but its region says 11x10");
    let junk = dir.path().join("junk.ppm");
    std::fs::write(&junk, b"hello").unwrap();
    fails(&[junk.to_str().unwrap()], "neither a PNG nor a binary PPM");
    fails(&["/nonexistent/p.ppm"], "/nonexistent/p.ppm");
    assert_eq!(raypack(&["stitch", "-o", &out_s]).status.code(), Some(2));
}

#[test]
fn anti_aliasing_is_deterministic_and_reports_its_cost() {
    let dir = tempfile::tempdir().unwrap();
    let size = ["--width", "40", "--height", "30"];
    let plain = render(dir.path(), "plain.ppm", &scene("extensions.nff"), &size);
    for aa in [["--samples", "3"], ["--adaptive", "0.3"]] {
        let mut reference: Option<Vec<u8>> = None;
        for (packet, threads, isa) in [
            ("1", "1", "baseline"),
            ("4", "2", "baseline"),
            ("8", "3", "auto"),
            ("16", "1", "auto"),
            ("8", "2", "avx2"),
        ] {
            let args = [&size[..], &aa, &["--packet", packet, "-j", threads, "--isa", isa]].concat();
            let out = dir.path().join("aa.ppm");
            let o = raypack(&[&["render", &scene("extensions.nff"), "-o", out.to_str().unwrap()][..], &args].concat());
            if !o.status.success() {
                assert!(stderr(&o).contains("this CPU cannot run --isa"), "{}", stderr(&o));
                continue;
            }
            assert!(
                stderr(&o).contains("raypack: anti-aliasing: ")
                    && stderr(&o).contains("primary rays per pixel (1 without)"),
                "{}",
                stderr(&o)
            );
            let bytes = std::fs::read(&out).unwrap();
            match &reference {
                None => reference = Some(bytes),
                Some(r) => assert!(*r == bytes, "{aa:?} packet {packet} threads {threads} isa {isa} differ"),
            }
        }
        assert!(reference.unwrap() != plain, "{aa:?} changed nothing");
    }
    // Usage errors: --adaptive with one sample, AA of a non-colour AOV, bad values.
    for bad in [
        &["--adaptive", "0.3", "--samples", "1"][..],
        &["--samples", "2", "--aov", "depth"],
        &["--adaptive", "4"],
        &["--adaptive", "x"],
        &["--samples", "0"],
        &["--samples", "17"],
    ] {
        assert_eq!(
            raypack(&[&["render", &scene("balls-1.nff"), "-o", "x.ppm"][..], bad].concat()).status.code(),
            Some(2),
            "{bad:?}"
        );
    }
}

#[test]
fn version_and_bench_of_both_accelerators() {
    let o = raypack(&["--version"]);
    assert!(o.status.success());
    assert_eq!(String::from_utf8_lossy(&o.stdout).trim(), format!("raypack {}", env!("CARGO_PKG_VERSION")));
    let o = raypack(&[
        "bench",
        &scene("balls-1.nff"),
        "--width",
        "16",
        "--height",
        "16",
        "--rounds",
        "2",
        "--packet",
        "8",
        "-j",
        "1",
        "--accel",
        "bvh,none",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    assert!(out.lines().nth(1).unwrap().contains("accel=bvh nodes="), "{out}");
    let bench: Vec<_> = out.lines().filter(|l| l.starts_with("bench ")).map(fields).collect();
    assert_eq!(bench.len(), 4, "{out}");
    for measure in ["primary", "whitted"] {
        let rays: Vec<_> = ["bvh", "none"]
            .iter()
            .map(|a| bench.iter().find(|f| f["measure"] == measure && f["accel"] == *a).expect(a)["rays"])
            .collect();
        assert_eq!(rays[0], rays[1], "{out}");
    }
}

/// The summary reports the packet width that really ran: fixed point one
/// ray per packet whatever `--packet` asks, `f32` the width asked, and
/// without `--packet` 16 under AVX2/AVX-512 and 8 on the baseline.
#[test]
fn summary_reports_the_packet_width_that_ran() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p.ppm");
    let out_s = out.to_string_lossy().into_owned();
    let summary = |extra: &[&str]| {
        let mut args = vec!["render", "--width", "16", "--height", "16", "-o", &out_s];
        args.extend_from_slice(extra);
        let s = scene("balls-1.nff");
        args.push(&s);
        let o = raypack(&args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        stderr(&o).lines().next().unwrap_or_default().to_owned()
    };
    let fixed = summary(&["--scalar", "fixed32", "--packet", "16"]);
    assert!(fixed.contains("packet 1, isa baseline"), "{fixed}");
    let f32_4 = summary(&["--packet", "4"]);
    assert!(f32_4.contains("packet 4, isa baseline"), "{f32_4}");
    let baseline = summary(&["--isa", "baseline"]);
    assert!(baseline.contains("packet 8, isa baseline"), "{baseline}");
    let auto = summary(&[]);
    assert!(auto.contains("packet 16, isa avx") || auto.contains("packet 8, isa baseline"), "{auto}");
}

#[test]
fn a_closed_pipe_on_standard_output_ends_quietly() {
    use std::io::Read;
    // `raypack render … -o - | head -c 10`: 768 KB of PPM (or a PNG of
    // some 100 KB), more than a pipe holds, so the writes meet the closed
    // pipe. Exit 0 and nothing on stderr (with -q; without it, the summary
    // only).
    for (format, quiet) in [("ppm", true), ("png", true), ("ppm", false)] {
        let mut args =
            vec!["render", "-", "-o", "-", "--format", format, "--width", "512", "--height", "512", "-j", "1"];
        if quiet {
            args.push("-q");
        }
        let mut child = Command::new(env!("CARGO_BIN_EXE_raypack"))
            .args(&args)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("run raypack");
        {
            use std::io::Write;
            let mut stdin = child.stdin.take().unwrap();
            stdin.write_all(&std::fs::read(scene("balls-1.nff")).unwrap()).unwrap();
        }
        let mut stdout = child.stdout.take().unwrap();
        let mut head = [0u8; 10];
        stdout.read_exact(&mut head).unwrap();
        drop(stdout);
        let o = child.wait_with_output().unwrap();
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(0), "{format}: {err}");
        assert!(!err.contains("Broken pipe") && !err.contains("error"), "{format}: {err}");
        if quiet {
            assert!(err.is_empty(), "{format}: {err}");
        }
        assert!(head.starts_with(if format == "ppm" { b"P6\n512 512" } else { b"\x89PNG" }));
    }
}

/// Runs raypack with standard output a pipe the test closes after reading
/// `lines` lines (0: before raypack writes anything, so its first write
/// meets the closed pipe); returns the exit code and standard error.
fn with_stdout_closed_after(args: &[&str], lines: usize) -> (Option<i32>, String) {
    use std::io::BufRead;
    let mut child = Command::new(env!("CARGO_BIN_EXE_raypack"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run raypack");
    let mut stdout = std::io::BufReader::new(child.stdout.take().unwrap());
    for _ in 0..lines {
        let mut line = String::new();
        assert!(stdout.read_line(&mut line).unwrap() > 0, "{args:?}: output ended before line {lines}");
    }
    drop(stdout);
    let o = child.wait_with_output().unwrap();
    (o.status.code(), stderr(&o))
}

#[test]
fn a_closed_or_full_standard_error_does_not_panic() {
    // `raypack render … 2>&1 | head -c 0` and `2>/dev/full`: the summary (or
    // the error line) is lost, and the exit status is the command's own:
    // 0 for a render, 1 for a bad scene; never a panic (101).
    let out = std::env::temp_dir().join(format!("raypack-closed-stderr-{}.ppm", std::process::id()));
    let balls = scene("balls-1.nff");
    let render = ["render", &balls, "-o", out.to_str().unwrap(), "--width", "256", "--height", "256", "-j", "1"];
    let mut child = Command::new(env!("CARGO_BIN_EXE_raypack"))
        .args(render)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run raypack");
    drop(child.stderr.take());
    assert_eq!(child.wait().unwrap().code(), Some(0), "render with a closed stderr");
    assert!(std::fs::metadata(&out).map(|m| m.len() > 0).unwrap_or(false), "the image was written");
    let _ = std::fs::remove_file(&out);
    if Path::new("/dev/full").exists() {
        let missing = ["render", "no-such-scene.nff", "-o", out.to_str().unwrap()];
        for (args, code) in [(&render[..], 0), (&missing[..], 1)] {
            let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
            let status = Command::new(env!("CARGO_BIN_EXE_raypack"))
                .args(args)
                .stdout(std::process::Stdio::null())
                .stderr(full)
                .status()
                .expect("run raypack");
            assert_eq!(status.code(), Some(code), "{args:?} with stderr on /dev/full");
        }
        let _ = std::fs::remove_file(&out);
    }
}

#[test]
fn bench_and_info_end_quietly_on_a_closed_pipe() {
    // `raypack bench … | head -1`, `raypack info … | head -1`, and a reader
    // that closes before the first line: exit 0, nothing on stderr (no
    // "Broken pipe", no panic).
    let balls = scene("balls-1.nff");
    let bench = ["bench", &balls, "--width", "32", "--height", "32", "--rounds", "2", "--packet", "1,8", "-j", "1"];
    let info = ["info", &balls];
    for (args, lines) in [(&bench[..], 0), (&bench[..], 1), (&info[..], 0), (&info[..], 1)] {
        let (code, err) = with_stdout_closed_after(args, lines);
        assert_eq!(code, Some(0), "{} after {lines} lines: {err}", args[0]);
        assert!(!err.contains("panicked") && !err.contains("Broken pipe"), "{} after {lines} lines: {err}", args[0]);
        assert!(err.is_empty(), "{} after {lines} lines: {err}", args[0]);
    }
    // Any other write error is one, with exit code 1.
    if Path::new("/dev/full").exists() {
        for args in [&bench[..], &info[..]] {
            let o = Command::new(env!("CARGO_BIN_EXE_raypack"))
                .args(args)
                .stdout(std::fs::File::options().write(true).open("/dev/full").unwrap())
                .output()
                .expect("run raypack");
            let err = stderr(&o);
            assert_eq!(o.status.code(), Some(1), "{}: {err}", args[0]);
            assert!(err.starts_with("raypack: error: ") && err.contains("standard output: "), "{}: {err}", args[0]);
            assert!(!err.contains("panicked"), "{}: {err}", args[0]);
        }
    }
}

#[test]
fn a_scene_that_is_not_utf8_fails_with_a_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("latin1.nff");
    // Line 3, after 6 characters (one of them a two-byte é): a Latin-1 byte.
    std::fs::write(&bad, b"v\nfrom 0 0 5\n# caf\xc3\xa9 \xe9t\xe9\n").unwrap();
    for cmd in ["render", "info", "bench"] {
        let mut args = vec![cmd, bad.to_str().unwrap()];
        if cmd == "render" {
            args.extend(["-o", "-"]);
        }
        let o = raypack(&args);
        assert_eq!(o.status.code(), Some(1), "{cmd}");
        let err = stderr(&o);
        assert!(err.contains("latin1.nff: line 3, column 8: not UTF-8 text (byte 0xe9)"), "{cmd}: {err}");
        assert_eq!(err.lines().count(), 1, "{cmd}: {err}");
    }
    // From standard input, named so.
    let o = raypack_in(dir.path(), &["render", "-", "-o", "-"], b"v\n\xff");
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("standard input: line 2, column 1: not UTF-8 text (byte 0xff)"), "{}", stderr(&o));
}

/// `raypack bake`: every primitive of the file in the statics, the camera
/// for the size asked, the same source through `-o` as on standard output,
/// and a one-line error naming a file that is not there.
#[test]
fn bake_writes_the_scene_as_statics() {
    let o = raypack(&["bake", &scene("teapot-1.nff"), "--width", "64", "--height", "48"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = String::from_utf8(o.stdout.clone()).unwrap();
    assert!(s.contains("pub static PRIMITIVES: [raypack::scene::Primitive<raypack::Fixed32>; 57] = ["), "{s}");
    assert_eq!(s.matches("raypack::scene::Primitive::from_baked(").count(), 57);
    assert!(s.contains(", 64, 48, raypack::num::scalar::Divisor::new(64), raypack::num::scalar::Divisor::new(48), "));
    let f = raypack(&["bake", &scene("teapot-1.nff"), "--scalar", "f32"]);
    assert!(f.status.success(), "{}", stderr(&f));
    let fs = String::from_utf8_lossy(&f.stdout);
    assert!(fs.contains("pub static PRIMITIVES: [raypack::scene::Primitive<f32>; 57] = ["));
    // The file's size by default (teapot-1: 512×512).
    assert!(
        fs.contains(", 512, 512, raypack::num::scalar::Divisor::new(512), raypack::num::scalar::Divisor::new(512), ")
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("scene.rs");
    let w = raypack(&["bake", &scene("teapot-1.nff"), "--width", "64", "--height", "48", "-o", out.to_str().unwrap()]);
    assert!(w.status.success() && w.stdout.is_empty(), "{}", stderr(&w));
    assert_eq!(std::fs::read(&out).unwrap(), o.stdout);
    let missing = raypack(&["bake", "no-such-scene.nff"]);
    assert_eq!(missing.status.code(), Some(1));
    let e = stderr(&missing);
    assert!(e.contains("no-such-scene.nff") && e.lines().count() == 1, "{e}");
}
