//! raypack on a Cortex-M0 with 16 KiB of RAM (QEMU `microbit`), the image a
//! user would flash: the demo scene at 160×128 in Q8.24 fixed point only
//! (no soft-float render), one ray at a time, one image row per band,
//! reported over semihosting. The scene is baked on the host into flash
//! (`raypack_firmware_common::baked_demo`, written by `cargo run --example
//! bake_scene`): the image holds no scene-building code and no scene in RAM.
//! `scripts/firmware.sh` builds it with the feature `compact-mul` (the
//! Q8.24 multiply out of line), for the smallest image.
#![no_std]
#![no_main]

mod board;

use board::WIDTH;
use cortex_m_rt::entry;
use raypack_firmware_common as fw;

#[entry]
fn main() -> ! {
    let mut b = board::start("cortex-m0 (fixed32 only, baked scene)");
    let ok = fw::run_baked::<WIDTH>(&mut b.con, &mut b.clock, b.band);
    board::finish(b.con, ok && b.clock_ok)
}
