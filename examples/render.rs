//! Renders an NFF scene file to a binary PPM through the library's entry
//! point, [`raypack::Image::render`]: the scene read into a fitting
//! capacity, a BVH, the fastest instruction set, every core.
//!
//! `cargo run --release --example render -- tests/scenes/balls-1.nff balls.ppm`
use raypack::{Image, Options};
use std::io::Write;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let scene = args.get(1).map(String::as_str).unwrap_or("tests/scenes/balls-1.nff");
    let out = args.get(2).map(String::as_str).unwrap_or("out.ppm");
    let text = std::fs::read_to_string(scene)?;
    let image = Image::render(&text, &Options { width: Some(256), height: Some(256), ..Options::default() })?;
    let mut f = std::io::BufWriter::new(std::fs::File::create(out)?);
    write!(f, "P6\n{} {}\n255\n", image.width, image.height)?;
    for p in &image.pixels {
        f.write_all(p)?;
    }
    eprintln!(
        "{out}: {}x{}, {} rays in {:.3} s ({})",
        image.width,
        image.height,
        image.stats.total(),
        image.time.as_secs_f64(),
        image.isa
    );
    Ok(())
}
