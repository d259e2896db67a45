//! G38.2–G38.5, straight probing, as LinuxCNC's `convert_probe` checks it and its standalone
//! canon (`saicanon.cc`) carries it out.
//!
//! Oficina's machines have no probe input, so a probe never trips, as in the standalone
//! `rs274`: the probed point reported (#5061–#5066) is the target, #5070 is 0 (not tripped),
//! and the tool is left [`BACKOFF_MM`] back from the target towards the start, where
//! `saicanon.cc` leaves it.

use super::words::{g_group as G, Decoded};
use super::{param, Interpreter, Sink};
use crate::diag::Diagnostic;
use crate::params::Params;
use oficina_canon::{CanonOp, FeedMode};

/// How far back from the target the standalone canon leaves the tool: 0.01 in, or
/// 0.254 mm in millimetre units (`STRAIGHT_PROBE`'s `backoff`): the same length.
const BACKOFF_MM: f64 = 0.254;

impl Interpreter {
    /// The probing move of G38.`code` (382 … 385) to `end` (program coordinates, mm).
    pub(super) fn probe(
        &mut self,
        d: &Decoded,
        code: u16,
        sink: Sink,
        end: [f64; 6],
    ) -> Result<(), Diagnostic> {
        let span = d.g_span(G::MOTION);
        if self.modal.comp.is_some() {
            return Err(self.fail(span, "Cannot probe with cutter radius comp on", 0));
        }
        if self.modal.feed == 0.0 {
            return Err(self
                .fail(span, "Cannot probe with zero feed rate", 0)
                .with_help("program the probing feed with an F word"));
        }
        if self.modal.feed_mode == FeedMode::UnitsPerRev {
            return Err(self.fail(span, "Cannot probe with feed per rev mode", 0));
        }
        // G38.3 and G38.5 (odd probe types) report a failed probe instead of stopping, so
        // only G38.2 and G38.4 refuse a target where the tool already is.
        let reports_failure = (code - 382) % 2 == 1;
        if !reports_failure && end == self.pos {
            return Err(self.fail(span, "Start point too close to probe point", 0));
        }
        // Where saicanon leaves the tool: `backoff` along the way back to the start,
        // x + backoff·(x₀ − x)/|p₀ − p| per axis, the rotary axes at their targets.
        let start = self.pos;
        let back: [f64; 3] = std::array::from_fn(|i| start[i] - end[i]);
        let distance = back.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut left = end;
        if distance != 0.0 {
            for i in 0..3 {
                left[i] += BACKOFF_MM * back[i] / distance;
            }
        }
        self.emit(
            sink,
            CanonOp::StraightProbe {
                to: self.machine(end),
                feeds: if distance != 0.0 { 2 } else { 1 },
            },
        );
        self.emit_straight(sink, true, end);
        if distance != 0.0 {
            self.emit_straight(sink, true, left);
        }
        self.pos = left;
        self.probed = Some(end);
        Ok(())
    }

    /// #5061–#5070 after a probing move: the probed point in program units (the target: the
    /// probe never trips), U V W 0, and 0 for "not tripped".
    pub(super) fn set_probe_params(&mut self, params: &mut Params) {
        if let Some(p) = self.probed.take() {
            let k = self.k();
            let mut v = [0.0; 10];
            for i in 0..6 {
                v[i] = if i < 3 { p[i] / k } else { p[i] };
            }
            let _ = params.set_run(param::PROBE_POSITION, &v);
        }
    }
}
