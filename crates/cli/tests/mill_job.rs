//! `oficina mill --job`: jobs of several operations and tools (tests/data/jobs) give one
//! program that LinuxCNC's rs274 accepts, the stock simulator finds no gouge in, whose tool
//! changes are grouped, and that runs on the virtual machine; the nested cut-out is checked
//! by shapely (scripts/job_cut_sides.py) on the cutter centre rs274 reads from the program.
//! The NEMA 17 mount job skips when the shared realworld drawings are not beside the
//! checkout; the plate job is self-contained.

mod common;

use common::{root, text};
use oficina_testkit::rs274;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// `shared/data/realworld/mill-dxf-svg` beside the checkout (main's `../shared` or a
/// worktree's `../../shared`).
fn realworld() -> Option<PathBuf> {
    oficina_testkit::realworld("mill-dxf-svg")
}

/// Copies the job files `names` from tests/data/jobs into a scratch folder.
fn job_dir(tag: &str, names: &[&str]) -> PathBuf {
    let dir = oficina_testkit::scratch_dir(tag);
    for n in names {
        std::fs::copy(root().join("tests/data/jobs").join(n), dir.join(n)).unwrap();
    }
    dir
}

/// `oficina args…` in `dir`: (exit code, stdout, stderr).
fn oficina_in(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("the binary runs");
    let (out, err) = text(&o);
    (o.status.code(), out, err)
}

/// The tool numbers of the program's M6 blocks, in order.
fn tool_changes(program: &str) -> Vec<u32> {
    program
        .lines()
        .filter(|l| l.contains("M6") && !l.trim_start().starts_with('('))
        .filter_map(|l| {
            let t = l.split_whitespace().find(|w| w.starts_with('T'))?;
            t[1..].parse().ok()
        })
        .collect()
}

/// Operation comments in program order: "op 3 cut-out …" → 3.
fn op_order(program: &str) -> Vec<usize> {
    program
        .lines()
        .filter_map(|l| l.split("(operation: op ").nth(1))
        .filter_map(|rest| rest.split_whitespace().next()?.parse().ok())
        .collect()
}

/// shapely's figures (scripts/job_cut_sides.py) for the operations `ops` of the canon.
fn cut_sides(canon: &Path, spec: &str) -> (f64, Vec<usize>) {
    let v = sides_json(canon, spec);
    let near = v["near"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_u64().unwrap() as usize)
        .collect();
    (v["min_distance"].as_f64().unwrap(), near)
}

/// scripts/job_cut_sides.py's answer.
fn sides_json(canon: &Path, spec: &str) -> serde_json::Value {
    let mut child = Command::new("python3")
        .arg(root().join("scripts/job_cut_sides.py"))
        .arg(canon)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("python3 runs");
    use std::io::Write;
    child
        .stdin
        .take()
        .unwrap()
        .write_all(spec.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let (stdout, stderr) = text(&out);
    assert!(out.status.success(), "job_cut_sides.py: {stderr}");
    serde_json::from_str(&stdout).unwrap()
}

/// rs274's canon of `program`, written beside it.
fn canon_of(program: &Path) -> PathBuf {
    let canon = rs274::accepts_file(program, None);
    let path = program.with_extension("canon.txt");
    std::fs::write(&path, canon).unwrap();
    path
}

/// The deepest Z of the feed moves of operation `op` in rs274's canon.
fn deepest(canon: &Path, op: &str) -> f64 {
    let text = std::fs::read_to_string(canon).unwrap();
    let mut active = false;
    let mut low = f64::INFINITY;
    for l in text.lines() {
        if let Some(c) = l.split("COMMENT(\"operation: ").nth(1) {
            active = c.starts_with(op);
        } else if active && l.contains("STRAIGHT_FEED(") {
            let args = l.split('(').nth(1).unwrap();
            let z: f64 = args.split(',').nth(2).unwrap().trim().parse().unwrap();
            low = low.min(z);
        }
    }
    low
}

/// `oficina run --instant` on the virtual machine: finishes.
fn runs_on_the_vm(dir: &Path, program: &str) {
    let (code, out, err) = oficina_in(dir, &["run", "--instant", program]);
    assert_eq!(code, Some(0), "{out}\n{err}");
    assert!(out.contains("done:"), "{out}");
}

fn circle(cx: f64, cy: f64, r: f64) -> String {
    let pts: Vec<String> = (0..720)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 720.0;
            format!("[{}, {}]", cx + r * a.cos(), cy + r * a.sin())
        })
        .collect();
    format!("[{}]", pts.join(", "))
}

#[test]
fn the_plate_job_cuts_out_by_nesting_groups_its_tools_and_runs() {
    let dir = job_dir("job-plate", &["nested-plate.svg", "nested-plate.toml"]);
    let (code, out, err) = oficina_in(
        &dir,
        &["mill", "--job", "nested-plate.toml", "-o", "part.nc"],
    );
    assert_eq!(code, Some(0), "{out}\n{err}");
    assert!(out.contains("gouge:    none"), "{out}");
    // The ids the selections name, in the report.
    assert!(
        out.contains("shape:    #3 CUTS #0000ff closed circle Ø12.00"),
        "{out}"
    );
    let program = std::fs::read_to_string(dir.join("part.nc")).unwrap();
    // Written: holes T1, chamfer T2, cut-out T1. The cut-out stays last; the V bit goes
    // first so T1 is loaded once: two loads, the fewest for two tools.
    assert_eq!(op_order(&program), [2, 1, 3], "{out}");
    assert_eq!(tool_changes(&program), [2, 1]);
    let canon = canon_of(&dir.join("part.nc"));
    // The cut-out (3 mm tool): never nearer the part than the radius; it cuts outside the
    // outline, inside the window, outside the island, inside each hole.
    let rings = format!(
        "[[[0, 0], [80, 0], [80, 50], [0, 50]], {}, {}, {}, {}]",
        circle(25.0, 25.0, 15.0),
        circle(25.0, 25.0, 6.0),
        circle(60.0, 15.0, 3.0),
        circle(60.0, 35.0, 3.0)
    );
    let probes = "[[-2, -2], [25, 12], [60, 15], [60, 35]]";
    let (d, near) = cut_sides(
        &canon,
        &format!(r#"{{"ops": ["op 3 "], "rings": {rings}, "probes": {probes}}}"#),
    );
    // The SVG's circles are Béziers, within 0.004 mm of the true circle.
    assert!(d >= 1.5 - 0.01, "the cut-out comes {d} mm from the part");
    assert!(
        near.iter().all(|&n| n > 0),
        "every waste region is cut: {near:?}"
    );
    // The holes op: only in the small holes.
    let (d, near) = cut_sides(
        &canon,
        &format!(r#"{{"ops": ["op 1 "], "rings": {rings}, "probes": {probes}}}"#),
    );
    assert!(d >= 1.5 - 0.01, "{d}");
    assert_eq!((near[0], near[1]), (0, 0), "{near:?}");
    assert!(near[2] > 0 && near[3] > 0, "{near:?}");
    // The chamfer: tip 0 mm into the hole (no tip offset), (0.6 + 0) / tan 45° deep.
    let (d, _) = cut_sides(
        &canon,
        &format!(r#"{{"ops": ["op 2 "], "rings": {rings}, "probes": []}}"#),
    );
    assert!(d < 0.01, "{d}");
    assert!((deepest(&canon, "op 2 ") + 0.6).abs() < 1e-3);
    runs_on_the_vm(&dir, "part.nc");
}

#[test]
fn per_tool_writes_one_program_per_tool_each_checked() {
    let dir = job_dir("job-per-tool", &["nested-plate.svg", "nested-plate.toml"]);
    let (code, out, err) = oficina_in(
        &dir,
        &[
            "mill",
            "--job",
            "nested-plate.toml",
            "-o",
            "part.nc",
            "--per-tool",
        ],
    );
    assert_eq!(code, Some(0), "{out}\n{err}");
    assert_eq!(out.matches("gouge:    none").count(), 2, "{out}");
    for (file, tool) in [("part.T2.nc", 2), ("part.T1.nc", 1)] {
        let program = std::fs::read_to_string(dir.join(file)).unwrap();
        assert_eq!(tool_changes(&program), [tool], "{file}");
        rs274::accepts_file(&dir.join(file), None);
        runs_on_the_vm(&dir, file);
    }
}

#[test]
fn the_nema17_mount_as_one_job_holes_pocket_chamfer_outline_with_tabs() {
    let Some(data) = realworld() else { return };
    let dir = job_dir("job-nema17", &["nema17-mount.toml", "tools.toml"]);
    let dxf = data.join("obcam_Motor NEMA17 - Mount.dxf");
    let job = std::fs::read_to_string(dir.join("nema17-mount.toml")).unwrap();
    let job = job.replace(
        "drawing = \"obcam_Motor NEMA17 - Mount.dxf\"",
        &format!("drawing = {:?}", dxf.to_str().unwrap()),
    );
    std::fs::write(dir.join("nema17-mount.toml"), job).unwrap();
    let (code, out, err) = oficina_in(
        &dir,
        &["mill", "--job", "nema17-mount.toml", "-o", "part.nc"],
    );
    assert_eq!(code, Some(0), "{out}\n{err}");
    assert!(out.contains("gouge:    none"), "{out}");
    assert!(out.contains("(planner"), "{out}");
    eprintln!("{out}");
    let program = std::fs::read_to_string(dir.join("part.nc")).unwrap();
    // Written: holes T1, chamfer T2, bore T1, outline T1 (the cut-out, last). Two loads is
    // the fewest, and only the V bit first gives it.
    assert_eq!(tool_changes(&program), [2, 1]);
    assert_eq!(op_order(&program), [2, 1, 3, 4]);
    // Feeds from the library: 0.01 mm/tooth × 2 × 18000 rpm for the 2 mm mill.
    assert!(program.contains("F360"), "the library's feed");
    let canon = canon_of(&dir.join("part.nc"));
    // Every flat-mill cut (holes, bore, outline) stays a radius from the plate, as ezdxf
    // reads the drawing; each waste region is cut.
    let spec = format!(
        r#"{{"ops": ["op 1 ", "op 3 ", "op 4 "], "dxf": {:?}, "rounded_rects": [[0, 0, 42, 42, 4]], "probes": [[-3, -3], [21, 21], [5.5, 5.5], [36.5, 36.5], [5.5, 36.5], [36.5, 5.5]]}}"#,
        dxf.to_str().unwrap()
    );
    let (d, near) = cut_sides(&canon, &spec);
    assert!(d >= 1.0 - 1e-3, "{d}");
    assert!(near.iter().all(|&n| n > 0), "{near:?}");
    // The chamfer's tip 0.2 mm off every edge, (0.5 + 0.2) / tan 45° deep.
    let (d, _) = cut_sides(
        &canon,
        &spec.replace(r#"["op 1 ", "op 3 ", "op 4 "]"#, r#"["op 2 "]"#),
    );
    assert!((d - 0.2).abs() < 2e-3, "{d}");
    assert!((deepest(&canon, "op 2 ") + 0.7).abs() < 1e-3);
    runs_on_the_vm(&dir, "part.nc");
}

#[test]
fn bad_jobs_say_which_file_line_and_key() {
    let dir = job_dir(
        "job-bad",
        &["nested-plate.svg", "nested-plate.toml", "tools.toml"],
    );
    let good = std::fs::read_to_string(dir.join("nested-plate.toml")).unwrap();
    let typo = good.replace(
        "stepdown = 1.5\nfeed = 900\nrpm = 18000\ntabs",
        "stepdown = 1.5\nfeed = 900\nrmp = 18000\ntabs",
    );
    let typo_line = format!(
        "line {}",
        typo[..typo.find("rmp").unwrap()].matches('\n').count() + 1
    );
    let cases: &[(&str, String, &[&str])] = &[
        ("unknown key", typo.clone(), &["bad.toml", "rmp"]),
        (
            "tool not in the library",
            format!(
                "library = \"tools.toml\"\n{}",
                good.replace("tool = \"v:6:90\"", "tool = 9")
            ),
            &[
                "bad.toml",
                "op 2 (deburr)",
                "tool = 9",
                "tools.toml",
                "1, 2, 3",
            ],
        ),
        (
            "a number without a library",
            good.replace("tool = \"v:6:90\"", "tool = 2"),
            &["bad.toml", "op 2 (deburr)", "needs a library"],
        ),
        (
            "selection matching nothing",
            good.replace(
                "color = \"red\", diameter_under = 10",
                "color = \"red\", diameter_over = 10",
            ),
            &[
                "bad.toml",
                "op 1 (small holes)",
                "matches none of the 5 shapes",
            ],
        ),
        (
            "unknown layer",
            good.replace("select = {}", "select = { layer = \"HOLES\" }"),
            &[
                "bad.toml",
                "op 3 (cut-out)",
                "no layer \"HOLES\"",
                "OUTLINE, CUTS",
            ],
        ),
        (
            "a chamfer without a V bit",
            good.replace("tool = \"v:6:90\"", "tool = \"flat:3\""),
            &[
                "bad.toml",
                "op 2 (deburr)",
                "a chamfer needs a V bit",
                "flat:3",
            ],
        ),
        (
            "unknown kind",
            good.replace("kind = \"chamfer\"", "kind = \"chamfre\""),
            &["bad.toml", "chamfre", "chamfer"],
        ),
    ];
    for (what, text, wants) in cases {
        std::fs::write(dir.join("bad.toml"), text).unwrap();
        let (code, out, err) = oficina_in(&dir, &["mill", "--job", "bad.toml", "-o", "x.nc"]);
        assert_eq!(code, Some(1), "{what}: {out}\n{err}");
        assert!(!err.contains("panicked"), "{what}: {err}");
        for w in *wants {
            assert!(err.contains(w), "{what}: want {w:?} in {err}");
        }
        if *what == "unknown key" {
            assert!(err.contains(&typo_line), "want {typo_line}: {err}");
        }
    }
}

#[test]
fn the_feeds_calculator_multiplies_chip_load_flutes_and_rpm() {
    let lib = root().join("tests/data/jobs/tools.toml");
    let (code, out, err) = oficina_in(
        &root(),
        &[
            "tools",
            "feeds",
            "--library",
            lib.to_str().unwrap(),
            "--tool",
            "2",
            "--material",
            "wood",
        ],
    );
    assert_eq!(code, Some(0), "{err}");
    // 0.05 mm/tooth × 2 × 16000 rpm; π × 6 mm × 16000 rpm = 301.6 m/min.
    assert!(out.contains("feed:          1600 mm/min"), "{out}");
    assert!(out.contains("cutting speed: 302 m/min"), "{out}");
    let (code, _, err) = oficina_in(
        &root(),
        &[
            "tools",
            "feeds",
            "--library",
            lib.to_str().unwrap(),
            "--tool",
            "2",
            "--material",
            "steel",
        ],
    );
    assert_eq!(code, Some(1));
    assert!(
        err.contains("no chip load for \"steel\"") && err.contains("aluminium"),
        "{err}"
    );
}

#[test]
fn plain_mill_lists_the_shape_ids_a_job_selects_by() {
    let dir = job_dir("job-ids", &["nested-plate.svg", "nested-plate.toml"]);
    let (code, job_out, err) =
        oficina_in(&dir, &["mill", "--job", "nested-plate.toml", "-o", "a.nc"]);
    assert_eq!(code, Some(0), "{err}");
    let (code, out, err) = oficina_in(
        &dir,
        &[
            "mill",
            "nested-plate.svg",
            "--op",
            "pocket",
            "--depth",
            "1",
            "-o",
            "b.nc",
        ],
    );
    assert_eq!(code, Some(0), "{err}");
    let ids = |s: &str| -> Vec<String> {
        s.lines()
            .filter(|l| l.starts_with("shape:"))
            .map(|l| l.split_whitespace().take(2).collect::<Vec<_>>().join(" "))
            .collect()
    };
    // Five shapes in the SVG's order, the same numbers in both reports.
    assert_eq!(
        ids(&out),
        [
            "shape: #1",
            "shape: #2",
            "shape: #3",
            "shape: #4",
            "shape: #5"
        ]
    );
    assert_eq!(ids(&out), ids(&job_out));
    assert!(out.contains("#4 CUTS #ff0000 closed circle Ø6.00"), "{out}");
}

#[test]
fn plain_mill_takes_a_library_tool_by_number_with_its_feeds() {
    let dir = job_dir("job-lib", &["nested-plate.svg", "tools.toml"]);
    let args = [
        "mill",
        "nested-plate.svg",
        "--op",
        "profile-out",
        "--depth",
        "2",
        "--library",
        "tools.toml",
        "--tool",
        "3",
        "--material",
        "wood",
        "-o",
        "c.nc",
    ];
    let (code, out, err) = oficina_in(&dir, &args);
    assert_eq!(code, Some(0), "{out}\n{err}");
    let program = std::fs::read_to_string(dir.join("c.nc")).unwrap();
    // Tool 3 of tools.toml: 3 mm, 2 flutes, 18000 rpm, 0.04 mm/tooth in wood → 1440 mm/min.
    assert!(
        program.contains("T3 M6") && program.contains("S18000"),
        "{program}"
    );
    assert!(program.contains("F1440"), "chip load × flutes × rpm");
    // No chip load for the material: the library's own feed (900 mm/min).
    let mut args = args.to_vec();
    args[11] = "steel";
    let (code, _, err) = oficina_in(&dir, &args);
    assert_eq!(code, Some(0), "{err}");
    assert!(std::fs::read_to_string(dir.join("c.nc"))
        .unwrap()
        .contains("F900"));
    // A number the library lacks.
    args[9] = "7";
    let (code, _, err) = oficina_in(&dir, &args);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("--tool 7: not in the library tools.toml (it has 1, 2, 3)"),
        "{err}"
    );
}

#[test]
fn dogbones_carry_the_tool_into_every_inside_corner() {
    let dir = job_dir("job-dogbone", &["tenon-slots.svg", "tenon-slots.toml"]);
    let (code, out, err) = oficina_in(
        &dir,
        &["mill", "--job", "tenon-slots.toml", "-o", "part.nc"],
    );
    assert_eq!(code, Some(0), "{out}\n{err}");
    assert!(out.contains("gouge:    none"), "{out}");
    let canon = canon_of(&dir.join("part.nc"));
    // The eight corners of the two sockets (the SVG is symmetric about y = 15, so a reader
    // flipping y sees the same). A 4 mm mill without dogbones keeps its centre 2·√2 mm
    // from a square corner; with them its edge reaches the corner: centre within 2 mm.
    let corners = "[[5, 10], [25, 10], [25, 20], [5, 20], [35, 9], [47, 9], [47, 21], [35, 21]]";
    let v = sides_json(
        &canon,
        &format!(r#"{{"ops": ["op 1 "], "rings": [], "points": {corners}}}"#),
    );
    for (k, d) in v["reach"].as_array().unwrap().iter().enumerate() {
        let d = d.as_f64().unwrap();
        assert!(
            d <= 2.0 + 1e-3,
            "corner {k}: the centre comes only {d} mm near"
        );
    }
    // Without dogbones the same job leaves the corners (the check can fail).
    let plain = std::fs::read_to_string(dir.join("tenon-slots.toml"))
        .unwrap()
        .replace("dogbone = true", "dogbone = false");
    std::fs::write(dir.join("plain.toml"), plain).unwrap();
    let (code, _, err) = oficina_in(&dir, &["mill", "--job", "plain.toml", "-o", "plain.nc"]);
    assert_eq!(code, Some(0), "{err}");
    let canon = canon_of(&dir.join("plain.nc"));
    let v = sides_json(
        &canon,
        &format!(r#"{{"ops": ["op 1 "], "rings": [], "points": {corners}}}"#),
    );
    let d = v["reach"][0].as_f64().unwrap();
    assert!((d - 2.0 * 2f64.sqrt()).abs() < 0.05, "{d}");
    runs_on_the_vm(&dir, "part.nc");
    // The slot (x 5…25) with dogbones: the centre stays a radius/√2 inside its end wall.
    assert!(slot_max_x(&dir.join("part.canon.txt")) < 24.0);
    // T-bones: along the slot's long sides, so the centre comes level with the end wall
    // (the notch runs past it) and the edge still reaches every corner.
    let tbone = std::fs::read_to_string(dir.join("tenon-slots.toml"))
        .unwrap()
        .replace("dogbone = true", "dogbone = \"t-bone\"");
    std::fs::write(dir.join("tbone.toml"), tbone).unwrap();
    let (code, out, err) = oficina_in(&dir, &["mill", "--job", "tbone.toml", "-o", "t.nc"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("gouge:    none"), "{out}");
    let canon = canon_of(&dir.join("t.nc"));
    let v = sides_json(
        &canon,
        &format!(r#"{{"ops": ["op 1 "], "rings": [], "points": {corners}}}"#),
    );
    for d in v["reach"].as_array().unwrap() {
        assert!(d.as_f64().unwrap() <= 2.0 + 1e-3, "{d}");
    }
    assert!(slot_max_x(&canon) > 25.0 - 1e-3);
}

/// The largest X of the cutting feed moves' ends over the slot (x < 30) in rs274's canon.
fn slot_max_x(canon: &Path) -> f64 {
    let text = std::fs::read_to_string(canon).unwrap();
    text.lines()
        .filter(|l| l.contains("STRAIGHT_FEED(") || l.contains("ARC_FEED("))
        .filter_map(|l| {
            let a: Vec<f64> = l
                .split('(')
                .nth(1)?
                .trim_end_matches(')')
                .split(',')
                .map(|v| v.trim().parse().unwrap())
                .collect();
            let z = if l.contains("ARC_FEED(") { a[5] } else { a[2] };
            (a[0] < 30.0 && z < 0.0).then_some(a[0])
        })
        .fold(f64::MIN, f64::max)
}

/// The least X and Y of the feed moves in rs274's canon.
fn feed_min_xy(canon: &Path) -> [f64; 2] {
    let text = std::fs::read_to_string(canon).unwrap();
    let mut m = [f64::INFINITY; 2];
    for l in text.lines().filter(|l| l.contains("STRAIGHT_FEED(")) {
        let args: Vec<f64> = l
            .split('(')
            .nth(1)
            .unwrap()
            .trim_end_matches(')')
            .split(',')
            .map(|v| v.trim().parse().unwrap())
            .collect();
        m = [m[0].min(args[0]), m[1].min(args[1])];
    }
    m
}

#[test]
fn origin_at_the_stock_corner_moves_the_program_by_the_corner() {
    let dir = job_dir("job-origin", &["nested-plate.svg", "nested-plate.toml"]);
    let job = std::fs::read_to_string(dir.join("nested-plate.toml")).unwrap();
    assert!(job.contains("corner = [-5, -5]"));
    std::fs::write(
        dir.join("corner.toml"),
        job.replace(
            "corner = [-5, -5]",
            "corner = [-5, -5]\norigin = \"stock-corner\"",
        ),
    )
    .unwrap();
    for (file, out) in [("nested-plate.toml", "a.nc"), ("corner.toml", "b.nc")] {
        let (code, o, err) = oficina_in(&dir, &["mill", "--job", file, "-o", out]);
        assert_eq!(code, Some(0), "{o}\n{err}");
        assert!(o.contains("gouge:    none"), "{o}");
    }
    let a = feed_min_xy(&canon_of(&dir.join("a.nc")));
    let b = feed_min_xy(&canon_of(&dir.join("b.nc")));
    assert!(
        (b[0] - a[0] - 5.0).abs() < 1e-3 && (b[1] - a[1] - 5.0).abs() < 1e-3,
        "{a:?} {b:?}"
    );
    assert!(
        b[0] > 0.0 && b[1] > 0.0,
        "the part sits on the stock: {b:?}"
    );
}

#[test]
fn an_engraving_is_checked_within_its_tool_radius_of_the_line() {
    let dir = job_dir("job-engrave", &["nested-plate.svg", "nested-plate.toml"]);
    let job = std::fs::read_to_string(dir.join("nested-plate.toml")).unwrap();
    let mark = "\n[[op]]\nname = \"mark\"\nkind = \"engrave\"\nselect = { color = \"blue\" }\n\
        tool = \"flat:1\"\ndepth = 0.5\nfeed = 600\nrpm = 18000\n";
    std::fs::write(dir.join("mark.toml"), format!("{job}{mark}")).unwrap();
    let (code, out, err) = oficina_in(&dir, &["mill", "--job", "mark.toml", "-o", "m.nc"]);
    assert_eq!(code, Some(0), "{out}\n{err}");
    assert!(
        out.contains("gouge:    none") && !err.contains("not checked"),
        "{out}\n{err}"
    );
    rs274::accepts_file(&dir.join("m.nc"), None);
    // Alone (no cut-out around it to allow the waste), a lead-out arc swings the 1 mm mill
    // 3 mm off the outline, whichever way the outline runs: the check sees it.
    let solo = "drawing = \"nested-plate.svg\"\n[stock]\nthickness = 5\n\
        [[op]]\nkind = \"engrave\"\nselect = { ids = [1] }\ntool = \"flat:1\"\n\
        depth = 0.5\nfeed = 600\nrpm = 18000\n";
    std::fs::write(dir.join("solo.toml"), solo).unwrap();
    let (code, out, _) = oficina_in(&dir, &["mill", "--job", "solo.toml", "-o", "s.nc"]);
    assert_eq!(code, Some(0), "{out}");
    assert!(out.contains("gouge:    none"), "{out}");
    std::fs::write(dir.join("off.toml"), format!("{solo}lead_out = 3\n")).unwrap();
    let (code, out, _) = oficina_in(&dir, &["mill", "--job", "off.toml", "-o", "o.nc"]);
    assert_eq!(code, Some(2), "{out}");
    assert!(out.contains("← cut outside the drawing"), "{out}");
}

#[test]
fn an_adaptive_op_clears_the_window_round_its_island() {
    let dir = job_dir("job-adaptive", &["nested-plate.svg"]);
    std::fs::write(
        dir.join("adaptive.toml"),
        r#"drawing = "nested-plate.svg"
[stock]
thickness = 5
[[op]]
name = "window"
kind = "adaptive"
select = { layer = "CUTS", diameter_over = 10 }
tool = "flat:6"
depth = 3
stepdown = 1.5
max_engagement = 90
feed = 900
rpm = 18000
"#,
    )
    .unwrap();
    let (code, out, err) = oficina_in(&dir, &["mill", "--job", "adaptive.toml", "-o", "a.nc"]);
    assert_eq!(code, Some(0), "{out}\n{err}");
    assert!(out.contains("gouge:    none"), "{out}");
    let canon = canon_of(&dir.join("a.nc"));
    assert!((deepest(&canon, "op 1 window") + 3.0).abs() < 1e-6, "{out}");
    runs_on_the_vm(&dir, "a.nc");
    // A misspelt parameter is named.
    let bad = std::fs::read_to_string(dir.join("adaptive.toml"))
        .unwrap()
        .replace("max_engagement", "max_engagment");
    std::fs::write(dir.join("bad.toml"), bad).unwrap();
    let (code, _, err) = oficina_in(&dir, &["mill", "--job", "bad.toml", "-o", "b.nc"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("max_engagment"), "{err}");
}

/// `--upto N`: the job stopped after N operations of its cutting order is the whole program
/// cut before the next operation's comment, then its end; LinuxCNC's rs274 accepts it; an
/// operation the job has not is refused with the range, and `--upto` needs `--job`.
#[test]
fn upto_stops_the_job_after_n_operations() {
    let dir = job_dir("mill-job-upto", &["nested-plate.toml", "nested-plate.svg"]);
    let (code, _, err) = oficina_in(
        &dir,
        &["mill", "--job", "nested-plate.toml", "-o", "all.nc"],
    );
    assert_eq!(code, Some(0), "{err}");
    let all = std::fs::read_to_string(dir.join("all.nc")).unwrap();
    let lines: Vec<&str> = all.lines().collect();
    let starts: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].starts_with("(operation: "))
        .collect();
    assert_eq!(starts.len(), 3);
    let moves = |ls: &[&str]| -> Vec<String> {
        ls.iter()
            .filter(|l| !l.starts_with('('))
            .map(|l| l.to_string())
            .collect()
    };
    for n in 1..=2 {
        let out = format!("upto{n}.nc");
        let (code, stdout, err) = oficina_in(
            &dir,
            &[
                "mill",
                "--job",
                "nested-plate.toml",
                "--upto",
                &n.to_string(),
                "-o",
                &out,
            ],
        );
        assert_eq!(code, Some(0), "{err}");
        assert!(
            stdout.contains(&format!("job:      {n} operations")),
            "{stdout}"
        );
        let stopped = std::fs::read_to_string(dir.join(&out)).unwrap();
        rs274::accepts_file(&dir.join(&out), None);
        let want = moves(&lines[..starts[n]]);
        let got = moves(&stopped.lines().collect::<Vec<_>>());
        assert_eq!(got[..want.len()], want[..], "--upto {n}");
        let tail = &got[want.len()..];
        assert!(
            tail.len() <= 4
                && tail
                    .iter()
                    .all(|l| !l.starts_with("G1") && !l.starts_with("G2") && !l.starts_with("G3")),
            "--upto {n}: the end is {tail:?}"
        );
    }
    let (code, _, err) = oficina_in(
        &dir,
        &[
            "mill",
            "--job",
            "nested-plate.toml",
            "--upto",
            "4",
            "-o",
            "x.nc",
        ],
    );
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("up to operation 4: the job has operations 1 to 3"),
        "{err}"
    );
    let (code, _, err) = oficina_in(
        &dir,
        &[
            "mill",
            "nested-plate.svg",
            "--op",
            "pocket",
            "--upto",
            "1",
            "-o",
            "x.nc",
        ],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--job"), "{err}");
}
