//! pyembroidery, the reference reader of embroidery files, as an oracle: what it reads from a
//! file and what we read, in the terms both readers share. Included by the stitch crate's
//! peer tests and by the CLI's (`#[path]`), so both compare the same way.
#![allow(dead_code)]

use oficina_stitch::{ColorBlock, Format, Kind, StitchPlan};
use std::path::Path;
use std::process::Command;

/// Prints every command of a file as pyembroidery reads it (letter, x, y in 0.1 mm, y down),
/// then its threads and its bounds.
const DUMP: &str = r#"
import sys, pyembroidery as P
p = P.read(sys.argv[1])
names = {P.STITCH: 'S', P.JUMP: 'J', P.TRIM: 'T', P.COLOR_CHANGE: 'C', P.STOP: 'P', P.END: 'E', P.NEEDLE_SET: 'N'}
for x, y, c in p.stitches:
    print(names.get(c & P.COMMAND_MASK, '?'), x, y)
for t in p.threadlist:
    print('H', t.hex_color() if t is not None else 'none')
# The extents of the points sewn or jumped to (a command at the origin, as U01's first
# needle, is no point of the design).
pts = [(x, y) for x, y, c in p.stitches if c & P.COMMAND_MASK in (P.STITCH, P.JUMP)] or [(0, 0)]
print('B', min(x for x, _ in pts), min(y for _, y in pts), max(x for x, _ in pts), max(y for _, y in pts))
"#;

pub(crate) fn python_with_pyembroidery() -> Option<String> {
    let py = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    let ok = Command::new(&py)
        .args(["-c", "import pyembroidery"])
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        Some(py)
    } else {
        eprintln!(
            "note: skipped, {py} lacks pyembroidery (python3 -m pip install --user pyembroidery)"
        );
        None
    }
}

/// What a reader makes of a file, in the terms both readers share (jumps are not counted:
/// how a run of them is split is the writer's choice, their end points are in the extents).
#[derive(Debug, PartialEq)]
pub(crate) struct Reading {
    /// Sewn stitches, 0.1 mm, y up.
    pub(crate) stitches: Vec<(i64, i64)>,
    pub(crate) trims: usize,
    pub(crate) color_changes: usize,
    pub(crate) stops: usize,
    /// [min x, min y, max x, max y] over the points sewn or jumped to, 0.1 mm, y up.
    pub(crate) extents: [i64; 4],
}

/// pyembroidery's reading of `path` and its threads (`#rrggbb`, "none" for an empty slot).
pub(crate) fn peer_read(py: &str, path: &Path) -> (Reading, Vec<String>) {
    let out = Command::new(py)
        .args(["-c", DUMP, path.to_str().unwrap()])
        .output()
        .unwrap();
    oficina_testkit::assert_success(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    let n = |s: &str| s.parse::<f64>().unwrap().round() as i64;
    let mut r = Reading {
        stitches: Vec::new(),
        trims: 0,
        color_changes: 0,
        stops: 0,
        extents: [0; 4],
    };
    let mut threads = Vec::new();
    for l in text.lines() {
        let f: Vec<&str> = l.split_whitespace().collect();
        match f[0] {
            "S" => r.stitches.push((n(f[1]), -n(f[2]))),
            "T" => r.trims += 1,
            "C" => r.color_changes += 1,
            // U01's needle changes: the first, before anything is sewn, picks the first thread.
            "N" if !r.stitches.is_empty() => r.color_changes += 1,
            "P" => r.stops += 1,
            "H" => threads.push(f[1].to_string()),
            "B" => r.extents = [n(f[1]), -n(f[4]), n(f[3]), -n(f[2])],
            _ => {}
        }
    }
    (r, threads)
}

pub(crate) fn ours(plan: &StitchPlan) -> Reading {
    ours_as(plan, Format::Dst)
}

/// Our reading in pyembroidery's terms for `format`: VP3's move after a trim, which we read
/// as a jump, is a stitch to pyembroidery.
pub(crate) fn ours_as(plan: &StitchPlan, format: Format) -> Reading {
    let u = |v: f64| (v * 10.0).round() as i64;
    let c = plan.counts();
    let b = plan
        .entries()
        .filter(|(_, s)| matches!(s.kind, Kind::Stitch | Kind::Jump))
        .fold(None, |acc: Option<[f64; 4]>, (_, s)| {
            Some(acc.map_or([s.x, s.y, s.x, s.y], |[a, b, c, d]| {
                [a.min(s.x), b.min(s.y), c.max(s.x), d.max(s.y)]
            }))
        })
        .unwrap_or([0.0; 4]);
    let sewn = |block: &ColorBlock, i: usize| {
        let s = block.stitches[i];
        s.kind == Kind::Stitch
            || (format == Format::Vp3
                && s.kind == Kind::Jump
                && i > 0
                && block.stitches[i - 1].kind == Kind::Trim)
    };
    Reading {
        stitches: plan
            .blocks
            .iter()
            .flat_map(|b| {
                (0..b.stitches.len())
                    .filter(move |&i| sewn(b, i))
                    .map(move |i| &b.stitches[i])
            })
            .map(|s| (u(s.x), u(s.y)))
            .collect(),
        trims: c.trims,
        color_changes: c.color_changes,
        stops: c.stops,
        extents: b.map(u),
    }
}

/// Asserts that two readings agree, naming the first stitch that differs.
pub(crate) fn agree(what: &str, mine: &Reading, peer: &Reading) {
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
