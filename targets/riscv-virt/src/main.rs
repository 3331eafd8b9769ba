//! raypack on RV32IMAC (QEMU riscv32 `virt`, `-bios none`): the demo scene
//! at 160×128 in soft-float single precision and then in Q8.24 fixed point,
//! one ray at a time, band by band, reported over semihosting.
#![no_std]
#![no_main]

use core::ptr::{addr_of, addr_of_mut};
use raypack::render::Rgb8;
use raypack_firmware_common::timing::mtime::Mtime;
use raypack_firmware_common::{self as fw, stack, Console, Fixed32, SceneSlot};
use riscv_semihosting::{debug, hio};

/// Packet width: one ray at a time (soft-float lanes gain nothing from
/// packets, and each width is another copy of the render path in flash).
const WIDTH: usize = 1;
/// Rows per band.
const BAND_ROWS: usize = 2;
/// Bytes of stack painted and watched (the stack region is most of 16 MiB).
const STACK_WINDOW: usize = 64 * 1024;

static mut SCENE: SceneSlot = SceneSlot::new();
static mut BAND: [Rgb8; fw::band_pixels(BAND_ROWS)] = [[0; 3]; fw::band_pixels(BAND_ROWS)];

extern "C" {
    /// Top of the stack (riscv-rt): the end of RAM.
    static _stack_start: u32;
    /// Bottom of the stack region (riscv-rt): above the statics and the
    /// (empty) heap.
    static __estack: u32;
    /// Start of `.data`, the first static.
    static __sdata: u32;
}

/// Semihosting standard output.
struct Semihosting(Option<hio::HostStream>);

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
        riscv::asm::wfi();
    }
}

#[riscv_rt::entry]
fn main() -> ! {
    let top = addr_of!(_stack_start) as usize;
    let bottom = (addr_of!(__estack) as usize).max(top.saturating_sub(STACK_WINDOW));
    // SAFETY: `[bottom, sp)` is unused stack: above the statics, below us.
    unsafe { stack::paint(bottom as *mut u32) };

    let mut con = console();
    fw::report_start(&mut con, &fw::Board { name: "riscv-virt", cpu: "rv32imac (soft-float f32)" });

    // The CLINT's `mtime` (10 MHz on `virt`), read-only: no interrupt.
    let mut clock = Mtime;
    let clock_ok = fw::check_clock(&mut con, &mut clock, "mtime");

    // SAFETY: the only references to these statics, taken once.
    let (slot, band) = unsafe { (&mut *addr_of_mut!(SCENE), &mut *addr_of_mut!(BAND)) };
    let ok_f32 = fw::run::<f32, WIDTH>(&mut con, &mut clock, "f32", slot, band);
    // The same scene again in Q8.24 fixed point, in the same memory.
    let ok_fixed = fw::run::<Fixed32, WIDTH>(&mut con, &mut clock, "fixed32", slot, band);
    let ok = ok_f32 && ok_fixed && clock_ok;

    // SAFETY: `[bottom, top)` is the painted stack window.
    let used = unsafe { stack::high_water(bottom as *const u32, top as *const u32) };
    let static_ram = (addr_of!(__estack) as usize).saturating_sub(addr_of!(__sdata) as usize);
    fw::report_footprint(
        &mut con,
        &fw::Footprint { stack_used: used, stack_watched: top.saturating_sub(bottom), static_ram },
    );
    con.write_str(if ok { "result=ok\n" } else { "result=FAILED\n" });
    exit(ok)
}

/// Any exception (illegal instruction, access fault, misaligned access,
/// ...): report `mcause` and `mepc`, exit non-zero.
#[export_name = "ExceptionHandler"]
fn exception_handler(_frame: &riscv_rt::TrapFrame) -> ! {
    let mut con = console();
    con.write_str("result=FAILED exception mcause=");
    con.write_hex32(riscv::register::mcause::read().bits() as u32);
    con.write_str(" mepc=");
    con.write_hex32(riscv::register::mepc::read() as u32);
    con.write_str("\n");
    exit(false)
}

/// Any interrupt (none is enabled): report and exit non-zero.
#[export_name = "DefaultHandler"]
fn default_handler() -> ! {
    let mut con = console();
    con.write_str("result=FAILED unexpected interrupt mcause=");
    con.write_hex32(riscv::register::mcause::read().bits() as u32);
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
