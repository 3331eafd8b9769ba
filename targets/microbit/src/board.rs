//! What both `microbit` images share: start-up report and clock, the static
//! row buffer, the semihosting console, the closing report,
//! and the fault and panic handlers.
//!
//! Memory: the band is one row (480 bytes); the test image builds each
//! scene in place in one `static` slot of its own (`main.rs`), the
//! `fixed32`-only image renders the scene baked into flash; statics and the stack together must fit in
//! the 16 KiB, and the report says how much of it they took.

use core::ptr::{addr_of, addr_of_mut};
use cortex_m_rt::{exception, ExceptionFrame};
use cortex_m_semihosting::{debug, hio};
use raypack::render::Rgb8;
use raypack_firmware_common::timing::systick::{self, SysTick};
use raypack_firmware_common::{self as fw, stack, Console};

/// Packet width: the scalar path (no SIMD, and the smallest stack).
pub const WIDTH: usize = 1;
/// Rows per band.
const BAND_ROWS: usize = 1;

/// The processor clock QEMU gives this machine (its `cpuclk`), which
/// SysTick counts with CLKSOURCE = processor clock.
const CPU_HZ: u32 = 16_000_000;

static mut BAND: [Rgb8; fw::band_pixels(BAND_ROWS)] = [[0; 3]; fw::band_pixels(BAND_ROWS)];

extern "C" {
    /// Top of the stack (cortex-m-rt): the end of RAM.
    static _stack_start: u32;
    /// Lowest address the stack may use: the end of the statics.
    static _stack_end: u32;
    /// Start of `.data`, the first static in RAM.
    static __sdata: u32;
}

/// Semihosting standard output.
pub struct Semihosting(Option<hio::HostStream>);

impl Console for Semihosting {
    fn write_str(&mut self, s: &str) {
        if let Some(out) = self.0.as_mut() {
            let _ = out.write_all(s.as_bytes());
        }
    }
}

fn console() -> Semihosting {
    Semihosting(hio::hstdout().ok())
}

fn exit(ok: bool) -> ! {
    debug::exit(if ok { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    loop {
        cortex_m::asm::bkpt();
    }
}

/// The board after start-up: its console, its instruction clock and the
/// row buffer.
pub struct Board {
    /// Semihosting standard output.
    pub con: Semihosting,
    /// SysTick, counting instructions under `-icount shift=0`.
    pub clock: SysTick,
    /// Whether the clock passed its calibration.
    pub clock_ok: bool,
    /// The band buffer: one image row (a `static`).
    pub band: &'static mut [Rgb8],
}

/// Paints the stack, prints the first line as `cpu`, starts and checks the
/// clock. Call once, first thing.
pub fn start(cpu: &'static str) -> Board {
    let bottom = addr_of!(_stack_end) as usize;
    // SAFETY: `[bottom, sp)` is unused stack: above the statics, below us.
    unsafe { stack::paint(bottom as *mut u32) };

    let mut con = console();
    fw::report_start(&mut con, &fw::Board { name: "microbit", cpu });

    // SAFETY: nothing else uses SysTick; the SysTick handler below calls
    // `systick::on_wrap`.
    let mut clock = unsafe { SysTick::start(CPU_HZ) };
    let clock_ok = fw::check_clock(&mut con, &mut clock, "systick");

    // SAFETY: the only reference to this static, taken once (`start` is
    // called once).
    let band = unsafe { &mut *addr_of_mut!(BAND) };
    Board { con, clock, clock_ok, band }
}

/// Prints the memory figures and the result line, and exits QEMU.
pub fn finish(mut con: Semihosting, ok: bool) -> ! {
    let top = addr_of!(_stack_start) as usize;
    let bottom = addr_of!(_stack_end) as usize;
    // SAFETY: `[bottom, top)` is the painted stack region.
    let used = unsafe { stack::high_water(bottom as *const u32, top as *const u32) };
    let static_ram = bottom.saturating_sub(addr_of!(__sdata) as usize);
    fw::report_footprint(
        &mut con,
        &fw::Footprint { stack_used: used, stack_watched: top.saturating_sub(bottom), static_ram },
    );
    con.write_str(if ok { "result=ok\n" } else { "result=FAILED\n" });
    exit(ok)
}

/// Counts SysTick wraps for the frame-time clock.
#[exception]
fn SysTick() {
    systick::on_wrap();
}

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    let mut con = console();
    con.write_str("result=FAILED HardFault at pc=");
    con.write_hex32(frame.pc());
    con.write_str("\n");
    exit(false)
}

#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    let mut con = console();
    con.write_str("result=FAILED unexpected exception ");
    con.write_u32(irqn as u16 as u32);
    con.write_str("\n");
    exit(false)
}

#[cfg(not(feature = "panic-never"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    let mut con = console();
    con.write_str("result=FAILED panic\n");
    exit(false)
}
