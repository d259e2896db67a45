//! gc_execute_line STEP 4: the checked block executed in grbl's order: feed, spindle speed,
//! tool, spindle, coolant, plane, units, distance mode, coordinate system, tool length offset,
//! then the non-modal actions (dwell, G10, G28/G30, G92), the motion, and program flow.
//! It runs on a copy of the state: a later error still leaves the state untouched.

use super::arc;
use super::check::Plan;
use super::parse::{Block, NonModal};
use super::*;

/// STEP 4.
pub(super) fn execute(s: &mut Interp, mut b: Block, p: Plan, jog: bool) -> Result<Effect, u8> {
    let sync = set_modes(s, &mut b, &p)?;
    let mut effect = Effect {
        segments: Vec::new(),
        dwell: 0.0,
        flow: b.stop.unwrap_or(Flow::Continue),
        sync,
        probe: None,
    };
    non_modal(s, &mut b, &p, &mut effect)?;
    if p.uses_motion && !matches!(b.non_modal, NonModal::SetCoord | NonModal::SetG92) {
        motion(s, &mut b, &p, &mut effect)?;
    }
    if jog {
        effect.flow = Flow::Continue;
    }
    if b.stop == Some(Flow::End) {
        program_end(s);
    }
    for c in ['I', 'J', 'K', 'L', 'P', 'R'] {
        if b.unused(c) {
            return Err(E_UNUSED_WORDS);
        }
    }
    Ok(effect)
}

/// The modal changes that precede motion; true when the line must wait for the planner to
/// empty (spindle, coolant, coordinate system, tool length offset).
fn set_modes(s: &mut Interp, b: &mut Block, p: &Plan) -> Result<bool, u8> {
    s.feed = p.feed;
    if let Some(v) = b.value('S') {
        s.spindle_speed = v;
    }
    if let Some(t) = b.value('T') {
        s.tool = t as u32;
    }
    let mut sync = false;
    if let Some(sp) = b.spindle {
        sync |= sp != s.modal.spindle || b.value('S').is_some();
        s.modal.spindle = sp;
    }
    sync |= b.coolant_changed;
    s.modal.mist = b.mist;
    s.modal.flood = b.flood;
    s.modal.plane = b.plane;
    s.modal.inches = b.inches;
    s.modal.absolute = b.absolute;
    s.modal.inverse_time = b.inverse_time;
    sync |= b.wcs != s.modal.wcs;
    s.modal.wcs = b.wcs;
    if let Some(m) = b.motion {
        s.modal.motion = m;
    }
    match b.tlo {
        Some(true) => {
            let z = b.take('Z').ok_or(E_VALUE_MISSING)?;
            s.tool_length = z * p.scale;
            sync = true;
        }
        Some(false) => {
            s.tool_length = 0.0;
            sync = true;
        }
        None => {}
    }
    Ok(sync)
}

/// Target in machine coordinates for the axis words given: machine coordinates (G53),
/// absolute work coordinates (G90) or increments (G91).
fn target(s: &Interp, b: &Block, p: &Plan, machine: bool) -> [f64; 3] {
    let mut t = s.pos;
    let wco = s.wco();
    for (i, a) in b.axes().into_iter().enumerate() {
        if let Some(a) = a {
            let a = a * p.scale;
            t[i] = if machine {
                a
            } else if b.absolute {
                a + wco[i]
            } else {
                s.pos[i] + a
            };
        }
    }
    t
}

/// Target of A, degrees: G53 and G90 absolute, G91 incremental (no work offset on A).
fn target_a(s: &Interp, b: &Block) -> f64 {
    match b.a() {
        Some(a) if b.absolute || b.non_modal == NonModal::AbsOverride => a,
        Some(a) => s.a + a,
        None => s.a,
    }
}

fn non_modal(s: &mut Interp, b: &mut Block, p: &Plan, effect: &mut Effect) -> Result<(), u8> {
    match b.non_modal {
        NonModal::Dwell => {
            effect.dwell = b.take('P').ok_or(E_VALUE_MISSING)?;
            effect.sync = true;
        }
        NonModal::SetCoord => {
            set_coord(s, b, p)?;
            effect.sync = true;
        }
        NonModal::SetG92 => {
            if !p.any_axis {
                return Err(E_NO_AXIS_WORDS);
            }
            let base = s.wcs_offsets[s.modal.wcs as usize];
            for (i, a) in b.axes().into_iter().enumerate() {
                if let Some(a) = a {
                    let tl = if i == 2 { s.tool_length } else { 0.0 };
                    s.g92[i] = s.pos[i] - base[i] - tl - a * p.scale;
                }
            }
            effect.sync = true;
        }
        NonModal::ResetG92 => {
            s.g92 = [0.0; 3];
            effect.sync = true;
        }
        NonModal::Set28 => s.g28 = s.pos,
        NonModal::Set30 => s.g30 = s.pos,
        NonModal::Home28 | NonModal::Home30 => {
            // Optional intermediate point, then the stored position, both at rapid rate.
            if p.any_axis {
                let mid = target(s, b, p, false);
                let a = target_a(s, b);
                effect.segments.push(Segment {
                    to: mid,
                    a,
                    rate: Rate::Rapid,
                });
                s.pos = mid;
                s.a = a;
            }
            let home = if b.non_modal == NonModal::Home28 {
                s.g28
            } else {
                s.g30
            };
            effect.segments.push(Segment {
                to: home,
                a: s.a,
                rate: Rate::Rapid,
            });
            s.pos = home;
        }
        NonModal::None | NonModal::AbsOverride => {}
    }
    Ok(())
}

/// G10 L2 / L20 P…: set a coordinate system's offset.
fn set_coord(s: &mut Interp, b: &mut Block, p: &Plan) -> Result<(), u8> {
    // grbl checks the axis words first, then L and P.
    if !p.any_axis {
        return Err(E_NO_AXIS_WORDS);
    }
    let l = b.take('L').ok_or(E_VALUE_MISSING)?;
    let n = b.take('P').ok_or(E_VALUE_MISSING)?;
    if n.fract() != 0.0 || n > 6.0 {
        return Err(E_UNSUPPORTED_WCS);
    }
    // gcode.c: "[G10 L2 R not supported]".
    if l == 2.0 && b.take('R').is_some() {
        return Err(E_UNSUPPORTED);
    }
    let index = if n == 0.0 {
        s.modal.wcs as usize
    } else {
        n as usize - 1
    };
    let mut off = s.wcs_offsets[index];
    for (i, a) in b.axes().into_iter().enumerate() {
        if let Some(a) = a {
            off[i] = if l == 20.0 {
                // L20: the current position becomes the given work coordinate.
                s.pos[i] - a * p.scale - s.g92[i] - if i == 2 { s.tool_length } else { 0.0 }
            } else if l == 2.0 {
                a * p.scale
            } else {
                return Err(E_UNSUPPORTED);
            };
        }
    }
    s.wcs_offsets[index] = off;
    Ok(())
}

/// The rate of a feed move of length `len`: F mm/min, or in inverse time 1/F minutes for the
/// whole move, i.e. len·F mm/min.
fn feed_rate(p: &Plan, inverse_time: bool, len: f64) -> Rate {
    if inverse_time {
        Rate::Feed(if p.feed > 0.0 { len * p.feed } else { 0.0 })
    } else {
        Rate::Feed(p.feed)
    }
}

fn motion(s: &mut Interp, b: &mut Block, p: &Plan, effect: &mut Effect) -> Result<(), u8> {
    let mode = p.motion_mode;
    match mode {
        MotionMode::Rapid | MotionMode::Linear | MotionMode::Probe(_) => {
            if !p.any_axis {
                return if matches!(mode, MotionMode::Probe(_)) {
                    Err(E_NO_AXIS_WORDS)
                } else {
                    Ok(())
                };
            }
            let to = target(s, b, p, b.non_modal == NonModal::AbsOverride);
            let a = target_a(s, b);
            let len = dist(&s.pos, &to);
            // A move of A alone: its feed is degrees per minute (LinuxCNC's rule; the
            // emulator times it so), and in inverse time its "length" is the turn.
            let turn = if len == 0.0 { (a - s.a).abs() } else { 0.0 };
            if matches!(mode, MotionMode::Probe(_)) && len == 0.0 {
                return Err(E_INVALID_TARGET);
            }
            let rate = if mode == MotionMode::Rapid {
                Rate::Rapid
            } else {
                feed_rate(p, b.inverse_time, len + turn)
            };
            if len > 0.0 || turn > 0.0 {
                effect.segments.push(Segment { to, a, rate });
            }
            effect.probe = match mode {
                MotionMode::Probe(kind) => Some(kind),
                _ => None,
            };
            s.pos = to;
            s.a = a;
        }
        MotionMode::ArcCw | MotionMode::ArcCcw => {
            let plane = arc::plane(b.plane);
            let (a0, a1, _) = plane.axes();
            let given = b.axes();
            if given[a0].is_none() && given[a1].is_none() {
                return Err(E_NO_AXIS_IN_PLANE);
            }
            let to = target(s, b, p, false);
            let ijk = [b.take('I'), b.take('J'), b.take('K')];
            let r = b.take('R');
            let cw = mode == MotionMode::ArcCw;
            let center = arc::center(
                s.pos,
                to,
                plane,
                cw,
                r.map(|r| r * p.scale),
                ijk.map(|o| o.map(|o| o * p.scale)),
            )?;
            let pts = arc::chords(s.pos, to, center, plane, cw, s.arc_tolerance);
            // A turns with the arc, in step with its chords.
            let (a0, a1) = (s.a, target_a(s, b));
            let n = pts.len() as f64;
            let mut at = s.pos;
            let len: f64 = pts
                .iter()
                .map(|q| {
                    let d = dist(&at, q);
                    at = *q;
                    d
                })
                .sum();
            for (k, q) in pts.into_iter().enumerate() {
                // In inverse time the whole arc takes 1/F minutes, shared by its chords.
                let rate = feed_rate(p, b.inverse_time, if b.inverse_time { len } else { 0.0 });
                let a = a0 + (a1 - a0) * (k + 1) as f64 / n;
                effect.segments.push(Segment { to: q, a, rate });
                s.pos = q;
            }
            s.pos = to;
            s.a = a1;
        }
        MotionMode::None => {}
    }
    Ok(())
}

/// M2/M30 restore grbl's program-end defaults.
fn program_end(s: &mut Interp) {
    s.modal.motion = MotionMode::Linear;
    s.modal.plane = 0;
    s.modal.absolute = true;
    s.modal.inverse_time = false;
    s.modal.wcs = 0;
    s.modal.spindle = Spindle::Off;
    s.modal.mist = false;
    s.modal.flood = false;
    s.g92 = [0.0; 3];
}
