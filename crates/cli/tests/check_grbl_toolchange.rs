//! `oficina check --dialect grbl` on a CAM program for grbl with tool changes: grbl has no
//! `M6` (error:20) and refuses `%`, but the sender handles both, so they get notes naming
//! what the sender does; any real error still fails the check.

use oficina_testkit::scratch_file;
use std::process::{Command, Output};

/// The two-tool sample, as Fusion 360's and FreeCAD's grbl posts write such programs: tape
/// marks, the tool list in comments, `T1 M6` … `T2 M6`.
const CAM: &str = include_str!("../../../samples/grbl/two-tools.nc");

fn check(file: &str, text: &str, extra: &[&str]) -> (Output, String, String) {
    let path = scratch_file(file, text);
    let out = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(["check", "--dialect", "grbl"])
        .args(extra)
        .arg(&path)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).replace(&path.display().to_string(), "F");
    let stdout = String::from_utf8_lossy(&out.stdout).replace(&path.display().to_string(), "F");
    (out, err, stdout)
}

#[test]
fn a_cam_program_with_tool_changes_passes_with_notes() {
    let (out, err, stdout) = check("cam.nc", CAM, &[]);
    assert!(out.status.success(), "{err}\n{stdout}");
    assert!(
        err.contains("F:9:4: note: M6 T1: grbl has no tool changer; the sender pauses for a manual change (--tool-change pause)"),
        "{err}"
    );
    assert!(err.contains("F:19:4: note: M6 T2"), "{err}");
    assert!(err.contains("F:1:1: note: '%' tape mark"), "{err}");
    assert!(err.contains("F:27:1: note: '%' tape mark"), "{err}");
    assert!(!err.contains("error"), "{err}");
    assert!(stdout.contains("0 errors, 0 warnings, 4 notes"), "{stdout}");
    assert!(stdout.contains("T1 T2"), "{stdout}");

    let (out, err, _) = check("cam-ignore.nc", CAM, &["--tool-change", "ignore"]);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("F:19:1: note: M6 T2: grbl has no tool changer; the sender drops M6 and the T word (--tool-change ignore)"),
        "{err}"
    );
}

#[test]
fn real_errors_still_fail_and_m6_sent_as_written_is_grbls_error_20() {
    // G41 (cutter compensation) is not grbl's; the notes do not hide it.
    let bad = CAM.replace("G1 X20 F800", "G41 G1 X20 F800");
    let (out, err, stdout) = check("bad.nc", &bad, &[]);
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("F:14:1: error[grbl:20]"), "{err}");
    assert!(err.contains("note: M6 T1"), "{err}");
    assert!(stdout.contains("1 error,"), "{stdout}");

    // A '%' in the middle is not a tape mark.
    let mid = CAM.replace("(Parallel1)", "%");
    let (out, err, _) = check("mid.nc", &mid, &[]);
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("F:18:1: error"), "{err}");

    // With M6 sent to the firmware, grbl refuses it.
    let (out, err, _) = check("fw.nc", CAM, &["--tool-change", "firmware"]);
    assert!(!out.status.success());
    assert!(
        err.contains("F:9:4: error[grbl:20]: M6 is not supported by grbl"),
        "{err}"
    );
}
