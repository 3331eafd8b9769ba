//! Measures which fixed-point format the tracer needs: renders scenes with
//! emulated formats of various integer/fraction splits and with the real
//! [`raypack::Fixed`] (32.32), and prints PSNR and ID-AOV agreement against
//! the `f32` render of the same scene.
//!
//! ```sh
//! cargo run --release --example fixed_formats -- 160 120      # demo scene, every format
//! cargo run --release --example fixed_formats -- 0 0 tests/scenes/*-1.nff  # files at their resolution
//! ```
//!
//! The emulation `Q<F, B>` is a `B`-bit two's-complement number with `F`
//! fractional bits, stored in an `i64`: every operation is computed exactly
//! in 128 bits, rounded to nearest and saturated to `B` bits: the best a
//! `B`-bit format can do with wide intermediates. Its `powf` goes through
//! `f64` (also a best case); `Fixed` uses its own integer `powf`. Emulated
//! formats skip the range check, so they show what happens without it.

use raypack::demo::{demo_camera, demo_scene};
use raypack::prelude::*;

#[derive(Clone, Copy, Debug, PartialEq, PartialOrd, Default)]
struct Q<const F: u32, const B: u32>(i64);

impl<const F: u32, const B: u32> Q<F, B> {
    const RAW_MAX: i64 = if B >= 64 { i64::MAX } else { (1i64 << (B - 1)) - 1 };
    fn sat(v: i128) -> Self {
        Q(v.clamp(-(Self::RAW_MAX as i128), Self::RAW_MAX as i128) as i64)
    }
    fn from_f64(v: f64) -> Self {
        if v.is_nan() {
            return Q(0);
        }
        let s = (v * (1u64 << F) as f64).round();
        Self::sat(s.clamp(-1.0e30, 1.0e30) as i128)
    }
    fn to_f64(self) -> f64 {
        self.0 as f64 / (1u64 << F) as f64
    }
}

impl<const F: u32, const B: u32> core::ops::Add for Q<F, B> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::sat(self.0 as i128 + o.0 as i128)
    }
}
impl<const F: u32, const B: u32> core::ops::Sub for Q<F, B> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::sat(self.0 as i128 - o.0 as i128)
    }
}
impl<const F: u32, const B: u32> core::ops::Neg for Q<F, B> {
    type Output = Self;
    fn neg(self) -> Self {
        Self::sat(-(self.0 as i128))
    }
}
impl<const F: u32, const B: u32> core::ops::Mul for Q<F, B> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let p = self.0 as i128 * o.0 as i128;
        Self::sat((p + (1i128 << (F - 1))) >> F)
    }
}
impl<const F: u32, const B: u32> core::ops::Div for Q<F, B> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        if o.0 == 0 {
            return Self::sat(self.0.signum() as i128 * Self::RAW_MAX as i128);
        }
        let n = (self.0 as i128) << F;
        let (q, r) = (n / o.0 as i128, n % o.0 as i128);
        let q = if 2 * r.abs() >= (o.0 as i128).abs() { q + if (r < 0) == (o.0 < 0) { 1 } else { -1 } } else { q };
        Self::sat(q)
    }
}

impl<const F: u32, const B: u32> Scalar for Q<F, B> {
    const ZERO: Self = Q(0);
    const ONE: Self = Q(1 << F);
    const HALF: Self = Q(1 << (F - 1));
    const TWO: Self = Q(2 << F);
    const MAX: Self = Q(Self::RAW_MAX);
    const RAY_EPSILON: Self = Q((1.0e-4 * (1u64 << F) as f64 + 0.5) as i64);
    const MIN_WEIGHT: Self = Q((1 << F) / 512);
    fn from_f32(v: f32) -> Self {
        Self::from_f64(v as f64)
    }
    fn from_i32(v: i32) -> Self {
        Self::sat((v as i128) << F)
    }
    fn to_f32(self) -> f32 {
        self.to_f64() as f32
    }
    fn sqrt(self) -> Self {
        if self.0 <= 0 {
            return Q(0);
        }
        let n = (self.0 as u128) << F;
        let r = n.isqrt();
        let r = if n - r * r > r { r + 1 } else { r };
        Self::sat(r as i128)
    }
    fn powf(self, e: Self) -> Self {
        Self::from_f64(libm::pow(self.to_f64(), e.to_f64()))
    }
    fn floor_to_i32(self) -> i32 {
        (self.0 >> F).clamp(i32::MIN as i64, i32::MAX as i64) as i32
    }
    fn is_finite(self) -> bool {
        true
    }
}

type Big<S> = Scene<S, 16384, 65536, 64, 16>;

/// Colour and ID renders (width 8, through a BVH when `bvh` is set).
fn render<S: Scalar>(scene: &SceneView<'_, S>, camera: Camera<S>, bvh: bool) -> (Vec<Rgb8>, Vec<Rgb8>) {
    let mut tree = Box::new(Bvh::<S, 16384>::new());
    let accel = if bvh {
        tree.build(scene).unwrap();
        AccelChoice::Bvh(tree.view())
    } else {
        AccelChoice::BruteForce
    };
    let tracer = Tracer::<S, _>::with_accelerator(*scene, accel, TraceSettings::default()).unwrap();
    let mut out = Vec::new();
    for aov in [Aov::Color, Aov::Id] {
        let renderer = Renderer { tracer, camera, aov, sampling: Sampling::Centre };
        let mut img = vec![[0u8; 3]; (camera.width() * camera.height()) as usize];
        let mut stats = RayStats::default();
        renderer.render_rect::<8>(camera.full_rect(), &mut img, &mut stats).unwrap();
        out.push(img);
    }
    let id = out.pop().unwrap();
    (out.pop().unwrap(), id)
}

/// Renders the demo scene (`text` empty) or an NFF file with scalar `S`.
fn render_any<S: Scalar>(text: &str, w: u32, h: u32) -> Result<(Vec<Rgb8>, Vec<Rgb8>), String> {
    if text.is_empty() {
        let scene = demo_scene::<S>().unwrap();
        return Ok(render(&scene.view(), demo_camera::<S>(w, h).unwrap(), false));
    }
    let mut scene = Box::new(Big::<S>::new());
    let info = raypack::nff::parse(text, &mut *scene).map_err(|e| e.to_string())?;
    let cam = info.camera.ok_or("no camera")?;
    let (w, h) = if w == 0 { (cam.width, cam.height) } else { (w, h) };
    let camera = cam.camera::<S>(w, h).map_err(|e| e.to_string())?;
    // Report (but do not enforce) the range check, so the emulated formats
    // show what happens without it.
    if let Err(e) = scene.view().check_range(camera.eye()) {
        eprintln!("  (range check: {e})");
    }
    Ok(render(&scene.view(), camera, true))
}

fn psnr(a: &[Rgb8], b: &[Rgb8]) -> f64 {
    let se: f64 = a.iter().zip(b).map(|(p, q)| (0..3).map(|c| (p[c] as f64 - q[c] as f64).powi(2)).sum::<f64>()).sum();
    let mse = se / (3 * a.len()) as f64;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0 * 255.0 / mse).log10()
    }
}

fn agreement(a: &[Rgb8], b: &[Rgb8]) -> f64 {
    a.iter().zip(b).filter(|(p, q)| p == q).count() as f64 / a.len() as f64
}

fn cell<S: Scalar>(text: &str, w: u32, h: u32, reference: &(Vec<Rgb8>, Vec<Rgb8>)) -> String {
    match render_any::<S>(text, w, h) {
        Ok((c, id)) => format!("{:.2} dB / {:.3} %", psnr(&reference.0, &c), 100.0 * agreement(&reference.1, &id)),
        Err(e) => format!("error: {e}"),
    }
}

fn run(args: Vec<String>) {
    let w: u32 = args.first().and_then(|s| s.parse().ok()).unwrap_or(160);
    let h: u32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(120);
    let files: Vec<String> = args.iter().skip(2).cloned().collect();
    println!("PSNR of the colour image / ID-AOV agreement, against f32 (size {w}×{h}; 0 = the file's resolution)\n");
    if files.is_empty() {
        let reference = render_any::<f32>("", w, h).unwrap();
        println!("| format | demo scene |\n| --- | --- |");
        println!("| I16F16 (32-bit) | {} |", cell::<Q<16, 32>>("", w, h, &reference));
        println!("| I20F12 (32-bit) | {} |", cell::<Q<12, 32>>("", w, h, &reference));
        println!("| I24F24 (48-bit) | {} |", cell::<Q<24, 48>>("", w, h, &reference));
        println!("| I40F24 (64-bit) | {} |", cell::<Q<24, 64>>("", w, h, &reference));
        println!("| I24F40 (64-bit) | {} |", cell::<Q<40, 64>>("", w, h, &reference));
        println!("| I32F32 (64-bit, emulated) | {} |", cell::<Q<32, 64>>("", w, h, &reference));
        println!("| raypack::Fixed (I32F32) | {} |", cell::<Fixed>("", w, h, &reference));
        return;
    }
    println!("| scene | Fixed (I32F32) | I16F16 (emulated) |\n| --- | --- | --- |");
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap_or_else(|e| panic!("{f}: {e}"));
        let name = std::path::Path::new(&f).file_stem().unwrap().to_string_lossy().into_owned();
        let reference = match render_any::<f32>(&text, w, h) {
            Ok(r) => r,
            Err(e) => {
                println!("| {name} | error: {e} | |");
                continue;
            }
        };
        println!("| {name} | {} | {} |", cell::<Fixed>(&text, w, h, &reference), cell::<Q<16, 32>>(&text, w, h, &reference));
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    // The scenes and trees are built in place: give them a big stack.
    std::thread::Builder::new().stack_size(512 << 20).spawn(move || run(args)).unwrap().join().unwrap();
}
