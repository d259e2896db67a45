//! Numbers as text without the formatting machinery: `%.4f` (C's printf, which `{:.4}`
//! matches: the exact binary value rounded half to even) and right-aligned integers. The
//! printer writes millions of them; `write!` costs several times the work of a whole block.

/// Above this, `v·10⁴` no longer has a fraction to round: left to the standard formatter.
const FAST_LIMIT: f64 = 4_503_599_627_370_496.0; // 2^52

/// Whether [`Line::push_fixed4`] can write `v` (finite and below about 4.5·10¹¹).
pub(crate) fn fixed4_fits(v: f64) -> bool {
    v.abs() * 1e4 < FAST_LIMIT
}

/// Longest line [`Line`] holds: far above any call the printer builds with it.
pub(crate) const LINE_MAX: usize = 512;

/// One output line built in place: digits are written straight into a fixed buffer, with
/// no capacity checks or copies per number.
#[derive(Clone, Debug)]
pub(crate) struct Line {
    buf: [u8; LINE_MAX],
    len: usize,
}

impl Default for Line {
    fn default() -> Line {
        Line {
            buf: [0; LINE_MAX],
            len: 0,
        }
    }
}

impl Line {
    pub(crate) fn clear(&mut self) {
        self.len = 0;
    }

    pub(crate) fn as_bytes(&self) -> &[u8] {
        &self.buf[..self.len]
    }

    pub(crate) fn push_bytes(&mut self, bytes: &[u8]) {
        self.buf[self.len..self.len + bytes.len()].copy_from_slice(bytes);
        self.len += bytes.len();
    }

    /// Append `v` with four decimals, exactly as `format!("{v:.4}")` (and C's `%.4f`)
    /// writes it, `-0.0000` included. `v` must pass [`fixed4_fits`].
    pub(crate) fn push_fixed4(&mut self, v: f64) {
        debug_assert!(fixed4_fits(v));
        let a = v.abs();
        let p = a * 1e4;
        // p is a·10⁴ rounded; err is what that rounding lost, exactly (10⁴ is exact and
        // the product's error is representable), so a·10⁴ = p + err.
        let err = a.mul_add(1e4, -p);
        // 0 <= p < 2^52: truncation is the floor, and t = p - floor is exact and a
        // multiple of p's ulp; |err| is at most half an ulp, so it only decides when t is
        // exactly one half (then the exact value rounds half to even).
        let floor = p as u64;
        let t = p - floor as f64;
        let up = t > 0.5 || (t == 0.5 && (err > 0.0 || (err == 0.0 && floor % 2 == 1)));
        let n = floor + u64::from(up);
        if v.is_sign_negative() {
            self.push_bytes(b"-");
        }
        self.push_u64(n / 10_000);
        let frac = (n % 10_000) as u16;
        self.push_bytes(&[
            b'.',
            b'0' + (frac / 1000) as u8,
            b'0' + (frac / 100 % 10) as u8,
            b'0' + (frac / 10 % 10) as u8,
            b'0' + (frac % 10) as u8,
        ]);
    }

    /// Append `n` in decimal.
    pub(crate) fn push_u64(&mut self, mut n: u64) {
        let mut digits = [0u8; 20];
        let mut i = digits.len();
        loop {
            i -= 1;
            digits[i] = b'0' + (n % 10) as u8;
            n /= 10;
            if n == 0 {
                break;
            }
        }
        self.push_bytes(&digits[i..]);
    }

    /// Append `n` right-aligned in `width` (at most 20) columns, as `format!("{n:width$}")`.
    pub(crate) fn push_u64_padded(&mut self, n: u64, width: usize) {
        let digits = n.checked_ilog10().unwrap_or(0) as usize + 1;
        for _ in digits..width.min(20) {
            self.push_bytes(b" ");
        }
        self.push_u64(n);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fixed4(v: f64) -> String {
        if !fixed4_fits(v) {
            // What the printer does with these.
            return format!("{v:.4}");
        }
        let mut line = Line::default();
        line.push_fixed4(v);
        String::from_utf8(line.as_bytes().to_vec()).unwrap()
    }

    #[test]
    fn matches_the_standard_formatter_at_the_edges() {
        for v in [
            0.0,
            -0.0,
            -0.00001,
            0.00005,
            -0.00005,
            0.00015,
            0.00025,
            1.00005,
            2.5e-5,
            7.5e-5,
            0.99995,
            9.99995,
            123.45675,
            -123.45665,
            1e-300,
            5e-324,
            0.5,
            1.0,
            1234567.0,
            4.5e11,
            4.503599627370496e11,
            4.6e11,
            1e20,
            -1e300,
            f64::MAX,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ] {
            assert_eq!(fixed4(v), format!("{v:.4}"), "{v:e}");
        }
        // Every tie k + 0.5 ten-thousandths that is exact in binary, and its neighbours.
        for k in 0..20_000u64 {
            let v = (k as f64 + 0.5) / 1e4;
            for w in [v, v.next_up(), v.next_down(), -v] {
                assert_eq!(fixed4(w), format!("{w:.4}"), "{w:e}");
            }
        }
    }

    #[test]
    fn integers_are_padded_like_the_standard_formatter() {
        for n in [0u64, 7, 10, 9999, 12345, 123456, u64::MAX] {
            let mut line = Line::default();
            line.push_u64_padded(n, 5);
            assert_eq!(line.as_bytes(), format!("{n:5}").as_bytes());
        }
    }

    proptest! {
        #[test]
        fn matches_the_standard_formatter(bits in any::<u64>(), scaled in -1e7f64..1e7) {
            let v = f64::from_bits(bits);
            prop_assert_eq!(fixed4(v), format!("{v:.4}"));
            // Values near four decimals, where rounding decides.
            let w = (scaled * 1e4).round() / 1e4 + 5e-5;
            prop_assert_eq!(fixed4(w), format!("{w:.4}"));
            prop_assert_eq!(fixed4(scaled), format!("{scaled:.4}"));
        }
    }
}
