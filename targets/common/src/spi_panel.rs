//! A 4-wire SPI link to a MIPI DCS panel for `mipidsi` (feature `panel`),
//! written so that no panic is reachable: [`PanelSpi`] implements
//! [`mipidsi::interface::Interface`] like mipidsi's own `SpiInterface`, but
//! batches pixels in a buffer it owns (a fixed-size array) with checked
//! indexing only. (`SpiInterface` asserts on its borrowed buffer's length and
//! slices it unchecked, which keeps panics reachable after LTO and fails the
//! `panic-never` link.)
//!
//! Commands are sent with DC low, their parameters and pixel data with DC
//! high, as on any 4-wire DCS panel; pixels go out in the byte order mipidsi
//! gives them (RGB565 high byte first).

use embedded_hal::digital::OutputPin;
use embedded_hal::spi::SpiDevice;
use mipidsi::interface::{Interface, InterfaceKind, SpiError};

/// Bytes of the default batch buffer: 256 RGB565 pixels per SPI write.
pub const DEFAULT_BATCH: usize = 512;

/// A panel on SPI device `SPI` (chip select handled by the device) with
/// data/command pin `DC`, batching pixel data `B` bytes at a time.
pub struct PanelSpi<SPI, DC, const B: usize = DEFAULT_BATCH> {
    spi: SPI,
    dc: DC,
    buf: [u8; B],
}

impl<SPI: SpiDevice, DC: OutputPin, const B: usize> PanelSpi<SPI, DC, B> {
    /// The link over `spi` and `dc`.
    pub const fn new(spi: SPI, dc: DC) -> Self {
        PanelSpi { spi, dc, buf: [0; B] }
    }

    /// Gives the SPI device and the DC pin back.
    pub fn release(self) -> (SPI, DC) {
        (self.spi, self.dc)
    }

    fn write(&mut self, len: usize) -> Result<(), SpiError<SPI::Error, DC::Error>> {
        let data = self.buf.get(..len).unwrap_or(&[]);
        if data.is_empty() {
            return Ok(());
        }
        self.spi.write(data).map_err(SpiError::Spi)
    }
}

impl<SPI: SpiDevice, DC: OutputPin, const B: usize> Interface for PanelSpi<SPI, DC, B> {
    type Word = u8;
    type Error = SpiError<SPI::Error, DC::Error>;

    const KIND: InterfaceKind = InterfaceKind::Serial4Line;

    fn send_command(&mut self, command: u8, args: &[u8]) -> Result<(), Self::Error> {
        self.dc.set_low().map_err(SpiError::Dc)?;
        self.spi.write(&[command]).map_err(SpiError::Spi)?;
        self.dc.set_high().map_err(SpiError::Dc)?;
        if !args.is_empty() {
            self.spi.write(args).map_err(SpiError::Spi)?;
        }
        Ok(())
    }

    fn send_pixels<const N: usize>(&mut self, pixels: impl IntoIterator<Item = [u8; N]>) -> Result<(), Self::Error> {
        let mut len = 0;
        for pixel in pixels {
            if len + N > B {
                self.write(len)?;
                len = 0;
            }
            match self.buf.get_mut(len..len + N) {
                Some(slot) => {
                    slot.copy_from_slice(&pixel);
                    len += N;
                }
                // A pixel larger than the whole buffer: send it alone.
                None => self.spi.write(&pixel).map_err(SpiError::Spi)?,
            }
        }
        self.write(len)
    }

    fn send_repeated_pixel<const N: usize>(&mut self, pixel: [u8; N], count: u32) -> Result<(), Self::Error> {
        if N == 0 || N > B {
            for _ in 0..count {
                self.spi.write(&pixel).map_err(SpiError::Spi)?;
            }
            return Ok(());
        }
        // Fill the buffer with whole pixels once, then send it as often as
        // needed.
        let per_batch = B / N;
        for chunk in self.buf.chunks_exact_mut(N) {
            chunk.copy_from_slice(&pixel);
        }
        let mut left = count as usize;
        while left > 0 {
            let n = left.min(per_batch);
            self.write(n * N)?;
            left -= n;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::draw::render_demo_into;
    use crate::dual::tests::thread_link;
    use crate::dual::{core1_bands, BAND_PIXELS, BAND_ROWS};
    use crate::panel::{show_frame, show_frame_dual, IMAGE_TOP_LEFT, PANEL_HEIGHT, PANEL_WIDTH};
    use crate::tests::{recorded, Fnv};
    use crate::timing::{Clock, TickRate};
    use crate::{SceneSlot, IMAGE_HEIGHT, IMAGE_WIDTH};
    use core::convert::Infallible;
    use embedded_graphics::geometry::OriginDimensions;
    use mipidsi::models::ST7789;
    use mipidsi::options::{ColorInversion, Orientation, Rotation};
    use mipidsi::Builder;
    use raypack::Fixed32;
    use std::cell::RefCell;
    use std::rc::Rc;

    /// What went over the wire: DCS commands, each with its data bytes.
    #[derive(Default)]
    struct Wire {
        dc_high: bool,
        commands: Vec<(u8, Vec<u8>)>,
    }

    #[derive(Clone)]
    struct Bus(Rc<RefCell<Wire>>);
    impl embedded_hal::spi::ErrorType for Bus {
        type Error = Infallible;
    }
    impl SpiDevice for Bus {
        fn transaction(&mut self, ops: &mut [embedded_hal::spi::Operation<'_, u8>]) -> Result<(), Infallible> {
            let mut w = self.0.borrow_mut();
            for op in ops {
                if let embedded_hal::spi::Operation::Write(bytes) = op {
                    if w.dc_high {
                        let Some((_, data)) = w.commands.last_mut() else { panic!("data before any command") };
                        data.extend_from_slice(bytes);
                    } else {
                        assert_eq!(bytes.len(), 1, "a command is one byte");
                        w.commands.push((bytes[0], Vec::new()));
                    }
                }
            }
            Ok(())
        }
    }
    struct Dc(Rc<RefCell<Wire>>);
    impl embedded_hal::digital::ErrorType for Dc {
        type Error = Infallible;
    }
    impl OutputPin for Dc {
        fn set_low(&mut self) -> Result<(), Infallible> {
            self.0.borrow_mut().dc_high = false;
            Ok(())
        }
        fn set_high(&mut self) -> Result<(), Infallible> {
            self.0.borrow_mut().dc_high = true;
            Ok(())
        }
    }
    struct NoDelay;
    impl embedded_hal::delay::DelayNs for NoDelay {
        fn delay_ns(&mut self, _: u32) {}
    }

    /// The Pico's panel, as the Pico sets it up, on a recording wire.
    fn panel(
        wire: &Rc<RefCell<Wire>>,
    ) -> impl embedded_graphics::draw_target::DrawTarget<Color = embedded_graphics::pixelcolor::Rgb565> + OriginDimensions
    {
        let link: PanelSpi<_, _, 64> = PanelSpi::new(Bus(wire.clone()), Dc(wire.clone()));
        Builder::new(ST7789, link)
            .display_size(PANEL_HEIGHT as u16, PANEL_WIDTH as u16)
            .display_offset(52, 40)
            .orientation(Orientation::new().rotate(Rotation::Deg90))
            .invert_colors(ColorInversion::Inverted)
            .init(&mut NoDelay)
            .unwrap()
    }

    const RAMWR: u8 = 0x2c;

    #[test]
    fn the_spi_bytes_of_the_image_are_the_checksummed_rgb565_stream() {
        let wire = Rc::new(RefCell::new(Wire::default()));
        let mut display = panel(&wire);
        assert_eq!(display.size(), embedded_graphics::geometry::Size::new(PANEL_WIDTH, PANEL_HEIGHT));
        let init_commands = wire.borrow().commands.len();
        let mut scene = Box::new(SceneSlot::new());
        let mut band = vec![[0u8; 3]; IMAGE_WIDTH as usize * 8];
        render_demo_into::<Fixed32, 1, _>(&mut scene, &mut band, &mut display, IMAGE_TOP_LEFT).unwrap();
        let w = wire.borrow();
        let mut h = Fnv::new();
        let mut bytes = 0;
        let mut bursts = 0;
        for (cmd, data) in &w.commands[init_commands..] {
            if *cmd == RAMWR {
                h.write(data);
                bytes += data.len();
                bursts += 1;
            }
        }
        // Every byte written to the panel's memory, in order, high byte
        // first: the image the QEMU boards checksum.
        assert_eq!(h.finish(), recorded("fixed32", "rgb565-bayer4"));
        assert_eq!(bytes as u32, 2 * IMAGE_WIDTH * IMAGE_HEIGHT);
        assert_eq!(bursts, IMAGE_HEIGHT / 8);
    }

    #[test]
    fn a_whole_frame_goes_over_the_wire_without_error() {
        struct Counter(u64);
        impl Clock for Counter {
            fn now(&mut self) -> u64 {
                self.0 += 7;
                self.0
            }
            fn rate(&self) -> TickRate {
                TickRate::from_hz(1_000_000)
            }
        }
        let wire = Rc::new(RefCell::new(Wire::default()));
        let mut display = panel(&wire);
        let mut scene = Box::new(SceneSlot::new());
        let mut band = vec![[0u8; 3]; IMAGE_WIDTH as usize * 8];
        let frame =
            show_frame::<Fixed32, 1, _>(&mut display, &mut Counter(0), "fixed32", &mut scene, &mut band).unwrap();
        assert_eq!(frame.micros, 7);
        // The clear: the whole panel in repeated-pixel batches.
        let w = wire.borrow();
        let clear = w.commands.iter().find(|(c, _)| *c == RAMWR).unwrap();
        assert_eq!(clear.1.len() as u32, 2 * PANEL_WIDTH * PANEL_HEIGHT);
    }

    /// The Pico's two-core frame (`show_frame_dual`, core 1 on a second
    /// host thread) puts the very bytes on the wire that the one-core frame
    /// does: every command and every data byte after the panel's set-up,
    /// the clear, the image's address windows and pixels, and the label.
    #[test]
    fn two_cores_send_the_panel_the_same_bytes_as_one() {
        struct Counter(u64);
        impl Clock for Counter {
            fn now(&mut self) -> u64 {
                self.0 += 7;
                self.0
            }
            fn rate(&self) -> TickRate {
                TickRate::from_hz(1_000_000)
            }
        }
        let frame_bytes = |two_cores: bool| {
            let wire = Rc::new(RefCell::new(Wire::default()));
            let mut display = panel(&wire);
            let init_commands = wire.borrow().commands.len();
            let mut scene = Box::new(SceneSlot::new());
            let mut band = vec![[0u8; 3]; BAND_PIXELS];
            let frame = if two_cores {
                let (peer, mut courier) = thread_link(BAND_PIXELS);
                std::thread::scope(|s| {
                    show_frame_dual::<Fixed32, 1, _, _>(
                        &mut display,
                        &mut Counter(0),
                        "fixed32",
                        &mut scene,
                        &mut band,
                        |r| {
                            s.spawn(move || core1_bands::<Fixed32, 1>(&r, &mut courier));
                            Ok(peer)
                        },
                    )
                })
            } else {
                show_frame::<Fixed32, 1, _>(&mut display, &mut Counter(0), "fixed32", &mut scene, &mut band)
            };
            assert_eq!(frame.unwrap().rays.total(), recorded("fixed32", "rays") as u64);
            let sent = wire.borrow().commands[init_commands..].to_vec();
            sent
        };
        let (one, two) = (frame_bytes(false), frame_bytes(true));
        let image: Vec<u8> = two
            .iter()
            .filter(|(c, _)| *c == RAMWR)
            .skip(1)
            .take((IMAGE_HEIGHT / BAND_ROWS) as usize)
            .flat_map(|(_, d)| d.clone())
            .collect();
        let mut h = Fnv::new();
        h.write(&image);
        assert_eq!(h.finish(), recorded("fixed32", "rgb565-bayer4"));
        assert!(one == two, "the two-core frame sent other bytes ({} and {} commands)", one.len(), two.len());
    }

    #[test]
    fn batches_split_at_the_buffer_and_odd_sizes_work() {
        let wire = Rc::new(RefCell::new(Wire::default()));
        let mut link: PanelSpi<_, _, 5> = PanelSpi::new(Bus(wire.clone()), Dc(wire.clone()));
        link.send_command(RAMWR, &[]).unwrap();
        link.send_pixels([[1u8, 2], [3, 4], [5, 6]]).unwrap();
        link.send_repeated_pixel([9u8, 8], 3).unwrap();
        link.send_pixels([[1u8, 2, 3, 4, 5, 6]]).unwrap();
        link.send_repeated_pixel([7u8; 6], 2).unwrap();
        let w = wire.borrow();
        assert_eq!(
            w.commands,
            vec![(
                RAMWR,
                vec![1, 2, 3, 4, 5, 6, 9, 8, 9, 8, 9, 8, 1, 2, 3, 4, 5, 6, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7, 7]
            )]
        );
    }
}
