//! `raypack`: renders NFF scenes (the SPD databases and raypack's extensions)
//! to PPM or PNG with the raypack core, on several threads, and reports what
//! a scene holds.
//!
//! Exit codes: 0 success; 1 bad scene, unreadable input or unwritable output
//! (one line on stderr, the reader's message with line and column); 2 bad
//! command line.

/// `eprintln!` that never panics: with standard error closed or full
/// (`2>&1 | head`, `2>/dev/full`) the message is lost, as with other Unix
/// tools, and the command goes on to its own exit status.
macro_rules! note {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

mod bake;
mod bench;
mod info;
mod output;
mod render;
mod stitch;

use clap::{Parser, Subcommand, ValueEnum};
use raypack::camera::Rect;
use raypack::image::{AccelKind, Options, ScalarKind, MAX_DEPTH};
use raypack::render::{Aov, Sampling};
use raypack::trace::Mode;
use std::path::PathBuf;
use std::process::ExitCode;

/// Render NFF scenes with raypack, a deterministic packet ray tracer.
#[derive(Parser, Debug)]
#[command(name = "raypack", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene (or a region of it) to a PPM (binary P6) or PNG image.
    Render(RenderArgs),
    /// Assemble the parts of a frame rendered with `render --region` into one image.
    Stitch(stitch::StitchArgs),
    /// Measure primary-ray and full-render throughput of a scene, one line per measurement.
    Bench(bench::BenchArgs),
    /// Write a scene and its camera as Rust `static` data for a firmware (no scene code on the device).
    Bake(bake::BakeArgs),
    /// Show what a scene holds: primitives by kind, lights, materials, bounds, camera.
    Info {
        /// The NFF scene file (`-`: standard input).
        scene: PathBuf,
    },
}

/// Number type the tracer computes with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ScalarArg {
    /// 32-bit IEEE float.
    F32,
    /// Q8.24 fixed point with 32-bit storage (`raypack::Fixed32`): what FPU-less firmware runs.
    Fixed32,
}

/// Packet width: rays traced together.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Packet {
    /// One ray at a time (the scalar tracer).
    #[value(name = "1")]
    One,
    /// 2×2 pixels per packet.
    #[value(name = "4")]
    Four,
    /// 4×2 pixels per packet.
    #[value(name = "8")]
    Eight,
    /// 4×4 pixels per packet (one 512-bit register per value with AVX-512).
    #[value(name = "16")]
    Sixteen,
}

impl Packet {
    /// Rays per packet.
    pub fn width(self) -> usize {
        match self {
            Packet::One => 1,
            Packet::Four => 4,
            Packet::Eight => 8,
            Packet::Sixteen => 16,
        }
    }
}

/// Instruction set of the render path (x86-64; the bytes are the same with every one).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum IsaArg {
    /// The fastest this CPU has (AVX-512, else AVX2, else the baseline).
    Auto,
    /// The build's baseline (x86-64: SSE2).
    Baseline,
    /// AVX2 (256-bit vectors, no FMA).
    Avx2,
    /// AVX-512 F/VL/BW/DQ.
    Avx512,
}

impl ScalarArg {
    /// The library's name for it.
    pub fn kind(self) -> ScalarKind {
        match self {
            ScalarArg::F32 => ScalarKind::F32,
            ScalarArg::Fixed32 => ScalarKind::Fixed32,
        }
    }
}

impl AccelArg {
    /// The library's name for it.
    fn kind(self) -> AccelKind {
        match self {
            AccelArg::Bvh => AccelKind::Bvh,
            AccelArg::None => AccelKind::BruteForce,
        }
    }
}

impl ModeArg {
    /// The library's name for it.
    fn mode(self) -> Mode {
        match self {
            ModeArg::Cast => Mode::Cast,
            ModeArg::Trace => Mode::Whitted,
        }
    }
}

impl AovArg {
    /// The library's name for it.
    fn aov(self) -> Aov {
        match self {
            AovArg::Color => Aov::Color,
            AovArg::Depth => Aov::Depth,
            AovArg::Normal => Aov::Normal,
            AovArg::Id => Aov::Id,
        }
    }
}

/// Exits with a usage error (code 2), in clap's format.
pub fn usage_error(msg: impl std::fmt::Display) -> ! {
    use clap::CommandFactory;
    Cli::command().error(clap::error::ErrorKind::ArgumentConflict, msg).exit()
}

/// `X,Y,W,H` (W and H at least 1).
fn parse_region(s: &str) -> Result<Rect, String> {
    let v: Vec<u32> = s
        .split(',')
        .map(|f| f.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("`{s}`: {e} (expected X,Y,W,H)"))?;
    match v[..] {
        [x, y, w, h] if w > 0 && h > 0 => Ok(Rect { x, y, w, h }),
        [_, _, _, _] => Err(format!("`{s}`: width and height must be at least 1")),
        _ => Err(format!("`{s}`: expected four numbers X,Y,W,H")),
    }
}

/// The sampling these arguments ask for (usage errors exit with 2).
fn sampling(samples: Option<u8>, adaptive: Option<f32>, aov: AovArg) -> Sampling {
    if (samples.is_some_and(|n| n > 1) || adaptive.is_some()) && aov != AovArg::Color {
        usage_error("--samples and --adaptive apply to --aov color only");
    }
    match (samples, adaptive) {
        (None | Some(1), None) => Sampling::Centre,
        (Some(n), None) => Sampling::Grid(n),
        (Some(1), Some(_)) => {
            usage_error("--adaptive needs --samples of at least 2 (the grid of a supersampled pixel)")
        }
        (n, Some(t)) => Sampling::adaptive(n.unwrap_or(3), t),
    }
}

/// `--adaptive`: a finite threshold in [0, 3].
fn parse_threshold(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(t) if (0.0..=3.0).contains(&t) => Ok(t),
        _ => Err(format!("`{s}`: expected a number from 0 to 3 (POV-Ray's +A threshold, e.g. 0.3)")),
    }
}

impl RenderArgs {
    /// The library options these arguments ask for.
    fn options(&self) -> Result<Options, Failure> {
        let isa = self.isa.resolve()?;
        Ok(Options {
            region: self.region,
            sampling: sampling(self.samples, self.adaptive, self.aov),
            width: self.width,
            height: self.height,
            packet: self.packet.map_or(raypack::image::best_packet(isa), Packet::width),
            threads: self.threads.map(|t| t as usize),
            mode: self.mode.mode(),
            depth: self.depth,
            aov: self.aov.aov(),
            accel: self.accel.kind(),
            scalar: self.scalar.kind(),
            isa,
        })
    }
}

/// Reads a scene file as text (`-`: standard input), with the path in the
/// error.
pub fn read_scene(path: &std::path::Path) -> Result<String, Failure> {
    let name = scene_name(path);
    let bytes = if path.as_os_str() == "-" {
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut std::io::stdin().lock(), &mut bytes)
            .map_err(|e| Failure(format!("{name}: {e}")))?;
        bytes
    } else {
        std::fs::read(path).map_err(|e| Failure(format!("{name}: {e}")))?
    };
    String::from_utf8(bytes).map_err(|e| Failure(format!("{name}: {}", not_utf8(e.as_bytes(), e.utf8_error()))))
}

/// Where text stops being UTF-8, as the reader reports positions: `line N,
/// column M: ...` (1-based; the column counts the characters before it on
/// its line, as the NFF reader's do).
fn not_utf8(bytes: &[u8], e: std::str::Utf8Error) -> String {
    let good = &bytes[..e.valid_up_to()];
    let line_start = good.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
    // The prefix is valid UTF-8, so this counts characters.
    let column = String::from_utf8_lossy(&good[line_start..]).chars().count() + 1;
    let bad = &bytes[e.valid_up_to()..];
    let shown: Vec<String> =
        bad.iter().take(e.error_len().unwrap_or(bad.len()).min(4)).map(|b| format!("0x{b:02x}")).collect();
    format!("line {line}, column {column}: not UTF-8 text (byte {}); NFF files are ASCII or UTF-8", shown.join(" "))
}

/// How a scene path is named in messages (`-` is standard input).
pub fn scene_name(path: &std::path::Path) -> String {
    if path.as_os_str() == "-" {
        "standard input".into()
    } else {
        path.display().to_string()
    }
}

impl IsaArg {
    /// The instruction set asked for; an error if this CPU lacks it.
    fn resolve(self) -> Result<raypack::dispatch::Isa, Failure> {
        use raypack::dispatch::Isa;
        let isa = match self {
            IsaArg::Auto => return Ok(Isa::best()),
            IsaArg::Baseline => Isa::Baseline,
            IsaArg::Avx2 => Isa::Avx2,
            IsaArg::Avx512 => Isa::Avx512,
        };
        if isa.is_available() {
            Ok(isa)
        } else {
            Err(Failure(format!("this CPU cannot run --isa {isa} (it can run: {})", available_isas())))
        }
    }
}

/// The instruction sets this CPU can run, comma-separated.
fn available_isas() -> String {
    let names: Vec<&str> = raypack::dispatch::Isa::ALL.iter().filter(|i| i.is_available()).map(|i| i.name()).collect();
    names.join(", ")
}

/// How rays are traced.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum ModeArg {
    /// Primary rays only, local shading without shadows.
    Cast,
    /// Whitted ray tracing: shadows, reflection, refraction.
    Trace,
}

/// What each pixel shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum AovArg {
    /// The traced colour.
    Color,
    /// Distance along the primary ray, 24-bit round(t·256) (r high byte), background white.
    Depth,
    /// Shading normal as 0.5·n + 0.5, background black.
    Normal,
    /// Index k of the primitive hit (file order) as the 24-bit number k + 1, background 0.
    Id,
}

/// How rays find what they hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum AccelArg {
    /// A bounding volume hierarchy (the same image, faster).
    Bvh,
    /// Test every primitive (brute force, for comparison).
    None,
}

#[derive(clap::Args, Debug)]
struct RenderArgs {
    /// The NFF scene file (`-`: standard input).
    scene: PathBuf,
    /// Output image (`-`: standard output); the format follows the extension (.ppm or .png).
    /// Default: SCENE_STEM.png in the current directory, never overwriting an existing file
    /// unless --force is given. With -o, an existing file is replaced, atomically.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Output format where the extension does not say which (standard output: PPM by default).
    #[arg(long, value_enum)]
    format: Option<output::Format>,
    /// Overwrite an existing file at the default output name.
    #[arg(long)]
    force: bool,
    /// Render only this pixel rectangle of the full image, X,Y,W,H (from the top-left);
    /// the image is that rectangle, marked with its place for `raypack stitch`.
    #[arg(long, value_parser = parse_region)]
    region: Option<Rect>,
    /// Anti-aliasing: N×N regular supersampling per pixel, box filter (1: one ray per pixel).
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=16))]
    samples: Option<u8>,
    /// Adaptive anti-aliasing: supersample (--samples N, default 3) only pixels whose colour differs
    /// from a neighbour's by more than T (sum of the channel differences on 0..1, as POV-Ray's +A0.3).
    #[arg(long, value_name = "T", value_parser = parse_threshold)]
    adaptive: Option<f32>,
    /// Image width (default: the scene's `resolution`; alone, keeps the aspect ratio).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65535))]
    width: Option<u32>,
    /// Image height (default: the scene's `resolution`; alone, keeps the aspect ratio).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65535))]
    height: Option<u32>,
    /// Rays per packet (default: 16 where the instruction set is AVX2 or
    /// AVX-512, 8 otherwise: the faster on every scene measured).
    #[arg(long, value_enum)]
    packet: Option<Packet>,
    /// Worker threads (default: one per core).
    #[arg(short = 'j', long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Ray casting or Whitted ray tracing.
    #[arg(long, value_enum, default_value = "trace")]
    mode: ModeArg,
    /// Maximum ray depth (segments per path, primary included).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=MAX_DEPTH as i64))]
    depth: u32,
    /// What to write per pixel.
    #[arg(long, value_enum, default_value = "color")]
    aov: AovArg,
    /// Acceleration structure (`none`: brute force; the image is the same).
    #[arg(long, value_enum, default_value = "bvh")]
    accel: AccelArg,
    /// Number type: 32-bit float, or the Q8.24 fixed point FPU-less firmware runs (the library also has a 32.32 `Fixed`).
    #[arg(long, value_enum, default_value = "f32")]
    scalar: ScalarArg,
    /// Instruction set of the f32 render path (the image is the same with every one).
    #[arg(long, value_enum, default_value = "auto")]
    isa: IsaArg,
    /// No progress bar, warnings or summary (errors are still reported).
    #[arg(short, long)]
    quiet: bool,
}

/// A failure to report: one line, exit code 1.
pub struct Failure(String);

impl<E: std::fmt::Display> From<E> for Failure {
    fn from(e: E) -> Self {
        Failure(e.to_string())
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Stitch(args) => stitch::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Bake(args) => bake::run(&args),
        Command::Info { scene } => info::run(&scene),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure(msg)) => {
            note!("raypack: error: {msg}");
            ExitCode::FAILURE
        }
    }
}
