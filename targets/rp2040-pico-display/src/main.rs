//! raypack on a Raspberry Pi Pico (RP2040: two Cortex-M0+ cores, no FPU)
//! driving a Pimoroni Pico Display Pack (1.14" 240×135 IPS, ST7789, SPI):
//! the demo scene rendered band by band straight into the panel, no
//! framebuffer, on both cores (`raypack_firmware_common::dual`: bands of 4
//! rows alternate between the cores, each core renders into its own band
//! buffer, core 0 sends every band to the panel in image order), then the
//! frame time, from the RP2040's microsecond timer, beside the image.
//!
//! Everything here is pin and peripheral set-up and the link between the
//! cores (the SIO FIFOs); the frame itself is common code
//! (`panel::show_frame_dual`), host-tested down to the SPI bytes: the same
//! bytes as one core's frame, whose image is `targets/checksums.txt`'s.
//! The on-board LED (GP25) lights if the frame could not be shown.
//!
//! Not run by `scripts/firmware.sh` (QEMU has no RP2040 machine): it is
//! built and proved panic-free there, and flashed by hand (docs/firmware.md).
#![no_std]
#![no_main]

use core::ptr::{addr_of, addr_of_mut};
use core::sync::atomic::{compiler_fence, Ordering};
use embedded_hal::digital::OutputPin;
use embedded_hal_bus::spi::ExclusiveDevice;
use mipidsi::models::ST7789;
use mipidsi::options::{ColorInversion, Orientation, Rotation};
use mipidsi::Builder;
use raypack::render::{Renderer, Rgb8};
use raypack::trace::RayStats;
use raypack_firmware_common::dual::{self, Courier, Peer, BAND_PIXELS, DONE};
use raypack_firmware_common::spi_panel::PanelSpi;
use raypack_firmware_common::timing::{Clock, TickRate};
use raypack_firmware_common::{self as fw, panel, stack, Failure, ScalarName};
use rp2040_hal::clocks::{ClocksManager, InitError};
use rp2040_hal::fugit::RateExtU32;
use rp2040_hal::gpio::{bank0, FunctionSioOutput, FunctionSpi, Pin, PullDown, PullNone};
use rp2040_hal::multicore::{Multicore, Stack};
use rp2040_hal::pac;
use rp2040_hal::pll::{common_configs::PLL_USB_48MHZ, setup_pll_blocking, PLLConfig};
use rp2040_hal::sio::SioFifo;
use rp2040_hal::xosc::setup_xosc_blocking;
use rp2040_hal::{Clock as _, Sio, Spi, Timer, Watchdog};

/// The scalar the panel renders with: Q8.24 fixed point (no FPU on the
/// M0+; integer arithmetic only, so the image is the one the QEMU boards
/// check bit for bit).
type PanelScalar = raypack::Fixed32;
/// Packet width: one ray at a time, as on the `microbit` QEMU board (the
/// same Armv6-M code, so its instruction counts apply).
const WIDTH: usize = 1;

/// The Pico's crystal.
const XOSC_HZ: u32 = 12_000_000;
/// System clock: 133 MHz, the RP2040's rated maximum (12 MHz × 133 /
/// (6 × 2) from a 1596 MHz VCO, as the Pico SDK sets it).
const PLL_SYS_133MHZ: PLLConfig =
    PLLConfig { vco_freq: rp2040_hal::fugit::HertzU32::MHz(1596), refdiv: 1, post_div1: 6, post_div2: 2 };
/// SPI clock to the panel (the ST7789's write cycle allows 62.5 MHz; the
/// RP2040 divides clk_peri = 133 MHz by an even number: 33.25 MHz here).
const SPI_HZ: u32 = 40_000_000;

/// Pimoroni Pico Display Pack wiring (GPIO numbers, SPI0). The typed pins
/// below must match; `main` checks.
mod pack {
    /// Panel data/command select.
    pub const DC: u8 = 16;
    /// Panel chip select (SPI0 CSn, driven as a GPIO).
    pub const CS: u8 = 17;
    /// SPI0 SCK.
    pub const SCK: u8 = 18;
    /// SPI0 TX (MOSI).
    pub const MOSI: u8 = 19;
    /// Backlight (high: on).
    pub const BACKLIGHT: u8 = 20;
    /// The Pico's own LED: on if the frame failed.
    pub const LED: u8 = 25;
}
type DcPin = Pin<bank0::Gpio16, FunctionSioOutput, PullDown>;
type CsPin = Pin<bank0::Gpio17, FunctionSioOutput, PullDown>;
type SckPin = Pin<bank0::Gpio18, FunctionSpi, PullNone>;
type MosiPin = Pin<bank0::Gpio19, FunctionSpi, PullNone>;

/// The second-stage boot loader for the Pico's W25Q16JV flash.
#[link_section = ".boot2"]
#[used]
pub static BOOT2_FIRMWARE: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

static mut SCENE: fw::SceneSlot = fw::SceneSlot::new();
/// Core 0's band buffer: 1 row of 160 pixels (480 bytes), one SPI
/// address window and pixel burst per band.
static mut BAND0: [Rgb8; BAND_PIXELS] = [[0; 3]; BAND_PIXELS];
/// Core 1's band buffer: written by core 1 between hand-overs, read by
/// core 0 during one (the SIO FIFO messages order the two).
static mut BAND1: [Rgb8; BAND_PIXELS] = [[0; 3]; BAND_PIXELS];
/// Core 1's ray counts: written by core 1 before it sends `DONE`, read by
/// core 0 after.
static mut CORE1_RAYS: RayStats = RayStats {
    primary: 0,
    shadow: 0,
    reflected: 0,
    refracted: 0,
    primary_packets: 0,
    shadow_packets: 0,
    reflected_packets: 0,
    refracted_packets: 0,
};
/// Core 1's stack: 8 KiB (the render needs about 3; painted and measured
/// on the QEMU boards).
static CORE1_STACK: Stack<2048> = Stack::new();

/// What core 0 sends back when it is done with core 1's buffer.
const TAKEN: u32 = 0;

/// Core 1's end of the link: its buffer `BAND1` and the SIO FIFO. Each
/// core sees its own ends of the two FIFOs (one per direction) at the same
/// SIO addresses.
struct FifoCourier<'f>(&'f mut SioFifo);

impl Courier for FifoCourier<'_> {
    fn with_buffer<R>(&mut self, f: impl FnOnce(&mut [Rgb8]) -> R) -> R {
        // SAFETY: between hand-overs core 0 does not touch BAND1, and this
        // reference ends before the next hand-over.
        f(unsafe { &mut *addr_of_mut!(BAND1) })
    }
    fn hand_over(&mut self, message: u32) {
        // The band's pixels are written before the message goes out (the
        // RP2040 has no data cache and writes in order; the fence keeps the
        // compiler from moving them), and read by core 0 before it answers.
        compiler_fence(Ordering::SeqCst);
        self.0.write_blocking(message);
        let _taken = self.0.read_blocking();
        compiler_fence(Ordering::SeqCst);
    }
    fn finish(&mut self, stats: RayStats) {
        // SAFETY: core 0 reads CORE1_RAYS only after DONE, sent below.
        unsafe { addr_of_mut!(CORE1_RAYS).write_volatile(stats) };
        compiler_fence(Ordering::SeqCst);
        self.0.write_blocking(DONE);
    }
}

/// Core 0's end of the link.
struct FifoPeer<'f>(&'f mut SioFifo);

impl Peer for FifoPeer<'_> {
    fn receive<R>(&mut self, f: impl FnOnce(u32, &[Rgb8]) -> R) -> R {
        let message = self.0.read_blocking();
        compiler_fence(Ordering::SeqCst);
        // SAFETY: core 1 has handed BAND1 over and waits for TAKEN before
        // it writes it again; this reference ends before TAKEN goes out.
        let r = f(message, unsafe { &*addr_of!(BAND1) });
        compiler_fence(Ordering::SeqCst);
        self.0.write_blocking(TAKEN);
        r
    }
    fn finish(&mut self) -> Result<RayStats, Failure> {
        if self.0.read_blocking() != DONE {
            return Err(Failure::Peer);
        }
        compiler_fence(Ordering::SeqCst);
        // SAFETY: core 1 wrote CORE1_RAYS before DONE and no longer touches it.
        Ok(unsafe { addr_of!(CORE1_RAYS).read_volatile() })
    }
}

/// Core 1's program: its bands of the frame, then back to sleep (in
/// rp2040-hal's spawn wrapper).
fn core1_main(renderer: Renderer<'static, PanelScalar>) {
    // SAFETY: core 1 uses only its own ends of the SIO FIFOs (per-core
    // registers); core 0's `Sio` keeps off them while core 1 runs, except
    // through `FifoPeer`, which is the other end.
    let pac = unsafe { pac::Peripherals::steal() };
    let mut sio = Sio::new(pac.SIO);
    dual::core1_bands::<PanelScalar, WIDTH>(&renderer, &mut FifoCourier(&mut sio.fifo));
}

/// The RP2040 timer: 64 bits of microseconds.
struct Micros(Timer);

impl Clock for Micros {
    fn now(&mut self) -> u64 {
        self.0.get_counter().ticks()
    }
    fn rate(&self) -> TickRate {
        TickRate::from_hz(1_000_000)
    }
}

/// Crystal, 133 MHz system PLL, 48 MHz USB PLL, and the watchdog's
/// microsecond tick for the timer: rp2040-hal's `init_clocks_and_plls`
/// with the system PLL at 133 MHz instead of 125 MHz.
fn init_clocks(
    xosc: pac::XOSC,
    clocks: pac::CLOCKS,
    pll_sys: pac::PLL_SYS,
    pll_usb: pac::PLL_USB,
    resets: &mut pac::RESETS,
    watchdog: &mut Watchdog,
) -> Result<ClocksManager, InitError> {
    let xosc = setup_xosc_blocking(xosc, XOSC_HZ.Hz()).map_err(InitError::XoscErr)?;
    watchdog.enable_tick_generation((XOSC_HZ / 1_000_000) as u8);
    let mut clocks = ClocksManager::new(clocks);
    let pll_sys = setup_pll_blocking(pll_sys, xosc.operating_frequency(), PLL_SYS_133MHZ, &mut clocks, resets)
        .map_err(InitError::PllError)?;
    let pll_usb = setup_pll_blocking(pll_usb, xosc.operating_frequency(), PLL_USB_48MHZ, &mut clocks, resets)
        .map_err(InitError::PllError)?;
    clocks.init_default(&xosc, &pll_sys, &pll_usb).map_err(InitError::ClockError)?;
    Ok(clocks)
}

/// Sets up the clocks, the panel and the timer, shows one frame; `false`
/// if any step failed.
fn run(mut pac: pac::Peripherals) -> bool {
    let mut watchdog = Watchdog::new(pac.WATCHDOG);
    let Ok(clocks) = init_clocks(pac.XOSC, pac.CLOCKS, pac.PLL_SYS, pac.PLL_USB, &mut pac.RESETS, &mut watchdog) else {
        return false;
    };
    let mut sio = Sio::new(pac.SIO);
    let pins = rp2040_hal::gpio::Pins::new(pac.IO_BANK0, pac.PADS_BANK0, sio.gpio_bank0, &mut pac.RESETS);
    let timer = Timer::new(pac.TIMER, &mut pac.RESETS, &clocks);

    let dc: DcPin = pins.gpio16.reconfigure();
    let cs: CsPin = pins.gpio17.reconfigure();
    let sck: SckPin = pins.gpio18.reconfigure();
    let mosi: MosiPin = pins.gpio19.reconfigure();
    let mut backlight = pins.gpio20.into_push_pull_output();
    let ids = [dc.id().num, cs.id().num, sck.id().num, mosi.id().num, backlight.id().num];
    if ids != [pack::DC, pack::CS, pack::SCK, pack::MOSI, pack::BACKLIGHT] {
        return false;
    }

    let spi = Spi::<_, _, _, 8>::new(pac.SPI0, (mosi, sck)).init(
        &mut pac.RESETS,
        clocks.peripheral_clock.freq(),
        SPI_HZ.Hz(),
        embedded_hal::spi::MODE_0,
    );
    // (Setting a GPIO cannot fail on the RP2040: the error is `Infallible`.)
    let spi = match ExclusiveDevice::new_no_delay(spi, cs) {
        Ok(spi) => spi,
        Err(never) => match never {},
    };
    // Pixels go out 512 bytes (256 pixels) per SPI write.
    let interface: PanelSpi<_, _> = PanelSpi::new(spi, dc);
    let mut delay = timer;
    // The pack's 135×240 window sits at (52, 40) in the ST7789's 240×320
    // memory; rotated 90° for landscape. The panel is an IPS one, which
    // wants inverted colours.
    let Ok(mut display) = Builder::new(ST7789, interface)
        .display_size(135, 240)
        .display_offset(52, 40)
        .orientation(Orientation::new().rotate(Rotation::Deg90))
        .invert_colors(ColorInversion::Inverted)
        .init(&mut delay)
    else {
        return false;
    };
    if backlight.set_high().is_err() {
        return false;
    }

    // SAFETY: the only references to these statics, taken once.
    let (scene, band) = unsafe { (&mut *addr_of_mut!(SCENE), &mut *addr_of_mut!(BAND0)) };
    let mut clock = Micros(timer);
    let (psm, ppb, fifo) = (&mut pac.PSM, &mut pac.PPB, &mut sio.fifo);
    // Once the scene is built: core 1 starts on its bands with a copy of the
    // renderer (which only reads the scene, in a static, from then on).
    let start_core1 = move |renderer: Renderer<'static, PanelScalar>| {
        let fifo = fifo; // (moved in: the link outlives this call)
        {
            let mut cores = Multicore::new(&mut *psm, &mut *ppb, &mut *fifo);
            let core1 = cores.cores().get_mut(1).ok_or(Failure::Peer)?;
            let stack = CORE1_STACK.take().ok_or(Failure::Peer)?;
            core1.spawn(stack, move || core1_main(renderer)).map_err(|_| Failure::Peer)?;
        }
        Ok(FifoPeer(fifo))
    };
    if panel::show_frame_dual::<PanelScalar, WIDTH, _, _>(
        &mut display,
        &mut clock,
        PanelScalar::NAME,
        scene,
        band,
        start_core1,
    )
    .is_err()
    {
        return false;
    }
    // The stack's high-water mark so far (painted at boot), under the label.
    // SAFETY: `[bottom, top)` is the stack region painted in `main`.
    let used = unsafe { stack::high_water(stack_bottom() as *const u32, addr_of!(_stack_start)) };
    let mut digits = [0u8; panel::LINE_BYTES];
    panel::draw_label_line(&mut display, 6, "stack bytes", false).is_ok()
        && panel::draw_label_line(&mut display, 7, panel::format_count(used as u64, &mut digits), true).is_ok()
}

extern "C" {
    /// Top of the stack (cortex-m-rt): the end of RAM.
    static _stack_start: u32;
    /// Lowest address the stack may use: the end of the statics.
    static _stack_end: u32;
}

/// The lowest stack address painted and watched: 64 KiB below the top
/// (the stack may use all of RAM above the statics; the frame needs a few).
fn stack_bottom() -> usize {
    let top = addr_of!(_stack_start) as usize;
    (addr_of!(_stack_end) as usize).max(top.saturating_sub(STACK_WINDOW))
}

/// Bytes of stack painted and watched.
const STACK_WINDOW: usize = 64 * 1024;

#[rp2040_hal::entry]
fn main() -> ! {
    // The renderer's code and constants to SRAM (`ram_code.x`): from flash,
    // through the 16 KiB XIP cache, its fetches missed about 8 M times a
    // frame (docs/firmware.md).
    // SAFETY: the first thing `main` does; nothing has called the
    // renderer's code yet (the reset handler and `main` live in flash).
    unsafe { fw::ram_code::copy() };
    // SAFETY: `[stack_bottom(), sp)` is unused stack: above the statics,
    // below this frame.
    unsafe { stack::paint(stack_bottom() as *mut u32) };
    // `take` is `Some` on the first call, and this is the only call.
    if let Some(pac) = pac::Peripherals::take() {
        let ok = run(pac);
        if !ok {
            // SAFETY: `run` is over and dropped its peripherals; only the
            // LED pin's SIO and pad bits are touched (GP25: output, high).
            unsafe { led_on() };
        }
    }
    loop {
        cortex_m::asm::wfi();
    }
}

/// Lights the Pico's LED (GP25) with raw register writes, whatever state
/// the HAL left: function SIO, output enable, output high.
///
/// # Safety
/// Nothing else may be using GPIO 25.
unsafe fn led_on() {
    let pin = pack::LED as usize;
    // SAFETY: documented RP2040 registers (IO_BANK0 GPIO25_CTRL, SIO
    // GPIO_OE_SET and GPIO_OUT_SET, RESETS), caller's contract on GP25.
    unsafe {
        // Take IO_BANK0 and PADS_BANK0 out of reset (atomic clear alias).
        core::ptr::write_volatile((0x4000_C000 + 0x3000) as *mut u32, (1 << 5) | (1 << 8));
        while core::ptr::read_volatile((0x4000_C000 + 0x8) as *const u32) & ((1 << 5) | (1 << 8))
            != ((1 << 5) | (1 << 8))
        {}
        core::ptr::write_volatile((0x4001_4000 + 8 * pin + 4) as *mut u32, 5); // FUNCSEL = SIO
        core::ptr::write_volatile(0xD000_0024 as *mut u32, 1 << pin); // GPIO_OE_SET
        core::ptr::write_volatile(0xD000_0014 as *mut u32, 1 << pin); // GPIO_OUT_SET
    }
}

#[cfg(not(feature = "panic-never"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    // SAFETY: nothing runs after a panic; GP25 is the LED.
    unsafe { led_on() };
    loop {
        cortex_m::asm::wfi();
    }
}
