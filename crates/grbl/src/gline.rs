//! One grbl input line → words, with grbl's own clean-up and error numbers (protocol.c and
//! the first stage of gcode.c): whitespace and control characters vanish, `(…)` and `;…`
//! are comments, letters are upper-cased, and the cleaned line must fit grbl's 80-byte
//! line buffer.

/// grbl's LINE_BUFFER_SIZE less the terminating zero.
pub const MAX_LINE: usize = 79;

pub(crate) const E_EXPECTED_LETTER: u8 = 1;
pub(crate) const E_BAD_NUMBER: u8 = 2;
/// grbl's error 4: a negative value where a positive one is needed.
pub(crate) const E_NEGATIVE: u8 = 4;
/// grbl's error 11: the line is longer than the line buffer.
pub const E_LINE_OVERFLOW: u8 = 11;

/// The line as grbl's protocol loop keeps it: no spaces, comments or control characters,
/// upper-case. `Err(11)` when it overflows the line buffer.
pub fn clean(line: &str) -> Result<String, u8> {
    let mut out = Vec::with_capacity(line.len());
    walk(line.as_bytes(), |_, b| out.push(b));
    if out.len() > MAX_LINE {
        return Err(E_LINE_OVERFLOW);
    }
    // Only ASCII bytes are changed or dropped, so whole UTF-8 characters remain.
    Ok(String::from_utf8(out).unwrap_or_default())
}

/// [`clean`] on raw bytes, with the index in `raw` of every byte kept: where each word of the
/// cleaned line stands in the source (for diagnostics and for blanking words in place).
pub(crate) fn clean_mapped(raw: &[u8]) -> (Vec<u8>, Vec<usize>) {
    let (mut out, mut at) = (Vec::new(), Vec::new());
    walk(raw, |i, b| {
        out.push(b);
        at.push(i);
    });
    (out, at)
}

/// grbl's clean-up, byte by byte: `keep(index, byte)` for every byte it keeps, upper-cased.
/// ('(', ')', ';' and '/' never occur inside a multi-byte UTF-8 character.)
fn walk(line: &[u8], mut keep: impl FnMut(usize, u8)) {
    let mut in_paren = false;
    for (i, &c) in line.iter().enumerate() {
        if in_paren {
            if c == b')' {
                in_paren = false;
            }
            continue;
        }
        match c {
            b'(' => in_paren = true,
            b';' => break,
            // Block delete is not supported by grbl: the character is ignored.
            b'/' => {}
            c if c <= b' ' || c == 0x7f => {}
            c => keep(i, c.to_ascii_uppercase()),
        }
    }
}

/// Splits a cleaned line into (letter, value) words; grbl's read_float rules: optional sign,
/// digits with at most one decimal point, no exponent.
pub fn words(clean: &str) -> Result<Vec<(char, f64)>, u8> {
    Ok(word_spans(clean.as_bytes())?
        .into_iter()
        .map(|(l, v, _)| (l, v))
        .collect())
}

/// [`words`] with where each word stands in the cleaned line (byte range).
pub(crate) fn word_spans(b: &[u8]) -> Result<Vec<(char, f64, std::ops::Range<usize>)>, u8> {
    let mut i = 0;
    let mut out = Vec::new();
    while i < b.len() {
        let letter = b[i] as char;
        if !letter.is_ascii_uppercase() {
            return Err(E_EXPECTED_LETTER);
        }
        let word_start = i;
        i += 1;
        let start = i;
        if i < b.len() && (b[i] == b'-' || b[i] == b'+') {
            i += 1;
        }
        let mut digits = 0;
        let mut dots = 0;
        while i < b.len() && (b[i].is_ascii_digit() || (b[i] == b'.' && dots == 0)) {
            if b[i] == b'.' {
                dots += 1;
            } else {
                digits += 1;
            }
            i += 1;
        }
        // A second '.' ends the number, as in grbl's read_float; it then fails as a letter.
        if digits == 0 {
            return Err(E_BAD_NUMBER);
        }
        let value: f64 = std::str::from_utf8(&b[start..i])
            .ok()
            .and_then(|t| t.parse().ok())
            .ok_or(E_BAD_NUMBER)?;
        out.push((letter, value, word_start..i));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cleans_like_grbl() {
        assert_eq!(clean("g1 x1.5 (move) y2 ; rest").unwrap(), "G1X1.5Y2");
        assert_eq!(clean("\tG0\r").unwrap(), "G0");
        assert_eq!(clean(&"X1".repeat(40)), Err(E_LINE_OVERFLOW));
    }

    #[test]
    fn words_and_errors() {
        assert_eq!(
            words("G1X-1.5F300").unwrap(),
            vec![('G', 1.0), ('X', -1.5), ('F', 300.0)]
        );
        assert_eq!(words("1X2"), Err(E_EXPECTED_LETTER));
        assert_eq!(words("G1X"), Err(E_BAD_NUMBER));
        assert_eq!(words("X1.2.3"), Err(E_EXPECTED_LETTER));
        assert_eq!(words("X-"), Err(E_BAD_NUMBER));
        assert_eq!(words("#1=2"), Err(E_EXPECTED_LETTER));
    }
}
