//! raypack in the browser: the `no_std` core compiled to WebAssembly (with
//! `simd128`: packets of 4 rays in 128-bit vectors), behind a plain
//! `extern "C"` surface over linear memory. No allocator, no imports, no
//! JavaScript glue beyond `web/worker.js`.
//!
//! The calls, in order (integers are `u32`/`i32`, ray counts `f64`):
//! 1. `rp_text_buffer(len)`: where to write `len` bytes of NFF text (0 if
//!    more than the preview holds), then `rp_load(len, scalar)`; or
//!    `rp_load_demo(scalar)`. Scalar 0 is `f32`, 1 `fixed32`.
//! 2. `rp_setup(width, height, packet, aov, output)`: 0 for a side is the
//!    scene's size; packet 1 or 4; AOV 0 colour, 1 depth, 2 normal, 3 id;
//!    output 0 RGB888, 1 RGB565 (Bayer 4×4, high byte first).
//! 3. `rp_render_band(max_rows)` until it returns 0: each call renders the
//!    next band and returns its rows; its pixels are at `rp_rgba()`
//!    (RGBA, `width·rows·4` bytes) and `rp_stream()` (`rp_stream_len()`
//!    bytes in the output format), its first row is `rp_band_y()`.
//! 4. `rp_checksum(0)` / `rp_checksum(1)`: FNV-1a of the RGB888 bytes and of
//!    the RGB565 pixels so far (at the end: `targets/checksums.txt`'s
//!    values); `rp_rays(k)`: primary, shadow, reflected, refracted.
//!
//! Every call that can fail returns a negative number (or 0 from
//! `rp_text_buffer`) and leaves one line at `rp_message()`
//! (`rp_message_len()` bytes of UTF-8): the text the `raypack` command line
//! prints after `raypack: error: FILE: `, with line and column for a
//! malformed scene.
//!
//! The module imports nothing. Nothing panics by design (errors are
//! values); only `rp_load` has a call path to the panic handler at all, and
//! only inside `core`'s float parser (see the panic handler).
// `no_std` on WebAssembly; the host build (for `cargo test`) has std for the
// test harness and its panic handler.
#![cfg_attr(all(not(test), target_arch = "wasm32"), no_std)]
#![deny(missing_docs)]
#![deny(unsafe_op_in_unsafe_fn)]

pub mod preview;

use preview::{aov_from_code, Memory, Output, Preview, ScalarKind, State, MAX_TEXT};

/// The preview's buffers, scenes and trees: zeros, so they take no room in
/// the module (zero-filled linear memory).
static mut MEMORY: Memory = Memory::new();
/// What is loaded and rendering.
static mut STATE: State = State::new();

/// The preview, for the duration of one exported call.
#[allow(unsafe_code)]
fn preview() -> Preview<'static> {
    // SAFETY: wasm32-unknown-unknown without the `atomics` feature runs one
    // thread, and the module imports nothing, so no export runs while
    // another does: each export takes these references once, at its start,
    // and drops them when it returns; none is kept. (Host tests build their
    // own `Preview` and never call the exports.)
    unsafe { Preview { mem: &mut *core::ptr::addr_of_mut!(MEMORY), state: &mut *core::ptr::addr_of_mut!(STATE) } }
}

/// Where to write `len` bytes of NFF text before `rp_load`; 0 (null) if the
/// preview holds less (the message says how much).
#[no_mangle]
pub extern "C" fn rp_text_buffer(len: u32) -> *mut u8 {
    let p = preview();
    if len as usize > MAX_TEXT {
        p.state
            .message
            .set(format_args!("the scene is {len} bytes; the browser preview reads at most {MAX_TEXT} bytes"));
        return core::ptr::null_mut();
    }
    p.mem.text.as_mut_ptr()
}

/// Loads the NFF text written at `rp_text_buffer` with `scalar` (0 `f32`,
/// 1 `fixed32`) and builds its BVH: 0, or -1 (`rp_message`).
#[no_mangle]
pub extern "C" fn rp_load(len: u32, scalar: u32) -> i32 {
    let mut p = preview();
    let Some(scalar) = ScalarKind::from_code(scalar) else {
        p.state.message.set(format_args!("scalar {scalar} is not 0 (f32) or 1 (fixed32)"));
        return -1;
    };
    status(p.load_nff(len as usize, scalar).is_ok())
}

/// Loads the demo scene (the firmware's) with `scalar`: 0, or -1.
#[no_mangle]
pub extern "C" fn rp_load_demo(scalar: u32) -> i32 {
    let mut p = preview();
    let Some(scalar) = ScalarKind::from_code(scalar) else {
        p.state.message.set(format_args!("scalar {scalar} is not 0 (f32) or 1 (fixed32)"));
        return -1;
    };
    status(p.load_demo(scalar).is_ok())
}

/// Sets up a render of the loaded scene (see the crate documentation): 0,
/// or -1.
#[no_mangle]
pub extern "C" fn rp_setup(width: u32, height: u32, packet: u32, aov: u32, output: u32) -> i32 {
    let mut p = preview();
    let (Some(aov), Some(output)) = (aov_from_code(aov), Output::from_code(output)) else {
        p.state
            .message
            .set(format_args!("AOV {aov} or output {output} is not one the preview knows (AOV 0 to 3, output 0 or 1)"));
        return -1;
    };
    status(p.setup(width, height, packet, aov, output).is_ok())
}

/// Renders the next band of at most `max_rows` rows: its rows (0: the image
/// is complete), or -1.
#[no_mangle]
pub extern "C" fn rp_render_band(max_rows: u32) -> i32 {
    match preview().render_band(max_rows) {
        Ok(band) => band.rows as i32,
        Err(_) => -1,
    }
}

/// First row of the band last rendered.
#[no_mangle]
pub extern "C" fn rp_band_y() -> u32 {
    preview().last_band().y
}

/// The last band as RGBA, row-major.
#[no_mangle]
pub extern "C" fn rp_rgba() -> *const u8 {
    preview().mem.rgba.as_ptr()
}

/// The last band in the output format, row-major.
#[no_mangle]
pub extern "C" fn rp_stream() -> *const u8 {
    preview().mem.stream.as_ptr()
}

/// Bytes of the last band's output stream.
#[no_mangle]
pub extern "C" fn rp_stream_len() -> u32 {
    preview().stream_len() as u32
}

/// Width (0), height (1) of the render set up, and the packet width it
/// traces with (2); the loaded scene's primitives (3).
#[no_mangle]
pub extern "C" fn rp_info(what: u32) -> u32 {
    let p = preview();
    let shape = p.render_shape().unwrap_or((0, 0, 0));
    match what {
        0 => shape.0,
        1 => shape.1,
        2 => shape.2 as u32,
        3 => p.primitives() as u32,
        _ => 0,
    }
}

/// Rays traced so far: 0 primary, 1 shadow, 2 reflected, 3 refracted, 4 all.
#[no_mangle]
pub extern "C" fn rp_rays(kind: u32) -> f64 {
    let s = preview().stats();
    let n = match kind {
        0 => s.primary,
        1 => s.shadow,
        2 => s.reflected,
        3 => s.refracted,
        4 => s.total(),
        _ => 0,
    };
    n as f64
}

/// FNV-1a so far: 0 of the RGB888 bytes, 1 of the RGB565 pixels.
#[no_mangle]
pub extern "C" fn rp_checksum(which: u32) -> u32 {
    let (rgb888, rgb565) = preview().checksums();
    if which == 0 {
        rgb888
    } else {
        rgb565
    }
}

/// The message of the last failure (UTF-8).
#[no_mangle]
pub extern "C" fn rp_message() -> *const u8 {
    preview().state.message.as_bytes().as_ptr()
}

/// Bytes of the message of the last failure.
#[no_mangle]
pub extern "C" fn rp_message_len() -> u32 {
    preview().state.message.as_bytes().len() as u32
}

/// 0 for success, -1 for failure.
fn status(ok: bool) -> i32 {
    if ok {
        0
    } else {
        -1
    }
}

/// The panic handler: a trap (`unreachable`), which the worker reports as
/// an internal error. No export but `rp_load` has a call path to it (the
/// demo, set-up, the render path, the getters), and `rp_load` only through
/// bounds checks inside `core`'s float parser (`core::num::dec2flt`, behind
/// `str::parse::<f32>`), which the optimizer keeps and no input is known to
/// reach: web/test/check_module.py checks both on the linked module.
#[cfg(all(not(test), target_arch = "wasm32"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    core::arch::wasm32::unreachable()
}
