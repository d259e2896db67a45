//! The DXF group-code layer: pairs of (group code, value) from ASCII DXF (two lines per pair,
//! any line ending) or binary DXF (the `AutoCAD Binary DXF` sentinel, one-byte codes as R12
//! writes them or two-byte codes as R13+ does). Values stay slices of the file until a reader
//! asks for a number, so reading allocates nothing per pair.

use std::borrow::Cow;

/// The binary DXF sentinel: 18 characters, CR LF, SUB, NUL.
const SENTINEL: &[u8] = b"AutoCAD Binary DXF\r\n\x1a\0";

/// One group value as the file holds it.
#[derive(Clone, Copy, Debug)]
pub(super) enum Raw<'a> {
    /// ASCII text of the value line (line ending removed).
    Text(&'a [u8]),
    /// Binary double.
    F(f64),
    /// Binary integer (16, 32 or 64 bits, or a bool).
    I(i64),
}

/// One (group code, value) pair and where it starts.
#[derive(Clone, Copy, Debug)]
pub(super) struct Tag<'a> {
    pub(super) code: i32,
    pub(super) raw: Raw<'a>,
    /// 1-based line of the group code (ASCII) or byte offset (binary).
    pub(super) at: usize,
    pub(super) binary: bool,
}

impl<'a> Tag<'a> {
    /// Where the pair is, for messages: "line 12" or "byte 345".
    pub(super) fn place(&self) -> String {
        if self.binary {
            format!("byte {}", self.at)
        } else {
            format!("line {}", self.at)
        }
    }

    /// The value as text (numbers formatted); see [`decode`].
    pub(super) fn text(&self) -> Cow<'a, str> {
        match self.raw {
            Raw::Text(t) => decode(t),
            Raw::F(f) => Cow::Owned(f.to_string()),
            Raw::I(i) => Cow::Owned(i.to_string()),
        }
    }

    /// The value as text with surrounding blanks removed (names, keywords).
    pub(super) fn word(&self) -> Cow<'a, str> {
        match self.text() {
            Cow::Borrowed(s) => Cow::Borrowed(s.trim()),
            Cow::Owned(s) => Cow::Owned(s.trim().to_string()),
        }
    }

    /// A finite number, or an error naming the place.
    pub(super) fn f(&self) -> Result<f64, String> {
        let v = match self.raw {
            Raw::F(f) => f,
            Raw::I(i) => i as f64,
            Raw::Text(t) => std::str::from_utf8(t)
                .ok()
                .and_then(|s| s.trim().parse::<f64>().ok())
                .ok_or_else(|| {
                    format!(
                        "{}: group {} value '{}' is not a number",
                        self.place(),
                        self.code,
                        String::from_utf8_lossy(&t[..t.len().min(40)])
                    )
                })?,
        };
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!(
                "{}: group {} value {v} is not a finite number",
                self.place(),
                self.code
            ))
        }
    }

    /// An integer (a number with a fraction is truncated, as ezdxf's lenient loader does).
    pub(super) fn i(&self) -> Result<i64, String> {
        if let Raw::I(i) = self.raw {
            return Ok(i);
        }
        if let Raw::Text(t) = self.raw {
            if let Some(i) = std::str::from_utf8(t)
                .ok()
                .and_then(|s| s.trim().parse::<i64>().ok())
            {
                return Ok(i);
            }
        }
        let f = self.f()?;
        if f.abs() < 9.0e18 {
            Ok(f as i64)
        } else {
            Err(format!(
                "{}: group {} value {f} is not an integer",
                self.place(),
                self.code
            ))
        }
    }
}

/// Windows-1252 in 0x80–0x9F (the rest of the code page is Latin-1).
const CP1252_HIGH: [char; 32] = [
    '€', '\u{81}', '‚', 'ƒ', '„', '…', '†', '‡', 'ˆ', '‰', 'Š', '‹', 'Œ', '\u{8d}', 'Ž', '\u{8f}',
    '\u{90}', '‘', '’', '“', '”', '•', '–', '—', '˜', '™', 'š', '›', 'œ', '\u{9d}', 'ž', 'Ÿ',
];

/// Text of a value: UTF-8 (R2007 and later) or, when it is not, the ANSI_1252 code page older
/// releases write by default; `\U+XXXX` escapes (how AutoCAD writes characters outside the
/// code page) become their characters.
pub(super) fn decode(t: &[u8]) -> Cow<'_, str> {
    let s = match std::str::from_utf8(t) {
        Ok(s) => Cow::Borrowed(s),
        Err(_) => Cow::Owned(
            t.iter()
                .map(|&b| match b {
                    0x80..=0x9f => CP1252_HIGH[(b - 0x80) as usize],
                    b => b as char,
                })
                .collect(),
        ),
    };
    if !s.contains("\\U+") {
        return s;
    }
    let mut out = String::with_capacity(s.len());
    let mut rest: &str = &s;
    while let Some(i) = rest.find("\\U+") {
        out.push_str(&rest[..i]);
        let hex = rest
            .get(i + 3..i + 7)
            .filter(|h| h.bytes().all(|b| b.is_ascii_hexdigit()));
        match hex
            .and_then(|h| u32::from_str_radix(h, 16).ok())
            .and_then(char::from_u32)
        {
            Some(c) => {
                out.push(c);
                rest = &rest[i + 7..];
            }
            None => {
                out.push_str("\\U+");
                rest = &rest[i + 3..];
            }
        }
    }
    out.push_str(rest);
    Cow::Owned(out)
}

/// Reads pairs one at a time; `next` gives `None` at the end and an error (with its place)
/// for a group code that is not a number or a value cut off by the end of the file.
pub(super) struct Tokens<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
    binary: Option<bool>, // Some(two-byte codes) for binary files
}

impl<'a> Tokens<'a> {
    pub(super) fn new(bytes: &'a [u8]) -> Tokens<'a> {
        if bytes.starts_with(SENTINEL) {
            let n = SENTINEL.len();
            // R12 writes one byte per group code (the first pair is 0, "SECTION": byte 0 then
            // 'S'); R13 and later write two (0, 0 then 'S').
            let two = bytes.get(n..n + 2) == Some(&[0, 0]);
            return Tokens {
                bytes,
                pos: n,
                line: 0,
                binary: Some(two),
            };
        }
        // A UTF-8 byte order mark is not part of the first group code.
        let pos = if bytes.starts_with(b"\xEF\xBB\xBF") {
            3
        } else {
            0
        };
        Tokens {
            bytes,
            pos,
            line: 0,
            binary: None,
        }
    }

    pub(super) fn is_binary(&self) -> bool {
        self.binary.is_some()
    }

    fn ascii_line(&mut self) -> Option<&'a [u8]> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let end = rest
            .iter()
            .position(|&b| b == b'\n' || b == b'\r')
            .unwrap_or(rest.len());
        let line = &rest[..end];
        let mut next = self.pos + end;
        if rest.get(end) == Some(&b'\r') {
            next += 1;
            if self.bytes.get(next) == Some(&b'\n') {
                next += 1;
            }
        } else if end < rest.len() {
            next += 1;
        }
        self.pos = next;
        self.line += 1;
        Some(line)
    }

    fn next_ascii(&mut self) -> Option<Result<Tag<'a>, String>> {
        // Blank lines where a group code belongs (trailing newlines, a blank line at the end)
        // are skipped; anything else must be an integer.
        let (code_line, at) = loop {
            let l = self.ascii_line()?;
            if l.iter().any(|b| !b.is_ascii_whitespace()) {
                break (l, self.line);
            }
        };
        let code = match std::str::from_utf8(code_line)
            .ok()
            .and_then(|s| s.trim().parse::<i32>().ok())
        {
            Some(c) => c,
            None => {
                self.pos = self.bytes.len();
                return Some(Err(format!(
                    "line {at}: '{}' is not a group code (a DXF file alternates group-code lines and value lines)",
                    String::from_utf8_lossy(&code_line[..code_line.len().min(40)])
                )));
            }
        };
        let Some(value) = self.ascii_line() else {
            return Some(Err(format!(
                "line {at}: group code {code} has no value: the file ends there"
            )));
        };
        Some(Ok(Tag {
            code,
            raw: Raw::Text(value),
            at,
            binary: false,
        }))
    }

    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let s = self.bytes.get(self.pos..self.pos.checked_add(n)?)?;
        self.pos += n;
        Some(s)
    }

    fn next_binary(&mut self, two: bool) -> Option<Result<Tag<'a>, String>> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let at = self.pos;
        let cut = move || Err(format!("byte {at}: the binary DXF ends inside a group"));
        let code = if two {
            match self.take(2) {
                Some(b) => i16::from_le_bytes([b[0], b[1]]) as i32,
                None => return Some(cut()),
            }
        } else {
            match self.take(1) {
                Some([255]) => match self.take(2) {
                    Some(b) => i16::from_le_bytes([b[0], b[1]]) as i32,
                    None => return Some(cut()),
                },
                Some(b) => b[0] as i32,
                None => return Some(cut()),
            }
        };
        let int = |s: &mut Self, n: usize| -> Option<i64> {
            let b = s.take(n)?;
            Some(match n {
                1 => b[0] as i64,
                2 => i16::from_le_bytes([b[0], b[1]]) as i64,
                4 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as i64,
                _ => i64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
            })
        };
        let raw = match code {
            10..=59 | 110..=149 | 210..=239 | 460..=469 | 1010..=1059 => self.take(8).map(|b| {
                Raw::F(f64::from_le_bytes([
                    b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7],
                ]))
            }),
            60..=79 | 170..=179 | 270..=289 | 370..=389 | 400..=409 | 1060..=1070 => {
                int(self, 2).map(Raw::I)
            }
            90..=99 | 420..=429 | 440..=459 | 1071 => int(self, 4).map(Raw::I),
            160..=169 => int(self, 8).map(Raw::I),
            290..=299 => int(self, 1).map(Raw::I),
            310..=319 | 1004 => {
                // Binary chunk: a length byte, then that many bytes (kept as opaque text).
                match self.take(1) {
                    Some(&[n]) => self.take(n as usize).map(Raw::Text),
                    _ => None,
                }
            }
            _ => {
                // Strings (0–9, 100–109, 300–309, 320–369, 390–399, 410–419, 430–439,
                // 470–481, 999, 1000–1009 …) end with a NUL.
                let rest = &self.bytes[self.pos..];
                rest.iter().position(|&b| b == 0).map(|n| {
                    self.pos += n + 1;
                    Raw::Text(&rest[..n])
                })
            }
        };
        match raw {
            Some(raw) => Some(Ok(Tag {
                code,
                raw,
                at,
                binary: true,
            })),
            None => {
                self.pos = self.bytes.len();
                Some(cut())
            }
        }
    }
}

impl<'a> Iterator for Tokens<'a> {
    type Item = Result<Tag<'a>, String>;

    fn next(&mut self) -> Option<Self::Item> {
        match self.binary {
            Some(two) => self.next_binary(two),
            None => self.next_ascii(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_pairs_with_any_line_ending_and_places() {
        let t: Vec<Tag> = Tokens::new(b"  0\r\nSECTION\r\n  2\nENTITIES\r10\r1.5\n\n\n")
            .collect::<Result<_, _>>()
            .unwrap();
        assert_eq!(t.len(), 3);
        assert_eq!((t[0].code, t[0].word().as_ref()), (0, "SECTION"));
        assert_eq!((t[2].code, t[2].f().unwrap(), t[2].at), (10, 1.5, 5));
    }

    #[test]
    fn bad_group_codes_and_values_name_their_line() {
        let e = Tokens::new(b"0\nLINE\nxx\n1\n")
            .collect::<Result<Vec<_>, _>>()
            .unwrap_err();
        assert!(e.starts_with("line 3:"), "{e}");
        let t: Vec<Tag> = Tokens::new(b"0\nLINE\n10\nnan\n20\nabc\n")
            .collect::<Result<_, _>>()
            .unwrap();
        assert!(t[1].f().unwrap_err().starts_with("line 3: group 10"));
        assert!(t[2].f().unwrap_err().contains("'abc'"));
        let e = Tokens::new(b"0\nLINE\n10\n")
            .collect::<Result<Vec<_>, _>>()
            .unwrap_err();
        assert!(e.contains("no value"), "{e}");
    }

    #[test]
    fn code_page_and_unicode_escapes() {
        assert_eq!(decode(b"Ma\xe7\xe3 \x80"), "Maçã €");
        assert_eq!(decode("maçã".as_bytes()), "maçã");
        assert_eq!(decode(br"a\U+00E7o \U+20ACx \U+zz"), "aço €x \\U+zz");
    }

    #[test]
    fn binary_one_and_two_byte_codes() {
        let mut r12 = SENTINEL.to_vec();
        r12.extend_from_slice(b"\0SECTION\0\x0a");
        r12.extend_from_slice(&2.5f64.to_le_bytes());
        r12.extend_from_slice(b"\x46\x03\x00");
        r12.extend_from_slice(b"\xff\xe7\x03hi\0"); // code 999 through the escape
        let t: Vec<Tag> = Tokens::new(&r12).collect::<Result<_, _>>().unwrap();
        assert_eq!(t.len(), 4);
        assert_eq!((t[1].code, t[1].f().unwrap()), (10, 2.5));
        assert_eq!((t[2].code, t[2].i().unwrap()), (70, 3));
        assert_eq!((t[3].code, t[3].text().as_ref()), (999, "hi"));
        let mut r13 = SENTINEL.to_vec();
        r13.extend_from_slice(b"\0\0SECTION\0\x0a\0");
        r13.extend_from_slice(&(-1.0f64).to_le_bytes());
        r13.extend_from_slice(b"\x0a\0\x01"); // cut off
        let t: Vec<Result<Tag, String>> = Tokens::new(&r13).collect();
        assert_eq!(t.len(), 3);
        assert_eq!(t[1].as_ref().unwrap().f().unwrap(), -1.0);
        assert!(t[2].as_ref().unwrap_err().contains("ends inside"));
    }
}
