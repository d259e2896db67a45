//! Characters → a compact line the parser can walk, as LinuxCNC reads a block: letters
//! lower-cased and every space or tab outside comments removed (so `G 0 1`, `X1 0.5` and
//! `M O D` read as `g01`, `x10.5`, `mod`), while each kept byte remembers its source column
//! for diagnostics. Comments are kept verbatim (with their parentheses) so the parser can
//! turn `(MSG,…)` and `(DEBUG,…)` into notes.
//!
//! Also here: the byte-level scanners the parser uses (numbers without allocation, names).

use crate::diag::{Diagnostic, Span};

/// One source line after compaction. Reused from line to line: no allocation per line once
/// the buffers have grown.
#[derive(Clone, Debug, Default)]
pub struct Compact {
    /// Lower-cased bytes without blanks outside comments; comments verbatim.
    pub bytes: Vec<u8>,
    /// 1-based source column (in characters) of each byte in `bytes`.
    pub cols: Vec<u32>,
    /// 1-based source line.
    pub line: u32,
    /// Column just after the last character of the source line (for spans at the end).
    pub end_col: u32,
}

impl Compact {
    /// An empty line.
    pub fn new() -> Compact {
        Compact::default()
    }

    /// Whether the line holds nothing (blank, or blanks only).
    pub fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }

    /// Column of byte `i`, or the end of the line when `i` is past the end.
    pub fn col(&self, i: usize) -> u32 {
        self.cols.get(i).copied().unwrap_or(self.end_col)
    }

    /// The span covering compact bytes `start..end`.
    pub fn span(&self, start: usize, end: usize) -> Span {
        let c0 = self.col(start);
        let c1 = if end > start {
            self.col(end - 1) + 1
        } else {
            c0
        };
        Span::new(self.line, c0, c1.saturating_sub(c0))
    }

    /// Compact `raw` (one line without its newline) into `self`.
    ///
    /// Errors: an unclosed or nested comment, a byte outside ASCII outside a comment.
    pub fn load(&mut self, raw: &[u8], line: u32) -> Result<(), Diagnostic> {
        self.load_impl(raw, line, false)
    }

    /// Compact as grbl's serial reader does: every byte up to a blank is dropped, a comment
    /// runs to the first `)` (a `(` inside it is just text) or to the end of the line, and
    /// bytes outside ASCII are kept (the parser rejects them as it would any non-letter).
    /// Never fails.
    pub fn load_grbl(&mut self, raw: &[u8], line: u32) {
        // Infallible with grbl's rules.
        let _ = self.load_impl(raw, line, true);
    }

    fn load_impl(&mut self, raw: &[u8], line: u32, grbl: bool) -> Result<(), Diagnostic> {
        self.bytes.clear();
        self.cols.clear();
        self.line = line;
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        let mut col: u32 = 0;
        let mut comment_start: Option<u32> = None;
        let mut i = 0;
        while i < raw.len() {
            let b = raw[i];
            if starts_char(raw, i) {
                col += 1;
            }
            if let Some(start) = comment_start {
                if b == b'(' && !grbl {
                    return Err(Diagnostic::error(
                        Span::new(line, col, 1),
                        "nested comment: '(' inside a comment",
                    )
                    .with_help(format!(
                        "the comment opened at column {start} must be closed with ')' before another opens"
                    )));
                }
                if b == b')' {
                    comment_start = None;
                }
                self.bytes.push(b);
                self.cols.push(col);
                i += 1;
                continue;
            }
            match b {
                b' ' | b'\t' | b'\r' | 0x0B | 0x0C => {}
                0..=b' ' if grbl => {}
                b'(' => {
                    comment_start = Some(col);
                    self.bytes.push(b);
                    self.cols.push(col);
                }
                b';' => {
                    // The rest of the line is a comment, kept verbatim.
                    self.bytes.push(b);
                    self.cols.push(col);
                    for j in i + 1..raw.len() {
                        if starts_char(raw, j) {
                            col += 1;
                        }
                        self.bytes.push(raw[j]);
                        self.cols.push(col);
                    }
                    break;
                }
                0x80.. if !grbl => return Err(non_ascii(raw, i, line, col)),
                _ => {
                    self.bytes.push(b.to_ascii_lowercase());
                    self.cols.push(col);
                }
            }
            i += 1;
        }
        self.end_col = col + 1;
        if let (Some(start), false) = (comment_start, grbl) {
            return Err(Diagnostic::error(
                Span::new(line, start, col + 1 - start),
                "unclosed comment: '(' without ')'",
            )
            .with_help("close the comment with ')' on the same line"));
        }
        Ok(())
    }
}

/// The error for the byte outside ASCII at `raw[i]` (outside a comment): a UTF-8 byte-order
/// mark, a character, or a byte that is not UTF-8 at all, each named as what it is.
fn non_ascii(raw: &[u8], i: usize, line: u32, col: u32) -> Diagnostic {
    let span = Span::new(line, col, 1);
    if line == 1 && i == 0 && raw.starts_with(crate::text::UTF8_BOM) {
        return Diagnostic::error(
            span,
            "the file starts with a UTF-8 byte-order mark (bytes EF BB BF)",
        )
        .with_help(
            "save the program as UTF-8 without a BOM (or as ASCII); LinuxCNC refuses it too",
        );
    }
    let rest = &raw[i..raw.len().min(i + 4)];
    let valid = match std::str::from_utf8(rest) {
        Ok(s) => s.chars().next(),
        Err(e) => std::str::from_utf8(&rest[..e.valid_up_to()])
            .ok()
            .and_then(|s| s.chars().next()),
    };
    let message = match valid {
        Some(ch) => format!(
            "bad character '{}' (U+{:04X}): only ASCII is allowed outside comments",
            crate::text::escape(&ch.to_string()),
            ch as u32
        ),
        None => format!(
            "byte 0x{:02X} is not UTF-8 text: only ASCII is allowed outside comments",
            raw[i]
        ),
    };
    Diagnostic::error(span, message)
        .with_help("put text in a comment: ( … ), where bytes of any encoding are kept")
}

/// Columns count characters: a UTF-8 continuation byte does not start a new one, unless
/// it has no lead byte before it (invalid UTF-8 still gets a column of its own).
fn starts_char(raw: &[u8], i: usize) -> bool {
    raw[i] & 0xC0 != 0x80 || i == 0 || raw[i - 1] < 0x80
}

/// A number as LinuxCNC reads it: digits with at most one decimal point, at least one digit,
/// no sign (signs are unary operators) and no exponent. Returns the value and the number of
/// bytes used, or `None` when `s` does not start with a digit or point.
///
/// Exact for the usual CNC numbers: up to 19 significant digits go through an integer
/// mantissa and one division by an exact power of ten (correctly rounded); longer ones fall
/// back to the standard library parser.
// Inlined into the readers: the nested Option/Result then stays in registers instead of
// going through memory on every number.
#[inline(always)]
pub(crate) fn scan_number(s: &[u8]) -> Option<Result<(f64, usize), usize>> {
    // A single digit (G1, #1, M2) is the most common number of all.
    if let [d @ b'0'..=b'9', rest @ ..] = s {
        if !matches!(rest.first(), Some(b'0'..=b'9' | b'.')) {
            return Some(Ok((f64::from(d - b'0'), 1)));
        }
    }
    // Two tight loops (integer part, fraction) rather than one loop with a state: this is
    // the hottest code of the whole front end. The mantissa may wrap when there are more
    // than 19 digits, but it is only used for 15 digits or fewer (the rest are parsed by
    // the standard library). `i < s.len()` lets the compiler drop the bounds checks.
    let mut mantissa: u64 = 0;
    let mut i = 0;
    while i < s.len() {
        let d = s[i].wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    let int_digits = i;
    let mut frac_digits = 0usize;
    if i < s.len() && s[i] == b'.' {
        i += 1;
        let frac_start = i;
        // Four digits at a time (CAM output usually writes four decimals): one load, a
        // check that all four bytes are digits, and two multiply-add steps to combine them.
        while let Some(chunk) = s.get(i..i + 4) {
            let word = u32::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]);
            // Each byte is 0x30..=0x39: high nibble 3, and still 3 after adding 6.
            if (word & 0xF0F0_F0F0) | ((word.wrapping_add(0x0606_0606) & 0xF0F0_F0F0) >> 4)
                != 0x3333_3333
            {
                break;
            }
            let d = word - 0x3030_3030;
            // Bytes d0 d1 d2 d3 (d0 first) → pairs d0d1, d2d3 → d0d1d2d3.
            let pairs = (d.wrapping_mul(10) + (d >> 8)) & 0x00FF_00FF;
            let four = (pairs.wrapping_mul(100) + (pairs >> 16)) & 0xFFFF;
            mantissa = mantissa.wrapping_mul(10_000).wrapping_add(u64::from(four));
            i += 4;
        }
        while i < s.len() {
            let d = s[i].wrapping_sub(b'0');
            if d > 9 {
                break;
            }
            mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(d));
            i += 1;
        }
        frac_digits = i - frac_start;
        if i < s.len() && s[i] == b'.' {
            return Some(Err(i + 1));
        }
    }
    if i == 0 {
        return None;
    }
    let digits = int_digits + frac_digits;
    if digits == 0 {
        return Some(Err(i));
    }
    const POW10: [f64; 16] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
    ];
    if digits <= 15 {
        // Both the mantissa (< 10^15 < 2^53, so exact through i64) and the power are
        // exact: one correctly rounded division.
        return Some(Ok((mantissa as i64 as f64 / POW10[frac_digits], i)));
    }
    Some(Ok((parse_long(&s[..i]), i)))
}

/// A number of more than 15 digits, by the standard library (rare: kept out of line).
#[cold]
#[inline(never)]
fn parse_long(s: &[u8]) -> f64 {
    // Only ASCII digits and one point: always valid UTF-8 and a valid Rust float literal.
    let text = std::str::from_utf8(s).unwrap_or("0");
    text.parse::<f64>().unwrap_or(0.0)
}

/// The text of a comment body with the comment marker removed: `(text)` → `text`,
/// `;text` → `text`.
pub(crate) fn comment_text(raw: &[u8]) -> String {
    let inner = match raw.first() {
        Some(b'(') => raw[1..].strip_suffix(b")").unwrap_or(&raw[1..]),
        Some(b';') => &raw[1..],
        _ => raw,
    };
    crate::text::decode(inner).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Every number reads as the standard parser reads its text, with the same length.
        #[test]
        fn numbers_match_the_standard_parser(int in "[0-9]{0,24}", frac in "(\\.[0-9]{0,24})?", tail in "[x ;]{0,3}") {
            let text = format!("{int}{frac}{tail}");
            let len = int.len() + frac.len();
            match scan_number(text.as_bytes()) {
                None => prop_assert_eq!(len, 0),
                Some(Err(_)) => prop_assert!(int.is_empty() && frac == "."),
                Some(Ok((v, used))) => {
                    prop_assert_eq!(used, len);
                    let reference: f64 = text[..len].parse().unwrap();
                    prop_assert_eq!(v, reference, "{}", text);
                }
            }
        }
    }

    proptest! {
        /// Any byte after the digits ends the number, including near-digits such as `:` and
        /// `/` and bytes that carry when the four-digit check adds 6.
        #[test]
        fn numbers_stop_at_any_other_byte(int in "[0-9]{0,3}", frac in "[0-9]{1,9}", tail in proptest::collection::vec(any::<u8>(), 0..5)) {
            prop_assume!(!tail.first().is_some_and(|&b| b.is_ascii_digit() || b == b'.'));
            let text = format!("{int}.{frac}");
            let mut bytes = text.clone().into_bytes();
            bytes.extend(&tail);
            let reference: f64 = text.parse().unwrap();
            prop_assert_eq!(scan_number(&bytes), Some(Ok((reference, text.len()))));
        }
    }

    #[test]
    fn four_digit_groups_reject_each_neighbour_of_the_digits() {
        for bad in [b'/', b':', 0xFA, 0x39 + 0x80, 0x00, b'?'] {
            for at in 0..4 {
                let mut text = b"1.5555".to_vec();
                text[2 + at] = bad;
                let want: f64 = std::str::from_utf8(&text[..2 + at])
                    .unwrap()
                    .parse()
                    .unwrap();
                assert_eq!(
                    scan_number(&text),
                    Some(Ok((want, 2 + at))),
                    "{bad} at {at}"
                );
            }
        }
    }

    fn compact(s: &str) -> Compact {
        let mut c = Compact::new();
        c.load(s.as_bytes(), 7).unwrap();
        c
    }

    #[test]
    fn blanks_go_and_letters_fold_outside_comments_only() {
        let c = compact("G 0 1 X1 0.5 (Keep  This) m o d");
        assert_eq!(c.bytes, b"g01x10.5(Keep  This)mod");
        assert_eq!(c.cols[0], 1);
        assert_eq!(c.cols[3], 7, "the x is in column 7");
        assert_eq!(c.span(3, 8), Span::new(7, 7, 6), "X1 0.5 spans six columns");
    }

    #[test]
    fn semicolon_comment_runs_to_end_and_carriage_return_is_dropped() {
        let c = compact("G1 ; a (b)\r");
        assert_eq!(c.bytes, b"g1; a (b)");
        assert_eq!(c.cols[2], 4, "the ';' is in column 4");
        assert_eq!(c.end_col, 11);
        let mut c = Compact::new();
        let e = c.load(b"\x80G1", 1).unwrap_err();
        assert_eq!(
            e.span.col, 1,
            "a stray continuation byte still has a column"
        );
    }

    #[test]
    fn comment_errors_point_at_the_culprit() {
        let mut c = Compact::new();
        let e = c.load(b"G0 (a (b) c)", 3).unwrap_err();
        assert_eq!(e.span, Span::new(3, 7, 1));
        assert!(e.message.contains("nested"));
        let e = c.load(b"G0 (abc", 3).unwrap_err();
        assert_eq!(e.span, Span::new(3, 4, 4));
        assert!(e.message.contains("unclosed"));
        let e = c.load("G0 X1 µ".as_bytes(), 2).unwrap_err();
        assert_eq!(e.span.col, 7);
        assert!(e.message.contains('µ'));
    }

    #[test]
    fn grbl_compaction_follows_grbls_reader() {
        let mut c = Compact::new();
        c.load_grbl(b"G1 (a (b) c) X1 (open", 1);
        assert_eq!(
            c.bytes, b"g1(a (b)c)x1(open",
            "the comment ends at the first ')'"
        );
        c.load_grbl("G1\x01X1 µ".as_bytes(), 1);
        assert_eq!(&c.bytes[..4], b"g1x1");
        assert_eq!(
            c.bytes.len(),
            6,
            "non-ASCII is kept for the parser to reject"
        );
    }

    #[test]
    fn columns_count_characters_not_bytes() {
        let c = compact("(µm) X1");
        assert_eq!(c.bytes.last(), Some(&b'1'));
        assert_eq!(*c.cols.last().unwrap(), 7);
    }

    #[test]
    fn numbers_parse_exactly_without_allocating() {
        assert_eq!(scan_number(b"12.5x"), Some(Ok((12.5, 4))));
        assert_eq!(scan_number(b".5"), Some(Ok((0.5, 2))));
        assert_eq!(scan_number(b"5."), Some(Ok((5.0, 2))));
        assert_eq!(scan_number(b"0.1"), Some(Ok((0.1, 3))));
        assert_eq!(scan_number(b"x"), None);
        assert_eq!(scan_number(b"."), Some(Err(1)));
        assert_eq!(scan_number(b"1..2"), Some(Err(3)));
        let long = b"3.14159265358979323846264338327950288";
        assert_eq!(scan_number(long).unwrap().unwrap().0, std::f64::consts::PI);
        // Every short decimal equals the standard parser's correctly rounded value.
        for s in ["123.456", "0.0001", "99999.99999", "1.1", "7.000000000001"] {
            let v = scan_number(s.as_bytes()).unwrap().unwrap().0;
            assert_eq!(v, s.parse::<f64>().unwrap(), "{s}");
        }
    }
}
