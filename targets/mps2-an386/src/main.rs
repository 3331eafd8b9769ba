//! raypack on a Cortex-M4F (QEMU `mps2-an386`): the demo scene at 160×128
//! in hardware single precision (its main path), then in Q8.24 fixed point
//! (for comparison), one ray at a time, band by band,
//! reported over semihosting. Also checks that the FPU computes plain IEEE 754: no
//! flush-to-zero, no default-NaN mode, round to nearest.
#![no_std]
#![no_main]

use core::ptr::{addr_of, addr_of_mut};
use cortex_m_rt::entry;
use raypack::render::Rgb8;
use raypack_firmware_common::semihosting::{console, exit};
use raypack_firmware_common::timing::systick::SysTick;
use raypack_firmware_common::{self as fw, stack, Console, Fixed32, SceneSlot};

/// Packet width: one ray at a time (an in-order scalar FPU gains nothing
/// from packets, and each width is another copy of the render path in flash).
const WIDTH: usize = 1;
/// Rows per band.
const BAND_ROWS: usize = 2;
/// Bytes of stack painted and watched (the stack region is most of 4 MiB).
const STACK_WINDOW: usize = 64 * 1024;

/// The processor clock QEMU gives this machine (its `cpuclk`), which
/// SysTick counts with CLKSOURCE = processor clock.
const CPU_HZ: u32 = 25_000_000;

static mut SCENE: SceneSlot = SceneSlot::new();
static mut BAND: [Rgb8; fw::band_pixels(BAND_ROWS)] = [[0; 3]; fw::band_pixels(BAND_ROWS)];

extern "C" {
    /// Top of the stack (cortex-m-rt).
    static _stack_start: u32;
    /// Lowest address the stack may use: the end of the statics.
    static _stack_end: u32;
    /// Start of `.data`, the first static in RAM.
    static __sdata: u32;
}

/// Reads FPSCR (current FP status and control) and FPDSCR (the defaults
/// loaded into FPSCR for new floating-point contexts, 0xE000_EF3C).
fn fp_control() -> (u32, u32) {
    let fpscr = cortex_m::register::fpscr::read().bits();
    // SAFETY: FPDSCR is an always-readable System Control Space register.
    let fpdscr = unsafe { core::ptr::read_volatile(0xE000_EF3C as *const u32) };
    (fpscr, fpdscr)
}

#[entry]
fn main() -> ! {
    let top = addr_of!(_stack_start) as usize;
    let bottom = (addr_of!(_stack_end) as usize).max(top.saturating_sub(STACK_WINDOW));
    // SAFETY: `[bottom, sp)` is unused stack: above the statics, below us.
    unsafe { stack::paint(bottom as *mut u32) };

    let mut con = console();
    fw::report_start(&mut con, &fw::Board { name: "mps2-an386", cpu: "cortex-m4f (hardware f32)" });

    // IEEE mode check: FZ (bit 24) and DN (bit 25) must be clear, RMode
    // (bits 23:22) round-to-nearest, in FPSCR and in FPDSCR.
    let (fpscr, fpdscr) = fp_control();
    const MODE_BITS: u32 = (1 << 24) | (1 << 25) | (3 << 22);
    let ieee = fpscr & MODE_BITS == 0 && fpdscr & MODE_BITS == 0;
    con.write_str("fpscr=");
    con.write_hex32(fpscr);
    con.write_str(" fpdscr=");
    con.write_hex32(fpdscr);
    con.write_str(if ieee { " (flush-to-zero off, default-NaN off, round to nearest)\n" } else { " NOT IEEE MODE\n" });

    // SAFETY: nothing else uses SysTick; the SysTick handler
    // (`arm_handlers!`) calls `systick::on_wrap`.
    let mut clock = unsafe { SysTick::start(CPU_HZ) };
    let clock_ok = fw::check_clock(&mut con, &mut clock, "systick");

    // SAFETY: the only references to these statics, taken once.
    let (slot, band) = unsafe { (&mut *addr_of_mut!(SCENE), &mut *addr_of_mut!(BAND)) };
    let ok_f32 = fw::run::<f32, WIDTH>(&mut con, &mut clock, "f32", slot, band);
    // The same scene in Q8.24 fixed point, one ray at a time.
    let ok_fixed = fw::run::<Fixed32, 1>(&mut con, &mut clock, "fixed32", slot, band);
    let ok = ok_f32 && ok_fixed;

    // SAFETY: `[bottom, top)` is the painted stack window.
    let used = unsafe { stack::high_water(bottom as *const u32, top as *const u32) };
    let static_ram = (addr_of!(_stack_end) as usize).saturating_sub(addr_of!(__sdata) as usize);
    fw::report_footprint(
        &mut con,
        &fw::Footprint { stack_used: used, stack_watched: top.saturating_sub(bottom), static_ram },
    );
    let ok = ok && ieee && clock_ok;
    con.write_str(if ok { "result=ok\n" } else { "result=FAILED\n" });
    exit(ok)
}

fw::arm_handlers!();
