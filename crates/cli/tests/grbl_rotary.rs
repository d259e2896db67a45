//! `oficina emulate --machine router-4axis` is grblHAL with a 4th axis A, and `oficina run`
//! drives a 4-axis program on it through the `Machine` trait to the end. (The emulator's A
//! and its timing against the planner are checked in simulated time by
//! crates/grbl-emu/tests/rotary.rs; this runs in real time, so the program is short.)

mod common;

use std::process::{Command, Stdio};

fn oficina() -> Command {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
}

#[test]
fn a_four_axis_program_runs_to_its_end_on_the_emulated_4th_axis() {
    let (emulator, addr, _) = common::emulator(&[
        "--machine",
        "router-4axis",
        "--baud",
        "0",
        "--for-seconds",
        "60",
    ]);
    // A alone (F in °/min), then X with A (F in mm/min along X): about 1.5 s of motion.
    let out = common::run_program_on(
        &addr,
        "turn.ngc",
        "G21 G90 G94\nG0 X5 A0\nG1 A90 F5400\nG1 X10 A120 F600\nG0 A0\nM2\n",
    );
    common::assert_ran_to_done(emulator, &out);
}

/// A line the firmware refuses (`error:20`) ends the job: `oficina run` reports the error
/// and the resume point and exits with failure instead of waiting for an end that the
/// device never announced (it sent only the alarm before).
#[test]
fn a_refused_line_ends_the_run_with_its_error_and_resume_point() {
    let (mut emulator, addr, _) = common::emulator(&["--baud", "0", "--for-seconds", "60"]);
    let dir = oficina_testkit::scratch_dir("grbl-error20");
    let path = dir.join("bad.ngc");
    // A 3-axis grbl has no A axis: line 3 is refused with error:20.
    std::fs::write(&path, "G21 G90\nG1 X1 F600\nG1 A5\nG1 X2\nM2\n").unwrap();
    let mut run = oficina()
        .arg("run")
        .arg(&path)
        .args(["--machine", &addr])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // A guard against the old hang, not a timing assertion: the job is a few blocks long.
    let mut status = None;
    for _ in 0..600 {
        if let Some(s) = run.try_wait().unwrap() {
            status = Some(s);
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    if status.is_none() {
        let _ = run.kill();
    }
    let out = run.wait_with_output().unwrap();
    let _ = emulator.kill();
    let _ = emulator.wait();
    let _ = std::fs::remove_dir_all(&dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let status = status.unwrap_or_else(|| panic!("run did not end after the error: {stderr}"));
    assert!(!status.success(), "{stderr}");
    assert!(stderr.contains("error:20"), "{stderr}");
    assert!(stderr.contains("bad.ngc:3"), "{stderr}");
    assert!(stderr.contains("Resume from"), "{stderr}");
}
