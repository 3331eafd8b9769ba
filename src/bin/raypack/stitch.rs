//! `raypack stitch`: assembles the parts of a frame rendered with
//! `render --region` (see `output.rs` for what a part carries) into the full
//! image, after checking that they tile it exactly: the same full size and
//! render in every part, each part inside the frame and of its region's
//! size, no two parts sharing a pixel, no pixel left out.

use crate::output::{read_image, Format, Region, Sink};
use crate::Failure;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct StitchArgs {
    /// The parts (PPM or PNG files written by `raypack render --region`).
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    /// The full image (`-`: standard output); the format follows the extension.
    #[arg(short, long)]
    output: PathBuf,
    /// Output format where the extension does not say (PPM on standard output by default).
    #[arg(long, value_enum)]
    format: Option<Format>,
    /// No summary line.
    #[arg(short, long)]
    quiet: bool,
}

pub fn run(args: &StitchArgs) -> Result<(), Failure> {
    let sink = Sink::create(&args.output, args.format, false)?;
    let mut frame: Option<(Region, String)> = None;
    let mut image: Vec<u8> = Vec::new();
    // Which part covers each pixel (`u32::MAX`: none yet).
    let mut owner: Vec<u32> = Vec::new();
    for (k, path) in args.parts.iter().enumerate() {
        let name = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|e| Failure(format!("{name}: {e}")))?;
        let part = read_image(&bytes).map_err(|e| Failure(format!("{name}: {e}")))?;
        let Some(region) = part.region else {
            return Err(Failure(format!("{name}: no raypack-region (render the parts with --region)")));
        };
        let r = region.rect;
        if (part.width, part.height) != (r.w, r.h) {
            return Err(Failure(format!(
                "{name}: {}x{} pixels, but its region says {}x{}",
                part.width, part.height, r.w, r.h
            )));
        }
        let (fw, fh) = region.full;
        match &frame {
            None => {
                let pixels = fw as usize * fh as usize;
                image = vec![0; pixels * 3];
                owner = vec![u32::MAX; pixels];
                frame = Some((region.clone(), name.clone()));
            }
            Some((first, first_name)) => {
                if first.full != region.full {
                    return Err(Failure(format!(
                        "{name}: part of a {fw}x{fh} image, but {first_name} of a {}x{} one",
                        first.full.0, first.full.1
                    )));
                }
                if first.render != region.render {
                    return Err(Failure(format!(
                        "{name}: part of another render than {first_name} (render {} vs {}: scene or options differ)",
                        region.render, first.render
                    )));
                }
            }
        }
        if r.w == 0 || r.h == 0 || r.x as u64 + r.w as u64 > fw as u64 || r.y as u64 + r.h as u64 > fh as u64 {
            return Err(Failure(format!(
                "{name}: region {},{},{},{} is not inside the {fw}x{fh} image",
                r.x, r.y, r.w, r.h
            )));
        }
        for row in 0..r.h {
            let y = (r.y + row) as usize;
            for col in 0..r.w {
                let at = y * fw as usize + (r.x + col) as usize;
                if owner[at] != u32::MAX {
                    let other = args.parts[owner[at] as usize].display();
                    return Err(Failure(format!("{name} and {other} overlap at pixel ({}, {y})", r.x + col)));
                }
                owner[at] = k as u32;
            }
            let src = row as usize * r.w as usize * 3;
            let dst = (y * fw as usize + r.x as usize) * 3;
            image[dst..dst + r.w as usize * 3].copy_from_slice(&part.pixels[src..src + r.w as usize * 3]);
        }
    }
    let Some((region, _)) = frame else { return Err(Failure("no parts".into())) };
    let (fw, fh) = region.full;
    let missing = owner.iter().filter(|&&o| o == u32::MAX).count();
    if let Some(i) = owner.iter().position(|&o| o == u32::MAX) {
        return Err(Failure(format!(
            "the parts leave a gap: no part covers pixel ({}, {}) ({missing} pixel{} of the {fw}x{fh} image uncovered)",
            i % fw as usize,
            i / fw as usize,
            if missing == 1 { "" } else { "s" }
        )));
    }
    let name = sink.name();
    let pixels: Vec<[u8; 3]> = image.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    sink.finish(fw, fh, &pixels, None)?;
    if !args.quiet {
        note!("raypack: {name}: {fw}x{fh} from {} parts", args.parts.len());
    }
    Ok(())
}
