//! raypack on a Cortex-M0 with 16 KiB of RAM (QEMU `microbit`), the test
//! image: the demo scene at 160×128 in soft-float single precision and then
//! in Q8.24 fixed point, one ray at a time (width 1), one image row per
//! band, reported over semihosting. (`raypack-microbit-fixed32` is the
//! image a user would flash: `fixed32` only.)
//!
//! Each frame is also timed band by band as the Raspberry Pi Pico firmware
//! splits it between its two cores (`raypack_firmware_common::dual`):
//! `SCALAR.core0.instructions` and `SCALAR.core1.instructions` are what each
//! core of a two-core part retires for its bands (the scene build
//! included, which both wait for), `SCALAR.per-core.instructions` the
//! larger, `SCALAR.lockstep.instructions` the frame when the cores go band
//! pair by band pair (the Pico's hand-over).
#![no_std]
#![no_main]

mod board;

use board::WIDTH;
use core::ptr::addr_of_mut;
use cortex_m_rt::entry;
use raypack_firmware_common::dual::run_shares;
use raypack_firmware_common::{Fixed32, SceneSlot};

/// Each scene is built in place here (never copied on the stack; the
/// fixed-point scene reuses the f32 scene's bytes).
static mut SCENE: SceneSlot = SceneSlot::new();

#[entry]
fn main() -> ! {
    let b = board::start("cortex-m0 (soft-float f32)");
    // SAFETY: the only reference to this static, taken once.
    let slot = unsafe { &mut *addr_of_mut!(SCENE) };
    let (mut con, mut clock) = (b.con, b.clock);
    let ok_f32 = run_shares::<f32, WIDTH>(&mut con, &mut clock, "f32", slot, b.band);
    // The same scene again in Q8.24 fixed point, in the same memory.
    let ok_fixed = run_shares::<Fixed32, WIDTH>(&mut con, &mut clock, "fixed32", slot, b.band);
    board::finish(con, ok_f32 && ok_fixed && b.clock_ok)
}
