//! Canon ops → straight pieces. Arcs become chords within the arc tolerance; on machines with
//! non-linear kinematics every straight piece is cut further so that moving the joints
//! linearly between piece ends stays within the path tolerance of the Cartesian line. The
//! stream is lazy: one canon op in, its pieces out, no buffering of the program.

use crate::kinematics::{AnyKinematics, Kinematics};
use crate::profile::Profile;
use crate::MotionError;
use oficina_canon::{from_arc_frame, to_arc_frame, Canon, CanonOp, FeedMode, PathControlMode, Pos};
use oficina_geom::{chord_count, Helix};

/// What kind of programmed motion a piece comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MoveKind {
    /// G0.
    Rapid,
    /// G1 (or a move at the feed rate).
    Feed,
    /// A chord of a G2/G3 arc or helix.
    Arc,
}

/// One straight piece of programmed motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Move {
    pub line: u32,
    /// Index of the canon motion op this piece belongs to (0-based over motion ops).
    pub op: u64,
    pub kind: MoveKind,
    pub start: [f64; 3],
    pub end: [f64; 3],
    pub q0: [f64; 3],
    pub q1: [f64; 3],
    /// Rotary joints A, B, C at the ends, degrees (0 where the machine has none); they move
    /// linearly along the piece, like every joint of a Cartesian machine.
    pub rot0: [f64; 3],
    pub rot1: [f64; 3],
    /// Path length, the distance the feed rate applies to ([`path_length`]): mm, or degrees
    /// for a move of the rotary axes alone.
    pub length: f64,
    /// Length of the whole piece this is part of: a live command may cut a piece, which
    /// shortens `length` but not the corner the piece makes with the next one.
    pub whole: f64,
    /// Requested path speed, mm/s (`INFINITY` for rapids: joint limits only), with the
    /// overrides applied.
    pub speed: f64,
    /// The feed override scales `speed` (a feed or arc while M48 allows overrides).
    pub feed_scaled: bool,
    /// The machine must be at rest when this piece starts (G61, after dwell or sync).
    pub stop_before: bool,
    /// Corner blending tolerance at the start of this piece, mm.
    pub deviation: f64,
}

/// What the planner receives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Item {
    Move(Move),
    Dwell {
        line: u32,
        seconds: f64,
    },
    /// A non-motion op that needs the machine at rest (spindle, tool change, M0, end).
    Sync {
        line: u32,
        pause: bool,
    },
}

/// Run-time adjustments applied while reading the program.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overrides {
    /// Feed override factor (1.0 = 100 %).
    pub feed: f64,
    /// Rapid override factor (1.0 = 100 %).
    pub rapid: f64,
}

impl Default for Overrides {
    fn default() -> Self {
        Overrides {
            feed: 1.0,
            rapid: 1.0,
        }
    }
}

/// The parametric geometry of the canon op being cut into pieces.
#[derive(Clone, Copy, Debug)]
enum MovePath {
    Line {
        a: [f64; 3],
        b: [f64; 3],
    },
    /// An arc or helix of the arc module, its radius running to `r1` at the end; the helix
    /// lies in the arc's own frame, turned by `rotation` degrees about Z from the machine's.
    Arc {
        helix: Helix,
        r1: f64,
        rotation: f64,
    },
}

impl MovePath {
    fn point(&self, f: f64) -> [f64; 3] {
        match *self {
            MovePath::Line { a, b } => lerp3(a, b, f),
            MovePath::Arc {
                helix,
                r1,
                rotation,
            } => from_arc_frame(helix.spiral_point_at(f, r1), rotation),
        }
    }
}

/// The distance the feed rate applies to, as LinuxCNC reads F (G-code overview, "Feed
/// Rate"): when any of X, Y, Z moves, F is mm/min along the XYZ path and the rotary axes
/// start and stop with it, so the length is the XYZ distance alone; otherwise the move is
/// pure rotary and F is in degrees per minute in the ABC "pseudo-Cartesian" space, so the
/// length is √(ΔA² + ΔB² + ΔC²) in degrees. A mixed G1 X10 A90 F600 thus takes
/// 10 mm / 600 mm/min = 1 s whatever A does (unless A's own rate limit slows it), and
/// G1 A90 F600 takes 90° / 600 °/min = 9 s.
pub(crate) fn path_length(a: [f64; 3], b: [f64; 3], ra: [f64; 3], rb: [f64; 3]) -> f64 {
    let linear = dist3(a, b);
    if linear >= 1e-9 {
        linear
    } else {
        dist3(ra, rb)
    }
}

/// The point at fraction `f` from `a` to `b`.
pub fn lerp3(a: [f64; 3], b: [f64; 3], f: f64) -> [f64; 3] {
    [
        a[0] + (b[0] - a[0]) * f,
        a[1] + (b[1] - a[1]) * f,
        a[2] + (b[2] - a[2]) * f,
    ]
}

pub(crate) fn dist3(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Distance from `p` to the segment a–b.
pub(crate) fn dist_to_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1] + (p[2] - a[2]) * d[2]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist3(p, lerp3(a, b, t))
}

/// The op being cut: its shape, how many chords, and how far the cutting has gone.
struct Current {
    line: u32,
    op: u64,
    kind: MoveKind,
    shape: MovePath,
    chords: u64,
    chord: u64,
    /// Programmed speed before overrides.
    speed: f64,
    feed_scaled: bool,
    /// Rotary joints at the op's start and end, degrees.
    rot_a: [f64; 3],
    rot_b: [f64; 3],
    /// Sub-piece cursor inside the current chord (non-linear kinematics only).
    sub_from: f64,
    sub_step: f64,
    first: bool,
    /// How the junction at the op's start is passed: the previous op's rule ([`EndRule`]).
    start_rule: EndRule,
    /// Deviation at the corners between its own chords.
    chord_deviation: f64,
}

/// How a programmed move's end is passed, fixed when the move is issued: LinuxCNC's planner
/// gives each move the termination condition in force when it was queued and applies it at
/// that move's end, so `G64 … G1 … G61.1 G1 …` blends the first corner and stops after the
/// second move. The mode, and the corner deviation at that end (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct EndRule {
    mode: PathControlMode,
    deviation: f64,
}

/// The lazy canon → pieces stream.
pub(crate) struct MoveStream<'p, I> {
    ops: I,
    profile: &'p Profile,
    kin: AnyKinematics,
    pos: [f64; 3],
    q: [f64; 3],
    /// Rotary joints, degrees (counting whole turns: a wrapping axis never unwinds).
    rot: [f64; 3],
    feed: f64,
    inverse_time: bool,
    /// G95: `feed` is mm per spindle revolution.
    per_rev: bool,
    mode: PathControlMode,
    tolerance: f64,
    overrides: Overrides,
    override_enabled: bool,
    stop_next: bool,
    op_count: u64,
    current: Option<Current>,
    failed: bool,
    /// Spindle speed (rev/min) of the last S word.
    spindle_rpm: f64,
    /// Inside G33 / G33.1 / G76: mm per spindle revolution along the path.
    sync_pitch: Option<f64>,
    /// The way back out of a rigid tap (G33.1): its line and the point it returns to.
    tap_return: Option<(u32, [f64; 3])>,
    /// The way back out of a tap is under way: the move after it starts from rest.
    after_tap: bool,
    /// The G5x origin, the G92 offset and the tool length offset in force, to quote a
    /// position in the program's own coordinates; `origin` is their sum, `None` while the
    /// XY plane is rotated (G10 L2 R), where a plain difference would mislead.
    offsets: [[f64; 3]; 3],
    origin: Option<[f64; 3]>,
    /// The end rule of the last programmed move: the next move's start junction.
    end_rule: EndRule,
}

impl<'p, I: Iterator<Item = Canon>> MoveStream<'p, I> {
    pub(crate) fn new(
        ops: I,
        profile: &'p Profile,
        overrides: Overrides,
    ) -> Result<Self, MotionError> {
        let kin = crate::kinematics::for_profile(profile);
        let q = kin
            .joints(profile.start)
            .map_err(|why| MotionError::Unreachable {
                line: 0,
                x: profile.start[0],
                y: profile.start[1],
                why,
            })?;
        Ok(MoveStream {
            ops,
            profile,
            kin,
            pos: profile.start,
            q,
            rot: [0.0; 3],
            feed: profile.default_feed,
            inverse_time: false,
            per_rev: false,
            mode: PathControlMode::Continuous,
            tolerance: 0.0,
            overrides,
            override_enabled: true,
            stop_next: true,
            op_count: 0,
            current: None,
            failed: false,
            spindle_rpm: 0.0,
            sync_pitch: None,
            offsets: [[0.0; 3]; 3],
            origin: Some([0.0; 3]),
            tap_return: None,
            after_tap: false,
            end_rule: EndRule {
                mode: PathControlMode::Continuous,
                deviation: profile.junction_deviation,
            },
        })
    }

    /// A new feed override for every piece not yet produced (live override).
    pub(crate) fn set_feed_override(&mut self, factor: f64) {
        self.overrides.feed = factor;
    }

    /// Joint position at the profile's start point.
    pub(crate) fn start_joints(&self) -> [f64; 3] {
        self.q
    }

    pub(crate) fn kinematics(&self) -> &AnyKinematics {
        &self.kin
    }

    fn deviation(&self) -> f64 {
        match self.mode {
            PathControlMode::ExactPath => 0.0,
            _ if self.tolerance > 0.0 => self.tolerance.min(self.profile.junction_deviation),
            _ => self.profile.junction_deviation,
        }
    }

    /// Corner deviation between the chords of one arc: one programmed move to LinuxCNC,
    /// which G61/G61.1 never stop inside.
    fn chord_deviation(&self) -> f64 {
        match self.mode {
            PathControlMode::Continuous => self.deviation(),
            _ => self.profile.junction_deviation,
        }
    }

    fn start_op(
        &mut self,
        line: u32,
        kind: MoveKind,
        shape: MovePath,
        rot_b: [f64; 3],
        length: f64,
    ) {
        let speed = match (kind, self.sync_pitch) {
            (MoveKind::Rapid, _) => f64::INFINITY,
            // Synchronised: `pitch` mm per revolution at `spindle_rpm` rev/min, in mm/s.
            (_, Some(pitch)) => pitch * self.spindle_rpm / 60.0,
            _ if self.inverse_time => length * self.feed / 60.0,
            // G95: F mm per revolution at the programmed spindle speed (rev/min).
            _ if self.per_rev => self.feed * self.spindle_rpm / 60.0,
            _ => self.feed,
        };
        // The feed override does not apply to spindle-synchronised motion.
        let feed_scaled =
            kind != MoveKind::Rapid && self.override_enabled && self.sync_pitch.is_none();
        let chords = match shape {
            MovePath::Line { .. } => 1,
            MovePath::Arc { helix, r1, .. } => {
                let r = helix.arc.radius.max(r1);
                chord_count(r, helix.arc.sweep, self.profile.arc_tolerance) as u64
            }
        };
        let start_rule = self.end_rule;
        self.end_rule = EndRule {
            mode: self.mode,
            deviation: self.deviation(),
        };
        self.current = Some(Current {
            line,
            op: self.op_count,
            kind,
            shape,
            chords,
            chord: 0,
            speed,
            feed_scaled,
            rot_a: self.rot,
            rot_b,
            sub_from: 0.0,
            sub_step: 1.0,
            first: true,
            start_rule,
            chord_deviation: self.chord_deviation(),
        });
        self.op_count += 1;
    }

    fn bad(&self, line: u32, what: impl Into<String>) -> MotionError {
        MotionError::BadMove {
            line,
            what: what.into(),
        }
    }

    /// A synchronised move needs a turning spindle: its speed is pitch × rpm; so does a
    /// G95 feed, F × rpm.
    fn check_sync(&self, line: u32) -> Result<(), MotionError> {
        let turning = self.spindle_rpm > 0.0 && self.spindle_rpm.is_finite();
        if self.per_rev && self.sync_pitch.is_none() && !turning {
            return Err(self.bad(
                line,
                "G95 feed per revolution with no spindle speed: its feed is F × spindle speed; set S before it",
            ));
        }
        if self.sync_pitch.is_some() && !(self.spindle_rpm > 0.0 && self.spindle_rpm.is_finite()) {
            return Err(self.bad(
                line,
                "spindle-synchronised move (G33, G33.1 or G76) with no spindle speed: its feed is pitch × spindle speed; set S before it",
            ));
        }
        Ok(())
    }

    /// Reads canon ops until one produces motion or a planner item.
    fn read_op(&mut self) -> Option<Result<Item, MotionError>> {
        if let Some((line, back)) = self.tap_return.take() {
            // Out of a rigid tap the way it went in, from rest (the spindle reverses at the
            // bottom). It is the same canon op: the op index does not advance.
            let length = path_length(self.pos, back, self.rot, self.rot);
            self.stop_next = true;
            self.after_tap = true;
            self.op_count -= 1;
            self.start_op(
                line,
                MoveKind::Feed,
                MovePath::Line {
                    a: self.pos,
                    b: back,
                },
                self.rot,
                length,
            );
            return None;
        }
        // At the top the spindle reverses once more and the tap ends at rest.
        if std::mem::take(&mut self.after_tap) {
            self.stop_next = true;
        }
        loop {
            let c = self.ops.next()?;
            let line = c.line;
            match c.op {
                CanonOp::SetFeedRate(f) => {
                    // F0 is legal (M2 resets it); feed moves check for it below.
                    if !(f.is_finite() && f >= 0.0) {
                        return Some(Err(self.bad(line, format!("feed rate F{f} must be >= 0"))));
                    }
                    // Inverse-time F is 1/min, G95's mm/rev; otherwise mm/min.
                    self.feed = if self.inverse_time || self.per_rev {
                        f
                    } else {
                        f / 60.0
                    };
                }
                CanonOp::SetFeedMode(m) => {
                    self.inverse_time = m == FeedMode::InverseTime;
                    self.per_rev = m == FeedMode::UnitsPerRev;
                }
                CanonOp::SetMotionControlMode { mode, tolerance } => {
                    self.mode = mode;
                    self.tolerance = if tolerance.is_finite() {
                        tolerance.max(0.0)
                    } else {
                        0.0
                    };
                }
                CanonOp::EnableFeedOverride(on) => self.override_enabled = on,
                CanonOp::StraightTraverse { to } | CanonOp::StraightFeed { to } => {
                    let kind = if matches!(c.op, CanonOp::StraightTraverse { .. }) {
                        MoveKind::Rapid
                    } else {
                        MoveKind::Feed
                    };
                    let (b, rb) = match self.target(line, &to) {
                        Ok(b) => b,
                        Err(e) => return Some(Err(e)),
                    };
                    let length = path_length(self.pos, b, self.rot, rb);
                    if kind == MoveKind::Feed && length >= 1e-9 {
                        if let Err(e) = self.check_sync(line) {
                            return Some(Err(e));
                        }
                        if self.sync_pitch.is_none() && self.feed <= 0.0 {
                            return Some(Err(
                                self.bad(line, "feed move with a zero feed rate; set F")
                            ));
                        }
                    }
                    if length < 1e-9 {
                        self.op_count += 1; // keep op indices aligned with the canon stream
                        continue;
                    }
                    self.start_op(line, kind, MovePath::Line { a: self.pos, b }, rb, length);
                    return None;
                }
                CanonOp::ArcFeed {
                    plane,
                    end,
                    center,
                    turns,
                    rotation,
                } => {
                    let (b, rb) = match self.target(line, &end) {
                        Ok(b) => b,
                        Err(e) => return Some(Err(e)),
                    };
                    if let Err(e) = self.check_sync(line) {
                        return Some(Err(e));
                    }
                    if self.sync_pitch.is_none() && self.feed <= 0.0 {
                        return Some(Err(self.bad(line, "arc with a zero feed rate; set F")));
                    }
                    if turns == 0 || !center.iter().all(|v| v.is_finite()) {
                        return Some(Err(
                            self.bad(line, "arc with zero turns or a non-finite centre")
                        ));
                    }
                    // In the arc's own frame, where its plane is `plane`.
                    let (a_local, b_local) =
                        (to_arc_frame(self.pos, rotation), to_arc_frame(b, rotation));
                    let helix = Helix::new(plane, a_local, b_local, center, turns);
                    let r0 = helix.arc.radius;
                    let r1 = plane.project(b_local).distance(helix.arc.center);
                    if r0 < 1e-9 || r1 < 1e-9 {
                        return Some(Err(
                            self.bad(line, "arc centre coincides with its start or end point")
                        ));
                    }
                    let planar = helix.arc.sweep.abs() * 0.5 * (r0 + r1);
                    let length = planar.hypot(helix.axial.1 - helix.axial.0);
                    let shape = MovePath::Arc {
                        helix,
                        r1,
                        rotation,
                    };
                    self.start_op(line, MoveKind::Arc, shape, rb, length);
                    return None;
                }
                CanonOp::Dwell(s) => {
                    if !(s.is_finite() && s >= 0.0) {
                        return Some(Err(self.bad(line, format!("dwell of {s} s"))));
                    }
                    self.stop_next = true;
                    return Some(Ok(Item::Dwell { line, seconds: s }));
                }
                CanonOp::ProgramStop | CanonOp::OptionalProgramStop => {
                    self.stop_next = true;
                    return Some(Ok(Item::Sync { line, pause: true }));
                }
                CanonOp::StartSpeedFeedSync { pitch } => {
                    if !(pitch > 0.0 && pitch.is_finite()) {
                        return Some(Err(self.bad(
                            line,
                            format!("spindle-synchronised pitch {pitch} mm/rev must be > 0"),
                        )));
                    }
                    // Synchronised motion waits for the spindle's index pulse: from rest.
                    if self.sync_pitch.is_none() {
                        self.stop_next = true;
                    }
                    self.sync_pitch = Some(pitch);
                }
                CanonOp::StopSpeedFeedSync => self.sync_pitch = None,
                CanonOp::RigidTap { to } => {
                    let (b, _) = match self.target(line, &to) {
                        Ok(b) => b,
                        Err(e) => return Some(Err(e)),
                    };
                    if self.sync_pitch.is_none() {
                        return Some(Err(
                            self.bad(line, "rigid tap outside spindle synchronisation")
                        ));
                    }
                    if let Err(e) = self.check_sync(line) {
                        return Some(Err(e));
                    }
                    // Rotary axes do not take part in a tap.
                    let length = path_length(self.pos, b, self.rot, self.rot);
                    if length < 1e-9 {
                        self.op_count += 1;
                        continue;
                    }
                    self.tap_return = Some((line, self.pos));
                    self.start_op(
                        line,
                        MoveKind::Feed,
                        MovePath::Line { a: self.pos, b },
                        self.rot,
                        length,
                    );
                    return None;
                }
                CanonOp::SetSpindleSpeed(s) => {
                    self.spindle_rpm = s;
                    self.stop_next = true;
                    return Some(Ok(Item::Sync { line, pause: false }));
                }
                CanonOp::StartSpindle(_)
                | CanonOp::StopSpindle
                | CanonOp::OrientSpindle { .. }
                | CanonOp::WaitOrientComplete(_)
                | CanonOp::ChangeTool(_)
                | CanonOp::ProgramEnd => {
                    self.stop_next = true;
                    return Some(Ok(Item::Sync { line, pause: false }));
                }
                CanonOp::SetG5xOffset { offset, .. } => self.set_offset(0, offset.to_array()),
                CanonOp::SetG92Offset(p) => self.set_offset(1, p.to_array()),
                CanonOp::UseToolLengthOffset(p) => self.set_offset(2, p.to_array()),
                CanonOp::SetXyRotation(r) => {
                    self.origin = (r.abs() < 1e-12).then(|| self.origin_sum());
                }
                _ => {}
            }
        }
    }

    /// One of the offsets changed (0 G5x, 1 G92, 2 tool length).
    fn set_offset(&mut self, which: usize, v: [f64; 6]) {
        self.offsets[which] = [v[0], v[1], v[2]];
        if self.origin.is_some() {
            self.origin = Some(self.origin_sum());
        }
    }

    fn origin_sum(&self) -> [f64; 3] {
        std::array::from_fn(|i| self.offsets.iter().map(|o| o[i]).sum())
    }

    /// The XYZ end point and the rotary joints' end values of a move to `to`. A rotary axis
    /// the machine does not have must stay where it is.
    fn target(&self, line: u32, to: &Pos) -> Result<([f64; 3], [f64; 3]), MotionError> {
        let v = to.to_array();
        if !v.iter().all(|x| x.is_finite()) {
            return Err(self.bad(line, "non-finite coordinate"));
        }
        let rot = [v[3], v[4], v[5]];
        for (i, axis) in ["A", "B", "C"].iter().enumerate() {
            let Some(r) = &self.profile.rotary[i] else {
                if (rot[i] - self.rot[i]).abs() > 1e-9 {
                    return Err(MotionError::MissingJoint {
                        line,
                        axis: format!("rotary axis {axis}"),
                    });
                }
                continue;
            };
            if let (false, Some([lo, hi])) = (r.wrap, r.joint.limits) {
                if rot[i] < lo - 1e-9 || rot[i] > hi + 1e-9 {
                    return Err(self.bad(
                        line,
                        format!("rotary axis {axis} would reach {:.4}°, outside its limits [{lo:.4}, {hi:.4}]", rot[i]),
                    ));
                }
            }
        }
        Ok(([v[0], v[1], v[2]], rot))
    }

    /// Validates one piece end: travel, reachability, joint existence and joint limits.
    fn admit(&self, line: u32, p: [f64; 3], q_prev: [f64; 3]) -> Result<[f64; 3], MotionError> {
        for (i, axis) in ['X', 'Y', 'Z'].iter().enumerate() {
            let [lo, hi] = self.profile.travel[i];
            // A hair of slack so arcs ending on the limit pass despite rounding.
            if p[i] < lo - 1e-7 || p[i] > hi + 1e-7 {
                if i == 2 && self.profile.joints[2].is_none() {
                    return Err(MotionError::MissingJoint {
                        line,
                        axis: "Z".into(),
                    });
                }
                return Err(MotionError::SoftLimit {
                    line,
                    axis: *axis,
                    value: p[i],
                    program: self.origin.map(|o| p[i] - o[i]),
                    min: lo,
                    max: hi,
                });
            }
        }
        let q = self
            .kin
            .joints_near(p, q_prev)
            .map_err(|why| MotionError::Unreachable {
                line,
                x: p[0],
                y: p[1],
                why,
            })?;
        for (i, j) in self.profile.joints.iter().enumerate() {
            if let Some(j) = j {
                if let Some([lo, hi]) = j.limits {
                    if q[i] < lo - 1e-9 || q[i] > hi + 1e-9 {
                        return Err(self.bad(
                            line,
                            format!(
                                "joint {} would reach {:.4}, outside its limits [{lo:.4}, {hi:.4}]",
                                j.name, q[i]
                            ),
                        ));
                    }
                }
            } else if (q[i] - q_prev[i]).abs() > 1e-9 {
                let name = self.profile.kinematics.joint_names()[i];
                return Err(MotionError::MissingJoint {
                    line,
                    axis: name.to_uppercase(),
                });
            }
        }
        Ok(q)
    }

    /// Next piece of the current op, or `None` when it is finished.
    fn next_piece(&mut self) -> Option<Result<Move, MotionError>> {
        let linear = self.kin.is_linear();
        let cur = self.current.as_mut()?;
        if cur.chord >= cur.chords {
            self.current = None;
            return None;
        }
        let (f0, f1) = (
            cur.chord as f64 / cur.chords as f64,
            (cur.chord + 1) as f64 / cur.chords as f64,
        );
        let (ca, cb) = (
            cur.shape.point(f0),
            if cur.chord + 1 == cur.chords {
                cur.shape.point(1.0)
            } else {
                cur.shape.point(f1)
            },
        );
        let factor = match (cur.kind, cur.feed_scaled) {
            (MoveKind::Rapid, _) => self.overrides.rapid,
            (_, true) => self.overrides.feed,
            _ => 1.0,
        };
        let (line, op, kind, speed, first) =
            (cur.line, cur.op, cur.kind, cur.speed * factor, cur.first);
        let (rot_a, rot_b) = (cur.rot_a, cur.rot_b);
        let feed_scaled = cur.feed_scaled;
        let (start_rule, chord_deviation) = (cur.start_rule, cur.chord_deviation);
        cur.first = false;
        // Fraction of the op where this piece ends: the rotary joints follow it linearly.
        let (a, b, f_end) = if linear {
            cur.chord += 1;
            (ca, cb, f1)
        } else {
            // Cut the chord so joint-linear motion stays within half the path tolerance
            // (the checker verifies the full tolerance with denser sampling).
            let from = cur.sub_from;
            let pa = lerp3(ca, cb, from);
            let chord_len = dist3(ca, cb);
            let tol = self.profile.path_tolerance;
            let min_step = (tol * 1e-3 / chord_len.max(1e-12)).min(1.0);
            let mut step = (cur.sub_step * 2.0).min(1.0 - from);
            let q_from = self.q;
            if from == 0.0 {
                if let Err(why) = self.kin.check_line(ca, cb) {
                    self.failed = true;
                    return Some(Err(MotionError::Unreachable {
                        line,
                        x: ca[0],
                        y: ca[1],
                        why,
                    }));
                }
            }
            loop {
                let to = from + step;
                let pb = if to >= 1.0 - 1e-12 {
                    cb
                } else {
                    lerp3(ca, cb, to)
                };
                let ok = match self.kin.joints_near(pb, q_from) {
                    Ok(qb) => joint_lerp_error(&self.kin, q_from, qb, pa, pb) <= 0.5 * tol,
                    Err(_) => false,
                };
                if ok || step <= min_step {
                    break;
                }
                step *= 0.5;
            }
            let cur = self.current.as_mut().expect("current op");
            let to = from + step;
            let pb = if to >= 1.0 - 1e-12 {
                cb
            } else {
                lerp3(ca, cb, to)
            };
            if to >= 1.0 - 1e-12 {
                cur.chord += 1;
                cur.sub_from = 0.0;
            } else {
                cur.sub_from = to;
            }
            cur.sub_step = step;
            (pa, pb, f0 + (f1 - f0) * to.min(1.0))
        };
        let rot1 = if f_end >= 1.0 - 1e-12 {
            rot_b
        } else {
            lerp3(rot_a, rot_b, f_end)
        };
        let a = if first { self.pos } else { a };
        let q1 = match self.admit(line, b, self.q) {
            Ok(q) => q,
            Err(e) => {
                self.failed = true;
                return Some(Err(e));
            }
        };
        let m = Move {
            line,
            op,
            kind,
            start: a,
            end: b,
            q0: self.q,
            q1,
            rot0: self.rot,
            rot1,
            length: path_length(a, b, self.rot, rot1),
            whole: path_length(a, b, self.rot, rot1),
            speed,
            feed_scaled,
            // G61.1 stops at the ends of programmed moves, not between an arc's chords.
            stop_before: std::mem::take(&mut self.stop_next)
                || (first && start_rule.mode == PathControlMode::ExactStop),
            deviation: if first {
                start_rule.deviation
            } else {
                chord_deviation
            },
        };
        self.pos = b;
        self.q = q1;
        self.rot = rot1;
        Some(Ok(m))
    }
}

/// Largest distance from the Cartesian segment pa–pb of the path traced when the joints
/// move linearly from qa to qb.
pub(crate) fn joint_lerp_error(
    kin: &AnyKinematics,
    qa: [f64; 3],
    qb: [f64; 3],
    pa: [f64; 3],
    pb: [f64; 3],
) -> f64 {
    [0.25, 0.5, 0.75]
        .iter()
        .map(|&f| dist_to_segment(kin.forward(lerp3(qa, qb, f)), pa, pb))
        .fold(0.0, f64::max)
}

impl<I: Iterator<Item = Canon>> Iterator for MoveStream<'_, I> {
    type Item = Result<Item, MotionError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        loop {
            if self.current.is_some() {
                match self.next_piece() {
                    Some(Ok(m)) if m.length < 1e-12 => continue,
                    Some(r) => return Some(r.map(Item::Move)),
                    None => continue,
                }
            }
            match self.read_op() {
                Some(Err(e)) => {
                    self.failed = true;
                    return Some(Err(e));
                }
                Some(Ok(item)) => return Some(Ok(item)),
                None if self.current.is_some() => continue,
                None => return None,
            }
        }
    }
}
