//! A run-time choice between brute force and a tree.

use super::accelerator::{Accelerator, Hit, SceneMismatch};
use super::brute::BruteForce;
use super::bvh::BvhView;
use crate::geom::ray::RayPacket;
use crate::num::lanes::{Lanes, Mask};
use crate::num::scalar::Scalar;
use crate::scene::SceneView;

/// Brute force or a BVH, chosen at run time: one compiled renderer serves
/// both (the CLI's `--accel bvh|none`). Programs that always use one of
/// them should use that type directly: a firmware image with
/// [`BruteForce`] contains no tree code at all.
#[derive(Clone, Copy, Debug)]
pub enum AccelChoice<'a, S> {
    /// Test every primitive ([`BruteForce`]).
    BruteForce,
    /// Go through a tree.
    Bvh(BvhView<'a, S>),
}

impl<S: Scalar> Accelerator<S> for AccelChoice<'_, S> {
    fn check(&self, scene: &SceneView<'_, S>) -> Result<(), SceneMismatch> {
        match self {
            AccelChoice::BruteForce => BruteForce.check(scene),
            AccelChoice::Bvh(tree) => tree.check(scene),
        }
    }

    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn closest_hit<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Hit<S, W> {
        match self {
            AccelChoice::BruteForce => BruteForce.closest_hit(scene, ray, t_min, t_max, active),
            AccelChoice::Bvh(tree) => tree.closest_hit(scene, ray, t_min, t_max, active),
        }
    }

    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    fn transmittance<const W: usize>(
        &self,
        scene: &SceneView<'_, S>,
        ray: &RayPacket<S, W>,
        t_min: Lanes<S, W>,
        t_max: Lanes<S, W>,
        active: Mask<W>,
    ) -> Lanes<S, W> {
        match self {
            AccelChoice::BruteForce => BruteForce.transmittance(scene, ray, t_min, t_max, active),
            AccelChoice::Bvh(tree) => tree.transmittance(scene, ray, t_min, t_max, active),
        }
    }
}
