//! Run-time choice of the instruction set for the render path (`std` only).
//!
//! A default Rust build for x86-64 may use only SSE2, so an 8-wide packet is
//! two 4-wide halves. This module compiles the same generic code again
//! inside functions marked `#[target_feature(enable = "avx2")]` (and
//! `"avx512f,avx512vl,avx512bw,avx512dq"`) and picks a copy at run time from
//! what the CPU has (`is_x86_feature_detected!`, cached by `std`).
//! Everything on the render path, from [`Renderer::render_rect`] down to the
//! primitive kernels, is `#[inline(always)]`, so LLVM inlines it into the
//! entry point and compiles it there with `ymm` (or `zmm`) registers.
//! In builds with debug assertions (the test profile) those attributes are
//! plain `#[inline]` hints instead: inlining the whole tracer everywhere
//! made the tests take most of CI's time to compile. The bytes are the same
//! either way; `scripts/check-asm.sh` checks the release machine code.
//!
//! # Determinism
//! The AVX2 copy enables only `avx2` (which implies `avx`), not `fma`. The
//! AVX-512 copy needs `avx512f`, which LLVM ties to `fma`; that is harmless
//! because Rust never allows the compiler to contract a multiply and an add
//! (no fast-math flags), so no fused multiply-add is ever selected
//! (`scripts/check-asm.sh` checks the binary for `vfmadd`). Packed IEEE add,
//! subtract, multiply, divide and square root are correctly rounded, exactly
//! like their SSE2 and scalar forms, so the output bytes do not depend on the
//! instruction set; `tests/dispatch.rs` checks that on the demo scene and on
//! random scenes.
//!
//! # Using it
//! [`Isa::best`] is the fastest instruction set this CPU supports.
//! [`render_rect`] renders a rectangle with it; [`Isa::run`] runs any
//! [`IsaKernel`] (benchmarks use it to put their inner loops through the
//! same path).
#![allow(unsafe_code)]

use crate::bvh::LeafIsa;
use crate::camera::Rect;
use crate::render::{BufferTooSmall, Renderer, Rgb8};
use crate::scalar::Scalar;
use crate::scene::SceneView;
use crate::trace::RayStats;

/// An instruction set the render path can be compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Isa {
    /// Whatever the build targets (x86-64: SSE2). Always available.
    Baseline,
    /// x86-64 with AVX2 (256-bit packed single precision), without FMA.
    Avx2,
    /// x86-64 with AVX-512 F, VL, BW and DQ: 32 vector registers, mask
    /// registers, 512-bit vectors for 16-wide packets. (In LLVM `avx512f`
    /// implies `fma`; Rust never asks for contraction, so no fused
    /// multiply-add is emitted: `scripts/check-asm.sh` checks the binary.)
    Avx512,
}

impl Isa {
    /// Every instruction set, baseline first.
    pub const ALL: [Isa; 3] = [Isa::Baseline, Isa::Avx2, Isa::Avx512];

    /// Whether this CPU can run code compiled for `self`.
    pub fn is_available(self) -> bool {
        match self {
            Isa::Baseline => true,
            #[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
            Isa::Avx2 => std::is_x86_feature_detected!("avx2"),
            #[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
            Isa::Avx512 => {
                std::is_x86_feature_detected!("avx512f")
                    && std::is_x86_feature_detected!("avx512vl")
                    && std::is_x86_feature_detected!("avx512bw")
                    && std::is_x86_feature_detected!("avx512dq")
            }
            #[cfg(not(any(target_arch = "x86_64", target_arch = "x86")))]
            Isa::Avx2 | Isa::Avx512 => false,
        }
    }

    /// The fastest available instruction set.
    pub fn best() -> Isa {
        if Isa::Avx512.is_available() {
            Isa::Avx512
        } else if Isa::Avx2.is_available() {
            Isa::Avx2
        } else {
            Isa::Baseline
        }
    }

    /// The instruction set [`Isa::run`] really uses for `self`: `self` when
    /// available, otherwise the baseline (the bytes are the same either way,
    /// only the speed differs).
    pub fn effective(self) -> Isa {
        if self.is_available() {
            self
        } else {
            Isa::Baseline
        }
    }

    /// The token for the BVH leaf tests compiled for
    /// [`Isa::effective`]`(self)` (see [`crate::bvh::isa`]).
    pub fn leaf_isa(self) -> LeafIsa {
        match self.effective() {
            Isa::Baseline => LeafIsa::default(),
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `effective` returned Avx2 only because run-time
            // detection found AVX2 on this CPU.
            Isa::Avx2 => unsafe { LeafIsa::avx2() },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `effective` returned Avx512 only because run-time
            // detection found AVX-512 F, VL, BW and DQ on this CPU.
            Isa::Avx512 => unsafe { LeafIsa::avx512() },
            #[cfg(not(target_arch = "x86_64"))]
            Isa::Avx2 | Isa::Avx512 => LeafIsa::default(),
        }
    }

    /// `view` with its BVH traversals calling the leaf tests compiled for
    /// [`Isa::effective`]`(self)`. [`render_rect`] does this itself; an
    /// [`IsaKernel`] that queries a view with a tree should use it, since
    /// the leaf tests are compiled apart from the inlined path.
    pub fn view<'a, S: Scalar>(self, view: SceneView<'a, S>) -> SceneView<'a, S> {
        view.with_leaf_isa(self.leaf_isa())
    }

    /// Short lower-case name: `baseline`, `avx2` or `avx512`.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Baseline => "baseline",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
        }
    }

    /// The instruction set called `name` (as printed by [`Isa::name`]).
    pub fn from_name(name: &str) -> Option<Isa> {
        Isa::ALL.into_iter().find(|i| i.name() == name)
    }

    /// Runs `kernel` compiled for [`Isa::effective`]`(self)`.
    #[inline]
    pub fn run<K: IsaKernel>(self, kernel: K) -> K::Output {
        match self.effective() {
            Isa::Baseline => run_baseline(kernel),
            #[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
            // SAFETY: `effective` returned Avx2 only because
            // `is_x86_feature_detected!("avx2")` said this CPU has AVX2, which
            // is the one feature `run_avx2` is compiled for.
            Isa::Avx2 => unsafe { run_avx2(kernel) },
            #[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
            // SAFETY: `effective` returned Avx512 only because run-time
            // detection found every feature `run_avx512` is compiled for.
            Isa::Avx512 => unsafe { run_avx512(kernel) },
            #[cfg(not(any(target_arch = "x86_64", target_arch = "x86")))]
            Isa::Avx2 | Isa::Avx512 => run_baseline(kernel),
        }
    }
}

impl core::fmt::Display for Isa {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// A piece of work that [`Isa::run`] compiles once per instruction set.
///
/// Implementations should mark [`IsaKernel::run`] `#[inline(always)]` (and
/// call only `#[inline(always)]` code in their hot loops): code that is not
/// inlined into the entry point is compiled once, for the baseline.
pub trait IsaKernel {
    /// What the work returns.
    type Output;
    /// Does the work.
    fn run(self) -> Self::Output;
}

#[inline(never)]
fn run_baseline<K: IsaKernel>(kernel: K) -> K::Output {
    kernel.run()
}

/// # Safety
/// The CPU must support AVX2.
#[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
#[inline(never)]
#[target_feature(enable = "avx2")]
unsafe fn run_avx2<K: IsaKernel>(kernel: K) -> K::Output {
    kernel.run()
}

/// # Safety
/// The CPU must support AVX-512 F, VL, BW and DQ.
#[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
#[inline(never)]
#[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq")]
unsafe fn run_avx512<K: IsaKernel>(kernel: K) -> K::Output {
    kernel.run()
}

/// [`Renderer::render_rect`] as an [`IsaKernel`].
struct RenderRect<'r, 'a, 'o, 's, S, const D: usize, const W: usize> {
    renderer: &'r Renderer<'a, S, D>,
    rect: Rect,
    out: &'o mut [Rgb8],
    stats: &'s mut RayStats,
}

impl<S: Scalar, const D: usize, const W: usize> IsaKernel for RenderRect<'_, '_, '_, '_, S, D, W> {
    type Output = Result<(), BufferTooSmall>;
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn run(self) -> Self::Output {
        self.renderer.render_rect::<W>(self.rect, self.out, self.stats)
    }
}

/// [`Renderer::render_rect`] compiled for `isa` (see [`Isa::run`]): the same
/// bytes as the plain call, faster where the CPU allows.
pub fn render_rect<S: Scalar, const D: usize, const W: usize>(
    isa: Isa,
    renderer: &Renderer<'_, S, D>,
    rect: Rect,
    out: &mut [Rgb8],
    stats: &mut RayStats,
) -> Result<(), BufferTooSmall> {
    // The same renderer, its BVH leaf tests (compiled apart from the
    // inlined path, see `crate::bvh::isa`) in the same instruction set.
    let mut local = *renderer;
    local.tracer = local.tracer.with_leaf_isa(isa.leaf_isa());
    isa.run(RenderRect::<S, D, W> { renderer: &local, rect, out, stats })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_baseline_is_always_there() {
        for isa in Isa::ALL {
            assert_eq!(Isa::from_name(isa.name()), Some(isa));
        }
        assert_eq!(Isa::from_name("sse9"), None);
        assert!(Isa::Baseline.is_available());
        assert!(Isa::best().is_available());
        assert_eq!(Isa::Baseline.effective(), Isa::Baseline);
    }
}
