//! `--dialect marlin` end to end: Makelangelo-style programs checked and planned, and the
//! plotter's own output with Marlin servo commands read back in the Marlin dialect.

mod common;

use common::{oficina_in, root};

fn oficina(args: &[&str]) -> std::process::Output {
    oficina_in(&root(), args)
}

fn text(o: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

const SQUARE: &str = "crates/gcode/tests/data/marlin/makelangelo_square.gcode";

#[test]
fn a_makelangelo_program_checks_and_plans_in_the_marlin_dialect() {
    let o = oficina(&["check", SQUARE, "--dialect", "marlin"]);
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(t.contains("0 errors"), "{t}");
    assert!(t.contains("note: M0 pause: Ready for pen change"), "{t}");
    // Makelangelo's origin is the paper's centre: the hanging polargraph with its work zero
    // at the home (500, -400) G28 goes to.
    let o = oficina(&[
        "plan",
        SQUARE,
        "--dialect",
        "marlin",
        "--machine",
        "polargraph-wall",
        "--work-offset",
        "500,-400,0",
    ]);
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    // Five servo moves of 250 ms, G4 P500 (half a second, not 500 s) and 190 mm of drawing
    // at 3000 mm/min: a few seconds.
    let i = t.find("total time: ").expect(&t) + "total time: ".len();
    let secs: f64 = t[i..].split(' ').next().unwrap().parse().unwrap();
    assert!(secs > 1.75 + 190.0 / 50.0 && secs < 60.0, "{t}");
    // The checksum file: refused at line 3.
    let o = oficina(&[
        "check",
        "crates/gcode/tests/data/marlin/checksum.gcode",
        "--dialect",
        "marlin",
    ]);
    let t = text(&o);
    assert!(!o.status.success());
    assert!(t.contains("checksum.gcode:3:"), "{t}");
    assert!(t.contains("checksum mismatch on line 3"), "{t}");
}

/// `oficina plot --pen command` with Marlin's M280 lines: the program has no errors in the
/// Marlin dialect; what Marlin would not do as written is warned about (a feed alone on its
/// line, several commands on one line) — the plot emitter writes grbl-style lines.
#[test]
fn plot_output_with_m280_lifts_reads_in_the_marlin_dialect() {
    let dir = tempfile::tempdir().unwrap();
    let nc = dir.path().join("out.gcode");
    let o = oficina(&[
        "plot",
        "samples/plot/design.svg",
        "--machine",
        "polargraph-wall",
        "--layout",
        "a3",
        "--pen",
        "command",
        "--pen-down-cmd",
        "M280 P0 S25 T250",
        "--pen-up-cmd",
        "M280 P0 S90 T250",
        "-o",
        nc.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = oficina(&[
        "check",
        nc.to_str().unwrap(),
        "--dialect",
        "marlin",
        "--machine",
        "polargraph-wall",
    ]);
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(t.contains(" 0 errors"), "{t}");
    assert!(t.contains("the first servo angle is read as pen up"), "{t}");
    assert!(t.contains("Marlin runs one command per line"), "{t}");
}
