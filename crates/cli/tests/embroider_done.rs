//! Issue #22's first "done when", from the CLI: the sample design (fills, satins, running
//! stitches, three colours) with a lettered name goes to PES, JEF, VP3 and DST, and
//! pyembroidery reads each file as we read it: the same sewn stitches (0.1 mm), trims, colour
//! changes, stops and extents. The pyembroidery half is skipped with a note when python3
//! lacks it (`python3 -m pip install --user pyembroidery`).

mod common;

use common::{oficina, root, text};
use oficina_stitch::{Format, Kind, StitchPlan};
use std::path::{Path, PathBuf};
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    oficina_testkit::scratch_dir("embroider-done").join(name)
}

/// Every command of a file as pyembroidery reads it (letter, x, y in 0.1 mm, y down) and the
/// extents of the points sewn or jumped to.
const DUMP: &str = r#"
import sys, pyembroidery as P
p = P.read(sys.argv[1])
names = {P.STITCH: 'S', P.JUMP: 'J', P.TRIM: 'T', P.COLOR_CHANGE: 'C', P.STOP: 'P', P.END: 'E'}
for x, y, c in p.stitches:
    print(names.get(c & P.COMMAND_MASK, '?'), x, y)
pts = [(x, y) for x, y, c in p.stitches if c & P.COMMAND_MASK in (P.STITCH, P.JUMP)] or [(0, 0)]
print('B', min(x for x, _ in pts), min(y for _, y in pts), max(x for x, _ in pts), max(y for _, y in pts))
"#;

fn python_with_pyembroidery() -> Option<String> {
    let py = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    let ok = Command::new(&py)
        .args(["-c", "import pyembroidery"])
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        Some(py)
    } else {
        eprintln!(
            "note: pyembroidery half skipped, {py} lacks pyembroidery (python3 -m pip install --user pyembroidery)"
        );
        None
    }
}

/// What a reader makes of a file, in the terms both readers share (jumps are not counted:
/// how a run of them is split is the writer's choice; their end points are in the extents).
#[derive(Debug, PartialEq)]
struct Reading {
    /// Sewn stitches, 0.1 mm, y up.
    stitches: Vec<(i64, i64)>,
    trims: usize,
    color_changes: usize,
    stops: usize,
    /// [min x, min y, max x, max y] over the points sewn or jumped to, 0.1 mm, y up.
    extents: [i64; 4],
}

fn peer_read(py: &str, path: &Path) -> Reading {
    let out = Command::new(py)
        .args(["-c", DUMP, path.to_str().unwrap()])
        .output()
        .unwrap();
    oficina_testkit::assert_success(&out);
    let n = |s: &str| s.parse::<f64>().unwrap().round() as i64;
    let mut r = Reading {
        stitches: Vec::new(),
        trims: 0,
        color_changes: 0,
        stops: 0,
        extents: [0; 4],
    };
    for l in String::from_utf8(out.stdout).unwrap().lines() {
        let f: Vec<&str> = l.split_whitespace().collect();
        match f[0] {
            "S" => r.stitches.push((n(f[1]), -n(f[2]))),
            "T" => r.trims += 1,
            "C" => r.color_changes += 1,
            "P" => r.stops += 1,
            "B" => r.extents = [n(f[1]), -n(f[4]), n(f[3]), -n(f[2])],
            _ => {}
        }
    }
    r
}

/// Our reading in pyembroidery's terms for `format`: VP3's move after a trim, which we read
/// as a jump, is a stitch to pyembroidery.
fn ours(plan: &StitchPlan, format: Format) -> Reading {
    let u = |v: f64| (v * 10.0).round() as i64;
    let c = plan.counts();
    let mut stitches = Vec::new();
    let mut b: Option<[f64; 4]> = None;
    for block in &plan.blocks {
        for (i, s) in block.stitches.iter().enumerate() {
            let sewn = s.kind == Kind::Stitch
                || (format == Format::Vp3
                    && s.kind == Kind::Jump
                    && i > 0
                    && block.stitches[i - 1].kind == Kind::Trim);
            if sewn {
                stitches.push((u(s.x), u(s.y)));
            }
            if matches!(s.kind, Kind::Stitch | Kind::Jump) {
                b = Some(b.map_or([s.x, s.y, s.x, s.y], |[a, b, c, d]| {
                    [a.min(s.x), b.min(s.y), c.max(s.x), d.max(s.y)]
                }));
            }
        }
    }
    Reading {
        stitches,
        trims: c.trims,
        color_changes: c.color_changes,
        stops: c.stops,
        extents: b.unwrap_or([0.0; 4]).map(u),
    }
}

fn agree(what: &str, mine: &Reading, peer: &Reading) {
    if let Some(i) = mine
        .stitches
        .iter()
        .zip(&peer.stitches)
        .position(|(a, b)| a != b)
    {
        panic!(
            "{what}: stitch {i} is {:?} for us, {:?} for pyembroidery",
            mine.stitches[i], peer.stitches[i]
        );
    }
    assert_eq!(
        mine.stitches.len(),
        peer.stitches.len(),
        "{what}: stitch count"
    );
    assert_eq!(mine.trims, peer.trims, "{what}: trims");
    assert_eq!(
        mine.color_changes, peer.color_changes,
        "{what}: colour changes"
    );
    assert_eq!(mine.stops, peer.stops, "{what}: stops");
    assert_eq!(mine.extents, peer.extents, "{what}: extents");
}

/// `fill, satin, running` from the CLI's "shapes: …" line.
fn shapes(stdout: &str) -> (usize, usize, usize) {
    let line = stdout
        .lines()
        .find_map(|l| l.strip_prefix("shapes: "))
        .unwrap_or_else(|| panic!("no shapes line in {stdout}"));
    let n: Vec<usize> = line
        .split(", ")
        .map(|p| p.split_whitespace().next().unwrap().parse().unwrap())
        .collect();
    (n[0], n[1], n[2])
}

/// The figure after `key` on the sheet the CLI prints.
fn figure(stdout: &str, key: &str) -> usize {
    stdout
        .lines()
        .find_map(|l| l.strip_prefix(key))
        .and_then(|v| v.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no {key} in {stdout}"))
}

/// `oficina embroider sunflower.svg [--text Ana] -o OUT`: its stdout (the name is set under
/// the design, centred, as `--text-at` is not given).
fn embroider(out: &Path, lettered: bool) -> String {
    let sample = root().join("samples/embroidery/sunflower.svg");
    let mut args = vec![
        "embroider",
        sample.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    if lettered {
        args.extend(["--text", "Ana"]);
    }
    let o = oficina(&args);
    let (stdout, stderr) = text(&o);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    stdout
}

#[test]
fn a_lettered_multicolour_design_goes_to_pes_jef_vp3_dst_and_pyembroidery_reads_each_identically() {
    let py = python_with_pyembroidery();
    for format in [Format::Pes, Format::Jef, Format::Vp3, Format::Dst] {
        let ext = format.extension();
        let plain = scratch(&format!("sunflower.{ext}"));
        let named = scratch(&format!("sunflower-ana.{ext}"));
        let without = embroider(&plain, false);
        let with = embroider(&named, true);

        // Fills, satins and running stitches; the lettering adds satin columns.
        let (fills, satins, runs) = shapes(&with);
        let (_, plain_satins, _) = shapes(&without);
        assert!(fills > 0 && satins > 0 && runs > 0, "{ext}: {with}");
        assert!(satins > plain_satins, "{ext}: the name's satins: {with}");
        let stitches = figure(&with, "Stitches");
        assert!(
            stitches > figure(&without, "Stitches") + 100,
            "{ext}: the name's stitches"
        );
        assert!(figure(&with, "Colours") >= 2, "{ext}: {with}");

        // Our reader: the file, by its extension, holds what the sheet says.
        let bytes = std::fs::read(&named).unwrap();
        assert_eq!(Format::from_path(&named), Some(format), "{ext}");
        let back = format.read(&bytes, "sunflower-ana").unwrap();
        let c = back.counts();
        assert_eq!(c.stitches, stitches, "{ext}: sheet and file");
        assert!(back.blocks.len() >= 2, "{ext}: colours");
        assert!(c.trims > 0, "{ext}: trims");
        let o = oficina(&["embroider", "--info", named.to_str().unwrap()]);
        let (info, stderr) = text(&o);
        assert!(o.status.success(), "{info}\n{stderr}");
        assert_eq!(figure(&info, "Stitches"), stitches, "{ext}: --info");
        // The name, 15 mm high, is set half its height under the flower's ground line (the
        // files are centred in the hoop): the lettered design is at least 15 mm taller, and
        // its lowest 14 mm hold the name's stitches alone.
        let sewn_y = |p: &StitchPlan| -> Vec<f64> {
            p.entries()
                .filter(|(_, s)| s.kind == Kind::Stitch)
                .map(|(_, s)| s.y)
                .collect()
        };
        let span = |ys: &[f64]| {
            let lo = ys.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (lo, hi - lo)
        };
        let plain_back = format
            .read(&std::fs::read(&plain).unwrap(), "sunflower")
            .unwrap();
        let ys = sewn_y(&back);
        let (bottom, height) = span(&ys);
        let (_, plain_height) = span(&sewn_y(&plain_back));
        assert!(
            height > plain_height + 15.0,
            "{ext}: {height:.1} mm tall with the name, {plain_height:.1} mm without"
        );
        let name = ys.iter().filter(|&&y| y < bottom + 14.0).count();
        assert!(name > 100, "{ext}: {name} stitches of the name");
        // Centred under the design.
        let xs = |low: bool| -> Vec<f64> {
            back.entries()
                .filter(|(_, s)| s.kind == Kind::Stitch && (!low || s.y < bottom + 14.0))
                .map(|(_, s)| s.x)
                .collect()
        };
        let ((x0, w), (n0, nw)) = (span(&xs(false)), span(&xs(true)));
        assert!(
            ((x0 + w / 2.0) - (n0 + nw / 2.0)).abs() < 3.0,
            "{ext}: the name spans x {n0:.1}+{nw:.1}, the design {x0:.1}+{w:.1}"
        );

        let Some(py) = &py else { continue };
        let peer = peer_read(py, &named);
        let mine = ours(&back, format);
        agree(&format!("{ext} lettered"), &mine, &peer);
        println!(
            "{format}: {} sewn, {} trims, {} colour changes, extents {:?} (0.1 mm): pyembroidery reads the same",
            peer.stitches.len(),
            peer.trims,
            peer.color_changes,
            peer.extents
        );
    }
}
