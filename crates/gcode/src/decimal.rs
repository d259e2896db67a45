//! Numbers as text without the formatting machinery: `%.4f` (C's printf, which `{:.4}`
//! matches: the exact binary value rounded half to even) and right-aligned integers. The
//! printer writes millions of them; `write!` costs several times the work of a whole block.

/// Above this, `v·10⁴` no longer has a fraction to round: left to the standard formatter.
const FAST_LIMIT: f64 = 4_503_599_627_370_496.0; // 2^52

/// Append `v` with four decimals, exactly as `format!("{v:.4}")` (and C's `%.4f`) writes
/// it, `-0.0000` included.
pub fn push_fixed4(out: &mut Vec<u8>, v: f64) {
    let a = v.abs();
    let p = a * 1e4;
    if !(p < FAST_LIMIT) {
        // Huge, infinite or NaN: rare enough for the general formatter.
        out.extend_from_slice(format!("{v:.4}").as_bytes());
        return;
    }
    // p is a·10⁴ rounded; err is what that rounding lost, exactly (10⁴ is exact and the
    // product's error is representable), so a·10⁴ = p + err.
    let err = a.mul_add(1e4, -p);
    let floor = p.floor();
    // t is exact (p and floor are within one of each other) and a multiple of p's ulp;
    // |err| is at most half an ulp, so it only decides when t is exactly one half.
    let t = p - floor;
    let up = t > 0.5 || (t == 0.5 && (err > 0.0 || (err == 0.0 && floor % 2.0 != 0.0)));
    let n = floor as u64 + u64::from(up);
    if v.is_sign_negative() {
        out.push(b'-');
    }
    push_u64(out, n / 10_000);
    let frac = n % 10_000;
    out.extend_from_slice(&[
        b'.',
        b'0' + (frac / 1000) as u8,
        b'0' + (frac / 100 % 10) as u8,
        b'0' + (frac / 10 % 10) as u8,
        b'0' + (frac % 10) as u8,
    ]);
}

/// Append `n` in decimal.
pub fn push_u64(out: &mut Vec<u8>, mut n: u64) {
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
    out.extend_from_slice(&digits[i..]);
}

/// Append `n` right-aligned in `width` columns, as `format!("{n:width$}")`.
pub fn push_u64_padded(out: &mut Vec<u8>, n: u64, width: usize) {
    let start = out.len();
    push_u64(out, n);
    let len = out.len() - start;
    if len < width {
        let pad = width - len;
        out.splice(start..start, std::iter::repeat_n(b' ', pad));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn fixed4(v: f64) -> String {
        let mut out = Vec::new();
        push_fixed4(&mut out, v);
        String::from_utf8(out).unwrap()
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
        for n in [0u64, 7, 12345, 123456, u64::MAX] {
            let mut out = Vec::new();
            push_u64_padded(&mut out, n, 5);
            assert_eq!(String::from_utf8(out).unwrap(), format!("{n:5}"));
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
