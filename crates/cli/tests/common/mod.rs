//! What several CLI test binaries share.
// Each test binary compiles this module and uses part of it.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Output, Stdio};

/// An `oficina emulate grbl …` on a free local TCP port (`extra` before the port options),
/// with the `tcp://` address and the first line it printed (its banner).
pub fn emulator(extra: &[&str]) -> (Child, String, String) {
    let mut emulator = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(["emulate", "grbl"])
        .args(extra)
        .args(["--tcp", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(emulator.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    let addr = first
        .split_whitespace()
        .find(|w| w.starts_with("tcp://"))
        .expect(&first)
        .to_string();
    (emulator, addr, first)
}

/// `oficina run` of `program` (written to a scratch file named `name`) on the machine at
/// `addr`, with no terminal.
pub fn run_program_on(addr: &str, name: &str, program: &str) -> Output {
    let dir = std::env::temp_dir().join(format!("oficina-run-on-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, program).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .arg("run")
        .arg(&path)
        .args(["--machine", addr])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    out
}
