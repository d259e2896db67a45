//! pyembroidery, the reference reader/writer of embroidery files, as the oracle of every
//! format Oficina writes: files we write are read by pyembroidery stitch by stitch, files
//! pyembroidery writes are read by us, and so are the real files of
//! `../shared/data/realworld/embroidery-files`: the same sewn stitches (exactly, in 0.1 mm),
//! trims, colour changes, stops, thread colours and extents. Skipped with a note when
//! python3 lacks pyembroidery (`python3 -m pip install --user pyembroidery`, see
//! scripts/install-deps).

mod common;
#[path = "common/pyembroidery.rs"]
mod pyembroidery;

use oficina_stitch::{ColorBlock, Format, Kind, Stitch, StitchPlan, Thread};
use pyembroidery::{agree, ours, ours_as, peer_read, python_with_pyembroidery};
use std::path::PathBuf;
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let dir = oficina_testkit::scratch_dir("stitch-peer");
    dir.join(name)
}

/// Formats that store colours: our blocks' threads are pyembroidery's threads, in order.
fn same_threads(what: &str, format: Format, plan: &StitchPlan, peer: &[String]) {
    if matches!(format, Format::Dst | Format::Exp | Format::U01) {
        return;
    }
    let mine: Vec<String> = plan.blocks.iter().map(|b| b.thread.hex()).collect();
    assert!(peer.len() >= mine.len(), "{what}: {peer:?} for {mine:?}");
    assert_eq!(mine, peer[..mine.len()], "{what}: thread colours");
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
P.write(p, sys.argv[1], {'version': sys.argv[2]} if len(sys.argv) > 2 else None)
"#;

/// The colour a format keeps of a thread: exact where it stores RGB, else a chart colour.
fn stores_rgb(format: Format) -> bool {
    matches!(format, Format::Pes | Format::Vp3 | Format::Xxx)
}

#[test]
fn pyembroidery_reads_every_stitch_we_write() {
    let Some(py) = python_with_pyembroidery() else {
        return;
    };
    let plan = awkward_plan();
    for format in Format::ALL {
        let bytes = format.write(&plan).unwrap();
        let path = scratch(&format!("ours-{}.{}", format.id(), format.extension()));
        std::fs::write(&path, &bytes).unwrap();
        let (peer, peer_threads) = peer_read(&py, &path);
        let back = format.read(&bytes, "ours").unwrap();
        let mine = ours_as(&back, format);
        agree(&format!("{format} we wrote"), &mine, &peer);
        same_threads(&format!("{format} we wrote"), format, &back, &peer_threads);
        // And the file holds the plan: each sewn point of the plan is a stitch of the file
        // at its 0.1 mm rounding (split stitches add points between, never move them).
        let planned = ours(&plan);
        let read = ours(&back);
        let mut it = read.stitches.iter();
        for p in &planned.stitches {
            assert!(it.any(|q| q == p), "{format}: planned stitch {p:?} missing");
        }
        // VP3 cuts the thread at the end too (its machines do not), as pyembroidery writes.
        let trims = if format == Format::Vp3 { 2 } else { 1 };
        assert_eq!(peer.trims, trims, "{format}: the trim");
        assert_eq!(peer.color_changes, 2, "{format}: two colour changes");
        assert_eq!(back.blocks.len(), 3, "{format}: three blocks");
        if stores_rgb(format) {
            for (a, b) in back.blocks.iter().zip(&plan.blocks) {
                assert_eq!(a.thread.rgb, b.thread.rgb, "{format}: exact colours");
            }
        }
        println!(
            "{format}: {} stitches, {} trims, {} colour changes, threads {:?}: pyembroidery reads the same",
            peer.stitches.len(),
            peer.trims,
            peer.color_changes,
            &peer_threads[..peer_threads.len().min(3)]
        );
    }
}

/// The sample design (fills, satins, running stitches, three colours, trims) as Oficina
/// generates it: pyembroidery reads each format's file as we read it back.
#[test]
fn the_sample_design_reads_identically_in_every_format() {
    let Some(py) = python_with_pyembroidery() else {
        return;
    };
    let plan = common::sample();
    for format in Format::ALL {
        let bytes = format.write(&plan).unwrap();
        let path = scratch(&format!("sample-{}.{}", format.id(), format.extension()));
        std::fs::write(&path, &bytes).unwrap();
        let (peer, threads) = peer_read(&py, &path);
        let back = format.read(&bytes, "sample").unwrap();
        agree(&format!("sample {format}"), &ours_as(&back, format), &peer);
        same_threads(&format!("sample {format}"), format, &back, &threads);
        assert_eq!(back.blocks.len(), 3, "{format}");
        assert_eq!(
            ours(&back).stitches,
            ours(&plan).stitches,
            "{format}: the design's stitches"
        );
    }
}

/// Stops survive in the formats that have one (PES and PEC as a change to the same thread,
/// JEF as a change to thread 0, U01's stop code); DST, EXP and XXX stop at their colour
/// change code, VP3 has none.
#[test]
fn stops_are_read_as_pyembroidery_reads_them() {
    let Some(py) = python_with_pyembroidery() else {
        return;
    };
    let mut plan = awkward_plan();
    let b = &mut plan.blocks[1].stitches;
    let at = b[50];
    b.insert(51, Stitch::new(at.x, at.y, Kind::Stop));
    for format in Format::ALL {
        let bytes = format.write(&plan).unwrap();
        let path = scratch(&format!("stop-{}.{}", format.id(), format.extension()));
        std::fs::write(&path, &bytes).unwrap();
        let (peer, _) = peer_read(&py, &path);
        let back = format.read(&bytes, "stop").unwrap();
        agree(
            &format!("{format} with a stop"),
            &ours_as(&back, format),
            &peer,
        );
        let want = match format {
            Format::Pes | Format::PesV1 | Format::Pec | Format::Jef | Format::U01 => (1, 2),
            Format::Vp3 => (0, 2),
            _ => (0, 3),
        };
        let c = back.counts();
        assert_eq!((c.stops, c.color_changes), want, "{format}: stops, changes");
    }
}

#[test]
fn we_read_every_stitch_pyembroidery_writes() {
    let Some(py) = python_with_pyembroidery() else {
        return;
    };
    for format in Format::ALL {
        let path = scratch(&format!("theirs-{}.{}", format.id(), format.extension()));
        let mut cmd = Command::new(&py);
        cmd.args(["-c", WRITE, path.to_str().unwrap()]);
        match format {
            Format::Pes => cmd.arg("6"),
            Format::PesV1 => cmd.arg("1"),
            _ => &mut cmd,
        };
        let out = cmd.output().unwrap();
        oficina_testkit::assert_success(&out);
        let bytes = std::fs::read(&path).unwrap();
        let sniffed = Format::sniff(&bytes);
        if let Some(s) = sniffed {
            assert_eq!(
                s.extension(),
                format.extension(),
                "{format}: sniffed as {s}"
            );
        }
        let plan = format.read(&bytes, "theirs").unwrap();
        let (peer, threads) = peer_read(&py, &path);
        assert!(
            peer.stitches.len() > 400,
            "{format}: {}",
            peer.stitches.len()
        );
        agree(
            &format!("{format} pyembroidery wrote"),
            &ours_as(&plan, format),
            &peer,
        );
        same_threads(
            &format!("{format} pyembroidery wrote"),
            format,
            &plan,
            &threads,
        );
        println!(
            "{format}: pyembroidery wrote {} stitches, {} trims, {} colour changes; we read the same",
            peer.stitches.len(),
            peer.trims,
            peer.color_changes
        );
    }
}

fn realworld() -> Option<PathBuf> {
    oficina_testkit::realworld("embroidery-files")
}

#[test]
fn real_files_read_as_pyembroidery_reads_them() {
    let Some(py) = python_with_pyembroidery() else {
        return;
    };
    let Some(dir) = realworld() else {
        return;
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| Format::from_path(p).is_some())
        .collect();
    files.sort();
    assert!(
        files.len() >= 6,
        "{} files in {}",
        files.len(),
        dir.display()
    );
    for path in files {
        let bytes = std::fs::read(&path).unwrap();
        let by_ext = Format::from_path(&path).unwrap();
        let format = Format::sniff(&bytes).unwrap_or(by_ext);
        assert_eq!(format.extension(), by_ext.extension(), "{}", path.display());
        let plan = format
            .read(&bytes, "real")
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (peer, threads) = peer_read(&py, &path);
        let what = path.file_name().unwrap().to_string_lossy().to_string();
        agree(&what, &ours_as(&plan, format), &peer);
        same_threads(&what, format, &plan, &threads);
        println!(
            "{what}: {} stitches, {} trims, {} colour changes, {} stops, extents {:?} (0.1 mm): as pyembroidery",
            peer.stitches.len(),
            peer.trims,
            peer.color_changes,
            peer.stops,
            peer.extents
        );
    }
}

/// Each real file converted to every format: pyembroidery reads our file as we read it back,
/// every stitch of the original is still sewn where it was (in order, 0.1 mm), the colour
/// blocks are the original's, and formats that store RGB keep its colours exactly.
#[test]
fn real_files_convert_to_every_format() {
    let Some(py) = python_with_pyembroidery() else {
        return;
    };
    let Some(dir) = realworld() else {
        return;
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| Format::from_path(p).is_some())
        .collect();
    files.sort();
    for path in files {
        let bytes = std::fs::read(&path).unwrap();
        let source = Format::sniff(&bytes)
            .or_else(|| Format::from_path(&path))
            .unwrap();
        let plan = source.read(&bytes, "real").unwrap();
        let what = path.file_name().unwrap().to_string_lossy().to_string();
        for format in Format::ALL {
            let out = format.write(&plan).unwrap();
            let p = scratch(&format!("conv-{}.{}", format.id(), format.extension()));
            std::fs::write(&p, &out).unwrap();
            let back = format.read(&out, "conv").unwrap();
            let (peer, threads) = peer_read(&py, &p);
            let label = format!("{what} → {format}");
            agree(&label, &ours_as(&back, format), &peer);
            same_threads(&label, format, &back, &threads);
            let read = ours(&back);
            let mut it = read.stitches.iter();
            for s in &ours(&plan).stitches {
                assert!(it.any(|q| q == s), "{label}: stitch {s:?} missing");
            }
            assert_eq!(
                back.blocks.len(),
                plan.blocks.len(),
                "{label}: colour blocks"
            );
            if stores_rgb(format) && source.stores_colours() {
                for (a, b) in back.blocks.iter().zip(&plan.blocks) {
                    assert_eq!(a.thread.rgb, b.thread.rgb, "{label}: colours");
                }
            }
        }
        println!("{what}: converted to every format, read back by pyembroidery as by us");
    }
}

/// Our PES headers (PE-Design's `CEmbOne`/`CSewSeg` segments, the thread list, the PEC header
/// and colour list) are byte for byte what pyembroidery writes for the same stitches, so
/// software that reads the PES side (PE-Design) sees what it sees in pyembroidery's files.
/// The sample design: its jumps land where the next stitch is, as Oficina generates them
/// (pyembroidery's encoder moves a jump that lands elsewhere onto the next stitch).
#[test]
fn pes_headers_match_pyembroidery_byte_for_byte() {
    let Some(py) = python_with_pyembroidery() else {
        return;
    };
    const REWRITE: &str = r#"
import sys, pyembroidery as P
P.write(P.read(sys.argv[1]), sys.argv[2], {'version': int(sys.argv[3])})
"#;
    let plan = common::sample();
    for (format, version) in [(Format::Pes, "6"), (Format::PesV1, "1")] {
        let ours = format.write(&plan).unwrap();
        let a = scratch(&format!("hdr-ours-{version}.pes"));
        let b = scratch(&format!("hdr-theirs-{version}.pes"));
        std::fs::write(&a, &ours).unwrap();
        let out = Command::new(&py)
            .args([
                "-c",
                REWRITE,
                a.to_str().unwrap(),
                b.to_str().unwrap(),
                version,
            ])
            .output()
            .unwrap();
        oficina_testkit::assert_success(&out);
        let theirs = std::fs::read(&b).unwrap();
        let pec = u32::from_le_bytes([ours[8], ours[9], ours[10], ours[11]]) as usize;
        assert_eq!(
            &ours[..12],
            &theirs[..12],
            "{format}: signature and PEC offset"
        );
        // Up to the first stitch of the PEC block; PES v1 carries no name for pyembroidery
        // to write back, so the PEC label (16 bytes after "LA:") is skipped there.
        let end = pec + 0x210;
        let differ: Vec<usize> = (0..end)
            .filter(|&i| ours[i] != theirs[i])
            .filter(|&i| !(version == "1" && (pec + 3..pec + 19).contains(&i)))
            .collect();
        assert!(differ.is_empty(), "{format}: bytes {differ:?} differ");
    }
}
