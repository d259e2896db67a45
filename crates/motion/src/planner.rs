//! Streaming look-ahead planner (grbl's model, with a time horizon).
//!
//! Each straight piece becomes a block with a nominal speed, a path acceleration and jerk
//! derived from every joint's limits (through dq/ds, so non-linear machines slow down where
//! a joint moves fast, e.g. near the polar arm's pivot). Junction speeds follow grbl's
//! junction deviation (a virtual arc of deviation δ tangent to both pieces, whose centripetal
//! acceleration stays within the limit), plus a centripetal cap for short curved pieces: the
//! change of joint velocity across a junction, spread over the shorter neighbour, must not
//! exceed any joint's acceleration.
//!
//! The buffer always ends in a planned stop, so whatever is emitted is safe even if the
//! program ends right after. A block is emitted once no future block can change it (the
//! backward pass met a block already at its junction ceiling), or when the buffer holds more
//! than `horizon` seconds of motion at nominal speed (bounded memory on any program).

pub(crate) mod incremental;
mod live;

pub(crate) use crate::moves::MoveKind;
use crate::moves::{Item, Move, MoveStream, Overrides};
use crate::profile::{Joint, Profile, VelocityProfile};
use crate::velocity::{reachable, Limits, Motion};
use crate::MotionError;
use oficina_canon::Canon;
use std::collections::VecDeque;

/// Hard cap on buffered blocks, whatever the horizon says (memory bound).
pub(crate) const MAX_BLOCKS: usize = 1 << 16;

/// Blocks read between two backward passes. Each pass walks the new blocks plus the ramp
/// down to the planned stop behind them, so larger batches walk each block fewer times.
const BATCH: usize = 128;

/// What a planned segment is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentKind {
    /// Motion of this kind.
    Move(MoveKind),
    /// G4: at rest for the segment's duration.
    Dwell,
    /// M0/M1: the machine waits for the operator.
    Pause,
    /// A spindle, tool or end op reached with the machine at rest.
    Sync,
    /// Where a feed hold ([`Planner::hold`]) brought the machine to rest.
    Hold,
}

/// Where the machine is inside the last segment the planner gave out, when a live command
/// re-plans what follows: distance done along it and path speed there. The acceleration must
/// be zero at that instant in S-curve mode (the new motion starts with none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cut {
    /// Distance done along the segment, mm.
    pub s: f64,
    /// Path speed there, mm/s.
    pub v: f64,
}

/// One planned, timed straight piece (or a pause at rest).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Source line.
    pub line: u32,
    /// Index of the canon motion op this segment comes from.
    pub op: u64,
    /// Motion, dwell, pause, sync or hold.
    pub kind: SegmentKind,
    /// Cartesian start, mm.
    pub start: [f64; 3],
    /// Cartesian end, mm.
    pub end: [f64; 3],
    /// Joint positions at the ends; joints move linearly in between.
    pub q0: [f64; 3],
    /// Joint positions at the end.
    pub q1: [f64; 3],
    /// Rotary joints A, B, C at the ends, degrees; they move linearly in between too.
    pub rot0: [f64; 3],
    /// Rotary joints at the end, degrees.
    pub rot1: [f64; 3],
    /// Distance and speed over time along the segment.
    pub motion: Motion,
}

impl Segment {
    /// Length of the segment in time, seconds.
    pub fn duration(&self) -> f64 {
        self.motion.duration
    }

    /// Rotary joints (A, B, C, degrees) at time `t` into the segment.
    pub fn rotary_at(&self, t: f64) -> [f64; 3] {
        let (s, _, _) = self.motion.at(t);
        let f = if self.motion.length > 0.0 {
            (s / self.motion.length).clamp(0.0, 1.0)
        } else {
            0.0
        };
        crate::moves::lerp3(self.rot0, self.rot1, f)
    }

    /// Cartesian and joint position at time `t` into the segment, and path speed.
    pub fn sample(&self, t: f64) -> ([f64; 3], [f64; 3], f64) {
        let (s, v, _) = self.motion.at(t);
        let f = if self.motion.length > 0.0 {
            (s / self.motion.length).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (
            crate::moves::lerp3(self.start, self.end, f),
            crate::moves::lerp3(self.q0, self.q1, f),
            v,
        )
    }
}

/// How to plan besides the profile.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct PlanOptions {
    /// Feed and rapid overrides.
    pub overrides: Overrides,
    /// Overrides the profile's velocity shape.
    pub shape: Option<VelocityProfile>,
}

/// Per-block limits along the path, derived from the joints.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BlockLimits {
    pub v_nominal: f64,
    pub lim: Limits,
    /// Joint displacement per mm of path.
    pub dqds: [f64; 3],
    /// Rotary joint displacement (degrees) per unit of path.
    pub drds: [f64; 3],
}

/// Limits of a piece: every joint's speed, step rate, acceleration and jerk, seen through
/// dq/ds. Shared with the checker only as the definition of the limits, not of the plan.
pub(crate) fn block_limits(m: &Move, profile: &Profile, shape: VelocityProfile) -> BlockLimits {
    let l = m.length;
    let mut v = m.speed;
    let mut lim = Limits {
        accel: f64::INFINITY,
        jerk: f64::INFINITY,
    };
    // Each joint moving d units per mm of path caps the path speed at its rate / d, its
    // step rate / d, and the path acceleration and jerk at its own / d.
    let mut cap = |joint: &Joint, d: f64| {
        v = v
            .min(joint.max_rate / d)
            .min(profile.max_step_rate / joint.steps_per_unit / d);
        lim.accel = lim.accel.min(joint.acceleration / d);
        if shape == VelocityProfile::SCurve {
            lim.jerk = lim.jerk.min(joint.jerk.unwrap_or(f64::INFINITY) / d);
        }
    };
    let mut dqds = [0.0; 3];
    for (i, jt) in profile.joints.iter().enumerate() {
        dqds[i] = (m.q1[i] - m.q0[i]) / l;
        let d = dqds[i].abs();
        if let (Some(jt), true) = (jt, d > 0.0) {
            cap(jt, d);
        }
    }
    // Rotary joints the same way: a mixed move is slowed so A, B, C keep within their
    // °/s, °/s² and steps/s (LinuxCNC: "all axes are slowed to maintain the desired path").
    let mut drds = [0.0; 3];
    for (i, r) in profile.rotary.iter().enumerate() {
        drds[i] = (m.rot1[i] - m.rot0[i]) / l;
        let d = drds[i].abs();
        if let (Some(r), true) = (r, d > 0.0) {
            cap(&r.joint, d);
        }
    }
    BlockLimits {
        v_nominal: v,
        lim,
        dqds,
        drds,
    }
}

/// Largest speed allowed through the junction between `p` and `b`.
///
/// Junction deviation, derived as grbl's `planner.c` does. The machine does not really round
/// the corner, but it may pass it as fast as if it followed a circle tangent to both moves
/// whose closest approach to the corner is δ (`b.deviation`). Let θ be the angle between the
/// two moves at the corner, so cos θ = −u_p·u_b with u_p, u_b their unit directions
/// (θ = π straight on, θ → 0 a reversal). The circle's centre lies on the corner's
/// bisector; its radius R meets each move at a right angle, so the centre is d = R / sin(θ/2)
/// from the corner and the circle passes d − R from it. Setting d − R = δ:
///
/// ```text
/// δ = R / sin(θ/2) − R   ⇒   R = δ · sin(θ/2) / (1 − sin(θ/2))
/// ```
///
/// with sin(θ/2) = √((1 − cos θ) / 2), no trigonometric call needed. Going round that circle
/// at speed v needs the centripetal acceleration v²/R, so v² = a·R, where a is the
/// acceleration available along the junction vector u_b − u_p: each joint i allows
/// a_i·|u_b − u_p| / |Δq_i|, with Δq_i the change of joint i's rate per mm across the corner
/// (for Cartesian machines grbl's `junction_unit_vec` limit). A reversal (θ ≈ 0) must stop;
/// straight on (θ ≈ π) the circle is infinite and only the caps below apply.
pub(crate) fn junction_limit(
    p: &Move,
    pl: &BlockLimits,
    b: &Move,
    bl: &BlockLimits,
    profile: &Profile,
) -> f64 {
    if b.stop_before {
        return 0.0;
    }
    let up = unit(p);
    let ub = unit(b);
    let dot: f64 = (0..6).map(|i| up[i] * ub[i]).sum();
    let cos = -dot;
    let mut v2 = f64::INFINITY;
    if cos > 0.999_999 {
        return 0.0; // a reversal
    }
    // Change of every joint's rate per unit of path across the corner: X, Y, Z joints, then
    // the rotary ones.
    let dq: [f64; 6] = std::array::from_fn(|i| {
        if i < 3 {
            bl.dqds[i] - pl.dqds[i]
        } else {
            bl.drds[i - 3] - pl.drds[i - 3]
        }
    });
    let joints = profile.all_joints();
    if cos > -0.999_999 {
        // grbl: the junction vector's acceleration limit and the virtual arc through δ.
        let du = (0..6).map(|i| (ub[i] - up[i]).powi(2)).sum::<f64>().sqrt();
        let mut acc = f64::INFINITY;
        for (i, jt) in joints.iter().enumerate() {
            if let (Some(jt), true) = (jt, dq[i] != 0.0) {
                acc = acc.min(jt.acceleration * du / dq[i].abs());
            }
        }
        let sin_half = (0.5 * (1.0 - cos)).sqrt();
        v2 = acc * b.deviation * sin_half / (1.0 - sin_half);
    }
    // Centripetal cap: the joint velocity change spread over the shorter piece.
    let lmin = p.whole.min(b.whole);
    for (i, jt) in joints.iter().enumerate() {
        if let (Some(jt), true) = (jt, dq[i] != 0.0) {
            v2 = v2.min(jt.acceleration * lmin / dq[i].abs());
        }
    }
    v2.sqrt().min(pl.v_nominal).min(bl.v_nominal)
}

/// Direction of a piece in the path space the feed rate is measured in ([`path_length`]):
/// X, Y, Z when the tool moves (the rotary axes ride along), else A, B, C of a pure rotary
/// move. A unit vector of six components, so a corner between a cut and a pure turn of the
/// 4th axis is a right angle.
///
/// [`path_length`]: crate::moves::path_length
fn unit(m: &Move) -> [f64; 6] {
    let l = m.length;
    let linear = crate::moves::dist3(m.start, m.end) > 0.5 * l;
    std::array::from_fn(|i| match (i < 3, linear) {
        (true, true) => (m.end[i] - m.start[i]) / l,
        (false, false) => (m.rot1[i - 3] - m.rot0[i - 3]) / l,
        _ => 0.0,
    })
}

#[derive(Clone, Copy)]
struct Block {
    m: Move,
    bl: BlockLimits,
    max_entry: f64,
    /// Backward-pass entry speed (assuming a stop at the end of the buffer).
    entry: f64,
}

/// The streaming planner: an iterator of planned segments.
pub struct Planner<'p, I: Iterator<Item = Canon>> {
    moves: MoveStream<'p, I>,
    profile: &'p Profile,
    shape: VelocityProfile,
    buf: VecDeque<Block>,
    /// Absolute index of `buf[0]`.
    base: u64,
    /// Blocks at the back of `buf` that no backward pass has seen yet.
    unplanned: usize,
    /// Absolute index of the latest block whose entry sits at its ceiling.
    ceiling: Option<u64>,
    /// Entry speed of `buf[0]`, fixed by the segment emitted before it.
    front_entry: f64,
    buffered_time: f64,
    pending: Option<Segment>,
    /// The block given out last (what a [`Cut`] cuts).
    last: Option<Block>,
    /// The feed override in force.
    feed_factor: f64,
    /// Absolute block index before which a hold stop is due.
    hold_before: Option<u64>,
    /// Where the last buffered piece ends (Cartesian, joints): dwells happen there.
    tail: ([f64; 3], [f64; 3], [f64; 3]),
    flushing: bool,
    done: bool,
}

/// Plans `ops` on `profile`: a lazy stream of timed segments (or the first error).
pub fn plan<'p, I: Iterator<Item = Canon>>(
    ops: I,
    profile: &'p Profile,
    opts: PlanOptions,
) -> Result<Planner<'p, I>, MotionError> {
    let shape = opts.shape.unwrap_or(profile.shape);
    if shape == VelocityProfile::SCurve {
        for j in profile.joints.iter().flatten() {
            if j.jerk.is_none() {
                return Err(MotionError::BadMove {
                    line: 0,
                    what: format!(
                        "S-curve planning needs joints.{}.jerk in the profile",
                        j.name
                    ),
                });
            }
        }
    }
    let moves = MoveStream::new(ops, profile, opts.overrides)?;
    let tail = (profile.start, moves.start_joints(), [0.0; 3]);
    Ok(Planner {
        moves,
        tail,
        profile,
        shape,
        buf: VecDeque::new(),
        base: 0,
        ceiling: None,
        unplanned: 0,
        front_entry: 0.0,
        buffered_time: 0.0,
        pending: None,
        last: None,
        feed_factor: opts.overrides.feed,
        hold_before: None,
        flushing: false,
        done: false,
    })
}

impl<'p, I: Iterator<Item = Canon>> Planner<'p, I> {
    /// The kinematics the planner moves the joints with.
    pub fn kinematics(&self) -> &crate::kinematics::AnyKinematics {
        self.moves.kinematics()
    }

    /// Blocks waiting in the look-ahead buffer.
    pub fn buffered(&self) -> usize {
        self.buf.len()
    }

    /// Appends a block without re-planning: the backward pass runs once per batch
    /// ([`Planner::replan`]), so a long run of blocks is walked about once, not once per push.
    fn push(&mut self, m: Move) {
        let bl = block_limits(&m, self.profile, self.shape);
        self.tail = (m.end, m.q1, m.rot1);
        let after_hold = self.hold_before == Some(self.base + self.buf.len() as u64);
        let max_entry = match self.buf.back() {
            Some(p) if !m.stop_before && !after_hold => {
                junction_limit(&p.m, &p.bl, &m, &bl, self.profile)
            }
            _ => 0.0,
        };
        self.buffered_time += m.length / bl.v_nominal;
        self.buf.push_back(Block {
            m,
            bl,
            max_entry,
            entry: 0.0,
        });
        self.unplanned += 1;
    }

    /// Backward pass from the planned stop at the end of the buffer (grbl's
    /// planner_recalculate). Blocks pushed since the last pass are all relaxed; older ones
    /// only while their entry still rises, since an entry that did not move cannot raise
    /// anything before it.
    fn replan(&mut self) {
        let n = self.buf.len();
        if self.unplanned == 0 || n == 0 {
            return;
        }
        let first_new = n - self.unplanned;
        self.unplanned = 0;
        let mut ceiling_found = false;
        let mut exit = 0.0;
        for i in (0..n).rev() {
            let b = &mut self.buf[i];
            let new = b.max_entry.min(reachable(exit, b.m.length, b.bl.lim));
            if i < first_new && new <= b.entry {
                break;
            }
            b.entry = new;
            if !ceiling_found && new >= b.max_entry {
                // The latest block at its ceiling: nothing after it can raise what is before.
                ceiling_found = true;
                let abs = self.base + i as u64;
                if self.ceiling.is_none_or(|c| c < abs) {
                    self.ceiling = Some(abs);
                }
            }
            exit = new;
        }
    }

    /// Is `buf[0]` final (or must it go now)?
    fn front_ready(&self) -> bool {
        if self.buf.is_empty() {
            return false;
        }
        if self.flushing {
            return self.unplanned == 0;
        }
        // Blocks up to the ceiling were planned by a finished backward pass.
        if self.ceiling.is_some_and(|c| c > self.base) {
            return true;
        }
        // A lone block waits for its successor so the junction between them is not lost.
        self.unplanned == 0 && self.over_horizon() && self.buf.len() > 1
    }

    fn over_horizon(&self) -> bool {
        self.buffered_time > self.profile.horizon || self.buf.len() >= MAX_BLOCKS
    }

    fn emit_front(&mut self) -> Segment {
        let b = self.buf.pop_front().expect("front block");
        self.base += 1;
        self.buffered_time = (self.buffered_time - b.m.length / b.bl.v_nominal).max(0.0);
        // Above the nominal speed only after a lowered override: the block brakes first.
        let v0 = self.front_entry;
        let next_entry = self.buf.front().map_or(0.0, |n| n.entry);
        let v1 = next_entry.min(reachable(v0, b.m.length, b.bl.lim));
        self.front_entry = v1;
        self.last = Some(b);
        Segment {
            line: b.m.line,
            op: b.m.op,
            kind: SegmentKind::Move(b.m.kind),
            start: b.m.start,
            end: b.m.end,
            q0: b.m.q0,
            q1: b.m.q1,
            rot0: b.m.rot0,
            rot1: b.m.rot1,
            motion: Motion::plan(b.m.length, v0, b.bl.v_nominal, v1, b.bl.lim),
        }
    }

    fn at_rest(&self, line: u32, kind: SegmentKind, seconds: f64) -> Segment {
        let (p, q, r) = match self.buf.front() {
            Some(b) if kind == SegmentKind::Hold => (b.m.start, b.m.q0, b.m.rot0),
            _ => self.tail,
        };
        let line = match (kind, self.buf.front(), &self.last) {
            (SegmentKind::Hold, Some(b), _) => b.m.line,
            (SegmentKind::Hold, None, Some(l)) => l.m.line,
            _ => line,
        };
        Segment {
            line,
            op: u64::MAX,
            kind,
            start: p,
            end: p,
            q0: q,
            q1: q,
            rot0: r,
            rot1: r,
            motion: Motion::dwell(seconds),
        }
    }
}

impl<I: Iterator<Item = Canon>> Iterator for Planner<'_, I> {
    type Item = Result<Segment, MotionError>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            if self.unplanned > 0
                && (self.unplanned >= BATCH || self.flushing || self.over_horizon())
            {
                self.replan();
            }
            if self.hold_before == Some(self.base) {
                self.hold_before = None;
                return Some(Ok(self.at_rest(0, SegmentKind::Hold, 0.0)));
            }
            if self.front_ready() {
                return Some(Ok(self.emit_front()));
            }
            if self.buf.is_empty() {
                if let Some(s) = self.pending.take() {
                    self.flushing = false;
                    return Some(Ok(s));
                }
                self.flushing = false;
            }
            if self.done || self.flushing {
                return None;
            }
            match self.moves.next() {
                None => {
                    self.done = true;
                    self.flushing = true;
                }
                Some(Err(e)) => {
                    self.done = true;
                    self.buf.clear();
                    return Some(Err(e));
                }
                Some(Ok(Item::Move(m))) => self.push(m),
                Some(Ok(Item::Dwell { line, seconds })) => {
                    self.pending = Some(self.at_rest(line, SegmentKind::Dwell, seconds));
                    self.flushing = true;
                }
                Some(Ok(Item::Sync { line, pause })) => {
                    let kind = if pause {
                        SegmentKind::Pause
                    } else {
                        SegmentKind::Sync
                    };
                    self.pending = Some(self.at_rest(line, kind, 0.0));
                    self.flushing = true;
                }
            }
        }
    }
}
