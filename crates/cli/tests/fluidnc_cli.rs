//! `oficina run --machine tcp://…` against `oficina emulate --flavor fluidnc --tcp …`: FluidNC
//! is reached over its network port (telnet, TCP 23 on the board), which greets no one, so
//! the sender must find the firmware by asking.

mod common;

use std::process::{Command, Stdio};

fn oficina() -> Command {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
}

#[test]
fn a_job_runs_on_fluidnc_over_its_network_port() {
    let (mut emulator, addr, first) = common::emulator(&["--flavor", "fluidnc", "--baud", "0"]);
    assert!(first.contains("fluidnc"), "{first}");
    let dir = std::env::temp_dir().join(format!("oficina-fluidnc-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("square.nc");
    std::fs::write(
        &path,
        "G21 G90 G94\nG0 Z2\nG1 Z-0.5 F300\nG1 X10 F1200\nY10\nX0\nY0\nG0 Z2\nM2\n",
    )
    .unwrap();
    let out = oficina()
        .arg("run")
        .arg(&path)
        .args(["--machine", &addr])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let _ = emulator.kill();
    let _ = emulator.wait();
    let _ = std::fs::remove_dir_all(&dir);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("done:"), "{stdout}\n{stderr}");
}
