//! G5 / G5.1 / G5.2…G5.3 downstream: after its `NurbsFeed` each curve is straight feeds
//! through points on the curve, within the G64 P tolerance (or 0.01 mm), compared here with
//! the Bézier / rational curve computed independently from the block's words. (The calls
//! themselves are compared with rs274 by the differential corpus, `tests/corpus/spline_*`.)

use oficina_canon::{Canon, CanonOp, FeedMode};
use oficina_gcode::{canon_of, Dialect, RunOptions};

fn run(text: &str) -> Vec<Canon> {
    let (ops, diags) = canon_of(text, &RunOptions::check(Dialect::LinuxCnc));
    assert!(diags.is_empty(), "{diags:?}");
    ops
}

/// The XY points of the feeds that trace each spline, start point first.
fn curves(ops: &[Canon]) -> Vec<(u32, Vec<[f64; 2]>)> {
    let mut out = Vec::new();
    let mut last = [0.0, 0.0];
    let mut i = 0;
    while i < ops.len() {
        match &ops[i].op {
            CanonOp::NurbsFeed {
                control_points,
                segments,
            } => {
                let mut pts = vec![last];
                for op in &ops[i + 1..=i + *segments as usize] {
                    let CanonOp::StraightFeed { to } = op.op else {
                        panic!("a spline is traced by straight feeds: {op:?}");
                    };
                    pts.push([to.x, to.y]);
                }
                last = *pts.last().unwrap();
                out.push((*control_points, pts));
                i += *segments as usize + 1;
                continue;
            }
            CanonOp::StraightFeed { to }
            | CanonOp::StraightTraverse { to }
            | CanonOp::ArcFeed { end: to, .. } => last = [to.x, to.y],
            _ => {}
        }
        i += 1;
    }
    out
}

fn bezier(p: &[[f64; 2]], t: f64) -> [f64; 2] {
    // de Casteljau: independent of the interpreter's B-spline evaluation.
    let mut q = p.to_vec();
    while q.len() > 1 {
        q = q
            .windows(2)
            .map(|w| {
                [
                    w[0][0] + t * (w[1][0] - w[0][0]),
                    w[0][1] + t * (w[1][1] - w[0][1]),
                ]
            })
            .collect();
    }
    q[0]
}

fn distance_to_polyline(q: [f64; 2], path: &[[f64; 2]]) -> f64 {
    path.windows(2)
        .map(|s| {
            let (a, b) = (s[0], s[1]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let l2 = dx * dx + dy * dy;
            let t = if l2 > 0.0 {
                (((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (q[0] - a[0] - t * dx).hypot(q[1] - a[1] - t * dy)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Every sampled point of the curve is within `tol` of the path, and every path point is on
/// the curve (not on its control polygon).
fn assert_follows(path: &[[f64; 2]], curve: impl Fn(f64) -> [f64; 2], tol: f64) {
    assert_eq!(path[0], curve(0.0));
    let end = curve(1.0);
    let last = path.last().unwrap();
    assert!((last[0] - end[0]).abs() < 1e-9 && (last[1] - end[1]).abs() < 1e-9);
    for i in 0..=2000 {
        let q = curve(i as f64 / 2000.0);
        let d = distance_to_polyline(q, path);
        assert!(d <= tol * 1.001, "curve point {q:?} is {d} from the path");
    }
    let fine: Vec<[f64; 2]> = (0..=20000).map(|i| curve(i as f64 / 20000.0)).collect();
    for p in path {
        let d = distance_to_polyline(*p, &fine);
        assert!(d < 1e-4, "path point {p:?} is off the curve by {d}");
    }
}

#[test]
fn g5_and_g5_1_follow_their_bezier_within_the_default_tolerance() {
    let ops = run("G21 G17 G90 F300\nG0 X0 Y0\nG5 I0 J10 P0 Q-10 X20 Y0\nG5.1 X30 Y0 I5 J8\nM2\n");
    let c = curves(&ops);
    assert_eq!(c.len(), 2);
    assert_eq!(c[0].0, 4);
    assert!(c[0].1.len() > 8, "{} points", c[0].1.len());
    let cubic = [[0.0, 0.0], [0.0, 10.0], [20.0, -10.0], [20.0, 0.0]];
    assert_follows(&c[0].1, |t| bezier(&cubic, t), 0.01);
    assert_eq!(c[1].0, 3);
    let quad = [[20.0, 0.0], [25.0, 8.0], [30.0, 0.0]];
    assert_follows(&c[1].1, |t| bezier(&quad, t), 0.01);
}

#[test]
fn g64_p_is_the_tolerance_and_a_coarser_one_takes_fewer_feeds() {
    let prog = |p: &str| format!("G21 G17 G90 F300 {p}\nG0 X0 Y0\nG5 I0 J30 P0 Q-30 X50 Y0\nM2\n");
    let fine = curves(&run(&prog("G64 P0.001")));
    let coarse = curves(&run(&prog("G64 P0.5")));
    let cubic = [[0.0, 0.0], [0.0, 30.0], [50.0, -30.0], [50.0, 0.0]];
    assert_follows(&fine[0].1, |t| bezier(&cubic, t), 0.001);
    assert_follows(&coarse[0].1, |t| bezier(&cubic, t), 0.5);
    assert!(coarse[0].1.len() * 4 < fine[0].1.len());
}

#[test]
fn a_nurbs_quarter_circle_stays_on_its_circle_and_the_next_move_starts_at_its_end() {
    // Rational quadratic with weights 1, √½, 1: a quarter of the circle of radius 10.
    let ops = run(
        "G21 G17 G90 F300\nG0 X10 Y0\nG5.2 X10 Y10 P0.70710678118654757 L3\nX0 Y10 P1\nG5.3\nG1 X-5\nM2\n",
    );
    let c = curves(&ops);
    assert_eq!(c[0].0, 3);
    for p in &c[0].1 {
        assert!((p[0].hypot(p[1]) - 10.0).abs() < 1e-9, "{p:?}");
    }
    let CanonOp::StraightFeed { to } = ops.iter().rev().find(|o| o.op.is_motion()).unwrap().op
    else {
        panic!()
    };
    assert_eq!((to.x, to.y), (-5.0, 10.0));
}

#[test]
fn spline_errors_name_their_line_and_word() {
    let opts = RunOptions::check(Dialect::LinuxCnc);
    let (_, d) = canon_of("G21 F100\nG5.1 X1 Y1 I1\nM2\n", &opts);
    assert_eq!(d[0].message, "Must specify both I and J with G5.1");
    assert_eq!((d[0].span.line, d[0].span.col), (2, 1));
    let (_, d) = canon_of("G21 F100\nG5 I1 J1 P1 Q1 X1 Y1 Z2\nM2\n", &opts);
    assert_eq!((d[0].span.line, d[0].span.col), (2, 22));
    // grbl has no splines: refused with its number and a hint.
    let (_, d) = canon_of(
        "G21 F100\nG5.1 X1 Y1 I1 J0\nM2\n",
        &RunOptions::check(Dialect::Grbl),
    );
    assert_eq!(d[0].code, Some(20));
    assert!(
        d[0].help.as_deref().unwrap().contains("arcs and lines"),
        "{d:?}"
    );
}

#[test]
fn under_g93_the_whole_curve_takes_one_over_f_minutes() {
    let ops = run("G21 G17 G90 G93\nG0 X0 Y0\nG5 I0 J10 P0 Q-10 X20 Y0 F2\nG94 F100 G1 X30\nM2\n");
    let at = ops
        .iter()
        .position(|c| matches!(c.op, CanonOp::NurbsFeed { .. }))
        .unwrap();
    let CanonOp::NurbsFeed { segments, .. } = ops[at].op else {
        unreachable!()
    };
    // Each traced feed is preceded by its rate; the minutes 1/rate add up to 1/F.
    let body = &ops[at + 1..at + 1 + 2 * segments as usize];
    let mut minutes = 0.0;
    for pair in body.chunks(2) {
        let (CanonOp::SetFeedRate(rate), CanonOp::StraightFeed { .. }) = (&pair[0].op, &pair[1].op)
        else {
            panic!("{pair:?}");
        };
        minutes += 1.0 / rate;
    }
    assert!((minutes - 0.5).abs() < 1e-9, "{minutes}");
}

/// The program run with splines traced (the default) and kept whole.
fn traced_and_whole(text: &str) -> (Vec<Canon>, Vec<Canon>) {
    let mut opts = RunOptions::check(Dialect::LinuxCnc);
    let (traced, d) = canon_of(text, &opts);
    assert!(d.is_empty(), "{d:?}");
    opts.whole_splines = true;
    let (whole, d) = canon_of(text, &opts);
    assert!(d.is_empty(), "{d:?}");
    (traced, whole)
}

#[test]
fn a_spline_kept_whole_traces_to_the_feeds_of_a_traced_run_under_rotation_and_g93() {
    // Rotated work offset, G92 shift, inverse time: the whole curve is in machine
    // coordinates, its trace follows the Bézier of the machine images of the control points.
    let text = "G21 G17 G90\nG10 L2 P1 X5 Y-3 R30\nG54 G92 X1 Y1\nG0 X1 Y1\n\
                G5 I0 J10 P0 Q-10 X21 Y1 F400\nG93 G5.1 X30 Y1 I5 J8 F3\n\
                G94 F500 G5.2 X30 Y10 P0.7 L3\nX40 Y10 P1\nX45 Y0 P2\nG5.3\nG1 X50\nM2\n";
    let (traced, whole) = traced_and_whole(text);
    let mut expanded = Vec::new();
    for c in &whole {
        match &c.op {
            CanonOp::Spline(curve) => curve.trace(|op| expanded.push(Canon { line: c.line, op })),
            _ => expanded.push(c.clone()),
        }
    }
    let splines = whole
        .iter()
        .filter(|c| matches!(c.op, CanonOp::Spline(_)))
        .count();
    assert_eq!(splines, 3);
    assert!(!whole
        .iter()
        .any(|c| matches!(c.op, CanonOp::NurbsFeed { .. })));
    assert_eq!(expanded.len(), traced.len());
    for (a, b) in expanded.iter().zip(&traced) {
        assert_eq!(a.line, b.line);
        match (&a.op, &b.op) {
            (CanonOp::StraightFeed { to: p }, CanonOp::StraightFeed { to: q }) => {
                assert!(p.dist_xyz(q) < 1e-9 && p.a == q.a, "{p:?} / {q:?}");
            }
            (CanonOp::SetFeedRate(f), CanonOp::SetFeedRate(g)) => {
                assert!((f - g).abs() <= 1e-9 * g.abs(), "{f} / {g}")
            }
            (x, y) => assert_eq!(x, y),
        }
    }
    // G92 made program (1, 1) the machine origin, so the control points (1,1) (1,11)
    // (21,-9) (21,1) are, in the machine, (0,0) (0,10) (20,-10) (20,0) turned by 30°.
    let (s, c) = 30f64.to_radians().sin_cos();
    let machine = |p: [f64; 2]| [p[0] * c - p[1] * s, p[0] * s + p[1] * c];
    let mut cubic = [[0.0, 0.0], [0.0, 10.0], [20.0, -10.0], [20.0, 0.0]].map(machine);
    let g93 = traced
        .iter()
        .position(|c| c.op == CanonOp::SetFeedMode(FeedMode::InverseTime))
        .unwrap();
    let c0 = &curves(&traced[..g93])[0];
    let start = c0.1[0];
    assert!(
        (start[0] - cubic[0][0]).hypot(start[1] - cubic[0][1]) < 1e-9,
        "{start:?}"
    );
    cubic[0] = start; // the machine origin within rounding of the G92 chain
    assert_follows(&c0.1, |t| bezier(&cubic, t), 0.01);
}

#[test]
fn a_spline_kept_whole_prints_the_same_rs274_text() {
    let text = "G20 G17 G90 F20\nG10 L2 P1 X0.2 R15\nG54 G0 X1 Y1\nG5 I0 J1 P0 Q-1 X2 Y1\n\
                G93 G5.1 X3 Y1 I0.5 J0.8 F4\nG1 X4 F2\nM2\n";
    let (traced, whole) = traced_and_whole(text);
    let print = |ops: &[Canon]| {
        let mut printer = oficina_gcode::Rs274Printer::new();
        let mut out = Vec::new();
        for c in ops {
            printer.print(c, &mut out).unwrap();
        }
        String::from_utf8(out).unwrap()
    };
    let text = print(&traced);
    assert_eq!(text.matches("NURBS_FEED(").count(), 2);
    assert_eq!(print(&whole), text);
}

#[test]
fn the_time_estimate_of_a_whole_spline_is_that_of_its_trace_and_of_the_curve() {
    // 600 mm/min along the cubic: its length (sampled finely here, independently of the
    // flattening) over 10 mm/s, whichever form of the spline the estimate is given.
    let text = "G21 G17 G90 F600\nG0 X0 Y0\nG5 I0 J10 P0 Q-10 X20 Y0\nM2\n";
    let (traced, whole) = traced_and_whole(text);
    let summary = |ops: &[Canon]| {
        let mut s = oficina_canon::Summarizer::new(oficina_canon::Pos::ZERO, [6000.0; 3]);
        for c in ops {
            s.add(&c.op);
        }
        s.finish()
    };
    let (t, w) = (summary(&traced), summary(&whole));
    assert_eq!((w.feed_moves, w.feed_length), (t.feed_moves, t.feed_length));
    assert_eq!(w.feed_moves, 1);
    let cubic = [[0.0, 0.0], [0.0, 10.0], [20.0, -10.0], [20.0, 0.0]];
    let length: f64 = (0..100_000)
        .map(|i| {
            let (a, b) = (
                bezier(&cubic, i as f64 / 1e5),
                bezier(&cubic, (i + 1) as f64 / 1e5),
            );
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .sum();
    // Chords within 0.01 mm of the curve are at most a little shorter than it.
    assert!(
        w.feed_length <= length && w.feed_length > length * 0.999,
        "{} / {length}",
        w.feed_length
    );
    assert!((w.feed_rate_seconds - w.feed_length / 10.0).abs() < 1e-9);
}
