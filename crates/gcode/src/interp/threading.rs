//! Spindle-synchronised motion: M19 spindle orientation, G33 synchronised feeds, G33.1 rigid
//! tapping and the G76 multi-pass threading cycle, as LinuxCNC's G- and M-code reference
//! describes them and as `rs274` 2.9 prints them (its calls are checked by the corpus).

use super::words::{g_group as G, slot, Decoded};
use super::{Interpreter, Sink};
use crate::diag::Diagnostic;
use oficina_canon::{CanonOp, OrientDir, Plane};

/// G76's words, in program units (X offsets already radii under G7).
struct Thread {
    /// Distance per revolution along the drive line.
    pitch: f64,
    /// Thread peak offset from the drive line (negative: external thread).
    peak: f64,
    /// First cut depth beyond the peak, and full thread depth.
    first: f64,
    full: f64,
    /// Depth degression: pass n cuts at `first · n^(1/degression)`.
    degression: f64,
    /// Compound slide angle, radians.
    compound: f64,
    spring_passes: u32,
    /// Taper length along the drive line, and whether entry / exit are tapered.
    taper: f64,
    entry: bool,
    exit: bool,
}

impl Interpreter {
    /// M19 R- Q- P-: rs274 orients only when R or P is given and waits only when Q is; in
    /// every case the spindle stops turning (the next M3/M4 starts it again).
    pub(super) fn orient_spindle(&mut self, d: &Decoded, sink: Sink) -> Result<(), Diagnostic> {
        let angle = d.get('R');
        if let Some(r) = angle {
            if !(0.0..=360.0).contains(&r) {
                return Err(self.fail(d.span_of('R'), "R value must be within 0..360 with M19", 0));
            }
        }
        let dir = match d.get('P') {
            None => None,
            Some(0.0) => Some(OrientDir::Shortest),
            Some(1.0) => Some(OrientDir::Clockwise),
            Some(2.0) => Some(OrientDir::CounterClockwise),
            Some(_) => {
                return Err(self.fail(d.span_of('P'), "P value must be 0,1,or 2 with M19", 0))
            }
        };
        self.modal.spindle = None;
        if angle.is_some() || dir.is_some() {
            self.emit(
                sink,
                CanonOp::OrientSpindle {
                    // rs274 adds ORIENT_OFFSET to R, or takes it alone without R.
                    angle: angle.unwrap_or(0.0) + self.orient_offset,
                    dir: dir.unwrap_or_default(),
                },
            );
        }
        if let Some(q) = d.get('Q') {
            if !(q > 0.0) {
                return Err(self.fail(d.span_of('Q'), "Q word with M19 requires a value > 0", 0));
            }
            self.emit(sink, CanonOp::WaitOrientComplete(q));
        }
        Ok(())
    }

    /// The pitch (K, mm per revolution) of G33 / G33.1 and the checks both share.
    fn sync_pitch(&self, d: &Decoded, name: &str) -> Result<f64, Diagnostic> {
        if !d.any_axis() {
            return Err(self.fail(d.g_span(G::MOTION), "All axes missing with motion code", 31));
        }
        let Some(k) = d.values[slot('K')] else {
            return Err(self
                .fail(d.g_span(G::MOTION), "K word missing with g33/g33.1", 0)
                .with_help("K is the distance moved per spindle revolution; it is not modal"));
        };
        if self.modal.spindle.is_none() {
            return Err(self
                .fail(
                    d.g_span(G::MOTION),
                    format!("Spindle not turning in {name}"),
                    0,
                )
                .with_help("start the spindle with M3 or M4 (and an S word) first"));
        }
        if self.modal.comp.is_some() {
            return Err(self.fail(
                d.g_span(G::MOTION),
                format!("Cannot use {name} with cutter radius compensation on"),
                0,
            ));
        }
        // rs274 passes K ≤ 0 on; a move that never advances (or runs backwards against the
        // spindle) cannot be timed or cut: refused (docs/linuxcnc-differences.md).
        if !(k.v > 0.0) || !k.v.is_finite() {
            return Err(self.fail(
                k.span,
                format!(
                    "K (distance per revolution) must be > 0 with {name}, not {}",
                    k.v
                ),
                0,
            ));
        }
        Ok(k.v * self.k())
    }

    /// G33: a straight feed from the current point to `end`, `K` per spindle revolution.
    pub(super) fn spindle_sync(
        &mut self,
        d: &Decoded,
        sink: Sink,
        end: [f64; 6],
    ) -> Result<(), Diagnostic> {
        let pitch = self.sync_pitch(d, "G33")?;
        self.emit(sink, CanonOp::StartSpeedFeedSync { pitch });
        self.emit_straight(sink, true, end);
        self.emit(sink, CanonOp::StopSpeedFeedSync);
        self.pos = end;
        Ok(())
    }

    /// G33.1: in to `end` and back out, synchronised; the tool ends where it started. The
    /// I word (spindle speed multiplier for the way out) is accepted; rs274 2.9's canonical
    /// call carries no such value.
    pub(super) fn rigid_tap(
        &mut self,
        d: &Decoded,
        sink: Sink,
        end: [f64; 6],
    ) -> Result<(), Diagnostic> {
        let pitch = self.sync_pitch(d, "G33.1")?;
        self.emit(sink, CanonOp::StartSpeedFeedSync { pitch });
        self.emit(
            sink,
            CanonOp::RigidTap {
                to: self.machine(end),
            },
        );
        self.emit(sink, CanonOp::StopSpeedFeedSync);
        Ok(())
    }

    /// G76's words, checked as LinuxCNC's reference lists its errors.
    fn thread_words(&self, d: &Decoded) -> Result<Thread, Diagnostic> {
        let span = d.g_span(G::MOTION);
        if self.modal.plane != Plane::XZ {
            return Err(self
                .fail(span, "G76 needs the XZ plane", 0)
                .with_help("select it with G18 before G76"));
        }
        for l in ['X', 'Y', 'A', 'B', 'C', '@', '^'] {
            if d.has(l) {
                return Err(self
                    .fail(d.span_of(l), format!("{l} word used with G76"), 0)
                    .with_help("G76 starts at the current X (the drive line) and takes only Z"));
            }
        }
        if !d.has('Z') {
            return Err(self.fail(span, "Z word missing with G76", 0));
        }
        let Some(pitch) = d.get('P') else {
            return Err(self.fail(span, "P word missing with G76", 0));
        };
        let (Some(peak), Some(first), Some(full)) = (d.get('I'), d.get('J'), d.get('K')) else {
            return Err(self.fail(span, "I J or K words missing with G76", 0));
        };
        if peak == 0.0 {
            return Err(self.fail(d.span_of('I'), "In G76, I must not be 0", 0));
        }
        for (l, v) in [('P', pitch), ('J', first), ('K', full)] {
            if !(v > 0.0) || !v.is_finite() {
                return Err(self.fail(
                    d.span_of(l),
                    format!("{l} must be > 0 with G76, not {v}"),
                    0,
                ));
            }
        }
        let degression = d.get('R').unwrap_or(1.0);
        if !(degression >= 1.0) || !degression.is_finite() {
            return Err(self.fail(
                d.span_of('R'),
                format!("R (depth degression) must be ≥ 1 with G76, not {degression}"),
                0,
            ));
        }
        let h = d.get('H').unwrap_or(0.0);
        if !(0.0..=1000.0).contains(&h) || h.fract() != 0.0 {
            return Err(self.fail(
                d.span_of('H'),
                format!("H (spring passes) must be a whole number from 0 to 1000, not {h}"),
                0,
            ));
        }
        let q = d.get('Q').unwrap_or(0.0);
        if !(q.abs() < 90.0) {
            return Err(self.fail(
                d.span_of('Q'),
                format!("Q (compound angle) must be within ±90° with G76, not {q}"),
                0,
            ));
        }
        let taper = d.get('E').unwrap_or(0.0);
        let l = d.get('L').unwrap_or(0.0);
        if !(0.0..=3.0).contains(&l) || l.fract() != 0.0 {
            return Err(self.fail(
                d.span_of('L'),
                format!("L must be 0, 1, 2 or 3 with G76, not {l}"),
                0,
            ));
        }
        let z_end = self.axis_target(d)[2] / self.k();
        let drive = (z_end - self.pos[2] / self.k()).abs();
        if !(taper >= 0.0) || taper > drive / 2.0 {
            return Err(self.fail(
                d.span_of('E'),
                format!("E (taper length) must be from 0 to half the thread length ({:.4}), not {taper}", drive / 2.0),
                0,
            ));
        }
        // G7: I, J and K are diameters, as X words are.
        let r = if self.modal.diameter_mode { 0.5 } else { 1.0 };
        let l = l as u32;
        Ok(Thread {
            pitch,
            peak: peak * r,
            first: first * r,
            full: full * r,
            degression,
            compound: q.to_radians(),
            spring_passes: h as u32,
            taper,
            entry: taper > 0.0 && l & 1 != 0,
            exit: taper > 0.0 && l & 2 != 0,
        })
    }

    /// G76: passes at depths `J·n^(1/R)` (n = 1, 2, … while shallower than K), one at the
    /// full depth K, then H spring passes at K. With the drive line at x₀ (the current X),
    /// the peak at p = x₀ + I and s = sign(I), a pass at depth δ cuts at x = p + s·δ and
    /// stands off at x − (p + s·K − x₀), so every pass retracts as far as the last one
    /// needs. The compound angle Q shifts a pass along the drive direction u (sign of
    /// Z − z₀) by δ·tan Q at its start and by (δ − K)·tan Q at its end. A taper (E along
    /// Z, K across) is fed at pitch·√(K² + E²)/E so the thread's lead along Z stays P.
    pub(super) fn threading_cycle(&mut self, d: &Decoded, sink: Sink) -> Result<(), Diagnostic> {
        let t = self.thread_words(d)?;
        if self.modal.spindle.is_none() {
            return Err(self
                .fail(d.g_span(G::MOTION), "Spindle not turning in G76", 0)
                .with_help("start the spindle with M3 or M4 (and an S word) first"));
        }
        // Worked in program units (so a depth on a pass boundary falls as in rs274), then
        // scaled to mm for the moves.
        let k = self.k();
        let x0 = self.pos[0] / k;
        let z0 = self.pos[2] / k;
        let z_end = self.axis_target(d)[2] / k;
        let u = if z_end > z0 { 1.0 } else { -1.0 };
        let s = t.peak.signum();
        let peak = x0 + t.peak;
        let stand_off = peak + s * t.full - x0;
        let tan_q = t.compound.tan();
        let taper_pitch = t.pitch * t.full.hypot(t.taper) / t.taper.max(f64::MIN_POSITIVE);
        let base = self.pos;
        let to = |x: f64, z: f64| {
            let mut p = base;
            p[0] = x * k;
            p[2] = z * k;
            p
        };
        let mut pass = |me: &mut Interpreter, depth: f64| {
            let x = peak + s * depth;
            let x_out = x - stand_off;
            let z_in = z0 + u * depth * tan_q;
            let z_out = z_end + u * (depth - t.full) * tan_q;
            me.emit_straight(sink, false, to(x_out, z_in));
            if t.entry {
                me.emit(sink, CanonOp::EnableFeedOverride(false));
                me.emit(
                    sink,
                    CanonOp::StartSpeedFeedSync {
                        pitch: taper_pitch * k,
                    },
                );
                me.emit_straight(sink, true, to(x - s * t.full, z_in));
                me.emit_straight(sink, true, to(x, z_in + u * t.taper));
                me.emit(sink, CanonOp::StartSpeedFeedSync { pitch: t.pitch * k });
            } else {
                me.emit_straight(sink, false, to(x, z_in));
                me.emit(sink, CanonOp::EnableFeedOverride(false));
                me.emit(sink, CanonOp::StartSpeedFeedSync { pitch: t.pitch * k });
            }
            if t.exit {
                me.emit_straight(sink, true, to(x, z_out - u * t.taper));
                me.emit(
                    sink,
                    CanonOp::StartSpeedFeedSync {
                        pitch: taper_pitch * k,
                    },
                );
                me.emit_straight(sink, true, to(x - s * t.full, z_out));
            } else {
                me.emit_straight(sink, true, to(x, z_out));
            }
            me.emit(sink, CanonOp::StopSpeedFeedSync);
            me.emit_straight(sink, false, to(x_out, z_out));
            me.emit(sink, CanonOp::EnableFeedOverride(true));
        };
        // The depths of the passes before the full one. Bounded: more passes than this is a
        // typing error (J tiny against K, or R huge), not a thread.
        const MAX_PASSES: usize = 10_000;
        let mut depths = Vec::new();
        let mut depth = t.first;
        while depth < t.full {
            if depths.len() == MAX_PASSES {
                return Err(self.fail(
                    d.g_span(G::MOTION),
                    format!(
                        "G76 would need more than {MAX_PASSES} passes: J is too small against K, or R too large"
                    ),
                    0,
                ));
            }
            depths.push(depth);
            depth = t.first * (depths.len() as f64 + 1.0).powf(1.0 / t.degression);
        }
        for depth in depths {
            pass(self, depth);
        }
        for _ in 0..=t.spring_passes {
            pass(self, t.full);
        }
        let end = to(x0, z_end);
        self.emit_straight(sink, false, end);
        self.pos = end;
        self.modal.feed_override = true;
        Ok(())
    }
}
