//! An independent checker of what the planner promises, run over whole planned programs.
//!
//! It re-reads the canon ops itself (positions, feeds, modes, arc geometry) and verifies, for
//! every segment: it lies on the programmed path (endpoints on the line or arc; chord sag
//! within the arc tolerance; joint-linear motion within the path tolerance); the path is
//! continuous in position and speed; no joint exceeds its speed, acceleration, jerk or step
//! rate; feeds never exceed the programmed feed; and every junction respects the
//! virtual-arc model of the junction deviation (derived here from the corner geometry, not
//! grbl's formula), the centripetal cap, G61 exact stops and reversals.
//!
//! On purpose, the checker does not use the arc module (`oficina_geom`) that the planner
//! cuts arcs with: it reads the arc's sweep, radii and axial travel with its own few lines
//! below ([`travel_angle`]), so a mistake in the shared geometry cannot hide itself by
//! agreeing with its own output. For the same reason its [`Geometry`] is its own, though it
//! reads like the move stream's shapes (`moves.rs`): the second, independent reading of
//! the program is the point of the checker, so the likeness is kept on purpose, not folded.

use crate::kinematics::{self, Kinematics};
use crate::moves::{dist3, dist_to_segment, lerp3};
use crate::planner::{Segment, SegmentKind};
use crate::profile::{Profile, VelocityProfile};
use oficina_canon::{to_arc_frame, Canon, CanonOp, FeedMode, PathControlMode};

/// Relative slack for floating-point comparisons of limits.
const REL: f64 = 1e-6;
const ABS: f64 = 1e-7;

#[derive(Clone, Copy, Debug)]
enum Geometry {
    Line {
        a: [f64; 3],
        b: [f64; 3],
    },
    Arc {
        axes: (usize, usize, usize),
        c: [f64; 2],
        r0: f64,
        r1: f64,
        n0: f64,
        n1: f64,
        /// Everything above holds in the arc's own frame: the machine frame turned by
        /// `rotation` degrees about Z (an XZ/YZ arc under G10 L2 R).
        a: [f64; 3],
        b: [f64; 3],
        rotation: f64,
    },
}

#[derive(Clone, Copy, Debug)]
struct OpInfo {
    geom: Geometry,
    /// Rotary axes A, B, C at the op's start and end, degrees.
    rot_a: [f64; 3],
    rot_b: [f64; 3],
    /// Highest path speed allowed by the program, mm/s (∞ for rapids).
    feed_cap: f64,
    stop_before: bool,
    /// Corner deviation at the op's start: the previous op's, as the planner's end rule.
    deviation: f64,
    /// Corner deviation between its own chords.
    chord_deviation: f64,
}

/// Figures measured by the checker over a program.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CheckReport {
    /// Segments checked.
    pub segments: usize,
    /// Machine time of the whole program, seconds.
    pub duration: f64,
    /// Largest distance of planned motion from the programmed path, mm.
    pub max_path_deviation: f64,
    /// Largest ratio of any joint's speed / acceleration / jerk to its limit.
    pub max_speed_ratio: f64,
    /// Largest ratio of a joint's acceleration to its limit.
    pub max_accel_ratio: f64,
    /// Largest ratio of a joint's jerk to its limit.
    pub max_jerk_ratio: f64,
}

/// Checks `segments` planned from `ops`; returns the report or every violation found (at most
/// 50, each naming the segment and source line).
pub fn check(
    ops: &[Canon],
    segments: &[Segment],
    profile: &Profile,
    shape: VelocityProfile,
    feed_override: f64,
) -> Result<CheckReport, Vec<String>> {
    let kin = kinematics::for_profile(profile);
    let info = read_ops(ops, profile, feed_override);
    let mut bad = Vec::new();
    let mut rep = CheckReport {
        segments: segments.len(),
        ..CheckReport::default()
    };
    let mut prev: Option<&Segment> = None;
    let mut pos = profile.start;
    let mut rot = [0.0; 3];
    let mut v_prev_end = 0.0;
    let whole = whole_pieces(segments);
    let mut fail = |msg: String| {
        if bad.len() < 50 {
            bad.push(msg)
        }
    };
    for (k, s) in segments.iter().enumerate() {
        let tag = format!("segment {k} (line {})", s.line);
        rep.duration += s.motion.duration;
        if dist3(s.start, pos) > ABS {
            fail(format!(
                "{tag}: starts at {:?}, not where the machine is, {pos:?}",
                s.start
            ));
        }
        pos = s.end;
        if dist3(s.rot0, rot) > ABS {
            fail(format!(
                "{tag}: rotary axes start at {:?}, not where they are, {rot:?}",
                s.rot0
            ));
        }
        rot = s.rot1;
        let ps = s.motion.pieces();
        let v_start = s.motion.v_start();
        if (v_start - v_prev_end).abs() > 1e-6 * v_start.max(1.0) {
            fail(format!("{tag}: speed jumps from {v_prev_end} to {v_start}"));
        }
        v_prev_end = s.motion.v_end();
        let SegmentKind::Move(_) = s.kind else {
            if v_start != 0.0 || s.start != s.end || s.rot0 != s.rot1 {
                fail(format!("{tag}: a dwell or sync while moving"));
            }
            prev = None;
            continue;
        };
        let Some(op) = info.get(s.op as usize) else {
            fail(format!(
                "{tag}: refers to motion op {} which the program does not have",
                s.op
            ));
            continue;
        };
        let len = feed_length(s);
        let (s_end, _, a_end) = s.motion.at(s.motion.duration);
        if (s.motion.length - len).abs() > 1e-9 * len.max(1.0)
            || (s_end - len).abs() > 1e-6 * len.max(1.0)
        {
            fail(format!(
                "{tag}: profile covers {s_end} mm of a {len} mm segment"
            ));
        }
        // On the programmed path.
        let dev = path_deviation(&op.geom, s.start).max(path_deviation(&op.geom, s.end));
        let chord_dev = chord_sag(&op.geom, s.start, s.end);
        let mut joint_dev: f64 = 0.0;
        for i in 0..=16 {
            let f = i as f64 / 16.0;
            let p = kin.forward(lerp3(s.q0, s.q1, f));
            joint_dev = joint_dev.max(dist_to_segment(p, s.start, s.end));
        }
        rep.max_path_deviation = rep.max_path_deviation.max(dev + chord_dev + joint_dev);
        // The rotary axes: between the op's start and end values, and in step with the
        // tool along a line (they start and stop together, so the fraction done agrees).
        for (r, at_end) in [(s.rot0, false), (s.rot1, true)] {
            if let Some(msg) = rotary_off(op, r, if at_end { s.end } else { s.start }) {
                fail(format!("{tag}: {msg}"));
            }
        }
        // Arc pieces may end inside a chord (a live command cut it there): within the arc
        // tolerance of the arc, like the chord itself.
        let end_tol = match op.geom {
            Geometry::Line { .. } => 1e-6,
            Geometry::Arc { .. } => profile.arc_tolerance * (1.0 + REL) + ABS,
        };
        if dev > end_tol {
            fail(format!(
                "{tag}: endpoint lies {dev} mm off the programmed path"
            ));
        }
        if chord_dev > profile.arc_tolerance * (1.0 + REL) + ABS {
            fail(format!(
                "{tag}: chord sags {chord_dev} mm, above arc_tolerance {}",
                profile.arc_tolerance
            ));
        }
        if joint_dev > profile.path_tolerance * (1.0 + REL) + ABS {
            fail(format!(
                "{tag}: joint motion strays {joint_dev} mm, above path_tolerance {}",
                profile.path_tolerance
            ));
        }
        for (p, q) in [(s.start, s.q0), (s.end, s.q1)] {
            if dist3(kin.forward(q), p) > 1e-6 {
                fail(format!("{tag}: joints {q:?} do not reach {p:?}"));
            }
        }
        // Joint limits through dq/ds of this segment: X, Y, Z joints, then A, B, C.
        let dqds: [f64; 6] = std::array::from_fn(|i| {
            let d = if i < 3 {
                s.q1[i] - s.q0[i]
            } else {
                s.rot1[i - 3] - s.rot0[i - 3]
            };
            if len > 0.0 {
                d / len
            } else {
                0.0
            }
        });
        let joints = profile.all_joints();
        let mut v_max: f64 = 0.0;
        for p in ps {
            let (_, v1, a1) = p.at(p.dur);
            let mut vs = vec![p.v0, v1];
            if p.jerk != 0.0 {
                let t = -p.a0 / p.jerk;
                if t > 0.0 && t < p.dur {
                    vs.push(p.at(t).1);
                }
            }
            for &v in &vs {
                if v < -1e-9 {
                    fail(format!("{tag}: moves backwards ({v} mm/s)"));
                }
                v_max = v_max.max(v);
            }
            let a_max = p.a0.abs().max(a1.abs());
            for (i, j) in joints.iter().enumerate() {
                let d = dqds[i].abs();
                let Some(j) = j else {
                    if d > 0.0 {
                        fail(format!("{tag}: moves joint {i}, which does not exist"));
                    }
                    continue;
                };
                let vr = v_max * d / j.max_rate;
                let sr = v_max * d * j.steps_per_unit / profile.max_step_rate;
                let ar = a_max * d / j.acceleration;
                rep.max_speed_ratio = rep.max_speed_ratio.max(vr);
                rep.max_accel_ratio = rep.max_accel_ratio.max(ar);
                if vr > 1.0 + REL || sr > 1.0 + REL {
                    fail(format!(
                        "{tag}: joint {} at {:.6} unit/s, limit {:.6}",
                        j.name,
                        v_max * d,
                        j.max_rate
                    ));
                }
                if ar > 1.0 + REL {
                    fail(format!(
                        "{tag}: joint {} accelerates at {:.6}, limit {:.6}",
                        j.name,
                        a_max * d,
                        j.acceleration
                    ));
                }
                if shape == VelocityProfile::SCurve {
                    let jr = p.jerk.abs() * d / j.jerk.unwrap_or(f64::INFINITY);
                    rep.max_jerk_ratio = rep.max_jerk_ratio.max(jr);
                    if jr > 1.0 + REL {
                        fail(format!(
                            "{tag}: joint {} jerk {:.6}, limit {:?}",
                            j.name,
                            p.jerk.abs() * d,
                            j.jerk
                        ));
                    }
                }
            }
        }
        if v_max > op.feed_cap * (1.0 + REL) + 1e-9 {
            fail(format!(
                "{tag}: {v_max} mm/s exceeds the programmed feed {} mm/s",
                op.feed_cap
            ));
        }
        if shape == VelocityProfile::SCurve
            && (s.motion.at(0.0).2.abs() > 1e-6 || a_end.abs() > 1e-6)
        {
            fail(format!(
                "{tag}: S-curve segment starts or ends while accelerating"
            ));
        }
        // The junction with the previous segment.
        let v_j = s.motion.v_start();
        let at_op_start = prev.is_none_or(|p| p.op != s.op);
        if at_op_start && op.stop_before && v_j > 1e-9 {
            fail(format!(
                "{tag}: must start at rest (G61, dwell or sync) but starts at {v_j} mm/s"
            ));
        }
        if let Some(p) = prev {
            let dev = if at_op_start {
                op.deviation
            } else {
                op.chord_deviation
            };
            let bound = junction_bound(p, whole[k - 1], s, whole[k], dev, profile);
            if v_j > bound * (1.0 + 1e-5) + 1e-9 {
                fail(format!(
                    "{tag}: corner taken at {v_j} mm/s, the junction allows {bound} mm/s"
                ));
            }
        } else if v_j > 1e-9 {
            fail(format!(
                "{tag}: the first move after rest starts at {v_j} mm/s"
            ));
        }
        prev = Some(s);
    }
    if v_prev_end > 1e-9 {
        fail(format!(
            "the program ends at {v_prev_end} mm/s instead of at rest"
        ));
    }
    if bad.is_empty() {
        Ok(rep)
    } else {
        Err(bad)
    }
}

/// Highest corner speed allowed between segments `p` and `s`.
fn junction_bound(
    p: &Segment,
    p_whole: f64,
    s: &Segment,
    s_whole: f64,
    deviation: f64,
    profile: &Profile,
) -> f64 {
    let (lp, ls) = (feed_length(p), feed_length(s));
    let up = direction(p);
    let us = direction(s);
    let dot = (0..6).map(|i| up[i] * us[i]).sum::<f64>().clamp(-1.0, 1.0);
    let turn = dot.acos(); // 0 = straight on, π = reversal
    let (rp, rs) = (joint_travel(p), joint_travel(s));
    let dq: [f64; 6] = std::array::from_fn(|i| rs[i] / ls - rp[i] / lp);
    let du = (0..6).map(|i| (us[i] - up[i]).powi(2)).sum::<f64>().sqrt();
    let joints = profile.all_joints();
    let mut v2 = f64::INFINITY;
    if turn > 1e-3 {
        if turn > std::f64::consts::PI - 1.5e-3 {
            return 0.0;
        }
        // The arc tangent to both pieces that passes `deviation` from the corner.
        let c = (turn * 0.5).cos();
        let radius = deviation * c / (1.0 - c);
        for (i, j) in joints.iter().enumerate() {
            if let (Some(j), true) = (j, dq[i] != 0.0) {
                // Centripetal acceleration v²/R points along Δu; its share on joint i.
                v2 = v2.min(j.acceleration * radius * du / dq[i].abs());
            }
        }
    }
    let lmin = p_whole.max(lp).min(s_whole.max(ls));
    for (i, j) in joints.iter().enumerate() {
        if let (Some(j), true) = (j, dq[i] != 0.0) {
            v2 = v2.min(j.acceleration * lmin / dq[i].abs());
        }
    }
    v2.sqrt()
}

/// For each segment, the length of the straight piece it is part of: a live command (feed
/// override, hold) cuts a piece where the machine is, which changes no corner.
fn whole_pieces(segments: &[Segment]) -> Vec<f64> {
    let mut whole = vec![0.0; segments.len()];
    let mut run: Vec<usize> = Vec::new();
    let mut last_move: Option<&Segment> = None;
    let close = |run: &mut Vec<usize>, whole: &mut Vec<f64>| {
        let total: f64 = run.iter().map(|&i| segments[i].motion.length).sum();
        for &i in run.iter() {
            whole[i] = total;
        }
        run.clear();
    };
    for (k, s) in segments.iter().enumerate() {
        match s.kind {
            SegmentKind::Move(_) => {}
            // A hold splits a piece at rest; anything else ends it.
            SegmentKind::Hold => continue,
            _ => {
                close(&mut run, &mut whole);
                last_move = None;
                continue;
            }
        }
        let goes_on = last_move
            .is_some_and(|p| p.op == s.op && dist3(p.end, s.start) < ABS && same_direction(p, s));
        if !goes_on {
            close(&mut run, &mut whole);
        }
        run.push(k);
        last_move = Some(s);
    }
    close(&mut run, &mut whole);
    whole
}

/// `s` goes on exactly where `p` was heading, joints included (a cut, not a corner).
fn same_direction(p: &Segment, s: &Segment) -> bool {
    let (lp, ls) = (feed_length(p), feed_length(s));
    let (up, us) = (direction(p), direction(s));
    let (rp, rs) = (joint_travel(p), joint_travel(s));
    (0..6).all(|i| (up[i] - us[i]).abs() < 1e-9 && (rp[i] / lp - rs[i] / ls).abs() < 1e-9)
}

/// The length the feed rate applies to, read from the segment's own ends (LinuxCNC's rule,
/// restated here: the XYZ distance when the tool moves, else the ABC distance in degrees).
fn feed_length(s: &Segment) -> f64 {
    let xyz = dist3(s.start, s.end);
    if xyz >= 1e-9 {
        xyz
    } else {
        dist3(s.rot0, s.rot1)
    }
}

/// Unit direction in (X, Y, Z, A, B, C): the tool's when it moves, else the rotary axes'.
fn direction(s: &Segment) -> [f64; 6] {
    let l = feed_length(s);
    let xyz = dist3(s.start, s.end) >= 1e-9;
    std::array::from_fn(|i| match (i < 3, xyz) {
        (true, true) => (s.end[i] - s.start[i]) / l,
        (false, false) => (s.rot1[i - 3] - s.rot0[i - 3]) / l,
        _ => 0.0,
    })
}

/// How far each joint travels over the segment: X, Y, Z joints, then A, B, C.
fn joint_travel(s: &Segment) -> [f64; 6] {
    std::array::from_fn(|i| {
        if i < 3 {
            s.q1[i] - s.q0[i]
        } else {
            s.rot1[i - 3] - s.rot0[i - 3]
        }
    })
}

/// Why rotary values `r` at tool point `p` do not belong to `op`, if they do not: outside
/// the op's A/B/C range, or (on a line that moves the tool) not at the fraction of the
/// rotary travel that the tool has done of the line.
fn rotary_off(op: &OpInfo, r: [f64; 3], p: [f64; 3]) -> Option<String> {
    let (ra, rb) = (op.rot_a, op.rot_b);
    for i in 0..3 {
        let (lo, hi) = (ra[i].min(rb[i]), ra[i].max(rb[i]));
        if r[i] < lo - 1e-6 || r[i] > hi + 1e-6 {
            return Some(format!(
                "rotary axis {} at {:.6}° lies outside the move's [{lo:.6}, {hi:.6}]",
                ["A", "B", "C"][i],
                r[i]
            ));
        }
    }
    if let Geometry::Line { a, b } = op.geom {
        let l = dist3(a, b);
        if l >= 1e-9 && dist3(ra, rb) > 0.0 {
            let f = dist3(a, p) / l;
            let want = lerp3(ra, rb, f);
            // 1e-6 of the rotary travel per mm of line: rounding, not drift.
            if dist3(want, r) > 1e-6 * dist3(ra, rb).max(1.0) {
                return Some(format!(
                    "rotary axes at {r:?}, but {:.6} of the line is done, where they are {want:?}",
                    f
                ));
            }
        }
    }
    None
}

fn path_deviation(g: &Geometry, p: [f64; 3]) -> f64 {
    match *g {
        Geometry::Line { a, b } => dist_to_segment(p, a, b),
        Geometry::Arc {
            axes,
            c,
            r0,
            r1,
            n0,
            n1,
            a,
            b,
            rotation,
        } => {
            let p = to_arc_frame(p, rotation);
            if dist3(p, a) < 1e-9 || dist3(p, b) < 1e-9 {
                return 0.0;
            }
            let r = (p[axes.0] - c[0]).hypot(p[axes.1] - c[1]);
            let dr = (r - r0.min(r1)).min(0.0).abs() + (r - r0.max(r1)).max(0.0);
            let dn = (p[axes.2] - n0.min(n1)).min(0.0).abs() + (p[axes.2] - n0.max(n1)).max(0.0);
            dr.hypot(dn)
        }
    }
}

/// How far the chord a–b sags inside the programmed arc (0 for lines).
fn chord_sag(g: &Geometry, a: [f64; 3], b: [f64; 3]) -> f64 {
    match *g {
        Geometry::Line { .. } => 0.0,
        Geometry::Arc {
            axes, c, rotation, ..
        } => {
            let (a, b) = (to_arc_frame(a, rotation), to_arc_frame(b, rotation));
            let m = lerp3(a, b, 0.5);
            let r_mid = (m[axes.0] - c[0]).hypot(m[axes.1] - c[1]);
            let ra = (a[axes.0] - c[0]).hypot(a[axes.1] - c[1]);
            let rb = (b[axes.0] - c[0]).hypot(b[axes.1] - c[1]);
            (0.5 * (ra + rb) - r_mid).max(0.0)
        }
    }
}

/// Angle travelled from `a0` to `a1` (radians, unsigned) by an arc of G-code `turns`: the
/// partial turn in the direction of travel (a whole one when the ends coincide) plus
/// |turns| − 1 full turns. Written here apart from the arc module (see the module note).
fn travel_angle(a0: f64, a1: f64, turns: i32) -> f64 {
    use std::f64::consts::TAU;
    let delta = if turns > 0 { a1 - a0 } else { a0 - a1 };
    let mut partial = delta - TAU * (delta / TAU).floor();
    if partial <= 1e-12 {
        partial += TAU;
    }
    partial + TAU * (turns.unsigned_abs().max(1) - 1) as f64
}

fn read_ops(ops: &[Canon], profile: &Profile, feed_override: f64) -> Vec<OpInfo> {
    let mut out = Vec::new();
    let mut pos = profile.start;
    let mut rot = [0.0; 3];
    let (mut feed, mut inverse, mut mode, mut tol) = (
        profile.default_feed,
        false,
        PathControlMode::Continuous,
        0.0_f64,
    );
    let mut stop = true;
    // The mode and deviation in force when the last moving op was issued: LinuxCNC applies
    // them at that op's end, the next op's start (G61.1 stops after its move).
    let mut end_rule = (PathControlMode::Continuous, profile.junction_deviation);
    let mut override_on = true;
    // Spindle speed (rev/min) and, inside G33/G33.1/G76, the pitch (mm/rev): a synchronised
    // move's cap is pitch × rpm, no override.
    let (mut rpm, mut sync) = (0.0_f64, None::<f64>);
    // G95: feed in mm per revolution.
    let mut per_rev = false;
    for c in ops {
        let deviation = match mode {
            PathControlMode::ExactPath => 0.0,
            _ if tol > 0.0 => tol.min(profile.junction_deviation),
            _ => profile.junction_deviation,
        };
        let chord_deviation = match mode {
            PathControlMode::Continuous => deviation,
            _ => profile.junction_deviation,
        };
        let factor = if override_on { feed_override } else { 1.0 };
        match &c.op {
            CanonOp::SetFeedRate(f) => feed = if inverse || per_rev { *f } else { f / 60.0 },
            CanonOp::SetFeedMode(m) => {
                inverse = *m == FeedMode::InverseTime;
                per_rev = *m == FeedMode::UnitsPerRev;
            }
            CanonOp::SetMotionControlMode { mode: m, tolerance } => {
                mode = *m;
                tol = *tolerance;
            }
            CanonOp::EnableFeedOverride(on) => override_on = *on,
            CanonOp::StraightTraverse { to } | CanonOp::StraightFeed { to } => {
                let b = [to.x, to.y, to.z];
                let rb = [to.a, to.b, to.c];
                let rapid = matches!(c.op, CanonOp::StraightTraverse { .. });
                let len = if dist3(pos, b) >= 1e-9 {
                    dist3(pos, b)
                } else {
                    dist3(rot, rb)
                };
                let cap = if rapid {
                    f64::INFINITY
                } else if let Some(pitch) = sync {
                    pitch * rpm / 60.0
                } else if inverse {
                    len * feed / 60.0 * factor
                } else if per_rev {
                    feed * rpm / 60.0 * factor
                } else {
                    feed * factor
                };
                let moving = len >= 1e-9;
                out.push(OpInfo {
                    geom: Geometry::Line { a: pos, b },
                    rot_a: rot,
                    rot_b: rb,
                    feed_cap: cap,
                    stop_before: moving && (stop || end_rule.0 == PathControlMode::ExactStop),
                    deviation: end_rule.1,
                    chord_deviation,
                });
                if moving {
                    stop = false;
                    end_rule = (mode, deviation);
                }
                pos = b;
                rot = rb;
            }
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                rotation,
            } => {
                let axes = plane.axes();
                let b_machine = [end.x, end.y, end.z];
                let rb = [end.a, end.b, end.c];
                // Measured in the arc's own frame (identity unless turned about Z).
                let (pa, b) = (
                    to_arc_frame(pos, *rotation),
                    to_arc_frame(b_machine, *rotation),
                );
                let r0 = (pa[axes.0] - center[0]).hypot(pa[axes.1] - center[1]);
                let r1 = (b[axes.0] - center[0]).hypot(b[axes.1] - center[1]);
                let a0 = (pa[axes.1] - center[1]).atan2(pa[axes.0] - center[0]);
                let a1 = (b[axes.1] - center[1]).atan2(b[axes.0] - center[0]);
                let sweep = travel_angle(a0, a1, *turns);
                let len = (sweep.abs() * 0.5 * (r0 + r1)).hypot(b[axes.2] - pa[axes.2]);
                let cap = if inverse {
                    len * feed / 60.0 * factor
                } else if per_rev {
                    feed * rpm / 60.0 * factor
                } else {
                    feed * factor
                };
                out.push(OpInfo {
                    geom: Geometry::Arc {
                        axes,
                        c: *center,
                        r0,
                        r1,
                        n0: pa[axes.2],
                        n1: b[axes.2],
                        a: pa,
                        b,
                        rotation: *rotation,
                    },
                    rot_a: rot,
                    rot_b: rb,
                    feed_cap: cap,
                    stop_before: stop || end_rule.0 == PathControlMode::ExactStop,
                    deviation: end_rule.1,
                    chord_deviation,
                });
                stop = false;
                end_rule = (mode, deviation);
                pos = b_machine;
                rot = rb;
            }
            CanonOp::StartSpeedFeedSync { pitch } => {
                if sync.is_none() {
                    stop = true;
                }
                sync = Some(*pitch);
            }
            CanonOp::StopSpeedFeedSync => sync = None,
            // In along a line and back out of it: one op whose two legs lie on that line.
            CanonOp::RigidTap { to } => {
                let b = [to.x, to.y, to.z];
                out.push(OpInfo {
                    geom: Geometry::Line { a: pos, b },
                    rot_a: rot,
                    rot_b: rot,
                    feed_cap: sync.unwrap_or(0.0) * rpm / 60.0,
                    stop_before: dist3(pos, b) >= 1e-9,
                    deviation,
                    chord_deviation,
                });
                stop = true;
                end_rule = (mode, deviation);
            }
            CanonOp::SetSpindleSpeed(s) => {
                rpm = *s;
                stop = true;
            }
            CanonOp::Dwell(_)
            | CanonOp::ProgramStop
            | CanonOp::OptionalProgramStop
            | CanonOp::StartSpindle(_)
            | CanonOp::StopSpindle
            | CanonOp::OrientSpindle { .. }
            | CanonOp::WaitOrientComplete(_)
            | CanonOp::ChangeTool(_)
            | CanonOp::ProgramEnd => stop = true,
            _ => {}
        }
    }
    out
}
