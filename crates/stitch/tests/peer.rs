//! pyembroidery, the reference reader/writer of embroidery files, as the oracle of our DST
//! and EXP: files we write are read by pyembroidery stitch by stitch, and files
//! pyembroidery writes are read by us. Skipped with a note when python3 lacks pyembroidery
//! (`python3 -m pip install --user pyembroidery`, see scripts/install-deps).

use oficina_stitch::{ColorBlock, Format, Kind, Stitch, StitchPlan, Thread};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Prints every command of a file as pyembroidery reads it: letter, x, y (0.1 mm, y down).
const DUMP: &str = r#"
import sys, pyembroidery as P
p = P.read(sys.argv[1])
names = {P.STITCH: 'S', P.JUMP: 'J', P.TRIM: 'T', P.COLOR_CHANGE: 'C', P.STOP: 'P', P.END: 'E'}
for x, y, c in p.stitches:
    print(names.get(c & P.COMMAND_MASK, '?'), x, y)
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
            "note: skipped, {py} lacks pyembroidery (python3 -m pip install --user pyembroidery)"
        );
        None
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = oficina_testkit::scratch_dir("stitch-peer");
    dir.join(name)
}

/// pyembroidery's reading of `path`: (command letter, x, y) in 0.1 mm, y up.
fn peer_read(py: &str, path: &Path) -> Vec<(char, i64, i64)> {
    let out = Command::new(py)
        .args(["-c", DUMP, path.to_str().unwrap()])
        .output()
        .unwrap();
    oficina_testkit::assert_success(&out);
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            let n = |s: &str| s.parse::<f64>().unwrap().round() as i64;
            (f[0].chars().next().unwrap(), n(f[1]), -n(f[2]))
        })
        .collect()
}

/// Our reading: sewn stitches in 0.1 mm, trims, colour changes.
fn ours(plan: &StitchPlan) -> (Vec<(i64, i64)>, usize, usize) {
    let u = |v: f64| (v * 10.0).round() as i64;
    let stitches = plan
        .entries()
        .filter(|(_, s)| s.kind == Kind::Stitch)
        .map(|(_, s)| (u(s.x), u(s.y)))
        .collect();
    let c = plan.counts();
    (stitches, c.trims, c.color_changes)
}

fn theirs(cmds: &[(char, i64, i64)]) -> (Vec<(i64, i64)>, usize, usize) {
    let stitches = cmds
        .iter()
        .filter(|c| c.0 == 'S')
        .map(|c| (c.1, c.2))
        .collect();
    let count = |k| cmds.iter().filter(|c| c.0 == k).count();
    (stitches, count('T'), count('C'))
}

/// A plan that exercises the limits: stitches longer than a record (split), jumps of
/// 2 to 6 records, a trim, colour changes, negative and fractional coordinates.
fn awkward_plan() -> StitchPlan {
    let mut a = vec![Stitch::new(-3.04, 2.96, Kind::Jump)];
    for i in 0..120 {
        let t = i as f64 * 0.21;
        a.push(Stitch::new(
            -3.0 + t * 1.7,
            3.0 + 9.0 * t.sin(),
            Kind::Stitch,
        ));
    }
    a.push(Stitch::new(a.last().unwrap().x + 15.3, -4.46, Kind::Stitch)); // > 12.7 mm
    a.push(Stitch::new(0.0, 0.0, Kind::Trim));
    a.push(Stitch::new(-61.27, -40.02, Kind::Jump)); // 6 DST records
    a.push(Stitch::new(-60.0, -39.0, Kind::Stitch));
    let mut b = vec![Stitch::new(30.0, 45.55, Kind::Jump)];
    for i in 0..200 {
        let r = 5.0 + i as f64 * 0.1;
        let t = i as f64 * 0.3;
        b.push(Stitch::new(
            30.0 + r * t.cos(),
            45.55 + r * t.sin(),
            Kind::Stitch,
        ));
    }
    let c = vec![
        Stitch::new(-20.0, 10.0, Kind::Jump), // 2 records, no trim
        Stitch::new(-20.0, 12.5, Kind::Stitch),
        Stitch::new(-8.0, 12.5, Kind::Stitch),
    ];
    // The trim's position is where the needle is; fix it from the previous entry.
    let trim_at = a[a.len() - 4];
    let i = a.len() - 3;
    a[i] = Stitch::new(trim_at.x, trim_at.y, Kind::Trim);
    StitchPlan {
        name: "awkward".into(),
        blocks: vec![
            ColorBlock {
                thread: Thread::rgb(200, 0, 0),
                stitches: a,
            },
            ColorBlock {
                thread: Thread::rgb(0, 0, 200),
                stitches: b,
            },
            ColorBlock {
                thread: Thread::rgb(0, 150, 0),
                stitches: c,
            },
        ],
    }
}

#[test]
fn pyembroidery_reads_every_stitch_we_write() {
    let Some(py) = python_with_pyembroidery() else {
        return;
    };
    let plan = awkward_plan();
    for format in Format::ALL {
        let bytes = format.write(&plan).unwrap();
        let path = scratch(&format!("ours.{}", format.extension()));
        std::fs::write(&path, &bytes).unwrap();
        let peer = theirs(&peer_read(&py, &path));
        let back = format.read(&bytes, "ours").unwrap();
        let mine = ours(&back);
        assert_eq!(mine.0.len(), peer.0.len(), "{format}: stitch count");
        assert_eq!(mine, peer, "{format}: every stitch, trims, colour changes");
        // And the file holds the plan: each sewn point of the plan is a stitch of the file
        // at its 0.1 mm rounding (split stitches add points between, never move them).
        let planned = ours(&plan).0;
        let mut it = mine.0.iter();
        for p in &planned {
            assert!(it.any(|q| q == p), "{format}: planned stitch {p:?} missing");
        }
        assert_eq!(peer.1, 1, "{format}: one trim");
        assert_eq!(peer.2, 2, "{format}: two colour changes");
        println!(
            "{format}: {} stitches agree with pyembroidery exactly",
            peer.0.len()
        );
    }
}

/// pyembroidery writes a pattern (its own encoder splits, jumps, trims); we read the file
/// and must see what pyembroidery reads back from it.
const WRITE: &str = r#"
import sys, math, pyembroidery as P
p = P.EmbPattern()
for c in ('#ff0000', '#00aa00', '#0000ff'):
    p.add_thread(c)
x = y = 0.0
for i in range(300):
    t = i * 0.17
    p.add_stitch_absolute(P.STITCH, 40 * math.cos(t) * (1 + t / 10), 40 * math.sin(t) * (1 + t / 10))
p.add_command(P.TRIM)
p.add_stitch_absolute(P.JUMP, -700, 500)
for i in range(50):
    p.add_stitch_absolute(P.STITCH, -700 + 33 * i, 500 + (i % 2) * 60)
p.add_command(P.COLOR_CHANGE)
for i in range(80):
    p.add_stitch_absolute(P.STITCH, 300 - 7 * i, -300 + 190 * (i % 2))
p.add_command(P.COLOR_CHANGE)
p.add_stitch_absolute(P.STITCH, 900, 900)
p.add_stitch_absolute(P.STITCH, 905, 1000)
p.add_command(P.END)
P.write(p, sys.argv[1])
"#;

#[test]
fn we_read_every_stitch_pyembroidery_writes() {
    let Some(py) = python_with_pyembroidery() else {
        return;
    };
    for format in Format::ALL {
        let path = scratch(&format!("theirs.{}", format.extension()));
        let out = Command::new(&py)
            .args(["-c", WRITE, path.to_str().unwrap()])
            .output()
            .unwrap();
        oficina_testkit::assert_success(&out);
        let bytes = std::fs::read(&path).unwrap();
        let plan = format.read(&bytes, "theirs").unwrap();
        let mine = ours(&plan);
        let peer = theirs(&peer_read(&py, &path));
        assert!(peer.0.len() > 400, "{format}: {}", peer.0.len());
        assert_eq!(mine, peer, "{format}: every stitch, trims, colour changes");
        println!(
            "{format}: pyembroidery wrote {} stitches, {} trims, {} colour changes; we read the same",
            peer.0.len(),
            peer.1,
            peer.2
        );
    }
}
