//! The packet and instruction-set policy of the host: which packet width
//! is fastest for an instruction set, and which width a scalar really runs.

use crate::host::dispatch::Isa;
use crate::num::scalar::Scalar;

/// The fastest packet width for `f32` with instruction set `isa` (as
/// [`Isa::effective`]): 16 with AVX2 or AVX-512, 8 with the baseline
/// (SSE2), where 16 lanes are four registers per value. Measured on
/// balls-2, gears-2 and the sphere grids, Whitted and primary rays, in
/// docs/performance.md. The command line's default; the bytes are the
/// same at every width.
pub fn best_packet(isa: Isa) -> usize {
    match isa.effective() {
        Isa::Avx2 | Isa::Avx512 => 16,
        Isa::Baseline => 8,
    }
}

/// The packet width [`render_tiles`](super::render_tiles) really traces `S` with when asked for
/// `packet` rays: `packet` for a [`Scalar::PACKED`] type (`f32`), 1 for
/// the integer fixed-point scalars. Their lanes do not map onto SIMD
/// instructions (each multiply is a 64-bit product), so wider packets only
/// add work (docs/performance.md measures it), and compiling them would
/// more than triple the dispatched machine code a release build compiles.
/// The bytes are the same at every width, so this changes speed only; the
/// core still traces fixed point at any width for callers of [`Renderer::render_rect`](crate::render::Renderer::render_rect).
pub fn packet_used<S: Scalar>(packet: usize) -> usize {
    if S::PACKED {
        packet
    } else {
        1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::host::image::{Image, Options, ScalarKind};
    use crate::num::fixed32::Fixed32;

    #[test]
    fn fixed_point_runs_one_ray_per_packet_and_f32_the_width_asked() {
        assert_eq!(packet_used::<Fixed32>(16), 1);
        assert_eq!(packet_used::<Fixed32>(1), 1);
        assert_eq!(packet_used::<f32>(16), 16);
        assert_eq!(packet_used::<f32>(4), 4);
        assert_eq!(best_packet(Isa::Baseline), 8);
        let scene = "v\nfrom 0 -5 0\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.1\nresolution 12 10\nl 3 -4 5\nf 1 0 0 0.5 0.5 10 0 1\ns 0 0 0 1\n";
        let base = Options { scalar: ScalarKind::Fixed32, threads: Some(1), ..Options::default() };
        let one = Image::render(scene, &Options { packet: 1, ..base }).unwrap();
        let wide = Image::render(scene, &Options { packet: 16, ..base }).unwrap();
        assert_eq!((one.packet, wide.packet), (1, 1));
        assert_eq!(one.pixels, wide.pixels);
        assert_eq!(one.stats, wide.stats);
        let f = Image::render(scene, &Options { packet: 16, ..Options::default() }).unwrap();
        assert_eq!(f.packet, 16);
    }
}
