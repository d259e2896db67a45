//! Programs for the machines: G-code for grbl-family firmware, joint-space G-code for polar
//! and hanging plotters driven by a plain Cartesian controller, and HPGL for vintage plotters.

use oficina_geom::Point;
use oficina_motion::Profile;
use oficina_motion::{for_profile, Kinematics};
use std::fmt::Write;

use crate::machine::{arm_limited_feed, PenLift, PenMachine, PlotError};
use crate::strokes::Plot;

fn num(v: f64) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

fn pen_down(out: &mut String, m: &PenMachine) {
    match &m.lift {
        PenLift::Z { down, .. } => {
            let _ = writeln!(out, "G1 Z{} F{}", num(*down), num(m.draw_feed));
        }
        PenLift::Servo { down } => {
            let _ = writeln!(out, "M3 S{}", num(*down));
        }
        PenLift::Command { down, .. } => {
            let _ = writeln!(out, "{down}");
        }
    }
    if m.lift_dwell > 0.0 {
        let _ = writeln!(out, "G4 P{}", num(m.lift_dwell));
    }
}

fn pen_up(out: &mut String, m: &PenMachine) {
    match &m.lift {
        PenLift::Z { up, .. } => {
            let _ = writeln!(out, "G0 Z{}", num(*up));
        }
        PenLift::Servo { .. } => out.push_str("M5\n"),
        PenLift::Command { up, .. } => {
            let _ = writeln!(out, "{up}");
        }
    }
    if m.lift_dwell > 0.0 {
        let _ = writeln!(out, "G4 P{}", num(m.lift_dwell));
    }
}

/// G-code for grbl-family firmware, in work coordinates (mm, G90). On a polar profile each
/// stroke's feed is lowered so the arm stays within its rate ([`arm_limited_feed`]).
pub fn gcode(plot: &Plot, m: &PenMachine, profile: &Profile) -> String {
    let mut out = String::new();
    out.push_str("(oficina plot)\nG21 G90 G94 G17\n");
    // The first move names every axis: an interpreter knows no position before it, and on a
    // polar arm the move from an unknown place could not be checked.
    match m.lift {
        PenLift::Z { up, .. } => {
            let _ = writeln!(out, "G0 X{} Y{} Z{}", num(m.home.x), num(m.home.y), num(up));
        }
        _ => {
            pen_up(&mut out, m);
            let _ = writeln!(out, "G0 X{} Y{}", num(m.home.x), num(m.home.y));
        }
    }
    for (pi, pen) in plot.pens.iter().enumerate() {
        if pi > 0 && m.pause_between_pens {
            pen_up(&mut out, m);
            let _ = writeln!(out, "G0 X{} Y{}", num(m.home.x), num(m.home.y));
            let _ = writeln!(out, "M0 (MSG, pen {}: {})", pi + 1, pen.name);
        } else {
            let _ = writeln!(out, "(pen {}: {})", pi + 1, pen.name);
        }
        for s in &pen.strokes {
            let feed = arm_limited_feed(profile, s, m.draw_feed);
            let _ = writeln!(out, "G0 X{} Y{}", num(s[0].x), num(s[0].y));
            pen_down(&mut out, m);
            let _ = writeln!(out, "F{}", num(feed));
            for p in &s[1..] {
                let _ = writeln!(out, "G1 X{} Y{}", num(p.x), num(p.y));
            }
            pen_up(&mut out, m);
        }
    }
    let _ = writeln!(out, "G0 X{} Y{}", num(m.home.x), num(m.home.y));
    out.push_str("M2\n");
    out
}

/// Marlin 2.x G-code for a servo pen lift, as Marlin reads it: one command per line, `;`
/// comments, a feed on every move that changes it (Marlin shares one feed between G0 and
/// G1, so every travel and the first line of every stroke carry theirs), `G4 P` in
/// milliseconds, `M0 <message>` for a pen change and no program end code (Marlin has none).
/// The pen: `M280 P0 S<up>` / `S<down>` (servo 0, angles in degrees; a Z lift or command
/// lines where the machine has those), each followed by a dwell of `m.lift_dwell` (0.15 s
/// where that is 0: a hobby servo's travel). The program homes (`G28`) with the pen up and
/// ends with the motors off (`M84`).
pub fn marlin(plot: &Plot, m: &PenMachine, profile: &Profile) -> String {
    let travel_feed = profile.joints[..2]
        .iter()
        .flatten()
        .map(|j| j.max_rate * 60.0)
        .fold(f64::INFINITY, f64::min);
    let travel_feed = if travel_feed.is_finite() {
        travel_feed
    } else {
        m.draw_feed
    };
    let dwell_ms = if m.lift_dwell > 0.0 {
        m.lift_dwell * 1000.0
    } else {
        MARLIN_SERVO_MS
    };
    // The pen moves, then the dwell: a servo by M280, a Z axis by G0/G1 Z, or the lines given.
    let lift = |out: &mut String, down: bool| {
        match &m.lift {
            PenLift::Servo { down: angle } => {
                let a = if down { *angle } else { m.servo_up };
                let _ = writeln!(out, "M280 P0 S{}", num(a));
            }
            PenLift::Z { down: zd, up: zu } => {
                let (g, z) = if down { (1, zd) } else { (0, zu) };
                let _ = writeln!(out, "G{g} Z{} F{}", num(*z), num(m.draw_feed));
            }
            PenLift::Command { down: d, up: u } => {
                let _ = writeln!(out, "{}", if down { d } else { u });
            }
        }
        let _ = writeln!(out, "G4 P{}", num(dwell_ms.round()));
    };
    let travel = |out: &mut String, p: Point| {
        let _ = writeln!(out, "G0 X{} Y{} F{}", num(p.x), num(p.y), num(travel_feed));
    };
    let mut out = String::from("; oficina plot (Marlin)\nG21\nG90\n");
    lift(&mut out, false);
    out.push_str("G28\n");
    travel(&mut out, m.home);
    for (pi, pen) in plot.pens.iter().enumerate() {
        if pi > 0 && m.pause_between_pens {
            travel(&mut out, m.home);
            let _ = writeln!(out, "M0 Pen {}: {}", pi + 1, marlin_text(&pen.name));
        } else {
            let _ = writeln!(out, "; pen {}: {}", pi + 1, marlin_text(&pen.name));
        }
        for s in &pen.strokes {
            let feed = arm_limited_feed(profile, s, m.draw_feed);
            travel(&mut out, s[0]);
            lift(&mut out, true);
            for (i, p) in s[1..].iter().enumerate() {
                let _ = write!(out, "G1 X{} Y{}", num(p.x), num(p.y));
                if i == 0 {
                    let _ = write!(out, " F{}", num(feed));
                }
                out.push('\n');
            }
            lift(&mut out, false);
        }
    }
    travel(&mut out, m.home);
    out.push_str("M84\n");
    out
}

/// Servo settling time where the machine gives none, ms.
const MARLIN_SERVO_MS: f64 = 150.0;

/// A name made safe on a Marlin line: `;` would start a comment and `*` a checksum.
fn marlin_text(s: &str) -> String {
    s.replace([';', '*', '\n', '\r'], " ")
}

/// Joint-space G-code: X and Y carry the two joints (θ in degrees and R in mm for the polar
/// arm; the two cord lengths for a hanging plotter), for a controller that knows only
/// Cartesian axes. Lines are cut into pieces of at most `piece` mm (the seed's elementary
/// sub-segments) and each piece is timed in inverse-time mode (G93, F = 1/minutes) so the pen
/// keeps the Cartesian feed whatever the joints do.
pub fn joint_gcode(
    plot: &Plot,
    m: &PenMachine,
    profile: &Profile,
    piece: f64,
) -> Result<String, PlotError> {
    let k = for_profile(profile);
    let off = profile.work_offset;
    let angular0 = profile.kinematics.is_angular(0);
    let mut near = k
        .joints(profile.start)
        .map_err(|why| PlotError::OutOfReach {
            pen: String::new(),
            stroke: 0,
            x: profile.start[0],
            y: profile.start[1],
            why,
        })?;
    let mut out = String::new();
    let names = profile.kinematics.joint_names();
    let _ = writeln!(
        out,
        "(oficina plot: joint space, X = {}, Y = {})\nG21 G90 G17",
        names[0], names[1]
    );
    let joint_at = |pen: &str, stroke: usize, p: Point, near: &mut [f64; 3]| {
        let q = k
            .joints_near([p.x + off[0], p.y + off[1], 0.0], *near)
            .map_err(|why| PlotError::OutOfReach {
                pen: pen.to_string(),
                stroke,
                x: p.x,
                y: p.y,
                why,
            })?;
        *near = q;
        let j0 = if angular0 { q[0].to_degrees() } else { q[0] };
        Ok::<_, PlotError>((num(j0), num(q[1])))
    };
    pen_up(&mut out, m);
    for (pi, pen) in plot.pens.iter().enumerate() {
        if pi > 0 && m.pause_between_pens {
            let _ = writeln!(out, "M0 (MSG, pen {}: {})", pi + 1, pen.name);
        }
        for (si, s) in pen.strokes.iter().enumerate() {
            let (a, b) = joint_at(&pen.name, si + 1, s[0], &mut near)?;
            let _ = writeln!(out, "G94 G0 X{a} Y{b}");
            pen_down(&mut out, m);
            out.push_str("G93\n");
            let feed = arm_limited_feed(profile, s, m.draw_feed);
            for w in s.windows(2) {
                let len = w[0].distance(w[1]);
                let n = ((len / piece).ceil() as usize).clamp(1, 100_000);
                let minutes = len / n as f64 / feed;
                for i in 1..=n {
                    let (a, b) = joint_at(
                        &pen.name,
                        si + 1,
                        w[0].lerp(w[1], i as f64 / n as f64),
                        &mut near,
                    )?;
                    let _ = writeln!(out, "G1 X{a} Y{b} F{}", num(1.0 / minutes.max(1e-9)));
                }
            }
            out.push_str("G94\n");
            pen_up(&mut out, m);
        }
    }
    let (a, b) = joint_at("", 0, m.home, &mut near)?;
    let _ = writeln!(out, "G94 G0 X{a} Y{b}\nM2");
    Ok(out)
}

/// HPGL for vintage pen plotters: 40 plotter units per mm, one `SP` per pen (1-based).
pub fn hpgl(plot: &Plot) -> String {
    let u = |v: f64| (v * 40.0).round() as i64;
    let mut out = String::from("IN;\n");
    for (pi, pen) in plot.pens.iter().enumerate() {
        let _ = writeln!(out, "SP{};", pi + 1);
        for s in &pen.strokes {
            let _ = write!(out, "PU{},{};PD", u(s[0].x), u(s[0].y));
            for (i, p) in s[1..].iter().enumerate() {
                let sep = if i == 0 { "" } else { "," };
                let _ = write!(out, "{sep}{},{}", u(p.x), u(p.y));
            }
            out.push_str(";\n");
        }
    }
    out.push_str("PU;SP0;\n");
    out
}
