//! Ink/Stitch's ripple stitch and guided fill, from SVGs written as Ink/Stitch writes them
//! and read through `oficina embroider`'s path (strip, import, sew). Checked against the
//! geometry the SVG draws, computed here independently: a ripple of a circle is a spiral of
//! `line_count` turns round the centre, its radius falling by r / line_count a turn; a
//! ripple between two rails is copies on the lines between them; a guided fill's rows are
//! concentric with an arc guide (parallel offset) or shifted copies of a wavy guide (copy),
//! a row spacing apart, and cover the shape.

mod common;

use common::sewn;
use oficina_stitch::{generate_inkstitch, read_inkstitch, Kind, Params, StitchPlan};
use std::f64::consts::PI;

fn doc(body: &str) -> String {
    format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"
        xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
        xmlns:inkstitch="http://inkstitch.org/namespace" width="100mm" height="100mm" viewBox="0 0 100 100">
        <defs><marker id="inkstitch-guide-line-marker" orient="auto" refX="0" refY="0" style="overflow:visible">
          <circle id="guide-dot" r="4" style="fill:#fffffd;stroke:#9d9d9d"/></marker></defs>
        <g id="layer1" inkscape:groupmode="layer">{body}</g></svg>"##
    )
}

fn sew(svg: &str) -> StitchPlan {
    let p = Params {
        center: false,
        ties: false,
        ..Params::default()
    };
    common::sew_inkstitch(svg, &p)
}

fn jumps(plan: &StitchPlan) -> usize {
    plan.entries()
        .filter(|(_, s)| matches!(s.kind, Kind::Jump | Kind::Trim))
        .count()
}

fn longest(pts: &[(f64, f64)]) -> f64 {
    pts.windows(2)
        .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1))
        .fold(0.0, f64::max)
}

fn ripple_circle(extra: &str) -> String {
    format!(
        r#"<circle id="c" cx="50" cy="50" r="20" style="fill:none;stroke:#000;stroke-width:0.1"
           inkstitch:stroke_method="ripple_stitch" inkstitch:running_stitch_length_mm="2" {extra}/>"#
    )
}

/// Turns round (50, 50) swept by the path, and each point's radius.
fn turns(pts: &[(f64, f64)]) -> (f64, Vec<f64>) {
    let ang = |p: &(f64, f64)| (p.1 - 50.0).atan2(p.0 - 50.0);
    let mut total = 0.0;
    for w in pts.windows(2) {
        let mut d = ang(&w[1]) - ang(&w[0]);
        if d > PI {
            d -= 2.0 * PI;
        } else if d < -PI {
            d += 2.0 * PI;
        }
        total += d;
    }
    let r = pts.iter().map(|p| (p.0 - 50.0).hypot(p.1 - 50.0)).collect();
    (total.abs() / (2.0 * PI), r)
}

#[test]
fn a_closed_ripple_is_a_spiral_of_line_count_turns() {
    let plan = sew(&doc(&ripple_circle(r#"inkstitch:line_count="6""#)));
    let pts = sewn(&plan);
    // One connected run: the jump to its start, nothing else.
    assert_eq!(jumps(&plan), 1);
    assert!(longest(&pts) <= 2.0 + 1e-6, "{}", longest(&pts));
    let (n, r) = turns(&pts);
    assert!((n - 6.0).abs() < 0.05, "{n} turns");
    // Nested: the radius never grows (each loop inside the one before), from 20 to 0.
    assert!(r.windows(2).all(|w| w[1] <= w[0] + 0.05), "radius grows");
    assert!(
        (r[0] - 20.0).abs() < 0.05 && r[r.len() - 1] < 0.05,
        "{} {}",
        r[0],
        r[r.len() - 1]
    );
    // A turn later the radius is 20 / 6 smaller: compare each point with the one a turn on.
    let ang = |p: &(f64, f64)| (p.1 - 50.0).atan2(p.0 - 50.0);
    let mut swept = vec![0.0];
    for w in pts.windows(2) {
        let d = (ang(&w[1]) - ang(&w[0]) + 3.0 * PI).rem_euclid(2.0 * PI) - PI;
        swept.push(swept.last().unwrap() + d.abs());
    }
    let mut checked = 0;
    for i in 0..pts.len() {
        if let Some(j) = (i + 1..pts.len()).find(|&j| swept[j] >= swept[i] + 2.0 * PI) {
            // The radius exactly a turn on, between the stitches either side of it.
            let t = (swept[i] + 2.0 * PI - swept[j - 1]) / (swept[j] - swept[j - 1]);
            let drop = r[i] - (r[j - 1] + t * (r[j] - r[j - 1]));
            assert!((drop - 20.0 / 6.0).abs() < 0.15, "at {i}: {drop}");
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked}");
}

#[test]
fn skips_and_reverse_change_where_the_ripple_runs() {
    let pts = sewn(&sew(&doc(&ripple_circle(
        r#"inkstitch:line_count="6" inkstitch:skip_start="2" inkstitch:skip_end="1""#,
    ))));
    let (n, r) = turns(&pts);
    assert!((n - 3.0).abs() < 0.05, "{n} turns");
    assert!((r[0] - 20.0 * 4.0 / 6.0).abs() < 0.05, "{}", r[0]);
    assert!(
        (r[r.len() - 1] - 20.0 / 6.0).abs() < 0.05,
        "{}",
        r[r.len() - 1]
    );
    let pts = sewn(&sew(&doc(&ripple_circle(
        r#"inkstitch:line_count="4" inkstitch:reverse="true""#,
    ))));
    let (_, r) = turns(&pts);
    assert!(r[0] < 0.05 && (r[r.len() - 1] - 20.0).abs() < 0.05);
    // min_line_dist_mm 5: 20 / 5 = 4 turns (even, as the line count 10).
    let pts = sewn(&sew(&doc(&ripple_circle(
        r#"inkstitch:min_line_dist_mm="5""#,
    ))));
    let (n, _) = turns(&pts);
    assert!((n - 4.0).abs() < 0.05, "{n} turns");
}

#[test]
fn a_ripple_grid_adds_the_joins_across_the_copies() {
    // Two rails (SVG y 40 and 60, x 10..70), three copies; a 10 mm grid: the rails cut every
    // 10 mm (x = 10, 20, .., 70) and seven lines across the copies, x constant along each.
    let body = |grid: &str| {
        format!(
            r#"<path id="r" d="M10,40 H70 M10,60 H70" style="fill:none;stroke:#000;stroke-width:0.1"
            inkstitch:stroke_method="ripple_stitch" inkstitch:line_count="3" {grid}/>"#
        )
    };
    let plain = sewn(&sew(&doc(&body(""))));
    let plan = sew(&doc(&body(r#"inkstitch:grid_size_mm="10""#)));
    let pts = sewn(&plan);
    assert_eq!(jumps(&plan), 1);
    assert!(longest(&pts) <= 2.5 + 1e-6);
    // The copies first (as many needle points as without the grid's cut points and more),
    // then the grid: stitches running across (y changes, x does not) at x = 10, 20, .. 70.
    let across: std::collections::BTreeSet<i64> = pts
        .windows(2)
        .filter(|w| (w[0].0 - w[1].0).abs() < 1e-6 && (w[0].1 - w[1].1).abs() > 1e-6)
        .map(|w| w[0].0.round() as i64)
        .collect();
    assert_eq!(
        across.into_iter().collect::<Vec<_>>(),
        [10, 20, 30, 40, 50, 60, 70]
    );
    // The grid's length: seven lines of 20 mm and the six 10 mm steps between them.
    let len = |p: &[(f64, f64)]| {
        p.windows(2)
            .map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1))
            .sum::<f64>()
    };
    let extra = len(&pts) - len(&plain);
    assert!((extra - (7.0 * 20.0 + 6.0 * 10.0)).abs() < 1.0, "{extra}");
    // grid_first: the same stitches the other way round.
    let first = sewn(&sew(&doc(&body(
        r#"inkstitch:grid_size_mm="10" inkstitch:grid_first="true""#,
    ))));
    let mut back = pts.clone();
    back.reverse();
    assert_eq!(first.len(), back.len());
    assert!(first
        .iter()
        .zip(&back)
        .all(|(a, b)| (a.0 - b.0).hypot(a.1 - b.1) < 1e-6));
}

#[test]
fn a_ripple_between_two_rails_sews_copies_back_and_forth() {
    // Rails at SVG y 40 and 60 (drawing y 60 and 40), x 10..70; five copies 5 mm apart.
    let body = r#"<path id="r" d="M10,40 H70 M10,60 H70" style="fill:none;stroke:#000;stroke-width:0.1"
        inkstitch:stroke_method="ripple_stitch" inkstitch:line_count="5" inkstitch:running_stitch_length_mm="2.5"/>"#;
    let plan = sew(&doc(body));
    let pts = sewn(&plan);
    assert_eq!(jumps(&plan), 1);
    assert!(longest(&pts) <= 2.5 + 1e-6);
    let mut ys: Vec<i64> = pts
        .iter()
        .filter(|p| p.0 > 10.5 && p.0 < 69.5)
        .map(|p| (p.1 * 100.0).round() as i64)
        .collect();
    ys.sort();
    ys.dedup();
    assert_eq!(ys, [4000, 4500, 5000, 5500, 6000]);
    // Back and forth: the copies start at alternate ends.
    let mut ends: Vec<f64> = pts
        .windows(2)
        .filter(|w| (w[0].1 - w[1].1).abs() > 1e-6)
        .map(|w| w[0].0)
        .collect();
    ends.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
    assert!(
        ends.len() >= 4 && ends.windows(2).all(|w| (w[0] - w[1]).abs() > 50.0),
        "{ends:?}"
    );
}

#[test]
fn ripple_copies_follow_a_guide_line_and_turn_with_it() {
    // A 10 mm upright line at the start of an L-shaped guide (right 20 mm, then up 20 mm):
    // three copies, at the start, the corner and the end (y up: the guide runs (10, 60) →
    // (30, 60) → (30, 80)). The last copy turns a quarter left about the guide's end.
    let body = |rotate: &str| {
        format!(
            r#"<g id="g1">
              <path id="l" d="M 10,40 V 30" style="fill:none;stroke:#000;stroke-width:0.1"
                inkstitch:stroke_method="ripple_stitch" inkstitch:line_count="3"
                inkstitch:scale_start="100" inkstitch:scale_end="100" inkstitch:rotate_ripples="{rotate}"/>
              <path id="guide" d="M 10,40 H 30 V 20" style="fill:none;stroke:#000;stroke-width:0.2;marker-start:url(#inkstitch-guide-line-marker)"/>
            </g>"#
        )
    };
    let has =
        |pts: &[(f64, f64)], q: (f64, f64)| pts.iter().any(|p| (p.0 - q.0).hypot(p.1 - q.1) < 0.01);
    let pts = sewn(&sew(&doc(&body("true"))));
    for q in [
        (10.0, 60.0),
        (10.0, 70.0),
        (30.0, 60.0),
        (30.0, 70.0),
        (30.0, 80.0),
        (20.0, 80.0),
    ] {
        assert!(has(&pts, q), "{q:?} not sewn: {pts:?}");
    }
    let pts = sewn(&sew(&doc(&body("false"))));
    assert!(
        has(&pts, (30.0, 90.0)) && !has(&pts, (20.0, 80.0)),
        "{pts:?}"
    );
}

/// A 40 × 30 mm rectangle (SVG x 10..50, y 20..50) with a guide line in its group.
fn guided(strategy: u32, guide_d: &str) -> String {
    format!(
        r#"<g id="g1">
          <path id="shape" d="M10,20 H50 V50 H10 Z" style="fill:#00aa00;stroke:none"
                inkstitch:fill_method="guided_fill" inkstitch:guided_fill_strategy="{strategy}"
                inkstitch:row_spacing_mm="0.5" inkstitch:fill_underlay="false"/>
          <path id="guide" d="{guide_d}" style="fill:none;stroke:#000000;stroke-width:0.2;marker-start:url(#inkstitch-guide-line-marker)"/>
        </g>"#
    )
}

/// Whether a stitch touches the rectangle's outline: row ends lie on it, and what joins
/// rows (a turn, or travel along the outline as Ink/Stitch travels) runs from there; the
/// stitches with both ends inside are the rows' own.
fn on_edge(w: &[(f64, f64)]) -> bool {
    let near = |p: &(f64, f64)| {
        (p.0 - 10.0)
            .abs()
            .min((p.0 - 50.0).abs())
            .min((p.1 - 50.0).abs())
            .min((p.1 - 80.0).abs())
            < 0.05
    };
    near(&w[0]) || near(&w[1])
}

/// Distance from `p` to the segments of `line`.
fn to_line(line: &[(f64, f64)], p: (f64, f64)) -> f64 {
    line.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let (vx, vy) = (b.0 - a.0, b.1 - a.1);
            let l2 = vx * vx + vy * vy;
            let t = (((p.0 - a.0) * vx + (p.1 - a.1) * vy) / l2).clamp(0.0, 1.0);
            (p.0 - a.0 - t * vx).hypot(p.1 - a.1 - t * vy)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Share of the rectangle's points (a 0.5 mm grid, 0.3 mm in from the edge) within a row
/// spacing of the thread.
fn coverage(pts: &[(f64, f64)]) -> f64 {
    let mut hit = 0;
    let mut all = 0;
    let mut y = 50.3;
    while y < 80.0 - 0.3 {
        let mut x = 10.3;
        while x < 50.0 - 0.3 {
            all += 1;
            if to_line(pts, (x, y)) <= 0.5 {
                hit += 1;
            }
            x += 0.5;
        }
        y += 0.5;
    }
    hit as f64 / all as f64
}

#[test]
fn parallel_offset_rows_keep_their_distance_from_an_arc_guide() {
    // An arc about (60, 60) of radius 60 (SVG); in the drawing about (60, 40), y up.
    let plan = sew(&doc(&guided(1, "M 0,60 A 60,60 0 0 1 60,0")));
    let pts = sewn(&plan);
    // The guide and its marker are not sewn: the thread stays on the rectangle.
    let b = plan.bounds().unwrap();
    assert!(
        b[0] > 9.9 && b[2] < 50.1 && b[1] > 49.9 && b[3] < 80.1,
        "{b:?}"
    );
    let off = |p: &(f64, f64)| 60.0 - (p.0 - 60.0).hypot(p.1 - 40.0);
    // Every row stitch (the long ones: rows are sewn in 3 mm stitches, turns are 0.5 mm)
    // runs at a whole number of row spacings from the guide.
    let mut rows = std::collections::BTreeSet::new();
    let mut long = 0;
    for w in pts.windows(2) {
        if (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1) < 1.0 || on_edge(w) {
            continue;
        }
        long += 1;
        let (d0, d1) = (off(&w[0]), off(&w[1]));
        let k = (d0 / 0.5).round();
        assert!(
            (d0 - 0.5 * k).abs() < 0.03 && (d1 - 0.5 * k).abs() < 0.03,
            "{w:?}: {d0} {d1}"
        );
        rows.insert(k as i64);
    }
    assert!(long > 500, "{long}");
    // Rows one spacing apart, none missing, from the guide's side of the shape to the other.
    let (lo, hi) = (*rows.first().unwrap(), *rows.last().unwrap());
    assert_eq!(rows.len() as i64, hi - lo + 1);
    // The rectangle reaches from 60 − 64.03 to 60 − 14.14 mm off the arc: rows to 0.5 mm.
    assert!(hi - lo > 80, "{lo}..{hi}");
    // The thread reaches the rectangle's corners nearest and farthest from the arc: 60 −
    // 64.03 and 60 − 14.14 mm off it.
    let (near, far) = pts
        .iter()
        .map(off)
        .fold((f64::MAX, f64::MIN), |(a, b), d| (a.min(d), b.max(d)));
    assert!(
        (near + 4.03).abs() < 0.5 && (far - 45.86).abs() < 0.5,
        "{near} {far}"
    );
    let c = coverage(&pts);
    assert!(c >= 0.95, "coverage {c}");
}

#[test]
fn copy_rows_are_the_guide_shifted_across_its_chord() {
    // A wavy guide from (0, 35) to (60, 35) (SVG): its chord is level, so each row is the
    // guide moved straight up or down by whole row spacings.
    let guide = "M 0,35 C 15,25 25,45 30,35 C 35,25 45,45 60,35";
    let wave: Vec<(f64, f64)> = {
        // The same curve, sampled finely, in the drawing's coordinates (y up).
        let cubic = |p: [(f64, f64); 4], t: f64| {
            let u = 1.0 - t;
            let f = |i: usize| [p[0], p[1], p[2], p[3]].map(|q| if i == 0 { q.0 } else { q.1 });
            let c = |v: [f64; 4]| {
                u * u * u * v[0]
                    + 3.0 * u * u * t * v[1]
                    + 3.0 * u * t * t * v[2]
                    + t * t * t * v[3]
            };
            (c(f(0)), 100.0 - c(f(1)))
        };
        let a = [(0.0, 35.0), (15.0, 25.0), (25.0, 45.0), (30.0, 35.0)];
        let b = [(30.0, 35.0), (35.0, 25.0), (45.0, 45.0), (60.0, 35.0)];
        (0..=400)
            .map(|i| cubic(a, i as f64 / 400.0))
            .chain((1..=400).map(|i| cubic(b, i as f64 / 400.0)))
            .collect()
    };
    let plan = sew(&doc(&guided(0, guide)));
    let pts = sewn(&plan);
    let (mut long, mut off) = (0, 0);
    for w in pts.windows(2) {
        if (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1) < 1.0 || on_edge(w) {
            continue;
        }
        long += 1;
        // Some whole number of spacings down puts both ends of the stitch back on the guide
        // (a stitch is a chord of its row: 0.1 mm of sag allowed).
        let on = (-120..=120).any(|k| {
            let dy = k as f64 * 0.5;
            to_line(&wave, (w[0].0, w[0].1 - dy)) < 0.1
                && to_line(&wave, (w[1].0, w[1].1 - dy)) < 0.1
        });
        if !on {
            off += 1;
            eprintln!("{w:?} is on no shifted copy of the guide");
        }
    }
    // Where a row meets the outline at a glancing angle, the turn to the next row is a long
    // stitch across (Ink/Stitch's too): a few, no more.
    eprintln!("{off} of {long} stitches inside the shape off the rows");
    assert!(
        long > 500 && (off as f64) < 0.02 * long as f64,
        "{off} of {long}"
    );
    let c = coverage(&pts);
    assert!(c >= 0.95, "coverage {c}");
}

#[test]
fn a_guided_fill_without_a_guide_is_sewn_as_rows() {
    let body = r#"<path id="shape" d="M10,20 H50 V50 H10 Z" style="fill:#00aa00;stroke:none"
        inkstitch:fill_method="guided_fill" inkstitch:row_spacing_mm="0.5" inkstitch:fill_underlay="false"/>"#;
    let pts = sewn(&sew(&doc(body)));
    assert!(coverage(&pts) >= 0.95);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 60, ..Default::default() })]

    /// Any ripple parameters, target, guide and fill start/end: sewn or refused with the
    /// element named, never a panic; no stitch longer than the machine's.
    #[test]
    fn any_ripple_or_guided_fill_is_sewn_or_refused(
        count in 0u32..40, skip in 0u32..12, exponent in 0.1f64..4.0,
        min_dist in proptest::option::of(0.01f64..30.0),
        tx in -50.0f64..150.0, ty in -50.0f64..150.0,
        g in proptest::collection::vec((-20.0f64..120.0, -20.0f64..120.0), 1..5),
        strategy in 0u32..2, spacing in 0.2f64..3.0, grid in 0.0f64..8.0,
    ) {
        let guide: String = g.iter().enumerate()
            .map(|(i, (x, y))| format!("{}{x:.3},{y:.3} ", if i == 0 { "M" } else { "L" }))
            .collect();
        let min = min_dist.map(|d| format!(r#"inkstitch:min_line_dist_mm="{d}""#)).unwrap_or_default();
        let body = format!(
            r##"<g id="g1">
              <path id="shape" d="M10,20 H50 V50 H10 Z" style="fill:#00aa00;stroke:none"
                inkstitch:fill_method="guided_fill" inkstitch:guided_fill_strategy="{strategy}"
                inkstitch:row_spacing_mm="{spacing}"/>
              <path id="c" d="M 60,60 C 90,50 95,90 70,95 L 60,60 Z" style="fill:none;stroke:#000;stroke-width:0.1"
                inkstitch:stroke_method="ripple_stitch" inkstitch:line_count="{count}" inkstitch:skip_start="{skip}"
                inkstitch:skip_end="{skip}" inkstitch:exponent="{exponent}" inkstitch:grid_size_mm="{grid}" {min}/>
              <path id="guide" d="{guide}" style="fill:none;stroke:#000;marker-start:url(#inkstitch-guide-line-marker)"/>
              <path id="conn" d="M 0,0 {tx},{ty}" inkscape:connection-start="#use1" inkscape:connection-end="#shape"/>
              <use id="use1" xlink:href="#inkstitch_fill_start" x="0" y="0"/>
              <path id="conn2" d="M 0,0 {ty},{tx}" inkscape:connection-start="#use2" inkscape:connection-end="#c"/>
              <use id="use2" xlink:href="#inkstitch_ripple_target" x="{tx}" y="{ty}"/>
            </g>"##
        );
        let svg = doc(&body);
        let ink = read_inkstitch(&svg, "t.svg").unwrap();
        let text = ink.strip(&svg);
        let no_text = oficina_io::SvgOptions { draw_text: false };
        let d = oficina_io::read_svg(text.as_bytes(), "t.svg", &no_text).unwrap().drawing;
        let p = Params { center: false, ..Params::default() };
        match generate_inkstitch(&d, "t", &p, &ink, &mut |_, _| {}) {
            Ok(g) => {
                let pts = sewn(&g.plan);
                proptest::prop_assert!(!pts.is_empty());
                // Stitches within a colour block, not across a jump.
                for b in &g.plan.blocks {
                    let mut prev: Option<(f64, f64)> = None;
                    for s in &b.stitches {
                        if s.kind == Kind::Stitch {
                            if let Some(q) = prev {
                                proptest::prop_assert!((s.x - q.0).hypot(s.y - q.1) <= p.max_stitch + 1e-6);
                            }
                            prev = Some((s.x, s.y));
                        } else {
                            prev = None;
                        }
                    }
                }
            }
            Err(e) => proptest::prop_assert!(e.0.contains("stitches"), "{e}"),
        }
    }
}

#[test]
fn marked_objects_are_not_sewn_and_the_first_guide_counts() {
    // A second guide (down the page) and a pattern, both far outside the rectangle.
    let body = r#"<g id="g1">
          <path id="shape" d="M10,20 H50 V50 H10 Z" style="fill:#00aa00;stroke:none"
                inkstitch:fill_method="guided_fill" inkstitch:guided_fill_strategy="1"
                inkstitch:row_spacing_mm="0.5" inkstitch:fill_underlay="false"/>
          <path id="guide" d="M 0,35 H 90" style="fill:none;stroke:#000;marker-start:url(#inkstitch-guide-line-marker)"/>
          <path id="guide2" d="M 95,0 V 95" style="fill:none;stroke:#000;marker-start:url(#inkstitch-guide-line-marker)"/>
          <path id="pat" d="M 70,70 H 95" style="fill:none;stroke:#000;marker-start:url(#inkstitch-pattern-marker)"/>
        </g>"#;
    let svg = doc(body);
    let ink = read_inkstitch(&svg, "t.svg").unwrap();
    assert!(
        ink.notes
            .iter()
            .any(|n| n.contains("#pat") && n.contains("pattern")),
        "{:?}",
        ink.notes
    );
    let plan = sew(&svg);
    let b = plan.bounds().unwrap();
    assert!(
        b[0] > 9.9 && b[2] < 50.1 && b[1] > 49.9 && b[3] < 80.1,
        "{b:?}"
    );
    // The first guide is level: every row stitch inside the shape is level too.
    let pts = sewn(&plan);
    let level = pts
        .windows(2)
        .filter(|w| !on_edge(w) && (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1) > 1.0)
        .all(|w| (w[0].1 - w[1].1).abs() < 1e-6);
    assert!(level);
}
