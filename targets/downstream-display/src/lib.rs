//! What an application drawing raypack's demo scene on a mipidsi panel
//! writes: a function generic over any embedded-graphics `DrawTarget`,
//! and the same on a mipidsi ST7789. Built (not run) by
//! `scripts/firmware.sh` for `thumbv6m-none-eabi`, after a fresh resolve.
#![no_std]

use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::*;
use mipidsi::interface::Interface;
use mipidsi::models::ST7789;
use raypack::demo::{build_demo_scene, demo_camera, DemoScene};
use raypack::draw_target::DrawError;
use raypack::output::Dither;
use raypack::prelude::*;

/// Why [`draw_demo`] stopped.
#[derive(Debug)]
pub enum DemoError<E> {
    /// The scene did not build (it always does).
    Scene,
    /// Camera or tracer set-up failed (they never do for the demo).
    Setup,
    /// Drawing failed.
    Draw(DrawError<E>),
}

/// Renders the demo scene into `scene` (empty) and draws it, `width` ×
/// `height`, on `display` at its top-left corner, band by band through
/// `band`, with Bayer 4×4 dithering.
pub fn draw_demo<S: Scalar, D: DrawTarget<Color = Rgb565>>(
    display: &mut D,
    scene: &mut DemoScene<S>,
    band: &mut [Rgb8],
    width: u32,
    height: u32,
) -> Result<RayStats, DemoError<D::Error>> {
    build_demo_scene(scene).map_err(|_| DemoError::Scene)?;
    let camera = demo_camera::<S>(width, height).map_err(|_| DemoError::Setup)?;
    let tracer: Tracer<'_, S> = Tracer::new(scene.view(), TraceSettings::default()).map_err(|_| DemoError::Setup)?;
    let mut stats = RayStats::default();
    Renderer::new(tracer, camera)
        .draw_bands::<1, D>(display, Point::zero(), band, Dither::Bayer4, &mut stats)
        .map_err(DemoError::Draw)?;
    Ok(stats)
}

/// [`draw_demo`] on a mipidsi ST7789 over any 8-bit interface, at the
/// panel's size.
pub fn draw_demo_on_st7789<S: Scalar, DI, RST>(
    display: &mut mipidsi::Display<DI, ST7789, RST>,
    scene: &mut DemoScene<S>,
    band: &mut [Rgb8],
) -> Result<RayStats, DemoError<DI::Error>>
where
    DI: Interface<Word = u8>,
    RST: embedded_hal::digital::OutputPin,
{
    let size = display.bounding_box().size;
    draw_demo(display, scene, band, size.width, size.height)
}
