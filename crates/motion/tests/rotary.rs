//! Rotary joints in the planner and the invariant checker: a mixed X + A move plans within
//! every limit, and the checker catches rotary motion that breaks a limit or leaves the
//! programmed move.

use oficina_canon::{Canon, CanonOp, Pos};
use oficina_motion::check;
use oficina_motion::{plan, PlanOptions, Segment, SegmentKind};
use oficina_motion::{resolve, VelocityProfile};
use oficina_motion::{StepGenerator, StepLog};

fn ops(moves: &[(f64, f64, f64)]) -> Vec<Canon> {
    let mut v = vec![Canon {
        line: 1,
        op: CanonOp::SetFeedRate(600.0),
    }];
    for (k, &(x, a, f)) in moves.iter().enumerate() {
        v.push(Canon {
            line: 2 + k as u32,
            op: CanonOp::SetFeedRate(f),
        });
        v.push(Canon {
            line: 2 + k as u32,
            op: CanonOp::StraightFeed {
                to: Pos { x, a, ..Pos::ZERO },
            },
        });
    }
    v
}

fn planned(ops: &[Canon]) -> Vec<Segment> {
    let p = resolve("router-4axis").unwrap();
    plan(ops.iter().cloned(), &p, PlanOptions::default())
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap()
}

#[test]
fn mixed_and_pure_rotary_moves_pass_the_checker_and_step_the_a_motor() {
    let p = resolve("router-4axis").unwrap();
    // A cut with A turning, a pure turn back, and a turn past a full revolution.
    let prog = ops(&[
        (10.0, 90.0, 600.0),
        (10.0, 0.0, 3600.0),
        (20.0, 450.0, 900.0),
    ]);
    let segs = planned(&prog);
    let r = check(&prog, &segs, &p, VelocityProfile::Trapezoid, 1.0).unwrap();
    assert!(
        r.max_accel_ratio > 0.99 && r.max_accel_ratio <= 1.0 + 1e-6,
        "{r:?}"
    );
    let last = segs
        .iter()
        .rev()
        .find(|s| matches!(s.kind, SegmentKind::Move(_)));
    assert_eq!(
        last.unwrap().rot1[0],
        450.0,
        "whole turns are counted, not wrapped"
    );
    let mut gen = StepGenerator::new(&p, [0.0; 3]);
    let mut log = StepLog::default();
    for s in &segs {
        gen.segment(s, &mut log).unwrap();
    }
    // 90° out, 90° back, 450° out at 20 steps per degree.
    assert_eq!(log.motors[3].len(), (90 + 90 + 450) * 20);
    assert_eq!(gen.rotary_counts(), [450 * 20, 0, 0]);
}

#[test]
fn checker_catches_rotary_motion_beyond_the_limits_or_off_the_move() {
    let p = resolve("router-4axis").unwrap();
    let prog = ops(&[(10.0, 90.0, 600.0)]);
    let segs = planned(&prog);
    // A turned four times as far in the same time: too fast for A's acceleration, and off
    // the programmed move.
    let mut fast = segs.clone();
    for s in &mut fast {
        s.rot0[0] *= 4.0;
        s.rot1[0] *= 4.0;
    }
    let bad = check(&prog, &fast, &p, VelocityProfile::Trapezoid, 1.0).unwrap_err();
    assert!(
        bad.iter().any(|m| m.contains("joint a accelerates")),
        "{bad:?}"
    );
    assert!(bad.iter().any(|m| m.contains("rotary axis A")), "{bad:?}");
    // A rotary move on a profile without the joint is refused by the planner.
    let three = resolve("grbl-router").unwrap();
    let e = plan(prog.iter().cloned(), &three, PlanOptions::default())
        .unwrap()
        .find_map(|r| r.err())
        .unwrap();
    assert!(e.to_string().contains("rotary axis A"), "{e}");
}
