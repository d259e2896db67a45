//! Post-processors: a [`Toolpath`] becomes G-code text for a named control.
//!
//! Every setting that shaped the program is written into the header as comments, so the
//! file says how to regenerate it. Numbers carry 4 decimals (0.1 µm): rounding can never
//! add up to a visible gouge.

use oficina_cam::{Move, Toolpath};
use std::fmt::Write as _;
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
                let _ = write!(self.line, " X{} Y{}", num(to[0]), num(to[1]));
                if to[2] != self.pos[2] {
                    let _ = write!(self.line, " Z{}", num(to[2]));
                }
                let _ = write!(self.line, " I{} J{}", num(i), num(j));
                self.pos = to;
                self.feed_word(feed);
            }
            Move::Dwell(s) => {
                self.last_motion = "";
                let _ = write!(self.line, "G4 P{}", num(s));
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
        for (k, axis) in ["X", "Y", "Z"].iter().enumerate() {
            if !to[k].is_nan() && num(to[k]) != num(self.pos[k]) {
                let _ = write!(self.line, " {axis}{}", num(to[k]));
                self.pos[k] = to[k];
            }
        }
    }

    fn feed_word(&mut self, feed_mm_s: f64) {
        let f = feed_mm_s * 60.0;
        if num(f) != num(self.feed) {
            let _ = write!(self.line, " F{}", num(f));
            self.feed = f;
        }
    }
}

/// A number with up to 4 decimals, no trailing zeros, no "-0".
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
