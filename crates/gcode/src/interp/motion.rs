//! Straight and arc motion: G0, G1, G2, G3 (and G53), their feed checks, and the arc centre
//! and turns from the block's words through the one arc module, `oficina_geom::arc`.

use super::arcs::{self, ArcError};
use super::state::Motion;
use super::words::{g_group as G, Decoded};
use super::{words, Interpreter, Sink, AXES};
use crate::diag::{Diagnostic, Span};
use crate::Dialect;
use oficina_canon::{CanonOp, FeedMode, Plane, Units};

impl Interpreter {
    /// The end point of the axis words (incremental or absolute), in program coordinates.
    pub(crate) fn axis_target(&self, d: &Decoded) -> [f64; 6] {
        let mut end = self.pos;
        let k = self.k();
        for (i, &l) in AXES.iter().enumerate() {
            if let Some(v) = d.get(l) {
                let v = if i < 3 { v * k } else { v };
                // G7: an X word is a diameter (incremental ones too); I and K are not.
                let v = if i == 0 && self.modal.diameter_mode {
                    v / 2.0
                } else {
                    v
                };
                end[i] = if self.modal.incremental {
                    self.pos[i] + v
                } else {
                    v
                };
            }
        }
        if d.has('@') || d.has('^') {
            [end[0], end[1]] = self.polar_target(d);
        }
        end
    }

    /// The XY end point of polar words (`@` radius, `^` angle in degrees, about the program
    /// origin): a word left out keeps the current point's radius or angle; under G91 both
    /// add to the current point's. X and Y words are refused beside them ([`check_words`]).
    ///
    /// [`check_words`]: Interpreter::check_words
    pub(super) fn polar_target(&self, d: &Decoded) -> [f64; 2] {
        let [x, y] = [self.pos[0], self.pos[1]];
        let (r0, a0) = (x.hypot(y), y.atan2(x).to_degrees());
        let r = d.get('@').map(|v| v * self.k());
        let a = d.get('^');
        let (r, a) = if self.modal.incremental {
            (r0 + r.unwrap_or(0.0), a0 + a.unwrap_or(0.0))
        } else {
            (r.unwrap_or(r0), a.unwrap_or(a0))
        };
        let (s, c) = a.to_radians().sin_cos();
        [r * c, r * s]
    }

    pub(crate) fn emit_straight(&self, sink: Sink, feed: bool, to: [f64; 6]) {
        let to = self.machine(to);
        let op = if feed {
            CanonOp::StraightFeed { to }
        } else {
            CanonOp::StraightTraverse { to }
        };
        self.emit(sink, op);
    }

    /// Feed checks common to every feed move of the block.
    pub(crate) fn check_feed(&self, d: &Decoded, what: &str, arc: bool) -> Result<(), Diagnostic> {
        match self.modal.feed_mode {
            FeedMode::InverseTime if !d.has('F') => {
                let msg = if arc {
                    "F word missing with inverse time arc move".to_string()
                } else {
                    format!("F word missing with inverse time {what} move")
                };
                return Err(self.fail(d.g_span(G::MOTION), msg, 22));
            }
            FeedMode::UnitsPerRev if self.modal.speed <= 0.0 => {
                return Err(self
                    .fail(
                        d.g_span(G::MOTION),
                        "Cannot feed with zero spindle speed in feed per rev mode",
                        0,
                    )
                    .with_help("set a spindle speed with an S word before feeding under G95"));
            }
            _ if self.modal.feed <= 0.0 => {
                let msg = if arc {
                    "Cannot make arc with zero feed rate".to_string()
                } else {
                    format!("Cannot do {what} with zero feed rate")
                };
                let help = if self.dialect == Dialect::Legacy2006 {
                    "the legacy dialect takes its feed from the machine configuration: set one"
                } else {
                    "program a feed with an F word before the first feed move"
                };
                return Err(self.fail(d.g_span(G::MOTION), msg, 22).with_help(help));
            }
            _ => {}
        }
        Ok(())
    }

    pub(super) fn motion(&mut self, d: &Decoded, sink: Sink) -> Result<(), Diagnostic> {
        let g53 = d.g_in(G::NON_MODAL) == Some(530);
        if g53 && self.modal.incremental {
            return Err(self.fail(d.g_span(G::NON_MODAL), "Cannot use g53 incremental", 0));
        }
        if g53 && self.modal.comp.is_some() {
            return Err(self.fail(
                d.g_span(G::NON_MODAL),
                "Cannot use G53 with cutter radius compensation",
                0,
            ));
        }
        let end = if g53 {
            let mut m = self.frame.to_machine(self.pos);
            for (i, &l) in AXES.iter().enumerate() {
                if let Some(v) = d.get(l) {
                    m[i] = if i < 3 { v * self.k() } else { v };
                }
            }
            self.frame.to_program(m)
        } else {
            self.axis_target(d)
        };
        if self.modal.feed_mode == FeedMode::InverseTime
            && matches!(
                self.modal.motion,
                Motion::Linear | Motion::Clockwise | Motion::CounterClockwise
            )
        {
            if let Some(f) = d.get('F') {
                self.modal.feed = f;
            }
        }
        match self.block_motion(d) {
            Motion::Rapid => self.straight(d, sink, false, end),
            Motion::Linear => {
                self.check_feed(d, "g1", false)?;
                self.inverse_time_rate(d, sink);
                self.straight(d, sink, true, end)
            }
            Motion::Clockwise | Motion::CounterClockwise => {
                self.check_feed(d, "arc", true)?;
                self.inverse_time_rate(d, sink);
                self.arc(d, sink, end)
            }
            Motion::Cycle(code) if super::lathe_cycle::is_lathe_cycle(code) => {
                if self.dialect != Dialect::LinuxCnc {
                    let span = d.g_span(G::MOTION);
                    return Err(words::unknown_g(span, f64::from(code) / 10.0));
                }
                self.start_lathe_cycle(d, code, sink)
            }
            Motion::Cycle(code) => self.canned_cycle(d, code, sink),
            Motion::SpindleSync => self.spindle_sync(d, sink, end),
            Motion::RigidTap => self.rigid_tap(d, sink, end),
            Motion::Threading => self.threading_cycle(d, sink),
            Motion::Spline(t @ (50 | 51)) => self.spline(d, t, sink, end),
            Motion::Spline(t) => self.nurbs(d, t, sink, end),
            Motion::Probe(t) => self.probe(d, t, sink, end),
            Motion::Off => Ok(()),
        }
    }

    pub(super) fn inverse_time_rate(&self, d: &Decoded, sink: Sink) {
        if self.modal.feed_mode == FeedMode::InverseTime {
            if let Some(f) = d.get('F') {
                self.emit(sink, CanonOp::SetFeedRate(f));
            }
        }
    }

    pub(super) fn straight(
        &mut self,
        d: &Decoded,
        sink: Sink,
        feed: bool,
        end: [f64; 6],
    ) -> Result<(), Diagnostic> {
        if self.comp_offsets() {
            return self.comp_straight(d, sink, feed, end);
        }
        self.emit_straight(sink, feed, end);
        self.pos = end;
        Ok(())
    }

    /// Centre of the arc to `end` (program coordinates, mm) from the block's words.
    pub(crate) fn arc_center(
        &self,
        d: &Decoded,
        start: [f64; 2],
        end: [f64; 2],
    ) -> Result<[f64; 2], Diagnostic> {
        let plane = self.modal.plane;
        let (a0, a1, _) = plane.axes();
        let (l0, l1) = (AXES[a0], AXES[a1]);
        let (o0, o1, off_axis, pname) = match plane {
            Plane::XY => ('I', 'J', 'K', "xy"),
            Plane::XZ => ('K', 'I', 'J', "xz"),
            Plane::YZ => ('J', 'K', 'I', "yz"),
        };
        let clockwise = self.modal.motion == Motion::Clockwise;
        let k = self.k();
        let tol = arcs::tolerance(self.modal.units);
        if let Some(r) = d.values[words::slot('R')] {
            if d.has(o0) || d.has(o1) {
                return Err(self.fail(r.span, "Mixed radius ijk format for arc", 0));
            }
            let polar = d.has('@') || d.has('^');
            if !d.has(l0) && !d.has(l1) && !polar {
                let (n0, n1) = (l0.to_ascii_uppercase(), l1.to_ascii_lowercase());
                let (n0, n1) = if plane == Plane::XZ {
                    ('X', 'z')
                } else {
                    (n0, n1)
                };
                return Err(self.fail(
                    d.g_span(G::MOTION),
                    format!("{n0} and {n1} words missing for arc in {pname} plane"),
                    32,
                ));
            }
            return arcs::center_from_radius(start, end, r.v * k, clockwise, &tol)
                .map_err(|e| self.arc_error(e, r.span, start, end));
        }
        if d.has(off_axis) {
            return Err(self.fail(
                d.span_of(off_axis),
                format!(
                    "{} word given for arc in {pname} plane",
                    off_axis.to_ascii_uppercase()
                ),
                0,
            ));
        }
        if !d.has(o0) && !d.has(o1) {
            return Err(self
                .fail(d.g_span(G::MOTION), "R i j k words all missing for arc", 35)
                .with_help(format!(
                    "give the centre with {o0}/{o1} or the radius with R"
                )));
        }
        let (i, j) = (d.get(o0).unwrap_or(0.0) * k, d.get(o1).unwrap_or(0.0) * k);
        let center = if self.modal.arc_incremental {
            [start[0] + i, start[1] + j]
        } else {
            [i, j]
        };
        let span = d.values[words::slot(o0)]
            .or(d.values[words::slot(o1)])
            .map(|v| v.span);
        arcs::center_from_offsets(start, end, center, &tol)
            .map_err(|e| self.arc_error(e, span.unwrap_or(Span::line(d.line)), start, end))
    }

    pub(super) fn arc_error(
        &self,
        e: ArcError,
        span: Span,
        start: [f64; 2],
        end: [f64; 2],
    ) -> Diagnostic {
        let k = self.k();
        let u = if self.modal.units == Units::Mm {
            "mm"
        } else {
            "in"
        };
        let (a0, a1, _) = self.modal.plane.axes();
        let (l0, l1) = (AXES[a0], AXES[a1]);
        let pt = |p: [f64; 2]| format!("({l0}{:.4},{l1}{:.4})", p[0] / k, p[1] / k);
        match e {
            ArcError::ZeroRadius { r1, r2, center } => self.fail(
                span,
                format!(
                    "Zero-radius arc: start={} center={} end={} r1={:.4} r2={:.4}",
                    pt(start),
                    pt(center),
                    pt(end),
                    r1 / k,
                    r2 / k
                ),
                33,
            ),
            ArcError::RadiiDiffer { r1, r2, center } => self
                .fail(
                    span,
                    format!(
                        "Radius to end of arc differs from radius to start by {:.4} {u}: start={} center={} end={} r1={:.4} r2={:.4}",
                        (r1 - r2).abs() / k,
                        pt(start),
                        pt(center),
                        pt(end),
                        r1 / k,
                        r2 / k
                    ),
                    33,
                )
                .with_help("the end point must lie on the circle through the start point about the centre"),
            ArcError::NotFinite => self.fail(span, "Arc numbers are not finite", 0),
            ArcError::SameEndPoint => {
                self.fail(span, "Current point same as end point of arc", 33)
                    .with_help("a full circle needs the centre form (I J K), not R")
            }
            ArcError::RadiusTooSmall { radius, half_chord } => self
                .fail(
                    span,
                    format!(
                        "Arc radius too small to reach end point: R{:.4} but half the chord is {:.4} {u}",
                        radius / k,
                        half_chord / k
                    ),
                    34,
                )
                .with_help("the radius must be at least half the distance from start to end"),
        }
    }

    /// Turns of an arc from the P word: ±P, sign by direction.
    pub(crate) fn arc_turns(&self, d: &Decoded) -> Result<i32, Diagnostic> {
        let p = match d.values[words::slot('P')] {
            None => 1,
            Some(p) => {
                if p.v.fract() != 0.0 {
                    return Err(self.fail(p.span, "P value not an integer with M19 G2 or G3", 23));
                }
                if p.v < 1.0 {
                    return Err(self.fail(
                        p.span,
                        "P value should be 1 or greater with G2 or G3",
                        0,
                    ));
                }
                if p.v > 10_000.0 {
                    return Err(self.fail(p.span, "P value of more than 10000 turns", 0));
                }
                p.v as i32
            }
        };
        Ok(if self.modal.motion == Motion::Clockwise {
            -p
        } else {
            p
        })
    }

    pub(super) fn arc(&mut self, d: &Decoded, sink: Sink, end: [f64; 6]) -> Result<(), Diagnostic> {
        let (a0, a1, _) = self.modal.plane.axes();
        let start2 = [self.pos[a0], self.pos[a1]];
        let end2 = [end[a0], end[a1]];
        if self.comp_offsets() {
            return self.comp_arc(d, sink, end);
        }
        let center = self.arc_center(d, start2, end2)?;
        let turns = self.arc_turns(d)?;
        self.emit_arc(sink, end, center, turns);
        self.pos = end;
        Ok(())
    }

    /// Emit an arc to `end` about `center` (program coordinates) in the current plane.
    ///
    /// The frame maps the program's circle rigidly into machine space. Under an XY rotation
    /// an XZ or YZ circle lands in a vertical plane turned about Z, so its centre is given
    /// in the arc's own frame (the machine frame turned by the same rotation), where that
    /// plane is the program's plane again.
    pub(crate) fn emit_arc(&self, sink: Sink, end: [f64; 6], center: [f64; 2], turns: i32) {
        let plane = self.modal.plane;
        let (a0, a1, _) = plane.axes();
        // The centre as a whole point (`end` off the plane), written out per plane rather
        // than patched into a copy of `end`: 8-byte patches read back as 16-byte words
        // miss store forwarding, a stall on every arc.
        let [c0, c1] = center;
        let [x, y, z, a, b, cc] = end;
        let c = match plane {
            Plane::XY => [c0, c1, z, a, b, cc],
            Plane::YZ => [x, c0, c1, a, b, cc],
            Plane::XZ => [c1, y, c0, a, b, cc],
        };
        let cm = self.frame.to_machine(c);
        let rotation = if plane == Plane::XY {
            0.0
        } else {
            self.frame.rotation
        };
        let cl = oficina_canon::to_arc_frame([cm[0], cm[1], cm[2]], rotation);
        self.emit(
            sink,
            CanonOp::ArcFeed {
                plane,
                end: self.machine(end),
                center: [cl[a0], cl[a1]],
                turns,
                rotation,
            },
        );
    }
}
