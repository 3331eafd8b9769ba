//! The preview's state machine, in fixed memory and without `unsafe`: a
//! scene is loaded (NFF text or the demo scene, `f32` or the Q8.24
//! fixed point), a render is set up (size, packet width, AOV, output
//! format), then rendered band by band; each band leaves its pixels as
//! RGBA (for a canvas) and as the output stream (RGB888, or the RGB565
//! a panel receives, Bayer 4×4 dithered, high byte first), and folds them
//! into the FNV-1a checksums of `targets/checksums.txt` and
//! `Renderer::checksums`.
//!
//! Every step follows the `raypack` command line (`src/host/image.rs`):
//! the same reading order (`scan`, then `parse`), the same fixed-point
//! frame, the same BVH settings and the same error text, so a scene gives
//! the CLI's bytes, rays and one-line errors.

use core::fmt::Write;
use raypack::demo::{build_demo_scene, demo_camera_for, DemoScene, DEMO_VIEW};
use raypack::geom::camera::{Camera, Rect};
use raypack::geom::uniform_scale::Similarity;
use raypack::nff::{self, NffInfo};
use raypack::output::{rgb565, Fnv1a, RectPositions, CHECKSUM_DITHER};
use raypack::prelude::*;
use raypack::Fixed32;

/// Primitives a scene may hold (the command line's second capacity tier:
/// every SPD scene of `tests/scenes` fits, the largest, sombrero-1, holds
/// 1 922).
pub const MAX_PRIMITIVES: usize = 1 << 14;
/// Vertex-pool slots (gears-2 uses 6 916).
pub const MAX_VERTICES: usize = 1 << 17;
/// Materials (lattice-1 has 20).
pub const MAX_MATERIALS: usize = 1024;
/// Lights (tree-1 and tree-2 have 7).
pub const MAX_LIGHTS: usize = 256;
/// Bytes of NFF text (gears-2, the largest test scene, is 162 KB).
pub const MAX_TEXT: usize = 4 << 20;
/// Largest image side.
pub const MAX_SIDE: u32 = 4096;
/// Largest band, in rows.
pub const MAX_BAND_ROWS: u32 = 16;
/// Pixels of the largest band.
pub const BAND_PIXELS: usize = MAX_SIDE as usize * MAX_BAND_ROWS as usize;
/// Size of the demo image when none is asked for (the firmware's frame,
/// whose checksums `targets/checksums.txt` records).
pub const DEMO_SIZE: (u32, u32) = (160, 128);
/// Bytes of the message buffer (longer messages are cut at a character).
pub const MESSAGE_BYTES: usize = 1024;
/// The tracer's ray stack (the command line's default depth, 5, fits).
const DEPTH: usize = 8;

type SceneOf<S> = Scene<S, MAX_PRIMITIVES, MAX_VERTICES, MAX_MATERIALS, MAX_LIGHTS>;
type BvhOf<S> = Bvh<S, MAX_PRIMITIVES>;

/// The number type a scene is loaded with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScalarKind {
    /// 32-bit IEEE float (packed into `simd128` vectors at packet width 4).
    F32,
    /// Q8.24 fixed point, what FPU-less firmware runs (one ray per packet,
    /// as the command line traces it).
    Fixed32,
}

impl ScalarKind {
    /// 0 is `f32`, 1 is `fixed32`.
    pub fn from_code(code: u32) -> Option<Self> {
        match code {
            0 => Some(ScalarKind::F32),
            1 => Some(ScalarKind::Fixed32),
            _ => None,
        }
    }
}

/// What the output stream holds per pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// `r, g, b`, three bytes.
    Rgb888,
    /// RGB565 with the Bayer 4×4 dither, two bytes, high byte first: what
    /// the panel receives.
    Rgb565,
}

impl Output {
    /// 0 is RGB888, 1 is RGB565.
    pub fn from_code(code: u32) -> Option<Self> {
        match code {
            0 => Some(Output::Rgb888),
            1 => Some(Output::Rgb565),
            _ => None,
        }
    }
    /// Bytes per pixel of the stream.
    pub const fn bytes(self) -> usize {
        match self {
            Output::Rgb888 => 3,
            Output::Rgb565 => 2,
        }
    }
}

/// 0 colour, 1 depth, 2 normal, 3 primitive id (the CLI's `--aov`).
pub fn aov_from_code(code: u32) -> Option<Aov> {
    match code {
        0 => Some(Aov::Color),
        1 => Some(Aov::Depth),
        2 => Some(Aov::Normal),
        3 => Some(Aov::Id),
        _ => None,
    }
}

/// Where the loaded scene lives.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Source {
    /// NFF text, with what the file says (camera, counts).
    Nff(NffInfo),
    /// The built-in demo scene.
    Demo,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Loaded {
    source: Source,
    scalar: ScalarKind,
    /// The fixed-point frame (the identity for `f32`).
    frame: Similarity,
}

/// The camera of a render, in its scalar.
#[derive(Clone, Copy, Debug)]
enum JobCamera {
    F32(Camera<f32>),
    Fixed32(Camera<Fixed32>),
}

/// A render in progress.
#[derive(Clone, Copy, Debug)]
struct Job {
    camera: JobCamera,
    width: u32,
    height: u32,
    packet: usize,
    aov: Aov,
    output: Output,
    next_row: u32,
    rgb888: Fnv1a,
    rgb565: Fnv1a,
    stats: RayStats,
}

/// A band just rendered: its first row and its number of rows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Band {
    /// First row.
    pub y: u32,
    /// Rows (0: the image is complete).
    pub rows: u32,
}

/// The message of the last failure, in fixed memory.
pub struct Message {
    bytes: [u8; MESSAGE_BYTES],
    len: usize,
}

impl Message {
    const fn new() -> Self {
        Message { bytes: [0; MESSAGE_BYTES], len: 0 }
    }
    /// The text (UTF-8).
    pub fn as_bytes(&self) -> &[u8] {
        self.bytes.get(..self.len).unwrap_or(&[])
    }
    /// The text.
    pub fn as_str(&self) -> &str {
        core::str::from_utf8(self.as_bytes()).unwrap_or("")
    }
    /// Replaces the text.
    pub fn set(&mut self, text: core::fmt::Arguments<'_>) {
        self.len = 0;
        // Writing into the buffer cannot fail (it cuts instead).
        let _ = self.write_fmt(text);
    }
}

impl Message {
    /// Replaces the text by a fixed one, without `core::fmt` (the render
    /// path's messages: it keeps formatting, and its panic paths, out of
    /// the render path).
    pub fn set_static(&mut self, text: &'static str) {
        self.len = 0;
        let _ = self.write_str(text);
    }
}

impl Write for Message {
    /// Appends what fits, whole characters only.
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        for (at, c) in s.char_indices() {
            let end = at + c.len_utf8();
            let (Some(src), Some(dst)) =
                (s.as_bytes().get(at..end), self.bytes.get_mut(self.len..self.len + (end - at)))
            else {
                break;
            };
            dst.copy_from_slice(src);
            self.len += end - at;
        }
        Ok(())
    }
}

/// Why a step failed; the text is in [`Preview::message`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Failed;

/// The preview's large memory, about 20 MB: input text, the scenes and
/// trees of both scalars, the band buffers. Every field starts as zeros,
/// so a `static` of it is zero-filled memory, not bytes in the module.
pub struct Memory {
    /// NFF text is written here before [`Preview::load_nff`].
    pub text: [u8; MAX_TEXT],
    /// The `f32` scene; for `fixed32`, the file read in `f32` before it is
    /// converted into the fixed-point frame.
    f32_scene: SceneOf<f32>,
    fixed_scene: SceneOf<Fixed32>,
    f32_bvh: BvhOf<f32>,
    fixed_bvh: BvhOf<Fixed32>,
    /// The demo scene, built in `f32` (for `fixed32`, converted into
    /// `fixed_scene` as a file is).
    demo_f32: DemoScene<f32>,
    band: [Rgb8; BAND_PIXELS],
    /// The last band as RGBA (what a canvas shows: RGB565 expanded back to
    /// 8 bits per channel by bit replication), row-major.
    pub rgba: [u8; BAND_PIXELS * 4],
    /// The last band in the output format, row-major.
    pub stream: [u8; BAND_PIXELS * 3],
}

impl Memory {
    /// Empty scenes and trees, zeroed buffers.
    pub const fn new() -> Self {
        Memory {
            text: [0; MAX_TEXT],
            f32_scene: Scene::new(),
            fixed_scene: Scene::new(),
            f32_bvh: Bvh::new(),
            fixed_bvh: Bvh::new(),
            demo_f32: Scene::new(),
            band: [[0; 3]; BAND_PIXELS],
            rgba: [0; BAND_PIXELS * 4],
            stream: [0; BAND_PIXELS * 3],
        }
    }
}

impl Default for Memory {
    fn default() -> Self {
        Self::new()
    }
}

/// What is loaded and rendering, and the last message: the small state.
pub struct State {
    loaded: Option<Loaded>,
    job: Option<Job>,
    stream_len: usize,
    last: Band,
    /// The text of the last failure.
    pub message: Message,
}

impl State {
    /// Nothing loaded.
    pub const fn new() -> Self {
        State { loaded: None, job: None, stream_len: 0, last: Band { y: 0, rows: 0 }, message: Message::new() }
    }
}

impl Default for State {
    fn default() -> Self {
        Self::new()
    }
}

/// The preview: its memory and its state (two `static`s in the module; boxes
/// in the host tests).
pub struct Preview<'a> {
    /// The large buffers.
    pub mem: &'a mut Memory,
    /// The state.
    pub state: &'a mut State,
}

impl Preview<'_> {
    /// Records a failure and returns it.
    fn fail(&mut self, text: core::fmt::Arguments<'_>) -> Failed {
        self.state.message.set(text);
        Failed
    }

    /// Reads the first `len` bytes of [`Memory::text`] as an NFF scene,
    /// with `scalar`, and builds its BVH: the command line's steps, errors
    /// and settings (`with_scene` in `src/host/image.rs`).
    pub fn load_nff(&mut self, len: usize, scalar: ScalarKind) -> Result<(), Failed> {
        self.state.loaded = None;
        self.state.job = None;
        let Some(bytes) = self.mem.text.get(..len) else {
            return Err(
                self.fail(format_args!("the scene is {len} bytes; the browser preview reads at most {MAX_TEXT} bytes"))
            );
        };
        let Ok(text) = core::str::from_utf8(bytes) else {
            // What `std::fs::read_to_string` says, as the CLI prints it.
            self.state.message.set(format_args!("stream did not contain valid UTF-8"));
            return Err(Failed);
        };
        // Checked completely before anything is built, as the CLI does.
        if let Err(e) = nff::scan(text) {
            return Err(self.fail(format_args!("{e}")));
        }
        self.mem.f32_scene.clear();
        self.mem.fixed_scene.clear();
        let info = match nff::parse(text, &mut self.mem.f32_scene) {
            Ok(info) => info,
            Err(e) => {
                // Only a capacity can fail here (scan accepted the text):
                // say that the limit is the preview's.
                self.state.message.set(format_args!(
                    "{e} (the browser preview holds {MAX_PRIMITIVES} primitives, {MAX_VERTICES} vertex slots, \
                     {MAX_MATERIALS} materials and {MAX_LIGHTS} lights; the raypack command line holds more)"
                ));
                return Err(Failed);
            }
        };
        let eye = info.camera.map(|c| Vec3::new(c.from[0], c.from[1], c.from[2]));
        let frame = match scalar {
            ScalarKind::F32 => Similarity::IDENTITY,
            ScalarKind::Fixed32 => {
                // Read in f32, in the file's units, then converted into the
                // fixed point's frame: the box of the bounded primitives and
                // the eye, centred, its largest half-extent SCENE_FRAME.
                let half = <Fixed32 as Scalar>::SCENE_FRAME.unwrap_or(1.0);
                let frame = self.mem.f32_scene.view().fitting_frame(eye, half);
                if let Err(e) = self.mem.fixed_scene.add_similar(&self.mem.f32_scene.view(), &frame) {
                    return Err(self.fail(format_args!("in the fixed-point frame: {e}")));
                }
                frame
            }
        };
        // Boxes padded for rays that start as far out as the eye (in the
        // scene's frame), as the CLI builds them.
        let reach = eye.map_or(0.0, |e| frame.point::<f32, f32>(e).max_abs());
        self.build_tree(scalar, false, reach)?;
        self.state.loaded = Some(Loaded { source: Source::Nff(info), scalar, frame });
        Ok(())
    }

    /// Loads the built-in demo scene (the firmware's scene) with `scalar`.
    pub fn load_demo(&mut self, scalar: ScalarKind) -> Result<(), Failed> {
        self.state.loaded = None;
        self.state.job = None;
        self.mem.demo_f32.clear();
        self.mem.fixed_scene.clear();
        // `build_demo_scene_for` of the core, with the fixed-point copy in
        // the preview's one fixed-point scene: built in f32 where it lies,
        // then (fixed32) converted into the frame that fits it and the eye,
        // as a file is (one conversion in the module, not two).
        let (e, _, _, _) = DEMO_VIEW;
        let eye = Vec3::new(e[0], e[1], e[2]);
        let built = build_demo_scene(&mut self.mem.demo_f32).and_then(|()| match scalar {
            ScalarKind::F32 => Ok(Similarity::IDENTITY),
            ScalarKind::Fixed32 => self.mem.fixed_scene.add_in_frame(&self.mem.demo_f32.view(), Some(eye)),
        });
        let frame = match built {
            Ok(f) => f,
            Err(e) => return Err(self.fail(format_args!("demo scene: {e}"))),
        };
        let reach = frame.point::<f32, f32>(eye).max_abs();
        self.build_tree(scalar, true, reach)?;
        self.state.loaded = Some(Loaded { source: Source::Demo, scalar, frame });
        Ok(())
    }

    /// Builds the BVH of the scene just loaded (the demo's, or the file's).
    fn build_tree(&mut self, scalar: ScalarKind, demo: bool, reach: f32) -> Result<(), Failed> {
        let settings = BuildSettings { reach, ..BuildSettings::default() };
        let built = match (scalar, demo) {
            (ScalarKind::F32, false) => self.mem.f32_bvh.build_with(&self.mem.f32_scene.view(), &settings),
            (ScalarKind::F32, true) => self.mem.f32_bvh.build_with(&self.mem.demo_f32.view(), &settings),
            (ScalarKind::Fixed32, _) => self.mem.fixed_bvh.build_with(&self.mem.fixed_scene.view(), &settings),
        };
        match built {
            Ok(_) => Ok(()),
            Err(e) => Err(self.fail(format_args!("{e}"))),
        }
    }

    /// The scene's own image size (`resolution`; the demo: [`DEMO_SIZE`]),
    /// if a scene with a camera is loaded.
    pub fn scene_size(&self) -> Option<(u32, u32)> {
        match self.state.loaded?.source {
            Source::Demo => Some(DEMO_SIZE),
            Source::Nff(info) => info.camera.map(|c| (c.width, c.height)),
        }
    }

    /// Primitives of the loaded scene.
    pub fn primitives(&self) -> usize {
        match self.state.loaded {
            None => 0,
            Some(l) => match (l.source, l.scalar) {
                (Source::Demo, ScalarKind::F32) => self.mem.demo_f32.len(),
                (Source::Nff(_), ScalarKind::F32) => self.mem.f32_scene.len(),
                (_, ScalarKind::Fixed32) => self.mem.fixed_scene.len(),
            },
        }
    }

    /// Sets up a render of the loaded scene: `width × height` (0 for either:
    /// the scene's size, or the size that keeps its aspect ratio, as the
    /// CLI's `--width`/`--height`), packets of `packet` rays (1 or 4; the
    /// fixed point traces one ray per packet, as the CLI does), `aov`,
    /// `output`. Whitted ray tracing to depth 5, as the CLI's default.
    pub fn setup(&mut self, width: u32, height: u32, packet: u32, aov: Aov, output: Output) -> Result<(), Failed> {
        self.state.job = None;
        self.state.last = Band::default();
        let Some(loaded) = self.state.loaded else {
            return Err(self.fail(format_args!("no scene is loaded")));
        };
        if !matches!(packet, 1 | 4) {
            return Err(self.fail(format_args!("packet width {packet} is not one of 1, 4 (the browser preview)")));
        }
        let Some(file_size) = self.scene_size() else {
            return Err(self.fail(format_args!("the scene has no `v` block (camera)")));
        };
        let (w, h) = image_size(width, height, file_size);
        if !(1..=MAX_SIDE).contains(&w) || !(1..=MAX_SIDE).contains(&h) {
            return Err(self.fail(format_args!(
                "image size {w}x{h}: the browser preview renders 1 to {MAX_SIDE} pixels per side"
            )));
        }
        let camera = match loaded.scalar {
            ScalarKind::F32 => self.camera::<f32>(loaded, w, h).map(JobCamera::F32),
            ScalarKind::Fixed32 => self.camera::<Fixed32>(loaded, w, h).map(JobCamera::Fixed32),
        }?;
        // Fixed point: the whole scene must fit its range (a no-op for f32).
        let range = match (camera, loaded.source) {
            (JobCamera::F32(_), _) => Ok(0.0),
            (JobCamera::Fixed32(c), _) => self.mem.fixed_scene.view().check_range(c.eye()),
        };
        if let Err(e) = range {
            return Err(self.fail(format_args!("{e}")));
        }
        let packet = if loaded.scalar == ScalarKind::F32 { packet as usize } else { 1 };
        self.state.job = Some(Job {
            camera,
            width: w,
            height: h,
            packet,
            aov,
            output,
            next_row: 0,
            rgb888: Fnv1a::new(),
            rgb565: Fnv1a::new(),
            stats: RayStats::default(),
        });
        Ok(())
    }

    /// The camera of `loaded` for a `w × h` image, in the scalar's frame.
    fn camera<S: Scalar>(&mut self, loaded: Loaded, w: u32, h: u32) -> Result<Camera<S>, Failed> {
        let camera = match loaded.source {
            Source::Demo => demo_camera_for::<S>(&loaded.frame, w, h),
            Source::Nff(info) => match info.camera {
                None => return Err(self.fail(format_args!("the scene has no `v` block (camera)"))),
                Some(c) if loaded.scalar == ScalarKind::F32 => c.camera::<S>(w, h),
                Some(c) => Camera::<S>::in_frame(c.from, c.at, c.up, c.angle, w, h, &loaded.frame),
            },
        };
        camera.map_err(|e| self.fail(format_args!("{e}")))
    }

    /// Renders the next band of at most `max_rows` rows (at most
    /// [`MAX_BAND_ROWS`]); returns it (0 rows: the image is complete). Its
    /// pixels are in [`Memory::rgba`] and [`Memory::stream`].
    pub fn render_band(&mut self, max_rows: u32) -> Result<Band, Failed> {
        let (Some(mut job), Some(loaded)) = (self.state.job, self.state.loaded) else {
            self.state.message.set_static("no render is set up");
            return Err(Failed);
        };
        let rows = max_rows.clamp(1, MAX_BAND_ROWS).min(job.height - job.next_row.min(job.height));
        self.state.stream_len = 0;
        self.state.last = Band { y: job.next_row, rows };
        if rows == 0 {
            return Ok(self.state.last);
        }
        let rect = Rect { x: 0, y: job.next_row, w: job.width, h: rows };
        let n = job.width as usize * rows as usize;
        let out = &mut self.mem.band;
        let done = match (job.camera, loaded.source) {
            (JobCamera::F32(c), Source::Nff(_)) => {
                band(self.mem.f32_scene.view(), self.mem.f32_bvh.view(), c, &job, rect, out)
            }
            (JobCamera::F32(c), Source::Demo) => {
                band(self.mem.demo_f32.view(), self.mem.f32_bvh.view(), c, &job, rect, out)
            }
            // (The demo too: converted into the fixed-point scene.)
            (JobCamera::Fixed32(c), _) => {
                band(self.mem.fixed_scene.view(), self.mem.fixed_bvh.view(), c, &job, rect, out)
            }
        };
        match done {
            Ok(stats) => job.stats.merge(&stats),
            Err(e) => {
                self.state.job = None;
                self.state.message.set_static(e.text());
                return Err(Failed);
            }
        }
        let pixels = self.mem.band.get(..n).unwrap_or(&[]);
        let positions = pixels.iter().zip(RectPositions::new(rect)).zip(self.mem.rgba.chunks_exact_mut(4));
        let bpp = job.output.bytes();
        // Element by element (`copy_from_slice` keeps a length check, a
        // panic path, that the render path must not have).
        for (((p, (x, y)), rgba), out) in positions.zip(self.mem.stream.chunks_exact_mut(bpp)) {
            job.rgb888.write(p);
            let panel = rgb565(*p, x, y, CHECKSUM_DITHER);
            let be = panel.to_be_bytes();
            job.rgb565.write(&be);
            let (shown, bytes): ([u8; 4], &[u8]) = match job.output {
                Output::Rgb888 => ([p[0], p[1], p[2], 255], p),
                Output::Rgb565 => (expand565(panel), &be),
            };
            for (d, s) in rgba.iter_mut().zip(shown) {
                *d = s;
            }
            for (d, s) in out.iter_mut().zip(bytes) {
                *d = *s;
            }
        }
        self.state.stream_len = n * bpp;
        job.next_row += rows;
        self.state.job = Some(job);
        Ok(self.state.last)
    }

    /// The band last rendered.
    pub fn last_band(&self) -> Band {
        self.state.last
    }
    /// Bytes of the last band's output stream.
    pub fn stream_len(&self) -> usize {
        self.state.stream_len
    }
    /// Width and height of the render set up, packet width traced with.
    pub fn render_shape(&self) -> Option<(u32, u32, usize)> {
        self.state.job.map(|j| (j.width, j.height, j.packet))
    }
    /// Rays traced so far by the render set up.
    pub fn stats(&self) -> RayStats {
        self.state.job.map_or(RayStats::default(), |j| j.stats)
    }
    /// FNV-1a so far of the RGB888 bytes and of the RGB565 (Bayer 4×4,
    /// high byte first) pixels: once every band is rendered, the values of
    /// `Renderer::checksums` and `targets/checksums.txt`.
    pub fn checksums(&self) -> (u32, u32) {
        self.state.job.map_or((0, 0), |j| (j.rgb888.finish(), j.rgb565.finish()))
    }
    /// Whether every band of the render has been rendered.
    pub fn complete(&self) -> bool {
        self.state.job.is_some_and(|j| j.next_row >= j.height)
    }
}

/// Renders `rect` of the image with the packet width of `job`: a renderer
/// is rebuilt per band from the scene and tree in memory (cheap: views and
/// a copy of the camera), so the render keeps no borrow between calls.
fn band<S: Scalar>(
    view: SceneView<'_, S>,
    tree: BvhView<'_, S>,
    camera: Camera<S>,
    job: &Job,
    rect: Rect,
    out: &mut [Rgb8],
) -> Result<RayStats, BandFailure> {
    // Whitted to depth 5, the CLI's default.
    let settings = TraceSettings::default();
    let tracer = Tracer::<'_, S, _, DEPTH>::with_accelerator(view, tree, settings).map_err(BandFailure::Trace)?;
    let mut renderer = Renderer::new(tracer, camera);
    renderer.aov = job.aov;
    let mut stats = RayStats::default();
    // The rule of the CLI's `packet_used`: only `f32` compiles the wider copy.
    let done = if const { !S::PACKED } || job.packet == 1 {
        renderer.render_rect::<1>(rect, out, &mut stats)
    } else {
        renderer.render_rect::<4>(rect, out, &mut stats)
    };
    done.map_err(|_| BandFailure::Buffer)?;
    Ok(stats)
}

/// Why a band failed (none can happen with the depth and buffers set here;
/// still errors, not panics).
enum BandFailure {
    Trace(TraceError),
    Buffer,
}

impl BandFailure {
    /// The message, fixed text: the render path does not format.
    fn text(&self) -> &'static str {
        match self {
            BandFailure::Trace(TraceError::Depth { .. }) => "internal error: the tracer's depth does not fit",
            BandFailure::Trace(TraceError::Accelerator(_)) => "internal error: the BVH does not match the scene",
            BandFailure::Buffer => "internal error: the band buffer is too small",
        }
    }
}

/// An RGB565 pixel as RGBA with 8 bits per channel, each channel's bits
/// replicated into the low bits (`r8 = r5·8 + r5/4`): 0 stays 0 and the
/// top level becomes 255, as a panel shows them.
pub fn expand565(p: u16) -> [u8; 4] {
    let (r, g, b) = ((p >> 11) as u8 & 31, (p >> 5) as u8 & 63, p as u8 & 31);
    [(r << 3) | (r >> 2), (g << 2) | (g >> 4), (b << 3) | (b >> 2), 255]
}

/// Image size: the file's resolution, or the overrides (0: not given); one
/// override alone keeps the file's aspect ratio (rounded, at least 1, at
/// most 65 535). The rule of the CLI (`raypack::image::image_size`).
pub fn image_size(width: u32, height: u32, file: (u32, u32)) -> (u32, u32) {
    let scaled = |a: u32, num: u32, den: u32| {
        ((a as u64 * num as u64 + den as u64 / 2) / den.max(1) as u64).clamp(1, 65535) as u32
    };
    match (width, height) {
        (0, 0) => file,
        (w, 0) => (w, scaled(w, file.1, file.0)),
        (0, h) => (scaled(h, file.0, file.1), h),
        (w, h) => (w, h),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    extern crate std;
    use std::boxed::Box;

    /// Runs `f` with a fresh preview, on a thread with room for building the
    /// 13.5 MB `Memory` (a debug build makes it on the stack first).
    fn with_preview(f: impl FnOnce(&mut Preview<'_>) + Send + 'static) {
        std::thread::Builder::new()
            .stack_size(64 << 20)
            .spawn(move || {
                let mut mem = Box::new(Memory::new());
                let mut state = Box::new(State::new());
                f(&mut Preview { mem: &mut mem, state: &mut state });
            })
            .unwrap()
            .join()
            .unwrap();
    }

    /// Renders every band; returns the checksums, the rays and the output
    /// stream.
    fn render_all(p: &mut Preview<'_>, rows: u32) -> ((u32, u32), u64, std::vec::Vec<u8>) {
        let mut stream = std::vec::Vec::new();
        let mut next = 0;
        loop {
            let band = p.render_band(rows).unwrap();
            if band.rows == 0 {
                break;
            }
            assert_eq!(band.y, next);
            next += band.rows;
            stream.extend_from_slice(&p.mem.stream[..p.stream_len()]);
        }
        assert!(p.complete());
        (p.checksums(), p.stats().total(), stream)
    }

    fn fnv(bytes: &[u8]) -> u32 {
        let mut h = Fnv1a::new();
        h.write(bytes);
        h.finish()
    }

    #[test]
    fn the_demo_gives_the_firmware_checksums_at_both_widths_and_scalars() {
        with_preview(|p| {
            // The values the host and every board agree on.
            let recorded = include_str!("../../targets/checksums.txt");
            let value = |scalar: &str, key: &str| -> u32 {
                let line = recorded
                    .lines()
                    .find(|l| l.split_whitespace().take(2).eq([scalar, key]))
                    .unwrap_or_else(|| panic!("targets/checksums.txt has no `{scalar} {key}` line"));
                let v = line.split_whitespace().nth(2).unwrap();
                match v.strip_prefix("0x") {
                    Some(hex) => u32::from_str_radix(hex, 16).unwrap(),
                    None => v.parse().unwrap(),
                }
            };
            let expect =
                |name: &str| ((value(name, "rgb888"), value(name, "rgb565-bayer4")), value(name, "rays") as u64);
            for (scalar, (want, rays)) in [(ScalarKind::F32, expect("f32")), (ScalarKind::Fixed32, expect("fixed32"))] {
                for (packet, rows, output) in [(4, 8, Output::Rgb888), (1, 3, Output::Rgb565)] {
                    p.load_demo(scalar).unwrap();
                    p.setup(0, 0, packet, Aov::Color, output).unwrap();
                    assert_eq!(p.render_shape().map(|s| (s.0, s.1)), Some(DEMO_SIZE));
                    let (sums, total, stream) = render_all(p, rows);
                    assert_eq!((sums, total), (want, rays), "{scalar:?} packet {packet}");
                    let streamed = if output == Output::Rgb888 { want.0 } else { want.1 };
                    assert_eq!(fnv(&stream), streamed, "{scalar:?} packet {packet} {output:?}");
                }
            }
        });
    }

    #[test]
    fn bad_scenes_give_the_command_lines_messages() {
        with_preview(|p| {
            let load = |p: &mut Preview<'_>, text: &str| {
                p.mem.text[..text.len()].copy_from_slice(text.as_bytes());
                p.load_nff(text.len(), ScalarKind::F32).map(|_| p.setup(0, 0, 4, Aov::Color, Output::Rgb888))
            };
            assert_eq!(load(p, "f 1 1 1 1 0 0 0 1\ns 0 0 0 one\n"), Err(Failed));
            assert_eq!(p.state.message.as_str(), "line 2, column 9: expected a number, found `one`");
            assert_eq!(load(p, "f 1 1 1 1 0 0 0 1\ns 0 0 0 1\n"), Ok(Err(Failed)));
            assert_eq!(p.state.message.as_str(), "the scene has no `v` block (camera)");
            assert_eq!(p.render_band(8), Err(Failed));
            assert_eq!(p.state.message.as_str(), "no render is set up");
            p.mem.text[..2].copy_from_slice(&[b's', 0xff]);
            assert_eq!(p.load_nff(2, ScalarKind::F32), Err(Failed));
            assert_eq!(p.state.message.as_str(), "stream did not contain valid UTF-8");
            assert_eq!(p.load_nff(MAX_TEXT + 1, ScalarKind::F32), Err(Failed));
            let view = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.01\nresolution 8 6\nf 1 0 0 1 0 0 0 1\n";
            let mut big = std::string::String::from(view);
            for i in 0..=MAX_PRIMITIVES {
                big += &std::format!("s {} 0 0 0.1\n", i % 50);
            }
            assert_eq!(load(p, &big), Err(Failed));
            let m = p.state.message.as_str();
            assert!(m.contains("scene too large: primitive capacity 16384 exceeded (needs 16385)"), "{m}");
            // A good scene after the errors.
            let good = std::format!("{view}l 1 1 5\ns 0 0 0 1\n");
            assert_eq!(load(p, &good), Ok(Ok(())));
            assert_eq!(p.setup(0, 0, 3, Aov::Color, Output::Rgb888), Err(Failed));
            assert_eq!(p.setup(5000, 0, 4, Aov::Color, Output::Rgb888), Err(Failed));
            assert_eq!(p.setup(0, 3, 4, Aov::Depth, Output::Rgb888), Ok(()));
            assert_eq!(p.render_shape(), Some((4, 3, 4)));
        });
    }

    #[test]
    fn messages_are_cut_at_a_character() {
        let mut m = Message::new();
        let long = "é".repeat(MESSAGE_BYTES);
        m.set(format_args!("x{long}"));
        assert_eq!(m.as_bytes().len(), MESSAGE_BYTES - 1);
        assert!(m.as_str().starts_with("xé"));
        m.set_static("fixed");
        assert_eq!(m.as_str(), "fixed");
    }

    #[test]
    fn sizes_follow_the_command_line_and_rgb565_expands_to_the_full_range() {
        assert_eq!(image_size(0, 0, (512, 256)), (512, 256));
        assert_eq!(image_size(100, 0, (512, 256)), (100, 50));
        assert_eq!(image_size(0, 100, (512, 256)), (200, 100));
        assert_eq!(image_size(7, 9, (512, 256)), (7, 9));
        assert_eq!(expand565(0), [0, 0, 0, 255]);
        assert_eq!(expand565(0xffff), [255, 255, 255, 255]);
        assert_eq!(expand565(0xf800), [255, 0, 0, 255]);
        assert_eq!(expand565(0x07e0), [0, 255, 0, 255]);
        // Grouped as the 5-6-5 fields.
        #[allow(clippy::unusual_byte_groupings)]
        let mid = 0b10000_100000_10000;
        assert_eq!(expand565(mid), [132, 130, 132, 255]);
    }
}
