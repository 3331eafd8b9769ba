//! Getting pixels out without a framebuffer: band-by-band rendering, pixel
//! formats (RGB888, RGB565 with ordered dithering) and the FNV-1a checksum
//! the firmware and the host tests use to compare images bit for bit.
//!
//! [`Renderer::render_bands`] renders the whole image a band of rows at a
//! time into one small caller buffer and hands each band to a sink (a display
//! driver, a hasher, a file writer); memory is one band, whatever the image
//! size.
//!
//! ```
//! use raypack::demo::{demo_camera, demo_scene};
//! use raypack::output::{rgb565, Dither, Fnv1a};
//! use raypack::prelude::*;
//!
//! let scene = demo_scene::<f32>().unwrap();
//! let camera = demo_camera::<f32>(32, 24).unwrap();
//! let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
//! let renderer = Renderer::new(tracer, camera);
//! let mut band = [[0u8; 3]; 32 * 2];                // two rows of 32 pixels
//! let mut hash = Fnv1a::new();
//! let mut stats = RayStats::default();
//! renderer
//!     .render_bands::<4, ()>(&mut band, &mut stats, |rect, pixels| {
//!         for (i, p) in pixels.iter().enumerate() {
//!             let (x, y) = (rect.x + i as u32 % rect.w, rect.y + i as u32 / rect.w);
//!             hash.write(&rgb565(*p, x, y, Dither::Bayer4).to_be_bytes());
//!         }
//!         Ok(())
//!     })
//!     .unwrap();
//! assert_eq!(stats.primary, 32 * 24);
//! # let _ = hash.finish();
//! ```

use crate::geom::camera::{packet_shape, Rect};
pub use crate::geom::rect::RectPositions;
use crate::num::scalar::Scalar;
use crate::query::Accelerator;
use crate::render::{BufferTooSmall, Renderer, Rgb8};
use crate::trace::RayStats;

/// The 32-bit FNV-1a hash (Fowler–Noll–Vo, variant 1a): for each byte,
/// `h = (h XOR byte) · 16777619` modulo 2³², starting from `2166136261`.
///
/// Cheap on any 32-bit core (one XOR and one multiply per byte), with no
/// tables; used as the image checksum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fnv1a {
    state: u32,
}

impl Fnv1a {
    /// The FNV-1a 32-bit offset basis.
    pub const OFFSET_BASIS: u32 = 0x811c_9dc5;
    /// The FNV 32-bit prime, `2²⁴ + 2⁸ + 0x93`.
    pub const PRIME: u32 = 0x0100_0193;

    /// A hasher that has seen no bytes.
    pub const fn new() -> Self {
        Fnv1a { state: Self::OFFSET_BASIS }
    }
    /// Folds one byte in.
    #[inline]
    pub fn write_u8(&mut self, byte: u8) {
        self.state = (self.state ^ byte as u32).wrapping_mul(Self::PRIME);
    }
    /// Folds bytes in, in order.
    #[inline]
    pub fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u8(b);
        }
    }
    /// The hash of every byte written so far.
    pub const fn finish(&self) -> u32 {
        self.state
    }
}

impl Default for Fnv1a {
    fn default() -> Self {
        Self::new()
    }
}

/// Ordered dithering used when reducing 8-bit channels to fewer bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Dither {
    /// Round to the nearest level.
    #[default]
    None,
    /// Bayer 4×4 ordered dither (16 thresholds).
    Bayer4,
    /// Bayer 8×8 ordered dither (64 thresholds).
    Bayer8,
}

/// The Bayer index matrix of side `N` (a power of two, at least 2), built by
/// Bayer's recursion `M₂ₙ = [[4Mₙ, 4Mₙ+2], [4Mₙ+3, 4Mₙ+1]]` from `M₁ = [0]`;
/// entry `[y][x]` is the rank of the threshold at pixel `(x mod N, y mod N)`.
const fn bayer_matrix<const N: usize>() -> [[u8; N]; N] {
    let mut m = [[0u8; N]; N];
    let mut n = 1;
    while n < N {
        // Expand the top-left n×n block into 2n×2n, bottom-right quadrant first
        // so the source block is read before it is overwritten.
        let mut y = 0;
        while y < n {
            let mut x = 0;
            while x < n {
                let v = 4 * m[y][x];
                m[y + n][x + n] = v + 1;
                m[y + n][x] = v + 3;
                m[y][x + n] = v + 2;
                m[y][x] = v;
                x += 1;
            }
            y += 1;
        }
        n *= 2;
    }
    m
}

/// The Bayer 4×4 index matrix (`[y][x]`, ranks 0 to 15).
pub const BAYER4: [[u8; 4]; 4] = bayer_matrix::<4>();
/// The Bayer 8×8 index matrix (`[y][x]`, ranks 0 to 63).
pub const BAYER8: [[u8; 8]; 8] = bayer_matrix::<8>();

impl Dither {
    /// `(rank, cells)`: the threshold rank at pixel `(x, y)` and the number
    /// of cells of the matrix; `Dither::None` is the single mid threshold
    /// `(0, 1)`, which makes [`quantize`] round to nearest.
    #[inline]
    pub fn rank(self, x: u32, y: u32) -> (u32, u32) {
        match self {
            Dither::None => (0, 1 << self.cells_log2()),
            Dither::Bayer4 => (BAYER4[(y & 3) as usize][(x & 3) as usize] as u32, 1 << self.cells_log2()),
            Dither::Bayer8 => (BAYER8[(y & 7) as usize][(x & 7) as usize] as u32, 1 << self.cells_log2()),
        }
    }
    /// `log₂` of the number of cells of [`Dither::rank`] (every matrix has a
    /// power-of-two number of cells): 0, 4 (4×4) or 6 (8×8).
    #[inline]
    pub fn cells_log2(self) -> u32 {
        match self {
            Dither::None => 0,
            Dither::Bayer4 => 4,
            Dither::Bayer8 => 6,
        }
    }
}

/// Reduces an 8-bit channel value to `bits` bits (1 to 8) with ordered
/// dithering at pixel `(x, y)`.
///
/// With `m = 2^bits − 1` levels above zero and threshold
/// `τ = (rank + ½)/cells` from the dither matrix, the result is
/// `min(m, floor(v·m/255 + τ))`, computed exactly in integers:
/// `floor((2·cells·m·v + (2·rank + 1)·255) / (2·cells·255))`. Without
/// dithering `τ = ½`, which is rounding to nearest (`v·m/255` is never
/// exactly half-way, as 255 is odd). The average of the dithered output over
/// a matrix tile approximates `v·m/255`.
#[inline]
pub fn quantize(v: u8, bits: u32, dither: Dither, x: u32, y: u32) -> u8 {
    let bits = bits.clamp(1, 8);
    let m = (1u32 << bits) - 1;
    let (rank, cells) = dither.rank(x, y);
    // Largest numerator: 2·64·255·255 + 127·255 < 2²⁴, no overflow.
    let num = 2 * cells * m * v as u32 + (2 * rank + 1) * 255;
    // ⌊num/(2·cells·255)⌋ = ⌊⌊num/(2·cells)⌋/255⌋ (nested floors), the
    // first a shift (cells = 2^c). Its quotient n stays below 2¹⁶ for every
    // matrix (at most 65 278, for Bayer 8×8), and for n < 2¹⁶,
    // ⌊n/255⌋ = ⌊n·0x8081/2²³⌋ (0x8081/2²³ = 1/255 + 1/(255·2²³); checked
    // for every n by `quantize_divides_exactly`), within 32 bits: no
    // division, which costs about 130 instructions on a core without one.
    let n = num >> (dither.cells_log2() + 1);
    let q = (n * 0x8081) >> 23;
    q.min(m) as u8
}

/// An RGB888 pixel reduced to RGB565 (`r` in bits 15–11, `g` in 10–5, `b`
/// in 4–0) with ordered dithering at pixel `(x, y)`; see [`quantize`].
#[inline]
pub fn rgb565(p: Rgb8, x: u32, y: u32, dither: Dither) -> u16 {
    let [r, g, b] = p;
    let r = quantize(r, 5, dither, x, y) as u16;
    let g = quantize(g, 6, dither, x, y) as u16;
    let b = quantize(b, 5, dither, x, y) as u16;
    (r << 11) | (g << 5) | b
}

/// Pixel formats a band can be written out in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelFormat {
    /// Three bytes per pixel, `r, g, b`.
    Rgb888,
    /// Two bytes per pixel (see [`rgb565`]), with the given dithering.
    Rgb565(Dither),
}

impl PixelFormat {
    /// Bytes per pixel.
    pub const fn bytes_per_pixel(self) -> usize {
        match self {
            PixelFormat::Rgb888 => 3,
            PixelFormat::Rgb565(_) => 2,
        }
    }
    /// Encodes the pixel at `(x, y)`; RGB565 is big-endian (high byte
    /// first, as most SPI displays take it). Returns the bytes and how many
    /// of them are used.
    #[inline]
    pub fn encode(self, p: Rgb8, x: u32, y: u32) -> ([u8; 3], usize) {
        match self {
            PixelFormat::Rgb888 => (p, 3),
            PixelFormat::Rgb565(d) => {
                let [hi, lo] = rgb565(p, x, y, d).to_be_bytes();
                ([hi, lo, 0], 2)
            }
        }
    }
}

/// Why [`Renderer::render_bands`] stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BandError<E> {
    /// The band buffer holds less than one image row.
    BufferTooSmall(BufferTooSmall),
    /// The sink returned an error.
    Sink(E),
}

impl<E: core::fmt::Display> core::fmt::Display for BandError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            BandError::BufferTooSmall(b) => write!(f, "band {b}"),
            BandError::Sink(e) => write!(f, "band sink: {e}"),
        }
    }
}

impl<E: core::fmt::Display + core::fmt::Debug> core::error::Error for BandError<E> {}

/// The rows per band that a buffer of `buffer_pixels` pixels holds for an
/// image `width` pixels wide, rounded down to whole packet rows of width-`W`
/// packets when it holds at least one packet row (so no lanes are wasted at
/// band edges); 0 if the buffer holds less than one row.
pub fn band_rows<const W: usize>(width: u32, buffer_pixels: usize) -> u32 {
    if width == 0 {
        return 0;
    }
    let rows = (buffer_pixels / width as usize).min(u32::MAX as usize) as u32;
    let (_, ph) = packet_shape(W);
    if ph > 0 && rows >= ph {
        rows - rows % ph
    } else {
        rows
    }
}

/// Checksums of a whole rendered image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageChecksums {
    /// FNV-1a over the RGB888 bytes, row-major, `r, g, b` per pixel.
    pub rgb888: u32,
    /// FNV-1a over the RGB565 pixels ([`CHECKSUM_DITHER`]), row-major, two
    /// bytes per pixel, high byte first.
    pub rgb565: u32,
    /// Pixels hashed.
    pub pixels: u32,
    /// Rays traced (and the packets that carried them: the packet counts
    /// depend on the packet width, everything else here does not).
    pub rays: RayStats,
}

impl ImageChecksums {
    /// Whether two renders gave the same image and traced the same rays:
    /// every field but the packet counts, so renders at different packet
    /// widths compare equal when they agree.
    pub fn same_render(&self, other: &ImageChecksums) -> bool {
        (self.rgb888, self.rgb565, self.pixels, self.rays.rays())
            == (other.rgb888, other.rgb565, other.pixels, other.rays.rays())
    }
}

/// The dithering used for [`ImageChecksums::rgb565`].
pub const CHECKSUM_DITHER: Dither = Dither::Bayer4;

impl<'a, S: Scalar, A: Accelerator<S>, const D: usize> Renderer<'a, S, A, D> {
    /// Renders the whole image band by band with packets of width `W`: each
    /// band is as many full rows as `band` holds (see [`band_rows`]),
    /// rendered into `band` and passed to `sink` with its rectangle (pixels
    /// row-major, stride = image width). Stops at the first sink error. Ray
    /// counts are added to `stats`.
    pub fn render_bands<const W: usize, E>(
        &self,
        band: &mut [Rgb8],
        stats: &mut RayStats,
        mut sink: impl FnMut(Rect, &[Rgb8]) -> Result<(), E>,
    ) -> Result<(), BandError<E>> {
        let full = self.camera.full_rect();
        let rows = band_rows::<W>(full.w, band.len());
        if rows == 0 {
            return Err(BandError::BufferTooSmall(BufferTooSmall { needed: full.w as usize, provided: band.len() }));
        }
        // Screen culling worked out once for the frame, not per band.
        let mut cull = crate::render::renderer::FrameCull::empty();
        self.frame_cull(&mut cull);
        let mut y = 0;
        while y < full.h {
            let h = rows.min(full.h - y);
            let rect = Rect { x: 0, y, w: full.w, h };
            self.render_rect_culled::<W>(rect, band, &cull, stats).map_err(BandError::BufferTooSmall)?;
            let n = full.w as usize * h as usize;
            // `rows` rows fit in `band`, so this is all of the band's pixels.
            let pixels = band.get(..n).unwrap_or(&[]);
            sink(rect, pixels).map_err(BandError::Sink)?;
            y += h;
        }
        Ok(())
    }

    /// Renders the whole image band by band through `band` (see
    /// [`Renderer::render_bands`]) and returns its checksums: what the
    /// firmware prints and the host tests compare.
    pub fn checksums<const W: usize>(&self, band: &mut [Rgb8]) -> Result<ImageChecksums, BufferTooSmall> {
        let mut h888 = Fnv1a::new();
        let mut h565 = Fnv1a::new();
        let mut pixels = 0u32;
        let mut stats = RayStats::default();
        let r = self.render_bands::<W, core::convert::Infallible>(band, &mut stats, |rect, px| {
            for (p, (x, y)) in px.iter().zip(RectPositions::new(rect)) {
                h888.write(p);
                h565.write(&rgb565(*p, x, y, CHECKSUM_DITHER).to_be_bytes());
                pixels = pixels.wrapping_add(1);
            }
            Ok(())
        });
        match r {
            Ok(()) => Ok(ImageChecksums { rgb888: h888.finish(), rgb565: h565.finish(), pixels, rays: stats }),
            Err(BandError::BufferTooSmall(b)) => Err(b),
            Err(BandError::Sink(never)) => match never {},
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::scene::demo::{demo_camera, demo_scene};
    use crate::trace::{TraceSettings, Tracer};
    use std::vec;
    use std::vec::Vec;

    #[test]
    fn quantize_divides_exactly() {
        // The shift-and-multiply quotient against the division it replaces,
        // for every matrix, bit depth, value and rank (every cell visited).
        for dither in [Dither::None, Dither::Bayer4, Dither::Bayer8] {
            assert_eq!(1u32 << dither.cells_log2(), dither.rank(0, 0).1);
            for bits in 1..=8u32 {
                let m = (1u32 << bits) - 1;
                for v in 0..=255u8 {
                    for y in 0..8 {
                        for x in 0..8 {
                            let (rank, cells) = dither.rank(x, y);
                            let num = 2 * cells * m * v as u32 + (2 * rank + 1) * 255;
                            let want = (num / (2 * cells * 255)).min(m) as u8;
                            assert_eq!(quantize(v, bits, dither, x, y), want, "{dither:?} {bits} {v} {x} {y}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn fnv1a_matches_published_vectors() {
        // Test vectors from the FNV reference (Noll's fnv test suite).
        let h = |s: &[u8]| {
            let mut f = Fnv1a::new();
            f.write(s);
            f.finish()
        };
        assert_eq!(h(b""), 0x811c_9dc5);
        assert_eq!(h(b"a"), 0xe40c_292c);
        assert_eq!(h(b"foobar"), 0xbf9c_f968);
    }

    #[test]
    fn bayer_matrices_are_the_textbook_ones() {
        // Bayer 4×4 as printed in Ulichney, "Digital Halftoning" (1987).
        assert_eq!(BAYER4, [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]]);
        // 8×8: first row as printed in the same literature, every rank once.
        assert_eq!(BAYER8[0], [0, 32, 8, 40, 2, 34, 10, 42]);
        let mut seen = [false; 64];
        for row in BAYER8 {
            for v in row {
                assert!(!seen[v as usize]);
                seen[v as usize] = true;
            }
        }
        // Bayer's recursion: the 8×8 matrix's quadrants are 4·M₄ + (0, 2; 3, 1).
        for y in 0..4 {
            for x in 0..4 {
                let m = 4 * BAYER4[y][x];
                assert_eq!(
                    [BAYER8[y][x], BAYER8[y][x + 4], BAYER8[y + 4][x], BAYER8[y + 4][x + 4]],
                    [m, m + 2, m + 3, m + 1]
                );
            }
        }
    }

    #[test]
    fn quantize_without_dither_rounds_to_nearest() {
        for bits in [5u32, 6] {
            let m = (1u32 << bits) - 1;
            for v in 0..=255u32 {
                let want = (v as f64 * m as f64 / 255.0).round() as u32;
                assert_eq!(quantize(v as u8, bits, Dither::None, 7, 3) as u32, want, "v={v} bits={bits}");
            }
        }
        assert_eq!(rgb565([255, 255, 255], 0, 0, Dither::None), 0xffff);
        assert_eq!(rgb565([0, 0, 0], 5, 9, Dither::Bayer8), 0);
        assert_eq!(rgb565([255, 0, 0], 0, 0, Dither::None), 0xf800);
        assert_eq!(rgb565([0, 255, 0], 0, 0, Dither::None), 0x07e0);
    }

    #[test]
    fn dither_matches_float_definition_and_preserves_the_mean() {
        for (d, n) in [(Dither::Bayer4, 4u32), (Dither::Bayer8, 8)] {
            for v in 0..=255u32 {
                let mut sum = 0u32;
                for y in 0..n {
                    for x in 0..n {
                        let (rank, cells) = d.rank(x, y);
                        let tau = (rank as f64 + 0.5) / cells as f64;
                        let want = ((v as f64 * 31.0 / 255.0 + tau).floor() as u32).min(31);
                        let got = quantize(v as u8, 5, d, x + 8 * n, y + 3 * n) as u32;
                        assert_eq!(got, want, "v={v} x={x} y={y}");
                        sum += got;
                    }
                }
                // The tile mean is within one threshold step of v·31/255.
                let mean = sum as f64 / (n * n) as f64;
                let exact = v as f64 * 31.0 / 255.0;
                assert!((mean - exact).abs() <= 1.0 / (n * n) as f64 + 1e-9 || v == 255, "v={v} mean={mean}");
            }
        }
    }

    #[test]
    fn band_rows_round_to_packet_rows() {
        assert_eq!(band_rows::<8>(10, 35), 2);
        assert_eq!(band_rows::<8>(10, 15), 1);
        assert_eq!(band_rows::<1>(10, 35), 3);
        assert_eq!(band_rows::<8>(10, 9), 0);
        assert_eq!(band_rows::<4>(0, 9), 0);
    }

    #[test]
    fn bands_cover_the_image_like_one_rect_for_every_width_and_band_size() {
        let scene = demo_scene::<f32>().unwrap();
        let camera = demo_camera::<f32>(21, 13).unwrap();
        let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
        let renderer = Renderer::new(tracer, camera);
        let mut full = vec![[0u8; 3]; 21 * 13];
        let mut full_stats = RayStats::default();
        renderer.render_rect::<1>(camera.full_rect(), &mut full, &mut full_stats).unwrap();

        fn check<const W: usize>(renderer: &Renderer<'_, f32>, full: &[Rgb8], band_px: usize) {
            let mut band = vec![[0u8; 3]; band_px];
            let mut out = vec![[9u8; 3]; full.len()];
            let mut stats = RayStats::default();
            let mut next_row = 0;
            renderer
                .render_bands::<W, ()>(&mut band, &mut stats, |r, px| {
                    assert_eq!((r.x, r.w, r.y), (0, 21, next_row));
                    assert_eq!(px.len(), (r.w * r.h) as usize);
                    out[(r.y * 21) as usize..][..px.len()].copy_from_slice(px);
                    next_row += r.h;
                    Ok(())
                })
                .unwrap();
            assert_eq!(next_row, 13);
            assert_eq!(out, full, "W={W} band={band_px}");
            assert_eq!(stats.primary, 21 * 13);
        }
        for band_px in [21, 21 * 2 + 5, 21 * 3, 21 * 13, 21 * 20] {
            check::<1>(&renderer, &full, band_px);
            check::<4>(&renderer, &full, band_px);
            check::<8>(&renderer, &full, band_px);
        }
        let mut tiny = [[0u8; 3]; 20];
        let err = renderer.render_bands::<4, ()>(&mut tiny, &mut RayStats::default(), |_, _| Ok(()));
        assert_eq!(err, Err(BandError::BufferTooSmall(BufferTooSmall { needed: 21, provided: 20 })));
        let err = renderer.render_bands::<4, u8>(&mut band_of(21), &mut RayStats::default(), |_, _| Err(7));
        assert_eq!(err, Err(BandError::Sink(7)));
    }

    #[test]
    fn bands_with_anti_aliasing_equal_one_rect_at_every_width() {
        use crate::render::Sampling;
        let scene = demo_scene::<f32>().unwrap();
        let camera = demo_camera::<f32>(37, 19).unwrap();
        let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
        for sampling in [Sampling::Grid(3), Sampling::adaptive(3, 0.2)] {
            let renderer = Renderer { sampling, ..Renderer::new(tracer, camera) };
            let mut full = vec![[0u8; 3]; 37 * 19];
            renderer.render_rect::<1>(camera.full_rect(), &mut full, &mut RayStats::default()).unwrap();
            let mut plain = vec![[0u8; 3]; 37 * 19];
            Renderer::new(tracer, camera)
                .render_rect::<1>(camera.full_rect(), &mut plain, &mut RayStats::default())
                .unwrap();
            assert_ne!(full, plain, "{sampling:?} changed nothing");
            let one = renderer.checksums::<1>(&mut band_of(37 * 3)).unwrap();
            for c in [
                renderer.checksums::<4>(&mut band_of(37 * 2)).unwrap(),
                renderer.checksums::<8>(&mut band_of(37 * 5)).unwrap(),
                renderer.checksums::<16>(&mut band_of(37 * 19)).unwrap(),
            ] {
                assert_eq!((c.rgb888, c.rgb565), (one.rgb888, one.rgb565), "{sampling:?}");
            }
            let mut h = Fnv1a::new();
            full.iter().for_each(|p| h.write(p));
            assert_eq!(one.rgb888, h.finish(), "{sampling:?}");
        }
    }

    fn band_of(n: usize) -> Vec<Rgb8> {
        vec![[0u8; 3]; n]
    }

    #[test]
    fn checksums_hash_the_pixels_in_row_major_order() {
        let scene = demo_scene::<f32>().unwrap();
        let camera = demo_camera::<f32>(16, 10).unwrap();
        let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).unwrap();
        let renderer = Renderer::new(tracer, camera);
        let mut full = vec![[0u8; 3]; 16 * 10];
        renderer.render_rect::<1>(camera.full_rect(), &mut full, &mut RayStats::default()).unwrap();
        // Independent fold of the full frame.
        let mut a = 0x811c_9dc5u32;
        let mut b = 0x811c_9dc5u32;
        for (i, p) in full.iter().enumerate() {
            for &c in p {
                a = (a ^ c as u32).wrapping_mul(0x0100_0193);
            }
            let (x, y) = ((i % 16) as u32, (i / 16) as u32);
            for c in rgb565(*p, x, y, Dither::Bayer4).to_be_bytes() {
                b = (b ^ c as u32).wrapping_mul(0x0100_0193);
            }
        }
        let c = renderer.checksums::<8>(&mut band_of(16 * 3)).unwrap();
        assert_eq!((c.rgb888, c.rgb565, c.pixels), (a, b, 160));
        assert_eq!(c.rays.primary, 160);
        let one = renderer.checksums::<1>(&mut band_of(16)).unwrap();
        assert!(one.same_render(&c), "{one:?} vs {c:?}");
        // Only the packet counts differ between widths.
        assert_ne!(one, c);
        assert_eq!(ImageChecksums { rays: c.rays, ..one }, c);
    }
}
