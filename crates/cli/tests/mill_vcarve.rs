//! V-carving (issue 11 item 7): the carved depth against an independent closed form — a
//! W × H rectangle's deepest cut is min(W, H) / 2 / tan(θ/2) along its medial segment, a
//! circle of radius R is R / tan(θ/2) deep at its centre — with the stock simulator as the
//! judge (the V bit's cone, zero gouge below the ideal sloped walls, little left above
//! them), LinuxCNC's `rs274` accepting the program, and the CLI end to end.

mod common;

use common::mill;

use oficina_cam::ops::{vcarve, Cut, Entry, VCarveParams};
use oficina_cam::{Tool, Toolpath};
use oficina_geom::{to_ring, Arc, Path, Point, Segment};
use oficina_post::{program_text, read_back, PostDialect, PostOptions};
use oficina_sim::{check_mill, Design, MillCheck};
use oficina_testkit::{assert_success, rs274};
use std::collections::HashMap;

fn rect(w: f64, h: f64) -> Path {
    let p = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)].map(|(x, y)| Point::new(x, y));
    Path::polyline(&p, true)
}

fn circle(r: f64) -> Path {
    Path::new(
        vec![Segment::Arc(Arc::circle(Point::new(0.0, 0.0), r))],
        true,
    )
}

fn cut(tool: &str, depth: f64) -> Cut {
    Cut {
        tool_number: 1,
        tool: tool.parse::<Tool>().unwrap(),
        spindle_rpm: 18000.0,
        feed: 600.0 / 60.0,
        plunge_feed: 200.0 / 60.0,
        top: 0.0,
        depth,
        stepdown: depth,
        clear_z: 3.0,
        entry: Entry::Plunge,
    }
}

fn post() -> PostOptions {
    PostOptions {
        dialect: PostDialect::LinuxCnc,
        allow_m6: false,
        title: "vcarve test".into(),
        settings: vec![],
    }
}

/// Carves `shape`, posts, rs274, reads back, simulates against the sloped design.
fn carve(shape: Path, c: &Cut, name: &str) -> (Toolpath, MillCheck, f64) {
    let op = vcarve(
        "V-carve",
        std::slice::from_ref(&shape),
        c,
        &VCarveParams::default(),
    )
    .unwrap();
    let tp = Toolpath {
        safe_z: 10.0,
        operations: vec![op],
    };
    let text = program_text(&tp, &post()).unwrap();
    rs274::accepts(&text, None);
    let canon = read_back(&text, &post()).unwrap();
    let Tool { shape: s, .. } = c.tool;
    let angle = match s {
        oficina_cam::CutterShape::V { angle } => angle,
        _ => unreachable!(),
    };
    let t = (angle.to_radians() / 2.0).tan();
    let design = Design {
        rings: vec![to_ring(&shape.flatten(1e-4))],
        cut_inside: true,
        top: 0.0,
        floor: -c.depth,
        slope: 1.0 / t,
    };
    let tools: HashMap<u32, Tool> = [(1, c.tool.clone())].into();
    let check = check_mill(&canon, &tools, &[design], PIXEL, 4.0, 10.0, &c.tool).unwrap();
    eprintln!(
        "{name}: {} moves, gouge {:.4} mm at {:?}, leftover max {:.4} mean {:.5}, scallop max {:.4}",
        tp.move_count(),
        check.report.max_gouge,
        check.report.gouge_at,
        check.report.leftover_max,
        check.report.leftover_mean,
        check.report.scallop_max
    );
    (tp, check, t)
}

fn lowest_z(tp: &Toolpath) -> f64 {
    tp.operations
        .iter()
        .flat_map(|o| o.moves.iter().filter_map(|m| m.end()))
        .map(|e| e[2])
        .fold(f64::INFINITY, f64::min)
}

/// The simulator's own sampling: the V bit is stamped every pixel / 4 along a move, so a
/// point between two stamps stands up to (pixel / 8) / tan(θ/2) above the swept cone.
const PIXEL: f64 = 0.2;
fn sampling(t: f64) -> f64 {
    PIXEL / 8.0 / t + 0.005
}

/// Stock height at (x, y).
fn stock_at(check: &MillCheck, x: f64, y: f64) -> f64 {
    let s = &check.stock;
    let ix = ((x - check.origin[0]) / s.pixel).round() as usize;
    let iy = ((y - check.origin[1]) / s.pixel).round() as usize;
    s.z[iy * s.width + ix] as f64
}

#[test]
fn rectangle_is_carved_to_half_its_width_along_the_medial_segment() {
    // 30 × 10 with a 90° bit: the medial segment y = 5, x ∈ [5, 25], 5 mm deep.
    let (w, h) = (30.0, 10.0);
    let c = cut("v:16:90", 8.0);
    let (tp, check, t) = carve(rect(w, h), &c, "rect");
    let want = w.min(h) / 2.0 / t;
    let leftover = VCarveParams::default().leftover;
    assert!((lowest_z(&tp) + want).abs() < leftover, "{}", lowest_z(&tp));
    for x in [6.0, 10.0, 15.0, 20.0, 24.0] {
        let z = stock_at(&check, x, 5.0);
        assert!((z + want).abs() < leftover + sampling(t), "at x = {x}: {z}");
    }
    // The walls: 1 mm in from the long side, 1 mm deep.
    let z = stock_at(&check, 15.0, 1.0);
    assert!((z + 1.0 / t).abs() < 0.02, "{z}");
    assert!(check.report.max_gouge < 1e-3, "{:?}", check.report);
    assert!(
        check.report.leftover_max < leftover + 0.02,
        "{:?}",
        check.report
    );
}

#[test]
fn circle_centre_is_r_over_tan_half_angle_deep() {
    // R = 4 with a 60° bit: 4 / tan 30° = 6.93 mm at the centre.
    let r = 4.0;
    let c = cut("v:16:60", 12.0);
    let (tp, check, t) = carve(circle(r), &c, "circle");
    let want = r / t;
    let leftover = VCarveParams::default().leftover;
    assert!((lowest_z(&tp) + want).abs() < leftover, "{}", lowest_z(&tp));
    assert!((stock_at(&check, 0.0, 0.0) + want).abs() < leftover + sampling(t));
    assert!(check.report.max_gouge < 1e-3, "{:?}", check.report);
    assert!(
        check.report.leftover_max < leftover + 0.05,
        "{:?}",
        check.report
    );
}

#[test]
fn a_capped_depth_leaves_a_flat_floor() {
    // 30 × 10 at most 2 mm deep with a 90° bit: walls 2 mm wide, then a floor at −2.
    let c = cut("v:16:90", 2.0);
    let (tp, check, t) = carve(rect(30.0, 10.0), &c, "capped");
    assert!(
        (lowest_z(&tp) + 2.0).abs() < 1e-3 + 0.002,
        "{}",
        lowest_z(&tp)
    );
    for (x, y) in [(15.0, 5.0), (4.0, 4.0), (26.0, 7.0)] {
        let z = stock_at(&check, x, y);
        assert!((z + 2.0).abs() < 0.05 + sampling(t), "at ({x}, {y}): {z}");
    }
    assert!(check.report.max_gouge < 1e-3, "{:?}", check.report);
    assert!(
        check.report.leftover_max < 0.05 + 0.02,
        "{:?}",
        check.report
    );
}

#[test]
fn a_flat_mill_is_refused_and_a_too_narrow_bit_named() {
    let e = vcarve(
        "v",
        &[rect(10.0, 10.0)],
        &cut("flat:3", 1.0),
        &VCarveParams::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("V bit"), "{e}");
    let e = vcarve(
        "v",
        &[rect(10.0, 10.0)],
        &cut("v:2:90", 5.0),
        &VCarveParams::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("wide"), "{e}");
}

#[test]
fn cli_vcarves_a_drawing_and_hershey_text() {
    let dir = oficina_testkit::scratch_dir("vcarve-cli");
    let svg = dir.join("shapes.svg");
    std::fs::write(
        &svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="60mm" height="20mm" viewBox="0 0 60 20">
<rect x="2" y="2" width="30" height="8"/><circle cx="45" cy="10" r="5"/></svg>"#,
    )
    .unwrap();
    let out = dir.join("v.ngc");
    let o = mill(
        &[
            svg.to_str().unwrap(),
            "--op",
            "vcarve",
            "--tool",
            "v:12:90",
            "--depth",
            "3",
        ],
        &out,
    );
    let stdout = assert_success(&o);
    assert!(stdout.contains("gouge:    none"), "{stdout}");
    let text = std::fs::read_to_string(&out).unwrap();
    rs274::accepts(&text, None);
    let o = mill(
        &[
            "--text",
            "OFICINA",
            "--text-height",
            "8",
            "--op",
            "vcarve",
            "--tool",
            "v:6:60",
            "--depth",
            "0.8",
        ],
        &out,
    );
    assert_success(&o);
    let text = std::fs::read_to_string(&out).unwrap();
    rs274::accepts(&text, None);
    // Every stroke is cut at the cap (Hershey strokes have no width).
    assert!(text.contains("Z-0.8"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}
