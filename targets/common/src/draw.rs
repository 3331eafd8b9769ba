//! The render loop every firmware runs, real panel or not:
//! [`render_demo_into`] builds the demo scene and draws it into an
//! embedded-graphics [`DrawTarget`] with the core's
//! [`Renderer::draw_bands`](raypack::render::Renderer), band by band.
//!
//! The Raspberry Pi Pico calls it with its ST7789 panel (colour `Rgb565`);
//! the QEMU boards call it with a [`ChecksumPanel`], a target that folds
//! what it is sent into the checksums of `targets/checksums.txt`. Its colour,
//! [`Probe`], carries each pixel both as RGB888 and as the very `Rgb565`
//! value a panel receives (computed by raypack's `FromRgb8` for `Rgb565`,
//! the conversion the Pico's `draw_bands` runs), so the QEMU boards check
//! the RGB565 stream the panel gets, bit for bit, and the RGB888 image too.

use crate::Failure;
use crate::{SceneSlot, SlotScalar};
use core::convert::Infallible;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Point, Size};
use embedded_graphics_core::pixelcolor::raw::{RawU16, ToBytes};
use embedded_graphics_core::pixelcolor::{PixelColor, Rgb565};
use embedded_graphics_core::primitives::Rectangle;
use embedded_graphics_core::Pixel;
use raypack::demo::{build_demo_scene_for, demo_camera_for};
use raypack::draw_target::{DrawError, FromRgb8};
use raypack::output::{Dither, Fnv1a, ImageChecksums, CHECKSUM_DITHER};
use raypack::render::{Renderer, Rgb8};
use raypack::scene::SceneView;
use raypack::trace::{RayStats, TraceSettings, Tracer};
use raypack::Scalar;

/// Builds the core's demo scene for scalar `S` in `slot` (typically a
/// `static`, so the scene is never copied on the stack; a Q8.24 scene is
/// built in `f32` and converted into its frame), then renders it
/// at [`IMAGE_WIDTH`](crate::IMAGE_WIDTH)×[`IMAGE_HEIGHT`](crate::IMAGE_HEIGHT)
/// with packets of width `W` and draws it on `target` with its top-left
/// pixel at `top_left`, band by band through `band` (RGB565 colours get the
/// checksum's Bayer 4×4 dither, by image position). Returns the rays traced.
pub fn render_demo_into<S: SlotScalar, const W: usize, D>(
    slot: &mut SceneSlot,
    band: &mut [Rgb8],
    target: &mut D,
    top_left: Point,
) -> Result<RayStats, Failure>
where
    D: DrawTarget,
    D::Color: FromRgb8,
{
    draw_into::<S, W, D>(&demo_renderer::<S>(slot)?, band, target, top_left)
}

/// `renderer`'s frame drawn on `target` with its top-left pixel at
/// `top_left`, band by band through `band`, with the checksum's dither;
/// returns the rays traced.
fn draw_into<S: Scalar, const W: usize, D>(
    renderer: &Renderer<'_, S>,
    band: &mut [Rgb8],
    target: &mut D,
    top_left: Point,
) -> Result<RayStats, Failure>
where
    D: DrawTarget,
    D::Color: FromRgb8,
{
    let mut stats = RayStats::default();
    renderer.draw_bands::<W, D>(target, top_left, band, DITHER, &mut stats).map_err(draw_failure)?;
    Ok(stats)
}

/// What a failed `draw_bands` means for the firmware.
pub(crate) fn draw_failure<E>(e: DrawError<E>) -> Failure {
    match e {
        DrawError::BufferTooSmall(b) => Failure::Buffer(b),
        DrawError::Target(_) => Failure::Target,
    }
}

/// Builds the core's demo scene for scalar `S` in `slot` (see
/// [`render_demo_into`]) and returns a renderer of it at
/// [`IMAGE_WIDTH`](crate::IMAGE_WIDTH)×[`IMAGE_HEIGHT`](crate::IMAGE_HEIGHT),
/// which borrows the scene from `slot`.
pub fn demo_renderer<S: SlotScalar>(slot: &mut SceneSlot) -> Result<Renderer<'_, S>, Failure> {
    let (scene, described) = S::empty(slot);
    let frame = build_demo_scene_for(scene, described).map_err(Failure::Scene)?;
    let camera = demo_camera_for::<S>(&frame, crate::IMAGE_WIDTH, crate::IMAGE_HEIGHT).map_err(Failure::Camera)?;
    // Built: from here on the scene is only read, for as long as `slot` is lent.
    let scene = &*scene;
    let tracer: Tracer<'_, S> = Tracer::new(scene.view(), TraceSettings::default()).map_err(Failure::Trace)?;
    Ok(Renderer::new(tracer, camera))
}

/// The dither of every RGB565 pixel drawn: the one the checksums use.
pub const DITHER: Dither = CHECKSUM_DITHER;

/// A pixel as a [`ChecksumPanel`] receives it: its RGB888 value and the
/// `Rgb565` a panel would receive for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Probe {
    /// The rendered pixel.
    pub rgb888: Rgb8,
    /// What an `Rgb565` panel receives for it (same position, same dither).
    pub rgb565: Rgb565,
}

impl PixelColor for Probe {
    type Raw = ();
}

impl FromRgb8 for Probe {
    #[inline]
    fn from_rgb8(p: Rgb8, x: u32, y: u32, dither: Dither) -> Self {
        Probe { rgb888: p, rgb565: Rgb565::from_rgb8(p, x, y, dither) }
    }
}

/// The two bytes an RGB565 panel receives for `c`, high byte first (the
/// order of an ST7789's 16-bit colour and of the checksum).
#[inline]
pub fn rgb565_wire_bytes(c: Rgb565) -> [u8; 2] {
    RawU16::from(c).to_be_bytes()
}

/// A [`DrawTarget`] of [`IMAGE_WIDTH`](crate::IMAGE_WIDTH)×[`IMAGE_HEIGHT`](crate::IMAGE_HEIGHT)
/// [`Probe`] pixels that keeps no pixels: it folds every pixel it is sent,
/// in the order sent, into FNV-1a checksums of the RGB888 bytes and of the
/// RGB565 wire bytes, exactly as `Renderer::checksums` does for
/// `targets/checksums.txt`.
#[derive(Clone, Debug)]
pub struct ChecksumPanel {
    rgb888: Fnv1a,
    rgb565: Fnv1a,
    pixels: u32,
}

impl ChecksumPanel {
    /// A panel that has been sent nothing.
    pub const fn new() -> Self {
        ChecksumPanel { rgb888: Fnv1a::new(), rgb565: Fnv1a::new(), pixels: 0 }
    }

    #[inline]
    fn fold(&mut self, c: Probe) {
        self.rgb888.write(&c.rgb888);
        self.rgb565.write(&rgb565_wire_bytes(c.rgb565));
        self.pixels = self.pixels.wrapping_add(1);
    }

    /// The checksums of everything sent, with the rays `rays`.
    pub fn checksums(&self, rays: RayStats) -> ImageChecksums {
        ImageChecksums { rgb888: self.rgb888.finish(), rgb565: self.rgb565.finish(), pixels: self.pixels, rays }
    }
}

impl Default for ChecksumPanel {
    fn default() -> Self {
        Self::new()
    }
}

impl OriginDimensions for ChecksumPanel {
    fn size(&self) -> Size {
        Size::new(crate::IMAGE_WIDTH, crate::IMAGE_HEIGHT)
    }
}

impl DrawTarget for ChecksumPanel {
    type Color = Probe;
    type Error = Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Self::Color>>,
    {
        for Pixel(_, c) in pixels {
            self.fold(c);
        }
        Ok(())
    }

    fn fill_contiguous<I>(&mut self, _area: &Rectangle, colors: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Self::Color>,
    {
        // `draw_bands` sends whole bands inside the panel, top to bottom:
        // the colours in the order sent are the image, row-major.
        for c in colors {
            self.fold(c);
        }
        Ok(())
    }
}

/// The renderer of the demo scene baked into `static` data
/// ([`crate::baked_demo`]): [`Fixed32`](raypack::Fixed32) at
/// [`IMAGE_WIDTH`](crate::IMAGE_WIDTH)×[`IMAGE_HEIGHT`](crate::IMAGE_HEIGHT),
/// the same scene and camera [`demo_renderer`] builds, without building
/// anything: the view over the statics is checked, not made.
pub fn baked_demo_renderer() -> Result<Renderer<'static, raypack::Fixed32>, Failure> {
    use crate::baked_demo::{BACKGROUND, CAMERA, LIGHTS, MATERIALS, PRIMITIVES, VERTICES};
    let view = SceneView::new(&PRIMITIVES, &VERTICES, &MATERIALS, &LIGHTS, BACKGROUND).map_err(Failure::Scene)?;
    let tracer = Tracer::new(view, TraceSettings::default()).map_err(Failure::Trace)?;
    Ok(Renderer::new(tracer, CAMERA))
}

/// The baked demo ([`baked_demo_renderer`]) into a [`ChecksumPanel`]: the
/// `fixed32` checksums and ray counts of `targets/checksums.txt`, as
/// [`render_demo`] gives them.
pub fn render_baked_demo<const W: usize>(band: &mut [Rgb8]) -> Result<ImageChecksums, Failure> {
    let mut panel = ChecksumPanel::new();
    let rays = draw_into::<_, W, _>(&baked_demo_renderer()?, band, &mut panel, Point::zero())?;
    Ok(panel.checksums(rays))
}

/// [`render_demo_into`] a [`ChecksumPanel`]: the checksums and ray counts of
/// the demo image, as `targets/checksums.txt` records them.
pub fn render_demo<S: SlotScalar, const W: usize>(
    slot: &mut SceneSlot,
    band: &mut [Rgb8],
) -> Result<ImageChecksums, Failure> {
    let mut panel = ChecksumPanel::new();
    let rays = render_demo_into::<S, W, _>(slot, band, &mut panel, Point::zero())?;
    Ok(panel.checksums(rays))
}
