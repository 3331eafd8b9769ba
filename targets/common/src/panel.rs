//! The frame a real 240×135 RGB565 panel shows (feature `panel`): the demo
//! image, drawn by the same [`render_demo_into`] the QEMU boards check, and
//! beside it the frame time as text.
//!
//! The image is the firmware image ([`IMAGE_WIDTH`]×[`IMAGE_HEIGHT`],
//! 160×128), so the RGB565 stream the panel receives for it is, pixel for
//! pixel, the one whose checksum the QEMU boards print and
//! `targets/checksums.txt` records (`rgb565-bayer4`); the host tests below
//! check that on a mock panel. The 80 columns to its right hold the label.

use crate::draw::{demo_renderer, render_demo_into};
use crate::dual::{core0_bands, Peer};
use crate::timing::{measure, Clock};
use crate::{console, Failure, SceneSlot, SlotScalar, IMAGE_HEIGHT, IMAGE_WIDTH};
use embedded_graphics::image::GetPixel;
use embedded_graphics::mono_font::ascii::FONT_6X10;
use embedded_graphics::mono_font::MonoFont;
use embedded_graphics::pixelcolor::{BinaryColor, Rgb565, RgbColor};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use raypack::render::{Renderer, Rgb8};
use raypack::trace::RayStats;

/// Panel width in pixels (landscape).
pub const PANEL_WIDTH: u32 = 240;
/// Panel height in pixels (landscape).
pub const PANEL_HEIGHT: u32 = 135;
/// Where the image's top-left pixel goes: the left edge, centred vertically.
pub const IMAGE_TOP_LEFT: Point = Point::new(0, ((PANEL_HEIGHT - IMAGE_HEIGHT) / 2) as i32);
/// Top-left corner of the label, right of the image.
pub const LABEL_TOP_LEFT: Point = Point::new(IMAGE_WIDTH as i32 + 6, IMAGE_TOP_LEFT.y + 2);
/// Height of one label line (the font's 10 pixels and 2 of spacing).
pub const LABEL_LINE: i32 = 12;

/// One frame shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Frame {
    /// Microseconds from the start of the scene build to the last band sent
    /// (build, render, and the transfer to the panel; not the clear or the
    /// label).
    pub micros: u64,
    /// Rays traced.
    pub rays: RayStats,
}

/// Clears `display`, renders the demo image into it at [`IMAGE_TOP_LEFT`]
/// with [`render_demo_into`] (scalar `S`, packet width `W`, band buffer
/// `band`), timed by `clock`, then writes the label: `raypack`, `scalar`,
/// the frame time and the rays.
pub fn show_frame<S: SlotScalar, const W: usize, D>(
    display: &mut D,
    clock: &mut impl Clock,
    scalar: &str,
    slot: &mut SceneSlot,
    band: &mut [Rgb8],
) -> Result<Frame, Failure>
where
    D: DrawTarget<Color = Rgb565>,
{
    display.clear(Rgb565::BLACK).map_err(|_| Failure::Target)?;
    let rate = clock.rate();
    let (r, ticks) = measure(clock, || render_demo_into::<S, W, D>(slot, band, display, IMAGE_TOP_LEFT));
    let frame = Frame { micros: rate.micros(ticks), rays: r? };
    draw_label(display, scalar, &frame).map_err(|_| Failure::Target)?;
    Ok(frame)
}

/// [`show_frame`] with the image rendered by two cores ([`crate::dual`]):
/// clears `display`, builds the demo scene in `slot`, calls `start_core1`
/// with the renderer (it starts the other core on
/// [`core1_bands`](crate::dual::core1_bands) and returns this core's end of
/// the link), renders this core's bands through `band` and sends all bands
/// to the panel at [`IMAGE_TOP_LEFT`] ([`core0_bands`]), timed by `clock`
/// from the build to the last band; then the label. The panel receives
/// what [`show_frame`] sends (host-tested down to the SPI bytes).
pub fn show_frame_dual<'s, S: SlotScalar, const W: usize, D, P: Peer>(
    display: &mut D,
    clock: &mut impl Clock,
    scalar: &str,
    slot: &'s mut SceneSlot,
    band: &mut [Rgb8],
    start_core1: impl FnOnce(Renderer<'s, S>) -> Result<P, Failure>,
) -> Result<Frame, Failure>
where
    D: DrawTarget<Color = Rgb565>,
{
    display.clear(Rgb565::BLACK).map_err(|_| Failure::Target)?;
    let rate = clock.rate();
    let (r, ticks) = measure(clock, || {
        let renderer = demo_renderer::<S>(slot)?;
        let mut peer = start_core1(renderer)?;
        core0_bands::<S, W, D>(&renderer, display, IMAGE_TOP_LEFT, band, &mut peer)
    });
    let frame = Frame { micros: rate.micros(ticks), rays: r? };
    draw_label(display, scalar, &frame).map_err(|_| Failure::Target)?;
    Ok(frame)
}

/// Writes the label lines right of the image.
pub fn draw_label<D: DrawTarget<Color = Rgb565>>(display: &mut D, scalar: &str, frame: &Frame) -> Result<(), D::Error> {
    let bright = Rgb565::WHITE;
    let dim = DIM;
    let mut seconds = [0u8; LINE_BYTES];
    let mut rays = [0u8; LINE_BYTES];
    let lines: [(&str, Rgb565); 6] = [
        ("raypack", bright),
        (scalar, bright),
        ("frame time", dim),
        (format_seconds(frame.micros, &mut seconds), bright),
        ("rays", dim),
        (format_count(frame.rays.total(), &mut rays), bright),
    ];
    let mut at = LABEL_TOP_LEFT;
    for (text, color) in lines {
        draw_text(display, text, at, color, Rgb565::BLACK)?;
        at.y += LABEL_LINE;
    }
    Ok(())
}

/// Writes `text` on label line `line` (0 is the first; [`draw_label`]
/// fills lines 0 to 5, a board may add lines 6 and 7), bright or dim.
pub fn draw_label_line<D: DrawTarget<Color = Rgb565>>(
    display: &mut D,
    line: i32,
    text: &str,
    bright: bool,
) -> Result<(), D::Error> {
    let color = if bright { Rgb565::WHITE } else { DIM };
    draw_text(display, text, LABEL_TOP_LEFT + Point::new(0, line * LABEL_LINE), color, Rgb565::BLACK)
}

/// The colour of the label's captions.
const DIM: Rgb565 = Rgb565::new(20, 40, 20);

/// The label's font.
pub const FONT: MonoFont<'static> = FONT_6X10;
/// Glyph width of [`FONT`].
const GLYPH_W: u32 = 6;
/// Glyph height of [`FONT`].
const GLYPH_H: u32 = 10;

/// Draws `text` in [`FONT`] with its top-left corner at `at`: each glyph
/// as one 6×10 `fill_contiguous` (`color` on `background`), its pixels read
/// from the font's glyph image with checked look-ups. (embedded-graphics'
/// own `Text` drawing does the same, but leaves a slice-index panic
/// reachable after LTO, which the `panic-never` build refuses.)
pub fn draw_text<D: DrawTarget<Color = Rgb565>>(
    display: &mut D,
    text: &str,
    at: Point,
    color: Rgb565,
    background: Rgb565,
) -> Result<(), D::Error> {
    let per_row = (FONT.image.size().width / GLYPH_W).max(1);
    let mut x = at.x;
    for c in text.chars() {
        let index = FONT.glyph_mapping.index(c) as u32;
        let cell = Point::new(((index % per_row) * GLYPH_W) as i32, ((index / per_row) * GLYPH_H) as i32);
        let mut pixels = [background; (GLYPH_W * GLYPH_H) as usize];
        for (i, px) in pixels.iter_mut().enumerate() {
            let p = cell + Point::new((i as u32 % GLYPH_W) as i32, (i as u32 / GLYPH_W) as i32);
            if FONT.image.pixel(p) == Some(BinaryColor::On) {
                *px = color;
            }
        }
        display.fill_contiguous(&Rectangle::new(Point::new(x, at.y), Size::new(GLYPH_W, GLYPH_H)), pixels)?;
        x = x.saturating_add((GLYPH_W + FONT.character_spacing) as i32);
    }
    Ok(())
}

/// Bytes of one formatted label line.
pub const LINE_BYTES: usize = 24;

/// `micros` as seconds with three decimals and a unit, `12.345 s`
/// (rounded down to the millisecond), in `buf`.
pub fn format_seconds(micros: u64, buf: &mut [u8; LINE_BYTES]) -> &str {
    let millis = micros / 1000;
    let mut digits = [0u8; 20];
    let whole = console::format_u64(millis / 1000, &mut digits);
    let mut n = 0;
    push(buf, &mut n, whole.as_bytes());
    let frac = (millis % 1000) as u32;
    push(buf, &mut n, &[b'.', b'0' + (frac / 100) as u8, b'0' + (frac / 10 % 10) as u8, b'0' + (frac % 10) as u8]);
    push(buf, &mut n, b" s");
    core::str::from_utf8(buf.get(..n).unwrap_or(&[])).unwrap_or("?")
}

/// `v` in decimal, in `buf`.
pub fn format_count(v: u64, buf: &mut [u8; LINE_BYTES]) -> &str {
    let mut digits = [0u8; 20];
    let s = console::format_u64(v, &mut digits);
    let mut n = 0;
    push(buf, &mut n, s.as_bytes());
    core::str::from_utf8(buf.get(..n).unwrap_or(&[])).unwrap_or("?")
}

/// Appends `bytes` at `*n` (as many as fit).
fn push(buf: &mut [u8; LINE_BYTES], n: &mut usize, bytes: &[u8]) {
    for &b in bytes {
        if let Some(slot) = buf.get_mut(*n) {
            *slot = b;
            *n += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::{recorded, Fnv};
    use crate::timing::TickRate;
    use embedded_graphics::pixelcolor::raw::{RawU16, ToBytes};
    use embedded_graphics::text::{Baseline, Text};
    use raypack::Fixed32;

    /// A 240×135 RGB565 panel in memory: a framebuffer, and the FNV-1a of
    /// the wire bytes (high byte first) of every pixel it is sent, in the
    /// order sent, from the moment it is armed.
    struct WirePanel {
        pixels: Vec<Rgb565>,
        wire: Fnv,
        sent: u32,
        armed: bool,
        fills: u32,
    }

    impl WirePanel {
        fn new() -> Self {
            WirePanel {
                pixels: vec![Rgb565::new(1, 2, 3); (PANEL_WIDTH * PANEL_HEIGHT) as usize],
                wire: Fnv::new(),
                sent: 0,
                armed: true,
                fills: 0,
            }
        }
        fn put(&mut self, p: Point, c: Rgb565) {
            if self.armed {
                self.wire.write(&RawU16::from(c).to_be_bytes());
                self.sent += 1;
            }
            if p.x >= 0 && p.y >= 0 && (p.x as u32) < PANEL_WIDTH && (p.y as u32) < PANEL_HEIGHT {
                self.pixels[(p.y as u32 * PANEL_WIDTH + p.x as u32) as usize] = c;
            }
        }
        fn at(&self, x: u32, y: u32) -> Rgb565 {
            self.pixels[(y * PANEL_WIDTH + x) as usize]
        }
    }

    impl OriginDimensions for WirePanel {
        fn size(&self) -> Size {
            Size::new(PANEL_WIDTH, PANEL_HEIGHT)
        }
    }

    impl DrawTarget for WirePanel {
        type Color = Rgb565;
        type Error = core::convert::Infallible;
        fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(&mut self, pixels: I) -> Result<(), Self::Error> {
            for Pixel(p, c) in pixels {
                self.put(p, c);
            }
            Ok(())
        }
        fn fill_contiguous<I: IntoIterator<Item = Rgb565>>(
            &mut self,
            area: &Rectangle,
            colors: I,
        ) -> Result<(), Self::Error> {
            self.fills += 1;
            for (p, c) in area.points().zip(colors) {
                self.put(p, c);
            }
            Ok(())
        }
        fn clear(&mut self, color: Rgb565) -> Result<(), Self::Error> {
            // A panel clear is not part of the image stream.
            self.pixels.fill(color);
            Ok(())
        }
    }

    /// A microsecond clock that advances 1000 µs per reading.
    struct Millis(u64);
    impl Clock for Millis {
        fn now(&mut self) -> u64 {
            self.0 += 1000;
            self.0
        }
        fn rate(&self) -> TickRate {
            TickRate::from_hz(1_000_000)
        }
    }

    fn panel_stream<S: SlotScalar>() -> (u32, u32, u32) {
        let mut scene = Box::new(SceneSlot::new());
        let mut band = vec![[0u8; 3]; IMAGE_WIDTH as usize * 8];
        let mut panel = WirePanel::new();
        render_demo_into::<S, 1, _>(&mut scene, &mut band, &mut panel, IMAGE_TOP_LEFT).unwrap();
        (panel.wire.finish(), panel.sent, panel.fills)
    }

    #[test]
    fn the_panel_receives_the_rgb565_stream_the_firmware_checksums() {
        for (name, (wire, sent, fills)) in [("f32", panel_stream::<f32>()), ("fixed32", panel_stream::<Fixed32>())] {
            assert_eq!(wire, recorded(name, "rgb565-bayer4"), "{name}: the panel's RGB565 stream");
            assert_eq!(sent, IMAGE_WIDTH * IMAGE_HEIGHT);
            // One fill_contiguous per band of 8 rows: one address window and
            // one pixel burst each.
            assert_eq!(fills, IMAGE_HEIGHT / 8);
        }
    }

    #[test]
    fn the_frame_shows_the_image_and_a_label_beside_it() {
        let mut scene = Box::new(SceneSlot::new());
        let mut band = vec![[0u8; 3]; IMAGE_WIDTH as usize * 8];
        let mut panel = WirePanel::new();
        let mut clock = Millis(0);
        let frame = show_frame::<Fixed32, 1, _>(&mut panel, &mut clock, "fixed32", &mut scene, &mut band).unwrap();
        assert_eq!(frame.micros, 1000);
        assert_eq!(frame.rays.total(), recorded("fixed32", "rays") as u64);
        // The image, read back from the framebuffer after the label: intact.
        let mut h = Fnv::new();
        for y in 0..IMAGE_HEIGHT {
            for x in 0..IMAGE_WIDTH {
                let c = panel.at(x + IMAGE_TOP_LEFT.x as u32, y + IMAGE_TOP_LEFT.y as u32);
                h.write(&RawU16::from(c).to_be_bytes());
            }
        }
        assert_eq!(h.finish(), recorded("fixed32", "rgb565-bayer4"));
        // The label: white pixels right of the image, black margins above
        // and below the image.
        let white = (IMAGE_WIDTH..PANEL_WIDTH)
            .flat_map(|x| (0..PANEL_HEIGHT).map(move |y| (x, y)))
            .filter(|&(x, y)| panel.at(x, y) == Rgb565::WHITE)
            .count();
        assert!(white > 200, "label pixels: {white}");
        assert_eq!(panel.at(0, 0), Rgb565::BLACK);
        assert_eq!(panel.at(IMAGE_WIDTH - 1, PANEL_HEIGHT - 1), Rgb565::BLACK);
    }

    #[test]
    fn draw_text_draws_what_embedded_graphics_text_draws() {
        let mut ours = WirePanel::new();
        let mut theirs = WirePanel::new();
        for (i, line) in ["raypack", "fixed32", "12.345 s", "65678", "~{|}?"].iter().enumerate() {
            let at = Point::new(3 + 7 * i as i32, 2 + 11 * i as i32);
            draw_text(&mut ours, line, at, Rgb565::WHITE, Rgb565::BLACK).unwrap();
            let style = embedded_graphics::mono_font::MonoTextStyleBuilder::new()
                .font(&FONT_6X10)
                .text_color(Rgb565::WHITE)
                .background_color(Rgb565::BLACK)
                .build();
            Text::with_baseline(line, at, style, Baseline::Top).draw(&mut theirs).unwrap();
        }
        assert!(ours.pixels == theirs.pixels);
    }

    #[test]
    fn the_label_fits_right_of_the_image() {
        let mut b = [0u8; LINE_BYTES];
        assert_eq!(format_seconds(12_345_678, &mut b), "12.345 s");
        assert_eq!(format_seconds(5_000, &mut b), "0.005 s");
        assert_eq!(format_seconds(u64::MAX, &mut b), "18446744073709.551 s");
        assert_eq!(format_count(65678, &mut b), "65678");
        // 12 characters of 6 pixels fit in the columns right of the image.
        assert!(LABEL_TOP_LEFT.x as u32 + 12 * 6 <= PANEL_WIDTH);
        assert!(LABEL_TOP_LEFT.y + 8 * LABEL_LINE <= PANEL_HEIGHT as i32);
    }
}
