//! Pixel rectangles: the one home of rectangle arithmetic (clipping,
//! containment, cutting into bands, walking pixels, placing on a target).
//! Everything saturates or is checked: no rectangle arithmetic overflows.

/// A pixel rectangle: columns `x .. x + w`, rows `y .. y + h`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    /// First column.
    pub x: u32,
    /// First row.
    pub y: u32,
    /// Width in pixels.
    pub w: u32,
    /// Height in pixels.
    pub h: u32,
}

impl Rect {
    /// Whether the rectangle has no pixels.
    pub fn is_empty(&self) -> bool {
        self.w == 0 || self.h == 0
    }

    /// Whether `self` is non-empty and lies inside `outer`.
    pub fn inside(&self, outer: Rect) -> bool {
        !self.is_empty()
            && self.x >= outer.x
            && self.y >= outer.y
            && self.x.checked_add(self.w).is_some_and(|e| e <= outer.x.saturating_add(outer.w))
            && self.y.checked_add(self.h).is_some_and(|e| e <= outer.y.saturating_add(outer.h))
    }

    /// The part of `self` inside `to` (empty, `w` or `h` 0, if none).
    pub fn clip(&self, to: Rect) -> Rect {
        let x0 = self.x.max(to.x);
        let y0 = self.y.max(to.y);
        let x1 = self.x.saturating_add(self.w).min(to.x.saturating_add(to.w));
        let y1 = self.y.saturating_add(self.h).min(to.y.saturating_add(to.h));
        Rect { x: x0, y: y0, w: x1.saturating_sub(x0), h: y1.saturating_sub(y0) }
    }

    /// The bands covering `self`, top to bottom: as wide as `self`, cut at
    /// the rows that are multiples of `pitch` (the image's grid, so the
    /// bands of any rectangle line up with those of the whole image).
    pub fn bands(&self, pitch: u32) -> Bands {
        Bands { rect: *self, pitch: pitch.max(1), y: self.y }
    }

    /// The number of [`Rect::bands`] (without walking them).
    pub fn band_count(&self, pitch: u32) -> u64 {
        let p = pitch.max(1) as u64;
        if self.is_empty() {
            return 0;
        }
        (self.y as u64 + self.h as u64).div_ceil(p) - self.y as u64 / p
    }

    /// The pixel positions of the rectangle, row by row.
    pub fn positions(&self) -> RectPositions {
        RectPositions::new(*self)
    }

    /// The part of `self` (image coordinates) that is visible when the
    /// image's top-left pixel is placed at `at` on a target whose visible
    /// area is `clip` (target coordinates: top-left and size): the visible
    /// part in image coordinates and its top-left on the target, or `None`
    /// if nothing is visible. Computed in `i64`, so no placement overflows.
    pub fn placed(&self, at: (i32, i32), clip: ((i32, i32), (u32, u32))) -> Option<(Rect, (i32, i32))> {
        // One axis: the interval [start, start + len) of the image, shifted by
        // `offset`, intersected with [clip_start, clip_start + clip_len).
        let axis = |start: u32, len: u32, offset: i32, clip_start: i32, clip_len: u32| -> Option<(u32, u32, i32)> {
            // Target coordinates are i32: nothing lies past i32::MAX.
            let clip_end = (clip_start as i64 + clip_len as i64).min(i32::MAX as i64 + 1);
            let lo = (offset as i64 + start as i64).max(clip_start as i64);
            let hi = (offset as i64 + start as i64 + len as i64).min(clip_end);
            if hi <= lo {
                return None;
            }
            // `clip_start <= lo < hi <= i32::MAX + 1`, and `lo - offset` is
            // at least `start`: the conversions cannot fail.
            let target_lo = i32::try_from(lo).ok()?;
            let image_lo = u32::try_from(lo - offset as i64).ok()?;
            let len = u32::try_from(hi - lo).ok()?;
            Some((image_lo, len, target_lo))
        };
        let ((cx, cy), (cw, ch)) = clip;
        let (x, w, tx) = axis(self.x, self.w, at.0, cx, cw)?;
        let (y, h, ty) = axis(self.y, self.h, at.1, cy, ch)?;
        Some((Rect { x, y, w, h }, (tx, ty)))
    }
}

/// The bands of a rectangle ([`Rect::bands`]).
#[derive(Clone, Copy, Debug)]
pub struct Bands {
    rect: Rect,
    pitch: u32,
    y: u32,
}

impl Iterator for Bands {
    type Item = Rect;
    fn next(&mut self) -> Option<Rect> {
        let end = self.rect.y.saturating_add(self.rect.h);
        if self.rect.w == 0 || self.y >= end {
            return None;
        }
        let next = (self.y / self.pitch).saturating_add(1).saturating_mul(self.pitch).min(end);
        let band = Rect { x: self.rect.x, y: self.y, w: self.rect.w, h: next - self.y };
        self.y = next;
        Some(band)
    }
}

/// Row-major pixel positions of a rectangle, without a division per pixel.
#[derive(Clone, Copy, Debug)]
pub struct RectPositions {
    rect: Rect,
    x: u32,
    y: u32,
}

impl RectPositions {
    /// Positions of `rect`'s pixels, row by row.
    pub fn new(rect: Rect) -> Self {
        RectPositions { rect, x: 0, y: 0 }
    }
}

impl Iterator for RectPositions {
    type Item = (u32, u32);
    #[inline]
    fn next(&mut self) -> Option<(u32, u32)> {
        if self.y >= self.rect.h || self.rect.w == 0 {
            return None;
        }
        let p = (self.rect.x.wrapping_add(self.x), self.rect.y.wrapping_add(self.y));
        // `x < w` and `y < h` here, so neither increment can wrap.
        self.x = self.x.wrapping_add(1);
        if self.x >= self.rect.w {
            self.x = 0;
            self.y = self.y.wrapping_add(1);
        }
        Some(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_cover_a_rectangle_once_on_the_image_grid() {
        const PITCH: u32 = 8;
        for rect in [
            Rect { x: 0, y: 0, w: 1, h: 1 },
            Rect { x: 0, y: 0, w: 31, h: 33 },
            Rect { x: 5, y: 30, w: 64, h: 64 },
            Rect { x: 31, y: 1, w: 100, h: 7 },
        ] {
            let stride = rect.x + rect.w;
            let mut seen = [0u8; 200 * 100];
            for t in rect.bands(PITCH) {
                assert!(t.y / PITCH == (t.y + t.h - 1) / PITCH, "{t:?} crosses the grid");
                assert!(t.x == rect.x && t.w == rect.w, "{t:?} is not a band of {rect:?}");
                for (x, y) in t.positions() {
                    seen[(y * stride + x) as usize] += 1;
                }
            }
            for y in 0..rect.y + rect.h {
                for x in 0..stride {
                    let inside = x >= rect.x && y >= rect.y;
                    assert_eq!(seen[(y * stride + x) as usize], inside as u8, "{rect:?} at ({x}, {y})");
                }
            }
            assert_eq!(rect.band_count(PITCH), rect.bands(PITCH).count() as u64, "{rect:?}");
        }
        assert_eq!(Rect { x: 3, y: 3, w: 0, h: 5 }.bands(PITCH).count(), 0);
        assert_eq!(Rect { x: 2, y: 2, w: 0, h: 9 }.band_count(PITCH), 0);
        assert_eq!(Rect { x: 0, y: 0, w: 3, h: 2 }.bands(1).count(), 2);
        let last = Rect { x: 0, y: u32::MAX - 2, w: 1, h: 2 };
        assert_eq!(last.bands(PITCH).map(|b| b.h).sum::<u32>(), 2);
    }

    #[test]
    fn clip_and_inside_saturate() {
        let image = Rect { x: 0, y: 0, w: 40, h: 30 };
        assert!(Rect { x: 39, y: 29, w: 1, h: 1 }.inside(image));
        assert!(!Rect { x: 10, y: 0, w: 31, h: 3 }.inside(image));
        assert!(!Rect { x: 0, y: 0, w: 0, h: 3 }.inside(image));
        assert!(!Rect { x: u32::MAX, y: 0, w: 2, h: 1 }.inside(image));
        assert_eq!(Rect { x: 30, y: 20, w: 20, h: 20 }.clip(image), Rect { x: 30, y: 20, w: 10, h: 10 });
        assert!(Rect { x: 50, y: 0, w: 5, h: 5 }.clip(image).is_empty());
        assert!(Rect { x: u32::MAX, y: 0, w: u32::MAX, h: 5 }.clip(image).is_empty());
    }

    #[test]
    fn positions_walk_rows() {
        let p: Vec<_> = Rect { x: 3, y: 5, w: 2, h: 2 }.positions().collect();
        assert_eq!(p, [(3, 5), (4, 5), (3, 6), (4, 6)]);
        assert_eq!(Rect { x: 0, y: 0, w: 0, h: 4 }.positions().count(), 0);
    }
}
