//! `raypack`: renders NFF scenes (the SPD databases and raypack's extensions)
//! to PPM or PNG with the raypack core, on several threads, and reports what
//! a scene holds.
//!
//! Exit codes: 0 success; 1 bad scene, unreadable input or unwritable output
//! (one line on stderr, the reader's message with line and column); 2 bad
//! command line.

mod bench;
mod info;
mod output;
mod render;

use clap::{Parser, Subcommand, ValueEnum};
use raypack::image::{AccelKind, Options, ScalarKind, MAX_DEPTH};
use raypack::render::Aov;
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
    /// Render a scene to a PPM (binary P6) or PNG image.
    Render(RenderArgs),
    /// Measure primary-ray and full-render throughput of a scene, one line per measurement.
    Bench(bench::BenchArgs),
    /// Show what a scene holds: primitives by kind, lights, materials, bounds, camera.
    Info {
        /// The NFF scene file.
        scene: PathBuf,
    },
}

/// Number type the tracer computes with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum ScalarArg {
    /// 32-bit IEEE float.
    F32,
    /// 32.32 fixed point (`raypack::Fixed`): the accurate fixed-point reference, slow.
    Fixed,
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
    fn kind(self) -> ScalarKind {
        match self {
            ScalarArg::F32 => ScalarKind::F32,
            ScalarArg::Fixed => ScalarKind::Fixed,
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

impl RenderArgs {
    /// The library options these arguments ask for.
    fn options(&self) -> Result<Options, Failure> {
        Ok(Options {
            width: self.width,
            height: self.height,
            packet: self.packet.width(),
            threads: self.threads.map(|t| t as usize),
            mode: self.mode.mode(),
            depth: self.depth,
            aov: self.aov.aov(),
            accel: self.accel.kind(),
            scalar: self.scalar.kind(),
            isa: self.isa.resolve()?,
        })
    }
}

/// Reads a scene file as text, with the path in the error.
pub fn read_scene(path: &std::path::Path) -> Result<String, Failure> {
    std::fs::read_to_string(path).map_err(|e| Failure(format!("{}: {e}", path.display())))
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
    /// The NFF scene file.
    scene: PathBuf,
    /// Output image; the format follows the extension (.ppm or .png).
    #[arg(short, long)]
    output: PathBuf,
    /// Image width (default: the scene's `resolution`; alone, keeps the aspect ratio).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65535))]
    width: Option<u32>,
    /// Image height (default: the scene's `resolution`; alone, keeps the aspect ratio).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65535))]
    height: Option<u32>,
    /// Rays per packet.
    #[arg(long, value_enum, default_value = "8")]
    packet: Packet,
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
    /// Number type: 32-bit float, or 32.32 fixed point (for FPU-less targets).
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
        Command::Bench(args) => bench::run(&args),
        Command::Info { scene } => info::run(&scene),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure(msg)) => {
            eprintln!("raypack: error: {msg}");
            ExitCode::FAILURE
        }
    }
}
