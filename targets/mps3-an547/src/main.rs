//! raypack on a Cortex-M55 with Helium (QEMU `mps3-an547`: Armv8.1-M, the
//! M-profile Vector Extension with floating point, 128-bit vectors of four
//! `f32` lanes): the demo scene at 160×128 in hardware single precision with
//! ray packets of 1, 4 and 8 lanes, then in Q8.24 fixed point, band by band,
//! each frame's checksums and instruction count reported over semihosting.
//! Also checks that the FPU computes plain IEEE 754: no flush-to-zero, no
//! default-NaN mode, round to nearest (MVE's floating-point lanes follow
//! FPSCR's rounding mode; they flush denormals only when FZ is set).
//!
//! The packet code is the core's generic lane loops (`raypack::lanes`),
//! compiled with `-C target-cpu=cortex-m55` (`targets/.cargo/config.toml`):
//! LLVM's vectorisers turn them into MVE instructions. Which frames are in
//! the image is chosen by cargo features (all by default), so that the size
//! of an image of one width can be measured.
#![no_std]
#![no_main]

use core::ptr::{addr_of, addr_of_mut};
use cortex_m_rt::entry;
use raypack::render::Rgb8;
use raypack_firmware_common::semihosting::{console, exit};
use raypack_firmware_common::timing::systick::SysTick;
#[cfg(feature = "fixed32")]
use raypack_firmware_common::Fixed32;
use raypack_firmware_common::{self as fw, stack, Console, SceneSlot};

/// Rows per band: one row of 4×2 packets (width 8), two of 2×2 (width 4).
const BAND_ROWS: usize = 2;
/// Bytes of stack painted and watched.
const STACK_WINDOW: usize = 64 * 1024;
/// The fixed-point frame's packet width (see docs/firmware.md: Q8.24
/// multiplications need 64-bit products, which MVE forms two lanes at a
/// time, so wider packets do not pay for their flash).
#[cfg(feature = "fixed32")]
const FIXED32_WIDTH: usize = 1;

/// The processor clock QEMU gives this machine (`mps3-an547`'s
/// `sysclk_frq`, the SSE-300's MAINCLK, wired to the CPU's `cpuclk`),
/// which SysTick counts with CLKSOURCE = processor clock.
const CPU_HZ: u32 = 32_000_000;

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

/// Reads MVFR1 (0xE000_EF44): its MVE field (bits 11:8) is 2 when the
/// core has MVE with floating point (Helium for `f32` lanes).
fn mve_level() -> u32 {
    // SAFETY: MVFR1 is an always-readable, read-only System Control Space register.
    let mvfr1 = unsafe { core::ptr::read_volatile(0xE000_EF44 as *const u32) };
    (mvfr1 >> 8) & 0xF
}

#[entry]
fn main() -> ! {
    let top = addr_of!(_stack_start) as usize;
    let bottom = (addr_of!(_stack_end) as usize).max(top.saturating_sub(STACK_WINDOW));
    // SAFETY: `[bottom, sp)` is unused stack: above the statics, below us.
    unsafe { stack::paint(bottom as *mut u32) };

    let mut con = console();
    fw::report_start(&mut con, &fw::Board { name: "mps3-an547", cpu: "cortex-m55 (hardware f32, MVE/Helium)" });

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
    let mve = mve_level();
    con.write_str("mvfr1.mve=");
    con.write_u32(mve);
    let helium = mve == 2;
    con.write_str(if helium { " (MVE with floating point)\n" } else { " NO MVE FLOATING POINT\n" });

    // SAFETY: nothing else uses SysTick; the SysTick handler
    // (`arm_handlers!`) calls `systick::on_wrap`.
    let mut clock = unsafe { SysTick::start(CPU_HZ) };
    let clock_ok = fw::check_clock(&mut con, &mut clock, "systick");

    // SAFETY: the only references to these statics, taken once.
    let (slot, band) = unsafe { (&mut *addr_of_mut!(SCENE), &mut *addr_of_mut!(BAND)) };
    let mut ok = true;
    // The same frame at each packet width: same checksums, fewer
    // instructions where the lanes run in MVE registers.
    #[cfg(feature = "f32-w1")]
    {
        ok &= fw::run::<f32, 1>(&mut con, &mut clock, "f32-w1", slot, band);
    }
    #[cfg(feature = "f32-w4")]
    {
        ok &= fw::run::<f32, 4>(&mut con, &mut clock, "f32-w4", slot, band);
    }
    #[cfg(feature = "f32-w8")]
    {
        ok &= fw::run::<f32, 8>(&mut con, &mut clock, "f32-w8", slot, band);
    }
    // The same scene in Q8.24 fixed point.
    #[cfg(feature = "fixed32")]
    {
        ok &= fw::run::<Fixed32, FIXED32_WIDTH>(&mut con, &mut clock, "fixed32-w1", slot, band);
    }

    // SAFETY: `[bottom, top)` is the painted stack window.
    let used = unsafe { stack::high_water(bottom as *const u32, top as *const u32) };
    let static_ram = (addr_of!(_stack_end) as usize).saturating_sub(addr_of!(__sdata) as usize);
    fw::report_footprint(
        &mut con,
        &fw::Footprint { stack_used: used, stack_watched: top.saturating_sub(bottom), static_ram },
    );
    let ok = ok && ieee && helium && clock_ok;
    con.write_str(if ok { "result=ok\n" } else { "result=FAILED\n" });
    exit(ok)
}

fw::arm_handlers!();
