//! A grbl 1.1 G-code interpreter: the modal state, the checks of gcode.c with grbl's error
//! numbers, and the moves a line produces (arcs cut into chords the way grbl's mc_arc does,
//! so the emulator fills its planner with as many blocks as the firmware would).
//!
//! It serves two masters: the emulator executes with it, and the resume logic replays a
//! program through it to know the modal state and the tool position at any line. A failing
//! line leaves the state untouched, as in grbl.

use crate::gline;

pub const E_UNSUPPORTED: u8 = 20;
pub const E_MODAL_GROUP: u8 = 21;
pub const E_UNDEFINED_FEED: u8 = 22;
pub const E_NOT_INTEGER: u8 = 23;
pub const E_TWO_AXIS_COMMANDS: u8 = 24;
pub const E_REPEATED_WORD: u8 = 25;
pub const E_NO_AXIS_WORDS: u8 = 26;
pub const E_INVALID_LINE_NUMBER: u8 = 27;
pub const E_VALUE_MISSING: u8 = 28;
pub const E_UNSUPPORTED_WCS: u8 = 29;
pub const E_G53_MODE: u8 = 30;
pub const E_AXIS_UNUSED: u8 = 31;
pub const E_NO_AXIS_IN_PLANE: u8 = 32;
pub const E_INVALID_TARGET: u8 = 33;
pub const E_ARC_RADIUS: u8 = 34;
pub const E_NO_OFFSETS_IN_PLANE: u8 = 35;
pub const E_UNUSED_WORDS: u8 = 36;
pub const E_TOOL_NUMBER: u8 = 38;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionMode {
    Rapid,
    Linear,
    ArcCw,
    ArcCcw,
    Probe,
    None,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spindle {
    Off,
    Cw,
    Ccw,
}

/// The modal groups grbl keeps (what `$G` reports).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Modal {
    pub motion: MotionMode,
    /// 0 = G17 (XY), 1 = G18 (ZX), 2 = G19 (YZ)
    pub plane: u8,
    pub inches: bool,
    pub absolute: bool,
    pub inverse_time: bool,
    /// 0 = G54 … 5 = G59
    pub wcs: u8,
    pub spindle: Spindle,
    pub mist: bool,
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
    pub to: [f64; 3],
    pub rate: Rate,
}

/// Program flow requested by the line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    Continue,
    /// M0 / M1: feed hold after the buffer drains.
    Pause,
    /// M2 / M30: end of program.
    End,
}

/// What executing one line does beyond changing the modal state.
#[derive(Clone, Debug, PartialEq)]
pub struct Effect {
    pub segments: Vec<Segment>,
    pub dwell: f64,
    pub flow: Flow,
    /// The line waits for the planner to empty before acknowledging (spindle, coolant,
    /// offsets, dwell in grbl).
    pub sync: bool,
    pub probe: bool,
}

/// Interpreter state: modal groups, feed, spindle, tool, position and offsets (machine mm).
#[derive(Clone, Debug, PartialEq)]
pub struct Interp {
    pub modal: Modal,
    /// Programmed feed, mm/min (or 1/min in inverse time).
    pub feed: f64,
    pub spindle_speed: f64,
    pub tool: u32,
    /// Machine position of the controlled point.
    pub pos: [f64; 3],
    pub wcs_offsets: [[f64; 3]; 6],
    pub g92: [f64; 3],
    pub tool_length: f64,
    pub g28: [f64; 3],
    pub g30: [f64; 3],
    /// $12 arc tolerance, mm.
    pub arc_tolerance: f64,
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
        }
    }
}

#[derive(Clone, Copy, PartialEq)]
enum NonModal {
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

    fn execute_words(&mut self, words: &[(char, f64)], jog: bool) -> Result<Effect, u8> {
        let mut groups_seen = [false; 16];
        let mut seen_letters = [false; 26];
        let mut non_modal = NonModal::None;
        let mut motion: Option<MotionMode> = None;
        let mut axis_word_command = false;
        let mut plane = self.modal.plane;
        let mut inches = self.modal.inches;
        let mut absolute = self.modal.absolute;
        let mut inverse_time = self.modal.inverse_time;
        let mut wcs = self.modal.wcs;
        let mut spindle: Option<Spindle> = None;
        let mut mist = self.modal.mist;
        let mut flood = self.modal.flood;
        let mut coolant_changed = false;
        let mut stop: Option<Flow> = None;
        let mut tlo: Option<bool> = None; // Some(true) = G43.1, Some(false) = G49
        let mut values: [Option<f64>; 26] = [None; 26];

        let group = |g: usize, seen: &mut [bool; 16]| -> Result<(), u8> {
            if seen[g] {
                return Err(E_MODAL_GROUP);
            }
            seen[g] = true;
            Ok(())
        };

        for &(letter, value) in words {
            match letter {
                'G' => {
                    let int = value.trunc();
                    let mantissa = ((value - int) * 100.0).round() as i32;
                    let code = int as i32;
                    let need_int = |m: i32| if m != 0 { Err(E_NOT_INTEGER) } else { Ok(()) };
                    match code {
                        4 | 10 | 28 | 30 | 53 | 92 => {
                            // gcode.c: a second axis command (G10 G28 G30 G92, not their .1
                            // forms) fails before the modal group is checked.
                            if matches!(code, 10 | 28 | 30 | 92) && mantissa == 0 {
                                if axis_word_command {
                                    return Err(E_TWO_AXIS_COMMANDS);
                                }
                                axis_word_command = true;
                            }
                            group(0, &mut groups_seen)?;
                            non_modal = match (code, mantissa) {
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
                            // Likewise a second motion axis command (G80 is none).
                            if code != 80 {
                                if axis_word_command {
                                    return Err(E_TWO_AXIS_COMMANDS);
                                }
                                axis_word_command = true;
                            }
                            group(1, &mut groups_seen)?;
                            motion = Some(match (code, mantissa) {
                                (0, 0) => MotionMode::Rapid,
                                (1, 0) => MotionMode::Linear,
                                (2, 0) => MotionMode::ArcCw,
                                (3, 0) => MotionMode::ArcCcw,
                                (38, 20..=50) if mantissa % 10 == 0 => MotionMode::Probe,
                                (80, 0) => MotionMode::None,
                                (38, _) => return Err(E_UNSUPPORTED),
                                _ => return Err(E_NOT_INTEGER),
                            });
                        }
                        17..=19 => {
                            group(2, &mut groups_seen)?;
                            need_int(mantissa)?;
                            plane = (code - 17) as u8;
                        }
                        90 | 91 => {
                            if mantissa == 10 {
                                // G91.1: arc IJK are incremental, grbl's only mode.
                                group(3, &mut groups_seen)?;
                                continue;
                            }
                            group(4, &mut groups_seen)?;
                            need_int(mantissa)?;
                            absolute = code == 90;
                        }
                        93 | 94 => {
                            group(5, &mut groups_seen)?;
                            need_int(mantissa)?;
                            inverse_time = code == 93;
                        }
                        20 | 21 => {
                            group(6, &mut groups_seen)?;
                            need_int(mantissa)?;
                            inches = code == 20;
                        }
                        40 => {
                            group(7, &mut groups_seen)?;
                            need_int(mantissa)?;
                        }
                        43 | 49 => {
                            group(8, &mut groups_seen)?;
                            tlo = match (code, mantissa) {
                                (43, 10) => Some(true),
                                (49, 0) => Some(false),
                                _ => return Err(E_UNSUPPORTED),
                            };
                        }
                        54..=59 => {
                            group(12, &mut groups_seen)?;
                            if mantissa != 0 {
                                return Err(E_UNSUPPORTED_WCS);
                            }
                            wcs = (code - 54) as u8;
                        }
                        61 => {
                            group(13, &mut groups_seen)?;
                            need_int(mantissa)?;
                        }
                        _ => return Err(E_UNSUPPORTED),
                    }
                }
                'M' => {
                    if value.fract() != 0.0 {
                        return Err(E_NOT_INTEGER);
                    }
                    match value as i32 {
                        0 | 1 | 2 | 30 => {
                            group(9, &mut groups_seen)?;
                            stop = Some(if value < 2.0 { Flow::Pause } else { Flow::End });
                        }
                        3..=5 => {
                            group(10, &mut groups_seen)?;
                            spindle = Some(match value as i32 {
                                3 => Spindle::Cw,
                                4 => Spindle::Ccw,
                                _ => Spindle::Off,
                            });
                        }
                        7..=9 => {
                            // grbl allows M7 and M8 together, so coolant is not a strict group.
                            coolant_changed = true;
                            match value as i32 {
                                7 => mist = true,
                                8 => flood = true,
                                _ => {
                                    mist = false;
                                    flood = false;
                                }
                            }
                        }
                        56 => {}
                        _ => return Err(E_UNSUPPORTED),
                    }
                }
                'F' | 'I' | 'J' | 'K' | 'L' | 'N' | 'P' | 'R' | 'S' | 'T' | 'X' | 'Y' | 'Z' => {
                    let idx = (letter as u8 - b'A') as usize;
                    if seen_letters[idx] {
                        return Err(E_REPEATED_WORD);
                    }
                    seen_letters[idx] = true;
                    if matches!(letter, 'F' | 'N' | 'P' | 'T' | 'S') && value < 0.0 {
                        return Err(gline::E_NEGATIVE);
                    }
                    values[idx] = Some(value);
                }
                _ => return Err(E_UNSUPPORTED),
            }
        }
        let v = |c: char| values[(c as u8 - b'A') as usize];
        let mut used = [false; 26];
        let mut take = |c: char| {
            used[(c as u8 - b'A') as usize] = true;
            v(c)
        };
        for c in ['N', 'F', 'S', 'T', 'X', 'Y', 'Z'] {
            take(c);
        }
        if let Some(n) = v('N') {
            if n > 9_999_999.0 {
                return Err(E_INVALID_LINE_NUMBER);
            }
        }
        if let Some(t) = v('T') {
            if t > 255.0 {
                return Err(E_TOOL_NUMBER);
            }
        }
        let scale = if inches { 25.4 } else { 1.0 };
        let axis_given = [v('X'), v('Y'), v('Z')];
        let any_axis = axis_given.iter().any(|a| a.is_some());

        // Axis words with no explicit command fall to the modal motion mode.
        let motion_mode = motion.unwrap_or(self.modal.motion);
        let uses_motion = motion.is_some() || (any_axis && !axis_word_command);
        let non_modal_uses_axes = matches!(
            non_modal,
            NonModal::SetCoord | NonModal::Home28 | NonModal::Home30 | NonModal::SetG92
        ) || tlo == Some(true);
        if any_axis && !non_modal_uses_axes && motion_mode == MotionMode::None {
            return Err(E_AXIS_UNUSED);
        }
        if non_modal == NonModal::AbsOverride
            && uses_motion
            && !matches!(motion_mode, MotionMode::Rapid | MotionMode::Linear)
        {
            return Err(E_G53_MODE);
        }

        // Feed: in inverse time F must be on every feed move; otherwise it is modal.
        let mut feed = self.feed;
        if let Some(f) = v('F') {
            feed = if inverse_time { f } else { f * scale };
        } else if inverse_time && !self.modal.inverse_time {
            feed = 0.0;
        }
        let feeding = uses_motion
            && matches!(
                motion_mode,
                MotionMode::Linear | MotionMode::ArcCw | MotionMode::ArcCcw | MotionMode::Probe
            );
        if feeding && (feed <= 0.0 || (inverse_time && v('F').is_none())) {
            return Err(E_UNDEFINED_FEED);
        }

        // Commit modal changes that precede motion in grbl's order of execution.
        self.feed = feed;
        if let Some(s) = v('S') {
            self.spindle_speed = s;
        }
        if let Some(t) = v('T') {
            self.tool = t as u32;
        }
        let mut sync = false;
        if let Some(s) = spindle {
            sync |= s != self.modal.spindle || v('S').is_some();
            self.modal.spindle = s;
        }
        if coolant_changed {
            sync = true;
        }
        self.modal.mist = mist;
        self.modal.flood = flood;
        self.modal.plane = plane;
        self.modal.inches = inches;
        self.modal.absolute = absolute;
        self.modal.inverse_time = inverse_time;
        if wcs != self.modal.wcs {
            sync = true;
        }
        self.modal.wcs = wcs;
        if let Some(m) = motion {
            self.modal.motion = m;
        }
        match tlo {
            Some(true) => {
                let z = take('Z').ok_or(E_VALUE_MISSING)?;
                self.tool_length = z * scale;
                sync = true;
            }
            Some(false) => {
                self.tool_length = 0.0;
                sync = true;
            }
            None => {}
        }

        let mut effect = Effect {
            segments: Vec::new(),
            dwell: 0.0,
            flow: stop.unwrap_or(Flow::Continue),
            sync,
            probe: false,
        };

        // Target in machine coordinates for the axis words given.
        let target_of = |s: &Interp, absolute_machine: bool| -> [f64; 3] {
            let mut t = s.pos;
            let wco = s.wco();
            for i in 0..3 {
                if let Some(a) = axis_given[i] {
                    let a = a * scale;
                    t[i] = if absolute_machine {
                        a
                    } else if absolute {
                        a + wco[i]
                    } else {
                        s.pos[i] + a
                    };
                }
            }
            t
        };

        match non_modal {
            NonModal::Dwell => {
                let p = take('P').ok_or(E_VALUE_MISSING)?;
                effect.dwell = p;
                effect.sync = true;
            }
            NonModal::SetCoord => {
                // grbl checks the axis words first, then L and P.
                if !any_axis {
                    return Err(E_NO_AXIS_WORDS);
                }
                let l = take('L').ok_or(E_VALUE_MISSING)?;
                let p = take('P').ok_or(E_VALUE_MISSING)?;
                if p.fract() != 0.0 || p > 6.0 {
                    return Err(E_UNSUPPORTED_WCS);
                }
                // gcode.c: "[G10 L2 R not supported]".
                if l == 2.0 && take('R').is_some() {
                    return Err(E_UNSUPPORTED);
                }
                let index = if p == 0.0 {
                    self.modal.wcs as usize
                } else {
                    p as usize - 1
                };
                let mut off = self.wcs_offsets[index];
                for i in 0..3 {
                    if let Some(a) = axis_given[i] {
                        off[i] = if l == 20.0 {
                            // L20: the current position becomes the given work coordinate.
                            self.pos[i]
                                - a * scale
                                - self.g92[i]
                                - if i == 2 { self.tool_length } else { 0.0 }
                        } else if l == 2.0 {
                            a * scale
                        } else {
                            return Err(E_UNSUPPORTED);
                        };
                    }
                }
                self.wcs_offsets[index] = off;
                effect.sync = true;
            }
            NonModal::SetG92 => {
                if !any_axis {
                    return Err(E_NO_AXIS_WORDS);
                }
                let base = self.wcs_offsets[self.modal.wcs as usize];
                for i in 0..3 {
                    if let Some(a) = axis_given[i] {
                        let tl = if i == 2 { self.tool_length } else { 0.0 };
                        self.g92[i] = self.pos[i] - base[i] - tl - a * scale;
                    }
                }
                effect.sync = true;
            }
            NonModal::ResetG92 => {
                self.g92 = [0.0; 3];
                effect.sync = true;
            }
            NonModal::Set28 => self.g28 = self.pos,
            NonModal::Set30 => self.g30 = self.pos,
            NonModal::Home28 | NonModal::Home30 => {
                // Optional intermediate point, then the stored position, both at rapid rate.
                if any_axis {
                    let mid = target_of(self, false);
                    effect.segments.push(Segment {
                        to: mid,
                        rate: Rate::Rapid,
                    });
                    self.pos = mid;
                }
                let home = if non_modal == NonModal::Home28 {
                    self.g28
                } else {
                    self.g30
                };
                effect.segments.push(Segment {
                    to: home,
                    rate: Rate::Rapid,
                });
                self.pos = home;
            }
            NonModal::None | NonModal::AbsOverride => {}
        }

        if uses_motion && non_modal != NonModal::SetCoord && non_modal != NonModal::SetG92 {
            let machine_abs = non_modal == NonModal::AbsOverride;
            let rate = |f: f64, len: f64| -> Rate {
                if inverse_time {
                    // 1/F minutes for the whole move.
                    Rate::Feed(if f > 0.0 { len * f } else { 0.0 })
                } else {
                    Rate::Feed(f)
                }
            };
            match motion_mode {
                MotionMode::Rapid | MotionMode::Linear | MotionMode::Probe => {
                    if any_axis {
                        let to = target_of(self, machine_abs);
                        let len = dist(&self.pos, &to);
                        if motion_mode == MotionMode::Probe && len == 0.0 {
                            return Err(E_INVALID_TARGET);
                        }
                        let r = if motion_mode == MotionMode::Rapid {
                            Rate::Rapid
                        } else {
                            rate(feed, len)
                        };
                        if len > 0.0 {
                            effect.segments.push(Segment { to, rate: r });
                        }
                        effect.probe = motion_mode == MotionMode::Probe;
                        self.pos = to;
                    } else if motion_mode == MotionMode::Probe {
                        return Err(E_NO_AXIS_WORDS);
                    }
                }
                MotionMode::ArcCw | MotionMode::ArcCcw => {
                    let (a0, a1, _) = plane_axes(plane);
                    if axis_given[a0].is_none() && axis_given[a1].is_none() {
                        return Err(E_NO_AXIS_IN_PLANE);
                    }
                    let to = target_of(self, false);
                    let ijk = [take('I'), take('J'), take('K')];
                    let r = take('R');
                    let center = arc_center(
                        self.pos,
                        to,
                        plane,
                        motion_mode == MotionMode::ArcCw,
                        r.map(|r| r * scale),
                        ijk.map(|o| o.map(|o| o * scale)),
                    )?;
                    let pts = arc_points(
                        self.pos,
                        to,
                        center,
                        plane,
                        motion_mode == MotionMode::ArcCw,
                        self.arc_tolerance,
                    );
                    let len: f64 = {
                        let mut p = self.pos;
                        pts.iter()
                            .map(|q| {
                                let d = dist(&p, q);
                                p = *q;
                                d
                            })
                            .sum()
                    };
                    for q in pts {
                        let seg_len = dist(&self.pos, &q);
                        let r = if inverse_time {
                            Rate::Feed(if len > 0.0 { len * feed } else { 0.0 })
                        } else {
                            rate(feed, seg_len)
                        };
                        effect.segments.push(Segment { to: q, rate: r });
                        self.pos = q;
                    }
                    self.pos = to;
                }
                MotionMode::None => {}
            }
        }
        if jog {
            effect.flow = Flow::Continue;
        }
        if stop == Some(Flow::End) {
            // M2/M30 restore grbl's program-end defaults.
            self.modal.motion = MotionMode::Linear;
            self.modal.plane = 0;
            self.modal.absolute = true;
            self.modal.inverse_time = false;
            self.modal.wcs = 0;
            self.modal.spindle = Spindle::Off;
            self.modal.mist = false;
            self.modal.flood = false;
            self.g92 = [0.0; 3];
        }
        for c in ['I', 'J', 'K', 'L', 'P', 'R'] {
            if v(c).is_some() && !used[(c as u8 - b'A') as usize] {
                return Err(E_UNUSED_WORDS);
            }
        }
        Ok(effect)
    }

    /// The `$G` report: `G0 G54 G17 G21 G90 G94 M5 M9 T0 F0 S0`.
    pub fn parser_state(&self) -> String {
        let m = &self.modal;
        let motion = match m.motion {
            MotionMode::Rapid => "G0",
            MotionMode::Linear => "G1",
            MotionMode::ArcCw => "G2",
            MotionMode::ArcCcw => "G3",
            MotionMode::Probe => "G38.2",
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

pub fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// (first in-plane axis, second in-plane axis, normal axis) for G17/G18/G19 as grbl orders them.
pub fn plane_axes(plane: u8) -> (usize, usize, usize) {
    match plane {
        1 => (2, 0, 1),
        2 => (1, 2, 0),
        _ => (0, 1, 2),
    }
}

/// Arc centre (in-plane coordinates) from R or IJK, with grbl's checks (gcode.c).
fn arc_center(
    from: [f64; 3],
    to: [f64; 3],
    plane: u8,
    cw: bool,
    r: Option<f64>,
    ijk: [Option<f64>; 3],
) -> Result<[f64; 2], u8> {
    let (a0, a1, _) = plane_axes(plane);
    let x = to[a0] - from[a0];
    let y = to[a1] - from[a1];
    if let Some(r) = r {
        if x == 0.0 && y == 0.0 {
            return Err(E_INVALID_TARGET);
        }
        let mut h_x2_div_d = 4.0 * r * r - x * x - y * y;
        if h_x2_div_d < 0.0 {
            return Err(E_ARC_RADIUS);
        }
        h_x2_div_d = -h_x2_div_d.sqrt() / x.hypot(y);
        if !cw {
            h_x2_div_d = -h_x2_div_d;
        }
        if r < 0.0 {
            h_x2_div_d = -h_x2_div_d;
        }
        let i = 0.5 * (x - y * h_x2_div_d);
        let j = 0.5 * (y + x * h_x2_div_d);
        Ok([from[a0] + i, from[a1] + j])
    } else {
        let off = [ijk[a0], ijk[a1]];
        if off[0].is_none() && off[1].is_none() {
            return Err(E_NO_OFFSETS_IN_PLANE);
        }
        let i = off[0].unwrap_or(0.0);
        let j = off[1].unwrap_or(0.0);
        let r0 = i.hypot(j);
        let r1 = (x - i).hypot(y - j);
        let delta_r = (r1 - r0).abs();
        if delta_r > 0.005 && (delta_r > 0.5 || delta_r > 0.001 * r0) {
            return Err(E_INVALID_TARGET);
        }
        Ok([from[a0] + i, from[a1] + j])
    }
}

/// Chord end points of an arc, cut as grbl's mc_arc does: chords within `tolerance`.
fn arc_points(
    from: [f64; 3],
    to: [f64; 3],
    center: [f64; 2],
    plane: u8,
    cw: bool,
    tolerance: f64,
) -> Vec<[f64; 3]> {
    let (a0, a1, n) = plane_axes(plane);
    let r0 = [from[a0] - center[0], from[a1] - center[1]];
    let r1 = [to[a0] - center[0], to[a1] - center[1]];
    let radius = r0[0].hypot(r0[1]);
    let mut angle = (r0[0] * r1[1] - r0[1] * r1[0]).atan2(r0[0] * r1[0] + r0[1] * r1[1]);
    if cw {
        if angle >= -1e-9 {
            angle -= 2.0 * std::f64::consts::PI;
        }
    } else if angle <= 1e-9 {
        angle += 2.0 * std::f64::consts::PI;
    }
    let tol = tolerance.max(1e-6);
    let chord = (tol * (2.0 * radius - tol)).max(1e-12).sqrt();
    let segments = ((0.5 * angle * radius).abs() / chord)
        .floor()
        .min(100_000.0) as usize;
    let mut pts = Vec::with_capacity(segments + 1);
    for k in 1..segments {
        let t = k as f64 / segments as f64;
        let a = angle * t;
        let (s, c) = a.sin_cos();
        let mut p = from;
        p[a0] = center[0] + r0[0] * c - r0[1] * s;
        p[a1] = center[1] + r0[0] * s + r0[1] * c;
        p[n] = from[n] + (to[n] - from[n]) * t;
        pts.push(p);
    }
    pts.push(to);
    pts
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
