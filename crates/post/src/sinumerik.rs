//! A Sinumerik-7M-style control as the seed 001 processor wrote for it (digest §6.3):
//! integer words in 0.001 mm (`X100000` = 100 mm), I J incremental from the arc start,
//! two-digit G codes, G53 machine positions for the tool change, G54 work zero, G43 with a
//! D register on the first positioning after a change, `T nn M06`, B table rotation in
//! 0.001°, G60 exact stop / G64 continuous path, safety plane for changes and the end.
//!
//! Oficina's interpreter has no Sinumerik dialect, so [`sinumerik_to_ngc`] rewrites such a program in
//! RS274/NGC word for word (scaling the integer words, G60 → G61, `G43 Dn` → `G43 Hn`,
//! pallet M21/M22 dropped) for the read-back; nothing else changes.

use crate::emit::{Emitter, MotionWords};
use crate::format::{Format, Numbers, Units};
use crate::{Post, PostOptions, ToolChange};
use oficina_cam::{CompSide, Operation, PathMode, Toolpath};
use std::io;

/// The tool number the program ends by loading: an empty spindle.
pub(crate) const EMPTY_TOOL: u32 = 99;

/// The machine set-up the seed's dialog asks for once per program.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Sinumerik {
    /// Tool-change position in machine coordinates, mm (seed: X450 Y150 Z600).
    pub change_at: [f64; 3],
    /// Table (B) rotation for the job, degrees; `None` writes no B word.
    pub table_rotation: Option<f64>,
    /// Coolant on with each tool (M08/M09).
    pub coolant: bool,
    /// Pallet in/out (M21/M22), machine-specific.
    pub pallet: bool,
    /// Feed at which a tool enters the first positioning after a change: G60 exact stop
    /// or G64 continuous path from the start.
    pub start_mode: PathMode,
}

impl Default for Sinumerik {
    fn default() -> Sinumerik {
        Sinumerik {
            change_at: [450.0, 150.0, 600.0],
            table_rotation: None,
            coolant: true,
            pallet: false,
            start_mode: PathMode::Continuous,
        }
    }
}

const WORDS: MotionWords = MotionWords {
    rapid: "G00",
    line: "G01",
    cw: "G02",
    ccw: "G03",
    absolute_centres: false,
    feed_words: true,
    integer_feed: true,
};

impl Sinumerik {
    fn change_position(&self, e: &Emitter) -> String {
        let [x, y, z] = self.change_at;
        format!(
            "G40 G53{}{}{}",
            e.len_word('X', x),
            e.len_word('Y', y),
            e.len_word('Z', z)
        )
    }

    fn rotation_word(e: &Emitter, degrees: f64) -> String {
        let mut s = String::new();
        e.format.push_word(&mut s, 'B', degrees);
        s
    }
}

impl Post for Sinumerik {
    fn words(&self) -> MotionWords {
        WORDS
    }

    fn default_format(&self) -> Format {
        Format {
            numbers: Numbers::Integer { per_unit: 1000 },
            units: Units::Mm,
            line_numbers: Some(crate::LineNumbers { start: 10, step: 1 }),
            modal: true,
        }
    }

    fn check_format(&self, format: &Format) -> Result<(), String> {
        format.validate()?;
        if format.units != Units::Mm {
            return Err(
                "the Sinumerik post writes 0.001 mm integer words: millimetres only".into(),
            );
        }
        Ok(())
    }

    fn prologue(&self, e: &mut Emitter, tp: &Toolpath, opts: &PostOptions) -> io::Result<()> {
        e.raw("%")?;
        crate::title_and_settings(e, opts)?;
        e.comment(&format!(
            "post = Sinumerik, safety plane Z{} mm, tool change at G53 X{} Y{} Z{}",
            tp.safe_z, self.change_at[0], self.change_at[1], self.change_at[2]
        ))?;
        let up = format!("G00 G40 G53 G90{}", e.len_word('Z', self.change_at[2]));
        e.block(&up)?;
        let at = format!(
            "G53{}{} M05",
            e.len_word('X', self.change_at[0]),
            e.len_word('Y', self.change_at[1])
        );
        e.block(&at)?;
        // Machine coordinates: the work position is not known until G54.
        e.pos = [f64::NAN; 3];
        Ok(())
    }

    /// From the safety plane: coolant off, to the change position in machine coordinates,
    /// then `T nn M06`.
    fn load_tool(&self, e: &mut Emitter, c: &ToolChange) -> io::Result<()> {
        if c.previous.is_some() {
            if self.coolant {
                e.block("M09")?;
            }
            let at = self.change_position(e);
            e.block(&format!("{at} M05"))?;
            e.pos = [f64::NAN; 3];
        }
        e.block(&format!("T{:02} M06", c.op.tool_number))
    }

    /// The first tool stays at the change position (G43 comes with the first positioning):
    /// pallet in and table rotation instead of a move to safe Z.
    fn first_tool_ready(&self, e: &mut Emitter, _c: &ToolChange) -> io::Result<()> {
        if self.pallet {
            e.block("M21")?;
        }
        if let Some(b) = self.table_rotation {
            let w = Self::rotation_word(e, b);
            e.block(w.trim())?;
        }
        Ok(())
    }

    fn spindle(
        &self,
        e: &mut Emitter,
        tp: &Toolpath,
        op: &Operation,
        new_tool: bool,
    ) -> io::Result<()> {
        let rpm = op.spindle_rpm.round();
        if new_tool {
            let mode = match self.start_mode {
                PathMode::ExactStop => "G60",
                PathMode::Continuous => "G64",
            };
            let z = e.len_word('Z', tp.safe_z);
            e.block(&format!(
                "G00 G54 G43 D{:02} {mode}{z} S{rpm} M03",
                op.tool_number
            ))?;
            e.forget_motion();
            e.pos = [f64::NAN, f64::NAN, tp.safe_z];
            if self.coolant {
                e.block("M08")?;
            }
            Ok(())
        } else {
            e.block(&format!("S{rpm} M03"))
        }
    }

    fn dwell(&self, e: &mut Emitter, seconds: f64) -> io::Result<()> {
        // G04 with the time in the F word (0.1 s resolution on these controls).
        let mut s = String::from("G04 F");
        crate::format::push_decimal(&mut s, seconds, 1);
        e.block(&s)
    }

    fn path_mode(&self, e: &mut Emitter, mode: PathMode) -> io::Result<()> {
        e.block(match mode {
            PathMode::ExactStop => "G60",
            PathMode::Continuous => "G64",
        })
    }

    /// G41/G42 use the D register the tool change selected; G40 cancels.
    fn comp(&self, e: &mut Emitter, comp: Option<(CompSide, u32)>) -> io::Result<()> {
        e.block(match comp {
            Some((CompSide::Left, _)) => "G41",
            Some((CompSide::Right, _)) => "G42",
            None => "G40",
        })
    }

    /// Coolant off, back to the change position (table at 0°), the empty tool, pallet out.
    fn end_program(&self, e: &mut Emitter) -> io::Result<()> {
        if self.coolant {
            e.block("M09")?;
        }
        let mut at = self.change_position(e);
        if self.table_rotation.is_some() {
            at.push_str(&Self::rotation_word(e, 0.0));
        }
        e.block(&format!("{at} M05"))?;
        e.block(&format!("T{EMPTY_TOOL} M06"))?;
        if self.pallet {
            e.block("M22")?;
        }
        e.block("M30")
    }
}

/// RS274/NGC text for a program this post wrote: integer length words (X Y Z I J B) are
/// scaled back to mm (degrees for B), `G60` becomes `G61`, `G04 F` a `G4 P` dwell, `G43 Dn`
/// becomes `G43 Hn`, a lone `Dn` (radius register) is dropped, `%` and the pallet codes are
/// left out. An error names the line and word it cannot read.
pub fn sinumerik_to_ngc(text: &str) -> Result<String, String> {
    let mut out = String::with_capacity(text.len());
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line == "%" || line.is_empty() {
            continue;
        }
        if line.starts_with('(') {
            out.push_str(line);
            out.push('\n');
            continue;
        }
        let (code, comment) = match line.find('(') {
            Some(k) => (&line[..k], &line[k..]),
            None => (line, ""),
        };
        let words: Vec<&str> = code.split_whitespace().collect();
        let has_g43 = words.iter().any(|w| w.eq_ignore_ascii_case("G43"));
        let has_dwell = words.iter().any(|w| w.eq_ignore_ascii_case("G04"));
        let mut o = Vec::with_capacity(words.len());
        for w in &words {
            let bad = || format!("line {}: cannot read word '{w}'", i + 1);
            let mut chars = w.chars();
            let letter = chars.next().ok_or_else(bad)?.to_ascii_uppercase();
            let value = chars.as_str();
            let int = || value.parse::<i64>().map_err(|_| bad());
            match letter {
                'X' | 'Y' | 'Z' | 'I' | 'J' | 'B' => {
                    let mut s = String::new();
                    s.push(letter);
                    crate::format::push_decimal(&mut s, int()? as f64 / 1000.0, 3);
                    o.push(s);
                }
                'G' => match int()? {
                    60 => o.push("G61".into()),
                    4 => o.push("G4".into()),
                    n => o.push(format!("G{n}")),
                },
                'D' if has_g43 => o.push(format!("H{}", int()?)),
                'D' => {}
                'M' => match int()? {
                    21 | 22 => {}
                    n => o.push(format!("M{n}")),
                },
                'F' if has_dwell => o.push(format!("P{value}")),
                'N' | 'F' | 'S' | 'T' => o.push(format!("{letter}{value}")),
                _ => return Err(bad()),
            }
        }
        // A block of pallet codes alone becomes its number only: drop it.
        if o.iter().all(|w| w.starts_with('N')) {
            continue;
        }
        out.push_str(&o.join(" "));
        if !comment.is_empty() {
            out.push(' ');
            out.push_str(comment);
        }
        out.push('\n');
    }
    Ok(out)
}
