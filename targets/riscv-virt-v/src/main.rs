//! raypack on RV32IMAFC with vectors (QEMU riscv32 `virt` with
//! `-cpu rv32,v=true,vlen=128`, `-bios none`; compiled for Zve32f with a
//! 128-bit minimum vector length): the demo scene at 160×128 in hardware
//! single precision with ray packets of 1, 4 and 8 lanes, band by band,
//! reported over semihosting. LLVM's vectorisers turn the core's lane loops
//! into RVV code (`vfmul.vv`, `vmflt.vv`, `vmerge.vvm`...).
#![no_std]
#![no_main]

use core::ptr::{addr_of, addr_of_mut};
use raypack::render::Rgb8;
use raypack_firmware_common::timing::mtime::Mtime;
use raypack_firmware_common::{self as fw, stack, Console, SceneSlot};
use riscv_semihosting::{debug, hio};

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

// Before RAM is initialised (riscv-rt's `pre-init`): turn the vector unit
// on (mstatus.VS, bits 10:9, to Initial), or the first vector instruction
// traps as illegal.
core::arch::global_asm!(
    ".section .init.pre_init, \"ax\"",
    ".global __pre_init",
    "__pre_init:",
    "li t0, 0x200",
    "csrs mstatus, t0",
    "ret",
);

#[riscv_rt::entry]
fn main() -> ! {
    let top = addr_of!(_stack_start) as usize;
    let bottom = (addr_of!(__estack) as usize).max(top.saturating_sub(STACK_WINDOW));
    // SAFETY: `[bottom, sp)` is unused stack: above the statics, below us.
    unsafe { stack::paint(bottom as *mut u32) };

    let mut con = console();
    fw::report_start(
        &mut con,
        &fw::Board { name: "riscv-virt-v", cpu: "rv32imafc + zve32f, vlen 128 (hardware f32, vectors)" },
    );

    // The CLINT's `mtime` (10 MHz on `virt`), read-only: no interrupt.
    let mut clock = Mtime;
    let clock_ok = fw::check_clock(&mut con, &mut clock, "mtime");

    // SAFETY: the only references to these statics, taken once.
    let (slot, band) = unsafe { (&mut *addr_of_mut!(SCENE), &mut *addr_of_mut!(BAND)) };
    // The same frame at each packet width.
    let ok_w1 = fw::run::<f32, 1>(&mut con, &mut clock, "f32-w1", slot, band);
    let ok_w4 = fw::run::<f32, 4>(&mut con, &mut clock, "f32-w4", slot, band);
    let ok_w8 = fw::run::<f32, 8>(&mut con, &mut clock, "f32-w8", slot, band);
    let ok = ok_w1 && ok_w4 && ok_w8 && clock_ok;

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
