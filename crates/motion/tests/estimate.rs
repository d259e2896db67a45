//! Time estimates against independent closed forms.

mod common;
use common::{profile, Prog};
use oficina_canon::{CanonOp, PathControlMode};
use oficina_motion::check;
use oficina_motion::estimate;
use oficina_motion::VelocityProfile;
use oficina_motion::{plan, PlanOptions, Segment};

/// Trapezoid time for distance d from rest to rest: cruise v, acceleration a.
fn trapezoid(d: f64, v: f64, a: f64) -> f64 {
    if d >= v * v / a {
        d / v + v / a
    } else {
        2.0 * (d / a).sqrt()
    }
}

#[test]
fn single_long_move_matches_the_closed_form() {
    let p = profile("grbl-router.toml");
    let mut prog = Prog::new(3000.0);
    prog.g1(700.0, 0.0, 0.0);
    prog.op(CanonOp::ProgramEnd);
    let e = estimate(prog.ops.into_iter(), &p).unwrap();
    // 700 mm at 50 mm/s with 300 mm/s²: 14 s + 1/6 s.
    let want = trapezoid(700.0, 50.0, 300.0);
    assert!((e.seconds - want).abs() < 1e-9, "{} vs {want}", e.seconds);
}

#[test]
fn diagonal_rapid_is_limited_by_each_axis() {
    let p = profile("grbl-router.toml");
    let mut prog = Prog::new(1000.0);
    prog.g0(300.0, 400.0, 0.0);
    let e = estimate(prog.ops.into_iter(), &p).unwrap();
    // Along (0.6, 0.8) the Y axis binds: v = 100/0.8, a = 300/0.8.
    let want = trapezoid(500.0, 100.0 / 0.8, 300.0 / 0.8);
    assert!((e.seconds - want).abs() < 1e-9, "{} vs {want}", e.seconds);
}

#[test]
fn exact_stop_moves_sum_independently() {
    let p = profile("grbl-router.toml");
    let mut prog = Prog::new(1200.0);
    prog.op(CanonOp::SetMotionControlMode {
        mode: PathControlMode::ExactStop,
        tolerance: 0.0,
    });
    let pts = [
        (100.0, 0.0),
        (100.0, 80.0),
        (20.0, 80.0),
        (20.0, 10.0),
        (20.5, 10.0),
    ];
    let mut want = 0.0;
    let mut at: (f64, f64) = (0.0, 0.0);
    for (x, y) in pts {
        want += trapezoid((x - at.0).hypot(y - at.1), 20.0, 300.0);
        at = (x, y);
        prog.g1(x, y, 0.0);
    }
    prog.op(CanonOp::Dwell(1.5));
    want += 1.5;
    let e = estimate(prog.ops.into_iter(), &p).unwrap();
    assert!((e.seconds - want).abs() < 1e-9, "{} vs {want}", e.seconds);
}

#[test]
fn the_checker_catches_broken_plans() {
    let p = profile("grbl-router.toml");
    let prog = common::program("zigzag", 1, [400.0, 225.0, -10.0], 200.0);
    let segs: Vec<Segment> = plan(prog.ops.iter().cloned(), &p, PlanOptions::default())
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert!(check(&prog.ops, &segs, &p, VelocityProfile::Trapezoid, 1.0).is_ok());
    // Too fast: the same plan checked against half the programmed feed.
    assert!(check(&prog.ops, &segs, &p, VelocityProfile::Trapezoid, 0.5).is_err());
    // Off the path: one endpoint moved by 0.01 mm.
    let mut moved = segs.clone();
    moved[5].end[1] += 0.01;
    moved[6].start[1] += 0.01;
    let v = check(&prog.ops, &moved, &p, VelocityProfile::Trapezoid, 1.0).unwrap_err();
    assert!(
        v.iter().any(|m| m.contains("off the programmed path")),
        "{v:?}"
    );
    // A corner taken too fast: lift one junction speed by replanning a segment.
    let mut fast = segs.clone();
    let k = fast.iter().position(|s| s.motion.v_start() > 1.0).unwrap();
    let m = fast[k].motion;
    let lim = oficina_motion::Limits {
        accel: 1e9,
        jerk: f64::INFINITY,
    };
    fast[k].motion = oficina_motion::Motion::plan(
        m.length,
        m.v_start() * 3.0,
        m.v_start() * 3.0,
        m.v_end(),
        lim,
    );
    assert!(check(&prog.ops, &fast, &p, VelocityProfile::Trapezoid, 1.0).is_err());
}
