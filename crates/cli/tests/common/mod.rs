//! What several CLI test binaries share.
// Each test binary compiles this module and uses part of it.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

/// The repository's root (samples, profiles).
pub(crate) fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `oficina args…`, run to its end.
pub(crate) fn oficina(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// `oficina args…` run in the folder `dir`.
pub(crate) fn oficina_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_oficina"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("the binary runs")
}

/// A command's stdout and stderr as text.
pub(crate) fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// A program `{name}.ngc` in a scratch folder.
pub(crate) fn program(name: &str, body: &str) -> PathBuf {
    oficina_testkit::scratch_file(&format!("{name}.ngc"), body)
}

/// The "total time: N s" figure `oficina plan` prints.
pub(crate) fn total_time(out: &str) -> f64 {
    let line = out
        .lines()
        .find(|l| l.starts_with("total time:"))
        .unwrap_or_else(|| panic!("no total time in {out}"));
    line["total time:".len()..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

/// An `oficina emulate grbl …` on a free local TCP port (`extra` before the port options),
/// with the `tcp://` address and the first line it printed (its banner).
pub(crate) fn emulator(extra: &[&str]) -> (Child, String, String) {
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
pub(crate) fn run_program_on(addr: &str, name: &str, program: &str) -> Output {
    let path = oficina_testkit::scratch_file(name, program);
    let out = Command::new(env!("CARGO_BIN_EXE_oficina"))
        .arg("run")
        .arg(&path)
        .args(["--machine", addr])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(path.parent().unwrap());
    out
}

/// The shipped size-34 sole contour, read by the library's point-list reader.
pub(crate) fn sole_sample() -> Vec<oficina_geom::Point> {
    oficina_io::load_points(&root().join("samples/sole/size34.csv")).unwrap()
}

/// Stops the `emulator` once `out`, a run on it, has ended; the run must have succeeded and
/// said `done:`.
pub(crate) fn assert_ran_to_done(mut emulator: Child, out: &Output) {
    let _ = emulator.kill();
    let _ = emulator.wait();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("done:"), "{stdout}\n{stderr}");
}

/// `oficina mill ARGS… -o OUT` in the repository's root (sample paths are relative to it).
pub(crate) fn mill(args: &[&str], out: &Path) -> Output {
    let mut all = vec!["mill"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", out.to_str().unwrap()]);
    oficina_in(&root(), &all)
}
