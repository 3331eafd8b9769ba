//! What both `microbit` images share: start-up report and clock, the static
//! row buffer, the closing report, and the semihosting console and
//! handlers (common's `semihosting`).
//!
//! Memory: the band is one row (480 bytes); the test image builds each
//! scene in place in one `static` slot of its own (`main.rs`), the
//! `fixed32`-only image renders the scene baked into flash; statics and the stack together must fit in
//! the 16 KiB, and the report says how much of it they took.

use core::ptr::{addr_of, addr_of_mut};
use raypack::render::Rgb8;
use raypack_firmware_common::semihosting::{console, exit, Semihosting};
use raypack_firmware_common::timing::systick::SysTick;
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

    // SAFETY: nothing else uses SysTick; the SysTick handler
    // (`arm_handlers!`) calls `systick::on_wrap`.
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

fw::arm_handlers!();
