//! `raypack bake`: a scene and its camera as Rust `static` data, for a
//! firmware that renders it without building it (docs/firmware.md,
//! "Scenes baked into flash").

use crate::output::print;
use crate::{read_scene, scene_name, Failure, ScalarArg};
use raypack::image::{self, AccelKind};
use std::path::PathBuf;

/// Arguments of `raypack bake`.
#[derive(clap::Args, Debug)]
pub struct BakeArgs {
    /// The NFF scene file (`-`: standard input).
    scene: PathBuf,
    /// The Rust file to write (default: standard output).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// The scalar the firmware renders with (a `fixed32` scene is converted
    /// into its frame, as `render --scalar fixed32` does).
    #[arg(long, value_enum, default_value = "fixed32")]
    scalar: ScalarArg,
    /// Image width the camera is made for (default: the file's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65535))]
    width: Option<u32>,
    /// Image height the camera is made for (default: the file's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65535))]
    height: Option<u32>,
}

pub fn run(args: &BakeArgs) -> Result<(), Failure> {
    let name = scene_name(&args.scene);
    let text = read_scene(&args.scene)?;
    let source =
        image::with_scene(&text, args.scalar.kind(), AccelKind::BruteForce, |s| s.bake(args.width, args.height))
            .and_then(|r| r)
            .map_err(|e| Failure(format!("{name}: {e}")))?;
    match &args.output {
        None => {
            // A closed pipe ends quietly, as for `render -o -`.
            print(&source)?;
        }
        Some(path) => {
            std::fs::write(path, source).map_err(|e| Failure(format!("{}: {e}", path.display())))?;
        }
    }
    Ok(())
}
