//! gc_execute_line STEP 1 and 2: a fresh block with the current modes, then every word of the
//! line imported into it. The errors found here are the ones grbl finds while importing:
//! unsupported codes, two commands of one modal group, two axis commands, a repeated or
//! negative value word.

use super::*;

/// Commands that do not stay in force (modal group 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum NonModal {
    None,
    Dwell,
    SetCoord,
    Home28,
    Set28,
    Home30,
    Set30,
    AbsOverride,
    SetG92,
    ResetG92,
}

/// One line's commands and values, with the modes it would leave in force (grbl's
/// `parser_block_t`).
pub(super) struct Block {
    pub non_modal: NonModal,
    /// The motion command given on the line, if any.
    pub motion: Option<MotionMode>,
    /// G10/G28/G30/G92 or a motion command claimed the axis words.
    pub axis_word_command: bool,
    pub plane: u8,
    pub inches: bool,
    pub absolute: bool,
    pub inverse_time: bool,
    pub wcs: u8,
    pub spindle: Option<Spindle>,
    pub mist: bool,
    pub flood: bool,
    pub coolant_changed: bool,
    pub stop: Option<Flow>,
    /// Some(true) = G43.1, Some(false) = G49.
    pub tlo: Option<bool>,
    values: [Option<f64>; 26],
    used: [bool; 26],
}

fn index(letter: char) -> usize {
    (letter as u8 - b'A') as usize
}

impl Block {
    /// STEP 1: a block that changes nothing, starting from the modes in force.
    fn new(modal: &Modal) -> Block {
        Block {
            non_modal: NonModal::None,
            motion: None,
            axis_word_command: false,
            plane: modal.plane,
            inches: modal.inches,
            absolute: modal.absolute,
            inverse_time: modal.inverse_time,
            wcs: modal.wcs,
            spindle: None,
            mist: modal.mist,
            flood: modal.flood,
            coolant_changed: false,
            stop: None,
            tlo: None,
            values: [None; 26],
            used: [false; 26],
        }
    }

    /// The value of a word, if the line has it.
    pub(super) fn value(&self, letter: char) -> Option<f64> {
        self.values[index(letter)]
    }

    /// The value of a word, marking it used (grbl's error 36 catches the unused ones).
    pub(super) fn take(&mut self, letter: char) -> Option<f64> {
        self.used[index(letter)] = true;
        self.value(letter)
    }

    /// A value word given on the line that no command used.
    pub(super) fn unused(&self, letter: char) -> bool {
        self.value(letter).is_some() && !self.used[index(letter)]
    }

    /// The X, Y, Z words given.
    pub(super) fn axes(&self) -> [Option<f64>; 3] {
        [self.value('X'), self.value('Y'), self.value('Z')]
    }

    /// The A word (degrees), if given.
    pub(super) fn a(&self) -> Option<f64> {
        self.value('A')
    }

    /// A second axis command (G10 G28 G30 G92 without .1, G0–G3, G38) fails before its modal
    /// group is checked, as in gcode.c.
    fn claim_axes(&mut self) -> Result<(), u8> {
        if self.axis_word_command {
            return Err(E_TWO_AXIS_COMMANDS);
        }
        self.axis_word_command = true;
        Ok(())
    }
}

/// Modal groups already given on the line.
struct Groups([bool; 16]);

impl Groups {
    fn claim(&mut self, g: usize) -> Result<(), u8> {
        if self.0[g] {
            return Err(E_MODAL_GROUP);
        }
        self.0[g] = true;
        Ok(())
    }
}

/// STEP 1 and 2: the line's words into a block.
/// `a_axis`: the machine has a 4th axis A, so A is an axis word.
pub(super) fn import_words(
    words: &[(char, f64)],
    modal: &Modal,
    a_axis: bool,
) -> Result<Block, u8> {
    let mut b = Block::new(modal);
    let mut groups = Groups([false; 16]);
    for &(letter, value) in words {
        match letter {
            'G' => g_word(&mut b, &mut groups, value)?,
            'M' => m_word(&mut b, &mut groups, value)?,
            'A' if !a_axis => return Err(E_UNSUPPORTED),
            'A' | 'F' | 'I' | 'J' | 'K' | 'L' | 'N' | 'P' | 'R' | 'S' | 'T' | 'X' | 'Y' | 'Z' => {
                let idx = index(letter);
                if b.values[idx].is_some() {
                    return Err(E_REPEATED_WORD);
                }
                if matches!(letter, 'F' | 'N' | 'P' | 'T' | 'S') && value < 0.0 {
                    return Err(gline::E_NEGATIVE);
                }
                b.values[idx] = Some(value);
            }
            _ => return Err(E_UNSUPPORTED),
        }
    }
    for c in ['N', 'F', 'S', 'T', 'X', 'Y', 'Z', 'A'] {
        b.take(c);
    }
    Ok(b)
}

fn g_word(b: &mut Block, groups: &mut Groups, value: f64) -> Result<(), u8> {
    let int = value.trunc();
    let mantissa = ((value - int) * 100.0).round() as i32;
    let code = int as i32;
    let need_int = |m: i32| if m != 0 { Err(E_NOT_INTEGER) } else { Ok(()) };
    match code {
        4 | 10 | 28 | 30 | 53 | 92 => {
            if matches!(code, 10 | 28 | 30 | 92) && mantissa == 0 {
                b.claim_axes()?;
            }
            groups.claim(0)?;
            b.non_modal = match (code, mantissa) {
                (4, 0) => NonModal::Dwell,
                (10, 0) => NonModal::SetCoord,
                (28, 0) => NonModal::Home28,
                (28, 10) => NonModal::Set28,
                (30, 0) => NonModal::Home30,
                (30, 10) => NonModal::Set30,
                (53, 0) => NonModal::AbsOverride,
                (92, 0) => NonModal::SetG92,
                (92, 10) => NonModal::ResetG92,
                _ => return Err(E_UNSUPPORTED),
            };
        }
        0 | 1 | 2 | 3 | 38 | 80 => {
            // G80 (no motion) claims no axis words.
            if code != 80 {
                b.claim_axes()?;
            }
            groups.claim(1)?;
            b.motion = Some(match (code, mantissa) {
                (0, 0) => MotionMode::Rapid,
                (1, 0) => MotionMode::Linear,
                (2, 0) => MotionMode::ArcCw,
                (3, 0) => MotionMode::ArcCcw,
                (38, 20..=50) if mantissa % 10 == 0 => MotionMode::Probe(ProbeKind {
                    away: mantissa >= 40,
                    no_error: mantissa % 20 == 10,
                }),
                (80, 0) => MotionMode::None,
                (38, _) => return Err(E_UNSUPPORTED),
                _ => return Err(E_NOT_INTEGER),
            });
        }
        17..=19 => {
            groups.claim(2)?;
            need_int(mantissa)?;
            b.plane = (code - 17) as u8;
        }
        90 | 91 => {
            if mantissa == 10 {
                // G91.1: arc IJK are incremental, grbl's only mode.
                return groups.claim(3);
            }
            groups.claim(4)?;
            need_int(mantissa)?;
            b.absolute = code == 90;
        }
        93 | 94 => {
            groups.claim(5)?;
            need_int(mantissa)?;
            b.inverse_time = code == 93;
        }
        20 | 21 => {
            groups.claim(6)?;
            need_int(mantissa)?;
            b.inches = code == 20;
        }
        40 => {
            groups.claim(7)?;
            need_int(mantissa)?;
        }
        43 | 49 => {
            groups.claim(8)?;
            b.tlo = match (code, mantissa) {
                (43, 10) => Some(true),
                (49, 0) => Some(false),
                _ => return Err(E_UNSUPPORTED),
            };
        }
        54..=59 => {
            groups.claim(12)?;
            if mantissa != 0 {
                return Err(E_UNSUPPORTED_WCS);
            }
            b.wcs = (code - 54) as u8;
        }
        61 => {
            groups.claim(13)?;
            need_int(mantissa)?;
        }
        _ => return Err(E_UNSUPPORTED),
    }
    Ok(())
}

fn m_word(b: &mut Block, groups: &mut Groups, value: f64) -> Result<(), u8> {
    if value.fract() != 0.0 {
        return Err(E_NOT_INTEGER);
    }
    match value as i32 {
        0 | 1 | 2 | 30 => {
            groups.claim(9)?;
            b.stop = Some(if value < 2.0 { Flow::Pause } else { Flow::End });
        }
        3..=5 => {
            groups.claim(10)?;
            b.spindle = Some(match value as i32 {
                3 => Spindle::Cw,
                4 => Spindle::Ccw,
                _ => Spindle::Off,
            });
        }
        7..=9 => {
            // grbl allows M7 and M8 together, so coolant is not a strict group.
            b.coolant_changed = true;
            match value as i32 {
                7 => b.mist = true,
                8 => b.flood = true,
                _ => {
                    b.mist = false;
                    b.flood = false;
                }
            }
        }
        56 => {}
        _ => return Err(E_UNSUPPORTED),
    }
    Ok(())
}
