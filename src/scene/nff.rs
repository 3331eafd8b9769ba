//! The NFF scene reader: `&str` in, a scene out ([`SceneStore`]: a
//! fixed-capacity `Scene` without an allocator, or with `std` a `HeapScene`).
//!
//! NFF (Neutral File Format, Eric Haines, 1988) is the text format of the
//! Standard Procedural Databases. One entity per line, fields separated by
//! white space, `#` starts a comment to the end of the line, blank lines are
//! ignored:
//!
//! | entity | lines | meaning |
//! | --- | --- | --- |
//! | `v` | `v`, then `from x y z`, `at x y z`, `up x y z`, `angle deg`, `hither d`, `resolution w h`, in this order | pinhole camera (`angle` is the full vertical field of view) |
//! | `b r g b` | 1 | background colour |
//! | `l x y z [r g b]` | 1 | point light; without a colour, `1/sqrt(number of lights)` per channel |
//! | `f r g b Kd Ks Shine T ior` | 1 | material of the following objects (`Ka = 0`, `Kr = Ks`) |
//! | `s cx cy cz r` | 1 | sphere |
//! | `c` | `c bx by bz br ax ay az ar`, or `c` then `bx by bz br` and `ax ay az ar` on two lines | open cone or cylinder |
//! | `p n` | 1 + n (`x y z` per line) | polygon |
//! | `pp n` | 1 + n (`x y z nx ny nz` per line) | polygon patch |
//!
//! and raypack's extensions:
//!
//! | entity | meaning |
//! | --- | --- |
//! | `pl A B C D` | plane `Ax + By + Cz + D = 0` |
//! | `box x0 y0 z0 x1 y1 z1` | axis-aligned box |
//! | `obox cx cy cz hx hy hz ux uy uz vx vy vz` | oriented box |
//! | `q A B C D E F G H I J [x0 y0 z0 x1 y1 z1]` | quadric, optionally clipped to a box |
//! | `fx r g b Ka Kd Ks Shine Kr Kt ior` | extended material |
//!
//! Every primitive entity (`s`, `p`, `pp`, `c`, `pl`, `box`, `obox`, `q`)
//! becomes exactly one primitive, in file order, so primitive `k` of the
//! scene is the `k`-th primitive entity of the file (zero-area polygons
//! included: they are kept and never hit, see
//! [`SceneStore::degenerate_polygons`]).
//!
//! Reading rules beyond the format:
//! - Numbers are parsed as `f32` (correctly rounded) and converted to the
//!   scene's scalar; NaN, infinities and values too large for `f32` are
//!   errors.
//! - The SPD files write `ior = 0` for opaque materials; the index of
//!   refraction matters only when `T > 0` (`Kt > 0` for `fx`), so a
//!   non-positive index with no transmission is stored as 1. With
//!   transmission it is an error.
//! - An object before any `f`/`fx` line is an error (there is no implicit
//!   material), as is a second `v` block.
//!
//! Errors are values ([`NffError`]): the line and column (1-based, in
//! characters) of the offending field and what was expected. The reader never
//! panics and never skips input. When a scene capacity is too small, the rest
//! of the file is counted (see [`scan`]) so the error says how much the whole
//! file needs.
//!
//! ```
//! use raypack::nff;
//! use raypack::prelude::*;
//!
//! let text = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.01\nresolution 64 48\n\
//!             l 5 5 5\nf 1 0 0 1 0 0 0 1\ns 0 0 0 1\n";
//! let needs = nff::scan(text).unwrap().counts;
//! assert_eq!((needs.primitives(), needs.lights), (1, 1));
//! let mut scene: Scene<f32, 4, 16> = Scene::new();
//! let info = nff::parse(text, &mut scene).unwrap();
//! assert_eq!(info.camera.unwrap().width, 64);
//!
//! let mut small: Scene<f32, 4, 16> = Scene::new();
//! let err = nff::parse("f 1 1 1 1 0 0 0 1\ns 0 0 0 one\n", &mut small).unwrap_err();
//! assert_eq!((err.line, err.column), (2, 9));
//! assert_eq!(err.to_string(), "line 2, column 9: expected a number, found `one`");
//! ```

use crate::geom::camera::{Camera, CameraError};
use crate::geom::primitives::{AaBox, Cone, GeometryError, OrientedBox, Plane, Quadric, Shape, Sphere};
use crate::geom::vec3::Vec3;
use crate::num::scalar::Scalar;
use crate::scene::{CapacityError, CapacityKind, Material, MemoryError, Pool, SceneError, SceneStore, Storage};

/// A short copy of an offending piece of input (up to 24 bytes, cut at a
/// character boundary), so errors can quote it without borrowing the text.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Token {
    bytes: [u8; 24],
    len: u8,
    truncated: bool,
}

impl Token {
    /// A copy of `s`, shortened to at most 24 bytes.
    pub fn new(s: &str) -> Self {
        let mut end = s.len().min(24);
        while !s.is_char_boundary(end) {
            end -= 1;
        }
        let mut bytes = [0u8; 24];
        // (`get` and a zip: no index can fail, so no panic path.)
        for (d, b) in bytes.iter_mut().zip(s.as_bytes().get(..end).unwrap_or(&[])) {
            *d = *b;
        }
        Token { bytes, len: end as u8, truncated: end < s.len() }
    }

    /// The (possibly shortened) text.
    pub fn as_str(&self) -> &str {
        // The bytes are a prefix of a `str` cut at a character boundary.
        core::str::from_utf8(self.bytes.get(..self.len as usize).unwrap_or(&[])).unwrap_or("")
    }
}

impl core::fmt::Display for Token {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())?;
        if self.truncated {
            f.write_str("…")?;
        }
        Ok(())
    }
}

impl core::fmt::Debug for Token {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{:?}", self.as_str())
    }
}

/// What is wrong with an NFF file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NffErrorKind {
    /// A line starts with a word that is not an NFF entity.
    UnknownEntity(Token),
    /// A line has the wrong number of fields.
    FieldCount {
        /// The entity (or continuation line) being read, e.g. "`s`".
        what: &'static str,
        /// What it takes, e.g. "4 numbers (cx cy cz r)".
        expected: &'static str,
        /// Number of fields found after the keyword (all fields for
        /// continuation lines).
        found: u32,
    },
    /// A field that should be a number is not one.
    BadNumber(Token),
    /// A number is NaN, infinite or too large for `f32`.
    NotFinite(Token),
    /// A field that should be a whole number is not one.
    BadInteger(Token),
    /// A polygon's vertex count is negative.
    NegativeVertexCount(Token),
    /// A polygon has fewer than 3 vertices.
    TooFewVertices(u32),
    /// A `pp` vertex normal has zero length.
    ZeroLengthNormal,
    /// A scene capacity is too small; `needed` is what the whole file needs
    /// when the rest of it could be counted.
    Capacity(CapacityError),
    /// A line of the `v` block is missing or out of order.
    ViewOrder {
        /// The keyword expected here.
        expected: &'static str,
        /// What was found instead.
        found: Token,
    },
    /// A `v`-block keyword (`from`, `at`, ...) outside a `v` block.
    ViewLineOutsideBlock(Token),
    /// A second `v` block.
    DuplicateView {
        /// Line of the first `v`.
        first_line: u32,
    },
    /// The camera of the `v` block is unusable.
    Camera(CameraError),
    /// `resolution` outside 1..=65535.
    BadResolution,
    /// The file ends inside a multi-line entity.
    UnexpectedEnd {
        /// What was still expected.
        expected: &'static str,
        /// Line of the entity that is incomplete.
        entity_line: u32,
    },
    /// An object before any `f`/`fx` material.
    NoMaterial(&'static str),
    /// Numbers that do not describe a valid primitive.
    Geometry {
        /// The entity, e.g. "`s`".
        what: &'static str,
        /// Why it is invalid.
        error: GeometryError,
    },
    /// Material numbers out of range.
    InvalidMaterial(&'static str),
    /// A coordinate is beyond what the scalar type represents safely
    /// (fixed point; see [`crate::geom::fixed_range`]).
    OutOfRange(crate::geom::fixed_range::RangeError),
    /// The memory ran out while a heap scene grew (`std` only).
    OutOfMemory(MemoryError),
}

impl core::fmt::Display for NffErrorKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        use NffErrorKind::*;
        match self {
            UnknownEntity(t) => write!(
                f,
                "unknown entity `{t}` (expected one of v b l f fx s c p pp pl box obox q)"
            ),
            FieldCount { what, expected, found } => write!(f, "{what} takes {expected}, found {found} fields"),
            BadNumber(t) => write!(f, "expected a number, found `{t}`"),
            NotFinite(t) => write!(f, "`{t}` is not a finite number (NaN, infinity or too large)"),
            BadInteger(t) => write!(f, "expected a whole number, found `{t}`"),
            NegativeVertexCount(t) => write!(f, "negative vertex count `{t}`"),
            TooFewVertices(n) => write!(f, "a polygon needs at least 3 vertices, got {n}"),
            ZeroLengthNormal => f.write_str("`pp` vertex normal has zero length"),
            Capacity(c) => write!(f, "scene too large: {c}"),
            ViewOrder { expected, found } => write!(
                f,
                "`v` block out of order: expected `{expected}` (order: from, at, up, angle, hither, resolution), found `{found}`"
            ),
            ViewLineOutsideBlock(t) => write!(f, "`{t}` outside a `v` block (it belongs right after `v`, in order)"),
            DuplicateView { first_line } => write!(f, "second `v` block (the first is on line {first_line})"),
            Camera(e) => write!(f, "bad camera: {e}"),
            BadResolution => f.write_str("resolution must be between 1 and 65535 pixels per side"),
            UnexpectedEnd { expected, entity_line } => {
                write!(f, "file ends early: expected {expected} for the entity on line {entity_line}")
            }
            NoMaterial(what) => write!(f, "{what} before any `f` or `fx` material"),
            Geometry { what, error } => write!(f, "invalid {what}: {error}"),
            InvalidMaterial(why) => write!(f, "invalid material: {why}"),
            OutOfRange(r) => r.fmt(f),
            OutOfMemory(m) => write!(f, "scene too large: {m}"),
        }
    }
}

impl core::error::Error for NffErrorKind {}

/// An error in an NFF file: where, and what.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NffError {
    /// Line (1-based).
    pub line: u32,
    /// Column (1-based, in characters) of the offending field; for a missing
    /// field, one past the end of the line.
    pub column: u32,
    /// What is wrong.
    pub kind: NffErrorKind,
}

impl core::fmt::Display for NffError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "line {}, column {}: {}", self.line, self.column, self.kind)
    }
}

impl core::error::Error for NffError {}

/// The camera of a `v` block, as written in the file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NffCamera {
    /// Eye point.
    pub from: [f32; 3],
    /// Look-at point.
    pub at: [f32; 3],
    /// Up vector (any length, not parallel to the view direction).
    pub up: [f32; 3],
    /// Full vertical field of view in degrees.
    pub angle: f32,
    /// Near distance (the core's camera starts rays at the eye; kept for
    /// information).
    pub hither: f32,
    /// Image width from `resolution`.
    pub width: u32,
    /// Image height from `resolution`.
    pub height: u32,
}

impl NffCamera {
    /// The core camera for a `width × height` image (the file's resolution,
    /// or an override).
    pub fn camera<S: Scalar>(&self, width: u32, height: u32) -> Result<Camera<S>, CameraError> {
        let v = |a: [f32; 3]| Vec3::<S>::from_f32(a[0], a[1], a[2]);
        Camera::new(v(self.from), v(self.at), v(self.up), self.angle, width, height)
    }
}

/// How many of each thing a file holds (what [`scan`] reports and the
/// capacities [`parse`] needs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NffCounts {
    /// `s`.
    pub spheres: usize,
    /// `pl`.
    pub planes: usize,
    /// `p`.
    pub polygons: usize,
    /// `pp`.
    pub patches: usize,
    /// `box`.
    pub boxes: usize,
    /// `obox`.
    pub oriented_boxes: usize,
    /// `q`.
    pub quadrics: usize,
    /// `c`.
    pub cones: usize,
    /// Vertex-pool slots: `n` per `p n`, `2n` per `pp n` (positions and normals).
    pub vertices: usize,
    /// `f` and `fx` lines (each is one material).
    pub materials: usize,
    /// `l`.
    pub lights: usize,
}

impl NffCounts {
    /// All primitives.
    pub fn primitives(&self) -> usize {
        self.spheres
            + self.planes
            + self.polygons
            + self.patches
            + self.boxes
            + self.oriented_boxes
            + self.quadrics
            + self.cones
    }
    /// The count of one capacity.
    pub fn of(&self, kind: CapacityKind) -> usize {
        match kind {
            CapacityKind::Primitives => self.primitives(),
            CapacityKind::Vertices => self.vertices,
            CapacityKind::Materials => self.materials,
            CapacityKind::Lights => self.lights,
        }
    }
}

/// What a file holds besides its objects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NffInfo {
    /// The `v` block, if the file has one.
    pub camera: Option<NffCamera>,
    /// Background colour (black unless a `b` line says otherwise).
    pub background: [f32; 3],
    /// Numbers of primitives, vertices, materials, lights.
    pub counts: NffCounts,
    /// Number of lines.
    pub lines: u32,
}

/// Where parsed entities go: a scene, or a counter. The reader builds and
/// validates every shape itself, so both see the same errors.
trait Sink<S> {
    fn set_background(&mut self, c: Vec3<S>) -> Result<(), SceneError>;
    fn add_material(&mut self, m: Material<S>) -> Result<u16, SceneError>;
    fn add_light(&mut self, p: Vec3<S>, c: Vec3<S>) -> Result<(), SceneError>;
    fn add_shape(&mut self, s: Shape<S>, material: u16) -> Result<(), SceneError>;
    /// Room for one more primitive with `slots` pool vertices.
    fn polygon_room(&mut self, slots: u64) -> Result<(), SceneError>;
    fn push_vertex(&mut self, v: Vec3<S>) -> Result<u32, SceneError>;
    /// Removes the pool vertices from `len` on.
    fn truncate_vertices(&mut self, len: usize);
    fn add_polygon_from_pool(&mut self, first: u32, count: u32, patch: bool, material: u16) -> Result<(), SceneError>;
}

impl<S: Scalar, St: Storage<S>> Sink<S> for SceneStore<S, St> {
    fn set_background(&mut self, c: Vec3<S>) -> Result<(), SceneError> {
        SceneStore::set_background(self, c)
    }
    fn add_material(&mut self, m: Material<S>) -> Result<u16, SceneError> {
        SceneStore::add_material(self, m)
    }
    fn add_light(&mut self, p: Vec3<S>, c: Vec3<S>) -> Result<(), SceneError> {
        SceneStore::add_light(self, p, c)
    }
    fn add_shape(&mut self, s: Shape<S>, material: u16) -> Result<(), SceneError> {
        SceneStore::add_shape(self, s, material).map(|_| ())
    }
    fn polygon_room(&mut self, slots: u64) -> Result<(), SceneError> {
        let (p, v) = (St::Prims::LIMIT, St::Verts::LIMIT);
        if self.len() >= p {
            return Err(SceneError::Capacity(CapacityError {
                kind: CapacityKind::Primitives,
                capacity: p,
                needed: self.len() + 1,
            }));
        }
        let needed = self.vertex_count() as u64 + slots;
        if needed > v as u64 {
            let needed = usize::try_from(needed).unwrap_or(usize::MAX);
            return Err(SceneError::Capacity(CapacityError { kind: CapacityKind::Vertices, capacity: v, needed }));
        }
        Ok(())
    }
    fn push_vertex(&mut self, v: Vec3<S>) -> Result<u32, SceneError> {
        SceneStore::push_vertex(self, v)
    }
    fn truncate_vertices(&mut self, len: usize) {
        SceneStore::truncate_vertices(self, len)
    }
    fn add_polygon_from_pool(&mut self, first: u32, count: u32, patch: bool, material: u16) -> Result<(), SceneError> {
        SceneStore::add_polygon_from_pool(self, first, count, patch, material).map(|_| ())
    }
}

/// The sink of [`scan`]: builds nothing (the reader counts).
struct Discard;

impl Sink<f32> for Discard {
    fn set_background(&mut self, _: Vec3<f32>) -> Result<(), SceneError> {
        Ok(())
    }
    fn add_material(&mut self, _: Material<f32>) -> Result<u16, SceneError> {
        Ok(0)
    }
    fn add_light(&mut self, _: Vec3<f32>, _: Vec3<f32>) -> Result<(), SceneError> {
        Ok(())
    }
    fn add_shape(&mut self, _: Shape<f32>, _: u16) -> Result<(), SceneError> {
        Ok(())
    }
    fn polygon_room(&mut self, _: u64) -> Result<(), SceneError> {
        Ok(())
    }
    fn push_vertex(&mut self, _: Vec3<f32>) -> Result<u32, SceneError> {
        Ok(0)
    }
    fn truncate_vertices(&mut self, _: usize) {}
    fn add_polygon_from_pool(&mut self, _: u32, _: u32, _: bool, _: u16) -> Result<(), SceneError> {
        Ok(())
    }
}

/// Reads `text` into `scene` (appending to what it holds) and returns the
/// camera, background and counts.
///
/// On error the scene holds the entities before the failing one.
pub fn parse<S: Scalar, St: Storage<S>>(text: &str, scene: &mut SceneStore<S, St>) -> Result<NffInfo, NffError> {
    read::<S, dyn Sink<S>>(text, scene).map_err(|mut e| {
        // Say what the whole file needs, if the rest of it can be counted.
        if let NffErrorKind::Capacity(ref mut c) = e.kind {
            if let Ok(info) = scan(text) {
                c.needed = c.needed.max(info.counts.of(c.kind));
            }
        }
        e
    })
}

/// Reads `text` without building anything: checks it completely (the same
/// errors as [`parse`], except capacity) and counts what a scene needs to
/// hold it.
pub fn scan(text: &str) -> Result<NffInfo, NffError> {
    read::<f32, dyn Sink<f32>>(text, &mut Discard)
}

/// One line, with the comment removed.
#[derive(Clone, Copy)]
struct Line<'a> {
    no: u32,
    text: &'a str,
}

/// A field of a line and its byte offset in the line.
#[derive(Clone, Copy)]
struct Field<'a> {
    text: &'a str,
    at: usize,
}

/// Up to 17 fields (the longest entity, `q` with a clip box, has 17).
const MAX_FIELDS: usize = 17;

struct Fields<'a> {
    f: [Field<'a>; MAX_FIELDS],
    /// Fields on the line (may exceed `MAX_FIELDS`; only the first are kept).
    n: usize,
}

impl<'a> Line<'a> {
    fn fields(&self) -> Fields<'a> {
        let mut f = [Field { text: "", at: 0 }; MAX_FIELDS];
        let mut n = 0;
        let bytes = self.text.as_bytes();
        let mut i = 0;
        while i < bytes.len() {
            while i < bytes.len() && bytes[i].is_ascii_whitespace() {
                i += 1;
            }
            if i >= bytes.len() {
                break;
            }
            let start = i;
            while i < bytes.len() && !bytes[i].is_ascii_whitespace() {
                i += 1;
            }
            if n < MAX_FIELDS {
                // Splitting at ASCII white space keeps character boundaries.
                f[n] = Field { text: self.text.get(start..i).unwrap_or(""), at: start };
            }
            n += 1;
        }
        Fields { f, n }
    }

    /// 1-based character column of byte offset `at`.
    fn column(&self, at: usize) -> u32 {
        let at = at.min(self.text.len());
        let mut end = at;
        while !self.text.is_char_boundary(end) {
            end -= 1;
        }
        self.text[..end].chars().count() as u32 + 1
    }

    fn error_at(&self, at: usize, kind: NffErrorKind) -> NffError {
        NffError { line: self.no, column: self.column(at), kind }
    }

    /// Column just past the end of the line's content.
    fn end(&self) -> usize {
        self.text.trim_end().len() + 1
    }
}

/// The lines of a text, numbered from 1, comments removed.
#[derive(Clone)]
struct Lines<'a> {
    rest: &'a str,
    no: u32,
    done: bool,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        Lines { rest: text, no: 0, done: false }
    }

    fn next_raw(&mut self) -> Option<Line<'a>> {
        if self.done || (self.rest.is_empty() && self.no > 0) {
            return None;
        }
        let (line, rest) = match self.rest.split_once('\n') {
            Some(split) => split,
            None => {
                self.done = true;
                (self.rest, "")
            }
        };
        self.rest = rest;
        self.no += 1;
        let line = line.split_once('#').map_or(line, |(content, _)| content);
        Some(Line { no: self.no, text: line.strip_suffix('\r').unwrap_or(line) })
    }

    /// The next line with at least one field.
    fn next_content(&mut self) -> Option<Line<'a>> {
        while let Some(l) = self.next_raw() {
            if l.text.bytes().any(|b| !b.is_ascii_whitespace()) {
                return Some(l);
            }
        }
        None
    }

    /// Number of the last line read.
    fn line_no(&self) -> u32 {
        self.no
    }
}

fn number(line: &Line, f: &Field) -> Result<f32, NffError> {
    match f.text.parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(line.error_at(f.at, NffErrorKind::NotFinite(Token::new(f.text)))),
        Err(_) => Err(line.error_at(f.at, NffErrorKind::BadNumber(Token::new(f.text)))),
    }
}

/// The numbers of fields `from..from + N`.
fn numbers<const N: usize>(line: &Line, fields: &Fields, from: usize) -> Result<[f32; N], NffError> {
    let mut out = [0.0f32; N];
    for (k, o) in out.iter_mut().enumerate() {
        *o = number(line, &fields.f[from + k])?;
    }
    Ok(out)
}

/// Checks that the line has `1 + n` fields (keyword and `n` values) for one
/// of the allowed `n`.
fn expect_fields(
    line: &Line,
    fields: &Fields,
    allowed: &[usize],
    what: &'static str,
    expected: &'static str,
) -> Result<usize, NffError> {
    let found = fields.n - 1;
    if allowed.contains(&found) {
        return Ok(found);
    }
    let max = allowed.iter().copied().max().unwrap_or(0);
    // Point at the first surplus field, or past the end if fields are missing.
    let at = if found > max && max + 1 < MAX_FIELDS { fields.f[max + 1].at } else { line.end() };
    Err(line.error_at(at, NffErrorKind::FieldCount { what, expected, found: found as u32 }))
}

/// A continuation line of exactly `n` numbers.
fn continuation<'a, const N: usize>(
    lines: &mut Lines<'a>,
    entity_line: u32,
    what: &'static str,
    expected: &'static str,
) -> Result<(Line<'a>, [f32; N]), NffError> {
    let line = lines.next_content().ok_or(NffError {
        line: lines.line_no() + 1,
        column: 1,
        kind: NffErrorKind::UnexpectedEnd { expected, entity_line },
    })?;
    let fields = line.fields();
    if fields.n != N {
        let at = if fields.n > N && N < MAX_FIELDS { fields.f[N].at } else { line.end() };
        return Err(line.error_at(at, NffErrorKind::FieldCount { what, expected, found: fields.n as u32 }));
    }
    let v = numbers::<N>(&line, &fields, 0)?;
    Ok((line, v))
}

fn v3<S: Scalar>(a: &[f32]) -> Vec3<S> {
    Vec3::from_f32(a[0], a[1], a[2])
}

fn scene_error(line: &Line, what: &'static str, e: SceneError) -> NffError {
    let kind = match e {
        SceneError::Capacity(c) => NffErrorKind::Capacity(c),
        SceneError::Geometry(error) => NffErrorKind::Geometry { what, error },
        SceneError::InvalidMaterial(why) => NffErrorKind::InvalidMaterial(why),
        SceneError::OutOfRange(r) => NffErrorKind::OutOfRange(r),
        SceneError::OutOfMemory(m) => NffErrorKind::OutOfMemory(m),
        // The reader only uses material indices it was given.
        SceneError::UnknownMaterial(_) => NffErrorKind::NoMaterial(what),
    };
    line.error_at(0, kind)
}

fn geometry<T>(line: &Line, what: &'static str, r: Result<T, GeometryError>) -> Result<T, NffError> {
    r.map_err(|error| line.error_at(0, NffErrorKind::Geometry { what, error }))
}

/// The `v` block's keywords, in order.
const VIEW_KEYS: [&str; 6] = ["from", "at", "up", "angle", "hither", "resolution"];

/// Reads the six lines of a `v` block; returns the camera and the line and
/// column of each line's keyword (in [`VIEW_KEYS`] order), so that a camera
/// the numbers cannot make is reported where the offending numbers are.
fn read_view(lines: &mut Lines, v_line: u32) -> Result<(NffCamera, [(u32, u32); 6]), NffError> {
    let mut cam =
        NffCamera { from: [0.0; 3], at: [0.0; 3], up: [0.0; 3], angle: 0.0, hither: 0.0, width: 0, height: 0 };
    let mut at_lines = [(v_line, 1u32); 6];
    for (slot, key) in at_lines.iter_mut().zip(VIEW_KEYS) {
        let line = lines.next_content().ok_or(NffError {
            line: lines.line_no() + 1,
            column: 1,
            kind: NffErrorKind::UnexpectedEnd { expected: key, entity_line: v_line },
        })?;
        let fields = line.fields();
        if fields.f[0].text != key {
            return Err(line.error_at(
                fields.f[0].at,
                NffErrorKind::ViewOrder { expected: key, found: Token::new(fields.f[0].text) },
            ));
        }
        *slot = (line.no, line.column(fields.f[0].at));
        match key {
            "from" | "at" | "up" => {
                expect_fields(&line, &fields, &[3], view_what(key), "3 numbers (x y z)")?;
                let v = numbers::<3>(&line, &fields, 1)?;
                match key {
                    "from" => cam.from = v,
                    "at" => cam.at = v,
                    _ => cam.up = v,
                }
            }
            "angle" | "hither" => {
                expect_fields(&line, &fields, &[1], view_what(key), "1 number")?;
                let [v] = numbers::<1>(&line, &fields, 1)?;
                if key == "angle" {
                    cam.angle = v;
                } else {
                    cam.hither = v;
                }
            }
            _ => {
                expect_fields(&line, &fields, &[2], "`resolution`", "2 whole numbers (width height)")?;
                let mut wh = [0u32; 2];
                for (k, slot) in wh.iter_mut().enumerate() {
                    let f = &fields.f[1 + k];
                    let n: u32 = f
                        .text
                        .parse()
                        .map_err(|_| line.error_at(f.at, NffErrorKind::BadInteger(Token::new(f.text))))?;
                    if n == 0 || n > 65535 {
                        return Err(line.error_at(f.at, NffErrorKind::BadResolution));
                    }
                    *slot = n;
                }
                cam.width = wh[0];
                cam.height = wh[1];
            }
        }
    }
    Ok((cam, at_lines))
}

fn view_what(key: &str) -> &'static str {
    match key {
        "from" => "`from`",
        "at" => "`at`",
        "up" => "`up`",
        "angle" => "`angle`",
        _ => "`hither`",
    }
}

/// Reads a `p`/`pp` vertex count.
fn vertex_count(line: &Line, f: &Field) -> Result<u32, NffError> {
    match f.text.parse::<i64>() {
        Ok(n) if n < 0 => Err(line.error_at(f.at, NffErrorKind::NegativeVertexCount(Token::new(f.text)))),
        Ok(n) if n < 3 => Err(line.error_at(f.at, NffErrorKind::TooFewVertices(n as u32))),
        Ok(n) => u32::try_from(n).map_err(|_| line.error_at(f.at, NffErrorKind::BadInteger(Token::new(f.text)))),
        Err(_) => Err(line.error_at(f.at, NffErrorKind::BadInteger(Token::new(f.text)))),
    }
}

fn read_polygon<'a, S: Scalar, K: Sink<S> + ?Sized>(
    lines: &mut Lines<'a>,
    line: &Line<'a>,
    count: u32,
    patch: bool,
    material: u16,
    sink: &mut K,
) -> Result<(), NffError> {
    let what = if patch { "`pp`" } else { "`p`" };
    let slots = count as u64 * if patch { 2 } else { 1 };
    sink.polygon_room(slots).map_err(|e| scene_error(line, what, e))?;
    let (vwhat, vexp) = if patch {
        ("a `pp` vertex line", "6 numbers (x y z nx ny nz)")
    } else {
        ("a `p` vertex line", "3 numbers (x y z)")
    };
    // First pass: read and check every vertex line, so a bad line leaves
    // nothing behind in the scene.
    let start = lines.clone();
    for _ in 0..count {
        if patch {
            let (vline, v) = continuation::<6>(lines, line.no, vwhat, vexp)?;
            if v3::<S>(&v[3..]).normalize_or_zero() == Vec3::ZERO {
                let at = vline.fields().f[3].at;
                return Err(vline.error_at(at, NffErrorKind::ZeroLengthNormal));
            }
        } else {
            continuation::<3>(lines, line.no, vwhat, vexp)?;
        }
    }
    // Then the pool gets the `n` positions, and for a patch the `n` unit
    // normals after them (a second pass over the same lines). A vertex
    // that does not fit (a heap scene out of memory) takes those before it
    // out again.
    let mut first = None;
    let mut pushed = || -> Result<(), NffError> {
        let mut again = start.clone();
        for _ in 0..count {
            let pos = if patch {
                let (_, v) = continuation::<6>(&mut again, line.no, vwhat, vexp)?;
                [v[0], v[1], v[2]]
            } else {
                continuation::<3>(&mut again, line.no, vwhat, vexp)?.1
            };
            let id = sink.push_vertex(v3(&pos)).map_err(|e| scene_error(line, what, e))?;
            first.get_or_insert(id);
        }
        if patch {
            let mut again = start.clone();
            for _ in 0..count {
                let (_, v) = continuation::<6>(&mut again, line.no, vwhat, vexp)?;
                sink.push_vertex(v3::<S>(&v[3..]).normalize_or_zero()).map_err(|e| scene_error(line, what, e))?;
            }
        }
        Ok(())
    };
    if let Err(e) = pushed() {
        if let Some(f) = first {
            sink.truncate_vertices(f as usize);
        }
        return Err(e);
    }
    sink.add_polygon_from_pool(first.unwrap_or(0), count, patch, material).map_err(|e| scene_error(line, what, e))
}

/// Number of `l` lines (for the default light intensity).
fn count_lights(text: &str) -> usize {
    let mut lines = Lines::new(text);
    let mut n = 0;
    while let Some(l) = lines.next_content() {
        if l.fields().f[0].text == "l" {
            n += 1;
        }
    }
    n
}

// `parse` and `scan` call it with a `dyn Sink` (a call per entity, not per
// number), and out of line: one copy of the reader per scalar, not one per
// sink and caller (14 KB each in the browser preview's module).
#[inline(never)]
fn read<S: Scalar, K: Sink<S> + ?Sized>(text: &str, sink: &mut K) -> Result<NffInfo, NffError> {
    // A UTF-8 byte order mark (editors on some systems write one) is not
    // part of the first line.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut info = NffInfo { camera: None, background: [0.0; 3], counts: NffCounts::default(), lines: 0 };
    let n_lights = count_lights(text);
    // Default light intensity 1/sqrt(n): libm, so the same bits everywhere.
    let default_light = if n_lights > 0 { 1.0 / libm::sqrtf(n_lights as f32) } else { 1.0 };
    let mut material: Option<u16> = None;
    let mut view_line: Option<u32> = None;
    let mut lines = Lines::new(text);

    while let Some(line) = lines.next_content() {
        let fields = line.fields();
        let key = fields.f[0];
        let need_material = |what: &'static str| material.ok_or(line.error_at(key.at, NffErrorKind::NoMaterial(what)));
        match key.text {
            "v" => {
                if let Some(first_line) = view_line {
                    return Err(line.error_at(key.at, NffErrorKind::DuplicateView { first_line }));
                }
                expect_fields(&line, &fields, &[0], "`v`", "no numbers (the camera follows on 6 lines)")?;
                view_line = Some(line.no);
                let (cam, at_lines) = read_view(&mut lines, line.no)?;
                cam.camera::<f32>(cam.width, cam.height).map_err(|e| {
                    // The line whose numbers make the camera impossible
                    // (VIEW_KEYS order); the `v` line for the rest.
                    let which = match e {
                        CameraError::EyeAtTarget => Some(1),
                        CameraError::UpParallel => Some(2),
                        CameraError::FieldOfView => Some(3),
                        CameraError::ImageSize => Some(5),
                        CameraError::NonFinite | CameraError::OutOfRange(_) => None,
                    };
                    match which.and_then(|i| at_lines.get(i)) {
                        Some(&(line, column)) => NffError { line, column, kind: NffErrorKind::Camera(e) },
                        None => line.error_at(key.at, NffErrorKind::Camera(e)),
                    }
                })?;
                info.camera = Some(cam);
            }
            "from" | "at" | "up" | "angle" | "hither" | "resolution" => {
                return Err(line.error_at(key.at, NffErrorKind::ViewLineOutsideBlock(Token::new(key.text))));
            }
            "b" => {
                expect_fields(&line, &fields, &[3], "`b`", "3 numbers (r g b)")?;
                let c = numbers::<3>(&line, &fields, 1)?;
                sink.set_background(v3(&c)).map_err(|e| scene_error(&line, "`b`", e))?;
                info.background = c;
            }
            "l" => {
                let n = expect_fields(&line, &fields, &[3, 6], "`l`", "3 numbers (x y z) or 6 (x y z r g b)")?;
                let p = numbers::<3>(&line, &fields, 1)?;
                let c = if n == 6 { numbers::<3>(&line, &fields, 4)? } else { [default_light; 3] };
                sink.add_light(v3(&p), v3(&c)).map_err(|e| scene_error(&line, "`l`", e))?;
                info.counts.lights += 1;
            }
            "f" | "fx" => {
                let m = read_material::<S>(&line, &fields, key.text)?;
                material = Some(sink.add_material(m).map_err(|e| scene_error(&line, material_what(key.text), e))?);
                info.counts.materials += 1;
            }
            "s" | "c" | "pl" | "box" | "obox" | "q" => {
                read_primitive::<S, K>(&mut lines, &line, &fields, material, sink, &mut info.counts)?
            }
            "p" | "pp" => {
                let patch = key.text == "pp";
                let what = if patch { "`pp`" } else { "`p`" };
                expect_fields(
                    &line,
                    &fields,
                    &[1],
                    what,
                    "1 number (the vertex count), vertices on the following lines",
                )?;
                let count = vertex_count(&line, &fields.f[1])?;
                let m = need_material(what)?;
                read_polygon::<S, K>(&mut lines, &line, count, patch, m, sink)?;
                if patch {
                    info.counts.patches += 1;
                    info.counts.vertices += 2 * count as usize;
                } else {
                    info.counts.polygons += 1;
                    info.counts.vertices += count as usize;
                }
            }
            other => return Err(line.error_at(key.at, NffErrorKind::UnknownEntity(Token::new(other)))),
        }
    }
    info.lines = lines.line_no();
    Ok(info)
}

/// `"`f`"` or `"`fx`"`, for messages.
fn material_what(key: &str) -> &'static str {
    if key == "f" {
        "`f`"
    } else {
        "`fx`"
    }
}

/// Reads an `f` or `fx` line (`key`) into a checked material.
fn read_material<S: Scalar>(line: &Line, fields: &Fields, key: &str) -> Result<Material<S>, NffError> {
    let m = if key == "f" {
        expect_fields(line, fields, &[8], "`f`", "8 numbers (r g b Kd Ks Shine T ior)")?;
        let [r, g, b, kd, ks, shine, t, ior] = numbers::<8>(line, fields, 1)?;
        Material::nff(
            v3(&[r, g, b]),
            S::from_f32(kd),
            S::from_f32(ks),
            S::from_f32(shine),
            S::from_f32(t),
            S::from_f32(ior),
        )
    } else {
        expect_fields(line, fields, &[10], "`fx`", "10 numbers (r g b Ka Kd Ks Shine Kr Kt ior)")?;
        let [r, g, b, ka, kd, ks, shine, kr, kt, ior] = numbers::<10>(line, fields, 1)?;
        let f = S::from_f32;
        Material {
            color: v3(&[r, g, b]),
            ka: f(ka),
            kd: f(kd),
            ks: f(ks),
            shine: f(shine),
            kr: f(kr),
            kt: f(kt),
            ior: f(ior),
        }
    };
    // Opaque SPD materials say ior 0; it is unused without transmission.
    let m = if m.kt == S::ZERO && !(m.ior > S::ZERO) { Material { ior: S::ONE, ..m } } else { m };
    m.validate().map_err(|e| scene_error(line, material_what(key), e))?;
    Ok(m)
}

/// Reads a one-line primitive entity (`s`, `pl`, `box`, `obox`, `q`) or a
/// `c` (one line or three) into `sink` with `material`, and counts it. The
/// checks run in the order of every entity: fields and numbers, then the
/// material, then the geometry.
fn read_primitive<S: Scalar, K: Sink<S> + ?Sized>(
    lines: &mut Lines,
    line: &Line,
    fields: &Fields,
    material: Option<u16>,
    sink: &mut K,
    counts: &mut NffCounts,
) -> Result<(), NffError> {
    let key = fields.f[0];
    let need_material = |what: &'static str| material.ok_or(line.error_at(key.at, NffErrorKind::NoMaterial(what)));
    match key.text {
        "s" => {
            expect_fields(line, fields, &[4], "`s`", "4 numbers (cx cy cz r)")?;
            let [x, y, z, r] = numbers::<4>(line, fields, 1)?;
            let m = need_material("`s`")?;
            let s = geometry(line, "`s`", Sphere::new(v3(&[x, y, z]), S::from_f32(r)))?;
            sink.add_shape(Shape::Sphere(s), m).map_err(|e| scene_error(line, "`s`", e))?;
            counts.spheres += 1;
        }
        "c" => {
            let n = expect_fields(
                line,
                fields,
                &[0, 8],
                "`c`",
                "8 numbers (bx by bz br ax ay az ar), or none with base and apex on the next two lines",
            )?;
            let (b, a) = if n == 8 {
                let v = numbers::<8>(line, fields, 1)?;
                ([v[0], v[1], v[2], v[3]], [v[4], v[5], v[6], v[7]])
            } else {
                let (_, b) = continuation::<4>(lines, line.no, "the `c` base line", "4 numbers (bx by bz br)")?;
                let (_, a) = continuation::<4>(lines, line.no, "the `c` apex line", "4 numbers (ax ay az ar)")?;
                (b, a)
            };
            let m = need_material("`c`")?;
            let c = geometry(line, "`c`", Cone::new(v3(&b), S::from_f32(b[3]), v3(&a), S::from_f32(a[3])))?;
            sink.add_shape(Shape::Cone(c), m).map_err(|e| scene_error(line, "`c`", e))?;
            counts.cones += 1;
        }
        "pl" => {
            expect_fields(line, fields, &[4], "`pl`", "4 numbers (A B C D)")?;
            let [a, b, c, d] = numbers::<4>(line, fields, 1)?;
            let m = need_material("`pl`")?;
            let f = S::from_f32;
            let p = geometry(line, "`pl`", Plane::from_coefficients(f(a), f(b), f(c), f(d)))?;
            sink.add_shape(Shape::Plane(p), m).map_err(|e| scene_error(line, "`pl`", e))?;
            counts.planes += 1;
        }
        "box" => {
            expect_fields(line, fields, &[6], "`box`", "6 numbers (x0 y0 z0 x1 y1 z1)")?;
            let v = numbers::<6>(line, fields, 1)?;
            let m = need_material("`box`")?;
            let b = geometry(line, "`box`", AaBox::new(v3(&v[..3]), v3(&v[3..])))?;
            sink.add_shape(Shape::AaBox(b), m).map_err(|e| scene_error(line, "`box`", e))?;
            counts.boxes += 1;
        }
        "obox" => {
            expect_fields(line, fields, &[12], "`obox`", "12 numbers (cx cy cz hx hy hz ux uy uz vx vy vz)")?;
            let v = numbers::<12>(line, fields, 1)?;
            let m = need_material("`obox`")?;
            let b = geometry(line, "`obox`", OrientedBox::new(v3(&v[..3]), v3(&v[3..6]), v3(&v[6..9]), v3(&v[9..])))?;
            sink.add_shape(Shape::OrientedBox(b), m).map_err(|e| scene_error(line, "`obox`", e))?;
            counts.oriented_boxes += 1;
        }
        "q" => {
            let n = expect_fields(
                line,
                fields,
                &[10, 16],
                "`q`",
                "10 numbers (A to J), or 16 with a clip box (x0 y0 z0 x1 y1 z1)",
            )?;
            let k = numbers::<10>(line, fields, 1)?;
            let m = need_material("`q`")?;
            let mut q = geometry(line, "`q`", Quadric::new(k.map(S::from_f32)))?;
            if n == 16 {
                let c = numbers::<6>(line, fields, 11)?;
                q = geometry(line, "`q`", q.with_clip(v3(&c[..3]), v3(&c[3..])))?;
            }
            sink.add_shape(Shape::Quadric(q), m).map_err(|e| scene_error(line, "`q`", e))?;
            counts.quadrics += 1;
        }
        _ => {}
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::geom::primitives::ShapeKind;
    use crate::scene::Scene;
    use std::format;
    use std::string::{String, ToString};

    type Small = Scene<f32, 64, 256, 16, 8>;

    const CAMERA: &str = "v\nfrom 0 -8 3\nat 0 0 0.8\nup 0 0 1\nangle 40\nhither 0.01\nresolution 32 24\n";

    fn parse_str(text: &str) -> Result<(Small, NffInfo), NffError> {
        let mut s = Small::new();
        let info = parse(text, &mut s)?;
        Ok((s, info))
    }

    /// Parses `text` expecting an error; checks its line and that the
    /// message names that line and contains `needle`; returns the error.
    fn fails(text: &str, line: u32, needle: &str) -> NffError {
        let e = parse_str(text).err().unwrap_or_else(|| panic!("no error for {text:?}"));
        let msg = e.to_string();
        assert_eq!(e.line, line, "{msg}");
        assert!(msg.starts_with(&format!("line {line}, column ")), "{msg}");
        assert!(msg.contains(needle), "{msg:?} lacks {needle:?}");
        // The scanner agrees (except about capacities, which it does not have).
        if !matches!(e.kind, NffErrorKind::Capacity(_)) {
            assert_eq!(scan(text).err(), Some(e));
        }
        e
    }

    const F: &str = "f 1 1 1 1 0 0 0 1\n";

    #[test]
    fn unknown_entity() {
        let e = fails(&format!("{F}s 0 0 0 1\n\n  sphere 0 0 0 1\n"), 4, "unknown entity `sphere`");
        assert_eq!(e.column, 3);
        fails("# comment\nP 3\n", 2, "unknown entity `P`");
        // A very long word is quoted shortened.
        let e = fails("abcdefghijklmnopqrstuvwxyz0123456789\n", 1, "`abcdefghijklmnopqrstuvwx…`");
        assert_eq!(e.column, 1);
    }

    #[test]
    fn byte_order_mark_is_skipped() {
        let (scene, info) = parse_str(&format!("\u{feff}{F}s 0 0 0 1\n")).unwrap();
        assert_eq!((scene.len(), info.counts.spheres), (1, 1));
        // Only at the start: elsewhere it is an unknown entity on its line.
        fails(&format!("{F}\u{feff}s 0 0 0 1\n"), 2, "unknown entity");
    }

    #[test]
    fn wrong_field_count() {
        let e = fails(&format!("{F}s 0 0 0\n"), 2, "`s` takes 4 numbers (cx cy cz r), found 3 fields");
        assert_eq!(e.column, 8); // one past the end
        let e = fails(&format!("{F}s 0 0 0 1 2\n"), 2, "found 5 fields");
        assert_eq!(e.column, 11); // the surplus field
        fails(&format!("{F}c 0 0 0 1 0 0 1\n"), 2, "`c` takes 8 numbers");
        fails(&format!("{F}c\n0 0 0 1\n0 0 1\n"), 4, "the `c` apex line takes 4 numbers");
        fails("l 1 2 3 4\n", 1, "`l` takes 3 numbers (x y z) or 6");
        fails("b 1 2\n", 1, "`b` takes 3 numbers");
        fails("f 1 1 1 1 0 0 0\n", 1, "`f` takes 8 numbers");
        fails("fx 1 1 1 0 1 0 0 0 0 0 1\n", 1, "`fx` takes 10 numbers");
        fails(&format!("{F}pl 0 0 1\n"), 2, "`pl` takes 4");
        fails(&format!("{F}box 0 0 0 1 1\n"), 2, "`box` takes 6");
        fails(&format!("{F}obox 0 0 0 1 1 1 1 0 0 0 1\n"), 2, "`obox` takes 12");
        fails(&format!("{F}q 1 1 1 0 0 0 0 0 0 -1 0 0 0\n"), 2, "`q` takes 10 numbers (A to J), or 16");
        fails(&format!("{F}p 3\n0 0 0\n1 0 0 5\n0 1 0\n"), 4, "a `p` vertex line takes 3 numbers (x y z), found 4");
        fails(&format!("{F}pp 3\n0 0 0 0 0 1\n1 0 0\n"), 4, "a `pp` vertex line takes 6 numbers");
        fails(&format!("{F}p 3 4\n"), 2, "`p` takes 1 number");
        fails("v 1\n", 1, "`v` takes no numbers");
        fails("v\nfrom 0 0\n", 2, "`from` takes 3 numbers");
        fails("v\nfrom 0 0 1\nat 0 0 0\nup 0 1 0\nangle 40 2\n", 5, "`angle` takes 1 number");
    }

    #[test]
    fn bad_numbers() {
        let e = fails(&format!("{F}s 0 0 zero 1\n"), 2, "expected a number, found `zero`");
        assert_eq!(e.column, 7);
        fails(&format!("{F}p 3\n0 0 0\n1 0,5 0\n0 1 0\n"), 4, "found `0,5`");
        fails("b 0.1 0.2 0.3.4\n", 1, "found `0.3.4`");
        fails(&format!("{F}p three\n"), 2, "expected a whole number, found `three`");
        fails(&format!("{F}p 3.0\n"), 2, "expected a whole number, found `3.0`");
        fails(&CAMERA.replace("resolution 32 24", "resolution 32 24.5"), 7, "whole number, found `24.5`");
        fails(&CAMERA.replace("resolution 32 24", "resolution 0 24"), 7, "resolution must be between 1 and 65535");
    }

    #[test]
    fn nan_and_infinity() {
        fails(&format!("{F}s 0 0 0 NaN\n"), 2, "`NaN` is not a finite number");
        fails("l inf 0 0\n", 1, "`inf` is not a finite number");
        fails(&format!("{F}pl 0 0 1 -infinity\n"), 2, "`-infinity` is not a finite");
        // Too large for f32 rounds to infinity: an error too.
        fails(&format!("{F}s 0 0 0 1e39\n"), 2, "`1e39` is not a finite");
    }

    #[test]
    fn vertex_counts() {
        let e = fails(&format!("{F}p -3\n"), 2, "negative vertex count `-3`");
        assert_eq!(e.column, 3);
        fails(&format!("{F}pp -1\n"), 2, "negative vertex count");
        fails(&format!("{F}p 2\n0 0 0\n1 0 0\n"), 2, "a polygon needs at least 3 vertices, got 2");
        fails(&format!("{F}pp 0\n"), 2, "at least 3 vertices, got 0");
        // Too few vertex lines before the end of the file.
        fails(
            &format!("{F}p 4\n0 0 0\n1 0 0\n0 1 0\n"),
            6,
            "file ends early: expected 3 numbers (x y z) for the entity on line 2",
        );
        // A count larger than the vertex lines runs into the next entity.
        fails(
            &format!("{F}p 4\n0 0 0\n1 0 0\n0 1 0\ns 0 0 0 1\n"),
            6,
            "a `p` vertex line takes 3 numbers (x y z), found 5",
        );
    }

    #[test]
    fn zero_length_patch_normal() {
        let e = fails(
            &format!("{F}pp 3\n0 0 0 0 0 1\n1 0 0 0 0 0\n0 1 0 0 0 1\n"),
            4,
            "`pp` vertex normal has zero length",
        );
        assert_eq!(e.column, 7);
        // Nothing of the failed patch stays in the scene.
        let mut s = Small::new();
        let _ = parse(&format!("{F}pp 3\n0 0 0 0 0 1\n1 0 0 0 0 0\n0 1 0 0 0 1\n"), &mut s);
        assert_eq!((s.len(), s.vertex_count()), (0, 0));
    }

    #[test]
    fn capacity_errors_name_the_capacity_and_what_the_file_needs() {
        let mut text = String::from(F);
        for i in 0..10 {
            text += &format!("s {i} 0 0 0.5\n");
        }
        let mut tiny: Scene<f32, 4, 16, 2, 2> = Scene::new();
        let e = parse(&text, &mut tiny).unwrap_err();
        assert_eq!(e.line, 6); // the fifth sphere
        assert_eq!(
            e.kind,
            NffErrorKind::Capacity(CapacityError { kind: CapacityKind::Primitives, capacity: 4, needed: 10 })
        );
        assert_eq!(e.to_string(), "line 6, column 1: scene too large: primitive capacity 4 exceeded (needs 10)");

        // Vertices: the second polygon does not fit; the file needs 12 slots.
        let quad = "p 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
        let text = format!("{F}{quad}{quad}{quad}");
        let mut tiny: Scene<f32, 8, 6, 2, 2> = Scene::new();
        let e = parse(&text, &mut tiny).unwrap_err();
        assert_eq!(e.line, 7);
        assert!(e.to_string().contains("vertex capacity 6 exceeded (needs 12)"), "{e}");

        let mut tiny: Scene<f32, 8, 6, 2, 2> = Scene::new();
        let e = parse(&format!("{F}{F}{F}"), &mut tiny).unwrap_err();
        assert!(
            e.to_string().starts_with("line 3,") && e.to_string().contains("material capacity 2 exceeded (needs 3)"),
            "{e}"
        );
        let mut tiny: Scene<f32, 8, 6, 2, 2> = Scene::new();
        let e = parse("l 0 0 1\nl 0 0 2\nl 0 0 3\nl 0 0 4\n", &mut tiny).unwrap_err();
        assert!(
            e.to_string().starts_with("line 3,") && e.to_string().contains("light capacity 2 exceeded (needs 4)"),
            "{e}"
        );
    }

    #[test]
    fn view_block_out_of_order() {
        let e = fails(
            "v\nat 0 0 0\nfrom 0 0 1\n",
            2,
            "`v` block out of order: expected `from` (order: from, at, up, angle, hither, resolution), found `at`",
        );
        assert_eq!(e.column, 1);
        fails(
            &CAMERA.replace("hither 0.01\nresolution 32 24", "resolution 32 24\nhither 0.01"),
            6,
            "expected `hither`",
        );
        fails(
            &CAMERA.replace("angle 40\n", ""),
            5,
            "expected `angle` (order: from, at, up, angle, hither, resolution), found `hither`",
        );
        fails(&format!("{F}s 0 0 0 1\nup 0 0 1\n"), 3, "`up` outside a `v` block");
        fails("v\nfrom 0 0 1\nat 0 0 0\n", 4, "file ends early: expected up for the entity on line 1");
        fails(&format!("{CAMERA}{CAMERA}"), 8, "second `v` block (the first is on line 1)");
        // An impossible camera is reported on the line that makes it so.
        fails(&CAMERA.replace("at 0 0 0.8", "at 0 -8 3"), 3, "bad camera: the camera's eye and look-at point coincide");
        fails(&CAMERA.replace("up 0 0 1", "up 0 8 -2.2"), 4, "bad camera: the up vector is zero or parallel");
        fails(&CAMERA.replace("up 0 0 1", "up 0 0 0"), 4, "bad camera: the up vector");
        fails(&CAMERA.replace("angle 40", "angle 180"), 5, "bad camera: the field of view");
        assert_eq!(fails(&CAMERA.replace("angle 40", "  angle 0"), 5, "bad camera: the field of view").column, 3);
    }

    #[test]
    fn invalid_objects_and_materials() {
        fails("s 0 0 0 1\n", 1, "`s` before any `f` or `fx` material");
        fails(&format!("{F}s 0 0 0 -1\n"), 2, "invalid `s`: a radius or size is zero or negative");
        fails(&format!("{F}c 0 0 0 1 0 0 0 1\n"), 2, "invalid `c`: an axis");
        fails(&format!("{F}pl 0 0 0 1\n"), 2, "invalid `pl`");
        fails(&format!("{F}q 0 0 0 0 0 0 0 0 0 1\n"), 2, "invalid `q`: quadric with all of A..I zero");
        fails(&format!("{F}obox 0 0 0 1 1 1 1 0 0 2 0 0\n"), 2, "invalid `obox`");
        fails("f 1 1 1 1 0 0 0.5 0\n", 1, "invalid material: index of refraction must be positive");
        fails("f 1 1 1 1 0 -2 0 1\n", 1, "invalid material: negative Phong exponent");
        // Opaque materials with the SPD's `ior 0` are fine.
        let (s, _) = parse_str("f 1 1 1 1 0 0 0 0\n").unwrap();
        assert_eq!(s.view().materials()[0].ior, 1.0);
    }

    #[test]
    fn comments_blank_lines_and_line_endings() {
        let text = "# header\r\n\r\nf 1 1 1 1 0 0 0 1 # white\r\n  s 0 0 0 1\t\r\n#p 3\n";
        let (s, info) = parse_str(text).unwrap();
        assert_eq!(s.len(), 1);
        assert_eq!(info.lines, 5);
        let e = fails("f 1 1 1 1 0 0 0 1\r\ns 0 0 0 x\r\n", 2, "found `x`");
        assert_eq!(e.column, 9);
        // Columns count characters, not bytes.
        let e = fails("# é\nf 1 1 1 1 0 0 0 1\ns 0 0 0 é\n", 3, "found `é`");
        assert_eq!(e.column, 9);
        assert_eq!(parse_str("").unwrap().1.counts, NffCounts::default());
    }

    #[test]
    fn default_light_intensity_is_one_over_sqrt_of_light_count() {
        let (s, _) = parse_str("l 0 0 1\nl 0 0 2 0.5 0.25 1\nl 0 0 3\nl 0 0 4\n").unwrap();
        let lights = s.view().lights();
        assert_eq!(lights.len(), 4);
        assert_eq!(lights[0].color, Vec3::new(0.5, 0.5, 0.5)); // 1/sqrt(4)
        assert_eq!(lights[1].color, Vec3::new(0.5, 0.25, 1.0));
        assert_eq!(lights[3].position, Vec3::new(0.0, 0.0, 4.0));
    }

    const EXTENSIONS: &str = include_str!("../../tests/scenes/extensions.nff");

    #[test]
    fn every_entity_lands_in_the_scene() {
        let (s, info) = parse_str(EXTENSIONS).unwrap();
        let view = s.view();
        let cam = info.camera.unwrap();
        assert_eq!(cam.from, [0.0, -8.0, 3.0]);
        assert_eq!(cam.at, [0.0, 0.0, 0.8]);
        assert_eq!(cam.up, [0.0, 0.0, 1.0]);
        assert_eq!((cam.angle, cam.hither, cam.width, cam.height), (40.0, 0.01, 320, 240));
        assert_eq!(info.background, [0.1, 0.12, 0.2]);
        assert_eq!(view.background(), Vec3::new(0.1, 0.12, 0.2));
        let c = info.counts;
        assert_eq!(
            (c.planes, c.boxes, c.oriented_boxes, c.quadrics, c.spheres, c.cones, c.polygons, c.patches),
            (1, 1, 1, 2, 2, 2, 1, 1)
        );
        assert_eq!((c.vertices, c.materials, c.lights, c.primitives()), (10, 7, 2, 11));
        assert_eq!(scan(EXTENSIONS).unwrap(), info);

        let lights = view.lights();
        let d = 1.0 / libm::sqrtf(2.0);
        assert_eq!(lights[0].position, Vec3::new(-4.0, -5.0, 7.0));
        assert_eq!(lights[0].color, Vec3::new(d, d, d));
        assert_eq!(lights[1].color, Vec3::new(0.5, 0.45, 0.4));

        let mats = view.materials();
        assert_eq!(
            mats[0],
            Material {
                color: Vec3::new(0.8, 0.8, 0.7),
                ka: 0.1,
                kd: 0.8,
                ks: 0.0,
                shine: 1.0,
                kr: 0.0,
                kt: 0.0,
                ior: 1.0
            }
        );
        // `f`: Ka = 0, Kr = Ks.
        assert_eq!(
            mats[1],
            Material {
                color: Vec3::new(0.9, 0.2, 0.15),
                ka: 0.0,
                kd: 0.7,
                ks: 0.3,
                shine: 20.0,
                kr: 0.3,
                kt: 0.0,
                ior: 1.0
            }
        );
        assert_eq!(mats[4].ior, 1.0); // `ior 0` with T = 0
        assert_eq!((mats[5].kt, mats[5].ior), (0.85, 1.5));

        let p = view.primitives();
        let kinds = p.iter().map(|q| q.shape.kind()).collect::<std::vec::Vec<_>>();
        use ShapeKind::*;
        assert_eq!(kinds, [Plane, AaBox, OrientedBox, Quadric, Quadric, Sphere, Sphere, Cone, Cone, Polygon, Patch]);
        assert_eq!(p.iter().map(|q| q.material).collect::<std::vec::Vec<_>>(), [0, 1, 2, 3, 3, 4, 5, 6, 6, 6, 6]);
        match p[0].shape {
            Shape::Plane(pl) => assert_eq!((pl.normal_vector(), pl.offset()), (Vec3::new(0.0, 0.0, 1.0), 0.0)),
            _ => unreachable!(),
        }
        match p[1].shape {
            Shape::AaBox(b) => assert_eq!((b.min(), b.max()), (Vec3::new(-2.6, -0.4, 0.0), Vec3::new(-1.6, 0.6, 1.0))),
            _ => unreachable!(),
        }
        match p[2].shape {
            Shape::OrientedBox(b) => {
                let h = core::f32::consts::FRAC_1_SQRT_2;
                assert_eq!(b.center(), Vec3::new(1.9, -0.6, 0.4));
                assert_eq!(b.half_extents(), Vec3::new(0.4, 0.4, 0.4));
                let (u, v, w) = b.axes();
                assert!((u - Vec3::new(h, h, 0.0)).length() < 1e-6 && (v - Vec3::new(-h, h, 0.0)).length() < 1e-6);
                assert!((w - Vec3::new(0.0, 0.0, 1.0)).length() < 1e-6);
            }
            _ => unreachable!(),
        }
        match (p[3].shape, p[4].shape) {
            (Shape::Quadric(a), Shape::Quadric(b)) => {
                assert_eq!(
                    a.coefficients(),
                    [4.0, 11.111111, 11.111111, 0.0, 0.0, 0.0, -9.6, -28.888_89, -6.6666667, 24.537778]
                );
                assert_eq!(a.clip_box(), None);
                assert_eq!(b.coefficients(), [1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 2.0, -4.0, 0.0, 4.91]);
                assert_eq!(b.clip_box(), Some((Vec3::new(-1.5, 1.5, 0.0), Vec3::new(-0.5, 2.5, 1.6))));
            }
            _ => unreachable!(),
        }
        match p[6].shape {
            Shape::Sphere(sp) => assert_eq!((sp.center(), sp.radius()), (Vec3::new(-0.6, -1.3, 0.5), 0.5)),
            _ => unreachable!(),
        }
        match (p[7].shape, p[8].shape) {
            (Shape::Cone(a), Shape::Cone(b)) => {
                assert_eq!(a.ends(), (Vec3::new(3.0, 0.6, 0.0), 0.4, Vec3::new(3.0, 0.6, 1.2), 0.05));
                assert_eq!(b.ends(), (Vec3::new(-3.0, 0.6, 0.0), 0.3, Vec3::new(-3.0, 0.6, 0.9), 0.3));
            }
            _ => unreachable!(),
        }
        match (p[9].shape, p[10].shape) {
            (Shape::Polygon(a), Shape::Polygon(b)) => {
                let pool = view.vertices();
                assert_eq!(a.vertices(pool)[2], Vec3::new(4.0, 3.0, 3.0));
                assert_eq!(
                    b.vertices(pool),
                    [Vec3::new(-3.6, 2.8, 0.3), Vec3::new(-2.4, 2.8, 0.3), Vec3::new(-3.0, 2.8, 1.5)]
                );
                assert_eq!(b.vertex_normals(pool)[2], Vec3::new(0.0, -1.0, 0.6).normalize_or_zero());
            }
            _ => unreachable!(),
        }
    }

    /// Writes a scene back as NFF (with `fx` materials and explicit light
    /// colours, so nothing depends on defaults).
    fn write_nff(view: &crate::scene::SceneView<'_, f32>, cam: &NffCamera) -> String {
        let mut out = String::new();
        let v = |a: Vec3<f32>| format!("{} {} {}", a.x, a.y, a.z);
        let b = view.background();
        out += &format!(
            "b {}\nv\nfrom {} {} {}\nat {} {} {}\nup {} {} {}\n",
            v(b),
            cam.from[0],
            cam.from[1],
            cam.from[2],
            cam.at[0],
            cam.at[1],
            cam.at[2],
            cam.up[0],
            cam.up[1],
            cam.up[2]
        );
        out += &format!("angle {}\nhither {}\nresolution {} {}\n", cam.angle, cam.hither, cam.width, cam.height);
        for l in view.lights() {
            out += &format!("l {} {}\n", v(l.position), v(l.color));
        }
        // Each object gets its material in front of it.
        let pool = view.vertices();
        for p in view.primitives() {
            let m = view.materials()[p.material as usize];
            out += &format!("fx {} {} {} {} {} {} {} {}\n", v(m.color), m.ka, m.kd, m.ks, m.shine, m.kr, m.kt, m.ior);
            match p.shape {
                Shape::Sphere(s) => out += &format!("s {} {}\n", v(s.center()), s.radius()),
                Shape::Plane(pl) => out += &format!("pl {} {}\n", v(pl.normal_vector()), pl.offset()),
                Shape::AaBox(bx) => out += &format!("box {} {}\n", v(bx.min()), v(bx.max())),
                Shape::OrientedBox(o) => {
                    let (u, w, _) = o.axes();
                    out += &format!("obox {} {} {} {}\n", v(o.center()), v(o.half_extents()), v(u), v(w));
                }
                Shape::Quadric(q) => {
                    let k = q.coefficients().map(|c| c.to_string()).join(" ");
                    match q.clip_box() {
                        Some((lo, hi)) => out += &format!("q {k} {} {}\n", v(lo), v(hi)),
                        None => out += &format!("q {k}\n"),
                    }
                }
                Shape::Cone(c) => {
                    let (b0, r0, a0, r1) = c.ends();
                    out += &format!("c\n{} {}\n{} {}\n", v(b0), r0, v(a0), r1);
                }
                Shape::Polygon(pg) => {
                    let vs = pg.vertices(pool);
                    if pg.is_patch() {
                        out += &format!("pp {}\n", vs.len());
                        for (a, n) in vs.iter().zip(pg.vertex_normals(pool)) {
                            out += &format!("{} {}\n", v(*a), v(*n));
                        }
                    } else {
                        out += &format!("p {}\n", vs.len());
                        for a in vs {
                            out += &format!("{}\n", v(*a));
                        }
                    }
                }
            }
        }
        out
    }

    #[test]
    fn round_trip_of_every_entity() {
        let mut first: Scene<f32, 64, 256, 64, 8> = Scene::new();
        let info = parse(EXTENSIONS, &mut first).unwrap();
        let cam = info.camera.unwrap();
        let text = write_nff(&first.view(), &cam);
        let mut second: Scene<f32, 64, 256, 64, 8> = Scene::new();
        let info2 = parse(&text, &mut second).unwrap();
        assert_eq!(info2.camera, info.camera);
        let (a, b) = (first.view(), second.view());
        assert_eq!(a.background(), b.background());
        assert_eq!(a.lights(), b.lights());
        assert_eq!(a.vertices(), b.vertices());
        assert_eq!(a.primitives().len(), b.primitives().len());
        for (k, (p, q)) in a.primitives().iter().zip(b.primitives()).enumerate() {
            assert_eq!(a.material_of(k as u32), b.material_of(k as u32));
            // Planes and oriented boxes normalize their (already unit)
            // vectors again: equal to the last bits or within an ulp.
            match (p.shape, q.shape) {
                (Shape::Plane(x), Shape::Plane(y)) => {
                    assert!(
                        (x.normal_vector() - y.normal_vector()).length() <= 1e-7
                            && (x.offset() - y.offset()).abs() <= 1e-7
                    );
                }
                (Shape::OrientedBox(x), Shape::OrientedBox(y)) => {
                    let ((u0, v0, w0), (u1, v1, w1)) = (x.axes(), y.axes());
                    assert_eq!((x.center(), x.half_extents()), (y.center(), y.half_extents()));
                    assert!((u0 - u1).length() <= 1e-6 && (v0 - v1).length() <= 1e-6 && (w0 - w1).length() <= 1e-6);
                }
                _ => assert_eq!(p.shape, q.shape, "primitive {k}"),
            }
        }
    }

    #[test]
    fn every_primitive_entity_is_one_primitive_in_file_order() {
        let (s, _) = parse_str(EXTENSIONS).unwrap();
        let v = s.view();
        assert_eq!(v.count(ShapeKind::Quadric), 2);
        assert_eq!(v.primitives().len(), scan(EXTENSIONS).unwrap().counts.primitives());
        // A zero-area polygon is kept (and counted) so indices stay stable.
        let (s, _) = parse_str(&format!("{F}p 3\n0 0 0\n1 0 0\n2 0 0\ns 0 0 0 1\n")).unwrap();
        assert_eq!((s.len(), s.degenerate_polygons()), (2, 1));
    }
}
