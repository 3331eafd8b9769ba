//! Bins over a window of values: `clamp(⌊(v − origin)·2^shift⌋, 0, n − 1)`.
//!
//! The bin is a non-decreasing function of `v` in every scalar: a rounded
//! (or saturating) subtraction, a rounded product by a power of two, a
//! floor and a clamp each are. So `lo ≤ v ≤ hi` puts `v`'s bin between
//! those of `lo` and `hi`, and a list of things kept per bin, built from
//! the bins of their bounds with this same function, needs no margin to be
//! exact. The window (`origin`, `shift`) only decides how well the bins
//! separate what they list. Used by the shadow rays' direction cells
//! (`query::cull`) and the edge blocks of many-sided polygons.

use crate::num::scalar::Scalar;

/// The largest `shift` in `[MIN, MAX]` that brings a window `width` wide
/// to at most `n` bins (`width·2^shift ≤ n`), or `MIN`.
#[inline(always)]
pub(crate) fn fit_shift<const MIN: i32, const MAX: i32>(width: f32, n: usize) -> i32 {
    let n = n as f32;
    let mut shift = if MAX < 0 {
        MAX
    } else if MIN > 0 {
        MIN
    } else {
        0
    };
    while shift < MAX && width * libm::ldexpf(1.0, shift + 1) <= n {
        shift += 1;
    }
    while shift > MIN && width * libm::ldexpf(1.0, shift) > n {
        shift -= 1;
    }
    shift
}

/// `2^shift` in `S`: the factor of [`bin`] for scalars whose product by a
/// power of two is not a shift.
pub(crate) fn scale_of<S: Scalar>(shift: i32) -> S {
    S::from_f32(libm::ldexpf(1.0, shift))
}

/// The bin of `v` among `n`: `clamp(⌊(v − origin)·2^shift⌋, 0, n − 1)`
/// (`scale` is [`scale_of`]`(shift)`; fixed point shifts instead).
#[inline(always)]
pub(crate) fn bin<S: Scalar>(v: S, origin: S, shift: i32, scale: S, n: usize) -> usize {
    // (Each scalar's own form, [`Scalar::bin`]: in fixed point one
    // subtraction and one shift.)
    v.bin(origin, shift, scale, n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::fixed32::Fixed32;

    #[test]
    fn fit_shift_is_the_largest_that_fits() {
        assert_eq!(fit_shift::<-4, 16>(1.0, 16), 4);
        assert_eq!(fit_shift::<-4, 16>(1.5, 16), 3);
        assert_eq!(fit_shift::<-120, 24>(100.0, 256), 1);
        assert_eq!(fit_shift::<-120, 24>(1.0e-9, 256), 24);
        assert_eq!(fit_shift::<-4, 16>(1.0e9, 16), -4);
    }

    fn monotone<S: Scalar>(origin: f32, shift: i32) {
        let (o, s) = (S::from_f32(origin), scale_of::<S>(shift));
        let mut prev = 0;
        let mut x = origin - 120.0;
        while x < origin + 120.0 {
            let b = bin(S::from_f32(x), o, shift, s, 256);
            assert!(b >= prev && b < 256, "{x}: {b} after {prev}");
            prev = b;
            x += 0.0137;
        }
        assert!(prev >= 50, "{prev}");
    }

    #[test]
    fn fixed_point_bins_are_the_exact_floor() {
        let mut x = -5.0f64;
        while x < 5.0 {
            let v = Fixed32::from_f32(x as f32);
            for (origin, shift) in [(-1.0f32, 3), (0.25, 0), (-0.75, -2), (0.0, 16), (-2.0, 24)] {
                let o = Fixed32::from_f32(origin);
                // Both raw values are exact multiples of 2⁻²⁴: the exact floor.
                let exact = ((v.to_f32() as f64 - o.to_f32() as f64) * (shift as f64).exp2()).floor();
                let want = exact.clamp(0.0, 255.0) as usize;
                assert_eq!(bin(v, o, shift, scale_of::<Fixed32>(shift), 256), want, "{x} {origin} {shift}");
            }
            x += 0.00731;
        }
    }

    #[test]
    fn fixed_point_bins_are_the_exact_floor_across_the_range() {
        // Differences of raw values past `i32::MAX` (here up to 240·2²⁴):
        // the bin is still the exact floor, not that of a saturated
        // difference.
        for (origin, shift) in [(-120.0f32, -4), (-127.5, -3), (-100.0, -2)] {
            let o = Fixed32::from_f32(origin);
            let mut x = -127.9f64;
            while x < 127.9 {
                let v = Fixed32::from_f32(x as f32);
                let exact = ((v.to_f32() as f64 - o.to_f32() as f64) * (shift as f64).exp2()).floor();
                let want = exact.clamp(0.0, 255.0) as usize;
                assert_eq!(bin(v, o, shift, scale_of::<Fixed32>(shift), 256), want, "{x} {origin} {shift}");
                x += 0.0917;
            }
        }
    }

    #[test]
    fn bins_never_decrease() {
        monotone::<f32>(-3.25, 5);
        monotone::<f32>(7.0, -1);
        monotone::<Fixed32>(-3.25, 5);
        monotone::<Fixed32>(7.0, -1);
    }
}
