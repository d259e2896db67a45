//! `oficina run` as a user runs it without a terminal: a CAM-style program in work
//! coordinates on the virtual router (its stored G54 puts it inside travel), program pauses,
//! and the same job on grbl firmware (the emulator) over TCP.

mod common;

use oficina_testkit::scratch_file;
use std::process::{Command, Stdio};

fn oficina() -> Command {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
}

/// Safe Z above work zero and a tool change pause, as `oficina carve` writes for grbl.
const CAM_JOB: &str = "G21 G90 G94 G17\nT1\nM3 S12000\nG0 Z5\nG0 X0 Y0\nG1 Z-2 F300\n\
    G1 X20 F1200\nG1 Y10\nG0 Z5\nM5\n(MSG,Change to T2)\nT2\nM0\nM3 S12000\nG0 X5 Y5\n\
    G1 Z-1 F300\nG1 X15 F1200\nG0 Z5\nM5\nM30\n";

#[test]
fn a_work_coordinate_program_runs_on_the_router_and_passes_its_pause() {
    let path = scratch_file("cam.nc", CAM_JOB);
    let out = oficina()
        .arg("run")
        .arg(&path)
        .arg("--instant")
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("done:"), "{stdout}");
    assert!(
        stderr.contains("going on"),
        "the pause is passed and said so: {stderr}"
    );
    assert!(!stderr.contains("outside the travel"), "{stderr}");
}

#[test]
fn stop_at_pauses_stops_the_job_at_m0() {
    let path = scratch_file("cam-stop.nc", CAM_JOB);
    let out = oficina()
        .arg("run")
        .arg(&path)
        .args(["--instant", "--stop-at-pauses"])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(2), "{stdout}");
    assert!(stdout.contains("stopped after"), "{stdout}");
}

#[test]
fn a_work_offset_outside_travel_is_refused_before_any_motion() {
    let path = scratch_file("cam-off.nc", CAM_JOB);
    let out = oficina()
        .arg("run")
        .arg(&path)
        .args(["--instant", "--work-offset", "10,10,0"])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let all = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        !out.status.success(),
        "Z5 above a work zero at the top of travel cannot be reached: {all}"
    );
    assert!(all.contains("travel"), "{all}");
}

#[test]
fn the_same_job_runs_on_grbl_firmware_through_the_emulator() {
    let (emulator, addr, _) = common::emulator(&[]);
    let path = scratch_file("cam-grbl.nc", CAM_JOB.replace("M0\n", ""));
    let out = oficina()
        .arg("run")
        .arg(&path)
        .args(["--machine", &addr])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    common::assert_ran_to_done(emulator, &out);
}
