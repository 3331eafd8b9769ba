//! The band loop firmware runs, on the host: the demo scene rendered band
//! by band into one small buffer (no framebuffer, no allocation in the
//! core), each band handed to a sink; here the sink folds the RGB565
//! pixels a display would receive into a checksum. Everything used is
//! `no_std`; only `main` and the printing are std.
//!
//! `cargo run --example bands`
use raypack::demo::{demo_camera, demo_scene};
use raypack::output::{rgb565, Dither, Fnv1a};
use raypack::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = demo_scene::<f32>()?;
    let camera = demo_camera::<f32>(160, 128)?;
    let renderer = Renderer::new(Tracer::<f32>::new(scene.view(), TraceSettings::default())?, camera);
    let mut band = [[0u8; 3]; 160 * 2]; // two rows of 160 pixels
    let mut hash = Fnv1a::new();
    let mut stats = RayStats::default();
    renderer.render_bands::<4, core::convert::Infallible>(&mut band, &mut stats, |rect, pixels| {
        for (i, p) in pixels.iter().enumerate() {
            let (x, y) = (rect.x + i as u32 % rect.w, rect.y + i as u32 / rect.w);
            hash.write(&rgb565(*p, x, y, Dither::Bayer4).to_be_bytes());
        }
        Ok(())
    })?;
    println!("rgb565-bayer4 {:#010x}, {} rays", hash.finish(), stats.total());
    Ok(())
}
