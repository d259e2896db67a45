//! Cutter radius compensation (G40 G41 G42 G41.1 G42.1) in the interpreter, as LinuxCNC does
//! it: the tool centre runs one radius beside the programmed path. Each offset segment is
//! held back until the next one is known, so that a concave corner can shorten it to the
//! intersection and a convex corner can get an arc about the programmed corner. A concave
//! corner whose intersection falls outside the held segment would gouge: that is an error.
//! The XY plane (G17) and the lathe's XZ plane (G18, in Z X order) are compensated. An arc may be the entry move ([`Interpreter::comp_entry_arc`]).

use super::state::Side;
use super::words::{g_group as G, slot, Decoded};
use super::{Interpreter, Sink};
use crate::diag::Diagnostic;
use oficina_canon::{Canon, CanonOp, Plane};
use std::cell::RefCell;

type P2 = [f64; 2];

/// One compensated segment waiting for its successor.
#[derive(Clone, Copy, Debug)]
enum Seg {
    /// `dir`: the programmed direction, used for corners (the entry move's emitted line
    /// is not parallel to it).
    Line {
        start: P2,
        end: [f64; 6],
        feed: bool,
        dir: P2,
    },
    Arc {
        start: P2,
        end: [f64; 6],
        center: P2,
        turns: i32,
    },
}

impl Seg {
    fn end(&self) -> [f64; 6] {
        match self {
            Seg::Line { end, .. } | Seg::Arc { end, .. } => *end,
        }
    }

    fn set_end(&mut self, p: P2, ax: Axes) {
        match self {
            Seg::Line { end, .. } | Seg::Arc { end, .. } => put2(end, ax, p),
        }
    }

    /// Unit tangent (direction of travel) at the end. A line's is its programmed direction:
    /// a concave corner may have pulled its start past its end, and the corner after it
    /// must still be judged (and found gouging) by the programmed path, as rs274 does.
    fn end_tangent(&self, ax: Axes) -> P2 {
        match self {
            Seg::Line { dir, .. } => *dir,
            Seg::Arc {
                end, center, turns, ..
            } => arc_tangent(get2(end, ax), *center, *turns > 0),
        }
    }
}

#[derive(Clone, Debug)]
pub(crate) struct CompState {
    /// The compensated position of the tool centre, XY.
    point: P2,
    /// The next move is the entry move.
    entry: bool,
    pending: Option<Seg>,
    /// What came after `pending`, in program order: moves without XY motion (they run at
    /// its final XY end) and the calls rs274 queues behind a held move (see [`queued`]).
    /// A RefCell because [`Interpreter::emit`] takes `&self`.
    tail: RefCell<Vec<Held>>,
    /// The plane's two axes (indices into positions): X Y under G17, Z X under G18.
    axes: Axes,
}

/// One entry of [`CompState::tail`].
#[derive(Clone, Debug)]
enum Held {
    Move([f64; 6], bool),
    Op(Canon),
}

/// Whether rs274 queues this call behind a move held by cutter compensation rather than
/// issuing it at once (interp_queue.cc: the `enqueue_*` functions; MESSAGE and the others
/// go out at once).
fn queued(op: &CanonOp) -> bool {
    matches!(
        op,
        CanonOp::SetFeedRate(_)
            | CanonOp::SetFeedMode(_)
            | CanonOp::Dwell(_)
            | CanonOp::MistOn
            | CanonOp::MistOff
            | CanonOp::FloodOn
            | CanonOp::FloodOff
            | CanonOp::StartSpindle(_)
            | CanonOp::StopSpindle
            | CanonOp::OrientSpindle { .. }
            | CanonOp::WaitOrientComplete(_)
            | CanonOp::SetSpindleSpeed(_)
            | CanonOp::Comment(_)
    )
}

/// Most entries held behind a segment; more are issued at once (bounded memory).
const MAX_HELD: usize = 4096;

impl CompState {
    /// Whether a segment is held (then [`CompState::hold`] may hold what follows it).
    pub(crate) fn is_holding(&self) -> bool {
        self.pending.is_some()
    }

    /// Hold `op` behind the held segment if rs274 would; gives it back otherwise.
    pub(crate) fn hold(&self, op: Canon) -> Option<Canon> {
        let mut tail = self.tail.borrow_mut();
        if self.pending.is_some() && queued(&op.op) && tail.len() < MAX_HELD {
            tail.push(Held::Op(op));
            None
        } else {
            Some(op)
        }
    }
}

impl Default for CompState {
    fn default() -> Self {
        CompState {
            point: [0.0; 2],
            entry: false,
            pending: None,
            tail: RefCell::new(Vec::new()),
            axes: (0, 1),
        }
    }
}

/// Indices of the compensated plane's first and second axis.
type Axes = (usize, usize);

/// The in-plane coordinates of a position ("XY" below means these two).
fn get2(p: &[f64; 6], ax: Axes) -> P2 {
    [p[ax.0], p[ax.1]]
}

fn put2(p: &mut [f64; 6], ax: Axes, q: P2) {
    p[ax.0] = q[0];
    p[ax.1] = q[1];
}

/// Most XY-less moves held behind a segment; more are flushed (bounded memory).
const MAX_TAIL: usize = 64;

fn sub(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
}

fn add(a: P2, b: P2) -> P2 {
    [a[0] + b[0], a[1] + b[1]]
}

fn scale(a: P2, k: f64) -> P2 {
    [a[0] * k, a[1] * k]
}

fn len(a: P2) -> f64 {
    a[0].hypot(a[1])
}

fn unit(a: P2) -> P2 {
    let l = len(a);
    if l == 0.0 {
        [0.0, 0.0]
    } else {
        scale(a, 1.0 / l)
    }
}

fn cross(a: P2, b: P2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn dot(a: P2, b: P2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Left normal of a direction.
fn left(a: P2) -> P2 {
    [-a[1], a[0]]
}

fn arc_tangent(p: P2, center: P2, ccw: bool) -> P2 {
    let r = unit(sub(p, center));
    if ccw {
        left(r)
    } else {
        [r[1], -r[0]]
    }
}

/// Corners turning less than this (radians) either way are tangent: no arc, no endpoint
/// moved (rs274's TOLERANCE_CONCAVE_CORNER, 0.05, the `small` of convert_*_comp2).
const SMALL_CORNER: f64 = 0.05;

/// Intersections of segment-carrying circles/lines near `near`: line through (p, dir) or
/// circle (center, radius).
#[derive(Clone, Copy)]
enum Curve {
    Line { p: P2, dir: P2 },
    Circle { c: P2, r: f64 },
}

fn intersections(a: Curve, b: Curve) -> Vec<P2> {
    match (a, b) {
        (Curve::Line { p: p1, dir: d1 }, Curve::Line { p: p2, dir: d2 }) => {
            let den = cross(d1, d2);
            if den.abs() < 1e-12 {
                return vec![];
            }
            let t = cross(sub(p2, p1), d2) / den;
            vec![add(p1, scale(d1, t))]
        }
        (Curve::Line { p, dir }, Curve::Circle { c, r })
        | (Curve::Circle { c, r }, Curve::Line { p, dir }) => {
            let f = sub(p, c);
            let b = dot(f, dir);
            let disc = b * b - (dot(f, f) - r * r);
            if disc < 0.0 {
                return vec![];
            }
            let s = disc.sqrt();
            vec![add(p, scale(dir, -b - s)), add(p, scale(dir, -b + s))]
        }
        (Curve::Circle { c: c1, r: r1 }, Curve::Circle { c: c2, r: r2 }) => {
            let d = len(sub(c2, c1));
            if d < 1e-12 || d > r1 + r2 || d < (r1 - r2).abs() {
                return vec![];
            }
            let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
            let h = (r1 * r1 - a * a).max(0.0).sqrt();
            let u = scale(sub(c2, c1), 1.0 / d);
            let m = add(c1, scale(u, a));
            vec![add(m, scale(left(u), h)), sub(m, scale(left(u), h))]
        }
    }
}

impl Interpreter {
    /// A compensation error at the block's motion word, with advice on what to change.
    fn comp_fail(&self, d: &Decoded, message: &str, help: impl Into<String>) -> Diagnostic {
        self.fail(d.g_span(G::MOTION), message, 0).with_help(help)
    }

    /// Where a line meets the arc after it at a concave corner, by rs274's formula
    /// (convert_arc_comp2, "line->arc"): it takes the programmed corner to lie at the arc's
    /// end radius, so the point is off the exact intersection when the start radius differs.
    /// `ends_at`: the compensated radius at the arc's end; `t1`: the line's direction.
    fn line_arc_corner(
        &self,
        d: &Decoded,
        t1: P2,
        corner: P2,
        center: P2,
        ends_at: f64,
        turns: i32,
    ) -> Result<Option<P2>, Diagnostic> {
        use std::f64::consts::{FRAC_PI_2, PI};
        let r = self.modal.comp_radius;
        let left = self.modal.comp == Some(Side::Left);
        let inside = left == (turns > 0);
        let arc_radius = if inside { ends_at + r } else { ends_at - r };
        let theta = t1[1].atan2(t1[0]);
        let delta = (center[1] - corner[1]).atan2(center[0] - corner[0]);
        let alpha = if turns > 0 {
            delta - FRAC_PI_2
        } else {
            delta + FRAC_PI_2
        };
        let mut beta = if left { theta - alpha } else { alpha - theta };
        if beta > 1.5 * PI {
            beta -= 2.0 * PI;
        } else if beta < -FRAC_PI_2 {
            beta += 2.0 * PI;
        }
        let cy = arc_radius * (beta - FRAC_PI_2).sin();
        let (dist, l) = if inside {
            (arc_radius - r, (cy + r) / (arc_radius - r))
        } else {
            (arc_radius + r, (cy - r) / (arc_radius + r))
        };
        if !(-1.0..=1.0).contains(&l) {
            return Err(self.comp_fail(
                d,
                "Arc move in concave corner cannot be reached by the tool without gouging",
                "open the corner or use a smaller tool",
            ));
        }
        let angle = match (inside, turns > 0) {
            (true, true) => theta + l.asin(),
            (true, false) => theta - l.asin(),
            (false, true) => theta + PI - l.asin(),
            (false, false) => theta + PI + l.asin(),
        };
        Ok(Some(add(center, [dist * angle.cos(), dist * angle.sin()])))
    }

    /// Whether moves are offset: compensation on with a radius above zero. rs274 runs the
    /// moves of a zero radius (`D0`, `G41.1 D0`) as programmed, without the entry-move and
    /// corner logic (convert_straight, convert_arc: `cutter_comp_radius > 0`).
    pub(crate) fn comp_offsets(&self) -> bool {
        self.modal.comp.is_some() && self.modal.comp_radius > 0.0
    }

    fn comp_side_sign(&self) -> f64 {
        match self.modal.comp {
            Some(Side::Left) => 1.0,
            _ => -1.0,
        }
    }

    /// G40 / G41 / G42 (and .1) of this block.
    pub(crate) fn set_cutter_comp(
        &mut self,
        d: &Decoded,
        t: u16,
        sink: Sink,
    ) -> Result<(), Diagnostic> {
        let span = d.g_span(G::CUTTER_COMP);
        if t == 400 {
            // The next move starts where the tool centre is; G91 words still count from
            // the programmed point (as rs274).
            self.comp_flush(sink);
            self.modal.comp = None;
            return Ok(());
        }
        if self.modal.comp.is_some() {
            return Err(self
                .fail(span, "Cannot turn cutter radius comp on when already on", 0)
                .with_help("turn it off with G40 first"));
        }
        if self.modal.plane == Plane::YZ {
            return Err(self
                .fail(
                    span,
                    "Cutter radius compensation allowed only in XY, XZ planes",
                    0,
                )
                .with_help("select G17 (mill) or G18 (lathe) before G41/G42"));
        }
        let (a0, a1, _) = self.modal.plane.axes();
        let axes = (a0, a1);
        let k = self.modal.units.mm();
        let radius = if t == 411 || t == 421 {
            let dv = d.values[slot('D')]
                .ok_or_else(|| self.fail(span, "G41.1/G42.1 needs a D word (diameter)", 0))?;
            // A negative diameter compensates on the other side (measured on rs274:
            // G41.1 D-4 cuts as G42.1 D4; corpus comp_g41_1_negative_d).
            dv.v * k / 2.0
        } else {
            let n = match d.values[slot('D')] {
                Some(dv) => {
                    if dv.v < 0.0 || dv.v.fract() != 0.0 {
                        return Err(self.fail(
                            dv.span,
                            "D word must be a tool number (a whole number ≥ 0)",
                            0,
                        ));
                    }
                    dv.v as u32
                }
                None => self.modal.tool_in_spindle,
            };
            match self.tools.get(n) {
                Some(tool) => tool.diameter / 2.0,
                None if n == 0 => 0.0,
                None => {
                    return Err(self.fail(
                        d.span_of('D'),
                        format!("Requested tool {n} not found in the tool table"),
                        0,
                    ))
                }
            }
        };
        let left = (t == 410 || t == 411) == (radius >= 0.0);
        self.modal.comp = Some(if left { Side::Left } else { Side::Right });
        self.modal.comp_radius = radius.abs();
        self.comp = CompState {
            point: get2(&self.pos, axes),
            axes,
            entry: true,
            pending: None,
            tail: RefCell::new(Vec::new()),
        };
        Ok(())
    }

    /// Emit the held segment as it is.
    pub(crate) fn comp_flush(&mut self, sink: Sink) {
        if let Some(seg) = self.comp.pending.take() {
            self.emit_seg(sink, seg);
            self.emit_tail(sink, seg.end());
        }
    }

    /// Emit the held XY-less moves at the XY of `at`; returns the last point.
    fn emit_tail(&mut self, sink: Sink, at: [f64; 6]) -> [f64; 6] {
        let mut last = at;
        for held in self.comp.tail.take() {
            match held {
                Held::Move(mut p, feed) => {
                    put2(&mut p, self.comp.axes, get2(&at, self.comp.axes));
                    self.emit_straight(sink, feed, p);
                    last = p;
                }
                Held::Op(op) => sink(op),
            }
        }
        last
    }

    fn emit_seg(&self, sink: Sink, seg: Seg) {
        match seg {
            Seg::Line { end, feed, .. } => self.emit_straight(sink, feed, end),
            Seg::Arc {
                end, center, turns, ..
            } => self.emit_arc(sink, end, center, turns),
        }
    }

    /// Hold `next` after joining it to the held segment at programmed corner `corner`.
    fn comp_push(
        &mut self,
        sink: Sink,
        d: &Decoded,
        corner: P2,
        next: Seg,
    ) -> Result<(), Diagnostic> {
        let mut next = next;
        let ax = self.comp.axes;
        if let Some(mut prev) = self.comp.pending.take() {
            let t1 = prev.end_tangent(ax);
            let t2 = match next {
                Seg::Line { dir, .. } => dir,
                Seg::Arc {
                    start,
                    center,
                    turns,
                    ..
                } => arc_tangent(start, center, turns > 0),
            };
            // The turn, positive away from the tool's side (convex). rs274 takes it in
            // (−π/2, 3π/2]: a reversal (near ±π) is convex.
            let phi = -self.comp_side_sign() * cross(t1, t2).atan2(dot(t1, t2));
            // A reversal onto or off an arc the tool runs outside of (the "h" and "m"
            // shapes of rs274's convert_*_comp2) is taken as concave: the tool stays on the
            // outside instead of looping round the corner.
            let reversal = phi.abs() > std::f64::consts::PI - SMALL_CORNER;
            let outside = |turns: i32| (self.modal.comp == Some(Side::Left)) != (turns > 0);
            let h_shape = reversal
                && match (&prev, &next) {
                    (_, Seg::Arc { turns, .. }) => outside(*turns),
                    (Seg::Arc { turns, .. }, Seg::Line { .. }) => outside(*turns),
                    _ => false,
                };
            let convex =
                !h_shape && !(-std::f64::consts::PI + SMALL_CORNER..=SMALL_CORNER).contains(&phi);
            let tangent = !convex && !h_shape && phi >= -SMALL_CORNER;
            let prev_end = prev.end();
            let next_start = match next {
                Seg::Line { start, .. } | Seg::Arc { start, .. } => start,
            };
            if tangent || len(sub(next_start, get2(&prev_end, ax))) < 1e-9 {
                self.emit_seg(sink, prev);
                self.emit_tail(sink, prev_end);
            } else if convex {
                self.emit_seg(sink, prev);
                let here = self.emit_tail(sink, prev_end);
                // Round the outside of the corner about the programmed corner point.
                let mut end = here;
                put2(&mut end, ax, next_start);
                let turns = if self.modal.comp == Some(Side::Left) {
                    -1
                } else {
                    1
                };
                self.emit_arc(sink, end, corner, turns);
            } else {
                let curve = |s: &Seg| match *s {
                    Seg::Line { start, dir, .. } => Curve::Line { p: start, dir },
                    // rs274 intersects with the radius at the arc's (compensated) end.
                    Seg::Arc { end, center, .. } => Curve::Circle {
                        c: center,
                        r: len(sub(get2(&end, ax), center)),
                    },
                };
                let cands = intersections(curve(&prev), curve(&next));
                // The intersection nearest the corner; on a reversal both are as near, and
                // rs274 takes the one ahead along the new move.
                let key = |x: &P2| {
                    if h_shape {
                        -dot(sub(*x, corner), t2)
                    } else {
                        len(sub(*x, corner))
                    }
                };
                let best = match (&prev, &next) {
                    (
                        Seg::Line { .. },
                        Seg::Arc {
                            end, center, turns, ..
                        },
                    ) => {
                        let ends_at = len(sub(get2(end, ax), *center));
                        self.line_arc_corner(d, t1, corner, *center, ends_at, *turns)?
                    }
                    _ => cands.into_iter().min_by(|a, b| {
                        key(a)
                            .partial_cmp(&key(b))
                            .unwrap_or(std::cmp::Ordering::Equal)
                    }),
                };
                // A line gouges when the corner point falls behind its start; an arc's
                // candidates all lie on the arc itself (the nearest to the corner was kept).
                let gouge = match best {
                    None => true,
                    Some(x) => match prev {
                        Seg::Line { start, dir, .. } => dot(sub(x, start), dir) < -1e-9,
                        Seg::Arc { .. } => false,
                    },
                };
                if gouge {
                    return Err(self.comp_fail(
                        d,
                        "Cutter gouging with cutter radius comp: concave corner too small for the tool",
                        format!(
                            "the inside corner leaves less room than the tool radius {:.4}; use a smaller tool or open the corner",
                            self.modal.comp_radius / self.modal.units.mm()
                        ),
                    ));
                }
                let x = best.unwrap_or(corner);
                prev.set_end(x, ax);
                self.emit_seg(sink, prev);
                self.emit_tail(sink, prev.end());
                match &mut next {
                    Seg::Line { start, .. } | Seg::Arc { start, .. } => *start = x,
                }
            }
        }
        let e = next.end();
        self.comp.point = get2(&e, self.comp.axes);
        self.comp.pending = Some(next);
        Ok(())
    }

    pub(crate) fn comp_straight(
        &mut self,
        d: &Decoded,
        sink: Sink,
        feed: bool,
        end: [f64; 6],
    ) -> Result<(), Diagnostic> {
        let r = self.modal.comp_radius;
        let ax = self.comp.axes;
        let prog = get2(&self.pos, ax);
        let target = get2(&end, ax);
        let mut out = end;
        if self.comp.entry {
            // Entry (as rs274): the held segment lies on the programmed line shifted by r,
            // and the tool reaches it from wherever it stands.
            // rs274 (`distance <= radius`) takes an entry move exactly one radius long:
            // its radius and position come out a hair apart (measured in G20 and G21, with
            // and without D); one a micron shorter is refused.
            let dist = len(sub(target, self.comp.point));
            if dist < r * (1.0 - 1e-9) {
                return Err(self.comp_fail(
                    d,
                    "Length of cutter compensation entry move is not greater than the tool radius",
                    format!(
                        "the entry move is {:.4} long; start farther from the path",
                        dist / self.modal.units.mm()
                    ),
                ));
            }
            self.comp.entry = false;
            // As rs274: the tool goes straight to the programmed end shifted by r at right
            // angles to the programmed line, and corners use that shifted line.
            let dir = unit(sub(target, prog));
            let n = scale(left(dir), r * self.comp_side_sign());
            put2(&mut out, ax, add(target, n));
            self.comp_flush(sink);
            let start = add(prog, n);
            self.comp.pending = Some(Seg::Line {
                start,
                end: out,
                feed,
                dir,
            });
            self.comp.point = get2(&out, ax);
            self.pos = end;
            return Ok(());
        }
        let dir = unit(sub(target, prog));
        if len(sub(target, prog)) < 1e-12 {
            // No XY motion: keep the tool centre where it is, move the other axes.
            put2(&mut out, ax, self.comp.point);
            let moves = self
                .comp
                .tail
                .borrow()
                .iter()
                .filter(|h| matches!(h, Held::Move(..)))
                .count();
            if self.comp.pending.is_some() && moves < MAX_TAIL {
                self.comp.tail.borrow_mut().push(Held::Move(out, feed));
            } else {
                self.comp_flush(sink);
                self.emit_straight(sink, feed, out);
            }
            self.pos = end;
            return Ok(());
        }
        let n = scale(left(dir), r * self.comp_side_sign());
        let start = add(prog, n);
        put2(&mut out, ax, add(target, n));
        self.comp_push(
            sink,
            d,
            prog,
            Seg::Line {
                start,
                end: out,
                feed,
                dir,
            },
        )?;
        self.pos = end;
        Ok(())
    }

    pub(crate) fn comp_arc(
        &mut self,
        d: &Decoded,
        sink: Sink,
        end: [f64; 6],
    ) -> Result<(), Diagnostic> {
        let r = self.modal.comp_radius;
        let ax = self.comp.axes;
        let prog = get2(&self.pos, ax);
        let target = get2(&end, ax);
        let center = self.arc_center(d, prog, target)?;
        let turns = self.arc_turns(d)?;
        let ccw = turns > 0;
        // rs274 offsets the radius at the end (arc_radius in convert_arc_comp*), which may
        // differ from the start's within the arc tolerance.
        let radius = len(sub(target, center));
        // Left of a CCW arc is towards the centre.
        let inside = (self.modal.comp == Some(Side::Left)) == ccw;
        let new_r = if inside { radius - r } else { radius + r };
        if new_r <= 0.0 || (inside && radius <= r) {
            return Err(self.comp_fail(
                d,
                "Tool radius not less than arc radius with comp",
                format!(
                    "the arc radius {:.4} is not larger than the tool radius {:.4}",
                    radius / self.modal.units.mm(),
                    r / self.modal.units.mm()
                ),
            ));
        }
        let on = |p: P2| add(center, scale(unit(sub(p, center)), new_r));
        let e = on(target);
        let mut out = end;
        put2(&mut out, ax, e);
        if self.comp.entry {
            return self.comp_entry_arc(d, sink, end, out, center, turns);
        }
        // The start stays one tool radius from the programmed start (rs274's corner arc
        // ends at `op + tool_radius·(cos δ, sin δ)`), whatever the radius at the end.
        let toward = if inside { -r } else { r };
        let start = add(prog, scale(unit(sub(prog, center)), toward));
        self.comp_push(
            sink,
            d,
            prog,
            Seg::Arc {
                start,
                end: out,
                center,
                turns,
            },
        )?;
        self.pos = end;
        Ok(())
    }

    /// An arc as the entry move (as rs274): it runs from where the tool stands to the
    /// compensated end point, about a centre on the programmed arc's radius through that end
    /// point (unit u from the programmed centre c), at the same distance from both ends.
    /// With the tool at s and the end at c + ρ·u, the centre c + t·u is equidistant when
    /// |c − s|² + 2t·u·(c − s) + t² = (ρ − t)², so t = (ρ² − |c − s|²) / (2·(u·(c − s) + ρ)).
    fn comp_entry_arc(
        &mut self,
        d: &Decoded,
        sink: Sink,
        end: [f64; 6],
        out: [f64; 6],
        center: P2,
        turns: i32,
    ) -> Result<(), Diagnostic> {
        let s = self.comp.point;
        let e = get2(&out, self.comp.axes);
        let u = unit(sub(e, center));
        let rho = len(sub(e, center));
        let cs = sub(center, s);
        let den = 2.0 * (dot(u, cs) + rho);
        let t = (rho * rho - dot(cs, cs)) / den;
        if !t.is_finite() || rho - t <= 0.0 {
            return Err(self.comp_fail(
                d,
                "Cannot make this arc the entry move of cutter compensation",
                "start the tool farther from the arc, or enter with a straight move",
            ));
        }
        self.comp.entry = false;
        self.comp_flush(sink);
        self.comp.pending = Some(Seg::Arc {
            start: s,
            end: out,
            center: add(center, scale(u, t)),
            turns,
        });
        self.comp.point = e;
        self.pos = end;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_circle_intersections() {
        let x = intersections(
            Curve::Line {
                p: [0.0, 1.0],
                dir: [1.0, 0.0],
            },
            Curve::Line {
                p: [2.0, 0.0],
                dir: [0.0, 1.0],
            },
        );
        assert_eq!(x, vec![[2.0, 1.0]]);
        let x = intersections(
            Curve::Line {
                p: [-5.0, 0.0],
                dir: [1.0, 0.0],
            },
            Curve::Circle {
                c: [0.0, 0.0],
                r: 2.0,
            },
        );
        assert!((x[0][0] + 2.0).abs() < 1e-12 && (x[1][0] - 2.0).abs() < 1e-12);
        let x = intersections(
            Curve::Circle {
                c: [0.0, 0.0],
                r: 5.0,
            },
            Curve::Circle {
                c: [8.0, 0.0],
                r: 5.0,
            },
        );
        assert_eq!(x.len(), 2);
        assert!((x[0][0] - 4.0).abs() < 1e-12 && (x[0][1].abs() - 3.0).abs() < 1e-12);
    }
}
