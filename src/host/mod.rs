//! The `std` harness inside the library: run-time instruction-set dispatch
//! (the one module allowed `unsafe`) and the one-call entry point from NFF
//! text to pixels on threads. The top layer.

// Run-time instruction-set dispatch (the one module allowed `unsafe`).
pub mod dispatch;
// From NFF text to pixels in one call, on threads.
pub mod image;
