//! One frame on two cores: the band schedule the Raspberry Pi Pico's two
//! Cortex-M0+ cores split the demo frame by, and its measurement on one
//! core under QEMU.
//!
//! The image is cut into bands of [`BAND_ROWS`] rows; band `i` belongs to
//! core `i mod 2` ([`band_owner`]). Each core renders its bands into its own
//! band buffer. Core 0 also sends every band to the display, in image order:
//! its own as soon as it has rendered them, core 1's when core 1 hands them
//! over ([`Peer`]); core 1 renders its next band once core 0 has sent the
//! previous one on ([`Courier`]). The display therefore receives the very
//! stream one core sends through [`Renderer::draw_bands`](raypack::render::Renderer)
//! with a buffer of [`BAND_ROWS`] rows (host-tested in `panel`): the same
//! pixels, computed by the same code, in the same order and the same
//! `fill_contiguous` calls.
//!
//! [`run_shares`] renders each core's bands on one core and counts the
//! instructions of each band (under QEMU's `-icount`): what each core of a
//! two-core part retires for its share of the frame.

use crate::draw::{demo_renderer, draw_failure, ChecksumPanel, Probe, DITHER};
use crate::timing::Clock;
use crate::{report_failure, report_render, Console, Failure, SceneSlot, SlotScalar, IMAGE_HEIGHT, IMAGE_WIDTH};
use core::convert::Infallible;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Point, Size};
use embedded_graphics_core::primitives::Rectangle;
use embedded_graphics_core::Pixel;
use raypack::camera::Rect;
use raypack::draw_target::FromRgb8;
use raypack::output::RectPositions;
use raypack::render::{BufferTooSmall, Renderer, Rgb8};
use raypack::trace::RayStats;

/// Rows per band: the Pico's band buffers (one per core, 480 bytes each).
/// One row rather than two or four evens the cores' pairs of bands out
/// (adjacent rows cost nearly the same: a shorter lockstep frame,
/// docs/firmware.md "Two cores"), for more hand-overs and SPI address
/// windows (128 a frame).
pub const BAND_ROWS: u32 = 1;
/// Cores the frame is split between.
pub const CORES: u32 = 2;
/// Bands in the image.
pub const BANDS: u32 = IMAGE_HEIGHT.div_ceil(BAND_ROWS);
/// Pixels of one band buffer.
pub const BAND_PIXELS: usize = (IMAGE_WIDTH * BAND_ROWS) as usize;
/// What core 1 hands over instead of a band index when its render failed.
pub const FAILED: u32 = u32::MAX;
/// What core 1 sends after its last band, with its ray counts.
pub const DONE: u32 = u32::MAX - 1;

/// The core that renders band `index`: bands alternate between the cores,
/// so each gets rows from the whole height of the image.
pub const fn band_owner(index: u32) -> u32 {
    index % CORES
}

/// The image rows of band `index` (the last band may be shorter; a band
/// past the image is empty).
pub fn band_rect(index: u32) -> Rect {
    let y = index.saturating_mul(BAND_ROWS).min(IMAGE_HEIGHT);
    Rect { x: 0, y, w: IMAGE_WIDTH, h: BAND_ROWS.min(IMAGE_HEIGHT - y) }
}

/// Renders band `index` with packets of width `W` through `buffer`, in
/// pieces of as many whole rows as `buffer` holds (all of the band when it
/// holds [`BAND_PIXELS`]), handing each piece to `sink`; ray counts go to
/// `stats`.
pub fn render_band<S: raypack::Scalar, const W: usize, E>(
    renderer: &Renderer<'_, S>,
    index: u32,
    buffer: &mut [Rgb8],
    stats: &mut RayStats,
    mut sink: impl FnMut(Rect, &[Rgb8]) -> Result<(), E>,
) -> Result<(), BandFailure<E>> {
    let band = band_rect(index);
    let rows = (buffer.len() / IMAGE_WIDTH as usize).min(BAND_ROWS as usize) as u32;
    if rows == 0 {
        return Err(BandFailure::Render(Failure::Buffer(BufferTooSmall {
            needed: IMAGE_WIDTH as usize,
            provided: buffer.len(),
        })));
    }
    let mut y = band.y;
    while y < band.y + band.h {
        let piece = Rect { x: 0, y, w: IMAGE_WIDTH, h: rows.min(band.y + band.h - y) };
        renderer.render_rect::<W>(piece, buffer, stats).map_err(|e| BandFailure::Render(Failure::Buffer(e)))?;
        // `rows` rows fit in `buffer`: this is all of the piece.
        let pixels = buffer.get(..(piece.w * piece.h) as usize).unwrap_or(&[]);
        sink(piece, pixels).map_err(BandFailure::Sink)?;
        y += piece.h;
    }
    Ok(())
}

/// Why [`render_band`] stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BandFailure<E> {
    /// The render could not run.
    Render(Failure),
    /// The sink returned an error.
    Sink(E),
}

/// Core 1's end of the link between the cores: its band buffer and the
/// hand-over to core 0.
pub trait Courier {
    /// Runs `f` on this core's band buffer (of [`BAND_PIXELS`] pixels),
    /// which core 0 does not read meanwhile.
    fn with_buffer<R>(&mut self, f: impl FnOnce(&mut [Rgb8]) -> R) -> R;
    /// Tells core 0 that band `message` is in the buffer ([`FAILED`]: that
    /// the render failed) and returns once core 0 is done with the buffer.
    fn hand_over(&mut self, message: u32);
    /// Passes this core's ray counts to core 0, after its last band.
    fn finish(&mut self, stats: RayStats);
}

/// Core 0's end of the link.
pub trait Peer {
    /// Waits for core 1's next hand-over and runs `f` on its message (a band
    /// index or [`FAILED`]) and the pixels of core 1's buffer, then lets
    /// core 1 have the buffer back.
    fn receive<R>(&mut self, f: impl FnOnce(u32, &[Rgb8]) -> R) -> R;
    /// Waits for core 1 to finish and returns its ray counts
    /// ([`Failure::Peer`] if it sent anything else).
    fn finish(&mut self) -> Result<RayStats, Failure>;
}

/// Core 1's part of the frame: renders every band of core 1 into its
/// buffer and hands each over; then its ray counts.
pub fn core1_bands<S: raypack::Scalar, const W: usize>(renderer: &Renderer<'_, S>, courier: &mut impl Courier) {
    let mut stats = RayStats::default();
    for index in (0..BANDS).filter(|&i| band_owner(i) == 1) {
        let ok = courier.with_buffer(|buffer| {
            let enough = buffer.len() >= BAND_PIXELS;
            enough && render_band::<S, W, ()>(renderer, index, buffer, &mut stats, |_, _| Ok(())).is_ok()
        });
        courier.hand_over(if ok { index } else { FAILED });
        if !ok {
            return;
        }
    }
    courier.finish(stats);
}

/// Core 0's part of the frame: renders core 0's bands into `buffer` (at
/// least [`BAND_PIXELS`]) and sends every band to `target`, core 1's from
/// `peer`, in image order, with the image's top-left pixel at `top_left`
/// (the image must lie inside the target). Returns the rays of both cores.
///
/// Each band goes out as one `fill_contiguous` of its rectangle, colours
/// converted by [`FromRgb8`] with [`DITHER`] at their image position: what
/// `Renderer::draw_bands` sends for a band that lies inside the target.
pub fn core0_bands<S: raypack::Scalar, const W: usize, D>(
    renderer: &Renderer<'_, S>,
    target: &mut D,
    top_left: Point,
    buffer: &mut [Rgb8],
    peer: &mut impl Peer,
) -> Result<RayStats, Failure>
where
    D: DrawTarget,
    D::Color: FromRgb8,
{
    let image = Rectangle::new(top_left, Size::new(IMAGE_WIDTH, IMAGE_HEIGHT));
    if target.bounding_box().intersection(&image) != image {
        return Err(Failure::Target);
    }
    if buffer.len() < BAND_PIXELS {
        return Err(Failure::Buffer(BufferTooSmall { needed: BAND_PIXELS, provided: buffer.len() }));
    }
    let mut stats = RayStats::default();
    for index in 0..BANDS {
        if band_owner(index) == 0 {
            render_band::<S, W, _>(renderer, index, buffer, &mut stats, |rect, px| send(target, top_left, rect, px))
                .map_err(|e| match e {
                    BandFailure::Render(f) | BandFailure::Sink(f) => f,
                })?;
        } else {
            peer.receive(|message, px| {
                if message != index {
                    return Err(Failure::Peer);
                }
                let rect = band_rect(index);
                send(target, top_left, rect, px.get(..(rect.w * rect.h) as usize).ok_or(Failure::Peer)?)
            })?;
        }
    }
    Ok(add_stats(stats, peer.finish()?))
}

/// Sends the pixels of image rectangle `rect` to `target` at `top_left +
/// rect`'s corner: one `fill_contiguous`, row-major.
fn send<D>(target: &mut D, top_left: Point, rect: Rect, pixels: &[Rgb8]) -> Result<(), Failure>
where
    D: DrawTarget,
    D::Color: FromRgb8,
{
    let area = Rectangle::new(top_left + Point::new(rect.x as i32, rect.y as i32), Size::new(rect.w, rect.h));
    let colors = pixels
        .iter()
        .zip(RectPositions::new(rect))
        .map(|(p, (x, y))| <D::Color as FromRgb8>::from_rgb8(*p, x, y, DITHER));
    target.fill_contiguous(&area, colors).map_err(|_| Failure::Target)
}

/// The sum of two cores' ray counts (saturating, like the counters).
pub fn add_stats(a: RayStats, b: RayStats) -> RayStats {
    RayStats {
        primary: a.primary.saturating_add(b.primary),
        shadow: a.shadow.saturating_add(b.shadow),
        reflected: a.reflected.saturating_add(b.reflected),
        refracted: a.refracted.saturating_add(b.refracted),
        primary_packets: a.primary_packets.saturating_add(b.primary_packets),
        shadow_packets: a.shadow_packets.saturating_add(b.shadow_packets),
        reflected_packets: a.reflected_packets.saturating_add(b.reflected_packets),
        refracted_packets: a.refracted_packets.saturating_add(b.refracted_packets),
    }
}

/// Each core's share of a two-core frame, measured on one core: summed
/// band by band as the bands arrive, in order (a band may come in several
/// pieces), so no per-band table takes RAM (the Cortex-M0 test image has a
/// few hundred bytes to spare).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Shares {
    /// Ticks of the scene build and renderer set-up (core 0, before core 1
    /// starts).
    pub build: u64,
    /// Ticks of each core's finished bands.
    cores: [u64; CORES as usize],
    /// Over the finished band pairs `(2k, 2k + 1)`: the slower band's ticks.
    pairs: u64,
    /// The band being timed: its index and its ticks so far.
    open: Option<(u32, u64)>,
    /// The ticks of band `2k` while band `2k + 1` is still to come.
    first_of_pair: Option<u64>,
    /// Pixels rendered for each core.
    pub pixels: [u32; CORES as usize],
}

impl Shares {
    /// No band yet, the build's ticks `build`.
    pub fn new(build: u64) -> Self {
        Shares { build, ..Shares::default() }
    }
    /// Charges `ticks` to band `index` (the band of the previous call, or
    /// the next one: a new index closes the band before it).
    pub fn add(&mut self, index: u32, ticks: u64) {
        match self.open {
            Some((i, t)) if i == index => self.open = Some((i, t.saturating_add(ticks))),
            _ => {
                self.close();
                self.open = Some((index, ticks));
            }
        }
    }
    /// Books the open band to its core and its pair.
    fn close(&mut self) {
        let Some((index, ticks)) = self.open.take() else { return };
        if let Some(c) = self.cores.get_mut(band_owner(index) as usize) {
            *c = c.saturating_add(ticks);
        }
        if index % 2 == 0 {
            // A pair whose second band never came costs its first.
            if let Some(first) = self.first_of_pair.replace(ticks) {
                self.pairs = self.pairs.saturating_add(first);
            }
        } else {
            let first = self.first_of_pair.take().unwrap_or(0);
            self.pairs = self.pairs.saturating_add(first.max(ticks));
        }
    }
    /// The shares with every band booked.
    fn closed(&self) -> Self {
        let mut s = *self;
        s.close();
        if let Some(first) = s.first_of_pair.take() {
            s.pairs = s.pairs.saturating_add(first);
        }
        s
    }
    /// The share of core `core`: the build (which both cores wait for) and
    /// its bands.
    pub fn core(&self, core: u32) -> u64 {
        self.build.saturating_add(self.closed().cores.get(core as usize).copied().unwrap_or(0))
    }
    /// The larger share: a lower bound of the two-core frame.
    pub fn larger(&self) -> u64 {
        (0..CORES).map(|c| self.core(c)).max().unwrap_or(0)
    }
    /// The frame when the cores go band pair by band pair (core 1 renders
    /// band `2k + 1` while core 0 renders band `2k`, and waits for core 0 to
    /// take it, as [`core0_bands`] and [`core1_bands`] do): the build plus,
    /// per pair, the slower band.
    pub fn lockstep(&self) -> u64 {
        self.build.saturating_add(self.closed().pairs)
    }
}

/// A [`ChecksumPanel`] that also times the render of every band it is sent:
/// the ticks of `clock` from the end of the previous `fill_contiguous` (or
/// from `start`) to the next, charged to the band of the rows it carries.
/// Band buffers must hold whole bands or divide them (the `microbit`'s one
/// row does).
pub struct TimedPanel<'c, C> {
    panel: ChecksumPanel,
    clock: &'c mut C,
    mark: u64,
    shares: Shares,
}

impl<'c, C: Clock> TimedPanel<'c, C> {
    /// A panel that has been sent nothing, timing from `start` (a reading of
    /// `clock`), with the build's ticks `build`.
    pub fn new(clock: &'c mut C, start: u64, build: u64) -> Self {
        TimedPanel { panel: ChecksumPanel::new(), clock, mark: start, shares: Shares::new(build) }
    }
}

impl<C> OriginDimensions for TimedPanel<'_, C> {
    fn size(&self) -> Size {
        self.panel.size()
    }
}

impl<C: Clock> DrawTarget for TimedPanel<'_, C> {
    type Color = Probe;
    type Error = Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Probe>>>(&mut self, pixels: I) -> Result<(), Infallible> {
        self.panel.draw_iter(pixels)
    }

    fn fill_contiguous<I: IntoIterator<Item = Probe>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Infallible> {
        let now = self.clock.now();
        let index = (area.top_left.y.max(0) as u32) / BAND_ROWS;
        self.shares.add(index, now.saturating_sub(self.mark));
        if let Some(p) = self.shares.pixels.get_mut(band_owner(index) as usize) {
            *p = p.saturating_add(area.size.width.saturating_mul(area.size.height));
        }
        let r = self.panel.fill_contiguous(area, colors);
        self.mark = self.clock.now();
        r
    }
}

/// [`crate::run`] with each core's share of the frame: renders the demo
/// frame once (the same `draw_bands` loop into a checksum panel), timing
/// the build and every band ([`TimedPanel`]), prints the report and
/// `SCALAR.instructions=N` as `run` does, then `SCALAR.core0.instructions`,
/// `SCALAR.core1.instructions` (each core's bands and the build),
/// `SCALAR.per-core.instructions` (the larger) and
/// `SCALAR.lockstep.instructions` ([`Shares::lockstep`]); returns whether
/// the render ran and every pixel was timed.
///
/// Out of line: a firmware rendering both scalars (the Cortex-M0 test
/// image) then holds one scalar's frame state at a time, not both (about
/// 5 KB each, of the chip's 16 KiB).
#[inline(never)]
pub fn run_shares<S: SlotScalar, const W: usize>(
    c: &mut impl Console,
    clock: &mut impl Clock,
    scalar: &str,
    slot: &mut SceneSlot,
    band: &mut [Rgb8],
) -> bool {
    let rate = clock.rate();
    let start = clock.now();
    let renderer = demo_renderer::<S>(slot);
    let built = clock.now();
    let mut panel = TimedPanel::new(clock, built, built.saturating_sub(start));
    let mut stats = RayStats::default();
    let r = renderer
        .and_then(|r| r.draw_bands::<W, _>(&mut panel, Point::zero(), band, DITHER, &mut stats).map_err(draw_failure));
    let end = panel.clock.now();
    if let Err(e) = r {
        report_failure(c, scalar, &e);
        return false;
    }
    report_render(c, scalar, W, &panel.panel.checksums(stats));
    let s = panel.shares;
    let lines = [
        ("instructions", end.saturating_sub(start)),
        ("core0.instructions", s.core(0)),
        ("core1.instructions", s.core(1)),
        ("per-core.instructions", s.larger()),
        ("lockstep.instructions", s.lockstep()),
    ];
    for (key, ticks) in lines {
        c.write_str(scalar);
        c.write_str(".");
        c.write_str(key);
        c.write_str("=");
        c.write_u64(rate.instructions(ticks));
        c.write_str("\n");
    }
    s.pixels == [IMAGE_WIDTH * IMAGE_HEIGHT / CORES; CORES as usize]
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::draw::ChecksumPanel;
    use crate::tests::recorded;
    use crate::timing::TickRate;
    use raypack::Fixed32;
    use std::sync::mpsc::{channel, Receiver, Sender};
    use std::sync::{Arc, Mutex};

    #[test]
    fn the_bands_cover_the_image_once_alternating_between_the_cores() {
        let mut rows = vec![0u32; IMAGE_HEIGHT as usize];
        for i in 0..BANDS {
            let r = band_rect(i);
            assert_eq!((r.x, r.w), (0, IMAGE_WIDTH));
            for y in r.y..r.y + r.h {
                rows[y as usize] += 1;
            }
        }
        assert!(rows.iter().all(|&n| n == 1));
        assert_eq!(band_rect(BANDS).h, 0);
        let per_core: Vec<u32> =
            (0..CORES).map(|c| (0..BANDS).filter(|&i| band_owner(i) == c).count() as u32).collect();
        assert_eq!(per_core, vec![BANDS / 2, BANDS / 2]);
    }

    /// Core 1 on a host thread: its buffer behind a mutex, the FIFO as two
    /// channels.
    pub(crate) struct ThreadCourier {
        buffer: Arc<Mutex<Vec<Rgb8>>>,
        to_core0: Sender<u32>,
        acks: Receiver<()>,
        stats: Sender<RayStats>,
    }
    impl Courier for ThreadCourier {
        fn with_buffer<R>(&mut self, f: impl FnOnce(&mut [Rgb8]) -> R) -> R {
            f(&mut self.buffer.lock().unwrap())
        }
        fn hand_over(&mut self, message: u32) {
            self.to_core0.send(message).unwrap();
            self.acks.recv().unwrap();
        }
        fn finish(&mut self, stats: RayStats) {
            self.stats.send(stats).unwrap();
        }
    }
    pub(crate) struct ThreadPeer {
        buffer: Arc<Mutex<Vec<Rgb8>>>,
        from_core1: Receiver<u32>,
        acks: Sender<()>,
        stats: Receiver<RayStats>,
        received: Vec<u32>,
    }
    impl Peer for ThreadPeer {
        fn receive<R>(&mut self, f: impl FnOnce(u32, &[Rgb8]) -> R) -> R {
            let message = self.from_core1.recv().unwrap();
            self.received.push(message);
            let r = f(message, &self.buffer.lock().unwrap());
            self.acks.send(()).unwrap();
            r
        }
        fn finish(&mut self) -> Result<RayStats, Failure> {
            Ok(self.stats.recv().unwrap())
        }
    }

    /// The two ends of a link between host threads, core 1's buffer of
    /// `pixels` pixels.
    pub(crate) fn thread_link(pixels: usize) -> (ThreadPeer, ThreadCourier) {
        let buffer = Arc::new(Mutex::new(vec![[0u8; 3]; pixels]));
        let (to_core0, from_core1) = channel();
        let (ack_tx, ack_rx) = channel();
        let (stats_tx, stats_rx) = channel();
        let peer = ThreadPeer { buffer: buffer.clone(), from_core1, acks: ack_tx, stats: stats_rx, received: vec![] };
        (peer, ThreadCourier { buffer, to_core0, acks: ack_rx, stats: stats_tx })
    }

    /// Runs the two-core frame of scalar `S` on two host threads into
    /// `target`; returns the rays and core 1's hand-overs.
    pub(crate) fn two_threads<S: SlotScalar + Send + Sync, D>(
        target: &mut D,
        top_left: Point,
    ) -> (Result<RayStats, Failure>, Vec<u32>)
    where
        D: DrawTarget,
        D::Color: FromRgb8,
    {
        let mut slot = Box::new(SceneSlot::new());
        let renderer = demo_renderer::<S>(&mut slot).unwrap();
        let (mut peer, mut courier) = thread_link(BAND_PIXELS);
        let mut band0 = vec![[0u8; 3]; BAND_PIXELS];
        let r = std::thread::scope(|s| {
            s.spawn(|| core1_bands::<S, 1>(&renderer, &mut courier));
            core0_bands::<S, 1, D>(&renderer, target, top_left, &mut band0, &mut peer)
        });
        (r, peer.received)
    }

    #[test]
    fn two_cores_send_the_recorded_image() {
        let mut panel = ChecksumPanel::new();
        let (rays, handed) = two_threads::<Fixed32, _>(&mut panel, Point::zero());
        let c = panel.checksums(rays.unwrap());
        assert_eq!(c.rgb888, recorded("fixed32", "rgb888"));
        assert_eq!(c.rgb565, recorded("fixed32", "rgb565-bayer4"));
        assert_eq!(c.rays.total(), recorded("fixed32", "rays") as u64);
        assert_eq!(c.pixels, IMAGE_WIDTH * IMAGE_HEIGHT);
        assert_eq!(handed, (0..BANDS).filter(|&i| band_owner(i) == 1).collect::<Vec<_>>());
    }

    #[test]
    fn an_image_outside_the_target_or_a_short_buffer_is_refused() {
        let mut panel = ChecksumPanel::new();
        let mut slot = Box::new(SceneSlot::new());
        let renderer = demo_renderer::<f32>(&mut slot).unwrap();
        struct Nobody;
        impl Peer for Nobody {
            fn receive<R>(&mut self, _: impl FnOnce(u32, &[Rgb8]) -> R) -> R {
                panic!("core 1 asked for")
            }
            fn finish(&mut self) -> Result<RayStats, Failure> {
                panic!("core 1 asked for")
            }
        }
        let mut band = vec![[0u8; 3]; BAND_PIXELS];
        let r = core0_bands::<f32, 1, _>(&renderer, &mut panel, Point::new(1, 0), &mut band, &mut Nobody);
        assert_eq!(r, Err(Failure::Target));
        let mut short = vec![[0u8; 3]; BAND_PIXELS - 1];
        let r = core0_bands::<f32, 1, _>(&renderer, &mut panel, Point::zero(), &mut short, &mut Nobody);
        assert!(matches!(r, Err(Failure::Buffer(_))));
    }

    /// A failed render on core 1 reaches core 0 as a failure, not a hang.
    #[test]
    fn a_failure_on_core1_is_reported_by_core0() {
        let mut slot = Box::new(SceneSlot::new());
        let renderer = demo_renderer::<f32>(&mut slot).unwrap();
        // Core 1's buffer is one pixel short of a band.
        let (mut peer, mut courier) = thread_link(BAND_PIXELS - 1);
        let mut panel = ChecksumPanel::new();
        let mut band0 = vec![[0u8; 3]; BAND_PIXELS];
        let r = std::thread::scope(|s| {
            s.spawn(|| core1_bands::<f32, 1>(&renderer, &mut courier));
            core0_bands::<f32, 1, _>(&renderer, &mut panel, Point::zero(), &mut band0, &mut peer)
        });
        assert_eq!(r, Err(Failure::Peer));
        assert_eq!(peer.received, vec![FAILED]);
    }

    /// A clock that counts its readings.
    struct Readings(u64);
    impl Clock for Readings {
        fn now(&mut self) -> u64 {
            self.0 += 1;
            self.0
        }
        fn rate(&self) -> TickRate {
            TickRate::from_hz(1_000_000_000)
        }
    }

    /// Collects the report.
    struct Text(String);
    impl Console for Text {
        fn write_str(&mut self, s: &str) {
            self.0.push_str(s);
        }
    }

    #[test]
    fn the_shares_come_from_the_recorded_frame() {
        let mut slot = Box::new(SceneSlot::new());
        let mut row = vec![[0u8; 3]; IMAGE_WIDTH as usize];
        let mut out = Text(String::new());
        // The clock is read twice around the build and twice per row (one
        // tick each way), once at the end.
        assert!(run_shares::<Fixed32, 1>(&mut out, &mut Readings(0), "fixed32", &mut slot, &mut row));
        let lines: Vec<&str> = out.0.lines().collect();
        let rows = IMAGE_HEIGHT as u64;
        let frame = 2 + 2 * rows;
        let core = 1 + rows / 2;
        for want in [
            format!("fixed32.rgb888={:#010x}", recorded("fixed32", "rgb888")),
            format!("fixed32.rgb565-bayer4={:#010x}", recorded("fixed32", "rgb565-bayer4")),
            format!("fixed32.instructions={frame}"),
            format!("fixed32.core0.instructions={core}"),
            format!("fixed32.core1.instructions={core}"),
            format!("fixed32.per-core.instructions={core}"),
            format!("fixed32.lockstep.instructions={}", 1 + BAND_ROWS as u64 * BANDS as u64 / 2),
        ] {
            assert!(lines.contains(&want.as_str()), "{want} not in {lines:?}");
        }
    }

    #[test]
    fn the_shares_add_up() {
        let shares = |ticks: &dyn Fn(u32) -> u64, pieces: u64| {
            let mut s = Shares::new(5);
            for i in 0..BANDS {
                for _ in 0..pieces {
                    s.add(i, ticks(i) / pieces);
                }
            }
            s
        };
        let even: u64 = (0..BANDS as u64).filter(|i| i % 2 == 0).map(|i| 10 + i).sum();
        let odd: u64 = (0..BANDS as u64).filter(|i| i % 2 == 1).map(|i| 10 + i).sum();
        let s = shares(&|i| 10 + i as u64, 1);
        assert_eq!((s.core(0), s.core(1), s.larger()), (5 + even, 5 + odd, 5 + odd));
        assert_eq!(s.lockstep(), 5 + odd);
        // Every fourth band heavy: all on core 0, each pair costs its
        // heavier band; the same with each band in two pieces.
        for pieces in [1, 2] {
            let s = shares(&|i| if i % 4 == 0 { 18 } else { 2 }, pieces);
            let quarter = BANDS as u64 / 4;
            assert_eq!((s.core(0), s.core(1)), (5 + 18 * quarter + 2 * quarter, 5 + 4 * quarter));
            assert_eq!(s.lockstep(), 5 + 18 * quarter + 2 * quarter);
        }
        // Querying does not book the open band twice.
        let mut s = Shares::new(0);
        s.add(0, 7);
        assert_eq!((s.core(0), s.lockstep()), (7, 7));
        s.add(0, 1);
        s.add(1, 9);
        assert_eq!((s.core(0), s.core(1), s.lockstep()), (8, 9, 9));
    }
}
