//! `oficina plot` end to end: design → program → live run on the virtual machine, for a
//! Cartesian pen plotter and the seed-003 polar plotter; HPGL and joint-space output; bounds
//! refused before drawing; the seed-check table.

mod common;

use oficina_testkit::assert_success;

use common::{oficina_in, root};

/// `oficina args…` in the repository's root (the sample paths are relative to it).
fn oficina(args: &[&str]) -> std::process::Output {
    oficina_in(&root(), args)
}

/// `oficina plot args…`, which must succeed: its stdout.
fn plot(args: &[&str]) -> String {
    let mut all = vec!["plot"];
    all.extend_from_slice(args);
    assert_success(&oficina(&all))
}

/// `oficina run PROGRAM --machine MACHINE --instant`, which must succeed: its stdout.
fn run_instant(program: &std::path::Path, machine: &str) -> String {
    assert_success(&oficina(&[
        "run",
        program.to_str().unwrap(),
        "--machine",
        machine,
        "--instant",
    ]))
}

fn number_after(text: &str, key: &str) -> f64 {
    let i = text
        .find(key)
        .unwrap_or_else(|| panic!("no '{key}' in {text}"))
        + key.len();
    text[i..]
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .find(|s| !s.is_empty())
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn a_svg_plots_and_runs_on_the_cartesian_pen_plotter() {
    let dir = tempfile::tempdir().unwrap();
    let nc = dir.path().join("out.nc");
    let svg = dir.path().join("preview.svg");
    let out = plot(&[
        "samples/plot/design.svg",
        "--machine",
        "pen-plotter",
        "--at",
        "20,20",
        "-o",
        nc.to_str().unwrap(),
        "--preview",
        svg.to_str().unwrap(),
    ]);
    // Two pens (black and red); the black grid of rect + open box + 3 lines merges.
    assert!(
        out.contains("pen 1: #000000") && out.contains("pen 2: #ff0000"),
        "{out}"
    );
    let before = number_after(&out, "pen-up ");
    let after = number_after(&out, "-> ");
    let _ = after;
    let pen_up_after: f64 = number_after(out.split("pen-up").nth(1).unwrap(), "-> ");
    assert!(pen_up_after < before, "{out}");
    let program = std::fs::read_to_string(&nc).unwrap();
    assert!(
        program.contains("M0 (MSG, pen 2"),
        "a pause to change the pen"
    );
    assert!(std::fs::read_to_string(&svg)
        .unwrap()
        .contains("id=\"pen-up\""));
    let run = run_instant(&nc, "pen-plotter");
    let _ = run;
}

#[test]
fn the_polar_plotter_draws_the_same_design_and_runs_it() {
    let dir = tempfile::tempdir().unwrap();
    let nc = dir.path().join("polar.nc");
    plot(&[
        "samples/plot/design.svg",
        "--machine",
        "polar-plotter",
        "--at",
        "300,-100",
        "-o",
        nc.to_str().unwrap(),
    ]);
    run_instant(&nc, "polar-plotter");
    // Joint space: X is the arm angle in degrees, Y the carriage in mm, timed by G93.
    let joint = dir.path().join("joint.nc");
    plot(&[
        "samples/plot/design.svg",
        "--machine",
        "polar-plotter",
        "--at",
        "300,-100",
        "--format",
        "joint",
        "-o",
        joint.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&joint).unwrap();
    assert!(
        text.contains("G93") && text.contains("X = theta"),
        "{}",
        &text[..200]
    );
}

#[test]
fn hpgl_in_and_out() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("house.hpgl");
    let o = plot(&[
        "samples/plot/house.plt",
        "--machine",
        "pen-plotter",
        "--format",
        "hpgl",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(
        o.contains("pen 1: pen 1") && o.contains("pen 2: pen 2"),
        "{o}"
    );
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("IN;") && text.contains("SP2;"));
}

#[test]
fn a_drawing_off_the_machine_is_refused_before_drawing() {
    let o = oficina(&[
        "plot",
        "samples/plot/design.svg",
        "--machine",
        "pen-plotter",
        "--at",
        "400,0",
    ]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("outside the machine travel x"), "{e}");
    // Inside h of the polar pivot.
    let o = oficina(&[
        "plot",
        "samples/plot/design.svg",
        "--machine",
        "polar-plotter",
        "--at",
        "-20,-20",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("pen offset"));
    let o = oficina(&["plot", "samples/plot/design.svg", "--paper", "50,50"]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("does not fit the paper"));
}

/// With no machine named, a drawing beyond the default plotter's travel is written where it
/// lies, as vpype writes it, with a note naming the span; the program's moves reach there.
#[test]
fn a_drawing_beyond_the_default_plotter_is_written_with_a_note() {
    let dir = oficina_testkit::scratch_dir("plot-far");
    let out = dir.join("far.gcode");
    let o = oficina(&[
        "plot",
        "samples/plot/design.svg",
        "--at",
        "400,0",
        "-o",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(stderr.contains("no --machine named"), "{stderr}");
    assert!(stderr.contains("X 400.0"), "{stderr}");
    let program = std::fs::read_to_string(&out).unwrap();
    let max_x = program
        .lines()
        .filter_map(|l| l.split_whitespace().find_map(|w| w.strip_prefix('X')))
        .filter_map(|v| v.parse::<f64>().ok())
        .fold(f64::MIN, f64::max);
    assert!(max_x > 420.0, "the drawing was moved or cut: max X {max_x}");
}

#[test]
fn the_seed_check_prints_five_places() {
    let out = plot(&["--seed-check", "--machine", "polar-plotter"]);
    for place in [
        "lower right",
        "upper right",
        "centre",
        "upper left",
        "lower left",
    ] {
        assert!(out.contains(place), "{out}");
    }
    assert!(out.contains("ramp theta"), "{out}");
}

#[test]
fn images_hatch_text_draws_and_a_broken_image_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let nc = dir.path().join("h.nc");
    let out = plot(&[
        "samples/relief/dome.png",
        "--pixel",
        "0.5",
        "--pitch",
        "1.5",
        "--at",
        "10,10",
        "-o",
        nc.to_str().unwrap(),
    ]);
    assert!(number_after(&out, "pen-down ") > 100.0, "{out}");
    let out = plot(&["--text", "Oficina", "--at", "10,10"]);
    assert!(out.contains("G1 X"), "{out}");
    let empty = dir.path().join("empty.png");
    std::fs::write(&empty, b"").unwrap();
    let o = oficina(&["plot", empty.to_str().unwrap()]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("empty.png") && e.contains("not a readable image"),
        "{e}"
    );
}
