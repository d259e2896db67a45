//! Canonical operations in the text of LinuxCNC's standalone interpreter (`rs274 -g`), so a
//! run can be compared line by line with the real peer: program units, program coordinates
//! (the offsets of the stream are undone), four decimals.

use crate::decimal;
use crate::interp::frame::Frame;
use oficina_canon::{
    Canon, CanonOp, FeedMode, OrientDir, PathControlMode, Plane, Pos, SpindleDir, SpindleMode,
    Units,
};
use std::io::{self, Write};

/// Follows the offset and unit records of a stream and prints every operation.
#[derive(Clone, Debug, Default)]
pub struct Rs274Printer {
    units: Units,
    frame: Frame,
    feed_mode: FeedMode,
    /// Print `rs274`'s own prefix (`   12 N..... `) before each call.
    numbered: bool,
    count: u64,
    /// Machine point of the last motion: the start of the next one.
    last: [f64; 6],
    /// An inverse-time F (1/min) not printed yet: rs274 prints the rate in units per minute
    /// that makes the next feed move take 1/F minutes, so it needs that move's length.
    inverse_f: Option<f64>,
    /// The line being built, for the calls printed without `write!` (reused).
    line: decimal::Line,
    /// Straight feeds still to come that make the last `NURBS_FEED` or `STRAIGHT_PROBE`:
    /// rs274 prints the call alone, so they are followed but not printed.
    part_feeds: u32,
}

impl Rs274Printer {
    /// A printer at the start of a program (millimetres, no offsets).
    pub fn new() -> Rs274Printer {
        Rs274Printer::default()
    }

    /// Prefix every call with a running number and `N..... ` as `rs274 -g` does.
    pub fn numbered(mut self) -> Rs274Printer {
        self.numbered = true;
        self
    }

    fn k(&self) -> f64 {
        self.units.mm()
    }

    /// Program coordinates, program units, of a machine point.
    fn program(&self, p: &Pos) -> [f64; 6] {
        let mut q = self.frame.to_program(p.to_array());
        for v in q.iter_mut().take(3) {
            *v /= self.k();
        }
        q
    }

    /// An arc's end and centre in program coordinates. In the arc's own frame the centre
    /// shares the end's off-plane coordinate; taken back to the machine frame, the printer's
    /// chain maps it like any point.
    fn arc_in_program(
        &self,
        plane: Plane,
        end: &Pos,
        center: &[f64; 2],
        rotation: f64,
    ) -> ([f64; 6], [f64; 6]) {
        let (a0, a1, _) = plane.axes();
        let e = end.to_array();
        let mut c = oficina_canon::to_arc_frame([e[0], e[1], e[2]], rotation);
        c[a0] = center[0];
        c[a1] = center[1];
        let [x, y, z] = oficina_canon::from_arc_frame(c, rotation);
        let c = Pos { x, y, z, ..*end };
        (self.program(end), self.program(&c))
    }

    fn lengths(&self, p: &Pos) -> [f64; 6] {
        let mut q = p.to_array();
        for v in q.iter_mut().take(3) {
            *v /= self.k();
        }
        q
    }

    /// Print one operation (one or more lines; none for an inverse-time feed, which is
    /// printed with the move it times).
    pub fn print(&mut self, canon: &Canon, out: &mut impl Write) -> io::Result<()> {
        // Everything up to the last feed that traces the spline is the spline's (its G93
        // rates too): rs274 prints the NURBS_FEED alone; so for a probing move.
        if self.part_feeds > 0 {
            if let CanonOp::StraightFeed { to } = &canon.op {
                self.part_feeds -= 1;
                self.last = to.to_array();
            }
            return Ok(());
        }
        if let CanonOp::SetFeedRate(f) = canon.op {
            if self.feed_mode == FeedMode::InverseTime {
                self.inverse_f = Some(f);
                return Ok(());
            }
        }
        if let Some(f) = self.inverse_f.take() {
            if let Some(len) = self.feed_length(&canon.op) {
                self.start_line(out)?;
                writeln!(out, "SET_FEED_RATE({:.4})", (len * f).max(0.1))?;
            }
        }
        if self.print_fast(&canon.op, out)? {
            return Ok(());
        }
        self.start_line(out)?;
        self.call(&canon.op, out)?;
        writeln!(out)
    }

    /// The calls of nearly every line of a program (moves and feed rates), built with
    /// hand-rolled number formatting; `false` for the others (and for numbers too large
    /// for it).
    fn print_fast(&mut self, op: &CanonOp, out: &mut impl Write) -> io::Result<bool> {
        let mut line = std::mem::take(&mut self.line);
        line.clear();
        let printed = match op {
            CanonOp::StraightTraverse { to } | CanonOp::StraightFeed { to } => {
                let p = self.program(to);
                let fits = p.iter().all(|&v| decimal::fixed4_fits(v));
                if fits {
                    self.last = to.to_array();
                    self.push_prefix(&mut line);
                    line.push_bytes(match op {
                        CanonOp::StraightTraverse { .. } => b"STRAIGHT_TRAVERSE(",
                        _ => b"STRAIGHT_FEED(",
                    });
                    push_list(&mut line, &p);
                }
                fits
            }
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                rotation,
            } => {
                let (a0, a1, a2) = plane.axes();
                let (e, c) = self.arc_in_program(*plane, end, center, *rotation);
                let first = [e[a0], e[a1], c[a0], c[a1]];
                let second = [e[a2], e[3], e[4], e[5]];
                let fits = first
                    .iter()
                    .chain(&second)
                    .all(|&v| decimal::fixed4_fits(v));
                if fits {
                    self.last = end.to_array();
                    self.push_prefix(&mut line);
                    line.push_bytes(b"ARC_FEED(");
                    push_list(&mut line, &first);
                    line.push_bytes(if *turns < 0 { b", -" } else { b", " });
                    line.push_u64(u64::from(turns.unsigned_abs()));
                    line.push_bytes(b", ");
                    push_list(&mut line, &second);
                }
                fits
            }
            CanonOp::SetFeedRate(f) if self.feed_mode != FeedMode::InverseTime => {
                let f = f / self.k();
                let fits = decimal::fixed4_fits(f);
                if fits {
                    self.push_prefix(&mut line);
                    line.push_bytes(b"SET_FEED_RATE(");
                    push_list(&mut line, &[f]);
                }
                fits
            }
            _ => false,
        };
        if printed {
            line.push_bytes(b")\n");
            out.write_all(line.as_bytes())?;
        }
        self.line = line;
        Ok(printed)
    }

    /// What [`Rs274Printer::start_line`] writes, into `line`.
    fn push_prefix(&mut self, line: &mut decimal::Line) {
        self.count += 1;
        if self.numbered {
            line.push_u64_padded(self.count, 5);
            line.push_bytes(b" N..... ");
        }
    }

    fn start_line(&mut self, out: &mut impl Write) -> io::Result<()> {
        self.count += 1;
        if self.numbered {
            write!(out, "{:5} N..... ", self.count)?;
        }
        Ok(())
    }

    /// Length in program units of a feed move from the last point, as rs274 measures it
    /// for inverse time: the XYZ path, or the rotary one when only A B C move.
    fn feed_length(&self, op: &CanonOp) -> Option<f64> {
        let k = self.k();
        match op {
            CanonOp::StraightFeed { to } => {
                let to = to.to_array();
                let norm = |axes: std::ops::Range<usize>| {
                    axes.map(|i| (to[i] - self.last[i]).powi(2))
                        .sum::<f64>()
                        .sqrt()
                };
                let (linear, rotary) = (norm(0..3), norm(3..6));
                Some(if linear > 0.0 || rotary == 0.0 {
                    linear / k
                } else {
                    rotary
                })
            }
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                rotation,
            } => {
                let (a0, a1, a2) = plane.axes();
                let e = end.to_array();
                let e = oficina_canon::to_arc_frame([e[0], e[1], e[2]], *rotation);
                let s = self.last;
                let s = oficina_canon::to_arc_frame([s[0], s[1], s[2]], *rotation);
                let radius = (s[a0] - center[0]).hypot(s[a1] - center[1]);
                let theta = turn_angle(
                    [s[a0] - center[0], s[a1] - center[1]],
                    [e[a0] - center[0], e[a1] - center[1]],
                    *turns,
                );
                let dz = e[a2] - s[a2];
                Some((radius * theta).hypot(dz) / k)
            }
            _ => None,
        }
    }

    fn call(&mut self, op: &CanonOp, out: &mut impl Write) -> io::Result<()> {
        match op {
            CanonOp::StraightTraverse { to } | CanonOp::StraightFeed { to } => {
                self.last = to.to_array()
            }
            CanonOp::ArcFeed { end, .. } => self.last = end.to_array(),
            // A rigid tap comes back to where it started: `last` stays.
            _ => {}
        }
        match op {
            CanonOp::UseLengthUnits(u) => {
                self.units = *u;
                let name = if *u == Units::Mm {
                    "CANON_UNITS_MM"
                } else {
                    "CANON_UNITS_INCHES"
                };
                write!(out, "USE_LENGTH_UNITS({name})")
            }
            CanonOp::SetG5xOffset { index, offset } => {
                self.frame.g5x = offset.to_array();
                let v = self.lengths(offset);
                write_call(out, &format!("SET_G5X_OFFSET({index}, "), &v)
            }
            CanonOp::SetG92Offset(offset) => {
                self.frame.g92 = offset.to_array();
                let v = self.lengths(offset);
                write_call(out, "SET_G92_OFFSET(", &v)
            }
            CanonOp::SetXyRotation(r) => {
                self.frame.rotation = *r;
                write!(out, "SET_XY_ROTATION({r:.4})")
            }
            CanonOp::SelectPlane(p) => {
                let name = match p {
                    Plane::XY => "CANON_PLANE_XY",
                    Plane::YZ => "CANON_PLANE_YZ",
                    Plane::XZ => "CANON_PLANE_XZ",
                };
                write!(out, "SELECT_PLANE({name})")
            }
            CanonOp::SetFeedRate(f) => {
                let f = if self.feed_mode == FeedMode::InverseTime {
                    *f
                } else {
                    f / self.k()
                };
                write!(out, "SET_FEED_RATE({f:.4})")
            }
            CanonOp::SetFeedMode(m) => {
                self.feed_mode = *m;
                // rs274's canon knows per minute (0) and per revolution (1); inverse time
                // is per minute with a rate worked out for each move.
                let n = match m {
                    FeedMode::UnitsPerMinute | FeedMode::InverseTime => 0,
                    FeedMode::UnitsPerRev => 1,
                };
                write!(out, "SET_FEED_MODE(0, {n})")
            }
            CanonOp::SetMotionControlMode { mode, tolerance } => match mode {
                PathControlMode::Continuous => write!(
                    out,
                    "SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, {:.6})",
                    tolerance / self.k()
                ),
                PathControlMode::ExactPath => {
                    write!(out, "SET_MOTION_CONTROL_MODE(CANON_EXACT_PATH)")
                }
                PathControlMode::ExactStop => {
                    write!(out, "SET_MOTION_CONTROL_MODE(CANON_EXACT_STOP)")
                }
            },
            CanonOp::SetNaivecamTolerance(t) => {
                write!(out, "SET_NAIVECAM_TOLERANCE({:.4})", t / self.k())
            }
            CanonOp::StraightTraverse { to } => {
                let p = self.program(to);
                write_call(out, "STRAIGHT_TRAVERSE(", &p)
            }
            CanonOp::StraightFeed { to } => {
                let p = self.program(to);
                write_call(out, "STRAIGHT_FEED(", &p)
            }
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                rotation,
            } => {
                let (a0, a1, a2) = plane.axes();
                let (e, c) = self.arc_in_program(*plane, end, center, *rotation);
                write!(
                    out,
                    "ARC_FEED({:.4}, {:.4}, {:.4}, {:.4}, {turns}, {:.4}, {:.4}, {:.4}, {:.4})",
                    e[a0], e[a1], c[a0], c[a1], e[a2], e[3], e[4], e[5]
                )
            }
            CanonOp::Dwell(s) => write!(out, "DWELL({s:.4})"),
            CanonOp::SetSpindleSpeed(s) => write!(out, "SET_SPINDLE_SPEED(0, {s:.4})"),
            // rs274's argument: 0 for G97, the D limit (1e30 without one) for G96.
            CanonOp::SetSpindleMode(mode) => {
                let arg = match mode {
                    SpindleMode::Rpm => 0.0,
                    SpindleMode::SurfaceSpeed { max_rpm } => max_rpm.unwrap_or(1e30),
                };
                write!(out, "SET_SPINDLE_MODE(0 {arg:.4})")
            }
            CanonOp::StartSpindle(SpindleDir::Clockwise) => {
                write!(out, "START_SPINDLE_CLOCKWISE(0)")
            }
            CanonOp::StartSpindle(SpindleDir::CounterClockwise) => {
                write!(out, "START_SPINDLE_COUNTERCLOCKWISE(0)")
            }
            CanonOp::StopSpindle => write!(out, "STOP_SPINDLE_TURNING(0)"),
            CanonOp::OrientSpindle { angle, dir } => {
                let p = match dir {
                    OrientDir::Shortest => 0,
                    OrientDir::Clockwise => 1,
                    OrientDir::CounterClockwise => 2,
                };
                write!(out, "ORIENT_SPINDLE(0, {angle:.4}, {p})")
            }
            CanonOp::WaitOrientComplete(s) => write!(out, "SPINDLE.0.WAIT_ORIENT_COMPLETE({s:.4})"),
            // rs274 prints the pitch in program units with six decimals and no space.
            CanonOp::StartSpeedFeedSync { pitch } => {
                write!(out, "START_SPEED_FEED_SYNC({:.6},0)", pitch / self.k())
            }
            CanonOp::StopSpeedFeedSync => write!(out, "STOP_SPEED_FEED_SYNCH()"),
            CanonOp::RigidTap { to } => {
                let p = self.program(to);
                write!(out, "RIGID_TAP({:.4}, {:.4}, {:.4})", p[0], p[1], p[2])
            }
            CanonOp::MistOn => write!(out, "MIST_ON()"),
            CanonOp::MistOff => write!(out, "MIST_OFF()"),
            CanonOp::FloodOn => write!(out, "FLOOD_ON()"),
            CanonOp::FloodOff => write!(out, "FLOOD_OFF()"),
            CanonOp::SelectTool(n) => write!(out, "SELECT_TOOL({n})"),
            CanonOp::ChangeTool(n) => write!(out, "CHANGE_TOOL({n})"),
            CanonOp::UseToolLengthOffset(p) => {
                self.frame.tool = p.to_array();
                let v = self.lengths(p);
                write!(
                    out,
                    "USE_TOOL_LENGTH_OFFSET({:.4} {:.4} {:.4}, {:.4} {:.4} {:.4}, 0.0000 0.0000 0.0000)",
                    v[0], v[1], v[2], v[3], v[4], v[5]
                )
            }
            CanonOp::EnableFeedOverride(on) => switch_call(out, *on, "FEED_OVERRIDE()"),
            CanonOp::EnableSpeedOverride(on) => switch_call(out, *on, "SPEED_OVERRIDE(0)"),
            CanonOp::EnableAdaptiveFeed(on) => switch_call(out, *on, "ADAPTIVE_FEED()"),
            CanonOp::EnableFeedHold(on) => switch_call(out, *on, "FEED_HOLD()"),
            CanonOp::ProgramStop => write!(out, "PROGRAM_STOP()"),
            CanonOp::OptionalProgramStop => write!(out, "OPTIONAL_PROGRAM_STOP()"),
            CanonOp::ProgramEnd => write!(out, "PROGRAM_END()"),
            CanonOp::NurbsFeed {
                control_points,
                segments,
            } => {
                self.part_feeds = *segments;
                write!(out, "NURBS_FEED({control_points}, ...)")
            }
            CanonOp::Spline(curve) => {
                self.last = curve.end.to_array();
                write!(out, "NURBS_FEED({}, ...)", curve.points.len())
            }
            CanonOp::StraightProbe { to, feeds } => {
                self.part_feeds = *feeds;
                let p = self.program(to);
                writeln!(out, "TURN_PROBE_ON()")?;
                self.start_line(out)?;
                write_call(out, "STRAIGHT_PROBE(", &p)?;
                writeln!(out)?;
                self.start_line(out)?;
                write!(out, "TURN_PROBE_OFF()")
            }
            CanonOp::Message(m) => write!(out, "MESSAGE(\"{m}\")"),
            CanonOp::Comment(c) => write!(out, "COMMENT(\"{c}\")"),
        }
    }
}

/// `head` then the six axis values with four decimals and `)`: the calls that carry a
/// whole position or offset (the general path; [`push_list`] is the fast one).
fn write_call(out: &mut impl Write, head: &str, v: &[f64; 6]) -> io::Result<()> {
    write!(
        out,
        "{head}{:.4}, {:.4}, {:.4}, {:.4}, {:.4}, {:.4})",
        v[0], v[1], v[2], v[3], v[4], v[5]
    )
}

/// `v0, v1, …` with four decimals each (each passing [`decimal::fixed4_fits`]).
fn push_list(line: &mut decimal::Line, values: &[f64]) {
    for (i, &v) in values.iter().enumerate() {
        if i > 0 {
            line.push_bytes(b", ");
        }
        line.push_fixed4(v);
    }
}

/// Angle swept (radians, ≥ 0) from `start` to `end` (both relative to the centre) over
/// `turns` (> 0 counter-clockwise), as LinuxCNC's `find_turn` counts it: an end on the
/// start is a whole turn.
fn turn_angle(start: [f64; 2], end: [f64; 2], turns: i32) -> f64 {
    use std::f64::consts::TAU;
    let mut alpha = start[1].atan2(start[0]);
    let mut beta = end[1].atan2(end[0]);
    let extra = (turns.unsigned_abs().max(1) - 1) as f64 * TAU;
    if turns > 0 {
        if beta <= alpha {
            beta += TAU;
        }
        beta - alpha + extra
    } else {
        if alpha <= beta {
            alpha += TAU;
        }
        alpha - beta + extra
    }
}

/// Print a whole stream into a string (tests and small programs).
pub fn to_rs274_text<'a>(ops: impl IntoIterator<Item = &'a Canon>) -> String {
    let mut p = Rs274Printer::new();
    let mut out = Vec::new();
    for c in ops {
        // Writing to a Vec cannot fail.
        let _ = p.print(c, &mut out);
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// `ENABLE_…` or `DISABLE_…`: rs274's pair of calls for each override switch.
fn switch_call(out: &mut impl Write, on: bool, call: &str) -> io::Result<()> {
    write!(out, "{}_{call}", if on { "ENABLE" } else { "DISABLE" })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn undoes_offsets_and_units() {
        let ops = [
            CanonOp::UseLengthUnits(Units::Inch),
            CanonOp::SetG5xOffset {
                index: 1,
                offset: Pos::xyz(25.4, 0.0, 0.0),
            },
            CanonOp::StraightFeed {
                to: Pos::xyz(50.8, 25.4, 0.0),
            },
        ];
        let canon: Vec<Canon> = ops.into_iter().map(|op| Canon { line: 1, op }).collect();
        let text = to_rs274_text(&canon);
        assert_eq!(
            text.lines().last().unwrap(),
            "STRAIGHT_FEED(1.0000, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000)"
        );
        assert_eq!(
            text.lines().nth(1).unwrap(),
            "SET_G5X_OFFSET(1, 1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)"
        );
    }
}
