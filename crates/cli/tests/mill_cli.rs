//! `oficina mill` and `oficina sole` end to end: files written, every program accepted by
//! LinuxCNC's rs274, no gouge, bad input refused with a message naming the file.

mod common;

use common::{oficina_in, root};
use oficina_testkit::rs274;

use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("oficina-mill-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `oficina args…` in the repository's root (the sample paths are relative to it).
fn oficina(args: &[&str]) -> std::process::Output {
    oficina_in(&root(), args)
}

#[test]
fn mill_pocket_profile_and_drill_samples() {
    let dir = tmp("ops");
    for (input, op, tool, extra) in [
        (
            "samples/mill/plate.svg",
            "pocket",
            "flat:6",
            vec!["--stepdown", "2"],
        ),
        (
            "samples/mill/plate.svg",
            "profile-out",
            "flat:6",
            vec!["--tabs", "3", "--lead-out", "2"],
        ),
        (
            "samples/mill/holes.svg",
            "drill",
            "flat:3",
            vec!["--entry", "plunge", "--peck", "2"],
        ),
    ] {
        let out_file = dir.join(format!("{op}.nc"));
        let mut args = vec![
            "mill",
            input,
            "--op",
            op,
            "--tool",
            tool,
            "--depth",
            "5",
            "-o",
            out_file.to_str().unwrap(),
        ];
        args.extend(extra);
        let out = oficina(&args);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{op}: {}\n{stdout}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(stdout.contains("gouge:    none"), "{op}: {stdout}");
        assert!(stdout.contains("(planner)"), "{op}: {stdout}");
        rs274::accepts_file(&out_file, None);
        let svg = std::fs::read_to_string(out_file.with_extension("svg")).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("stroke=\"blue\""));
        assert!(out_file.with_extension("stock.png").exists());
    }
}

#[test]
fn sole_34_to_40_writes_four_programs_rs274_accepts() {
    let dir = tmp("sole");
    let out = oficina(&[
        "sole",
        "samples/sole/size34.csv",
        "--from-size",
        "34",
        "--to-size",
        "40",
        "--system",
        "br",
        "--shrink",
        "2",
        "--tread",
        "samples/sole/tread.svg",
        "-o",
        dir.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}\n{stdout}",
        String::from_utf8_lossy(&out.stderr)
    );
    // α = 1 + 6·1.66/LP + 0.02 and β = 1 + 6·6.66/CP + 0.02 (seed eq. 3.2, 3.3).
    assert!(
        stdout.contains("α = ") && stdout.contains("β = "),
        "{stdout}"
    );
    assert_eq!(stdout.matches("gouge:    none").count(), 4, "{stdout}");
    // The planner's time for each tool: three on each insert, one on each cavity.
    assert_eq!(stdout.matches("T1 flat:16: ").count(), 4, "{stdout}");
    assert_eq!(stdout.matches("T2 flat:6: ").count(), 2, "{stdout}");
    assert_eq!(stdout.matches("T3 flat:1: ").count(), 2, "{stdout}");
    for name in ["insert-left", "insert-right", "cavity-left", "cavity-right"] {
        let f = dir.join(format!("{name}.ngc"));
        let text = std::fs::read_to_string(&f).unwrap();
        // The seed's tools and feeds: the 16 mm mill everywhere, the 6 mm mill and the
        // 1 mm bit in the insert's tread.
        assert!(text.contains("T1 M6"), "{name}");
        let detail = text.contains("T2 M6") && text.contains("T3 M6");
        assert_eq!(detail, name.starts_with("insert"), "{name}");
        assert!(
            text.contains("S1600 M3") && text.contains("S1800 M3"),
            "{name}"
        );
        assert!(text.contains("F190") && text.contains("F100"), "{name}");
        rs274::accepts_file(&f, None);
    }
    // The right foot is the left one mirrored: arcs turn the other way.
    let left = std::fs::read_to_string(dir.join("cavity-left.ngc")).unwrap();
    let right = std::fs::read_to_string(dir.join("cavity-right.ngc")).unwrap();
    assert_ne!(left, right);
}

#[test]
fn bad_drawings_are_refused_with_the_file_named() {
    let dir = tmp("bad");
    let empty = dir.join("empty.svg");
    std::fs::write(&empty, "").unwrap();
    let broken = dir.join("broken.dxf");
    std::fs::write(
        &broken,
        "0\nSECTION\n2\nENTITIES\n0\nLINE\n10\nnot-a-number\n",
    )
    .unwrap();
    for f in [&empty, &broken] {
        let out = oficina(&[
            "mill",
            f.to_str().unwrap(),
            "--op",
            "pocket",
            "--depth",
            "3",
            "-o",
            dir.join("x.nc").to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{err}");
        assert!(
            err.contains(f.file_name().unwrap().to_str().unwrap()),
            "{err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    // A tool wider than the pocket: said, not a silent empty program.
    let out = oficina(&[
        "mill",
        "samples/mill/holes.svg",
        "--op",
        "pocket",
        "--tool",
        "flat:10",
        "--depth",
        "3",
        "-o",
        dir.join("y.nc").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("narrower than the 10 mm tool"), "{err}");
}

#[test]
fn every_post_reads_back_and_checks_clean() {
    let dir = tmp("posts");
    for post in ["sinumerik", "legacy-2006", "grbl"] {
        let f = dir.join(format!("{post}.nc"));
        let out = oficina(&[
            "mill",
            "samples/mill/plate.svg",
            "--op",
            "profile-in",
            "--depth",
            "3",
            "--post",
            post,
            "-o",
            f.to_str().unwrap(),
        ]);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success() && stdout.contains("gouge:    none"),
            "{post}: {}\n{stdout}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let sin = std::fs::read_to_string(dir.join("sinumerik.nc")).unwrap();
    assert!(sin.starts_with("%\n") && sin.contains("T01 M06") && sin.contains("T99 M06"));
}
