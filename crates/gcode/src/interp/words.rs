//! Sorting one block's words into modal groups and value slots, with LinuxCNC's checks for
//! conflicts: two codes of one modal group, a letter given twice, codes that do not exist.
//! Everything lives in fixed arrays so decoding a block never allocates.

use crate::block::Block;
use crate::diag::{Diagnostic, Span};

/// A G or M code in tenths (G38.2 → 382, G1 → 10), with the span of its word.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Code {
    pub tenths: u16,
    pub span: Span,
}

/// A value word (X, F, P …) with its span.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Value {
    pub v: f64,
    pub span: Span,
}

/// The G modal groups of LinuxCNC (`overview.adoc`, "Modal Groups"), as array indices.
pub(crate) mod g_group {
    pub(crate) const NON_MODAL: usize = 0;
    pub(crate) const MOTION: usize = 1;
    pub(crate) const PLANE: usize = 2;
    pub(crate) const DISTANCE: usize = 3;
    pub(crate) const ARC_DISTANCE: usize = 4;
    pub(crate) const FEED_MODE: usize = 5;
    pub(crate) const UNITS: usize = 6;
    pub(crate) const CUTTER_COMP: usize = 7;
    pub(crate) const TOOL_LENGTH: usize = 8;
    /// G96 / G97: constant surface speed or rev/min (LinuxCNC's group 14).
    pub(crate) const SPINDLE_MODE: usize = 9;
    pub(crate) const RETRACT: usize = 10;
    /// G7 / G8: lathe diameter or radius mode (LinuxCNC's group 15).
    pub(crate) const LATHE_DIAMETER: usize = 11;
    pub(crate) const COORD_SYSTEM: usize = 12;
    pub(crate) const CONTROL: usize = 13;
    pub(crate) const COUNT: usize = 14;
}

/// The M modal groups.
pub(crate) mod m_group {
    pub(crate) const STOP: usize = 4;
    /// M66: inputs.
    pub(crate) const IO: usize = 5;
    pub(crate) const TOOL_CHANGE: usize = 6;
    pub(crate) const SPINDLE: usize = 7;
    pub(crate) const COOLANT: usize = 8;
    pub(crate) const OVERRIDE: usize = 9;
    pub(crate) const COUNT: usize = 10;
}

/// The modal group of a G code in tenths; `None` for codes Oficina does not know.
pub(crate) fn group_of_g(tenths: u16) -> Option<usize> {
    use g_group::*;
    Some(match tenths {
        40 | 100 | 280 | 281 | 300 | 301 | 520 | 530 | 920 | 921 | 922 | 923 => NON_MODAL,
        0
        | 10
        | 20
        | 30
        | 50..=53
        | 330
        | 331
        | 730
        | 740
        | 760
        | 800
        | 810
        | 820
        | 830
        | 840
        | 850
        | 860
        | 870
        | 880
        | 890 => MOTION,
        // G70–G72 lathe cycles (lathe_cycle/), LinuxCNC only.
        700 | 710..=712 | 720..=722 => MOTION,
        // G38.2–G38.5 (probing) decode so that grbl can run them; the other dialects
        // refuse them after decoding (dialect::refuse_probe); LinuxCNC runs them (probe.rs).
        382..=385 => MOTION,
        170 | 180 | 190 => PLANE,
        900 | 910 => DISTANCE,
        901 | 911 => ARC_DISTANCE,
        930 | 940 | 950 => FEED_MODE,
        200 | 210 => UNITS,
        400 | 410 | 411 | 420 | 421 => CUTTER_COMP,
        430 | 431 | 490 => TOOL_LENGTH,
        980 | 990 => RETRACT,
        960 | 970 => SPINDLE_MODE,
        70 | 80 => LATHE_DIAMETER,
        540 | 550 | 560 | 570 | 580 | 590 | 591 | 592 | 593 => COORD_SYSTEM,
        610 | 611 | 640 => CONTROL,
        _ => return None,
    })
}

/// The modal group of an M code; `None` for codes Oficina does not know.
pub(crate) fn group_of_m(code: u16) -> Option<usize> {
    use m_group::*;
    Some(match code {
        0 | 1 | 2 | 30 | 60 => STOP,
        6 => TOOL_CHANGE,
        3..=5 | 19 | 70..=73 => SPINDLE,
        7..=9 => COOLANT,
        48..=53 => OVERRIDE,
        66 => IO,
        _ => return None,
    })
}

/// The bits of `letters` (upper case, `@`, `^`) for [`Decoded::has_any_of`].
pub(crate) const fn letter_mask(letters: &[u8]) -> u32 {
    let mut mask = 0;
    let mut i = 0;
    while i < letters.len() {
        mask |= 1 << byte_slot(letters[i]);
        i += 1;
    }
    mask
}

/// Value slots: A…Z, then the polar radius `@` and angle `^`.
pub(crate) const SLOTS: usize = 28;

const fn byte_slot(b: u8) -> usize {
    match b {
        b'@' => 26,
        b'^' => 27,
        _ => (b - b'A') as usize,
    }
}

/// Index of a value letter in [`Decoded::values`].
pub(crate) fn slot(letter: char) -> usize {
    byte_slot(letter as u8)
}

/// One block, sorted. Letters G and M live in `g`/`m`; all other letters in `values`.
#[derive(Clone, Debug)]
pub(crate) struct Decoded {
    pub line: u32,
    pub g: [Option<Code>; g_group::COUNT],
    pub m: [Option<Code>; m_group::COUNT],
    pub values: [Option<Value>; SLOTS],
    /// Bit `slot` is set for each letter in `values`: clearing touches only those.
    present: u32,
}

impl Decoded {
    pub(crate) fn get(&self, letter: char) -> Option<f64> {
        self.values[slot(letter)].map(|w| w.v)
    }

    pub(crate) fn has(&self, letter: char) -> bool {
        self.values[slot(letter)].is_some()
    }

    /// The span of a value word, or of the whole line if it is absent.
    pub(crate) fn span_of(&self, letter: char) -> Span {
        self.values[slot(letter)]
            .map(|w| w.span)
            .unwrap_or(Span::line(self.line))
    }

    pub(crate) fn g_in(&self, group: usize) -> Option<u16> {
        self.g[group].map(|c| c.tenths)
    }

    pub(crate) fn m_in(&self, group: usize) -> Option<u16> {
        self.m[group].map(|c| c.tenths)
    }

    /// The span of the G code of `group`, or of the whole line.
    pub(crate) fn g_span(&self, group: usize) -> Span {
        self.g[group]
            .map(|c| c.span)
            .unwrap_or(Span::line(self.line))
    }

    /// The span of the M code of `group`, or of the whole line.
    pub(crate) fn m_span(&self, group: usize) -> Span {
        self.m[group]
            .map(|c| c.span)
            .unwrap_or(Span::line(self.line))
    }

    /// Whether any letter of `mask` (see [`letter_mask`]) has a value word.
    pub(crate) fn has_any_of(&self, mask: u32) -> bool {
        self.present & mask != 0
    }

    pub(crate) fn any_axis(&self) -> bool {
        const fn bit(letter: u8) -> u32 {
            1 << (letter - b'A')
        }
        const AXES: u32 = bit(b'X')
            | bit(b'Y')
            | bit(b'Z')
            | bit(b'A')
            | bit(b'B')
            | bit(b'C')
            | 1 << 26
            | 1 << 27;
        self.present & AXES != 0
    }

    /// The span of the first axis word, for errors about axis words as a whole.
    pub(crate) fn axis_span(&self) -> Span {
        "XYZABC@^"
            .chars()
            .find(|&c| self.has(c))
            .map(|c| self.span_of(c))
            .unwrap_or(Span::line(self.line))
    }

    /// Sort the words of `block`; errors name the offending word (the unit tests' entry).
    #[cfg(test)]
    pub(crate) fn from_block(block: &Block) -> Result<Decoded, Diagnostic> {
        let mut d = Decoded::empty();
        d.fill(block).map_err(|e| e.diag)?;
        Ok(d)
    }

    pub(crate) fn empty() -> Decoded {
        Decoded {
            line: 0,
            g: [None; g_group::COUNT],
            m: [None; m_group::COUNT],
            values: [None; SLOTS],
            present: 0,
        }
    }

    /// Decode `block` in place: the interpreter reuses one `Decoded` (over a kilobyte)
    /// rather than moving a fresh one around for every block.
    pub(crate) fn fill(&mut self, block: &Block) -> Result<(), DecodeError> {
        self.line = block.line;
        self.g = [None; g_group::COUNT];
        self.m = [None; m_group::COUNT];
        while self.present != 0 {
            let s = self.present.trailing_zeros() as usize;
            self.values[s] = None;
            self.present &= self.present - 1;
        }
        let d = self;
        for w in &block.words {
            match w.letter {
                'G' => {
                    let tenths = to_tenths(w.value)
                        .ok_or_else(|| DecodeError::unsupported(unknown_g(w.span, w.value)))?;
                    let group = group_of_g(tenths)
                        .ok_or_else(|| DecodeError::unsupported(unknown_g(w.span, w.value)))?;
                    // rs274 accepts G80 beside another motion code: the other one wins.
                    // G80 alone is kept (it cancels the motion mode).
                    if group == g_group::MOTION && (tenths == 800 || d.g_in(group) == Some(800)) {
                        if tenths != 800 || d.g[group].is_none() {
                            d.g[group] = Some(Code {
                                tenths,
                                span: w.span,
                            });
                        }
                        continue;
                    }
                    if let Some(first) = d.g[group] {
                        return Err(DecodeError {
                            fault: DecodeFault::SameModalGroup {
                                letter: 'G',
                                first: first.tenths,
                                second: tenths,
                            },
                            diag: Diagnostic::error(
                                w.span,
                                "Two g codes used from same modal group",
                            )
                            .with_help("a block may hold at most one G code of each modal group"),
                        });
                    }
                    d.g[group] = Some(Code {
                        tenths,
                        span: w.span,
                    });
                }
                'M' => {
                    let code = (w.value.fract() == 0.0 && (0.0..1000.0).contains(&w.value))
                        .then_some(w.value as u16);
                    let group = code.and_then(group_of_m).ok_or_else(|| {
                        DecodeError::unsupported(
                            Diagnostic::error(w.span, format!("Unknown m code used: M{}", w.value))
                                .with_help(
                                    "supported: M0 M1 M2 M3 M4 M5 M6 M7 M8 M9 M19 M30 M48-M53 M60",
                                ),
                        )
                    })?;
                    if let Some(first) = d.m[group] {
                        return Err(DecodeError {
                            fault: DecodeFault::SameModalGroup {
                                letter: 'M',
                                first: first.tenths,
                                second: code.unwrap_or(0),
                            },
                            diag: Diagnostic::error(
                                w.span,
                                "Two m codes used from same modal group",
                            )
                            .with_help("a block may hold at most one M code of each modal group"),
                        });
                    }
                    d.m[group] = Some(Code {
                        tenths: code.unwrap_or(0),
                        span: w.span,
                    });
                }
                'A'..='Z' | '@' | '^' => {
                    if matches!(w.letter, 'U' | 'V' | 'W' | 'N' | 'O') {
                        return Err(DecodeError::unsupported(
                            Diagnostic::error(
                                w.span,
                                format!("Bad character '{}' used", w.letter.to_ascii_lowercase()),
                            )
                            .with_help("Oficina machines have the axes X Y Z A B C"),
                        ));
                    }
                    let s = slot(w.letter);
                    if d.values[s].is_some() {
                        return Err(DecodeError {
                            fault: DecodeFault::RepeatedWord,
                            diag: Diagnostic::error(
                                w.span,
                                format!(
                                    "Multiple {} words on one line",
                                    w.letter.to_ascii_lowercase()
                                ),
                            ),
                        });
                    }
                    d.values[s] = Some(Value {
                        v: w.value,
                        span: w.span,
                    });
                    d.present |= 1 << s;
                }
                other => {
                    return Err(DecodeError::unsupported(Diagnostic::error(
                        w.span,
                        format!("Bad character '{other}' used"),
                    )))
                }
            }
        }
        Ok(())
    }
}

/// What kind of conflict stopped decoding: a firmware dialect numbers its error by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DecodeFault {
    /// Two codes of one modal group: the letter and both codes in tenths (G38.2 is 382).
    SameModalGroup {
        letter: char,
        first: u16,
        second: u16,
    },
    /// A letter given twice.
    RepeatedWord,
    /// A code or letter that does not exist.
    Unsupported,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct DecodeError {
    pub fault: DecodeFault,
    pub diag: Diagnostic,
}

impl DecodeError {
    fn unsupported(diag: Diagnostic) -> DecodeError {
        DecodeError {
            fault: DecodeFault::Unsupported,
            diag,
        }
    }
}

/// G numbers have at most one decimal (G38.2); anything finer is not a G code.
fn to_tenths(v: f64) -> Option<u16> {
    let x = v * 10.0;
    // Codes 0 to 999.9 (NaN fails too). In that range `(x + 0.5) as u16` is x rounded,
    // without a call to `round` (a library routine on baseline x86-64); the two differ
    // only next to a half, which is far from any code anyway.
    if !(x > -0.5 && x < 9999.5) {
        return None;
    }
    let t = (x + 0.5) as u16;
    ((x - f64::from(t)).abs() < 1e-6).then_some(t)
}

pub(crate) fn unknown_g(span: Span, value: f64) -> Diagnostic {
    let help = match to_tenths(value) {
        Some(700 | 710..=712 | 720..=722 | 382..=385) => {
            "this LinuxCNC code (the G70–G72 lathe cycles, probing) runs in the LinuxCNC \
             dialect only"
        }
        _ => "see the list of supported G codes in the user guide",
    };
    Diagnostic::error(span, format!("Unknown g code used: G{value}")).with_help(help)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::block::Word;

    fn block(words: &[(char, f64)]) -> Block {
        Block {
            line: 3,
            words: words
                .iter()
                .enumerate()
                .map(|(i, &(letter, value))| Word {
                    letter,
                    value,
                    span: Span::new(3, 1 + 4 * i as u32, 3),
                })
                .collect(),
            ..Block::default()
        }
    }

    #[test]
    fn groups_and_values_are_sorted() {
        let d = Decoded::from_block(&block(&[('G', 1.0), ('X', 2.0), ('G', 91.0), ('M', 3.0)]))
            .unwrap();
        assert_eq!(d.g_in(g_group::MOTION), Some(10));
        assert_eq!(d.g_in(g_group::DISTANCE), Some(910));
        assert_eq!(d.m_in(m_group::SPINDLE), Some(3));
        assert_eq!(d.get('X'), Some(2.0));
    }

    #[test]
    fn conflicts_name_the_second_word() {
        let e = Decoded::from_block(&block(&[('G', 0.0), ('G', 1.0)])).unwrap_err();
        assert_eq!(e.message, "Two g codes used from same modal group");
        assert_eq!(e.span.col, 5);
        let e = Decoded::from_block(&block(&[('X', 0.0), ('X', 1.0)])).unwrap_err();
        assert_eq!(e.message, "Multiple x words on one line");
        let e = Decoded::from_block(&block(&[('G', 1.5)])).unwrap_err();
        assert!(e.message.starts_with("Unknown g code"));
        assert!(Decoded::from_block(&block(&[('G', 5.2)])).is_ok());
        assert!(Decoded::from_block(&block(&[('G', 71.0)])).is_ok());
        let e = Decoded::from_block(&block(&[('G', 12.0)])).unwrap_err();
        assert!(e.help.unwrap().contains("supported G codes"));
        assert!(Decoded::from_block(&block(&[('G', 81.0)])).is_ok());
        assert!(Decoded::from_block(&block(&[('G', 81.5)])).is_err());
        assert_eq!(to_tenths(38.2), Some(382));
        assert_eq!(to_tenths(-0.00000001), Some(0));
        assert_eq!(to_tenths(999.9), Some(9999));
        for bad in [-0.1, 1.05, 999.96, 1000.0, f64::NAN, f64::INFINITY] {
            assert_eq!(to_tenths(bad), None, "{bad}");
        }
    }
}
