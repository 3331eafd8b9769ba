//! Draws the demo scene on an `embedded-graphics` display without a
//! framebuffer: the renderer sends each band of rows to the display with one
//! `fill_contiguous` call. The "display" is a 240×135 RGB565 panel simulated
//! in memory (standing in for an SPI driver such as an ST7789's: one address
//! window and one pixel burst per call), saved as a PPM at the end so the
//! result can be looked at.
//!
//! `cargo run --example draw_target --features embedded-graphics -- [out.ppm]`
use embedded_graphics::pixelcolor::raw::{RawData, RawU16};
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use raypack::demo::{demo_camera, demo_scene};
use raypack::output::{Fnv1a, CHECKSUM_DITHER};
use raypack::prelude::*;
use std::io::Write;

const WIDTH: u32 = 240;
const HEIGHT: u32 = 135;

/// A 240×135 RGB565 panel: its display RAM, and the transfers a real driver
/// would make (address windows set, pixels sent).
struct Panel {
    ram: Vec<u16>,
    windows: usize,
    pixels_sent: usize,
}

impl Panel {
    fn write(&mut self, p: Point, c: Rgb565) {
        if let (Ok(x), Ok(y)) = (u32::try_from(p.x), u32::try_from(p.y)) {
            if x < WIDTH && y < HEIGHT {
                self.ram[(y * WIDTH + x) as usize] = RawU16::from(c).into_inner();
            }
        }
        self.pixels_sent += 1;
    }
}

impl OriginDimensions for Panel {
    fn size(&self) -> Size {
        Size::new(WIDTH, HEIGHT)
    }
}

impl DrawTarget for Panel {
    type Color = Rgb565;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(&mut self, pixels: I) -> Result<(), Self::Error> {
        // A real driver sets a one-pixel window per pixel: slow, and unused here.
        for Pixel(p, c) in pixels {
            self.windows += 1;
            self.write(p, c);
        }
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb565>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Self::Error> {
        // A real driver sets the address window to `area` and streams `colors`.
        self.windows += 1;
        for (p, c) in area.points().zip(colors) {
            self.write(p, c);
        }
        Ok(())
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).unwrap_or_else(|| "draw_target.ppm".into());
    let scene = demo_scene::<f32>().map_err(|e| e.to_string())?;
    let camera = demo_camera::<f32>(WIDTH, HEIGHT).map_err(|e| e.to_string())?;
    let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).map_err(|e| e.to_string())?;
    let renderer = Renderer::new(tracer, camera);

    let mut panel = Panel { ram: vec![0; (WIDTH * HEIGHT) as usize], windows: 0, pixels_sent: 0 };
    let mut band = [[0u8; 3]; WIDTH as usize * 8]; // 8 rows, 5.6 KiB: all the pixel memory
    let mut stats = RayStats::default();
    renderer
        .draw_bands::<8, _>(&mut panel, Point::zero(), &mut band, CHECKSUM_DITHER, &mut stats)
        .map_err(|e| e.to_string())?;

    // The panel now holds the pixels the firmware checksums (RGB565, big-endian).
    let mut hash = Fnv1a::new();
    for v in &panel.ram {
        hash.write(&v.to_be_bytes());
    }
    let want = renderer.checksums::<8>(&mut band).map_err(|e| e.to_string())?;
    println!(
        "{WIDTH}x{HEIGHT} RGB565 ({CHECKSUM_DITHER:?}): {} address windows, {} pixels sent, {} rays; \
         panel FNV-1a {:08x}, render_bands checksum {:08x} ({})",
        panel.windows,
        panel.pixels_sent,
        stats.total(),
        hash.finish(),
        want.rgb565,
        if hash.finish() == want.rgb565 { "equal" } else { "DIFFERENT" }
    );

    // Expand RGB565 to RGB888 by bit replication for the PPM.
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path)?);
    write!(f, "P6\n{WIDTH} {HEIGHT}\n255\n")?;
    for &v in &panel.ram {
        let (r, g, b) = ((v >> 11) & 31, (v >> 5) & 63, v & 31);
        f.write_all(&[((r << 3) | (r >> 2)) as u8, ((g << 2) | (g >> 4)) as u8, ((b << 3) | (b >> 2)) as u8])?;
    }
    f.flush()?;
    println!("wrote {path}");
    if hash.finish() != want.rgb565 {
        return Err("the panel's pixels differ from the checksummed ones".into());
    }
    Ok(())
}
