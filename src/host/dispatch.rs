//! Run-time choice of the instruction set for the render path (`std` only;
//! the one module of the crate allowed `unsafe`).
//!
//! A default Rust build for x86-64 may use only SSE2, so an 8-wide packet is
//! two 4-wide halves. This module compiles the same generic code again
//! inside functions marked `#[target_feature(enable = "avx2")]` (and
//! `"avx512f,avx512vl,avx512bw,avx512dq"`) and picks a copy at run time from
//! what the CPU has (`is_x86_feature_detected!`, cached by `std`).
//!
//! Code is compiled for an instruction set only where it is inlined into
//! such a function, so the render path is cut into a few large pieces, each
//! one function per instruction set:
//! - the render loop (camera rays, the tracer's stack, shading, pixels):
//!   [`Renderer::render_rect`] and everything below it is `#[inline(always)]`
//!   on x86 and compiled inside the entry point;
//! - the tracer (a packet's whole trace: shading, shadows, secondary rays),
//!   and the two queries, closest hit and shadow transmittance (the
//!   traversal and the primitive kernels): the renderer's accelerator is
//!   wrapped in a type of this module whose `run` and queries call functions
//!   compiled for the same instruction set, with the tracer's and the
//!   accelerator's code inlined into them (`Accelerator::run` is how the
//!   tracer hands its work over). However many places of the render loop
//!   trace (anti-aliasing has several), the tracer is compiled once.
//!
//! Cutting the path at the queries keeps each function a size LLVM compiles
//! quickly (its time grows faster than linearly with function size), and
//! compiles the primitive kernels once per query instead of once per call
//! site. In builds with debug assertions (the test profile) the
//! `inline(always)` attributes are off: inlining the whole tracer everywhere
//! made the tests take most of CI's time to compile. The bytes are the same
//! either way; `scripts/check-asm.sh` checks the release machine code.
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

use crate::geom::camera::Rect;
use crate::geom::ray::RayPacket;
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;
use crate::query::{Accelerator, Hit, PacketJob, SceneMismatch};
use crate::render::{BufferTooSmall, Renderer, Rgb8};
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

    /// The instruction set [`render_rect`] really uses for `self` with
    /// packets of `packet` lanes of `S`: [`Isa::effective`]`(self)` for
    /// packets of 8 or more lanes of a [`Scalar::PACKED`] type, the
    /// baseline otherwise.
    pub fn used_for<S: Scalar>(self, packet: usize) -> Isa {
        if S::PACKED && packet >= 8 {
            self.effective()
        } else {
            Isa::Baseline
        }
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

/// A module for one instruction set: its entry point (the items after the
/// `;`), and the tracer and queries of an accelerator compiled as functions
/// of their own: the pieces of the render path that [`render_rect`] cuts
/// off (see the module documentation). One accelerator type per
/// instruction set; the AVX2 and AVX-512 ones are made only by
/// [`render_rect`], after run-time detection, which is what makes their
/// `unsafe` calls sound.
macro_rules! isa_queries {
    ($(#[$doc:meta])* $module:ident, $name:ident, $job:ident, $closest:ident, $shadow:ident, $(#[$tf:meta])*; $($entry:item)*) => {
        mod $module {
            use super::*;

            $($entry)*

            $(#[$doc])*
            #[derive(Clone, Copy, Debug)]
            pub(super) struct $name<A>(pub(super) A);

            impl<S: Scalar, A: Accelerator<S>> Accelerator<S> for $name<A> {
                fn check(&self, scene: &SceneView<'_, S>) -> Result<(), SceneMismatch> {
                    self.0.check(scene)
                }
                #[inline(always)]
                fn run<J: PacketJob>(&self, job: J) -> J::Output {
                    // SAFETY: a value of this type exists only where the CPU
                    // supports the instruction set `$job` is compiled for.
                    unsafe { $job(job) }
                }
                #[inline(always)]
                fn closest_hit<const W: usize>(&self, scene: &SceneView<'_, S>, ray: &RayPacket<S, W>, t_min: Lanes<S, W>, t_max: Lanes<S, W>, active: Mask<W>) -> Hit<S, W> {
                    // SAFETY: a value of this type exists only where the CPU
                    // supports the instruction set `$closest` is compiled for
                    // (see `render_rect`; the baseline needs nothing).
                    unsafe { $closest(&self.0, scene, ray, t_min, t_max, active) }
                }
                #[inline(always)]
                fn transmittance<const W: usize>(&self, scene: &SceneView<'_, S>, ray: &RayPacket<S, W>, t_min: Lanes<S, W>, t_max: Lanes<S, W>, active: Mask<W>) -> Lanes<S, W> {
                    // SAFETY: as for `closest_hit`.
                    unsafe { $shadow(&self.0, scene, ray, t_min, t_max, active) }
                }
            }

            /// # Safety
            /// The CPU must support the instruction set this is compiled for.
            #[inline(never)]
            $(#[$tf])*
            unsafe fn $job<J: PacketJob>(job: J) -> J::Output {
                job.run()
            }

            /// # Safety
            /// The CPU must support the instruction set this is compiled for.
            #[inline(never)]
            $(#[$tf])*
            unsafe fn $closest<S: Scalar, A: Accelerator<S>, const W: usize>(a: &A, scene: &SceneView<'_, S>, ray: &RayPacket<S, W>, t_min: Lanes<S, W>, t_max: Lanes<S, W>, active: Mask<W>) -> Hit<S, W> {
                a.closest_hit(scene, ray, t_min, t_max, active)
            }

            /// # Safety
            /// The CPU must support the instruction set this is compiled for.
            #[inline(never)]
            $(#[$tf])*
            unsafe fn $shadow<S: Scalar, A: Accelerator<S>, const W: usize>(a: &A, scene: &SceneView<'_, S>, ray: &RayPacket<S, W>, t_min: Lanes<S, W>, t_max: Lanes<S, W>, active: Mask<W>) -> Lanes<S, W> {
                a.transmittance(scene, ray, t_min, t_max, active)
            }
        }
        use $module::$name;
    };
}

// One module per instruction set, holding its entry point, its tracer and
// its queries: rustc puts a module's code (generic instantiations included)
// in one codegen unit, and one LLVM thread compiles a unit, so the release
// build compiles the instruction sets' copies side by side instead of one
// after the other. Each set's pieces stay in one unit: with the queries in
// units of their own, the scalar tracer (packets of 1) ran 4–7 % slower
// (docs/performance.md, "The release build").
isa_queries!(
    /// Queries compiled for the baseline instruction set.
    baseline, BaselineQueries, job_baseline, closest_hit_baseline, transmittance_baseline, ;
    #[inline(never)]
    pub(super) fn run_baseline<K: IsaKernel>(kernel: K) -> K::Output {
        kernel.run()
    }
);
use baseline::run_baseline;
#[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
isa_queries!(
    /// Queries compiled for AVX2 (made only once AVX2 was detected).
    avx2, Avx2Queries, job_avx2, closest_hit_avx2, transmittance_avx2, #[target_feature(enable = "avx2")];
    /// # Safety
    /// The CPU must support AVX2.
    #[inline(never)]
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn run_avx2<K: IsaKernel>(kernel: K) -> K::Output {
        kernel.run()
    }
);
#[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
use avx2::run_avx2;
#[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
isa_queries!(
    /// Queries compiled for AVX-512 F, VL, BW and DQ (made only once all
    /// four were detected).
    avx512, Avx512Queries, job_avx512, closest_hit_avx512, transmittance_avx512, #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq")];
    /// # Safety
    /// The CPU must support AVX-512 F, VL, BW and DQ.
    #[inline(never)]
    #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq")]
    pub(super) unsafe fn run_avx512<K: IsaKernel>(kernel: K) -> K::Output {
        kernel.run()
    }
);
#[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
use avx512::run_avx512;

/// [`Renderer::render_rect`] as an [`IsaKernel`].
struct RenderRect<'r, 'a, 'o, 's, S, A, const D: usize, const W: usize> {
    renderer: &'r Renderer<'a, S, A, D>,
    rect: Rect,
    out: &'o mut [Rgb8],
    stats: &'s mut RayStats,
}

impl<S: Scalar, A: Accelerator<S>, const D: usize, const W: usize> IsaKernel
    for RenderRect<'_, '_, '_, '_, S, A, D, W>
{
    type Output = Result<(), BufferTooSmall>;
    #[cfg_attr(not(debug_assertions), inline(always))]
    fn run(self) -> Self::Output {
        self.renderer.render_rect::<W>(self.rect, self.out, self.stats)
    }
}

/// [`Renderer::render_rect`] compiled for `isa` (see [`Isa::run`]): the same
/// bytes as the plain call, faster where the CPU allows. The render loop is
/// compiled inside the entry point for `isa`, and the renderer's queries in
/// functions of their own for the same instruction set.
///
/// Only packets of 8 or more lanes of a [`Scalar::PACKED`] type (`f32`)
/// have AVX2 and AVX-512 copies; everything else runs the baseline copy
/// whatever `isa` says ([`Isa::used_for`] tells which), since 1 and 4
/// lanes of `f32` fit SSE2's registers and integer fixed point gains
/// little, and every copy costs compile time. (The condition is a constant
/// of each instantiation, so the other instantiations compile no copies.)
pub fn render_rect<S: Scalar, A: Accelerator<S>, const D: usize, const W: usize>(
    isa: Isa,
    renderer: &Renderer<'_, S, A, D>,
    rect: Rect,
    out: &mut [Rgb8],
    stats: &mut RayStats,
) -> Result<(), BufferTooSmall> {
    if const { !S::PACKED || W < 8 } {
        let r = renderer.map_accelerator(BaselineQueries);
        return run_baseline(RenderRect::<S, _, D, W> { renderer: &r, rect, out, stats });
    }
    match isa.effective() {
        Isa::Baseline => {
            let r = renderer.map_accelerator(BaselineQueries);
            run_baseline(RenderRect::<S, _, D, W> { renderer: &r, rect, out, stats })
        }
        #[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
        Isa::Avx2 => {
            // `effective` returned Avx2 only because run-time detection
            // found AVX2: the condition for making `Avx2Queries`.
            let r = renderer.map_accelerator(Avx2Queries);
            // SAFETY: the same detection; AVX2 is all `run_avx2` needs.
            unsafe { run_avx2(RenderRect::<S, _, D, W> { renderer: &r, rect, out, stats }) }
        }
        #[cfg(any(target_arch = "x86_64", target_arch = "x86"))]
        Isa::Avx512 => {
            // `effective` returned Avx512 only because run-time detection
            // found AVX-512 F, VL, BW and DQ: the condition for making
            // `Avx512Queries`.
            let r = renderer.map_accelerator(Avx512Queries);
            // SAFETY: the same detection; those four are all `run_avx512` needs.
            unsafe { run_avx512(RenderRect::<S, _, D, W> { renderer: &r, rect, out, stats }) }
        }
        #[cfg(not(any(target_arch = "x86_64", target_arch = "x86")))]
        // (Never available off x86: `effective` gives the baseline.)
        Isa::Avx2 | Isa::Avx512 => {
            let r = renderer.map_accelerator(BaselineQueries);
            run_baseline(RenderRect::<S, _, D, W> { renderer: &r, rect, out, stats })
        }
    }
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
