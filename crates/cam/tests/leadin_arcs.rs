//! Item 7: the lead-in arc of a profile joins each loop tangentially from the waste side
//! (outside a part, inside a hole) and never comes nearer the drawn wall than the tool
//! radius.

use oficina_cam::ops::{profile, Comp, Cut, Entry, ProfileParams, Side};
use oficina_cam::{Move, Tool};
use oficina_geom::{Arc, Path, Point, Segment};
use oficina_testkit::shapes::dumbbell;

fn disc() -> Vec<Path> {
    vec![Path::new(
        vec![Segment::Arc(Arc::circle(Point::new(10.0, 10.0), 9.0))],
        true,
    )]
}

fn cut(entry: Entry) -> Cut {
    Cut {
        tool_number: 1,
        tool: "flat:6".parse::<Tool>().unwrap(),
        spindle_rpm: 12000.0,
        feed: 10.0,
        plunge_feed: 4.0,
        top: 0.0,
        depth: 4.0,
        stepdown: 2.0,
        clear_z: 5.0,
        entry,
    }
}

fn unit(v: [f64; 2]) -> [f64; 2] {
    let n = v[0].hypot(v[1]);
    [v[0] / n, v[1] / n]
}

/// XY direction of an arc about `c` at point `p`.
fn arc_dir(c: [f64; 2], p: [f64; 2], ccw: bool) -> [f64; 2] {
    let v = [p[0] - c[0], p[1] - c[1]];
    unit(if ccw { [-v[1], v[0]] } else { [v[1], -v[0]] })
}

fn seg_dist(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let t = (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]))
        .clamp(0.0, 1.0);
    (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
}

fn ring_of(paths: &[Path]) -> Vec<[f64; 2]> {
    paths[0].flatten(1e-4).iter().map(|p| [p.x, p.y]).collect()
}

fn inside(ring: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut c = false;
    for i in 0..ring.len() {
        let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0])
        {
            c = !c;
        }
    }
    c
}

/// Every lead-in (an arc right after a rapid): tangent join, waste side, ≥ r from the wall.
fn check(paths: &[Path], side: Side, entry: Entry, allowance: f64) -> usize {
    let c = cut(entry);
    let r = c.radius();
    let p = ProfileParams {
        side,
        allowance,
        tabs: None,
        lead_out: 0.0,
        lead_in: r,
        comp: Comp::Computer,
    };
    let op = profile("t", paths, &c, &p).unwrap();
    let ring = ring_of(paths);
    let mut found = 0;
    let mut at = [f64::NAN; 3];
    let ms = &op.moves;
    for i in 0..ms.len() {
        if let (
            Some(prev),
            Move::Arc {
                to, center, ccw, ..
            },
        ) = (i.checked_sub(1).map(|k| &ms[k]), &ms[i])
        {
            // The plunge (with Entry::Plunge) is a vertical line after the rapids.
            let after_travel = matches!(prev, Move::Rapid { .. })
                || (entry == Entry::Plunge
                    && matches!(prev, Move::Line { .. })
                    && matches!(ms[i - 2], Move::Rapid { to: t } if t[0] == at[0] && t[1] == at[1]));
            if after_travel {
                found += 1;
                assert!(*ccw, "the lead-in turns towards the waste side (left)");
                let end = [to[0], to[1]];
                let d_in = arc_dir(*center, end, *ccw);
                let d_next = match &ms[i + 1] {
                    Move::Line { to: t, .. } => unit([t[0] - end[0], t[1] - end[1]]),
                    Move::Arc {
                        center: c2, ccw: w, ..
                    } => arc_dir(*c2, end, *w),
                    m => panic!("after the lead-in: {m:?}"),
                };
                assert!(
                    (d_in[0] - d_next[0]).abs() < 1e-6 && (d_in[1] - d_next[1]).abs() < 1e-6,
                    "{side:?}: not tangent at {end:?}: {d_in:?} then {d_next:?}"
                );
                // Sample the arc from its start (the point reached before it) to its end.
                let start = [at[0], at[1]];
                let a0 = (start[1] - center[1]).atan2(start[0] - center[0]);
                let rad = (start[0] - center[0]).hypot(start[1] - center[1]);
                assert!(rad > 0.3, "lead-in radius {rad}");
                for k in 0..=64 {
                    let ang = a0 + std::f64::consts::FRAC_PI_2 * k as f64 / 64.0;
                    let q = [center[0] + rad * ang.cos(), center[1] + rad * ang.sin()];
                    let wall = (0..ring.len())
                        .map(|j| seg_dist(q, ring[j], ring[(j + 1) % ring.len()]))
                        .fold(f64::INFINITY, f64::min);
                    assert!(wall >= r - 2e-3, "{side:?}: {q:?} is {wall} from the wall");
                    assert_eq!(
                        inside(&ring, q),
                        side == Side::Inside,
                        "{side:?}: {q:?} on the part side"
                    );
                }
            }
        }
        if let Some(e) = ms[i].end() {
            at = e;
        }
    }
    found
}

#[test]
fn lead_in_is_tangent_and_on_the_waste_side() {
    for entry in [
        Entry::Ramp { angle: 3.0 },
        Entry::Plunge,
        Entry::Helix {
            radius: 2.0,
            angle: 5.0,
        },
    ] {
        for side in [Side::Outside, Side::Inside] {
            for allowance in [0.0, 0.3] {
                let n = check(&dumbbell(), side, entry, allowance);
                // One loop, plus one for the finishing pass when there is an allowance.
                let want = if allowance > 0.0 { 2 } else { 1 };
                assert_eq!(n, want, "{side:?} {entry:?} allowance {allowance}");
                assert_eq!(check(&disc(), side, entry, allowance), want);
            }
        }
    }
}

#[test]
fn lead_in_too_big_for_a_hole_shrinks_or_is_left_out() {
    // A 7 mm hole radius leaves a 4 mm tool-centre circle: a 20 mm arc cannot fit, a
    // smaller one does.
    let c = cut(Entry::Ramp { angle: 3.0 });
    let paths = vec![Path::new(
        vec![Segment::Arc(Arc::circle(Point::new(0.0, 0.0), 7.0))],
        true,
    )];
    let p = ProfileParams {
        side: Side::Inside,
        allowance: 0.0,
        tabs: None,
        lead_out: 0.0,
        lead_in: 20.0,
        comp: Comp::Computer,
    };
    let op = profile("t", &paths, &c, &p).unwrap();
    for m in &op.moves {
        if let Some(e) = m.end() {
            assert!(
                e[0].hypot(e[1]) <= 4.0 + 1e-6,
                "left the hole's tool-centre disc: {e:?}"
            );
        }
    }
    let bad = ProfileParams {
        lead_in: f64::NAN,
        ..p
    };
    assert!(profile("t", &paths, &c, &bad).is_err());
}
