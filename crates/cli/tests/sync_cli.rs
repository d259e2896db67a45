//! Spindle-synchronised motion through the CLI: `oficina plan` times a G33 move at pitch ×
//! spindle speed (the trapezoid computed here from the profile's numbers), refuses one with no
//! spindle speed naming the line, and a G76 threading cycle and G33.1 taps from the corpus
//! pass the motion invariant checker and run on the virtual machine.

mod common;

use common::{oficina, program, root, total_time};

use std::process::Output;

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

#[test]
fn a_g33_move_is_timed_at_pitch_times_spindle_speed() {
    // From the machine's start (0, 0, 0) along X to 110 mm (G54 is X10 on grbl-router):
    // 1.5 mm/rev × 600 rev/min = 15 mm/s, X accelerates at 300 mm/s², rest to rest:
    // t = L/v + v/a = 110/15 + 15/300. F1000 (the profile's default feed) must not apply.
    let p = program("g33", "G21 G90\nS600 M3\nG33 X100 K1.5\nM2\n");
    let o = oficina(&[
        "plan",
        p.to_str().unwrap(),
        "--machine",
        "grbl-router",
        "--check",
    ]);
    let out = text(&o);
    assert!(o.status.success(), "{out}");
    let want = 110.0 / 15.0 + 15.0 / 300.0;
    assert!((total_time(&out) - want).abs() < 2e-3, "{out} vs {want}");
    assert!(out.contains("check: ok"), "{out}");
}

#[test]
fn a_synchronised_move_without_spindle_speed_is_refused_with_its_line() {
    let p = program("no_speed", "G21 G90\nM3\nG33 X100 K1.5\nM2\n");
    let o = oficina(&["plan", p.to_str().unwrap(), "--machine", "grbl-router"]);
    let out = text(&o);
    assert!(!o.status.success(), "{out}");
    assert!(
        out.contains("line 3") && out.contains("spindle speed"),
        "{out}"
    );
}

#[test]
fn threading_and_tapping_programs_plan_check_and_run() {
    for f in [
        "sync_g76_spring_degression.ngc",
        "sync_g33_1_metric_holes.ngc",
    ] {
        let path = root().join("tests/corpus").join(f);
        let path = path.to_str().unwrap();
        let o = oficina(&["plan", path, "--machine", "grbl-router", "--check"]);
        assert!(text(&o).contains("check: ok"), "{f}: {}", text(&o));
        let o = oficina(&["run", path, "--machine", "grbl-router", "--instant"]);
        assert!(
            o.status.success() && text(&o).contains("done"),
            "{f}: {}",
            text(&o)
        );
    }
}
