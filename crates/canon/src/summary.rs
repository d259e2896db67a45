//! What a program does, at a glance: extents per axis (rapid and feed apart), path lengths,
//! tools, and a plain feed-rate time estimate. Built by folding the canon stream, so it works
//! on programs of any length in constant memory.

use crate::{CanonOp, FeedMode, Plane, Pos};
use oficina_geom::Helix;

/// Axis-aligned box of the linear axes; empty until the first point is added.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extents {
    /// Smallest X, Y, Z, mm.
    pub min: [f64; 3],
    /// Largest X, Y, Z, mm.
    pub max: [f64; 3],
}

impl Default for Extents {
    fn default() -> Self {
        Extents {
            min: [f64::INFINITY; 3],
            max: [f64::NEG_INFINITY; 3],
        }
    }
}

impl Extents {
    /// No point added yet.
    pub fn is_empty(&self) -> bool {
        self.min[0] > self.max[0]
    }

    /// Grows the box to hold `p`.
    pub fn add(&mut self, p: [f64; 3]) {
        for i in 0..3 {
            self.min[i] = self.min[i].min(p[i]);
            self.max[i] = self.max[i].max(p[i]);
        }
    }
}

/// What a program does, at a glance (see the module comment).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    /// Where the rapid moves go (their end points and start points). The position before
    /// the program's first move is where the tool happened to be, not the program's: it
    /// counts in neither box.
    pub rapid_extents: Extents,
    /// Where the tool moves while cutting (lines and the whole swept arcs).
    pub feed_extents: Extents,
    /// Rapid path length, mm.
    pub rapid_length: f64,
    /// Feed path length, mm.
    pub feed_length: f64,
    /// Rapid moves.
    pub rapid_moves: u64,
    /// Feed moves, arcs included.
    pub feed_moves: u64,
    /// Arc moves among them.
    pub arcs: u64,
    /// Tools in the order they were first selected or changed to.
    pub tools: Vec<u32>,
    /// Total dwell, seconds.
    pub dwell_seconds: f64,
    /// Feed moves at their programmed feed plus rapids at the machine's top speed, no
    /// acceleration, every move at least as long as its [`MoveBound`]: a lower bound of the
    /// time any planner within those limits takes (the planner's exact estimate replaces it).
    pub feed_rate_seconds: f64,
    /// Feed moves programmed with no usable feed rate (counted, not timed).
    pub untimed_moves: u64,
}

/// The least time, in seconds, any move between two machine points (X, Y, Z mm) can take on
/// a machine, whatever its path: e.g. from the top speed of each joint, as a joint must cover
/// at least the difference of its end values. Rapids take exactly this long in the
/// feed-rate figure; feed moves take at least this long.
pub trait MoveBound {
    /// The least time from `from` to `to`, seconds.
    fn min_seconds(&self, from: [f64; 3], to: [f64; 3]) -> f64;
}

/// X, Y and Z top speeds in mm/min, each axis its own motor (a move takes as long as its
/// slowest axis needs); 0 = no limit known.
impl MoveBound for [f64; 3] {
    fn min_seconds(&self, a: [f64; 3], b: [f64; 3]) -> f64 {
        (0..3)
            .filter(|&i| self[i] > 0.0)
            .map(|i| (b[i] - a[i]).abs() / self[i] * 60.0)
            .fold(0.0, f64::max)
    }
}

/// Folds canon operations into a [`Summary`].
pub struct Summarizer {
    pos: Pos,
    /// A move has been made: `pos` is the program's (before it, the tool's start).
    moved: bool,
    feed: f64,
    feed_mode: FeedMode,
    /// Spindle speed, rev/min, and inside G33/G33.1/G76 the pitch, mm/rev.
    spindle_rpm: f64,
    sync_pitch: Option<f64>,
    /// Straight feeds still to come that make the last spline or probing move: one move
    /// with it.
    part_feeds: u32,
    bound: Box<dyn MoveBound + Send>,
    summary: Summary,
}

impl Summarizer {
    /// `start` is the machine position before the program; `rapid_rates` are the top speeds
    /// of X, Y and Z in mm/min (a rapid takes as long as its slowest axis needs).
    pub fn new(start: Pos, rapid_rates: [f64; 3]) -> Summarizer {
        Summarizer::with_bound(start, Box::new(rapid_rates))
    }

    /// As [`Summarizer::new`], with the machine's own bound on the time of a move (e.g. one
    /// computed in joint space for a machine whose joints are not its axes).
    pub fn with_bound(start: Pos, bound: Box<dyn MoveBound + Send>) -> Summarizer {
        Summarizer {
            pos: start,
            moved: false,
            feed: 0.0,
            feed_mode: FeedMode::UnitsPerMinute,
            spindle_rpm: 0.0,
            sync_pitch: None,
            part_feeds: 0,
            bound,
            summary: Summary::default(),
        }
    }

    /// Folds one more op into the summary.
    pub fn add(&mut self, op: &CanonOp) {
        // A spline kept whole is summed as the feeds that trace it.
        if let CanonOp::Spline(curve) = op {
            curve.trace(|traced| self.add(&traced));
            return;
        }
        self.fold(op);
        self.moved |= matches!(
            op,
            CanonOp::StraightTraverse { .. }
                | CanonOp::StraightFeed { .. }
                | CanonOp::ArcFeed { .. }
                | CanonOp::RigidTap { .. }
        );
    }

    fn fold(&mut self, op: &CanonOp) {
        let s = &mut self.summary;
        match op {
            CanonOp::SetFeedRate(f) => self.feed = *f,
            CanonOp::SetFeedMode(m) => self.feed_mode = *m,
            CanonOp::StraightTraverse { to } => {
                let len = self.pos.dist_xyz(to);
                if self.moved {
                    s.rapid_extents.add(xyz(&self.pos));
                }
                s.rapid_extents.add(xyz(to));
                s.rapid_length += len;
                s.rapid_moves += 1;
                s.feed_rate_seconds += self.bound.min_seconds(xyz(&self.pos), xyz(to));
                self.pos = *to;
            }
            CanonOp::StraightFeed { to } => {
                let len = self.pos.dist_xyz(to);
                if self.moved {
                    s.feed_extents.add(xyz(&self.pos));
                }
                s.feed_extents.add(xyz(to));
                if self.part_feeds > 0 {
                    self.part_feeds -= 1;
                } else {
                    s.feed_moves += 1;
                }
                s.feed_length += len;
                self.time_feed(len, to);
                self.pos = *to;
            }
            // A spline is one programmed move; its length and time are its straight feeds'.
            CanonOp::NurbsFeed { segments, .. } => {
                s.feed_moves += 1;
                self.part_feeds = *segments;
            }
            // So is a probing move (in and back off): its feeds follow.
            CanonOp::StraightProbe { feeds, .. } => {
                s.feed_moves += 1;
                self.part_feeds = *feeds;
            }
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                rotation,
            } => {
                let (len, ext) =
                    arc_length_and_extents(&self.pos, *plane, end, *center, *turns, *rotation);
                let s = &mut self.summary;
                s.feed_extents.add(ext.min);
                s.feed_extents.add(ext.max);
                s.feed_moves += 1;
                s.arcs += 1;
                s.feed_length += len;
                self.time_feed(len, end);
                self.pos = *end;
            }
            // In and back out along the same line: twice its length, ending where it began.
            CanonOp::RigidTap { to } => {
                let len = 2.0 * self.pos.dist_xyz(to);
                s.feed_extents.add(xyz(&self.pos));
                s.feed_extents.add(xyz(to));
                s.feed_moves += 1;
                s.feed_length += len;
                let back = self.pos;
                self.time_feed(len, to);
                self.pos = back;
            }
            CanonOp::SetSpindleSpeed(rpm) => self.spindle_rpm = *rpm,
            CanonOp::StartSpeedFeedSync { pitch } => self.sync_pitch = Some(*pitch),
            CanonOp::StopSpeedFeedSync => self.sync_pitch = None,
            // T selects, M6 changes; grbl programs change by hand at an M0, so both count.
            CanonOp::SelectTool(t) | CanonOp::ChangeTool(t) if !s.tools.contains(t) => {
                s.tools.push(*t);
            }
            CanonOp::Dwell(secs) => {
                s.dwell_seconds += secs;
                s.feed_rate_seconds += secs;
            }
            _ => {}
        }
    }

    /// A feed move of `len` mm from the current point to `to`: at its programmed feed, and
    /// never faster than the machine allows.
    fn time_feed(&mut self, len: f64, to: &Pos) {
        let sync_rate = self.sync_pitch.map(|p| p * self.spindle_rpm);
        let at_feed = match self.feed_mode {
            // Synchronised: pitch (mm/rev) × spindle speed (rev/min) is the feed in mm/min.
            _ if sync_rate.is_some() => match sync_rate {
                Some(rate) if rate > 0.0 => len / rate * 60.0,
                _ => {
                    self.summary.untimed_moves += 1;
                    return;
                }
            },
            FeedMode::InverseTime if self.feed > 0.0 => 60.0 / self.feed,
            FeedMode::UnitsPerMinute if self.feed > 0.0 => len / self.feed * 60.0,
            _ => {
                self.summary.untimed_moves += 1;
                return;
            }
        };
        let least = self.bound.min_seconds(xyz(&self.pos), xyz(to));
        self.summary.feed_rate_seconds += at_feed.max(least);
    }

    /// The summary of every op added.
    pub fn finish(self) -> Summary {
        self.summary
    }
}

fn xyz(p: &Pos) -> [f64; 3] {
    [p.x, p.y, p.z]
}

/// Length of an arc or helix and the box it sweeps (including the quadrant points it passes).
/// The geometry is the arc module's; an arc whose end radius differs a little from its start
/// radius (within the interpreter's tolerance) counts at the mean radius in length and at the
/// larger one in the box, a safe box. An arc turned about Z (`rotation`, degrees) is measured
/// in its own frame; its box is the box of that frame's box turned back (safe, not tight).
pub(crate) fn arc_length_and_extents(
    start: &Pos,
    plane: Plane,
    end: &Pos,
    center: [f64; 2],
    turns: i32,
    rotation: f64,
) -> (f64, Extents) {
    let s = crate::to_arc_frame(xyz(start), rotation);
    let e = crate::to_arc_frame(xyz(end), rotation);
    let mut helix = Helix::new(plane, s, e, center, turns);
    let r0 = helix.arc.radius;
    let r1 = plane.project(e).distance(helix.arc.center);
    let planar = 0.5 * (r0 + r1) * helix.arc.sweep.abs();
    let len = planar.hypot(helix.axial.1 - helix.axial.0);
    helix.arc.radius = r0.max(r1);
    let (lo, hi) = helix.extents();
    let mut ext = Extents::default();
    for p in [s, e, lo, hi] {
        ext.add(p);
    }
    if rotation != 0.0 {
        let local = ext;
        ext = Extents::default();
        for k in 0..8 {
            let pick = |i: usize| {
                if k >> i & 1 == 0 {
                    local.min[i]
                } else {
                    local.max[i]
                }
            };
            ext.add(crate::from_arc_frame([pick(0), pick(1), pick(2)], rotation));
        }
    }
    (len, ext)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn quarter_arc_length_and_box() {
        // From (10,0) CCW about the origin to (0,10): a quarter circle of radius 10.
        let (len, ext) = arc_length_and_extents(
            &Pos::xyz(10.0, 0.0, 0.0),
            Plane::XY,
            &Pos::xyz(0.0, 10.0, 0.0),
            [0.0, 0.0],
            1,
            0.0,
        );
        assert!((len - 10.0 * std::f64::consts::FRAC_PI_2).abs() < 1e-9);
        assert_eq!(ext.max[0], 10.0);
        assert_eq!(ext.max[1], 10.0);
        assert!(ext.min[0].abs() < 1e-9 && ext.min[1].abs() < 1e-9);
    }

    #[test]
    fn clockwise_three_quarter_arc_reaches_negative_quadrants() {
        // CW from (10,0) to (0,10) goes through (0,-10) and (-10,0).
        let (len, ext) = arc_length_and_extents(
            &Pos::xyz(10.0, 0.0, 0.0),
            Plane::XY,
            &Pos::xyz(0.0, 10.0, 0.0),
            [0.0, 0.0],
            -1,
            0.0,
        );
        assert!((len - 10.0 * 1.5 * std::f64::consts::PI).abs() < 1e-9);
        assert!((ext.min[0] + 10.0).abs() < 1e-9 && (ext.min[1] + 10.0).abs() < 1e-9);
    }

    #[test]
    fn full_circle_helix_with_two_turns() {
        let (len, _) = arc_length_and_extents(
            &Pos::xyz(5.0, 0.0, 0.0),
            Plane::XY,
            &Pos::xyz(5.0, 0.0, -3.0),
            [0.0, 0.0],
            2,
            0.0,
        );
        let planar = 2.0 * TAU * 5.0;
        assert!((len - planar.hypot(3.0)).abs() < 1e-9);
    }

    #[test]
    fn feed_rate_estimate_adds_rapids_feeds_and_dwells() {
        let mut s = Summarizer::new(Pos::ZERO, [6000.0, 6000.0, 600.0]);
        // 1 s in X, then 1 s up and 1 s down in Z (its own, slower, top speed).
        for to in [(100.0, 0.0, 0.0), (100.0, 0.0, 10.0), (100.0, 0.0, 0.0)] {
            s.add(&CanonOp::StraightTraverse {
                to: Pos::xyz(to.0, to.1, to.2),
            });
        }
        s.add(&CanonOp::SetFeedRate(600.0));
        s.add(&CanonOp::StraightFeed {
            to: Pos::xyz(100.0, 50.0, 0.0),
        }); // 5 s
        s.add(&CanonOp::Dwell(2.5));
        s.add(&CanonOp::ChangeTool(3));
        let r = s.finish();
        assert!((r.feed_rate_seconds - 10.5).abs() < 1e-9);
        assert_eq!(r.tools, vec![3]);
        assert_eq!(r.rapid_extents.max[0], 100.0);
        assert_eq!(r.feed_extents.min[0], 100.0);
        assert_eq!(r.feed_length, 50.0);
    }

    #[test]
    fn the_start_position_is_not_the_programs_extents() {
        // The tool stands at X-200 Z40 before the program: its first rapid and its first
        // feed begin there, but only where the program goes counts.
        let mut s = Summarizer::new(Pos::xyz(-200.0, 0.0, 40.0), [6000.0; 3]);
        s.add(&CanonOp::StraightTraverse {
            to: Pos::xyz(10.0, 10.0, 5.0),
        });
        s.add(&CanonOp::StraightTraverse {
            to: Pos::xyz(20.0, 10.0, 5.0),
        });
        let r = s.finish();
        assert_eq!(r.rapid_extents.min, [10.0, 10.0, 5.0]);
        assert_eq!(r.rapid_extents.max, [20.0, 10.0, 5.0]);
        // A program that starts cutting at once: the plunge's start is not its box either.
        let mut s = Summarizer::new(Pos::xyz(-200.0, 0.0, 40.0), [6000.0; 3]);
        s.add(&CanonOp::SetFeedRate(100.0));
        for to in [(5.0, 5.0, -1.0), (15.0, 5.0, -1.0)] {
            s.add(&CanonOp::StraightFeed {
                to: Pos::xyz(to.0, to.1, to.2),
            });
        }
        let r = s.finish();
        assert_eq!(r.feed_extents.min, [5.0, 5.0, -1.0]);
        assert_eq!(r.feed_extents.max, [15.0, 5.0, -1.0]);
        assert!(r.rapid_extents.is_empty());
    }

    #[test]
    fn a_spline_is_one_move_as_long_as_the_feeds_that_trace_it() {
        let mut s = Summarizer::new(Pos::ZERO, [6000.0, 6000.0, 600.0]);
        s.add(&CanonOp::SetFeedRate(600.0));
        s.add(&CanonOp::NurbsFeed {
            control_points: 3,
            segments: 2,
        });
        for to in [(30.0, 40.0, 0.0), (30.0, 50.0, 0.0), (40.0, 50.0, 0.0)] {
            s.add(&CanonOp::StraightFeed {
                to: Pos::xyz(to.0, to.1, to.2),
            });
        }
        let r = s.finish();
        assert_eq!(r.feed_moves, 2, "the spline and the feed after it");
        assert_eq!(r.feed_length, 70.0);
        assert!((r.feed_rate_seconds - 7.0).abs() < 1e-9);
    }

    #[test]
    fn synchronised_moves_are_timed_at_pitch_times_spindle_speed() {
        let mut s = Summarizer::new(Pos::ZERO, [0.0; 3]);
        s.add(&CanonOp::SetFeedRate(100.0));
        s.add(&CanonOp::SetSpindleSpeed(400.0));
        s.add(&CanonOp::StartSpeedFeedSync { pitch: 1.5 });
        // 30 mm at 1.5 mm/rev × 400 rev/min = 600 mm/min: 3 s (F100 would give 18 s).
        s.add(&CanonOp::StraightFeed {
            to: Pos::xyz(0.0, 0.0, -30.0),
        });
        s.add(&CanonOp::StopSpeedFeedSync);
        s.add(&CanonOp::StartSpeedFeedSync { pitch: 1.0 });
        // A tap 10 mm deep: 20 mm in and out at 400 mm/min, 3 s, ending where it began.
        s.add(&CanonOp::RigidTap {
            to: Pos::xyz(0.0, 0.0, -40.0),
        });
        s.add(&CanonOp::StopSpeedFeedSync);
        s.add(&CanonOp::StraightFeed {
            to: Pos::xyz(0.0, 0.0, -35.0),
        }); // 5 mm at F100: 3 s
        let r = s.finish();
        assert!((r.feed_rate_seconds - 9.0).abs() < 1e-9, "{r:?}");
        assert_eq!(r.feed_length, 55.0);
        assert_eq!(r.feed_extents.min[2], -40.0);
    }
}
