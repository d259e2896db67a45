//! One rule for the bytes of a program, whichever command reads it:
//! - outside comments only ASCII is allowed (the lexer reports anything else with its line and
//!   column, a UTF-8 byte-order mark by that name);
//! - inside comments any byte is kept: UTF-8 where it is valid, and each other byte read as its
//!   Latin-1 character (old controllers and CAM posts write `°` or `µ` as one byte);
//! - text shown on a terminal (a quoted source line, a message) has its control characters
//!   escaped, so a binary file cannot send escape sequences to the terminal.
//!
//! `check` and `gcode canon` stream the file's bytes through the interpreter; `run` and `plan`
//! hold the program as text ([`read_program`]), decoded by the same rule, so every command
//! accepts and refuses the same programs at the same places.

use crate::diag::Diagnostic;
use crate::lex::Compact;
use std::borrow::Cow;
use std::fmt::Write as _;
use std::io::Read;
use std::path::Path;

/// The UTF-8 encoding of U+FEFF, which some editors put at the start of a file.
pub const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// `bytes` as text: UTF-8 where it is valid, every other byte as its Latin-1 character.
pub fn decode(bytes: &[u8]) -> Cow<'_, str> {
    match std::str::from_utf8(bytes) {
        Ok(s) => Cow::Borrowed(s),
        Err(_) => Cow::Owned(decode_lossless(bytes)),
    }
}

fn decode_lossless(mut bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len() + 8);
    while !bytes.is_empty() {
        match std::str::from_utf8(bytes) {
            Ok(s) => {
                out.push_str(s);
                break;
            }
            Err(e) => {
                let good = e.valid_up_to();
                // Valid up to `good` by construction.
                out.push_str(std::str::from_utf8(&bytes[..good]).unwrap_or_default());
                let bad = e.error_len().unwrap_or(bytes.len() - good);
                out.extend(bytes[good..good + bad].iter().map(|&b| char::from(b)));
                bytes = &bytes[good + bad..];
            }
        }
    }
    out
}

/// Whether `c` must not reach a terminal as it is: C0 and C1 controls and DEL (a tab is
/// shown as one space by [`escape_into`]), and the invisible characters that hide or reorder
/// text (the byte-order mark, zero-width spaces, bidirectional controls).
fn is_control(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{FEFF}' | '\u{200B}'..='\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}')
}

/// Append `c` as it is safe to show: a control character as `\xNN` (or `\u{NNNN}`), a tab as
/// a space. Returns how many terminal columns it takes.
pub fn escape_into(out: &mut String, c: char) -> usize {
    if c == '\t' {
        out.push(' ');
        1
    } else if is_control(c) {
        let before = out.len();
        if (c as u32) < 0x100 {
            let _ = write!(out, "\\x{:02X}", c as u32);
        } else {
            let _ = write!(out, "\\u{{{:X}}}", c as u32);
        }
        out.len() - before
    } else {
        out.push(c);
        1
    }
}

/// `s` with every control character escaped (and tabs as spaces).
pub fn escape(s: &str) -> Cow<'_, str> {
    if !s.chars().any(|c| c == '\t' || is_control(c) && c != '\n') {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if c == '\n' {
            out.push(c);
        } else {
            escape_into(&mut out, c);
        }
    }
    Cow::Owned(out)
}

/// Why a program could not be read as a whole.
#[derive(Debug)]
pub enum ReadError {
    /// The file could not be opened or read (the OS error, once).
    Io(std::io::Error),
    /// The file is larger than the caller allows to hold in memory.
    TooLarge {
        /// The file's size.
        bytes: u64,
        /// The most the caller allows.
        limit: u64,
    },
    /// A byte outside UTF-8 outside a comment (or a byte-order mark): the lexer's diagnostic.
    Bad(Diagnostic),
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReadError::Io(e) => write!(f, "{e}"),
            ReadError::TooLarge { bytes, limit } => write!(
                f,
                "the program is {:.1} MB, more than the {:.0} MB this command holds in memory",
                *bytes as f64 / 1e6,
                *limit as f64 / 1e6
            ),
            ReadError::Bad(d) => write!(f, "{d}"),
        }
    }
}

/// Open a program file to stream it (what `check` and `gcode canon` do; [`read_program`]
/// starts here too): a directory is refused by name.
pub fn open_program(path: &Path) -> Result<std::io::BufReader<std::fs::File>, ReadError> {
    let file = std::fs::File::open(path).map_err(ReadError::Io)?;
    if file.metadata().map_err(ReadError::Io)?.is_dir() {
        return Err(ReadError::Io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "a directory, not a program",
        )));
    }
    Ok(std::io::BufReader::with_capacity(1 << 16, file))
}

/// Read a whole program file as text by the rule of this module: refused when it is larger
/// than `max_bytes`, or when a line holds bytes outside UTF-8 outside its comments (the
/// lexer's error, with line and column); bytes outside UTF-8 inside comments are decoded as
/// Latin-1. A file that is all UTF-8 is returned unchanged.
pub fn read_program(path: &Path, max_bytes: u64) -> Result<String, ReadError> {
    let reader = open_program(path)?;
    let len = reader.get_ref().metadata().map_err(ReadError::Io)?.len();
    if len > max_bytes {
        return Err(ReadError::TooLarge {
            bytes: len,
            limit: max_bytes,
        });
    }
    let mut bytes = Vec::with_capacity(len as usize);
    // A file that grows while it is read is still cut at the limit.
    reader
        .take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(ReadError::Io)?;
    if bytes.len() as u64 > max_bytes {
        return Err(ReadError::TooLarge {
            bytes: bytes.len() as u64,
            limit: max_bytes,
        });
    }
    program_text(bytes).map_err(ReadError::Bad)
}

/// [`read_program`] on bytes already in memory.
pub fn program_text(bytes: Vec<u8>) -> Result<String, Diagnostic> {
    let bytes = match String::from_utf8(bytes) {
        Ok(s) => return Ok(s),
        Err(e) => e.into_bytes(),
    };
    let mut compact = Compact::new();
    for (i, line) in bytes.split(|&b| b == b'\n').enumerate() {
        if std::str::from_utf8(line).is_err() {
            let number = u32::try_from(i + 1).unwrap_or(u32::MAX);
            compact.load(line, number)?;
        }
    }
    Ok(decode_lossless(&bytes))
}

/// The width of a quoted source line, in terminal columns: a screen is at least 80 wide, and
/// the gutter and the ellipses take the rest.
pub const QUOTE_WIDTH: usize = 72;

/// A window of one source line for a diagnostic: at most [`QUOTE_WIDTH`] columns around the
/// place, control characters escaped; `pad` is the terminal column of the place in `text`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Quote {
    /// The text of the window.
    pub text: String,
    /// Terminal column of the place in `text`.
    pub pad: usize,
    /// Terminal columns under the span (at least 1).
    pub width: usize,
}

/// Quote `line` (whose 1-based character columns the span counts) around `col..col+len`.
pub fn quote(line: &str, col: u32, len: u32) -> Quote {
    let col = col.max(1) as usize;
    let count = line.chars().count();
    let first = if count <= QUOTE_WIDTH {
        1
    } else {
        // The place a third of the way in, so what follows it shows too.
        col.saturating_sub(QUOTE_WIDTH / 3)
            .clamp(1, count + 1 - QUOTE_WIDTH)
    };
    let last = first + QUOTE_WIDTH - 1; // inclusive
    let mut text = String::new();
    let (mut used, mut pad, mut width) = (0usize, None, 0usize);
    if first > 1 {
        text.push('…');
        used += 1;
    }
    let span_end = col + len.max(1) as usize;
    for (i, c) in line.chars().enumerate().skip(first - 1) {
        let here = i + 1;
        if here > last {
            text.push('…');
            break;
        }
        if here == col {
            pad = Some(used);
        }
        let w = escape_into(&mut text, c);
        if here >= col && here < span_end {
            width += w;
        }
        used += w;
    }
    Quote {
        text,
        pad: pad.unwrap_or(used),
        width: width.max(1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_bytes_are_latin1_and_valid_utf8_is_kept() {
        assert_eq!(decode(b"(20\xb0C)"), "(20°C)");
        assert_eq!(decode("(µ)".as_bytes()), "(µ)");
        assert_eq!(decode(b"a\xff\xfeb"), "a\u{ff}\u{fe}b");
    }

    #[test]
    fn a_latin1_comment_is_text_and_a_byte_outside_one_is_refused_at_its_place() {
        assert_eq!(
            program_text(b"G0\n(temp 20\xb0C)\nM2\n".to_vec()).unwrap(),
            "G0\n(temp 20°C)\nM2\n"
        );
        let e = program_text(b"G0\nG1 X1\xb0\nM2\n".to_vec()).unwrap_err();
        assert_eq!((e.span.line, e.span.col), (2, 6));
        assert!(e.message.contains("0xB0"), "{}", e.message);
    }

    #[test]
    fn control_characters_never_reach_the_terminal() {
        assert_eq!(escape("a\x1b[2Jb\tc"), "a\\x1B[2Jb c");
        assert_eq!(escape("x\u{85}y"), "x\\x85y");
        assert_eq!(escape("ok\nfine"), "ok\nfine");
        assert_eq!(escape("\u{feff}G0"), "\\u{FEFF}G0");
    }

    #[test]
    fn a_long_line_is_quoted_around_the_place() {
        let line = format!("G1 X{}Y", "1".repeat(1_000_000));
        let q = quote(&line, 1_000_005, 1);
        assert!(q.text.chars().count() <= QUOTE_WIDTH + 2);
        assert!(q.text.starts_with('…') && q.text.ends_with('Y'));
        assert_eq!(q.text.chars().nth(q.pad), Some('Y'));
        let q = quote(&line, 1, 2);
        assert!(q.text.starts_with("G1 X") && q.text.ends_with('…'));
        assert_eq!((q.pad, q.width), (0, 2));
        let q = quote("G1\x1bX", 4, 1);
        assert_eq!(q.text, "G1\\x1BX");
        assert_eq!(q.pad, 6);
    }
}
