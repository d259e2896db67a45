//! Canned cycles G73 G81–G89, with G98/G99 and L repeats, as LinuxCNC runs them
//! (interp_cycles.cc): in the active plane, `aa`/`bb` the in-plane axes and `cc` the drilling
//! axis; R and Z are remembered while the same cycle stays active.

use super::words::{g_group as G, slot, Decoded};
use super::{Interpreter, Sink};
use crate::diag::Diagnostic;
use oficina_canon::{CanonOp, PathControlMode, SpindleDir, Units};

/// What a cycle remembers between blocks of the same cycle.
#[derive(Clone, Debug, Default)]
pub(crate) struct CycleMemory {
    /// The cycle that ran last (tenths), while cycles keep running.
    pub last: Option<u16>,
    /// The drilling-axis height when this run of cycles began ("initial level", G98).
    pub initial_level: Option<f64>,
    pub r: f64,
    pub bottom: f64,
    pub p: f64,
    pub q: f64,
    pub ijk: [f64; 3],
}

impl CycleMemory {
    pub(crate) fn reset(&mut self) {
        self.last = None;
        self.initial_level = None;
    }
}

/// LinuxCNC backs off this much above the last peck before feeding again (0.010 in).
fn peck_clearance(units: Units) -> f64 {
    match units {
        Units::Inch => 0.010 * 25.4,
        Units::Mm => 0.254,
    }
}

/// The numbers one repeat of a cycle needs (mm, program coordinates).
struct Hole {
    aa: f64,
    bb: f64,
    r: f64,
    clear: f64,
    bottom: f64,
}

impl Interpreter {
    fn cycle_point(&self, aa: f64, bb: f64, cc: f64) -> [f64; 6] {
        let (a0, a1, a2) = self.modal.plane.axes();
        let mut p = self.pos;
        p[a0] = aa;
        p[a1] = bb;
        p[a2] = cc;
        p
    }

    /// A G84/G74 feed as rs274 2.9 makes it: `convert_cycle_g74_g84` orders the plane's
    /// coordinates for G18/G19 and `cycle_feed` orders them again, so a G18 tap feeds along
    /// G19's axes and a G19 tap along G18's (away from the hole; LinuxCNC's own
    /// tests/interp/g84 expect it). Matched, deliberately: docs/linuxcnc-differences.md.
    fn tap_feed(&mut self, sink: Sink, aa: f64, bb: f64, cc: f64) {
        use oficina_canon::Plane;
        let (a0, a1, a2) = match self.modal.plane {
            Plane::XY => Plane::XY.axes(),
            Plane::XZ => Plane::YZ.axes(),
            Plane::YZ => Plane::XZ.axes(),
        };
        let mut p = self.pos;
        p[a0] = aa;
        p[a1] = bb;
        p[a2] = cc;
        self.emit_straight(sink, true, p);
        self.pos = p;
    }

    fn cycle_move(&mut self, sink: Sink, feed: bool, aa: f64, bb: f64, cc: f64) {
        let p = self.cycle_point(aa, bb, cc);
        self.emit_straight(sink, feed, p);
        self.pos = p;
    }

    pub(crate) fn canned_cycle(
        &mut self,
        d: &Decoded,
        code: u16,
        sink: Sink,
    ) -> Result<(), Diagnostic> {
        let span = d.g_span(G::MOTION);
        if self.modal.comp.is_some() {
            return Err(self.fail(
                span,
                "Cannot use canned cycle with cutter radius compensation",
                0,
            ));
        }
        for l in ['A', 'B', 'C'] {
            if d.has(l) {
                return Err(self.fail(
                    d.span_of(l),
                    format!("Cannot put an {} in canned cycle", l.to_ascii_lowercase()),
                    0,
                ));
            }
        }
        self.check_feed_cycle(d)?;
        let (a0, a1, a2) = self.modal.plane.axes();
        let axes = super::AXES;
        let same = self.cycle.last == Some(code);
        let k = self.modal.units.mm();
        let plane_name = match self.modal.plane {
            oficina_canon::Plane::XY => "xy",
            oficina_canon::Plane::XZ => "xz",
            oficina_canon::Plane::YZ => "yz",
        };
        let r_word = d.get('R').map(|v| v * k);
        let z_word = d.get(axes[a2]).map(|v| v * k);
        let r_in = match (r_word, same) {
            (Some(r), _) => r,
            (None, true) => self.cycle.r,
            (None, false) => {
                return Err(self
                    .fail(span, "R clearance plane unspecified in cycle", 0)
                    .with_help("give the retract height with an R word"))
            }
        };
        let z_in = match (z_word, same) {
            (Some(z), _) => z,
            (None, true) => self.cycle.bottom,
            (None, false) => {
                return Err(self.fail(
                    span,
                    format!(
                        "{} value unspecified in {plane_name} plane canned cycle",
                        axes[a2]
                    ),
                    0,
                ))
            }
        };
        let repeats = match d.values[slot('L')] {
            None => 1,
            Some(l) => {
                if l.v.fract() != 0.0 || l.v < 1.0 || l.v > 100_000.0 {
                    return Err(self.fail(
                        l.span,
                        format!("L must be a whole number from 1 to 100000, not {}", l.v),
                        0,
                    ));
                }
                l.v as u32
            }
        };
        let current_cc = self.pos[a2];
        let mut old_cc = *self.cycle.initial_level.get_or_insert(current_cc);
        // Hole positions from the axis words, or from polar words (an XY point, mm).
        let polar = (d.has('@') || d.has('^')).then(|| self.polar_target(d));
        // Under G91, rs274 (CYCLE_MACRO) adds @ to the radius and ^ to the angle of the
        // hole before, on every repeat: L6 ^60 goes round a circle.
        let polar_step = (polar.is_some() && self.modal.incremental).then(|| {
            (
                d.get('@').unwrap_or(0.0) * k,
                d.get('^').unwrap_or(0.0).to_radians(),
            )
        });
        let inc_word = |ax: usize| match polar {
            Some(_) if ax < 2 => 0.0,
            _ => d.get(axes[ax]).unwrap_or(0.0) * k,
        };
        let abs_word = |ax: usize| match polar {
            Some(p) if ax < 2 => p[ax],
            _ => d.get(axes[ax]).map(|v| v * k).unwrap_or(self.pos[ax]),
        };
        let (mut aa, mut bb, inc_a, inc_b, r, bottom) = if self.modal.incremental {
            let r = r_in + old_cc;
            (
                self.pos[a0],
                self.pos[a1],
                inc_word(a0),
                inc_word(a1),
                r,
                r + z_in,
            )
        } else {
            (abs_word(a0), abs_word(a1), 0.0, 0.0, r_in, z_in)
        };
        if r < bottom {
            return Err(self
                .fail(
                    d.values[slot('R')].map(|v| v.span).unwrap_or(span),
                    format!("R less than {} in cycle in {plane_name} plane", axes[a2]),
                    0,
                )
                .with_help("the retract plane R must be above the hole bottom"));
        }
        let p = self.cycle_dwell(d, code, same)?;
        let q = self.cycle_peck(d, code, same)?;
        let ijk = self.cycle_back_bore(d, code, same)?;
        if matches!(code, 740 | 840 | 860 | 870 | 880) && self.modal.spindle.is_none() {
            return Err(self.fail(span, format!("Spindle not turning in G{}", code / 10), 0));
        }
        if code == 840 && self.modal.spindle != Some(SpindleDir::Clockwise) {
            return Err(self.fail(span, "Spindle not turning clockwise in G84", 0));
        }
        if code == 740 && self.modal.spindle != Some(SpindleDir::CounterClockwise) {
            return Err(self.fail(span, "Spindle turning clockwise in G74", 0));
        }

        // The first move of a run of cycles: up to R when below it.
        let mut cc_now = current_cc;
        if old_cc < r {
            let (x, y) = (self.pos[a0], self.pos[a1]);
            self.cycle_move(sink, false, x, y, r);
            old_cc = r;
            cc_now = r;
        }
        let clear = if self.modal.retract_to_old_z {
            old_cc
        } else {
            r
        };
        let exact = self.modal.control == PathControlMode::ExactPath;
        if !exact {
            self.emit(
                sink,
                CanonOp::SetMotionControlMode {
                    mode: PathControlMode::ExactPath,
                    tolerance: 0.0,
                },
            );
        }
        for _ in 0..repeats {
            aa += inc_a;
            bb += inc_b;
            if let Some((dr, dt)) = polar_step {
                if aa == 0.0 && bb == 0.0 && (dr != 0.0 || dt != 0.0) {
                    return Err(self.fail(
                        span,
                        "Incremental motion with polar coordinates is indeterminate when at the origin",
                        0,
                    ));
                }
                let (radius, theta) = (aa.hypot(bb) + dr, bb.atan2(aa) + dt);
                (aa, bb) = (radius * theta.cos(), radius * theta.sin());
            }
            // rs274 crosses at the old Z under G98; under G99 at the current height, or at
            // R when below it.
            let cross_height = if self.modal.retract_to_old_z {
                old_cc.max(cc_now)
            } else {
                cc_now
            }
            .max(r);
            self.cycle_move(sink, false, aa, bb, cross_height);
            if cross_height != r {
                self.cycle_move(sink, false, aa, bb, r);
            }
            let hole = Hole {
                aa,
                bb,
                r,
                clear,
                bottom,
            };
            self.cycle_body(sink, code, &hole, p, q, ijk);
            cc_now = clear;
        }
        self.pos = self.cycle_point(aa, bb, clear);
        if !exact {
            // rs274 restores the mode and, whatever the mode, the naive-CAM tolerance.
            self.emit_control_mode(sink);
            if self.modal.control != PathControlMode::Continuous {
                self.emit(
                    sink,
                    CanonOp::SetNaivecamTolerance(self.modal.naive_tolerance),
                );
            }
        }
        self.cycle.last = Some(code);
        self.cycle.r = r_in;
        self.cycle.bottom = z_in;
        self.cycle.p = p;
        self.cycle.q = q;
        self.cycle.ijk = ijk;
        Ok(())
    }

    fn check_feed_cycle(&self, d: &Decoded) -> Result<(), Diagnostic> {
        if self.modal.feed <= 0.0
            && !(self.modal.feed_mode == oficina_canon::FeedMode::InverseTime && d.has('F'))
        {
            return Err(self
                .fail(d.g_span(G::MOTION), "Cannot feed with zero feed rate", 22)
                .with_help("program a feed with an F word before the cycle"));
        }
        Ok(())
    }

    fn cycle_dwell(&self, d: &Decoded, code: u16, same: bool) -> Result<f64, Diagnostic> {
        if !matches!(code, 820 | 860 | 880 | 890 | 740 | 840) {
            return Ok(0.0);
        }
        match d.values[slot('P')] {
            Some(p) if p.v < 0.0 => Err(self.fail(p.span, "Negative p word used", 0)),
            Some(p) => Ok(p.v),
            None if same || code == 840 || code == 740 => Ok(if same { self.cycle.p } else { 0.0 }),
            None => Err(self.fail(
                d.g_span(G::MOTION),
                format!("Dwell time P word missing with g{}", code / 10),
                0,
            )),
        }
    }

    fn cycle_peck(&self, d: &Decoded, code: u16, same: bool) -> Result<f64, Diagnostic> {
        if !matches!(code, 730 | 830) {
            return Ok(0.0);
        }
        let q = match d.values[slot('Q')] {
            Some(q) => q.v * self.modal.units.mm(),
            None if same => self.cycle.q,
            None => {
                return Err(self.fail(
                    d.g_span(G::MOTION),
                    format!("Q word missing with g{}", code / 10),
                    0,
                ))
            }
        };
        if q <= 0.0 {
            return Err(self
                .fail(d.span_of('Q'), "Negative or zero q value used", 0)
                .with_help("Q is the peck depth and must be positive"));
        }
        Ok(q)
    }

    fn cycle_back_bore(&self, d: &Decoded, code: u16, same: bool) -> Result<[f64; 3], Diagnostic> {
        if code != 870 {
            return Ok([0.0; 3]);
        }
        let k = self.modal.units.mm();
        let mut out = self.cycle.ijk;
        for (i, l) in ['I', 'J', 'K'].into_iter().enumerate() {
            match d.get(l) {
                Some(v) => out[i] = v * k,
                None if same => {}
                None => {
                    return Err(self.fail(
                        d.g_span(G::MOTION),
                        format!("{} word missing with g87", l.to_ascii_lowercase()),
                        0,
                    ))
                }
            }
        }
        Ok(out)
    }

    /// One hole, starting at R above (aa, bb).
    fn cycle_body(&mut self, sink: Sink, code: u16, h: &Hole, p: f64, q: f64, ijk: [f64; 3]) {
        let (aa, bb) = (h.aa, h.bb);
        let spindle = self.modal.spindle;
        match code {
            730 | 830 => {
                let back = peck_clearance(self.modal.units);
                let mut depth = h.r - q;
                while depth > h.bottom {
                    self.cycle_move(sink, true, aa, bb, depth);
                    if code == 830 {
                        self.cycle_move(sink, false, aa, bb, h.r);
                    }
                    self.cycle_move(sink, false, aa, bb, depth + back);
                    depth -= q;
                }
                self.cycle_move(sink, true, aa, bb, h.bottom);
                self.cycle_move(sink, false, aa, bb, h.clear);
            }
            810 | 820 => {
                self.cycle_move(sink, true, aa, bb, h.bottom);
                if code == 820 {
                    self.emit(sink, CanonOp::Dwell(p));
                }
                self.cycle_move(sink, false, aa, bb, h.clear);
            }
            740 | 840 => {
                // Tapping (G84 right hand, G74 left hand): overrides off, feed in, reverse,
                // dwell, feed out to the clear height, spindle forward again. In G18/G19
                // the two feeds go where rs274 2.9 sends them (see `tap_feed`).
                let (forward, reverse) = if code == 840 {
                    (SpindleDir::Clockwise, SpindleDir::CounterClockwise)
                } else {
                    (SpindleDir::CounterClockwise, SpindleDir::Clockwise)
                };
                self.emit(sink, CanonOp::EnableFeedOverride(false));
                self.emit(sink, CanonOp::EnableSpeedOverride(false));
                self.tap_feed(sink, aa, bb, h.bottom);
                self.emit(sink, CanonOp::StopSpindle);
                self.emit(sink, CanonOp::StartSpindle(reverse));
                self.emit(sink, CanonOp::Dwell(p));
                self.tap_feed(sink, aa, bb, h.clear);
                self.emit(sink, CanonOp::StopSpindle);
                self.emit(sink, CanonOp::StartSpindle(forward));
                self.emit(sink, CanonOp::EnableFeedOverride(true));
                self.emit(sink, CanonOp::EnableSpeedOverride(true));
            }
            850 => {
                self.cycle_move(sink, true, aa, bb, h.bottom);
                self.cycle_move(sink, true, aa, bb, h.r);
                self.cycle_move(sink, false, aa, bb, h.clear);
            }
            860 => {
                self.cycle_move(sink, true, aa, bb, h.bottom);
                self.emit(sink, CanonOp::Dwell(p));
                self.emit(sink, CanonOp::StopSpindle);
                self.cycle_move(sink, false, aa, bb, h.clear);
                if let Some(dir) = spindle {
                    self.emit(sink, CanonOp::StartSpindle(dir));
                }
            }
            870 => {
                // Back boring: enter off-centre with the spindle stopped, bore upwards.
                let (oa, ob) = (aa + ijk[0], bb + ijk[1]);
                let top = if self.modal.incremental {
                    h.bottom + ijk[2]
                } else {
                    ijk[2]
                };
                self.cycle_move(sink, false, oa, ob, h.r);
                self.stop_and_orient(sink);
                self.cycle_move(sink, false, oa, ob, h.bottom);
                self.cycle_move(sink, false, aa, bb, h.bottom);
                if let Some(dir) = spindle {
                    self.emit(sink, CanonOp::StartSpindle(dir));
                }
                self.cycle_move(sink, true, aa, bb, top);
                self.cycle_move(sink, true, aa, bb, h.bottom);
                self.stop_and_orient(sink);
                self.cycle_move(sink, false, oa, ob, h.bottom);
                self.cycle_move(sink, false, oa, ob, h.clear);
                self.cycle_move(sink, false, aa, bb, h.clear);
                if let Some(dir) = spindle {
                    self.emit(sink, CanonOp::StartSpindle(dir));
                }
            }
            880 => {
                // The operator retracts by hand after the program stop.
                self.cycle_move(sink, true, aa, bb, h.bottom);
                self.emit(sink, CanonOp::Dwell(p));
                self.emit(sink, CanonOp::StopSpindle);
                self.emit(sink, CanonOp::ProgramStop);
                if let Some(dir) = spindle {
                    self.emit(sink, CanonOp::StartSpindle(dir));
                }
            }
            _ => {
                // G89: bore, dwell, feed out.
                self.cycle_move(sink, true, aa, bb, h.bottom);
                self.emit(sink, CanonOp::Dwell(p));
                self.cycle_move(sink, true, aa, bb, h.clear);
            }
        }
    }
}

impl Interpreter {
    /// G87 passes the tool through the bore off-centre: rs274 stops the spindle and orients
    /// it to 0° turning counter-clockwise, so the cutter's edge faces the offset.
    fn stop_and_orient(&self, sink: Sink) {
        self.emit(sink, CanonOp::StopSpindle);
        self.emit(
            sink,
            CanonOp::OrientSpindle {
                angle: 0.0,
                dir: oficina_canon::OrientDir::CounterClockwise,
            },
        );
    }
}
