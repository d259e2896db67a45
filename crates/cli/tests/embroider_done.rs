//! Issue #22's first "done when", from the CLI: the sample design (fills, satins, running
//! stitches, three colours) with a lettered name goes to PES, JEF, VP3 and DST, and
//! pyembroidery reads each file as we read it: the same sewn stitches (0.1 mm), trims, colour
//! changes, stops and extents. The pyembroidery half is skipped with a note when python3
//! lacks it (`python3 -m pip install --user pyembroidery`).

mod common;
#[path = "../../stitch/tests/common/pyembroidery.rs"]
mod pyembroidery;

use common::{oficina, root, text};
use oficina_stitch::{Format, Kind, StitchPlan};
use pyembroidery::{agree, ours_as, peer_read, python_with_pyembroidery};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    oficina_testkit::scratch_dir("embroider-done").join(name)
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
        let (peer, _) = peer_read(py, &named);
        let mine = ours_as(&back, format);
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
