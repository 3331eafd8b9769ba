//! Reading a scene file into a scene whose capacity fits it.
//!
//! Scenes have fixed capacities (const generics). The file is scanned first;
//! the smallest capacity tier that holds it is chosen, and the scene is built
//! on a thread whose stack is sized for that tier (a `Scene` is one
//! contiguous value, megabytes for the larger tiers). Files larger than the
//! largest tier fail with the reader's capacity error, which names the
//! capacity and what the file needs.
//!
//! With acceleration on, the BVH (capacity = the tier's primitive capacity)
//! is built on the same thread, right after the scene.

use crate::Failure;
use raypack::nff::{self, NffCounts, NffInfo};
use raypack::prelude::*;
use std::path::Path;

/// What a command does with a loaded scene.
pub struct Loaded<'a, S = f32> {
    /// The scene.
    pub view: SceneView<'a, S>,
    /// Camera, background and counts from the file.
    pub info: NffInfo,
    /// Zero-area polygons (kept, never hit).
    pub degenerate: u32,
    /// The capacity tier used: (primitives, vertices, materials, lights).
    pub capacity: (usize, usize, usize, usize),
    /// The BVH the view traces through, and its build time; `None` for brute force.
    pub bvh: Option<(BvhStats, std::time::Duration)>,
}

/// Reads a scene file as text, with the path in the error.
pub fn read_text(path: &Path) -> Result<String, Failure> {
    std::fs::read_to_string(path).map_err(|e| Failure(format!("{}: {e}", path.display())))
}

/// Whether counts fit a tier.
fn fits(c: &NffCounts, p: usize, v: usize, m: usize, l: usize) -> bool {
    c.primitives() <= p && c.vertices <= v && c.materials <= m && c.lights <= l
}

/// Loads into a `Scene<S, P, V, M, L>` on a thread with room for it and
/// runs `f` there.
fn load_in<S: Scalar, const P: usize, const V: usize, const M: usize, const L: usize, T: Send>(
    path: &Path,
    text: &str,
    accel: bool,
    f: &(dyn Fn(Loaded<'_, S>) -> Result<T, Failure> + Sync),
) -> Result<T, Failure> {
    // Twice the scene (and tree): an unoptimized build may build them in a
    // temporary first.
    let tree = if accel { std::mem::size_of::<Bvh<S, P>>() } else { 0 };
    let stack = 2 * (std::mem::size_of::<Scene<S, P, V, M, L>>() + tree) + (32 << 20);
    std::thread::scope(|s| {
        let worker = std::thread::Builder::new()
            .name("raypack-scene".into())
            .stack_size(stack)
            .spawn_scoped(s, || {
                let mut scene = Scene::<S, P, V, M, L>::new();
                let info = nff::parse(text, &mut scene).map_err(|e| Failure(format!("{}: {e}", path.display())))?;
                let loaded = |view, bvh| Loaded { view, info, degenerate: scene.degenerate_polygons(), capacity: (P, V, M, L), bvh };
                if !accel {
                    return f(loaded(scene.view(), None));
                }
                let mut bvh = Bvh::<S, P>::new();
                // Pad the boxes for rays that start as far out as the eye.
                let reach = info.camera.map_or(0.0, |c| c.from.iter().fold(0.0f32, |m, v| m.max(v.abs())));
                let start = std::time::Instant::now();
                let stats = bvh.build_with(&scene.view(), &BuildSettings { reach, ..BuildSettings::default() })?;
                let built = start.elapsed();
                f(loaded(scene.view().with_bvh(&bvh)?, Some((stats, built))))
            })
            .map_err(|e| Failure(format!("cannot start a thread for the scene: {e}")))?;
        worker.join().unwrap_or_else(|p| std::panic::resume_unwind(p))
    })
}

/// Reads `path` into the smallest capacity tier that holds it, with scalar
/// `S` (`f32` or [`Fixed`]), builds a BVH over it when `accel`, and runs `f`
/// on the scene.
pub fn with_scene<S: Scalar, T: Send>(path: &Path, accel: bool, f: &(dyn Fn(Loaded<'_, S>) -> Result<T, Failure> + Sync)) -> Result<T, Failure> {
    let text = read_text(path)?;
    let counts = nff::scan(&text).map_err(|e| Failure(format!("{}: {e}", path.display())))?.counts;
    if fits(&counts, 1 << 10, 1 << 13, 256, 64) {
        load_in::<S, { 1 << 10 }, { 1 << 13 }, 256, 64, T>(path, &text, accel, f)
    } else if fits(&counts, 1 << 14, 1 << 17, 1024, 256) {
        load_in::<S, { 1 << 14 }, { 1 << 17 }, 1024, 256, T>(path, &text, accel, f)
    } else if fits(&counts, 1 << 18, 1 << 21, 16384, 4096) {
        load_in::<S, { 1 << 18 }, { 1 << 21 }, 16384, 4096, T>(path, &text, accel, f)
    } else {
        // The largest tier; beyond it the reader reports the capacity error.
        load_in::<S, { 1 << 20 }, { 1 << 23 }, 65536, 16384, T>(path, &text, accel, f)
    }
}
