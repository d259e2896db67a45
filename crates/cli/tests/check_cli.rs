//! `oficina check` as a user runs it: all errors of a file with their places, then the summary.

use oficina_testkit::scratch_file;
use std::process::Command;

fn oficina() -> Command {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
}

#[test]
fn five_different_errors_are_all_reported_with_positions_and_checking_goes_on() {
    let path = scratch_file(
        "five.ngc",
        "G21 G90\n\
         G0 X0 Y0\n\
         G1 X10 F100\n\
         G1 X10 Y10 G0\n\
         G2 X20 Y0 R3\n\
         G1 X[1/0]\n\
         G1 Q5 X3\n\
         #<a> = #<undefined>\n\
         G1 X5 Y5\n\
         M2\n",
    );
    let out = oficina().arg("check").arg(&path).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        !out.status.success(),
        "a file with errors must fail the check"
    );
    let name = path.display().to_string();
    // file:line:col for each of the five errors, in order.
    for (line, col) in [(4, 12), (5, 11), (6, 6), (7, 4), (8, 8)] {
        let place = format!("{name}:{line}:{col}: error:");
        assert!(err.contains(&place), "missing {place} in:\n{err}");
    }
    assert_eq!(err.matches(": error:").count(), 5, "{err}");
    // Each diagnostic shows its source line and a caret under the place.
    assert!(
        err.contains("4 | G1 X10 Y10 G0\n  |            ^^"),
        "{err}"
    );
    assert!(err.contains("division by zero"), "{err}");
    assert!(stdout.contains("5 errors"), "{stdout}");
    // Checking went on after the errors: the last good move is in the summary's extents.
    assert!(stdout.contains("feed "), "{stdout}");
}

#[test]
fn a_good_file_prints_extents_length_tools_and_planner_time() {
    let path = scratch_file(
        "good.ngc",
        "G21 G90 G17\nG10 L2 P1 X100 Y100 Z-50\nG54\nT2 M6\nG0 X0 Y0 Z5\n\
         G1 Z-1 F300\nG1 X100 F1200\nG1 Y50\nG2 X50 Y100 R50\nG0 Z5\nM2\n",
    );
    let out = oficina().arg("check").arg(&path).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("0 errors"), "{stdout}");
    // Feed extents in machine coordinates: X 100…200 (work X0…100 + offset 100).
    assert!(stdout.contains("100.000 … 200.000"), "{stdout}");
    assert!(stdout.contains("(1 arcs)"), "{stdout}");
    assert!(stdout.contains("T2"), "{stdout}");
    assert!(stdout.contains("look-ahead planner"), "{stdout}");
    // The straight feed length: 6 mm plunge + 100 + 50 + a 90° arc of radius 50.
    let expected = 6.0 + 100.0 + 50.0 + 50.0 * std::f64::consts::FRAC_PI_2;
    assert!(
        stdout.contains(&format!("feed {expected:.3} mm")),
        "{stdout}"
    );
}

#[test]
fn a_missing_file_is_a_clear_error_not_a_panic() {
    let out = oficina()
        .args(["check", "/nonexistent/program.ngc"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("cannot open /nonexistent/program.ngc"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}
