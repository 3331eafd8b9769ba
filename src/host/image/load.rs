//! Loading: NFF text into a scene on the heap and a BVH built into `Vec`s,
//! ready to be rendered any number of times. Sized by the file, not by
//! compiled-in capacities: a scene is as large as memory, and running out
//! of it is an error ([`Error::Scene`] with the line, or [`Error::Bvh`]),
//! not an abort.

use super::bands::{render_tiles, Tiling, TILE};
use super::options::{image_size, threads, AccelKind, Error, Image, Options, ScalarKind, DEPTH};
use super::policy::packet_used;
use crate::geom::camera::Camera;
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::Vec3;
use crate::num::fixed32::Fixed32;
use crate::num::scalar::Scalar;
use crate::query::{AccelChoice, BuildSettings, BvhStats, HeapBvh, HeapCameraTiles, TileSettings};
use crate::render::Renderer;
use crate::scene::bake::{bake_scene, BakeScalar};
use crate::scene::nff::{self, NffInfo};
use crate::scene::HeapScene;
use crate::trace::{TraceSettings, Tracer};
use std::time::{Duration, Instant};

/// What a loaded scene holds, besides its objects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneInfo {
    /// Camera, background, counts and lines of the file.
    pub nff: NffInfo,
    /// Zero-area polygons (kept, so primitive ids follow the file; never hit).
    pub degenerate: u32,
    /// Time to read the file into the scene (and, for a scalar with a
    /// frame of its own, to convert it).
    pub parse: Duration,
    /// Heap bytes the scene and its tree hold.
    pub bytes: usize,
    /// The tree and its build time, if one was built.
    pub bvh: Option<(BvhStats, Duration)>,
    /// The scalar the scene was built with.
    pub scalar: ScalarKind,
}

/// A scene read by [`LoadedScene::load`] (or [`with_scene`]), ready to be
/// rendered any number of times; its scalar is fixed when loading.
pub struct LoadedScene {
    scene: Scalars,
}

/// The loaded scene, by scalar.
enum Scalars {
    F32(Loaded<f32>),
    Fixed32(Loaded<Fixed32>),
}

/// A scene of scalar `S` and the tree it is traced through.
struct Loaded<S: Scalar> {
    scene: HeapScene<S>,
    bvh: Option<HeapBvh<S>>,
    info: SceneInfo,
    /// The frame the scene was converted into (the identity unless the
    /// scalar asks for one: [`Scalar::SCENE_FRAME`]).
    frame: Similarity,
}

impl LoadedScene {
    /// Reads `text` (NFF) into a scene of scalar `scalar` on the heap and
    /// builds a BVH over it unless `accel` is brute force.
    pub fn load(text: &str, scalar: ScalarKind, accel: AccelKind) -> Result<LoadedScene, Error> {
        let accel = accel == AccelKind::Bvh;
        let scene = match scalar {
            ScalarKind::F32 => Scalars::F32(Loaded::load(text, scalar, accel)?),
            ScalarKind::Fixed32 => Scalars::Fixed32(Loaded::load(text, scalar, accel)?),
        };
        Ok(LoadedScene { scene })
    }

    /// What the scene holds.
    pub fn info(&self) -> &SceneInfo {
        match &self.scene {
            Scalars::F32(s) => &s.info,
            Scalars::Fixed32(s) => &s.info,
        }
    }

    /// Bounds of the bounded primitives (`None` if there are none), in
    /// `f32`, in the frame the scene is traced in.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        match &self.scene {
            Scalars::F32(s) => s.bounds(),
            Scalars::Fixed32(s) => s.bounds(),
        }
    }

    /// Renders the scene with `options`; `progress` is called after each
    /// tile, from the worker threads. `options.scalar` is the loaded
    /// scene's and is ignored here; `options.accel` may ask for brute force
    /// even where a tree was built (a scene loaded without a tree always
    /// renders by brute force: [`Image::accel`] says which ran).
    pub fn render(&self, options: &Options, progress: &(dyn Fn() + Sync)) -> Result<Image, Error> {
        match &self.scene {
            Scalars::F32(s) => s.render(options, progress),
            Scalars::Fixed32(s) => s.render(options, progress),
        }
    }
}

impl LoadedScene {
    /// The scene and its camera (the file's, for a `width × height` image,
    /// by default the file's size) as Rust source for a firmware, written
    /// by [`bake_scene`](crate::scene::bake::bake_scene): `static` arrays a
    /// `SceneView` is made over, and the camera. Fixed point: the scene
    /// must fit the scalar's range, as for rendering ([`Error::Range`]).
    pub fn bake(&self, width: Option<u32>, height: Option<u32>) -> Result<String, Error> {
        match &self.scene {
            Scalars::F32(s) => s.bake(width, height),
            Scalars::Fixed32(s) => s.bake(width, height),
        }
    }
}

impl<S: BakeScalar> Loaded<S> {
    fn bake(&self, width: Option<u32>, height: Option<u32>) -> Result<String, Error> {
        let camera = self.camera(width, height)?;
        let view = self.scene.view();
        let mut source = String::new();
        // A `String` accepts every write: this cannot fail.
        let _ = bake_scene(&view, &camera, &mut source);
        Ok(source)
    }
}

impl Image {
    /// Reads `scene` (NFF text), builds what `options` asks for and renders
    /// it; see the module documentation.
    pub fn render(scene: &str, options: &Options) -> Result<Image, Error> {
        with_scene(scene, options.scalar, options.accel, |s| s.render(options, &|| {}))?
    }
}

/// Loads `text` with [`LoadedScene::load`] and runs `f` on the scene;
/// returns what `f` returns.
pub fn with_scene<T>(
    text: &str,
    scalar: ScalarKind,
    accel: AccelKind,
    f: impl FnOnce(&LoadedScene) -> T,
) -> Result<T, Error> {
    Ok(f(&LoadedScene::load(text, scalar, accel)?))
}

impl<S: Scalar> Loaded<S> {
    fn load(text: &str, scalar: ScalarKind, accel: bool) -> Result<Self, Error> {
        let start = Instant::now();
        let mut scene = HeapScene::<S>::new();
        let (nff, frame) = match S::SCENE_FRAME {
            None => (nff::parse(text, &mut scene).map_err(Error::Scene)?, Similarity::IDENTITY),
            Some(_) => {
                // Read in f32, in the file's units, then convert into the
                // scalar's frame (around the bounded primitives and the eye).
                let mut described = HeapScene::<f32>::new();
                let nff = nff::parse(text, &mut described).map_err(Error::Scene)?;
                let eye = nff.camera.map(|c| Vec3::new(c.from[0], c.from[1], c.from[2]));
                (nff, scene.add_in_frame(&described.view(), eye).map_err(Error::Convert)?)
            }
        };
        let parse = start.elapsed();
        let mut info = SceneInfo {
            nff,
            degenerate: scene.degenerate_polygons(),
            parse,
            bytes: scene.heap_bytes(),
            bvh: None,
            scalar,
        };
        if !accel {
            return Ok(Loaded { scene, bvh: None, info, frame });
        }
        // Pad the boxes for rays that start as far out as the eye (in the
        // scene's frame).
        let reach = nff.camera.map_or(0.0, |c| {
            let e: Vec3<f32> = frame.point(Vec3::new(c.from[0], c.from[1], c.from[2]));
            e.max_abs()
        });
        let start = Instant::now();
        let bvh = HeapBvh::build_with(&scene.view(), &BuildSettings { reach, ..BuildSettings::default() })
            .map_err(Error::Bvh)?;
        info.bvh = Some((bvh.stats(), start.elapsed()));
        info.bytes += bvh.heap_bytes();
        Ok(Loaded { scene, bvh: Some(bvh), info, frame })
    }

    fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        self.scene.view().bounds().map(|(lo, hi)| (lo.to_f32(), hi.to_f32()))
    }

    /// The file's camera for a `width × height` image (default: the file's
    /// size), in the scene's frame, once the whole scene is known to fit
    /// the scalar's range (fixed point; a no-op for `f32`).
    fn camera(&self, width: Option<u32>, height: Option<u32>) -> Result<Camera<S>, Error> {
        let cam = self.info.nff.camera.ok_or(Error::NoCamera)?;
        let (width, height) = image_size(width, height, (cam.width, cam.height));
        let camera = Camera::<S>::in_frame(cam.from, cam.at, cam.up, cam.angle, width, height, &self.frame)
            .map_err(Error::Camera)?;
        self.scene.view().check_range(camera.eye()).map_err(Error::Range)?;
        Ok(camera)
    }

    fn render(&self, options: &Options, progress: &(dyn Fn() + Sync)) -> Result<Image, Error> {
        let camera = self.camera(options.width, options.height)?;
        let (width, height) = (camera.full_rect().w, camera.full_rect().h);
        let region = options.region.unwrap_or(camera.full_rect());
        if !region.inside(camera.full_rect()) {
            return Err(Error::Region { region, size: (width, height) });
        }
        let view = self.scene.view();
        let settings = TraceSettings { mode: options.mode, max_depth: options.depth, ..TraceSettings::default() };
        // With the tree, camera tiles for this camera (where enough tiles
        // list something: `TileSettings`): packets of camera rays inside a
        // tile test its short list instead of walking.
        let tiles = match (options.accel, &self.bvh) {
            (AccelKind::Bvh, Some(_)) => HeapCameraTiles::build(&view, &camera, TileSettings::default()),
            _ => None,
        };
        let tiles = tiles.as_ref().map(|t| t.view());
        let (accel, kind) = match (options.accel, &self.bvh) {
            (AccelKind::Bvh, Some(tree)) => {
                let tree = tree.view();
                let tree = match &tiles {
                    Some(t) => tree.with_camera_tiles(t),
                    None => tree,
                };
                (AccelChoice::Bvh(tree), AccelKind::Bvh)
            }
            _ => (AccelChoice::BruteForce, AccelKind::BruteForce),
        };
        let tracer = Tracer::<'_, S, _, DEPTH>::with_accelerator(view, accel, settings).map_err(Error::Trace)?;
        let mut renderer = Renderer::new(tracer, camera);
        renderer.aov = options.aov;
        renderer.sampling = options.sampling;
        let threads = threads(options.threads)?;
        let start = Instant::now();
        let tiling = Tiling { packet: options.packet, isa: options.isa, threads, tile: TILE };
        let (pixels, stats) = render_tiles(&renderer, region, &tiling, progress)?;
        let time = start.elapsed();
        let packet = packet_used::<S>(options.packet);
        let isa = options.isa.used_for::<S>(packet);
        Ok(Image {
            width: region.w,
            height: region.h,
            region,
            full_size: (width, height),
            pixels,
            stats,
            isa,
            packet,
            threads,
            accel: kind,
            time,
        })
    }
}
