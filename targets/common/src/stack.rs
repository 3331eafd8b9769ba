//! Measuring the stack on the chip: paint it with a pattern at boot, run,
//! then find the lowest word that no longer holds the pattern.
//!
//! The stack grows down from `top`. [`paint`] fills the window
//! `[bottom, current stack pointer − margin)` with [`PAINT`]; after the work,
//! [`high_water`] scans up from `bottom` for the first word that changed.
//! Everything above it counts as used, including what was in use when the
//! paint ran (so the figure errs high by at most the boot frames and the
//! margin, never low). A program that wrote exactly the pattern would be
//! under-counted by those words; a 32-bit pattern makes that unlikely.

use core::ptr;

/// The paint pattern.
pub const PAINT: u32 = 0x5aa5_c33c;

/// Bytes below the painting function's own frame left unpainted (its own
/// spills and the call itself).
pub const MARGIN: usize = 64;

/// Paints the stack from `bottom` up to just below the caller's frame.
///
/// # Safety
/// `bottom` must be a word-aligned address inside this program's stack
/// region, below the current stack pointer, with nothing else (statics,
/// heap) between it and the stack pointer.
#[inline(never)]
pub unsafe fn paint(bottom: *mut u32) {
    let marker = 0u32;
    // An address in this function's own frame: the live stack is above it.
    let here = ptr::addr_of!(marker) as usize;
    let end = here.saturating_sub(MARGIN) & !3;
    let mut p = bottom;
    while (p as usize) < end {
        // SAFETY: `p` is in `[bottom, end)`, unused stack (caller's contract).
        unsafe {
            ptr::write_volatile(p, PAINT);
            p = p.add(1);
        }
    }
    // Keep `marker` on the stack (its address was taken above).
    unsafe { ptr::read_volatile(ptr::addr_of!(marker)) };
}

/// Bytes of stack used since [`paint`]: `top` minus the address of the
/// lowest word in `[bottom, top)` that no longer holds [`PAINT`]. Equals
/// `top − bottom` if even the lowest painted word was overwritten (the
/// stack may then have gone deeper than the window).
///
/// # Safety
/// `[bottom, top)` must be readable memory (the stack region passed to
/// [`paint`] and above).
pub unsafe fn high_water(bottom: *const u32, top: *const u32) -> usize {
    let mut p = bottom;
    while (p as usize) < (top as usize) {
        // SAFETY: inside `[bottom, top)` (caller's contract).
        if unsafe { ptr::read_volatile(p) } != PAINT {
            break;
        }
        p = unsafe { p.add(1) };
    }
    (top as usize).saturating_sub(p as usize)
}
