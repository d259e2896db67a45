//! The incremental (firmware-style) planner against independent figures: the whole-job
//! planner's estimate, the closed-form trapezoid, a hold's braking distance, and the
//! acceleration limit over random pushes, holds and override changes.

mod common;
use common::{profile, Lcg, Prog};
use oficina_motion::{estimate, MoveKind, Profile};
use oficina_motion::{Incremental, Push};

const DT: f64 = 1e-4;

fn router() -> Profile {
    profile("grbl-router.toml")
}

fn feed(end: [f64; 3], mm_min: f64) -> Push {
    Push {
        line: 1,
        end,
        speed: mm_min / 60.0,
        kind: MoveKind::Feed,
    }
}

/// A closed polyline of long random segments (look-ahead of a few blocks suffices).
fn polyline(seed: u64, n: usize) -> Vec<[f64; 3]> {
    let mut r = Lcg::new(seed);
    (0..n)
        .map(|_| [r.range(0.0, 200.0), r.range(0.0, 200.0), r.range(-5.0, 0.0)])
        .collect()
}

fn expected(points: &[[f64; 3]], mm_min: f64, p: &Profile) -> f64 {
    let mut prog = Prog::new(mm_min);
    for q in points {
        prog.g1(q[0], q[1], q[2]);
    }
    estimate(prog.ops.into_iter(), p).unwrap().seconds
}

/// Streams `points` keeping at most `buffer` blocks queued; returns the job time.
fn stream(points: &[[f64; 3]], mm_min: f64, p: &Profile, buffer: usize) -> f64 {
    let mut q = Incremental::new(p.clone(), p.start).unwrap();
    let mut next = 0;
    let mut t = 0.0;
    loop {
        while next < points.len() && q.len() < buffer {
            q.push(feed(points[next], mm_min)).unwrap();
            next += 1;
        }
        if q.is_empty() {
            return t;
        }
        let a = q.advance(DT);
        t += DT - a.rest;
        assert!(t < 1e4, "no progress");
    }
}

#[test]
fn whole_job_in_the_buffer_takes_the_estimate() {
    let p = router();
    let pts = polyline(7, 40);
    let want = expected(&pts, 3000.0, &p);
    let got = stream(&pts, 3000.0, &p, usize::MAX);
    assert!((got - want).abs() < 1e-6 * want, "{got} vs {want}");
}

#[test]
fn fifteen_blocks_of_long_segments_take_the_estimate() {
    let p = router();
    let pts = polyline(11, 200);
    let want = expected(&pts, 4000.0, &p);
    let got = stream(&pts, 4000.0, &p, 15);
    assert!((got - want).abs() < 1e-3 * want, "{got} vs {want}");
}

#[test]
fn a_two_block_buffer_slows_short_segments_down() {
    let p = router();
    // 1 mm steps along a gentle zigzag: at 100 mm/s the machine needs ~17 mm to stop.
    let pts: Vec<[f64; 3]> = (1..=300)
        .map(|i| [i as f64, (i % 2) as f64 * 0.01, 0.0])
        .collect();
    let full = stream(&pts, 6000.0, &p, 15);
    let starved = stream(&pts, 6000.0, &p, 2);
    assert!(starved > full * 1.5, "{starved} vs {full}");
}

#[test]
fn position_follows_the_closed_form_trapezoid() {
    let p = router();
    let mut q = Incremental::new(p.clone(), [0.0; 3]).unwrap();
    q.push(feed([100.0, 0.0, 0.0], 6000.0)).unwrap();
    let a = p.joints[0].unwrap().acceleration;
    // 100 mm/s at 300 mm/s² takes 1/3 s; sample at 0.2 s, then the symmetric braking.
    q.advance(0.2);
    assert!(
        (q.position()[0] - 0.5 * a * 0.04).abs() < 1e-9,
        "{:?}",
        q.position()
    );
    assert!((q.speed() - a * 0.2).abs() < 1e-9);
    let total = 100.0 / 100.0 + 100.0 / a;
    let r = q.advance(total - 0.2 - 0.1);
    assert_eq!(r.finished, 0);
    assert!((q.position()[0] - (100.0 - 0.5 * a * 0.01)).abs() < 1e-9);
    let r = q.advance(0.2);
    assert_eq!(r.finished, 1);
    assert!((r.rest - 0.1).abs() < 1e-9);
    assert_eq!(q.position(), [100.0, 0.0, 0.0]);
}

#[test]
fn hold_brakes_at_the_limit_and_resume_finishes_the_job() {
    let p = router();
    let a = p.joints[0].unwrap().acceleration;
    let mut q = Incremental::new(p.clone(), [0.0; 3]).unwrap();
    // Three collinear blocks: the hold's braking runs across a block boundary.
    for x in [40.0, 60.0, 100.0] {
        q.push(feed([x, 0.0, 0.0], 6000.0)).unwrap();
    }
    q.advance(0.5); // cruising at 100 mm/s from 1/3 s on, at x = 33.3
    let x0 = q.position()[0];
    assert!(
        (q.speed() - 100.0).abs() < 1e-9,
        "{} at {:?}",
        q.speed(),
        q.position()
    );
    q.hold();
    let mut t = 0.0;
    while !q.held() {
        q.advance(1e-3);
        t += 1e-3;
        assert!(t < 2.0);
    }
    let stop = 100.0 * 100.0 / (2.0 * a);
    assert!(
        (q.position()[0] - (x0 + stop)).abs() < 1e-6,
        "{:?}",
        q.position()
    );
    assert!((t - 100.0 / a).abs() < 2e-3);
    assert_eq!(q.len(), 2, "stopped inside the second block");
    q.advance(5.0);
    assert!((q.position()[0] - (x0 + stop)).abs() < 1e-6, "stays held");
    q.resume();
    let mut finished = 0;
    for _ in 0..5000 {
        finished += q.advance(1e-3).finished;
    }
    assert_eq!(finished, 2);
    assert_eq!(q.position(), [100.0, 0.0, 0.0]);
}

/// Random pushes, holds, resumes and override changes: inside a block (fixed direction)
/// every joint's sampled acceleration stays within its limit, path speed never jumps, and
/// every block pushed ends.
#[test]
fn random_use_keeps_the_limits() {
    let mut p = router();
    p.junction_deviation = 0.05;
    let a_joint: Vec<f64> = p.joints.iter().flatten().map(|j| j.acceleration).collect();
    let a_path = a_joint.iter().map(|a| a * a).sum::<f64>().sqrt();
    let mut r = Lcg::new(3);
    let mut q = Incremental::new(p.clone(), [0.0; 3]).unwrap();
    let (mut pushed, mut finished) = (0, 0);
    let dt = 1e-3;
    let mut v_prev = 0.0;
    // Positions of the last three samples, and whether a block ended between them.
    let mut hist = [[0.0; 3]; 3];
    let mut ended = [true; 2];
    for step in 0..40_000 {
        let u = r.f();
        if u < 0.05 && q.len() < 15 {
            let end = [r.range(0.0, 50.0), r.range(0.0, 50.0), r.range(-3.0, 0.0)];
            if q.push(feed(end, r.range(100.0, 8000.0))).unwrap() {
                pushed += 1;
            }
        } else if u < 0.052 {
            q.hold();
        } else if u < 0.056 {
            q.resume();
        } else if u < 0.058 {
            q.set_overrides(r.range(0.1, 2.0), 1.0);
        }
        let f = q.advance(dt).finished;
        finished += f;
        let v = q.speed();
        assert!(v <= 150.0, "step {step}: {v} mm/s");
        assert!(
            (v - v_prev).abs() <= a_path * dt + 1e-9,
            "step {step}: {v_prev} → {v}"
        );
        v_prev = v;
        hist = [hist[1], hist[2], q.position()];
        ended = [ended[1], f > 0];
        if ended.iter().any(|e| *e) {
            continue;
        }
        for j in 0..3 {
            let acc = (hist[2][j] - 2.0 * hist[1][j] + hist[0][j]) / (dt * dt);
            assert!(
                acc.abs() <= a_joint[j] * 1.001 + 1e-6,
                "step {step}: joint {j} at {acc} mm/s²"
            );
        }
    }
    q.resume();
    for _ in 0..200_000 {
        if q.is_empty() {
            break;
        }
        finished += q.advance(dt).finished;
    }
    assert_eq!(finished, pushed);
}
