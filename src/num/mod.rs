//! Numbers: the [`Scalar`](scalar::Scalar) trait every algorithm is written
//! against, its implementations (`f32`, the Q8.24 [`Fixed32`](fixed32::Fixed32),
//! the 32.32 [`Fixed`](fixed64::Fixed)), packet lanes and masks, and the
//! deterministic power function. The bottom layer: it uses nothing else of
//! the crate.

pub mod bake;
pub(crate) mod bins;
pub mod fixed32;
pub mod fixed64;
pub mod lanes;
pub mod scalar;
// Used by `f32` where neither `std` nor WebAssembly SIMD gives the square
// root instruction (the firmware), and by its tests on the host.
#[cfg(any(test, not(any(feature = "std", all(target_arch = "wasm32", target_feature = "simd128")))))]
pub(crate) mod sqrtf;
#[cfg(test)]
pub(crate) mod test_rng;
pub mod unit_pow;
pub(crate) mod wide;
