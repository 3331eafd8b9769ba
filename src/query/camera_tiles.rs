//! Camera tiles: per square tile of the image, the primitives some camera
//! ray of its pixels can hit, so that a packet of camera rays inside one
//! tile tests that short list instead of walking a tree.
//!
//! The lists come from [`screen_rects`](super::cull::screen_rects), the
//! rectangles of [`ScreenCull`](super::ScreenCull) for any number of
//! primitives: a primitive is listed in every tile its rectangle meets, in
//! index order. A packet takes a tile's list only when it is a packet of
//! camera rays in that tile, which it tells from the rays themselves:
//! - every active lane starts exactly at the eye (the rectangles are a fact
//!   about rays from the eye: a ray from `E` with direction `d` that
//!   reports a crossing at `t` has `E + t·d` in the primitive's grown box,
//!   so `d`'s projection `(d·r/d·f, d·u/d·f)` lies in the projection of
//!   that box, which the rectangle holds with a pixel to spare and more);
//! - every active lane's direction projects (`d·f > 0`) into the image, to
//!   the same tile. The projection is computed here in `f32`, a few parts
//!   in 10⁷ of the image's size from its exact value, far inside the
//!   rectangle's spare pixel.
//!
//! So a primitive left out of the list cannot report a crossing for any
//! lane, and the closest hit among the list (nearest root, ties to the
//! lower index) is the closest hit among all primitives, bit for bit: the
//! answer of [`BruteForce`](super::BruteForce), which every accelerator
//! gives. Other packets (secondary rays, packets across tiles, tiles whose
//! list is over the builder's budget) go through the tree as before.

use crate::geom::camera::Camera;
use crate::geom::ray::RayPacket;
use crate::geom::vec3::Vec3;
use crate::num::lanes::Mask;
use crate::num::scalar::Scalar;

/// The flag, in a tile's start, of a tile with no list (more test work
/// than the builder's budget): its packets walk the tree.
const NO_LIST: u32 = 1 << 31;

/// What the tiles need of the camera to place a ray's direction in the
/// image, in `f32` (as [`ScreenCull`](super::ScreenCull) does).
#[derive(Clone, Copy, Debug)]
struct Projection<S> {
    eye: Vec3<S>,
    f: [f32; 3],
    r: [f32; 3],
    u: [f32; 3],
    /// The image's half width over the screen's half width, and likewise
    /// for heights: pixels per unit of `x/z` and `y/z`.
    kx: f32,
    ky: f32,
    w: u32,
    h: u32,
}

impl<S: Scalar> Projection<S> {
    // (Only the `std` builder makes tiles.)
    #[cfg_attr(not(feature = "std"), allow(dead_code))]
    fn new(camera: &Camera<S>) -> Self {
        let (f, r, u) = camera.frame();
        let (sx, sy) = camera.screen_scale();
        Projection {
            eye: camera.eye(),
            f: f.to_f32(),
            r: r.to_f32(),
            u: u.to_f32(),
            kx: camera.width() as f32 * 0.5 / sx.to_f32(),
            ky: camera.height() as f32 * 0.5 / sy.to_f32(),
            w: camera.width(),
            h: camera.height(),
        }
    }
}

/// Camera tiles as slices (see the module docs): the view a
/// [`BvhView`](super::BvhView) takes with
/// [`BvhView::with_camera_tiles`](super::BvhView::with_camera_tiles).
#[derive(Clone, Copy, Debug)]
pub struct CameraTiles<'a, S> {
    view: Projection<S>,
    /// Tiles are `2^shift` pixels square, `cols` of them per row.
    shift: u32,
    cols: u32,
    /// Per tile, where its list starts in `ids` (with [`NO_LIST`] set for a
    /// tile without one), then the end of the last list.
    starts: &'a [u32],
    ids: &'a [u32],
    /// The primitives of the scene the lists were made for.
    primitives: usize,
}

impl<'a, S: Scalar> CameraTiles<'a, S> {
    /// How many primitives the scene had that the tiles were made for (a
    /// tree with tiles of another scene fails its
    /// [`check`](crate::query::Accelerator::check)).
    pub fn primitives(&self) -> usize {
        self.primitives
    }

    /// The list of the tile every active lane of `ray` lies in, if `ray`
    /// is a packet of camera rays inside one tile that has a list.
    #[inline(always)]
    pub fn list<const W: usize>(&self, ray: &RayPacket<S, W>, active: Mask<W>) -> Option<&'a [u32]> {
        let v = &self.view;
        let (o, d) = (&ray.origin, &ray.dir);
        let (w, h) = (v.w as f32, v.h as f32);
        // Every lane at once, without branches (so that the lanes' loop
        // vectorises); inactive lanes only drop out of the reductions.
        let (mut bad, mut lo, mut hi) = (false, u32::MAX, 0u32);
        for i in 0..W {
            let live = active.get(i);
            let at_eye = (o.x.0[i] == v.eye.x) & (o.y.0[i] == v.eye.y) & (o.z.0[i] == v.eye.z);
            let di = [d.x.0[i].to_f32(), d.y.0[i].to_f32(), d.z.0[i].to_f32()];
            let dot = |a: [f32; 3]| di[0] * a[0] + di[1] * a[1] + di[2] * a[2];
            let z = dot(v.f);
            // Continuous pixel coordinates, as the rectangles' (pixel `i`
            // covers `[i, i + 1]`; rows grow downwards).
            // (`kx = W/(2·sx)`, `ky = H/(2·sy)`: one division per lane.)
            let inv = 1.0 / z;
            let cx = dot(v.r) * inv * v.kx + w * 0.5;
            let cy = h * 0.5 - dot(v.u) * inv * v.ky;
            // Ahead of the eye and inside the image (NaN fails every test).
            let inside = (z > 0.0) & (cx >= 0.0) & (cx < w) & (cy >= 0.0) & (cy < h);
            // The conversions truncate (and saturate): the floor of the
            // non-negative values that matter.
            let t = ((cy as u32) >> self.shift) * self.cols + ((cx as u32) >> self.shift);
            bad |= live & !(at_eye & inside);
            lo = if live { lo.min(t) } else { lo };
            hi = if live { hi.max(t) } else { hi };
        }
        if bad || lo != hi {
            return None;
        }
        let t = lo as usize;
        let (&start, &end) = (self.starts.get(t)?, self.starts.get(t + 1)?);
        if start & NO_LIST != 0 {
            return None;
        }
        self.ids.get(start as usize..(end & !NO_LIST) as usize)
    }
}

#[cfg(feature = "std")]
pub use heap::{test_weight, HeapCameraTiles, TileSettings};

#[cfg(feature = "std")]
mod heap {
    use super::*;
    use crate::geom::primitives::Shape;
    use crate::query::cull::screen_rects;
    use crate::scene::SceneView;
    use std::vec::Vec;

    /// How [`HeapCameraTiles`] cuts the image, and when its tiles are worth
    /// having.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct TileSettings {
        /// Tiles are `2^shift` pixels square.
        pub shift: u32,
        /// The most test work a tile's list may hold, in sphere tests
        /// ([`test_weight`]); a tile over it keeps no list (its packets
        /// walk the tree, which skips the primitives whose boxes a ray
        /// misses).
        pub budget: u32,
        /// The least share of the tiles, in per cent, that must have a list
        /// that is not empty for the tiles to be built at all: below it most
        /// packets would work out their tile for nothing.
        pub min_listed_percent: u32,
    }

    impl Default for TileSettings {
        /// Tiles of 16 × 16 pixels with at most 8 sphere tests' work each,
        /// built where at least half of them list something (chosen by
        /// measurement: docs/performance.md, "Camera tiles": gears-2, whose
        /// polygons' lists are long, and sombrero-1, whose tiles with lists
        /// are the empty sky, were 2–9 % slower with tiles).
        fn default() -> Self {
            TileSettings { shift: 4, budget: 8, min_listed_percent: 50 }
        }
    }

    /// A primitive's test work in sphere tests, roughly: a sphere or plane
    /// 1, a box, quadric or cone 2, a polygon 1 and a half per two
    /// vertices (its edge tests). Only [`TileSettings::budget`] uses it:
    /// the lists are exact whatever it says.
    pub fn test_weight<S: Scalar>(shape: &Shape<S>) -> u32 {
        match shape {
            Shape::Sphere(_) | Shape::Plane(_) => 1,
            Shape::Polygon(p) => 1 + p.vertex_count().div_ceil(2),
            _ => 2,
        }
    }

    /// Camera tiles in `Vec`s, built for one scene and one camera (`std`).
    #[derive(Clone, Debug)]
    pub struct HeapCameraTiles<S> {
        view: Projection<S>,
        shift: u32,
        cols: u32,
        starts: Vec<u32>,
        ids: Vec<u32>,
        primitives: usize,
    }

    /// An empty `Vec` with room for `n`, or `None` if the allocator refuses.
    fn with_room<T>(n: usize) -> Option<Vec<T>> {
        let mut v = Vec::new();
        v.try_reserve_exact(n).ok()?;
        Some(v)
    }

    impl<S: Scalar> HeapCameraTiles<S> {
        /// The tiles of `scene` seen by `camera`; `None` if fewer tiles
        /// than [`TileSettings::min_listed_percent`] would list something,
        /// if the lists would not fit their `u32` indices, or if the
        /// allocator refuses them (the tree then answers every packet, as
        /// without tiles).
        pub fn build(scene: &SceneView<'_, S>, camera: &Camera<S>, settings: TileSettings) -> Option<Self> {
            let shift = settings.shift.min(15);
            let view = Projection::new(camera);
            // (A camera's sides are 1 to 65 535 pixels: the rectangles'
            // `u16` pixel indices hold them, and there is at least a tile.)
            let cols = view.w.div_ceil(1 << shift);
            let rows = view.h.div_ceil(1 << shift);
            let n = (cols as usize).checked_mul(rows as usize)?;
            // The tiles a rectangle meets, by index.
            let tiles = |r: [u32; 4]| {
                let (c0, c1) = (r[0] >> shift, (r[1] >> shift).min(cols - 1));
                let (r0, r1) = (r[2] >> shift, (r[3] >> shift).min(rows - 1));
                (r0..=r1).flat_map(move |row| (c0..=c1).map(move |col| (row * cols + col) as usize))
            };
            // Each primitive's rectangle, projected once for both passes.
            let mut rects = with_room(scene.primitives().len())?;
            rects.extend(screen_rects(scene, camera));
            // First pass: how many primitives each tile lists, and their
            // test work.
            let mut count: Vec<(u32, u32)> = with_room(n)?;
            count.resize(n, (0, 0));
            for (r, p) in rects.iter().zip(scene.primitives()) {
                let Some(r) = *r else { continue };
                let weight = test_weight(&p.shape);
                for t in tiles(r) {
                    if let Some((c, w)) = count.get_mut(t) {
                        *c = c.saturating_add(1);
                        *w = w.saturating_add(weight);
                    }
                }
            }
            let listed = count.iter().filter(|&&(c, w)| c > 0 && w <= settings.budget).count();
            if (listed as u64) * 100 < n as u64 * settings.min_listed_percent as u64 {
                return None;
            }
            // Starts (tiles over the budget keep no list); each tile's count
            // becomes the cursor where its next entry goes.
            let mut starts: Vec<u32> = with_room(n + 1)?;
            let mut total: u32 = 0;
            for (c, weight) in count.iter_mut() {
                if *weight > settings.budget {
                    starts.push(total | NO_LIST);
                } else {
                    starts.push(total);
                    let first = total;
                    total = total.checked_add(*c).filter(|t| t & NO_LIST == 0)?;
                    *c = first;
                }
            }
            starts.push(total);
            // Second pass: the lists, each in index order.
            let mut ids: Vec<u32> = with_room(total as usize)?;
            ids.resize(total as usize, 0);
            for (k, r) in rects.iter().enumerate() {
                let Some(r) = *r else { continue };
                for t in tiles(r) {
                    if starts.get(t).is_some_and(|&s| s & NO_LIST == 0) {
                        if let Some((at, _)) = count.get_mut(t) {
                            if let Some(slot) = ids.get_mut(*at as usize) {
                                *slot = k as u32;
                            }
                            *at += 1;
                        }
                    }
                }
            }
            Some(HeapCameraTiles { view, shift, cols, starts, ids, primitives: scene.primitives().len() })
        }

        /// The tiles as slices, for [`BvhView::with_camera_tiles`](crate::query::BvhView::with_camera_tiles).
        pub fn view(&self) -> CameraTiles<'_, S> {
            CameraTiles {
                view: self.view,
                shift: self.shift,
                cols: self.cols,
                starts: &self.starts,
                ids: &self.ids,
                primitives: self.primitives,
            }
        }

        /// Bytes of heap the tiles hold.
        pub fn heap_bytes(&self) -> usize {
            (self.starts.capacity() + self.ids.capacity()) * core::mem::size_of::<u32>()
        }

        /// How many tiles have a list that is not empty, of how many.
        pub fn tiles_with_lists(&self) -> (usize, usize) {
            let n = self.starts.len().saturating_sub(1);
            let listed = self.starts.windows(2).filter(|s| s[0] & NO_LIST == 0 && s[0] != s[1] & !NO_LIST).count();
            (listed, n)
        }
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;
    use crate::geom::camera::packet_shape;
    use crate::scene::{Material, Scene};

    type Small = Scene<f32, 8, 8, 2, 2>;

    /// A 40 × 40 camera at the origin looking down −z, 90°.
    fn camera() -> Camera<f32> {
        let up = Vec3::new(0.0, 1.0, 0.0);
        Camera::new(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0), up, 90.0, 40, 40).unwrap()
    }

    /// A small sphere straight ahead (about pixels 18–21) and a plane below.
    fn scene() -> Small {
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        s.add_sphere(Vec3::new(0.0, 0.0, -10.0), 0.5, m).unwrap();
        s.add_plane(0.0, 1.0, 0.0, 1.0, m).unwrap();
        s
    }

    fn tiles(budget: u32) -> HeapCameraTiles<f32> {
        HeapCameraTiles::build(&scene().view(), &camera(), TileSettings { shift: 2, budget, min_listed_percent: 0 })
            .unwrap()
    }

    #[test]
    fn a_camera_packet_in_one_tile_gets_its_list() {
        let (t, cam) = (tiles(8), camera());
        let t = t.view();
        // Tiles of 4 × 4 pixels: the plane is everywhere, the sphere only
        // in the tiles around the centre.
        let (ray, active) = cam.packet::<4>(0, 0, cam.full_rect());
        assert_eq!(t.list(&ray, active), Some(&[1u32][..]));
        let (ray, active) = cam.packet::<16>(20, 20, cam.full_rect());
        assert_eq!(t.list(&ray, active), Some(&[0u32, 1][..]));
        let (ray, active) = cam.packet::<1>(39, 39, cam.full_rect());
        assert_eq!(t.list(&ray, active), Some(&[1u32][..]));
        // Inactive lanes do not count: a packet at the image's edge.
        let (ray, active) = cam.packet::<16>(38, 38, cam.full_rect());
        assert_eq!(active.count(), 4);
        assert_eq!(t.list(&ray, active), Some(&[1u32][..]));
        assert_eq!(tiles(8).tiles_with_lists(), (100, 100));
    }

    #[test]
    fn other_rays_and_long_lists_walk_the_tree() {
        let (t, cam) = (tiles(8), camera());
        let t = t.view();
        // Across two tiles (pixels 3 and 4 of a row).
        let (w, _) = packet_shape(4);
        let (ray, active) = cam.packet::<4>(4 - w / 2, 0, cam.full_rect());
        assert_eq!(t.list(&ray, active), None);
        // Not from the eye.
        let (mut ray, active) = cam.packet::<4>(0, 0, cam.full_rect());
        ray.origin.x.0[1] = f32::from_bits(1);
        assert_eq!(t.list(&ray, active), None);
        // Backwards, sideways, NaN.
        for d in [Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(f32::NAN, 0.0, -1.0)] {
            let (mut ray, active) = cam.packet::<1>(0, 0, cam.full_rect());
            ray.dir = d.splat();
            assert_eq!(t.list(&ray, active), None, "{d:?}");
        }
        // No active lane.
        let (ray, _) = cam.packet::<4>(0, 0, cam.full_rect());
        assert_eq!(t.list(&ray, Mask::splat(false)), None);
        // A tile over the limit keeps no list; one under it does.
        let short = tiles(1);
        let short = short.view();
        let (ray, active) = cam.packet::<1>(20, 20, cam.full_rect());
        assert_eq!(short.list(&ray, active), None);
        let (ray, active) = cam.packet::<1>(0, 0, cam.full_rect());
        assert_eq!(short.list(&ray, active), Some(&[1u32][..]));
        assert_eq!(tiles(1).tiles_with_lists().1, 100);
        assert!(tiles(1).tiles_with_lists().0 < 100);
        // Empty lists do not count: a sphere alone leaves most tiles empty.
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        s.add_sphere(Vec3::new(0.0, 0.0, -10.0), 0.5, m).unwrap();
        let alone =
            HeapCameraTiles::build(&s.view(), &cam, TileSettings { shift: 2, budget: 8, min_listed_percent: 0 })
                .unwrap();
        let (listed, all) = alone.tiles_with_lists();
        assert!((1..=9).contains(&listed) && all == 100, "{listed} of {all}");
        // And with at least half the tiles asked to list something, no tiles.
        let half = TileSettings { shift: 2, budget: 8, min_listed_percent: 50 };
        assert!(HeapCameraTiles::build(&s.view(), &cam, half).is_none());
        assert!(HeapCameraTiles::build(&scene().view(), &cam, half).is_some());
    }
}
