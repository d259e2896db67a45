//! A grbl 1.1 G-code interpreter: the modal state, the checks of gcode.c with grbl's error
//! numbers, and the moves a line produces (arcs cut into chords the way grbl's mc_arc does,
//! so the emulator fills its planner with as many blocks as the firmware would).
//!
//! It serves two masters: the emulator executes with it, and the resume logic replays a
//! program through it to know the modal state and the tool position at any line. A failing
//! line leaves the state untouched, as in grbl.

use crate::gline;

mod arc;
mod check;
mod execute;
mod parse;

pub(crate) const E_UNSUPPORTED: u8 = 20;
pub(crate) const E_MODAL_GROUP: u8 = 21;
pub(crate) const E_UNDEFINED_FEED: u8 = 22;
pub(crate) const E_NOT_INTEGER: u8 = 23;
pub(crate) const E_TWO_AXIS_COMMANDS: u8 = 24;
pub(crate) const E_REPEATED_WORD: u8 = 25;
pub(crate) const E_NO_AXIS_WORDS: u8 = 26;
pub(crate) const E_INVALID_LINE_NUMBER: u8 = 27;
pub(crate) const E_VALUE_MISSING: u8 = 28;
pub(crate) const E_UNSUPPORTED_WCS: u8 = 29;
pub(crate) const E_G53_MODE: u8 = 30;
pub(crate) const E_AXIS_UNUSED: u8 = 31;
pub(crate) const E_NO_AXIS_IN_PLANE: u8 = 32;
pub(crate) const E_INVALID_TARGET: u8 = 33;
pub(crate) const E_ARC_RADIUS: u8 = 34;
pub(crate) const E_NO_OFFSETS_IN_PLANE: u8 = 35;
pub(crate) const E_UNUSED_WORDS: u8 = 36;
pub(crate) const E_TOOL_NUMBER: u8 = 38;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionMode {
    Rapid,
    Linear,
    ArcCw,
    ArcCcw,
    Probe(ProbeKind),
    None,
}

/// Which of grbl's four probing moves: G38.2 (toward the work, alarm if it is not touched),
/// G38.3 (toward, no alarm), G38.4 (away, until contact is lost, alarm if it is not),
/// G38.5 (away, no alarm).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ProbeKind {
    /// G38.4 / G38.5: the move ends when the probe opens.
    pub away: bool,
    /// G38.3 / G38.5: a move that ends without the change is not an alarm.
    pub no_error: bool,
}

impl ProbeKind {
    /// The G-code that names it, e.g. `G38.2`.
    pub fn code(self) -> &'static str {
        match (self.away, self.no_error) {
            (false, false) => "G38.2",
            (false, true) => "G38.3",
            (true, false) => "G38.4",
            (true, true) => "G38.5",
        }
    }
}

/// Spindle state (M3 / M4 / M5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spindle {
    /// M5.
    Off,
    /// M3.
    Cw,
    /// M4.
    Ccw,
}

/// The modal groups grbl keeps (what `$G` reports).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Modal {
    /// G0 / G1 / G2 / G3 / G38.x / G80.
    pub motion: MotionMode,
    /// 0 = G17 (XY), 1 = G18 (ZX), 2 = G19 (YZ)
    pub plane: u8,
    /// G20 in force (else G21).
    pub inches: bool,
    /// G90 in force (else G91).
    pub absolute: bool,
    /// G93 in force (else G94).
    pub inverse_time: bool,
    /// 0 = G54 … 5 = G59
    pub wcs: u8,
    /// M3 / M4 / M5.
    pub spindle: Spindle,
    /// M7 on.
    pub mist: bool,
    /// M8 on.
    pub flood: bool,
}

impl Default for Modal {
    fn default() -> Self {
        Modal {
            motion: MotionMode::Rapid,
            plane: 0,
            inches: false,
            absolute: true,
            inverse_time: false,
            wcs: 0,
            spindle: Spindle::Off,
            mist: false,
            flood: false,
        }
    }
}

/// How fast a segment moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rate {
    /// At the machine's maximum rates ($110…).
    Rapid,
    /// mm/min
    Feed(f64),
}

/// One straight segment in machine coordinates (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// End point, machine mm.
    pub to: [f64; 3],
    /// The 4th axis A at the end, degrees (unchanged on a 3-axis machine).
    pub a: f64,
    /// Rapid or feed rate.
    pub rate: Rate,
}

/// Program flow requested by the line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Go on with the next line.
    Continue,
    /// M0 / M1: feed hold after the buffer drains.
    Pause,
    /// M2 / M30: end of program.
    End,
}

/// What executing one line does beyond changing the modal state.
#[derive(Clone, Debug, PartialEq)]
pub struct Effect {
    /// Straight pieces to queue, in order.
    pub segments: Vec<Segment>,
    /// Seconds to dwell (G4).
    pub dwell: f64,
    /// Pause, end, or go on.
    pub flow: Flow,
    /// The line waits for the planner to empty before acknowledging (spindle, coolant,
    /// offsets, dwell in grbl).
    pub sync: bool,
    /// A probing move (G38.x): which one.
    pub probe: Option<ProbeKind>,
}

/// Interpreter state: modal groups, feed, spindle, tool, position and offsets (machine mm).
#[derive(Clone, Debug, PartialEq)]
pub struct Interp {
    /// Modal groups in force.
    pub modal: Modal,
    /// Programmed feed, mm/min (or 1/min in inverse time).
    pub feed: f64,
    /// Spindle speed, rpm.
    pub spindle_speed: f64,
    /// The tool number last selected.
    pub tool: u32,
    /// Machine position of the controlled point.
    pub pos: [f64; 3],
    /// G54…G59 origins, machine mm.
    pub wcs_offsets: [[f64; 3]; 6],
    /// G92 offset, mm.
    pub g92: [f64; 3],
    /// G43.1 tool length offset, mm.
    pub tool_length: f64,
    /// G28 stored position, machine mm.
    pub g28: [f64; 3],
    /// G30 stored position, machine mm.
    pub g30: [f64; 3],
    /// $12 arc tolerance, mm.
    pub arc_tolerance: f64,
    /// The machine has a 4th axis A (grblHAL built with N_AXIS = 4): A words are read,
    /// otherwise they are error 20 as in grbl 1.1.
    pub a_axis: bool,
    /// Machine position of A, degrees. A has no work offset here: work A = machine A.
    pub a: f64,
}

impl Default for Interp {
    fn default() -> Self {
        Interp {
            modal: Modal::default(),
            feed: 0.0,
            spindle_speed: 0.0,
            tool: 0,
            pos: [0.0; 3],
            wcs_offsets: [[0.0; 3]; 6],
            g92: [0.0; 3],
            tool_length: 0.0,
            g28: [0.0; 3],
            g30: [0.0; 3],
            arc_tolerance: 0.002,
            a_axis: false,
            a: 0.0,
        }
    }
}

impl Interp {
    /// Work coordinate offset (what grbl reports as WCO).
    pub fn wco(&self) -> [f64; 3] {
        let w = self.wcs_offsets[self.modal.wcs as usize];
        [
            w[0] + self.g92[0],
            w[1] + self.g92[1],
            w[2] + self.g92[2] + self.tool_length,
        ]
    }

    /// Position in the active work coordinates (mm).
    pub fn work_pos(&self) -> [f64; 3] {
        let o = self.wco();
        [self.pos[0] - o[0], self.pos[1] - o[1], self.pos[2] - o[2]]
    }

    /// Executes one cleaned line (no `$` commands). On error the state is unchanged.
    pub fn execute(&mut self, clean: &str) -> Result<Effect, u8> {
        let words = gline::words(clean)?;
        let mut next = self.clone();
        let effect = next.execute_words(&words, false)?;
        *self = next;
        Ok(effect)
    }

    /// Executes the body of a `$J=` jog line: only G20/21, G90/91, G53, X Y Z and F, and F is
    /// required. The modal state is not changed by a jog.
    pub fn jog(&mut self, body: &str) -> Result<Effect, u8> {
        const E_INVALID_JOG: u8 = 16;
        let clean = gline::clean(body)?;
        let words = gline::words(&clean)?;
        for (l, v) in &words {
            let ok = match l {
                'G' => [20.0, 21.0, 90.0, 91.0, 53.0].contains(v),
                'X' | 'Y' | 'Z' | 'F' | 'N' => true,
                _ => false,
            };
            if !ok {
                return Err(E_INVALID_JOG);
            }
        }
        if !words.iter().any(|(l, _)| *l == 'F') {
            return Err(E_UNDEFINED_FEED);
        }
        let mut next = self.clone();
        next.modal.motion = MotionMode::Linear;
        next.modal.inverse_time = false;
        let effect = next.execute_words(&words, true)?;
        // A jog moves the machine but leaves the parser's modal state as it was.
        self.pos = next.pos;
        Ok(effect)
    }

    /// One line through gc_execute_line's steps: import the words (STEP 1–2), check them
    /// (STEP 3), execute (STEP 4).
    fn execute_words(&mut self, words: &[(char, f64)], jog: bool) -> Result<Effect, u8> {
        let block = parse::import_words(words, &self.modal, self.a_axis)?;
        let plan = check::check(self, &block)?;
        execute::execute(self, block, plan, jog)
    }

    /// The `$G` report: `G0 G54 G17 G21 G90 G94 M5 M9 T0 F0 S0`.
    pub fn parser_state(&self) -> String {
        let m = &self.modal;
        let motion = match m.motion {
            MotionMode::Rapid => "G0",
            MotionMode::Linear => "G1",
            MotionMode::ArcCw => "G2",
            MotionMode::ArcCcw => "G3",
            MotionMode::Probe(kind) => kind.code(),
            MotionMode::None => "G80",
        };
        let spindle = match m.spindle {
            Spindle::Off => "M5",
            Spindle::Cw => "M3",
            Spindle::Ccw => "M4",
        };
        let coolant = match (m.mist, m.flood) {
            (false, false) => "M9".to_string(),
            (true, false) => "M7".to_string(),
            (false, true) => "M8".to_string(),
            (true, true) => "M7 M8".to_string(),
        };
        let scale = if m.inches && !m.inverse_time {
            25.4
        } else {
            1.0
        };
        format!(
            "{motion} G{} G{} G{} G{} G{} {spindle} {coolant} T{} F{} S{}",
            54 + m.wcs,
            17 + m.plane,
            if m.inches { 20 } else { 21 },
            if m.absolute { 90 } else { 91 },
            if m.inverse_time { 93 } else { 94 },
            self.tool,
            trim_num(self.feed / scale),
            trim_num(self.spindle_speed)
        )
    }
}

fn trim_num(v: f64) -> String {
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Distance between two points, mm.
pub fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(i: &mut Interp, line: &str) -> Result<Effect, u8> {
        i.execute(&gline::clean(line).unwrap())
    }

    #[test]
    fn grbl_error_numbers() {
        let mut i = Interp::default();
        assert_eq!(run(&mut i, "G1 X10"), Err(E_UNDEFINED_FEED));
        assert_eq!(run(&mut i, "G0 G1 X1"), Err(E_TWO_AXIS_COMMANDS));
        assert_eq!(run(&mut i, "G17 G18"), Err(E_MODAL_GROUP));
        assert_eq!(run(&mut i, "X1 X2"), Err(E_REPEATED_WORD));
        assert_eq!(run(&mut i, "G5 X1"), Err(E_UNSUPPORTED));
        assert_eq!(run(&mut i, "G1.5 X1"), Err(E_NOT_INTEGER));
        assert_eq!(run(&mut i, "G2 X10 F100"), Err(E_NO_OFFSETS_IN_PLANE));
        assert_eq!(run(&mut i, "G2 Z10 I1 F100"), Err(E_NO_AXIS_IN_PLANE));
        assert_eq!(run(&mut i, "G2 X10 R2 F100"), Err(E_ARC_RADIUS));
        assert_eq!(run(&mut i, "G4"), Err(E_VALUE_MISSING));
        assert_eq!(run(&mut i, "G0 X1 P3"), Err(E_UNUSED_WORDS));
        assert_eq!(run(&mut i, "G59.1"), Err(E_UNSUPPORTED_WCS));
        assert_eq!(run(&mut i, "M6 T300"), Err(E_UNSUPPORTED));
        assert_eq!(run(&mut i, "T300"), Err(E_TOOL_NUMBER));
        assert_eq!(run(&mut i, "F-1"), Err(gline::E_NEGATIVE));
        assert_eq!(run(&mut i, "G80 X1"), Err(E_AXIS_UNUSED));
        assert_eq!(run(&mut i, "G10 L2 P1"), Err(E_NO_AXIS_WORDS));
        // The failed lines changed nothing.
        assert_eq!(
            i,
            Interp {
                modal: Modal {
                    motion: MotionMode::Rapid,
                    ..Modal::default()
                },
                ..Interp::default()
            }
        );
    }

    #[test]
    fn modal_moves_units_and_offsets() {
        let mut i = Interp::default();
        run(&mut i, "G21 G90 G10 L2 P1 X10 Y20").unwrap();
        let e = run(&mut i, "G1 X1 Y2 F600").unwrap();
        assert_eq!(
            e.segments,
            vec![Segment {
                to: [11.0, 22.0, 0.0],
                a: 0.0,
                rate: Rate::Feed(600.0)
            }]
        );
        run(&mut i, "G20 G91").unwrap();
        run(&mut i, "X1").unwrap();
        assert!((i.pos[0] - 36.4).abs() < 1e-9);
        assert!((i.work_pos()[0] - 26.4).abs() < 1e-9);
        // F is modal in inches too: 600 mm/min kept until a new F.
        assert_eq!(i.feed, 600.0);
        run(&mut i, "F10").unwrap();
        assert!((i.feed - 254.0).abs() < 1e-9);
        assert!(i
            .parser_state()
            .starts_with("G1 G54 G17 G20 G91 G94 M5 M9 T0 F10"));
    }

    #[test]
    fn arcs_end_exactly_and_stay_on_the_circle() {
        let mut i = Interp::default();
        run(&mut i, "G0 X10 Y0").unwrap();
        let e = run(&mut i, "G3 X-10 Y0 I-10 J0 F300").unwrap();
        assert!(e.segments.len() > 10);
        for s in &e.segments {
            let r = s.to[0].hypot(s.to[1]);
            assert!((r - 10.0).abs() < 1e-9);
            assert!(
                s.to[1] >= -1e-9,
                "counter-clockwise from +X goes through +Y"
            );
        }
        assert_eq!(e.segments.last().unwrap().to, [-10.0, 0.0, 0.0]);
        // Same half circle by radius: the centre must be found at the origin.
        let mut j = Interp::default();
        run(&mut j, "G0 X10 Y0").unwrap();
        let e2 = run(&mut j, "G2 X-10 Y0 R10 F300").unwrap();
        assert!(e2
            .segments
            .iter()
            .all(|s| (s.to[0].hypot(s.to[1]) - 10.0).abs() < 1e-6 && s.to[1] <= 1e-9));
    }

    #[test]
    fn the_four_probe_moves_are_told_apart() {
        let mut i = Interp::default();
        for (line, away, no_error) in [
            ("G38.2 Z-5 F100", false, false),
            ("G38.3 Z-10", false, true),
            ("G38.4 Z-5", true, false),
            ("G38.5 Z0", true, true),
        ] {
            let e = run(&mut i, line).unwrap();
            assert_eq!(e.probe, Some(ProbeKind { away, no_error }), "{line}");
            assert!(i.parser_state().starts_with(&line[..5]), "{line}");
        }
        assert_eq!(run(&mut i, "G0 X1").unwrap().probe, None);
        assert_eq!(run(&mut i, "G38.6 Z1"), Err(E_UNSUPPORTED));
    }

    #[test]
    fn jog_does_not_change_modal_state() {
        let mut i = Interp::default();
        run(&mut i, "G91").unwrap();
        let e = i.jog("G90 X5 F1000").unwrap();
        assert_eq!(e.segments[0].to, [5.0, 0.0, 0.0]);
        assert!(!i.modal.absolute);
        assert_eq!(i.jog("X1"), Err(E_UNDEFINED_FEED));
        assert_eq!(i.jog("G1 X1 F100"), Err(16));
    }
}
