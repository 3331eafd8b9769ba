//! Scenes: primitives, the shared vertex pool, materials and lights, with
//! errors instead of panics. [`Scene`] has capacities as const generics
//! (fixed memory, the core and firmware); with `std`, [`HeapScene`] grows on
//! the heap (the command line). One builder serves both ([`SceneStore`]).
//!
//! [`Scene`] owns its storage (heapless vectors, no allocator); tracing works
//! on a [`SceneView`] of slices, so the tracer is not monomorphized per
//! capacity and a scene can also be assembled from static slices. Both are
//! plain data: how a scene is searched is the business of
//! [`crate::query`].

use crate::geom::fixed_range::{self, RangeError, RangeItem};
use crate::geom::primitives::{
    AaBox, Cone, GeometryError, OrientedBox, Plane, Polygon, Quadric, Shape, ShapeKind, Sphere,
};
use crate::geom::uniform_scale::Similarity;
use crate::geom::vec3::Vec3;
use crate::num::scalar::Scalar;
use heapless::Vec as HVec;

/// Surface description for the Whitted model.
///
/// `local = Ka·colour + Σ lights · (Kd·colour·max(0, N·L) + Ks·max(0, R·V)^shine)`,
/// `colour = (1 − Kt)·local + Kr·reflected + Kt·refracted`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material<S> {
    /// Surface colour (linear RGB).
    pub color: Vec3<S>,
    /// Ambient weight (the ambient light is white, 1).
    pub ka: S,
    /// Diffuse weight.
    pub kd: S,
    /// Specular highlight weight.
    pub ks: S,
    /// Phong exponent.
    pub shine: S,
    /// Mirror-reflection weight.
    pub kr: S,
    /// Transmission weight (also the shadow attenuation per surface crossed).
    pub kt: S,
    /// Index of refraction.
    pub ior: S,
}

crate::num::bake::bake_struct!("raypack::scene::Material", Material<S> { color: Vec3<S>, ka: S, kd: S, ks: S, shine: S, kr: S, kt: S, ior: S });

impl<S: Scalar> Material<S> {
    /// A plain diffuse material of the given colour.
    pub fn diffuse(color: Vec3<S>) -> Self {
        Material { color, ka: S::ZERO, kd: S::ONE, ks: S::ZERO, shine: S::ONE, kr: S::ZERO, kt: S::ZERO, ior: S::ONE }
    }

    /// The NFF `f` material: `Ka = 0`, and `Ks` is both the highlight and the
    /// mirror weight.
    pub fn nff(color: Vec3<S>, kd: S, ks: S, shine: S, kt: S, ior: S) -> Self {
        Material { color, ka: S::ZERO, kd, ks, shine, kr: ks, kt, ior }
    }

    /// Checks that every number is finite, the exponent is non-negative and
    /// the index of refraction is positive.
    pub fn validate(&self) -> Result<(), SceneError> {
        let all = [self.ka, self.kd, self.ks, self.shine, self.kr, self.kt, self.ior];
        if !self.color.is_finite() || all.iter().any(|v| !v.is_finite()) {
            return Err(SceneError::Geometry(GeometryError::NonFinite));
        }
        if self.shine < S::ZERO {
            return Err(SceneError::InvalidMaterial("negative Phong exponent"));
        }
        if !(self.ior > S::ZERO) {
            return Err(SceneError::InvalidMaterial("index of refraction must be positive"));
        }
        Ok(())
    }
}

/// A point light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light<S> {
    /// Position.
    pub position: Vec3<S>,
    /// Intensity per channel.
    pub color: Vec3<S>,
}

crate::num::bake::bake_struct!("raypack::scene::Light", Light<S> { position: Vec3<S>, color: Vec3<S> });

/// One primitive of a scene and its material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Primitive<S> {
    /// The geometry.
    pub shape: Shape<S>,
    /// Index into the scene's materials.
    pub material: u16,
}

crate::num::bake::bake_struct!("raypack::scene::Primitive", Primitive<S> { shape: Shape<S>, material: u16 });

/// Which fixed capacity of a scene was exceeded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CapacityKind {
    /// The number of primitives.
    Primitives,
    /// The vertex pool (polygon vertices, and patch normals).
    Vertices,
    /// The number of materials.
    Materials,
    /// The number of lights.
    Lights,
}

/// A scene capacity was too small: which one, its size, and the size the
/// insertion needed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CapacityError {
    /// The capacity that was exceeded.
    pub kind: CapacityKind,
    /// Its size.
    pub capacity: usize,
    /// The size needed to hold what did not fit.
    pub needed: usize,
}

impl CapacityKind {
    /// The name of one item, as messages say it.
    fn singular(self) -> &'static str {
        match self {
            CapacityKind::Primitives => "primitive",
            CapacityKind::Vertices => "vertex",
            CapacityKind::Materials => "material",
            CapacityKind::Lights => "light",
        }
    }
    /// The name of several items.
    fn plural(self) -> &'static str {
        match self {
            CapacityKind::Primitives => "primitives",
            CapacityKind::Vertices => "vertices",
            CapacityKind::Materials => "materials",
            CapacityKind::Lights => "lights",
        }
    }
}

impl core::fmt::Display for CapacityError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{} capacity {} exceeded (needs {})", self.kind.singular(), self.capacity, self.needed)
    }
}

/// Why something could not be added to a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneError {
    /// A capacity was exceeded.
    Capacity(CapacityError),
    /// The geometry is invalid.
    Geometry(GeometryError),
    /// A material index that the scene does not have.
    UnknownMaterial(u16),
    /// A material parameter is out of range.
    InvalidMaterial(&'static str),
    /// A coordinate is beyond what the scalar type represents safely
    /// (fixed point; see [`crate::geom::fixed_range`]).
    OutOfRange(RangeError),
    /// The allocator could not grow a list of a [`HeapScene`].
    OutOfMemory(MemoryError),
}

/// A heap scene's list could not grow: which one, and how many items it
/// needed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryError {
    /// The list that could not grow.
    pub kind: CapacityKind,
    /// The number of items it needed room for.
    pub needed: usize,
}

impl core::fmt::Display for MemoryError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "out of memory for {} {}", self.needed, self.kind.plural())
    }
}

impl core::error::Error for MemoryError {}

impl From<GeometryError> for SceneError {
    fn from(e: GeometryError) -> Self {
        SceneError::Geometry(e)
    }
}
impl From<RangeError> for SceneError {
    fn from(e: RangeError) -> Self {
        SceneError::OutOfRange(e)
    }
}

impl From<CapacityError> for SceneError {
    fn from(e: CapacityError) -> Self {
        SceneError::Capacity(e)
    }
}

impl core::error::Error for CapacityError {}
impl core::error::Error for SceneError {}

impl core::fmt::Display for SceneError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SceneError::Capacity(c) => c.fmt(f),
            SceneError::Geometry(g) => g.fmt(f),
            SceneError::UnknownMaterial(m) => write!(f, "unknown material {m}"),
            SceneError::InvalidMaterial(why) => write!(f, "invalid material: {why}"),
            SceneError::OutOfRange(r) => r.fmt(f),
            SceneError::OutOfMemory(m) => m.fmt(f),
        }
    }
}

/// Why an item did not fit a [`Pool`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoolFull {
    /// The pool's limit ([`Pool::LIMIT`]) is reached.
    Limit,
    /// The allocator could not grow the pool (heap pools only).
    Memory,
}

/// One list of a scene (primitives, vertices, materials or lights): a
/// growable array with a limit. Implemented by `heapless::Vec` (fixed
/// capacity, no allocator) and, with `std`, by `Vec` (grown on the heap,
/// with `try_reserve`: no abort when memory runs out).
pub trait Pool<T>: core::ops::Deref<Target = [T]> + core::ops::DerefMut + Clone {
    /// Most items the pool can hold.
    const LIMIT: usize;
    /// Appends `item`, or says why it did not fit (the pool unchanged).
    fn try_push(&mut self, item: T) -> Result<(), PoolFull>;
    /// Keeps the first `len` items.
    fn truncate_to(&mut self, len: usize);
}

impl<T: Clone, const N: usize> Pool<T> for HVec<T, N> {
    const LIMIT: usize = N;
    fn try_push(&mut self, item: T) -> Result<(), PoolFull> {
        self.push(item).map_err(|_| PoolFull::Limit)
    }
    fn truncate_to(&mut self, len: usize) {
        self.truncate(len)
    }
}

#[cfg(feature = "std")]
impl<T: Clone> Pool<T> for std::vec::Vec<T> {
    /// Items are indexed by `u32` (primitive ids, vertex indices).
    const LIMIT: usize = u32::MAX as usize;
    fn try_push(&mut self, item: T) -> Result<(), PoolFull> {
        if self.len() >= Self::LIMIT {
            return Err(PoolFull::Limit);
        }
        // `try_reserve` grows geometrically, as `push` does, but reports a
        // failed allocation instead of aborting the process.
        self.try_reserve(1).map_err(|_| PoolFull::Memory)?;
        self.push(item);
        Ok(())
    }
    fn truncate_to(&mut self, len: usize) {
        self.truncate(len)
    }
}

/// Where a [`SceneStore`] keeps its four lists: [`Fixed`] capacities (the
/// core, firmware) or, with `std`, [`Heap`] (as large as memory).
pub trait Storage<S> {
    /// The primitives.
    type Prims: Pool<Primitive<S>>;
    /// The vertex pool.
    type Verts: Pool<Vec3<S>>;
    /// The materials.
    type Materials: Pool<Material<S>>;
    /// The lights.
    type Lights: Pool<Light<S>>;
}

/// Fixed capacities: `P` primitives, `V` pool vertices, `M` materials and
/// `L` lights, in the scene value itself (no allocator).
#[derive(Clone, Copy, Debug)]
pub struct Fixed<const P: usize, const V: usize, const M: usize, const L: usize>;

impl<S: Copy, const P: usize, const V: usize, const M: usize, const L: usize> Storage<S> for Fixed<P, V, M, L> {
    type Prims = HVec<Primitive<S>, P>;
    type Verts = HVec<Vec3<S>, V>;
    type Materials = HVec<Material<S>, M>;
    type Lights = HVec<Light<S>, L>;
}

/// Heap storage (`std`): lists that grow as needed, up to `u32` indices or
/// the memory there is (an [`SceneError::OutOfMemory`], not an abort).
#[cfg(feature = "std")]
#[derive(Clone, Copy, Debug)]
pub struct Heap;

#[cfg(feature = "std")]
impl<S: Copy> Storage<S> for Heap {
    type Prims = std::vec::Vec<Primitive<S>>;
    type Verts = std::vec::Vec<Vec3<S>>;
    type Materials = std::vec::Vec<Material<S>>;
    type Lights = std::vec::Vec<Light<S>>;
}

/// A scene with room for `P` primitives, `V` pool vertices, `M` materials and
/// `L` lights, in fixed memory.
pub type Scene<S, const P: usize, const V: usize, const M: usize = 64, const L: usize = 16> =
    SceneStore<S, Fixed<P, V, M, L>>;

/// A scene on the heap (`std`), as large as memory: the same builder and the
/// same [`SceneView`] as [`Scene`].
#[cfg(feature = "std")]
pub type HeapScene<S> = SceneStore<S, Heap>;

/// A scene's primitives, vertex pool, materials and lights, stored as
/// `St` says ([`Scene`]: fixed capacities; [`HeapScene`]: the heap). Built
/// with `add_*`, traced through [`SceneStore::view`].
pub struct SceneStore<S, St: Storage<S>> {
    prims: St::Prims,
    verts: St::Verts,
    materials: St::Materials,
    lights: St::Lights,
    background: Vec3<S>,
    degenerate_polygons: u32,
}

impl<S: Copy, St: Storage<S>> Clone for SceneStore<S, St> {
    fn clone(&self) -> Self {
        SceneStore {
            prims: self.prims.clone(),
            verts: self.verts.clone(),
            materials: self.materials.clone(),
            lights: self.lights.clone(),
            background: self.background,
            degenerate_polygons: self.degenerate_polygons,
        }
    }
}

impl<S: Scalar, const P: usize, const V: usize, const M: usize, const L: usize> Default for Scene<S, P, V, M, L> {
    fn default() -> Self {
        Self::new()
    }
}

impl<S: Scalar, const P: usize, const V: usize, const M: usize, const L: usize> Scene<S, P, V, M, L> {
    /// An empty scene with a black background.
    pub const fn new() -> Self {
        SceneStore {
            prims: HVec::new(),
            verts: HVec::new(),
            materials: HVec::new(),
            lights: HVec::new(),
            background: Vec3::new(S::ZERO, S::ZERO, S::ZERO),
            degenerate_polygons: 0,
        }
    }

    /// Empties the scene in place (as [`Scene::new`], without building a
    /// new value: a scene in a `static`, megabytes for large capacities,
    /// is reused without a copy on the stack).
    pub fn clear(&mut self) {
        self.prims.clear();
        self.verts.clear();
        self.materials.clear();
        self.lights.clear();
        self.background = Vec3::new(S::ZERO, S::ZERO, S::ZERO);
        self.degenerate_polygons = 0;
    }
}

#[cfg(feature = "std")]
impl<S: Scalar> Default for HeapScene<S> {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(feature = "std")]
impl<S: Scalar> HeapScene<S> {
    /// An empty scene with a black background.
    pub fn new() -> Self {
        SceneStore {
            prims: std::vec::Vec::new(),
            verts: std::vec::Vec::new(),
            materials: std::vec::Vec::new(),
            lights: std::vec::Vec::new(),
            background: Vec3::new(S::ZERO, S::ZERO, S::ZERO),
            degenerate_polygons: 0,
        }
    }

    /// Bytes of heap the scene holds (its lists' capacities).
    pub fn heap_bytes(&self) -> usize {
        use core::mem::size_of;
        self.prims.capacity() * size_of::<Primitive<S>>()
            + self.verts.capacity() * size_of::<Vec3<S>>()
            + self.materials.capacity() * size_of::<Material<S>>()
            + self.lights.capacity() * size_of::<Light<S>>()
    }
}

/// Pushes `item` onto `pool`, or says which list did not fit and how many
/// items it needed.
fn push<T, P: Pool<T>>(pool: &mut P, item: T, kind: CapacityKind) -> Result<(), SceneError> {
    let needed = pool.len().saturating_add(1);
    pool.try_push(item).map_err(|why| match why {
        PoolFull::Limit => full(kind, P::LIMIT, needed),
        PoolFull::Memory => SceneError::OutOfMemory(MemoryError { kind, needed }),
    })
}

fn full(kind: CapacityKind, capacity: usize, needed: usize) -> SceneError {
    SceneError::Capacity(CapacityError { kind, capacity, needed })
}

impl<S: Scalar, St: Storage<S>> SceneStore<S, St> {
    /// Sets the colour seen by rays that hit nothing.
    pub fn set_background(&mut self, color: Vec3<S>) -> Result<(), SceneError> {
        if !color.is_finite() {
            return Err(GeometryError::NonFinite.into());
        }
        self.background = color;
        Ok(())
    }

    /// Adds a material and returns its index.
    pub fn add_material(&mut self, m: Material<S>) -> Result<u16, SceneError> {
        m.validate()?;
        let id = self.materials.len();
        if id > u16::MAX as usize {
            return Err(full(CapacityKind::Materials, u16::MAX as usize + 1, id.saturating_add(1)));
        }
        push(&mut self.materials, m, CapacityKind::Materials)?;
        Ok(id as u16)
    }

    /// Adds a point light.
    pub fn add_light(&mut self, position: Vec3<S>, color: Vec3<S>) -> Result<(), SceneError> {
        if !position.is_finite() || !color.is_finite() {
            return Err(GeometryError::NonFinite.into());
        }
        let n = self.lights.len();
        fixed_range::check_point(position, RangeItem::Light(n as u32))?;
        push(&mut self.lights, Light { position, color }, CapacityKind::Lights)
    }

    /// Adds a primitive with material `material` and returns its index
    /// (primitive indices are insertion order).
    pub fn add_shape(&mut self, shape: Shape<S>, material: u16) -> Result<u32, SceneError> {
        if material as usize >= self.materials.len() {
            return Err(SceneError::UnknownMaterial(material));
        }
        let id = self.prims.len();
        fixed_range::check_shape(&shape, &self.verts, id as u32)?;
        push(&mut self.prims, Primitive { shape, material }, CapacityKind::Primitives)?;
        if let Shape::Polygon(p) = shape {
            if p.is_degenerate() {
                self.degenerate_polygons = self.degenerate_polygons.saturating_add(1);
            }
        }
        Ok(id as u32)
    }

    /// Adds a sphere.
    pub fn add_sphere(&mut self, center: Vec3<S>, radius: S, material: u16) -> Result<u32, SceneError> {
        self.add_shape(Shape::Sphere(Sphere::new(center, radius)?), material)
    }
    /// Adds an infinite plane `Ax + By + Cz + D = 0`.
    pub fn add_plane(&mut self, a: S, b: S, c: S, d: S, material: u16) -> Result<u32, SceneError> {
        self.add_shape(Shape::Plane(Plane::from_coefficients(a, b, c, d)?), material)
    }
    /// Adds an axis-aligned box between two opposite corners.
    pub fn add_box(&mut self, a: Vec3<S>, b: Vec3<S>, material: u16) -> Result<u32, SceneError> {
        self.add_shape(Shape::AaBox(AaBox::new(a, b)?), material)
    }
    /// Adds an oriented box.
    pub fn add_oriented_box(
        &mut self,
        center: Vec3<S>,
        half: Vec3<S>,
        u: Vec3<S>,
        v: Vec3<S>,
        material: u16,
    ) -> Result<u32, SceneError> {
        self.add_shape(Shape::OrientedBox(OrientedBox::new(center, half, u, v)?), material)
    }
    /// Adds a quadric (see [`Quadric`] for the named constructors).
    pub fn add_quadric(&mut self, q: Quadric<S>, material: u16) -> Result<u32, SceneError> {
        self.add_shape(Shape::Quadric(q), material)
    }
    /// Adds a finite open cone or cylinder.
    pub fn add_cone(
        &mut self,
        base: Vec3<S>,
        base_radius: S,
        apex: Vec3<S>,
        apex_radius: S,
        material: u16,
    ) -> Result<u32, SceneError> {
        self.add_shape(Shape::Cone(Cone::new(base, base_radius, apex, apex_radius)?), material)
    }

    /// Appends one vertex to the pool and returns its index. With
    /// [`Self::add_polygon_from_pool`] this lets a reader stream vertices
    /// without a buffer of its own.
    pub fn push_vertex(&mut self, v: Vec3<S>) -> Result<u32, SceneError> {
        let n = self.verts.len();
        push(&mut self.verts, v, CapacityKind::Vertices)?;
        Ok(n as u32)
    }

    /// Appends `vertices` to the pool and returns the index of the first;
    /// if one does not fit (a heap pool out of memory), none stays.
    fn push_vertices(&mut self, vertices: impl Iterator<Item = Vec3<S>>) -> Result<u32, SceneError> {
        let first = self.verts.len();
        for v in vertices {
            if let Err(e) = self.push_vertex(v) {
                self.verts.truncate_to(first);
                return Err(e);
            }
        }
        Ok(first as u32)
    }

    /// Removes the vertices from index `len` on (what a reader streamed
    /// for a polygon it could not complete).
    pub(crate) fn truncate_vertices(&mut self, len: usize) {
        self.verts.truncate_to(len);
    }

    /// Number of vertices in the pool.
    pub fn vertex_count(&self) -> usize {
        self.verts.len()
    }

    /// Adds a polygon over the last pushed vertices `first .. first + count`
    /// (a patch: `count` positions followed by `count` unit normals).
    /// On error the vertices from `first` on are removed again.
    pub fn add_polygon_from_pool(
        &mut self,
        first: u32,
        count: u32,
        patch: bool,
        material: u16,
    ) -> Result<u32, SceneError> {
        let result = Polygon::from_pool(&self.verts, first, count, patch)
            .map_err(SceneError::from)
            .and_then(|p| self.add_shape(Shape::Polygon(p), material));
        if result.is_err() {
            self.verts.truncate_to(first as usize);
        }
        result
    }

    fn check_vertex_room(&self, n: usize) -> Result<(), SceneError> {
        let needed = self.verts.len().saturating_add(n);
        let (v, p) = (St::Verts::LIMIT, St::Prims::LIMIT);
        if needed > v {
            return Err(full(CapacityKind::Vertices, v, needed));
        }
        if self.prims.len() >= p {
            return Err(full(CapacityKind::Primitives, p, self.prims.len().saturating_add(1)));
        }
        Ok(())
    }

    /// Adds a planar polygon (vertices counter-clockwise seen from the front).
    pub fn add_polygon(&mut self, vertices: &[Vec3<S>], material: u16) -> Result<u32, SceneError> {
        if vertices.len() < 3 {
            return Err(GeometryError::TooFewVertices(vertices.len() as u32).into());
        }
        self.check_vertex_room(vertices.len())?;
        let first = self.push_vertices(vertices.iter().copied())?;
        self.add_polygon_from_pool(first, vertices.len() as u32, false, material)
    }

    /// Adds a polygon patch: vertices and one normal per vertex (normalized
    /// here; a zero-length normal is an error).
    pub fn add_patch(&mut self, vertices: &[Vec3<S>], normals: &[Vec3<S>], material: u16) -> Result<u32, SceneError> {
        if vertices.len() < 3 {
            return Err(GeometryError::TooFewVertices(vertices.len() as u32).into());
        }
        if normals.len() != vertices.len() {
            return Err(GeometryError::VertexRange.into());
        }
        self.check_vertex_room(vertices.len().saturating_mul(2))?;
        let mut unit = [Vec3::ZERO; 1];
        for n in normals {
            unit[0] = n.normalize_or_zero();
            if unit[0] == Vec3::ZERO {
                return Err(if n.is_finite() { GeometryError::ZeroLengthAxis } else { GeometryError::NonFinite }.into());
            }
        }
        let first =
            self.push_vertices(vertices.iter().copied().chain(normals.iter().map(|n| n.normalize_or_zero())))?;
        self.add_polygon_from_pool(first, vertices.len() as u32, true, material)
    }

    /// Appends everything `src` holds (of any scalar) in the frame of `sim`
    /// and converted to this scene's scalar: its materials, lights and
    /// primitives (in order, so primitive `k` of `src` becomes primitive
    /// `len() + k` here), its vertex pool, and its background. Every
    /// transform is computed in `f32` before the conversion (see
    /// [`crate::geom::uniform_scale`]): how a scene for a limited-range scalar is
    /// made from one described in any units. Errors as `add_*` (capacity,
    /// range); on error the scene holds what was added before it.
    pub fn add_similar<S0: Scalar>(&mut self, src: &SceneView<'_, S0>, sim: &Similarity) -> Result<(), SceneError> {
        let [r, g, b] = src.background().to_f32();
        self.set_background(Vec3::from_f32(r, g, b))?;
        let first_material = self.materials.len();
        for m in src.materials() {
            let f = |v: S0| S::from_f32(v.to_f32());
            let [r, g, b] = m.color.to_f32();
            let color = Vec3::from_f32(r, g, b);
            self.add_material(Material {
                color,
                ka: f(m.ka),
                kd: f(m.kd),
                ks: f(m.ks),
                shine: f(m.shine),
                kr: f(m.kr),
                kt: f(m.kt),
                ior: f(m.ior),
            })?;
        }
        // The pool in order: positions by `sim`, then each patch's normals
        // (the second half of its slots) as directions.
        let first_vertex = self.verts.len();
        for &v in src.vertices() {
            self.push_vertex(sim.point(v))?;
        }
        for p in src.primitives() {
            if let Shape::Polygon(pg) = &p.shape {
                if pg.is_patch() {
                    let (first, count) = (pg.first_vertex() as usize, pg.vertex_count() as usize);
                    for i in first.saturating_add(count)..first.saturating_add(2 * count) {
                        if let (Some(n), Some(slot)) =
                            (src.vertices().get(i), self.verts.get_mut(first_vertex.saturating_add(i)))
                        {
                            *slot = sim.direction(*n);
                        }
                    }
                }
            }
        }
        for p in src.primitives() {
            let shape = match p.shape.similar::<S>(sim) {
                Shape::Polygon(pg) => Shape::Polygon(
                    pg.at_first(pg.first_vertex().saturating_add(first_vertex as u32)).with_edge_blocks(&self.verts),
                ),
                other => other,
            };
            let material = u16::try_from(p.material as usize + first_material)
                .map_err(|_| SceneError::UnknownMaterial(p.material))?;
            self.add_shape(shape, material)?;
        }
        for l in src.lights() {
            let [r, g, b] = l.color.to_f32();
            self.add_light(sim.point(l.position), Vec3::from_f32(r, g, b))?;
        }
        Ok(())
    }

    /// Appends `described` (a scene built in `f32`, in whatever units it was
    /// written) in the frame this scene's scalar traces in, and returns
    /// that frame: for a scalar with [`Scalar::SCENE_FRAME`] `half`, the box
    /// around `described`'s bounded primitives and `eye` centred on the
    /// origin, its largest half-extent scaled to `half`
    /// ([`SceneView::fitting_frame`]); the identity for every other scalar.
    /// Errors as [`Self::add_similar`].
    pub fn add_in_frame(
        &mut self,
        described: &SceneView<'_, f32>,
        eye: Option<Vec3<f32>>,
    ) -> Result<Similarity, SceneError> {
        let frame = match S::SCENE_FRAME {
            Some(half) => described.fitting_frame(eye, half),
            None => Similarity::IDENTITY,
        };
        self.add_similar(described, &frame)?;
        Ok(frame)
    }

    /// Number of zero-area polygons (kept, never hit), so a reader can warn.
    pub fn degenerate_polygons(&self) -> u32 {
        self.degenerate_polygons
    }

    /// Number of primitives.
    pub fn len(&self) -> usize {
        self.prims.len()
    }
    /// Whether the scene has no primitives.
    pub fn is_empty(&self) -> bool {
        self.prims.is_empty()
    }

    /// The scene as slices, for tracing.
    pub fn view(&self) -> SceneView<'_, S> {
        SceneView {
            prims: &self.prims,
            verts: &self.verts,
            materials: &self.materials,
            lights: &self.lights,
            background: self.background,
        }
    }
}

/// A read-only scene made of slices: what the tracer works on.
#[derive(Clone, Copy, Debug)]
pub struct SceneView<'a, S> {
    prims: &'a [Primitive<S>],
    verts: &'a [Vec3<S>],
    materials: &'a [Material<S>],
    lights: &'a [Light<S>],
    background: Vec3<S>,
}

/// The material used where a primitive names a material the view lacks
/// (impossible for views made by [`Scene::view`] or [`SceneView::new`]).
fn fallback_material<S: Scalar>() -> Material<S> {
    Material::diffuse(Vec3::new(S::ONE, S::ONE, S::ONE))
}

impl<'a, S: Scalar> SceneView<'a, S> {
    /// A view over caller-provided slices (for example `static` data in
    /// flash), checked: every material index must exist and every polygon
    /// must lie inside `verts`.
    pub fn new(
        prims: &'a [Primitive<S>],
        verts: &'a [Vec3<S>],
        materials: &'a [Material<S>],
        lights: &'a [Light<S>],
        background: Vec3<S>,
    ) -> Result<Self, SceneError> {
        for p in prims {
            if p.material as usize >= materials.len() {
                return Err(SceneError::UnknownMaterial(p.material));
            }
            if let Shape::Polygon(poly) = &p.shape {
                // Saturating: a polygon from `from_baked` may hold any counts.
                let slots = (poly.vertex_count() as usize).saturating_mul(if poly.is_patch() { 2 } else { 1 });
                if (poly.first_vertex() as usize).saturating_add(slots) > verts.len() {
                    return Err(GeometryError::VertexRange.into());
                }
            }
        }
        for m in materials {
            m.validate()?;
        }
        Ok(SceneView { prims, verts, materials, lights, background })
    }

    /// The primitives, in index order.
    pub fn primitives(&self) -> &'a [Primitive<S>] {
        self.prims
    }
    /// The vertex pool.
    pub fn vertices(&self) -> &'a [Vec3<S>] {
        self.verts
    }
    /// The materials.
    pub fn materials(&self) -> &'a [Material<S>] {
        self.materials
    }
    /// The lights.
    pub fn lights(&self) -> &'a [Light<S>] {
        self.lights
    }
    /// The background colour.
    pub fn background(&self) -> Vec3<S> {
        self.background
    }
    /// The material of primitive `prim`.
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn material_of(&self, prim: u32) -> Material<S> {
        self.prims
            .get(prim as usize)
            .and_then(|p| self.materials.get(p.material as usize))
            .copied()
            .unwrap_or_else(fallback_material)
    }
    /// Number of primitives of each kind.
    pub fn count(&self, kind: ShapeKind) -> usize {
        self.prims.iter().filter(|p| p.shape.kind() == kind).count()
    }
    /// Bounds of all bounded primitives, or `None` if there are none.
    pub fn bounds(&self) -> Option<(Vec3<S>, Vec3<S>)> {
        self.prims
            .iter()
            .filter_map(|p| p.shape.bounds(self.verts))
            .reduce(|(a, b), (c, d)| (a.min_elem(c), b.max_elem(d)))
    }

    /// The frame a limited-range scalar traces this scene in
    /// ([`Scalar::SCENE_FRAME`] gives `half`): the box around the bounded
    /// primitives and `eye`, centred on the origin, its largest half-extent
    /// scaled to `half`. Lights and unbounded primitives may lie outside.
    pub fn fitting_frame(&self, eye: Option<Vec3<S>>, half: f32) -> Similarity {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        let mut grow = |p: [f32; 3]| {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        };
        if let Some((a, b)) = self.bounds() {
            grow(a.to_f32());
            grow(b.to_f32());
        }
        if let Some(e) = eye {
            grow(e.to_f32());
        }
        Similarity::fitting(lo, hi, half)
    }

    /// The transmission weight `Kt` of material `m` (0, opaque, for a
    /// material the view lacks).
    #[cfg_attr(all(not(debug_assertions), any(target_arch = "x86", target_arch = "x86_64")), inline(always))]
    pub fn kt_of_material(&self, m: u16) -> S {
        self.materials.get(m as usize).map_or(S::ZERO, |m| m.kt)
    }

    /// The whole-scene range check for limited-range scalars (fixed point),
    /// for rays starting at `eye` (the camera's): every coordinate (eye and
    /// primitives) within [`Scalar::COORDINATE_LIMIT`], lights within
    /// [`Scalar::LIGHT_LIMIT`], and every quadric's and cone's intersection
    /// intermediates within [`Scalar::INTERMEDIATE_LIMIT`] for ray origins
    /// anywhere in the scene's extent `R` (the largest coordinate magnitude
    /// of the eye and the primitives, at least 1; see
    /// [`fixed_range::intermediate_bound`]). Returns `R`; always `Ok` for
    /// `f32`. `Scene::add_*` already checks each item's coordinates; this
    /// adds what depends on the whole scene.
    pub fn check_range(&self, eye: Vec3<S>) -> Result<f32, RangeError> {
        if !S::LIMITED_RANGE {
            return Ok(f32::MAX);
        }
        fixed_range::check_point(eye, RangeItem::Camera)?;
        let mut extent = fixed_range::magnitude(eye);
        // Lights are checked, but are no ray origins: they do not widen the
        // extent the intermediates are bounded for.
        for (k, light) in (0u32..).zip(self.lights.iter()) {
            fixed_range::check_point(light.position, RangeItem::Light(k))?;
        }
        for (k, p) in (0u32..).zip(self.prims.iter()) {
            fixed_range::check_shape(&p.shape, self.verts, k)?;
            if let Some(m) = fixed_range::shape_extent(&p.shape, self.verts) {
                extent = extent.max(m);
            }
        }
        let r = extent.max(1.0);
        for (k, p) in (0u32..).zip(self.prims.iter()) {
            fixed_range::check_intermediates(&p.shape, r, k)?;
        }
        Ok(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Small = Scene<f32, 4, 8, 2, 1>;

    #[test]
    fn capacity_errors_say_what_did_not_fit() {
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        s.add_material(Material::diffuse(Vec3::new(1.0, 0.0, 0.0))).unwrap();
        assert_eq!(
            s.add_material(Material::diffuse(Vec3::ZERO)),
            Err(SceneError::Capacity(CapacityError { kind: CapacityKind::Materials, capacity: 2, needed: 3 }))
        );
        for i in 0..4 {
            s.add_sphere(Vec3::new(i as f32, 0.0, 0.0), 1.0, m).unwrap();
        }
        assert_eq!(
            s.add_sphere(Vec3::ZERO, 1.0, m),
            Err(SceneError::Capacity(CapacityError { kind: CapacityKind::Primitives, capacity: 4, needed: 5 }))
        );
        s.add_light(Vec3::ZERO, Vec3::new(1.0, 1.0, 1.0)).unwrap();
        assert_eq!(
            s.add_light(Vec3::ZERO, Vec3::new(1.0, 1.0, 1.0)),
            Err(SceneError::Capacity(CapacityError { kind: CapacityKind::Lights, capacity: 1, needed: 2 }))
        );
    }

    #[test]
    fn clear_empties_the_scene_for_reuse() {
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        let tri = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        s.add_polygon(&tri, m).unwrap();
        s.add_polygon(&[Vec3::ZERO, Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0)], m).unwrap();
        s.add_light(Vec3::ZERO, Vec3::new(1.0, 1.0, 1.0)).unwrap();
        s.set_background(Vec3::new(0.5, 0.5, 0.5)).unwrap();
        assert_eq!((s.len(), s.degenerate_polygons()), (2, 1));
        s.clear();
        let v = s.view();
        assert_eq!((s.len(), s.vertex_count(), s.degenerate_polygons()), (0, 0, 0));
        assert_eq!((v.materials().len(), v.lights().len(), v.background()), (0, 0, Vec3::ZERO));
        // The whole capacity is free again.
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        assert_eq!(m, 0);
        s.add_polygon(&tri, m).unwrap();
        s.add_polygon(&tri, m).unwrap();
        assert_eq!(s.vertex_count(), 6);
    }

    #[test]
    fn vertex_pool_overflow_is_reported_and_rolled_back() {
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        let tri = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        s.add_polygon(&tri, m).unwrap();
        s.add_polygon(&tri, m).unwrap();
        assert_eq!(
            s.add_polygon(&tri, m),
            Err(SceneError::Capacity(CapacityError { kind: CapacityKind::Vertices, capacity: 8, needed: 9 }))
        );
        assert_eq!(s.vertex_count(), 6);
        assert_eq!(s.len(), 2);
    }

    #[test]
    fn invalid_input_is_an_error_not_a_panic() {
        let mut s = Small::new();
        assert_eq!(s.add_sphere(Vec3::ZERO, 1.0, 0), Err(SceneError::UnknownMaterial(0)));
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        assert_eq!(s.add_sphere(Vec3::ZERO, 0.0, m), Err(SceneError::Geometry(GeometryError::NonPositiveRadius)));
        assert_eq!(
            s.add_polygon(&[Vec3::ZERO, Vec3::ZERO], m),
            Err(SceneError::Geometry(GeometryError::TooFewVertices(2)))
        );
        let tri = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        assert_eq!(
            s.add_patch(&tri, &[Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0)], m),
            Err(SceneError::Geometry(GeometryError::ZeroLengthAxis))
        );
        let mut bad = Material::diffuse(Vec3::new(1.0, 1.0, 1.0));
        bad.ior = 0.0;
        assert!(matches!(s.add_material(bad), Err(SceneError::InvalidMaterial(_))));
        bad.ior = f32::NAN;
        assert_eq!(s.add_material(bad), Err(SceneError::Geometry(GeometryError::NonFinite)));
    }

    #[test]
    fn degenerate_polygons_are_counted_and_keep_indices() {
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        let line = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0)];
        assert_eq!(s.add_polygon(&line, m), Ok(0));
        assert_eq!(s.add_sphere(Vec3::ZERO, 1.0, m), Ok(1));
        assert_eq!(s.degenerate_polygons(), 1);
    }

    /// A pool that fails as a heap pool does when the allocator refuses
    /// to grow it: after 3 items.
    #[derive(Clone)]
    struct Starved<T>(HVec<T, 3>);

    impl<T> core::ops::Deref for Starved<T> {
        type Target = [T];
        fn deref(&self) -> &[T] {
            &self.0
        }
    }
    impl<T> core::ops::DerefMut for Starved<T> {
        fn deref_mut(&mut self) -> &mut [T] {
            &mut self.0
        }
    }
    impl<T: Clone> Pool<T> for Starved<T> {
        const LIMIT: usize = u32::MAX as usize;
        fn try_push(&mut self, item: T) -> Result<(), PoolFull> {
            self.0.push(item).map_err(|_| PoolFull::Memory)
        }
        fn truncate_to(&mut self, len: usize) {
            self.0.truncate(len)
        }
    }

    struct StarvedStorage;
    impl<S: Copy> Storage<S> for StarvedStorage {
        type Prims = Starved<Primitive<S>>;
        type Verts = Starved<Vec3<S>>;
        type Materials = HVec<Material<S>, 4>;
        type Lights = HVec<Light<S>, 4>;
    }

    fn starved() -> SceneStore<f32, StarvedStorage> {
        SceneStore {
            prims: Starved(HVec::new()),
            verts: Starved(HVec::new()),
            materials: HVec::new(),
            lights: HVec::new(),
            background: Vec3::ZERO,
            degenerate_polygons: 0,
        }
    }

    #[test]
    fn memory_that_runs_out_is_an_error_that_says_which_list() {
        extern crate std;
        use std::string::ToString;
        let mut s = starved();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        for i in 0..3 {
            s.add_sphere(Vec3::new(i as f32, 0.0, 0.0), 1.0, m).unwrap();
        }
        let e = s.add_sphere(Vec3::ZERO, 1.0, m).unwrap_err();
        assert_eq!(e, SceneError::OutOfMemory(MemoryError { kind: CapacityKind::Primitives, needed: 4 }));
        assert_eq!(e.to_string(), "out of memory for 4 primitives");
        assert_eq!(s.len(), 3);
        // A polygon whose vertices do not fit leaves nothing behind.
        let mut s = starved();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 1.0, 1.0))).unwrap();
        let quad = [Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let e = s.add_polygon(&quad, m).unwrap_err();
        assert_eq!(e, SceneError::OutOfMemory(MemoryError { kind: CapacityKind::Vertices, needed: 4 }));
        assert_eq!((s.len(), s.vertex_count()), (0, 0));
        // The reader reports it on the line of the entity that did not fit.
        let mut s = starved();
        let text = "f 1 1 1 1 0 0 0 1\ns 0 0 0 1\ns 1 0 0 1\ns 2 0 0 1\ns 3 0 0 1\n";
        let e = crate::scene::nff::parse(text, &mut s).unwrap_err();
        assert_eq!(e.to_string(), "line 5, column 1: scene too large: out of memory for 4 primitives");
        // ... and takes back the vertices of a polygon that did not fit.
        let mut s = starved();
        let text = "f 1 1 1 1 0 0 0 1\np 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
        let e = crate::scene::nff::parse(text, &mut s).unwrap_err();
        assert_eq!(e.to_string(), "line 2, column 1: scene too large: out of memory for 4 vertices");
        assert_eq!((s.len(), s.vertex_count()), (0, 0));
    }

    #[test]
    fn a_similar_scene_is_the_same_scene_scaled() {
        let mut s = Small::new();
        let m = s.add_material(Material::diffuse(Vec3::new(1.0, 0.5, 0.25))).unwrap();
        s.add_sphere(Vec3::new(10.0, 0.0, 0.0), 2.0, m).unwrap();
        s.add_patch(
            &[Vec3::new(0.0, 0.0, 0.0), Vec3::new(4.0, 0.0, 0.0), Vec3::new(0.0, 4.0, 0.0)],
            &[Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.6, 0.8)],
            m,
        )
        .unwrap();
        s.add_light(Vec3::new(0.0, 0.0, 20.0), Vec3::new(1.0, 1.0, 1.0)).unwrap();
        let sim = Similarity { origin: [2.0, 0.0, 0.0], scale: 0.5 };
        let mut t = Small::new();
        t.add_similar(&s.view(), &sim).unwrap();
        let v = t.view();
        assert_eq!(v.materials(), s.view().materials());
        match v.primitives()[0].shape {
            Shape::Sphere(sp) => assert_eq!((sp.center(), sp.radius()), (Vec3::new(4.0, 0.0, 0.0), 1.0)),
            _ => panic!(),
        }
        // Positions move, the patch's normals do not.
        assert_eq!(
            &v.vertices()[..3],
            &[Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(-1.0, 2.0, 0.0)]
        );
        assert_eq!(&v.vertices()[3..], &s.view().vertices()[3..]);
        assert_eq!(v.lights()[0].position, Vec3::new(-1.0, 0.0, 10.0));
    }
}
