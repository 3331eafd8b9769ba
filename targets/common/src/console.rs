//! A byte sink for the report, with number formatting that needs neither
//! `core::fmt` nor any division by a value the compiler cannot see.

/// Where the report goes (semihosting on every board here).
pub trait Console {
    /// Writes a string; errors are ignored (there is nowhere to report them).
    fn write_str(&mut self, s: &str);

    /// Writes `v` in decimal.
    fn write_u64(&mut self, v: u64) {
        let mut digits = [0u8; 20];
        let n = decimal_digits(v, &mut digits);
        for &d in digits.iter().skip(20usize.saturating_sub(n)) {
            self.write_str(DIGITS[d as usize & 15]);
        }
    }
    /// Writes `v` in decimal.
    fn write_u32(&mut self, v: u32) {
        self.write_u64(v as u64);
    }
    /// Writes `v` as `0x` and 8 lower-case hexadecimal digits.
    fn write_hex32(&mut self, v: u32) {
        self.write_str("0x");
        for k in 0..8 {
            self.write_str(DIGITS[(v >> (28 - 4 * k)) as usize & 15]);
        }
    }
}

/// The digits `0`–`9`, `a`–`f` as strings: the console writes a number
/// digit by digit, so no bytes are turned into a `str` (whose UTF-8 check
/// would be the largest formatting routine in a small image).
const DIGITS: [&str; 16] = ["0", "1", "2", "3", "4", "5", "6", "7", "8", "9", "a", "b", "c", "d", "e", "f"];

/// `(⌊v/10⌋, v mod 10)` by long division in base 2¹⁶: four 32-bit
/// divisions by a constant, so that no image links the 64-bit library
/// division (about 1 KB of flash) for printing counts.
fn div10(v: u64) -> (u64, u32) {
    let mut q = 0u64;
    let mut r = 0u32;
    for k in (0..4).rev() {
        // r < 10, so the partial dividend stays below 10·2¹⁶.
        let cur = (r << 16) | ((v >> (16 * k)) as u32 & 0xFFFF);
        q |= ((cur / 10) as u64) << (16 * k);
        r = cur % 10;
    }
    (q, r)
}

/// The decimal digits of `v` (values 0–9), in the tail of `buf`; returns
/// how many.
fn decimal_digits(mut v: u64, buf: &mut [u8; 20]) -> usize {
    let mut n = 0;
    // 20 digits hold u64::MAX.
    for d in buf.iter_mut().rev() {
        let (q, r) = div10(v);
        *d = r as u8;
        n += 1;
        v = q;
        if v == 0 {
            break;
        }
    }
    n
}

/// `v` in decimal, in the tail of `buf`.
pub fn format_u64(v: u64, buf: &mut [u8; 20]) -> &str {
    let n = decimal_digits(v, buf);
    let start = buf.len().saturating_sub(n);
    for d in buf.iter_mut().skip(start) {
        // A digit (0–9): no overflow, wrapping only spares the check.
        *d = d.wrapping_add(b'0');
    }
    core::str::from_utf8(buf.get(start..).unwrap_or(&[])).unwrap_or("?")
}

/// `v` as `0x` followed by 8 hexadecimal digits.
pub fn format_hex32(v: u32, buf: &mut [u8; 10]) -> &str {
    const HEX: &[u8; 16] = b"0123456789abcdef";
    buf[0] = b'0';
    buf[1] = b'x';
    for k in 0..8 {
        let nibble = (v >> (28 - 4 * k)) & 0xf;
        buf[2 + k] = HEX[nibble as usize];
    }
    core::str::from_utf8(buf).unwrap_or("?")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimal_and_hex() {
        let mut b = [0u8; 20];
        assert_eq!(format_u64(0, &mut b), "0");
        assert_eq!(format_u64(20480, &mut b), "20480");
        assert_eq!(format_u64(u64::MAX, &mut b), "18446744073709551615");
        let mut h = [0u8; 10];
        assert_eq!(format_hex32(0x0123_abcd, &mut h), "0x0123abcd");
        assert_eq!(format_hex32(u32::MAX, &mut h), "0xffffffff");
    }

    #[test]
    fn div10_is_the_64_bit_division() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        for k in 0..10_000u64 {
            // A xorshift sequence, its values shifted to every size.
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let v = x >> (k % 64);
            assert_eq!(div10(v), (v / 10, (v % 10) as u32), "{v}");
        }
        for v in [0, 9, 10, 0xFFFF, 0x1_0000, u32::MAX as u64, u64::MAX, u64::MAX - 5] {
            assert_eq!(div10(v), (v / 10, (v % 10) as u32), "{v}");
        }
    }

    struct Text(std::string::String);
    impl Console for Text {
        fn write_str(&mut self, s: &str) {
            self.0.push_str(s);
        }
    }

    #[test]
    fn the_console_writes_the_same_digits() {
        for v in [0, 7, 10, 20480, 890_604_400, u32::MAX as u64, u64::MAX] {
            let mut t = Text(std::string::String::new());
            t.write_u64(v);
            assert_eq!(t.0, std::format!("{v}"));
        }
        for v in [0, 0x0123_abcd, u32::MAX] {
            let mut t = Text(std::string::String::new());
            t.write_hex32(v);
            assert_eq!(t.0, std::format!("{v:#010x}"));
        }
    }
}
