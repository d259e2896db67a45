//! Live commands on a running plan (grbl's feed override and feed hold): the part of the
//! program not yet executed is re-planned from where the machine is, at the speed it has.
//!
//! Both start from a [`Cut`] inside the segment being executed: its unexecuted rest becomes
//! the front block again, entered at the current speed. A lowered override cannot take
//! effect at once: blocks whose new ceiling is below what braking from the current speed can
//! reach keep that braking floor (still never faster than the old plan, which met every hard
//! limit), so the machine slows down at its acceleration (and jerk) limits.

use super::{block_limits, junction_limit, Block, Cut, Planner};
use crate::kinematics::Kinematics;
use crate::moves::lerp3;
use crate::velocity::{brake_floor, ramp_distance};
use oficina_canon::Canon;

impl<I: Iterator<Item = Canon>> Planner<'_, I> {
    /// Changes the feed override from now on: `cut` is where the machine is inside the last
    /// segment given out (`None` at a segment boundary or at rest). The segments given out
    /// after this call replace the rest of that segment. Not meant during a hold.
    pub fn set_feed_override(&mut self, factor: f64, cut: Option<Cut>) {
        let ratio = factor / self.feed_factor;
        self.feed_factor = factor;
        self.moves.set_feed_override(factor);
        self.requeue_rest(cut);
        for b in self.buf.iter_mut().filter(|b| b.m.feed_scaled) {
            b.m.speed *= ratio;
        }
        self.rebuild(None);
    }

    /// Feed hold: brake on the path as soon as the limits allow, then give out a
    /// [`super::SegmentKind::Hold`] segment where the machine stopped. What follows starts
    /// from rest, so resuming is simply reading on.
    pub fn hold(&mut self, cut: Option<Cut>) {
        self.requeue_rest(cut);
        let mut v = self.front_entry;
        let mut i = 0;
        let mut chain = Vec::new();
        while i < self.buf.len() && v > 0.0 {
            let b = self.buf[i];
            let d = ramp_distance(0.0, v, b.bl.lim);
            if d < b.m.length - 1e-9 {
                let rest = self.split(i, d);
                self.buf.insert(i + 1, rest);
                i += 1;
                break;
            }
            v = brake_floor(v, b.m.length, b.bl.lim);
            i += 1;
            chain.push(v);
        }
        // The stop lies before block i; the buffer's end is always a planned stop.
        self.hold_before = Some(self.base + i as u64);
        self.rebuild(Some(&chain));
    }

    /// Puts the unexecuted rest of the last segment given out back at the front.
    fn requeue_rest(&mut self, cut: Option<Cut>) {
        let (Some(cut), Some(last)) = (cut, self.last) else {
            return;
        };
        if !(cut.s >= 0.0 && cut.s < last.m.length - 1e-9 && cut.v.is_finite()) {
            return; // at its end: the next block is entered at the planned exit speed
        }
        // The executed part goes back in front only to be cut off again.
        self.buf.push_front(last);
        self.base -= 1;
        self.buf[0] = self.split(0, cut.s);
        self.buf[0].m.stop_before = false;
        self.front_entry = cut.v;
    }

    /// The part of block `i` after distance `d` (block `i` keeps the part before), starting
    /// at rest.
    fn split(&mut self, i: usize, d: f64) -> Block {
        let b = &mut self.buf[i];
        let f = (d / b.m.length).clamp(0.0, 1.0);
        let p = lerp3(b.m.start, b.m.end, f);
        // The exact joints of the cut point (they differ from the joint lerp on non-linear
        // machines by less than the path tolerance).
        let q = self
            .moves
            .kinematics()
            .joints_near(p, b.m.q0)
            .unwrap_or_else(|_| lerp3(b.m.q0, b.m.q1, f));
        let r = lerp3(b.m.rot0, b.m.rot1, f);
        let mut rest = *b;
        rest.m.start = p;
        rest.m.q0 = q;
        rest.m.rot0 = r;
        rest.m.length = b.m.length - d;
        rest.m.stop_before = true;
        b.m.end = p;
        b.m.q1 = q;
        b.m.rot1 = r;
        b.m.length = d;
        rest
    }

    /// Recomputes every buffered block's limits and junction ceilings, then the whole plan.
    /// `chain`: entry speeds imposed on blocks 1.. (a hold's braking).
    fn rebuild(&mut self, chain: Option<&[f64]>) {
        let n = self.buf.len();
        self.buffered_time = 0.0;
        for i in 0..n {
            let bl = block_limits(&self.buf[i].m, self.profile, self.shape);
            self.buffered_time += self.buf[i].m.length / bl.v_nominal;
            let max_entry = if i == 0 {
                self.front_entry
            } else if self.buf[i].m.stop_before {
                0.0
            } else {
                let p = &self.buf[i - 1];
                junction_limit(&p.m, &p.bl, &self.buf[i].m, &bl, self.profile)
            };
            self.buf[i].bl = bl;
            self.buf[i].max_entry = max_entry;
        }
        match chain {
            Some(chain) => {
                for (k, &v) in chain.iter().enumerate() {
                    if let Some(b) = self.buf.get_mut(k + 1) {
                        b.max_entry = if b.m.stop_before { 0.0 } else { v };
                    }
                }
            }
            None => {
                // Braking floors: what the machine cannot avoid reaching.
                let mut v = self.front_entry;
                for i in 0..n.saturating_sub(1) {
                    v = brake_floor(v, self.buf[i].m.length, self.buf[i].bl.lim);
                    let next = &mut self.buf[i + 1];
                    if v <= next.max_entry || next.m.stop_before {
                        break;
                    }
                    next.max_entry = v;
                }
            }
        }
        self.unplanned = n;
        self.ceiling = None;
        self.replan();
    }
}
