//! G5 (cubic spline), G5.1 (quadratic B-spline), G5.2 … G5.3 (NURBS) in the XY plane, read as
//! LinuxCNC's interpreter reads them (`interp_convert.cc`, `convert_spline` and
//! `convert_nurbs`): the same checks, the same control points (the start point first, all
//! in program coordinates), one `NURBS_FEED` call per curve.
//!
//! Each curve becomes an [`oficina_canon::Nurbs`] in machine coordinates. A run that asks
//! for whole splines gets it as one [`CanonOp::Spline`] (as `rs274` prints one call); every
//! other run gets it traced ([`oficina_canon::Nurbs::trace`]): [`CanonOp::NurbsFeed`]
//! followed by straight feeds through points on the curve, no farther from it than the
//! program's G64 P tolerance (or [`DEFAULT_TOLERANCE`]), so the planner, the preview, the
//! simulator and the time estimate follow the curve, not its control polygon.

use super::state::Motion;
use super::words::{g_group as G, Decoded};
use super::{Interpreter, Sink};
use crate::diag::Diagnostic;
use oficina_canon::{CanonOp, FeedMode, Nurbs, Plane};

/// Largest distance between the emitted straight feeds and the curve when the program sets
/// no G64 P tolerance, mm.
pub(crate) const DEFAULT_TOLERANCE: f64 = 0.01;

/// What the interpreter remembers between spline blocks.
#[derive(Clone, Debug, Default)]
pub(crate) struct SplineMemory {
    /// G5.2 control points so far: X, Y (program coordinates, mm) and weight.
    nurbs: Vec<[f64; 3]>,
    /// The order of the NURBS being built (3 unless an L word over 3 says otherwise).
    order: u32,
    /// G5 without I and J starts with the reflection of the previous G5's P Q (mm).
    last_pq: [f64; 2],
    /// The motion mode is G5.2 (a NURBS is being built): LinuxCNC's
    /// `motion_mode == G_5_2`, cleared by any other motion code but G5.3.
    pub(crate) continuing: bool,
}

impl Interpreter {
    /// G5 / G5.1 (`tenths` 50 / 51) to the block's X Y.
    pub(super) fn spline(
        &mut self,
        d: &Decoded,
        tenths: u16,
        sink: Sink,
        end: [f64; 6],
    ) -> Result<(), Diagnostic> {
        let span = d.g_span(G::MOTION);
        if self.modal.comp.is_some() {
            return Err(self.fail(
                span,
                "Cannot convert spline with cutter radius compensation",
                0,
            ));
        }
        match self.modal.feed_mode {
            FeedMode::InverseTime if !d.has('F') => {
                return Err(self.fail(span, "F word missing with inverse time arc move", 0))
            }
            FeedMode::UnitsPerMinute if self.modal.feed <= 0.0 => {
                return Err(self
                    .fail(span, "Cannot make arc with zero feed rate", 0)
                    .with_help("program a feed with an F word before the first feed move"))
            }
            _ => {}
        }
        if self.modal.plane != Plane::XY {
            return Err(self
                .fail(span, "Splines must be in the XY plane", 0)
                .with_help("select the XY plane with G17 before G5 or G5.1"));
        }
        if let Some(l) = ['Z', 'A', 'B', 'C'].into_iter().find(|&l| d.has(l)) {
            return Err(self.fail(
                d.span_of(l),
                "Splines may not have motion in Z, A, B, or C",
                0,
            ));
        }
        let k = self.k();
        // Control points X, Y and weight (G5 and G5.1 weigh each 1).
        let start = [self.pos[0], self.pos[1], 1.0];
        let stop = [end[0], end[1], 1.0];
        let points = if tenths == 51 {
            let (Some(i), Some(j)) = (d.get('I'), d.get('J')) else {
                return Err(self.fail(span, "Must specify both I and J with G5.1", 0));
            };
            vec![start, [start[0] + i * k, start[1] + j * k, 1.0], stop]
        } else {
            let first = match (d.get('I'), d.get('J')) {
                (Some(i), Some(j)) => [i * k, j * k],
                (None, None) => self.spline.last_pq,
                _ => {
                    return Err(self.fail(span, "Must specify both I and J, or neither", 0));
                }
            };
            let (Some(p), Some(q)) = (d.get('P'), d.get('Q')) else {
                return Err(self.fail(span, "Must specify both P and Q with G5", 0));
            };
            let (p, q) = (p * k, q * k);
            self.spline.last_pq = [-p, -q];
            vec![
                start,
                [start[0] + first[0], start[1] + first[1], 1.0],
                [stop[0] + p, stop[1] + q, 1.0],
                stop,
            ]
        };
        self.inverse_time_rate(d, sink);
        let order = points.len() as u32;
        self.emit_nurbs(sink, points, order, d.get('F'));
        Ok(())
    }

    /// G5.2 (`tenths` 52): one more control point; G5.3 (53): the curve.
    pub(super) fn nurbs(
        &mut self,
        d: &Decoded,
        tenths: u16,
        sink: Sink,
        end: [f64; 6],
    ) -> Result<(), Diagnostic> {
        let span = d.g_span(G::MOTION);
        if tenths == 53 {
            if !self.spline.continuing {
                return Err(self.fail(span, "Cannot use G5.3 without G5.2 first", 0));
            }
            let (points, order) = (std::mem::take(&mut self.spline.nurbs), self.spline.order);
            self.spline.continuing = false;
            self.modal.motion = Motion::Off;
            if (points.len() as u32) < order {
                return Err(self.fail(
                    span,
                    format!(
                        "You must specify a number of control points at least equal to the order L = {order}"
                    ),
                    0,
                ));
            }
            self.emit_nurbs(sink, points, order, d.get('F'));
            return Ok(());
        }
        let (x, y) = (d.has('X'), d.has('Y'));
        if x != y {
            return Err(self.fail(
                d.axis_span(),
                "You must specify both X and Y coordinates for Control Points",
                0,
            ));
        }
        let p = d.get('P').unwrap_or(-1.0);
        let started = self.spline.continuing && !self.spline.nurbs.is_empty();
        if !x && p > 0.0 && started {
            return Err(self.fail(
                d.span_of('P'),
                "Can specify P without X and Y only for the first control point",
                0,
            ));
        }
        if p <= 0.0 && started {
            return Err(self
                .fail(
                    span,
                    "Must specify positive weight P for every Control Point",
                    0,
                )
                .with_help(
                    "each control point after the first needs its weight: P1 for an ordinary one",
                ));
        }
        if self.modal.feed_mode == FeedMode::UnitsPerMinute && self.modal.feed <= 0.0 {
            return Err(self.fail(span, "Cannot make a NURBS with 0 feedrate", 0));
        }
        if !self.spline.continuing {
            self.spline.nurbs.clear();
            self.spline.continuing = true;
        }
        if self.spline.nurbs.is_empty() {
            let w = if !x && p > 0.0 { p } else { 1.0 };
            self.spline.nurbs.push([self.pos[0], self.pos[1], w]);
            self.spline.order = 3;
        }
        if let Some(l) = d.get('L') {
            if l > 3.0 {
                self.spline.order = l as u32;
            }
        }
        if x {
            self.spline.nurbs.push([end[0], end[1], p]);
        }
        Ok(())
    }

    /// The curve from the current point, whole or traced (see the module); the current
    /// point becomes the last control point (X and Y only, as in LinuxCNC). Under G93 the
    /// block's F (else the last one) times the whole curve.
    /// `points` (program coordinates, weighted) become the curve's, in machine coordinates.
    fn emit_nurbs(&mut self, sink: Sink, mut points: Vec<[f64; 3]>, order: u32, f: Option<f64>) {
        let tolerance = if self.modal.blend_tolerance > 0.0 {
            self.modal.blend_tolerance
        } else {
            DEFAULT_TOLERANCE
        };
        let Some(&[last_x, last_y, _]) = points.last() else {
            return;
        };
        let at = |x: f64, y: f64| {
            let mut p = self.pos;
            [p[0], p[1]] = [x, y];
            self.machine(p)
        };
        // In place: the points' vector becomes the curve's, no copy.
        for p in &mut points {
            let m = at(p[0], p[1]);
            [p[0], p[1]] = [m.x, m.y];
        }
        let curve = Nurbs {
            points,
            order,
            tolerance,
            end: at(last_x, last_y),
            inverse_time: (self.modal.feed_mode == FeedMode::InverseTime)
                .then(|| f.unwrap_or(self.modal.feed)),
        };
        if self.whole_splines {
            self.emit(sink, CanonOp::Spline(Box::new(curve)));
        } else {
            curve.trace(|op| self.emit(sink, op));
        }
        self.pos[0] = last_x;
        self.pos[1] = last_y;
    }
}
