//! The byte level of an HP-GL file: instructions and their parameters, and everything around
//! them that real files carry — RS-232 device-control escapes (`ESC . x … :`), PCL printer
//! language around HP-GL/2 (`ESC E`, `ESC % -12345 X` with PJL lines, `ESC % n A` / `ESC % n B`
//! switching between PCL and HP-GL/2, PCL escapes with binary data such as raster rows).
//!
//! PCL escapes (PCL 5 Technical Reference, ch. 2): `ESC` then a parameterized character
//! (0x21…0x2F), a group character (0x60…0x7E), then value fields, each a signed decimal number
//! followed by a parameter character: lower case (0x60…0x7E) continues a combined sequence, upper
//! case (0x40…0x5E) ends it. A value field ended by `W` (or `w`) is followed by that many bytes
//! of data (raster rows, fonts, macros), as is `ESC & p # X` (transparent print data). Other
//! escapes are two bytes (`ESC E`, `ESC 9`, …).

use crate::import::ImportError;

/// Largest number of parameters one instruction may carry.
const MAX_PARAMS: usize = 1_000_000;
/// Coordinates beyond this (plotter units, ≈ 25 km) are refused as absurd.
pub(super) const MAX_COORD: f64 = 1e9;

pub(super) struct Scanner<'a> {
    pub(super) b: &'a [u8],
    pub(super) i: usize,
    pub(super) line: usize,
    line_start: usize,
    /// Inside PCL (between `ESC % n A` / `ESC E` / UEL and `ESC % n B`): bytes are skipped.
    pcl: bool,
    /// What was skipped that a user should hear of: PCL text or raster data.
    pub(super) skipped_pcl: bool,
    /// Vendor instructions (`!PZ…;` of Roland and Graphtec cutters) skipped, and where.
    pub(super) vendor: Vec<(String, String)>,
    /// An instruction has been read (before one, anything else is an error).
    pub(super) started: bool,
    /// Bytes skipped as not HP-GL.
    garbage: usize,
    file: &'a str,
}

impl<'a> Scanner<'a> {
    pub(super) fn new(b: &'a [u8], file: &'a str) -> Scanner<'a> {
        Scanner {
            b,
            i: 0,
            line: 1,
            line_start: 0,
            pcl: false,
            skipped_pcl: false,
            vendor: Vec::new(),
            started: false,
            garbage: 0,
            file,
        }
    }

    /// "line L, column C" of byte `at` (files without newlines are common: the column finds it).
    pub(super) fn place(&self) -> String {
        format!(
            "line {}, column {}",
            self.line,
            self.i - self.line_start + 1
        )
    }

    pub(super) fn err(&self, what: &str, msg: String) -> ImportError {
        let loc = if what.is_empty() {
            self.place()
        } else {
            format!("{}, {what}", self.place())
        };
        ImportError::new(self.file, loc, msg)
    }

    fn peek(&self) -> Option<u8> {
        self.b.get(self.i).copied()
    }

    /// Advances one byte, counting lines.
    pub(super) fn bump(&mut self) -> Option<u8> {
        let c = self.peek()?;
        self.i += 1;
        if c == b'\n' {
            self.line += 1;
            self.line_start = self.i;
        }
        Some(c)
    }

    fn skip_n(&mut self, n: usize) {
        let end = (self.i + n).min(self.b.len());
        while self.i < end {
            self.bump();
        }
    }

    /// The next two-letter instruction (upper case), skipping separators, escapes and PCL;
    /// `None` at the end of the file.
    pub(super) fn instruction(&mut self) -> Result<Option<[u8; 2]>, ImportError> {
        loop {
            let Some(c) = self.peek() else {
                return Ok(None);
            };
            if c == 0x1b {
                self.escape();
                continue;
            }
            if self.pcl {
                if self.b[self.i..].starts_with(b"@PJL") {
                    // A PJL line; `@PJL ENTER LANGUAGE = HPGL2` switches to HP-GL/2.
                    let l = self.text_until(b'\n').to_ascii_uppercase();
                    if l.contains("ENTER") && l.contains("HPGL") {
                        self.pcl = false;
                    }
                    continue;
                }
                if c.is_ascii_graphic() {
                    self.skipped_pcl = true;
                }
                self.bump();
                continue;
            }
            match c {
                b' ' | b'\t' | b'\r' | b'\n' | b';' | b',' | 0 | 0x03 | 0x0c | 0x1a => {
                    self.bump();
                    continue;
                }
                _ => {}
            }
            if c == b'!' {
                let place = self.place();
                let cmd = self.text_until(b';');
                let name: String = cmd.chars().take(2).collect();
                self.vendor
                    .push((format!("!{name} (vendor instruction)"), place));
                continue;
            }
            let next = self.b.get(self.i + 1).copied().unwrap_or(0);
            if !(c.is_ascii_alphabetic() && next.is_ascii_alphabetic()) {
                let end = (self.i + 8).min(self.b.len());
                let found = String::from_utf8_lossy(&self.b[self.i..end])
                    .escape_debug()
                    .to_string();
                if !self.started {
                    return Err(self.err(
                        "",
                        format!("expected a two-letter instruction, found '{found}'"),
                    ));
                }
                // Text that is not HP-GL inside a plot (notes a program left, "X0=0;Y0=0;"):
                // skipped up to the next ';' or line, counted, as plotters and hp2xx ignore it;
                // a file that is mostly such text is refused.
                let place = self.place();
                let from = self.i;
                while let Some(c) = self.bump() {
                    if c == b';' || c == b'\n' {
                        break;
                    }
                }
                self.garbage += self.i - from;
                if self.garbage * 2 > self.b.len() {
                    return Err(self.err(
                        "",
                        format!("mostly not HP-GL: {} bytes of it are not instructions (the last at {place}: '{found}')", self.garbage),
                    ));
                }
                self.vendor.push((
                    "text that is not HP-GL, skipped".to_string(),
                    format!("{place}: '{found}'"),
                ));
                continue;
            }
            self.started = true;
            self.i += 2;
            return Ok(Some([c.to_ascii_uppercase(), next.to_ascii_uppercase()]));
        }
    }

    /// Skips one escape sequence at `ESC`, switching between PCL and HP-GL as it says.
    fn escape(&mut self) {
        self.bump();
        let Some(c) = self.peek() else { return };
        match c {
            // HP-GL/1 device control: ESC . x, some with parameters up to ':'.
            b'.' => {
                self.bump();
                let Some(k) = self.bump() else { return };
                if b"@HIMNPST".contains(&k) {
                    while let Some(p) = self.peek() {
                        match p {
                            b':' => {
                                self.bump();
                                break;
                            }
                            b'0'..=b'9' | b';' | b' ' | b'-' | b'+' | b'.' => {
                                self.bump();
                            }
                            _ => break,
                        }
                    }
                }
            }
            b'E' => {
                // PCL reset: the printer is in PCL until ESC % n B.
                self.bump();
                self.pcl = true;
            }
            0x21..=0x2f => {
                let param = c;
                self.bump();
                let group = self.peek().filter(|g| (0x60..=0x7e).contains(g));
                if group.is_some() {
                    self.bump();
                }
                loop {
                    let v = self.value();
                    let Some(t) = self.bump() else { return };
                    let data = matches!(t, b'W' | b'w')
                        || (param == b'&' && group == Some(b'p') && t == b'X');
                    if param == b'%' && group.is_none() {
                        match t {
                            // UEL (ESC % -12345 X) and ESC % n A: PCL; ESC % n B: HP-GL/2.
                            b'X' | b'A' => self.pcl = true,
                            b'B' => self.pcl = false,
                            _ => {}
                        }
                    }
                    if data {
                        let n = v.unwrap_or(0.0).max(0.0) as usize;
                        self.skipped_pcl = true;
                        self.skip_n(n);
                    }
                    if !(0x60..=0x7e).contains(&t) {
                        return;
                    }
                }
            }
            _ => {
                self.bump();
            }
        }
    }

    /// A PCL value field: optional sign, digits, optional fraction.
    fn value(&mut self) -> Option<f64> {
        let start = self.i;
        if matches!(self.peek(), Some(b'+' | b'-')) {
            self.i += 1;
        }
        while matches!(self.peek(), Some(b'0'..=b'9' | b'.')) {
            self.i += 1;
        }
        std::str::from_utf8(&self.b[start..self.i])
            .ok()?
            .parse()
            .ok()
    }

    /// Skips separators inside a parameter list (commas, blanks, newlines).
    fn separators(&mut self) {
        while matches!(self.peek(), Some(b' ' | b',' | b'\t' | b'\r' | b'\n')) {
            self.bump();
        }
    }

    /// The numeric parameters of instruction `name`, up to the next instruction or `;`.
    /// Quoted strings (HP-GL/2 `CO "…"`, `BP 1,"name"`) are skipped.
    pub(super) fn numbers(&mut self, name: &str) -> Result<Vec<f64>, ImportError> {
        let mut params = Vec::new();
        loop {
            self.separators();
            match self.peek() {
                Some(b'"') => {
                    self.bump();
                    while let Some(c) = self.bump() {
                        if c == b'"' {
                            break;
                        }
                    }
                    continue;
                }
                Some(b'-' | b'+' | b'.' | b'0'..=b'9') => {}
                _ => return Ok(params),
            }
            let start = self.i;
            self.i += 1;
            loop {
                match self.peek() {
                    Some(b'0'..=b'9' | b'.') => self.i += 1,
                    // An exponent only when a digit follows: "100E" may be "…,100EA…".
                    Some(b'e' | b'E') => {
                        let d = self.b.get(self.i + 1).copied().unwrap_or(0);
                        let d2 = self.b.get(self.i + 2).copied().unwrap_or(0);
                        if d.is_ascii_digit() || (matches!(d, b'-' | b'+') && d2.is_ascii_digit()) {
                            self.i += 2;
                        } else {
                            break;
                        }
                    }
                    _ => break,
                }
            }
            let t = std::str::from_utf8(&self.b[start..self.i]).unwrap_or("");
            let v: f64 = t
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite() && v.abs() <= MAX_COORD)
                .ok_or_else(|| {
                    self.err(name, format!("'{t}' is not a number within ±{MAX_COORD}"))
                })?;
            params.push(v);
            if params.len() > MAX_PARAMS {
                return Err(self.err(name, "more than a million parameters".into()));
            }
        }
    }

    /// Text up to (not including) `end`, which is consumed; the end of the file also ends it.
    pub(super) fn text_until(&mut self, end: u8) -> String {
        let start = self.i;
        while let Some(c) = self.peek() {
            if c == end {
                break;
            }
            self.bump();
        }
        let text = String::from_utf8_lossy(&self.b[start..self.i]).into_owned();
        self.bump();
        text
    }

    /// The next raw byte (DT's terminator, SM's symbol).
    pub(super) fn raw(&mut self) -> Option<u8> {
        self.bump()
    }

    /// The next byte without consuming it.
    pub(super) fn look(&self) -> Option<u8> {
        self.peek()
    }
}
