//! Measures which fixed-point format the tracer needs: renders scenes with
//! emulated formats of various integer/fraction splits and with the real
//! [`raypack::Fixed`] (32.32), and prints PSNR and ID-AOV agreement against
//! the `f32` render of the same scene.
//!
//! ```sh
//! cargo run --release --example fixed_formats -- [WIDTH HEIGHT] [scene.nff ...]
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

/// A scene and its camera in any scalar: the demo scene, or an NFF file when
/// the crate has a reader.
fn render<S: Scalar>(scene: &SceneView<'_, S>, camera: Camera<S>, aov: Aov) -> Vec<Rgb8> {
    let tracer: Tracer<S> = Tracer::new(*scene, TraceSettings::default()).unwrap();
    let renderer = Renderer { tracer, camera, aov };
    let mut img = vec![[0u8; 3]; (camera.width() * camera.height()) as usize];
    let mut stats = RayStats::default();
    renderer.render_rect::<8>(camera.full_rect(), &mut img, &mut stats).unwrap();
    img
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

fn measure<S: Scalar>(name: &str, w: u32, h: u32, reference: &(Vec<Rgb8>, Vec<Rgb8>)) {
    let scene = demo_scene::<S>().unwrap();
    let camera = demo_camera::<S>(w, h).unwrap();
    let c = render(&scene.view(), camera, Aov::Color);
    let id = render(&scene.view(), camera, Aov::Id);
    println!("| {name} | {:.2} | {:.3} % |", psnr(&reference.0, &c), 100.0 * agreement(&reference.1, &id));
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let w: u32 = args.first().and_then(|s| s.parse().ok()).unwrap_or(160);
    let h: u32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(120);
    let sf = demo_scene::<f32>().unwrap();
    let cf = demo_camera::<f32>(w, h).unwrap();
    let reference = (render(&sf.view(), cf, Aov::Color), render(&sf.view(), cf, Aov::Id));
    println!("demo scene, {w}×{h}, against f32:\n");
    println!("| format | PSNR (dB) | ID agreement |\n| --- | --- | --- |");
    measure::<Q<16, 32>>("I16F16 (32-bit)", w, h, &reference);
    measure::<Q<12, 32>>("I20F12 (32-bit)", w, h, &reference);
    measure::<Q<24, 48>>("I24F24 (48-bit)", w, h, &reference);
    measure::<Q<24, 64>>("I40F24 (64-bit)", w, h, &reference);
    measure::<Q<40, 64>>("I24F40 (64-bit)", w, h, &reference);
    measure::<Q<32, 64>>("I32F32 (64-bit, emulated)", w, h, &reference);
    measure::<Fixed>("raypack::Fixed (I32F32)", w, h, &reference);
}
