//! The interface every accelerator implements, and the result of a
//! closest-hit query.

use crate::geom::ray::RayPacket;
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;
use crate::scene::SceneView;

/// Per-lane result of a closest-hit query.
#[derive(Clone, Copy, Debug)]
pub struct Hit<S, const W: usize> {
    /// Distance along the ray (meaningful where `mask` is set).
    pub t: Lanes<S, W>,
    /// Index of the primitive hit (meaningful where `mask` is set).
    pub prim: [u32; W],
    /// Lanes that hit something.
    pub mask: Mask<W>,
}

/// An accelerator was built for another scene: it covers `built_for`
/// primitives, the scene has `scene_has`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneMismatch {
    /// Primitives the accelerator was built for.
    pub built_for: usize,
    /// Primitives the scene has.
    pub scene_has: usize,
}

impl core::fmt::Display for SceneMismatch {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "accelerator built for {} primitives, scene has {}", self.built_for, self.scene_has)
    }
}

impl core::error::Error for SceneMismatch {}

/// Packet work an accelerator runs on its caller's behalf
/// ([`Accelerator::run`]): the tracer hands it the whole trace of a packet,
/// so that an accelerator compiled for another instruction set (the
/// dispatcher's wrappers) compiles the tracer with it, in one function.
pub trait PacketJob {
    /// What the work returns.
    type Output;
    /// Does the work.
    fn run(self) -> Self::Output;
}

/// Answers closest-hit and shadow queries over a scene's data.
///
/// Every implementation must return the same bits as [`crate::query::BruteForce`]
/// for every ray: that is what lets a renderer switch accelerators (or
/// instruction sets) without changing a byte of its output.
pub trait Accelerator<S: Scalar>: Copy + core::fmt::Debug {
    /// Checks that the accelerator belongs to `scene` (a tree built for
    /// another scene is an error, not wrong pixels).
    fn check(&self, scene: &SceneView<'_, S>) -> Result<(), SceneMismatch> {
        let _ = scene;
        Ok(())
    }

    /// The nearest hit of each active ray in `(t_min, t_max)`. Ties (two
    /// primitives at exactly the same distance) go to the lower primitive
    /// index, whatever the packet width.
    fn closest_hit<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Hit<S, W>;

    /// Runs `job` (the tracer runs each packet's whole trace through this).
    /// The default runs it in place; an accelerator compiled for another
    /// instruction set runs it compiled for that set too.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn run<J: PacketJob>(&self, job: J) -> J::Output {
        job.run()
    }

    /// Fraction of light that reaches the end of each active ray segment
    /// `(t_min, t_max)`: every surface crossed multiplies it by the crossed
    /// object's `Kt`, in primitive order (an opaque object stops it; a glass
    /// sphere gives `Kt²`). Inactive lanes return 0.
    fn transmittance<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Lanes<S, W>;
}
