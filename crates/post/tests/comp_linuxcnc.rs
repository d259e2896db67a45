//! Item 8: cutter radius compensation. A profile posted with G41 D1 on the part outline,
//! run by LinuxCNC's `rs274` and by Oficina's interpreter with the tool table giving T1's
//! diameter, cuts the same tool-centre path as Oficina's own offset path for that contour.

use oficina_cam::ops::{profile, Comp, Cut, Entry, ProfileParams, Side};
use oficina_cam::{Move, Operation, Tool, Toolpath};
use oficina_canon::CanonOp;
use oficina_geom::{Arc, Path, Point, Segment};
use oficina_post::{program_text, read_back_with_tools, PostDialect, PostOptions};
use oficina_testkit::shapes::dumbbell;
use std::f64::consts::TAU;

type P3 = [f64; 3];

/// A feed move: straight, or an arc about a centre (turns > 0 counter-clockwise).
#[derive(Clone, Copy, Debug)]
enum Feed {
    Line(P3, P3),
    Arc(P3, P3, [f64; 2], bool),
}

impl Feed {
    /// Points every ~0.05 mm along the move.
    fn samples(&self) -> Vec<P3> {
        match *self {
            Feed::Line(a, b) => {
                let n = ((b[0] - a[0]).hypot(b[1] - a[1]) / 0.05).ceil().max(1.0) as usize;
                (0..=n)
                    .map(|k| {
                        let t = k as f64 / n as f64;
                        [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * t)
                    })
                    .collect()
            }
            Feed::Arc(a, b, c, ccw) => {
                let r = (a[0] - c[0]).hypot(a[1] - c[1]);
                let a0 = (a[1] - c[1]).atan2(a[0] - c[0]);
                let a1 = (b[1] - c[1]).atan2(b[0] - c[0]);
                let mut sweep = if ccw {
                    (a1 - a0).rem_euclid(TAU)
                } else {
                    -(a0 - a1).rem_euclid(TAU)
                };
                if sweep.abs() < 1e-9 {
                    sweep = if ccw { TAU } else { -TAU };
                }
                let n = (r * sweep.abs() / 0.05).ceil().max(1.0) as usize;
                (0..=n)
                    .map(|k| {
                        let t = k as f64 / n as f64;
                        let ang = a0 + sweep * t;
                        [
                            c[0] + r * ang.cos(),
                            c[1] + r * ang.sin(),
                            a[2] + (b[2] - a[2]) * t,
                        ]
                    })
                    .collect()
            }
        }
    }
    fn end(&self) -> P3 {
        match *self {
            Feed::Line(_, b) | Feed::Arc(_, b, _, _) => b,
        }
    }
}

/// A plate with a rounded end (convex and concave corners, an arc side).
fn plate() -> Vec<Path> {
    vec![Path::new(
        vec![
            Segment::line(Point::new(0.0, 0.0), Point::new(40.0, 0.0)),
            Segment::Arc(Arc::from_center(
                Point::new(40.0, 0.0),
                Point::new(40.0, 30.0),
                Point::new(40.0, 15.0),
                1,
            )),
            Segment::line(Point::new(40.0, 30.0), Point::new(20.0, 30.0)),
            Segment::line(Point::new(20.0, 30.0), Point::new(20.0, 20.0)),
            Segment::line(Point::new(20.0, 20.0), Point::new(0.0, 20.0)),
            Segment::line(Point::new(0.0, 20.0), Point::new(0.0, 0.0)),
        ],
        true,
    )]
}

fn cut() -> Cut {
    Cut {
        tool_number: 1,
        tool: "flat:6".parse::<Tool>().unwrap(),
        spindle_rpm: 12000.0,
        feed: 800.0 / 60.0,
        plunge_feed: 300.0 / 60.0,
        top: 0.0,
        depth: 3.0,
        stepdown: 1.5,
        clear_z: 5.0,
        entry: Entry::Ramp { angle: 3.0 },
    }
}

fn opts(dialect: PostDialect) -> PostOptions {
    PostOptions {
        dialect,
        allow_m6: true,
        title: "comp".into(),
        settings: vec![],
    }
}

fn op(paths: &[Path], side: Side, comp: Comp) -> Toolpath {
    let p = ProfileParams {
        side,
        allowance: 0.0,
        tabs: None,
        lead_out: 2.0,
        lead_in: 3.0,
        comp,
    };
    let o: Operation = profile("p", paths, &cut(), &p).unwrap();
    Toolpath {
        safe_z: 20.0,
        operations: vec![o],
    }
}

/// The toolpath's own feed moves (tool centre).
fn own_feeds(tp: &Toolpath) -> Vec<Feed> {
    let mut at = [0.0, 0.0, tp.safe_z];
    let mut out = vec![];
    for m in &tp.operations[0].moves {
        match *m {
            Move::Line { to, .. } => out.push(Feed::Line(at, to)),
            Move::Arc {
                to, center, ccw, ..
            } => out.push(Feed::Arc(at, to, center, ccw)),
            _ => {}
        }
        if let Some(e) = m.end() {
            at = e;
        }
    }
    out
}

/// Feed moves as Oficina's interpreter reads the program with T1 = 6 mm.
fn interp_feeds(text: &str, o: &PostOptions) -> Vec<Feed> {
    let canon = read_back_with_tools(text, o, &[(1, 6.0)]).unwrap();
    let mut at = [0.0; 3];
    let mut out = vec![];
    for c in canon {
        match c.op {
            CanonOp::StraightTraverse { to } => at = [to.x, to.y, to.z],
            CanonOp::StraightFeed { to } => {
                let e = [to.x, to.y, to.z];
                out.push(Feed::Line(at, e));
                at = e;
            }
            CanonOp::ArcFeed {
                end, center, turns, ..
            } => {
                let e = [end.x, end.y, end.z];
                out.push(Feed::Arc(at, e, center, turns > 0));
                at = e;
            }
            _ => {}
        }
    }
    out
}

/// Feed move ends as LinuxCNC's `rs274` runs the program with T1 = 6 mm.
fn rs274_feed_ends(text: &str) -> Vec<P3> {
    // Without an INI file rs274 reads the tool table in inches.
    let table = format!("T1 P1 D{:.10} Z0\n", 6.0 / 25.4);
    let stdout = oficina_testkit::rs274::accepts(text, Some(&table));
    let mut ends = vec![];
    for line in stdout.lines() {
        let args = |name: &str| -> Option<Vec<f64>> {
            let k = line.find(name)?;
            let inner = &line[k + name.len() + 1..line.rfind(')')?];
            Some(
                inner
                    .split(',')
                    .map(|v| v.trim().parse().unwrap())
                    .collect(),
            )
        };
        if let Some(v) = args("STRAIGHT_FEED") {
            ends.push([v[0], v[1], v[2]]);
        } else if let Some(v) = args("ARC_FEED") {
            ends.push([v[0], v[1], v[5]]);
        }
    }
    ends
}

fn dist_xy(p: P3, q: P3) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

fn seg_dist(p: P3, a: P3, b: P3) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let dd = d[0] * d[0] + d[1] * d[1];
    let t = if dd > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
}

/// Greatest XY distance from a cutting sample (below the top) of `a` to the path `b`
/// (its moves as chords 0.05 mm long: at most 0.05²/(8·3) ≈ 1e-4 mm off a 3 mm arc). Z is
/// left out: ramps descend over programmed lengths, which differ between the outline and
/// the tool centre; the floors are compared by the caller.
fn deviation(a: &[Feed], b: &[Feed]) -> f64 {
    let chords: Vec<(P3, P3)> = b
        .iter()
        .flat_map(|f| {
            let s = f.samples();
            s.windows(2).map(|w| (w[0], w[1])).collect::<Vec<_>>()
        })
        .collect();
    let mut worst: f64 = 0.0;
    for p in a.iter().flat_map(Feed::samples).filter(|p| p[2] < -1e-6) {
        let d = chords
            .iter()
            .map(|&(u, v)| seg_dist(p, u, v))
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d);
    }
    worst
}

fn lowest(f: &[Feed]) -> f64 {
    f.iter().map(|m| m.end()[2]).fold(f64::INFINITY, f64::min)
}

#[test]
fn linuxcnc_comp_cuts_oficinas_offset_path() {
    for (paths, side) in [
        (plate(), Side::Outside),
        (plate(), Side::Inside),
        (dumbbell(), Side::Outside),
        (dumbbell(), Side::Inside),
    ] {
        let o = opts(PostDialect::LinuxCnc);
        let ctrl = op(&paths, side, Comp::Control);
        let text = program_text(&ctrl, &o).unwrap();
        assert!(text.contains("G41 D1") && text.contains("G40"), "{text}");
        let read = interp_feeds(&text, &o);
        // rs274 and Oficina's interpreter agree move by move.
        let ends = rs274_feed_ends(&text);
        assert_eq!(
            ends.len(),
            read.len(),
            "{side:?}: feed moves differ\n{text}"
        );
        for (k, (e, f)) in ends.iter().zip(&read).enumerate() {
            let g = f.end();
            assert!(
                dist_xy(*e, g) < 1e-3 && (e[2] - g[2]).abs() < 1e-3,
                "{side:?} move {k}: rs274 {e:?}, Oficina {g:?}"
            );
        }
        // And the compensated path is Oficina's own offset path, both ways (the
        // straight comp exit move, last before each G40, is not in the offset path).
        let own = own_feeds(&op(&paths, side, Comp::Computer));
        let exit_dropped: Vec<Feed> = read[..read.len() - 1].to_vec();
        let there = deviation(&exit_dropped, &own);
        let back = deviation(&own, &read);
        eprintln!("{side:?}: comp → own {there:.5} mm, own → comp {back:.5} mm");
        assert!(there < 1e-3 && back < 1e-3, "{side:?}: {there} / {back}");
        assert!((lowest(&read) - lowest(&own)).abs() < 1e-9);
    }
}

#[test]
fn sinumerik_comp_reads_back_and_grbl_refuses() {
    let ctrl = op(&plate(), Side::Outside, Comp::Control);
    let o = opts(PostDialect::Sinumerik);
    let text = program_text(&ctrl, &o).unwrap();
    assert!(text.lines().any(|l| l.contains("G41")), "{text}");
    let read = interp_feeds(&text, &o);
    let own = own_feeds(&op(&plate(), Side::Outside, Comp::Computer));
    let there = deviation(&read[..read.len() - 1], &own);
    assert!(there < 2e-3, "sinumerik comp path off by {there}");
    let mut buf = Vec::new();
    let err = oficina_post::write_program(&ctrl, &opts(PostDialect::Grbl), &mut buf).unwrap_err();
    assert!(err.to_string().contains("compensation"), "{err}");
}
