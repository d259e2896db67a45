//! Canonical machining operations.
//!
//! ```
//! use oficina_canon::Summarizer;
//! use oficina_canon::{CanonOp, Pos};
//!
//! // A 3-4-5 feed move at 600 mm/min, summarised without a machine model.
//! let mut s = Summarizer::new(Pos::ZERO, [3000.0; 3]);
//! s.add(&CanonOp::SetFeedRate(600.0));
//! s.add(&CanonOp::StraightFeed { to: Pos::xyz(30.0, 40.0, 0.0) });
//! let summary = s.finish();
//! assert_eq!(summary.feed_length, 50.0);
//! assert_eq!(summary.feed_rate_seconds, 5.0);
//! ```
//!
//! The interpreter turns G-code text into a stream of [`Canon`] records; the planner, the
//! simulators, the estimators and the machine links consume only this stream, never text.
//! The idea and the names follow LinuxCNC's canonical machining functions.
//!
//! Conventions: every length is in millimetres and in **machine coordinates** (all work
//! offsets, G92 offsets, rotation and tool length offsets already applied), rotary axes in
//! degrees, feeds in mm/min (or 1/min in inverse time mode), times in seconds. The offset
//! records are still emitted so that a printer can reconstruct program coordinates.

mod spline;
mod summary;

pub use spline::{flatten, Nurbs};
pub use summary::{Extents, MoveBound, Summarizer, Summary};

/// A point in the six-axis machine space: X Y Z in mm, A B C in degrees.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pos {
    /// X, mm.
    pub x: f64,
    /// Y, mm.
    pub y: f64,
    /// Z, mm.
    pub z: f64,
    /// A, degrees.
    pub a: f64,
    /// B, degrees.
    pub b: f64,
    /// C, degrees.
    pub c: f64,
}

impl Pos {
    /// The origin.
    pub const ZERO: Pos = Pos {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        a: 0.0,
        b: 0.0,
        c: 0.0,
    };

    /// A point with only linear axes set (mm).
    pub fn xyz(x: f64, y: f64, z: f64) -> Pos {
        Pos {
            x,
            y,
            z,
            ..Pos::ZERO
        }
    }

    /// X Y Z A B C in that order.
    pub fn to_array(self) -> [f64; 6] {
        [self.x, self.y, self.z, self.a, self.b, self.c]
    }

    /// From X Y Z A B C in that order.
    pub fn from_array(v: [f64; 6]) -> Pos {
        Pos {
            x: v[0],
            y: v[1],
            z: v[2],
            a: v[3],
            b: v[4],
            c: v[5],
        }
    }

    /// Euclidean distance of the linear axes.
    pub fn dist_xyz(&self, o: &Pos) -> f64 {
        ((self.x - o.x).powi(2) + (self.y - o.y).powi(2) + (self.z - o.z).powi(2)).sqrt()
    }
}

/// The plane of circular motion (G17 / G18 / G19): the one definition, in the arc module.
/// `Plane::axes()` indexes [`Pos::to_array`] as (first in-plane, second in-plane, normal).
pub use oficina_geom::Plane;

/// Length units of the program.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Units {
    /// Millimetres (G21).
    #[default]
    Mm,
    /// Inches (G20).
    Inch,
}

impl Units {
    /// Millimetres per unit.
    pub fn mm(self) -> f64 {
        match self {
            Units::Mm => 1.0,
            Units::Inch => 25.4,
        }
    }
}

/// How the feed rate is read (G93 / G94 / G95).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FeedMode {
    /// G94: feed is mm/min.
    #[default]
    UnitsPerMinute,
    /// G93: feed is 1/min, the move takes 1/F minutes.
    InverseTime,
    /// G95: feed is mm per spindle revolution.
    UnitsPerRev,
}

/// LinuxCNC's path control mode (G61, G61.1, G64), carried by `SetMotionControlMode`; the
/// motion modes G0–G3 are the interpreter's modal state, not this.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum PathControlMode {
    /// G61.1: stop exactly at every corner.
    ExactStop,
    /// G61: follow the path exactly, may slow at corners.
    ExactPath,
    /// G64 P Q: blend corners within `tolerance` mm (0 = as fast as possible).
    #[default]
    Continuous,
}

/// Spindle rotation direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpindleDir {
    /// M3.
    Clockwise,
    /// M4.
    CounterClockwise,
}

/// How the spindle speed is read (G96 / G97).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum SpindleMode {
    /// G97: S is the spindle speed, rev/min.
    #[default]
    Rpm,
    /// G96: S is the cutting surface speed (m/min under G21, ft/min under G20); the
    /// control turns the spindle at S / (2π·|X|) and at most `max_rpm` (G96's D word).
    SurfaceSpeed {
        /// The D word, rev/min; `None`: no limit.
        max_rpm: Option<f64>,
    },
}

/// How M19 turns the spindle to its orientation angle (its P word).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum OrientDir {
    /// P0: the smaller angular movement.
    #[default]
    Shortest,
    /// P1: always clockwise (M3's direction).
    Clockwise,
    /// P2: always counter-clockwise (M4's direction).
    CounterClockwise,
}

/// One canonical operation. Lengths in mm, machine coordinates.
#[derive(Clone, Debug, PartialEq)]
pub enum CanonOp {
    /// G20 / G21: the program's length units.
    UseLengthUnits(Units),
    /// Work coordinate system `index` (1 = G54 … 9 = G59.3) is active with this offset.
    SetG5xOffset {
        /// 1 = G54 … 9 = G59.3.
        index: u8,
        /// The system's origin in machine coordinates.
        offset: Pos,
    },
    /// G92 offset in force.
    SetG92Offset(Pos),
    /// Rotation of the XY plane of the active coordinate system, degrees.
    SetXyRotation(f64),
    /// G17 / G18 / G19.
    SelectPlane(Plane),
    /// Feed rate: mm/min (G94), 1/min (G93) or mm per revolution (G95).
    SetFeedRate(f64),
    /// How the feed rate is read.
    SetFeedMode(FeedMode),
    /// G61 / G61.1 / G64 with its tolerance.
    SetMotionControlMode {
        /// Exact stop, exact path or blending.
        mode: PathControlMode,
        /// G64 P: blending tolerance, mm (0 = as fast as possible).
        tolerance: f64,
    },
    /// G64 Q: LinuxCNC's naive-CAM collinearity tolerance, mm.
    SetNaivecamTolerance(f64),
    /// G0: rapid to `to`.
    StraightTraverse {
        /// End point, machine coordinates.
        to: Pos,
    },
    /// G1: straight feed to `to`.
    StraightFeed {
        /// End point, machine coordinates.
        to: Pos,
    },
    /// Arc (or helix) in `plane` ending at `end`, about `center` given as the two in-plane
    /// coordinates (first, second); `turns` > 0 is counter-clockwise, < 0 clockwise, and its
    /// magnitude counts full turns plus the partial one (1 = less than one full turn).
    ///
    /// `rotation` (degrees) turns the arc's plane about the machine Z axis: an XZ or YZ arc
    /// programmed under `G10 L2 … R` lies in a vertical plane that is not a machine plane.
    /// Then `plane` and `center` hold in the arc's own frame, the machine frame turned by
    /// `rotation` about Z ([`to_arc_frame`] / [`from_arc_frame`]). 0 for every other arc.
    ArcFeed {
        /// Plane of the arc (in its own frame when `rotation` ≠ 0).
        plane: Plane,
        /// End point, machine coordinates.
        end: Pos,
        /// Centre, the two in-plane coordinates.
        center: [f64; 2],
        /// Direction and turns (see above).
        turns: i32,
        /// Rotation of the arc's plane about machine Z, degrees.
        rotation: f64,
    },
    /// G5, G5.1, G5.2 … G5.3: a spline in the XY plane, LinuxCNC's `NURBS_FEED` call over
    /// `control_points` points (the start point included). The curve itself is the next
    /// `segments` [`CanonOp::StraightFeed`]s of the same line, points on it within the
    /// program's G64 P tolerance (under G93 each preceded by its own inverse-time
    /// [`CanonOp::SetFeedRate`]): whatever moves the machine follows them and may pass over
    /// this operation; whatever prints canonical calls prints it in their place.
    NurbsFeed {
        /// Control points of the curve, its start point included.
        control_points: u32,
        /// How many straight feeds follow that trace the curve.
        segments: u32,
    },
    /// The same spline kept whole, as rs274's `NURBS_FEED` is: only in the operations of a
    /// run that asks for it (`RunOptions::whole_splines` of the interpreter), for readers
    /// that need no points on the curve (printing rs274's text, counting). Whatever moves
    /// along it traces it with [`Nurbs::trace`] into the [`CanonOp::NurbsFeed`] and straight
    /// feeds above, the ones every other run gets in its place.
    Spline(Box<Nurbs>),
    /// G38.2–G38.5: a straight probing move towards `to`, LinuxCNC's `TURN_PROBE_ON`,
    /// `STRAIGHT_PROBE`, `TURN_PROBE_OFF`. Oficina's machines have no probe input, so the
    /// probe never trips: the motion itself is the next `feeds` [`CanonOp::StraightFeed`]s of
    /// the same line (to `to`, then back to where the probe leaves the tool). Whatever moves
    /// the machine follows them and may pass over this operation; whatever prints canonical
    /// calls prints it in their place.
    StraightProbe {
        /// The probe's target, machine coordinates.
        to: Pos,
        /// How many straight feeds follow that make the probing move.
        feeds: u32,
    },
    /// G4: wait this many seconds.
    Dwell(f64),
    /// S: spindle speed, rpm (under [`SpindleMode::SurfaceSpeed`], the surface speed).
    SetSpindleSpeed(f64),
    /// G96 / G97: how [`CanonOp::SetSpindleSpeed`] is read from here on.
    SetSpindleMode(SpindleMode),
    /// M3 / M4.
    StartSpindle(SpindleDir),
    /// M5.
    StopSpindle,
    /// M19 R P: turn the spindle to `angle` degrees and hold it there; the spindle no
    /// longer turns (M3/M4 start it again).
    OrientSpindle {
        /// Orientation angle, degrees.
        angle: f64,
        /// Which way the spindle turns to it.
        dir: OrientDir,
    },
    /// M19 Q: wait up to this many seconds for the orientation to complete.
    WaitOrientComplete(f64),
    /// G33 / G33.1 / G76: from here until [`CanonOp::StopSpeedFeedSync`], every feed move
    /// advances `pitch` mm along its own path per spindle revolution, so its speed is
    /// pitch × spindle speed (mm/min) and no feed rate applies.
    StartSpeedFeedSync {
        /// Advance per spindle revolution, mm.
        pitch: f64,
    },
    /// Ends [`CanonOp::StartSpeedFeedSync`].
    StopSpeedFeedSync,
    /// G33.1 rigid tapping: a synchronised feed from the current point to `to`, the spindle
    /// reversed there, and the same path back; the move ends where it started.
    RigidTap {
        /// Bottom of the tap, machine coordinates.
        to: Pos,
    },
    /// M7.
    MistOn,
    /// M9 (mist off).
    MistOff,
    /// M8.
    FloodOn,
    /// M9 (flood off).
    FloodOff,
    /// T: the tool to load next.
    SelectTool(u32),
    /// M6: load this tool.
    ChangeTool(u32),
    /// Tool length offset (X, Y, Z… components, mm).
    UseToolLengthOffset(Pos),
    /// M50: feed override allowed or not.
    EnableFeedOverride(bool),
    /// M51: spindle speed override allowed or not.
    EnableSpeedOverride(bool),
    /// M52: adaptive feed on or off.
    EnableAdaptiveFeed(bool),
    /// M53: feed hold allowed or not.
    EnableFeedHold(bool),
    /// M0
    ProgramStop,
    /// M1
    OptionalProgramStop,
    /// M2 / M30
    ProgramEnd,
    /// `(MSG,…)`: shown to the operator.
    Message(String),
    /// A comment in the program.
    Comment(String),
}

/// A machine point (X, Y, Z) in the frame of an arc turned by `rotation` degrees about the
/// machine Z axis: the point turned by −rotation. Identity for 0.
pub fn to_arc_frame(p: [f64; 3], rotation: f64) -> [f64; 3] {
    turn_about_z(p, -rotation)
}

/// The inverse of [`to_arc_frame`]: a point of the arc's frame in machine coordinates.
pub fn from_arc_frame(p: [f64; 3], rotation: f64) -> [f64; 3] {
    turn_about_z(p, rotation)
}

fn turn_about_z(p: [f64; 3], degrees: f64) -> [f64; 3] {
    if degrees == 0.0 {
        return p;
    }
    let (s, c) = degrees.to_radians().sin_cos();
    [p[0] * c - p[1] * s, p[0] * s + p[1] * c, p[2]]
}

/// A canonical operation tagged with the 1-based source line it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Canon {
    /// 1-based source line.
    pub line: u32,
    /// The operation.
    pub op: CanonOp,
}

impl Canon {
    /// The same operation with every position moved by `d` (X, Y, Z, mm): straight moves'
    /// ends, a whole spline's control points and end, an arc's end and centre (the centre given in the arc's frame, so `d` is turned
    /// into it first). Operations without a position are unchanged.
    pub fn translated(&self, d: [f64; 3]) -> Canon {
        let shift = |mut p: Pos| {
            p.x += d[0];
            p.y += d[1];
            p.z += d[2];
            p
        };
        let op = match &self.op {
            CanonOp::StraightTraverse { to } => CanonOp::StraightTraverse { to: shift(*to) },
            CanonOp::StraightFeed { to } => CanonOp::StraightFeed { to: shift(*to) },
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                rotation,
            } => {
                let framed = to_arc_frame(d, *rotation);
                let (a0, a1, _) = plane.axes();
                let mut center = *center;
                for (i, axis) in [a0, a1].into_iter().enumerate() {
                    center[i] += framed[axis];
                }
                CanonOp::ArcFeed {
                    plane: *plane,
                    end: shift(*end),
                    center,
                    turns: *turns,
                    rotation: *rotation,
                }
            }
            CanonOp::Spline(n) => {
                let mut n = n.clone();
                for p in &mut n.points {
                    p[0] += d[0];
                    p[1] += d[1];
                }
                n.end = shift(n.end);
                CanonOp::Spline(n)
            }
            other => other.clone(),
        };
        Canon {
            line: self.line,
            op,
        }
    }
}

impl CanonOp {
    /// True for operations that move the machine.
    pub fn is_motion(&self) -> bool {
        matches!(
            self,
            CanonOp::StraightTraverse { .. }
                | CanonOp::StraightFeed { .. }
                | CanonOp::ArcFeed { .. }
                | CanonOp::RigidTap { .. }
                | CanonOp::Spline(_)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Translating moves every point by `d`: an arc's end and centre stay the same distance
    /// apart in the arc's own frame, and the centre, taken back to the machine, moves by `d`.
    #[test]
    fn a_translated_arc_keeps_its_radius_vector_in_its_frame() {
        let d = [3.0, -2.0, 0.5];
        for rotation in [0.0, 30.0, 90.0] {
            for plane in [Plane::XY, Plane::XZ, Plane::YZ] {
                let arc = Canon {
                    line: 7,
                    op: CanonOp::ArcFeed {
                        plane,
                        end: Pos::xyz(4.0, 1.0, -1.0),
                        center: [1.5, -0.5],
                        turns: 1,
                        rotation,
                    },
                };
                let moved = arc.translated(d);
                let radius = |c: &Canon| match &c.op {
                    CanonOp::ArcFeed { end, center, .. } => {
                        let e = to_arc_frame([end.x, end.y, end.z], rotation);
                        let (a0, a1, _) = plane.axes();
                        [e[a0] - center[0], e[a1] - center[1]]
                    }
                    _ => unreachable!(),
                };
                let (r0, r1) = (radius(&arc), radius(&moved));
                assert!(
                    (r0[0] - r1[0]).abs() < 1e-12 && (r0[1] - r1[1]).abs() < 1e-12,
                    "{plane:?} at {rotation}°: {r0:?} / {r1:?}"
                );
                assert_eq!(moved.line, 7);
            }
        }
        let feed = Canon {
            line: 1,
            op: CanonOp::StraightFeed {
                to: Pos::xyz(1.0, 1.0, 1.0),
            },
        };
        match feed.translated(d).op {
            CanonOp::StraightFeed { to } => assert_eq!([to.x, to.y, to.z], [4.0, -1.0, 1.5]),
            other => panic!("{other:?}"),
        }
    }
}
