//! `oficina plot --format marlin`: the program is clean Marlin (Oficina's Marlin reader finds
//! no error and no warning; the lines are checked here as Marlin reads them), and its pen-down
//! path, read back by the small reader below, is the plain G-code's.

mod common;

use common::{oficina_in, pen_down_path, root, text, word};
use oficina_testkit::assert_success;
use std::path::Path;

/// `oficina plot samples/plot/design.svg … -o OUT`, which must succeed; the program's text.
fn plot(out: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "plot",
        "samples/plot/design.svg",
        "--machine",
        "pen-plotter",
        "--at",
        "20,20",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    assert_success(&oficina_in(&root(), &args));
    std::fs::read_to_string(out).unwrap()
}

#[test]
fn marlin_output_is_clean_marlin_and_draws_the_plain_programs_path() {
    let dir = tempfile::tempdir().unwrap();
    let plain = plot(&dir.path().join("plain.nc"), &[]);
    let marlin = plot(&dir.path().join("marlin.gcode"), &["--format", "marlin"]);

    // Oficina's Marlin reader: zero errors and zero warnings.
    let o = oficina_in(
        &root(),
        &[
            "check",
            "--dialect",
            "marlin",
            "--machine",
            "pen-plotter",
            dir.path().join("marlin.gcode").to_str().unwrap(),
        ],
    );
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}\n{err}");
    assert!(out.contains(" 0 errors, 0 warnings"), "{out}\n{err}");

    // Line by line, as Marlin reads them.
    let lines: Vec<&str> = marlin
        .lines()
        .map(|l| l.split(';').next().unwrap().trim())
        .filter(|l| !l.is_empty())
        .collect();
    let first_move = lines.iter().position(|l| l.starts_with("G0")).unwrap();
    let home = lines.iter().position(|l| *l == "G28").expect("G28 homes");
    assert!(home < first_move, "G28 before the first move");
    assert!(
        lines[..home].iter().any(|l| l.starts_with("M280 P0 S90")),
        "the pen is lifted before homing"
    );
    assert_eq!(*lines.last().unwrap(), "M84");
    for l in &lines {
        if l.starts_with("M0 ") {
            continue; // the rest of an M0 line is its message
        }
        let commands = l.matches(['G', 'M']).count();
        assert_eq!(commands, 1, "one command per line: {l}");
        assert!(!l.starts_with('F'), "a feed alone: {l}");
        if l.starts_with("G4") {
            let ms = word(l, 'P').unwrap();
            assert!(
                ms >= 100.0 && ms.fract() == 0.0,
                "G4 P in milliseconds: {l}"
            );
        }
        assert!(
            !l.starts_with("M2") || l.starts_with("M280"),
            "no program end: {l}"
        );
    }
    assert!(
        marlin.contains("\nM0 Pen 2: "),
        "a pen change stops with a message"
    );
    // Every move that follows a feed of the other kind carries its feed.
    let mut last_kind = "";
    for l in &lines {
        let kind = if l.starts_with("G0") {
            "G0"
        } else if l.starts_with("G1") {
            "G1"
        } else {
            continue;
        };
        if kind != last_kind {
            assert!(word(l, 'F').is_some(), "{l} follows a {last_kind}: no F");
        }
        last_kind = kind;
    }

    // The same pen-down path as the plain program (pen on Z there, on the servo here).
    let plain_path = pen_down_path(&plain, |l| {
        (l.starts_with("G1 Z") || l.starts_with("G0 Z")).then(|| l.starts_with("G1"))
    });
    let marlin_path = pen_down_path(&marlin, |l| {
        l.strip_prefix("M280 P0 S")
            .map(|a| a.parse::<f64>().unwrap() == 30.0)
    });
    assert!(plain_path.len() >= 5, "{} strokes", plain_path.len());
    assert_eq!(plain_path.len(), marlin_path.len(), "strokes");
    for (a, b) in plain_path.iter().zip(&marlin_path) {
        assert_eq!(a.len(), b.len());
        for (p, q) in a.iter().zip(b) {
            let d = (p[0] - q[0]).hypot(p[1] - q[1]);
            assert!(d <= 0.01, "{p:?} vs {q:?}");
        }
    }
}

#[test]
fn marlin_servo_angles_and_dwell_are_the_options() {
    let dir = tempfile::tempdir().unwrap();
    let m = plot(
        &dir.path().join("m.gcode"),
        &[
            "--format",
            "marlin",
            "--servo-up",
            "120",
            "--servo-down",
            "45",
            "--pen-dwell",
            "0.3",
        ],
    );
    let downs = m.matches("M280 P0 S45\nG4 P300\n").count();
    let ups = m.matches("M280 P0 S120\nG4 P300\n").count();
    assert!(downs >= 5, "{downs} pen-downs");
    // Lifted before homing and after every stroke.
    assert_eq!(ups, downs + 1);
}

#[test]
fn marlin_refuses_servo_angles_a_servo_cannot_take() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.gcode");
    let o = oficina_in(
        &root(),
        &[
            "plot",
            "samples/plot/design.svg",
            "--machine",
            "pen-plotter",
            "--dialect",
            "marlin",
            "--servo-up",
            "200",
            "-o",
            out.to_str().unwrap(),
        ],
    );
    let (_, err) = text(&o);
    assert!(!o.status.success());
    assert!(err.contains("0 to 180"), "{err}");
    assert!(!out.exists(), "nothing written");
}

#[test]
fn marlin_with_a_z_lift_is_clean_too_and_draws_the_same_path() {
    let dir = tempfile::tempdir().unwrap();
    let plain = plot(&dir.path().join("plain.nc"), &[]);
    let path = dir.path().join("z.gcode");
    let z = plot(&path, &["--format", "marlin", "--pen", "z"]);
    let o = oficina_in(
        &root(),
        &["check", "--dialect", "marlin", path.to_str().unwrap()],
    );
    let (out, err) = text(&o);
    assert!(out.contains(" 0 errors, 0 warnings"), "{out}\n{err}");
    assert!(!z.contains("M280"), "a Z lift, no servo");
    let by_z =
        |l: &str| (l.starts_with("G1 Z") || l.starts_with("G0 Z")).then(|| l.starts_with("G1"));
    assert_eq!(pen_down_path(&plain, by_z), pen_down_path(&z, by_z));
}
