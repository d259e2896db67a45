//! Spindle-synchronised motion (G33, G33.1, G76) in the planner: a synchronised move runs at
//! pitch × spindle speed whatever F says, a rigid tap goes in and comes back out along the
//! same line, and a synchronised move without a spindle speed is refused.

mod common;

use common::numbered as canon;
use oficina_canon::{Canon, CanonOp, Pos};
use oficina_motion::{
    check, plan, resolve, MotionError, PlanOptions, Segment, SegmentKind, VelocityProfile,
};

fn planned(ops: &[Canon]) -> Result<Vec<Segment>, MotionError> {
    let p = resolve("grbl-router").unwrap();
    plan(ops.iter().cloned(), &p, PlanOptions::default())?.collect()
}

fn moves(segs: &[Segment]) -> Vec<&Segment> {
    segs.iter()
        .filter(|s| matches!(s.kind, SegmentKind::Move(_)))
        .collect()
}

/// Highest speed a segment reaches, sampled densely (mm/s).
fn peak(s: &Segment) -> f64 {
    (0..=1000)
        .map(|k| s.motion.at(s.duration() * k as f64 / 1000.0).1)
        .fold(0.0, f64::max)
}

#[test]
fn synchronised_feed_runs_at_pitch_times_spindle_speed() {
    let p = resolve("grbl-router").unwrap();
    let (pitch, rpm) = (1.5, 600.0);
    let ops = canon(vec![
        CanonOp::SetSpindleSpeed(rpm),
        CanonOp::StartSpindle(oficina_canon::SpindleDir::Clockwise),
        // A feed rate that must not apply to the synchronised move.
        CanonOp::SetFeedRate(50.0),
        CanonOp::StraightTraverse {
            to: Pos::xyz(10.0, 10.0, 0.0),
        },
        CanonOp::StartSpeedFeedSync { pitch },
        CanonOp::StraightFeed {
            to: Pos::xyz(110.0, 10.0, 0.0),
        },
        CanonOp::StopSpeedFeedSync,
        CanonOp::StraightFeed {
            to: Pos::xyz(120.0, 10.0, 0.0),
        },
    ]);
    let segs = planned(&ops).unwrap();
    let m = moves(&segs);
    let sync = m.iter().find(|s| s.line == 6).unwrap();
    // 1.5 mm/rev × 600 rev/min = 900 mm/min = 15 mm/s.
    let v = pitch * rpm / 60.0;
    assert!((peak(sync) - v).abs() < 1e-6, "{} vs {v}", peak(sync));
    // From rest (the move waits for the spindle's index) to rest (the next move is at F50,
    // far slower, s): a trapezoid over L = 100 mm: up in v/a over v²/2a, down to s in (v−s)/a
    // over (v²−s²)/2a, the rest at v, so t = L/v + v/2a + (v−s)²/2av.
    let a = p.joints[0].unwrap().acceleration;
    let slower = 50.0 / 60.0;
    let expect = 100.0 / v + v / (2.0 * a) + (v - slower).powi(2) / (2.0 * a * v);
    assert!(
        (sync.duration() - expect).abs() < 1e-6,
        "{} vs {expect}",
        sync.duration()
    );
    let after = m.iter().find(|s| s.line == 8).unwrap();
    assert!((peak(after) - slower).abs() < 1e-6);
    let r = check(&ops, &segs, &p, VelocityProfile::Trapezoid, 1.0).unwrap();
    assert!(r.max_speed_ratio <= 1.0 + 1e-6, "{r:?}");
}

#[test]
fn rigid_tap_goes_in_and_back_out_on_the_same_line() {
    let p = resolve("grbl-router").unwrap();
    let start = Pos::xyz(20.0, 20.0, -5.0);
    let ops = canon(vec![
        CanonOp::SetSpindleSpeed(300.0),
        CanonOp::StartSpindle(oficina_canon::SpindleDir::Clockwise),
        CanonOp::StraightTraverse { to: start },
        CanonOp::StartSpeedFeedSync { pitch: 1.0 },
        CanonOp::RigidTap {
            to: Pos::xyz(20.0, 20.0, -25.0),
        },
        CanonOp::StopSpeedFeedSync,
        CanonOp::StraightTraverse {
            to: Pos::xyz(40.0, 20.0, -5.0),
        },
    ]);
    let segs = planned(&ops).unwrap();
    let tap: Vec<_> = moves(&segs).into_iter().filter(|s| s.line == 5).collect();
    assert_eq!(tap.len(), 2, "in and out");
    assert_eq!(tap[0].end, [20.0, 20.0, -25.0]);
    assert_eq!(tap[1].end, [20.0, 20.0, -5.0]);
    assert_eq!(tap[0].op, tap[1].op, "one canon op");
    for s in &tap {
        // 1 mm/rev × 300 rev/min = 5 mm/s, each leg from rest to rest.
        assert!((peak(s) - 5.0).abs() < 1e-6);
        assert_eq!(s.motion.v_start(), 0.0);
        assert_eq!(s.motion.v_end(), 0.0);
    }
    check(&ops, &segs, &p, VelocityProfile::Trapezoid, 1.0).unwrap();
}

#[test]
fn a_synchronised_move_without_spindle_speed_is_refused() {
    for motion in [
        CanonOp::StraightFeed {
            to: Pos::xyz(5.0, 0.0, 0.0),
        },
        CanonOp::RigidTap {
            to: Pos::xyz(0.0, 0.0, -5.0),
        },
    ] {
        let ops = canon(vec![
            CanonOp::StartSpindle(oficina_canon::SpindleDir::Clockwise),
            CanonOp::SetFeedRate(600.0),
            CanonOp::StartSpeedFeedSync { pitch: 1.0 },
            motion,
        ]);
        let e = planned(&ops).unwrap_err().to_string();
        assert!(e.contains("line 4") && e.contains("spindle speed"), "{e}");
    }
}

#[test]
fn a_g95_feed_runs_at_f_times_spindle_speed_and_needs_one() {
    let p = resolve("grbl-router").unwrap();
    // 0.2 mm/rev at 600 rev/min: 120 mm/min, 2 mm/s; the feed override does apply.
    let ops = canon(vec![
        CanonOp::SetSpindleSpeed(600.0),
        CanonOp::StartSpindle(oficina_canon::SpindleDir::Clockwise),
        CanonOp::SetFeedMode(oficina_canon::FeedMode::UnitsPerRev),
        CanonOp::SetFeedRate(0.2),
        CanonOp::StraightFeed {
            to: Pos::xyz(50.0, 0.0, 0.0),
        },
    ]);
    let segs = planned(&ops).unwrap();
    let m = moves(&segs);
    assert_eq!(m.len(), 1);
    assert!((peak(m[0]) - 2.0).abs() < 1e-6, "{}", peak(m[0]));
    check(&ops, &segs, &p, VelocityProfile::Trapezoid, 1.0).unwrap();

    let mut no_speed = ops.clone();
    no_speed.remove(0);
    let e = planned(&no_speed).unwrap_err().to_string();
    assert!(e.contains("G95") && e.contains("set S"), "{e}");
}
