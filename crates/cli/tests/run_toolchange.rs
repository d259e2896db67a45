//! `oficina run FILE --machine tcp://…` on a program with tool changes, against `oficina
//! emulate grbl`, with no terminal: under `pause` it stops at the first M6 (nobody is there
//! to change the tool), says so once and names the line to continue from; under `ignore` it runs through.

mod common;
use common::*;
use std::process::{Command, Stdio};

const TWO_TOOLS: &str = "%\n(T1 D=3.175 - flat)\n(T2 D=6 - ball)\nG21 G90 G94\nT1 M6\nS10000 M3\nG0 X1 Y1\nG0 Z2\nG1 Z-0.5 F600\nG1 X5 F1200\nG0 Z2\nM5\nT2 M6\nS12000 M3\nG0 X2 Y2\nG1 Z-0.2 F600\nG0 Z2\nM5\nM30\n%\n";

fn run(addr: &str, extra: &[&str]) -> std::process::Output {
    let path = oficina_testkit::scratch_file("two-tools.nc", TWO_TOOLS);
    let out = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .arg("run")
        .arg(&path)
        .args(["--machine", addr])
        .args(extra)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(path.parent().unwrap());
    out
}

#[test]
fn without_a_terminal_a_tool_change_stops_the_run_and_ignore_runs_through() {
    let (mut emu, addr, _) = emulator(&["--baud", "0"]);
    let out = run(&addr, &[]);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{stdout}\n{stderr}");
    assert!(
        stderr.contains(
            "TOOL CHANGE: change to tool T1 (T1 D=3.175 - flat; M6 at line 5), then resume"
        ),
        "{stderr}"
    );
    // One story: it stops (never "going on" past the M6), and says how to continue.
    assert!(stderr.contains("stopping here"), "{stderr}");
    assert!(!stderr.contains("going on"), "{stderr}");
    assert!(stderr.contains("two-tools.nc:5 (M6 T1)"), "{stderr}");
    assert!(stdout.contains("--resume"), "{stdout}");
    let _ = emu.kill();
    let _ = emu.wait();

    let (emu, addr, _) = emulator(&["--baud", "0"]);
    let out = run(&addr, &["--tool-change", "ignore"]);
    let (_, stderr) = text(&out);
    assert!(
        stderr.contains("M6 T2 dropped (--tool-change ignore)"),
        "{stderr}"
    );
    assert_ran_to_done(emu, &out);

    // A policy that needs a place says so before anything moves.
    let out = run("tcp://127.0.0.1:1", &["--tool-change", "park"]);
    let (_, stderr) = text(&out);
    assert!(!out.status.success());
    assert!(stderr.contains("--park X,Y,Z"), "{stderr}");
}
