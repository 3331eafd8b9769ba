//! Code run from RAM: the renderer's code and constants, which `ram_code.x`
//! (beside this crate's `Cargo.toml`) links to run at the start of RAM and
//! stores in flash, copied there by [`copy`] first thing in `main`.
//!
//! Why: on the RP2040 the code runs from QSPI flash through a 16 KiB XIP
//! cache, and the frame's 38.9 KB of code missed it about 8.2 M times a
//! frame, some 112 cycles each (docs/firmware.md, "XIP cache misses on the
//! RP2040"). The Pico runs this layout; so does the QEMU board
//! `mps2-an385`, the same Armv6-M code, where the copy is tested.
//!
//! Everything here is `#[inline(always)]`, and must stay so: it runs before
//! the copy, from the caller's code in flash, and any function of this
//! crate that is not inlined is linked into the section (a call to it
//! before the copy would jump into uninitialised RAM).

use core::ptr::{addr_of, addr_of_mut};

extern "C" {
    /// Start of the section where it runs (RAM).
    static mut __sram_code: u32;
    /// End of the section where it runs.
    static __eram_code: u32;
    /// Where the linker stored it (flash).
    static __siram_code: u32;
}

/// Where the section runs, where it is stored, and its length in bytes.
#[inline(always)]
pub fn section() -> (usize, usize, usize) {
    let run = addr_of!(__sram_code) as usize;
    let end = addr_of!(__eram_code) as usize;
    (run, addr_of!(__siram_code) as usize, end.saturating_sub(run))
}

/// Whether RAM already holds the section's bytes before [`copy`]: true only
/// if a loader wrote the section at its run address rather than at its
/// load address (a debugger may; QEMU's ELF loader and the Pico's UF2 and
/// SWD loaders write the load address, so there RAM holds something else).
/// A firmware that tests the copy checks that this is false first.
///
/// # Safety
/// Before [`copy`], or after it: nothing may be writing the section's RAM.
#[inline(always)]
pub unsafe fn in_place() -> bool {
    let (run, load, len) = section();
    let (run, load) = (run as *const u32, load as *const u32);
    let mut i = 0;
    while i < len / 4 {
        // SAFETY: both ranges are `len` bytes, word-aligned (`ram_code.x`);
        // the caller's contract on the RAM range.
        if unsafe { run.add(i).read_volatile() != load.add(i).read_volatile() } {
            return false;
        }
        i += 1;
    }
    true
}

/// Copies the section from flash to RAM, where it is linked to run and be
/// read. A word at a time with volatile accesses, so that no call (a
/// `memcpy`), no function of this crate or of `raypack` and no constant is
/// used before the copy is done; then the barriers make the new code
/// visible to the instruction fetches that follow.
///
/// # Safety
/// Once, first thing in `main`, before anything calls code of `raypack` or
/// of this crate or reads a constant; nothing else may use that RAM.
#[inline(always)]
pub unsafe fn copy() {
    // SAFETY: the linker's symbols bound one word-aligned region of flash
    // and one of RAM of the same length (`ram_code.x`); the caller's
    // contract: nothing else uses that RAM, nothing in it runs yet.
    unsafe {
        let mut dst = addr_of_mut!(__sram_code);
        let end = addr_of!(__eram_code);
        let mut src = addr_of!(__siram_code);
        while (dst as *const u32) < end {
            dst.write_volatile(src.read_volatile());
            dst = dst.add(1);
            src = src.add(1);
        }
    }
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
}
