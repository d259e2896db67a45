//! Arcs in the XZ and YZ planes under a rotated coordinate system (`G10 L2 … R`): the
//! interpreter's circle is the program's circle carried rigidly into machine space (turned
//! about Z and shifted). The planner's pieces and the simulator's cut must stay on it; the
//! circle here is computed by hand from the program's numbers, not taken from canon.

use oficina_cam::{CutterShape, Tool};
use oficina_canon::{Canon, CanonOp};
use oficina_gcode::{canon_of, RunOptions};
use oficina_io::Heightmap;
use oficina_motion::{plan, resolve, PlanOptions, SegmentKind, StepGenerator, StepLog};
use std::collections::HashMap;

/// A program point in machine coordinates: turned by `deg` about Z, then shifted by `off`.
fn to_machine(p: [f64; 3], deg: f64, off: [f64; 3]) -> [f64; 3] {
    let (s, c) = deg.to_radians().sin_cos();
    [
        p[0] * c - p[1] * s + off[0],
        p[0] * s + p[1] * c + off[1],
        p[2] + off[2],
    ]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// A circle in machine space: centre, radius, unit normal.
struct Circle {
    c: [f64; 3],
    r: f64,
    n: [f64; 3],
}

impl Circle {
    /// (distance from the circle's plane, |distance from the centre − r|).
    fn miss(&self, p: [f64; 3]) -> (f64, f64) {
        let d = sub(p, self.c);
        let off_plane = dot(d, self.n);
        let in_plane = (dot(d, d) - off_plane * off_plane).max(0.0).sqrt();
        (off_plane.abs(), (in_plane - self.r).abs())
    }
}

fn canon(text: &str) -> Vec<Canon> {
    let (ops, diags) = canon_of(text, &RunOptions::default());
    assert!(diags.is_empty(), "{diags:?}");
    ops
}

#[test]
fn planned_pieces_of_rotated_xz_and_yz_arcs_stay_on_the_interpreters_circle() {
    let (deg, off) = (30.0, [100.0, 120.0, -20.0]);
    let program = "G21 G90 G17\n\
                   G10 L2 P1 X100 Y120 Z-20 R30\n\
                   G54 G0 X0 Y0 Z10\n\
                   G1 Z0 F600\n\
                   G18 G2 X20 Z0 I10 K0\n\
                   G19 G3 Y20 Z0 J10 K0\n\
                   G18 G3 X0 Z0 I-10 K0 Y25\n\
                   M2\n";
    let ops = canon(program);
    // Line 5: XZ circle about program (10, 0, 0), normal program Y; line 6: YZ circle about
    // (20, 10, 0), normal program X; line 7: an XZ helix rising along program Y from 20 to
    // 25 about the axis through (10, y, 0) (checked by the distance from that axis).
    let circles = [
        (5, [10.0, 0.0, 0.0], 10.0, [0.0, 1.0, 0.0]),
        (6, [20.0, 10.0, 0.0], 10.0, [1.0, 0.0, 0.0]),
    ];
    let profile = resolve("grbl-router").unwrap();
    let segs: Vec<_> = plan(ops.into_iter(), &profile, PlanOptions::default())
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    let tol = profile.arc_tolerance;
    // The step generator's motor positions after each piece (steps / steps per mm).
    let mut steps = StepGenerator::new(&profile, profile.start);
    let mut log = StepLog::default();
    let mut motor_at = Vec::new();
    for s in &segs {
        steps.segment(s, &mut log).unwrap();
        let spu = [0, 1, 2].map(|i| profile.joints[i].unwrap().steps_per_unit);
        let n = steps.counts();
        motor_at.push([0, 1, 2].map(|i| n[i] as f64 / spu[i]));
    }
    let half_step = 0.5 / profile.joints[0].unwrap().steps_per_unit * 3f64.sqrt();
    let mut checked = 0;
    for (line, centre, r, normal) in circles {
        let circle = Circle {
            c: to_machine(centre, deg, off),
            r,
            n: to_machine(normal, deg, [0.0; 3]),
        };
        for (k, s) in segs
            .iter()
            .enumerate()
            .filter(|(_, s)| s.line == line && matches!(s.kind, SegmentKind::Move(_)))
        {
            let (plane, radial) = circle.miss(motor_at[k]);
            assert!(
                plane <= half_step && radial <= half_step,
                "steps off the circle"
            );
            for p in [s.start, s.end] {
                let (plane, radial) = circle.miss(p);
                assert!(
                    plane < 1e-9 && radial < 1e-9,
                    "line {line}: {p:?} {plane} {radial}"
                );
            }
            // Every point of a chord: off the circle by at most the chord tolerance.
            for k in 1..10 {
                let f = k as f64 / 10.0;
                let p = [0, 1, 2].map(|i| s.start[i] + f * (s.end[i] - s.start[i]));
                let (plane, radial) = circle.miss(p);
                assert!(
                    plane < 1e-9 && radial <= tol + 1e-9,
                    "line {line}: {radial} > {tol}"
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 20, "{checked} pieces");
    // The helix: every piece end keeps the distance 10 from the axis through its centre.
    let axis_point = to_machine([10.0, 20.0, 0.0], deg, off);
    let axis = to_machine([0.0, 1.0, 0.0], deg, [0.0; 3]);
    for s in segs.iter().filter(|s| s.line == 7) {
        let d = sub(s.end, axis_point);
        let along = dot(d, axis);
        let r = (dot(d, d) - along * along).sqrt();
        assert!((r - 10.0).abs() < 1e-9, "{r}");
    }
}

#[test]
fn the_simulator_cuts_a_rotated_xz_arc_along_the_rotated_direction() {
    // A half circle of radius 10 bulging 10 mm down into the stock, programmed along the
    // program's X axis, which G10 L2 R30 turns by 30° in machine XY.
    let program = "G21 G90 G17\n\
                   G10 L2 P1 X20 Y20 Z0 R30\n\
                   T1 M6\n\
                   G54 G0 X0 Y0 Z0\n\
                   G18 G2 X20 Z0 I10 K0 F600\n\
                   M2\n";
    let ops = canon(program);
    assert!(ops.iter().any(|c| matches!(
        c.op,
        CanonOp::ArcFeed { rotation, .. } if rotation == 30.0
    )));
    let tools = HashMap::from([(1, Tool::new(CutterShape::Flat, 1.0).unwrap())]);
    let pixel = 0.1;
    let mut stock = Heightmap::flat(500, 500, pixel, 0.0);
    let end = oficina_sim::replay(&ops, &tools, &mut stock, [20.0, 20.0, 0.0]).unwrap();
    let want_end = to_machine([20.0, 0.0, 0.0], 30.0, [20.0, 20.0, 0.0]);
    assert!(
        (0..3).all(|i| (end[i] - want_end[i]).abs() < 1e-9),
        "{end:?}"
    );
    let depth = |t: f64| -(100.0 - (t - 10.0).powi(2)).max(0.0).sqrt();
    let cell = |p: [f64; 3]| {
        let (ix, iy) = (
            (p[0] / pixel).round() as usize,
            (p[1] / pixel).round() as usize,
        );
        stock.at(ix, iy) as f64
    };
    for k in 1..20 {
        let t = k as f64;
        // On the rotated path: cut at least as deep as the circle there, and no deeper than
        // the circle anywhere within the tool's reach (radius 0.5, plus a cell).
        let on = cell(to_machine([t, 0.0, 0.0], 30.0, [20.0, 20.0, 0.0]));
        let deepest = (-6..=6)
            .map(|j| depth(t + j as f64 * 0.1))
            .fold(0.0, f64::min);
        assert!(on <= depth(t) + 1e-3 && on >= deepest - 1e-3, "t={t}: {on}");
        // Where an unrotated arc would have cut (along machine X) there is no cut, once the
        // two directions are further apart than the tool.
        if t * 0.5 > 1.0 {
            assert_eq!(cell([20.0 + t, 20.0, 0.0]), 0.0, "t={t}");
        }
    }
}
