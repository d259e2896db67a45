//! G70 (finishing), G71/G71.1/G71.2 (turning) and G72/G72.1/G72.2 (facing) as LinuxCNC's
//! rs274 runs them (`interp_g7x.cc`). The cycle block rapids to its X Z; the subroutine
//! its Q names is then *read, not run*: the driver (program.rs) calls it and hands each
//! of its blocks to [`Interpreter::profile_block`], its o-word flow and assignments run
//! as usual, until it returns; [`Interpreter::finish_lathe_cycle`] then cuts.
//!
//! Coordinates of the profile are the program's units, as rs274 reads them (the block's
//! numbers, in absolute mode whatever G90/G91 says, as its `switch_settings` does).

mod path;
mod segment;

use super::state::Motion;
use super::words::{g_group as G, Decoded};
use super::{Interpreter, Sink};
use crate::block::Block;
use crate::diag::{Diagnostic, Span};
use oficina_canon::Plane;
use path::Path;
use segment::{c, Move, Segment, C, I};

/// A cycle whose profile is being read.
#[derive(Clone, Debug)]
pub(crate) struct Pending {
    /// G code in tenths: 700, 710, 711, 712, 720, 721, 722.
    code: u16,
    label: String,
    span: Span,
    /// Where the cycle cuts from (X Z of the block), program units.
    x: f64,
    z: f64,
    d: f64,
    e: f64,
    i: f64,
    p: i32,
    r: f64,
    /// The end of the profile read so far; the first piece starts at (z, x).
    at: C,
    segs: Vec<Segment>,
    /// The program's G91 / G91.1, which the profile does not follow but reads for I K.
    incremental: bool,
    arc_incremental: bool,
}

/// Whether `code` (tenths) is one of the G7x lathe cycles.
pub(crate) fn is_lathe_cycle(code: u16) -> bool {
    matches!(code, 700 | 710 | 711 | 712 | 720 | 721 | 722)
}

/// "G71.1" for 711, as rs274 names them in messages ("G71.0" for 710).
fn name(code: u16) -> String {
    format!("G{}.{}", code / 10, code % 10)
}

impl Interpreter {
    /// The cycle block: checks, the rapid to X Z, and the profile to read (the caller gets
    /// `Flow::ReadProfile`).
    pub(super) fn start_lathe_cycle(
        &mut self,
        d: &Decoded,
        code: u16,
        sink: Sink,
    ) -> Result<(), Diagnostic> {
        let span = d.g_span(G::MOTION);
        let Some(q) = d.get('Q') else {
            return Err(self.fail(span, "G7x.x  requires a Q word", 0));
        };
        if self.modal.comp.is_some() && code != 700 {
            return Err(self.fail(
                span,
                format!(
                    "{} cannot be used with cutter compensation enabled",
                    name(code)
                ),
                0,
            ));
        }
        if self.modal.plane != Plane::XZ {
            return Err(self.fail(
                span,
                format!("{} can only be used in XZ plane (G18)", name(code)),
                0,
            ));
        }
        if self.modal.comp.is_some() {
            return Err(self
                .fail(
                    span,
                    "G70 with cutter compensation is not supported by Oficina",
                    0,
                )
                .with_help("turn compensation off (G40) before G70"));
        }
        if d.has('U') || d.has('W') {
            return Err(self.fail(span, "G7x U and W allowances are not supported", 0));
        }
        let k = self.k();
        let (cx, cz) = (self.pos[0] / k, self.pos[2] / k);
        let word = |l: char, now: f64| match d.get(l) {
            Some(v) if self.modal.incremental => now + v,
            Some(v) => v,
            None => now,
        };
        let (x, z) = (word('X', cx), word('Z', cz));
        // The rapid is read in absolute mode (rs274 switches modes before it).
        let mut to = self.pos;
        if let Some(v) = d.get('X') {
            to[0] = v * k / if self.modal.diameter_mode { 2.0 } else { 1.0 };
        }
        if let Some(v) = d.get('Z') {
            to[2] = v * k;
        }
        self.emit_straight(sink, false, to);
        self.pos = to;
        self.lathe = Some(Box::new(Pending {
            code,
            label: format!("{}", q as i64),
            span,
            x,
            z,
            d: d.get('D').unwrap_or(0.0),
            e: d.get('E').unwrap_or(0.0),
            i: d.get('I').unwrap_or(1.0),
            p: d.get('P').map_or(1, |p| p as i32),
            r: d.get('R').unwrap_or(0.5),
            at: c(z, x),
            segs: Vec::new(),
            incremental: self.modal.incremental,
            arc_incremental: self.modal.arc_incremental,
        }));
        self.modal.motion = Motion::Rapid;
        Ok(())
    }

    /// The subroutine the profile is read from, and the line of the cycle block.
    pub fn lathe_profile_call(&self) -> Option<(String, u32)> {
        self.lathe.as_ref().map(|p| (p.label.clone(), p.span.line))
    }

    /// A cycle is given up (an error while reading its profile).
    pub fn abort_lathe_cycle(&mut self) {
        self.lathe = None;
    }

    /// One block of the profile subroutine: its move becomes a piece of the profile.
    pub fn profile_block(&mut self, block: &Block) -> Result<(), Diagnostic> {
        let mut d = Decoded::empty();
        d.fill(block).map_err(|e| e.diag)?;
        self.line = block.line;
        let Some(mut pc) = self.lathe.take() else {
            return Ok(());
        };
        let r = self.read_piece(&d, &mut pc);
        self.lathe = Some(pc);
        r
    }

    fn read_piece(&mut self, d: &Decoded, pc: &mut Pending) -> Result<(), Diagnostic> {
        let start = pc.at;
        let mut end = if pc.incremental { c(0.0, 0.0) } else { start };
        if let Some(x) = d.get('X') {
            end.im = x;
        }
        if let Some(z) = d.get('Z') {
            end.re = z;
        }
        let mut center = c(0.0, 0.0);
        if let Some(i) = d.get('I') {
            center.im = i;
        }
        if let Some(k) = d.get('K') {
            center.re = k;
        }
        if pc.incremental {
            end += start;
        }
        if let Some(t) = d.g_in(G::MOTION) {
            self.modal.motion = Motion::from_tenths(t);
        }
        if start == end {
            return Ok(());
        }
        let motion = self.modal.motion;
        match motion {
            Motion::Rapid | Motion::Linear => pc.segs.push(Segment::straight(start, end)),
            Motion::Clockwise | Motion::CounterClockwise => {
                let ccw = motion == Motion::CounterClockwise;
                if let Some(r) = d.get('R') {
                    if d.has('I') || d.has('K') {
                        return Err(self.fail(
                            d.span_of('R'),
                            "G7X error: both R and I or K flag used for arc",
                            0,
                        ));
                    }
                    // The centre on the chord's bisector, √(r² − (chord/2)²) from its
                    // middle, to the left of the chord for G3.
                    let chord = end - start;
                    let h = I * chord.scale(((r * r - chord.norm() / 4.0) / chord.norm()).sqrt());
                    let mid = (start + end).scale(0.5);
                    center = if ccw { mid + h } else { mid - h };
                } else {
                    if !d.has('I') && !d.has('K') {
                        return Err(self.fail(
                            d.g_span(G::MOTION),
                            "G7X error: either I or K must be present for arc",
                            0,
                        ));
                    }
                    if pc.arc_incremental {
                        center += start;
                    }
                }
                pc.segs.push(Segment::round(ccw, start, center, end));
            }
            _ => {}
        }
        if matches!(
            motion,
            Motion::Rapid | Motion::Linear | Motion::Clockwise | Motion::CounterClockwise
        ) {
            match (d.get('A'), d.get('C')) {
                (Some(_), Some(_)) => {
                    return Err(self.fail(
                        d.span_of('C'),
                        "G7X error: Both A and C parameters on a corner",
                        0,
                    ))
                }
                (Some(a), None) => pc.segs.push(Segment::fillet(a, end)),
                (None, Some(ch)) => pc.segs.push(Segment::chamfer(ch, end)),
                (None, None) => {}
            }
        }
        let k = self.k();
        self.pos[0] = end.im * k;
        self.pos[2] = end.re * k;
        pc.at = end;
        Ok(())
    }

    /// The profile is read: cut it.
    pub fn finish_lathe_cycle(&mut self, sink: Sink) -> Result<(), Diagnostic> {
        let Some(pc) = self.lathe.take() else {
            return Ok(());
        };
        let span = pc.span;
        // The first piece leads from the cycle's start point (z, x) to the profile.
        let segs = pc.segs;
        if segs.len() <= 1 {
            return Ok(());
        }
        if pc.i <= 0.0 {
            return Err(self.fail(span, "G7X error: I must be greater than zero.", 0));
        }
        let (x, z) = (pc.x, pc.z);
        let mut path = Path::new(segs);
        let (moves, result) = match pc.code {
            700 => path.finish(x, z, pc.d, pc.e, pc.p),
            code => {
                let facing = code / 10 == 72;
                path.rough(
                    facing,
                    (code % 10) as u8,
                    (x, z),
                    (0.0, 0.0),
                    pc.d,
                    pc.i,
                    pc.r,
                )
            }
        };
        self.emit_moves(&moves, sink)?;
        result.map_err(|e| self.fail(span, format!("G7X error: {e}"), 0))
    }

    /// The cycle's moves as rs274's `motion_machine` makes them: absolute X Z of the
    /// program, through the usual G0/G1/G2/G3.
    fn emit_moves(&mut self, moves: &[Move], sink: Sink) -> Result<(), Diagnostic> {
        let k = self.k();
        let dia = if self.modal.diameter_mode { 2.0 } else { 1.0 };
        let target = |me: &Interpreter, p: C| {
            let mut to = me.pos;
            to[0] = p.im * k / dia;
            to[2] = p.re * k;
            to
        };
        for m in moves {
            match *m {
                Move::Rapid(p) => {
                    let to = target(self, p);
                    self.emit_straight(sink, false, to);
                    self.pos = to;
                    self.modal.motion = Motion::Rapid;
                }
                Move::Feed(p) => {
                    self.modal.motion = Motion::Linear;
                    self.check_feed(&Decoded::empty(), "g1", false)?;
                    let to = target(self, p);
                    self.emit_straight(sink, true, to);
                    self.pos = to;
                }
                Move::Arc { ccw, center, end } => {
                    let to = target(self, end);
                    // rs274 skips an arc that ends where it starts.
                    if (to[0] - self.pos[0]).abs() < 1e-4 * k
                        && (to[2] - self.pos[2]).abs() < 1e-4 * k
                    {
                        continue;
                    }
                    self.modal.motion = if ccw {
                        Motion::CounterClockwise
                    } else {
                        Motion::Clockwise
                    };
                    self.check_feed(&Decoded::empty(), "arc", true)?;
                    let turns = if ccw { 1 } else { -1 };
                    self.emit_arc(sink, to, [center.re * k, center.im * k], turns);
                    self.pos = to;
                }
            }
        }
        Ok(())
    }
}
