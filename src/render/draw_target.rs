//! Rendering straight into an [embedded-graphics] display (feature
//! `embedded-graphics`): any [`DrawTarget`] whose colour is [`Rgb565`] or
//! [`Rgb888`] (or [`Bgr565`]/[`Bgr888`]), band by band, without a
//! framebuffer.
//!
//! [`Renderer::draw_bands`] runs [`Renderer::render_bands`] (the band loop the
//! firmware checksums) and sends each band to the target with one
//! [`DrawTarget::fill_contiguous`] call: a display driver gets whole
//! rectangles of full rows (one address window and one burst of pixels on
//! most SPI panels), and the only pixel memory is the band buffer the caller
//! supplies, for example an array on the stack. Nothing is allocated.
//!
//! Colours are converted by [`crate::render::bands`]: RGB565 is
//! [`rgb565`] with the requested ordered
//! [`Dither`], a function of the pixel's position *in the image* (not on the
//! display), so it is deterministic and the 16-bit values drawn are the ones
//! [`ImageChecksums::rgb565`](crate::render::bands::ImageChecksums::rgb565) hashes
//! when the dither is [`CHECKSUM_DITHER`](crate::render::bands::CHECKSUM_DITHER).
//!
//! # Placement and clipping
//!
//! The image's top-left pixel goes to `top_left` in target coordinates.
//! Each band is clipped to the target's [`bounding_box`](embedded_graphics_core::geometry::Dimensions::bounding_box)
//! before it is sent (drivers are asked to clip too, but not all do): a band
//! partly outside the target is sent as its visible part, a band wholly
//! outside is not sent at all, and nothing is ever drawn outside the target.
//! When the image lies inside the target, every call is one whole band:
//! full image width, the band height (see
//! [`band_rows`](crate::render::bands::band_rows)), the last band shorter, top to
//! bottom, covering the image once. The whole image is rendered in every case
//! (ray counts count it all): size the camera to the display.
//!
//! The first error the target returns stops rendering and is returned as
//! [`DrawError::Target`]; nothing panics.
//!
//! ```
//! use embedded_graphics::{mock_display::MockDisplay, pixelcolor::Rgb565, prelude::*, primitives::Rectangle};
//! use raypack::demo::{demo_camera, demo_scene};
//! use raypack::output::Dither;
//! use raypack::prelude::*;
//!
//! let scene = demo_scene::<f32>().unwrap();
//! let camera = demo_camera::<f32>(48, 32).unwrap();
//! let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
//! let renderer = Renderer::new(tracer, camera);
//!
//! // Any display driver implementing DrawTarget<Color = Rgb565> works the same.
//! let mut display: MockDisplay<Rgb565> = MockDisplay::new();
//! let mut band = [[0u8; 3]; 48 * 4]; // four rows: all the pixel memory needed
//! let mut stats = RayStats::default();
//! renderer
//!     .draw_bands::<4, _>(&mut display, Point::new(8, 16), &mut band, Dither::Bayer4, &mut stats)
//!     .unwrap();
//! assert_eq!(display.affected_area(), Rectangle::new(Point::new(8, 16), Size::new(48, 32)));
//! assert_eq!(stats.primary, 48 * 32);
//! ```
//!
//! [embedded-graphics]: https://docs.rs/embedded-graphics/0.8

use crate::geom::camera::Rect;
use crate::num::scalar::Scalar;
use crate::query::Accelerator;
use crate::render::bands::{rgb565, BandError, Dither, RectPositions};
use crate::render::{BufferTooSmall, Renderer, Rgb8};
use crate::trace::RayStats;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::raw::RawU16;
use embedded_graphics_core::pixelcolor::{Bgr565, Bgr888, PixelColor, Rgb565, Rgb888, RgbColor};
use embedded_graphics_core::primitives::Rectangle;

/// Display colours raypack can produce from its RGB888 pixels.
pub trait FromRgb8: PixelColor {
    /// The colour of image pixel `(x, y)` whose RGB888 value is `p`,
    /// reduced with ordered dithering `dither` where the colour has fewer
    /// bits than 8 per channel (ignored otherwise).
    fn from_rgb8(p: Rgb8, x: u32, y: u32, dither: Dither) -> Self;
}

impl FromRgb8 for Rgb888 {
    #[inline]
    fn from_rgb8(p: Rgb8, _x: u32, _y: u32, _dither: Dither) -> Self {
        Rgb888::new(p[0], p[1], p[2])
    }
}

impl FromRgb8 for Bgr888 {
    #[inline]
    fn from_rgb8(p: Rgb8, _x: u32, _y: u32, _dither: Dither) -> Self {
        Bgr888::new(p[0], p[1], p[2])
    }
}

impl FromRgb8 for Rgb565 {
    #[inline]
    fn from_rgb8(p: Rgb8, x: u32, y: u32, dither: Dither) -> Self {
        // The same 16 bits as `output::rgb565`, which the firmware checksums
        // (embedded-graphics' raw Rgb565 layout is r:15–11, g:10–5, b:4–0 too).
        Rgb565::from(RawU16::new(rgb565(p, x, y, dither)))
    }
}

impl FromRgb8 for Bgr565 {
    #[inline]
    fn from_rgb8(p: Rgb8, x: u32, y: u32, dither: Dither) -> Self {
        // The channels of the RGB565 value, stored in BGR order.
        let c = Rgb565::from_rgb8(p, x, y, dither);
        Bgr565::new(c.r(), c.g(), c.b())
    }
}

/// Why [`Renderer::draw_bands`] stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawError<E> {
    /// The band buffer holds less than one image row.
    BufferTooSmall(BufferTooSmall),
    /// The draw target returned an error (rendering stopped there).
    Target(E),
}

impl<E: core::fmt::Debug> core::fmt::Display for DrawError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            DrawError::BufferTooSmall(b) => write!(f, "band {b}"),
            DrawError::Target(e) => write!(f, "draw target: {e:?}"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for DrawError<E> {}

/// The part of image rectangle `rect`, placed with the image's top-left
/// pixel at `top_left`, that lies inside `clip` (target coordinates):
/// [`Rect::placed`] in embedded-graphics types.
fn visible_part(rect: Rect, top_left: Point, clip: &Rectangle) -> Option<(Rect, Point)> {
    let clip = ((clip.top_left.x, clip.top_left.y), (clip.size.width, clip.size.height));
    rect.placed((top_left.x, top_left.y), clip).map(|(r, (x, y))| (r, Point::new(x, y)))
}

impl<'a, S: Scalar, A: Accelerator<S>, const D: usize> Renderer<'a, S, A, D> {
    /// Renders the whole image with packets of width `W` and draws it on
    /// `target` with its top-left pixel at `top_left`, band by band through
    /// `band` (as many full rows as it holds, see
    /// [`band_rows`](crate::render::bands::band_rows)): one
    /// [`fill_contiguous`](DrawTarget::fill_contiguous) call per band, pixels
    /// row-major, each band clipped to the target's bounding box (see the
    /// [module documentation](self) for placement and clipping). Colours with
    /// fewer than 8 bits per channel get `dither`, by image position. Ray
    /// counts are added to `stats`.
    ///
    /// Stops at the first target error and returns it as
    /// [`DrawError::Target`]; a `band` shorter than one image row is
    /// [`DrawError::BufferTooSmall`] and nothing is drawn.
    pub fn draw_bands<const W: usize, T>(
        &self,
        target: &mut T,
        top_left: Point,
        band: &mut [Rgb8],
        dither: Dither,
        stats: &mut RayStats,
    ) -> Result<(), DrawError<T::Error>>
    where
        T: DrawTarget,
        T::Color: FromRgb8,
    {
        let clip = target.bounding_box();
        let width = self.camera.width() as usize;
        let r = self.render_bands::<W, T::Error>(band, stats, |rect, pixels| {
            let Some((visible, corner)) = visible_part(rect, top_left, &clip) else {
                return Ok(());
            };
            // `pixels` is the band, row-major with stride `width`; take the
            // visible rows, and in each the visible columns. `visible` lies
            // inside `rect`, so every `get` succeeds and the colours number
            // exactly `visible.w · visible.h`.
            let (x0, x1) = (visible.x as usize, visible.x as usize + visible.w as usize);
            let area = Rectangle::new(corner, Size::new(visible.w, visible.h));
            let skip = (visible.y - rect.y) as usize;
            if x0 == 0 && x1 == width {
                // Whole rows (a band on a panel at least as wide as the
                // image): one run of the band, without a row iterator.
                let run = pixels.get(skip * width..(skip + visible.h as usize) * width).unwrap_or(&[]);
                let colors = run
                    .iter()
                    .zip(RectPositions::new(visible))
                    .map(|(p, (x, y))| T::Color::from_rgb8(*p, x, y, dither));
                return target.fill_contiguous(&area, colors);
            }
            let colors = pixels
                .chunks(width.max(1))
                .skip(skip)
                .take(visible.h as usize)
                .flat_map(|row| row.get(x0..x1).unwrap_or(&[]))
                .zip(RectPositions::new(visible))
                .map(|(p, (x, y))| T::Color::from_rgb8(*p, x, y, dither));
            target.fill_contiguous(&area, colors)
        });
        r.map_err(|e| match e {
            BandError::BufferTooSmall(b) => DrawError::BufferTooSmall(b),
            BandError::Sink(e) => DrawError::Target(e),
        })
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::render::bands::{band_rows, Fnv1a, BAYER8, CHECKSUM_DITHER};
    use crate::scene::demo::{demo_camera, demo_scene, DemoScene};
    use crate::trace::{TraceSettings, Tracer};
    use embedded_graphics::draw_target::DrawTargetExt;
    use embedded_graphics::mock_display::MockDisplay;
    use embedded_graphics::pixelcolor::raw::RawData;
    use embedded_graphics::prelude::{OriginDimensions, Pixel, PointsIter};
    use std::vec;
    use std::vec::Vec;

    /// A display in memory that records every `fill_contiguous` call (its
    /// area and colours), refuses to draw outside itself or a pixel twice,
    /// and can be told to fail on its `n`-th call.
    struct RecordingPanel<C> {
        size: Size,
        pixels: Vec<Option<C>>,
        fills: Vec<(Rectangle, Vec<C>)>,
        single_pixels: usize,
        fail_on_call: Option<usize>,
    }

    impl<C: PixelColor> RecordingPanel<C> {
        fn new(w: u32, h: u32) -> Self {
            RecordingPanel {
                size: Size::new(w, h),
                pixels: vec![None; (w * h) as usize],
                fills: Vec::new(),
                single_pixels: 0,
                fail_on_call: None,
            }
        }
        fn put(&mut self, p: Point, c: C) {
            assert!(
                p.x >= 0 && p.y >= 0 && (p.x as u32) < self.size.width && (p.y as u32) < self.size.height,
                "outside: {p:?}"
            );
            let slot = &mut self.pixels[(p.y as u32 * self.size.width + p.x as u32) as usize];
            assert!(slot.is_none(), "pixel {p:?} drawn twice");
            *slot = Some(c);
        }
        fn pixel(&self, x: u32, y: u32) -> Option<C> {
            self.pixels[(y * self.size.width + x) as usize]
        }
        /// `(top, height)` of every call, in call order.
        fn rows(&self) -> Vec<(i32, u32)> {
            self.fills.iter().map(|(r, _)| (r.top_left.y, r.size.height)).collect()
        }
    }

    impl<C: PixelColor> OriginDimensions for RecordingPanel<C> {
        fn size(&self) -> Size {
            self.size
        }
    }

    impl<C: PixelColor> DrawTarget for RecordingPanel<C> {
        type Color = C;
        type Error = &'static str;
        fn draw_iter<I: IntoIterator<Item = Pixel<C>>>(&mut self, pixels: I) -> Result<(), Self::Error> {
            for Pixel(p, c) in pixels {
                self.single_pixels += 1;
                self.put(p, c);
            }
            Ok(())
        }
        fn fill_contiguous<I: IntoIterator<Item = C>>(
            &mut self,
            area: &Rectangle,
            colors: I,
        ) -> Result<(), Self::Error> {
            if self.fail_on_call == Some(self.fills.len()) {
                return Err("bus error");
            }
            let colors: Vec<C> = colors.into_iter().collect();
            assert_eq!(colors.len() as u32, area.size.width * area.size.height, "one colour per pixel of {area:?}");
            for (p, c) in area.points().zip(colors.iter()) {
                self.put(p, *c);
            }
            self.fills.push((*area, colors));
            Ok(())
        }
    }

    fn renderer(scene: &DemoScene<f32>, w: u32, h: u32) -> Renderer<'_, f32> {
        let camera = demo_camera::<f32>(w, h).unwrap();
        Renderer::new(Tracer::new(scene.view(), TraceSettings::default()).unwrap(), camera)
    }

    /// The image as `render_bands` delivers it (pixels and their image
    /// positions), assembled into one row-major frame.
    fn banded_frame<const W: usize>(r: &Renderer<'_, f32>, band_px: usize) -> Vec<Rgb8> {
        let (w, h) = (r.camera.width(), r.camera.height());
        let mut frame = vec![[0u8; 3]; (w * h) as usize];
        let mut band = vec![[0u8; 3]; band_px];
        r.render_bands::<W, ()>(&mut band, &mut RayStats::default(), |rect, px| {
            for (p, (x, y)) in px.iter().zip(RectPositions::new(rect)) {
                frame[(y * w + x) as usize] = *p;
            }
            Ok(())
        })
        .unwrap();
        frame
    }

    /// (a) + (b): for one packet width and band size, RGB888 and RGB565
    /// targets (each dither) get exactly the `output.rs` pixels, in whole
    /// bands of the requested height, top to bottom, each pixel once; and
    /// the drawn bytes hash to the firmware's checksums.
    fn check_width<const W: usize>(r: &Renderer<'_, f32>, band_px: usize) {
        let (w, h) = (r.camera.width(), r.camera.height());
        let frame = banded_frame::<W>(r, band_px);
        let rows = band_rows::<W>(w, band_px);
        assert!(rows > 0 && h % rows != 0, "the cases should end on a shorter band");
        let mut want_rows = Vec::new();
        let mut y = 0;
        while y < h {
            want_rows.push((y as i32, rows.min(h - y)));
            y += rows;
        }
        let checks = r.checksums::<W>(&mut vec![[0u8; 3]; band_px]).unwrap();

        let mut band = vec![[0u8; 3]; band_px];
        let mut panel = RecordingPanel::<Rgb888>::new(w, h);
        let mut stats = RayStats::default();
        r.draw_bands::<W, _>(&mut panel, Point::zero(), &mut band, Dither::Bayer8, &mut stats).unwrap();
        assert_eq!(panel.single_pixels, 0, "every pixel goes through fill_contiguous");
        assert_eq!(panel.rows(), want_rows, "W={W} band={band_px}");
        assert!(panel.fills.iter().all(|(a, _)| a.top_left.x == 0 && a.size.width == w));
        assert_eq!(stats.primary, (w * h) as u64);
        let drawn: Vec<Rgb8> = panel.pixels.iter().map(|c| c.map(|c| [c.r(), c.g(), c.b()]).unwrap()).collect();
        assert_eq!(drawn, frame, "RGB888, W={W} band={band_px}");
        let mut hash = Fnv1a::new();
        for (_, colors) in &panel.fills {
            for c in colors {
                hash.write(&[c.r(), c.g(), c.b()]);
            }
        }
        assert_eq!(hash.finish(), checks.rgb888, "the RGB888 bytes drawn are the bytes the firmware hashes");

        for dither in [Dither::None, Dither::Bayer4, Dither::Bayer8] {
            let mut panel = RecordingPanel::<Rgb565>::new(w, h);
            r.draw_bands::<W, _>(&mut panel, Point::zero(), &mut band, dither, &mut RayStats::default()).unwrap();
            assert_eq!(panel.rows(), want_rows);
            for y in 0..h {
                for x in 0..w {
                    let want = rgb565(frame[(y * w + x) as usize], x, y, dither);
                    let got = panel.pixel(x, y).map(|c| RawU16::from(c).into_inner());
                    assert_eq!(got, Some(want), "RGB565 {dither:?} W={W} ({x}, {y})");
                }
            }
            if dither == CHECKSUM_DITHER {
                let mut hash = Fnv1a::new();
                for (_, colors) in &panel.fills {
                    for c in colors {
                        hash.write(&RawU16::from(*c).into_inner().to_be_bytes());
                    }
                }
                assert_eq!(hash.finish(), checks.rgb565, "the RGB565 bytes drawn are the bytes the firmware hashes");
            }
        }
    }

    #[test]
    fn targets_get_the_output_pixels_in_whole_bands_for_every_width() {
        let scene = demo_scene::<f32>().unwrap();
        let r = renderer(&scene, 13, 11);
        // Two rows (an exact fit), and five rows plus change (rounded down
        // to whole packet rows: 4 for W = 4 and 8, 5 for W = 1).
        for band_px in [13 * 2, 13 * 5 + 3] {
            check_width::<1>(&r, band_px);
            check_width::<4>(&r, band_px);
            check_width::<8>(&r, band_px);
        }
        // The band heights, counted by hand for 13×11.
        let mut panel = RecordingPanel::<Rgb888>::new(13, 11);
        let mut band = [[0u8; 3]; 13 * 5 + 3];
        r.draw_bands::<8, _>(&mut panel, Point::zero(), &mut band, Dither::None, &mut RayStats::default()).unwrap();
        assert_eq!(panel.rows(), [(0, 4), (4, 4), (8, 3)]);
        let mut panel = RecordingPanel::<Rgb888>::new(13, 11);
        r.draw_bands::<1, _>(&mut panel, Point::zero(), &mut band, Dither::None, &mut RayStats::default()).unwrap();
        assert_eq!(panel.rows(), [(0, 5), (5, 5), (10, 1)]);
    }

    #[test]
    fn rgb565_dither_follows_the_textbook_formula_by_image_position_with_an_offset() {
        let scene = demo_scene::<f32>().unwrap();
        let r = renderer(&scene, 30, 11);
        let mut full = vec![[0u8; 3]; 30 * 11];
        r.render_rect::<1>(r.camera.full_rect(), &mut full, &mut RayStats::default()).unwrap();

        let mut panel = RecordingPanel::<Rgb565>::new(40, 20);
        let mut band = [[0u8; 3]; 30 * 4 + 7]; // four rows
        let mut stats = RayStats::default();
        r.draw_bands::<8, _>(&mut panel, Point::new(5, 3), &mut band, Dither::Bayer8, &mut stats).unwrap();

        assert_eq!(panel.single_pixels, 0);
        assert_eq!(panel.rows(), [(3, 4), (7, 4), (11, 3)]);
        assert!(panel.fills.iter().all(|(a, _)| a.top_left.x == 5 && a.size.width == 30));
        assert_eq!(stats.primary, 30 * 11);
        for y in 0..20u32 {
            for x in 0..40u32 {
                let got = panel.pixel(x, y);
                if !((5..35).contains(&x) && (3..14).contains(&y)) {
                    assert_eq!(got, None, "outside the image ({x}, {y})");
                    continue;
                }
                // Independent of output.rs's integer form: τ = (rank + ½)/64
                // at the *image* position, floor(v·m/255 + τ) capped at m.
                let (ix, iy) = (x - 5, y - 3);
                let p = full[(iy * 30 + ix) as usize];
                let rank = BAYER8[(iy % 8) as usize][(ix % 8) as usize] as f64;
                let q = |v: u8, m: f64| ((v as f64 * m / 255.0 + (rank + 0.5) / 64.0).floor()).min(m) as u16;
                let want = (q(p[0], 31.0) << 11) | (q(p[1], 63.0) << 5) | q(p[2], 31.0);
                assert_eq!(got.map(|c| RawU16::from(c).into_inner()), Some(want), "({x}, {y})");
            }
        }

        // BGR targets get the same channel values.
        let mut bgr = RecordingPanel::<Bgr565>::new(40, 20);
        r.draw_bands::<8, _>(&mut bgr, Point::new(5, 3), &mut band, Dither::Bayer8, &mut RayStats::default()).unwrap();
        let mut bgr888 = RecordingPanel::<Bgr888>::new(30, 11);
        r.draw_bands::<4, _>(&mut bgr888, Point::zero(), &mut band, Dither::Bayer8, &mut RayStats::default()).unwrap();
        for y in 0..11u32 {
            for x in 0..30u32 {
                let (a, b) = (panel.pixel(x + 5, y + 3).unwrap(), bgr.pixel(x + 5, y + 3).unwrap());
                assert_eq!((a.r(), a.g(), a.b()), (b.r(), b.g(), b.b()));
                let c = bgr888.pixel(x, y).unwrap();
                assert_eq!([c.r(), c.g(), c.b()], full[(y * 30 + x) as usize]);
            }
        }
    }

    #[test]
    fn a_target_error_is_returned_and_stops_rendering() {
        let scene = demo_scene::<f32>().unwrap();
        let r = renderer(&scene, 16, 9);
        let mut band = [[0u8; 3]; 16 * 2];
        for fail_on in [0usize, 2] {
            let mut panel = RecordingPanel::<Rgb565>::new(16, 9);
            panel.fail_on_call = Some(fail_on);
            let mut stats = RayStats::default();
            let err = r.draw_bands::<4, _>(&mut panel, Point::zero(), &mut band, Dither::None, &mut stats);
            assert_eq!(err, Err(DrawError::Target("bus error")));
            assert_eq!(panel.fills.len(), fail_on, "no call after the failing one");
            // The failing band was rendered, nothing after it.
            assert_eq!(stats.primary, 16 * 2 * (fail_on as u64 + 1));
        }
        let mut tiny = [[0u8; 3]; 15];
        let mut panel = RecordingPanel::<Rgb888>::new(16, 9);
        let err = r.draw_bands::<4, _>(&mut panel, Point::zero(), &mut tiny, Dither::None, &mut RayStats::default());
        assert_eq!(err, Err(DrawError::BufferTooSmall(BufferTooSmall { needed: 16, provided: 15 })));
        assert!(panel.fills.is_empty());
        assert!(std::format!("{}", DrawError::Target("bus error")).contains("bus error"));
    }

    #[test]
    fn bands_are_clipped_to_a_smaller_target_and_skipped_when_invisible() {
        let scene = demo_scene::<f32>().unwrap();
        let r = renderer(&scene, 13, 11);
        let mut full = vec![[0u8; 3]; 13 * 11];
        r.render_rect::<1>(r.camera.full_rect(), &mut full, &mut RayStats::default()).unwrap();
        let mut band = [[0u8; 3]; 13 * 3];

        // A 9×6 target, the image at (-2, -4): image columns 2..11 and rows
        // 4..10 are visible. Bands of 3 rows: 0..3 (invisible), 3..6, 6..9, 9..11.
        let mut panel = RecordingPanel::<Rgb888>::new(9, 6);
        let mut stats = RayStats::default();
        r.draw_bands::<1, _>(&mut panel, Point::new(-2, -4), &mut band, Dither::None, &mut stats).unwrap();
        let areas: Vec<Rectangle> = panel.fills.iter().map(|(a, _)| *a).collect();
        let rect = |x, y, w, h| Rectangle::new(Point::new(x, y), Size::new(w, h));
        assert_eq!(areas, [rect(0, 0, 9, 2), rect(0, 2, 9, 3), rect(0, 5, 9, 1)]);
        assert_eq!(stats.primary, 13 * 11, "the whole image is rendered");
        for y in 0..6u32 {
            for x in 0..9u32 {
                let c = panel.pixel(x, y).unwrap();
                assert_eq!([c.r(), c.g(), c.b()], full[((y + 4) * 13 + x + 2) as usize], "({x}, {y})");
            }
        }

        // A larger target with the image hanging off its right and bottom edges.
        let mut panel = RecordingPanel::<Rgb888>::new(20, 12);
        r.draw_bands::<4, _>(&mut panel, Point::new(15, 7), &mut band, Dither::None, &mut RayStats::default()).unwrap();
        let areas: Vec<Rectangle> = panel.fills.iter().map(|(a, _)| *a).collect();
        assert_eq!(areas, [rect(15, 7, 5, 2), rect(15, 9, 5, 2), rect(15, 11, 5, 1)]);
        for y in 0..12u32 {
            for x in 0..20u32 {
                let got = panel.pixel(x, y).map(|c| [c.r(), c.g(), c.b()]);
                let want = (x >= 15 && y >= 7).then(|| full[((y - 7) * 13 + x - 15) as usize]);
                assert_eq!(got, want, "({x}, {y})");
            }
        }

        // Wholly outside (including at the far ends of i32): no call, no error.
        for at in [Point::new(9, 0), Point::new(0, -11), Point::new(i32::MAX, i32::MAX), Point::new(i32::MIN, 0)] {
            let mut panel = RecordingPanel::<Rgb565>::new(9, 6);
            r.draw_bands::<8, _>(&mut panel, at, &mut band, Dither::Bayer4, &mut RayStats::default()).unwrap();
            assert!(panel.fills.is_empty(), "{at:?}");
        }
        // At x = i32::MAX - 1 of a target reaching past i32::MAX, two
        // columns are addressable (i32::MAX - 1 and i32::MAX).
        assert_eq!(
            visible_part(Rect { x: 0, y: 0, w: 13, h: 2 }, Point::new(i32::MAX - 1, 0), &rect(0, 0, u32::MAX, 6)),
            Some((Rect { x: 0, y: 0, w: 2, h: 2 }, Point::new(i32::MAX - 1, 0)))
        );
    }

    #[test]
    fn mock_display_gets_every_pixel_once_and_clipped_targets_only_their_part() {
        let scene = demo_scene::<f32>().unwrap();
        let r = renderer(&scene, 24, 20);
        let mut full = vec![[0u8; 3]; 24 * 20];
        r.render_rect::<8>(r.camera.full_rect(), &mut full, &mut RayStats::default()).unwrap();
        let mut band = [[0u8; 3]; 24 * 4];

        // MockDisplay panics on out-of-bounds drawing and on overdraw.
        let mut display: MockDisplay<Rgb565> = MockDisplay::new();
        r.draw_bands::<8, _>(&mut display, Point::new(40, 44), &mut band, CHECKSUM_DITHER, &mut RayStats::default())
            .unwrap();
        assert_eq!(display.affected_area(), Rectangle::new(Point::new(40, 44), Size::new(24, 20)));
        for y in 0..20u32 {
            for x in 0..24u32 {
                let got = display.get_pixel(Point::new(40 + x as i32, 44 + y as i32));
                let want = rgb565(full[(y * 24 + x) as usize], x, y, CHECKSUM_DITHER);
                assert_eq!(got.map(|c| RawU16::from(c).into_inner()), Some(want));
            }
        }

        // A clipped view: its bounding box does not start at the origin.
        let mut display: MockDisplay<Rgb888> = MockDisplay::new();
        let window = Rectangle::new(Point::new(10, 12), Size::new(7, 5));
        r.draw_bands::<4, _>(
            &mut display.clipped(&window),
            Point::new(4, 6),
            &mut band,
            Dither::None,
            &mut RayStats::default(),
        )
        .unwrap();
        assert_eq!(display.affected_area(), window);
        for y in 12..17u32 {
            for x in 10..17u32 {
                let c = display.get_pixel(Point::new(x as i32, y as i32)).unwrap();
                assert_eq!([c.r(), c.g(), c.b()], full[((y - 6) * 24 + x - 4) as usize]);
            }
        }
    }
}
