//! Renders the built-in demo scene (every primitive kind) to a binary PPM.
//!
//! `cargo run --release --example demo -- out.ppm [width height]`
use raypack::demo::{demo_camera, demo_scene};
use raypack::prelude::*;
use std::io::Write;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).map(String::as_str).unwrap_or("demo.ppm");
    let w: u32 = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(640);
    let h: u32 = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(480);
    let scene = demo_scene::<f32>()?;
    let camera = demo_camera::<f32>(w, h)?;
    let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default())?;
    let renderer = Renderer::new(tracer, camera);
    let mut img = vec![[0u8; 3]; (w * h) as usize];
    let mut stats = RayStats::default();
    let t0 = std::time::Instant::now();
    renderer.render_rect::<8>(camera.full_rect(), &mut img, &mut stats)?;
    let dt = t0.elapsed();
    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    write!(f, "P6\n{w} {h}\n255\n")?;
    for p in &img {
        f.write_all(p)?;
    }
    eprintln!("{path}: {w}x{h} in {:.3} s, {:?}", dt.as_secs_f64(), stats);
    Ok(())
}
