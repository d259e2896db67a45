//! Item 7 and 10: every 2.5D operation on drawings with arcs, islands, a pocket that splits
//! and non-convex walls, written by the LinuxCNC post, read back by the interpreter,
//! accepted by LinuxCNC's `rs274`, and replayed on a simulated stock: zero gouge, and no
//! material left where the tool can reach.

mod common;

use common::mill;

use oficina_cam::ops::{
    allowed_region, toolpath, Comp, Cut, DrillParams, Entry, MillOp, PocketParams, ProfileParams,
    Side, Strategy, Tabs,
};
use oficina_cam::{Move, Tool, Toolpath};
use oficina_geom::{Arc, Path, Point, Segment};
use oficina_post::{program_text, read_back, PostDialect, PostOptions};
use oficina_sim::{check_mill, Design};
use oficina_testkit::rs274;
use oficina_testkit::shapes::{dumbbell, poly};
use std::collections::HashMap;

fn circle(cx: f64, cy: f64, r: f64) -> Path {
    Path::new(vec![Segment::Arc(Arc::circle(Point::new(cx, cy), r))], true)
}

/// A 60 × 40 rectangle with rounded right end (an arc), a round island and a square island.
fn plate_with_islands() -> Vec<Path> {
    let outer = Path::new(
        vec![
            Segment::line(Point::new(0.0, 0.0), Point::new(60.0, 0.0)),
            Segment::Arc(Arc::from_center(
                Point::new(60.0, 0.0),
                Point::new(60.0, 40.0),
                Point::new(60.0, 20.0),
                1,
            )),
            Segment::line(Point::new(60.0, 40.0), Point::new(0.0, 40.0)),
            Segment::line(Point::new(0.0, 40.0), Point::new(0.0, 0.0)),
        ],
        true,
    );
    vec![
        outer,
        circle(20.0, 20.0, 6.0),
        poly(&[(40.0, 15.0), (50.0, 15.0), (50.0, 25.0), (40.0, 25.0)]),
    ]
}

fn cut(tool: &str, depth: f64, stepdown: f64, entry: Entry) -> Cut {
    Cut {
        tool_number: 1,
        tool: tool.parse::<Tool>().unwrap(),
        spindle_rpm: 12000.0,
        feed: 800.0 / 60.0,
        plunge_feed: 300.0 / 60.0,
        top: 0.0,
        depth,
        stepdown,
        clear_z: 5.0,
        entry,
    }
}

fn post() -> PostOptions {
    PostOptions {
        dialect: PostDialect::LinuxCnc,
        allow_m6: false,
        title: "mill test".into(),
        settings: vec![],
    }
}

/// rs274 must accept `text` with this file's tools (T1 6 mm, T2 2 mm).
fn rs274_accepts(text: &str) {
    rs274::accepts(text, Some("T1 P1 D6 Z0\nT2 P2 D2 Z0\n"));
}

/// Post, read back, rs274, simulate; returns (gouge, mean scallop).
fn verify(paths: &[Path], c: &Cut, op: &MillOp) -> (f64, f64, Toolpath) {
    let tp = toolpath(paths, c, op, 20.0).unwrap_or_else(|e| panic!("{}: {e}", op.name()));
    // No straight plunge into material: every downward feed that is purely vertical
    // starts in air or on a floor already cut (above the top, or a drill cycle).
    if c.entry != Entry::Plunge {
        let mut at = [0.0, 0.0, 20.0];
        for m in &tp.operations[0].moves {
            if let Move::Line { to, .. } = m {
                let vertical = to[0] == at[0] && to[1] == at[1] && to[2] < at[2];
                assert!(
                    !vertical || to[2] >= c.top,
                    "{}: straight plunge to Z{} at ({}, {})",
                    op.name(),
                    to[2],
                    to[0],
                    to[1]
                );
            }
            if let Some(e) = m.end() {
                at = e;
            }
        }
    }
    let text = program_text(&tp, &post()).unwrap();
    rs274_accepts(&text);
    let canon = read_back(&text, &post()).unwrap();
    let (rings, cut_inside) = allowed_region(paths, op).unwrap().unwrap();
    let design = Design {
        rings,
        cut_inside,
        top: c.top,
        floor: c.top - c.depth,
        slope: 0.0,
    };
    let tools: HashMap<u32, Tool> = [(1, c.tool.clone())].into();
    let check = check_mill(
        &canon,
        &tools,
        std::slice::from_ref(&design),
        0.1,
        8.0,
        20.0,
        &c.tool,
    )
    .unwrap();
    eprintln!(
        "{}: gouge {:.4} at {:?}, leftover max {:.3} mean {:.4}, scallop max {:.3} mean {:.5}",
        op.name(),
        check.report.max_gouge,
        check.report.gouge_at,
        check.report.leftover_max,
        check.report.leftover_mean,
        check.report.scallop_max,
        check.report.scallop_mean
    );
    (check.report.max_gouge, check.report.scallop_mean, tp)
}

const NO_GOUGE: f64 = 1e-3;

#[test]
fn offset_pocket_with_islands_from_the_centre_out() {
    let c = cut("flat:6", 5.0, 2.0, Entry::Ramp { angle: 3.0 });
    let op = MillOp::Pocket(PocketParams::for_tool(Strategy::Offset, 6.0));
    let (gouge, scallop, _) = verify(&plate_with_islands(), &c, &op);
    assert!(gouge < NO_GOUGE, "gouge {gouge}");
    assert!(scallop < 0.01, "scallop mean {scallop}");
}

#[test]
fn helix_entry_pocket_that_splits_in_two() {
    let c = cut(
        "flat:6",
        4.0,
        4.0,
        Entry::Helix {
            radius: 1.5,
            angle: 3.0,
        },
    );
    let op = MillOp::Pocket(PocketParams::for_tool(Strategy::Offset, 6.0));
    let (gouge, scallop, tp) = verify(&dumbbell(), &c, &op);
    assert!(gouge < NO_GOUGE, "gouge {gouge}");
    assert!(scallop < 0.01, "scallop mean {scallop}");
    let helices = tp.operations[0]
        .moves
        .iter()
        .filter(|m| matches!(m, Move::Arc { to, .. } if to[2] < 0.0))
        .count();
    assert!(helices > 0);
}

#[test]
fn zigzag_pocket() {
    let c = cut("flat:6", 3.0, 1.5, Entry::Ramp { angle: 5.0 });
    let op = MillOp::Pocket(PocketParams {
        strategy: Strategy::ZigZag,
        stepover: 4.0,
        allowance: 0.3,
    });
    let (gouge, scallop, _) = verify(&plate_with_islands(), &c, &op);
    assert!(gouge < NO_GOUGE, "gouge {gouge}");
    assert!(scallop < 0.01, "scallop mean {scallop}");
}

#[test]
fn profiles_inside_and_outside_with_tabs_and_lead_out() {
    let c = cut("flat:6", 6.0, 2.0, Entry::Ramp { angle: 3.0 });
    for side in [Side::Outside, Side::Inside] {
        let op = MillOp::Profile(ProfileParams {
            side,
            allowance: 0.3,
            tabs: Some(Tabs {
                count: 3,
                width: 4.0,
                height: 1.5,
            }),
            lead_out: 2.0,
            lead_in: 0.0,
            comp: Comp::Computer,
        });
        let (gouge, _, tp) = verify(&dumbbell(), &c, &op);
        assert!(gouge < NO_GOUGE, "{side:?}: gouge {gouge}");
        // The tabs: the last pass rises to 1.5 mm above the bottom somewhere.
        let tab_top = c.top - c.depth + 1.5;
        assert!(tp.operations[0]
            .moves
            .iter()
            .filter_map(Move::end)
            .any(|e| (e[2] - tab_top).abs() < 1e-9));
    }
}

#[test]
fn profiles_with_lead_in_arcs_do_not_gouge() {
    // Lead-in on (tool radius), rough passes plus a finishing pass, tabs and a lead-out:
    // posted, accepted by rs274, read back and simulated.
    for entry in [Entry::Ramp { angle: 3.0 }, Entry::Plunge] {
        let c = cut("flat:6", 6.0, 2.0, entry);
        for (paths, side) in [
            (dumbbell(), Side::Outside),
            (dumbbell(), Side::Inside),
            (plate_with_islands(), Side::Outside),
        ] {
            let op = MillOp::Profile(ProfileParams {
                side,
                allowance: 0.3,
                tabs: Some(Tabs {
                    count: 2,
                    width: 4.0,
                    height: 1.5,
                }),
                lead_out: 2.0,
                lead_in: 3.0,
                comp: Comp::Computer,
            });
            let (gouge, _, tp) = verify(&paths, &c, &op);
            assert!(gouge < NO_GOUGE, "{side:?} {entry:?}: gouge {gouge}");
            let arcs = tp.operations[0]
                .moves
                .windows(2)
                .filter(|w| matches!(w[0], Move::Rapid { .. }) && matches!(w[1], Move::Arc { .. }))
                .count();
            if entry != Entry::Plunge {
                assert!(arcs >= 2, "{side:?}: {arcs} lead-in arcs");
            }
        }
    }
}

#[test]
fn drilling_canned_cycles_at_circle_centres() {
    let c = cut("flat:3", 8.0, 8.0, Entry::Plunge);
    let paths = vec![
        circle(10.0, 10.0, 1.6),
        circle(30.0, 12.0, 1.6),
        circle(20.0, 30.0, 2.0),
    ];
    let op = MillOp::Drill(DrillParams {
        peck: Some(3.0),
        dwell: 0.0,
    });
    let (gouge, _, tp) = verify(&paths, &c, &op);
    assert!(gouge < NO_GOUGE, "gouge {gouge}");
    let text = program_text(&tp, &post()).unwrap();
    assert_eq!(text.matches("G83").count(), 3, "{text}");
    // A 5 mm drill does not fit the 3.2 mm holes: the check sees the gouge.
    let big = cut("flat:5", 8.0, 8.0, Entry::Plunge);
    let (gouge, _, _) = verify(&paths, &big, &op);
    assert!(
        gouge > 1.0,
        "a drill wider than the hole must gouge: {gouge}"
    );
}

#[test]
fn cli_comp_posts_g41_and_the_check_sees_no_gouge() {
    let dir = oficina_testkit::scratch_dir("mill-comp");
    let out = dir.join("p.ngc");
    let run = |post: &str| {
        mill(
            &[
                "samples/mill/plate.svg",
                "--op",
                "profile-out",
                "--tool",
                "flat:6",
                "--depth",
                "3",
                "--comp",
                "--post",
                post,
            ],
            &out,
        )
    };
    let ok = run("linuxcnc");
    let said =
        String::from_utf8_lossy(&ok.stdout).to_string() + &String::from_utf8_lossy(&ok.stderr);
    assert!(ok.status.success(), "{said}");
    assert!(said.contains("gouge:    none"), "{said}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("G41 D1") && text.contains("G40"), "{text}");
    let refused = run("grbl");
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("no cutter radius compensation"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Distance from `p` to the boundary of the axis-aligned square [0, s]², negative inside.
fn square_distance(p: [f64; 2], s: f64) -> f64 {
    let h = s / 2.0;
    let (dx, dy) = ((p[0] - h).abs() - h, (p[1] - h).abs() - h);
    if dx > 0.0 || dy > 0.0 {
        dx.max(0.0).hypot(dy.max(0.0))
    } else {
        dx.max(dy)
    }
}

#[test]
fn comp_preview_shows_the_tool_centre_a_radius_off_the_outline() {
    // A 40 mm square cut outside with a 6 mm mill under G41: the program holds the
    // outline, the preview must show where the control moves the tool: 3 mm outside it.
    let dir = oficina_testkit::scratch_dir("mill-comp-svg");
    let svg = dir.join("square.svg");
    std::fs::write(
        &svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="40mm" height="40mm" viewBox="0 0 40 40"><rect x="0" y="0" width="40" height="40"/></svg>"#,
    )
    .unwrap();
    let out = dir.join("p.ngc");
    let o = mill(
        &[
            svg.to_str().unwrap(),
            "--op",
            "profile-out",
            "--tool",
            "flat:6",
            "--depth",
            "2",
            "--lead-in",
            "0",
            "--allowance",
            "0",
            "--comp",
        ],
        &out,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let preview = std::fs::read_to_string(out.with_extension("svg")).unwrap();
    // The cutting moves: blue polylines, "x,y x,y …".
    let pts: Vec<[f64; 2]> = preview
        .lines()
        .filter(|l| l.contains(r#"stroke="blue""#))
        .flat_map(|l| {
            let inner = l
                .split("points=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap();
            inner
                .split_whitespace()
                .map(|xy| {
                    let (x, y) = xy.split_once(',').unwrap();
                    [x.parse().unwrap(), y.parse().unwrap()]
                })
                .collect::<Vec<_>>()
        })
        .collect();
    assert!(pts.len() > 10, "{preview}");
    // Nothing the tool centre does is nearer the outline than the radius (the entry and
    // exit moves come from farther out), and the wall pass is the radius away.
    let d: Vec<f64> = pts.iter().map(|&p| square_distance(p, 40.0)).collect();
    let nearest = d.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(
        nearest > 3.0 - 2e-3,
        "a point {nearest} mm from the outline"
    );
    let on_wall = d.iter().filter(|&&v| (v - 3.0).abs() < 2e-3).count();
    assert!(on_wall * 10 >= pts.len() * 8, "{on_wall} of {}", pts.len());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cli_rest_tool_clears_what_the_first_tool_could_not_reach() {
    // A 30 × 20 pocket with a 3 mm slot off its side: the 6 mm mill cannot enter the slot
    // nor its corners; `--rest-tool flat:2` must leave nothing the 2 mm one can reach.
    let dir = oficina_testkit::scratch_dir("mill-rest");
    let svg = dir.join("slot.svg");
    std::fs::write(
        &svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="50mm" height="20mm" viewBox="0 0 50 20"><path d="M0 0 H30 V8 H45 V11 H30 V20 H0 Z"/></svg>"#,
    )
    .unwrap();
    let out = dir.join("p.ngc");
    let o = mill(
        &[
            svg.to_str().unwrap(),
            "--op",
            "pocket",
            "--tool",
            "flat:6",
            "--depth",
            "3",
            "--rest-tool",
            "flat:2",
            "--check-pixel",
            "0.1",
        ],
        &out,
    );
    let said = String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{said}");
    assert!(said.contains("gouge:    none"), "{said}");
    assert!(said.contains("T2 flat:2: "), "{said}");
    let leftover: f64 = said
        .lines()
        .find_map(|l| l.trim().strip_prefix("leftover: "))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap();
    // Judged against what the last tool (2 mm) can reach: the slot left standing alone
    // (15 × 3 × 3 mm over the checked area) would be about 0.03 mm.
    assert!(leftover < 0.005, "{said}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("T2 M6") || text.contains("T2"), "{text}");
    rs274_accepts(&text);
    let _ = std::fs::remove_dir_all(&dir);
}
