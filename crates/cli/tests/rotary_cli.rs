//! A router's rotary 4th axis through the CLI: `oficina plan --check` of a 4-axis program on
//! the bundled `router-4axis` profile passes the motion invariant checker, `oficina run`
//! drives it on the virtual machine, and the planned times of single moves agree with the
//! trapezoid formula computed here from the profile's numbers and LinuxCNC's feed rule.

mod common;

use common::{oficina, program, root, text, total_time};

use std::path::{Path, PathBuf};

fn sample() -> PathBuf {
    root().join("samples/motion/rotary-engrave.ngc")
}

/// `oficina plan FILE --machine router-4axis --check` with `extra` options: it must pass the
/// invariant checker; its stdout.
fn checked_plan(file: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "plan",
        file.to_str().unwrap(),
        "--machine",
        "router-4axis",
        "--check",
    ];
    args.extend_from_slice(extra);
    let o = oficina(&args);
    let (out, err) = text(&o);
    assert!(
        o.status.success() && out.contains("check: ok"),
        "{out}\n{err}"
    );
    out
}

/// Time of a move of length `l` from rest to rest at cruise `v` and acceleration `a`:
/// a trapezoid (t = l/v + v/a) when it reaches `v`, else a triangle (t = 2·√(l/a)).
fn trapezoid(l: f64, v: f64, a: f64) -> f64 {
    if v * v / a <= l {
        l / v + v / a
    } else {
        2.0 * (l / a).sqrt()
    }
}

#[test]
fn four_axis_sample_plans_and_passes_the_invariant_checker() {
    let s = sample();
    let out = checked_plan(&s, &[]);
    // The joints are driven up to their limits, never beyond (the checker's own figures).
    assert!(out.contains("peak joint speed 100.0 %"), "{out}");
    // The S-curve profile drives it too (the A joint has a jerk limit).
    checked_plan(&s, &["--scurve"]);
}

#[test]
fn run_drives_the_four_axis_sample_on_the_virtual_machine() {
    let s = sample();
    let o = oficina(&[
        "run",
        s.to_str().unwrap(),
        "--machine",
        "router-4axis",
        "--instant",
    ]);
    let (out, err) = text(&o);
    assert!(o.status.success() && out.contains("done"), "{out}\n{err}");
}

#[test]
fn a_three_axis_machine_refuses_the_rotary_move_naming_the_axis() {
    let s = sample();
    for cmd in ["plan", "run"] {
        let mut args = vec![cmd, s.to_str().unwrap(), "--machine", "grbl-router"];
        if cmd == "run" {
            args.push("--instant");
        }
        let o = oficina(&args);
        let (out, err) = text(&o);
        assert!(!o.status.success(), "{cmd}: {out}");
        assert!(err.contains("rotary axis A"), "{cmd}: {err}");
    }
}

#[test]
fn pure_rotary_move_takes_the_trapezoid_time_in_degrees() {
    // LinuxCNC: no X, Y, Z motion, so F is °/min: 3600 °/min = 60 °/s over 360°, with the
    // profile's A acceleration of 360 °/s². 60 °/s stays under A's 10800 °/min.
    let p = program("pure", "G21 G90 G94\nG1 A360 F3600\nM2\n");
    let steps = p.with_extension("csv");
    let out = checked_plan(&p, &["--steps", steps.to_str().unwrap()]);
    let want = trapezoid(360.0, 60.0, 360.0); // 6.1667 s
    assert!((total_time(&out) - want).abs() < 1e-3, "{out} vs {want}");
    // One full turn at 20 steps per degree, all forward, on motor "a".
    let csv = std::fs::read_to_string(&steps).unwrap();
    let a: Vec<&str> = csv.lines().filter(|l| l.starts_with("a,")).collect();
    assert_eq!(a.len(), 7200);
    assert!(a.iter().all(|l| l.ends_with(",+")));
    assert_eq!(csv.lines().count(), 7201, "only A moves");
}

#[test]
fn mixed_move_times_its_feed_on_xyz_and_is_slowed_by_the_rotary_acceleration() {
    // LinuxCNC: X moves, so F600 is mm/min along X (10 mm/s) and A keeps pace: 90° over
    // 10 mm is 9 °/mm, 90 °/s at 10 mm/s (under A's 180 °/s). A's 360 °/s² allows only
    // 360 / 9 = 40 mm/s² along the path (X alone would allow 300).
    let p = program("mixed", "G21 G90 G94\nG1 X10 A90 F600\nM2\n");
    let out = checked_plan(&p, &["--work-offset", "0,0,0"]);
    let want = trapezoid(10.0, 10.0, 40.0); // 1.25 s
    assert!((total_time(&out) - want).abs() < 1e-3, "{out} vs {want}");
    // The same move with A's rate too high for the feed: A's 180 °/s caps the path speed at
    // 180 / 36 = 5 mm/s (360° over 10 mm), whatever F asks.
    let p = program("capped", "G21 G90 G94\nG1 X10 A360 F600\nM2\n");
    let out = checked_plan(&p, &["--work-offset", "0,0,0"]);
    let want = trapezoid(10.0, 5.0, 10.0); // 360 / 36 = 10 mm/s² along the path
    assert!((total_time(&out) - want).abs() < 1e-3, "{out} vs {want}");
}
