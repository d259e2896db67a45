//! How numbers and lines look: decimals, units, integer words, block numbers, modal
//! suppression. One [`Format`] per program; every dialect prints through it.

/// Length units of the program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    /// Millimetres (G21).
    Mm,
    /// Inches (G20).
    Inch,
}

/// How a number is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Numbers {
    /// Up to `places` decimals, trailing zeros dropped, never "-0".
    Decimal {
        /// Most decimals written.
        places: u8,
    },
    /// An integer count of 1/`per_unit` of the unit with no decimal point (Sinumerik 7M
    /// words in 0.001 mm: `X100000` is 100 mm).
    Integer {
        /// Counts per unit (1000: 0.001 mm).
        per_unit: u32,
    },
}

/// Block numbers: `N<start>`, then every `step`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineNumbers {
    /// The first block number.
    pub start: u32,
    /// The increment between block numbers.
    pub step: u32,
}

/// Everything about the text that does not change what the program does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Format {
    /// Decimal or integer words.
    pub numbers: Numbers,
    /// Millimetres or inches.
    pub units: Units,
    /// Block numbers, if any.
    pub line_numbers: Option<LineNumbers>,
    /// Leave out a motion word or axis that would repeat the modal state (the usual way);
    /// off writes every word on every block, for controls or readers that want that.
    pub modal: bool,
}

impl Format {
    /// 4 decimals (0.1 µm: rounding can never add up to a visible gouge), mm, no block
    /// numbers, modal words once.
    pub const DEFAULT: Format = Format {
        numbers: Numbers::Decimal { places: 4 },
        units: Units::Mm,
        line_numbers: None,
        modal: true,
    };

    /// Checks the ranges a user could get wrong.
    pub fn validate(&self) -> Result<(), String> {
        match self.numbers {
            Numbers::Decimal { places } if places > 6 => {
                return Err(format!("precision {places}: use 0 to 6 decimals"))
            }
            Numbers::Integer { per_unit: 0 } => {
                return Err("integer words need a resolution above 0".into())
            }
            _ => {}
        }
        if let Some(n) = self.line_numbers {
            if n.step == 0 {
                return Err("line numbers need a step of at least 1".into());
            }
        }
        Ok(())
    }

    /// Millimetres → program units.
    pub fn length(&self, mm: f64) -> f64 {
        match self.units {
            Units::Mm => mm,
            Units::Inch => mm / 25.4,
        }
    }

    /// Appends " Lv" with `v` already in program units.
    pub fn push_word(&self, line: &mut String, letter: char, v: f64) {
        line.push(' ');
        line.push(letter);
        self.push_num(line, v);
    }

    /// Appends `v` (already in program units) as this format writes numbers.
    pub fn push_num(&self, line: &mut String, v: f64) {
        match self.numbers {
            Numbers::Decimal { places } => push_decimal(line, v, places),
            Numbers::Integer { per_unit } => push_decimal(line, v * per_unit as f64, 0),
        }
    }

    /// Whether two values (program units) print the same (both NaN counts as the same).
    pub fn same_printed(&self, a: f64, b: f64) -> bool {
        let (places, scale) = match self.numbers {
            Numbers::Decimal { places } => (places, 1.0),
            Numbers::Integer { per_unit } => (0, per_unit as f64),
        };
        match (fixed(a * scale, places), fixed(b * scale, places)) {
            (Some(x), Some(y)) => x == y,
            _ => num(a * scale, places) == num(b * scale, places),
        }
    }
}

impl Default for Format {
    fn default() -> Format {
        Format::DEFAULT
    }
}

/// Beyond this the fixed-point path could overflow; such numbers take the slow path.
const FIXED_LIMIT: f64 = 1e14;

/// `v` in units of the last place, rounded half away from zero, when it fits the fast path.
fn fixed(v: f64, places: u8) -> Option<i64> {
    let scaled = v * 10f64.powi(places as i32);
    // `as` truncates toward zero in one instruction; f64::round is a libm call here.
    (scaled.abs() < FIXED_LIMIT).then(|| (scaled + 0.5f64.copysign(scaled)) as i64)
}

/// Writes a number with up to `places` decimals, no trailing zeros, no "-0", without going
/// through the float formatter (a post writes millions of these).
pub(crate) fn push_decimal(out: &mut String, v: f64, places: u8) {
    let Some(mut n) = fixed(v, places) else {
        out.push_str(&num(v, places));
        return;
    };
    if n < 0 {
        out.push('-');
        n = -n;
    }
    let unit = 10i64.pow(places as u32);
    let (whole, mut frac) = (n / unit, n % unit);
    let mut digits = [0u8; 20];
    let mut len = 0;
    let mut w = whole;
    loop {
        digits[len] = b'0' + (w % 10) as u8;
        len += 1;
        w /= 10;
        if w == 0 {
            break;
        }
    }
    out.extend(digits[..len].iter().rev().map(|&d| d as char));
    if frac != 0 {
        let mut shown = places as u32;
        while frac % 10 == 0 {
            frac /= 10;
            shown -= 1;
        }
        out.push('.');
        for p in (0..shown).rev() {
            out.push((b'0' + (frac / 10i64.pow(p) % 10) as u8) as char);
        }
    }
}

/// A number with up to `places` decimals, no trailing zeros, no "-0" (the float formatter:
/// for numbers too large for the fast path, and the reference in tests).
pub(crate) fn num(v: f64, places: u8) -> String {
    if v.is_nan() {
        return "nan".into();
    }
    let mut s = format!("{v:.*}", places as usize);
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" {
        s = "0".into();
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_numbers_print_as_the_float_formatter_does() {
        let mut values = vec![
            0.0, -0.0, 1.0, -1.0, 0.00004, -0.00004, 0.00005, 12.5, -3.14158,
        ];
        values.extend([
            1e9 + 0.123456,
            -987654.32101,
            2000.0 / 60.0 * 60.0,
            0.1 + 0.2,
        ]);
        // Deterministic spread of magnitudes and signs.
        let mut x = 0.7236f64;
        for _ in 0..20_000 {
            x = (x * 9301.0 + 0.49297).fract();
            values.push((x - 0.5) * 10f64.powi((x * 1e4) as i32 % 8 - 2));
        }
        for places in [0u8, 1, 3, 4, 6] {
            let ulp = 10f64.powi(-(places as i32));
            for &v in &values {
                let mut fast = String::new();
                push_decimal(&mut fast, v, places);
                let slow = num(v, places);
                if fast != slow {
                    // Only a value within rounding noise of a half unit in the last place
                    // may differ, by one unit in the last place.
                    let (a, b): (f64, f64) = (fast.parse().unwrap(), slow.parse().unwrap());
                    assert!((a - b).abs() <= ulp * 1.0001, "{v}: {fast} vs {slow}");
                    let scaled = v / ulp;
                    assert!(
                        (scaled.fract().abs() - 0.5).abs() < 1e-6 * scaled.abs().max(1.0),
                        "{v}@{places}: {fast} vs {slow}"
                    );
                }
            }
        }
    }

    #[test]
    fn integer_words_are_thousandths_without_a_point() {
        let f = Format {
            numbers: Numbers::Integer { per_unit: 1000 },
            ..Format::DEFAULT
        };
        let mut s = String::new();
        f.push_word(&mut s, 'X', 100.0);
        f.push_word(&mut s, 'Z', -5.0);
        f.push_word(&mut s, 'I', 0.0004);
        f.push_word(&mut s, 'J', -0.0004);
        assert_eq!(s, " X100000 Z-5000 I0 J0");
        assert!(f.same_printed(1.0001, 1.0));
        assert!(!f.same_printed(1.001, 1.0));
    }
}
