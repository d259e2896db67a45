//! LinuxCNC's standalone interpreter `rs274` (Debian package `linuxcnc-uspace`) as the
//! oracle: the programs Oficina writes must run on it, and Oficina's interpreter must print
//! the calls it prints.

use std::path::Path;
use std::process::Command;
use std::sync::{Mutex, MutexGuard};

/// Canonical calls compared with rs274. Everything else is dropped, each for a reason:
/// - `ON_RESET`, `FINISH`: notifications of rs274's own driver loop, not machine operations;
/// - `SET_FEED_REFERENCE`: always `CANON_XYZ` in rs274, not a state Oficina models;
/// - `START_CHANGE`: a hint to a tool changer to start moving, no state change;
/// - `SET_SPINDLE_MODE`: constant-surface-speed mode (G96), not part of the corpus.
///
/// The start-up preamble (units, G54 and G92 offsets, rotation) is compared like the rest:
/// it is the state the program's first moves are relative to.
pub const COMPARED: &[&str] = &[
    "STRAIGHT_TRAVERSE",
    "STRAIGHT_FEED",
    "ARC_FEED",
    "NURBS_FEED",
    "TURN_PROBE_ON",
    "STRAIGHT_PROBE",
    "TURN_PROBE_OFF",
    "DWELL",
    "SET_FEED_RATE",
    "SET_FEED_MODE",
    "SET_SPINDLE_SPEED",
    "SET_SPINDLE_MODE",
    "START_SPINDLE_CLOCKWISE",
    "START_SPINDLE_COUNTERCLOCKWISE",
    "STOP_SPINDLE_TURNING",
    "ORIENT_SPINDLE",
    "SPINDLE.0.WAIT_ORIENT_COMPLETE",
    "START_SPEED_FEED_SYNC",
    "STOP_SPEED_FEED_SYNCH",
    "RIGID_TAP",
    "MIST_ON",
    "MIST_OFF",
    "FLOOD_ON",
    "FLOOD_OFF",
    "SELECT_TOOL",
    "CHANGE_TOOL",
    "USE_TOOL_LENGTH_OFFSET",
    "USE_LENGTH_UNITS",
    "SELECT_PLANE",
    "SET_G5X_OFFSET",
    "SET_G92_OFFSET",
    "SET_XY_ROTATION",
    "SET_MOTION_CONTROL_MODE",
    "SET_NAIVECAM_TOLERANCE",
    "ENABLE_FEED_OVERRIDE",
    "DISABLE_FEED_OVERRIDE",
    "ENABLE_SPEED_OVERRIDE",
    "DISABLE_SPEED_OVERRIDE",
    "ENABLE_ADAPTIVE_FEED",
    "DISABLE_ADAPTIVE_FEED",
    "ENABLE_FEED_HOLD",
    "DISABLE_FEED_HOLD",
    "MESSAGE",
    "COMMENT",
    "PROGRAM_STOP",
    "OPTIONAL_PROGRAM_STOP",
    "PROGRAM_END",
];

/// Whether the `rs274` command can be started.
pub fn installed() -> bool {
    Command::new("rs274").arg("-h").output().is_ok()
}

/// One rs274 at a time in this test binary: it keeps state in files (the tool table in
/// `$HOME/.tool.mmap`), so concurrent runs could change a table under each other.
pub fn alone() -> MutexGuard<'static, ()> {
    static ALONE: Mutex<()> = Mutex::new(());
    ALONE.lock().unwrap_or_else(|e| e.into_inner())
}

/// `rs274` with a private `HOME` (its tool table lives in `$HOME/.tool.mmap`: another rs274,
/// of another test binary or checkout, must not change it under this one).
pub fn command(home: &Path) -> Command {
    let mut cmd = Command::new("rs274");
    cmd.env("HOME", home);
    cmd
}

/// The lines of rs274's stderr that complain: all but blank ones and its "executing" banner.
pub fn complaints(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| !l.trim().is_empty() && l.trim() != "executing")
        .collect()
}

/// `rs274 -g [-t tool_table] file`, alone and with a private HOME; panics unless it exits
/// with success and complains of nothing. Returns its stdout (the canonical calls).
pub fn accepts_file(file: &Path, tool_table: Option<&Path>) -> String {
    run_accepted(file, tool_table, &file.display().to_string())
}

fn run_accepted(file: &Path, tool_table: Option<&Path>, what: &str) -> String {
    let home = crate::scratch_dir("rs274-home");
    let mut cmd = command(&home);
    cmd.arg("-g");
    if let Some(tbl) = tool_table {
        cmd.arg("-t").arg(tbl);
    }
    cmd.arg(file);
    let out = {
        let _alone = alone();
        cmd.output()
            .expect("rs274 (LinuxCNC) must be installed: apt install linuxcnc-uspace")
    };
    let _ = std::fs::remove_dir_all(&home);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && complaints(&stderr).is_empty(),
        "rs274 rejects {what}: {stderr}"
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// [`accepts_file`] on `program` (and on `tool_table`, the text of a table file), both
/// written to a scratch folder that is removed afterwards.
pub fn accepts(program: &str, tool_table: Option<&str>) -> String {
    let dir = crate::scratch_dir("rs274-program");
    let file = dir.join("p.ngc");
    std::fs::write(&file, program).unwrap();
    let tbl = tool_table.map(|t| {
        let tbl = dir.join("tool.tbl");
        std::fs::write(&tbl, t).unwrap();
        tbl
    });
    let stdout = run_accepted(&file, tbl.as_deref(), &format!("the program\n{program}\n"));
    let _ = std::fs::remove_dir_all(&dir);
    stdout
}
