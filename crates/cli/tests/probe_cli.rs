//! `oficina emulate grbl --probe-…` in one process, `oficina console --tcp …` in another,
//! `/probe` typed on the console's stdin: the offset it sets is printed and read back.

mod common;

use std::io::Write;
use std::process::{Command, Stdio};

/// The console on `addr` with `input` typed, run until the input is used up.
fn console(addr: &str, input: &str) -> String {
    let mut child = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(["console", "--tcp", addr])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let (stdout, stderr) = common::text(&out);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    stdout
}

#[test]
fn console_probe_z_on_the_emulated_plate_prints_the_offset() {
    let emu = common::emulate_fast(
        2000,
        &[
            "--baud",
            "0",
            "--for-seconds",
            "60",
            "--probe-block",
            "10,20,210,170,-60",
            "--probe-plate",
            "100,60,140,100,10",
            "--probe-setter",
            "250,50,-80",
        ],
    );
    let addr = emu.host_port();
    let out = console(
        addr,
        "G90 G0 X120 Y80 Z-40\n/probe z --plate 10 --feed 1000 --slow 200\n$#\n\
         /probe setter --at 250,50 --safe-z -45 --travel 40 --feed 1000 --slow 200\n\
         /probe z --plate -1\nG90 G0 X300 Y80\n/probe z --plate 10 --feed 1000\n",
    );
    // The plate's top: the block's −60 plus 10; G54 Z is the block's top.
    assert!(
        out.contains("touched the plate at machine Z -50.000"),
        "{out}"
    );
    assert!(
        out.contains("G54 offset Z = -60.000 (the stock's top is Z0)"),
        "{out}"
    );
    assert!(out.contains("[G54:0.000,0.000,-60.000]"), "{out}");
    // The setter's pad: the reference for later tools.
    assert!(
        out.contains("probe setter: touched at machine Z -80.000 (after a tool change: /probe setter --reference -80.000)"),
        "{out}"
    );
    assert!(out.contains("plate thickness cannot be negative"), "{out}");
    // Beside the block nothing is touched: ALARM:5, in words.
    assert!(out.contains("probe failed: no contact"), "{out}");
    assert!(out.contains("ALARM:5 (Probe fail"), "{out}");
}

#[test]
fn emulate_refuses_impossible_probe_options() {
    for (args, want) in [
        (vec!["--probe-block", "1,2,3"], "expected 5 numbers"),
        (vec!["--probe-plate", "1,2,3,4,5"], "--probe-block"),
        (
            vec![
                "--probe-block",
                "10,20,210,170,-60",
                "--probe-warp",
                "0.5,0",
            ],
            "wavelength",
        ),
    ] {
        let mut all = vec!["emulate", "grbl", "--tcp", "127.0.0.1:0"];
        all.extend(args);
        let out = common::oficina(&all);
        let (_, stderr) = common::text(&out);
        assert!(!out.status.success(), "{all:?}");
        assert!(stderr.contains(want), "{all:?}: {stderr}");
    }
}
