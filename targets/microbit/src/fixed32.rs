//! raypack on a Cortex-M0 with 16 KiB of RAM (QEMU `microbit`), the image a
//! user would flash: the demo scene at 160×128 in Q8.24 fixed point only
//! (no soft-float render), one ray at a time, one image row per band,
//! reported over semihosting. `scripts/firmware.sh` builds it with the
//! feature `compact-mul` (the Q8.24 multiply out of line: the image fits
//! 48 KiB of flash).
#![no_std]
#![no_main]

mod board;

use board::WIDTH;
use cortex_m_rt::entry;
use raypack_firmware_common::{self as fw, Fixed32};

#[entry]
fn main() -> ! {
    let mut b = board::start("cortex-m0 (fixed32 only)");
    let ok = fw::run::<Fixed32, WIDTH>(&mut b.con, &mut b.clock, "fixed32", b.slot, b.band);
    board::finish(b.con, ok && b.clock_ok)
}
