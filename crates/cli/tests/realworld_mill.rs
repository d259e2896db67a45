//! The DXF/SVG parts that CAD programs and their users wrote (`../shared/data/realworld/
//! mill-dxf-svg`, beside the checkout) mill as a user would run them, from a folder outside
//! the checkout: the loops found (closed in the file, closed where their ends meet, chained),
//! no gouge, and the planner's time. The DXF files are compared with ezdxf, the peer reader
//! (`scripts/ezdxf_loops.py`), on loops, total length and extents. Tests skip with a note
//! when the shared data or ezdxf is missing.

mod common;

use common::{root, text};
use std::path::{Path, PathBuf};
use std::process::Command;

fn data() -> Option<PathBuf> {
    oficina_testkit::realworld("mill-dxf-svg")
}

/// Each part: file, closed loops imported, and what the import summary must say of them.
const PARTS: &[(&str, usize, &str)] = &[
    // 4 LINEs and 4 ARCs meeting end to end: one outline.
    ("camotics_border.dxf", 1, "1 chained from 8 pieces"),
    ("camotics_stretching_cat.svg", 1, "1 closed in the file"),
    ("emm_Puzzle-R2007.dxf", 1, "1 closed in the file"),
    // The outline and the features; one stray LINE pair on layer 0 stays open (reported).
    ("emm_Tux-R2000.dxf", 25, "25 closed in the file"),
    // 14 closed POLYLINEs (some in a tilted plane) and a 3DFACE's outline.
    ("ezdxf_POLI-ALL210_12.DXF", 15, "15 closed in the file"),
    ("ezdxf_forms.dxf", 40, "40 closed in the file"),
    // A square and a 24-gon drawn back to their start, no `Z`.
    (
        "maslowmech_6 Inch Square Test Shape.svg",
        2,
        "2 closed where their ends meet",
    ),
    // Five 24-gon POLYLINEs ending on their start, no closed flag.
    (
        "obcam_Motor NEMA17 - Mount.dxf",
        5,
        "5 closed where their ends meet",
    ),
];

/// `oficina mill FILE --op OP … -o x.nc` run in `dir`; stdout, after asserting success.
fn mill(dir: &Path, file: &Path, op: &str, extra: &[&str]) -> String {
    let out = dir.join("x.nc");
    let mut args = vec![
        "mill",
        file.to_str().unwrap(),
        "--op",
        op,
        "--depth",
        "3",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let run = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .current_dir(dir)
        .args(&args)
        .output()
        .expect("the binary runs");
    let (stdout, stderr) = text(&run);
    assert!(
        run.status.success(),
        "{} {op}: {stderr}\n{stdout}",
        file.display()
    );
    assert!(out.is_file());
    stdout
}

/// The import summary's loop count and the report's gouge line.
fn check_loops_and_gouge(name: &str, stdout: &str, loops: usize, how: &str) {
    let want = format!(
        "imported: {loops} closed loop{}: ",
        if loops == 1 { "" } else { "s" }
    );
    let line = stdout
        .lines()
        .find(|l| l.starts_with(&want))
        .unwrap_or_else(|| panic!("{name}: no '{want}' in\n{stdout}"));
    assert!(line.contains(how), "{name}: want '{how}' in {line}");
    assert!(
        stdout.contains("gouge:    none"),
        "{name}: a gouge or no check\n{stdout}"
    );
}

/// A machine as the bundled router but with `travel` mm of X and Y, written into `dir`.
fn big_router(dir: &Path, travel: f64) -> PathBuf {
    let text = std::fs::read_to_string(root().join("profiles/grbl-router.toml")).unwrap();
    let text = text
        .replace("x = [0.0, 800.0]", &format!("x = [0.0, {travel}]"))
        .replace("y = [0.0, 450.0]", &format!("y = [0.0, {travel}]"));
    assert!(text.contains(&format!("y = [0.0, {travel}]")));
    let path = dir.join("big-router.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn every_real_part_mills_profile_out_with_no_gouge_and_the_planners_time_from_any_folder() {
    let Some(data) = data() else { return };
    let dir = tempfile::tempdir().unwrap();
    // A file named like the bundled profile in the current folder: the name still means the
    // bundled profile (it never depends on the folder).
    std::fs::write(dir.path().join("grbl-router"), "not a profile").unwrap();
    for &(name, loops, how) in PARTS {
        let file = data.join(name);
        let stdout = mill(dir.path(), &file, "profile-out", &[]);
        check_loops_and_gouge(name, &stdout, loops, how);
        if name == "ezdxf_forms.dxf" {
            // 1 m square: larger than the router, which the report says; timed on a larger one.
            assert!(
                stdout.contains("the program spans 1025.4 × 1018.2 mm, the machine's travel is 800.0 × 450.0 mm"),
                "{stdout}"
            );
            let big = big_router(dir.path(), 2000.0);
            let stdout = mill(
                dir.path(),
                &file,
                "profile-out",
                &["--profile", big.to_str().unwrap()],
            );
            assert!(stdout.contains("(planner"), "{name}: {stdout}");
            continue;
        }
        assert!(
            stdout
                .lines()
                .any(|l| l.trim_start().starts_with("time:") && l.contains("(planner")),
            "{name}: no planner time\n{stdout}"
        );
    }
}

#[test]
fn parts_with_islands_pocket_with_no_gouge() {
    let Some(data) = data() else { return };
    let dir = tempfile::tempdir().unwrap();
    for &(name, loops, how) in &[
        // The square with the round island.
        (
            "maslowmech_6 Inch Square Test Shape.svg",
            2,
            "2 closed where their ends meet",
        ),
        // Tux's outline with its eyes, beak and belly inside.
        ("emm_Tux-R2000.dxf", 25, "25 closed in the file"),
    ] {
        let stdout = mill(
            dir.path(),
            &data.join(name),
            "pocket",
            &["--tool", "flat:3"],
        );
        check_loops_and_gouge(name, &stdout, loops, how);
        assert!(stdout.contains("(planner)"), "{name}: {stdout}");
    }
}

#[test]
fn open_pieces_are_reported_per_layer_with_the_largest_gap() {
    let Some(data) = data() else { return };
    let dir = tempfile::tempdir().unwrap();
    let stdout = mill(
        dir.path(),
        &data.join("emm_Tux-R2000.dxf"),
        "profile-out",
        &[],
    );
    // Two LINEs on layer 0 meet each other but not their far ends: one open path, 218.5 mm
    // between its ends, named by its entities.
    let line = stdout
        .lines()
        .find(|l| l.starts_with("imported: open on layer 0: 1 path, largest gap 218.499 mm"))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(line.contains("LINE #1DF5 + LINE #1DF6"), "{line}");
    // The 24-gon holes of the NEMA 17 mount drill as holes: the bore and four screws.
    let out = dir.path().join("d.nc");
    let run = common::oficina_in(
        dir.path(),
        &[
            "mill",
            data.join("obcam_Motor NEMA17 - Mount.dxf")
                .to_str()
                .unwrap(),
            "--op",
            "drill",
            "--tool",
            "flat:3",
            "--depth",
            "3",
            "-o",
            out.to_str().unwrap(),
        ],
    );
    assert!(run.status.success(), "{}", text(&run).1);
    let program = std::fs::read_to_string(&out).unwrap();
    let mut holes: Vec<&str> = program
        .lines()
        .filter(|l| l.contains("G81"))
        .map(|l| l.split(" Z").next().unwrap().trim_start_matches("G99 G81 "))
        .collect();
    holes.sort();
    assert_eq!(
        holes,
        [
            "X21 Y21",
            "X36.5 Y36.5",
            "X36.5 Y5.5",
            "X5.5 Y36.5",
            "X5.5 Y5.5"
        ],
        "{program}"
    );
}

/// Where the DXF reader differs from ezdxf on extents, and why: the figure is printed, not
/// asserted. None today (the reader projects entities in a tilted plane onto XY as ezdxf does).
const KNOWN_EXTENTS: &[(&str, &str)] = &[];

/// ezdxf's figures for `file` (None, with a note, when python3 or ezdxf is missing).
fn ezdxf(file: &Path) -> Option<serde_json::Value> {
    let run = Command::new("python3")
        .arg(root().join("scripts/ezdxf_loops.py"))
        .arg(file)
        .output();
    match run {
        Ok(o) if o.status.success() => serde_json::from_slice(&o.stdout).ok(),
        Ok(o) => {
            eprintln!(
                "note: ezdxf_loops.py failed (is ezdxf installed?): {}",
                String::from_utf8_lossy(&o.stderr)
            );
            None
        }
        Err(e) => {
            eprintln!("note: no python3 ({e}): the ezdxf comparison is skipped");
            None
        }
    }
}

#[test]
fn dxf_loops_length_and_extents_match_ezdxf() {
    let Some(data) = data() else { return };
    let mut wrong = vec![];
    let mut table = vec![format!(
        "{:<32} {:>11} {:>11} {:>12} {:>12}  units (ours / ezdxf, mm per unit)",
        "file", "loops ours", "loops ezdxf", "length ours", "length ezdxf"
    )];
    for &(name, _, _) in PARTS
        .iter()
        .filter(|p| p.0.to_lowercase().ends_with(".dxf"))
    {
        let file = data.join(name);
        let Some(peer) = ezdxf(&file) else { return };
        let ours = oficina_io::load_drawing(&file).unwrap_or_else(|e| panic!("{e}"));
        // In the file's own units: how $INSUNITS is read is compared apart (below).
        let k = ours.mm_per_unit;
        let length: f64 = ours.drawing.paths().map(|p| p.length()).sum::<f64>() / k;
        let b = ours.drawing.bounding_box().unwrap();
        let ext = [b.x0 / k, b.y0 / k, b.x1 / k, b.y1 / k];
        let peer_loops = peer["loops"].as_u64().unwrap() as usize;
        let peer_length = peer["length_units"].as_f64().unwrap();
        let peer_ext: Vec<f64> = peer["extents_units"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        table.push(format!(
            "{name:<32} {:>11} {:>11} {:>12.3} {:>12.3}  {} / {}",
            ours.closure.loops(),
            peer_loops,
            length,
            peer_length,
            k,
            peer["mm_per_unit"]
        ));
        if ours.closure.loops() != peer_loops {
            wrong.push(format!(
                "{name}: loops {} vs ezdxf {peer_loops}\n{}",
                ours.closure.loops(),
                ours.closure
            ));
        }
        // Chords of curves flattened to 1 µm: lengths agree to 0.05 %.
        if (length - peer_length).abs() > 5e-4 * peer_length {
            wrong.push(format!("{name}: length {length} vs ezdxf {peer_length}"));
        }
        let size = (peer_ext[2] - peer_ext[0]).max(peer_ext[3] - peer_ext[1]);
        if ext
            .iter()
            .zip(&peer_ext)
            .any(|(a, p)| (a - p).abs() > 1e-4 * size + 1e-6)
        {
            let msg = format!("{name}: extents {ext:?} vs ezdxf {peer_ext:?}");
            match KNOWN_EXTENTS.iter().find(|k| k.0 == name) {
                Some((_, why)) => eprintln!("note (known, not asserted): {msg}: {why}"),
                None => wrong.push(msg),
            }
        }
    }
    eprintln!("{}", table.join("\n"));
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
