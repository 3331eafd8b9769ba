//! `raypack bench`: throughput of a scene on this machine, one line per
//! measurement, so machines (and packet widths, thread counts, instruction
//! sets) can be compared.
//!
//! Two measurements per configuration:
//! - `primary`: the closest hit of one primary ray per pixel (the ID image:
//!   intersection and traversal only, no shading);
//! - `whitted`: the full Whitted render (colour: shadows, reflection,
//!   refraction up to `--depth`), every ray counted.
//!
//! All configurations run interleaved, round after round, and each reports
//! its best and median wall time over the rounds, so the configurations of
//! one run saw the same machine conditions: compare ratios within a run.
//! Every render of a measurement must give the same bytes (whatever the
//! packet width, thread count or instruction set); a difference is reported
//! as an error, never averaged away.
//!
//! Output format (stable; `key=value` fields separated by one space, lines
//! starting with `#` are comments):
//! ```text
//! # raypack-bench 1 version=0.1.0 cpu="…" cores=2 isas=baseline,avx2 rounds=5
//! # scene=balls-2 primitives=92 lights=3 accel=bvh nodes=… depth=…
//! bench scene=balls-2 size=512x512 scalar=f32 accel=bvh measure=primary isa=avx2 packet=8 threads=1 rays=262144 best_s=0.012345678 median_s=0.012800000 mrays_per_s=20.480 mrays_min=19.861 mrays_max=21.235 vs_packet1=4.97 vs_1thread=1.00
//! ```
//! `isa` is the instruction set the configuration really ran with: `f32`
//! packets of 8 and 16 run the one asked for (`--isa`), narrower packets and fixed
//! point the baseline (see `tiles.rs`).
//! `mrays_per_s` is rays / median time / 10⁶, `mrays_min` and `mrays_max`
//! the same over the slowest and the fastest round; `vs_packet1` divides the best
//! time of packet width 1 (same threads) by this one's, `vs_1thread`
//! the best time of 1 thread (same isa and packet) by this one's; each is
//! printed only when that configuration was measured.

use crate::{AccelArg, Failure, IsaArg, Packet, ScalarArg};
use raypack::dispatch::Isa;
use raypack::image::{self, image_size, AccelKind, LoadedScene, Options, ScalarKind, MAX_DEPTH};
use raypack::prelude::*;
use std::path::PathBuf;

/// Version of the output format (first field of the header line).
const FORMAT: u32 = 1;

#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    /// The NFF scene file.
    scene: PathBuf,
    /// Image width (default 512, or keeps the file's aspect ratio with --height alone).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65535))]
    width: Option<u32>,
    /// Image height (default 512, or keeps the file's aspect ratio with --width alone).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65535))]
    height: Option<u32>,
    /// Packet widths to measure (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', default_values = ["1", "8"])]
    packet: Vec<Packet>,
    /// Thread counts to measure (comma-separated; default: 1 and one per core).
    #[arg(short = 'j', long, value_delimiter = ',', value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Vec<u32>,
    /// Instruction sets to measure (comma-separated; `auto` is the best this CPU has).
    #[arg(long, value_enum, value_delimiter = ',', default_values = ["auto"])]
    isa: Vec<IsaArg>,
    /// Rounds over all configurations (each configuration reports its best and median).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=10000))]
    rounds: u32,
    /// Maximum ray depth of the Whitted measurement.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=MAX_DEPTH as i64))]
    depth: u32,
    /// Acceleration structures to measure (comma-separated: `bvh,none` measures the tree and brute force interleaved).
    #[arg(long, value_enum, value_delimiter = ',', default_values = ["bvh"])]
    accel: Vec<AccelArg>,
    /// Number type.
    #[arg(long, value_enum, default_value = "f32")]
    scalar: ScalarArg,
}

/// One configuration and what it measured.
struct Config {
    measure: &'static str,
    accel: AccelKind,
    isa: Isa,
    packet: usize,
    threads: u32,
    times: Vec<f64>,
    /// What the last render traced (rays and packets by kind).
    stats: RayStats,
}

pub fn run(args: &BenchArgs) -> Result<(), Failure> {
    let text = crate::read_scene(&args.scene)?;
    let path = args.scene.display();
    // One load: the tree is built if any configuration uses it (brute force
    // then simply ignores it).
    let load = if args.accel.contains(&AccelArg::Bvh) { AccelKind::Bvh } else { AccelKind::BruteForce };
    // Every error names the file: the loader's and those of the
    // measurements (a render the scene cannot make, determinism).
    image::with_scene(&text, args.scalar.kind(), load, |scene| bench_scene(args, scene))
        .map_err(|e| Failure(format!("{path}: {e}")))?
        .map_err(|Failure(e)| Failure(format!("{path}: {e}")))
}

/// The CPU's model name (Linux), for the header.
fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().replace('"', "'"))
        })
        .unwrap_or_else(|| "unknown".into())
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn best(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

fn worst(v: &[f64]) -> f64 {
    v.iter().copied().fold(0.0, f64::max)
}

/// Millions of rays per second for `rays` in `secs` (0 for no time).
fn mrays(rays: u64, secs: f64) -> f64 {
    if secs > 0.0 {
        rays as f64 / secs / 1e6
    } else {
        0.0
    }
}

fn bench_scene(args: &BenchArgs, scene: &LoadedScene) -> Result<(), Failure> {
    let info = *scene.info();
    let scalar = info.scalar.name();
    let name = args.scene.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().replace(' ', "_"));
    let (width, height) = match (args.width, args.height) {
        (None, None) => (512, 512),
        (w, h) => image_size(w, h, info.nff.camera.map_or((1, 1), |c| (c.width, c.height))),
    };
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get() as u32);
    let mut configs = plan(args, info.scalar, cores)?;

    let accel = match &info.bvh {
        Some((b, built)) => format!(
            "accel=bvh nodes={} leaves={} depth={} outside={} build_ms={:.3}",
            b.nodes,
            b.leaves,
            b.depth,
            b.unbounded,
            built.as_secs_f64() * 1e3
        ),
        None => "accel=none".into(),
    };
    let header = format!(
        "# raypack-bench {FORMAT} version={} cpu=\"{}\" cores={cores} isas={} rounds={}\n\
         # scene={name} primitives={} lights={} size={width}x{height} scalar={scalar} {accel}\n",
        env!("CARGO_PKG_VERSION"),
        cpu_model(),
        crate::available_isas().replace(' ', ""),
        args.rounds,
        info.nff.counts.primitives(),
        info.nff.counts.lights
    );
    // The reader is gone (`raypack bench … | head -0`): nothing to measure for.
    if !crate::output::print(&header)? {
        return Ok(());
    }
    crate::render::warn_degenerate(&args.scene, &info, false);

    // The two measurements: closest hit of primary rays (the ID image), and
    // the full render.
    let base = Options { width: Some(width), height: Some(height), scalar: info.scalar, ..Options::default() };
    let primary = Options { mode: Mode::Cast, aov: Aov::Id, ..base };
    let whitted = Options { mode: Mode::Whitted, depth: args.depth, aov: Aov::Color, ..base };

    run_rounds(scene, &mut configs, [&primary, &whitted], args.rounds)?;

    for c in &configs {
        let (b, m, rays) = (best(&c.times), median(&c.times), c.stats.total());
        let mut line = format!(
            "bench scene={name} size={width}x{height} scalar={scalar} accel={} measure={} isa={} packet={} threads={} rays={rays} best_s={b:.9} median_s={m:.9} mrays_per_s={:.3} mrays_min={:.3} mrays_max={:.3}",
            accel_name(c.accel),
            c.measure,
            c.isa,
            c.packet,
            c.threads,
            mrays(rays, m),
            mrays(rays, worst(&c.times)),
            mrays(rays, b),
        );
        // How full the packets were (compaction could at best fill them).
        for (kind, lanes) in ["primary", "shadow", "reflected", "refracted"].iter().zip(c.stats.lanes_per_packet()) {
            line += &format!(" lanes_{kind}={lanes:.2}");
        }
        let find = |packet: usize, threads: u32| {
            let (isa, packet) = runs_with(info.scalar, c.isa, packet);
            configs.iter().find(|o| {
                o.measure == c.measure
                    && o.accel == c.accel
                    && o.isa == isa
                    && o.packet == packet
                    && o.threads == threads
            })
        };
        if let Some(o) = find(1, c.threads) {
            line += &format!(" vs_packet1={:.2}", best(&o.times) / b);
        }
        if let Some(o) = find(c.packet, 1) {
            line += &format!(" vs_1thread={:.2}", best(&o.times) / b);
        }
        line.push('\n');
        // A closed pipe (`raypack bench … | head -1`) ends quietly.
        if !crate::output::print(&line)? {
            break;
        }
    }
    Ok(())
}

/// The configurations `args` asks for, by the instruction set and packet
/// width they really run with (packets narrower than 8 and fixed point run
/// the baseline whatever is asked, fixed point one ray per packet): each
/// is measured once.
fn plan(args: &BenchArgs, scalar: ScalarKind, cores: u32) -> Result<Vec<Config>, Failure> {
    let mut threads = args.threads.clone();
    if threads.is_empty() {
        threads = vec![1, cores];
    }
    threads.sort_unstable();
    threads.dedup();
    let mut isas = Vec::new();
    for a in &args.isa {
        let isa = a.resolve()?;
        if !isas.contains(&isa) {
            isas.push(isa);
        }
    }
    let mut packets: Vec<usize> = args.packet.iter().map(|p| p.width()).collect();
    packets.sort_unstable();
    packets.dedup();
    let mut accels: Vec<AccelKind> = Vec::new();
    for a in &args.accel {
        if !accels.contains(&a.kind()) {
            accels.push(a.kind());
        }
    }
    let mut configs: Vec<Config> = Vec::new();
    for measure in ["primary", "whitted"] {
        for &accel in &accels {
            for &asked in &isas {
                for &asked_packet in &packets {
                    let (isa, packet) = runs_with(scalar, asked, asked_packet);
                    for &t in &threads {
                        if !configs.iter().any(|c| {
                            c.measure == measure
                                && c.accel == accel
                                && c.isa == isa
                                && c.packet == packet
                                && c.threads == t
                        }) {
                            configs.push(Config {
                                measure,
                                accel,
                                isa,
                                packet,
                                threads: t,
                                times: Vec::new(),
                                stats: RayStats::default(),
                            });
                        }
                    }
                }
            }
        }
    }
    Ok(configs)
}

/// Renders every configuration `rounds` times (`[primary, whitted]`
/// options by measure), recording the times; every image of a measurement
/// must equal its first.
fn run_rounds(
    scene: &LoadedScene,
    configs: &mut [Config],
    [primary, whitted]: [&Options; 2],
    rounds: u32,
) -> Result<(), Failure> {
    // The first image of each measurement; every other must equal it.
    let mut reference: [Option<Vec<Rgb8>>; 2] = [None, None];
    let nothing = || {};
    for _ in 0..rounds {
        for c in configs.iter_mut() {
            let (options, slot) = if c.measure == "primary" { (primary, 0) } else { (whitted, 1) };
            let options =
                Options { packet: c.packet, isa: c.isa, threads: Some(c.threads as usize), accel: c.accel, ..*options };
            let img = scene.render(&options, &nothing)?;
            c.times.push(img.time.as_secs_f64());
            c.stats = img.stats;
            let pixels = img.pixels;
            match &reference[slot] {
                None => reference[slot] = Some(pixels),
                Some(r) if *r == pixels => {}
                Some(_) => {
                    return Err(Failure(format!(
                        "determinism violated: the {} image of accel {} isa {} packet {} threads {} differs from the first one",
                        c.measure, accel_name(c.accel), c.isa, c.packet, c.threads
                    )))
                }
            }
        }
    }
    Ok(())
}

/// How the output names an accelerator.
fn accel_name(a: AccelKind) -> &'static str {
    match a {
        AccelKind::Bvh => "bvh",
        AccelKind::BruteForce => "none",
    }
}

/// The instruction set and packet width a configuration really runs with
/// (see [`Isa::used_for`] and [`image::packet_used`]).
fn runs_with(scalar: image::ScalarKind, isa: Isa, packet: usize) -> (Isa, usize) {
    fn of<S: raypack::Scalar>(isa: Isa, packet: usize) -> (Isa, usize) {
        let packet = image::packet_used::<S>(packet);
        (isa.used_for::<S>(packet), packet)
    }
    match scalar {
        image::ScalarKind::F32 => of::<f32>(isa, packet),
        image::ScalarKind::Fixed32 => of::<raypack::Fixed32>(isa, packet),
    }
}
