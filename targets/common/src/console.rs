//! A byte sink for the report, with number formatting that needs neither
//! `core::fmt` nor any division by a value the compiler cannot see.

/// Where the report goes (semihosting on every board here).
pub trait Console {
    /// Writes a string; errors are ignored (there is nowhere to report them).
    fn write_str(&mut self, s: &str);

    /// Writes `v` in decimal.
    fn write_u64(&mut self, v: u64) {
        let mut digits = [0u8; 20];
        let s = format_u64(v, &mut digits);
        self.write_str(s);
    }
    /// Writes `v` in decimal.
    fn write_u32(&mut self, v: u32) {
        self.write_u64(v as u64);
    }
    /// Writes `v` as `0x` and 8 lower-case hexadecimal digits.
    fn write_hex32(&mut self, v: u32) {
        let mut digits = [0u8; 10];
        self.write_str(format_hex32(v, &mut digits));
    }
}

/// `v` in decimal, in the tail of `buf`.
pub fn format_u64(mut v: u64, buf: &mut [u8; 20]) -> &str {
    let mut i = buf.len();
    loop {
        // 20 digits hold u64::MAX, so `i` never underflows.
        i -= 1;
        if let Some(d) = buf.get_mut(i) {
            *d = b'0' + (v % 10) as u8;
        }
        v /= 10;
        if v == 0 || i == 0 {
            break;
        }
    }
    core::str::from_utf8(buf.get(i..).unwrap_or(&[])).unwrap_or("?")
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
}
