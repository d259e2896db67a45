//! `oficina simulate`: the stock a program leaves, checked against geometry computed here
//! from the program's own moves (slots of known width and depth cut by a flat, a ball and a
//! V bit), a rapid through material and a cut into the table named by their lines, and
//! real programs other CAM wrote (`realworld/gcode`): the stock's lowest point is the
//! program's lowest Z as `oficina check` reports it, and the render has the stock's shape.

mod common;

use common::{oficina, program, text};
use serde_json::Value;
use std::f64::consts::PI;
use std::path::Path;

/// `simulate --json` of `prog` with `args`, its report.
fn simulate(prog: &Path, args: &[&str]) -> Value {
    let png = prog.with_extension("png");
    let mut all = vec!["simulate", prog.to_str().unwrap(), "--json", "-o"];
    all.push(png.to_str().unwrap());
    all.extend_from_slice(args);
    let out = oficina(&all);
    let (o, e) = text(&out);
    assert!(out.status.success(), "{o}\n{e}");
    serde_json::from_str(&o).unwrap_or_else(|err| panic!("{err}: {o}"))
}

fn num(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

/// A 40 mm slot along X on the cell centres of Y20.025, `depth` deep, on a 60 x 40 x 10 stock at the origin.
fn slot(name: &str, depth: f64) -> std::path::PathBuf {
    program(
        name,
        &format!("G21 G90\nT1 M6\nG0 X10 Y20.025 Z5\nG1 Z-{depth} F200\nG1 X50 F600\nG0 Z5\nM2\n"),
    )
}

const STOCK: [&str; 6] = [
    "--stock",
    "60x40x10",
    "--stock-origin",
    "0,0,0",
    "--resolution",
    "0.05",
];

fn check_slot(name: &str, tool: &str, depth: f64, volume: f64) {
    let prog = slot(name, depth);
    let mut args = STOCK.to_vec();
    args.extend(["--tool", tool]);
    let r = simulate(&prog, &args);
    let got = num(&r, "removed_mm3");
    assert!(
        (got - volume).abs() < 0.03 * volume,
        "{tool}: removed {got} mm³, geometry says {volume}"
    );
    // The tip's depth, to float precision (the slot's floor is cut at cell centres).
    assert!((num(&r, "lowest_z") + depth).abs() < 1e-4, "{r}");
    assert_eq!(num(&r, "highest_z"), 0.0);
    assert_eq!(r["counts"], serde_json::json!([0, 0, 0]), "{r}");
    assert!(prog.with_extension("png").exists());
}

#[test]
fn a_flat_slot_removes_its_box_and_two_half_discs() {
    // 6 mm wide, 2 deep: 40 × 6 × 2 plus a full disc of radius 3 at the two ends.
    check_slot("sim_flat", "flat:6", 2.0, 40.0 * 6.0 * 2.0 + PI * 9.0 * 2.0);
}

#[test]
fn a_ball_slot_removes_a_circular_segment_and_a_cap() {
    let (r, d) = (3.0f64, 2.0f64);
    // The segment of a circle of radius r, d deep, swept 40 mm; the two half caps are a cap.
    let segment = r * r * ((r - d) / r).acos() - (r - d) * (2.0 * r * d - d * d).sqrt();
    let cap = PI * d * d * (3.0 * r - d) / 3.0;
    check_slot("sim_ball", "ball:6", d, 40.0 * segment + cap);
}

#[test]
fn a_v_groove_removes_a_triangle_and_a_cone() {
    // A 90° V bit 1.5 mm deep: a groove d² tan 45° in section, the ends a cone.
    let d = 1.5f64;
    let half = (45f64).to_radians().tan() * d;
    let volume = 40.0 * d * half + PI * half * half * d / 3.0;
    check_slot("sim_vee", "v:6:90", d, volume);
}

#[test]
fn a_rapid_through_material_and_a_cut_into_the_table_are_named_by_line() {
    let prog = program(
        "sim_crash",
        "G21 G90\nT1 M6\nG0 X10 Y10 Z5\nG1 Z-2 F200\nG1 X30\nG0 Z5\n\
         G0 X45 Y30\nG0 Z-3\nG0 Z5\nG0 X20 Y30\nG1 Z-12 F100\nG0 Z5\nM2\n",
    );
    let mut args = STOCK.to_vec();
    args.extend(["--tool", "flat:4"]);
    let r = simulate(&prog, &args);
    // Line 8 rapids 3 mm into uncut stock; line 5's feed and line 9's retract do not count.
    let rapids = r["rapids_into_material"].as_array().unwrap();
    assert_eq!(rapids.len(), 1, "{r}");
    assert_eq!(rapids[0][0], 8);
    assert!((rapids[0][1].as_f64().unwrap() - 3.0).abs() < 1e-4, "{r}");
    // Line 11 feeds to Z-12 through a 10 mm stock.
    assert_eq!(r["below_bottom"][0][0], 11, "{r}");
    assert!(num(&r, "through_mm2") > 0.9 * PI * 4.0, "{r}");
    assert_eq!(num(&r, "lowest_z"), -10.0);
}

#[test]
fn bad_stocks_grids_and_tools_are_refused_by_name() {
    let prog = slot("sim_bad", 1.0);
    let p = prog.to_str().unwrap();
    for (args, says) in [
        (vec!["--stock", "0x40x10"], "stock width 0"),
        (vec!["--stock", "1e9x40x10"], "stock width 1000000000"),
        (vec!["--stock", "60x40"], "WxHxT"),
        (
            vec!["--stock", "5000x5000x10", "--resolution", "0.001"],
            "--memory-mb",
        ),
        (
            vec!["--stock", "60x40x10", "--tool", "spoon:3"],
            "unknown shape",
        ),
    ] {
        let mut all = vec!["simulate", p, "-o", "/tmp/oficina-sim-bad.png"];
        all.extend(args.iter().copied());
        let out = oficina(&all);
        let (o, e) = text(&out);
        assert!(!out.status.success(), "{args:?}: {o}");
        assert!(e.contains(says), "{args:?}: {e}");
        assert!(!e.contains("panicked"), "{e}");
    }
}

#[test]
fn an_unknown_tool_is_simulated_with_the_default_and_a_note() {
    let prog = program(
        "sim_t7",
        "G21 G90\nT7 M6\nG0 X10 Y20 Z5\nG1 Z-1 F200\nG1 X50\nG0 Z5\nM2\n",
    );
    let r = simulate(&prog, &["--stock", "auto", "--tool", "flat:2"]);
    let notes = r["notes"].to_string();
    assert!(notes.contains("T7") && notes.contains("flat:2"), "{notes}");
}

/// The lowest feed Z `oficina check` reports for a program, mm.
fn check_lowest_z(prog: &Path, dialect: &str) -> f64 {
    let out = oficina(&[
        "check",
        prog.to_str().unwrap(),
        "--dialect",
        dialect,
        "--work-offset",
        "0,0,0",
    ]);
    let (o, _) = text(&out);
    let line = o
        .lines()
        .find(|l| l.trim_start().starts_with("feed "))
        .unwrap_or_else(|| panic!("no feed extents in {o}"));
    // "feed   x0 … x1   y0 … y1   z0 … z1"
    let cells: Vec<&str> = line.split('…').collect();
    cells[2].split_whitespace().last().unwrap().parse().unwrap()
}

/// The lowest feed Z LinuxCNC's `rs274 -g` reports (its canon is in the program's units:
/// only asked of metric programs), or `None` without rs274.
fn rs274_lowest_z(prog: &Path) -> Option<f64> {
    let out = std::process::Command::new("rs274")
        .arg("-g")
        .arg(prog)
        .stdin(std::process::Stdio::null())
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    let mut low: Option<f64> = None;
    for line in text.lines() {
        // STRAIGHT_FEED(x, y, z, …) and ARC_FEED(e1, e2, c1, c2, turns, z, …).
        let (name, at) = if line.contains("STRAIGHT_FEED(") {
            ("STRAIGHT_FEED(", 2)
        } else if line.contains("ARC_FEED(") {
            ("ARC_FEED(", 5)
        } else {
            continue;
        };
        let args = line.split(name).nth(1)?.trim_end_matches(')');
        let z: f64 = args.split(',').nth(at)?.trim().parse().ok()?;
        low = Some(low.map_or(z, |l: f64| l.min(z)));
    }
    low
}

#[test]
fn real_programs_from_other_cam_render_down_to_their_lowest_z() {
    let Some(dir) = oficina_testkit::realworld("gcode") else {
        eprintln!("note: realworld/gcode is absent; skipped");
        return;
    };
    // File, dialect, tools, and cells of error allowed on the lowest point: 0 for flat
    // tools (a flat bottom covers cell centres), cot 30° ≈ 1.73 for a 60° V bit, whose
    // deepest cell centre may sit that far up the cone.
    let cases: &[(&str, &str, &[&str], f64)] = &[
        (
            "camotics_botomata_bottom.nc",
            "linuxcnc",
            &[
                "--tool",
                "1=flat:6.35",
                "--tool",
                "2=flat:3.175",
                "--tool",
                "3=flat:1.5875",
            ],
            0.0,
        ),
        ("bcnc_sample.gcode", "grbl", &["--tool", "flat:3"], 0.0),
        (
            "camotics_vcarve.ngc",
            "linuxcnc",
            &["--tool", "v:6:60"],
            1.74,
        ),
        (
            "ugs_ShapeOko_Calibration_Pattern_01b.ngc",
            "linuxcnc",
            &["--tool", "flat:3"],
            0.0,
        ),
    ];
    let mut ran = 0;
    for (name, dialect, tools, cells) in cases {
        let src = dir.join(name);
        if !src.exists() {
            eprintln!("note: {name} is absent; skipped");
            continue;
        }
        let prog = oficina_testkit::scratch_file(name, std::fs::read(&src).unwrap());
        let mut args = vec!["--stock", "auto", "--dialect", dialect];
        args.extend_from_slice(tools);
        let r = simulate(&prog, &args);
        let want = check_lowest_z(&src, dialect);
        // LinuxCNC's reading of the metric ones says the same.
        let text = std::fs::read_to_string(&src).unwrap();
        if text.contains("G21") && !text.contains("G20") {
            match rs274_lowest_z(&src) {
                Some(z) => assert!((z - want).abs() < 1e-3, "{name}: rs274 {z}, check {want}"),
                None => {
                    eprintln!("note: rs274 gave no feed moves for {name}; check's figure alone")
                }
            }
        }
        let got = num(&r, "lowest_z");
        let pixel = num(&r, "pixel");
        let tol = 1e-3 + cells * pixel;
        assert!(
            (got - want).abs() <= tol,
            "{name}: stock bottom {got}, check's lowest Z {want} (cell {pixel} mm)"
        );
        // Material goes only where the program goes below the top (the ShapeOko pattern
        // traces Z 0: it removes nothing).
        assert_eq!(num(&r, "removed_mm3") > 0.0, want < 0.0, "{name}: {r}");
        // The render is the stock seen from above: its proportions within a cell.
        let (w, h) = image::image_dimensions(prog.with_extension("png")).unwrap();
        let size = r["stock_size"].as_array().unwrap();
        let (sw, sh) = (size[0].as_f64().unwrap(), size[1].as_f64().unwrap());
        assert!(
            ((w as f64) * pixel - sw).abs() <= pixel,
            "{name}: {w} px for {sw} mm"
        );
        assert!(
            ((h as f64) * pixel - sh).abs() <= pixel,
            "{name}: {h} px for {sh} mm"
        );
        ran += 1;
    }
    eprintln!("{ran} real programs simulated");
}

#[test]
fn a_design_image_gives_gouge_and_leftover() {
    // The design: a 60 × 40 mm picture (0.1 mm a pixel), white = the top, a black rectangle
    // X6.9–53.1 Y16.9–23.1 around the 6 mm flat slot (X7–53 with its round ends, Y17.025–
    // 23.025). Symmetric about Y20, so the picture's row order does not matter.
    let img = image::GrayImage::from_fn(600, 400, |x, y| {
        let inside = (69..531).contains(&x) && (169..231).contains(&y);
        image::Luma([if inside { 0 } else { 255 }])
    });
    let design = oficina_testkit::scratch_dir("sim-design").join("slot.png");
    img.save(&design).unwrap();
    let prog = slot("sim_design", 2.0);
    let mut args = STOCK.to_vec();
    args.extend(["--tool", "flat:6", "--design", design.to_str().unwrap()]);
    // Black 2 mm deep: the slot stays inside the design, whose square corners it cannot
    // reach (its ends are round): no gouge, 2 mm left in the corners.
    let mut deep = args.clone();
    deep.extend(["--design-depth", "2"]);
    let r = simulate(&prog, &deep);
    let d = &r["design"];
    assert!(num(d, "max_gouge") < 1e-3, "{d}");
    assert!((num(d, "leftover_max") - 2.0).abs() < 1e-3, "{d}");
    // Black 1 mm deep: the 2 mm slot is 1 mm below the design.
    let mut shallow = args.clone();
    shallow.extend(["--design-depth", "1"]);
    let r = simulate(&prog, &shallow);
    let d = &r["design"];
    assert!((num(d, "max_gouge") - 1.0).abs() < 1e-3, "{d}");
    let at = d["gouge_at"].as_array().unwrap();
    let (x, y) = (at[0].as_f64().unwrap(), at[1].as_f64().unwrap());
    assert!(
        (7.0..=53.0).contains(&x) && (17.0..=23.1).contains(&y),
        "{d}"
    );
}

#[test]
fn a_tool_tables_diameter_and_the_shape_its_comment_names_are_used() {
    let table = oficina_testkit::scratch_file("sim.tbl", "T1 P1 D6 Z0 ;6 mm ball nose\n");
    let prog = slot("sim_table", 2.0);
    let mut args = STOCK.to_vec();
    args.extend(["--tool-table", table.to_str().unwrap()]);
    let r = simulate(&prog, &args);
    assert_eq!(r["tools"][0]["spec"], "ball:6", "{r}");
    assert!(r["notes"].to_string().matches("T1").count() == 0, "{r}");
    // The same circular segment and cap as the ball given by --tool.
    let (rad, d) = (3.0f64, 2.0f64);
    let segment = rad * rad * ((rad - d) / rad).acos() - (rad - d) * (2.0 * rad * d - d * d).sqrt();
    let volume = 40.0 * segment + PI * d * d * (3.0 * rad - d) / 3.0;
    assert!(
        (num(&r, "removed_mm3") - volume).abs() < 0.03 * volume,
        "{r}"
    );
}

#[test]
fn cuts_off_the_stock_are_listed_by_line() {
    // The stock 30 mm wide from X0: the slot's feed to X50 (line 5) ends off it.
    let prog = slot("sim_off", 1.0);
    let r = simulate(
        &prog,
        &[
            "--stock",
            "30x40x10",
            "--stock-origin",
            "0,0,0",
            "--tool",
            "flat:6",
        ],
    );
    assert_eq!(r["counts"][2], 1, "{r}");
    assert_eq!(r["off_stock"][0][0], 5, "{r}");
    // What is on the stock is still cut: 20 mm of the slot plus the entry's half disc.
    let volume = 20.0 * 6.0 + PI * 9.0 / 2.0;
    assert!(
        (num(&r, "removed_mm3") - volume).abs() < 0.03 * volume,
        "{r}"
    );
}
