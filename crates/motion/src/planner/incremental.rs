//! The planner as firmware runs it (grbl's planner.c and stepper.c): blocks arrive one at a
//! time into a small buffer while the machine moves, so the plan always ends at rest after
//! the last buffered block — if nothing more comes the machine must still stop within what
//! it has, which is why a starved buffer slows the machine down. Every push re-plans what is
//! not executed yet from where the machine is and the speed it has (grbl re-plans from its
//! last optimal block; the buffer here is a few blocks, so the whole rest is re-planned).
//!
//! Limits, junction speeds and velocity profiles are the ones [`super::plan`] uses
//! ([`block_limits`], [`junction_limit`], [`Motion::plan`]), so a job whose look-ahead fits
//! in the buffer takes the same time here as in [`crate::estimate`]. Trapezoids only: a
//! re-plan may start mid-ramp, which an S-curve (zero acceleration at block ends) forbids.

use super::{block_limits, junction_limit, BlockLimits};
use crate::kinematics::{AnyKinematics, Kinematics};
use crate::moves::{lerp3, Move, MoveKind};
use crate::profile::{Profile, VelocityProfile};
use crate::velocity::{brake_floor, ramp_distance, reachable, Motion};
use crate::MotionError;
use std::collections::VecDeque;

/// A straight move offered to [`Incremental::push`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Push {
    /// Source line (for errors and the finished-block report).
    pub line: u32,
    /// Cartesian end, mm.
    pub end: [f64; 3],
    /// Requested path speed before overrides, mm/s; `INFINITY` for rapids (joint limits).
    pub speed: f64,
    /// Rapid or feed (arcs come as their chords).
    pub kind: MoveKind,
}

#[derive(Clone, Copy, Debug)]
struct Queued {
    m: Move,
    bl: BlockLimits,
    /// Speed asked for, before the overrides scale it.
    requested: f64,
    /// Junction ceiling at the block's start.
    max_entry: f64,
    /// Planned entry speed.
    entry: f64,
}

/// Where a feed hold brings the machine to rest: block index and distance along it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct HoldStop {
    block: usize,
    at: f64,
}

/// What one [`Incremental::advance`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Advanced {
    /// Blocks completed, oldest first (their count; they left the buffer).
    pub finished: usize,
    /// Seconds of the step spent at rest after the motion ran out (buffer empty or hold
    /// reached): when the machine stopped, counted back from the end of the step.
    pub rest: f64,
}

/// The incremental planner: push blocks, advance time, read position and speed.
pub struct Incremental {
    profile: Profile,
    kin: AnyKinematics,
    blocks: VecDeque<Queued>,
    /// Distance already done along the front block when its motion was last planned.
    done: f64,
    /// The front block's motion from `done` at the last re-plan, and the time spent in it.
    motion: Motion,
    t: f64,
    /// Where the last pushed block ends (the next one starts there).
    tail: [f64; 3],
    q_tail: [f64; 3],
    hold: Option<HoldStop>,
    /// Feed and rapid override factors (1.0 = 100 %).
    feed: f64,
    rapid: f64,
}

impl Incremental {
    /// A planner for `profile` with the machine at rest at `start`. Only machines whose
    /// joints are linear in Cartesian position: a firmware block is one straight joint move.
    pub fn new(mut profile: Profile, start: [f64; 3]) -> Result<Incremental, MotionError> {
        let kin = crate::kinematics::for_profile(&profile);
        if !kin.is_linear() {
            return Err(MotionError::BadMove {
                line: 0,
                what: format!(
                    "profile '{}': the incremental planner needs linear kinematics",
                    profile.name
                ),
            });
        }
        profile.shape = VelocityProfile::Trapezoid;
        let q = joints(&kin, start, 0)?;
        Ok(Incremental {
            profile,
            kin,
            blocks: VecDeque::new(),
            done: 0.0,
            motion: Motion::default(),
            t: 0.0,
            tail: start,
            q_tail: q,
            hold: None,
            feed: 1.0,
            rapid: 1.0,
        })
    }

    /// The machine profile planned for.
    pub fn profile(&self) -> &Profile {
        &self.profile
    }

    /// Blocks in the buffer, the one being executed included.
    pub fn len(&self) -> usize {
        self.blocks.len()
    }

    /// No block in the buffer.
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// Where the last buffered block ends (the machine position when empty).
    pub fn tail(&self) -> [f64; 3] {
        self.tail
    }

    /// Path speed now, mm/s.
    pub fn speed(&self) -> f64 {
        if self.blocks.is_empty() {
            return 0.0;
        }
        self.motion.at(self.t).1
    }

    /// Cartesian position now.
    pub fn position(&self) -> [f64; 3] {
        let Some(b) = self.blocks.front() else {
            return self.tail;
        };
        let s = self.done + self.motion.at(self.t).0;
        lerp3(b.m.start, b.m.end, (s / b.m.length).clamp(0.0, 1.0))
    }

    /// Appends a straight move from the tail and re-plans. A move shorter than a
    /// micrometre queues nothing (grbl drops blocks without steps) and returns `false`.
    pub fn push(&mut self, p: Push) -> Result<bool, MotionError> {
        if !(p.end.iter().all(|c| c.is_finite()) && p.speed > 0.0) {
            return Err(MotionError::BadMove {
                line: p.line,
                what: format!(
                    "move to {:?} at {} mm/s: needs a finite end and a positive speed",
                    p.end, p.speed
                ),
            });
        }
        let length = crate::moves::dist3(self.tail, p.end);
        if length < 1e-6 {
            return Ok(false);
        }
        let q1 = joints(&self.kin, p.end, p.line)?;
        let m = Move {
            line: p.line,
            op: 0,
            kind: p.kind,
            start: self.tail,
            end: p.end,
            q0: self.q_tail,
            q1,
            // Firmware blocks here are X, Y, Z only.
            rot0: [0.0; 3],
            rot1: [0.0; 3],
            length,
            whole: length,
            speed: p.speed,
            feed_scaled: p.kind != MoveKind::Rapid,
            stop_before: false,
            deviation: self.profile.junction_deviation,
        };
        let mut q = Queued {
            m,
            bl: block_limits(&m, &self.profile, VelocityProfile::Trapezoid),
            requested: p.speed,
            max_entry: 0.0,
            entry: 0.0,
        };
        self.apply_overrides(&mut q);
        if let Some(prev) = self.blocks.back() {
            q.max_entry = junction_limit(&prev.m, &prev.bl, &q.m, &q.bl, &self.profile);
        }
        self.tail = p.end;
        self.q_tail = q1;
        self.blocks.push_back(q);
        if self.blocks.len() == 1 {
            self.done = 0.0;
            self.t = 0.0;
        }
        self.replan();
        Ok(true)
    }

    /// New feed and rapid override factors, effective at once: the machine brakes or speeds
    /// up at its acceleration limit, as grbl does on an override change.
    pub fn set_overrides(&mut self, feed: f64, rapid: f64) {
        if feed == self.feed && rapid == self.rapid {
            return;
        }
        self.feed = feed;
        self.rapid = rapid;
        for i in 0..self.blocks.len() {
            let mut q = self.blocks[i];
            self.apply_overrides(&mut q);
            if i > 0 {
                let p = &self.blocks[i - 1];
                q.max_entry = junction_limit(&p.m, &p.bl, &q.m, &q.bl, &self.profile);
            }
            self.blocks[i] = q;
        }
        self.replan();
    }

    fn apply_overrides(&self, q: &mut Queued) {
        let rapid = q.m.kind == MoveKind::Rapid;
        q.m.speed = if rapid {
            q.requested
        } else {
            q.requested * self.feed
        };
        q.bl = block_limits(&q.m, &self.profile, VelocityProfile::Trapezoid);
        if rapid {
            // Rapids run at the joints' limits; the rapid override scales that.
            q.bl.v_nominal *= self.rapid;
        }
    }

    /// Feed hold: brake along the path as hard as the limits allow. The machine stops
    /// inside the buffer; [`Incremental::held`] says when it is at rest.
    pub fn hold(&mut self) {
        if self.hold.is_some() || self.blocks.is_empty() {
            return;
        }
        let mut v = self.speed();
        let mut from = self.done + self.motion.at(self.t).0;
        let mut stop = None;
        for (i, b) in self.blocks.iter_mut().enumerate() {
            if i > 0 {
                b.entry = v;
                from = 0.0;
            }
            let left = b.m.length - from;
            let d = ramp_distance(0.0, v, b.bl.lim);
            if d <= left + 1e-9 {
                stop = Some(HoldStop {
                    block: i,
                    at: (from + d).min(b.m.length),
                });
                break;
            }
            v = brake_floor(v, left, b.bl.lim);
        }
        // The buffer always ends at rest, so braking stops inside it.
        self.hold = Some(stop.unwrap_or(HoldStop {
            block: self.blocks.len() - 1,
            at: self.blocks.back().map_or(0.0, |b| b.m.length),
        }));
        self.replan();
    }

    /// True while a hold is in force and the machine has come to rest. A braking ramp ends
    /// at `v0 − a·(v0/a)`, a few ulps off zero (1e-15 mm/s seen): rest is "below a nanometre
    /// a second", not exactly 0, or the hold never completes.
    pub fn held(&self) -> bool {
        self.hold.is_some() && self.speed() <= 1e-9 && self.t >= self.motion.duration
    }

    /// Ends a hold: the rest of the buffer is re-planned from rest.
    pub fn resume(&mut self) {
        if self.hold.take().is_some() {
            self.replan();
        }
    }

    /// Drops every block (a reset or a cancelled jog once stopped); the machine stays where
    /// it is.
    pub fn clear(&mut self) {
        let p = self.position();
        self.blocks.clear();
        self.hold = None;
        self.motion = Motion::default();
        self.done = 0.0;
        self.t = 0.0;
        self.tail = p;
        self.q_tail = self.kin.joints(p).unwrap_or(p);
    }

    /// Runs the machine for `dt` seconds.
    pub fn advance(&mut self, mut dt: f64) -> Advanced {
        let mut out = Advanced::default();
        while dt > 0.0 && !self.blocks.is_empty() {
            let left = self.motion.duration - self.t;
            if left > dt {
                self.t += dt;
                return out;
            }
            dt -= left.max(0.0);
            let stopping_here = self.hold.is_some_and(|h| h.block == 0);
            let at_end = self.done + self.motion.length >= self.blocks[0].m.length - 1e-9;
            if stopping_here && !at_end {
                // At rest inside the block until resumed.
                self.t = self.motion.duration;
                out.rest = dt;
                return out;
            }
            let v = self.motion.v_end();
            self.blocks.pop_front();
            out.finished += 1;
            if let Some(h) = self.hold.as_mut() {
                if h.block == 0 {
                    // The hold stop fell on the block's end: at rest before the next one.
                    h.at = 0.0;
                } else {
                    h.block -= 1;
                }
            }
            self.done = 0.0;
            self.t = 0.0;
            match self.blocks.front_mut() {
                Some(b) => {
                    b.entry = v;
                    self.replan();
                }
                None => self.motion = Motion::default(),
            }
        }
        out.rest = dt;
        out
    }

    /// Plans every unexecuted block: ceilings raised to what braking from the current
    /// speed cannot avoid (after a lowered override), a backward pass from rest at the end
    /// of the buffer (or at the hold stop), a forward pass from the current speed; then the
    /// front block's motion from where the machine is.
    fn replan(&mut self) {
        let n = self.blocks.len();
        if n == 0 {
            return;
        }
        let s_now = self.done + self.motion.at(self.t).0;
        let v_now = if self.t > 0.0 || self.done > 0.0 {
            self.speed()
        } else {
            self.blocks[0].entry
        };
        self.done = s_now;
        self.blocks[0].entry = v_now;
        // Lengths still to run, the front counted from the machine's position.
        let len = |i: usize, b: &Queued, hold: Option<HoldStop>| {
            let start = if i == 0 { s_now } else { 0.0 };
            let end = match hold {
                Some(h) if h.block == i => h.at,
                _ => b.m.length,
            };
            (end - start).max(0.0)
        };
        let last = self.hold.map_or(n - 1, |h| h.block);
        if self.hold.is_none() {
            // Braking floors: what the machine cannot avoid reaching from its speed now.
            let mut ceiling: Vec<f64> = self.blocks.iter().map(|b| b.max_entry).collect();
            let mut v = v_now;
            for i in 0..n - 1 {
                v = brake_floor(v, len(i, &self.blocks[i], None), self.blocks[i].bl.lim);
                if v <= ceiling[i + 1] {
                    break;
                }
                ceiling[i + 1] = v;
            }
            let mut exit = 0.0;
            for i in (1..n).rev() {
                let b = &mut self.blocks[i];
                b.entry = ceiling[i].min(reachable(exit, b.m.length, b.bl.lim));
                exit = b.entry;
            }
            let mut v = v_now;
            for i in 1..n {
                let prev = &self.blocks[i - 1];
                let cap = reachable(v, len(i - 1, prev, None), prev.bl.lim);
                let b = &mut self.blocks[i];
                b.entry = b.entry.min(cap);
                v = b.entry;
            }
        }
        // Under a hold the entries up to the stop are the braking chain [`hold`] set.
        let f = &self.blocks[0];
        let exit = if last == 0 { 0.0 } else { self.blocks[1].entry };
        let length = len(0, f, self.hold);
        self.motion = Motion::plan(length, v_now, f.bl.v_nominal, exit, f.bl.lim);
        self.t = 0.0;
    }
}

fn joints(kin: &AnyKinematics, p: [f64; 3], line: u32) -> Result<[f64; 3], MotionError> {
    kin.joints(p).map_err(|why| MotionError::Unreachable {
        line,
        x: p[0],
        y: p[1],
        why,
    })
}
