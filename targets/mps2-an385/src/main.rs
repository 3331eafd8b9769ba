//! raypack on a Cortex-M3 (QEMU `mps2-an385`) in the Raspberry Pi Pico's
//! image layout: Armv6-M code (`thumbv6m-none-eabi`, the Pico's build
//! profile), the renderer's code and constants stored in flash and copied to
//! RAM first thing in `main` (`ram_code.x`, common's `ram_code`), then the
//! demo scene at 160×128 in Q8.24 fixed point, one ray at a time, one row
//! per band, reported over semihosting, with each band timed as the Pico
//! splits the frame between its two cores (`SCALAR.per-core.instructions`
//! and the others of common's `dual`, as on `microbit`). No QEMU machine models the RP2040; this
//! board runs its layout and its copy where they can be checked: the
//! checksum equals the host's only if the code ran from RAM as copied.
//!
//! The Cortex-M3 runs Armv6-M code unchanged (Armv7-M's Thumb instruction
//! set contains Armv6-M's), so the instructions per frame are those of
//! the same code on a Cortex-M0 or M0+.
#![no_std]
#![no_main]

use core::ptr::{addr_of, addr_of_mut};
use cortex_m_rt::entry;
use raypack::render::Rgb8;
use raypack_firmware_common::dual::run_shares;
use raypack_firmware_common::semihosting::{console, exit};
use raypack_firmware_common::timing::systick::SysTick;
use raypack_firmware_common::{self as fw, ram_code, stack, Console, Fixed32, SceneSlot};

/// Packet width: one ray at a time, as on the Pico.
const WIDTH: usize = 1;
/// Rows per band (the Pico's: one row per band).
const BAND_ROWS: usize = 1;
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
    /// Start of `.data`, the first static in RAM after the code.
    static __sdata: u32;
}

#[entry]
fn main() -> ! {
    // Before anything else, from this crate's code in flash: RAM must not
    // hold the section yet (else the loader put it there, and the copy
    // would go untested), then the copy.
    // SAFETY: nothing has run from or written that RAM yet.
    let loaded_in_place = unsafe { ram_code::in_place() };
    // SAFETY: first thing in `main`; nothing has called code of `raypack`
    // or of the common crate yet (the reset handler and `main` are in flash).
    unsafe { ram_code::copy() };

    let top = addr_of!(_stack_start) as usize;
    let bottom = (addr_of!(_stack_end) as usize).max(top.saturating_sub(STACK_WINDOW));
    // SAFETY: `[bottom, sp)` is unused stack: above the statics, below us.
    unsafe { stack::paint(bottom as *mut u32) };

    let mut con = console();
    fw::report_start(
        &mut con,
        &fw::Board { name: "mps2-an385", cpu: "cortex-m3 running the Pico's Armv6-M image layout (renderer in RAM)" },
    );
    let (run, load, len) = ram_code::section();
    con.write_str("ram-code=");
    con.write_u32(len as u32);
    con.write_str(" bytes run at ");
    con.write_hex32(run as u32);
    con.write_str(", stored at ");
    con.write_hex32(load as u32);
    // The code that prints this line runs from RAM: the copy worked if
    // it is printed at all, and the checksum below says it ran right.
    con.write_str(if loaded_in_place { " (ALREADY IN RAM BEFORE THE COPY)\n" } else { ", copied by main\n" });
    let layout_ok = !loaded_in_place && len > 0 && run >= 0x2000_0000 && load < 0x0040_0000;

    // SAFETY: nothing else uses SysTick; the SysTick handler
    // (`arm_handlers!`) calls `systick::on_wrap`.
    let mut clock = unsafe { SysTick::start(CPU_HZ) };
    let clock_ok = fw::check_clock(&mut con, &mut clock, "systick");

    // SAFETY: the only references to these statics, taken once.
    let (slot, band) = unsafe { (&mut *addr_of_mut!(SCENE), &mut *addr_of_mut!(BAND)) };
    let ok = run_shares::<Fixed32, WIDTH>(&mut con, &mut clock, "fixed32", slot, band);

    // SAFETY: `[bottom, top)` is the painted stack window.
    let used = unsafe { stack::high_water(bottom as *const u32, top as *const u32) };
    let static_ram = (addr_of!(_stack_end) as usize).saturating_sub(addr_of!(__sdata) as usize);
    fw::report_footprint(
        &mut con,
        &fw::Footprint { stack_used: used, stack_watched: top.saturating_sub(bottom), static_ram },
    );
    let ok = ok && clock_ok && layout_ok;
    con.write_str(if ok { "result=ok\n" } else { "result=FAILED\n" });
    exit(ok)
}

fw::arm_handlers!();
