//! Live feed override and feed hold: the re-planned motion against closed forms, and the
//! invariant checker over the executed timeline (the part run before the command, cut where
//! the command came, then everything re-planned after it).

mod common;
use common::{profile, program, Prog, KINDS};
use oficina_canon::{Canon, CanonOp};
use oficina_motion::check;
use oficina_motion::lerp3;
use oficina_motion::Cut;
use oficina_motion::VelocityProfile;
use oficina_motion::{plan, PlanOptions, Planner, Profile, Segment, SegmentKind};

/// Time to change speed by `dv` with acceleration `a` and jerk `j` (∞ for a trapezoid).
fn ramp(dv: f64, a: f64, j: f64) -> f64 {
    if !j.is_finite() {
        dv / a
    } else if dv >= a * a / j {
        dv / a + a / j
    } else {
        2.0 * (dv / j).sqrt()
    }
}

/// Runs the plan of `ops`, applies `command` inside the first segment at or after `from`
/// that can be cut (S-curve: only where the acceleration is zero), and returns the executed
/// timeline: segments before, the cut one truncated, then all re-planned segments.
fn run_with<F>(
    ops: &[Canon],
    p: &Profile,
    shape: VelocityProfile,
    from: usize,
    command: F,
) -> (Vec<Segment>, Cut)
where
    F: FnOnce(&mut Planner<'_, std::vec::IntoIter<Canon>>, Cut),
{
    let opts = PlanOptions {
        shape: Some(shape),
        ..PlanOptions::default()
    };
    let mut planner = plan(Vec::from(ops).into_iter(), p, opts).unwrap();
    let mut out = Vec::new();
    let mut command = Some(command);
    let mut cut_at = None;
    while let Some(seg) = planner.next() {
        let seg = seg.unwrap();
        let cut_time = match (out.len() >= from, seg.kind, &command) {
            (true, SegmentKind::Move(_), Some(_)) => cut_time(&seg, shape),
            _ => None,
        };
        let Some(t) = cut_time else {
            out.push(seg);
            continue;
        };
        let (s, v, _) = seg.motion.at(t);
        let f = s / seg.motion.length;
        let mut done = seg;
        done.motion = seg.motion.truncated(t);
        done.end = lerp3(seg.start, seg.end, f);
        done.q1 = lerp3(seg.q0, seg.q1, f);
        out.push(done);
        let cut = Cut { s, v };
        (command.take().unwrap())(&mut planner, cut);
        cut_at = Some(cut);
    }
    (out, cut_at.expect("the command was applied"))
}

/// Middle of a cruise piece (zero acceleration), or halfway for a trapezoid.
fn cut_time(seg: &Segment, shape: VelocityProfile) -> Option<f64> {
    match shape {
        VelocityProfile::Trapezoid => Some(seg.duration() * 0.5).filter(|&t| t > 0.0),
        VelocityProfile::SCurve => seg
            .motion
            .pieces()
            .iter()
            .find(|p| p.a0 == 0.0 && p.jerk == 0.0 && p.v0 > 0.0 && p.dur > 0.0)
            .map(|p| p.t0 + 0.5 * p.dur),
    }
}

fn total(segs: &[Segment]) -> f64 {
    segs.iter().map(|s| s.duration()).sum()
}

#[test]
fn override_to_half_doubles_the_remaining_time_of_a_long_move() {
    let mut p = profile("grbl-router.toml");
    for shape in [VelocityProfile::Trapezoid, VelocityProfile::SCurve] {
        let jerk = match shape {
            VelocityProfile::Trapezoid => f64::INFINITY,
            VelocityProfile::SCurve => 6000.0,
        };
        p.shape = shape;
        let mut prog = Prog::new(3000.0);
        prog.g1(700.0, 0.0, 0.0);
        prog.op(CanonOp::ProgramEnd);
        let (segs, cut) = run_with(&prog.ops, &p, shape, 0, |pl, cut| {
            pl.set_feed_override(0.5, Some(cut))
        });
        assert!((cut.v - 50.0).abs() < 1e-9, "cut while cruising: {cut:?}");
        let executed = segs[0].duration();
        let remaining = total(&segs) - executed;
        // Closed form at 50 %: brake 50 → 25 and 25 → 0 at a = 300 (jerk 6000), cruise at 25.
        let (a, d) = (300.0, 700.0 - cut.s);
        let (t1, t2) = (ramp(25.0, a, jerk), ramp(25.0, a, jerk));
        let want = t1 + t2 + (d - 37.5 * t1 - 12.5 * t2) / 25.0;
        assert!(
            (remaining - want).abs() < 1e-6,
            "{shape:?}: {remaining} vs {want}"
        );
        // At 100 % the same rest takes: cruise at 50 and brake 50 → 0.
        let t3 = ramp(50.0, a, jerk);
        let before = t3 + (d - 25.0 * t3) / 50.0;
        let ratio = remaining / before;
        assert!((1.95..2.0).contains(&ratio), "{shape:?}: ratio {ratio}");
        let rep = check(&prog.ops, &segs, &p, shape, 1.0)
            .unwrap_or_else(|v| panic!("{shape:?}: {}", v.join("\n")));
        assert!(rep.max_accel_ratio <= 1.0 + 1e-6 && rep.max_jerk_ratio <= 1.0 + 1e-6);
        let end = segs.last().unwrap().end;
        assert!((end[0] - 700.0).abs() < 1e-9);
    }
}

#[test]
fn scurve_hold_stops_at_the_closed_form_distance_and_resumes() {
    let mut p = profile("grbl-router.toml");
    p.shape = VelocityProfile::SCurve;
    let mut prog = Prog::new(3000.0);
    prog.g1(700.0, 0.0, 0.0);
    prog.op(CanonOp::ProgramEnd);
    let (segs, cut) = run_with(&prog.ops, &p, VelocityProfile::SCurve, 0, |pl, cut| {
        pl.hold(Some(cut))
    });
    let holds: Vec<&Segment> = segs
        .iter()
        .filter(|s| s.kind == SegmentKind::Hold)
        .collect();
    assert_eq!(holds.len(), 1);
    // Jerk-limited stop from 50 mm/s: mean speed 25 for 50/300 + 300/6000 s.
    let want = cut.s + 25.0 * (50.0 / 300.0 + 300.0 / 6000.0);
    assert!(
        (holds[0].start[0] - want).abs() < 1e-6,
        "{:?}",
        holds[0].start
    );
    let rep = check(&prog.ops, &segs, &p, VelocityProfile::SCurve, 1.0)
        .unwrap_or_else(|v| panic!("{}", v.join("\n")));
    assert!(rep.max_jerk_ratio <= 1.0 + 1e-6, "{}", rep.max_jerk_ratio);
    assert!((segs.last().unwrap().end[0] - 700.0).abs() < 1e-9);
}

#[test]
fn override_and_hold_over_the_corpus_pass_the_checker() {
    let p = profile("grbl-router.toml");
    for shape in [VelocityProfile::Trapezoid, VelocityProfile::SCurve] {
        for kind in KINDS {
            for seed in 0..2 {
                let prog = program(kind, seed, [400.0, 225.0, -10.0], 300.0);
                let n = prog.ops.len() / 3;
                for (factor, hold) in [(0.4, false), (1.7, false), (1.0, true)] {
                    let (segs, _) = run_with(&prog.ops, &p, shape, n, |pl, cut| {
                        if hold {
                            pl.hold(Some(cut))
                        } else {
                            pl.set_feed_override(factor, Some(cut))
                        }
                    });
                    check(&prog.ops, &segs, &p, shape, factor.max(1.0)).unwrap_or_else(|v| {
                        panic!(
                            "{kind}/{seed} {shape:?} override {factor} hold {hold}:\n{}",
                            v.join("\n")
                        )
                    });
                }
            }
        }
    }
}
