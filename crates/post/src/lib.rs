//! Post-processors: a [`Toolpath`] becomes G-code text for a named control.
//!
//! Every setting that shaped the program is written into the header as comments, so the
//! file says how to regenerate it. Numbers carry 4 decimals (0.1 µm): rounding can never
//! add up to a visible gouge.

use oficina_cam::{Move, Toolpath};
use std::io::{self, Write};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    /// grbl 1.1: no M6 unless the machine allows it; tool changes are an M0 pause.
    Grbl,
    /// LinuxCNC: `T n M6`.
    LinuxCnc,
}

impl std::str::FromStr for Dialect {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "grbl" => Ok(Dialect::Grbl),
            "linuxcnc" | "rs274" => Ok(Dialect::LinuxCnc),
            other => Err(format!(
                "unknown post-processor '{other}': use grbl or linuxcnc"
            )),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct PostOptions {
    pub dialect: Dialect,
    /// The machine has a tool changer (or a sender that handles M6).
    pub allow_m6: bool,
    pub title: String,
    /// (name, value) pairs written as header comments.
    pub settings: Vec<(String, String)>,
}

/// Writes the whole program.
pub fn write_program(tp: &Toolpath, opts: &PostOptions, out: &mut dyn Write) -> io::Result<()> {
    let mut w = Writer {
        out,
        line: String::new(),
        last_motion: "",
        pos: [f64::NAN; 3],
        feed: f64::NAN,
    };
    w.comment(&opts.title)?;
    for (k, v) in &opts.settings {
        w.comment(&format!("{k} = {v}"))?;
    }
    w.comment(&format!(
        "post = {:?}, M6 allowed = {}",
        opts.dialect, opts.allow_m6
    ))?;
    w.raw("G21 G90 G94 G17")?;
    let mut current: Option<u32> = None;
    for op in &tp.operations {
        if current != Some(op.tool_number) {
            w.comment(&format!(
                "operation: {} with T{} {}",
                op.name, op.tool_number, op.tool
            ))?;
            let uses_m6 = opts.dialect == Dialect::LinuxCnc || opts.allow_m6;
            if uses_m6 {
                if current.is_some() {
                    w.rapid_z(tp.safe_z)?;
                }
                w.raw(&format!("T{} M6", op.tool_number))?;
            } else if current.is_some() {
                w.rapid_z(tp.safe_z)?;
                w.raw("M5")?;
                w.raw(&format!(
                    "(MSG, Change to T{}: {}, set Z zero, then resume)",
                    op.tool_number,
                    op.tool.spec()
                ))?;
                // grbl accepts and ignores T; it names the tool for readers and simulators.
                w.raw(&format!("T{}", op.tool_number))?;
                w.raw("M0")?;
            } else {
                w.comment(&format!(
                    "load T{} ({}) and set Z zero on the stock top before starting",
                    op.tool_number,
                    op.tool.spec()
                ))?;
                w.raw(&format!("T{}", op.tool_number))?;
            }
            if current.is_none() {
                // First move of the program: up to safe Z with the tool now known.
                w.rapid_z(tp.safe_z)?;
            }
            current = Some(op.tool_number);
        } else {
            w.comment(&format!("operation: {}", op.name))?;
        }
        w.raw(&format!("S{} M3", num(op.spindle_rpm)))?;
        for m in &op.moves {
            w.motion(m)?;
        }
    }
    w.rapid_z(tp.safe_z)?;
    w.raw("M5")?;
    w.raw("M30")?;
    Ok(())
}

/// The program as a string.
pub fn program_text(tp: &Toolpath, opts: &PostOptions) -> String {
    let mut buf = Vec::new();
    write_program(tp, opts, &mut buf).expect("writing to memory cannot fail");
    String::from_utf8(buf).expect("the post writes ASCII")
}

struct Writer<'a> {
    out: &'a mut dyn Write,
    line: String,
    last_motion: &'static str,
    pos: [f64; 3],
    feed: f64,
}

impl Writer<'_> {
    fn raw(&mut self, s: &str) -> io::Result<()> {
        self.last_motion = if s.starts_with("G0 ") || s.starts_with("G1 ") {
            self.last_motion
        } else {
            ""
        };
        writeln!(self.out, "{s}")
    }

    fn comment(&mut self, s: &str) -> io::Result<()> {
        // Parentheses would end the comment early.
        let clean: String = s
            .chars()
            .map(|c| match c {
                '(' => '[',
                ')' => ']',
                c => c,
            })
            .filter(|c| c.is_ascii() && *c != '\n')
            .collect();
        writeln!(self.out, "({clean})")
    }

    fn rapid_z(&mut self, z: f64) -> io::Result<()> {
        let to = [self.pos[0], self.pos[1], z];
        self.motion(&Move::Rapid { to })
    }

    fn motion(&mut self, m: &Move) -> io::Result<()> {
        self.line.clear();
        let before = self.last_motion;
        match *m {
            Move::Rapid { to } => {
                self.word_motion("G0");
                self.axes(to);
            }
            Move::Line { to, feed } => {
                self.word_motion("G1");
                self.axes(to);
                self.feed_word(feed);
            }
            Move::Arc {
                to,
                center,
                ccw,
                feed,
            } => {
                let (i, j) = (center[0] - self.pos[0], center[1] - self.pos[1]);
                self.last_motion = "";
                self.word_motion(if ccw { "G3" } else { "G2" });
                push_word(&mut self.line, 'X', to[0]);
                push_word(&mut self.line, 'Y', to[1]);
                if to[2] != self.pos[2] {
                    push_word(&mut self.line, 'Z', to[2]);
                }
                push_word(&mut self.line, 'I', i);
                push_word(&mut self.line, 'J', j);
                self.pos = to;
                self.feed_word(feed);
            }
            Move::Dwell(s) => {
                self.last_motion = "";
                self.line.push_str("G4 P");
                push_num(&mut self.line, s);
            }
        }
        if self.line.is_empty() || self.line == "G0" || self.line == "G1" {
            // Nothing moved: the G word was not written, so it is not modal yet.
            self.last_motion = before;
            return Ok(());
        }
        writeln!(self.out, "{}", self.line.trim_start())
    }

    fn word_motion(&mut self, g: &'static str) {
        if self.last_motion != g {
            self.line.push_str(g);
            self.last_motion = g;
        }
    }

    fn axes(&mut self, to: [f64; 3]) {
        for (k, axis) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            if !to[k].is_nan() && !same_printed(to[k], self.pos[k]) {
                push_word(&mut self.line, axis, to[k]);
                self.pos[k] = to[k];
            }
        }
    }

    fn feed_word(&mut self, feed_mm_s: f64) {
        let f = feed_mm_s * 60.0;
        if !same_printed(f, self.feed) {
            push_word(&mut self.line, 'F', f);
            self.feed = f;
        }
    }
}

/// Ten-thousandths: the 4 decimals every number is printed with.
const SCALE: f64 = 1e4;
/// Beyond this the fixed-point path could overflow; such numbers take the slow path.
const FIXED_LIMIT: f64 = 1e14;

/// Whether two numbers print the same (both NaN counts as the same).
fn same_printed(a: f64, b: f64) -> bool {
    match (fixed(a), fixed(b)) {
        (Some(x), Some(y)) => x == y,
        _ => num(a) == num(b),
    }
}

/// `v` in ten-thousandths, rounded half away from zero, when it fits the fast path.
fn fixed(v: f64) -> Option<i64> {
    let scaled = v * SCALE;
    // `as` truncates toward zero in one instruction; f64::round is a libm call here.
    (scaled.abs() < FIXED_LIMIT).then(|| (scaled + 0.5f64.copysign(scaled)) as i64)
}

/// " Xnum": a space, the letter and the number.
fn push_word(line: &mut String, letter: char, v: f64) {
    line.push(' ');
    line.push(letter);
    push_num(line, v);
}

/// Writes a number with up to 4 decimals, no trailing zeros, no "-0", without going
/// through the float formatter (the post writes millions of these).
fn push_num(out: &mut String, v: f64) {
    let Some(mut n) = fixed(v) else {
        out.push_str(&num(v));
        return;
    };
    if n < 0 {
        out.push('-');
        n = -n;
    }
    let (whole, mut frac) = (n / 10_000, n % 10_000);
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
        let mut places = 4;
        while frac % 10 == 0 {
            frac /= 10;
            places -= 1;
        }
        out.push('.');
        for p in (0..places).rev() {
            out.push((b'0' + (frac / 10i64.pow(p) % 10) as u8) as char);
        }
    }
}

/// A number with up to 4 decimals, no trailing zeros, no "-0" (the float formatter: for
/// words written once per program and for numbers too large for [`push_num`]).
fn num(v: f64) -> String {
    if v.is_nan() {
        return "nan".into();
    }
    let mut s = format!("{v:.4}");
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
            0.0, -0.0, 1.0, -1.0, 0.00004, -0.00004, 0.00005, 12.5, -3.14159,
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
        for v in values {
            let mut fast = String::new();
            push_num(&mut fast, v);
            let slow = num(v);
            if fast != slow {
                // Only a value within rounding noise of a half ten-thousandth may differ, by
                // one unit in the last place.
                let (a, b): (f64, f64) = (fast.parse().unwrap(), slow.parse().unwrap());
                assert!((a - b).abs() <= 1.0001e-4, "{v}: {fast} vs {slow}");
                assert!(
                    ((v * SCALE).fract().abs() - 0.5).abs() < 1e-6,
                    "{v}: {fast} vs {slow}"
                );
            }
        }
    }
}
